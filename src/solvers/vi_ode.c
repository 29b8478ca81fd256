/* vi_ode.c - Dormand-Prince 8(5,3) with dense output of order 7 and event location; see vi_ode.h. */
#include "vi_ode.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vi_text.h"

/* ---------------------------------------------------------------------------------------------
 * The coefficients of DOP853 (Hairer and Wanner; HNW I, 2nd ed., II.5 and II.6), 0-based stages:
 * 0..11 the step, 12 = f(t + h, x1) (the next step's first stage), 13..15 the dense output.
 * c2..c5 involve sqrt(6): c4 = (6 - sqrt 6)/30, c5 = (6 + sqrt 6)/30, c3 = 2 c4/3, c2 = 4 c4/9.
 * ------------------------------------------------------------------------------------------- */
enum { NS = VI_ODE_STAGES, S_STEP = 12, S_END = 12, S_DENSE = 13 };

static const double C[NS] = {
    0.0,
    0.526001519587677318785587544488e-1,
    0.789002279381515978178381316732e-1,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    1.0 / 3.0,
    0.25,
    4.0 / 13.0,
    127.0 / 195.0,
    0.6,
    6.0 / 7.0,
    1.0,
    1.0,
    0.1,
    0.2,
    7.0 / 9.0,
};

#define B0 0.542937341165687622380535766363e-1
#define B5 4.45031289275240888144113950566
#define B6 1.89151789931450038304281599044
#define B7 -5.8012039600105847814672114227
#define B8 0.31116436695781989440891606237
#define B9 -0.152160949662516078556178806805
#define B10 0.201365400804030348374776537501
#define B11 0.447106157277725905176885569043e-1

static const double A[NS][NS] = {
    {0},
    {0.526001519587677318785587544488e-1},
    {0.197250569845378994544595329183e-1, 0.591751709536136983633785987549e-1},
    {0.295875854768068491816892993775e-1, 0, 0.887627564304205475450678981324e-1},
    {0.241365134159266685502369798665, 0, -0.884549479328286085344864962717,
     0.924834003261792003115737966543},
    {0.37037037037037037037037037037e-1, 0, 0, 0.170828608729473871279604482173,
     0.125467687566822425016691814123},
    {0.37109375e-1, 0, 0, 0.170252211019544039314978060272, 0.602165389804559606850219397283e-1,
     -0.17578125e-1},
    {0.370920001185047927108779319836e-1, 0, 0, 0.170383925712239993810273719705,
     0.107262030446373284651809199168, -0.153194377486244017527936158236e-1,
     0.827378916381402288758473766002e-2},
    {0.624110958716075717114429577812, 0, 0, -3.36089262944694129406857109825,
     -0.868219346841726006818189891453, 27.5920996994467083049415600797, 20.1540675504778934086186788979,
     -43.4898841810699588477366255144},
    {0.477662536438264365890433908527, 0, 0, -2.48811461997166764192642586468,
     -0.590290826836842996371446475743, 21.2300514481811942347288949897, 15.2792336328824235832586722938,
     -33.2882109689848629194453265587, -0.203312017085086261358222928593e-1},
    {-0.93714243008598732571704021658, 0, 0, 5.18637242884406370830023853209,
     1.09143734899672957818505394654, -8.14978701074692612513997267357, -18.5200656599969598641566180701,
     22.7394870993505042818970056734, 2.49360555267965238987089396762, -3.0467644718982195003823669022},
    {2.27331014751653820792359768449, 0, 0, -10.5344954667372501984066689879,
     -2.00087205822486249909675718444, -17.9589318631187989172765950534, 27.9488845294199600508499808837,
     -2.85899827713502369474065508674, -8.87285693353062954433549289258, 12.3605671757943030647266201528,
     0.643392746015763530355970484046},
    {B0, 0, 0, 0, 0, B5, B6, B7, B8, B9, B10, B11},
    {0.561675022830479523392909219681e-1, 0, 0, 0, 0, 0, 0.253500210216624811088794765333,
     -0.246239037470802489917441475441, -0.124191423263816360469010140626, 0.15329179827876569731206322685,
     0.820105229563468988491666602057e-2, 0.756789766054569976138603589584e-2, -0.8298e-2},
    {0.318346481635021405060768473261e-1, 0, 0, 0, 0, 0.283009096723667755288322961402e-1,
     0.535419883074385676223797384372e-1, -0.549237485713909884646569340306e-1, 0, 0,
     -0.108347328697249322858509316994e-3, 0.382571090835658412954920192323e-3,
     -0.340465008687404560802977114492e-3, 0.141312443674632500278074618366},
    {-0.428896301583791923408573538692, 0, 0, 0, 0, -4.69762141536116384314449447206,
     7.68342119606259904184240953878, 4.06898981839711007970285354331, 0.356727187455281109270669543021,
     0, 0, 0, -0.139902416515901462129418009734e-2, 2.9475147891527723389556272149,
     -9.15095847217987001081870187138},
};

static const double Bw[NS] = {B0, 0, 0, 0, 0, B5, B6, B7, B8, B9, B10, B11};

