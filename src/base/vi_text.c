/* vi_text.c - numbers as text with '.' whatever the locale; definitions and reasons in vi_text.h. */
#include "vi_text.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

_Static_assert(DBL_MANT_DIG == 53 && DBL_MAX_EXP == 1024 && DBL_MIN_EXP == -1021, "double is IEEE 754 binary64");
_Static_assert(sizeof(size_t) == sizeof(ptrdiff_t), "%zd and %tu pass through as ptrdiff_t and size_t");

/* ---- reading: rounding ---------------------------------------------------------------------- */

#define EXP2_MIN -1022 /* the exponent of the smallest normal double */
#define MANT_BITS 53
/* Binary exponents beyond +-EXP2_CLAMP give infinity or zero for any 64-bit mantissa. */
#define EXP2_CLAMP (1L << 20)

/* The bits of q: 0 for 0, else one more than the place of its highest set bit. */
static int bits64(uint64_t q)
{
#if defined(__GNUC__) && ULLONG_MAX == UINT64_MAX
    return q ? 64 - __builtin_clzll(q) : 0;
#else
    int b = 0;
    for (; q; q >>= 1) b++; /* bounded: 64 bits */
    return b;
#endif
}

/* (q + f) 2^e2 rounded to the nearest double, ties to even, where 2^62 <= q < 2^64, 0 <= f < 1 and
 * f > 0 exactly when sticky; |e2| <= EXP2_CLAMP. In the subnormal range fewer than 53 bits are kept,
 * so that there too the value is rounded once. */
static double round_bits(uint64_t q, int sticky, long e2)
{
    int b = bits64(q);
    long lead = b - 1 + e2; /* 2^lead <= the value < 2^(lead + 1) */
    long keep = lead >= EXP2_MIN ? MANT_BITS : lead - EXP2_MIN + MANT_BITS; /* bits of the result */
    if (keep < 0) return 0.0; /* below half the smallest subnormal */
    int drop = b - (int)keep; /* 10 to 64 */
    uint64_t m = drop == 64 ? 0 : q >> drop;
    uint64_t rest = drop == 64 ? q : q & ((UINT64_C(1) << drop) - 1), half = UINT64_C(1) << (drop - 1);
    if (rest > half || (rest == half && (sticky || (m & 1u)))) m++;
    /* exact (m <= 2^53, 2^(e2 + drop) >= 2^-1074) up to DBL_MAX; beyond, ldexp overflows to HUGE_VAL */
    return ldexp((double)m, (int)(e2 + drop));
}

/* ---- reading: exact big-integer arithmetic ---------------------------------------------------- */

/* Significant decimal digits kept: no midpoint between two doubles has more than 767, so a number cut
 * after 768 digits with a nonzero digit appended when it had more lies between the same doubles and
 * midpoints as the whole number. */
#define DIGITS_MAX 768
/* The exponents of the leading decimal digit beyond which every number is infinite (10^310 > DBL_MAX)
 * or zero (below 10^-325, less than 2^-1075, half the smallest subnormal). */
#define EXP10_LEAD_MAX 309
#define EXP10_LEAD_MIN -325
/* The largest numbers exact() makes: D < 10^769 (2555 bits) shifted, or 5^(768 + 325) < 2^2538
 * shifted by 63 bits: 2601 bits, 82 words written by the shift. No operation checks the size:
 * tests/test_text.c reads the largest operands under AddressSanitizer (it fails with 81 words). */
#define BIG_WORDS 84

typedef struct {
    uint32_t w[BIG_WORDS]; /* little-endian 32-bit words, zero from w[n] on */
    int n;                 /* words in use; w[n - 1] != 0 */
} big;

static void big_mul_add(big *a, uint32_t k, uint32_t add)
{
    uint64_t carry = add;
    for (int i = 0; i < a->n; i++) {
        carry += (uint64_t)a->w[i] * k;
        a->w[i] = (uint32_t)carry;
        carry >>= 32;
    }
    if (carry) a->w[a->n++] = (uint32_t)carry;
}

