/* Benchmark of the linsolve module: filtered PCG with no preconditioner, Jacobi, block-Jacobi
   and smoothed-aggregation multigrid on the implicit-Euler systems of the "hang" scene
   (docs/scenes.md): a 1 m square cloth of n x n vertices (n = 16, 32, 64, 128),
   areal density 0.1 kg/m^2, h = 1/60 s, the two corners at z = -0.5 pinned through the filter.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/linsolve bench/linsolve.c -lm
       ./build/bench/linsolve [bench/results/linsolve.csv [largest side [steps]]]

   Two kinds of matrix, A = M + h^2 K:
     springs   the earlier hang-like matrix: stretch (5000 N/m), shear (2500 N/m) and bend
               (50 N/m) springs of a grid with their material and clamped geometric Hessians,
               on a gently wrinkled and 2 % compressed pose; b = h M g plus noise; x from 0.
     membrane  the integrator's system: the default cotton's orthotropic StVK membrane
               (C11 = 8477, C22 = 5651, C12 = 1695, C33 = 56.2 N/m) and dihedral bending, both
               with their projected Hessians, on a grid with alternating diagonals, at the pose
               the scene reaches after `steps` steps (default 30, 0.5 s) of linearized backward
               Euler (solved here with multigrid), b its right-hand side and x the integrator's
               warm start h v.
   For each matrix, tolerance (1e-3 and 1e-6) and preconditioner (none and Jacobi only up to
   n = 64: minutes per solve at 128, and nothing new), one row of bench/results/linsolve.csv:
   iterations, the reported residual, the hierarchy's levels and operator complexity, and times
   in milliseconds: setup_ms a fresh cloth_pcg_multigrid_setup (symbolic and first numeric
   phase), numeric_ms cloth_pcg_multigrid_update (the numeric phase alone), solve_ms a solve with
   multigrid_update = 0 (it refreshes level 0 only), total_ms a solve with multigrid_update = 1,
   what an integrator pays per solve (for the other preconditioners total = solve, which builds
   them), and ms_per_iteration = (total - numeric) / iterations. Times are medians of 3 of the
   process's CPU time (clock_gettime(CLOCK_PROCESS_CPUTIME_ID), clock()'s quantity at a finer
   resolution), which other load on a shared machine disturbs less than wall time.

   Then bench/results/linsolve_sequence.csv: the whole run of `steps` steps, solved as the
   integrator would, at tolerance 1e-3: multigrid set up at the first step and updated by every
   solve after it ("multigrid_every_step"), multigrid updated only every 4th step
   ("multigrid_every_4th_step"), and block-Jacobi for n <= 64; the mean and largest iterations
   per step, the setup time and the mean time per step of the solves (updates included) after
   the first. */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "machine.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median3(double *v)
{
    qsort(v, 3, sizeof *v, cmp_double);
    return v[1];
}

static void *xmalloc(size_t bytes)
{
    void *p = calloc(1, bytes ? bytes : 1);
    if (!p) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    return p;
}

#define CHECK(call) do { cloth_result r_ = (call); if (r_ != CLOTH_SUCCESS) { \
    fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, #call, cloth_result_string(r_)); exit(1); } } while (0)

/* ---- the spring matrix ------------------------------------------------------------- */

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

/* The spring system of side g: A, b, the filter's counts and the start x = 0. */
static void make_springs(int32_t g, cloth_block_matrix *A, cloth_real *b, int32_t *constrained, cloth_real *x0)
{
    int32_t n = g * g, i, j, pc = 0, p;
    double dx = 1.0 / (g - 1), h = 1.0 / 60, mass = 0.1 * dx * dx;
    double *x = (double *)xmalloc(sizeof(double) * 3 * (size_t)n);
    double *rest = (double *)xmalloc(sizeof(double) * 3 * (size_t)n);
    int32_t *pair = (int32_t *)xmalloc(sizeof(int32_t) * 2 * 6 * (size_t)n);
    int32_t *kind = (int32_t *)xmalloc(sizeof(int32_t) * 6 * (size_t)n);
    cloth_real *masses = (cloth_real *)xmalloc(sizeof(cloth_real) * (size_t)n);
    cloth_rng rng = cloth_rng_make(2026);
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
    CHECK(cloth_block_matrix_create(A, n, pair, pc, NULL));
    cloth_block_matrix_add_diagonal(A, 1, masses);
    for (p = 0; p < pc; ++p) {
        static const double k[3] = { 5000, 2500, 50 };
        add_spring(A, x, rest, pair[2 * p], pair[2 * p + 1], k[kind[p]], h * h);
    }
    /* b = h M g plus a random disturbance, as a velocity-change right-hand side would look */
    for (i = 0; i < 3 * n; ++i) b[i] = (cloth_real)(mass * (0.1 * (double)cloth_rng_normal(&rng) + (i % 3 == 1 ? -9.81 * h : 0)));
    for (i = 0; i < n; ++i) constrained[i] = 0;
    constrained[0] = 3;
    constrained[g - 1] = 3;
    for (i = 0; i < 3 * n; ++i) x0[i] = 0;
    free(x);
    free(rest);
    free(pair);
    free(kind);
    free(masses);
}

