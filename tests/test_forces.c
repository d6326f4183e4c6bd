/* Tests of the forces module: springs, FEM membrane, dihedral bending, gravity, aerodynamics,
   gusts and damping. Every energy term is checked against finite differences (gradient and
   exact Hessian), for positive semidefinite projected Hessians, for zero energy and force at
   rest and for invariance under rigid motions; the bending stiffness is calibrated against the
   continuum energy of a cylinder. */
#include "runner.h"
#include "../cloth.h"


#include <float.h>
#include <stdlib.h>
#include <string.h>

/* The finite-difference tests need double: a central difference of a float energy loses
   about half of float's 24 bits to cancellation, so agreement to 1e-6 cannot be asked of it.
   They are compiled when cloth_real is double (the default). */
#define TEST_REAL_IS_double 1
#define TEST_REAL_IS_(t) TEST_REAL_IS_##t
#define TEST_REAL_IS(t) TEST_REAL_IS_(t)
#if TEST_REAL_IS(CLOTH_REAL)
#define FORCES_FD_TESTS 1
#endif

/* The unit roundoff of cloth_real: tolerances of exact identities scale with it. */
#define REAL_EPS ((double)(sizeof(cloth_real) < sizeof(double) ? FLT_EPSILON : DBL_EPSILON))
#define PI 3.14159265358979323846

/* ---- helpers ------------------------------------------------------------------------ */

static double uniform(cloth_rng *rng, double lo, double hi) { return lo + (hi - lo) * (double)cloth_rng_uniform(rng); }

/* Eigenvalues of a symmetric n x n matrix (n <= 12) by cyclic Jacobi rotations, in double. */
static void jacobi_eigenvalues(const cloth_real *matrix, int n, double *eigenvalue)
{
    double a[144];
    int i, j, k, sweep;
    for (i = 0; i < n * n; ++i) a[i] = (double)matrix[i];
    for (sweep = 0; sweep < 100; ++sweep) {
        double off = 0, total = 0;
        for (i = 0; i < n; ++i)
            for (j = 0; j < n; ++j) {
                total += a[i * n + j] * a[i * n + j];
                if (i != j) off += a[i * n + j] * a[i * n + j];
            }
        if (off <= 1e-30 * total) break;
        for (i = 0; i < n; ++i)
            for (j = i + 1; j < n; ++j) {
                double apq = a[i * n + j], theta, t, c, s;
                if (apq == 0) continue;
                theta = (a[j * n + j] - a[i * n + i]) / (2 * apq);
                t = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
                c = 1 / sqrt(t * t + 1);
                s = t * c;
                for (k = 0; k < n; ++k) { /* columns i, j */
                    double aki = a[k * n + i], akj = a[k * n + j];
                    a[k * n + i] = c * aki - s * akj;
                    a[k * n + j] = s * aki + c * akj;
                }
                for (k = 0; k < n; ++k) { /* rows i, j */
                    double aik = a[i * n + k], ajk = a[j * n + k];
                    a[i * n + k] = c * aik - s * ajk;
                    a[j * n + k] = s * aik + c * ajk;
                }
            }
    }
    for (i = 0; i < n; ++i) eigenvalue[i] = a[i * n + i];
}

static double min_eigenvalue(const cloth_real *matrix, int n)
{
    double ev[12], m;
    int i;
    jacobi_eigenvalues(matrix, n, ev);
    m = ev[0];
    for (i = 1; i < n; ++i)
        if (ev[i] < m) m = ev[i];
    return m;
}

static double max_abs(const cloth_real *a, int n)
{
    double m = 0;
    int i;
    for (i = 0; i < n; ++i)
        if (fabs((double)a[i]) > m) m = fabs((double)a[i]);
    return m;
}

static int is_symmetric(const cloth_real *h, int n)
{
    int i, j;
    for (i = 0; i < n; ++i)
        for (j = 0; j < n; ++j)
            if (h[i * n + j] != h[j * n + i]) return 0;
    return 1;
}

/* A random rotation (from a random unit quaternion) as a row-major 3x3 matrix. */
static void random_rotation(cloth_rng *rng, double *r)
{
    double q[4], n = 0;
    int k;
    for (k = 0; k < 4; ++k) { q[k] = (double)cloth_rng_normal(rng); n += q[k] * q[k]; }
    n = sqrt(n);
    for (k = 0; k < 4; ++k) q[k] /= n;
    r[0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]); r[1] = 2 * (q[1] * q[2] - q[0] * q[3]); r[2] = 2 * (q[1] * q[3] + q[0] * q[2]);
    r[3] = 2 * (q[1] * q[2] + q[0] * q[3]); r[4] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]); r[5] = 2 * (q[2] * q[3] - q[0] * q[1]);
    r[6] = 2 * (q[1] * q[3] - q[0] * q[2]); r[7] = 2 * (q[2] * q[3] + q[0] * q[1]); r[8] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
}

/* out[3k] = R in[3k] + t, vertex by vertex. */
static void rigid_apply(const double *r, const double *t, const cloth_real *in, int count, cloth_real *out)
{
    int v, i;
    for (v = 0; v < count; ++v)
        for (i = 0; i < 3; ++i)
            out[3 * v + i] = (cloth_real)(r[3 * i] * in[3 * v] + r[3 * i + 1] * in[3 * v + 1] + r[3 * i + 2] * in[3 * v + 2] +
                                          (t ? t[i] : 0));
}

/* A uniform interface over the energy kernels: x[3 * vertices] in, energy out. */
typedef struct energy_term {
    int vertices;
    cloth_real (*eval)(const struct energy_term *term, const cloth_real *x, cloth_real *gradient, cloth_real *hessian,
                       cloth_hessian_form form);
    cloth_real stiffness, rest_length, limit;
    cloth_real target[3];
    cloth_membrane_rest membrane;
    cloth_membrane_stiffness material;
    cloth_bending_rest bending;
} energy_term;

static cloth_real eval_spring(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ return cloth_spring_energy(x, x + 3, t->stiffness, t->rest_length, g, h, f); }
static cloth_real eval_strain_limit(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ (void)f; return cloth_strain_limit_energy(x, x + 3, t->stiffness, t->rest_length, t->limit, g, h); }
static cloth_real eval_attachment(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ (void)f; return cloth_attachment_energy(x, t->target, t->stiffness, g, h); }
static cloth_real eval_gravity(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ (void)f; return cloth_gravity_energy(x, t->stiffness, t->target, g, h); }
static cloth_real eval_membrane(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ return cloth_membrane_energy(x, x + 3, x + 6, &t->membrane, &t->material, g, h, f); }
static cloth_real eval_bending(const energy_term *t, const cloth_real *x, cloth_real *g, cloth_real *h, cloth_hessian_form f)
{ return cloth_bending_energy(x, x + 3, x + 6, x + 9, &t->bending, t->stiffness, g, h, f); }

#ifdef FORCES_FD_TESTS
/* Largest difference between the kernel's gradient and a central difference of its energy,
   relative to the gradient's largest entry. */
