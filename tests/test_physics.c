/* Physics tests: the accuracy of the integrators and of the cloth model against references computed
   here, independently of the simulator (closed forms, a Richardson-extrapolated reference run, a
   shooting solver for the heavy elastica), and robustness over extreme parameters. Each test
   prints its key measured numbers, indented by four spaces, for the README's tables.

   Scenes are the standard ones of docs/scenes.md where they apply: "hang" is a 1 m x 1 m cloth of
   n x n vertices flat at y = 1 with the two corners at z = -0.5 pinned (vertices 0 and n - 1 of
   cloth_mesh_grid, whose vertex (i, j) is j * n + i, i along x, j along z). */
#include "runner.h"
#include "../cloth.h"
#include "drape_scene.h"
#include <stdlib.h>
#include <string.h>

#define PHYS_G 9.81 /* the gravity of cloth_default_world_def, m/s^2 */

/* ---- helpers ----------------------------------------------------------------------------- */

/* A piece def with an orthotropic membrane of equal warp and weft stiffness k, no Poisson
   coupling and shear k/2, so that the membrane energy density is exactly k/2 |E|^2 (E the Green
   strain), and the given areal density; bending as in the default material unless changed. */
static cloth_piece_def membrane_def(cloth_real stretch, cloth_real density)
{
    cloth_piece_def p = cloth_default_piece_def();
    p.material.areal_density = density;
    p.material.stretch_warp = p.material.stretch_weft = stretch;
    p.material.stretch_coupling = 0;
    p.material.shear = stretch / 2;
    return p;
}

