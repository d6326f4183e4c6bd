/* Tests of the contact module (the collide phase of a step): vertices against analytic
   obstacles with friction, the fast projectile, sheets pushed through sheets, a cloth folding
   onto itself, mesh obstacles, pins, unresolvable cases, determinism and allocation.

   The checks do not trust the library's geometry: the signed distances of the analytic
   shapes, the closest-point distances, the check that no vertex-face or edge-edge pair comes
   close along the straight paths x0 -> x1 (a Lipschitz bound on the distance, subdivided in
   time) and the triangle-triangle intersection test at x1 (separating axes) are written here. */
#include "runner.h"
#include "../cloth.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Tolerances of the checks: rounding of cloth_real (positions of order 1, velocities over h). */
#define IS_FLOAT (sizeof(cloth_real) == sizeof(float))
#define REL (IS_FLOAT ? 1e-2 : 1e-9)   /* relative, on thicknesses (float: normals from float
                                          positions tilt rows by ~1e-4 over cm-long slides) */
#define ABS (IS_FLOAT ? 1e-5 : 1e-9)   /* absolute, on velocities and small quantities */
#define VABS (IS_FLOAT ? 2e-4 : 1e-9)  /* velocities from float positions over a step of 1/60 s */

/* ===================================================================================== */
/* independent geometry                                                                  */
/* ===================================================================================== */

static double d3dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void d3sub(const double *a, const double *b, double *o) { o[0] = a[0] - b[0]; o[1] = a[1] - b[1]; o[2] = a[2] - b[2]; }
static void d3cross(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}
static double d3len(const double *a) { return sqrt(d3dot(a, a)); }
static double d3dist(const double *a, const double *b) { double d[3]; d3sub(a, b, d); return d3len(d); }
static double clamp01(double v) { return v < 0 ? 0 : (v > 1 ? 1 : v); }

/* Closest point of triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5). */
static double point_triangle(const double *p, const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3], d1, d2, d3, d4, d5, d6, va, vb, vc, v, w, den;
    int k;
    d3sub(b, a, ab); d3sub(c, a, ac); d3sub(p, a, ap);
    d1 = d3dot(ab, ap); d2 = d3dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return d3dist(p, a);
    d3sub(p, b, bp);
    d3 = d3dot(ab, bp); d4 = d3dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return d3dist(p, b);
    vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        v = d1 / (d1 - d3);
        for (k = 0; k < 3; ++k) q[k] = a[k] + v * ab[k];
        return d3dist(p, q);
    }
    d3sub(p, c, cp);
    d5 = d3dot(ab, cp); d6 = d3dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return d3dist(p, c);
    vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        w = d2 / (d2 - d6);
        for (k = 0; k < 3; ++k) q[k] = a[k] + w * ac[k];
        return d3dist(p, q);
    }
    va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (k = 0; k < 3; ++k) q[k] = b[k] + w * (c[k] - b[k]);
        return d3dist(p, q);
    }
    den = 1 / (va + vb + vc);
    v = vb * den;
    w = vc * den;
    for (k = 0; k < 3; ++k) q[k] = a[k] + ab[k] * v + ac[k] * w;
    return d3dist(p, q);
}

/* Distance between segments p1q1 and p2q2 (Ericson 5.1.9), parallel and degenerate included. */
static double segment_segment(const double *p1, const double *q1, const double *p2, const double *q2)
{
    double d1[3], d2[3], r[3], a, e, f, s, t, c1[3], c2[3];
    int k;
    d3sub(q1, p1, d1); d3sub(q2, p2, d2); d3sub(p1, p2, r);
    a = d3dot(d1, d1); e = d3dot(d2, d2); f = d3dot(d2, r);
    if (a <= 1e-300 && e <= 1e-300) return d3dist(p1, p2);
    if (a <= 1e-300) { s = 0; t = clamp01(f / e); }
    else {
        double c = d3dot(d1, r);
        if (e <= 1e-300) { t = 0; s = clamp01(-c / a); }
        else {
            double b = d3dot(d1, d2), den = a * e - b * b;
            s = den > 0 ? clamp01((b * f - c * e) / den) : 0;
            t = (b * s + f) / e;
            if (t < 0) { t = 0; s = clamp01(-c / a); }
            else if (t > 1) { t = 1; s = clamp01((b - c) / a); }
        }
    }
    for (k = 0; k < 3; ++k) { c1[k] = p1[k] + d1[k] * s; c2[k] = p2[k] + d2[k] * t; }
    return d3dist(c1, c2);
}

/* Distance of a vertex-face (ee = 0: p, f0, f1, f2) or edge-edge (ee = 1) pair at time t. */
static double pair_distance(int ee, double P0[4][3], double P1[4][3], double t)
{
    double y[4][3];
    int j, k;
    for (j = 0; j < 4; ++j)
        for (k = 0; k < 3; ++k) y[j][k] = P0[j][k] + t * (P1[j][k] - P0[j][k]);
    return ee ? segment_segment(y[0], y[1], y[2], y[3]) : point_triangle(y[0], y[1], y[2], y[3]);
}

/* Lower bound check of the distance of a pair over its straight motion: the distance is
   L-Lipschitz in t with L the largest relative displacement of a point of one primitive
   against a point of the other, so over [ta, tb] it is at least (D(ta) + D(tb) - L (tb - ta)) / 2.
   Intervals whose bound does not clear `floor` are halved. Returns the smallest distance seen
   at a sample, or -1 when some interval narrower than 1e-9 still may go below floor. */
static double path_min_distance(int ee, double P0[4][3], double P1[4][3], double floor_)
{
    struct { double ta, tb, da, db; } st[128];
    double L = 0, best;
    int n, i, j, k;
    for (i = 0; i < (ee ? 2 : 1); ++i)
        for (j = ee ? 2 : 1; j < 4; ++j) {
            double r[3];
            for (k = 0; k < 3; ++k) r[k] = (P1[i][k] - P0[i][k]) - (P1[j][k] - P0[j][k]);
            if (d3len(r) > L) L = d3len(r);
        }
    st[0].ta = 0; st[0].da = pair_distance(ee, P0, P1, 0);
    st[0].tb = 1; st[0].db = pair_distance(ee, P0, P1, 1);
    best = st[0].da < st[0].db ? st[0].da : st[0].db;
    n = 1;
    while (n > 0) {
        double ta = st[n - 1].ta, tb = st[n - 1].tb, da = st[n - 1].da, db = st[n - 1].db, tm, dm;
        --n;
        if ((da + db - L * (tb - ta)) / 2 > floor_) continue;
        if (tb - ta < 1e-9) {
            if (da < floor_ || db < floor_) return -1;
            continue;
        }
        if (n + 2 > 128) return -1;
        tm = 0.5 * (ta + tb);
        dm = pair_distance(ee, P0, P1, tm);
        if (dm < best) best = dm;
        st[n].ta = tm; st[n].tb = tb; st[n].da = dm; st[n].db = db; ++n;
        st[n].ta = ta; st[n].tb = tm; st[n].da = da; st[n].db = dm; ++n;
    }
    return best;
}

/* Whether two triangles (closed) intersect: separating axis test over the two normals, the
   nine edge cross products and the six in-plane edge normals (for coplanar pairs). A pair
   whose best separation is below 1e-12 m counts as intersecting. */
static int triangles_intersect(double A[3][3], double B[3][3])
{
    double ea[3][3], eb[3][3], na[3], nb[3], axes[17][3];
    int i, j, k, na_ = 0;
    for (i = 0; i < 3; ++i) { d3sub(A[(i + 1) % 3], A[i], ea[i]); d3sub(B[(i + 1) % 3], B[i], eb[i]); }
    d3cross(ea[0], ea[1], na);
    d3cross(eb[0], eb[1], nb);
    for (k = 0; k < 3; ++k) { axes[0][k] = na[k]; axes[1][k] = nb[k]; }
    na_ = 2;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) d3cross(ea[i], eb[j], axes[na_++]);
    for (i = 0; i < 3; ++i) d3cross(na, ea[i], axes[na_++]);
    for (i = 0; i < 3; ++i) d3cross(nb, eb[i], axes[na_++]);
    for (i = 0; i < na_; ++i) {
        double l = d3len(axes[i]), alo = HUGE_VAL, ahi = -HUGE_VAL, blo = HUGE_VAL, bhi = -HUGE_VAL;
        if (!(l > 1e-14)) continue;
        for (k = 0; k < 3; ++k) {
            double pa = d3dot(A[k], axes[i]) / l, pb = d3dot(B[k], axes[i]) / l;
            if (pa < alo) alo = pa;
            if (pa > ahi) ahi = pa;
            if (pb < blo) blo = pb;
            if (pb > bhi) bhi = pb;
        }
        if (blo - ahi > 1e-12 || alo - bhi > 1e-12) return 0;
    }
    return 1;
}

/* ===================================================================================== */
/* scenes                                                                                */
/* ===================================================================================== */

typedef struct scene {
    int32_t n, m;
    cloth_real *x0, *x1, *invm;
    int32_t *tri, *piece;
} scene;

static void scene_free(scene *s)
{
    free(s->x0); free(s->x1); free(s->invm); free(s->tri); free(s->piece);
    memset(s, 0, sizeof *s);
}

