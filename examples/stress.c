/* stress.c - cloth crumpling in a funnel, checked exactly for intersections every frame.

   A 1 m x 1 m cloth of 20 x 20 vertices falls from y = 1 into an open square funnel (a
   pyramid standing on its apex: a 4-triangle mesh obstacle, 0.8 m across at y = 0.6) and
   crumples into it, folding onto itself many times: the "funnel" scene of docs/scenes.md.
   After every frame an exact triangle-triangle test that shares no code with cloth.h
   (tests/exact_tritri.h, exact arithmetic, no tolerance) counts cloth triangles that cross
   each other or the funnel's walls. A correct simulation keeps that count at zero.

   What it teaches: triangle-mesh obstacles, self-collision under stress, the step statistics
   of the collide phase, and how to check a contact simulation from the outside.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -ffp-contract=off -o build/examples/stress examples/stress.c -lm
       ./build/examples/stress     (--short: fewer frames, as `make test` runs it)
   It exits with 1 when a step fails or a check finds an intersection. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "../tests/exact_tritri.h"
#include <stdio.h>
#include <string.h>

#define N 20

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0;
    int frames = quick ? 90 : 180, frame, failed = 0;
    /* The funnel: apex at the origin, the four top corners at y = 0.6; its triangles face
       inwards (counter-clockwise seen from inside), which is the side the cloth stays on. */
    static const cloth_real funnel_x[15] = { 0, 0, 0, -0.4, 0.6, -0.4, 0.4, 0.6, -0.4, 0.4, 0.6, 0.4, -0.4, 0.6, 0.4 };
    static const int32_t funnel_tri[12] = { 0, 2, 1, 0, 3, 2, 0, 4, 3, 0, 1, 4 };
    static double funnel_xd[15];
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_obstacle_def funnel = cloth_default_obstacle_def();
    cloth_world *world = NULL;
    cloth_mesh mesh;
    exact_mesh check[2];
    long impacts = 0;
    int32_t piece, i;
    cloth_result r;

    r = cloth_mesh_grid(&mesh, N, N, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: grid (%s)\n", cloth_result_string(r)); return 1; }
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1;
    def.self_collision = 1;
    piece_def.material.areal_density = (cloth_real)0.1;
    /* A mesh obstacle: its vertices (in its own frame) and triangles are copied by the world;
       the cloth meets it by continuous collision detection, triangle against triangle. */
    funnel.shape = CLOTH_OBSTACLE_MESH;
    funnel.mesh_x = funnel_x;
    funnel.mesh_vertex_count = 5;
    funnel.mesh_tri = funnel_tri;
    funnel.mesh_triangle_count = 4;
    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(world, &funnel, NULL);
    if (r != CLOTH_SUCCESS) { printf("FAILED: setup (%s)\n", cloth_result_string(r)); cloth_world_destroy(world); cloth_mesh_free(&mesh); return 1; }

    /* The checker's view: the cloth (its triangles tested against each other too) and the
       funnel (only against the cloth). The checker works on doubles. */
    for (i = 0; i < 15; ++i) funnel_xd[i] = (double)funnel_x[i];
    check[0].tri = mesh.tri;
    check[0].triangle_count = mesh.triangle_count;
    check[0].self = 1;
    check[1].x = funnel_xd;
    check[1].tri = funnel_tri;
    check[1].triangle_count = 4;
    check[1].self = 0;

    for (frame = 0; frame < frames && !failed; ++frame) {
        cloth_step_stats stats;
        long crossing;
        r = cloth_world_step(world, (cloth_real)(1.0 / 60), &stats);
        if (r != CLOTH_SUCCESS) { printf("FAILED: step %d (%s)\n", frame, cloth_result_string(r)); failed = 1; break; }
        impacts += stats.impacts;
        check[0].x = cloth_world_positions(world, piece); /* cloth_real is double here */
        crossing = exact_count_intersecting_pairs(check, 2, NULL);
        if (crossing != 0) { printf("FAILED: frame %d: %ld intersecting triangle pairs\n", frame, crossing); failed = 1; }
        if (frame % 30 == 29)
            printf("t = %.1f s: %ld impacts so far, %d impact zones now, max edge strain %.1f%%, 0 intersecting pairs\n",
                   (frame + 1) / 60.0, impacts, (int)stats.impact_zones, 100 * (double)cloth_world_max_edge_strain(world, piece));
    }
    if (!failed && impacts == 0) { printf("FAILED: no impact: the cloth touched neither the funnel nor itself\n"); failed = 1; }
    if (!failed) printf("ok: %d frames, %ld impacts resolved, no triangle ever crossed another\n", frames, impacts);
    cloth_world_destroy(world);
    cloth_mesh_free(&mesh);
    return failed;
}
