/* Unit tests of numbers as text whatever the locale (vi_text.h). Every test runs in de_DE.UTF-8, whose
 * decimal point is ',' (Criterion runs each test in its own process, so the locale stays in it).
 * Expected values: Python's float() written here as hexadecimal literals, and the C library's strtod
 * and snprintf (glibc: correctly rounded, exact) run in the C locale before the switch. */
#include <criterion/criterion.h>
#include <float.h>
#include <limits.h>
#include <locale.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vi_profile.h"
#include "vi_text.h"

/* Into the locale `name` (de_DE.UTF-8 or ps_AF.UTF-8), checking that the C library then writes its
 * decimal point `point` (else the test would prove nothing). */
static void into(const char *name, const char *point)
{
    cr_assert(setlocale(LC_ALL, name) != NULL,
              "the locale %s is missing: install Debian's package locales and generate it with "
              "localedef -i %.5s -f UTF-8 %s (tools/setup.sh does both)", name, name, name);
    char text[16], want[16];
    snprintf(text, sizeof text, "%.1f", 1.5);
    snprintf(want, sizeof want, "1%s5", point);
    cr_assert(strcmp(text, want) == 0, "%s does not write '%s': %s", name, point, text);
}

/* de_DE.UTF-8: decimal point ',' (the C library also reads it: strtod("1,5") is 1.5 there). */
static void german(void)
{
    into("de_DE.UTF-8", ",");
    cr_assert(strtod("1,5", NULL) == 1.5);
}

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* Numbers of every form against Python's float(): beyond 19 digits, 1.5e-30, the ends of the range
 * (DBL_MAX and what rounds to it or overflows, DBL_MIN, subnormals, half the smallest subnormal),
 * ties to even in decimal and hexadecimal, signs, "5." and ".5". */
Test(text, numbers_of_every_form_read_as_python_float_reads_them)
{
    german();
    static const struct {
        const char *text;
        double value;
    } cases[] = {
        {"1.5e-30", 0x1.e6c71fe61a3efp-100},
        {"-1.5E-30", -0x1.e6c71fe61a3efp-100},
        {"0.1", 0x1.999999999999ap-4},
        {"1e23", 0x1.52d02c7e14af6p+76},
        {"1e22", 0x1.0f0cf064dd592p+73},
        {"1e-22", 0x1.e392010175ee6p-74},
        {"4.1e22", 0x1.15d3a99a9614fp+75},
        {"7e-27", 0x1.154c6f013f48ep-87},
        {"123456789012345678e-27", 0x1.0f7bfe5e2538bp-33},
        {"8.988465674311579e307", 0x1.fffffffffffffp+1022},
        {"1.7976931348623157e308", 0x1.fffffffffffffp+1023},
        {"1.7976931348623158e308", 0x1.fffffffffffffp+1023},
        {"1.7976931348623159e308", INFINITY},
        {"1e400", INFINITY},
        {"2.2250738585072011e-308", 0x0.fffffffffffffp-1022},
        {"2.2250738585072012e-308", 0x1.0000000000000p-1022},
        {"4.9406564584124654e-324", 0x0.0000000000001p-1022},
        {"2.4703282292062327e-324", 0.0},
        {"2.4703282292062328e-324", 0x0.0000000000001p-1022},
        {"1e-320", 0x0.00000000007e8p-1022},
        {"-3e-310", -0x0.03739a252b281p-1022},
        {"1e-400", 0.0},
        {"-0", -0.0},
        {"0.12345678901234567890123", 0x1.f9add3746f65fp-4},
        {"123456789012345678901234567890", 0x1.8ee90ff6c373ep+96},
        {"0.000000000000000000000000000000000000000000001e40", 0x1.4f8b588e368f1p-17},
        {"9007199254740993", 0x1.0000000000000p+53},
        {"9007199254740995", 0x1.0000000000002p+53},
        {"9007199254740993.000000000000000000001", 0x1.0000000000001p+53},
        {"1.00000000000000011102230246251565404236316680908203125", 0x1.0000000000000p+0},
        {"1.00000000000000011102230246251565404236316680908203124", 0x1.0000000000000p+0},
        {"1.00000000000000011102230246251565404236316680908203126", 0x1.0000000000001p+0},
        {"+.5", 0x1.0000000000000p-1},
        {"5.", 0x1.4000000000000p+2},
        {"0x1.8p1", 0x1.8000000000000p+1},
        {"0X1P+1023", 0x1.0000000000000p+1023},
        {"0x1.fffffffffffffp1023", 0x1.fffffffffffffp+1023},
        {"0x1.fffffffffffff8p1023", INFINITY},
        {"0x1p-1074", 0x0.0000000000001p-1022},
        {"0x1p-1075", 0.0},
        {"0x.8p-1073", 0x0.0000000000001p-1022},
        {"0x1.00000000000008p0", 0x1.0000000000000p+0},
        {"0x1.00000000000018p0", 0x1.0000000000002p+0},
        {"0x1.0000000000000800000000001p0", 0x1.0000000000001p+0},
        {"0x0p5000", 0.0},
        {"-0x0.000p-99", -0.0},
        {"1e-325", 0.0},
        {"3e-324", 0x0.0000000000001p-1022},
        {"0x1p-1080", 0.0},
        {"0x1.8p-1076", 0.0},
        {"0x1.0000000000001p-1075", 0x0.0000000000001p-1022},
        {"0x1.fffffffffffff7ffp1023", 0x1.fffffffffffffp+1023},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *end;
        double v = vi_strtod(cases[i].text, &end);
        cr_expect(same_bits(v, cases[i].value) && *end == '\0', "%s: read %a (%s left), want %a", cases[i].text, v, end,
                  cases[i].value);
    }
}

