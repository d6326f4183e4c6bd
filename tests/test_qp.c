/* Tests of the qp module: the KKT conditions checked independently, brute-force enumeration of
   active sets on small random zones, closed forms (vertex-face and edge-edge impacts, immovable
   vertices), already-feasible zones, degenerate rows (duplicates, four rows on one vertex pair,
   parallel normals, rows over immovable vertices), infeasible zones, bad input, determinism,
   memory, and the backward pass against finite differences and against the dense QR formula
   of docs/algorithms.md section 3. */
#include "runner.h"
#include "../cloth.h"
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ===================================================================================== */
/* helpers                                                                               */
/* ===================================================================================== */

#define IS_FLOAT (sizeof(cloth_real) == sizeof(float))
/* Relative tolerance of the KKT checks: rounding of the results to cloth_real. */
#define KTOL (IS_FLOAT ? 3e-5 : 1e-10)
/* Relative tolerance of comparisons with closed forms and with brute force. */
#define CTOL (IS_FLOAT ? 1e-4 : 1e-9)
/* Tolerance of an objective value f = sum |d|^2 / 2m: relative, plus what the rounding of z
   (positions of size 1) does to it. */
#define OBJTOL(f) (1e-14 + CTOL * (f) + (IS_FLOAT ? 1e-5 * sqrt(f) : 0))

#define MAXN 48
#define MAXM 64

typedef struct zone {
    int32_t n, m;
    cloth_real x[3 * MAXN];
    cloth_real iw[MAXN];
    cloth_qp_row rows[MAXM];
} zone;

static cloth_qp_problem zone_problem(const zone *zn)
{
    cloth_qp_problem p;
    p.vertex_count = zn->n;
    p.x = zn->x;
    p.inverse_weight = zn->iw;
    p.rows = zn->rows;
    p.row_count = zn->m;
    return p;
}

static void set_row(cloth_qp_row *r, const int v[4], const double a[4], const double nrm[3], double t)
{
    int k;
    for (k = 0; k < 4; ++k) {
        r->vertex[k] = v[k];
        r->weight[k] = (cloth_real)a[k];
    }
    for (k = 0; k < 3; ++k) r->normal[k] = (cloth_real)nrm[k];
    r->thickness = (cloth_real)t;
}

static double urand(cloth_rng *g) { return (double)cloth_rng_uniform(g); }
static int irand(cloth_rng *g, int k) { return (int)(cloth_rng_next(g) % (uint64_t)k); }

static void rand_unit(cloth_rng *g, double *nv)
{
    double len;
    do {
        nv[0] = (double)cloth_rng_normal(g);
        nv[1] = (double)cloth_rng_normal(g);
        nv[2] = (double)cloth_rng_normal(g);
        len = sqrt(nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2]);
    } while (len < 1e-3);
    nv[0] /= len; nv[1] /= len; nv[2] /= len;
}

/* sum_k a_k n . p_(v_k) of a row at positions p (as the row is stored). */
static double row_value(const cloth_qp_row *r, const cloth_real *p)
{
    double s = 0;
    int k, c;
    for (k = 0; k < 4; ++k) {
        if (r->vertex[k] < 0) continue;
        for (c = 0; c < 3; ++c) s += (double)r->weight[k] * (double)r->normal[c] * (double)p[3 * r->vertex[k] + c];
    }
    return s;
}

/* g_j(z) = t_j - sum a n.z, and the size of its terms. */
static double row_violation(const cloth_qp_row *r, const cloth_real *z, double *scale)
{
    double nn = sqrt((double)r->normal[0] * r->normal[0] + (double)r->normal[1] * r->normal[1] + (double)r->normal[2] * r->normal[2]);
    double sc = fabs((double)r->thickness);
    int k;
    for (k = 0; k < 4; ++k) {
        const cloth_real *p;
        if (r->vertex[k] < 0) continue;
        p = z + 3 * r->vertex[k];
        sc += fabs((double)r->weight[k]) * nn * sqrt((double)p[0] * p[0] + (double)p[1] * p[1] + (double)p[2] * p[2]);
    }
    *scale = sc;
    return (double)r->thickness - row_value(r, z);
}

/* A random row: vertex-face, edge-edge, vertex-vertex ([1, -1]) or vertex-obstacle ([1]) over
   distinct vertices, random unit normal, and a thickness that leaves a gap in
   [gap_lo, gap_hi] at x (gap > 0: violated). */
static void random_row(cloth_rng *g, const zone *zn, cloth_qp_row *row, double gap_lo, double gap_hi)
{
    int perm[MAXN], v[4] = { -1, -1, -1, -1 }, i, kind, count;
    double a[4] = { 0, 0, 0, 0 }, nv[3], s;
    for (i = 0; i < zn->n; ++i) perm[i] = i;
    for (i = 0; i < 4 && i < zn->n; ++i) {
        int j = i + irand(g, zn->n - i), tmp = perm[i];
        perm[i] = perm[j];
        perm[j] = tmp;
    }
    do kind = irand(g, 4); while ((kind < 2 && zn->n < 4) || (kind == 2 && zn->n < 2));
    if (kind == 0) {
        double b0 = urand(g) + 0.05, b1 = urand(g) + 0.05, b2 = urand(g) + 0.05, sb = b0 + b1 + b2;
        a[0] = 1; a[1] = -b0 / sb; a[2] = -b1 / sb; a[3] = -b2 / sb;
        count = 4;
    } else if (kind == 1) {
        double s0 = 0.05 + 0.9 * urand(g), t0 = 0.05 + 0.9 * urand(g);
        a[0] = s0; a[1] = 1 - s0; a[2] = -t0; a[3] = -(1 - t0);
        count = 4;
    } else if (kind == 2) {
        a[0] = 1; a[1] = -1;
        count = 2;
    } else {
        a[0] = 1;
        count = 1;
    }
    for (i = 0; i < count; ++i) v[i] = perm[i];
    rand_unit(g, nv);
    set_row(row, v, a, nv, 0);
    s = row_value(row, zn->x);
    row->thickness = (cloth_real)(s + gap_lo + (gap_hi - gap_lo) * urand(g));
}

/* n vertices in a box of side 1, inverse weights in [0.2, 5] (0 with probability p_fixed),
   m random rows. */
static void random_zone(cloth_rng *g, zone *zn, int n, int m, double p_fixed, double gap_lo, double gap_hi)
{
    int i;
    zn->n = n;
    zn->m = m;
    for (i = 0; i < 3 * n; ++i) zn->x[i] = (cloth_real)(urand(g) - 0.5);
    for (i = 0; i < n; ++i) zn->iw[i] = (cloth_real)(urand(g) < p_fixed ? 0.0 : 0.2 + 4.8 * urand(g));
    for (i = 0; i < m; ++i) random_row(g, zn, &zn->rows[i], gap_lo, gap_hi);
}

/* The KKT conditions of a result, computed here from the problem alone. */
typedef struct kkt {
    double stationarity;  /* max |z - x - M G-force| over movable coordinates / scale */
    double fixed_moved;   /* max |z - x| over immovable coordinates (must be 0) */
    double feasibility;   /* max_j max(g_j, 0) / scale_j */
    double dual;          /* max_j max(-lambda_j, 0) (must be 0) */
    double complementarity; /* max over lambda_j > 0 of |g_j| / scale_j */
    double objective;
} kkt;

static kkt kkt_check(const cloth_qp_problem *pr, const cloth_real *z, const cloth_real *lam)
{
    kkt k;
    double force[3 * MAXN], absf[3 * MAXN], scale = 0;
    int i, j, c, e;
    memset(&k, 0, sizeof k);
    for (i = 0; i < 3 * pr->vertex_count; ++i) force[i] = absf[i] = 0;
    for (j = 0; j < pr->row_count; ++j) {
        const cloth_qp_row *r = &pr->rows[j];
        double sc, g = row_violation(r, z, &sc);
        if (-(double)lam[j] > k.dual) k.dual = -(double)lam[j];
        if (sc > 0 && g / sc > k.feasibility) k.feasibility = g / sc;
        if (lam[j] > 0 && sc > 0 && fabs(g) / sc > k.complementarity) k.complementarity = fabs(g) / sc;
        for (e = 0; e < 4; ++e) {
            if (r->vertex[e] < 0) continue;
            for (c = 0; c < 3; ++c) {
                double f = (double)lam[j] * (double)r->weight[e] * (double)r->normal[c];
                force[3 * r->vertex[e] + c] += f;
                absf[3 * r->vertex[e] + c] += fabs(f);
            }
        }
    }
    for (i = 0; i < pr->vertex_count; ++i) {
        double mi = pr->inverse_weight ? (double)pr->inverse_weight[i] : 1.0;
        for (c = 0; c < 3; ++c) {
            double d = (double)z[3 * i + c] - (double)pr->x[3 * i + c];
            if (mi == 0) {
                if (fabs(d) > k.fixed_moved) k.fixed_moved = fabs(d);
                continue;
            }
            k.objective += 0.5 * d * d / mi;
            if (fabs(d) > scale) scale = fabs(d);
            if (mi * absf[3 * i + c] > scale) scale = mi * absf[3 * i + c];
        }
    }
    /* z itself is rounded to cloth_real: what is left of the residual after half an ulp of the
       coordinates (taken twice over) is the solver's error. */
    for (i = 0; i < pr->vertex_count; ++i) {
        double mi = pr->inverse_weight ? (double)pr->inverse_weight[i] : 1.0;
        if (mi == 0) continue;
        for (c = 0; c < 3; ++c) {
            double ulps = (IS_FLOAT ? FLT_EPSILON : DBL_EPSILON) * (fabs((double)z[3 * i + c]) + fabs((double)pr->x[3 * i + c]));
            double rr = fabs((double)z[3 * i + c] - (double)pr->x[3 * i + c] - mi * force[3 * i + c]) - ulps;
            if (rr < 0) rr = 0;
            if (scale > 0 && rr / scale > k.stationarity) k.stationarity = rr / scale;
        }
    }
    return k;
}

static int kkt_ok(const kkt *k)
{
    return k->stationarity <= KTOL && k->fixed_moved == 0 && k->feasibility <= KTOL && k->dual == 0 &&
           k->complementarity <= KTOL;
}

static void print_kkt(const char *what, const kkt *k)
{
    printf("    %s: stationarity %.3g, fixed moved %.3g, feasibility %.3g, dual %.3g, complementarity %.3g\n", what,
           k->stationarity, k->fixed_moved, k->feasibility, k->dual, k->complementarity);
}

/* ===================================================================================== */
/* brute force                                                                           */
/* ===================================================================================== */

/* Solve the dense system A x = b (dimension d <= 8) by Gaussian elimination with partial
   pivoting; returns 0 when a pivot is below 1e-12 of the largest diagonal entry. */
static int dense_solve(double A[8][8], double *b, int d)
{
    double big = 0;
    int i, j, k;
    for (i = 0; i < d; ++i)
        if (fabs(A[i][i]) > big) big = fabs(A[i][i]);
    for (k = 0; k < d; ++k) {
        int piv = k;
        for (i = k + 1; i < d; ++i)
            if (fabs(A[i][k]) > fabs(A[piv][k])) piv = i;
        if (!(fabs(A[piv][k]) > 1e-12 * big)) return 0;
        if (piv != k) {
            double t;
            for (j = 0; j < d; ++j) { t = A[k][j]; A[k][j] = A[piv][j]; A[piv][j] = t; }
            t = b[k]; b[k] = b[piv]; b[piv] = t;
        }
        for (i = k + 1; i < d; ++i) {
            double f = A[i][k] / A[k][k];
            for (j = k; j < d; ++j) A[i][j] -= f * A[k][j];
            b[i] -= f * b[k];
        }
    }
    for (i = d - 1; i >= 0; --i) {
        double s = b[i];
        for (j = i + 1; j < d; ++j) s -= A[i][j] * b[j];
        b[i] = s / A[i][i];
    }
    return 1;
}

/* Enumerate every subset S of rows, solve the equality-constrained problem with the rows of S,
   and keep the KKT points (lambda_S >= 0, every row met). Returns 1 with the smallest
   objective and its z, 0 when no subset gives a KKT point (infeasible). Dense G (m <= 8,
   n <= 4) in double from the stored problem. */
