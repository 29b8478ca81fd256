/* Unit tests of the rolling constraint yb (vi_profile.h). Expected values from closed forms (flat
 * ground, a V-shaped trough, a step, a narrow bump, a periodic copy) and from a brute-force
 * evaluation of the definition written here: the maximum over the vertices and, segment by
 * segment, a golden-section search of the concave h(s) + sqrt(R^2 - (x - s)^2) (no envelope). */
#include <criterion/criterion.h>
#include <errno.h>
#include <float.h>
#include <malloc.h> /* mallinfo2 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "vi_profile.h"

#define R 0.475

static vi_profile *make(const double *x, const double *h, size_t n, double r, int periodic)
{
    char msg[512];
    vi_profile *p = vi_profile_create(x, h, n, r, periodic, "test", msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    return p;
}

static double yb(const vi_profile *p, double x)
{
    double y[4];
    vi_profile_eval(p, x, y);
    return y[0];
}

/* The definition: max over s in the table with |s - x| <= r of h(s) + sqrt(r^2 - (x - s)^2), - r. */
static double brute(const double *x, const double *h, size_t n, double r, double at)
{
    double best = -INFINITY;
    for (size_t i = 0; i < n; i++)
        if (fabs(x[i] - at) <= r) best = fmax(best, h[i] + sqrt(r * r - (x[i] - at) * (x[i] - at)) - r);
    for (size_t j = 0; j + 1 < n; j++) {
        double a = fmax(x[j], at - r), b = fmin(x[j + 1], at + r);
        if (!(b > a)) continue;
        double s = (h[j + 1] - h[j]) / (x[j + 1] - x[j]);
#define G(u) (h[j] + s * ((u) - x[j]) + sqrt(fmax(r * r - ((u) - at) * ((u) - at), 0.0)) - r)
        double g = 0.5 * (sqrt(5.0) - 1.0), c = b - g * (b - a), d = a + g * (b - a);
        for (int it = 0; it < 200; it++) { /* golden section on a concave function */
            if (G(c) > G(d)) b = d;
            else a = c;
            c = b - g * (b - a), d = a + g * (b - a);
        }
        best = fmax(best, fmax(G(a), G(b)));
#undef G
    }
    return best;
}

/* The largest excess of a change of yb' between neighbours of n points spread over (a, b) over what
 * the curvature of p (built for the given radius) allows: on a vertex circle
 * yb'' = -(1 + yb'^2)^(3/2) / radius, on a segment tangent 0, so between two points u < w on no kink
 * |yb'(w) - yb'(u)| <= (w - u) (1 + S^2)^(3/2) / radius with S the largest |yb'|. <= 0 when yb' is
 * continuous over (a, b) (to rounding); > 0 at a slope jump above that allowance. */
static double slope_jump(const vi_profile *p, double radius, double a, double b, int n)
{
    double S = vi_profile_max_slope(p), bound = pow(1.0 + S * S, 1.5) / radius, worst = -INFINITY;
    double prev[4], y[4], du = (b - a) / n;
    vi_profile_eval(p, a + 0.5 * du, prev);
    for (int i = 1; i < n; i++) {
        vi_profile_eval(p, a + (i + 0.5) * du, y);
        worst = fmax(worst, fabs(y[1] - prev[1]) - (du * bound + 1e-12));
        memcpy(prev, y, sizeof y);
    }
    return worst;
}

Test(profile, flat_ground_is_followed_exactly)
{
    double x[] = {0.0, 0.3, 1.0, 2.5}, h[] = {0.0, 0.0, 0.0, 0.0};
    vi_profile *p = make(x, h, 4, R, 0);
    for (int k = 0; k <= 100; k++) {
        double y[4];
        cr_assert(vi_profile_eval(p, 2.5 * k / 100.0, y) == 0);
        cr_assert(y[0] == 0.0 && y[1] == 0.0 && y[2] == 0.0, "x %g: %g %g %g", 2.5 * k / 100.0, y[0], y[1], y[2]);
    }
    cr_assert(vi_profile_kinks(p) == 0);
    vi_profile_free(p);
}

/* A V-shaped trough of slope s0: the body rests on both flanks, yb = s0 |x| + R (sqrt(1 + s0^2) - 1)
 * near the bottom, with one kink (slope jump 2 s0) at x = 0. */
Test(profile, v_trough_touches_both_flanks)
{
    double s0 = 0.05, x[] = {-1.0, 0.0, 1.0}, h[] = {s0, 0.0, s0};
    vi_profile *p = make(x, h, 3, R, 0);
    double lift = R * (sqrt(1.0 + s0 * s0) - 1.0);
    for (int k = -50; k <= 50; k++) {
        double at = 0.01 * k, y[4];
        vi_profile_eval(p, at, y);
        cr_assert(fabs(y[0] - (s0 * fabs(at) + lift)) <= 1e-15, "x %g: %.17g", at, y[0]);
        if (k) cr_assert(y[1] == (k > 0 ? s0 : -s0) && y[2] == 0.0);
    }
    cr_assert(vi_profile_kinks(p) == 1);
    cr_assert(fabs(vi_profile_next_kink(p, -0.3, 1)) <= 1e-15);
    cr_assert(fabs(vi_profile_next_kink(p, 0.3, -1)) <= 1e-15);
    cr_assert(vi_profile_next_kink(p, 0.3, 1) == INFINITY && vi_profile_next_kink(p, -0.3, -1) == -INFINITY);
    vi_profile_free(p);
}

/* A step of height H < R (over 1 nm): approaching from the low side the body climbs the circle
 * around the upper corner, yb = max(0, H - d^2/(R + sqrt(R^2 - d^2))), d = x - corner; one kink
 * where that circle meets the ground, d = -sqrt(R^2 - (R - H)^2). */
Test(profile, step_becomes_the_circular_ramp)
{
    double H = 0.01, c = 1e-9, x[] = {-1.0, 0.0, c, 1.0}, h[] = {0.0, 0.0, H, H};
    vi_profile *p = make(x, h, 4, R, 0);
    double foot = c - sqrt(R * R - (R - H) * (R - H));
    for (int k = 0; k <= 400; k++) {
        double at = -0.2 + 0.3 * k / 400.0, d = at - c;
        double expect = at >= c ? H : fmax(0.0, H - d * d / (R + sqrt(R * R - d * d)));
        cr_assert(fabs(yb(p, at) - expect) <= 1e-14, "x %g: %.17g vs %.17g", at, yb(p, at), expect);
    }
    cr_assert(vi_profile_kinks(p) == 1, "%zu kinks", vi_profile_kinks(p));
    cr_assert(fabs(vi_profile_next_kink(p, -0.5, 1) - foot) <= 1e-12, "%.17g vs %.17g", vi_profile_next_kink(p, -0.5, 1),
              foot);
    /* on the ramp yb = H + sqrt(R^2 - d^2) - R: yb' = -d/sqrt(R^2 - d^2), yb'' = -R^2/(R^2 - d^2)^1.5,
     * yb''' = -3 R^2 d/(R^2 - d^2)^2.5 */
    double y[4], d = -0.05;
    vi_profile_eval(p, c + d, y);
    cr_assert(fabs(y[1] + d / sqrt(R * R - d * d)) <= 1e-12 && fabs(y[2] + R * R / pow(R * R - d * d, 1.5)) <= 1e-9);
    double d3 = -3.0 * R * R * d / pow(R * R - d * d, 2.5);
    cr_assert(fabs(y[3] - d3) <= 1e-9 * fabs(d3), "yb''' = %.17g, expected %.17g", y[3], d3);
    vi_profile_free(p);
}

/* A narrow bump (width 2 um, height 0.2 mm): the body is lifted over it on the circle around its apex. */
Test(profile, narrow_bump_is_swept_as_a_circle)
{
    double H = 2e-4, w = 1e-6, x[] = {-1.0, -w, 0.0, w, 1.0}, h[] = {0.0, 0.0, H, 0.0, 0.0};
    vi_profile *p = make(x, h, 5, R, 0);
    double half = sqrt(R * R - (R - H) * (R - H)); /* where the apex circle meets the ground */
    for (int k = 0; k <= 200; k++) {
        double at = -0.02 + 0.04 * k / 200.0, circle = H - at * at / (R + sqrt(R * R - at * at));
        if (fabs(fabs(at) - half) < 2.0 * w) continue; /* the feet, where the flanks and ground meet */
        cr_assert(fabs(yb(p, at) - fmax(circle, 0.0)) <= 1e-15, "x %g: %.17g vs %.17g", at, yb(p, at), circle);
    }
    cr_assert(vi_profile_kinks(p) == 2);
    vi_profile_free(p);
}

/* A deep trough between two peaks of different heights, narrower than the body: the body rests on
 * both peaks, yb = max of the two vertex circles h_i - d^2/(R + sqrt(R^2 - d^2)) (the flanks fall
 * away too steeply to touch), with one kink where the circles cross. */
Test(profile, a_trough_bridged_between_two_peaks)
{
    const double dh[] = {-0.08, -0.05, -0.01, 0.0, 0.02, 0.06}, gap[] = {0.3, 0.5, 0.7};
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 3; j++) {
            double L = gap[j], x[] = {0.0, 0.5 * L, L}, h[] = {0.1, -0.5, 0.1 + dh[i]};
            vi_profile *p = make(x, h, 3, R, 0);
            cr_assert(vi_profile_kinks(p) == 1, "dh %g gap %g: %zu kinks", dh[i], L, vi_profile_kinks(p));
            for (int k = 0; k <= 200; k++) {
                double at = L * k / 200.0, best = -INFINITY;
                for (int v = 0; v < 3; v += 2) {
                    double d = at - x[v];
                    if (fabs(d) <= R) best = fmax(best, h[v] - d * d / (R + sqrt(R * R - d * d)));
                }
                cr_assert(fabs(yb(p, at) - best) <= 1e-15, "dh %g gap %g x %g: %.17g vs %.17g", dh[i], L, at, yb(p, at), best);
            }
            vi_profile_free(p);
        }
}

/* ---- the cubic spline (VI_PROFILE_CUBIC) ---------------------------------------------------- */