/* Append a grid (cloth_mesh_grid: y = 0, x and z in [-w/2, w/2]) transformed by pose as piece p. */
static int scene_add_grid(scene *s, int32_t nx, int32_t ny, double w, double d, const cloth_pose *pose, int32_t p)
{
    cloth_mesh g;
    int32_t i, base = s->n;
    if (cloth_mesh_grid(&g, nx, ny, (cloth_real)w, (cloth_real)d, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return 0;
    s->x0 = (cloth_real *)realloc(s->x0, sizeof(cloth_real) * 3 * (size_t)(s->n + g.vertex_count));
    s->x1 = (cloth_real *)realloc(s->x1, sizeof(cloth_real) * 3 * (size_t)(s->n + g.vertex_count));
    s->invm = (cloth_real *)realloc(s->invm, sizeof(cloth_real) * (size_t)(s->n + g.vertex_count));
    s->tri = (int32_t *)realloc(s->tri, sizeof(int32_t) * 3 * (size_t)(s->m + g.triangle_count));
    s->piece = (int32_t *)realloc(s->piece, sizeof(int32_t) * (size_t)(s->m + g.triangle_count));
    for (i = 0; i < g.vertex_count; ++i) {
        cloth_pose_apply(pose, g.x + 3 * i, s->x0 + 3 * (base + i));
        memcpy(s->x1 + 3 * (base + i), s->x0 + 3 * (base + i), 3 * sizeof(cloth_real));
        s->invm[base + i] = 1;
    }
    for (i = 0; i < g.triangle_count; ++i) {
        s->tri[3 * (s->m + i)] = base + g.tri[3 * i];
        s->tri[3 * (s->m + i) + 1] = base + g.tri[3 * i + 1];
        s->tri[3 * (s->m + i) + 2] = base + g.tri[3 * i + 2];
        s->piece[s->m + i] = p;
    }
    s->n += g.vertex_count;
    s->m += g.triangle_count;
    cloth_mesh_free(&g);
    return 1;
}

/* A round_check for scene_contact's contacts (NULL: none). */
static int (*scene_round_check)(void *user, const cloth_real *x1) = NULL;

static cloth_contact *scene_contact(const scene *s, int self, int pieces)
{
    cloth_contact_def def = cloth_default_contact_def();
    cloth_contact *c = NULL;
    def.round_check = scene_round_check;
    def.vertex_count = s->n;
    def.tri = s->tri;
    def.triangle_count = s->m;
    def.triangle_piece = s->piece;
    def.self_collision = self;
    def.piece_collision = pieces;
    if (cloth_contact_create(&c, &def) != CLOTH_SUCCESS) return NULL;
    return c;
}

/* A 1 m x 1 m sheet of nx x nx vertices in the plane z = 0 (the y = 0 grid turned about x),
   its four corners pinned (listed in corners), and its contact with self-collision on. */
static cloth_contact *pinned_vertical_sheet(scene *s, int32_t nx, int32_t corners[4])
{
    cloth_real xaxis[3] = {1, 0, 0};
    cloth_pose p = cloth_pose_make(NULL, xaxis, (cloth_real)1.5707963267948966);
    int32_t i;
    memset(s, 0, sizeof *s);
    if (!scene_add_grid(s, nx, nx, 1, 1, &p, 0)) return NULL;
    corners[0] = 0; corners[1] = nx - 1; corners[2] = nx * (nx - 1); corners[3] = nx * nx - 1;
    for (i = 0; i < 4; ++i) s->invm[corners[i]] = 0;
    return scene_contact(s, 1, 0);
}

static int shares(const int32_t *t, int32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

static void load_point(const cloth_real *p, double *o) { o[0] = (double)p[0]; o[1] = (double)p[1]; o[2] = (double)p[2]; }

/* An extra triangle mesh taking part in the checks (a mesh obstacle), positions at both ends. */
typedef struct check_mesh {
    int32_t n, m;
    const cloth_real *y0, *y1;
    const int32_t *tri;
} check_mesh;

typedef struct check_result {
    int32_t close_pairs;       /* pairs whose distance along the path may go below floor */
    int32_t intersecting;      /* triangle pairs intersecting at x1 */
    double min_distance;       /* smallest distance sampled over all pairs' paths */
} check_result;

/* Every vertex-face and edge-edge pair sharing no vertex, between the cloth and itself
   (within a piece if self, between pieces if pieces) and between the cloth and mesh ob:
   their distance along the straight paths stays above floor; and no two triangles sharing
   no vertex intersect at the end. */
static check_result check_scene(const scene *s, const cloth_real *x1, int self, int pieces, const check_mesh *ob, double floor_)
{
    check_result res;
    int32_t a, b, i, j;
    int32_t total = s->n + (ob ? ob->n : 0), tri_total = s->m + (ob ? ob->m : 0);
    double (*X0)[3] = (double (*)[3])malloc(sizeof(double) * 3 * (size_t)total);
    double (*X1)[3] = (double (*)[3])malloc(sizeof(double) * 3 * (size_t)total);
    int32_t *T = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)tri_total);
    int32_t *P = (int32_t *)malloc(sizeof(int32_t) * (size_t)tri_total);
    double (*lo)[3] = (double (*)[3])malloc(sizeof(double) * 3 * (size_t)tri_total);
    double (*hi)[3] = (double (*)[3])malloc(sizeof(double) * 3 * (size_t)tri_total);
    res.close_pairs = 0;
    res.intersecting = 0;
    res.min_distance = HUGE_VAL;
    for (i = 0; i < s->n; ++i) { load_point(s->x0 + 3 * i, X0[i]); load_point(x1 + 3 * i, X1[i]); }
    for (i = 0; ob && i < ob->n; ++i) { load_point(ob->y0 + 3 * i, X0[s->n + i]); load_point(ob->y1 + 3 * i, X1[s->n + i]); }
    for (i = 0; i < s->m; ++i) { for (j = 0; j < 3; ++j) T[3 * i + j] = s->tri[3 * i + j]; P[i] = s->piece[i]; }
    for (i = 0; ob && i < ob->m; ++i) { for (j = 0; j < 3; ++j) T[3 * (s->m + i) + j] = s->n + ob->tri[3 * i + j]; P[s->m + i] = -1; }
    for (i = 0; i < tri_total; ++i) {
        int k;
        for (k = 0; k < 3; ++k) { lo[i][k] = HUGE_VAL; hi[i][k] = -HUGE_VAL; }
        for (j = 0; j < 3; ++j)
            for (k = 0; k < 3; ++k) {
                double u = X0[T[3 * i + j]][k], w = X1[T[3 * i + j]][k];
                if (u < lo[i][k]) lo[i][k] = u;
                if (w < lo[i][k]) lo[i][k] = w;
                if (u > hi[i][k]) hi[i][k] = u;
                if (w > hi[i][k]) hi[i][k] = w;
            }
    }
    /* every triangle pair: its primitive pairs (each primitive pair is met several times; the
       check is idempotent, so repetition only costs time) */
    for (a = 0; a < tri_total; ++a)
        for (b = a + 1; b < tri_total; ++b) {
            const int32_t *ta = T + 3 * a, *tb = T + 3 * b;
            int k, side, sep = 0;
            if (P[a] < 0 && P[b] < 0) continue;
            if (P[a] >= 0 && P[b] >= 0 && (P[a] == P[b] ? !self : !pieces)) continue;
            for (k = 0; k < 3; ++k)
                if (lo[a][k] > hi[b][k] + floor_ || lo[b][k] > hi[a][k] + floor_) sep = 1;
            if (sep) continue;
            for (side = 0; side < 2; ++side) {
                const int32_t *tv = side ? tb : ta, *tf = side ? ta : tb;
                for (i = 0; i < 3; ++i) {
                    double P0[4][3], P1[4][3], dmin;
                    if (shares(tf, tv[i])) continue;
                    for (k = 0; k < 3; ++k) {
                        P0[0][k] = X0[tv[i]][k]; P1[0][k] = X1[tv[i]][k];
                        for (j = 0; j < 3; ++j) { P0[1 + j][k] = X0[tf[j]][k]; P1[1 + j][k] = X1[tf[j]][k]; }
                    }
                    dmin = path_min_distance(0, P0, P1, floor_);
                    if (dmin < 0) res.close_pairs++;
                    else if (dmin < res.min_distance) res.min_distance = dmin;
                }
            }
            for (i = 0; i < 3; ++i)
                for (j = 0; j < 3; ++j) {
                    int32_t e0 = ta[i], e1 = ta[(i + 1) % 3], f0 = tb[j], f1 = tb[(j + 1) % 3];
                    double P0[4][3], P1[4][3], dmin;
                    if (e0 == f0 || e0 == f1 || e1 == f0 || e1 == f1) continue;
                    for (k = 0; k < 3; ++k) {
                        P0[0][k] = X0[e0][k]; P0[1][k] = X0[e1][k]; P0[2][k] = X0[f0][k]; P0[3][k] = X0[f1][k];
                        P1[0][k] = X1[e0][k]; P1[1][k] = X1[e1][k]; P1[2][k] = X1[f0][k]; P1[3][k] = X1[f1][k];
                    }
                    dmin = path_min_distance(1, P0, P1, floor_);
                    if (dmin < 0) res.close_pairs++;
                    else if (dmin < res.min_distance) res.min_distance = dmin;
                }
            if (!shares(ta, tb[0]) && !shares(ta, tb[1]) && !shares(ta, tb[2])) {
                double A[3][3], B[3][3];
                for (i = 0; i < 3; ++i)
                    for (k = 0; k < 3; ++k) { A[i][k] = X1[ta[i]][k]; B[i][k] = X1[tb[i]][k]; }
                if (triangles_intersect(A, B)) res.intersecting++;
            }
        }
    free(X0); free(X1); free(T); free(P); free(lo); free(hi);
    return res;
}

/* Signed distances of the analytic shapes, written here (local frame). */
static double sdf_local(const cloth_obstacle_def *d, const double *p)
{
    double q[3];
    int k;
    switch (d->shape) {
    case CLOTH_OBSTACLE_PLANE: return p[1];
    case CLOTH_OBSTACLE_SPHERE: return d3len(p) - (double)d->radius;
    case CLOTH_OBSTACLE_CAPSULE: {
        double L = (double)d->half_length, cx = p[0] < -L ? -L : (p[0] > L ? L : p[0]);
        q[0] = p[0] - cx; q[1] = p[1]; q[2] = p[2];
        return d3len(q) - (double)d->radius;
    }
    case CLOTH_OBSTACLE_BOX: {
        double out = 0, in = -HUGE_VAL;
        for (k = 0; k < 3; ++k) {
            double e = fabs(p[k]) - (double)d->half_extents[k];
            if (e > 0) out += e * e;
            if (e > in) in = e;
        }
        return out > 0 ? sqrt(out) : in;
    }
    default: return HUGE_VAL;
    }
}

/* The signed distance of a world point to an analytic obstacle posed by pose. */
static double sdf_world(const cloth_obstacle_def *d, const cloth_pose *pose, const cloth_real *x)
{
    double w[3], r[3], p[3];
    int i;
    load_point(x, w);
    for (i = 0; i < 3; ++i) r[i] = w[i] - (double)pose->translation[i];
    for (i = 0; i < 3; ++i)
        p[i] = (double)pose->rotation[i] * r[0] + (double)pose->rotation[3 + i] * r[1] + (double)pose->rotation[6 + i] * r[2];
    return sdf_local(d, p);
}

static int verbose(void) { const char *v = getenv("CONTACT_VERBOSE"); return v && *v == '1'; }

static void print_stats(const char *name, const cloth_contact_stats *st)
{
    if (!verbose()) return;
    printf("    [%s] rounds %d rigid %d obstacle_contacts %d impacts %d (vf %d ee %d prox %d) rows %d zones %d largest %d qp %d/%d it "
           "pairs %d ccd %d checks %lld exhausted %d stale %d friction_rows %d frozen %d rigid_zones %d | bvh %.4f ccd %.4f resp %.4f total %.4f s\n",
           name, st->rounds, st->rigid_rounds, st->obstacle_contacts, st->impacts, st->vertex_face_impacts, st->edge_edge_impacts, st->proximity_impacts,
           st->impact_rows, st->impact_zones, st->largest_zone, st->qp_solves, st->qp_iterations, st->candidate_pairs,
           st->ccd_queries, (long long)st->ccd_checks, st->ccd_budget_exhausted, st->stale_impacts, st->friction_rows, st->frozen_zones, st->rigid_zones, st->time_bvh,
           st->time_ccd, st->time_response, st->time_total);
}

/* ===================================================================================== */
/* analytic obstacles                                                                    */
/* ===================================================================================== */

/* Poses: cloth_pose_interpolate ends exactly at its two poses, turns about the fixed axis at a
   uniform rate (also through the half-turn branch), stays orthonormal; cloth_pose_apply_inverse
   undoes cloth_pose_apply; cloth_contact_get_def gives back the def. */
TEST(poses_interpolate_apply_and_invert)
{
    double tol = IS_FLOAT ? 2e-5 : 1e-12;
    cloth_real t0[3] = {1, 2, 3}, t1[3] = {3, 2, 1}, z[3] = {0, 0, 1}, xy[3] = {1, 1, 0}, xaxis[3] = {1, 0, 0};
    cloth_real p[3] = {(cloth_real)0.3, (cloth_real)-0.7, (cloth_real)1.1}, q[3], back[3];
    cloth_pose a = cloth_pose_make(t0, z, (cloth_real)0.3), b = cloth_pose_make(t1, xy, (cloth_real)2.0), m;
    int k, f;
    m = cloth_pose_interpolate(&a, &b, 0);
    for (k = 0; k < 9; ++k) ENSURE(fabs((double)m.rotation[k] - (double)a.rotation[k]) <= tol);
    for (k = 0; k < 3; ++k) ENSURE(m.translation[k] == a.translation[k]);
    m = cloth_pose_interpolate(&a, &b, 1);
    for (k = 0; k < 9; ++k) ENSURE(fabs((double)m.rotation[k] - (double)b.rotation[k]) <= 10 * tol);
    for (k = 0; k < 3; ++k) ENSURE(fabs((double)m.translation[k] - (double)b.translation[k]) <= tol);
    /* about one axis the angle goes linearly: 0.2 -> 1.0 about z, a quarter of the way is 0.4 */
    a = cloth_pose_make(t0, z, (cloth_real)0.2);
    b = cloth_pose_make(t1, z, (cloth_real)1.0);
    m = cloth_pose_interpolate(&a, &b, (cloth_real)0.25);
    {
        cloth_pose e = cloth_pose_make(NULL, z, (cloth_real)0.4);
        for (k = 0; k < 9; ++k) ENSURE(fabs((double)m.rotation[k] - (double)e.rotation[k]) <= 10 * tol);
        ENSURE(fabs((double)m.translation[0] - 1.5) <= tol && fabs((double)m.translation[2] - 2.5) <= tol);
    }
    /* nearly a half turn about x (the skew part nearly vanishes): half of it is a quarter turn */
    a = cloth_pose_identity();
    b = cloth_pose_make(NULL, xaxis, (cloth_real)(3.14159265358979 - 1e-7));
    m = cloth_pose_interpolate(&a, &b, (cloth_real)0.5);
    {
        cloth_real y[3] = {0, 1, 0}, out[3];
        cloth_pose_apply(&m, y, out);
        ENSURE(fabs((double)out[0]) <= 1e-5 && fabs((double)out[1]) <= 1e-5 && fabs((double)out[2] - 1) <= 1e-5);
    }
    /* every interpolated rotation is orthonormal, and apply_inverse undoes apply */
    a = cloth_pose_make(t0, z, (cloth_real)0.3);
    b = cloth_pose_make(t1, xy, (cloth_real)2.0);
    for (f = 0; f <= 8; ++f) {
        int r, c;
        m = cloth_pose_interpolate(&a, &b, (cloth_real)f / 8);
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) {
                double d = 0;
                for (k = 0; k < 3; ++k) d += (double)m.rotation[3 * r + k] * (double)m.rotation[3 * c + k];
                ENSURE(fabs(d - (r == c)) <= 10 * tol);
            }
        cloth_pose_apply(&m, p, q);
        cloth_pose_apply_inverse(&m, q, back);
        for (k = 0; k < 3; ++k) ENSURE(fabs((double)back[k] - (double)p[k]) <= 10 * tol);
    }
    {
        cloth_contact_def def = cloth_default_contact_def();
        cloth_contact *c = NULL;
        def.self_collision = 1;
        def.thickness = (cloth_real)2e-3;
        ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
        ENSURE(cloth_contact_get_def(c)->self_collision == 1 && cloth_contact_get_def(c)->thickness == (cloth_real)2e-3);
        cloth_contact_destroy(c);
    }
}