static int brute_force(const cloth_qp_problem *pr, double *best_obj, double *best_z)
{
    int n = pr->vertex_count, m = pr->row_count, N = 3 * n, found = 0;
    double G[8][12], h[8], mi[4], cx[8];
    unsigned mask;
    int i, j, k, c;
    for (i = 0; i < n; ++i) mi[i] = pr->inverse_weight ? (double)pr->inverse_weight[i] : 1.0;
    for (j = 0; j < m; ++j) {
        const cloth_qp_row *r = &pr->rows[j];
        for (c = 0; c < N; ++c) G[j][c] = 0;
        for (k = 0; k < 4; ++k)
            if (r->vertex[k] >= 0)
                for (c = 0; c < 3; ++c) G[j][3 * r->vertex[k] + c] -= (double)r->weight[k] * (double)r->normal[c];
        h[j] = (double)r->thickness;
        cx[j] = h[j];
        for (c = 0; c < N; ++c) cx[j] += G[j][c] * (double)pr->x[c];
    }
    for (mask = 0; mask < (1u << m); ++mask) {
        int S[8], q = 0, ok = 1;
        double Q[8][8], lam[8], z[12], obj = 0;
        for (j = 0; j < m; ++j)
            if (mask & (1u << j)) S[q++] = j;
        for (i = 0; i < q; ++i) {
            for (k = 0; k < q; ++k) {
                double s = 0;
                for (c = 0; c < N; ++c) s += G[S[i]][c] * mi[c / 3] * G[S[k]][c];
                Q[i][k] = s;
            }
            lam[i] = cx[S[i]];
        }
        if (q > 0 && !dense_solve(Q, lam, q)) continue;
        for (i = 0; i < q; ++i)
            if (lam[i] < -1e-9) ok = 0;
        if (!ok) continue;
        for (c = 0; c < N; ++c) {
            z[c] = (double)pr->x[c];
            for (i = 0; i < q; ++i) z[c] -= mi[c / 3] * G[S[i]][c] * lam[i];
        }
        for (j = 0; j < m && ok; ++j) {
            double g = h[j], sc = fabs(h[j]);
            for (c = 0; c < N; ++c) {
                g += G[j][c] * z[c];
                sc += fabs(G[j][c] * z[c]);
            }
            if (g > 1e-9 * sc) ok = 0;
        }
        if (!ok) continue;
        for (c = 0; c < N; ++c)
            if (mi[c / 3] > 0) obj += 0.5 * (z[c] - (double)pr->x[c]) * (z[c] - (double)pr->x[c]) / mi[c / 3];
        if (!found || obj < *best_obj) {
            *best_obj = obj;
            for (c = 0; c < N; ++c) best_z[c] = z[c];
        }
        found = 1;
    }
    return found;
}

/* ===================================================================================== */
/* options, closed forms, feasible zones                                                 */
/* ===================================================================================== */

TEST(default_options)
{
    cloth_qp_options o = cloth_qp_default_options();
    ENSURE(o.feasibility_tolerance == (cloth_real)1e-12);
    ENSURE(o.kkt_tolerance == (cloth_real)1e-9);
    ENSURE(o.dependency_tolerance == (cloth_real)(IS_FLOAT ? 1e-5 : 1e-10));
    ENSURE(o.max_iterations == 0);
}

/* One vertex-face impact: the vertex and the face move along the normal, each by its inverse
   weight times its weight times lambda = violation / sum_k a_k^2 m_k. */
TEST(single_vertex_face_closed_form)
{
    cloth_rng g = cloth_rng_make(11);
    int trial;
    for (trial = 0; trial < 50; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[12], lam[1];
        int32_t act[1];
        int v[4] = { 0, 1, 2, 3 }, k, c;
        double a[4], nv[3], b0 = 0.1 + urand(&g), b1 = 0.1 + urand(&g), b2 = 0.1 + urand(&g), sb = b0 + b1 + b2;
        double viol = 0.01 + urand(&g), denom = 0, lambda;
        cloth_qp_stats st;
        zn.n = 4;
        zn.m = 1;
        for (k = 0; k < 12; ++k) zn.x[k] = (cloth_real)(urand(&g) - 0.5);
        for (k = 0; k < 4; ++k) zn.iw[k] = (cloth_real)(0.1 + 3 * urand(&g));
        a[0] = 1; a[1] = -b0 / sb; a[2] = -b1 / sb; a[3] = -b2 / sb;
        rand_unit(&g, nv);
        set_row(&zn.rows[0], v, a, nv, 0);
        zn.rows[0].thickness = (cloth_real)(row_value(&zn.rows[0], zn.x) + viol);
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, &st) == CLOTH_SUCCESS);
        /* the exact answer from the stored (rounded) data */
        viol = (double)zn.rows[0].thickness - row_value(&zn.rows[0], zn.x);
        for (k = 0; k < 4; ++k) {
            double nn = 0;
            for (c = 0; c < 3; ++c) nn += (double)zn.rows[0].normal[c] * (double)zn.rows[0].normal[c];
            denom += (double)zn.rows[0].weight[k] * (double)zn.rows[0].weight[k] * (double)zn.iw[k] * nn;
        }
        lambda = viol / denom;
        ENSURE_NEAR(lam[0], lambda, CTOL * lambda);
        ENSURE(act[0] == CLOTH_QP_ACTIVE);
        ENSURE(st.active_count == 1 && st.tight_count == 0 && st.iterations == 1);
        for (k = 0; k < 4; ++k)
            for (c = 0; c < 3; ++c) {
                double expect = (double)zn.x[3 * k + c] + (double)zn.iw[k] * (double)zn.rows[0].weight[k] * lambda * (double)zn.rows[0].normal[c];
                ENSURE_NEAR(z[3 * k + c], expect, (IS_FLOAT ? 2e-7 : 2e-15) * (1 + fabs(expect)));
            }
        ENSURE(st.stationarity <= KTOL && st.primal_violation <= KTOL && st.complementarity <= KTOL);
    }
}

/* One edge-edge impact with weights [a0, a1, -b0, -b1], and the vertex-face row with the face
   immovable (the vertex takes the whole correction) or the vertex immovable. */
TEST(edge_edge_and_immovable_closed_forms)
{
    zone zn;
    cloth_qp_problem pr;
    cloth_real z[12], lam[1];
    int32_t act[1];
    int v[4] = { 0, 1, 2, 3 }, k, c, caseno;
    double a[4] = { 0.3, 0.7, -0.6, -0.4 }, nv[3] = { 0, 0.6, 0.8 };
    zn.n = 4;
    zn.m = 1;
    for (k = 0; k < 12; ++k) zn.x[k] = (cloth_real)(0.1 * k - 0.5);
    for (caseno = 0; caseno < 3; ++caseno) {
        double viol = 0.25, denom = 0, lambda;
        if (caseno == 1) { a[0] = 1; a[1] = -0.2; a[2] = -0.3; a[3] = -0.5; }
        for (k = 0; k < 4; ++k) zn.iw[k] = (cloth_real)(0.5 + k);
        if (caseno == 1) zn.iw[1] = zn.iw[2] = zn.iw[3] = 0; /* immovable face */
        if (caseno == 2) zn.iw[0] = 0;                       /* immovable vertex */
        set_row(&zn.rows[0], v, a, nv, 0);
        zn.rows[0].thickness = (cloth_real)(row_value(&zn.rows[0], zn.x) + viol);
        viol = (double)zn.rows[0].thickness - row_value(&zn.rows[0], zn.x);
        for (k = 0; k < 4; ++k) denom += (double)zn.rows[0].weight[k] * (double)zn.rows[0].weight[k] * (double)zn.iw[k];
        lambda = viol / denom;
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
        ENSURE_NEAR(lam[0], lambda, CTOL * lambda);
        for (k = 0; k < 4; ++k)
            for (c = 0; c < 3; ++c) {
                double expect = (double)zn.x[3 * k + c] + (double)zn.iw[k] * (double)zn.rows[0].weight[k] * lambda * (double)zn.rows[0].normal[c];
                if (zn.iw[k] == 0) ENSURE(z[3 * k + c] == zn.x[3 * k + c]); /* bit for bit */
                ENSURE_NEAR(z[3 * k + c], expect, (IS_FLOAT ? 2e-7 : 2e-15) * (1 + fabs(expect)));
            }
        if (caseno == 1) {
            /* the vertex alone moves, by the whole violation along the normal */
            ENSURE_NEAR((double)z[1] - (double)zn.x[1], 0.6 * viol, CTOL);
            ENSURE_NEAR((double)z[2] - (double)zn.x[2], 0.8 * viol, CTOL);
        }
    }
}

/* A zone that already meets every row comes back unchanged, bit for bit, with lambda = 0. */
TEST(already_feasible_is_identity)
{
    cloth_rng g = cloth_rng_make(3);
    cloth_qp_workspace ws;
    int trial;
    memset(&ws, 0, sizeof ws);
    for (trial = 0; trial < 200; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM];
        int32_t act[MAXM];
        cloth_qp_stats st;
        int j;
        random_zone(&g, &zn, 1 + irand(&g, 20), irand(&g, 30), 0.3, -0.5, -1e-6);
        pr = zone_problem(&zn);
        for (j = 0; j < zn.m; ++j) lam[j] = 7, act[j] = 7;
        ENSURE(cloth_qp_project(&ws, &pr, NULL, z, lam, act, &st) == CLOTH_SUCCESS);
        ENSURE(memcmp(z, zn.x, 3 * (size_t)zn.n * sizeof(cloth_real)) == 0);
        for (j = 0; j < zn.m; ++j) ENSURE(lam[j] == 0 && act[j] == CLOTH_QP_INACTIVE);
        ENSURE(st.iterations == 0 && st.objective == 0 && st.active_count == 0);
    }
    cloth_qp_workspace_free(&ws);
}

/* ===================================================================================== */
/* random zones: KKT, brute force, scale                                                 */
/* ===================================================================================== */

TEST(kkt_random_zones)
{
    cloth_rng g = cloth_rng_make(2024);
    cloth_qp_workspace ws;
    int trial, solved = 0, infeasible = 0;
    kkt worst;
    memset(&worst, 0, sizeof worst);
    ENSURE(cloth_qp_workspace_create(&ws, 8, 8, NULL) == CLOTH_SUCCESS);
    for (trial = 0; trial < 3000; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM];
        int32_t act[MAXM];
        cloth_qp_stats st;
        cloth_result r;
        kkt k;
        int j, n = 1 + irand(&g, 24), m = 1 + irand(&g, 40);
        random_zone(&g, &zn, n, m, trial % 3 == 0 ? 0.25 : 0.0, -0.3, 0.3);
        pr = zone_problem(&zn);
        r = cloth_qp_project(&ws, &pr, NULL, z, lam, act, &st);
        if (r == CLOTH_ERROR_COLLISION_UNRESOLVED) {
            ++infeasible;
            ENSURE(memcmp(z, zn.x, 3 * (size_t)n * sizeof(cloth_real)) == 0);
            continue;
        }
        ENSURE(r == CLOTH_SUCCESS);
        ++solved;
        k = kkt_check(&pr, z, lam);
        if (!kkt_ok(&k)) { printf("    trial %d (n %d, m %d)\n", trial, n, m); print_kkt("kkt", &k); }
        ENSURE(kkt_ok(&k));
        if (k.stationarity > worst.stationarity) worst.stationarity = k.stationarity;
        if (k.feasibility > worst.feasibility) worst.feasibility = k.feasibility;
        if (k.complementarity > worst.complementarity) worst.complementarity = k.complementarity;
        /* the library's own residuals agree with these */
        ENSURE(st.stationarity <= KTOL && st.primal_violation <= KTOL && st.complementarity <= KTOL);
        ENSURE_NEAR(st.objective, k.objective, 1e-12 + CTOL * k.objective);
        /* states: lambda only on active rows; active and tight rows meet their bound */
        for (j = 0; j < m; ++j) {
            double sc, gj = row_violation(&zn.rows[j], z, &sc);
            ENSURE(act[j] == CLOTH_QP_ACTIVE || lam[j] == 0);
            if (act[j] != CLOTH_QP_INACTIVE) ENSURE(fabs(gj) <= (IS_FLOAT ? 1e-5 : 2e-9) * sc);
            else ENSURE(gj < (IS_FLOAT ? KTOL * sc : 0));
        }
    }
    printf("    %d solved, %d infeasible; worst stationarity %.2g, feasibility %.2g, complementarity %.2g\n", solved,
           infeasible, worst.stationarity, worst.feasibility, worst.complementarity);
    ENSURE(solved > 2000);
    cloth_qp_workspace_free(&ws);
}

