/* sphere.c - docs/scenes.md's "sphere" scene through cloth.h's world: a 1 m x 1 m cloth of n x n
   vertices dropped flat from y = 1 onto a static sphere of radius 0.3 at the origin, friction
   0.5, self-collision on, 3 s at 60 frames per second (one step per frame, linearized backward
   Euler). Prints one CSV row: ms per frame (process CPU time; dynamics and collisions apart),
   contact statistics, penetration (the deepest any cloth vertex got inside the sphere, checked
   after every step), max edge strain (end and worst), lowest y, unresolved steps.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/sphere bench/sphere.c -lm
       ./build/bench/sphere N [FRAMES] [CONSTRAINTS] [TRACE.csv|-] [OBSTACLE_ITERATIONS] [PROXIMITY_STIFFNESS] [MAX_SUBSTEP_DOUBLINGS] [STRAIN_LIMIT] [CG_TOLERANCE] [STRENGTH_THRESHOLD] [LUMPED]

   CONSTRAINTS (default 1) is the world def's obstacle_constraints: 1 holds vertices on the
   sphere inside the implicit solve (with Coulomb stick/slip there), 0 leaves the sphere to the
   collide phase after the solve (the behaviour before 2026-11-21, kept for comparison).
   OBSTACLE_ITERATIONS, PROXIMITY_STIFFNESS and MAX_SUBSTEP_DOUBLINGS set the world def's
   fields of those names (defaults 4, 100 and 3), STRAIN_LIMIT the piece def's strain_limit
   (default 0: no limiters; the stiffening stays the library's 100), CG_TOLERANCE the world
   def's cg.tolerance (default the library's, 1e-4), STRENGTH_THRESHOLD the world def's
   multigrid.strength_threshold (default the library's, 0.04), LUMPED the piece def's
   bending_lumped (default 0). TRACE.csv, when given (not "-"), gets one row per frame: substeps, Newton and CG iterations, ms per phase,
   impacts, zones, CCD rounds, QP iterations, strain of the collide phase and of the whole step. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_seconds(void *user) { (void)user; return (double)clock() / CLOCKS_PER_SEC; }

int main(int argc, char **argv)
{
    int32_t n = argc > 1 ? atoi(argv[1]) : 16, frames = argc > 2 ? atoi(argv[2]) : 180, piece, sphere, i, f;
    int constraints = argc > 3 ? atoi(argv[3]) : 1;
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def pd = cloth_default_piece_def();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_world *w = NULL;
    cloth_mesh m;
    double collide = 0, total = 0, penetration = 0, worst_strain = 0, lowest = 1e9;
    long impacts = 0, unresolved = 0, newton = 0;
    int32_t largest_zones = 0;
    cloth_result r;
    int use_trace = argc > 4 && strcmp(argv[4], "-") != 0;
    FILE *trace = use_trace ? fopen(argv[4], "w") : NULL;
    if (use_trace && !trace) { fprintf(stderr, "cannot write %s\n", argv[4]); return 1; }
    if (trace)
        fprintf(trace, "frame,substeps,redos,newton,cg,ms_total,ms_assembly,ms_solve,ms_bvh,ms_ccd,ms_response,impacts,zones,largest_zone,"
                       "ccd_rounds,qp_iterations,rigid_zones,frozen_zones,obstacle_constraints,collision_strain,step_strain,strain\n");
    if (n < 2 || frames < 1) return 2;
    def.self_collision = 1;
    def.obstacle_constraints = constraints;
    if (argc > 5) def.obstacle_iterations = atoi(argv[5]);
    if (argc > 6) def.proximity_stiffness = (cloth_real)atof(argv[6]);
    if (argc > 7) def.max_substep_doublings = atoi(argv[7]);
    if (argc > 9) def.cg.tolerance = (cloth_real)atof(argv[9]);
    if (argc > 10) def.multigrid.strength_threshold = (cloth_real)atof(argv[10]);
    def.clock = cpu_seconds;
    pd.material.areal_density = (cloth_real)0.1;
    if (argc > 8) pd.strain_limit = (cloth_real)atof(argv[8]);
    if (argc > 11) pd.bending_lumped = atoi(argv[11]);
    od.shape = CLOTH_OBSTACLE_SPHERE;
    od.radius = (cloth_real)0.3;
    od.friction_static = od.friction_kinetic = (cloth_real)0.5;
    if (cloth_mesh_grid(&m, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return 1;
    for (i = 0; i < m.vertex_count; ++i) m.x[3 * i + 1] = 1;
    r = cloth_world_create(&w, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(w, &m, &pd, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(w, &od, &sphere);
    if (r != CLOTH_SUCCESS) { fprintf(stderr, "setup: %s\n", cloth_result_string(r)); return 1; }
    for (f = 0; f < frames; ++f) {
        cloth_step_stats st;
        const cloth_real *x;
        double strain;
        r = cloth_world_step(w, (cloth_real)1 / 60, &st);
        if (r == CLOTH_ERROR_COLLISION_UNRESOLVED) { ++unresolved; continue; }
        if (r != CLOTH_SUCCESS) { fprintf(stderr, "frame %d: %s\n", (int)f, cloth_result_string(r)); return 1; }
        collide += st.time_collide;
        total += st.time_total;
        impacts += st.impacts;
        newton += st.newton_iterations;
        if (st.impact_zones > largest_zones) largest_zones = st.impact_zones;
        x = cloth_world_positions(w, piece);
        for (i = 0; i < m.vertex_count; ++i) {
            double d = 0.3 - sqrt((double)x[3 * i] * x[3 * i] + (double)x[3 * i + 1] * x[3 * i + 1] + (double)x[3 * i + 2] * x[3 * i + 2]);
            if (d > penetration) penetration = d;
            if (x[3 * i + 1] < lowest) lowest = x[3 * i + 1];
        }
        strain = cloth_world_max_edge_strain(w, piece);
        if (strain > worst_strain) worst_strain = strain;
        if (trace)
            fprintf(trace, "%d,%d,%d,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%d,%d,%d,%d,%d,%d,%d,%d,%.4f,%.4f,%.4f\n", (int)f, (int)st.substeps,
                    (int)st.substep_redos, (int)st.newton_iterations, (int)st.cg_iterations, 1000 * st.time_total, 1000 * st.time_assembly,
                    1000 * st.time_solve, 1000 * st.time_bvh, 1000 * st.time_ccd, 1000 * st.time_response, (int)st.impacts, (int)st.impact_zones,
                    (int)st.largest_zone, (int)st.ccd_rounds, (int)st.qp_iterations, (int)st.rigid_zones, (int)st.frozen_zones,
                    (int)st.obstacle_constraints, (double)st.collision_strain, (double)st.step_strain, strain);
    }
    printf("n,frames,obstacle_constraints,obstacle_iterations,proximity_stiffness,newton_per_frame,ms_per_frame_cpu,collide_ms_per_frame_cpu,dynamics_ms_per_frame_cpu,impacts_per_frame,max_impact_zones,unresolved_steps,penetration_m,strain_end,strain_worst,lowest_y\n");
    printf("%d,%d,%d,%d,%g,%.2f,%.3f,%.3f,%.3f,%.1f,%d,%ld,%.6g,%.4f,%.4f,%.4f\n", (int)n, (int)frames, constraints, (int)def.obstacle_iterations, (double)def.proximity_stiffness, (double)newton / frames, 1000 * total / frames, 1000 * collide / frames,
           1000 * (total - collide) / frames, (double)impacts / frames, (int)largest_zones, unresolved, penetration,
           (double)cloth_world_max_edge_strain(w, piece), worst_strain, lowest);
    if (trace) fclose(trace);
    cloth_world_destroy(w);
    cloth_mesh_free(&m);
    return 0;
}