/* The largest operands of the exact conversion (vi_text.c sizes its big integers for them without
 * checking; under AddressSanitizer an overflow fails here): 800 significant digits, whose first 768
 * are kept, at the smallest and the largest exponent that is not read as 0 or infinity at once, and
 * just outside them; 800 zeros before the first significant digit, or after the last but one; against
 * strtod in the C locale. */
Test(text, the_longest_numbers_at_the_ends_of_the_range)
{
    static char text[11][1200];
    double want[11];
    char zeros[801];
    memset(zeros, '0', 800);
    zeros[800] = '\0';
    snprintf(text[8], sizeof text[8], "0.%s15e800", zeros); /* 0.15 */
    snprintf(text[9], sizeof text[9], "1.5%s1", zeros);     /* 1.5 and a digit past the 768 kept */
    snprintf(text[10], sizeof text[10], "1%se-800", zeros); /* 1 */
    for (int i = 8; i < 11; i++) want[i] = strtod(text[i], NULL);
    for (int i = 0; i < 8; i++) {
        int lead = i < 4 ? -325 - i % 2 : 309 + i % 2; /* the exponent of the leading digit */
        char *o = text[i] + sprintf(text[i], "%s", i % 4 >= 2 ? "-" : "");
        for (int d = 0; d < 800; d++) *o++ = (char)('1' + (d * 7 + i) % 9);
        sprintf(o, "e%d", lead - 799);
        want[i] = strtod(text[i], NULL);
    }
    german();
    for (int i = 0; i < 11; i++) {
        char *end;
        double v = vi_strtod(text[i], &end);
        cr_expect(same_bits(v, want[i]) && *end == '\0', "%.30s...: read %a, strtod %a", text[i], v, want[i]);
    }
}

/* A number no wider than 1200 characters: a random decimal (sign, up to 40 digits, a point, an
 * exponent), a printed double (%.17g, %.*e, %a), or a midpoint between two neighbouring doubles
 * (normal or subnormal) printed exactly (up to 767 digits), alone or just above or below. */
