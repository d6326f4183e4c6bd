/* stress_pictures.c - one picture of each contact stress scene (tests/stress_scenes.h, the
   scenes of bench/stress.c) at a chosen frame, drawn with examples/render.h into a contact
   sheet: bench/results/stress_scenes.png (4 x 2 panels, in the order sphere, funnel, twist,
   stack / projectile, capsule, projectile_mesh). Every step is checked as in bench/stress.c
   (exact triangle-triangle test, penetration); one line per scene says what was drawn.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/stress_pictures bench/stress_pictures.c -lm
       ./build/bench/stress_pictures [N] [OUT.png]          (N = 16 by default, about 2 minutes)

   Obstacles are drawn 3 mm inside their true size, since the cloth rests on their 1 mm
   thickness layer at its vertices and its flat triangles dip below the vertices. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include "../tests/stress_scenes.h"
#define RENDER_IMPLEMENTATION
#include "../examples/render.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PANEL_W 400
#define PANEL_H 300

/* The frame drawn and the camera, per scene (stress_scene_id order). */
typedef struct shot { int32_t frame; double eye[3], target[3], fov; } shot;
static const shot shots[STRESS_SCENE_COUNT] = {
    {179, {1.3, 1.0, 1.7}, {0, 0.1, 0}, 40},         /* sphere: at rest, 3 s */
    {179, {1.2, 1.5, 1.6}, {0, 0.35, 0}, 40},        /* funnel: at rest, 3 s */
    {180, {0.2, 1.6, 1.5}, {0, 1.0, 0}, 42},         /* twist: 3 s of 4, 1.5 turns */
    {179, {1.5, 1.1, 1.9}, {0, 0.25, 0}, 40},        /* stack: at rest, 3 s */
    {1, {2.4, 1.4, 0.9}, {0, 1.0, 0.7}, 48},         /* projectile: 2 frames, the ball 1.4 m on */
    {40, {1.2, 1.2, 1.7}, {0, 0.0, 0}, 42},          /* capsule: 0.68 s, the cloth on the spinning capsule */
    {1, {2.4, 1.4, 0.9}, {0, 1.0, 0.7}, 48},         /* projectile_mesh */
};

static const double cloth_front[3][3] = {{0.86, 0.33, 0.27}, {0.30, 0.62, 0.40}, {0.35, 0.45, 0.80}};
static const double cloth_back[3][3] = {{0.95, 0.78, 0.45}, {0.80, 0.90, 0.60}, {0.75, 0.80, 0.95}};
static const double grey[3] = {0.62, 0.64, 0.68}, ball[3] = {0.45, 0.58, 0.78};

/* A box of half size h about c as 12 triangles, drawn flat. */
static void draw_box(render_image *img, const render_camera *cam, const double c[3], double h)
{
    static const int32_t tri[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 0, 4, 7, 0, 7, 3};
    double x[24];
    int i;
    for (i = 0; i < 8; ++i) {
        x[3 * i] = c[0] + ((i & 1) ^ ((i >> 1) & 1) ? h : -h);
        x[3 * i + 1] = c[1] + (i & 4 ? h : -h);
        x[3 * i + 2] = c[2] + (i & 2 ? h : -h);
    }
    render_mesh(img, cam, x, tri, 12, grey, grey);
}

/* A capsule along x about the origin: a 48-sided cylinder and two balls. */
static void draw_capsule(render_image *img, const render_camera *cam, double radius, double half_length)
{
    enum { SIDES = 48 };
    double x[2 * SIDES * 3], end[3] = {0, 0, 0};
    int32_t tri[6 * SIDES];
    int i;
    for (i = 0; i < SIDES; ++i) {
        double a = 2 * STRESS_PI * i / SIDES;
        int j = (i + 1) % SIDES;
        x[6 * i] = -half_length;
        x[6 * i + 3] = half_length;
        x[6 * i + 1] = x[6 * i + 4] = radius * cos(a);
        x[6 * i + 2] = x[6 * i + 5] = radius * sin(a);
        tri[6 * i] = 2 * i; tri[6 * i + 1] = 2 * j; tri[6 * i + 2] = 2 * i + 1;
        tri[6 * i + 3] = 2 * i + 1; tri[6 * i + 4] = 2 * j; tri[6 * i + 5] = 2 * j + 1;
    }
    render_mesh_smooth(img, cam, x, 2 * SIDES, tri, 2 * SIDES, ball, ball);
    end[0] = -half_length;
    render_sphere(img, cam, end, radius, ball);
    end[0] = half_length;
    render_sphere(img, cam, end, radius, ball);
}

