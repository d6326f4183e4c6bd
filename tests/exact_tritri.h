/* exact_tritri.h - an exact triangle-triangle intersection check for cloth meshes, written apart
   from cloth.h's collision code (it uses nothing of cloth.h), for tests/ and bench/.

   All functions are static; include the header in any C99 translation unit.

       int exact_tri_tri_intersect(a0, a1, a2, b0, b1, b2)
           1 when the closed triangles a0a1a2 and b0b1b2 share at least one point, else 0.
           Degenerate triangles (collinear or coincident vertices) are allowed: a degenerate
           triangle is the segment (or point) that is its convex hull.
       long exact_count_intersecting_pairs(meshes, mesh_count, counts)
           the number of intersecting triangle pairs among one or more meshes (broad phase: a
           uniform grid of cells), see below.

   METHOD. Two closed convex sets A, B that meet have an extreme point p of A n B; p lies on the
   relative boundary of A or of B (an interior point of both would have a neighbourhood, in the
   common line or plane of the two triangles, inside A n B). So the triangles meet exactly when
   one of the 3 + 3 edges of one meets the other triangle (a degenerate triangle is the union
   of its edges, so this holds for it too). Segment pq against triangle abc:
     - abc not degenerate, p and q not both in its plane: the segment reaches the plane iff
       orient3d(a,b,c,p) and orient3d(a,b,c,q) do not have the same strict sign; then the line
       pq pierces the closed triangle iff orient3d(p,q,a,b), orient3d(p,q,b,c),
       orient3d(p,q,c,a) are all >= 0 or all <= 0 (not all 0: the line is not in the plane).
     - everything in one plane: two convex sets in a common plane P meet iff their projections
       along each coordinate axis meet (disjoint sets have a separating line L in P; the plane
       through L containing the axis e_k separates them strictly whenever e_k is not parallel
       to P, and some axis is not), so the 2D test runs in all three coordinate projections.
       2D: an endpoint inside the (non-degenerate) triangle by orient2d signs, or the segment
       meets one of the three edges (closed segment-segment test with the collinear cases).
     - abc degenerate: the segment against each of its three edges; segment-segment in 3D is
       orient3d(p,q,r,s) == 0 and the coplanar test above.
   Every decision is the sign of an orient3d or orient2d determinant or a comparison of input
   coordinates, so the answer is exact when those signs are.

   EXACTNESS. orient3d and orient2d first evaluate the determinant in doubles with Shewchuk's
   proven error bounds ("Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
   Predicates", 1997: orient3d (7 + 56 eps) eps * permanent, orient2d (3 + 16 eps) eps); when the
   sign is not certain they evaluate it exactly with floating-point expansions (two-sum,
   Veltkamp-Dekker two-product, expansion sum and scaling with zero elimination, written here
   after that paper). Both rely on IEEE double arithmetic rounding to nearest-even, no extended
   precision (FLT_EVAL_METHOD 0) and no fused multiply-add contraction (compile with
   -ffp-contract=off; gcc in -std=c99 mode does not contract by default), and on no overflow or
   underflow: every input coordinate must be 0 or of magnitude in [2^-250, 2^250]
   (exact_tritri_coordinate_ok; products of three coordinate differences then stay normal).

   PAIRS OF ONE MESH THAT SHARE VERTICES. Adjacent triangles meet by construction, so
   exact_count_intersecting_pairs decides, exactly, whether they meet anywhere else:
     - one shared vertex v, A = v a1 a2, B = v b1 b2 (both non-degenerate): A n B is convex and
       contains v; it holds another point iff the two wedges at v share a direction d; the ray
       v + t d leaves A through segment a1a2 and B through b1b2, and whichever it leaves first
       lies in the other triangle. So: segment a1a2 meets B, or segment b1b2 meets A (neither
       contains v). Counted as intersecting when so.
     - a shared edge uv, A = u v a, B = u v b: the planes meet in line uv unless the four points
       are coplanar; then A and B overlap beyond uv iff a and b lie on the same side of uv
       (a fold flattened onto itself). Counted as intersecting when so.
     - identical triangles (three shared vertices) and pairs involving a degenerate triangle
       that shares a vertex are skipped (not counted).
   Vertices are "shared" only by index within one mesh; triangles of different meshes are
   always tested in full. */