TEST(brute_force_small_zones)
{
    cloth_rng g = cloth_rng_make(77);
    int trial, agree_solved = 0, agree_infeasible = 0;
    for (trial = 0; trial < 4000; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[12], lam[8];
        int32_t act[8];
        double bobj = 0, bz[12];
        int n = 1 + irand(&g, 4), m = 1 + irand(&g, 5), found, c;
        cloth_result r;
        random_zone(&g, &zn, n, m, trial % 2 ? 0.3 : 0.0, -0.3, 0.4);
        pr = zone_problem(&zn);
        found = brute_force(&pr, &bobj, bz);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL);
        if (!found) {
            if (r != CLOTH_ERROR_COLLISION_UNRESOLVED) printf("    trial %d: brute force finds no KKT point, solver %d\n", trial, (int)r);
            ENSURE(r == CLOTH_ERROR_COLLISION_UNRESOLVED);
            ENSURE(memcmp(z, zn.x, 3 * (size_t)n * sizeof(cloth_real)) == 0);
            ++agree_infeasible;
            continue;
        }
        if (r != CLOTH_SUCCESS) printf("    trial %d: solver %d, brute force objective %.17g\n", trial, (int)r, bobj);
        ENSURE(r == CLOTH_SUCCESS);
        {
            kkt k = kkt_check(&pr, z, lam);
            ENSURE(kkt_ok(&k));
            ENSURE_NEAR(k.objective, bobj, OBJTOL(bobj));
        }
        for (c = 0; c < 3 * n; ++c) ENSURE_NEAR(z[c], bz[c], CTOL * (1 + fabs(bz[c])));
        ++agree_solved;
    }
    printf("    agree: %d solved, %d infeasible\n", agree_solved, agree_infeasible);
    ENSURE(agree_solved > 3000 && agree_infeasible > 50);
}

/* Zones far from the origin, tiny and huge ones: the tolerances are relative. */
TEST(scale_invariance)
{
    cloth_rng g = cloth_rng_make(5);
    int trial;
    for (trial = 0; trial < 300; ++trial) {
        double scale = trial % 3 == 0 ? 1e-3 : (trial % 3 == 1 ? 1.0 : 1e3);
        double offset = trial % 2 ? 1e3 * scale : 0;
        zone zn, ref;
        cloth_qp_problem pr, pref;
        cloth_real z[3 * MAXN], lam[MAXM], zr[3 * MAXN], lamr[MAXM];
        int i, n = 2 + irand(&g, 10), m = 1 + irand(&g, 12);
        kkt k;
        cloth_result r;
        random_zone(&g, &zn, n, m, 0.2, -1e-4, 1e-4);
        ref = zn;
        for (i = 0; i < 3 * n; ++i) zn.x[i] = (cloth_real)((double)zn.x[i] * scale + offset);
        for (i = 0; i < m; ++i) {
            /* the same gaps, scaled: thickness relative to the moved positions */
            double gap = (double)ref.rows[i].thickness - row_value(&ref.rows[i], ref.x);
            zn.rows[i].thickness = (cloth_real)(row_value(&zn.rows[i], zn.x) + gap * scale);
        }
        pr = zone_problem(&zn);
        pref = zone_problem(&ref);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, NULL, NULL);
        if (r == CLOTH_ERROR_COLLISION_UNRESOLVED) {
            ENSURE(cloth_qp_project(NULL, &pref, NULL, zr, lamr, NULL, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
            continue;
        }
        ENSURE(r == CLOTH_SUCCESS);
        k = kkt_check(&pr, z, lam);
        if (IS_FLOAT && offset > 0) continue; /* float positions 1e3 away cannot hold 1e-4 gaps */
        if (!kkt_ok(&k)) print_kkt("scaled", &k);
        ENSURE(kkt_ok(&k));
    }
}

/* Inverse weights over eight orders of magnitude (ARCSim treats obstacles as heavy
   deformables, mass 1e3 and up) and nearly parallel normals: ill-conditioned zones, some of
   which need enormous displacements. What the library returns as a solution is a KKT point to
   the same accuracy as for well-conditioned zones; zones it could not solve to kkt_tolerance
   would come back unresolved (none of these do: the unresolved ones are infeasible). */
TEST(ill_conditioned_zones)
{
    cloth_rng g = cloth_rng_make(123);
    int trial, solved = 0, unresolved = 0;
    kkt worst;
    memset(&worst, 0, sizeof worst);
    for (trial = 0; trial < 1500; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM];
        int32_t act[MAXM];
        cloth_result r;
        kkt k;
        int i, n = 2 + irand(&g, 10), m = 1 + irand(&g, 20);
        random_zone(&g, &zn, n, m, 0.1, -0.2, 0.3);
        for (i = 0; i < n; ++i)
            if (zn.iw[i] > 0) zn.iw[i] = (cloth_real)pow(10.0, -6 + 8 * urand(&g));
        if (trial % 2) {
            /* nearly parallel normals: each a small tilt of +y */
            for (i = 0; i < m; ++i) {
                double nv[3], t = 1e-3 * (1 + trial % 5), gap;
                gap = (double)zn.rows[i].thickness - row_value(&zn.rows[i], zn.x);
                rand_unit(&g, nv);
                nv[0] *= t; nv[2] *= t; nv[1] = 1;
                zn.rows[i].normal[0] = (cloth_real)(nv[0] / sqrt(1 + nv[0] * nv[0] + nv[2] * nv[2]));
                zn.rows[i].normal[1] = (cloth_real)(nv[1] / sqrt(1 + nv[0] * nv[0] + nv[2] * nv[2]));
                zn.rows[i].normal[2] = (cloth_real)(nv[2] / sqrt(1 + nv[0] * nv[0] + nv[2] * nv[2]));
                zn.rows[i].thickness = (cloth_real)(row_value(&zn.rows[i], zn.x) + gap);
            }
        }
        pr = zone_problem(&zn);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL);
        if (r == CLOTH_ERROR_COLLISION_UNRESOLVED) { ++unresolved; continue; }
        ENSURE(r == CLOTH_SUCCESS);
        ++solved;
        k = kkt_check(&pr, z, lam);
        if (!kkt_ok(&k)) { printf("    trial %d\n", trial); print_kkt("ill-conditioned", &k); }
        ENSURE(kkt_ok(&k));
        if (k.stationarity > worst.stationarity) worst.stationarity = k.stationarity;
        if (k.feasibility > worst.feasibility) worst.feasibility = k.feasibility;
        if (k.complementarity > worst.complementarity) worst.complementarity = k.complementarity;
    }
    printf("    %d solved, %d unresolved; worst stationarity %.2g, feasibility %.2g, complementarity %.2g\n", solved,
           unresolved, worst.stationarity, worst.feasibility, worst.complementarity);
    ENSURE(solved > 500);
}

/* Odd but valid input: a vertex named twice in a row, zero weights, zero normals, unused
   slots in the middle, inverse weights and coordinates from 1e-150 to 1e150. Every call
   returns success (with a KKT point), unresolved or not-finite (overflow), and ASan watches
   the memory. */
TEST(odd_input)
{
    cloth_rng g = cloth_rng_make(2718);
    int trial, counts[3] = { 0, 0, 0 };
    for (trial = 0; trial < 3000; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM];
        int32_t act[MAXM];
        cloth_result r;
        int i, k, n = 1 + irand(&g, 6), m = 1 + irand(&g, 10);
        double big = trial % 4 == 0 ? 1.0 : pow(10.0, (IS_FLOAT ? 30.0 : 150.0) * (2 * urand(&g) - 1));
        random_zone(&g, &zn, n, m, 0.2, -0.3, 0.3);
        for (i = 0; i < m; ++i) {
            cloth_qp_row *row = &zn.rows[i];
            if (irand(&g, 4) == 0) row->vertex[1] = row->vertex[0];     /* a vertex twice */
            if (irand(&g, 6) == 0) row->weight[irand(&g, 4)] = 0;       /* a zero weight */
            if (irand(&g, 10) == 0) row->normal[0] = row->normal[1] = row->normal[2] = 0;
            if (irand(&g, 6) == 0) { row->vertex[2] = -1; row->weight[2] = (cloth_real)1e30; }
            if (trial % 3 == 1) row->thickness = (cloth_real)((double)row->thickness * big);
        }
        if (trial % 3 == 1)
            for (i = 0; i < 3 * n; ++i) zn.x[i] = (cloth_real)((double)zn.x[i] * big);
        if (trial % 3 == 2)
            for (i = 0; i < n; ++i) zn.iw[i] = (cloth_real)((double)zn.iw[i] * big);
        pr = zone_problem(&zn);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL);
        ENSURE(r == CLOTH_SUCCESS || r == CLOTH_ERROR_COLLISION_UNRESOLVED || r == CLOTH_ERROR_NOT_FINITE);
        if (r != CLOTH_SUCCESS) {
            ENSURE(memcmp(z, zn.x, 3 * (size_t)n * sizeof(cloth_real)) == 0);
            ++counts[r == CLOTH_ERROR_COLLISION_UNRESOLVED ? 1 : 2];
            continue;
        }
        ++counts[0];
        for (k = 0; k < 3 * n; ++k) ENSURE(z[k] == z[k] && fabs((double)z[k]) <= DBL_MAX);
        {
            kkt kk = kkt_check(&pr, z, lam);
            if (!kkt_ok(&kk)) { printf("    trial %d (scale %g)\n", trial, big); print_kkt("odd", &kk); }
            ENSURE(kkt_ok(&kk));
        }
    }
    printf("    %d solved, %d unresolved, %d not finite\n", counts[0], counts[1], counts[2]);
}

/* A larger zone: a sheet of nx x nx vertices with m rows on its cells (random vertex-face and
   edge-edge weights among neighbours), each asking for its present value plus up to 0.7 mm;
   the KKT conditions, checked here, hold to KTOL. With signed_normals the normals point
   anywhere, so rows push against each other and rows leave the working set (drops) many
   times; otherwise they point up and few leave it. *exchanges_out gets the iterations beyond
   the active rows, summed over the trials; trial 2 pins the grid's last column. */
/* KKT of a large result, computed here as kkt_check does (stationarity over the largest
   displacement or force term, less the rounding of z and x to cloth_real), and the largest
   relative violation; ENSUREs dual feasibility and complementarity. */
static void large_kkt(const cloth_qp_problem *pr, const cloth_real *z, const cloth_real *lam, double *stationarity,
                      double *feasibility)
{
    int i, k, c, n = pr->vertex_count;
    double *force = (double *)calloc(6 * (size_t)n + 1, sizeof(double)), *absf, worst = 0, scale = 0;
    ENSURE(force != NULL);
    absf = force + 3 * (size_t)n;
    *feasibility = 0;
    for (i = 0; i < pr->row_count; ++i) {
        const cloth_qp_row *r = &pr->rows[i];
        double sc, gv = row_violation(r, z, &sc);
        ENSURE(lam[i] >= 0);
        if (gv / sc > *feasibility) *feasibility = gv / sc;
        if (lam[i] > 0) ENSURE(fabs(gv) <= KTOL * sc);
        for (k = 0; k < 4; ++k)
            if (r->vertex[k] >= 0)
                for (c = 0; c < 3; ++c) {
                    double f = (double)lam[i] * (double)r->weight[k] * (double)r->normal[c];
                    force[3 * r->vertex[k] + c] += f;
                    absf[3 * r->vertex[k] + c] += fabs(f);
                }
    }
    for (i = 0; i < 3 * n; ++i) {
        double mi = pr->inverse_weight ? (double)pr->inverse_weight[i / 3] : 1.0, d = (double)z[i] - (double)pr->x[i];
        if (mi == 0) continue;
        if (fabs(d) > scale) scale = fabs(d);
        if (mi * absf[i] > scale) scale = mi * absf[i];
    }
    for (i = 0; i < 3 * n; ++i) {
        double mi = pr->inverse_weight ? (double)pr->inverse_weight[i / 3] : 1.0;
        double ulps = (IS_FLOAT ? FLT_EPSILON : DBL_EPSILON) * (fabs((double)z[i]) + fabs((double)pr->x[i]));
        double d = fabs((double)z[i] - (double)pr->x[i] - mi * force[i]) - ulps;
        if (mi > 0 && d > worst) worst = d;
    }
    *stationarity = scale > 0 ? worst / scale : worst;
    free(force);
}

