/* vi_profile.c - the rolling constraint yb of a piecewise-linear or cubic-spline profile; definitions in
 * vi_profile.h. */
#include "vi_profile.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vi_check.h"
#include "vi_text.h"

#ifdef _WIN32
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#endif

/* A piece of the envelope. Circle: yb = py - d^2/(R + sqrt(R^2 - d^2)), d = x - px (the vertex at
 * px, height py). Line: yb = py + s (x - px) (value py at the start px of its domain). Arc: the
 * offset of part arc of a spline segment whose first row lies at px (arc_eval). */
enum { CIRCLE, LINE, ARC };
/* The most arcs a profile may have: their index fits in piece's 30 bits. */
#define ARCS_MAX (1u << 30)
typedef struct {
    double px, py, s;
    unsigned arc : 30; /* ARC: index into the profile's arcs; LINE: 1 + the index of its slope s in the
                        * profile's slopes once an interval holds the piece (push), 0 before */
    unsigned kind : 2;
    uint32_t g; /* in an interval: its place in the order of the profile (insert): 2 i the circle of vertex i,
                 * 2 i + 1 the tangent of segment i; below 2^32 (at most VI_PROFILE_ROWS_MAX rows and their
                 * arcs on the copies in reach, periodic_copies) */
} piece;

/* The part of a spline segment the body may touch (1 - R curvature > 0 there): h = c0 + c1 u +
 * c2 u^2 + c3 u^3 on u = s - (the segment's first row) in [u0, u1]; starts, ends: u0 is the segment's
 * first row, u1 its last. */
typedef struct {
    double c[4], u0, u1;
    int starts, ends;
} arc;

/* The arcs of a cubic profile: stored (list), or, when every segment of the spline is one whole arc
 * (list NULL), none stored: arc i is then segment i whole, its cubic computed from the rows x, h and
 * the spline's slopes k (arc_at) as make_arcs computes it, to the bit. */
typedef struct {
    const arc *list;
    const double *x, *h, *k;
} arc_set;

/* The slopes s of the lines that carry intervals of the envelope. */
typedef struct {
    double *v;
    size_t n, cap;
} slope_list;

/* An interval [x0, x1) of the envelope and its piece: px, py, arc (for a line the reference of its
 * slope), kind and place g of the piece (piece_at gives the piece back). */
typedef struct {
    double x0, x1; /* [x0, x1) */
    double px, py;
    unsigned arc : 30, kind : 2;
    uint32_t g;
} span;

struct vi_profile {
    double R, lo, hi, period; /* period = hi - lo when periodic, else 0 */
    int periodic;
    span *spans;    /* m intervals, spans[0].x0 = lo, spans[m - 1].x1 = hi, each ending where the next starts */
    slope_list sl;  /* the slopes of their lines */
    arc_set arcs;   /* the spline's parts (cubic interpolation), n_arcs of them */
    size_t n_arcs;
    arc *arc_list;  /* the memory the profile owns behind arcs: the stored arcs, or the rows and slopes */
    double *own_x, *own_h, *own_k;
    size_t m;       /* intervals */
    size_t *bucket; /* n_buckets + 1 entries, or NULL: where the search for x starts (index_intervals) */
    size_t n_buckets;
    double bucket_scale; /* buckets per metre */
    double *kinks;  /* sorted kink positions in [lo, hi) */
    size_t n_kinks;
    double max_slope;
    double h_span; /* max h - min h of the table [m] */
};

/* fmax and fmin as the C library's are on x86-64 (of two equal numbers, such as 0 and -0, the second; a
 * NaN loses to a number), inlined: the loops over the rows call them per row. */
static double larger(double a, double b) { return a > b || b != b ? a : b; }
static double smaller(double a, double b) { return a < b || b != b ? a : b; }

/* ---- pieces -------------------------------------------------------------------------------- */

/* The centre's shift along x from the contact point of slope s: -R s/sqrt(1 + s^2) (s^2 would overflow
 * beyond 1e154: there the root is |s| to the last bit). */
static double centre_shift(double R, double s) { return -R * (s / (fabs(s) < 1e100 ? sqrt(1.0 + s * s) : fabs(s))); }

/* X(u) - (the first row) on arc a: the position of the centre of the body touching it at u. */
static double arc_centre(const arc *a, double R, double u)
{
    const double *c = a->c;
    return u + centre_shift(R, c[1] + u * (2.0 * c[2] + 3.0 * c[3] * u));
}

/* The position u in [a->u0, a->u1] where the body centred above x touches arc a (first row at px):
 * the root of X(u) - target = u - R h'/sqrt(1 + h'^2) - target, target = x - px, increasing in u on
 * the arc; an end when target is within slack (the rounding of x - px) of that end's X; else Newton's
 * method from the linear guess between the ends' X, kept inside the bracket by bisection (at most 80 passes, ending when
 * a pass moves u by less than 4 eps of the segment). */
static double arc_root(const arc *a, double R, double target, double slack)
{
    const double *c = a->c;
    double lo = a->u0, hi = a->u1;
    double X0 = arc_centre(a, R, lo);
    if (!(target > X0 + slack)) return lo;
    double X1 = arc_centre(a, R, hi);
    if (!(target < X1 - slack)) return hi;
    double u = lo + (hi - lo) * ((target - X0) / (X1 - X0)), tiny = 4.0 * DBL_EPSILON * (fabs(lo) + fabs(hi));
    for (int it = 0; it < 80; it++) {
        double h1 = c[1] + u * (2.0 * c[2] + 3.0 * c[3] * u), h2 = 2.0 * c[2] + 6.0 * c[3] * u;
        double w = 1.0 + h1 * h1, rw = sqrt(w);
        double F = u - R * h1 / rw - target, dF = 1.0 - R * h2 / (w * rw);
        if (F == 0.0) return u;
        if (F > 0.0) hi = u;
        else lo = u;
        double next = u - F / dF;
        if (!(next > lo && next < hi)) next = lo + 0.5 * (hi - lo);
        if (fabs(next - u) <= tiny) return next;
        u = next;
    }
    return u;
}

/* Value and derivatives of the offset of arc a (first row at px) at x (vi_profile.h: yb = h + R
 * (1/sqrt(w) - 1), yb' = h', yb'' = h''/X', yb''' = (h''' X' - h'' X'')/X'^3). */
static double arc_eval(const arc *a, double R, double px, double x, double d[3])
{
    const double *c = a->c;
    double u = arc_root(a, R, x - px, 4.0 * DBL_EPSILON * fabs(x));
    double h1 = c[1] + u * (2.0 * c[2] + 3.0 * c[3] * u), w = 1.0 + h1 * h1, rw = sqrt(w);
    if (d) {
        double h2 = 2.0 * c[2] + 6.0 * c[3] * u, h3 = 6.0 * c[3];
        double X1 = 1.0 - R * h2 / (w * rw), X2 = -R * (h3 - 3.0 * h1 * h2 * h2 / w) / (w * rw);
        d[0] = h1;
        d[1] = h2 / X1;
        d[2] = (h3 * X1 - h2 * X2) / (X1 * X1 * X1);
    }
    return c[0] + u * (c[1] + u * (c[2] + u * c[3])) - R * (h1 * h1 / (rw * (rw + 1.0)));
}

/* The Hermite cubic of segment j of the spline through rows x, h with slopes k: c[0..3] in u = s - x_j;
 * the segment's length dx returned. */
static double segment_cubic(const double *x, const double *h, const double *k, size_t j, double c[4])
{
    double dx = x[j + 1] - x[j], d = (h[j + 1] - h[j]) / dx;
    c[0] = h[j], c[1] = k[j], c[2] = (3.0 * d - 2.0 * k[j] - k[j + 1]) / dx;
    c[3] = (k[j] + k[j + 1] - 2.0 * d) / (dx * dx);
    return dx;
}

/* Arc i of set: the stored one, or segment i whole, written into tmp. */
static const arc *arc_at(const arc_set *set, size_t i, arc *tmp)
{
    if (set->list) return &set->list[i];
    double dx = segment_cubic(set->x, set->h, set->k, i, tmp->c);
    tmp->u0 = 0.0, tmp->u1 = dx, tmp->starts = 1, tmp->ends = 1;
    return tmp;
}

