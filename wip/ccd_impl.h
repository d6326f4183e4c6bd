/* ------------------------------------------------------------------------------------- */
/* ccd                                                                                   */
/* ------------------------------------------------------------------------------------- */

/* Everything here computes in double whatever cloth_real is (float inputs convert exactly). */

static void cloth__d3_sub(const double *a, const double *b, double *out)
{ out[0] = a[0] - b[0]; out[1] = a[1] - b[1]; out[2] = a[2] - b[2]; }
static double cloth__d3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cloth__d3_cross(const double *a, const double *b, double *out)
{
    double c0 = a[1] * b[2] - a[2] * b[1];
    double c1 = a[2] * b[0] - a[0] * b[2];
    double c2 = a[0] * b[1] - a[1] * b[0];
    out[0] = c0; out[1] = c1; out[2] = c2;
}
/* |a + s e - p|^2 */
static double cloth__d3_dist2_along(const double *p, const double *a, const double *e, double s)
{
    double d[3];
    d[0] = a[0] + s * e[0] - p[0];
    d[1] = a[1] + s * e[1] - p[1];
    d[2] = a[2] + s * e[2] - p[2];
    return cloth__d3_dot(d, d);
}

/* ---- proximity ---------------------------------------------------------------------- */

/* Copies n points into double and scales them by one power of two so that the largest
   magnitude lies in [0.5, 1): squares then neither overflow nor underflow. Returns the
   power of two to scale distances back with (0 for all-zero input), or INT_MIN when an input
   is not finite. */
static int cloth__prox_load(const cloth_real *const *in, int n, double (*out)[3])
{
    double m = 0;
    int i, k, e = 0;
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) {
            if (!cloth__is_finite(in[i][k])) return INT_MIN;
            out[i][k] = (double)in[i][k];
            if (fabs(out[i][k]) > m) m = fabs(out[i][k]);
        }
    if (m == 0) return 0;
    (void)frexp(m, &e);
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) out[i][k] = ldexp(out[i][k], -e);
    return e;
}

/* Closest point of segment a + s (b - a), s in [0,1], to p: returns the squared distance and s.
   A zero-length segment is its point a. */
static double cloth__point_segment(const double *p, const double *a, const double *b, double *s_out)
{
    double e[3], w[3], ee, s = 0;
    cloth__d3_sub(b, a, e);
    cloth__d3_sub(p, a, w);
    ee = cloth__d3_dot(e, e);
    if (ee > 0) {
        s = cloth__d3_dot(w, e) / ee;
        s = s < 0 ? 0 : (s > 1 ? 1 : s);
    }
    *s_out = s;
    return cloth__d3_dist2_along(p, a, e, s);
}

CLOTH_API cloth_real cloth_distance_vertex_face(const cloth_real p[3], const cloth_real f0[3], const cloth_real f1[3],
                                                const cloth_real f2[3], cloth_real weights[3])
{
    /* The closest point is the projection onto the plane when that falls inside the triangle,
       and otherwise lies on an edge. All four candidates are tried and the nearest kept, so a
       degenerate or nearly degenerate triangle (no usable plane) falls back on its edges, and
       the distance returned is always measured to the point the weights name. */
    const cloth_real *in[4];
    double x[4][3], w[3], best, d2, s;
    double e1[3], e2[3], r[3], n[3], c[3], nn;
    int e;
    in[0] = p; in[1] = f0; in[2] = f1; in[3] = f2;
    CLOTH_ASSERT(p && f0 && f1 && f2);
    e = cloth__prox_load(in, 4, x);
    if (e == INT_MIN) {
        if (weights) weights[0] = weights[1] = weights[2] = (cloth_real)NAN;
        return (cloth_real)NAN;
    }
    best = -1;
    w[0] = 1; w[1] = 0; w[2] = 0;
    cloth__d3_sub(x[2], x[1], e1);
    cloth__d3_sub(x[3], x[1], e2);
    cloth__d3_sub(x[0], x[1], r);
    cloth__d3_cross(e1, e2, n);
    nn = cloth__d3_dot(n, n);
    if (nn > 0) {
        double u, v;
        cloth__d3_cross(r, e2, c);
        u = cloth__d3_dot(c, n) / nn;
        cloth__d3_cross(e1, r, c);
        v = cloth__d3_dot(c, n) / nn;
        if (u >= 0 && v >= 0 && u + v <= 1) {
            double q[3];
            int k;
            for (k = 0; k < 3; ++k) q[k] = x[1][k] + u * e1[k] + v * e2[k];
            cloth__d3_sub(x[0], q, q);
            best = cloth__d3_dot(q, q);
            w[0] = 1 - (u + v); w[1] = u; w[2] = v;
        }
    }
    d2 = cloth__point_segment(x[0], x[1], x[2], &s);
    if (best < 0 || d2 < best) { best = d2; w[0] = 1 - s; w[1] = s; w[2] = 0; }
    d2 = cloth__point_segment(x[0], x[2], x[3], &s);
    if (d2 < best) { best = d2; w[0] = 0; w[1] = 1 - s; w[2] = s; }
    d2 = cloth__point_segment(x[0], x[3], x[1], &s);
    if (d2 < best) { best = d2; w[0] = s; w[1] = 0; w[2] = 1 - s; }
    if (weights) { weights[0] = (cloth_real)w[0]; weights[1] = (cloth_real)w[1]; weights[2] = (cloth_real)w[2]; }
    return (cloth_real)ldexp(sqrt(best), e);
}