static int big_bits(const big *a) { return a->n ? 32 * (a->n - 1) + bits64(a->w[a->n - 1]) : 0; }

static void big_shift_left(big *a, int s)
{
    int words = s / 32, sh = s % 32, n = a->n + words + 1;
    for (int i = n - 1; i >= words; i--) {
        uint64_t hi = i - words < a->n ? a->w[i - words] : 0, lo = i - words - 1 >= 0 ? a->w[i - words - 1] : 0;
        a->w[i] = (uint32_t)(((hi << 32 | lo) << sh) >> 32);
    }
    memset(a->w, 0, (size_t)words * sizeof a->w[0]);
    a->n = n;
    while (a->n && !a->w[a->n - 1]) a->n--;
}

static void big_halve(big *a)
{
    for (int i = 0; i < a->n; i++) a->w[i] = a->w[i] >> 1 | (i + 1 < a->n ? a->w[i + 1] << 31 : 0);
    while (a->n && !a->w[a->n - 1]) a->n--;
}

static int big_compare(const big *a, const big *b)
{
    if (a->n != b->n) return a->n < b->n ? -1 : 1;
    for (int i = a->n - 1; i >= 0; i--)
        if (a->w[i] != b->w[i]) return a->w[i] < b->w[i] ? -1 : 1;
    return 0;
}

static void big_subtract(big *a, const big *b) /* a >= b */
{
    int64_t borrow = 0;
    for (int i = 0; i < a->n; i++) {
        int64_t d = (int64_t)a->w[i] - (i < b->n ? b->w[i] : 0) - borrow;
        borrow = d < 0;
        a->w[i] = (uint32_t)(d + (borrow << 32));
    }
    while (a->n && !a->w[a->n - 1]) a->n--;
}

static void big_mul_pow5(big *a, int e)
{
    for (; e >= 13; e -= 13) big_mul_add(a, 1220703125u, 0); /* 5^13 < 2^32 */
    static const uint32_t pow5[13] = {1, 5, 25, 125, 625, 3125, 15625, 78125, 390625, 1953125, 9765625, 48828125,
                                      244140625};
    big_mul_add(a, pow5[e], 0);
}

/* D 10^e10 rounded to the nearest double, D the integer of the nd digits dig[] (values 0 to 9, nd <=
 * DIGITS_MAX + 1, the first nonzero), its leading digit's exponent nd - 1 + e10 within
 * [EXP10_LEAD_MIN, EXP10_LEAD_MAX]. With N = D 5^e10, M = 1 (e10 >= 0) or N = D, M = 5^-e10, the
 * value is N / M 2^e10; one of them is shifted so that the quotient has 63 or 64 bits, which long
 * division gives with the remainder deciding the rounding (sticky). */
static double exact(const char *dig, int nd, int e10, int sticky_digit)
{
    big n = {{(uint32_t)dig[0]}, 1}, m = {{1}, 1};
    for (int i = 1; i < nd; i++) big_mul_add(&n, 10, (uint32_t)dig[i]);
    if (sticky_digit) big_mul_add(&n, 10, 1), e10--;
    if (e10 >= 0) big_mul_pow5(&n, e10);
    else big_mul_pow5(&m, -e10);
    int k = 63 - (big_bits(&n) - big_bits(&m)); /* N 2^k / M (k > 0) or N / (M 2^-k) has 63 to 64 bits */
    if (k > 0) big_shift_left(&n, k);
    big_shift_left(&m, 63 + (k < 0 ? -k : 0));
    uint64_t q = 0;
    for (int i = 63; i >= 0; i--) { /* restoring division, one quotient bit a pass */
        if (big_compare(&n, &m) >= 0) big_subtract(&n, &m), q |= UINT64_C(1) << i;
        big_halve(&m);
    }
    return round_bits(q, n.n != 0, (long)e10 - k);
}

/* ---- reading: the fast paths ------------------------------------------------------------------ */