/* Value and derivatives of piece q at x (derivatives only when d is not NULL); arcs: the profile's. */
static double piece_eval(const piece *q, const arc_set *arcs, double R, double x, double d[3])
{
    if (q->kind == ARC && arcs->list) return arc_eval(&arcs->list[q->arc], R, q->px, x, d);
    if (q->kind == ARC) {
        arc tmp;
        return arc_eval(arc_at(arcs, q->arc, &tmp), R, q->px, x, d);
    }
    if (q->kind == LINE) {
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

/* ---- the envelope, built in one pass ------------------------------------------------------------
 *
 * The body's contact point s(x) never moves backwards along the profile: h(s) + sqrt(R^2 - (x - s)^2)
 * has increasing differences in (x, s) (sqrt(R^2 - u^2) is concave), so its maximiser is nondecreasing
 * in x. Taken in the order of the profile (circle of vertex 0, tangent of segment 0, circle of vertex
 * 1, ...), the pieces therefore appear on the envelope in that order, each on one interval; and a
 * new piece q beats the envelope of the pieces before it on one interval that ends where q's domain
 * ends. Inserting q pops from a stack the intervals it wins whole, cuts the one it wins in part and
 * pushes its own: every interval is pushed and popped at most once, so the construction is linear
 * in the rows. Intervals of earlier pieces beyond q's domain (a circle that reaches further than the
 * next tangent) are set aside and put back. A vertex circle and the tangent of a segment at that
 * vertex meet where the tangent's domain starts or ends (the tangent is the higher inside its
 * domain); such neighbours are not compared numerically, so the switch between them is exact. */

typedef struct {
    span *s;
    size_t n, cap;
    slope_list *sl; /* the slopes of the lines its intervals carry (shared with the tail's) */
} stack;

/* The piece of interval t, the slopes of whose lines are sl. */
static piece piece_at(const slope_list *sl, const span *t)
{
    piece q = {.px = t->px, .py = t->py, .arc = t->arc, .kind = t->kind, .g = t->g};
    if (t->kind == LINE) q.s = sl->v[t->arc - 1];
    return q;
}

/* The interval t of piece q at place g (its bounds set by push). */
static span piece_span(const piece *q, size_t g)
{
    return (span){0.0, 0.0, q->px, q->py, q->arc, q->kind, (uint32_t)g};
}

/* The slope of t's piece q, a line not yet held by an interval, into sl (t->arc refers to it). 0, or -1
 * when out of memory. */
static int add_slope(slope_list *sl, span *t, const piece *q)
{
    if (sl->n == sl->cap) {
        size_t cap = sl->cap ? 2 * sl->cap : 256;
        double *v = cap < ARCS_MAX ? realloc(sl->v, cap * sizeof *v) : NULL;
        if (!v) return -1;
        sl->v = v, sl->cap = cap;
    }
    sl->v[sl->n++] = q->s;
    t->arc = (unsigned)sl->n;
    return 0;
}

/* Push [x0, x1) carried by t's piece (joined to the top when that is the same piece and ends at x0);
 * q: that piece when it is new (piece_span), else NULL. 0, or -1 when out of memory. */
static int push(stack *st, double x0, double x1, const span *t, const piece *q)
{
    if (!(x1 > x0)) return 0;
    if (st->n && st->s[st->n - 1].g == t->g && st->s[st->n - 1].x1 == x0) {
        st->s[st->n - 1].x1 = x1;
        return 0;
    }
    if (st->n == st->cap) {
        size_t cap = st->cap ? 2 * st->cap : 256;
        span *s = realloc(st->s, cap * sizeof *s);
        if (!s) return -1;
        st->s = s, st->cap = cap;
    }
    st->s[st->n] = *t, st->s[st->n].x0 = x0, st->s[st->n].x1 = x1;
    if (q && q->kind == LINE && !q->arc && add_slope(st->sl, &st->s[st->n], q) < 0) return -1;
    st->n++;
    return 0;
}

typedef struct {
    double R;
    double tol; /* values closer than this count as equal (the continuity check) */
    arc_set arcs;
} context;

static double gap(const context *c, const piece *a, const piece *b, double x)
{
    return piece_eval(a, &c->arcs, c->R, x, NULL) - piece_eval(b, &c->arcs, c->R, x, NULL);
}

/* The root of gap(a, b) in (lo, hi), where it changes sign strictly (bisection to the last bit,
 * at most 2100 halvings: more than the doubles between any two). */
static double bisect(const context *c, const piece *a, const piece *b, double lo, double hi, double glo)
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

/* A root in [w, v] of the equation piece a = piece b, in closed form; NAN when none is found there or
 * the form does not decide (two roots in the bracket). */
static double closed_form(double R, const piece *a, const piece *b, double w, double v)
{
    double r1 = NAN, r2 = NAN;
    if (a->kind == ARC || b->kind == ARC) return NAN; /* no closed form: bisection */
    if (a->kind == CIRCLE && b->kind == CIRCLE) { /* equal circles: the upper crossing on the bisector of the vertices */
        double dx = b->px - a->px, dy = b->py - a->py, d = hypot(dx, dy);
        if (!(dx > 0.0) || !(d < 2.0 * R)) return NAN;
        r1 = a->px + 0.5 * dx - dy / d * sqrt((R - 0.5 * d) * (R + 0.5 * d));
    } else if (a->kind == LINE && b->kind == LINE) { /* two lines */
        r1 = a->px + (b->py - a->py + b->s * (a->px - b->px)) / (a->s - b->s);
    } else { /* circle (px, py) and line: with u = x - px, sqrt(R^2 - u^2) = A + s u, A = R + e */
        const piece *cq = a->kind == LINE ? b : a, *lq = a->kind == LINE ? a : b;
        double s = lq->s, e = lq->py + s * (cq->px - lq->px) - cq->py; /* the line above the vertex */
        double hyp = hypot(1.0, s), A = R + e;
        double disc = (R * (s * s / (hyp + 1.0)) - e) * (hyp * R + A); /* (1 + s^2) R^2 - A^2 */
        if (!(disc >= 0.0)) return NAN;
        double k = 1.0 + s * s, t = -(A * s + copysign(sqrt(disc), A * s)); /* u1 = t / k, u1 u2 = e (2R + e) / k */
        double u1 = t / k, u2 = t != 0.0 ? e * (2.0 * R + e) / t : NAN;
        if (A + s * u1 >= 0.0) r1 = cq->px + u1;
        if (A + s * u2 >= 0.0) r2 = cq->px + u2;
    }
    int in1 = r1 >= w && r1 <= v, in2 = r2 >= w && r2 <= v;
    return in1 == in2 ? NAN : in1 ? r1 : r2;
}

/* Where q (after p in the profile) takes over from p in [w, v]: gap(p, q) >= 0 at w, < 0 at v. */
static double crossing(const context *c, const piece *p, const piece *q, double w, double v)
{
    double r = closed_form(c->R, p, q, w, v);
    return r == r ? r : bisect(c, p, q, w, v, gap(c, p, q, w));
}

/* Where q takes over from the piece of interval t (its line's slope in sl) in [w, start]: w when q is
 * above there, start when q is not above at start, else where they cross. */
static double takeover(const context *c, const slope_list *sl, const span *t, const piece *q, double w, double start)
{
    piece tq = piece_at(sl, t);
    if (gap(c, &tq, q, w) < 0.0) return w;
    if (gap(c, &tq, q, start) >= 0.0) return start;
    return crossing(c, &tq, q, w, start);
}

/* Pop the top interval of st; the slope of its line with it when that is the last slope and no
 * interval set aside in tail holds the same line. No other interval of the stack holds it then: a
 * line is split in two only by a piece inserted after it whose domain ends before its own (insert's
 * tail); a later line would hold a later slope, and no later circle ends first (circle i ends at
 * x_i + R, at or beyond the end x_j+1 - shift_j of tangent j < i, rounded the same way). */
static void drop_top(stack *st, const stack *tail)
{
    const span *t = &st->s[--st->n];
    if (t->kind != LINE || t->arc != st->sl->n) return;
    for (size_t i = 0; i < tail->n; i++) /* bounded by the tail */
        if (tail->s[i].kind == LINE && tail->s[i].arc == t->arc) return;
    st->sl->n--;
}

/* Add piece q (place g in the order of the profile) on its domain [a, b) to the envelope of the
 * pieces before it. tail: scratch for what lies beyond b. 0, or -1 when out of memory. */
static int insert(const context *c, stack *st, stack *tail, const piece *q, size_t g, double a, double b)
{
    if (!(b > a)) return 0;
    tail->n = 0;
    while (st->n && st->s[st->n - 1].x0 >= b) { /* bounded by the stack */
        span *t = &st->s[--st->n];
        if (push(tail, t->x0, t->x1, t, NULL) < 0) return -1;
    }
    if (st->n && st->s[st->n - 1].x1 > b) {
        span *t = &st->s[st->n - 1];
        if (push(tail, b, t->x1, t, NULL) < 0) return -1;
        t->x1 = b;
    }
    /* q holds [start, b); where nothing lies yet it wins */
    double start = !st->n ? a : larger(a, smaller(b, st->s[st->n - 1].x1));
    while (st->n) { /* bounded by the stack: every pass pops an interval or ends */
        span *t = &st->s[st->n - 1];
        if (t->x1 != start || !(start > a)) break;
        double w = larger(t->x0, a), from; /* q wins on [from, start) */
        if ((size_t)t->g + 1 == g) /* neighbours: a tangent wins inside its domain */
            from = (g & 1u) ? w : start;
        else
            from = takeover(c, st->sl, t, q, w, start);
        if (from > w) {
            t->x1 = from;
            start = from;
            break;
        }
        start = w;
        if (t->x0 < a) {
            t->x1 = a;
            break;
        }
        drop_top(st, tail);
    }
    span sq = piece_span(q, g);
    if (push(st, start, b, &sq, q) < 0) return -1;
    while (tail->n) { /* bounded by the tail */
        span *t = &tail->s[--tail->n];
        if (push(st, t->x0, t->x1, t, NULL) < 0) return -1;
    }
    return 0;
}

/* ---- construction ------------------------------------------------------------------------- */

void vi_profile_free(vi_profile *p)
{
    if (!p) return;
    free(p->spans), free(p->sl.v), free(p->kinks), free(p->arc_list), free(p->bucket);
    free(p->own_x), free(p->own_h), free(p->own_k);
    free(p);
}

#define FAIL(...)                                      \
    do {                                               \
        vi_snprintf(msg, msg_size, __VA_ARGS__);       \
        goto fail;                                     \
    } while (0)

/* Vertex j of copy k of the table: x_j + k L. A periodic table's last vertex is the first of the next
 * copy, and it is computed as that one (x_0 + (k + 1) L): the tangent of the last segment then ends
 * where the next copy's first vertex circle starts, or after it, to the bit (in exact arithmetic
 * x_n-1 + k L = x_0 + (k + 1) L, but not after rounding). */
static double vertex_x(const double *x, size_t n, int periodic, double period, size_t j, long k)
{
    if (periodic && j == n - 1) return x[0] + (double)(k + 1) * period;
    return x[j] + (double)k * period;
}

/* The envelope on [lo, hi] of the vertex circles (domain |x - x_i| <= R) and the segment tangents
 * (where the tangent point lies on the segment), taken in the order of the profile. A periodic
 * profile is unrolled: the copies of the table one period apart, from the last vertex more than R
 * before lo to the first more than R after hi (copies kmin .. kmax). The domains chain without a
 * gap: with v_j the vertex and shift = R s/sqrt(1 + s^2) (|shift| <= R), circle j's domain starts at
 * v_j - R <= v_j - shift_j-1, where tangent j-1's ends, and tangent j's starts at v_j - shift_j <=
 * v_j + R, where circle j's ends; both sides are rounded from the same v_j, and rounding keeps the
 * order. 0, or -1 when out of memory. */
static int build(const context *c, const double *x, const double *h, size_t n, int periodic, double lo, double hi,
                 long kmin, long kmax, stack *st)
{
    double R = c->R, period = periodic ? hi - lo : 0.0;
    size_t n_vertices = periodic ? n - 1 : n, g = 0;
    stack tail = {.sl = st->sl};
    int rc = 0;
    for (long k = kmin; k <= kmax && rc == 0; k++) { /* bounded: kmax - kmin + 1 copies of n rows */
        for (size_t j = 0; j < n_vertices && rc == 0; j++, g += 2) {
            double v = vertex_x(x, n, periodic, period, j, k);
            piece circle = {.px = v, .py = h[j], .kind = CIRCLE};
            rc = insert(c, st, &tail, &circle, g, larger(v - R, lo), smaller(v + R, hi));
            if (rc < 0 || j + 1 >= n) break;
            double slope = (h[j + 1] - h[j]) / (x[j + 1] - x[j]), hyp = hypot(1.0, slope), shift = R * (slope / hyp);
            double next = vertex_x(x, n, periodic, period, j + 1, k);
            /* the tangent's height at its vertex: h_j + R (1/hyp - 1) */
            piece tangent = {.px = v - shift, .py = h[j] - R * (slope * slope / (hyp * (hyp + 1.0))), .s = slope,
                             .kind = LINE};
            rc = insert(c, st, &tail, &tangent, g + 1, larger(tangent.px, lo), smaller(next - shift, hi));
        }
    }
    free(tail.s);
    return rc;
}

/* ---- the cubic spline through the rows ------------------------------------------------------
 *
 * The slopes k_i at the rows make the spline C2 where, for each inner row i (dx_i = x_(i+1) - x_i,
 * d_i = (h_(i+1) - h_i)/dx_i),
 *
 *   dx_i k_(i-1) + 2 (dx_(i-1) + dx_i) k_i + dx_(i-1) k_(i+1) = 3 (dx_i d_(i-1) + dx_(i-1) d_i);
 *
 * a periodic table closes the system cyclically (row 0 is the inner row between the last segment
 * and the first, k_(n-1) = k_0); an open one by not-a-knot ends, h''' continuous at rows 1 and n-2,
 * which with the row beside them reads (D = dx_0 + dx_1)
 *
 *   dx_1 k_0 + D k_1 = ((dx_0 + 2 D) dx_1 d_0 + dx_0^2 d_1) / D
 *
 * and its mirror image at the other end. Segment i is then the Hermite cubic of h_i, h_(i+1), k_i,
 * k_(i+1): c2 = (3 d_i - 2 k_i - k_(i+1))/dx_i, c3 = (k_i + k_(i+1) - 2 d_i)/dx_i^2. */

/* Row i of the system: coefficients of k_(i-1), k_i, k_(i+1) and the right-hand side, into e[4]. m: the
 * unknowns (n - 1 periodic, indices cyclic; n open, m >= 4). */
static void spline_row(const double *x, const double *h, size_t m, int periodic, size_t i, double e[4])
{
    size_t last = m - 1, p = i ? i - 1 : last, q = i; /* segments before and after row i (periodic) */
    if (!periodic && (i == 0 || i == last)) {
        size_t a = i == 0 ? 0 : last - 2, b = a + 1; /* the two end segments */
        double da = x[a + 1] - x[a], db = x[b + 1] - x[b], D = da + db;
        double sa = (h[a + 1] - h[a]) / da, sb = (h[b + 1] - h[b]) / db;
        if (i == 0) e[0] = 0.0, e[1] = db, e[2] = D, e[3] = ((da + 2.0 * D) * db * sa + da * da * sb) / D;
        else e[0] = D, e[1] = da, e[2] = 0.0, e[3] = (db * db * sa + (db + 2.0 * D) * da * sb) / D;
        return;
    }
    double dp = x[p + 1] - x[p], dq = x[q + 1] - x[q];
    e[0] = dq, e[1] = 2.0 * (dp + dq), e[2] = dp;
    e[3] = 3.0 * (dq * (h[p + 1] - h[p]) / dp + dp * (h[q + 1] - h[q]) / dq);
}

/* Forward elimination of the tridiagonal part of the system (Thomas): cp[i] = the multiplier of
 * k_(i+1), rp = the reduced right-hand side of the system's own, and (z not NULL) z reduced in place
 * as a second right-hand side. The first diagonal entry is b0 (the cyclic correction changes it),
 * the last one's change is b_last. */
static void eliminate(const double *x, const double *h, size_t m, int periodic, double b0, double b_last, double *cp,
                      double *rp, double *z)
{
    double e[4];
    for (size_t i = 0; i < m; i++) { /* bounded by the rows */
        spline_row(x, h, m, periodic, i, e);
        double b = i == 0 ? b0 : e[1] - (i == m - 1 ? b_last : 0.0);
        double piv = i == 0 ? b : b - e[0] * cp[i - 1];
        cp[i] = e[2] / piv;
        rp[i] = (i == 0 ? e[3] : e[3] - e[0] * rp[i - 1]) / piv;
        if (z) z[i] = (i == 0 ? z[i] : z[i] - e[0] * z[i - 1]) / piv;
    }
}

/* Back substitution into k and (z not NULL) z, which hold the reduced right-hand sides on entry; the two
 * in one pass, their chains of operations side by side. */
static void back_substitute(size_t m, const double *cp, double *k, double *z)
{
    if (!z)
        for (size_t i = m - 1; i-- > 0;) k[i] -= cp[i] * k[i + 1]; /* bounded by the rows */
    else
        for (size_t i = m - 1; i-- > 0;) k[i] -= cp[i] * k[i + 1], z[i] -= cp[i] * z[i + 1]; /* bounded by the rows */
}

/* The slopes k[0..n-1] of the spline through the n >= 2 rows (periodic: k[n-1] = k[0]; open: two
 * rows give the line, three the parabola). scratch: 2 n doubles. */
static void spline_slopes(const double *x, const double *h, size_t n, int periodic, double *k, double *scratch)
{
    double d0 = (h[1] - h[0]) / (x[1] - x[0]), e[4], f[4];
    if (n == 2) {
        k[0] = k[1] = periodic ? 0.0 : d0;
        return;
    }
    if (!periodic && n == 3) { /* the parabola h0 + d0 (x - x0) + c (x - x0)(x - x1) */
        double dx0 = x[1] - x[0], dx1 = x[2] - x[1], c = ((h[2] - h[1]) / dx1 - d0) / (dx0 + dx1);
        k[0] = d0 - c * dx0, k[1] = d0 + c * dx0, k[2] = d0 + c * (dx0 + 2.0 * dx1);
        return;
    }
    size_t m = periodic ? n - 1 : n;
    double *cp = scratch, *z = scratch + n;
    if (periodic && m == 2) { /* two unknowns, both neighbours of each row the other one */
        spline_row(x, h, m, 1, 0, e), spline_row(x, h, m, 1, 1, f);
        double det = e[1] * f[1] - (e[0] + e[2]) * (f[0] + f[2]);
        k[0] = (e[3] * f[1] - (e[0] + e[2]) * f[3]) / det;
        k[1] = (e[1] * f[3] - (f[0] + f[2]) * e[3]) / det;
    } else if (periodic) { /* Sherman-Morrison: the corners beta (row 0) and alpha (row m-1) as a rank-one term */
        spline_row(x, h, m, 1, 0, e), spline_row(x, h, m, 1, m - 1, f);
        double beta = e[0], alpha = f[2], gamma = -e[1];
        for (size_t i = 0; i < m; i++) z[i] = 0.0; /* bounded by the rows */
        z[0] = gamma, z[m - 1] = alpha;
        eliminate(x, h, m, 1, e[1] - gamma, alpha * beta / gamma, cp, k, z);
        back_substitute(m, cp, k, z);
        double fact = (k[0] + beta * k[m - 1] / gamma) / (1.0 + z[0] + beta * z[m - 1] / gamma);
        for (size_t i = 0; i < m; i++) k[i] -= fact * z[i]; /* bounded by the rows */
    } else {
        spline_row(x, h, m, 0, 0, e);
        eliminate(x, h, m, 0, e[1], 0.0, cp, k, NULL);
        back_substitute(m, cp, k, NULL);
    }
    if (periodic) k[n - 1] = k[0];
}

/* ---- the spline's offsets: arcs -------------------------------------------------------------- */

/* 1 - R times the curvature of cubic c at u: X'(u), positive where the body may touch. */
static double touch(const double c[4], double R, double u)
{
    double h1 = c[1] + u * (2.0 * c[2] + 3.0 * c[3] * u), w = 1.0 + h1 * h1;
    return 1.0 - R * (2.0 * c[2] + 6.0 * c[3] * u) / (w * sqrt(w));
}

typedef struct {
    arc *a;
    size_t n, cap;
    double max_slope;
} arcs;

/* The largest |h'| of cubic c on [u0, u1]: at the ends or where h' is stationary. */
static double arc_slope(const double c[4], double u0, double u1)
{
    double s0 = c[1] + u0 * (2.0 * c[2] + 3.0 * c[3] * u0), s1 = c[1] + u1 * (2.0 * c[2] + 3.0 * c[3] * u1);
    double um = c[3] != 0.0 ? -c[2] / (3.0 * c[3]) : u0; /* where h' is stationary */
    double sm = um > u0 && um < u1 ? c[1] + um * (2.0 * c[2] + 3.0 * c[3] * um) : s0;
    return larger(fabs(sm), larger(fabs(s0), fabs(s1)));
}

/* Append the part [u0, u1] of segment cubic c on [0, dx] as an arc (its largest |h'| into max_slope).
 * 0, or -1 when out of memory or past ARCS_MAX arcs. */
static int add_arc(arcs *list, const double c[4], double dx, double u0, double u1)
{
    if (!(u1 > u0)) return 0;
    if (list->n == list->cap) {
        size_t cap = list->cap ? 2 * list->cap : 256;
        arc *a = cap <= ARCS_MAX ? realloc(list->a, cap * sizeof *a) : NULL;
        if (!a) return -1;
        list->a = a, list->cap = cap;
    }
    list->max_slope = larger(list->max_slope, arc_slope(c, u0, u1));
    list->a[list->n++] = (arc){{c[0], c[1], c[2], c[3]}, u0, u1, u0 == 0.0, u1 == dx};
    return 0;
}

/* The body touches segment cubic c on [0, dx] everywhere: R h'' < 1 at both ends (h'' is linear, w >= 1). */
static int whole_arc(double R, const double c[4], double dx)
{
    return R * larger(2.0 * c[2], 2.0 * c[2] + 6.0 * c[3] * dx) < 1.0;
}

/* Where touch changes sign in (lo, hi), to the last bit (at most 2100 halvings): the end of the two
 * closest to the root on the side where touch > 0. */
static double touch_root(const double c[4], double R, double lo, double hi)
{
    double tlo = touch(c, R, lo);
    for (int it = 0; it < 2100; it++) {
        double mid = lo + 0.5 * (hi - lo);
        if (!(mid > lo && mid < hi)) break;
        if ((touch(c, R, mid) > 0.0) == (tlo > 0.0)) lo = mid;
        else hi = mid;
    }
    return tlo > 0.0 ? lo : hi;
}

/* The arcs of segment cubic c on [0, dx]: the whole segment when the body touches it everywhere
 * (whole_arc), else the parts where touch > 0, their ends located between TOUCH_SAMPLES samples. 0, or
 * -1 when out of memory. */
#define TOUCH_SAMPLES 32
static int segment_arcs(arcs *list, double R, const double c[4], double dx)
{
    if (whole_arc(R, c, dx)) return add_arc(list, c, dx, 0.0, dx);
    double start = touch(c, R, 0.0) > 0.0 ? 0.0 : NAN, u_prev = 0.0; /* start: of the part being kept, NAN: none */
    for (int i = 1; i <= TOUCH_SAMPLES; i++) { /* bounded: TOUCH_SAMPLES samples */
        double u = i == TOUCH_SAMPLES ? dx : dx * i / TOUCH_SAMPLES;
        int inside = touch(c, R, u) > 0.0;
        if (inside == (start == start)) { u_prev = u; continue; }
        double root = touch_root(c, R, u_prev, u);
        if (start == start) {
            if (add_arc(list, c, dx, start, root) < 0) return -1;
            start = NAN;
        } else start = root;
        u_prev = u;
    }
    return start == start ? add_arc(list, c, dx, start, dx) : 0;
}

/* Whether a spline of n rows leaves its arcs unstored when its segments are all whole: one of more than
 * STORED_ARCS_MAX segments, whose arcs would take more memory than a cache holds (reading and building
 * it costs less without them); the arcs of a shorter one are stored, their cubics evaluated faster. */
#define STORED_ARCS_MAX 16384

/* Whether the body touches every segment of the spline through the rows (slopes k) everywhere
 * (whole_arc) and the spline is long (STORED_ARCS_MAX): then each segment is one arc, none is stored
 * (arc_set), and the largest |h'| of any is *max_slope, as add_arc takes it. */
static int whole_segments(const double *x, const double *h, const double *k, size_t n, double R, double *max_slope)
{
    double slope = 0.0, c[4];
    if (n - 1 <= STORED_ARCS_MAX) return 0;
    for (size_t j = 0; j + 1 < n; j++) { /* bounded by the rows */
        double dx = segment_cubic(x, h, k, j, c);
        if (!whole_arc(R, c, dx)) return 0;
        slope = larger(slope, arc_slope(c, 0.0, dx));
    }
    *max_slope = slope;
    return 1;
}

/* The arcs of the spline through the table with slopes k, segment by segment: none stored when every
 * segment is whole (whole_segments: list->a NULL, list->n the segments, *scratch NULL), else in list->a,
 * with *scratch (2 n doubles, the caller's to free) holding the centre_shift of the slope at each row,
 * then where the arcs of each segment start (first[j]: the first arc of segment j, first[n - 1] = their
 * number); and the largest |h'| of any arc. 0, or -1 when out of memory. */
static int make_arcs(const double *x, const double *h, const double *k, size_t n, double R, arcs *list,
                     double **scratch)
{
    _Static_assert(sizeof(size_t) <= sizeof(double) && _Alignof(double) % _Alignof(size_t) == 0, "first fits");
    *scratch = NULL;
    if (whole_segments(x, h, k, n, R, &list->max_slope)) {
        list->n = n - 1;
        return 0;
    }
    double *shift = *scratch = malloc(2 * n * sizeof *shift);
    size_t *first = (size_t *)(shift + n);
    list->a = shift && n - 1 <= ARCS_MAX ? malloc((n - 1) * sizeof *list->a) : NULL; /* one a segment, as a rule */
    if (!list->a) return -1;
    list->cap = n - 1;
    for (size_t j = 0; j + 1 < n; j++) { /* bounded by the rows */
        shift[j] = centre_shift(R, k[j]);
        double c[4], dx = segment_cubic(x, h, k, j, c);
        first[j] = list->n;
        if (segment_arcs(list, R, c, dx) < 0) return -1;
    }
    first[n - 1] = list->n, shift[n - 1] = centre_shift(R, k[n - 1]);
    return 0;
}

/* The first segment j of copy k of the table whose end vertex_x(j + 1) + reach is not below lo (as
 * build_cubic computes it: the segments before it pass over, their centres missing [lo, hi]), or the
 * last segment: found by bisection, as vertex_x(j + 1) + reach does not decrease with j (x increases, and
 * rounding keeps the order) up to the last segment, whose end may be the next copy's first vertex. */
static size_t first_in_reach(const double *x, size_t n, int periodic, double period, long k, double reach, double lo)
{
    size_t a = 0, b = n - 2; /* the answer in [a, b] */
    while (a < b) { /* log2(n) halvings */
        size_t mid = a + (b - a) / 2;
        if (vertex_x(x, n, periodic, period, mid + 1, k) + reach < lo) a = mid + 1;
        else b = mid;
    }
    return a;
}

/* The centre_shift of the slopes at the rows: stored, or (stored NULL) computed from the slopes k, the
 * last one kept for the next call (build_cubic asks for row j, then j + 1, then j + 1 again). */
typedef struct {
    const double *stored, *k;
    double R, last;
    size_t row; /* of last; SIZE_MAX: none */
} shifts;

static double shift_at(shifts *s, size_t j)
{
    if (s->stored) return s->stored[j];
    if (j != s->row) s->row = j, s->last = centre_shift(s->R, s->k[j]);
    return s->last;
}

/* The first arc of segment j: first[j], or j when every segment is one whole arc (first NULL). */
static size_t first_arc(const size_t *first, size_t j) { return first ? first[j] : j; }

/* The envelope on [lo, hi] of the arcs (c->arcs, first_arc: the first arc of segment j) and, for an open
 * table, the circles around its end rows, in the order of the profile (copies kmin .. kmax of a
 * periodic table, as build takes them; segments whose centres, within reach of them, miss [lo, hi]
 * are passed over). An arc that starts or ends at a row starts or ends at that row's x (vertex_x) plus
 * shift_at(row), the centre_shift of the slope there: the same number on both sides of the row. An
 * arc after a dropped part starts no later than the one before it ends (the dropped part's centres
 * move backwards). An end circle and the arc that starts (ends) at its row meet tangentially where
 * the arc's domain starts (ends): they are numbered as insert's neighbours, the arcs odd as tangents
 * and the circles even (circle 0, arc 1; arc g, circle g + 1), so that the switch is there exactly,
 * not where rounding puts a numerical crossing (the spline between the row and the contact point
 * curves less than the body, so it stays below the body there); other pieces are numbered at least
 * two apart, never neighbours. 0, or -1 when out of memory. */
static int build_cubic(const context *c, const double *x, const double *h, shifts *shift, double reach,
                       const size_t *first, size_t n, int periodic, double lo, double hi, long kmin, long kmax,
                       stack *st)
{
    double R = c->R, period = periodic ? hi - lo : 0.0, before = INFINITY; /* before: where the last arc ends */
    size_t g = 0, n_arcs = first_arc(first, n - 1);
    stack tail = {.sl = st->sl};
    int rc = 0;
    if (!periodic) {
        piece circle = {.px = x[0], .py = h[0], .kind = CIRCLE};
        rc = insert(c, st, &tail, &circle, g, lo, smaller(x[0] + R, hi));
    }
    for (long copy = kmin; copy <= kmax && rc == 0; copy++) { /* bounded: the copies of n rows */
        size_t j = first_in_reach(x, n, periodic, period, copy, reach, lo);
        if (j > 0) before = INFINITY;
        for (; j + 1 < n && rc == 0; j++) {
            double row = vertex_x(x, n, periodic, period, j, copy);
            double next = vertex_x(x, n, periodic, period, j + 1, copy);
            if (next + reach < lo) {
                before = INFINITY;
                continue;
            }
            if (row - reach > hi) { /* and every later segment of this copy */
                before = INFINITY;
                break;
            }
            for (size_t i = first_arc(first, j); i < first_arc(first, j + 1) && rc == 0; i++) { /* bounded by the arcs */
                const arc *a = c->arcs.list ? &c->arcs.list[i] : NULL; /* NULL: segment j whole */
                int starts = !a || a->starts, ends = !a || a->ends;
                double from = starts ? row + shift_at(shift, j) : row + arc_centre(a, R, a->u0);
                double to = ends ? next + shift_at(shift, j + 1) : row + arc_centre(a, R, a->u1);
                from = smaller(from, before);
                before = to;
                piece q = {.px = row, .arc = (unsigned)i, .kind = ARC};
                if (g == 0) /* the first arc: the first circle's neighbour when it starts at row 0 */
                    g = periodic || i != 0 || !starts ? 3 : 1;
                else g += 2;
                from = larger(from, lo), to = smaller(to, hi);
                const span *top = st->n ? &st->s[st->n - 1] : NULL;
                span sq = piece_span(&q, g);
                if (top && top->x1 <= from && to > from) /* after all the stack holds: insert would push it there */
                    rc = push(st, larger(from, smaller(to, top->x1)), to, &sq, &q);
                else
                    rc = insert(c, st, &tail, &q, g, from, to);
            }
        }
    }
    if (!periodic && rc == 0) {
        piece circle = {.px = x[n - 1], .py = h[n - 1], .kind = CIRCLE};
        arc tmp;
        int tangent = n_arcs && arc_at(&c->arcs, n_arcs - 1, &tmp)->ends && first_arc(first, n - 2) < n_arcs;
        rc = insert(c, st, &tail, &circle, g + (tangent ? 1 : 3), larger(x[n - 1] - R, lo), hi);
    }
    free(tail.s);
    return rc;
}

/* The spline's arcs into p and c->arcs, and the envelope of the cubic profile on st (the centres lie
 * within R S/sqrt(1 + S^2) of the contact point, S the largest slope). The slopes are solved for in
 * the memory of the envelope's intervals (st reserved for one an arc, as a rule), which no interval
 * holds yet. When no arc is stored (arc_set), the profile keeps the spline's slopes (p->own_k) and
 * reads the rows x, h, which must outlive it (its caller sees p->own_k). 0, or -1 when out of memory. */
static int cubic(vi_profile *p, context *c, const double *x, const double *h, size_t n, long kmin, long kmax, stack *st)
{
    _Static_assert(sizeof(span) >= 2 * sizeof(double), "the solver's 2 n doubles fit in n intervals");
    double *k = malloc(n * sizeof *k), *scratch = NULL;
    arcs list = {0};
    st->cap = n, st->n = 0, st->s = malloc(n * sizeof *st->s);
    int rc = k && st->s ? 0 : -1;
    if (rc == 0) {
        spline_slopes(x, h, n, p->periodic, k, (double *)(void *)st->s);
        rc = make_arcs(x, h, k, n, p->R, &list, &scratch);
    }
    p->arc_list = list.a, p->n_arcs = list.n, p->max_slope = list.max_slope;
    p->arcs = (arc_set){list.a, x, h, k};
    if (list.a || rc < 0) free(k), k = NULL, p->arcs.k = NULL;
    else p->own_k = k;
    c->arcs = p->arcs;
    double reach = 1.000001 * fabs(centre_shift(p->R, list.max_slope));
    shifts shift = {scratch, k, p->R, 0.0, SIZE_MAX};
    size_t *first = scratch ? (size_t *)(scratch + n) : NULL;
    if (rc == 0) rc = build_cubic(c, x, h, &shift, reach, first, n, p->periodic, p->lo, p->hi, kmin, kmax, st);
    free(scratch);
    return rc;
}

/* The largest |h| and the least and largest h of a table's heights, taken row by row (heights_add). */
typedef struct {
    double abs_max, lo, hi;
} heights;

static void heights_add(heights *s, size_t i, double h)
{
    if (i == 0) s->abs_max = 0.0, s->lo = s->hi = h;
    s->abs_max = larger(s->abs_max, fabs(h)), s->lo = smaller(s->lo, h), s->hi = larger(s->hi, h);
}

/* R positive, and a periodic table ending at its first height. 0, or -1 with the reason in msg. */
static int check_ends(const double *h, size_t n, double R, int periodic, const char *name, char *msg, size_t msg_size)
{
    if (!(R > 0.0 && isfinite(R)))
        VI_FAIL(msg, msg_size, "%s: the rolling radius R1 = %g m must be positive and finite", name, R);
    if (periodic && h[n - 1] != h[0])
        VI_FAIL(msg, msg_size, "%s: profile_periodic needs the last height to repeat the first (h = %.17g on row %zu, "
                               "%.17g on row 1)", name, h[n - 1], n, h[0]);
    return 0;
}

/* The rows as a profile needs them: at least two, finite, x increasing, a periodic one ending at
 * its first height; and R positive (after the rows' count, before the rows). 0, or -1 with the reason
 * in msg. */
static int check_rows(const double *x, const double *h, size_t n, double R, int periodic, const char *name, char *msg,
                      size_t msg_size)
{
    if (n < 2) VI_FAIL(msg, msg_size, "%s: %zu rows; a profile needs at least two (x [m], h [m])", name, n);
    if (!(R > 0.0 && isfinite(R)))
        VI_FAIL(msg, msg_size, "%s: the rolling radius R1 = %g m must be positive and finite", name, R);
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(x[i]) || !isfinite(h[i]))
            VI_FAIL(msg, msg_size, "%s, row %zu: x = %g, h = %g are not finite", name, i + 1, x[i], h[i]);
        if (i && !(x[i] > x[i - 1]))
            VI_FAIL(msg, msg_size, "%s, row %zu: x = %.17g is not greater than x = %.17g of the row before (x must "
                                   "increase)", name, i + 1, x[i], x[i - 1]);
    }
    return check_ends(h, n, R, periodic, name, msg, msg_size);
}

