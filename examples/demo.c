/* demo.c - the flagship scene of `make demo`: docs/scenes.md's "sphere" scene.

   A 1 m x 1 m cloth (n x n vertices, areal density 0.1 kg/m^2) is dropped flat from y = 1 onto
   a static sphere of radius 0.3 at the origin (friction 0.5) with self-collision on, and drapes
   over it in folds for 3 s at 60 frames per second (one world step per frame, the default
   integrator), with strain limiters at 5% (piece def strain_limit), a CG tolerance of 1e-3
   (world def cg.tolerance; the library's default is 1e-4) and at most 2 solves per step while
   the cloth's contacts with the sphere change (world def obstacle_iterations; the library's
   default is 4): the impact frame's edges stretch about 5.5% instead of 14%, in about half of
   the time (bench/results/sphere.md). Writes an OBJ file per frame into build/demo/frames/, the sphere as
   build/demo/sphere.obj (to view the frames in another tool), PNG pictures of four chosen frames
   into build/demo/, a contact sheet of those four into examples/demo.png (the README's picture),
   and a summary line.

   Every frame the demo checks, apart from the library's contact code, the deepest any cloth
   vertex got inside the sphere (cloth_world_obstacle_distance) and the largest edge strain. A
   step that returns an error is counted, the world is left as it was (cloth_world_step
   guarantees that), and the frame is retried as two half steps (then four quarter steps); the
   demo goes on either way.

   What it shows of cloth.h: a world with one piece and an analytic obstacle, self-collision,
   Coulomb friction, strain limiting, the step statistics of the collide phase, and mesh
   writing. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#define RENDER_IMPLEMENTATION
#include "render.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>

#define DEMO_N 32            /* vertices per side (the whole run takes ~8 s on a 2-core VM) */
#define DEMO_FPS 60
#define DEMO_SECONDS 3
#define DEMO_RADIUS 0.3
#define DEMO_W 480           /* one picture; the contact sheet is 2 x 2 of them */
#define DEMO_H 360

static double cpu_seconds(void *user) { (void)user; return (double)clock() / CLOCKS_PER_SEC; }

static void progress(int frame, int frames)
{
    int width = 40, filled = width * frame / frames, i;
    if (frame != frames && 100 * frame / frames == 100 * (frame - 1) / frames) return; /* redraw on change */
    printf("\r  [");
    for (i = 0; i < width; ++i) putchar(i < filled ? '#' : '.');
    printf("] %3d%%  frame %d/%d", 100 * frame / frames, frame, frames);
    fflush(stdout);
}

/* The step statistics summed over a frame (a frame may take several calls when one fails). */
typedef struct demo_totals {
    double step_cpu, collide;
    long impacts, doublings, redos, obstacle_constraints, failed;
    int32_t impact_zones;
    cloth_result last_error;
} demo_totals;

/* Advance the world by dt. A failed step leaves the world as it was; it is counted and the
   interval is retried as two halves, down to quarters. Returns the last error when even that
   fails (the rest of the interval is then skipped). */
static cloth_result advance(cloth_world *world, double dt, int depth, demo_totals *t)
{
    cloth_step_stats st;
    double c0 = cpu_seconds(NULL);
    cloth_result r = cloth_world_step(world, (cloth_real)dt, &st);
    t->step_cpu += cpu_seconds(NULL) - c0;
    if (r == CLOTH_SUCCESS) {
        t->collide += st.time_collide;
        t->impacts += st.impacts;
        t->doublings += st.substep_doublings > 0; /* frames that ran on more substeps */
        t->redos += st.substep_redos;
        t->obstacle_constraints += st.obstacle_constraints;
        if (st.impact_zones > t->impact_zones) t->impact_zones = st.impact_zones;
        return r;
    }
    ++t->failed;
    t->last_error = r;
    if (depth >= 2) return r;
    r = advance(world, dt / 2, depth + 1, t);
    if (r == CLOTH_SUCCESS) r = advance(world, dt / 2, depth + 1, t);
    return r;
}