/* ---- the hang scene with membranes and bending ------------------------------------- */

typedef struct hang {
    int32_t g, n, tri_count, hinge_count;
    cloth_mesh mesh;                 /* x: the current positions */
    cloth_real *v, *mass, *rhs, *dx;
    cloth_membrane_rest *membrane;
    cloth_membrane_stiffness stiffness;
    int32_t *hinge;                  /* 4 vertices each */
    cloth_bending_rest *bending;
    cloth_real *bend_k;
    int32_t *tri_block, *hinge_block; /* 9 and 16 block indices each */
    int32_t *constrained;
    cloth_block_matrix A;
} hang;

static void hang_make(hang *s, int32_t g)
{
    cloth_material mat = cloth_default_material();
    cloth_topology top;
    int32_t n = g * g, t, e, a, b, pc = 0, *pair;
    memset(s, 0, sizeof *s);
    s->g = g;
    s->n = n;
    CHECK(cloth_mesh_grid(&s->mesh, g, g, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL));
    for (a = 0; a < n; ++a) s->mesh.x[3 * a + 1] = 1;
    s->tri_count = s->mesh.triangle_count;
    CHECK(cloth_topology_build(&top, &s->mesh, NULL));
    s->v = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
    s->rhs = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
    s->dx = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
    s->mass = (cloth_real *)xmalloc(sizeof(cloth_real) * (size_t)n);
    s->membrane = (cloth_membrane_rest *)xmalloc(sizeof(cloth_membrane_rest) * (size_t)s->tri_count);
    s->hinge = (int32_t *)xmalloc(sizeof(int32_t) * 4 * (size_t)top.edge_count);
    s->bending = (cloth_bending_rest *)xmalloc(sizeof(cloth_bending_rest) * (size_t)top.edge_count);
    s->bend_k = (cloth_real *)xmalloc(sizeof(cloth_real) * (size_t)top.edge_count);
    s->constrained = (int32_t *)xmalloc(sizeof(int32_t) * (size_t)n);
    s->stiffness.c11 = mat.stretch_warp;
    s->stiffness.c22 = mat.stretch_weft;
    s->stiffness.c12 = mat.stretch_coupling;
    s->stiffness.c33 = mat.shear;
    for (t = 0; t < s->tri_count; ++t) {
        const int32_t *v = s->mesh.tri + 3 * t;
        CHECK(cloth_membrane_rest_make(s->membrane + t, s->mesh.uv + 2 * v[0], s->mesh.uv + 2 * v[1], s->mesh.uv + 2 * v[2]));
        for (a = 0; a < 3; ++a) s->mass[v[a]] += (cloth_real)(0.1 * (double)s->membrane[t].area / 3);
    }
    for (e = 0; e < top.edge_count; ++e) {
        int32_t *h = s->hinge + 4 * s->hinge_count;
        if (top.edge_opposite[2 * e] < 0 || top.edge_opposite[2 * e + 1] < 0) continue;
        h[0] = top.edge_vertex[2 * e];
        h[1] = top.edge_vertex[2 * e + 1];
        h[2] = top.edge_opposite[2 * e];
        h[3] = top.edge_opposite[2 * e + 1];
        CHECK(cloth_bending_rest_make(s->bending + s->hinge_count, s->mesh.uv + 2 * h[0], s->mesh.uv + 2 * h[1],
                                      s->mesh.uv + 2 * h[2], s->mesh.uv + 2 * h[3], 0));
        s->bend_k[s->hinge_count] = cloth_bending_stiffness_orthotropic(mat.bend_warp, mat.bend_weft, s->mesh.uv + 2 * h[0],
                                                                        s->mesh.uv + 2 * h[1]);
        ++s->hinge_count;
    }
    cloth_topology_free(&top);
    pair = (int32_t *)xmalloc(sizeof(int32_t) * 2 * (3 * (size_t)s->tri_count + 6 * (size_t)s->hinge_count));
    for (t = 0; t < s->tri_count; ++t)
        for (a = 0; a < 3; ++a) { pair[2 * pc] = s->mesh.tri[3 * t + a]; pair[2 * pc + 1] = s->mesh.tri[3 * t + (a + 1) % 3]; ++pc; }
    for (e = 0; e < s->hinge_count; ++e)
        for (a = 0; a < 4; ++a)
            for (b = a + 1; b < 4; ++b) { pair[2 * pc] = s->hinge[4 * e + a]; pair[2 * pc + 1] = s->hinge[4 * e + b]; ++pc; }
    CHECK(cloth_block_matrix_create(&s->A, n, pair, pc, NULL));
    free(pair);
    s->tri_block = (int32_t *)xmalloc(sizeof(int32_t) * 9 * (size_t)s->tri_count);
    s->hinge_block = (int32_t *)xmalloc(sizeof(int32_t) * 16 * (size_t)s->hinge_count);
    for (t = 0; t < s->tri_count; ++t)
        for (a = 0; a < 3; ++a)
            for (b = 0; b < 3; ++b) s->tri_block[9 * t + 3 * a + b] = cloth_block_matrix_find(&s->A, s->mesh.tri[3 * t + a], s->mesh.tri[3 * t + b]);
    for (e = 0; e < s->hinge_count; ++e)
        for (a = 0; a < 4; ++a)
            for (b = 0; b < 4; ++b) s->hinge_block[16 * e + 4 * a + b] = cloth_block_matrix_find(&s->A, s->hinge[4 * e + a], s->hinge[4 * e + b]);
    /* the two corners at z = -0.5 (row j = 0 of the grid) */
    s->constrained[0] = 3;
    s->constrained[g - 1] = 3;
}