/* The copies of a periodic profile the envelope is built from, k = *kmin..*kmax (0..0 when it is
 * not periodic): those whose vertices lie within R of [lo, hi], and one more each side. 0, or -1. */
static int periodic_copies(const vi_profile *p, size_t n, const char *name, long *kmin, long *kmax, char *msg,
                           size_t msg_size)
{
    *kmin = 0, *kmax = 0;
    if (!p->periodic) return 0;
    double reach = ceil(p->R / p->period) + 1.0;
    if (reach * 2.0 * (double)(n - 1) > VI_PROFILE_ROWS_MAX)
        VI_FAIL(msg, msg_size, "%s: the period %g m is too short for R1 = %g m: the body spans %.0f periods of %zu "
                               "rows, more than %d rows in all", name, p->period, p->R, 2.0 * reach, n - 1,
                VI_PROFILE_ROWS_MAX);
    *kmin = -(long)reach, *kmax = (long)reach;
    return 0;
}

/* The envelope's intervals into p, which then owns env's memory, shrunk to them (env is left empty); it
 * must cover [lo, hi] without gaps. 0, or -1 (env's memory then still env's). */
static int take_envelope(vi_profile *p, stack *env, const char *name, char *msg, size_t msg_size)
{
    if (!env->n || env->s[0].x0 != p->lo || env->s[env->n - 1].x1 != p->hi)
        VI_FAIL(msg, msg_size, "%s: internal error: the envelope covers [%g, %g] instead of [%g, %g]", name,
                env->n ? env->s[0].x0 : NAN, env->n ? env->s[env->n - 1].x1 : NAN, p->lo, p->hi);
    for (size_t j = 1; j < env->n; j++) /* bounded by the envelope */
        if (env->s[j].x0 != env->s[j - 1].x1)
            VI_FAIL(msg, msg_size, "%s: internal error: a gap in the envelope at x = %g", name, env->s[j - 1].x1);
    p->m = env->n;
    p->kinks = malloc((p->m + 1) * sizeof *p->kinks);
    if (!p->kinks) VI_FAIL(msg, msg_size, "%s: out of memory", name);
    p->spans = realloc(env->s, p->m * sizeof *p->spans);
    if (!p->spans) VI_FAIL(msg, msg_size, "%s: out of memory", name); /* env still holds the block */
    env->s = NULL, env->n = env->cap = 0;
    return 0;
}