static void random_number(char *out, size_t size)
{
    int form = rand() % 5;
    if (form == 0) {
        char *o = out + sprintf(out, "%s", rand() % 3 == 0 ? "-" : rand() % 4 == 0 ? "+" : "");
        int nd = 1 + rand() % 40, dot = rand() % (nd + 2) - 1;
        for (int d = 0; d < nd; d++) o += sprintf(o, "%s%d", d == dot ? "." : "", rand() % 10);
        if (rand() % 2) sprintf(o, "%ce%d", rand() % 2 ? 'e' : 'E', rand() % 700 - 350);
        return;
    }
    double d = ldexp((double)rand() / RAND_MAX + 0.5, rand() % 2100 - 1075);
    if (form == 1) snprintf(out, size, "%.17g", d);
    else if (form == 2) snprintf(out, size, "%.*e", rand() % 25, d);
    else if (form == 3) snprintf(out, size, "%a", d);
    else { /* the midpoint of d and the next double, exact in long double; 1000 digits show it whole */
        long double mid = ((long double)d + (long double)nextafter(d, INFINITY)) / 2;
        int k = rand() % 3;
        if (k == 1) mid = nextafterl(mid, 0.0L); /* just below */
        snprintf(out, size, "%.1000Le", mid);
        char *e = strchr(out, 'e');
        if (k == 2 && e) { /* a nonzero digit after the last of the mantissa: just above */
            memmove(e + 1, e, strlen(e) + 1);
            *e = '1';
        }
    }
}

/* count numbers made by make (from srand(seed), each in width bytes) read by strtod in the C locale,
 * then by vi_strtod in de_DE: the same value to the bit and the same end. */
static void read_as_strtod(void (*make)(char *, size_t), int count, size_t width, unsigned seed)
{
    char *text = malloc((size_t)count * width);
    double *want = malloc((size_t)count * sizeof *want);
    long *want_end = malloc((size_t)count * sizeof *want_end);
    cr_assert(text && want && want_end);
    srand(seed);
    for (int k = 0; k < count; k++) {
        char *t = text + (size_t)k * width, *end;
        make(t, width);
        want[k] = strtod(t, &end); /* still the C locale */
        want_end[k] = end - t;
    }
    german();
    for (int k = 0; k < count; k++) {
        char *t = text + (size_t)k * width, *end;
        double v = vi_strtod(t, &end);
        if (!same_bits(v, want[k]) || end - t != want_end[k])
            cr_assert(0, "%.200s: read %a ending at %ld, strtod %a ending at %ld", t, v, (long)(end - t), want[k],
                      want_end[k]);
    }
    free(text), free(want), free(want_end);
}

/* Thousands of numbers of every form, against strtod in the C locale: the value to the bit and where
 * the number ends. */
Test(text, numbers_read_as_strtod_reads_them_in_the_c_locale, .timeout = 60)
{
    read_as_strtod(random_number, 6000, 1200, 4242);
}

/* A number of the kind profiles hold, mostly on the fast paths (at most 19 significant digits, a power of
 * ten within +-27: one floating-point operation or 128-bit integers): a random double of 1e-12 to 1e4 printed as numpy.savetxt and C programs
 * write it (%.6e %.17g %.4f %g %.19g %.18e, or an integer), or up to 21 random digits with a point, zeros
 * before and after and an exponent, beyond those limits by a few, or a tie between two doubles of 54
 * bits (2^53 + 1 and the like, times powers of ten). */
static void profile_number(char *out, size_t size)
{
    static const char *const formats[] = {"%.6e", "%.17g", "%.4f", "%g", "%.19g", "%.18e"};
    const char *sign = rand() % 2 ? "-" : "";
    int form = rand() % 9;
    if (form < 6) {
        double d = pow(10.0, -12.0 + 16.0 * rand() / RAND_MAX);
        snprintf(out, size, formats[form], rand() % 2 ? -d : d);
    } else if (form == 6) snprintf(out, size, "%s%d", sign, rand() % 2000001 - 1000000);
    else if (form == 7) {
        char *o = out + sprintf(out, "%s%.*s", sign, rand() % 3, "00");
        int nd = 1 + rand() % 21, dot = rand() % (nd + 1);
        for (int d = 0; d < nd; d++) o += sprintf(o, "%s%d", d == dot ? "." : "", rand() % 10);
        if (rand() % 2) sprintf(o, "%se%d", rand() % 2 ? "000" : "", rand() % 70 - 35);
    } else { /* (2^53 + 2k + 1) 2^j: midway between two doubles, written exactly in decimal when j >= 0 */
        uint64_t odd = (UINT64_C(1) << 53) + 2 * (uint64_t)(rand() % 1000) + 1;
        snprintf(out, size, "%s%llu%se%d", sign, (unsigned long long)odd, rand() % 2 ? "" : "0", rand() % 9);
    }
}