static vi_profile *make_cubic(const double *x, const double *h, size_t n, double r, int periodic)
{
    char msg[512];
    vi_profile *p = vi_profile_create_as(x, h, n, r, periodic, VI_PROFILE_CUBIC, "test", msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    return p;
}

/* The offset of a curve at its point s of height hs, slope h1, second and third derivatives h2, h3
 * (vi_profile.h): the centre's x, yb and its first three derivatives in x, into o[5]. */
static void offset_at(double s, double hs, double h1, double h2, double h3, double r, double o[5])
{
    double w = 1.0 + h1 * h1, X1 = 1.0 - r * h2 / pow(w, 1.5), X2 = -r * (h3 / pow(w, 1.5) - 3.0 * h1 * h2 * h2 / pow(w, 2.5));
    o[0] = s - r * h1 / sqrt(w);
    o[1] = hs - r * h1 * h1 / (sqrt(w) * (sqrt(w) + 1.0)); /* hs + r / sqrt(w) - r without the cancellation */
    o[2] = h1;
    o[3] = h2 / X1;
    o[4] = (h3 * X1 - h2 * X2) / (X1 * X1 * X1);
}

/* The not-a-knot spline through rows of a cubic is that cubic: yb is its offset, checked at the
 * contact points s (unevenly spaced rows, the curvature below 1/R). */
Test(profile, a_cubic_spline_through_a_cubic_is_that_cubic)
{
    enum { N = 9 };
    double x[N] = {-0.2, -0.17, -0.1, -0.02, 0.0, 0.05, 0.11, 0.12, 0.2}, h[N];
    const double a = 1e-3, b = 0.01, c = 0.2, d = -1.0; /* h = a + b x + c x^2 + d x^3, |h''| <= 1.6 < 1/R */
    for (int i = 0; i < N; i++) h[i] = a + x[i] * (b + x[i] * (c + x[i] * d));
    vi_profile *p = make_cubic(x, h, N, R, 0);
    for (int i = 0; i <= 100; i++) {
        double s = -0.15 + 0.3 * i / 100, o[5], y[4];
        offset_at(s, a + s * (b + s * (c + s * d)), b + s * (2.0 * c + 3.0 * d * s), 2.0 * c + 6.0 * d * s, 6.0 * d, R, o);
        cr_assert(vi_profile_eval(p, o[0], y) == 0);
        cr_assert(fabs(y[0] - o[1]) < 1e-15, "s = %g: yb %.17g, offset %.17g", s, y[0], o[1]);
        cr_assert(fabs(y[1] - o[2]) < 1e-12 && fabs(y[2] - o[3]) < 1e-9 * fabs(o[3]) + 1e-9, "s = %g: yb' %.17g %.17g, "
                  "yb'' %.17g %.17g", s, y[1], o[2], y[2], o[3]);
        cr_assert(fabs(y[3] - o[4]) < 1e-7 * fabs(o[4]) + 1e-7, "s = %g: yb''' %.17g, offset %.17g", s, y[3], o[4]);
    }
    cr_assert_eq(vi_profile_kinks(p), 0);
    vi_profile_free(p);
    /* two rows: the line; three: the parabola */
    double x2[] = {0.0, 1.0}, h2[] = {0.0, 0.01}, x3[] = {0.0, 0.3, 1.0}, h3[3], y[4], o[5];
    for (int i = 0; i < 3; i++) h3[i] = 0.2 * x3[i] * x3[i];
    p = make_cubic(x2, h2, 2, R, 0);
    offset_at(0.5, 0.005, 0.01, 0.0, 0.0, R, o);
    vi_profile_eval(p, o[0], y);
    cr_assert(fabs(y[0] - o[1]) < 1e-15 && fabs(y[1] - 0.01) < 1e-15 && fabs(y[2]) < 1e-15);
    vi_profile_free(p);
    p = make_cubic(x3, h3, 3, R, 0);
    offset_at(0.5, 0.05, 0.2, 0.4, 0.0, R, o);
    vi_profile_eval(p, o[0], y);
    cr_assert(fabs(y[0] - o[1]) < 1e-15 && fabs(y[1] - 0.2) < 1e-14 && fabs(y[2] - o[3]) < 1e-12, "%g %g %g", y[0], y[1], y[2]);
    vi_profile_free(p);
}

/* A gentle sinusoid h = A cos(2 pi x / L) (A (2 pi / L)^2 < 1/R) sampled n times a period: the
 * periodic spline is within 5/384 dx^4 max|h''''| of it, so yb is within that (and its slope within
 * dx^3 A k^4 / 24) of the offset of the sinusoid; no kink. Also open: away from the ends. */
static void gentle_sinusoid(int rows, int periodic)
{
    const double L = 0.05, A = 2e-5, k = 2.0 * 3.14159265358979323846 / L;
    double *x = malloc(rows * sizeof *x), *h = malloc(rows * sizeof *h), dx = 4.0 * L / (rows - 1);
    for (int i = 0; i < rows; i++) x[i] = dx * i, h[i] = A * cos(k * x[i]);
    h[rows - 1] = h[0];
    vi_profile *p = make_cubic(x, h, rows, R, periodic);
    double bound = 5.0 / 384.0 * pow(dx, 4) * A * pow(k, 4) + 1e-18, slope_bound = pow(dx, 3) * A * pow(k, 4) / 24.0 + 1e-15;
    for (int i = 0; i <= 400; i++) {
        double s = (periodic ? 0.0 : 0.5 * L) + 3.0 * L * i / 400, o[5], y[4], ks = k * s;
        offset_at(s, A * cos(ks), -A * k * sin(ks), -A * k * k * cos(ks), A * k * k * k * sin(ks), R, o);
        vi_profile_eval(p, o[0], y);
        cr_assert(fabs(y[0] - o[1]) <= bound, "rows %d, s = %g: yb %.17g, offset %.17g (bound %g)", rows, s, y[0], o[1], bound);
        cr_assert(fabs(y[1] - o[2]) <= slope_bound, "rows %d, s = %g: yb' %.17g, offset %.17g", rows, s, y[1], o[2]);
    }
    cr_assert_eq(vi_profile_kinks(p), 0, "rows %d", rows);
    vi_profile_free(p);
    free(x), free(h);
}

/* 20001 rows: more than 16,384 segments, all touched everywhere, whose arcs the profile does not
 * store (their cubics computed from the rows and slopes when evaluated). */
Test(profile, a_spline_through_a_gentle_sinusoid_gives_its_offset)
{
    for (int periodic = 0; periodic <= 1; periodic++) {
        gentle_sinusoid(81, periodic);
        gentle_sinusoid(801, periodic);
        gentle_sinusoid(8001, periodic);
        gentle_sinusoid(20001, periodic);
    }
}

/* Across the seam of a periodic table yb, yb' and yb'' are continuous: their changes over 2 d
 * around the first row shrink with d as yb'' and yb''' allow (uneven rows, a rough shape). */
Test(profile, a_periodic_spline_is_c2_across_its_seam)
{
    enum { N = 12 };
    double x[N] = {0.1, 0.13, 0.2, 0.26, 0.3, 0.38, 0.41, 0.5, 0.55, 0.6, 0.7, 0.74}, h[N];
    for (int i = 0; i < N; i++) h[i] = 1e-3 * sin(7.0 * i) * (i % 3 == 0 ? 1.0 : 0.3);
    h[N - 1] = h[0];
    vi_profile *p = make_cubic(x, h, N, R, 1);
    double mid[4];
    vi_profile_eval(p, 0.1, mid);
    for (double dd = 1e-3; dd > 1e-7; dd /= 10.0) {
        double a[4], b[4];
        vi_profile_eval(p, 0.1 - dd, a); /* wraps to the end of the table */
        vi_profile_eval(p, 0.1 + dd, b);
        double big = 1.0 + fabs(mid[3]);
        cr_assert(fabs(b[0] - a[0] - 2.0 * dd * mid[1]) <= dd * dd * big * 10.0, "d = %g: yb %g %g", dd, a[0], b[0]);
        cr_assert(fabs(b[1] - a[1]) <= 2.0 * dd * (fabs(mid[2]) + dd * big) * 1.5, "d = %g: yb' %g %g", dd, a[1], b[1]);
        cr_assert(fabs(b[2] - a[2]) <= 2.0 * dd * big * 10.0, "d = %g: yb'' %g %g", dd, a[2], b[2]);
    }
    /* the same at the seam of a copy far along the track */
    double far = 0.1 + 1000.0 * 0.64, a[4], b[4];
    vi_profile_eval(p, far - 1e-6, a);
    vi_profile_eval(p, far + 1e-6, b);
    cr_assert(fabs(b[1] - a[1]) < 1e-5 && fabs(b[2] - a[2]) < 1e-3, "%g %g, %g %g", a[1], b[1], a[2], b[2]);
    cr_assert_eq(vi_profile_kinks(p), 0);
    vi_profile_free(p);
}

/* A parabola h = c x^2 sharper than the body (2 c > 1/R) is bridged: the body centred above its
 * axis touches it at +-s*, s*^2 = R^2 - 1/(4 c^2), at the height c s*^2 + 1/(2 c) - R, one kink
 * there with slopes -+2 c s*; beyond the bridge yb is the offset of the parabola (the not-a-knot
 * spline through its rows is the parabola). */
Test(profile, a_trough_sharper_than_the_body_is_bridged_with_one_kink)
{
    enum { N = 41 };
    const double r = 0.05, c = 20.0;
    double x[N], h[N];
    for (int i = 0; i < N; i++) x[i] = -0.1 + 0.2 * i / (N - 1) + (i % 2 ? 1e-3 : 0.0), h[i] = c * x[i] * x[i];
    vi_profile *p = make_cubic(x, h, N, r, 0);
    double s2 = r * r - 1.0 / (4.0 * c * c), y[4];
    cr_assert_eq(vi_profile_kinks(p), 1);
    double kink = vi_profile_next_kink(p, -0.05, 1);
    cr_assert(fabs(kink) < 1e-12, "kink at %g", kink);
    vi_profile_eval(p, 0.0, y);
    cr_assert(fabs(y[0] - (c * s2 + 1.0 / (2.0 * c) - r)) < 1e-14, "yb(0) %.17g", y[0]);
    cr_assert(fabs(y[1] - 2.0 * c * sqrt(s2)) < 1e-9, "right-hand slope %.17g, expected %.17g", y[1], 2.0 * c * sqrt(s2));
    for (int i = 1; i <= 20; i++) { /* contact points beyond the bridge */
        double s = sqrt(s2) + 0.05 * i / 20, o[5];
        for (int side = -1; side <= 1; side += 2) {
            offset_at(side * s, c * s * s, side * 2.0 * c * s, 2.0 * c, 0.0, r, o);
            if (fabs(o[0]) > 0.1) continue;
            vi_profile_eval(p, o[0], y);
            cr_assert(fabs(y[0] - o[1]) < 1e-14 && fabs(y[1] - o[2]) < 1e-9, "s = %g: yb %.17g, offset %.17g", side * s,
                      y[0], o[1]);
        }
    }
    vi_profile_free(p);
}

/* An interpolation that is neither linear nor cubic is refused, naming both. */
Test(profile, an_unknown_interpolation_is_refused)
{
    double x[] = {0.0, 1.0}, h[] = {0.0, 0.0};
    char msg[256] = "";
    cr_assert(vi_profile_create_as(x, h, 2, R, 0, 3, "table", msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "table: interpolation 3 is neither linear (1) nor cubic (2)"), "%s", msg);
}

/* Random rough profiles (steep and gentle, dense and sparse against R) against the brute force. */
Test(profile, random_profiles_match_the_definition, .timeout = 60)
{
    srand(4242);
    const struct { size_t n; double dx, amp, r; } cases[] = {
        {400, 1e-3, 1e-4, R}, {400, 1e-3, 5e-3, R}, {200, 0.05, 0.02, R}, {300, 1e-2, 1e-3, 0.01}, {50, 0.5, 0.1, R}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        size_t n = cases[c].n;
        double *x = malloc(n * sizeof *x), *h = malloc(n * sizeof *h);
        x[0] = 0.0, h[0] = 0.0;
        for (size_t i = 1; i < n; i++) {
            x[i] = x[i - 1] + cases[c].dx * (0.2 + 1.6 * rand() / RAND_MAX);
            h[i] = cases[c].amp * (2.0 * rand() / RAND_MAX - 1.0);
        }
        vi_profile *p = make(x, h, n, cases[c].r, 0);
        double worst = 0.0;
        for (int k = 0; k <= 1000; k++) {
            double at = x[0] + (x[n - 1] - x[0]) * k / 1000.0;
            worst = fmax(worst, fabs(yb(p, at) - brute(x, h, n, cases[c].r, at)));
        }
        cr_assert(worst <= 1e-12 * (cases[c].amp + cases[c].r), "case %zu: max |yb - brute| = %g", c, worst);
        /* continuity, and the derivative against a central difference away from kinks */
        for (int k = 1; k < 300; k++) {
            double at = x[0] + (x[n - 1] - x[0]) * k / 300.0, e = 1e-7, y[4];
            double kl = vi_profile_next_kink(p, at, -1), kr = vi_profile_next_kink(p, at, 1);
            if (at - kl < 2 * e || kr - at < 2 * e) continue;
            vi_profile_eval(p, at, y);
            double fd = (yb(p, at + e) - yb(p, at - e)) / (2 * e);
            cr_assert(fabs(fd - y[1]) <= 1e-5 * (1.0 + fabs(y[1])) + 1e-7 * fabs(y[2]) * 10, "case %zu x %g: %g vs %g",
                      c, at, y[1], fd);
        }
        vi_profile_free(p);
        free(x), free(h);
    }
}

/* The slopes of yb at x over the points where the body touches the profile (within tol of the best
 * h(s) + sqrt(r^2 - (x - s)^2)): at a contact s the slope is -(x - s)/sqrt(r^2 - (x - s)^2). The
 * candidates are the vertices and, on each segment, the point whose normal passes through the
 * body's centre, s = x + r slope/sqrt(1 + slope^2), clamped to the segment. Their least and greatest. */
static void contact_slopes(const double *x, const double *h, size_t n, double r, double at, double tol, double *lo,
                           double *hi)
{
    double best = -INFINITY;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < 2 * n - 1; i++) {
            double s;
            if (i < n) s = x[i];
            else {
                size_t j = i - n;
                double m = (h[j + 1] - h[j]) / (x[j + 1] - x[j]);
                s = fmin(fmax(at + r * m / sqrt(1.0 + m * m), x[j]), x[j + 1]);
            }
            if (!(fabs(s - at) < r)) continue;
            size_t j = i < n ? (i ? i - 1 : 0) : i - n; /* h(s) on segment j */
            double hs = i < n ? h[i] : h[j] + (h[j + 1] - h[j]) * ((s - x[j]) / (x[j + 1] - x[j]));
            double root = sqrt(r * r - (at - s) * (at - s)), v = hs + root, d = -(at - s) / root;
            if (pass == 0) best = fmax(best, v);
            else if (v >= best - tol) *lo = fmin(*lo, d), *hi = fmax(*hi, d);
        }
        if (pass == 0) *lo = INFINITY, *hi = -INFINITY;
    }
}

/* A kink is where the body touches the profile at two places (it bridges a trough): yb's slope jumps
 * there by the difference of the slopes at the two contacts. Where the contact passes from a vertex
 * onto the next segment (a circle meeting a tangent) the slope is continuous: no kink. Every kink
 * reported is checked against the slopes at the contacts; sparse, rough profiles. */
/* A slope jump of exactly VI_PROFILE_KINK_SLOPE is no kink, and twice that is one: a trough whose
 * flanks have the slopes 0 and 1e-9 (the rolling body touches both, its path turns by the flanks'
 * slopes) and one with 0 and 2e-9. */
Test(profile, a_slope_jump_at_the_kink_threshold_is_no_kink)
{
    double x[] = {0.0, 1.0, 2.0}, h[] = {0.0, 0.0, VI_PROFILE_KINK_SLOPE}, y[4];
    vi_profile *p = make(x, h, 3, R, 0);
    vi_profile_eval(p, 1.9, y);
    cr_assert(y[1] == VI_PROFILE_KINK_SLOPE, "yb' on the second flank %.17g", y[1]); /* the jump is the threshold */
    cr_assert(vi_profile_kinks(p) == 0, "%zu kinks", vi_profile_kinks(p));
    vi_profile_free(p);
    h[2] = 2.0 * VI_PROFILE_KINK_SLOPE;
    p = make(x, h, 3, R, 0);
    cr_assert(vi_profile_kinks(p) == 1, "%zu kinks", vi_profile_kinks(p));
    vi_profile_free(p);
}