static double gradient_error(const energy_term *t, const cloth_real *x0, double step)
{
    cloth_real x[12], g[12];
    double err = 0, scale;
    int i, n = 3 * t->vertices;
    memcpy(x, x0, sizeof(cloth_real) * (size_t)n);
    t->eval(t, x, g, NULL, CLOTH_HESSIAN_EXACT);
    for (i = 0; i < n; ++i) {
        double ep, em, fd;
        x[i] = x0[i] + step;
        ep = (double)t->eval(t, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
        x[i] = x0[i] - step;
        em = (double)t->eval(t, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
        x[i] = x0[i];
        fd = (ep - em) / (2 * step);
        if (fabs(fd - g[i]) > err) err = fabs(fd - g[i]);
    }
    scale = max_abs(g, n);
    return err / (scale > 0 ? scale : 1);
}

/* The same for the exact Hessian against central differences of the gradient. */
static double hessian_error(const energy_term *t, const cloth_real *x0, double step)
{
    cloth_real x[12], h[144], gp[12], gm[12];
    double err = 0, scale;
    int i, j, n = 3 * t->vertices;
    memcpy(x, x0, sizeof(cloth_real) * (size_t)n);
    t->eval(t, x, NULL, h, CLOTH_HESSIAN_EXACT);
    for (j = 0; j < n; ++j) {
        x[j] = x0[j] + step;
        t->eval(t, x, gp, NULL, CLOTH_HESSIAN_EXACT);
        x[j] = x0[j] - step;
        t->eval(t, x, gm, NULL, CLOTH_HESSIAN_EXACT);
        x[j] = x0[j];
        for (i = 0; i < n; ++i) {
            double fd = ((double)gp[i] - gm[i]) / (2 * step);
            if (fabs(fd - h[i * n + j]) > err) err = fabs(fd - h[i * n + j]);
        }
    }
    scale = max_abs(h, n * n);
    return err / (scale > 0 ? scale : 1);
}
#endif

/* Energy invariance and gradient covariance under a random rigid motion. */
static int rigid_invariant(const energy_term *t, const cloth_real *x, cloth_rng *rng, double tol)
{
    cloth_real y[12], g[12], gy[12], rg[12];
    double r[9], shift[3], e, ey, gscale;
    int i, n = 3 * t->vertices;
    random_rotation(rng, r);
    for (i = 0; i < 3; ++i) shift[i] = uniform(rng, -2, 2);
    rigid_apply(r, shift, x, t->vertices, y);
    e = (double)t->eval(t, x, g, NULL, CLOTH_HESSIAN_EXACT);
    ey = (double)t->eval(t, y, gy, NULL, CLOTH_HESSIAN_EXACT);
    rigid_apply(r, NULL, g, t->vertices, rg);
    gscale = max_abs(g, n);
    if (!(fabs(e - ey) <= tol * (fabs(e) + 1e-30))) { printf("    energy %.17g vs %.17g\n", e, ey); return 0; }
    for (i = 0; i < n; ++i)
        if (!(fabs((double)rg[i] - gy[i]) <= tol * gscale)) { printf("    gradient %d: %.17g vs %.17g\n", i, (double)rg[i], (double)gy[i]); return 0; }
    return 1;
}

static void random_points(cloth_rng *rng, cloth_real *x, int n, double lo, double hi)
{
    int i;
    for (i = 0; i < n; ++i) x[i] = (cloth_real)uniform(rng, lo, hi);
}

/* ---- springs ----------------------------------------------------------------------- */

static energy_term spring_term(cloth_real k, cloth_real rest_length)
{
    energy_term t;
    memset(&t, 0, sizeof t);
    t.vertices = 2;
    t.eval = eval_spring;
    t.stiffness = k;
    t.rest_length = rest_length;
    return t;
}

#ifdef FORCES_FD_TESTS
TEST(spring_derivatives_match_finite_differences)
{
    cloth_rng rng = cloth_rng_make(11);
    int trial;
    for (trial = 0; trial < 40; ++trial) {
        cloth_real x[6];
        /* stretched and compressed springs, and seams (rest length 0) */
        energy_term t = spring_term((cloth_real)uniform(&rng, 10, 1000), trial % 4 == 0 ? 0 : (cloth_real)uniform(&rng, 0.2, 2));
        random_points(&rng, x, 6, -1, 1);
        ENSURE(gradient_error(&t, x, 1e-6) < 1e-6);
        ENSURE(hessian_error(&t, x, 1e-6) < 1e-6);
    }
}
#endif

TEST(spring_projected_hessian_is_psd)
{
    cloth_rng rng = cloth_rng_make(12);
    cloth_real xi[3] = { 0, 0, 0 }, xj[3] = { (cloth_real)0.5, 0, 0 }, he[36], hp[36];
    int trial, found_indefinite = 0;
    /* A compressed spring's exact Hessian is indefinite; the projected one is not. */
    cloth_spring_energy(xi, xj, 100, 1, NULL, he, CLOTH_HESSIAN_EXACT);
    cloth_spring_energy(xi, xj, 100, 1, NULL, hp, CLOTH_HESSIAN_PROJECTED);
    ENSURE(min_eigenvalue(he, 6) < -50); /* transverse term k (1 - L/l) = -100, doubled by the two ends */
    ENSURE(min_eigenvalue(hp, 6) > -1e-9);
    for (trial = 0; trial < 200; ++trial) {
        cloth_real x[6], h[36], hx[36];
        cloth_real k = (cloth_real)uniform(&rng, 1, 100), rest = (cloth_real)uniform(&rng, 0, 2);
        double l, scale;
        random_points(&rng, x, 6, -1, 1);
        cloth_spring_energy(x, x + 3, k, rest, NULL, h, CLOTH_HESSIAN_PROJECTED);
        cloth_spring_energy(x, x + 3, k, rest, NULL, hx, CLOTH_HESSIAN_EXACT);
        ENSURE(is_symmetric(h, 6));
        scale = max_abs(h, 36);
        ENSURE(min_eigenvalue(h, 6) >= -1e3 * REAL_EPS * scale);
        l = sqrt(((double)x[0] - x[3]) * ((double)x[0] - x[3]) + ((double)x[1] - x[4]) * ((double)x[1] - x[4]) +
                 ((double)x[2] - x[5]) * ((double)x[2] - x[5]));
        if (l >= rest) ENSURE(memcmp(h, hx, sizeof h) == 0); /* stretched: projected is exact */
        else if (min_eigenvalue(hx, 6) < -1e3 * REAL_EPS * scale) ++found_indefinite;
    }
    ENSURE(found_indefinite > 10);
}

TEST(spring_rest_rigid_motion_and_seam)
{
    cloth_rng rng = cloth_rng_make(13);
    cloth_real x[6] = { (cloth_real)0.1, (cloth_real)0.2, (cloth_real)0.3, (cloth_real)0.4, (cloth_real)-0.2, (cloth_real)0.3 };
    cloth_real g[6], h[36], e;
    energy_term t = spring_term(250, (cloth_real)0.5);
    int trial, i;
    /* at rest: length 0.5 */
    e = cloth_spring_energy(x, x + 3, 250, (cloth_real)0.5, g, NULL, CLOTH_HESSIAN_EXACT);
    ENSURE(fabs((double)e) <= 1e2 * REAL_EPS);
    ENSURE(max_abs(g, 6) <= 1e3 * REAL_EPS * 250);
    /* the force pulls a stretched spring's ends together, with magnitude k (l - L) */
    x[3] = (cloth_real)0.7;
    e = cloth_spring_energy(x, x + 3, 250, (cloth_real)0.5, g, NULL, CLOTH_HESSIAN_EXACT);
    ENSURE_NEAR(e, 125 * (sqrt(0.6 * 0.6 + 0.16) - 0.5) * (sqrt(0.6 * 0.6 + 0.16) - 0.5), 1e3 * REAL_EPS);
    ENSURE(-g[0] > 0 && -g[3] < 0); /* vertex 0 (x = 0.1) pulled towards +x, vertex 1 towards -x */
    ENSURE_NEAR(sqrt((double)g[0] * g[0] + (double)g[1] * g[1] + (double)g[2] * g[2]), 250 * (sqrt(0.52) - 0.5), 1e4 * REAL_EPS);
    for (trial = 0; trial < 20; ++trial) {
        random_points(&rng, x, 6, -1, 1);
        ENSURE(rigid_invariant(&t, x, &rng, 1e3 * REAL_EPS));
    }
    /* a seam (rest length 0) is smooth through coincident vertices: E = 0, H = k [I -I; -I I] */
    for (i = 0; i < 3; ++i) x[3 + i] = x[i];
    e = cloth_spring_energy(x, x + 3, 40, 0, g, h, CLOTH_HESSIAN_PROJECTED);
    ENSURE(e == 0 && max_abs(g, 6) == 0);
    ENSURE(h[0] == 40 && h[7] == 40 && h[3] == -40 && h[1] == 0 && h[6 * 3 + 0] == -40 && h[35] == 40);
    /* a spring of positive rest length through coincident vertices: energy k L^2 / 2, no direction */
    e = cloth_spring_energy(x, x + 3, 40, 2, g, h, CLOTH_HESSIAN_EXACT);
    ENSURE_NEAR(e, 80, 1e-12);
    ENSURE(max_abs(g, 6) == 0 && max_abs(h, 36) == 0);
}

/* The edge length of a two-vertex x. */
static double edge_length(const cloth_real *x)
{
    return sqrt(((double)x[0] - x[3]) * ((double)x[0] - x[3]) + ((double)x[1] - x[4]) * ((double)x[1] - x[4]) +
                ((double)x[2] - x[5]) * ((double)x[2] - x[5]));
}

TEST(strain_limit_engages_beyond_its_limit_only)
{
    cloth_rng rng = cloth_rng_make(14);
    energy_term t;
    int trial, engaged = 0, idle = 0;
    memset(&t, 0, sizeof t);
    t.vertices = 2;
    t.eval = eval_strain_limit;
    for (trial = 0; trial < 200; ++trial) {
        cloth_real x[6], g[6], h[36], gs[6], hs[36], e;
        double l, engaged_length;
        t.stiffness = (cloth_real)uniform(&rng, 10, 1e4);
        t.rest_length = (cloth_real)uniform(&rng, 0.2, 1);
        t.limit = (cloth_real)(trial % 5 == 0 ? 0 : uniform(&rng, 0, 0.2));
        random_points(&rng, x, 6, -0.7, 0.7);
        l = edge_length(x);
        engaged_length = (1 + (double)t.limit) * (double)t.rest_length;
        e = cloth_strain_limit_energy(x, x + 3, t.stiffness, t.rest_length, t.limit, g, h);
        if (l <= engaged_length) {
            /* below the limit: nothing at all */
            ENSURE(e == 0 && max_abs(g, 6) == 0 && max_abs(h, 36) == 0);
            ++idle;
            continue;
        }
        ++engaged;
        /* beyond it: a spring of rest length (1 + limit) L, whose Hessian is PSD there */
        ENSURE(e == cloth_spring_energy(x, x + 3, t.stiffness, (cloth_real)engaged_length, gs, hs, CLOTH_HESSIAN_EXACT));
        ENSURE(memcmp(g, gs, sizeof g) == 0 && memcmp(h, hs, sizeof h) == 0);
        ENSURE_NEAR(e, (double)t.stiffness / 2 * (l - engaged_length) * (l - engaged_length), 1e3 * REAL_EPS * (1 + (double)e));
        ENSURE(min_eigenvalue(h, 6) >= -1e3 * REAL_EPS * max_abs(h, 36));
        ENSURE(rigid_invariant(&t, x, &rng, 1e3 * REAL_EPS));
#ifdef FORCES_FD_TESTS
        if (l - engaged_length > 1e-4) { /* away from the kink of the Hessian */
            ENSURE(gradient_error(&t, x, 1e-6) < 1e-6);
            ENSURE(hessian_error(&t, x, 1e-6) < 1e-6);
        }
#endif
    }
    ENSURE(engaged > 40 && idle > 40);
    {
        /* the force is continuous at the limit: just beyond it, it is k times the excess */
        cloth_real x[6] = { 0, 0, 0, 0, 0, 0 }, g[6];
        x[3] = (cloth_real)(1.05 * (1 + 1e-9));
        ENSURE(cloth_strain_limit_energy(x, x + 3, 1000, 1, (cloth_real)0.05, g, NULL) >= 0);
        ENSURE(max_abs(g, 6) <= 1000 * 1.05 * 2e-9 + 1e4 * REAL_EPS);
        x[3] = (cloth_real)1.049;
        ENSURE(cloth_strain_limit_energy(x, x + 3, 1000, 1, (cloth_real)0.05, g, NULL) == 0 && max_abs(g, 6) == 0);
    }
}

TEST(attachment_and_gravity)
{
    cloth_real x[3] = { 1, 2, 3 }, target[3] = { (cloth_real)0.5, 2, 4 }, g[3], h[9], e;
    cloth_real gravity[3] = { 0, (cloth_real)-9.81, 0 };
    energy_term t;
    e = cloth_attachment_energy(x, target, 200, g, h);
    ENSURE_NEAR(e, 100 * (0.25 + 1), 1e3 * REAL_EPS);
    ENSURE_NEAR(g[0], 100, 1e3 * REAL_EPS);
    ENSURE_NEAR(g[2], -200, 1e3 * REAL_EPS);
    ENSURE(h[0] == 200 && h[4] == 200 && h[8] == 200 && h[1] == 0 && h[5] == 0);
    e = cloth_attachment_energy(target, target, 200, g, NULL);
    ENSURE(e == 0 && max_abs(g, 3) == 0);
    e = cloth_gravity_energy(x, (cloth_real)0.01, gravity, g, h);
    ENSURE_NEAR(e, 0.01 * 9.81 * 2, 1e2 * REAL_EPS);
    ENSURE_NEAR(g[1], 0.0981, 1e2 * REAL_EPS); /* the force -g is m g, downwards */
    ENSURE(g[0] == 0 && g[2] == 0 && max_abs(h, 9) == 0);
    /* the uniform interface works for both (finite differences below) */
    memset(&t, 0, sizeof t);
    t.vertices = 1;
    t.eval = eval_attachment;
    t.stiffness = 200;
    memcpy(t.target, target, sizeof target);
#ifdef FORCES_FD_TESTS
    ENSURE(gradient_error(&t, x, 1e-6) < 1e-6);
    ENSURE(hessian_error(&t, x, 1e-6) < 1e-6);
#endif
    t.eval = eval_gravity;
    t.stiffness = (cloth_real)0.01;
    memcpy(t.target, gravity, sizeof gravity);
    ENSURE_NEAR(t.eval(&t, x, NULL, NULL, CLOTH_HESSIAN_EXACT), 0.01 * 9.81 * 2, 1e2 * REAL_EPS);
#ifdef FORCES_FD_TESTS
    ENSURE(gradient_error(&t, x, 1e-6) < 1e-6);
#endif
}

/* Whether pair (a, b) appears among the first n springs, and how often. */
static int spring_multiplicity(const int32_t *pair, int32_t n, int32_t a, int32_t b)
{
    int32_t s;
    int m = 0;
    for (s = 0; s < n; ++s)
        if ((pair[2 * s] == a && pair[2 * s + 1] == b) || (pair[2 * s] == b && pair[2 * s + 1] == a)) ++m;
    return m;
}

TEST(grid_springs_are_provots)
{
    const int32_t nx = 5, ny = 4;
    int32_t count, n_struct, n_shear, n_bend, s, kind[200], pair[400];
    cloth_real rest[200];
    cloth_mesh mesh;
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_STRUCTURAL, NULL, NULL, 0, &n_struct) == CLOTH_SUCCESS);
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_SHEAR, NULL, NULL, 0, &n_shear) == CLOTH_SUCCESS);
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_BEND, NULL, NULL, 0, &n_bend) == CLOTH_SUCCESS);
    ENSURE(n_struct == (nx - 1) * ny + nx * (ny - 1));
    ENSURE(n_shear == 2 * (nx - 1) * (ny - 1));
    ENSURE(n_bend == (nx - 2) * ny + nx * (ny - 2));
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_ALL, NULL, NULL, 0, &count) == CLOTH_SUCCESS);
    ENSURE(count == n_struct + n_shear + n_bend && count <= 200);
    /* too little room, bad sizes, bad kinds */
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_ALL, pair, kind, count - 1, &s) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_grid_springs(1, ny, CLOTH_SPRING_ALL, NULL, NULL, 0, &s) == CLOTH_ERROR_INVALID_ARGUMENT && s == 0);
    ENSURE(cloth_grid_springs(nx, ny, 8, NULL, NULL, 0, &s) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_grid_springs(100000, 100000, CLOTH_SPRING_ALL, NULL, NULL, 0, &s) == CLOTH_ERROR_SIZE_OVERFLOW);
    ENSURE(cloth_grid_springs(nx, ny, CLOTH_SPRING_ALL, pair, kind, 200, &count) == CLOTH_SUCCESS);
    /* each spring once, in kind order, with the rest length of its kind on a 0.4 x 0.3 grid
       (cell 0.1 x 0.1) */
    ENSURE(cloth_mesh_grid(&mesh, nx, ny, (cloth_real)0.4, (cloth_real)0.3, CLOTH_GRID_DIAGONAL_REGULAR, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_spring_rest_lengths(mesh.uv, 2, mesh.vertex_count, pair, count, rest) == CLOTH_SUCCESS);
    for (s = 0; s < count; ++s) {
        double expect = kind[s] == CLOTH_SPRING_STRUCTURAL ? 0.1 : kind[s] == CLOTH_SPRING_SHEAR ? sqrt(0.02) : 0.2;
        ENSURE(pair[2 * s] < pair[2 * s + 1] && pair[2 * s] >= 0 && pair[2 * s + 1] < nx * ny);
        ENSURE(spring_multiplicity(pair, count, pair[2 * s], pair[2 * s + 1]) == 1);
        ENSURE(kind[s] == (s < n_struct                ? CLOTH_SPRING_STRUCTURAL
                           : s < n_struct + n_shear ? CLOTH_SPRING_SHEAR
                                                    : CLOTH_SPRING_BEND));
        ENSURE_NEAR(rest[s], expect, 1e2 * REAL_EPS);
    }
    /* the named Provot springs of vertex (1, 1) are there */
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 1, 1 * nx + 2) == 1);
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 1, 2 * nx + 1) == 1);
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 1, 2 * nx + 2) == 1);
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 2, 2 * nx + 1) == 1);
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 1, 1 * nx + 3) == 1);
    ENSURE(spring_multiplicity(pair, count, 1 * nx + 1, 3 * nx + 1) == 1);
    /* rest lengths also from 3D points, and index checks */
    ENSURE(cloth_spring_rest_lengths(mesh.x, 3, mesh.vertex_count, pair, count, rest) == CLOTH_SUCCESS);
    ENSURE_NEAR(rest[0], 0.1, 1e2 * REAL_EPS);
    pair[5] = nx * ny;
    ENSURE(cloth_spring_rest_lengths(mesh.x, 3, mesh.vertex_count, pair, count, rest) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    ENSURE(cloth_spring_rest_lengths(mesh.x, 4, mesh.vertex_count, pair, count, rest) == CLOTH_ERROR_INVALID_ARGUMENT);
    cloth_mesh_free(&mesh);
}

