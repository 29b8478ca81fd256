/*
 * vi_check.h - the one way a check in the C code reports why it failed: the reason, printf-style
 * (vi_snprintf: numbers with '.' whatever the locale), into the caller's message buffer msg of n
 * bytes, then return -1 from the checking function:
 *
 *     if (!(m > 0.0)) VI_FAIL(msg, n, "m = %g kg: the mass must be positive", m);
 */
#ifndef VI_CHECK_H
#define VI_CHECK_H

#include "vi_text.h"

#define VI_FAIL(msg, n, ...)                   \
    do {                                       \
        vi_snprintf((msg), (n), __VA_ARGS__);  \
        return -1;                             \
    } while (0)

#endif