/* w 10^e when w and 10^e are exact doubles (w <= 2^53, |e| <= 22): one rounded operation, the
 * correctly rounded result (Clinger's fast path; only where double arithmetic is not carried out in
 * a wider format). 0 when it does not apply. */
static int clinger(uint64_t w, int e, double *v)
{
#if FLT_EVAL_METHOD == 0
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                     1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    if (w <= (UINT64_C(1) << 53) && e >= -22 && e <= 22) {
        *v = e >= 0 ? (double)w * pow10[e] : (double)w / pow10[-e];
        return 1;
    }
#endif
    (void)w, (void)e, (void)v;
    return 0;
}

#ifdef __SIZEOF_INT128__
typedef unsigned __int128 u128;

/* 5^k for k = 0 .. EXP10_U128_MAX (5^27 < 2^63): the exponents the 128-bit path takes. */
#define EXP10_U128_MAX 27
static const uint64_t POW5[EXP10_U128_MAX + 1] = {
    1u, 5u, 25u, 125u, 625u, 3125u, 15625u, 78125u, 390625u, 1953125u, 9765625u, 48828125u, 244140625u,
    1220703125u, 6103515625u, 30517578125u, 152587890625u, 762939453125u, 3814697265625u, 19073486328125u,
    95367431640625u, 476837158203125u, 2384185791015625u, 11920928955078125u, 59604644775390625u,
    298023223876953125u, 1490116119384765625u, 7450580596923828125u};

/* m 2^e for m <= 2^53 and a normal result: m times the double 2^e, exact, as ldexp gives it (ldexp
 * itself where 2^e is no normal double). */
static double times_pow2(double m, int e)
{
    if (e < EXP2_MIN || e > 1023) return ldexp(m, e);
    uint64_t bits = (uint64_t)(e + 1023) << 52;
    double p;
    memcpy(&p, &bits, sizeof p);
    return m * p;
}

/* (q + a fraction that is nonzero when sticky) 2^e2, rounded to the nearest double (ties to even).
 * q has more than 53 bits when sticky; the value is a normal double (|e| <= EXP10_U128_MAX). */
static double round_u128(u128 q, int sticky, int e2)
{
    uint64_t hi = (uint64_t)(q >> 64);
    int bits = hi ? 64 + bits64(hi) : bits64((uint64_t)q);
    if (bits <= MANT_BITS) return times_pow2((double)(uint64_t)q, e2);
    int drop = bits - MANT_BITS;
    uint64_t m = (uint64_t)(q >> drop);
    u128 rest = q & (((u128)1 << drop) - 1), half = (u128)1 << (drop - 1);
    m += (uint64_t)(rest > half) | ((uint64_t)(rest == half) & ((uint64_t)(sticky != 0) | (m & 1u))); /* no branch: the
                                                                                  * bits that decide are random */
    return times_pow2((double)m, e2 + drop);
}

/* RECIP[k] = floor(2^(63 + b) / 5^k), b the bits of 5^k, for k = 1 .. EXP10_U128_MAX: the reciprocals
 * that take the place of a division in scaled (tests/test_text.c reads numbers of every such exponent,
 * their quotients exact and not, against strtod). */
static const uint64_t RECIP[EXP10_U128_MAX + 1] = {
    0u, UINT64_C(14757395258967641292), UINT64_C(11805916207174113034), UINT64_C(9444732965739290427),
    UINT64_C(15111572745182864683), UINT64_C(12089258196146291747), UINT64_C(9671406556917033397),
    UINT64_C(15474250491067253436), UINT64_C(12379400392853802748), UINT64_C(9903520314283042199),
    UINT64_C(15845632502852867518), UINT64_C(12676506002282294014), UINT64_C(10141204801825835211),
    UINT64_C(16225927682921336339), UINT64_C(12980742146337069071), UINT64_C(10384593717069655257),
    UINT64_C(16615349947311448411), UINT64_C(13292279957849158729), UINT64_C(10633823966279326983),
    UINT64_C(17014118346046923173), UINT64_C(13611294676837538538), UINT64_C(10889035741470030830),
    UINT64_C(17422457186352049329), UINT64_C(13937965749081639463), UINT64_C(11150372599265311570),
    UINT64_C(17840596158824498513), UINT64_C(14272476927059598810), UINT64_C(11417981541647679048)};