/* The hang scene with n x n vertices; NULL on failure. */
static cloth_world *hang_scene(const cloth_world_def *def, const cloth_piece_def *pdef, int32_t n, int32_t *piece)
{
    cloth_mesh m;
    cloth_world *w = NULL;
    int32_t i;
    if (cloth_mesh_grid(&m, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return NULL;
    for (i = 0; i < m.vertex_count; ++i) m.x[3 * i + 1] = 1;
    if (cloth_world_create(&w, def) != CLOTH_SUCCESS || cloth_world_add_piece(w, &m, pdef, piece) != CLOTH_SUCCESS ||
        cloth_world_pin(w, *piece, 0, NULL) != CLOTH_SUCCESS || cloth_world_pin(w, *piece, n - 1, NULL) != CLOTH_SUCCESS) {
        cloth_world_destroy(w);
        w = NULL;
    }
    cloth_mesh_free(&m);
    return w;
}

static double max_speed(const cloth_world *w, int32_t piece)
{
    const cloth_real *v = cloth_world_velocities(w, piece);
    int32_t i, n = cloth_world_vertex_count(w, piece);
    double best = 0;
    for (i = 0; i < n; ++i) {
        double s = sqrt((double)v[3 * i] * v[3 * i] + (double)v[3 * i + 1] * v[3 * i + 1] + (double)v[3 * i + 2] * v[3 * i + 2]);
        if (s > best) best = s;
    }
    return best;
}

/* Step with a fixed h until every vertex is slower than speed_tolerance (m/s): the number of
   steps taken, or -1 when a step fails or max_steps pass first. A step that leaves every
   vertex at rest is a fixed point of any of the integrators, i.e. a static equilibrium. */
static int32_t settle(cloth_world *w, int32_t piece, cloth_real h, double speed_tolerance, int32_t max_steps)
{
    int32_t s;
    for (s = 1; s <= max_steps; ++s) {
        if (cloth_world_step(w, h, NULL) != CLOTH_SUCCESS) return -1;
        if (max_speed(w, piece) < speed_tolerance) return s;
    }
    return -1;
}

/* Least-squares slope of log(e) against log(h). */
static double fitted_order(const double *h, const double *e, int count)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int i;
    for (i = 0; i < count; ++i) {
        double a = log(h[i]), b = log(e[i]);
        sx += a; sy += b; sxx += a * a; sxy += a * b;
    }
    return (count * sxy - sx * sy) / (count * sxx - sx * sx);
}

static double max_vertex_distance(const cloth_real *a, const cloth_real *b, int32_t n)
{
    double worst = 0;
    int32_t i;
    for (i = 0; i < n; ++i) {
        double dx = (double)a[3 * i] - b[3 * i], dy = (double)a[3 * i + 1] - b[3 * i + 1], dz = (double)a[3 * i + 2] - b[3 * i + 2];
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        if (d > worst) worst = d;
    }
    return worst;
}

/* ---- 1. convergence in the time step ------------------------------------------------------ */

/* Run the hang scene for `steps` steps of T / steps and copy the final positions to x (3 n^2).
   Newton (where the integrator iterates) and CG are driven to tight tolerances so that the
   error measured is the time discretization's. Returns 1 on success; *all_converged is cleared
   when some step's Newton iteration stopped at its cap. */
static int hang_run(cloth_integrator integrator, const cloth_piece_def *p, int32_t n, double T, int32_t steps,
                    cloth_real *x, int *all_converged)
{
    cloth_world_def d = cloth_default_world_def();
    cloth_world *w;
    int32_t piece, s;
    int ok = 1;
    d.integrator = integrator;
    d.newton_tolerance = (cloth_real)1e-10;
    d.newton_max_iterations = 100;
    d.cg.tolerance = (cloth_real)1e-12;
    d.cg.max_iterations = 10000;
    w = hang_scene(&d, p, n, &piece);
    if (!w) return 0;
    for (s = 0; s < steps && ok; ++s) {
        cloth_step_stats st;
        ok = cloth_world_step(w, (cloth_real)(T / steps), &st) == CLOTH_SUCCESS;
        if (!st.newton_converged) *all_converged = 0;
    }
    if (ok) memcpy(x, cloth_world_positions(w, piece), sizeof(cloth_real) * 3 * (size_t)n * (size_t)n);
    cloth_world_destroy(w);
    return ok;
}

TEST(integrators_converge_in_dt_at_their_order)
{
    /* The hang scene with n = 6, from rest, for T = 0.2 s; error = the largest vertex distance
       at T from a reference. Material: C11 = C22 = 10 N/m, C33 = 5 N/m, density 0.1 kg/m^2,
       the default (cotton) bending.
       Why so soft: the error is in its asymptotic regime only when the coarsest step resolves
       the fastest mode the start excites (the pins hold two corners while the rest falls: a
       sharp wave). For a membrane omega^2 <= 12 lambda_max(D) / (rho L^2) (the bound of
       cloth_material_stable_time_step), here lambda_max(D) = 10 N/m, rho = 0.1 kg/m^2 and
       L = sqrt(2/3) * 0.2 m (the stability length of the grid's right triangles): omega <= 212
       rad/s, so the coarsest step h0 = T/48 = 4.2 ms has omega h0 <= 0.88 (bending adds
       nothing visible). Since omega^2 ~ 12 g H / (strain L^2) for any stiffness, resolved
       steps need either a soft cloth (15% strain here) or very small steps; a stiffer cloth at
       the same steps (n = 8, C11 = 100 N/m, omega h0 <= 3.9) fits 0.90 and 1.89, still
       pre-asymptotic.
       Reference: backward Euler with Newton converged (newton_tolerance 1e-10 m/s, CG 1e-12)
       at h0/32 and h0/64, Richardson-extrapolated, x_ref = 2 x(h0/64) - x(h0/32): backward
       Euler's error has an expansion C1 h + C2 h^2 + ..., so x_ref is second-order accurate.
       Its error is ~8e-8 m here (it differs by 2.4e-7 m from the extrapolation of h0/16 and
       h0/32, whose error is 4 times larger), 2% of the smallest error fitted (BDF2 at h0/8,
       3.6e-6 m); the unextrapolated backward Euler reference at h0/64 carries ~6e-5 m and
       would hide BDF2's order (fitted 0.5 against it).
       The order is the least-squares slope of log(error) over log(h) for h0, h0/2, h0/4,
       h0/8. Expected: 1 for backward Euler, with Newton converged or with its single
       linearized Newton step (whose defect per step is O(h^2)), and 2 for BDF2 (its first step
       is backward Euler, a local O(h^2) error that keeps the global error O(h^2)). */
    const int32_t n = 6, N0 = 48, nv = 36;
    const double T = 0.2;
    cloth_piece_def p = membrane_def(10, (cloth_real)0.1);
    cloth_real ref[3 * 36], half[3 * 36], x[3 * 36];
    double h[4], e_be[4], e_bdf2[4], e_lin[4], order_be, order_bdf2, order_lin;
    int conv_ref = 1, conv = 1, k, i;
    ENSURE(hang_run(CLOTH_INTEGRATOR_BACKWARD_EULER, &p, n, T, N0 * 32, half, &conv_ref));
    ENSURE(hang_run(CLOTH_INTEGRATOR_BACKWARD_EULER, &p, n, T, N0 * 64, ref, &conv_ref));
    printf("    reference: |x(h0/64) - x(h0/32)| = %.3g m (the backward Euler error at h0/64, removed by extrapolation)\n",
           max_vertex_distance(ref, half, nv));
    for (i = 0; i < 3 * nv; ++i) ref[i] = 2 * ref[i] - half[i];
    for (k = 0; k < 4; ++k) {
        int32_t steps = N0 << k;
        h[k] = T / steps;
        ENSURE(hang_run(CLOTH_INTEGRATOR_BACKWARD_EULER, &p, n, T, steps, x, &conv));
        e_be[k] = max_vertex_distance(x, ref, nv);
        ENSURE(hang_run(CLOTH_INTEGRATOR_BDF2, &p, n, T, steps, x, &conv));
        e_bdf2[k] = max_vertex_distance(x, ref, nv);
        ENSURE(hang_run(CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED, &p, n, T, steps, x, &conv));
        e_lin[k] = max_vertex_distance(x, ref, nv);
        printf("    h = %.4g s: error backward Euler (Newton) %.3e m, BDF2 %.3e m, linearized backward Euler %.3e m\n", h[k],
               e_be[k], e_bdf2[k], e_lin[k]);
    }
    order_be = fitted_order(h, e_be, 4);
    order_bdf2 = fitted_order(h, e_bdf2, 4);
    order_lin = fitted_order(h, e_lin, 4);
    printf("    fitted order: backward Euler (Newton) %.3f, BDF2 %.3f, linearized backward Euler %.3f\n", order_be, order_bdf2,
           order_lin);
    ENSURE(conv_ref && conv);
    ENSURE(order_be >= 0.8 && order_be <= 1.2);
    ENSURE(order_lin >= 0.8 && order_lin <= 1.2);
    ENSURE(order_bdf2 >= 1.7 && order_bdf2 <= 2.3);
}

/* ---- 2. convergence in the mesh size ------------------------------------------------------ */

/* Positions on the n x n grid, n = 2 nc - 1, interpolated from those of the nc x nc grid (the
   two grids nest: vertex (2i, 2j) is coarse vertex (i, j); the others average the coarse
   vertices around them). */
static void upsample_grid(const cloth_real *coarse, int32_t nc, cloth_real *fine)
{
    int32_t n = 2 * nc - 1, i, j, k;
    for (j = 0; j < n; ++j)
        for (i = 0; i < n; ++i) {
            int32_t i0 = i / 2, j0 = j / 2, i1 = i0 + (i & 1), j1 = j0 + (j & 1);
            for (k = 0; k < 3; ++k)
                fine[3 * (j * n + i) + k] = (coarse[3 * (j0 * nc + i0) + k] + coarse[3 * (j0 * nc + i1) + k] +
                                             coarse[3 * (j1 * nc + i0) + k] + coarse[3 * (j1 * nc + i1) + k]) / 4;
        }
}

/* The static equilibrium of the hang scene with n x n vertices, hanging from the vertices of its
   top edge (z = -0.5) within `clamp` metres of either corner (clamp 0: the two corner vertices
   alone, the standard scene), started from `start` (NULL: flat). Material: isotropic membrane,
   tensile stiffness 100 N/m, Poisson ratio 0.3, density 0.1 kg/m^2, the default bending.
   Equilibrium is reached by linearized backward Euler steps of 0.2 s with air drag 0.3 N s/m^3
   until every vertex is slower than 1e-5 m/s: a step that leaves the cloth at rest is a fixed
   point of the step, where the elastic forces balance gravity (the CG tolerance, 1e-3, then
   only slows the approach: at rest the right-hand side h f(x) must itself vanish). Stopping at
   1e-7 m/s instead moves the lowest point by less than 1e-7 m, 0.03% of the smallest
   difference measured. Returns the number of steps, or -1. */
static int32_t hang_equilibrium(int32_t n, double clamp, const cloth_real *start, cloth_real *x, double *strain)
{
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = cloth_default_piece_def();
    cloth_world *w;
    int32_t piece, i, steps = -1;
    d.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    d.cg.tolerance = (cloth_real)1e-3;
    d.cg.max_iterations = 10000;
    p.material.areal_density = (cloth_real)0.1;
    if (cloth_material_set_isotropic(&p.material, 100, (cloth_real)0.3) != CLOTH_SUCCESS) return -1;
    p.drag = (cloth_real)0.3;
    w = hang_scene(&d, &p, n, &piece);
    if (!w) return -1;
    for (i = 1; i < n - 1; ++i)
        if ((double)i / (n - 1) <= clamp + 1e-9 || (double)(n - 1 - i) / (n - 1) <= clamp + 1e-9)
            if (cloth_world_pin(w, piece, i, NULL) != CLOTH_SUCCESS) goto done;
    if (start && cloth_world_set_positions(w, piece, start) != CLOTH_SUCCESS) goto done;
    steps = settle(w, piece, (cloth_real)0.2, 1e-5, 400);
    memcpy(x, cloth_world_positions(w, piece), sizeof(cloth_real) * 3 * (size_t)n * (size_t)n);
    *strain = cloth_world_max_edge_strain(w, piece);
done:
    cloth_world_destroy(w);
    return steps;
}

static double lowest_y(const cloth_real *x, int32_t count)
{
    double y = x[1];
    int32_t i;
    for (i = 1; i < count; ++i)
        if (x[3 * i + 1] < y) y = x[3 * i + 1];
    return y;
}

TEST(static_sag_converges_under_mesh_refinement)
{
    /* The static sag (lowest y at rest) of the hang scene at n = 9, 17, 33 vertices per side
       (8, 16, 32 intervals: nested grids), each level started from the previous one's
       equilibrium interpolated, must converge: the difference between successive levels must
       shrink. (n = 65 takes about 30 times the n = 33 solve, past this suite's budget; run
       outside it, it gives a third difference of 2.08e-4 m, ratio 1.54 to the second.)
       The standard scene pins the two corner vertices alone. A point support of a membrane is
       a singularity: the reaction F ~ 0.5 N spreads over a radius r, so the strain there is
       ~F / (pi k r) and the displacement ~F / (2 pi k) ln(1 / r), unbounded as r shrinks; at a
       pin r is the mesh size, so each halving of it adds about the same sag, and the strain at
       the pin doubles. That scene therefore has no converged sag to compare with (only the
       St.Venant-Kirchhoff stiffening at large strain eventually bounds it), and this test
       holds each corner instead over a fixed physical length, 1/8 m of the top edge (2, 3 and 5
       vertices at n = 9, 17, 33): a clamp whose ends have integrable singularities. The point
       pins' behaviour is checked too, on n = 5, 9, 17: the strain at the pins must grow by at
       least 1.5 per halving of the mesh size (2 for linear elasticity; the stiffening of
       St.Venant-Kirchhoff at the 10% strains reached here takes off less than a quarter). */
    cloth_real *x[3] = { NULL, NULL, NULL };
    double y[3], strain[3], pin_y[3], pin_strain[3];
    int32_t steps[3], pin_steps[3], level, nlev[3] = { 9, 17, 33 }, plev[3] = { 5, 9, 17 };
    double d1, d2;
    int ok = 1;
    for (level = 0; level < 3 && ok; ++level) {
        int32_t n = nlev[level];
        x[level] = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n * (size_t)n);
        if (!x[level]) { ok = 0; break; }
        if (level) upsample_grid(x[level - 1], nlev[level - 1], x[level]);
        steps[level] = hang_equilibrium(n, 0.125, level ? x[level] : NULL, x[level], &strain[level]);
        y[level] = lowest_y(x[level], n * n);
        ok = steps[level] > 0;
        printf("    corners clamped over 1/8 m, n = %2d: lowest y %.7f m, max strain %.4f (%d steps to rest)\n", (int)n, y[level],
               strain[level], (int)steps[level]);
    }
    for (level = 0; level < 3; ++level) {
        free(x[level]);
        x[level] = NULL;
    }
    ENSURE(ok);
    d1 = fabs(y[1] - y[0]);
    d2 = fabs(y[2] - y[1]);
    printf("    successive differences %.3e m, %.3e m: ratio %.2f\n", d1, d2, d1 / d2);
    for (level = 0; level < 3 && ok; ++level) {
        int32_t n = plev[level];
        x[level] = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)n * (size_t)n);
        if (!x[level]) { ok = 0; break; }
        if (level) upsample_grid(x[level - 1], plev[level - 1], x[level]);
        pin_steps[level] = hang_equilibrium(n, 0, level ? x[level] : NULL, x[level], &pin_strain[level]);
        pin_y[level] = lowest_y(x[level], n * n);
        ok = pin_steps[level] > 0;
        printf("    corner vertices pinned (the standard scene), n = %2d: lowest y %.7f m, max strain %.4f\n", (int)n,
               pin_y[level], pin_strain[level]);
    }
    for (level = 0; level < 3; ++level) free(x[level]);
    ENSURE(ok);
    printf("    point pins: successive differences %.3e m, %.3e m (ratio %.2f); strain ratios %.2f, %.2f\n",
           fabs(pin_y[1] - pin_y[0]), fabs(pin_y[2] - pin_y[1]), fabs(pin_y[1] - pin_y[0]) / fabs(pin_y[2] - pin_y[1]),
           pin_strain[1] / pin_strain[0], pin_strain[2] / pin_strain[1]);
    ENSURE(d2 < d1);
    ENSURE(pin_strain[1] >= 1.5 * pin_strain[0] && pin_strain[2] >= 1.5 * pin_strain[1]);
}

