/* paired.c - two settings of one stress scene compared in one process: world A and world B
   are stepped alternately frame by frame (which goes first swaps every frame), so that the
   machine's drift over the run falls on both alike; on the noisy 2-core VM this resolves a
   few percent where separate runs cannot. Each path is one such pair from the start of the
   scene; PAIRED_PATHS paths differ only by a prolongator damping of 4/3 + k 1e-4 in both
   worlds, which moves the chaotic path and nothing else, since the figures of one path also
   carry the path's own luck.

       cc -std=c99 -O2 -ffp-contract=off [-DCLOTH_THREADS -pthread] -o build/bench/paired bench/paired.c -lm
       ./build/bench/paired SCENE N

   Both worlds take bench/stress.c's environment (STRESS_CG_TOLERANCE, STRESS_OBSTACLE_ITERATIONS,
   STRESS_TRIAL_TOLERANCE, STRESS_TRIAL_UPDATE, STRESS_HOLD_TOUCHING, STRESS_BENDING_LUMPED,
   STRESS_BENDING_MODEL, STRESS_MG_LEVELS, STRESS_STRENGTH, STRESS_SWEEP_PARTS, STRESS_THREADS);
   B then takes PAIRED_B_MG_LEVELS, PAIRED_B_SWEEP_PARTS, PAIRED_B_STRENGTH,
   PAIRED_B_TRIAL_TOLERANCE, PAIRED_B_HOLD_TOUCHING and PAIRED_B_BENDING_MODEL (multigrid
   max_levels, sweep_parts, strength_threshold, obstacle_trial_tolerance,
   obstacle_hold_touching_only, the pieces' bending_model) over them. PAIRED_PATHS (default 4).
   Frames are timed by the wall clock. Prints a CSV header and one row per path: machine, cpu, loadavg, scene, n, path,
   frames, a_ms_frame, b_ms_frame, ratio (b / a), a_cg_per_frame, b_cg_per_frame,
   a_strain_worst, b_strain_worst, a_ms_median, b_ms_median (the median frame, as bench/stress
   and bench/target.sh report it), median_ratio (b / a), a_strain_end, b_strain_end (the last
   frame's worst edge strain). */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "../tests/stress_scenes.h"
#include "machine.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void paired_settings(int b, int32_t levels, int32_t parts, double trial, int touching, int bending, double damping)
{
    stress_hold_touching = b && getenv("PAIRED_B_HOLD_TOUCHING") ? atoi(getenv("PAIRED_B_HOLD_TOUCHING")) : touching;
    stress_trial_tolerance = b && getenv("PAIRED_B_TRIAL_TOLERANCE") ? atof(getenv("PAIRED_B_TRIAL_TOLERANCE")) : trial;
    stress_bending_model = b && getenv("PAIRED_B_BENDING_MODEL") ? atoi(getenv("PAIRED_B_BENDING_MODEL")) : bending;
    stress_mg_levels = b && getenv("PAIRED_B_MG_LEVELS") ? atoi(getenv("PAIRED_B_MG_LEVELS")) : levels;
    stress_sweep_parts = b && getenv("PAIRED_B_SWEEP_PARTS") ? atoi(getenv("PAIRED_B_SWEEP_PARTS")) : parts;
    stress_strength_threshold = b && getenv("PAIRED_B_STRENGTH") ? atof(getenv("PAIRED_B_STRENGTH"))
                                : getenv("STRESS_STRENGTH") ? atof(getenv("STRESS_STRENGTH")) : -1;
    stress_prolongator_damping = damping;
}

static int paired_cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* The median of a sorted list. */
static double paired_median(const double *sorted, int32_t count)
{
    return count % 2 ? sorted[count / 2] : 0.5 * (sorted[count / 2 - 1] + sorted[count / 2]);
}