/* The buckets of interval: n_buckets equal parts of [lo, hi], about INTERVALS_PER_BUCKET intervals each;
 * bucket[k] is the interval holding the start of part k (bucket[n_buckets] the last interval), so
 * that the intervals of part k are bucket[k] .. bucket[k + 1]. None for few intervals. 0, or -1 when out
 * of memory. */
#define INTERVALS_PER_BUCKET 8
static int index_intervals(vi_profile *p)
{
    if (p->m < 4 * INTERVALS_PER_BUCKET) return 0;
    p->n_buckets = p->m / INTERVALS_PER_BUCKET;
    p->bucket = malloc((p->n_buckets + 1) * sizeof *p->bucket);
    if (!p->bucket) return -1;
    p->bucket_scale = (double)p->n_buckets / (p->hi - p->lo);
    size_t j = 0;
    for (size_t k = 0; k <= p->n_buckets; k++) { /* bounded by the buckets and the intervals */
        double start = p->lo + (double)k / p->bucket_scale;
        while (j + 1 < p->m && p->spans[j + 1].x0 <= start) j++;
        p->bucket[k] = k == p->n_buckets ? p->m - 1 : j;
    }
    return 0;
}

/* The table a profile is built from, for the messages. */
typedef struct {
    const double *x, *h;
    size_t n;
} table;