TEST(topology_springs_edges_and_hinges)
{
    /* two triangles sharing the edge 1-2: one hinge, between 0 and 3 */
    cloth_real x[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
    int32_t tri[6] = { 0, 1, 2, 1, 3, 2 }, pair[40], kind[20], count, s, n_edges = 0;
    cloth_mesh mesh, grid;
    cloth_topology topo;
    memset(&mesh, 0, sizeof mesh);
    mesh.vertex_count = 4;
    mesh.triangle_count = 2;
    mesh.x = x;
    mesh.tri = tri;
    ENSURE(cloth_topology_build(&topo, &mesh, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_topology_springs(&topo, CLOTH_SPRING_ALL, pair, kind, 20, &count) == CLOTH_SUCCESS);
    ENSURE(count == 6);
    for (s = 0; s < 5; ++s) ENSURE(kind[s] == CLOTH_SPRING_STRUCTURAL);
    ENSURE(kind[5] == CLOTH_SPRING_BEND && pair[10] == 0 && pair[11] == 3);
    ENSURE(spring_multiplicity(pair, 5, 1, 2) == 1 && spring_multiplicity(pair, 5, 0, 3) == 0);
    ENSURE(cloth_topology_springs(&topo, CLOTH_SPRING_BEND, pair, kind, 0, &count) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_topology_springs(&topo, 9, NULL, NULL, 0, &count) == CLOTH_ERROR_INVALID_ARGUMENT);
    cloth_topology_free(&topo);
    /* on a grid: one spring per edge and one per interior edge */
    ENSURE(cloth_mesh_grid(&grid, 4, 3, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_topology_build(&topo, &grid, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_topology_springs(&topo, CLOTH_SPRING_STRUCTURAL, NULL, NULL, 0, &n_edges) == CLOTH_SUCCESS);
    ENSURE(n_edges == topo.edge_count && n_edges == 3 * 3 + 4 * 2 + 6);
    ENSURE(cloth_topology_springs(&topo, CLOTH_SPRING_BEND | CLOTH_SPRING_SHEAR, NULL, NULL, 0, &count) == CLOTH_SUCCESS);
    ENSURE(count == topo.edge_count - topo.boundary_edge_count);
    cloth_topology_free(&topo);
    cloth_mesh_free(&grid);
}

/* ---- membrane ---------------------------------------------------------------------- */

static energy_term membrane_term(const cloth_real *uv, cloth_membrane_stiffness material)
{
    energy_term t;
    memset(&t, 0, sizeof t);
    t.vertices = 3;
    t.eval = eval_membrane;
    t.material = material;
    cloth_membrane_rest_make(&t.membrane, uv, uv + 2, uv + 4);
    return t;
}

static cloth_membrane_stiffness stiffness4(double c11, double c12, double c22, double c33)
{
    cloth_membrane_stiffness s;
    s.c11 = (cloth_real)c11;
    s.c12 = (cloth_real)c12;
    s.c22 = (cloth_real)c22;
    s.c33 = (cloth_real)c33;
    return s;
}

/* A random pattern triangle of reasonable shape (sides of a few centimetres). */
static void random_pattern_triangle(cloth_rng *rng, cloth_real *uv)
{
    for (;;) {
        double area;
        random_points(rng, uv, 6, 0, 0.05);
        area = ((double)uv[2] - uv[0]) * ((double)uv[5] - uv[1]) - ((double)uv[3] - uv[1]) * ((double)uv[4] - uv[0]);
        if (fabs(area) > 2e-4) return;
    }
}

TEST(membrane_rest_data)
{
    cloth_real uv[6] = { (cloth_real)0.1, (cloth_real)0.2, (cloth_real)0.4, (cloth_real)0.25, (cloth_real)0.2, (cloth_real)0.6 };
    cloth_real degenerate[6] = { 0, 0, 1, 1, 2, 2 }, nan_uv[6] = { 0, 0, 1, 0, 0, 1 };
    cloth_membrane_rest rest, flipped;
    double dm[4];
    ENSURE(cloth_membrane_rest_make(&rest, uv, uv + 2, uv + 4) == CLOTH_SUCCESS);
    dm[0] = 0.3; dm[1] = 0.1; dm[2] = 0.05; dm[3] = 0.4; /* [uv1 - uv0, uv2 - uv0] */
    ENSURE_NEAR(rest.dm_inverse[0] * dm[0] + rest.dm_inverse[1] * dm[2], 1, 1e2 * REAL_EPS);
    ENSURE_NEAR(rest.dm_inverse[0] * dm[1] + rest.dm_inverse[1] * dm[3], 0, 1e2 * REAL_EPS);
    ENSURE_NEAR(rest.dm_inverse[2] * dm[0] + rest.dm_inverse[3] * dm[2], 0, 1e2 * REAL_EPS);
    ENSURE_NEAR(rest.dm_inverse[2] * dm[1] + rest.dm_inverse[3] * dm[3], 1, 1e2 * REAL_EPS);
    ENSURE_NEAR(rest.area, (0.3 * 0.4 - 0.05 * 0.1) / 2, 1e2 * REAL_EPS);
    ENSURE(cloth_membrane_rest_make(&flipped, uv, uv + 4, uv + 2) == CLOTH_SUCCESS); /* clockwise */
    ENSURE_NEAR(flipped.area, rest.area, 1e2 * REAL_EPS);
    ENSURE(cloth_membrane_rest_make(&rest, degenerate, degenerate + 2, degenerate + 4) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    ENSURE(rest.area == 0 && rest.dm_inverse[0] == 0);
    ENSURE(cloth_membrane_rest_make(&rest, uv, uv, uv + 4) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    nan_uv[3] = (cloth_real)strtod("nan", NULL);
    ENSURE(cloth_membrane_rest_make(&rest, nan_uv, nan_uv + 2, nan_uv + 4) == CLOTH_ERROR_NOT_FINITE);
}

#ifdef FORCES_FD_TESTS
TEST(membrane_derivatives_match_finite_differences)
{
    cloth_rng rng = cloth_rng_make(21);
    int trial;
    for (trial = 0; trial < 40; ++trial) {
        cloth_real uv[6], x[9];
        /* warp stiffer than weft, as in a woven fabric; N/m */
        energy_term t;
        random_pattern_triangle(&rng, uv);
        t = membrane_term(uv, stiffness4(uniform(&rng, 1e3, 5e3), uniform(&rng, 0, 500), uniform(&rng, 500, 2e3),
                                         uniform(&rng, 100, 800)));
        /* deformed: a random stretch/compression/shear of the pattern in 3D */
        random_points(&rng, x, 9, -0.06, 0.06);
        ENSURE(gradient_error(&t, x, 1e-7) < 1e-6);
        ENSURE(hessian_error(&t, x, 1e-7) < 1e-6);
    }
}
#endif

TEST(membrane_projected_hessian_is_psd)
{
    cloth_rng rng = cloth_rng_make(22);
    int trial, indefinite = 0, exact_when_stretched = 0;
    for (trial = 0; trial < 200; ++trial) {
        cloth_real uv[6], x[9], hp[81], he[81], strain[3];
        energy_term t;
        double scale, s00, s11, s01, a, b, c;
        int k;
        random_pattern_triangle(&rng, uv);
        t = membrane_term(uv, stiffness4(uniform(&rng, 1e3, 5e3), uniform(&rng, 0, 500), uniform(&rng, 500, 2e3),
                                         uniform(&rng, 100, 800)));
        /* the pattern, scaled by 0.7 .. 1.3 and sheared, placed in 3D, plus noise */
        a = uniform(&rng, 0.7, 1.3);
        b = uniform(&rng, 0.7, 1.3);
        c = uniform(&rng, -0.3, 0.3);
        for (k = 0; k < 3; ++k) {
            x[3 * k] = (cloth_real)(a * uv[2 * k] + c * uv[2 * k + 1] + uniform(&rng, -0.003, 0.003));
            x[3 * k + 1] = (cloth_real)(b * uv[2 * k + 1] + uniform(&rng, -0.003, 0.003));
            x[3 * k + 2] = (cloth_real)uniform(&rng, -0.005, 0.005);
        }
        t.eval(&t, x, NULL, hp, CLOTH_HESSIAN_PROJECTED);
        t.eval(&t, x, NULL, he, CLOTH_HESSIAN_EXACT);
        ENSURE(is_symmetric(hp, 9) && is_symmetric(he, 9));
        scale = max_abs(he, 81);
        ENSURE(min_eigenvalue(hp, 9) >= -1e3 * REAL_EPS * scale);
        if (min_eigenvalue(he, 9) < -1e-6 * scale) ++indefinite;
        /* the projection only adds stiffness: hp - he = the negative part of S, mapped, is PSD */
        {
            cloth_real diff[81];
            for (k = 0; k < 81; ++k) diff[k] = hp[k] - he[k];
            ENSURE(min_eigenvalue(diff, 9) >= -1e3 * REAL_EPS * scale);
        }
        /* under tension in both principal directions (S positive definite) the two agree */
        cloth_membrane_strain(x, x + 3, x + 6, &t.membrane, strain);
        s00 = t.material.c11 * strain[0] + t.material.c12 * strain[1];
        s11 = t.material.c12 * strain[0] + t.material.c22 * strain[1];
        s01 = 2 * t.material.c33 * strain[2];
        if (s00 > 0 && s00 * s11 - s01 * s01 > 0) {
            for (k = 0; k < 81; ++k) ENSURE(fabs((double)hp[k] - he[k]) <= 1e2 * REAL_EPS * scale);
            ++exact_when_stretched;
        }
    }
    ENSURE(indefinite > 20);          /* compression makes the exact Hessian indefinite ... */
    ENSURE(exact_when_stretched > 5); /* ... and both cases were exercised */
}

TEST(membrane_projected_hessian_stiffens_compressed_sheets_out_of_plane)
{
    /* A flat triangle compressed in both directions: out of its plane (the z rows and columns)
       the material term vanishes, so the exact Hessian there is the geometric term alone, S
       mapped, negative; the projected form's |S| is the same with the opposite sign (clamping at
       zero would give no stiffness at all there, and a Newton step nothing to stop it). */
    cloth_rng rng = cloth_rng_make(24);
    int trial;
    for (trial = 0; trial < 20; ++trial) {
        cloth_real uv[6], x[9], hp[81], he[81], zz[9];
        energy_term t;
        double squeeze = uniform(&rng, 0.8, 0.98), scale;
        int a, b;
        random_pattern_triangle(&rng, uv);
        t = membrane_term(uv, stiffness4(uniform(&rng, 1e3, 5e3), uniform(&rng, 0, 500), uniform(&rng, 500, 2e3),
                                         uniform(&rng, 100, 800)));
        for (a = 0; a < 3; ++a) {
            x[3 * a] = (cloth_real)(squeeze * uv[2 * a]);
            x[3 * a + 1] = (cloth_real)(squeeze * uv[2 * a + 1]);
            x[3 * a + 2] = 0;
        }
        t.eval(&t, x, NULL, hp, CLOTH_HESSIAN_PROJECTED);
        t.eval(&t, x, NULL, he, CLOTH_HESSIAN_EXACT);
        scale = max_abs(he, 81);
        for (a = 0; a < 3; ++a)
            for (b = 0; b < 3; ++b) {
                ENSURE(fabs((double)hp[9 * (3 * a + 2) + 3 * b + 2] + he[9 * (3 * a + 2) + 3 * b + 2]) <= 1e2 * REAL_EPS * scale);
                zz[3 * a + b] = he[9 * (3 * a + 2) + 3 * b + 2];
            }
        ENSURE(min_eigenvalue(zz, 3) < -1e-6 * scale); /* the exact form is unstable there */
    }
}

TEST(membrane_rest_and_rigid_motion)
{
    cloth_rng rng = cloth_rng_make(23);
    int trial;
    for (trial = 0; trial < 20; ++trial) {
        cloth_real uv[6], flat[9], x[9], g[9], e;
        double r[9], shift[3];
        energy_term t;
        int k;
        random_pattern_triangle(&rng, uv);
        t = membrane_term(uv, stiffness4(3000, 300, 1500, 400));
        for (k = 0; k < 3; ++k) {
            flat[3 * k] = uv[2 * k];
            flat[3 * k + 1] = uv[2 * k + 1];
            flat[3 * k + 2] = 0;
        }
        /* the pattern moved rigidly into space is at rest */
        random_rotation(&rng, r);
        for (k = 0; k < 3; ++k) shift[k] = uniform(&rng, -1, 1);
        rigid_apply(r, shift, flat, 3, x);
        e = t.eval(&t, x, g, NULL, CLOTH_HESSIAN_EXACT);
        ENSURE(fabs((double)e) <= 1e4 * REAL_EPS * REAL_EPS * 3000 * t.membrane.area + 1e-30);
        ENSURE(max_abs(g, 9) <= 1e3 * REAL_EPS * 3000 * 0.05);
        /* a deformed triangle keeps its energy under rigid motion */
        random_points(&rng, x, 9, -0.06, 0.06);
        ENSURE(rigid_invariant(&t, x, &rng, 1e4 * REAL_EPS));
    }
}

TEST(membrane_uniaxial_stretch_gives_analytic_stress)
{
    /* right triangle along the axes of the pattern, a = 0.04 m along u, b = 0.03 m along v */
    const double a = 0.04, b = 0.03;
    cloth_real uv[6], x[9], g[9], strain[3], e;
    cloth_membrane_stiffness m = stiffness4(2000, 400, 1000, 300);
    energy_term t;
    double s, e11, e22;
    int k, dir;
    uv[0] = 0; uv[1] = 0; uv[2] = (cloth_real)a; uv[3] = 0; uv[4] = 0; uv[5] = (cloth_real)b;
    t = membrane_term(uv, m);
    for (dir = 0; dir < 2; ++dir)
        for (s = -0.1; s <= 0.31; s += 0.1) {
            /* x = (1 + s) u along the stretched axis, the other axis unchanged (no lateral contraction) */
            for (k = 0; k < 3; ++k) {
                x[3 * k] = (cloth_real)(uv[2 * k] * (dir == 0 ? 1 + s : 1));
                x[3 * k + 1] = 0;
                x[3 * k + 2] = (cloth_real)(uv[2 * k + 1] * (dir == 1 ? 1 + s : 1));
            }
            cloth_membrane_strain(x, x + 3, x + 6, &t.membrane, strain);
            e11 = ((1 + s) * (1 + s) - 1) / 2;
            ENSURE_NEAR(strain[dir], e11, 1e2 * REAL_EPS);
            ENSURE_NEAR(strain[1 - dir], 0, 1e2 * REAL_EPS);
            ENSURE_NEAR(strain[2], 0, 1e2 * REAL_EPS);
            e = t.eval(&t, x, g, NULL, CLOTH_HESSIAN_EXACT);
            /* energy = area * c E^2 / 2 with c = c11 (warp) or c22 (weft) */
            ENSURE_NEAR(e, a * b / 2 * (dir == 0 ? 2000.0 : 1000.0) * e11 * e11 / 2, 1e3 * REAL_EPS * (fabs(e) + 1e-12));
            if (dir == 0) {
                /* vertex 1 (at u = a) carries the traction S11 F11 = c11 E11 (1 + s) over half the edge of length b */
                ENSURE_NEAR(-g[3], -b / 2 * (1 + s) * 2000 * e11, 1e3 * REAL_EPS * 100);
                /* Poisson coupling: S22 = c12 E11 pulls vertex 2 (at v = b) back along v, over half the edge a */
                ENSURE_NEAR(g[8], a / 2 * 400 * e11, 1e3 * REAL_EPS * 100);
            } else {
                ENSURE_NEAR(g[8], a / 2 * (1 + s) * 1000 * e11, 1e3 * REAL_EPS * 100);
                ENSURE_NEAR(g[3], b / 2 * 400 * e11, 1e3 * REAL_EPS * 100);
            }
        }
    /* shear: x = u + gamma v along u gives E12 = gamma / 2, E22 = gamma^2 / 2, W's shear part 2 c33 E12^2 */
    for (k = 0; k < 3; ++k) {
        x[3 * k] = (cloth_real)(uv[2 * k] + 0.2 * uv[2 * k + 1]);
        x[3 * k + 1] = 0;
        x[3 * k + 2] = uv[2 * k + 1];
    }
    e = t.eval(&t, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
    e22 = 0.02;
    ENSURE_NEAR(e, a * b / 2 * (1000 * e22 * e22 / 2 + 2 * 300 * 0.1 * 0.1), 1e3 * REAL_EPS * e);
}

TEST(membrane_isotropy_and_anisotropy)
{
    cloth_rng rng = cloth_rng_make(24);
    cloth_membrane_stiffness iso = cloth_membrane_stiffness_isotropic(2e6, (cloth_real)5e-4, (cloth_real)0.3);
    cloth_membrane_stiffness ortho = cloth_membrane_stiffness_orthotropic(2e6, 2e6, (cloth_real)0.3, (cloth_real)(2e6 / 2.6),
                                                                          (cloth_real)5e-4);
    cloth_membrane_stiffness aniso = cloth_membrane_stiffness_orthotropic(4e6, 1e6, (cloth_real)0.2, 3e5, (cloth_real)5e-4);
    int trial, differs = 0;
    /* Y t / (1 - nu^2) etc. */
    ENSURE_NEAR(iso.c11, 1000 / 0.91, 1e3 * REAL_EPS * 1e3);
    ENSURE_NEAR(iso.c12, 300 / 0.91, 1e3 * REAL_EPS * 1e3);
    ENSURE_NEAR(iso.c33, 1000 / 2.6, 1e3 * REAL_EPS * 1e3);
    ENSURE_NEAR(ortho.c11, iso.c11, 1e3 * REAL_EPS * 1e3);
    ENSURE_NEAR(ortho.c12, iso.c12, 1e3 * REAL_EPS * 1e3);
    ENSURE_NEAR(ortho.c33, iso.c33, 1e3 * REAL_EPS * 1e3);
    /* orthotropic: c12 = nu12 Y2 t / D is symmetric in the roles of the two axes */
    ENSURE_NEAR(aniso.c12, 0.2 * aniso.c22, 1e3 * REAL_EPS * 1e3);
    for (trial = 0; trial < 20; ++trial) {
        cloth_real uv[6], ruv[6], x[9];
        double beta = uniform(&rng, 0.2, 3.0), c = cos(beta), s = sin(beta);
        energy_term t0, t1;
        int k;
        random_pattern_triangle(&rng, uv);
        for (k = 0; k < 3; ++k) { /* the same pattern turned in its plane */
            ruv[2 * k] = (cloth_real)(c * uv[2 * k] - s * uv[2 * k + 1]);
            ruv[2 * k + 1] = (cloth_real)(s * uv[2 * k] + c * uv[2 * k + 1]);
        }
        random_points(&rng, x, 9, -0.06, 0.06);
        t0 = membrane_term(uv, iso);
        t1 = membrane_term(ruv, iso);
        {
            double e0 = (double)t0.eval(&t0, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
            double e1 = (double)t1.eval(&t1, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
            ENSURE(fabs(e0 - e1) <= 1e4 * REAL_EPS * e0);
        }
        t0 = membrane_term(uv, aniso);
        t1 = membrane_term(ruv, aniso);
        {
            double e0 = (double)t0.eval(&t0, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
            double e1 = (double)t1.eval(&t1, x, NULL, NULL, CLOTH_HESSIAN_EXACT);
            if (fabs(e0 - e1) > 1e-3 * e0) ++differs;
        }
    }
    ENSURE(differs >= 18);
}

/* ---- bending ----------------------------------------------------------------------- */

static energy_term bending_term(const cloth_real *rest_x, cloth_real stiffness)
{
    energy_term t;
    memset(&t, 0, sizeof t);
    t.vertices = 4;
    t.eval = eval_bending;
    t.stiffness = stiffness;
    cloth_bending_rest_from_shape(&t.bending, rest_x, rest_x + 3, rest_x + 6, rest_x + 9);
    return t;
}

/* A hinge: edge from (0,0,0) to (1,0,0), x2 at (0.3, cos a, sin a) * 0.8, x3 at (0.6, -cos b, sin b) * 0.7. */
static void hinge(cloth_real *x, double a, double b)
{
    memset(x, 0, sizeof(cloth_real) * 12);
    x[3] = 1;
    x[6] = (cloth_real)0.3; x[7] = (cloth_real)(0.8 * cos(a)); x[8] = (cloth_real)(0.8 * sin(a));
    x[9] = (cloth_real)0.6; x[10] = (cloth_real)(-0.7 * cos(b)); x[11] = (cloth_real)(0.7 * sin(b));
}

TEST(bending_angle_sign_rest_and_weight)
{
    cloth_real x[12], uv[8] = { 0, 0, 1, 0, (cloth_real)0.3, (cloth_real)0.8, (cloth_real)0.6, (cloth_real)-0.7 };
    cloth_real g[12];
    cloth_bending_rest rest;
    energy_term t;
    hinge(x, 0, 0);
    ENSURE_NEAR(cloth_dihedral_angle(x, x + 3, x + 6, x + 9), 0, 1e2 * REAL_EPS);
    /* front normals are +z; both wings folded down (away from the front) by 0.2: a ridge, theta = +0.4 */
    hinge(x, -0.2, -0.2);
    ENSURE_NEAR(cloth_dihedral_angle(x, x + 3, x + 6, x + 9), 0.4, 1e3 * REAL_EPS);
    /* folded up towards the front: a valley, theta < 0 */
    hinge(x, 0.5, 0.2);
    ENSURE_NEAR(cloth_dihedral_angle(x, x + 3, x + 6, x + 9), -0.7, 1e3 * REAL_EPS);
    /* nearly closed */
    hinge(x, -1.5, -1.5);
    ENSURE_NEAR(cloth_dihedral_angle(x, x + 3, x + 6, x + 9), 3.0, 1e3 * REAL_EPS);
    /* rest data from the pattern: l^2 / (2 (a0 + a1)) = 1 / (0.8 + 0.7) */
    ENSURE(cloth_bending_rest_make(&rest, uv, uv + 2, uv + 4, uv + 6, 0) == CLOTH_SUCCESS);
    ENSURE_NEAR(rest.weight, 1 / 1.5, 1e2 * REAL_EPS);
    ENSURE(rest.rest_angle == 0);
    /* E = B weight theta^2 at theta = 0.4 */
    hinge(x, -0.2, -0.2);
    ENSURE_NEAR(cloth_bending_energy(x, x + 3, x + 6, x + 9, &rest, (cloth_real)1e-4, NULL, NULL, CLOTH_HESSIAN_EXACT),
                1e-4 / 1.5 * 0.16, 1e3 * REAL_EPS * 1e-5);
    /* a curved rest shape is at rest: zero energy and force */
    hinge(x, 0.3, -0.9);
    t = bending_term(x, (cloth_real)1e-4);
    ENSURE_NEAR(t.bending.rest_angle, -0.3 + 0.9, 1e3 * REAL_EPS);
    ENSURE_NEAR(t.bending.weight, 1 / 1.5, 1e2 * REAL_EPS); /* same lengths and areas, bent */
    ENSURE(t.eval(&t, x, g, NULL, CLOTH_HESSIAN_EXACT) <= 1e-4 * 1e4 * REAL_EPS * REAL_EPS);
    ENSURE(max_abs(g, 12) <= 1e-4 * 1e3 * REAL_EPS);
    /* dtheta wraps: rest near +pi, current near -pi is a small difference */
    hinge(x, -1.5, -1.52);
    t = bending_term(x, 1);
    hinge(x, -1.58, -1.58);
    ENSURE(cloth_dihedral_angle(x, x + 3, x + 6, x + 9) < -3);
    ENSURE_NEAR(t.eval(&t, x, NULL, NULL, CLOTH_HESSIAN_EXACT), t.bending.weight * (0.14 * 0.14), 1e3 * REAL_EPS);
    /* degenerate stencils: errors for rest data, silence in the kernel */
    uv[4] = (cloth_real)0.5; uv[5] = 0;
    ENSURE(cloth_bending_rest_make(&rest, uv, uv + 2, uv + 4, uv + 6, 0) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    hinge(x, 0, 0);
    x[6] = (cloth_real)0.5; x[7] = 0; x[8] = 0;
    ENSURE(cloth_bending_rest_from_shape(&rest, x, x + 3, x + 6, x + 9) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    ENSURE(cloth_bending_energy(x, x + 3, x + 6, x + 9, &t.bending, 1, g, NULL, CLOTH_HESSIAN_EXACT) == 0);
    ENSURE(max_abs(g, 12) == 0);
}

/* The angle all the way round, through every octant and every eighth of the library's own
   atan2 (cloth.h computes the hinge angle without libm): one wing fixed, the other turned by
   b, so theta = -b, wrapped into (-pi, pi]; also with the stencil scaled and turned. */
TEST(bending_angle_all_the_way_round)
{
    cloth_real x[12], small[12], y[12];
    double r[9], shift[3] = { 0.1, -0.2, 0.3 }, worst = 0;
    cloth_rng rng = cloth_rng_make(11);
    int k, q;
    random_rotation(&rng, r);
    for (k = -3999; k < 4000; ++k) {
        double b = PI * k / 4000.0, expect = -b;
        hinge(x, 0, b);
        for (q = 0; q < 12; ++q) small[q] = (cloth_real)(x[q] * 0.01);
        rigid_apply(r, shift, small, 4, y);
        worst = fmax(worst, fabs((double)cloth_dihedral_angle(x, x + 3, x + 6, x + 9) - expect));
        /* a turned, shifted centimetre-sized copy: only the rounding of its coordinates */
        ENSURE_NEAR(cloth_dihedral_angle(y, y + 3, y + 6, y + 9), expect, 1e3 * REAL_EPS);
    }
    ENSURE(worst <= 16 * REAL_EPS);
    /* the half turn itself: the wings folded onto each other */
    hinge(x, 0, PI);
    ENSURE(fabs(fabs((double)cloth_dihedral_angle(x, x + 3, x + 6, x + 9)) - PI) <= 16 * REAL_EPS);
}

/* A random bending stencil: a hinge with random angles, lengths and placement. */
static void random_stencil(cloth_rng *rng, cloth_real *x)
{
    double r[9], shift[3];
    cloth_real h[12];
    int k;
    hinge(h, uniform(rng, -1.2, 1.2), uniform(rng, -1.2, 1.2));
    for (k = 0; k < 12; ++k) h[k] = (cloth_real)(h[k] * 0.05 + uniform(rng, -0.005, 0.005));
    random_rotation(rng, r);
    for (k = 0; k < 3; ++k) shift[k] = uniform(rng, -0.1, 0.1);
    rigid_apply(r, shift, h, 4, x);
}

#ifdef FORCES_FD_TESTS
TEST(bending_derivatives_match_finite_differences)
{
    cloth_rng rng = cloth_rng_make(31);
    int trial;
    for (trial = 0; trial < 40; ++trial) {
        cloth_real rest_x[12], x[12];
        energy_term t;
        random_stencil(&rng, rest_x);
        t = bending_term(rest_x, (cloth_real)uniform(&rng, 1e-6, 1e-4));
        if (trial % 3 == 0) t.bending.rest_angle = 0; /* flat pattern */
        random_stencil(&rng, x);
        ENSURE(gradient_error(&t, x, 1e-7) < 1e-6);
        ENSURE(hessian_error(&t, x, 1e-7) < 1e-6);
    }
}
#endif

TEST(bending_projected_hessian_and_rigid_motion)
{
    cloth_rng rng = cloth_rng_make(32);
    int trial, indefinite = 0;
    for (trial = 0; trial < 100; ++trial) {
        cloth_real rest_x[12], x[12], hp[144], he[144], g[12];
        energy_term t;
        double scale, ev[12];
        int k, positive = 0;
        random_stencil(&rng, rest_x);
        t = bending_term(rest_x, (cloth_real)1e-5);
        random_stencil(&rng, x);
        t.eval(&t, x, g, hp, CLOTH_HESSIAN_PROJECTED);
        t.eval(&t, x, NULL, he, CLOTH_HESSIAN_EXACT);
        ENSURE(is_symmetric(hp, 12) && is_symmetric(he, 12));
        scale = max_abs(hp, 144);
        jacobi_eigenvalues(hp, 12, ev);
        for (k = 0; k < 12; ++k) {
            ENSURE(ev[k] >= -1e3 * REAL_EPS * scale);
            if (ev[k] > 1e-6 * scale) ++positive;
        }
        ENSURE(positive == 1); /* Gauss-Newton: rank one */
        if (min_eigenvalue(he, 12) < -1e-6 * max_abs(he, 144)) ++indefinite;
        ENSURE(rigid_invariant(&t, x, &rng, 1e5 * REAL_EPS));
        /* forces are free of net force and torque: sum g = 0 and sum x x g = 0 */
        {
            double f[3] = { 0, 0, 0 }, tq[3] = { 0, 0, 0 }, gs = max_abs(g, 12);
            int v;
            for (v = 0; v < 4; ++v) {
                const cloth_real *p = x + 3 * v, *q = g + 3 * v;
                for (k = 0; k < 3; ++k) f[k] += q[k];
                tq[0] += (double)p[1] * q[2] - (double)p[2] * q[1];
                tq[1] += (double)p[2] * q[0] - (double)p[0] * q[2];
                tq[2] += (double)p[0] * q[1] - (double)p[1] * q[0];
            }
            for (k = 0; k < 3; ++k) {
                ENSURE(fabs(f[k]) <= 1e3 * REAL_EPS * gs);
                ENSURE(fabs(tq[k]) <= 1e3 * REAL_EPS * gs);
            }
        }
    }
    ENSURE(indefinite > 10);
}

/* The bending energy of a flat pattern wrapped isometrically onto a cylinder of radius R whose
   curvature runs along the pattern direction psi, divided by the continuum value
   B / (2 R^2) times the area that belongs to the hinges (a third of each hinge's two faces:
   boundary edges carry no hinge). */
static double cylinder_ratio_orthotropic(const cloth_mesh *pattern, double psi, double radius, double stiffness,
                                         double bend_warp, double bend_weft)
{
    cloth_topology topo;
    cloth_real *x;
    double energy = 0, area = 0, c = cos(psi), s = sin(psi);
    int32_t v, e;
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)pattern->vertex_count);
    if (!x || cloth_topology_build(&topo, pattern, NULL) != CLOTH_SUCCESS) { free(x); return -1; }
    for (v = 0; v < pattern->vertex_count; ++v) {
        double u = pattern->uv[2 * v], w = pattern->uv[2 * v + 1];
        double along = c * u + s * w, axis = -s * u + c * w;
        x[3 * v] = (cloth_real)(radius * sin(along / radius));
        x[3 * v + 1] = (cloth_real)(radius * (1 - cos(along / radius)));
        x[3 * v + 2] = (cloth_real)axis;
    }
    for (e = 0; e < topo.edge_count; ++e) {
        int32_t i0 = topo.edge_vertex[2 * e], i1 = topo.edge_vertex[2 * e + 1];
        int32_t i2 = topo.edge_opposite[2 * e], i3 = topo.edge_opposite[2 * e + 1];
        cloth_bending_rest rest;
        const cloth_real *uv = pattern->uv;
        if (i2 < 0 || i3 < 0) continue;
        if (cloth_bending_rest_make(&rest, uv + 2 * i0, uv + 2 * i1, uv + 2 * i2, uv + 2 * i3, 0) != CLOTH_SUCCESS) {
            energy = -1e30;
            break;
        }
        energy += (double)cloth_bending_energy(
            x + 3 * i0, x + 3 * i1, x + 3 * i2, x + 3 * i3, &rest,
            bend_warp > 0 ? cloth_bending_stiffness_orthotropic((cloth_real)bend_warp, (cloth_real)bend_weft, uv + 2 * i0,
                                                                uv + 2 * i1)
                          : (cloth_real)stiffness,
            NULL, NULL, CLOTH_HESSIAN_PROJECTED);
        /* l^2 / (2 (a0 + a1)) = weight, so (a0 + a1) / 3 = l^2 / (6 weight) */
        {
            double du = (double)uv[2 * i1] - uv[2 * i0], dv = (double)uv[2 * i1 + 1] - uv[2 * i0 + 1];
            area += (du * du + dv * dv) / (6 * (double)rest.weight);
        }
    }
    cloth_topology_free(&topo);
    free(x);
    return energy / (stiffness / (2 * radius * radius) * area);
}

static double cylinder_ratio(const cloth_mesh *pattern, double psi, double radius, double stiffness)
{
    return cylinder_ratio_orthotropic(pattern, psi, radius, stiffness, 0, 0);
}

/* A pattern of equilateral triangles, side `side`, nx vertices per row, ny rows, odd rows
   shifted by half a side; counter-clockwise in uv. Arrays owned by the caller's struct. */
static int equilateral_pattern(cloth_mesh *m, int32_t nx, int32_t ny, double side)
{
    int32_t i, j, t = 0;
    double h = side * sqrt(3.0) / 2;
    memset(m, 0, sizeof *m);
    m->vertex_count = nx * ny;
    m->triangle_count = 2 * (nx - 1) * (ny - 1);
    m->x = (cloth_real *)calloc((size_t)m->vertex_count * 3, sizeof(cloth_real));
    m->uv = (cloth_real *)malloc(sizeof(cloth_real) * 2 * (size_t)m->vertex_count);
    m->tri = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)m->triangle_count);
    if (!m->x || !m->uv || !m->tri) return 0;
    for (j = 0; j < ny; ++j)
        for (i = 0; i < nx; ++i) {
            m->uv[2 * (j * nx + i)] = (cloth_real)(side * (i + ((j & 1) ? 0.5 : 0)));
            m->uv[2 * (j * nx + i) + 1] = (cloth_real)(h * j);
        }
    for (j = 0; j + 1 < ny; ++j)
        for (i = 0; i + 1 < nx; ++i) {
            int32_t a = j * nx + i, b = a + 1, c = a + nx, d = c + 1; /* c, d on the row above */
            int32_t *q = m->tri + 3 * t;
            if ((j & 1) == 0) { /* row above shifted right: triangles (a, b, c) and (b, d, c) */
                q[0] = a; q[1] = b; q[2] = c; q[3] = b; q[4] = d; q[5] = c;
            } else { /* row above shifted left: (a, d, c) and (a, b, d) */
                q[0] = a; q[1] = d; q[2] = c; q[3] = a; q[4] = b; q[5] = d;
            }
            t += 2;
        }
    return 1;
}

static void free_pattern(cloth_mesh *m)
{
    free(m->x);
    free(m->uv);
    free(m->tri);
}

TEST(bending_cylinder_calibration)
{
    /* B = 1e-5 N m, R = 0.25 m, mesh spacing 5 mm: kappa h ~ 0.02 */
    const double stiffness = 1e-5, radius = 0.25, spacing = 0.005;
    cloth_mesh tri_pattern, grid, jack;
    double r, psi;
    int k;
    ENSURE(equilateral_pattern(&tri_pattern, 81, 93, spacing));
    /* equilateral triangles: B / (2 R^2) per unit area in every direction */
    for (k = 0; k < 4; ++k) {
        psi = k * PI / 7;
        r = cylinder_ratio(&tri_pattern, psi, radius, stiffness);
        printf("    cylinder, equilateral triangles, bending at %5.1f deg to the rows: energy / (B/(2R^2) area) = %.4f\n",
               psi * 180 / PI, r);
        ENSURE_NEAR(r, 1, 0.02);
    }
    free_pattern(&tri_pattern);
    /* right-triangle grids (cloth_mesh_grid's layout): with every diagonal along -45 degrees in uv,
       1 - sin 2psi + sin^2 2psi times the continuum value; with alternating diagonals,
       1 + sin^2(2psi) / 2 (both from the dihedral angles of the piecewise-linear interpolant of
       the cylinder: horizontal edges see kappa h sin psi (sin psi - cos psi) on the regular grid,
       kappa h sin^2 psi on the alternating one) */
    ENSURE(cloth_mesh_grid(&grid, 81, 81, (cloth_real)(80 * spacing), (cloth_real)(80 * spacing), CLOTH_GRID_DIAGONAL_REGULAR, NULL) ==
           CLOTH_SUCCESS);
    ENSURE(cloth_mesh_grid(&jack, 81, 81, (cloth_real)(80 * spacing), (cloth_real)(80 * spacing), CLOTH_GRID_DIAGONAL_ALTERNATING,
                           NULL) == CLOTH_SUCCESS);
    for (k = 0; k < 6; ++k) {
        const double angles[6] = { 0, 90, 45, -45, 30, 15 };
        double predicted, predicted_jack, rj;
        psi = angles[k] * PI / 180;
        predicted = 1 - sin(2 * psi) + sin(2 * psi) * sin(2 * psi);
        predicted_jack = 1 + sin(2 * psi) * sin(2 * psi) / 2;
        r = cylinder_ratio(&grid, psi, radius, stiffness);
        rj = cylinder_ratio(&jack, psi, radius, stiffness);
        printf("    cylinder, right-triangle grid at %5.1f deg to u: regular %.4f (predicted %.4f), alternating %.4f (predicted %.4f)\n",
               angles[k], r, predicted, rj, predicted_jack);
        ENSURE_NEAR(r, predicted, 0.02 * predicted);
        ENSURE_NEAR(rj, predicted_jack, 0.02 * predicted_jack);
    }
    /* orthotropic bending on the grid: bent along the warp (u) it stores bend_warp / (2 R^2),
       along the weft bend_weft / (2 R^2) */
    r = cylinder_ratio_orthotropic(&grid, 0, radius, 3e-5, 3e-5, 1e-5);
    ENSURE_NEAR(r, 1, 0.02);
    r = cylinder_ratio_orthotropic(&grid, PI / 2, radius, 1e-5, 3e-5, 1e-5);
    ENSURE_NEAR(r, 1, 0.02);
    cloth_mesh_free(&grid);
    cloth_mesh_free(&jack);
}

TEST(bending_orthotropic_stiffness)
{
    cloth_real a[2] = { (cloth_real)0.1, (cloth_real)0.2 }, b[2], c = (cloth_real)(1 / sqrt(2.0));
    /* an edge along the weft (v) folds the warp yarns */
    b[0] = a[0]; b[1] = (cloth_real)0.5;
    ENSURE_NEAR(cloth_bending_stiffness_orthotropic(3, 1, a, b), 3, 1e2 * REAL_EPS);
    b[0] = (cloth_real)-0.3; b[1] = a[1];
    ENSURE_NEAR(cloth_bending_stiffness_orthotropic(3, 1, a, b), 1, 1e2 * REAL_EPS);
    b[0] = a[0] + c; b[1] = a[1] - c;
    ENSURE_NEAR(cloth_bending_stiffness_orthotropic(3, 1, a, b), 2, 1e2 * REAL_EPS);
    ENSURE_NEAR(cloth_bending_stiffness_orthotropic(3, 1, a, a), 2, 1e2 * REAL_EPS);
}

/* ---- aerodynamics ------------------------------------------------------------------ */

/* ---- quadratic bending ------------------------------------------------------------- */

/* The stencils of a pattern (count-then-fill) with the given pins (NULL: none), in arrays the
   caller frees. */
static int quadratic_stencils_pinned(const cloth_mesh *m, double warp, double weft, const int32_t *pinned, int32_t **start,
                                     int32_t **vertex, cloth_real **weight, cloth_real **area)
{
    cloth_topology topo;
    int32_t count = 0;
    int ok;
    *start = NULL; *vertex = NULL; *weight = NULL; *area = NULL;
    if (cloth_topology_build(&topo, m, NULL) != CLOTH_SUCCESS) return 0;
    ok = cloth_quadratic_bending_stencils(m, &topo, (cloth_real)warp, (cloth_real)weft, NULL, NULL, NULL, NULL, NULL, 0, &count) == CLOTH_SUCCESS;
    if (ok) {
        *start = (int32_t *)malloc(sizeof(int32_t) * ((size_t)m->vertex_count + 1));
        *vertex = (int32_t *)malloc(sizeof(int32_t) * (size_t)count);
        *weight = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)count);
        *area = (cloth_real *)malloc(sizeof(cloth_real) * (size_t)m->vertex_count);
        ok = *start && *vertex && *weight && *area &&
             cloth_quadratic_bending_stencils(m, &topo, (cloth_real)warp, (cloth_real)weft, pinned, *start, *vertex, *weight, *area, count,
                                              &count) == CLOTH_SUCCESS;
        ok = ok && cloth_quadratic_bending_stencils(m, &topo, (cloth_real)warp, (cloth_real)weft, pinned, *start, *vertex, *weight, *area,
                                                    count - 1, &count) == CLOTH_ERROR_INVALID_ARGUMENT;
    }
    cloth_topology_free(&topo);
    return ok;
}

static int quadratic_stencils(const cloth_mesh *m, double warp, double weft, int32_t **start, int32_t **vertex, cloth_real **weight,
                              cloth_real **area)
{
    return quadratic_stencils_pinned(m, warp, weft, NULL, start, vertex, weight, area);
}

static void free_stencils(int32_t *start, int32_t *vertex, cloth_real *weight, cloth_real *area)
{
    free(start); free(vertex); free(weight); free(area);
}

#ifdef FORCES_FD_TESTS
/* The checks of quadratic_bending_derivatives_rest_and_rigid_motion on the 5 x 5 union-jack
   pattern 0.1 m across with the given pins (NULL: none); the areas must sum to free_area. */
static void quadratic_derivative_checks(const int32_t *pinned, double free_area, const char *label)
{
    cloth_mesh m;
    int32_t *start, *vertex, v, i, j, n;
    cloth_real *weight, *area, *x, *y, g[3 * 32], gp[3 * 32], gm[3 * 32], gy[3 * 32], rg[3 * 32], h[96 * 96];
    cloth_rng rng;
    double r[9], shift[3] = { 0.3, -1.1, 0.7 }, worst_g = 0, worst_h = 0, worst_rest = 0, worst_rigid = 0, total_area = 0;
    int trial;
    ENSURE(cloth_mesh_grid(&m, 5, 5, (cloth_real)0.1, (cloth_real)0.1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    ENSURE(quadratic_stencils_pinned(&m, 2e-5, 1e-5, pinned, &start, &vertex, &weight, &area));
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)m.vertex_count);
    y = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)m.vertex_count);
    ENSURE(x && y);
    rng = cloth_rng_make(7);
    for (v = 0; v < m.vertex_count; ++v) total_area += area[v];
    ENSURE_NEAR(total_area, free_area, 1e-12);
    for (trial = 0; trial < 4; ++trial) {
        random_rotation(&rng, r);
        for (v = 0; v < m.vertex_count; ++v) { x[3 * v] = m.uv[2 * v]; x[3 * v + 1] = m.uv[2 * v + 1]; x[3 * v + 2] = 0; }
        rigid_apply(r, trial ? shift : NULL, x, m.vertex_count, y);
        for (v = 0; v < m.vertex_count; ++v) {
            n = start[v + 1] - start[v];
            ENSURE(n <= 32);
            if (fabs((double)cloth_quadratic_bending_energy(y, vertex + start[v], weight + 3 * start[v], n, g, NULL)) > worst_rest)
                worst_rest = fabs((double)cloth_quadratic_bending_energy(y, vertex + start[v], weight + 3 * start[v], n, NULL, NULL));
            if (max_abs(g, 3 * n) > worst_rest) worst_rest = max_abs(g, 3 * n);
        }
    }
    printf("    quadratic bending%s on a flat pattern moved rigidly: largest |E| or |gradient| %.2e\n", label, worst_rest);
    ENSURE(worst_rest <= 1e-14); /* roundoff: weights of order 1 sqrt(N m) / m on positions of 0.1 m */
    for (trial = 0; trial < 3; ++trial) {
        for (v = 0; v < m.vertex_count; ++v) {
            x[3 * v] = (cloth_real)(m.uv[2 * v] + uniform(&rng, -0.01, 0.01));
            x[3 * v + 1] = (cloth_real)(m.uv[2 * v + 1] + uniform(&rng, -0.01, 0.01));
            x[3 * v + 2] = (cloth_real)uniform(&rng, -0.02, 0.02);
        }
        random_rotation(&rng, r);
        rigid_apply(r, shift, x, m.vertex_count, y);
        for (v = 0; v < m.vertex_count; ++v) {
            const int32_t *sv = vertex + start[v];
            const cloth_real *sw = weight + 3 * start[v];
            double e, ey, scale, step = 1e-6;
            n = start[v + 1] - start[v];
            e = (double)cloth_quadratic_bending_energy(x, sv, sw, n, g, h);
            ENSURE(is_symmetric(h, 3 * n));
            for (i = 0; i < 3 * n; ++i) {
                cloth_real keep = x[3 * sv[i / 3] + i % 3];
                double ep, em;
                x[3 * sv[i / 3] + i % 3] = keep + (cloth_real)step;
                ep = (double)cloth_quadratic_bending_energy(x, sv, sw, n, gp, NULL);
                x[3 * sv[i / 3] + i % 3] = keep - (cloth_real)step;
                em = (double)cloth_quadratic_bending_energy(x, sv, sw, n, gm, NULL);
                x[3 * sv[i / 3] + i % 3] = keep;
                scale = max_abs(g, 3 * n);
                if (scale > 0 && fabs((ep - em) / (2 * step) - g[i]) / scale > worst_g) worst_g = fabs((ep - em) / (2 * step) - g[i]) / scale;
                scale = max_abs(h, 9 * n * n);
                for (j = 0; j < 3 * n; ++j)
                    if (scale > 0 && fabs(((double)gp[j] - gm[j]) / (2 * step) - h[j * 3 * n + i]) / scale > worst_h)
                        worst_h = fabs(((double)gp[j] - gm[j]) / (2 * step) - h[j * 3 * n + i]) / scale;
            }
            {
                double q = 0; /* x^T H x for a random direction */
                for (i = 0; i < 3 * n; ++i) gp[i] = (cloth_real)uniform(&rng, -1, 1);
                for (i = 0; i < 3 * n; ++i)
                    for (j = 0; j < 3 * n; ++j) q += (double)gp[i] * h[i * 3 * n + j] * gp[j];
                ENSURE(q >= -1e-12 * max_abs(h, 9 * n * n));
            }
            ey = (double)cloth_quadratic_bending_energy(y, sv, sw, n, gy, NULL);
            rigid_apply(r, NULL, g, n, rg);
            scale = max_abs(g, 3 * n);
            if (fabs(e - ey) / (e > 0 ? e : 1) > worst_rigid) worst_rigid = fabs(e - ey) / (e > 0 ? e : 1);
            for (i = 0; i < 3 * n; ++i)
                if (scale > 0 && fabs((double)rg[i] - gy[i]) / scale > worst_rigid) worst_rigid = fabs((double)rg[i] - gy[i]) / scale;
        }
    }
    printf("    quadratic bending%s, random deformations: gradient vs central differences %.2e, Hessian %.2e, rigid motion %.2e "
           "(relative)\n", label, worst_g, worst_h, worst_rigid);
    ENSURE(worst_g <= 1e-6);
    ENSURE(worst_h <= 1e-6);
    ENSURE(worst_rigid <= 1e-9);
    /* bad input */
    {
        cloth_topology topo;
        int32_t count;
        cloth_real *uv = m.uv;
        ENSURE(cloth_topology_build(&topo, &m, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_quadratic_bending_stencils(&m, &topo, -1, 1, NULL, NULL, NULL, NULL, NULL, 0, &count) == CLOTH_ERROR_INVALID_ARGUMENT);
        m.uv = NULL;
        ENSURE(cloth_quadratic_bending_stencils(&m, &topo, 1, 1, NULL, NULL, NULL, NULL, NULL, 0, &count) == CLOTH_ERROR_INVALID_ARGUMENT);
        m.uv = uv;
        cloth_topology_free(&topo);
    }
    free(x);
    free(y);
    free_stencils(start, vertex, weight, area);
    cloth_mesh_free(&m);
}


TEST(quadratic_bending_derivatives_rest_and_rigid_motion)
{
    /* a 5 x 5 union-jack pattern 0.1 m across, bend_warp 2e-5, bend_weft 1e-5 N m: every vertex's
       stencil (interior, edge and corner) is zero with zero gradient on the flat pattern and on
       any rigid motion of it; on random deformations its gradient matches central differences
       of its energy and its Hessian central differences of its gradient (it is constant), its
       Hessian is symmetric and x^T H x >= 0, and energy and gradient are invariant under rigid
       motions */
    quadratic_derivative_checks(NULL, 0.01, "");
}

TEST(quadratic_bending_with_a_clamp_derivatives_rest_and_rigid_motion)
{
    /* the same checks with the first two columns pinned (a clamp: the 8 faces between them are
       pinned and the free region starts at u = 0.025), a pinned vertex inside and a pinned edge
       on the far side (neither forms a pinned face, so neither clamps): the areas sum to the
       free region's, 0.1 x 0.075 m; the stencils of the first column (all its faces pinned) are
       zero and so are their areas */
    int32_t pinned[25] = { 0 }, *start, *vertex, j, a;
    cloth_real *weight, *area;
    cloth_mesh m;
    double worst = 0;
    for (j = 0; j < 5; ++j) pinned[5 * j] = pinned[5 * j + 1] = 1;
    pinned[5 * 2 + 3] = 1;
    pinned[5 * 3 + 4] = pinned[5 * 4 + 4] = 1;
    quadratic_derivative_checks(pinned, 0.1 * 0.075, " with a clamp");
    ENSURE(cloth_mesh_grid(&m, 5, 5, (cloth_real)0.1, (cloth_real)0.1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    ENSURE(quadratic_stencils_pinned(&m, 2e-5, 1e-5, pinned, &start, &vertex, &weight, &area));
    for (j = 0; j < 5; ++j) {
        if (fabs((double)area[5 * j]) > worst) worst = fabs((double)area[5 * j]);
        for (a = 3 * start[5 * j]; a < 3 * start[5 * j + 1]; ++a)
            if (fabs((double)weight[a]) > worst) worst = fabs((double)weight[a]);
    }
    free_stencils(start, vertex, weight, area);
    cloth_mesh_free(&m);
    ENSURE(worst == 0);
}

#endif

/* The quadratic energy of a pattern wrapped on a cylinder (as cylinder_ratio_orthotropic), over
   the interior vertices, divided by B / (2 R^2) times their areas; *edge_ratio the same over
   the boundary vertices that are not corners. */
static double quadratic_cylinder_ratio(const cloth_mesh *pattern, double psi, double radius, double warp, double weft, double stiffness,
                                       double *edge_ratio)
{
    int32_t *start, *vertex, v, e;
    cloth_real *weight, *area, *x;
    cloth_topology topo;
    char *boundary;
    double energy = 0, a = 0, edge_energy = 0, edge_area = 0, c = cos(psi), s = sin(psi);
    if (!quadratic_stencils(pattern, warp, weft, &start, &vertex, &weight, &area)) return -1;
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)pattern->vertex_count);
    boundary = (char *)calloc((size_t)pattern->vertex_count, 1);
    if (!x || !boundary || cloth_topology_build(&topo, pattern, NULL) != CLOTH_SUCCESS) return -1;
    for (e = 0; e < topo.boundary_edge_count; ++e) {
        boundary[topo.edge_vertex[2 * topo.boundary_edge[e]]]++;
        boundary[topo.edge_vertex[2 * topo.boundary_edge[e] + 1]]++;
    }
    for (v = 0; v < pattern->vertex_count; ++v) {
        double u = pattern->uv[2 * v], w = pattern->uv[2 * v + 1], along = c * u + s * w, axis = -s * u + c * w;
        x[3 * v] = (cloth_real)(radius * sin(along / radius));
        x[3 * v + 1] = (cloth_real)(radius * (1 - cos(along / radius)));
        x[3 * v + 2] = (cloth_real)axis;
    }
    for (v = 0; v < pattern->vertex_count; ++v) {
        double ev = (double)cloth_quadratic_bending_energy(x, vertex + start[v], weight + 3 * start[v], start[v + 1] - start[v], NULL, NULL);
        if (!boundary[v]) { energy += ev; a += area[v]; }
        else { edge_energy += ev; edge_area += area[v]; }
    }
    cloth_topology_free(&topo);
    free(x);
    free(boundary);
    free_stencils(start, vertex, weight, area);
    *edge_ratio = edge_energy / (stiffness / (2 * radius * radius) * edge_area);
    return energy / (stiffness / (2 * radius * radius) * a);
}

TEST(quadratic_bending_cylinder_calibration)
{
    /* B = 1e-5 N m, R = 0.25 m, spacing 5 mm, as bending_cylinder_calibration: at the interior
       vertices the energy per area is B / (2 R^2) in every direction on equilateral triangles and
       on the regular grid, and along the axes on the alternating grid; boundary vertices are
       printed (they measure only the curvature along their edge) */
    const double stiffness = 1e-5, radius = 0.25, spacing = 0.005;
    const double angles[6] = { 0, 90, 45, -45, 30, 15 };
    cloth_mesh tri_pattern, grid, jack;
    double r, edge;
    int k;
    ENSURE(equilateral_pattern(&tri_pattern, 81, 93, spacing));
    ENSURE(cloth_mesh_grid(&grid, 81, 81, (cloth_real)(80 * spacing), (cloth_real)(80 * spacing), CLOTH_GRID_DIAGONAL_REGULAR, NULL) ==
           CLOTH_SUCCESS);
    ENSURE(cloth_mesh_grid(&jack, 81, 81, (cloth_real)(80 * spacing), (cloth_real)(80 * spacing), CLOTH_GRID_DIAGONAL_ALTERNATING,
                           NULL) == CLOTH_SUCCESS);
    for (k = 0; k < 6; ++k) {
        double psi = angles[k] * PI / 180, rt, et, rg, eg, rj, ej;
        rt = quadratic_cylinder_ratio(&tri_pattern, psi, radius, stiffness, stiffness, stiffness, &et);
        rg = quadratic_cylinder_ratio(&grid, psi, radius, stiffness, stiffness, stiffness, &eg);
        rj = quadratic_cylinder_ratio(&jack, psi, radius, stiffness, stiffness, stiffness, &ej);
        printf("    quadratic, cylinder at %5.1f deg to u: interior energy / (B/(2R^2) area): equilateral %.4f, regular grid %.4f, "
               "alternating %.4f (boundary vertices: %.3f %.3f %.3f)\n", angles[k], rt, rg, rj, et, eg, ej);
        ENSURE_NEAR(rt, 1, 0.02);
        ENSURE_NEAR(rg, 1, 0.02);
        /* the alternating grid measures twist unevenly (its valence-4 vertices see no diagonal):
           exact along the axes, 1 + sin^2(2 psi) / 2 off them, like the dihedral energy there */
        ENSURE_NEAR(rj, 1 + sin(2 * psi) * sin(2 * psi) / 2, 0.02);
    }
    /* orthotropic: along the warp bend_warp / (2 R^2), along the weft bend_weft / (2 R^2) */
    r = quadratic_cylinder_ratio(&jack, 0, radius, 3e-5, 1e-5, 3e-5, &edge);
    printf("    quadratic, orthotropic (3e-5, 1e-5) on the alternating grid: along the warp %.4f", r);
    ENSURE_NEAR(r, 1, 0.02);
    r = quadratic_cylinder_ratio(&jack, PI / 2, radius, 3e-5, 1e-5, 1e-5, &edge);
    printf(", along the weft %.4f\n", r);
    ENSURE_NEAR(r, 1, 0.02);
    free_pattern(&tri_pattern);
    cloth_mesh_free(&grid);
    cloth_mesh_free(&jack);
}


/* A strip pattern of nx x ny vertices, spacing h, whose columns i <= clamp are pinned (pinned
   NULL: the same positions without pins), flat for u <= u_c = clamp h and wrapped beyond on a
   cylinder of radius R tangent to it there (the curvature along u); the energy of the column
   i = clamp (the clamp line) and of the free columns i > clamp, interior rows only, each divided
   by B / (2 R^2) times their areas. */
static int quadratic_clamp_ratio(cloth_grid_diagonal diagonal, int use_pins, double *line_ratio, double *free_ratio)
{
    const int32_t nx = 81, ny = 21, clamp = 9;
    const double h = 0.005, radius = 0.25, stiffness = 1e-5;
    int32_t *start, *vertex, *pinned, v, i, j;
    cloth_real *weight, *area, *x;
    cloth_mesh m;
    double e[2] = { 0, 0 }, a[2] = { 0, 0 };
    if (cloth_mesh_grid(&m, nx, ny, (cloth_real)((nx - 1) * h), (cloth_real)((ny - 1) * h), diagonal, NULL) != CLOTH_SUCCESS) return 0;
    pinned = (int32_t *)calloc((size_t)m.vertex_count, sizeof(int32_t));
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)m.vertex_count);
    if (!pinned || !x) return 0;
    for (j = 0; j < ny; ++j)
        for (i = 0; i <= clamp; ++i) pinned[j * nx + i] = 1;
    if (!quadratic_stencils_pinned(&m, stiffness, stiffness, use_pins ? pinned : NULL, &start, &vertex, &weight, &area)) return 0;
    for (v = 0; v < m.vertex_count; ++v) {
        double along = m.uv[2 * v] - clamp * h;
        x[3 * v] = (cloth_real)(along <= 0 ? along : radius * sin(along / radius));
        x[3 * v + 1] = (cloth_real)(along <= 0 ? 0 : radius * (1 - cos(along / radius)));
        x[3 * v + 2] = m.uv[2 * v + 1];
    }
    for (j = 1; j < ny - 1; ++j)
        for (i = clamp; i < nx - 1; ++i) {
            v = j * nx + i;
            e[i > clamp] += (double)cloth_quadratic_bending_energy(x, vertex + start[v], weight + 3 * start[v], start[v + 1] - start[v],
                                                                   NULL, NULL);
            a[i > clamp] += area[v];
        }
    *line_ratio = e[0] / (stiffness / (2 * radius * radius) * a[0]);
    *free_ratio = e[1] / (stiffness / (2 * radius * radius) * a[1]);
    free_stencils(start, vertex, weight, area);
    free(pinned);
    free(x);
    cloth_mesh_free(&m);
    return 1;
}

TEST(quadratic_bending_clamp_calibration)
{
    /* a strip clamped flat (its first 10 columns pinned) and bent beyond the clamp line on a
       cylinder of radius 0.25 m tangent to the clamp (spacing 5 mm, B = 1e-5 N m): with the
       pins the clamp line's vertices measure the curvature on their free half cells, B / (2 R^2)
       per area like every free vertex, on the alternating and on the regular grid. Without the
       pins the same positions put a full interior cell on the clamp line, which sees half the
       curvature across it (printed: the clamp treatment's reason) */
    const cloth_grid_diagonal diagonals[2] = { CLOTH_GRID_DIAGONAL_ALTERNATING, CLOTH_GRID_DIAGONAL_REGULAR };
    const char *names[2] = { "alternating", "regular" };
    int k;
    for (k = 0; k < 2; ++k) {
        double line, free_part, line_unpinned, free_unpinned;
        ENSURE(quadratic_clamp_ratio(diagonals[k], 1, &line, &free_part));
        ENSURE(quadratic_clamp_ratio(diagonals[k], 0, &line_unpinned, &free_unpinned));
        printf("    quadratic, clamped strip on a cylinder (%s grid): energy / (B/(2R^2) area) on the clamp line %.4f, free vertices "
               "%.4f (without the pins: clamp line %.4f)\n", names[k], line, free_part, line_unpinned);
        ENSURE_NEAR(line, 1, 0.02);
        ENSURE_NEAR(free_part, 1, 0.02);
    }
}

TEST(aerodynamic_force)
{
    cloth_real x[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 }; /* area 1/2, normal +z */
    cloth_real v[9], wind[3], f[9], f2[9], jac[81];
    cloth_aerodynamics air = cloth_default_aerodynamics();
    int k;
    double a = 0.5;
    ENSURE_NEAR(air.air_density, 1.225, 1e-6);
    /* the face moves with the wind: no force */
    for (k = 0; k < 9; ++k) v[k] = (cloth_real)(k % 3 == 0 ? 3 : k % 3 == 2 ? -1 : 0.5);
    wind[0] = 3; wind[1] = (cloth_real)0.5; wind[2] = -1;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, jac);
    ENSURE(max_abs(f, 9) == 0);
    /* wind in the plane of a resting face: no pressure force */
    memset(v, 0, sizeof v);
    wind[0] = 4; wind[1] = -3; wind[2] = 0;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, NULL);
    ENSURE(max_abs(f, 9) == 0);
    /* face-on wind: 1/2 rho C A u^2 along the wind, a third to each vertex */
    wind[0] = 0; wind[1] = 0; wind[2] = 5;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, NULL);
    for (k = 0; k < 3; ++k) {
        ENSURE(f[3 * k] == 0 && f[3 * k + 1] == 0);
        ENSURE_NEAR(f[3 * k + 2], 0.5 * 1.225 * 1.28 * a * 25 / 3, 1e3 * REAL_EPS);
    }
    /* quadratic in the relative speed, whatever side the wind comes from */
    wind[0] = 1; wind[1] = 2; wind[2] = -3;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, NULL);
    for (k = 0; k < 3; ++k) wind[k] *= 2;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f2, NULL);
    ENSURE(f[2] < 0); /* pushed along the wind's normal component */
    for (k = 0; k < 9; ++k) ENSURE_NEAR(f2[k], 4 * f[k], 1e3 * REAL_EPS * max_abs(f2, 9));
    /* an inclined face gets lift: force across the wind */
    x[5] = (cloth_real)0.5; /* tilt vertex 1 up */
    wind[0] = 10; wind[1] = 0; wind[2] = 0;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, NULL);
    ENSURE(f[0] > 0 && fabs((double)f[2]) > 0.1 * f[0]);
    /* skin friction along the face when asked for */
    x[5] = 0;
    wind[0] = 4; wind[1] = -3; wind[2] = 0;
    air.tangential_coefficient = (cloth_real)0.02;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, NULL);
    ENSURE_NEAR(f[0], 0.5 * 1.225 * 0.02 * a * 5 * 4 / 3, 1e3 * REAL_EPS);
    ENSURE_NEAR(f[1], -0.5 * 1.225 * 0.02 * a * 5 * 3 / 3, 1e3 * REAL_EPS);
    /* a degenerate face: nothing */
    x[3] = 0; x[4] = 1;
    cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, f, jac);
    ENSURE(max_abs(f, 9) == 0 && max_abs(jac, 81) == 0);
}

