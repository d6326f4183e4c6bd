/* threads.c - a world stepped on threads: the library's pool and a host's own task system.

   The same scene (a 20 x 20 cloth dropped onto a sphere, with self-collision) runs three
   times: on one thread; on a tiny task system of this program's own, as a game engine would
   hand cloth.h its job system; and, when built with -DCLOTH_THREADS -pthread, on the
   library's own thread pool (world def `threads`). The three runs must end bit for bit the
   same: cloth.h splits work into fixed parts and sums them in a fixed order, so results never
   depend on the threads. (Timings: on a scene this small, or on a machine busy with other work,
   two threads can be slower than one; bench/results/target.md times 64 x 64 cloths on two.)

   What it teaches: the cloth_task_system interface (enqueue_task, finish_task, worker_count)
   and cloth.h's determinism.

   Build and run from the repository root (`make examples` builds all the examples):
       cc -std=c99 -O2 -DCLOTH_THREADS -pthread -o build/examples/threads examples/threads.c -lm
       ./build/examples/threads     (--short: fewer frames, as `make test` runs it)
   It exits with 1 when a check fails. */
#define _POSIX_C_SOURCE 200112L /* pthreads */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define N 20
#define WORKERS 2

/* ---- a tiny task system ------------------------------------------------------------------
   cloth.h calls enqueue_task(task, context, parts, user) and then finish_task(handle, user):
   every part p in 0 .. parts-1 must have run task(context, p) when finish_task returns. Here
   enqueue starts WORKERS - 1 threads, thread k running parts k, k + WORKERS, ...; finish runs
   the calling thread's share (parts 0, WORKERS, ...) and joins the threads. A real engine
   would keep its threads alive between calls instead of starting them every time. */
typedef struct tiny_share { cloth_task_fn task; void *context; int32_t first, parts; } tiny_share;
typedef struct tiny_tasks { pthread_t thread[WORKERS]; tiny_share share[WORKERS]; int started; long calls; } tiny_tasks;

static void *tiny_run(void *arg)
{
    tiny_share *s = (tiny_share *)arg;
    int32_t p;
    for (p = s->first; p < s->parts; p += WORKERS) s->task(s->context, p);
    return NULL;
}

static void *tiny_enqueue(cloth_task_fn task, void *context, int32_t parts, void *user)
{
    tiny_tasks *t = (tiny_tasks *)user;
    int k;
    t->started = 0;
    ++t->calls;
    for (k = 0; k < WORKERS; ++k) {
        t->share[k].task = task; t->share[k].context = context; t->share[k].first = k; t->share[k].parts = parts;
        if (k > 0 && pthread_create(&t->thread[k], NULL, tiny_run, &t->share[k]) == 0) t->started |= 1 << k;
    }
    return t; /* the handle: this system runs one batch at a time */
}

static void tiny_finish(void *handle, void *user)
{
    tiny_tasks *t = (tiny_tasks *)handle;
    int k;
    (void)user;
    tiny_run(&t->share[0]);
    for (k = 1; k < WORKERS; ++k) {
        if (t->started & (1 << k)) pthread_join(t->thread[k], NULL);
        else tiny_run(&t->share[k]); /* the thread did not start: run its share here */
    }
}

/* ---- the scene ----------------------------------------------------------------------------- */

/* Runs the scene with the given def; copies the final positions into x (3 N^2 values).
   Returns the seconds of wall clock it took, -1 on failure. */
static double run(cloth_world_def def, int frames, cloth_real *x)
{
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_obstacle_def ball = cloth_default_obstacle_def();
    cloth_world *world = NULL;
    cloth_mesh mesh;
    struct timespec t0, t1;
    int32_t piece, i;
    int frame;
    cloth_result r = cloth_mesh_grid(&mesh, N, N, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) return -1;
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1;
    def.self_collision = 1;
    ball.shape = CLOTH_OBSTACLE_SPHERE;
    ball.radius = (cloth_real)0.3;
    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(world, &ball, NULL);
    cloth_mesh_free(&mesh);
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (frame = 0; frame < frames && r == CLOTH_SUCCESS; ++frame) r = cloth_world_step(world, (cloth_real)(1.0 / 60), NULL);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (r == CLOTH_SUCCESS) memcpy(x, cloth_world_positions(world, piece), sizeof(cloth_real) * 3 * N * N);
    else printf("step failed: %s\n", cloth_result_string(r));
    cloth_world_destroy(world);
    return r == CLOTH_SUCCESS ? (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec) : -1;
}

int main(int argc, char **argv)
{
    int quick = argc > 1 && strcmp(argv[1], "--short") == 0, frames = quick ? 30 : 120, failed = 0;
    static cloth_real serial[3 * N * N], hosted[3 * N * N], pooled[3 * N * N];
    cloth_world_def def = cloth_default_world_def();
    tiny_tasks tasks;
    double seconds;

    seconds = run(def, frames, serial); /* threads 0: everything on the calling thread */
    printf("one thread:       %.2f s\n", seconds);
    if (seconds < 0) return 1;

    /* The host's task system: the world splits its parallel work into worker_count parts. */
    memset(&tasks, 0, sizeof tasks);
    def.tasks.worker_count = WORKERS;
    def.tasks.enqueue_task = tiny_enqueue;
    def.tasks.finish_task = tiny_finish;
    def.tasks.user = &tasks;
    seconds = run(def, frames, hosted);
    printf("tiny task system: %.2f s, %ld batches\n", seconds, tasks.calls);
    if (seconds < 0 || memcmp(serial, hosted, sizeof serial) != 0) { printf("FAILED: the task system's run differs\n"); failed = 1; }

#ifdef CLOTH_THREADS
    def = cloth_default_world_def();
    def.threads = WORKERS; /* the library's own pool: the calling thread and WORKERS - 1 workers */
    seconds = run(def, frames, pooled);
    printf("cloth.h's pool:   %.2f s\n", seconds);
    if (seconds < 0 || memcmp(serial, pooled, sizeof serial) != 0) { printf("FAILED: the pool's run differs\n"); failed = 1; }
#else
    (void)pooled;
    printf("(built without CLOTH_THREADS: no pool run)\n");
#endif
    if (!failed) printf("ok: %d frames, the same bits on one thread and on %d\n", frames, WORKERS);
    return failed;
}
