/* Tests of the linsolve module: the block sparse matrix (pattern, assembly, SpMV) and the
   filtered PCG, against dense products and dense Cholesky solves written here in double. */
#include "runner.h"
#include "../cloth.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

/* The unit roundoff-sized quantity of the build's cloth_real. */
#define EPS (sizeof(cloth_real) < sizeof(double) ? (double)FLT_EPSILON : DBL_EPSILON)
/* The solver tolerance the accuracy tests ask for: far below what any test problem needs in
   double; in float 1e-5, about 80 EPS, which the recurrence reaches before it stagnates. */
#define SOLVE_TOL (sizeof(cloth_real) < sizeof(double) ? 1e-5 : 1e-10)

static const cloth_preconditioner all_preconditioners[3] = {
    CLOTH_PRECONDITIONER_NONE, CLOTH_PRECONDITIONER_JACOBI, CLOTH_PRECONDITIONER_BLOCK_JACOBI
};

/* ---- dense helpers (double) ------------------------------------------------------- */

/* In-place Cholesky factor (lower triangle) of the N x N row-major a; 0 if not SPD. */
static int dense_cholesky(double *a, int N)
{
    int i, j, k;
    for (j = 0; j < N; ++j) {
        double d = a[j * N + j];
        for (k = 0; k < j; ++k) d -= a[j * N + k] * a[j * N + k];
        if (!(d > 0)) return 0;
        d = sqrt(d);
        a[j * N + j] = d;
        for (i = j + 1; i < N; ++i) {
            double s = a[i * N + j];
            for (k = 0; k < j; ++k) s -= a[i * N + k] * a[j * N + k];
            a[i * N + j] = s / d;
        }
    }
    return 1;
}

/* Solve L L^T x = b in place in x (x holds b on entry). */
static void dense_cholesky_solve(const double *l, int N, double *x)
{
    int i, k;
    for (i = 0; i < N; ++i) {
        double s = x[i];
        for (k = 0; k < i; ++k) s -= l[i * N + k] * x[k];
        x[i] = s / l[i * N + i];
    }
    for (i = N - 1; i >= 0; --i) {
        double s = x[i];
        for (k = i + 1; k < N; ++k) s -= l[k * N + i] * x[k];
        x[i] = s / l[i * N + i];
    }
}

/* Solve the SPD system a x = b (a is copied); 0 if a is not SPD. */
static int dense_solve(const double *a, int N, const double *b, double *x)
{
    double *l = (double *)malloc(sizeof(double) * (size_t)N * (size_t)N);
    int ok;
    memcpy(l, a, sizeof(double) * (size_t)N * (size_t)N);
    memcpy(x, b, sizeof(double) * (size_t)N);
    ok = dense_cholesky(l, N);
    if (ok) dense_cholesky_solve(l, N, x);
    free(l);
    return ok;
}

static double norm2(const double *v, int N)
{
    double s = 0;
    int i;
    for (i = 0; i < N; ++i) s += v[i] * v[i];
    return sqrt(s);
}

/* The dense copy of a block matrix's values. */
static double *dense_from_blocks(const cloth_block_matrix *A)
{
    int N = 3 * A->vertex_count, i, k, r, c;
    double *d = (double *)calloc((size_t)N * (size_t)N, sizeof(double));
    for (i = 0; i < A->vertex_count; ++i)
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k)
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) d[(3 * i + r) * N + 3 * A->column[k] + c] = (double)A->value[9 * k + 3 * r + c];
    return d;
}

/* An upper bound on the largest eigenvalue: the largest absolute row sum (Gershgorin). */
static double gershgorin_max(const double *a, int N)
{
    double best = 0;
    int i, j;
    for (i = 0; i < N; ++i) {
        double s = 0;
        for (j = 0; j < N; ++j) s += fabs(a[i * N + j]);
        if (s > best) best = s;
    }
    return best;
}

/* ---- random SPD block matrices ------------------------------------------------------ */

/* A = diag(mass) I + sum over pairs (u, v) of J_e^T J_e with J_e x = E1 x_u - E2 x_v (E1, E2
   random 3x3), and G^T G on the diagonal for pairs (u, u): SPD with smallest eigenvalue at
   least min(mass) >= 1. dense is assembled independently from the same cloth_real terms. */
typedef struct spd_problem {
    int32_t n;
    cloth_block_matrix A;
    double *dense;      /* assembled independently, (3n)^2 */
    double *dense_abs;  /* the sum of the absolute values of the terms of each entry */
    int *adds;          /* additions into each block, for rounding bounds */
    double lambda_min;  /* lower bound on the smallest eigenvalue */
    double kappa;       /* upper bound on the condition number */
    int max_row_blocks;
} spd_problem;

static void random_block(cloth_rng *rng, double scale, cloth_real *m)
{
    int e;
    for (e = 0; e < 9; ++e) m[e] = (cloth_real)(scale * (double)cloth_rng_normal(rng));
}

/* out = a^T b (3x3, cloth_real arithmetic as assembly code would do it). */
static void mul_at_b(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    int r, c, k;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) {
            cloth_real s = 0;
            for (k = 0; k < 3; ++k) s += a[3 * k + r] * b[3 * k + c];
            out[3 * r + c] = s;
        }
}

static void dense_add_block(spd_problem *pr, int32_t u, int32_t v, double scale, const cloth_real *m, int transposed)
{
    int N = 3 * pr->n, r, c;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c)
        {
            double t = scale * (double)(transposed ? m[3 * c + r] : m[3 * r + c]);
            pr->dense[(3 * u + r) * N + 3 * v + c] += t;
            pr->dense_abs[(3 * u + r) * N + 3 * v + c] += fabs(t);
        }
    ++pr->adds[cloth_block_matrix_find(&pr->A, u, v)];
}

static int make_spd(spd_problem *pr, uint64_t seed, int32_t n, int32_t pair_count, double coupling)
{
    cloth_rng rng = cloth_rng_make(seed);
    int32_t *pair = (int32_t *)malloc(sizeof(int32_t) * 2 * (size_t)(pair_count > 0 ? pair_count : 1));
    cloth_real *mass = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)n);
    int32_t k, i;
    int N = 3 * n;
    cloth_result res;
    memset(pr, 0, sizeof *pr);
    pr->n = n;
    for (k = 0; k < pair_count; ++k) {
        if (k % 7 == 3) { /* a duplicate of the previous pair, in the other order */
            pair[2 * k] = pair[2 * k - 1];
            pair[2 * k + 1] = pair[2 * k - 2];
        } else {
            pair[2 * k] = (int32_t)(cloth_rng_next(&rng) % (uint64_t)n);
            pair[2 * k + 1] = (int32_t)(cloth_rng_next(&rng) % (uint64_t)n);
        }
    }
    res = cloth_block_matrix_create(&pr->A, n, pair, pair_count, NULL);
    if (res != CLOTH_SUCCESS) { free(pair); free(mass); return 0; }
    pr->dense = (double *)calloc((size_t)N * (size_t)N, sizeof(double));
    pr->dense_abs = (double *)calloc((size_t)N * (size_t)N, sizeof(double));
    pr->adds = (int *)calloc((size_t)pr->A.block_count, sizeof(int));
    pr->lambda_min = 1e300;
    for (i = 0; i < n; ++i) {
        mass[i] = (cloth_real)(1.0 + cloth_rng_uniform(&rng));
        if ((double)mass[i] < pr->lambda_min) pr->lambda_min = (double)mass[i];
    }
    cloth_block_matrix_add_diagonal(&pr->A, 1, mass);
    for (i = 0; i < n; ++i) {
        cloth_real id[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
        dense_add_block(pr, i, i, (double)mass[i], id, 0);
    }
    for (k = 0; k < pair_count; ++k) {
        int32_t u = pair[2 * k], v = pair[2 * k + 1];
        cloth_real e1[9], e2[9], h[9];
        random_block(&rng, coupling, e1);
        random_block(&rng, coupling, e2);
        if (u == v) {
            mul_at_b(e1, e1, h);
            cloth_block_matrix_add_block(&pr->A, pr->A.diagonal[u], 1, h);
            dense_add_block(pr, u, u, 1, h, 0);
            continue;
        }
        mul_at_b(e1, e1, h);
        cloth_block_matrix_add_block(&pr->A, cloth_block_matrix_find(&pr->A, u, u), 1, h);
        dense_add_block(pr, u, u, 1, h, 0);
        mul_at_b(e2, e2, h);
        cloth_block_matrix_add_block(&pr->A, cloth_block_matrix_find(&pr->A, v, v), 1, h);
        dense_add_block(pr, v, v, 1, h, 0);
        mul_at_b(e1, e2, h); /* coupling block (u, v) = -E1^T E2, (v, u) its transpose */
        cloth_block_matrix_add_block(&pr->A, cloth_block_matrix_find(&pr->A, u, v), -1, h);
        dense_add_block(pr, u, v, -1, h, 0);
        cloth_block_matrix_add_block_transposed(&pr->A, cloth_block_matrix_find(&pr->A, v, u), -1, h);
        dense_add_block(pr, v, u, -1, h, 1);
    }
    pr->kappa = gershgorin_max(pr->dense, N) / pr->lambda_min;
    pr->max_row_blocks = 0;
    for (i = 0; i < n; ++i)
        if (pr->A.row_start[i + 1] - pr->A.row_start[i] > pr->max_row_blocks)
            pr->max_row_blocks = pr->A.row_start[i + 1] - pr->A.row_start[i];
    free(pair);
    free(mass);
    return 1;
}

static void free_spd(spd_problem *pr)
{
    cloth_block_matrix_free(&pr->A);
    free(pr->dense);
    free(pr->dense_abs);
    free(pr->adds);
}

static void random_vector(cloth_rng *rng, cloth_real *v, int N)
{
    int i;
    for (i = 0; i < N; ++i) v[i] = (cloth_real)cloth_rng_normal(rng);
}

/* A bound on |S (b - A x)| / |bhat| after a converged solve: the stopping test bounds the
   recurrence residual by sqrt(kappa(P)) tol, with kappa(P) <= kappa (the preconditioner's
   eigenvalues are Rayleigh quotients of A); the true residual differs from the recurrence by
   rounding, a few EPS |A| |x| per iteration and per SpMV row, relative to |b| up to kappa. */
static double residual_bound(double kappa, double tol, int iterations, int max_row_blocks)
{
    return sqrt(kappa) * tol + (double)(iterations + 2) * 3.0 * max_row_blocks * EPS * kappa;
}

/* ---- the matrix --------------------------------------------------------------------- */

TEST(pattern_from_pairs)
{
    /* duplicates, both orders, a self pair; vertex 5 has no pair */
    const int32_t pair[] = { 0, 1, 1, 0, 2, 4, 4, 2, 3, 3, 0, 1, 1, 4, 0, 4 };
    cloth_block_matrix A;
    int32_t i, j, k, expect_blocks = 6;
    int adjacent[6][6];
    memset(adjacent, 0, sizeof adjacent);
    for (k = 0; k < 8; ++k) adjacent[pair[2 * k]][pair[2 * k + 1]] = adjacent[pair[2 * k + 1]][pair[2 * k]] = 1;
    for (i = 0; i < 6; ++i)
        for (j = 0; j < 6; ++j) expect_blocks += i != j && adjacent[i][j];
    ENSURE(cloth_block_matrix_create(&A, 6, pair, 8, NULL) == CLOTH_SUCCESS);
    ENSURE(A.vertex_count == 6);
    ENSURE(A.block_count == expect_blocks);
    ENSURE(A.row_start[0] == 0 && A.row_start[6] == A.block_count);
    for (i = 0; i < 6; ++i) {
        ENSURE(A.column[A.diagonal[i]] == i);
        ENSURE(A.diagonal[i] >= A.row_start[i] && A.diagonal[i] < A.row_start[i + 1]);
        for (k = A.row_start[i] + 1; k < A.row_start[i + 1]; ++k) ENSURE(A.column[k - 1] < A.column[k]);
        for (j = 0; j < 6; ++j) {
            int32_t b = cloth_block_matrix_find(&A, i, j);
            if (i == j || adjacent[i][j]) {
                ENSURE(b >= A.row_start[i] && b < A.row_start[i + 1]);
                ENSURE(A.column[b] == j);
            } else {
                ENSURE(b == -1);
            }
        }
    }
    ENSURE(A.row_start[6] - A.row_start[5] == 1);
    ENSURE(cloth_block_matrix_find(&A, -1, 0) == -1);
    ENSURE(cloth_block_matrix_find(&A, 0, 6) == -1);
    for (k = 0; k < 9 * A.block_count; ++k) ENSURE(A.value[k] == 0);
    cloth_block_matrix_free(&A);
    ENSURE(A.value == NULL && A.block_count == 0);
    cloth_block_matrix_free(&A); /* freeing an empty matrix is fine */
}