/* The 5th-order estimator: b minus a 5th-order weight vector. */
static const double E5[NS] = {
    0.1312004499419488073250102996e-1, 0, 0, 0, 0, -1.225156446376204440720569753,
    -0.4957589496572501915214079952, 1.664377182454986536961530415, -0.3503288487499736816887290,
    0.3341791187130174790297318841, 0.8192320648511571246570742613e-1, -0.2235530786388629525884427845e-1,
};

/* The 3rd-order estimator: b minus the 3rd-order weights (31/127, 12675/17272 at stage 8, 3/136). */
static const double E3[NS] = {
    B0 - 0.244094488188976377952755905512, 0, 0, 0, 0, B5, B6, B7, B8 - 0.733846688281611857341361741547,
    B9, B10, B11 - 0.220588235294117647058823529412e-1,
};

/* Dense output: q(3+r) = h sum_j D[r][j] k_j. */
static const double D[4][NS] = {
    {-8.4289382761090128651353491142, 0, 0, 0, 0, 0.56671495351937776962531783590,
     -3.0689499459498916912704704727, 2.3846676565120698287753134976, 2.1170345824450282767155149949,
     -0.87139158377797299206789907490, 2.2404374302607882749540472165, 0.63157877876946881815570249290,
     -0.88990336451333310820673977400e-1, 18.148505520854727256656404962, -9.194632392478355400045195936,
     -4.4360363875948939664310572000},
    {10.42750864257913460341310501009, 0, 0, 0, 0, 242.28349177525818288430175319,
     165.20045171727028198505394887, -374.54675472269020238830791215, -22.113666853125306036205892,
     7.733432668472263838965751, -30.674084731089398182053959, -9.332130526430227872956967217,
     15.697238121770843886135, -31.139403219565177677585, -9.352924358844478386573,
     35.816841486394083752452},
    {19.985053242002433820987653617, 0, 0, 0, 0, -387.03730874935176555105901742,
     -189.17813819516756882838328328, 527.80815920542364900561016686, -11.573902539959630126118,
     6.8812326946963000169669266, -1.0006050966910838403183861, 0.77771377980534432092869265740,
     -2.778205752353508406594771, -60.196695231264120758252, 84.320405506677161036681,
     11.992291136182789328028},
    {-25.693933462703749003312586129, 0, 0, 0, 0, -154.18974869023643374053993627,
     -231.52937917604549567536039109, 357.63911791061412378285349910, 93.405324183624300100390,
     -37.458323136451633116857531, 104.099649508962300451472, 29.840293426660503123344,
     -43.533456590011143754432, 96.324553959188282948349, -39.177261675615439165,
     -149.72683625798562581422},
};

/* Sparsity: in row i of A the nonzero entries are column 0 and columns LO[i] .. i-1 (a few zeros
 * among those are multiplied through); b, e5 and e3 have the pattern of row 12 (LO[12] .. 11), d
 * that of column 0 and LO_D .. 15. The sums skip the rest (a test checks that only zeros are). */
static const int LO[NS] = {1, 1, 1, 2, 2, 3, 3, 3, 3, 3, 3, 3, 5, 6, 5, 5};
#define LO_D 5

static const vi_ode_tableau TABLEAU = {C, A, Bw, E5, E3, D, LO, LO_D};

const vi_ode_tableau *vi_ode_method(void) { return &TABLEAU; }

/* Step-size controller (HNW II.4): h_new = h min(FAC_MAX, max(FAC_MIN, SAFETY err^(-1/8))). */
#define SAFETY 0.9
#define FAC_MIN 0.2
#define FAC_MAX 5.0
#define STRETCH 1.01 /* a step ending within 1 % of h before t_stop is stretched to t_stop */
#define LOW_ORDER_TARGET 0.25 /* the error a step size from an order below 8 aims at */

typedef vi_ode_span span;

/* The parts the profile of `vibroimpact bench` names by function (an attempted step, the event search's
 * root finding) are kept out of line; each is called once per attempt or per event. */
#if defined(__GNUC__)
#define PART __attribute__((noinline))
#else
#define PART
#endif

