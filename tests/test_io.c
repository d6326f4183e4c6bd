/* io: reading OBJ, PLY, VTK legacy and OFF from hand-written buffers, exact write -> read
   round trips of every writer, paths, and every error path with its place (line or byte
   offset), an empty mesh and nothing leaked afterwards. */
#include "runner.h"
#include "../cloth.h"
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- helpers -------------------------------------------------------------------------- */

/* Like ENSURE, inside helpers that return 0 on failure. */
#define CHECK(cond) do { if (!(cond)) { test_fail(__FILE__, __LINE__, #cond); return 0; } } while (0)

/* An allocator that counts live blocks, records the largest request, fails any request above
   `limit` and (when fail_at >= 0) the request numbered fail_at. */
typedef struct counting {
    size_t limit;
    size_t largest;
    long live;
    long requests;
    long fail_at;
} counting;

static void *counting_alloc(size_t size, void *user)
{
    counting *c = (counting *)user;
    void *p;
    long number = c->requests++;
    if (size > c->largest) c->largest = size;
    if (c->limit && size > c->limit) return NULL;
    if (c->fail_at >= 0 && number == c->fail_at) return NULL;
    p = malloc(size);
    if (p) ++c->live;
    return p;
}

static void counting_free(void *p, void *user)
{
    counting *c = (counting *)user;
    if (!p) return;
    --c->live;
    free(p);
}

static cloth_allocator counting_allocator(counting *c, size_t limit)
{
    cloth_allocator a;
    memset(c, 0, sizeof *c);
    c->limit = limit;
    c->fail_at = -1;
    a.alloc = counting_alloc;
    a.free = counting_free;
    a.user = c;
    return a;
}

static int mesh_is_empty(const cloth_mesh *m)
{
    return m->x == NULL && m->uv == NULL && m->tri == NULL && m->vertex_count == 0 && m->triangle_count == 0;
}

static cloth_result read_text(const char *text, cloth_file_format format, cloth_mesh *m, cloth_io_error *e)
{
    return cloth_mesh_read_memory(m, text, strlen(text), format, e, NULL);
}

/* Reading `size` bytes must fail with `code` at `line` and `offset` (-1: not checked), leave
   the mesh empty and free everything it allocated. */
static int expect_error(const void *data, size_t size, cloth_file_format format, cloth_result code, long line, long offset)
{
    counting c;
    cloth_allocator a = counting_allocator(&c, 64u << 20);
    cloth_mesh m;
    cloth_io_error e;
    cloth_result r = cloth_mesh_read_memory(&m, data, size, format, &e, &a);
    if (r != code || (line >= 0 && e.line != line) || (offset >= 0 && e.byte_offset != offset))
        printf("    got %s (line %lld, byte %lld: %s), expected %s (line %ld, byte %ld)\n", cloth_result_string(r),
               (long long)e.line, (long long)e.byte_offset, e.message, cloth_result_string(code), line, offset);
    CHECK(r == code);
    CHECK(line < 0 || e.line == line);
    CHECK(offset < 0 || e.byte_offset == offset);
    CHECK(e.message[0] != 0);
    CHECK(mesh_is_empty(&m));
    CHECK(c.live == 0);
    return 1;
}

static int expect_text_error(const char *text, cloth_file_format format, cloth_result code, long line, long offset)
{
    return expect_error(text, strlen(text), format, code, line, offset);
}

/* The offset of the first occurrence of `needle` in `text` (which must be there). */
static long offset_of(const char *text, const char *needle)
{
    const char *at = strstr(text, needle);
    return at ? (long)(at - text) : -1000000;
}

/* The offset of the first occurrence of `needle` in binary data (-1000000 when absent). */
static long find_bytes(const unsigned char *data, size_t size, const char *needle)
{
    size_t n = strlen(needle), i;
    for (i = 0; i + n <= size; ++i)
        if (memcmp(data + i, needle, n) == 0) return (long)i;
    return -1000000;
}

static int tri_is(const cloth_mesh *m, int32_t t, int32_t a, int32_t b, int32_t c)
{
    return t < m->triangle_count && m->tri[3 * t] == a && m->tri[3 * t + 1] == b && m->tri[3 * t + 2] == c;
}

/* Bit-exact equality of reals (so that -0.0 differs from 0.0). */
static int same_bits(const cloth_real *a, const cloth_real *b, size_t n)
{
    return memcmp(a, b, n * sizeof(cloth_real)) == 0;
}

/* A growing byte buffer for binary test files. */
typedef struct bytes {
    unsigned char data[16384];
    size_t n;
} bytes;

static void put(bytes *b, const void *p, size_t n)
{
    if (b->n + n > sizeof b->data) return;
    memcpy(b->data + b->n, p, n);
    b->n += n;
}
static void put_text(bytes *b, const char *s) { put(b, s, strlen(s)); }
static void put_uint(bytes *b, uint64_t v, int size, int big_endian)
{
    int i;
    for (i = 0; i < size; ++i) {
        unsigned char byte = (unsigned char)(v >> (8 * (big_endian ? size - 1 - i : i)));
        put(b, &byte, 1);
    }
}
static void put_f32(bytes *b, float f, int big_endian)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_uint(b, u, 4, big_endian);
}
static void put_f64(bytes *b, double d, int big_endian)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put_uint(b, u, 8, big_endian);
}

/* ---- OBJ ------------------------------------------------------------------------------ */

TEST(obj_face_forms)
{
    const char *text =
        "# every face form, skipped statements and extra vertex values\n"
        "mtllib cloth.mtl\n"
        "o sheet\n"
        "v 0 0 0\n"
        "v 1 0 0 1.0\n"
        "v 1 1 0 0.5 0.25 0.125\n"
        "v 0 1 0 # a comment after the numbers\n"
        "vt 0.25 0.5\n"
        "vt 0.75\n"
        "vn 0 0 1\n"
        "vp 0.5\n"
        "g group\n"
        "usemtl cotton\n"
        "s off\n"
        "f 1 2 3\n"
        "f 1/1 3/2 4/1\n"
        "f 1//1 2//1 4//1\n"
        "f 2/2/1 3/1/1 4/2/1\n"
        "l 1 2\n"
        "p 3\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(text, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 4 && m.triangle_count == 4);
    ENSURE(m.x[3] == 1 && m.x[6] == 1 && m.x[7] == 1 && m.x[10] == 1 && m.x[11] == 0);
    ENSURE(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 0, 1, 3) && tri_is(&m, 3, 1, 2, 3));
    ENSURE(m.uv != NULL);
    /* first pairings: v1 with vt1 (face 2), v2 with vt2 (face 2), v3 with vt1, v1 ... v2 with vt2 (face 4) */
    ENSURE(m.uv[0] == 0.25 && m.uv[1] == 0.5);
    ENSURE(m.uv[2] == 0.75 && m.uv[3] == 0);
    ENSURE(m.uv[4] == 0.75 && m.uv[5] == 0);
    ENSURE(m.uv[6] == 0.25 && m.uv[7] == 0.5);
    cloth_mesh_free(&m);
    ENSURE(mesh_is_empty(&m));
}

TEST(obj_relative_indices_and_polygons)
{
    const char *text =
        "v 0 0 0\r\n"
        "v 1 0 0\r\n"
        "\tv 1 1 0\r\n"
        "v 0.5 1.5 0\r\n"
        "v 0 1 0\r\n"
        "f -5 -4 -3 -2 -1\r\n"
        "v 2 2 2\r\n"
        "f -1 1 2 # relative to the vertices above\r\n"
        "f 6/1 1 -5\r\n"
        "vt 0 0\r\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(text, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 6 && m.triangle_count == 5);
    ENSURE(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 0, 3, 4));
    ENSURE(tri_is(&m, 3, 5, 0, 1) && tri_is(&m, 4, 5, 0, 1));
    ENSURE(m.x[3 * 3] == 0.5 && m.x[3 * 3 + 1] == 1.5 && m.x[3 * 5 + 2] == 2);
    ENSURE(m.uv != NULL && m.uv[2 * 5] == 0 && m.uv[2 * 5 + 1] == 0);
    cloth_mesh_free(&m);
}