TEST(pattern_errors)
{
    const int32_t bad[] = { 0, 1, 2, 3 };
    cloth_block_matrix A;
    ENSURE(cloth_block_matrix_create(&A, 3, bad, 2, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    ENSURE(A.row_start == NULL && A.value == NULL);
    ENSURE(cloth_block_matrix_create(&A, -1, NULL, 0, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_block_matrix_create(&A, 3, NULL, 1, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_block_matrix_create(&A, 3, bad, -1, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_block_matrix_create(&A, 0, NULL, 0, NULL) == CLOTH_SUCCESS);
    ENSURE(A.block_count == 0 && A.vertex_count == 0);
    {
        /* an empty system solves at once, even with an empty workspace */
        cloth_pcg_workspace ws;
        cloth_pcg_stats st;
        cloth_real none[1] = { 0 };
        memset(&ws, 0, sizeof ws);
        ENSURE(cloth_pcg_solve(&A, none, none, NULL, NULL, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.iterations == 0 && st.converged == 1);
    }
    cloth_block_matrix_free(&A);
}

/* SpMV, multiply_add, add_diagonal and zero against dense products of the independently
   assembled dense matrix. */
TEST(spmv_matches_dense)
{
    spd_problem pr;
    cloth_rng rng = cloth_rng_make(11);
    cloth_real *x, *y;
    double *dense_copy;
    int N, i, j, k, max_adds = 0;
    ENSURE(make_spd(&pr, 101, 50, 120, 0.7));
    for (k = 0; k < pr.A.block_count; ++k) if (pr.adds[k] > max_adds) max_adds = pr.adds[k];
    N = 3 * pr.n;
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    y = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, x, N);
    /* the block values hold the dense assembly, to the rounding of the additions */
    dense_copy = dense_from_blocks(&pr.A);
    for (i = 0; i < pr.n; ++i)
        for (k = pr.A.row_start[i]; k < pr.A.row_start[i + 1]; ++k) {
            int r, c, col = pr.A.column[k];
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) {
                    /* a sum of adds terms in cloth_real: at most adds roundings of partial sums */
                    ENSURE_NEAR(dense_copy[(3 * i + r) * N + 3 * col + c], pr.dense[(3 * i + r) * N + 3 * col + c],
                                pr.adds[k] * EPS * pr.dense_abs[(3 * i + r) * N + 3 * col + c]);
                }
        }
    /* every dense entry outside the pattern is zero */
    for (i = 0; i < N; ++i)
        for (j = 0; j < N; ++j)
            if (cloth_block_matrix_find(&pr.A, i / 3, j / 3) < 0) ENSURE(pr.dense[i * N + j] == 0);
    /* Rounding: the assembly's error in each entry (max_adds EPS times its terms' magnitudes),
       then a row sum of 3 * blocks-per-row products (one rounding each for the product and for
       every partial sum). */
    cloth_block_matrix_multiply(&pr.A, x, y);
    for (i = 0; i < N; ++i) {
        double want = 0, mag = 0, mag_terms = 0;
        for (j = 0; j < N; ++j) {
            want += pr.dense[i * N + j] * (double)x[j];
            mag += fabs(pr.dense[i * N + j] * (double)x[j]);
            mag_terms += pr.dense_abs[i * N + j] * fabs((double)x[j]);
        }
        ENSURE_NEAR(y[i], want, (3.0 * pr.max_row_blocks + 1) * EPS * mag + max_adds * EPS * mag_terms);
    }
    /* y += -2 A x gives -A x: y's own error doubled, plus the same again, plus the sum */
    cloth_block_matrix_multiply_add(&pr.A, -2, x, y);
    for (i = 0; i < N; ++i) {
        double want = 0, mag = 0, mag_terms = 0;
        for (j = 0; j < N; ++j) {
            want -= pr.dense[i * N + j] * (double)x[j];
            mag += fabs(pr.dense[i * N + j] * (double)x[j]);
            mag_terms += pr.dense_abs[i * N + j] * fabs((double)x[j]);
        }
        ENSURE_NEAR(y[i], want, 3 * ((3.0 * pr.max_row_blocks + 2) * EPS * mag + max_adds * EPS * mag_terms));
    }
    /* zero, then a scaled identity: A x = 2.5 x exactly */
    cloth_block_matrix_zero(&pr.A);
    cloth_block_matrix_add_diagonal(&pr.A, (cloth_real)2.5, NULL);
    cloth_block_matrix_multiply(&pr.A, x, y);
    for (i = 0; i < N; ++i) ENSURE(y[i] == (cloth_real)2.5 * x[i]);
    free(dense_copy);
    free(x);
    free(y);
    free_spd(&pr);
}

/* ---- the solver, no constraints ------------------------------------------------------ */

/* |A x - b| / |b| in double with the dense copy of the matrix. */
static double dense_relative_residual(const double *a, int N, const cloth_real *x, const double *b)
{
    double num = 0;
    int i, j;
    for (i = 0; i < N; ++i) {
        double s = b[i];
        for (j = 0; j < N; ++j) s -= a[i * N + j] * (double)x[j];
        num += s * s;
    }
    return sqrt(num) / norm2(b, N);
}

/* A random SPD system, a right-hand side and the dense Cholesky solution: the reference of the
   unfiltered solve tests. */
typedef struct dense_reference {
    spd_problem pr;
    int N;
    double *a, *bd, *xd; /* the dense matrix, b and the solution in double */
    cloth_real *b, *x;   /* b, and room for the library's solution */
} dense_reference;

static int dense_reference_make(dense_reference *d, uint64_t seed, int32_t n, int32_t pair_count, uint64_t rhs_seed)
{
    cloth_rng rng = cloth_rng_make(rhs_seed);
    int i;
    memset(d, 0, sizeof *d);
    if (!make_spd(&d->pr, seed, n, pair_count, 0.6)) return 0;
    d->N = 3 * d->pr.n;
    d->a = dense_from_blocks(&d->pr.A);
    d->bd = (double *)malloc(sizeof(double) * (size_t)d->N);
    d->xd = (double *)malloc(sizeof(double) * (size_t)d->N);
    d->b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)d->N);
    d->x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)d->N);
    random_vector(&rng, d->b, d->N);
    for (i = 0; i < d->N; ++i) d->bd[i] = (double)d->b[i];
    return dense_solve(d->a, d->N, d->bd, d->xd);
}

static void dense_reference_free(dense_reference *d)
{
    free(d->a);
    free(d->bd);
    free(d->xd);
    free(d->b);
    free(d->x);
    free_spd(&d->pr);
}

/* The library's solution d->x of a converged solve (stats st) against the reference: its dense
   residual within the bound the iterations and the condition number allow, the library's own
   residual report agreeing with the dense one, and the error within kappa times the bound. */
static void dense_reference_check(const dense_reference *d, const cloth_pcg_stats *st)
{
    double err = 0, bound = residual_bound(d->pr.kappa, SOLVE_TOL, st->iterations, d->pr.max_row_blocks);
    int i;
    ENSURE(dense_relative_residual(d->a, d->N, d->x, d->bd) <= bound);
    ENSURE_NEAR(st->residual, dense_relative_residual(d->a, d->N, d->x, d->bd), bound);
    for (i = 0; i < d->N; ++i) err += ((double)d->x[i] - d->xd[i]) * ((double)d->x[i] - d->xd[i]);
    err = sqrt(err) / norm2(d->xd, d->N);
    ENSURE(err <= d->pr.kappa * bound);
}

