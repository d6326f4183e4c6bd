/* Benchmark of the integrate module on the standard "hang" scene of docs/scenes.md:
   a 1 m x 1 m cloth of n x n vertices (cloth_mesh_grid, alternating diagonals, as Bullet's
   CreatePatch), flat at y = 1 with x, z in [-0.5, 0.5], the two corners at z = -0.5 pinned,
   areal density 0.1 kg/m^2, gravity -9.81 m/s^2, 2 s at 60 frames per second.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/dynamics bench/dynamics.c -lm
       ./build/bench/dynamics MODE [options]

   Modes (each prints a CSV header line, then one or more rows, on stdout):
     scene       runs the scene `runs` times with one configuration and prints one row:
                 timing (median over the runs, stepping only; setup apart), solver counts,
                 the assembly / solve split of cloth_step_stats, strain, lowest y, memory.
     payuse      pay-for-what-you-use: the cost of one step from the same state (the scene
                 at t = 1 s) with bending on / off and wind off / on, repeated and medianed.
     preconditioners   lists the preconditioners this build of cloth.h knows, one a line.
     accuracy    the CG tolerance as a speed-accuracy knob: one untimed reference run at
                 tolerance 1e-9 records every frame; then for each tolerance of
                 DYNAMICS_TOLERANCES (default "1e-2 3e-3 1e-3 3e-4 1e-4 1e-5") `runs` timed
                 runs and one row: ms per frame (median), CG iterations, strain, the free
                 corners' height and its error, and the largest distance of any vertex from
                 the reference over all frames and at the end (on stdout; no script keeps it).
     knobs       the integrator, the time step (substeps) and the Newton iteration cap as
                 speed-accuracy knobs, against one untimed reference run that approximates
                 the scene's exact motion: BDF2 (second order), Newton to 1e-7 m/s (at most 50
                 iterations), DYNAMICS_REFERENCE_SUBSTEPS substeps per frame (default 32), CG
                 tolerance 1e-9. Rows (each `runs` timed runs; the options' CG tolerance and
                 preconditioner): knob "integrator" lbe, be, bdf2 on one substep; "substeps"
                 lbe on 2, 4, 8; "newton" be with newton_max_iterations 1, 2, 3, 5 (20, the
                 default, is the integrator row). Columns as accuracy's, after knob and value,
                 and the energy (kinetic + gravitational + elastic) lost over the run
                 (bench/results/dynamics_knobs.csv; bench/knobs.sh runs 0.5 s, -f 30: over
                 longer runs the swinging cloth's paths part whatever the step).

   Options (scene and payuse):
     -n N                 vertices per side (default 32)
     -i se|lbe|be|bdf2    integrator (default lbe: linearized backward Euler)
     -t TOL               CG relative tolerance (default: cloth_default_pcg_options())
     -m MAXIT             CG iteration cap (default: cloth_default_pcg_options())
     -p NAME|NUMBER|NAME=NUMBER   preconditioner (default: cloth_default_pcg_options());
                          names from the `preconditioners` mode; a number is passed through
                          as the enum value (NAME=NUMBER also names it in the output)
     -M NAME              material: a preset name of cloth_material_preset (default cotton,
                          the library's default), or "cottonxK" for cotton with its membrane
                          (C11, C12, C22, C33) multiplied by K; the areal density is always
                          set to the scene's 0.1 kg/m^2
     -b 0|1               bending (piece def bending; default 1)
     -K q|d               bending model: q quadratic (default), d dihedral (piece def bending_model)
     -Z 0|1|2             lumped bending (piece def bending_lumped; default 0: exact; 1: in the
                          step; 2: in the preconditioner only); the material column then ends
                          in +lumped or +lumped_preconditioner
     -w SPEED             wind along +z, m/s (world def wind; default 0)
     -l LIMIT             strain limiting: piece def strain_limit (default 0: off); the
                          material column then reads e.g. cotton+limit0.04x100
     -s STIFFENING        piece def strain_limit_stiffening (default the library's, 100)
     -u SUBSTEPS          world def substeps (default the library's, 1)
     -N NEWTON_MAX        world def newton_max_iterations (default the library's, 20)
     -G PARTS             world def multigrid.sweep_parts (default the library's, 1): 0 runs the
                          multigrid V-cycle's finest sweeps in one part per 1024 vertices, on the
                          threads of -j
     -j THREADS           world def threads (default 0: single-threaded); more than 1 needs the
                          bench compiled with -DCLOTH_THREADS (and -pthread); the phase times
                          and ms_per_frame_cpu then add up all threads' CPU time, so compare
                          ms_per_frame_wall
     -r RUNS              timed runs (default 3)
     -y JITTER            run k (from 0) starts the cloth k JITTER metres higher (default 0). A
                          tiny height (1e-9) changes nothing a user could see, but the runs then
                          take their own paths through the adaptive steps (where limiters send a
                          frame to more substeps), so that the medians are over paths, not only
                          over timings of one path (runs_identical is then 0)
     -f FRAMES            frames (default 120 = 2 s)
     -B SECONDS           CPU budget: no further run starts when the runs so far plus one more
                          of their mean length would pass this much stepping CPU time
                          (default: no budget; the first run always happens)
     -P FRAMES            pilot: step this many frames first; when the pilot's CPU time times
                          frames / pilot frames exceeds -L, print a row with status "skipped"
                          and the pilot's figures instead of running (default 0: no pilot)
     -L SECONDS           the limit for -P (default 120)
     -S REASON            run nothing: print the row with status "skipped: REASON" and no figures
     -H                   print no header

   Timing: CPU time is the process's (CLOCK_PROCESS_CPUTIME_ID), which other load on a
   shared machine disturbs less; wall time is CLOCK_MONOTONIC. Only the cloth_world_step
   calls are inside the timed region; the strain and lowest-y measurements after each frame
   are outside it. The world's phase clock (def.clock) is the process CPU time, so
   time_assembly and time_solve are CPU seconds. Setup (mesh, world, piece, pins and the
   lazy build of the element lists, forced with cloth_world_energy) is timed apart.

   Symplectic Euler runs at its stable step: the world is made with substeps = 1 and each
   frame is split into k calls of 1/(60 k) s; k starts from cloth_world_stable_time_step()
   at rest (k = ceil((1/60) / (0.9 h_stable))) and grows by 25 % whenever a call returns
   CLOTH_ERROR_UNSTABLE (the world is restored then; the failed call is retried at the new
   k and its time counted). The per-call state backup of cloth_world_step is included.

   Memory: the world is made with a counting allocator; bytes per vertex are the peak of the
   bytes it held (world create, piece, pins, build and every step) over the vertex count.
   The mesh passed to cloth_world_add_piece is the caller's and not counted. Allocations
   made during stepping are counted apart (the library should make none). */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define FRAME_DT (1.0 / 60.0)