TEST(obj_uv_pairing)
{
    /* v1 is paired with vt1 first and later with vt2: it keeps vt1. v4 is never paired: (0, 0).
       A forward vt reference (vt 3 defined below the face) is allowed. */
    const char *text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\n"
        "vt 0.125 0.25\nvt 0.5 0.75\n"
        "f 1/1 2/2 3/3\n"
        "f 1/2 3/1 2/1\n"
        "vt 0.875 1\n";
    const char *no_pairs = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1 2 3\nf 1//1 2//1 3//1\n";
    const char *no_vt = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(text, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.uv != NULL && m.vertex_count == 4);
    ENSURE(m.uv[0] == 0.125 && m.uv[1] == 0.25);
    ENSURE(m.uv[2] == 0.5 && m.uv[3] == 0.75);
    ENSURE(m.uv[4] == 0.875 && m.uv[5] == 1);
    ENSURE(m.uv[6] == 0 && m.uv[7] == 0);
    cloth_mesh_free(&m);
    ENSURE(read_text(no_pairs, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.uv == NULL && m.triangle_count == 2);
    cloth_mesh_free(&m);
    ENSURE(read_text(no_vt, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.uv == NULL && m.triangle_count == 1);
    cloth_mesh_free(&m);
}

/* A small deterministic generator for the tests. */
static uint64_t test_random(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* Numbers are read correctly rounded: every value must equal strtod's (glibc's strtod is
   correctly rounded). Covers the three paths of the reader: short mantissas, 17-19 digits
   (shortest round-trip output), and long or extreme numbers (exact arithmetic). */
TEST(obj_numbers_correctly_rounded)
{
    static const char *hard[] = {
        "0.1", "1e23", "8.988465674311579e307", "1.7976931348623157e308", "2.2250738585072011e-308",
        "2.2250738585072012e-308", "4.9406564584124654e-324", "2.4703282292062328e-324", "2.4703282292062327e-324",
        "9007199254740993", "9007199254740992.5", "18446744073709551615", "18446744073709551616",
        "1.00000000000000011102230246251565404236316680908203125",
        "1.00000000000000011102230246251565404236316680908203124",
        "1.00000000000000011102230246251565404236316680908203126",
        "1.00000000000000033306690738754696212708950042724609375", "123456789012345678901234567890", "-0", "0e999",
        ".5", "5.", "+1.5e+3", "-2.5E-3", "0.000000000000000000000000000000000000000000001", "7.2057594037927933e16",
        "3.0517578125e-05", "1e-320", "6.02214076e+23", "0.30000000000000004", "1e-64", "1e64", "1e-65", "9.999999999999999e22",
        "4.35679577e-05", "0.1234567890123456789e-40", "1234567890123456789e-300", "99999999999999999999e-20"
    };
    static char text[400000];
    static double expected[8000];
    size_t n = 0, count = 0, i;
    uint64_t state = 12345;
    cloth_mesh m;
    cloth_io_error e;
    char number[2000];
    /* an 800+ digit number just above the halfway point 1 + 2^-53: must round up */
    strcpy(number, "1.00000000000000011102230246251565404236316680908203125");
    for (i = strlen(number); i < 1500; ++i) number[i] = '0';
    number[1500] = '1';
    number[1501] = 0;
    for (i = 0; i < 6000; ++i) {
        char buf[64];
        const char *s = buf;
        double d;
        uint64_t r = test_random(&state);
        if (i < sizeof hard / sizeof hard[0]) {
            s = hard[i];
        } else if (i == sizeof hard / sizeof hard[0]) {
            s = number;
        } else if (i % 4 == 0) {
            uint64_t bits = test_random(&state) & 0x7FEFFFFFFFFFFFFFull; /* finite doubles, all exponents */
            memcpy(&d, &bits, sizeof d);
            snprintf(buf, sizeof buf, "%.17g", (r & 1) ? -d : d);
        } else if (i % 4 == 3) {
            /* near a halfway point between two doubles (exact where long double is wider):
               where rounding is hardest */
            uint64_t bits = test_random(&state) & 0x7FEFFFFFFFFFFFFFull;
            long double mid;
            memcpy(&d, &bits, sizeof d);
            mid = ((long double)d + (long double)nextafter(d, HUGE_VAL)) / 2;
            snprintf(buf, sizeof buf, "%.*Le", 15 + (int)(r % 10), mid);
        } else if (i % 4 == 1) {
            snprintf(buf, sizeof buf, "%.*g", (int)(1 + r % 19), (double)(r >> 11) * 1e-16 * ((r >> 5) % 7 + 1));
        } else {
            /* random digit strings of 1 to 25 digits with exponents -340 ... 300 */
            int digits = 1 + (int)(r % 25), k, len = 0;
            for (k = 0; k < digits; ++k) buf[len++] = (char)('0' + test_random(&state) % 10);
            len += snprintf(buf + len, sizeof buf - (size_t)len, "e%d", (int)(test_random(&state) % 641) - 340);
        }
        d = (double)(cloth_real)strtod(s, NULL); /* with float cloth_real: rounded through double, as documented */
        if (!(d - d == 0)) continue; /* overflow: not a coordinate */
        n += (size_t)snprintf(text + n, sizeof text - n, "v %s 0 0\n", s);
        expected[count++] = d;
    }
    n += (size_t)snprintf(text + n, sizeof text - n, "f 1 2 3\n");
    ENSURE(n < sizeof text - 1);
    ENSURE(read_text(text, CLOTH_FORMAT_OBJ, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == (int32_t)count);
    for (i = 0; i < count; ++i) {
        double got = (double)m.x[3 * i];
        if (memcmp(&got, &expected[i], sizeof got) != 0) {
            printf("    vertex %d: read %.17g, strtod says %.17g\n", (int)i, got, expected[i]);
            ENSURE(memcmp(&got, &expected[i], sizeof got) == 0);
        }
    }
    cloth_mesh_free(&m);
}

/* ---- PLY ------------------------------------------------------------------------------ */

TEST(ply_ascii)
{
    const char *text =
        "ply\r\n"
        "format ascii 1.0\r\n"
        "comment unknown elements and properties, lists included, are skipped\n"
        "obj_info anything\n"
        "element material 2\n"
        "property list uchar float shininess\n"
        "property int id\n"
        "element vertex 5\n"
        "property float temperature\n"
        "property double x\n"
        "property list int int neighbours\n"
        "property double y\n"
        "property float s\n"
        "property double z\n"
        "property float t\n"
        "element face 2\n"
        "property uchar flags\n"
        "property list int uint vertex_index\n"
        "property list uchar float weights\n"
        "end_header\n"
        "2 0.5 0.25 7\n"
        "0 9\n"
        "20.5 0 2 1 2 0 0.125 0 0.75\n"
        "21 1 0 0 0.25 0 0.5\n"
        "22 1 1 4 1 0.375 0 1\n"
        "23 0.5 0 1.5 0.5 -1e-3 1\n"
        "24 0 0 1 1 2.5e2 1\n"
        "7 3 0 1 2 3 0.1 0.2 0.3\n"
        "0 4 0 2 3 4 0\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(text, CLOTH_FORMAT_PLY_ASCII, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 5 && m.triangle_count == 3);
    ENSURE(m.x[0] == 0 && m.x[1] == 0 && m.x[2] == 0);
    ENSURE(m.x[3] == 1 && m.x[4] == 0 && m.x[5] == 0);
    ENSURE(m.x[6] == 1 && m.x[7] == 1 && m.x[8] == 0);
    ENSURE(m.x[9] == 0.5 && m.x[10] == 1.5 && m.x[11] == (cloth_real)-1e-3);
    ENSURE(m.x[12] == 0 && m.x[13] == 1 && m.x[14] == 2.5e2);
    ENSURE(m.uv != NULL);
    ENSURE(m.uv[0] == 0.125 && m.uv[1] == 0.75 && m.uv[2] == 0.25 && m.uv[3] == 0.5 && m.uv[8] == 1 && m.uv[9] == 1);
    ENSURE(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 0, 3, 4));
    cloth_mesh_free(&m);
}

static const char *const ply_type_names[] = { "char", "uchar", "short", "ushort", "int", "uint", "float", "double",
                                              "int8", "uint8", "int16", "uint16", "int32", "uint32", "float32", "float64" };
static const int ply_type_sizes[] = { 1, 1, 2, 2, 4, 4, 4, 8, 1, 1, 2, 2, 4, 4, 4, 8 };

/* Append value as PLY type t (an index into ply_type_names). */
static void put_ply_value(bytes *b, int t, double value, int big_endian)
{
    int size = ply_type_sizes[t];
    if (t % 8 == 6) put_f32(b, (float)value, big_endian);
    else if (t % 8 == 7) put_f64(b, value, big_endian);
    else put_uint(b, (uint64_t)(int64_t)value, size, big_endian);
}

/* A binary PLY: 4 vertices with coordinates of type ct (and uv of type double when uv is
   set, as texture_u/texture_v), an unknown element with a list between vertices and faces, a
   quad and a triangle with count type nt and index type it, and an extra list after them. */
static void make_binary_ply(bytes *b, int big_endian, int ct, int nt, int it, int uv)
{
    static const double coords[4][3] = { { 0, 0, 0 }, { 2, 0, 1 }, { 2, 3, 1 }, { 0, 3, 100 } };
    char line[160];
    int i, k;
    b->n = 0;
    put_text(b, "ply\nformat ");
    put_text(b, big_endian ? "binary_big_endian 1.0\n" : "binary_little_endian 1.0\n");
    put_text(b, "comment binary test\nelement vertex 4\nproperty short extra\n");
    for (k = 0; k < 3; ++k) {
        snprintf(line, sizeof line, "property %s %c\n", ply_type_names[ct], "xyz"[k]);
        put_text(b, line);
    }
    if (uv) put_text(b, "property double texture_u\nproperty double texture_v\n");
    put_text(b, "element edge 2\nproperty int a\nproperty list ushort double weights\n");
    snprintf(line, sizeof line, "element face 2\nproperty list %s %s vertex_indices\nproperty list uchar uchar tags\nend_header\n",
             ply_type_names[nt], ply_type_names[it]);
    put_text(b, line);
    for (i = 0; i < 4; ++i) {
        put_uint(b, 0xBEEF, 2, big_endian);
        for (k = 0; k < 3; ++k) put_ply_value(b, ct, coords[i][k] * ((ct % 8 >= 6) ? 0.5 : 1), big_endian);
        if (uv) {
            put_f64(b, 0.1 * i, big_endian);
            put_f64(b, -0.3 * i, big_endian);
        }
    }
    for (i = 0; i < 2; ++i) {
        put_uint(b, 77, 4, big_endian);
        put_uint(b, (uint64_t)(i + 1), 2, big_endian);
        for (k = 0; k <= i; ++k) put_f64(b, 1.5, big_endian);
    }
    put_ply_value(b, nt, 4, big_endian);
    for (k = 0; k < 4; ++k) put_ply_value(b, it, k, big_endian);
    put_uint(b, 2, 1, 0);
    put_uint(b, 0x0101, 2, 0);
    put_ply_value(b, nt, 3, big_endian);
    put_ply_value(b, it, 3, big_endian);
    put_ply_value(b, it, 2, big_endian);
    put_ply_value(b, it, 1, big_endian);
    put_uint(b, 0, 1, 0);
}

static int check_binary_ply(int big_endian, int ct, int nt, int it, int uv)
{
    static const double coords[4][3] = { { 0, 0, 0 }, { 2, 0, 1 }, { 2, 3, 1 }, { 0, 3, 100 } };
    bytes b;
    cloth_mesh m;
    cloth_io_error e;
    cloth_result r;
    int i, k;
    make_binary_ply(&b, big_endian, ct, nt, it, uv);
    r = cloth_mesh_read_memory(&m, b.data, b.n, CLOTH_FORMAT_PLY_BINARY_LE, &e, NULL);
    if (r != CLOTH_SUCCESS)
        printf("    %s coordinates %s, counts %s, indices %s: %s (byte %lld: %s)\n", big_endian ? "BE" : "LE", ply_type_names[ct],
               ply_type_names[nt], ply_type_names[it], cloth_result_string(r), (long long)e.byte_offset, e.message);
    CHECK(r == CLOTH_SUCCESS);
    CHECK(cloth_detect_format(b.data, b.n) == (big_endian ? CLOTH_FORMAT_PLY_BINARY_BE : CLOTH_FORMAT_PLY_BINARY_LE));
    CHECK(m.vertex_count == 4 && m.triangle_count == 3);
    for (i = 0; i < 4; ++i)
        for (k = 0; k < 3; ++k) CHECK(m.x[3 * i + k] == (cloth_real)(coords[i][k] * ((ct % 8 >= 6) ? 0.5 : 1)));
    CHECK(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 3, 2, 1));
    CHECK((m.uv != NULL) == (uv != 0));
    if (uv) CHECK(m.uv[6] == (cloth_real)0.30000000000000004 && m.uv[7] == (cloth_real)(-0.3 * 3));
    cloth_mesh_free(&m);
    return 1;
}

TEST(ply_binary_every_type)
{
    int be, t, nt, it;
    for (be = 0; be < 2; ++be) {
        for (t = 0; t < 16; ++t) ENSURE(check_binary_ply(be, t, 1, 4, t & 1));
        for (nt = 0; nt < 16; ++nt) {
            if (nt % 8 >= 6) continue; /* counts are integers */
            for (it = 0; it < 16; ++it) {
                if (it % 8 >= 6) continue;
                ENSURE(check_binary_ply(be, 7, nt, it, 0));
            }
        }
    }
}

TEST(ply_uv_names)
{
    const char *uv_names[3][2] = { { "u", "v" }, { "s", "t" }, { "texture_u", "texture_v" } };
    int k;
    for (k = 0; k < 3; ++k) {
        char text[600];
        cloth_mesh m;
        cloth_io_error e;
        snprintf(text, sizeof text,
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float %s\nproperty float %s\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0 0.5 0.25\n1 0 0 1 0.25\n0 1 0 0.5 1\n3 0 1 2\n",
                 uv_names[k][0], uv_names[k][1]);
        ENSURE(read_text(text, CLOTH_FORMAT_AUTO, &m, &e) == CLOTH_SUCCESS);
        ENSURE(m.uv != NULL && m.uv[0] == 0.5 && m.uv[1] == 0.25 && m.uv[2] == 1 && m.uv[5] == 1);
        cloth_mesh_free(&m);
    }
}

/* ---- VTK ------------------------------------------------------------------------------ */

/* Six points; cells: a triangle, a quad, a line, a vertex, a pentagon, a tetrahedron. */
static const double vtk_points[6][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 1.5, 0.25 }, { 0.5, 0.5, 1 } };
static const int vtk_cell_sizes[6] = { 3, 4, 2, 1, 5, 4 };
static const int vtk_cells[6][5] = { { 0, 1, 2 }, { 0, 1, 2, 3 }, { 0, 5 }, { 5 }, { 0, 1, 2, 4, 3 }, { 0, 1, 2, 5 } };
static const int vtk_cell_types[6] = { 5, 9, 3, 1, 7, 10 };

