/* ===================================================================================== */
/* io: reading and writing OBJ, PLY (ascii, binary little and big endian), VTK legacy     */
/*     (ascii and binary unstructured grids and polydata) and OFF, from memory and paths  */
/*     needs: core, mesh                                                                  */
/* ===================================================================================== */
/*
   Every reader turns a file into a cloth_mesh: positions, triangles and, where the format
   carries them, material coordinates uv. Polygons are fan-triangulated in file order:
   (a, b, c, d, ...) becomes (a, b, c), (a, c, d), ... Indices are checked against the vertex
   count, coordinates must be finite, and a file without vertices or without triangles is
   CLOTH_ERROR_EMPTY_MESH. What each reader accepts:

   OBJ   v x y z (further values on the line, such as w or a vertex colour, are ignored),
         vt u [v [w]], f with corners v, v/vt, v//vn or v/vt/vn, 1-based or negative
         (relative: -1 is the last vertex defined above the face). Comments (#) anywhere.
         Skipped: vn, vp, o, g, s, usemtl, mtllib, l (lines), p (points) and the free-form
         statements of the OBJ specification (cstype, deg, curv, surf, ...); any other
         statement is a parse error. uv: a vertex takes the vt of its first v/vt corner in
         file order; a vertex paired later with another vt keeps the first (connectivity
         always follows the positions, vertices are never split by uv); vertices never paired
         get uv (0, 0). uv is NULL when no face corner names a vt.
   PLY   format ascii, binary_little_endian or binary_big_endian 1.0; comment and obj_info
         lines. Element vertex with scalar properties x, y, z of any numeric type (char,
         uchar, short, ushort, int, uint, float, double, their int8 ... float64 aliases, and
         int64/uint64); uv from u v, else s t, else texture_u texture_v. Element face with a
         list property vertex_indices (or vertex_index) of integer count and index types.
         Other elements and properties, lists included, are skipped in any order. The format
         named to the reader only selects PLY; the header decides the encoding.
   VTK   legacy "# vtk DataFile Version x.y", ASCII or BINARY (big endian). DATASET
         UNSTRUCTURED_GRID: cells of type 5 (triangle), 9 (quad) and 7 (polygon) become
         triangles, other cell types (vertices, lines, tetrahedra, ...) are skipped. DATASET
         POLYDATA: POLYGONS become triangles; VERTICES, LINES and TRIANGLE_STRIPS are skipped.
         POINTS of any numeric type. Both cell layouts: "CELLS n size" with a count before
         each cell (version <= 4.2) and "CELLS n+1 m" followed by OFFSETS and CONNECTIVITY
         arrays (version 5.1, meshio's default). FIELD data and METADATA blocks before or
         between the geometry sections are skipped; reading stops at the first POINT_DATA or
         CELL_DATA section once the geometry is complete, so attribute data is never read.
         Other datasets (STRUCTURED_POINTS, ...) are CLOTH_ERROR_UNSUPPORTED. No uv.
   OFF   a first line "OFF" (also COFF, NOFF, STOFF, ...; the counts may follow on the same
         line; 4OFF and nOFF, other dimensions, are CLOTH_ERROR_UNSUPPORTED), then "vertices
         faces [edges]", one vertex per line (values after x y z, such as colours, are
         ignored) and one face per line as a count and 0-based indices (values after the
         indices, such as a colour, are ignored). Comments (#) anywhere. No uv.

   Numbers are read as correctly rounded doubles (with float cloth_real, then rounded to
   float), without strtod and so whatever the C locale; "nan" and "inf" are recognised only
   to report CLOTH_ERROR_NOT_FINITE. Line endings may be \n or \r\n. A reader never
   allocates more than a small multiple of the input size: counts from a header are checked
   against the bytes that are really there before anything is allocated.

   Writers write what they read back exactly: text formats print every value with enough
   digits to round-trip (%.17g for double, %.9g for float; printf's decimal separator is
   turned back into '.' if the C locale has a one-byte decimal comma), binary formats store
   the bits.
   OBJ writes v, vt (one per vertex, when the mesh has uv) and f; PLY writes double x y z
   (and u v) and faces as "list uchar int vertex_indices"; VTK writes version 4.2
   UNSTRUCTURED_GRID with double points and triangle cells; OFF writes OFF. VTK and OFF
   drop uv. Writers refuse meshes they could not read back: no vertices or no triangles,
   indices out of range, non-finite coordinates or uv.
*/
#ifdef __cplusplus
extern "C" {
#endif

/* A file format. For reading, the PLY and the VTK entries each select their family (the
   file's header decides the encoding); for writing they say exactly what is written. */
typedef enum cloth_file_format {
    CLOTH_FORMAT_AUTO = 0,      /* reading: detect from the content (then, for a path, its extension);
                                   writing a path: from the extension (.obj, .ply binary little
                                   endian, .vtk binary, .off) */
    CLOTH_FORMAT_OBJ,           /* Wavefront OBJ */
    CLOTH_FORMAT_PLY_ASCII,     /* PLY 1.0, ascii */
    CLOTH_FORMAT_PLY_BINARY_LE, /* PLY 1.0, binary little endian */
    CLOTH_FORMAT_PLY_BINARY_BE, /* PLY 1.0, binary big endian */
    CLOTH_FORMAT_VTK_ASCII,     /* VTK legacy, ASCII */
    CLOTH_FORMAT_VTK_BINARY,    /* VTK legacy, BINARY (big endian) */
    CLOTH_FORMAT_OFF            /* Object File Format */
} cloth_file_format;

/* Where and why reading failed. line is the 1-based line of the problem in text formats and
   in the text headers of PLY and VTK, 0 inside binary data and for errors that have no
   place (a file that cannot be opened); byte_offset is the offset of the problem in the
   input (0 when it has no place). message says what is wrong, for a person. */
typedef struct cloth_io_error {
    int64_t line;
    int64_t byte_offset;
    char message[160];
} cloth_io_error;

/* Read a mesh from size bytes at data (which need not be NUL-terminated). With
   CLOTH_FORMAT_AUTO the format is detected with cloth_detect_format. On success *mesh owns
   its arrays (allocated with allocator, NULL meaning the default; free with
   cloth_mesh_free). On failure *mesh is empty (all pointers NULL), nothing is leaked, and
   *error (when error is not NULL) says where and why: CLOTH_ERROR_PARSE for malformed
   content, CLOTH_ERROR_TRUNCATED when the data ends before what a header announced,
   CLOTH_ERROR_UNSUPPORTED for well-formed files that use what cloth.h does not read,
   CLOTH_ERROR_NOT_FINITE for a NaN or infinite coordinate, CLOTH_ERROR_INDEX_OUT_OF_RANGE
   for a face naming a missing vertex, CLOTH_ERROR_EMPTY_MESH for a file without vertices or
   triangles (or empty input), CLOTH_ERROR_OUT_OF_MEMORY and CLOTH_ERROR_SIZE_OVERFLOW. */
CLOTH_API cloth_result cloth_mesh_read_memory(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                              cloth_io_error *error, const cloth_allocator *allocator);

/* Write a mesh into a new buffer: on success *data (allocated with allocator, NULL meaning
   the default; release it with that allocator's free) holds *size bytes. format must not be
   CLOTH_FORMAT_AUTO. On failure *data is NULL and *size 0. */
CLOTH_API cloth_result cloth_mesh_write_memory(const cloth_mesh *mesh, cloth_file_format format, void **data, size_t *size,
                                               const cloth_allocator *allocator);

#ifndef CLOTH_NO_STDIO
/* Read a mesh from a file: the whole file is read into memory (with allocator) and parsed as
   by cloth_mesh_read_memory. CLOTH_ERROR_FILE_OPEN when the path cannot be opened,
   CLOTH_ERROR_FILE_READ when reading fails part way. With CLOTH_FORMAT_AUTO, content that
   cloth_detect_format does not recognise is read by the path's extension (.obj, .ply, .vtk,
   .off, in any case). */
CLOTH_API cloth_result cloth_mesh_read_file(cloth_mesh *mesh, const char *path, cloth_file_format format,
                                            cloth_io_error *error, const cloth_allocator *allocator);

/* Write a mesh to a file, streamed through a small buffer on the stack (nothing is
   allocated). CLOTH_FORMAT_AUTO picks the format from the extension (.obj, .ply: binary
   little endian, .vtk: binary, .off) and is CLOTH_ERROR_INVALID_ARGUMENT for any other.
   CLOTH_ERROR_FILE_OPEN or CLOTH_ERROR_FILE_WRITE when the file cannot be written (a
   partly written file is left behind). */
CLOTH_API cloth_result cloth_mesh_write_file(const cloth_mesh *mesh, const char *path, cloth_file_format format);
#endif

/* The format a buffer's content looks like, CLOTH_FORMAT_AUTO when it looks like none:
   "ply" then the encoding from its format line; "# vtk DataFile" then ASCII or BINARY from
   its third line; OFF from a first word ending in OFF; OBJ when the first line that is not
   blank or a comment starts with an OBJ statement (v, vt, f, o, g, ...). */
CLOTH_API cloth_file_format cloth_detect_format(const void *data, size_t size);

#ifdef __cplusplus
}
#endif
