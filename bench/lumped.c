/* lumped.c - what lumped hinges (the piece def's bending_lumped) cost in accuracy. Two
   measurements, each with bending_lumped 0 and 1, printed as CSV rows:

     path N FRAMES [q]  the hang scene (bench/dynamics.c's: 1 m cloth of N x N vertices, two
                     corners pinned, 0.1 kg/m^2, one linearized backward Euler step per 1/60 s
                     frame, multigrid CG at 1e-6) run four ways: exact and lumped hinges, one
                     and two steps per frame. Prints the largest distance of any vertex, over
                     all frames, between exact and lumped (one step; two steps), and between one
                     and two exact steps: how far lumping moves the path against how far
                     halving the time step moves it. q: the quadratic bending energy instead
                     of the dihedral one (the world's default).
     spin N          a free N x N cloth without gravity turning about an axis in its plane
                     (x) and about its normal (y) at 2 rad/s, 1 s of 1/60 s steps (CG 1e-8):
                     the kinetic energy left at the end over the energy at the start. The
                     linearized step damps such a turn by itself; lumped hinges damp a turn
                     about the hinge edges (x) more, and leave the turn in the plane (y) alone.
     cantilever      where lumping fails: tests/test_physics.c's cantilever (a strip of B = 1e-5
                     N m, 0.2 kg/m^2, 30 cells of 1.15 mm over the overhang l = 2 (B / (w g))^(1/3),
                     the quadratic or the dihedral energy) settling by steps of 0.2 s with air
                     drag: the steps until every vertex is slower than 1e-7 m/s (at most 400) and
                     the tip's drop then, exact and lumped. dt^2 B / (w l^4) is about 1e6 here:
                     the lumped matrix stiffens the strip's slow bending so much that it creeps.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/lumped bench/lumped.c -lm
       ./build/bench/lumped path 64 60
       ./build/bench/lumped spin 64
       ./build/bench/lumped cantilever */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void fail(const char *what, cloth_result r)
{
    fprintf(stderr, "lumped: %s: %s\n", what, cloth_result_string(r));
    exit(1);
}

static cloth_bending_model path_model = CLOTH_BENDING_DIHEDRAL;

static cloth_world *make(int32_t n, int lumped, int32_t substeps, double tolerance, int hang)
{
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = cloth_default_piece_def();
    cloth_world *w = NULL;
    cloth_mesh m;
    cloth_result r;
    int32_t i;
    d.substeps = substeps;
    d.cg.tolerance = (cloth_real)tolerance;
    d.cg.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
    if (!hang) d.gravity[1] = 0;
    p.material.areal_density = (cloth_real)0.1;
    p.bending_lumped = lumped;
    p.bending_model = hang ? path_model : CLOTH_BENDING_DIHEDRAL;
    r = cloth_mesh_grid(&m, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) fail("grid", r);
    if (hang)
        for (i = 0; i < m.vertex_count; ++i) m.x[3 * i + 1] = 1;
    if ((r = cloth_world_create(&w, &d)) != CLOTH_SUCCESS) fail("world", r);
    if ((r = cloth_world_add_piece(w, &m, &p, NULL)) != CLOTH_SUCCESS) fail("piece", r);
    if (hang && ((r = cloth_world_pin(w, 0, 0, NULL)) != CLOTH_SUCCESS || (r = cloth_world_pin(w, 0, n - 1, NULL)) != CLOTH_SUCCESS))
        fail("pin", r);
    cloth_mesh_free(&m);
    return w;
}