TEST(solve_matches_dense_cholesky)
{
    dense_reference d;
    cloth_pcg_workspace ws;
    int i, pc;
    ENSURE(dense_reference_make(&d, 202, 40, 90, 5));
    ENSURE(cloth_pcg_workspace_create(&ws, d.pr.n, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = all_preconditioners[pc];
        opt.tolerance = (cloth_real)SOLVE_TOL;
        for (i = 0; i < d.N; ++i) d.x[i] = 0;
        ENSURE(cloth_pcg_solve(&d.pr.A, d.b, d.x, NULL, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged == 1);
        ENSURE(st.iterations > 0 && st.iterations <= d.N);
        ENSURE(st.preconditioned_residual <= opt.tolerance);
        /* the residual, the library's own residual report and the error against the dense solve */
        dense_reference_check(&d, &st);
    }
    cloth_pcg_workspace_free(&ws);
    dense_reference_free(&d);
}

/* cloth_pcg_solve_preconditioned: the dense reference's system A, preconditioned by B = A's
   blocks on the pattern of the pairs (i, j) with i + j even, each block A_ij it lacks lumped
   onto both diagonal blocks as |A_ij|_F I (B bounds A from above: the world's lumped
   preconditioner). Every preconditioner, multigrid set up for B's pattern, converges to A's
   solution as the dense reference checks, and B was used (block-Jacobi takes another number
   of iterations than with A's own blocks). B of another vertex count, a NaN in B, and a
   hierarchy made for A's pattern leave x unchanged with named results. */
TEST(solve_preconditioned_by_a_sparser_matrix)
{
    dense_reference d;
    cloth_pcg_workspace ws;
    cloth_block_matrix B, small;
    int32_t *pair, count = 0, i, k, own_iterations = -1, other_iterations = -1;
    int pc;
    ENSURE(dense_reference_make(&d, 303, 40, 90, 7));
    pair = (int32_t *)malloc(sizeof(int32_t) * 2 * (size_t)d.pr.A.block_count);
    ENSURE(pair != NULL);
    for (i = 0; i < d.pr.n; ++i)
        for (k = d.pr.A.row_start[i]; k < d.pr.A.row_start[i + 1]; ++k)
            if (d.pr.A.column[k] > i && (i + d.pr.A.column[k]) % 2 == 0) {
                pair[2 * count] = i;
                pair[2 * count + 1] = d.pr.A.column[k];
                ++count;
            }
    ENSURE(cloth_block_matrix_create(&B, d.pr.n, pair, count, NULL) == CLOTH_SUCCESS);
    ENSURE(B.block_count < d.pr.A.block_count);
    for (i = 0; i < d.pr.n; ++i)
        for (k = d.pr.A.row_start[i]; k < d.pr.A.row_start[i + 1]; ++k) {
            int32_t j = d.pr.A.column[k], at = cloth_block_matrix_find(&B, i, j);
            const cloth_real *a = d.pr.A.value + 9 * (size_t)k;
            if (at >= 0) {
                memcpy(B.value + 9 * (size_t)at, a, 9 * sizeof(cloth_real));
            } else {
                double f = 0;
                int q;
                for (q = 0; q < 9; ++q) f += (double)a[q] * a[q];
                f = sqrt(f); /* counted from both (i, j) and (j, i): once onto each side */
                B.value[9 * (size_t)B.diagonal[i]] += (cloth_real)f;
                B.value[9 * (size_t)B.diagonal[i] + 4] += (cloth_real)f;
                B.value[9 * (size_t)B.diagonal[i] + 8] += (cloth_real)f;
            }
        }
    ENSURE(cloth_pcg_workspace_create(&ws, d.pr.n, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 4; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = pc < 3 ? all_preconditioners[pc] : CLOTH_PRECONDITIONER_MULTIGRID;
        opt.tolerance = (cloth_real)SOLVE_TOL;
        if (pc == 3) ENSURE(cloth_pcg_multigrid_setup(&ws, &B, NULL, NULL) == CLOTH_SUCCESS);
        for (i = 0; i < d.N; ++i) d.x[i] = 0;
        ENSURE(cloth_pcg_solve_preconditioned(&d.pr.A, &B, d.b, d.x, NULL, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged == 1);
        dense_reference_check(&d, &st);
        if (opt.preconditioner == CLOTH_PRECONDITIONER_BLOCK_JACOBI) {
            other_iterations = st.iterations;
            for (i = 0; i < d.N; ++i) d.x[i] = 0;
            ENSURE(cloth_pcg_solve(&d.pr.A, d.b, d.x, NULL, &opt, &ws, &st) == CLOTH_SUCCESS);
            own_iterations = st.iterations;
        }
    }
    ENSURE(own_iterations > 0 && other_iterations != own_iterations);
    {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_real keep;
        for (i = 0; i < d.N; ++i) d.x[i] = (cloth_real)0.5;
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        /* the hierarchy is B's: A's pattern does not match it */
        ENSURE(cloth_pcg_solve_preconditioned(&d.pr.A, &d.pr.A, d.b, d.x, NULL, &opt, &ws, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
        opt.preconditioner = CLOTH_PRECONDITIONER_BLOCK_JACOBI;
        ENSURE(cloth_block_matrix_create(&small, d.pr.n - 1, NULL, 0, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_solve_preconditioned(&d.pr.A, &small, d.b, d.x, NULL, &opt, &ws, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
        keep = B.value[4];
        B.value[4] = (cloth_real)NAN;
        ENSURE(cloth_pcg_solve_preconditioned(&d.pr.A, &B, d.b, d.x, NULL, &opt, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
        B.value[4] = keep;
        for (i = 0; i < d.N; ++i) ENSURE(d.x[i] == (cloth_real)0.5);
        cloth_block_matrix_free(&small);
    }
    free(pair);
    cloth_block_matrix_free(&B);
    cloth_pcg_workspace_free(&ws);
    dense_reference_free(&d);
}

/* ---- the constraint filter ---------------------------------------------------------- */

typedef struct filter_setup {
    int32_t *constrained;
    cloth_real *direction;
    cloth_real *value;
    double *s;  /* 9 per vertex: the filter S_i in double */
} filter_setup;

static void unit3(double *v)
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}

/* Vertices cycle through 0, 1, 2, 3 constrained directions; random directions except on
   vertices 1 and 2, which use coordinate axes (there the constrained components must come
   out bit-exact). z is random. */
static void make_filter(filter_setup *f, int32_t n, uint64_t seed)
{
    cloth_rng rng = cloth_rng_make(seed);
    int32_t i;
    int r, c;
    f->constrained = (int32_t *)malloc(sizeof(int32_t) * (size_t)n);
    f->direction = (cloth_real *)malloc(sizeof(cloth_real) * 6 * (size_t)n);
    f->value = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    f->s = (double *)malloc(sizeof(double) * 9 * (size_t)n);
    for (i = 0; i < n; ++i) {
        double p[3], q[3], t;
        int e;
        f->constrained[i] = i % 4;
        for (e = 0; e < 3; ++e) { p[e] = (double)cloth_rng_normal(&rng); q[e] = (double)cloth_rng_normal(&rng); }
        if (i == 1) { p[0] = 0; p[1] = 1; p[2] = 0; }
        if (i == 2) { p[0] = 1; p[1] = 0; p[2] = 0; q[0] = 0; q[1] = 0; q[2] = 1; }
        unit3(p);
        t = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        for (e = 0; e < 3; ++e) q[e] -= t * p[e];
        unit3(q);
        for (e = 0; e < 3; ++e) {
            f->direction[6 * i + e] = (cloth_real)p[e];
            f->direction[6 * i + 3 + e] = (cloth_real)q[e];
            f->value[3 * i + e] = (cloth_real)(2.0 * cloth_rng_normal(&rng));
        }
        /* S in double from the directions as stored (re-normalized in double) */
        for (e = 0; e < 3; ++e) { p[e] = (double)f->direction[6 * i + e]; q[e] = (double)f->direction[6 * i + 3 + e]; }
        unit3(p);
        t = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        for (e = 0; e < 3; ++e) q[e] -= t * p[e];
        unit3(q);
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) {
                double id = r == c ? 1.0 : 0.0;
                switch (f->constrained[i]) {
                case 0: f->s[9 * i + 3 * r + c] = id; break;
                case 1: f->s[9 * i + 3 * r + c] = id - p[r] * p[c]; break;
                case 2: f->s[9 * i + 3 * r + c] = id - p[r] * p[c] - q[r] * q[c]; break;
                default: f->s[9 * i + 3 * r + c] = 0; break;
                }
            }
    }
}

static void free_filter(filter_setup *f)
{
    free(f->constrained);
    free(f->direction);
    free(f->value);
    free(f->s);
}

/* The dense solution of the reduced system: x = y + c with c = (I - S) z and
   (S A S + (I - S)) y = S (b - A c), which has y in the range of S. With correct = 0 the
   right-hand side is S b, what a filter that forgets the prescribed values' coupling solves. */
static int reduced_reference(const double *a, int32_t n, const filter_setup *f, const cloth_real *b, int correct,
                             double *x)
{
    int N = 3 * n, i, j, r, c, k;
    double *k_mat = (double *)calloc((size_t)N * (size_t)N, sizeof(double));
    double *cz = (double *)malloc(sizeof(double) * (size_t)N);
    double *rhs = (double *)calloc((size_t)N, sizeof(double));
    double *tmp = (double *)malloc(sizeof(double) * (size_t)N);
    int ok;
    for (i = 0; i < n; ++i)
        for (r = 0; r < 3; ++r) {
            double s = (double)f->value[3 * i + r];
            for (c = 0; c < 3; ++c) s -= f->s[9 * i + 3 * r + c] * (double)f->value[3 * i + c];
            cz[3 * i + r] = s;
        }
    for (i = 0; i < N; ++i) {
        double s = (double)b[i];
        if (correct)
            for (j = 0; j < N; ++j) s -= a[i * N + j] * cz[j];
        tmp[i] = s;
    }
    for (i = 0; i < n; ++i)
        for (r = 0; r < 3; ++r) {
            double s = 0;
            for (c = 0; c < 3; ++c) s += f->s[9 * i + 3 * r + c] * tmp[3 * i + c];
            rhs[3 * i + r] = s;
        }
    /* K = S A S + (I - S), S block diagonal */
    for (i = 0; i < n; ++i)
        for (j = 0; j < n; ++j)
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) {
                    double s = 0;
                    int u, v;
                    for (u = 0; u < 3; ++u)
                        for (v = 0; v < 3; ++v)
                            s += f->s[9 * i + 3 * r + u] * a[(3 * i + u) * N + 3 * j + v] * f->s[9 * j + 3 * v + c];
                    if (i == j) s += (r == c ? 1.0 : 0.0) - f->s[9 * i + 3 * r + c];
                    k_mat[(3 * i + r) * N + 3 * j + c] = s;
                }
    ok = dense_solve(k_mat, N, rhs, x);
    for (k = 0; k < N; ++k) x[k] += cz[k];
    free(k_mat);
    free(cz);
    free(rhs);
    free(tmp);
    return ok;
}

TEST(filter_prescribed_values_match_reduced_system)
{
    spd_problem pr;
    filter_setup f;
    cloth_rng rng = cloth_rng_make(77);
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    int N, i, pc;
    double *a, *xd, *xnaive, diff = 0;
    cloth_real *b, *x;
    ENSURE(make_spd(&pr, 303, 44, 100, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 9);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    a = dense_from_blocks(&pr.A);
    xd = (double *)malloc(sizeof(double) * (size_t)N);
    xnaive = (double *)malloc(sizeof(double) * (size_t)N);
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    ENSURE(reduced_reference(a, pr.n, &f, b, 1, xd));
    ENSURE(reduced_reference(a, pr.n, &f, b, 0, xnaive));
    /* the test can tell: forgetting -S A (I - S) z moves the solution by O(1) */
    for (i = 0; i < N; ++i) diff += (xd[i] - xnaive[i]) * (xd[i] - xnaive[i]);
    ENSURE(sqrt(diff) / norm2(xd, N) > 0.05);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        double err = 0, bound;
        opt.preconditioner = all_preconditioners[pc];
        opt.tolerance = (cloth_real)SOLVE_TOL;
        for (i = 0; i < N; ++i) x[i] = (cloth_real)(i % 5); /* a start with constrained parts to replace */
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged == 1);
        /* constrained components: exact on pinned and axis-aligned vertices, to rounding elsewhere */
        for (i = 0; i < pr.n; ++i) {
            int r, c;
            if (f.constrained[i] == 3) {
                ENSURE(x[3 * i] == f.value[3 * i] && x[3 * i + 1] == f.value[3 * i + 1] && x[3 * i + 2] == f.value[3 * i + 2]);
            }
            if (i == 1) ENSURE(x[4] == f.value[4]);
            if (i == 2) ENSURE(x[6] == f.value[6] && x[8] == f.value[8]);
            for (r = 0; r < 3; ++r) {
                double cx = 0, mag = 0;
                for (c = 0; c < 3; ++c) {
                    double icomp = (r == c ? 1.0 : 0.0) - f.s[9 * i + 3 * r + c];
                    cx += icomp * ((double)x[3 * i + c] - (double)f.value[3 * i + c]);
                    mag += fabs((double)x[3 * i + c]) + fabs((double)f.value[3 * i + c]);
                }
                /* a handful of roundings: S y, (I - S) z and the stored directions */
                ENSURE(fabs(cx) <= 16 * EPS * mag);
            }
        }
        /* the free part is the reduced system's solution; the reduced matrix's condition is
           bounded by A's (interlacing) */
        bound = residual_bound(pr.kappa, SOLVE_TOL, st.iterations, pr.max_row_blocks);
        for (i = 0; i < N; ++i) err += ((double)x[i] - xd[i]) * ((double)x[i] - xd[i]);
        err = sqrt(err) / norm2(xd, N);
        ENSURE(err <= pr.kappa * bound);
        ENSURE(st.residual <= bound);
    }
    cloth_pcg_workspace_free(&ws);
    free(a);
    free(xd);
    free(xnaive);
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

/* A pinned vertex's diagonal block does not enter the reduced system: an indefinite block there
   must not stop the solve, whatever the preconditioner. */
TEST(pinned_vertex_block_is_ignored)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(3);
    cloth_real *b, *x, minus[9] = { -50, 0, 0, 0, -50, 0, 0, 0, -50 };
    int N, pc;
    ENSURE(make_spd(&pr, 404, 20, 40, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 4);
    ENSURE(f.constrained[3] == 3);
    cloth_block_matrix_add_block(&pr.A, pr.A.diagonal[3], 1, minus);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = all_preconditioners[pc];
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged);
    }
    /* unpinned, the same block makes the solve fail: the preconditioners see it at once */
    f.constrained[3] = 0;
    for (pc = 1; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        opt.preconditioner = all_preconditioners[pc];
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL) == CLOTH_ERROR_NOT_POSITIVE_DEFINITE);
    }
    cloth_pcg_workspace_free(&ws);
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

/* Without coupling between vertices the reduced system is block diagonal, and the restricted
   block-Jacobi preconditioner is its exact inverse: one iteration gives the solution. An
   unrestricted S A_ii^-1 S would not be exact where A_ii couples free and constrained
   directions. */
TEST(block_jacobi_exact_on_block_diagonal)
{
    cloth_block_matrix A;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_pcg_stats st;
    cloth_rng rng = cloth_rng_make(18);
    cloth_real b[3 * 24], x[3 * 24];
    double a[9 * 24], xd[3 * 24];
    int32_t n = 24, i;
    int r, c, k;
    ENSURE(cloth_block_matrix_create(&A, n, NULL, 0, NULL) == CLOTH_SUCCESS);
    make_filter(&f, n, 12);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    for (i = 0; i < n; ++i) {
        cloth_real g[9], h[9];
        random_block(&rng, 1.0, g);
        mul_at_b(g, g, h);
        for (k = 0; k < 9; ++k) h[k] += (cloth_real)(k % 4 == 0 ? 0.5 : 0.0);
        cloth_block_matrix_add_block(&A, A.diagonal[i], 1, h);
        for (k = 0; k < 9; ++k) a[9 * i + k] = (double)A.value[9 * A.diagonal[i] + k];
    }
    random_vector(&rng, b, 3 * n);
    /* the reference, vertex by vertex: (S A S + I - S) y = S (b - A c), x = y + c */
    for (i = 0; i < n; ++i) {
        double cz[3], t[3], rhs[3], m[9], y[3];
        const double *s = f.s + 9 * i;
        for (r = 0; r < 3; ++r) {
            cz[r] = (double)f.value[3 * i + r];
            for (c = 0; c < 3; ++c) cz[r] -= s[3 * r + c] * (double)f.value[3 * i + c];
        }
        for (r = 0; r < 3; ++r) {
            t[r] = (double)b[3 * i + r];
            for (c = 0; c < 3; ++c) t[r] -= a[9 * i + 3 * r + c] * cz[c];
        }
        for (r = 0; r < 3; ++r) {
            rhs[r] = 0;
            for (c = 0; c < 3; ++c) rhs[r] += s[3 * r + c] * t[c];
        }
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) {
                int u, v;
                m[3 * r + c] = (r == c ? 1.0 : 0.0) - s[3 * r + c];
                for (u = 0; u < 3; ++u)
                    for (v = 0; v < 3; ++v) m[3 * r + c] += s[3 * r + u] * a[9 * i + 3 * u + v] * s[3 * v + c];
            }
        ENSURE(dense_solve(m, 3, rhs, y));
        for (r = 0; r < 3; ++r) xd[3 * i + r] = y[r] + cz[r];
    }
    ENSURE(cloth_pcg_workspace_create(&ws, n, NULL) == CLOTH_SUCCESS);
    opt.preconditioner = CLOTH_PRECONDITIONER_BLOCK_JACOBI;
    opt.tolerance = (cloth_real)SOLVE_TOL;
    memset(x, 0, sizeof x);
    ENSURE(cloth_pcg_solve(&A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations == 1);
    /* each block's condition number is at most trace / 0.5 (eigenvalues of G^T G + 0.5 I lie in
       [0.5, trace]); the rounding of the 3x3 Cholesky inverse and of the one CG step is a small
       multiple of EPS times that, relative to the block's solution */
    for (i = 0; i < n; ++i) {
        double tr = a[9 * i] + a[9 * i + 4] + a[9 * i + 8], cond = tr / 0.5;
        for (r = 0; r < 3; ++r)
            ENSURE_NEAR(x[3 * i + r], xd[3 * i + r], 64 * cond * EPS * (fabs(xd[3 * i]) + fabs(xd[3 * i + 1]) + fabs(xd[3 * i + 2])));
    }
    cloth_pcg_workspace_free(&ws);
    cloth_block_matrix_free(&A);
    free_filter(&f);
}

/* ---- behaviour of the iteration ----------------------------------------------------- */

TEST(warm_start_from_solution)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(8);
    cloth_real *b, *x;
    int N, pc;
    ENSURE(make_spd(&pr, 505, 40, 90, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 5);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats first, again;
        opt.preconditioner = all_preconditioners[pc];
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &first) == CLOTH_SUCCESS);
        ENSURE(first.iterations >= 3);
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &again) == CLOTH_SUCCESS);
        ENSURE(again.iterations <= 1);
        ENSURE(again.converged);
    }
    cloth_pcg_workspace_free(&ws);
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

TEST(zero_right_hand_side)
{
    spd_problem pr;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_pcg_stats st;
    int32_t *constrained;
    cloth_real *b, *x, *z;
    int N, i;
    ENSURE(make_spd(&pr, 606, 12, 20, 0.5));
    N = 3 * pr.n;
    b = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    z = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    constrained = (int32_t *)malloc(sizeof(int32_t) * (size_t)pr.n);
    for (i = 0; i < N; ++i) { x[i] = (cloth_real)(1 + i); z[i] = (cloth_real)(-3 - i); }
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    /* b = 0, no constraints: x = 0 at once */
    ENSURE(cloth_pcg_solve(&pr.A, b, x, NULL, NULL, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations == 0 && st.converged == 1 && st.residual == 0);
    for (i = 0; i < N; ++i) ENSURE(x[i] == 0);
    /* every vertex pinned: bhat = 0 whatever b, and x = z exactly */
    for (i = 0; i < pr.n; ++i) constrained[i] = 3;
    filter.constrained = constrained;
    filter.direction = NULL;
    filter.value = z;
    b[0] = 1;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations == 0 && st.converged == 1);
    for (i = 0; i < N; ++i) ENSURE(x[i] == z[i]);
    cloth_pcg_workspace_free(&ws);
    free(b);
    free(x);
    free(z);
    free(constrained);
    free_spd(&pr);
}

TEST(iteration_cap)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(12);
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_pcg_stats st;
    cloth_real *b, *x;
    int N, i;
    ENSURE(make_spd(&pr, 707, 40, 90, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 6);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    opt.max_iterations = 3;
    opt.tolerance = (cloth_real)SOLVE_TOL;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_ERROR_CG_NOT_CONVERGED);
    ENSURE(st.iterations == 3 && st.converged == 0);
    ENSURE(st.preconditioned_residual > opt.tolerance);
    /* the last iterate honours the constraints */
    for (i = 0; i < pr.n; ++i)
        if (f.constrained[i] == 3) ENSURE(x[3 * i] == f.value[3 * i] && x[3 * i + 2] == f.value[3 * i + 2]);
    /* and going on from it converges */
    opt.max_iterations = 1000;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
    /* 0 iterations allowed: only the start is tested */
    memset(x, 0, sizeof(cloth_real) * (size_t)N);
    opt.max_iterations = 0;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_ERROR_CG_NOT_CONVERGED);
    ENSURE(st.iterations == 0);
    /* reference_norm: an absolute floor on the stopping test's scale. The same right-hand side
       scaled by 1e-3 solved relative to itself takes the full iterations; with the unscaled
       solve's rhs_norm as reference it stops at the unscaled solve's absolute accuracy, in
       fewer iterations, and the stats say converged */
    {
        cloth_pcg_stats full, small_rel, small_ref;
        cloth_real *bs = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
        cloth_pcg_filter zero_filter = filter;
        zero_filter.value = NULL; /* a constrained part scales with nothing: keep it zero */
        opt.max_iterations = 1000;
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &zero_filter, &opt, &ws, &full) == CLOTH_SUCCESS);
        ENSURE(full.rhs_norm > 0 && full.converged);
        for (i = 0; i < N; ++i) bs[i] = (cloth_real)1e-3 * b[i];
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, bs, x, &zero_filter, &opt, &ws, &small_rel) == CLOTH_SUCCESS);
        ENSURE_NEAR(small_rel.rhs_norm, 1e-3 * full.rhs_norm, 1e-9 * full.rhs_norm);
        opt.reference_norm = full.rhs_norm;
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, bs, x, &zero_filter, &opt, &ws, &small_ref) == CLOTH_SUCCESS);
        ENSURE(small_ref.converged && small_ref.iterations < small_rel.iterations);
        /* relative to its own right-hand side it stopped 1000 times less accurately, at most */
        ENSURE(small_ref.preconditioned_residual <= 1000 * opt.tolerance * (1 + 1e-9));
        ENSURE(small_ref.preconditioned_residual > opt.tolerance);
        /* a reference below the right-hand side's own norm changes nothing */
        opt.reference_norm = (cloth_real)1e-6 * small_rel.rhs_norm;
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, bs, x, &zero_filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.iterations == small_rel.iterations);
        opt.reference_norm = 0;
        free(bs);
    }
    cloth_pcg_workspace_free(&ws);
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