static int check_vtk_mesh(const cloth_mesh *m)
{
    int i, k;
    CHECK(m->vertex_count == 6 && m->triangle_count == 6);
    for (i = 0; i < 6; ++i)
        for (k = 0; k < 3; ++k) CHECK(m->x[3 * i + k] == vtk_points[i][k]);
    CHECK(tri_is(m, 0, 0, 1, 2));
    CHECK(tri_is(m, 1, 0, 1, 2) && tri_is(m, 2, 0, 2, 3));
    CHECK(tri_is(m, 3, 0, 1, 2) && tri_is(m, 4, 0, 2, 4) && tri_is(m, 5, 0, 4, 3));
    CHECK(m->uv == NULL);
    return 1;
}

/* A VTK file with the cells above: classic or 5.1 layout, ascii or binary, with field data
   before the points, metadata after them, and point and cell data after the cells. */
static void make_vtk(bytes *b, int binary, int v51)
{
    char line[200];
    int i, k, size = 0;
    b->n = 0;
    put_text(b, v51 ? "# vtk DataFile Version 5.1\n" : "# vtk DataFile Version 4.2\n");
    put_text(b, "a title line\n");
    put_text(b, binary ? "BINARY\n" : "ASCII\n");
    put_text(b, "DATASET UNSTRUCTURED_GRID\nFIELD FieldData 2\nTIME 1 1 double\n");
    if (binary) put_f64(b, 1.25, 1);
    else put_text(b, "1.25");
    put_text(b, "\nCYCLE 1 1 int\n");
    if (binary) put_uint(b, 3, 4, 1);
    else put_text(b, "3");
    put_text(b, "\nPOINTS 6 double\n");
    for (i = 0; i < 6; ++i) {
        for (k = 0; k < 3; ++k) {
            if (binary) put_f64(b, vtk_points[i][k], 1);
            else {
                snprintf(line, sizeof line, "%.17g%s", vtk_points[i][k], k == 2 ? "\n" : " ");
                put_text(b, line);
            }
        }
    }
    if (binary) put_text(b, "\n");
    put_text(b, "METADATA\nINFORMATION 0\n\n");
    for (i = 0; i < 6; ++i) size += vtk_cell_sizes[i];
    if (v51) {
        int offset = 0;
        snprintf(line, sizeof line, "CELLS 7 %d\nOFFSETS vtktypeint64\n", size);
        put_text(b, line);
        for (i = 0; i <= 6; ++i) {
            if (binary) put_uint(b, (uint64_t)offset, 8, 1);
            else {
                snprintf(line, sizeof line, "%d\n", offset);
                put_text(b, line);
            }
            if (i < 6) offset += vtk_cell_sizes[i];
        }
        put_text(b, binary ? "\nCONNECTIVITY vtktypeint64\n" : "CONNECTIVITY vtktypeint64\n");
        for (i = 0; i < 6; ++i)
            for (k = 0; k < vtk_cell_sizes[i]; ++k) {
                if (binary) put_uint(b, (uint64_t)vtk_cells[i][k], 8, 1);
                else {
                    snprintf(line, sizeof line, "%d ", vtk_cells[i][k]);
                    put_text(b, line);
                }
            }
    } else {
        snprintf(line, sizeof line, "CELLS 6 %d\n", size + 6);
        put_text(b, line);
        for (i = 0; i < 6; ++i) {
            if (binary) put_uint(b, (uint64_t)vtk_cell_sizes[i], 4, 1);
            else {
                snprintf(line, sizeof line, "%d", vtk_cell_sizes[i]);
                put_text(b, line);
            }
            for (k = 0; k < vtk_cell_sizes[i]; ++k) {
                if (binary) put_uint(b, (uint64_t)vtk_cells[i][k], 4, 1);
                else {
                    snprintf(line, sizeof line, " %d", vtk_cells[i][k]);
                    put_text(b, line);
                }
            }
            if (!binary) put_text(b, "\n");
        }
    }
    put_text(b, "\nCELL_TYPES 6\n");
    for (i = 0; i < 6; ++i) {
        if (binary) put_uint(b, (uint64_t)vtk_cell_types[i], 4, 1);
        else {
            snprintf(line, sizeof line, "%d\n", vtk_cell_types[i]);
            put_text(b, line);
        }
    }
    put_text(b, binary ? "\nPOINT_DATA 6\nSCALARS temperature float 1\nLOOKUP_TABLE default\n" :
                         "POINT_DATA 6\nSCALARS temperature float 1\nLOOKUP_TABLE default\n");
    for (i = 0; i < 6; ++i) {
        if (binary) put_f32(b, 20.0f + (float)i, 1);
        else put_text(b, "20.5\n");
    }
    put_text(b, binary ? "\nCELL_DATA 6\nFIELD FieldData 1\nmaterial 1 6 int\n" : "CELL_DATA 6\nFIELD FieldData 1\nmaterial 1 6 int\n");
    for (i = 0; i < 6; ++i) {
        if (binary) put_uint(b, (uint64_t)i, 4, 1);
        else put_text(b, "1 ");
    }
    put_text(b, "\n");
}