/* Numbers of the profiles' formats, against strtod in the C locale: the value to the bit and the end. */
Test(text, numbers_of_the_profiles_formats_read_as_strtod_reads_them)
{
    read_as_strtod(profile_number, 40000, 64, 41);
}

/* Numbers at the edges of the 19-digit form read in one pass: 19 and 20 significant digits, trailing
 * zeros that bring 20 or more down to 19 (before the point, after it, on both sides), the point first,
 * last or between zeros, long runs of leading zeros and powers of ten at the ends of the 128-bit path;
 * against strtod in the C locale, the value to the bit and the end. */
Test(text, numbers_at_the_edges_of_the_short_form_read_as_strtod_reads_them)
{
    static const char *const text[] = {
        "1234567890123456789", "12345678901234567891", "12345678901234567890", "1234567890123456789000",
        "1234567890123456789.000", "123456789.01234567890", "1.2345678901234567890", "1.23456789012345678901",
        "0.0000000000000000000001234567890123456789", "000000000000000000000000001.5", "1200.", ".0012e3",
        "9999999999999999999e-27", "9999999999999999999e-28", "9999999999999999999e27", "9999999999999999999e28",
        "18446744073709551615", "18446744073709551616e-5", "0.", "0.000e5", ".5e-330", "5e-324", "1.", "10.010"};
    for (size_t i = 0; i < sizeof text / sizeof text[0]; i++) {
        char *end_want, *end;
        double want = strtod(text[i], &end_want), v = vi_strtod(text[i], &end);
        cr_assert(same_bits(v, want) && end == end_want, "%s: read %a ending at %ld, strtod %a ending at %ld", text[i],
                  v, (long)(end - text[i]), want, (long)(end_want - text[i]));
    }
}

/* Integers of 54 to 64 bits times 10^-k, k = 1 .. 27 (read with one 128-bit quotient by 5^k, from a
 * reciprocal of it): random ones (the quotient inexact), multiples of 5^k (exact: m 2^-k), and odd
 * integers of 54 bits times 5^k for k <= 4 (exactly halfway between two doubles: the tie goes to the
 * even one); against strtod in the C locale, the value to the bit. */
Test(text, integers_times_negative_powers_of_ten_read_as_strtod_reads_them)
{
    srand(27);
    char text[64];
    for (int k = 1; k <= 27; k++) {
        uint64_t p5 = 1;
        for (int i = 0; i < k; i++) p5 *= 5;
        for (int i = 0; i < 400; i++) {
            uint64_t w;
            if (i < 300) { /* 54 to 64 bits */
                int bits = 54 + i % 11;
                w = (UINT64_C(1) << (bits - 1)) | ((((uint64_t)rand() << 31) ^ (uint64_t)rand() << 16 ^ (uint64_t)rand())
                                                   & ((UINT64_C(1) << (bits - 1)) - 1));
            } else if (i < 350) { /* a multiple of 5^k above 2^53, below 2^64 */
                uint64_t lo = (UINT64_C(1) << 53) / p5 + 1, hi = UINT64_MAX / p5;
                w = p5 * (lo + (uint64_t)rand() % (hi - lo + 1));
            } else if (k <= 4) /* (2^53 + odd) 5^k 10^-k = (2^53 + odd) 2^-k */
                w = ((UINT64_C(1) << 53) + 2 * (uint64_t)(rand() % 100000) + 1) * p5;
            else
                continue;
            snprintf(text, sizeof text, "%llue-%d", (unsigned long long)w, k);
            double want = strtod(text, NULL), v = vi_strtod(text, NULL);
            cr_assert(same_bits(v, want), "%s: read %a, strtod %a", text, v, want);
        }
    }
}

