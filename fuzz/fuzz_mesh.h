/* The body shared by the libFuzzer harnesses of cloth.h's mesh readers: fuzz_obj.c,
   fuzz_ply.c, fuzz_vtk.c and fuzz_off.c each define FUZZ_FORMAT (the format they read) and
   FUZZ_WRITE_FORMAT (the format they write back when the input does not name one) and then
   include this file after cloth.h's implementation.

   For every input: read it with the explicit format. A failure must leave the mesh empty and
   say where (an offset inside the input). A success must give a mesh that holds what the
   readers promise (vertices and triangles, every index in range, finite coordinates and uv);
   the mesh is then written to memory in the same format, read back, and must come back
   identical, bit for bit. Any broken promise is a __builtin_trap(), which the fuzzer reports
   as a crash. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define FUZZ_REQUIRE(cond) do { if (!(cond)) __builtin_trap(); } while (0)

static int fuzz_finite(cloth_real v) { return v == v && v - v == 0; }

/* The encoding to write back: the one the input names for PLY and VTK, else the default. */
static cloth_file_format fuzz_write_format(const uint8_t *data, size_t size)
{
    cloth_file_format detected = cloth_detect_format(data, size);
    if (FUZZ_FORMAT == CLOTH_FORMAT_PLY_ASCII &&
        (detected == CLOTH_FORMAT_PLY_ASCII || detected == CLOTH_FORMAT_PLY_BINARY_LE || detected == CLOTH_FORMAT_PLY_BINARY_BE))
        return detected;
    if (FUZZ_FORMAT == CLOTH_FORMAT_VTK_ASCII && (detected == CLOTH_FORMAT_VTK_ASCII || detected == CLOTH_FORMAT_VTK_BINARY))
        return detected;
    return FUZZ_WRITE_FORMAT;
}

static void fuzz_check_mesh(const cloth_mesh *m)
{
    int64_t i;
    FUZZ_REQUIRE(m->vertex_count > 0 && m->triangle_count > 0);
    FUZZ_REQUIRE(m->x != NULL && m->tri != NULL);
    for (i = 0; i < 3 * (int64_t)m->vertex_count; ++i) FUZZ_REQUIRE(fuzz_finite(m->x[i]));
    if (m->uv)
        for (i = 0; i < 2 * (int64_t)m->vertex_count; ++i) FUZZ_REQUIRE(fuzz_finite(m->uv[i]));
    for (i = 0; i < 3 * (int64_t)m->triangle_count; ++i) FUZZ_REQUIRE(m->tri[i] >= 0 && m->tri[i] < m->vertex_count);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    cloth_mesh m, back;
    cloth_io_error e;
    cloth_file_format out_format;
    void *out = NULL;
    size_t out_size = 0;
    int keeps_uv;
    cloth_result r = cloth_mesh_read_memory(&m, data, size, FUZZ_FORMAT, &e, NULL);
    if (r != CLOTH_SUCCESS) {
        FUZZ_REQUIRE(r < 0);
        FUZZ_REQUIRE(m.x == NULL && m.uv == NULL && m.tri == NULL && m.vertex_count == 0 && m.triangle_count == 0);
        FUZZ_REQUIRE(e.byte_offset >= 0 && (uint64_t)e.byte_offset <= (uint64_t)size && e.line >= 0);
        FUZZ_REQUIRE(memchr(e.message, 0, sizeof e.message) != NULL && e.message[0] != 0);
        return 0;
    }
    fuzz_check_mesh(&m);

    out_format = fuzz_write_format(data, size);
    r = cloth_mesh_write_memory(&m, out_format, &out, &out_size, NULL);
    FUZZ_REQUIRE(r == CLOTH_SUCCESS && out != NULL);
    FUZZ_REQUIRE(cloth_detect_format(out, out_size) == out_format);
    r = cloth_mesh_read_memory(&back, out, out_size, out_format, &e, NULL);
    FUZZ_REQUIRE(r == CLOTH_SUCCESS);
    fuzz_check_mesh(&back);
    FUZZ_REQUIRE(back.vertex_count == m.vertex_count && back.triangle_count == m.triangle_count);
    FUZZ_REQUIRE(memcmp(back.x, m.x, sizeof(cloth_real) * 3 * (size_t)m.vertex_count) == 0);
    FUZZ_REQUIRE(memcmp(back.tri, m.tri, sizeof(int32_t) * 3 * (size_t)m.triangle_count) == 0);
    keeps_uv = out_format == CLOTH_FORMAT_OBJ || out_format == CLOTH_FORMAT_PLY_ASCII ||
               out_format == CLOTH_FORMAT_PLY_BINARY_LE || out_format == CLOTH_FORMAT_PLY_BINARY_BE;
    if (m.uv && keeps_uv)
        FUZZ_REQUIRE(back.uv != NULL && memcmp(back.uv, m.uv, sizeof(cloth_real) * 2 * (size_t)m.vertex_count) == 0);
    else
        FUZZ_REQUIRE(back.uv == NULL);
    cloth_mesh_free(&back);
    free(out);
    cloth_mesh_free(&m);
    return 0;
}