/* w 10^e correctly rounded, 0 < w < 2^64, |e| <= EXP10_U128_MAX, not on Clinger's fast path: w 5^e 2^e
 * is exact in 128 bits for e >= 0 (54 bits or more: w > 2^53 or 5^e > 2^53); for e < 0 the quotient
 * q = floor(n / d), n = w 2^sh < 2^(63 + b), d = 5^-e of b bits (3 to 63), has 63 or 64 bits, and the
 * remainder decides the rounding of a tie. With t = floor(n / 2^(b - 1)) < 2^64, t RECIP / 2^64 lies
 * within 2 below n / d (t 2^(b - 1) is within 2^(b - 1) <= d below n, RECIP within 1 below 2^(63 + b) / d,
 * t < 2^64): its integer part is q, q - 1 or q - 2, and the exact remainder puts it right. */
static double scaled(uint64_t w, int e)
{
    if (e >= 0) return round_u128((u128)w * POW5[e], 0, e);
    uint64_t d = POW5[-e];
    int b = bits64(d), sh = 63 + b - bits64(w); /* 2 to 125 */
    u128 n = (u128)w << sh;
    uint64_t q = (uint64_t)(((u128)(uint64_t)(n >> (b - 1)) * RECIP[-e]) >> 64);
    u128 rem = n - (u128)q * d;
    for (int i = 0; i < 2; i++) { /* bounded: two passes, without a branch (whether rem >= d is random) */
        uint64_t more = rem >= d;
        rem -= (u128)(d & (0 - more)), q += more;
    }
    return round_u128(q, rem != 0, -sh + e);
}
#endif

/* ---- reading: the forms --------------------------------------------------------------------- */

typedef struct {
    char dig[DIGITS_MAX]; /* significant digits, values 0 to 9, the first nonzero */
    int nd;
    int sticky;           /* a nonzero digit after the DIGITS_MAX kept */
    long long point;      /* significant digits before the decimal point (negative: zeros after it) */
} decimal;

/* The digits of a decimal mantissa ("12.5", "5.", ".5") at c into d; the character after them, or NULL
 * when there is no digit. */
static const char *scan_mantissa(const char *c, decimal *d)
{
    int frac = 0, any = 0;
    for (;; c++) { /* bounded by the string */
        if (*c == '.' && !frac) {
            frac = 1;
            continue;
        }
        if (*c < '0' || *c > '9') break;
        any = 1;
        if (*c == '0' && !d->nd) { /* a leading zero */
            d->point -= frac;
            continue;
        }
        d->point += !frac;
        if (d->nd < DIGITS_MAX) d->dig[d->nd++] = (char)(*c - '0');
        else if (*c != '0') d->sticky = 1;
    }
    if (!d->sticky)
        while (d->nd && !d->dig[d->nd - 1]) d->nd--; /* trailing zeros: bounded by nd */
    return any ? c : NULL;
}

/* An exponent "[+-]digits" at c (after the e or p): its value (saturated at +-10^15) in *e, the
 * character after it; c itself when no digit follows. */
static const char *scan_exponent(const char *c, long long *e)
{
    const char *d = c;
    int neg = *d == '-';
    long long v = 0;
    if (*d == '+' || *d == '-') d++;
    if (*d < '0' || *d > '9') return c;
    for (; *d >= '0' && *d <= '9'; d++) /* bounded by the string */
        if (v < 1000000000000000LL) v = 10 * v + (*d - '0');
    *e = neg ? -v : v;
    return d;
}