static void large_zone_run(uint64_t seed, int nx, int m, int signed_normals, int trials, int *exchanges_out)
{
    cloth_rng g = cloth_rng_make(seed);
    int n = nx * nx, i, j, trial;
    cloth_real *x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *z = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n);
    cloth_real *iw = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)n);
    cloth_real *lam = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)m);
    int32_t *act = (int32_t *)malloc(sizeof(int32_t) * (size_t)m);
    cloth_qp_row *rows = (cloth_qp_row *)malloc(sizeof(cloth_qp_row) * (size_t)m);
    cloth_qp_workspace ws;
    ENSURE(x && z && iw && lam && act && rows);
    memset(&ws, 0, sizeof ws);
    *exchanges_out = 0;
    for (trial = 0; trial < trials; ++trial) {
        cloth_qp_problem pr;
        cloth_qp_stats st;
        double worst = 0, feas = 0;
        for (i = 0; i < nx; ++i)
            for (j = 0; j < nx; ++j) {
                int v = i * nx + j;
                x[3 * v] = (cloth_real)(0.05 * i + 0.01 * urand(&g));
                x[3 * v + 1] = (cloth_real)(0.01 * urand(&g));
                x[3 * v + 2] = (cloth_real)(0.05 * j + 0.01 * urand(&g));
                iw[v] = (cloth_real)(trial == 2 && j == nx - 1 ? 0.0 : 0.5 + urand(&g));
            }
        for (i = 0; i < m; ++i) {
            int ci = irand(&g, nx - 1), cj = irand(&g, nx - 1), v0 = ci * nx + cj, vv[4];
            double a[4], nv[3];
            vv[0] = v0; vv[1] = v0 + 1; vv[2] = v0 + nx; vv[3] = v0 + nx + 1;
            if (irand(&g, 2)) { double b0 = urand(&g) + 0.1, b1 = urand(&g) + 0.1, b2 = urand(&g) + 0.1, sb = b0 + b1 + b2;
                a[0] = 1; a[1] = -b0 / sb; a[2] = -b1 / sb; a[3] = -b2 / sb; }
            else { double s0 = urand(&g), t0 = urand(&g); a[0] = s0; a[1] = 1 - s0; a[2] = -t0; a[3] = -(1 - t0); }
            rand_unit(&g, nv);
            if (!signed_normals && nv[1] < 0) { nv[0] = -nv[0]; nv[1] = -nv[1]; nv[2] = -nv[2]; }
            set_row(&rows[i], vv, a, nv, 0);
            rows[i].thickness = (cloth_real)(row_value(&rows[i], x) + 1e-3 * (urand(&g) - 0.3));
        }
        pr.vertex_count = n; pr.x = x; pr.inverse_weight = iw; pr.rows = rows; pr.row_count = m;
        ENSURE(cloth_qp_project(&ws, &pr, NULL, z, lam, act, &st) == CLOTH_SUCCESS);
        large_kkt(&pr, z, lam, &worst, &feas);
        printf("    %d rows: %d iterations, %d active, %d tight; stationarity %.2g, feasibility %.2g\n", m, (int)st.iterations,
               (int)st.active_count, (int)st.tight_count, worst, feas);
        ENSURE(worst <= KTOL && feas <= KTOL);
        *exchanges_out += st.iterations - st.active_count;
    }
    cloth_qp_workspace_free(&ws);
    free(x); free(z); free(iw); free(lam); free(act); free(rows);
}

TEST(large_zone)
{
    int exchanges;
    large_zone_run(99, 20, 600, 0, 3, &exchanges);
}

/* Rows pushing every way on a 20 x 20 grid: a working set of hundreds of rows from which rows
   leave and join hundreds of times (the factor's deletions and additions at a size where
   its rows are long), still exact. */
TEST(large_zone_with_many_exchanges)
{
    int exchanges = -1;
    large_zone_run(7, 20, 1600, 1, 3, &exchanges);
    printf("    %d exchanges\n", exchanges);
    ENSURE(exchanges >= 1000);
}

/* ===================================================================================== */
/* degenerate zones                                                                      */
/* ===================================================================================== */

/* The same row two and three times, in any order and with a weaker copy: the solution of the
   single row, one row active carrying the whole multiplier, the copies tight with lambda 0. */
TEST(duplicate_rows)
{
    zone zn, one;
    cloth_qp_problem pr, p1;
    cloth_real z[12], z1[12], lam[4], lam1[1];
    int32_t act[4];
    int v[4] = { 0, 1, 2, 3 }, copies, k, c;
    double a[4] = { 1, -0.2, -0.3, -0.5 }, nv[3] = { 0.48, 0.6, 0.64 };
    one.n = 4; one.m = 1;
    for (k = 0; k < 12; ++k) one.x[k] = (cloth_real)(0.07 * k);
    for (k = 0; k < 4; ++k) one.iw[k] = (cloth_real)(1 + k);
    set_row(&one.rows[0], v, a, nv, 0);
    one.rows[0].thickness = (cloth_real)(row_value(&one.rows[0], one.x) + 0.1);
    p1 = zone_problem(&one);
    ENSURE(cloth_qp_project(NULL, &p1, NULL, z1, lam1, NULL, NULL) == CLOTH_SUCCESS);
    for (copies = 2; copies <= 4; ++copies) {
        double sum = 0;
        int active = 0, tight = 0;
        kkt kk;
        zn = one;
        zn.m = copies;
        for (k = 1; k < copies; ++k) zn.rows[k] = one.rows[0];
        if (copies == 4) zn.rows[2].thickness = (cloth_real)((double)zn.rows[2].thickness - 0.05); /* a weaker copy */
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
        kk = kkt_check(&pr, z, lam);
        ENSURE(kkt_ok(&kk));
        for (k = 0; k < copies; ++k) {
            sum += (double)lam[k];
            active += act[k] == CLOTH_QP_ACTIVE;
            tight += act[k] == CLOTH_QP_TIGHT;
            if (act[k] != CLOTH_QP_ACTIVE) ENSURE(lam[k] == 0);
        }
        ENSURE(active == 1);
        ENSURE(tight == copies - 1 - (copies == 4));
        ENSURE(act[0] == CLOTH_QP_ACTIVE); /* the first of equal rows wins */
        if (copies == 4) ENSURE(act[2] == CLOTH_QP_INACTIVE);
        ENSURE_NEAR(sum, lam1[0], CTOL * lam1[0]);
        for (c = 0; c < 12; ++c) ENSURE_NEAR(z[c], z1[c], CTOL);
    }
}

/* Rows on one vertex pair: [1, -1] with three independent normals and a fourth normal in their
   span (rank 3 in a 6-dimensional space), parallel normals with different thicknesses, and a
   row given twice with its normal scaled by 2 (the same constraint written differently). */
TEST(dependent_rows_on_a_vertex_pair)
{
    cloth_rng g = cloth_rng_make(8);
    int trial;
    for (trial = 0; trial < 300; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[6], lam[8];
        int32_t act[8];
        int v[4] = { 0, 1, -1, -1 }, j, active = 0;
        double a[4] = { 1, -1, 0, 0 }, nv[8][3], bobj = 0, bz[12];
        kkt kk;
        cloth_result r;
        zn.n = 2;
        zn.m = 4 + irand(&g, 4);
        for (j = 0; j < 6; ++j) zn.x[j] = (cloth_real)(urand(&g) - 0.5);
        zn.iw[0] = (cloth_real)(0.5 + urand(&g));
        zn.iw[1] = (cloth_real)(trial % 4 == 0 ? 0.0 : 0.5 + urand(&g));
        rand_unit(&g, nv[0]); rand_unit(&g, nv[1]); rand_unit(&g, nv[2]);
        for (j = 0; j < 3; ++j) nv[3][j] = 0.6 * nv[0][j] + 0.8 * nv[1][j]; /* in the span, not unit */
        for (j = 4; j < zn.m; ++j) {
            int src = irand(&g, 4), c;
            double f = j == 6 ? 2.0 : 1.0;
            for (c = 0; c < 3; ++c) nv[j][c] = f * nv[src][c];
        }
        for (j = 0; j < zn.m; ++j) {
            set_row(&zn.rows[j], v, a, nv[j], 0);
            zn.rows[j].thickness = (cloth_real)(row_value(&zn.rows[j], zn.x) + 0.3 * (urand(&g) - 0.2));
        }
        if (zn.m > 6) { /* row 6 is 2 x row src with twice the thickness gap: an exact multiple */
            zn.rows[6].thickness = (cloth_real)(2 * (double)zn.rows[irand(&g, 1)].thickness);
            zn.rows[6].normal[0] = (cloth_real)(2 * (double)zn.rows[0].normal[0]);
            zn.rows[6].normal[1] = (cloth_real)(2 * (double)zn.rows[0].normal[1]);
            zn.rows[6].normal[2] = (cloth_real)(2 * (double)zn.rows[0].normal[2]);
        }
        pr = zone_problem(&zn);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL);
        if (zn.m <= 8 && zn.n <= 4 && !brute_force(&pr, &bobj, bz)) {
            ENSURE(r == CLOTH_ERROR_COLLISION_UNRESOLVED);
            continue;
        }
        ENSURE(r == CLOTH_SUCCESS);
        kk = kkt_check(&pr, z, lam);
        if (!kkt_ok(&kk)) print_kkt("pair", &kk);
        ENSURE(kkt_ok(&kk));
        ENSURE_NEAR(kk.objective, bobj, OBJTOL(bobj));
        for (j = 0; j < zn.m; ++j) active += act[j] == CLOTH_QP_ACTIVE;
        ENSURE(active <= 3);
    }
}

/* Three rows on one vertex pair with parallel normals (n, n and 2n, the last with twice the
   thickness): only the most demanding acts, and the pair separates by exactly its thickness,
   split by inverse weight. */
TEST(parallel_rows_on_a_vertex_pair)
{
    zone zn;
    cloth_qp_problem pr;
    cloth_real z[6], lam[3];
    int32_t act[3];
    int v[4] = { 1, 0, -1, -1 }, k, c;
    double a[4] = { 1, -1, 0, 0 }, nv[3] = { 0.6, 0, 0.8 }, n2[3] = { 1.2, 0, 1.6 }, gap, dl;
    kkt kk;
    zn.n = 2; zn.m = 3;
    zn.x[0] = (cloth_real)0.25; zn.x[1] = (cloth_real)0.5; zn.x[2] = (cloth_real)-0.125;
    zn.x[3] = (cloth_real)0.375; zn.x[4] = (cloth_real)0.5; zn.x[5] = (cloth_real)0.0625;
    zn.iw[0] = (cloth_real)0.5; zn.iw[1] = (cloth_real)1.5;
    set_row(&zn.rows[0], v, a, nv, 0.25);
    set_row(&zn.rows[1], v, a, n2, 0.875); /* 2 x (n . d >= 0.4375): the binding one */
    set_row(&zn.rows[2], v, a, nv, 0.375);
    pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
    kk = kkt_check(&pr, z, lam);
    ENSURE(kkt_ok(&kk));
    ENSURE(act[1] == CLOTH_QP_ACTIVE && act[0] == CLOTH_QP_INACTIVE && act[2] == CLOTH_QP_INACTIVE);
    ENSURE(lam[0] == 0 && lam[2] == 0);
    /* n . (x1 - x0) = 0.6 * 0.125 + 0.8 * 0.1875 = 0.225; the gap to 0.4375 closes with
       vertex 1 moving by 1.5 / 2 of it along n and vertex 0 by 0.5 / 2 against it */
    gap = 0.4375 - (0.6 * ((double)zn.x[3] - (double)zn.x[0]) + 0.8 * ((double)zn.x[5] - (double)zn.x[2]));
    dl = gap / 2.0;
    for (c = 0; c < 3; ++c) {
        ENSURE_NEAR(z[3 + c], (double)zn.x[3 + c] + 1.5 * dl * nv[c], IS_FLOAT ? 1e-7 : 1e-15);
        ENSURE_NEAR(z[c], (double)zn.x[c] - 0.5 * dl * nv[c], IS_FLOAT ? 1e-7 : 1e-15);
    }
    ENSURE_NEAR(lam[1], dl / 2, IS_FLOAT ? 1e-7 : 1e-15); /* lambda (2n) = dl n */
    /* the same rows in another order: the same z */
    {
        cloth_qp_row t = zn.rows[0];
        cloth_real z2[6];
        zn.rows[0] = zn.rows[1]; zn.rows[1] = zn.rows[2]; zn.rows[2] = t;
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z2, lam, act, NULL) == CLOTH_SUCCESS);
        for (k = 0; k < 6; ++k) ENSURE_NEAR(z2[k], z[k], IS_FLOAT ? 1e-7 : 1e-15);
    }
}