TEST(indefinite_matrix)
{
    /* [[I, 2I], [2I, I]] has eigenvalues 3 and -1 and identity diagonal blocks, so every
       preconditioner is the identity and CG meets negative curvature in its second step:
       with b = e0, x1 = e0, r1 = -2 e3, p1 = 4 e0 - 2 e3 and p1^T A p1 = -12. */
    const int32_t pair[2] = { 0, 1 };
    const cloth_real two_i[9] = { 2, 0, 0, 0, 2, 0, 0, 0, 2 };
    cloth_block_matrix A;
    cloth_pcg_workspace ws;
    int pc, i;
    ENSURE(cloth_block_matrix_create(&A, 2, pair, 1, NULL) == CLOTH_SUCCESS);
    cloth_block_matrix_add_diagonal(&A, 1, NULL);
    cloth_block_matrix_add_block(&A, cloth_block_matrix_find(&A, 0, 1), 1, two_i);
    cloth_block_matrix_add_block(&A, cloth_block_matrix_find(&A, 1, 0), 1, two_i);
    ENSURE(cloth_pcg_workspace_create(&ws, 2, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_real b[6] = { 1, 0, 0, 0, 0, 0 }, x[6] = { 0, 0, 0, 0, 0, 0 };
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = all_preconditioners[pc];
        ENSURE(cloth_pcg_solve(&A, b, x, NULL, &opt, &ws, &st) == CLOTH_ERROR_NOT_POSITIVE_DEFINITE);
        ENSURE(st.iterations == 1 && st.converged == 0);
        /* x holds the last iterate, e0 */
        ENSURE(x[0] == 1);
        for (i = 1; i < 6; ++i) ENSURE(x[i] == 0);
    }
    cloth_pcg_workspace_free(&ws);
    cloth_block_matrix_free(&A);
}

TEST(non_finite_input_leaves_x_unchanged)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(13);
    cloth_real *b, *x, *x0, nan_value, inf_value, keep;
    int N, i;
    ENSURE(make_spd(&pr, 808, 16, 30, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 7);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x0 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    for (i = 0; i < N; ++i) x0[i] = x[i] = (cloth_real)(0.25 * i);
    nan_value = (cloth_real)NAN;
    inf_value = (cloth_real)INFINITY;
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    /* NaN in b */
    keep = b[7];
    b[7] = nan_value;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0);
    b[7] = keep;
    /* infinity in z */
    keep = f.value[5];
    f.value[5] = inf_value;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0);
    f.value[5] = keep;
    /* NaN in an off-diagonal block of the matrix */
    for (i = 0; i < pr.A.block_count; ++i) /* the first off-diagonal block */
        if (i != pr.A.diagonal[pr.A.column[i]]) break;
    ENSURE(i < pr.A.block_count);
    i = 9 * i + 4;
    keep = pr.A.value[i];
    pr.A.value[i] = nan_value;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0);
    pr.A.value[i] = keep;
    /* NaN in a direction */
    keep = f.direction[6 * 1 + 1];
    f.direction[6 * 1 + 1] = nan_value;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0);
    f.direction[6 * 1 + 1] = keep;
    /* NaN in the start */
    x[4] = x0[4] = nan_value;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0);
    x[4] = x0[4] = 0;
    /* all restored: it solves */
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL) == CLOTH_SUCCESS);
    cloth_pcg_workspace_free(&ws);
    free(b);
    free(x);
    free(x0);
    free_filter(&f);
    free_spd(&pr);
}

TEST(invalid_arguments_leave_x_unchanged)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws, small;
    cloth_pcg_filter filter;
    cloth_pcg_options opt;
    cloth_rng rng = cloth_rng_make(14);
    cloth_real *b, *x, *x0, keep[6];
    int N, i;
    ENSURE(make_spd(&pr, 909, 16, 30, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 8);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x0 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    for (i = 0; i < N; ++i) x0[i] = x[i] = (cloth_real)(0.5 * i);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_workspace_create(&small, -1, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(small.memory == NULL);
    ENSURE(cloth_pcg_workspace_create(&small, pr.n - 1, NULL) == CLOTH_SUCCESS);
#define EXPECT_INVALID(call) do { ENSURE((call) == CLOTH_ERROR_INVALID_ARGUMENT); \
        ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0); } while (0)
    opt = cloth_default_pcg_options();
    opt.tolerance = -1;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    opt.tolerance = (cloth_real)NAN;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    opt = cloth_default_pcg_options();
    opt.max_iterations = -1;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    opt = cloth_default_pcg_options();
    opt.reference_norm = -1;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    opt.reference_norm = (cloth_real)INFINITY;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    opt = cloth_default_pcg_options();
    opt.preconditioner = (cloth_preconditioner)7;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL));
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &small, NULL));
    /* a constrained count outside 0..3 */
    f.constrained[5] = 4;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL));
    f.constrained[5] = -1;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL));
    f.constrained[5] = 1;
    /* a zero direction p on a vertex with 1, and q parallel to p on a vertex with 2 */
    ENSURE(f.constrained[5] == 1 && f.constrained[6] == 2);
    memcpy(keep, f.direction + 30, sizeof keep);
    f.direction[30] = f.direction[31] = f.direction[32] = 0;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL));
    memcpy(f.direction + 30, keep, sizeof keep);
    memcpy(keep, f.direction + 36, sizeof keep);
    for (i = 0; i < 3; ++i) f.direction[39 + i] = (cloth_real)-2.0 * f.direction[36 + i];
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL));
    memcpy(f.direction + 36, keep, sizeof keep);
    /* directions missing while some vertex needs them */
    filter.direction = NULL;
    EXPECT_INVALID(cloth_pcg_solve(&pr.A, b, x, &filter, NULL, &ws, NULL));
    filter.direction = f.direction;
#undef EXPECT_INVALID
    /* non-unit, non-orthogonal directions are normalized: scaling them changes nothing */
    {
        cloth_real *y = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
        cloth_pcg_options o = cloth_default_pcg_options();
        cloth_pcg_stats s1, s2;
        double diff = 0, size = 0, bound;
        o.tolerance = (cloth_real)SOLVE_TOL;
        memcpy(y, x0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &o, &ws, &s1) == CLOTH_SUCCESS);
        for (i = 0; i < pr.n; ++i) {
            int e;
            if (f.constrained[i] == 2)
                for (e = 0; e < 3; ++e) f.direction[6 * i + 3 + e] += (cloth_real)0.5 * f.direction[6 * i + e];
            for (e = 0; e < 6; ++e) f.direction[6 * i + e] *= 4;
        }
        ENSURE(cloth_pcg_solve(&pr.A, b, y, &filter, &o, &ws, &s2) == CLOTH_SUCCESS);
        /* both are within kappa times their residual bound of the same solution */
        bound = pr.kappa * (residual_bound(pr.kappa, SOLVE_TOL, s1.iterations, pr.max_row_blocks) +
                            residual_bound(pr.kappa, SOLVE_TOL, s2.iterations, pr.max_row_blocks));
        for (i = 0; i < N; ++i) {
            diff += ((double)y[i] - (double)x[i]) * ((double)y[i] - (double)x[i]);
            size += (double)x[i] * (double)x[i];
        }
        ENSURE(sqrt(diff) <= bound * sqrt(size));
        free(y);
    }
    cloth_pcg_workspace_free(&ws);
    cloth_pcg_workspace_free(&small);
    free(b);
    free(x);
    free(x0);
    free_filter(&f);
    free_spd(&pr);
}

/* ---- memory and determinism --------------------------------------------------------- */

typedef struct counting_allocator {
    long allocations, frees, fail_after; /* fail_after < 0: never fail */
} counting_allocator;

static void *counting_alloc(size_t size, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (c->fail_after >= 0 && c->allocations >= c->fail_after) return NULL;
    ++c->allocations;
    return malloc(size);
}

static void counting_free(void *ptr, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (ptr) ++c->frees;
    free(ptr);
}

TEST(solve_allocates_nothing)
{
    counting_allocator count = { 0, 0, -1 };
    cloth_allocator alloc;
    spd_problem pr;
    filter_setup f;
    cloth_block_matrix A;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(15);
    cloth_real *b, *x;
    int32_t *pair;
    long before;
    int N, i, k, pc;
    alloc.alloc = counting_alloc;
    alloc.free = counting_free;
    alloc.user = &count;
    ENSURE(make_spd(&pr, 1001, 30, 60, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 10);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    /* the same pattern made through the counting allocator, with the same values */
    pair = (int32_t *)malloc(sizeof(int32_t) * 2 * (size_t)pr.A.block_count);
    for (i = 0, k = 0; i < pr.n; ++i) {
        int32_t j;
        for (j = pr.A.row_start[i]; j < pr.A.row_start[i + 1]; ++j) { pair[2 * k] = i; pair[2 * k + 1] = pr.A.column[j]; ++k; }
    }
    ENSURE(cloth_block_matrix_create(&A, pr.n, pair, k, &alloc) == CLOTH_SUCCESS);
    ENSURE(A.block_count == pr.A.block_count);
    ENSURE(memcmp(A.column, pr.A.column, sizeof(int32_t) * (size_t)A.block_count) == 0);
    memcpy(A.value, pr.A.value, sizeof(cloth_real) * 9 * (size_t)A.block_count);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, &alloc) == CLOTH_SUCCESS);
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    before = count.allocations;
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        opt.preconditioner = all_preconditioners[pc];
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&A, b, x, &filter, &opt, &ws, NULL) == CLOTH_SUCCESS);
        cloth_block_matrix_zero(&A);
        memcpy(A.value, pr.A.value, sizeof(cloth_real) * 9 * (size_t)A.block_count);
        cloth_block_matrix_multiply(&A, b, x);
    }
    ENSURE(count.allocations == before);
    cloth_pcg_workspace_free(&ws);
    cloth_block_matrix_free(&A);
    ENSURE(count.frees == count.allocations);
    /* every allocation failure is reported and leaks nothing */
    for (k = 0; k <= 8; ++k) {
        cloth_result r;
        count.allocations = count.frees = 0;
        count.fail_after = k;
        r = cloth_block_matrix_create(&A, pr.n, pair, pr.A.block_count, &alloc);
        if (k < 8) {
            ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY);
            ENSURE(A.value == NULL && A.row_start == NULL && A.block_count == 0);
        } else {
            ENSURE(r == CLOTH_SUCCESS); /* 4 scratch arrays and 4 of the matrix */
            cloth_block_matrix_free(&A);
        }
        ENSURE(count.frees == count.allocations);
    }
    count.fail_after = 0;
    ENSURE(cloth_pcg_workspace_create(&ws, 10, &alloc) == CLOTH_ERROR_OUT_OF_MEMORY);
    ENSURE(ws.memory == NULL && ws.vertex_count == 0);
    free(pair);
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

