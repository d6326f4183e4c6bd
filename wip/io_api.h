/* ===================================================================================== */
/* io: reading and writing OBJ, PLY (ascii, binary little and big endian), VTK legacy     */
/*     (ascii and binary unstructured grids of triangles) and OFF, from memory and paths  */
/*     needs: core, mesh                                                                  */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

typedef enum cloth_file_format {
    CLOTH_FORMAT_AUTO = 0,  /* reading: from the content (and the extension for paths) */
    CLOTH_FORMAT_OBJ,
    CLOTH_FORMAT_PLY_ASCII,
    CLOTH_FORMAT_PLY_BINARY_LE,
    CLOTH_FORMAT_PLY_BINARY_BE,
    CLOTH_FORMAT_VTK_ASCII,
    CLOTH_FORMAT_VTK_BINARY,
    CLOTH_FORMAT_OFF
} cloth_file_format;

/* Where and why a parse failed. line is 1-based for text (0 when not applicable);
   byte_offset is the offset in the input of the problem (always set). */
typedef struct cloth_io_error {
    int64_t line;
    int64_t byte_offset;
    char message[160];
} cloth_io_error;

/* Read a mesh from a buffer. Polygons are fan-triangulated. uv comes from OBJ vt (by the
   vertex's first v/vt pairing), PLY u v / s t / texture_u texture_v, and is NULL otherwise.
   error may be NULL. On failure *mesh is empty. */
CLOTH_API cloth_result cloth_mesh_read_memory(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                              cloth_io_error *error, const cloth_allocator *allocator);
/* Write a mesh into a buffer allocated with the allocator (*data, *size; free with the same
   allocator's free). */
CLOTH_API cloth_result cloth_mesh_write_memory(const cloth_mesh *mesh, cloth_file_format format, void **data, size_t *size,
                                               const cloth_allocator *allocator);
#ifndef CLOTH_NO_STDIO
CLOTH_API cloth_result cloth_mesh_read_file(cloth_mesh *mesh, const char *path, cloth_file_format format,
                                            cloth_io_error *error, const cloth_allocator *allocator);
CLOTH_API cloth_result cloth_mesh_write_file(const cloth_mesh *mesh, const char *path, cloth_file_format format);
#endif
/* The format a buffer looks like (CLOTH_FORMAT_AUTO when unknown). */
CLOTH_API cloth_file_format cloth_detect_format(const void *data, size_t size);

#ifdef __cplusplus
}
#endif
