/* render.h - a small software rasterizer and PNG writer for cloth.h's examples and benchmarks.
   Not part of the library: it draws triangle meshes into an RGB image with a z-buffer, a
   perspective camera and two-sided Lambert shading, and writes the image as a PNG (compressed
   by its own small deflate encoder: per-row PNG filters, LZ77 matches and the fixed Huffman
   codes, so no zlib is needed).

       render_image img;
       render_camera cam = render_look_at(eye, target, 40.0);
       render_init(&img, 640, 480);              (clears to a sky gradient)
       render_mesh(&img, &cam, x, tri, n_tri, front_rgb, back_rgb);
       render_mesh_smooth(&img, &cam, x, n_vertices, tri, n_tri, front_rgb, back_rgb);   (Gouraud)
       render_sphere(&img, &cam, centre, radius, rgb);   (a smooth ball, ray-cast per pixel)
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
/* The same with smooth (Gouraud) shading from area-weighted vertex normals, still two-sided: a
   triangle seen from its back uses the back colour and the reversed normals. Returns 0 when out
   of memory (nothing drawn). */
int render_mesh_smooth(render_image *img, const render_camera *cam, const double *x, int32_t vertices, const int32_t *tri,
                       int32_t triangles, const double front[3], const double back[3]);
/* A sphere, ray-cast per pixel into the same z-buffer (so it hides and is hidden by meshes
   correctly), with smooth Lambert shading and a small highlight; rgb is 0..1. */
void render_sphere(render_image *img, const render_camera *cam, const double centre[3], double radius, const double rgb[3]);
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

static void render__triangle3(render_image *img, const double a[3], const double b[3], const double c[3], const double *ca,
                              const double *cb, const double *cc);
static void render__triangle(render_image *img, const double a[3], const double b[3], const double c[3], const unsigned char rgb[3])
{
    double col[3];
    int k;
    for (k = 0; k < 3; ++k) col[k] = rgb[k];
    render__triangle3(img, a, b, c, col, col, col);
}

/* Rasterise with colours (0..255) at the three corners, interpolated linearly on screen. */
static void render__triangle3(render_image *img, const double a[3], const double b[3], const double c[3], const double *ca,
                              const double *cb, const double *cc)
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
            {
                int k;
                for (k = 0; k < 3; ++k) {
                    double v = w0 * ca[k] + w1 * cb[k] + w2 * cc[k] + 0.5;
                    img->rgb[3 * i + k] = (unsigned char)(v < 0 ? 0 : v > 255 ? 255 : v);
                }
            }
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

static double render__lit(double base, const double n[3], const double light[3])
{
    double lambert = n[0] * light[0] + n[1] * light[1] + n[2] * light[2], v;
    if (lambert < 0) lambert = 0;
    v = base * (0.3 + 0.7 * lambert);
    return 255 * (v < 0 ? 0 : v > 1 ? 1 : v);
}