/* What is not a number, or only partly one: white space, inf and nan, an 'e' or 'p' without digits,
 * "0x" without hex digits, exponents beyond any int. */
Test(text, the_forms_and_ends_of_strtod)
{
    static const char *const texts[] = {
        "", " ", "abc", ".", "-.", "+", "e5", ".e5", " \t\n\v\f\r12", "1e", "1e+", "1E-x", "1.5ex", "0x", "0x.p1",
        "0xg", "0x1p", "0x1.8P-", "inf", "-INF", "Infinity", "infinit", "nan", "-NaN", "nan(123_abc)", "nan(",
        "nan(x y)", "nanq)", "nan(0)", "nan(9)", "nan(a)", "nan(z)", "nan(A)", "nan(Z)", "nan(_)", "1e4294967297",
        "1e-4294967296", "0x1p99999999999999999999", "0x1p4294967296", "0x1p-4294967296", "0x1p2147483648", "1,5",
        "12 34", "0012.50e0003x", "0x000000000000000000001p0", "0x100000000000000000000p0", "0x1.00000000000008000p0",
        "0x1.000000000000080001p0", "0XABCDEF.8P-3", "0xabcdef.8p-3",
        "1" /* followed by 400 zeros and an exponent, below */,
    };
    static char buf[sizeof texts / sizeof texts[0]][512];
    static double want[sizeof texts / sizeof texts[0]];
    static long want_end[sizeof texts / sizeof texts[0]];
    size_t n = sizeof texts / sizeof texts[0];
    for (size_t i = 0; i < n; i++) {
        snprintf(buf[i], sizeof buf[i], "%s", texts[i]);
        if (i == n - 1) {
            memset(buf[i] + 1, '0', 400);
            strcpy(buf[i] + 401, "e-420");
        }
        char *end;
        want[i] = strtod(buf[i], &end);
        want_end[i] = end - buf[i];
    }
    german();
    for (size_t i = 0; i < n; i++) {
        char *end;
        double v = vi_strtod(buf[i], &end);
        cr_expect((same_bits(v, want[i]) || (isnan(v) && isnan(want[i]))) && end - buf[i] == want_end[i],
                  "'%s': read %a ending at %ld, strtod %a ending at %ld", buf[i], v, (long)(end - buf[i]), want[i],
                  want_end[i]);
    }
    cr_assert(vi_strtod("1.5", NULL) == 1.5); /* end may be NULL */
}

/* vi_snprintf in de_DE writes what snprintf writes in the C locale: floating conversions with flags,
 * width, precision and '*' (negative too), long double, infinities and NaN, mixed with the other
 * conversions; and cut to a short buffer, with the same return value. */