CLOTH_API cloth_real cloth_distance_edge_edge(const cloth_real a0[3], const cloth_real a1[3], const cloth_real b0[3],
                                              const cloth_real b1[3], cloth_real params[2])
{
    /* The squared distance is a convex quadratic over (s,t) in [0,1]^2: its minimum is the
       interior critical point when the segments are not parallel and that point lies in the
       square, and otherwise lies on a side of the square, where one endpoint is fixed and the
       problem is point-segment. Parallel and zero-length segments have no usable critical
       point and are answered by the sides alone. */
    const cloth_real *in[4];
    double x[4][3], ea[3], eb[3], r[3], n[3], c[3], nn, best = -1, d2, s = 0, t = 0, u;
    int e;
    in[0] = a0; in[1] = a1; in[2] = b0; in[3] = b1;
    CLOTH_ASSERT(a0 && a1 && b0 && b1);
    e = cloth__prox_load(in, 4, x);
    if (e == INT_MIN) {
        if (params) params[0] = params[1] = (cloth_real)NAN;
        return (cloth_real)NAN;
    }
    cloth__d3_sub(x[1], x[0], ea);
    cloth__d3_sub(x[3], x[2], eb);
    cloth__d3_sub(x[2], x[0], r);
    cloth__d3_cross(ea, eb, n);
    nn = cloth__d3_dot(n, n);
    if (nn > 0) {
        double si, ti;
        cloth__d3_cross(r, eb, c);
        si = cloth__d3_dot(c, n) / nn;
        cloth__d3_cross(r, ea, c);
        ti = cloth__d3_dot(c, n) / nn;
        if (si >= 0 && si <= 1 && ti >= 0 && ti <= 1) {
            double d[3];
            int k;
            for (k = 0; k < 3; ++k) d[k] = (x[0][k] + si * ea[k]) - (x[2][k] + ti * eb[k]);
            best = cloth__d3_dot(d, d);
            s = si; t = ti;
        }
    }
    d2 = cloth__point_segment(x[0], x[2], x[3], &u);
    if (best < 0 || d2 < best) { best = d2; s = 0; t = u; }
    d2 = cloth__point_segment(x[1], x[2], x[3], &u);
    if (d2 < best) { best = d2; s = 1; t = u; }
    d2 = cloth__point_segment(x[2], x[0], x[1], &u);
    if (d2 < best) { best = d2; s = u; t = 0; }
    d2 = cloth__point_segment(x[3], x[0], x[1], &u);
    if (d2 < best) { best = d2; s = u; t = 1; }
    if (params) { params[0] = (cloth_real)s; params[1] = (cloth_real)t; }
    return (cloth_real)ldexp(sqrt(best), e);
}

/* ---- continuous collision detection ------------------------------------------------- */