TEST(deterministic)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws, other;
    cloth_pcg_filter filter;
    cloth_rng rng = cloth_rng_make(16);
    cloth_real *b, *x1, *x2;
    int N, pc;
    ENSURE(make_spd(&pr, 1102, 40, 90, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 11);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x1 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x2 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_workspace_create(&other, pr.n + 5, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats s1, s2;
        opt.preconditioner = all_preconditioners[pc];
        memset(x1, 0, sizeof(cloth_real) * (size_t)N);
        memset(x2, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, b, x1, &filter, &opt, &ws, &s1) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_solve(&pr.A, b, x2, &filter, &opt, &other, &s2) == CLOTH_SUCCESS);
        ENSURE(memcmp(x1, x2, sizeof(cloth_real) * (size_t)N) == 0);
        ENSURE(s1.iterations == s2.iterations && s1.residual == s2.residual);
    }
    cloth_pcg_workspace_free(&ws);
    cloth_pcg_workspace_free(&other);
    free(b);
    free(x1);
    free(x2);
    free_filter(&f);
    free_spd(&pr);
}

/* ---- preconditioners on an anisotropic, badly scaled problem ------------------------- */

/* The neighbour pairs of a g x g grid (right, below and the diagonal below-right), into pair
   (room for 6 g^2); returns how many. */
static int32_t grid_neighbour_pairs(int32_t g, int32_t *pair)
{
    int32_t i, j, count = 0;
    for (j = 0; j < g; ++j)
        for (i = 0; i < g; ++i) {
            int32_t v = j * g + i;
            if (i + 1 < g) { pair[2 * count] = v; pair[2 * count + 1] = v + 1; ++count; }
            if (j + 1 < g) { pair[2 * count] = v; pair[2 * count + 1] = v + g; ++count; }
            if (i + 1 < g && j + 1 < g) { pair[2 * count] = v; pair[2 * count + 1] = v + g + 1; ++count; }
        }
    return count;
}

/* A g x g grid: vertex i has the block s_i R_i diag(aniso, 1, 1) R_i^T (random rotation R_i,
   scale s_i = 10^u with u uniform in [-1.5, 1.5]), and neighbours (4-neighbourhood and one
   diagonal) are coupled by springs 0.3 sqrt(s_u s_v) d d^T along random unit d. Block-Jacobi
   removes both the scale and the anisotropy, Jacobi only the scale, none neither. */
static void make_anisotropic(cloth_block_matrix *A, int32_t g, double aniso, uint64_t seed)
{
    cloth_rng rng = cloth_rng_make(seed);
    int32_t n = g * g, i, k = 0, pc;
    int32_t *pair = (int32_t *)malloc(sizeof(int32_t) * 6 * (size_t)n);
    double *scale = (double *)malloc(sizeof(double) * (size_t)n);
    pc = grid_neighbour_pairs(g, pair);
    cloth_block_matrix_create(A, n, pair, pc, NULL);
    for (i = 0; i < n; ++i) {
        double q[4], rot[9], blk[9];
        cloth_real out[9];
        int r, c, e;
        scale[i] = pow(10.0, 3.0 * (double)cloth_rng_uniform(&rng) - 1.5);
        for (e = 0; e < 4; ++e) q[e] = (double)cloth_rng_normal(&rng);
        {
            double l = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            double w = q[0] / l, x = q[1] / l, y = q[2] / l, z = q[3] / l;
            rot[0] = 1 - 2 * (y * y + z * z); rot[1] = 2 * (x * y - w * z); rot[2] = 2 * (x * z + w * y);
            rot[3] = 2 * (x * y + w * z); rot[4] = 1 - 2 * (x * x + z * z); rot[5] = 2 * (y * z - w * x);
            rot[6] = 2 * (x * z - w * y); rot[7] = 2 * (y * z + w * x); rot[8] = 1 - 2 * (x * x + y * y);
        }
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c)
                blk[3 * r + c] = scale[i] * (aniso * rot[3 * r] * rot[3 * c] + rot[3 * r + 1] * rot[3 * c + 1] +
                                             rot[3 * r + 2] * rot[3 * c + 2]);
        for (e = 0; e < 9; ++e) out[e] = (cloth_real)blk[e];
        cloth_block_matrix_add_block(A, A->diagonal[i], 1, out);
    }
    for (k = 0; k < pc; ++k) {
        int32_t u = pair[2 * k], v = pair[2 * k + 1];
        double d[3], kk;
        cloth_real h[9];
        int r, c;
        for (r = 0; r < 3; ++r) d[r] = (double)cloth_rng_normal(&rng);
        unit3(d);
        kk = 0.3 * sqrt(scale[u] * scale[v]);
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) h[3 * r + c] = (cloth_real)(kk * d[r] * d[c]);
        cloth_block_matrix_add_block(A, A->diagonal[u], 1, h);
        cloth_block_matrix_add_block(A, A->diagonal[v], 1, h);
        cloth_block_matrix_add_block(A, cloth_block_matrix_find(A, u, v), -1, h);
        cloth_block_matrix_add_block_transposed(A, cloth_block_matrix_find(A, v, u), -1, h);
    }
    free(pair);
    free(scale);
}

TEST(preconditioner_ordering)
{
    cloth_block_matrix A;
    cloth_pcg_workspace ws;
    cloth_rng rng = cloth_rng_make(17);
    cloth_real *b, *x;
    int32_t g = 10, N, pc;
    int iterations[3];
    cloth_result result[3];
    make_anisotropic(&A, g, 300.0, 1203);
    ENSURE(A.vertex_count == g * g);
    N = 3 * A.vertex_count;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, A.vertex_count, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 3; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = all_preconditioners[pc];
        opt.tolerance = (cloth_real)(sizeof(cloth_real) < sizeof(double) ? 1e-4 : 1e-8);
        opt.max_iterations = 3000;
        memset(x, 0, sizeof(cloth_real) * (size_t)N);
        result[pc] = cloth_pcg_solve(&A, b, x, NULL, &opt, &ws, &st);
        iterations[pc] = st.iterations;
    }
    printf("    iterations: none %d (%s), jacobi %d (%s), block-jacobi %d (%s)\n", iterations[0],
           cloth_result_string(result[0]), iterations[1], cloth_result_string(result[1]), iterations[2],
           cloth_result_string(result[2]));
    ENSURE(result[2] == CLOTH_SUCCESS && result[1] == CLOTH_SUCCESS);
    /* none may hit the cap: then it is certainly the slowest */
    ENSURE(result[0] == CLOTH_SUCCESS || result[0] == CLOTH_ERROR_CG_NOT_CONVERGED);
    ENSURE(2 * iterations[2] < iterations[1]);
    ENSURE(2 * iterations[1] < iterations[0]);
    cloth_pcg_workspace_free(&ws);
    cloth_block_matrix_free(&A);
    free(b);
    free(x);
}

/* ---- multigrid ---------------------------------------------------------------------- */

/* Options that build a real hierarchy on the small test matrices: coarsen down to 4 vertices. */
static cloth_multigrid_options small_multigrid_options(void)
{
    cloth_multigrid_options o = cloth_default_multigrid_options();
    o.coarse_size = 4;
    return o;
}

/* A g x g cloth-like grid, 1 m wide, as the implicit integrator sees it: mass 0.1 dx^2 per
   vertex plus h^2 (h = 1/60) times the Hessians of stretch (5000 N/m), shear (2500 N/m) and
   bend (50 N/m) springs, with their clamped geometric terms, on a pose wrinkled with amplitude
   `wrinkle` (m) and 2 % compressed; stiff in the plane, soft across it. b = h M g plus noise;
   the two corners of row 0 pinned. */
/* The springs' stiffness of make_cloth_grid is multiplied by this (1 unless a test sets it). */
static double grid_stiffness_scale = 1;

static void make_cloth_grid(cloth_block_matrix *A, int32_t g, double wrinkle, cloth_real *b, int32_t *constrained)
{
    int32_t n = g * g, i, j, pc = 0, p;
    double dx = 1.0 / (g - 1), h = 1.0 / 60, mass = 0.1 * dx * dx;
    double *x = (double *)malloc(sizeof(double) * 3 * (size_t)n), *rest = (double *)malloc(sizeof(double) * 3 * (size_t)n);
    int32_t *pair = (int32_t *)malloc(sizeof(int32_t) * 12 * (size_t)n), *kind = (int32_t *)malloc(sizeof(int32_t) * 6 * (size_t)n);
    cloth_rng rng = cloth_rng_make(2027);
    for (j = 0; j < g; ++j)
        for (i = 0; i < g; ++i) {
            int32_t q = j * g + i;
            double u = i * dx - 0.5, w = j * dx - 0.5;
            rest[3 * q] = u;
            rest[3 * q + 1] = 0;
            rest[3 * q + 2] = w;
            x[3 * q] = 0.98 * u;
            x[3 * q + 1] = wrinkle * sin(9.0 * u) * cos(7.0 * w);
            x[3 * q + 2] = w;
        }
    for (j = 0; j < g; ++j)
        for (i = 0; i < g; ++i) {
            int32_t q = j * g + i;
#define GRID_SPRING(a, c, k) do { pair[2 * pc] = (a); pair[2 * pc + 1] = (c); kind[pc] = (k); ++pc; } while (0)
            if (i + 1 < g) GRID_SPRING(q, q + 1, 0);
            if (j + 1 < g) GRID_SPRING(q, q + g, 0);
            if (i + 1 < g && j + 1 < g) { GRID_SPRING(q, q + g + 1, 1); GRID_SPRING(q + 1, q + g, 1); }
            if (i + 2 < g) GRID_SPRING(q, q + 2, 2);
            if (j + 2 < g) GRID_SPRING(q, q + 2 * g, 2);
#undef GRID_SPRING
        }
    cloth_block_matrix_create(A, n, pair, pc, NULL);
    cloth_block_matrix_add_diagonal(A, (cloth_real)mass, NULL);
    for (p = 0; p < pc; ++p) {
        static const double stiffness[3] = { 5000, 2500, 50 };
        int32_t u = pair[2 * p], v = pair[2 * p + 1];
        double d[3], l = 0, l0 = 0, geo;
        cloth_real hb[9];
        int r, c;
        for (r = 0; r < 3; ++r) {
            d[r] = x[3 * v + r] - x[3 * u + r];
            l += d[r] * d[r];
            l0 += (rest[3 * v + r] - rest[3 * u + r]) * (rest[3 * v + r] - rest[3 * u + r]);
        }
        l = sqrt(l);
        l0 = sqrt(l0);
        for (r = 0; r < 3; ++r) d[r] /= l;
        geo = 1 - l0 / l > 0 ? 1 - l0 / l : 0;
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c)
                hb[3 * r + c] = (cloth_real)(h * h * grid_stiffness_scale * stiffness[kind[p]] *
                                             (d[r] * d[c] + geo * ((r == c ? 1.0 : 0.0) - d[r] * d[c])));
        cloth_block_matrix_add_block(A, A->diagonal[u], 1, hb);
        cloth_block_matrix_add_block(A, A->diagonal[v], 1, hb);
        cloth_block_matrix_add_block(A, cloth_block_matrix_find(A, u, v), -1, hb);
        cloth_block_matrix_add_block_transposed(A, cloth_block_matrix_find(A, v, u), -1, hb);
    }
    for (i = 0; i < 3 * n; ++i) b[i] = (cloth_real)(mass * (0.1 * (double)cloth_rng_normal(&rng) + (i % 3 == 1 ? -9.81 * h : 0)));
    for (i = 0; i < n; ++i) constrained[i] = 0;
    constrained[0] = constrained[g - 1] = 3;
    free(x);
    free(rest);
    free(pair);
    free(kind);
}

/* The multigrid-preconditioned solve agrees with the dense Cholesky solution, with several
   hierarchies: the defaults made to coarsen (four levels here), Jacobi smoothing, unsmoothed
   aggregation, two sweeps, a single dense level. */
