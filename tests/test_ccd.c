/* Tests of the ccd module: proximity against dense sampling, CCD against hand-made cases, the
   public sample of Wang et al. 2021 (exact ground truth), an exact oracle on random queries
   with small integer coordinates, and exactly-touching queries built in full double precision. */
#include "runner.h"
#include "../cloth.h"
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ===================================================================================== */
/* helpers                                                                               */
/* ===================================================================================== */

static void set3(cloth_real *v, double x, double y, double z) { v[0] = (cloth_real)x; v[1] = (cloth_real)y; v[2] = (cloth_real)z; }

/* Tolerance of the proximity checks: rounding of cloth_real. */
#define PTOL (sizeof(cloth_real) == sizeof(float) ? 1e-6 : 1e-12)
/* x rounded to cloth_real, so that tests compare with what the library sees. */
static double as_real(double x) { return (double)(cloth_real)x; }

static int rnd_int(cloth_rng *g, int lo, int hi) { return lo + (int)(cloth_rng_next(g) % (uint64_t)(hi - lo + 1)); }

static double dist3(const double *a, const double *b)
{
    double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* CCD on a query given as 8 points (4 at t = 0, then 4 at t = 1) in double. */
static cloth_result ccd_run(int edge_edge, double x[8][3], const cloth_ccd_options *opt, cloth_ccd_report *rep)
{
    cloth_real v[8][3];
    int i, k;
    for (i = 0; i < 8; ++i)
        for (k = 0; k < 3; ++k) v[i][k] = (cloth_real)x[i][k];
    if (edge_edge) return cloth_ccd_edge_edge(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], opt, rep);
    return cloth_ccd_vertex_face(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], opt, rep);
}

/* ===================================================================================== */
/* proximity                                                                             */
/* ===================================================================================== */

static double vf_distance(const double *p, const double *a, const double *b, const double *c, double w[3])
{
    cloth_real P[3], A[3], B[3], C[3], W[3];
    double d;
    set3(P, p[0], p[1], p[2]); set3(A, a[0], a[1], a[2]); set3(B, b[0], b[1], b[2]); set3(C, c[0], c[1], c[2]);
    d = (double)cloth_distance_vertex_face(P, A, B, C, W);
    w[0] = W[0]; w[1] = W[1]; w[2] = W[2];
    return d;
}

static double ee_distance(const double *a0, const double *a1, const double *b0, const double *b1, double st[2])
{
    cloth_real A0[3], A1[3], B0[3], B1[3], ST[2];
    double d;
    set3(A0, a0[0], a0[1], a0[2]); set3(A1, a1[0], a1[1], a1[2]); set3(B0, b0[0], b0[1], b0[2]); set3(B1, b1[0], b1[1], b1[2]);
    d = (double)cloth_distance_edge_edge(A0, A1, B0, B1, ST);
    st[0] = ST[0]; st[1] = ST[1];
    return d;
}

