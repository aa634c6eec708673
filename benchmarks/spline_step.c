/* The cubic-spline step (Newmark beta = 1/6, gamma = 1/2) with a fixed number
 * of fixed-point sweeps per step, in plain C: the speed limit that the
 * benchmark measures splinestep against.  Same arithmetic as
 * splinestep.spline._spline_loop with iterations = SWEEPS.
 *
 * usage: spline_step PROBLEM STEPS SWEEPS REPEATS
 *   PROBLEM: kepler (mu = 0.6, t in [0, 50]) or rigid (I = 3, 2, 1, t in [0, 80])
 * prints: median ns per step over REPEATS runs, evaluations, final y and y'
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static inline void kepler(double t, const double *y, const double *yp, double *out) {
    (void)t; (void)yp;
    double r2 = y[0] * y[0] + y[1] * y[1];
    double w2 = 0.6 / (r2 * sqrt(r2));
    out[0] = -w2 * y[0];
    out[1] = -w2 * y[1];
}

static inline void rigid(double t, const double *w, const double *wp, double *out) {
    (void)t; (void)wp;
    const double i1 = 3.0, i2 = 2.0, i3 = 1.0;
    double a1 = w[2] * w[2] * (i2 - i3) * (i3 - i1) / (i1 * i2)
              + w[1] * w[1] * (i2 - i3) * (i1 - i2) / (i1 * i3);
    double a2 = w[0] * w[0] * (i3 - i1) * (i1 - i2) / (i2 * i3)
              + w[2] * w[2] * (i2 - i3) * (i3 - i1) / (i2 * i1);
    double a3 = w[1] * w[1] * (i1 - i2) * (i2 - i3) / (i3 * i1)
              + w[0] * w[0] * (i1 - i2) * (i3 - i1) / (i3 * i2);
    out[0] = a1 * w[0];
    out[1] = a2 * w[1];
    out[2] = a3 * w[2];
}

#define DEFINE_LOOP(NAME, RHS, M)                                              \
static long NAME(double t0, double tf, long n, int sweeps, double *y, double *yp) { \
    double ypp[M], base_y[M], base_yp[M], z[M], y_new[M], yp_new[M], g[M];    \
    double h = (tf - t0) / n, t = t0;                                          \
    long nfev = 0;                                                             \
    RHS(t0, y, yp, ypp); nfev++;                                               \
    for (long i = 0; i < n; i++) {                                             \
        double t_new = (i + 1 < n) ? t0 + (i + 1) * h : tf;                    \
        double dt = t_new - t, wy = dt * dt / 6.0, wyp = 0.5 * dt;             \
        for (int k = 0; k < M; k++) {                                          \
            base_y[k] = y[k] + dt * yp[k] + (dt * dt / 3.0) * ypp[k];          \
            base_yp[k] = yp[k] + wyp * ypp[k];                                 \
            z[k] = ypp[k];                                                     \
        }                                                                      \
        for (int s = 0; s < sweeps; s++) {                                     \
            for (int k = 0; k < M; k++) {                                      \
                y_new[k] = base_y[k] + wy * z[k];                              \
                yp_new[k] = base_yp[k] + wyp * z[k];                           \
            }                                                                  \
            RHS(t_new, y_new, yp_new, g); nfev++;                              \
            for (int k = 0; k < M; k++) {                                      \
                if (!(fabs(g[k]) < INFINITY)) { fprintf(stderr, "non-finite\n"); exit(1); } \
                z[k] = g[k];                                                   \
            }                                                                  \
        }                                                                      \
        for (int k = 0; k < M; k++) {                                          \
            y[k] = base_y[k] + wy * z[k];                                      \
            yp[k] = base_yp[k] + wyp * z[k];                                   \
            ypp[k] = z[k];                                                     \
        }                                                                      \
        t = t_new;                                                             \
    }                                                                          \
    return nfev;                                                               \
}

DEFINE_LOOP(loop_kepler, kepler, 2)
DEFINE_LOOP(loop_rigid, rigid, 3)

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (argc != 5) { fprintf(stderr, "usage: %s kepler|rigid STEPS SWEEPS REPEATS\n", argv[0]); return 2; }
    int is_kepler = strcmp(argv[1], "kepler") == 0;
    long n = atol(argv[2]);
    int sweeps = atoi(argv[3]), repeats = atoi(argv[4]);
    double times[64], y[3], yp[3];
    long nfev = 0;
    if (repeats > 64) repeats = 64;
    for (int r = 0; r < repeats; r++) {
        double start = now();
        if (is_kepler) {
            y[0] = 1.0; y[1] = 0.0; yp[0] = 0.0; yp[1] = 1.0;
            nfev = loop_kepler(0.0, 50.0, n, sweeps, y, yp);
        } else {
            y[0] = 1.0; y[1] = 0.01; y[2] = 0.01;
            yp[0] = 1e-4 / 3.0; yp[1] = -0.01; yp[2] = 0.01;
            nfev = loop_rigid(0.0, 80.0, n, sweeps, y, yp);
        }
        times[r] = now() - start;
    }
    qsort(times, repeats, sizeof(double), cmp);
    int m = is_kepler ? 2 : 3;
    printf("%.6f %ld", 1e9 * times[repeats / 2] / n, nfev);
    for (int k = 0; k < m; k++) printf(" %.17g", y[k]);
    for (int k = 0; k < m; k++) printf(" %.17g", yp[k]);
    printf("\n");
    return 0;
}