TEST(aerodynamic_velocity_jacobian)
{
    cloth_rng rng = cloth_rng_make(41);
    cloth_aerodynamics air = cloth_default_aerodynamics();
    int trial;
    air.tangential_coefficient = (cloth_real)0.05;
    for (trial = 0; trial < 30; ++trial) {
        cloth_real x[9], v[9], wind[3], jac[81], neg[81];
        int i;
        random_points(&rng, x, 9, -1, 1);
        random_points(&rng, v, 9, -2, 2);
        random_points(&rng, wind, 3, -8, 8);
        cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, NULL, jac);
        ENSURE(is_symmetric(jac, 9));
        for (i = 0; i < 81; ++i) neg[i] = -jac[i];
        ENSURE(min_eigenvalue(neg, 9) >= -1e3 * REAL_EPS * max_abs(jac, 81)); /* -df/dv is PSD */
#ifdef FORCES_FD_TESTS
        {
            cloth_real fp[9], fm[9];
            double err = 0, step = 1e-6;
            int j;
            for (j = 0; j < 9; ++j) {
                cloth_real keep = v[j];
                v[j] = (cloth_real)(keep + step);
                cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, fp, NULL);
                v[j] = (cloth_real)(keep - step);
                cloth_aerodynamic_force(x, x + 3, x + 6, v, v + 3, v + 6, wind, &air, fm, NULL);
                v[j] = keep;
                for (i = 0; i < 9; ++i) {
                    double d = fabs(((double)fp[i] - fm[i]) / (2 * step) - jac[9 * i + j]);
                    if (d > err) err = d;
                }
            }
            ENSURE(err <= 1e-6 * max_abs(jac, 81));
        }