static void formatting_in(const char *name, const char *point)
{
    enum { N = 24 };
    char want[N][256], got[N][256];
    double x = -1234.5678901234567, tiny = 1.5e-30;
    for (int pass = 0; pass < 2; pass++) {
        char(*out)[256] = pass ? got : want;
        int (*format)(char *, size_t, const char *, ...) = pass ? vi_snprintf : snprintf;
        if (pass) into(name, point);
        int i = 0;
        format(out[i++], 256, "%g %e %f %E %G", x, x, x, tiny, tiny);
        format(out[i++], 256, "%.17g|%.0f|%#.0f|%#g|%.3e", tiny, 2.5, 2.5, 1.0, 0.5);
        format(out[i++], 256, "[%10.4f][%-12.3e][%+g][% g][%010.2f]", x, x, 0.25, 0.25, -3.75);
        format(out[i++], 256, "[%*.*g][%*.*f][%.*e]", 12, 5, x, -12, 2, x, -1, x);
        format(out[i++], 256, "%a %A %La %Lg", 0.1, -0.1, 0.1L, 1.25L);
        format(out[i++], 256, "%f %F %e %g %g", INFINITY, -INFINITY, NAN, -0.0, 1e300);
        format(out[i++], 256, "%d %i %u %x %X %o %ld %lld %zu %c %s %% %5.1f%%", -7, 42, 7u, 255u, 255u, 8u, -1L, -2LL,
               (size_t)9, 'k', "text", 99.5);
        format(out[i++], 256, "%hhd %hu %jd %td %zd %p|", (signed char)-3, (unsigned short)65535, (intmax_t)-5,
               (ptrdiff_t)-6, (ptrdiff_t)-7, (void *)0);
        format(out[i++], 256, "x = %.17g m, v = %g m/s at t = %.17g s", 0.1, -2.5e-7, 1e-3);
        format(out[i++], 256, "%.300f", 1e-3); /* a floating conversion of more than 256 characters: cut */
        format(out[i++], 256, "[%25.3e][%9.9g][%.12g][%99.19f]", x, x, x, 0.1);
        format(out[i++], 256, "%lu %llu %ju %zx %tu %lx", 4000000000ul, 18000000000000000000ull, (uintmax_t)7, (size_t)255,
               (size_t)3, 0xfffffffful);
        format(out[i++], 256, "no conversion at all");
        cr_assert(i <= N);
        for (int k = 0; pass && k < i; k++) cr_expect(strcmp(got[k], want[k]) == 0, "'%s', want '%s'", got[k], want[k]);
    }
    /* a short buffer: the same text cut and the same length returned; size 0 writes nothing */
    char small_want[10], small_got[10];
    setlocale(LC_ALL, "C");
    int (*volatile c_format)(char *, size_t, const char *, ...) = snprintf; /* no warning of the cut wanted */
    int n_want = c_format(small_want, sizeof small_want, "v = %.6f m/s", 1.5);
    into(name, point);
    volatile size_t cut = sizeof small_got; /* not known to the compiler: no warning of the cut */
    int n_got = vi_snprintf(small_got, cut, "v = %.6f m/s", 1.5);
    cr_assert(n_got == n_want && strcmp(small_got, small_want) == 0, "%d '%s', want %d '%s'", n_got, small_got, n_want,
              small_want);
    /* cut inside text, an integer and a string conversion: the same as the C library */
    char cut_want[3][8], cut_got[3][8];
    volatile size_t cut8 = sizeof cut_want[0];
    memset(cut_want, 'x', sizeof cut_want);
    memset(cut_got, 'x', sizeof cut_got);
    int n_cut[3] = {c_format(cut_want[0], cut8, "abcdefghijkl"), c_format(cut_want[1], cut8, "%ld", 12345678901L),
                    c_format(cut_want[2], cut8, "%s", "a string of 24 characters")};
    int g_cut[3] = {vi_snprintf(cut_got[0], cut8, "abcdefghijkl"), vi_snprintf(cut_got[1], cut8, "%ld", 12345678901L),
                    vi_snprintf(cut_got[2], cut8, "%s", "a string of 24 characters")};
    for (int k = 0; k < 3; k++)
        cr_expect(g_cut[k] == n_cut[k] && memcmp(cut_got[k], cut_want[k], 8) == 0, "%d: %d '%.8s'", k, g_cut[k], cut_got[k]);
    char guarded[16]; /* a conversion after text, cut: nothing written past the size given */
    memset(guarded, 'x', sizeof guarded);
    cr_expect(vi_snprintf(guarded, cut8, "ab%s", "a string of 24 characters") == 27 && strcmp(guarded, "aba str") == 0 &&
              memcmp(guarded + 8, "xxxxxxxx", 8) == 0, "%.16s", guarded);
    strcpy(small_got, "old");
    cr_assert(vi_snprintf(small_got, sizeof small_got, "%s", "") == 0 && small_got[0] == '\0');
    strcpy(small_got, "old");
    char empty[1] = "";
    cr_assert(vi_snprintf(small_got, sizeof small_got, empty) == 0 && small_got[0] == '\0', "%s", small_got);
    small_got[0] = 'z';
    cr_assert(vi_snprintf(small_got, 0, "%g", 1.5) == 3 && small_got[0] == 'z');
    cr_assert(vi_snprintf(NULL, 0, "%s = %.1f", "m", 0.5) == 7);
}