static void hang_free(hang *s)
{
    cloth_mesh_free(&s->mesh);
    cloth_block_matrix_free(&s->A);
    free(s->v);
    free(s->rhs);
    free(s->dx);
    free(s->mass);
    free(s->membrane);
    free(s->hinge);
    free(s->bending);
    free(s->bend_k);
    free(s->tri_block);
    free(s->hinge_block);
    free(s->constrained);
}

/* The step's system at the current state: A = M + h^2 H (projected Hessians),
   b = M h v + h^2 (M g - grad E) (the first Newton step of the incremental potential from x),
   and the integrator's warm start dx = h v (0 on pinned vertices). */
static void hang_assemble(hang *s, double h)
{
    cloth_real *grad = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)s->n), gr[12], hs[144];
    const cloth_real *x = s->mesh.x;
    int32_t t, e, a, b, r, c, i;
    cloth_block_matrix_zero(&s->A);
    for (t = 0; t < s->tri_count; ++t) {
        const int32_t *v = s->mesh.tri + 3 * t;
        cloth_membrane_energy(x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], s->membrane + t, &s->stiffness, gr, hs,
                              CLOTH_HESSIAN_PROJECTED);
        for (a = 0; a < 3; ++a) {
            for (r = 0; r < 3; ++r) grad[3 * v[a] + r] += gr[3 * a + r];
            for (b = 0; b < 3; ++b) {
                cloth_real blk[9];
                for (r = 0; r < 3; ++r)
                    for (c = 0; c < 3; ++c) blk[3 * r + c] = hs[(3 * a + r) * 9 + 3 * b + c];
                cloth_block_matrix_add_block(&s->A, s->tri_block[9 * t + 3 * a + b], (cloth_real)(h * h), blk);
            }
        }
    }
    for (e = 0; e < s->hinge_count; ++e) {
        const int32_t *v = s->hinge + 4 * e;
        cloth_bending_energy(x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], x + 3 * v[3], s->bending + e, s->bend_k[e], gr, hs,
                             CLOTH_HESSIAN_PROJECTED);
        for (a = 0; a < 4; ++a) {
            for (r = 0; r < 3; ++r) grad[3 * v[a] + r] += gr[3 * a + r];
            for (b = 0; b < 4; ++b) {
                cloth_real blk[9];
                for (r = 0; r < 3; ++r)
                    for (c = 0; c < 3; ++c) blk[3 * r + c] = hs[(3 * a + r) * 12 + 3 * b + c];
                cloth_block_matrix_add_block(&s->A, s->hinge_block[16 * e + 4 * a + b], (cloth_real)(h * h), blk);
            }
        }
    }
    cloth_block_matrix_add_diagonal(&s->A, 1, s->mass);
    for (i = 0; i < s->n; ++i)
        for (r = 0; r < 3; ++r) {
            size_t q = 3 * (size_t)i + (size_t)r;
            s->rhs[q] = (cloth_real)((double)s->mass[i] * h * (double)s->v[q] +
                                     h * h * ((r == 1 ? -9.81 * (double)s->mass[i] : 0.0) - (double)grad[q]));
            s->dx[q] = s->constrained[i] ? 0 : (cloth_real)(h * (double)s->v[q]);
        }
    free(grad);
}