/* |a - b| [m], for a periodic profile to the nearest copy of a. */
static double distance(const vi_profile *p, double a, double b)
{
    return p->periodic ? fabs(remainder(a - b, p->period)) : fabs(a - b);
}

/* Why yb is vertical (not finite) at xb on vertex circle q, which starts there (starts = 0: it ends
 * there): the segment into q's vertex (out of it) is so steep that the body leaves it R (1 -
 * |s|/sqrt(1 + s^2)) = R/(hyp (hyp + |s|)) before the vertex, closer than the spacing of doubles at
 * xb, and the circle meets it at the edge of its domain, where it is vertical. Into msg; -1. */
static int too_steep(const vi_profile *p, const table *t, const piece *q, int starts, double xb, const char *name,
                     char *msg, size_t msg_size)
{
    size_t rows = p->periodic ? t->n - 1 : t->n, i = 0; /* the row of q's vertex (a periodic table's last is its first) */
    for (size_t k = 1; k < rows; k++) /* bounded by the rows: the nearest vertex, in any period */
        if (distance(p, t->x[k], q->px) < distance(p, t->x[i], q->px)) i = k;
    /* the segment into the vertex or out of it (an open table's end vertex has none beyond the end,
     * but its circle is cut at the end, where it is not vertical) */
    size_t a = starts ? (i > 0 ? i - 1 : rows - 1) : i;
    if (a + 1 >= t->n) a = t->n - 2;
    size_t b = a + 1;
    double s = (t->h[b] - t->h[a]) / (t->x[b] - t->x[a]), hyp = hypot(1.0, s), before = p->R / (hyp * (hyp + fabs(s)));
    double spacing = nextafter(fabs(xb), INFINITY) - fabs(xb);
    VI_FAIL(msg, msg_size, "%s: rows %zu and %zu (x = %.17g and %.17g m) make a slope of %.6g, too steep for R1 = %g m "
                           "near x = %g m: the body leaves that segment %.2g m before its end, less than the spacing "
                           "of doubles there (%.2g m), and yb is vertical; slopes up to about %.3g (sqrt(R1/(2 spacing))) "
                           "can be rolled over there", name, a + 1, b + 1, t->x[a], t->x[b], s, p->R, xb, before,
            spacing, sqrt(p->R / (2.0 * spacing)));
}