/* One free vertex (no triangles) and one obstacle. */
static cloth_contact *single_vertex(const cloth_obstacle_def *od)
{
    cloth_contact_def def = cloth_default_contact_def();
    cloth_contact *c = NULL;
    def.vertex_count = 1;
    if (cloth_contact_create(&c, &def) != CLOTH_SUCCESS) return NULL;
    if (cloth_contact_add_obstacle(c, od, NULL) != CLOTH_SUCCESS) { cloth_contact_destroy(c); return NULL; }
    return c;
}

/* A vertex dropped onto each shape, from several directions and speeds: it ends outside by the
   thickness, on the side it came from, and its velocity does not approach the surface. */
TEST(vertex_falls_onto_each_shape)
{
    int shape, trial, contacts = 0;
    for (shape = 0; shape < 4; ++shape)
        for (trial = 0; trial < 12; ++trial) {
            cloth_obstacle_def od = cloth_default_obstacle_def();
            cloth_real axis[3] = {(cloth_real)0.3, 1, (cloth_real)-0.2}, tr[3] = {(cloth_real)0.1, (cloth_real)0.2, (cloth_real)-0.05};
            cloth_real x0[3], x1[3], v[3], nrm[3];
            cloth_contact *c;
            cloth_contact_stats st;
            double dir[3], speed = 0.5 + 3.0 * trial, h = 1.0 / 60, s0, s1, vn;
            int k;
            od.shape = (cloth_obstacle_shape)shape;
            od.radius = (cloth_real)0.2;
            od.half_length = (cloth_real)0.15;
            od.half_extents[0] = (cloth_real)0.2; od.half_extents[1] = (cloth_real)0.1; od.half_extents[2] = (cloth_real)0.15;
            od.pose = cloth_pose_make(tr, axis, (cloth_real)0.4);
            od.thickness = (cloth_real)2e-3;
            c = single_vertex(&od);
            ENSURE(c != NULL);
            /* start outside along a direction that depends on the trial, then move towards the
               obstacle's centre (the plane: straight down) by speed * h, often far through it */
            dir[0] = sin(1.7 * trial); dir[1] = cos(1.3 * trial) + (shape == 0 ? 2 : 0); dir[2] = sin(0.7 * trial + 1);
            {
                double l = d3len(dir), mv[3], ml;
                cloth_real pr[3];
                for (k = 0; k < 3; ++k) pr[k] = (cloth_real)(dir[k] / l * (shape == 0 ? 0.05 : 0.35));
                cloth_pose_apply(&od.pose, pr, x0);
                if (shape == 0)
                    for (k = 0; k < 3; ++k) mv[k] = -(double)od.pose.rotation[3 * k + 1];
                else
                    for (k = 0; k < 3; ++k) mv[k] = (double)od.pose.translation[k] - (double)x0[k];
                ml = d3len(mv);
                for (k = 0; k < 3; ++k) x1[k] = (cloth_real)((double)x0[k] + speed * h * mv[k] / ml);
            }
            s0 = sdf_world(&od, &od.pose, x0);
            ENSURE(s0 > 2e-3);
            {
                cloth_real free_x1[3];
                int reaches;
                memcpy(free_x1, x1, sizeof free_x1);
                /* does the unconstrained motion reach the layer (sampled; the obstacles are convex)? */
                reaches = 0;
                for (k = 0; k <= 1000; ++k) {
                    cloth_real y[3];
                    int q;
                    for (q = 0; q < 3; ++q) y[q] = (cloth_real)((double)x0[q] + (k / 1000.0) * ((double)x1[q] - (double)x0[q]));
                    if (sdf_world(&od, &od.pose, y) < 2e-3) reaches = 1;
                }
                ENSURE(cloth_contact_resolve(c, x0, x1, NULL, (cloth_real)h, v, &st) == CLOTH_SUCCESS);
                s1 = sdf_world(&od, &od.pose, x1);
                ENSURE(s1 >= 2e-3 * (1 - REL));
                if (!reaches) {
                    ENSURE(memcmp(free_x1, x1, sizeof free_x1) == 0);
                    cloth_contact_destroy(c);
                    continue;
                }
                ++contacts;
            }
            /* on the side it came from: the segment from x0 to x1 stays outside the shape */
            {
                int q;
                for (q = 0; q <= 200; ++q) {
                    cloth_real y[3];
                    for (k = 0; k < 3; ++k) y[k] = (cloth_real)((double)x0[k] + (q / 200.0) * ((double)x1[k] - (double)x0[k]));
                    ENSURE(sdf_world(&od, &od.pose, y) > 0);
                }
            }
            /* the velocity does not approach the surface */
            cloth_contact_obstacle_distance(c, 0, x1, nrm);
            vn = (double)v[0] * nrm[0] + (double)v[1] * nrm[1] + (double)v[2] * nrm[2];
            ENSURE(vn >= -VABS);
            ENSURE(st.obstacle_contacts >= 1);
            cloth_contact_destroy(c);
        }
    ENSURE(contacts >= 36);
}

/* Paths that end in an obstacle's thickness layer without reaching the ball about its origin
   that holds it (the contact module skips paths that stay out of that ball grown by the
   thickness): a vertex moving radially to half the thickness off a sphere, off a capsule's cap
   and off a box's corner, and a resting vertex that a translating sphere comes to within half
   the thickness of; each ends outside the layer (a skip that forgot the thickness leaves all
   four in it), and a path that stays 1.5 thicknesses off is left alone. */
TEST(paths_ending_in_the_layer_are_pushed_out)
{
    int shape, moving;
    for (shape = 0; shape < 3; ++shape)
        for (moving = 0; moving < 2; ++moving) {
            cloth_obstacle_def od = cloth_default_obstacle_def();
            const double th = 2e-3;
            double u[3], rim, l;
            cloth_real x0[3], x1[3], v[3], far_x1[3];
            cloth_pose a = cloth_pose_identity(), b = cloth_pose_identity();
            cloth_contact *c;
            int k, end;
            if (moving && shape != 0) continue;
            od.shape = shape == 0 ? CLOTH_OBSTACLE_SPHERE : shape == 1 ? CLOTH_OBSTACLE_CAPSULE : CLOTH_OBSTACLE_BOX;
            od.radius = (cloth_real)0.2;
            od.half_length = (cloth_real)0.15;
            od.half_extents[0] = (cloth_real)0.2; od.half_extents[1] = (cloth_real)0.1; od.half_extents[2] = (cloth_real)0.15;
            od.thickness = (cloth_real)th;
            /* the direction to the farthest point: the capsule's cap along x, the box's corner */
            u[0] = shape == 0 ? 0.3 : shape == 1 ? 1 : 0.2;
            u[1] = shape == 0 ? 0.9 : shape == 1 ? 0 : 0.1;
            u[2] = shape == 0 ? -0.2 : shape == 1 ? 0 : 0.15;
            l = d3len(u);
            for (k = 0; k < 3; ++k) u[k] /= l;
            rim = shape == 0 ? 0.2 : shape == 1 ? 0.35 : l; /* the shape's extent along u: the ball's radius */
            for (end = 0; end < 2; ++end) { /* end 0: half a thickness off; end 1: 1.5 thicknesses off */
                const double off = end ? 1.5 * th : 0.5 * th;
                c = single_vertex(&od);
                ENSURE(c != NULL);
                for (k = 0; k < 3; ++k) {
                    x0[k] = (cloth_real)((rim + (moving ? off : 10 * th)) * u[k]);
                    x1[k] = moving ? x0[k] : (cloth_real)((rim + off) * u[k]);
                }
                if (moving) { /* the sphere comes from 9.5 thicknesses away along -u */
                    for (k = 0; k < 3; ++k) a.translation[k] = (cloth_real)(-(10 * th - off) * u[k]);
                    ENSURE(cloth_contact_move_obstacle(c, 0, &a, &b) == CLOTH_SUCCESS);
                }
                memcpy(far_x1, x1, sizeof far_x1);
                ENSURE(cloth_contact_resolve(c, x0, x1, NULL, (cloth_real)(1.0 / 60), v, NULL) == CLOTH_SUCCESS);
                ENSURE(sdf_world(&od, &b, x1) >= th * (1 - REL));
                if (end == 1) ENSURE(memcmp(far_x1, x1, sizeof far_x1) == 0);
                else ENSURE(memcmp(far_x1, x1, sizeof far_x1) != 0);
                cloth_contact_destroy(c);
            }
        }
}

/* A step of a single vertex under gravity on an obstacle: x1 = x0 + h v + h^2 g. */
static int vertex_step(cloth_contact *c, cloth_real *x, cloth_real *v, double h, const double *g)
{
    cloth_real x1[3], vn[3];
    int k;
    for (k = 0; k < 3; ++k) x1[k] = (cloth_real)((double)x[k] + h * (double)v[k] + h * h * g[k]);
    if (cloth_contact_resolve(c, x, x1, NULL, (cloth_real)h, vn, NULL) != CLOTH_SUCCESS) return 0;
    for (k = 0; k < 3; ++k) { x[k] = x1[k]; v[k] = vn[k]; }
    return 1;
}

/* Sliding on the ground plane: the speed falls by mu_k g per second, then the vertex stops
   (below mu_s g h in one step) and stays. */
TEST(friction_sliding_on_a_plane)
{
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_contact *c;
    cloth_real x[3], v[3];
    double g[3] = {0, -9.81, 0}, h = 1.0 / 100, mu_k = 0.3, t;
    int i;
    od.friction_static = (cloth_real)0.5;
    od.friction_kinetic = (cloth_real)mu_k;
    od.thickness = (cloth_real)1e-3;
    c = single_vertex(&od);
    ENSURE(c != NULL);
    x[0] = 0; x[1] = (cloth_real)1e-3; x[2] = 0;
    v[0] = 2; v[1] = 0; v[2] = 1;
    for (i = 1; i <= 30; ++i) {
        double speed, expect;
        ENSURE(vertex_step(c, x, v, h, g));
        t = i * h;
        speed = sqrt((double)v[0] * v[0] + (double)v[2] * v[2]);
        expect = sqrt(5.0) - mu_k * 9.81 * t;
        ENSURE_NEAR(speed, expect, ABS * i);
        ENSURE_NEAR(x[1], 1e-3, ABS * 1e-3);
        ENSURE(fabs((double)v[1]) <= ABS);
        /* the direction of sliding is kept */
        ENSURE_NEAR((double)v[2] / (double)v[0], 0.5, ABS);
    }
    for (i = 0; i < 100; ++i) ENSURE(vertex_step(c, x, v, h, g));
    ENSURE(v[0] == 0 && v[2] == 0);
    {
        cloth_real keep[3];
        memcpy(keep, x, sizeof keep);
        for (i = 0; i < 20; ++i) ENSURE(vertex_step(c, x, v, h, g));
        ENSURE(x[0] == keep[0] && x[2] == keep[2]);
    }
    cloth_contact_destroy(c);
}

/* On an inclined plane: below the friction angle (tan < mu_s) a vertex at rest stays at rest;
   above it, it slides with acceleration g (sin - mu_k cos). */
TEST(friction_on_an_incline)
{
    int steep;
    for (steep = 0; steep < 2; ++steep) {
        cloth_obstacle_def od = cloth_default_obstacle_def();
        cloth_real z[3] = {0, 0, 1};
        double angle = steep ? 0.6 : 0.4, g[3] = {0, -9.81, 0}, h = 1.0 / 120, travelled, T = 0.5;
        cloth_contact *c;
        cloth_real x[3], v[3], start[3];
        int i;
        od.pose = cloth_pose_make(NULL, z, (cloth_real)angle); /* tan 0.4 = 0.42 < 0.5 < tan 0.6 = 0.68 */
        od.friction_static = (cloth_real)0.5;
        od.friction_kinetic = (cloth_real)0.4;
        c = single_vertex(&od);
        ENSURE(c != NULL);
        {
            cloth_real local[3] = {0, (cloth_real)1e-3, 0};
            cloth_pose_apply(&od.pose, local, x);
        }
        v[0] = v[1] = v[2] = 0;
        memcpy(start, x, sizeof start);
        for (i = 0; i < (int)(T / h + 0.5); ++i) ENSURE(vertex_step(c, x, v, h, g));
        {
            double xa[3], xb[3];
            load_point(x, xa);
            load_point(start, xb);
            travelled = d3dist(xa, xb);
        }
        ENSURE(sdf_world(&od, &od.pose, x) >= 1e-3 * (1 - REL));
        if (!steep) {
            ENSURE(travelled < ABS * 1e-3);
        } else {
            double a = 9.81 * (sin(angle) - 0.4 * cos(angle));
            /* backward-Euler-like discretisation: distance sum_i a h^2 i = a h^2 N (N+1) / 2 */
            double N = (double)(int)(T / h + 0.5);
            ENSURE_NEAR(travelled, a * h * h * N * (N + 1) / 2, 0.02 * a * T * T);
        }
        cloth_contact_destroy(c);
    }
}