/* ---- clocks, statistics -------------------------------------------------------------- */

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double cpu_clock(void *user)
{
    (void)user;
    return cpu_s();
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(const double *v, int n)
{
    double *s = (double *)malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
    double m;
    if (n <= 0 || !s) { free(s); return 0; }
    memcpy(s, v, sizeof(double) * (size_t)n);
    qsort(s, (size_t)n, sizeof *s, cmp_double);
    m = n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
    free(s);
    return m;
}

static double vmin(const double *v, int n) { double m = v[0]; int i; for (i = 1; i < n; ++i) if (v[i] < m) m = v[i]; return m; }
static double vmax(const double *v, int n) { double m = v[0]; int i; for (i = 1; i < n; ++i) if (v[i] > m) m = v[i]; return m; }

/* ---- counting allocator --------------------------------------------------------------- */

typedef struct counter {
    size_t current, peak, total;
    long allocations;
} counter;

typedef union header { size_t size; double align_d; void *align_p; long double align_l; } header;

static void *count_alloc(size_t size, void *user)
{
    counter *c = (counter *)user;
    header *h = (header *)malloc(sizeof(header) + size);
    if (!h) return NULL;
    h->size = size;
    c->current += size;
    c->total += size;
    c->allocations++;
    if (c->current > c->peak) c->peak = c->current;
    return h + 1;
}

static void count_free(void *ptr, void *user)
{
    counter *c = (counter *)user;
    header *h;
    if (!ptr) return;
    h = (header *)ptr - 1;
    c->current -= h->size;
    free(h);
}

/* ---- logger: counts the solver's warnings ---------------------------------------------- */

typedef struct warnings { long cg_capped, newton_capped, other; } warnings;

static void count_log(cloth_log_level level, const char *message, void *user)
{
    warnings *w = (warnings *)user;
    if (level < CLOTH_LOG_WARNING) return;
    if (strstr(message, "conjugate gradient")) w->cg_capped++;
    else if (strstr(message, "Newton")) w->newton_capped++;
    else w->other++;
}

/* ---- options ------------------------------------------------------------------------ */

/* The preconditioners of this build. Add a line when cloth.h gains one; a value the table
   does not name can still be passed as a number (-p 3). */
typedef struct named_preconditioner { const char *name; int value; } named_preconditioner;
static const named_preconditioner PRECONDITIONERS[] = {
    { "none", CLOTH_PRECONDITIONER_NONE },
    { "jacobi", CLOTH_PRECONDITIONER_JACOBI },
    { "block_jacobi", CLOTH_PRECONDITIONER_BLOCK_JACOBI },
#if defined(CLOTH_PRECONDITIONER_MULTIGRID) || defined(DYNAMICS_HAVE_MULTIGRID)
    /* when cloth.h defines a macro of that name, or when bench/dynamics.sh finds the enum
       value by compiling a probe and builds with -DDYNAMICS_HAVE_MULTIGRID */
    { "multigrid", CLOTH_PRECONDITIONER_MULTIGRID },
#endif
};
#define PRECONDITIONER_COUNT ((int)(sizeof PRECONDITIONERS / sizeof PRECONDITIONERS[0]))

static char extra_preconditioner[48]; /* a name given as NAME=VALUE on the command line */
static int extra_preconditioner_value = -1;

static const char *preconditioner_name(int value)
{
    static char buf[32];
    int i;
    if (extra_preconditioner[0] && value == extra_preconditioner_value) return extra_preconditioner;
    for (i = 0; i < PRECONDITIONER_COUNT; ++i)
        if (PRECONDITIONERS[i].value == value) return PRECONDITIONERS[i].name;
    snprintf(buf, sizeof buf, "preconditioner_%d", value);
    return buf;
}

static const char *INTEGRATOR_NAMES[4] = { "symplectic_euler", "backward_euler_linearized", "backward_euler_newton", "bdf2" };
static const char *INTEGRATOR_SHORT[4] = { "se", "lbe", "be", "bdf2" };

typedef struct options {
    int n;
    int integrator;
    cloth_pcg_options cg;
    char material_name[64];
    cloth_material material;
    int bending;
    int bending_model;
    int lumped;                          /* piece def bending_lumped (-Z) */
    double wind;
    int runs, frames, pilot, header, threads;
    double budget, limit;
    double strain_limit, strain_limit_stiffening;
    int substeps, newton_max;            /* world def substeps and newton_max_iterations; 0: the library's */
    double newton_tolerance;             /* world def newton_tolerance; 0: the library's */
    double jitter;                       /* run k starts k jitter metres higher (-y) */
    int sweep_parts;                     /* world def multigrid.sweep_parts (-G); -1: the library's */
    char skip[200];
} options;

static int current_run; /* the run being set up (for -y) */

static void usage(void)
{
    fprintf(stderr, "usage: dynamics scene|payuse|accuracy|knobs|preconditioners [-n N] [-i se|lbe|be|bdf2] [-t TOL] [-m MAXIT]\n"
                    "       [-p PRECONDITIONER] [-M MATERIAL] [-b 0|1] [-K q|d] [-Z 0|1|2] [-w WIND] [-u SUBSTEPS] [-N NEWTON_MAX] [-r RUNS] [-y JITTER] [-G PARTS] [-f FRAMES] [-B SECONDS]\n"
                    "       [-P PILOT_FRAMES] [-L SECONDS] [-H]   (see the top of bench/dynamics.c)\n");
    exit(2);
}

static int parse_material(const char *name, cloth_material *m)
{
    const char *x = strstr(name, "x");
    if (strncmp(name, "cotton", 6) == 0 && x && x == name + 6) {
        double k = atof(x + 1);
        if (!(k > 0)) return 0;
        *m = cloth_default_material();
        m->stretch_warp *= (cloth_real)k;
        m->stretch_weft *= (cloth_real)k;
        m->stretch_coupling *= (cloth_real)k;
        m->shear *= (cloth_real)k;
    } else if (cloth_material_preset(name, m) != CLOTH_SUCCESS)
        return 0;
    m->areal_density = (cloth_real)0.1; /* the scene's */
    return cloth_material_validate(m) == CLOTH_SUCCESS;
}

static void parse(int argc, char **argv, int first, options *o)
{
    int i;
    memset(o, 0, sizeof *o);
    o->n = 32;
    o->integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    o->cg = cloth_default_pcg_options();
    strcpy(o->material_name, "cotton");
    o->bending = 1;
    o->runs = 3;
    o->frames = 120;
    o->header = 1;
    o->limit = 120;
    o->strain_limit_stiffening = (double)cloth_default_piece_def().strain_limit_stiffening;
    o->sweep_parts = -1;
    for (i = first; i < argc; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "-H") == 0) { o->header = 0; continue; }
        if (a[0] != '-' || strlen(a) != 2 || !v) usage();
        ++i;
        switch (a[1]) {
        case 'n': o->n = atoi(v); break;
        case 'i': {
            int k, found = -1;
            for (k = 0; k < 4; ++k)
                if (strcmp(v, INTEGRATOR_SHORT[k]) == 0 || strcmp(v, INTEGRATOR_NAMES[k]) == 0) found = k;
            if (found < 0) usage();
            o->integrator = found;
            break;
        }
        case 't': o->cg.tolerance = (cloth_real)atof(v); break;
        case 'm': o->cg.max_iterations = atoi(v); break;
        case 'p': {
            int k, found = 0;
            for (k = 0; k < PRECONDITIONER_COUNT; ++k)
                if (strcmp(v, PRECONDITIONERS[k].name) == 0) { o->cg.preconditioner = (cloth_preconditioner)PRECONDITIONERS[k].value; found = 1; }
            if (!found) {
                /* NUMBER, or NAME=NUMBER for a value this build's table does not name */
                const char *eq = strchr(v, '='), *num = eq ? eq + 1 : v;
                char *end;
                long value = strtol(num, &end, 10);
                if (*end || end == num) { fprintf(stderr, "dynamics: unknown preconditioner %s\n", v); exit(2); }
                o->cg.preconditioner = (cloth_preconditioner)value;
                if (eq && (size_t)(eq - v) < sizeof extra_preconditioner) {
                    memcpy(extra_preconditioner, v, (size_t)(eq - v));
                    extra_preconditioner[eq - v] = 0;
                    extra_preconditioner_value = (int)value;
                }
            }
            break;
        }
        case 'M': snprintf(o->material_name, sizeof o->material_name, "%s", v); break;
        case 'b': o->bending = atoi(v); break;
        case 'Z': o->lumped = atoi(v); break;
        case 'K': o->bending_model = v[0] == 'd' ? (int)CLOTH_BENDING_DIHEDRAL : (int)CLOTH_BENDING_QUADRATIC; break;
        case 'w': o->wind = atof(v); break;
        case 'l': o->strain_limit = atof(v); break;
        case 's': o->strain_limit_stiffening = atof(v); break;
        case 'r': o->runs = atoi(v); break;
        case 'j': o->threads = atoi(v); break;
        case 'u': o->substeps = atoi(v); break;
        case 'N': o->newton_max = atoi(v); break;
        case 'f': o->frames = atoi(v); break;
        case 'B': o->budget = atof(v); break;
        case 'y': o->jitter = atof(v); break;
        case 'G': o->sweep_parts = atoi(v); break;
        case 'P': o->pilot = atoi(v); break;
        case 'L': o->limit = atof(v); break;
        case 'S': snprintf(o->skip, sizeof o->skip, "%s", v); break;
        default: usage();
        }
    }
    if (o->n < 2 || o->runs < 1 || o->frames < 1) usage();
    if (!parse_material(o->material_name, &o->material)) {
        fprintf(stderr, "dynamics: unknown or invalid material %s\n", o->material_name);
        exit(2);
    }
    if (o->strain_limit > 0) {
        size_t used = strlen(o->material_name);
        snprintf(o->material_name + used, sizeof o->material_name - used, "+limit%gx%g", o->strain_limit, o->strain_limit_stiffening);
    }
    if (o->lumped) {
        size_t used = strlen(o->material_name);
        snprintf(o->material_name + used, sizeof o->material_name - used, o->lumped == 2 ? "+lumped_preconditioner" : "+lumped");
    }
}

