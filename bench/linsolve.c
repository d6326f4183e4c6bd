/* Benchmark of the linsolve module: SpMV and filtered PCG on the implicit-Euler matrix
   A = M + h^2 K of a square cloth of n x n vertices (n = 16, 32, 64, 128), 1 m wide, areal
   density 0.1 kg/m^2, h = 1/60 s, with stretch (k = 5000 N/m), shear (k = 2500 N/m) and bend
   (k = 50 N/m) springs whose Hessians carry the material and geometric terms
   (k d d^T + k max(0, 1 - L0/L) (I - d d^T)) on a gently wrinkled pose, and the two corners
   at z = -0.5 pinned by the filter (the "hang" scene's solve).

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/linsolve bench/linsolve.c -lm
       ./build/bench/linsolve [bench/results/linsolve.csv [largest side]]

   One CSV row per (grid, preconditioner) with the machine and CPU named: the SpMV time (median
   of 9 samples of repeated products, microseconds), then for the solve from x = 0 to relative
   tolerance 1e-6 the iterations, the reported residual and the time (median of 3,
   milliseconds). Times are the process's CPU time (CLOCK_PROCESS_CPUTIME_ID), which a shared
   machine disturbs less than wall time; the solve's wall time is written too. */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* A spring between u and v: its 3x3 Hessian block H goes to (u,u) and (v,v) with +, to (u,v)
   and (v,u) with -. */
static void add_spring(cloth_block_matrix *A, const double *x, const double *rest, int32_t u, int32_t v, double k,
                       double scale)
{
    double d[3], l = 0, l0 = 0, g;
    cloth_real h[9];
    int r, c;
    for (r = 0; r < 3; ++r) {
        d[r] = x[3 * v + r] - x[3 * u + r];
        l += d[r] * d[r];
        l0 += (rest[3 * v + r] - rest[3 * u + r]) * (rest[3 * v + r] - rest[3 * u + r]);
    }
    l = sqrt(l);
    l0 = sqrt(l0);
    for (r = 0; r < 3; ++r) d[r] /= l;
    g = 1 - l0 / l;
    if (g < 0) g = 0; /* the geometric term clamped to keep H positive semidefinite */
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) h[3 * r + c] = (cloth_real)(scale * k * (d[r] * d[c] + g * ((r == c) - d[r] * d[c])));
    cloth_block_matrix_add_block(A, A->diagonal[u], 1, h);
    cloth_block_matrix_add_block(A, A->diagonal[v], 1, h);
    cloth_block_matrix_add_block(A, cloth_block_matrix_find(A, u, v), -1, h);
    cloth_block_matrix_add_block_transposed(A, cloth_block_matrix_find(A, v, u), -1, h);
}

int main(int argc, char **argv)
{
    static const int32_t sides[] = { 16, 32, 64, 128 };
    static const char *names[] = { "none", "jacobi", "block_jacobi" };
    const char *path = argc > 1 ? argv[1] : "bench/results/linsolve.csv";
    int32_t largest = argc > 2 ? (int32_t)atoi(argv[2]) : 128;
    char host[256] = "unknown", cpu[256] = "unknown", line[512];
    FILE *f, *out;
    size_t s;
    if (gethostname(host, sizeof host) != 0) strcpy(host, "unknown");
    host[sizeof host - 1] = 0;
    f = fopen("/proc/cpuinfo", "r");
    if (f) {
        while (fgets(line, sizeof line, f))
            if (strncmp(line, "model name", 10) == 0) {
                char *c = strchr(line, ':');
                if (c) {
                    c += 1 + strspn(c + 1, " \t");
                    c[strcspn(c, "\n")] = 0;
                    strncpy(cpu, c, sizeof cpu - 1);
                }
                break;
            }
        fclose(f);
    }
    for (s = 0; cpu[s]; ++s) if (cpu[s] == ',' || cpu[s] == '"') cpu[s] = ' ';
    for (s = 0; host[s]; ++s) if (host[s] == ',' || host[s] == '"') host[s] = ' ';
    out = fopen(path, "w");
    if (!out) { fprintf(stderr, "cannot write %s\n", path); return 1; }
    fprintf(out, "machine,cpu,real_bytes,side,vertices,blocks,spmv_us,preconditioner,iterations,residual,pcg_ms,pcg_wall_ms,result\n");

    for (s = 0; s < sizeof sides / sizeof sides[0]; ++s) {
        int32_t g = sides[s], n = g * g, i, j, pc = 0, p;
        double dx = 1.0 / (g - 1), h = 1.0 / 60, mass = 0.1 * dx * dx, t[64], tw[64];
        double *x = (double *)malloc(sizeof(double) * 3 * (size_t)n);
        double *rest = (double *)malloc(sizeof(double) * 3 * (size_t)n);
        int32_t *pair = (int32_t *)malloc(sizeof(int32_t) * 2 * 6 * (size_t)n);
        int32_t *kind = (int32_t *)malloc(sizeof(int32_t) * 6 * (size_t)n);
        int32_t *constrained = (int32_t *)calloc((size_t)n, sizeof(int32_t));
        cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *v = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *y = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *masses = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)n);
        cloth_block_matrix A;
        cloth_pcg_workspace ws;
        cloth_pcg_filter filter;
        cloth_rng rng = cloth_rng_make(2026);
        double spmv_us;
        int reps, r, prec;
        if (g > largest) break;
        for (j = 0; j < g; ++j)
            for (i = 0; i < g; ++i) {
                int32_t q = j * g + i;
                double u = i * dx - 0.5, w = j * dx - 0.5;
                rest[3 * q] = u;
                rest[3 * q + 1] = 0;
                rest[3 * q + 2] = w;
                x[3 * q] = 0.98 * u;
                x[3 * q + 1] = 0.02 * sin(9.0 * u) * cos(7.0 * w);
                x[3 * q + 2] = w;
                masses[q] = (cloth_real)mass;
            }
