/* render.h - a small software rasterizer and PNG writer for cloth.h's examples and benchmarks.
   Not part of the library: it draws triangle meshes into an RGB image with a z-buffer, a
   perspective camera and two-sided Lambert shading, and writes the image as a PNG (stored,
   uncompressed deflate blocks, so no zlib is needed).

       render_image img;
       render_camera cam = render_look_at(eye, target, 40.0);
       render_init(&img, 640, 480);              (clears to a sky gradient)
       render_mesh(&img, &cam, x, tri, n_tri, front_rgb, back_rgb);
       render_write_png(&img, "frame.png");
       render_free(&img);

   Define RENDER_IMPLEMENTATION in one file before including. */
#ifndef RENDER_H
#define RENDER_H
#include <stdint.h>

typedef struct render_image { int width, height; unsigned char *rgb; float *depth; } render_image;
typedef struct render_camera { double eye[3], right[3], up[3], forward[3], focal; } render_camera;

render_camera render_look_at(const double eye[3], const double target[3], double fov_degrees);
int render_init(render_image *img, int width, int height);
void render_free(render_image *img);
/* Draw triangles; x is double[3 * vertices], tri int32_t[3 * triangles]. Colours are 0..1 RGB for
   the front side (counter-clockwise seen by the camera) and the back side. */
void render_mesh(render_image *img, const render_camera *cam, const double *x, const int32_t *tri, int32_t triangles,
                 const double front[3], const double back[3]);
/* A horizontal checkerboard floor at height y, size 2*half across, centred under the origin. */
void render_floor(render_image *img, const render_camera *cam, double y, double half);
int render_write_png(const render_image *img, const char *path);
#endif

#ifdef RENDER_IMPLEMENTATION
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void render__normalize(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0) { v[0] /= n; v[1] /= n; v[2] /= n; }
}
static void render__cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

render_camera render_look_at(const double eye[3], const double target[3], double fov_degrees)
{
    render_camera c;
    double world_up[3] = { 0, 1, 0 };
    int k;
    for (k = 0; k < 3; ++k) { c.eye[k] = eye[k]; c.forward[k] = target[k] - eye[k]; }
    render__normalize(c.forward);
    render__cross(c.forward, world_up, c.right);
    render__normalize(c.right);
    render__cross(c.right, c.forward, c.up);
    c.focal = 1.0 / tan(fov_degrees * 3.14159265358979 / 360.0);
    return c;
}

int render_init(render_image *img, int width, int height)
{
    int x, y;
    img->width = width;
    img->height = height;
    img->rgb = (unsigned char *)malloc((size_t)width * height * 3);
    img->depth = (float *)malloc((size_t)width * height * sizeof(float));
    if (!img->rgb || !img->depth) { free(img->rgb); free(img->depth); return 0; }
    for (y = 0; y < height; ++y)
        for (x = 0; x < width; ++x) {
            unsigned char *p = img->rgb + 3 * ((size_t)y * width + x);
            double t = (double)y / height;
            p[0] = (unsigned char)(235 - 60 * t);
            p[1] = (unsigned char)(240 - 45 * t);
            p[2] = (unsigned char)(250 - 20 * t);
            img->depth[(size_t)y * width + x] = 1e30f;
        }
    return 1;
}

void render_free(render_image *img)
{
    free(img->rgb);
    free(img->depth);
    img->rgb = NULL;
    img->depth = NULL;
}

/* Camera space then screen: sx, sy in pixels, sz the view depth. Returns 0 behind the camera. */
static int render__project(const render_image *img, const render_camera *c, const double p[3], double s[3])
{
    double d[3] = { p[0] - c->eye[0], p[1] - c->eye[1], p[2] - c->eye[2] };
    double vx = d[0] * c->right[0] + d[1] * c->right[1] + d[2] * c->right[2];
    double vy = d[0] * c->up[0] + d[1] * c->up[1] + d[2] * c->up[2];
    double vz = d[0] * c->forward[0] + d[1] * c->forward[1] + d[2] * c->forward[2];
    double half_h = img->height * 0.5;
    if (vz < 1e-3) return 0;
    s[0] = img->width * 0.5 + vx / vz * c->focal * half_h;
    s[1] = half_h - vy / vz * c->focal * half_h;
    s[2] = vz;
    return 1;
}

