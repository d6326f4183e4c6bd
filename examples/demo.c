/* demo.c - the flagship scene of `make demo`.

   A 1 m x 1 m cotton cloth hangs from two corners in a gusty wind; at t = 2 s one corner is
   released and the cloth swings and flaps from the other. Writes an OBJ file per frame into
   build/demo/frames/, PNG pictures of four chosen frames into build/demo/, a contact sheet of
   those four into examples/demo.png (the README's picture), and a summary line.

   What it shows of cloth.h: a world with one piece, pins, wind with seeded gusts, the linearized
   backward Euler integrator, step statistics, and mesh writing. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#define RENDER_IMPLEMENTATION
#include "render.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define DEMO_N 32            /* vertices per side */
#define DEMO_FPS 60
#define DEMO_SECONDS 4
#define DEMO_RELEASE_FRAME (2 * DEMO_FPS)

static void progress(int frame, int frames)
{
    int width = 40, filled = width * frame / frames, i;
    if (frame != frames && 100 * frame / frames == 100 * (frame - 1) / frames) return; /* redraw on change */
    printf("\r  [");
    for (i = 0; i < width; ++i) putchar(i < filled ? '#' : '.');
    printf("] %3d%%  frame %d/%d", 100 * frame / frames, frame, frames);
    fflush(stdout);
}

/* Draw the cloth as it is now into img. */
static void draw(render_image *img, const cloth_world *world, int32_t piece)
{
    static const double eye[3] = { 1.5, 1.35, 1.7 }, target[3] = { 0.0, 0.55, -0.15 };
    static const double front[3] = { 0.86, 0.33, 0.27 }, back[3] = { 0.95, 0.78, 0.45 };
    render_camera cam = render_look_at(eye, target, 45);
    cloth_mesh m = cloth_world_mesh(world, piece);
    double *x = (double *)malloc(sizeof(double) * 3 * (size_t)m.vertex_count);
    int32_t i;
    if (!x) return;
    for (i = 0; i < 3 * m.vertex_count; ++i) x[i] = (double)m.x[i];
    render_floor(img, &cam, -0.15, 1.5);
    render_mesh(img, &cam, x, m.tri, m.triangle_count, front, back);
    free(x);
}

int main(void)
{
    const int frames = DEMO_FPS * DEMO_SECONDS, shots[4] = { 30, DEMO_RELEASE_FRAME - 1, DEMO_RELEASE_FRAME + 24, frames - 1 };
    cloth_world_def def = cloth_default_world_def();
    cloth_piece_def piece_def = cloth_default_piece_def();
    cloth_world *world = NULL;
    cloth_mesh mesh;
    render_image sheet;
    int32_t piece, i;
    int frame, shot = 0;
    long cg_total = 0;
    double solve = 0, total = 0;
    cloth_result r;

    mkdir("build", 0755);
    mkdir("build/demo", 0755);
    mkdir("build/demo/frames", 0755);

    /* The cloth: flat at y = 1, the two corners at z = -0.5 will be pinned. */
    r = cloth_mesh_grid(&mesh, DEMO_N, DEMO_N, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
    if (r != CLOTH_SUCCESS) { printf("grid: %s\n", cloth_result_string(r)); return 1; }
    for (i = 0; i < mesh.vertex_count; ++i) mesh.x[3 * i + 1] = 1;

    /* The world: gravity, a 4 m/s wind along +z with 2.5 m/s gusts, linearized backward Euler. */
    def.wind[2] = 4;
    def.gust_strength = (cloth_real)2.5;
    def.gust_time = (cloth_real)0.4;
    def.seed = 2026;
    def.cg.tolerance = (cloth_real)1e-3;
    def.cg.max_iterations = 2000;
    piece_def.material.damping_stiffness = (cloth_real)2e-3; /* a little stiffness-proportional damping */
    r = cloth_world_create(&world, &def);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(world, &mesh, &piece_def, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(world, piece, 0, NULL);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(world, piece, DEMO_N - 1, NULL);
    if (r != CLOTH_SUCCESS) { printf("setup: %s\n", cloth_result_string(r)); return 1; }

    if (!render_init(&sheet, 2 * 480, 2 * 360)) return 1;
    printf("cloth.h demo: %d x %d cloth, %d frames at %d fps, wind 4 m/s with gusts, release at t = %.1f s\n",
           DEMO_N, DEMO_N, frames, DEMO_FPS, (double)DEMO_RELEASE_FRAME / DEMO_FPS);
    for (frame = 0; frame < frames; ++frame) {
        cloth_step_stats st;
        char path[256];
        if (frame == DEMO_RELEASE_FRAME) cloth_world_unpin(world, piece, DEMO_N - 1);
        r = cloth_world_step(world, (cloth_real)1 / DEMO_FPS, &st);
        if (r != CLOTH_SUCCESS) { printf("\nstep %d: %s\n", frame, cloth_result_string(r)); return 1; }
        cg_total += st.cg_iterations;
        solve += st.time_solve;
        total += st.time_total;
        {
            cloth_mesh view = cloth_world_mesh(world, piece);
            snprintf(path, sizeof path, "build/demo/frames/frame_%04d.obj", frame);
            r = cloth_mesh_write_file(&view, path, CLOTH_FORMAT_OBJ);
            if (r != CLOTH_SUCCESS) { printf("\n%s: %s\n", path, cloth_result_string(r)); return 1; }
        }
        if (shot < 4 && frame == shots[shot]) {
            render_image img;
            int y;
            if (!render_init(&img, 480, 360)) return 1;
            draw(&img, world, piece);
            snprintf(path, sizeof path, "build/demo/frame_%04d.png", frame);
            render_write_png(&img, path);
            for (y = 0; y < 360; ++y)
                memcpy(sheet.rgb + 3 * ((size_t)(y + 360 * (shot / 2)) * sheet.width + 480 * (shot % 2)), img.rgb + 3 * (size_t)y * 480, 3 * 480);
            render_free(&img);
            ++shot;
        }
        progress(frame + 1, frames);
    }
    render_write_png(&sheet, "examples/demo.png");
    render_free(&sheet);
    printf("\n%d steps, %.2f ms per step (%.2f ms in the solver), %.1f CG iterations per step, max edge strain %.2f%%\n",
           frames, 1000 * total / frames, 1000 * solve / frames, (double)cg_total / frames, 100 * (double)cloth_world_max_edge_strain(world, piece));
    printf("frames: build/demo/frames/*.obj, pictures: build/demo/*.png, contact sheet: examples/demo.png\n");
    cloth_world_destroy(world);
    cloth_mesh_free(&mesh);
    return 0;
}