/* A kinematic box sliding sideways under a resting vertex drags it with acceleration mu_k g
   until the vertex moves with it; a spinning capsule drags a vertex resting on top. */
TEST(friction_with_moving_obstacles)
{
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_contact *c;
    cloth_real x[3], v[3];
    double g[3] = {0, -9.81, 0}, h = 1.0 / 100, speed = 1.0, mu = 0.4;
    int i;
    od.shape = CLOTH_OBSTACLE_BOX;
    od.half_extents[0] = 100; od.half_extents[1] = (cloth_real)0.5; od.half_extents[2] = 100;
    od.friction_static = od.friction_kinetic = (cloth_real)mu;
    od.pose.translation[1] = (cloth_real)-0.5;
    c = single_vertex(&od);
    ENSURE(c != NULL);
    x[0] = 0; x[1] = (cloth_real)1e-3; x[2] = 0;
    v[0] = v[1] = v[2] = 0;
    for (i = 0; i < 40; ++i) {
        cloth_pose a = od.pose, b = od.pose;
        a.translation[0] = (cloth_real)(speed * h * i);
        b.translation[0] = (cloth_real)(speed * h * (i + 1));
        ENSURE(cloth_contact_move_obstacle(c, 0, &a, &b) == CLOTH_SUCCESS);
        ENSURE(vertex_step(c, x, v, h, g));
        if ((i + 1) * h * mu * 9.81 < speed) ENSURE_NEAR(v[0], (i + 1) * h * mu * 9.81, ABS * 10);
        else ENSURE_NEAR(v[0], speed, ABS * 10);
        ENSURE_NEAR(x[1], 1e-3, ABS * 1e-3);
    }
    cloth_contact_destroy(c);

    /* capsule along x spinning about its axis at 1 turn/s, a vertex on top: pulled along -z */
    od = cloth_default_obstacle_def();
    od.shape = CLOTH_OBSTACLE_CAPSULE;
    od.radius = (cloth_real)0.15;
    od.half_length = (cloth_real)0.3;
    od.friction_static = od.friction_kinetic = (cloth_real)0.5;
    c = single_vertex(&od);
    ENSURE(c != NULL);
    x[0] = 0; x[1] = (cloth_real)0.151; x[2] = 0;
    v[0] = v[1] = v[2] = 0;
    {
        cloth_real axis[3] = {1, 0, 0};
        for (i = 0; i < 5; ++i) {
            cloth_pose a = cloth_pose_make(NULL, axis, (cloth_real)(6.283185307179586 * h * i));
            cloth_pose b = cloth_pose_make(NULL, axis, (cloth_real)(6.283185307179586 * h * (i + 1)));
            ENSURE(cloth_contact_move_obstacle(c, 0, &a, &b) == CLOTH_SUCCESS);
            ENSURE(vertex_step(c, x, v, h, g));
            ENSURE(sdf_world(&od, &b, x) >= 1e-3 * (1 - REL));
        }
    }
    /* rotation about +x moves the top towards +z; kinetic friction 0.5 g: |v_z| ~ 0.5 g t */
    ENSURE(v[2] > 0);
    ENSURE_NEAR(v[2], 0.5 * 9.81 * 5 * h, 0.1 * 0.5 * 9.81 * 5 * h);
    cloth_contact_destroy(c);
}

/* docs/scenes.md projectile: a 1 m cloth (21 x 21) in the plane z = 0 pinned at its corners, a
   sphere of radius 5 cm crossing it along +z at 50 m/s in one step of 1/60 s. Every vertex
   ends outside the sphere by the thickness and none went through it. */
TEST(projectile_does_not_tunnel)
{
    scene s;
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_contact *c;
    cloth_pose a, b;
    cloth_contact_stats st;
    cloth_real *v;
    int32_t i, hit = 0, corners[4];
    double h = 1.0 / 60;
    c = pinned_vertical_sheet(&s, 21, corners);
    ENSURE(c != NULL);
    od.shape = CLOTH_OBSTACLE_SPHERE;
    od.radius = (cloth_real)0.05;
    od.thickness = (cloth_real)1e-3;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS);
    a = b = cloth_pose_identity();
    a.translation[0] = (cloth_real)0.013; a.translation[1] = (cloth_real)-0.007; a.translation[2] = (cloth_real)-0.4;
    b = a;
    b.translation[2] = (cloth_real)(-0.4 + 50 * h);
    ENSURE(cloth_contact_move_obstacle(c, 0, &a, &b) == CLOTH_SUCCESS);
    v = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)h, v, &st) == CLOTH_SUCCESS);
    print_stats("projectile", &st);
    for (i = 0; i < s.n; ++i) {
        double rho, dx = (double)s.x0[3 * i] - (double)a.translation[0], dy = (double)s.x0[3 * i + 1] - (double)a.translation[1];
        ENSURE(sdf_world(&od, &b, s.x1 + 3 * i) >= 1e-3 * (1 - REL));
        rho = sqrt(dx * dx + dy * dy);
        if (rho < 0.05) { /* in the sphere's path: not behind it within its shadow at the end */
            double ex = (double)s.x1[3 * i] - (double)b.translation[0], ey = (double)s.x1[3 * i + 1] - (double)b.translation[1];
            ++hit;
            ENSURE(!((double)s.x1[3 * i + 2] < (double)b.translation[2] && sqrt(ex * ex + ey * ey) < 0.05));
        }
    }
    ENSURE(hit >= 3);
    for (i = 0; i < 4; ++i)
        ENSURE(memcmp(s.x1 + 3 * corners[i], s.x0 + 3 * corners[i], 3 * sizeof(cloth_real)) == 0);
    /* the cloth itself stays free of intersections */
    {
        check_result r = check_scene(&s, s.x1, 1, 0, NULL, 1e-5);
        ENSURE(r.close_pairs == 0);
        ENSURE(r.intersecting == 0);
    }
    free(v);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* A 6 x 6 sheet (cells of 0.2 m, corners pinned) in the plane z = 0, and a sphere, a thin
   capsule and a thin box far smaller than a cell crossing its middle along +z at 50 m/s in one
   step, between the vertices. The vertex tests alone never see them; the inner proxy (PROXY)
   must stop every one: at the end the sheet's faces are in front of the obstacle's centre
   (the cloth point over the centre is ahead of it), no vertex is inside, and the sheet does
   not intersect itself. */
TEST(obstacles_smaller_than_cells_do_not_pass_between_vertices)
{
    int shape;
    for (shape = 0; shape < 3; ++shape) {
        scene s;
        cloth_obstacle_def od = cloth_default_obstacle_def();
        cloth_contact *c;
        cloth_pose a, b;
        cloth_contact_stats st;
        int32_t i, corners[4];
        double h = 1.0 / 60, ahead = -1e9;
        c = pinned_vertical_sheet(&s, 6, corners);
        ENSURE(c != NULL);
        od.thickness = (cloth_real)1e-3;
        if (shape == 0) { od.shape = CLOTH_OBSTACLE_SPHERE; od.radius = (cloth_real)0.04; }
        if (shape == 1) { od.shape = CLOTH_OBSTACLE_CAPSULE; od.radius = (cloth_real)0.02; od.half_length = (cloth_real)0.05; }
        if (shape == 2) {
            od.shape = CLOTH_OBSTACLE_BOX;
            od.half_extents[0] = od.half_extents[1] = (cloth_real)0.04;
            od.half_extents[2] = (cloth_real)0.03;
        }
        ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS);
        a = cloth_pose_identity();
        a.translation[2] = (cloth_real)-0.3; /* the middle of the sheet is a cell's centre */
        b = a;
        b.translation[2] = (cloth_real)(-0.3 + 50 * h);
        ENSURE(cloth_contact_move_obstacle(c, 0, &a, &b) == CLOTH_SUCCESS);
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)h, NULL, &st) == CLOTH_SUCCESS);
        if (verbose()) print_stats(shape == 0 ? "small sphere" : shape == 1 ? "thin capsule" : "thin box", &st);
        for (i = 0; i < s.n; ++i) ENSURE(sdf_world(&od, &b, s.x1 + 3 * i) >= 1e-3 * (1 - REL));
        /* the sheet over the obstacle's centre, at the end: the face under (x, y) = (0, 0) */
        for (i = 0; i < s.m; ++i) {
            const int32_t *t = s.tri + 3 * i;
            double A[3], B[3], C[3], e1[3], e2[3], q[3], d00, d01, d11, d20, d21, den, v, w;
            load_point(s.x1 + 3 * t[0], A); load_point(s.x1 + 3 * t[1], B); load_point(s.x1 + 3 * t[2], C);
            d3sub(B, A, e1); d3sub(C, A, e2);
            q[0] = -A[0]; q[1] = -A[1]; q[2] = 0;
            e1[2] = e2[2] = 0; /* barycentric coordinates of (0, 0) in the projection onto z = 0 */
            d00 = d3dot(e1, e1); d01 = d3dot(e1, e2); d11 = d3dot(e2, e2); d20 = d3dot(q, e1); d21 = d3dot(q, e2);
            den = d00 * d11 - d01 * d01;
            if (!(den > 0)) continue;
            v = (d11 * d20 - d01 * d21) / den;
            w = (d00 * d21 - d01 * d20) / den;
            if (v < 0 || w < 0 || v + w > 1) continue;
            {
                double z = (1 - v - w) * A[2] + v * B[2] + w * C[2];
                if (z > ahead) ahead = z;
            }
        }
        printf("    %s: the sheet over its centre ends %.4f m ahead of it\n", shape == 0 ? "sphere r 0.04" : shape == 1 ? "capsule r 0.02" : "box 0.08 x 0.08 x 0.06",
               ahead - (double)b.translation[2]);
        ENSURE(ahead > (double)b.translation[2]);
        {
            check_result r = check_scene(&s, s.x1, 1, 0, NULL, 1e-5);
            ENSURE(r.intersecting == 0);
        }
        cloth_contact_destroy(c);
        scene_free(&s);
    }
}

/* ===================================================================================== */
/* cloth against cloth                                                                   */
/* ===================================================================================== */

/* Two sheets 4 cm apart; the upper one is pushed down by `drop` in one step, through the
   lower one. Afterwards the motion is free of crossings and the end free of intersections. */
static void sheet_through_sheet(int32_t nx, double drop, int pin_lower, check_result *res, cloth_contact_stats *st,
                                cloth_real **out, int32_t *out_n, cloth_result *rr, scene *keep)
{
    scene s;
    cloth_pose lower = cloth_pose_identity(), upper = cloth_pose_identity();
    cloth_contact *c;
    int32_t i;
    memset(&s, 0, sizeof s);
    upper.translation[0] = (cloth_real)0.013;
    upper.translation[1] = (cloth_real)0.04;
    upper.translation[2] = (cloth_real)-0.021;
    scene_add_grid(&s, nx, nx, 1, 1, &lower, 0);
    scene_add_grid(&s, nx, nx, (cloth_real)0.8, (cloth_real)0.8, &upper, 1);
    for (i = nx * nx; i < s.n; ++i) {
        s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - drop);
        s.x1[3 * i] = (cloth_real)((double)s.x1[3 * i] + 0.01 * sin(3.0 * i));
    }
    if (pin_lower)
        for (i = 0; i < nx * nx; i += 3) s.invm[i] = 0;
    c = scene_contact(&s, 0, 1);
    *rr = cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, st);
    if (res) *res = check_scene(&s, s.x1, 0, 1, NULL, 0.5 * 0.25e-3);
    if (out) {
        *out = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
        memcpy(*out, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
        *out_n = s.n;
    }
    cloth_contact_destroy(c);
    if (keep) *keep = s;
    else scene_free(&s);
}