TEST(vtk_layouts)
{
    int binary, v51;
    for (binary = 0; binary < 2; ++binary) {
        for (v51 = 0; v51 < 2; ++v51) {
            bytes b;
            cloth_mesh m;
            cloth_io_error e;
            cloth_result r;
            make_vtk(&b, binary, v51);
            r = cloth_mesh_read_memory(&m, b.data, b.n, binary ? CLOTH_FORMAT_VTK_BINARY : CLOTH_FORMAT_VTK_ASCII, &e, NULL);
            if (r != CLOTH_SUCCESS)
                printf("    %s %s: %s (line %lld, byte %lld: %s)\n", binary ? "binary" : "ascii", v51 ? "5.1" : "4.2",
                       cloth_result_string(r), (long long)e.line, (long long)e.byte_offset, e.message);
            ENSURE(r == CLOTH_SUCCESS);
            ENSURE(check_vtk_mesh(&m));
            cloth_mesh_free(&m);
            ENSURE(cloth_detect_format(b.data, b.n) == (binary ? CLOTH_FORMAT_VTK_BINARY : CLOTH_FORMAT_VTK_ASCII));
            ENSURE(cloth_mesh_read_memory(&m, b.data, b.n, CLOTH_FORMAT_AUTO, &e, NULL) == CLOTH_SUCCESS);
            ENSURE(check_vtk_mesh(&m));
            cloth_mesh_free(&m);
        }
    }
}

TEST(vtk_polydata)
{
    const char *text =
        "# vtk DataFile Version 3.0\n"
        "polydata with vertices, lines and polygons\n"
        "ascii\n"
        "dataset polydata\n"
        "POINTS 5 float\n"
        "0 0 0 1 0 0 1 1 0\n"
        "0 1 0 0.5 0.5 0.5\n"
        "VERTICES 1 2\n"
        "1 4\n"
        "LINES 1 3\n"
        "2 0 4\n"
        "POLYGONS 2 9\n"
        "4 0 1 2 3\n"
        "3 1 2 4\n"
        "POINT_DATA 5\n"
        "NORMALS n float\n"
        "0 0 1 0 0 1 0 0 1 0 0 1 0 0 1\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(text, CLOTH_FORMAT_VTK_ASCII, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 5 && m.triangle_count == 3);
    ENSURE(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 1, 2, 4));
    ENSURE(m.x[12] == 0.5 && m.x[14] == 0.5);
    cloth_mesh_free(&m);
    /* integer points */
    ENSURE(read_text("# vtk DataFile Version 2.0\nint points\nASCII\nDATASET POLYDATA\nPOINTS 3 int\n0 0 0 -2 0 0 0 7 0\n"
                     "POLYGONS 1 4\n3 0 1 2\n", CLOTH_FORMAT_VTK_ASCII, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 3 && m.triangle_count == 1 && m.x[3] == -2 && m.x[7] == 7);
    cloth_mesh_free(&m);
}

/* ---- OFF ------------------------------------------------------------------------------ */

