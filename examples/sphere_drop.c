/* sphere_drop.c - a cloth dropped onto a sphere, folding onto itself.

   A 1 m x 1 m cloth of 24 x 24 vertices falls flat from y = 1 onto a fixed ball of radius
   0.3 m (Coulomb friction 0.5) and drapes over it; where its folds touch, self-collision
   keeps the cloth from passing through itself. This is the "sphere" scene of
   docs/scenes.md at a small size (`make demo` runs it at 32 x 32 and draws it).

   What it teaches: obstacles (shape, pose, thickness, friction), turning self-collision
   on, the step statistics (impacts, substeps), and checking a result apart from the library:
   every frame, every vertex is measured against the sphere with
   cloth_world_obstacle_distance.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -o build/examples/sphere_drop examples/sphere_drop.c -lm
       ./build/examples/sphere_drop            (--short: fewer frames, as `make test` runs it)
   It exits with 1 when a check fails. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <string.h>

#define N 24 /* vertices per side */

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0;
    int frames = quick ? 60 : 180, frame, failed = 0;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_obstacle_def ball = cloth_default_obstacle_def();
    cloth_world *world = NULL;
    cloth_mesh mesh;
    int32_t piece, sphere, i, impacts = 0, touches = 0, redone = 0;
    double deepest = 0, centre_y = 0;
    cloth_result r;

    r = cloth_mesh_grid(&mesh, N, N, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: grid (%s)\n", cloth_result_string(r)); return 1; }
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1;

    /* Self-collision is off by default: it costs a collision pass every step. With it on,
       the world keeps every pair of non-neighbouring triangles at least collision_thickness
       (1 mm) apart, and no triangle passes through another. */
    def.self_collision = 1;
    piece_def.material.areal_density = (cloth_real)0.1; /* a light cloth, 100 g/m^2 */

    /* A sphere obstacle: its shape is described in its own frame (centred at the origin) and
       placed by its pose (the identity here). The cloth keeps `thickness` (1 mm) away from
       it; friction_static and friction_kinetic are Coulomb's coefficients. */
    ball.shape = CLOTH_OBSTACLE_SPHERE;
    ball.radius = (cloth_real)0.3;
    ball.friction_static = ball.friction_kinetic = (cloth_real)0.5;

    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(world, &ball, &sphere);
    cloth_mesh_free(&mesh);
    if (r != CLOTH_SUCCESS) { printf("FAILED: setup (%s)\n", cloth_result_string(r)); cloth_world_destroy(world); return 1; }

    for (frame = 0; frame < frames && !failed; ++frame) {
        cloth_step_stats stats;
        const cloth_real *x;
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), &stats);
        if (r != CLOTH_SUCCESS) {
            /* The world is exactly as before the call; a program could retry with smaller
               steps. Here it is a failed check. */
            printf("FAILED: step %d (%s)\n", frame, cloth_result_string(r));
            failed = 1;
            break;
        }
        impacts += stats.impacts;                 /* contacts the collision pass resolved */
        touches += stats.obstacle_constraints     /* vertices the solver held on the sphere */
                   + stats.obstacle_contacts;     /* and those the collision pass pushed out */
        redone += stats.substep_redos;            /* steps redone with more substeps */
        /* Our own check, apart from the library's contact code: the signed distance of every
           vertex to the sphere (negative inside). */
        x = cloth_world_positions(world, piece);
        for (i = 0; i < N * N; ++i) {
            double d = (double)cloth_world_obstacle_distance(world, sphere, x + 3 * i);
            if (-d > deepest) deepest = -d;
        }
        centre_y = (double)x[3 * (N / 2 * N + N / 2) + 1];
        if (frame % 30 == 29)
            printf("t = %.1f s: cloth centre at y = %.3f m, max edge strain %.2f%%, %d impacts so far, %d substep redos\n",
                   (frame + 1) / 60.0, centre_y, 100 * (double)cloth_world_max_edge_strain(world, piece), (int)impacts,
                   (int)redone);
    }

    /* Checks: no vertex ever entered the sphere; the centre of the cloth came to lie on the
       top of the sphere (y = radius + thickness = 0.301 m, give or take a centimetre); the
       cloth did touch the sphere. */
    if (!failed && deepest > 0) { printf("FAILED: a vertex went %.3g m into the sphere\n", deepest); failed = 1; }
    if (!failed && !(centre_y > 0.29 && centre_y < 0.31)) {
        printf("FAILED: the cloth's centre is at y = %.3f m, not on the sphere\n", centre_y);
        failed = 1;
    }
    if (!failed && touches == 0) { printf("FAILED: nothing touched the sphere\n"); failed = 1; }
    if (!failed) printf("ok: %d frames, no vertex inside the sphere, the cloth rests on it\n", frames);
    cloth_world_destroy(world);
    return failed;
}