static void render__triangle(render_image *img, const double a[3], const double b[3], const double c[3], const unsigned char rgb[3])
{
    double minx = floor(fmin(a[0], fmin(b[0], c[0]))), maxx = ceil(fmax(a[0], fmax(b[0], c[0])));
    double miny = floor(fmin(a[1], fmin(b[1], c[1]))), maxy = ceil(fmax(a[1], fmax(b[1], c[1])));
    double area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    int x, y;
    if (fabs(area) < 1e-12) return;
    if (minx < 0) minx = 0;
    if (miny < 0) miny = 0;
    if (maxx > img->width - 1) maxx = img->width - 1;
    if (maxy > img->height - 1) maxy = img->height - 1;
    for (y = (int)miny; y <= (int)maxy; ++y)
        for (x = (int)minx; x <= (int)maxx; ++x) {
            double px = x + 0.5, py = y + 0.5;
            double w0 = ((b[0] - px) * (c[1] - py) - (b[1] - py) * (c[0] - px)) / area;
            double w1 = ((c[0] - px) * (a[1] - py) - (c[1] - py) * (a[0] - px)) / area;
            double w2 = 1 - w0 - w1;
            float z;
            size_t i;
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            /* perspective-correct depth: interpolate 1/z */
            z = (float)(1.0 / (w0 / a[2] + w1 / b[2] + w2 / c[2]));
            i = (size_t)y * img->width + x;
            if (z >= img->depth[i]) continue;
            img->depth[i] = z;
            memcpy(img->rgb + 3 * i, rgb, 3);
        }
}

static void render__shade(const render_camera *cam, const double *p0, const double *p1, const double *p2,
                          const double front[3], const double back[3], unsigned char out[3])
{
    double e0[3], e1[3], n[3], view[3], light[3] = { 0.4, 0.8, 0.45 }, lambert;
    const double *base;
    int k;
    for (k = 0; k < 3; ++k) { e0[k] = p1[k] - p0[k]; e1[k] = p2[k] - p0[k]; view[k] = cam->eye[k] - p0[k]; }
    render__cross(e0, e1, n);
    render__normalize(n);
    render__normalize(light);
    base = front;
    if (n[0] * view[0] + n[1] * view[1] + n[2] * view[2] < 0) {
        for (k = 0; k < 3; ++k) n[k] = -n[k];
        base = back;
    }
    lambert = n[0] * light[0] + n[1] * light[1] + n[2] * light[2];
    if (lambert < 0) lambert = 0;
    for (k = 0; k < 3; ++k) {
        double v = base[k] * (0.3 + 0.7 * lambert);
        out[k] = (unsigned char)(v < 0 ? 0 : v > 1 ? 255 : v * 255);
    }
}

void render_mesh(render_image *img, const render_camera *cam, const double *x, const int32_t *tri, int32_t triangles,
                 const double front[3], const double back[3])
{
    int32_t f;
    for (f = 0; f < triangles; ++f) {
        const double *p0 = x + 3 * tri[3 * f], *p1 = x + 3 * tri[3 * f + 1], *p2 = x + 3 * tri[3 * f + 2];
        double s0[3], s1[3], s2[3];
        unsigned char rgb[3];
        if (!render__project(img, cam, p0, s0) || !render__project(img, cam, p1, s1) || !render__project(img, cam, p2, s2)) continue;
        render__shade(cam, p0, p1, p2, front, back, rgb);
        render__triangle(img, s0, s1, s2, rgb);
    }
}