TEST(off_variants)
{
    const char *plain =
        "OFF\n"
        "# a comment\n"
        "\n"
        "5 3 0\n"
        "0 0 0\n"
        "1 0 0\n"
        "1 1 0 # comment\n"
        "0 1 0\n"
        "0.5 1.5 -2.5e-1\n"
        "3 0 1 2 255 0 0\n"
        "4 0 2 3 4\n"
        "3 4 3 2 0.5 0.5 0.5 1\n";
    const char *counts_on_header = "COFF 3 1 3\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n";
    cloth_mesh m;
    cloth_io_error e;
    ENSURE(read_text(plain, CLOTH_FORMAT_OFF, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 5 && m.triangle_count == 4 && m.uv == NULL);
    ENSURE(tri_is(&m, 0, 0, 1, 2) && tri_is(&m, 1, 0, 2, 3) && tri_is(&m, 2, 0, 3, 4) && tri_is(&m, 3, 4, 3, 2));
    ENSURE(m.x[12] == 0.5 && m.x[13] == 1.5 && m.x[14] == -0.25);
    cloth_mesh_free(&m);
    ENSURE(read_text(counts_on_header, CLOTH_FORMAT_AUTO, &m, &e) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 3 && m.triangle_count == 1 && m.x[3] == 1 && m.x[7] == 1);
    cloth_mesh_free(&m);
}

/* ---- detection ------------------------------------------------------------------------ */

TEST(detect_format)
{
    ENSURE(cloth_detect_format("ply\nformat ascii 1.0\n", 20) == CLOTH_FORMAT_PLY_ASCII);
    ENSURE(cloth_detect_format("ply\r\nformat binary_big_endian 1.0\r\n", 34) == CLOTH_FORMAT_PLY_BINARY_BE);
    ENSURE(cloth_detect_format("ply\ncomment x\nformat binary_little_endian 1.0\n", 46) == CLOTH_FORMAT_PLY_BINARY_LE);
    ENSURE(cloth_detect_format("# vtk DataFile Version 2.0\nt\nBINARY\n", 36) == CLOTH_FORMAT_VTK_BINARY);
    ENSURE(cloth_detect_format("# vtk DataFile Version 2.0\nt\nASCII\n", 35) == CLOTH_FORMAT_VTK_ASCII);
    ENSURE(cloth_detect_format("OFF\n3 1 0\n", 10) == CLOTH_FORMAT_OFF);
    ENSURE(cloth_detect_format("# made by hand\nNOFF 3 1 0\n", 26) == CLOTH_FORMAT_OFF);
    ENSURE(cloth_detect_format("# comment\n\nv 1 2 3\n", 20) == CLOTH_FORMAT_OBJ);
    ENSURE(cloth_detect_format("mtllib a.mtl\n", 13) == CLOTH_FORMAT_OBJ);
    ENSURE(cloth_detect_format("hello world\n", 12) == CLOTH_FORMAT_AUTO);
    ENSURE(cloth_detect_format("# only a comment\n", 17) == CLOTH_FORMAT_AUTO);
    ENSURE(cloth_detect_format("", 0) == CLOTH_FORMAT_AUTO);
    ENSURE(cloth_detect_format(NULL, 0) == CLOTH_FORMAT_AUTO);
    ENSURE(cloth_detect_format("plywood 3\n", 10) == CLOTH_FORMAT_AUTO);
}

/* ---- round trips ------------------------------------------------------------------------ */

static const cloth_file_format all_formats[7] = { CLOTH_FORMAT_OBJ, CLOTH_FORMAT_PLY_ASCII, CLOTH_FORMAT_PLY_BINARY_LE,
                                                  CLOTH_FORMAT_PLY_BINARY_BE, CLOTH_FORMAT_VTK_ASCII, CLOTH_FORMAT_VTK_BINARY,
                                                  CLOTH_FORMAT_OFF };
static const char *const format_names[8] = { "auto", "obj", "ply_ascii", "ply_le", "ply_be", "vtk_ascii", "vtk_binary", "off" };

static int format_keeps_uv(cloth_file_format f) { return f != CLOTH_FORMAT_VTK_ASCII && f != CLOTH_FORMAT_VTK_BINARY && f != CLOTH_FORMAT_OFF; }

/* A 9 x 7 grid with values that need every digit, extremes, a subnormal and a negative zero. */
static void awkward_mesh(cloth_mesh *m, cloth_real *x, cloth_real *uv, int32_t *tri)
{
    int i, j, t = 0;
    for (j = 0; j < 7; ++j) {
        for (i = 0; i < 9; ++i) {
            int v = j * 9 + i;
            x[3 * v] = (cloth_real)(0.1 * i - 0.3);
            x[3 * v + 1] = (cloth_real)(1.0 / 3.0 + 0.01 * sin(0.7 * i + 1.3 * j));
            x[3 * v + 2] = (cloth_real)(j / 7.0);
            uv[2 * v] = (cloth_real)(0.1 * i);
            uv[2 * v + 1] = (cloth_real)(j / 3.0);
        }
    }
    x[1] = (cloth_real)-0.0;
    x[4] = (cloth_real)1e-300;   /* 0 in float */
    x[7] = (cloth_real)4.9406564584124654e-324;
    x[10] = sizeof(cloth_real) == sizeof(float) ? (cloth_real)FLT_MAX : (cloth_real)DBL_MAX;
    x[13] = (cloth_real)-6.02214076e23;
    x[16] = (cloth_real)2.2250738585072014e-308;
    uv[3] = (cloth_real)-1.2345678901234567e-7;
    for (j = 0; j + 1 < 7; ++j) {
        for (i = 0; i + 1 < 9; ++i) {
            int32_t a = j * 9 + i;
            tri[t++] = a; tri[t++] = a + 1; tri[t++] = a + 10;
            tri[t++] = a; tri[t++] = a + 10; tri[t++] = a + 9;
        }
    }
    memset(m, 0, sizeof *m);
    m->vertex_count = 63;
    m->triangle_count = 96;
    m->x = x;
    m->uv = uv;
    m->tri = tri;
}

static int same_mesh(const cloth_mesh *a, const cloth_mesh *b, int with_uv)
{
    CHECK(a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count);
    CHECK(same_bits(a->x, b->x, 3 * (size_t)a->vertex_count));
    CHECK(memcmp(a->tri, b->tri, sizeof(int32_t) * 3 * (size_t)a->triangle_count) == 0);
    if (with_uv) CHECK(b->uv != NULL && same_bits(a->uv, b->uv, 2 * (size_t)a->vertex_count));
    else CHECK(b->uv == NULL);
    return 1;
}

TEST(roundtrip_memory_exact)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    cloth_mesh m, back;
    int k, with_uv;
    awkward_mesh(&m, x, uv, tri);
    for (with_uv = 0; with_uv < 2; ++with_uv) {
        m.uv = with_uv ? uv : NULL;
        for (k = 0; k < 7; ++k) {
            cloth_file_format f = all_formats[k];
            counting c;
            cloth_allocator a = counting_allocator(&c, 0);
            void *data = NULL;
            size_t size = 0;
            cloth_io_error e;
            cloth_result r = cloth_mesh_write_memory(&m, f, &data, &size, &a);
            if (r != CLOTH_SUCCESS) printf("    writing %s: %s\n", format_names[f], cloth_result_string(r));
            ENSURE(r == CLOTH_SUCCESS && data != NULL && size > 0);
            ENSURE(cloth_detect_format(data, size) == f);
            r = cloth_mesh_read_memory(&back, data, size, f, &e, &a);
            if (r != CLOTH_SUCCESS)
                printf("    reading %s: %s (line %lld, byte %lld: %s)\n", format_names[f], cloth_result_string(r), (long long)e.line,
                       (long long)e.byte_offset, e.message);
            ENSURE(r == CLOTH_SUCCESS);
            if (!same_mesh(&m, &back, with_uv && format_keeps_uv(f))) printf("    format %s, uv %d\n", format_names[f], with_uv);
            cloth_mesh_free(&back);
            ENSURE(cloth_mesh_read_memory(&back, data, size, CLOTH_FORMAT_AUTO, &e, &a) == CLOTH_SUCCESS);
            ENSURE(same_mesh(&m, &back, with_uv && format_keeps_uv(f)));
            cloth_mesh_free(&back);
            a.free(data, a.user);
            ENSURE(c.live == 0);
        }
    }
}

/* Bigger meshes through the fixed-stride fast paths of binary PLY and through the writers'
   buffer growth; the generator's mesh goes out and comes back unchanged. */