TEST(sheet_pushed_through_sheet)
{
    check_result res;
    cloth_contact_stats st;
    cloth_result r;
    scene s;
    int32_t i;
    sheet_through_sheet(9, 0.1, 1, &res, &st, NULL, NULL, &r, &s);
    print_stats("sheet 9x9 through 9x9, drop 0.1", &st);
    ENSURE(r == CLOTH_SUCCESS);
    ENSURE(res.close_pairs == 0);
    ENSURE(res.intersecting == 0);
    ENSURE(st.impacts > 0 && st.impact_zones > 0);
    /* pinned vertices never move */
    for (i = 0; i < 81; i += 3) ENSURE(memcmp(s.x0 + 3 * i, s.x1 + 3 * i, 3 * sizeof(cloth_real)) == 0);
    scene_free(&s);
    /* a larger push, nothing pinned */
    sheet_through_sheet(8, 0.3, 0, &res, &st, NULL, NULL, &r, NULL);
    print_stats("sheet 8x8 through 8x8, drop 0.3", &st);
    ENSURE(r == CLOTH_SUCCESS);
    ENSURE(res.close_pairs == 0);
    ENSURE(res.intersecting == 0);
}

/* def.round_check: called after every round of zone projections; a nonzero answer stops the
   resolve with CLOTH_ERROR_COLLISION_UNRESOLVED, x1 as it came in and stats.stopped set; a
   check that always answers 0 changes nothing. */
static long round_checks;
static long round_check_stop_at; /* stop at this call (1 = the first); 0: never */
static int round_check_count(void *user, const cloth_real *x1)
{
    (void)user;
    (void)x1;
    ++round_checks;
    return round_check_stop_at > 0 && round_checks >= round_check_stop_at;
}

TEST(round_check_stops_the_resolve)
{
    cloth_real *plain, *checked;
    int32_t n_plain, n_checked, i, nx = 8;
    cloth_contact_stats s_plain, s_checked, s_stopped;
    cloth_result r_plain, r_checked, r_stopped;
    scene s;
    const double drop = 0.3;
    long rounds;
    sheet_through_sheet(nx, drop, 0, NULL, &s_plain, &plain, &n_plain, &r_plain, NULL);
    scene_round_check = round_check_count;
    round_checks = 0;
    round_check_stop_at = 0;
    sheet_through_sheet(nx, drop, 0, NULL, &s_checked, &checked, &n_checked, &r_checked, NULL);
    rounds = round_checks;
    round_checks = 0;
    round_check_stop_at = 2;
    sheet_through_sheet(nx, drop, 0, NULL, &s_stopped, NULL, NULL, &r_stopped, &s);
    scene_round_check = NULL;
    printf("    sheet 8x8 through 8x8: %ld projection rounds, %d detection rounds; stopped at the second\n", rounds,
           (int)s_plain.rounds);
    ENSURE(r_plain == CLOTH_SUCCESS && r_checked == CLOTH_SUCCESS && n_plain == n_checked);
    ENSURE(memcmp(plain, checked, sizeof(cloth_real) * 3 * (size_t)n_plain) == 0);
    ENSURE(s_plain.rounds == s_checked.rounds && s_plain.qp_iterations == s_checked.qp_iterations);
    ENSURE(!s_plain.stopped && !s_checked.stopped);
    ENSURE(rounds >= 2 && rounds < s_plain.rounds);
    ENSURE(r_stopped == CLOTH_ERROR_COLLISION_UNRESOLVED && s_stopped.stopped == 1 && round_checks == 2);
    /* x1 as it came in: the lower sheet where it was, the upper one's proposal */
    for (i = 0; i < s.n; ++i) {
        cloth_real want[3];
        want[0] = s.x0[3 * i];
        want[1] = s.x0[3 * i + 1];
        want[2] = s.x0[3 * i + 2];
        if (i >= nx * nx) {
            want[1] = (cloth_real)((double)want[1] - drop);
            want[0] = (cloth_real)((double)want[0] + 0.01 * sin(3.0 * i));
        }
        ENSURE(memcmp(want, s.x1 + 3 * i, sizeof want) == 0);
    }
    scene_free(&s);
    free(plain);
    free(checked);
}

/* A sheet set down on another, slowly (0.85 mm in the step, less than the 1 mm thickness),
   ending 0.15 mm above it, inside the detection separation: these pairs are certain contacts,
   answered without a CCD search (stats.ccd_certain), and the response still keeps every pair
   apart along the whole path (the independent check) and ends the sheets apart. */
TEST(resting_sheet_pairs_are_certain_contacts)
{
    scene s;
    cloth_pose lower = cloth_pose_identity(), upper = cloth_pose_identity();
    cloth_contact *c;
    cloth_contact_stats st;
    check_result res;
    int32_t i, j;
    double gap = HUGE_VAL, below = 0;
    memset(&s, 0, sizeof s);
    upper.translation[0] = (cloth_real)0.011;
    upper.translation[1] = (cloth_real)1e-3;
    upper.translation[2] = (cloth_real)-0.007;
    ENSURE(scene_add_grid(&s, 7, 7, 0.3, 0.3, &lower, 0));
    ENSURE(scene_add_grid(&s, 6, 6, 0.24, 0.24, &upper, 1));
    for (i = 49; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)0.15e-3;
    c = scene_contact(&s, 0, 1);
    ENSURE(c != NULL);
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
    print_stats("sheet set down on a sheet, 0.85 mm", &st);
    res = check_scene(&s, s.x1, 0, 1, NULL, 0.5 * 0.25e-3);
    /* every upper vertex ends above the lower sheet (flat, moved as one) by more than d */
    for (j = 0; j < 49; ++j) below += (double)s.x1[3 * j + 1] / 49;
    for (i = 49; i < s.n; ++i)
        if ((double)s.x1[3 * i + 1] - below < gap) gap = (double)s.x1[3 * i + 1] - below;
    printf("    certain contacts %d of %d impacts, smallest vertical gap %.3g mm\n", (int)st.ccd_certain, (int)st.impacts, 1e3 * gap);
    cloth_contact_destroy(c);
    scene_free(&s);
    ENSURE(st.ccd_certain > 0);
    ENSURE(st.impacts >= st.ccd_certain);
    ENSURE(res.close_pairs == 0);
    ENSURE(res.intersecting == 0);
    ENSURE(gap > 0.25e-3);
    scene_free(&s);
}

/* The right half of a sheet folds over the left half about the line x = 0, in steps of a
   rotation, each step's proposal being the rotated positions; the last ones turn it past
   flat, into the left half (pinned). Every step's motion is free of crossings. */
TEST(cloth_folding_onto_itself)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_contact *c;
    double angles[6] = {1.2, 2.2, 2.8, 3.05, 3.2, 3.4};
    int32_t i, step, nx = 11;
    cloth_real *x;
    memset(&s, 0, sizeof s);
    ENSURE(scene_add_grid(&s, nx, nx, 1, 1, &id, 0));
    for (i = 0; i < s.n; ++i)
        if ((double)s.x0[3 * i] < -1e-9) s.invm[i] = 0; /* left half pinned */
    c = scene_contact(&s, 1, 0);
    ENSURE(c != NULL);
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    memcpy(x, s.x0, sizeof(cloth_real) * 3 * (size_t)s.n);
    for (step = 0; step < 6; ++step) {
        cloth_contact_stats st;
        cloth_result r;
        check_result res;
        char name[64];
        /* x0 = where the last step ended, x1 = the flat rest positions rotated by the angle */
        memcpy(s.x0, x, sizeof(cloth_real) * 3 * (size_t)s.n);
        for (i = 0; i < s.n; ++i) {
            double px = (double)x[3 * i], a = angles[step];
            (void)px;
            if (s.invm[i] == 0) { memcpy(s.x1 + 3 * i, s.x0 + 3 * i, 3 * sizeof(cloth_real)); continue; }
            {
                double rx = 0.5 + (double)(i % nx) / (nx - 1) - 1.0; /* rest x in [-0.5, 0.5] */
                s.x1[3 * i] = (cloth_real)(rx * cos(a));
                s.x1[3 * i + 1] = (cloth_real)(rx * sin(a) + 0.002 * rx);
                s.x1[3 * i + 2] = s.x0[3 * i + 2];
            }
        }
        r = cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st);
        snprintf(name, sizeof name, "fold step %d (%.2f rad)", step, angles[step]);
        print_stats(name, &st);
        ENSURE(r == CLOTH_SUCCESS);
        res = check_scene(&s, s.x1, 1, 0, NULL, 0.5 * 0.25e-3);
        ENSURE(res.close_pairs == 0);
        ENSURE(res.intersecting == 0);
        for (i = 0; i < s.n; ++i)
            if (s.invm[i] == 0) ENSURE(memcmp(s.x0 + 3 * i, s.x1 + 3 * i, 3 * sizeof(cloth_real)) == 0);
        if (step >= 4) ENSURE(st.impacts > 0);
        memcpy(x, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
    }
    /* the folded half lies on top of the left half (positive y over it) */
    for (i = 0; i < s.n; ++i)
        if (s.invm[i] != 0 && (double)x[3 * i] < -0.05) ENSURE((double)x[3 * i + 1] > 0);
    free(x);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* A sheet that falls as a whole, 5 cm in the step (its swept boxes overlap all their
   neighbours'): every candidate pair of triangles is culled in the frame that moves with it
   (stats.pairs_culled), before any distance or CCD query, and nothing moves. */
TEST(falling_sheet_pairs_are_culled_in_its_moving_frame)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_contact *c;
    cloth_contact_stats st;
    cloth_real *in;
    int32_t i;
    memset(&s, 0, sizeof s);
    ENSURE(scene_add_grid(&s, 16, 16, 0.3, 0.3, &id, 0));
    for (i = 0; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - 0.05);
    in = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    memcpy(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
    c = scene_contact(&s, 1, 0);
    ENSURE(c != NULL);
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
    print_stats("16 x 16 sheet falling 5 cm", &st);
    ENSURE(st.candidate_pairs > 0);
    ENSURE(st.pairs_culled == st.candidate_pairs);
    ENSURE(st.ccd_queries == 0);
    ENSURE(st.impacts == 0);
    ENSURE(memcmp(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n) == 0);
    free(in);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* The self pairs from the neighbour list (NEIGHBOUR LIST in the implementation) are exactly
   the pairs whose boxes overlap: a 24 x 24 sheet carried down at 2 cm a step (the list kept,
   every triangle held), then with a corner folding up over the sheet (new pairs, found by a
   traversal over the corner's triangles, which the list no longer holds, while it is kept),
   the sheet folded 90 degrees about a line (the list made again), then each vertex on a
   random walk of up to 0.8 mm per axis a step (the list kept in most steps; a list that held
   vertices up to 3 r from their boxes, not r, misses 2 of 2528 pairs in the 38th step). In every step, one round without impacts, stats.candidate_pairs
   equals the number of non-adjacent triangle pairs whose swept boxes, grown as the tree's
   (0.5 detection_ratio thickness (1 + 2 tol)), overlap, counted by brute force. */
TEST(neighbour_list_gives_the_traversals_pairs)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_contact *c;
    const cloth_contact_def *d;
    cloth_rng g;
    cloth_real *rest, *path, th;
    double *walk;
    int32_t i, j, step, steps = 40, builds[4] = { 0, 0, 0, 0 }, unheld[4] = { 0, 0, 0, 0 }, first_pairs = 0;
    int more_pairs = 0;
    memset(&s, 0, sizeof s);
    g = cloth_rng_make(41);
    ENSURE(scene_add_grid(&s, 24, 24, 0.3, 0.3, &id, 0));
    c = scene_contact(&s, 1, 0);
    ENSURE(c != NULL);
    d = cloth_contact_get_def(c);
    th = (cloth_real)(0.5 * (double)d->detection_ratio * (double)d->thickness * (1 + 2 * (double)d->ccd_relative_tolerance));
    rest = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    path = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n * (size_t)(steps + 1));
    walk = (double *)calloc(3 * (size_t)s.n, sizeof(double));
    memcpy(rest, s.x0, sizeof(cloth_real) * 3 * (size_t)s.n);
    for (step = 0; step <= steps; ++step) {
        for (i = 0; i < s.n; ++i) {
            double p[3], x;
            int k;
            for (k = 0; k < 3; ++k) p[k] = (double)rest[3 * i + k];
            x = p[0];
            if (step >= 10 && x + p[2] < -0.18) {
                /* a corner folded up about the diagonal x + z = -0.18, up to 120 degrees */
                double a = 2.0943951023931953 * (step < 20 ? (step - 10) / 10.0 : 1), h = -0.18 - x - p[2];
                double r = h / 1.4142135623730951; /* distance from the line */
                p[0] += 0.5 * h * (1 - cos(a));
                p[2] += 0.5 * h * (1 - cos(a));
                p[1] += r * sin(a);
            }
            if (step >= 20 && x > 0.05) { /* folded about x = 0.05, up to 90 degrees */
                double a = 1.5707963267948966 * (step < 30 ? (step - 20) / 10.0 : 1), r = x - 0.05;
                p[0] = 0.05 + r * cos(a);
                p[1] += r * sin(a);
            }
            if (step >= 30) /* a random walk */
                for (k = 0; k < 3; ++k) {
                    walk[3 * i + k] += 0.0008 * (2 * (double)cloth_rng_uniform(&g) - 1);
                    p[k] += walk[3 * i + k];
                }
            p[1] -= 0.02 * step;
            for (k = 0; k < 3; ++k) path[3 * ((size_t)step * s.n + i) + k] = (cloth_real)p[k];
        }
    }
    for (step = 0; step < steps; ++step) {
        cloth_contact_stats st;
        int32_t brute = 0;
        memcpy(s.x0, path + 3 * (size_t)step * s.n, sizeof(cloth_real) * 3 * (size_t)s.n);
        memcpy(s.x1, path + 3 * (size_t)(step + 1) * s.n, sizeof(cloth_real) * 3 * (size_t)s.n);
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
        ENSURE(st.rounds == 1 && st.impacts == 0);
        for (i = 0; i < s.m; ++i)
            for (j = i + 1; j < s.m; ++j) {
                const int32_t *a = s.tri + 3 * i, *b = s.tri + 3 * j;
                int k, e, f, apart = 0;
                for (e = 0; e < 3; ++e)
                    for (f = 0; f < 3; ++f)
                        if (a[e] == b[f]) apart = 1; /* adjacent: never a candidate */
                for (k = 0; k < 3 && !apart; ++k) {
                    cloth_real alo = s.x0[3 * a[0] + k], ahi = alo, blo = s.x0[3 * b[0] + k], bhi = blo;
                    for (e = 0; e < 3; ++e) {
                        cloth_real v[4];
                        v[0] = s.x0[3 * a[e] + k]; v[1] = s.x1[3 * a[e] + k];
                        v[2] = s.x0[3 * b[e] + k]; v[3] = s.x1[3 * b[e] + k];
                        for (f = 0; f < 2; ++f) {
                            if (v[f] < alo) alo = v[f];
                            if (v[f] > ahi) ahi = v[f];
                            if (v[2 + f] < blo) blo = v[2 + f];
                            if (v[2 + f] > bhi) bhi = v[2 + f];
                        }
                    }
                    alo -= th; ahi += th; blo -= th; bhi += th;
                    if (alo > bhi || blo > ahi) apart = 1;
                }
                brute += !apart;
            }
        if (verbose()) printf("    step %d: candidates %d, brute force %d, list builds %d, unheld %d\n", step, st.candidate_pairs, brute, st.list_builds, st.list_unheld);
        ENSURE(st.candidate_pairs == brute);
        if (step == 9) first_pairs = brute;
        if (st.list_builds == 0 && st.list_unheld > 0 && brute > first_pairs) more_pairs = 1;
        builds[step / 10] += st.list_builds;
        unheld[step / 10] += st.list_unheld;
    }
    /* made at the start only while the sheet is carried, and held all through */
    ENSURE(builds[0] == 1 && unheld[0] == 0);
    /* the folding corner: new pairs found by the traversal over it while the list was kept */
    ENSURE(more_pairs);
    /* the fold made it again; the random walk kept it in most steps */
    ENSURE(builds[2] > 0 && builds[3] < 5);
    free(rest);
    free(path);
    free(walk);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* Two triangles for moving_frame_cull_misses_nothing, P[0..2] and P[3..5], with s = the
   separation it aims at. Odd trials: a vertex of the first triangle s from the plane of the
   second, which lies across the foot of that vertex, and the rest of the first triangle
   behind the vertex, all along an axis that is one of the cull's nine (the coordinate axes
   and face diagonals): the pair is s apart, and s apart along the axis, the tightest case
   of the cull. Even trials: two random triangles about a centimetre across, the second moved
   along the line between their centres until its nearest primitive pair is s apart. */
static void cull_trial_pair(cloth_rng *g, int trial, double s, double P[6][3])
{
    static const double axes[9][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 0 }, { 1, -1, 0 },
                                       { 1, 0, 1 }, { 1, 0, -1 }, { 0, 1, 1 }, { 0, 1, -1 } };
    double a[3], b1[3], b2[3], t[3] = { 0.3, -0.5, 0.8 }, len, best = HUGE_VAL, n[3];
    int j, k, e, f;
    if (trial % 2) {
        const double *ax = axes[trial / 2 % 9];
        len = d3len(ax);
        for (k = 0; k < 3; ++k) a[k] = ax[k] / len;
        d3cross(a, t, b1);
        len = d3len(b1);
        for (k = 0; k < 3; ++k) b1[k] /= len;
        d3cross(a, b1, b2);
        for (k = 0; k < 3; ++k) P[0][k] = 0.002 * (2 * (double)cloth_rng_uniform(g) - 1);
        for (j = 1; j < 3; ++j) {
            double back = 0.005 + 0.005 * (double)cloth_rng_uniform(g), u = 0.01 * (2 * (double)cloth_rng_uniform(g) - 1),
                   v = 0.01 * (2 * (double)cloth_rng_uniform(g) - 1);
            for (k = 0; k < 3; ++k) P[j][k] = P[0][k] - back * a[k] + u * b1[k] + v * b2[k];
        }
        {
            double th = 6.283185307179586 * (double)cloth_rng_uniform(g);
            for (j = 0; j < 3; ++j) {
                double c = cos(th + 2.0943951023931953 * j), sn = sin(th + 2.0943951023931953 * j);
                for (k = 0; k < 3; ++k) P[3 + j][k] = P[0][k] + s * a[k] + 0.01 * (c * b1[k] + sn * b2[k]);
            }
        }
        return;
    }
    for (k = 0; k < 3; ++k) n[k] = 2 * (double)cloth_rng_uniform(g) - 1;
    len = d3len(n);
    if (!(len > 0.1)) { n[0] = 1; n[1] = n[2] = 0; len = 1; }
    for (k = 0; k < 3; ++k) n[k] /= len;
    for (j = 0; j < 6; ++j)
        for (k = 0; k < 3; ++k) P[j][k] = 0.01 * (2 * (double)cloth_rng_uniform(g) - 1) + (j >= 3 ? 0.015 * n[k] : 0);
    for (j = 0; j < 3; ++j) {
        double D = point_triangle(P[j], P[3], P[4], P[5]);
        if (D < best) best = D;
        D = point_triangle(P[3 + j], P[0], P[1], P[2]);
        if (D < best) best = D;
    }
    for (e = 0; e < 3; ++e)
        for (f = 0; f < 3; ++f) {
            double D = segment_segment(P[e], P[(e + 1) % 3], P[3 + f], P[3 + (f + 1) % 3]);
            if (D < best) best = D;
        }
    for (j = 3; j < 6; ++j)
        for (k = 0; k < 3; ++k) P[j][k] += (s - best) * n[k];
}

