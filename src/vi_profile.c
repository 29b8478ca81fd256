/* vi_profile.c - the rolling constraint yb of a piecewise-linear profile; definitions in vi_profile.h. */
#include "vi_profile.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A piece of the envelope. Circle: yb = py - d^2/(R + sqrt(R^2 - d^2)), d = x - px (the vertex at
 * px, height py). Line: yb = py + s (x - px) (value py at the start px of its domain). */
typedef struct {
    int line;
    double px, py, s;
} piece;

struct vi_profile {
    double R, lo, hi, period; /* period = hi - lo when periodic, else 0 */
    int periodic;
    piece *pieces;
    size_t m;       /* intervals */
    double *xb;     /* m + 1 boundaries, xb[0] = lo, xb[m] = hi */
    int *pid;       /* m piece indices */
    double *kinks;  /* sorted kink positions in [lo, hi) */
    size_t n_kinks;
    double max_slope;
    double h_span; /* max h - min h of the table [m] */
};

/* ---- pieces -------------------------------------------------------------------------------- */

/* Value and derivatives of piece q at x (derivatives only when d is not NULL). */
static double piece_eval(const piece *q, double R, double x, double d[3])
{
    if (q->line) {
        if (d) d[0] = q->s, d[1] = 0.0, d[2] = 0.0;
        return q->py + q->s * (x - q->px);
    }
    double u = x - q->px, r2 = (R - u) * (R + u);
    if (r2 < 0.0) r2 = 0.0; /* rounding at the edge of the circle's domain */
    double root = sqrt(r2);
    if (d) {
        double k = R / root;
        d[0] = -u / root;
        d[1] = -k * k / root;
        d[2] = 3.0 * d[1] * u / r2;
    }
    return q->py - u * u / (R + root);
}

/* ---- envelopes: sorted, disjoint intervals [x0, x1) each carried by one piece ------------------ */

typedef struct {
    size_t n, cap;
    double *x0, *x1;
    int *id;
} envelope;

static void env_free(envelope *e)
{
    free(e->x0), free(e->x1), free(e->id);
    memset(e, 0, sizeof *e);
}

/* Append [a, b) carried by id, joining it to the last interval when that one ends at a with the
 * same piece. 0, or -1 when out of memory. */
static int env_push(envelope *e, double a, double b, int id)
{
    if (!(b > a)) return 0;
    if (e->n && e->id[e->n - 1] == id && e->x1[e->n - 1] == a) {
        e->x1[e->n - 1] = b;
        return 0;
    }
    if (e->n == e->cap) {
        size_t cap = e->cap ? 2 * e->cap : 16;
        double *x0 = realloc(e->x0, cap * sizeof *x0), *x1 = x0 ? realloc(e->x1, cap * sizeof *x1) : NULL;
        int *id_ = x1 ? realloc(e->id, cap * sizeof *id_) : NULL;
        if (x0) e->x0 = x0;
        if (x1) e->x1 = x1;
        if (id_) e->id = id_;
        if (!x0 || !x1 || !id_) return -1;
        e->cap = cap;
    }
    e->x0[e->n] = a, e->x1[e->n] = b, e->id[e->n] = id;
    e->n++;
    return 0;
}

typedef struct {
    const piece *pieces;
    double R;
    double tol; /* values closer than this count as equal (tangent pieces) */
} context;

static double gap(const context *c, int a, int b, double x)
{
    return piece_eval(&c->pieces[a], c->R, x, NULL) - piece_eval(&c->pieces[b], c->R, x, NULL);
}

/* The root of gap(a, b) in (lo, hi), where it changes sign strictly (bisection to the last bit,
 * at most 2100 halvings: more than the doubles between any two). */
static double bisect(const context *c, int a, int b, double lo, double hi, double glo)
{
    for (int it = 0; it < 2100; it++) {
        double mid = lo + 0.5 * (hi - lo);
        if (!(mid > lo && mid < hi)) break;
        double g = gap(c, a, b, mid);
        if ((g < 0.0) == (glo < 0.0) && g != 0.0) lo = mid, glo = g;
        else hi = mid;
    }
    return hi;
}

/* Crossings of pieces a and b strictly inside (u, v): at most two (the difference of two equal
 * circles is monotone, that of a circle and a line concave, that of two lines linear). */