/* Random zones with few vertices and many rows, rows repeated: heavily dependent rows. */
TEST(dependent_rows_random)
{
    cloth_rng g = cloth_rng_make(31);
    int trial, solved = 0;
    for (trial = 0; trial < 2000; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[12], lam[8];
        int32_t act[8];
        double bobj = 0, bz[12];
        int n = 1 + irand(&g, 3), m = 3 + irand(&g, 6), j, found;
        cloth_result r;
        random_zone(&g, &zn, n, m, 0.15, -0.2, 0.3);
        for (j = 1; j < m; ++j)
            if (irand(&g, 3) == 0) {
                zn.rows[j] = zn.rows[irand(&g, j)];
                if (irand(&g, 2)) zn.rows[j].thickness = (cloth_real)((double)zn.rows[j].thickness - 0.1 * urand(&g));
            }
        pr = zone_problem(&zn);
        found = brute_force(&pr, &bobj, bz);
        r = cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL);
        if (!found) {
            if (r != CLOTH_ERROR_COLLISION_UNRESOLVED) printf("    trial %d: brute force infeasible, solver %d\n", trial, (int)r);
            ENSURE(r == CLOTH_ERROR_COLLISION_UNRESOLVED);
            continue;
        }
        if (r != CLOTH_SUCCESS) printf("    trial %d: solver %d\n", trial, (int)r);
        ENSURE(r == CLOTH_SUCCESS);
        {
            kkt k = kkt_check(&pr, z, lam);
            if (!kkt_ok(&k)) print_kkt("dependent", &k);
            ENSURE(kkt_ok(&k));
            ENSURE_NEAR(k.objective, bobj, OBJTOL(bobj));
        }
        ++solved;
    }
    ENSURE(solved > 1000);
}

/* Rows over immovable vertices only are constants: met, they do nothing (tight when met
   exactly); violated, the zone is infeasible. */
TEST(rows_over_immovable_vertices)
{
    zone zn;
    cloth_qp_problem pr;
    cloth_real z[12], lam[3];
    int32_t act[3];
    int v0[4] = { 0, 1, -1, -1 }, v1[4] = { 2, 3, -1, -1 }, v2[4] = { 0, 2, -1, -1 }, k;
    double a[4] = { 1, -1, 0, 0 }, nv[3] = { 0, 1, 0 };
    kkt kk;
    zn.n = 4; zn.m = 3;
    for (k = 0; k < 12; ++k) zn.x[k] = (cloth_real)(0.125 * k);
    zn.iw[0] = 0; zn.iw[1] = 0; zn.iw[2] = 1; zn.iw[3] = 2;
    set_row(&zn.rows[0], v0, a, nv, 0);
    zn.rows[0].thickness = (cloth_real)row_value(&zn.rows[0], zn.x); /* met exactly */
    set_row(&zn.rows[1], v1, a, nv, 0);
    zn.rows[1].thickness = (cloth_real)(row_value(&zn.rows[1], zn.x) + 0.2);
    set_row(&zn.rows[2], v2, a, nv, 0);
    zn.rows[2].thickness = (cloth_real)(row_value(&zn.rows[2], zn.x) - 0.5);
    pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
    kk = kkt_check(&pr, z, lam);
    ENSURE(kkt_ok(&kk));
    ENSURE(act[0] == CLOTH_QP_TIGHT && lam[0] == 0);
    ENSURE(act[1] == CLOTH_QP_ACTIVE && lam[1] > 0);
    for (k = 0; k < 6; ++k) ENSURE(z[k] == zn.x[k]);
    /* now violate the constant row */
    zn.rows[0].thickness = (cloth_real)((double)zn.rows[0].thickness + 1e-3);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
    ENSURE(memcmp(z, zn.x, sizeof z) == 0);
    for (k = 0; k < 3; ++k) ENSURE(lam[k] == 0 && act[k] == CLOTH_QP_INACTIVE);
    /* a row with no used slot reads 0 >= t */
    zn.m = 1;
    zn.rows[0].vertex[0] = zn.rows[0].vertex[1] = -1;
    zn.rows[0].thickness = (cloth_real)-1;
    pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS && act[0] == CLOTH_QP_INACTIVE);
    zn.rows[0].thickness = (cloth_real)1;
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
}

/* ===================================================================================== */
/* infeasible zones, bad input                                                           */
/* ===================================================================================== */

TEST(infeasible_zones)
{
    zone zn;
    cloth_qp_problem pr;
    cloth_real z[9], lam[3], xcopy[9];
    int32_t act[3];
    cloth_qp_stats st;
    int k;
    double nv[3] = { 0, 0, 1 }, mn[3] = { 0, 0, -1 };
    /* one vertex asked to be above 1 and below 0 */
    {
        int v[4] = { 0, -1, -1, -1 };
        double a[4] = { 1, 0, 0, 0 };
        zn.n = 1; zn.m = 2;
        zn.x[0] = zn.x[1] = zn.x[2] = (cloth_real)0.5;
        zn.iw[0] = 1;
        set_row(&zn.rows[0], v, a, nv, 1.0);
        set_row(&zn.rows[1], v, a, mn, 0.0);
        pr = zone_problem(&zn);
        for (k = 0; k < 2; ++k) lam[k] = 5, act[k] = 5;
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, &st) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(z, zn.x, 3 * sizeof(cloth_real)) == 0);
        ENSURE(lam[0] == 0 && lam[1] == 0 && act[0] == CLOTH_QP_INACTIVE && act[1] == CLOTH_QP_INACTIVE);
        ENSURE(st.iterations >= 1);
        /* in place: x is left as it was */
        memcpy(xcopy, zn.x, sizeof(cloth_real) * 3);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, zn.x, NULL, NULL, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(xcopy, zn.x, sizeof(cloth_real) * 3) == 0);
    }
    /* a cycle: z1 - z0 >= 1, z2 - z1 >= 1, z0 - z2 >= 1 along z (pairwise independent rows) */
    {
        int v01[4] = { 1, 0, -1, -1 }, v12[4] = { 2, 1, -1, -1 }, v20[4] = { 0, 2, -1, -1 };
        double a[4] = { 1, -1, 0, 0 };
        zn.n = 3; zn.m = 3;
        for (k = 0; k < 9; ++k) zn.x[k] = (cloth_real)(0.1 * k);
        for (k = 0; k < 3; ++k) zn.iw[k] = (cloth_real)(1 + k);
        set_row(&zn.rows[0], v01, a, nv, 1);
        set_row(&zn.rows[1], v12, a, nv, 1);
        set_row(&zn.rows[2], v20, a, nv, 1);
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(z, zn.x, sizeof z) == 0);
        /* with a zero total thickness the cycle is feasible (all three tight) */
        zn.rows[2].thickness = (cloth_real)-2;
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
        {
            kkt kk = kkt_check(&pr, z, lam);
            ENSURE(kkt_ok(&kk));
        }
    }
    /* a vertex between two immovable vertices that are too close */
    {
        int va[4] = { 1, 0, -1, -1 }, vb[4] = { 2, 1, -1, -1 };
        double a[4] = { 1, -1, 0, 0 };
        zn.n = 3; zn.m = 2;
        /* binary fractions, so that float and double see the same zone */
        for (k = 0; k < 9; ++k) zn.x[k] = 0;
        zn.x[5] = (cloth_real)0.0625; zn.x[8] = (cloth_real)0.25;
        zn.iw[0] = 0; zn.iw[1] = 1; zn.iw[2] = 0;
        set_row(&zn.rows[0], va, a, nv, 0.125);
        set_row(&zn.rows[1], vb, a, nv, 0.1875);
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(z, zn.x, sizeof z) == 0);
        zn.rows[1].thickness = (cloth_real)0.125; /* now just room for it: exactly at 0.125 */
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
        ENSURE(z[5] == (cloth_real)0.125);
        ENSURE(act[0] == CLOTH_QP_ACTIVE && act[1] == CLOTH_QP_TIGHT && lam[1] == 0);
    }
}

TEST(not_finite_and_invalid_input)
{
    zone zn, good;
    cloth_qp_problem pr;
    cloth_real z[12], lam[2];
    int32_t act[2];
    cloth_qp_options o;
    int v[4] = { 0, 1, 2, 3 }, k, which;
    double a[4] = { 1, -0.25, -0.25, -0.5 }, nv[3] = { 0, 1, 0 };
    volatile double zero = 0;
    cloth_real nan_ = (cloth_real)(zero / zero), inf_ = (cloth_real)(1 / zero);
    good.n = 4; good.m = 2;
    for (k = 0; k < 12; ++k) good.x[k] = (cloth_real)(0.1 * k);
    for (k = 0; k < 4; ++k) good.iw[k] = 1;
    set_row(&good.rows[0], v, a, nv, 0.5);
    set_row(&good.rows[1], v, a, nv, 0.2);
    for (which = 0; which < 9; ++which) {
        zn = good;
        switch (which) {
        case 0: zn.x[4] = nan_; break;
        case 1: zn.x[7] = inf_; break;
        case 2: zn.iw[2] = nan_; break;
        case 3: zn.rows[1].weight[3] = nan_; break;
        case 4: zn.rows[0].normal[2] = nan_; break;
        case 5: zn.rows[1].thickness = -inf_; break;
        case 6: zn.iw[1] = inf_; break;
        case 7: zn.rows[0].normal[0] = inf_; zn.rows[1].vertex[0] = 9; break; /* non-finite is reported first */
        default: zn.rows[0].weight[1] = nan_; zn.iw[0] = -1; break;
        }
        pr = zone_problem(&zn);
        lam[0] = lam[1] = 3;
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_NOT_FINITE);
        ENSURE(memcmp(z, zn.x, sizeof z) == 0); /* z = x, NaN included, bit for bit */
        ENSURE(lam[0] == 0 && lam[1] == 0);
    }
    /* a NaN weight in an unused slot is ignored */
    zn = good;
    zn.rows[0].vertex[3] = -1;
    zn.rows[0].weight[3] = nan_;
    pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
    /* indices */
    zn = good; zn.rows[1].vertex[2] = 4; pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    ENSURE(memcmp(z, zn.x, sizeof z) == 0);
    zn = good; zn.rows[0].vertex[0] = -2; pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    /* negative inverse weight, negative counts */
    zn = good; zn.iw[3] = (cloth_real)-0.5; pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    zn = good; pr = zone_problem(&zn); pr.row_count = -1;
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    /* options */
    pr = zone_problem(&good);
    o = cloth_qp_default_options(); o.feasibility_tolerance = 0;
    ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    o = cloth_qp_default_options(); o.dependency_tolerance = 1;
    ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    o = cloth_qp_default_options(); o.kkt_tolerance = nan_;
    ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    o = cloth_qp_default_options(); o.max_iterations = -1;
    ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    /* the iteration cap: two rows need two additions */
    o = cloth_qp_default_options(); o.max_iterations = 1;
    {
        double n2[3] = { 1, 0, 0 };
        int w[4] = { 0, -1, -1, -1 }, w2[4] = { 1, -1, -1, -1 };
        double a1[4] = { 1, 0, 0, 0 };
        zn = good;
        set_row(&zn.rows[0], w, a1, nv, 5);
        set_row(&zn.rows[1], w2, a1, n2, 5);
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(z, zn.x, sizeof z) == 0);
        o.max_iterations = 2;
        ENSURE(cloth_qp_project(NULL, &pr, &o, z, lam, act, NULL) == CLOTH_SUCCESS);
    }
    /* an empty zone and a zone without rows */
    zn = good; zn.m = 0; pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, NULL, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(memcmp(z, zn.x, sizeof z) == 0);
    zn.n = 0; pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, NULL, NULL, NULL) == CLOTH_SUCCESS);
    /* NULL inverse weights: all 1 */
    pr = zone_problem(&good);
    pr.inverse_weight = NULL;
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
    ENSURE_NEAR((double)z[1] - (double)good.x[1], (0.5 - row_value(&good.rows[0], good.x)) / (1 + 0.0625 * 2 + 0.25), 1e-6);
}