static int finite_n(const double *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static void copy_n(double *dst, const double *src, int n)
{
    for (int i = 0; i < n; i++) dst[i] = src[i];
}

static void rhs(const vi_ode_problem *p, vi_ode_stats *st, double t, const double *x, double *dx)
{
    p->rhs(t, x, dx, p->user);
    st->rhs_evals++;
}

static int guards(const vi_ode_problem *p, vi_ode_stats *st, double t, const double *x, double *g)
{
    p->guards(t, x, g, p->user);
    st->guard_evals++;
    return finite_n(g, p->ng);
}

/* The component loops of the stages run over a fixed number of LANES (2 when n <= 2, else
 * VI_ODE_MAX_N): a compile-time length the compiler unrolls into registers. The functions taking
 * `lanes` are inline and called with a constant. Lanes beyond n hold zeros in every stage
 * (vi_ode_init zeroes the state, rhs writes n values), so they stay zero. */
#define LANES(n) ((n) <= 2 ? 2 : VI_ODE_MAX_N)

/* UNROLLED: the loop after it is unrolled completely (GCC, Clang), so that the stage index, and with it
 * the coefficients and the bounds of the sums, are constants; the sums are the same, in the same order. */
#if defined(__GNUC__)
#define UNROLLED _Pragma("GCC unroll 16")
#else
#define UNROLLED
#endif

/* sum[c] = w[0] k[0][c] + sum_{j = lo}^{hi - 1} w[j] k[j][c] */
static inline void combine(const double *w, int lo, int hi, const double k[NS][VI_ODE_MAX_N], double *sum, int lanes)
{
    double acc[VI_ODE_MAX_N];
    for (int c = 0; c < lanes; c++) acc[c] = w[0] * k[0][c];
    UNROLLED
    for (int j = lo; j < hi; j++) {
        double a = w[j];
        for (int c = 0; c < lanes; c++) acc[c] += a * k[j][c];
    }
    for (int c = 0; c < lanes; c++) sum[c] = acc[c];
}

/* Stage i of the step in sp (t0, x0, h): k_i = f(t0 + c_i h, x0 + h sum_{j<i} a_ij k_j). */
static inline void stage(const vi_ode_problem *p, vi_ode_stats *st, span *sp, int i, double h, int lanes)
{
    double y[VI_ODE_MAX_N];
    combine(A[i], LO[i], i, sp->k, y, lanes);
    for (int c = 0; c < lanes; c++) y[c] = sp->x0[c] + h * y[c];
    rhs(p, st, sp->t0 + C[i] * h, y, sp->k[i]);
}

/* Stages 2..12 of a step of size h from (sp->t0, sp->x0) with k[0] set; x1 and the sums of the
 * two estimators. */
static inline void attempt(const vi_ode_problem *p, vi_ode_stats *st, span *sp, double h, double *e5, double *e3,
                           int lanes)
{
    double sb[VI_ODE_MAX_N];
    UNROLLED
    for (int i = 1; i < S_STEP; i++) stage(p, st, sp, i, h, lanes);
    combine(Bw, LO[S_END], S_STEP, sp->k, sb, lanes);
    combine(E5, LO[S_END], S_STEP, sp->k, e5, lanes);
    combine(E3, LO[S_END], S_STEP, sp->k, e3, lanes);
    for (int c = 0; c < lanes; c++) {
        sp->x1[c] = sp->x0[c] + h * sb[c];
        e5[c] *= h;
        e3[c] *= h;
    }
}

PART static void attempt_2(const vi_ode_problem *p, vi_ode_stats *st, span *sp, double h, double *e5, double *e3)
{
    attempt(p, st, sp, h, e5, e3, 2);
}

PART static void attempt_max(const vi_ode_problem *p, vi_ode_stats *st, span *sp, double h, double *e5, double *e3)
{
    attempt(p, st, sp, h, e5, e3, VI_ODE_MAX_N);
}

/* The three extra stages and the coefficients q of the dense output of a step. */
static inline int dense_build_lanes(span *sp, const vi_ode_problem *p, vi_ode_stats *st, int lanes)
{
    int n = p->n;
    double h = sp->t1 - sp->t0;
    UNROLLED
    for (int i = S_DENSE; i < NS; i++) {
        stage(p, st, sp, i, h, lanes);
        if (!finite_n(sp->k[i], n)) return VI_ODE_ERR_NONFINITE;
    }
    for (int c = 0; c < lanes; c++) {
        double q0 = sp->x1[c] - sp->x0[c];
        double q1 = h * sp->k[0][c] - q0;
        sp->q[0][c] = q0;
        sp->q[1][c] = q1;
        sp->q[2][c] = q0 - h * sp->k[S_END][c] - q1;
    }
    UNROLLED
    for (int r = 0; r < 4; r++) {
        combine(D[r], LO_D, NS, sp->k, sp->q[3 + r], lanes);
        for (int c = 0; c < lanes; c++) sp->q[3 + r][c] *= h;
    }
    sp->dense_ready = 1;
    st->dense_builds++;
    return VI_ODE_OK;
}

static int dense_build(span *sp, const vi_ode_problem *p, vi_ode_stats *st)
{
    if (sp->dense_ready) return VI_ODE_OK;
    return LANES(p->n) == 2 ? dense_build_lanes(sp, p, st, 2) : dense_build_lanes(sp, p, st, VI_ODE_MAX_N);
}

/* Evaluate the built dense output at t in [t0, t1] (and x' when dx != NULL); the step ends are
 * returned exactly. From the inside out: a_l = q_l + w a_(l+1), w alternating theta (l odd) and
 * theta1 = 1 - theta (l even); the derivatives d_l = da_l/dtheta follow (theta1' = -1). */
static void dense_eval(const span *sp, int n, double t, double *x, double *dx)
{
    double h = sp->t1 - sp->t0, th = (t - sp->t0) / h, th1 = 1.0 - th;
    for (int c = 0; c < n; c++) {
        double a5 = sp->q[5][c] + th * sp->q[6][c];
        double a4 = sp->q[4][c] + th1 * a5;
        double a3 = sp->q[3][c] + th * a4;
        double a2 = sp->q[2][c] + th1 * a3;
        double a1 = sp->q[1][c] + th * a2;
        double a0 = sp->q[0][c] + th1 * a1;
        x[c] = t == sp->t1 ? sp->x1[c] : t == sp->t0 ? sp->x0[c] : sp->x0[c] + th * a0;
        if (dx) {
            double d5 = sp->q[6][c];
            double d4 = -a5 + th1 * d5;
            double d3 = a4 + th * d4;
            double d2 = -a3 + th1 * d3;
            double d1 = a2 + th * d2;
            double d0 = -a1 + th1 * d1;
            dx[c] = (a0 + th * d0) / h;
        }
    }
}

/* ---------------------------------------------------------------------------------------------
 * Problem check, start
 * ------------------------------------------------------------------------------------------- */
static int fail_msg(char *msg, size_t size, const char *text, double value)
{
    if (msg && size) vi_snprintf(msg, size, "%s (got %g)", text, value);
    return VI_ODE_ERR_ARGS;
}

int vi_ode_check(const vi_ode_problem *p, char *msg, size_t size)
{
    if (!p) return fail_msg(msg, size, "no problem given", 0.0);
    if (p->n < 1 || p->n > VI_ODE_MAX_N) return fail_msg(msg, size, "n must be in 1..VI_ODE_MAX_N", p->n);
    if (p->ng < 0 || p->ng > VI_ODE_MAX_G) return fail_msg(msg, size, "ng must be in 0..VI_ODE_MAX_G", p->ng);
    if (!p->rhs) return fail_msg(msg, size, "rhs is NULL", 0.0);
    if (p->ng > 0 && !p->guards) return fail_msg(msg, size, "guards is NULL while ng > 0", p->ng);
    if (!(p->rtol > 0.0 && p->rtol < 1.0)) return fail_msg(msg, size, "rtol must be in (0, 1)", p->rtol);
    for (int i = 0; i < p->n; i++)
        if (!(p->atol[i] > 0.0 && isfinite(p->atol[i])))
            return fail_msg(msg, size, "atol[i] must be finite and > 0", p->atol[i]);
    if (!(p->max_step >= 0.0 && isfinite(p->max_step)))
        return fail_msg(msg, size, "max_step must be finite and >= 0", p->max_step);
    if (!(p->h_min >= 0.0 && isfinite(p->h_min))) return fail_msg(msg, size, "h_min must be finite and >= 0", p->h_min);
    if (!(p->h_fixed >= 0.0 && isfinite(p->h_fixed)))
        return fail_msg(msg, size, "h_fixed must be finite and >= 0", p->h_fixed);
    if (!(p->h_rho_max >= 0.0 && isfinite(p->h_rho_max)))
        return fail_msg(msg, size, "h_rho_max must be finite and >= 0", p->h_rho_max);
    if (p->h_rho_max > 0.0 && !p->spectral_radius)
        return fail_msg(msg, size, "spectral_radius is NULL while h_rho_max > 0", p->h_rho_max);
    if (p->guard_samples < 0 || p->guard_samples > VI_ODE_MAX_SAMPLES)
        return fail_msg(msg, size, "guard_samples must be in 0..VI_ODE_MAX_SAMPLES", p->guard_samples);
    for (int i = 0; i < p->ng; i++)
        if (!(p->arm_eps[i] >= 0.0 && isfinite(p->arm_eps[i])))
            return fail_msg(msg, size, "arm_eps[i] must be finite and >= 0", p->arm_eps[i]);
    return VI_ODE_OK;
}

/* RMS norm of v scaled by 1/inv_sc. */
static double norm(const double *v, const double *inv_sc, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        double r = v[i] * inv_sc[i];
        s += r * r;
    }
    return sqrt(s / n);
}