Test(profile, kinks_are_two_point_contacts, .timeout = 60)
{
    srand(99);
    const struct { size_t n; double dx, amp; int wave; } cases[] = {
        {200, 0.1, 4e-3, 0}, {300, 0.3, 1e-3, 0}, {300, 0.04, 0.13, 1}, {300, 0.5, 0.2, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        size_t n = cases[c].n, count = 0;
        double *x = malloc(n * sizeof *x), *h = malloc(n * sizeof *h);
        x[0] = 0.0, h[0] = 0.0;
        for (size_t i = 1; i < n; i++) {
            x[i] = x[i - 1] + cases[c].dx * (0.2 + 1.6 * rand() / RAND_MAX);
            h[i] = cases[c].amp * (cases[c].wave ? sin(50.0 * x[i]) : 2.0 * rand() / RAND_MAX - 1.0);
        }
        vi_profile *p = make(x, h, n, R, 0);
        double bad_at = NAN, bad_jump = 0.0, bad_contacts = 0.0; /* the first kink that is none */
        for (double at = vi_profile_next_kink(p, x[0], 1); at < x[n - 1]; at = vi_profile_next_kink(p, at, 1)) {
            double lo, hi, yl[4], yr[4];
            vi_profile_eval(p, nextafter(at, -INFINITY), yl);
            vi_profile_eval(p, at, yr);
            double jump = fabs(yr[1] - yl[1]); /* the kink's place is known to some ulps: values to jump times that */
            contact_slopes(x, h, n, R, at, 1e-14 * (R + cases[c].amp) + 64.0 * DBL_EPSILON * at * jump, &lo, &hi);
            if (!(fabs(jump - (hi - lo)) <= 3e-7 + 1e-6 * jump) && isnan(bad_at))
                bad_at = at, bad_jump = jump, bad_contacts = hi - lo;
            count++;
        }
        cr_assert(isnan(bad_at), "case %zu: kink at x = %.17g: yb' jumps by %.3g, the slopes at the contacts differ by %.3g",
                  c, bad_at, bad_jump, bad_contacts);
        cr_assert(count == vi_profile_kinks(p) && count > 0, "case %zu: %zu kinks walked, %zu counted", c, count,
                  vi_profile_kinks(p));
        vi_profile_free(p);
        free(x), free(h);
    }
}

/* A small random table for the tests below: n rows, spacing from 1 % to 3 R, heights spanning at most
 * 0.4 r (no step the body cannot roll over); on a grid (x multiples of r/8, h of r/64: exact ties
 * between pieces, equal flanks, flat runs) when grid is set; h[n-1] = h[0] when periodic. */
static void small_table(double *x, double *h, size_t n, double r, int grid, int periodic)
{
    double dx = r * (0.01 + 3.0 * rand() / RAND_MAX), amp = 0.2 * r * rand() / RAND_MAX;
    x[0] = grid ? 0.125 * r * (rand() % 9 - 4) : r * (2.0 * rand() / RAND_MAX - 1.0);
    for (size_t i = 0; i < n; i++) {
        if (i) x[i] = grid ? x[i - 1] + 0.125 * r * (1 + rand() % 12) : x[i - 1] + dx * (0.05 + 1.9 * rand() / RAND_MAX);
        h[i] = grid ? r / 64.0 * (rand() % 13 - 6) : amp * (2.0 * rand() / RAND_MAX - 1.0);
        if (i && rand() % 5 == 0) h[i] = h[i - 1]; /* a flat segment */
    }
    if (periodic) h[n - 1] = h[0];
}

enum { SMALL_NMAX = 8, SMALL_COPIES = 40 };

/* The table the definition is evaluated on into xu, hu (*nu rows): a periodic one unrolled over the
 * body's reach r, an open one as it is. */
static void unrolled(const double *x, const double *h, size_t n, double r, int periodic, double *xu, double *hu,
                     size_t *nu, int t)
{
    double L = x[n - 1] - x[0];
    if (!periodic) {
        memcpy(xu, x, n * sizeof *x), memcpy(hu, h, n * sizeof *h);
        *nu = n;
        return;
    }
    int reach = (int)ceil(r / L) + 1;
    cr_assert(2 * reach + 1 <= SMALL_COPIES, "table %d: period %g", t, L);
    *nu = 0;
    for (int k = -reach; k <= reach; k++)
        for (size_t i = (k == -reach ? 0 : 1); i < n; i++) xu[*nu] = x[i] + k * L, hu[*nu] = h[i], (*nu)++;
}

/* yb at SMALL_POINTS + 1 points across the table and at and beside every row against the definition,
 * yb' within the contacts' slopes, yb'' and yb''' against a vertex circle's (or 0 on a tangent); the
 * points checked are counted in *checked. Returns the largest |yb'| sampled. */
enum { SMALL_POINTS = 64 };
static double check_samples(const vi_profile *p, const double *x, size_t n, double r, int periodic, const double *xu,
                            const double *hu, size_t nu, int t, int *checked)
{
    double L = x[n - 1] - x[0], tol = 1e-12 * r, smax = 0.0;
    int pts = SMALL_POINTS;
    for (int k = 0; k <= pts + 3 * (int)n; k++) {
        double at;
        if (k <= pts) at = x[0] + L * k / pts;
        else {
            size_t i = (size_t)(k - pts - 1) / 3;
            int side = (k - pts - 1) % 3;
            at = x[i] + (side == 0 ? 0.0 : side == 1 ? -1e-3 * r : 1e-3 * r);
            if (!periodic && (at < x[0] || at > x[n - 1])) continue;
        }
        double y[4], ref = brute(xu, hu, nu, r, at), lo, hi;
        vi_profile_eval(p, at, y);
        cr_assert(fabs(y[0] - ref) <= tol, "table %d (n %zu, r %g, %s) x %.17g: yb %.17g, by the definition %.17g", t,
                  n, r, periodic ? "periodic" : "open", at, y[0], ref);
        contact_slopes(xu, hu, nu, r, at, 1e-13 * r, &lo, &hi);
        cr_assert(y[1] >= lo - 1e-9 && y[1] <= hi + 1e-9, "table %d x %.17g: yb' %.17g, contact slopes %.17g..%.17g", t,
                  at, y[1], lo, hi);
        /* on a vertex circle yb'' = -(1 + yb'^2)^(3/2)/r and yb''' = -3 yb' yb'' sqrt(1 + yb'^2)/r; on a tangent both 0 */
        double c2 = -pow(1.0 + y[1] * y[1], 1.5) / r, c3 = -3.0 * y[1] * c2 * sqrt(1.0 + y[1] * y[1]) / r;
        cr_assert((y[2] == 0.0 && y[3] == 0.0) ||
                      (fabs(y[2] - c2) <= 1e-9 * fabs(c2) && fabs(y[3] - c3) <= 1e-9 * fabs(c2) * (1.0 + fabs(y[1])) / r),
                  "table %d x %.17g: yb' %.17g, yb'' %.17g, yb''' %.17g", t, at, y[1], y[2], y[3]);
        smax = fmax(smax, fabs(y[1]));
        (*checked)++;
    }
    return smax;
}

/* Kinks (one period of a periodic table, from just before its first row): the slope jumps by more
 * than VI_PROFILE_KINK_SLOPE at each, not between two; each finds the one before it; a periodic
 * table's kinks repeat one period before and after. */
static void check_kinks(const vi_profile *p, const double *x, size_t n, double r, int periodic, int t)
{
    double L = x[n - 1] - x[0];
    double a = periodic ? x[0] - 1e-9 * L : x[0], prev = NAN, yl[4], yr[4], first = NAN, first_before = NAN;
    size_t walked = 0;
    for (double at = vi_profile_next_kink(p, a, 1); at < x[n - 1]; at = vi_profile_next_kink(p, at, 1)) {
        double e = 1e-12 * (1.0 + fabs(at)); /* a periodic table's positions are reduced to some ulps */
        vi_profile_eval(p, at - e, yl);
        vi_profile_eval(p, at + e, yr);
        cr_assert(fabs(yr[1] - yl[1]) > 0.5 * VI_PROFILE_KINK_SLOPE, "table %d: no slope jump at the kink %.17g (%g)", t, at,
                  yr[1] - yl[1]);
        cr_assert(slope_jump(p, r, a + 1e-12, at - 1e-12, 200) <= 0.0, "table %d: a slope jump in %.17g..%.17g", t, a, at);
        double before = vi_profile_next_kink(p, at, -1);
        if (walked) cr_assert(before == prev, "table %d: the kink before %.17g is %.17g, not %.17g", t, at, before, prev);
        else if (!periodic) cr_assert(before == -INFINITY, "table %d: a kink %.17g before the first", t, before);
        else first = at, first_before = before;
        prev = at, a = at, walked++;
        cr_assert(walked <= 2 * SMALL_NMAX);
    }
    if (!walked) cr_assert(vi_profile_next_kink(p, a, -1) == -INFINITY && vi_profile_next_kink(p, a, 1) == INFINITY);
    cr_assert(slope_jump(p, r, a + 1e-12, x[n - 1] - 1e-12, 200) <= 0.0, "table %d: a slope jump after %.17g", t, a);
    cr_assert(walked == vi_profile_kinks(p), "table %d: %zu kinks walked, %zu counted", t, walked, vi_profile_kinks(p));
    if (periodic && walked) { /* the kinks of the periods before and after */
        double after = vi_profile_next_kink(p, prev, 1);
        cr_assert(fabs(first_before - (prev - L)) <= 1e-12 * (1.0 + fabs(prev)) && fabs(after - (first + L)) <= 1e-12 * (1.0 + fabs(first)),
                  "table %d: kinks %.17g .. %.17g, before the first %.17g, after the last %.17g", t, first, prev,
                  first_before, after);
    }
}

/* Many small tables (2 to 8 rows, open and periodic, on a grid and not) against the definition: yb
 * at the rows, just beside them and between them; yb' against the slopes where the body touches
 * (within the two contacts' slopes at a kink) and against a central difference of yb, yb'' and yb'''
 * against central differences of yb' and yb''; every kink reported a slope jump, and no slope jump
 * between kinks; the largest |yb'| and the height span. */
Test(profile, small_random_tables_match_the_definition, .timeout = 60)
{
    srand(31337);
    static double xu[SMALL_COPIES * SMALL_NMAX], hu[SMALL_COPIES * SMALL_NMAX];
    int checked = 0;
    for (int t = 0; t < 1200; t++) {
        size_t n = 2 + (size_t)(rand() % (SMALL_NMAX - 1));
        int grid = t % 2, periodic = t % 3 == 2;
        if (periodic && n < 3) n = 3;
        double r = grid ? 1.0 : 0.05 + rand() % 100 / 100.0, x[SMALL_NMAX], h[SMALL_NMAX];
        small_table(x, h, n, r, grid, periodic);
        char msg[512];
        vi_profile *p = vi_profile_create(x, h, n, r, periodic, "small", msg, sizeof msg);
        cr_assert(p != NULL, "table %d: %s", t, msg);
        double L = x[n - 1] - x[0];
        if (periodic && L < 0.25 * r) { /* copies enough; the short periods have their own test */
            vi_profile_free(p);
            continue;
        }
        size_t nu;
        unrolled(x, h, n, r, periodic, xu, hu, &nu, t);
        double hlo = h[0], hhi = h[0];
        for (size_t i = 0; i < n; i++) hlo = fmin(hlo, h[i]), hhi = fmax(hhi, h[i]);
        cr_assert(vi_profile_height_span(p) == hhi - hlo, "table %d: span %.17g", t, vi_profile_height_span(p));
        cr_assert(vi_profile_periodic(p) == periodic && vi_profile_x_first(p) == x[0] && vi_profile_x_last(p) == x[n - 1]);
        double smax = check_samples(p, x, n, r, periodic, xu, hu, nu, t, &checked);
        /* the largest |yb'| is taken at a boundary of the pieces: at least the sampled one, and the
         * samples 1/SMALL_POINTS of the table apart come within the curvature allowance of it */
        double S = vi_profile_max_slope(p);
        cr_assert(S >= smax - 1e-12 && S <= smax + L / SMALL_POINTS * pow(1.0 + S * S, 1.5) / r + 1e-12,
                  "table %d: max slope %.17g, sampled %.17g", t, S, smax);
        check_kinks(p, x, n, r, periodic, t);
        vi_profile_free(p);
    }
    cr_assert(checked > 50000);
}

/* A periodic table starting at x0: its period is x_last - x_first = L wherever it starts. */
static void periodic_profile_repeats_from(double x0)
{
    enum { N = 65 };
    double x[N], h[N], L = 0.2;
    for (int i = 0; i < N; i++) {
        x[i] = x0 + L * i / (N - 1);
        h[i] = 5e-3 * cos(2.0 * 3.14159265358979323846 * (x[i] - x0) / L); /* curvature 5e-3 (2 pi/L)^2 = 4.9/m > 1/R: bridged troughs */
    }
    h[N - 1] = h[0];
    vi_profile *p = make(x, h, N, R, 1);
    /* three periods of the table, evaluated by the definition, against the periodic profile */
    double x3[3 * N - 2], h3[3 * N - 2];
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < N; i++)
            if (k == 0 || i > 0) x3[k * (N - 1) + i] = x[i] + k * L, h3[k * (N - 1) + i] = h[i];
    for (int k = 0; k <= 400; k++) {
        double at = x0 + L * k / 400.0;
        double expect = brute(x3, h3, 3 * N - 2, R, at + L);
        for (int shift = -3; shift <= 3; shift++)
            cr_assert(fabs(yb(p, at + shift * L) - expect) <= 1e-12, "x %g shift %d: %.17g vs %.17g", at, shift,
                      yb(p, at + shift * L), expect);
    }
    /* the kinks (the concave vertices the body rests in, and the bridge over the trough at L/2)
     * repeat with the period, found both ways from any position */
    size_t nk = vi_profile_kinks(p);
    cr_assert(nk >= 1 && nk < N);
    double at = x0 + 0.5 * L - 1e-9, k0 = vi_profile_next_kink(p, at, 1);
    cr_assert(fabs(k0 - (x0 + 0.5 * L)) < 1e-12, "%g", k0);
    for (int k = 0; k <= 100; k++) {
        at = x0 - 2.0 * L + 4.0 * L * k / 100.0;
        double up = vi_profile_next_kink(p, at, 1), down = vi_profile_next_kink(p, at, -1);
        cr_assert(up > at && down < at && up - down <= L + 1e-12);
        cr_assert(fabs(vi_profile_next_kink(p, at + L, 1) - (up + L)) < 1e-12);
        cr_assert(vi_profile_next_kink(p, up, -1) <= at + 1e-15 && vi_profile_next_kink(p, down, 1) >= at - 1e-15);
        /* no kink between at and up: yb' is continuous there (Lipschitz with the curvature bound), and
         * the same check over an interval that holds the kink at up sees the slope jump */
        cr_assert(slope_jump(p, R, at, up, 400) <= 0.0, "x %g..%g: a slope jump of %g", at, up, slope_jump(p, R, at, up, 400));
        cr_assert(slope_jump(p, R, at, up + 0.01 * (up - at), 400) > 0.0, "x %g: the kink at %g is not seen", at, up);
    }
    cr_assert(yb(p, x0 + 0.5 * L) - h[(N - 1) / 2] > 1e-4, "the trough is bridged: %g", yb(p, x0 + 0.5 * L) - h[(N - 1) / 2]);
    cr_assert(yb(p, x0) == h[0], "the crest is followed");
    vi_profile_free(p);
}

Test(profile, periodic_profile_repeats) { periodic_profile_repeats_from(0.0); }

/* a table that starts at x0 = 0.37 m (1.85 periods: no whole number of them) */
Test(profile, periodic_profile_repeats_from_its_first_row) { periodic_profile_repeats_from(0.37); }

/* A periodic V trough whose bottom is the seam (first and last row, flank slopes +-s): the body
 * bridges it, yb = h_0 + s |x - seam| + r (sqrt(1 + s^2) - 1) near it, with the kink at the first row.
 * There, and one period on, yb' is the right-hand slope +s. Two tables: from -0.5 to 0.09, where
 * x_first + (x_last - x_first) rounds below x_last (a position that wraps to exactly one period must
 * still be taken as the first row); and a trapezoid and a triangle on a grid, where the flanks'
 * tangents cross exactly at the seam (at 0 and at -0.5: the crossing is found by bisection there,
 * the closed form puts it a rounding outside the bracket). */