/* ---- 3. the catenary ---------------------------------------------------------------------- */

TEST(a_hanging_strip_is_a_catenary)
{
    /* A strip of rest length L = 1 m and width 0.02 m (31 x 3 vertices; the pattern's u runs
       along it), nearly inextensible (C11 = C22 = 1e4 N/m, C33 = 5e3 N/m: its weight, 0.02 N,
       stretches it by ~6e-5) and nearly without bending (B = 1e-8 N m: a bending length
       (B / (w g))^(1/3) = 2 mm, against a span of 0.8 m), density 0.1 kg/m^2, held along both
       short ends (all three vertices of each end pinned) at equal height, the ends d = 0.8 m
       apart. The slack is given by the initial shape: a circular arc of length L through the
       two ends (every edge at its rest length to 2e-4), from which the strip swings to rest (linearized
       backward Euler steps of 0.1 s, air drag 0.3 N s/m^3, until every vertex is slower than
       1e-6 m/s). At rest its centre line must be the catenary of an inextensible chain,
       y = a cosh(x / a) + c with L = 2 a sinh(d / (2 a)) (a solved here by bisection) and c
       putting the ends at their height: every centre-line vertex within 1% of the span of the
       curve (distance to the curve, sampled at 20001 points). */
    const int32_t nx = 31, ny = 3;
    const double L = 1, d = 0.8, width = 0.02, top = 1;
    cloth_mesh m;
    cloth_world *w = NULL;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def p = membrane_def((cloth_real)1e4, (cloth_real)0.1);
    int32_t piece, i, j, steps;
    double lo, hi, phi, R, yc, a, c, worst = 0, strain;
    /* the arc: half-angle phi with sin(phi) / phi = d / L */
    lo = 1e-9; hi = 3.14159;
    for (i = 0; i < 200; ++i) {
        double mid = 0.5 * (lo + hi);
        if (sin(mid) / mid > d / L) lo = mid; else hi = mid;
    }
    phi = 0.5 * (lo + hi);
    R = L / (2 * phi);
    yc = top + R * cos(phi);
    ENSURE(cloth_mesh_grid(&m, nx, ny, (cloth_real)L, (cloth_real)width, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    for (i = 0; i < m.vertex_count; ++i) {
        double angle = -phi + m.uv[2 * i] / R; /* arc length u from the left end */
        m.x[3 * i] = (cloth_real)(R * sin(angle));
        m.x[3 * i + 1] = (cloth_real)(yc - R * cos(angle));
    }
    def.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    def.cg.max_iterations = 10000;
    p.material.bend_warp = p.material.bend_weft = (cloth_real)1e-8;
    p.drag = (cloth_real)0.3;
    ENSURE(cloth_world_create(&w, &def) == CLOTH_SUCCESS);
    ENSURE(cloth_world_add_piece(w, &m, &p, &piece) == CLOTH_SUCCESS);
    cloth_mesh_free(&m);
    for (j = 0; j < ny; ++j) {
        ENSURE(cloth_world_pin(w, piece, j * nx, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_world_pin(w, piece, j * nx + nx - 1, NULL) == CLOTH_SUCCESS);
    }
    steps = settle(w, piece, (cloth_real)0.1, 1e-6, 300);
    strain = cloth_world_max_edge_strain(w, piece);
    /* the catenary through the ends: 2 a sinh(d / 2a) decreases from infinity to d as a grows */
    lo = 1e-3; hi = 1e3;
    for (i = 0; i < 200; ++i) {
        double mid = sqrt(lo * hi);
        if (2 * mid * sinh(d / (2 * mid)) > L) lo = mid; else hi = mid;
    }
    a = sqrt(lo * hi);
    c = top - a * cosh(d / (2 * a));
    for (i = 0; i < nx; ++i) {
        const cloth_real *q = cloth_world_positions(w, piece) + 3 * (nx + i); /* the middle row */
        double best = 1e30;
        int32_t t;
        for (t = 0; t <= 20000; ++t) {
            double cx = -d / 2 + d * t / 20000, cy = a * cosh(cx / a) + c;
            double dist = sqrt((q[0] - cx) * (q[0] - cx) + (q[1] - cy) * (q[1] - cy));
            if (dist < best) best = dist;
        }
        if (best > worst) worst = best;
    }
    printf("    catenary: a = %.5f m, lowest point %.5f m (strip's middle vertex %.5f m); max deviation %.3e m = %.4f%% of the span "
           "(%d steps to rest, max strain %.1e)\n", a, a + c, (double)cloth_world_positions(w, piece)[3 * (nx + nx / 2) + 1], worst,
           100 * worst / d, (int)steps, strain);
    cloth_world_destroy(w);
    ENSURE(steps > 0);
    ENSURE(worst <= 0.01 * d);
}

/* ---- 4. Peirce's cantilever and the heavy elastica -------------------------------------- */

/* The heavy elastica, solved here independently of the simulator. A strip clamped horizontally
   at s = 0 and free at s = l, of bending stiffness B (N m: moment per unit width per unit
   curvature) and weight w g per unit area; theta(s) is the angle of its tangent below the horizontal. The
   moment of the weight beyond s is B theta'(s), so B theta'' + w g (l - s) cos(theta) = 0 with
   theta(0) = 0 and theta'(l) = 0. In sigma = s / l: theta'' = -lambda (1 - sigma) cos(theta),
   lambda = w g l^3 / B, and the shape follows from x' = cos(theta), y' = sin(theta) (y
   downward, in units of l). RK4 in 2000 steps from theta'(0) = kappa0, and bisection on kappa0
   in [0, lambda] for theta'(1) = 0: at kappa0 = 0, theta'(1) < 0; at kappa0 = lambda,
   theta'(1) >= lambda - lambda/2 > 0. */
static void elastica_rhs(double s, const double *y, double lambda, double *f)
{
    f[0] = y[1];
    f[1] = -lambda * (1 - s) * cos(y[0]);
    f[2] = cos(y[0]);
    f[3] = sin(y[0]);
}

static void elastica_shoot(double lambda, double kappa0, double *y)
{
    const int steps = 2000;
    const double h = 1.0 / steps;
    int i, k;
    y[0] = 0; y[1] = kappa0; y[2] = 0; y[3] = 0;
    for (i = 0; i < steps; ++i) {
        double s = i * h, k1[4], k2[4], k3[4], k4[4], t[4];
        elastica_rhs(s, y, lambda, k1);
        for (k = 0; k < 4; ++k) t[k] = y[k] + h / 2 * k1[k];
        elastica_rhs(s + h / 2, t, lambda, k2);
        for (k = 0; k < 4; ++k) t[k] = y[k] + h / 2 * k2[k];
        elastica_rhs(s + h / 2, t, lambda, k3);
        for (k = 0; k < 4; ++k) t[k] = y[k] + h * k3[k];
        elastica_rhs(s + h, t, lambda, k4);
        for (k = 0; k < 4; ++k) y[k] += h / 6 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]);
    }
}

/* The chord angle (clamp to tip) and the tip's tangent angle below the horizontal, radians. */
static void heavy_elastica(double lambda, double *chord, double *tip)
{
    double lo = 0, hi = lambda, y[4];
    int i;
    for (i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi);
        elastica_shoot(lambda, mid, y);
        if (y[1] > 0) hi = mid; else lo = mid;
    }
    elastica_shoot(lambda, 0.5 * (lo + hi), y);
    *chord = atan2(y[3], y[2]);
    *tip = y[0];
}