/* err^(-1/8) by three square roots (cheaper than pow, and exact to rounding). */
static double inv_root8(double err) { return 1.0 / sqrt(sqrt(sqrt(err))); }

/* Hairer's starting step size (HNW I, II.4): from ||x0||, ||f0|| and a difference quotient of f. */
static double initial_step(const vi_ode_problem *p, vi_ode_stats *st, double t0, const double *x0, const double *f0)
{
    int n = p->n;
    double isc[VI_ODE_MAX_N], x1[VI_ODE_MAX_N], f1[VI_ODE_MAX_N], df[VI_ODE_MAX_N];
    for (int i = 0; i < n; i++) isc[i] = 1.0 / (p->atol[i] + p->rtol * fabs(x0[i]));
    double d0 = norm(x0, isc, n), d1 = norm(f0, isc, n);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (p->max_step > 0.0 && h0 > p->max_step) h0 = p->max_step;
    for (int i = 0; i < n; i++) x1[i] = x0[i] + h0 * f0[i];
    rhs(p, st, t0 + h0, x1, f1);
    if (!finite_n(f1, n)) return h0;
    for (int i = 0; i < n; i++) df[i] = (f1[i] - f0[i]) / h0;
    double d2 = norm(df, isc, n), dm = fmax(d1, d2);
    double h1 = dm <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / dm, 1.0 / VI_ODE_ORDER);
    return fmin(100.0 * h0, h1);
}