/* After a solve of s->dx: x += dx, v = dx / h. */
static void hang_advance(hang *s, double h)
{
    int32_t q;
    for (q = 0; q < 3 * s->n; ++q) {
        s->mesh.x[q] += s->dx[q];
        s->v[q] = (cloth_real)((double)s->dx[q] / h);
    }
}

/* ---- runs ---------------------------------------------------------------------------- */

static const char *const names[4] = { "none", "jacobi", "block_jacobi", "multigrid" };

typedef struct run_result {
    int32_t iterations;
    double residual, setup_ms, numeric_ms, solve_ms, total_ms;
    cloth_result result;
    cloth_multigrid_info info;
} run_result;

/* Solve A x = b from x0 with one preconditioner, 3 times; medians. For multigrid: setup_ms a
   fresh setup (symbolic and numeric phase), numeric_ms cloth_pcg_multigrid_update, solve_ms a
   solve with multigrid_update = 0 (it refreshes level 0 only), total_ms a solve with
   multigrid_update = 1, what an integrator pays per solve. For the others total = solve. */
static run_result run_one(const cloth_block_matrix *A, const cloth_real *b, const cloth_real *x0, const int32_t *constrained,
                          int prec, double tolerance)
{
    const int32_t n = A->vertex_count;
    cloth_real *x = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_pcg_stats st;
    run_result out;
    double setup[3] = { 0, 0, 0 }, numeric[3] = { 0, 0, 0 }, solve[3], total[3];
    int rep;
    memset(&out, 0, sizeof out);
    filter.constrained = constrained;
    filter.direction = NULL;
    filter.value = NULL;
    opt.preconditioner = (cloth_preconditioner)prec;
    opt.tolerance = (cloth_real)tolerance;
    opt.max_iterations = 20000;
    CHECK(cloth_pcg_workspace_create(&ws, n, NULL));
    for (rep = 0; rep < 3; ++rep) {
        double t0;
        if (prec == CLOTH_PRECONDITIONER_MULTIGRID) {
            cloth_pcg_workspace_free(&ws);
            CHECK(cloth_pcg_workspace_create(&ws, n, NULL));
            t0 = now_ms();
            CHECK(cloth_pcg_multigrid_setup(&ws, A, &filter, NULL));
            setup[rep] = now_ms() - t0;
            t0 = now_ms();
            CHECK(cloth_pcg_multigrid_update(&ws, A, &filter));
            numeric[rep] = now_ms() - t0;
        }
        opt.multigrid_update = 0;
        memcpy(x, x0, sizeof(cloth_real) * 3 * (size_t)n);
        t0 = now_ms();
        out.result = cloth_pcg_solve(A, b, x, &filter, &opt, &ws, &st);
        solve[rep] = total[rep] = now_ms() - t0;
        if (prec == CLOTH_PRECONDITIONER_MULTIGRID) {
            opt.multigrid_update = 1;
            memcpy(x, x0, sizeof(cloth_real) * 3 * (size_t)n);
            t0 = now_ms();
            out.result = cloth_pcg_solve(A, b, x, &filter, &opt, &ws, &st);
            total[rep] = now_ms() - t0;
        }
    }
    out.iterations = st.iterations;
    out.residual = (double)st.residual;
    out.setup_ms = median3(setup);
    out.numeric_ms = median3(numeric);
    out.solve_ms = median3(solve);
    out.total_ms = median3(total);
    cloth_pcg_multigrid_info(&ws, &out.info);
    cloth_pcg_workspace_free(&ws);
    free(x);
    return out;
}

