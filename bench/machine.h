/* machine.h - what every benchmark writes into its CSV rows: the host name, the CPU model
   (from /proc/cpuinfo) and the 1-minute load average (from /proc/loadavg), each "unknown"
   when it cannot be read, with commas and quotes replaced so the fields stay CSV-safe; and
   the wall clock the benchmarks time with. Needs _POSIX_C_SOURCE >= 200112L defined before
   the first system header (gethostname, clock_gettime). */
#ifndef BENCH_MACHINE_H
#define BENCH_MACHINE_H
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* Seconds of CLOCK_MONOTONIC. */
static double bench_wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct bench_machine { char host[256], cpu[256], load[32]; } bench_machine;

static void bench_machine_csv_safe(char *s)
{
    for (; *s; ++s)
        if (*s == ',' || *s == '"') *s = ' ';
}

static bench_machine bench_machine_read(void)
{
    bench_machine m;
    char line[512];
    FILE *f;
    strcpy(m.host, "unknown");
    strcpy(m.cpu, "unknown");
    strcpy(m.load, "unknown");
    if (gethostname(m.host, sizeof m.host) != 0) strcpy(m.host, "unknown");
    m.host[sizeof m.host - 1] = 0;
    f = fopen("/proc/cpuinfo", "r");
    if (f) {
        while (fgets(line, sizeof line, f))
            if (strncmp(line, "model name", 10) == 0) {
                char *c = strchr(line, ':');
                if (c) {
                    c += 1 + strspn(c + 1, " \t");
                    c[strcspn(c, "\n")] = 0;
                    snprintf(m.cpu, sizeof m.cpu, "%s", c);
                }
                break;
            }
        fclose(f);
    }
    f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%31s", m.load) != 1) strcpy(m.load, "unknown");
        fclose(f);
    }
    bench_machine_csv_safe(m.host);
    bench_machine_csv_safe(m.cpu);
    return m;
}
#endif