/* Draw the sphere and the cloth as it is now into img. */
static void draw(render_image *img, const cloth_world *world, int32_t piece)
{
    static const double eye[3] = { 1.25, 0.95, 1.6 }, target[3] = { 0.0, 0.17, 0.0 };
    static const double front[3] = { 0.86, 0.33, 0.27 }, back[3] = { 0.95, 0.78, 0.45 };
    static const double ball[3] = { 0.45, 0.58, 0.78 }, centre[3] = { 0, 0, 0 };
    render_camera cam = render_look_at(eye, target, 38);
    cloth_mesh m = cloth_world_mesh(world, piece);
    double *x = (double *)malloc(sizeof(double) * 3 * (size_t)m.vertex_count);
    int32_t i;
    if (!x) return;
    for (i = 0; i < 3 * m.vertex_count; ++i) x[i] = (double)m.x[i];
    render_floor(img, &cam, -0.45, 1.2);
    /* Drawn 3 mm inside its true radius: the cloth rests 1 mm (the obstacle thickness) above
       the sphere at its vertices, and its flat triangles dip up to ~1.6 mm (n = 24 diagonals)
       below the vertices, which a true-size ball would poke through in the picture. */
    render_sphere(img, &cam, centre, DEMO_RADIUS - 0.003, ball);
    render_mesh_smooth(img, &cam, x, m.vertex_count, m.tri, m.triangle_count, front, back);
    free(x);
}