#define CLOTH__CCD_COOKIE 0x43434431
#define CLOTH__CCD_MAX_COORDINATE 1e300
/* A box side is not split below 2^-50, so a box is at most about 3 * 51 splits deep (a rounded
   midpoint may leave a half slightly wider than half). */
#define CLOTH__CCD_MIN_WIDTH (1.0 / 1125899906842624.0)
/* The depth-first stack holds at most one box per level plus one; the heap of waiting boxes
   has a fixed size too: a query uses about 35 KB of the caller's stack and allocates nothing. */
#define CLOTH__CCD_STACK 200
#define CLOTH__CCD_HEAP 512
/* Once a contact is found, at most max_checks / 16 further checks go into tightening toi. */
#define CLOTH__CCD_REFINE_SHARE 16

CLOTH_API cloth_ccd_options cloth_ccd_default_options(void)
{
    cloth_ccd_options o;
    o.tolerance = (cloth_real)1e-6;
    o.max_checks = 1000000;
    o.minimum_separation = 0;
    o.internal_cookie = CLOTH__CCD_COOKIE;
    return o;
}

/* A box of the parameter domain. */
typedef struct cloth__ccd_box { double t0, t1, u0, u1, v0, v1; } cloth__ccd_box;

/* A query ready for the search: vertex positions at t = 0 and their motion over the step, in
   the order p, f0, f1, f2 (vertex-face) or a0, a1, b0, b1 (edge-edge). */
typedef struct cloth__ccd_problem {
    int edge_edge;
    double x0[3][4];  /* x0[k][j]: axis k of vertex j at t = 0 */
    double dx[3][4];  /* fl(x1 - x0) */
    double reach[3];  /* >= minimum separation + error bound on axis k: a box is dropped when F_k
                         on it lies wholly above reach or wholly below -reach */
    double eps[3];    /* the error bound alone */
    double separation;
} cloth__ccd_problem;

/* The error bound. Let U = 2^-53 (unit roundoff), M the largest magnitude of the eight input
   coordinates on an axis, and t, u, v exact doubles in [0,1]. The corner values are computed as

       x(t) = x0 + t * fl(x1 - x0)                                   for each vertex
       vertex-face:  F = ((p(t) - f0(t)) - u * (f1(t) - f0(t))) - v * (f2(t) - f0(t))
       edge-edge:    F = (a0(t) + u * (a1(t) - a0(t))) - (b0(t) + v * (b1(t) - b0(t)))

   Carrying a bound B on the exact value and E on the error of each intermediate through
   |fl(a +- b) - (a +- b)| <= Ea + Eb + U (Ba + Bb + Ea + Eb) and
   |fl(a b) - a b| <= Ba Eb + Bb Ea + Ea Eb + U (Ba + Ea)(Bb + Eb):
   fl(x1 - x0): B 2M, E 2UM;  t * that: E 4UM;  x(t): B M (a convex combination), E 5UM;
   vertex-face: differences of two x(t): B 2M, E 12UM; u or v times one: E 14UM;
   (p - f0) - u (f1 - f0): B 2M, E 28UM; F: B 4M (u + v may reach 2 in a box), E 46UM;
   edge-edge: a0 + u (a1 - a0): B M, E 20UM; F: B 2M, E 42UM; each to first order, the
   second-order terms being below 100 U^2 M. So 64 U M = 32 DBL_EPSILON M bounds the error of
   every corner value. A fused multiply-add rounds once where two operations rounded, and its
   error is at most U times the magnitude bound already charged to the sum, so the bound also
   holds under -ffp-contract=fast. Underflow adds at most 2^-1075 per product (DBL_MIN per
   operation even with flush-to-zero), covered by the 64 DBL_MIN term. The exact F over a box
   lies between its smallest and largest exact corner values (F is multilinear), hence within
   [min computed - eps, max computed + eps]. */
