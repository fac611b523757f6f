/* The floor of the linear exact route (benchmarks/bench_kernel.py): a C loop that applies the
 * S affine step maps of one mesh period, y -> F_j y + h_j (2 x 2, damped, made up here), to a
 * state, period after period, and stores every sample, as the route's output needs (into memory
 * touched beforehand: the floor leaves out the page faults of a fresh output array).
 *
 * usage: kernel_floor S N_PERIODS    prints the CPU time per period in microseconds
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

int main(int argc, char **argv)
{
    long s = argc > 1 ? atol(argv[1]) : 64, periods = argc > 2 ? atol(argv[2]) : 20000, j, k;
    double *F = malloc((size_t)s * 4 * sizeof(double)), *h = malloc((size_t)s * 2 * sizeof(double));
    double *out = malloc((size_t)(s * periods + 1) * 2 * sizeof(double));
    double y0 = 1.0, y1 = 0.0, sum = 0.0;
    clock_t t0;
    if (!F || !h || !out) return 1;
    for (j = 0; j < s; j++) {   /* a damped rotation per step */
        double a = 6.283185307179586 * 0.7 / (double)s, d = 0.99;
        F[4 * j] = d * cos(a); F[4 * j + 1] = d * sin(a);
        F[4 * j + 2] = -d * sin(a); F[4 * j + 3] = d * cos(a);
        h[2 * j] = 1e-3; h[2 * j + 1] = 0.0;
    }
    for (k = 0; k < 2 * (s * periods + 1); k++) out[k] = 0.0;   /* pages touched before timing */
    t0 = clock();
    for (k = 0; k < periods; k++)
        for (j = 0; j < s; j++) {
            const double *f = F + 4 * j;
            double n0 = f[0] * y0 + f[1] * y1 + h[2 * j], n1 = f[2] * y0 + f[3] * y1 + h[2 * j + 1];
            out[2 * (k * s + j)] = y0;
            out[2 * (k * s + j) + 1] = y1;
            y0 = n0;
            y1 = n1;
        }
    {
        double us = (double)(clock() - t0) / CLOCKS_PER_SEC * 1e6 / (double)periods;
        for (k = 0; k < s * periods; k += 997) sum += out[2 * k];
        printf("%.6g\n", us + 0.0 * sum);
    }
    free(F);
    free(h);
    free(out);
    return 0;
}