TEST(multigrid_matches_dense_cholesky)
{
    dense_reference d;
    cloth_pcg_workspace ws;
    int i, variant;
    ENSURE(dense_reference_make(&d, 2020, 60, 150, 31));
    ENSURE(cloth_pcg_workspace_create(&ws, d.pr.n, NULL) == CLOTH_SUCCESS);
    for (variant = 0; variant < 5; ++variant) {
        cloth_multigrid_options mo = small_multigrid_options();
        cloth_multigrid_info info;
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        if (variant == 1) mo.smoother = CLOTH_MULTIGRID_SMOOTHER_JACOBI;
        if (variant == 2) mo.prolongator_damping = 0;
        if (variant == 3) mo.smoothing_steps = 2;
        if (variant == 4) { mo.max_levels = 1; mo.coarse_size = d.pr.n; }
        ENSURE(cloth_pcg_multigrid_setup(&ws, &d.pr.A, NULL, &mo) == CLOTH_SUCCESS);
        cloth_pcg_multigrid_info(&ws, &info);
        if (variant == 4) ENSURE(info.level_count == 1 && info.coarsest_dense == 1);
        else ENSURE(info.level_count >= (variant == 0 ? 3 : 2) && info.node_count[0] == d.pr.n && info.node_count[1] < d.pr.n);
        ENSURE(info.operator_complexity >= 1 && info.bytes > 0);
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        opt.tolerance = (cloth_real)SOLVE_TOL;
        for (i = 0; i < d.N; ++i) d.x[i] = 0;
        ENSURE(cloth_pcg_solve(&d.pr.A, d.b, d.x, NULL, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged == 1 && st.iterations > 0 && st.iterations <= d.N);
        /* a dense factor of the whole system is its inverse, applied in single precision:
           each step gains about 7 digits */
        if (variant == 4) ENSURE(st.iterations <= 2);
        dense_reference_check(&d, &st);
    }
    cloth_pcg_workspace_free(&ws);
    ENSURE(ws.multigrid == NULL);
    dense_reference_free(&d);
}

/* With 0, 1, 2 and 3 constrained directions and prescribed values, the multigrid solve gives
   the reduced system's solution, exact in the constrained components; also when the hierarchy
   was built under another filter and not updated (multigrid_update = 0): a weaker but valid
   preconditioner. */
TEST(multigrid_filter_matches_reduced_system)
{
    spd_problem pr;
    filter_setup f, other;
    cloth_rng rng = cloth_rng_make(78);
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter, other_filter;
    cloth_multigrid_options mo = small_multigrid_options();
    int N, i, pass;
    double *a, *xd;
    cloth_real *b, *x;
    ENSURE(make_spd(&pr, 3030, 64, 160, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 19);
    make_filter(&other, pr.n, 20);
    for (i = 0; i < pr.n; ++i) other.constrained[i] = (i * 7) % 4; /* other pins, other directions */
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    other_filter.constrained = other.constrained;
    other_filter.direction = other.direction;
    other_filter.value = other.value;
    a = dense_from_blocks(&pr.A);
    xd = (double *)malloc(sizeof(double) * (size_t)N);
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    ENSURE(reduced_reference(a, pr.n, &f, b, 1, xd));
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    for (pass = 0; pass < 3; ++pass) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        double err = 0, bound;
        /* pass 0: built for this filter; 1: built for the other, not updated; 2: built for the
           other, updated by the solve */
        ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, pass ? &other_filter : &filter, &mo) == CLOTH_SUCCESS);
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        opt.tolerance = (cloth_real)SOLVE_TOL;
        opt.multigrid_update = pass != 1;
        for (i = 0; i < N; ++i) x[i] = (cloth_real)(i % 5);
        ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.converged == 1);
        for (i = 0; i < pr.n; ++i) {
            int r, c;
            if (f.constrained[i] == 3)
                ENSURE(x[3 * i] == f.value[3 * i] && x[3 * i + 1] == f.value[3 * i + 1] && x[3 * i + 2] == f.value[3 * i + 2]);
            for (r = 0; r < 3; ++r) {
                double cx = 0, mag = 0;
                for (c = 0; c < 3; ++c) {
                    double icomp = (r == c ? 1.0 : 0.0) - f.s[9 * i + 3 * r + c];
                    cx += icomp * ((double)x[3 * i + c] - (double)f.value[3 * i + c]);
                    mag += fabs((double)x[3 * i + c]) + fabs((double)f.value[3 * i + c]);
                }
                ENSURE(fabs(cx) <= 16 * EPS * mag);
            }
        }
        if (f.constrained[1] == 1) ENSURE(x[4] == f.value[4]);
        if (f.constrained[2] == 2) ENSURE(x[6] == f.value[6] && x[8] == f.value[8]);
        bound = residual_bound(pr.kappa, SOLVE_TOL, st.iterations, pr.max_row_blocks);
        for (i = 0; i < N; ++i) err += ((double)x[i] - xd[i]) * ((double)x[i] - xd[i]);
        err = sqrt(err) / norm2(xd, N);
        ENSURE(err <= pr.kappa * bound);
        ENSURE(st.residual <= bound);
    }
    cloth_pcg_workspace_free(&ws);
    free(a);
    free(xd);
    free(b);
    free(x);
    free_filter(&f);
    free_filter(&other);
    free_spd(&pr);
}

/* On a stiff 32 x 32 cloth grid with two pinned corners, multigrid needs several times fewer
   iterations than block-Jacobi. Measured with the default options (double, tolerance 1e-8):
   block-Jacobi 690, multigrid 43 (16x); float, 1e-4: 443 and 19 (23x). Asserted: at least
   6x. */
TEST(multigrid_far_fewer_iterations)
{
    const int32_t g = 32, n = g * g;
    cloth_block_matrix A;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    int32_t *constrained = (int32_t *)malloc(sizeof(int32_t) * (size_t)n);
    int iterations[2], pc;
    make_cloth_grid(&A, g, 0.02, b, constrained);
    filter.constrained = constrained;
    filter.direction = NULL;
    filter.value = NULL;
    ENSURE(cloth_pcg_workspace_create(&ws, n, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_setup(&ws, &A, &filter, NULL) == CLOTH_SUCCESS);
    for (pc = 0; pc < 2; ++pc) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        opt.preconditioner = pc ? CLOTH_PRECONDITIONER_MULTIGRID : CLOTH_PRECONDITIONER_BLOCK_JACOBI;
        opt.tolerance = (cloth_real)(sizeof(cloth_real) < sizeof(double) ? 1e-4 : 1e-8);
        opt.max_iterations = 5000;
        memset(x, 0, sizeof(cloth_real) * 3 * (size_t)n);
        ENSURE(cloth_pcg_solve(&A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        iterations[pc] = st.iterations;
    }
    printf("    iterations: block-jacobi %d, multigrid %d\n", iterations[0], iterations[1]);
    ENSURE(6 * iterations[1] <= iterations[0]);
    cloth_pcg_workspace_free(&ws);
    cloth_block_matrix_free(&A);
    free(b);
    free(x);
    free(constrained);
}

/* The hierarchy's Galerkin products are summed in single precision (the linsolve banner). On
   very stiff cloth, where the coarse operators span the widest range of scales, the
   preconditioner must stay as good as with the same sums in double: a 48 x 48 grid (four
   levels) with springs 1, 100 and 10,000 times make_cloth_grid's, solved to 1e-8. Iterations
   with the double sums (the commit before they went to single precision): 52, 159 and 188;
   with the single-precision sums 52, 159 and 192. Asserted: at most 10% more, plus one. */
TEST(multigrid_keeps_its_iterations_on_very_stiff_cloth)
{
    static const double scale[3] = { 1, 100, 10000 };
    static const int32_t with_double_sums[3] = { 52, 159, 188 };
    const int32_t g = 48, n = g * g;
    int k;
    for (k = 0; k < 3; ++k) {
        cloth_block_matrix A;
        cloth_pcg_workspace ws;
        cloth_pcg_filter filter;
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        cloth_multigrid_info info;
        cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *x = (cloth_real *)calloc(3 * (size_t)n, sizeof(cloth_real));
        int32_t *constrained = (int32_t *)malloc(sizeof(int32_t) * (size_t)n);
        grid_stiffness_scale = scale[k];
        make_cloth_grid(&A, g, 0.02, b, constrained);
        grid_stiffness_scale = 1;
        filter.constrained = constrained;
        filter.direction = NULL;
        filter.value = NULL;
        ENSURE(cloth_pcg_workspace_create(&ws, n, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_multigrid_setup(&ws, &A, &filter, NULL) == CLOTH_SUCCESS);
        cloth_pcg_multigrid_info(&ws, &info);
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        opt.tolerance = (cloth_real)(sizeof(cloth_real) < sizeof(double) ? 1e-4 : 1e-8);
        opt.max_iterations = 2000;
        ENSURE(cloth_pcg_solve(&A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
        printf("    springs x %g: %d levels, %d iterations (double sums: %d)\n", scale[k], (int)info.level_count, (int)st.iterations,
               (int)with_double_sums[k]);
        ENSURE(info.level_count >= 3);
        if (sizeof(cloth_real) == sizeof(double)) ENSURE(10 * st.iterations <= 11 * with_double_sums[k] + 10);
        cloth_pcg_workspace_free(&ws);
        cloth_block_matrix_free(&A);
        free(b);
        free(x);
        free(constrained);
    }
}

/* The numeric phase depends on the hierarchy's patterns and the values it is given, nothing
   else. An update to new values (another pose) after any other update gives bit for bit what
   an update right after the setup gives; an update to 4 A (the same aggregates: strength does not see an exact
   scaling) gives bit for bit the solve of a fresh setup on 4 A; and a solve that updates itself
   equals an update then a solve that does not. */
TEST(multigrid_update_matches_fresh_setup)
{
    const int32_t g = 12, n = g * g;
    cloth_block_matrix A1, A2, A3, A4;
    cloth_pcg_workspace ws1, ws2;
    cloth_pcg_filter filter;
    cloth_multigrid_options mo = small_multigrid_options();
    cloth_multigrid_info info;
    cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *x1 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *x2 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    int32_t *constrained = (int32_t *)malloc(sizeof(int32_t) * (size_t)n);
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_pcg_stats s1, s2;
    int32_t k;
    make_cloth_grid(&A1, g, 0.02, b, constrained);
    make_cloth_grid(&A2, g, 0.03, b, constrained);
    make_cloth_grid(&A3, g, 0.01, b, constrained);
    make_cloth_grid(&A4, g, 0.02, b, constrained);
    /* A2, A3: other poses; A4 = 4 A1 exactly */
    for (k = 0; k < 9 * A1.block_count; ++k) A4.value[k] *= 4;
    filter.constrained = constrained;
    filter.direction = NULL;
    filter.value = NULL;
    opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
    opt.multigrid_update = 0;
    opt.tolerance = (cloth_real)SOLVE_TOL;
    ENSURE(cloth_pcg_workspace_create(&ws1, n, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_workspace_create(&ws2, n, NULL) == CLOTH_SUCCESS);
#define SAME_SOLVES(A) do { memset(x1, 0, sizeof(cloth_real) * 3 * (size_t)n); \
        memset(x2, 0, sizeof(cloth_real) * 3 * (size_t)n); \
        ENSURE(cloth_pcg_solve(&(A), b, x1, &filter, &opt, &ws1, &s1) == CLOTH_SUCCESS); \
        ENSURE(cloth_pcg_solve(&(A), b, x2, &filter, &opt, &ws2, &s2) == CLOTH_SUCCESS); \
        ENSURE(s1.iterations > 1 && s1.iterations == s2.iterations && s1.residual == s2.residual); \
        ENSURE(memcmp(x1, x2, sizeof(cloth_real) * 3 * (size_t)n) == 0); } while (0)
    /* history: setup A1, update A3, update A2 against setup A1, update A2 */
    ENSURE(cloth_pcg_multigrid_setup(&ws1, &A1, &filter, &mo) == CLOTH_SUCCESS);
    cloth_pcg_multigrid_info(&ws1, &info);
    ENSURE(info.level_count >= 3);
    ENSURE(cloth_pcg_multigrid_update(&ws1, &A3, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_update(&ws1, &A2, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_setup(&ws2, &A1, &filter, &mo) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_update(&ws2, &A2, &filter) == CLOTH_SUCCESS);
    SAME_SOLVES(A2);
    /* a fresh setup: setup A1, update A3, update A4 against setup A4 */
    ENSURE(cloth_pcg_multigrid_update(&ws1, &A3, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_update(&ws1, &A4, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_setup(&ws2, &A4, &filter, &mo) == CLOTH_SUCCESS);
    SAME_SOLVES(A4);
    /* the solve's own update (ws1 holds A3's values before it) against update then solve */
    ENSURE(cloth_pcg_multigrid_update(&ws1, &A3, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_update(&ws2, &A2, &filter) == CLOTH_SUCCESS);
    opt.multigrid_update = 1;
    memset(x1, 0, sizeof(cloth_real) * 3 * (size_t)n);
    ENSURE(cloth_pcg_solve(&A2, b, x1, &filter, &opt, &ws1, &s1) == CLOTH_SUCCESS);
    opt.multigrid_update = 0;
    memset(x2, 0, sizeof(cloth_real) * 3 * (size_t)n);
    ENSURE(cloth_pcg_solve(&A2, b, x2, &filter, &opt, &ws2, &s2) == CLOTH_SUCCESS);
    ENSURE(s1.iterations == s2.iterations && memcmp(x1, x2, sizeof(cloth_real) * 3 * (size_t)n) == 0);
#undef SAME_SOLVES
    cloth_pcg_workspace_free(&ws1);
    cloth_pcg_workspace_free(&ws2);
    cloth_block_matrix_free(&A1);
    cloth_block_matrix_free(&A2);
    cloth_block_matrix_free(&A3);
    cloth_block_matrix_free(&A4);
    free(b);
    free(x1);
    free(x2);
    free(constrained);
}

/* Setup allocates through the workspace's allocator and frees everything on failure; updates
   and solves allocate nothing; the same inputs give bit-identical results in another
   workspace. */
TEST(multigrid_allocates_nothing_and_is_deterministic)
{
    counting_allocator count = { 0, 0, -1 };
    cloth_allocator alloc;
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws, other;
    cloth_pcg_filter filter;
    cloth_multigrid_options mo = small_multigrid_options();
    cloth_rng rng = cloth_rng_make(51);
    cloth_real *b, *x1, *x2;
    long before, setup_allocations;
    int N, k, rep;
    alloc.alloc = counting_alloc;
    alloc.free = counting_free;
    alloc.user = &count;
    ENSURE(make_spd(&pr, 4040, 50, 120, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 21);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x1 = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    x2 = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, &alloc) == CLOTH_SUCCESS);
    before = count.allocations;
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, &mo) == CLOTH_SUCCESS);
    setup_allocations = count.allocations - before;
    ENSURE(setup_allocations > 0);
    before = count.allocations;
    for (rep = 0; rep < 3; ++rep) {
        cloth_pcg_options opt = cloth_default_pcg_options();
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        opt.multigrid_update = rep != 1;
        memset(x1, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_multigrid_update(&ws, &pr.A, &filter) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_solve(&pr.A, b, x1, &filter, &opt, &ws, NULL) == CLOTH_SUCCESS);
    }
    ENSURE(count.allocations == before);
    /* another workspace, larger, default allocator: the same bits */
    ENSURE(cloth_pcg_workspace_create(&other, pr.n + 7, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_multigrid_setup(&other, &pr.A, &filter, &mo) == CLOTH_SUCCESS);
    {
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats s1, s2;
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        memset(x1, 0, sizeof(cloth_real) * (size_t)N);
        ENSURE(cloth_pcg_solve(&pr.A, b, x1, &filter, &opt, &ws, &s1) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_solve(&pr.A, b, x2, &filter, &opt, &other, &s2) == CLOTH_SUCCESS);
        ENSURE(s1.iterations == s2.iterations && s1.residual == s2.residual);
        ENSURE(memcmp(x1, x2, sizeof(cloth_real) * (size_t)N) == 0);
    }
    cloth_pcg_workspace_free(&other);
    /* a second setup replaces the hierarchy and frees the first */
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, NULL, &mo) == CLOTH_SUCCESS);
    cloth_pcg_workspace_free(&ws);
    ENSURE(count.frees == count.allocations);
    /* every allocation failure of a setup is reported, leaves no hierarchy and leaks nothing */
    for (k = 0; k < setup_allocations; ++k) {
        count.allocations = count.frees = 0;
        count.fail_after = -1;
        ENSURE(cloth_pcg_workspace_create(&ws, pr.n, &alloc) == CLOTH_SUCCESS);
        count.fail_after = count.allocations + k;
        ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, &mo) == CLOTH_ERROR_OUT_OF_MEMORY);
        ENSURE(ws.multigrid == NULL);
        count.fail_after = -1;
        cloth_pcg_workspace_free(&ws);
        ENSURE(count.frees == count.allocations);
    }
    free(b);
    free(x1);
    free(x2);
    free_filter(&f);
    free_spd(&pr);
}

/* Bad arguments and bad data are rejected as the rest of the solver rejects them, with x left
   as it was. */
TEST(multigrid_invalid_input)
{
    spd_problem pr, other_pattern;
    filter_setup f;
    cloth_pcg_workspace ws, small;
    cloth_pcg_filter filter;
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_multigrid_options mo;
    cloth_multigrid_info info;
    cloth_rng rng = cloth_rng_make(61);
    cloth_real *b, *x, *x0, keep;
    int N, i;
    ENSURE(make_spd(&pr, 5050, 30, 70, 0.5));
    ENSURE(make_spd(&other_pattern, 5051, 30, 70, 0.5));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 22);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x0 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    random_vector(&rng, b, N);
    for (i = 0; i < N; ++i) x0[i] = x[i] = (cloth_real)(0.25 * i);
    opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_workspace_create(&small, pr.n - 1, NULL) == CLOTH_SUCCESS);
    cloth_pcg_multigrid_info(&ws, &info);
    ENSURE(info.level_count == 0);
#define EXPECT_X_KEPT(call, expected) do { ENSURE((call) == (expected)); \
        ENSURE(memcmp(x, x0, sizeof(cloth_real) * (size_t)N) == 0); } while (0)
    /* no hierarchy yet */
    EXPECT_X_KEPT(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL), CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_pcg_multigrid_update(&ws, &pr.A, &filter) == CLOTH_ERROR_INVALID_ARGUMENT);
    /* options out of range */
#define EXPECT_BAD_OPTION(field, bad) do { mo = cloth_default_multigrid_options(); mo.field = bad; \
        ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, &mo) == CLOTH_ERROR_INVALID_ARGUMENT); \
        ENSURE(ws.multigrid == NULL); } while (0)
    EXPECT_BAD_OPTION(strength_threshold, (cloth_real)-0.1);
    EXPECT_BAD_OPTION(strength_threshold, (cloth_real)1);
    EXPECT_BAD_OPTION(strength_threshold, (cloth_real)NAN);
    EXPECT_BAD_OPTION(prolongator_damping, (cloth_real)2.5);
    EXPECT_BAD_OPTION(prolongator_damping, (cloth_real)-1);
    EXPECT_BAD_OPTION(coarse_size, 0);
    EXPECT_BAD_OPTION(max_levels, 0);
    EXPECT_BAD_OPTION(max_levels, CLOTH_MULTIGRID_MAX_LEVELS + 1);
    EXPECT_BAD_OPTION(smoothing_steps, 0);
    EXPECT_BAD_OPTION(smoother, (cloth_multigrid_smoother)5);