/* ---- the scene ---------------------------------------------------------------------- */

typedef struct scene {
    cloth_world *world;
    int32_t piece, vertex_count, edge_like;
    counter mem;
    warnings warn;
} scene;

static cloth_result scene_make(scene *s, const options *o)
{
    cloth_mesh m;
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = cloth_default_piece_def();
    cloth_real ke, pe, el;
    cloth_result r;
    int32_t i;
    memset(&s->mem, 0, sizeof s->mem);
    memset(&s->warn, 0, sizeof s->warn);
    s->world = NULL;
    d.integrator = (cloth_integrator)o->integrator;
    d.cg = o->cg;
    if (o->sweep_parts >= 0) d.multigrid.sweep_parts = o->sweep_parts;
    d.threads = o->threads;
    if (o->substeps > 0) d.substeps = o->substeps;
    if (o->newton_max > 0) d.newton_max_iterations = o->newton_max;
    if (o->newton_tolerance > 0) d.newton_tolerance = (cloth_real)o->newton_tolerance;
    d.wind[2] = (cloth_real)o->wind;
    d.allocator.alloc = count_alloc;
    d.allocator.free = count_free;
    d.allocator.user = &s->mem;
    d.logger.log = count_log;
    d.logger.user = &s->warn;
    d.clock = cpu_clock;
    p.material = o->material;
    p.bending = o->bending;
    p.bending_model = (cloth_bending_model)o->bending_model;
    p.bending_lumped = o->lumped;
    p.strain_limit = (cloth_real)o->strain_limit;
    p.strain_limit_stiffening = (cloth_real)o->strain_limit_stiffening;
    r = cloth_mesh_grid(&m, o->n, o->n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) return r;
    for (i = 0; i < m.vertex_count; ++i) m.x[3 * i + 1] = (cloth_real)(1 + o->jitter * current_run);
    r = cloth_world_create(&s->world, &d);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(s->world, &m, &p, &s->piece);
    /* vertex (i, j) = j n + i with z = j / (n - 1) - 0.5: the corners at z = -0.5 are 0 and n - 1 */
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(s->world, s->piece, 0, NULL);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(s->world, s->piece, o->n - 1, NULL);
    s->vertex_count = m.vertex_count;
    cloth_mesh_free(&m);
    if (r == CLOTH_SUCCESS) cloth_world_energy(s->world, &ke, &pe, &el); /* builds the element lists now */
    if (r != CLOTH_SUCCESS) {
        cloth_world_destroy(s->world);
        s->world = NULL;
    }
    return r;
}

