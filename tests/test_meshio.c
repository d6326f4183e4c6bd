/* meshio interoperability: cloth.h reads the files meshio writes, and meshio reads the files
   cloth.h writes.

   Reading: tests/fixtures holds meshes written by meshio (tests/fixtures/generate.py; see
   tests/fixtures/README.md) in every format meshio writes, with their expected content in
   tests/fixtures/expected.txt (vertex and triangle counts after fan triangulation, every
   coordinate, every triangle and the uv cloth.h must find). Each fixture is read by path with
   CLOTH_FORMAT_AUTO, from memory with its format named, and from memory with
   CLOTH_FORMAT_AUTO, and must match exactly: the expected numbers are the very doubles meshio
   wrote (float32 files hold float32 values, which a double represents exactly, and meshio's
   ascii writers print every value with enough digits to round-trip).

   Writing: a mesh is written by cloth.h in each writable format into test_tmpdir(), its
   content into a side file, and tests/fixtures/meshio_readback.py reads both with meshio
   (/usr/bin/python3, Debian's python3-meshio) and exits 0 only if they agree. */
#define _POSIX_C_SOURCE 200809L
#include "../cloth.h"
#include "runner.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#define MESHIO_PYTHON "/usr/bin/python3"
#define MESHIO_INSTALL_HINT "install python3-meshio (apt-get install -y python3-meshio)"

/* ---- expected.txt ------------------------------------------------------------------- */

typedef struct fixture {
    char name[64];
    char format_token[32];
    cloth_file_format format;
    int32_t vertex_count, triangle_count;
    int has_uv;
    double *x;      /* 3 per vertex */
    double *uv;     /* 2 per vertex when has_uv */
    int32_t *tri;   /* 3 per triangle */
} fixture;

typedef struct fixture_list {
    int count;
    fixture items[128];
} fixture_list;

static const struct { const char *token; cloth_file_format format; const char *extension; } format_table[] = {
    { "OBJ", CLOTH_FORMAT_OBJ, "obj" },
    { "PLY_ASCII", CLOTH_FORMAT_PLY_ASCII, "ply" },
    { "PLY_BINARY_LE", CLOTH_FORMAT_PLY_BINARY_LE, "ply" },
    { "PLY_BINARY_BE", CLOTH_FORMAT_PLY_BINARY_BE, "ply" },
    { "VTK_ASCII", CLOTH_FORMAT_VTK_ASCII, "vtk" },
    { "VTK_BINARY", CLOTH_FORMAT_VTK_BINARY, "vtk" },
    { "OFF", CLOTH_FORMAT_OFF, "off" },
};
#define FORMAT_COUNT ((int)(sizeof format_table / sizeof format_table[0]))

static int format_index(cloth_file_format f)
{
    int i;
    for (i = 0; i < FORMAT_COUNT; ++i) if (format_table[i].format == f) return i;
    return -1;
}

/* The whole of a file, NUL-terminated (the NUL is not counted in *size); NULL on failure. */
static char *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    char *data = NULL;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = (char *)malloc((size_t)n + 1);
        if (data && fread(data, 1, (size_t)n, f) == (size_t)n) {
            data[n] = 0;
            *size = (size_t)n;
        } else {
            free(data);
            data = NULL;
        }
    }
    fclose(f);
    return data;
}

static void fixtures_free(fixture_list *list)
{
    int i;
    for (i = 0; i < list->count; ++i) {
        free(list->items[i].x);
        free(list->items[i].uv);
        free(list->items[i].tri);
    }
    list->count = 0;
}