/* The moving-frame cull (stats.pairs_culled) never drops a pair that could come within reach:
   two free triangles (cull_trial_pair) 0.5 d to 4 d apart, d the detection separation,
   carried by a common translation of up to 5 cm, with relative motions of up to 0, d/4, d or
   4 d per vertex and axis. Whenever the pair is culled, every vertex-face and edge-edge pair
   of the two must stay farther than sqrt 3 d (1 + tol) (the farthest the CCD reports) over
   the whole path, proven by the Lipschitz bisection path_min_distance; a pair that starts
   outside the band of close pairs and comes within d at a sampled time must give an impact. */
TEST(moving_frame_cull_misses_nothing)
{
    cloth_contact_def def = cloth_default_contact_def();
    cloth_real x0[18], x1[18], invm[6] = { 1, 1, 1, 1, 1, 1 };
    int32_t tri[6] = { 0, 1, 2, 3, 4, 5 }, piece[2] = { 0, 0 };
    cloth_rng g = cloth_rng_make(7);
    cloth_contact *c = NULL;
    const double d = (double)def.detection_ratio * (double)def.thickness, tol = (double)def.ccd_relative_tolerance;
    const double reach = 1.7320508075688772 * d * (1 + tol);
    int trial, culled = 0, culled_near = 0, touching = 0, touching_found = 0;
    def.vertex_count = 6;
    def.tri = tri;
    def.triangle_count = 2;
    def.triangle_piece = piece;
    def.self_collision = 1;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
    for (trial = 0; trial < 4000; ++trial) {
        double P[6][3], Q[6][3], u[3], lo = HUGE_VAL, sampled = HUGE_VAL, start = HUGE_VAL;
        double amplitude = trial / 2 % 4 == 0 ? 0 : (trial / 2 % 4 == 1 ? 0.25 * d : (trial / 2 % 4 == 2 ? d : 4 * d));
        cloth_contact_stats st;
        cloth_result r;
        int j, k, q;
        cull_trial_pair(&g, trial, d * (0.5 + 3.5 * (double)cloth_rng_uniform(&g)), P);
        for (k = 0; k < 3; ++k) u[k] = 0.05 * (2 * (double)cloth_rng_uniform(&g) - 1);
        for (j = 0; j < 6; ++j)
            for (k = 0; k < 3; ++k) {
                x0[3 * j + k] = (cloth_real)P[j][k];
                x1[3 * j + k] = (cloth_real)(P[j][k] + u[k] + amplitude * (2 * (double)cloth_rng_uniform(&g) - 1));
            }
        /* the positions the contact module sees */
        for (j = 0; j < 6; ++j)
            for (k = 0; k < 3; ++k) { P[j][k] = (double)x0[3 * j + k]; Q[j][k] = (double)x1[3 * j + k]; }
        /* over the path: a proven lower bound (0 when not proven beyond reach) and samples */
        for (j = 0; j < 15; ++j) {
            double A0[4][3], A1[4][3], m;
            int ee = j >= 6, idx[4];
            if (!ee) {
                idx[0] = j;
                for (q = 0; q < 3; ++q) idx[1 + q] = (j < 3 ? 3 : 0) + q;
            } else {
                int e = (j - 6) / 3, f = (j - 6) % 3;
                idx[0] = e; idx[1] = (e + 1) % 3; idx[2] = 3 + f; idx[3] = 3 + (f + 1) % 3;
            }
            for (q = 0; q < 4; ++q)
                for (k = 0; k < 3; ++k) { A0[q][k] = P[idx[q]][k]; A1[q][k] = Q[idx[q]][k]; }
            m = path_min_distance(ee, A0, A1, reach);
            if (m < 0) m = 0;
            if (m < lo) lo = m;
            for (q = 0; q <= 64; ++q) {
                double at = pair_distance(ee, A0, A1, q / 64.0);
                if (at < sampled) sampled = at;
                if (q == 0 && at < start) start = at;
            }
        }
        r = cloth_contact_resolve(c, x0, x1, invm, (cloth_real)(1.0 / 60), NULL, &st);
        ENSURE(r == CLOTH_SUCCESS);
        if (st.candidate_pairs > 0 && st.pairs_culled == st.candidate_pairs) { /* culled in every round, the first included */
            ++culled;
            culled_near += lo < 3 * d;
            if (!(lo >= reach)) printf("    trial %d culled, path distance not proven beyond reach (%.3g d)\n", trial, reach / d);
            ENSURE(lo >= reach);
        } else if (sampled < d && start > 1.01 * reach) {
            ++touching;
            touching_found += st.impacts > 0;
        }
    }
    if (verbose()) printf("    culled %d of 4000 (%d within 3 d), %d came within d, %d of those found\n", culled, culled_near, touching, touching_found);
    ENSURE(culled > 500);
    ENSURE(culled_near > 100);
    ENSURE(touching > 30);
    ENSURE(touching_found == touching);
    cloth_contact_destroy(c);
}

/* A quad of two triangles, (0, 1, 2) and (0, 2, 3) sharing the diagonal 0-2, with 0, 2 and 3
   pinned; corner 1 folds across the diagonal through triangle (0, 2, 3). Every triangle around
   vertex 1 shares a vertex with that face, so the vertex-face pair belongs to the adjacent
   pair, which the tree skips (the contact's list of adjacent pairs): it must still be caught. */