#endif
    }
}

/* ---- gusts ------------------------------------------------------------------------- */

TEST(gusts_are_deterministic_with_requested_statistics)
{
    cloth_gust_def def = cloth_default_gust_def();
    cloth_gust a, b, c;
    const int steps = 200000;
    const double dt = 0.05;
    double sum[3] = { 0, 0, 0 }, sq[3] = { 0, 0, 0 }, lag = 0, lag_norm = 0;
    double prev[40];
    int i, k, same = 1, differs = 0;
    def.mean[0] = 6; def.mean[1] = 0; def.mean[2] = (cloth_real)-1;
    def.deviation[0] = 2; def.deviation[1] = (cloth_real)0.5; def.deviation[2] = 1;
    def.correlation_time = 1;
    def.seed = 1234;
    ENSURE(cloth_gust_init(&a, &def) == CLOTH_SUCCESS);
    ENSURE(cloth_gust_init(&b, &def) == CLOTH_SUCCESS);
    def.seed = 1235;
    ENSURE(cloth_gust_init(&c, &def) == CLOTH_SUCCESS);
    for (i = 0; i < steps; ++i) {
        cloth_real wa[3], wb[3], wc[3];
        ENSURE(cloth_gust_advance(&a, (cloth_real)dt) == CLOTH_SUCCESS);
        cloth_gust_advance(&b, (cloth_real)dt);
        cloth_gust_advance(&c, (cloth_real)dt);
        cloth_gust_wind(&a, wa);
        cloth_gust_wind(&b, wb);
        cloth_gust_wind(&c, wc);
        if (memcmp(wa, wb, sizeof wa) != 0) same = 0;
        if (memcmp(wa, wc, sizeof wa) != 0) ++differs;
        for (k = 0; k < 3; ++k) {
            sum[k] += wa[k];
            sq[k] += ((double)wa[k] - def.mean[k]) * ((double)wa[k] - def.mean[k]);
        }
        /* autocorrelation of the x gust at a lag of one correlation time (20 steps) */
        if (i >= 20) {
            lag += ((double)wa[0] - 6) * prev[i % 20];
            lag_norm += ((double)wa[0] - 6) * ((double)wa[0] - 6);
        }
        prev[i % 20] = (double)wa[0] - 6;
    }
    ENSURE(same);
    ENSURE(differs > steps - 10);
    ENSURE_NEAR(a.time, steps * dt, 1e-6 * steps * dt + 1e3 * REAL_EPS * steps * dt);
    /* with 10,000 correlation times, the standard error of the mean is about
       deviation * sqrt(2 tau / T) = 1.4% of the deviation */
    for (k = 0; k < 3; ++k) {
        ENSURE_NEAR(sum[k] / steps, def.mean[k], 0.06 * def.deviation[k]);
        ENSURE_NEAR(sqrt(sq[k] / steps), def.deviation[k], 0.05 * def.deviation[k]);
    }
    ENSURE_NEAR(lag / lag_norm, exp(-1.0), 0.04);
    /* a zero step changes nothing; a copy of the state forks the same future */
    c = a;
    ENSURE(cloth_gust_advance(&c, 0) == CLOTH_SUCCESS);
    ENSURE(memcmp(c.gust, a.gust, sizeof a.gust) == 0);
    cloth_gust_advance(&a, (cloth_real)0.3);
    cloth_gust_advance(&c, (cloth_real)0.3);
    ENSURE(memcmp(c.gust, a.gust, sizeof a.gust) == 0);
}

