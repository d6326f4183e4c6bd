/* Short versions of docs/scenes.md's contact stress scenes (tests/stress_scenes.h; the full ones are
   bench/stress.c), asserting after every step: no intersecting cloth triangle pairs (exact
   checker, tests/exact_tritri.h), no cloth vertex inside an analytic obstacle deeper than
   1e-9 m, no cloth triangle intersecting a mesh obstacle, the projectile never through the
   cloth, and every step CLOTH_SUCCESS or CLOTH_ERROR_COLLISION_UNRESOLVED (counted and
   printed, the world then stays as before the step).

   The 1e-9 m tolerance: the contact module keeps vertices a thickness (1e-3 m) outside
   obstacles, and cloth_world_obstacle_distance of a point at coordinates of order 1 is off by
   a few 1e-16 m at most; a vertex more than 1e-9 m inside is a contact failure, not rounding.

   Scenes that fail today are listed in stress_known_failures_tests (`make known-failures`),
   not in stress_tests, with what failed. */
#include "runner.h"
#include "../cloth.h"
#include "stress_scenes.h"

#define STRESS_DEPTH_TOLERANCE 1e-9

/* Run scene id with n vertices per side for frames frames, asserting the above. */
static void run_scene(stress_scene_id id, int32_t n, int32_t frames)
{
    stress_scene s;
    stress_metrics m;
    cloth_result r;
    int32_t f;
    long bad_pairs_frames = 0, bad_obstacle_frames = 0;
    int bad_result = 0;
    r = stress_scene_create(&s, id, n);
    if (r != CLOTH_SUCCESS) { stress_scene_destroy(&s); ENSURE(r == CLOTH_SUCCESS); }
    stress_metrics_init(&m, frames);
    for (f = 0; f < frames; ++f) {
        long before_pairs = m.pairs_total, before_obstacle = m.obstacle_pairs_max;
        r = stress_step(&s, &m);
        if (r != CLOTH_SUCCESS && r != CLOTH_ERROR_COLLISION_UNRESOLVED && !bad_result) {
            bad_result = 1;
            printf("    frame %d: %s\n", (int)f, cloth_result_string(r));
        }
        if (m.pairs_total > before_pairs) ++bad_pairs_frames;
        if (m.obstacle_pairs_max > before_obstacle) ++bad_obstacle_frames;
        if (m.checker_error || bad_result) break;
    }
    printf("    %s n=%d, %d of the full scene's %d frames, median step %.2f ms: pairs max %ld (first at frame %d, %ld frames with pairs), obstacle-mesh pairs max %ld, "
           "penetration %.3g m, min vertex-obstacle distance %.4g m, strain end %.3f worst %.3f, lowest y %.4f, "
           "unresolved %d, impacts %ld, projectile through %d (frame %d)\n",
           stress_scene_names[id], (int)n, (int)m.frames, (int)stress_scene_frames(id), stress_median_ms(&m), m.pairs_max, (int)m.pairs_first_frame, bad_pairs_frames,
           m.obstacle_pairs_max, m.penetration, m.min_obstacle_distance, m.strain_end, m.strain_worst, m.lowest_y,
           (int)m.unresolved_steps, m.impacts, m.projectile_through, (int)m.projectile_through_frame);
    stress_metrics_free(&m);
    stress_scene_destroy(&s);
    ENSURE(!m.checker_error);
    ENSURE(!bad_result);
    ENSURE(m.pairs_max == 0);
    ENSURE(m.obstacle_pairs_max == 0);
    ENSURE(m.penetration <= STRESS_DEPTH_TOLERANCE);
    ENSURE(!m.projectile_through);
}

/* A host task system that runs the parts in reverse order and counts them. */
static long stress_host_parts;
static void *stress_host_enqueue(cloth_task_fn task, void *context, int32_t part_count, void *user)
{
    int32_t p;
    for (p = part_count - 1; p >= 0; --p) task(context, p);
    stress_host_parts += part_count;
    return user;
}
static void stress_host_finish(void *handle, void *user) { (void)handle; (void)user; }

TEST(threads_collide_bit_identical)
{
    /* The collide phase's CCD queries run on the world's threads (def.threads; CLOTH_THREADS)
       or on a host task system, each query on its own record, the impacts added in the
       serial order afterwards: the stack scene at 8 (three sheets on a box, cloth-cloth
       contact in every step) gives the same bits, impacts and rounds on 1, 2 and 3 threads and
       on a host system that runs the parts in reverse order. */
    static cloth_real x[4][3 * 3 * 8 * 8];
    long impacts[4], rounds[4], qp[4];
    cloth_task_system host;
    int t;
    memset(&host, 0, sizeof host);
    host.worker_count = 3;
    host.enqueue_task = stress_host_enqueue;
    host.finish_task = stress_host_finish;
    for (t = 0; t < 4; ++t) {
        stress_scene s;
        int32_t f, p;
        size_t at = 0;
        cloth_result r;
        stress_threads = t < 3 ? t + 1 : 0;
        stress_tasks = t == 3 ? &host : NULL;
        r = stress_scene_create(&s, STRESS_STACK, 8);
        stress_threads = 0;
        stress_tasks = NULL;
        if (r != CLOTH_SUCCESS) { stress_scene_destroy(&s); ENSURE(r == CLOTH_SUCCESS); }
        impacts[t] = rounds[t] = qp[t] = 0;
        for (f = 0; f < 20; ++f) {
            cloth_step_stats st;
            r = cloth_world_step(s.world, (cloth_real)s.dt, &st);
            if (r != CLOTH_SUCCESS) { stress_scene_destroy(&s); ENSURE(r == CLOTH_SUCCESS); }
            impacts[t] += st.impacts;
            rounds[t] += st.ccd_rounds;
            qp[t] += st.qp_iterations;
        }
        for (p = 0; p < s.pieces; ++p) {
            size_t bytes = 3 * sizeof(cloth_real) * (size_t)s.piece_vertices[p];
            ENSURE(at + bytes <= sizeof x[t]);
            memcpy((char *)x[t] + at, cloth_world_positions(s.world, p), bytes);
            at += bytes;
        }
        stress_scene_destroy(&s);
    }
    printf("    stack 8, 20 frames: %ld impacts, %ld CCD rounds, %ld QP iterations; host system: %ld parts\n", impacts[0],
           rounds[0], qp[0], stress_host_parts);
    ENSURE(impacts[0] > 100 && stress_host_parts > 0);
    for (t = 1; t < 4; ++t) {
        ENSURE(memcmp(x[t], x[0], sizeof x[0]) == 0);
        ENSURE(impacts[t] == impacts[0] && rounds[t] == rounds[0] && qp[t] == qp[0]);
    }
}