/* Every frame's positions of the hang scene. */
static cloth_real *hang_path(int32_t n, int32_t frames, int lumped, int32_t substeps)
{
    cloth_world *w = make(n, lumped, substeps, 1e-6, 1);
    size_t count = 3 * (size_t)n * (size_t)n;
    cloth_real *out = (cloth_real *)malloc(count * (size_t)frames * sizeof *out);
    int32_t f;
    if (!out) fail("memory", CLOTH_ERROR_OUT_OF_MEMORY);
    for (f = 0; f < frames; ++f) {
        cloth_result r = cloth_world_step(w, (cloth_real)1 / 60, NULL);
        if (r != CLOTH_SUCCESS) fail("step", r);
        memcpy(out + count * (size_t)f, cloth_world_positions(w, 0), count * sizeof *out);
    }
    cloth_world_destroy(w);
    return out;
}

static double largest_distance(const cloth_real *a, const cloth_real *b, size_t vertices)
{
    double worst = 0;
    size_t i;
    for (i = 0; i < vertices; ++i) {
        double dx = (double)a[3 * i] - b[3 * i], dy = (double)a[3 * i + 1] - b[3 * i + 1], dz = (double)a[3 * i + 2] - b[3 * i + 2];
        double d = sqrt(dx * dx + dy * dy + dz * dz);
        if (d > worst) worst = d;
    }
    return worst;
}

static double spin(int32_t n, int lumped, int axis)
{
    cloth_world *w = make(n, lumped, 1, 1e-8, 0);
    const cloth_real *x = cloth_world_positions(w, 0);
    cloth_real *v = (cloth_real *)malloc(3 * (size_t)n * (size_t)n * sizeof *v), k0, k1, g, e;
    cloth_result r;
    int32_t i, f;
    if (!v) fail("memory", CLOTH_ERROR_OUT_OF_MEMORY);
    for (i = 0; i < n * n; ++i) { /* omega x r, |omega| = 2 rad/s */
        const cloth_real *xi = x + 3 * i;
        v[3 * i] = axis ? 2 * xi[2] : 0;
        v[3 * i + 1] = axis ? 0 : 2 * xi[2];
        v[3 * i + 2] = axis ? -2 * xi[0] : -2 * xi[1];
    }
    if ((r = cloth_world_set_velocities(w, 0, v)) != CLOTH_SUCCESS) fail("velocities", r);
    cloth_world_energy(w, &k0, &g, &e);
    for (f = 0; f < 60; ++f)
        if ((r = cloth_world_step(w, (cloth_real)1 / 60, NULL)) != CLOTH_SUCCESS) fail("step", r);
    cloth_world_energy(w, &k1, &g, &e);
    cloth_world_destroy(w);
    free(v);
    return (double)k1 / (double)k0;
}

/* The cantilever: steps to rest (-1: not within 400) and the tip's drop (m) after them. */
static void cantilever(cloth_bending_model model, int lumped, int32_t *steps, double *drop)
{
    const double b = 1e-5, density = 0.2, l = 2 * cbrt(b / (density * 9.81)), dx = l / 30;
    const int32_t nx = 32, ny = 3;
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = cloth_default_piece_def();
    cloth_world *w = NULL;
    cloth_mesh m;
    cloth_result r;
    int32_t i, j, s;
    d.cg.tolerance = (cloth_real)1e-3;
    d.cg.max_iterations = 10000;
    p.material.stretch_warp = p.material.stretch_weft = (cloth_real)1e3;
    p.material.stretch_coupling = 0;
    p.material.shear = (cloth_real)500;
    p.material.areal_density = (cloth_real)density;
    p.material.bend_warp = p.material.bend_weft = (cloth_real)b;
    p.bending_model = model;
    p.bending_lumped = lumped;
    p.drag = (cloth_real)0.02;
    r = cloth_mesh_grid(&m, nx, ny, (cloth_real)(l + dx), (cloth_real)(2 * dx), CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) fail("grid", r);
    for (i = 0; i < m.vertex_count; ++i) m.x[3 * i] += (cloth_real)((l + dx) / 2 - dx); /* column 1 at x = 0 */
    if ((r = cloth_world_create(&w, &d)) != CLOTH_SUCCESS) fail("world", r);
    if ((r = cloth_world_add_piece(w, &m, &p, NULL)) != CLOTH_SUCCESS) fail("piece", r);
    for (j = 0; j < ny; ++j) /* the clamp: the first two columns */
        if ((r = cloth_world_pin(w, 0, j * nx, NULL)) != CLOTH_SUCCESS || (r = cloth_world_pin(w, 0, j * nx + 1, NULL)) != CLOTH_SUCCESS)
            fail("pin", r);
    *steps = -1;
    for (s = 1; s <= 400; ++s) {
        const cloth_real *v;
        double fastest = 0;
        if ((r = cloth_world_step(w, (cloth_real)0.2, NULL)) != CLOTH_SUCCESS) fail("step", r);
        v = cloth_world_velocities(w, 0);
        for (i = 0; i < 3 * m.vertex_count; ++i) fastest = fmax(fastest, fabs((double)v[i]));
        if (fastest < 1e-7) { *steps = s; break; }
    }
    *drop = -(double)cloth_world_positions(w, 0)[3 * (nx + nx - 1) + 1];
    cloth_mesh_free(&m);
    cloth_world_destroy(w);
}