#undef EXPECT_BAD_OPTION
    /* a workspace smaller than the matrix; a bad filter */
    ENSURE(cloth_pcg_multigrid_setup(&small, &pr.A, &filter, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    f.constrained[4] = 5;
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    f.constrained[4] = 0;
    /* a NaN among the values */
    keep = pr.A.value[13];
    pr.A.value[13] = (cloth_real)NAN;
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, NULL) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(ws.multigrid == NULL);
    pr.A.value[13] = keep;
    /* a hierarchy for another pattern is refused by solve and update */
    ENSURE(cloth_pcg_multigrid_setup(&ws, &other_pattern.A, NULL, NULL) == CLOTH_SUCCESS);
    EXPECT_X_KEPT(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL), CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_pcg_multigrid_update(&ws, &pr.A, &filter) == CLOTH_ERROR_INVALID_ARGUMENT);
    /* this pattern: an update with a NaN fails, leaves no values, and a solve that does not
       update is refused until an update succeeds */
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, NULL) == CLOTH_SUCCESS);
    pr.A.value[13] = (cloth_real)INFINITY;
    ENSURE(cloth_pcg_multigrid_update(&ws, &pr.A, &filter) == CLOTH_ERROR_NOT_FINITE);
    EXPECT_X_KEPT(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL), CLOTH_ERROR_NOT_FINITE);
    pr.A.value[13] = keep;
    opt.multigrid_update = 0;
    EXPECT_X_KEPT(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL), CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_pcg_multigrid_update(&ws, &pr.A, &filter) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, NULL) == CLOTH_SUCCESS);
    /* a free vertex whose diagonal block is not positive definite */
    for (i = 0; i < pr.n && f.constrained[i] != 0; ++i) {}
    ENSURE(i < pr.n);
    {
        cloth_real minus[9] = { -100, 0, 0, 0, -100, 0, 0, 0, -100 };
        cloth_block_matrix_add_block(&pr.A, pr.A.diagonal[i], 1, minus);
        ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, NULL) == CLOTH_ERROR_NOT_POSITIVE_DEFINITE);
        ENSURE(ws.multigrid == NULL);
    }
#undef EXPECT_X_KEPT
    cloth_pcg_workspace_free(&ws);
    cloth_pcg_workspace_free(&small);
    free(b);
    free(x);
    free(x0);
    free_filter(&f);
    free_spd(&pr);
    free_spd(&other_pattern);
}

/* The behaviours the other preconditioners show, with multigrid: a warm start at the solution
   takes at most one step; b = 0 gives x = (I - S) z at once; a pinned vertex's indefinite
   block is ignored; an indefinite system is reported; an empty system solves. */