static double lowest_y(const scene *s)
{
    const cloth_real *x = cloth_world_positions(s->world, s->piece);
    double y = 1e30;
    int32_t i;
    for (i = 0; i < s->vertex_count; ++i)
        if (x[3 * i + 1] < y) y = x[3 * i + 1];
    return y;
}

/* What one run measures. */
typedef struct run_result {
    cloth_result status;
    int frames_done;
    double setup_cpu, setup_wall;
    double step_cpu, step_wall;          /* all frames, s */
    double assembly, solve, total;       /* sums of cloth_step_stats, s */
    long cg, newton, substeps, line_search, calls, retries;
    long cg_max_frame, substeps_max_frame;
    long newton_not_converged_frames;
    double strain_end, strain_worst, lowest;
    int strain_worst_frame;
    size_t peak_bytes;
    long step_allocations;
    long cg_capped, newton_capped;
    double checksum;                     /* sum of final positions: runs must agree */
    double deviation_max, deviation_end; /* accuracy mode: largest vertex distance to the reference run */
    double corner_sag_end;               /* accuracy mode: mean y of the two free corners at the end */
    double energy_start, energy_end;     /* kinetic + gravitational + elastic, J */
} run_result;

/* accuracy mode: the reference run's positions after every frame (NULL: no comparison) */
static double *reference_x = NULL;
static int reference_frames = 0;
static int reference_record = 0; /* 1: run_scene records its frames into reference_x instead */

/* One run of `frames` frames (from a fresh world). */
static void run_scene(const options *o, int frames, run_result *res)
{
    scene s;
    double c0, w0;
    int f, k = 1;
    memset(res, 0, sizeof *res);
    c0 = cpu_s();
    w0 = wall_s();
    res->status = scene_make(&s, o);
    res->setup_cpu = cpu_s() - c0;
    res->setup_wall = wall_s() - w0;
    if (res->status != CLOTH_SUCCESS) return;
    if (o->integrator == CLOTH_INTEGRATOR_SYMPLECTIC_EULER) {
        double hs = (double)cloth_world_stable_time_step(s.world);
        k = hs > 0 ? (int)ceil(FRAME_DT / (0.9 * hs)) : 1;
        if (k < 1) k = 1;
    }
    res->lowest = 1e30;
    {
        cloth_real ke, pe, el;
        cloth_world_energy(s.world, &ke, &pe, &el);
        res->energy_start = (double)ke + (double)pe + (double)el;
    }
    {
        long allocs_before = s.mem.allocations;
        for (f = 0; f < frames; ++f) {
            cloth_step_stats st;
            long cg_frame = 0, sub_frame = 0, done = 0;
            double c1, w1, strain, y;
            cloth_result r = CLOTH_SUCCESS;
            c1 = cpu_s();
            w1 = wall_s();
            if (o->integrator == CLOTH_INTEGRATOR_SYMPLECTIC_EULER) {
                /* the rest of the frame in calls of FRAME_DT / k */
                double left = FRAME_DT;
                while (left > 1e-15) {
                    double h = FRAME_DT / k;
                    if (h > left) h = left;
                    r = cloth_world_step(s.world, (cloth_real)h, &st);
                    res->calls++;
                    res->assembly += st.time_assembly;
                    res->solve += st.time_solve;
                    res->total += st.time_total;
                    if (r == CLOTH_ERROR_UNSTABLE) {
                        int k2 = (int)ceil(1.25 * k);
                        k = k2 > k ? k2 : k + 1;
                        res->retries++;
                        if (k > 10000000) break;
                        continue;
                    }
                    if (r != CLOTH_SUCCESS) break;
                    left -= h;
                    sub_frame += st.substeps;
                }
            } else {
                r = cloth_world_step(s.world, (cloth_real)FRAME_DT, &st);
                res->calls++;
                res->assembly += st.time_assembly;
                res->solve += st.time_solve;
                res->total += st.time_total;
                cg_frame = st.cg_iterations;
                sub_frame = st.substeps;
                res->newton += st.newton_iterations;
                res->line_search += st.line_search_halvings;
                if (!st.newton_converged) res->newton_not_converged_frames++;
                done = 1;
            }
            res->step_cpu += cpu_s() - c1;
            res->step_wall += wall_s() - w1;
            (void)done;
            if (r != CLOTH_SUCCESS) { res->status = r; break; }
            res->cg += cg_frame;
            res->substeps += sub_frame;
            if (cg_frame > res->cg_max_frame) res->cg_max_frame = cg_frame;
            if (sub_frame > res->substeps_max_frame) res->substeps_max_frame = sub_frame;
            /* metrics, outside the timed region */
            strain = (double)cloth_world_max_edge_strain(s.world, s.piece);
            if (strain > res->strain_worst) { res->strain_worst = strain; res->strain_worst_frame = f + 1; }
            res->strain_end = strain;
            y = lowest_y(&s);
            if (y < res->lowest) res->lowest = y;
            res->frames_done = f + 1;
            if (reference_x && f < reference_frames) {
                const cloth_real *x = cloth_world_positions(s.world, s.piece);
                double *xr = reference_x + 3 * (size_t)s.vertex_count * (size_t)f;
                double dmax = 0;
                int32_t q;
                if (reference_record)
                    for (q = 0; q < 3 * s.vertex_count; ++q) xr[q] = (double)x[q];
                for (q = 0; q < s.vertex_count; ++q) {
                    double dx = (double)x[3 * q] - xr[3 * q], dy = (double)x[3 * q + 1] - xr[3 * q + 1];
                    double dz = (double)x[3 * q + 2] - xr[3 * q + 2], dd = sqrt(dx * dx + dy * dy + dz * dz);
                    if (dd > dmax) dmax = dd;
                }
                if (dmax > res->deviation_max) res->deviation_max = dmax;
                res->deviation_end = dmax;
            }
        }
        res->step_allocations = s.mem.allocations - allocs_before;
    }
    {
        const cloth_real *x = cloth_world_positions(s.world, s.piece);
        int32_t i;
        for (i = 0; i < 3 * s.vertex_count; ++i) res->checksum += (double)x[i];
        /* the free corners: (0, n-1) and (n-1, n-1), vertex j n + i */
        res->corner_sag_end = 0.5 * ((double)x[3 * ((o->n - 1) * o->n) + 1] + (double)x[3 * (o->n * o->n - 1) + 1]);
    }
    {
        cloth_real ke, pe, el;
        cloth_world_energy(s.world, &ke, &pe, &el);
        res->energy_end = (double)ke + (double)pe + (double)el;
    }
    res->peak_bytes = s.mem.peak;
    res->cg_capped = s.warn.cg_capped;
    res->newton_capped = s.warn.newton_capped;
    cloth_world_destroy(s.world);
}

