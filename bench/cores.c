/* cores.c - how much two threads gain on this machine, before any cloth.h figure on 2 threads
   is read: a VM's two "cores" may be the two hardware threads of one physical core, which
   share its caches and load/store units. Two loops, each timed alone and then on two threads
   at once (one copy per thread, nothing shared):
     stream   a[i] = c a[i] + b[i] over 2 x 64 KB (past L1, inside L2), vectorized: the kind of
              pass the solver's products, sweeps and transfers make
     alu      eight independent multiply-add chains in registers (latency-bound, no memory)
   ratio = (time of the two-thread run) / (time of one alone): 1 means two threads do twice the
   work in the same time, 2 means they gain nothing. The median of 5 repetitions.

       cc -std=c99 -O2 -pthread -o build/bench/cores bench/cores.c
       ./build/bench/cores

   Prints a CSV header and one row: machine, cpu, loadavg, stream_1_s, stream_2_s,
   stream_ratio, alu_1_s, alu_2_s, alu_ratio. */
#define _POSIX_C_SOURCE 200112L
#include "machine.h"
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

#define CORES_N 8192 /* doubles per array: 64 KB */
#define CORES_PASSES 20000
#define CORES_ALU_STEPS 100000000L

static volatile double cores_sink[32];

static void *cores_stream(void *arg)
{
    const long id = (long)(size_t)arg;
    double *a = (double *)malloc(CORES_N * sizeof *a), *b = (double *)malloc(CORES_N * sizeof *b), s = 0;
    long i, r;
    if (!a || !b) {
        free(a);
        free(b);
        return NULL;
    }
    for (i = 0; i < CORES_N; ++i) {
        a[i] = (double)i;
        b[i] = 1.0 / (double)(i + 1);
    }
    for (r = 0; r < CORES_PASSES; ++r)
        for (i = 0; i < CORES_N; ++i) a[i] = a[i] * 0.999 + b[i];
    for (i = 0; i < CORES_N; ++i) s += a[i];
    cores_sink[8 * id % 32] = s;
    free(a);
    free(b);
    return NULL;
}

static void *cores_alu(void *arg)
{
    const long id = (long)(size_t)arg;
    double a0 = 1, a1 = 1, a2 = 1, a3 = 1, a4 = 1, a5 = 1, a6 = 1, a7 = 1;
    long i;
    for (i = 0; i < CORES_ALU_STEPS; ++i) {
        a0 = a0 * 0.9999999 + 1e-9;
        a1 = a1 * 0.9999998 + 1e-9;
        a2 = a2 * 0.9999997 + 1e-9;
        a3 = a3 * 0.9999996 + 1e-9;
        a4 = a4 * 0.9999995 + 1e-9;
        a5 = a5 * 0.9999994 + 1e-9;
        a6 = a6 * 0.9999993 + 1e-9;
        a7 = a7 * 0.9999992 + 1e-9;
    }
    cores_sink[8 * id % 32 + 1] = a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7;
    return NULL;
}

static int cores_cmp(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

/* The median over 5 repetitions of the seconds one copy takes alone (*one) and two copies
   take on two threads at once (*two); 0 when a thread cannot be started. */
static int cores_time(void *(*fn)(void *), double *one, double *two)
{
    double t1[5], t2[5];
    int r;
    for (r = 0; r < 5; ++r) {
        pthread_t a, b;
        double t0 = bench_wall_seconds();
        fn((void *)0);
        t1[r] = bench_wall_seconds() - t0;
        t0 = bench_wall_seconds();
        if (pthread_create(&a, NULL, fn, (void *)0) != 0) return 0;
        if (pthread_create(&b, NULL, fn, (void *)1) != 0) {
            pthread_join(a, NULL);
            return 0;
        }
        pthread_join(a, NULL);
        pthread_join(b, NULL);
        t2[r] = bench_wall_seconds() - t0;
    }
    qsort(t1, 5, sizeof t1[0], cores_cmp);
    qsort(t2, 5, sizeof t2[0], cores_cmp);
    *one = t1[2];
    *two = t2[2];
    return 1;
}

int main(void)
{
    bench_machine m = bench_machine_read();
    double s1, s2, a1, a2;
    if (!cores_time(cores_stream, &s1, &s2) || !cores_time(cores_alu, &a1, &a2)) {
        fprintf(stderr, "cores: a thread could not be started\n");
        return 1;
    }
    printf("machine,cpu,loadavg,stream_1_s,stream_2_s,stream_ratio,alu_1_s,alu_2_s,alu_ratio\n");
    printf("%s,%s,%s,%.4f,%.4f,%.2f,%.4f,%.4f,%.2f\n", m.host, m.cpu, m.load, s1, s2, s2 / s1, a1, a2, a2 / a1);
    return 0;
}