int vi_ode_init(vi_ode *s, const vi_ode_problem *p, double t0, const double *x0, double h0, unsigned int hold)
{
    if (!s || vi_ode_check(p, NULL, 0) != VI_ODE_OK || !x0 || !isfinite(t0) || !(h0 >= 0.0 && isfinite(h0)))
        return VI_ODE_ERR_ARGS;
    if (!finite_n(x0, p->n)) return VI_ODE_ERR_ARGS;
    /* f, g and the first step size first: when one of them fails, *s is left as it was */
    double x[VI_ODE_MAX_N], f[VI_ODE_MAX_N] = {0}, g[VI_ODE_MAX_G] = {0};
    vi_ode_stats st = {0};
    copy_n(x, x0, p->n); /* x0 may point into *s (e.g. s->ev_x) */
    rhs(p, &st, t0, x, f);
    if (!finite_n(f, p->n)) return VI_ODE_ERR_NONFINITE;
    if (p->ng > 0 && !guards(p, &st, t0, x, g)) return VI_ODE_ERR_NONFINITE;
    double h = p->h_fixed > 0.0 ? p->h_fixed : h0 > 0.0 ? h0 : initial_step(p, &st, t0, x, f);
    if (p->h_fixed == 0.0 && p->max_step > 0.0 && h > p->max_step) h = p->max_step;
    if (!(h > 0.0 && isfinite(h))) return VI_ODE_ERR_HMIN; /* Hairer's estimate when |f| overflows its scale */
    memset(s, 0, sizeof *s);
    s->st = st;
    s->n = p->n;
    s->ng = p->ng;
    s->t = s->t_old = t0;
    copy_n(s->x, x, p->n);
    copy_n(s->x_old, x, p->n);
    copy_n(s->f, f, p->n);
    if (p->ng > 0) {
        copy_n(s->g, g, p->ng);
        for (int i = 0; i < p->ng; i++)
            if (s->g[i] > p->arm_eps[i] && !(hold & (1u << i))) s->armed |= 1u << i;
    }
    s->h = h;
    return VI_ODE_OK;
}

int vi_ode_restart(vi_ode *s, const vi_ode_problem *p, double t0, const double *x0, double h0, unsigned int hold)
{
    if (!s) return VI_ODE_ERR_ARGS;
    vi_ode_stats keep = s->st;
    int r = vi_ode_init(s, p, t0, x0, h0, hold);
    if (r != VI_ODE_OK) return r; /* s is as it was, its statistics too */
    vi_ode_stats *st = &s->st;
    st->attempts += keep.attempts;
    st->accepted += keep.accepted;
    st->rejected += keep.rejected;
    st->rhs_evals += keep.rhs_evals;
    st->guard_evals += keep.guard_evals;
    st->dense_builds += keep.dense_builds;
    st->root_iters += keep.root_iters;
    st->events += keep.events;
    return r;
}

/* ---------------------------------------------------------------------------------------------
 * Event location
 * ------------------------------------------------------------------------------------------- */

/* Bit mask of the guards in `set` with g <= 0. */
static unsigned int nonpositive(const double *g, int ng, unsigned int set)
{
    unsigned int m = 0;
    for (int i = 0; i < ng; i++)
        if ((set & (1u << i)) && g[i] <= 0.0) m |= 1u << i;
    return m;
}

/* The time to probe next in the bracket [a, b] (tol: 1 or 2 ulps of it) of the guards in cand, with
 * values ga at a and gb at b: the Illinois estimate (weights wa, wb) of the guard that crosses first
 * by linear estimate (ties: lowest index), or the midpoint when two iterations did not halve the
 * bracket (w2: its width then); at least tol inside it. */
static double probe_time(double a, double b, double tol, double w2, double wa, double wb, const double *ga,
                         const double *gb, int ng, unsigned int cand)
{
    int best = -1;
    double frac = 2.0;
    for (int i = 0; i < ng; i++) {
        if (!(cand & (1u << i)) || gb[i] > 0.0) continue;
        double f = ga[i] / (ga[i] - gb[i]);
        if (f < frac) frac = f, best = i;
    }
    double tm;
    if (b - a > 0.5 * w2)
        tm = a + 0.5 * (b - a);
    else {
        double fa = wa * ga[best], fb = wb * gb[best];
        tm = a + (b - a) * (fa / (fa - fb));
    }
    /* an estimate at an end probes just beside it, which closes the bracket when the root is there */
    if (b - a <= 2.0 * tol)
        tm = a + 0.5 * (b - a);
    else if (tm < a + tol)
        tm = a + tol;
    else if (tm > b - tol)
        tm = b - tol;
    return tm;
}

/* Find the first root in [a, b] of the guards in cand (all > 0 at a, at least one <= 0 at b).
 * On success ev_t = b, ev_t_lo = a of the final bracket, ev_fired, ev_x. */