static void config_columns_header(void)
{
    printf("scene,n,vertices,integrator,material,c11_n_per_m,bending,wind_m_per_s,preconditioner,cg_tolerance,cg_max_iterations,");
}

static void config_columns(const options *o)
{
    printf("hang,%d,%d,%s,%s,%.6g,%d,%.6g,%s,%.3g,%d,", o->n, o->n * o->n, INTEGRATOR_NAMES[o->integrator], o->material_name,
           (double)o->material.stretch_warp, o->bending, o->wind, preconditioner_name((int)o->cg.preconditioner),
           (double)o->cg.tolerance, (int)o->cg.max_iterations);
}

static int mode_scene(const options *o)
{
    run_result *res = (run_result *)calloc((size_t)o->runs, sizeof(run_result));
    double *cpu = (double *)calloc((size_t)o->runs, sizeof(double)), *wall = (double *)calloc((size_t)o->runs, sizeof(double));
    double *setup_c = (double *)calloc((size_t)o->runs, sizeof(double)), *setup_w = (double *)calloc((size_t)o->runs, sizeof(double));
    const char *status = "ok";
    char status_buf[160];
    int runs = 0, i, mid = 0, frames = o->frames, identical = 1;
    double used = 0;
    if (!res || !cpu || !wall || !setup_c || !setup_w) return 1;
    if (o->header) {
        config_columns_header();
        printf("frames,runs,status,setup_ms_cpu,setup_ms_wall,ms_per_frame_cpu,ms_per_frame_cpu_min,ms_per_frame_cpu_max,"
               "ms_per_frame_wall,ms_per_frame_wall_min,ms_per_frame_wall_max,substeps_per_frame,substeps_max_frame,"
               "unstable_retries,cg_per_frame,cg_max_frame,newton_per_frame,line_search_halvings,cg_capped_solves,"
               "newton_capped_frames,assembly_ms_per_frame,solve_ms_per_frame,other_ms_per_frame,assembly_share,solve_share,"
               "strain_end,strain_worst,strain_worst_frame,lowest_y,peak_bytes,bytes_per_vertex,step_allocations,runs_identical\n");
    }
    if (o->skip[0]) {
        config_columns(o);
        printf("0,0,\"skipped: %s\"", o->skip);
        for (i = 0; i < 30; ++i) printf(","); /* the 30 figure columns, empty */
        printf("\n");
        free(res); free(cpu); free(wall); free(setup_c); free(setup_w);
        return 0;
    }
    if (o->pilot > 0 && o->pilot < o->frames) {
        /* estimate the full run from a short one */
        double estimate;
        run_scene(o, o->pilot, &res[0]);
        estimate = res[0].step_cpu * (double)o->frames / (double)o->pilot;
        if (res[0].status == CLOTH_SUCCESS && estimate > o->limit) {
            snprintf(status_buf, sizeof status_buf, "skipped: %d-frame pilot projects %.0f s CPU per run > %.0f s; figures from the pilot",
                     o->pilot, estimate, o->limit);
            status = status_buf;
            runs = 1;
            frames = o->pilot;
            cpu[0] = res[0].step_cpu;
            wall[0] = res[0].step_wall;
            setup_c[0] = res[0].setup_cpu;
            setup_w[0] = res[0].setup_wall;
        }
    }
    if (runs == 0) {
        for (i = 0; i < o->runs; ++i) {
            current_run = i;
            run_scene(o, frames, &res[i]);
            cpu[i] = res[i].step_cpu;
            wall[i] = res[i].step_wall;
            setup_c[i] = res[i].setup_cpu;
            setup_w[i] = res[i].setup_wall;
            runs = i + 1;
            used += res[i].step_cpu;
            {
                const double done = res[i].frames_done ? res[i].frames_done : 1;
                fprintf(stderr, "  run %d: %.2f ms/frame CPU, %.2f wall, %.3f solves per frame (%s)\n", i + 1, 1e3 * cpu[i] / done,
                        1e3 * wall[i] / done, (double)res[i].newton / done, cloth_result_string(res[i].status));
            }
            if (res[i].status != CLOTH_SUCCESS) break;
            /* the budget: no run that would take the total past it (judged by the mean so far) */
            if (o->budget > 0 && used + used / (i + 1) > o->budget) break;
        }
        if (res[runs - 1].status != CLOTH_SUCCESS) {
            snprintf(status_buf, sizeof status_buf, "failed at frame %d: %s", res[runs - 1].frames_done + 1,
                     cloth_result_string(res[runs - 1].status));
            status = status_buf;
            frames = res[runs - 1].frames_done > 0 ? res[runs - 1].frames_done : 1;
        }
    }
    /* the run whose CPU time is the median gives the phase split */
    {
        double m = median(cpu, runs), best = 1e300;
        for (i = 0; i < runs; ++i)
            if (fabs(cpu[i] - m) < best) { best = fabs(cpu[i] - m); mid = i; }
        for (i = 1; i < runs; ++i)
            if (res[i].checksum != res[0].checksum || res[i].cg != res[0].cg) identical = 0;
    }
    if (res[mid].frames_done == 0 && res[mid].status != CLOTH_SUCCESS) {
        /* nothing to report but the failure */
        config_columns(o);
        printf("0,%d,\"%s\"", runs, status);
        for (i = 0; i < 30; ++i) printf(",");
        printf("\n");
        free(res); free(cpu); free(wall); free(setup_c); free(setup_w);
        return 0;
    }
    {
        const run_result *r = &res[mid];
        double fr = (double)frames;
        double ms = 1e3 / fr;
        double other = r->total - r->assembly - r->solve;
        for (i = 0; i < runs; ++i) { cpu[i] *= ms; wall[i] *= ms; }
        config_columns(o);
        printf("%d,%d,\"%s\",%.3f,%.3f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%ld,%ld,%.2f,%ld,%.3f,%ld,%ld,%ld,%.4f,%.4f,%.4f,%.4f,%.4f,"
               "%.6f,%.6f,%d,%.6f,%zu,%.1f,%ld,%d\n",
               frames, runs, status, 1e3 * median(setup_c, runs), 1e3 * median(setup_w, runs), median(cpu, runs), vmin(cpu, runs),
               vmax(cpu, runs), median(wall, runs), vmin(wall, runs), vmax(wall, runs), (double)r->substeps / fr, r->substeps_max_frame,
               r->retries, (double)r->cg / fr, r->cg_max_frame, (double)r->newton / fr, r->line_search, r->cg_capped, r->newton_capped,
               r->assembly * ms, r->solve * ms, other * ms, r->total > 0 ? r->assembly / r->total : 0,
               r->total > 0 ? r->solve / r->total : 0, r->strain_end, r->strain_worst, r->strain_worst_frame, r->lowest, r->peak_bytes,
               (double)r->peak_bytes / (double)(o->n * o->n), r->step_allocations, identical);
    }
    free(res); free(cpu); free(wall); free(setup_c); free(setup_w);
    return 0;
}

