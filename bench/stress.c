/* stress.c - docs/scenes.md's contact stress scenes through cloth.h's world (sphere, funnel, twist,
   stack, projectile, capsule; set up in tests/stress_scenes.h), each checked after every step
   by the exact triangle-triangle checker tests/exact_tritri.h (written apart from cloth.h's
   collision code). Prints a CSV header and one row per scene:

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/stress bench/stress.c -lm
       ./build/bench/stress SCENE|all N [FRAMES] [noheader]

   STRESS_THREADS=N (N > 1, with the program built with -DCLOTH_THREADS -pthread) runs every
   world on N threads and times the frames by the wall clock (the phase columns stay CPU time).
   STRESS_SWEEP_PARTS=K sets every world def's multigrid.sweep_parts (0: one part per 1024
   vertices, so that the V-cycle's finest sweeps run on the threads too).
   STRESS_CG_TOLERANCE=T and STRESS_OBSTACLE_ITERATIONS=K set every world def's cg.tolerance and
   obstacle_iterations (the library's defaults: 1e-4 and 4).
   STRESS_BENDING_LUMPED=1 sets every piece def's bending_lumped (lumped hinges; default 0).
   STRESS_BENDING_MODEL=0 (quadratic) or 1 (dihedral) sets every piece def's bending_model.
   STRESS_MG_LEVELS=L sets every world def's multigrid.max_levels (0 or unset: the library's).
   STRESS_STRENGTH=T sets every world def's multigrid.strength_threshold (unset: the library's).
   STRESS_TRIAL_TOLERANCE=T sets every world def's obstacle_trial_tolerance (0 or unset: none).
   STRESS_TRIAL_UPDATE=0 or 1 sets every world def's obstacle_trial_multigrid_update.
   STRESS_HOLD_TOUCHING=0 or 1 sets every world def's obstacle_hold_touching_only.
   FRAMES (0 or missing) defaults to the scene's simulated time at 60 frames per second. With
   STRESS_BUDGET_S set in the environment, a scene stops after that many CPU seconds of
   stepping and checking, and its row says status "timeout" with the frames it finished.
   STRESS_PROGRESS=FILE rewrites FILE after every frame with the row so far (status
   "running"), so that a run killed inside a long frame still leaves its figures
   (bench/stress.sh uses it).
   Columns:
     machine, cpu, loadavg           from bench/machine.h
     scene, n, frames, vertices      frames stepped (one world step each), cloth vertices
     setup_ms                        world creation (CPU)
     ms_frame_median, ms_frame_mean  CPU time of cloth_world_step per frame (checks excluded)
     assembly_ms, solve_ms, collide_ms, other_ms   per frame, from cloth_step_stats (successful
                                     steps only: time_assembly, time_solve, time_collide and
                                     time_total minus those)
     impacts_per_frame, max_impact_zones, obstacle_contacts_per_frame
     pairs_max, pairs_total, pairs_first_frame   intersecting cloth triangle pairs (self and
                                     between pieces) after every step, exact; -1: none
     obstacle_pairs_max              cloth triangles intersecting the funnel's mesh (exact)
     check_ms                        CPU time of one exact check (mean)
     penetration_m                   deepest cloth vertex inside an analytic obstacle
     min_obstacle_distance_m         smallest vertex-obstacle distance seen (signed)
     strain_end, strain_worst        max edge strain (|e| / |e_rest| - 1), all pieces
     lowest_y
     unresolved_steps, other_failed_steps, last_error   steps that returned
                                     CLOTH_ERROR_COLLISION_UNRESOLVED (counted, the world
                                     stays as before the step) or another error
     projectile_through, through_frame   the sphere got entirely beyond every cloth vertex
     status                          complete, or timeout (STRESS_BUDGET_S ran out); bench/stress.sh
                                     writes "killed in frame F" for a run it had to kill */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "../tests/stress_scenes.h"
#include "machine.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void header(void)
{
    printf("machine,cpu,loadavg,scene,n,frames,vertices,setup_ms,ms_frame_median,ms_frame_mean,assembly_ms,solve_ms,collide_ms,"
           "other_ms,impacts_per_frame,max_impact_zones,obstacle_contacts_per_frame,pairs_max,pairs_total,pairs_first_frame,"
           "obstacle_pairs_max,check_ms,penetration_m,min_obstacle_distance_m,strain_end,strain_worst,lowest_y,"
           "unresolved_steps,other_failed_steps,last_error,projectile_through,through_frame,status\n");
}

/* One CSV row of the scene's figures so far, with the given status. */
static void print_row(FILE *out, const stress_scene *s, stress_scene_id id, int32_t n, const stress_metrics *m,
                      const bench_machine *mach, double setup_ms, const char *status)
{
    double sum = 0, ok = m->frames - m->failed_steps > 0 ? m->frames - m->failed_steps : 1;
    int32_t f, vertices = 0, p;
    for (f = 0; f < m->frames && f < m->capacity; ++f) sum += m->frame_ms[f];
    for (p = 0; p < s->pieces; ++p) vertices += s->piece_vertices[p];
    fprintf(out, "%s,%s,%s,%s,%d,%d,%d,%.1f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f,%d,%.1f,%ld,%ld,%d,%ld,%.3f,%.3g,%.4g,%.4f,%.4f,%.4f,%d,%d,%d,%d,%d,%s\n",
            mach->host, mach->cpu, mach->load, stress_scene_names[id], (int)n, (int)m->frames, (int)vertices, setup_ms,
            stress_median_ms(m), sum / (m->frames ? m->frames : 1), 1000 * m->time_assembly / ok, 1000 * m->time_solve / ok,
            1000 * m->time_collide / ok, 1000 * (m->time_total - m->time_assembly - m->time_solve - m->time_collide) / ok,
            (double)m->impacts / ok, (int)m->max_impact_zones, (double)m->obstacle_contacts / ok, m->pairs_max, m->pairs_total,
            (int)m->pairs_first_frame, m->obstacle_pairs_max, 1000 * m->check_seconds / (m->frames ? m->frames : 1),
            m->penetration, m->min_obstacle_distance, m->strain_end, m->strain_worst, m->lowest_y, (int)m->unresolved_steps,
            (int)m->other_errors, (int)m->last_error, m->projectile_through, (int)m->projectile_through_frame, status);
}

