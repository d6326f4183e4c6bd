/* stress_scenes.h - docs/scenes.md's contact stress scenes (sphere, funnel, twist, stack, projectile,
   capsule) built through cloth.h's public world API, and the measurements taken after every
   step: intersecting cloth triangle pairs by the exact checker (tests/exact_tritri.h, apart
   from cloth.h's collision code), penetration into obstacles, edge strain, lowest point, step
   failures, and for the projectile whether the sphere got through the cloth. Used by
   bench/stress.c (full scenes) and tests/test_stress.c (short ones). Include cloth.h (the
   declarations; CLOTH_REAL double) first. All functions are static.

   The scenes (SI units, y up, 60 frames per second, one world step per frame, n vertices per
   side of a square cloth, self-collision on everywhere; friction 0.5 unless said):
     sphere      1 m x 1 m at y = 1 over a static sphere r = 0.3 at the origin, 3 s.
     funnel      1 m x 1 m at y = 1 into an open inverted square pyramid, a 4-triangle mesh
                 obstacle (top opening 0.8 m x 0.8 m at y = 0.6, apex at the origin), 3 s.
     twist       1 m (x) x 0.5 m (z) at y = 1 (n x ((n - 1) / 2 + 1) vertices); every vertex of the
                 two short edges is a handle turning about the long axis (x, through y = 1,
                 z = 0) by 2 turns, the two edges in opposite directions, while each edge moves
                 0.1 m inward (0.2 m together), uniformly over the 4 s.
     stack       three 0.8 m x 0.8 m cloths flat at y = 0.5, 0.6, 0.7 over a 0.4 m cube (box
                 obstacle, centre y = 0.2) on the ground plane y = 0; piece collision on, 3 s.
     projectile  1 m x 1 m vertical in the plane z = 0 (centre (0, 1, 0)), pinned at its 4
                 corners; a kinematic sphere r = 0.05 moving along +z through the centre at
                 50 m/s from z = -0.3 (set_obstacle_pose every frame), 0.5 s.
     capsule     1 m x 1 m at y = 1 over a capsule along x at the origin, radius 0.15,
                 half_length 0.3 (a 0.6 m cylinder between the hemispheres), spinning about its
                 axis at 1 turn/s (set_obstacle_pose every frame), 3 s.
     projectile_mesh  the projectile with the sphere as a mesh obstacle (an icosahedron
                 subdivided once, 42 vertices, 80 triangles, vertices on r = 0.05), which
                 the contact module meets by CCD rather than vertex by vertex (not in docs/scenes.md).

   Measurements (stress_metrics): penetration is the deepest any cloth vertex got inside an
   analytic obstacle (cloth_world_obstacle_distance < 0), after every step; for the funnel's
   mesh obstacle, whose distance is unsigned, the exact checker counts cloth triangles that
   intersect the obstacle's triangles instead (obstacle_pairs), and the smallest vertex
   distance to it is reported. The projectile is "through" once the sphere is entirely beyond
   every cloth vertex (centre z - r > max z of the cloth). */
#ifndef STRESS_SCENES_H
#define STRESS_SCENES_H
#ifndef CLOTH_H
#error "include cloth.h before stress_scenes.h"
#endif
#include "exact_tritri.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define STRESS_PI 3.14159265358979323846
#define STRESS_MAX_PIECES 3

typedef enum stress_scene_id { STRESS_SPHERE, STRESS_FUNNEL, STRESS_TWIST, STRESS_STACK, STRESS_PROJECTILE, STRESS_CAPSULE,
                               STRESS_PROJECTILE_MESH, STRESS_SCENE_COUNT } stress_scene_id;

static const char *const stress_scene_names[STRESS_SCENE_COUNT] = {"sphere", "funnel", "twist", "stack", "projectile", "capsule",
                                                                   "projectile_mesh"};
/* simulated seconds of each scene */
static const double stress_scene_seconds[STRESS_SCENE_COUNT] = {3, 3, 4, 3, 0.5, 3, 0.5};

/* One twist handle: where the vertex starts and which way its edge turns and moves. */
typedef struct stress_handle { double x0[3]; double sign; } stress_handle;