/* Pieces a and b (b after a) are the arcs either side of one row of the spline: continuous there with
 * their slope (the spline is C2), no step or kink to look for. */
static int joined(const vi_profile *p, const piece *a, const piece *b)
{
    arc ta, tb;
    if (a->kind != ARC || b->kind != ARC || !arc_at(&p->arcs, a->arc, &ta)->ends || !arc_at(&p->arcs, b->arc, &tb)->starts)
        return 0;
    return (size_t)b->arc == (size_t)a->arc + 1 || (p->periodic && (size_t)a->arc + 1 == p->n_arcs && b->arc == 0);
}

/* Continuity, slopes and kinks at the boundaries of the pieces (a periodic profile also at the seam):
 * max_slope and the kinks into p; -1 where the body cannot roll over the profile (too steep, a step).
 * tol: the rounding of the heights. */
static int check_boundaries(vi_profile *p, const table *t, double tol, const char *name, char *msg, size_t msg_size)
{
    double R = p->R;
    for (size_t j = 0; j <= p->m; j++) {
        double dl[3], dr[3], yl = NAN, yr = NAN; /* set before use (has_left, has_right); gcc -fsanitize cannot tell */
        int has_left = j > 0 || p->periodic, has_right = j < p->m || p->periodic;
        size_t jl = j > 0 ? j - 1 : p->m - 1, jr = j < p->m ? j : 0;
        double xl = j > 0 && j < p->m ? p->spans[j].x0 : p->hi, xr = j < p->m ? p->spans[j].x0 : p->lo;
        piece pl = piece_at(&p->sl, &p->spans[jl]), pr = piece_at(&p->sl, &p->spans[jr]);
        const piece *ql = &pl, *qr = &pr;
        if (has_left && has_right && joined(p, ql, qr)) continue; /* slopes: the arcs' */
        if (has_left) {
            yl = piece_eval(ql, &p->arcs, R, xl, dl);
            if (!isfinite(yl) || !isfinite(dl[0])) return too_steep(p, t, ql, 0, xl, name, msg, msg_size);
            p->max_slope = larger(p->max_slope, fabs(dl[0]));
        }
        if (has_right) {
            yr = piece_eval(qr, &p->arcs, R, xr, dr);
            if (!isfinite(yr) || !isfinite(dr[0])) return too_steep(p, t, qr, 1, xr, name, msg, msg_size);
            p->max_slope = larger(p->max_slope, fabs(dr[0]));
        }
        if (!has_left || !has_right) continue;
        /* a step: the pieces differ at the boundary by more than their rounding there; besides the
         * heights' (tol), the boundary is rounded to a few eps of its position (at the seam of a
         * periodic profile xl = x_last, xr = x_first, one period apart), which moves each piece by its
         * slope times that */
        double rounding = 1e3 * tol + 16.0 * DBL_EPSILON * larger(fabs(xl), fabs(xr)) * (fabs(dl[0]) + fabs(dr[0]));
        if (fabs(yl - yr) > rounding)
            VI_FAIL(msg, msg_size, "%s: a step of more than R1 = %g m near x = %g m: yb jumps by %g m there (the body "
                                   "cannot roll over it)", name, R, xr, yr - yl);
        if (fabs(dr[0] - dl[0]) > VI_PROFILE_KINK_SLOPE && j < p->m) p->kinks[p->n_kinks++] = xr;
    }
    return 0;
}

vi_profile *vi_profile_create(const double *x, const double *h, size_t n, double R, int periodic, const char *name,
                              char *msg, size_t msg_size)
{
    return vi_profile_create_as(x, h, n, R, periodic, VI_PROFILE_LINEAR, name, msg, msg_size);
}

/* The rows x, h of a spline whose arcs are not stored (cubic: arc_set) into p: own[0] and own[1] (x and h
 * themselves), taken over and set NULL, or when own is NULL a copy. 0, or -1 when out of memory. */
static int keep_rows(vi_profile *p, const double *x, const double *h, size_t n, double **own)
{
    if (own) {
        p->own_x = own[0], p->own_h = own[1], own[0] = own[1] = NULL;
    } else {
        p->own_x = malloc(n * sizeof *p->own_x), p->own_h = malloc(n * sizeof *p->own_h);
        if (!p->own_x || !p->own_h) return -1;
        memcpy(p->own_x, x, n * sizeof *x), memcpy(p->own_h, h, n * sizeof *h);
    }
    p->arcs.x = p->own_x, p->arcs.h = p->own_h;
    return 0;
}

/* The profile of n checked rows (check_rows) whose heights are hs, joined as interpolation says. own:
 * NULL, or the blocks of x and h, which the profile may take over (keep_rows). */
static vi_profile *create(const double *x, const double *h, size_t n, double R, int periodic, int interpolation,
                          const heights *hs, double **own, const char *name, char *msg, size_t msg_size)
{
    vi_profile *p = NULL;
    stack env = {0};
    p = calloc(1, sizeof *p);
    if (!p) FAIL("%s: out of memory", name);
    env.sl = &p->sl;
    p->R = R, p->lo = x[0], p->hi = x[n - 1], p->periodic = periodic != 0;
    p->period = periodic ? p->hi - p->lo : 0.0;
    long kmin, kmax;
    if (periodic_copies(p, n, name, &kmin, &kmax, msg, msg_size) < 0) goto fail;
    p->h_span = hs->hi - hs->lo;
    context c = {R, 64.0 * DBL_EPSILON * (R + hs->abs_max), {NULL, NULL, NULL, NULL}};
    if (interpolation == VI_PROFILE_CUBIC ? cubic(p, &c, x, h, n, kmin, kmax, &env) < 0
                                          : build(&c, x, h, n, p->periodic, p->lo, p->hi, kmin, kmax, &env) < 0)
        FAIL("%s: out of memory", name);
    if (p->own_k && keep_rows(p, x, h, n, own) < 0) FAIL("%s: out of memory", name);
    if (take_envelope(p, &env, name, msg, msg_size) < 0) goto fail;
    if (index_intervals(p) < 0) FAIL("%s: out of memory", name);
    free(env.s);
    env.s = NULL;
    table t = {x, h, n};
    if (check_boundaries(p, &t, c.tol, name, msg, msg_size) < 0) goto fail;
    return p;
fail:
    free(env.s);
    vi_profile_free(p);
    return NULL;
}

