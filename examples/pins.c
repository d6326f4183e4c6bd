/* pins.c - a cloth hanging from pins, and a pin that moves.

   A 1 m x 1 m cloth of 21 x 21 vertices is held at two corners and falls under gravity; after
   one second the right-hand corner is carried 30 cm towards the left one, so the cloth
   sags between them. This is the standard "hang" scene of docs/scenes.md at a small size.

   What it teaches: the life of a world (def, create, add a piece, step, destroy), pins as
   exact constraints, moving a pin's target, and reading results back (positions, strain,
   energy). Every call that can fail returns a cloth_result; a failed step leaves the world
   exactly as it was.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -o build/examples/pins examples/pins.c -lm && ./build/examples/pins
   With --short it simulates less (as `make test` runs it). It exits with 1 when a check fails. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <math.h>
#include <stdio.h>
#include <string.h>

#define N 21 /* vertices per side */

/* Print what went wrong and return 1: every failure path of the example goes through here. */
static int fail(const char *what, cloth_result r)
{
    printf("FAILED: %s (%s)\n", what, cloth_result_string(r));
    return 1;
}

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0;
    int frames = quick ? 90 : 180, frame, failed = 0;
    cloth_world_def def = cloth_default_world_def(); /* gravity (0, -9.81, 0), implicit solver */
    cloth_piece_def piece_def = cloth_default_piece_def(); /* a woven cotton, 150 g/m^2 */
    cloth_world *world = NULL;
    cloth_mesh mesh;
    cloth_real left[3], right[3], kinetic, gravitational, elastic;
    const cloth_real *x;
    double worst_strain = 0;
    int32_t piece, i;
    cloth_result r;

    /* The mesh: a flat grid in the plane y = 0 (x and z in [-0.5, 0.5]); vertex (i, j) is
       number j * N + i. The grid also gets uv coordinates, which become the rest shape. */
    r = cloth_mesh_grid(&mesh, N, N, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) return fail("grid", r);
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1; /* lift it to y = 1 */

    /* The world copies the mesh, so ours can be freed right after. */
    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    cloth_mesh_free(&mesh);
    if (r != CLOTH_SUCCESS) { cloth_world_destroy(world); return fail("setup", r); }

    /* Pin the two corners of the edge z = -0.5: vertices 0 and N - 1. NULL means "where it
       is now". A pin is exact: the solver removes those vertices' motion from its unknowns. */
    r = cloth_world_pin(world, piece, 0, NULL);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(world, piece, N - 1, NULL);
    if (r != CLOTH_SUCCESS) { cloth_world_destroy(world); return fail("pins", r); }
    x = cloth_world_positions(world, piece);
    memcpy(left, x, sizeof left);
    memcpy(right, x + 3 * (N - 1), sizeof right);

    for (frame = 0; frame < frames; ++frame) {
        double strain;
        /* From the second second on, carry the right corner 1 cm a frame towards the left
           one, 30 cm in all. The vertex reaches its new target at the end of the step. */
        if (frame >= 60 && frame < 90) {
            right[0] -= (cloth_real)0.01;
            r = cloth_world_set_pin_target(world, piece, N - 1, right);
            if (r != CLOTH_SUCCESS) { failed = fail("moving the pin", r); break; }
        }
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), NULL);
        if (r != CLOTH_SUCCESS) { failed = fail("step", r); break; }
        strain = (double)cloth_world_max_edge_strain(world, piece);
        if (strain > worst_strain) worst_strain = strain;
        if (frame % 30 == 29) {
            x = cloth_world_positions(world, piece); /* valid until the world changes */
            cloth_world_energy(world, &kinetic, &gravitational, &elastic);
            printf("t = %.1f s: free corner at y = %.3f m, max edge strain %.2f%%, energy %.3f J kinetic, %.4f J elastic\n",
                   (frame + 1) / 60.0, (double)x[3 * (N * N - 1) + 1], 100 * strain, (double)kinetic, (double)elastic);
        }
    }

    /* Checks: the pins held exactly where they were put; the cloth hangs below them; no
       edge stretched beyond 15% (woven cotton under its own weight stretches a few %). */
    x = cloth_world_positions(world, piece);
    if (!failed && memcmp(x, left, sizeof left) != 0) failed = fail("the fixed pin moved", CLOTH_SUCCESS);
    if (!failed && memcmp(x + 3 * (N - 1), right, sizeof right) != 0) failed = fail("the moved pin is off its target", CLOTH_SUCCESS);
    if (!failed && !(x[3 * (N * N - 1) + 1] < (cloth_real)0.5)) failed = fail("the free corner did not fall", CLOTH_SUCCESS);
    if (!failed && !(worst_strain < 0.15)) failed = fail("an edge stretched by more than 15%", CLOTH_SUCCESS);
    if (!failed)
        printf("ok: %d frames, the pins exact, worst edge strain %.2f%%, pins %.2f m apart\n", frames, 100 * worst_strain,
               (double)(right[0] - left[0]));
    cloth_world_destroy(world);
    return failed;
}