/* Parse expected.txt; 0 and a message on stdout on failure. */
static int fixtures_load(fixture_list *list)
{
    char path[512];
    size_t size = 0;
    char *text, *line, *next;
    fixture *cur = NULL;
    int32_t nv = 0, nt = 0, nuv = 0;
    int ok = 1;
    list->count = 0;
    snprintf(path, sizeof path, "%s/tests/fixtures/expected.txt", test_root());
    text = slurp(path, &size);
    if (!text) { printf("    cannot read %s (run from the repository root or set CLOTH_ROOT)\n", path); return 0; }
    for (line = text; ok && line && *line; line = next) {
        char *end;
        next = strchr(line, '\n');
        if (next) *next++ = 0;
        if (line[0] == '#' || line[0] == 0) continue;
        if (strncmp(line, "file ", 5) == 0) {
            int k, consumed = 0;
            if (list->count == (int)(sizeof list->items / sizeof list->items[0])) { ok = 0; break; }
            cur = &list->items[list->count++];
            memset(cur, 0, sizeof *cur);
            if (sscanf(line, "file %63s %31s %d %d %d%n", cur->name, cur->format_token, &cur->vertex_count,
                       &cur->triangle_count, &cur->has_uv, &consumed) != 5 || consumed == 0 ||
                cur->vertex_count <= 0 || cur->triangle_count <= 0) { ok = 0; break; }
            cur->format = CLOTH_FORMAT_AUTO;
            for (k = 0; k < FORMAT_COUNT; ++k)
                if (strcmp(cur->format_token, format_table[k].token) == 0) cur->format = format_table[k].format;
            if (cur->format == CLOTH_FORMAT_AUTO) { ok = 0; break; }
            cur->x = (double *)malloc(sizeof(double) * 3 * (size_t)cur->vertex_count);
            cur->tri = (int32_t *)malloc(sizeof(int32_t) * 3 * (size_t)cur->triangle_count);
            cur->uv = cur->has_uv ? (double *)malloc(sizeof(double) * 2 * (size_t)cur->vertex_count) : NULL;
            if (!cur->x || !cur->tri || (cur->has_uv && !cur->uv)) { ok = 0; break; }
            nv = nt = nuv = 0;
        } else if (!cur) {
            ok = 0;
        } else if (line[0] == 'v' && line[1] == ' ') {
            int k;
            char *p = line + 2;
            if (nv >= cur->vertex_count) { ok = 0; break; }
            for (k = 0; k < 3; ++k) { cur->x[3 * nv + k] = strtod(p, &end); if (end == p) ok = 0; p = end; }
            ++nv;
        } else if (line[0] == 't' && line[1] == ' ') {
            int k;
            char *p = line + 2;
            if (nt >= cur->triangle_count) { ok = 0; break; }
            for (k = 0; k < 3; ++k) { cur->tri[3 * nt + k] = (int32_t)strtol(p, &end, 10); if (end == p) ok = 0; p = end; }
            ++nt;
        } else if (strncmp(line, "uv ", 3) == 0) {
            int k;
            char *p = line + 3;
            if (!cur->has_uv || nuv >= cur->vertex_count) { ok = 0; break; }
            for (k = 0; k < 2; ++k) { cur->uv[2 * nuv + k] = strtod(p, &end); if (end == p) ok = 0; p = end; }
            ++nuv;
        } else if (strcmp(line, "end") == 0) {
            if (nv != cur->vertex_count || nt != cur->triangle_count || (cur->has_uv && nuv != cur->vertex_count)) ok = 0;
            cur = NULL;
        } else {
            ok = 0;
        }
    }
    if (cur) ok = 0; /* a record without its "end" */
    if (!ok) {
        printf("    %s is malformed near: %.60s\n", path, line ? line : "(end)");
        fixtures_free(list);
    }
    free(text);
    return ok;
}

/* ---- comparing ----------------------------------------------------------------------- */