TEST(gusts_reject_bad_definitions)
{
    cloth_gust_def def = cloth_default_gust_def();
    cloth_gust g;
    cloth_real w[3];
    ENSURE(cloth_gust_init(&g, &def) == CLOTH_SUCCESS);
    cloth_gust_wind(&g, w);
    ENSURE(w[0] == 0 && w[1] == 0 && w[2] == 0); /* the default is a calm */
    ENSURE(cloth_gust_advance(&g, -1) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_gust_advance(&g, (cloth_real)strtod("inf", NULL)) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.correlation_time = 0;
    ENSURE(cloth_gust_init(&g, &def) == CLOTH_ERROR_INVALID_ARGUMENT);
    def = cloth_default_gust_def();
    def.deviation[1] = -1;
    ENSURE(cloth_gust_init(&g, &def) == CLOTH_ERROR_INVALID_ARGUMENT);
    def = cloth_default_gust_def();
    def.mean[2] = (cloth_real)strtod("nan", NULL);
    ENSURE(cloth_gust_init(&g, &def) == CLOTH_ERROR_NOT_FINITE);
}

/* ---- damping ----------------------------------------------------------------------- */

TEST(relative_damping_and_air_drag)
{
    cloth_rng rng = cloth_rng_make(51);
    int n;
    for (n = 2; n <= 4; ++n) {
        cloth_real v[12], f[12], jac[144], neg[144], jv[12];
        const cloth_real *vp[4] = { NULL, NULL, NULL, NULL };
        double momentum[3] = { 0, 0, 0 }, power = 0, dissipation = 0;
        int a, b, k;
        random_points(&rng, v, 3 * n, -1, 1);
        for (a = 0; a < n; ++a) vp[a] = v + 3 * a;
        for (a = 0; a < 12; ++a) f[a] = 99;
        cloth_relative_damping_force(vp[0], vp[1], vp[2], vp[3], (cloth_real)0.7, f, jac);
        for (a = 3 * n; a < 12; ++a) ENSURE(f[a] == 99); /* k = n vertices, no more */
        for (a = 0; a < 3 * n; ++a) momentum[a % 3] += f[a];
        for (k = 0; k < 3; ++k) ENSURE(fabs(momentum[k]) <= 1e2 * REAL_EPS);
        /* power v . f = -c sum_{a<b} |v_a - v_b|^2 */
        for (a = 0; a < 3 * n; ++a) power += (double)v[a] * f[a];
        for (a = 0; a < n; ++a)
            for (b = a + 1; b < n; ++b)
                for (k = 0; k < 3; ++k) dissipation += ((double)v[3 * a + k] - v[3 * b + k]) * ((double)v[3 * a + k] - v[3 * b + k]);
        ENSURE_NEAR(power, -0.7 * dissipation, 1e3 * REAL_EPS);
        /* the force is linear: f = (df/dv) v; -df/dv is PSD with rigid translation in its null space */
        for (a = 0; a < 3 * n; ++a) {
            double s = 0;
            for (b = 0; b < 3 * n; ++b) s += (double)jac[3 * n * a + b] * v[b];
            jv[a] = (cloth_real)s;
            ENSURE_NEAR(jv[a], f[a], 1e2 * REAL_EPS);
        }
        for (a = 0; a < 9 * n * n; ++a) neg[a] = -jac[a];
        ENSURE(is_symmetric(jac, 3 * n));
        ENSURE(min_eigenvalue(neg, 3 * n) >= -1e2 * REAL_EPS);
        ENSURE_NEAR(min_eigenvalue(neg, 3 * n), 0, 1e2 * REAL_EPS);
        /* a translating element is not damped */
        for (a = 0; a < n; ++a) vp[a] = v;
        cloth_relative_damping_force(vp[0], vp[1], vp[2], vp[3], (cloth_real)0.7, f, NULL);
        ENSURE(max_abs(f, 3 * n) == 0);
    }
    {
        cloth_real v[3] = { 1, -2, (cloth_real)0.5 }, f[3], jac[9];
        cloth_air_drag_force(v, (cloth_real)0.1, f, jac);
        ENSURE_NEAR(f[1], 0.2, 1e2 * REAL_EPS);
        ENSURE_NEAR(jac[0], -0.1, 1e2 * REAL_EPS);
        ENSURE(jac[1] == 0 && jac[4] == jac[0] && jac[8] == jac[0]);
    }
}

const test_case forces_tests[] = {
#ifdef FORCES_FD_TESTS
    { "spring_derivatives_match_finite_differences", spring_derivatives_match_finite_differences },
#endif
    { "spring_projected_hessian_is_psd", spring_projected_hessian_is_psd },
    { "spring_rest_rigid_motion_and_seam", spring_rest_rigid_motion_and_seam },
    { "strain_limit_engages_beyond_its_limit_only", strain_limit_engages_beyond_its_limit_only },
    { "attachment_and_gravity", attachment_and_gravity },
    { "grid_springs_are_provots", grid_springs_are_provots },
    { "topology_springs_edges_and_hinges", topology_springs_edges_and_hinges },
    { "membrane_rest_data", membrane_rest_data },
#ifdef FORCES_FD_TESTS
    { "membrane_derivatives_match_finite_differences", membrane_derivatives_match_finite_differences },
#endif
    { "membrane_projected_hessian_is_psd", membrane_projected_hessian_is_psd },
    { "membrane_projected_hessian_stiffens_compressed_sheets_out_of_plane", membrane_projected_hessian_stiffens_compressed_sheets_out_of_plane },
    { "membrane_rest_and_rigid_motion", membrane_rest_and_rigid_motion },
    { "membrane_uniaxial_stretch_gives_analytic_stress", membrane_uniaxial_stretch_gives_analytic_stress },
    { "membrane_isotropy_and_anisotropy", membrane_isotropy_and_anisotropy },
    { "bending_angle_sign_rest_and_weight", bending_angle_sign_rest_and_weight },
    { "bending_angle_all_the_way_round", bending_angle_all_the_way_round },
#ifdef FORCES_FD_TESTS
    { "bending_derivatives_match_finite_differences", bending_derivatives_match_finite_differences },
#endif
    { "bending_projected_hessian_and_rigid_motion", bending_projected_hessian_and_rigid_motion },
    { "bending_cylinder_calibration", bending_cylinder_calibration },
    { "bending_orthotropic_stiffness", bending_orthotropic_stiffness },
#ifdef FORCES_FD_TESTS
    { "quadratic_bending_derivatives_rest_and_rigid_motion", quadratic_bending_derivatives_rest_and_rigid_motion },
    { "quadratic_bending_with_a_clamp_derivatives_rest_and_rigid_motion", quadratic_bending_with_a_clamp_derivatives_rest_and_rigid_motion },
#endif
    { "quadratic_bending_cylinder_calibration", quadratic_bending_cylinder_calibration },
    { "quadratic_bending_clamp_calibration", quadratic_bending_clamp_calibration },
    { "aerodynamic_force", aerodynamic_force },
    { "aerodynamic_velocity_jacobian", aerodynamic_velocity_jacobian },
    { "gusts_are_deterministic_with_requested_statistics", gusts_are_deterministic_with_requested_statistics },
    { "gusts_reject_bad_definitions", gusts_reject_bad_definitions },
    { "relative_damping_and_air_drag", relative_damping_and_air_drag },
    { NULL, NULL }
};