typedef struct stress_scene {
    stress_scene_id id;
    int32_t n;
    cloth_world *world;
    int32_t pieces, piece_vertices[STRESS_MAX_PIECES];
    int32_t obstacle_count, obstacle[3];
    int obstacle_is_mesh[3];
    /* the mesh obstacle (funnel, projectile_mesh): vertices in its frame and in the world now */
    double mesh_local[3 * 42], mesh_world[3 * 42];
    int32_t mesh_tri[3 * 80], mesh_vertex_count, mesh_triangle_count;
    stress_handle *handles;       /* twist */
    int32_t frame;                /* frames stepped (attempted) */
    int32_t stepped;              /* of them, the steps that succeeded: the world's time is
                                     stepped dt (a failed step leaves it, and the world, as
                                     they were) */
    double dt;
} stress_scene;

typedef struct stress_metrics {
    int32_t frames, failed_steps, unresolved_steps, other_errors, last_error;
    double *frame_ms;             /* per-frame CPU time of cloth_world_step (ms), capacity entries */
    int32_t capacity;
    double time_assembly, time_solve, time_collide, time_total; /* sums from cloth_step_stats (s) */
    long impacts, obstacle_contacts;
    long qp_iterations, substep_redos, collide_stops; /* successful steps' (cloth_step_stats) */
    int32_t max_impact_zones;
    long pairs_total, pairs_max;  /* intersecting cloth-cloth triangle pairs after each step */
    int32_t pairs_first_frame;    /* first frame with pairs, -1 none */
    long obstacle_pairs_max;      /* cloth-obstacle-mesh intersecting pairs (funnel) */
    double check_seconds;         /* CPU time of the exact checks */
    double penetration;           /* deepest vertex inside an analytic obstacle (m, >= 0) */
    double min_obstacle_distance; /* smallest vertex distance to any obstacle (m; negative inside) */
    double strain_worst, strain_end, lowest_y;
    int projectile_through;       /* the sphere got entirely beyond every cloth vertex */
    int32_t projectile_through_frame;
    int checker_error;            /* the checker refused (coordinates out of range) */
} stress_metrics;

static double stress__cpu(void *user) { (void)user; return (double)clock() / CLOCKS_PER_SEC; }

static void stress__twist_handle(double time, cloth_real position[3], void *user)
{
    const stress_handle *h = (const stress_handle *)user;
    double s = time / 4.0, a, y, z;
    if (s > 1) s = 1;
    a = h->sign * 2 * 2 * STRESS_PI * s;
    y = h->x0[1] - 1;
    z = h->x0[2];
    position[0] = (cloth_real)(h->x0[0] + h->sign * 0.1 * s); /* sign +1 at x = -0.5: moves to +x */
    position[1] = (cloth_real)(1 + y * cos(a) - z * sin(a));
    position[2] = (cloth_real)(y * sin(a) + z * cos(a));
}

static cloth_pose stress__sphere_pose(double t)
{
    cloth_real tr[3], axis[3] = {0, 0, 0};
    tr[0] = 0;
    tr[1] = 1;
    tr[2] = (cloth_real)(-0.3 + 50 * t);
    return cloth_pose_make(tr, axis, 0);
}

static cloth_pose stress__capsule_pose(double t)
{
    cloth_real tr[3] = {0, 0, 0}, axis[3] = {1, 0, 0};
    return cloth_pose_make(tr, axis, (cloth_real)(2 * STRESS_PI * t));
}

/* The mesh obstacle's world vertices for a pose. */
static void stress__pose_mesh(stress_scene *s, const cloth_pose *pose)
{
    int32_t i;
    for (i = 0; i < s->mesh_vertex_count; ++i) {
        cloth_real p[3], q[3];
        int k;
        for (k = 0; k < 3; ++k) p[k] = (cloth_real)s->mesh_local[3 * i + k];
        cloth_pose_apply(pose, p, q);
        for (k = 0; k < 3; ++k) s->mesh_world[3 * i + k] = q[k];
    }
}