/* Like ENSURE, but says which fixture and how it was read, and returns 0 from a helper. */
#define FIX_ENSURE(cond) do { if (!(cond)) { printf("    %s (%s):\n", f->name, how); \
    test_fail(__FILE__, __LINE__, #cond); return 0; } } while (0)

static int mesh_matches(const fixture *f, const cloth_mesh *m, const char *how)
{
    int32_t i;
    FIX_ENSURE(m->vertex_count == f->vertex_count);
    FIX_ENSURE(m->triangle_count == f->triangle_count);
    FIX_ENSURE(m->x != NULL && m->tri != NULL);
    for (i = 0; i < 3 * f->vertex_count; ++i) {
        if ((double)m->x[i] != f->x[i]) {
            printf("    %s (%s): vertex %d coordinate %d is %.17g, expected %.17g\n", f->name, how, (int)(i / 3),
                   (int)(i % 3), (double)m->x[i], f->x[i]);
            FIX_ENSURE((double)m->x[i] == f->x[i]);
        }
    }
    for (i = 0; i < 3 * f->triangle_count; ++i) {
        if (m->tri[i] != f->tri[i]) {
            printf("    %s (%s): triangle %d is (%d %d %d), expected (%d %d %d)\n", f->name, how, (int)(i / 3),
                   (int)m->tri[i - i % 3], (int)m->tri[i - i % 3 + 1], (int)m->tri[i - i % 3 + 2],
                   (int)f->tri[i - i % 3], (int)f->tri[i - i % 3 + 1], (int)f->tri[i - i % 3 + 2]);
            FIX_ENSURE(m->tri[i] == f->tri[i]);
        }
    }
    if (!f->has_uv) {
        FIX_ENSURE(m->uv == NULL);
    } else {
        FIX_ENSURE(m->uv != NULL);
        for (i = 0; i < 2 * f->vertex_count; ++i) {
            if ((double)m->uv[i] != f->uv[i]) {
                printf("    %s (%s): uv %d component %d is %.17g, expected %.17g\n", f->name, how, (int)(i / 2),
                       (int)(i % 2), (double)m->uv[i], f->uv[i]);
                FIX_ENSURE((double)m->uv[i] == f->uv[i]);
            }
        }
    }
    return 1;
}

/* Read one fixture by path, from memory with its format named and from memory with
   CLOTH_FORMAT_AUTO, and check cloth_detect_format on it; 1 when everything matches. Each
   way is tried even when an earlier one failed, so that one run shows every problem. */
static int check_fixture(const fixture *f)
{
    char path[512];
    const char *how;
    size_t size = 0;
    char *data;
    cloth_mesh m;
    cloth_io_error err;
    cloth_result r;
    cloth_file_format detected;
    int ok = 1, k;
    snprintf(path, sizeof path, "%s/tests/fixtures/%s", test_root(), f->name);

    how = "slurp";
    data = slurp(path, &size);
    FIX_ENSURE(data != NULL);

    for (k = 0; k < 3; ++k) {
        memset(&err, 0, sizeof err);
        if (k == 0) {
            how = "cloth_mesh_read_file, CLOTH_FORMAT_AUTO";
            r = cloth_mesh_read_file(&m, path, CLOTH_FORMAT_AUTO, &err, NULL);
        } else if (k == 1) {
            how = "cloth_mesh_read_memory, format named";
            r = cloth_mesh_read_memory(&m, data, size, f->format, &err, NULL);
        } else {
            how = "cloth_mesh_read_memory, CLOTH_FORMAT_AUTO";
            r = cloth_mesh_read_memory(&m, data, size, CLOTH_FORMAT_AUTO, &err, NULL);
        }
        if (r != CLOTH_SUCCESS) {
            printf("    %s (%s): %s; line %lld, byte %lld: %s\n", f->name, how, cloth_result_string(r),
                   (long long)err.line, (long long)err.byte_offset, err.message);
            test_fail(__FILE__, __LINE__, "r == CLOTH_SUCCESS");
            ok = 0;
        } else if (!mesh_matches(f, &m, how)) {
            ok = 0;
        }
        cloth_mesh_free(&m);
    }

    detected = cloth_detect_format(data, size);
    free(data);
    if (detected != f->format) {
        printf("    %s: cloth_detect_format says %s, expected %s\n", f->name,
               format_index(detected) >= 0 ? format_table[format_index(detected)].token : "AUTO (unknown)",
               f->format_token);
        test_fail(__FILE__, __LINE__, "cloth_detect_format(data, size) == f->format");
        ok = 0;
    }
    return ok;
}

/* Check every fixture whose format is `format` and whose name contains `name_part`; the test
   fails if there are fewer than `minimum` of them (a missing fixture is a failure too). */
static void check_fixtures(cloth_file_format format, const char *name_part, int minimum)
{
    static fixture_list list; /* large; one test runs at a time */
    int i, n = 0;
    if (!fixtures_load(&list)) { test_fail(__FILE__, __LINE__, "tests/fixtures/expected.txt loads"); return; }
    for (i = 0; i < list.count; ++i) {
        if (list.items[i].format != format || !strstr(list.items[i].name, name_part)) continue;
        ++n;
        check_fixture(&list.items[i]);
    }
    fixtures_free(&list);
    if (n < minimum) printf("    only %d fixtures of this kind, expected at least %d\n", n, minimum);
    ENSURE(n >= minimum);
}

/* ---- tests: cloth.h reads what meshio wrote --------------------------------------------- */

/* The sidecar lists the meshes and formats the README promises, and every file exists. */
TEST(fixtures_complete)
{
    static fixture_list list;
    static const char *meshes[] = { "grid", "grid_f32", "sphere", "quads", "mixed", "attrs" };
    static const char *suffixes[] = { ".obj", "_ascii.ply", "_le.ply", "_be.ply", "_v51_ascii.vtk", "_v51_binary.vtk",
                                      "_v42_ascii.vtk", "_v42_binary.vtk", ".off" };
    size_t a, b;
    int i, found_all = 1;
    ENSURE(fixtures_load(&list));
    for (a = 0; a < sizeof meshes / sizeof meshes[0]; ++a) {
        for (b = 0; b < sizeof suffixes / sizeof suffixes[0]; ++b) {
            char name[96];
            int found = 0;
            /* meshio's OFF writer keeps triangles only and no point data (see the README) */
            if (strcmp(suffixes[b], ".off") == 0 && a >= 3) continue;
            snprintf(name, sizeof name, "%s%s", meshes[a], suffixes[b]);
            for (i = 0; i < list.count; ++i) found |= strcmp(list.items[i].name, name) == 0;
            if (!found) { printf("    %s is not in expected.txt\n", name); found_all = 0; }
        }
    }
    for (i = 0; i < list.count; ++i) {
        char path[512];
        FILE *fp;
        snprintf(path, sizeof path, "%s/tests/fixtures/%s", test_root(), list.items[i].name);
        fp = fopen(path, "rb");
        if (!fp) { printf("    %s is missing\n", path); found_all = 0; }
        else fclose(fp);
    }
    i = list.count;
    fixtures_free(&list);
    ENSURE(i == 51);
    ENSURE(found_all);
}

TEST(read_obj) { check_fixtures(CLOTH_FORMAT_OBJ, ".obj", 6); }
TEST(read_ply_ascii) { check_fixtures(CLOTH_FORMAT_PLY_ASCII, "_ascii.ply", 6); }
TEST(read_ply_binary_le) { check_fixtures(CLOTH_FORMAT_PLY_BINARY_LE, "_le.ply", 6); }
TEST(read_ply_binary_be) { check_fixtures(CLOTH_FORMAT_PLY_BINARY_BE, "_be.ply", 6); }
TEST(read_vtk51_ascii) { check_fixtures(CLOTH_FORMAT_VTK_ASCII, "_v51_", 6); }
TEST(read_vtk51_binary) { check_fixtures(CLOTH_FORMAT_VTK_BINARY, "_v51_", 6); }
TEST(read_vtk42_ascii) { check_fixtures(CLOTH_FORMAT_VTK_ASCII, "_v42_", 6); }
TEST(read_vtk42_binary) { check_fixtures(CLOTH_FORMAT_VTK_BINARY, "_v42_", 6); }
TEST(read_off) { check_fixtures(CLOTH_FORMAT_OFF, ".off", 3); }

/* ---- tests: meshio reads what cloth.h wrote --------------------------------------------- */

#define RB_NX 23
#define RB_NY 13

/* A 23 x 13 vertex wavy grid (299 vertices, so indices pass 255; 528 triangles) with uv and
   coordinates that need all 17 digits, plus a few that need exponents. */
static void readback_mesh(cloth_mesh *m, double *x, double *uv, int32_t *tri)
{
    int i, j, t = 0;
    for (j = 0; j < RB_NY; ++j) {
        for (i = 0; i < RB_NX; ++i) {
            int v = j * RB_NX + i;
            x[3 * v + 0] = 0.1 * i - 1.1;
            x[3 * v + 1] = 0.03 * sin(0.9 * i + 1.7 * j) + 1.0 / 7.0;
            x[3 * v + 2] = j / 3.0 - 2.0;
            uv[2 * v + 0] = x[3 * v + 0] + 1.1;
            uv[2 * v + 1] = x[3 * v + 2] + 2.0;
        }
    }
    x[3 * 5 + 1] = 1.25e-05;
    x[3 * 40 + 1] = -3.5e-12;
    x[3 * 77 + 1] = 1e-300;
    x[3 * 100 + 0] = 6.02214076e+23;
    x[3 * 150 + 1] = -0.0;
    for (j = 0; j + 1 < RB_NY; ++j) {
        for (i = 0; i + 1 < RB_NX; ++i) {
            int32_t a = j * RB_NX + i, b = a + 1, c = a + RB_NX + 1, d = a + RB_NX;
            tri[t++] = a; tri[t++] = b; tri[t++] = c;
            tri[t++] = a; tri[t++] = c; tri[t++] = d;
        }
    }
    memset(m, 0, sizeof *m);
    m->vertex_count = RB_NX * RB_NY;
    m->triangle_count = 2 * (RB_NX - 1) * (RB_NY - 1);
    m->x = x;
    m->uv = uv;
    m->tri = tri;
}

static int write_expected(const char *path, const char *name, const char *token, const cloth_mesh *m, int with_uv)
{
    FILE *f = fopen(path, "w");
    int32_t i;
    if (!f) return 0;
    fprintf(f, "file %s %s %d %d %d\n", name, token, (int)m->vertex_count, (int)m->triangle_count, with_uv);
    for (i = 0; i < m->vertex_count; ++i)
        fprintf(f, "v %.17g %.17g %.17g\n", (double)m->x[3 * i], (double)m->x[3 * i + 1], (double)m->x[3 * i + 2]);
    for (i = 0; i < m->triangle_count; ++i)
        fprintf(f, "t %d %d %d\n", (int)m->tri[3 * i], (int)m->tri[3 * i + 1], (int)m->tri[3 * i + 2]);
    if (with_uv)
        for (i = 0; i < m->vertex_count; ++i) fprintf(f, "uv %.17g %.17g\n", (double)m->uv[2 * i], (double)m->uv[2 * i + 1]);
    fprintf(f, "end\n");
    return fclose(f) == 0;
}

static void print_file(const char *path)
{
    size_t size = 0;
    char *text = slurp(path, &size);
    if (text) { printf("%s", text); free(text); }
}

/* Write the readback mesh with cloth.h in `format` and have meshio read it back. */
static void readback(cloth_file_format format, const char *stem, int uv_required)
{
    static double x[3 * RB_NX * RB_NY], uv[2 * RB_NX * RB_NY];
    static int32_t tri[6 * (RB_NX - 1) * (RB_NY - 1)];
    cloth_mesh m;
    char file[512], expected[512], log[512], cmd[2048];
    int k = format_index(format), rc;
    cloth_result r;
    ENSURE(k >= 0);
    rc = system(MESHIO_PYTHON " -c 'import meshio' > /dev/null 2>&1");
    if (rc != 0) {
        test_fail(__FILE__, __LINE__, MESHIO_PYTHON " cannot import meshio: " MESHIO_INSTALL_HINT);
        return;
    }

    readback_mesh(&m, x, uv, tri);
    snprintf(file, sizeof file, "%s/%s.%s", test_tmpdir(), stem, format_table[k].extension);
    snprintf(expected, sizeof expected, "%s/%s.expected.txt", test_tmpdir(), stem);
    snprintf(log, sizeof log, "%s/%s.log", test_tmpdir(), stem);
    r = cloth_mesh_write_file(&m, file, format);
    if (r != CLOTH_SUCCESS) printf("    cloth_mesh_write_file(%s): %s\n", file, cloth_result_string(r));
    ENSURE(r == CLOTH_SUCCESS);
    ENSURE(write_expected(expected, stem, format_table[k].token, &m, uv_required));
    snprintf(cmd, sizeof cmd, MESHIO_PYTHON " '%s/tests/fixtures/meshio_readback.py' '%s' '%s'%s > '%s' 2>&1",
             test_root(), file, expected, uv_required ? " --uv" : "", log);
    rc = system(cmd);
    if (rc != 0) {
        printf("    %s\n", cmd);
        print_file(log);
    }
    ENSURE(rc != -1 && WIFEXITED(rc) && WEXITSTATUS(rc) == 0);
}

/* Every format cloth.h writes is read back by meshio 5.0.0 (Debian 12's python3-meshio),
   including PLY binary big endian (meshio reads both byte orders; it only writes the host's),
   and uv is found where cloth.h writes it (OBJ vt, PLY u v). None is left out. What meshio
   5.0.0's readers insist on, and cloth.h's writers must keep doing:
     PLY   ascii: x y z are the first three vertex properties; binary: property types among
           uchar int uint float double int8..int64 uint8..uint64 float32 (its binary reader
           does not know char, short, ushort, int16 or float64, and reads uchar as signed);
     OFF   "OFF" alone on the first line, the counts line split by single spaces into exactly
           three numbers, triangles only;
     VTK   legacy 4.2 (and older) or 5.1 headers; points and cells big endian when binary;
     OBJ   uv by index: meshio ignores the vt of "f v/vt" and lists vt lines in file order, so
           uv is compared only because cloth.h writes one vt per vertex in vertex order. */
TEST(readback_obj) { readback(CLOTH_FORMAT_OBJ, "readback_obj", 1); }
TEST(readback_ply_ascii) { readback(CLOTH_FORMAT_PLY_ASCII, "readback_ply_ascii", 1); }
TEST(readback_ply_binary_le) { readback(CLOTH_FORMAT_PLY_BINARY_LE, "readback_ply_le", 1); }
TEST(readback_ply_binary_be) { readback(CLOTH_FORMAT_PLY_BINARY_BE, "readback_ply_be", 1); }
TEST(readback_vtk_ascii) { readback(CLOTH_FORMAT_VTK_ASCII, "readback_vtk_ascii", 0); }
TEST(readback_vtk_binary) { readback(CLOTH_FORMAT_VTK_BINARY, "readback_vtk_binary", 0); }
TEST(readback_off) { readback(CLOTH_FORMAT_OFF, "readback_off", 0); }

const test_case meshio_tests[] = {
    { "fixtures_complete", fixtures_complete },
    { "read_obj", read_obj },
    { "read_ply_ascii", read_ply_ascii },
    { "read_ply_binary_le", read_ply_binary_le },
    { "read_ply_binary_be", read_ply_binary_be },
    { "read_vtk51_ascii", read_vtk51_ascii },
    { "read_vtk51_binary", read_vtk51_binary },
    { "read_vtk42_ascii", read_vtk42_ascii },
    { "read_vtk42_binary", read_vtk42_binary },
    { "read_off", read_off },
    { "readback_obj", readback_obj },
    { "readback_ply_ascii", readback_ply_ascii },
    { "readback_ply_binary_le", readback_ply_binary_le },
    { "readback_ply_binary_be", readback_ply_binary_be },
    { "readback_vtk_ascii", readback_vtk_ascii },
    { "readback_vtk_binary", readback_vtk_binary },
    { "readback_off", readback_off },
    { NULL, NULL }
};