int main(int argc, char **argv)
{
    int32_t n = argc > 2 ? atoi(argv[2]) : 0;
    if (argc >= 4 && strcmp(argv[1], "path") == 0 && n >= 2) {
        int32_t frames = atoi(argv[3]), f;
        cloth_real *exact, *lumped, *exact2, *lumped2;
        double d_lumped = 0, d_lumped2 = 0, d_step = 0;
        size_t count = 3 * (size_t)n * (size_t)n;
        if (frames < 1) return 2;
        if (argc > 4 && strcmp(argv[4], "q") == 0) path_model = CLOTH_BENDING_QUADRATIC;
        exact = hang_path(n, frames, 0, 1);
        lumped = hang_path(n, frames, 1, 1);
        exact2 = hang_path(n, frames, 0, 2);
        lumped2 = hang_path(n, frames, 1, 2);
        for (f = 0; f < frames; ++f) {
            size_t o = count * (size_t)f;
            d_lumped = fmax(d_lumped, largest_distance(exact + o, lumped + o, (size_t)n * n));
            d_lumped2 = fmax(d_lumped2, largest_distance(exact2 + o, lumped2 + o, (size_t)n * n));
            d_step = fmax(d_step, largest_distance(exact + o, exact2 + o, (size_t)n * n));
        }
        printf("bending,n,frames,lumped_vs_exact_m,lumped_vs_exact_2_steps_m,one_vs_two_steps_m\n%s,%d,%d,%.4g,%.4g,%.4g\n",
               path_model == CLOTH_BENDING_QUADRATIC ? "quadratic" : "dihedral", n, frames, d_lumped, d_lumped2, d_step);
        free(exact); free(lumped); free(exact2); free(lumped2);
        return 0;
    }
    if (argc >= 3 && strcmp(argv[1], "spin") == 0 && n >= 2) {
        printf("n,kinetic_left_exact_x,kinetic_left_lumped_x,kinetic_left_exact_y,kinetic_left_lumped_y\n");
        printf("%d,%.4f,%.4f,%.4f,%.4f\n", n, spin(n, 0, 0), spin(n, 1, 0), spin(n, 0, 1), spin(n, 1, 1));
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "cantilever") == 0) {
        int model, lumped;
        printf("bending,lumped,steps_to_rest,tip_drop_m\n");
        for (model = 0; model < 2; ++model)
            for (lumped = 0; lumped < 2; ++lumped) {
                int32_t steps;
                double drop;
                cantilever(model ? CLOTH_BENDING_DIHEDRAL : CLOTH_BENDING_QUADRATIC, lumped, &steps, &drop);
                printf("%s,%d,%d,%.5f\n", model ? "dihedral" : "quadratic", lumped, (int)steps, drop);
            }
        return 0;
    }
    fprintf(stderr, "usage: lumped path N FRAMES | lumped spin N | lumped cantilever\n");
    return 2;
}