/* The interpolation's name: 0, or -1 with the reason in msg. */
static int check_interpolation(int interpolation, const char *name, char *msg, size_t msg_size)
{
    if (interpolation != VI_PROFILE_LINEAR && interpolation != VI_PROFILE_CUBIC)
        VI_FAIL(msg, msg_size, "%s: interpolation %d is neither linear (%d) nor cubic (%d)", name, interpolation,
                VI_PROFILE_LINEAR, VI_PROFILE_CUBIC);
    return 0;
}

vi_profile *vi_profile_create_as(const double *x, const double *h, size_t n, double R, int periodic, int interpolation,
                                 const char *name, char *msg, size_t msg_size)
{
    if (!name) name = "profile";
    if (check_interpolation(interpolation, name, msg, msg_size) < 0) return NULL;
    if (check_rows(x, h, n, R, periodic, name, msg, msg_size) < 0) return NULL;
    heights hs;
    for (size_t i = 0; i < n; i++) heights_add(&hs, i, h[i]); /* bounded by the rows */
    return create(x, h, n, R, periodic, interpolation, &hs, NULL, name, msg, msg_size);
}

/* ---- reading a file -------------------------------------------------------------------------
 *
 * A data line is "x h": two numbers in the C syntax (vi_strtod) separated by blanks or tabs, with at
 * most one ';' or ',' among them, blanks and tabs before and after, and a '\r' at its end (CRLF files).
 * A line that is empty, holds blanks only or starts with '#' after blanks is skipped. A line that
 * would be one number with a decimal comma ("0,5", "-12,75e-3": digits, the comma, digits and an
 * exponent, nothing between) is refused: it could be the decimal 0.5 or the two columns 0 and 5, and
 * the reader does not guess. */

static int is_blank(char ch) { return ch == ' ' || ch == '\t'; }

static const char *skip_blanks(const char *s)
{
    while (is_blank(*s)) s++; /* bounded by the line's terminating '\0' */
    return s;
}

/* s is at the end of the line [line, end), or at a '\r' that ends it. */
static int at_end(const char *s, const char *end) { return s == end || (*s == '\r' && s + 1 == end); }

static int is_digit(char ch) { return ch >= '0' && ch <= '9'; }

/* [s, end) is one or more digits; the end of them. */
static const char *digits(const char *s, const char *end)
{
    const char *d = s;
    while (d < end && is_digit(*d)) d++; /* bounded by end */
    return d > s ? d : NULL;
}

/* [x, comma) and (comma, h_end) read together as one number with a decimal comma: [+-]digits,digits
 * with an optional exponent [eE][+-]digits. */
static int decimal_comma(const char *x, const char *comma, const char *h_end)
{
    if (*x == '+' || *x == '-') x++;
    if (digits(x, comma) != comma) return 0;
    const char *d = digits(comma + 1, h_end);
    if (!d || d == h_end) return d == h_end;
    if (*d != 'e' && *d != 'E') return 0;
    d++;
    if (d < h_end && (*d == '+' || *d == '-')) d++;
    return digits(d, h_end) == h_end;
}

/* A line [line, end) (*end = '\0'): 1 for a data row (into *x, *h), 0 for a line to skip, -1 for any
 * other (a NUL byte inside the line stops the parse before end: -1). */
static int parse_row(const char *line, const char *end, double *x, double *h)
{
    const char *s = skip_blanks(line), *x_text = s;
    if (*s == '#' || at_end(s, end)) return 0;
    char *after;
    *x = vi_strtod(s, &after);
    if (after == s) return -1;
    const char *x_end = after;
    s = skip_blanks(after);
    const char *sep = s;
    if (*s == ';' || *s == ',') s = skip_blanks(s + 1);
    if (s == after) return -1; /* no separator */
    *h = vi_strtod(s, &after);
    if (after == s) return -1;
    if (*sep == ',' && sep == x_end && s == sep + 1 && decimal_comma(x_text, sep, after)) return -1;
    return at_end(skip_blanks(after), end) ? 1 : -1;
}

/* What a line that is not a data row holds, for the message. */
enum { SHOW_FIELDS = 3, SHOW_CHARS = 24, QUOTED_MAX = 128 };
/* a quoted field: the quotes, SHOW_CHARS bytes of 4 characters at most (\xNN), "..." and the '\0' */
_Static_assert(QUOTED_MAX >= 2 + 4 * SHOW_CHARS + 3 + 1, "a quoted field fits");
typedef struct {
    size_t fields, semicolons, not_number; /* not_number: the first field that is no number, 1-based (0: none) */
    size_t words; /* fields starting with a letter */
    int blanks, tabs, comma, nul, hash;
    const char *text[SHOW_FIELDS];
    size_t len[SHOW_FIELDS];
} row_view;

/* s (before end) ends a field: a blank, a tab, a ';', or the '\r' that ends a CRLF line. */
static int field_end(const char *s, const char *end) { return s == end || is_blank(*s) || *s == ';' || at_end(s, end); }

/* Fields of [line, end): the text between blanks, tabs and semicolons. */
static void view_row(const char *line, const char *end, row_view *v)
{
    memset(v, 0, sizeof *v);
    for (const char *s = line; s < end;) { /* bounded by the line: every pass moves s */
        if (field_end(s, end)) {
            v->blanks |= *s == ' ', v->tabs |= *s == '\t', v->semicolons += *s == ';';
            s++;
            continue;
        }
        const char *f = s;
        while (!field_end(s, end)) v->comma |= *s == ',', v->nul |= *s == '\0', s++; /* bounded by end */
        char *after;
        vi_strtod(f, &after);
        if (after == f || after != s) {
            if (!v->not_number) v->not_number = v->fields + 1;
            v->hash |= *f == '#';
            v->words += (*f >= 'a' && *f <= 'z') || (*f >= 'A' && *f <= 'Z');
        }
        if (v->fields < SHOW_FIELDS) v->text[v->fields] = f, v->len[v->fields] = (size_t)(s - f);
        v->fields++;
    }
}

/* Field text quoted, cut after SHOW_CHARS characters, bytes outside printable ASCII as \xNN. */
static void quote(char *out, size_t size, const char *text, size_t len)
{
    size_t k = 0;
    out[k++] = '\'';
    for (size_t i = 0; i < len && i < SHOW_CHARS; i++) {
        unsigned char ch = (unsigned char)text[i];
        if (ch >= 0x20 && ch < 0x7f) out[k++] = (char)ch;
        else k += (size_t)vi_snprintf(out + k, size - k, "\\x%02X", (unsigned)ch);
    }
    vi_snprintf(out + k, size - k, "%s'", len > SHOW_CHARS ? "..." : "");
}

/* The message for line line_no of path, which is no data row: the fields found, the separators seen,
 * what is wrong and how to write a row. */
static void refuse_row(const char *line, const char *end, const char *path, size_t line_no, char *msg, size_t msg_size)
{
    row_view v;
    view_row(line, end, &v);
    char shown[SHOW_FIELDS * QUOTED_MAX] = "", q[QUOTED_MAX];
    for (size_t i = 0; i < v.fields && i < SHOW_FIELDS; i++) {
        quote(q, sizeof q, v.text[i], v.len[i]);
        size_t used = strlen(shown);
        vi_snprintf(shown + used, sizeof shown - used, " %s", q);
    }
    const char *sep = v.semicolons ? (v.semicolons > 1 ? "several semicolons" : "a semicolon")
                      : v.blanks && v.tabs ? "blanks and tabs" : v.blanks ? "blanks" : v.tabs ? "a tab" : "none";
    char why[160];
    if (v.nul) vi_snprintf(why, sizeof why, "it holds a NUL byte (a binary or UTF-16 file?)");
    else if (v.comma) vi_snprintf(why, sizeof why, "a comma is no decimal point, and '0,5' could be 0.5 or the columns 0 "
                                                   "and 5");
    else if (v.hash) vi_snprintf(why, sizeof why, "a comment (#) must start its line");
    else if (v.not_number) {
        quote(q, sizeof q, v.text[v.not_number <= SHOW_FIELDS ? v.not_number - 1 : 0],
              v.not_number <= SHOW_FIELDS ? v.len[v.not_number - 1] : 0);
        vi_snprintf(why, sizeof why, "%s%s is not a number%s", v.not_number <= SHOW_FIELDS ? "" : "a field after ",
                    v.not_number <= SHOW_FIELDS ? q : "them", v.words == v.fields ? " (a header? start it with #)" : "");
    } else if (v.semicolons > 1) vi_snprintf(why, sizeof why, "more than one semicolon");
    else if (v.fields == 2) vi_snprintf(why, sizeof why, "the semicolon does not stand between the numbers");
    else vi_snprintf(why, sizeof why, "%s", !v.fields ? "no number" : v.fields == 1 ? "a second number is missing"
                                                                         : "more than two numbers");
    vi_snprintf(msg, msg_size, "profile_file '%s', line %zu: expected two numbers x [m] and h [m], found %zu field%s%s%s "
                               "(separator: %s): %s; write x and h in the C syntax with '.' decimals (0.5, -1.2e-3) "
                               "separated by blanks, a tab, one comma or one semicolon; lines starting with # are comments",
                path, line_no, v.fields, v.fields == 1 ? "" : "s", shown, v.fields > SHOW_FIELDS ? " ..." : "", sep, why);
}

/* The file is read in blocks of VI_PROFILE_BLOCK bytes (more than two lines of the longest kind). */
#define VI_PROFILE_BLOCK (1 << 16)
_Static_assert(VI_PROFILE_BLOCK >= 2 * VI_PROFILE_LINE_MAX, "a block holds the longest line");