int main(int argc, char **argv)
{
    bench_machine mach = bench_machine_read();
    int32_t n, levels, parts, paths, k, f, i, frames;
    double trial;
    int bending, touching;
    int id = -1;
    /* the scene header's per-frame check helpers, which this comparison does without */
    (void)stress_step;
    (void)stress_metrics_init;
    (void)stress_metrics_free;
    (void)stress_median_ms;
    if (argc < 3) {
        fprintf(stderr, "usage: %s SCENE N\n", argv[0]);
        return 2;
    }
    for (i = 0; i < STRESS_SCENE_COUNT; ++i)
        if (strcmp(argv[1], stress_scene_names[i]) == 0) id = i;
    n = atoi(argv[2]);
    if (id < 0 || n < 4) {
        fprintf(stderr, "paired: no scene '%s' or N < 4\n", argv[1]);
        return 2;
    }
    if (getenv("STRESS_CG_TOLERANCE")) stress_cg_tolerance = atof(getenv("STRESS_CG_TOLERANCE"));
    if (getenv("STRESS_OBSTACLE_ITERATIONS")) stress_obstacle_iterations = atoi(getenv("STRESS_OBSTACLE_ITERATIONS"));
    if (getenv("STRESS_BENDING_LUMPED")) stress_bending_lumped = atoi(getenv("STRESS_BENDING_LUMPED"));
    if (getenv("STRESS_TRIAL_UPDATE")) stress_trial_update = atoi(getenv("STRESS_TRIAL_UPDATE"));
    if (getenv("STRESS_THREADS")) stress_threads = atoi(getenv("STRESS_THREADS"));
    levels = getenv("STRESS_MG_LEVELS") ? atoi(getenv("STRESS_MG_LEVELS")) : 0;
    parts = getenv("STRESS_SWEEP_PARTS") ? atoi(getenv("STRESS_SWEEP_PARTS")) : -1;
    trial = getenv("STRESS_TRIAL_TOLERANCE") ? atof(getenv("STRESS_TRIAL_TOLERANCE")) : 0;
    bending = getenv("STRESS_BENDING_MODEL") ? atoi(getenv("STRESS_BENDING_MODEL")) : -1;
    touching = getenv("STRESS_HOLD_TOUCHING") ? atoi(getenv("STRESS_HOLD_TOUCHING")) : -1;
    paths = getenv("PAIRED_PATHS") ? atoi(getenv("PAIRED_PATHS")) : 4;
    frames = stress_scene_frames((stress_scene_id)id);
    printf("machine,cpu,loadavg,scene,n,path,frames,a_ms_frame,b_ms_frame,ratio,a_cg_per_frame,b_cg_per_frame,a_strain_worst,"
           "b_strain_worst,a_ms_median,b_ms_median,median_ratio,a_strain_end,b_strain_end\n");
    for (k = 0; k < paths; ++k) {
        stress_scene s[2];
        double t[2] = { 0, 0 }, worst[2] = { 0, 0 }, end[2] = { 0, 0 }, *frame_ms[2];
        long cg[2] = { 0, 0 };
        int w;
        for (w = 0; w < 2; ++w) {
            frame_ms[w] = (double *)malloc((size_t)frames * sizeof(double));
            if (!frame_ms[w]) {
                fprintf(stderr, "paired: out of memory\n");
                return 1;
            }
            paired_settings(w, levels, parts, trial, touching, bending, 4.0 / 3.0 + 1e-4 * k);
            if (stress_scene_create(&s[w], (stress_scene_id)id, n) != CLOTH_SUCCESS) {
                fprintf(stderr, "paired: setup failed\n");
                return 1;
            }
        }
        for (f = 0; f < frames; ++f)
            for (i = 0; i < 2; ++i) {
                cloth_step_stats st;
                double t0, strain = 0;
                int32_t p;
                w = (f & 1) ? 1 - i : i;
                t0 = bench_wall_seconds();
                if (cloth_world_step(s[w].world, (cloth_real)s[w].dt, &st) != CLOTH_SUCCESS) memset(&st, 0, sizeof st);
                frame_ms[w][f] = 1000 * (bench_wall_seconds() - t0);
                t[w] += frame_ms[w][f] / 1000;
                cg[w] += st.cg_iterations;
                for (p = 0; p < s[w].pieces; ++p)
                    if ((double)cloth_world_max_edge_strain(s[w].world, p) > strain) strain = (double)cloth_world_max_edge_strain(s[w].world, p);
                if (strain > worst[w]) worst[w] = strain;
                end[w] = strain;
            }
        for (w = 0; w < 2; ++w) qsort(frame_ms[w], (size_t)frames, sizeof(double), paired_cmp);
        printf("%s,%s,%s,%s,%d,%d,%d,%.3f,%.3f,%.4f,%.2f,%.2f,%.4f,%.4f,%.3f,%.3f,%.4f,%.4f,%.4f\n", mach.host, mach.cpu, mach.load, argv[1], (int)n,
               (int)k, (int)frames, 1000 * t[0] / frames, 1000 * t[1] / frames, t[1] / t[0], (double)cg[0] / frames,
               (double)cg[1] / frames, worst[0], worst[1], paired_median(frame_ms[0], frames), paired_median(frame_ms[1], frames),
               paired_median(frame_ms[1], frames) / paired_median(frame_ms[0], frames), end[0], end[1]);
        fflush(stdout);
        free(frame_ms[0]);
        free(frame_ms[1]);
        stress_scene_destroy(&s[0]);
        stress_scene_destroy(&s[1]);
    }
    return 0;
}