Test(profile, periodic_seam_is_the_first_row)
{
    struct { double x[4], h[4], r; size_t n; } tables[] = {
        {{-0.5, -0.3, -0.11, 0.09}, {0.0, 0.01, 0.01, 0.0}, R, 4},
        {{0.0, 1.0, 1.875, 2.875}, {0.0625, 0.09375, 0.09375, 0.0625}, 1.0, 4},
        {{-0.5, 0.5, 1.5}, {-0.375, -0.078125, -0.375}, 1.0, 3}};
    for (int k = 0; k < 3; k++) {
        const double *x = tables[k].x, *h = tables[k].h, r = tables[k].r;
        size_t n = tables[k].n;
        double lo = x[0], L = x[n - 1] - x[0], s = (h[1] - h[0]) / (x[1] - x[0]), lift = r * (sqrt(1.0 + s * s) - 1.0), y[4];
        if (k == 0) cr_assert(lo + L < x[n - 1]);
        vi_profile *p = make(x, h, n, r, 1);
        double kink = vi_profile_next_kink(p, lo - 1e-9, 1); /* at the first row (the others: to the last bit) */
        cr_assert(vi_profile_kinks(p) == 1 && (k == 0 ? kink == lo : fabs(kink - lo) <= 2.0 * DBL_EPSILON * fabs(lo) + DBL_MIN),
                  "table %d: %.17g", k, kink);
        const double at[] = {lo, x[n - 1], lo + L, lo - L, lo + 3.0 * L};
        for (size_t i = 0; i < sizeof at / sizeof at[0]; i++) {
            cr_assert(vi_profile_eval(p, at[i], y) == 0);
            /* the second table's kink lies a denormal after the first row: the slope there is either flank's */
            cr_assert(fabs(y[0] - (h[0] + lift)) <= 1e-15 && fabs((k == 0 ? y[1] : fabs(y[1])) - s) <= 1e-15,
                      "table %d x %.17g: yb %.17g, yb' %.17g", k, at[i], y[0], y[1]);
        }
        for (int i = -100; i <= 100; i++) { /* both flanks, 0.1 r either side of the seam */
            double d = 1e-3 * r * i;
            vi_profile_eval(p, lo + d, y);
            cr_assert(fabs(y[0] - (h[0] + fabs(d) * s + lift)) <= 1e-15 && (i == 0 || fabs(y[1] - (d > 0 ? s : -s)) <= 1e-15),
                      "table %d x %.17g: yb %.17g, yb' %.17g", k, lo + d, y[0], y[1]);
        }
        vi_profile_free(p);
    }
}

/* vi_profile_next_kink takes a kink within 8 DBL_EPSILON (|x| + period) of x as the one at x (positions
 * of other periods are rounded) and steps over it: at exactly that distance before (after) the kink it
 * is skipped, one double further it is found. A V trough with its kink at 1, open, periodic, and
 * periodic with a period of 1000 m (the window is then some thousand doubles wide), and open with its
 * kink at 1 mm; x not finite finds none. */
Test(profile, a_kink_within_rounding_of_x_is_the_one_at_x)
{
    double x[] = {0.0, 1.0, 2.0, 1000.0}, h[] = {0.05, 0.0, 0.05, 0.05}, xs[] = {-0.999, 1e-3, 1.001};
    for (int c = 0; c < 4; c++) {
        size_t n = c == 2 ? 4 : 3;
        int periodic = c == 1 || c == 2;
        const double *xc = c == 3 ? xs : x; /* the last: open, the kink at 1 mm (its window some ulps wide) */
        vi_profile *p = make(xc, h, n, R, periodic);
        double P = periodic ? xc[n - 1] - xc[0] : 0.0, k = vi_profile_next_kink(p, xc[1] - 0.5, 1);
        cr_assert(fabs(k - xc[1]) <= 1e-15 && vi_profile_kinks(p) == 1, "%.17g", k);
        double after = periodic ? k + P : INFINITY, before = periodic ? k - P : -INFINITY;
        int found_up = 0, found_down = 0;
        double up = k - 8.0 * DBL_EPSILON * (fabs(k) + P), down = k + 8.0 * DBL_EPSILON * (fabs(k) + P);
        for (int i = 0; i < 64; i++) up = nextafter(up, -INFINITY), down = nextafter(down, INFINITY);
        for (int i = 0; i < 128; i++, up = nextafter(up, INFINITY), down = nextafter(down, -INFINITY)) {
            if (up + 8.0 * DBL_EPSILON * (fabs(up) + P) == k) { /* the farthest x before k whose window reaches k */
                double out = nextafter(up, -INFINITY);
                if (out + 8.0 * DBL_EPSILON * (fabs(out) + P) < k) {
                    found_up++;
                    cr_assert(vi_profile_next_kink(p, up, 1) == after, "x %.17g: %.17g", up, vi_profile_next_kink(p, up, 1));
                    cr_assert(vi_profile_next_kink(p, out, 1) == k, "x %.17g: %.17g", out, vi_profile_next_kink(p, out, 1));
                }
            }
            if (down - 8.0 * DBL_EPSILON * (fabs(down) + P) == k) {
                double out = nextafter(down, INFINITY);
                if (out - 8.0 * DBL_EPSILON * (fabs(out) + P) > k) {
                    found_down++;
                    cr_assert(vi_profile_next_kink(p, down, -1) == before, "x %.17g: %.17g", down,
                              vi_profile_next_kink(p, down, -1));
                    cr_assert(vi_profile_next_kink(p, out, -1) == k, "x %.17g: %.17g", out, vi_profile_next_kink(p, out, -1));
                }
            }
        }
        cr_assert(found_up == 1 && found_down == 1, "table %d: %d %d", c, found_up, found_down);
        cr_assert(vi_profile_next_kink(p, NAN, 1) == INFINITY && vi_profile_next_kink(p, NAN, -1) == -INFINITY);
        cr_assert(vi_profile_next_kink(p, INFINITY, -1) == -INFINITY && vi_profile_next_kink(p, -INFINITY, 1) == INFINITY);
        vi_profile_free(p);
    }
}

Test(profile, outside_the_table)
{
    double x[] = {0.0, 1.0}, h[] = {0.0, 0.0}, y[4];
    vi_profile *p = make(x, h, 2, R, 0);
    cr_assert(vi_profile_eval(p, 1.0, y) == 0 && vi_profile_eval(p, 0.0, y) == 0);
    cr_assert(vi_profile_eval(p, 1.0 + 1e-12, y) == -1 && vi_profile_eval(p, -1e-12, y) == -1);
    cr_assert(vi_profile_x_first(p) == 0.0 && vi_profile_x_last(p) == 1.0);
    vi_profile_free(p);
}

static void refused(const double *x, const double *h, size_t n, double r, int periodic, const char *expect)
{
    char msg[512] = "";
    cr_assert(vi_profile_create(x, h, n, r, periodic, "bad", msg, sizeof msg) == NULL, "accepted: %s", expect);
    cr_assert(strstr(msg, expect) != NULL, "expected '%s' in: %s", expect, msg);
}

Test(profile, bad_tables_are_refused)
{
    double x[] = {0.0, 1.0, 2.0}, h[] = {0.0, 0.1, 0.0};
    refused(x, h, 1, R, 0, "at least two");
    double xu[] = {0.0, 2.0, 1.0};
    refused(xu, h, 3, R, 0, "row 3");
    double xn[] = {0.0, NAN, 2.0};
    refused(xn, h, 3, R, 0, "row 2");
    double hp[] = {0.0, 0.1, 0.2};
    refused(x, hp, 3, R, 1, "last height");
    double xs[] = {0.0, 1.0, 1.0 + 1e-9, 3.0}, hs[] = {0.0, 0.0, 2.0 * R, 2.0 * R}; /* a wall higher than R */
    refused(xs, hs, 4, R, 0, "too steep");
    refused(x, h, 3, 0.0, 0, "R1");
}

/* Each rule of vi_profile_create alone, with the message naming the table, the rule and its values:
 * too few rows, a radius that is not positive and finite, equal positions, a periodic table whose
 * last height differs, a period too short for the body (R1/L + 1 periods each side of 2 rows), a wall
 * as high as R1 climbed and descended (the vertex circle's edge, vertical, at the corner -+ R1) and a
 * wall higher than R1 (the body would touch the wall with its front: yb vertical at the corner - R1). */
Test(profile, refusals_name_the_rule_and_its_values)
{
    double x[] = {0.0, 1.0, 2.0}, h[] = {0.0, 0.1, 0.0};
    refused(x, h, 1, R, 0, "bad: 1 rows; a profile needs at least two (x [m], h [m])");
    refused(x, h, 3, INFINITY, 0, "bad: the rolling radius R1 = inf m must be positive and finite");
    refused(x, h, 3, NAN, 0, "bad: the rolling radius R1 = nan m must be positive and finite");
    refused(x, h, 3, -1.0, 0, "bad: the rolling radius R1 = -1 m must be positive and finite");
    double xe[] = {0.0, 1.0, 1.0};
    refused(xe, h, 3, R, 0, "bad, row 3: x = 1 is not greater than x = 1 of the row before (x must increase)");
    double xu[] = {0.0, 2.0, 1.0};
    refused(xu, h, 3, R, 0, "bad, row 3: x = 1 is not greater than x = 2 of the row before (x must increase)");
    double hp[] = {0.0, 0.1, 0.2};
    refused(x, hp, 3, R, 1, "bad: profile_periodic needs the last height to repeat the first (h = 0.20000000000000001 on row 3, 0 on row 1)");
    double xs[] = {0.0, 0.5e-7, 1e-7}, hs[] = {0.0, 1e-9, 0.0};
    refused(xs, hs, 3, R, 1, "bad: the period 1e-07 m is too short for R1 = 0.475 m: the body spans 9500002 periods of 2 rows, "
                             "more than 10000000 rows in all");
    double xw[] = {0.0, 1.0, 1.0 + 1e-9, 3.0}, hw[] = {0.0, 0.0, R, R}, xd[] = {0.0, 2.0, 2.0 + 1e-9, 3.0}, hd[] = {R, R, 0.0, 0.0};
    /* the wall's slope s = R1/1e-9: the body leaves it R1/(2 s^2) = 1.05e-18 m before its corner, below the spacing
     * of doubles at 0.525 (2^-53) and 2.475 (2^-51), so the circle meets it vertically; the limit sqrt(R1/(2 spacing)) */
    refused(xw, hw, 4, R, 0, "bad: rows 2 and 3 (x = 1 and 1.0000000010000001 m) make a slope of 4.75e+08, too steep for "
                             "R1 = 0.475 m near x = 0.525 m: the body leaves that segment 1.1e-18 m before its end, less than "
                             "the spacing of doubles there (1.1e-16 m), and yb is vertical; slopes up to about 4.63e+07 "
                             "(sqrt(R1/(2 spacing))) can be rolled over there");
    refused(xd, hd, 4, R, 0, "bad: rows 2 and 3 (x = 2 and 2.0000000010000001 m) make a slope of -4.75e+08, too steep for "
                             "R1 = 0.475 m near x = 2.475 m: the body leaves that segment 1.1e-18 m before its end, less than "
                             "the spacing of doubles there (4.4e-16 m), and yb is vertical; slopes up to about 2.31e+07");
    double hw2[] = {0.0, 0.0, 1.5 * R, 1.5 * R};
    refused(xw, hw2, 4, R, 0, "bad: rows 2 and 3 (x = 1 and 1.0000000010000001 m) make a slope of 7.125e+08, too steep");
    /* just below: a wall of 0.9 R1 is climbed on the circle around its upper corner */
    double hw3[] = {0.0, 0.0, 0.9 * R, 0.9 * R};
    vi_profile *p = make(xw, hw3, 4, R, 0);
    double d = -0.3, expect = 0.9 * R - d * d / (R + sqrt(R * R - d * d));
    cr_assert(fabs(yb(p, 1.0 + 1e-9 + d) - expect) <= 1e-15, "%.17g vs %.17g", yb(p, 1.0 + 1e-9 + d), expect);
    vi_profile_free(p);
    /* a wall higher than R1 that is not vertical (1e-6 m wide, slope s = 7.1e5): the body touches its face
     * and yb climbs the face's parallel, s (x - 1) + R1 (sqrt(1 + s^2) - 1), to within s times the
     * rounding of x */
    double xf[] = {0.0, 1.0, 1.0 + 1e-6, 3.0}, s = 1.5 * R / 1e-6, at = 1.0 - R + 0.9e-6;
    p = make(xf, hw2, 4, R, 0);
    expect = s * (at - 1.0) + R * (hypot(1.0, s) - 1.0);
    cr_assert(expect > 0.1 && fabs(yb(p, at) - expect) <= 1e-9, "%.17g vs %.17g", yb(p, at), expect);
    vi_profile_free(p);
}

/* Tables far above or below the datum (heights near +-1000 m, a sub-millimetre relief) are taken as
 * they are: yb against the definition, the relief bridged as without the offset. */
Test(profile, tables_far_from_the_datum)
{
    srand(11);
    for (int t = 0; t < 200; t++) {
        size_t n = 2 + (size_t)(rand() % 7);
        double off = t % 2 ? 1000.0 : -1000.0, x[8], h[8];
        small_table(x, h, n, R, t % 4 < 2, 0);
        for (size_t i = 0; i < n; i++) h[i] += off;
        vi_profile *p = make(x, h, n, R, 0);
        for (int k = 0; k <= 40; k++) {
            double at = x[0] + (x[n - 1] - x[0]) * k / 40.0, ref = brute(x, h, n, R, at);
            cr_assert(fabs(yb(p, at) - ref) <= 1e-12 * (R + 1000.0), "table %d x %.17g: %.17g vs %.17g", t, at, yb(p, at), ref);
        }
        vi_profile_free(p);
    }
}

/* Tables far along the track (x near +-1e7 m and +-1e8 m, where a double resolves 2e-9 m and 1.5e-8 m)
 * are taken: yb against the definition to the slope times that resolution; a wall higher than R1 is
 * still a step there. */
Test(profile, tables_far_along_the_track)
{
    srand(12);
    for (int t = 0; t < 200; t++) {
        size_t n = 2 + (size_t)(rand() % 7);
        double off = (t % 2 ? 1.0 : -1.0) * (t % 4 < 2 ? 1e7 : 1e8), x[8], h[8];
        small_table(x, h, n, R, t % 8 < 4, 0);
        for (size_t i = 0; i < n; i++) x[i] += off;
        vi_profile *p = make(x, h, n, R, 0);
        for (int k = 0; k <= 40; k++) {
            double at = x[0] + (x[n - 1] - x[0]) * k / 40.0, ref = brute(x, h, n, R, at), y[4];
            vi_profile_eval(p, at, y);
            double tol = 1e-12 * R + 8.0 * DBL_EPSILON * fabs(off) * (1.0 + fabs(y[1]));
            cr_assert(fabs(y[0] - ref) <= tol, "table %d x %.17g: %.17g vs %.17g", t, at, y[0], ref);
        }
        vi_profile_free(p);
    }
    /* a wall one double wide there (1.86e-9 m): the steep segment's parallel is lost to rounding and yb
     * jumps by the wall's height less R1 */
    double xw[] = {1e7, 1e7 + 1.0, 1e7 + 1.0 + 1e-9, 1e7 + 3.0}, hw[] = {0.0, 0.0, 1.5 * R, 1.5 * R};
    refused(xw, hw, 4, R, 0, "bad: a step of more than R1 = 0.475 m near x = 1e+07 m: yb jumps by 0.2375");
}

