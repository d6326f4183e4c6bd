/* Tests of tests/exact_tritri.h, the exact triangle-triangle checker the stress scenes use (it
   is no part of cloth.h). Its predicates are compared with exact integer arithmetic: every
   double is M 2^E (M an odd integer); shifted to the case's smallest E, all coordinates become
   integers, held here in fixed-size two's complement big integers. The intersection test is
   compared with a different formulation on those integers: the separating axis theorem over a
   candidate set that is complete for closed triangles, degenerate ones included (below). */
#include "runner.h"
#include "exact_tritri.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ---- fixed-size big integers (two's complement, 16 x 32 bits) ---------------------------- */

#define BIG_LIMBS 24
typedef struct big { uint32_t w[BIG_LIMBS]; } big;

static big big_from_u64(uint64_t m)
{
    big r;
    memset(&r, 0, sizeof r);
    r.w[0] = (uint32_t)m;
    r.w[1] = (uint32_t)(m >> 32);
    return r;
}

static int big_negative(const big *a) { return (a->w[BIG_LIMBS - 1] >> 31) != 0; }

static big big_add(big a, big b)
{
    big r;
    uint64_t carry = 0;
    int i;
    for (i = 0; i < BIG_LIMBS; ++i) {
        uint64_t s = (uint64_t)a.w[i] + b.w[i] + carry;
        r.w[i] = (uint32_t)s;
        carry = s >> 32;
    }
    return r;
}

static big big_neg(big a)
{
    int i;
    for (i = 0; i < BIG_LIMBS; ++i) a.w[i] = ~a.w[i];
    return big_add(a, big_from_u64(1));
}

static big big_sub(big a, big b) { return big_add(a, big_neg(b)); }

static int big_sign(big a)
{
    int i;
    if (big_negative(&a)) return -1;
    for (i = 0; i < BIG_LIMBS; ++i)
        if (a.w[i]) return 1;
    return 0;
}

static int big_cmp(big a, big b) { return big_sign(big_sub(a, b)); }

/* The product; the caller keeps magnitudes below 2^(32 BIG_LIMBS - 2) (checked). */
static big big_mul(big a, big b)
{
    int na = big_negative(&a), nb = big_negative(&b), la = BIG_LIMBS, lb = BIG_LIMBS, i, j;
    uint32_t r[2 * BIG_LIMBS];
    big out;
    if (na) a = big_neg(a);
    if (nb) b = big_neg(b);
    while (la > 0 && a.w[la - 1] == 0) --la;
    while (lb > 0 && b.w[lb - 1] == 0) --lb;
    memset(r, 0, sizeof r);
    for (i = 0; i < la; ++i) {
        uint64_t carry = 0;
        for (j = 0; j < lb; ++j) {
            uint64_t t = (uint64_t)a.w[i] * b.w[j] + r[i + j] + carry;
            r[i + j] = (uint32_t)t;
            carry = t >> 32;
        }
        r[i + lb] = (uint32_t)carry;
    }
    for (i = BIG_LIMBS - 1; i < 2 * BIG_LIMBS; ++i)
        if (r[i] != 0 && !(i == BIG_LIMBS - 1 && r[i] < 0x40000000u)) abort(); /* overflow: a test bug */
    memcpy(out.w, r, sizeof out.w);
    return (na != nb) ? big_neg(out) : out;
}

typedef struct bvec { big c[3]; } bvec;

static bvec bvec_sub(const bvec *a, const bvec *b)
{
    bvec r;
    int k;
    for (k = 0; k < 3; ++k) r.c[k] = big_sub(a->c[k], b->c[k]);
    return r;
}

static bvec bvec_cross(const bvec *a, const bvec *b)
{
    bvec r;
    r.c[0] = big_sub(big_mul(a->c[1], b->c[2]), big_mul(a->c[2], b->c[1]));
    r.c[1] = big_sub(big_mul(a->c[2], b->c[0]), big_mul(a->c[0], b->c[2]));
    r.c[2] = big_sub(big_mul(a->c[0], b->c[1]), big_mul(a->c[1], b->c[0]));
    return r;
}