Test(text, formatting_writes_what_the_c_locale_writes) { formatting_in("de_DE.UTF-8", ","); }

/* ps_AF.UTF-8 writes U+066B, two bytes in UTF-8, as its decimal point: the text gets shorter by one
 * byte with each replaced. */
Test(text, formatting_with_a_decimal_point_of_two_bytes) { formatting_in("ps_AF.UTF-8", "\xd9\xab"); }

/* Refused with -1 (the text before the conversion kept): %n, the non-standard ' flag, and a floating
 * conversion longer than VI_TEXT_FLOAT_MAX - 1 characters. */
Test(text, formatting_refuses_what_it_cannot_do)
{
    german();
    char buf[64];
    int count = 0;
    cr_assert(vi_snprintf(buf, sizeof buf, "a = %g%n", 0.5, &count) == -1 && strcmp(buf, "a = 0.5") == 0, "%s", buf);
    cr_assert(count == 0);
    /* formats the compiler would warn of (not literals here): a non-standard flag, a format ending in
     * '%', an unknown conversion, length modifiers a conversion does not take, wide characters,
     * widths and precisions beyond an int (also after a conversion that went well) */
    static const char *const bad[] = {"%'d", "50%", "%k", "%Ld", "ab%Ld", "%Lu", "%hf", "%lc", "%hp", "%ls", "%99999999999d",
                                      "%.99999999999d", "%d%99999999999d", "%d%.99999999999d"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char fmt[32];
        snprintf(fmt, sizeof fmt, "%s", bad[i]);
        cr_expect(vi_snprintf(buf, sizeof buf, fmt, 1000) == -1, "%s: %s", bad[i], buf);
    }
    volatile int int_min = INT_MIN; /* not known to the compiler: no warning of its width */
    cr_assert(vi_snprintf(buf, sizeof buf, "%*d|", int_min, 5) == -1); /* -INT_MIN is no int */
    cr_assert(vi_snprintf(buf, sizeof buf, "[%*d][%-*d][%.*d]", -3, 5, -3, 5, -2, 5) == 13 && strcmp(buf, "[5  ][5  ][5]") == 0,
              "%s", buf);
    cr_assert(vi_snprintf(buf, sizeof buf, "b%.*f", VI_TEXT_FLOAT_MAX, 1.0) == -1 && strcmp(buf, "b") == 0);
    cr_assert(vi_snprintf(buf, sizeof buf, "%.*f", VI_TEXT_FLOAT_MAX - 3, 1.0) == VI_TEXT_FLOAT_MAX - 1);
    cr_assert(vi_snprintf(buf, sizeof buf, "%.*f", VI_TEXT_FLOAT_MAX - 2, 1.0) == -1); /* one character too many */
}

/* A profile file read in de_DE holds what it holds in the C locale: numbers of more than 19 digits,
 * exponents beyond +-27, hexadecimal (the values from Python's float()). */
Test(text, a_profile_file_reads_the_same_in_de_DE)
{
    german();
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_text_test_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fprintf(f, "0 1.5e-30\n0x1p-1 2e-30\n0.12345678901234567890123e1; 1.5e-30\n");
    fclose(f);
    char msg[512];
    vi_profile *p = vi_profile_load(path, 0.5, 0, msg, sizeof msg);
    remove(path);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(vi_profile_x_last(p) == 0x1.3c0ca428c59fbp+0, "x_last = %a", vi_profile_x_last(p));
    double y[4];
    vi_profile_eval(p, 0.0, y);
    cr_assert(y[0] == 0x1.e6c71fe61a3efp-100, "yb(0) = %a", y[0]);
    vi_profile_free(p);
}