#define CANT_B 1e-5   /* N m: a shirting-weight cotton (cloth_default_material has 9.8e-6) */
#define CANT_W 0.2    /* kg/m^2 */

/* A cantilever in cloth.h: a strip on a union-jack grid (cloth_mesh_grid, alternating
   diagonals) of 3 rows dz apart, with `intervals` cells of length dx = l / intervals over the
   overhang and one more behind the clamp line; the strip runs along x = the warp u, flat at
   y = 0. The two columns x = -dx and x = 0 are pinned: together they hold the clamp line's
   position and slope (a horizontal ledge, the strip's free part starting at x = 0; the faces
   between them are pinned, which the quadratic bending takes for a clamp: the clamp line's
   vertices get their half cells on the free side). This is ASTM D1388's geometry: there the
   specimen lies on a horizontal platform under a weighted slide and is pushed over the edge,
   and the slide holds the part on the platform flat, so the strip leaves the edge tangent to
   the platform, Peirce's clamped heavy elastica (without the slide the moment at the edge,
   about w g l^2 / 2, would lift the strip off the platform behind the edge). Material:
   bend_warp = bend_weft = CANT_B (along u the hinges of the grid's z-edges take bend_warp, the
   diagonals mix both: equal values leave no ambiguity), density CANT_W, membrane C11 = C22 =
   1e3 N/m, C33 = 500 N/m (the strip's tension, < w g l <= 0.1 N/m, stretches it by < 1e-4:
   inextensible). With couple_force == 0 it hangs under gravity; otherwise gravity is off and a
   couple acts at the tip, couple_force (N) down on the tip column and up on the one before,
   spread over the rows as 1/4, 1/2, 1/4 (each row's share of the width): a moment
   couple_force * dx on every hinge from the clamp to the tip. Rest by linearized backward Euler
   steps of 0.2 s with air drag 0.02 N s/m^3 until every vertex is slower than 1e-7 m/s.
   Measured on the middle row: the chord angle from the clamp vertex to the tip vertex and the
   tip's tangent (its last segment) below the horizontal; and the ratio of the mean row hinge
   angle (the turn between successive segments of a row) at the grid's valence-8 vertices
   ((i + j) even) to that at its valence-4 vertices, over the interior columns (1 for a smooth
   bend). Returns 1 on success. */