/* The digits at s appended to *w (*w 10^k + their integer, modulo 2^64, for k digits), four a pass:
 * their values do not wait for *w (the chain of multiplications is a quarter as long), and a byte is
 * read only after a digit. The character after them. */
static const char *read_digits(const char *s, uint64_t *w)
{
    uint64_t v = *w;
    for (;; s += 4) { /* bounded by the string */
        unsigned d0 = (unsigned)(s[0] - '0'), d1, d2, d3;
        if (d0 > 9) break;
        if ((d1 = (unsigned)(s[1] - '0')) > 9) {
            v = 10 * v + d0, s += 1;
            break;
        }
        if ((d2 = (unsigned)(s[2] - '0')) > 9) {
            v = 100 * v + (10 * d0 + d1), s += 2;
            break;
        }
        if ((d3 = (unsigned)(s[3] - '0')) > 9) {
            v = 1000 * v + (100 * d0 + 10 * d1 + d2), s += 3;
            break;
        }
        v = 10000 * v + (1000 * d0 + 100 * d1 + 10 * d2 + d3);
    }
    *w = v;
    return s;
}

/* The short form of a decimal number at c (after the sign), read in one pass without the digit array:
 * up to 19 digits from the first nonzero one to the last digit (trailing zeros counted) as the integer
 * w, w 10^e10 the value, which takes Clinger's path or the 128-bit one. The digits, the point and the
 * exponent are the ones scan_mantissa and scan_exponent take, and w 10^e10 is rounded by the same
 * functions decimal_number calls for them, so the result is the same double. Its value in *v and the
 * character after it; NULL when the number is not of that form (then decimal_number reads it whole). */
static const char *short_decimal(const char *c, double *v)
{
    uint64_t w = 0;
    const char *first = c;
    while (*c == '0') c++; /* leading zeros: bounded by the string */
    const char *lead_at = c;
    c = read_digits(c, &w);
    long long nd = c - lead_at, frac = 0; /* the digits in w; those after the point */
    int digit = c > first;
    if (*c == '.') {
        const char *point = ++c;
        if (!nd)
            while (*c == '0') c++; /* zeros after the point before the first nonzero digit: bounded */
        lead_at = c;
        c = read_digits(c, &w);
        nd += c - lead_at, frac = c - point, digit |= c > point;
    }
    if (!digit || !w || nd > 19) return NULL; /* no digit; zero or more than 19 digits: the long form */
    long long e = 0;
    if (*c == 'e' || *c == 'E') {
        const char *after = scan_exponent(c + 1, &e);
        if (after != c + 1) c = after;
    }
    long long e10 = e - frac, lead = e10 + nd - 1; /* the exponents of the last and the leading digit */
    if (lead < EXP10_LEAD_MIN || lead > EXP10_LEAD_MAX) return NULL;
    for (; w > (UINT64_C(1) << 53) && w % 10 == 0; e10++) w /= 10; /* trailing zeros, for Clinger's path: bounded by 19 */
    if (clinger(w, (int)e10, v)) return c;
#ifdef __SIZEOF_INT128__
    if (e10 >= -EXP10_U128_MAX && e10 <= EXP10_U128_MAX) {
        *v = scaled(w, (int)e10);
        return c;
    }
#endif
    return NULL;
}

/* A decimal number at c (after the sign): its value in *v, the character after it; NULL if none. */
static const char *decimal_number(const char *c, double *v)
{
    const char *fast = short_decimal(c, v);
    if (fast) return fast;
    decimal d;
    d.nd = d.sticky = 0, d.point = 0;
    c = scan_mantissa(c, &d);
    if (!c) return NULL;
    long long e = 0;
    if (*c == 'e' || *c == 'E') {
        const char *after = scan_exponent(c + 1, &e);
        if (after != c + 1) c = after;
    }
    long long lead = d.point + e - 1; /* the exponent of the leading digit */
    if (!d.nd || lead < EXP10_LEAD_MIN) *v = 0.0;
    else if (lead > EXP10_LEAD_MAX) *v = HUGE_VAL;
    else {
        int e10 = (int)(lead + 1 - d.nd); /* the value is D 10^e10, D the integer of the digits */
        uint64_t w = 0;
        for (int i = 0; i < d.nd && d.nd <= 19 && !d.sticky; i++) w = 10 * w + (uint64_t)d.dig[i];
        if (d.nd > 19 || d.sticky || !clinger(w, e10, v)) {
#ifdef __SIZEOF_INT128__
            if (d.nd <= 19 && !d.sticky && e10 >= -EXP10_U128_MAX && e10 <= EXP10_U128_MAX) *v = scaled(w, e10);
            else
#endif
                *v = exact(d.dig, d.nd, e10, d.sticky);
        }
    }
    return c;
}

