/*
 * vi_profile.h - rolling over an irregular surface (paper Fig. 1b): the rigid constraint yb.
 *
 * A body of radius R (R1) rolls over a profile h(x) given as a table (x_i, h_i), x increasing,
 * linear between samples (VI_PROFILE_LINEAR) or the cubic spline through them (VI_PROFILE_CUBIC, see
 * below). The lowest point of the body, touching the profile without penetrating it, follows the
 * constraint
 *
 *     yb(x) = max over s in the profile with |s - x| <= R of [h(s) + sqrt(R^2 - (x - s)^2)] - R,
 *
 * the upper envelope of the circles around the vertices and the lines parallel to the segments at
 * distance R (segment tangents), minus R. It is computed once (vi_profile_create), in time and memory
 * linear in the rows: the pieces are taken in the order of the profile (the contact point moves
 * forward along the profile as the body does) and kept on a stack of sorted intervals, each carried
 * by one piece; a crossing of two pieces is located by a closed form (a bisection to the last bit
 * when that does not decide). The pieces:
 *
 *   vertex circle (x_i, h_i):  yb = h_i - d^2 / (R + sqrt(R^2 - d^2)),  d = x - x_i
 *   segment tangent i:         yb = h_i + s (x - x_i) + R (sqrt(1 + s^2) - 1),  s the segment's slope,
 *                              where the tangent point x + R s/sqrt(1 + s^2) lies on the segment.
 *
 * Evaluation (vi_profile_eval) only searches the interval (a binary search among the few that start in
 * x's part of the range, cut into parts of about eight intervals each; no allocation) and returns
 * yb and its first three derivatives in x. yb is continuous; its slope jumps (a kink) where the body
 * touches two points at once (it bridges a trough); vi_profile_next_kink finds them. A circle-line
 * switch is tangent (only the curvature jumps) and is no kink.
 *
 * Cubic (VI_PROFILE_CUBIC): h is the C2 cubic spline through the rows, with not-a-knot ends (the
 * third derivative continuous at the second and the last but one row: a cubic is reproduced
 * exactly; two rows give the line, three the parabola) or, for a periodic table, periodic ends (value,
 * slope and curvature continuous across the seam). Where the body touches the curve at one point s,
 * its centre lies on the normal at s: with h' = h'(s), w = 1 + h'^2,
 *
 *   x = X(s) = s - R h' / sqrt(w),   yb = h(s) + R (1/sqrt(w) - 1),   yb' = h'(s),
 *   yb'' = h'' / X',   X' = 1 - R h'' / w^(3/2)   (1 - R times the curvature),
 *
 * the curve offset by R along its normal, lowered by R. Where the curvature of a trough exceeds 1/R
 * (X' <= 0) the body cannot touch the curve; those parts are dropped, and the offsets of the parts on
 * either side cross where the body bridges the trough: a kink. Each spline segment's part with X' > 0
 * is a piece of the envelope (s found from x by Newton's method inside the part, safeguarded by
 * bisection), besides the circles around the end rows of a table that is not periodic; the envelope
 * of these pieces is built as for the polyline. A spline whose curvature stays below 1/R everywhere
 * gives a yb with a continuous second derivative and no kink.
 *
 * Range: without periodicity the profile exists on [x_first, x_last] only (the body touches nothing
 * beyond), and yb is defined there; outside, vi_profile_eval clamps and returns -1. With periodicity
 * the table is one period, L = x_last - x_first, and its last height must equal the first.
 *
 * Refused (with a message naming the file and line, or the position): a file that cannot be read,
 * a line that is not two numbers (the message quotes the fields found, names the separator seen and
 * the rule broken), a value that is not finite, x not strictly increasing (naming the line before),
 * an empty file, a file without data rows, one row, more than VI_PROFILE_ROWS_MAX rows, a periodic
 * table whose ends differ, a periodic table whose period is so short that the body spans more than
 * VI_PROFILE_ROWS_MAX rows of its copies, a profile with a step higher than the body can roll over
 * (yb would jump), and a wall so steep that yb is vertical in doubles (the body leaves it closer to
 * its corner than the spacing of doubles there: the rows, the slope and the limit are named). Every
 * loop is bounded.
 *
 * File format: two numbers a line, separated by blanks or tabs with at most one ';' or ',' among them;
 * a '\r' may end a line; a line that would read as one number with a decimal comma ("0,5") is refused
 * (never guessed). Lines
 * that are empty, blank or start with '#' after blanks are skipped; a UTF-8 byte-order mark before
 * the first line is skipped, a UTF-16 or UTF-32 one refused. Numbers are read by vi_strtod
 * (vi_text.h): as strtod reads them in the C locale, whatever the locale of the process (decimal
 * point '.'): decimal numbers of any length rounded to the nearest double, hexadecimal ones (0x1.8p-3),
 * and inf, infinity, nan, which are then refused as not finite, like a number beyond DBL_MAX.
 */
