/* Benchmark of the bvh module: build (SAH and median), refit (static and swept), rebuild and
   self traversal on square grids of n = 16 .. 256 vertices per side, draped into a wave and
   then moved by one step of a fold, with thickness 1 mm on a 1 m cloth.

       cc -std=c99 -O2 -ffp-contract=off -o build/bench/bvh bench/bvh.c -lm
       ./build/bench/bvh [bench/results/bvh.csv]

   Writes one CSV row per (grid, leaf size, split) with the machine, the CPU and the load
   average when the run began; times are the fastest of repeated runs (the least disturbed by
   other work on a shared machine), in milliseconds. */
#define _POSIX_C_SOURCE 200112L
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "machine.h"

static double fastest(const double *v, int n)
{
    double best = v[0];
    int i;
    for (i = 1; i < n; ++i)
        if (v[i] < best) best = v[i];
    return best;
}

static int count_pair(int32_t a, int32_t b, void *user)
{
    (void)a;
    (void)b;
    ++*(long *)user;
    return 0;
}

/* The cloth at time s in [0, 1]: a wave, whose far half folds over the near half as s grows. */
static void pose(const cloth_real *rest, cloth_real *x, int32_t n, double s)
{
    int32_t v;
    for (v = 0; v < n; ++v) {
        double u = (double)rest[3 * v] + 0.5, w = (double)rest[3 * v + 2];
        double y = 0.02 * sin(12.0 * u) * cos(9.0 * w);
        if (u > 0.5) { /* fold about x = 0.5 by angle pi * s */
            double a = 3.141592653589793 * s, d = u - 0.5;
            x[3 * v] = (cloth_real)(0.5 + d * cos(a) - y * sin(a) - 0.5);
            x[3 * v + 1] = (cloth_real)(0.01 * s + d * sin(a) + y * cos(a));
        } else {
            x[3 * v] = (cloth_real)(u - 0.5);
            x[3 * v + 1] = (cloth_real)y;
        }
        x[3 * v + 2] = (cloth_real)w;
    }
}

int main(int argc, char **argv)
{
    static const int32_t sides[] = { 16, 32, 64, 128, 256 };
    static const int32_t leaves[] = { 1, 2, 4, 8 };
    const char *path = argc > 1 ? argv[1] : "bench/results/bvh.csv";
    bench_machine machine = bench_machine_read();
    const char *host = machine.host, *cpu = machine.cpu, *load = machine.load;
    FILE *out;
    size_t s, l;
    out = fopen(path, "w");
    if (!out) { fprintf(stderr, "bench bvh: cannot write %s\n", path); return 1; }
    fprintf(out, "machine,cpu,load_average,real_bytes,side,triangles,split,leaf_size,nodes,depth,build_ms,refit_ms,refit_swept_ms,"
                 "rebuild_ms,self_ms,self_pairs,quality_after_fold,self_ms_after_fold_refit,self_ms_after_fold_rebuild\n");
    for (s = 0; s < sizeof sides / sizeof sides[0]; ++s) {
        cloth_mesh mesh;
        cloth_real *x0, *x1, *xf;
        int32_t side = sides[s];
        if (cloth_mesh_grid(&mesh, side, side, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return 1;
        x0 = (cloth_real *)malloc(3 * (size_t)mesh.vertex_count * sizeof(cloth_real));
        x1 = (cloth_real *)malloc(3 * (size_t)mesh.vertex_count * sizeof(cloth_real));
        xf = (cloth_real *)malloc(3 * (size_t)mesh.vertex_count * sizeof(cloth_real));
        if (!x0 || !x1 || !xf) return 1;
        pose(mesh.x, x0, mesh.vertex_count, 0.0);
        pose(mesh.x, x1, mesh.vertex_count, 0.01);
        pose(mesh.x, xf, mesh.vertex_count, 0.98);
        for (l = 0; l < sizeof leaves / sizeof leaves[0] + 1; ++l) {
            cloth_bvh_def def = cloth_default_bvh_def();
            cloth_bvh bvh;
            double t_build[41], t_refit[41], t_swept[41], t_rebuild[41], t_self[41], t_fold[41], t_fold_rb[41];
            int reps = (int)(2000000 / mesh.triangle_count), r;
            long pairs = 0;
            cloth_real quality;
            if (reps < 5) reps = 5;
            if (reps > 41) reps = 41;
            def.thickness = (cloth_real)0.001;
            if (l < sizeof leaves / sizeof leaves[0]) def.leaf_size = leaves[l];
            else def.split = CLOTH_BVH_SPLIT_MEDIAN;
            for (r = 0; r < reps; ++r) {
                double t = bench_wall_seconds();
                if (cloth_bvh_build(&bvh, x0, NULL, mesh.vertex_count, mesh.tri, mesh.triangle_count, &def, NULL) != CLOTH_SUCCESS) return 1;
                t_build[r] = bench_wall_seconds() - t;
                t = bench_wall_seconds();
                cloth_bvh_refit(&bvh, x0, NULL);
                t_refit[r] = bench_wall_seconds() - t;
                t = bench_wall_seconds();
                cloth_bvh_refit(&bvh, x0, x1);
                t_swept[r] = bench_wall_seconds() - t;
                t = bench_wall_seconds();
                cloth_bvh_rebuild(&bvh, x0, NULL);
                t_rebuild[r] = bench_wall_seconds() - t;
                pairs = 0;
                t = bench_wall_seconds();
                cloth_bvh_self_pairs(&bvh, count_pair, &pairs);
                t_self[r] = bench_wall_seconds() - t;
                if (r + 1 < reps) cloth_bvh_free(&bvh);
            }
            cloth_bvh_refit(&bvh, xf, NULL);
            quality = cloth_bvh_quality(&bvh);
            for (r = 0; r < reps; ++r) {
                long p = 0;
                double t = bench_wall_seconds();
                cloth_bvh_self_pairs(&bvh, count_pair, &p);
                t_fold[r] = bench_wall_seconds() - t;
            }
            cloth_bvh_rebuild(&bvh, xf, NULL);
            for (r = 0; r < reps; ++r) {
                long p = 0;
                double t = bench_wall_seconds();
                cloth_bvh_self_pairs(&bvh, count_pair, &p);
                t_fold_rb[r] = bench_wall_seconds() - t;
            }
            fprintf(out, "%s,\"%s\",%s,%d,%d,%d,%s,%d,%d,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%ld,%.3f,%.4f,%.4f\n", host, cpu, load,
                    (int)sizeof(cloth_real), (int)side, (int)mesh.triangle_count,
                    def.split == CLOTH_BVH_SPLIT_SAH ? "sah" : "median", (int)def.leaf_size, (int)bvh.node_count,
                    (int)bvh.depth, 1e3 * fastest(t_build, reps), 1e3 * fastest(t_refit, reps), 1e3 * fastest(t_swept, reps),
                    1e3 * fastest(t_rebuild, reps), 1e3 * fastest(t_self, reps), pairs, (double)quality,
                    1e3 * fastest(t_fold, reps), 1e3 * fastest(t_fold_rb, reps));
            cloth_bvh_free(&bvh);
        }
        free(x0);
        free(x1);
        free(xf);
        cloth_mesh_free(&mesh);
    }
    fclose(out);
    return 0;
}