static int hex_value(char ch)
{
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* A hexadecimal number at c (after "0x"): its value in *v, the character after it; NULL when no hex
 * digit follows. The first 16 significant hex digits are kept (64 bits), the rest mark the sticky bit. */
static const char *hex_number(const char *c, double *v)
{
    uint64_t q = 0;
    int frac = 0, any = 0, kept = 0, sticky = 0;
    long long e2 = 0;
    for (;; c++) { /* bounded by the string */
        if (*c == '.' && !frac) {
            frac = 1;
            continue;
        }
        int h = hex_value(*c);
        if (h < 0) break;
        any = 1;
        if (!q && !h) { /* a leading zero */
            e2 -= 4 * frac;
            continue;
        }
        if (kept < 16) q = q << 4 | (uint64_t)h, kept++, e2 -= 4 * frac;
        else sticky |= h != 0, e2 += 4 * !frac;
    }
    if (!any) return NULL;
    long long p = 0;
    if (*c == 'p' || *c == 'P') {
        const char *after = scan_exponent(c + 1, &p);
        if (after != c + 1) c = after;
    }
    int up = 64 - bits64(q); /* q shifted to 64 bits for round_bits */
    e2 += p - up;
    if (e2 < -EXP2_CLAMP || e2 > EXP2_CLAMP) e2 = e2 < 0 ? -EXP2_CLAMP : EXP2_CLAMP;
    *v = q ? round_bits(q << up, sticky, (long)e2) : 0.0;
    return c;
}

/* Does c start with word (lower case), in any case? */
static int starts_with(const char *c, const char *word)
{
    for (; *word; c++, word++) /* bounded by word */
        if (*c != *word && *c != *word - 'a' + 'A') return 0;
    return 1;
}

/* inf, infinity, nan, nan(chars) at c (after the sign): the value in *v, the character after it; NULL
 * if none. */
static const char *special(const char *c, double *v)
{
    if (starts_with(c, "inf")) {
        *v = INFINITY;
        return c + (starts_with(c, "infinity") ? 8 : 3);
    }
    if (!starts_with(c, "nan")) return NULL;
    *v = NAN;
    const char *d = c + 3;
    if (*d != '(') return d;
    for (d++; (*d >= '0' && *d <= '9') || (*d >= 'a' && *d <= 'z') || (*d >= 'A' && *d <= 'Z') || *d == '_'; d++) {
    } /* bounded by the string */
    return *d == ')' ? d + 1 : c + 3;
}

double vi_strtod(const char *s, char **end)
{
    const char *c = s;
    while (*c == ' ' || (*c >= '\t' && *c <= '\r')) c++; /* the C locale's white space; bounded by s */
    int neg = *c == '-';
    if (*c == '+' || *c == '-') c++;
    double v = 0.0;
    const char *after = NULL;
    if ((*c >= '1' && *c <= '9') || *c == '.' || (*c == '0' && c[1] != 'x' && c[1] != 'X'))
        after = decimal_number(c, &v); /* neither inf, nan nor hex */
    else {
        after = special(c, &v);
        if (!after && c[0] == '0' && (c[1] == 'x' || c[1] == 'X')) after = hex_number(c + 2, &v);
        if (!after) after = decimal_number(c, &v); /* also "0x" without hex digits: the 0 */
    }
    if (end) *end = (char *)(after ? after : s);
    if (!after) return 0.0;
    return neg ? -v : v;
}

/* ---- writing -------------------------------------------------------------------------------- */

/* The formats below are built at run time, one conversion each, from a format the compiler checked
 * (VI_PRINTF_FORMAT on vi_snprintf). */
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#endif

/* The output: buf of size bytes, used the length of the whole text so far (also what did not fit). */
typedef struct {
    char *buf;
    size_t size, used;
} sink;

static void put(sink *o, const char *text, size_t len)
{
    if (o->used < o->size) {
        size_t room = o->size - 1 - o->used, k = len < room ? len : room;
        memcpy(o->buf + o->used, text, k);
        o->buf[o->used + k] = '\0';
    }
    o->used += len;
}

/* One conversion alone, as the C library's snprintf takes it. */
typedef struct {
    char text[64];  /* %, flags, width, precision, length modifier, conversion */
    char length[3]; /* "", hh, h, l, ll, j, z, t, L */
    char conv;
} conversion;

/* The conversion at *f (after its '%'), with '*' widths and precisions taken from ap and written out
 * (a negative width is the '-' flag, a negative precision none). 0, or -1 for what vi_text.h refuses. */
static int parse_conversion(const char **f, va_list *ap, conversion *cv)
{
    const char *c = *f;
    char flags[8] = "";
    int width = -1, prec = -1, nflags = 0;
    for (; *c && strchr("-+ #0", *c); c++) /* bounded by the five flags (each kept once) */
        if (!strchr(flags, *c)) flags[nflags++] = *c;
    if (*c == '*') {
        width = va_arg(*ap, int), c++;
        if (width == INT_MIN) return -1;
        if (width < 0 && !strchr(flags, '-')) flags[nflags++] = '-';
        width = width < 0 ? -width : width;
    } else
        for (; *c >= '0' && *c <= '9'; c++) { /* bounded by the format */
            if (width > (INT_MAX - 9) / 10) return -1;
            width = (width < 0 ? 0 : 10 * width) + (*c - '0');
        }
    if (*c == '.') {
        c++, prec = 0;
        if (*c == '*') prec = va_arg(*ap, int), c++;
        else
            for (; *c >= '0' && *c <= '9'; c++) { /* bounded by the format */
                if (prec > (INT_MAX - 9) / 10) return -1;
                prec = 10 * prec + (*c - '0');
            }
    }
    static const char *const lengths[] = {"hh", "h", "ll", "l", "j", "z", "t", "L"};
    cv->length[0] = '\0';
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0] && !cv->length[0]; i++)
        if (strncmp(c, lengths[i], strlen(lengths[i])) == 0) strcpy(cv->length, lengths[i]), c += strlen(lengths[i]);
    if (!*c || !strchr("diouxXcspfFeEgGaA", *c)) return -1;
    cv->conv = *c;
    *f = c + 1;
    char w[16] = "", p[16] = "";
    if (width >= 0) snprintf(w, sizeof w, "%d", width);
    if (prec >= 0) snprintf(p, sizeof p, ".%d", prec);
    snprintf(cv->text, sizeof cv->text, "%%%s%s%s%s%c", flags, w, p, cv->length, cv->conv);
    return 0;
}