/* The hang scene for `steps` steps, as the integrator would run it. mode 0: multigrid, set up
   at the first step, then every solve updates it (multigrid_update = 1); 1: multigrid updated
   only every 4th step (multigrid_update = 0 between); 2: block-Jacobi. setup_ms: the setup at
   the first step; step_ms: the mean time per step of the solves and updates after it. */
typedef struct sequence_result {
    double iterations_mean, setup_ms, step_ms;
    int32_t iterations_max, failures;
} sequence_result;

static sequence_result run_sequence(hang *s, int32_t steps, int mode, double tolerance)
{
    const double h = 1.0 / 60;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_pcg_options opt = cloth_default_pcg_options();
    sequence_result out;
    int32_t step, total = 0;
    memset(&out, 0, sizeof out);
    filter.constrained = s->constrained;
    filter.direction = NULL;
    filter.value = NULL;
    opt.tolerance = (cloth_real)tolerance;
    opt.max_iterations = 20000;
    opt.preconditioner = mode == 2 ? CLOTH_PRECONDITIONER_BLOCK_JACOBI : CLOTH_PRECONDITIONER_MULTIGRID;
    CHECK(cloth_pcg_workspace_create(&ws, s->n, NULL));
    for (step = 0; step < steps; ++step) {
        cloth_pcg_stats st;
        cloth_result r;
        double t0;
        hang_assemble(s, h);
        opt.multigrid_update = mode == 0 && step > 0;
        if (mode != 2 && step == 0) {
            t0 = now_ms();
            CHECK(cloth_pcg_multigrid_setup(&ws, &s->A, &filter, NULL));
            out.setup_ms = now_ms() - t0;
        }
        t0 = now_ms();
        if (mode == 1 && step > 0 && step % 4 == 0) CHECK(cloth_pcg_multigrid_update(&ws, &s->A, &filter));
        r = cloth_pcg_solve(&s->A, s->rhs, s->dx, &filter, &opt, &ws, &st);
        if (step > 0) out.step_ms += now_ms() - t0;
        if (r != CLOTH_SUCCESS) ++out.failures;
        total += st.iterations;
        if (st.iterations > out.iterations_max) out.iterations_max = st.iterations;
        hang_advance(s, h);
    }
    cloth_pcg_workspace_free(&ws);
    out.iterations_mean = (double)total / steps;
    out.step_ms /= steps > 1 ? steps - 1 : 1;
    return out;
}