static void draw_scene(render_image *img, const stress_scene *s, const shot *sh)
{
    render_camera cam = render_look_at(sh->eye, sh->target, sh->fov);
    int32_t p, i;
    if (s->id == STRESS_STACK) render_floor(img, &cam, 0, 1.2);
    else if (s->id != STRESS_PROJECTILE && s->id != STRESS_PROJECTILE_MESH) render_floor(img, &cam, -0.5, 1.4);
    switch (s->id) {
    case STRESS_SPHERE: {
        double c[3] = {0, 0, 0};
        render_sphere(img, &cam, c, 0.3 - 0.003, ball);
        break;
    }
    case STRESS_STACK: {
        double c[3] = {0, 0.2, 0};
        draw_box(img, &cam, c, 0.2 - 0.003);
        break;
    }
    case STRESS_PROJECTILE: {
        cloth_pose pose = stress__sphere_pose(cloth_world_time(s->world));
        double c[3];
        for (i = 0; i < 3; ++i) c[i] = (double)pose.translation[i];
        render_sphere(img, &cam, c, 0.05 - 0.003, ball);
        break;
    }
    case STRESS_CAPSULE: draw_capsule(img, &cam, 0.15 - 0.006, 0.3); break; /* 6 mm: 6.7 cm cells on r = 0.15 dip 3.7 mm */
    case STRESS_FUNNEL:
    case STRESS_PROJECTILE_MESH:
        render_mesh(img, &cam, s->mesh_world, s->mesh_tri, s->mesh_triangle_count, grey, grey);
        break;
    default: break;
    }
    for (p = 0; p < s->pieces; ++p) {
        cloth_mesh m = cloth_world_mesh(s->world, p);
        double *x = (double *)malloc(sizeof(double) * 3 * (size_t)m.vertex_count);
        if (!x) return;
        for (i = 0; i < 3 * m.vertex_count; ++i) x[i] = (double)m.x[i];
        render_mesh_smooth(img, &cam, x, m.vertex_count, m.tri, m.triangle_count, cloth_front[p], cloth_back[p]);
        free(x);
    }
}

int main(int argc, char **argv)
{
    int32_t n = argc > 1 ? atoi(argv[1]) : 16;
    const char *out = argc > 2 ? argv[2] : "bench/results/stress_scenes.png";
    render_image sheet;
    int id;
    if (n < 4) return 2;
    if (!render_init(&sheet, 4 * PANEL_W, 2 * PANEL_H)) return 1;
    for (id = 0; id < STRESS_SCENE_COUNT; ++id) {
        const shot *sh = shots + id;
        stress_scene s;
        stress_metrics m;
        render_image img;
        int32_t f, y;
        cloth_result r = stress_scene_create(&s, (stress_scene_id)id, n);
        if (r != CLOTH_SUCCESS) { fprintf(stderr, "%s: %s\n", stress_scene_names[id], cloth_result_string(r)); return 1; }
        if (sh->frame >= stress_scene_frames((stress_scene_id)id)) return 1; /* a shot past the scene's end */
        stress_metrics_init(&m, sh->frame + 1);
        for (f = 0; f <= sh->frame; ++f) stress_step(&s, &m);
        printf("%s n=%d frame %d (t = %.3f s): intersecting pairs max %ld, penetration %.3g m, strain %.1f%% (worst %.1f%%), "
               "failed steps %d, %.1f ms per frame (median)\n", stress_scene_names[id], (int)n, (int)sh->frame,
               (double)cloth_world_time(s.world), m.pairs_max, m.penetration, 100 * m.strain_end, 100 * m.strain_worst,
               (int)m.failed_steps, stress_median_ms(&m));
        fflush(stdout);
        if (!render_init(&img, PANEL_W, PANEL_H)) return 1;
        draw_scene(&img, &s, sh);
        for (y = 0; y < PANEL_H; ++y)
            memcpy(sheet.rgb + 3 * ((size_t)(y + PANEL_H * (id / 4)) * sheet.width + PANEL_W * (id % 4)),
                   img.rgb + 3 * (size_t)y * PANEL_W, 3 * PANEL_W);
        render_free(&img);
        stress_metrics_free(&m);
        stress_scene_destroy(&s);
    }
    if (!render_write_png(&sheet, out)) { fprintf(stderr, "cannot write %s\n", out); return 1; }
    render_free(&sheet);
    printf("contact sheet: %s\n", out);
    return 0;
}