PART static int root_search(vi_ode *s, span *sp, const vi_ode_problem *p, double a, double b, const double *g_a,
                       const double *g_b, unsigned int cand)
{
    int n = p->n, ng = p->ng;
    double ga[VI_ODE_MAX_G], gb[VI_ODE_MAX_G], gm[VI_ODE_MAX_G], xm[VI_ODE_MAX_N];
    copy_n(ga, g_a, ng);
    copy_n(gb, g_b, ng);
    double wa = 1.0, wb = 1.0;               /* Illinois weights of the two ends */
    int side = 0;                            /* -1: b moved last time, +1: a moved last time */
    double w1 = INFINITY, w2 = INFINITY;     /* bracket widths one and two iterations ago */
    for (int iter = 0;; iter++) {
        double tol = fmax(DBL_EPSILON * fmax(fabs(a), fabs(b)), DBL_MIN); /* 1 or 2 ulps */
        if (b - a <= tol) break;
        if (iter >= VI_ODE_MAX_ROOT_ITERS) return VI_ODE_ERR_ROOT;
        double tm = probe_time(a, b, tol, w2, wa, wb, ga, gb, ng, cand);
        w2 = w1;
        w1 = b - a;
        dense_eval(sp, n, tm, xm, NULL);
        s->st.root_iters++;
        if (!guards(p, &s->st, tm, xm, gm)) return VI_ODE_ERR_NONFINITE;
        if (nonpositive(gm, ng, cand)) { /* a crossing in [a, tm] */
            b = tm;
            copy_n(gb, gm, ng);
            wb = 1.0;
            if (side == -1) wa *= 0.5;
            side = -1;
        } else {
            a = tm;
            copy_n(ga, gm, ng);
            wa = 1.0;
            if (side == 1) wb *= 0.5;
            side = 1;
        }
    }
    s->ev_t = b;
    s->ev_t_lo = a;
    s->ev_fired = nonpositive(gb, ng, cand);
    dense_eval(sp, n, b, s->ev_x, NULL);
    return VI_ODE_EVENT;
}

/* Scan the step for the first falling crossing of an armed guard (see vi_ode.h, EVENTS).
 * g_end: the guards at t1 (already evaluated). Returns VI_ODE_OK with *armed updated, or the event. */
static int event_search(vi_ode *s, span *sp, const vi_ode_problem *p, const double *g_end, unsigned int *armed)
{
    int n = p->n, ng = p->ng, m = p->guard_samples;
    double g_prev[VI_ODE_MAX_G], g_j[VI_ODE_MAX_G], x_j[VI_ODE_MAX_N];
    double t_prev = sp->t0;
    copy_n(g_prev, s->g, ng);
    for (int j = 1; j <= m + 1; j++) {
        double t_j;
        if (j <= m) {
            int r = dense_build(sp, p, &s->st);
            if (r != VI_ODE_OK) return r;
            t_j = sp->t0 + (sp->t1 - sp->t0) * ((double)j / (m + 1));
            dense_eval(sp, n, t_j, x_j, NULL);
            if (!guards(p, &s->st, t_j, x_j, g_j)) return VI_ODE_ERR_NONFINITE;
        } else {
            t_j = sp->t1;
            copy_n(g_j, g_end, ng);
        }
        unsigned int cand = 0;
        for (int i = 0; i < ng; i++)
            if ((*armed & (1u << i)) && g_prev[i] > 0.0) cand |= 1u << i;
        if (nonpositive(g_j, ng, cand)) {
            int r = dense_build(sp, p, &s->st);
            if (r != VI_ODE_OK) return r;
            return root_search(s, sp, p, t_prev, t_j, g_prev, g_j, cand);
        }
        for (int i = 0; i < ng; i++)
            if (g_j[i] > p->arm_eps[i]) *armed |= 1u << i;
        t_prev = t_j;
        copy_n(g_prev, g_j, ng);
    }
    return VI_ODE_OK;
}

/* ---------------------------------------------------------------------------------------------
 * The step
 * ------------------------------------------------------------------------------------------- */

/* The bounds of a step from s->t: *h_lim the largest (max_step, else none), *h_min the shortest (16
 * ulps of t, or the problem's h_min when larger). */
static void step_bounds(const vi_ode *s, const vi_ode_problem *p, double *h_lim, double *h_min)
{
    *h_lim = p->max_step > 0.0 ? p->max_step : INFINITY;
    *h_min = 16.0 * DBL_EPSILON * fabs(s->t);
    if (p->h_min > *h_min) *h_min = p->h_min;
}

/* The stability bound of a step from s->t (STEPS): h_rho_max / rho(t, x), never below h_min (no step
 * resolves time below it; rho = inf: h_min); INFINITY without a bound or where rho is 0 or NaN. */
static double stable_step(const vi_ode *s, const vi_ode_problem *p, double h_min)
{
    if (!(p->h_rho_max > 0.0) || p->h_fixed > 0.0) return INFINITY;
    double rho = p->spectral_radius(s->t, s->x, p->rho_env);
    return rho > 0.0 ? fmax(p->h_rho_max / rho, h_min) : INFINITY;
}

/* Are the n components of each of the stages 0 .. last - 1 exactly 0? */
static int stages_zero(const span *sp, int last, int n)
{
    for (int i = 0; i < last; i++)
        for (int c = 0; c < n; c++)
            if (sp->k[i][c] != 0.0) return 0;
    return 1;
}

/* The span the new step is built in (committed by flipping s->cur), starting at the current point. */
static span *begin_span(vi_ode *s, int n)
{
    span *sp = &s->sp[1 - s->cur];
    sp->t0 = s->t;
    sp->dense_ready = 0;
    copy_n(sp->x0, s->x, n);
    copy_n(sp->k[0], s->f, n);
    return sp;
}