static int crossings(const context *c, int a, int b, double u, double v, double r[2])
{
    const piece *pa = &c->pieces[a], *pb = &c->pieces[b];
    double cut[3] = {u, v, v};
    int nb = 1;
    if (pa->line != pb->line) { /* split at the extremum of the difference: the circle's slope = s */
        const piece *circle = pa->line ? pb : pa, *line = pa->line ? pa : pb;
        double xs = circle->px - line->s * c->R / hypot(1.0, line->s);
        double ext = gap(c, a, b, xs > u && xs < v ? xs : 0.5 * (u + v));
        if (xs > u && xs < v) {
            if (fabs(ext) <= c->tol) return 0; /* tangent: they touch, no crossing */
            cut[1] = xs, cut[2] = v, nb = 2;
        }
    }
    int n = 0;
    for (int k = 0; k < nb; k++) {
        double lo = cut[k], hi = cut[k + 1], glo = gap(c, a, b, lo), ghi = gap(c, a, b, hi);
        if (fabs(glo) <= c->tol || fabs(ghi) <= c->tol || (glo < 0.0) == (ghi < 0.0)) continue;
        r[n++] = bisect(c, a, b, lo, hi, glo);
    }
    return n;
}

/* Upper envelope of a and b on [u, v), appended to out. */
static int upper_of_two(const context *c, int a, int b, double u, double v, envelope *out)
{
    double r[2], cuts[4];
    int n = crossings(c, a, b, u, v, r), k = 0;
    cuts[k++] = u;
    for (int i = 0; i < n; i++)
        if (r[i] > cuts[k - 1] && r[i] < v) cuts[k++] = r[i];
    cuts[k++] = v;
    for (int i = 0; i + 1 < k; i++) {
        double mid = cuts[i] + 0.5 * (cuts[i + 1] - cuts[i]);
        if (env_push(out, cuts[i], cuts[i + 1], gap(c, a, b, mid) >= 0.0 ? a : b) < 0) return -1;
    }
    return 0;
}

/* The piece of e active at position x, advancing *i past intervals that end at or before x; -1 in a gap. */
static int active(const envelope *e, size_t *i, double x)
{
    while (*i < e->n && e->x1[*i] <= x) (*i)++;
    return *i < e->n && e->x0[*i] <= x ? e->id[*i] : -1;
}

/* The next boundary of e after x (INFINITY if none), with *i as left by active(). */
static double next_boundary(const envelope *e, size_t i, double x)
{
    if (i >= e->n) return INFINITY;
    return e->x0[i] > x ? e->x0[i] : e->x1[i];
}

static int env_merge(const context *c, const envelope *A, const envelope *B, envelope *out)
{
    size_t ia = 0, ib = 0;
    double u = fmin(A->n ? A->x0[0] : INFINITY, B->n ? B->x0[0] : INFINITY);
    /* every pass moves u to the next boundary of A or B: at most 2 (A->n + B->n) passes */
    for (size_t pass = 0; pass <= 2 * (A->n + B->n) && isfinite(u); pass++) {
        int pa = active(A, &ia, u), pb = active(B, &ib, u);
        double v = fmin(next_boundary(A, ia, u), next_boundary(B, ib, u));
        if (!isfinite(v)) break;
        int rc = 0;
        if (pa >= 0 && pb >= 0) rc = upper_of_two(c, pa, pb, u, v, out);
        else if (pa >= 0 || pb >= 0) rc = env_push(out, u, v, pa >= 0 ? pa : pb);
        if (rc < 0) return -1;
        u = v;
    }
    return 0;
}

/* Envelope of pieces [first, first + count), each on its domain [dom0, dom1). Recursion depth
 * log2(count). */
static int env_build(const context *c, const double *dom0, const double *dom1, int first, int count, envelope *out)
{
    if (count == 1) return env_push(out, dom0[first], dom1[first], first);
    envelope L = {0}, R = {0};
    int half = count / 2, rc = -1;
    if (env_build(c, dom0, dom1, first, half, &L) == 0 && env_build(c, dom0, dom1, first + half, count - half, &R) == 0)
        rc = env_merge(c, &L, &R, out);
    env_free(&L), env_free(&R);
    return rc;
}

/* ---- construction ------------------------------------------------------------------------- */

void vi_profile_free(vi_profile *p)
{
    if (!p) return;
    free(p->pieces), free(p->xb), free(p->pid), free(p->kinks);
    free(p);
}

#define FAIL(...)                                      \
    do {                                               \
        snprintf(msg, msg_size, __VA_ARGS__);          \
        goto fail;                                     \
    } while (0)

/* Candidate pieces of the envelope on [lo, hi], with their domains: the vertex circles (domain
 * |x - x_i| <= R) and the segment tangents (where the tangent point lies on the segment). A
 * periodic profile takes the copies of vertices and segments one period to each side whose domains
 * reach into [lo, hi]: the nearest copy of a vertex dominates the others. */