/* Add the scene's mesh (mesh_local, mesh_tri) as an obstacle with od's pose. */
static cloth_result stress__add_mesh_obstacle(stress_scene *s, cloth_obstacle_def *od)
{
    cloth_real xr[3 * 42];
    int32_t i;
    for (i = 0; i < 3 * s->mesh_vertex_count; ++i) xr[i] = (cloth_real)s->mesh_local[i];
    od->shape = CLOTH_OBSTACLE_MESH;
    od->mesh_x = xr;
    od->mesh_vertex_count = s->mesh_vertex_count;
    od->mesh_tri = s->mesh_tri;
    od->mesh_triangle_count = s->mesh_triangle_count;
    stress__pose_mesh(s, &od->pose);
    s->obstacle_is_mesh[s->obstacle_count] = 1;
    return cloth_world_add_obstacle(s->world, od, &s->obstacle[s->obstacle_count++]);
}

/* An icosahedron subdivided once (42 vertices, 80 outward triangles) with vertices on the
   sphere of radius r, into mesh_local / mesh_tri. */
static void stress__icosphere(stress_scene *s, double r)
{
    static const int32_t face[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                        {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    double g = (1 + sqrt(5.0)) / 2, v[42][3];
    int32_t count = 12, f, k, e, mid[3], i;
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    memcpy(v, base, sizeof base);
    s->mesh_triangle_count = 0;
    for (f = 0; f < 20; ++f) {
        for (e = 0; e < 3; ++e) {
            int32_t a = face[f][e], b = face[f][(e + 1) % 3];
            double m[3];
            for (k = 0; k < 3; ++k) m[k] = 0.5 * (v[a][k] + v[b][k]);
            for (i = 12; i < count; ++i)
                if (v[i][0] == m[0] && v[i][1] == m[1] && v[i][2] == m[2]) break;
            if (i == count) { memcpy(v[count], m, sizeof m); ++count; }
            mid[e] = i;
        }
        {
            const int32_t t[4][3] = {{face[f][0], mid[0], mid[2]}, {face[f][1], mid[1], mid[0]}, {face[f][2], mid[2], mid[1]},
                                     {mid[0], mid[1], mid[2]}};
            memcpy(s->mesh_tri + 3 * s->mesh_triangle_count, t, sizeof t);
            s->mesh_triangle_count += 4;
        }
    }
    for (i = 0; i < count; ++i) {
        double l = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
        for (k = 0; k < 3; ++k) s->mesh_local[3 * i + k] = r * v[i][k] / l;
    }
    s->mesh_vertex_count = count;
}

/* The collision thickness of the scenes made after it is set, m: the world def's
   collision_thickness (cloth-cloth) and every obstacle's thickness; 0 (the default) keeps the
   library's 1 mm. bench/stress.c sets it from STRESS_THICKNESS (the thickness knob). */
static double stress_thickness = 0;
/* The world def's threads for every scene (0: the default, single-threaded; bench/stress.c
   sets it from STRESS_THREADS; more than 1 needs cloth.h built with CLOTH_THREADS). */
static int32_t stress_threads = 0;
/* The world def's multigrid.sweep_parts for every scene (-1: the library's default;
   bench/stress.c sets it from STRESS_SWEEP_PARTS). */
static int32_t stress_sweep_parts = -1;
/* The world def's cg.tolerance and obstacle_iterations for every scene (0: the library's
   defaults; bench/stress.c sets them from STRESS_CG_TOLERANCE and STRESS_OBSTACLE_ITERATIONS,
   the contact scenes' speed knobs). */
static double stress_cg_tolerance = 0;
static int32_t stress_obstacle_iterations = 0;
/* The world def's obstacle_trial_tolerance (bench/stress: STRESS_TRIAL_TOLERANCE); 0: none. */
static double stress_trial_tolerance = 0;
/* The world def's obstacle_trial_multigrid_update (bench/stress: STRESS_TRIAL_UPDATE);
   negative: the library's. */
static int stress_trial_update = -1;
/* The world def's obstacle_hold_touching_only (bench/stress: STRESS_HOLD_TOUCHING); negative:
   the library's. */
static int stress_hold_touching = -1;
/* The pieces' bending_lumped (bench/stress: STRESS_BENDING_LUMPED); 0: the library's. */
static int stress_bending_lumped = 0;
/* The pieces' bending_model (bench/stress: STRESS_BENDING_MODEL, 0 quadratic, 1 dihedral);
   negative: the library's. */
static int stress_bending_model = -1;
/* The world def's multigrid.max_levels (bench/stress: STRESS_MG_LEVELS); 0: the library's. */
static int32_t stress_mg_levels = 0;
/* The world def's multigrid.strength_threshold and prolongator_damping (bench/stress:
   STRESS_STRENGTH; bench/paired.c); negative: the library's. */
static double stress_strength_threshold = -1, stress_prolongator_damping = -1;
/* The world def's collision_strain_stop (tests/test_stress.c); negative: the library's. */
static double stress_collision_strain_stop = -1;
/* The clock of stress_step's frame times in seconds (NULL: process CPU time, clock()); a
   bench on several threads sets a wall clock. */
static double (*stress_frame_clock)(void) = NULL;
/* A host task system for every scene's world def (NULL: none). */
static const cloth_task_system *stress_tasks = NULL;

/* Build a scene with n vertices per side; returns CLOTH_SUCCESS or the first error. */
static cloth_result stress_scene_create(stress_scene *s, stress_scene_id id, int32_t n)
{
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def pd = cloth_default_piece_def();
    cloth_obstacle_def od = cloth_default_obstacle_def();
    cloth_mesh m;
    cloth_result r;
    int32_t i, p, nx = n, ny = n;
    double w = 1, d = 1;
    memset(s, 0, sizeof *s);
    s->id = id;
    s->n = n;
    s->dt = 1.0 / 60;
    def.self_collision = 1;
    def.piece_collision = id == STRESS_STACK;
    def.clock = stress__cpu;
    if (stress_thickness > 0) def.collision_thickness = od.thickness = (cloth_real)stress_thickness;
    def.threads = stress_threads;
    if (stress_sweep_parts >= 0) def.multigrid.sweep_parts = stress_sweep_parts;
    if (stress_mg_levels > 0) def.multigrid.max_levels = stress_mg_levels;
    if (stress_strength_threshold >= 0) def.multigrid.strength_threshold = (cloth_real)stress_strength_threshold;
    if (stress_prolongator_damping >= 0) def.multigrid.prolongator_damping = (cloth_real)stress_prolongator_damping;
    if (stress_cg_tolerance > 0) def.cg.tolerance = (cloth_real)stress_cg_tolerance;
    if (stress_obstacle_iterations > 0) def.obstacle_iterations = stress_obstacle_iterations;
    if (stress_trial_tolerance > 0) def.obstacle_trial_tolerance = (cloth_real)stress_trial_tolerance;
    if (stress_trial_update >= 0) def.obstacle_trial_multigrid_update = stress_trial_update;
    if (stress_hold_touching >= 0) def.obstacle_hold_touching_only = stress_hold_touching;
    if (stress_collision_strain_stop >= 0) def.collision_strain_stop = (cloth_real)stress_collision_strain_stop;
    if (stress_tasks) def.tasks = *stress_tasks;
    pd.material.areal_density = (cloth_real)0.1;
    pd.bending_lumped = stress_bending_lumped;
    if (stress_bending_model >= 0) pd.bending_model = (cloth_bending_model)stress_bending_model;
    r = cloth_world_create(&s->world, &def);
    if (r != CLOTH_SUCCESS) return r;
    if (id == STRESS_TWIST) { d = 0.5; ny = (n - 1) / 2 + 1; }
    if (id == STRESS_STACK) w = d = 0.8;
    s->pieces = id == STRESS_STACK ? 3 : 1;
    for (p = 0; p < s->pieces; ++p) {
        r = cloth_mesh_grid(&m, nx, ny, (cloth_real)w, (cloth_real)d, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
        if (r != CLOTH_SUCCESS) return r;
        for (i = 0; i < m.vertex_count; ++i) {
            if (id == STRESS_PROJECTILE || id == STRESS_PROJECTILE_MESH) { /* vertical: grid z becomes height */
                m.x[3 * i + 1] = 1 - m.x[3 * i + 2];
                m.x[3 * i + 2] = 0;
            } else if (id == STRESS_STACK) {
                m.x[3 * i + 1] = (cloth_real)(0.5 + 0.1 * p);
            } else {
                m.x[3 * i + 1] = 1;
            }
        }
        r = cloth_world_add_piece(s->world, &m, &pd, &i);
        s->piece_vertices[p] = m.vertex_count;
        cloth_mesh_free(&m);
        if (r != CLOTH_SUCCESS) return r;
    }
    switch (id) {
    case STRESS_SPHERE:
        od.shape = CLOTH_OBSTACLE_SPHERE;
        od.radius = (cloth_real)0.3;
        od.friction_static = od.friction_kinetic = (cloth_real)0.5;
        r = cloth_world_add_obstacle(s->world, &od, &s->obstacle[s->obstacle_count++]);
        break;
    case STRESS_FUNNEL: {
        static const double corner[4][2] = {{-0.4, -0.4}, {0.4, -0.4}, {0.4, 0.4}, {-0.4, 0.4}};
        for (i = 0; i < 3; ++i) s->mesh_local[i] = 0;
        for (i = 0; i < 4; ++i) {
            s->mesh_local[3 * (i + 1)] = corner[i][0];
            s->mesh_local[3 * (i + 1) + 1] = 0.6;
            s->mesh_local[3 * (i + 1) + 2] = corner[i][1];
            /* inward-facing walls: apex, next corner, corner */
            s->mesh_tri[3 * i] = 0;
            s->mesh_tri[3 * i + 1] = 1 + (i + 1) % 4;
            s->mesh_tri[3 * i + 2] = 1 + i;
        }
        s->mesh_vertex_count = 5;
        s->mesh_triangle_count = 4;
        r = stress__add_mesh_obstacle(s, &od);
        break;
    }
    case STRESS_TWIST: {
        int32_t count = 0, j, side;
        const cloth_real *x = cloth_world_positions(s->world, 0);
        s->handles = (stress_handle *)malloc(2 * (size_t)ny * sizeof *s->handles);
        if (!s->handles) return CLOTH_ERROR_OUT_OF_MEMORY;
        for (side = 0; side < 2 && r == CLOTH_SUCCESS; ++side)
            for (j = 0; j < ny && r == CLOTH_SUCCESS; ++j) {
                int32_t v = j * nx + (side ? nx - 1 : 0);
                stress_handle *h = s->handles + count++;
                h->x0[0] = x[3 * v];
                h->x0[1] = x[3 * v + 1];
                h->x0[2] = x[3 * v + 2];
                h->sign = side ? -1 : 1;
                r = cloth_world_set_handle(s->world, 0, v, stress__twist_handle, h);
            }
        break;
    }
    case STRESS_STACK:
        od.shape = CLOTH_OBSTACLE_PLANE;
        r = cloth_world_add_obstacle(s->world, &od, &s->obstacle[s->obstacle_count++]);
        if (r != CLOTH_SUCCESS) break;
        od.shape = CLOTH_OBSTACLE_BOX;
        od.half_extents[0] = od.half_extents[1] = od.half_extents[2] = (cloth_real)0.2;
        od.pose.translation[1] = (cloth_real)0.2;
        r = cloth_world_add_obstacle(s->world, &od, &s->obstacle[s->obstacle_count++]);
        break;
    case STRESS_PROJECTILE: {
        static const int32_t corners[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
        for (i = 0; i < 4 && r == CLOTH_SUCCESS; ++i)
            r = cloth_world_pin(s->world, 0, corners[i][1] * (ny - 1) * nx + corners[i][0] * (nx - 1), NULL);
        if (r != CLOTH_SUCCESS) break;
        od.shape = CLOTH_OBSTACLE_SPHERE;
        od.radius = (cloth_real)0.05;
        od.pose = stress__sphere_pose(0);
        r = cloth_world_add_obstacle(s->world, &od, &s->obstacle[s->obstacle_count++]);
        break;
    }
    case STRESS_PROJECTILE_MESH:
        for (i = 0; i < 4 && r == CLOTH_SUCCESS; ++i) {
            static const int32_t corners[4][2] = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
            r = cloth_world_pin(s->world, 0, corners[i][1] * (ny - 1) * nx + corners[i][0] * (nx - 1), NULL);
        }
        if (r != CLOTH_SUCCESS) break;
        stress__icosphere(s, 0.05);
        od.pose = stress__sphere_pose(0);
        r = stress__add_mesh_obstacle(s, &od);
        break;
    case STRESS_CAPSULE:
        od.shape = CLOTH_OBSTACLE_CAPSULE;
        od.radius = (cloth_real)0.15;
        od.half_length = (cloth_real)0.3;
        od.friction_static = od.friction_kinetic = (cloth_real)0.5;
        r = cloth_world_add_obstacle(s->world, &od, &s->obstacle[s->obstacle_count++]);
        break;
    default:
        break;
    }
    return r;
}

static void stress_scene_destroy(stress_scene *s)
{
    cloth_world_destroy(s->world);
    free(s->handles);
    memset(s, 0, sizeof *s);
}

static void stress_metrics_init(stress_metrics *m, int32_t frames)
{
    memset(m, 0, sizeof *m);
    m->frame_ms = (double *)calloc((size_t)(frames > 0 ? frames : 1), sizeof(double));
    m->capacity = m->frame_ms ? frames : 0;
    m->pairs_first_frame = -1;
    m->projectile_through_frame = -1;
    m->lowest_y = HUGE_VAL;
    m->min_obstacle_distance = HUGE_VAL;
}

static void stress_metrics_free(stress_metrics *m) { free(m->frame_ms); m->frame_ms = NULL; }

/* The exact check of the current state: cloth-cloth pairs (self and between pieces) and, for
   a mesh obstacle, cloth-obstacle pairs. */
static void stress_check(stress_scene *s, stress_metrics *m)
{
    exact_mesh em[STRESS_MAX_PIECES + 1];
    long counts[(STRESS_MAX_PIECES + 1) * (STRESS_MAX_PIECES + 1)], cloth_pairs = 0, obstacle_pairs = 0, got;
    int32_t p, q, k = 0, i;
    clock_t c0 = clock();
    for (p = 0; p < s->pieces; ++p) {
        cloth_mesh mesh = cloth_world_mesh(s->world, p);
        em[k].x = mesh.x;
        em[k].tri = mesh.tri;
        em[k].triangle_count = mesh.triangle_count;
        em[k].self = 1;
        ++k;
    }
    for (i = 0; i < s->obstacle_count; ++i)
        if (s->obstacle_is_mesh[i]) {
            em[k].x = s->mesh_world;
            em[k].tri = s->mesh_tri;
            em[k].triangle_count = s->mesh_triangle_count;
            em[k].self = 0;
            ++k;
        }
    got = exact_count_intersecting_pairs(em, k, counts);
    if (got < 0) { m->checker_error = 1; return; }
    for (p = 0; p < k; ++p)
        for (q = p; q < k; ++q) {
            if (q < s->pieces) cloth_pairs += counts[p * k + q];
            else obstacle_pairs += counts[p * k + q];
        }
    m->pairs_total += cloth_pairs;
    if (cloth_pairs > m->pairs_max) m->pairs_max = cloth_pairs;
    if (cloth_pairs > 0 && m->pairs_first_frame < 0) m->pairs_first_frame = s->frame;
    if (obstacle_pairs > m->obstacle_pairs_max) m->obstacle_pairs_max = obstacle_pairs;
    m->check_seconds += (double)(clock() - c0) / CLOCKS_PER_SEC;
}

/* Advance one frame (kinematic poses first) and measure. Returns the step's result. */
static cloth_result stress_step(stress_scene *s, stress_metrics *m)
{
    cloth_step_stats st;
    cloth_result r;
    clock_t c0;
    /* the kinematic obstacles' poses for the end of this step, from the world's time (the
       steps that succeeded): after a failed step the next one tries the same frame again
       rather than moving the obstacle two frames at once */
    double t_end = (s->stepped + 1) * s->dt, strain, wall0;
    int32_t p, i, o;
    if (s->id == STRESS_PROJECTILE || s->id == STRESS_PROJECTILE_MESH) {
        cloth_pose pose = stress__sphere_pose(t_end);
        cloth_world_set_obstacle_pose(s->world, s->obstacle[0], &pose);
    } else if (s->id == STRESS_CAPSULE) {
        cloth_pose pose = stress__capsule_pose(t_end);
        cloth_world_set_obstacle_pose(s->world, s->obstacle[0], &pose);
    }
    memset(&st, 0, sizeof st);
    c0 = clock();
    wall0 = stress_frame_clock ? stress_frame_clock() : 0;
    r = cloth_world_step(s->world, (cloth_real)s->dt, &st);
    if (m->frames < m->capacity)
        m->frame_ms[m->frames] = stress_frame_clock ? 1000.0 * (stress_frame_clock() - wall0) : 1000.0 * (double)(clock() - c0) / CLOCKS_PER_SEC;
    ++m->frames;
    ++s->frame;
    if (r == CLOTH_SUCCESS) ++s->stepped;
    if (r != CLOTH_SUCCESS) {
        ++m->failed_steps;
        if (r == CLOTH_ERROR_COLLISION_UNRESOLVED) ++m->unresolved_steps;
        else ++m->other_errors;
        m->last_error = (int32_t)r;
    } else {
        m->time_assembly += st.time_assembly;
        m->time_solve += st.time_solve;
        m->time_collide += st.time_collide;
        m->time_total += st.time_total;
        m->impacts += st.impacts;
        m->obstacle_contacts += st.obstacle_contacts;
        m->qp_iterations += st.qp_iterations;
        m->substep_redos += st.substep_redos;
        m->collide_stops += st.collide_stops;
        if (st.impact_zones > m->max_impact_zones) m->max_impact_zones = st.impact_zones;
    }
    if (s->id == STRESS_PROJECTILE_MESH) { /* where the world has the sphere now */
        cloth_pose pose = stress__sphere_pose(cloth_world_time(s->world));
        stress__pose_mesh(s, &pose);
    }
    stress_check(s, m);
    for (p = 0; p < s->pieces; ++p) {
        const cloth_real *x = cloth_world_positions(s->world, p);
        for (i = 0; i < s->piece_vertices[p]; ++i) {
            if (x[3 * i + 1] < m->lowest_y) m->lowest_y = x[3 * i + 1];
            for (o = 0; o < s->obstacle_count; ++o) {
                double dist = (double)cloth_world_obstacle_distance(s->world, s->obstacle[o], x + 3 * i);
                if (dist < m->min_obstacle_distance) m->min_obstacle_distance = dist;
                if (!s->obstacle_is_mesh[o] && -dist > m->penetration) m->penetration = -dist;
            }
        }
        strain = (double)cloth_world_max_edge_strain(s->world, p);
        if (strain > m->strain_worst) m->strain_worst = strain;
    }
    m->strain_end = 0;
    for (p = 0; p < s->pieces; ++p) {
        strain = (double)cloth_world_max_edge_strain(s->world, p);
        if (strain > m->strain_end) m->strain_end = strain;
    }
    if (s->id == STRESS_PROJECTILE || s->id == STRESS_PROJECTILE_MESH) {
        /* the sphere's centre, where the world has it after this step */
        double zc = -0.3 + 50 * cloth_world_time(s->world), zmax = -HUGE_VAL;
        const cloth_real *x = cloth_world_positions(s->world, 0);
        for (i = 0; i < s->piece_vertices[0]; ++i)
            if (x[3 * i + 2] > zmax) zmax = x[3 * i + 2];
        if (zc - 0.05 > zmax && !m->projectile_through) {
            m->projectile_through = 1;
            m->projectile_through_frame = s->frame;
        }
    }
    return r;
}

/* Frames of the full scene. */
static int32_t stress_scene_frames(stress_scene_id id) { return (int32_t)(stress_scene_seconds[id] * 60 + 0.5); }

static int stress__cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Median of the per-frame step times (ms); sorts a copy. */
static double stress_median_ms(const stress_metrics *m)
{
    double *c, med;
    if (m->frames <= 0) return 0;
    c = (double *)malloc((size_t)m->frames * sizeof(double));
    if (!c) return -1;
    memcpy(c, m->frame_ms, (size_t)m->frames * sizeof(double));
    qsort(c, (size_t)m->frames, sizeof(double), stress__cmp_double);
    med = m->frames % 2 ? c[m->frames / 2] : 0.5 * (c[m->frames / 2 - 1] + c[m->frames / 2]);
    free(c);
    return med;
}
#endif