static int run(stress_scene_id id, int32_t n, int32_t frames, const bench_machine *mach, double budget, const char *progress)
{
    int timed_out = 0;
    stress_scene s;
    stress_metrics m;
    clock_t c0 = clock();
    double setup_ms;
    int32_t f;
    cloth_result r = stress_scene_create(&s, id, n);
    setup_ms = 1000.0 * (double)(clock() - c0) / CLOCKS_PER_SEC;
    if (r != CLOTH_SUCCESS) {
        fprintf(stderr, "stress %s %d: setup: %s\n", stress_scene_names[id], (int)n, cloth_result_string(r));
        stress_scene_destroy(&s);
        return 1;
    }
    if (frames <= 0) frames = stress_scene_frames(id);
    stress_metrics_init(&m, frames);
    for (f = 0; f < frames; ++f) {
        stress_step(&s, &m);
        if (progress) { /* the row so far, for a run killed inside a later frame (bench/stress.sh) */
            FILE *out = fopen(progress, "w");
            if (out) {
                print_row(out, &s, id, n, &m, mach, setup_ms, "running");
                fclose(out);
            }
        }
        if (m.checker_error) { fprintf(stderr, "stress %s: coordinates out of the checker's range\n", stress_scene_names[id]); break; }
        if (m.other_errors >= 10) { fprintf(stderr, "stress %s: 10 failed steps, stopping\n", stress_scene_names[id]); break; }
        if (budget > 0 && (double)(clock() - c0) / CLOCKS_PER_SEC > budget && f + 1 < frames) { timed_out = 1; break; }
    }
    print_row(stdout, &s, id, n, &m, mach, setup_ms, timed_out ? "timeout" : "complete");
    fflush(stdout);
    stress_metrics_free(&m);
    stress_scene_destroy(&s);
    return 0;
}

int main(int argc, char **argv)
{
    bench_machine mach = bench_machine_read();
    int32_t n, frames, i, rc = 0, found = 0;
    const char *b = getenv("STRESS_BUDGET_S"), *t = getenv("STRESS_THICKNESS"), *th = getenv("STRESS_THREADS");
    double budget = b ? atof(b) : 0;
    if (t) stress_thickness = atof(t);
    if (getenv("STRESS_SWEEP_PARTS")) stress_sweep_parts = atoi(getenv("STRESS_SWEEP_PARTS"));
    if (getenv("STRESS_CG_TOLERANCE")) stress_cg_tolerance = atof(getenv("STRESS_CG_TOLERANCE"));
    if (getenv("STRESS_OBSTACLE_ITERATIONS")) stress_obstacle_iterations = atoi(getenv("STRESS_OBSTACLE_ITERATIONS"));
    if (getenv("STRESS_TRIAL_TOLERANCE")) stress_trial_tolerance = atof(getenv("STRESS_TRIAL_TOLERANCE"));
    if (getenv("STRESS_TRIAL_UPDATE")) stress_trial_update = atoi(getenv("STRESS_TRIAL_UPDATE"));
    if (getenv("STRESS_HOLD_TOUCHING")) stress_hold_touching = atoi(getenv("STRESS_HOLD_TOUCHING"));
    if (getenv("STRESS_BENDING_LUMPED")) stress_bending_lumped = atoi(getenv("STRESS_BENDING_LUMPED"));
    if (getenv("STRESS_BENDING_MODEL")) stress_bending_model = atoi(getenv("STRESS_BENDING_MODEL"));
    if (getenv("STRESS_MG_LEVELS")) stress_mg_levels = atoi(getenv("STRESS_MG_LEVELS"));
    if (getenv("STRESS_STRENGTH")) stress_strength_threshold = atof(getenv("STRESS_STRENGTH"));
    if (th && atoi(th) > 1) {
        /* world def threads (cloth.h built with -DCLOTH_THREADS -pthread); frames timed by the wall clock */
        stress_threads = atoi(th);
        stress_frame_clock = bench_wall_seconds;
    }
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE|all N [FRAMES] [noheader]\n", argv[0]);
        return 2;
    }
    n = atoi(argv[2]);
    frames = argc > 3 ? atoi(argv[3]) : 0;
    if (n < 4) return 2;
    if (!(argc > 4 && strcmp(argv[4], "noheader") == 0)) header();
    for (i = 0; i < STRESS_SCENE_COUNT; ++i)
        if (strcmp(argv[1], "all") == 0 || strcmp(argv[1], stress_scene_names[i]) == 0) {
            found = 1;
            rc |= run((stress_scene_id)i, n, frames, &mach, budget, getenv("STRESS_PROGRESS"));
        }
    if (!found) { fprintf(stderr, "stress: no scene '%s'\n", argv[1]); return 2; }
    return rc;
}
