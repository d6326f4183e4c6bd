/* flag.c - a flag on a pole in gusty wind.

   A 1.5 m x 1 m flag of 30 x 20 vertices hangs from a vertical pole (its whole left edge is
   pinned) in a wind of 8 m/s along +x with random gusts (2 m/s standard deviation on each
   axis, changing over about half a second). It lifts off the pole and streams downwind,
   fluttering.

   What it teaches: turning a generated grid into a vertical sheet, pinning a whole edge,
   the world's wind (mean, gusts, their seed) and the pieces' aerodynamic drag; the gusts
   come from the library's own seeded generator, so a run is repeatable on any machine.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -o build/examples/flag examples/flag.c -lm && ./build/examples/flag
   With --short it simulates less (as `make test` runs it). It exits with 1 when a check fails. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#define NX 30 /* vertices along the flag (x) */
#define NY 20 /* vertices up the pole (y) */

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0;
    int frames = quick ? 60 : 240, frame, failed = 0;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_world *world = NULL;
    cloth_mesh mesh;
    double reach = 0, lo = 1e9, hi = -1e9;
    int32_t piece, i, j;
    cloth_result r;

    /* cloth_mesh_grid makes a flat sheet in the plane y = 0 (x across, z deep). Stand it up
       across the wind: the grid's x becomes z, from the pole (z = 0) to 1.5 m, and its z the
       height y, from 1 m to 2 m. The wind (along +x) first hits it face on, then swings it
       round. Only positions change; the uv coordinates stay the flat rest shape. */
    r = cloth_mesh_grid(&mesh, NX, NY, 1.5, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: grid (%s)\n", cloth_result_string(r)); return 1; }
    for (i = 0; i < mesh.vertex_count; ++i) {
        cloth_real *p = mesh.x + 3 * i;
        p[1] = (cloth_real)1.5 - p[2];
        p[2] = p[0] + (cloth_real)0.75;
        p[0] = 0;
    }

    /* The wind is the world's: a mean velocity plus gusts, a random process with the given
       deviation and correlation time, from a seeded generator. Each face of a piece feels a
       drag from the wind's velocity relative to it, along its normal (piece def:
       wind = 1, drag_coefficient 1 by default). */
    def.wind[0] = 8;
    def.gust_strength = 2;
    def.gust_time = (cloth_real)0.5;
    def.seed = 7;
    piece_def.material.areal_density = (cloth_real)0.12; /* a light polyester flag */

    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    cloth_mesh_free(&mesh);
    /* The pole: every vertex of the grid's column i = 0 (index j * NX), now at z = 0. */
    for (j = 0; j < NY && r == CLOTH_SUCCESS; ++j) r = cloth_world_pin(world, piece, j * NX, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: setup (%s)\n", cloth_result_string(r)); cloth_world_destroy(world); return 1; }

    for (frame = 0; frame < frames; ++frame) {
        const cloth_real *x;
        double sum = 0;
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), NULL);
        if (r != CLOTH_SUCCESS) { printf("FAILED: step %d (%s)\n", frame, cloth_result_string(r)); failed = 1; break; }
        /* How far downwind the free edge (i = NX - 1) reaches, on average over its vertices,
           and how high its top corner goes over the last half of the run (the flutter). */
        x = cloth_world_positions(world, piece);
        for (j = 0; j < NY; ++j) sum += (double)x[3 * (j * NX + NX - 1)];
        reach = sum / NY;
        if (frame >= frames / 2) {
            double y = (double)x[3 * ((NY - 1) * NX + NX - 1) + 1];
            if (y < lo) lo = y;
            if (y > hi) hi = y;
        }
        if (frame % 30 == 29)
            printf("t = %.1f s: free edge %.2f m downwind of the pole, max edge strain %.2f%%\n", (frame + 1) / 60.0, reach,
                   100 * (double)cloth_world_max_edge_strain(world, piece));
    }

    /* Checks: the flag swung round and streams out (its free edge, which starts at x = 0, more
       than 1 m downwind), it flutters (its corner moves), and no edge stretched more than
       20%. */
    if (!failed && !(reach > 1.0)) { printf("FAILED: the flag does not stream out (%.2f m)\n", reach); failed = 1; }
    if (!failed && !(hi - lo > 0.01)) { printf("FAILED: the flag does not flutter\n"); failed = 1; }
    if (!failed && !(cloth_world_max_edge_strain(world, piece) < (cloth_real)0.2)) {
        printf("FAILED: the flag is overstretched\n");
        failed = 1;
    }
    if (!failed)
        printf("ok: %d frames, the free edge %.2f m downwind, its top corner moving over %.1f cm\n", frames, reach,
               100 * (hi - lo));
    cloth_world_destroy(world);
    return failed;
}