static int cantilever(double l, int32_t intervals, double dz, double couple_force, double *chord, double *tip, double *star_ratio)
{
    const int32_t nx = intervals + 2, ny = 3;
    double dx = l / intervals;
    cloth_mesh m;
    cloth_world *w = NULL;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def p = membrane_def((cloth_real)1e3, (cloth_real)CANT_W);
    cloth_real *force = NULL;
    int32_t piece, i, j, steps = -1;
    int ok = 0;
    p.bending_model = CLOTH_BENDING_QUADRATIC; /* the accurate one (the world's default is the faster dihedral) */
    if (cloth_mesh_grid(&m, nx, ny, (cloth_real)(l + dx), (cloth_real)(2 * dz), CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS)
        return 0;
    for (i = 0; i < m.vertex_count; ++i) m.x[3 * i] += (cloth_real)((l + dx) / 2 - dx); /* column 1 at x = 0 */
    def.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    def.cg.tolerance = (cloth_real)1e-3;
    def.cg.max_iterations = 10000;
    if (couple_force != 0) def.gravity[1] = 0;
    p.material.bend_warp = p.material.bend_weft = (cloth_real)CANT_B;
    p.drag = (cloth_real)0.02;
    if (cloth_world_create(&w, &def) != CLOTH_SUCCESS || cloth_world_add_piece(w, &m, &p, &piece) != CLOTH_SUCCESS) goto done;
    for (j = 0; j < ny; ++j)
        if (cloth_world_pin(w, piece, j * nx, NULL) != CLOTH_SUCCESS || cloth_world_pin(w, piece, j * nx + 1, NULL) != CLOTH_SUCCESS)
            goto done;
    if (couple_force != 0) {
        force = (cloth_real *)calloc(3 * (size_t)m.vertex_count, sizeof(cloth_real));
        if (!force) goto done;
        for (j = 0; j < ny; ++j) {
            double share = (j == 0 || j == ny - 1) ? 0.25 : 0.5;
            force[3 * (j * nx + nx - 1) + 1] = (cloth_real)(-couple_force * share);
            force[3 * (j * nx + nx - 2) + 1] = (cloth_real)(couple_force * share);
        }
        if (cloth_world_set_external_forces(w, piece, force) != CLOTH_SUCCESS) goto done;
    }
    steps = settle(w, piece, (cloth_real)0.2, 1e-7, 400);
    if (steps > 0) {
        const cloth_real *x = cloth_world_positions(w, piece);
        const cloth_real *clamp = x + 3 * (nx + 1), *end = x + 3 * (nx + nx - 1), *before = x + 3 * (nx + nx - 2);
        double sum[2] = { 0, 0 };
        int32_t count[2] = { 0, 0 };
        *chord = atan2(-(double)(end[1] - clamp[1]), (double)(end[0] - clamp[0]));
        *tip = atan2(-(double)(end[1] - before[1]), (double)(end[0] - before[0]));
        for (j = 0; j < ny; ++j)
            for (i = 2; i < nx - 2; ++i) {
                const cloth_real *a = x + 3 * (j * nx + i - 1), *b = x + 3 * (j * nx + i), *c = x + 3 * (j * nx + i + 1);
                double turn = atan2((double)(a[1] - b[1]), (double)(b[0] - a[0])) - atan2((double)(b[1] - c[1]), (double)(c[0] - b[0]));
                sum[(i + j) & 1] += fabs(turn);
                count[(i + j) & 1]++;
            }
        *star_ratio = (sum[0] / count[0]) / (sum[1] / count[1]);
        ok = 1;
    }
done:
    free(force);
    cloth_mesh_free(&m);
    cloth_world_destroy(w);
    return ok;
}

TEST(a_cantilever_matches_the_heavy_elastica)
{
    /* Peirce's cantilever (ASTM D1388): B = 1e-5 N m, w = 0.2 kg/m^2, so the bending length is
       c = (B / (w g))^(1/3) = 17.2 mm. Overhangs l = c, 2c, 3c (lambda = w g l^3 / B = 1, 8,
       27: small, Peirce's and large deflection). Two meshes of 30 cells along the overhang and
       3 rows: "square" cells (dz = dx, a strip 2 dx wide: per unit width the model has no
       anticlastic coupling, and wider strips of square cells give the same angles within 1%),
       and the ASTM strip's real width, 25 mm (dz = 12.5 mm, cells 7 to 22 times longer across
       than along). Required: the chord angle and the tip tangent's angle within 3% of the heavy
       elastica's (each compared with the same quantity). Peirce: the overhang at which the
       chord reaches 41.5 degrees must be within 3% of 2c (cloth_cantilever_overhang) for the
       square-cell strip (found by a secant step in log l from l = 2c, using the elastica's
       local slope d ln(chord) / d ln(l) for the first step) and, for the elastica itself
       (bisection on lambda), within 0.5% (the exact heavy elastica puts 41.49 degrees at
       lambda = 8). */
    const double g = PHYS_G, c = cbrt(CANT_B / (CANT_W * g)), target = 41.5 * 3.14159265358979323846 / 180;
    const double rad = 180 / 3.14159265358979323846;
    double chord[2][3], tip[2][3], ref_chord[3], ref_tip[3], star[2][3], worst = 0;
    double lambda_star, lo = 4, hi = 16, l_star_elastica, slope, t0, t1, l1, l_star, check, fine_chord, fine_tip;
    double dummy_tip, dummy_star, api_overhang = 0;
    cloth_real overhang;
    int32_t mesh, k, i;
    int ok = 1;
    const char *mesh_name[2] = { "square cells (dz = dx)", "ASTM width 25 mm (dz = 12.5 mm)" };
    for (k = 0; k < 3; ++k) heavy_elastica((double)(k + 1) * (k + 1) * (k + 1), &ref_chord[k], &ref_tip[k]);
    for (mesh = 0; mesh < 2 && ok; ++mesh)
        for (k = 0; k < 3 && ok; ++k) {
            double l = (k + 1) * c, dz = mesh == 0 ? l / 30 : 0.0125;
            ok = cantilever(l, 30, dz, 0, &chord[mesh][k], &tip[mesh][k], &star[mesh][k]);
        }
    if (ok) ok = cantilever(2 * c, 60, 2 * c / 60, 0, &fine_chord, &fine_tip, &dummy_star);
    ENSURE(ok);
    printf("    | mesh | l / c | lambda | chord cloth.h | chord elastica | error | tip cloth.h | tip elastica | error |\n");
    for (mesh = 0; mesh < 2; ++mesh)
        for (k = 0; k < 3; ++k) {
            double ec = chord[mesh][k] / ref_chord[k] - 1, et = tip[mesh][k] / ref_tip[k] - 1;
            printf("    | %s | %d | %d | %.2f deg | %.2f deg | %+.1f%% | %.2f deg | %.2f deg | %+.1f%% |\n", mesh_name[mesh], (int)k + 1,
                   (int)((k + 1) * (k + 1) * (k + 1)), chord[mesh][k] * rad, ref_chord[k] * rad, 100 * ec, tip[mesh][k] * rad,
                   ref_tip[k] * rad, 100 * et);
            if (fabs(ec) > worst) worst = fabs(ec);
            if (fabs(et) > worst) worst = fabs(et);
        }
    printf("    | square cells, 60 cells along | 2 | 8 | %.2f deg | %.2f deg | %+.1f%% | %.2f deg | %.2f deg | %+.1f%% |\n",
           fine_chord * rad, ref_chord[1] * rad, 100 * (fine_chord / ref_chord[1] - 1), fine_tip * rad, ref_tip[1] * rad,
           100 * (fine_tip / ref_tip[1] - 1));
    if (fabs(fine_chord / ref_chord[1] - 1) > worst) worst = fabs(fine_chord / ref_chord[1] - 1);
    if (fabs(fine_tip / ref_tip[1] - 1) > worst) worst = fabs(fine_tip / ref_tip[1] - 1);
    printf("    valence-8 / valence-4 mean row hinge angle (1 for a smooth bend): square %.2f %.2f %.2f, ASTM %.2f %.2f %.2f\n",
           star[0][0], star[0][1], star[0][2], star[1][0], star[1][1], star[1][2]);
    /* Peirce: the elastica's overhang for 41.5 degrees */
    for (i = 0; i < 60; ++i) {
        double mid = 0.5 * (lo + hi), ch, tp;
        heavy_elastica(mid, &ch, &tp);
        if (ch < target) lo = mid; else hi = mid;
    }
    lambda_star = 0.5 * (lo + hi);
    l_star_elastica = cbrt(lambda_star * CANT_B / (CANT_W * g));
    {
        double ch_hi, tp_hi;
        heavy_elastica(8 * 1.03 * 1.03 * 1.03, &ch_hi, &tp_hi);
        slope = log(ch_hi / ref_chord[1]) / log(1.03);
    }
    /* cloth.h's overhang for 41.5 degrees: secant in log l from l = 2c */
    t0 = chord[0][1];
    l1 = 2 * c * exp(log(target / t0) / slope);
    ok = cantilever(l1, 30, l1 / 30, 0, &t1, &dummy_tip, &dummy_star);
    ENSURE(ok);
    l_star = exp(log(2 * c) + (log(l1) - log(2 * c)) * (target - t0) / (t1 - t0));
    ok = cantilever(l_star, 30, l_star / 30, 0, &check, &dummy_tip, &dummy_star); /* how well the secant landed */
    ENSURE(ok);
    if (cloth_cantilever_overhang((cloth_real)CANT_B, (cloth_real)CANT_W, (cloth_real)g, &overhang) == CLOTH_SUCCESS)
        api_overhang = overhang;
    printf("    Peirce, overhang for a 41.5 degree chord: cloth.h %.2f mm, heavy elastica %.2f mm, 2 (B/(w g))^(1/3) = %.2f mm "
           "(cloth_cantilever_overhang %.2f mm): cloth.h / Peirce %.3f, elastica / Peirce %.4f (cloth.h's chord there: %.2f deg)\n",
           1e3 * l_star, 1e3 * l_star_elastica, 2e3 * c, 1e3 * api_overhang, l_star / (2 * c), l_star_elastica / (2 * c), check * rad);
    ENSURE_NEAR(api_overhang, 2 * c, 1e-9);
    ENSURE(fabs(l_star_elastica / (2 * c) - 1) <= 0.005);
    ENSURE(worst <= 0.03);
    ENSURE(fabs(l_star / (2 * c) - 1) <= 0.03);
}

TEST(a_pure_end_moment_bends_a_strip_uniformly)
{
    /* The cantilever's error isolated: no gravity, a couple at the tip puts the same moment M on
       every hinge of the square-cell strip of a_cantilever_matches_the_heavy_elastica (l = c,
       30 and 60 cells of length dx, width W = 2 dx). Plate theory: the strip bends into a
       circular arc of curvature M / (B W), so its tip turns by M l / (B W). The discrete strip
       bends uniformly (a cylinder along a grid axis stores exactly B / (2 R^2) per area on this
       grid: cloth.h's bending documentation) from the clamp line, whose vertex has the half cell
       on the free side, so the tip's last segment, measured here, has the tangent at its middle,
       M (l - dx/2) / (B W): 1/(2 cells) short of the tip's (-1.7% at 30 cells, -0.9% at 60).
       The couple is set for a 0.02 rad turn (its arm shortens by cos(0.02): 0.02%). Required:
       the tip turn within the 3% of the cantilever requirement, and a smooth bend: the mean
       hinge angle at the grid's valence-8 vertices within 3% of that at its valence-4 ones. */
    const double l = cbrt(CANT_B / (CANT_W * PHYS_G)), turn = 0.02;
    double tip[2], star[2], chord;
    int32_t k;
    for (k = 0; k < 2; ++k) {
        int32_t cells = 30 << k;
        double dx = l / cells, force = turn * CANT_B * (2 * dx) / (dx * l);
        ENSURE(cantilever(l, cells, dx, force, &chord, &tip[k], &star[k]));
        printf("    pure moment, %d cells: tip turn %.5f rad, plate theory %.5f rad (%+.1f%%); valence-8 / valence-4 hinge angle %.3f\n",
               (int)cells, tip[k], turn, 100 * (tip[k] / turn - 1), star[k]);
    }
    for (k = 0; k < 2; ++k) {
        ENSURE(fabs(tip[k] / turn - 1) <= 0.03);
        ENSURE(fabs(star[k] - 1) <= 0.03);
    }
}

/* ---- 5. extreme parameters --------------------------------------------------------------- */

/* One run of the extremes matrix and what it showed. */
typedef struct extreme_run {
    cloth_result result;   /* of the first failed step, or CLOTH_SUCCESS */
    int32_t failed_step;   /* its index */
    int restored;          /* a failed step left positions, velocities and time exactly as before */
    int bounded;           /* every state finite and within |x| < 10 m */
    double strain;         /* the largest max edge strain after any step */
    double energy_gain;    /* max over steps of (E - E0) / (M g * 1 m), E = kinetic + gravity + elastic */
    double stable_step;    /* cloth_world_stable_time_step at the start */
} extreme_run;

static void run_extreme(const cloth_mesh *m, int32_t n, cloth_real stretch, cloth_real density, cloth_real strain_limit,
                        double dt, int32_t steps, cloth_integrator integrator, extreme_run *out)
{
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = membrane_def(stretch, density);
    cloth_world *w = NULL;
    cloth_real *x0 = NULL, *v0 = NULL, ke, pe, el;
    int32_t piece, s, nv = m->vertex_count;
    double e0, scale = density * PHYS_G; /* the cloth's weight (1 m^2) times 1 m */
    memset(out, 0, sizeof *out);
    out->result = CLOTH_ERROR_OUT_OF_MEMORY;
    out->bounded = 1;
    d.integrator = integrator;
    p.strain_limit = strain_limit;
    x0 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)nv);
    v0 = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)nv);
    if (!x0 || !v0 || cloth_world_create(&w, &d) != CLOTH_SUCCESS || cloth_world_add_piece(w, m, &p, &piece) != CLOTH_SUCCESS ||
        cloth_world_pin(w, piece, 0, NULL) != CLOTH_SUCCESS || cloth_world_pin(w, piece, n - 1, NULL) != CLOTH_SUCCESS)
        goto done;
    out->stable_step = cloth_world_stable_time_step(w);
    cloth_world_energy(w, &ke, &pe, &el);
    e0 = (double)ke + pe + el;
    out->result = CLOTH_SUCCESS;
    for (s = 0; s < steps; ++s) {
        const cloth_real *x;
        double t0 = cloth_world_time(w), strain;
        int32_t i;
        memcpy(x0, cloth_world_positions(w, piece), sizeof(cloth_real) * 3 * (size_t)nv);
        memcpy(v0, cloth_world_velocities(w, piece), sizeof(cloth_real) * 3 * (size_t)nv);
        out->result = cloth_world_step(w, (cloth_real)dt, NULL);
        if (out->result != CLOTH_SUCCESS) {
            out->failed_step = s;
            out->restored = memcmp(x0, cloth_world_positions(w, piece), sizeof(cloth_real) * 3 * (size_t)nv) == 0 &&
                            memcmp(v0, cloth_world_velocities(w, piece), sizeof(cloth_real) * 3 * (size_t)nv) == 0 &&
                            cloth_world_time(w) == t0;
            break;
        }
        x = cloth_world_positions(w, piece);
        for (i = 0; i < 3 * nv; ++i)
            if (!(fabs((double)x[i]) < 10)) out->bounded = 0; /* also catches NaN */
        strain = cloth_world_max_edge_strain(w, piece);
        if (!(strain <= out->strain)) out->strain = strain; /* NaN propagates */
        cloth_world_energy(w, &ke, &pe, &el);
        if (((double)ke + pe + el - e0) / scale > out->energy_gain) out->energy_gain = ((double)ke + pe + el - e0) / scale;
    }