int main(int argc, char **argv)
{
    static const int32_t sides[] = { 16, 32, 64, 128 };
    static const double tolerances[2] = { 1e-3, 1e-6 };
    const char *path = argc > 1 ? argv[1] : "bench/results/linsolve.csv";
    int32_t largest = argc > 2 ? (int32_t)atoi(argv[2]) : 128;
    int32_t steps = argc > 3 ? (int32_t)atoi(argv[3]) : 30;
    bench_machine machine = bench_machine_read();
    const char *host = machine.host, *cpu = machine.cpu;
    char seq_path[600];
    FILE *out, *seq;
    size_t s, len;
    /* the sequence file next to the main one: linsolve.csv -> linsolve_sequence.csv */
    len = strlen(path);
    if (len > 4 && strcmp(path + len - 4, ".csv") == 0) snprintf(seq_path, sizeof seq_path, "%.*s_sequence.csv", (int)(len - 4), path);
    else snprintf(seq_path, sizeof seq_path, "%s_sequence.csv", path);
    out = fopen(path, "w");
    seq = fopen(seq_path, "w");
    if (!out || !seq) { fprintf(stderr, "cannot write %s or %s\n", path, seq_path); return 1; }
    fprintf(out, "machine,cpu,real_bytes,matrix,side,vertices,blocks,tolerance,preconditioner,iterations,residual,"
                 "levels,operator_complexity,setup_ms,numeric_ms,solve_ms,total_ms,ms_per_iteration,result\n");
    fprintf(seq, "machine,cpu,real_bytes,side,vertices,steps,tolerance,mode,iterations_mean,iterations_max,setup_ms,"
                 "ms_per_step,failures\n");

    for (s = 0; s < sizeof sides / sizeof sides[0]; ++s) {
        const int32_t g = sides[s], n = g * g;
        int kind;
        if (g > largest) break;
        for (kind = 0; kind < 2; ++kind) {
            cloth_block_matrix springs;
            hang scene;
            const cloth_block_matrix *A;
            cloth_real *b, *x0;
            int32_t *constrained;
            int t, prec;
            if (kind == 0) {
                b = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
                x0 = (cloth_real *)xmalloc(sizeof(cloth_real) * 3 * (size_t)n);
                constrained = (int32_t *)xmalloc(sizeof(int32_t) * (size_t)n);
                make_springs(g, &springs, b, constrained, x0);
                A = &springs;
            } else {
                /* the pose after `steps` steps (multigrid, every step), then the next system */
                sequence_result r;
                hang_make(&scene, g);
                r = run_sequence(&scene, steps, 0, 1e-3);
                fprintf(seq, "%s,%s,%d,%d,%d,%d,%g,multigrid_every_step,%.2f,%d,%.3f,%.3f,%d\n", host, cpu, (int)sizeof(cloth_real), g,
                        n, steps, 1e-3, r.iterations_mean, r.iterations_max, r.setup_ms, r.step_ms, r.failures);
                printf("n=%3d hang, %d steps: multigrid, update every step %6.1f iterations (max %d), setup %.2f ms, %8.2f ms/step\n", g,
                       steps, r.iterations_mean, r.iterations_max, r.setup_ms, r.step_ms);
                fflush(stdout);
                hang_assemble(&scene, 1.0 / 60);
                A = &scene.A;
                b = scene.rhs;
                x0 = scene.dx;
                constrained = scene.constrained;
            }
            for (t = 0; t < 2; ++t)
                for (prec = 0; prec < 4; ++prec) {
                    run_result r;
                    double per_iteration;
                    if (prec < 2 && g > 64) continue; /* minutes per solve, and no news */
                    r = run_one(A, b, x0, constrained, prec, tolerances[t]);
                    per_iteration = r.iterations ? (r.total_ms - r.numeric_ms) / r.iterations : 0.0;
                    fprintf(out, "%s,%s,%d,%s,%d,%d,%d,%g,%s,%d,%.3g,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.4f,%s\n", host, cpu,
                            (int)sizeof(cloth_real), kind ? "membrane" : "springs", g, n, A->block_count, tolerances[t], names[prec],
                            r.iterations, r.residual, r.info.level_count, r.info.operator_complexity, r.setup_ms, r.numeric_ms,
                            r.solve_ms, r.total_ms, per_iteration,
                            r.result == CLOTH_SUCCESS ? "converged" : cloth_result_string(r.result));
                    printf("n=%3d %-8s tol %g %-12s %5d it  res %8.2g  setup %7.2f numeric %7.2f solve %8.2f total %8.2f ms (%.3f/it)\n",
                           g, kind ? "membrane" : "springs", tolerances[t], names[prec], r.iterations, r.residual, r.setup_ms,
                           r.numeric_ms, r.solve_ms, r.total_ms, per_iteration);
                    fflush(stdout);
                }
            if (kind == 0) {
                cloth_block_matrix_free(&springs);
                free(b);
                free(x0);
                free(constrained);
            } else {
                int mode;
                for (mode = 1; mode < 3; ++mode) {
                    sequence_result r;
                    if (mode == 2 && g > 64) continue;
                    hang_free(&scene);
                    hang_make(&scene, g);
                    r = run_sequence(&scene, steps, mode, 1e-3);
                    fprintf(seq, "%s,%s,%d,%d,%d,%d,%g,%s,%.2f,%d,%.3f,%.3f,%d\n", host, cpu, (int)sizeof(cloth_real), g, n, steps, 1e-3,
                            mode == 1 ? "multigrid_every_4th_step" : "block_jacobi", r.iterations_mean, r.iterations_max, r.setup_ms,
                            r.step_ms, r.failures);
                    printf("n=%3d hang, %d steps: %-30s %6.1f iterations (max %d), setup %.2f ms, %8.2f ms/step\n", g, steps,
                           mode == 1 ? "multigrid, update every 4th" : "block-jacobi", r.iterations_mean, r.iterations_max, r.setup_ms,
                           r.step_ms);
                    fflush(stdout);
                }
                hang_free(&scene);
            }
        }
    }
    fclose(out);
    fclose(seq);
    return 0;
}