static int make_pieces(const double *x, const double *h, size_t n, double R, int periodic, piece **out, double **d0,
                       double **d1, int *count)
{
    size_t nv = periodic ? n - 1 : n, ns = n - 1, cap = 3 * nv + 3 * ns;
    double lo = x[0], hi = x[n - 1], L = periodic ? hi - lo : 0.0;
    piece *pc = malloc(cap * sizeof *pc);
    double *a = malloc(cap * sizeof *a), *b = malloc(cap * sizeof *b);
    if (!pc || !a || !b) {
        free(pc), free(a), free(b);
        return -1;
    }
    int k = 0;
    for (size_t i = 0; i < nv + ns; i++) {
        int line = i >= nv;
        size_t j = line ? i - nv : i;
        piece q = {line, x[j], h[j], 0.0};
        double from = x[j] - R, to = x[j] + R;
        if (line) {
            double s = (h[j + 1] - h[j]) / (x[j + 1] - x[j]), hyp = hypot(1.0, s), shift = R * (s / hyp);
            q.s = s;
            q.px = x[j] - shift;
            q.py = h[j] - R * (s * s / (hyp * (hyp + 1.0))); /* h_j + R (1/hyp - 1), without cancellation */
            from = q.px, to = x[j + 1] - shift;
        }
        /* copies: a vertex's nearest copy is one of k = -1, 0, 1; a tangent's domain (at most one
         * period wide, shifted by up to R) meets [lo, hi] for at most two consecutive k */
        double k0 = 0.0, k1 = 0.0;
        if (periodic) {
            k0 = line ? ceil((lo - to) / L) : -1.0;
            k1 = line ? k0 + 1.0 : 1.0;
        }
        for (double copy = k0; copy <= k1; copy += 1.0) {
            double off = copy * L, f = fmax(from + off, lo), t = fmin(to + off, hi);
            if (!(t > f)) continue;
            pc[k] = q;
            pc[k].px += off;
            a[k] = f, b[k] = t;
            k++;
        }
    }
    *out = pc, *d0 = a, *d1 = b, *count = k;
    return 0;
}