static void cloth__ccd_setup(cloth__ccd_problem *q, int edge_edge, const double (*x)[3], double separation)
{
    int j, k;
    q->edge_edge = edge_edge;
    q->separation = separation;
    for (k = 0; k < 3; ++k) {
        double m = 0;
        for (j = 0; j < 4; ++j) {
            q->x0[k][j] = x[j][k];
            q->dx[k][j] = x[4 + j][k] - x[j][k];
            if (fabs(x[j][k]) > m) m = fabs(x[j][k]);
            if (fabs(x[4 + j][k]) > m) m = fabs(x[4 + j][k]);
        }
        q->eps[k] = 32 * DBL_EPSILON * m + 64 * DBL_MIN;
        /* fl(d + eps) >= (d + eps)(1 - U); the product with 1 + 8U, rounded, is >= d + eps. */
        q->reach[k] = (separation + q->eps[k]) * (1 + 4 * DBL_EPSILON);
    }
}

/* Corner values of F over box b on all three axes, corner[k][4 it + 2 iu + iv] with it, iu,
   iv = 0 for the lower bound of t, u, v and 1 for the upper; lo and hi are their extremes.
   Returns 0 when the box is proven free of collisions on some axis (then later axes are left
   unevaluated) or along a fourth direction, 1 otherwise. */
static int cloth__ccd_check(const cloth__ccd_problem *q, const cloth__ccd_box *b, double lo[3], double hi[3],
                            double corner[3][8])
{
    double ts[2], us[2], vs[2];
    int k, it, iu, iv, j;
    ts[0] = b->t0; ts[1] = b->t1; us[0] = b->u0; us[1] = b->u1; vs[0] = b->v0; vs[1] = b->v1;
    for (k = 0; k < 3; ++k) {
        double mn, mx;
        for (it = 0; it < 2; ++it) {
            double xt[4];
            for (j = 0; j < 4; ++j) xt[j] = q->x0[k][j] + ts[it] * q->dx[k][j];
            if (q->edge_edge) {
                double da = xt[1] - xt[0], db = xt[3] - xt[2];
                for (iu = 0; iu < 2; ++iu) {
                    double pa = xt[0] + us[iu] * da;
                    for (iv = 0; iv < 2; ++iv) corner[k][4 * it + 2 * iu + iv] = pa - (xt[2] + vs[iv] * db);
                }
            } else {
                double w = xt[0] - xt[1], e1 = xt[2] - xt[1], e2 = xt[3] - xt[1];
                for (iu = 0; iu < 2; ++iu) {
                    double s = w - us[iu] * e1;
                    for (iv = 0; iv < 2; ++iv) corner[k][4 * it + 2 * iu + iv] = s - vs[iv] * e2;
                }
            }
        }
        mn = mx = corner[k][0];
        for (j = 1; j < 8; ++j) {
            if (corner[k][j] < mn) mn = corner[k][j];
            if (corner[k][j] > mx) mx = corner[k][j];
        }
        lo[k] = mn; hi[k] = mx;
        if (mx < -q->reach[k] || mn > q->reach[k]) return 0;
    }
    /* A fourth direction n: the normal of the triangle (vertex-face) or of the two edges
       (edge-edge) at the middle of the box's time span, divided by its largest component. Any
       n gives a valid test, since n.F is multilinear too: its exact range over the box lies
       between its exact corner values, each within sum |n_k| eps_k (the corner errors) plus
       the rounding of the dot product (below 2 DBL_EPSILON sum |n_k F_k|, fused or not, plus
       DBL_MIN for underflow) of the computed one. A collision (|F_k| <= d on every axis) has
       |n.F| <= d sum |n_k|. Along n, F is close to the distance from the plane, nearly
       independent of u and v, which prunes near misses that the axes alone leave open. */
    {
        double tm = 0.5 * (b->t0 + b->t1), ea[3], eb[3], n[3], m, sum = 0, err = DBL_MIN, reach, g, gmin, gmax;
        int c;
        for (k = 0; k < 3; ++k) {
            double y[4];
            for (j = 0; j < 4; ++j) y[j] = q->x0[k][j] + tm * q->dx[k][j];
            ea[k] = q->edge_edge ? y[1] - y[0] : y[2] - y[1];
            eb[k] = q->edge_edge ? y[3] - y[2] : y[3] - y[1];
        }
        n[0] = ea[1] * eb[2] - ea[2] * eb[1];
        n[1] = ea[2] * eb[0] - ea[0] * eb[2];
        n[2] = ea[0] * eb[1] - ea[1] * eb[0];
        m = fabs(n[0]) > fabs(n[1]) ? fabs(n[0]) : fabs(n[1]);
        if (fabs(n[2]) > m) m = fabs(n[2]);
        if (!(m > DBL_MIN && m <= DBL_MAX)) return 1; /* no usable normal */
        for (k = 0; k < 3; ++k) {
            double big = fabs(lo[k]) > fabs(hi[k]) ? fabs(lo[k]) : fabs(hi[k]);
            n[k] /= m;
            sum += fabs(n[k]);
            err += fabs(n[k]) * (q->eps[k] + 2 * DBL_EPSILON * big);
        }
        /* the rounding of this sum of nonnegative terms is covered by the 1 + 8 DBL_EPSILON */
        reach = (q->separation * sum + err) * (1 + 8 * DBL_EPSILON);
        gmin = gmax = n[0] * corner[0][0] + n[1] * corner[1][0] + n[2] * corner[2][0];
        for (c = 1; c < 8; ++c) {
            g = n[0] * corner[0][c] + n[1] * corner[1][c] + n[2] * corner[2][c];
            if (g < gmin) gmin = g;
            if (g > gmax) gmax = g;
        }
        if (gmax < -reach || gmin > reach) return 0;
    }
    return 1;
}