void render_floor(render_image *img, const render_camera *cam, double y, double half)
{
    int i, j, n = 16;
    double cell = 2 * half / n;
    for (j = 0; j < n; ++j)
        for (i = 0; i < n; ++i) {
            double x0 = -half + i * cell, z0 = -half + j * cell;
            double q[12] = { x0, y, z0, x0 + cell, y, z0, x0 + cell, y, z0 + cell, x0, y, z0 + cell };
            int32_t t[6] = { 0, 2, 1, 0, 3, 2 };
            double c = ((i + j) & 1) ? 0.82 : 0.68, col[3];
            col[0] = c; col[1] = c; col[2] = c * 0.95;
            render_mesh(img, cam, q, t, 2, col, col);
        }
}

static uint32_t render__crc(uint32_t crc, const unsigned char *p, size_t n)
{
    size_t i;
    int k;
    crc = ~crc;
    for (i = 0; i < n; ++i) {
        crc ^= p[i];
        for (k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

static void render__be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24); p[1] = (unsigned char)(v >> 16); p[2] = (unsigned char)(v >> 8); p[3] = (unsigned char)v;
}

static int render__chunk(FILE *f, const char *type, const unsigned char *data, size_t n)
{
    unsigned char head[8], tail[4];
    uint32_t crc;
    render__be32(head, (uint32_t)n);
    memcpy(head + 4, type, 4);
    crc = render__crc(0, head + 4, 4);
    crc = render__crc(crc, data, n);
    render__be32(tail, crc);
    return fwrite(head, 1, 8, f) == 8 && (n == 0 || fwrite(data, 1, n, f) == n) && fwrite(tail, 1, 4, f) == 4;
}

int render_write_png(const render_image *img, const char *path)
{
    static const unsigned char signature[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    size_t row = (size_t)img->width * 3 + 1, raw_size = row * img->height, blocks = (raw_size + 65534) / 65535;
    size_t z_size = 2 + raw_size + 5 * blocks + 4, pos = 0, done = 0;
    unsigned char *raw = (unsigned char *)malloc(raw_size), *z = (unsigned char *)malloc(z_size), ihdr[13];
    uint32_t s1 = 1, s2 = 0;
    size_t i;
    int y, ok;
    FILE *f;
    if (!raw || !z) { free(raw); free(z); return 0; }
    for (y = 0; y < img->height; ++y) {
        raw[y * row] = 0; /* filter: none */
        memcpy(raw + y * row + 1, img->rgb + (size_t)y * img->width * 3, row - 1);
    }
    z[pos++] = 0x78; z[pos++] = 0x01;
    while (done < raw_size) {
        size_t n = raw_size - done > 65535 ? 65535 : raw_size - done;
        z[pos++] = done + n == raw_size ? 1 : 0;
        z[pos++] = (unsigned char)(n & 255); z[pos++] = (unsigned char)(n >> 8);
        z[pos++] = (unsigned char)(~n & 255); z[pos++] = (unsigned char)((~n >> 8) & 255);
        memcpy(z + pos, raw + done, n);
        pos += n;
        done += n;
    }
    for (i = 0; i < raw_size; ++i) { s1 = (s1 + raw[i]) % 65521; s2 = (s2 + s1) % 65521; }
    render__be32(z + pos, (s2 << 16) | s1);
    pos += 4;
    render__be32(ihdr, (uint32_t)img->width);
    render__be32(ihdr + 4, (uint32_t)img->height);
    ihdr[8] = 8; ihdr[9] = 2; ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = 0;
    f = fopen(path, "wb");
    ok = f && fwrite(signature, 1, 8, f) == 8 && render__chunk(f, "IHDR", ihdr, 13) && render__chunk(f, "IDAT", z, pos) &&
         render__chunk(f, "IEND", NULL, 0);
    if (f && fclose(f) != 0) ok = 0;
    free(raw);
    free(z);
    return ok;
}
#endif
