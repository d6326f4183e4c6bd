/* Load benchmark of cloth.h's readers (run by bench/run.sh; not a test).

   Builds a 709 x 708 vertex grid (501,972 vertices, 1,001,112 triangles) with uv, writes it
   with cloth.h as OBJ and as binary little-endian PLY into a directory (default build/bench),
   then times cloth_mesh_read_file on each file: wall clock, file reading included, median of
   RUNS runs (default 5). The files stay for bench/io_meshio.py to read.

   Output, one line per format on stdout:  format,triangles,reader,median_s,runs,median_cpu_s
   where median_cpu_s is the median of the process CPU time (user and system) of the same runs,
   which says less about the other load on a shared machine than wall clock does. The
   individual runs go to stderr.

       cc -std=c99 -O2 -o build/bench/io_load bench/io_load.c -lm
       build/bench/io_load [directory] [runs] */
#define _POSIX_C_SOURCE 200809L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>

#define GRID_NX 709
#define GRID_NY 708

static int compare_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double clock_s(clockid_t clock)
{
    struct timespec ts;
    clock_gettime(clock, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(double), compare_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The grid, built here so the benchmark does not depend on the mesh generators: vertex (i, j)
   is j * nx + i, a gentle wave in y so the numbers are not all short, uv the flat pattern. */
static int build_grid(cloth_mesh *m, double **x, double **uv, int32_t **tri)
{
    int32_t nx = GRID_NX, ny = GRID_NY, i, j, t = 0;
    size_t nv = (size_t)nx * (size_t)ny, nt = 2 * (size_t)(nx - 1) * (size_t)(ny - 1);
    const double h = 1.0 / (double)(nx - 1);
    *x = (double *)malloc(3 * nv * sizeof(double));
    *uv = (double *)malloc(2 * nv * sizeof(double));
    *tri = (int32_t *)malloc(3 * nt * sizeof(int32_t));
    if (!*x || !*uv || !*tri) return 0;
    for (j = 0; j < ny; ++j) {
        for (i = 0; i < nx; ++i) {
            size_t v = (size_t)j * (size_t)nx + (size_t)i;
            (*x)[3 * v + 0] = i * h - 0.5;
            (*x)[3 * v + 1] = 0.01 * sin(7.0 * i * h) * cos(5.0 * j * h);
            (*x)[3 * v + 2] = j * h - 0.5;
            (*uv)[2 * v + 0] = i * h;
            (*uv)[2 * v + 1] = j * h;
        }
    }
    for (j = 0; j + 1 < ny; ++j) {
        for (i = 0; i + 1 < nx; ++i) {
            int32_t a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
            (*tri)[t++] = a; (*tri)[t++] = b; (*tri)[t++] = c;
            (*tri)[t++] = a; (*tri)[t++] = c; (*tri)[t++] = d;
        }
    }
    memset(m, 0, sizeof *m);
    m->vertex_count = (int32_t)nv;
    m->triangle_count = (int32_t)nt;
    m->x = *x;
    m->uv = *uv;
    m->tri = *tri;
    return 1;
}

int main(int argc, char **argv)
{
    const char *dir = argc > 1 ? argv[1] : "build/bench";
    int runs = argc > 2 ? atoi(argv[2]) : 5;
    static const struct { const char *name; const char *file; cloth_file_format format; } formats[] = {
        { "obj", "io_load.obj", CLOTH_FORMAT_OBJ },
        { "ply_binary_le", "io_load_le.ply", CLOTH_FORMAT_PLY_BINARY_LE },
    };
    cloth_mesh grid;
    double *x, *uv, *times, *cpu_times;
    int32_t *tri;
    size_t f;
    if (runs < 1 || runs > 1000) { fprintf(stderr, "io_load: runs must be 1..1000\n"); return 2; }
    times = (double *)malloc((size_t)runs * sizeof(double));
    cpu_times = (double *)malloc((size_t)runs * sizeof(double));
    if (!times || !cpu_times || !build_grid(&grid, &x, &uv, &tri)) { fprintf(stderr, "io_load: out of memory\n"); return 1; }
    for (f = 0; f < sizeof formats / sizeof formats[0]; ++f) {
        char path[1024];
        cloth_result r;
        int k;
        snprintf(path, sizeof path, "%s/%s", dir, formats[f].file);
        r = cloth_mesh_write_file(&grid, path, formats[f].format);
        if (r != CLOTH_SUCCESS) {
            fprintf(stderr, "io_load: writing %s: %s\n", path, cloth_result_string(r));
            return 1;
        }
        for (k = 0; k < runs; ++k) {
            cloth_mesh m;
            cloth_io_error err;
            double c0 = clock_s(CLOCK_PROCESS_CPUTIME_ID), t0 = clock_s(CLOCK_MONOTONIC), t1, c1;
            r = cloth_mesh_read_file(&m, path, CLOTH_FORMAT_AUTO, &err, NULL);
            t1 = clock_s(CLOCK_MONOTONIC);
            c1 = clock_s(CLOCK_PROCESS_CPUTIME_ID);
            if (r != CLOTH_SUCCESS) {
                fprintf(stderr, "io_load: reading %s: %s (line %lld, byte %lld: %s)\n", path, cloth_result_string(r),
                        (long long)err.line, (long long)err.byte_offset, err.message);
                return 1;
            }
            /* A reader that returned the wrong mesh fast would not count. */
            if (m.vertex_count != grid.vertex_count || m.triangle_count != grid.triangle_count ||
                m.tri[3 * (size_t)m.triangle_count - 1] != grid.tri[3 * (size_t)grid.triangle_count - 1] ||
                fabs((double)m.x[3 * (size_t)m.vertex_count - 2] - grid.x[3 * (size_t)grid.vertex_count - 2]) > 1e-6 ||
                !m.uv) {
                fprintf(stderr, "io_load: %s read back as a different mesh\n", path);
                return 1;
            }
            cloth_mesh_free(&m);
            times[k] = t1 - t0;
            cpu_times[k] = c1 - c0;
            fprintf(stderr, "io_load: cloth.h %s run %d: %.4f s (cpu %.4f s)\n", formats[f].name, k + 1, times[k],
                    cpu_times[k]);
        }
        printf("%s,%d,cloth.h,%.6f,%d,%.6f\n", formats[f].name, (int)grid.triangle_count, median(times, runs), runs,
               median(cpu_times, runs));
        fflush(stdout);
    }
    free(times);
    free(cpu_times);
    free(x);
    free(uv);
    free(tri);
    return 0;
}