static big bvec_dot(const bvec *a, const bvec *b)
{
    return big_add(big_add(big_mul(a->c[0], b->c[0]), big_mul(a->c[1], b->c[1])), big_mul(a->c[2], b->c[2]));
}

/* Doubles to integers: x = M 2^E with M odd; every coordinate becomes M 2^(E - emin). */
static void decompose(double x, int64_t *m, int *e)
{
    int ex;
    double f = frexp(x, &ex);
    int64_t mm = (int64_t)ldexp(f, 53);
    int ee = ex - 53;
    if (mm == 0) { *m = 0; *e = 0; return; }
    while ((mm & 1) == 0) { mm /= 2; ++ee; }
    *m = mm;
    *e = ee;
}

/* Convert count points (3 doubles each) to integer vectors with a common scale. */
static void to_big(const double *const *pts, int count, bvec *out)
{
    int64_t m[64];
    int e[64], emin = 1 << 30, i, k;
    for (i = 0; i < count; ++i)
        for (k = 0; k < 3; ++k) {
            decompose(pts[i][k], &m[3 * i + k], &e[3 * i + k]);
            if (m[3 * i + k] != 0 && e[3 * i + k] < emin) emin = e[3 * i + k];
        }
    for (i = 0; i < count; ++i)
        for (k = 0; k < 3; ++k) {
            int64_t mm = m[3 * i + k];
            int shift = e[3 * i + k] - emin, s;
            big v = big_from_u64((uint64_t)(mm < 0 ? -mm : mm));
            if (mm != 0 && shift + 53 > 150) abort(); /* keep degree-4 products inside 768 bits */
            for (s = 0; mm != 0 && s < shift; ++s) v = big_add(v, v);
            out[i].c[k] = mm < 0 ? big_neg(v) : v;
        }
}

static int ref_orient3d(const double *a, const double *b, const double *c, const double *d)
{
    const double *p[4];
    bvec v[4], ad, bd, cd, x;
    p[0] = a; p[1] = b; p[2] = c; p[3] = d;
    to_big(p, 4, v);
    ad = bvec_sub(&v[0], &v[3]);
    bd = bvec_sub(&v[1], &v[3]);
    cd = bvec_sub(&v[2], &v[3]);
    x = bvec_cross(&bd, &cd);
    return big_sign(bvec_dot(&ad, &x));
}

/* Separating axes. A - B (the Minkowski difference) is a polytope of dimension 0..3 with edges
   along the edges E of A and B and vertices among D = {a_i - b_j}. The triangles are disjoint
   iff 0 is not in it iff some direction separates strictly: a facet normal (v x w, v, w in E);
   for a flat polytope with 0 in its plane, an in-plane edge normal ((v x w) x u); for a segment
   along d with 0 off its line, (d x p) x d for a vertex p in D, with 0 on its line, d; for a
   point p, p itself. Every such axis is tried. */
static int ref_separated(const bvec *pts, const bvec *axis)
{
    big amin, amax, bmin, bmax;
    int i;
    for (i = 0; i < 6; ++i) {
        big d = bvec_dot(&pts[i], axis);
        if (i == 0) amin = amax = d;
        else if (i < 3) { if (big_cmp(d, amin) < 0) amin = d; if (big_cmp(d, amax) > 0) amax = d; }
        else if (i == 3) bmin = bmax = d;
        else { if (big_cmp(d, bmin) < 0) bmin = d; if (big_cmp(d, bmax) > 0) bmax = d; }
    }
    return big_cmp(amax, bmin) < 0 || big_cmp(bmax, amin) < 0;
}

