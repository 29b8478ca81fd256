/* tsuji_table - writes src/model/vi_tsuji_table.inc, the table of alpha(e) of the exact damping (vi_laws.h):
 *
 *   vi_tsuji_table > src/model/vi_tsuji_table.inc
 *
 * On each piece of u = ln(e/(1 - e)) (VI_TSUJI_TABLE_PIECES of width VI_TSUJI_TABLE_WIDTH from
 * VI_TSUJI_TABLE_U_MIN), G = alpha sqrt(e)/(1 - e) at the N = VI_TSUJI_TABLE_DEGREE + 1 Chebyshev nodes
 * x_j = cos(pi (j + 1/2)/N), alpha from the integration (vi_tsuji_alpha_solve), and the coefficients
 * of the series that interpolates them, c_k = (2 - [k = 0])/N sum_j G(x_j) cos(pi k (j + 1/2)/N).
 * tests/test_laws.c checks the table against the integration. Exit status 1 when a solve fails. */
#include <math.h>
#include <stdio.h>

#include "vi_laws.h"

#define N (VI_TSUJI_TABLE_DEGREE + 1)

static const double pi = 3.14159265358979323846;

/* G at the nodes of piece i; -1 when a solve fails */
static int piece_values(int i, double G[N])
{
    double u0 = VI_TSUJI_TABLE_U_MIN + i * VI_TSUJI_TABLE_WIDTH;
    for (int j = 0; j < N; j++) {
        double u = u0 + 0.5 * VI_TSUJI_TABLE_WIDTH * (1.0 + cos(pi * (j + 0.5) / N));
        double e = 1.0 / (1.0 + exp(-u)), alpha;
        if (vi_tsuji_alpha_solve(e, &alpha) != 0) {
            fprintf(stderr, "no alpha for e = %.17g\n", e);
            return -1;
        }
        G[j] = alpha * sqrt(e) / (1.0 - e);
    }
    return 0;
}

int main(void)
{
    printf("/* vi_tsuji_table.inc - written by tools/tsuji_table.c (vi_tsuji_table > src/model/vi_tsuji_table.inc); "
           "do not edit.\n * The Chebyshev coefficients of G(u) = alpha sqrt(e)/(1 - e), u = ln(e/(1 - e)), on "
           "each piece of vi_laws.h. */\n");
    printf("static const double vi_tsuji_table[%d][%d] = {\n", VI_TSUJI_TABLE_PIECES, N);
    for (int i = 0; i < VI_TSUJI_TABLE_PIECES; i++) {
        double G[N];
        if (piece_values(i, G) != 0) return 1;
        printf("    {");
        for (int k = 0; k < N; k++) {
            long double sum = 0.0L;
            for (int j = 0; j < N; j++) sum += (long double)G[j] * cosl((long double)pi * k * (j + 0.5L) / N);
            double c = (double)((k == 0 ? 1.0L : 2.0L) * sum / N);
            printf("%s%.17g", k == 0 ? "" : (k % 4 == 0 ? ",\n     " : ", "), c);
        }
        printf("},\n");
    }
    printf("};\n");
    return 0;
}