int main(void)
{
    /* falling, first contact (the cloth reaches the sphere's top at t = 0.378 s, in the step of frame 22),
       folds forming, at rest */
    const int frames = DEMO_FPS * DEMO_SECONDS, shots[4] = { 16, 24, 45, frames - 1 };
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_obstacle_def sphere_def = cloth_default_obstacle_def();
    cloth_world *world = NULL;
    cloth_mesh mesh, ball;
    render_image sheet;
    demo_totals tot;
    int32_t piece, sphere, i;
    int frame, shot = 0, lost_frames = 0, first_contact = -1;
    double penetration = 0, worst_strain = 0, lowest = 1e30, setup_cpu = cpu_seconds(NULL);
    int worst_frame = 0;
    cloth_result r;

    mkdir("build", 0755);
    mkdir("build/demo", 0755);
    mkdir("build/demo/frames", 0755);
    memset(&tot, 0, sizeof tot);

    /* The cloth: flat at y = 1, x and z in [-0.5, 0.5], nothing pinned. */
    r = cloth_mesh_grid(&mesh, DEMO_N, DEMO_N, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) { printf("grid: %s\n", cloth_result_string(r)); return 1; }
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1;

    /* The world: gravity, the default integrator (linearized backward Euler), self-collision;
       phase timings in CPU seconds. */
    def.self_collision = 1;
    def.cg.tolerance = (cloth_real)1e-3; /* with the limiters below: faster, and less strained than 1e-4 without */
    def.obstacle_iterations = 2;          /* with the limiters: 1.4-1.9x faster at 16-48 vertices a side, as strained */
    def.clock = cpu_seconds;
    piece_def.material.areal_density = (cloth_real)0.1;
    piece_def.strain_limit = (cloth_real)0.05; /* edges stiffen steeply beyond 5% */
    sphere_def.shape = CLOTH_OBSTACLE_SPHERE;
    sphere_def.radius = (cloth_real)DEMO_RADIUS;
    sphere_def.friction_static = sphere_def.friction_kinetic = (cloth_real)0.5;
    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_obstacle(world, &sphere_def, &sphere);
    if (r != CLOTH_SUCCESS) { printf("setup: %s\n", cloth_result_string(r)); return 1; }

    /* The sphere as a mesh once, for viewing the OBJ frames elsewhere. */
    if (cloth_mesh_icosphere(&ball, (cloth_real)DEMO_RADIUS, 4, NULL) == CLOTH_SUCCESS) {
        r = cloth_mesh_write_file(&ball, "build/demo/sphere.obj", CLOTH_FORMAT_OBJ);
        if (r != CLOTH_SUCCESS) printf("build/demo/sphere.obj: %s\n", cloth_result_string(r));
        cloth_mesh_free(&ball);
    }
    setup_cpu = cpu_seconds(NULL) - setup_cpu;

    if (!render_init(&sheet, 2 * DEMO_W, 2 * DEMO_H)) return 1;
    printf("cloth.h demo: %d x %d cloth dropped on a sphere (r = %.1f m, friction 0.5), self-collision on, strain limit %.0f%%, CG tolerance %g, "
           "%d obstacle solves, %d frames at %d fps\n", DEMO_N, DEMO_N, DEMO_RADIUS, 100 * (double)piece_def.strain_limit, (double)def.cg.tolerance,
           (int)def.obstacle_iterations, frames, DEMO_FPS);
    for (frame = 0; frame < frames; ++frame) {
        char path[256];
        long impacts_before = tot.impacts, constraints_before = tot.obstacle_constraints;
        const cloth_real *x;
        double strain;
        r = advance(world, 1.0 / DEMO_FPS, 0, &tot);
        if (r != CLOTH_SUCCESS) ++lost_frames;
        if (first_contact < 0 && (tot.impacts > impacts_before || tot.obstacle_constraints > constraints_before)) first_contact = frame;
        /* Checks of the state after every frame, apart from the contact code. */
        x = cloth_world_positions(world, piece);
        for (i = 0; i < mesh.vertex_count; ++i) {
            double d = (double)cloth_world_obstacle_distance(world, sphere, x + 3 * i);
            if (-d > penetration) penetration = -d;
            if (x[3 * i + 1] < lowest) lowest = x[3 * i + 1];
        }
        strain = (double)cloth_world_max_edge_strain(world, piece);
        if (strain > worst_strain) { worst_strain = strain; worst_frame = frame; }
        {
            cloth_mesh view = cloth_world_mesh(world, piece);
            snprintf(path, sizeof path, "build/demo/frames/frame_%04d.obj", frame);
            r = cloth_mesh_write_file(&view, path, CLOTH_FORMAT_OBJ);
            if (r != CLOTH_SUCCESS) { printf("\n%s: %s\n", path, cloth_result_string(r)); return 1; }
        }
        if (shot < 4 && frame == shots[shot]) {
            render_image img;
            int y;
            if (!render_init(&img, DEMO_W, DEMO_H)) return 1;
            draw(&img, world, piece);
            snprintf(path, sizeof path, "build/demo/frame_%04d.png", frame);
            render_write_png(&img, path);
            for (y = 0; y < DEMO_H; ++y)
                memcpy(sheet.rgb + 3 * ((size_t)(y + DEMO_H * (shot / 2)) * sheet.width + DEMO_W * (shot % 2)),
                       img.rgb + 3 * (size_t)y * DEMO_W, 3 * DEMO_W);
            render_free(&img);
            ++shot;
        }
        progress(frame + 1, frames);
    }
    render_write_png(&sheet, "examples/demo.png");
    render_free(&sheet);
    printf("\n%d frames, %.2f ms per frame (CPU, stepping only; setup %.1f ms), %.2f ms collide per frame, %.1f impacts per frame "
           "(largest %d impact zones), max edge strain %.2f%% at the end (worst %.2f%%, frame %d), penetration %.3g m, "
           "lowest y %.3f m, first contact frame %d, %ld frames on more substeps (%ld attempts redone), %ld failed steps (%d frames lost)",
           frames, 1000 * tot.step_cpu / frames, 1000 * setup_cpu, 1000 * tot.collide / frames, (double)tot.impacts / frames,
           (int)tot.impact_zones, 100 * (double)cloth_world_max_edge_strain(world, piece), 100 * worst_strain, worst_frame,
           penetration, lowest, first_contact, tot.doublings, tot.redos, tot.failed, lost_frames);
    if (tot.failed) printf(", last error %s", cloth_result_string(tot.last_error));
    printf("\nframes: build/demo/frames/*.obj (sphere: build/demo/sphere.obj), pictures: build/demo/*.png, contact sheet: examples/demo.png\n");
    cloth_world_destroy(world);
    cloth_mesh_free(&mesh);
    return 0;
}