static int is_length(const conversion *cv, const char *l) { return strcmp(cv->length, l) == 0; }

#define FORMAT(type) snprintf(dst, room, cv->text, va_arg(*ap, type))

/* An integer, character, string or pointer conversion into dst (room bytes): snprintf's result, -1 for
 * a length modifier the conversion does not take. */
static int format_other(const conversion *cv, va_list *ap, char *dst, size_t room)
{
    int l0 = is_length(cv, "") || is_length(cv, "hh") || is_length(cv, "h");
    if (strchr("di", cv->conv)) {
        if (l0) return FORMAT(int);
        if (is_length(cv, "l")) return FORMAT(long);
        if (is_length(cv, "ll")) return FORMAT(long long);
        if (is_length(cv, "j")) return FORMAT(intmax_t);
        if (is_length(cv, "z") || is_length(cv, "t")) return FORMAT(ptrdiff_t);
        return -1;
    }
    if (strchr("ouxX", cv->conv)) {
        if (l0) return FORMAT(unsigned);
        if (is_length(cv, "l")) return FORMAT(unsigned long);
        if (is_length(cv, "ll")) return FORMAT(unsigned long long);
        if (is_length(cv, "j")) return FORMAT(uintmax_t);
        if (is_length(cv, "z") || is_length(cv, "t")) return FORMAT(size_t);
        return -1;
    }
    if (cv->conv == 'c' && is_length(cv, "")) return FORMAT(int);
    if (cv->conv == 's' && is_length(cv, "")) return FORMAT(const char *);
    if (cv->conv == 'p' && is_length(cv, "")) return FORMAT(void *);
    return -1; /* %lc and %ls: wide characters are converted by the locale's character set */
}