TEST(roundtrip_grid)
{
    cloth_mesh grid, back;
    int k;
    ENSURE(cloth_mesh_grid(&grid, 61, 43, (cloth_real)1.7, (cloth_real)1.1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    for (k = 0; k < 7; ++k) {
        void *data = NULL;
        size_t size = 0;
        cloth_io_error e;
        ENSURE(cloth_mesh_write_memory(&grid, all_formats[k], &data, &size, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_mesh_read_memory(&back, data, size, all_formats[k], &e, NULL) == CLOTH_SUCCESS);
        ENSURE(same_mesh(&grid, &back, format_keeps_uv(all_formats[k])));
        cloth_mesh_free(&back);
        free(data);
    }
    cloth_mesh_free(&grid);
}

TEST(paths)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    static const char *const extensions[7] = { "obj", "ply", "ply", "ply", "vtk", "vtk", "off" };
    cloth_mesh m, back;
    cloth_io_error e;
    char path[512];
    int k;
    FILE *f;
    awkward_mesh(&m, x, uv, tri);
    for (k = 0; k < 7; ++k) {
        snprintf(path, sizeof path, "%s/io_path_%s.%s", test_tmpdir(), format_names[all_formats[k]], extensions[k]);
        ENSURE(cloth_mesh_write_file(&m, path, all_formats[k]) == CLOTH_SUCCESS);
        ENSURE(cloth_mesh_read_file(&back, path, all_formats[k], &e, NULL) == CLOTH_SUCCESS);
        ENSURE(same_mesh(&m, &back, format_keeps_uv(all_formats[k])));
        cloth_mesh_free(&back);
        ENSURE(cloth_mesh_read_file(&back, path, CLOTH_FORMAT_AUTO, &e, NULL) == CLOTH_SUCCESS);
        ENSURE(same_mesh(&m, &back, format_keeps_uv(all_formats[k])));
        cloth_mesh_free(&back);
    }
    /* CLOTH_FORMAT_AUTO when writing: by extension, in any case */
    snprintf(path, sizeof path, "%s/io_auto.PLY", test_tmpdir());
    ENSURE(cloth_mesh_write_file(&m, path, CLOTH_FORMAT_AUTO) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_read_file(&back, path, CLOTH_FORMAT_AUTO, &e, NULL) == CLOTH_SUCCESS);
    ENSURE(same_mesh(&m, &back, 1));
    cloth_mesh_free(&back);
    snprintf(path, sizeof path, "%s/io_auto.mesh", test_tmpdir());
    ENSURE(cloth_mesh_write_file(&m, path, CLOTH_FORMAT_AUTO) == CLOTH_ERROR_INVALID_ARGUMENT);
    /* Content that says nothing is read by the extension: an OBJ of comments has no vertices. */
    snprintf(path, sizeof path, "%s/io_comments.obj", test_tmpdir());
    f = fopen(path, "wb");
    ENSURE(f != NULL);
    fputs("# nothing but a comment\n", f);
    fclose(f);
    ENSURE(cloth_mesh_read_file(&back, path, CLOTH_FORMAT_AUTO, &e, NULL) == CLOTH_ERROR_EMPTY_MESH);
    ENSURE(mesh_is_empty(&back));
    ENSURE(expect_text_error("# nothing but a comment\n", CLOTH_FORMAT_AUTO, CLOTH_ERROR_PARSE, 1, 0));
}

TEST(path_errors)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    cloth_mesh m, back;
    cloth_io_error e;
    counting c;
    cloth_allocator a = counting_allocator(&c, 0);
    char path[512];
    awkward_mesh(&m, x, uv, tri);
    snprintf(path, sizeof path, "%s/no/such/dir/mesh.obj", test_tmpdir());
    ENSURE(cloth_mesh_read_file(&back, path, CLOTH_FORMAT_AUTO, &e, &a) == CLOTH_ERROR_FILE_OPEN);
    ENSURE(mesh_is_empty(&back) && e.line == 0 && e.byte_offset == 0 && strstr(e.message, "no/such/dir") != NULL);
    ENSURE(cloth_mesh_write_file(&m, path, CLOTH_FORMAT_OBJ) == CLOTH_ERROR_FILE_OPEN);
    /* a directory opens but cannot be read */
    ENSURE(cloth_mesh_read_file(&back, test_tmpdir(), CLOTH_FORMAT_OBJ, &e, &a) == CLOTH_ERROR_FILE_READ);
    ENSURE(mesh_is_empty(&back) && c.live == 0 && c.largest < 65536);
    /* an empty file */
    snprintf(path, sizeof path, "%s/io_empty.ply", test_tmpdir());
    fclose(fopen(path, "wb"));
    ENSURE(cloth_mesh_read_file(&back, path, CLOTH_FORMAT_AUTO, &e, &a) == CLOTH_ERROR_EMPTY_MESH);
    ENSURE(mesh_is_empty(&back) && c.live == 0);
}

/* ---- errors: reading ---------------------------------------------------------------------- */

TEST(errors_obj)
{
    const char *bad_number = "v 0 0 0\nv 1 0 0\nv 0 1.5.2 0\nf 1 2 3\n";
    const char *missing = "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n";
    const char *out_of_range = "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 3\nf 1 2 4\n";
    const char *relative = "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n";
    const char *zero = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n";
    const char *vt_range = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n";
    const char *nan = "v 0 0 0\nv 1 0 0\nv 0 NaN 0\nf 1 2 3\n";
    const char *inf = "v 0 0 0\nv 1 0 0\nv 0 1e999 0\nf 1 2 3\n";
    const char *vt_nan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 -inf\nf 1/1 2/1 3/1\n";
    const char *unknown = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvertex 1 2 3\nf 1 2 3\n";
    const char *two = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n";
    const char *corner = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3x\n";
    const char *no_faces = "v 0 0 0\nv 1 0 0\n";
    ENSURE(expect_text_error(bad_number, CLOTH_FORMAT_OBJ, CLOTH_ERROR_PARSE, 3, offset_of(bad_number, "1.5.2")));
    ENSURE(expect_text_error(missing, CLOTH_FORMAT_OBJ, CLOTH_ERROR_PARSE, 2, offset_of(missing, "\nv 0 1 0")));
    ENSURE(expect_text_error(out_of_range, CLOTH_FORMAT_OBJ, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 6, offset_of(out_of_range, "4\n")));
    ENSURE(expect_text_error(relative, CLOTH_FORMAT_OBJ, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 3, offset_of(relative, "-3")));
    ENSURE(expect_text_error(zero, CLOTH_FORMAT_OBJ, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 4, offset_of(zero, "0 1 2")));
    ENSURE(expect_text_error(vt_range, CLOTH_FORMAT_OBJ, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 5, offset_of(vt_range, "2/2 ") + 2));
    ENSURE(expect_text_error(nan, CLOTH_FORMAT_OBJ, CLOTH_ERROR_NOT_FINITE, 3, offset_of(nan, "NaN")));
    ENSURE(expect_text_error(inf, CLOTH_FORMAT_OBJ, CLOTH_ERROR_NOT_FINITE, 3, offset_of(inf, "1e999")));
    ENSURE(expect_text_error(vt_nan, CLOTH_FORMAT_OBJ, CLOTH_ERROR_NOT_FINITE, 4, offset_of(vt_nan, "-inf")));
    ENSURE(expect_text_error(unknown, CLOTH_FORMAT_OBJ, CLOTH_ERROR_PARSE, 4, offset_of(unknown, "vertex")));
    ENSURE(expect_text_error(two, CLOTH_FORMAT_OBJ, CLOTH_ERROR_PARSE, 5, offset_of(two, "f 1 2\n")));
    ENSURE(expect_text_error(corner, CLOTH_FORMAT_OBJ, CLOTH_ERROR_PARSE, 4, offset_of(corner, "3x")));
    ENSURE(expect_text_error(no_faces, CLOTH_FORMAT_OBJ, CLOTH_ERROR_EMPTY_MESH, 3, (long)strlen(no_faces)));
}

TEST(errors_empty_input)
{
    int k;
    for (k = 0; k < 7; ++k) {
        ENSURE(expect_error("", 0, all_formats[k], CLOTH_ERROR_EMPTY_MESH, 1, 0));
        ENSURE(expect_error(NULL, 0, all_formats[k], CLOTH_ERROR_EMPTY_MESH, 1, 0));
        ENSURE(expect_text_error(" \n\r\n\t", all_formats[k], CLOTH_ERROR_EMPTY_MESH, 3, 5));
    }
    ENSURE(expect_error("", 0, CLOTH_FORMAT_AUTO, CLOTH_ERROR_EMPTY_MESH, 1, 0));
    ENSURE(expect_text_error("\x01\x02 garbage", CLOTH_FORMAT_AUTO, CLOTH_ERROR_PARSE, 1, 0));
}

static const char ply_head[] = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

/* The binary PLY above with three vertices and one triangle; index k of the face is `last`. */
static void make_small_ply(bytes *b, float y1, int32_t last)
{
    int i;
    b->n = 0;
    put_text(b, ply_head);
    for (i = 0; i < 9; ++i) put_f32(b, i == 4 ? y1 : (float)i, 0);
    put_uint(b, 3, 1, 0);
    put_uint(b, 0, 4, 0);
    put_uint(b, 1, 4, 0);
    put_uint(b, (uint32_t)last, 4, 0);
}

TEST(errors_ply)
{
    const char *not_ply = "plyx\nformat ascii 1.0\nend_header\n";
    const char *no_format = "ply\nelement vertex 0\nend_header\n";
    const char *version = "ply\nformat ascii 2.0\nend_header\n";
    const char *type = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty real y\nend_header\n";
    const char *no_end = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
    const char *no_z = "ply\nformat ascii 1.0\ncomment\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n";
    const char *float_index = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar float vertex_indices\nend_header\n";
    const char *ascii_nan = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n";
    const char *ascii_range = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
    const char *ascii_bad = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1,5 0\n3 0 1 2\n";
    const char *ascii_short = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n";
    const char *two_corners = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n";
    bytes b;
    size_t body = strlen(ply_head);
    ENSURE(expect_text_error(not_ply, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 1, 0));
    ENSURE(expect_text_error(no_format, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 4, (long)strlen(no_format)));
    ENSURE(expect_text_error(version, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_UNSUPPORTED, 2, offset_of(version, "2.0")));
    ENSURE(expect_text_error(type, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 5, offset_of(type, "real")));
    ENSURE(expect_text_error(no_end, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_TRUNCATED, 5, (long)strlen(no_end)));
    ENSURE(expect_text_error(no_z, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 4, offset_of(no_z, "element")));
    ENSURE(expect_text_error(float_index, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_UNSUPPORTED, 8, offset_of(float_index, "float vertex_")));
    ENSURE(expect_text_error(ascii_nan, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_NOT_FINITE, 12, offset_of(ascii_nan, "nan")));
    ENSURE(expect_text_error(ascii_range, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 13, (long)strlen(ascii_range) - 2));
    ENSURE(expect_text_error(ascii_bad, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 12, offset_of(ascii_bad, "1,5")));
    ENSURE(expect_text_error(ascii_short, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_TRUNCATED, 14, (long)strlen(ascii_short)));
    ENSURE(expect_text_error(two_corners, CLOTH_FORMAT_PLY_ASCII, CLOTH_ERROR_PARSE, 13, (long)strlen(two_corners) - 1));
    /* binary: the place is a byte offset, the line 0 */
    make_small_ply(&b, 1.0f, 2);
    {
        cloth_mesh m;
        cloth_io_error e;
        ENSURE(cloth_mesh_read_memory(&m, b.data, b.n, CLOTH_FORMAT_PLY_BINARY_LE, &e, NULL) == CLOTH_SUCCESS);
        ENSURE(m.triangle_count == 1 && m.x[4] == 1.0f);
        cloth_mesh_free(&m);
    }
    ENSURE(expect_error(b.data, b.n - 5, CLOTH_FORMAT_PLY_BINARY_LE, CLOTH_ERROR_TRUNCATED, 0, (long)(body + 36 + 1)));
    ENSURE(expect_error(b.data, body + 20, CLOTH_FORMAT_PLY_BINARY_LE, CLOTH_ERROR_TRUNCATED, 0, (long)body));
    make_small_ply(&b, NAN, 2);
    ENSURE(expect_error(b.data, b.n, CLOTH_FORMAT_PLY_BINARY_LE, CLOTH_ERROR_NOT_FINITE, 0, (long)(body + 16)));
    make_small_ply(&b, 1.0f, 3);
    ENSURE(expect_error(b.data, b.n, CLOTH_FORMAT_PLY_BINARY_LE, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 0, (long)(body + 36 + 9)));
    make_small_ply(&b, 1.0f, -1);
    ENSURE(expect_error(b.data, b.n, CLOTH_FORMAT_PLY_BINARY_LE, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 0, (long)(body + 36 + 9)));
}

TEST(errors_vtk)
{
    const char *not_vtk = "# vtk data\nx\nASCII\n";
    const char *third = "# vtk DataFile Version 2.0\ntitle\nTEXT\nDATASET UNSTRUCTURED_GRID\n";
    const char *structured = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n";
    const char *keyword = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1 float\n0 0 0\nCELS 0 0\n";
    const char *nan = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0\n1 0 0\n0 -nan 0\n";
    const char *range = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                        "CELLS 1 4\n3 0 1 3\nCELL_TYPES 1\n5\n";
    const char *no_types = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                           "CELLS 1 4\n3 0 1 2\n";
    const char *bad_tri = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 1 1 0\n"
                          "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n5\n";
    const char *size = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                       "CELLS 1 5\n3 0 1 2 1\nCELL_TYPES 1\n5\n";
    const char *short_points = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1\n";
    const char *string_field = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nFIELD f 1\nnames 1 1 string\nab\n";
    const char *no_tris = "# vtk DataFile Version 2.0\ntitle\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                          "CELLS 1 3\n2 0 1\nCELL_TYPES 1\n3\n";
    bytes b;
    ENSURE(expect_text_error(not_vtk, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, 1, 0));
    ENSURE(expect_text_error(third, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, 3, offset_of(third, "TEXT")));
    ENSURE(expect_text_error(structured, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_UNSUPPORTED, 4, offset_of(structured, "STRUCTURED")));
    ENSURE(expect_text_error(keyword, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, 7, offset_of(keyword, "CELS")));
    ENSURE(expect_text_error(nan, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_NOT_FINITE, 8, offset_of(nan, "-nan")));
    ENSURE(expect_text_error(range, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 8, offset_of(range, "3\nCELL_") ));
    ENSURE(expect_text_error(no_types, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, 9, (long)strlen(no_types)));
    ENSURE(expect_text_error(bad_tri, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, 10, offset_of(bad_tri, "CELL_TYPES 1\n") + 13));
    ENSURE(expect_text_error(size, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_PARSE, -1, -1));
    ENSURE(expect_text_error(short_points, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_TRUNCATED, 6, offset_of(short_points, "0 0 0 1")));
    ENSURE(expect_text_error(string_field, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_UNSUPPORTED, 6, offset_of(string_field, "string")));
    ENSURE(expect_text_error(no_tris, CLOTH_FORMAT_VTK_ASCII, CLOTH_ERROR_EMPTY_MESH, -1, (long)strlen(no_tris)));
    /* binary: a point index out of range at its byte offset, and a truncated points array */
    make_vtk(&b, 1, 0);
    {
        size_t at = (size_t)find_bytes(b.data, b.n, "CELLS 6") + strlen("CELLS 6 25\n") + 4 + 8;
        ENSURE(b.data[at + 3] == 2);
        b.data[at + 3] = 6;
        ENSURE(expect_error(b.data, b.n, CLOTH_FORMAT_VTK_BINARY, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 0, (long)at));
        at = (size_t)find_bytes(b.data, b.n, "POINTS 6 double\n") + strlen("POINTS 6 double\n");
        ENSURE(expect_error(b.data, at + 100, CLOTH_FORMAT_VTK_BINARY, CLOTH_ERROR_TRUNCATED, 0, (long)at));
    }
}

TEST(errors_off)
{
    const char *not_off = "OFFICE\n3 1 0\n";
    const char *four = "4OFF\n3 1 0\n";
    const char *bad = "OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n";
    const char *range = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n";
    const char *missing_face = "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const char *two = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n";
    const char *short_vertex = "OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n";
    const char *inf = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 Infinity\n3 0 1 2\n";
    const char *huge_face = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2147483647 0 1 2\n"; /* found by fuzz_off */
    ENSURE(expect_text_error(not_off, CLOTH_FORMAT_OFF, CLOTH_ERROR_PARSE, 1, 0));
    ENSURE(expect_text_error(four, CLOTH_FORMAT_OFF, CLOTH_ERROR_UNSUPPORTED, 1, 0));
    ENSURE(expect_text_error(bad, CLOTH_FORMAT_OFF, CLOTH_ERROR_PARSE, 4, offset_of(bad, "zero")));
    ENSURE(expect_text_error(range, CLOTH_FORMAT_OFF, CLOTH_ERROR_INDEX_OUT_OF_RANGE, 6, (long)strlen(range) - 2));
    ENSURE(expect_text_error(missing_face, CLOTH_FORMAT_OFF, CLOTH_ERROR_TRUNCATED, 7, (long)strlen(missing_face)));
    ENSURE(expect_text_error(two, CLOTH_FORMAT_OFF, CLOTH_ERROR_PARSE, 6, offset_of(two, "2 0 1")));
    ENSURE(expect_text_error(short_vertex, CLOTH_FORMAT_OFF, CLOTH_ERROR_PARSE, 4, offset_of(short_vertex, "\n0 1 0")));
    ENSURE(expect_text_error(inf, CLOTH_FORMAT_OFF, CLOTH_ERROR_NOT_FINITE, 5, offset_of(inf, "Infinity")));
    ENSURE(expect_text_error(huge_face, CLOTH_FORMAT_OFF, CLOTH_ERROR_PARSE, 6, offset_of(huge_face, "2147483647")));
}

/* A header that claims far more than the data holds is an error found before any
   allocation of that size: the counting allocator refuses anything over 4 MB and records
   the largest request. */
TEST(errors_huge_counts)
{
    /* each text, and the text after which the error is placed (NULL: the end of the input) */
    static const char *const texts[][2] = {
        { "ply\nformat binary_little_endian 1.0\nelement vertex 2147483647\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0000000000000",
          "end_header\n" },
        { "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
          NULL },
        { "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty uchar x\nproperty uchar y\nproperty uchar z\n"
          "element face 4000000000\nproperty list uchar int vertex_indices\nend_header\n000111222\x03",
          "222\x03" },
        { "ply\nformat binary_little_endian 1.0\nelement junk 9223372036854775807\nproperty double a\nelement vertex 1\n"
          "property float x\nproperty float y\nproperty float z\nend_header\n",
          "end_header\n" },
        { "# vtk DataFile Version 2.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 2147483647 double\n00000000",
          "double\n" },
        { "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 1000000000 float\n0 0 0\n", "float\n" },
        { "# vtk DataFile Version 2.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
          "CELLS 2000000000 2000000000\n3 0 1 2\n",
          "2000000000\n" },
        { "# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
          "CELLS 2000000000 6000000000\nOFFSETS vtktypeint64\n0 3\nCONNECTIVITY vtktypeint64\n0 1 2\n",
          "6000000000\nOFFSETS vtktypeint64\n" },
        { "# vtk DataFile Version 2.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nFIELD f 1\na 2000000000 2000000000 double\n0000",
          "double\n" },
        { "OFF\n2147483647 1 0\n0 0 0\n", NULL },
        { "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", NULL },
    };
    size_t i;
    for (i = 0; i < sizeof texts / sizeof texts[0]; ++i) {
        const char *text = texts[i][0];
        long expected = texts[i][1] ? offset_of(text, texts[i][1]) + (long)strlen(texts[i][1]) : (long)strlen(text);
        counting c;
        cloth_allocator a = counting_allocator(&c, 4u << 20);
        cloth_mesh m;
        cloth_io_error e;
        cloth_result r = cloth_mesh_read_memory(&m, text, strlen(text), CLOTH_FORMAT_AUTO, &e, &a);
        if (r != CLOTH_ERROR_TRUNCATED || e.byte_offset != expected)
            printf("    text %d: %s at byte %lld, expected byte %ld (%s)\n", (int)i, cloth_result_string(r), (long long)e.byte_offset,
                   expected, e.message);
        ENSURE(r == CLOTH_ERROR_TRUNCATED && e.byte_offset == expected);
        ENSURE(mesh_is_empty(&m) && c.live == 0);
        if (c.largest > 4096) printf("    text %d: largest allocation %lu bytes\n", (int)i, (unsigned long)c.largest);
        ENSURE(c.largest <= 4096);
    }
}

/* Every allocation of a read or a write may fail: the call reports OUT_OF_MEMORY, leaves
   the output empty and leaks nothing. */
TEST(errors_out_of_memory)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    cloth_mesh m;
    int k;
    awkward_mesh(&m, x, uv, tri);
    for (k = 0; k < 7; ++k) {
        void *data = NULL;
        size_t size = 0;
        long fail;
        ENSURE(cloth_mesh_write_memory(&m, all_formats[k], &data, &size, NULL) == CLOTH_SUCCESS);
        for (fail = 0;; ++fail) {
            counting c;
            cloth_allocator a = counting_allocator(&c, 0);
            cloth_mesh back;
            cloth_io_error e;
            cloth_result r;
            c.fail_at = fail;
            r = cloth_mesh_read_memory(&back, data, size, all_formats[k], &e, &a);
            if (r == CLOTH_SUCCESS) {
                ENSURE(c.requests == fail); /* every earlier request was failed once */
                cloth_mesh_free(&back);
                ENSURE(c.live == 0);
                break;
            }
            ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && mesh_is_empty(&back) && c.live == 0);
        }
        for (fail = 0;; ++fail) {
            counting c;
            cloth_allocator a = counting_allocator(&c, 0);
            void *out = NULL;
            size_t out_size = 1;
            cloth_result r;
            c.fail_at = fail;
            r = cloth_mesh_write_memory(&m, all_formats[k], &out, &out_size, &a);
            if (r == CLOTH_SUCCESS) {
                ENSURE(out_size == size && memcmp(out, data, size) == 0);
                a.free(out, a.user);
                ENSURE(c.live == 0);
                break;
            }
            ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && out == NULL && out_size == 0 && c.live == 0);
        }
        free(data);
    }
}