TEST(corner_folding_through_its_neighbour)
{
    scene s;
    cloth_contact *c;
    cloth_contact_stats st;
    check_result before, after;
    int32_t i;
    const cloth_real x0[12] = {0, 0, 0, 1, (cloth_real)0.09, 0, 1, 0, 1, 0, 0, 1};
    const int32_t tri[6] = {0, 1, 2, 0, 2, 3};
    memset(&s, 0, sizeof s);
    s.n = 4;
    s.m = 2;
    s.x0 = (cloth_real *)malloc(sizeof(cloth_real) * 12);
    s.x1 = (cloth_real *)malloc(sizeof(cloth_real) * 12);
    s.invm = (cloth_real *)malloc(sizeof(cloth_real) * 4);
    s.tri = (int32_t *)malloc(sizeof(int32_t) * 6);
    s.piece = (int32_t *)calloc(2, sizeof(int32_t));
    memcpy(s.x0, x0, sizeof x0);
    memcpy(s.x1, x0, sizeof x0);
    memcpy(s.tri, tri, sizeof tri);
    for (i = 0; i < 4; ++i) s.invm[i] = i == 1 ? 1 : 0;
    /* corner 1 from (1, 0.09, 0) to (0.1, -0.01, 0.9): it crosses y = 0 at t = 0.9, at
       (0.19, 0, 0.81), inside triangle (0, 2, 3) */
    s.x1[3] = (cloth_real)0.1;
    s.x1[4] = (cloth_real)-0.01;
    s.x1[5] = (cloth_real)0.9;
    before = check_scene(&s, s.x1, 1, 0, NULL, 0.5 * 0.25e-3);
    ENSURE(before.close_pairs > 0); /* the motion does pass through */
    c = scene_contact(&s, 1, 0);
    ENSURE(c != NULL);
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
    print_stats("corner fold", &st);
    ENSURE(st.candidate_pairs == 0); /* no pair from the tree: the adjacent pair found it */
    ENSURE(st.impacts > 0);
    after = check_scene(&s, s.x1, 1, 0, NULL, 0.5 * 0.25e-3);
    ENSURE(after.close_pairs == 0);
    ENSURE((double)s.x1[4] > 0); /* stopped above the pinned triangle */
    cloth_contact_destroy(c);
    /* with self-collision off nothing is tested, and the corner goes through */
    c = scene_contact(&s, 0, 0);
    ENSURE(c != NULL);
    s.x1[3] = (cloth_real)0.1;
    s.x1[4] = (cloth_real)-0.01;
    s.x1[5] = (cloth_real)0.9;
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
    ENSURE(st.impacts == 0);
    ENSURE((double)s.x1[4] < 0);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* ===================================================================================== */
/* mesh obstacles                                                                        */
/* ===================================================================================== */

/* A sheet dropped onto a static box mesh, then a box mesh that rises fast into a sheet. */
TEST(mesh_obstacle)
{
    int moving;
    for (moving = 0; moving < 2; ++moving) {
        scene s;
        cloth_pose id = cloth_pose_identity();
        cloth_mesh box;
        cloth_obstacle_def od = cloth_default_obstacle_def();
        cloth_contact *c;
        cloth_contact_stats st;
        check_mesh cm;
        check_result res;
        cloth_real *y0, *y1;
        int32_t i, o;
        memset(&s, 0, sizeof s);
        ENSURE(cloth_mesh_box(&box, (cloth_real)0.2, (cloth_real)0.2, (cloth_real)0.2, 3, NULL) == CLOTH_SUCCESS);
        id.translation[1] = (cloth_real)0.25;
        id.translation[0] = (cloth_real)0.011;
        ENSURE(scene_add_grid(&s, 12, 12, 1, 1, &id, 0));
        for (i = 0; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - (moving ? 0.0 : 0.15));
        c = scene_contact(&s, 1, 1);
        ENSURE(c != NULL);
        od.shape = CLOTH_OBSTACLE_MESH;
        od.mesh_x = box.x;
        od.mesh_vertex_count = box.vertex_count;
        od.mesh_tri = box.tri;
        od.mesh_triangle_count = box.triangle_count;
        ENSURE(cloth_contact_add_obstacle(c, &od, &o) == CLOTH_SUCCESS);
        y0 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)box.vertex_count);
        y1 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)box.vertex_count);
        for (i = 0; i < 3 * box.vertex_count; ++i) y0[i] = y1[i] = box.x[i];
        if (moving) { /* the box rises from below through where the sheet is, 0.3 m in the step */
            for (i = 0; i < box.vertex_count; ++i) {
                y0[3 * i + 1] = (cloth_real)((double)box.x[3 * i + 1] - 0.1);
                y1[3 * i + 1] = (cloth_real)((double)box.x[3 * i + 1] + 0.2);
            }
            ENSURE(cloth_contact_set_obstacle_vertices(c, o, y0, y1) == CLOTH_SUCCESS);
        }
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
        print_stats(moving ? "box mesh rising through a sheet" : "sheet dropped onto a box mesh", &st);
        ENSURE(st.impacts > 0);
        cm.n = box.vertex_count; cm.m = box.triangle_count; cm.y0 = y0; cm.y1 = y1; cm.tri = box.tri;
        res = check_scene(&s, s.x1, 1, 1, &cm, 0.5 * 0.25e-3);
        ENSURE(res.close_pairs == 0);
        ENSURE(res.intersecting == 0);
        /* the cloth over the box top stays above it */
        for (i = 0; i < s.n; ++i)
            if (fabs((double)s.x1[3 * i]) < 0.15 && fabs((double)s.x1[3 * i + 2]) < 0.15) ENSURE((double)s.x1[3 * i + 1] > 0.2 + (moving ? 0.2 : 0.0));
        free(y0); free(y1);
        cloth_mesh_free(&box);
        cloth_contact_destroy(c);
        scene_free(&s);
    }
}


/* Random proposals that tangle a sheet with itself (every vertex moved up to `amp` in each
   axis, neighbours independently). Whatever the resolve answers must hold: on success the
   motion is free of crossings and the end free of intersections, on failure x1 is as given. */
TEST(random_tangles)
{
    int seed, ok = 0, failed = 0;
    for (seed = 1; seed <= 8; ++seed) {
        scene s;
        cloth_pose id = cloth_pose_identity();
        cloth_rng g = cloth_rng_make((uint64_t)seed);
        cloth_contact *c;
        cloth_contact_stats st;
        cloth_result r;
        cloth_real *in;
        double amp = seed <= 4 ? 0.1 : (seed <= 6 ? 0.3 : 0.6);
        int32_t i;
        char name[64];
        memset(&s, 0, sizeof s);
        ENSURE(scene_add_grid(&s, 10, 10, 1, 1, &id, 0));
        for (i = 0; i < 3 * s.n; ++i) s.x1[i] = (cloth_real)((double)s.x1[i] + amp * (2 * (double)cloth_rng_uniform(&g) - 1));
        if (seed % 3 == 0) s.invm[0] = s.invm[9] = 0;
        for (i = 0; i < s.n; ++i) if (s.invm[i] == 0) memcpy(s.x1 + 3 * i, s.x0 + 3 * i, 3 * sizeof(cloth_real));
        in = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
        memcpy(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
        c = scene_contact(&s, 1, 0);
        ENSURE(c != NULL);
        r = cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st);
        snprintf(name, sizeof name, "random tangle %d (amp %.2f): result %d", seed, amp, (int)r);
        print_stats(name, &st);
        if (r == CLOTH_SUCCESS) {
            check_result res = check_scene(&s, s.x1, 1, 0, NULL, 0.5 * 0.25e-3);
            ENSURE(res.close_pairs == 0);
            ENSURE(res.intersecting == 0);
            for (i = 0; i < s.n; ++i)
                if (s.invm[i] == 0) ENSURE(memcmp(s.x0 + 3 * i, s.x1 + 3 * i, 3 * sizeof(cloth_real)) == 0);
            ++ok;
        } else {
            ENSURE(r == CLOTH_ERROR_COLLISION_UNRESOLVED);
            ENSURE(memcmp(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n) == 0);
            ++failed;
        }
        free(in);
        cloth_contact_destroy(c);
        scene_free(&s);
    }
    if (verbose()) printf("    random tangles: %d resolved, %d unresolved\n", ok, failed);
    ENSURE(ok >= 7);
}

/* A sheet resting on a flat mesh obstacle and sliding at 1 m/s: the impact rows of the step
   (gravity pushes it in by h^2 g) give it a normal impulse m g h, and the velocity pass takes
   mu m g h of tangential momentum away (friction of a mesh obstacle acts on velocities). */
TEST(friction_on_a_mesh_obstacle)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_real floor_x[12] = {-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, 2};
    int32_t floor_tri[6] = {0, 2, 1, 0, 3, 2};
    cloth_contact *c;
    cloth_contact_stats st;
    cloth_real *v;
    double h = 1.0 / 60, mu = 0.4;
    int32_t i;
    memset(&s, 0, sizeof s);
    id.translation[1] = (cloth_real)1e-3;
    ENSURE(scene_add_grid(&s, 6, 6, (cloth_real)0.5, (cloth_real)0.5, &id, 0));
    for (i = 0; i < s.n; ++i) {
        s.x1[3 * i] = (cloth_real)((double)s.x0[3 * i] + h * 1.0);
        s.x1[3 * i + 1] = (cloth_real)((double)s.x0[3 * i + 1] - h * h * 9.81);
    }
    c = scene_contact(&s, 1, 0);
    ENSURE(c != NULL);
    od.shape = CLOTH_OBSTACLE_MESH;
    od.mesh_x = floor_x; od.mesh_vertex_count = 4; od.mesh_tri = floor_tri; od.mesh_triangle_count = 2;
    od.friction_static = od.friction_kinetic = (cloth_real)mu;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS);
    v = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    ENSURE(cloth_contact_resolve(c, s.x0, s.x1, NULL, (cloth_real)h, v, &st) == CLOTH_SUCCESS);
    print_stats("sheet sliding on a mesh floor", &st);
    ENSURE(st.friction_rows > 0);
    for (i = 0; i < s.n; ++i) {
        ENSURE((double)s.x1[3 * i + 1] >= 1e-3 * (1 - REL));
        ENSURE((double)v[3 * i + 1] >= -VABS);
    }
    {
        /* momentum: the mean tangential velocity drops by mu g h */
        double mean = 0;
        for (i = 0; i < s.n; ++i) mean += (double)v[3 * i];
        mean /= s.n;
        if (verbose()) printf("    mean v_x after the step %.6f (expected %.6f)\n", mean, 1 - mu * 9.81 * h);
        ENSURE_NEAR(mean, 1 - mu * 9.81 * h, 0.1 * mu * 9.81 * h);
    }
    free(v);
    cloth_contact_destroy(c);
    scene_free(&s);
}

/* ===================================================================================== */
/* failures, determinism, memory, arguments                                              */
/* ===================================================================================== */

TEST(unresolvable_cases_fail_and_keep_x1)
{
    /* a pinned vertex inside a static sphere */
    {
        cloth_obstacle_def od = cloth_default_obstacle_def();
        cloth_contact *c;
        cloth_real x0[3] = {0, (cloth_real)0.1, 0}, x1[3] = {0, (cloth_real)0.1, 0}, invm = 0, v[3] = {7, 7, 7};
        od.shape = CLOTH_OBSTACLE_SPHERE;
        od.radius = (cloth_real)0.3;
        c = single_vertex(&od);
        ENSURE(c != NULL);
        ENSURE(cloth_contact_resolve(c, x0, x1, &invm, (cloth_real)0.01, v, NULL) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(x1[0] == 0 && x1[1] == (cloth_real)0.1 && x1[2] == 0);
        ENSURE(v[0] == 7 && v[1] == 7 && v[2] == 7);
        /* the same vertex free is pushed out */
        invm = 1;
        ENSURE(cloth_contact_resolve(c, x0, x1, &invm, (cloth_real)0.01, v, NULL) == CLOTH_SUCCESS);
        ENSURE(sdf_world(&od, &od.pose, x1) >= 1e-3 * (1 - REL));
        cloth_contact_destroy(c);
    }
    /* two sheets, all pinned, forced through each other */
    {
        scene s;
        cloth_real *in;
        cloth_contact *c;
        cloth_contact_stats st;
        int32_t i;
        cloth_pose lower = cloth_pose_identity(), upper = cloth_pose_identity();
        memset(&s, 0, sizeof s);
        upper.translation[1] = (cloth_real)0.05;
        upper.translation[0] = (cloth_real)0.017;
        scene_add_grid(&s, 5, 5, 1, 1, &lower, 0);
        scene_add_grid(&s, 5, 5, 1, 1, &upper, 1);
        for (i = 0; i < s.n; ++i) s.invm[i] = 0;
        for (i = 25; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - 0.1);
        in = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
        memcpy(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
        c = scene_contact(&s, 0, 1);
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)0.01, NULL, &st) == CLOTH_ERROR_COLLISION_UNRESOLVED);
        ENSURE(memcmp(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n) == 0);
        free(in);
        cloth_contact_destroy(c);
        scene_free(&s);
    }
    /* a free patch squeezed between two pinned sheets that close to 0.4 mm (the patch cannot
       keep the detection separation from both): the QP is infeasible, and the fail-safe cannot
       move the pinned sheets */
    {
        scene s;
        cloth_real *in;
        cloth_contact *c;
        cloth_contact_stats st;
        int32_t i;
        cloth_pose lower = cloth_pose_identity(), upper = cloth_pose_identity(), mid = cloth_pose_identity();
        memset(&s, 0, sizeof s);
        upper.translation[1] = (cloth_real)0.01;
        mid.translation[1] = (cloth_real)0.005;
        mid.translation[0] = (cloth_real)0.011;
        mid.translation[2] = (cloth_real)0.007;
        scene_add_grid(&s, 5, 5, 1, 1, &lower, 0);
        scene_add_grid(&s, 5, 5, 1, 1, &upper, 1);
        scene_add_grid(&s, 3, 3, (cloth_real)0.3, (cloth_real)0.3, &mid, 2);
        for (i = 0; i < 50; ++i) s.invm[i] = 0;
        for (i = 25; i < 50; ++i) s.x1[3 * i + 1] = (cloth_real)0.0004;
        in = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
        memcpy(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
        c = scene_contact(&s, 0, 1);
        {
            cloth_result rr = cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)0.01, NULL, &st);
            print_stats("squeezed between pinned sheets (unresolved)", &st);
            ENSURE(rr == CLOTH_ERROR_COLLISION_UNRESOLVED);
        }
        ENSURE(memcmp(in, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n) == 0);
        free(in);
        cloth_contact_destroy(c);
        scene_free(&s);
    }
}