done:
    cloth_world_destroy(w);
    free(x0);
    free(v0);
}

static const char *result_short_name(cloth_result r)
{
    switch (r) {
    case CLOTH_SUCCESS: return "ok";
    case CLOTH_ERROR_UNSTABLE: return "UNSTABLE";
    case CLOTH_ERROR_NOT_FINITE: return "NOT_FINITE";
    case CLOTH_ERROR_CG_NOT_CONVERGED: return "CG_NOT_CONVERGED";
    case CLOTH_ERROR_NOT_POSITIVE_DEFINITE: return "NOT_POSITIVE_DEFINITE";
    default: return cloth_result_string(r);
    }
}

/* 2 area / (longest edge)^2 of a pattern triangle (cloth_mesh_validate's quality). */
static double pattern_quality(const cloth_real *a, const cloth_real *b, const cloth_real *c)
{
    double ux = (double)b[0] - a[0], uy = (double)b[1] - a[1], vx = (double)c[0] - a[0], vy = (double)c[1] - a[1];
    double wx = (double)c[0] - b[0], wy = (double)c[1] - b[1], l = ux * ux + uy * uy;
    if (vx * vx + vy * vy > l) l = vx * vx + vy * vy;
    if (wx * wx + wy * wy > l) l = wx * wx + wy * wy;
    return fabs(ux * vy - uy * vx) / l;
}