/* ---- errors: writing ---------------------------------------------------------------------- */

TEST(errors_write)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    cloth_mesh m;
    void *data = (void *)&m;
    size_t size = 7;
    awkward_mesh(&m, x, uv, tri);
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_AUTO, &data, &size, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(data == NULL && size == 0);
    x[5] = (cloth_real)NAN;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_OBJ, &data, &size, NULL) == CLOTH_ERROR_NOT_FINITE && data == NULL);
    x[5] = 0;
    uv[5] = (cloth_real)HUGE_VAL;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_PLY_ASCII, &data, &size, NULL) == CLOTH_ERROR_NOT_FINITE && data == NULL);
    uv[5] = 0;
    tri[7] = 63;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_OFF, &data, &size, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE && data == NULL);
    tri[7] = -1;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_VTK_BINARY, &data, &size, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    tri[7] = 0;
    m.triangle_count = 0;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_PLY_BINARY_LE, &data, &size, NULL) == CLOTH_ERROR_EMPTY_MESH);
    m.triangle_count = 96;
    ENSURE(cloth_mesh_write_memory(&m, CLOTH_FORMAT_PLY_BINARY_LE, &data, &size, NULL) == CLOTH_SUCCESS);
    free(data);
}

/* ---- robustness ------------------------------------------------------------------------- */