TEST(sphere_scene) { run_scene(STRESS_SPHERE, 10, 90); }
TEST(funnel_scene) { run_scene(STRESS_FUNNEL, 10, 90); }
TEST(twist_scene) { run_scene(STRESS_TWIST, 10, 120); }
/* The world def's collision_strain_stop: an attempt whose collide phase has stretched an edge
   past twice collision_strain_limit after a round of zone projections is given up there and
   redone on twice the substeps. In these scenes every attempt given up would have failed the
   strain test at the end of its collide phase anyway: the same bits with the stop as without
   it, the same redos, and less projection work. */
TEST(collide_stops_change_nothing_but_the_work)
{
    static const struct { stress_scene_id id; int32_t n, frames; } runs[] = {
        { STRESS_PROJECTILE, 10, 6 }, { STRESS_TWIST, 8, 60 } };
    int k, t;
    for (k = 0; k < 2; ++k) {
        static cloth_real x[2][3 * 10 * 10];
        long stops[2], redos[2], qp[2], pairs[2];
        for (t = 0; t < 2; ++t) {
            stress_scene s;
            stress_metrics m;
            int32_t f;
            cloth_result r;
            stress_collision_strain_stop = t == 0 ? -1 : 0; /* the default (2), then never */
            r = stress_scene_create(&s, runs[k].id, runs[k].n);
            stress_collision_strain_stop = -1;
            if (r != CLOTH_SUCCESS) { stress_scene_destroy(&s); ENSURE(r == CLOTH_SUCCESS); }
            stress_metrics_init(&m, runs[k].frames);
            for (f = 0; f < runs[k].frames; ++f) stress_step(&s, &m);
            ENSURE(s.pieces == 1 && (size_t)s.piece_vertices[0] * 3 <= sizeof x[t] / sizeof x[t][0]);
            memcpy(x[t], cloth_world_positions(s.world, 0), 3 * sizeof(cloth_real) * (size_t)s.piece_vertices[0]);
            stops[t] = m.collide_stops;
            redos[t] = m.substep_redos;
            qp[t] = m.qp_iterations;
            pairs[t] = m.pairs_max;
            ENSURE(m.failed_steps == 0 && !m.checker_error);
            stress_metrics_free(&m);
            stress_scene_destroy(&s);
        }
        printf("    %s %d x %d frames: %ld attempts given up inside the collide phase of %ld redone; QP working-set changes %ld (never giving up: %ld)\n",
               stress_scene_names[runs[k].id], (int)runs[k].n, (int)runs[k].frames, stops[0], redos[0], qp[0], qp[1]);
        ENSURE(memcmp(x[0], x[1], sizeof x[0]) == 0);
        ENSURE(stops[0] > 0 && stops[1] == 0 && redos[0] == redos[1] && qp[0] < qp[1]);
        ENSURE(pairs[0] == 0 && pairs[1] == 0);
    }
}

TEST(stack_scene) { run_scene(STRESS_STACK, 8, 30); }
/* the projectile with the analytic sphere: it reaches the cloth's plane in the first frame
   (0.83 m per frame) and then drags the pinned cloth along; 6 of the 30 frames keep the test
   short under the sanitizers (the whole scene: bench/stress.c, which also never lets it through) */
TEST(projectile_scene) { run_scene(STRESS_PROJECTILE, 10, 6); }
TEST(capsule_scene) { run_scene(STRESS_CAPSULE, 10, 90); }
/* the projectile as a mesh obstacle: met by CCD, it does not get through (it drags the pinned
   cloth along; the strain that makes is printed, not asserted) */
TEST(projectile_mesh_scene) { run_scene(STRESS_PROJECTILE_MESH, 10, 12); }

const test_case stress_tests[] = {
    { "threads_collide_bit_identical", threads_collide_bit_identical },
    { "collide_stops_change_nothing_but_the_work", collide_stops_change_nothing_but_the_work },
    { "sphere_scene", sphere_scene },
    { "funnel_scene", funnel_scene },
    { "twist_scene", twist_scene },
    { "stack_scene", stack_scene },
    { "capsule_scene", capsule_scene },
    { "projectile_mesh_scene", projectile_mesh_scene },
    { "projectile_scene", projectile_scene },
    { NULL, NULL }
};

/* KNOWN FAILURES, run by `make known-failures` and not by `make test`: none today. (The
   projectile left this list when spheres got their inner proxy, met by CCD: before, the 0.05 m
   sphere at 50 m/s went through the 10 x 10 cloth in the first step without one impact, its
   path 0.079 m from the nearest vertices.) */
const test_case stress_known_failures_tests[] = {
    { NULL, NULL }
};