/* ---- pay for what you use ----------------------------------------------------------- */

/* The number of 3x3 blocks of the world's system matrix for this scene, rebuilt from the
   public API the way the world lays it out (its pattern holds the pairs of every element:
   the mesh edges for the membrane, and for bending each hinge's four vertices, i.e. the
   edges plus the pair of opposite vertices). Gives the size of the damping matrix the world
   keeps on the same pattern (9 reals per block). -1 on failure. */
static int32_t matrix_blocks(int n, int bending)
{
    cloth_mesh m;
    cloth_topology t;
    cloth_block_matrix a;
    int32_t *pair, count = 0, e, blocks = -1;
    if (cloth_mesh_grid(&m, n, n, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return -1;
    if (cloth_topology_build(&t, &m, NULL) != CLOTH_SUCCESS) { cloth_mesh_free(&m); return -1; }
    pair = (int32_t *)malloc(sizeof(int32_t) * 4 * (size_t)t.edge_count);
    for (e = 0; pair && e < t.edge_count; ++e) {
        pair[2 * count] = t.edge_vertex[2 * e];
        pair[2 * count + 1] = t.edge_vertex[2 * e + 1];
        count++;
        if (bending && t.edge_opposite[2 * e] >= 0 && t.edge_opposite[2 * e + 1] >= 0) {
            pair[2 * count] = t.edge_opposite[2 * e];
            pair[2 * count + 1] = t.edge_opposite[2 * e + 1];
            count++;
        }
    }
    if (pair && cloth_block_matrix_create(&a, m.vertex_count, pair, count, NULL) == CLOTH_SUCCESS) {
        blocks = a.block_count;
        cloth_block_matrix_free(&a);
    }
    free(pair);
    cloth_topology_free(&t);
    cloth_mesh_free(&m);
    return blocks;
}

/* The cost of one step from a fixed state: a reference run (bending on, no wind) to
   t = 1 s gives x, v; then for each variant a fresh world gets that state and takes `reps`
   steps, each from the same state (set_positions / set_velocities before it), so every step
   does the same work. Medians over the repetitions of the phase times of cloth_step_stats
   (assembly, solve, other = total - assembly - solve: wind forces, state backup, health
   check) and of the step's CPU time. */
static int mode_payuse(const options *base, int reps)
{
    options o = *base;
    scene s;
    cloth_real *x = NULL, *v = NULL;
    int32_t nv;
    int f, variant;
    struct { const char *name; int bending; double wind; } variants[4] = {
        { "membrane+gravity (bending off, no wind)", 0, 0 },
        { "membrane+bending (no wind)", 1, 0 },
        { "membrane+bending+wind 5 m/s", 1, 5 },
        { "membrane+wind 5 m/s (bending off)", 0, 5 },
    };
    o.bending = 1;
    o.wind = 0;
    if (scene_make(&s, &o) != CLOTH_SUCCESS) return 1;
    for (f = 0; f < 60; ++f)
        if (o.integrator == CLOTH_INTEGRATOR_SYMPLECTIC_EULER) {
            fprintf(stderr, "dynamics payuse: use an implicit integrator\n");
            return 1;
        } else if (cloth_world_step(s.world, (cloth_real)FRAME_DT, NULL) != CLOTH_SUCCESS) {
            fprintf(stderr, "dynamics payuse: reference run failed\n");
            return 1;
        }
    nv = s.vertex_count;
    x = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)nv);
    v = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)nv);
    memcpy(x, cloth_world_positions(s.world, s.piece), sizeof(cloth_real) * 3 * (size_t)nv);
    memcpy(v, cloth_world_velocities(s.world, s.piece), sizeof(cloth_real) * 3 * (size_t)nv);
    cloth_world_destroy(s.world);
    if (base->header) {
        config_columns_header();
        printf("variant,reps,step_ms_cpu,step_ms_cpu_min,step_ms_cpu_max,step_ms_wall,assembly_ms,assembly_ms_min,assembly_ms_max,"
               "solve_ms,other_ms,other_ms_min,other_ms_max,cg_iterations,newton_iterations,peak_bytes,bytes_per_vertex,"
               "matrix_blocks,matrix_bytes_per_vertex\n");
    }
    for (variant = 0; variant < 4; ++variant) {
        double *step_c = (double *)calloc((size_t)reps, sizeof(double)), *step_w = (double *)calloc((size_t)reps, sizeof(double));
        double *as = (double *)calloc((size_t)reps, sizeof(double)), *so = (double *)calloc((size_t)reps, sizeof(double));
        double *ot = (double *)calloc((size_t)reps, sizeof(double));
        cloth_step_stats st;
        int rep;
        int32_t blocks;
        memset(&st, 0, sizeof st);
        o.bending = variants[variant].bending;
        o.wind = variants[variant].wind;
        if (scene_make(&s, &o) != CLOTH_SUCCESS) return 1;
        for (rep = 0; rep < reps; ++rep) {
            double c0, w0;
            cloth_world_set_positions(s.world, s.piece, x);
            cloth_world_set_velocities(s.world, s.piece, v);
            c0 = cpu_s();
            w0 = wall_s();
            if (cloth_world_step(s.world, (cloth_real)FRAME_DT, &st) != CLOTH_SUCCESS) {
                fprintf(stderr, "dynamics payuse: step failed\n");
                return 1;
            }
            step_c[rep] = 1e3 * (cpu_s() - c0);
            step_w[rep] = 1e3 * (wall_s() - w0);
            as[rep] = 1e3 * st.time_assembly;
            so[rep] = 1e3 * st.time_solve;
            ot[rep] = 1e3 * (st.time_total - st.time_assembly - st.time_solve);
        }
        config_columns(&o);
        blocks = matrix_blocks(o.n, o.bending);
        printf("\"%s\",%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%d,%d,%zu,%.1f,%d,%.1f\n", variants[variant].name, reps,
               median(step_c, reps), vmin(step_c, reps), vmax(step_c, reps), median(step_w, reps), median(as, reps), vmin(as, reps),
               vmax(as, reps), median(so, reps), median(ot, reps), vmin(ot, reps), vmax(ot, reps), (int)st.cg_iterations,
               (int)st.newton_iterations, s.mem.peak, (double)s.mem.peak / (double)nv, (int)blocks,
               72.0 * (double)blocks / (double)nv);
        cloth_world_destroy(s.world);
        free(step_c); free(step_w); free(as); free(so); free(ot);
    }
    free(x);
    free(v);
    return 0;
}