/* The rows read so far (x [m], h [m]) and the line of the last. */
typedef struct {
    double *x, *h;
    size_t n, cap, last_line;
    heights hs; /* of the rows so far */
} rows;

/* Append the row of line line_no of file path after checking it (finite, x increasing, at most
 * VI_PROFILE_ROWS_MAX rows). 0, or -1 with the reason in msg. */
static int add_row(rows *r, double xv, double hv, const char *path, size_t line_no, char *msg, size_t msg_size)
{
    if (!isfinite(xv) || !isfinite(hv))
        VI_FAIL(msg, msg_size, "profile_file '%s', line %zu: x = %g, h = %g: %s not finite (a number beyond "
                               "1.8e308, inf or nan)", path, line_no, xv, hv,
                isfinite(xv) ? "h is" : isfinite(hv) ? "x is" : "x and h are");
    if (r->n && !(xv > r->x[r->n - 1]))
        VI_FAIL(msg, msg_size, "profile_file '%s', line %zu: x = %.17g is not greater than x = %.17g on line %zu (x "
                               "must increase)", path, line_no, xv, r->x[r->n - 1], r->last_line);
    if (r->n == VI_PROFILE_ROWS_MAX)
        VI_FAIL(msg, msg_size, "profile_file '%s', line %zu: more than %d rows, the most a profile may have", path,
                line_no, VI_PROFILE_ROWS_MAX);
    if (r->n == r->cap) {
        r->cap = r->cap ? 2 * r->cap : 256;
        double *nx = realloc(r->x, r->cap * sizeof *nx), *nh = nx ? realloc(r->h, r->cap * sizeof *nh) : NULL;
        if (nx) r->x = nx;
        if (nh) r->h = nh;
        if (!nx || !nh) VI_FAIL(msg, msg_size, "profile_file '%s': out of memory at line %zu", path, line_no);
    }
    r->x[r->n] = xv, r->h[r->n] = hv;
    heights_add(&r->hs, r->n, hv);
    r->n++, r->last_line = line_no;
    return 0;
}

/* Fewer than two rows: the file empty, without data rows, or with one. The reason into msg; -1. */
static int too_few_rows(const rows *r, const char *path, size_t lines, char *msg, size_t msg_size)
{
    if (!lines) VI_FAIL(msg, msg_size, "profile_file '%s': the file is empty; a profile needs at least two rows "
                                       "x [m] h [m]", path);
    if (!r->n)
        VI_FAIL(msg, msg_size, "profile_file '%s': no data rows, its %zu line%s blank or comments; a profile needs "
                               "at least two rows x [m] h [m]", path, lines, lines == 1 ? " is" : "s are");
    VI_FAIL(msg, msg_size, "profile_file '%s': one data row (line %zu); a profile needs at least two rows x [m] h [m]",
            path, r->last_line);
}

/* A byte-order mark at the start of the first line: UTF-8's is skipped (its length), UTF-16's and
 * UTF-32's refused (-1, the reason in msg); 0 for none. */
static int byte_order_mark(const char *line, size_t len, const char *path, char *msg, size_t msg_size)
{
    const unsigned char *u = (const unsigned char *)line;
    if (len >= 3 && u[0] == 0xEF && u[1] == 0xBB && u[2] == 0xBF) return 3;
    if (len >= 2 && ((u[0] == 0xFF && u[1] == 0xFE) || (u[0] == 0xFE && u[1] == 0xFF)))
        VI_FAIL(msg, msg_size, "profile_file '%s', line 1: the file starts with a UTF-16 or UTF-32 byte-order mark; "
                               "save it as UTF-8 or ASCII text", path);
    return 0;
}

FILE *vi_profile_fopen(const char *path)
{
#ifdef _WIN32
    int n = MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, path, -1, NULL, 0);
    wchar_t *wide = n > 0 ? malloc((size_t)n * sizeof *wide) : NULL;
    if (wide && MultiByteToWideChar(CP_UTF8, MB_ERR_INVALID_CHARS, path, -1, wide, n) == n) {
        FILE *f = _wfopen(wide, L"r");
        free(wide);
        return f;
    }
    free(wide);
#endif
    return fopen(path, "r");
}

vi_profile *vi_profile_load(const char *path, double R, int periodic, char *msg, size_t msg_size)
{
    return vi_profile_load_as(path, R, periodic, VI_PROFILE_LINEAR, msg, msg_size);
}

/* The profile of the rows r read from path (at least two, checked as they were read: add_row), which
 * it may take over (r's pointers then NULL). NULL on failure with the reason in msg. */
static vi_profile *profile_of_rows(rows *r, const char *path, double R, int periodic, int interpolation, char *msg,
                                   size_t msg_size)
{
    char name[VI_PROFILE_LINE_MAX + 32];
    vi_snprintf(name, sizeof name, "profile_file '%s'", path);
    if (check_interpolation(interpolation, name, msg, msg_size) < 0 ||
        check_ends(r->h, r->n, R, periodic, name, msg, msg_size) < 0)
        return NULL;
    double *own[2] = {r->x, r->h};
    vi_profile *p = create(r->x, r->h, r->n, R, periodic, interpolation, &r->hs, own, name, msg, msg_size);
    r->x = own[0], r->h = own[1];
    return p;
}

vi_profile *vi_profile_load_as(const char *path, double R, int periodic, int interpolation, char *msg, size_t msg_size)
{
    FILE *f = vi_profile_fopen(path);
    if (!f) {
        vi_snprintf(msg, msg_size, "profile_file '%s': cannot open it (%s)", path, strerror(errno));
        return NULL;
    }
    rows r = {0};
    size_t line_no = 0, have = 0, pos = 0; /* buf[pos, have): read, not parsed yet */
    int eof = 0;
    vi_profile *p = NULL;
    char *buf = malloc(VI_PROFILE_BLOCK + 1);
    if (!buf) FAIL("profile_file '%s': out of memory at line %zu", path, line_no);
    for (;;) { /* bounded by the file and VI_PROFILE_ROWS_MAX: every pass reads a block or takes a line */
        char *line = buf + pos, *nl = memchr(line, '\n', have - pos);
        if (!nl && !eof) {
            if (have - pos > VI_PROFILE_LINE_MAX - 2)
                FAIL("profile_file '%s', line %zu: longer than %d characters", path, line_no + 1, VI_PROFILE_LINE_MAX - 2);
            memmove(buf, line, have - pos);
            have -= pos, pos = 0;
            size_t got = fread(buf + have, 1, VI_PROFILE_BLOCK - have, f);
            have += got;
            eof = got == 0;
            continue;
        }
        if (!nl && pos == have) break;
        if (!nl) nl = buf + have; /* the last line has no newline */
        line_no++;
        if ((size_t)(nl - line) > VI_PROFILE_LINE_MAX - 2)
            FAIL("profile_file '%s', line %zu: longer than %d characters", path, line_no, VI_PROFILE_LINE_MAX - 2);
        *nl = '\0';
        pos = (size_t)(nl - buf) + (nl < buf + have);
        if (line_no == 1) {
            int bom = byte_order_mark(line, (size_t)(nl - line), path, msg, msg_size);
            if (bom < 0) goto fail;
            line += bom;
        }
        double xv, hv;
        int rc = parse_row(line, nl, &xv, &hv);
        if (rc == 0) continue;
        if (rc < 0) {
            refuse_row(line, nl, path, line_no, msg, msg_size);
            goto fail;
        }
        if (add_row(&r, xv, hv, path, line_no, msg, msg_size) < 0) goto fail;
    }
    if (ferror(f)) FAIL("profile_file '%s': read error after line %zu", path, line_no);
    if (r.n < 2) {
        too_few_rows(&r, path, line_no, msg, msg_size);
        goto fail;
    }
    p = profile_of_rows(&r, path, R, periodic, interpolation, msg, msg_size);
fail:
    fclose(f);
    free(buf), free(r.x), free(r.h);
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
    return smaller(larger(x, p->lo), p->hi);
}

/* The last j in [a, b) with spans[j].x0 <= x, given spans[a].x0 <= x. */
static size_t search(const vi_profile *p, double x, size_t a, size_t b)
{
    while (b - a > 1) { /* log2(b - a) halvings */
        size_t mid = a + (b - a) / 2;
        if (p->spans[mid].x0 <= x) a = mid;
        else b = mid;
    }
    return a;
}

/* Interval holding x in [lo, hi]: the last j with x0 <= x (the right-hand piece at a boundary). The
 * search is made among the intervals of x's bucket, and its result kept when it holds x (rounding of
 * the bucket's number may miss by one), else over all intervals. */
static size_t interval(const vi_profile *p, double x)
{
    if (p->bucket) {
        double u = (x - p->lo) * p->bucket_scale; /* >= 0: x >= lo */
        size_t k = u < (double)p->n_buckets ? (size_t)u : p->n_buckets - 1, ka = p->bucket[k];
        if (p->spans[ka].x0 <= x) {
            size_t j = search(p, x, ka, p->bucket[k + 1] + 1);
            if (x < p->spans[j].x1) return j;
        }
    }
    return search(p, x, 0, p->m);
}

int vi_profile_eval(const vi_profile *p, double x, double y[4])
{
    int outside;
    double r = reduce(p, x, &outside);
    piece q = piece_at(&p->sl, &p->spans[interval(p, r)]);
    y[0] = piece_eval(&q, &p->arcs, p->R, r, y + 1);
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
