/* seam.c - two panels sewn together by a seam.

   Two square panels, 0.5 m on a side, hang side by side with a 10 cm gap, each from one
   outer top corner. The left panel has 11 x 11 vertices, the right one 16 x 16: their facing
   edges do not have the same vertices. A seam joins those two edges, matching points by arc
   length, and pulls them together until the two panels hang as one 1 m wide cloth.

   What it teaches: several pieces in one world, seams between pieces (and along edges of
   different resolution), and measuring how far a seam has closed
   (cloth_world_seam_sewn_fraction), which is how a garment's sewing is followed.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -o build/examples/seam examples/seam.c -lm && ./build/examples/seam
   With --short it simulates less (as `make test` runs it). It exits with 1 when a check fails. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <string.h>

#define NA 11 /* left panel: vertices per side */
#define NB 16 /* right panel */

/* A vertical panel of n x n vertices, 0.5 m square, its left edge at x = left, its top edge
   at y = 1.5 (vertex (i, j) is j * n + i: i to the right, j downwards). */
static cloth_result panel(cloth_mesh *mesh, int32_t n, double left)
{
    int32_t i;
    cloth_result r = cloth_mesh_grid(mesh, n, n, 0.5, 0.5, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    for (i = 0; r == CLOTH_SUCCESS && i < mesh->vertex_count; ++i) {
        cloth_real *p = mesh->x + 3 * i;
        p[0] += (cloth_real)(left + 0.25);
        p[1] = (cloth_real)1.25 - p[2]; /* the grid's z (-0.25 at j = 0) becomes the height */
        p[2] = 0;
    }
    return r;
}

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0;
    int frames = quick ? 90 : 240, frame, failed = 0;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_world *world = NULL;
    cloth_mesh a, b;
    int32_t left, right, edge_a[NA], edge_b[NB], j;
    cloth_real before, after;
    cloth_result r;

    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    r = panel(&a, NA, -0.55);
    if (r == CLOTH_SUCCESS) r = panel(&b, NB, 0.05);
    if (r == CLOTH_SUCCESS) r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &a, &piece_def, &left);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &b, &piece_def, &right);
    /* Each panel hangs from its outer top corner. */
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(world, left, 0, NULL);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(world, right, NB - 1, NULL);

    /* The seam: the left panel's right edge (column NA - 1) and the right panel's left edge
       (column 0), both listed top to bottom. Each vertex of one edge is pulled to the point
       at the same fraction of the way along the other by a zero-length spring of stiffness
       k (N/m), both ways. cloth_world_add_seam pairs vertices one to one instead. The seam
       carries the panels' weight where they pull apart (near the top): with 50 N/m it stays
       centimetres open there, with 2000 N/m it closes to under 5 mm. */
    for (j = 0; j < NA; ++j) edge_a[j] = j * NA + NA - 1;
    for (j = 0; j < NB; ++j) edge_b[j] = j * NB;
    if (r == CLOTH_SUCCESS) r = cloth_world_add_seam_polyline(world, left, edge_a, NA, right, edge_b, NB, 2000);
    cloth_mesh_free(&a);
    cloth_mesh_free(&b);
    if (r != CLOTH_SUCCESS) { printf("FAILED: setup (%s)\n", cloth_result_string(r)); cloth_world_destroy(world); return 1; }

    /* The fraction of seam springs whose ends are within 5 mm: sewn. */
    before = cloth_world_seam_sewn_fraction(world, (cloth_real)0.005);
    for (frame = 0; frame < frames; ++frame) {
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), NULL);
        if (r != CLOTH_SUCCESS) { printf("FAILED: step %d (%s)\n", frame, cloth_result_string(r)); failed = 1; break; }
        if (frame % 30 == 29)
            printf("t = %.1f s: %.0f%% of the seam sewn (ends within 5 mm)\n", (frame + 1) / 60.0,
                   100 * (double)cloth_world_seam_sewn_fraction(world, (cloth_real)0.005));
    }
    after = cloth_world_seam_sewn_fraction(world, (cloth_real)0.005);

    /* Checks: nothing was sewn at the start (10 cm apart), all of it at the end. */
    if (!failed && before != 0) { printf("FAILED: the seam was sewn before any step\n"); failed = 1; }
    if (!failed && after < 1) { printf("FAILED: only %.0f%% of the seam is sewn\n", 100 * (double)after); failed = 1; }
    if (!failed) printf("ok: %d frames, the seam sewn from 0%% to %.0f%%\n", frames, 100 * (double)after);
    cloth_world_destroy(world);
    return failed;
}