#ifndef VI_PROFILE_H
#define VI_PROFILE_H

#include <stddef.h>
#include <stdio.h>

typedef struct vi_profile vi_profile;

/* A slope jump of yb of at most this is no kink (tangent switches rounded to the last bits). */
#define VI_PROFILE_KINK_SLOPE 1e-9
/* Longest line of a profile file, and the most rows it may have. */
#define VI_PROFILE_LINE_MAX 4096
#define VI_PROFILE_ROWS_MAX 10000000

/* How the rows are joined: the values of the FMU's profile_interpolation. */
enum { VI_PROFILE_LINEAR = 1, VI_PROFILE_CUBIC = 2 };

/* From arrays (copied); name is used in messages. NULL on failure with the reason in msg. */
vi_profile *vi_profile_create(const double *x, const double *h, size_t n, double R, int periodic, const char *name,
                              char *msg, size_t msg_size);
/* The same with the rows joined as interpolation says (VI_PROFILE_LINEAR or VI_PROFILE_CUBIC). */
vi_profile *vi_profile_create_as(const double *x, const double *h, size_t n, double R, int periodic, int interpolation,
                                 const char *name, char *msg, size_t msg_size);
/* From a two-column text file at path. NULL on failure with the reason (file and line) in msg. */
vi_profile *vi_profile_load(const char *path, double R, int periodic, char *msg, size_t msg_size);
/* The same with the rows joined as interpolation says. */
vi_profile *vi_profile_load_as(const char *path, double R, int periodic, int interpolation, char *msg, size_t msg_size);
void vi_profile_free(vi_profile *p);
/* fopen(path, "r") of a path in UTF-8 (FMI's strings are UTF-8): on Windows, whose C library's fopen
 * takes the ANSI code page, through _wfopen of the path converted to UTF-16 (a path that is not
 * UTF-8 goes to fopen as it is). */
FILE *vi_profile_fopen(const char *path);

/* yb(x) and its derivatives: y[0] = yb [m], y[1] = yb', y[2] = yb'' [1/m], y[3] = yb''' [1/m^2]
 * (right-hand values at an interval boundary). 0, or -1 when x lies outside a non-periodic profile
 * (then the values at the nearer end). */
int vi_profile_eval(const vi_profile *p, double x, double y[4]);
/* The first kink beyond x in the direction dir (+1 or -1), a kink within 8 eps (|x| + period) of x
 * (rounding of the positions in other periods) counting as at x, not beyond; +-INFINITY if none. */
double vi_profile_next_kink(const vi_profile *p, double x, int dir);

/* Range [x_first, x_last] of the table, periodicity, largest |yb'|, the kinks in [x_first, x_last]
 * (one period), and the span of the table's heights, max h - min h [m]. */
double vi_profile_x_first(const vi_profile *p);
double vi_profile_x_last(const vi_profile *p);
int vi_profile_periodic(const vi_profile *p);
double vi_profile_max_slope(const vi_profile *p);
size_t vi_profile_kinks(const vi_profile *p);
double vi_profile_height_span(const vi_profile *p);

#endif