/* The fail-safe: with one projection round allowed, the sheets of sheet_pushed_through_sheet
   are resolved by rigid impact zones, and the motion is still free of crossings. */
TEST(fail_safe_rigid_zones)
{
    int rounds;
    for (rounds = 1; rounds <= 2; ++rounds) {
        scene s;
        cloth_pose lower = cloth_pose_identity(), upper = cloth_pose_identity();
        cloth_contact_def def = cloth_default_contact_def();
        cloth_contact *c = NULL;
        cloth_contact_stats st;
        check_result res;
        int32_t i;
        memset(&s, 0, sizeof s);
        upper.translation[0] = (cloth_real)0.013; upper.translation[1] = (cloth_real)0.04; upper.translation[2] = (cloth_real)-0.021;
        scene_add_grid(&s, 7, 7, 1, 1, &lower, 0);
        scene_add_grid(&s, 7, 7, (cloth_real)0.8, (cloth_real)0.8, &upper, 1);
        for (i = 49; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - 0.12);
        def.vertex_count = s.n; def.tri = s.tri; def.triangle_count = s.m; def.triangle_piece = s.piece;
        def.piece_collision = 1;
        def.max_rounds = rounds;
        ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, s.invm, (cloth_real)(1.0 / 60), NULL, &st) == CLOTH_SUCCESS);
        print_stats(rounds == 1 ? "fail-safe after 1 projection round" : "fail-safe after 2 projection rounds", &st);
        ENSURE(st.rigid_rounds > 0 && st.rigid_zones + st.frozen_zones > 0);
        res = check_scene(&s, s.x1, 0, 1, NULL, 0.5 * 0.25e-3);
        ENSURE(res.close_pairs == 0);
        ENSURE(res.intersecting == 0);
        cloth_contact_destroy(c);
        scene_free(&s);
    }
}

TEST(deterministic)
{
    cloth_real *a, *b;
    int32_t na, nb;
    cloth_contact_stats sa, sb;
    cloth_result ra, rb;
    sheet_through_sheet(7, 0.12, 0, NULL, &sa, &a, &na, &ra, NULL);
    sheet_through_sheet(7, 0.12, 0, NULL, &sb, &b, &nb, &rb, NULL);
    ENSURE(ra == CLOTH_SUCCESS && rb == CLOTH_SUCCESS && na == nb);
    ENSURE(memcmp(a, b, sizeof(cloth_real) * 3 * (size_t)na) == 0);
    ENSURE(sa.impacts == sb.impacts && sa.rounds == sb.rounds && sa.qp_iterations == sb.qp_iterations);
    free(a);
    free(b);
}

/* A counting allocator. */
typedef struct counter { long allocs, frees; } counter;
static void *count_alloc(size_t size, void *user) { ((counter *)user)->allocs++; return malloc(size); }
static void count_free(void *p, void *user) { if (p) ((counter *)user)->frees++; free(p); }

/* A steady scene: a sheet resting on a plane and draped on a sphere and a mesh box, with self
   collision, stepped with the same proposal again and again: after the first call nothing is
   allocated. */
TEST(no_allocation_in_a_steady_scene)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_contact_def def = cloth_default_contact_def();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_contact *c = NULL;
    counter cnt = {0, 0};
    cloth_mesh box;
    cloth_real *prop, *v;
    long after_first;
    int32_t i;
    int k;
    memset(&s, 0, sizeof s);
    id.translation[1] = (cloth_real)0.0065;
    ENSURE(scene_add_grid(&s, 10, 10, 1, 1, &id, 0));
    id.translation[1] = (cloth_real)0.03;
    id.translation[0] = (cloth_real)0.05;
    ENSURE(scene_add_grid(&s, 4, 4, (cloth_real)0.3, (cloth_real)0.3, &id, 1));
    /* proposal: the sheet falls 8 mm onto the ground, the sphere and the box; the patch 3 cm onto the sheet */
    for (i = 0; i < s.n; ++i) s.x1[3 * i + 1] = (cloth_real)((double)s.x1[3 * i + 1] - (i < 100 ? 0.008 : 0.03));
    prop = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    v = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)s.n);
    memcpy(prop, s.x1, sizeof(cloth_real) * 3 * (size_t)s.n);
    def.vertex_count = s.n; def.tri = s.tri; def.triangle_count = s.m;
    def.self_collision = 1;
    def.piece_collision = 1;
    def.triangle_piece = s.piece;
    def.allocator.alloc = count_alloc; def.allocator.free = count_free; def.allocator.user = &cnt;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS); /* the ground */
    od.shape = CLOTH_OBSTACLE_SPHERE; od.radius = (cloth_real)0.1; od.pose.translation[0] = (cloth_real)0.3;
    od.pose.translation[1] = (cloth_real)-0.095;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_box(&box, (cloth_real)0.1, (cloth_real)0.05, (cloth_real)0.1, 1, NULL) == CLOTH_SUCCESS);
    od = cloth_default_obstacle_def();
    od.shape = CLOTH_OBSTACLE_MESH; od.mesh_x = box.x; od.mesh_vertex_count = box.vertex_count; od.mesh_tri = box.tri;
    od.mesh_triangle_count = box.triangle_count; od.pose.translation[0] = (cloth_real)-0.3;
    od.pose.translation[1] = (cloth_real)-0.047;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_SUCCESS);
    for (k = 0; k < 4; ++k) {
        cloth_contact_stats st;
        memcpy(s.x1, prop, sizeof(cloth_real) * 3 * (size_t)s.n);
        ENSURE(cloth_contact_resolve(c, s.x0, s.x1, NULL, (cloth_real)(1.0 / 60), v, &st) == CLOTH_SUCCESS);
        if (k == 0) { after_first = cnt.allocs; print_stats("steady scene", &st); ENSURE(st.impacts > 0 && st.obstacle_contacts > 0); }
    }
    ENSURE(cnt.allocs == after_first);
    cloth_contact_destroy(c);
    ENSURE(cnt.allocs == cnt.frees);
    cloth_mesh_free(&box);
    free(prop); free(v);
    scene_free(&s);
}

/* An allocator that fails from its fail_at-th call on (-1: never), counting the rest. */
typedef struct failing_counter { long allocs, frees, fail_at, calls; } failing_counter;
static void *failing_alloc(size_t size, void *user)
{
    failing_counter *f = (failing_counter *)user;
    if (f->fail_at >= 0 && f->calls++ >= f->fail_at) return NULL;
    f->allocs++;
    return malloc(size);
}
static void failing_free(void *p, void *user) { if (p) ((failing_counter *)user)->frees++; free(p); }

/* cloth_contact_create with each of its allocations failing in turn (the copies, the topology,
   the list of adjacent pairs): CLOTH_ERROR_OUT_OF_MEMORY, no contact, nothing leaked. */
TEST(create_out_of_memory_at_every_allocation)
{
    scene s;
    cloth_pose id = cloth_pose_identity();
    cloth_contact_def def = cloth_default_contact_def();
    cloth_contact *c = NULL;
    failing_counter f = {0, 0, -1, 0};
    long total, k;
    memset(&s, 0, sizeof s);
    ENSURE(scene_add_grid(&s, 6, 6, 1, 1, &id, 0));
    def.vertex_count = s.n; def.tri = s.tri; def.triangle_count = s.m;
    def.self_collision = 1;
    def.allocator.alloc = failing_alloc; def.allocator.free = failing_free; def.allocator.user = &f;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
    total = f.allocs;
    ENSURE(total >= 4);
    cloth_contact_destroy(c);
    ENSURE(f.frees == f.allocs);
    for (k = 0; k < total; ++k) {
        f.allocs = f.frees = f.calls = 0;
        f.fail_at = k;
        c = (cloth_contact *)&f; /* overwritten with NULL on failure */
        ENSURE(cloth_contact_create(&c, &def) == CLOTH_ERROR_OUT_OF_MEMORY);
        ENSURE(c == NULL);
        ENSURE(f.frees == f.allocs);
    }
    scene_free(&s);
}

TEST(arguments)
{
    cloth_contact_def def = cloth_default_contact_def();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_contact *c = NULL;
    int32_t tri[3] = {0, 1, 5};
    cloth_real x0[9] = {0}, x1[9] = {0};
    def.vertex_count = 3;
    def.tri = tri;
    def.triangle_count = 1;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_ERROR_INDEX_OUT_OF_RANGE && c == NULL);
    tri[2] = 2;
    def.thickness = 0;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.thickness = (cloth_real)1e-3;
    def.friction_kinetic = def.friction_static + 1;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.friction_kinetic = def.friction_static;
    ENSURE(def.ccd_refine_checks == 64);
    def.ccd_refine_checks = -1;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.ccd_refine_checks = 0;
    ENSURE(cloth_contact_create(&c, &def) == CLOTH_SUCCESS);
    od.thickness = -1;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    od = cloth_default_obstacle_def();
    od.shape = CLOTH_OBSTACLE_MESH;
    ENSURE(cloth_contact_add_obstacle(c, &od, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_contact_obstacle_count(c) == 0);
    x0[3] = 1; x0[7] = 1; x1[3] = 1; x1[7] = 1;
    ENSURE(cloth_contact_resolve(c, x0, x1, NULL, 0, NULL, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    x1[4] = (cloth_real)NAN;
    ENSURE(cloth_contact_resolve(c, x0, x1, NULL, (cloth_real)0.01, NULL, NULL) == CLOTH_ERROR_NOT_FINITE);
    x1[4] = 0;
    ENSURE(cloth_contact_resolve(c, x0, x1, NULL, (cloth_real)0.01, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_contact_move_obstacle(c, 3, &od.pose, &od.pose) == CLOTH_ERROR_INVALID_ARGUMENT);
    cloth_contact_destroy(c);
    cloth_contact_destroy(NULL);
}

const test_case contact_tests[] = {
    {"poses_interpolate_apply_and_invert", poses_interpolate_apply_and_invert},
    {"vertex_falls_onto_each_shape", vertex_falls_onto_each_shape},
    {"paths_ending_in_the_layer_are_pushed_out", paths_ending_in_the_layer_are_pushed_out},
    {"friction_sliding_on_a_plane", friction_sliding_on_a_plane},
    {"friction_on_an_incline", friction_on_an_incline},
    {"friction_with_moving_obstacles", friction_with_moving_obstacles},
    {"projectile_does_not_tunnel", projectile_does_not_tunnel},
    {"obstacles_smaller_than_cells_do_not_pass_between_vertices", obstacles_smaller_than_cells_do_not_pass_between_vertices},
    {"sheet_pushed_through_sheet", sheet_pushed_through_sheet},
    {"resting_sheet_pairs_are_certain_contacts", resting_sheet_pairs_are_certain_contacts},
    {"falling_sheet_pairs_are_culled_in_its_moving_frame", falling_sheet_pairs_are_culled_in_its_moving_frame},
    {"neighbour_list_gives_the_traversals_pairs", neighbour_list_gives_the_traversals_pairs},
    {"moving_frame_cull_misses_nothing", moving_frame_cull_misses_nothing},
    {"cloth_folding_onto_itself", cloth_folding_onto_itself},
    {"corner_folding_through_its_neighbour", corner_folding_through_its_neighbour},
    {"create_out_of_memory_at_every_allocation", create_out_of_memory_at_every_allocation},
    {"mesh_obstacle", mesh_obstacle},
    {"friction_on_a_mesh_obstacle", friction_on_a_mesh_obstacle},
    {"random_tangles", random_tangles},
    {"unresolvable_cases_fail_and_keep_x1", unresolvable_cases_fail_and_keep_x1},
    {"fail_safe_rigid_zones", fail_safe_rigid_zones},
    {"deterministic", deterministic},
    {"round_check_stops_the_resolve", round_check_stops_the_resolve},
    {"no_allocation_in_a_steady_scene", no_allocation_in_a_steady_scene},
    {"arguments", arguments},
    {NULL, NULL}};
