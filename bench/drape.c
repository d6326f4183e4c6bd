/* drape.c - how smoothly the sphere drape comes to rest, over several paths. The scene of the
   physics test a_cloth_draped_on_a_sphere_comes_to_rest (a 1 m cloth of N x N vertices
   dropped flat onto a sphere of radius 0.3, friction 0.5, self-collision, 120 frames at 60
   per second), run PATHS times with the drop height raised by k 1e-4 m on path k (k = 1 ..
   PATHS): the scene is chaotic, so one path's figures carry that path's luck, and a claim
   about rest is a claim about their distribution. Per path: the fastest vertex and the worst
   edge strain over frames 80-119 (the test's bounds: 0.5 m/s and 5%), CG iterations and
   solves per frame, ms per frame (one thread, wall clock).

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/drape bench/drape.c -lm
       ./build/bench/drape [N [PATHS]]          (defaults 32 and 12)

   The environment sets world def knobs: DRAPE_CG_TOLERANCE (cg.tolerance),
   DRAPE_OBSTACLE_ITERATIONS (obstacle_iterations), DRAPE_TRIAL_TOLERANCE
   (obstacle_trial_tolerance), DRAPE_TRIAL_UPDATE (obstacle_trial_multigrid_update),
   DRAPE_HOLD_TOUCHING (obstacle_hold_touching_only); unset: the library's defaults. Prints a CSV header and one row
   per path (machine, cpu, loadavg, n, path, cg_tolerance, obstacle_iterations,
   trial_tolerance, fastest_rest_m_per_s, strain_rest, strain_worst, within_bounds,
   cg_per_frame, solves_per_frame, ms_per_frame), then a line "# median strain_rest S, paths
   within the test's bounds K of PATHS". */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "../tests/drape_scene.h"
#include "machine.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int drape_compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    bench_machine mach = bench_machine_read();
    int32_t n = argc > 1 ? atoi(argv[1]) : 32, paths = argc > 2 ? atoi(argv[2]) : 12, k, within = 0;
    double *rest;
    cloth_world_def d0 = cloth_default_world_def();
    if (n < 4 || paths < 1) {
        fprintf(stderr, "usage: %s [N >= 4 [PATHS >= 1]]\n", argv[0]);
        return 2;
    }
    if (getenv("DRAPE_CG_TOLERANCE")) d0.cg.tolerance = (cloth_real)atof(getenv("DRAPE_CG_TOLERANCE"));
    if (getenv("DRAPE_OBSTACLE_ITERATIONS")) d0.obstacle_iterations = atoi(getenv("DRAPE_OBSTACLE_ITERATIONS"));
    if (getenv("DRAPE_TRIAL_TOLERANCE")) d0.obstacle_trial_tolerance = (cloth_real)atof(getenv("DRAPE_TRIAL_TOLERANCE"));
    if (getenv("DRAPE_TRIAL_UPDATE")) d0.obstacle_trial_multigrid_update = atoi(getenv("DRAPE_TRIAL_UPDATE"));
    if (getenv("DRAPE_HOLD_TOUCHING")) d0.obstacle_hold_touching_only = atoi(getenv("DRAPE_HOLD_TOUCHING"));
    rest = (double *)malloc((size_t)paths * sizeof(double));
    if (!rest) return 1;
    printf("machine,cpu,loadavg,n,path,cg_tolerance,obstacle_iterations,trial_tolerance,fastest_rest_m_per_s,strain_rest,"
           "strain_worst,within_bounds,cg_per_frame,solves_per_frame,ms_per_frame\n");
    for (k = 0; k < paths; ++k) {
        cloth_world *w = NULL;
        cloth_mesh m;
        int32_t piece, i, f;
        long cg = 0, solves = 0;
        double fastest = 0, worst_rest = 0, worst = 0, t0;
        int ok = drape_scene_world(d0, n, 1e-4 * k, &w, &m, &piece);
        t0 = bench_wall_seconds();
        for (f = 0; f < 120 && ok; ++f) {
            cloth_step_stats st;
            double strain;
            ok = cloth_world_step(w, (cloth_real)1 / 60, &st) == CLOTH_SUCCESS;
            if (!ok) break;
            cg += st.cg_iterations;
            solves += st.newton_iterations;
            strain = (double)cloth_world_max_edge_strain(w, piece);
            if (strain > worst) worst = strain;
            if (f >= 80) {
                const cloth_real *v = cloth_world_velocities(w, piece);
                for (i = 0; i < m.vertex_count; ++i) {
                    double s = sqrt((double)v[3 * i] * v[3 * i] + (double)v[3 * i + 1] * v[3 * i + 1] + (double)v[3 * i + 2] * v[3 * i + 2]);
                    if (s > fastest) fastest = s;
                }
                if (strain > worst_rest) worst_rest = strain;
            }
        }
        t0 = bench_wall_seconds() - t0;
        if (!ok) {
            fprintf(stderr, "drape: path %d failed at frame %d\n", (int)k, (int)f);
            return 1;
        }
        rest[k] = worst_rest;
        within += fastest < 0.5 && worst_rest < 0.05;
        printf("%s,%s,%s,%d,%d,%g,%d,%g,%.3f,%.4f,%.4f,%d,%.1f,%.2f,%.2f\n", mach.host, mach.cpu, mach.load, (int)n, (int)k,
               (double)d0.cg.tolerance, (int)d0.obstacle_iterations, (double)d0.obstacle_trial_tolerance, fastest, worst_rest, worst,
               fastest < 0.5 && worst_rest < 0.05, (double)cg / 120, (double)solves / 120, 1000 * t0 / 120);
        fflush(stdout);
        cloth_world_destroy(w);
        cloth_mesh_free(&m);
    }
    qsort(rest, (size_t)paths, sizeof(double), drape_compare);
    printf("# median strain_rest %.4f, paths within the test's bounds %d of %d\n",
           paths % 2 ? rest[paths / 2] : (rest[paths / 2 - 1] + rest[paths / 2]) / 2, (int)within, (int)paths);
    free(rest);
    return 0;
}