/* The largest change of F along t, u and v across a box (any axis), from its corner values:
   F is multilinear, so its partial derivative along one parameter is extremal at corners, and
   these are exactly what each side contributes to the spread of F over the box. Only steers
   the search; the guarantee does not depend on it. */
static void cloth__ccd_spread(double corner[3][8], double spread[3])
{
    int k, c;
    spread[0] = spread[1] = spread[2] = 0;
    for (k = 0; k < 3; ++k)
        for (c = 0; c < 8; ++c) {
            double dt = (c & 4) ? 0 : fabs(corner[k][c | 4] - corner[k][c]);
            double du = (c & 2) ? 0 : fabs(corner[k][c | 2] - corner[k][c]);
            double dv = (c & 1) ? 0 : fabs(corner[k][c | 1] - corner[k][c]);
            if (dt > spread[0]) spread[0] = dt;
            if (du > spread[1]) spread[1] = du;
            if (dv > spread[2]) spread[2] = dv;
        }
}

/* A min-heap of boxes by t0, for the best-first phase of the search. */
static void cloth__ccd_heap_push(cloth__ccd_box *h, int *n, const cloth__ccd_box *b)
{
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].t0 > b->t0) { h[i] = h[(i - 1) / 2]; i = (i - 1) / 2; }
    h[i] = *b;
}
static cloth__ccd_box cloth__ccd_heap_pop(cloth__ccd_box *h, int *n)
{
    cloth__ccd_box top = h[0], last = h[--*n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= *n) break;
        if (c + 1 < *n && h[c + 1].t0 < h[c].t0) ++c;
        if (h[c].t0 >= last.t0) break;
        h[i] = h[c];
        i = c;
    }
    if (*n > 0) h[i] = last;
    return top;
}

/* The search. A box is checked; one that survives is accepted as a collision when F lies
   wholly within the separation band over it, when F varies by at most delta over it on every
   axis, or when it cannot be split usefully (no side longer than the smallest width along
   which F changes), and its t0 becomes the best time; otherwise the side along which F
   changes most over the box is halved.

   Boxes are explored depth first, earlier half of t first (a stack of one box per level),
   until a box is accepted. From then on only times before the cut, the best time less the
   time resolution (delta over three times the largest change of F along t over the step),
   matter: a box starting no earlier is dropped, one reaching past it is cut there, so that
   each later acceptance improves the best time by at least the resolution. The boxes still
   waiting go to a min-heap on t0 and are taken earliest first, each explored depth first
   again until the next acceptance. (Depth first alone reaches a first contact quickly but may
   then lower the best time in tiny steps across a surface of contacts; earliest first alone
   goes breadth first along a curve of contacts at one time.) The search stops when no box is
   left before the cut or when the budget runs out; once a contact is found the budget left is
   cut to a share of max_checks, since what remains only tightens toi (along a curve of
   contacts at one time, certifying that no earlier contact exists costs more the tighter the
   bound). When the heap is full the waiting boxes stay on the stack and the search stays
   depth first, so memory is fixed.

   Every root lies in a box that was accepted (so at or after the best time), dropped or cut
   for lying after the cut, or still waiting; so the smallest of the cut and the waiting boxes'
   t0 is a lower bound on the earliest root, and it is what is returned. Box bounds need not be
   exact midpoints: a rounded midpoint still splits a box into two that cover it, and the error
   bound holds for any double t, u, v in [0,1]. */