int render_mesh_smooth(render_image *img, const render_camera *cam, const double *x, int32_t vertices, const int32_t *tri,
                       int32_t triangles, const double front[3], const double back[3])
{
    double *vn = (double *)calloc((size_t)(vertices > 0 ? vertices : 1) * 3, sizeof(double)), light[3] = { 0.4, 0.8, 0.45 };
    int32_t f, v;
    int k;
    if (!vn) return 0;
    render__normalize(light);
    for (f = 0; f < triangles; ++f) { /* area-weighted: the unnormalised face normal */
        const double *p0 = x + 3 * tri[3 * f], *p1 = x + 3 * tri[3 * f + 1], *p2 = x + 3 * tri[3 * f + 2];
        double e0[3], e1[3], n[3];
        for (k = 0; k < 3; ++k) { e0[k] = p1[k] - p0[k]; e1[k] = p2[k] - p0[k]; }
        render__cross(e0, e1, n);
        for (v = 0; v < 3; ++v)
            for (k = 0; k < 3; ++k) vn[3 * tri[3 * f + v] + k] += n[k];
    }
    for (v = 0; v < vertices; ++v) render__normalize(vn + 3 * v);
    for (f = 0; f < triangles; ++f) {
        const double *p[3];
        double s[3][3], e0[3], e1[3], n[3], view[3], col[3][3], sign = 1;
        const double *base = front;
        for (v = 0; v < 3; ++v) p[v] = x + 3 * tri[3 * f + v];
        if (!render__project(img, cam, p[0], s[0]) || !render__project(img, cam, p[1], s[1]) || !render__project(img, cam, p[2], s[2])) continue;
        for (k = 0; k < 3; ++k) { e0[k] = p[1][k] - p[0][k]; e1[k] = p[2][k] - p[0][k]; view[k] = cam->eye[k] - p[0][k]; }
        render__cross(e0, e1, n);
        if (n[0] * view[0] + n[1] * view[1] + n[2] * view[2] < 0) { sign = -1; base = back; }
        for (v = 0; v < 3; ++v) {
            const double *m = vn + 3 * tri[3 * f + v];
            double nv[3];
            for (k = 0; k < 3; ++k) nv[k] = sign * m[k];
            for (k = 0; k < 3; ++k) col[v][k] = render__lit(base[k], nv, light);
        }
        render__triangle3(img, s[0], s[1], s[2], col[0], col[1], col[2]);
    }
    free(vn);
    return 1;
}