/* Read `data` cut at every length and with seeded random byte changes: every result is a
   success with a valid mesh or an error with an empty mesh, and nothing leaks. */
static int survives_damage(const unsigned char *data, size_t size, cloth_file_format format, uint64_t seed)
{
    static unsigned char copy[16384];
    size_t cut;
    int round;
    CHECK(size <= sizeof copy);
    for (round = 0; round < 2 * (int)size + 200; ++round) {
        counting c;
        cloth_allocator a = counting_allocator(&c, 1u << 20);
        cloth_mesh m;
        cloth_io_error e;
        cloth_result r;
        size_t n = size;
        memcpy(copy, data, size);
        if (round <= (int)size) {
            cut = (size_t)round;
            n = cut;
        } else {
            int changes = 1 + (int)(test_random(&seed) % 4), k;
            for (k = 0; k < changes; ++k) {
                size_t at = (size_t)(test_random(&seed) % size);
                uint64_t what = test_random(&seed);
                copy[at] = (what & 1) ? (unsigned char)(what >> 8) : (unsigned char)"0123456789 \n-.e#/"[(what >> 8) % 18];
            }
        }
        r = cloth_mesh_read_memory(&m, copy, n, format, &e, &a);
        if (r == CLOTH_SUCCESS) {
            int32_t i;
            CHECK(m.vertex_count > 0 && m.triangle_count > 0);
            for (i = 0; i < 3 * m.triangle_count; ++i) CHECK(m.tri[i] >= 0 && m.tri[i] < m.vertex_count);
            for (i = 0; i < 3 * m.vertex_count; ++i) CHECK(m.x[i] - m.x[i] == 0);
            cloth_mesh_free(&m);
        } else {
            CHECK(r < 0 && mesh_is_empty(&m));
            CHECK(e.byte_offset >= 0 && (size_t)e.byte_offset <= n);
        }
        CHECK(c.live == 0);
    }
    return 1;
}

TEST(damaged_inputs)
{
    static cloth_real x[3 * 63], uv[2 * 63];
    static int32_t tri[3 * 96];
    cloth_mesh m;
    bytes b;
    int k;
    awkward_mesh(&m, x, uv, tri);
    m.vertex_count = 12; /* a small mesh keeps the files short */
    m.triangle_count = 6;
    for (k = 0; k < 6 * 3; ++k) tri[k] = tri[k] % 12;
    for (k = 0; k < 7; ++k) {
        void *data = NULL;
        size_t size = 0;
        ENSURE(cloth_mesh_write_memory(&m, all_formats[k], &data, &size, NULL) == CLOTH_SUCCESS);
        ENSURE(survives_damage((const unsigned char *)data, size, all_formats[k], 1000 + (uint64_t)k));
        free(data);
    }
    make_vtk(&b, 1, 1);
    ENSURE(survives_damage(b.data, b.n, CLOTH_FORMAT_VTK_BINARY, 7));
    make_vtk(&b, 0, 0);
    ENSURE(survives_damage(b.data, b.n, CLOTH_FORMAT_VTK_ASCII, 8));
    make_binary_ply(&b, 1, 3, 5, 2, 1);
    ENSURE(survives_damage(b.data, b.n, CLOTH_FORMAT_PLY_BINARY_BE, 9));
}

const test_case io_tests[] = {
    { "obj_face_forms", obj_face_forms },
    { "obj_relative_indices_and_polygons", obj_relative_indices_and_polygons },
    { "obj_uv_pairing", obj_uv_pairing },
    { "obj_numbers_correctly_rounded", obj_numbers_correctly_rounded },
    { "ply_ascii", ply_ascii },
    { "ply_binary_every_type", ply_binary_every_type },
    { "ply_uv_names", ply_uv_names },
    { "vtk_layouts", vtk_layouts },
    { "vtk_polydata", vtk_polydata },
    { "off_variants", off_variants },
    { "detect_format", detect_format },
    { "roundtrip_memory_exact", roundtrip_memory_exact },
    { "roundtrip_grid", roundtrip_grid },
    { "paths", paths },
    { "path_errors", path_errors },
    { "errors_obj", errors_obj },
    { "errors_empty_input", errors_empty_input },
    { "errors_ply", errors_ply },
    { "errors_vtk", errors_vtk },
    { "errors_off", errors_off },
    { "errors_huge_counts", errors_huge_counts },
    { "errors_out_of_memory", errors_out_of_memory },
    { "errors_write", errors_write },
    { "damaged_inputs", damaged_inputs },
    { NULL, NULL }
};