static int ref_tri_tri(const double *a0, const double *a1, const double *a2, const double *b0, const double *b1, const double *b2)
{
    const double *p[6];
    bvec v[6], E[6], D[9], x, y;
    int i, j, k;
    p[0] = a0; p[1] = a1; p[2] = a2; p[3] = b0; p[4] = b1; p[5] = b2;
    to_big(p, 6, v);
    for (i = 0; i < 3; ++i) {
        E[i] = bvec_sub(&v[(i + 1) % 3], &v[i]);
        E[3 + i] = bvec_sub(&v[3 + (i + 1) % 3], &v[3 + i]);
        for (j = 0; j < 3; ++j) D[3 * i + j] = bvec_sub(&v[i], &v[3 + j]);
    }
    for (i = 0; i < 6; ++i)
        for (j = i + 1; j < 6; ++j) {
            x = bvec_cross(&E[i], &E[j]);
            if (ref_separated(v, &x)) return 0;
        }
    {
        /* both triangles proper: A - B has dimension 2 or 3 and the facet normals above and
           the in-plane normals nA x e (e in E, for coplanar triangles) are enough */
        bvec nA = bvec_cross(&E[0], &E[1]), nB = bvec_cross(&E[3], &E[4]);
        if ((big_sign(nA.c[0]) || big_sign(nA.c[1]) || big_sign(nA.c[2])) &&
            (big_sign(nB.c[0]) || big_sign(nB.c[1]) || big_sign(nB.c[2]))) {
            for (k = 0; k < 6; ++k) {
                y = bvec_cross(&nA, &E[k]);
                if (ref_separated(v, &y)) return 0;
            }
            return 1;
        }
    }
    for (i = 0; i < 6; ++i)
        if (ref_separated(v, &E[i])) return 0;
    for (i = 0; i < 9; ++i)
        if (ref_separated(v, &D[i])) return 0;
    for (i = 0; i < 6; ++i)
        for (j = i + 1; j < 6; ++j) {
            x = bvec_cross(&E[i], &E[j]);
            for (k = 0; k < 6; ++k) {
                y = bvec_cross(&x, &E[k]);
                if (ref_separated(v, &y)) return 0;
            }
        }
    for (i = 0; i < 6; ++i)
        for (j = 0; j < 9; ++j) {
            x = bvec_cross(&E[i], &D[j]);
            y = bvec_cross(&x, &E[i]);
            if (ref_separated(v, &y)) return 0;
        }
    return 1;
}

/* ---- random inputs ------------------------------------------------------------------------ */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static int rng_int(int n) { return (int)(rng_next() % (uint64_t)n); }
/* k 2^-bits with |k| < 2^bits: dyadic values in (-1, 1) */
static double rng_dyadic(int bits) { return ldexp((double)((int64_t)(rng_next() >> (63 - bits)) - ((int64_t)1 << bits)), -bits); }
/* nudge x by one ulp either way (x not 0) */
static double nudge(double x) { return x == 0 ? x : rng_int(2) ? nextafter(x, 2 * x) : nextafter(x, 0); }

/* Fill the 18 coordinates of a random case of the given kind. */
static void random_case(int kind, double t[6][3])
{
    int i, k;
    switch (kind) {
    case 0: /* general position, 30-bit dyadic coordinates */
        for (i = 0; i < 6; ++i)
            for (k = 0; k < 3; ++k) t[i][k] = rng_dyadic(30);
        break;
    case 1: /* a small integer lattice: coplanar, collinear, touching and degenerate cases */
        for (i = 0; i < 6; ++i)
            for (k = 0; k < 3; ++k) t[i][k] = (double)rng_int(4);
        break;
    case 2: { /* B's vertex on a point of A made exactly (a vertex or an edge midpoint), then
                 maybe nudged one ulp */
        double w;
        for (i = 0; i < 6; ++i)
            for (k = 0; k < 3; ++k) t[i][k] = rng_dyadic(20);
        i = rng_int(3);
        w = rng_int(2) ? 0.5 : 1.0;
        for (k = 0; k < 3; ++k) t[3][k] = w * t[i][k] + (1 - w) * t[(i + 1) % 3][k];
        if (rng_int(2)) { k = rng_int(3); t[3][k] = nudge(t[3][k]); }
        break;
    }
    case 3: { /* both in the plane y = c (coplanar), maybe one vertex nudged off it */
        double c = rng_dyadic(10);
        for (i = 0; i < 6; ++i) {
            t[i][0] = rng_dyadic(3);
            t[i][1] = c;
            t[i][2] = rng_dyadic(3);
        }
        if (rng_int(2)) { i = rng_int(6); t[i][1] = nudge(t[i][1]); }
        break;
    }
    case 4: { /* B's edge through a point of A's edge (edge-edge contact), maybe nudged */
        double m[3];
        for (i = 0; i < 6; ++i)
            for (k = 0; k < 3; ++k) t[i][k] = rng_dyadic(12);
        for (k = 0; k < 3; ++k) {
            m[k] = 0.5 * (t[0][k] + t[1][k]);
            t[4][k] = 2 * m[k] - t[3][k]; /* b1 = reflection of b0 through m: b0b1 passes m */
        }
        if (rng_int(2)) { i = 3 + rng_int(2); k = rng_int(3); t[i][k] = nudge(t[i][k]); }
        break;
    }
    default: /* degenerate triangles: A collinear (midpoint) or a point */
        for (i = 0; i < 6; ++i)
            for (k = 0; k < 3; ++k) t[i][k] = (double)rng_int(5) * 0.25;
        for (k = 0; k < 3; ++k) t[2][k] = rng_int(2) ? 0.5 * (t[0][k] + t[1][k]) : t[0][k];
        if (rng_int(3) == 0)
            for (k = 0; k < 3; ++k) t[4][k] = t[5][k] = t[3][k];
        break;
    }
}