/* ---- accuracy against speed ------------------------------------------------------------ */

/* The CG tolerance as a speed-accuracy knob: a reference run at tolerance 1e-9 (untimed) keeps
   every frame's positions; then for each tolerance of the list, `runs` timed runs (median)
   and, from the median run, the largest distance of any vertex from the reference over all
   frames and at the end, the strain, and the free corners' height at the end. */
static int mode_accuracy(const options *base, const char *tolerances)
{
    options o = *base;
    run_result ref, *res;
    double *cpu;
    char list[256], *tok;
    o.cg.tolerance = (cloth_real)1e-9;
    o.cg.max_iterations = 5000;
    reference_frames = o.frames;
    reference_x = (double *)malloc(sizeof(double) * 3 * (size_t)o.n * (size_t)o.n * (size_t)o.frames);
    res = (run_result *)calloc((size_t)o.runs, sizeof(run_result));
    cpu = (double *)calloc((size_t)o.runs, sizeof(double));
    if (!reference_x || !res || !cpu) return 1;
    /* the reference: one run that records every frame */
    memset(&ref, 0, sizeof ref);
    reference_record = 1;
    run_scene(&o, o.frames, &ref);
    reference_record = 0;
    if (ref.status != CLOTH_SUCCESS) { fprintf(stderr, "reference failed\n"); return 1; }
    if (o.header) {
        config_columns_header();
        printf("runs,ms_per_frame_cpu,assembly_ms_per_frame,solve_ms_per_frame,cg_per_frame,cg_max_frame,strain_end,strain_worst,"
               "corner_y_end,corner_y_error_end,deviation_max_m,deviation_end_m\n");
    }
    snprintf(list, sizeof list, "%s", tolerances);
    for (tok = strtok(list, " ,"); tok; tok = strtok(NULL, " ,")) {
        int i, mid = 0;
        double m, best = 1e300, ms = 1e3 / (double)o.frames;
        o.cg.tolerance = (cloth_real)atof(tok);
        o.cg.max_iterations = base->cg.max_iterations;
        for (i = 0; i < o.runs; ++i) {
            run_scene(&o, o.frames, &res[i]);
            cpu[i] = res[i].step_cpu;
            if (res[i].status != CLOTH_SUCCESS) { fprintf(stderr, "tolerance %s failed\n", tok); return 1; }
        }
        m = median(cpu, o.runs);
        for (i = 0; i < o.runs; ++i)
            if (fabs(cpu[i] - m) < best) { best = fabs(cpu[i] - m); mid = i; }
        config_columns(&o);
        printf("%d,%.4f,%.4f,%.4f,%.2f,%ld,%.6f,%.6f,%.6f,%.3g,%.3g,%.3g\n", o.runs, m * ms, res[mid].assembly * ms,
               res[mid].solve * ms, (double)res[mid].cg / (double)o.frames, res[mid].cg_max_frame, res[mid].strain_end,
               res[mid].strain_worst, res[mid].corner_sag_end, res[mid].corner_sag_end - ref.corner_sag_end,
               res[mid].deviation_max, res[mid].deviation_end);
        fflush(stdout);
    }
    free(reference_x);
    reference_x = NULL;
    free(res);
    free(cpu);
    return 0;
}

/* ---- the integrator, the step and Newton's cap against speed ------------------------------ */