#ifndef EXACT_TRITRI_H
#define EXACT_TRITRI_H
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if defined(FLT_EVAL_METHOD) && FLT_EVAL_METHOD != 0
#error "exact_tritri.h needs double arithmetic without extended precision (FLT_EVAL_METHOD 0)"
#endif
#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* ---- expansion arithmetic (Shewchuk 1997) ----------------------------------------------- */

#define EXACT__EPS (1.0 / 9007199254740992.0) /* 2^-53 */
#define EXACT__SPLITTER 134217729.0          /* 2^27 + 1 */

static void exact__two_sum(double a, double b, double *x, double *y)
{
    double s = a + b, bv = s - a, av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

static void exact__fast_two_sum(double a, double b, double *x, double *y) /* |a| >= |b| or a == 0 */
{
    double s = a + b;
    *x = s;
    *y = b - (s - a);
}

static void exact__two_diff(double a, double b, double *x, double *y)
{
    double s = a - b, bv = a - s, av = s + bv;
    *x = s;
    *y = (a - av) + (bv - b);
}

static void exact__split(double a, double *hi, double *lo)
{
    double c = EXACT__SPLITTER * a, big = c - a;
    *hi = c - big;
    *lo = a - *hi;
}

static void exact__two_product(double a, double b, double *x, double *y)
{
    double p = a * b, ahi, alo, bhi, blo, e1, e2, e3;
    exact__split(a, &ahi, &alo);
    exact__split(b, &bhi, &blo);
    e1 = p - ahi * bhi;
    e2 = e1 - alo * bhi;
    e3 = e2 - ahi * blo;
    *x = p;
    *y = alo * blo - e3;
}

/* h = e + f (nonoverlapping expansions, increasing magnitude, zeros removed); h may hold
   elen + flen components and must not alias e or f. Returns the length (>= 1). */
static int exact__expansion_sum(int elen, const double *e, int flen, const double *f, double *h)
{
    double q, qnew, hh, enow = e[0], fnow = f[0];
    int ei = 0, fi = 0, hi = 0;
    if ((fnow > enow) == (fnow > -enow)) { q = enow; if (++ei < elen) enow = e[ei]; }
    else { q = fnow; if (++fi < flen) fnow = f[fi]; }
    if (ei < elen && fi < flen) {
        if ((fnow > enow) == (fnow > -enow)) { exact__fast_two_sum(enow, q, &qnew, &hh); if (++ei < elen) enow = e[ei]; }
        else { exact__fast_two_sum(fnow, q, &qnew, &hh); if (++fi < flen) fnow = f[fi]; }
        q = qnew;
        if (hh != 0) h[hi++] = hh;
        while (ei < elen && fi < flen) {
            if ((fnow > enow) == (fnow > -enow)) { exact__two_sum(q, enow, &qnew, &hh); if (++ei < elen) enow = e[ei]; }
            else { exact__two_sum(q, fnow, &qnew, &hh); if (++fi < flen) fnow = f[fi]; }
            q = qnew;
            if (hh != 0) h[hi++] = hh;
        }
    }
    while (ei < elen) {
        exact__two_sum(q, enow, &qnew, &hh);
        if (++ei < elen) enow = e[ei];
        q = qnew;
        if (hh != 0) h[hi++] = hh;
    }
    while (fi < flen) {
        exact__two_sum(q, fnow, &qnew, &hh);
        if (++fi < flen) fnow = f[fi];
        q = qnew;
        if (hh != 0) h[hi++] = hh;
    }
    if (q != 0 || hi == 0) h[hi++] = q;
    return hi;
}

/* h = b e; h may hold 2 elen components. Returns the length (>= 1). */
static int exact__scale(int elen, const double *e, double b, double *h)
{
    double q, hh, p1, p0, sum;
    int i, hi = 0;
    exact__two_product(e[0], b, &q, &hh);
    if (hh != 0) h[hi++] = hh;
    for (i = 1; i < elen; ++i) {
        exact__two_product(e[i], b, &p1, &p0);
        exact__two_sum(q, p0, &sum, &hh);
        if (hh != 0) h[hi++] = hh;
        exact__fast_two_sum(p1, sum, &q, &hh);
        if (hh != 0) h[hi++] = hh;
    }
    if (q != 0 || hi == 0) h[hi++] = q;
    return hi;
}

/* h = e f with flen <= 2 and elen <= 16; h may hold 2 elen flen components. */
static int exact__product(int elen, const double *e, int flen, const double *f, double *h)
{
    double t0[32], t1[32];
    int n0 = exact__scale(elen, e, f[0], t0), n1;
    if (flen == 1) { memcpy(h, t0, (size_t)n0 * sizeof(double)); return n0; }
    n1 = exact__scale(elen, e, f[1], t1);
    return exact__expansion_sum(n0, t0, n1, t1, h);
}

/* a - b as an expansion of 1 or 2 components; returns the length. */
static int exact__diff(double a, double b, double *h)
{
    double x, y;
    exact__two_diff(a, b, &x, &y);
    if (y == 0) { h[0] = x; return 1; }
    h[0] = y;
    h[1] = x;
    return 2;
}

static int exact__sign_of(int n, const double *e) { return e[n - 1] > 0 ? 1 : e[n - 1] < 0 ? -1 : 0; }

static void exact__negate(int n, double *e)
{
    int i;
    for (i = 0; i < n; ++i) e[i] = -e[i];
}

/* Sign of (u1 v2 - u2 v1) w for 2-component-or-less expansions; result in h (<= 64). */
static int exact__minor(const double *u1, int nu1, const double *v2, int nv2, const double *u2, int nu2,
                        const double *v1, int nv1, const double *w, int nw, double *h)
{
    double p[8], q[8], d[16];
    int np = exact__product(nu1, u1, nv2, v2, p), nq = exact__product(nu2, u2, nv1, v1, q), nd;
    exact__negate(nq, q);
    nd = exact__expansion_sum(np, p, nq, q, d);
    return exact__product(nd, d, nw, w, h);
}

/* ---- predicates ------------------------------------------------------------------------- */

/* Sign of the determinant |a-d; b-d; c-d| (Shewchuk's orient3d: +1 when d lies below the plane
   of a, b, c seen counter-clockwise from above), exactly. */
static int exact_orient3d(const double *pa, const double *pb, const double *pc, const double *pd)
{
    double adx = pa[0] - pd[0], bdx = pb[0] - pd[0], cdx = pc[0] - pd[0];
    double ady = pa[1] - pd[1], bdy = pb[1] - pd[1], cdy = pc[1] - pd[1];
    double adz = pa[2] - pd[2], bdz = pb[2] - pd[2], cdz = pc[2] - pd[2];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy, cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    double permanent = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) + (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                       (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
    double bound = (7.0 + 56.0 * EXACT__EPS) * EXACT__EPS * permanent;
    double fx[3][2], ey[3][2], ez[3][2], t[3][64], s[128], r[192];
    int nx[3], ny[3], nz[3], nt[3], ns, nr, i;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    for (i = 0; i < 3; ++i) {
        const double *p = i == 0 ? pa : i == 1 ? pb : pc;
        nx[i] = exact__diff(p[0], pd[0], fx[i]);
        ny[i] = exact__diff(p[1], pd[1], ey[i]);
        nz[i] = exact__diff(p[2], pd[2], ez[i]);
    }
    /* adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady) */
    nt[0] = exact__minor(fx[1], nx[1], ey[2], ny[2], fx[2], nx[2], ey[1], ny[1], ez[0], nz[0], t[0]);
    nt[1] = exact__minor(fx[2], nx[2], ey[0], ny[0], fx[0], nx[0], ey[2], ny[2], ez[1], nz[1], t[1]);
    nt[2] = exact__minor(fx[0], nx[0], ey[1], ny[1], fx[1], nx[1], ey[0], ny[0], ez[2], nz[2], t[2]);
    ns = exact__expansion_sum(nt[0], t[0], nt[1], t[1], s);
    nr = exact__expansion_sum(ns, s, nt[2], t[2], r);
    return exact__sign_of(nr, r);
}

/* Sign of (a-c) x (b-c) for the 2D points (a[i], a[j]), ...: +1 counter-clockwise, exactly. */
static int exact_orient2d(const double *pa, const double *pb, const double *pc, int i, int j)
{
    double detleft = (pa[i] - pc[i]) * (pb[j] - pc[j]), detright = (pa[j] - pc[j]) * (pb[i] - pc[i]);
    double det = detleft - detright, bound = (3.0 + 16.0 * EXACT__EPS) * EXACT__EPS * (fabs(detleft) + fabs(detright));
    double acx[2], bcy[2], acy[2], bcx[2], p[8], q[8], d[16];
    int n1, n2, n3, n4, np, nq, nd;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    n1 = exact__diff(pa[i], pc[i], acx);
    n2 = exact__diff(pb[j], pc[j], bcy);
    n3 = exact__diff(pa[j], pc[j], acy);
    n4 = exact__diff(pb[i], pc[i], bcx);
    np = exact__product(n1, acx, n2, bcy, p);
    nq = exact__product(n3, acy, n4, bcx, q);
    exact__negate(nq, q);
    nd = exact__expansion_sum(np, p, nq, q, d);
    return exact__sign_of(nd, d);
}

/* 1 when x is 0 or |x| is in [2^-250, 2^250] (the range where the predicates are exact). */
static int exact_tritri_coordinate_ok(double x)
{
    double m = fabs(x); /* ldexp rather than 0x1p-250: hexadecimal floats are not C++11 */
    return x == 0 || (m >= ldexp(1.0, -250) && m <= ldexp(1.0, 250));
}

/* ---- the intersection test -------------------------------------------------------------- */

/* 2D, coordinates (i, j): r lies on the closed segment pq, given that the three are collinear. */
static int exact__on_segment_2d(const double *p, const double *q, const double *r, int i, int j)
{
    return (p[i] <= q[i] ? (p[i] <= r[i] && r[i] <= q[i]) : (q[i] <= r[i] && r[i] <= p[i])) &&
           (p[j] <= q[j] ? (p[j] <= r[j] && r[j] <= q[j]) : (q[j] <= r[j] && r[j] <= p[j]));
}

/* 2D closed segments pq and rs meet (degenerate segments allowed). */
static int exact__seg_seg_2d(const double *p, const double *q, const double *r, const double *s, int i, int j)
{
    int o1 = exact_orient2d(p, q, r, i, j), o2 = exact_orient2d(p, q, s, i, j);
    int o3 = exact_orient2d(r, s, p, i, j), o4 = exact_orient2d(r, s, q, i, j);
    if (o1 * o2 < 0 && o3 * o4 < 0) return 1;
    if (o1 == 0 && exact__on_segment_2d(p, q, r, i, j)) return 1;
    if (o2 == 0 && exact__on_segment_2d(p, q, s, i, j)) return 1;
    if (o3 == 0 && exact__on_segment_2d(r, s, p, i, j)) return 1;
    if (o4 == 0 && exact__on_segment_2d(r, s, q, i, j)) return 1;
    return 0;
}

/* 2D point p in the closed triangle abc of orientation o != 0. */
static int exact__point_in_tri_2d(const double *p, const double *a, const double *b, const double *c, int o, int i, int j)
{
    return exact_orient2d(a, b, p, i, j) * o >= 0 && exact_orient2d(b, c, p, i, j) * o >= 0 &&
           exact_orient2d(c, a, p, i, j) * o >= 0;
}

/* 2D closed segment pq against closed triangle abc (possibly degenerate). */
static int exact__seg_tri_2d(const double *p, const double *q, const double *a, const double *b, const double *c, int i, int j)
{
    int o = exact_orient2d(a, b, c, i, j);
    if (o != 0 && (exact__point_in_tri_2d(p, a, b, c, o, i, j) || exact__point_in_tri_2d(q, a, b, c, o, i, j))) return 1;
    return exact__seg_seg_2d(p, q, a, b, i, j) || exact__seg_seg_2d(p, q, b, c, i, j) || exact__seg_seg_2d(p, q, c, a, i, j);
}

/* 3D closed segments pq and rs meet. */
static int exact__seg_seg_3d(const double *p, const double *q, const double *r, const double *s)
{
    int k;
    if (exact_orient3d(p, q, r, s) != 0) return 0;
    for (k = 0; k < 3; ++k)
        if (!exact__seg_seg_2d(p, q, r, s, (k + 1) % 3, (k + 2) % 3)) return 0;
    return 1;
}

/* The triangle abc is degenerate (its three vertices collinear or coincident). */
static int exact__tri_degenerate(const double *a, const double *b, const double *c)
{
    return exact_orient2d(a, b, c, 1, 2) == 0 && exact_orient2d(a, b, c, 2, 0) == 0 && exact_orient2d(a, b, c, 0, 1) == 0;
}

/* 3D closed segment pq against closed triangle abc (both possibly degenerate). */
static int exact__seg_tri_3d(const double *p, const double *q, const double *a, const double *b, const double *c)
{
    int sp = exact_orient3d(a, b, c, p), sq = exact_orient3d(a, b, c, q), s1, s2, s3, k;
    if (sp * sq > 0) return 0;
    if (sp == 0 && sq == 0) {
        if (exact__tri_degenerate(a, b, c))
            return exact__seg_seg_3d(p, q, a, b) || exact__seg_seg_3d(p, q, b, c) || exact__seg_seg_3d(p, q, c, a);
        for (k = 0; k < 3; ++k)
            if (!exact__seg_tri_2d(p, q, a, b, c, (k + 1) % 3, (k + 2) % 3)) return 0;
        return 1;
    }
    /* abc is not degenerate here (a degenerate one gives sp == sq == 0) and the line pq is not
       in its plane. */
    s1 = exact_orient3d(p, q, a, b);
    s2 = exact_orient3d(p, q, b, c);
    s3 = exact_orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/* 1 when the closed triangles a0a1a2 and b0b1b2 share at least one point, exactly. */
static int exact_tri_tri_intersect(const double a0[3], const double a1[3], const double a2[3], const double b0[3],
                                   const double b1[3], const double b2[3])
{
    int k, s0, s1, s2;
    for (k = 0; k < 3; ++k) { /* bounding boxes (exact comparisons) */
        double amin = fmin(a0[k], fmin(a1[k], a2[k])), amax = fmax(a0[k], fmax(a1[k], a2[k]));
        double bmin = fmin(b0[k], fmin(b1[k], b2[k])), bmax = fmax(b0[k], fmax(b1[k], b2[k]));
        if (amax < bmin || bmax < amin) return 0;
    }
    /* all of B strictly on one side of A's plane, or all of A of B's (exact early outs) */
    s0 = exact_orient3d(a0, a1, a2, b0);
    s1 = exact_orient3d(a0, a1, a2, b1);
    s2 = exact_orient3d(a0, a1, a2, b2);
    if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) return 0;
    s0 = exact_orient3d(b0, b1, b2, a0);
    s1 = exact_orient3d(b0, b1, b2, a1);
    s2 = exact_orient3d(b0, b1, b2, a2);
    if ((s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0)) return 0;
    return exact__seg_tri_3d(a0, a1, b0, b1, b2) || exact__seg_tri_3d(a1, a2, b0, b1, b2) ||
           exact__seg_tri_3d(a2, a0, b0, b1, b2) || exact__seg_tri_3d(b0, b1, a0, a1, a2) ||
           exact__seg_tri_3d(b1, b2, a0, a1, a2) || exact__seg_tri_3d(b2, b0, a0, a1, a2);
}

/* Triangles v a1 a2 and v b1 b2 (non-degenerate) share a point other than v. */
static int exact_tri_tri_intersect_beyond_vertex(const double v[3], const double a1[3], const double a2[3],
                                                 const double b1[3], const double b2[3])
{
    return exact__seg_tri_3d(a1, a2, v, b1, b2) || exact__seg_tri_3d(b1, b2, v, a1, a2);
}

/* Triangles u v a and u v b (non-degenerate) share a point off the segment uv. */
static int exact_tri_tri_intersect_beyond_edge(const double u[3], const double v[3], const double a[3], const double b[3])
{
    int k;
    if (exact_orient3d(u, v, a, b) != 0) return 0;
    for (k = 0; k < 3; ++k) {
        int i = (k + 1) % 3, j = (k + 2) % 3, oa = exact_orient2d(u, v, a, i, j);
        if (oa != 0) return oa == exact_orient2d(u, v, b, i, j);
    }
    return 0; /* not reached for a non-degenerate u v a */
}

/* ---- counting intersecting pairs of meshes ----------------------------------------------- */

typedef struct exact_mesh {
    const double *x;         /* 3 per vertex */
    const int32_t *tri;      /* 3 per triangle */
    int32_t triangle_count;
    int self;                /* test the mesh's triangles against each other (0 for a rigid obstacle) */
} exact_mesh;

typedef struct exact__entry { uint64_t key; int32_t mesh, tri; } exact__entry;

static int exact__entry_cmp(const void *pa, const void *pb)
{
    const exact__entry *a = (const exact__entry *)pa, *b = (const exact__entry *)pb;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    if (a->mesh != b->mesh) return a->mesh < b->mesh ? -1 : 1;
    return a->tri < b->tri ? -1 : a->tri > b->tri;
}

/* The pair (mesh ma, triangle ta), (mesh mb, triangle tb) intersects (see the top for pairs
   that share vertices). */
static int exact__pair_intersects(const exact_mesh *meshes, int32_t ma, int32_t ta, int32_t mb, int32_t tb)
{
    const int32_t *A = meshes[ma].tri + 3 * ta, *B = meshes[mb].tri + 3 * tb;
    const double *xa = meshes[ma].x, *xb = meshes[mb].x;
    int shared = 0, ia[3], ib[3], i, j;
    if (ma == mb)
        for (i = 0; i < 3; ++i)
            for (j = 0; j < 3; ++j)
                if (A[i] == B[j]) { ia[shared] = i; ib[shared] = j; ++shared; }
    if (shared == 0)
        return exact_tri_tri_intersect(xa + 3 * A[0], xa + 3 * A[1], xa + 3 * A[2], xb + 3 * B[0], xb + 3 * B[1], xb + 3 * B[2]);
    if (shared == 3) return 0;
    if (exact__tri_degenerate(xa + 3 * A[0], xa + 3 * A[1], xa + 3 * A[2]) ||
        exact__tri_degenerate(xb + 3 * B[0], xb + 3 * B[1], xb + 3 * B[2]))
        return 0;
    if (shared == 1)
        return exact_tri_tri_intersect_beyond_vertex(xa + 3 * A[ia[0]], xa + 3 * A[(ia[0] + 1) % 3], xa + 3 * A[(ia[0] + 2) % 3],
                                                     xb + 3 * B[(ib[0] + 1) % 3], xb + 3 * B[(ib[0] + 2) % 3]);
    return exact_tri_tri_intersect_beyond_edge(xa + 3 * A[ia[0]], xa + 3 * A[ia[1]], xa + 3 * A[3 - ia[0] - ia[1]],
                                               xb + 3 * B[3 - ib[0] - ib[1]]);
}

/* The number of intersecting pairs of triangles: pairs within a mesh with self set, and pairs
   between different meshes. counts, when not NULL, gets mesh_count * mesh_count entries:
   counts[a * mesh_count + b] (a <= b) the pairs between meshes a and b. Returns -1 when a
   coordinate is out of the exact range (exact_tritri_coordinate_ok) or not finite, -2 when
   memory runs out. Broad phase: a uniform grid of cubic cells of about the mean triangle box
   size, each triangle entered in every cell its box overlaps; a pair is tested in the one cell
   that holds the lower corner of the intersection of the two boxes (cell indices are a
   monotone function of a coordinate, so that cell is in both ranges). */
static long exact_count_intersecting_pairs(const exact_mesh *meshes, int mesh_count, long *counts)
{
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, size = 0, cell;
    double *box;
    exact__entry *entries;
    int64_t total_tris = 0, n_entries = 0, cap, e0, e1, ea, eb;
    int32_t *first;
    long found = 0;
    int m, k;
    if (counts) memset(counts, 0, (size_t)mesh_count * (size_t)mesh_count * sizeof(long));
    for (m = 0; m < mesh_count; ++m) total_tris += meshes[m].triangle_count;
    if (total_tris == 0) return 0;
    box = (double *)malloc((size_t)total_tris * 6 * sizeof(double));
    first = (int32_t *)malloc((size_t)(mesh_count + 1) * sizeof(int32_t));
    if (!box || !first) { free(box); free(first); return -2; }
    first[0] = 0;
    for (m = 0; m < mesh_count; ++m) {
        int32_t t;
        first[m + 1] = first[m] + meshes[m].triangle_count;
        for (t = 0; t < meshes[m].triangle_count; ++t) {
            double *b = box + 6 * (first[m] + t);
            for (k = 0; k < 3; ++k) {
                int c;
                b[k] = HUGE_VAL;
                b[3 + k] = -HUGE_VAL;
                for (c = 0; c < 3; ++c) {
                    double v = meshes[m].x[3 * meshes[m].tri[3 * t + c] + k];
                    if (!exact_tritri_coordinate_ok(v) || v != v) { free(box); free(first); return -1; }
                    if (v < b[k]) b[k] = v;
                    if (v > b[3 + k]) b[3 + k] = v;
                }
                if (b[k] < lo[k]) lo[k] = b[k];
                if (b[3 + k] > hi[k]) hi[k] = b[3 + k];
                size += b[3 + k] - b[k];
            }
        }
    }
    cell = 2 * size / (3.0 * (double)total_tris);
    for (k = 0; k < 3; ++k) /* at most 2^20 cells per axis */
        if ((hi[k] - lo[k]) / 1048575.0 > cell) cell = (hi[k] - lo[k]) / 1048575.0;
    if (!(cell > 0)) cell = 1;
    /* count, then fill the entries */
    cap = 0;
    for (e0 = 0; e0 < total_tris; ++e0) {
        const double *b = box + 6 * e0;
        int64_t c = 1;
        for (k = 0; k < 3; ++k) c *= (int64_t)floor((b[3 + k] - lo[k]) / cell) - (int64_t)floor((b[k] - lo[k]) / cell) + 1;
        cap += c;
    }
    entries = (exact__entry *)malloc((size_t)cap * sizeof(exact__entry));
    if (!entries) { free(box); free(first); return -2; }
    for (m = 0; m < mesh_count; ++m) {
        int32_t t;
        for (t = 0; t < meshes[m].triangle_count; ++t) {
            const double *b = box + 6 * (first[m] + t);
            uint64_t c0[3], c1[3], ix, iy, iz;
            for (k = 0; k < 3; ++k) {
                c0[k] = (uint64_t)floor((b[k] - lo[k]) / cell);
                c1[k] = (uint64_t)floor((b[3 + k] - lo[k]) / cell);
            }
            for (ix = c0[0]; ix <= c1[0]; ++ix)
                for (iy = c0[1]; iy <= c1[1]; ++iy)
                    for (iz = c0[2]; iz <= c1[2]; ++iz) {
                        exact__entry *en = entries + n_entries++;
                        en->key = (ix << 42) | (iy << 21) | iz;
                        en->mesh = m;
                        en->tri = t;
                    }
        }
    }
    qsort(entries, (size_t)n_entries, sizeof *entries, exact__entry_cmp);
    for (e0 = 0; e0 < n_entries; e0 = e1) {
        for (e1 = e0 + 1; e1 < n_entries && entries[e1].key == entries[e0].key; ++e1) {}
        for (ea = e0; ea < e1; ++ea)
            for (eb = ea + 1; eb < e1; ++eb) {
                const exact__entry *A = entries + ea, *B = entries + eb;
                const double *ba = box + 6 * (first[A->mesh] + A->tri), *bb = box + 6 * (first[B->mesh] + B->tri);
                uint64_t key;
                int overlap = 1;
                if (A->mesh == B->mesh && !meshes[A->mesh].self) continue;
                for (k = 0; k < 3; ++k)
                    if (ba[3 + k] < bb[k] || bb[3 + k] < ba[k]) overlap = 0;
                if (!overlap) continue;
                key = ((uint64_t)floor((fmax(ba[0], bb[0]) - lo[0]) / cell) << 42) |
                      ((uint64_t)floor((fmax(ba[1], bb[1]) - lo[1]) / cell) << 21) |
                      (uint64_t)floor((fmax(ba[2], bb[2]) - lo[2]) / cell);
                if (key != A->key) continue;
                if (exact__pair_intersects(meshes, A->mesh, A->tri, B->mesh, B->tri)) {
                    ++found;
                    if (counts) ++counts[A->mesh * mesh_count + B->mesh];
                }
            }
    }
    free(entries);
    free(box);
    free(first);
    return found;
}

#endif