/* ---- tests ---------------------------------------------------------------------------------- */

TEST(orient_predicates_match_integer_arithmetic)
{
    int c, mismatches = 0, zeros = 0;
    rng_state = 1;
    for (c = 0; c < 40000; ++c) {
        double p[4][3], w = rng_dyadic(8);
        int i, k, fast3, ref3;
        for (i = 0; i < 3; ++i)
            for (k = 0; k < 3; ++k) p[i][k] = rng_dyadic(c % 2 ? 50 : 26);
        /* d near the plane: an affine combination of a, b, c rounded, maybe nudged */
        for (k = 0; k < 3; ++k) p[3][k] = w * p[0][k] + (1 - w) * p[1][k] + 0.25 * (p[2][k] - p[1][k]);
        if (c % 3 == 0) { k = rng_int(3); p[3][k] = nudge(p[3][k]); }
        fast3 = exact_orient3d(p[0], p[1], p[2], p[3]);
        ref3 = ref_orient3d(p[0], p[1], p[2], p[3]);
        if (fast3 != ref3) ++mismatches;
        if (ref3 == 0) ++zeros;
        {
            /* orient2d against the orient3d of the lifted points (x, y, 0), (0, 0, 1) */
            double q[4][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
            int r2;
            for (i = 0; i < 3; ++i) { q[i][0] = p[i][0]; q[i][1] = p[i][1]; }
            q[2][0] = p[3][0];
            q[2][1] = w * p[0][1] + (1 - w) * p[1][1];
            q[3][2] = 1;
            r2 = ref_orient3d(q[0], q[1], q[2], q[3]);
            if (exact_orient2d(q[0], q[1], q[2], 0, 1) != -r2) ++mismatches; /* det = -orient2d */
        }
    }
    printf("    orient: 40000 cases (%d exactly coplanar), %d mismatches\n", zeros, mismatches);
    ENSURE(mismatches == 0);
    ENSURE(zeros > 100); /* the cases reach the exact path */
}

static int tt(double a[3][3], double b[3][3])
{
    return exact_tri_tri_intersect(a[0], a[1], a[2], b[0], b[1], b[2]);
}

/* Both orders and both methods agree with the expected answer. */
static int agrees(double a[3][3], double b[3][3], int expected)
{
    return tt(a, b) == expected && tt(b, a) == expected &&
           ref_tri_tri(a[0], a[1], a[2], b[0], b[1], b[2]) == expected &&
           exact_tri_tri_intersect(a[1], a[2], a[0], b[2], b[0], b[1]) == expected;
}

TEST(hand_made_cases)
{
    double A[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, B[3][3];
    double Ah[3][3] = {{0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}};
    double Ap[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}; /* plane x + y + z = 1 */
    /* touching at a vertex, then 1 ulp apart */
    double B1[3][3] = {{1, 0, 0}, {2, 0, 1}, {2, 1, 1}};
    ENSURE(agrees(A, B1, 1));
    B1[0][0] = nextafter(1.0, 2.0);
    ENSURE(agrees(A, B1, 0));
    /* B's vertex on A's interior (plane z = 0.1 in doubles), then 1 ulp above */
    {
        double B2[3][3] = {{0.25, 0.25, 0.1}, {0.25, 0.5, 1}, {0.5, 0.25, 1}};
        ENSURE(agrees(Ah, B2, 1));
        B2[0][2] = nextafter(0.1, 1.0);
        ENSURE(agrees(Ah, B2, 0));
        B2[0][2] = nextafter(0.1, 0.0); /* 1 ulp below: pierces */
        ENSURE(agrees(Ah, B2, 1));
    }
    /* edge-edge crossing in one point, then 1 ulp apart */
    {
        double B3[3][3] = {{0.5, -0.5, 0.5}, {0.5, 0.5, -0.5}, {0.5, -1, -1}};
        ENSURE(agrees(A, B3, 1));
        B3[0][1] = nextafter(-0.5, -1.0);
        B3[1][1] = nextafter(0.5, 0.0);
        ENSURE(agrees(A, B3, 0));
    }
    /* a vertex of B on A's edge in a tilted plane: (0.5, 0.5, 0) on the edge x + y = 1 */
    {
        double B4[3][3] = {{0.5, 0.5, 0}, {0, 0, -1}, {-1, 0, 0}};
        ENSURE(agrees(Ap, B4, 1));
        B4[0][0] = nextafter(0.5, 0.0);
        ENSURE(agrees(Ap, B4, 0));
    }
    /* coplanar: overlapping, contained, touching along an edge point, disjoint */
    memcpy(B, (double[3][3]){{0.2, 0.2, 0}, {2, 0.2, 0}, {0.2, 2, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1));
    memcpy(B, (double[3][3]){{0.1, 0.1, 0}, {0.3, 0.1, 0}, {0.1, 0.3, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1));
    memcpy(B, (double[3][3]){{0.5, 0.5, 0}, {1, 1, 0}, {0, 1, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1));
    memcpy(B, (double[3][3]){{0.5, 0.5, 0}, {nextafter(0.5, 1.0), 1, 0}, {0, 1, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1)); /* still touching at (0.5, 0.5) */
    memcpy(B, (double[3][3]){{nextafter(0.5, 1.0), 0.5, 0}, {1, 1, 0}, {0.6, 1, 0}}, sizeof B);
    ENSURE(agrees(A, B, 0)); /* 1 ulp beyond the hypotenuse */
    memcpy(B, (double[3][3]){{1, 1, 0}, {2, 1, 0}, {1, 2, 0}}, sizeof B);
    ENSURE(agrees(A, B, 0));
    /* coplanar in x + y + z = 1: the star of David overlaps, a shifted copy does not */
    memcpy(B, (double[3][3]){{0, 0.5, 0.5}, {0.5, 0, 0.5}, {0.5, 0.5, 0}}, sizeof B);
    ENSURE(agrees(Ap, B, 1));
    /* parallel planes 1 ulp apart */
    memcpy(B, (double[3][3]){{0, 0, 0.1}, {1, 0, 0.1}, {0, 1, 0.1}}, sizeof B);
    B[0][2] = B[1][2] = B[2][2] = nextafter(0.1, 1.0);
    ENSURE(agrees(Ah, B, 0));
    /* degenerate: a segment piercing A, a segment above it, a point on A, a point off it */
    memcpy(B, (double[3][3]){{0.25, 0.25, -1}, {0.25, 0.25, 1}, {0.25, 0.25, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1));
    memcpy(B, (double[3][3]){{0.25, 0.25, 0.5}, {0.25, 0.25, 1}, {0.25, 0.25, 0.75}}, sizeof B);
    ENSURE(agrees(A, B, 0));
    memcpy(B, (double[3][3]){{0.25, 0.5, 0}, {0.25, 0.5, 0}, {0.25, 0.5, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1));
    memcpy(B, (double[3][3]){{0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 0}}, sizeof B);
    ENSURE(agrees(A, B, 1)); /* on the hypotenuse */
    memcpy(B, (double[3][3]){{0.5, 0.5, 0x1p-200}, {0.5, 0.5, 0x1p-200}, {0.5, 0.5, 0x1p-200}}, sizeof B);
    ENSURE(tt(A, B) == 0);
    {
        /* two collinear segments: overlapping, then disjoint; two parallel segments */
        double S[3][3] = {{0, 0, 0}, {2, 2, 2}, {1, 1, 1}}, T[3][3] = {{1.5, 1.5, 1.5}, {3, 3, 3}, {3, 3, 3}};
        ENSURE(agrees(S, T, 1));
        T[0][0] = T[0][1] = T[0][2] = nextafter(2.0, 3.0);
        ENSURE(agrees(S, T, 0));
        memcpy(T, (double[3][3]){{0, 0, 1}, {2, 2, 3}, {1, 1, 2}}, sizeof T);
        ENSURE(agrees(S, T, 0));
    }
}

TEST(random_triangles_match_the_separating_axis_reference)
{
    int kind, c, mismatches = 0, hits[6] = {0, 0, 0, 0, 0, 0}, counts[6] = {0, 0, 0, 0, 0, 0};
    rng_state = 12345;
    for (kind = 0; kind < 6; ++kind)
        for (c = 0; c < 2500; ++c) {
            double t[6][3];
            int fast, fast2, ref;
            random_case(kind, t);
            fast = exact_tri_tri_intersect(t[0], t[1], t[2], t[3], t[4], t[5]);
            fast2 = exact_tri_tri_intersect(t[4], t[5], t[3], t[1], t[2], t[0]);
            ref = ref_tri_tri(t[0], t[1], t[2], t[3], t[4], t[5]);
            if (fast != ref || fast2 != ref) {
                if (mismatches < 5)
                    printf("    mismatch kind %d: %.17g %.17g %.17g / %.17g %.17g %.17g / %.17g %.17g %.17g / %.17g %.17g %.17g / "
                           "%.17g %.17g %.17g / %.17g %.17g %.17g: fast %d %d, reference %d\n", kind,
                           t[0][0], t[0][1], t[0][2], t[1][0], t[1][1], t[1][2], t[2][0], t[2][1], t[2][2], t[3][0], t[3][1],
                           t[3][2], t[4][0], t[4][1], t[4][2], t[5][0], t[5][1], t[5][2], fast, fast2, ref);
                ++mismatches;
            }
            hits[kind] += ref;
            ++counts[kind];
        }
    printf("    intersecting per kind (of 2500): general %d, lattice %d, vertex-on-A %d, coplanar %d, edge-edge %d, degenerate %d; %d mismatches\n",
           hits[0], hits[1], hits[2], hits[3], hits[4], hits[5], mismatches);
    ENSURE(mismatches == 0);
    for (kind = 0; kind < 6; ++kind) ENSURE(hits[kind] > 100 && hits[kind] < counts[kind] - 100); /* both answers occur */
}

/* Pairs that share vertices (by index): hand cases, then random lattice pairs against the
   reference applied to the header's lemma (the far edge of each as a degenerate triangle). */
TEST(pairs_sharing_a_vertex_or_an_edge)
{
    double v[3] = {0, 0, 0}, a1[3] = {1, 0, 0}, a2[3] = {0, 1, 0};
    double b1[3] = {-1, 0, 0}, b2[3] = {0, -1, 0};
    double c1[3] = {1, 1, 0}, c2[3] = {1, 0, 1}, d1[3] = {0.5, 0.5, 1}, d2[3] = {0.5, 0.5, -1};
    /* opposite wedges in one plane: only v */
    ENSURE(exact_tri_tri_intersect_beyond_vertex(v, a1, a2, b1, b2) == 0);
    /* overlapping wedges in one plane */
    ENSURE(exact_tri_tri_intersect_beyond_vertex(v, a1, a2, c1, b1) == 1);
    /* a wedge crossing A's plane through A's interior: the segment v-(0.5,0.5,0) is shared */
    ENSURE(exact_tri_tri_intersect_beyond_vertex(v, a1, a2, d1, d2) == 1);
    /* a wedge leaving A's plane at v only */
    ENSURE(exact_tri_tri_intersect_beyond_vertex(v, a1, a2, c2, d1) == 0);
    /* touching along the edge v-a1 from above (the pair shares the segment v a1) */
    ENSURE(exact_tri_tri_intersect_beyond_vertex(v, a1, a2, a1, c2) == 1);
    /* shared edge v a1: folded flat onto each other, opposite sides, bent */
    {
        double p[3] = {0.5, 0.25, 0}, q[3] = {0.5, -0.25, 0}, r[3] = {0.5, 0.25, 0x1p-40};
        ENSURE(exact_tri_tri_intersect_beyond_edge(v, a1, a2, p) == 1);
        ENSURE(exact_tri_tri_intersect_beyond_edge(v, a1, a2, q) == 0);
        ENSURE(exact_tri_tri_intersect_beyond_edge(v, a1, a2, r) == 0);
    }
    /* random shared-vertex pairs on a lattice */
    {
        int c, mism = 0, yes = 0;
        rng_state = 77;
        for (c = 0; c < 3000; ++c) {
            double t[5][3];
            int i, k, fast, ref;
            for (i = 0; i < 5; ++i)
                for (k = 0; k < 3; ++k) t[i][k] = (double)rng_int(3);
            if (exact__tri_degenerate(t[0], t[1], t[2]) || exact__tri_degenerate(t[0], t[3], t[4])) continue;
            fast = exact_tri_tri_intersect_beyond_vertex(t[0], t[1], t[2], t[3], t[4]);
            ref = ref_tri_tri(t[1], t[2], t[2], t[0], t[3], t[4]) || ref_tri_tri(t[3], t[4], t[4], t[0], t[1], t[2]);
            if (fast != ref) ++mism;
            yes += ref;
        }
        printf("    shared vertex, lattice: %d meet beyond v, %d mismatches\n", yes, mism);
        ENSURE(mism == 0);
        ENSURE(yes > 50);
    }
}

/* A grid of n x n vertices on [0,1]^2 in the xz plane with heights h(x, z). */
static void make_grid(int n, double *x, int32_t *tri, double (*height)(double, double))
{
    int i, j;
    int32_t *t = tri;
    for (j = 0; j < n; ++j)
        for (i = 0; i < n; ++i) {
            double u = (double)i / (n - 1), w = (double)j / (n - 1);
            x[3 * (j * n + i)] = u;
            x[3 * (j * n + i) + 1] = height(u, w);
            x[3 * (j * n + i) + 2] = w;
        }
    for (j = 0; j + 1 < n; ++j)
        for (i = 0; i + 1 < n; ++i) {
            int32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            t[0] = a; t[1] = c; t[2] = b; t[3] = a; t[4] = d; t[5] = c;
            t += 6;
        }
}

static double wave(double u, double w) { return 0.05 * sin(12 * u) * cos(9 * w); }
static double flat(double u, double w) { (void)u; (void)w; return 0; }

/* Brute force over all pairs with exact__pair_intersects. */
static long brute_count(const exact_mesh *meshes, int mesh_count)
{
    long found = 0;
    int ma, mb;
    int32_t ta, tb;
    for (ma = 0; ma < mesh_count; ++ma)
        for (mb = ma; mb < mesh_count; ++mb) {
            if (ma == mb && !meshes[ma].self) continue;
            for (ta = 0; ta < meshes[ma].triangle_count; ++ta)
                for (tb = ma == mb ? ta + 1 : 0; tb < meshes[mb].triangle_count; ++tb)
                    found += exact__pair_intersects(meshes, ma, ta, mb, tb);
        }
    return found;
}

TEST(counting_pairs_matches_brute_force)
{
    enum { N = 12 };
    double xa[3 * N * N], xb[3 * N * N];
    int32_t ta[6 * (N - 1) * (N - 1)], tb[6 * (N - 1) * (N - 1)];
    exact_mesh m[2];
    long counts[4], got, want;
    int trial, i;
    /* a flat grid and a wavy one: no pairs (adjacent pairs only meet where they share) */
    make_grid(N, xa, ta, flat);
    m[0].x = xa; m[0].tri = ta; m[0].triangle_count = 2 * (N - 1) * (N - 1); m[0].self = 1;
    ENSURE(exact_count_intersecting_pairs(m, 1, NULL) == 0);
    make_grid(N, xa, ta, wave);
    ENSURE(exact_count_intersecting_pairs(m, 1, NULL) == 0);
    /* the same grid twice as two meshes: every pair of coincident or adjacent triangles meets */
    make_grid(N, xb, tb, wave);
    m[1] = m[0];
    m[1].x = xb; m[1].tri = tb;
    got = exact_count_intersecting_pairs(m, 2, counts);
    want = brute_count(m, 2);
    ENSURE(got == want && counts[1] == got && counts[0] == 0 && counts[3] == 0 && got > 2 * (N - 1) * (N - 1));
    /* a fold: the grid's far half moved onto the near half (coplanar overlap at y = 0) */
    make_grid(N, xa, ta, flat);
    for (i = 0; i < N * N; ++i)
        if (xa[3 * i + 2] > 0.5) { xa[3 * i + 1] = 0; xa[3 * i + 2] = 1 - xa[3 * i + 2]; }
    got = exact_count_intersecting_pairs(m, 1, NULL);
    ENSURE(got == brute_count(m, 1) && got > 0);
    /* crumpled random grids, self and against a second one, an obstacle without self pairs */
    rng_state = 99;
    for (trial = 0; trial < 20; ++trial) {
        make_grid(N, xa, ta, wave);
        make_grid(N, xb, tb, flat);
        for (i = 0; i < 3 * N * N; ++i) {
            xa[i] += 0.12 * rng_dyadic(20);
            xb[i] += 0.12 * rng_dyadic(20);
        }
        m[0].self = 1;
        m[1].self = trial % 2;
        got = exact_count_intersecting_pairs(m, 2, counts);
        want = brute_count(m, 2);
        if (got != want) printf("    trial %d: grid %ld, brute force %ld\n", trial, got, want);
        ENSURE(got == want);
        ENSURE(counts[0] + counts[1] + counts[3] == got);
        ENSURE(got > 0);
    }
    /* out-of-range coordinates are refused */
    xa[4] = 1e300;
    ENSURE(exact_count_intersecting_pairs(m, 1, NULL) == -1);
}

TEST(counting_a_128x128_cloth_is_fast)
{
    enum { N = 128 };
    double *x = (double *)malloc(3 * N * N * sizeof(double));
    int32_t *t = (int32_t *)malloc(6 * (N - 1) * (N - 1) * sizeof(int32_t));
    exact_mesh m;
    clock_t c0;
    double s;
    long got;
    ENSURE(x && t);
    make_grid(N, x, t, wave);
    m.x = x; m.tri = t; m.triangle_count = 2 * (N - 1) * (N - 1); m.self = 1;
    c0 = clock();
    got = exact_count_intersecting_pairs(&m, 1, NULL);
    s = (double)(clock() - c0) / CLOCKS_PER_SEC;
    printf("    128 x 128 wavy cloth (32258 triangles): %ld pairs in %.3f s (this build)\n", got, s);
    free(x);
    free(t);
    ENSURE(got == 0);
    ENSURE(s < 5.0); /* generous here (sanitizers, shared machine); bench/stress reports -O2 times */
}

const test_case checker_tests[] = {
    { "orient_predicates_match_integer_arithmetic", orient_predicates_match_integer_arithmetic },
    { "hand_made_cases", hand_made_cases },
    { "random_triangles_match_the_separating_axis_reference", random_triangles_match_the_separating_axis_reference },
    { "pairs_sharing_a_vertex_or_an_edge", pairs_sharing_a_vertex_or_an_edge },
    { "counting_pairs_matches_brute_force", counting_pairs_matches_brute_force },
    { "counting_a_128x128_cloth_is_fast", counting_a_128x128_cloth_is_fast },
    { NULL, NULL }
};