void render_sphere(render_image *img, const render_camera *cam, const double centre[3], double radius, const double rgb[3])
{
    double light[3] = { 0.4, 0.8, 0.45 }, oc[3], s[3], half_h = img->height * 0.5;
    int x, y, k, x0 = 0, x1 = img->width - 1, y0 = 0, y1 = img->height - 1;
    render__normalize(light);
    for (k = 0; k < 3; ++k) oc[k] = cam->eye[k] - centre[k];
    /* Screen bounds from the projected centre and a generous radius (skipped when behind). */
    if (render__project(img, cam, centre, s)) {
        double rr = radius / s[2] * cam->focal * half_h * 1.5 + 2, dist = sqrt(oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2]);
        if (dist > radius * 1.05) {
            x0 = (int)fmax(0, s[0] - rr); x1 = (int)fmin(img->width - 1, s[0] + rr);
            y0 = (int)fmax(0, s[1] - rr); y1 = (int)fmin(img->height - 1, s[1] + rr);
        }
    }
    for (y = y0; y <= y1; ++y)
        for (x = x0; x <= x1; ++x) {
            /* the ray eye + t d with d's forward component 1, so that t is the view depth */
            double a = (x + 0.5 - img->width * 0.5) / (cam->focal * half_h), b = (half_h - (y + 0.5)) / (cam->focal * half_h);
            double d[3], qa = 0, qb = 0, qc = 0, disc, t, n[3], h[3], lambert, spec;
            size_t i = (size_t)y * img->width + x;
            for (k = 0; k < 3; ++k) {
                d[k] = cam->forward[k] + a * cam->right[k] + b * cam->up[k];
                qa += d[k] * d[k]; qb += 2 * d[k] * oc[k]; qc += oc[k] * oc[k];
            }
            qc -= radius * radius;
            disc = qb * qb - 4 * qa * qc;
            if (disc < 0) continue;
            t = (-qb - sqrt(disc)) / (2 * qa);
            if (t < 1e-3 || (float)t >= img->depth[i]) continue;
            for (k = 0; k < 3; ++k) { n[k] = (oc[k] + t * d[k]) / radius; h[k] = light[k] - d[k] / sqrt(qa); }
            render__normalize(h);
            lambert = fmax(0, n[0] * light[0] + n[1] * light[1] + n[2] * light[2]);
            spec = pow(fmax(0, n[0] * h[0] + n[1] * h[1] + n[2] * h[2]), 40) * 0.35;
            img->depth[i] = (float)t;
            for (k = 0; k < 3; ++k) {
                double v = rgb[k] * (0.3 + 0.7 * lambert) + spec;
                img->rgb[3 * i + k] = (unsigned char)(v < 0 ? 0 : v > 1 ? 255 : v * 255);
            }
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

/* ---- deflate (RFC 1951) with the fixed Huffman codes and LZ77 matches ------------------ */

/* Bits go out least significant first; `out` has room for everything (checked by the caller's
   bound). */
typedef struct render__bits { unsigned char *out; size_t pos; uint32_t acc; int count; } render__bits;

static void render__put(render__bits *b, uint32_t value, int n)
{
    b->acc |= value << b->count;
    b->count += n;
    while (b->count >= 8) { b->out[b->pos++] = (unsigned char)b->acc; b->acc >>= 8; b->count -= 8; }
}

/* A Huffman code of n bits is sent most significant bit first. */
static void render__put_code(render__bits *b, uint32_t code, int n)
{
    uint32_t r = 0;
    int i;
    for (i = 0; i < n; ++i) r |= ((code >> i) & 1u) << (n - 1 - i);
    render__put(b, r, n);
}

/* A literal byte or length symbol (0..285) in the fixed code. */
static void render__put_symbol(render__bits *b, int sym)
{
    if (sym < 144) render__put_code(b, 0x30u + (uint32_t)sym, 8);
    else if (sym < 256) render__put_code(b, 0x190u + (uint32_t)(sym - 144), 9);
    else if (sym < 280) render__put_code(b, (uint32_t)(sym - 256), 7);
    else render__put_code(b, 0xC0u + (uint32_t)(sym - 280), 8);
}

static void render__put_match(render__bits *b, int length, int distance)
{
    static const int len_base[29] = { 3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31,
                                      35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258 };
    static const int len_extra[29] = { 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0 };
    static const int dist_base[30] = { 1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513, 769,
                                       1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577 };
    static const int dist_extra[30] = { 0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10, 11, 11, 12, 12, 13, 13 };
    int i = 28, d = 29;
    while (len_base[i] > length) --i;
    render__put_symbol(b, 257 + i);
    render__put(b, (uint32_t)(length - len_base[i]), len_extra[i]);
    while (dist_base[d] > distance) --d;
    render__put_code(b, (uint32_t)d, 5);
    render__put(b, (uint32_t)(distance - dist_base[d]), dist_extra[d]);
}

#define RENDER__WINDOW 32768
#define RENDER__HASH_BITS 15
#define RENDER__CHAIN 48 /* candidates tried per position: more is smaller and slower */

/* One fixed-code block holding all of in[0..n). Returns the bytes written to out, which needs
   room for n * 3 / 2 + 64 bytes (a literal costs at most 9 bits, a match of 3 or more bytes at
   most 31). 0 when out of memory. */
static size_t render__deflate(const unsigned char *in, size_t n, unsigned char *out)
{
    int32_t *head = (int32_t *)malloc(sizeof(int32_t) << RENDER__HASH_BITS);
    int32_t *prev = (int32_t *)malloc(sizeof(int32_t) * RENDER__WINDOW);
    render__bits b;
    size_t i = 0, k;
    if (!head || !prev) { free(head); free(prev); return 0; }
    for (k = 0; k < ((size_t)1 << RENDER__HASH_BITS); ++k) head[k] = -1;
    b.out = out; b.pos = 0; b.acc = 0; b.count = 0;
    render__put(&b, 1, 1); /* BFINAL */
    render__put(&b, 1, 2); /* BTYPE 01: fixed Huffman codes */
    while (i < n) {
        int best = 0, best_distance = 0, step, s;
        if (i + 3 <= n) {
            uint32_t h = ((uint32_t)in[i] << 16 | (uint32_t)in[i + 1] << 8 | in[i + 2]) * 2654435761u >> (32 - RENDER__HASH_BITS);
            int32_t cand = head[h];
            int tries = RENDER__CHAIN;
            size_t limit = n - i < 258 ? n - i : 258;
            while (cand >= 0 && i - (size_t)cand <= RENDER__WINDOW - 1 && tries-- > 0) {
                size_t len = 0;
                while (len < limit && in[(size_t)cand + len] == in[i + len]) ++len;
                if ((int)len > best) { best = (int)len; best_distance = (int)(i - (size_t)cand); if (len == limit) break; }
                cand = prev[cand % RENDER__WINDOW];
            }
            if (best < 3) best = 0;
        }
        if (best) render__put_match(&b, best, best_distance);
        else render__put_symbol(&b, in[i]);
        step = best ? best : 1;
        for (s = 0; s < step; ++s, ++i) /* every position passed enters the hash chains */
            if (i + 3 <= n) {
                uint32_t h = ((uint32_t)in[i] << 16 | (uint32_t)in[i + 1] << 8 | in[i + 2]) * 2654435761u >> (32 - RENDER__HASH_BITS);
                prev[i % RENDER__WINDOW] = head[h];
                head[h] = (int32_t)i;
            }
    }
    render__put_symbol(&b, 256); /* end of block */
    if (b.count > 0) render__put(&b, 0, 8 - b.count);
    free(head);
    free(prev);
    return b.pos;
}

/* The PNG Paeth predictor. */
static int render__paeth(int a, int b, int c)
{
    int p = a + b - c, pa = abs(p - a), pb = abs(p - b), pc = abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

int render_write_png(const render_image *img, const char *path)
{
    static const unsigned char signature[8] = { 137, 80, 78, 71, 13, 10, 26, 10 };
    size_t row = (size_t)img->width * 3 + 1, raw_size = row * img->height, z_cap = raw_size + raw_size / 2 + 80, pos = 0;
    unsigned char *raw = (unsigned char *)malloc(raw_size), *z = (unsigned char *)malloc(z_cap), ihdr[13];
    unsigned char *trial = (unsigned char *)malloc(row);
    uint32_t s1 = 1, s2 = 0;
    size_t i, n;
    int y, ok, filter;
    FILE *f;
    if (!raw || !z || !trial) { free(raw); free(z); free(trial); return 0; }
    /* Each row gets the filter (none, sub, up, average, Paeth) whose output has the smallest
       sum of magnitudes, the usual heuristic: smooth shading becomes runs of small numbers. */
    for (y = 0; y < img->height; ++y) {
        const unsigned char *cur = img->rgb + (size_t)y * img->width * 3, *up = y ? cur - (size_t)img->width * 3 : NULL;
        unsigned long best_cost = (unsigned long)-1;
        for (filter = 0; filter < 5; ++filter) {
            unsigned long cost = 0;
            trial[0] = (unsigned char)filter;
            for (i = 0; i + 1 < row; ++i) {
                int a = i >= 3 ? cur[i - 3] : 0, b = up ? up[i] : 0, c = i >= 3 && up ? up[i - 3] : 0, pred;
                pred = filter == 0 ? 0 : filter == 1 ? a : filter == 2 ? b : filter == 3 ? (a + b) / 2 : render__paeth(a, b, c);
                trial[i + 1] = (unsigned char)(cur[i] - pred);
                cost += trial[i + 1] < 128 ? trial[i + 1] : 256 - trial[i + 1];
            }
            if (cost < best_cost) { best_cost = cost; memcpy(raw + (size_t)y * row, trial, row); }
        }
    }
    z[pos++] = 0x78; z[pos++] = 0x01;
    n = render__deflate(raw, raw_size, z + pos);
    ok = n > 0;
    pos += n;
    for (i = 0; i < raw_size; ++i) { s1 = (s1 + raw[i]) % 65521; s2 = (s2 + s1) % 65521; }
    render__be32(z + pos, (s2 << 16) | s1);
    pos += 4;
    render__be32(ihdr, (uint32_t)img->width);
    render__be32(ihdr + 4, (uint32_t)img->height);
    ihdr[8] = 8; ihdr[9] = 2; ihdr[10] = 0; ihdr[11] = 0; ihdr[12] = 0;
    f = ok ? fopen(path, "wb") : NULL;
    ok = f && fwrite(signature, 1, 8, f) == 8 && render__chunk(f, "IHDR", ihdr, 13) && render__chunk(f, "IDAT", z, pos) &&
         render__chunk(f, "IEND", NULL, 0);
    if (f && fclose(f) != 0) ok = 0;
    free(raw);
    free(z);
    free(trial);
    return ok;
}
#endif