/* The decimal point the C library writes now, into point (size bytes): 0, or -1 if it cannot be told. */
static int library_point(char *point, size_t size)
{
    char probe[32];
    int k = snprintf(probe, sizeof probe, "%.1f", 0.5); /* "0", the point, "5" */
    if (k < 3 || k >= (int)sizeof probe || (size_t)(k - 2) >= size || probe[0] != '0' || probe[k - 1] != '5')
        return -1;
    memcpy(point, probe + 1, (size_t)(k - 2));
    point[k - 2] = '\0';
    return 0;
}

/* A floating conversion with '.' as its decimal point, appended to o. point: the C library's, found at
 * the first floating conversion ("" before). 0, or -1. */
static int put_floating(sink *o, const conversion *cv, va_list *ap, char *point, size_t point_size)
{
    char text[VI_TEXT_FLOAT_MAX], *dst = text;
    size_t room = sizeof text;
    int k;
    if (is_length(cv, "L")) k = FORMAT(long double);
    else if (is_length(cv, "") || is_length(cv, "l")) k = FORMAT(double);
    else return -1;
    if (k < 0 || k >= (int)sizeof text || (!point[0] && library_point(point, point_size) < 0)) return -1;
    size_t len = strlen(point);
    char *at = strcmp(point, ".") != 0 ? strstr(text, point) : NULL;
    if (at) { /* the point replaced by '.' */
        *at = '.';
        memmove(at + 1, at + len, strlen(at + len) + 1);
        k -= (int)len - 1;
    }
    put(o, text, (size_t)k);
    return 0;
}

int vi_vsnprintf(char *buf, size_t size, const char *fmt, va_list ap)
{
    va_list args;
    va_copy(args, ap);
    sink o = {buf, size, 0};
    char point[16] = "";
    int rc = 0;
    if (size) buf[0] = '\0';
    while (*fmt && rc == 0) { /* bounded by the format: each pass takes text or a conversion */
        const char *pct = strchr(fmt, '%');
        size_t lit = pct ? (size_t)(pct - fmt) : strlen(fmt);
        put(&o, fmt, lit);
        fmt += lit;
        if (!pct) break;
        fmt++;
        conversion cv;
        if (*fmt == '%') put(&o, "%", 1), fmt++;
        else if (parse_conversion(&fmt, &args, &cv) < 0) rc = -1;
        else if (strchr("fFeEgGaA", cv.conv)) rc = put_floating(&o, &cv, &args, point, sizeof point);
        else {
            int k = format_other(&cv, &args, o.used < size ? buf + o.used : NULL, o.used < size ? size - o.used : 0);
            if (k < 0) rc = -1;
            else o.used += (size_t)k;
        }
    }
    va_end(args);
    if (rc < 0 || o.used > INT_MAX) return -1;
    return (int)o.used;
}

int vi_snprintf(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vi_vsnprintf(buf, size, fmt, ap);
    va_end(ap);
    return k;
}
