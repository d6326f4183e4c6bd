/* materials.c - materials from the presets, and Peirce's cantilever rule.

   First it lists the library's material presets: weight, stretch and bending stiffness, and
   the bending length c = (B / (w g))^(1/3), the length at which a fabric's own weight bends
   it noticeably. Then it runs the ASTM D1388 cantilever test in the simulator for silk and
   for a measured 11 oz denim: a strip clamped flat on a ledge, pushed out by an overhang l,
   sags under its weight. Peirce's rule says that at l = 2c the line from the ledge to the
   tip falls 41.5 degrees, whatever the fabric; the program checks that the simulated strips
   do so, and compares the two fabrics on a strip of the same length.

   What it teaches: presets and material fields (SI units), the Peirce functions
   (cloth_bending_length, cloth_cantilever_overhang), the bending models of a piece, pins as a
   clamp, and letting a world come to rest with large implicit steps.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -o build/examples/materials examples/materials.c -lm
       ./build/examples/materials      (--short is accepted; the run is short anyway)
   It exits with 1 when a check fails. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#define CELLS 20 /* cells along the overhang */

/* The chord angle (degrees below the horizontal, from the ledge to the tip) of a strip of
   `material` with overhang l (m), at rest; -1 when something fails. The strip is a grid of
   3 rows along x (the warp), square cells; the columns x = -dx and x = 0 are pinned: two
   pinned rows of faces clamp the strip flat on the ledge, its free part starting at x = 0. */
static double cantilever(const cloth_material *material, double l)
{
    const int32_t nx = CELLS + 2, ny = 3;
    double dx = l / CELLS, angle = -1;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_world *world = NULL;
    cloth_mesh strip;
    int32_t piece, i, step;
    if (cloth_mesh_grid(&strip, nx, ny, l + dx, 2 * dx, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return -1;
    for (i = 0; i < strip.vertex_count; ++i) strip.x[3 * i] += (cloth_real)((l + dx) / 2 - dx);
    piece_def.material = *material;
    /* The quadratic bending model: a constant, exact bending Hessian, accurate on grids. */
    piece_def.bending_model = CLOTH_BENDING_QUADRATIC;
    piece_def.drag = (cloth_real)0.02; /* a little air drag helps it settle */
    def.cg.tolerance = (cloth_real)1e-3;
    if (cloth_world_create(&world, &def) == CLOTH_SUCCESS && cloth_world_add_piece(world, &strip, &piece_def, &piece) == CLOTH_SUCCESS) {
        int ok = 1;
        for (i = 0; i < ny && ok; ++i)
            ok = cloth_world_pin(world, piece, i * nx, NULL) == CLOTH_SUCCESS && cloth_world_pin(world, piece, i * nx + 1, NULL) == CLOTH_SUCCESS;
        /* Implicit steps of 0.2 s until every vertex is slower than 1e-7 m/s (at most 400). */
        for (step = 0; ok && step < 400; ++step) {
            const cloth_real *v;
            double fastest = 0;
            if (cloth_world_step(world, (cloth_real)0.2, NULL) != CLOTH_SUCCESS) { ok = 0; break; }
            v = cloth_world_velocities(world, piece);
            for (i = 0; i < 3 * strip.vertex_count; ++i) if (fabs((double)v[i]) > fastest) fastest = fabs((double)v[i]);
            if (fastest < 1e-7) break;
        }
        if (ok && step < 400) { /* the middle row: the clamp line's vertex and the tip */
            const cloth_real *x = cloth_world_positions(world, piece), *edge = x + 3 * (nx + 1), *tip = x + 3 * (2 * nx - 1);
            angle = atan2((double)(edge[1] - tip[1]), (double)(tip[0] - edge[0])) * 180 / 3.14159265358979;
        }
    }
    cloth_world_destroy(world);
    cloth_mesh_free(&strip);
    return angle;
}

int main(void)
{
    static const char *const compared[2] = { "silk", "denim_11oz" };
    double same_length[2];
    int32_t i, failed = 0;

    printf("%-11s %8s %9s %9s %10s %9s\n", "preset", "kg/m^2", "warp N/m", "weft N/m", "bend N m", "c (cm)");
    for (i = 0; i < cloth_material_preset_count(); ++i) {
        cloth_material m;
        cloth_real c = 0;
        cloth_material_preset_at(i, &m);
        cloth_bending_length(m.bend_warp, m.areal_density, (cloth_real)9.81, &c);
        printf("%-11s %8.3f %9.0f %9.0f %10.3g %9.2f\n", cloth_material_preset_name(i), (double)m.areal_density,
               (double)m.stretch_warp, (double)m.stretch_weft, (double)m.bend_warp, 100 * (double)c);
    }

    for (i = 0; i < 2; ++i) {
        cloth_material m;
        cloth_real overhang = 0;
        double chord;
        if (cloth_material_preset(compared[i], &m) != CLOTH_SUCCESS ||
            cloth_cantilever_overhang(m.bend_warp, m.areal_density, (cloth_real)9.81, &overhang) != CLOTH_SUCCESS) {
            printf("FAILED: preset %s\n", compared[i]);
            return 1;
        }
        /* The grid's diagonals bend with both the warp's and the weft's stiffness: give the
           strip the warp's in both directions, so that c means one thing. */
        m.bend_weft = m.bend_warp;
        chord = cantilever(&m, (double)overhang);
        same_length[i] = cantilever(&m, 0.06);
        printf("%s: overhang 2c = %.1f mm, chord %.2f degrees (Peirce: 41.5); a 6 cm strip: %.1f degrees\n", compared[i],
               1000 * (double)overhang, chord, same_length[i]);
        if (!(fabs(chord - 41.5) < 1.5)) { printf("FAILED: %s does not follow Peirce's rule\n", compared[i]); failed = 1; }
    }
    /* The same 6 cm strip droops more when the bending length is shorter: here the fitted
       silk preset is the stiffer for its weight (cloth.h's material notes say why). */
    if (!(same_length[0] > 0 && same_length[1] > 0 && same_length[1] > same_length[0])) {
        printf("FAILED: the strip with the shorter bending length does not droop more\n");
        failed = 1;
    }
    if (!failed) printf("ok\n");
    return failed;
}