/* ===================================================================================== */
/* determinism, memory                                                                    */
/* ===================================================================================== */

typedef struct counting { long allocs, frees, fail_after; } counting;
static void *count_alloc(size_t size, void *user)
{
    counting *c = (counting *)user;
    if (c->fail_after >= 0 && c->allocs >= c->fail_after) return NULL;
    ++c->allocs;
    return malloc(size);
}
static void count_free(void *p, void *user)
{
    counting *c = (counting *)user;
    if (p) { ++c->frees; free(p); }
}

TEST(determinism_and_workspace_reuse)
{
    cloth_rng g = cloth_rng_make(404);
    cloth_qp_workspace ws;
    counting cnt;
    cloth_allocator al;
    int trial;
    cnt.allocs = cnt.frees = 0;
    cnt.fail_after = -1;
    al.alloc = count_alloc; al.free = count_free; al.user = &cnt;
    ENSURE(cloth_qp_workspace_create(&ws, 40, 60, &al) == CLOTH_SUCCESS);
    ENSURE(cnt.allocs == 1);
    for (trial = 0; trial < 100; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z1[3 * MAXN], z2[3 * MAXN], l1[MAXM], l2[MAXM];
        int32_t a1[MAXM], a2[MAXM];
        cloth_qp_stats s1, s2;
        cloth_result r1, r2;
        random_zone(&g, &zn, 2 + irand(&g, 38), 1 + irand(&g, 59), 0.1, -0.3, 0.3);
        pr = zone_problem(&zn);
        r1 = cloth_qp_project(&ws, &pr, NULL, z1, l1, a1, &s1);
        r2 = cloth_qp_project(NULL, &pr, NULL, z2, l2, a2, &s2);
        ENSURE(r1 == r2);
        ENSURE(memcmp(z1, z2, 3 * (size_t)zn.n * sizeof(cloth_real)) == 0);
        ENSURE(memcmp(l1, l2, (size_t)zn.m * sizeof(cloth_real)) == 0);
        ENSURE(memcmp(a1, a2, (size_t)zn.m * sizeof(int32_t)) == 0);
        ENSURE(memcmp(&s1, &s2, sizeof s1) == 0);
    }
    ENSURE(cnt.allocs == 1); /* the workspace was large enough all along */
    {
        /* a larger zone makes it grow once */
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN];
        random_zone(&g, &zn, MAXN, MAXM, 0.1, -0.3, 0.3);
        pr = zone_problem(&zn);
        (void)cloth_qp_project(&ws, &pr, NULL, z, NULL, NULL, NULL);
        ENSURE(cnt.allocs == 2 && cnt.frees == 1);
        (void)cloth_qp_project(&ws, &pr, NULL, z, NULL, NULL, NULL);
        ENSURE(cnt.allocs == 2);
    }
    cloth_qp_workspace_free(&ws);
    ENSURE(cnt.allocs == cnt.frees);
    cloth_qp_workspace_free(&ws); /* empty: fine */
    /* out of memory: z = x */
    {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN];
        cnt.allocs = cnt.frees = 0;
        cnt.fail_after = 0;
        ENSURE(cloth_qp_workspace_create(&ws, 4, 4, &al) == CLOTH_ERROR_OUT_OF_MEMORY);
        random_zone(&g, &zn, 5, 5, 0, 0.1, 0.2);
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_project(&ws, &pr, NULL, z, NULL, NULL, NULL) == CLOTH_ERROR_OUT_OF_MEMORY);
        ENSURE(memcmp(z, zn.x, 3 * 5 * sizeof(cloth_real)) == 0);
        cnt.fail_after = -1;
        ENSURE(cloth_qp_project(&ws, &pr, NULL, z, NULL, NULL, NULL) == CLOTH_SUCCESS);
        cloth_qp_workspace_free(&ws);
        ENSURE(cnt.allocs == 1 && cnt.frees == 1);
    }
    ENSURE(cloth_qp_workspace_create(&ws, -1, 0, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
}

/* ===================================================================================== */
/* backward                                                                               */
/* ===================================================================================== */

/* L = gz . z + gl . lambda of a projection, or NaN when it fails or the row states differ
   from ref_act. */
static double loss_of(const zone *zn, const double *gz, const double *gl, const int32_t *ref_act)
{
    cloth_qp_problem pr = zone_problem(zn);
    cloth_real z[3 * MAXN], lam[MAXM];
    int32_t act[MAXM];
    double L = 0;
    int i;
    if (cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) != CLOTH_SUCCESS) return sqrt(-1.0 + 0 * L);
    for (i = 0; i < zn->m; ++i)
        if (act[i] != ref_act[i]) return sqrt(-1.0 + 0 * L);
    for (i = 0; i < 3 * zn->n; ++i) L += gz[i] * (double)z[i];
    for (i = 0; i < zn->m; ++i) L += gl[i] * (double)lam[i];
    return L;
}

/* A random zone with a clear active set: active multipliers and inactive slacks well away
   from 0, no tight rows. */
static int clear_zone(cloth_rng *g, zone *zn, int n, int m, double p_fixed, cloth_real *z, cloth_real *lam, int32_t *act)
{
    int tries;
    for (tries = 0; tries < 100; ++tries) {
        cloth_qp_problem pr;
        double lmax = 0;
        int j, ok = 1, nact = 0;
        random_zone(g, zn, n, m, p_fixed, -0.2, 0.2);
        pr = zone_problem(zn);
        if (cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) != CLOTH_SUCCESS) continue;
        for (j = 0; j < m; ++j)
            if ((double)lam[j] > lmax) lmax = (double)lam[j];
        for (j = 0; j < m; ++j) {
            double sc, gv = row_violation(&zn->rows[j], z, &sc);
            if (act[j] == CLOTH_QP_TIGHT) ok = 0;
            if (act[j] == CLOTH_QP_ACTIVE) { ++nact; if (!((double)lam[j] > 0.02 * lmax)) ok = 0; }
            if (act[j] == CLOTH_QP_INACTIVE && !(gv < -0.01 * sc)) ok = 0;
        }
        if (ok && nact > 0) return 1;
    }
    return 0;
}

TEST(backward_finite_differences)
{
    cloth_rng g = cloth_rng_make(555);
    int trial, checked = 0;
    double h = IS_FLOAT ? 2e-3 : 1e-6, rtol = IS_FLOAT ? 2e-2 : 2e-6;
    double worst = 0;
    for (trial = 0; trial < 40; ++trial) {
        zone zn, zp;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM], gzr[3 * MAXN], glr[MAXM];
        cloth_real gx[3 * MAXN], giw[MAXN], gn[3 * MAXM], gw[4 * MAXM], gt[MAXM];
        int32_t act[MAXM];
        double gz[3 * MAXN], gl[MAXM];
        cloth_qp_gradient grad;
        int n = 4 + irand(&g, 5), m = 3 + irand(&g, 6), i, j, k;
        if (!clear_zone(&g, &zn, n, m, trial % 2 ? 0.2 : 0.0, z, lam, act)) continue;
        for (i = 0; i < 3 * n; ++i) { gz[i] = urand(&g) - 0.5; gzr[i] = (cloth_real)gz[i]; gz[i] = (double)gzr[i]; }
        for (j = 0; j < m; ++j) { gl[j] = trial % 3 == 0 ? 0 : urand(&g) - 0.5; glr[j] = (cloth_real)gl[j]; gl[j] = (double)glr[j]; }
        grad.x = gx; grad.inverse_weight = giw; grad.normal = gn; grad.weight = gw; grad.thickness = gt;
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gzr, glr, &grad) == CLOTH_SUCCESS);
#define FD_CHECK(field, analytic, one_sided)                                                          \
        do {                                                                                          \
            double save = (double)(field), lp, lm, fd, an = (double)(analytic), err;                  \
            int os = (one_sided);                                                                     \
            double hh = os && !IS_FLOAT ? 1e-8 : h;                                                   \
            zp = zn; field = (cloth_real)(save + hh); lp = loss_of(&zn, gz, gl, act);                 \
            if (os) { field = (cloth_real)save; lm = loss_of(&zn, gz, gl, act); fd = (lp - lm) / ((double)(cloth_real)(save + hh) - save); } \
            else { field = (cloth_real)(save - hh); lm = loss_of(&zn, gz, gl, act);                   \
                   fd = (lp - lm) / ((double)(cloth_real)(save + hh) - (double)(cloth_real)(save - hh)); } \
            zn = zp;                                                                                  \
            if (!(lp == lp && lm == lm)) printf("    trial %d: %s: active set changed\n", trial, #field);  \
            ENSURE(lp == lp && lm == lm); /* the active set held */                                   \
            err = fabs(an - fd) / (1 + fabs(an));                                                     \
            if (err > worst) worst = err;                                                             \
            if (!(err <= rtol)) printf("    trial %d: %s analytic %.10g, finite difference %.10g\n", trial, #field, an, fd); \
            ENSURE(err <= rtol);                                                                      \
        } while (0)
        for (i = 0; i < 3 * n; ++i) FD_CHECK(zn.x[i], gx[i], 0);
        for (i = 0; i < n; ++i) FD_CHECK(zn.iw[i], giw[i], zn.iw[i] == 0);
        for (j = 0; j < m; ++j) {
            for (k = 0; k < 3; ++k) FD_CHECK(zn.rows[j].normal[k], gn[3 * j + k], 0);
            for (k = 0; k < 4; ++k)
                if (zn.rows[j].vertex[k] >= 0) FD_CHECK(zn.rows[j].weight[k], gw[4 * j + k], 0);
                else ENSURE(gw[4 * j + k] == 0);
            FD_CHECK(zn.rows[j].thickness, gt[j], 0);
        }
#undef FD_CHECK
        ++checked;
    }
    printf("    %d zones checked, worst relative difference %.2g\n", checked, worst);
    ENSURE(checked >= 30);
}

/* The formula of docs/algorithms.md section 3 done densely here (modified Gram-Schmidt QR of
   sqrt(W)^-1 G_A^T, then d_z, d_lambda, dL/dx = W d_z, dL/dh = -D(lambda) d_lambda,
   dL/dG = -D(lambda) d_lambda z^T - lambda d_z^T) agrees with cloth_qp_backward. */
