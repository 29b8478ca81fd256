/*
 * vi_text.h - numbers as text with '.' as the decimal point, whatever the locale of the process.
 *
 * An importer may run with LC_NUMERIC set (a modelling tool on a German Windows: de_DE, whose
 * decimal point is ','), and the C library's strtod and printf family follow it: strtod would stop
 * at the '.' of "1.5e-30" and printf would write "1,5e-30". Everything the FMU reads or writes as a
 * number goes through these functions instead, so files, messages and logs are the same in every
 * locale.
 *
 * vi_strtod reads a number as the C library's strtod does in the C locale, without calling it:
 *   - leading white space (' ', \t, \n, \v, \f, \r) is skipped;
 *   - decimal: [+-] digits with an optional '.', at least one digit, then an optional exponent
 *     (e|E)[+-]digits (an 'e' without digits after it is not part of the number), rounded to the
 *     nearest double, ties to even (IEEE 754 binary64), for any count of digits and any exponent:
 *     too large gives +-HUGE_VAL (infinity), too small +-0 or a subnormal, as strtod;
 *   - hexadecimal: [+-] 0x or 0X, hex digits with an optional '.', at least one hex digit, then an
 *     optional binary exponent (p|P)[+-]digits, rounded the same way;
 *   - inf, infinity, nan and nan(letters, digits, _), in any case: infinity and a quiet NaN;
 *   - anything else: no number, *end = s and 0 returned.
 * A number out of range is not reported in errno: the value shows it. Why not strtod_l or
 * uselocale: neither is in C11 nor on every platform the FMU is built for (mingw-w64 links its own
 * stdio; macOS), and an FMU must not change the locale of the importer's thread. The conversion (Clinger 1990, "How to read floating point numbers accurately"):
 * numbers of up to 19 significant digits whose value and power of ten are exact in a double take one
 * rounded multiplication or division; with a 128-bit integer type, up to 19 digits and exponents
 * within +-27 are exact integer arithmetic; everything else is exact big-integer arithmetic on the
 * first 768 significant digits (a nonzero digit after them is marked: no midpoint between two doubles
 * has more than 767), at most 82 32-bit words, on the stack.
 *
 * vi_snprintf and vi_vsnprintf are snprintf and vsnprintf of C99 (the same return value: the length
 * of the whole output, the buffer holding what fits, terminated when size > 0), except that floating
 * conversions (%f %F %e %E %g %G %a %A) write '.' as the decimal point. They walk the format and hand
 * each conversion alone to the C library's snprintf (so %zu, flags, width, precision and '*' mean
 * what the C library makes of them); in a floating conversion's text the decimal point that library
 * writes now (found by printing 0.5) is replaced by '.'. Refused, returning -1 with the text before
 * it in the buffer: %n, the non-standard flags (' I), an unknown conversion, and a floating
 * conversion longer than VI_TEXT_FLOAT_MAX - 1 characters (a width or precision of hundreds).
 */
#ifndef VI_TEXT_H
#define VI_TEXT_H

#include <stdarg.h>
#include <stddef.h>

#include "vi_format.h"

/* The longest floating conversion vi_vsnprintf writes, its terminating '\0' included (%.17g of any
 * double needs 24; %f of DBL_MAX 316). */
#define VI_TEXT_FLOAT_MAX 512

double vi_strtod(const char *s, char **end);
int vi_snprintf(char *buf, size_t size, const char *fmt, ...) VI_PRINTF_FORMAT(3, 4);
int vi_vsnprintf(char *buf, size_t size, const char *fmt, va_list ap) VI_PRINTF_FORMAT(3, 0);

#endif