/* The end t1 of a step of size *h from s->t, with *h made the exact span t1 - t: stretched to t_stop
 * when that lies within STRETCH h (*clipped = 1), else kept within h_lim. */
static double step_end(const vi_ode *s, double t_stop, double h_lim, double *h, int *clipped)
{
    double t1;
    *clipped = 0;
    if (t_stop - s->t <= STRETCH * *h && t_stop - s->t <= h_lim) {
        *h = t_stop - s->t;
        t1 = t_stop;
        *clipped = 1;
    } else {
        t1 = s->t + *h;
        if (t1 - s->t > h_lim) t1 = nextafter(t1, -INFINITY); /* max_step holds exactly */
        *h = t1 - s->t; /* exact: the step really spans [t, t1], so t does not drift by roundings */
    }
    return t1;
}

/* The error of an attempt, ||e5||^2 / sqrt(||e5||^2 + 0.01 ||e3||^2) in RMS norms scaled by the
 * tolerances at the larger of |x| at both ends. */
static double attempt_error(const vi_ode *s, const vi_ode_problem *p, const span *sp, const double *e5,
                            const double *e3)
{
    int n = p->n;
    double n5 = 0.0, n3 = 0.0;
    for (int c = 0; c < n; c++) {
        double ax = fabs(s->x[c]), ax1 = fabs(sp->x1[c]);
        double isc = 1.0 / (p->atol[c] + p->rtol * (ax > ax1 ? ax : ax1));
        double r5 = e5[c] * isc, r3 = e3[c] * isc;
        n5 += r5 * r5;
        n3 += r3 * r3;
    }
    double den = n5 + 0.01 * n3;
    return den > 0.0 ? n5 / sqrt(den * n) : 0.0;
}

/* The step size proposed after a step of size h accepted with error err (HNW II.4). */
static double next_step_size(const vi_ode *s, const vi_ode_problem *p, double h, double err, int rejections,
                             int clipped, double h_lim)
{
    if (p->h_fixed > 0.0) return p->h_fixed;
    double fac = err > 0.0 ? SAFETY * inv_root8(err) : FAC_MAX;
    fac = fac > FAC_MAX ? FAC_MAX : fac < FAC_MIN ? FAC_MIN : fac;
    if (rejections > 0 && fac > 1.0) fac = 1.0;
    double h_prop = h * fac;
    /* a step shortened to reach t_stop says little about the step size */
    if (clipped && rejections == 0 && h_prop < s->h) h_prop = s->h;
    if (h_prop > h_lim) h_prop = h_lim;
    return h_prop;
}

/* What an attempted step left: accepted or not, and what the step after it is to be. */
typedef struct {
    double err, h_next; /* the accepted step's error and the step size proposed after it */
    int rejections;     /* attempts rejected before it */
} step_result;

/* The step size after a rejected attempt of size h with error err (bad: err or the step not finite:
 * FAC_MIN h). After a rejected attempt of size h_prev > h with error err_prev > err whose ratio shows
 * an order q = ln(err_prev/err) / ln(h_prev/h) below the method's 8 (where the solution is not smooth:
 * a contact beginning at the step's start, with a force growing like a power 3/2 of the indentation,
 * leaves an error like h^2.5), the step that order asks for: h (0.25/err)^(1/q), q at least 1; else
 * h 0.9 err^(-1/8) (HNW II.4). Either between FAC_MIN^2 h and 0.9 h. */
static double shrunk_step(double h, double err, int bad, double h_prev, double err_prev)
{
    if (bad) return FAC_MIN * h;
    double fac = SAFETY * inv_root8(err);
    if (h_prev > h && err_prev > err) {
        double q = log(err_prev / err) / log(h_prev / h);
        if (q < VI_ODE_ORDER) fac = pow(LOW_ORDER_TARGET / err, 1.0 / fmax(q, 1.0));
    }
    return h * (fac < FAC_MIN * FAC_MIN ? FAC_MIN * FAC_MIN : fac > SAFETY ? SAFETY : fac);
}

/* Attempt steps from s->t, shrinking after each rejection, until one is accepted into sp (sp->t1,
 * sp->x1, its last stage the derivative at t1): VI_ODE_OK with *r filled, or an error status. */