static void cloth__ccd_search(const cloth__ccd_problem *q, double delta, int64_t max_checks, cloth_ccd_report *report)
{
    cloth__ccd_box stack[CLOTH__CCD_STACK], heap[CLOTH__CCD_HEAP];
    double best = 2, cut = 2, lowest, time_resolution = 0;
    int64_t checks = 0, limit = max_checks;
    int n = 0, nh = 0, i, exhausted = 0;
    stack[0].t0 = stack[0].u0 = stack[0].v0 = 0;
    stack[0].t1 = stack[0].u1 = stack[0].v1 = 1;
    n = 1;
    for (;;) {
        cloth__ccd_box b, c0, c1;
        double lo[3], hi[3], corner[3][8], spread[3], w[3], most = -1, mid;
        int k, split = -1, accept, sweep;
        if (n == 0) {
            if (nh == 0 || heap[0].t0 >= cut) { nh = 0; break; }
            b = cloth__ccd_heap_pop(heap, &nh);
            sweep = 1;
        } else {
            b = stack[--n];
            sweep = 0;
        }
        if (b.t0 >= cut) continue;
        if (b.t1 > cut) b.t1 = cut;
        if (!q->edge_edge && b.u0 + b.v0 > 1) continue; /* outside the triangle (rounding can only keep a box) */
        if (checks >= limit || n + 2 > CLOTH__CCD_STACK) { exhausted = 1; stack[n++] = b; break; }
        ++checks;
        if (!cloth__ccd_check(q, &b, lo, hi, corner)) continue;
        cloth__ccd_spread(corner, spread);
        if (checks == 1) time_resolution = spread[0] > 0 ? delta / (3 * spread[0]) : 2; /* the whole domain */
        w[0] = b.t1 - b.t0; w[1] = b.u1 - b.u0; w[2] = b.v1 - b.v0;
        for (k = 0; k < 3; ++k)
            if (w[k] > CLOTH__CCD_MIN_WIDTH && spread[k] > most) { most = spread[k]; split = k; }
        accept = split < 0 || most <= 0;
        if (!accept) {
            int inside = 1, narrow = 1;
            for (k = 0; k < 3; ++k) {
                if (lo[k] - 2 * q->eps[k] < -q->reach[k] || hi[k] + 2 * q->eps[k] > q->reach[k]) inside = 0;
                if (hi[k] - lo[k] > delta) narrow = 0;
            }
            accept = inside || narrow;
        }
        if (accept) {
            if (best > 1 && max_checks / CLOTH__CCD_REFINE_SHARE < limit - checks)
                limit = checks + (max_checks / CLOTH__CCD_REFINE_SHARE > 0 ? max_checks / CLOTH__CCD_REFINE_SHARE : 1);
            best = b.t0;
            cut = best - time_resolution;
            if (nh + n <= CLOTH__CCD_HEAP) /* the rest is taken earliest first */
                while (n > 0) { --n; if (stack[n].t0 < cut) cloth__ccd_heap_push(heap, &nh, &stack[n]); }
            continue;
        }
        c0 = c1 = b;
        if (split == 0) { mid = 0.5 * (b.t0 + b.t1); c0.t1 = mid; c1.t0 = mid; }
        else if (split == 1) { mid = 0.5 * (b.u0 + b.u1); c0.u1 = mid; c1.u0 = mid; }
        else { mid = 0.5 * (b.v0 + b.v1); c0.v1 = mid; c1.v0 = mid; }
        if (sweep && nh + 2 <= CLOTH__CCD_HEAP) {
            cloth__ccd_heap_push(heap, &nh, &c0);
            cloth__ccd_heap_push(heap, &nh, &c1);
        } else {
            stack[n++] = c1; /* the upper half waits; the lower (earlier) half is searched first */
            stack[n++] = c0;
        }
    }
    lowest = best <= 1 ? (cut > 0 ? cut : 0) : 2;
    for (i = 0; i < n; ++i)
        if (stack[i].t0 < lowest && (q->edge_edge || stack[i].u0 + stack[i].v0 <= 1)) lowest = stack[i].t0;
    for (i = 0; i < nh; ++i)
        if (heap[i].t0 < lowest && (q->edge_edge || heap[i].u0 + heap[i].v0 <= 1)) lowest = heap[i].t0;
    report->checks = checks;
    report->budget_exhausted = exhausted;
    report->may_collide = lowest <= 1;
    if (lowest > 1) {
        report->toi = 1;
    } else {
        /* round down into cloth_real: toi stays a lower bound */
        cloth_real r = (cloth_real)lowest;
        if ((double)r > lowest) r = sizeof(cloth_real) == sizeof(float) ? (cloth_real)nextafterf((float)r, -1.0f)
                                                                      : (cloth_real)nextafter((double)r, -1.0);
        report->toi = r;
    }
}