TEST(multigrid_edge_cases)
{
    spd_problem pr;
    filter_setup f;
    cloth_pcg_workspace ws;
    cloth_pcg_filter filter;
    cloth_pcg_options opt = cloth_default_pcg_options();
    cloth_pcg_stats st;
    cloth_multigrid_options mo = small_multigrid_options();
    cloth_rng rng = cloth_rng_make(71);
    cloth_real *b, *x, minus[9] = { -50, 0, 0, 0, -50, 0, 0, 0, -50 };
    int N, i;
    ENSURE(make_spd(&pr, 6060, 40, 90, 0.6));
    N = 3 * pr.n;
    make_filter(&f, pr.n, 23);
    filter.constrained = f.constrained;
    filter.direction = f.direction;
    filter.value = f.value;
    b = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)N);
    x = (cloth_real *)calloc((size_t)N, sizeof(cloth_real));
    random_vector(&rng, b, N);
    opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
    ENSURE(cloth_pcg_workspace_create(&ws, pr.n, NULL) == CLOTH_SUCCESS);
    /* a pinned vertex's indefinite block changes nothing */
    ENSURE(f.constrained[3] == 3);
    cloth_block_matrix_add_block(&pr.A, pr.A.diagonal[3], 1, minus);
    ENSURE(cloth_pcg_multigrid_setup(&ws, &pr.A, &filter, &mo) == CLOTH_SUCCESS);
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations >= 3 && st.converged);
    /* warm start at the solution */
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations <= 1 && st.converged);
    /* every vertex pinned: x = z exactly, no iteration */
    for (i = 0; i < pr.n; ++i) f.constrained[i] = 3;
    ENSURE(cloth_pcg_solve(&pr.A, b, x, &filter, &opt, &ws, &st) == CLOTH_SUCCESS);
    ENSURE(st.iterations == 0 && st.converged);
    for (i = 0; i < N; ++i) ENSURE(x[i] == f.value[i]);
    cloth_pcg_workspace_free(&ws);
    {
        /* [[I, 2I], [2I, I]] is indefinite: its dense factor (the whole problem is one level)
           finds it at setup */
        const int32_t pair[2] = { 0, 1 };
        const cloth_real two_i[9] = { 2, 0, 0, 0, 2, 0, 0, 0, 2 };
        cloth_block_matrix A;
        ENSURE(cloth_block_matrix_create(&A, 2, pair, 1, NULL) == CLOTH_SUCCESS);
        cloth_block_matrix_add_diagonal(&A, 1, NULL);
        cloth_block_matrix_add_block(&A, cloth_block_matrix_find(&A, 0, 1), 1, two_i);
        cloth_block_matrix_add_block(&A, cloth_block_matrix_find(&A, 1, 0), 1, two_i);
        ENSURE(cloth_pcg_workspace_create(&ws, 2, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, NULL) == CLOTH_ERROR_NOT_POSITIVE_DEFINITE);
        cloth_pcg_workspace_free(&ws);
        cloth_block_matrix_free(&A);
    }
    {
        /* the empty system */
        cloth_block_matrix A;
        cloth_real none[1] = { 0 };
        ENSURE(cloth_block_matrix_create(&A, 0, NULL, 0, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_workspace_create(&ws, 0, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_multigrid_update(&ws, &A, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_pcg_solve(&A, none, none, NULL, &opt, &ws, &st) == CLOTH_SUCCESS);
        ENSURE(st.iterations == 0 && st.converged);
        cloth_pcg_workspace_free(&ws);
        cloth_block_matrix_free(&A);
    }
    free(b);
    free(x);
    free_filter(&f);
    free_spd(&pr);
}

/* ---- threads (cloth_pcg_workspace_set_threads) ---------------------------------------- */

/* A grid-shaped SPD system over nx * nx vertices (neighbours right, below and diagonal):
   random coupling blocks B (i, j) with B^T at (j, i), and diagonal blocks that dominate. */
static void make_grid_system_numbered(cloth_block_matrix *A, int32_t nx, uint64_t seed, const int32_t *number);

static void make_grid_system(cloth_block_matrix *A, int32_t nx, uint64_t seed)
{
    make_grid_system_numbered(A, nx, seed, NULL);
}

/* The same with grid vertex v numbered number[v] (NULL: v). */
static void make_grid_system_numbered(cloth_block_matrix *A, int32_t nx, uint64_t seed, const int32_t *number)
{
    cloth_rng rng = cloth_rng_make(seed);
    const int32_t n = nx * nx;
    int32_t *pair = (int32_t *)malloc(sizeof(int32_t) * 6 * (size_t)n), count, i, k;
    cloth_real *weight = (cloth_real *)calloc((size_t)n, sizeof(cloth_real));
    count = grid_neighbour_pairs(nx, pair);
    if (number)
        for (k = 0; k < 2 * count; ++k) pair[k] = number[pair[k]];
    cloth_block_matrix_create(A, n, pair, count, NULL);
    for (k = 0; k < count; ++k) {
        cloth_real b[9], sum = 0;
        int e;
        for (e = 0; e < 9; ++e) { b[e] = (cloth_real)cloth_rng_normal(&rng); sum += (cloth_real)fabs((double)b[e]); }
        cloth_block_matrix_add_block(A, cloth_block_matrix_find(A, pair[2 * k], pair[2 * k + 1]), 1, b);
        cloth_block_matrix_add_block_transposed(A, cloth_block_matrix_find(A, pair[2 * k + 1], pair[2 * k]), 1, b);
        weight[pair[2 * k]] += sum;
        weight[pair[2 * k + 1]] += sum;
    }
    for (i = 0; i < n; ++i) weight[i] = weight[i] * (cloth_real)1.01 + (cloth_real)1e-3;
    cloth_block_matrix_add_diagonal(A, 1, weight);
    free(pair);
    free(weight);
}

/* 1, 2 and 3 threads give the same bits, with block-Jacobi and with multigrid (Gauss-Seidel,
   then the Jacobi smoother, whose weight uses the scratch the rho estimate's start goes to),
   and a solve allocates nothing: on 27 x 27 vertices (three chunks of 256; one sweep part) and
   on 64 x 64 (multigrid's level-0 Gauss-Seidel in 4 parts, sweep_parts 0, split 1/1/2 over 3
   threads; and in 3 parts). One thread sweeps the parts two at a time, a row of each in turn;
   more threads sweep each part on its own. */
TEST(threads_solve_bit_identical_and_allocate_nothing)
{
    static const int32_t sides[3] = { 27, 64, 64 }, parts_asked[3] = { 0, 0, 3 }, parts_made[3] = { 1, 4, 3 };
    int side;
    for (side = 0; side < 3; ++side) {
        counting_allocator count = { 0, 0, -1 };
        cloth_allocator alloc;
        cloth_block_matrix A;
        cloth_pcg_workspace ws[3];
        cloth_pcg_filter filter;
        cloth_multigrid_info info;
        cloth_multigrid_options parted = cloth_default_multigrid_options();
        cloth_rng rng = cloth_rng_make(77);
        const int32_t nx = sides[side], n = nx * nx;
        int32_t *constrained = (int32_t *)calloc((size_t)n, sizeof(int32_t)), i;
        cloth_real *direction = (cloth_real *)calloc(6 * (size_t)n, sizeof(cloth_real));
        cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *x[3];
        int pc, t;
        alloc.alloc = counting_alloc;
        alloc.free = counting_free;
        alloc.user = &count;
        parted.sweep_parts = parts_asked[side]; /* 0: one per 1024 rows */
        make_grid_system(&A, nx, 91);
        constrained[0] = 3;
        constrained[nx - 1] = 3;
        for (i = 100; i < 140; ++i) { constrained[i] = 1; direction[6 * i + 1] = 1; }
        filter.constrained = constrained;
        filter.direction = direction;
        filter.value = NULL;
        for (i = 0; i < 3 * n; ++i) b[i] = (cloth_real)cloth_rng_normal(&rng);
        for (t = 0; t < 3; ++t) {
            x[t] = (cloth_real *)calloc(3 * (size_t)n, sizeof(cloth_real));
            ENSURE(cloth_pcg_workspace_create(&ws[t], n, &alloc) == CLOTH_SUCCESS);
            /* 1, 2 and 3 threads (single-threaded without CLOTH_THREADS: the same bits either way) */
            ENSURE(cloth_pcg_workspace_set_threads(&ws[t], t + 1) == CLOTH_SUCCESS);
            ENSURE(cloth_pcg_multigrid_setup(&ws[t], &A, &filter, &parted) == CLOTH_SUCCESS);
            cloth_pcg_multigrid_info(&ws[t], &info);
            ENSURE(info.sweep_parts == parts_made[side]);
        }
        ENSURE(cloth_pcg_workspace_set_threads(&ws[0], -1) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(cloth_pcg_workspace_set_threads(&ws[0], 65) == CLOTH_ERROR_INVALID_ARGUMENT);
        for (pc = 0; pc < 3; ++pc) {
            cloth_pcg_options opt = cloth_default_pcg_options();
            cloth_pcg_stats st[3];
            long before;
            if (pc == 2) {
                parted.smoother = CLOTH_MULTIGRID_SMOOTHER_JACOBI;
                for (t = 0; t < 3; ++t) ENSURE(cloth_pcg_multigrid_setup(&ws[t], &A, &filter, &parted) == CLOTH_SUCCESS);
            }
            before = count.allocations;
            opt.preconditioner = pc ? CLOTH_PRECONDITIONER_MULTIGRID : CLOTH_PRECONDITIONER_BLOCK_JACOBI;
            opt.tolerance = (cloth_real)1e-5;
            for (t = 0; t < 3; ++t) {
                memset(x[t], 0, sizeof(cloth_real) * 3 * (size_t)n);
                ENSURE(cloth_pcg_solve(&A, b, x[t], &filter, &opt, &ws[t], &st[t]) == CLOTH_SUCCESS);
                ENSURE(cloth_pcg_multigrid_update(&ws[t], &A, &filter) == CLOTH_SUCCESS);
            }
            ENSURE(count.allocations == before);
            ENSURE(st[0].iterations > 2);
            for (t = 1; t < 3; ++t) {
                ENSURE(st[t].iterations == st[0].iterations && st[t].residual == st[0].residual);
                ENSURE(memcmp(x[t], x[0], sizeof(cloth_real) * 3 * (size_t)n) == 0);
            }
        }
        for (t = 0; t < 3; ++t) {
            cloth_pcg_workspace_free(&ws[t]);
            free(x[t]);
        }
        ENSURE(count.frees == count.allocations);
        cloth_block_matrix_free(&A);
        free(constrained);
        free(direction);
        free(b);
    }
}

/* The solve's own products (two rows side by side, each summed as one row alone) are the
   matrix's: with no iterations allowed, the reported residual of a random start x on 27 x 27
   and 28 x 28 grids (an odd and an even number of rows, chunks of 256 ending odd and even)
   equals |b - A x| / |b| from cloth_block_matrix_multiply to rounding (1e-12; a row off by a
   relative 1e-9 fails it). */
TEST(solve_products_are_the_matrixs)
{
    int side;
    for (side = 27; side <= 28; ++side) {
        cloth_block_matrix A;
        cloth_pcg_workspace ws;
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        cloth_rng rng = cloth_rng_make(11);
        const int32_t n = side * side;
        cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        cloth_real *ax = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
        double rr = 0, bb = 0, expected;
        int32_t i;
        make_grid_system(&A, side, 5);
        for (i = 0; i < 3 * n; ++i) {
            b[i] = (cloth_real)cloth_rng_normal(&rng);
            x[i] = (cloth_real)cloth_rng_normal(&rng);
        }
        cloth_block_matrix_multiply(&A, x, ax);
        for (i = 0; i < 3 * n; ++i) {
            rr += ((double)b[i] - (double)ax[i]) * ((double)b[i] - (double)ax[i]);
            bb += (double)b[i] * (double)b[i];
        }
        expected = sqrt(rr / bb);
        ENSURE(cloth_pcg_workspace_create(&ws, n, NULL) == CLOTH_SUCCESS);
        opt.max_iterations = 0;
        ENSURE(cloth_pcg_solve(&A, b, x, NULL, &opt, &ws, &st) == CLOTH_ERROR_CG_NOT_CONVERGED);
        ENSURE(st.iterations == 0 && expected > 0.1);
        ENSURE(fabs((double)st.residual - expected) <= 1e-12 * expected);
        cloth_pcg_workspace_free(&ws);
        cloth_block_matrix_free(&A);
        free(b);
        free(x);
        free(ax);
    }
}

/* Level 0's sweep parts: one by default; with sweep_parts 0 one per 1024 rows, the 64 x 64
   grid numbered row by row has 4 parts and 3 x 64 separators; numbered at random, its
   separators would be most rows and it keeps one part. Both solve to the tolerance. Asked
   for, N parts (at most one per 256 rows); more than CLOTH_MULTIGRID_MAX_SWEEP_PARTS, or a
   negative number, is refused. */
TEST(multigrid_sweep_parts_follow_the_numbering)
{
    const int32_t nx = 64, n = nx * nx;
    int32_t *number = (int32_t *)malloc(sizeof(int32_t) * (size_t)n), i, run;
    cloth_real *b = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_rng rng = cloth_rng_make(5);
    for (i = 0; i < n; ++i) number[i] = i;
    for (i = n - 1; i > 0; --i) { /* Fisher-Yates */
        int32_t j = (int32_t)(cloth_rng_next(&rng) % (uint64_t)(i + 1)), t = number[i];
        number[i] = number[j];
        number[j] = t;
    }
    for (i = 0; i < 3 * n; ++i) b[i] = (cloth_real)cloth_rng_normal(&rng);
    for (run = 0; run < 2; ++run) {
        cloth_block_matrix A;
        cloth_pcg_workspace ws;
        cloth_multigrid_info info;
        cloth_pcg_options opt = cloth_default_pcg_options();
        cloth_pcg_stats st;
        cloth_multigrid_options mo = cloth_default_multigrid_options();
        make_grid_system_numbered(&A, nx, 91, run ? number : NULL);
        ENSURE(cloth_pcg_workspace_create(&ws, n, NULL) == CLOTH_SUCCESS);
        ENSURE(mo.sweep_parts == 1);
        ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, &mo) == CLOTH_SUCCESS);
        cloth_pcg_multigrid_info(&ws, &info);
        ENSURE(info.sweep_parts == 1);
        if (run == 0) {
            static const int32_t asked[3] = { 3, 8, 2 }, got[3] = { 3, 8, 2 };
            int q;
            for (q = 0; q < 3; ++q) {
                mo.sweep_parts = asked[q];
                ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, &mo) == CLOTH_SUCCESS);
                cloth_pcg_multigrid_info(&ws, &info);
                ENSURE(info.sweep_parts == got[q]);
            }
            mo.sweep_parts = CLOTH_MULTIGRID_MAX_SWEEP_PARTS + 1;
            ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, &mo) == CLOTH_ERROR_INVALID_ARGUMENT);
            mo.sweep_parts = -1;
            ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, &mo) == CLOTH_ERROR_INVALID_ARGUMENT);
        }
        mo.sweep_parts = 0;
        ENSURE(cloth_pcg_multigrid_setup(&ws, &A, NULL, &mo) == CLOTH_SUCCESS);
        cloth_pcg_multigrid_info(&ws, &info);
        ENSURE(info.sweep_parts == (run ? 1 : 4));
        opt.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
        opt.tolerance = (cloth_real)1e-5;
        memset(x, 0, sizeof(cloth_real) * 3 * (size_t)n);
        ENSURE(cloth_pcg_solve(&A, b, x, NULL, &opt, &ws, &st) == CLOTH_SUCCESS && st.converged);
        printf("    numbered %s: %d sweep parts, %d iterations\n", run ? "at random" : "row by row", (int)info.sweep_parts,
               (int)st.iterations);
        cloth_pcg_workspace_free(&ws);
        cloth_block_matrix_free(&A);
    }
    free(number);
    free(b);
    free(x);
}

const test_case linsolve_tests[] = {
    { "pattern_from_pairs", pattern_from_pairs },
    { "pattern_errors", pattern_errors },
    { "spmv_matches_dense", spmv_matches_dense },
    { "solve_matches_dense_cholesky", solve_matches_dense_cholesky },
    { "solve_preconditioned_by_a_sparser_matrix", solve_preconditioned_by_a_sparser_matrix },
    { "filter_prescribed_values_match_reduced_system", filter_prescribed_values_match_reduced_system },
    { "pinned_vertex_block_is_ignored", pinned_vertex_block_is_ignored },
    { "block_jacobi_exact_on_block_diagonal", block_jacobi_exact_on_block_diagonal },
    { "warm_start_from_solution", warm_start_from_solution },
    { "zero_right_hand_side", zero_right_hand_side },
    { "iteration_cap", iteration_cap },
    { "indefinite_matrix", indefinite_matrix },
    { "non_finite_input_leaves_x_unchanged", non_finite_input_leaves_x_unchanged },
    { "invalid_arguments_leave_x_unchanged", invalid_arguments_leave_x_unchanged },
    { "solve_allocates_nothing", solve_allocates_nothing },
    { "deterministic", deterministic },
    { "preconditioner_ordering", preconditioner_ordering },
    { "multigrid_matches_dense_cholesky", multigrid_matches_dense_cholesky },
    { "multigrid_filter_matches_reduced_system", multigrid_filter_matches_reduced_system },
    { "multigrid_far_fewer_iterations", multigrid_far_fewer_iterations },
    { "multigrid_keeps_its_iterations_on_very_stiff_cloth", multigrid_keeps_its_iterations_on_very_stiff_cloth },
    { "multigrid_update_matches_fresh_setup", multigrid_update_matches_fresh_setup },
    { "multigrid_allocates_nothing_and_is_deterministic", multigrid_allocates_nothing_and_is_deterministic },
    { "multigrid_invalid_input", multigrid_invalid_input },
    { "multigrid_edge_cases", multigrid_edge_cases },
    { "threads_solve_bit_identical_and_allocate_nothing", threads_solve_bit_identical_and_allocate_nothing },
    { "solve_products_are_the_matrixs", solve_products_are_the_matrixs },
    { "multigrid_sweep_parts_follow_the_numbering", multigrid_sweep_parts_follow_the_numbering },
    { NULL, NULL }
};