static int accepted_step(vi_ode *s, const vi_ode_problem *p, span *sp, double t_stop, step_result *r)
{
    int n = p->n, fixed = p->h_fixed > 0.0;
    double h_lim, h_min;
    step_bounds(s, p, &h_lim, &h_min);
    /* At an exact rest (f = 0) a step whose stages all come out 0 is exact whatever its size (there is
     * no deviation to grow): it is tried without the stability bound first. */
    double h_stable = stable_step(s, p, h_min);
    int at_rest = h_stable < h_lim && stages_zero(sp, 1, n);
    if (!at_rest && h_stable < h_lim) h_lim = h_stable;
    double h = fixed ? p->h_fixed : s->h;
    /* the last rejected attempt of the first step after a start (h_prev 0: none, or not finite) */
    double h_prev = 0.0, err_prev = 0.0;
    for (r->rejections = 0;;) {
        if (h > h_lim) h = h_lim;
        /* a step under 16 ulps of t does not resolve time (t + h may round to t): the shortest is h_min */
        if (!fixed && h < h_min && h_min <= h_lim) h = h_min;
        int clipped;
        double t1 = step_end(s, t_stop, h_lim, &h, &clipped);
        if (!(h > 0.0)) return VI_ODE_ERR_HMIN; /* fixed or max_step below the rounding of t */
        s->st.attempts++;
        double e5[VI_ODE_MAX_N], e3[VI_ODE_MAX_N];
        if (LANES(n) == 2)
            attempt_2(p, &s->st, sp, h, e5, e3);
        else
            attempt_max(p, &s->st, sp, h, e5, e3);
        if (at_rest && !stages_zero(sp, S_STEP, n)) { /* not a rest after all: again within the bound */
            at_rest = 0, h_lim = h_stable;
            s->st.rejected++; /* a trial: the step-size control goes on as if it had not been */
            continue;
        }
        r->err = attempt_error(s, p, sp, e5, e3);
        int bad = !isfinite(r->err) || !finite_n(sp->x1, n);
        if (!bad && (fixed || r->err <= 1.0)) {
            rhs(p, &s->st, t1, sp->x1, sp->k[S_END]);
            bad = !finite_n(sp->k[S_END], n);
        }
        if (!bad && (fixed || r->err <= 1.0)) { /* accepted */
            sp->t1 = t1;
            r->h_next = next_step_size(s, p, h, r->err, r->rejections, clipped, h_lim);
            return VI_ODE_OK;
        }
        s->st.rejected++;
        if (fixed) return VI_ODE_ERR_NONFINITE;
        double h_next = shrunk_step(h, r->err, bad, h_prev, err_prev);
        h_prev = bad || s->have_step ? 0.0 : h, err_prev = r->err;
        h = h_next;
        if (++r->rejections >= VI_ODE_MAX_REJECTS) return bad ? VI_ODE_ERR_NONFINITE : VI_ODE_ERR_REJECTS;
        if (h < h_min) return bad ? VI_ODE_ERR_NONFINITE : VI_ODE_ERR_HMIN;
    }
}

/* Make the step in sp the current point (status: VI_ODE_OK, or VI_ODE_EVENT with an event pending). */
static void commit_step(vi_ode *s, const span *sp, int n, const step_result *r, unsigned int armed, int status)
{
    s->cur = 1 - s->cur;
    s->have_step = 1;
    s->armed = armed;
    s->st.accepted++;
    s->err = r->err;
    s->h = r->h_next;
    s->rejected_last = r->rejections;
    s->t_old = sp->t0;
    s->t = sp->t1;
    copy_n(s->x_old, sp->x0, n);
    copy_n(s->x, sp->x1, n);
    copy_n(s->f, sp->k[S_END], n);
    if (status == VI_ODE_EVENT) {
        s->event_pending = 1;
        s->st.events++;
    }
}

int vi_ode_step(vi_ode *s, const vi_ode_problem *p, double t_stop)
{
    if (!s || !p || s->n != p->n || s->ng != p->ng || s->n > VI_ODE_MAX_N || s->event_pending ||
        !(t_stop > s->t) || !(s->h > 0.0) || (s->cur != 0 && s->cur != 1))
        return VI_ODE_ERR_ARGS;
    span *sp = begin_span(s, p->n);
    step_result r;
    int status = accepted_step(s, p, sp, t_stop, &r);
    if (status != VI_ODE_OK) return status;
    /* Guards at the new point, then the event search; the state changes only when all succeeded. */
    double g_end[VI_ODE_MAX_G];
    unsigned int armed = s->armed;
    if (p->ng > 0) {
        if (!guards(p, &s->st, sp->t1, sp->x1, g_end)) return VI_ODE_ERR_NONFINITE;
        status = event_search(s, sp, p, g_end, &armed);
        if (status < 0) return status;
        copy_n(s->g, g_end, p->ng);
    }
    commit_step(s, sp, p->n, &r, armed, status);
    return status;
}

/* ---------------------------------------------------------------------------------------------
 * Dense output of the last accepted step
 * ------------------------------------------------------------------------------------------- */
int vi_ode_dense(vi_ode *s, const vi_ode_problem *p, double t, double *x, double *dx)
{
    if (!s || !p || !x || s->n != p->n || !s->have_step || (s->cur != 0 && s->cur != 1) ||
        !(t >= s->t_old && t <= s->t))
        return VI_ODE_ERR_ARGS;
    span *sp = &s->sp[s->cur];
    int r = dense_build(sp, p, &s->st);
    if (r != VI_ODE_OK) return r;
    dense_eval(sp, p->n, t, x, dx);
    return VI_ODE_OK;
}

const char *vi_ode_status_text(int status)
{
    switch (status) {
    case VI_ODE_OK: return "step accepted";
    case VI_ODE_EVENT: return "step accepted, event located";
    case VI_ODE_ERR_ARGS: return "invalid problem, state or call";
    case VI_ODE_ERR_HMIN: return "step size underflow";
    case VI_ODE_ERR_NONFINITE: return "right-hand side or guards not finite";
    case VI_ODE_ERR_REJECTS: return "too many rejected steps";
    case VI_ODE_ERR_ROOT: return "event root search did not converge";
    default: return "unknown status";
    }
}