static cloth_result cloth__ccd_run(int edge_edge, const cloth_real *const *v, const cloth_ccd_options *options,
                                   cloth_ccd_report *report)
{
    cloth_ccd_options opt = options ? *options : cloth_ccd_default_options();
    cloth__ccd_problem q;
    double x[8][3];
    int i, k;
    CLOTH_ASSERT(report);
    CLOTH_ASSERT(opt.internal_cookie == CLOTH__CCD_COOKIE); /* options not made by cloth_ccd_default_options */
    report->may_collide = 1;
    report->toi = 0;
    report->checks = 0;
    report->budget_exhausted = 0;
    if (!(opt.tolerance > 0) || !cloth__is_finite(opt.tolerance) || opt.max_checks < 1 ||
        !(opt.minimum_separation >= 0) || !((double)opt.minimum_separation <= CLOTH__CCD_MAX_COORDINATE))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < 8; ++i) {
        CLOTH_ASSERT(v[i]);
        for (k = 0; k < 3; ++k) {
            if (!cloth__is_finite(v[i][k])) return CLOTH_ERROR_NOT_FINITE;
            x[i][k] = (double)v[i][k];
        }
    }
    for (i = 0; i < 8; ++i)
        for (k = 0; k < 3; ++k)
            if (fabs(x[i][k]) > CLOTH__CCD_MAX_COORDINATE) return CLOTH_ERROR_INVALID_ARGUMENT;
    cloth__ccd_setup(&q, edge_edge, (const double (*)[3])x, (double)opt.minimum_separation);
    cloth__ccd_search(&q, (double)opt.tolerance, opt.max_checks, report);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_ccd_vertex_face(const cloth_real p_t0[3], const cloth_real f0_t0[3], const cloth_real f1_t0[3],
                                             const cloth_real f2_t0[3], const cloth_real p_t1[3], const cloth_real f0_t1[3],
                                             const cloth_real f1_t1[3], const cloth_real f2_t1[3],
                                             const cloth_ccd_options *options, cloth_ccd_report *report)
{
    const cloth_real *v[8];
    v[0] = p_t0; v[1] = f0_t0; v[2] = f1_t0; v[3] = f2_t0;
    v[4] = p_t1; v[5] = f0_t1; v[6] = f1_t1; v[7] = f2_t1;
    return cloth__ccd_run(0, v, options, report);
}

CLOTH_API cloth_result cloth_ccd_edge_edge(const cloth_real a0_t0[3], const cloth_real a1_t0[3], const cloth_real b0_t0[3],
                                           const cloth_real b1_t0[3], const cloth_real a0_t1[3], const cloth_real a1_t1[3],
                                           const cloth_real b0_t1[3], const cloth_real b1_t1[3],
                                           const cloth_ccd_options *options, cloth_ccd_report *report)
{
    const cloth_real *v[8];
    v[0] = a0_t0; v[1] = a1_t0; v[2] = b0_t0; v[3] = b1_t0;
    v[4] = a0_t1; v[5] = a1_t1; v[6] = b0_t1; v[7] = b1_t1;
    return cloth__ccd_run(1, v, options, report);
}