TEST(extreme_parameters_never_blow_up)
{
    /* The hang scene at n = 6 (a 5 x 5 union-jack grid) over stretch stiffness k = C11 = C22 =
       1e1 .. 1e7 N/m (C33 = k/2), areal density 0.01, 0.1, 1 kg/m^2 and steps 1e-4, 1e-3, 1/60,
       1/30 s, each run 0.1 s or 20 steps, whichever is shorter (0.1 s at 1/60 and 1/30 s), for
       linearized backward Euler, BDF2, backward Euler with Newton and symplectic Euler. Four more
       rows (density 0.1) use a grid with near-degenerate triangles: two interior vertices moved
       (in the pattern and in space alike) towards the diagonal of their cells until one
       triangle of each has quality 2 area / longest edge^2 = 1e-3. Four more (density 0.1,
       the grid) add strain limiters at 1e-6 (piece def strain_limit, stiffening 100: the
       edges beyond it are 101 times as stiff, up to 1e9 N/m; every implicit run of 0.1 s, at
       1/60 and 1/30 s, must strain past it, so that its limiters are engaged).
       Required of the implicit integrators: every step succeeds, every position stays finite
       and within |x| < 10 m (the scene is 1 m across and falls 5 cm in 0.1 s), and the max edge
       strain stays below 1. Why 1 bounds a blow-up: the strain near a pin is about the ratio of
       the fall speed (g t < 1 m/s) to the membrane's wave speed sqrt(k / rho) >= 3 m/s, so the
       physical strain stays below ~0.3 in every cell (measured: below 0.1). Symplectic Euler:
       a step above cloth_world_stable_time_step must be refused with CLOTH_ERROR_UNSTABLE and
       leave the world bit for bit as it was; below it, it must run like the implicit ones (with
       limiters too: the estimate counts them as engaged, since one may engage before it is
       made again).
       The table (markdown) gives per cell "ok" and the largest strain, or the error and the step
       it came at. The energy gain (E - E0 over the scene's M g * 1 m; not required of anyone
       here: linearized backward Euler and BDF2 do not promise it) is reported per integrator. */
    const int32_t n = 6;
    const double ks[4] = { 1e1, 1e3, 1e5, 1e7 }, rhos[3] = { 0.01, 0.1, 1 }, dts[4] = { 1e-4, 1e-3, 1.0 / 60, 1.0 / 30 };
    const cloth_integrator integ[4] = { CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED, CLOTH_INTEGRATOR_BDF2, CLOTH_INTEGRATOR_BACKWARD_EULER,
                                        CLOTH_INTEGRATOR_SYMPLECTIC_EULER };
    const char *integ_name[4] = { "linearized BE", "BDF2", "BE (Newton)", "symplectic Euler" };
    cloth_mesh grid, degenerate;
    double worst_gain[4] = { 0, 0, 0, 0 }, min_quality = 1, max_strain_implicit = 0;
    const char *worst_where[4] = { "no run gained energy", "no run gained energy", "no run gained energy", "no run gained energy" };
    char where[4][96];
    int32_t row, di, ii, t, failures = 0, refusals = 0, symplectic_runs = 0, limited_runs = 0, limited_engaged = 0;
    ENSURE(cloth_mesh_grid(&grid, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    for (t = 0; t < grid.vertex_count; ++t) grid.x[3 * t + 1] = 1;
    ENSURE(cloth_mesh_copy(&degenerate, &grid, NULL) == CLOTH_SUCCESS);
    {
        /* vertices (1, 2) and (3, 2): (i + j) odd, so their cells (i, j) are split along the
           diagonal from (i + 1, j) to (i, j + 1); moving (i, j) by s along (1, 1) / sqrt(2) in
           (x, z) leaves it h / sqrt(2) - s from that diagonal, of length h sqrt(2), so the
           triangle's quality is (h / sqrt(2) - s) / (h sqrt(2)): 1e-3 for the s below. */
        const int32_t moved[2] = { 2 * n + 1, 2 * n + 3 };
        double h = 1.0 / (n - 1), shift = h / sqrt(2.0) - sqrt(2.0) * 1e-3 * h;
        for (t = 0; t < 2; ++t) {
            int32_t v = moved[t];
            degenerate.x[3 * v] += (cloth_real)(shift / sqrt(2.0));
            degenerate.x[3 * v + 2] += (cloth_real)(shift / sqrt(2.0));
            degenerate.uv[2 * v] += (cloth_real)(shift / sqrt(2.0));
            degenerate.uv[2 * v + 1] -= (cloth_real)(shift / sqrt(2.0)); /* uv = (x + 1/2, 1/2 - z) */
        }
        for (t = 0; t < degenerate.triangle_count; ++t) {
            const int32_t *tri = degenerate.tri + 3 * t;
            double q = pattern_quality(degenerate.uv + 2 * tri[0], degenerate.uv + 2 * tri[1], degenerate.uv + 2 * tri[2]);
            if (q < min_quality) min_quality = q;
        }
    }
    printf("    extremes: hang scene n = 6, C11 = C22 = k, C33 = k/2, default bending; 0.1 s or 20 steps per run; "
           "entries: ok and the max edge strain, or the error @ the step it came at (* = above the stable step estimate)\n");
    printf("    near-degenerate mesh: min pattern quality %.2e (cloth_mesh_validate: %s)\n", min_quality,
           cloth_result_string(cloth_mesh_validate(&degenerate, 0, NULL, NULL)));
    printf("    | k (N/m) | rho (kg/m^2) | mesh |");
    for (di = 0; di < 4; ++di)
        for (ii = 0; ii < 4; ++ii) printf(" %s, dt %.3g |", integ_name[ii], dts[di]);
    printf("\n    |---|---|---|");
    for (di = 0; di < 16; ++di) printf("---|");
    printf("\n");
    for (row = 0; row < 20; ++row) {
        int deg = row >= 12 && row < 16, limited = row >= 16;
        double k = ks[deg ? row - 12 : limited ? row - 16 : row / 3], rho = deg || limited ? 0.1 : rhos[row % 3];
        cloth_real limit = limited ? (cloth_real)1e-6 : 0;
        printf("    | %.0e | %g | %s |", k, rho, deg ? "degenerate" : limited ? "grid, limiters at 1e-6" : "grid");
        for (di = 0; di < 4; ++di)
            for (ii = 0; ii < 4; ++ii) {
                extreme_run r;
                int32_t steps = (int32_t)floor(0.1 / dts[di] + 0.5);
                int above;
                if (steps > 20) steps = 20;
                run_extreme(deg ? &degenerate : &grid, n, (cloth_real)k, (cloth_real)rho, limit, dts[di], steps, integ[ii], &r);
                above = dts[di] > r.stable_step;
                if (r.result == CLOTH_SUCCESS) printf(" ok %.1e |", r.strain);
                else printf(" %s@%d%s |", result_short_name(r.result), (int)r.failed_step, above ? "*" : "");
                if (limited && di >= 2 && integ[ii] != CLOTH_INTEGRATOR_SYMPLECTIC_EULER) {
                    ++limited_runs;
                    limited_engaged += r.strain > limit;
                }
                if (integ[ii] == CLOTH_INTEGRATOR_SYMPLECTIC_EULER && above) {
                    ++refusals;
                    if (!(r.result == CLOTH_ERROR_UNSTABLE && r.failed_step == 0 && r.restored)) ++failures;
                } else {
                    if (integ[ii] == CLOTH_INTEGRATOR_SYMPLECTIC_EULER) ++symplectic_runs;
                    if (!(r.result == CLOTH_SUCCESS && r.bounded && r.strain < 1)) ++failures;
                    if (integ[ii] != CLOTH_INTEGRATOR_SYMPLECTIC_EULER && r.strain > max_strain_implicit) max_strain_implicit = r.strain;
                    if (r.energy_gain > worst_gain[ii]) {
                        worst_gain[ii] = r.energy_gain;
                        snprintf(where[ii], sizeof where[ii], "k %.0e, rho %g, %s, dt %.3g", k, rho, deg ? "degenerate" : "grid", dts[di]);
                        worst_where[ii] = where[ii];
                    }
                }
            }
        printf("\n");
    }
    for (ii = 0; ii < 4; ++ii)
        printf("    largest energy gain, %s: %.3g M g m (%s)\n", integ_name[ii], worst_gain[ii], worst_where[ii]);
    printf("    symplectic Euler: %d runs refused at the first step (above the estimate), %d ran below it; largest implicit strain %.3g; "
           "cells failing the requirements: %d\n", (int)refusals, (int)symplectic_runs, max_strain_implicit, (int)failures);
    printf("    limiter rows: %d of %d implicit 0.1 s runs strained past the limit\n", (int)limited_engaged, (int)limited_runs);
    cloth_mesh_free(&grid);
    cloth_mesh_free(&degenerate);
    ENSURE(min_quality > 0.5e-3 && min_quality < 2e-3);
    ENSURE(limited_engaged == limited_runs);
    ENSURE(failures == 0);
}

/* The sphere scene of docs/scenes.md at the library's defaults (tests/drape_scene.h). */
static int sphere_drop_world(int32_t n, cloth_world **w, cloth_mesh *m, int32_t *piece)
{
    return drape_scene_world(cloth_default_world_def(), n, 0, w, m, piece);
}

TEST(a_cloth_dropped_on_a_sphere_never_overstretches)
{
    /* The sphere scene at 12 x 12 for 2 s: the impact at 3.6 m/s may stretch the stiff cloth
       transiently, but no frame should exceed 25% edge strain (ARCSim: 10.7% worst at n = 16).
       Measured 11.1% (frame ~28) with the obstacle constraints of the solve and a frictionless
       collide phase for analytic obstacles; 57% before the collide phase stopped applying its
       position-level friction on top. */
    cloth_world *w = NULL;
    cloth_mesh m;
    int32_t piece, f;
    double worst = 0;
    int ok = sphere_drop_world(12, &w, &m, &piece);
    for (f = 0; f < 120 && ok; ++f) {
        double strain;
        ok = cloth_world_step(w, (cloth_real)1 / 60, NULL) == CLOTH_SUCCESS;
        strain = (double)cloth_world_max_edge_strain(w, piece);
        if (strain > worst) worst = strain;
    }
    printf("    sphere 12: worst frame's max edge strain %.4f (required below 0.25)\n", worst);
    cloth_world_destroy(w);
    cloth_mesh_free(&m);
    ENSURE(ok);
    ENSURE(worst < 0.25);
}

/* The 32 x 32 sphere drop dropped from 1 + lift metres, 2 s: over its last 40 frames (the cloth
   lying draped) the fastest vertex, the worst edge strain and the steps redone for a violent
   substep; 0 when a step failed. */
static int drape_rest(double lift, double *fastest, double *worst, int32_t *redos)
{
    cloth_world *w = NULL;
    cloth_mesh m;
    int32_t piece, f, i;
    int ok = drape_scene_world(cloth_default_world_def(), 32, lift, &w, &m, &piece);
    *fastest = *worst = 0;
    *redos = 0;
    for (f = 0; f < 120 && ok; ++f) {
        cloth_step_stats st;
        ok = cloth_world_step(w, (cloth_real)1 / 60, &st) == CLOTH_SUCCESS;
        if (ok && f >= 80) {
            const cloth_real *v = cloth_world_velocities(w, piece);
            double strain = (double)cloth_world_max_edge_strain(w, piece);
            for (i = 0; i < m.vertex_count; ++i) {
                double speed = sqrt((double)v[3 * i] * v[3 * i] + (double)v[3 * i + 1] * v[3 * i + 1] + (double)v[3 * i + 2] * v[3 * i + 2]);
                if (speed > *fastest) *fastest = speed;
            }
            if (strain > *worst) *worst = strain;
            *redos += st.substep_redos;
        }
    }
    cloth_world_destroy(w);
    cloth_mesh_free(&m);
    return ok;
}

TEST(a_cloth_draped_on_a_sphere_comes_to_rest)
{
    /* The sphere scene at 32 x 32 for 2 s. In the last 40 frames the cloth lies draped: no
       vertex faster than 0.5 m/s, every edge within 5% of its rest length, and no step redone
       for a violent substep. Before the linearized integrator stopped re-linearizing between
       its obstacle re-solves (and before the membrane's compressed directions kept a
       stiffness), vertices released from the sphere were thrown off it every few frames:
       1.25 m/s, 12.7% strain and 5 redone steps in those frames; measured after: 0.26 m/s,
       2.9%, 0. The scene is chaotic and these bounds hold on most of its paths, not all:
       over 48 paths with the drop height raised by k 1e-4 m (bench/drape.c, k = 0 this one)
       37 stay within them (resting strain: median 3.8%, worst 9.5%), 32 before no release
       was decided into the last obstacle solve (4.6%, 18.6%; 2026-11-22); the known failure
       a_cloth_draped_on_a_sphere_comes_to_rest_on_every_path asks it of 8 more. */
    double fastest, worst;
    int32_t redos;
    int ok = drape_rest(0, &fastest, &worst, &redos);
    printf("    sphere 32, frames 80-119: fastest vertex %.3f m/s, worst strain %.4f, %d steps redone\n", fastest, worst, (int)redos);
    ENSURE(ok);
    ENSURE(fastest < 0.5);
    ENSURE(worst < 0.05);
    ENSURE(redos == 0);
}

/* The same bounds on the paths k = 1 .. 8 (the drop height raised by k 1e-4 m): the rest
   should not depend on a tenth of a millimetre. It did until vertices lying a millimetre
   above the layer stopped being held on their inertial target (def.obstacle_hold_touching_only),
   pulled onto the layer and released as adhesive: paths 2, 4 and 5 ended outside (0.51 m/s
   and 6.3%; 5.1%; 5.5%), and before releases were kept out of the last obstacle solve paths 1,
   5, 6 and 7 (0.58 m/s and 5.6%; 0.92 m/s and 10.9%; 6.6%; 5.4%). Now all 8 rest within them
   (worst strain 2.5%; README, "Holding what touches"). */
TEST(a_cloth_draped_on_a_sphere_comes_to_rest_on_every_path)
{
    int k, within = 0;
    for (k = 1; k <= 8; ++k) {
        double fastest, worst;
        int32_t redos;
        int ok = drape_rest(1e-4 * k, &fastest, &worst, &redos);
        printf("    path %d: fastest vertex %.3f m/s, worst strain %.4f, %d steps redone\n", k, fastest, worst, (int)redos);
        within += ok && fastest < 0.5 && worst < 0.05 && redos == 0;
    }
    ENSURE(within == 8);
}

const test_case physics_tests[] = {
    { "a_cloth_dropped_on_a_sphere_never_overstretches", a_cloth_dropped_on_a_sphere_never_overstretches },
    { "a_cloth_draped_on_a_sphere_comes_to_rest", a_cloth_draped_on_a_sphere_comes_to_rest },
    { "integrators_converge_in_dt_at_their_order", integrators_converge_in_dt_at_their_order },
    { "static_sag_converges_under_mesh_refinement", static_sag_converges_under_mesh_refinement },
    { "a_hanging_strip_is_a_catenary", a_hanging_strip_is_a_catenary },
    { "extreme_parameters_never_blow_up", extreme_parameters_never_blow_up },
    { "a_pure_end_moment_bends_a_strip_uniformly", a_pure_end_moment_bends_a_strip_uniformly },
    { "a_cantilever_matches_the_heavy_elastica", a_cantilever_matches_the_heavy_elastica },
    { NULL, NULL }
};

/* SLOW TESTS, too slow under the sanitizers (the drape on 8 paths: about 9 minutes): `make
   test` builds them apart, optimized and without sanitizers (build/physics_slow, under a
   minute). */
const test_case physics_slow_tests[] = {
    { "a_cloth_draped_on_a_sphere_comes_to_rest_on_every_path", a_cloth_draped_on_a_sphere_comes_to_rest_on_every_path },
    { NULL, NULL }
};

/* KNOWN FAILURES, run by `make known-failures` and not by `make test` (README, "Known
   failures"). They assert the project's requirement unchanged and fail today; none in this
   module now. (The cantilever left them when the quadratic bending learned clamps: the clamp
   line's vertex had a full curvature cell reaching dx/2 behind the clamp line, so the strip
   bent as if dx/2 longer, +5.0% in the tip angle at 30 cells; with the half cell on the free
   side, +0.1%. The sphere drop left them when obstacles became constraints of the solve; the
   drape on 8 paths when a substep held only the vertices touching a layer on their inertial
   targets: 3 of 8 paths missed before, 0.51 m/s and 6.3%, 5.1%, 5.5%.) */
const test_case physics_known_failures_tests[] = {
    { NULL, NULL }
};