/* The point the weights name, and its distance to p, must be the distance returned. */
static int vf_consistent(const double *p, const double *a, const double *b, const double *c, double d, const double w[3], double tol)
{
    double q[3];
    int k;
    if (!(w[0] >= 0 && w[1] >= 0 && w[2] >= 0) || fabs(w[0] + w[1] + w[2] - 1) > 1e-6) return 0;
    for (k = 0; k < 3; ++k) q[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
    return fabs(dist3(p, q) - d) <= tol;
}

static int ee_consistent(const double *a0, const double *a1, const double *b0, const double *b1, double d, const double st[2], double tol)
{
    double pa[3], pb[3];
    int k;
    if (!(st[0] >= 0 && st[0] <= 1 && st[1] >= 0 && st[1] <= 1)) return 0;
    for (k = 0; k < 3; ++k) { pa[k] = a0[k] + st[0] * (a1[k] - a0[k]); pb[k] = b0[k] + st[1] * (b1[k] - b0[k]); }
    return fabs(dist3(pa, pb) - d) <= tol;
}

TEST(distance_vertex_face_regions)
{
    static const double a[3] = { 0, 0, 0 }, b[3] = { 1, 0, 0 }, c[3] = { 0, 1, 0 };
    /* point, expected distance, expected weights */
    static const double cases[][7] = {
        { 0.2, 0.2, 1, 1, 0.6, 0.2, 0.2 },                /* above the face */
        { 0.2, 0.2, -3, 3, 0.6, 0.2, 0.2 },               /* below the face */
        { -1, -1, 0, 1.4142135623730951, 1, 0, 0 },       /* corner f0 */
        { 2, -1, 0.5, 1.5, 0, 1, 0 },                     /* corner f1 */
        { -0.5, 3, 0, 2.0615528128088303, 0, 0, 1 },      /* corner f2 */
        { 0.5, -1, 0, 1, 0.5, 0.5, 0 },                   /* edge f0-f1 */
        { 1, 1, 0, 0.70710678118654752, 0, 0.5, 0.5 },    /* edge f1-f2 */
        { -1, 0.25, 2, 2.2360679774997897, 0.75, 0, 0.25 }, /* edge f2-f0 */
        { 0.25, 0.25, 0, 0, 0.5, 0.25, 0.25 },            /* on the face */
        { 0.5, 0, 0, 0, 0.5, 0.5, 0 },                    /* on an edge */
        { 1, 0, 0, 0, 0, 1, 0 },                          /* on a corner */
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        double w[3], d = vf_distance(cases[i], a, b, c, w);
        ENSURE_NEAR(d, cases[i][3], PTOL);
        ENSURE_NEAR(w[0], cases[i][4], PTOL);
        ENSURE_NEAR(w[1], cases[i][5], PTOL);
        ENSURE_NEAR(w[2], cases[i][6], PTOL);
    }
}

TEST(distance_vertex_face_degenerate)
{
    static const double p[3] = { 1.5, 1, 0 }, o[3] = { 0, 0, 0 }, x1[3] = { 1, 0, 0 }, x2[3] = { 2, 0, 0 };
    static const double q[3] = { 3, 4, 0 }, r[3] = { 5, 0, 0 };
    double w[3], d;
    /* collinear corners: the triangle is the segment (0,0,0)-(2,0,0), in every corner order */
    d = vf_distance(p, o, x1, x2, w);
    ENSURE_NEAR(d, 1, PTOL);
    ENSURE(vf_consistent(p, o, x1, x2, d, w, PTOL));
    d = vf_distance(p, x2, o, x1, w);
    ENSURE_NEAR(d, 1, PTOL);
    ENSURE(vf_consistent(p, x2, o, x1, d, w, PTOL));
    d = vf_distance(r, x1, x2, o, w);
    ENSURE_NEAR(d, 3, PTOL);
    ENSURE(vf_consistent(r, x1, x2, o, d, w, PTOL));
    /* all corners at one point */
    d = vf_distance(q, o, o, o, w);
    ENSURE_NEAR(d, 5, PTOL);
    ENSURE(vf_consistent(q, o, o, o, d, w, PTOL));
    /* two corners at one point */
    d = vf_distance(p, x2, o, x2, w);
    ENSURE_NEAR(d, 1, PTOL);
    ENSURE(vf_consistent(p, x2, o, x2, d, w, PTOL));
}

/* Random points and triangles (some degenerate) against a dense barycentric grid: every grid
   point is at least the returned distance away, and some grid point is within the grid's
   resolution of it. */
TEST(distance_vertex_face_sampled)
{
    cloth_rng g = cloth_rng_make(11);
    int it, n = 120;
    for (it = 0; it < 300; ++it) {
        double x[4][3], w[3], d, best = 1e300, h;
        int i, j, k, kind = it % 6;
        for (i = 0; i < 4; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = 2 * (double)cloth_rng_uniform(&g) - 1;
        if (kind == 1) for (k = 0; k < 3; ++k) x[3][k] = 2 * x[2][k] - x[1][k];                  /* collinear */
        if (kind == 2) for (k = 0; k < 3; ++k) x[3][k] = x[1][k];                                /* two corners coincide */
        if (kind == 3) for (k = 0; k < 3; ++k) x[2][k] = x[3][k] = x[1][k];                      /* a point */
        if (kind == 4) for (k = 0; k < 3; ++k) x[3][k] = x[1][k] + 1e-9 * (x[3][k] - x[1][k]) + (x[2][k] - x[1][k]); /* sliver */
        if (kind == 5) x[0][2] = x[1][2] = x[2][2] = x[3][2] = 0;                                /* coplanar point */
        for (i = 0; i < 4; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = as_real(x[i][k]);
        d = vf_distance(x[0], x[1], x[2], x[3], w);
        ENSURE(vf_consistent(x[0], x[1], x[2], x[3], d, w, PTOL));
        for (i = 0; i <= n; ++i)
            for (j = 0; i + j <= n; ++j) {
                double u = (double)i / n, v = (double)j / n, q[3], e;
                for (k = 0; k < 3; ++k) q[k] = (1 - u - v) * x[1][k] + u * x[2][k] + v * x[3][k];
                e = dist3(x[0], q);
                ENSURE(d <= e + PTOL);
                if (e < best) best = e;
            }
        h = (dist3(x[1], x[2]) + dist3(x[1], x[3])) / n;
        ENSURE(best <= d + h + PTOL);
    }
}

TEST(distance_edge_edge_cases)
{
    static const double o[3] = { 0, 0, 0 }, a1[3] = { 2, 0, 0 };
    double st[2], d;
    {   /* crossing at distance 1 */
        static const double b0[3] = { 1, -1, 1 }, b1[3] = { 1, 1, 1 };
        d = ee_distance(o, a1, b0, b1, st);
        ENSURE_NEAR(d, 1, PTOL); ENSURE_NEAR(st[0], 0.5, PTOL); ENSURE_NEAR(st[1], 0.5, PTOL);
    }
    {   /* parallel, overlapping on [1,2] at distance 1: any closest pair has s in [0.5,1] */
        static const double b0[3] = { 1, 1, 0 }, b1[3] = { 3, 1, 0 };
        d = ee_distance(o, a1, b0, b1, st);
        ENSURE_NEAR(d, 1, PTOL);
        ENSURE(ee_consistent(o, a1, b0, b1, d, st, PTOL));
        ENSURE(st[0] >= 0.5 - PTOL && st[1] <= 0.5 + PTOL);
    }
    {   /* parallel, not overlapping: endpoint to endpoint */
        static const double b0[3] = { 3, 1, 0 }, b1[3] = { 5, 1, 0 };
        d = ee_distance(o, a1, b0, b1, st);
        ENSURE_NEAR(d, sqrt(2.0), PTOL); ENSURE_NEAR(st[0], 1, PTOL); ENSURE_NEAR(st[1], 0, PTOL);
    }
    {   /* collinear, overlapping: distance 0 */
        static const double b0[3] = { 3, 0, 0 }, b1[3] = { 1, 0, 0 };
        d = ee_distance(o, a1, b0, b1, st);
        ENSURE_NEAR(d, 0, PTOL);
        ENSURE(ee_consistent(o, a1, b0, b1, d, st, PTOL));
    }
    {   /* one zero-length segment: point to segment */
        static const double b0[3] = { 1, 2, 0 };
        d = ee_distance(o, a1, b0, b0, st);
        ENSURE_NEAR(d, 2, PTOL); ENSURE_NEAR(st[0], 0.5, PTOL);
        d = ee_distance(b0, b0, o, a1, st);
        ENSURE_NEAR(d, 2, PTOL); ENSURE_NEAR(st[1], 0.5, PTOL);
    }
    {   /* both zero-length */
        static const double p[3] = { 3, 4, 0 };
        d = ee_distance(o, o, p, p, st);
        ENSURE_NEAR(d, 5, PTOL);
    }
    {   /* intersecting at an endpoint */
        static const double b0[3] = { 2, 0, 0 }, b1[3] = { 2, 5, 7 };
        d = ee_distance(o, a1, b0, b1, st);
        ENSURE_NEAR(d, 0, PTOL); ENSURE_NEAR(st[0], 1, PTOL); ENSURE_NEAR(st[1], 0, PTOL);
    }
}

TEST(distance_edge_edge_sampled)
{
    cloth_rng g = cloth_rng_make(12);
    int it, n = 200;
    for (it = 0; it < 200; ++it) {
        double x[4][3], st[2], d, best = 1e300, h;
        int i, j, k, kind = it % 5;
        for (i = 0; i < 4; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = 2 * (double)cloth_rng_uniform(&g) - 1;
        if (kind == 1) for (k = 0; k < 3; ++k) x[3][k] = x[2][k] + 0.7 * (x[1][k] - x[0][k]);    /* parallel */
        if (kind == 2) for (k = 0; k < 3; ++k) x[1][k] = x[0][k];                                /* zero length */
        if (kind == 3) for (k = 0; k < 3; ++k) { x[2][k] = x[0][k] + 0.3 * (x[1][k] - x[0][k]); x[3][k] = x[0][k] + 1.6 * (x[1][k] - x[0][k]); } /* collinear */
        if (kind == 4) for (k = 0; k < 3; ++k) x[3][k] = x[2][k] + (x[1][k] - x[0][k]) + 1e-9 * x[3][k]; /* nearly parallel */
        for (i = 0; i < 4; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = as_real(x[i][k]);
        d = ee_distance(x[0], x[1], x[2], x[3], st);
        ENSURE(ee_consistent(x[0], x[1], x[2], x[3], d, st, PTOL));
        for (i = 0; i <= n; ++i)
            for (j = 0; j <= n; ++j) {
                double s = (double)i / n, t = (double)j / n, pa[3], pb[3], e;
                for (k = 0; k < 3; ++k) { pa[k] = x[0][k] + s * (x[1][k] - x[0][k]); pb[k] = x[2][k] + t * (x[3][k] - x[2][k]); }
                e = dist3(pa, pb);
                ENSURE(d <= e + PTOL);
                if (e < best) best = e;
            }
        h = (dist3(x[0], x[1]) + dist3(x[2], x[3])) / n;
        ENSURE(best <= d + h + PTOL);
    }
}

TEST(distance_scale_and_bad_input)
{
    /* the same configurations at tiny and huge scales, where squares would under/overflow */
    static const double tri[4][3] = { { 0.3, 0.2, 0.9 }, { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 } };
    static const double seg[4][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0.3, -1, 0.9 }, { 0.3, 1, 0.9 } };
    cloth_real v[4][3], e[4][3], w[3], st[2], d;
    int i, j, k;
    for (j = 0; j < 2; ++j) {
        double scale = sizeof(cloth_real) == sizeof(float) ? (j ? 1e30 : 1e-30) : (j ? 1e200 : 1e-200);
        for (i = 0; i < 4; ++i)
            for (k = 0; k < 3; ++k) { v[i][k] = (cloth_real)(tri[i][k] * scale); e[i][k] = (cloth_real)(seg[i][k] * scale); }
        d = cloth_distance_vertex_face(v[0], v[1], v[2], v[3], w);
        ENSURE_NEAR((double)d / scale, 0.9, 1e-6);
        ENSURE_NEAR(w[0], 0.5, 1e-6); ENSURE_NEAR(w[1], 0.3, 1e-6); ENSURE_NEAR(w[2], 0.2, 1e-6);
        d = cloth_distance_edge_edge(e[0], e[1], e[2], e[3], st);
        ENSURE_NEAR((double)d / scale, 0.9, 1e-6);
        ENSURE_NEAR(st[0], 0.3, 1e-6); ENSURE_NEAR(st[1], 0.5, 1e-6);
    }
    for (i = 0; i < 4; ++i) set3(v[i], tri[i][0], tri[i][1], tri[i][2]);
    v[2][1] = (cloth_real)NAN;
    d = cloth_distance_vertex_face(v[0], v[1], v[2], v[3], w);
    ENSURE(d != d && w[0] != w[0]);
    d = cloth_distance_edge_edge(v[0], v[1], v[2], v[3], st);
    ENSURE(d != d);
    v[2][1] = (cloth_real)HUGE_VAL;
    d = cloth_distance_edge_edge(v[0], v[1], v[2], v[3], NULL);
    ENSURE(d != d);
}

/* ===================================================================================== */
/* CCD: hand-made cases                                                                  */
/* ===================================================================================== */

/* Fill a query from a flat list of 24 numbers. */
static void q8(double x[8][3], const double *v)
{
    int i, k;
    for (i = 0; i < 8; ++i)
        for (k = 0; k < 3; ++k) x[i][k] = v[3 * i + k];
}

TEST(ccd_default_options)
{
    cloth_ccd_options o = cloth_ccd_default_options();
    ENSURE_NEAR(o.tolerance, 1e-6, 1e-12);
    ENSURE(o.max_checks == 1000000);
    ENSURE(o.refine_checks == 62500);
    ENSURE(o.minimum_separation == 0);
}

TEST(ccd_vertex_face_hit_and_miss)
{
    /* triangle fixed in z = 0; vertex falling straight through it, reaching z = 0 at t = 0.5 */
    static const double hit[24] = { 0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                    0.25, 0.25, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* the same fall beside the triangle */
    static const double miss[24] = { 0.75, 0.75, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                     0.75, 0.75, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* triangle rising through a resting vertex: contact at t = 0.25 */
    static const double rise[24] = { 0.1, 0.1, 0, -1, -1, -1, 2, -1, -1, -1, 2, -1,
                                     0.1, 0.1, 0, -1, -1, 3, 2, -1, 3, -1, 2, 3 };
    double x[8][3];
    cloth_ccd_report r;
    q8(x, hit);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && !r.budget_exhausted);
    ENSURE(r.toi <= 0.5 && r.toi >= 0.5 - 1e-5);
    ENSURE(r.checks >= 1);
    q8(x, miss);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(!r.may_collide && r.toi == 1);
    q8(x, rise);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.25 && r.toi >= 0.25 - 1e-5);
}

TEST(ccd_vertex_face_grazing)
{
    /* sliding in the triangle's plane across the edge f0-f1 (y = 0) at t = 0.5 */
    static const double slide[24] = { 0.5, -1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                      0.5, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* falling exactly onto the corner f1 */
    static const double corner[24] = { 1, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                       1, 0, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* touching the plane only at t = 1 */
    static const double end[24] = { 0.2, 0.2, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                    0.2, 0.2, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* resting on the face at t = 0 and leaving */
    static const double start[24] = { 0.2, 0.2, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                      0.2, 0.2, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    /* passing 1e-3 beyond the corner f1: a clear miss at the default tolerance */
    static const double near[24] = { 1.001, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                     1.001, 0, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    double x[8][3];
    cloth_ccd_report r;
    q8(x, slide);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.5 && r.toi >= 0.5 - 1e-5);
    q8(x, corner);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.5 && r.toi >= 0.5 - 1e-5);
    q8(x, end);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 1 && r.toi >= 1 - 1e-5);
    q8(x, start);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi == 0);
    q8(x, near);
    ENSURE(ccd_run(0, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(!r.may_collide);
}

TEST(ccd_edge_edge_cases)
{
    /* edge a along x, edge b along y falling through it at t = 0.5 */
    static const double hit[24] = { -1, 0, 0, 1, 0, 0, 0, -1, 1, 0, 1, 1,
                                    -1, 0, 0, 1, 0, 0, 0, -1, -1, 0, 1, -1 };
    /* the same fall, edge b shifted beyond a's end */
    static const double miss[24] = { -1, 0, 0, 1, 0, 0, 2, -1, 1, 2, 1, 1,
                                     -1, 0, 0, 1, 0, 0, 2, -1, -1, 2, 1, -1 };
    /* parallel edges, b sliding onto a (collinear) at t = 0.5 */
    static const double parallel[24] = { 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 1.5, 1, 0,
                                         0, 0, 0, 1, 0, 0, 0.5, -1, 0, 1.5, -1, 0 };
    /* zero-length edges (two points) meeting at t = 0.75 */
    static const double points[24] = { 0, 0, 0, 0, 0, 0, 3, 0, 0, 3, 0, 0,
                                       0, 0, 0, 0, 0, 0, -1, 0, 0, -1, 0, 0 };
    /* edges meeting end to end at t = 1 */
    static const double ends[24] = { 0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 1, 0,
                                     0, 0, 0, 1, 0, 0, 1, 0, 0, 2, 1, 0 };
    double x[8][3];
    cloth_ccd_report r;
    q8(x, hit);
    ENSURE(ccd_run(1, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.5 && r.toi >= 0.5 - 1e-5);
    q8(x, miss);
    ENSURE(ccd_run(1, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(!r.may_collide && r.toi == 1);
    q8(x, parallel);
    ENSURE(ccd_run(1, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.5 && r.toi >= 0.5 - 1e-5);
    q8(x, points);
    ENSURE(ccd_run(1, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 0.75 && r.toi >= 0.75 - 1e-5);
    q8(x, ends);
    ENSURE(ccd_run(1, x, NULL, &r) == CLOTH_SUCCESS);
    ENSURE(r.may_collide && r.toi <= 1 && r.toi >= 1 - 1e-5);
}

/* Rotate a query about the origin by a fixed rotation that takes (0,0,1) to (1,1,1)/sqrt(3). */
static void rotate_query(double x[8][3])
{
    double n[3], e1[3], e2[3], len;
    int i;
    n[0] = n[1] = n[2] = 1 / sqrt(3.0);
    e1[0] = 1 / sqrt(2.0); e1[1] = -1 / sqrt(2.0); e1[2] = 0;
    e2[0] = n[1] * e1[2] - n[2] * e1[1]; e2[1] = n[2] * e1[0] - n[0] * e1[2]; e2[2] = n[0] * e1[1] - n[1] * e1[0];
    len = sqrt(e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]);
    e2[0] /= len; e2[1] /= len; e2[2] /= len;
    for (i = 0; i < 8; ++i) {
        double a = x[i][0], b = x[i][1], c = x[i][2];
        int k;
        for (k = 0; k < 3; ++k) x[i][k] = a * e1[k] + b * e2[k] + c * n[k];
    }
}

TEST(ccd_minimum_separation)
{
    /* a vertex gliding over the face 2 mm above it, and an edge crossing another 2 mm above */
    static const double vf[24] = { -0.5, 0.25, 0.002, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                   1.5, 0.25, 0.002, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    static const double ee[24] = { -1, 0, 0, 1, 0, 0, -2, -1, 0.002, -2, 1, 0.002,
                                   -1, 0, 0, 1, 0, 0, 2, -1, 0.002, 2, 1, 0.002 };
    double x[8][3];
    cloth_ccd_options o = cloth_ccd_default_options();
    cloth_ccd_report r;
    int rot;
    for (rot = 0; rot < 2; ++rot) {
        q8(x, vf);
        if (rot) rotate_query(x);
        o.minimum_separation = (cloth_real)0.003;
        ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(r.may_collide);
        ENSURE(r.toi <= 0.25); /* above the face from t = 0.25 */
        if (!rot) ENSURE(r.toi >= 0.248);
        o.minimum_separation = (cloth_real)0.001;
        ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(!r.may_collide);
        o.minimum_separation = 0;
        ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(!r.may_collide);
        q8(x, ee);
        if (rot) rotate_query(x);
        o.minimum_separation = (cloth_real)0.003;
        ENSURE(ccd_run(1, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(r.may_collide && r.toi <= 0.25); /* b passes over a from t = 0.25 */
        if (!rot) ENSURE(r.toi >= 0.248);
        o.minimum_separation = (cloth_real)0.001;
        ENSURE(ccd_run(1, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(!r.may_collide);
    }
}

TEST(ccd_bad_input_and_budget)
{
    static const double hit[24] = { 0.25, 0.25, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                    0.25, 0.25, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    static const double miss[24] = { 5, 5, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0,
                                     5, 5, -1, 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    double x[8][3];
    cloth_ccd_options o = cloth_ccd_default_options();
    cloth_ccd_report r;
    int kind;
    for (kind = 0; kind < 2; ++kind) {
        q8(x, hit);
        x[5][1] = NAN;
        ENSURE(ccd_run(kind, x, NULL, &r) == CLOTH_ERROR_NOT_FINITE);
        ENSURE(r.may_collide && r.toi == 0);
        x[5][1] = -HUGE_VAL;
        ENSURE(ccd_run(kind, x, NULL, &r) == CLOTH_ERROR_NOT_FINITE);
        if (sizeof(cloth_real) == sizeof(double)) {
            x[5][1] = 1e301;
            ENSURE(ccd_run(kind, x, NULL, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
            ENSURE(r.may_collide && r.toi == 0);
        }
        q8(x, hit);
        o = cloth_ccd_default_options(); o.tolerance = 0;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
        o = cloth_ccd_default_options(); o.tolerance = (cloth_real)NAN;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
        o = cloth_ccd_default_options(); o.max_checks = 0;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
        o = cloth_ccd_default_options(); o.refine_checks = -1;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
        o = cloth_ccd_default_options(); o.minimum_separation = (cloth_real)-1e-3;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
        o = cloth_ccd_default_options(); o.minimum_separation = (cloth_real)HUGE_VAL;
        ENSURE(ccd_run(kind, x, &o, &r) == CLOTH_ERROR_INVALID_ARGUMENT);
    }
    /* a budget too small to decide: "may collide" with a time no later than the contact */
    q8(x, hit);
    o = cloth_ccd_default_options();
    for (o.max_checks = 1; o.max_checks <= 40; ++o.max_checks) {
        ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
        ENSURE(r.may_collide && r.toi <= 0.5 && r.checks <= o.max_checks);
        if (r.budget_exhausted) ENSURE(r.checks == o.max_checks);
    }
    o.max_checks = 3;
    ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
    ENSURE(r.budget_exhausted);
    /* refine_checks: the first contact found answers (0), or a few checks tighten it; toi
       stays a lower bound no later than the contact, tightening can only raise it, and
       stopping the refinement is not an exhausted budget */
    {
        cloth_ccd_report full, first, some;
        o = cloth_ccd_default_options();
        ENSURE(ccd_run(0, x, &o, &full) == CLOTH_SUCCESS);
        o.refine_checks = 0;
        ENSURE(ccd_run(0, x, &o, &first) == CLOTH_SUCCESS);
        o.refine_checks = 2;
        ENSURE(ccd_run(0, x, &o, &some) == CLOTH_SUCCESS);
        ENSURE(full.may_collide && first.may_collide && some.may_collide);
        ENSURE(!full.budget_exhausted && !first.budget_exhausted && !some.budget_exhausted);
        ENSURE(first.toi <= some.toi && some.toi <= full.toi && full.toi <= 0.5);
        ENSURE(first.checks < some.checks && some.checks <= first.checks + 2 && some.checks < full.checks);
        ENSURE(first.toi < full.toi); /* here the first contact found is a loose bound (0.25 against 0.49999...) */
    }
    /* a clear miss is decided by the first check */
    q8(x, miss);
    o.max_checks = 1;
    ENSURE(ccd_run(0, x, &o, &r) == CLOTH_SUCCESS);
    ENSURE(!r.may_collide && !r.budget_exhausted && r.checks == 1);
}

/* ===================================================================================== */
/* CCD: the public sample of Wang et al. 2021                                             */
/* ===================================================================================== */

/* Parses one CSV row "xn,xd,yn,yd,zn,zd,truth". Each coordinate becomes cloth_real; *err gets
   a bound on |value - exact rational| (0 when the conversion is exact, which is checked: the
   decimal strings of numerator and denominator must print back unchanged, the denominator must
   be a power of two, and the quotient times the denominator must give the numerator back). */
static int sample_row(const char *line, cloth_real out[3], double *err, int *truth, long *inexact)
{
    char tok[7][64];
    int i = 0, n = 0, k;
    const char *s = line;
    while (*s && *s != '\n' && *s != '\r') {
        if (*s == ',') { tok[i][n] = 0; if (++i >= 7) return 0; n = 0; }
        else if (n < 63) tok[i][n++] = *s;
        else return 0;
        ++s;
    }
    tok[i][n] = 0;
    if (i != 6) return 0;
    *err = 0;
    for (k = 0; k < 3; ++k) {
        char back[80];
        double num = strtod(tok[2 * k], NULL), den = strtod(tok[2 * k + 1], NULL), x;
        int e, exact = 1;
        snprintf(back, sizeof back, "%.0f", num);
        if (strcmp(back, tok[2 * k]) != 0) exact = 0;
        snprintf(back, sizeof back, "%.0f", den);
        if (strcmp(back, tok[2 * k + 1]) != 0 || !(den > 0) || frexp(den, &e) != 0.5) exact = 0;
        x = num / den;
        if (x * den != num || (x != 0 && fabs(x) < DBL_MIN)) exact = 0;
        out[k] = (cloth_real)x;
        if ((double)out[k] != x) exact = 0;
        if (!exact) {
            double b = fabs((double)out[k] - x) + 4 * DBL_EPSILON * fabs(x) + DBL_MIN;
            ++*inexact;
            if (b > *err) *err = b;
        }
    }
    *truth = atoi(tok[6]);
    return 1;
}

typedef struct sample_tally { long queries, positives, false_negatives, false_positives, inexact, exhausted; } sample_tally;

/* Runs every query of one file; returns 0 when the file is missing or malformed. */
static int sample_file(const char *path, int edge_edge, sample_tally *t)
{
    FILE *f = fopen(path, "r");
    char line[512];
    cloth_real v[8][3];
    double err, qerr = 0;
    int row = 0, truth = 0, first_truth = 0;
    if (!f) return 0;
    while (fgets(line, sizeof line, f)) {
        if (!sample_row(line, v[row], &err, &truth, &t->inexact)) { fclose(f); return 0; }
        if (row == 0) { first_truth = truth; qerr = 0; }
        if (truth != first_truth) { fclose(f); return 0; }
        if (err > qerr) qerr = err;
        if (++row == 8) {
            cloth_ccd_options o = cloth_ccd_default_options();
            cloth_ccd_report r;
            cloth_result res;
            /* An inexact conversion moves each vertex by at most qerr per axis, hence F by at
               most 2 qerr (the weights are convex): asking for that much separation keeps the
               answer conservative for the exact query. */
            if (qerr > 0) o.minimum_separation = (cloth_real)(2 * qerr * (1 + 1e-6));
            if (edge_edge) res = cloth_ccd_edge_edge(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], &o, &r);
            else res = cloth_ccd_vertex_face(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], &o, &r);
            if (res != CLOTH_SUCCESS) { fclose(f); return 0; }
            ++t->queries;
            t->positives += truth;
            if (truth && !r.may_collide) ++t->false_negatives;
            if (!truth && r.may_collide) ++t->false_positives;
            t->exhausted += r.budget_exhausted;
            row = 0;
        }
    }
    fclose(f);
    return row == 0;
}

static const char *const sample_scenes[] = {
    "erleben-cube-cliff-edges", "erleben-cube-internal-edges", "erleben-sliding-spike", "erleben-sliding-wedge",
    "erleben-spike-crack", "erleben-spike-hole", "erleben-spike-wedge", "erleben-spikes", "erleben-wedge-crack",
    "erleben-wedges", "unit-tests"
};

static int sample_run(int edge_edge, sample_tally *t)
{
    size_t s;
    memset(t, 0, sizeof *t);
    for (s = 0; s < sizeof sample_scenes / sizeof sample_scenes[0]; ++s) {
        char path[1024];
        FILE *probe;
        snprintf(path, sizeof path, "%s/tests/data/ccd-sample/%s/%s/data_0_0.csv", test_root(), sample_scenes[s],
                 edge_edge ? "edge-edge" : "vertex-face");
        if (!sample_file(path, edge_edge, t)) {
            printf("    ccd sample: cannot read %s (the sample is tests/data/ccd-sample in the repository)\n", path);
            return 0;
        }
        snprintf(path, sizeof path, "%s/tests/data/ccd-sample/%s/%s/data_0_1.csv", test_root(), sample_scenes[s],
                 edge_edge ? "edge-edge" : "vertex-face");
        probe = fopen(path, "r");
        if (probe) {
            fclose(probe);
            if (!sample_file(path, edge_edge, t)) { printf("    ccd sample: cannot read %s\n", path); return 0; }
        }
    }
    printf("    ccd sample %s: %ld queries, %ld positive, %ld false negatives, %ld false positives, "
           "%ld inexact coordinates, %ld budget exhausted\n", edge_edge ? "edge-edge" : "vertex-face",
           t->queries, t->positives, t->false_negatives, t->false_positives, t->inexact, t->exhausted);
    return 1;
}

TEST(ccd_sample_vertex_face)
{
    sample_tally t;
    ENSURE(sample_run(0, &t));
    ENSURE(t.queries == 3085 && t.positives == 248); /* the whole sample was read */
    ENSURE(t.false_negatives == 0);
    if (sizeof(cloth_real) == sizeof(double)) ENSURE(t.inexact == 0); /* as its README says */
}

TEST(ccd_sample_edge_edge)
{
    sample_tally t;
    ENSURE(sample_run(1, &t));
    ENSURE(t.queries == 4194 && t.positives == 187);
    ENSURE(t.false_negatives == 0);
    if (sizeof(cloth_real) == sizeof(double)) ENSURE(t.inexact == 0);
}

/* ===================================================================================== */
/* Exact arithmetic: big integers, dyadic rationals, polynomials with Sturm sequences      */
/* ===================================================================================== */

#define BI_LIMBS 24 /* 768 bits: the oracle needs under 300 here; overflow is detected and fails the test */
/* value = (neg ? -1 : 1) * sum d[i] 2^(32 i); n limbs in use, d[n-1] != 0; zero has n = 0 */
typedef struct bi { int neg, n; uint32_t d[BI_LIMBS]; } bi;
/* Set when a number does not fit or an exact division is not exact: the oracle's answer is then
   void, and the tests check that it stays clear. */
static int oracle_failed;

static bi bi_small(int64_t v)
{
    bi r;
    uint64_t m = v < 0 ? (uint64_t)0 - (uint64_t)v : (uint64_t)v;
    r.neg = v < 0;
    r.n = 0;
    while (m) { r.d[r.n++] = (uint32_t)m; m >>= 32; }
    return r;
}
static void bi_trim(bi *a) { while (a->n > 0 && a->d[a->n - 1] == 0) --a->n; if (!a->n) a->neg = 0; }
static int bi_sign(const bi *a) { return a->n == 0 ? 0 : (a->neg ? -1 : 1); }
static int bi_cmpabs(const bi *a, const bi *b)
{
    int i;
    if (a->n != b->n) return a->n < b->n ? -1 : 1;
    for (i = a->n - 1; i >= 0; --i)
        if (a->d[i] != b->d[i]) return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}
static int bi_cmp(const bi *a, const bi *b)
{
    int sa = bi_sign(a), sb = bi_sign(b);
    if (sa != sb) return sa < sb ? -1 : 1;
    return sa >= 0 ? bi_cmpabs(a, b) : -bi_cmpabs(a, b);
}
static bi bi_addabs(const bi *a, const bi *b)
{
    bi r;
    int i, n = a->n > b->n ? a->n : b->n;
    uint64_t c = 0;
    for (i = 0; i < n; ++i) {
        c += (uint64_t)(i < a->n ? a->d[i] : 0u) + (i < b->n ? b->d[i] : 0u);
        r.d[i] = (uint32_t)c;
        c >>= 32;
    }
    if (c) {
        if (n >= BI_LIMBS) { oracle_failed = 1; return bi_small(0); }
        r.d[n++] = (uint32_t)c;
    }
    r.n = n; r.neg = 0;
    bi_trim(&r);
    return r;
}
static bi bi_subabs(const bi *a, const bi *b) /* |a| - |b| for |a| >= |b| */
{
    bi r;
    int i;
    uint32_t borrow = 0;
    for (i = 0; i < a->n; ++i) {
        uint64_t need = (uint64_t)(i < b->n ? b->d[i] : 0u) + borrow;
        if ((uint64_t)a->d[i] >= need) { r.d[i] = (uint32_t)(a->d[i] - need); borrow = 0; }
        else { r.d[i] = (uint32_t)(((uint64_t)1 << 32) + a->d[i] - need); borrow = 1; }
    }
    r.n = a->n; r.neg = 0;
    bi_trim(&r);
    return r;
}
static bi bi_add(const bi *a, const bi *b)
{
    bi r;
    if (a->neg == b->neg) { r = bi_addabs(a, b); r.neg = a->neg; }
    else if (bi_cmpabs(a, b) >= 0) { r = bi_subabs(a, b); r.neg = a->neg; }
    else { r = bi_subabs(b, a); r.neg = b->neg; }
    if (!r.n) r.neg = 0;
    return r;
}
static bi bi_negate(bi a) { if (a.n) a.neg = !a.neg; return a; }
static bi bi_sub(const bi *a, const bi *b) { bi nb = bi_negate(*b); return bi_add(a, &nb); }
static bi bi_mul(const bi *a, const bi *b)
{
    bi r;
    int i, j;
    if (!a->n || !b->n) return bi_small(0);
    if (a->n + b->n > BI_LIMBS) { oracle_failed = 1; return bi_small(0); }
    memset(r.d, 0, sizeof(uint32_t) * (size_t)(a->n + b->n));
    for (i = 0; i < a->n; ++i) {
        uint64_t c = 0;
        for (j = 0; j < b->n; ++j) {
            c += (uint64_t)a->d[i] * b->d[j] + r.d[i + j];
            r.d[i + j] = (uint32_t)c;
            c >>= 32;
        }
        r.d[i + b->n] = (uint32_t)c;
    }
    r.n = a->n + b->n; r.neg = a->neg != b->neg;
    bi_trim(&r);
    return r;
}
static bi bi_shl(const bi *a, int k)
{
    bi r;
    int ls = k / 32, bs = k % 32, i;
    if (!a->n || !k) return *a;
    if (a->n + ls + 1 > BI_LIMBS) { oracle_failed = 1; return bi_small(0); }
    memset(r.d, 0, sizeof(uint32_t) * (size_t)(a->n + ls + 1));
    for (i = 0; i < a->n; ++i) {
        uint64_t v = (uint64_t)a->d[i] << bs;
        r.d[i + ls] |= (uint32_t)v;
        r.d[i + ls + 1] |= (uint32_t)(v >> 32);
    }
    r.n = a->n + ls + 1; r.neg = a->neg;
    bi_trim(&r);
    return r;
}
static bi bi_shr(const bi *a, int k) /* magnitude shifted right (sign kept) */
{
    bi r;
    int ls = k / 32, bs = k % 32, i;
    if (!k) return *a;
    if (ls >= a->n) return bi_small(0);
    r.n = a->n - ls; r.neg = a->neg;
    for (i = 0; i < r.n; ++i) {
        uint64_t v = a->d[i + ls];
        if (i + ls + 1 < a->n) v |= (uint64_t)a->d[i + ls + 1] << 32;
        r.d[i] = (uint32_t)(v >> bs);
    }
    bi_trim(&r);
    return r;
}
static int bi_ctz(const bi *a)
{
    int i = 0, z = 0;
    uint32_t w;
    while (i < a->n && a->d[i] == 0) ++i;
    if (i == a->n) return 0;
    w = a->d[i];
    while (!(w & 1u)) { w >>= 1; ++z; }
    return 32 * i + z;
}
static bi bi_gcd(bi a, bi b) /* binary gcd, >= 0 */
{
    int za, zb;
    a.neg = b.neg = 0;
    if (!a.n) return b;
    if (!b.n) return a;
    za = bi_ctz(&a); zb = bi_ctz(&b);
    a = bi_shr(&a, za); b = bi_shr(&b, zb);
    for (;;) {
        int c = bi_cmpabs(&a, &b);
        if (c == 0) break;
        if (c > 0) { bi t = a; a = b; b = t; }
        b = bi_subabs(&b, &a);
        b = bi_shr(&b, bi_ctz(&b));
    }
    return bi_shl(&a, za < zb ? za : zb);
}
/* a / b when b divides a (Hensel division from the low limbs); flags oracle_failed otherwise. */
static bi bi_divexact(const bi *a, const bi *b)
{
    bi x = *a, y = *b, q;
    int z, i, j, qn;
    uint32_t inv;
    if (!b->n) { oracle_failed = 1; return bi_small(0); }
    if (!a->n) return bi_small(0);
    z = bi_ctz(&y);
    if (bi_ctz(&x) < z) { oracle_failed = 1; return bi_small(0); }
    y = bi_shr(&y, z); x = bi_shr(&x, z);
    inv = y.d[0];
    for (i = 0; i < 5; ++i) inv *= 2u - y.d[0] * inv;
    qn = x.n - y.n + 1;
    if (qn < 1) { oracle_failed = 1; return bi_small(0); }
    q.n = qn; q.neg = a->neg != b->neg;
    for (i = 0; i < qn; ++i) {
        uint32_t qi = x.d[i] * inv, borrow = 0;
        uint64_t carry = 0;
        q.d[i] = qi;
        for (j = 0; i + j < x.n; ++j) {
            uint64_t p = (uint64_t)qi * (j < y.n ? y.d[j] : 0u) + carry, need;
            carry = p >> 32;
            need = (uint64_t)(uint32_t)p + borrow;
            if ((uint64_t)x.d[i + j] >= need) { x.d[i + j] = (uint32_t)(x.d[i + j] - need); borrow = 0; }
            else { x.d[i + j] = (uint32_t)(((uint64_t)1 << 32) + x.d[i + j] - need); borrow = 1; }
        }
        if (carry || borrow) { oracle_failed = 1; return bi_small(0); }
    }
    bi_trim(&x);
    if (x.n) oracle_failed = 1;
    bi_trim(&q);
    return q;
}

/* Dyadic rationals m / 2^e, e >= 0, kept with m odd or e = 0. */
typedef struct dy { bi m; int e; } dy;
static dy dy_make(bi m, int e)
{
    dy r;
    int z = m.n ? bi_ctz(&m) : e;
    if (z > e) z = e;
    r.m = bi_shr(&m, z);
    r.e = e - z;
    if (!r.m.n) r.e = 0;
    return r;
}
static dy dy_int(int64_t v) { return dy_make(bi_small(v), 0); }
static dy dy_from_double(double x)
{
    int ex, e;
    double f = frexp(x, &ex);
    bi m = bi_small((int64_t)ldexp(f, 53));
    e = 53 - ex;
    if (e < 0) { m = bi_shl(&m, -e); e = 0; }
    return dy_make(m, e);
}
static dy dy_add(const dy *a, const dy *b)
{
    int e = a->e > b->e ? a->e : b->e;
    bi x = bi_shl(&a->m, e - a->e), y = bi_shl(&b->m, e - b->e);
    return dy_make(bi_add(&x, &y), e);
}
static dy dy_sub(const dy *a, const dy *b) { dy nb = *b; nb.m = bi_negate(nb.m); return dy_add(a, &nb); }
static dy dy_mul(const dy *a, const dy *b) { return dy_make(bi_mul(&a->m, &b->m), a->e + b->e); }
static int dy_cmp(const dy *a, const dy *b)
{
    int e = a->e > b->e ? a->e : b->e;
    bi x = bi_shl(&a->m, e - a->e), y = bi_shl(&b->m, e - b->e);
    return bi_cmp(&x, &y);
}
static dy dy_mid(const dy *a, const dy *b)
{
    dy s = dy_add(a, b);
    return dy_make(s.m, s.e + 1);
}

/* Polynomials in t with integer coefficients, degree <= PMAX; deg = -1 for zero. */
#define PMAX 6
typedef struct poly { int deg; bi c[PMAX + 1]; } poly;

static void poly_trim(poly *p) { while (p->deg >= 0 && !p->c[p->deg].n) --p->deg; }
static poly poly_zero(void) { poly p; p.deg = -1; return p; }
static poly poly_lin(int64_t c0, int64_t c1) { poly p; p.deg = 1; p.c[0] = bi_small(c0); p.c[1] = bi_small(c1); poly_trim(&p); return p; }
static poly poly_addsub(const poly *a, const poly *b, int sub)
{
    poly r;
    int i;
    r.deg = a->deg > b->deg ? a->deg : b->deg;
    for (i = 0; i <= r.deg; ++i) {
        bi x = i <= a->deg ? a->c[i] : bi_small(0), y = i <= b->deg ? b->c[i] : bi_small(0);
        r.c[i] = sub ? bi_sub(&x, &y) : bi_add(&x, &y);
    }
    poly_trim(&r);
    return r;
}
static poly poly_add(const poly *a, const poly *b) { return poly_addsub(a, b, 0); }
static poly poly_sub(const poly *a, const poly *b) { return poly_addsub(a, b, 1); }
static poly poly_mul(const poly *a, const poly *b)
{
    poly r;
    int i, j;
    if (a->deg < 0 || b->deg < 0) return poly_zero();
    if (a->deg + b->deg > PMAX) { oracle_failed = 1; return poly_zero(); }
    r.deg = a->deg + b->deg;
    for (i = 0; i <= r.deg; ++i) r.c[i] = bi_small(0);
    for (i = 0; i <= a->deg; ++i)
        for (j = 0; j <= b->deg; ++j) {
            bi t = bi_mul(&a->c[i], &b->c[j]);
            r.c[i + j] = bi_add(&r.c[i + j], &t);
        }
    poly_trim(&r);
    return r;
}
static poly poly_negate(poly p) { int i; for (i = 0; i <= p.deg; ++i) p.c[i] = bi_negate(p.c[i]); return p; }
static poly poly_deriv(const poly *a)
{
    poly r;
    int i;
    r.deg = a->deg - 1;
    if (r.deg < 0) return poly_zero();
    for (i = 1; i <= a->deg; ++i) { bi k = bi_small(i); r.c[i - 1] = bi_mul(&a->c[i], &k); }
    poly_trim(&r);
    return r;
}
/* p divided by the (positive) gcd of its coefficients: signs are kept. */
static poly poly_prim(poly p)
{
    bi g = bi_small(0);
    int i;
    for (i = 0; i <= p.deg; ++i) g = bi_gcd(g, p.c[i]);
    if (g.n && !(g.n == 1 && g.d[0] == 1))
        for (i = 0; i <= p.deg; ++i) p.c[i] = bi_divexact(&p.c[i], &g);
    return p;
}
/* A positive multiple of the remainder of a by b (b nonzero). */
static poly poly_prem(const poly *a, const poly *b)
{
    poly r = *a;
    bi lc;
    int steps = 0, i;
    if (b->deg < 0) { oracle_failed = 1; return poly_zero(); }
    lc = b->c[b->deg];
    while (r.deg >= b->deg && r.deg >= 0) {
        int sh = r.deg - b->deg;
        bi lr = r.c[r.deg];
        for (i = 0; i <= r.deg; ++i) r.c[i] = bi_mul(&lc, &r.c[i]);
        for (i = 0; i <= b->deg; ++i) { bi t = bi_mul(&lr, &b->c[i]); r.c[i + sh] = bi_sub(&r.c[i + sh], &t); }
        r.c[r.deg] = bi_small(0);
        poly_trim(&r);
        ++steps;
        if (oracle_failed) return poly_zero();
    }
    if (lc.neg && (steps & 1)) r = poly_negate(r);
    return poly_prim(r);
}
/* Greatest common divisor, primitive with a positive leading coefficient (zero if both are). */
static poly poly_gcd(poly a, poly b)
{
    while (b.deg >= 0) {
        poly r = poly_prem(&a, &b);
        a = b;
        b = r;
        if (oracle_failed) return poly_zero();
    }
    if (a.deg < 0) return a;
    a = poly_prim(a);
    if (a.c[a.deg].neg) a = poly_negate(a);
    return a;
}
/* a / b for b dividing a (b primitive: the quotient has integer coefficients). */
static poly poly_divexact(const poly *a, const poly *b)
{
    poly q = poly_zero(), r = *a;
    int i;
    if (b->deg < 0) { oracle_failed = 1; return q; }
    if (a->deg < b->deg) { if (a->deg >= 0) oracle_failed = 1; return q; }
    q.deg = a->deg - b->deg;
    for (i = 0; i <= q.deg; ++i) q.c[i] = bi_small(0);
    while (r.deg >= b->deg && r.deg >= 0) {
        int sh = r.deg - b->deg, j;
        bi c = bi_divexact(&r.c[r.deg], &b->c[b->deg]);
        q.c[sh] = c;
        for (j = 0; j <= b->deg; ++j) { bi t = bi_mul(&c, &b->c[j]); r.c[j + sh] = bi_sub(&r.c[j + sh], &t); }
        poly_trim(&r);
        if (oracle_failed) return poly_zero();
    }
    if (r.deg >= 0) oracle_failed = 1;
    poly_trim(&q);
    return q;
}
/* The squarefree part of a nonconstant polynomial, primitive with a positive leading coefficient. */
static poly poly_sqfree(const poly *f)
{
    poly d = poly_deriv(f), g = poly_gcd(*f, d), q = poly_divexact(f, &g);
    q = poly_prim(q);
    if (q.deg >= 0 && q.c[q.deg].neg) q = poly_negate(q);
    return q;
}
/* Sign of f(x), exactly: the sign of sum c_i m^i 2^(e (deg - i)) for x = m / 2^e. */
static int poly_sign_at(const poly *f, const dy *x)
{
    bi acc;
    int i;
    if (f->deg < 0) return 0;
    acc = f->c[f->deg];
    for (i = f->deg - 1; i >= 0; --i) {
        bi t = bi_mul(&acc, &x->m), s = bi_shl(&f->c[i], x->e * (f->deg - i));
        acc = bi_add(&t, &s);
    }
    return bi_sign(&acc);
}

/* Sturm sequences: for squarefree f, var(a) - var(b) is the number of roots in (a, b]. */
typedef struct sturm { int n; poly p[PMAX + 2]; } sturm;
static void sturm_make(sturm *s, const poly *f)
{
    s->p[0] = *f;
    s->n = 1;
    if (f->deg < 1) return;
    s->p[1] = poly_prim(poly_deriv(f));
    s->n = 2;
    while (s->p[s->n - 1].deg > 0 && s->n < PMAX + 2) {
        poly r = poly_prem(&s->p[s->n - 2], &s->p[s->n - 1]);
        if (r.deg < 0 || oracle_failed) break;
        s->p[s->n++] = poly_negate(r);
    }
}
static int sturm_var(const sturm *s, const dy *x)
{
    int i, last = 0, v = 0;
    for (i = 0; i < s->n; ++i) {
        int sg = poly_sign_at(&s->p[i], x);
        if (!sg) continue;
        if (last && sg != last) ++v;
        last = sg;
    }
    return v;
}
static int sturm_count(const sturm *s, const dy *a, const dy *b) { return sturm_var(s, a) - sturm_var(s, b); }

/* ---- the exact CCD oracle -------------------------------------------------------------- */

/* Real algebraic numbers in [0,1]: the dyadic lo when exact, otherwise the only root of the
   oracle's squarefree polynomial f in (lo, hi]. */
#define ORACLE_POLYS 64
typedef struct oracle { int n; poly f[ORACLE_POLYS]; sturm s[ORACLE_POLYS]; } oracle;
typedef struct apt { int exact, f; dy lo, hi; } apt;
static oracle the_oracle; /* about 1 MB: kept out of the stack */

static int oracle_add(oracle *o, const poly *f)
{
    if (o->n >= ORACLE_POLYS) { oracle_failed = 1; return 0; }
    o->f[o->n] = poly_sqfree(f);
    sturm_make(&o->s[o->n], &o->f[o->n]);
    return o->n++;
}
static void apt_refine(oracle *o, apt *x)
{
    dy mid;
    if (x->exact) return;
    mid = dy_mid(&x->lo, &x->hi);
    if (sturm_count(&o->s[x->f], &x->lo, &mid) == 1) {
        if (poly_sign_at(&o->f[x->f], &mid) == 0) { x->exact = 1; x->lo = x->hi = mid; }
        else x->hi = mid;
    } else {
        x->lo = mid;
    }
}
static void isolate_rec(oracle *o, int f, const dy *lo, const dy *hi, int count, apt *out, int *n)
{
    dy mid;
    int c;
    if (count <= 0 || oracle_failed) return;
    if (count == 1) {
        apt a;
        a.f = f; a.lo = *lo; a.hi = *hi; a.exact = 0;
        if (poly_sign_at(&o->f[f], hi) == 0) { a.exact = 1; a.lo = *hi; }
        if (*n < 2 * PMAX) out[(*n)++] = a; else oracle_failed = 1;
        return;
    }
    mid = dy_mid(lo, hi);
    c = sturm_count(&o->s[f], lo, &mid);
    isolate_rec(o, f, lo, &mid, c, out, n);
    isolate_rec(o, f, &mid, hi, count - c, out, n);
}
/* The roots in [0,1] of oracle polynomial f, increasing. */
static int isolate(oracle *o, int f, apt *out)
{
    dy zero = dy_int(0), one = dy_int(1);
    int n = 0;
    if (poly_sign_at(&o->f[f], &zero) == 0) { out[0].exact = 1; out[0].f = f; out[0].lo = out[0].hi = zero; n = 1; }
    isolate_rec(o, f, &zero, &one, sturm_count(&o->s[f], &zero, &one), out, &n);
    return n;
}
/* Sign of g at x (x may be refined). */
static int apt_sign(oracle *o, apt *x, const poly *g)
{
    poly h, gs;
    sturm sg;
    if (g->deg < 0) return 0;
    if (g->deg == 0) return bi_sign(&g->c[0]);
    if (x->exact) return poly_sign_at(g, &x->lo);
    h = poly_gcd(o->f[x->f], *g);
    if (h.deg >= 1) {
        sturm_make(&sg, &h);
        if (sturm_count(&sg, &x->lo, &x->hi) >= 1) return 0; /* a common root in (lo, hi] is x */
    }
    gs = poly_sqfree(g);
    sturm_make(&sg, &gs);
    while (!x->exact && !oracle_failed) {
        if (sturm_count(&sg, &x->lo, &x->hi) == 0) return poly_sign_at(g, &x->hi);
        apt_refine(o, x);
    }
    return poly_sign_at(g, &x->lo);
}
/* -1, 0, 1 as x <, =, > y (both may be refined). */
static int apt_cmp(oracle *o, apt *x, apt *y)
{
    int swap = 0, r;
    if (x->exact && y->exact) return dy_cmp(&x->lo, &y->lo);
    if (!x->exact && y->exact) { apt *t = x; x = y; y = t; swap = 1; }
    if (x->exact) {
        const dy *q = &x->lo;
        if (dy_cmp(q, &y->lo) <= 0) r = -1;
        else if (dy_cmp(q, &y->hi) > 0) r = 1;
        else if (poly_sign_at(&o->f[y->f], q) == 0) r = 0;
        else r = sturm_count(&o->s[y->f], &y->lo, q) == 1 ? 1 : -1;
        return swap ? -r : r;
    }
    {
        poly g = poly_gcd(o->f[x->f], o->f[y->f]);
        sturm sg;
        int have = g.deg >= 1;
        if (have) sturm_make(&sg, &g);
        for (;;) {
            const dy *lo, *hi;
            if (oracle_failed) return 0;
            if (x->exact || y->exact) return apt_cmp(o, x, y);
            if (dy_cmp(&x->hi, &y->lo) <= 0) return -1;
            if (dy_cmp(&y->hi, &x->lo) <= 0) return 1;
            lo = dy_cmp(&x->lo, &y->lo) > 0 ? &x->lo : &y->lo;
            hi = dy_cmp(&x->hi, &y->hi) < 0 ? &x->hi : &y->hi;
            if (have && sturm_count(&sg, lo, hi) >= 1) return 0;
            apt_refine(o, x);
            apt_refine(o, y);
        }
    }
}

enum { REL_EQ, REL_GE, REL_GT };
typedef struct cond { poly p; int rel; } cond;
static int rel_ok(int s, int rel) { return rel == REL_EQ ? s == 0 : (rel == REL_GE ? s >= 0 : s > 0); }

static int conds_hold(oracle *o, apt *x, const cond *c, int n)
{
    int i;
    for (i = 0; i < n; ++i)
        if (!rel_ok(apt_sign(o, x, &c[i].p), c[i].rel)) return 0;
    return 1;
}

/* Is there a t in [0,1] where every condition holds? If so, *earliest is the infimum of them. */
static int conj_exists(oracle *o, const cond *c, int n, apt *earliest)
{
    cond rest[8];
    apt cand[2 + 8 * 2 * PMAX], pts[2 + 8 * 2 * PMAX];
    poly h = poly_zero();
    int i, m = 0, have_eq = 0, np, nc;
    for (i = 0; i < n; ++i) {
        if (c[i].p.deg <= 0) {
            if (!rel_ok(c[i].p.deg < 0 ? 0 : bi_sign(&c[i].p.c[0]), c[i].rel)) return 0;
        } else if (c[i].rel == REL_EQ) {
            h = have_eq ? poly_gcd(h, c[i].p) : c[i].p;
            have_eq = 1;
        } else {
            rest[m++] = c[i];
        }
    }
    if (have_eq) {
        if (h.deg < 1) return 0;
        np = isolate(o, oracle_add(o, &h), pts);
        for (i = 0; i < np; ++i)
            if (conds_hold(o, &pts[i], rest, m)) { *earliest = pts[i]; return 1; }
        return 0;
    }
    /* inequalities only: the answer is decided at the roots, at 0 and 1, and at one point of
       each open interval between them, where every sign is constant */
    cand[0].exact = 1; cand[0].f = 0; cand[0].lo = cand[0].hi = dy_int(0);
    cand[1].exact = 1; cand[1].f = 0; cand[1].lo = cand[1].hi = dy_int(1);
    nc = 2;
    for (i = 0; i < m; ++i) nc += isolate(o, oracle_add(o, &rest[i].p), cand + nc);
    np = 0;
    for (i = 0; i < nc; ++i) { /* insertion into the sorted list, dropping duplicates */
        int j = np, dup = 0;
        while (j > 0) {
            int cmp = apt_cmp(o, &pts[j - 1], &cand[i]);
            if (cmp == 0) dup = 1;
            if (cmp <= 0) break;
            --j;
        }
        if (dup) continue;
        memmove(&pts[j + 1], &pts[j], sizeof(apt) * (size_t)(np - j));
        pts[j] = cand[i];
        ++np;
    }
    for (i = 0; i < np; ++i) {
        if (conds_hold(o, &pts[i], rest, m)) { *earliest = pts[i]; return 1; }
        if (i + 1 < np) {
            apt s;
            while (!oracle_failed && dy_cmp(&pts[i].hi, &pts[i + 1].lo) >= 0) { apt_refine(o, &pts[i]); apt_refine(o, &pts[i + 1]); }
            s.exact = 1; s.f = 0; s.lo = s.hi = dy_mid(&pts[i].hi, &pts[i + 1].lo);
            if (conds_hold(o, &s, rest, m)) { *earliest = pts[i]; return 1; }
        }
    }
    return 0;
}

/* Vectors of polynomials. */
typedef struct vpoly { poly c[3]; } vpoly;
static vpoly vp_motion(const int64_t *x0, const int64_t *x1) { vpoly r; int k; for (k = 0; k < 3; ++k) r.c[k] = poly_lin(x0[k], x1[k] - x0[k]); return r; }
static vpoly vp_sub(const vpoly *a, const vpoly *b) { vpoly r; int k; for (k = 0; k < 3; ++k) r.c[k] = poly_sub(&a->c[k], &b->c[k]); return r; }
static vpoly vp_add(const vpoly *a, const vpoly *b) { vpoly r; int k; for (k = 0; k < 3; ++k) r.c[k] = poly_add(&a->c[k], &b->c[k]); return r; }
static vpoly vp_neg(const vpoly *a) { vpoly r; int k; for (k = 0; k < 3; ++k) r.c[k] = poly_negate(a->c[k]); return r; }
static poly vp_dot(const vpoly *a, const vpoly *b)
{
    poly r = poly_zero();
    int k;
    for (k = 0; k < 3; ++k) { poly t = poly_mul(&a->c[k], &b->c[k]); r = poly_add(&r, &t); }
    return r;
}
static vpoly vp_cross(const vpoly *a, const vpoly *b)
{
    vpoly r;
    int k;
    for (k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        poly x = poly_mul(&a->c[i], &b->c[j]), y = poly_mul(&a->c[j], &b->c[i]);
        r.c[k] = poly_sub(&x, &y);
    }
    return r;
}
static cond mkcond(poly p, int rel) { cond c; c.p = p; c.rel = rel; return c; }

/* Point X on segment [0, E] at some t: two alternatives (E != 0 and X = lambda E, or X = 0),
   each with "N = 0" in front. Appends the conjunctions to list. */
static int onseg_conjs(const poly *nn, const vpoly *x, const vpoly *e, cond list[][8], int *len, int n)
{
    vpoly xe = vp_cross(x, e);
    poly xdote = vp_dot(x, e), ee = vp_dot(e, e);
    list[n][0] = mkcond(*nn, REL_EQ);
    list[n][1] = mkcond(vp_dot(&xe, &xe), REL_EQ);
    list[n][2] = mkcond(xdote, REL_GE);
    list[n][3] = mkcond(poly_sub(&ee, &xdote), REL_GE);
    list[n][4] = mkcond(ee, REL_GT);
    len[n++] = 5;
    list[n][0] = mkcond(*nn, REL_EQ);
    list[n][1] = mkcond(vp_dot(x, x), REL_EQ);
    len[n++] = 2;
    return n;
}

/* Exact answer for a query with integer coordinates: does F have a root in the closed domain,
   and when is the first one. The query holds at each t either the nondegenerate case (N != 0:
   coplanar, with barycentric coordinates from cross products in range) or the degenerate one
   (N = 0: the primitives reduce to segments, and they meet iff an endpoint lies on a segment).
   Every condition is a polynomial sign condition in t, decided exactly. */
static int oracle_collide(oracle *o, int edge_edge, const int64_t x[8][3], apt *earliest)
{
    cond list[9][8];
    int len[9], n = 0, i, found = 0;
    vpoly v[4], nrm, tmp;
    poly nn;
    o->n = 0;
    for (i = 0; i < 4; ++i) v[i] = vp_motion(x[i], x[4 + i]);
    if (!edge_edge) {
        vpoly P = vp_sub(&v[0], &v[1]), B = vp_sub(&v[2], &v[1]), C = vp_sub(&v[3], &v[1]), X, E;
        poly g1, g2, g3;
        nrm = vp_cross(&B, &C);
        nn = vp_dot(&nrm, &nrm);
        tmp = vp_cross(&P, &C); g1 = vp_dot(&tmp, &nrm);
        tmp = vp_cross(&B, &P); g2 = vp_dot(&tmp, &nrm);
        g3 = poly_sub(&nn, &g1); g3 = poly_sub(&g3, &g2);
        list[n][0] = mkcond(nn, REL_GT);
        list[n][1] = mkcond(vp_dot(&P, &nrm), REL_EQ);
        list[n][2] = mkcond(g1, REL_GE);
        list[n][3] = mkcond(g2, REL_GE);
        list[n][4] = mkcond(g3, REL_GE);
        len[n++] = 5;
        n = onseg_conjs(&nn, &P, &B, list, len, n);
        n = onseg_conjs(&nn, &P, &C, list, len, n);
        X = vp_sub(&P, &B); E = vp_sub(&C, &B);
        n = onseg_conjs(&nn, &X, &E, list, len, n);
    } else {
        vpoly A = vp_sub(&v[1], &v[0]), B = vp_sub(&v[3], &v[2]), R = vp_sub(&v[2], &v[0]), X;
        poly su, sv;
        nrm = vp_cross(&A, &B);
        nn = vp_dot(&nrm, &nrm);
        tmp = vp_cross(&R, &B); su = vp_dot(&tmp, &nrm);
        tmp = vp_cross(&R, &A); sv = vp_dot(&tmp, &nrm);
        list[n][0] = mkcond(nn, REL_GT);
        list[n][1] = mkcond(vp_dot(&R, &nrm), REL_EQ);
        list[n][2] = mkcond(su, REL_GE);
        list[n][3] = mkcond(poly_sub(&nn, &su), REL_GE);
        list[n][4] = mkcond(sv, REL_GE);
        list[n][5] = mkcond(poly_sub(&nn, &sv), REL_GE);
        len[n++] = 6;
        n = onseg_conjs(&nn, &R, &A, list, len, n);            /* b0 on edge a */
        X = vp_add(&R, &B);
        n = onseg_conjs(&nn, &X, &A, list, len, n);            /* b1 on edge a */
        X = vp_neg(&R);
        n = onseg_conjs(&nn, &X, &B, list, len, n);            /* a0 on edge b */
        X = vp_sub(&A, &R);
        n = onseg_conjs(&nn, &X, &B, list, len, n);            /* a1 on edge b */
    }
    for (i = 0; i < n && !oracle_failed; ++i) {
        apt e;
        if (conj_exists(o, list[i], len[i], &e)) {
            if (!found || apt_cmp(o, &e, earliest) < 0) *earliest = e;
            found = 1;
        }
    }
    return found;
}

/* ===================================================================================== */
/* Randomized CCD against the exact oracle                                                */
/* ===================================================================================== */

/* Random queries with integer coordinates of magnitude <= 16, most of them degenerate on purpose. */
static void gen_query(cloth_rng *g, int edge_edge, int x[8][3])
{
    int fam = rnd_int(g, 0, 9), i, k, s = rnd_int(g, 0, 1) ? 4 : 0; /* s: the time a contact is built at */
    for (i = 0; i < 8; ++i)
        for (k = 0; k < 3; ++k) x[i][k] = rnd_int(g, -3, 3);
    switch (fam) {
    case 0: break;                                                    /* general */
    case 1: for (i = 0; i < 8; ++i) x[i][2] = 0; break;                /* all in one plane */
    case 2: for (i = 0; i < 4; ++i) for (k = 0; k < 3; ++k) x[4 + i][k] = x[i][k]; break; /* static */
    case 3: /* a vertex exactly on a corner of the other primitive at t = 0 or 1 */
        for (k = 0; k < 3; ++k) x[s + (edge_edge ? 2 : 0)][k] = x[s + 1][k];
        break;
    case 4: /* a vertex exactly at an edge midpoint at t = 0 or 1 */
        for (k = 0; k < 3; ++k) x[s + (edge_edge ? 1 : 2)][k] = 2 * x[s + (edge_edge ? 2 : 0)][k] - x[s + (edge_edge ? 0 : 1)][k];
        break;
    case 5: /* vertex-face: p at the centroid at t = 0 or 1; edge-edge: the midpoints coincide */
        if (!edge_edge) { for (k = 0; k < 3; ++k) x[s + 3][k] = 3 * x[s][k] - x[s + 1][k] - x[s + 2][k]; } /* p the centroid */
        else { for (k = 0; k < 3; ++k) x[s + 3][k] = x[s][k] + x[s + 1][k] - x[s + 2][k]; }
        break;
    case 6: /* degenerate: collinear triangle / parallel edges, at both times */
        for (i = 0; i < 2; ++i)
            for (k = 0; k < 3; ++k) {
                if (!edge_edge) x[4 * i + 3][k] = 2 * x[4 * i + 2][k] - x[4 * i + 1][k];
                else x[4 * i + 3][k] = x[4 * i + 2][k] + x[4 * i + 1][k] - x[4 * i][k];
            }
        break;
    case 7: /* degenerate: coincident corners / zero-length edge, at both times */
        for (i = 0; i < 2; ++i)
            for (k = 0; k < 3; ++k) x[4 * i + (edge_edge ? 1 : 3)][k] = x[4 * i + (edge_edge ? 0 : 2)][k];
        break;
    case 8: /* small coordinates: many coincidences */
        for (i = 0; i < 8; ++i) for (k = 0; k < 3; ++k) x[i][k] = rnd_int(g, -1, 1);
        break;
    default: /* collinear edges / vertex moving within the face's plane */
        for (i = 0; i < 8; ++i) x[i][1] = x[i][2] = 0;
        if (!edge_edge) for (i = 0; i < 8; ++i) x[i][1] = i % 4 == 0 ? 0 : rnd_int(g, -3, 3);
        break;
    }
}

/* Proves, when it can, that max_k |F_k| > band over the whole domain, by exact corner values
   over dyadic boxes: with integer coordinates of magnitude <= 16 (times a power of two) and box
   bounds of at most 21 fractional bits, every corner value below is an exact double (positions
   at t have numerators below 2^(21+6), each weighted term below 2^(42+6), their sum below 2^50). Returns 1
   only with such a proof; 0 when it finds a point within the band or gives up. */
static int certify_apart(int edge_edge, const double x[8][3], double band)
{
    typedef struct cbox { double t0, t1, u0, u1, v0, v1; } cbox;
    cbox stack[128];
    int n = 1, nodes = 0;
    const double floor_width = 1.0 / 2097152.0; /* 2^-21 */
    stack[0].t0 = stack[0].u0 = stack[0].v0 = 0;
    stack[0].t1 = stack[0].u1 = stack[0].v1 = 1;
    while (n > 0) {
        cbox b = stack[--n], c0, c1;
        double lo[3] = { 1e300, 1e300, 1e300 }, hi[3] = { -1e300, -1e300, -1e300 }, w[3];
        int it, iu, iv, k, j, out = 0, split = 0;
        if (++nodes > 400000) return 0;
        if (!edge_edge && b.u0 + b.v0 > 1) continue;
        for (it = 0; it < 2; ++it)
            for (iu = 0; iu < 2; ++iu)
                for (iv = 0; iv < 2; ++iv) {
                    double t = it ? b.t1 : b.t0, u = iu ? b.u1 : b.u0, v = iv ? b.v1 : b.v0, y[4], f[3], m = 0;
                    for (k = 0; k < 3; ++k) {
                        for (j = 0; j < 4; ++j) y[j] = x[j][k] + t * (x[4 + j][k] - x[j][k]);
                        if (edge_edge) f[k] = ((1 - u) * y[0] + u * y[1]) - ((1 - v) * y[2] + v * y[3]);
                        else f[k] = y[0] - ((1 - u - v) * y[1] + u * y[2] + v * y[3]);
                        if (f[k] < lo[k]) lo[k] = f[k];
                        if (f[k] > hi[k]) hi[k] = f[k];
                        if (fabs(f[k]) > m) m = fabs(f[k]);
                    }
                    if (m <= band && (edge_edge || u + v <= 1)) return 0; /* a point within the band */
                }
        for (k = 0; k < 3; ++k)
            if (lo[k] > band || hi[k] < -band) out = 1;
        if (out) continue;
        w[0] = b.t1 - b.t0; w[1] = b.u1 - b.u0; w[2] = b.v1 - b.v0;
        for (k = 1; k < 3; ++k) if (w[k] > w[split]) split = k;
        if (w[split] <= floor_width || n + 2 > 128) return 0;
        c0 = c1 = b;
        if (split == 0) c0.t1 = c1.t0 = 0.5 * (b.t0 + b.t1);
        else if (split == 1) c0.u1 = c1.u0 = 0.5 * (b.u0 + b.u1);
        else c0.v1 = c1.v0 = 0.5 * (b.v0 + b.v1);
        stack[n++] = c1;
        stack[n++] = c0;
    }
    return 1;
}

typedef struct oracle_tally { long queries, collide, fp, fp_separation, exhausted; } oracle_tally;

/* One kind: random queries, the exact answer, and CCD at two scales and two separations.
   Asserted: no false negative, toi no later than the exact first contact, and every report
   without a collision (budget exhausted or not) not provably farther than the tolerance band. */
static void oracle_suite(int edge_edge, int count, unsigned seed)
{
    oracle *o = &the_oracle;
    cloth_rng g = cloth_rng_make(seed);
    oracle_tally t;
    int q;
    memset(&t, 0, sizeof t);
    oracle_failed = 0;
    for (q = 0; q < count; ++q) {
        int xi[8][3], i, k, sc, dsel, collide;
        int64_t xl[8][3];
        apt first;
        gen_query(&g, edge_edge, xi);
        for (i = 0; i < 8; ++i)
            for (k = 0; k < 3; ++k) xl[i][k] = xi[i][k];
        collide = oracle_collide(o, edge_edge, (const int64_t (*)[3])xl, &first);
        if (oracle_failed) { printf("    oracle failed on query %d\n", q); break; }
        ++t.queries;
        t.collide += collide;
        for (sc = 0; sc < 2; ++sc)
            for (dsel = 0; dsel < 2; ++dsel) {
                double scale = sc ? 1.0 / 1024 : 1, x[8][3], d = dsel ? 0.05 * scale : 0, band;
                cloth_ccd_options opt = cloth_ccd_default_options();
                cloth_ccd_report r;
                cloth_result res;
                for (i = 0; i < 8; ++i)
                    for (k = 0; k < 3; ++k) x[i][k] = xi[i][k] * scale;
                opt.minimum_separation = (cloth_real)d;
                res = ccd_run(edge_edge, x, &opt, &r);
                t.exhausted += r.budget_exhausted;
                if (res != CLOTH_SUCCESS || (collide && !r.may_collide)) {
                    printf("    %s query %d (scale %g, d %g): exact %d, ccd %d, exhausted %d, points",
                           edge_edge ? "edge-edge" : "vertex-face", q, scale, d, collide, r.may_collide, r.budget_exhausted);
                    for (i = 0; i < 8; ++i) printf(" (%d %d %d)", xi[i][0], xi[i][1], xi[i][2]);
                    printf("\n");
                    ENSURE(0);
                }
                if (collide) {
                    /* toi <= the exact first contact (itself no earlier than the first time within d) */
                    apt toi;
                    toi.exact = 1; toi.f = 0; toi.lo = toi.hi = dy_from_double((double)r.toi);
                    ENSURE(apt_cmp(o, &toi, &first) <= 0);
                    ENSURE(!oracle_failed);
                } else if (r.may_collide) {
                    /* a report must come from within about d + tolerance per axis */
                    band = (double)(cloth_real)d + 1.000001 * (double)opt.tolerance + 1e-12;
                    if (dsel == 0) ++t.fp; else ++t.fp_separation;
                    if (certify_apart(edge_edge, (const double (*)[3])x, band)) {
                        printf("    %s query %d (scale %g, d %g): reported but provably apart\n",
                               edge_edge ? "edge-edge" : "vertex-face", q, scale, d);
                        ENSURE(0);
                    }
                }
            }
    }
    ENSURE(!oracle_failed);
    ENSURE(t.queries == count);
    printf("    exact oracle %s: %ld queries, %ld colliding, 0 false negatives; reported without a collision: %ld at d = 0, "
           "%ld at d > 0 (none provably outside the band); %ld of %ld runs out of budget\n", edge_edge ? "edge-edge" : "vertex-face",
           t.queries, t.collide, t.fp, t.fp_separation, t.exhausted, 4 * t.queries);
    /* the generator must produce both answers in quantity, or the test tests little */
    ENSURE(t.collide > count / 10 && t.collide < count - count / 10);
}

TEST(ccd_exact_oracle_vertex_face) { oracle_suite(0, 2000, 21); }
TEST(ccd_exact_oracle_edge_edge) { oracle_suite(1, 2000, 22); }

/* The oracle itself, on cases whose answers are known by hand. */
TEST(ccd_exact_oracle_known_cases)
{
    static const int64_t vf_hit[8][3] = { { 1, 1, 4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 },
                                      { 1, 1, -4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 } };  /* first contact t = 1/2 */
    static const int64_t vf_miss[8][3] = { { 3, 3, 4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 },
                                       { 3, 3, -4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 } };
    static const int64_t vf_edge[8][3] = { { 2, 2, 4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 },
                                       { 2, 2, -4 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 } }; /* through an edge */
    static const int64_t ee_par[8][3] = { { 0, 0, 0 }, { 2, 0, 0 }, { 3, 1, 0 }, { 5, 1, 0 },
                                      { 0, 0, 0 }, { 2, 0, 0 }, { 3, -1, 0 }, { 5, -1, 0 } }; /* parallel, never overlapping */
    static const int64_t ee_col[8][3] = { { 0, 0, 0 }, { 2, 0, 0 }, { 1, 3, 0 }, { 3, 3, 0 },
                                      { 0, 0, 0 }, { 2, 0, 0 }, { 1, -1, 0 }, { 3, -1, 0 } }; /* collinear overlap at t = 3/4 */
    /* a vertex that reaches the plane inside the triangle at t = 1/3 (a root that is not dyadic) */
    static const int64_t vf_third[8][3] = { { 1, 1, 1 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 },
                                        { 1, 1, -2 }, { 0, 0, 0 }, { 4, 0, 0 }, { 0, 4, 0 } };
    oracle *o = &the_oracle;
    apt e, ref;
    oracle_failed = 0;
    ref.exact = 1; ref.f = 0;
    ENSURE(oracle_collide(o, 0, vf_hit, &e));
    ref.lo = ref.hi = dy_make(bi_small(1), 1);
    ENSURE(apt_cmp(o, &e, &ref) == 0);
    ENSURE(!oracle_collide(o, 0, vf_miss, &e));
    ENSURE(oracle_collide(o, 0, vf_edge, &e));
    ENSURE(!oracle_collide(o, 1, ee_par, &e));
    ENSURE(oracle_collide(o, 1, ee_col, &e));
    ref.lo = ref.hi = dy_make(bi_small(3), 2);
    ENSURE(apt_cmp(o, &e, &ref) == 0);
    ENSURE(oracle_collide(o, 0, vf_third, &e));
    ENSURE(!e.exact);
    ref.lo = ref.hi = dy_make(bi_small(5461), 14); /* 0.33331... < 1/3 */
    ENSURE(apt_cmp(o, &e, &ref) > 0);
    ref.lo = ref.hi = dy_make(bi_small(5462), 14); /* 0.33337... > 1/3 */
    ENSURE(apt_cmp(o, &e, &ref) < 0);
    ENSURE(!oracle_failed);
    {   /* the certifier of separation: the miss passes 1.41 away (at least 1 on some axis) */
        double x[8][3];
        int i, k;
        for (i = 0; i < 8; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = (double)vf_miss[i][k];
        ENSURE(certify_apart(0, (const double (*)[3])x, 0.9));
        ENSURE(!certify_apart(0, (const double (*)[3])x, 1.1));
        for (i = 0; i < 8; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = (double)vf_hit[i][k];
        ENSURE(!certify_apart(0, (const double (*)[3])x, 1e-6));
        for (i = 0; i < 8; ++i)
            for (k = 0; k < 3; ++k) x[i][k] = (double)ee_par[i][k];
        ENSURE(certify_apart(1, (const double (*)[3])x, 0.9)); /* 1 apart along x, always */
    }
}

/* The oracle against the sample's own exact ground truth, on its hand-built degenerate
   "unit-tests" scene: every coordinate there is a dyadic rational, so a query scaled by a
   power of two has integer coordinates; those that fit the oracle's arithmetic are decided
   and must agree with the sample's answer. */
TEST(ccd_exact_oracle_matches_sample)
{
    static const char *const files[] = { "vertex-face/data_0_0.csv", "vertex-face/data_0_1.csv",
                                         "edge-edge/data_0_0.csv", "edge-edge/data_0_1.csv" };
    oracle *o = &the_oracle;
    int decided = 0, skipped = 0, positives = 0;
    size_t fi;
    for (fi = 0; fi < sizeof files / sizeof files[0]; ++fi) {
        char path[1024], line[512];
        FILE *f;
        int64_t num[8][3];
        int ex[8][3], row = 0, truth = 0, edge_edge = fi >= 2;
        snprintf(path, sizeof path, "%s/tests/data/ccd-sample/unit-tests/%s", test_root(), files[fi]);
        f = fopen(path, "r");
        if (!f) printf("    ccd sample: cannot read %s (the sample is tests/data/ccd-sample in the repository)\n", path);
        ENSURE(f != NULL);
        while (fgets(line, sizeof line, f)) {
            char *s = line;
            int k, ok = 1;
            for (k = 0; k < 3; ++k) {
                double den;
                num[row][k] = strtoll(s, &s, 10);
                if (*s == ',') ++s;
                den = strtod(s, &s);
                if (*s == ',') ++s;
                if (!(den >= 1) || frexp(den, &ex[row][k]) != 0.5) ok = 0; /* den = 2^(ex - 1) */
            }
            truth = atoi(s);
            ENSURE(ok);
            if (++row == 8) {
                int64_t x[8][3];
                int emax = 0, i, fits = 1, collide;
                apt first;
                for (i = 0; i < 8; ++i)
                    for (k = 0; k < 3; ++k) if (ex[i][k] > emax) emax = ex[i][k];
                for (i = 0; i < 8; ++i)
                    for (k = 0; k < 3; ++k) {
                        int sh = emax - ex[i][k];
                        int64_t a = num[i][k] < 0 ? -num[i][k] : num[i][k];
                        if (sh > 60 || a > (((int64_t)1 << 60) >> sh)) fits = 0;
                        else x[i][k] = num[i][k] * ((int64_t)1 << sh);
                    }
                row = 0;
                if (!fits) { ++skipped; continue; }
                oracle_failed = 0;
                collide = oracle_collide(o, edge_edge, (const int64_t (*)[3])x, &first);
                if (oracle_failed) { ++skipped; continue; } /* beyond the oracle's fixed-size numbers */
                ++decided;
                positives += truth;
                if (collide != truth) printf("    %s query %d: oracle %d, ground truth %d\n", files[fi], decided + skipped, collide, truth);
                ENSURE(collide == truth);
            }
        }
        fclose(f);
    }
    oracle_failed = 0;
    printf("    exact oracle on the sample's unit tests: %d queries agree with the ground truth (%d positive), "
           "%d beyond its number size\n", decided, positives, skipped);
    ENSURE(decided >= 100 && positives >= 30);
}

/* ===================================================================================== */
/* Exactly touching queries in full floating point                                       */
/* ===================================================================================== */

static double rnd_double(cloth_rng *g, int mant_bits, int exp_lo, int exp_hi)
{
    uint64_t m = (cloth_rng_next(g) >> (64 - mant_bits)) | ((uint64_t)1 << (mant_bits - 1));
    double v = ldexp((double)m, rnd_int(g, exp_lo, exp_hi) - mant_bits);
    if (rnd_int(g, 0, 15) == 0) return 0;
    return (cloth_rng_next(g) & 1) ? -v : v;
}

/* x0 + t (x1 - x0) exactly */
static dy dy_lerp(double x0, double x1, const dy *t)
{
    dy a = dy_from_double(x0), b = dy_from_double(x1), d = dy_sub(&b, &a), m = dy_mul(t, &d);
    return dy_add(&a, &m);
}

/* F(t,u,v) of a query given in cloth_real, exactly. */
static void exact_f(int edge_edge, const cloth_real v[8][3], double t, double u, double w, dy f[3])
{
    dy dt = dy_from_double(t), du = dy_from_double(u), dv = dy_from_double(w);
    int k;
    for (k = 0; k < 3; ++k) {
        dy y[4], a, b;
        int j;
        for (j = 0; j < 4; ++j) y[j] = dy_lerp((double)v[j][k], (double)v[4 + j][k], &dt);
        if (edge_edge) {
            a = dy_sub(&y[1], &y[0]); a = dy_mul(&du, &a); a = dy_add(&y[0], &a);
            b = dy_sub(&y[3], &y[2]); b = dy_mul(&dv, &b); b = dy_add(&y[2], &b);
            f[k] = dy_sub(&a, &b);
        } else {
            f[k] = dy_sub(&y[0], &y[1]);
            a = dy_sub(&y[2], &y[1]); a = dy_mul(&du, &a); f[k] = dy_sub(&f[k], &a);
            b = dy_sub(&y[3], &y[1]); b = dy_mul(&dv, &b); f[k] = dy_sub(&f[k], &b);
        }
    }
}

/* Is max_k |F_k(t,u,v)| <= bound, exactly? (bound 0: do the primitives touch there?) */
static int exact_within(int edge_edge, const cloth_real v[8][3], double t, double u, double w, double bound)
{
    dy f[3], b = dy_from_double(bound), nb = dy_from_double(-bound);
    int k;
    exact_f(edge_edge, v, t, u, w, f);
    for (k = 0; k < 3; ++k)
        if (dy_cmp(&f[k], &b) > 0 || dy_cmp(&f[k], &nb) < 0) return 0;
    return 1;
}

/* Queries built to touch exactly (d = 0) at a vertex, on an edge or inside, at t = 0, 1 or in
   between, with coordinates of many magnitudes and long mantissas: the grazing contacts that
   floating-point rounding would lose. Each is checked exact with rational arithmetic first.
   Then the same queries pushed apart by exactly the minimum separation. */
TEST(ccd_exact_touching)
{
    static const double ts[] = { 0, 1, 0.5, 0.25, 0.125, 0.0625 };
    static const double us[] = { 0, 1, 0.5, 0.25, 0.375, 0.625, 0.75 };
    static const double vs[] = { 0, 1, 0.5, 0.25, 0.125 };
    cloth_rng g = cloth_rng_make(33);
    int it, kind, exact_count[2] = { 0, 0 }, separated_count[2] = { 0, 0 };
    int flt = sizeof(cloth_real) == sizeof(float), mant = flt ? 10 : 26;
    oracle_failed = 0;
    for (kind = 0; kind < 2; ++kind)
        for (it = 0; it < 1500; ++it) {
            int scale_exp = flt ? 10 * rnd_int(&g, -1, 1) : 20 * rnd_int(&g, -1, 1), i, k;
            double x[8][3], t = ts[rnd_int(&g, 0, 5)], u = us[rnd_int(&g, 0, 6)], v = vs[rnd_int(&g, 0, 4)];
            cloth_real cv[8][3];
            cloth_ccd_report r;
            for (i = 0; i < 8; ++i)
                for (k = 0; k < 3; ++k) x[i][k] = rnd_double(&g, mant, scale_exp - 3, scale_exp + 1);
            /* contact at t = 1 only involves the end positions: the start positions then take
               full-length mantissas, so that x0 + 1 * (x1 - x0) rounds away from x1 and the
               corner values at the contact are off zero by rounding */
            if (t == 1)
                for (i = 0; i < 4; ++i)
                    for (k = 0; k < 3; ++k) x[i][k] = rnd_double(&g, flt ? 24 : 53, scale_exp - 3, scale_exp + 1);
            if (!kind && u + v > 1) { u = 1 - v; }
            for (k = 0; k < 3; ++k) {
                double y[4], target;
                int j, free_vertex = kind ? 3 : 0;
                for (j = 0; j < 4; ++j) y[j] = x[j][k] + t * (x[4 + j][k] - x[j][k]);
                if (!kind) target = y[1] + u * (y[2] - y[1]) + v * (y[3] - y[1]); /* the face point */
                else if (v == 0) { free_vertex = 2; target = y[0] + u * (y[1] - y[0]); } /* b0 on a */
                else {                                                               /* b1 from b0 through the point on a */
                    double pa = y[0] + u * (y[1] - y[0]);
                    target = y[2] + (pa - y[2]) / v;
                }
                /* move the free vertex so that it is at target at time t */
                if (t == 0) x[free_vertex][k] = target;
                else x[4 + free_vertex][k] = x[free_vertex][k] + (target - x[free_vertex][k]) / t;
            }
            for (i = 0; i < 8; ++i)
                for (k = 0; k < 3; ++k) cv[i][k] = (cloth_real)x[i][k];
            if (!exact_within(kind, (const cloth_real (*)[3])cv, t, u, v, 0)) continue;
            ++exact_count[kind];
            if (kind) ENSURE(cloth_ccd_edge_edge(cv[0], cv[1], cv[2], cv[3], cv[4], cv[5], cv[6], cv[7], NULL, &r) == CLOTH_SUCCESS);
            else ENSURE(cloth_ccd_vertex_face(cv[0], cv[1], cv[2], cv[3], cv[4], cv[5], cv[6], cv[7], NULL, &r) == CLOTH_SUCCESS);
            if (!r.may_collide || !(r.toi <= t)) {
                printf("    %s touching query %d (t %g, u %g, v %g): may_collide %d, toi %.17g\n",
                       kind ? "edge-edge" : "vertex-face", it, t, u, v, r.may_collide, (double)r.toi);
                ENSURE(0);
            }
            /* The same pair pushed apart by a constant w with max |w_k| = D (the vertex p, or
               the whole edge b, moved by w at both times): F becomes F + w or F - w, so max |F_k|
               is exactly D at the contact, and with minimum separation D it must be reported. */
            {
                double dsep = ldexp(1.0, scale_exp - 4 - rnd_int(&g, 0, 12)), w[3];
                int axis = rnd_int(&g, 0, 2), moved = kind ? 2 : 0, count = kind ? 2 : 1;
                cloth_ccd_options o = cloth_ccd_default_options();
                for (k = 0; k < 3; ++k) w[k] = (k == axis ? 1 : rnd_int(&g, 0, 8) / 8.0) * (rnd_int(&g, 0, 1) ? dsep : -dsep);
                for (i = 0; i < count; ++i)
                    for (k = 0; k < 3; ++k) {
                        cv[moved + i][k] = (cloth_real)(x[moved + i][k] + w[k]);
                        cv[4 + moved + i][k] = (cloth_real)(x[4 + moved + i][k] + w[k]);
                    }
                if (!exact_within(kind, (const cloth_real (*)[3])cv, t, u, v, dsep)) continue;
                ++separated_count[kind];
                o.minimum_separation = (cloth_real)dsep;
                o.max_checks = 100000; /* some of these are slow to tighten; toi must stay safe anyway */
                o.refine_checks = 6250;
                if (kind) ENSURE(cloth_ccd_edge_edge(cv[0], cv[1], cv[2], cv[3], cv[4], cv[5], cv[6], cv[7], &o, &r) == CLOTH_SUCCESS);
                else ENSURE(cloth_ccd_vertex_face(cv[0], cv[1], cv[2], cv[3], cv[4], cv[5], cv[6], cv[7], &o, &r) == CLOTH_SUCCESS);
                if (!r.may_collide || !(r.toi <= t)) {
                    printf("    %s query %d pushed apart by %g (t %g, u %g, v %g): may_collide %d, toi %.17g\n",
                           kind ? "edge-edge" : "vertex-face", it, dsep, t, u, v, r.may_collide, (double)r.toi);
                    ENSURE(0);
                }
            }
        }
    ENSURE(!oracle_failed);
    printf("    exactly touching: %d vertex-face, %d edge-edge queries, all reported; pushed apart by exactly the "
           "minimum separation: %d and %d, all reported\n", exact_count[0], exact_count[1], separated_count[0], separated_count[1]);
    ENSURE(exact_count[0] >= 750 && exact_count[1] >= 750);
    ENSURE(separated_count[0] >= 500 && separated_count[1] >= 500);
}

const test_case ccd_tests[] = {
    { "distance_vertex_face_regions", distance_vertex_face_regions },
    { "distance_vertex_face_degenerate", distance_vertex_face_degenerate },
    { "distance_vertex_face_sampled", distance_vertex_face_sampled },
    { "distance_edge_edge_cases", distance_edge_edge_cases },
    { "distance_edge_edge_sampled", distance_edge_edge_sampled },
    { "distance_scale_and_bad_input", distance_scale_and_bad_input },
    { "ccd_default_options", ccd_default_options },
    { "ccd_vertex_face_hit_and_miss", ccd_vertex_face_hit_and_miss },
    { "ccd_vertex_face_grazing", ccd_vertex_face_grazing },
    { "ccd_edge_edge_cases", ccd_edge_edge_cases },
    { "ccd_minimum_separation", ccd_minimum_separation },
    { "ccd_bad_input_and_budget", ccd_bad_input_and_budget },
    { "ccd_sample_vertex_face", ccd_sample_vertex_face },
    { "ccd_sample_edge_edge", ccd_sample_edge_edge },
    { "ccd_exact_oracle_known_cases", ccd_exact_oracle_known_cases },
    { "ccd_exact_oracle_matches_sample", ccd_exact_oracle_matches_sample },
    { "ccd_exact_oracle_vertex_face", ccd_exact_oracle_vertex_face },
    { "ccd_exact_oracle_edge_edge", ccd_exact_oracle_edge_edge },
    { "ccd_exact_touching", ccd_exact_touching },
    { NULL, NULL }
};