#define SPRING(a, bb, k) do { pair[2 * pc] = (a); pair[2 * pc + 1] = (bb); kind[pc] = (k); ++pc; } while (0)
        for (j = 0; j < g; ++j)
            for (i = 0; i < g; ++i) {
                int32_t q = j * g + i;
                if (i + 1 < g) SPRING(q, q + 1, 0);
                if (j + 1 < g) SPRING(q, q + g, 0);
                if (i + 1 < g && j + 1 < g) { SPRING(q, q + g + 1, 1); SPRING(q + 1, q + g, 1); }
                if (i + 2 < g) SPRING(q, q + 2, 2);
                if (j + 2 < g) SPRING(q, q + 2 * g, 2);
            }
#undef SPRING
        if (cloth_block_matrix_create(&A, n, pair, pc, NULL) != CLOTH_SUCCESS ||
            cloth_pcg_workspace_create(&ws, n, NULL) != CLOTH_SUCCESS) {
            fprintf(stderr, "setup failed\n");
            return 1;
        }
        cloth_block_matrix_add_diagonal(&A, 1, masses);
        for (p = 0; p < pc; ++p) {
            static const double k[3] = { 5000, 2500, 50 };
            add_spring(&A, x, rest, pair[2 * p], pair[2 * p + 1], k[kind[p]], h * h);
        }
        /* b = h M g plus a random disturbance, as a velocity-change right-hand side would look */
        for (i = 0; i < 3 * n; ++i) b[i] = (cloth_real)(mass * (0.1 * (double)cloth_rng_normal(&rng) + (i % 3 == 1 ? -9.81 * h : 0)));
        constrained[0] = 3;
        constrained[g - 1] = 3;
        filter.constrained = constrained;
        filter.direction = NULL;
        filter.value = NULL;

        for (i = 0; i < 3 * n; ++i) v[i] = (cloth_real)cloth_rng_normal(&rng);
        reps = 1;
        for (;;) { /* repeat until one sample takes at least 20 ms */
            double t0 = now_s();
            for (r = 0; r < reps; ++r) cloth_block_matrix_multiply(&A, v, y);
            if (now_s() - t0 > 0.02) break;
            reps *= 2;
        }
        for (r = 0; r < 9; ++r) {
            double t0 = now_s();
            int k2;
            for (k2 = 0; k2 < reps; ++k2) cloth_block_matrix_multiply(&A, v, y);
            t[r] = (now_s() - t0) / reps * 1e6;
        }
        spmv_us = median(t, 9);

        for (prec = 0; prec < 3; ++prec) {
            cloth_pcg_options opt = cloth_default_pcg_options();
            cloth_pcg_stats st;
            cloth_result res = CLOTH_SUCCESS;
            opt.preconditioner = (cloth_preconditioner)prec;
            opt.tolerance = (cloth_real)1e-6;
            opt.max_iterations = 20000;
            for (r = 0; r < 3; ++r) {
                double t0, w0;
                memset(y, 0, sizeof(cloth_real) * 3 * (size_t)n);
                t0 = now_s();
                w0 = wall_s();
                res = cloth_pcg_solve(&A, b, y, &filter, &opt, &ws, &st);
                t[r] = (now_s() - t0) * 1e3;
                tw[r] = (wall_s() - w0) * 1e3;
            }
            fprintf(out, "%s,%s,%d,%d,%d,%d,%.3f,%s,%d,%.3g,%.3f,%.3f,%s\n", host, cpu, (int)sizeof(cloth_real), g, n,
                    A.block_count, spmv_us, names[prec], st.iterations, (double)st.residual, median(t, 3),
                    median(tw, 3), res == CLOTH_SUCCESS ? "converged" : cloth_result_string(res));
            printf("n=%3d blocks=%7d spmv %9.1f us  %-12s %5d iterations  residual %.2g  %9.2f ms  %s\n", g,
                   A.block_count, spmv_us, names[prec], st.iterations, (double)st.residual, median(t, 3),
                   res == CLOTH_SUCCESS ? "converged" : cloth_result_string(res));
        }
        cloth_block_matrix_free(&A);
        cloth_pcg_workspace_free(&ws);
        free(x);
        free(rest);
        free(pair);
        free(kind);
        free(constrained);
        free(b);
        free(v);
        free(y);
        free(masses);
    }
    fclose(out);
    return 0;
}