/* One knob row: `runs` timed runs of o (median) and its distance from the reference frames. */
static int knob_row(const options *o, const char *knob, const char *value, const run_result *ref, run_result *res, double *cpu)
{
    int i, mid = 0;
    double m, best = 1e300, ms = 1e3 / (double)o->frames;
    for (i = 0; i < o->runs; ++i) {
        run_scene(o, o->frames, &res[i]);
        cpu[i] = res[i].step_cpu;
        if (res[i].status != CLOTH_SUCCESS) { fprintf(stderr, "knobs: %s %s failed\n", knob, value); return 1; }
    }
    m = median(cpu, o->runs);
    for (i = 0; i < o->runs; ++i)
        if (fabs(cpu[i] - m) < best) { best = fabs(cpu[i] - m); mid = i; }
    printf("%s,%s,", knob, value);
    config_columns(o);
    printf("%d,%d,%d,%.4f,%.2f,%.2f,%.6f,%.6f,%.6f,%.3g,%.3g,%.3g,%.6g\n", o->substeps > 0 ? o->substeps : 1,
           o->newton_max > 0 ? o->newton_max : 20, o->runs, m * ms, (double)res[mid].cg / (double)o->frames,
           (double)res[mid].newton / (double)o->frames, res[mid].strain_end, res[mid].strain_worst, res[mid].corner_sag_end,
           res[mid].corner_sag_end - ref->corner_sag_end, res[mid].deviation_max, res[mid].deviation_end,
           res[mid].energy_start - res[mid].energy_end);
    fflush(stdout);
    return 0;
}

/* The reference run (its time is not reported): BDF2, Newton converged, fine steps; every
   frame kept in reference_x, its figures in ref. */
static int knob_reference(const options *base, int substeps, run_result *ref)
{
    options o = *base;
    o.integrator = CLOTH_INTEGRATOR_BDF2;
    o.substeps = substeps;
    o.newton_max = 50;
    o.newton_tolerance = 1e-7; /* m/s, the library's is 1e-5 */
    o.cg.tolerance = (cloth_real)1e-9;
    o.cg.max_iterations = 5000;
    reference_frames = o.frames;
    reference_x = (double *)malloc(sizeof(double) * 3 * (size_t)o.n * (size_t)o.n * (size_t)o.frames);
    if (!reference_x) return 1;
    memset(ref, 0, sizeof *ref);
    reference_record = 1;
    run_scene(&o, o.frames, ref);
    reference_record = 0;
    return ref->status != CLOTH_SUCCESS;
}

static int mode_knobs(const options *base)
{
    options o = *base;
    run_result ref, *res = (run_result *)calloc((size_t)base->runs, sizeof(run_result));
    double *cpu = (double *)calloc((size_t)base->runs, sizeof(double));
    const char *env = getenv("DYNAMICS_REFERENCE_SUBSTEPS");
    int reference_substeps = env ? atoi(env) : 32, k, fail = 0;
    static const int substeps[] = { 2, 4, 8 }, newton[] = { 1, 2, 3, 5 };
    static const int integrators[] = { CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED, CLOTH_INTEGRATOR_BACKWARD_EULER, CLOTH_INTEGRATOR_BDF2 };
    char value[32];
    if (!res || !cpu || reference_substeps < 1) return 1;
    if (knob_reference(base, reference_substeps, &ref)) return 1;
    if (o.header) {
        printf("knob,value,");
        config_columns_header();
        printf("substeps,newton_max,runs,ms_per_frame_cpu,cg_per_frame,newton_per_frame,strain_end,strain_worst,corner_y_end,"
               "corner_y_error_end,deviation_max_m,deviation_end_m,energy_lost_j\n");
        /* the reference as a row of its own (untimed: ms 0) */
        printf("reference,bdf2x%d,", reference_substeps);
        o.integrator = CLOTH_INTEGRATOR_BDF2;
        config_columns(&o);
        printf("%d,50,1,0,%.2f,%.2f,%.6f,%.6f,%.6f,0,0,0,%.6g\n", reference_substeps, (double)ref.cg / (double)o.frames,
               (double)ref.newton / (double)o.frames, ref.strain_end, ref.strain_worst, ref.corner_sag_end,
               ref.energy_start - ref.energy_end);
        o = *base;
    }
    for (k = 0; k < 3 && !fail; ++k) {
        o = *base;
        o.integrator = integrators[k];
        o.substeps = 1;
        fail = knob_row(&o, "integrator", INTEGRATOR_SHORT[integrators[k]], &ref, res, cpu);
    }
    for (k = 0; k < 3 && !fail; ++k) {
        o = *base;
        o.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
        o.substeps = substeps[k];
        snprintf(value, sizeof value, "%d", substeps[k]);
        fail = knob_row(&o, "substeps", value, &ref, res, cpu);
    }
    for (k = 0; k < 4 && !fail; ++k) {
        o = *base;
        o.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER;
        o.substeps = 1;
        o.newton_max = newton[k];
        snprintf(value, sizeof value, "%d", newton[k]);
        fail = knob_row(&o, "newton", value, &ref, res, cpu);
    }
    free(reference_x);
    reference_x = NULL;
    free(res);
    free(cpu);
    return fail;
}

int main(int argc, char **argv)
{
    options o;
    if (argc < 2) usage();
    if (strcmp(argv[1], "preconditioners") == 0) {
        int i;
        for (i = 0; i < PRECONDITIONER_COUNT; ++i) printf("%s\n", PRECONDITIONERS[i].name);
        return 0;
    }
    parse(argc, argv, 2, &o);
    if (strcmp(argv[1], "scene") == 0) return mode_scene(&o);
    if (strcmp(argv[1], "payuse") == 0) return mode_payuse(&o, o.runs);
    if (strcmp(argv[1], "knobs") == 0) return mode_knobs(&o);
    if (strcmp(argv[1], "accuracy") == 0) return mode_accuracy(&o, getenv("DYNAMICS_TOLERANCES") ? getenv("DYNAMICS_TOLERANCES") : "1e-2 3e-3 1e-3 3e-4 1e-4 1e-5");
    usage();
    return 2;
}