vi_profile *vi_profile_create(const double *x, const double *h, size_t n, double R, int periodic, const char *name,
                              char *msg, size_t msg_size)
{
    vi_profile *p = NULL;
    piece *pc = NULL;
    double *dom0 = NULL, *dom1 = NULL;
    envelope env = {0};
    int count = 0;
    if (!name) name = "profile";
    if (n < 2) FAIL("%s: %zu rows; a profile needs at least two (x [m], h [m])", name, n);
    if (!(R > 0.0 && isfinite(R))) FAIL("%s: the rolling radius R1 = %g m must be positive and finite", name, R);
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(h[i])) FAIL("%s, row %zu: x = %g, h = %g are not finite", name, i + 1, x[i], h[i]);
        if (i && !(x[i] > x[i - 1]))
            FAIL("%s, row %zu: x = %.17g is not greater than x = %.17g of the row before (x must increase)", name, i + 1,
                 x[i], x[i - 1]);
    }
    if (periodic && h[n - 1] != h[0])
        FAIL("%s: profile_periodic needs the last height to repeat the first (h = %.17g on row %zu, %.17g on row 1)",
             name, h[n - 1], n, h[0]);
    p = calloc(1, sizeof *p);
    if (!p) FAIL("%s: out of memory", name);
    p->R = R, p->lo = x[0], p->hi = x[n - 1], p->periodic = periodic != 0;
    p->period = periodic ? p->hi - p->lo : 0.0;
    if (make_pieces(x, h, n, R, p->periodic, &pc, &dom0, &dom1, &count) < 0) FAIL("%s: out of memory", name);
    double hmax = 0.0, hlo = h[0], hhi = h[0];
    for (size_t i = 0; i < n; i++) hmax = fmax(hmax, fabs(h[i])), hlo = fmin(hlo, h[i]), hhi = fmax(hhi, h[i]);
    p->h_span = hhi - hlo;
    context c = {pc, R, 64.0 * DBL_EPSILON * (R + hmax)};
    if (env_build(&c, dom0, dom1, 0, count, &env) < 0) FAIL("%s: out of memory", name);

    /* the envelope covers [lo, hi] without gaps (every point lies under a vertex circle or a tangent) */
    if (!env.n || env.x0[0] != p->lo || env.x1[env.n - 1] != p->hi)
        FAIL("%s: internal error: the envelope covers [%g, %g] instead of [%g, %g]", name, env.n ? env.x0[0] : NAN,
             env.n ? env.x1[env.n - 1] : NAN, p->lo, p->hi);
    p->m = env.n;
    p->xb = malloc((p->m + 1) * sizeof *p->xb);
    p->pid = malloc(p->m * sizeof *p->pid);
    p->kinks = malloc((p->m + 1) * sizeof *p->kinks);
    if (!p->xb || !p->pid || !p->kinks) FAIL("%s: out of memory", name);
    for (size_t j = 0; j < p->m; j++) {
        if (j && env.x0[j] != env.x1[j - 1]) FAIL("%s: internal error: a gap in the envelope at x = %g", name, env.x1[j - 1]);
        p->xb[j] = env.x0[j];
        p->pid[j] = env.id[j];
    }
    p->xb[p->m] = p->hi;
    /* continuity, slopes and kinks at the boundaries (a periodic profile also at the seam) */
    for (size_t j = 0; j <= p->m; j++) {
        double dl[3], dr[3], yl = NAN, yr = NAN; /* set before use (has_left, has_right); gcc -fsanitize cannot tell */
        int has_left = j > 0 || p->periodic, has_right = j < p->m || p->periodic;
        size_t jl = j > 0 ? j - 1 : p->m - 1, jr = j < p->m ? j : 0;
        double xl = j > 0 ? p->xb[j] : p->hi, xr = j < p->m ? p->xb[j] : p->lo;
        if (has_left) {
            yl = piece_eval(&pc[p->pid[jl]], R, xl, dl);
            if (!isfinite(yl) || !isfinite(dl[0]))
                FAIL("%s: the profile is too steep for R1 = %g m near x = %g m: the body cannot roll over it", name, R, xl);
            p->max_slope = fmax(p->max_slope, fabs(dl[0]));
        }
        if (has_right) {
            yr = piece_eval(&pc[p->pid[jr]], R, xr, dr);
            if (!isfinite(yr) || !isfinite(dr[0]))
                FAIL("%s: the profile is too steep for R1 = %g m near x = %g m: the body cannot roll over it", name, R, xr);
            p->max_slope = fmax(p->max_slope, fabs(dr[0]));
        }
        if (!has_left || !has_right) continue;
        if (fabs(yl - yr) > 1e3 * c.tol)
            FAIL("%s: a step of more than R1 = %g m near x = %g m: yb jumps by %g m there (the body cannot roll over it)",
                 name, R, xr, yr - yl);
        if (fabs(dr[0] - dl[0]) > VI_PROFILE_KINK_SLOPE && j < p->m) p->kinks[p->n_kinks++] = xr;
    }
    env_free(&env);
    free(dom0), free(dom1);
    p->pieces = pc;
    return p;
fail:
    env_free(&env);
    free(dom0), free(dom1), free(pc);
    vi_profile_free(p);
    return NULL;
}

/* Parse "x h" (whitespace, comma or semicolon between); 1 for a data row, 0 to skip, -1 for a bad row. */
static int parse_row(char *line, double *x, double *h)
{
    char *s = line;
    while (*s == ' ' || *s == '\t') s++;
    if (*s == '\0' || *s == '\n' || *s == '\r' || *s == '#') return 0;
    char *end;
    errno = 0;
    *x = strtod(s, &end);
    if (end == s) return -1;
    s = end;
    while (*s == ' ' || *s == '\t' || *s == ',' || *s == ';') s++;
    *h = strtod(s, &end);
    if (end == s) return -1;
    s = end;
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n') s++;
    return *s == '\0' ? 1 : -1;
}