TEST(backward_matches_dense_formula)
{
    cloth_rng g = cloth_rng_make(9);
    int trial, checked = 0;
    for (trial = 0; trial < 60; ++trial) {
        zone zn;
        cloth_qp_problem pr;
        cloth_real z[3 * MAXN], lam[MAXM], gzr[3 * MAXN];
        cloth_real gx[3 * MAXN], gn[3 * MAXM], gt[MAXM];
        int32_t act[MAXM];
        cloth_qp_gradient grad;
        double B[3 * 10][10], Q[3 * 10][10], R[10][10], s[30], qs[10], dlam[10], dz[30], tmp[10];
        int A[10], q = 0, n = 3 + irand(&g, 6), m = 2 + irand(&g, 6), N, i, j, k, c;
        if (!clear_zone(&g, &zn, n, m, 0.0, z, lam, act)) continue;
        N = 3 * n;
        for (i = 0; i < N; ++i) gzr[i] = (cloth_real)(urand(&g) - 0.5);
        grad.x = gx; grad.inverse_weight = NULL; grad.normal = gn; grad.weight = NULL; grad.thickness = gt;
        pr = zone_problem(&zn);
        ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gzr, NULL, &grad) == CLOTH_SUCCESS);
        for (j = 0; j < m; ++j)
            if (act[j] == CLOTH_QP_ACTIVE) A[q++] = j;
        /* B = sqrt(M) G_A^T, G_j = -[a_jk n_j^T] */
        for (k = 0; k < q; ++k) {
            const cloth_qp_row *r = &zn.rows[A[k]];
            for (i = 0; i < N; ++i) B[i][k] = 0;
            for (i = 0; i < 4; ++i)
                if (r->vertex[i] >= 0)
                    for (c = 0; c < 3; ++c)
                        B[3 * r->vertex[i] + c][k] -= sqrt((double)zn.iw[r->vertex[i]]) * (double)r->weight[i] * (double)r->normal[c];
        }
        for (k = 0; k < q; ++k) {
            double nrm = 0;
            for (i = 0; i < N; ++i) Q[i][k] = B[i][k];
            for (j = 0; j < k; ++j) {
                double d = 0;
                for (i = 0; i < N; ++i) d += Q[i][j] * Q[i][k];
                R[j][k] = d;
                for (i = 0; i < N; ++i) Q[i][k] -= d * Q[i][j];
            }
            for (i = 0; i < N; ++i) nrm += Q[i][k] * Q[i][k];
            R[k][k] = sqrt(nrm);
            ENSURE(R[k][k] > 1e-6);
            for (i = 0; i < N; ++i) Q[i][k] /= R[k][k];
        }
        for (i = 0; i < N; ++i) s[i] = sqrt((double)zn.iw[i / 3]) * (double)gzr[i];
        for (k = 0; k < q; ++k) { qs[k] = 0; for (i = 0; i < N; ++i) qs[k] += Q[i][k] * s[i]; }
        for (i = 0; i < N; ++i) {
            double p = s[i];
            for (k = 0; k < q; ++k) p -= Q[i][k] * qs[k];
            dz[i] = sqrt((double)zn.iw[i / 3]) * p;
        }
        for (k = q - 1; k >= 0; --k) { /* R^-1 Q^T s */
            double t = qs[k];
            for (j = k + 1; j < q; ++j) t -= R[k][j] * tmp[j];
            tmp[k] = t / R[k][k];
        }
        for (k = 0; k < q; ++k) dlam[k] = tmp[k] / (double)lam[A[k]];
        for (i = 0; i < N; ++i) ENSURE_NEAR(gx[i], dz[i] / (double)zn.iw[i / 3], CTOL * (1 + fabs(gx[i])) * 10);
        for (k = 0; k < q; ++k) {
            const cloth_qp_row *r = &zn.rows[A[k]];
            double gnk[3] = { 0, 0, 0 };
            ENSURE_NEAR(gt[A[k]], -(double)lam[A[k]] * dlam[k], CTOL * (1 + fabs(gt[A[k]])) * 10);
            for (i = 0; i < 4; ++i)
                if (r->vertex[i] >= 0)
                    for (c = 0; c < 3; ++c) {
                        int col = 3 * r->vertex[i] + c;
                        double dG = -(double)lam[A[k]] * dlam[k] * (double)z[col] - (double)lam[A[k]] * dz[col];
                        gnk[c] -= (double)r->weight[i] * dG;
                    }
            for (c = 0; c < 3; ++c) ENSURE_NEAR(gn[3 * A[k] + c], gnk[c], CTOL * (1 + fabs(gnk[c])) * 10);
        }
        for (j = 0; j < m; ++j)
            if (act[j] != CLOTH_QP_ACTIVE) ENSURE(gt[j] == 0 && gn[3 * j] == 0 && gn[3 * j + 1] == 0 && gn[3 * j + 2] == 0);
        ++checked;
    }
    printf("    %d zones checked\n", checked);
    ENSURE(checked >= 40);
}

/* The backward pass on degenerate results (dependent rows flagged tight) and on bad input. */
TEST(backward_degenerate_and_bad_input)
{
    zone zn;
    cloth_qp_problem pr;
    cloth_real z[12], lam[3], gz[12], gx[12], gt[3];
    int32_t act[3];
    cloth_qp_gradient grad;
    int v[4] = { 0, 1, 2, 3 }, k;
    double a[4] = { 1, -0.2, -0.3, -0.5 }, nv[3] = { 0, 1, 0 };
    volatile double zero = 0;
    zn.n = 4; zn.m = 3;
    for (k = 0; k < 12; ++k) { zn.x[k] = (cloth_real)(0.05 * k); gz[k] = (cloth_real)(k == 1 ? 1 : 0); }
    for (k = 0; k < 4; ++k) zn.iw[k] = 1;
    set_row(&zn.rows[0], v, a, nv, 0.3);
    zn.rows[1] = zn.rows[0];
    zn.rows[2] = zn.rows[0];
    pr = zone_problem(&zn);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, NULL) == CLOTH_SUCCESS);
    ENSURE(act[0] == CLOTH_QP_ACTIVE && act[1] == CLOTH_QP_TIGHT && act[2] == CLOTH_QP_TIGHT);
    memset(&grad, 0, sizeof grad);
    grad.x = gx; grad.thickness = gt;
    ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gz, NULL, &grad) == CLOTH_SUCCESS);
    /* L = the y coordinate of vertex 0; raising t by dt moves vertex k by m_k a_k dlambda n
       with dlambda = dt / sum a_k^2 m_k, so dL/dt = a_0 m_0 / sum a_k^2 m_k */
    ENSURE_NEAR(gt[0], 1.0 / (1 + 0.04 + 0.09 + 0.25), IS_FLOAT ? 1e-6 : 1e-14);
    ENSURE(gt[1] == 0 && gt[2] == 0);
    /* the same with all three marked active: the dependent ones are dropped */
    act[1] = act[2] = CLOTH_QP_ACTIVE;
    ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gz, NULL, &grad) == CLOTH_SUCCESS);
    ENSURE(gt[1] == 0 && gt[2] == 0);
    /* bad input */
    act[1] = 7;
    gx[0] = 5;
    ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gz, NULL, &grad) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(gx[0] == 0);
    act[1] = CLOTH_QP_TIGHT;
    gz[2] = (cloth_real)(zero / zero);
    ENSURE(cloth_qp_backward(NULL, &pr, NULL, z, lam, act, gz, NULL, &grad) == CLOTH_ERROR_NOT_FINITE);
}

/* ===================================================================================== */
/* continuing a projection                                                               */
/* ===================================================================================== */

/* A growing zone on an nx x nx grid (vertex i nx + j): m rows over random cells, ordered by
   the cell's grid row, so that the first rows only reach the first vertices; immovable
   vertices on the first column. */
typedef struct growing_zone {
    int nx, n, m;
    cloth_real *x, *iw;
    cloth_qp_row *rows;
    int *reach; /* reach[k]: the vertices rows 0..k need */
} growing_zone;

static void growing_zone_make(growing_zone *gz, cloth_rng *g, int nx, int m, int signed_normals)
{
    int i, j, *cell_i = (int *)malloc(sizeof(int) * (size_t)m), *cell_j = (int *)malloc(sizeof(int) * (size_t)m);
    ENSURE(cell_i && cell_j);
    gz->nx = nx;
    gz->n = nx * nx;
    gz->m = m;
    gz->x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)gz->n);
    gz->iw = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)gz->n);
    gz->rows = (cloth_qp_row *)malloc(sizeof(cloth_qp_row) * (size_t)m);
    gz->reach = (int *)malloc(sizeof(int) * (size_t)m);
    ENSURE(gz->x && gz->iw && gz->rows && gz->reach);
    for (i = 0; i < nx; ++i)
        for (j = 0; j < nx; ++j) {
            int v = i * nx + j;
            gz->x[3 * v] = (cloth_real)(0.05 * i + 0.01 * urand(g));
            gz->x[3 * v + 1] = (cloth_real)(0.01 * urand(g));
            gz->x[3 * v + 2] = (cloth_real)(0.05 * j + 0.01 * urand(g));
            gz->iw[v] = (cloth_real)(j == 0 && i % 3 == 0 ? 0.0 : 0.5 + urand(g));
        }
    for (i = 0; i < m; ++i) {
        cell_i[i] = irand(g, nx - 1);
        cell_j[i] = irand(g, nx - 1);
    }
    for (i = 1; i < m; ++i) /* insertion sort by the cell's grid row */
        for (j = i; j > 0 && cell_i[j - 1] > cell_i[j]; --j) {
            int ti = cell_i[j], tj = cell_j[j];
            cell_i[j] = cell_i[j - 1]; cell_j[j] = cell_j[j - 1];
            cell_i[j - 1] = ti; cell_j[j - 1] = tj;
        }
    for (i = 0; i < m; ++i) {
        int v0 = cell_i[i] * nx + cell_j[i], vv[4];
        double a[4], nv[3];
        vv[0] = v0; vv[1] = v0 + 1; vv[2] = v0 + nx; vv[3] = v0 + nx + 1;
        if (irand(g, 2)) { double b0 = urand(g) + 0.1, b1 = urand(g) + 0.1, b2 = urand(g) + 0.1, sb = b0 + b1 + b2;
            a[0] = 1; a[1] = -b0 / sb; a[2] = -b1 / sb; a[3] = -b2 / sb; }
        else { double s0 = urand(g), t0 = urand(g); a[0] = s0; a[1] = 1 - s0; a[2] = -t0; a[3] = -(1 - t0); }
        rand_unit(g, nv);
        if (!signed_normals && nv[1] < 0) { nv[0] = -nv[0]; nv[1] = -nv[1]; nv[2] = -nv[2]; }
        set_row(&gz->rows[i], vv, a, nv, 0);
        gz->rows[i].thickness = (cloth_real)(row_value(&gz->rows[i], gz->x) + 1e-3 * (urand(g) - 0.3));
        gz->reach[i] = (cell_i[i] + 2) * nx;
    }
    free(cell_i);
    free(cell_j);
}

static void growing_zone_free(growing_zone *gz)
{
    free(gz->x); free(gz->iw); free(gz->rows); free(gz->reach);
}

/* The first m rows over the first n vertices. */
static cloth_qp_problem growing_problem(const growing_zone *gz, int n, int m)
{
    cloth_qp_problem pr;
    pr.vertex_count = n;
    pr.x = gz->x;
    pr.inverse_weight = gz->iw;
    pr.rows = gz->rows;
    pr.row_count = m;
    return pr;
}

/* A zone that grows in eight stages (rows and vertices appended; in the third trial every
   vertex also moves a little between stages), projected by cloth_qp_project_more on one
   workspace and by cloth_qp_project from the start: each stage goes on from the last, meets
   the KKT conditions checked here, and gives the z of the projection from the start; the
   continued stages take far fewer working-set changes. */
TEST(project_more_matches_project)
{
    cloth_rng g = cloth_rng_make(2026);
    int trial;
    for (trial = 0; trial < 3; ++trial) {
        growing_zone gz;
        cloth_qp_workspace ws;
        cloth_real *z1, *z2, *l1, *l2;
        int32_t *a1, *a2;
        long it_more = 0, it_scratch = 0;
        int stage, stages = 8;
        double zdiff = 0, zscale = 0;
        growing_zone_make(&gz, &g, 20, trial == 0 ? 900 : 1400, trial == 1);
        z1 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)gz.n);
        z2 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)gz.n);
        l1 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)gz.m);
        l2 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)gz.m);
        a1 = (int32_t *)malloc(sizeof(int32_t) * (size_t)gz.m);
        a2 = (int32_t *)malloc(sizeof(int32_t) * (size_t)gz.m);
        ENSURE(z1 && z2 && l1 && l2 && a1 && a2);
        memset(&ws, 0, sizeof ws);
        for (stage = 0; stage < stages; ++stage) {
            int m = gz.m * (stage + 1) / stages, n = gz.reach[m - 1], i;
            cloth_qp_problem pr = growing_problem(&gz, n, m);
            cloth_qp_stats s1, s2;
            double stat, feas;
            if (trial == 2 && stage > 0)
                for (i = 0; i < 3 * gz.n; ++i) gz.x[i] = (cloth_real)((double)gz.x[i] + 2e-4 * (urand(&g) - 0.5));
            ENSURE(cloth_qp_project_more(&ws, &pr, NULL, z1, l1, a1, &s1) == CLOTH_SUCCESS);
            ENSURE(cloth_qp_project(NULL, &pr, NULL, z2, l2, a2, &s2) == CLOTH_SUCCESS);
            ENSURE(s1.continued == (stage > 0));
            ENSURE(s2.continued == 0);
            large_kkt(&pr, z1, l1, &stat, &feas);
            ENSURE(stat <= KTOL && feas <= KTOL);
            for (i = 0; i < 3 * n; ++i) {
                double d = fabs((double)z1[i] - (double)z2[i]), s = fabs((double)z2[i] - (double)gz.x[i]);
                if (d > zdiff) zdiff = d;
                if (s > zscale) zscale = s;
            }
            it_more += s1.iterations;
            it_scratch += s2.iterations;
            if (stage == stages - 1)
                printf("    %d rows over %d vertices, %d active: working-set changes %ld continued, %ld from the start; "
                       "z differs by %.2g of the largest displacement (%.3g)\n", m, n, (int)s1.active_count, it_more,
                       it_scratch, zdiff / zscale, zscale);
        }
        ENSURE(zdiff <= CTOL * zscale);
        ENSURE(2 * it_more < it_scratch);
        cloth_qp_workspace_free(&ws);
        growing_zone_free(&gz);
        free(z1); free(z2); free(l1); free(l2); free(a1); free(a2);
    }
}