static const char *write_file(const char *text)
{
    static char path[64];
    snprintf(path, sizeof path, "/tmp/vi_profile_test_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fputs(text, f);
    fclose(f);
    return path;
}

Test(profile, files)
{
    char msg[512];
    const char *path = write_file("# x [m], h [m]\n\n0 0\n0.5; 1e-4\n1.0;0\n  1.5\t2e-4  \n");
    vi_profile *p = vi_profile_load(path, R, 0, msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(vi_profile_x_last(p) == 1.5 && yb(p, 0.5) == 1e-4);
    vi_profile_free(p);
    /* Windows line ends and trailing tabs */
    p = vi_profile_load(write_file("0 0\r\n0.5 1e-4\t\r\n1 0\t\n"), R, 0, msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(vi_profile_x_last(p) == 1.0 && yb(p, 0.5) == 1e-4);
    vi_profile_free(p);
    /* the longest line: VI_PROFILE_LINE_MAX - 2 characters before its newline; one more is refused */
    static char text[2 * VI_PROFILE_LINE_MAX];
    for (int extra = 0; extra <= 1; extra++) {
        int len = VI_PROFILE_LINE_MAX - 2 + extra;
        snprintf(text, sizeof text, "0 0\n%-*s\n", len, "1 0"); /* "1 0" padded with spaces */
        msg[0] = '\0';
        p = vi_profile_load(write_file(text), R, 0, msg, sizeof msg);
        cr_assert((p != NULL) == !extra, "a line of %d characters: %s", len, msg);
        if (extra) cr_assert(strstr(msg, "line 2: longer than 4094 characters"), "%s", msg);
        vi_profile_free(p);
    }
    struct { const char *text, *expect; } bad[] = {
        {"0 0\n1 0\nabc 2\n", "line 3: expected two numbers x [m] and h [m], found 2 fields 'abc' '2' (separator: blanks): 'abc' is not a number;"},
        {"0 0\n1\n", "line 2: expected two numbers x [m] and h [m], found 1 field '1' (separator: none): a second number is missing;"},
        {"0 0\n1 0 7\n", "line 2: expected two numbers x [m] and h [m], found 3 fields '1' '0' '7' (separator: blanks): more than two numbers;"},
        {",0\n1 0\n", "line 1: expected two numbers x [m] and h [m], found 1 field ',0' (separator: none): a comma is no decimal point"},
        {"0 0\n2 0\n1 0\n", "line 3: x = 1 is not greater than x = 2 on line 2 (x must increase)"},
        {"0 0\n1 inf\n", "line 2: x = 1, h = inf: h is not finite"},
        {"# only\n0 0\n", "one data row (line 2); a profile needs at least two rows x [m] h [m]"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        path = write_file(bad[i].text);
        msg[0] = '\0';
        cr_assert(vi_profile_load(path, R, 0, msg, sizeof msg) == NULL, "case %zu accepted", i);
        cr_assert(strstr(msg, bad[i].expect) && strstr(msg, path), "case %zu: %s", i, msg);
    }
    remove(path);
    cr_assert(vi_profile_load("/nonexistent/profile.txt", R, 0, msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "/nonexistent/profile.txt") && strstr(msg, "cannot open"), "%s", msg);
}

/* Lines that carry no row are skipped wherever they are: indented comments, blank lines of blanks,
 * tabs and CRLF, a last line of blanks without a newline; a table refused by vi_profile_create is
 * named by its file; a number whose 'e' has no exponent digits ends before the 'e' (as strtod reads
 * it), so its row is refused; a path that opens but cannot be read (a directory) is a read error. */
Test(profile, files_skip_empty_lines_and_refuse_broken_rows)
{
    char msg[512];
    vi_profile *p = vi_profile_load(write_file("  # x h\r\n\r\n0 0\n \t\r\n\t# more\n1 1e-4\n\n2 0\n   "), R, 0, msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(vi_profile_x_first(p) == 0.0 && vi_profile_x_last(p) == 2.0 && yb(p, 1.0) == 1e-4);
    vi_profile_free(p);
    const char *path = write_file("0 0\n1 0.1\n2 0.2\n");
    cr_assert(vi_profile_load(path, R, 1, msg, sizeof msg) == NULL);
    char expect[256];
    snprintf(expect, sizeof expect, "profile_file '%s': profile_periodic needs the last height to repeat the first (h = "
             "0.20000000000000001 on row 3, 0 on row 1)", path);
    cr_assert(strcmp(msg, expect) == 0, "%s", msg);
    remove(path);
    /* an 'e' without exponent digits ends the number before it (as strtod): the row is refused */
    const char *no_exponent[] = {"0 0\n1e 2\n", "0 0\n1E+ 2\n", "0 0\n1 2e-\n", "0 0\n1.5ex 2\n"};
    for (size_t i = 0; i < sizeof no_exponent / sizeof no_exponent[0]; i++) {
        cr_assert(vi_profile_load(write_file(no_exponent[i]), R, 0, msg, sizeof msg) == NULL, "%s", no_exponent[i]);
        cr_assert(strstr(msg, "line 2: expected two numbers x [m] and h [m]"), "%s", msg);
    }
    remove(write_file(""));
    cr_assert(vi_profile_load("/", R, 0, msg, sizeof msg) == NULL);
    cr_assert(strcmp(msg, "profile_file '/': read error after line 0") == 0, "%s", msg);
}

/* Numbers are read as strtod reads them (the value to the bit, in the C locale): random decimals with
 * 1 to 21 digits, exponents from -35 to 35 and signs, the printed forms %.17g and %.18e, and exact
 * binary midpoints (ties) printed in full. Each goes into a two-row file "X H / 1e7 H": the first x
 * is X and a flat profile is H everywhere. */
Test(profile, numbers_are_read_as_strtod_reads_them, .timeout = 60)
{
    srand(2024);
    char msg[512], text[256], num[2][64], first_bad[1024] = "";
    for (int k = 0; k < 3000; k++) {
        for (int i = 0; i < 2; i++) {
            char digits[32];
            int nd = 1 + rand() % 21, dot = rand() % (nd + 1), e = rand() % 71 - 35, form = rand() % 5;
            for (int d = 0; d < nd; d++) digits[d] = (char)('0' + rand() % 10);
            digits[nd] = '\0';
            const char *sign = rand() % 3 == 0 ? "-" : rand() % 4 == 0 ? "+" : "";
            double v = ((double)rand() / RAND_MAX) * pow(10.0, e);
            if (form == 0) snprintf(num[i], sizeof num[i], "%s%.*s.%se%d", sign, dot, digits, digits + dot, e);
            else if (form == 1) snprintf(num[i], sizeof num[i], "%s%.*s.%s", sign, dot, digits, digits + dot);
            else if (form == 2) snprintf(num[i], sizeof num[i], "%.17g", v);
            else if (form == 3) snprintf(num[i], sizeof num[i], "%.18e", v);
            else snprintf(num[i], sizeof num[i], "%.40g", ldexp((double)(rand() % (1 << 30)) * (1 << 23) + 0.5, -40 - rand() % 40));
        }
        double X = strtod(num[0], NULL), H = strtod(num[1], NULL);
        if (!(fabs(X) < 1e6) || !(fabs(H) < 0.1 * R)) continue;
        snprintf(text, sizeof text, "%s %s\n1e7 %s\n", num[0], num[1], num[1]);
        vi_profile *p = vi_profile_load(write_file(text), R, 0, msg, sizeof msg);
        if (!first_bad[0] && (!p || vi_profile_x_first(p) != X || yb(p, 1.0) != H))
            snprintf(first_bad, sizeof first_bad, "%s: %s, read %.17g and %.17g", text, p ? "loaded" : msg,
                     p ? vi_profile_x_first(p) : NAN, p ? yb(p, 1.0) : NAN);
        vi_profile_free(p);
    }
    cr_assert(first_bad[0] == '\0', "%s", first_bad);
}

/* A random decimal string (sign, leading zeros, up to 40 digits with or without a point, '.5' and '5.'
 * forms, an exponent with e or E, its sign and leading zeros; or some hundred zeros after the point
 * and a positive exponent), a printed double (%.17g, %.*e, %a) or an exact binary midpoint printed in
 * full. */
static void random_number(char *out, size_t size)
{
    int form = rand() % 7;
    if (form == 6) { /* 90 to 119 zeros after the point and a positive exponent: a tiny value */
        char *o = out + sprintf(out, "0.");
        for (int z = 90 + rand() % 30; z > 0; z--) *o++ = '0';
        o += sprintf(o, "%de%s%d", 1 + rand() % 999, rand() % 2 ? "+" : "", 1 + rand() % 40);
        cr_assert((size_t)(o - out) < size);
        return;
    }
    if (form == 4) {
        double v = ldexp(1.0 + rand() % 1000, -(rand() % 80)) * pow(10.0, -(rand() % 5));
        int k = rand() % 3;
        if (k == 0) snprintf(out, size, "%.17g", v);
        else if (k == 1) snprintf(out, size, "%.*e", rand() % 25, v);
        else snprintf(out, size, "%a", v);
        return;
    }
    if (form == 5) {
        snprintf(out, size, "%.60g", ldexp((double)(rand() % (1 << 30)) * (1 << 23) + 0.5, -40 - rand() % 40));
        return;
    }
    char *o = out;
    const char *sign = rand() % 3 == 0 ? "-" : rand() % 4 == 0 ? "+" : "";
    o += sprintf(o, "%s", sign);
    for (int z = rand() % 3 == 0 ? rand() % 4 : 0; z > 0; z--) *o++ = '0';
    int nd = rand() % 4 == 0 ? 17 + rand() % 24 : 1 + rand() % 16, dot = rand() % (nd + 2) - 1; /* -1: no point */
    int lead = rand() % 3 == 0 ? rand() % 6 : 0; /* zeros right after the point */
    for (int d = 0; d <= nd; d++) {
        if (d == dot) {
            *o++ = '.';
            for (int z = 0; z < lead; z++) *o++ = '0';
        }
        if (d < nd) *o++ = (char)('0' + (d == 0 && form != 3 ? 1 + rand() % 9 : rand() % 10));
    }
    int ints = dot < 0 ? nd : dot; /* digits before the point: the exponent keeps the value below 1 */
    if (form <= 2 || ints > 0) {
        int e = -ints - rand() % 12 - (form == 2 ? 20 : 0);
        char ech = rand() % 2 ? 'e' : 'E';
        if (e >= 0 && rand() % 2) o += sprintf(o, "%c+%0*d", ech, 1 + rand() % 3, e);
        else if (e < 0) o += sprintf(o, "%c-%0*d", ech, 1 + rand() % 3, -e);
        else o += sprintf(o, "%c%d", ech, e);
    }
    *o = '\0';
    cr_assert((size_t)(o - out) < size);
}

/* Thousands of numbers of every form in one file, read as strtod reads them (the value to the bit):
 * each is the height of a plateau 2 m wide (three rows), 10 m from the next, where yb is the height
 * exactly; the rows' positions are written in other forms of the same integers (signs, leading
 * zeros, a point, exponents, hexadecimal), the separators are blanks, tabs and semicolons,
 * with comments, blank lines and Windows line ends between. */
Test(profile, numbers_of_every_form_are_read_as_strtod_reads_them)
{
    enum { K = 4000 };
    static double want[K];
    static char text[K * 3 * 220];
    srand(777);
    char *o = text, num[192];
    const char *sep[] = {" ", "\t", ";", " ;", " ; ", "\t; ", "  "};
    const char *end[] = {"\n", "\r\n", " \n", "\t\r\n"};
    int k = 0;
    while (k < K) {
        random_number(num, sizeof num);
        double v = strtod(num, NULL);
        if (!(fabs(v) < 0.2)) continue;
        want[k] = v;
        for (int row = -1; row <= 1; row++) {
            long xi = 10L * (k + 1) + row;
            int f = rand() % 9;
            if (f == 0) o += sprintf(o, "%ld", xi);
            else if (f == 1) o += sprintf(o, "+%ld.", xi);
            else if (f == 2) o += sprintf(o, "000%ld.000", xi);
            else if (f == 3) o += sprintf(o, "%ld000e-3", xi);
            else if (f == 4) o += sprintf(o, "%.6E", (double)xi);
            else if (f == 5) o += sprintf(o, "0x%lx", xi);
            else if (f == 6) o += sprintf(o, "0.%ldE%d", xi, xi < 10 ? 1 : xi < 100 ? 2 : xi < 1000 ? 3 : xi < 10000 ? 4 : 5);
            else if (f == 7) o += sprintf(o, "%ld.0e+0", xi);
            else o += sprintf(o, "0X%lX", xi);
            o += sprintf(o, "%s%s%s", sep[rand() % 7], num, end[rand() % 4]);
        }
        if (rand() % 10 == 0) o += sprintf(o, rand() % 2 ? "# %s\n" : "\n  \t\n", num);
        k++;
    }
    *o = '\0';
    char msg[512];
    vi_profile *p = vi_profile_load(write_file(text), R, 0, msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(vi_profile_x_first(p) == 9.0 && vi_profile_x_last(p) == 10.0 * K + 1.0);
    for (k = 0; k < K; k++) {
        double got = yb(p, 10.0 * (k + 1));
        if (got != want[k]) {
            /* the row of the number, for the message */
            char *line = text;
            for (int skip = 0; skip < 3 * k; skip++) line = strchr(line, '\n') + 1;
            cr_assert(0, "number %d: read %.17g, strtod %.17g (%.80s)", k, got, want[k], line);
        }
    }
    vi_profile_free(p);
    remove(write_file(""));
}

/* Exponents beyond the exact conversion's (strtod's), as the last or first x: 1e28 and more, and
 * exponents of more digits than an int holds (2^32 + 1: infinite, refused; 2^32: a height of 0). */
Test(profile, exponents_beyond_the_exact_conversion_are_read_as_strtod_reads_them)
{
    char msg[512];
    vi_profile *p;
    struct { const char *text; double first, last; } big[] = {
        {"0 0\n1e28 0\n", 0.0, 1e28},
        {"0 0\n123456789012345678e30 0\n", 0.0, 123456789012345678e30},
        {"-5.5E+40 0\n0 0\n", -5.5e40, 0.0},
        {"0 0\n0.000000000000000000000000000000000000001e66 0\n", 0.0, 1e27},
        {"0 0\n3e23 0\n", 0.0, 3e23},
        {"-7E+22 0\n0 0\n", -7e22, 0.0},
        {"0 0\n4.1e22 0\n", 0.0, 4.1e22},
    };
    for (size_t i = 0; i < sizeof big / sizeof big[0]; i++) {
        p = vi_profile_load(write_file(big[i].text), R, 0, msg, sizeof msg);
        cr_assert(p != NULL, "%s: %s", big[i].text, msg);
        cr_assert(vi_profile_x_first(p) == big[i].first && vi_profile_x_last(p) == big[i].last, "%s: %.17g %.17g",
                  big[i].text, vi_profile_x_first(p), vi_profile_x_last(p));
        vi_profile_free(p);
    }
    cr_assert(vi_profile_load(write_file("0 0\n1e4294967297 0\n"), R, 0, msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "line 2: x = inf, h = 0: x is not finite"), "%s", msg);
    p = vi_profile_load(write_file("0 1e-4294967296\n1 0\n"), R, 0, msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    cr_assert(yb(p, 0.0) == 0.0 && yb(p, 1.0) == 0.0);
    vi_profile_free(p);
    remove(write_file(""));
}

/* Integers of 54 to 64 bits (and times 10^e), among them exact midpoints between two doubles with an
 * even and an odd lower neighbour (ties to even), as the last x: read as strtod reads them. */
Test(profile, integers_of_54_to_64_bits_and_midpoints_are_read_as_strtod_reads_them)
{
    srand(778);
    char msg[512], num[192];
    vi_profile *p;
    for (int i = 0; i < 300; i++) {
        unsigned long long m = (1ull << 52) + ((unsigned long long)rand() << 20) + (unsigned long long)rand() % (1u << 20);
        int j = rand() % 11, e = i % 4 == 0 ? rand() % 8 : 0;
        unsigned long long w = i % 2 ? ((2 * m + 1) << j) : (m << 11) + (unsigned long long)rand();
        char row[256];
        if (i % 6 == 5) /* midpoints with a decimal fraction: m + 1/2 (doubles 1 apart), m/2 + 1/4 or 3/4 (0.5 apart) */
            snprintf(num, sizeof num, "%llu.5", m);
        else if (i % 6 == 2)
            snprintf(num, sizeof num, "%llu.%s", m >> 1, rand() % 2 ? "25" : "75");
        else
            snprintf(num, sizeof num, "%llue%d", w, e);
        snprintf(row, sizeof row, "0 0\n%s 0\n", num);
        p = vi_profile_load(write_file(row), R, 0, msg, sizeof msg);
        cr_assert(p != NULL, "%s: %s", row, msg);
        cr_assert(vi_profile_x_last(p) == strtod(num, NULL), "%s: %.17g, strtod %.17g", num, vi_profile_x_last(p), strtod(num, NULL));
        vi_profile_free(p);
    }
    remove(write_file(""));
}

/* The ends of the exact conversion, as strtod reads them: mantissas of 15 to 21 digits (19 is the most
 * the exact conversion takes; 20 and more overflow 64 bits) with decimal exponents from -30 to -nd
 * (past -27 the conversion is strtod's; at -27 the exact quotient has 64 to 65 bits), written as
 * "<digits>e<E>" and "<d>.<digits>e<E>", as x and as the height of a two-row flat profile. */
Test(profile, long_mantissas_and_small_exponents_are_read_as_strtod_reads_them, .timeout = 60)
{
    srand(7);
    char msg[512], text[256], num[2][64], first_bad[1024] = "";
    int checked = 0;
    for (int nd = 15; nd <= 21; nd++)
        for (int E = -30; E <= -nd; E++)
            for (int k = 0; k < 40; k++) {
                for (int i = 0; i < 2; i++) {
                    char digits[32];
                    digits[0] = (char)('1' + rand() % 9);
                    for (int d = 1; d < nd; d++) digits[d] = (char)('0' + rand() % 10);
                    digits[nd] = '\0';
                    const char *sign = rand() % 2 ? "-" : "";
                    if (k % 2) snprintf(num[i], sizeof num[i], "%s%se%d", sign, digits, E - i);
                    else snprintf(num[i], sizeof num[i], "%s%c.%se%d", sign, digits[0], digits + 1, E - i + nd - 1);
                }
                double X = strtod(num[0], NULL), H = strtod(num[1], NULL);
                snprintf(text, sizeof text, "%s %s\n1e7 %s\n", num[0], num[1], num[1]);
                vi_profile *p = vi_profile_load(write_file(text), R, 0, msg, sizeof msg);
                checked++;
                if (!first_bad[0] && (!p || vi_profile_x_first(p) != X || yb(p, 1.0) != H))
                    snprintf(first_bad, sizeof first_bad, "%s: %s, read %.17g and %.17g", text, p ? "loaded" : msg,
                             p ? vi_profile_x_first(p) : NAN, p ? yb(p, 1.0) : NAN);
                vi_profile_free(p);
            }
    cr_assert(checked > 2000);
    cr_assert(first_bad[0] == '\0', "%s", first_bad);
}

/* A periodic profile whose period is so short that the body spans more than VI_PROFILE_ROWS_MAX rows
 * of its copies is refused, naming the period. */
Test(profile, periodic_period_too_short_for_the_body)
{
    double x[] = {0.0, 0.5e-7, 1e-7}, h[] = {0.0, 1e-9, 0.0};
    refused(x, h, 3, R, 1, "the period 1e-07 m is too short");
    vi_profile *p = make(x, h, 3, 1e-6, 1); /* a small body over the same period */
    cr_assert(vi_profile_kinks(p) >= 1);
    vi_profile_free(p);
}

/* Memory running out while a file is read: refused with a message naming the line, no crash.
 * (Criterion runs each test in its own process: the address-space limit stays in it. Skipped under
 * AddressSanitizer, whose shadow memory needs the address space.) */
Test(profile, out_of_memory_while_reading_is_refused)
{
#if defined(__SANITIZE_ADDRESS__)
    cr_skip_test("AddressSanitizer reserves the address space");
#endif
    char path[64];
    snprintf(path, sizeof path, "/tmp/vi_profile_test_big_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    for (int i = 0; i < 1 << 20; i++) fprintf(f, "%d 0\n", i); /* 2 x 8 MB of doubles at the end */
    fclose(f);
    long vm_kb = -1;
    char line[256];
    FILE *st = fopen("/proc/self/status", "r");
    cr_assert(st != NULL);
    while (fgets(line, sizeof line, st))
        if (sscanf(line, "VmSize: %ld kB", &vm_kb) == 1) break;
    fclose(st);
    cr_assert(vm_kb > 0);
    struct rlimit lim = {(rlim_t)(vm_kb + 4096) * 1024, (rlim_t)(vm_kb + 4096) * 1024}; /* 4 MB more */
    cr_assert(setrlimit(RLIMIT_AS, &lim) == 0);
    char msg[512] = "";
    vi_profile *p = vi_profile_load(path, R, 0, msg, sizeof msg);
    remove(path);
    cr_assert(p == NULL && strstr(msg, "out of memory at line"), "%s", msg);
}

#if defined(__SANITIZE_ADDRESS__)
#define VI_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VI_TEST_ASAN 1
#endif
#endif

#if defined(__GLIBC__) && !defined(VI_TEST_ASAN)
/* The test program's malloc, calloc and realloc (glibc's own otherwise: none calls another through
 * these names) fail the fail_countdown-th call among them from when it is set, once; 0: never. */
extern void *__libc_malloc(size_t n);
extern void *__libc_calloc(size_t n, size_t size);
extern void *__libc_realloc(void *p, size_t n);
static int fail_countdown;
static int fail_now(void) { return fail_countdown > 0 && --fail_countdown == 0; }
void *malloc(size_t n) { return fail_now() ? NULL : __libc_malloc(n); }
void *calloc(size_t n, size_t size) { return fail_now() ? NULL : __libc_calloc(n, size); }
void *realloc(void *p, size_t n) { return fail_now() ? NULL : __libc_realloc(p, n); }

/* vi_profile_create with its k-th allocation failing (malloc, calloc or realloc), for every k until
 * it needs no more: NULL and "out of memory" each time, nothing held afterwards. */
static void every_allocation_fails_cleanly_as(const double *x, const double *h, size_t n, double r, int periodic,
                                              int interpolation)
{
    char msg[256];
    vi_profile_free(vi_profile_create_as(x, h, n, r, periodic, interpolation, "table", msg, sizeof msg)); /* the
                                                                                  allocator's own first-use growth */
    struct mallinfo2 before = mallinfo2();
    int k = 1;
    for (;; k++) {
        msg[0] = '\0';
        fail_countdown = k;
        vi_profile *p = vi_profile_create_as(x, h, n, r, periodic, interpolation, "table", msg, sizeof msg);
        int failed = fail_countdown == 0;
        fail_countdown = 0;
        if (!failed) {
            cr_assert(p != NULL, "%s", msg);
            vi_profile_free(p);
            break;
        }
        cr_assert(p == NULL && strstr(msg, "table: out of memory"), "malloc %d failing: %s", k, msg);
    }
    cr_assert(k > 5, "only %d allocations", k - 1);
    struct mallinfo2 after = mallinfo2();
    cr_assert(after.uordblks <= before.uordblks + 4096, "heap in use grew by %zu bytes", after.uordblks - before.uordblks);
}

static void every_allocation_fails_cleanly(const double *x, const double *h, size_t n, double r, int periodic)
{
    every_allocation_fails_cleanly_as(x, h, n, r, periodic, VI_PROFILE_LINEAR);
    every_allocation_fails_cleanly_as(x, h, n, r, periodic, VI_PROFILE_CUBIC);
}
#endif

/* Every allocation checked, the rows joined linearly and by the spline: a smooth table (open and
 * periodic), a rough one whose scratch stack for the intervals beyond a piece's domain first takes a
 * whole interval (not a cut one), and one of 600 rough rows whose interval stack outgrows its first
 * capacity, also while intervals are put back (the spline's troughs sharper than the body: more arcs
 * than segments); and a smooth spline long enough to keep its rows instead of its arcs, from arrays
 * (copied). */
Test(profile, every_allocation_of_create_is_checked)
{
#if !defined(__GLIBC__) || defined(VI_TEST_ASAN)
    cr_skip_test("needs glibc's __libc_malloc, without AddressSanitizer");
#else
    enum { N = 33 };
    double x[N], h[N];
    for (int i = 0; i < N; i++) x[i] = 0.01 * i, h[i] = 5e-3 * cos(2.0 * 3.14159265358979323846 * x[i] / 0.32);
    every_allocation_fails_cleanly(x, h, N, R, 0);
    every_allocation_fails_cleanly(x, h, N, R, 1);
    double xr[] = {0.0, 0.5, 1.0, 1.125}, hr[] = {-0.25, 0.1875, -0.078125, 0.375};
    every_allocation_fails_cleanly(xr, hr, 4, 1.0, 0);
    static double xl[600], hl[600]; /* more intervals than the stack's first capacity: it grows while inserting */
    srand(5);
    for (int i = 0; i < 600; i++) xl[i] = 0.05 * i, hl[i] = 0.02 * rand() / RAND_MAX;
    every_allocation_fails_cleanly(xl, hl, 600, R, 0);
    enum { LONG = 16500 };
    static double xs[LONG], hs[LONG];
    for (int i = 0; i < LONG; i++) xs[i] = 1e-4 * i, hs[i] = 1e-5 * cos(2.0 * 3.14159265358979323846 * xs[i] / 0.05);
    hs[LONG - 1] = hs[0];
    every_allocation_fails_cleanly_as(xs, hs, LONG, R, 0, VI_PROFILE_CUBIC);
    every_allocation_fails_cleanly_as(xs, hs, LONG, R, 1, VI_PROFILE_CUBIC);
#endif
}

/* vi_profile_load with its k-th allocation failing, for every k until it needs no more (a file of 600
 * rows: the row arrays grow twice): NULL and "out of memory" naming the file (the first allocation,
 * fopen's: "cannot open"), or the profile when the allocation was the C library's own with a fallback (stdio's
 * buffer); nothing held afterwards. */
Test(profile, every_allocation_of_load_is_checked)
{
#if !defined(__GLIBC__) || defined(VI_TEST_ASAN)
    cr_skip_test("needs glibc's __libc_malloc, without AddressSanitizer");
#else
    static char text[600 * 24];
    char *o = text, msg[512];
    for (int i = 0; i < 600; i++) o += sprintf(o, "%d %g\n", i, 1e-4 * (i % 7));
    const char *path = write_file(text);
    vi_profile_free(vi_profile_load(path, R, 0, msg, sizeof msg)); /* the allocator's own first-use growth */
    struct mallinfo2 before = mallinfo2();
    int k = 1, refused = 0;
    for (;; k++) {
        msg[0] = '\0';
        fail_countdown = k;
        vi_profile *p = vi_profile_load(path, R, 0, msg, sizeof msg);
        int failed = fail_countdown == 0;
        fail_countdown = 0;
        if (!failed) {
            cr_assert(p != NULL, "%s", msg);
            cr_assert(vi_profile_x_last(p) == 599.0);
            vi_profile_free(p);
            break;
        }
        if (p) { /* a fallback of the C library */
            cr_assert(vi_profile_x_last(p) == 599.0);
            vi_profile_free(p);
            continue;
        }
        refused++;
        cr_assert(strstr(msg, path) && (strstr(msg, ": out of memory") || (k == 1 && strstr(msg, "cannot open"))),
                  "malloc %d failing: %s", k, msg);
    }
    cr_assert(refused > 5, "only %d refusals in %d allocations", refused, k - 1);
    struct mallinfo2 after = mallinfo2();
    cr_assert(after.uordblks <= before.uordblks + 4096, "heap in use grew by %zu bytes", after.uordblks - before.uordblks);
    remove(path);
#endif
}

/* A long profile (1e5 samples at 1 mm): built in bounded time, evaluated by binary search. */
Test(profile, long_profile, .timeout = 30)
{
    enum { N = 100000 };
    double *x = malloc(N * sizeof *x), *h = malloc(N * sizeof *h);
    srand(7);
    for (int i = 0; i < N; i++) x[i] = 1e-3 * i, h[i] = 5e-5 * sin(40.0 * x[i]) + 2e-6 * (2.0 * rand() / RAND_MAX - 1.0);
    vi_profile *p = make(x, h, N, R, 0);
    for (int k = 0; k < 50; k++) {
        double at = 0.5 + 98.0 * k / 50.0;
        cr_assert(fabs(yb(p, at) - brute(x, h, N, R, at)) <= 1e-15, "x %g", at);
    }
    vi_profile_free(p);
    free(x), free(h);
}

/* The search for x's interval starts in a bucket of equal parts of the range: a table of 3000 rows,
 * dense in its first tenth (0.01 mm apart) and sparse after it (up to 2 mm), so that a bucket holds
 * hundreds of intervals in one part and none in another, evaluated at every row, halfway between rows
 * and at 20001 points between, against the definition (the highest circle over the rows and segments),
 * for a body of 1 cm (its definition looks at fewer rows). */
Test(profile, the_interval_search_finds_every_piece_of_an_uneven_table, .timeout = 30)
{
    enum { N = 3000 };
    double *x = malloc(N * sizeof *x), *h = malloc(N * sizeof *h);
    srand(11);
    x[0] = 0.0, h[0] = 0.0;
    for (int i = 1; i < N; i++) {
        x[i] = x[i - 1] + (i < N / 10 ? 1e-5 : 2e-3 * rand() / RAND_MAX + 1e-6);
        h[i] = 1e-3 * sin(300.0 * x[i]) + 2e-5 * (2.0 * rand() / RAND_MAX - 1.0);
    }
    double r = 0.01;
    vi_profile *p = make(x, h, N, r, 0);
    for (int k = 0; k < 3 * N + 20001; k++) {
        double at = k < N ? x[k] : k < 2 * N - 1 ? 0.5 * (x[k - N] + x[k - N + 1])
                  : x[0] + (x[N - 1] - x[0]) * (k - 3 * N) / 20000.0;
        if (k >= 2 * N - 1 && k < 3 * N) continue;
        double want = brute(x, h, N, r, at);
        cr_assert(fabs(yb(p, at) - want) <= 1e-15, "x %.17g: yb %.17g, definition %.17g", at, yb(p, at), want);
    }
    vi_profile_free(p);
    free(x), free(h);
}

/* Tables given as arrays are checked like files: a row that is not finite is refused naming the
 * table and the row (NaN height, infinite position: no other check catches either); the name is
 * "profile" when none is given. */
Test(profile, non_finite_rows_are_refused_naming_the_table_and_row)
{
    double x[] = {0.0, 0.5, 1.0}, h[] = {0.0, 0.0, 0.0}, xi[] = {0.0, 0.5, INFINITY};
    char msg[512];
    h[1] = NAN;
    cr_assert(vi_profile_create(x, h, 3, R, 0, "table A", msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "table A, row 2:") && strstr(msg, "are not finite"), "%s", msg);
    h[1] = 0.0;
    cr_assert(vi_profile_create(xi, h, 3, R, 0, NULL, msg, sizeof msg) == NULL);
    cr_assert(strncmp(msg, "profile, row 3:", 15) == 0 && strstr(msg, "are not finite"), "%s", msg);
    double x1[] = {NAN, 0.5, 1.0}, h1[] = {0.0, 0.0, INFINITY}; /* the first row, and the last height */
    cr_assert(vi_profile_create(x1, h, 3, R, 0, "table B", msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "table B, row 1: x = nan, h = 0 are not finite"), "%s", msg);
    cr_assert(vi_profile_create(x, h1, 3, R, 0, "table B", msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "table B, row 3: x = 1, h = inf are not finite"), "%s", msg);
    vi_profile *p = vi_profile_create(x, h, 3, R, 0, "table A", msg, sizeof msg);
    cr_assert(p != NULL, "%s", msg);
    vi_profile_free(p);
}

/* vi_profile_create and vi_profile_free hold no memory afterwards: 200 profiles of 400 rough samples
 * made and freed leave the heap in use within 64 kB of where it was (the allocator's own caches move
 * it by some kB; a leak of the envelope's work arrays, tens of kB per profile, would show as MB). */
Test(profile, create_and_free_hold_no_memory)
{
    enum { N = 400 };
    double x[N], h[N];
    srand(3);
    for (int i = 0; i < N; i++) x[i] = 1e-3 * i, h[i] = 1e-4 * rand() / RAND_MAX;
    char msg[256];
    vi_profile_free(make(x, h, N, R, 0)); /* the allocator's own first-use growth */
    struct mallinfo2 before = mallinfo2();
    for (int k = 0; k < 200; k++) {
        vi_profile *p = vi_profile_create(x, h, N, R, 0, "rough", msg, sizeof msg);
        cr_assert(p != NULL, "%s", msg);
        vi_profile_free(p);
    }
    struct mallinfo2 after = mallinfo2();
    cr_assert(after.uordblks <= before.uordblks + 65536, "heap in use grew by %zu bytes",
              after.uordblks - before.uordblks);
}

/* A file is named by its whole path in the messages of the table's checks, up to the longest path
 * a file can be opened by: here 4070 characters (directories of 200), with a buffer that holds them. */
Test(profile, a_long_path_is_named_whole)
{
    enum { PATH_LEN = 4070 };
    static char path[PATH_LEN + 1], msg[2 * PATH_LEN];
    int k = snprintf(path, sizeof path, "/tmp/vi_profile_long_%d", (int)getpid());
    cr_assert(mkdir(path, 0700) == 0);
    int depth = 0;
    while (k + 1 + 200 + 12 < PATH_LEN) { /* room for a directory and the file's name */
        path[k++] = '/';
        memset(path + k, 'd', 200);
        k += 200;
        path[k] = '\0';
        cr_assert(mkdir(path, 0700) == 0, "%s", strerror(errno));
        depth++;
    }
    k += snprintf(path + k, sizeof path - (size_t)k, "/%0*d.txt", PATH_LEN - k - 5, 0);
    cr_assert(k == PATH_LEN, "%d", k);
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL, "%s", strerror(errno));
    fputs("0 0\n1 0.1\n2 0.2\n", f);
    fclose(f);
    vi_profile *p = vi_profile_load(path, R, 1, msg, sizeof msg); /* periodic: the last height must repeat */
    const char *at = strstr(msg, path);
    int named = at != NULL && strncmp(at + PATH_LEN, "': profile_periodic needs", 25) == 0;
    remove(path);
    for (; depth >= 0; depth--) { /* the directories, innermost first */
        *strrchr(path, '/') = '\0';
        rmdir(path);
    }
    cr_assert(p == NULL && named, "%.80s...", msg);
}

/* A file is refused with what its bad line holds: the fields (quoted, cut after 24 characters), the
 * separator seen and the rule broken, then how to write a row. A comma is no decimal point: a
 * one-column file of decimal commas is not read as two columns, German decimals and a header row are
 * named as what they are. */
static void file_refused(const char *text, const char *expect)
{
    char msg[1024] = "";
    const char *path = write_file(text);
    vi_profile *p = vi_profile_load(path, R, 0, msg, sizeof msg);
    cr_assert(p == NULL, "accepted: %s", text);
    char want[1024];
    snprintf(want, sizeof want, "profile_file '%s'%s", path, expect);
    cr_assert(strncmp(msg, want, strlen(want)) == 0, "expected\n  %s\nin\n  %s", want, msg);
    remove(path);
}

#define HOW "; write x and h in the C syntax with '.' decimals (0.5, -1.2e-3) separated by blanks, a tab, one " \
            "comma or one semicolon; lines starting with # are comments"

Test(profile, rows_that_are_not_two_numbers_are_refused_saying_what_they_hold)
{
    file_refused("0,5\n1,5\n2,5\n", ", line 1: expected two numbers x [m] and h [m], found 1 field '0,5' (separator: "
                                    "none): a comma is no decimal point, and '0,5' could be 0.5 or the columns 0 and 5" HOW);
    file_refused("x h\n0 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields 'x' 'h' (separator: "
                                    "blanks): 'x' is not a number (a header? start it with #)" HOW);
    file_refused("# x;h\n0;0\n1,5;2,5\n", ", line 3: expected two numbers x [m] and h [m], found 2 fields '1,5' '2,5' "
                                          "(separator: a semicolon): a comma is no decimal point");
    file_refused("0 0\n-12,75e-3\n", ", line 2: expected two numbers x [m] and h [m], found 1 field '-12,75e-3' "
                                     "(separator: none): a comma is no decimal point");
    file_refused("0 0\n1.5,2,5\n", ", line 2: expected two numbers x [m] and h [m], found 1 field '1.5,2,5' ");
    file_refused("0 0\n1 0 # end\n", ", line 2: expected two numbers x [m] and h [m], found 4 fields '1' '0' '#' ... "
                                     "(separator: blanks): a comment (#) must start its line" HOW);
    file_refused("0 0\n1-2\n", ", line 2: expected two numbers x [m] and h [m], found 1 field '1-2' (separator: none): "
                               "'1-2' is not a number" HOW);
    file_refused("0 0\n1\t2\t3\n", ", line 2: expected two numbers x [m] and h [m], found 3 fields '1' '2' '3' (separator: "
                                   "a tab): more than two numbers" HOW);
    file_refused("0 0\n1 2 3 4 x\n", ", line 2: expected two numbers x [m] and h [m], found 5 fields '1' '2' '3' ... "
                                     "(separator: blanks): a field after them is not a number" HOW);
    file_refused("0 0\n1 2 x\n", ", line 2: expected two numbers x [m] and h [m], found 3 fields '1' '2' 'x' (separator: "
                                 "blanks): 'x' is not a number" HOW);
    file_refused("0 0\n ; \r\n", ", line 2: expected two numbers x [m] and h [m], found 0 fields (separator: a "
                                 "semicolon): no number" HOW);
    file_refused(";0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 1 field '0' (separator: a semicolon): "
                               "a second number is missing" HOW);
    file_refused("0 0\n1;;2\n", ", line 2: expected two numbers x [m] and h [m], found 2 fields '1' '2' (separator: "
                                "several semicolons): more than one semicolon" HOW);
    file_refused("0 0\n1 2;\n", ", line 2: expected two numbers x [m] and h [m], found 2 fields '1' '2' (separator: a "
                                "semicolon): the semicolon does not stand between the numbers" HOW);
    file_refused("0 0\n\t1\t \n", ", line 2: expected two numbers x [m] and h [m], found 1 field '1' (separator: blanks "
                                  "and tabs): a second number is missing" HOW);
    file_refused("0 0\n0.123456789012345678901234567890 x\n",
                 ", line 2: expected two numbers x [m] and h [m], found 2 fields '0.1234567890123456789012...' 'x' "
                 "(separator: blanks): 'x' is not a number" HOW);
    file_refused("0 0\n1 2\xC3\xBC\r\n", ", line 2: expected two numbers x [m] and h [m], found 2 fields '1' '2\\xC3\\xBC' "
                                         "(separator: blanks): '2\\xC3\\xBC' is not a number" HOW);
    /* a field of 30 bytes outside printable ASCII: 24 of them shown, each as \xNN */
    char ctl[64] = "0 0\n1 ", want[256] = ", line 2: expected two numbers x [m] and h [m], found 2 fields '1' '";
    memset(ctl + 6, 0x01, 30);
    strcat(ctl, "\n");
    for (int i = 0; i < 24; i++) strcat(want, "\\x01");
    strcat(want, "...' (separator: blanks)");
    file_refused(ctl, want);
    /* a NUL byte inside a line (the text is written by hand: write_file stops at it) */
    const char *path = write_file("");
    FILE *f = fopen(path, "wb");
    fwrite("0 0\n1 0\0 junk\n", 1, 14, f);
    fclose(f);
    char msg[1024];
    cr_assert(vi_profile_load(path, R, 0, msg, sizeof msg) == NULL);
    cr_assert(strstr(msg, "line 2: expected two numbers x [m] and h [m], found 3 fields '1' '0\\x00' 'junk' (separator: "
                          "blanks): it holds a NUL byte (a binary or UTF-16 file?)"), "%s", msg);
    /* byte-order marks of UTF-16 (little- and big-endian); a first line merely holding such bytes is no mark */
    file_refused("\xFF\xFE" "0 0\n", ", line 1: the file starts with a UTF-16 or UTF-32 byte-order mark; save it as UTF-8 "
                                     "or ASCII text");
    file_refused("\xFE\xFF" "0 0\n", ", line 1: the file starts with a UTF-16 or UTF-32 byte-order mark");
    file_refused("0\xFE 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields '0\\xFE' '0'");
    file_refused("\xFF" "0 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields '\\xFF0' '0'");
    file_refused("\xFE" "0 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields '\\xFE0' '0'");
    file_refused("0\xFF 0\n1 0\n", ", line 1: expected two numbers x [m] and h [m], found 2 fields '0\\xFF' '0'");
}

/* A UTF-8 byte-order mark (EF BB BF, as some editors write) before the first row or comment is skipped. */
Test(profile, a_utf8_byte_order_mark_is_skipped)
{
    char msg[512];
    const char *texts[] = {"\xEF\xBB\xBF" "0 0\n1 1e-4\n2 0\n", "\xEF\xBB\xBF# x h\r\n0 0\r\n1 1e-4\r\n2 0\r\n"};
    for (size_t i = 0; i < 2; i++) {
        vi_profile *p = vi_profile_load(write_file(texts[i]), R, 0, msg, sizeof msg);
        cr_assert(p != NULL, "%s", msg);
        cr_assert(vi_profile_x_first(p) == 0.0 && vi_profile_x_last(p) == 2.0 && yb(p, 1.0) == 1e-4);
        vi_profile_free(p);
    }
    /* only on the first line: the mark inside the file is no number */
    file_refused("0 0\n\xEF\xBB\xBF" "1 0\n", ", line 2: expected two numbers x [m] and h [m], found 2 fields "
                                             "'\\xEF\\xBB\\xBF1' '0'");
}

/* A comma separates x and h as a semicolon does (CSV files), with blanks around it or none, unless the
 * line would read as one number with a decimal comma (digits, the comma, digits and an exponent, nothing
 * between): the rows read as the same table written with blanks. */
Test(profile, a_comma_separates_unless_the_line_is_one_number_with_a_decimal_comma)
{
    char msg[512];
    const char *same[][2] = {
        {"0.5,1e-4\n1.0,0\n1.5,2e-4\n", "0.5 1e-4\n1.0 0\n1.5 2e-4\n"},
        {"0, 1e-4\n1 ,0\n2 , 2e-4\n", "0 1e-4\n1 0\n2 2e-4\n"},
        {"0,0.001\n1,-2e-4\n2,0x1p-12\n", "0 0.001\n1 -2e-4\n2 0x1p-12\n"},
        {"1e-3,5\n2e-3,5\r\n", "1e-3 5\n2e-3 5\n"},
    };
    for (size_t i = 0; i < sizeof same / sizeof same[0]; i++) {
        vi_profile *p = vi_profile_load(write_file(same[i][0]), R, 0, msg, sizeof msg);
        cr_assert(p != NULL, "case %zu: %s", i, msg);
        vi_profile *q = vi_profile_load(write_file(same[i][1]), R, 0, msg, sizeof msg);
        cr_assert(q != NULL, "case %zu: %s", i, msg);
        cr_assert(vi_profile_x_first(p) == vi_profile_x_first(q) && vi_profile_x_last(p) == vi_profile_x_last(q));
        double lo = vi_profile_x_first(q), hi = vi_profile_x_last(q);
        for (int k = 0; k <= 20; k++) {
            double x = lo + (hi - lo) * k / 20.0;
            cr_assert(yb(p, x) == yb(q, x), "case %zu at x = %g", i, x);
        }
        vi_profile_free(p);
        vi_profile_free(q);
    }
    const char *one_number[] = {"0 0\n0,5\n", "0 0\n12,75\n", "0 0\n-1,5e-3\n", "0 0\n+3,25E+2\n", "0 0\n1,5\r\n"};
    for (size_t i = 0; i < sizeof one_number / sizeof one_number[0]; i++) {
        msg[0] = '\0';
        cr_assert(vi_profile_load(write_file(one_number[i]), R, 0, msg, sizeof msg) == NULL, "accepted: %s", one_number[i]);
        cr_assert(strstr(msg, "line 2: ") && strstr(msg, "a comma is no decimal point"), "%s", msg);
    }
}

/* Too few rows each have their message: an empty file, a file of blank lines and comments (a BOM
 * alone is blank), one data row (named by its line). */
Test(profile, empty_files_and_files_without_two_rows_are_refused)
{
    file_refused("", ": the file is empty; a profile needs at least two rows x [m] h [m]");
    file_refused("# x h\n\n   \n", ": no data rows, its 3 lines are blank or comments; a profile needs at least two "
                                  "rows x [m] h [m]");
    file_refused("\xEF\xBB\xBF", ": no data rows, its 1 line is blank or comments");
    file_refused("# x h\n\n5 0\n# end\n", ": one data row (line 3); a profile needs at least two rows x [m] h [m]");
}

/* A value that is not finite names which one; an x that does not increase names the line of the row
 * before it (comments between counted). */
Test(profile, non_finite_values_and_x_not_increasing_name_their_lines)
{
    file_refused("0 0\nnan 1\n", ", line 2: x = nan, h = 1: x is not finite (a number beyond 1.8e308, inf or nan)");
    file_refused("0 0\n1 -1e400\n", ", line 2: x = 1, h = -inf: h is not finite");
    file_refused("0 0\ninf NaN\n", ", line 2: x = inf, h = nan: x and h are not finite");
    file_refused("0 0\n# a comment\n2 0\n\n2 1\n", ", line 5: x = 2 is not greater than x = 2 on line 3 (x must increase)");
}

/* One row more than VI_PROFILE_ROWS_MAX is refused at that row's line (the table is read up to it). */
Test(profile, more_rows_than_the_cap_are_refused, .timeout = 120)
{
    char path[64], msg[512];
    snprintf(path, sizeof path, "/tmp/vi_profile_cap_%d.txt", (int)getpid());
    FILE *f = fopen(path, "w");
    cr_assert(f != NULL);
    fputs("# one row more than the cap\n", f);
    for (long i = 0; i <= VI_PROFILE_ROWS_MAX; i++) fprintf(f, "%ld 0\n", i);
    fclose(f);
    vi_profile *p = vi_profile_load(path, R, 0, msg, sizeof msg);
    remove(path);
    cr_assert(p == NULL);
    char want[256];
    snprintf(want, sizeof want, "profile_file '%s', line %d: more than %d rows, the most a profile may have", path,
             VI_PROFILE_ROWS_MAX + 2, VI_PROFILE_ROWS_MAX);
    cr_assert(strcmp(msg, want) == 0, "%s", msg);
}

/* A periodic table whose last vertex x_n-1 + k L differs after rounding from the next copy's first,
 * x_0 + (k + 1) L: the envelope's domains still chain (it was refused as "a gap in the envelope"),
 * and yb near the seam agrees with the definition on the unrolled table to the slope times the
 * spacing of doubles there. */
/* A periodic table of n <= 5 rows whose segments are all longer than r: p's yb at 201 points across
 * [c - w, c + w] for each of the nc centres c against the definition on the table unrolled one copy
 * each side, to the slope times the spacing of doubles at the table's far end (a position is reduced
 * into [x_first, x_last], rounded there). */
static void periodic_matches_the_definition(const vi_profile *p, const double *x, const double *h, size_t n, double r,
                                            const double *centres, int nc, double w)
{
    double L = x[n - 1] - x[0], far = fmax(fabs(x[0]), fabs(x[n - 1])), xu[16], hu[16];
    size_t nu = 0;
    for (int k = -1; k <= 1; k++)
        for (size_t i = (k == -1 ? 0 : 1); i < n; i++) xu[nu] = x[i] + k * L, hu[nu] = h[i], nu++;
    for (int c = 0; c < nc; c++)
        for (int k = 0; k <= 200; k++) {
            double at = centres[c] - w + 2.0 * w * k / 200.0, y[4], ref = brute(xu, hu, nu, r, at);
            vi_profile_eval(p, at, y);
            double tol = 1e-12 * r + 8.0 * DBL_EPSILON * far * (1.0 + fabs(y[1]));
            cr_assert(fabs(y[0] - ref) <= tol, "x %.17g: yb %.17g, by the definition %.17g (tol %g)", at, y[0], ref, tol);
        }
}

Test(profile, a_periodic_seam_rounded_apart_leaves_no_gap)
{
    double x[] = {-0.10166743402446966, -0.10158941869246281, 15.589183792583125, 28.067565743214107, 28.067587137412833};
    double h[] = {0.9832667256627543, 2.1718357294666744, 1.2396848249433958, 0.48296507517013931, 0.9832667256627543};
    double r = 1.9346202038855385e-07, centres[] = {x[4], x[0] + 2.0 * r};
    vi_profile *p = make(x, h, 5, r, 1);
    periodic_matches_the_definition(p, x, h, 5, r, centres, 2, 4.0 * r); /* the seam, and across the first wall */
    vi_profile_free(p);
}

/* A periodic table with a wall steeper than doubles resolve at its position: the body leaves the wall
 * R1/(hyp (hyp + |s|)) = 1.0e-15 m before its top, less than the spacing of doubles at x = 16.48
 * (2^-48 = 3.6e-15 m), so the envelope in doubles is vertical there. It is refused naming the rows,
 * the slope (1.1749 m over 48.7 um) and the slope doubles resolve there, sqrt(R1/(2 spacing)),
 * not as an internal error. */
Test(profile, a_wall_steeper_than_doubles_resolve_is_refused_naming_its_rows)
{
    double x[] = {-0.46331928351137353, 16.478735101136888, 16.478783788505101};
    double h[] = {3.3603288399901734, 2.1854535280021321, 3.3603288399901734};
    double r = 1.217226034797203e-06, s = (h[2] - h[1]) / (x[2] - x[1]), spacing = ldexp(1.0, -48);
    char expect[512];
    snprintf(expect, sizeof expect, "bad: rows 2 and 3 (x = 16.478735101136888 and 16.478783788505101 m) make a slope of "
             "%.6g, too steep for R1 = 1.21723e-06 m near x = 16.4788 m: the body leaves that segment %.2g m before its "
             "end, less than the spacing of doubles there (%.2g m), and yb is vertical; slopes up to about %.3g",
             s, r / (2.0 * s * s), spacing, sqrt(r / (2.0 * spacing)));
    refused(x, h, 3, r, 1, expect);
    /* the mirror image, one period on: the wall falls from the first row (the vertex at the seam, x = 16 m) */
    double xm[] = {16.0, 16.000048687368214, 32.942102687368212};
    refused(xm, h, 3, r, 1, "bad: rows 1 and 2 (x = 16 and 16.000048687368214 m) make a slope of -24131, too steep for "
                            "R1 = 1.21723e-06 m near x = 16 m");
    /* an open table whose wall rises into its second row: the segment into that vertex, rows 1 and 2 */
    double xo[] = {16.478735101136888, 16.478783788505101, 33.0}, ho[] = {2.1854535280021321, 3.3603288399901734, 3.3603288399901734};
    refused(xo, ho, 3, r, 0, "bad: rows 1 and 2 (x = 16.478735101136888 and 16.478783788505101 m) make a slope of 24131, "
                             "too steep for R1 = 1.21723e-06 m near x = 16.4788 m");
    /* 8 times the radius: 8e-15 m, above the spacing and the rounding of x, and it is rolled over */
    vi_profile *p = make(x, h, 3, 8.0 * r, 1);
    cr_assert(fabs(vi_profile_max_slope(p) - s) <= 1e-6 * s, "max slope %.17g, the wall's %.17g", vi_profile_max_slope(p), s);
    vi_profile_free(p);
}

/* A periodic table ending with a wall 0.35 m high and 4.6 um wide (slope -76770): at the seam the
 * wall's parallel is reached from x_last = 26.7 m on the left and from x_first = -0.0022 m on the
 * right, positions whose rounding differs by the spacing of doubles at 26.7 m (3.6e-15 m), times the
 * slope: 2e-10 m. That is the seam's rounding, no step (it was refused as one: the allowance took the
 * rounding at x_first); yb near the seam against the definition to the slope times that spacing. */
Test(profile, the_seam_of_a_periodic_table_is_rounded_at_its_last_row)
{
    double x[] = {-0.0022442443306763863, 6.6918654128405564, 23.857625585914416, 26.721692322158113, 26.721696926646633};
    double h[] = {0.089119036257788081, 2.5992689847942763, 1.9958331286887794, 0.44260680370154182, 0.089119036257788081};
    double r = 1.9593007941540804e-05, centres[] = {x[0], x[4]};
    vi_profile *p = make(x, h, 5, r, 1);
    periodic_matches_the_definition(p, x, h, 5, r, centres, 2, 2.0 * r);
    vi_profile_free(p);
}

/* A periodic table whose wall (slope 17026) rises to the seam with R1 = 1.95e-8 m: the body leaves
 * it R1/(2 s^2) = 3.4e-17 m before its top, more than the spacing of doubles at 0.153 m (2.8e-17 m),
 * so it is rolled over (it was refused as too steep: the last vertex of each copy, x_last + k L, and
 * the first of the next, x_first + (k + 1) L, were rounded apart by more than that). yb around the
 * seam against the definition, and the largest slope is the wall's, to the rounding of the corner. */
Test(profile, a_steep_wall_at_the_seam_that_doubles_resolve_is_rolled_over)
{
    double x[] = {-0.5347939573856042, 0.15301676567318712, 0.1530861505024072};
    double h[] = {2.5300901092263359, 1.3487220724805826, 2.5300901092263359};
    double r = 1.9527121758799592e-08, s = (h[2] - h[1]) / (x[2] - x[1]), centres[] = {x[2], x[1]};
    vi_profile *p = make(x, h, 3, r, 1);
    periodic_matches_the_definition(p, x, h, 3, r, centres, 2, 4.0 * r); /* the seam and the wall's foot */
    /* on the wall's parallel the slope is s; where the corner's circle takes over, its slope is s
     * to the rounding of that boundary, which moves R1 + u by the spacing: more there, by 4e-4 */
    cr_assert(vi_profile_max_slope(p) >= s && vi_profile_max_slope(p) <= 1.01 * s, "max slope %.17g, the wall's %.17g",
              vi_profile_max_slope(p), s);
    vi_profile_free(p);
}

/* A spline long enough that its arcs are not stored (more segments than STORED_ARCS_MAX, each touched
 * whole by the body): its largest slope is still the curve's, 2 pi A / lambda for a sinusoid of amplitude A
 * and wavelength lambda sampled 500 times a wavelength (the spline's slopes within 1e-6 of it). */
Test(profile, a_long_spline_of_whole_segments_keeps_its_largest_slope)
{
    enum { LONG = 16500 };
    static double xs[LONG], hs[LONG];
    const double A = 1e-5, lambda = 0.05, pi = 3.14159265358979323846, s = 2.0 * pi * A / lambda;
    for (int i = 0; i < LONG; i++) xs[i] = 1e-4 * i, hs[i] = A * cos(2.0 * pi * xs[i] / lambda);
    vi_profile *p = make_cubic(xs, hs, LONG, R, 0);
    cr_assert(fabs(vi_profile_max_slope(p) - s) <= 1e-6 * s, "max slope %.17g, the sinusoid's %.17g",
              vi_profile_max_slope(p), s);
    vi_profile_free(p);
}

/* A periodic table of three rows (two unknown slopes, solved in closed form) is C2 at both of its rows:
 * yb'' changes smoothly as the contact point passes each row (samples 1e-5 m apart on the centre's
 * path differ by at most 1e-4, where yb''' allows 2e-6), uneven rows so that no symmetry hides a
 * wrong slope. */
Test(profile, a_periodic_spline_of_three_rows_is_c2_at_both)
{
    double x[3] = {0.0, 0.07, 0.2}, h[3] = {1e-4, -5e-5, 1e-4};
    vi_profile *p = make_cubic(x, h, 3, R, 1);
    double knots[2] = {0.0, 0.07};
    for (int j = 0; j < 2; j++) {
        double prev[4], y[4], worst = 0.0;
        cr_assert(vi_profile_eval(p, knots[j] - 0.01, prev) == 0);
        for (int i = 1; i <= 2000; i++) {
            cr_assert(vi_profile_eval(p, knots[j] - 0.01 + 1e-5 * i, y) == 0);
            worst = fmax(worst, fabs(y[2] - prev[2]));
            memcpy(prev, y, sizeof y);
        }
        cr_assert(worst <= 1e-4, "row %d: yb'' jumps by %g", j, worst);
    }
    cr_assert_eq(vi_profile_kinks(p), 0);
    vi_profile_free(p);
}