vi_profile *vi_profile_load(const char *path, double R, int periodic, char *msg, size_t msg_size)
{
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(msg, msg_size, "profile_file '%s': cannot open it (%s)", path, strerror(errno));
        return NULL;
    }
    double *x = NULL, *h = NULL;
    size_t n = 0, cap = 0, line_no = 0;
    char line[VI_PROFILE_LINE_MAX];
    vi_profile *p = NULL;
    while (fgets(line, sizeof line, f)) { /* bounded by the file and VI_PROFILE_ROWS_MAX */
        line_no++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n' && !feof(f))
            FAIL("profile_file '%s', line %zu: longer than %d characters", path, line_no, VI_PROFILE_LINE_MAX - 2);
        double xv, hv;
        int rc = parse_row(line, &xv, &hv);
        if (rc == 0) continue;
        if (rc < 0) FAIL("profile_file '%s', line %zu: expected two numbers x [m] and h [m]", path, line_no);
        if (!isfinite(xv) || !isfinite(hv))
            FAIL("profile_file '%s', line %zu: x = %g, h = %g are not finite", path, line_no, xv, hv);
        if (n && !(xv > x[n - 1]))
            FAIL("profile_file '%s', line %zu: x = %.17g is not greater than x = %.17g before it (x must increase)", path,
                 line_no, xv, x[n - 1]);
        if (n == VI_PROFILE_ROWS_MAX) FAIL("profile_file '%s', line %zu: more than %d rows", path, line_no, VI_PROFILE_ROWS_MAX);
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            double *nx = realloc(x, cap * sizeof *nx), *nh = nx ? realloc(h, cap * sizeof *nh) : NULL;
            if (nx) x = nx;
            if (nh) h = nh;
            if (!nx || !nh) FAIL("profile_file '%s': out of memory at line %zu", path, line_no);
        }
        x[n] = xv, h[n] = hv;
        n++;
    }
    if (ferror(f)) FAIL("profile_file '%s': read error after line %zu", path, line_no);
    if (n < 2) FAIL("profile_file '%s': %zu data rows; a profile needs at least two (x [m], h [m])", path, n);
    char name[VI_PROFILE_LINE_MAX + 32];
    snprintf(name, sizeof name, "profile_file '%s'", path);
    p = vi_profile_create(x, h, n, R, periodic, name, msg, msg_size);
fail:
    fclose(f);
    free(x), free(h);
    return p;
}

/* ---- evaluation ----------------------------------------------------------------------------- */

/* x brought into [lo, hi): periodic wrap, or clamped (*outside set) */
static double reduce(const vi_profile *p, double x, int *outside)
{
    *outside = 0;
    if (p->periodic) {
        double r = fmod(x - p->lo, p->period);
        if (r < 0.0) r += p->period;
        r += p->lo;
        return r < p->hi ? r : p->lo;
    }
    if (x < p->lo || x > p->hi) *outside = 1;
    return fmin(fmax(x, p->lo), p->hi);
}

/* Interval holding x in [lo, hi]: the last j with xb[j] <= x (the right-hand piece at a boundary). */
static size_t interval(const vi_profile *p, double x)
{
    size_t a = 0, b = p->m; /* xb[a] <= x < xb[b] */
    while (b - a > 1) {     /* log2(m) halvings */
        size_t mid = a + (b - a) / 2;
        if (p->xb[mid] <= x) a = mid;
        else b = mid;
    }
    return a;
}

int vi_profile_eval(const vi_profile *p, double x, double y[4])
{
    int outside;
    double r = reduce(p, x, &outside);
    y[0] = piece_eval(&p->pieces[p->pid[interval(p, r)]], p->R, r, y + 1);
    return outside ? -1 : 0;
}

double vi_profile_next_kink(const vi_profile *p, double x, int dir)
{
    double none = dir > 0 ? INFINITY : -INFINITY;
    if (!p->n_kinks || !isfinite(x)) return none;
    double base = 0.0, r = x;
    if (p->periodic) {
        base = floor((x - p->lo) / p->period) * p->period;
        r = x - base;
    }
    /* a kink within rounding of r (positions of other periods are not exact) is the one at x */
    double tol = 8.0 * DBL_EPSILON * (fabs(x) + p->period);
    double from = dir > 0 ? r + tol : r - tol;
    size_t a = 0, b = p->n_kinks; /* binary search: the first index with kinks[i] > from */
    while (a < b) {
        size_t mid = a + (b - a) / 2;
        if (p->kinks[mid] > from) b = mid;
        else a = mid + 1;
    }
    if (dir > 0) {
        if (a < p->n_kinks) return base + p->kinks[a];
        return p->periodic ? base + p->period + p->kinks[0] : none;
    }
    size_t i = a; /* kinks[i - 1] <= from: step back over one equal to it */
    if (i > 0 && p->kinks[i - 1] >= from) i--;
    if (i > 0) return base + p->kinks[i - 1];
    return p->periodic ? base - p->period + p->kinks[p->n_kinks - 1] : none;
}

double vi_profile_x_first(const vi_profile *p) { return p->lo; }
double vi_profile_x_last(const vi_profile *p) { return p->hi; }
int vi_profile_periodic(const vi_profile *p) { return p->periodic; }
double vi_profile_max_slope(const vi_profile *p) { return p->max_slope; }
double vi_profile_height_span(const vi_profile *p) { return p->h_span; }
size_t vi_profile_kinks(const vi_profile *p) { return p->n_kinks; }