/* cloth_qp_project_more starts afresh, with the result of cloth_qp_project to the bit, when
   the problem does not extend the last one (a changed weight, a changed row, fewer rows), after
   a failed call, after cloth_qp_backward on the workspace, and on an empty workspace; after
   running out of memory it reports the error with z = x and goes on afresh next time. */
TEST(project_more_starts_afresh)
{
    cloth_rng g = cloth_rng_make(77);
    growing_zone gz;
    cloth_qp_workspace ws;
    cloth_real z1[3 * 400], z2[3 * 400], l1[600], l2[600], saved;
    int32_t a1[600], a2[600];
    cloth_qp_stats s1, s2;
    cloth_qp_problem pr;
    int kind;
    growing_zone_make(&gz, &g, 20, 600, 0);
    memset(&ws, 0, sizeof ws);
    for (kind = 0; kind < 6; ++kind) {
        cloth_qp_problem first = growing_problem(&gz, gz.reach[299], 300);
        cloth_result expect = CLOTH_SUCCESS;
        ENSURE(cloth_qp_project_more(&ws, &first, NULL, z1, l1, a1, &s1) == CLOTH_SUCCESS);
        pr = growing_problem(&gz, gz.n, 600);
        saved = 0;
        if (kind == 0) { saved = gz.iw[5]; gz.iw[5] = (cloth_real)(saved * 1.5); }
        if (kind == 1) { saved = gz.rows[17].normal[2]; gz.rows[17].normal[2] = (cloth_real)(saved * 0.5); }
        if (kind == 2) pr = growing_problem(&gz, gz.reach[199], 200);
        if (kind == 3) {
            /* a failed call in between: a row over immovable vertices only, violated */
            cloth_qp_row bad[1];
            cloth_qp_problem infeasible;
            int v[4] = { 0, -1, -1, -1 };
            double a[4] = { 1, 0, 0, 0 }, nv[3] = { 0, 1, 0 };
            set_row(&bad[0], v, a, nv, 1.0);
            infeasible.vertex_count = 1; infeasible.x = gz.x; infeasible.inverse_weight = gz.iw;
            infeasible.rows = bad; infeasible.row_count = 1;
            ENSURE(gz.iw[0] == 0);
            ENSURE(cloth_qp_project_more(&ws, &infeasible, NULL, z2, NULL, NULL, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        }
        if (kind == 4) {
            cloth_real gzv[3 * 400], gx[3 * 400];
            cloth_qp_gradient grad;
            int i;
            memset(&grad, 0, sizeof grad);
            grad.x = gx;
            for (i = 0; i < 3 * first.vertex_count; ++i) gzv[i] = (cloth_real)(i % 7 == 0);
            ENSURE(cloth_qp_backward(&ws, &first, NULL, z1, l1, a1, gzv, NULL, &grad) == CLOTH_SUCCESS);
        }
        if (kind == 5) cloth_qp_workspace_free(&ws);
        ENSURE(cloth_qp_project_more(&ws, &pr, NULL, z1, l1, a1, &s1) == expect);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z2, l2, a2, &s2) == expect);
        ENSURE(s1.continued == 0);
        ENSURE(memcmp(z1, z2, 3 * (size_t)pr.vertex_count * sizeof(cloth_real)) == 0);
        ENSURE(memcmp(l1, l2, (size_t)pr.row_count * sizeof(cloth_real)) == 0);
        ENSURE(memcmp(a1, a2, (size_t)pr.row_count * sizeof(int32_t)) == 0);
        ENSURE(s1.iterations == s2.iterations);
        /* the same problem once more goes on from its own solution, with nothing to add */
        ENSURE(cloth_qp_project_more(&ws, &pr, NULL, z2, NULL, NULL, &s2) == CLOTH_SUCCESS);
        ENSURE(s2.continued == 1 && s2.iterations == 0);
        ENSURE(memcmp(z1, z2, 3 * (size_t)pr.vertex_count * sizeof(cloth_real)) == 0);
        if (kind == 0) gz.iw[5] = saved;
        if (kind == 1) gz.rows[17].normal[2] = saved;
    }
    cloth_qp_workspace_free(&ws);
    {
        /* out of memory while the workspace grows for the larger problem */
        counting cnt;
        cloth_allocator al;
        cloth_qp_problem first = growing_problem(&gz, gz.reach[99], 100);
        cnt.allocs = cnt.frees = 0;
        cnt.fail_after = -1;
        al.alloc = count_alloc; al.free = count_free; al.user = &cnt;
        memset(&ws, 0, sizeof ws);
        ws.allocator = al;
        ENSURE(cloth_qp_project_more(&ws, &first, NULL, z1, NULL, NULL, &s1) == CLOTH_SUCCESS);
        pr = growing_problem(&gz, gz.n, 600);
        cnt.fail_after = cnt.allocs;
        ENSURE(cloth_qp_project_more(&ws, &pr, NULL, z1, NULL, NULL, &s1) == CLOTH_ERROR_OUT_OF_MEMORY);
        ENSURE(memcmp(z1, gz.x, 3 * (size_t)gz.n * sizeof(cloth_real)) == 0);
        cnt.fail_after = -1;
        ENSURE(cloth_qp_project_more(&ws, &pr, NULL, z1, NULL, NULL, &s1) == CLOTH_SUCCESS);
        ENSURE(s1.continued == 0);
        ENSURE(cloth_qp_project(NULL, &pr, NULL, z2, NULL, NULL, NULL) == CLOTH_SUCCESS);
        ENSURE(memcmp(z1, z2, 3 * (size_t)gz.n * sizeof(cloth_real)) == 0);
        cloth_qp_workspace_free(&ws);
        ENSURE(cnt.allocs == cnt.frees);
    }
    growing_zone_free(&gz);
}

/* Without active[] the row states are not formed (the tight rows outside the working set
   are not factored): z and lambda are the same to the bit, the counts are -1. The zone has
   such rows: 200 single-vertex rows put exactly at a first solution z0 (met there, so the
   solution stays z0, and tight). */
TEST(no_states_without_active)
{
    cloth_rng g = cloth_rng_make(31);
    growing_zone gz;
    cloth_qp_problem pr;
    cloth_qp_stats s1, s2;
    cloth_qp_row *rows;
    cloth_real *z1, *z2, *l1, *l2;
    int32_t *a1;
    int i, extra = 200, m;
    growing_zone_make(&gz, &g, 20, 1200, 1);
    m = gz.m + extra;
    rows = (cloth_qp_row *)malloc(sizeof(cloth_qp_row) * (size_t)m);
    z1 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)gz.n);
    z2 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)gz.n);
    l1 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)m);
    l2 = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)m);
    a1 = (int32_t *)malloc(sizeof(int32_t) * (size_t)m);
    ENSURE(rows && z1 && z2 && l1 && l2 && a1);
    pr = growing_problem(&gz, gz.n, gz.m);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z1, NULL, NULL, NULL) == CLOTH_SUCCESS);
    memcpy(rows, gz.rows, sizeof(cloth_qp_row) * (size_t)gz.m);
    for (i = 0; i < extra; ++i) {
        int v[4] = { -1, -1, -1, -1 }, axis = irand(&g, 3);
        double a[4] = { 1, 0, 0, 0 }, nv[3] = { 0, 0, 0 };
        v[0] = 1 + irand(&g, gz.n - 1);
        nv[axis] = 1;
        set_row(&rows[gz.m + i], v, a, nv, (double)z1[3 * v[0] + axis]);
    }
    pr.rows = rows;
    pr.row_count = m;
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z1, l1, a1, &s1) == CLOTH_SUCCESS);
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z2, l2, NULL, &s2) == CLOTH_SUCCESS);
    ENSURE(memcmp(z1, z2, 3 * (size_t)gz.n * sizeof(cloth_real)) == 0);
    ENSURE(memcmp(l1, l2, (size_t)m * sizeof(cloth_real)) == 0);
    ENSURE(s1.iterations == s2.iterations);
    ENSURE(s2.active_count == -1 && s2.tight_count == -1);
    {
        int outside = 0;
        for (i = 0; i < m; ++i)
            if (a1[i] == CLOTH_QP_ACTIVE && l1[i] == 0) ++outside;
        printf("    %d rows: %d active (%d of them at lambda 0), %d tight\n", m, (int)s1.active_count, outside,
               (int)s1.tight_count);
        /* (with float data the extra rows' thicknesses are z0 rounded to float, off the
           double solution by more than its tolerances: most are not tight there) */
        ENSURE(IS_FLOAT || (outside >= 50 && s1.active_count > outside));
    }
    growing_zone_free(&gz);
    free(rows); free(z1); free(z2); free(l1); free(l2); free(a1);
}

/* Rows already tight at x and independent (three per vertex along the axes, more than the
   factor's first 64 rows), and copies of some: z = x exactly, lambda = 0, the independent
   rows ACTIVE (the factor grows while the result is formed) and the copies TIGHT. */
TEST(tight_rows_beyond_the_first_factor)
{
    enum { NV = 40, M = 3 * NV + NV };
    cloth_real x[3 * NV], z[3 * NV], lam[M];
    int32_t act[M];
    cloth_qp_row rows[M];
    cloth_qp_problem pr;
    cloth_qp_stats st;
    cloth_rng g = cloth_rng_make(5);
    int i, k;
    for (i = 0; i < 3 * NV; ++i) x[i] = (cloth_real)(urand(&g) - 0.5);
    for (i = 0; i < NV; ++i)
        for (k = 0; k < 3; ++k) {
            int v[4] = { -1, -1, -1, -1 };
            double a[4] = { 1, 0, 0, 0 }, nv[3] = { 0, 0, 0 };
            v[0] = i;
            nv[k] = 1;
            set_row(&rows[3 * i + k], v, a, nv, (double)x[3 * i + k]);
        }
    for (i = 0; i < NV; ++i) rows[3 * NV + i] = rows[3 * i];
    pr.vertex_count = NV; pr.x = x; pr.inverse_weight = NULL; pr.rows = rows; pr.row_count = M;
    ENSURE(cloth_qp_project(NULL, &pr, NULL, z, lam, act, &st) == CLOTH_SUCCESS);
    ENSURE(memcmp(z, x, sizeof x) == 0);
    for (i = 0; i < M; ++i) {
        ENSURE(lam[i] == 0);
        ENSURE(act[i] == (i < 3 * NV ? CLOTH_QP_ACTIVE : CLOTH_QP_TIGHT));
    }
    ENSURE(st.active_count == 3 * NV && st.tight_count == NV && st.iterations == 0);
}

const test_case qp_tests[] = {
    { "default_options", default_options },
    { "single_vertex_face_closed_form", single_vertex_face_closed_form },
    { "edge_edge_and_immovable_closed_forms", edge_edge_and_immovable_closed_forms },
    { "already_feasible_is_identity", already_feasible_is_identity },
    { "kkt_random_zones", kkt_random_zones },
    { "brute_force_small_zones", brute_force_small_zones },
    { "scale_invariance", scale_invariance },
    { "ill_conditioned_zones", ill_conditioned_zones },
    { "odd_input", odd_input },
    { "large_zone", large_zone },
    { "large_zone_with_many_exchanges", large_zone_with_many_exchanges },
    { "duplicate_rows", duplicate_rows },
    { "dependent_rows_on_a_vertex_pair", dependent_rows_on_a_vertex_pair },
    { "parallel_rows_on_a_vertex_pair", parallel_rows_on_a_vertex_pair },
    { "dependent_rows_random", dependent_rows_random },
    { "rows_over_immovable_vertices", rows_over_immovable_vertices },
    { "infeasible_zones", infeasible_zones },
    { "not_finite_and_invalid_input", not_finite_and_invalid_input },
    { "determinism_and_workspace_reuse", determinism_and_workspace_reuse },
    { "backward_finite_differences", backward_finite_differences },
    { "backward_matches_dense_formula", backward_matches_dense_formula },
    { "backward_degenerate_and_bad_input", backward_degenerate_and_bad_input },
    { "project_more_matches_project", project_more_matches_project },
    { "project_more_starts_afresh", project_more_starts_afresh },
    { "tight_rows_beyond_the_first_factor", tight_rows_beyond_the_first_factor },
    { "no_states_without_active", no_states_without_active },
    { NULL, NULL }
};
