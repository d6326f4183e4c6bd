/* cloth.h - v0.1.0 - physically based cloth simulation in one C99 header - MIT or public domain (see end of file)

   Do this:
       #define CLOTH_IMPLEMENTATION
   before you include this file in *one* C or C++ file to create the implementation.
   Every other file includes cloth.h without the define and sees declarations only.

       #include ...
       #define CLOTH_IMPLEMENTATION
       #include "cloth.h"

   cloth.h needs libc and libm, and pthreads only when CLOTH_THREADS is defined.

   CONFIGURATION (define before including, in every file that includes cloth.h
   unless the entry says otherwise)

       CLOTH_REAL         the scalar type, double by default; float is allowed. It changes the
                          ABI: define it the same way everywhere and check cloth_real_size().
       CLOTH_STATIC       make every function static to the including file (then define
                          CLOTH_IMPLEMENTATION in that same file).
       CLOTH_API          override the linkage of public functions (default: extern).
       CLOTH_MALLOC(sz)   the default allocator's allocation; define together with
       CLOTH_FREE(p)      the default allocator's release (both or neither: checked by #error).
       CLOTH_ASSERT(c)    how misuse of the API is caught (default: assert from <assert.h>).
       CLOTH_NO_STDIO     leave out everything that opens files by path (reading and writing
                          from memory buffers stays).
       CLOTH_THREADS      compile in the thread pool of the implicit step (world def `threads`,
                          cloth_pcg_workspace_set_threads); needs pthreads (-pthread). Only the
                          file with CLOTH_IMPLEMENTATION needs it. Results do not depend on it.
                          An engine with its own job system needs neither: it passes a
                          cloth_task_system in the world def (enqueue_task, finish_task).

   Compile cloth.h with IEEE-754 arithmetic: never -ffast-math, -Ofast or /fp:fast (the
   continuous collision tests prove they never miss only under IEEE rounding; fused
   multiply-add contraction is allowed). -ffp-contract=off makes results bit-identical
   across compilers.

   MANUAL

   1. Quick start: a cloth hanging from two corners
        cloth_world_def def = cloth_default_world_def();       (gravity, integrator, solver)
        cloth_piece_def piece_def = cloth_default_piece_def(); (material, model, bending, wind)
        cloth_world *world;
        cloth_mesh mesh;
        int32_t piece, frame;
        cloth_mesh_grid(&mesh, 33, 33, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
        cloth_world_create(&world, &def);
        cloth_world_add_piece(world, &mesh, &piece_def, &piece);   (the mesh is copied)
        cloth_world_pin(world, piece, 0, NULL);
        cloth_world_pin(world, piece, 32, NULL);
        for (frame = 0; frame < 120; ++frame) {
            cloth_result r = cloth_world_step(world, 1.0 / 60, NULL);
            if (r != CLOTH_SUCCESS) puts(cloth_result_string(r));  (the world is as before)
            ... cloth_world_positions(world, piece) ...
        }
        cloth_world_destroy(world);
        cloth_mesh_free(&mesh);
      Every call above returns a cloth_result worth checking; examples/demo.c does.

   2. Speed and accuracy
        The knobs that trade one for the other: the integrator (linearized backward Euler is
        one solve per step; backward Euler iterates Newton to newton_tolerance; BDF2 adds
        order; symplectic Euler needs tiny steps), the step and substeps, the conjugate
        gradient's tolerance and preconditioner, the resolution. README.md measures each.

   3. Units and conventions
        SI units throughout: metres, kilograms, seconds, newtons. y is up; gravity is
        -9.81 m/s^2 along y by default. Triangles are counter-clockwise seen from the
        front side, so the front normal is (x1 - x0) x (x2 - x0). Material coordinates uv
        are the flat sewing pattern in metres. Arrays are flat: x[3*n], uv[2*n], tri[3*m].
        Indices and counts are int32_t; sizes are checked for overflow before any allocation.

   4. Thread safety
        There is no mutable global state. Different objects (meshes, topologies, worlds)
        may be used from different threads at the same time; one object is used by one
        thread at a time. With CLOTH_THREADS, a world whose def asks for threads > 1 runs its
        implicit step's assembly, conjugate gradient products and multigrid update, and the
        collide phase's CCD queries, on a pool of threads made with the world (no thread is
        started and nothing allocated per step);
        every partition is fixed and every sum runs in a fixed order, so the results are
        bit-identical for any thread count (the multigrid V-cycle's finest sweeps can run in
        parts, multigrid option sweep_parts, fixed by the options and the system's size, never
        by the threads; its coarser levels stay serial).

   5. Error handling
        Misuse of the API (a NULL pointer where an object is required) trips CLOTH_ASSERT.
        Bad data (a malformed file, a broken mesh, NaN coordinates, impossible parameters)
        never prints, exits or aborts: the call returns a negative cloth_result, named in
        cloth_result_string(). Parsers also say where: the line (text formats) or the byte
        offset (binary data) and the reason, in a cloth_io_error. On failure, output objects
        are left empty (all pointers NULL) and nothing is leaked. A step that fails (NaN, a
        blow-up, a solver failure) returns its error and leaves the world exactly as it was.

   6. Memory
        Every function that allocates takes a `const cloth_allocator *`; NULL means the
        default (CLOTH_MALLOC/CLOTH_FREE, malloc/free unless overridden). The allocator is
        copied into the object it made, so the object is freed the same way. Every _free
        function accepts an object that is already empty. A world allocates when it is built
        or changed (pieces, seams) and before its first step; after that a step allocates
        nothing.

   7. What cloth.h does NOT do
        It does not render, open windows, read images or load materials (.mtl); it does
        not remesh adaptively; it is not a rigid-body engine (obstacles are kinematic).

   MODULES (in file order; the implementation follows the same order)
        core       results, allocator, logger, seeded random numbers, version
        math       small vector helpers used inside the library
        mesh       cloth_mesh, topology, validation, generators, subdivision
        io         OBJ, PLY, VTK legacy and OFF reading and writing
        material   cloth_material in SI units, fabric presets, Kawabata and Peirce conversions
        forces     per-element energies with gradients and Hessians: springs, strain limiters,
                   FEM membrane, quadratic and dihedral bending, gravity, wind and gusts, damping
        linsolve   3x3 block sparse matrix with a fixed pattern, filtered PCG with Jacobi,
                   block-Jacobi or smoothed-aggregation multigrid preconditioning
        bvh        bounding volume hierarchy over triangles
        ccd        proximity and continuous collision detection
        contact    obstacles, impact zones and their exact QP projection, friction
        integrate  the world: pieces, pins, handles, seams, obstacles; symplectic Euler,
                   backward Euler (linearized or Newton), BDF2; the step and its statistics
*/
#ifndef CLOTH_H
#define CLOTH_H

/* ===================================================================================== */
/* core: version, configuration, results, allocator, logger, random numbers               */
/*       needs: libc                                                                      */
/* ===================================================================================== */

#define CLOTH_VERSION_MAJOR 0
#define CLOTH_VERSION_MINOR 1
#define CLOTH_VERSION_PATCH 0
#define CLOTH_VERSION_STRING "0.1.0"
/* One number that orders versions: major * 10000 + minor * 100 + patch. */
#define CLOTH_VERSION (CLOTH_VERSION_MAJOR * 10000 + CLOTH_VERSION_MINOR * 100 + CLOTH_VERSION_PATCH)

#include <stddef.h>
#include <stdint.h>

#ifndef CLOTH_REAL
#define CLOTH_REAL double
#endif
typedef CLOTH_REAL cloth_real;

#ifndef CLOTH_API
#ifdef CLOTH_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define CLOTH_API static __attribute__((unused)) /* a caller uses only some of them */
#else
#define CLOTH_API static
#endif
#else
#define CLOTH_API extern
#endif
#endif

#if (defined(CLOTH_MALLOC) && !defined(CLOTH_FREE)) || (!defined(CLOTH_MALLOC) && defined(CLOTH_FREE))
#error "cloth.h: define both CLOTH_MALLOC and CLOTH_FREE, or neither"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Every fallible call returns a cloth_result: 0 is success, failures are negative. */
typedef enum cloth_result {
    CLOTH_SUCCESS = 0,
    CLOTH_ERROR_INVALID_ARGUMENT = -1,      /* a parameter is out of its documented range */
    CLOTH_ERROR_OUT_OF_MEMORY = -2,         /* the allocator returned NULL */
    CLOTH_ERROR_SIZE_OVERFLOW = -3,         /* a count or byte size does not fit */
    CLOTH_ERROR_FILE_OPEN = -4,             /* a path could not be opened */
    CLOTH_ERROR_FILE_READ = -5,             /* reading a file failed part way */
    CLOTH_ERROR_FILE_WRITE = -6,            /* writing a file or buffer failed */
    CLOTH_ERROR_PARSE = -7,                 /* a file's content is malformed (see cloth_io_error) */
    CLOTH_ERROR_UNSUPPORTED = -8,           /* well-formed but uses a feature cloth.h does not read */
    CLOTH_ERROR_TRUNCATED = -9,             /* a file ends before the data its header announces */
    CLOTH_ERROR_NOT_FINITE = -10,           /* a NaN or an infinity where a finite number is needed */
    CLOTH_ERROR_INDEX_OUT_OF_RANGE = -11,   /* a triangle names a vertex that does not exist */
    CLOTH_ERROR_DEGENERATE_TRIANGLE = -12,  /* zero or near-zero area (rest or world), or a repeated vertex */
    CLOTH_ERROR_NON_MANIFOLD_EDGE = -13,    /* an edge shared by more than two triangles */
    CLOTH_ERROR_INCONSISTENT_ORIENTATION = -14, /* two neighbours traverse their shared edge the same way */
    CLOTH_ERROR_DUPLICATE_FACE = -15,       /* two triangles over the same three vertices */
    CLOTH_ERROR_EMPTY_MESH = -16,           /* no vertices or no triangles where some are needed */
    CLOTH_ERROR_CG_NOT_CONVERGED = -17,     /* the conjugate gradient solve hit its iteration cap */
    CLOTH_ERROR_NOT_POSITIVE_DEFINITE = -18, /* a matrix that must be positive definite is not */
    CLOTH_ERROR_UNSTABLE = -19,              /* a step blew up, or is larger than the integrator's stable step */
    CLOTH_ERROR_COLLISION_UNRESOLVED = -20,  /* collisions could not be resolved: the step is undone */
    CLOTH_ERROR_RESULT_COUNT_ = 21          /* not a result: the number of results, for tables */
} cloth_result;

/* A short English sentence for a result ("success", "index out of range", ...). Never NULL. */
CLOTH_API const char *cloth_result_string(cloth_result result);

/* The version this implementation was compiled as (CLOTH_VERSION) and sizeof(cloth_real) in it:
   compare them with the header a caller compiled against to catch an ABI mismatch. */
CLOTH_API int cloth_version(void);
CLOTH_API size_t cloth_real_size(void);

/* A run-time allocator: alloc(size, user) returns NULL on failure; free(ptr, user) accepts NULL.
   A cloth_allocator with alloc == NULL means the default (CLOTH_MALLOC/CLOTH_FREE). */
typedef struct cloth_allocator {
    void *(*alloc)(size_t size, void *user);
    void (*free)(void *ptr, void *user);
    void *user;
} cloth_allocator;

/* The default allocator, as a value. */
CLOTH_API cloth_allocator cloth_default_allocator(void);

/* A host's task system, for an engine that has its own job system (box2d style). cloth.h splits
   parallel work into part_count independent parts and calls enqueue_task(task, context,
   part_count, user): the host runs task(context, p) once for every p in 0 .. part_count-1, on
   any of its threads, in any order, and returns a handle (or NULL); cloth.h then calls
   finish_task(handle, user), which must return only when every part has run. Parts never touch
   each other's outputs and are summed in part order afterwards, so results do not depend on
   the threads or the order the host uses. worker_count (1..64) is how many parts the work is
   split into, about the host's worker threads. enqueue_task NULL means no host system. */
typedef void (*cloth_task_fn)(void *context, int32_t part);
typedef struct cloth_task_system {
    int32_t worker_count;
    void *(*enqueue_task)(cloth_task_fn task, void *context, int32_t part_count, void *user);
    void (*finish_task)(void *handle, void *user);
    void *user;
} cloth_task_system;

/* An optional logger. cloth.h prints nothing by itself; where an object holds a logger with a
   non-NULL log function, it reports what it would otherwise keep silent about (for example a
   step that needed many CG iterations). */
typedef enum cloth_log_level { CLOTH_LOG_DEBUG = 0, CLOTH_LOG_INFO = 1, CLOTH_LOG_WARNING = 2, CLOTH_LOG_ERROR = 3 } cloth_log_level;
typedef struct cloth_logger {
    void (*log)(cloth_log_level level, const char *message, void *user);
    void *user;
} cloth_logger;

/* A seeded random number generator of the library's own (xoshiro256**, seeded through
   splitmix64), so that the same seed gives the same numbers on every platform. */
typedef struct cloth_rng { uint64_t s[4]; } cloth_rng;
CLOTH_API cloth_rng cloth_rng_make(uint64_t seed);
CLOTH_API uint64_t cloth_rng_next(cloth_rng *rng);
/* Uniform in [0, 1). */
CLOTH_API cloth_real cloth_rng_uniform(cloth_rng *rng);
/* Standard normal (mean 0, deviation 1), Box-Muller. */
CLOTH_API cloth_real cloth_rng_normal(cloth_rng *rng);

#ifdef __cplusplus
}
#endif

/* ===================================================================================== */
/* math: vector helpers live in the implementation (cloth__v3_*); nothing public yet     */
/* ===================================================================================== */

/* ===================================================================================== */
/* mesh: triangle meshes over flat arrays, topology, validation, generators, subdivision   */
/*       needs: core                                                                      */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

/* A triangle mesh. x[3*vertex_count] are positions (m), uv[2*vertex_count] optional material
   (rest) coordinates in metres (NULL when absent), tri[3*triangle_count] vertex indices,
   counter-clockwise seen from the front. A mesh made by cloth.h owns its arrays and frees them
   with the allocator it keeps; a caller may also fill the struct over arrays of its own and
   never call cloth_mesh_free on it. */
typedef struct cloth_mesh {
    int32_t vertex_count;
    int32_t triangle_count;
    cloth_real *x;
    cloth_real *uv;
    int32_t *tri;
    cloth_allocator allocator;
} cloth_mesh;

/* Allocate a mesh with room for the counts (contents uninitialised; uv only if with_uv). */
CLOTH_API cloth_result cloth_mesh_alloc(cloth_mesh *mesh, int32_t vertex_count, int32_t triangle_count,
                                        int with_uv, const cloth_allocator *allocator);
/* Free a mesh made by cloth.h and leave it empty. Accepts an empty mesh. */
CLOTH_API void cloth_mesh_free(cloth_mesh *mesh);
/* A deep copy. */
CLOTH_API cloth_result cloth_mesh_copy(cloth_mesh *dst, const cloth_mesh *src, const cloth_allocator *allocator);

/* ---- topology ---------------------------------------------------------------------- */

/* Connectivity of a mesh whose indices are in range. Edges are unique and undirected,
   edge_vertex[2e] < edge_vertex[2e+1]. For each edge its one or two faces (edge_face[2e+k],
   -1 when absent) and the vertex of each face opposite the edge (edge_opposite[2e+k]), which
   is the bending stencil (edge_vertex[2e], edge_vertex[2e+1], edge_opposite[2e], edge_opposite[2e+1]).
   edge_face[2e] is the face that traverses the edge from edge_vertex[2e] to edge_vertex[2e+1]
   when there is one. face_edge[3f+k] is the edge from tri[3f+k] to tri[3f+(k+1)%3].
   Boundary edges (one face) are listed in boundary_edge[]; boundary loops follow the
   boundary in the direction of their faces: loop l is loop_vertex[loop_start[l] .. loop_start[l+1]).
   Faces around vertex v: vertex_face[vertex_face_start[v] .. vertex_face_start[v+1]).
   Edges with more than two faces keep their first two and are counted in nonmanifold_edge_count. */
typedef struct cloth_topology {
    int32_t vertex_count, triangle_count, edge_count;
    int32_t *edge_vertex;   /* 2 per edge */
    int32_t *edge_face;     /* 2 per edge, -1 when absent */
    int32_t *edge_opposite; /* 2 per edge, -1 when absent */
    int32_t *face_edge;     /* 3 per face */
    int32_t boundary_edge_count;
    int32_t *boundary_edge;
    int32_t loop_count;
    int32_t *loop_start;    /* loop_count + 1 */
    int32_t *loop_vertex;
    int32_t *vertex_face_start; /* vertex_count + 1 */
    int32_t *vertex_face;
    int32_t nonmanifold_edge_count;
    cloth_allocator allocator;
} cloth_topology;

/* Build the topology. Fails with CLOTH_ERROR_INDEX_OUT_OF_RANGE on a bad index and
   CLOTH_ERROR_DEGENERATE_TRIANGLE on a triangle that repeats a vertex. */
CLOTH_API cloth_result cloth_topology_build(cloth_topology *topology, const cloth_mesh *mesh, const cloth_allocator *allocator);
CLOTH_API void cloth_topology_free(cloth_topology *topology);
/* The edge between vertices a and b, or -1. O(valence). */
CLOTH_API int32_t cloth_topology_find_edge(const cloth_topology *topology, int32_t a, int32_t b);

/* ---- validation -------------------------------------------------------------------- */

/* What cloth_mesh_validate found. result is the first problem in the order the checks run
   (non-finite numbers, indices, degenerate triangles, duplicate faces, non-manifold edges,
   orientation); triangle, other_triangle and vertex say where (-1 when not applicable).
   Unreferenced vertices are not an error; they are counted here. */
typedef struct cloth_mesh_report {
    cloth_result result;
    int32_t triangle;
    int32_t other_triangle;
    int32_t vertex;
    int32_t unreferenced_vertex_count;
    int32_t first_unreferenced_vertex;
    cloth_real min_quality_world; /* smallest 2 area / longest edge^2 over triangles (world) */
    cloth_real min_quality_rest;  /* the same in uv, or 0 without uv */
} cloth_mesh_report;

/* Check a mesh. A triangle is degenerate when it repeats a vertex or when
   2 * area <= quality_tolerance * (longest edge)^2, in world coordinates and, if the mesh has
   uv, in rest coordinates; quality_tolerance <= 0 selects CLOTH_MESH_QUALITY_TOLERANCE.
   report may be NULL. Returns report->result. */
#define CLOTH_MESH_QUALITY_TOLERANCE 1e-6
CLOTH_API cloth_result cloth_mesh_validate(const cloth_mesh *mesh, cloth_real quality_tolerance,
                                           cloth_mesh_report *report, const cloth_allocator *scratch);

/* ---- generators -------------------------------------------------------------------- */

typedef enum cloth_grid_diagonal {
    CLOTH_GRID_DIAGONAL_REGULAR = 0,    /* every quad split along the same diagonal */
    CLOTH_GRID_DIAGONAL_ALTERNATING = 1 /* diagonals alternate in a checkerboard ("union jack") */
} cloth_grid_diagonal;

/* A flat rectangular cloth of nx * ny vertices (nx, ny >= 2), width along x, depth along z,
   centred at the origin in the plane y = 0, front side up (+y), with uv = (x + width/2, depth/2 - z)
   so that triangles are counter-clockwise in the uv plane too (positive rest area).
   Vertex (i, j) is index j * nx + i, i along x, j along z. */
CLOTH_API cloth_result cloth_mesh_grid(cloth_mesh *mesh, int32_t nx, int32_t ny, cloth_real width, cloth_real depth,
                                       cloth_grid_diagonal diagonal, const cloth_allocator *allocator);
/* A flat disc of the given radius in the plane y = 0, front up, centred at the origin, with
   `rings` rings of vertices (>= 1) and `segments` vertices on the innermost ring (>= 3),
   uv = (x + radius, radius - z), counter-clockwise in the uv plane like the grid's. */
CLOTH_API cloth_result cloth_mesh_disc(cloth_mesh *mesh, cloth_real radius, int32_t rings, int32_t segments,
                                       const cloth_allocator *allocator);
/* A sphere centred at the origin: an icosahedron subdivided `subdivisions` times (0..10),
   vertices projected onto the sphere; outward-facing. No uv. */
CLOTH_API cloth_result cloth_mesh_icosphere(cloth_mesh *mesh, cloth_real radius, int32_t subdivisions,
                                            const cloth_allocator *allocator);
/* A capsule along the x axis centred at the origin: a cylinder of the given radius and
   length (between the hemisphere centres, >= 0) closed by two hemispheres; `segments` around
   (>= 3) and `rings` per hemisphere (>= 1). Outward-facing. No uv. */
CLOTH_API cloth_result cloth_mesh_capsule(cloth_mesh *mesh, cloth_real radius, cloth_real length, int32_t segments,
                                          int32_t rings, const cloth_allocator *allocator);
/* An axis-aligned box centred at the origin with the given half extents; each face split into
   n x n quads (1 <= n <= 128; subdivide for finer), two triangles each; outward-facing, closed. No uv. */
CLOTH_API cloth_result cloth_mesh_box(cloth_mesh *mesh, cloth_real hx, cloth_real hy, cloth_real hz, int32_t n,
                                      const cloth_allocator *allocator);

/* ---- subdivision ------------------------------------------------------------------- */

/* How a fine mesh's vertices are made from a coarse mesh's: fine vertex f is
   sum over k in [start[f], start[f+1]) of weight[k] * coarse[coarse_vertex[k]]. */
typedef struct cloth_upsample_map {
    int32_t fine_count;
    int32_t coarse_count;
    int32_t *start;        /* fine_count + 1 */
    int32_t *coarse_vertex;
    cloth_real *weight;
    cloth_allocator allocator;
} cloth_upsample_map;

/* One-to-four subdivision: every triangle becomes four by inserting edge midpoints (positions
   and uv). The fine mesh keeps the coarse vertices first, in order, then one vertex per coarse
   edge in the order of cloth_topology's edges. map may be NULL. */
CLOTH_API cloth_result cloth_mesh_subdivide(cloth_mesh *fine, cloth_upsample_map *map, const cloth_mesh *coarse,
                                            const cloth_allocator *allocator);
/* Apply a map to per-vertex data with `dim` components: out[dim*fine_count] from in[dim*coarse_count]. */
CLOTH_API void cloth_upsample_apply(const cloth_upsample_map *map, int dim, const cloth_real *in, cloth_real *out);
CLOTH_API void cloth_upsample_map_free(cloth_upsample_map *map);

#ifdef __cplusplus
}
#endif

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

/* ===================================================================================== */
/* material: cloth_material in SI units (areal density, orthotropic membrane stiffness,  */
/*           warp/weft bending stiffness, damping), presets of measured fabrics, unit    */
/*           conversions (Kawabata KES-F, Peirce's cantilever) and the stable time step  */
/*           of explicit (symplectic Euler) integration for a material on a mesh         */
/*           needs: core                                                                 */
/*                                                                                       */
/* THE MODEL A MATERIAL FEEDS. u is the warp, v the weft (the axes of the pattern uv).   */
/* The membrane is orthotropic St.Venant-Kirchhoff on the Green strain E, with energy    */
/* per unit rest area                                                                    */
/*     W = 1/2 (C11 E11^2 + 2 C12 E11 E22 + C22 E22^2) + 2 C33 E12^2          (J/m^2)    */
/* C11 = stretch_warp, C22 = stretch_weft, C12 = stretch_coupling, C33 = shear, all N/m  */
/* (modulus times thickness). With the engineering shear gamma = 2 E12 the shear stress  */
/* resultant is N12 = C33 gamma. For small strain, in Voigt form (E11, E22, gamma):      */
/*     D = [C11 C12 0; C12 C22 0; 0 0 C33],  N = D (E11, E22, gamma).                    */
/* Bending is a dihedral energy with the physical bending stiffness B (N m: moment per   */
/* unit width per unit curvature). bend_warp is B for curvature along the warp, the      */
/* bending of the warp yarns, i.e. the fold line (hinge edge) runs along the weft; this  */
/* is the Kawabata "warp" B. bend_weft likewise. Mass is areal density (kg/m^2).         */
/*                                                                                       */
/* WHERE THE NUMBERS COME FROM. Every preset says its source                             */
/* (cloth_material_preset_source) and the mappings are public functions, so a user can   */
/* apply them to their own data:                                                         */
/*  * cloth_material_from_fem_fit: the three fitted parameters (lambda0, lambda1,        */
/*    lambda2) of seed 002 (Peng et al., "Generation of Realistic Virtual Garments on    */
/*    Recovery Human Model", Table 2: silk, fleece, denim, linen). Its section 4.1 model */
/*    is a Green-Lagrange St.Venant-Kirchhoff membrane with Hooke's law written through  */
/*    Young's modulus Y and Poisson's ratio tau in the plane-strain Lame form            */
/*        sigma = Y/((1+tau)(1-2tau)) [1-tau tau 0; tau 1-tau 0; 0 0 1-2tau] eps,        */
/*    i.e. [lambda+2mu lambda 0; lambda lambda+2mu 0; 0 0 2mu] with Lame's lambda and    */
/*    mu, plus a relative-velocity damping force -phi (v_i - v_j); bending is not        */
/*    written. The paper does not say which lambda is what nor give units. We read       */
/*        lambda0 = bending stiffness B (N m), lambda1 = Lame lambda, lambda2 = Lame mu  */
/*    (membrane, N/m), so C11 = C22 = lambda1 + 2 lambda2, C12 = lambda1, C33 = lambda2. */
/*    Reasons: the fit used stretching, shearing and bending experiments (three tests,   */
/*    three parameters); lambda0 ~ 1e-5 has the magnitude of measured fabric bending     */
/*    stiffness in N m (1e-6 .. 1e-4) and nothing else in the model; of the readings of  */
/*    (lambda1, lambda2) we considered (Lame lambda and mu either way round, or a        */
/*    stretch and a shear stiffness) only this one agrees with the paper's remark "silk  */
/*    is more stretchy than fleece" (2D Young's modulus 4mu(lambda+mu)/(lambda+2mu):     */
/*    silk 133 N/m < fleece 156 N/m), and its 2D Poisson ratios lambda/(lambda+2mu) =    */
/*    0.12 .. 0.33 are plausible. Ambiguities left open: (a) lambda0 could instead be    */
/*    the damping phi of its eq. (10) (the only other parameter of section 4.1); (b) the */
/*    units: read as SI, the membrane values (~100 N/m) are 10-100 times softer than KES */
/*    tensile data of wovens, so the presets reproduce the paper's fitted model rather   */
/*    than tensile measurements; (c) the paper's eq. (6) uses the engineering shear      */
/*    strain in the Lame matrix, which would double the shear energy; we keep the        */
/*    continuum form (C33 = mu); (d) the bending values put silk above denim, against    */
/*    the paper's own remark that denim is stiff in bending. The paper gives no areal    */
/*    densities: the presets use representative trade weights.                           */
/*  * cloth_material_from_arcsim: the measured fabrics of Wang, O'Brien and Ramamoorthi  */
/*    2011 as ARCSim ships them (materials/<name>.json: density; "stretching" 6 rows of  */
/*    (k0, k1, k2, k3), row 0 at zero strain; "bending" 3 rows, for hinge edges at 0, 45 */
/*    and 90 degrees to u, of 5 curvature samples). ARCSim doubles the stretching        */
/*    samples and clamps negatives to 0, and its membrane force is that of the energy    */
/*        k0 E11^2 + 2 k1 E11 E22 + k2 E22^2 + 2 k3 E12^2   (with the file's k),         */
/*    so C11 = 2 k0, C12 = 2 k1, C22 = 2 k2, C33 = k3: the preset reproduces ARCSim's    */
/*    membrane at small strain exactly. The knits stiffen strongly with strain (their    */
/*    rows at a stretch of 1/6 are up to tens of times stiffer; the wovens denim, pants  */
/*    and tablecloth change little), which a linear model cannot follow. ARCSim's        */
/*    bending energy is ke l^2/(2(a0+a1)) theta^2/4, the same dihedral energy as         */
/*    cloth.h's B l^2/(2(a0+a1)) theta^2 with B = ke/4; we take B = ke/4 at the first    */
/*    (lowest) curvature sample, so the presets bend as they do in ARCSim. Open: the     */
/*    database does not say whether u is the warp (we take it so), and some readers      */
/*    treat ke itself as B (our notes list the ke values as "bending coefficients        */
/*    (SI)"); that would make every measured preset four times stiffer in bending.       */
/*  * cloth_material_from_kes: Kawabata KES-F measurements (seed 003 maps warp and weft  */
/*    KES values onto its model); the conversions are below.                             */
/*                                                                                       */
/* Functions that write a cloth_material leave it unchanged when they fail.              */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

/* A cloth material in SI units. Valid values (cloth_material_validate): all finite,
   areal_density > 0, stretch_warp > 0, stretch_weft > 0, shear > 0,
   stretch_warp * stretch_weft - stretch_coupling^2 > 0 (a positive definite membrane),
   bend_warp, bend_weft, damping_stiffness, damping_relative >= 0. */
typedef struct cloth_material {
    cloth_real areal_density;     /* kg/m^2: mass per unit rest area */
    cloth_real stretch_warp;      /* C11, N/m: membrane stiffness along the warp (u) */
    cloth_real stretch_weft;      /* C22, N/m: membrane stiffness along the weft (v) */
    cloth_real stretch_coupling;  /* C12, N/m: Poisson coupling of warp and weft strain */
    cloth_real shear;             /* C33, N/m: in-plane shear stiffness, N12 = C33 * engineering shear */
    cloth_real bend_warp;         /* N m: bending stiffness for curvature along the warp */
    cloth_real bend_weft;         /* N m: bending stiffness for curvature along the weft */
    cloth_real damping_stiffness; /* s: Rayleigh stiffness-proportional damping, damping matrix
                                     = damping_stiffness * (membrane + bending stiffness matrix) */
    cloth_real damping_relative;  /* N s/m (kg/s): seed 002's relative-velocity damping, applied per
                                     triangle: f_a = -damping_relative * sum_b (v_a - v_b) over the
                                     triangle's other two vertices (cloth_relative_damping_force) */
} cloth_material;

/* The default material: a mid-weight plain-woven cotton (shirting/poplin class), made with
   cloth_material_from_kes from representative KES-F values of that class (they describe a
   typical fabric, not a measurement of one): W = 15 mg/cm^2 (150 g/m^2), EMT 4 % warp and
   6 % weft at Fm = 500 gf/cm with LT = 0.65, G = 1.0 gf/cm/degree, B = 0.10 (warp) and
   0.08 (weft) gf cm^2/cm, and an assumed Poisson ratio 0.3 (KES does not measure it). That
   gives 0.15 kg/m^2; tensile stiffness 7968 N/m (warp) and 5312 N/m (weft), so C11 = 8477,
   C22 = 5651, C12 = 1695 N/m; C33 = 56.2 N/m; B = 9.81e-6 and 7.85e-6 N m (a Peirce bending
   length of 1.9 cm along the warp). No damping: the measurements give none, and the choice
   belongs to the integrator. The same material is the preset "cotton". */
CLOTH_API cloth_material cloth_default_material(void);

/* Check a material against the ranges of cloth_material. Returns CLOTH_ERROR_NOT_FINITE when
   any field is NaN or infinite (checked first), CLOTH_ERROR_INVALID_ARGUMENT for a non-physical
   value (non-positive density or stretch or shear stiffness, negative bending or damping, a
   coupling with C11 C22 - C12^2 <= 0), else CLOTH_SUCCESS. */
CLOTH_API cloth_result cloth_material_validate(const cloth_material *material);

/* ---- membrane conversions ---------------------------------------------------------- */

/* The engineering constants of an orthotropic sheet in plane stress, per unit width.
   tensile_warp = Y1 t: warp stress resultant over warp strain with the weft free to contract
   (a uniaxial test); poisson_warp_weft = nu12 = -(weft strain)/(warp strain) under a warp
   load; the reciprocal ratio is nu21 = nu12 Y2 / Y1. With Delta = 1 - nu12 nu21:
       C11 = Y1 / Delta,  C22 = Y2 / Delta,  C12 = nu12 Y2 / Delta = nu21 Y1 / Delta,  C33 = G12 t
   and back: Y1 = C11 - C12^2/C22, Y2 = C22 - C12^2/C11, nu12 = C12/C22. */
typedef struct cloth_membrane_engineering {
    cloth_real tensile_warp;      /* Y1 t, N/m */
    cloth_real tensile_weft;      /* Y2 t, N/m */
    cloth_real poisson_warp_weft; /* nu12, dimensionless */
    cloth_real shear;             /* G12 t, N/m */
} cloth_membrane_engineering;

/* Set the membrane (stretch_warp, stretch_weft, stretch_coupling, shear) from engineering
   constants; the other fields are kept. CLOTH_ERROR_NOT_FINITE for a non-finite constant;
   CLOTH_ERROR_INVALID_ARGUMENT unless Y1 > 0, Y2 > 0, G12 t > 0 and nu12 nu21 < 1. */
CLOTH_API cloth_result cloth_material_set_engineering(cloth_material *material,
                                                      const cloth_membrane_engineering *constants);
/* The engineering constants of a material's membrane. CLOTH_ERROR_NOT_FINITE or
   CLOTH_ERROR_INVALID_ARGUMENT (constants untouched) when the membrane fields are not finite
   or not positive definite. */
CLOTH_API cloth_result cloth_material_engineering(const cloth_material *material,
                                                  cloth_membrane_engineering *constants);
/* An isotropic membrane of tensile stiffness Y t (N/m) and Poisson ratio nu, |nu| < 1:
   C11 = C22 = Y t / (1 - nu^2), C12 = nu C11, C33 = Y t / (2 (1 + nu)). Other fields kept.
   CLOTH_ERROR_INVALID_ARGUMENT for Y t <= 0 or |nu| >= 1. */
CLOTH_API cloth_result cloth_material_set_isotropic(cloth_material *material, cloth_real tensile, cloth_real poisson);
/* An isotropic membrane from the 2D Lame parameters lambda and mu (N/m), i.e. the energy
   W = lambda/2 (tr E)^2 + mu tr(E^2): C11 = C22 = lambda + 2 mu, C12 = lambda, C33 = mu
   (2D Young's modulus 4 mu (lambda + mu)/(lambda + 2 mu), Poisson ratio lambda/(lambda + 2 mu)).
   Other fields kept. CLOTH_ERROR_INVALID_ARGUMENT unless mu > 0 and lambda + mu > 0. */
CLOTH_API cloth_result cloth_material_set_lame(cloth_material *material, cloth_real lame_lambda, cloth_real lame_mu);

/* ---- fitted and measured materials ------------------------------------------------- */

/* A material from seed 002's fitted parameters (see the banner for the reading and what is
   ambiguous): bend_warp = bend_weft = lambda0 (N m); membrane from the Lame parameters
   lambda = lambda1, mu = lambda2 (N/m); the given areal density (kg/m^2); no damping.
   Errors as cloth_material_validate. */
CLOTH_API cloth_result cloth_material_from_fem_fit(cloth_real lambda0, cloth_real lambda1, cloth_real lambda2,
                                                   cloth_real areal_density, cloth_material *material);
/* A material from an ARCSim material file (the Wang-O'Brien-Ramamoorthi 2011 format, see the
   banner): density (kg/m^2), the zero-strain stretching row stretching[4] = (k0, k1, k2, k3)
   as written in the file (negative entries are clamped to 0, as ARCSim does), and the
   bending coefficients ke (first curvature sample) of the hinge edges along u (file row 0)
   and along v (row 2). Sets C11 = 2 k0, C12 = 2 k1, C22 = 2 k2, C33 = k3,
   bend_weft = ke(u edges)/4, bend_warp = ke(v edges)/4; no damping. Errors as
   cloth_material_validate. */
CLOTH_API cloth_result cloth_material_from_arcsim(cloth_real density, const cloth_real *stretching,
                                                  cloth_real bending_u_edges, cloth_real bending_v_edges,
                                                  cloth_material *material);

/* Kawabata KES-F measurements of a fabric, in KES units (suffix 1 = warp, 2 = weft). */
typedef struct cloth_kes_measurement {
    cloth_real mass;           /* W, mg/cm^2 */
    cloth_real extension_warp; /* EMT1, % strain at the maximum load */
    cloth_real extension_weft; /* EMT2, % */
    cloth_real linearity_warp; /* LT1, dimensionless: WT / (Fm EMT / 2) */
    cloth_real linearity_weft; /* LT2 */
    cloth_real max_load;       /* Fm, gf/cm: the tensile test's maximum load (CLOTH_KES_STANDARD_MAX_LOAD) */
    cloth_real shear_rigidity; /* G, gf/(cm degree) */
    cloth_real bending_warp;   /* B1, gf cm^2/cm */
    cloth_real bending_weft;   /* B2, gf cm^2/cm */
} cloth_kes_measurement;

/* A material from KES measurements and a Poisson ratio nu12 (KES does not measure one):
   areal density from W; tensile stiffnesses Y1, Y2 from cloth_kes_tensile_stiffness (EMT, LT,
   Fm), taken as the uniaxial (weft free) stiffness although the wide KES strip restrains its
   contraction partly (the difference is the factor 1 - nu12 nu21); shear from G; bending
   from B1, B2; membrane by cloth_material_set_engineering; no damping. Errors as
   cloth_material_validate and the conversions. */
CLOTH_API cloth_result cloth_material_from_kes(const cloth_kes_measurement *kes, cloth_real poisson_warp_weft,
                                               cloth_material *material);

/* ---- presets ----------------------------------------------------------------------- */

/* The presets, in this order:
     cotton      the default material (cloth_default_material)
     silk, fleece, denim, linen
                 seed 002 Table 2 through cloth_material_from_fem_fit, with representative
                 areal densities (the paper gives none): silk 0.07 kg/m^2 (16 momme, 1 momme
                 = 4.34 g/m^2), fleece 0.25 (mid-weight polar fleece, 200-300 g/m^2), denim
                 0.324 (the measured 11 oz denim below), linen 0.18 (dress linen, 150-200 g/m^2)
     denim_11oz, ponte_roma, rib_knit, blanket, sweater, pants, swimsuit, interlock,
     tablecloth, jet_set
                 the measured fabrics of Wang, O'Brien and Ramamoorthi 2011 through
                 cloth_material_from_arcsim from ARCSim's files 11oz-black-denim,
                 camel-ponte-roma, ivory-rib-knit, pink-ribbon-brown, navy-sparkle-sweat,
                 royal-target, white-swim-solid, gray-interlock, white-dots-on-blk,
                 tango-red-jet-set: areal density as measured; stiffness at zero strain.
   The number of presets. */
CLOTH_API int32_t cloth_material_preset_count(void);
/* The name of preset i (lower case, as listed above), or NULL when i is out of range. */
CLOTH_API const char *cloth_material_preset_name(int32_t i);
/* One sentence naming where preset i's numbers come from, or NULL when out of range. */
CLOTH_API const char *cloth_material_preset_source(int32_t i);
/* Preset i. CLOTH_ERROR_INVALID_ARGUMENT when i is out of range. */
CLOTH_API cloth_result cloth_material_preset_at(int32_t i, cloth_material *material);
/* The preset of a name, compared without regard to case ("Denim_11oz" finds denim_11oz).
   CLOTH_ERROR_INVALID_ARGUMENT for an unknown name or a NULL name. */
CLOTH_API cloth_result cloth_material_preset(const char *name, cloth_material *material);

/* ---- Kawabata KES-F units ------------------------------------------------------------ */

/* One gram-force in newtons (standard gravity times one gram), and standard gravity (m/s^2). */
#define CLOTH_GRAM_FORCE 9.80665e-3
#define CLOTH_STANDARD_GRAVITY 9.80665
/* The maximum load of the standard KES-FB1 tensile test of woven fabric, gf/cm. */
#define CLOTH_KES_STANDARD_MAX_LOAD 500.0

/* Bending rigidity B: gf cm^2/cm <-> N m. B is moment per unit width (gf cm/cm) per unit
   curvature (1/cm), so gf cm^2/cm = (9.80665e-3 N)(1e-2 m)^2/(1e-2 m) = 9.80665e-5 N m
   (our notes round it to 9.81e-5). */
CLOTH_API cloth_real cloth_kes_bending_to_si(cloth_real gf_cm2_per_cm);
CLOTH_API cloth_real cloth_kes_bending_from_si(cloth_real newton_metre);
/* Shear rigidity G: gf/(cm degree) <-> N/m per radian. KES G is the slope of shear force per
   unit width against shear angle (in degrees, the small-angle range of the KES-FB1 shear
   test); C33 is the slope of the shear stress resultant against the engineering shear
   strain gamma = tan(angle) ~ angle in radians, so C33 = G (9.80665e-3 N / 1e-2 m)(180/pi)
   = 56.19 N/m per gf/(cm degree). The KES value includes the stiffening of the test's
   pre-tension (10 gf/cm in the standard test); it is not corrected for. */
CLOTH_API cloth_real cloth_kes_shear_to_si(cloth_real gf_per_cm_degree);
CLOTH_API cloth_real cloth_kes_shear_from_si(cloth_real newton_per_metre);
/* Mass per unit area W: mg/cm^2 <-> kg/m^2 (1 mg/cm^2 = 1e-6 kg / 1e-4 m^2 = 0.01 kg/m^2). */
CLOTH_API cloth_real cloth_kes_mass_to_si(cloth_real mg_per_cm2);
CLOTH_API cloth_real cloth_kes_mass_from_si(cloth_real kg_per_m2);
/* Tensile load per unit width (Fm) gf/cm -> N/m (1 gf/cm = 0.980665 N/m), and tensile energy
   WT gf cm/cm^2 -> J/m^2 (work per unit specimen area, the same factor). */
CLOTH_API cloth_real cloth_kes_load_to_si(cloth_real gf_per_cm);
CLOTH_API cloth_real cloth_kes_tensile_energy_to_si(cloth_real gf_cm_per_cm2);
/* The linear tensile stiffness (N/m) that stores the measured tensile energy at the measured
   extension: with em = EMT/100 and WT = LT Fm em / 2 (the definition of LT),
       k = 2 WT / em^2 = LT Fm / em.
   A linear fabric has LT = 1 and k the secant Fm/em; real fabrics stiffen (LT < 1, a soft
   start), and k lies between their initial slope and the secant. It assumes the load is
   carried linearly in strain up to EMT, i.e. it replaces the curve by the linear one of
   equal energy; the hysteresis (RT) is ignored, and for the small strains of KES tests the
   Green and engineering strains agree to within em/2. CLOTH_ERROR_INVALID_ARGUMENT unless
   EMT > 0, LT > 0, Fm > 0; CLOTH_ERROR_NOT_FINITE for a non-finite input. */
CLOTH_API cloth_result cloth_kes_tensile_stiffness(cloth_real extension_percent, cloth_real linearity,
                                                   cloth_real max_load_gf_per_cm, cloth_real *stiffness);
/* The same stiffness from the tensile energy WT (gf cm/cm^2) and EMT (%): k = 2 WT / em^2, N/m. */
CLOTH_API cloth_result cloth_kes_tensile_stiffness_from_energy(cloth_real tensile_energy, cloth_real extension_percent,
                                                               cloth_real *stiffness);

/* ---- Peirce's cantilever (ASTM D1388) -------------------------------------------------- */

/* In the cantilever test a strip slides over a horizontal edge until its tip touches a plane
   inclined at 41.5 degrees below it; the overhang l gives the bending length c = l/2 and the
   flexural rigidity G = w c^3, with w = areal density * g the weight per unit area (N/m^2),
   so G is in N m and is the bending stiffness B. (The exact heavy elastica puts the chord
   of a cantilever with w l^3 / B = 8 at 41.49 degrees, which is why c = l/2 holds at that
   angle; Peirce's approximate formula c = l (cos(theta/2) / (8 tan theta))^(1/3) gives
   0.509 l there.) In ASTM units, G (mg cm) = W (mg/cm^2) c^3 (cm^3), and G in N m is that
   times 1e-8 kg m/(mg cm) times g. All three functions take g (m/s^2, > 0; 9.81 in
   cloth.h's scenes, CLOTH_STANDARD_GRAVITY in a laboratory) and return
   CLOTH_ERROR_INVALID_ARGUMENT for a non-positive input (bending may be 0 in the inverse
   functions) and CLOTH_ERROR_NOT_FINITE for a non-finite one. */

/* The bending length c = (B / (areal_density g))^(1/3) in metres. */
CLOTH_API cloth_result cloth_bending_length(cloth_real bending, cloth_real areal_density, cloth_real gravity,
                                            cloth_real *length);
/* The flexural rigidity (N m) from a measured overhang l (m): G = areal_density g (l/2)^3. */
CLOTH_API cloth_result cloth_cantilever_rigidity(cloth_real overhang, cloth_real areal_density, cloth_real gravity,
                                                 cloth_real *bending);
/* The overhang expected for a bending stiffness B (N m): l = 2 (B / (areal_density g))^(1/3), m. */
CLOTH_API cloth_result cloth_cantilever_overhang(cloth_real bending, cloth_real areal_density, cloth_real gravity,
                                                 cloth_real *overhang);

/* ---- stable time step of explicit integration ------------------------------------------ */

/* Symplectic Euler (v += h M^-1 f(x, v); x += h v, with the damping force evaluated at the
   old velocity) on the linear system M x'' + C x' + K x = 0, with M the lumped mass and C, K
   symmetric positive semidefinite, keeps the quantity
       v^T (M - h^2 K/4 - h C/2) v + 1/4 |x_n + x_(n-1)|_K^2
   from growing, so it is stable when M - h^2 K/4 - h C/2 is positive definite, which holds
   when h^2 omega^2 / 4 + h kappa / 2 < 1 with omega^2 >= the largest eigenvalue of M^-1 K and
   kappa >= that of M^-1 C:
       h < 4 / (kappa + sqrt(kappa^2 + 4 omega^2))        (= 2/omega without damping).
   For Rayleigh damping C = c K, per mode, the condition is also necessary. This function
   returns that bound (the supremum of stable steps: take a fraction of it) for
   omega_max >= 0 (rad/s) and damping_rate_max >= 0 (1/s), not both 0.
   CLOTH_ERROR_INVALID_ARGUMENT for a negative input or both 0; CLOTH_ERROR_NOT_FINITE.
   Plain explicit Euler is unstable for any step on an undamped oscillator; this bound does
   not apply to it. For a spring network (any stretch above half the rest length),
   omega^2 <= 2 max_i (sum of the stiffnesses of the springs at vertex i) / min_i m_i. */
CLOTH_API cloth_result cloth_explicit_time_step_limit(cloth_real omega_max, cloth_real damping_rate_max,
                                                      cloth_real *time_step);

/* The stability length of a rest triangle (uv, metres): L = sqrt(2 / lambda_max(S)), with
   S = sum_i grad N_i grad N_i^T the sum of the outer products of its shape function gradients
   (equivalently lambda_max(S) = lambda_max(sum of e e^T over its edges e) / (4 area^2)).
   L equals the side of an equilateral triangle and sqrt(2/3) times the legs of a right
   isosceles one; L^2 <= 4 area / sqrt(3) always. Returns 0 for a degenerate or non-finite
   triangle. */
CLOTH_API cloth_real cloth_triangle_stability_length(const cloth_real *uv0, const cloth_real *uv1, const cloth_real *uv2);

/* The stable symplectic Euler step (cloth_explicit_time_step_limit) for a material on a mesh
   whose smallest triangle stability length is `length` (m; for a mesh of equilateral
   triangles its shortest edge, for a grid of right isosceles triangles sqrt(2/3) times its
   shortest leg; in general the minimum of cloth_triangle_stability_length). With the
   element mass rho A / 3 at each vertex (the lumped mass matrix), the largest frequency of
   an assembled system is at most the largest of its elements' (Irons and Treharne), and for
   one triangle of the linearised membrane at rest
       omega^2 <= (3/rho) lambda_max(B^T D B) <= 12 lambda_max(D) / (rho L^2)
   (B the 3x6 strain-displacement matrix, D as in the banner; |B u|^2 <= 2 lambda_max(S) |u|^2).
   This membrane bound is rigorous at rest; stretch raises the tangent stiffness (by about
   1 + 3 strain for St.Venant-Kirchhoff), so integrate with a fraction of the step. To it
   are added an estimate for dihedral bending, omega^2 ~ 64 max(B) / (rho L^4) (for cloth.h's
   dihedral energy, linearised at the flat state with lumped masses, the largest values on
   periodic regular meshes are 45 (equilateral), 28 (right isosceles grid) and 48 (grid with
   alternating diagonals); irregular meshes may exceed 64), and the damping rates
   kappa = damping_stiffness * omega^2 + 12 sqrt(3) damping_relative / (rho L^2) (the
   relative damping of a triangle has rate 9 c / (rho A) and A >= sqrt(3)/4 L^2).
   Errors: those of cloth_material_validate, CLOTH_ERROR_INVALID_ARGUMENT for length <= 0,
   CLOTH_ERROR_NOT_FINITE for a non-finite length. */
CLOTH_API cloth_result cloth_material_stable_time_step(const cloth_material *material, cloth_real length,
                                                       cloth_real *time_step);
/* The same bound for one rest triangle (uv in metres; u the warp), with the membrane term
   computed exactly for the element, (3/rho) lambda_max(B^T D B), so it accounts for the
   triangle's shape and its orientation to the grain; the bending estimate and the relative
   damping use the triangle's own stability length and area. The step of a mesh is the
   minimum over its triangles; it is never smaller than cloth_material_stable_time_step with
   that triangle's stability length. Errors as cloth_material_stable_time_step, and
   CLOTH_ERROR_NOT_FINITE / CLOTH_ERROR_DEGENERATE_TRIANGLE for a bad triangle. */
CLOTH_API cloth_result cloth_material_triangle_time_step(const cloth_material *material, const cloth_real *uv0,
                                                         const cloth_real *uv1, const cloth_real *uv2,
                                                         cloth_real *time_step);

#ifdef __cplusplus
}
#endif

/* ===================================================================================== */
/* forces: per-element energy kernels of the dynamics phase -- springs (Provot grids and  */
/*         edge/bending springs of any mesh, attachments, seams, strain limiters), the    */
/*         FEM membrane (Green-Lagrange strain, orthotropic St.Venant-Kirchhoff,          */
/*         warp/weft), quadratic (per-vertex curvature) and dihedral bending calibrated   */
/*         to the physical bending stiffness, gravity, aerodynamic                        */
/*         face forces with a seeded gust process, relative-velocity and air damping      */
/*         needs: core, math, mesh (the spring lists read a cloth_topology)               */
/*                                                                                       */
/* Every conservative term is a function of one element's vertex positions (and the     */
/* element's rest data) that returns the element's energy E in joules and, when the      */
/* output pointers are not NULL, writes                                                  */
/*     gradient[3k]       dE/dx, vertex after vertex (x, y, z of vertex 0, then 1, ...)  */
/*                        in N; the force on vertex a is -gradient[3a .. 3a+2];          */
/*     hessian[3k * 3k]   d2E/dx2 in N/m, row-major and symmetric: entry (3a+r, 3b+c),    */
/*                        r, c in 0..2, is hessian[(3a + r) * 3k + 3b + c], so the 3x3   */
/*                        coupling block of vertices a and b starts at                   */
/*                        hessian + 3a * 3k + 3b with a row stride of 3k.                */
/* The outputs are overwritten, not accumulated. The element's vertices come as separate  */
/* pointers to their three coordinates, so an assembler passes &x[3 * index] directly.    */
/* df/dx = -hessian. cloth_hessian_form chooses between the positive semidefinite form    */
/* that the implicit solver needs and the exact second derivative (for Newton's method    */
/* with a line search, for the differentiation module and for tests).                     */
/*                                                                                       */
/* Velocity-dependent terms (aerodynamics, damping) write forces f[3k] in N and the       */
/* velocity Jacobian df/dv[3k * 3k] in N s/m, laid out like the Hessian; their df/dv is   */
/* symmetric negative semidefinite, so -h df/dv adds a positive semidefinite part to the  */
/* implicit system matrix.                                                                */
/*                                                                                       */
/* Rest data (spring lengths, membrane Dm^-1 and area, bending weights) are computed once */
/* from the sewing pattern uv (metres) or from a rest shape and kept by the caller.       */
/* Stiffnesses are physical: springs in N/m, membrane in N/m (modulus times thickness),   */
/* bending in N m (moment per unit width per unit curvature).                            */
/* The kernels allocate nothing, never fail and do not check their inputs for NaN: the    */
/* integrator's health check catches non-finite states. Functions that make rest data or  */
/* take parameters return a cloth_result.                                                 */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

/* Which second derivative a kernel writes. */
typedef enum cloth_hessian_form {
    CLOTH_HESSIAN_PROJECTED = 0, /* a positive semidefinite approximation (each kernel says which) */
    CLOTH_HESSIAN_EXACT = 1      /* the true second derivative of the energy; may be indefinite */
} cloth_hessian_form;

/* ---- springs ----------------------------------------------------------------------- */

/* A spring between xi and xj of stiffness k (N/m) and rest length L >= 0 (m):
       E = k/2 (l - L)^2,   l = |xi - xj|,   d = (xi - xj) / l
       dE/dxi = -dE/dxj = k (l - L) d
       Hessian blocks: H_ii = H_jj = K, H_ij = H_ji = -K with
       exact       K = k [ d d^T + (1 - L/l) (I - d d^T) ]
       projected   K = k [ d d^T + max(0, 1 - L/l) (I - d d^T) ]
   The transverse term (1 - L/l) is negative when the spring is compressed (l < L); the
   projected form clamps it at zero, which makes K positive semidefinite (the usual remedy
   since Choi & Ko 2002); for a stretched spring the two forms are the same. (The membrane's
   projected form takes the magnitude of its compressive stress instead, see
   cloth_membrane_energy; a spring's magnitude k (L/l - 1) would grow without bound as it
   collapses, so springs keep the clamp.)
   L = 0 is a seam (or zero-length tie) between two vertices: E = k/2 |xi - xj|^2, K = k I,
   exact and well defined even when the vertices coincide. For L > 0 and coincident vertices
   the direction is undefined: gradient and Hessian are then zero. gradient[6], hessian[36]. */
CLOTH_API cloth_real cloth_spring_energy(const cloth_real *xi, const cloth_real *xj, cloth_real stiffness,
                                         cloth_real rest_length, cloth_real *gradient, cloth_real *hessian,
                                         cloth_hessian_form form);

/* A zero-rest-length spring from x to a fixed point `target` (a soft pin or a handle):
       E = k/2 |x - target|^2,  gradient k (x - target) [3],  Hessian k I [9] (exact and PSD). */
CLOTH_API cloth_real cloth_attachment_energy(const cloth_real *x, const cloth_real *target, cloth_real stiffness,
                                             cloth_real *gradient, cloth_real *hessian);

/* A strain limiter on the edge from xi to xj, of rest length L (m) and limit s (>= 0): a spring
   of stiffness k (N/m) that engages only when the edge is longer than L_s = (1 + s) L,
       E = k/2 (l - L_s)^2 for l > L_s, else 0        (l = |xi - xj|)
   with the gradient and Hessian of cloth_spring_energy of rest length L_s beyond L_s and zero
   up to it. The energy and the gradient are continuous; the Hessian jumps from 0 to k d d^T
   at l = L_s. Beyond L_s the spring is stretched, so its Hessian is positive semidefinite
   (exact = projected). The world's pieces use it for strain limiting (cloth_piece_def's
   strain_limit). gradient[6], hessian[36], either may be NULL. */
CLOTH_API cloth_real cloth_strain_limit_energy(const cloth_real *xi, const cloth_real *xj, cloth_real stiffness,
                                               cloth_real rest_length, cloth_real limit, cloth_real *gradient,
                                               cloth_real *hessian);

/* Spring kinds; the values are bits so that a set of kinds is their sum (or bitwise or). */
typedef enum cloth_spring_kind {
    CLOTH_SPRING_STRUCTURAL = 1, /* grid: (i,j)-(i+1,j), (i,j)-(i,j+1); mesh: every edge */
    CLOTH_SPRING_SHEAR = 2,      /* grid: (i,j)-(i+1,j+1), (i+1,j)-(i,j+1); mesh: not used */
    CLOTH_SPRING_BEND = 4,       /* grid: (i,j)-(i+2,j), (i,j)-(i,j+2); mesh: across each interior edge */
    CLOTH_SPRING_ALL = 7
} cloth_spring_kind;

/* The Provot (1995) springs of an nx x ny grid of vertices numbered like cloth_mesh_grid's,
   vertex (i, j) = j * nx + i: structural, shear and bend springs, the kinds selected by the
   bits of `kinds`. Count-then-fill: *count receives the number of springs; when pair is not
   NULL it receives them, pair[2s], pair[2s+1] with pair[2s] < pair[2s+1], listed kind by kind
   in the order structural, shear, bend (within a kind by j, then i), and kind[s] (when kind is
   not NULL) their cloth_spring_kind. capacity is the room in pair (in springs) and in kind.
   Fails with CLOTH_ERROR_INVALID_ARGUMENT for nx or ny < 2, kinds outside CLOTH_SPRING_ALL,
   or capacity < *count when pair is not NULL (nothing is written then), and with
   CLOTH_ERROR_SIZE_OVERFLOW when the count does not fit an int32_t. */
CLOTH_API cloth_result cloth_grid_springs(int32_t nx, int32_t ny, int kinds, int32_t *pair, int32_t *kind,
                                          int32_t capacity, int32_t *count);

/* Springs of any triangle mesh from its topology: CLOTH_SPRING_STRUCTURAL lists one spring per
   edge (topology edge order), CLOTH_SPRING_BEND one per interior edge between its two opposite
   vertices (edge_opposite[2e], edge_opposite[2e+1], skipped when they coincide); the shear bit
   is accepted and ignored (a triangle mesh's diagonals are edges). Same count-then-fill
   contract and errors as cloth_grid_springs; edge springs come first. */
CLOTH_API cloth_result cloth_topology_springs(const cloth_topology *topology, int kinds, int32_t *pair,
                                              int32_t *kind, int32_t capacity, int32_t *count);

/* Rest lengths |p[pair[2s]] - p[pair[2s+1]]| of count springs, from points of `dimension` 2
   (the pattern uv, the usual choice) or 3 (a rest shape). Fails with
   CLOTH_ERROR_INVALID_ARGUMENT for another dimension or a negative count and
   CLOTH_ERROR_INDEX_OUT_OF_RANGE for an index outside 0..point_count-1 (nothing written). */
CLOTH_API cloth_result cloth_spring_rest_lengths(const cloth_real *points, int dimension, int32_t point_count,
                                                 const int32_t *pair, int32_t count, cloth_real *rest_length);

/* ---- FEM membrane ------------------------------------------------------------------ */

/* Rest data of a membrane triangle: the inverse of the rest edge matrix
   Dm = [uv1 - uv0, uv2 - uv0] (2x2, the edges as columns), row-major
   (dm_inverse[2r + c] is entry (r, c)), in 1/m, and the rest area |det Dm| / 2 in m^2. */
typedef struct cloth_membrane_rest {
    cloth_real dm_inverse[4];
    cloth_real area;
} cloth_membrane_rest;

/* Make the rest data from pattern coordinates uv0, uv1, uv2 (2 each, metres); u is the warp
   direction, v the weft. Either winding is accepted. Fails with CLOTH_ERROR_NOT_FINITE on a
   NaN or infinite coordinate and CLOTH_ERROR_DEGENERATE_TRIANGLE when
   2 area <= CLOTH_MESH_QUALITY_TOLERANCE * (longest edge)^2 (rest is then zeroed). */
CLOTH_API cloth_result cloth_membrane_rest_make(cloth_membrane_rest *rest, const cloth_real *uv0,
                                                const cloth_real *uv1, const cloth_real *uv2);

/* The in-plane stiffness of an orthotropic sheet, in N/m (a 3D modulus times the thickness),
   as the coefficients of the energy per rest area (below). c11 is the warp (u) stiffness,
   c22 the weft (v) stiffness, c12 the Poisson coupling, c33 the shear stiffness. The
   projected membrane Hessian is positive semidefinite when c11, c22, c33 >= 0 and
   c12^2 <= c11 c22 (a stable material). */
typedef struct cloth_membrane_stiffness {
    cloth_real c11, c12, c22, c33;
} cloth_membrane_stiffness;

/* An isotropic sheet of Young's modulus Y (Pa), thickness t (m) and Poisson ratio nu
   (-1 < nu < 1), plane stress: c11 = c22 = Y t / (1 - nu^2), c12 = nu c11,
   c33 = Y t / (2 (1 + nu)) (the shear modulus times t). */
CLOTH_API cloth_membrane_stiffness cloth_membrane_stiffness_isotropic(cloth_real young_modulus, cloth_real thickness,
                                                                      cloth_real poisson_ratio);
/* An orthotropic sheet, plane stress: warp and weft Young's moduli Y1, Y2 (Pa), the Poisson
   ratio nu12 (weft contraction per warp extension under warp load), the in-plane shear
   modulus G12 (Pa) and the thickness t (m). With nu21 = nu12 Y2 / Y1 and
   D = 1 - nu12 nu21: c11 = Y1 t / D, c22 = Y2 t / D, c12 = nu12 Y2 t / D, c33 = G12 t. */
CLOTH_API cloth_membrane_stiffness cloth_membrane_stiffness_orthotropic(cloth_real young_warp, cloth_real young_weft,
                                                                        cloth_real poisson_warp_weft,
                                                                        cloth_real shear_modulus, cloth_real thickness);

/* The Green-Lagrange strain of a triangle: F = Ds Dm^-1 (3x2, Ds = [x1 - x0, x2 - x0]),
   E = 1/2 (F^T F - I); strain[0] = E11 (warp), strain[1] = E22 (weft), strain[2] = E12
   (the tensor component, half the engineering shear), dimensionless. */
CLOTH_API void cloth_membrane_strain(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                     const cloth_membrane_rest *rest, cloth_real *strain);

/* The orthotropic St.Venant-Kirchhoff membrane energy of a triangle (seed 002's model):
       W = 1/2 (c11 E11^2 + 2 c12 E11 E22 + c22 E22^2) + 2 c33 E12^2     (J/m^2)
       E = area * W                                                      (J)
   with the second Piola-Kirchhoff stress S = dW/dE (N/m): S11 = c11 E11 + c12 E22,
   S22 = c12 E11 + c22 E22, S12 = 2 c33 E12. With D = [-1 -1; 1 0; 0 1] Dm^-1 (3x2, 1/m),
   whose row a weights vertex a in F = sum_a x_a D_a, the gradient is
   dE/dx_a = area * P D_a^T with the first Piola-Kirchhoff stress P = F S (3x2, N/m), and the
   Hessian block (a, b) is area * sum_{p,q} D_ap D_bq K_pq with K_pq = d2W/dF_p dF_q (F_p the
   columns of F) = a material term (from dS/dE) + S_pq I (the geometric term).
   exact: as written. projected: the geometric term uses the absolute value |S| of the stress
   (its 2x2 eigenvalues replaced by their magnitudes): under tension in both principal
   directions it equals the exact Hessian; under compression the destabilizing part turns
   into an equal stiffening one (absolute eigenvalue filtering, Chen et al. 2024). Clamping
   those eigenvalues at zero instead (the spring's remedy) leaves a compressed sheet no
   stiffness out of its plane while its forces keep an out-of-plane part wherever it is
   curved: a Newton step then throws such vertices centimetres off a draped surface (the
   sphere scene at 64 x 64 ran 1.45 times slower with the clamp, README). It is positive
   semidefinite for a stable material (see cloth_membrane_stiffness) and costs no eigen-solve.
   gradient[9], hessian[81]. */
CLOTH_API cloth_real cloth_membrane_energy(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                           const cloth_membrane_rest *rest, const cloth_membrane_stiffness *stiffness,
                                           cloth_real *gradient, cloth_real *hessian, cloth_hessian_form form);

/* ---- dihedral bending -------------------------------------------------------------- */

/* The bending stencil of an interior edge: x0, x1 the edge, x2 the vertex opposite it in the
   face (x0, x1, x2), x3 the vertex opposite it in the face (x1, x0, x3); both faces are
   counter-clockwise from the front, as cloth_topology lists them (edge_vertex[2e],
   edge_vertex[2e+1], edge_opposite[2e], edge_opposite[2e+1]). With front normals
   n0 ~ (x1 - x0) x (x2 - x0), n1 ~ (x0 - x1) x (x3 - x1) and e = (x1 - x0) / |x1 - x0|,
       theta = atan2(e . (n0 x n1), n0 . n1)          in (-pi, pi], radians.
   theta = 0 when flat, theta > 0 when the two faces fold away from their front side (a
   ridge seen from the front, as on a convex outward-facing surface), theta < 0 when they
   fold towards it. Returns 0 when a face of the stencil has no area (a height below roundoff
   times the edge length) or the edge no length. This is also the
   rest-angle helper: the angle of a rest shape with curvature (0 for a flat pattern). */
CLOTH_API cloth_real cloth_dihedral_angle(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                          const cloth_real *x3);

/* Rest data of a bending stencil: weight = l^2 / (2 (a0 + a1)) (dimensionless) from the rest
   edge length l and rest face areas a0, a1, and the rest angle theta_rest (radians). */
typedef struct cloth_bending_rest {
    cloth_real weight;
    cloth_real rest_angle;
} cloth_bending_rest;

/* Rest data from the pattern coordinates of the stencil (2 each, metres) and a rest angle
   (0 for cloth that is flat at rest). Fails with CLOTH_ERROR_NOT_FINITE and
   CLOTH_ERROR_DEGENERATE_TRIANGLE (a face with 2 area <= CLOTH_MESH_QUALITY_TOLERANCE *
   (longest edge)^2); rest is then zeroed. */
CLOTH_API cloth_result cloth_bending_rest_make(cloth_bending_rest *rest, const cloth_real *uv0, const cloth_real *uv1,
                                               const cloth_real *uv2, const cloth_real *uv3, cloth_real rest_angle);
/* Rest data from a curved 3D rest shape: lengths and areas from x0..x3 and
   rest_angle = cloth_dihedral_angle(x0, x1, x2, x3). Same errors. */
CLOTH_API cloth_result cloth_bending_rest_from_shape(cloth_bending_rest *rest, const cloth_real *x0,
                                                     const cloth_real *x1, const cloth_real *x2, const cloth_real *x3);

/* The bending stiffness of one hinge of an orthotropic fabric (N m), from the stiffness for
   curvature along the warp (u) and along the weft (v) and the hinge edge's pattern
   coordinates: with t = (uv1 - uv0) / |uv1 - uv0| the edge direction, curvature across the
   edge runs along (-t_v, t_u), so
       B = bend_warp t_v^2 + bend_weft t_u^2
   (an edge along the weft folds the warp yarns and takes bend_warp). On a mesh whose edges
   follow the warp and weft (cloth_mesh_grid) a cylinder bent along either axis then stores
   exactly that axis's B / (2 R^2); on other meshes the hinges share the two stiffnesses and
   bending along an axis mixes them (for equilateral triangles with an edge along the bending
   direction, 2/3 of the one and 1/3 of the other). A zero-length edge gets the mean. */
CLOTH_API cloth_real cloth_bending_stiffness_orthotropic(cloth_real bend_warp, cloth_real bend_weft, const cloth_real *uv0,
                                                         const cloth_real *uv1);

/* Dihedral bending energy (Grinspun et al. 2003, Bridson et al. 2003, ARCSim's form) with
   the physical bending stiffness B in N m:
       E = B * l^2 / (2 (a0 + a1)) * (theta - theta_rest)^2 = B * weight * dtheta^2   (J)
   dtheta = theta - theta_rest is taken in (-pi, pi]. The constant 1/2 makes a mesh wrapped
   on a cylinder of radius R store B / (2 R^2) per unit area, the continuum value
   (1/2) B kappa^2, exactly in the fine-mesh limit for meshes of equilateral triangles (any
   orientation) and for right-triangle grids bent along a grid axis. Bent at an angle psi to
   a grid axis, a grid of right triangles whose diagonals all run along psi = 45 degrees
   stores 1 + sin 2psi + sin^2 2psi times the continuum value (0.75 .. 3: a cylinder whose
   axis runs along the diagonals is exact, one across them is 3 times too stiff), and a grid
   with alternating diagonals 1 + sin^2(2psi) / 2 (1 .. 1.5). Prefer equilateral-ish meshes
   when bending isotropy matters. (The same energy written k l^2 / (8 (a0 + a1)) dtheta^2
   has k = 4 B.)
   The gradient uses the closed form, with n0, n1 the unit front normals, h0, h1 the heights
   of x2, x3 over the edge and t0, t1 the positions of their feet along it (x0 + t (x1 - x0)):
       dtheta/dx2 = -n0 / h0,  dtheta/dx3 = -n1 / h1,
       dtheta/dx0 = (1 - t0) n0 / h0 + (1 - t1) n1 / h1,  dtheta/dx1 = t0 n0 / h0 + t1 n1 / h1,
       dE/dx = 2 B weight dtheta * dtheta/dx.
   exact Hessian: 2 B weight (grad theta grad theta^T + dtheta * d2theta/dx2).
   projected (Gauss-Newton): 2 B weight grad theta grad theta^T, rank one and positive
   semidefinite; the omitted term is proportional to dtheta, so the two agree at the rest
   angle.
   A stencil with a zero-area face or a zero-length edge returns 0 with zero gradient and
   Hessian. gradient[12], hessian[144]. */
CLOTH_API cloth_real cloth_bending_energy(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                          const cloth_real *x3, const cloth_bending_rest *rest, cloth_real stiffness,
                                          cloth_real *gradient, cloth_real *hessian, cloth_hessian_form form);

/* ---- quadratic bending ------------------------------------------------------------- */

/* The world's accurate bending energy (cloth_piece_def.bending_model = CLOTH_BENDING_QUADRATIC;
   the default is the cheaper dihedral energy above): the plate energy of
   Poisson ratio 0 on curvatures measured per vertex, quadratic in the positions (in the
   spirit of Bergou et al. 2006, "A quadratic bending model for inextensible surfaces", whose
   cotangent Laplacian is the trace of the operator used here). For vertex i, three weak
   second derivatives of the map x(u, v) from the flat pattern,
       H_ab(i) = -1/A_i sum_faces area_t d_a(phi_i) d_b(x_h)   (ab = uu, vv, uv symmetrized)
   with phi_i the piecewise-linear hat function of the vertex, x_h the piecewise-linear
   positions and A_i the vertex's mixed Voronoi area in the pattern (Meyer et al. 2003; the
   areas sum to the pattern's), are linear in the positions of the vertex and its one-ring,
   and the energy is
       E_i = A_i / 2 (bend_warp |H_uu|^2 + bend_weft |H_vv|^2 + 2 sqrt(bend_warp bend_weft) |H_uv|^2)  (J).
   For an isometric deformation H_ab is the second fundamental form times the normal, so E is
   the continuum B/2 (k_uu^2 + k_vv^2 + 2 k_uv^2) (twist takes the geometric mean of the two
   stiffnesses): a pattern wrapped on a cylinder of radius R whose curvature runs along the
   warp stores bend_warp / (2 R^2) per unit area at every interior vertex of equilateral
   meshes and of the regular right-triangle grid, in any direction, and of the alternating
   (union-jack) grid along its axes; off its axes the alternating grid measures twist unevenly
   (its valence-4 vertices see no diagonal) and stores 1 + sin^2(2 psi) / 2 times the value at
   an angle psi to u, like the dihedral energy there (tests/test_forces.c). E is quadratic in x, so its
   Hessian is constant, exact and positive semidefinite (blocks sum_m w_am w_bm I), and the
   implicit solver sees the true stiffness.
   Why not the dihedral energy alone: that one is a sum of squares of hinge angles, edge by
   edge; on right-triangle grids a bend shared between edge and diagonal hinges in a
   checkerboard pattern costs less than an even bend, and a strip bent by an end moment turns
   24% too far (README, accuracy). Here every vertex measures the bend along each axis. And
   why all three curvatures: the mean curvature alone (Bergou's energy) leaves saddles free,
   and a narrow strip then bends with the opposite curvature across its width, like a plate
   of Poisson ratio 1, twice too soft in the cantilever test.
   Boundaries: at a boundary vertex the weak derivatives do not vanish on the flat pattern
   (they carry the boundary's flux), so each row is corrected with the vertex's gradient
   estimate (the area-weighted mean of its faces' gradients) until it is zero on every affine
   function of the pattern: E is zero on the flat sheet and invariant under rigid motion at
   every vertex. A straight free edge then measures the curvature along the edge exactly and
   nothing of the curvature across it: the free edge's condition of a plate of Poisson ratio
   0 (no moment across a free edge, so no curvature across it at equilibrium). A sheet bent
   across a free edge stores nothing in the half cells along that edge (a fraction that goes
   to 0 as the mesh is refined).
   Clamps: a face whose three vertices are all pinned is rigid, held by the pins; the pinned
   faces form the clamp, and the edges they share with free faces are the clamp line, where the
   free surface must leave with the clamp's slope. The stencils see the pins (the pinned
   argument): only free faces count, in the weak derivatives and in the vertex's area, so a
   vertex on the clamp line has the half cell on the free side, and the boundary term of its
   weak derivatives takes the slope of the clamp (the area-weighted mean gradient of its pinned
   faces) on the clamp line and the free faces' own on free edges. Along a grid axis this is the
   one-sided curvature (slope of the first free cell - slope of the clamp) / (dx / 2) on the
   half cell, the same as a ghost vertex mirrored across the clamp line; the turn of the strip
   at the clamp then takes the moment over the half cell the clamp leaves free, where counting
   the clamp-line vertex as an interior one (its cell reaching dx / 2 into the clamp) bent the
   strip as if it were dx / 2 longer (a cantilever of 30 cells turned 5% too far; now 0.1%,
   tests/test_physics.c). A vertex whose faces are all pinned stores nothing. A single pinned
   vertex, or a pinned line with no pinned face, holds positions and not slopes (a simply
   supported edge), and changes nothing here. The clamp's slope is exact for a flat clamp
   moved rigidly; a clamp bent to curvature k puts a kink of about k dx / 2 at its line. The
   world makes the stencils with its pins and makes their weights again before the next step
   after cloth_world_pin, _unpin or _set_handle changed which vertices are pinned.
   What it does not do: a curved rest shape (rest angles). The curvature is measured from the
   flat pattern; a piece without uv (its rest shape is its initial shape, which may be curved)
   keeps the dihedral energy and its rest angles in the world. */

/* The stencils of a whole mesh, one per vertex, count-then-fill. The mesh must have uv (the
   flat pattern, metres); its positions are not read. topology is cloth_topology_build's of
   the same mesh. *count receives the number of entries, the sum over vertices of 1 + the
   number of neighbours. When vertex is not NULL, start[vertex_count + 1] receives the offsets
   (vertex v's stencil is entries start[v] .. start[v+1]-1, v itself first, then its
   neighbours), vertex[] the mesh vertex of each entry and weight[3 * entry + m] its weights,
   m = 0, 1, 2 for H_uu, H_vv, H_uv scaled by sqrt(A_i bend_warp), sqrt(A_i bend_weft) and
   sqrt(2 A_i sqrt(bend_warp bend_weft)) (then E_i = 1/2 sum_m |sum_a weight[3a+m] x_a|^2);
   area (may be NULL) receives each vertex's mixed Voronoi area (m^2), over its free faces.
   pinned (may be NULL: none) marks the pinned vertices (nonzero), one per mesh vertex: faces
   with three pinned vertices are the clamp (above); the entries do not depend on it, only the
   weights, so stencils made with other pins fit the same arrays. capacity is the room in
   vertex (entries; weight has 3 per entry).
   Fails with CLOTH_ERROR_INVALID_ARGUMENT for a mesh without uv, a negative stiffness or
   capacity < *count when vertex is not NULL, CLOTH_ERROR_NOT_FINITE for a non-finite
   stiffness or uv, CLOTH_ERROR_DEGENERATE_TRIANGLE for a pattern triangle failing the
   quality test (2 area <= CLOTH_MESH_QUALITY_TOLERANCE * (longest edge)^2) and
   CLOTH_ERROR_SIZE_OVERFLOW when 3 * count does not fit an int32_t; the output arrays are not
   written then. */
CLOTH_API cloth_result cloth_quadratic_bending_stencils(const cloth_mesh *mesh, const cloth_topology *topology,
                                                        cloth_real bend_warp, cloth_real bend_weft, const int32_t *pinned,
                                                        int32_t *start, int32_t *vertex, cloth_real *weight, cloth_real *area,
                                                        int32_t capacity, int32_t *count);

/* The energy of one stencil of `count` entries (J), E = 1/2 sum_m |sum_a weight[3a+m] x[vertex[a]]|^2,
   with x the positions of the whole mesh (3 per vertex). gradient[3 count] (entry a is dE/dx
   of vertex[a]) and hessian[(3 count)^2] (block (a, b) is sum_m weight[3a+m] weight[3b+m] I,
   exact and positive semidefinite), laid out as the other kernels' with the stencil's entries
   in place of an element's vertices; either may be NULL. */
CLOTH_API cloth_real cloth_quadratic_bending_energy(const cloth_real *x, const int32_t *vertex, const cloth_real *weight,
                                                    int32_t count, cloth_real *gradient, cloth_real *hessian);

/* ---- gravity ----------------------------------------------------------------------- */

/* The potential of a point mass m (kg) in a uniform field g (m/s^2, 3 values):
   E = -m g . x, gradient -m g [3] (the force is m g), Hessian zero [9]. */
CLOTH_API cloth_real cloth_gravity_energy(const cloth_real *x, cloth_real mass, const cloth_real *gravity,
                                          cloth_real *gradient, cloth_real *hessian);

/* ---- aerodynamics ------------------------------------------------------------------ */

/* Air parameters of the face force model. */
typedef struct cloth_aerodynamics {
    cloth_real air_density;            /* rho, kg/m^3 (1.225: sea-level air at 15 C) */
    cloth_real normal_coefficient;     /* C_n, pressure coefficient across the face (1.28: flat plate) */
    cloth_real tangential_coefficient; /* C_t, skin friction along the face (0: none) */
} cloth_aerodynamics;

/* The defaults above. */
CLOTH_API cloth_aerodynamics cloth_default_aerodynamics(void);

/* The aerodynamic force on a triangle (x0, x1, x2) whose vertices move with v0, v1, v2 in a
   wind of velocity `wind` (m/s). With the relative velocity u = wind - (v0 + v1 + v2)/3, the
   unit normal n and the area A of the current triangle, u_n = u . n and u_t = u - u_n n:
       f = 1/2 rho A ( C_n u_n |u_n| n + C_t |u_t| u_t )            (N)
   a pressure force across the face, quadratic in the normal relative speed, which carries
   both the drag (its part along u) and the lift (its part across u) of an inclined face,
   plus optional quadratic skin friction along it. The force is the same for either side of
   the face, vanishes when the face moves with the wind, and the pressure part vanishes for a
   wind in the plane of the face. Each vertex receives f / 3: force[9] (may be NULL).
   velocity_jacobian[81] (may be NULL) is df/dv with every 3x3 block equal to
       -1/9 * 1/2 rho A ( 2 C_n |u_n| n n^T + C_t (|u_t| (I - n n^T) + u_t u_t^T / |u_t|) )
   (symmetric negative semidefinite). The dependence of A and n on the positions is not
   differentiated: the integrator treats it explicitly. A face of zero area gets no force. */
CLOTH_API void cloth_aerodynamic_force(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                       const cloth_real *v0, const cloth_real *v1, const cloth_real *v2,
                                       const cloth_real *wind, const cloth_aerodynamics *air, cloth_real *force,
                                       cloth_real *velocity_jacobian);

/* A gusty wind: a mean wind plus a random gust vector g(t) whose components are independent
   stationary Ornstein-Uhlenbeck processes, each of mean 0, standard deviation deviation[k]
   and autocorrelation exp(-|dt| / correlation_time). The gust changes both the strength and
   the direction of the wind smoothly over the correlation time. */
typedef struct cloth_gust_def {
    cloth_real mean[3];          /* m/s, the steady wind */
    cloth_real deviation[3];     /* m/s, the gust's standard deviation along x, y, z (>= 0) */
    cloth_real correlation_time; /* s (> 0) */
    uint64_t seed;               /* the same seed gives the same gusts */
} cloth_gust_def;

/* Defaults: no mean wind, deviation 0 (a calm), correlation time 1 s, seed 1. */
CLOTH_API cloth_gust_def cloth_default_gust_def(void);

/* The state of a gust process: the definition, the current gust (m/s), the time since the
   start (s) and the generator. Plain data: copying it forks an identical future. */
typedef struct cloth_gust {
    cloth_gust_def def;
    cloth_real gust[3];
    double time; /* double so that long runs of small steps keep an exact clock */
    cloth_rng rng;
} cloth_gust;

/* Start a process at time 0 with the gust drawn from its stationary distribution.
   Fails with CLOTH_ERROR_NOT_FINITE for a non-finite parameter and
   CLOTH_ERROR_INVALID_ARGUMENT for a negative deviation or a correlation time <= 0
   (gust is then zeroed). */
CLOTH_API cloth_result cloth_gust_init(cloth_gust *gust, const cloth_gust_def *def);
/* Advance by dt >= 0 seconds with the exact transition of the process,
       g <- g exp(-dt/tau) + deviation * sqrt(1 - exp(-2 dt/tau)) * N(0, 1),
   so the statistics do not depend on the step; dt = 0 changes nothing and draws no random
   number. Fails with CLOTH_ERROR_INVALID_ARGUMENT for a negative or non-finite dt (nothing
   changes then). */
CLOTH_API cloth_result cloth_gust_advance(cloth_gust *gust, cloth_real dt);
/* The current wind, mean + gust, in wind[3] (m/s). */
CLOTH_API void cloth_gust_wind(const cloth_gust *gust, cloth_real *wind);

/* ---- damping ----------------------------------------------------------------------- */

/* Seed 002's damping of the relative velocities of an element's k vertices (an edge: v0, v1,
   with v2 = v3 = NULL; a triangle: v0, v1, v2, with v3 = NULL; a hinge: all four; each
   points to a vertex's 3 velocity components, m/s):
       f_a = -c sum_b (v_a - v_b)          (N; c in N s/m = kg/s)
   It is the force of the dissipation function D = c/2 sum_{a<b} |v_a - v_b|^2: it removes
   no momentum and leaves rigid translation undamped. force[3k];
   velocity_jacobian[(3k)^2] (may be NULL): df_a/dv_b = -c (k delta_ab - 1) I, symmetric
   negative semidefinite. Passing v3 without v2 is a misuse (CLOTH_ASSERT). */
CLOTH_API void cloth_relative_damping_force(const cloth_real *v0, const cloth_real *v1, const cloth_real *v2,
                                            const cloth_real *v3, cloth_real coefficient, cloth_real *force,
                                            cloth_real *velocity_jacobian);

/* Linear air drag on a vertex: f = -c v (N; c in kg/s), df/dv = -c I. force[3],
   velocity_jacobian[9] (may be NULL). */
CLOTH_API void cloth_air_drag_force(const cloth_real *velocity, cloth_real coefficient, cloth_real *force,
                                    cloth_real *velocity_jacobian);

#ifdef __cplusplus
}
#endif

/* ===================================================================================== */
/* linsolve: a symmetric 3x3 block sparse matrix whose pattern is fixed at setup, SpMV,    */
/*           the filtered preconditioned conjugate gradient of Baraff & Witkin (1998)     */
/*           with the correction of Ascher & Boxerman (2003), and its preconditioners:    */
/*           Jacobi, block-Jacobi and smoothed-aggregation algebraic multigrid            */
/*           needs: core, math                                                            */
/*                                                                                       */
/* The implicit integrator assembles A = M - h df/dv - h^2 df/dx into a cloth_block_matrix */
/* and solves A dv = b with cloth_pcg_solve, where pinned vertices and vertices sliding   */
/* on a plane or a line are handled by a per-vertex constraint filter instead of by       */
/* changing the matrix. The same matrix, filter and workspace serve the adjoint solve of  */
/* the differentiation module: the filtered system S A S y = S g is symmetric, so the      */
/* adjoint of a filtered solve is another filtered solve with the same A and S and a zero  */
/* prescribed value.                                                                      */
/*                                                                                       */
/* Which preconditioner: stiff cloth makes A badly conditioned, and block-Jacobi needs    */
/* hundreds of iterations (about 560 per step for the hang scene at 64 x 64 vertices to   */
/* a relative 1e-3); multigrid needs about 16, each costing about 3.5 block-Jacobi        */
/* iterations, plus a numeric setup of about 5 more per solve: 6 to 8 times less time at  */
/* 64 x 64, 11 to 13 times at 128 x 128 (bench/linsolve.c, bench/results/linsolve*.csv).  */
/* Block-Jacobi stays competitive for small or soft systems (a few hundred vertices, or a */
/* few dozen iterations). cloth_pcg_solve_preconditioned makes the preconditioner from    */
/* another matrix, say a sparser one that bounds A from above: the world's lumped bending */
/* in the preconditioner runs the quadratic bending's exact step 2.5-3x faster so.        */
/*                                                                                       */
/* Memory: the matrix, the workspace and the multigrid hierarchy allocate at setup only;   */
/* cloth_block_matrix_zero, the add and multiply functions, cloth_pcg_multigrid_update     */
/* and the solves allocate nothing.                                                       */
/* Determinism: every sum runs in a fixed order (by row, then by column), so the same      */
/* inputs give bit-identical results.                                                     */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

/* A square matrix of vertex_count x vertex_count blocks of 3x3 reals, stored as compressed
   sparse rows over blocks (block CSR). Row i holds the blocks
   k = row_start[i] .. row_start[i+1]-1, in increasing column[k]; diagonal[i] is the index of
   block (i, i), which is always present. Block k's entries are value[9k .. 9k+8] in row-major
   order: entry (r, c) of the block, r and c in 0..2, is value[9k + 3r + c].
   The pattern is symmetric: block (i, j) exists exactly when block (j, i) does. The solver
   assumes the values are symmetric too (block (j, i) is the transpose of block (i, j)); the
   add functions below make that easy to keep. The arrays are owned by the matrix; callers
   may read them and write value[] directly. */
typedef struct cloth_block_matrix {
    int32_t vertex_count;  /* block rows = block columns; the matrix is 3 vertex_count square */
    int32_t block_count;   /* stored blocks: vertex_count diagonal blocks + 2 per distinct pair */
    int32_t *row_start;    /* vertex_count + 1 */
    int32_t *column;       /* block_count, sorted within each row */
    int32_t *diagonal;     /* vertex_count: block index of (i, i) */
    cloth_real *value;     /* 9 block_count */
    cloth_allocator allocator;
} cloth_block_matrix;

/* Make a matrix over vertex_count vertices (>= 0) whose pattern holds the diagonal blocks and,
   for each pair (pair[2k], pair[2k+1]), k < pair_count, the blocks (i, j) and (j, i).
   Duplicate pairs, both orders of a pair and pairs (i, i) are accepted and stored once.
   The values start at zero. pair may be NULL when pair_count is 0.
   Fails with CLOTH_ERROR_INVALID_ARGUMENT for a negative count, CLOTH_ERROR_INDEX_OUT_OF_RANGE
   for a vertex outside 0..vertex_count-1, CLOTH_ERROR_SIZE_OVERFLOW when the number of blocks
   does not fit an int32_t, CLOTH_ERROR_OUT_OF_MEMORY; the matrix is then left empty.
   Setup cost O(vertex_count + pair_count): no comparison sort. */
CLOTH_API cloth_result cloth_block_matrix_create(cloth_block_matrix *matrix, int32_t vertex_count,
                                                 const int32_t *pair, int32_t pair_count,
                                                 const cloth_allocator *allocator);
/* Free a matrix with the allocator it was made with and leave it empty. Accepts an empty
   (zero-filled or already freed) matrix. */
CLOTH_API void cloth_block_matrix_free(cloth_block_matrix *matrix);
/* The index k of block (row, column) (its values are value[9k .. 9k+8]), or -1 when the block
   is not in the pattern or an index is out of range. Binary search in the row: assembly code
   looks its blocks up once after setup and keeps the indices. */
CLOTH_API int32_t cloth_block_matrix_find(const cloth_block_matrix *matrix, int32_t row, int32_t column);
/* Set every value to zero; the pattern stays. */
CLOTH_API void cloth_block_matrix_zero(cloth_block_matrix *matrix);
/* block k += scale * b, where b[9] is a 3x3 block in row-major order. */
CLOTH_API void cloth_block_matrix_add_block(cloth_block_matrix *matrix, int32_t block, cloth_real scale,
                                            const cloth_real *b);
/* block k += scale * b^T. With the two calls an element's coupling block H(i, j) goes into
   block (i, j) and its transpose into block (j, i), which keeps the matrix exactly symmetric. */
CLOTH_API void cloth_block_matrix_add_block_transposed(cloth_block_matrix *matrix, int32_t block, cloth_real scale,
                                                       const cloth_real *b);
/* Diagonal block (i, i) += scale * weight[i] * I for every vertex i; weight == NULL means 1
   for all (a scaled identity). Adds the lumped mass matrix with weight = mass, scale = 1. */
CLOTH_API void cloth_block_matrix_add_diagonal(cloth_block_matrix *matrix, cloth_real scale, const cloth_real *weight);
/* y = A x, x and y of 3 vertex_count reals that do not overlap. */
CLOTH_API void cloth_block_matrix_multiply(const cloth_block_matrix *matrix, const cloth_real *x, cloth_real *y);
/* y += scale * A x, x and y of 3 vertex_count reals that do not overlap. */
CLOTH_API void cloth_block_matrix_multiply_add(const cloth_block_matrix *matrix, cloth_real scale, const cloth_real *x,
                                               cloth_real *y);

/* ---- filtered preconditioned conjugate gradient ------------------------------------ */

/* The constraint filter of Baraff & Witkin. Vertex i has constrained[i] in 0..3 constrained
   directions; with p = direction[6i .. 6i+2] and q = direction[6i+3 .. 6i+5] its filter is
       0 constrained: S_i = I                      (free)
       1 constrained: S_i = I - p p^T              (moves in the plane normal to p)
       2 constrained: S_i = I - p p^T - q q^T      (moves along p x q)
       3 constrained: S_i = 0                      (pinned)
   and the solution must satisfy (I - S_i) x_i = (I - S_i) z_i, with z = value[3i .. 3i+2].
   p and q should be unit and orthogonal; the solver normalizes p and orthogonalizes q against
   p itself, so rounding in the caller's directions does not spoil the projection. Only p is
   read for 1 constrained direction; direction may be NULL when no vertex has 1 or 2.
   constrained == NULL means every vertex is free (no filter). value == NULL means z = 0;
   otherwise all 3 vertex_count values must be finite (the free components are ignored but
   checked). Arrays are read during the call only. */
typedef struct cloth_pcg_filter {
    const int32_t *constrained;   /* vertex_count, each 0..3, or NULL */
    const cloth_real *direction;  /* 6 vertex_count: p then q, or NULL */
    const cloth_real *value;      /* 3 vertex_count: z, or NULL */
} cloth_pcg_filter;

typedef enum cloth_preconditioner {
    CLOTH_PRECONDITIONER_NONE = 0,
    /* The diagonal of the filtered diagonal blocks M_i (below). */
    CLOTH_PRECONDITIONER_JACOBI = 1,
    /* The inverse of each filtered diagonal block, restricted to the free directions:
       P_i^-1 = S_i M_i^-1 S_i with M_i = S_i A_ii S_i + c_i (I - S_i), c_i the mean of S_i A_ii S_i
       over the free directions (trace / number free). M_i acts as A_ii on the free directions
       and as c_i on the constrained ones, which decouples them, so P_i^-1 is the inverse of
       A_ii's restriction to the free subspace; a free vertex gets A_ii^-1 and a pinned one 0. */
    CLOTH_PRECONDITIONER_BLOCK_JACOBI = 2,
    /* One symmetric V-cycle of smoothed-aggregation algebraic multigrid (see "multigrid"
       below). Needs a hierarchy on the workspace, made once per matrix pattern by
       cloth_pcg_multigrid_setup; far fewer iterations than block-Jacobi on stiff cloth.
       Its finest level smooths with the block-Jacobi blocks above, so pinned and sliding
       vertices are treated exactly as block-Jacobi treats them. */
    CLOTH_PRECONDITIONER_MULTIGRID = 3
} cloth_preconditioner;

/* Options of a solve. Make them with cloth_default_pcg_options() and change what you need. */
typedef struct cloth_pcg_options {
    /* Relative tolerance, finite and >= 0: the solve stops when the preconditioned residual
       r^T P^-1 r falls to tolerance^2 times its value for the reduced right-hand side
       bhat = S (b - A (I - S) z) (that is, for the start x = (I - S) z), as in Baraff & Witkin.
       Default 1e-6 with double, 1e-4 with float. */
    cloth_real tolerance;
    /* The most iterations, >= 0 (0: only test the start x). Default 1000; stiff cloth at
       high resolution can need more (bench/linsolve.c). */
    int32_t max_iterations;
    /* Default CLOTH_PRECONDITIONER_BLOCK_JACOBI. */
    cloth_preconditioner preconditioner;
    /* CLOTH_PRECONDITIONER_MULTIGRID only. 1 (default): the solve first recomputes the values
       of the workspace's hierarchy from this matrix and filter, as cloth_pcg_multigrid_update
       does (the cost of about 5 iterations), for the best preconditioner of this system. 0: it
       keeps the coarse levels of the last setup or update and refreshes level 0 alone (its
       smoother and its copy of the matrix) from this matrix and filter; the preconditioner
       stays symmetric positive definite, so the result is as exact as ever, but convergence
       slows as the matrix drifts from the one the coarse levels came from. Use 0 for a second
       solve with the same matrix (an adjoint solve) or after your own update. */
    int multigrid_update;
    /* Absolute floor of the stopping test's scale, >= 0 and finite; 0 (default): none. The
       solve stops when sqrt(r^T P^-1 r) <= tolerance * max(sqrt(bhat^T P^-1 bhat),
       reference_norm). An inexact Newton method passes the first solve's rhs_norm (see
       cloth_pcg_stats) to the later ones: their corrections, small beside the first step, are
       then solved to the first step's accuracy, not to a tolerance relative to themselves. */
    cloth_real reference_norm;
} cloth_pcg_options;

/* Statistics of one solve. */
typedef struct cloth_pcg_stats {
    int32_t iterations;          /* conjugate gradient iterations done (0: the start x was accepted) */
    /* |S (b - A x)| / |bhat| in the 2-norm for the returned x, recomputed from x (not the
       recurrence), with bhat = S (b - A (I - S) z); 0 when bhat = 0. The stopping test works
       in the P^-1 norm, so this may exceed the tolerance by up to sqrt(cond(P)) (stiff
       in-plane against soft out-of-plane blocks make that ratio large). */
    cloth_real residual;
    /* sqrt(r^T P^-1 r / bhat^T P^-1 bhat) from the recurrence: the quantity the stopping test
       compares with the tolerance. */
    cloth_real preconditioned_residual;
    cloth_real rhs_norm;         /* sqrt(bhat^T P^-1 bhat), the stopping test's scale */
    int converged;               /* 1 when the stopping test passed (preconditioned_residual <=
                                    tolerance, or the reference_norm floor was met) */
} cloth_pcg_stats;

/* Scratch memory for solves over up to vertex_count vertices: 24 reals per vertex, and the
   multigrid hierarchy once cloth_pcg_multigrid_setup has made one. Make one at setup and reuse
   it; one workspace serves one solve at a time. A zero-filled workspace is a valid empty one. */
typedef struct cloth_pcg_workspace {
    int32_t vertex_count;
    cloth_real *memory;
    cloth_allocator allocator;
    struct cloth__multigrid *multigrid; /* private; NULL until cloth_pcg_multigrid_setup */
    struct cloth__pool *pool;     /* private; NULL: single-threaded (cloth_pcg_workspace_set_threads) */
    int pool_owned;               /* private: the workspace made the pool and frees it */
} cloth_pcg_workspace;

/* The default options (see cloth_pcg_options). */
CLOTH_API cloth_pcg_options cloth_default_pcg_options(void);
/* Make a workspace for matrices of up to vertex_count (>= 0) vertices. Fails with
   CLOTH_ERROR_INVALID_ARGUMENT, CLOTH_ERROR_SIZE_OVERFLOW or CLOTH_ERROR_OUT_OF_MEMORY and
   leaves the workspace empty. */
CLOTH_API cloth_result cloth_pcg_workspace_create(cloth_pcg_workspace *workspace, int32_t vertex_count,
                                                  const cloth_allocator *allocator);
/* Free a workspace, its multigrid hierarchy included, and leave it empty. Accepts an empty
   workspace. */
CLOTH_API void cloth_pcg_workspace_free(cloth_pcg_workspace *workspace);
/* Run this workspace's solves (and multigrid updates) on `threads` threads: 0 or 1
   single-threaded (the default), N > 1 the calling thread and N - 1 workers that the call
   starts and cloth_pcg_workspace_free stops (a persistent pool: a solve starts no thread and
   allocates nothing). Needs CLOTH_THREADS defined where the implementation is compiled;
   without it the call succeeds and the solves stay single-threaded. Results are bit-identical
   for every thread count: the matrix products and the multigrid update split by rows (or
   aggregates), dot products are summed per fixed chunk of 256 vertices and the chunks added in
   order, the multigrid smoother's Gauss-Seidel sweeps stay serial unless the hierarchy's
   options ask for sweep parts (fixed by those options and the matrix's size, whatever the
   threads; level 0 only). Call it after cloth_pcg_workspace_create and before
   cloth_pcg_multigrid_setup (the hierarchy sizes per-thread scratch then; one made earlier
   runs its update's products serially). Fails with CLOTH_ERROR_INVALID_ARGUMENT for
   threads < 0 or > 64, and with CLOTH_ERROR_OUT_OF_MEMORY when memory or a thread cannot be
   had (then single-threaded). */
CLOTH_API cloth_result cloth_pcg_workspace_set_threads(cloth_pcg_workspace *workspace, int32_t threads);

/* Solve A x = b for symmetric positive definite A (symmetry is assumed, not checked) under
   the constraint filter: on return
   (I - S) x = (I - S) z to rounding and S (b - A x) is small (stats). This is the modified
   conjugate gradient of Baraff & Witkin with Ascher & Boxerman's correction: it is plain PCG on
   the reduced system S A S y = S (b - A (I - S) z), x = S y + (I - S) z.
   x (3 vertex_count reals) holds the start on entry: its free part S x is kept (warm start),
   its constrained part is replaced by (I - S) z. filter == NULL means no constraints;
   options == NULL means the defaults; stats may be NULL. Allocates nothing.
   Returns
     CLOTH_SUCCESS                       converged (stats->converged = 1);
     CLOTH_ERROR_CG_NOT_CONVERGED        max_iterations reached; x holds the last iterate, which
                                         satisfies the constraints;
     CLOTH_ERROR_NOT_POSITIVE_DEFINITE   a search direction of non-positive curvature
                                         (p^T S A S p <= 0) or a diagonal block that is not
                                         positive definite on its free directions (found by a
                                         preconditioner); x holds the last iterate, or is
                                         unchanged when the preconditioner found it;
     CLOTH_ERROR_NOT_FINITE              a NaN or infinity in b, z, the filter's directions, the
                                         matrix values or the start x (x is then unchanged), or
                                         an overflow during the iteration (x holds the last
                                         iterate);
     CLOTH_ERROR_INVALID_ARGUMENT        bad options, a constrained count outside 0..3, a zero
                                         direction or q parallel to p (|q - (q.p)p| < 1e-3 |q|
                                         after normalizing p), a missing direction array, or a
                                         workspace smaller than the matrix (x unchanged).
   With CLOTH_PRECONDITIONER_MULTIGRID the workspace must hold a hierarchy made for this
   matrix's pattern (cloth_pcg_multigrid_setup), with values when multigrid_update is 0, else
   CLOTH_ERROR_INVALID_ARGUMENT with x unchanged; the numeric phase the solve runs first
   (multigrid_update = 1) fails as cloth_pcg_multigrid_update does, x unchanged.
   When bhat = 0 (a zero right-hand side for the reduced system) x becomes (I - S) z at once
   with 0 iterations. */
CLOTH_API cloth_result cloth_pcg_solve(const cloth_block_matrix *matrix, const cloth_real *b, cloth_real *x,
                                       const cloth_pcg_filter *filter, const cloth_pcg_options *options,
                                       cloth_pcg_workspace *workspace, cloth_pcg_stats *stats);
/* cloth_pcg_solve with the preconditioner made from `approximation` instead of `matrix`: a
   symmetric positive definite matrix over the same vertices, on any pattern (a sparser one
   makes a cheaper preconditioner; with CLOTH_PRECONDITIONER_MULTIGRID the hierarchy must have
   been set up for approximation's pattern). The iteration still solves matrix's system to the
   tolerance; the approximation only sets how fast. The world uses it for lumped bending in the
   preconditioner (cloth_piece_def's bending_lumped = 2). Fails as cloth_pcg_solve, and with
   CLOTH_ERROR_INVALID_ARGUMENT for an approximation of another vertex count, x unchanged;
   approximation = matrix is cloth_pcg_solve. */
CLOTH_API cloth_result cloth_pcg_solve_preconditioned(const cloth_block_matrix *matrix, const cloth_block_matrix *approximation,
                                                      const cloth_real *b, cloth_real *x, const cloth_pcg_filter *filter,
                                                      const cloth_pcg_options *options, cloth_pcg_workspace *workspace,
                                                      cloth_pcg_stats *stats);

/* ---- multigrid ---------------------------------------------------------------------- */

/* Smoothed-aggregation algebraic multigrid (Vanek, Mandel & Brezina 1996; for cloth, Tamstorf,
   Jones & McCormick 2015), the preconditioner CLOTH_PRECONDITIONER_MULTIGRID. It lives in the
   workspace: cloth_pcg_multigrid_setup builds it for one matrix pattern, and cloth_pcg_solve
   refreshes its values from each new matrix (options->multigrid_update).

   The hierarchy. Level 0 is the caller's matrix under the constraint filter; each level's
   vertices ("nodes", 3 unknowns each) are grouped into aggregates, and each aggregate is a node
   of the next level.
     Strength: block (i, j) is strong when |A_ij|_F^2 > theta^2 |A_ii|_F |A_jj|_F (Frobenius
       norms, so rotations of the cloth do not change it; bending couplings are weak).
     Aggregation, in vertex order: a node whose strong neighbours are all free makes an
       aggregate of itself and them; a node left joins the aggregate of its strongest
       neighbour; what is still left groups with its free strong neighbours. A node with no
       strong neighbour belongs to no aggregate: the smoother alone corrects it.
     Tentative prolongator T: an aggregate's 3 unknowns are its translations, filtered by each
       vertex's S on level 0 (a pinned vertex takes no part; a sliding one only its free
       directions) and orthonormalized over the aggregate by Gram-Schmidt (the R factors are
       the next level's near null space). A direction that the filter removes from a whole
       aggregate is dropped: that coarse unknown stays zero.
     Prolongator P = (I - omega D^+ A_s) T: one damped Jacobi step over the diagonal and strong
       blocks A_s, D^+ the smoother's blocks, omega = prolongator_damping / rho and rho 1.3
       times the Rayleigh quotient after two power steps on D^+ A from a fixed pseudo-random
       start (about rho(D^+ A) on cloth), in cloth_real with the matrix's own rows.
     Next level's matrix: the Galerkin product P^T A P with the whole A, computed on its upper
       triangle and mirrored, so it is exactly symmetric. A P and P^T (A P) are summed in
       single precision over P's padded single-precision rows, four lanes at a time (the
       V-cycle reads every operator in single precision anyway). Against the same sums in
       double: the same CG iterations (the hang at 64 with cotton x 1000, 8.5e6 N/m: 50.8 and
       49.9 per frame; at 128, dihedral: 57.2 and 57.15; the stiff 32 x 32 grid of the tests:
       43 and 43), and at n = 64 the hang's frame 8.5-8.6 -> 8.0-8.1 ms, the sphere's (CG
       1e-2, 2 obstacle solves, lumped hinges) 20.8-21.0 -> 19.9-20.0 ms.
     Coarsening stops at coarse_size nodes or fewer, at max_levels, or when aggregation
       makes no progress. A coarsest level of up to 4 coarse_size nodes is factored densely
       (Cholesky, in double); a larger one is smoothed instead.

   The V-cycle. From level 0 down: smoothing_steps pre-smoothing sweeps (block Gauss-Seidel,
   forward; or damped block Jacobi), the residual restricted by P^T; the coarsest solve; back up,
   the correction prolongated by P and as many post-smoothing sweeps (Gauss-Seidel backward, or
   Jacobi). On level 0, when the options ask for sweep parts, Gauss-Seidel visits the rows in
   an order that lets its sweeps run on the workspace's threads: the vertices split into parts
   of consecutive indices (sweep_parts), each part's rows that couple with a later part go last
   (the separators), and the parts' other rows, which couple with no other part's, are swept
   part by part, side by side, before the separators (sweep_parts in cloth_multigrid_info; a
   grid's separators are two rows of vertices per cut; when the separators would be over half
   the rows, as with vertices in no spatial order, there is one part). Pre- and post-smoothing
   are adjoint, so the cycle is symmetric, and positive definite because each sweep converges
   on its own: CG's theory holds. On level 0 the smoother's
   blocks are the filtered block-Jacobi inverses (zero for a pinned vertex), residuals are
   filtered and corrections are filtered again with the current filter. The cycle runs in single
   precision on single-precision copies of each level's lower and diagonal blocks (the upper
   ones are their transposes) and of P, padded to 4 lanes (see CLOTH__MG_W): a preconditioner needs no more, it halves the memory
   traffic, and CG stays exact because it multiplies with the caller's matrix.

   Setup and update. cloth_pcg_multigrid_setup is the symbolic phase, which chooses the
   aggregates from the values it is given, fixes every pattern and allocates, followed by a
   numeric phase. cloth_pcg_multigrid_update is the numeric phase alone: T, omega, P, the
   Galerkin products, the smoothers and the coarsest factor recomputed for a matrix with the
   setup's pattern, new values and any filter, in the setup's memory. Its result depends on the
   hierarchy's patterns and on the values and filter it is given, never on those of an earlier
   update: an update gives bit for bit the hierarchy of a fresh setup that chose the same
   aggregates.
     A new pattern needs a new setup; new values or a new filter (pins added or released,
     sliding directions) need an update, which cloth_pcg_solve does itself unless
     options->multigrid_update is 0. Skipping updates (multigrid_update = 0) keeps a symmetric
     positive definite preconditioner, always exact in the end, but on cloth that moves it
     loses quickly (the stiff directions turn with the cloth): in the falling hang scene,
     updating every 4th step needed 5 to 7 times the iterations of updating every step, far
     more than the updates saved.
     The aggregates are not revised by updates: after large changes of stiffness (a material
     change, a much shorter step), a new setup may converge faster.

   Costs (bench/linsolve.c, hang scene, 64 x 64 vertices, one core of a 2.6 GHz Xeon): setup
   5 to 7 ms, an update 3 ms, a V-cycle about three products with the matrix (an iteration
   0.57 ms against block-Jacobi's 0.16 ms), 16 iterations per step at a relative 1e-3 against
   block-Jacobi's 560: 12.4 ms per step against 95 ms. Since the V-cycle runs on 4-lane padded
   vectors and blocks that the compiler vectorizes, in the world's step at n = 64: a V-cycle
   0.23 ms (0.35 before), an update 2.45 ms (2.9), a product with the matrix 0.12 ms. Iterations grow slowly with the mesh
   (11, 15, 16, 18 per step at 16, 32, 64, 128 vertices a side); the rest is linear.

   Determinism: every sum runs in a fixed order, the aggregation and the power steps' start are
   fixed by the vertex order, and nothing depends on addresses or timing. */

/* The most levels a hierarchy can have, the finest included. */
#define CLOTH_MULTIGRID_MAX_LEVELS 16

typedef enum cloth_multigrid_smoother {
    /* Block Gauss-Seidel: forward sweeps before the coarse correction, backward after. */
    CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL = 0,
    /* Damped block Jacobi, weight 4/3 / rho with rho a Gershgorin bound on rho(D^+ A) in the
       symmetric scaling (so that the sweep always converges). 1.7 times the iterations of
       Gauss-Seidel at the same cost per sweep on one core; its sweeps would parallelize. */
    CLOTH_MULTIGRID_SMOOTHER_JACOBI = 1
} cloth_multigrid_smoother;

/* Options of a hierarchy. Make them with cloth_default_multigrid_options() and change what you
   need; the defaults were chosen on the hang scene's matrices (bench/linsolve.c). */
typedef struct cloth_multigrid_options {
    /* theta, the strength threshold, finite, in [0, 1). Default 0.04: on the hang scene 0.03
       to 0.06 do equally well, 0.08 needs 25 % more iterations at 128 x 128 vertices, and 0.12
       and above coarsen too little across the soft shear of woven cloth (twice the
       iterations). Bending couplings are far below any of these. */
    cloth_real strength_threshold;
    /* The factor in omega = factor / rho, finite, in [0, 2]. Default 4/3. 0 gives unsmoothed
       (plain) aggregation, P = T: a third of the update's cost, 1.7 times the iterations. */
    cloth_real prolongator_damping;
    /* Stop coarsening at this many nodes or fewer, >= 1; default 32. A coarsest level of up to
       4 coarse_size nodes is factored densely, a larger one (when aggregation stalls) is
       smoothed. */
    int32_t coarse_size;
    /* The most levels, 1..CLOTH_MULTIGRID_MAX_LEVELS, the finest included; default 10. With 1
       the preconditioner is the dense factor of the whole filtered matrix when it has at most
       4 coarse_size vertices (a direct solver for small systems), else symmetric Gauss-Seidel.
       With 2 the second level is smoothed, not coarsened further, when it has more than 4
       coarse_size nodes: on the sphere scene at 64 x 64 (CG 1e-2) 4% faster than the default
       despite 6-14% more iterations; at 32 x 32 its second level is small enough to be factored
       densely at every update, 3.3 times slower (README, the knobs, bench/paired.c). */
    int32_t max_levels;
    /* Pre- and post-smoothing sweeps per level, >= 1; default 1 (2 saves 15 % of the
       iterations and costs 70 % more per iteration). */
    int32_t smoothing_steps;
    /* Default CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL. */
    cloth_multigrid_smoother smoother;
    /* Level 0's Gauss-Seidel sweeps in parts that run side by side on the workspace's threads,
       0..CLOTH_MULTIGRID_MAX_SWEEP_PARTS: 1 (default) one sweep in the rows' order; 0 one part
       per 1024 rows (at most 8); N >= 2 N parts (at most one per 256 rows). Each part's rows
       that couple with a later part are swept after all parts (see the V-cycle above), so the
       order, and every result, depends on this number and never on the threads. With threads
       use 0 or the thread count: hang 128 on 2 threads 1.10x per solve, hang 64 1.07x. On one
       thread the parts cost no iterations, but at a loose CG tolerance their other order of
       sweeping leaves errors that hit strain limiters more often: hang 64 with 4% limiters
       took 4.5% more solves on average over 11 tolerances and limits (README). */
    int32_t sweep_parts;
} cloth_multigrid_options;

#define CLOTH_MULTIGRID_MAX_SWEEP_PARTS 8

/* What a hierarchy is made of (cloth_pcg_multigrid_info). */
typedef struct cloth_multigrid_info {
    int32_t level_count;                                    /* 0: no hierarchy */
    int32_t node_count[CLOTH_MULTIGRID_MAX_LEVELS];         /* nodes (3 unknowns each) per level */
    int32_t block_count[CLOTH_MULTIGRID_MAX_LEVELS];        /* stored 3x3 blocks of each level's matrix */
    int32_t prolongator_block_count[CLOTH_MULTIGRID_MAX_LEVELS]; /* blocks of P to the next level; 0 on the coarsest */
    /* the blocks of all levels over those of level 0, the usual measure of a hierarchy's
       memory and of a V-cycle's work per fine-level product (about 1.2 on cloth) */
    double operator_complexity;
    int coarsest_dense;          /* 1: the coarsest level is factored densely; 0: smoothed */
    size_t bytes;                /* memory the hierarchy holds (not counting the workspace's own) */
    int32_t sweep_parts;         /* the parts of level 0's Gauss-Seidel sweeps (1: one serial sweep) */
} cloth_multigrid_info;

/* The default options (see cloth_multigrid_options). */
CLOTH_API cloth_multigrid_options cloth_default_multigrid_options(void);

/* Build a multigrid hierarchy for this matrix's pattern on the workspace, replacing any it
   holds: the symbolic phase, which aggregates by the strength of the values given here and
   fixes every pattern, then the numeric phase for these values and this filter (read as
   cloth_pcg_solve reads it; filter may be NULL). Call it once the matrix holds representative
   values (after the first assembly, not on the zeros of a fresh matrix) and again when the
   pattern changes; options == NULL means the defaults. The workspace must cover the matrix
   (workspace->vertex_count >= matrix->vertex_count); the hierarchy is allocated with the
   workspace's allocator and freed by cloth_pcg_workspace_free or the next setup.
   Fails, leaving the workspace without a hierarchy, with CLOTH_ERROR_INVALID_ARGUMENT (options
   out of range, a bad filter, a workspace too small), CLOTH_ERROR_NOT_FINITE (a NaN or infinity
   in the values or the filter's directions, or an overflow in the products),
   CLOTH_ERROR_NOT_POSITIVE_DEFINITE (a free vertex's filtered diagonal block that is not
   positive definite, or, when the whole system is one dense level, a factor that is not),
   CLOTH_ERROR_SIZE_OVERFLOW or CLOTH_ERROR_OUT_OF_MEMORY. */
CLOTH_API cloth_result cloth_pcg_multigrid_setup(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                 const cloth_pcg_filter *filter,
                                                 const cloth_multigrid_options *options);

/* The numeric phase alone: recompute the hierarchy's values for a matrix with the setup's
   pattern and new values, under this filter. Allocates nothing. Fails with
   CLOTH_ERROR_INVALID_ARGUMENT (no hierarchy, another pattern or vertex count, a bad filter),
   CLOTH_ERROR_NOT_FINITE or CLOTH_ERROR_NOT_POSITIVE_DEFINITE as the setup does. After a
   failure the hierarchy keeps its patterns but has no values: solves that do not update it
   (multigrid_update = 0) fail with CLOTH_ERROR_INVALID_ARGUMENT until an update succeeds. */
CLOTH_API cloth_result cloth_pcg_multigrid_update(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                  const cloth_pcg_filter *filter);

/* Describe the workspace's hierarchy (level_count = 0 when it has none). */
CLOTH_API void cloth_pcg_multigrid_info(const cloth_pcg_workspace *workspace, cloth_multigrid_info *info);

#ifdef __cplusplus
}
#endif


/* ===================================================================================== */
/* bvh: bounding volume hierarchy over triangles, the broad phase of collision detection  */
/*      needs: core, math                                                                 */
/* ===================================================================================== */
/* An axis-aligned box tree over the triangles of flat arrays (x[3*vertex_count],
   tri[3*triangle_count]), built by binned SAH or by median split. Each triangle's box is the
   box of its three vertices grown by `thickness` on every side; with a second position array
   x1 it is swept: the box of the vertices at x and at x1 (the motion over a step, for
   continuous collision detection). Two boxes overlap when their closed intervals overlap on
   all three axes, so every pair of triangles at most 2 * thickness apart (swept: that come
   that close at some moment of a straight-line motion from x to x1) is a candidate; pass half
   the proximity distance you need as the thickness.

   Memory and cost: only cloth_bvh_build allocates (about 32 + 18 sizeof(cloth_real) bytes per
   triangle: the items and two nodes per triangle); refit, rebuild and the traversals
   allocate nothing and are O(n) (refit, quality) or O(n log n) (rebuild). Traversals use a
   fixed stack on the C stack: the build keeps the tree at most CLOTH_BVH_MAX_DEPTH deep. A
   built tree is read-only to the traversals, so several threads may traverse one tree at once.

   A step of a simulation, with x the positions now and x1 the predicted ones:

       cloth_bvh_refit(&bvh, x, x1);                      O(n), allocates nothing
       if (cloth_bvh_needs_rebuild(&bvh))                 the tree has grown loose
           cloth_bvh_rebuild(&bvh, x, x1);                new splits, same memory
       cloth_bvh_self_pairs(&bvh, on_pair, &state);       candidate pairs a < b

   The tree keeps its own copy of the triangles (their vertex indices), so the caller's tri
   array may change or go away after the build; a change of connectivity needs a new build.
   Pairs come out in an order fixed by the tree, the same for the same input on every run. */
#ifdef __cplusplus
extern "C" {
#endif

/* The deepest a tree may be (edges from the root to a leaf). The build switches to median
   splits below depth CLOTH_BVH_MAX_DEPTH / 2, so no input reaches it. */
#define CLOTH_BVH_MAX_DEPTH 64
/* The largest leaf_size a cloth_bvh_def accepts. */
#define CLOTH_BVH_MAX_LEAF_SIZE 64

/* How the build splits a node's triangles in two. */
typedef enum cloth_bvh_split {
    CLOTH_BVH_SPLIT_SAH = 0,   /* binned surface area heuristic (16 bins on each axis): tight trees */
    CLOTH_BVH_SPLIT_MEDIAN = 1 /* half the triangles on each side along the longest axis: balanced */
} cloth_bvh_split;

/* How a tree is built; make one with cloth_default_bvh_def() and change what you need.
   The tree keeps a copy in bvh.def, which a caller may change between calls: thickness takes
   effect at the next refit, rebuild_ratio at once, leaf_size and split at the next rebuild. */
typedef struct cloth_bvh_def {
    cloth_real thickness;       /* grown on every side of every triangle box, >= 0 (m); default 0 */
    int32_t leaf_size;          /* most triangles in a leaf, 1..CLOTH_BVH_MAX_LEAF_SIZE; default 2 */
    cloth_bvh_split split;      /* default CLOTH_BVH_SPLIT_SAH */
    cloth_real rebuild_ratio;   /* cloth_bvh_needs_rebuild's threshold on cloth_bvh_quality, >= 1
                                   (HUGE_VAL: never); default 2 */
    int32_t internal_cookie;    /* set by cloth_default_bvh_def; catches a def that was never made */
} cloth_bvh_def;

/* An axis-aligned box, lo <= hi on every axis. */
typedef struct cloth_bvh_box {
    cloth_real lo[3];
    cloth_real hi[3];
} cloth_bvh_box;

/* A node of the tree. A leaf (count >= 1) holds the items first .. first + count - 1; an
   internal node (count == 0) has the two children first and first + 1, which come after it
   in the node array. Its box is the union of its children's or its items' boxes. */
typedef struct cloth_bvh_node {
    cloth_bvh_box box;
    int32_t first;
    int32_t count;
} cloth_bvh_node;

/* A tree. nodes[0] is the root (node_count == 0 for a tree over no triangles). Items are the
   triangles in leaf order: item_triangle[i] is the triangle in slot i, item_vertex[3i..3i+2]
   its vertices and item_box[i] its (grown, possibly swept) box. cost is the tree's SAH cost
   at the last refit and build_cost the same at the last build or rebuild (see
   cloth_bvh_quality). Everything here may be read; only def may be written (see cloth_bvh_def). */
typedef struct cloth_bvh {
    int32_t vertex_count;
    int32_t triangle_count;
    int32_t node_count;      /* at most 2 * triangle_count - 1 */
    int32_t depth;           /* edges from the root to the deepest leaf, <= CLOTH_BVH_MAX_DEPTH */
    cloth_bvh_def def;
    cloth_real cost;
    cloth_real build_cost;
    cloth_bvh_node *nodes;
    cloth_bvh_box *item_box;
    int32_t *item_triangle;
    int32_t *item_vertex;
    cloth_allocator allocator;
} cloth_bvh;

/* Called with each candidate pair; return 0 to go on, non-zero to stop the traversal, which
   then returns that value. For cloth_bvh_self_pairs a < b are triangles of the one tree; for
   cloth_bvh_pairs a is a triangle of the first tree and b of the second. */
typedef int (*cloth_bvh_pair_fn)(int32_t a, int32_t b, void *user);
/* Called with each triangle a box query finds; return non-zero to stop, as above. */
typedef int (*cloth_bvh_triangle_fn)(int32_t triangle, void *user);

/* The defaults: thickness 0, leaf_size 2, SAH splits, rebuild_ratio 2. Leaves of 2 gave the
   fastest refit plus self traversal on grids of 450 to 130,050 triangles (bench/bvh.c). */
CLOTH_API cloth_bvh_def cloth_default_bvh_def(void);

/* Build a tree over triangles tri[3*triangle_count] of the vertices x[3*vertex_count], with
   boxes swept to x1[3*vertex_count] when x1 is not NULL. def NULL means the defaults. Arrays
   may be NULL when their count is zero; a tree over no triangles is valid and finds nothing.
   Returns CLOTH_ERROR_INVALID_ARGUMENT for a negative count, a NULL array with a non-zero
   count or a def value out of range, CLOTH_ERROR_INDEX_OUT_OF_RANGE for a vertex index
   outside [0, vertex_count), CLOTH_ERROR_NOT_FINITE when any coordinate of x or x1 is NaN or
   infinite, CLOTH_ERROR_SIZE_OVERFLOW above 2^30 triangles, CLOTH_ERROR_OUT_OF_MEMORY. The
   bvh is overwritten (free a built one first); on failure it is left empty. */
CLOTH_API cloth_result cloth_bvh_build(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1, int32_t vertex_count,
                                       const int32_t *tri, int32_t triangle_count, const cloth_bvh_def *def,
                                       const cloth_allocator *allocator);

/* Free a tree and leave it empty. Accepts an empty tree. */
CLOTH_API void cloth_bvh_free(cloth_bvh *bvh);

/* Recompute every box from new positions x (and x1, or NULL for boxes that are not swept),
   arrays of the vertex_count given to the build; the splits stay. O(n), no allocation; also
   updates bvh->cost. Returns CLOTH_ERROR_INVALID_ARGUMENT (x NULL with vertices, or a
   thickness below 0 or not finite) or CLOTH_ERROR_NOT_FINITE (a NaN or infinite coordinate)
   and leaves the tree as it was. */
CLOTH_API cloth_result cloth_bvh_refit(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1);

/* Build the splits again for positions x (and x1) with the tree's memory: the result equals a
   fresh cloth_bvh_build with bvh->def, without allocating. Resets the quality to 1. Errors as
   for cloth_bvh_refit (and CLOTH_ERROR_INVALID_ARGUMENT for a def value out of range),
   leaving the tree as it was. */
CLOTH_API cloth_result cloth_bvh_rebuild(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1);

/* How much looser the tree has become since it was built: bvh->cost / bvh->build_cost, where
   cost is the SAH cost over the triangles' own area,
       (sum over internal nodes of area(node) + sum over leaves of count * area(leaf))
       / (sum over triangles of area(triangle box)),
   area being a box's surface area: how much larger the nodes are than what they hold. It is 1
   right after a build or rebuild and 1 for an empty tree. A connected mesh keeps its
   neighbours close whatever it does, and so does its tree; on a 128 x 128 grid, stretched by
   10%: 1.03, turned 45 degrees: 1.21, folded in half: 0.98, crumpled into a ball: 1.07, its
   vertices scattered at random: 0.54 (the triangles themselves grow; no tree is tighter).
   Triangles that drift apart from their old neighbours make it grow: 60,000 separate small
   triangles moved 5 cm at random: 8.8, sent anywhere in the unit cube: 186. */
CLOTH_API cloth_real cloth_bvh_quality(const cloth_bvh *bvh);

/* The rebuild rule: 1 when cloth_bvh_quality(bvh) > bvh->def.rebuild_ratio, else 0. A rebuild
   costs about four self traversals. In the cases listed under cloth_bvh_quality a rebuilt
   tree's self traversal was no faster (within 7%, the noise of the measurement) wherever the
   quality stayed below 2, and 30 to 2000 times faster where it passed 8; hence the default
   ratio 2. */
CLOTH_API int cloth_bvh_needs_rebuild(const cloth_bvh *bvh);

/* Report every pair of triangles a < b of the tree whose boxes overlap and that share no
   vertex (adjacent triangles touch by construction and are left out), each pair once.
   Returns 0 after visiting all, or the first non-zero value fn returned. */
CLOTH_API int cloth_bvh_self_pairs(const cloth_bvh *bvh, cloth_bvh_pair_fn fn, void *user);

/* Report every pair (a of tree_a, b of tree_b) whose boxes overlap, each once: a cloth
   against an obstacle, one piece against another. Shared vertices are not looked at (the two
   trees may index different vertex arrays). Returns as cloth_bvh_self_pairs. */
CLOTH_API int cloth_bvh_pairs(const cloth_bvh *tree_a, const cloth_bvh *tree_b, cloth_bvh_pair_fn fn, void *user);

/* Report every triangle whose box overlaps the box [lo, hi] (for example a vertex's swept
   box against an obstacle). Returns as cloth_bvh_self_pairs. */
CLOTH_API int cloth_bvh_query_box(const cloth_bvh *bvh, const cloth_real lo[3], const cloth_real hi[3],
                                  cloth_bvh_triangle_fn fn, void *user);

#ifdef __cplusplus
}
#endif

/* ===================================================================================== */
/* ccd: proximity and continuous collision detection for vertex-face and edge-edge pairs  */
/*      needs: core, math                                                                 */
/* ===================================================================================== */
/*
   Proximity: the closest points of a point and a triangle, and of two segments, with their
   distance. Every input is handled, degenerate ones included (a triangle with collinear or
   coincident corners, parallel segments, zero-length segments); the weights or parameters
   returned always name a point of the primitive, and the distance returned is the distance
   between those points. Computed in double whatever cloth_real is. A non-finite input gives a
   NaN distance.

   Continuous collision detection (CCD): the four vertices of a pair move linearly from their
   positions at t = 0 to those at t = 1. With F(t,u,v) the vector from the point of one primitive
   to the point of the other,

       vertex-face:  F = p(t) - ((1-u-v) f0(t) + u f1(t) + v f2(t)),   u, v >= 0, u + v <= 1
       edge-edge:    F = (a0(t) + u (a1(t) - a0(t))) - (b0(t) + v (b1(t) - b0(t))),  u, v in [0,1]

   the pair collides when |F_k| <= d on every axis k at some (t,u,v) with t in [0,1], where d is
   the minimum separation (0: the primitives touch). The test is the inclusion-based root finder
   of Wang et al. 2021 ("A Large Scale Benchmark and an Inclusion-Based Algorithm for Continuous
   Collision Detection", ACM TOG 40(5)): F is multilinear, so its range over a box of (t,u,v) lies
   between the smallest and the largest of its eight corner values; boxes whose range, widened by
   a proven bound on the floating-point error of the corner values, misses [-d, d] on some axis
   hold no collision and are dropped; the others are bisected, earlier times first, until one is
   small enough to be accepted as a contact; then earlier contacts are searched for, down to a
   time resolution of delta over three times the largest change of F along t over the step.
   Computed in double whatever cloth_real is; a query allocates nothing and uses about 35 KB of
   stack.

   What is guaranteed: no false negatives. When a collision exists (in exact arithmetic, for the
   positions exactly as given), may_collide is 1 and toi is at most the earliest time of contact;
   this holds for every finite input up to 1e300 in magnitude, for CLOTH_REAL float or double,
   whether or not the compiler contracts a*b+c into fused multiply-adds (the error bound allows
   for either). It needs IEEE-754 double arithmetic without value-changing optimisations: do not
   compile cloth.h with -ffast-math (or -Ofast, /fp:fast), which lets the compiler reorder sums.
   What is not: a report may be a near miss. A box is accepted as a contact once F varies by at
   most the tolerance delta over it, so a reported pair came within about d + delta per axis
   (sqrt(3) (d + delta) in distance) of touching, unless the check budget ran out first, in which
   case may_collide is 1 with the earliest time that could not be ruled out. Since the test is
   per axis, a minimum separation d also reports pairs up to sqrt(3) d apart. toi is usually
   within the time resolution below the first contact, but it is only promised to be no later:
   where proving that no earlier contact exists is expensive (contacts along a curve at one
   time, large separations) the search stops at its budget with a looser, still safe, toi.
*/
#ifdef __cplusplus
extern "C" {
#endif

/* ---- proximity --------------------------------------------------------------------- */

/* Distance from point p to the triangle (f0, f1, f2), all regions (face, edges, corners) and
   degenerate triangles included. weights, if not NULL, receives the barycentric weights of the
   closest point c = weights[0] f0 + weights[1] f1 + weights[2] f2 (each >= 0, summing to 1). */
CLOTH_API cloth_real cloth_distance_vertex_face(const cloth_real p[3], const cloth_real f0[3], const cloth_real f1[3],
                                                const cloth_real f2[3], cloth_real weights[3]);

/* Distance between the segments a0-a1 and b0-b1, parallel and zero-length segments included.
   params, if not NULL, receives s and t in [0,1] of closest points a0 + s (a1 - a0) and
   b0 + t (b1 - b0). Where the closest points are not unique (parallel overlapping segments),
   one pair of them is returned. */
CLOTH_API cloth_real cloth_distance_edge_edge(const cloth_real a0[3], const cloth_real a1[3], const cloth_real b0[3],
                                              const cloth_real b1[3], cloth_real params[2]);

/* ---- continuous collision detection ------------------------------------------------ */

/* Options of a CCD query; make them with cloth_ccd_default_options() and change fields. */
typedef struct cloth_ccd_options {
    cloth_real tolerance;          /* delta > 0 (m): a box is accepted once F varies by at most
                                      this over it; smaller is tighter and slower. 1e-6 */
    int64_t max_checks;            /* box checks allowed (>= 1) before answering "may collide"
                                      with the earliest time not yet ruled out. 1000000 */
    int64_t refine_checks;         /* once a contact is found, at most this many more checks
                                      (>= 0, within max_checks) go into tightening toi; 0 answers
                                      with the first contact found, toi still a lower bound.
                                      62500 */
    cloth_real minimum_separation; /* d >= 0 (m): report the pair when it comes within d per
                                      axis. 0 */
    int32_t internal_cookie;       /* set by cloth_ccd_default_options; catches an uninitialised struct */
} cloth_ccd_options;

/* The default options (tolerance 1e-6, max_checks 1e6, refine_checks 62500, minimum_separation 0). */
CLOTH_API cloth_ccd_options cloth_ccd_default_options(void);

/* The answer of a CCD query. */
typedef struct cloth_ccd_report {
    int may_collide;      /* 1: a collision (within the minimum separation) may happen in [0,1];
                             0: it certainly does not */
    cloth_real toi;       /* time of impact, a lower bound on the earliest time of contact,
                             in [0,1]; 1 when may_collide is 0 */
    int64_t checks;       /* boxes checked */
    int budget_exhausted; /* 1 when max_checks ran out (may_collide is then 1 and toi the
                             earliest time not yet ruled out); reaching refine_checks after a
                             contact is not counted */
} cloth_ccd_report;

/* Vertex p against triangle (f0, f1, f2), counter-clockwise or not, each moving linearly from
   its position at t = 0 to its position at t = 1 (argument order: the four start positions,
   then the four end positions). options may be NULL for the defaults. Returns CLOTH_SUCCESS;
   CLOTH_ERROR_NOT_FINITE for a NaN or infinite coordinate; CLOTH_ERROR_INVALID_ARGUMENT for
   options out of range or a coordinate beyond 1e300 in magnitude. On an error the report says
   may_collide = 1, toi = 0, so that a caller that only reads the report stays safe. */
CLOTH_API cloth_result cloth_ccd_vertex_face(const cloth_real p_t0[3], const cloth_real f0_t0[3], const cloth_real f1_t0[3],
                                             const cloth_real f2_t0[3], const cloth_real p_t1[3], const cloth_real f0_t1[3],
                                             const cloth_real f1_t1[3], const cloth_real f2_t1[3],
                                             const cloth_ccd_options *options, cloth_ccd_report *report);

/* Edge a0-a1 against edge b0-b1, moving linearly, in the same form as cloth_ccd_vertex_face. */
CLOTH_API cloth_result cloth_ccd_edge_edge(const cloth_real a0_t0[3], const cloth_real a1_t0[3], const cloth_real b0_t0[3],
                                           const cloth_real b1_t0[3], const cloth_real a0_t1[3], const cloth_real a1_t1[3],
                                           const cloth_real b0_t1[3], const cloth_real b1_t1[3],
                                           const cloth_ccd_options *options, cloth_ccd_report *report);

#ifdef __cplusplus
}
#endif


/* ===================================================================================== */
/* qp: the exact projection of one impact zone (Harmon et al. 2008, as used by ARCSim     */
/*     and DiffSim) and its backward pass (the QP gradients of DiffSim)                   */
/*     needs: core                                                                        */
/* ===================================================================================== */
/*
   THE PROBLEM. An impact zone is a set of vertices with positions x (3 per vertex) and impacts
   between them. cloth_qp_project finds the positions z closest to x in the mass-weighted norm
   that satisfy every impact:

       minimize    1/2 (z - x)^T W (z - x)
       subject to  sum_k a_jk n_j . z_(v_jk)  >=  t_j        for every row j

   W is diagonal with one weight w_i per vertex (on its three coordinates); the problem takes
   the inverse weights m_i = 1/w_i, so that m_i = 0 makes a vertex immovable: it is a constant,
   not a variable, and z_i = x_i exactly (obstacles, pinned vertices). ALGORITHMS.md uses
   W_i = m_i mean(1/m) over the zone (masses m_i); any positive scale of W gives the same z.
   Row j (a cloth_qp_row) names up to four vertices v_jk with scalar weights a_jk, a normal n_j
   and a thickness t_j:
       vertex-face  (vertex p, face f0 f1 f2, barycentric b):  a = [1, -b0, -b1, -b2]
       edge-edge    (p = a0 p0 + a1 p1, q = b0 q0 + b1 q1):     a = [a0, a1, -b0, -b1]
   with n_j the unit normal oriented from the second primitive towards the first, so that the
   row says "the first primitive stays at least t_j in front of the second along n_j". In the
   notation of ALGORITHMS.md section 3 the constraints are G z + h <= 0 with
       G_j = -[a_j0 n_j^T, a_j1 n_j^T, ...] (at the columns of v_j0, v_j1, ...),  h_j = t_j,
   and g_j(z) = G_j z + h_j = t_j - sum_k a_jk n_j . z_(v_jk) is a row's violation (> 0
   violated, < 0 slack). The normal is used as given: a non-unit normal scales the row.

   The solution satisfies the KKT conditions with multipliers lambda_j >= 0 (impulses, in
   weight x length units):
       z_i = x_i + m_i sum_j lambda_j a_jk n_j   (sum over the rows j and slots k with v_jk = i)
       g_j(z) <= 0,   lambda_j >= 0,   lambda_j g_j(z) = 0.
   z is unique; lambda is unique when the rows that meet their bound are linearly independent
   (in the metric W^-1).

   THE ALGORITHM. The dual active-set method of Goldfarb and Idnani (Math. Programming 27,
   1983) on the primal, in the scaled variables y = sqrt(W) (z - x) of the movable vertices,
   where the problem becomes the minimum-norm point of a polyhedron: minimize |y|^2 / 2 subject
   to A y >= b (A_j = -G_j sqrt(W)^-1 over the movable vertices, b_j = g_j(x)). It starts from
   the unconstrained minimum z = x and repeatedly takes the most violated row (violation
   divided by |A_j|), adds it to a working set S of rows held as equalities, and drops working
   rows whose multiplier would turn negative on the way. It keeps the Cholesky factor R of
   A_S A_S^T, which is the R of the QR factorization A_S^T = Q R (Q is never formed): one new
   column per addition, from the part of the new row orthogonal to the working rows (projected
   twice, so that the rounding of the first projection does not stay), and Givens rotations
   per deletion. Rows are sparse (at most 4 vertices), so a step costs O(q^2 + m + n) for a
   working set of q rows, and no dense matrix of the zone's size is formed.
   When no row is violated any more, R is factored afresh (unless additions alone made it,
   which gives the same factor) and the working rows are solved as equalities once more,
   with iterative refinement that accumulates y itself (not only the multipliers), and z is
   formed from that y: the answer is the exact solution to rounding,
   not the end of an iteration with a tolerance, and stays accurate when nearly dependent rows
   make the multipliers much larger than the displacement. A working row whose multiplier
   comes out negative there leaves the working set and the method goes on (at most 3 such
   rounds). Before returning, the solution is checked: every row met and every row with
   lambda_j > 0 tight, to kkt_tolerance (1e-9) times the size of its terms. Random zones, well
   and badly conditioned, meet this to about 1e-15 in the tests. The method is finite (each
   addition strictly increases |y|; iterations are capped in any case).

   DEGENERACY. A row is linearly dependent on the working set when its projection off the
   working rows keeps at most dependency_tolerance of its length (duplicate rows, more than
   three rows on one vertex, parallel normals on a vertex pair, or a working set that already
   spans every movable coordinate). Such a row is never added; instead (Goldfarb-Idnani's pure
   dual step) a working row is dropped in exchange when that keeps the multipliers
   non-negative, and the zone is infeasible when none can be: the row contradicts the working
   rows (a Farkas certificate). So the working set stays linearly independent and the
   multipliers are supported on it: among equal rows the one taken first carries the whole
   multiplier and the others get 0. Rows over immovable vertices only (or with zero weights or
   a zero normal) are constants: met, they never act; violated, the zone is infeasible.

   CONTINUING. cloth_qp_project_more projects a problem that grew from the last one the
   workspace solved: the same rows first (bit for bit), more rows after them, the same
   vertices with the same inverse weights, perhaps more vertices; the positions x may all have
   moved. R factors A_S A_S^T, which depends on the rows and the weights alone, so the last
   working set and its R hold for the new problem: the multipliers and y are solved again for
   the new b (as in the polish), working rows whose multiplier comes out negative leave, and
   the method goes on from there, adding only what is still violated. The answer is the
   exact solution, as from the start (the same z to rounding), at O(q^2) per row that joins or
   leaves instead of a factor built again row by row. The workspace keeps the solution for
   this in its block; a call that fails, a cloth_qp_backward, or a problem that does not extend
   the last one (checked: weights and rows compared) makes the next call start afresh.

   RESULT. active[j] says how row j stands at z (cloth_qp_row_state): CLOTH_QP_ACTIVE rows form
   a maximal linearly independent set of the tight rows, namely the working set (which carries
   all of lambda) extended, in row order, by tight rows independent of it (lambda_j = 0);
   CLOTH_QP_TIGHT rows meet their bound too but depend on the active rows (lambda_j = 0);
   CLOTH_QP_INACTIVE rows have slack (lambda_j = 0). "Tight" means
   g_j(z) >= -kkt_tolerance scale_j with scale_j = |t_j| + sum_k |a_jk| |n_j| |z_(v_jk)|, the
   size of the terms whose rounding g_j suffers. The active rows are those the backward pass
   treats as equalities, which is the choice of DiffSim (all rows with |g_j| below a
   tolerance, dependent columns dropped).

   ERRORS. Infeasible zones (a violated row over immovable vertices only, contradictory rows)
   return CLOTH_ERROR_COLLISION_UNRESOLVED, as do zones whose solution fails the final check
   (rows so nearly contradictory that the solution is out of reach of double precision; such
   solutions move vertices by thousands of times the zone's size) and the iteration cap (never
   expected). On every error z = x, lambda = 0 and active = CLOTH_QP_INACTIVE, so a caller can
   keep going with the positions it had.

   PRECISION. Everything is computed in double whatever cloth_real is; with CLOTH_REAL float
   the results are rounded to float at the end, so the returned z meets the rows to float
   rounding (about 1e-7 of the coordinates), not to double rounding, and the final check and
   the row states are decided on the double solution. Since float data is itself only
   accurate to about 1e-7, the default dependency_tolerance is 1e-5 for float (1e-10 for
   double). Results are deterministic: the same inputs give bit-identical outputs (fixed loop
   orders, ties broken by the lower row index, no threads).

   MEMORY. A cloth_qp_workspace holds all scratch memory in one block of
   32 + 112 n + 156 m + 44 q + 8 q^2 bytes (n vertices, m rows, q = min(m, 3 movable vertices)); it
   grows when a problem exceeds every problem before it and allocates nothing otherwise.
   cloth_qp_project_more grows it with room to spare (n and m by a quarter, R's rows by half
   when the working set fills them), keeping the solution it goes on from.
   Passing NULL for the workspace makes a temporary one with the default allocator. One
   workspace serves one call at a time.

   BACKWARD. cloth_qp_backward maps dL/dz (and optionally dL/dlambda) at a solution to the
   gradients with respect to x, the inverse weights, the normals, the row weights and the
   thicknesses, by differentiating the KKT system of the active rows (see its declaration).
*/
#ifdef __cplusplus
extern "C" {
#endif

/* One impact: the row sum_k weight[k] normal . z_(vertex[k]) >= thickness. */
typedef struct cloth_qp_row {
    int32_t vertex[4];     /* vertices 0..vertex_count-1; -1 marks an unused slot (its weight
                              is ignored); a vertex named twice has its weights added */
    cloth_real weight[4];  /* a_jk: vertex-face [1, -b0, -b1, -b2], edge-edge [a0, a1, -b0, -b1] */
    cloth_real normal[3];  /* n_j, unit in normal use (used as given) */
    cloth_real thickness;  /* t_j (m): the separation the row asks for along the normal */
} cloth_qp_row;

/* One impact zone. The arrays are the caller's and are only read. */
typedef struct cloth_qp_problem {
    int32_t vertex_count;              /* n >= 0 */
    const cloth_real *x;               /* 3 n positions before projection */
    const cloth_real *inverse_weight;  /* n values m_i = 1/w_i >= 0, 0 = immovable; NULL = all 1 */
    const cloth_qp_row *rows;          /* row_count rows */
    int32_t row_count;                 /* m >= 0 */
} cloth_qp_problem;

/* How a row stands at the solution: the values cloth_qp_project writes to active[]. */
typedef enum cloth_qp_row_state {
    CLOTH_QP_INACTIVE = 0, /* slack: g_j(z) < -kkt_tolerance scale_j; lambda_j = 0 */
    CLOTH_QP_ACTIVE = 1,   /* tight and part of a linearly independent set that carries the
                              multipliers; lambda_j >= 0; an equality for the backward pass */
    CLOTH_QP_TIGHT = 2     /* tight but linearly dependent on the active rows (or a constant
                              row over immovable vertices only); lambda_j = 0 */
} cloth_qp_row_state;

/* Options of cloth_qp_project and cloth_qp_backward; make them with cloth_qp_default_options()
   and change fields. All tolerances are relative. */
typedef struct cloth_qp_options {
    cloth_real feasibility_tolerance; /* > 0: while it iterates, the solver counts row j as
                                         violated when g_j exceeds this times the size of its
                                         terms (|t_j|, |a_jk| |n_j| |x_v| and the terms of its
                                         change since x), the size of its rounding. 1e-12 */
    cloth_real kkt_tolerance;         /* > 0: the accuracy a solution is checked to before it
                                         is returned: every row met, g_j(z) <= this x scale_j,
                                         and every row with lambda_j > 0 tight,
                                         |g_j(z)| <= this x scale_j; also the band in which a
                                         row counts as tight (see RESULT above). 1e-9 */
    cloth_real dependency_tolerance;  /* in (0, 1): a row whose projection off the working rows
                                         (in the metric W^-1) keeps at most this fraction of its
                                         length counts as linearly dependent on them. 1e-10
                                         (1e-5 when cloth_real is float) */
    int32_t max_iterations;           /* >= 0: cap on additions plus deletions of working rows;
                                         0 = automatic, 10 (m + 3 n) + 100 */
    int32_t internal_cookie;          /* set by cloth_qp_default_options; catches an
                                         uninitialised struct */
} cloth_qp_options;

/* The default options (feasibility 1e-12, kkt 1e-9, dependency 1e-10 or 1e-5 for float,
   automatic iteration cap). */
CLOTH_API cloth_qp_options cloth_qp_default_options(void);

/* What a projection did. The residuals are measured on the returned (cloth_real) z and lambda,
   in double, each relative to the size of its terms; all are 0 for an empty problem. */
typedef struct cloth_qp_stats {
    int32_t iterations;          /* working-set additions plus deletions */
    int32_t active_count;        /* rows returned CLOTH_QP_ACTIVE (-1 when active is NULL) */
    int32_t tight_count;         /* rows returned CLOTH_QP_TIGHT (-1 when active is NULL) */
    cloth_real objective;        /* 1/2 sum over movable i of |z_i - x_i|^2 / m_i */
    cloth_real stationarity;     /* max_i |z_i - x_i - m_i sum_j lambda_j a_jk n_j| over the
                                    coordinates of movable vertices, divided by the largest
                                    |z_i - x_i| or m_i sum_j |lambda_j a_jk n_j| */
    cloth_real primal_violation; /* max_j max(g_j(z), 0) / scale_j (0 when feasible) */
    cloth_real complementarity;  /* max over rows with lambda_j > 0 of |g_j(z)| / scale_j */
    int32_t continued;           /* 1 when cloth_qp_project_more went on from the last
                                    solution, 0 when it solved from the start */
} cloth_qp_stats;

/* Scratch memory of cloth_qp_project and cloth_qp_backward, reused from call to call. An
   all-zero struct is a valid empty workspace with the default allocator. */
typedef struct cloth_qp_workspace {
    void *memory;              /* one block, carved per call */
    size_t capacity;           /* its size in bytes */
    cloth_allocator allocator; /* how it is allocated and freed */
} cloth_qp_workspace;

/* Make a workspace that serves problems of up to vertex_count vertices and row_count rows
   without allocating (larger problems make it grow). allocator NULL means the default.
   Fails with CLOTH_ERROR_INVALID_ARGUMENT for a negative count, CLOTH_ERROR_SIZE_OVERFLOW or
   CLOTH_ERROR_OUT_OF_MEMORY, and then leaves the workspace empty (but keeps the allocator). */
CLOTH_API cloth_result cloth_qp_workspace_create(cloth_qp_workspace *workspace, int32_t vertex_count,
                                                 int32_t row_count, const cloth_allocator *allocator);
/* Free a workspace's memory and leave it empty (its allocator is kept, so it may be used
   again). Accepts an empty workspace. */
CLOTH_API void cloth_qp_workspace_free(cloth_qp_workspace *workspace);

/* Project the zone: write z (3 vertex_count reals), the multipliers lambda (row_count reals,
   >= 0) and the row states active (row_count values of cloth_qp_row_state). z may be the same
   array as problem->x (projection in place). lambda, active, stats, options (defaults) and
   workspace (a temporary one) may be NULL. With active NULL the row states are not formed,
   which skips factoring the tight rows outside the working set (on zones of thousands of rows
   that is more work than the solve; z and lambda are the same), and stats->active_count and
   tight_count are -1. Returns
     CLOTH_SUCCESS                     z is the solution (see the top of this module);
     CLOTH_ERROR_COLLISION_UNRESOLVED  the rows cannot all be met, or the solution failed the
                                       final check (see ERRORS above), or the iteration cap;
     CLOTH_ERROR_NOT_FINITE            a NaN or infinity in x, the inverse weights, or a used
                                       slot's weight, a normal or a thickness of a row (checked
                                       first), or an overflow during the solve or of a result
                                       stored as cloth_real;
     CLOTH_ERROR_INDEX_OUT_OF_RANGE    a row names a vertex outside -1..vertex_count-1;
     CLOTH_ERROR_INVALID_ARGUMENT      a negative inverse weight or count, or bad options;
     CLOTH_ERROR_OUT_OF_MEMORY, CLOTH_ERROR_SIZE_OVERFLOW  the workspace could not grow.
   On every error z = x, lambda = 0, active = CLOTH_QP_INACTIVE (when the counts are valid) and
   stats says how far the solver got. A NULL problem, x (with vertex_count > 0), rows (with
   row_count > 0) or z trips CLOTH_ASSERT. */
CLOTH_API cloth_result cloth_qp_project(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                        const cloth_qp_options *options, cloth_real *z, cloth_real *lambda,
                                        int32_t *active, cloth_qp_stats *stats);

/* cloth_qp_project for a problem that grew: when the workspace holds the solution of its
   last successful cloth_qp_project or cloth_qp_project_more, and this problem extends that
   problem (its first vertices have the same inverse weights and its first rows are the
   earlier ones, bit for bit; more vertices and rows may follow; the positions x may all
   differ), the method goes on from that solution's working set and factor, which depend on
   the rows and weights alone: the multipliers are solved again for the new x, rows whose
   multiplier turns negative leave, and only what is still violated joins (see CONTINUING
   above). Otherwise it solves from the start, as cloth_qp_project. Either way it returns what
   cloth_qp_project would (the same z and the same states to rounding; lambda too where the
   active rows are independent), with stats->continued saying which way it went. A zone that
   gathers rows round after round then pays for the rows that join or leave, not for a factor
   built again. cloth_qp_backward, or any failed call, on the workspace in between makes the
   next call start afresh. Errors as cloth_qp_project. */
CLOTH_API cloth_result cloth_qp_project_more(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                             const cloth_qp_options *options, cloth_real *z, cloth_real *lambda,
                                             int32_t *active, cloth_qp_stats *stats);

/* Where cloth_qp_backward writes the gradients of a loss L. Every pointer may be NULL (that
   gradient is not computed); the arrays are overwritten, not accumulated into. */
typedef struct cloth_qp_gradient {
    cloth_real *x;              /* 3 n: dL/dx */
    cloth_real *inverse_weight; /* n: dL/dm_i (for an immovable vertex, the one-sided
                                   derivative towards m_i > 0) */
    cloth_real *normal;         /* 3 m: dL/dn_j, the normal taken as a free 3-vector */
    cloth_real *weight;         /* 4 m: dL/da_jk (0 in unused slots) */
    cloth_real *thickness;      /* m: dL/dt_j */
} cloth_qp_gradient;

/* The backward pass of cloth_qp_project: given the problem, the z, lambda and active it
   returned, and dL/dz (3 n reals, required) and dL/dlambda (m reals, or NULL for 0), write the
   gradients asked for in *gradient. It differentiates the KKT system with the CLOTH_QP_ACTIVE
   rows as equalities (the others contribute nothing):
       z - x + M G_A^T lambda_A = 0,   G_A z + h_A = 0       (M = W^-1)
   whose adjoint is
       v = (G_A M G_A^T)^-1 (G_A M dL/dz - dL/dlambda_A),   p = dL/dz - G_A^T v,
       dL/dx = p,   dL/dh_A = -v,   dL/dG_(j,i) = -m_i lambda_j p_i - v_j z_i,
       dL/dm_i = -p_i . (G_A^T lambda)_i,
   and dL/dG flows on into the normals and weights through G_(j,v) = -a_jv n_j. This is the
   formula of ALGORITHMS.md section 3 (d_z = M p, D(lambda) d_lambda = v) written without
   D(lambda)^-1, so that rows with lambda_j = 0 are handled, and with immovable vertices
   included (dL/dx_i = dL/dz_i - (G_A^T v)_i for them too). G_A M G_A^T = R^T R is factored
   from the sparse rows as in the forward pass (the R of sqrt(W)^-1 G_A^T = Q R), and an active
   row dependent on the earlier ones (projection below dependency_tolerance, the |R_kk| test of
   DiffSim) is dropped from the equalities (v_j = 0). The gradient is exact where the active
   set is locally constant (strict complementarity); at a weakly active row it is the one-sided
   gradient that keeps the row tight. Returns CLOTH_SUCCESS, CLOTH_ERROR_NOT_FINITE (also for a
   non-finite z, lambda, dL/dz or dL/dlambda), CLOTH_ERROR_INDEX_OUT_OF_RANGE,
   CLOTH_ERROR_INVALID_ARGUMENT (as cloth_qp_project, or an active[] value outside
   cloth_qp_row_state), CLOTH_ERROR_OUT_OF_MEMORY or CLOTH_ERROR_SIZE_OVERFLOW; on an error the
   requested gradients are set to 0. NULL problem, z, lambda, active, grad_z or gradient trips
   CLOTH_ASSERT. */
CLOTH_API cloth_result cloth_qp_backward(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                         const cloth_qp_options *options, const cloth_real *z,
                                         const cloth_real *lambda, const int32_t *active, const cloth_real *grad_z,
                                         const cloth_real *grad_lambda, const cloth_qp_gradient *gradient);

#ifdef __cplusplus
}
#endif


/* ===================================================================================== */
/* contact: the collide phase of a step -- analytic and mesh obstacles, cloth self and    */
/*          piece-piece collisions by CCD with impact zones, and friction                 */
/*          needs: core, math, mesh (topology), bvh, ccd, qp                              */
/* ===================================================================================== */
/*
   WHAT IT DOES. The integrator proposes new positions x1 for the cloth from the positions x0
   at the start of the step. cloth_contact_resolve changes x1 so that

     * every cloth vertex ends outside every obstacle by the obstacle's thickness, and its path
       was checked continuously against it, so that no obstacle however fast tunnels through it;
     * the motion x0 -> x1 (every vertex on a straight line) is free of collisions between the
       cloth and itself, between pieces, and between the cloth and mesh obstacles: no
       vertex-face or edge-edge pair comes within the detection separation at any time of the
       step (see SEPARATIONS);

   or returns CLOTH_ERROR_COLLISION_UNRESOLVED and leaves x1 exactly as it came in, so that the
   integrator can restore its state (or retry with a smaller step). It also writes velocities
   for the end of the step with inelastic contact and Coulomb friction applied (see VELOCITIES).
   It works on plain arrays, x0[3n], x1[3n] and inverse_mass[n], for one cloth made of any
   number of pieces (all pieces' vertices in one array, triangles tagged with a piece id).

   SETUP AND USE

       cloth_contact_def def = cloth_default_contact_def();
       def.vertex_count = n; def.tri = tri; def.triangle_count = m;
       def.triangle_piece = piece_of_triangle;        (NULL: one piece)
       def.self_collision = 1;                        (within a piece; default 0)
       def.piece_collision = 1;                       (between pieces; default 0)
       cloth_contact *contact;
       cloth_contact_create(&contact, &def);          copies the triangles, builds topology

       cloth_obstacle_def od = cloth_default_obstacle_def();
       od.shape = CLOTH_OBSTACLE_SPHERE; od.radius = 0.3;
       cloth_contact_add_obstacle(contact, &od, &sphere);

       each step, after the implicit solve:
         cloth_contact_move_obstacle(contact, sphere, &pose_start, &pose_end);  kinematic ones
         r = cloth_contact_resolve(contact, x0, x1, inverse_mass, h, v, &stats);
         if (r == CLOTH_SUCCESS) { x = x1; v is the new velocity }
         else                    restore the step (x1 is unchanged)

       cloth_contact_destroy(contact);

   The first resolve builds the bounding volume hierarchies and grows the scratch memory; a
   scene whose number of contacts stops growing stops allocating (every buffer grows
   geometrically and is kept).

   ALGORITHM. One resolve runs rounds of
     1. analytic obstacles (plane, sphere, capsule, box): each cloth vertex against each
        obstacle in the obstacle's frame, continuously (ANALYTIC OBSTACLES below), with a
        response and Coulomb friction that move the vertex's end position;
     2. continuous collision detection: candidate triangle pairs from bounding volume
        hierarchies over the swept triangles (x0 -> x1, grown by half the detection
        separation), for the cloth against itself, pieces against each other and the cloth
        against mesh obstacles, plus the triangle pairs that share a vertex (which the tree
        skips; their non-adjacent primitives can still collide in a tight fold); then every
        vertex-face and edge-edge pair of primitives that share no vertex, each once per
        round (OWNERSHIP below): a box test, a Lipschitz bound (the distance of the pair is
        L-Lipschitz in t, L the largest relative displacement of its vertices, so it stays
        above (D(0) + D(1) - L) / 2) that proves most pairs apart, and the CCD
        (cloth_ccd_vertex_face / cloth_ccd_edge_edge, which never miss a collision) on the rest;
     3. impact zones (Harmon, Vouga, Tamstorf, Grinspun, "Robust treatment of simultaneous
        collisions", SIGGRAPH 2008; as in ARCSim): each impact becomes a row of a QP (IMPACT
        ROWS); the rows of a round are kept earliest first, at most def.impacts_per_vertex on
        a movable vertex (1 is Harmon's "independent impacts"; the others are found again
        next round if they still collide); impacts that share movable vertices merge into
        zones (union-find; immovable vertices do not merge zones); zones persist and grow over
        the rounds of a step, and every zone that received a row is projected exactly by
        cloth_qp_project with all the rows it ever received;
   until a round finds nothing (success). A round tests again only the primitive pairs with a
   vertex that moved or collided in the round before (the others are unchanged and were
   clean). When def.max_rounds projection rounds do not converge, a zone's QP is infeasible,
   or a round finds only stale impacts (IMPACT ROWS), a fail-safe follows (Bridson, Fedkiw,
   Anderson, "Robust treatment of collisions, contact and friction for cloth animation",
   SIGGRAPH 2002): every zone that still collides moves rigidly, translating with the mass
   weighted mean of its vertices' proposed displacements (x1 as it came in, minus x0), and a
   zone that still collides after that (or one that holds pinned vertices, obstacle vertices
   or analytic contacts, which a translation cannot respect) stops: its vertices stay at x0,
   which is collision-free. When even that fails (def.max_rigid_rounds, or a collision whose
   vertices are all immovable or stopped) the resolve returns CLOTH_ERROR_COLLISION_UNRESOLVED.
   In step 2 the pairs that need a CCD query are recorded in the order the traversals meet
   them, the queries run (on the world's threads when its def has them: world def `threads`),
   and the impacts are added in that order, so the result does not depend on the threads.

   OWNERSHIP. A primitive pair is met through several triangle pairs; it is tested from one.
   A vertex-face pair (v, B) belongs to the first triangle around v (in cloth_topology's
   vertex_face order) that shares no vertex with B: the tree reports that triangle with B
   whenever v can come near B, since every triangle around v holds v's swept path in its box.
   When every triangle around v shares a vertex with B, the pair belongs to (the first
   triangle around v, B) in the enumeration of adjacent triangles. An edge-edge pair belongs
   likewise to the first pair of faces of its two edges (lower edge index first) that share no
   vertex, or, when all share one, to the first pair. Between the cloth and a mesh obstacle
   (no adjacency) the first triangle around a vertex and the first face of an edge own them.
   Only pairs of triangles whose pieces are enabled count (self_collision, piece_collision).
   Few adjacent pairs own anything (along borders: 1,431 of 41,000 on a 64 x 64 grid), so
   cloth_contact_create lists those with the primitive pairs each owns (topology and enabled
   pieces never change), and the rounds walk that list.

   IMPACT ROWS. An impact found by CCD at time toi gets its weights from the closest points of
   the pair at toi (cloth_distance_vertex_face / cloth_distance_edge_edge): vertex-face
   a = [1, -b0, -b1, -b2], edge-edge a = [1-s, s, -(1-t), -t]. Its normal is the direction of
   the closest points at toi (the face normal, or the edges' cross product, when they are too
   close to give a direction), oriented by the configuration at t = 0, so that the first
   primitive was in front of the second along it at the start of the step (by the relative
   velocity when they were level). Along n the row's two material points are apart by s0 at
   t = 0 and by at least the thickness at t = 1 once the row holds, so by min(s0, thickness)
   all along the straight motion; when s0 < 2 d (the closest points at toi were apart
   sideways, as for nearly parallel edges) the normal is the direction between the material
   points at t = 0 instead, which makes s0 their full distance. The row asks
   sum_k a_k n . z_k >= thickness at the end of the step. When it holds already at x1 (toi
   was a conservative bound, or the closest points at toi are not the ones that cross), the
   row is made again from the end of the step and from halfway; if none is violated the
   impact is stale: it cannot move anything, is not kept, and does not block other rows.
   Mesh obstacle vertices and pinned cloth vertices are immovable in the QP (inverse weight 0);
   the others have inverse_mass_i / mean(inverse_mass over the zone's movable vertices), that
   is W_i = m_i mean(1/m). A movable zone vertex that touched an analytic obstacle in the step
   gets one more row, n . (z - p) >= 0, that keeps it outside the obstacle's tangent plane at
   the contact (p on the thickness layer, n the outward normal).

   SEPARATIONS. Two distances per contact type: the thickness, which the response restores
   (cloth: def.thickness; obstacles: their own), and the detection separation
   d = def.detection_ratio * thickness (0.25 mm by default), below which CCD reports a pair:
   |F_k| <= d on every axis; the CCD accepts a box once F varies by at most
   tol d (tol = def.ccd_relative_tolerance), so a reported pair came within d (1 + tol) per
   axis, sqrt(3) d (1 + tol) in distance: 0.54 of the thickness with the defaults, so that a
   pair pushed to the thickness is not found again. A pair that starts closer than that
   band (cloth set down too close, or a pair an earlier step left near d) is guarded at half
   its starting per-axis bound, dist0 / (2 sqrt(3) (1 + tol)), so that it is not reported at
   t = 0; and when it ends the step closer than it started it becomes a proximity impact,
   whose row (from its closest points at t = 1) pushes it back to the thickness: close pairs
   cannot creep together over steps. A pair closer than 1e-11 m at x0 cannot be guarded and is
   counted in stats.initially_touching. Before any of this, a candidate pair of triangles is
   dropped when, in the frame that moves with the mean displacement of its six vertices (a
   common translation changes no distance), the two triangles' paths stay apart along one of
   nine axes (x, y, z and the six face diagonals) by more than the larger of the box reach
   d (1 + 2 tol) and the close band (stats.pairs_culled): it could neither be reported nor
   guarded. A cloth that falls or is carried as a whole thus costs no distance or CCD query,
   and neighbours on a flat grid, whose boxes touch, are separated by the diagonals (the
   sphere scene's free fall at 64 x 64: 8 ms of narrow phase per frame down to 3). Two cheap
   tests come before a CCD query: a pair whose distance, which changes by at most L (the
   largest relative displacement of a vertex of one primitive against one of the other),
   cannot come within reach over the step is culled (stats.ccd_culled); a slow pair (L at
   most the thickness) that ends the step within the guard distance is a certain contact, an
   impact at the lower-bound time
   (D(0) - reach) / L without a search (stats.ccd_certain). The queries that remain tighten
   the first contact they find by def.ccd_refine_checks checks at most. So the guarantee for
   cloth-cloth and cloth-mesh pairs is: along the whole motion x0 -> x1, no vertex-face or edge-edge pair of primitives that
   share no vertex comes within d per axis (hence within d in distance) of touching, less for
   pairs that started inside the band. The end state keeps the same separation, so the next
   step starts clean.

   ANALYTIC OBSTACLES. A plane, sphere, capsule or box with an exact signed distance sdf(p) and
   outward normal in its own frame; its pose (rotation and translation) is given at the start
   and at the end of the step, and between them the vertex moves on the straight line from
   p0 = pose_start^-1 x0 to p1 = pose_end^-1 x1 in the obstacle's frame (the relative motion).
   The vertex enters the contact layer when sdf(p(t)) <= thickness. Every shape is convex, so
   f(t) = sdf(p(t)) - thickness is convex in t, and Newton's method from t = 0 never passes
   its first root (the tangent lies below f); a slope >= 0 proves there is none, and a
   1-Lipschitz bound rejects far vertices at once. The iteration (at most 64 steps; capped, it
   answers its last iterate, before any contact) gives the time of entry t_e, the contact
   point p_c = p(t_e) and the normal n_c there. With r = (1 - t_e)(p1 - p0) the motion after
   entry, the response linearizes the surface
     * at the end point (n = n(p1), normal correction delta = thickness - sdf(p1)) when p1 lies
       in the layer on the side where the vertex entered (n(p1) . n_c > 1/2) and the path did
       not pass through the body and out again: resting and sliding contact;
     * at the contact point (n = n_c, delta = thickness - sdf(p_c) - r . n_c) otherwise: fast
       vertices, and any that went through (the projectile);
   nothing is done when delta <= 0 (leaving) or when the path only grazed the layer and ends
   outside it. With r_n = r . n and r_t = r - r_n n:

       p_f = p1 + delta n                                  on the layer (or outside it)
       if |r_t| <= mu_s delta:  p_f -= r_t                 static friction: it sticks
       else                     p_f -= (mu_k delta / |r_t|) r_t   kinetic friction

   (computed as p_c + (r_n + delta) n + keep r_t, so that a vertex that sticks stays exactly
   where it entered). The tangential motion relative to the obstacle after entry loses mu_k
   times the normal correction: a vertex sliding on a plane under gravity (correction h^2 g
   per step) slows by mu_k g per second, and stops once its tangential speed is below
   mu_s g h; on an incline below the friction angle a vertex at rest stays at rest. Friction
   applies at the first response of a vertex to an obstacle in a step; later responses in the
   same step (after a zone moved the vertex) are frictionless. A last check pushes the vertex
   out along the normal while it is within the thickness (curved surfaces), and every vertex
   is checked against every analytic obstacle at the end (to rounding). A pinned vertex
   (inverse_mass 0) that would need a response makes the resolve fail.

   MESH OBSTACLES. A triangle mesh, static, moved rigidly by a pose (start and end of the
   step), or deformed (world vertex positions at the start and end of the step, as from an
   animated OBJ sequence): cloth vertices against its faces, its vertices against cloth faces,
   and cloth edges against its edges, by CCD with the obstacle's thickness and friction; its
   vertices are immovable rows members. Its tree is refitted when it moved.

   PROXY. The vertex tests alone let an obstacle smaller than the cloth's triangles pass between
   their vertices. So a sphere, capsule or box also carries an inner proxy mesh, moved with it
   and met by CCD like a mesh obstacle (with the obstacle's thickness and friction): a sphere an
   icosphere of half its radius (CLOTH__CONTACT_PROXY_SUBDIVISIONS subdivisions, 42 vertices), a
   capsule a capsule mesh of half its radius on the same segment (12 segments, 2 rings), a box
   the box of half its extents (12 triangles). No cloth face or edge passes through that inner
   part. A face may dip into the outer part (an obstacle poking into a coarse face; a flat face
   resting on a curved obstacle dips by its sagitta), which the proxy leaves alone, so resting
   cloth is never touched by it. A plane needs none, and a shape with a zero radius or extent
   gets none.

   VELOCITIES. When v is not NULL it receives, for each vertex, (x1 - x0) / h corrected so that
     * for each analytic contact of the step, the velocity relative to the obstacle's surface
       (in its frame: (p1 - p0) / h) has no approaching component along the normal at the end
       point; the approach removed (dv_n) buys Coulomb friction on the relative tangential
       velocity (stick when within mu_s dv_n, else reduced by mu_k dv_n). This is the impact
       impulse of a vertex that arrived during the step; resting contact has dv_n = 0 and
       gets its friction from the position response above;
     * for each impact row near contact at the end of the step (gap below a tenth of the
       thickness), the relative normal velocity sum_k a_k n . v_k is not negative, and friction
       acts on the relative tangential velocity sum_k a_k v_k, capped by mu times the row's
       normal impulse: what the projections gave it over the step (lambda / (h mean(1/m)),
       the QP's multiplier in N s) plus the velocity correction; four projected Gauss-Seidel
       sweeps over the rows in a fixed order, static (stick) within mu_s, else mu_k.
   Positions are never changed by this velocity pass, so x1 stays collision-free. The
   integrator takes v as the velocity at the end of the step (with backward Euler, instead of
   (x1 - x0) / h); pinned vertices get (x1 - x0) / h.

   WHAT IS APPROXIMATED. The relative motion to a rotating obstacle is the straight line in its
   frame, not the arc. Friction of cloth-cloth and cloth-mesh contacts acts on velocities only
   (not on the positions of the step), and only where the step had an impact. There is no
   general proximity phase (only the proximity rows of pairs that start inside the detection
   band, SEPARATIONS): contacts that rest within the thickness without coming closer than d
   get no friction, and resting layers pushed together by gravity meet again as impacts every
   step, which is costly (a crumpled 32 x 32 cloth on a sphere: thousands of impacts and a few
   hundred ms per step); an integrator with a repulsion penalty in its solve, as ARCSim's,
   would meet far fewer. The fail-safe moves zones by translation only (no rotation). Mass
   weights come from inverse_mass only (a pinned vertex is immovable, never heavy).

   THREADS AND DETERMINISM. One cloth_contact is used by one thread at a time. Everything runs
   in a fixed order: the same inputs give bit-identical outputs.
*/
#ifdef __cplusplus
extern "C" {
#endif

/* A rigid pose: world = rotation * local + translation, rotation row-major (rotation[3*r+c])
   and orthonormal. */
typedef struct cloth_pose {
    cloth_real rotation[9];
    cloth_real translation[3];
} cloth_pose;

/* The identity pose. */
CLOTH_API cloth_pose cloth_pose_identity(void);
/* A pose from a translation and a rotation of `angle` radians about `axis` (need not be unit;
   a zero axis means no rotation). */
CLOTH_API cloth_pose cloth_pose_make(const cloth_real translation[3], const cloth_real axis[3], cloth_real angle);
/* The pose a fraction f of the way from a to b: the translation interpolated linearly, the
   rotation turned by f times the angle of the rotation that takes a's to b's (the shorter way,
   about a fixed axis). f = 0 gives a, f = 1 gives b (to rounding). */
CLOTH_API cloth_pose cloth_pose_interpolate(const cloth_pose *a, const cloth_pose *b, cloth_real f);
/* world = pose * local, and local = pose^-1 * world (out may alias p). */
CLOTH_API void cloth_pose_apply(const cloth_pose *pose, const cloth_real p[3], cloth_real out[3]);
CLOTH_API void cloth_pose_apply_inverse(const cloth_pose *pose, const cloth_real p[3], cloth_real out[3]);

/* The shapes of obstacles, each described in its own frame. */
typedef enum cloth_obstacle_shape {
    CLOTH_OBSTACLE_PLANE = 0,   /* the half-space y < 0; surface y = 0, outward normal +y */
    CLOTH_OBSTACLE_SPHERE = 1,  /* radius, centred at the origin */
    CLOTH_OBSTACLE_CAPSULE = 2, /* radius around the segment (-half_length, 0, 0) .. (half_length, 0, 0) */
    CLOTH_OBSTACLE_BOX = 3,     /* |x| <= half_extents[0], |y| <= [1], |z| <= [2]; with the
                                   thickness, its edges and corners are rounded */
    CLOTH_OBSTACLE_MESH = 4     /* a triangle mesh (closed or not), by CCD */
} cloth_obstacle_shape;

/* An obstacle; make it with cloth_default_obstacle_def() and change what you need. */
typedef struct cloth_obstacle_def {
    uint32_t cookie;              /* set by cloth_default_obstacle_def */
    cloth_obstacle_shape shape;   /* CLOTH_OBSTACLE_PLANE */
    cloth_real radius;            /* sphere, capsule (m); 0.5 */
    cloth_real half_length;       /* capsule: half the distance between the hemisphere centres; 0.5 */
    cloth_real half_extents[3];   /* box (m); 0.5 each */
    /* mesh: vertex positions in the obstacle's frame (3 per vertex) and triangles, copied */
    const cloth_real *mesh_x;
    int32_t mesh_vertex_count;
    const int32_t *mesh_tri;
    int32_t mesh_triangle_count;
    cloth_pose pose;              /* where it is (start and end of the first step); identity */
    cloth_real thickness;         /* the separation the cloth keeps from it (m), > 0; 1e-3 */
    cloth_real friction_static;   /* Coulomb mu_s >= 0; 0.5 */
    cloth_real friction_kinetic;  /* Coulomb mu_k, 0 <= mu_k <= mu_s; 0.5 */
} cloth_obstacle_def;

CLOTH_API cloth_obstacle_def cloth_default_obstacle_def(void);

/* The collide phase's setup; make it with cloth_default_contact_def(). */
typedef struct cloth_contact_def {
    uint32_t cookie;             /* set by cloth_default_contact_def */
    int32_t vertex_count;        /* n >= 0, cloth vertices of all pieces */
    const int32_t *tri;          /* 3 per triangle, indices into 0..n-1, copied; NULL when none */
    int32_t triangle_count;      /* m >= 0 */
    const int32_t *triangle_piece; /* piece id of each triangle, copied; NULL: all piece 0 */
    int self_collision;          /* collisions of a piece with itself; 0 */
    int piece_collision;         /* collisions between different pieces; 0 */
    cloth_real thickness;        /* cloth-cloth separation the response restores (m), > 0; 1e-3 */
    cloth_real detection_ratio;  /* detection separation / thickness, in (0, 0.5]; 0.25 */
    cloth_real friction_static;  /* cloth-cloth Coulomb mu_s; 0.3 */
    cloth_real friction_kinetic; /* cloth-cloth mu_k <= mu_s; 0.3 */
    int32_t max_rounds;          /* detection rounds with exact zone projection; 100 */
    int32_t max_rigid_rounds;    /* fail-safe rounds after that; 50 */
    cloth_real ccd_relative_tolerance; /* the CCD's delta as a fraction of the pair's detection
                                    separation d, > 0 with detection_ratio (1 + this) <= 0.4;
                                    0.25 (coarser is faster; a reported pair came within
                                    d (1 + this) per axis, which must stay well inside the
                                    thickness the response restores, or pairs are found again) */
    int32_t impacts_per_vertex;  /* rows a movable vertex may receive per round, earliest first
                                    (1 = Harmon's independent impacts), >= 1; 2 */
    int64_t ccd_max_checks;      /* the CCD's box budget per query, >= 1; 100000 (a query that
                                    runs out answers with a conservative time) */
    int64_t ccd_refine_checks;   /* the CCD's refine_checks, >= 0; 64: once a query finds a
                                    contact, 64 more checks tighten its time (a lower bound,
                                    not the tightest one). Resting layers make most queries
                                    contacts, and tightening their times to the end cost 2.7
                                    of every 3.3 checks in the stack scene (bench/stress.c);
                                    0 is faster still there, but fast impacts then get rows
                                    from too early a time and need more rounds */
    cloth_allocator allocator;   /* alloc NULL: the default */
    /* Wall clock in seconds for the phase timings in cloth_contact_stats; NULL uses clock(). */
    double (*clock)(void *user);
    void *clock_user;
} cloth_contact_def;

CLOTH_API cloth_contact_def cloth_default_contact_def(void);

/* What a resolve did. Counts are over the whole call, all rounds; times in seconds. */
typedef struct cloth_contact_stats {
    int32_t rounds;               /* detection rounds (CCD passes), the last clean one included */
    int32_t rigid_rounds;         /* fail-safe rounds (0 when the projection converged) */
    int32_t obstacle_contacts;    /* responses of a vertex to an analytic obstacle */
    int32_t impacts;              /* impacts found: the three kinds below */
    int32_t vertex_face_impacts;  /* by CCD */
    int32_t edge_edge_impacts;    /* by CCD */
    int32_t proximity_impacts;    /* close pairs that ended closer than they started (SEPARATIONS) */
    int32_t impact_rows;          /* impacts kept as QP rows (def.impacts_per_vertex) */
    int32_t stale_impacts;        /* impacts whose row held already at x1 (not kept) */
    int32_t impact_zones;         /* zones at the end (sets of vertices merged by impacts) */
    int32_t largest_zone;         /* movable vertices in the largest zone */
    int32_t qp_solves;
    int32_t qp_iterations;        /* working-set changes, all solves */
    int32_t rigid_zones;          /* zones the fail-safe translated */
    int32_t frozen_zones;         /* zones the fail-safe stopped at x0 */
    int32_t candidate_pairs;      /* triangle pairs from the BVH traversals (after the first
                                     round, of subtrees holding a touched triangle only) */
    int32_t ccd_queries;          /* vertex-face and edge-edge CCD calls */
    int32_t ccd_culled;           /* primitive pairs proven apart without a CCD call */
    int32_t pairs_culled;         /* candidate triangle pairs proven apart by their boxes in
                                     their own moving frame (SEPARATIONS), before any test */
    int32_t ccd_certain;          /* primitive pairs that end within the detection separation,
                                     slow pairs: impacts without a CCD call (SEPARATIONS) */
    int64_t ccd_checks;           /* boxes the CCD checked */
    int32_t ccd_budget_exhausted; /* queries that ran out of checks (answered conservatively) */
    int32_t initially_touching;   /* primitive pairs closer than ~1e-11 m at x0, not guarded */
    int32_t friction_rows;        /* impact rows whose tangential velocity friction changed */
    double time_bvh;              /* tree refits and rebuilds */
    double time_ccd;              /* traversals and the narrow phase (culling, CCD, rows) */
    double time_response;         /* analytic obstacles, zone projections, fail-safe, velocities */
    double time_total;
} cloth_contact_stats;

/* The collide phase's state: copies of the triangles, topology, trees, obstacles, scratch. */
typedef struct cloth_contact cloth_contact;

/* Make and destroy. cloth_contact_create returns CLOTH_ERROR_INVALID_ARGUMENT for a def out of
   range (counts, NULL arrays with counts, thickness, ratio, friction, rounds, CCD options),
   CLOTH_ERROR_INDEX_OUT_OF_RANGE or CLOTH_ERROR_DEGENERATE_TRIANGLE for bad triangles,
   CLOTH_ERROR_OUT_OF_MEMORY; *contact is then NULL. cloth_contact_destroy accepts NULL. */
CLOTH_API cloth_result cloth_contact_create(cloth_contact **contact, const cloth_contact_def *def);
CLOTH_API void cloth_contact_destroy(cloth_contact *contact);
/* The def the contact runs with. */
CLOTH_API const cloth_contact_def *cloth_contact_get_def(const cloth_contact *contact);

/* Add an obstacle; *index (may be NULL) gets its index, 0, 1, ... in the order of adding. A
   mesh obstacle's vertices and triangles are copied and its topology built. Returns
   CLOTH_ERROR_INVALID_ARGUMENT (a shape parameter, thickness or friction out of range, a mesh
   without vertices or triangles, a pose that is not finite), CLOTH_ERROR_NOT_FINITE (mesh
   coordinates), CLOTH_ERROR_INDEX_OUT_OF_RANGE / CLOTH_ERROR_DEGENERATE_TRIANGLE (mesh
   triangles), CLOTH_ERROR_OUT_OF_MEMORY. */
CLOTH_API cloth_result cloth_contact_add_obstacle(cloth_contact *contact, const cloth_obstacle_def *def, int32_t *index);
CLOTH_API int32_t cloth_contact_obstacle_count(const cloth_contact *contact);

/* Set an obstacle's pose at the start and at the end of the next step (kinematic motion); a
   static obstacle needs no call. For a mesh it also sets its vertices to the posed def
   vertices. The poses stay until the next call. CLOTH_ERROR_INVALID_ARGUMENT for a bad index
   or a pose that is not finite. */
CLOTH_API cloth_result cloth_contact_move_obstacle(cloth_contact *contact, int32_t obstacle, const cloth_pose *start,
                                                   const cloth_pose *end);
/* Set a mesh obstacle's world vertex positions at the start and at the end of the next step
   (3 per vertex, copied; a deforming obstacle such as an animated body). end NULL means the
   same as start. CLOTH_ERROR_INVALID_ARGUMENT for a bad index or a shape that is not a mesh,
   CLOTH_ERROR_NOT_FINITE for a NaN or infinite coordinate. */
CLOTH_API cloth_result cloth_contact_set_obstacle_vertices(cloth_contact *contact, int32_t obstacle,
                                                           const cloth_real *x_start, const cloth_real *x_end);

/* Signed distance (m) from world point p to an analytic obstacle at its end pose (negative
   inside), and its outward unit normal there when normal is not NULL. For a mesh obstacle:
   the unsigned distance to its end-of-step surface, with the direction from the closest point
   to p as the normal. For checks such as the penetration metric of SCENES.md. */
CLOTH_API cloth_real cloth_contact_obstacle_distance(const cloth_contact *contact, int32_t obstacle, const cloth_real p[3],
                                                     cloth_real normal[3]);

/* The collide phase of one step (see the top of this module). x0: positions at the start of
   the step (3n, read); x1: the integrator's proposal (3n, changed in place); inverse_mass: n
   values >= 0, 0 for pinned vertices, which never move (NULL: all 1); h > 0: the step (s), for
   velocities and impulses only; v: NULL or 3n velocities written at the end of the step;
   stats: NULL or filled. Returns
     CLOTH_SUCCESS                     x1 is collision-free (and v written);
     CLOTH_ERROR_COLLISION_UNRESOLVED  not resolvable (a pinned vertex inside an obstacle or
                                       colliding, immovable vertices forced through each other,
                                       the fail-safe out of rounds); x1 and v unchanged;
     CLOTH_ERROR_NOT_FINITE            a NaN or infinity in x0, x1 or inverse_mass (checked
                                       first); x1 and v unchanged;
     CLOTH_ERROR_INVALID_ARGUMENT      h not positive and finite, a negative inverse mass;
     CLOTH_ERROR_OUT_OF_MEMORY         scratch memory could not grow; x1 and v unchanged.
   NULL contact, x0 or x1 (with vertices) trips CLOTH_ASSERT. */
CLOTH_API cloth_result cloth_contact_resolve(cloth_contact *contact, const cloth_real *x0, cloth_real *x1,
                                            const cloth_real *inverse_mass, cloth_real h, cloth_real *v,
                                            cloth_contact_stats *stats);

#ifdef __cplusplus
}
#endif


/* ===================================================================================== */
/* integrate: the world (cloth pieces, pins, handles, seams, wind) and its time step:      */
/*            symplectic Euler, backward Euler (one linearized Newton step, or Newton       */
/*            iterations with a line search to a tolerance), BDF2; step statistics         */
/*            needs: core, mesh, material, forces, linsolve, contact                       */
/* ===================================================================================== */
#ifdef __cplusplus
extern "C" {
#endif

/* How a step advances positions x and velocities v over a time h.
   Implicit steps minimise the incremental potential
       Phi(x) = 1/(2 h^2) |x - xhat|_M^2 + E(x) + D(x),   xhat = x0 + h v0 + h^2 M^-1 f_ext
   (E the elastic energies, D the dissipation potential of damping) and set v = (x - x0)/h. */
typedef enum cloth_integrator {
    /* v += h M^-1 f(x); x += h v. Cheap, energy-preserving, stable only below
       cloth_world_stable_time_step(); a larger step returns CLOTH_ERROR_UNSTABLE. */
    CLOTH_INTEGRATOR_SYMPLECTIC_EULER = 0,
    /* One Newton iteration of Phi from x0: exactly the Baraff-Witkin linearized step. Fast. */
    CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED = 1,
    /* Newton iterations of Phi with a backtracking line search until the largest position
       update is below newton_tolerance * h: true backward Euler (needed for exact gradients). */
    CLOTH_INTEGRATOR_BACKWARD_EULER = 2,
    /* Second-order backward differentiation (x1 = 4/3 x0 - 1/3 x-1 + 2/3 h v1), Newton to the
       same tolerance; the first step of a world is backward Euler. Damps less than backward Euler. */
    CLOTH_INTEGRATOR_BDF2 = 3
} cloth_integrator;

/* The world's definition: make it with cloth_default_world_def() (physical defaults), change
   what you need, and pass it to cloth_world_create. */
typedef struct cloth_world_def {
    uint32_t cookie;                   /* set by cloth_default_world_def; catches a def never initialised */
    cloth_real gravity[3];             /* m/s^2; (0, -9.81, 0) */
    cloth_integrator integrator;       /* CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED */
    int32_t substeps;                  /* steps per cloth_world_step call; 1 */
    int32_t newton_max_iterations;     /* implicit integrators that iterate; 20 */
    cloth_real newton_tolerance;       /* m/s: stop when max |dx| / h falls below; 1e-5 */
    cloth_pcg_options cg;              /* the linear solver: cloth_default_pcg_options() with the
                                          multigrid preconditioner and relative tolerance 1e-4 */
    /* The multigrid hierarchy's options when cg.preconditioner is CLOTH_PRECONDITIONER_MULTIGRID;
       cloth_default_multigrid_options(), chosen on the hanging cloth. Contact may want others:
       on the sphere drop at 64 x 64 (CG 1e-4) a strength_threshold of 0.08 takes 6-10% fewer
       CG iterations per solve than 0.04, while a hanging cloth at 128 x 128 takes a third
       more (README, "Multigrid options under contact"). With threads, set
       multigrid.sweep_parts to 0 or the thread count so that the V-cycle's finest sweeps run on
       them too (its default, 1, keeps them on the calling thread). */
    cloth_multigrid_options multigrid;
    cloth_real air_density;            /* kg/m^3 for wind forces; 1.2 */
    cloth_real wind[3];                /* mean wind velocity, m/s; 0 */
    cloth_real gust_strength;          /* standard deviation of gusts per axis, m/s; 0 (no gusts) */
    cloth_real gust_time;              /* correlation time of gusts, s; 0.5 */
    uint64_t seed;                     /* seeds the gusts; 1 */
    cloth_real max_speed;              /* m/s: a step that makes any vertex faster has blown up; 1000 */
    /* Collisions (the contact module runs after each substep's solve only when the scene has
       obstacles or one of these is on): */
    int self_collision;                /* a piece against itself; 0 */
    int piece_collision;               /* pieces against each other; 0 */
    cloth_real collision_thickness;    /* cloth-cloth separation kept, m; 1e-3 */
    cloth_real cloth_friction;         /* cloth-cloth Coulomb coefficient (static = kinetic); 0.3 */
    /* Contact springs (dimensionless, >= 0; 100): cloth-cloth and cloth-mesh obstacle pairs the
       collide phase pushed apart (its impact rows) keep a one-sided spring along the row's
       normal in the following solves, E = k/2 (thickness - s)^2 while the pair's separation
       s along the normal is below the thickness, with k = proximity_stiffness m / h^2 (m the
       pair's mass along the normal, h the step), until the pair is more than twice the
       thickness apart. Resting
       layers (folds, stacked cloth) are then held apart by the solve itself instead of
       falling g h^2 into each other every step and being pushed back by the collide phase
       (which strains the cloth and costs most of a step). The spring's Hessian enters the
       solve as a diagonal majorant (the pattern stays fixed), so any stiffness is stable.
       The collide phase still runs after the solve and guarantees the result. 0: none.
       Implicit integrators only. */
    cloth_real proximity_stiffness;
    /* Analytic obstacles (plane, sphere, capsule, box) as constraints of the implicit solve; 1.
       A vertex whose inertial prediction (x0 + h v + h^2 f_ext / m) ends inside an obstacle's
       thickness layer is held on the layer's tangent plane during the solve (a one-direction
       Baraff-Witkin filter), so that the whole cloth answers the contact in the same solve;
       a vertex the solve would pull off the obstacle (an adhesive reaction) is released, and
       Coulomb friction is decided from the solve's reaction (stick within mu_s, else slip
       with mu_k); while these change, the linearized integrator solves its linear system
       again under the new constraints (at most obstacle_iterations solves in all). The
       collide phase still runs after the solve and is what guarantees the result (for a
       vertex the solve did not hold, with its own position-level friction). 0: obstacles act
       only in the collide phase, after the solve (a vertex is pushed out alone and its
       neighbours learn of it one step later, which strains stiff cloth at impacts).
       Symplectic Euler ignores this. */
    int obstacle_constraints;
    /* The most solves the linearized integrator makes in a substep while its obstacle
       constraints change (the same system each time, warm-started from the last solution),
       >= 1; 4. Fewer leave more to the collide phase: the sphere scene at 32 x 32 runs 1.8
       times as fast with 2 (64 x 64: 1.8 times) and reaches a higher strain in its worst
       frame (README, Collisions). No release is decided after the solve before the last
       (STICK AND SLIP below), so with 2 a vertex the obstacle pulls is released for the next
       substep. */
    int32_t obstacle_iterations;
    /* A trial first solve (relative CG tolerance, in [0, 1); 0: none). When it is larger
       than cg.tolerance, the linearized integrator's first solve of a substep that holds
       vertices on obstacles stops at this tolerance: a trial from which the releases,
       stick/slip switches and new holds are decided; a solve at cg.tolerance always
       follows it, warm-started from the trial (under the same constraints when nothing
       changed, whose multigrid hierarchy it keeps), so a substep's result meets
       cg.tolerance as without a trial. Needs obstacle_iterations >= 2 (the trial is one of
       them). The decisions are made on a less accurate reaction. The sphere scene at 64 x 64
       (CG 1e-2, 2 obstacle solves): 0.1 takes about a third fewer CG iterations and 10-15%
       less time per frame. Its 32 x 32 drape at rest (bench/drape.c): with the default
       holding (obstacle_hold_touching_only) nothing measurable, 96 of 96 paths within the
       rest test's bounds with 0.1 and without (resting strain median 2.6%), 24 of 24 at the
       defaults with 1e-3; with inertial holds it rested less smoothly (52 -> 43 of 96,
       fastest resting vertex median 0.40 -> 0.47 m/s; README, "Trial solves"). */
    cloth_real obstacle_trial_tolerance;
    /* Which vertices a substep holds on an obstacle before its first solve (STICK AND SLIP,
       HOLDING in the implementation). 1 (the default): those whose inertial target xhat lies
       in a layer when they touch one at the start (closer than 1.01 thickness), and the
       others when their velocity alone takes them into one (xhat without the h^2 a of the
       substep's forces); a vertex the solve then moves into a layer is held after it, as
       always. 0: every vertex whose inertial target lies in a layer, so a vertex the cloth
       holds up a millimetre above the layer (gravity's h^2 g is 2.7 mm at 60 Hz) is held,
       pulled onto the layer and released as adhesive, step after step. The 32 x 32 sphere
       drape at rest (bench/drape.c): with 1 every one of 48 paths at the defaults and of 96
       at CG 1e-2 with 2 solves stays within the rest test's bounds (0.5 m/s, 5%; resting
       strain median 2.0% and 2.6%), with 0 37 and 52 (3.8%, 4.7%); 1 costs 15-65% more CG
       iterations there and 1.17-1.22 times the time of the sphere scene at 64 x 64 (README,
       "Holding what touches"). */
    int obstacle_hold_touching_only;
    /* Adaptive steps for collisions: when the collide phase of a substep stretches some edge
       by more than collision_strain_limit (its length change over its rest length: cloth
       folding onto itself faster than a step can resolve smoothly, whose impact zones'
       projection then tears the membrane), or cannot resolve the step, or the step blows up,
       the whole step is redone from its start with twice the substeps, up to
       2^max_substep_doublings x substeps; the next step starts one doubling below the
       level this one needed; after two such tries failed in a row, the next one waits 1
       step, then 2, then 4 after each further failure, and a try that succeeds ends the
       waits. 0.1 and 3; a limit of 0
       turns its test off (both limits 0, or 0 doublings, turn adapting off). Only worlds with
       collisions and an implicit integrator adapt, and those with strain limiters (a piece's
       strain_limit: a substep that overshoots a limit is redone likewise). */
    cloth_real collision_strain_limit;
    /* Likewise when a whole substep of a world with collisions (solve and collide phase)
       stretches an edge by more than step_strain_limit: a contact event the step is too long
       for; 0.25, 0 turns it off. */
    cloth_real step_strain_limit;
    int32_t max_substep_doublings;
    /* Threads of the step: 0 or 1 single-threaded (the default); N > 1 runs the element
       assembly, the conjugate gradient's products and dot products, the multigrid update and
       the collide phase's CCD queries on the calling thread and N - 1 workers made by
       cloth_world_create (needs CLOTH_THREADS where
       the implementation is compiled; without it the world runs single-threaded). Results are
       bit-identical for every N (fixed partitions, fixed-order sums). At most 64. */
    int32_t threads;
    /* A host task system (see cloth_task_system) for the same work, instead of the pool:
       enqueue_task NULL (the default) means none. Needs no CLOTH_THREADS; threads is then
       ignored. Results are bit-identical to single-threaded ones. */
    cloth_task_system tasks;
    cloth_allocator allocator;         /* alloc NULL: the default */
    cloth_logger logger;               /* log NULL: silent */
    /* Wall clock in seconds for the phase timings in cloth_step_stats; NULL uses clock(). */
    double (*clock)(void *user);
    void *clock_user;
} cloth_world_def;

CLOTH_API cloth_world_def cloth_default_world_def(void);

/* Cloth models. */
typedef enum cloth_model {
    CLOTH_MODEL_MEMBRANE = 0,    /* FEM membrane (orthotropic St.Venant-Kirchhoff) on the uv pattern */
    CLOTH_MODEL_MASS_SPRING = 1  /* springs: Provot's structural/shear/bend springs on a grid, or
                                    edge springs and bending springs (across interior edges) on any mesh */
} cloth_model;

/* Bending energies of the membrane model (the forces module documents both). */
typedef enum cloth_bending_model {
    CLOTH_BENDING_QUADRATIC = 0, /* per-vertex curvature of the flat pattern (Bergou et al. 2006):
                                    constant exact Hessian, no soft checkerboard mode on grids
                                    (a pure end moment bends a strip exactly); a piece without uv
                                    (a curved rest shape) uses the dihedral one. Its stencils span
                                    two rings, so the system matrix is denser: hang 64 measured
                                    3.5x slower per frame than with the dihedral energy (same CG
                                    iterations, README speed), about as fast with
                                    bending_lumped (below) */
    CLOTH_BENDING_DIHEDRAL = 1   /* the default: per-edge hinge angles with rest angles; on
                                    right-triangle grids it lets the mesh relax into a
                                    checkerboard mode that makes a bent strip 15-25% too soft
                                    (README, accuracy) */
} cloth_bending_model;

/* One piece of cloth: its material and which forces act on it. */
typedef struct cloth_piece_def {
    uint32_t cookie;               /* set by cloth_default_piece_def */
    cloth_material material;       /* cloth_default_material() */
    cloth_model model;             /* CLOTH_MODEL_MEMBRANE */
    int bending;                   /* bending energy (membrane model); 1 */
    cloth_bending_model bending_model; /* CLOTH_BENDING_DIHEDRAL (the faster; see the enum) */
    /* Lumped bending (0, 1 or 2; default 0): a speed knob for the membrane model's bending. A
       dihedral hinge's Hessian couples its two wing tips (the vertices opposite its edge) and a
       quadratic stencil's couples its centre's neighbours, pairs no edge joins: on a grid that
       nearly doubles the system matrix with the dihedral energy (13 blocks a row instead of
       the 7 of the mesh's edges) and triples it with the quadratic one. 1 moves those
       couplings onto blocks the mesh's edges already have, as terms that bound the exact
       Hessian from above and vanish on translations, so the linearized step stays stable
       and a falling sheet falls as before; the energy and forces are unchanged, so a converged
       implicit step lands on the same state. What it costs: the lumped terms stiffen slopes
       (a first-derivative penalty of about the bending stiffness over the edge length
       squared), so the slow bending of the sheet and turns about its hinge edges are damped,
       the more so the larger dt^2 B / (rho l^4) (B the bending stiffness, rho the areal
       density, l the edge length: the step against the bending's own period). Below about 1
       it costs little: cotton at 1/60 s has 0.03, 0.4 and 7 at 32, 64 and 128 vertices a side,
       where the hang's path moves by 7%, 15% and 47% of what halving the time step moves it.
       Far above it the cloth creeps: a millimetre-cell cantilever (about 1e6) barely sags in
       400 steps. Speed (README, "Lumped bending"): hang 64 1.23-1.28x faster with the
       dihedral energy and 4-5x with the quadratic one, the sphere at 64 1.2x (CG 1e-2) to
       1.4x (defaults).
       2 lumps only in the preconditioner: the step keeps the exact matrix (the same path as
       0, to the CG tolerance) and the preconditioner is made from a lumped copy on the
       sparser pattern (cloth_pcg_solve_preconditioned). Worth it with the quadratic energy
       (hang 64 2.5-3x faster than 0, exact), not with the dihedral one (within a few percent
       of 0). No effect on the mass-spring model. */
    int bending_lumped;
    /* Mass-spring on a grid made by cloth_mesh_grid(nx, ny): set both to get Provot's springs;
       0 uses edge and bending springs of the mesh's topology. */
    int32_t grid_nx, grid_ny;
    cloth_real drag;               /* linear air drag per area, N s/m^3 (force -drag * area * v); 0 */
    int wind;                      /* aerodynamic force from the world's wind; 1 */
    cloth_real drag_coefficient;   /* aerodynamic normal drag coefficient of a face; 1.0 */
    /* Strain limiting (either model): every edge of the piece gets a limiter
       (cloth_strain_limit_energy) that engages when the edge is stretched by more than
       strain_limit (0.05: 5 % of its rest length), so that the cloth stiffens steeply beyond it.
       Its stiffness is strain_limit_stiffening times the material's larger tensile stiffness
       max(C11, C22), spread over the edges as a membrane of that stiffness would be: edge e
       gets k_e = Y A_e / L_e^2, with A_e a third of the rest area of the faces beside it and
       L_e its rest length. A soft limit, not a hard constraint: an edge loaded past the
       limit stretches by about 1 / (1 + strain_limit_stiffening) of what it would stretch
       without the limiter. The linearized integrator meets a limiter only once it is engaged
       at the start of a step, so a fast pull would overshoot within the step: a substep that
       carries an edge more than strain_limit / 4 past its limit (beyond where it started) is
       redone as the world def's adaptive steps are (max_substep_doublings). The limiters sit
       on the matrix's existing pattern; below the limit they change nothing (bit for bit) and
       cost one edge length each per assembly and per substep. Costs and strains on the hang
       scene: README, "Speed of the dynamics". strain_limit 0 (default): none;
       strain_limit_stiffening 100. */
    cloth_real strain_limit;
    cloth_real strain_limit_stiffening;
} cloth_piece_def;

CLOTH_API cloth_piece_def cloth_default_piece_def(void);

typedef struct cloth_world cloth_world;

/* Per-step statistics. Times are in seconds of the def's clock. */
typedef struct cloth_step_stats {
    int32_t substeps;
    int32_t newton_iterations;     /* all substeps together (the linearized integrator: its solves) */
    int32_t cg_iterations;         /* all solves together */
    cloth_real cg_residual;        /* relative residual of the last solve */
    int32_t line_search_halvings;  /* step-length halvings of the line search, all together */
    int newton_converged;          /* every substep met newton_tolerance (1 for the one-shot integrators) */
    double time_assembly;          /* energies, gradients and Hessians */
    double time_solve;             /* conjugate gradient */
    double time_collide;           /* the contact module (BVH, CCD, response), all substeps; */
    double time_bvh;               /*   of which tree refits and rebuilds, */
    double time_ccd;               /*   broad and narrow phase, */
    double time_response;          /*   obstacle responses, zone projections, fail-safe, velocities */
    int32_t impacts;               /* impacts the contact module found, all substeps */
    int32_t impact_zones;          /* impact zones at the end of the last substep */
    int32_t largest_zone;          /* movable vertices in the largest zone, any substep */
    int32_t ccd_rounds;            /* detection rounds, all substeps */
    int32_t qp_iterations;         /* working-set changes of the zone projections, all substeps */
    int32_t rigid_zones;           /* zones the fail-safe moved rigidly, all substeps */
    int32_t frozen_zones;          /* zones the fail-safe stopped at their start, all substeps */
    cloth_real collision_correction; /* the furthest the collide phase moved a vertex in a
                                      substep of the accepted attempt (m) */
    cloth_real collision_strain;   /* the most the collide phase stretched an edge in a substep
                                      of the accepted attempt (length change / rest length) */
    cloth_real step_strain;        /* the most a whole substep (solve and collide phase)
                                      stretched an edge, accepted attempt */
    int32_t substep_doublings;     /* the accepted attempt ran 2^this x def.substeps substeps */
    int32_t substep_redos;         /* attempts given up for one with twice the substeps */
    int32_t obstacle_contacts;     /* vertex responses to analytic obstacles, all substeps */
    int32_t obstacle_constraints;  /* vertices the solves held on an analytic obstacle (def's
                                      obstacle_constraints), all substeps */
    int32_t obstacle_releases;     /* of those, released for an adhesive reaction */
    int32_t obstacle_resolves;     /* extra solves the linearized integrator made because its
                                      obstacle constraints changed or a trial solve was made
                                      (def.obstacle_trial_tolerance) */
    int32_t contact_springs;       /* contact springs kept for the next step (cloth-cloth and
                                      cloth-mesh pairs, def.proximity_stiffness) */
    double time_total;
} cloth_step_stats;

/* Make and destroy a world. cloth_world_destroy accepts NULL. */
CLOTH_API cloth_result cloth_world_create(cloth_world **world, const cloth_world_def *def);
CLOTH_API void cloth_world_destroy(cloth_world *world);
/* The def the world runs with, defaults resolved. */
CLOTH_API const cloth_world_def *cloth_world_get_def(const cloth_world *world);

/* Add a piece: the mesh is copied. Its positions are the initial state; its rest shape is the uv
   pattern when the mesh has uv, otherwise the initial positions (each triangle's rest shape is
   then its initial shape, and bending rest angles are the initial dihedral angles). The mesh must
   pass cloth_mesh_validate; the error it gives is returned. *piece gets the piece's index. */
CLOTH_API cloth_result cloth_world_add_piece(cloth_world *world, const cloth_mesh *mesh, const cloth_piece_def *def,
                                             int32_t *piece);
CLOTH_API int32_t cloth_world_piece_count(const cloth_world *world);
CLOTH_API int32_t cloth_world_vertex_count(const cloth_world *world, int32_t piece);
/* The piece's current positions and velocities (3 per vertex), valid until the next call that
   changes the world's structure (adding pieces or seams). */
CLOTH_API const cloth_real *cloth_world_positions(const cloth_world *world, int32_t piece);
CLOTH_API const cloth_real *cloth_world_velocities(const cloth_world *world, int32_t piece);
CLOTH_API cloth_result cloth_world_set_positions(cloth_world *world, int32_t piece, const cloth_real *x);
CLOTH_API cloth_result cloth_world_set_velocities(cloth_world *world, int32_t piece, const cloth_real *v);
/* The piece's mesh (triangles, uv) with its current positions: a view, not a copy. */
CLOTH_API cloth_mesh cloth_world_mesh(const cloth_world *world, int32_t piece);

/* Pins: exact constraints through the solver's filter. A pinned vertex follows its target
   (NULL: where it is now); cloth_world_set_pin_target moves the target for the next step (the
   vertex arrives there at the end of the step). A triangle whose three vertices are pinned is
   a clamp for the quadratic bending: the free cloth leaves it with its slope (two pinned rows
   clamp an edge; one pinned row is a hinge). */
CLOTH_API cloth_result cloth_world_pin(cloth_world *world, int32_t piece, int32_t vertex, const cloth_real *target);
CLOTH_API cloth_result cloth_world_set_pin_target(cloth_world *world, int32_t piece, int32_t vertex, const cloth_real *target);
CLOTH_API cloth_result cloth_world_unpin(cloth_world *world, int32_t piece, int32_t vertex);
/* A kinematic handle: a pin whose target follows position(t) (the world's time at the end of
   each substep), evaluated by the world. */
typedef void (*cloth_trajectory_fn)(double time, cloth_real position[3], void *user);
CLOTH_API cloth_result cloth_world_set_handle(cloth_world *world, int32_t piece, int32_t vertex, cloth_trajectory_fn position,
                                              void *user);
/* An attachment spring of stiffness k (N/m) pulling a vertex to a fixed point: a soft pin. */
CLOTH_API cloth_result cloth_world_attach(cloth_world *world, int32_t piece, int32_t vertex, const cloth_real point[3],
                                          cloth_real stiffness);

/* Seams: zero-length springs of stiffness k (N/m) pulling vertex a[i] of piece_a to vertex
   b[i] of piece_b (pieces may be the same). cloth_world_add_seam_polyline pairs two boundary
   polylines (vertex lists) by arc length: each vertex of one is pulled to the point at the same
   arc-length fraction on the other, both ways. */
CLOTH_API cloth_result cloth_world_add_seam(cloth_world *world, int32_t piece_a, const int32_t *a, int32_t piece_b,
                                            const int32_t *b, int32_t count, cloth_real stiffness);
CLOTH_API cloth_result cloth_world_add_seam_polyline(cloth_world *world, int32_t piece_a, const int32_t *a, int32_t count_a,
                                                     int32_t piece_b, const int32_t *b, int32_t count_b, cloth_real stiffness);
/* The fraction (0..1) of seam springs whose two ends are closer than tolerance (m): sewn. */
CLOTH_API cloth_real cloth_world_seam_sewn_fraction(const cloth_world *world, cloth_real tolerance);

/* External forces per vertex (N, 3 per vertex of the piece), applied in every step until
   changed; NULL clears them. For controls and user interaction. */
CLOTH_API cloth_result cloth_world_set_external_forces(cloth_world *world, int32_t piece, const cloth_real *force);

/* Obstacles (see the contact module for shapes, thickness and friction): the def is copied,
   mesh arrays included. cloth_world_set_obstacle_pose gives the pose the obstacle reaches at the
   end of the next step (over the step's substeps it moves from its current pose as
   cloth_pose_interpolate says: translation on a straight line, rotation about a fixed axis at
   a uniform rate); cloth_world_set_obstacle_vertices
   gives a mesh obstacle's world vertices at the end of the next step (an animated body).
   cloth_world_obstacle_distance is the signed distance from p to the obstacle now. */
CLOTH_API cloth_result cloth_world_add_obstacle(cloth_world *world, const cloth_obstacle_def *def, int32_t *index);
CLOTH_API cloth_result cloth_world_set_obstacle_pose(cloth_world *world, int32_t obstacle, const cloth_pose *pose);
CLOTH_API cloth_result cloth_world_set_obstacle_vertices(cloth_world *world, int32_t obstacle, const cloth_real *x);
CLOTH_API cloth_real cloth_world_obstacle_distance(cloth_world *world, int32_t obstacle, const cloth_real p[3]);

/* Advance the world by dt (split into def.substeps substeps). On any failure (NaN or infinity,
   a blow-up past max_speed, a solver failure, a symplectic step past its stable step) it returns
   the error and the world is exactly as it was before the call. stats may be NULL. */
CLOTH_API cloth_result cloth_world_step(cloth_world *world, cloth_real dt, cloth_step_stats *stats);
/* The world's time (s) and number of substeps taken. */
CLOTH_API double cloth_world_time(const cloth_world *world);

/* Energies of the current state (J): kinetic, gravitational (relative to y = 0), elastic (all
   enabled terms). Any pointer may be NULL. The world is not const here: like a step, these
   two build the world's element lists first if a change (a piece, a seam) left them stale. */
CLOTH_API void cloth_world_energy(cloth_world *world, cloth_real *kinetic, cloth_real *gravitational,
                                  cloth_real *elastic);
/* An estimate of the largest stable symplectic Euler step (s) for the world as it is (strain
   limiters counted as engaged: one may engage before the estimate is made again, every 32
   substeps). */
CLOTH_API cloth_real cloth_world_stable_time_step(cloth_world *world);
/* The largest edge strain |e| / |e_rest| - 1 over all edges of a piece (rest from uv). */
CLOTH_API cloth_real cloth_world_max_edge_strain(const cloth_world *world, int32_t piece);

#ifdef __cplusplus
}
#endif


#endif /* CLOTH_H */

/* ===================================================================================== */
/*                                  IMPLEMENTATION                                        */
/* ===================================================================================== */
#ifdef CLOTH_IMPLEMENTATION
#ifndef CLOTH_IMPLEMENTATION_DONE
#define CLOTH_IMPLEMENTATION_DONE

#include <string.h>
#include <math.h>
#include <float.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <time.h>
#ifdef CLOTH_THREADS
#include <pthread.h>
#include <sched.h>
#endif

#ifndef CLOTH_MALLOC
#include <stdlib.h>
#define CLOTH_MALLOC(sz) malloc(sz)
#define CLOTH_FREE(p) free(p)
#endif

#ifndef CLOTH_ASSERT
#include <assert.h>
#define CLOTH_ASSERT(c) assert(c)
#endif

/* Private helpers that some configurations do not call are marked so that -Wunused stays quiet. */
#if defined(__GNUC__) || defined(__clang__)
#define CLOTH__MAYBE_UNUSED __attribute__((unused))
#else
#define CLOTH__MAYBE_UNUSED
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------- */
/* core                                                                                  */
/* ------------------------------------------------------------------------------------- */

CLOTH_API const char *cloth_result_string(cloth_result result)
{
    switch (result) {
    case CLOTH_SUCCESS: return "success";
    case CLOTH_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case CLOTH_ERROR_OUT_OF_MEMORY: return "out of memory";
    case CLOTH_ERROR_SIZE_OVERFLOW: return "size overflow";
    case CLOTH_ERROR_FILE_OPEN: return "cannot open file";
    case CLOTH_ERROR_FILE_READ: return "cannot read file";
    case CLOTH_ERROR_FILE_WRITE: return "cannot write file";
    case CLOTH_ERROR_PARSE: return "parse error";
    case CLOTH_ERROR_UNSUPPORTED: return "unsupported feature";
    case CLOTH_ERROR_TRUNCATED: return "truncated data";
    case CLOTH_ERROR_NOT_FINITE: return "not a finite number";
    case CLOTH_ERROR_INDEX_OUT_OF_RANGE: return "index out of range";
    case CLOTH_ERROR_DEGENERATE_TRIANGLE: return "degenerate triangle";
    case CLOTH_ERROR_NON_MANIFOLD_EDGE: return "non-manifold edge";
    case CLOTH_ERROR_INCONSISTENT_ORIENTATION: return "inconsistent orientation";
    case CLOTH_ERROR_DUPLICATE_FACE: return "duplicate face";
    case CLOTH_ERROR_EMPTY_MESH: return "empty mesh";
    case CLOTH_ERROR_CG_NOT_CONVERGED: return "conjugate gradient did not converge";
    case CLOTH_ERROR_NOT_POSITIVE_DEFINITE: return "matrix not positive definite";
    case CLOTH_ERROR_UNSTABLE: return "unstable step";
    case CLOTH_ERROR_COLLISION_UNRESOLVED: return "collisions unresolved";
    case CLOTH_ERROR_RESULT_COUNT_: break;
    }
    return "unknown result";
}

CLOTH_API int cloth_version(void) { return CLOTH_VERSION; }
CLOTH_API size_t cloth_real_size(void) { return sizeof(cloth_real); }

static void *cloth__default_alloc(size_t size, void *user) { (void)user; return CLOTH_MALLOC(size); }
static void cloth__default_free(void *ptr, void *user) { (void)user; CLOTH_FREE(ptr); }

CLOTH_API cloth_allocator cloth_default_allocator(void)
{
    cloth_allocator a;
    a.alloc = cloth__default_alloc;
    a.free = cloth__default_free;
    a.user = NULL;
    return a;
}

/* The allocator an object keeps: the caller's if it names one, else the default. */
CLOTH__MAYBE_UNUSED static cloth_allocator cloth__allocator_or_default(const cloth_allocator *allocator)
{
    if (allocator && allocator->alloc && allocator->free) return *allocator;
    return cloth_default_allocator();
}

/* a * b + c as a size, or 0 with *ok cleared on overflow. All sizes pass through here. */
CLOTH__MAYBE_UNUSED static size_t cloth__size_mul_add(size_t a, size_t b, size_t c, int *ok)
{
    if (b != 0 && a > (SIZE_MAX - c) / b) { *ok = 0; return 0; }
    return a * b + c;
}

/* Allocation of count elements of elem_size bytes, overflow-checked; NULL on failure.
   A count of zero allocates one byte so that a valid empty array is not NULL. */
CLOTH__MAYBE_UNUSED static void *cloth__alloc_array(const cloth_allocator *a, size_t count, size_t elem_size)
{
    int ok = 1;
    size_t bytes = cloth__size_mul_add(count, elem_size, 0, &ok);
    if (!ok) return NULL;
    return a->alloc(bytes ? bytes : 1, a->user);
}

CLOTH__MAYBE_UNUSED static void cloth__free(const cloth_allocator *a, void *p)
{
    if (p) a->free(p, a->user);
}

/* Report through the logger, if there is one; formatting happens only then. */
CLOTH__MAYBE_UNUSED static void cloth__log(const cloth_logger *logger, cloth_log_level level, const char *format, ...)
{
    char message[512];
    va_list args;
    if (!logger || !logger->log) return;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    logger->log(level, message, logger->user);
}

/* ---- the thread pool ----------------------------------------------------------------- */

/* A small persistent pool for the implicit step (world def `threads`, cloth_pcg_workspace_set_threads):
   the calling thread and threads - 1 workers made once. cloth__pool_run(pool, parts, task, ctx)
   calls task(ctx, part) for every part in 0 .. parts-1 and returns when all are done; thread t
   of T takes the contiguous parts t parts / T .. (t + 1) parts / T - 1. Callers make a part's work
   independent of which thread runs it and of the other parts (rows of a fixed partition, partial
   sums per fixed chunk added in order afterwards), so results never depend on the thread count.
   Without CLOTH_THREADS, or with pool NULL or one thread, the parts run in order on the caller. */
typedef cloth_task_fn cloth__task;

typedef struct cloth__pool cloth__pool;

/* The most threads a pool runs (world def threads and tasks.worker_count,
   cloth_pcg_workspace_set_threads): per-part arrays are sized by it. */
#define CLOTH__MAX_THREADS 64

/* Rows *lo .. *hi - 1 of part `part` when n rows are split evenly into `parts`. */
static void cloth__part_rows(int32_t n, int32_t part, int32_t parts, int32_t *lo, int32_t *hi)
{
    *lo = (int32_t)((int64_t)n * part / parts);
    *hi = (int32_t)((int64_t)n * (part + 1) / parts);
}

#ifdef CLOTH_THREADS
#if defined(__GNUC__) || defined(__clang__)
#define CLOTH__SPIN 200000 /* polls of a flag (yielding every 64) before sleeping on a condition variable */
#define CLOTH__LOAD(p) __atomic_load_n((p), __ATOMIC_ACQUIRE)
#define CLOTH__STORE(p, v) __atomic_store_n((p), (v), __ATOMIC_RELEASE)
#define CLOTH__DECREMENT(p) __atomic_sub_fetch((p), 1, __ATOMIC_ACQ_REL)
#else
#define CLOTH__SPIN 0 /* no atomics known: every wait sleeps, every flag is read under the lock */
#define CLOTH__LOAD(p) (*(p))
#define CLOTH__STORE(p, v) (*(p) = (v))
#define CLOTH__DECREMENT(p) (--*(p))
#endif

typedef struct cloth__pool_worker {
    cloth__pool *pool;
    int32_t index;
    pthread_t thread;
} cloth__pool_worker;

struct cloth__pool {
    int32_t threads;
    cloth_allocator allocator;
    cloth_task_system host;       /* a host task system (enqueue_task set), or none */
    cloth__pool_worker *worker;   /* threads - 1 */
    int32_t started;              /* workers running */
    pthread_mutex_t lock;
    pthread_cond_t wake, done;
    unsigned generation;          /* bumped per job (under the lock) */
    int32_t pending;              /* workers still on the current job */
    int quit;
    cloth__task task;
    void *context;
    int32_t parts;
};

static void cloth__pool_share(cloth__pool *pool, int32_t t)
{
    int32_t p, begin, end;
    cloth__part_rows(pool->parts, t, pool->threads, &begin, &end);
    for (p = begin; p < end; ++p) pool->task(pool->context, p);
}

static void *cloth__pool_main(void *arg)
{
    cloth__pool_worker *me = (cloth__pool_worker *)arg;
    cloth__pool *pool = me->pool;
    unsigned seen = 0;
    for (;;) {
        int spin;
        for (spin = 0; spin < CLOTH__SPIN && CLOTH__LOAD(&pool->generation) == seen; ++spin)
            if ((spin & 63) == 63) sched_yield();
        pthread_mutex_lock(&pool->lock);
        while (pool->generation == seen && !pool->quit) pthread_cond_wait(&pool->wake, &pool->lock);
        if (pool->quit) { pthread_mutex_unlock(&pool->lock); break; }
        seen = pool->generation;
        pthread_mutex_unlock(&pool->lock);
        cloth__pool_share(pool, me->index);
        if (CLOTH__DECREMENT(&pool->pending) == 0) {
            pthread_mutex_lock(&pool->lock);
            pthread_cond_signal(&pool->done);
            pthread_mutex_unlock(&pool->lock);
        }
    }
    return NULL;
}

CLOTH__MAYBE_UNUSED static void cloth__pool_destroy(cloth__pool *pool)
{
    int32_t k;
    if (!pool) return;
    if (pool->worker) {
        pthread_mutex_lock(&pool->lock);
        pool->quit = 1;
        pthread_cond_broadcast(&pool->wake);
        pthread_mutex_unlock(&pool->lock);
        for (k = 0; k < pool->started; ++k) pthread_join(pool->worker[k].thread, NULL);
        pthread_cond_destroy(&pool->wake);
        pthread_cond_destroy(&pool->done);
        pthread_mutex_destroy(&pool->lock);
        cloth__free(&pool->allocator, pool->worker);
    }
    cloth__free(&pool->allocator, pool);
}

/* A pool of `threads` (>= 2) threads, the caller's included; NULL when memory or a thread
   cannot be had. */
CLOTH__MAYBE_UNUSED static cloth__pool *cloth__pool_create(int32_t threads, const cloth_allocator *allocator)
{
    cloth__pool *pool = (cloth__pool *)cloth__alloc_array(allocator, 1, sizeof *pool);
    int32_t k;
    if (!pool) return NULL;
    memset(pool, 0, sizeof *pool);
    pool->threads = threads;
    pool->allocator = *allocator;
    pool->worker = (cloth__pool_worker *)cloth__alloc_array(allocator, (size_t)threads - 1, sizeof *pool->worker);
    if (!pool->worker) { cloth__free(allocator, pool); return NULL; }
    if (pthread_mutex_init(&pool->lock, NULL) != 0) { cloth__free(allocator, pool->worker); cloth__free(allocator, pool); return NULL; }
    pthread_cond_init(&pool->wake, NULL);
    pthread_cond_init(&pool->done, NULL);
    for (k = 0; k < threads - 1; ++k) {
        pool->worker[k].pool = pool;
        pool->worker[k].index = k + 1;
        if (pthread_create(&pool->worker[k].thread, NULL, cloth__pool_main, pool->worker + k) != 0) break;
        pool->started++;
    }
    if (pool->started != threads - 1) { cloth__pool_destroy(pool); return NULL; }
    return pool;
}

CLOTH__MAYBE_UNUSED static void cloth__pool_run(cloth__pool *pool, int32_t parts, cloth__task task, void *context)
{
    int32_t p;
    int spin;
    if (pool && pool->host.enqueue_task && parts >= 2) {
        pool->host.finish_task(pool->host.enqueue_task(task, context, parts, pool->host.user), pool->host.user);
        return;
    }
    if (!pool || pool->threads < 2 || parts < 2) {
        for (p = 0; p < parts; ++p) task(context, p);
        return;
    }
    pthread_mutex_lock(&pool->lock);
    pool->task = task;
    pool->context = context;
    pool->parts = parts;
    CLOTH__STORE(&pool->pending, pool->threads - 1);
    CLOTH__STORE(&pool->generation, pool->generation + 1);
    pthread_cond_broadcast(&pool->wake);
    pthread_mutex_unlock(&pool->lock);
    cloth__pool_share(pool, 0);
    for (spin = 0; spin < CLOTH__SPIN && CLOTH__LOAD(&pool->pending) != 0; ++spin)
        if ((spin & 63) == 63) sched_yield();
    if (CLOTH__LOAD(&pool->pending) != 0) {
        pthread_mutex_lock(&pool->lock);
        while (CLOTH__LOAD(&pool->pending) != 0) pthread_cond_wait(&pool->done, &pool->lock);
        pthread_mutex_unlock(&pool->lock);
    }
}
#else
struct cloth__pool { int32_t threads; cloth_allocator allocator; cloth_task_system host; };

CLOTH__MAYBE_UNUSED static void cloth__pool_destroy(cloth__pool *pool) { if (pool) cloth__free(&pool->allocator, pool); }

/* Without CLOTH_THREADS there are no workers: no pool (NULL), and every run is serial. */
CLOTH__MAYBE_UNUSED static cloth__pool *cloth__pool_create(int32_t threads, const cloth_allocator *allocator)
{
    (void)threads;
    (void)allocator;
    return NULL;
}

CLOTH__MAYBE_UNUSED static void cloth__pool_run(cloth__pool *pool, int32_t parts, cloth__task task, void *context)
{
    int32_t p;
    if (pool && pool->host.enqueue_task && parts >= 2) {
        pool->host.finish_task(pool->host.enqueue_task(task, context, parts, pool->host.user), pool->host.user);
        return;
    }
    for (p = 0; p < parts; ++p) task(context, p);
}
#endif

/* A pool that hands its work to a host task system (worker_count parts); NULL without memory. */
CLOTH__MAYBE_UNUSED static cloth__pool *cloth__pool_create_host(const cloth_task_system *host, const cloth_allocator *allocator)
{
    cloth__pool *pool = (cloth__pool *)cloth__alloc_array(allocator, 1, sizeof *pool);
    if (!pool) return NULL;
    memset(pool, 0, sizeof *pool);
    pool->threads = host->worker_count;
    pool->allocator = *allocator;
    pool->host = *host;
    return pool;
}

/* The threads a pool runs on (1 for none). */
CLOTH__MAYBE_UNUSED static int32_t cloth__pool_threads(const cloth__pool *pool) { return pool ? pool->threads : 1; }

static uint64_t cloth__splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

CLOTH_API cloth_rng cloth_rng_make(uint64_t seed)
{
    cloth_rng rng;
    int i;
    for (i = 0; i < 4; ++i) rng.s[i] = cloth__splitmix64(&seed);
    return rng;
}

static uint64_t cloth__rotl64(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

CLOTH_API uint64_t cloth_rng_next(cloth_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = cloth__rotl64(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = cloth__rotl64(s[3], 45);
    return result;
}

CLOTH_API cloth_real cloth_rng_uniform(cloth_rng *rng)
{
    /* 53 random bits into [0, 1) exactly as a double, then rounded to cloth_real; a float
       rounding up to 1 is folded back below 1. */
    double u = (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
    cloth_real r = (cloth_real)u;
    return r < (cloth_real)1 ? r : (cloth_real)0;
}

CLOTH_API cloth_real cloth_rng_normal(cloth_rng *rng)
{
    double u1 = 1.0 - (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0); /* (0, 1] */
    double u2 = (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
    return (cloth_real)(sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2));
}

/* ------------------------------------------------------------------------------------- */
/* math                                                                                  */
/* ------------------------------------------------------------------------------------- */

/* Small vector helpers over cloth_real[3] arrays. They take output pointers last and allow
   the output to alias an input. */
CLOTH__MAYBE_UNUSED static void cloth__v3_sub(const cloth_real *a, const cloth_real *b, cloth_real *out)
{ out[0] = a[0] - b[0]; out[1] = a[1] - b[1]; out[2] = a[2] - b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_add(const cloth_real *a, const cloth_real *b, cloth_real *out)
{ out[0] = a[0] + b[0]; out[1] = a[1] + b[1]; out[2] = a[2] + b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_scale(const cloth_real *a, cloth_real s, cloth_real *out)
{ out[0] = a[0] * s; out[1] = a[1] * s; out[2] = a[2] * s; }
CLOTH__MAYBE_UNUSED static cloth_real cloth__v3_dot(const cloth_real *a, const cloth_real *b)
{ return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_cross(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    cloth_real c0 = a[1] * b[2] - a[2] * b[1];
    cloth_real c1 = a[2] * b[0] - a[0] * b[2];
    cloth_real c2 = a[0] * b[1] - a[1] * b[0];
    out[0] = c0; out[1] = c1; out[2] = c2;
}
CLOTH__MAYBE_UNUSED static cloth_real cloth__v3_norm(const cloth_real *a) { return (cloth_real)sqrt((double)cloth__v3_dot(a, a)); }
CLOTH__MAYBE_UNUSED static int cloth__is_finite(cloth_real v) { return v == v && v - v == 0; }

/* atan2(y, x) in (-pi, pi], as C's, to within about an ulp of pi, written out so that the
   hot loops that need an angle (every dihedral hinge, every assembly) call no library
   function. Besides the call, a library call costs a hinge up to 190 ns instead of 11 when
   the program is built for AVX (-march=native, -mavx2) with GCC: the SSE code of libm's
   atan2 wrapper then meets 256-bit registers left dirty, and the hang scene's assembly took
   twice as long (README, "Choosing settings", compiler flags).
   The method: t = min / max of |y|, |x| in [0, 1]; c = k / 8 the nearest eighth, so that
   u = (t - c) / (1 + t c) has |u| <= 1/16 and atan t = atan c + atan u; atan u from its
   series to u^15 (the first term left out is below 2^-64 |u|); then the octant. */
static double cloth__atan2(double y, double x)
{
    /* atan(k / 8), k = 0..8, the doubles nearest them */
    static const double atan_eighth[9] = { 0.0, 0.12435499454676144, 0.24497866312686414, 0.35877067027057225,
                                           0.4636476090008061, 0.5585993153435624, 0.6435011087932844,
                                           0.7188299996216245, 0.7853981633974483 };
    /* pi / 2 and pi as a double and the rest below its last bit */
    const double half_pi = 1.5707963267948966, half_pi_low = 6.123233995736766e-17;
    const double pi = 3.141592653589793, pi_low = 1.2246467991473532e-16;
    double ay = fabs(y), ax = fabs(x), lo, hi, c, u, u2, r;
    int swapped, k, j;
    if (y != y || x != x) return y + x;
    if (ay == 0 && ax == 0) return signbit(x) ? copysign(pi, y) : copysign(0.0, y);
    swapped = ay > ax;
    lo = swapped ? ax : ay;
    hi = swapped ? ay : ax;
    /* k: the eighths' midpoints below t = lo / hi, found by products, not by a division (an
       eighth off at a midpoint leaves |u| a hair above 1/16: the series still holds); then
       u = (t - c) / (1 + t c) in one division, (lo - c hi) / (hi + c lo) */
    k = 0;
    for (j = 1; j < 16; j += 2) k += lo > hi * ((double)j / 16);
    c = (double)k / 8;
    if (lo == hi) u = 0; /* also both infinite */
    else u = k ? (lo - c * hi) / (hi + c * lo) : lo / hi;
    u2 = u * u;
    r = u * (1 - u2 * (1.0 / 3 - u2 * (1.0 / 5 - u2 * (1.0 / 7 - u2 * (1.0 / 9 - u2 * (1.0 / 11 - u2 * (1.0 / 13 - u2 / 15)))))));
    r += atan_eighth[k];
    if (swapped) r = (half_pi - r) + half_pi_low;
    if (signbit(x)) r = (pi - r) + pi_low;
    return signbit(y) ? -r : r;
}

/* ------------------------------------------------------------------------------------- */
/* mesh                                                                                  */
/* ------------------------------------------------------------------------------------- */

CLOTH_API cloth_result cloth_mesh_alloc(cloth_mesh *mesh, int32_t vertex_count, int32_t triangle_count,
                                        int with_uv, const cloth_allocator *allocator)
{
    cloth_allocator a;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (vertex_count < 0 || triangle_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    a = cloth__allocator_or_default(allocator);
    mesh->allocator = a;
    mesh->x = (cloth_real *)cloth__alloc_array(&a, (size_t)vertex_count, 3 * sizeof(cloth_real));
    mesh->uv = with_uv ? (cloth_real *)cloth__alloc_array(&a, (size_t)vertex_count, 2 * sizeof(cloth_real)) : NULL;
    mesh->tri = (int32_t *)cloth__alloc_array(&a, (size_t)triangle_count, 3 * sizeof(int32_t));
    if (!mesh->x || !mesh->tri || (with_uv && !mesh->uv)) {
        cloth_mesh_free(mesh);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_mesh_free(cloth_mesh *mesh)
{
    cloth_allocator a;
    if (!mesh) return;
    a = cloth__allocator_or_default(&mesh->allocator);
    cloth__free(&a, mesh->x);
    cloth__free(&a, mesh->uv);
    cloth__free(&a, mesh->tri);
    memset(mesh, 0, sizeof *mesh);
}

CLOTH_API cloth_result cloth_mesh_copy(cloth_mesh *dst, const cloth_mesh *src, const cloth_allocator *allocator)
{
    cloth_result r;
    CLOTH_ASSERT(dst && src);
    r = cloth_mesh_alloc(dst, src->vertex_count, src->triangle_count, src->uv != NULL, allocator);
    if (r != CLOTH_SUCCESS) return r;
    if (src->vertex_count) memcpy(dst->x, src->x, (size_t)src->vertex_count * 3 * sizeof(cloth_real));
    if (src->uv && src->vertex_count) memcpy(dst->uv, src->uv, (size_t)src->vertex_count * 2 * sizeof(cloth_real));
    if (src->triangle_count) memcpy(dst->tri, src->tri, (size_t)src->triangle_count * 3 * sizeof(int32_t));
    return CLOTH_SUCCESS;
}

/* The first triangle with an index out of range (or -1); *vertex gets the bad index. */
static int32_t cloth__first_bad_index(const cloth_mesh *mesh, int32_t *vertex)
{
    int32_t f;
    int k;
    for (f = 0; f < mesh->triangle_count; ++f)
        for (k = 0; k < 3; ++k) {
            int32_t v = mesh->tri[3 * f + k];
            if (v < 0 || v >= mesh->vertex_count) { *vertex = v; return f; }
        }
    return -1;
}

/* The first triangle that names one vertex twice (or -1). */
static int32_t cloth__first_repeated_vertex(const cloth_mesh *mesh)
{
    int32_t f;
    for (f = 0; f < mesh->triangle_count; ++f) {
        const int32_t *t = mesh->tri + 3 * f;
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return f;
    }
    return -1;
}

/* Half-edges bucketed by their smaller vertex: bucket v is he_hi/he_code[start[v] .. start[v+1]),
   he_code = 3 * face + k for the half-edge tri[3f+k] -> tri[3f+(k+1)%3]. Buckets keep face order. */
typedef struct cloth__edge_buckets {
    int32_t *start;
    int32_t *he_hi;
    int32_t *he_code;
} cloth__edge_buckets;

static void cloth__edge_buckets_free(const cloth_allocator *a, cloth__edge_buckets *b)
{
    cloth__free(a, b->start);
    cloth__free(a, b->he_hi);
    cloth__free(a, b->he_code);
    memset(b, 0, sizeof *b);
}

/* Needs indices in range. */
static cloth_result cloth__edge_buckets_build(const cloth_allocator *a, const cloth_mesh *mesh, cloth__edge_buckets *b)
{
    int32_t n = mesh->vertex_count, m = mesh->triangle_count, f, v;
    size_t half_edges = (size_t)m * 3;
    int k;
    memset(b, 0, sizeof *b);
    if (half_edges > (size_t)INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
    b->start = (int32_t *)cloth__alloc_array(a, (size_t)n + 1, sizeof(int32_t));
    b->he_hi = (int32_t *)cloth__alloc_array(a, half_edges, sizeof(int32_t));
    b->he_code = (int32_t *)cloth__alloc_array(a, half_edges, sizeof(int32_t));
    if (!b->start || !b->he_hi || !b->he_code) {
        cloth__edge_buckets_free(a, b);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    memset(b->start, 0, ((size_t)n + 1) * sizeof(int32_t));
    for (f = 0; f < m; ++f)
        for (k = 0; k < 3; ++k) {
            int32_t p = mesh->tri[3 * f + k], q = mesh->tri[3 * f + (k + 1) % 3];
            b->start[(p < q ? p : q) + 1]++;
        }
    for (v = 0; v < n; ++v) b->start[v + 1] += b->start[v];
    for (f = 0; f < m; ++f)
        for (k = 0; k < 3; ++k) {
            int32_t p = mesh->tri[3 * f + k], q = mesh->tri[3 * f + (k + 1) % 3];
            int32_t lo = p < q ? p : q, slot = b->start[lo]++;
            b->he_hi[slot] = p < q ? q : p;
            b->he_code[slot] = 3 * f + k;
        }
    for (v = n; v > 0; --v) b->start[v] = b->start[v - 1];
    b->start[0] = 0;
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_topology_free(cloth_topology *t)
{
    cloth_allocator a;
    if (!t) return;
    a = cloth__allocator_or_default(&t->allocator);
    cloth__free(&a, t->edge_vertex);
    cloth__free(&a, t->edge_face);
    cloth__free(&a, t->edge_opposite);
    cloth__free(&a, t->face_edge);
    cloth__free(&a, t->boundary_edge);
    cloth__free(&a, t->loop_start);
    cloth__free(&a, t->loop_vertex);
    cloth__free(&a, t->vertex_face_start);
    cloth__free(&a, t->vertex_face);
    memset(t, 0, sizeof *t);
}

/* Boundary loops: walk boundary edges in the direction of their faces. */
static cloth_result cloth__topology_loops(cloth_topology *t, const cloth_mesh *mesh, const cloth_allocator *a)
{
    int32_t nb = t->boundary_edge_count, n = t->vertex_count, i, v, loops = 0, written = 0;
    int32_t *out_start = (int32_t *)cloth__alloc_array(a, (size_t)n + 1, sizeof(int32_t));
    int32_t *out_edge = (int32_t *)cloth__alloc_array(a, (size_t)nb, sizeof(int32_t));
    int32_t *from = (int32_t *)cloth__alloc_array(a, (size_t)nb, sizeof(int32_t));
    int32_t *to = (int32_t *)cloth__alloc_array(a, (size_t)nb, sizeof(int32_t));
    unsigned char *used = (unsigned char *)cloth__alloc_array(a, (size_t)nb, 1);
    cloth_result r = CLOTH_SUCCESS;
    t->loop_start = (int32_t *)cloth__alloc_array(a, (size_t)nb + 1, sizeof(int32_t));
    t->loop_vertex = (int32_t *)cloth__alloc_array(a, (size_t)nb, sizeof(int32_t));
    if (!out_start || !out_edge || !from || !to || !used || !t->loop_start || !t->loop_vertex) {
        r = CLOTH_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    /* Direction of each boundary edge from its only face. */
    for (i = 0; i < nb; ++i) {
        int32_t e = t->boundary_edge[i], f = t->edge_face[2 * e], k;
        for (k = 0; k < 3; ++k)
            if (t->face_edge[3 * f + k] == e) break;
        from[i] = mesh->tri[3 * f + k];
        to[i] = mesh->tri[3 * f + (k + 1) % 3];
    }
    memset(out_start, 0, ((size_t)n + 1) * sizeof(int32_t));
    for (i = 0; i < nb; ++i) used[i] = 0;
    for (i = 0; i < nb; ++i) out_start[from[i] + 1]++;
    for (v = 0; v < n; ++v) out_start[v + 1] += out_start[v];
    for (i = 0; i < nb; ++i) out_edge[out_start[from[i]]++] = i;
    for (v = n; v > 0; --v) out_start[v] = out_start[v - 1];
    out_start[0] = 0;
    for (i = 0; i < nb; ++i) {
        int32_t cur = i;
        if (used[i]) continue;
        t->loop_start[loops++] = written;
        while (cur >= 0) {
            int32_t next = -1, s;
            used[cur] = 1;
            t->loop_vertex[written++] = from[cur];
            /* The next unused boundary edge leaving where this one ends; none closes the loop
               (or ends an open chain when orientation is inconsistent). */
            for (s = out_start[to[cur]]; s < out_start[to[cur] + 1]; ++s)
                if (!used[out_edge[s]]) { next = out_edge[s]; break; }
            cur = next;
        }
    }
    t->loop_start[loops] = written;
    t->loop_count = loops;
done:
    cloth__free(a, out_start);
    cloth__free(a, out_edge);
    cloth__free(a, from);
    cloth__free(a, to);
    cloth__free(a, used);
    return r;
}

CLOTH_API cloth_result cloth_topology_build(cloth_topology *t, const cloth_mesh *mesh, const cloth_allocator *allocator)
{
    cloth_allocator a;
    cloth__edge_buckets b;
    cloth_result r;
    int32_t n, m, v, f, e, i, bad_vertex = 0, edges = 0;
    CLOTH_ASSERT(t && mesh);
    memset(t, 0, sizeof *t);
    a = cloth__allocator_or_default(allocator);
    t->allocator = a;
    n = mesh->vertex_count;
    m = mesh->triangle_count;
    if (n < 0 || m < 0 || (m > 0 && !mesh->tri)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (cloth__first_bad_index(mesh, &bad_vertex) >= 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (cloth__first_repeated_vertex(mesh) >= 0) return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    r = cloth__edge_buckets_build(&a, mesh, &b);
    if (r != CLOTH_SUCCESS) return r;
    t->vertex_count = n;
    t->triangle_count = m;
    /* At most 3m edges; the arrays are sized for that and the count is exact after the pass. */
    t->edge_vertex = (int32_t *)cloth__alloc_array(&a, (size_t)m * 3, 2 * sizeof(int32_t));
    t->edge_face = (int32_t *)cloth__alloc_array(&a, (size_t)m * 3, 2 * sizeof(int32_t));
    t->edge_opposite = (int32_t *)cloth__alloc_array(&a, (size_t)m * 3, 2 * sizeof(int32_t));
    t->face_edge = (int32_t *)cloth__alloc_array(&a, (size_t)m, 3 * sizeof(int32_t));
    t->vertex_face_start = (int32_t *)cloth__alloc_array(&a, (size_t)n + 1, sizeof(int32_t));
    t->vertex_face = (int32_t *)cloth__alloc_array(&a, (size_t)m, 3 * sizeof(int32_t));
    if (!t->edge_vertex || !t->edge_face || !t->edge_opposite || !t->face_edge || !t->vertex_face_start || !t->vertex_face) {
        r = CLOTH_ERROR_OUT_OF_MEMORY;
        goto fail;
    }
    for (v = 0; v < n; ++v) {
        int32_t first_edge = edges, s;
        for (s = b.start[v]; s < b.start[v + 1]; ++s) {
            int32_t hi = b.he_hi[s], code = b.he_code[s], face = code / 3, k = code % 3, slot;
            int32_t forward = mesh->tri[3 * face + k] == v; /* traverses lo -> hi */
            int32_t opposite = mesh->tri[3 * face + (k + 2) % 3];
            for (e = first_edge; e < edges; ++e)
                if (t->edge_vertex[2 * e + 1] == hi) break;
            if (e == edges) {
                t->edge_vertex[2 * e] = v;
                t->edge_vertex[2 * e + 1] = hi;
                t->edge_face[2 * e] = t->edge_face[2 * e + 1] = -1;
                t->edge_opposite[2 * e] = t->edge_opposite[2 * e + 1] = -1;
                ++edges;
            }
            t->face_edge[code] = e;
            if (t->edge_face[2 * e] < 0) slot = 0;
            else if (t->edge_face[2 * e + 1] < 0) slot = 1;
            else continue; /* a third face: counted below, not stored */
            t->edge_face[2 * e + slot] = face;
            t->edge_opposite[2 * e + slot] = opposite;
            /* Keep the face that runs lo -> hi in slot 0 when the edge has one. */
            if (slot == 1 && forward) {
                int32_t tf = t->edge_face[2 * e], to = t->edge_opposite[2 * e];
                t->edge_face[2 * e] = t->edge_face[2 * e + 1];
                t->edge_opposite[2 * e] = t->edge_opposite[2 * e + 1];
                t->edge_face[2 * e + 1] = tf;
                t->edge_opposite[2 * e + 1] = to;
            }
        }
        /* Edges of this bucket with more than two faces. */
        for (e = first_edge; e < edges; ++e) {
            int32_t faces = 0;
            for (s = b.start[v]; s < b.start[v + 1]; ++s) faces += b.he_hi[s] == t->edge_vertex[2 * e + 1];
            if (faces > 2) t->nonmanifold_edge_count++;
        }
    }
    t->edge_count = edges;
    /* Vertex to faces. */
    memset(t->vertex_face_start, 0, ((size_t)n + 1) * sizeof(int32_t));
    for (i = 0; i < 3 * m; ++i) t->vertex_face_start[mesh->tri[i] + 1]++;
    for (v = 0; v < n; ++v) t->vertex_face_start[v + 1] += t->vertex_face_start[v];
    for (f = 0; f < m; ++f) {
        int k;
        for (k = 0; k < 3; ++k) t->vertex_face[t->vertex_face_start[mesh->tri[3 * f + k]]++] = f;
    }
    for (v = n; v > 0; --v) t->vertex_face_start[v] = t->vertex_face_start[v - 1];
    t->vertex_face_start[0] = 0;
    /* Boundary edges and loops. */
    for (e = 0; e < edges; ++e)
        if (t->edge_face[2 * e + 1] < 0) t->boundary_edge_count++;
    t->boundary_edge = (int32_t *)cloth__alloc_array(&a, (size_t)t->boundary_edge_count, sizeof(int32_t));
    if (!t->boundary_edge) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
    for (e = 0, i = 0; e < edges; ++e)
        if (t->edge_face[2 * e + 1] < 0) t->boundary_edge[i++] = e;
    r = cloth__topology_loops(t, mesh, &a);
    if (r != CLOTH_SUCCESS) goto fail;
    cloth__edge_buckets_free(&a, &b);
    return CLOTH_SUCCESS;
fail:
    cloth__edge_buckets_free(&a, &b);
    cloth_topology_free(t);
    return r;
}

CLOTH_API int32_t cloth_topology_find_edge(const cloth_topology *t, int32_t a, int32_t b)
{
    int32_t s, lo = a < b ? a : b, hi = a < b ? b : a;
    CLOTH_ASSERT(t);
    if (a < 0 || b < 0 || a >= t->vertex_count || b >= t->vertex_count) return -1;
    for (s = t->vertex_face_start[a]; s < t->vertex_face_start[a + 1]; ++s) {
        int k;
        for (k = 0; k < 3; ++k) {
            int32_t e = t->face_edge[3 * t->vertex_face[s] + k];
            if (t->edge_vertex[2 * e] == lo && t->edge_vertex[2 * e + 1] == hi) return e;
        }
    }
    return -1;
}

/* 2 area / (longest edge)^2 of a triangle in 3D: 0 for a degenerate one, sqrt(3)/2 at best. */
static cloth_real cloth__triangle_quality3(const cloth_real *p0, const cloth_real *p1, const cloth_real *p2)
{
    cloth_real e0[3], e1[3], e2[3], n[3], l0, l1, l2, lmax;
    cloth__v3_sub(p1, p0, e0);
    cloth__v3_sub(p2, p1, e1);
    cloth__v3_sub(p0, p2, e2);
    cloth__v3_cross(e0, e2, n);
    l0 = cloth__v3_dot(e0, e0);
    l1 = cloth__v3_dot(e1, e1);
    l2 = cloth__v3_dot(e2, e2);
    lmax = l0 > l1 ? (l0 > l2 ? l0 : l2) : (l1 > l2 ? l1 : l2);
    return lmax > 0 ? cloth__v3_norm(n) / lmax : 0;
}

static cloth_real cloth__triangle_quality2(const cloth_real *p0, const cloth_real *p1, const cloth_real *p2)
{
    cloth_real ax = p1[0] - p0[0], ay = p1[1] - p0[1], bx = p2[0] - p0[0], by = p2[1] - p0[1];
    cloth_real cx = p2[0] - p1[0], cy = p2[1] - p1[1];
    cloth_real l0 = ax * ax + ay * ay, l1 = bx * bx + by * by, l2 = cx * cx + cy * cy;
    cloth_real lmax = l0 > l1 ? (l0 > l2 ? l0 : l2) : (l1 > l2 ? l1 : l2);
    cloth_real twice_area = ax * by - ay * bx;
    return lmax > 0 ? (twice_area < 0 ? -twice_area : twice_area) / lmax : 0;
}

static void cloth__report_set(cloth_mesh_report *rep, cloth_result r, int32_t tri, int32_t other, int32_t vertex)
{
    rep->result = r;
    rep->triangle = tri;
    rep->other_triangle = other;
    rep->vertex = vertex;
}

CLOTH_API cloth_result cloth_mesh_validate(const cloth_mesh *mesh, cloth_real quality_tolerance,
                                           cloth_mesh_report *report, const cloth_allocator *scratch)
{
    cloth_mesh_report local;
    cloth_mesh_report *rep = report ? report : &local;
    cloth_allocator a;
    cloth__edge_buckets b;
    unsigned char *referenced;
    int32_t n, m, v, f, i;
    int32_t dup[2] = { -1, -1 }, nonmanifold[2] = { -1, -1 }, orient[2] = { -1, -1 };
    cloth_real tol = quality_tolerance > 0 ? quality_tolerance : (cloth_real)CLOTH_MESH_QUALITY_TOLERANCE;
    cloth_result r;
    CLOTH_ASSERT(mesh);
    memset(rep, 0, sizeof *rep);
    cloth__report_set(rep, CLOTH_SUCCESS, -1, -1, -1);
    rep->first_unreferenced_vertex = -1;
    n = mesh->vertex_count;
    m = mesh->triangle_count;
    if (n < 0 || m < 0 || (n > 0 && !mesh->x) || (m > 0 && !mesh->tri)) {
        rep->result = CLOTH_ERROR_INVALID_ARGUMENT;
        return rep->result;
    }
    if (n == 0 || m == 0) {
        rep->result = CLOTH_ERROR_EMPTY_MESH;
        return rep->result;
    }
    a = cloth__allocator_or_default(scratch);
    /* 1. Numbers. */
    for (v = 0; v < n; ++v) {
        int ok = cloth__is_finite(mesh->x[3 * v]) && cloth__is_finite(mesh->x[3 * v + 1]) && cloth__is_finite(mesh->x[3 * v + 2]);
        if (ok && mesh->uv) ok = cloth__is_finite(mesh->uv[2 * v]) && cloth__is_finite(mesh->uv[2 * v + 1]);
        if (!ok) { cloth__report_set(rep, CLOTH_ERROR_NOT_FINITE, -1, -1, v); return rep->result; }
    }
    /* 2. Indices. */
    f = cloth__first_bad_index(mesh, &v);
    if (f >= 0) { cloth__report_set(rep, CLOTH_ERROR_INDEX_OUT_OF_RANGE, f, -1, v); return rep->result; }
    /* Unreferenced vertices: counted, not an error. */
    referenced = (unsigned char *)cloth__alloc_array(&a, (size_t)n, 1);
    if (!referenced) { rep->result = CLOTH_ERROR_OUT_OF_MEMORY; return rep->result; }
    memset(referenced, 0, (size_t)n);
    for (i = 0; i < 3 * m; ++i) referenced[mesh->tri[i]] = 1;
    for (v = 0; v < n; ++v)
        if (!referenced[v]) {
            if (rep->first_unreferenced_vertex < 0) rep->first_unreferenced_vertex = v;
            rep->unreferenced_vertex_count++;
        }
    cloth__free(&a, referenced);
    /* 3. Degenerate triangles, world and rest. */
    f = cloth__first_repeated_vertex(mesh);
    if (f >= 0) { cloth__report_set(rep, CLOTH_ERROR_DEGENERATE_TRIANGLE, f, -1, -1); return rep->result; }
    rep->min_quality_world = (cloth_real)1;
    rep->min_quality_rest = mesh->uv ? (cloth_real)1 : (cloth_real)0;
    for (f = 0; f < m; ++f) {
        const int32_t *t = mesh->tri + 3 * f;
        cloth_real q = cloth__triangle_quality3(mesh->x + 3 * t[0], mesh->x + 3 * t[1], mesh->x + 3 * t[2]);
        if (q < rep->min_quality_world) rep->min_quality_world = q;
        if (mesh->uv) {
            cloth_real qr = cloth__triangle_quality2(mesh->uv + 2 * t[0], mesh->uv + 2 * t[1], mesh->uv + 2 * t[2]);
            if (qr < rep->min_quality_rest) rep->min_quality_rest = qr;
            if (qr <= tol && rep->result == CLOTH_SUCCESS) cloth__report_set(rep, CLOTH_ERROR_DEGENERATE_TRIANGLE, f, -1, -1);
        }
        if (q <= tol && rep->result == CLOTH_SUCCESS) cloth__report_set(rep, CLOTH_ERROR_DEGENERATE_TRIANGLE, f, -1, -1);
    }
    if (rep->result != CLOTH_SUCCESS) return rep->result;
    /* 4-6. Duplicate faces, non-manifold edges, orientation: from the faces of each edge. */
    r = cloth__edge_buckets_build(&a, mesh, &b);
    if (r != CLOTH_SUCCESS) { rep->result = r; return r; }
    for (v = 0; v < n; ++v) {
        int32_t s, s2;
        for (s = b.start[v]; s < b.start[v + 1]; ++s) {
            int32_t fa = b.he_code[s] / 3, ka = b.he_code[s] % 3, count = 1;
            int32_t dir_a = mesh->tri[3 * fa + ka] == v, opp_a = mesh->tri[3 * fa + (ka + 2) % 3];
            int first = 1;
            /* Only the first half-edge of each edge in the bucket starts the comparison. */
            for (s2 = b.start[v]; s2 < s; ++s2)
                if (b.he_hi[s2] == b.he_hi[s]) { first = 0; break; }
            for (s2 = s + 1; s2 < b.start[v + 1]; ++s2) {
                int32_t fb, kb, dir_b, opp_b;
                if (b.he_hi[s2] != b.he_hi[s]) continue;
                fb = b.he_code[s2] / 3;
                kb = b.he_code[s2] % 3;
                dir_b = mesh->tri[3 * fb + kb] == v;
                opp_b = mesh->tri[3 * fb + (kb + 2) % 3];
                ++count;
                if (opp_a == opp_b && dup[0] < 0) { dup[0] = fa; dup[1] = fb; }
                if (dir_a == dir_b && orient[0] < 0) { orient[0] = fa; orient[1] = fb; }
            }
            if (first && count > 2 && nonmanifold[0] < 0) { nonmanifold[0] = fa; nonmanifold[1] = v; }
        }
    }
    cloth__edge_buckets_free(&a, &b);
    if (dup[0] >= 0) cloth__report_set(rep, CLOTH_ERROR_DUPLICATE_FACE, dup[0], dup[1], -1);
    else if (nonmanifold[0] >= 0) cloth__report_set(rep, CLOTH_ERROR_NON_MANIFOLD_EDGE, nonmanifold[0], -1, nonmanifold[1]);
    else if (orient[0] >= 0) cloth__report_set(rep, CLOTH_ERROR_INCONSISTENT_ORIENTATION, orient[0], orient[1], -1);
    return rep->result;
}

/* ---- generators ---------------------------------------------------------------------- */

/* Counts as int64 checked against int32 before allocation. */
static cloth_result cloth__mesh_alloc_checked(cloth_mesh *mesh, int64_t vertices, int64_t triangles, int with_uv,
                                              const cloth_allocator *allocator)
{
    memset(mesh, 0, sizeof *mesh);
    if (vertices > INT32_MAX || triangles > INT32_MAX / 3) return CLOTH_ERROR_SIZE_OVERFLOW;
    return cloth_mesh_alloc(mesh, (int32_t)vertices, (int32_t)triangles, with_uv, allocator);
}

static void cloth__set_tri(int32_t *t, int32_t a, int32_t b, int32_t c) { t[0] = a; t[1] = b; t[2] = c; }

CLOTH_API cloth_result cloth_mesh_grid(cloth_mesh *mesh, int32_t nx, int32_t ny, cloth_real width, cloth_real depth,
                                       cloth_grid_diagonal diagonal, const cloth_allocator *allocator)
{
    int32_t i, j;
    int32_t *t;
    cloth_result r;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (nx < 2 || ny < 2 || !(width > 0) || !(depth > 0) || !cloth__is_finite(width) || !cloth__is_finite(depth) ||
        (diagonal != CLOTH_GRID_DIAGONAL_REGULAR && diagonal != CLOTH_GRID_DIAGONAL_ALTERNATING))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    r = cloth__mesh_alloc_checked(mesh, (int64_t)nx * ny, (int64_t)2 * (nx - 1) * (ny - 1), 1, allocator);
    if (r != CLOTH_SUCCESS) return r;
    for (j = 0; j < ny; ++j)
        for (i = 0; i < nx; ++i) {
            int32_t v = j * nx + i;
            cloth_real u = width * (cloth_real)i / (cloth_real)(nx - 1), w = depth * (cloth_real)j / (cloth_real)(ny - 1);
            mesh->uv[2 * v] = u;
            mesh->uv[2 * v + 1] = depth - w;
            mesh->x[3 * v] = u - width / 2;
            mesh->x[3 * v + 1] = 0;
            mesh->x[3 * v + 2] = w - depth / 2;
        }
    t = mesh->tri;
    for (j = 0; j + 1 < ny; ++j)
        for (i = 0; i + 1 < nx; ++i) {
            int32_t a = j * nx + i, b = a + 1, c = a + nx + 1, d = a + nx;
            if (diagonal == CLOTH_GRID_DIAGONAL_REGULAR || ((i + j) & 1) == 0) {
                cloth__set_tri(t, a, c, b);
                cloth__set_tri(t + 3, a, d, c);
            } else {
                cloth__set_tri(t, a, d, b);
                cloth__set_tri(t + 3, b, d, c);
            }
            t += 6;
        }
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_mesh_disc(cloth_mesh *mesh, cloth_real radius, int32_t rings, int32_t segments,
                                       const cloth_allocator *allocator)
{
    int64_t vertices, triangles;
    int32_t r, j, *t;
    cloth_result res;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (!(radius > 0) || !cloth__is_finite(radius) || rings < 1 || segments < 3 || rings > 1000000 || segments > 1000000)
        return CLOTH_ERROR_INVALID_ARGUMENT;
    vertices = 1 + (int64_t)segments * rings * (rings + 1) / 2;
    triangles = (int64_t)segments * rings * rings;
    res = cloth__mesh_alloc_checked(mesh, vertices, triangles, 1, allocator);
    if (res != CLOTH_SUCCESS) return res;
    /* Ring r (1..rings) holds r * segments vertices, counter-clockwise seen from +y
       (x = rho cos phi, z = -rho sin phi); the centre is vertex 0. */
    mesh->x[0] = mesh->x[1] = mesh->x[2] = 0;
    for (r = 1; r <= rings; ++r) {
        int32_t count = r * segments, base = (int32_t)(1 + (int64_t)segments * (r - 1) * r / 2);
        cloth_real rho = radius * (cloth_real)r / (cloth_real)rings;
        for (j = 0; j < count; ++j) {
            double phi = 6.283185307179586 * (double)j / (double)count;
            cloth_real *p = mesh->x + 3 * (base + j);
            p[0] = rho * (cloth_real)cos(phi);
            p[1] = 0;
            p[2] = -rho * (cloth_real)sin(phi);
        }
    }
    for (j = 0; j < (int32_t)vertices; ++j) {
        mesh->uv[2 * j] = mesh->x[3 * j] + radius;
        mesh->uv[2 * j + 1] = radius - mesh->x[3 * j + 2];
    }
    t = mesh->tri;
    for (j = 0; j < segments; ++j, t += 3) cloth__set_tri(t, 0, 1 + j, 1 + (j + 1) % segments);
    for (r = 2; r <= rings; ++r) {
        /* Zip ring r-1 (n0 vertices) to ring r (n1), advancing whichever has the smaller next angle
           (compared exactly in integers). */
        int32_t n0 = (r - 1) * segments, n1 = r * segments;
        int32_t b0 = (int32_t)(1 + (int64_t)segments * (r - 2) * (r - 1) / 2);
        int32_t b1 = (int32_t)(1 + (int64_t)segments * (r - 1) * r / 2), i = 0, k = 0;
        while (i < n0 || k < n1) {
            if (k >= n1 || (i < n0 && (int64_t)(i + 1) * n1 <= (int64_t)(k + 1) * n0)) {
                cloth__set_tri(t, b0 + i, b1 + k % n1, b0 + (i + 1) % n0);
                ++i;
            } else {
                cloth__set_tri(t, b0 + i % n0, b1 + k, b1 + (k + 1) % n1);
                ++k;
            }
            t += 3;
        }
    }
    return CLOTH_SUCCESS;
}

/* Flip every triangle whose normal points towards the origin (for convex closed shapes
   around the origin), so that all face outward. */
static void cloth__orient_outward(cloth_mesh *mesh)
{
    int32_t f;
    for (f = 0; f < mesh->triangle_count; ++f) {
        int32_t *t = mesh->tri + 3 * f;
        cloth_real e0[3], e1[3], n[3], c[3];
        cloth__v3_sub(mesh->x + 3 * t[1], mesh->x + 3 * t[0], e0);
        cloth__v3_sub(mesh->x + 3 * t[2], mesh->x + 3 * t[0], e1);
        cloth__v3_cross(e0, e1, n);
        cloth__v3_add(mesh->x + 3 * t[0], mesh->x + 3 * t[1], c);
        cloth__v3_add(c, mesh->x + 3 * t[2], c);
        if (cloth__v3_dot(n, c) < 0) { int32_t s = t[1]; t[1] = t[2]; t[2] = s; }
    }
}

CLOTH_API cloth_result cloth_mesh_icosphere(cloth_mesh *mesh, cloth_real radius, int32_t subdivisions,
                                            const cloth_allocator *allocator)
{
    static const signed char ico_tri[20][3] = {
        {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6},
        {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10},
        {8, 6, 7}, {9, 8, 1}};
    const double g = 1.6180339887498949; /* golden ratio */
    const double ico_x[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    cloth_mesh cur;
    cloth_result r;
    int32_t i, level;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (!(radius > 0) || !cloth__is_finite(radius) || subdivisions < 0 || subdivisions > 10) return CLOTH_ERROR_INVALID_ARGUMENT;
    r = cloth_mesh_alloc(&cur, 12, 20, 0, allocator);
    if (r != CLOTH_SUCCESS) return r;
    for (i = 0; i < 12; ++i) {
        double len = sqrt(ico_x[i][0] * ico_x[i][0] + ico_x[i][1] * ico_x[i][1] + ico_x[i][2] * ico_x[i][2]);
        cur.x[3 * i] = (cloth_real)(radius * ico_x[i][0] / len);
        cur.x[3 * i + 1] = (cloth_real)(radius * ico_x[i][1] / len);
        cur.x[3 * i + 2] = (cloth_real)(radius * ico_x[i][2] / len);
    }
    for (i = 0; i < 60; ++i) cur.tri[i] = ico_tri[i / 3][i % 3];
    cloth__orient_outward(&cur);
    for (level = 0; level < subdivisions; ++level) {
        cloth_mesh fine;
        r = cloth_mesh_subdivide(&fine, NULL, &cur, allocator);
        cloth_mesh_free(&cur);
        if (r != CLOTH_SUCCESS) return r;
        for (i = 0; i < fine.vertex_count; ++i) {
            cloth_real *p = fine.x + 3 * i;
            cloth__v3_scale(p, radius / cloth__v3_norm(p), p);
        }
        cur = fine;
    }
    *mesh = cur;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_mesh_capsule(cloth_mesh *mesh, cloth_real radius, cloth_real length, int32_t segments,
                                          int32_t rings, const cloth_allocator *allocator)
{
    /* Rings of `segments` vertices from the -x pole to the +x pole: `rings` on the -x cap
       (the last one the cap's equator), the same mirrored on the +x cap (the equator shared
       when length is 0), and the two poles last. */
    int32_t ring_count, r, j, *t;
    int64_t vertices, triangles;
    cloth_result res;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (!(radius > 0) || !cloth__is_finite(radius) || !(length >= 0) || !cloth__is_finite(length) || segments < 3 ||
        rings < 1 || segments > 1000000 || rings > 1000000)
        return CLOTH_ERROR_INVALID_ARGUMENT;
    ring_count = length > 0 ? 2 * rings : 2 * rings - 1;
    vertices = (int64_t)ring_count * segments + 2;
    triangles = (int64_t)2 * segments * (ring_count - 1) + 2 * (int64_t)segments;
    res = cloth__mesh_alloc_checked(mesh, vertices, triangles, 0, allocator);
    if (res != CLOTH_SUCCESS) return res;
    for (r = 0; r < ring_count; ++r) {
        /* Polar angle from the -x pole for the first cap, mirrored for the second. */
        int32_t k = r < rings ? r + 1 : ring_count - r;
        double polar = 1.5707963267948966 * (double)k / (double)rings;
        double cx = r < rings ? -(double)length / 2 - radius * cos(polar) : (double)length / 2 + radius * cos(polar);
        double rho = radius * sin(polar);
        for (j = 0; j < segments; ++j) {
            double theta = 6.283185307179586 * (double)j / (double)segments;
            cloth_real *p = mesh->x + 3 * (r * segments + j);
            p[0] = (cloth_real)cx;
            p[1] = (cloth_real)(rho * cos(theta));
            p[2] = (cloth_real)(rho * sin(theta));
        }
    }
    {
        int32_t pole0 = ring_count * segments, pole1 = pole0 + 1;
        cloth_real *p0 = mesh->x + 3 * pole0, *p1 = mesh->x + 3 * pole1;
        p0[0] = -length / 2 - radius; p0[1] = 0; p0[2] = 0;
        p1[0] = length / 2 + radius; p1[1] = 0; p1[2] = 0;
        t = mesh->tri;
        for (r = 0; r + 1 < ring_count; ++r)
            for (j = 0; j < segments; ++j) {
                int32_t a = r * segments + j, b = r * segments + (j + 1) % segments;
                int32_t c = a + segments, d = b + segments;
                cloth__set_tri(t, a, b, d);
                cloth__set_tri(t + 3, a, d, c);
                t += 6;
            }
        for (j = 0; j < segments; ++j) {
            cloth__set_tri(t, pole0, (j + 1) % segments, j);
            t += 3;
            cloth__set_tri(t, pole1, (ring_count - 1) * segments + j, (ring_count - 1) * segments + (j + 1) % segments);
            t += 3;
        }
    }
    cloth__orient_outward(mesh);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_mesh_box(cloth_mesh *mesh, cloth_real hx, cloth_real hy, cloth_real hz, int32_t n,
                                      const cloth_allocator *allocator)
{
    /* The surface points of an (n+1)^3 lattice, numbered through a lattice-sized index map. */
    int64_t side = (int64_t)n + 1, lattice, vertices, triangles;
    int32_t *index = NULL, *t, count = 0, i, j, k, axis;
    cloth_allocator a;
    cloth_result res;
    CLOTH_ASSERT(mesh);
    memset(mesh, 0, sizeof *mesh);
    if (!(hx > 0) || !(hy > 0) || !(hz > 0) || !cloth__is_finite(hx) || !cloth__is_finite(hy) || !cloth__is_finite(hz) ||
        n < 1 || n > 128)
        return CLOTH_ERROR_INVALID_ARGUMENT;
    lattice = side * side * side;
    vertices = lattice - (side - 2) * (side - 2) * (side - 2);
    triangles = 12 * (int64_t)n * n;
    a = cloth__allocator_or_default(allocator);
    index = (int32_t *)cloth__alloc_array(&a, (size_t)lattice, sizeof(int32_t));
    if (!index) return CLOTH_ERROR_OUT_OF_MEMORY;
    res = cloth__mesh_alloc_checked(mesh, vertices, triangles, 0, allocator);
    if (res != CLOTH_SUCCESS) { cloth__free(&a, index); return res; }
    for (k = 0; k <= n; ++k)
        for (j = 0; j <= n; ++j)
            for (i = 0; i <= n; ++i) {
                int64_t l = ((int64_t)k * side + j) * side + i;
                if (i == 0 || j == 0 || k == 0 || i == n || j == n || k == n) {
                    cloth_real *p = mesh->x + 3 * count;
                    p[0] = hx * (2 * (cloth_real)i / (cloth_real)n - 1);
                    p[1] = hy * (2 * (cloth_real)j / (cloth_real)n - 1);
                    p[2] = hz * (2 * (cloth_real)k / (cloth_real)n - 1);
                    index[l] = count++;
                } else
                    index[l] = -1;
            }
    t = mesh->tri;
    /* Two faces per axis (lattice coordinate 0 and n), each n x n quads. */
    for (axis = 0; axis < 3; ++axis) {
        int32_t s;
        for (s = 0; s <= n; s += n)
            for (j = 0; j < n; ++j)
                for (i = 0; i < n; ++i) {
                    int32_t q[4], c;
                    for (c = 0; c < 4; ++c) {
                        int32_t u = i + (c == 1 || c == 2), w = j + (c >= 2), coord[3];
                        coord[axis] = s;
                        coord[(axis + 1) % 3] = u;
                        coord[(axis + 2) % 3] = w;
                        q[c] = index[((int64_t)coord[2] * side + coord[1]) * side + coord[0]];
                    }
                    cloth__set_tri(t, q[0], q[1], q[2]);
                    cloth__set_tri(t + 3, q[0], q[2], q[3]);
                    t += 6;
                }
    }
    cloth__free(&a, index);
    cloth__orient_outward(mesh);
    return CLOTH_SUCCESS;
}

/* ---- subdivision --------------------------------------------------------------------- */

CLOTH_API void cloth_upsample_map_free(cloth_upsample_map *map)
{
    cloth_allocator a;
    if (!map) return;
    a = cloth__allocator_or_default(&map->allocator);
    cloth__free(&a, map->start);
    cloth__free(&a, map->coarse_vertex);
    cloth__free(&a, map->weight);
    memset(map, 0, sizeof *map);
}

CLOTH_API cloth_result cloth_mesh_subdivide(cloth_mesh *fine, cloth_upsample_map *map, const cloth_mesh *coarse,
                                            const cloth_allocator *allocator)
{
    cloth_topology topo;
    cloth_result r;
    int32_t n, e, f, v;
    int64_t fine_vertices, fine_triangles;
    CLOTH_ASSERT(fine && coarse);
    memset(fine, 0, sizeof *fine);
    if (map) memset(map, 0, sizeof *map);
    if (coarse->vertex_count < 0 || coarse->triangle_count < 0 || (coarse->vertex_count > 0 && !coarse->x))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    r = cloth_topology_build(&topo, coarse, allocator);
    if (r != CLOTH_SUCCESS) return r;
    n = coarse->vertex_count;
    fine_vertices = (int64_t)n + topo.edge_count;
    fine_triangles = (int64_t)4 * coarse->triangle_count;
    r = cloth__mesh_alloc_checked(fine, fine_vertices, fine_triangles, coarse->uv != NULL, allocator);
    if (r != CLOTH_SUCCESS) { cloth_topology_free(&topo); return r; }
    if (n) memcpy(fine->x, coarse->x, (size_t)n * 3 * sizeof(cloth_real));
    if (coarse->uv && n) memcpy(fine->uv, coarse->uv, (size_t)n * 2 * sizeof(cloth_real));
    for (e = 0; e < topo.edge_count; ++e) {
        int32_t p = topo.edge_vertex[2 * e], q = topo.edge_vertex[2 * e + 1], k;
        for (k = 0; k < 3; ++k) fine->x[3 * (n + e) + k] = (coarse->x[3 * p + k] + coarse->x[3 * q + k]) / 2;
        if (coarse->uv)
            for (k = 0; k < 2; ++k) fine->uv[2 * (n + e) + k] = (coarse->uv[2 * p + k] + coarse->uv[2 * q + k]) / 2;
    }
    for (f = 0; f < coarse->triangle_count; ++f) {
        const int32_t *c = coarse->tri + 3 * f;
        int32_t m01 = n + topo.face_edge[3 * f], m12 = n + topo.face_edge[3 * f + 1], m20 = n + topo.face_edge[3 * f + 2];
        int32_t *t = fine->tri + 12 * f;
        cloth__set_tri(t, c[0], m01, m20);
        cloth__set_tri(t + 3, m01, c[1], m12);
        cloth__set_tri(t + 6, m20, m12, c[2]);
        cloth__set_tri(t + 9, m01, m12, m20);
    }
    if (map) {
        cloth_allocator a = cloth__allocator_or_default(allocator);
        size_t entries = (size_t)n + 2 * (size_t)topo.edge_count;
        map->allocator = a;
        map->start = (int32_t *)cloth__alloc_array(&a, (size_t)fine_vertices + 1, sizeof(int32_t));
        map->coarse_vertex = (int32_t *)cloth__alloc_array(&a, entries, sizeof(int32_t));
        map->weight = (cloth_real *)cloth__alloc_array(&a, entries, sizeof(cloth_real));
        if (!map->start || !map->coarse_vertex || !map->weight) {
            cloth_upsample_map_free(map);
            cloth_mesh_free(fine);
            cloth_topology_free(&topo);
            return CLOTH_ERROR_OUT_OF_MEMORY;
        }
        map->fine_count = (int32_t)fine_vertices;
        map->coarse_count = n;
        for (v = 0; v < n; ++v) {
            map->start[v] = v;
            map->coarse_vertex[v] = v;
            map->weight[v] = 1;
        }
        for (e = 0; e < topo.edge_count; ++e) {
            int32_t s = n + 2 * e;
            map->start[n + e] = s;
            map->coarse_vertex[s] = topo.edge_vertex[2 * e];
            map->coarse_vertex[s + 1] = topo.edge_vertex[2 * e + 1];
            map->weight[s] = map->weight[s + 1] = (cloth_real)0.5;
        }
        map->start[fine_vertices] = (int32_t)entries;
    }
    cloth_topology_free(&topo);
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_upsample_apply(const cloth_upsample_map *map, int dim, const cloth_real *in, cloth_real *out)
{
    int32_t f;
    int d;
    CLOTH_ASSERT(map && in && out && dim > 0);
    for (f = 0; f < map->fine_count; ++f) {
        int32_t s;
        for (d = 0; d < dim; ++d) out[(size_t)dim * f + d] = 0;
        for (s = map->start[f]; s < map->start[f + 1]; ++s)
            for (d = 0; d < dim; ++d)
                out[(size_t)dim * f + d] += map->weight[s] * in[(size_t)dim * map->coarse_vertex[s] + d];
    }
}

/* ------------------------------------------------------------------------------------- */
/* io                                                                                    */
/* ------------------------------------------------------------------------------------- */

/* The readers work on the whole input in memory. They go over it twice: a first pass checks
   the structure and counts vertices and triangles against the bytes that are really there,
   then the mesh is allocated once at its final size and a second pass fills it. Nothing is
   allocated per line or per number, and nothing is sized by a count that a header claims. */

#if defined(__GNUC__) || defined(__clang__)
#define CLOTH__PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define CLOTH__PRINTF_LIKE(f, a)
#endif

/* The input of a reader and where its errors go. */
typedef struct cloth__io {
    const unsigned char *begin;
    const unsigned char *end;
    cloth_io_error *error;     /* never NULL inside the readers */
    cloth_allocator allocator; /* resolved: never the NULL allocator */
} cloth__io;

/* Character classes of the text readers: 1 white space inside a line (space, \t, \r, \v,
   \f), 2 the line break \n, 4 the comment sign #. */
#define CLOTH__CHAR_BLANK 1
#define CLOTH__CHAR_BREAK 2
#define CLOTH__CHAR_COMMENT 4
static const unsigned char cloth__char_class[256] = {
    0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    1, 0, 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0
};

/* White space inside a line; white space including the line break; the end of a word in a
   line (white space, line break or #). */
static int cloth__is_blank(int c) { return cloth__char_class[c & 255] & CLOTH__CHAR_BLANK; }
static int cloth__is_space(int c) { return cloth__char_class[c & 255] & (CLOTH__CHAR_BLANK | CLOTH__CHAR_BREAK); }
static int cloth__ends_word(int c)
{
    return cloth__char_class[c & 255] & (CLOTH__CHAR_BLANK | CLOTH__CHAR_BREAK | CLOTH__CHAR_COMMENT);
}
static int cloth__is_digit(int c) { return (unsigned)(c - '0') < 10u; }
static int cloth__ascii_lower(int c) { return c >= 'A' && c <= 'Z' ? c + ('a' - 'A') : c; }

static const unsigned char *cloth__skip_blank(const unsigned char *p, const unsigned char *end)
{
    while (p < end && cloth__is_blank(*p)) ++p;
    return p;
}

static const unsigned char *cloth__skip_space(const unsigned char *p, const unsigned char *end)
{
    while (p < end && cloth__is_space(*p)) ++p;
    return p;
}

/* The end of the line that contains p: its '\n', or end. */
static const unsigned char *cloth__line_end(const unsigned char *p, const unsigned char *end)
{
    const unsigned char *nl = p < end ? (const unsigned char *)memchr(p, '\n', (size_t)(end - p)) : NULL;
    return nl ? nl : end;
}

/* The end of the white-space delimited token that starts at p. */
static const unsigned char *cloth__token_end(const unsigned char *p, const unsigned char *end)
{
    while (p < end && !cloth__is_space(*p)) ++p;
    return p;
}

/* Whether the token [p, e) is `word`, ignoring ASCII case. */
static int cloth__token_is(const unsigned char *p, const unsigned char *e, const char *word)
{
    size_t n = strlen(word), i;
    if ((size_t)(e - p) != n) return 0;
    for (i = 0; i < n; ++i)
        if (cloth__ascii_lower(p[i]) != cloth__ascii_lower((unsigned char)word[i])) return 0;
    return 1;
}

/* Whether [p, end) starts with `word`, ignoring ASCII case. */
static int cloth__starts_with(const unsigned char *p, const unsigned char *end, const char *word)
{
    size_t n = strlen(word);
    return (size_t)(end - p) >= n && cloth__token_is(p, p + n, word);
}

/* The length of a token to quote in a message: at most 24 bytes, never past a line break. */
static int cloth__quote_length(const unsigned char *p, const unsigned char *end)
{
    int n = 0;
    while (p + n < end && n < 24 && !cloth__is_space(p[n]) && p[n] != 0) ++n;
    return n;
}

/* The 1-based line of the byte at `at`. Only called when reporting an error. */
static int64_t cloth__line_of(const cloth__io *io, const unsigned char *at)
{
    int64_t line = 1;
    const unsigned char *p = io->begin;
    while (p < at) {
        const unsigned char *nl = (const unsigned char *)memchr(p, '\n', (size_t)(at - p));
        if (!nl) break;
        ++line;
        p = nl + 1;
    }
    return line;
}

/* Record why reading failed and return `result`. `at` is the place of the problem (NULL when
   it has none); `text` says whether it lies in text, where a line number means something. */
CLOTH__PRINTF_LIKE(5, 6)
static cloth_result cloth__io_fail(const cloth__io *io, cloth_result result, const unsigned char *at, int text,
                                   const char *format, ...)
{
    cloth_io_error *e = io->error;
    va_list args;
    if (at) {
        if (at > io->end) at = io->end;
        e->byte_offset = (int64_t)(at - io->begin);
        e->line = text ? cloth__line_of(io, at) : 0;
    } else {
        e->byte_offset = 0;
        e->line = 0;
    }
    va_start(args, format);
    vsnprintf(e->message, sizeof e->message, format, args);
    va_end(args);
    return result;
}

/* ---- numbers -------------------------------------------------------------------------- */

/* Decimal to double, correctly rounded, without the C library (strtod depends on the locale
   and is slow). Three paths, fastest first:
     1. the mantissa has at most 15-16 digits (< 2^53) and |exponent| <= 22: one exact
        multiplication or division of two exact doubles (Clinger);
     2. up to 19 digits and |exponent| <= 64: the Eisel-Lemire algorithm, a 64 x 128-bit
        multiplication by a truncated power of ten that proves its own rounding or gives up;
     3. anything else, or when 2. gives up: exact big-integer arithmetic (slow, rare). */

static const double cloth__exact_pow10[23] = {
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22
};

/* 10^q for q in [CLOTH__POW10_MIN, CLOTH__POW10_MAX] as a 128-bit mantissa (high word, low
   word) normalised so that the top bit is set, truncated (rounded down). Generated with exact
   integer arithmetic: floor(10^q * 2^(127 - floor(log2(10^q)))). */
#define CLOTH__POW10_MIN (-64)
#define CLOTH__POW10_MAX 64
static const uint64_t cloth__pow10_128[CLOTH__POW10_MAX - CLOTH__POW10_MIN + 1][2] = {
    { 0xA87FEA27A539E9A5ULL, 0x3F2398D747B36224ULL }, { 0xD29FE4B18E88640EULL, 0x8EEC7F0D19A03AADULL },
    { 0x83A3EEEEF9153E89ULL, 0x1953CF68300424ACULL }, { 0xA48CEAAAB75A8E2BULL, 0x5FA8C3423C052DD7ULL },
    { 0xCDB02555653131B6ULL, 0x3792F412CB06794DULL }, { 0x808E17555F3EBF11ULL, 0xE2BBD88BBEE40BD0ULL },
    { 0xA0B19D2AB70E6ED6ULL, 0x5B6ACEAEAE9D0EC4ULL }, { 0xC8DE047564D20A8BULL, 0xF245825A5A445275ULL },
    { 0xFB158592BE068D2EULL, 0xEED6E2F0F0D56712ULL }, { 0x9CED737BB6C4183DULL, 0x55464DD69685606BULL },
    { 0xC428D05AA4751E4CULL, 0xAA97E14C3C26B886ULL }, { 0xF53304714D9265DFULL, 0xD53DD99F4B3066A8ULL },
    { 0x993FE2C6D07B7FABULL, 0xE546A8038EFE4029ULL }, { 0xBF8FDB78849A5F96ULL, 0xDE98520472BDD033ULL },
    { 0xEF73D256A5C0F77CULL, 0x963E66858F6D4440ULL }, { 0x95A8637627989AADULL, 0xDDE7001379A44AA8ULL },
    { 0xBB127C53B17EC159ULL, 0x5560C018580D5D52ULL }, { 0xE9D71B689DDE71AFULL, 0xAAB8F01E6E10B4A6ULL },
    { 0x9226712162AB070DULL, 0xCAB3961304CA70E8ULL }, { 0xB6B00D69BB55C8D1ULL, 0x3D607B97C5FD0D22ULL },
    { 0xE45C10C42A2B3B05ULL, 0x8CB89A7DB77C506AULL }, { 0x8EB98A7A9A5B04E3ULL, 0x77F3608E92ADB242ULL },
    { 0xB267ED1940F1C61CULL, 0x55F038B237591ED3ULL }, { 0xDF01E85F912E37A3ULL, 0x6B6C46DEC52F6688ULL },
    { 0x8B61313BBABCE2C6ULL, 0x2323AC4B3B3DA015ULL }, { 0xAE397D8AA96C1B77ULL, 0xABEC975E0A0D081AULL },
    { 0xD9C7DCED53C72255ULL, 0x96E7BD358C904A21ULL }, { 0x881CEA14545C7575ULL, 0x7E50D64177DA2E54ULL },
    { 0xAA242499697392D2ULL, 0xDDE50BD1D5D0B9E9ULL }, { 0xD4AD2DBFC3D07787ULL, 0x955E4EC64B44E864ULL },
    { 0x84EC3C97DA624AB4ULL, 0xBD5AF13BEF0B113EULL }, { 0xA6274BBDD0FADD61ULL, 0xECB1AD8AEACDD58EULL },
    { 0xCFB11EAD453994BAULL, 0x67DE18EDA5814AF2ULL }, { 0x81CEB32C4B43FCF4ULL, 0x80EACF948770CED7ULL },
    { 0xA2425FF75E14FC31ULL, 0xA1258379A94D028DULL }, { 0xCAD2F7F5359A3B3EULL, 0x096EE45813A04330ULL },
    { 0xFD87B5F28300CA0DULL, 0x8BCA9D6E188853FCULL }, { 0x9E74D1B791E07E48ULL, 0x775EA264CF55347DULL },
    { 0xC612062576589DDAULL, 0x95364AFE032A819DULL }, { 0xF79687AED3EEC551ULL, 0x3A83DDBD83F52204ULL },
    { 0x9ABE14CD44753B52ULL, 0xC4926A9672793542ULL }, { 0xC16D9A0095928A27ULL, 0x75B7053C0F178293ULL },
    { 0xF1C90080BAF72CB1ULL, 0x5324C68B12DD6338ULL }, { 0x971DA05074DA7BEEULL, 0xD3F6FC16EBCA5E03ULL },
    { 0xBCE5086492111AEAULL, 0x88F4BB1CA6BCF584ULL }, { 0xEC1E4A7DB69561A5ULL, 0x2B31E9E3D06C32E5ULL },
    { 0x9392EE8E921D5D07ULL, 0x3AFF322E62439FCFULL }, { 0xB877AA3236A4B449ULL, 0x09BEFEB9FAD487C2ULL },
    { 0xE69594BEC44DE15BULL, 0x4C2EBE687989A9B3ULL }, { 0x901D7CF73AB0ACD9ULL, 0x0F9D37014BF60A10ULL },
    { 0xB424DC35095CD80FULL, 0x538484C19EF38C94ULL }, { 0xE12E13424BB40E13ULL, 0x2865A5F206B06FB9ULL },
    { 0x8CBCCC096F5088CBULL, 0xF93F87B7442E45D3ULL }, { 0xAFEBFF0BCB24AAFEULL, 0xF78F69A51539D748ULL },
    { 0xDBE6FECEBDEDD5BEULL, 0xB573440E5A884D1BULL }, { 0x89705F4136B4A597ULL, 0x31680A88F8953030ULL },
    { 0xABCC77118461CEFCULL, 0xFDC20D2B36BA7C3DULL }, { 0xD6BF94D5E57A42BCULL, 0x3D32907604691B4CULL },
    { 0x8637BD05AF6C69B5ULL, 0xA63F9A49C2C1B10FULL }, { 0xA7C5AC471B478423ULL, 0x0FCF80DC33721D53ULL },
    { 0xD1B71758E219652BULL, 0xD3C36113404EA4A8ULL }, { 0x83126E978D4FDF3BULL, 0x645A1CAC083126E9ULL },
    { 0xA3D70A3D70A3D70AULL, 0x3D70A3D70A3D70A3ULL }, { 0xCCCCCCCCCCCCCCCCULL, 0xCCCCCCCCCCCCCCCCULL },
    { 0x8000000000000000ULL, 0x0000000000000000ULL }, { 0xA000000000000000ULL, 0x0000000000000000ULL },
    { 0xC800000000000000ULL, 0x0000000000000000ULL }, { 0xFA00000000000000ULL, 0x0000000000000000ULL },
    { 0x9C40000000000000ULL, 0x0000000000000000ULL }, { 0xC350000000000000ULL, 0x0000000000000000ULL },
    { 0xF424000000000000ULL, 0x0000000000000000ULL }, { 0x9896800000000000ULL, 0x0000000000000000ULL },
    { 0xBEBC200000000000ULL, 0x0000000000000000ULL }, { 0xEE6B280000000000ULL, 0x0000000000000000ULL },
    { 0x9502F90000000000ULL, 0x0000000000000000ULL }, { 0xBA43B74000000000ULL, 0x0000000000000000ULL },
    { 0xE8D4A51000000000ULL, 0x0000000000000000ULL }, { 0x9184E72A00000000ULL, 0x0000000000000000ULL },
    { 0xB5E620F480000000ULL, 0x0000000000000000ULL }, { 0xE35FA931A0000000ULL, 0x0000000000000000ULL },
    { 0x8E1BC9BF04000000ULL, 0x0000000000000000ULL }, { 0xB1A2BC2EC5000000ULL, 0x0000000000000000ULL },
    { 0xDE0B6B3A76400000ULL, 0x0000000000000000ULL }, { 0x8AC7230489E80000ULL, 0x0000000000000000ULL },
    { 0xAD78EBC5AC620000ULL, 0x0000000000000000ULL }, { 0xD8D726B7177A8000ULL, 0x0000000000000000ULL },
    { 0x878678326EAC9000ULL, 0x0000000000000000ULL }, { 0xA968163F0A57B400ULL, 0x0000000000000000ULL },
    { 0xD3C21BCECCEDA100ULL, 0x0000000000000000ULL }, { 0x84595161401484A0ULL, 0x0000000000000000ULL },
    { 0xA56FA5B99019A5C8ULL, 0x0000000000000000ULL }, { 0xCECB8F27F4200F3AULL, 0x0000000000000000ULL },
    { 0x813F3978F8940984ULL, 0x4000000000000000ULL }, { 0xA18F07D736B90BE5ULL, 0x5000000000000000ULL },
    { 0xC9F2C9CD04674EDEULL, 0xA400000000000000ULL }, { 0xFC6F7C4045812296ULL, 0x4D00000000000000ULL },
    { 0x9DC5ADA82B70B59DULL, 0xF020000000000000ULL }, { 0xC5371912364CE305ULL, 0x6C28000000000000ULL },
    { 0xF684DF56C3E01BC6ULL, 0xC732000000000000ULL }, { 0x9A130B963A6C115CULL, 0x3C7F400000000000ULL },
    { 0xC097CE7BC90715B3ULL, 0x4B9F100000000000ULL }, { 0xF0BDC21ABB48DB20ULL, 0x1E86D40000000000ULL },
    { 0x96769950B50D88F4ULL, 0x1314448000000000ULL }, { 0xBC143FA4E250EB31ULL, 0x17D955A000000000ULL },
    { 0xEB194F8E1AE525FDULL, 0x5DCFAB0800000000ULL }, { 0x92EFD1B8D0CF37BEULL, 0x5AA1CAE500000000ULL },
    { 0xB7ABC627050305ADULL, 0xF14A3D9E40000000ULL }, { 0xE596B7B0C643C719ULL, 0x6D9CCD05D0000000ULL },
    { 0x8F7E32CE7BEA5C6FULL, 0xE4820023A2000000ULL }, { 0xB35DBF821AE4F38BULL, 0xDDA2802C8A800000ULL },
    { 0xE0352F62A19E306EULL, 0xD50B2037AD200000ULL }, { 0x8C213D9DA502DE45ULL, 0x4526F422CC340000ULL },
    { 0xAF298D050E4395D6ULL, 0x9670B12B7F410000ULL }, { 0xDAF3F04651D47B4CULL, 0x3C0CDD765F114000ULL },
    { 0x88D8762BF324CD0FULL, 0xA5880A69FB6AC800ULL }, { 0xAB0E93B6EFEE0053ULL, 0x8EEA0D047A457A00ULL },
    { 0xD5D238A4ABE98068ULL, 0x72A4904598D6D880ULL }, { 0x85A36366EB71F041ULL, 0x47A6DA2B7F864750ULL },
    { 0xA70C3C40A64E6C51ULL, 0x999090B65F67D924ULL }, { 0xD0CF4B50CFE20765ULL, 0xFFF4B4E3F741CF6DULL },
    { 0x82818F1281ED449FULL, 0xBFF8F10E7A8921A4ULL }, { 0xA321F2D7226895C7ULL, 0xAFF72D52192B6A0DULL },
    { 0xCBEA6F8CEB02BB39ULL, 0x9BF4F8A69F764490ULL }, { 0xFEE50B7025C36A08ULL, 0x02F236D04753D5B4ULL },
    { 0x9F4F2726179A2245ULL, 0x01D762422C946590ULL }, { 0xC722F0EF9D80AAD6ULL, 0x424D3AD2B7B97EF5ULL },
    { 0xF8EBAD2B84E0D58BULL, 0xD2E0898765A7DEB2ULL }, { 0x9B934C3B330C8577ULL, 0x63CC55F49F88EB2FULL },
    { 0xC2781F49FFCFA6D5ULL, 0x3CBF6B71C76B25FBULL },
};

static int cloth__clz64(uint64_t x) /* x != 0 */
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_clzll((unsigned long long)x);
#else
    int n = 0;
    while (!(x & 0x8000000000000000ULL)) { x <<= 1; ++n; }
    return n;
#endif
}

/* The full 128-bit product of two 64-bit numbers (one instruction where the compiler has a
   128-bit type, four 32-bit products elsewhere). */
#if defined(__SIZEOF_INT128__) && (defined(__GNUC__) || defined(__clang__))
__extension__ typedef unsigned __int128 cloth__uint128;
static void cloth__mul_64x64(uint64_t a, uint64_t b, uint64_t *hi, uint64_t *lo)
{
    cloth__uint128 p = (cloth__uint128)a * b;
    *hi = (uint64_t)(p >> 64);
    *lo = (uint64_t)p;
}
#else
static void cloth__mul_64x64(uint64_t a, uint64_t b, uint64_t *hi, uint64_t *lo)
{
    uint64_t a0 = a & 0xFFFFFFFFu, a1 = a >> 32, b0 = b & 0xFFFFFFFFu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
    *lo = (mid << 32) | (p00 & 0xFFFFFFFFu);
    *hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
}
#endif

/* floor(q * log2(10)) for |q| < 1000, as 217706 / 2^16 approximates log2(10). */
static int cloth__floor_log2_pow10(int q)
{
    long v = 217706L * q;
    return v >= 0 ? (int)(v >> 16) : -(int)((-v + 65535) >> 16);
}

/* Eisel-Lemire: w * 10^q for 0 < w < 2^64 into *out, or 0 when it cannot decide (the exponent
   is outside the table, the result is subnormal or infinite, or too close to a halfway point). */
static int cloth__eisel_lemire(uint64_t w, int q, int negative, double *out)
{
    const uint64_t *t;
    uint64_t hi, lo, mantissa, bits;
    int shift, msb;
    long e2;
    if (q < CLOTH__POW10_MIN || q > CLOTH__POW10_MAX || w == 0) return 0;
    t = cloth__pow10_128[q - CLOTH__POW10_MIN];
    shift = cloth__clz64(w);
    w <<= shift;
    e2 = (long)cloth__floor_log2_pow10(q) + 64 + 1023 - shift;
    cloth__mul_64x64(w, t[0], &hi, &lo);
    if ((hi & 0x1FF) == 0x1FF && lo + w < w) {
        /* The truncation of the table may matter: bring in its low word. */
        uint64_t yhi, ylo, mhi = hi, mlo;
        cloth__mul_64x64(w, t[1], &yhi, &ylo);
        mlo = lo + yhi;
        if (mlo < lo) ++mhi;
        if ((mhi & 0x1FF) == 0x1FF && mlo + 1 == 0 && ylo + w < w) return 0;
        hi = mhi;
        lo = mlo;
    }
    msb = (int)(hi >> 63);
    mantissa = hi >> (msb + 9);
    e2 -= 1 ^ msb;
    if (lo == 0 && (hi & 0x1FF) == 0 && (mantissa & 3) == 1) return 0; /* maybe exactly halfway */
    mantissa += mantissa & 1;
    mantissa >>= 1;
    if (mantissa >> 53) {
        mantissa >>= 1;
        ++e2;
    }
    if (e2 <= 0 || e2 >= 0x7FF) return 0;
    bits = ((uint64_t)e2 << 52) | (mantissa & 0xFFFFFFFFFFFFFULL);
    if (negative) bits |= 0x8000000000000000ULL;
    memcpy(out, &bits, sizeof bits);
    return 1;
}

/* Unsigned big integers for the exact path: little-endian 32-bit limbs. 132 limbs hold the
   largest intermediate (800 significant digits scaled by up to 2^1126 or 10^1124). */
#define CLOTH__BIG_LIMBS 132
#define CLOTH__SLOW_DIGITS 800
typedef struct cloth__big {
    int n;
    uint32_t d[CLOTH__BIG_LIMBS];
} cloth__big;

static void cloth__big_trim(cloth__big *b)
{
    while (b->n > 0 && b->d[b->n - 1] == 0) --b->n;
}

static void cloth__big_mul_add(cloth__big *b, uint32_t m, uint32_t a)
{
    uint64_t carry = a;
    int i;
    for (i = 0; i < b->n; ++i) {
        uint64_t t = (uint64_t)b->d[i] * m + carry;
        b->d[i] = (uint32_t)t;
        carry = t >> 32;
    }
    if (carry && b->n < CLOTH__BIG_LIMBS) b->d[b->n++] = (uint32_t)carry;
}

static void cloth__big_mul_pow10(cloth__big *b, long e)
{
    static const uint32_t small[9] = { 1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000 };
    for (; e >= 9; e -= 9) cloth__big_mul_add(b, 1000000000u, 0);
    if (e > 0) cloth__big_mul_add(b, small[e], 0);
}

static void cloth__big_shl(cloth__big *b, long bits)
{
    int words = (int)(bits / 32), s = (int)(bits % 32), i, n = b->n;
    if (n == 0 || bits <= 0) return;
    if (n + words + 1 > CLOTH__BIG_LIMBS) words = CLOTH__BIG_LIMBS - n - 1; /* unreachable by the bounds above */
    if (s) {
        b->d[n + words] = b->d[n - 1] >> (32 - s);
        for (i = n - 1; i > 0; --i) b->d[i + words] = (b->d[i] << s) | (b->d[i - 1] >> (32 - s));
        b->d[words] = b->d[0] << s;
        b->n = n + words + 1;
    } else {
        for (i = n - 1; i >= 0; --i) b->d[i + words] = b->d[i];
        b->n = n + words;
    }
    for (i = 0; i < words; ++i) b->d[i] = 0;
    cloth__big_trim(b);
}

static void cloth__big_shr1(cloth__big *b)
{
    int i;
    for (i = 0; i < b->n; ++i) b->d[i] = (b->d[i] >> 1) | (i + 1 < b->n ? b->d[i + 1] << 31 : 0);
    cloth__big_trim(b);
}

static int cloth__big_cmp(const cloth__big *a, const cloth__big *b)
{
    int i;
    if (a->n != b->n) return a->n < b->n ? -1 : 1;
    for (i = a->n - 1; i >= 0; --i)
        if (a->d[i] != b->d[i]) return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}

static void cloth__big_sub(cloth__big *a, const cloth__big *b) /* a -= b, with a >= b */
{
    int64_t borrow = 0;
    int i;
    for (i = 0; i < a->n; ++i) {
        int64_t t = (int64_t)a->d[i] - (i < b->n ? (int64_t)b->d[i] : 0) - borrow;
        borrow = t < 0;
        a->d[i] = (uint32_t)(t + (borrow ? ((int64_t)1 << 32) : 0));
    }
    cloth__big_trim(a);
}

static long cloth__big_bitlen(const cloth__big *b)
{
    uint32_t top;
    long n;
    if (b->n == 0) return 0;
    top = b->d[b->n - 1];
    n = 32L * (b->n - 1);
    while (top) { ++n; top >>= 1; }
    return n;
}

/* The exact path: the number in [p, end) (already known to be well formed) as the nearest
   double, ties to even. value = D * 10^e10 with D the first 800 significant digits; a nonzero
   digit beyond them only breaks an exact tie (800 digits are more than the 768 that can
   separate two doubles). The result is q * 2^k with q = round(D * 10^e10 / 2^k). */
static double cloth__decimal_exact(const unsigned char *p, const unsigned char *end)
{
    cloth__big a, b, t;
    int negative = 0, digits = 0, sticky = 0, chunk_len = 0;
    long e10 = 0, position, d, e2, k, i;
    uint32_t chunk = 0;
    uint64_t q = 0;
    double value;
    a.n = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    for (; p < end && cloth__is_digit(*p); ++p) {
        int c = *p - '0';
        if (digits == 0 && c == 0) continue;
        if (digits < CLOTH__SLOW_DIGITS) {
            chunk = chunk * 10 + (uint32_t)c;
            if (++chunk_len == 9) { cloth__big_mul_add(&a, 1000000000u, chunk); chunk = 0; chunk_len = 0; }
            ++digits;
        } else {
            ++e10;
            sticky |= c != 0;
        }
    }
    if (p < end && *p == '.') {
        for (++p; p < end && cloth__is_digit(*p); ++p) {
            int c = *p - '0';
            if (digits == 0 && c == 0) { --e10; continue; }
            if (digits < CLOTH__SLOW_DIGITS) {
                chunk = chunk * 10 + (uint32_t)c;
                if (++chunk_len == 9) { cloth__big_mul_add(&a, 1000000000u, chunk); chunk = 0; chunk_len = 0; }
                ++digits;
                --e10;
            } else {
                sticky |= c != 0;
            }
        }
    }
    if (chunk_len) {
        uint32_t scale = 1;
        for (i = 0; i < chunk_len; ++i) scale *= 10;
        cloth__big_mul_add(&a, scale, chunk);
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        int eneg = 0;
        long ev = 0;
        ++p;
        if (p < end && (*p == '+' || *p == '-')) eneg = *p++ == '-';
        for (; p < end && cloth__is_digit(*p); ++p)
            if (ev < 100000000L) ev = ev * 10 + (*p - '0');
        e10 += eneg ? -ev : ev;
    }
    if (digits == 0) return negative ? -0.0 : 0.0;
    position = digits + e10; /* 10^(position-1) <= value < 10^position */
    if (position > 310) return negative ? -HUGE_VAL : HUGE_VAL;
    if (position < -324) return negative ? -0.0 : 0.0;
    b.n = 1;
    b.d[0] = 1;
    if (e10 >= 0) cloth__big_mul_pow10(&a, e10);
    else cloth__big_mul_pow10(&b, -e10);
    /* e2 = floor(log2(a / b)) */
    d = cloth__big_bitlen(&a) - cloth__big_bitlen(&b);
    if (d >= 0) {
        t = b;
        cloth__big_shl(&t, d);
        e2 = cloth__big_cmp(&a, &t) >= 0 ? d : d - 1;
    } else {
        t = a;
        cloth__big_shl(&t, -d);
        e2 = cloth__big_cmp(&t, &b) >= 0 ? d : d - 1;
    }
    if (e2 > 1023) return negative ? -HUGE_VAL : HUGE_VAL;
    k = e2 - 52;
    if (k < -1074) k = -1074;
    if (k < 0) cloth__big_shl(&a, -k);
    else cloth__big_shl(&b, k);
    /* q = floor(a / b) < 2^53 by the choice of k, by shift and subtract; a keeps the rest. */
    t = b;
    cloth__big_shl(&t, 53);
    for (i = 53; i >= 0; --i) {
        if (cloth__big_cmp(&a, &t) >= 0) {
            cloth__big_sub(&a, &t);
            q |= (uint64_t)1 << i;
        }
        cloth__big_shr1(&t);
    }
    cloth__big_shl(&a, 1);
    {
        int c = cloth__big_cmp(&a, &b); /* twice the remainder against the divisor */
        if (c > 0 || (c == 0 && (sticky || (q & 1)))) ++q;
    }
    value = ldexp((double)q, (int)k);
    return negative ? -value : value;
}

/* Eight ASCII bytes at p as a little-endian word: one load on little-endian machines. */
static uint64_t cloth__load_8_bytes(const unsigned char *p)
{
#if defined(__BYTE_ORDER__) && defined(__ORDER_LITTLE_ENDIAN__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    uint64_t v;
    memcpy(&v, p, sizeof v);
    return v;
#else
    return (uint64_t)p[0] | ((uint64_t)p[1] << 8) | ((uint64_t)p[2] << 16) | ((uint64_t)p[3] << 24) | ((uint64_t)p[4] << 32) |
           ((uint64_t)p[5] << 40) | ((uint64_t)p[6] << 48) | ((uint64_t)p[7] << 56);
#endif
}

static int cloth__ctz64(uint64_t x) /* x != 0 */
{
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll((unsigned long long)x);
#else
    int n = 0;
    while (!(x & 1)) { x >>= 1; ++n; }
    return n;
#endif
}

/* How many of the eight bytes of v (first byte lowest) are decimal digits before the first
   that is not: a byte is a digit when its high nibble is 3 and stays 3 after adding 6. (A
   carry out of a byte only comes from a byte that is no digit, into the bytes after it.) */
static int cloth__leading_digits(uint64_t v)
{
    uint64_t bad = ((v & 0xF0F0F0F0F0F0F0F0ULL) ^ 0x3030303030303030ULL) |
                   (((v + 0x0606060606060606ULL) & 0xF0F0F0F0F0F0F0F0ULL) ^ 0x3030303030303030ULL);
    return bad ? cloth__ctz64(bad) / 8 : 8;
}

/* The value of the first n (1 to 8) digits of v, without a branch per digit (SWAR): the
   digits are moved to the top, the bytes below filled with '0', then pairs, pairs of pairs and
   the two halves are combined with multiplications. */
static uint32_t cloth__leading_digits_value(uint64_t v, int n)
{
    if (n < 8) v = (v << (8 * (8 - n))) | (0x3030303030303030ULL >> (8 * n));
    v -= 0x3030303030303030ULL;
    v = v * 10 + (v >> 8);
    v = ((v & 0x000000FF000000FFULL) * (100 + (1000000ULL << 32)) +
         ((v >> 16) & 0x000000FF000000FFULL) * (1 + (10000ULL << 32))) >> 32;
    return (uint32_t)v;
}

static const uint32_t cloth__pow10_u32[10] = { 1u, 10u, 100u, 1000u, 10000u, 100000u, 1000000u, 10000000u, 100000000u,
                                               1000000000u };

/* Scan a decimal number at p: an optional sign, digits with an optional point, an optional
   exponent; also "nan", "inf" and "infinity" in any case (so that the caller can report
   CLOTH_ERROR_NOT_FINITE rather than a parse error). Returns the end of the number and the
   correctly rounded double in *out, or NULL when no number starts at p. The caller checks
   what follows. The first 19 significant digits are gathered in w (eight at a time where
   they allow), the value being w * 10^q. */
static const unsigned char *cloth__scan_double(const unsigned char *p, const unsigned char *end, double *out)
{
    const unsigned char *start = p;
    uint64_t w = 0;
    int negative = 0, digits = 0, truncated = 0, any = 0;
    long q = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    if (p < end && (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I')) {
        if (cloth__starts_with(p, end, "nan")) {
            *out = NAN;
            return p + 3;
        }
        if (cloth__starts_with(p, end, "infinity")) {
            *out = negative ? -HUGE_VAL : HUGE_VAL;
            return p + 8;
        }
        if (cloth__starts_with(p, end, "inf")) {
            *out = negative ? -HUGE_VAL : HUGE_VAL;
            return p + 3;
        }
        return NULL;
    }
    /* integer part: leading zeros, then significant digits */
    for (; p < end && *p == '0'; ++p) any = 1;
    while (end - p >= 8) {
        uint64_t v = cloth__load_8_bytes(p);
        int n = cloth__leading_digits(v);
        if (n == 0 || digits + n > 19) break;
        w = w * cloth__pow10_u32[n] + cloth__leading_digits_value(v, n);
        digits += n;
        p += n;
        any = 1;
        if (n < 8) break;
    }
    for (; p < end && cloth__is_digit(*p); ++p) {
        any = 1;
        if (digits < 19) {
            w = w * 10 + (unsigned)(*p - '0');
            ++digits;
        } else {
            ++q;
            truncated |= *p != '0';
        }
    }
    if (p < end && *p == '.') {
        ++p;
        if (digits == 0)
            for (; p < end && *p == '0'; ++p) { /* zeros after the point that lead */
                any = 1;
                --q;
            }
        while (end - p >= 8) {
            uint64_t v = cloth__load_8_bytes(p);
            int n = cloth__leading_digits(v);
            if (n == 0 || digits + n > 19) break;
            w = w * cloth__pow10_u32[n] + cloth__leading_digits_value(v, n);
            digits += n;
            q -= n;
            p += n;
            any = 1;
            if (n < 8) break;
        }
        for (; p < end && cloth__is_digit(*p); ++p) {
            any = 1;
            if (digits < 19) {
                w = w * 10 + (unsigned)(*p - '0');
                ++digits;
                --q;
            } else {
                truncated |= *p != '0';
            }
        }
    }
    if (!any) return NULL;
    if (p < end && (*p == 'e' || *p == 'E')) {
        const unsigned char *e = p + 1;
        int eneg = 0;
        long ev = 0;
        if (e < end && (*e == '+' || *e == '-')) eneg = *e++ == '-';
        if (e < end && cloth__is_digit(*e)) {
            for (; e < end && cloth__is_digit(*e); ++e)
                if (ev < 100000000L) ev = ev * 10 + (*e - '0');
            q += eneg ? -ev : ev;
            p = e;
        }
    }
    if (w == 0 && !truncated) {
        *out = negative ? -0.0 : 0.0;
        return p;
    }
    if (!truncated) {
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD == 0
        if (w <= ((uint64_t)1 << 53) && q >= -22 && q <= 22) {
            double v = (double)w;
            v = q >= 0 ? v * cloth__exact_pow10[q] : v / cloth__exact_pow10[-q];
            *out = negative ? -v : v;
            return p;
        }
#endif
        if (q >= CLOTH__POW10_MIN && q <= CLOTH__POW10_MAX && cloth__eisel_lemire(w, (int)q, negative, out)) return p;
    }
    *out = cloth__decimal_exact(start, p);
    return p;
}

/* Scan an optionally signed decimal integer at p; NULL when there is none. Values beyond
   +-2^62 saturate (they are out of every range anyway). */
static const unsigned char *cloth__scan_int(const unsigned char *p, const unsigned char *end, int64_t *out)
{
    const unsigned char *digits, *limit;
    int negative = 0;
    int64_t v = 0;
    if (p < end && (*p == '+' || *p == '-')) negative = *p++ == '-';
    digits = p;
    if (end - p >= 8) { /* the common case: up to 7 digits and what ends them, in one load */
        uint64_t word = cloth__load_8_bytes(p);
        int n = cloth__leading_digits(word);
        if (n == 0) return NULL;
        if (n < 8) {
            v = (int64_t)cloth__leading_digits_value(word, n);
            *out = negative ? -v : v;
            return p + n;
        }
    }
    while (p < end && *p == '0') ++p;
    limit = end - p > 18 ? p + 18 : end;
    for (; p < limit && cloth__is_digit(*p); ++p) v = v * 10 + (*p - '0');
    if (p < end && cloth__is_digit(*p)) {
        v = (int64_t)1 << 62;
        while (p < end && cloth__is_digit(*p)) ++p;
    }
    if (p == digits) return NULL;
    *out = negative ? -v : v;
    return p;
}

/* ---- fields of text formats ------------------------------------------------------------ */

/* Whether p ends a number or index in a line of text: the end of the line (eol, or a line
   break before it), white space or '#'. */
static int cloth__ends_field(const unsigned char *p, const unsigned char *eol)
{
    return p >= eol || cloth__ends_word(*p);
}

/* Whether p is at the end of a line's content: eol, a line break or a comment. */
static int cloth__ends_content(const unsigned char *p, const unsigned char *eol)
{
    return p >= eol || *p == '\n' || *p == '#';
}

/* Read one real of a line at *pp (leading blanks skipped) into *out; `what` names it in
   messages. A number must be finite after rounding to cloth_real. */
static cloth_result cloth__text_real(const cloth__io *io, const unsigned char **pp, const unsigned char *eol,
                                     cloth_real *out, const char *what)
{
    const unsigned char *p = cloth__skip_blank(*pp, eol), *q;
    double d = 0;
    if (cloth__ends_content(p, eol)) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: a number is missing", what);
    q = cloth__scan_double(p, eol, &d);
    if (!q || !cloth__ends_field(q, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: '%.*s' is not a number", what, cloth__quote_length(p, eol), p);
    *out = (cloth_real)d;
    if (!cloth__is_finite(*out))
        return cloth__io_fail(io, CLOTH_ERROR_NOT_FINITE, p, 1, "%s: %.*s is not a finite number", what,
                              cloth__quote_length(p, eol), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* Read one integer of a line at *pp (leading blanks skipped). */
static cloth_result cloth__text_int(const cloth__io *io, const unsigned char **pp, const unsigned char *eol, int64_t *out,
                                    const char *what)
{
    const unsigned char *p = cloth__skip_blank(*pp, eol), *q;
    if (cloth__ends_content(p, eol)) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: a number is missing", what);
    q = cloth__scan_int(p, eol, out);
    if (!q || !cloth__ends_field(q, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "%s: '%.*s' is not an integer", what, cloth__quote_length(p, eol), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* Allocate the output mesh once the counts are known, with `text` saying whether the input
   is text (for the place of an empty-mesh error, which is the end of the input). */
static cloth_result cloth__io_mesh_alloc(const cloth__io *io, cloth_mesh *mesh, int64_t vertex_count, int64_t triangle_count,
                                         int with_uv, int text)
{
    cloth_result r;
    if (vertex_count <= 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, io->end, text, "the file has no vertices");
    if (triangle_count <= 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, io->end, text, "the file has no triangles");
    if (vertex_count > INT32_MAX || triangle_count > INT32_MAX)
        return cloth__io_fail(io, CLOTH_ERROR_SIZE_OVERFLOW, io->end, text, "%lld vertices and %lld triangles exceed int32_t",
                              (long long)vertex_count, (long long)triangle_count);
    r = cloth_mesh_alloc(mesh, (int32_t)vertex_count, (int32_t)triangle_count, with_uv, &io->allocator);
    if (r != CLOTH_SUCCESS)
        return cloth__io_fail(io, r, NULL, 0, "cannot allocate a mesh of %lld vertices and %lld triangles",
                              (long long)vertex_count, (long long)triangle_count);
    return CLOTH_SUCCESS;
}

/* Skip a UTF-8 byte order mark. */
static const unsigned char *cloth__skip_bom(const unsigned char *p, const unsigned char *end)
{
    return end - p >= 3 && p[0] == 0xEF && p[1] == 0xBB && p[2] == 0xBF ? p + 3 : p;
}

/* ---- OBJ ----------------------------------------------------------------------------- */

typedef enum cloth__obj_statement {
    CLOTH__OBJ_VERTEX,
    CLOTH__OBJ_TEXCOORD,
    CLOTH__OBJ_FACE,
    CLOTH__OBJ_SKIPPED,
    CLOTH__OBJ_UNKNOWN
} cloth__obj_statement;

/* What the keyword [k, e) of a line is: every statement of the OBJ specification is known;
   v, vt and f are read and the others skipped. */
static cloth__obj_statement cloth__obj_keyword(const unsigned char *k, const unsigned char *e)
{
    static const char *const skipped[] = {
        "vn", "vp", "o", "g", "s", "l", "p", "usemtl", "mtllib", "cstype", "deg", "bmat", "step", "curv", "curv2",
        "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con", "mg", "bevel", "c_interp", "d_interp", "lod",
        "shadow_obj", "trace_obj", "ctech", "stech", "maplib", "usemap"
    };
    size_t n = (size_t)(e - k), i;
    if (n == 1 && k[0] == 'v') return CLOTH__OBJ_VERTEX;
    if (n == 1 && k[0] == 'f') return CLOTH__OBJ_FACE;
    if (n == 2 && k[0] == 'v' && k[1] == 't') return CLOTH__OBJ_TEXCOORD;
    for (i = 0; i < sizeof skipped / sizeof skipped[0]; ++i)
        if (strlen(skipped[i]) == n && memcmp(skipped[i], k, n) == 0) return CLOTH__OBJ_SKIPPED;
    return CLOTH__OBJ_UNKNOWN;
}

/* The keyword of a line: from p (after leading blanks) to white space or '#'. */
static const unsigned char *cloth__obj_keyword_end(const unsigned char *p, const unsigned char *eol)
{
    while (p < eol && !cloth__ends_word(*p)) ++p;
    return p;
}

/* The start of the next line after p, from where a statement's reading stopped (usually
   its line break already). */
static const unsigned char *cloth__next_line(const unsigned char *p, const unsigned char *end)
{
    p = cloth__skip_blank(p, end);
    if (p < end && *p != '\n') p = cloth__line_end(p, end);
    return p < end ? p + 1 : end;
}

/* Resolve an OBJ index (1-based, or negative relative to the `defined` items above) against
   `total` items; -1 when out of range. */
static int64_t cloth__obj_resolve(int64_t index, int64_t defined, int64_t total)
{
    if (index > 0) return index <= total ? index - 1 : -1;
    if (index < 0) return defined + index >= 0 ? defined + index : -1;
    return -1;
}

/* Read one face corner "v", "v/vt", "v//vn" or "v/vt/vn" at *pp. *vt is -1 without a vt. */
static cloth_result cloth__obj_corner(const cloth__io *io, const unsigned char **pp, const unsigned char *eol,
                                      int64_t vertices_above, int64_t vertex_total, int64_t texcoords_above,
                                      int64_t texcoord_total, int32_t *v, int32_t *vt)
{
    const unsigned char *start = *pp, *p;
    int64_t index = 0, resolved;
    p = cloth__scan_int(start, eol, &index);
    if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, start, 1, "face corner '%.*s' does not start with a vertex index",
                                  cloth__quote_length(start, eol), start);
    resolved = cloth__obj_resolve(index, vertices_above, vertex_total);
    if (resolved < 0)
        return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, start, 1,
                              "face names vertex %lld; %lld vertices are defined above it, %lld in the file", (long long)index,
                              (long long)vertices_above, (long long)vertex_total);
    *v = (int32_t)resolved;
    *vt = -1;
    if (p < eol && *p == '/') {
        ++p;
        if (!cloth__ends_field(p, eol) && *p != '/') {
            const unsigned char *t = p;
            p = cloth__scan_int(t, eol, &index);
            if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, t, 1, "face corner '%.*s': bad texture coordinate index",
                                          cloth__quote_length(start, eol), start);
            resolved = cloth__obj_resolve(index, texcoords_above, texcoord_total);
            if (resolved < 0)
                return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, t, 1,
                                      "face names texture coordinate %lld; %lld are defined above it, %lld in the file",
                                      (long long)index, (long long)texcoords_above, (long long)texcoord_total);
            *vt = (int32_t)resolved;
        }
        if (p < eol && *p == '/') {
            ++p;
            if (!cloth__ends_field(p, eol)) {
                const unsigned char *n = p;
                p = cloth__scan_int(n, eol, &index);
                if (!p) return cloth__io_fail(io, CLOTH_ERROR_PARSE, n, 1, "face corner '%.*s': bad normal index",
                                              cloth__quote_length(start, eol), start);
            }
        }
    }
    if (!cloth__ends_field(p, eol))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, start, 1, "malformed face corner '%.*s'", cloth__quote_length(start, eol),
                              start);
    *pp = p;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_obj(const cloth__io *io, cloth_mesh *mesh)
{
    const unsigned char *begin = cloth__skip_bom(io->begin, io->end), *end = io->end, *p;
    int64_t vertex_total = 0, texcoord_total = 0, triangle_total = 0, vertices = 0, texcoords = 0, triangles = 0;
    int with_uv = 0;
    cloth_real *vt = NULL;
    int32_t *pairing = NULL;
    cloth_result r = CLOTH_SUCCESS;

    /* First pass: check the statements; count vertices, texture coordinates and the corners
       of every face; find out whether any corner names a texture coordinate. */
    for (p = begin; p < end;) {
        const unsigned char *k;
        cloth__obj_statement s;
        p = cloth__skip_blank(p, end);
        if (cloth__ends_content(p, end)) {
            p = cloth__next_line(p, end);
            continue;
        }
        k = p;
        p = cloth__obj_keyword_end(p, end);
        s = cloth__obj_keyword(k, p);
        if (s == CLOTH__OBJ_VERTEX) {
            ++vertex_total;
        } else if (s == CLOTH__OBJ_TEXCOORD) {
            ++texcoord_total;
        } else if (s == CLOTH__OBJ_FACE) {
            /* corners: the words before the end of the line or a comment; texture coordinates:
               a word's first slash followed by an index */
            const unsigned char *eol = cloth__line_end(p, end), *stop, *q;
            int64_t corners = 0;
            stop = (const unsigned char *)memchr(p, '#', (size_t)(eol - p));
            if (!stop) stop = eol;
            /* A word starts where a byte above ' ' follows one at or below it. Control bytes
               count as separators here; the second pass rejects them. */
            for (q = p; q < stop; ++q) corners += (q[0] > ' ') & (q[-1] <= ' ');
            for (q = p; !with_uv && q < stop && (q = (const unsigned char *)memchr(q, '/', (size_t)(stop - q))) != NULL; ++q)
                if (!cloth__is_blank(q[-1]) && q[-1] != '/' && q + 1 < stop && q[1] != '/' && !cloth__is_blank(q[1])) with_uv = 1;
            p = eol;
            if (corners < 3)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a face needs at least 3 vertices, this one has %lld",
                                      (long long)corners);
            triangle_total += corners - 2;
        } else if (s == CLOTH__OBJ_UNKNOWN) {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "unknown OBJ statement '%.*s'", (int)(p - k > 24 ? 24 : p - k), k);
        }
        p = cloth__next_line(p, end);
    }
    r = cloth__io_mesh_alloc(io, mesh, vertex_total, triangle_total, with_uv, 1);
    if (r != CLOTH_SUCCESS) return r;
    if (with_uv) {
        if (texcoord_total > INT32_MAX) {
            r = cloth__io_fail(io, CLOTH_ERROR_SIZE_OVERFLOW, NULL, 0, "%lld texture coordinates exceed int32_t",
                               (long long)texcoord_total);
            goto done;
        }
        vt = (cloth_real *)cloth__alloc_array(&io->allocator, (size_t)texcoord_total * 2, sizeof(cloth_real));
        pairing = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)vertex_total, sizeof(int32_t));
        if (!vt || !pairing) {
            r = cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate %lld texture coordinates",
                               (long long)texcoord_total);
            goto done;
        }
        memset(pairing, 0xFF, sizeof(int32_t) * (size_t)vertex_total); /* -1: not paired yet */
    }

    /* Second pass: read. */
    for (p = begin; p < end && r == CLOTH_SUCCESS;) {
        const unsigned char *k;
        cloth__obj_statement s;
        p = cloth__skip_blank(p, end);
        if (cloth__ends_content(p, end)) {
            p = cloth__next_line(p, end);
            continue;
        }
        k = p;
        p = cloth__obj_keyword_end(p, end);
        s = cloth__obj_keyword(k, p);
        if (s == CLOTH__OBJ_VERTEX) {
            cloth_real *x = mesh->x + 3 * vertices;
            if ((r = cloth__text_real(io, &p, end, x, "vertex x")) != CLOTH_SUCCESS) break;
            if ((r = cloth__text_real(io, &p, end, x + 1, "vertex y")) != CLOTH_SUCCESS) break;
            if ((r = cloth__text_real(io, &p, end, x + 2, "vertex z")) != CLOTH_SUCCESS) break;
            ++vertices;
        } else if (s == CLOTH__OBJ_TEXCOORD) {
            cloth_real uv[2] = { 0, 0 };
            if ((r = cloth__text_real(io, &p, end, uv, "texture coordinate u")) != CLOTH_SUCCESS) break;
            p = cloth__skip_blank(p, end);
            if (!cloth__ends_content(p, end) &&
                (r = cloth__text_real(io, &p, end, uv + 1, "texture coordinate v")) != CLOTH_SUCCESS)
                break;
            if (vt) {
                vt[2 * texcoords] = uv[0];
                vt[2 * texcoords + 1] = uv[1];
            }
            ++texcoords;
        } else if (s == CLOTH__OBJ_FACE) {
            int32_t first = -1, previous = -1, v = 0, t = -1;
            int64_t corner = 0;
            for (;;) {
                p = cloth__skip_blank(p, end);
                if (cloth__ends_content(p, end)) break;
                r = cloth__obj_corner(io, &p, end, vertices, vertex_total, texcoords, texcoord_total, &v, &t);
                if (r != CLOTH_SUCCESS) break;
                if (pairing && t >= 0 && pairing[v] < 0) pairing[v] = t;
                if (corner == 0) first = v;
                if (corner >= 2 && triangles < triangle_total) {
                    int32_t *tri = mesh->tri + 3 * triangles++;
                    tri[0] = first;
                    tri[1] = previous;
                    tri[2] = v;
                }
                previous = v;
                ++corner;
            }
        }
        p = cloth__next_line(p, end);
    }
    if (r == CLOTH_SUCCESS && (vertices != vertex_total || triangles != triangle_total)) /* cannot happen */
        r = cloth__io_fail(io, CLOTH_ERROR_PARSE, end, 1,
                           "the second pass found %lld vertices and %lld triangles, not %lld and %lld", (long long)vertices,
                           (long long)triangles, (long long)vertex_total, (long long)triangle_total);
    if (r == CLOTH_SUCCESS && with_uv) {
        int64_t i;
        for (i = 0; i < vertex_total; ++i) {
            int32_t t = pairing[i];
            mesh->uv[2 * i] = t >= 0 ? vt[2 * t] : 0;
            mesh->uv[2 * i + 1] = t >= 0 ? vt[2 * t + 1] : 0;
        }
    }
done:
    cloth__free(&io->allocator, vt);
    cloth__free(&io->allocator, pairing);
    return r;
}

/* ---- binary values (PLY and VTK) ------------------------------------------------------- */

typedef enum cloth__type {
    CLOTH__TYPE_NONE = 0,
    CLOTH__TYPE_INT8,
    CLOTH__TYPE_UINT8,
    CLOTH__TYPE_INT16,
    CLOTH__TYPE_UINT16,
    CLOTH__TYPE_INT32,
    CLOTH__TYPE_UINT32,
    CLOTH__TYPE_INT64,
    CLOTH__TYPE_UINT64,
    CLOTH__TYPE_FLOAT32,
    CLOTH__TYPE_FLOAT64
} cloth__type;

static const unsigned char cloth__type_size[11] = { 0, 1, 1, 2, 2, 4, 4, 8, 8, 4, 8 };

static int cloth__type_is_integer(int type) { return type >= CLOTH__TYPE_INT8 && type <= CLOTH__TYPE_UINT64; }

static uint32_t cloth__load_u16(const unsigned char *p, int big_endian)
{
    return big_endian ? ((uint32_t)p[0] << 8) | p[1] : ((uint32_t)p[1] << 8) | p[0];
}

static uint32_t cloth__load_u32(const unsigned char *p, int big_endian)
{
    if (big_endian) return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | p[3];
    return ((uint32_t)p[3] << 24) | ((uint32_t)p[2] << 16) | ((uint32_t)p[1] << 8) | p[0];
}

static uint64_t cloth__load_u64(const unsigned char *p, int big_endian)
{
    uint64_t a = cloth__load_u32(p, big_endian), b = cloth__load_u32(p + 4, big_endian);
    return big_endian ? (a << 32) | b : (b << 32) | a;
}

/* The value at p of an integer type, as int64_t (uint64 values above INT64_MAX saturate). */
static int64_t cloth__load_int(const unsigned char *p, int type, int big_endian)
{
    uint64_t u;
    switch (type) {
    case CLOTH__TYPE_INT8: return p[0] >= 0x80 ? (int64_t)p[0] - 0x100 : (int64_t)p[0];
    case CLOTH__TYPE_UINT8: return p[0];
    case CLOTH__TYPE_INT16: u = cloth__load_u16(p, big_endian); return u >= 0x8000 ? (int64_t)u - 0x10000 : (int64_t)u;
    case CLOTH__TYPE_UINT16: return cloth__load_u16(p, big_endian);
    case CLOTH__TYPE_INT32:
        u = cloth__load_u32(p, big_endian);
        return u >= 0x80000000u ? (int64_t)u - ((int64_t)1 << 32) : (int64_t)u;
    case CLOTH__TYPE_UINT32: return cloth__load_u32(p, big_endian);
    case CLOTH__TYPE_INT64:
        u = cloth__load_u64(p, big_endian);
        return u >> 63 ? -(int64_t)(~u) - 1 : (int64_t)u;
    case CLOTH__TYPE_UINT64:
        u = cloth__load_u64(p, big_endian);
        return u >> 63 ? INT64_MAX : (int64_t)u;
    default: return 0;
    }
}

/* The value at p of any numeric type, as a double. */
static double cloth__load_real(const unsigned char *p, int type, int big_endian)
{
    if (type == CLOTH__TYPE_FLOAT32) {
        uint32_t bits = cloth__load_u32(p, big_endian);
        float f;
        memcpy(&f, &bits, sizeof f);
        return (double)f;
    }
    if (type == CLOTH__TYPE_FLOAT64) {
        uint64_t bits = cloth__load_u64(p, big_endian);
        double d;
        memcpy(&d, &bits, sizeof d);
        return d;
    }
    if (type == CLOTH__TYPE_INT64) {
        uint64_t u = cloth__load_u64(p, big_endian);
        return u >> 63 ? -(double)(~u) - 1.0 : (double)u;
    }
    if (type == CLOTH__TYPE_UINT64) return (double)cloth__load_u64(p, big_endian);
    return (double)cloth__load_int(p, type, big_endian);
}

/* ---- PLY ----------------------------------------------------------------------------- */

typedef enum cloth__ply_role {
    CLOTH__PLY_OTHER = 0,
    CLOTH__PLY_X, CLOTH__PLY_Y, CLOTH__PLY_Z,
    CLOTH__PLY_U, CLOTH__PLY_V, CLOTH__PLY_S, CLOTH__PLY_T, CLOTH__PLY_TEXTURE_U, CLOTH__PLY_TEXTURE_V,
    CLOTH__PLY_INDICES,
    CLOTH__PLY_ROLE_COUNT
} cloth__ply_role;

typedef struct cloth__ply_property {
    unsigned char type;       /* the value type, or the item type of a list */
    unsigned char count_type; /* the count type of a list; CLOTH__TYPE_NONE for a scalar */
    unsigned char role;       /* a cloth__ply_role */
} cloth__ply_property;

typedef struct cloth__ply_element {
    const unsigned char *line; /* its "element" line, for messages */
    const unsigned char *name;
    int name_length;
    int64_t count;
    int first_property, property_count;
    size_t stride;              /* binary: bytes per item when no property is a list, else 0 */
    const unsigned char *data;  /* where its items start (found by the first pass) */
} cloth__ply_element;

typedef struct cloth__ply {
    const cloth__io *io;
    int binary, big_endian;
    cloth__ply_element *element;
    int element_count;
    cloth__ply_property *property;
    int property_count;
    const unsigned char *body;      /* the first byte after end_header's line */
    int vertex, face;               /* element indices, -1 when absent */
    int role[CLOTH__PLY_ROLE_COUNT]; /* property index for each role, -1 when absent */
    int uv_u, uv_v;                 /* the roles that give uv, 0 when none */
    int64_t triangle_count;
    int all_triangles;              /* every face is a triangle */
} cloth__ply;

static cloth__type cloth__ply_type(const unsigned char *p, const unsigned char *e)
{
    static const struct { const char *name; cloth__type type; } names[] = {
        { "char", CLOTH__TYPE_INT8 }, { "int8", CLOTH__TYPE_INT8 }, { "uchar", CLOTH__TYPE_UINT8 },
        { "uint8", CLOTH__TYPE_UINT8 }, { "short", CLOTH__TYPE_INT16 }, { "int16", CLOTH__TYPE_INT16 },
        { "ushort", CLOTH__TYPE_UINT16 }, { "uint16", CLOTH__TYPE_UINT16 }, { "int", CLOTH__TYPE_INT32 },
        { "int32", CLOTH__TYPE_INT32 }, { "uint", CLOTH__TYPE_UINT32 }, { "uint32", CLOTH__TYPE_UINT32 },
        { "int64", CLOTH__TYPE_INT64 }, { "uint64", CLOTH__TYPE_UINT64 }, { "float", CLOTH__TYPE_FLOAT32 },
        { "float32", CLOTH__TYPE_FLOAT32 }, { "double", CLOTH__TYPE_FLOAT64 }, { "float64", CLOTH__TYPE_FLOAT64 }
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (cloth__token_is(p, e, names[i].name)) return names[i].type;
    return CLOTH__TYPE_NONE;
}

/* Split the line [p, eol) into at most `max` blank-separated words; returns their number
   (more than max when the line has more). */
static int cloth__split_line(const unsigned char *p, const unsigned char *eol, const unsigned char **word,
                             const unsigned char **word_end, int max)
{
    int n = 0;
    for (;;) {
        p = cloth__skip_blank(p, eol);
        if (p >= eol) return n;
        if (n < max) word[n] = p;
        while (p < eol && !cloth__is_blank(*p)) ++p;
        if (n < max) word_end[n] = p;
        ++n;
    }
}

static int cloth__bytes_are(const unsigned char *p, const unsigned char *e, const char *s)
{
    size_t n = strlen(s);
    return (size_t)(e - p) == n && memcmp(p, s, n) == 0;
}

static cloth_result cloth__ply_header(cloth__ply *ply)
{
    const cloth__io *io = ply->io;
    const unsigned char *end = io->end, *p = io->begin, *eol, *w[6], *we[6];
    int lines = 0, n, have_format = 0, i;
    /* "ply" alone on the first line */
    eol = cloth__line_end(p, end);
    n = cloth__split_line(p, eol, w, we, 6);
    if (n != 1 || !cloth__bytes_are(w[0], we[0], "ply"))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "not a PLY file: the first line is not 'ply'");
    /* Count the header's lines to size the tables. */
    for (p = eol < end ? eol + 1 : end;; ++lines) {
        if (p >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the PLY header has no end_header line");
        eol = cloth__line_end(p, end);
        n = cloth__split_line(p, eol, w, we, 6);
        if (n == 1 && cloth__bytes_are(w[0], we[0], "end_header")) break;
        p = eol < end ? eol + 1 : end;
    }
    ply->element = (cloth__ply_element *)cloth__alloc_array(&io->allocator, (size_t)lines + 1, sizeof(cloth__ply_element));
    ply->property = (cloth__ply_property *)cloth__alloc_array(&io->allocator, (size_t)lines + 1, sizeof(cloth__ply_property));
    if (!ply->element || !ply->property)
        return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the PLY header tables");
    eol = cloth__line_end(io->begin, end);
    for (p = eol + 1;; p = eol + 1) {
        eol = cloth__line_end(p, end);
        n = cloth__split_line(p, eol, w, we, 6);
        if (n == 0) continue;
        if (n == 1 && cloth__bytes_are(w[0], we[0], "end_header")) {
            ply->body = eol < end ? eol + 1 : end;
            break;
        } else if (cloth__bytes_are(w[0], we[0], "comment") || cloth__bytes_are(w[0], we[0], "obj_info")) {
            continue;
        } else if (cloth__bytes_are(w[0], we[0], "format")) {
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "the format line needs an encoding and a version");
            if (cloth__bytes_are(w[1], we[1], "ascii")) {
                ply->binary = 0;
            } else if (cloth__bytes_are(w[1], we[1], "binary_little_endian") ||
                       cloth__bytes_are(w[1], we[1], "binary_big_endian")) {
                ply->binary = 1;
                ply->big_endian = w[1][7] == 'b';
            } else {
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[1], 1, "unknown PLY encoding '%.*s'",
                                       cloth__quote_length(w[1], eol), w[1]);
            }
            if (!cloth__bytes_are(w[2], we[2], "1.0") && !cloth__bytes_are(w[2], we[2], "1"))
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[2], 1, "PLY version '%.*s' (only 1.0 is read)",
                                      cloth__quote_length(w[2], eol), w[2]);
            have_format = 1;
        } else if (cloth__bytes_are(w[0], we[0], "element")) {
            cloth__ply_element *e = &ply->element[ply->element_count++];
            const unsigned char *q;
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "an element line needs a name and a count");
            memset(e, 0, sizeof *e);
            e->line = p;
            e->name = w[1];
            e->name_length = (int)(we[1] - w[1] > 32 ? 32 : we[1] - w[1]);
            q = cloth__scan_int(w[2], we[2], &e->count);
            if (!q || q != we[2] || e->count < 0)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[2], 1, "bad element count '%.*s'", cloth__quote_length(w[2], eol),
                                      w[2]);
            e->first_property = ply->property_count;
        } else if (cloth__bytes_are(w[0], we[0], "property")) {
            cloth__ply_property *prop = &ply->property[ply->property_count];
            if (ply->element_count == 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "a property before any element");
            memset(prop, 0, sizeof *prop);
            if (n == 3) {
                prop->type = (unsigned char)cloth__ply_type(w[1], we[1]);
                if (!prop->type) return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "unknown property type '%.*s'",
                                                       cloth__quote_length(w[1], eol), w[1]);
            } else if (n == 5 && cloth__bytes_are(w[1], we[1], "list")) {
                prop->count_type = (unsigned char)cloth__ply_type(w[2], we[2]);
                prop->type = (unsigned char)cloth__ply_type(w[3], we[3]);
                if (!cloth__type_is_integer(prop->count_type))
                    return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[2], 1, "a list count type must be an integer type, not '%.*s'",
                                          cloth__quote_length(w[2], eol), w[2]);
                if (!prop->type) return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[3], 1, "unknown property type '%.*s'",
                                                       cloth__quote_length(w[3], eol), w[3]);
            } else {
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "a property line is 'property TYPE NAME' or "
                                      "'property list COUNT_TYPE ITEM_TYPE NAME'");
            }
            /* Roles, in the vertex and face elements only. */
            {
                cloth__ply_element *e = &ply->element[ply->element_count - 1];
                const unsigned char *name = w[n - 1], *name_end = we[n - 1];
                int role = CLOTH__PLY_OTHER;
                if (cloth__bytes_are(e->name, e->name + e->name_length, "vertex")) {
                    static const char *const names[] = { "x", "y", "z", "u", "v", "s", "t", "texture_u", "texture_v" };
                    int k;
                    for (k = 0; k < 9; ++k)
                        if (cloth__bytes_are(name, name_end, names[k])) role = CLOTH__PLY_X + k;
                    if (role != CLOTH__PLY_OTHER && prop->count_type) {
                        if (role <= CLOTH__PLY_Z)
                            return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "vertex property %.*s is a list",
                                                  cloth__quote_length(name, eol), name);
                        role = CLOTH__PLY_OTHER; /* a list named u is not a texture coordinate */
                    }
                } else if (cloth__bytes_are(e->name, e->name + e->name_length, "face")) {
                    if (prop->count_type &&
                        (cloth__bytes_are(name, name_end, "vertex_indices") || cloth__bytes_are(name, name_end, "vertex_index")))
                        role = CLOTH__PLY_INDICES;
                }
                if (role != CLOTH__PLY_OTHER && ply->role[role] < 0) {
                    if (role == CLOTH__PLY_INDICES && !cloth__type_is_integer(prop->type))
                        return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[3], 1, "face indices of type '%.*s' (integers only)",
                                              cloth__quote_length(w[3], eol), w[3]);
                    ply->role[role] = ply->property_count;
                    prop->role = (unsigned char)role;
                }
            }
            ++ply->property_count;
            ++ply->element[ply->element_count - 1].property_count;
        } else {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[0], 1, "unknown PLY header line '%.*s'",
                                  cloth__quote_length(w[0], eol), w[0]);
        }
    }
    if (!have_format) return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->body, 1, "the PLY header has no format line");
    for (i = 0; i < ply->element_count; ++i) {
        cloth__ply_element *e = &ply->element[i];
        int k;
        if (cloth__bytes_are(e->name, e->name + e->name_length, "vertex")) {
            if (ply->vertex >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, e->line, 1, "a second vertex element");
            ply->vertex = i;
        } else if (cloth__bytes_are(e->name, e->name + e->name_length, "face")) {
            if (ply->face >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, e->line, 1, "a second face element");
            ply->face = i;
        }
        e->stride = 0;
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &ply->property[e->first_property + k];
            if (prop->count_type) { e->stride = 0; break; }
            e->stride += cloth__type_size[prop->type];
        }
    }
    if (ply->vertex < 0) return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, ply->body, 1, "the PLY file has no vertex element");
    for (i = CLOTH__PLY_X; i <= CLOTH__PLY_Z; ++i)
        if (ply->role[i] < 0)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->element[ply->vertex].line, 1,
                                  "the vertex element has no property %c", "xyz"[i - CLOTH__PLY_X]);
    if (ply->face >= 0 && ply->role[CLOTH__PLY_INDICES] < 0)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, ply->element[ply->face].line, 1,
                              "the face element has no list property vertex_indices (or vertex_index)");
    for (i = CLOTH__PLY_U; i <= CLOTH__PLY_TEXTURE_U; i += 2) {
        if (ply->role[i] >= 0 && ply->role[i + 1] >= 0) {
            ply->uv_u = i;
            ply->uv_v = i + 1;
            break;
        }
    }
    return CLOTH_SUCCESS;
}

/* Skip one ascii token; TRUNCATED at the end of the data. */
static cloth_result cloth__ply_ascii_skip(const cloth__ply *ply, const unsigned char **pp, const cloth__ply_element *e,
                                          int64_t item)
{
    const unsigned char *p = cloth__skip_space(*pp, ply->io->end);
    if (p >= ply->io->end)
        return cloth__io_fail(ply->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside item %lld of element '%.*s'",
                              (long long)item, e->name_length, e->name);
    *pp = cloth__token_end(p, ply->io->end);
    return CLOTH_SUCCESS;
}

/* Read one ascii list length at *pp. */
static cloth_result cloth__ply_ascii_count(const cloth__ply *ply, const unsigned char **pp, const cloth__ply_element *e,
                                           int64_t item, int64_t *count)
{
    const unsigned char *end = ply->io->end, *p = cloth__skip_space(*pp, end), *q;
    if (p >= end)
        return cloth__io_fail(ply->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside item %lld of element '%.*s'",
                              (long long)item, e->name_length, e->name);
    q = cloth__scan_int(p, end, count);
    if (!q || (q < end && !cloth__is_space(*q)) || *count < 0)
        return cloth__io_fail(ply->io, CLOTH_ERROR_PARSE, p, 1, "bad list length '%.*s'", cloth__quote_length(p, end), p);
    *pp = q;
    return CLOTH_SUCCESS;
}

/* First pass over the body: find where each element starts, check that every item is
   there, count the triangles. */
static cloth_result cloth__ply_walk(cloth__ply *ply)
{
    const cloth__io *io = ply->io;
    const unsigned char *p = ply->body, *end = io->end;
    const cloth__ply_element *current = NULL;
    int i, k;
    cloth_result r;
    ply->triangle_count = 0;
    ply->all_triangles = 1;
    for (i = 0; i < ply->element_count; ++i) {
        cloth__ply_element *e = &ply->element[i];
        const cloth__ply_property *props = ply->property + e->first_property;
        int64_t item;
        current = e;
        e->data = p;
        if (e->count == 0 || e->property_count == 0) continue;
        if (ply->binary && e->stride) {
            if ((uint64_t)e->count > (uint64_t)(end - p) / e->stride)
                return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, p, 0,
                                      "element '%.*s' announces %lld items of %lu bytes; %lu bytes remain", e->name_length,
                                      e->name, (long long)e->count, (unsigned long)e->stride, (unsigned long)(end - p));
            p += (size_t)e->count * e->stride;
            continue;
        }
        for (item = 0; item < e->count; ++item) {
            for (k = 0; k < e->property_count; ++k) {
                const cloth__ply_property *prop = &props[k];
                int64_t count = 0, j;
                if (ply->binary) {
                    size_t size = cloth__type_size[prop->type], csize = cloth__type_size[prop->count_type];
                    if (!prop->count_type) {
                        if ((size_t)(end - p) < size) goto truncated;
                        p += size;
                        continue;
                    }
                    if ((size_t)(end - p) < csize) goto truncated;
                    count = cloth__load_int(p, prop->count_type, ply->big_endian);
                    if (count < 0)
                        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 0, "negative list length %lld", (long long)count);
                    p += csize;
                    if ((uint64_t)count > (uint64_t)(end - p) / size) goto truncated;
                    p += (size_t)count * size;
                } else {
                    if (!prop->count_type) {
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, item)) != CLOTH_SUCCESS) return r;
                        continue;
                    }
                    if ((r = cloth__ply_ascii_count(ply, &p, e, item, &count)) != CLOTH_SUCCESS) return r;
                    for (j = 0; j < count; ++j)
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, item)) != CLOTH_SUCCESS) return r;
                }
                if (prop->role == CLOTH__PLY_INDICES) {
                    if (count < 3)
                        return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, !ply->binary,
                                              "face %lld has %lld vertices (at least 3 needed)", (long long)item,
                                              (long long)count);
                    ply->triangle_count += count - 2;
                    ply->all_triangles &= count == 3;
                }
            }
        }
    }
    return CLOTH_SUCCESS;
truncated:
    return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, p, 0, "the data ends inside element '%.*s'", current->name_length,
                          current->name);
}

/* Where the value of a vertex property with `role` goes, NULL when it is not read. */
static cloth_real *cloth__ply_slot(const cloth__ply *ply, cloth_mesh *mesh, int role, int64_t vertex)
{
    if (role >= CLOTH__PLY_X && role <= CLOTH__PLY_Z) return mesh->x + 3 * vertex + (role - CLOTH__PLY_X);
    if (mesh->uv && role == ply->uv_u) return mesh->uv + 2 * vertex;
    if (mesh->uv && role == ply->uv_v) return mesh->uv + 2 * vertex + 1;
    return NULL;
}

static cloth_result cloth__ply_store(const cloth__ply *ply, cloth_real *slot, double value, const unsigned char *at,
                                     int64_t vertex)
{
    *slot = (cloth_real)value;
    if (!cloth__is_finite(*slot))
        return cloth__io_fail(ply->io, CLOTH_ERROR_NOT_FINITE, at, !ply->binary, "vertex %lld: a coordinate is not finite (%g)",
                              (long long)vertex, value);
    return CLOTH_SUCCESS;
}

static cloth_result cloth__ply_read_vertices(const cloth__ply *ply, cloth_mesh *mesh)
{
    const cloth__io *io = ply->io;
    const cloth__ply_element *e = &ply->element[ply->vertex];
    const cloth__ply_property *props = ply->property + e->first_property;
    const unsigned char *p = e->data, *end = io->end;
    int64_t i;
    int k;
    cloth_result r;
    if (ply->binary && e->stride) {
        /* Fixed stride: every property at a fixed offset in the item. */
        size_t offset[5];
        int type[5], count = 0, role[5];
        size_t at = 0;
        for (k = 0; k < e->property_count; ++k) {
            int rk = props[k].role;
            if (rk != CLOTH__PLY_OTHER && cloth__ply_slot(ply, mesh, rk, 0) != NULL) {
                offset[count] = at;
                type[count] = props[k].type;
                role[count++] = rk;
            }
            at += cloth__type_size[props[k].type];
        }
        for (i = 0; i < e->count; ++i, p += e->stride) {
            for (k = 0; k < count; ++k) {
                double value = cloth__load_real(p + offset[k], type[k], ply->big_endian);
                r = cloth__ply_store(ply, cloth__ply_slot(ply, mesh, role[k], i), value, p + offset[k], i);
                if (r != CLOTH_SUCCESS) return r;
            }
        }
        return CLOTH_SUCCESS;
    }
    for (i = 0; i < e->count; ++i) {
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &props[k];
            cloth_real *slot = prop->count_type ? NULL : cloth__ply_slot(ply, mesh, prop->role, i);
            if (ply->binary) {
                size_t size = cloth__type_size[prop->type];
                if (prop->count_type) {
                    int64_t count = cloth__load_int(p, prop->count_type, ply->big_endian);
                    p += cloth__type_size[prop->count_type] + (size_t)count * size;
                } else {
                    if (slot) {
                        r = cloth__ply_store(ply, slot, cloth__load_real(p, prop->type, ply->big_endian), p, i);
                        if (r != CLOTH_SUCCESS) return r;
                    }
                    p += size;
                }
            } else if (prop->count_type) {
                int64_t count = 0, j;
                if ((r = cloth__ply_ascii_count(ply, &p, e, i, &count)) != CLOTH_SUCCESS) return r;
                for (j = 0; j < count; ++j)
                    if ((r = cloth__ply_ascii_skip(ply, &p, e, i)) != CLOTH_SUCCESS) return r;
            } else if (slot) {
                double value = 0;
                const unsigned char *q;
                p = cloth__skip_space(p, end);
                q = cloth__scan_double(p, end, &value);
                if (!q || (q < end && !cloth__is_space(*q)))
                    return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "vertex %lld: '%.*s' is not a number", (long long)i,
                                          cloth__quote_length(p, end), p);
                if ((r = cloth__ply_store(ply, slot, value, p, i)) != CLOTH_SUCCESS) return r;
                p = q;
            } else if ((r = cloth__ply_ascii_skip(ply, &p, e, i)) != CLOTH_SUCCESS) {
                return r;
            }
        }
    }
    return CLOTH_SUCCESS;
}

/* One face index of a binary or ascii file into *index, checked against the vertex count. */
static cloth_result cloth__ply_index(const cloth__ply *ply, const unsigned char **pp, int type, int64_t face, int32_t *index)
{
    const cloth__io *io = ply->io;
    const unsigned char *p = *pp, *end = io->end;
    int64_t v = 0;
    int64_t vertex_count = ply->element[ply->vertex].count;
    if (ply->binary) {
        v = cloth__load_int(p, type, ply->big_endian);
        *pp = p + cloth__type_size[type];
    } else {
        const unsigned char *q;
        p = cloth__skip_space(p, end);
        q = cloth__scan_int(p, end, &v);
        if (!q || (q < end && !cloth__is_space(*q)))
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, p, 1, "face %lld: '%.*s' is not a vertex index", (long long)face,
                                  cloth__quote_length(p, end), p);
        *pp = q;
    }
    if (v < 0 || v >= vertex_count)
        return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, p, !ply->binary, "face %lld names vertex %lld of %lld",
                              (long long)face, (long long)v, (long long)vertex_count);
    *index = (int32_t)v;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__ply_read_faces(const cloth__ply *ply, cloth_mesh *mesh)
{
    const cloth__ply_element *e = &ply->element[ply->face];
    const cloth__ply_property *props = ply->property + e->first_property;
    const unsigned char *p = e->data;
    int32_t *tri = mesh->tri, *tri_end = mesh->tri + 3 * (size_t)mesh->triangle_count;
    int64_t f;
    int k;
    cloth_result r;
    if (ply->binary && ply->all_triangles && e->property_count == 1) {
        /* Fixed stride: a count and three indices per face. */
        int type = props[0].type;
        size_t csize = cloth__type_size[props[0].count_type];
        for (f = 0; f < e->count; ++f) {
            p += csize;
            if ((r = cloth__ply_index(ply, &p, type, f, tri)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__ply_index(ply, &p, type, f, tri + 1)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__ply_index(ply, &p, type, f, tri + 2)) != CLOTH_SUCCESS) return r;
            tri += 3;
        }
        return CLOTH_SUCCESS;
    }
    for (f = 0; f < e->count; ++f) {
        for (k = 0; k < e->property_count; ++k) {
            const cloth__ply_property *prop = &props[k];
            int64_t count = 0, j;
            if (!prop->count_type) {
                if (ply->binary) p += cloth__type_size[prop->type];
                else if ((r = cloth__ply_ascii_skip(ply, &p, e, f)) != CLOTH_SUCCESS) return r;
                continue;
            }
            if (ply->binary) {
                count = cloth__load_int(p, prop->count_type, ply->big_endian);
                p += cloth__type_size[prop->count_type];
            } else if ((r = cloth__ply_ascii_count(ply, &p, e, f, &count)) != CLOTH_SUCCESS) {
                return r;
            }
            if (prop->role != CLOTH__PLY_INDICES) {
                if (ply->binary) {
                    p += (size_t)count * cloth__type_size[prop->type];
                } else {
                    for (j = 0; j < count; ++j)
                        if ((r = cloth__ply_ascii_skip(ply, &p, e, f)) != CLOTH_SUCCESS) return r;
                }
                continue;
            }
            {
                int32_t first = 0, previous = 0, v = 0;
                for (j = 0; j < count; ++j) {
                    if ((r = cloth__ply_index(ply, &p, prop->type, f, &v)) != CLOTH_SUCCESS) return r;
                    if (j == 0) first = v;
                    if (j >= 2 && tri < tri_end) {
                        tri[0] = first;
                        tri[1] = previous;
                        tri[2] = v;
                        tri += 3;
                    }
                    previous = v;
                }
            }
        }
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_ply(const cloth__io *io, cloth_mesh *mesh)
{
    cloth__ply ply;
    cloth_result r;
    int i;
    memset(&ply, 0, sizeof ply);
    ply.io = io;
    ply.vertex = ply.face = -1;
    for (i = 0; i < CLOTH__PLY_ROLE_COUNT; ++i) ply.role[i] = -1;
    r = cloth__ply_header(&ply);
    if (r == CLOTH_SUCCESS) r = cloth__ply_walk(&ply);
    if (r == CLOTH_SUCCESS)
        r = cloth__io_mesh_alloc(io, mesh, ply.element[ply.vertex].count, ply.triangle_count, ply.uv_u != 0, !ply.binary);
    if (r == CLOTH_SUCCESS) r = cloth__ply_read_vertices(&ply, mesh);
    if (r == CLOTH_SUCCESS) r = cloth__ply_read_faces(&ply, mesh);
    cloth__free(&io->allocator, ply.element);
    cloth__free(&io->allocator, ply.property);
    return r;
}

/* ---- VTK legacy ------------------------------------------------------------------------ */

typedef struct cloth__vtk {
    const cloth__io *io;
    const unsigned char *p; /* the cursor */
    int binary;
    int dataset;            /* 1 UNSTRUCTURED_GRID, 2 POLYDATA */
    int64_t point_count;    /* -1 before POINTS */
    cloth_real *points;
    int64_t cell_count;     /* -1 before CELLS (or POLYGONS) */
    int64_t *offsets;       /* cell_count + 1: cell c is connectivity[offsets[c] .. offsets[c+1]) */
    int32_t *connectivity;
    int64_t type_count;     /* -1 before CELL_TYPES */
    int32_t *types;
    const unsigned char *types_at;
} cloth__vtk;

static cloth__type cloth__vtk_type(const unsigned char *p, const unsigned char *e)
{
    static const struct { const char *name; cloth__type type; } names[] = {
        { "unsigned_char", CLOTH__TYPE_UINT8 }, { "char", CLOTH__TYPE_INT8 }, { "unsigned_short", CLOTH__TYPE_UINT16 },
        { "short", CLOTH__TYPE_INT16 }, { "unsigned_int", CLOTH__TYPE_UINT32 }, { "int", CLOTH__TYPE_INT32 },
        { "unsigned_long", CLOTH__TYPE_UINT64 }, { "long", CLOTH__TYPE_INT64 }, { "float", CLOTH__TYPE_FLOAT32 },
        { "double", CLOTH__TYPE_FLOAT64 }, { "vtkIdType", CLOTH__TYPE_INT64 }, { "vtktypeint8", CLOTH__TYPE_INT8 },
        { "vtktypeuint8", CLOTH__TYPE_UINT8 }, { "vtktypeint16", CLOTH__TYPE_INT16 }, { "vtktypeuint16", CLOTH__TYPE_UINT16 },
        { "vtktypeint32", CLOTH__TYPE_INT32 }, { "vtktypeuint32", CLOTH__TYPE_UINT32 }, { "vtktypeint64", CLOTH__TYPE_INT64 },
        { "vtktypeuint64", CLOTH__TYPE_UINT64 }, { "vtktypefloat32", CLOTH__TYPE_FLOAT32 },
        { "vtktypefloat64", CLOTH__TYPE_FLOAT64 }
    };
    size_t i;
    for (i = 0; i < sizeof names / sizeof names[0]; ++i)
        if (cloth__token_is(p, e, names[i].name)) return names[i].type;
    return CLOTH__TYPE_NONE;
}

/* The words of the next line that is not blank (at most `max`, their number returned, 0 at
   the end of the data); the cursor moves past its line break, where binary data starts. */
static int cloth__vtk_line(cloth__vtk *v, const unsigned char **w, const unsigned char **we, int max)
{
    const unsigned char *end = v->io->end;
    while (v->p < end) {
        const unsigned char *p = v->p, *eol = cloth__line_end(p, end);
        int n;
        v->p = eol < end ? eol + 1 : end;
        n = cloth__split_line(p, eol, w, we, max);
        if (n > 0) return n;
    }
    return 0;
}

/* A count from a keyword line. */
static cloth_result cloth__vtk_count(const cloth__vtk *v, const unsigned char *w, const unsigned char *we, int64_t *out)
{
    const unsigned char *q = cloth__scan_int(w, we, out);
    if (!q || q != we || *out < 0)
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w, 1, "bad count '%.*s'", cloth__quote_length(w, we), w);
    return CLOTH_SUCCESS;
}

/* A data type from a keyword line; CLOTH_ERROR_UNSUPPORTED for bit and string data. */
static cloth_result cloth__vtk_data_type(const cloth__vtk *v, const unsigned char *w, const unsigned char *we, int integer,
                                         int *type)
{
    *type = cloth__vtk_type(w, we);
    if (!*type)
        return cloth__io_fail(v->io, CLOTH_ERROR_UNSUPPORTED, w, 1, "VTK data type '%.*s'", cloth__quote_length(w, we), w);
    if (integer && !cloth__type_is_integer(*type))
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w, 1, "cell data of type '%.*s' (integers needed)",
                              cloth__quote_length(w, we), w);
    return CLOTH_SUCCESS;
}

/* Whether `count` values of `type` can follow the cursor at all: each takes its size in
   binary and at least two bytes (but the last) in ascii. Checked before any allocation. */
static cloth_result cloth__vtk_fits(const cloth__vtk *v, int64_t count, int type, const char *what)
{
    uint64_t remaining = (uint64_t)(v->io->end - v->p), per = v->binary ? cloth__type_size[type] : 2;
    if ((uint64_t)count > (remaining + 1) / per)
        return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, !v->binary, "%s: %lld values announced, only %llu bytes remain",
                              what, (long long)count, (unsigned long long)remaining);
    return CLOTH_SUCCESS;
}

/* The next value at the cursor as a double (real) or an integer; *at is where it starts. */
static cloth_result cloth__vtk_value(cloth__vtk *v, int type, int integer, double *real, int64_t *whole, const unsigned char **at)
{
    const unsigned char *end = v->io->end, *p = v->p, *q;
    if (v->binary) {
        size_t size = cloth__type_size[type];
        if ((size_t)(end - p) < size) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 0, "the data ends inside an array");
        if (integer) *whole = cloth__load_int(p, type, 1);
        else *real = cloth__load_real(p, type, 1);
        *at = p;
        v->p = p + size;
        return CLOTH_SUCCESS;
    }
    p = cloth__skip_space(p, end);
    if (p >= end) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside an array");
    q = integer ? cloth__scan_int(p, end, whole) : cloth__scan_double(p, end, real);
    if (!q || (q < end && !cloth__is_space(*q)))
        return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, p, 1, "'%.*s' is not %s", cloth__quote_length(p, end), p,
                              integer ? "an integer" : "a number");
    *at = p;
    v->p = q;
    return CLOTH_SUCCESS;
}

/* Skip `count` values of `type` (already checked with cloth__vtk_fits). */
static cloth_result cloth__vtk_skip(cloth__vtk *v, int64_t count, int type)
{
    const unsigned char *end = v->io->end;
    int64_t i;
    if (v->binary) {
        if ((uint64_t)count > (uint64_t)(end - v->p) / cloth__type_size[type])
            return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, 0, "the data ends inside an array");
        v->p += (size_t)count * cloth__type_size[type];
        return CLOTH_SUCCESS;
    }
    for (i = 0; i < count; ++i) {
        const unsigned char *p = cloth__skip_space(v->p, end);
        if (p >= end) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, p, 1, "the data ends inside an array");
        v->p = cloth__token_end(p, end);
    }
    return CLOTH_SUCCESS;
}

/* Skip a METADATA block: lines up to the first blank one. */
static void cloth__vtk_skip_metadata(cloth__vtk *v)
{
    const unsigned char *end = v->io->end;
    while (v->p < end) {
        const unsigned char *p = v->p, *eol = cloth__line_end(p, end);
        v->p = eol < end ? eol + 1 : end;
        if (cloth__skip_blank(p, eol) == eol) break;
    }
}

/* FIELD name count: skip its arrays. */
static cloth_result cloth__vtk_skip_field(cloth__vtk *v, int64_t arrays)
{
    const unsigned char *w[6], *we[6];
    int64_t a;
    cloth_result r;
    for (a = 0; a < arrays; ++a) {
        int64_t components = 0, tuples = 0;
        int n = cloth__vtk_line(v, w, we, 6), type = 0;
        if (n == 0) return cloth__io_fail(v->io, CLOTH_ERROR_TRUNCATED, v->p, 1, "the data ends inside FIELD data");
        if (cloth__token_is(w[0], we[0], "METADATA")) {
            cloth__vtk_skip_metadata(v);
            --a;
            continue;
        }
        if (cloth__token_is(w[0], we[0], "NULL_ARRAY")) continue;
        if (n != 4) return cloth__io_fail(v->io, CLOTH_ERROR_PARSE, w[0], 1, "a FIELD array is 'NAME COMPONENTS TUPLES TYPE'");
        if ((r = cloth__vtk_count(v, w[1], we[1], &components)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_count(v, w[2], we[2], &tuples)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_data_type(v, w[3], we[3], 0, &type)) != CLOTH_SUCCESS) return r;
        if (components > INT32_MAX || tuples > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "FIELD array");
        if ((r = cloth__vtk_fits(v, components * tuples, type, "FIELD array")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_skip(v, components * tuples, type)) != CLOTH_SUCCESS) return r;
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__vtk_points(cloth__vtk *v, int64_t count, int type)
{
    const cloth__io *io = v->io;
    int64_t i;
    cloth_result r;
    if (count > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "POINTS");
    if ((r = cloth__vtk_fits(v, 3 * count, type, "POINTS")) != CLOTH_SUCCESS) return r;
    v->points = (cloth_real *)cloth__alloc_array(&io->allocator, (size_t)(3 * count), sizeof(cloth_real));
    if (!v->points)
        return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate %lld points", (long long)count);
    for (i = 0; i < 3 * count; ++i) {
        double value = 0;
        int64_t unused = 0;
        const unsigned char *at = NULL;
        if ((r = cloth__vtk_value(v, type, 0, &value, &unused, &at)) != CLOTH_SUCCESS) return r;
        v->points[i] = (cloth_real)value;
        if (!cloth__is_finite(v->points[i]))
            return cloth__io_fail(io, CLOTH_ERROR_NOT_FINITE, at, !v->binary, "point %lld: a coordinate is not finite (%g)",
                                  (long long)(i / 3), value);
    }
    v->point_count = count;
    return CLOTH_SUCCESS;
}

/* One vertex index of a cell, checked against the points. */
static cloth_result cloth__vtk_index(cloth__vtk *v, int type, int64_t cell, int32_t *out)
{
    int64_t index = 0;
    double unused = 0;
    const unsigned char *at = NULL;
    cloth_result r = cloth__vtk_value(v, type, 1, &unused, &index, &at);
    if (r != CLOTH_SUCCESS) return r;
    if (index < 0 || index >= v->point_count)
        return cloth__io_fail(v->io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, at, !v->binary, "cell %lld names point %lld of %lld",
                              (long long)cell, (long long)index, (long long)v->point_count);
    *out = (int32_t)index;
    return CLOTH_SUCCESS;
}

/* A cell array after its keyword line "KEYWORD n size": the classic layout (a count before
   each cell's indices, int32 in binary) or, when OFFSETS follows, the version 5.1 layout
   (n offsets, then size connectivity entries). Every index is checked. */
static cloth_result cloth__vtk_cells(cloth__vtk *v, int64_t n, int64_t size, int64_t *cell_count, int64_t **offsets,
                                     int32_t **connectivity)
{
    const cloth__io *io = v->io;
    const unsigned char *w[4], *we[4], *q = cloth__skip_space(v->p, io->end);
    int64_t c, i;
    cloth_result r;
    if (v->point_count < 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "cells before POINTS");
    if (cloth__starts_with(q, io->end, "OFFSETS")) {
        int type = 0;
        int64_t count = n > 0 ? n - 1 : 0, previous = 0, value = 0;
        double unused = 0;
        const unsigned char *at = NULL;
        if (cloth__vtk_line(v, w, we, 4) != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, q, 1, "expected 'OFFSETS TYPE'");
        if ((r = cloth__vtk_data_type(v, w[1], we[1], 1, &type)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_fits(v, n, type, "OFFSETS")) != CLOTH_SUCCESS) return r;
        if (size > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, type, "CONNECTIVITY");
        if ((r = cloth__vtk_fits(v, size, type, "CONNECTIVITY")) != CLOTH_SUCCESS) return r;
        *offsets = (int64_t *)cloth__alloc_array(&io->allocator, (size_t)count + 1, sizeof(int64_t));
        *connectivity = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)size, sizeof(int32_t));
        if (!*offsets || !*connectivity)
            return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cells");
        (*offsets)[0] = 0;
        for (i = 0; i < n; ++i) {
            if ((r = cloth__vtk_value(v, type, 1, &unused, &value, &at)) != CLOTH_SUCCESS) return r;
            if ((i == 0 && value != 0) || value < previous || value > size)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, at, !v->binary,
                                      "offset %lld is %lld: offsets start at 0 and grow up to the connectivity size %lld",
                                      (long long)i, (long long)value, (long long)size);
            (*offsets)[i] = value;
            previous = value;
        }
        if (previous != size)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, !v->binary,
                                  "the last offset is %lld, not the connectivity size %lld", (long long)previous,
                                  (long long)size);
        if (cloth__vtk_line(v, w, we, 4) != 2 || !cloth__token_is(w[0], we[0], "CONNECTIVITY"))
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "expected 'CONNECTIVITY TYPE' after the offsets");
        if ((r = cloth__vtk_data_type(v, w[1], we[1], 1, &type)) != CLOTH_SUCCESS) return r;
        if ((r = cloth__vtk_fits(v, size, type, "CONNECTIVITY")) != CLOTH_SUCCESS) return r;
        for (c = 0; c < count; ++c)
            for (i = (*offsets)[c]; i < (*offsets)[c + 1]; ++i)
                if ((r = cloth__vtk_index(v, type, c, *connectivity + i)) != CLOTH_SUCCESS) return r;
        *cell_count = count;
        return CLOTH_SUCCESS;
    }
    /* Classic: n cells in size values, each a count and that many indices. */
    if (n > size)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, 1, "%lld cells cannot fit in %lld values", (long long)n,
                              (long long)size);
    if (size > INT32_MAX) return cloth__vtk_fits(v, INT64_MAX, CLOTH__TYPE_INT32, "CELLS");
    if ((r = cloth__vtk_fits(v, size, CLOTH__TYPE_INT32, "CELLS")) != CLOTH_SUCCESS) return r;
    *offsets = (int64_t *)cloth__alloc_array(&io->allocator, (size_t)n + 1, sizeof(int64_t));
    *connectivity = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)(size - n), sizeof(int32_t));
    if (!*offsets || !*connectivity) return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cells");
    for (c = 0, i = 0; c < n; ++c) {
        int64_t k = 0;
        double unused = 0;
        const unsigned char *at = NULL;
        if ((r = cloth__vtk_value(v, CLOTH__TYPE_INT32, 1, &unused, &k, &at)) != CLOTH_SUCCESS) return r;
        if (k < 0 || k > size - n - i)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, at, !v->binary,
                                  "cell %lld has %lld points, more than the cell data holds", (long long)c, (long long)k);
        (*offsets)[c] = i;
        for (; k > 0; --k, ++i)
            if ((r = cloth__vtk_index(v, CLOTH__TYPE_INT32, c, *connectivity + i)) != CLOTH_SUCCESS) return r;
    }
    (*offsets)[n] = i;
    if (i != size - n)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v->p, !v->binary, "the cells hold %lld values, the header says %lld",
                              (long long)(i + n), (long long)size);
    *cell_count = n;
    return CLOTH_SUCCESS;
}

/* The keyword loop: everything up to the first attribute section or the end of the data. */
static cloth_result cloth__vtk_sections(cloth__vtk *v)
{
    const cloth__io *io = v->io;
    const unsigned char *w[6], *we[6];
    cloth_result r;
    int n;
    while ((n = cloth__vtk_line(v, w, we, 6)) > 0) {
        const unsigned char *k = w[0], *ke = we[0];
        int64_t a = 0, b = 0;
        int type = 0;
        if (cloth__token_is(k, ke, "DATASET")) {
            if (v->dataset) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second DATASET");
            if (n != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'DATASET TYPE'");
            if (cloth__token_is(w[1], we[1], "UNSTRUCTURED_GRID")) v->dataset = 1;
            else if (cloth__token_is(w[1], we[1], "POLYDATA")) v->dataset = 2;
            else if (cloth__token_is(w[1], we[1], "STRUCTURED_POINTS") || cloth__token_is(w[1], we[1], "STRUCTURED_GRID") ||
                     cloth__token_is(w[1], we[1], "RECTILINEAR_GRID") || cloth__token_is(w[1], we[1], "FIELD"))
                return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, w[1], 1,
                                      "VTK dataset %.*s (only UNSTRUCTURED_GRID and POLYDATA are read)",
                                      cloth__quote_length(w[1], we[1]), w[1]);
            else
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "unknown VTK dataset '%.*s'",
                                      cloth__quote_length(w[1], we[1]), w[1]);
        } else if (cloth__token_is(k, ke, "FIELD")) {
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'FIELD NAME ARRAYS'");
            if ((r = cloth__vtk_count(v, w[2], we[2], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_skip_field(v, a)) != CLOTH_SUCCESS) return r;
        } else if (cloth__token_is(k, ke, "METADATA")) {
            cloth__vtk_skip_metadata(v);
        } else if (cloth__token_is(k, ke, "POINT_DATA") || cloth__token_is(k, ke, "CELL_DATA")) {
            break; /* attributes: nothing more of the geometry follows */
        } else if (!v->dataset) {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "'%.*s' before the DATASET line", cloth__quote_length(k, ke), k);
        } else if (cloth__token_is(k, ke, "POINTS")) {
            if (v->point_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second POINTS section");
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'POINTS COUNT TYPE'");
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_data_type(v, w[2], we[2], 0, &type)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_points(v, a, type)) != CLOTH_SUCCESS) return r;
        } else if ((v->dataset == 1 && cloth__token_is(k, ke, "CELLS")) ||
                   (v->dataset == 2 && cloth__token_is(k, ke, "POLYGONS"))) {
            if (v->cell_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second %.*s section", (int)(ke - k), k);
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected '%.*s COUNT SIZE'", (int)(ke - k), k);
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_count(v, w[2], we[2], &b)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_cells(v, a, b, &v->cell_count, &v->offsets, &v->connectivity)) != CLOTH_SUCCESS) return r;
        } else if (v->dataset == 2 && (cloth__token_is(k, ke, "VERTICES") || cloth__token_is(k, ke, "LINES") ||
                                       cloth__token_is(k, ke, "TRIANGLE_STRIPS"))) {
            int64_t count = 0, *offsets = NULL;
            int32_t *connectivity = NULL;
            if (n != 3) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected '%.*s COUNT SIZE'", (int)(ke - k), k);
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if ((r = cloth__vtk_count(v, w[2], we[2], &b)) != CLOTH_SUCCESS) return r;
            r = cloth__vtk_cells(v, a, b, &count, &offsets, &connectivity);
            cloth__free(&io->allocator, offsets);
            cloth__free(&io->allocator, connectivity);
            if (r != CLOTH_SUCCESS) return r;
        } else if (v->dataset == 1 && cloth__token_is(k, ke, "CELL_TYPES")) {
            int64_t i;
            if (v->type_count >= 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "a second CELL_TYPES section");
            if (v->cell_count < 0) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "CELL_TYPES before CELLS");
            if (n != 2) return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "expected 'CELL_TYPES COUNT'");
            if ((r = cloth__vtk_count(v, w[1], we[1], &a)) != CLOTH_SUCCESS) return r;
            if (a != v->cell_count)
                return cloth__io_fail(io, CLOTH_ERROR_PARSE, w[1], 1, "%lld cell types for %lld cells", (long long)a,
                                      (long long)v->cell_count);
            if ((r = cloth__vtk_fits(v, a, CLOTH__TYPE_INT32, "CELL_TYPES")) != CLOTH_SUCCESS) return r;
            v->types = (int32_t *)cloth__alloc_array(&io->allocator, (size_t)a, sizeof(int32_t));
            if (!v->types) return cloth__io_fail(io, CLOTH_ERROR_OUT_OF_MEMORY, NULL, 0, "cannot allocate the cell types");
            v->types_at = cloth__skip_space(v->p, io->end);
            for (i = 0; i < a; ++i) {
                int64_t t = 0;
                double unused = 0;
                const unsigned char *at = NULL;
                if ((r = cloth__vtk_value(v, CLOTH__TYPE_INT32, 1, &unused, &t, &at)) != CLOTH_SUCCESS) return r;
                v->types[i] = t < 0 || t > 1000 ? -1 : (int32_t)t;
            }
            v->type_count = a;
        } else {
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "unknown VTK keyword '%.*s'", cloth__quote_length(k, ke), k);
        }
    }
    return CLOTH_SUCCESS;
}

static cloth_result cloth__read_vtk(const cloth__io *io, cloth_mesh *mesh)
{
    cloth__vtk v;
    const unsigned char *w[4], *we[4], *end = io->end, *eol;
    cloth_result r = CLOTH_SUCCESS;
    int64_t c, triangles = 0;
    int n;
    memset(&v, 0, sizeof v);
    v.io = io;
    v.point_count = v.cell_count = v.type_count = -1;
    /* "# vtk DataFile Version x.y", a title line, ASCII or BINARY */
    v.p = io->begin;
    eol = cloth__line_end(v.p, end);
    if (!cloth__starts_with(cloth__skip_blank(v.p, eol), eol, "# vtk DataFile"))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1,
                              "not a VTK legacy file: the first line is not '# vtk DataFile Version ...'");
    if (eol >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the VTK header ends after its first line");
    eol = cloth__line_end(eol + 1, end);
    if (eol >= end) return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the VTK header ends after its title line");
    v.p = eol + 1;
    eol = cloth__line_end(v.p, end);
    n = cloth__split_line(v.p, eol, w, we, 4);
    if (n == 1 && cloth__token_is(w[0], we[0], "ASCII")) v.binary = 0;
    else if (n == 1 && cloth__token_is(w[0], we[0], "BINARY")) v.binary = 1;
    else return cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "the third line of a VTK file must be ASCII or BINARY");
    v.p = eol < end ? eol + 1 : end;

    r = cloth__vtk_sections(&v);
    if (r == CLOTH_SUCCESS && !v.dataset) r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "the VTK file has no DATASET line");
    if (r == CLOTH_SUCCESS && v.point_count < 0)
        r = cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, v.p, 1, "the VTK file has no POINTS");
    if (r == CLOTH_SUCCESS && v.dataset == 1 && v.cell_count >= 0 && v.type_count < 0)
        r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.p, 1, "CELLS without CELL_TYPES");
    /* Count the triangles the cells make. */
    for (c = 0; r == CLOTH_SUCCESS && c < (v.cell_count > 0 ? v.cell_count : 0); ++c) {
        int64_t k = v.offsets[c + 1] - v.offsets[c];
        int type = v.dataset == 2 ? 7 : v.types[c];
        if ((type == 5 && k != 3) || (type == 9 && k != 4) || (type == 7 && k < 3))
            r = cloth__io_fail(io, CLOTH_ERROR_PARSE, v.types_at, !v.binary, "cell %lld of type %d has %lld points", (long long)c,
                               type, (long long)k);
        else if (type == 5 || type == 9 || type == 7)
            triangles += k - 2;
    }
    if (r == CLOTH_SUCCESS) r = cloth__io_mesh_alloc(io, mesh, v.point_count, triangles, 0, !v.binary);
    if (r == CLOTH_SUCCESS) {
        int32_t *tri = mesh->tri;
        memcpy(mesh->x, v.points, sizeof(cloth_real) * 3 * (size_t)v.point_count);
        for (c = 0; c < v.cell_count; ++c) {
            int type = v.dataset == 2 ? 7 : v.types[c];
            const int32_t *cell = v.connectivity + v.offsets[c];
            int64_t k = v.offsets[c + 1] - v.offsets[c], j;
            if (type != 5 && type != 9 && type != 7) continue;
            for (j = 2; j < k; ++j) {
                tri[0] = cell[0];
                tri[1] = cell[j - 1];
                tri[2] = cell[j];
                tri += 3;
            }
        }
    }
    cloth__free(&io->allocator, v.points);
    cloth__free(&io->allocator, v.offsets);
    cloth__free(&io->allocator, v.connectivity);
    cloth__free(&io->allocator, v.types);
    return r;
}

/* ---- OFF ----------------------------------------------------------------------------- */

/* The next line at or after *pp that is neither blank nor a comment: its first non-blank
   byte in *line and its end in *eol; 0 at the end of the data. */
static int cloth__next_content_line(const unsigned char **pp, const unsigned char *end, const unsigned char **line,
                                    const unsigned char **eol)
{
    const unsigned char *p = *pp;
    while (p < end) {
        const unsigned char *e = cloth__line_end(p, end), *q = cloth__skip_blank(p, e);
        p = e < end ? e + 1 : end;
        if (q < e && *q != '#') {
            *line = q;
            *eol = e;
            *pp = p;
            return 1;
        }
    }
    *pp = end;
    return 0;
}

/* Whether [p, e) is an OFF keyword: OFF with any of the prefixes ST, C, N, 4 and n. *plain is
   cleared by the 4 (four-dimensional) and n (n-dimensional) prefixes, which cloth.h does not read. */
static int cloth__off_keyword(const unsigned char *p, const unsigned char *e, int *plain)
{
    *plain = 1;
    if (e - p < 3 || memcmp(e - 3, "OFF", 3) != 0) return 0;
    for (; p < e - 3; ++p) {
        if (*p == '4' || *p == 'n') *plain = 0;
        else if (*p != 'S' && *p != 'T' && *p != 'C' && *p != 'N') return 0;
    }
    return 1;
}

static cloth_result cloth__read_off(const cloth__io *io, cloth_mesh *mesh)
{
    const unsigned char *end = io->end, *p = cloth__skip_bom(io->begin, end), *line = NULL, *eol = NULL, *k, *body;
    int64_t vertex_count = 0, face_count = 0, triangles = 0, i, j;
    int plain = 1;
    cloth_result r;
    if (!cloth__next_content_line(&p, end, &line, &eol))
        return cloth__io_fail(io, CLOTH_ERROR_EMPTY_MESH, end, 1, "the OFF file is empty");
    k = line;
    line = cloth__obj_keyword_end(line, eol);
    if (!cloth__off_keyword(k, line, &plain))
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "not an OFF file: the first word is not OFF");
    if (!plain) return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, k, 1, "OFF files of other than three dimensions");
    line = cloth__skip_blank(line, eol);
    if (line < eol && *line != '#') {
        if (cloth__starts_with(line, eol, "BINARY")) return cloth__io_fail(io, CLOTH_ERROR_UNSUPPORTED, line, 1, "binary OFF");
    } else if (!cloth__next_content_line(&p, end, &line, &eol)) {
        return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the OFF file ends before its counts");
    }
    if ((r = cloth__text_int(io, &line, eol, &vertex_count, "vertex count")) != CLOTH_SUCCESS) return r;
    if ((r = cloth__text_int(io, &line, eol, &face_count, "face count")) != CLOTH_SUCCESS) return r;
    if (vertex_count < 0 || face_count < 0)
        return cloth__io_fail(io, CLOTH_ERROR_PARSE, line, 1, "negative counts %lld %lld", (long long)vertex_count,
                              (long long)face_count);
    body = p;
    /* First pass: every vertex line is there; count the triangles of the faces. */
    for (i = 0; i < vertex_count; ++i)
        if (!cloth__next_content_line(&p, end, &line, &eol))
            return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the header announces %lld vertices, the file has %lld",
                                  (long long)vertex_count, (long long)i);
    for (i = 0; i < face_count; ++i) {
        int64_t corners = 0;
        if (!cloth__next_content_line(&p, end, &line, &eol))
            return cloth__io_fail(io, CLOTH_ERROR_TRUNCATED, end, 1, "the header announces %lld faces, the file has %lld",
                                  (long long)face_count, (long long)i);
        k = line;
        if ((r = cloth__text_int(io, &line, eol, &corners, "face vertex count")) != CLOTH_SUCCESS) return r;
        if (corners < 3)
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1, "face %lld has %lld vertices (at least 3 needed)", (long long)i,
                                  (long long)corners);
        if (corners > (eol - line) / 2) /* each index takes at least two bytes of the line */
            return cloth__io_fail(io, CLOTH_ERROR_PARSE, k, 1,
                                  "face %lld announces %lld vertices; its line is too short for them", (long long)i,
                                  (long long)corners);
        triangles += corners - 2;
    }
    if ((r = cloth__io_mesh_alloc(io, mesh, vertex_count, triangles, 0, 1)) != CLOTH_SUCCESS) return r;
    /* Second pass: read. */
    p = body;
    for (i = 0; i < vertex_count; ++i) {
        cloth_real *x = mesh->x + 3 * i;
        cloth__next_content_line(&p, end, &line, &eol);
        if ((r = cloth__text_real(io, &line, eol, x, "vertex x")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__text_real(io, &line, eol, x + 1, "vertex y")) != CLOTH_SUCCESS) return r;
        if ((r = cloth__text_real(io, &line, eol, x + 2, "vertex z")) != CLOTH_SUCCESS) return r;
    }
    {
        int32_t *tri = mesh->tri;
        for (i = 0; i < face_count; ++i) {
            int64_t corners = 0;
            int32_t first = 0, previous = 0;
            cloth__next_content_line(&p, end, &line, &eol);
            cloth__text_int(io, &line, eol, &corners, "face vertex count");
            for (j = 0; j < corners; ++j) {
                int64_t v = 0;
                const unsigned char *at = cloth__skip_blank(line, eol);
                if ((r = cloth__text_int(io, &line, eol, &v, "face index")) != CLOTH_SUCCESS) return r;
                if (v < 0 || v >= vertex_count)
                    return cloth__io_fail(io, CLOTH_ERROR_INDEX_OUT_OF_RANGE, at, 1, "face %lld names vertex %lld of %lld",
                                          (long long)i, (long long)v, (long long)vertex_count);
                if (j == 0) first = (int32_t)v;
                if (j >= 2) {
                    tri[0] = first;
                    tri[1] = previous;
                    tri[2] = (int32_t)v;
                    tri += 3;
                }
                previous = (int32_t)v;
            }
        }
    }
    return CLOTH_SUCCESS;
}

/* ---- format detection and the public readers -------------------------------------------- */

CLOTH_API cloth_file_format cloth_detect_format(const void *data, size_t size)
{
    const unsigned char *begin = (const unsigned char *)data, *end = begin + (data ? size : 0), *p, *line, *eol;
    int plain = 1;
    if (!data || size == 0) return CLOTH_FORMAT_AUTO;
    p = cloth__skip_bom(begin, end);
    if (end - p >= 3 && memcmp(p, "ply", 3) == 0 && (end - p == 3 || p[3] == '\n' || p[3] == '\r')) {
        /* the encoding from the format line of the header */
        for (p = cloth__line_end(p, end); p < end; p = cloth__line_end(p + 1, end)) {
            const unsigned char *w[3], *we[3];
            int n;
            eol = cloth__line_end(p + 1, end);
            n = cloth__split_line(p + 1, eol, w, we, 3);
            if (n >= 1 && cloth__bytes_are(w[0], we[0], "end_header")) break;
            if (n >= 2 && cloth__bytes_are(w[0], we[0], "format")) {
                if (cloth__bytes_are(w[1], we[1], "binary_little_endian")) return CLOTH_FORMAT_PLY_BINARY_LE;
                if (cloth__bytes_are(w[1], we[1], "binary_big_endian")) return CLOTH_FORMAT_PLY_BINARY_BE;
                break;
            }
        }
        return CLOTH_FORMAT_PLY_ASCII;
    }
    if (cloth__starts_with(cloth__skip_blank(p, end), end, "# vtk DataFile")) {
        /* ASCII or BINARY on the third line */
        eol = cloth__line_end(p, end);
        if (eol < end) eol = cloth__line_end(eol + 1, end);
        if (eol < end) {
            const unsigned char *w[2], *we[2];
            line = eol + 1;
            eol = cloth__line_end(line, end);
            if (cloth__split_line(line, eol, w, we, 2) == 1 && cloth__token_is(w[0], we[0], "BINARY"))
                return CLOTH_FORMAT_VTK_BINARY;
        }
        return CLOTH_FORMAT_VTK_ASCII;
    }
    if (cloth__next_content_line(&p, end, &line, &eol)) {
        const unsigned char *k = cloth__obj_keyword_end(line, eol);
        if (cloth__off_keyword(line, k, &plain)) return CLOTH_FORMAT_OFF;
        if (cloth__obj_keyword(line, k) != CLOTH__OBJ_UNKNOWN) return CLOTH_FORMAT_OBJ;
    }
    return CLOTH_FORMAT_AUTO;
}

/* The format of a path's extension, CLOTH_FORMAT_AUTO when it has none that cloth.h knows;
   `writing` picks binary PLY and VTK. */
static cloth_file_format cloth__format_of_path(const char *path, int writing)
{
    const char *dot = strrchr(path, '.');
    const unsigned char *e;
    if (!dot) return CLOTH_FORMAT_AUTO;
    e = (const unsigned char *)dot + strlen(dot);
    if (cloth__token_is((const unsigned char *)dot, e, ".obj")) return CLOTH_FORMAT_OBJ;
    if (cloth__token_is((const unsigned char *)dot, e, ".ply"))
        return writing ? CLOTH_FORMAT_PLY_BINARY_LE : CLOTH_FORMAT_PLY_ASCII;
    if (cloth__token_is((const unsigned char *)dot, e, ".vtk")) return writing ? CLOTH_FORMAT_VTK_BINARY : CLOTH_FORMAT_VTK_ASCII;
    if (cloth__token_is((const unsigned char *)dot, e, ".off")) return CLOTH_FORMAT_OFF;
    return CLOTH_FORMAT_AUTO;
}

static cloth_result cloth__read_format(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                       cloth_io_error *error, const cloth_allocator *allocator, const char *path)
{
    cloth_io_error local;
    cloth__io io;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL);
    CLOTH_ASSERT(data != NULL || size == 0);
    memset(mesh, 0, sizeof *mesh);
    io.begin = (const unsigned char *)data;
    io.end = io.begin + (data ? size : 0);
    io.error = error ? error : &local;
    io.allocator = cloth__allocator_or_default(allocator);
    memset(io.error, 0, sizeof *io.error);
    if (!data) io.begin = io.end = (const unsigned char *)"";
    if (cloth__skip_space(io.begin, io.end) == io.end)
        return cloth__io_fail(&io, CLOTH_ERROR_EMPTY_MESH, io.end, 1, "the input is empty");
    if (format == CLOTH_FORMAT_AUTO) format = cloth_detect_format(io.begin, size);
    if (format == CLOTH_FORMAT_AUTO && path) format = cloth__format_of_path(path, 0);
    if (format == CLOTH_FORMAT_AUTO)
        return cloth__io_fail(&io, CLOTH_ERROR_PARSE, io.begin, 1, "the content is not OBJ, PLY, VTK legacy or OFF");
    switch (format) {
    case CLOTH_FORMAT_OBJ: r = cloth__read_obj(&io, mesh); break;
    case CLOTH_FORMAT_PLY_ASCII:
    case CLOTH_FORMAT_PLY_BINARY_LE:
    case CLOTH_FORMAT_PLY_BINARY_BE: r = cloth__read_ply(&io, mesh); break;
    case CLOTH_FORMAT_VTK_ASCII:
    case CLOTH_FORMAT_VTK_BINARY: r = cloth__read_vtk(&io, mesh); break;
    case CLOTH_FORMAT_OFF: r = cloth__read_off(&io, mesh); break;
    default: r = cloth__io_fail(&io, CLOTH_ERROR_INVALID_ARGUMENT, NULL, 0, "unknown file format %d", (int)format); break;
    }
    if (r != CLOTH_SUCCESS) {
        if (mesh->x || mesh->tri || mesh->uv) cloth_mesh_free(mesh);
        memset(mesh, 0, sizeof *mesh);
    }
    return r;
}

CLOTH_API cloth_result cloth_mesh_read_memory(cloth_mesh *mesh, const void *data, size_t size, cloth_file_format format,
                                              cloth_io_error *error, const cloth_allocator *allocator)
{
    return cloth__read_format(mesh, data, size, format, error, allocator, NULL);
}

/* ---- writing ------------------------------------------------------------------------- */

/* Where a writer's bytes go: a buffer that grows (memory) or one that is flushed to a file. */
typedef struct cloth__sink {
    unsigned char *data;
    size_t size, capacity;
    cloth_allocator allocator; /* memory: what the buffer grows with */
    void *file;                /* a FILE * when writing a file, else NULL */
    cloth_result result;
} cloth__sink;

/* Room for n more bytes (a short piece: a number, a record, a header line), or NULL after
   a failure (recorded in s->result). */
static unsigned char *cloth__sink_room(cloth__sink *s, size_t n)
{
    if (s->result != CLOTH_SUCCESS) return NULL;
    if (s->capacity - s->size >= n) return s->data + s->size;
#ifndef CLOTH_NO_STDIO
    if (s->file) {
        if (n > s->capacity || fwrite(s->data, 1, s->size, (FILE *)s->file) != s->size) {
            s->result = CLOTH_ERROR_FILE_WRITE;
            return NULL;
        }
        s->size = 0;
        return s->data;
    }
#endif
    {
        size_t capacity = s->capacity < 4096 ? 4096 : s->capacity;
        unsigned char *grown;
        while (capacity - s->size < n) {
            if (capacity > SIZE_MAX / 2) {
                s->result = CLOTH_ERROR_SIZE_OVERFLOW;
                return NULL;
            }
            capacity *= 2;
        }
        grown = (unsigned char *)s->allocator.alloc(capacity, s->allocator.user);
        if (!grown) {
            s->result = CLOTH_ERROR_OUT_OF_MEMORY;
            return NULL;
        }
        if (s->size) memcpy(grown, s->data, s->size);
        cloth__free(&s->allocator, s->data);
        s->data = grown;
        s->capacity = capacity;
        return grown + s->size;
    }
}

static void cloth__sink_bytes(cloth__sink *s, const void *bytes, size_t n)
{
    unsigned char *room = cloth__sink_room(s, n);
    if (!room) return;
    memcpy(room, bytes, n);
    s->size += n;
}

static void cloth__sink_text(cloth__sink *s, const char *text) { cloth__sink_bytes(s, text, strlen(text)); }

/* A real with enough digits to round-trip, followed by `after`. The decimal separator of
   the C locale is forced back to '.', so a locale with a decimal comma does not leak in. */
static void cloth__sink_real(cloth__sink *s, cloth_real value, char after)
{
    char text[40];
    int n = snprintf(text, sizeof text, sizeof(cloth_real) == sizeof(float) ? "%.9g" : "%.17g", (double)value), i;
    unsigned char *room;
    if (n <= 0 || n >= (int)sizeof text - 1) {
        s->result = CLOTH_ERROR_FILE_WRITE;
        return;
    }
    for (i = 0; i < n; ++i)
        if (!cloth__is_digit(text[i]) && text[i] != '-' && text[i] != '+' && text[i] != 'e') text[i] = '.';
    text[n++] = after;
    if ((room = cloth__sink_room(s, (size_t)n)) == NULL) return;
    memcpy(room, text, (size_t)n);
    s->size += (size_t)n;
}

/* A non-negative integer followed by `after`. */
static void cloth__sink_int(cloth__sink *s, int64_t value, char after)
{
    char text[24];
    int n = 0, i;
    unsigned char *room;
    uint64_t v = value < 0 ? 0 : (uint64_t)value;
    do {
        text[n++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    if ((room = cloth__sink_room(s, (size_t)n + 1)) == NULL) return;
    for (i = 0; i < n; ++i) room[i] = (unsigned char)text[n - 1 - i];
    room[n] = (unsigned char)after;
    s->size += (size_t)n + 1;
}

static void cloth__store_u32(unsigned char *p, uint32_t v, int big_endian)
{
    int i;
    for (i = 0; i < 4; ++i) p[big_endian ? 3 - i : i] = (unsigned char)(v >> (8 * i));
}

static void cloth__store_f64(unsigned char *p, double value, int big_endian)
{
    uint64_t v;
    int i;
    memcpy(&v, &value, sizeof v);
    for (i = 0; i < 8; ++i) p[big_endian ? 7 - i : i] = (unsigned char)(v >> (8 * i));
}

/* A mesh that cloth.h can read back: vertices and triangles, finite numbers, indices in range. */
static cloth_result cloth__write_check(const cloth_mesh *mesh)
{
    int64_t i;
    if (mesh->vertex_count <= 0 || mesh->triangle_count <= 0) return CLOTH_ERROR_EMPTY_MESH;
    if (!mesh->x || !mesh->tri) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < 3 * (int64_t)mesh->vertex_count; ++i)
        if (!cloth__is_finite(mesh->x[i])) return CLOTH_ERROR_NOT_FINITE;
    if (mesh->uv)
        for (i = 0; i < 2 * (int64_t)mesh->vertex_count; ++i)
            if (!cloth__is_finite(mesh->uv[i])) return CLOTH_ERROR_NOT_FINITE;
    for (i = 0; i < 3 * (int64_t)mesh->triangle_count; ++i)
        if (mesh->tri[i] < 0 || mesh->tri[i] >= mesh->vertex_count) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    return CLOTH_SUCCESS;
}

static void cloth__write_obj(cloth__sink *s, const cloth_mesh *m)
{
    int64_t i;
    cloth__sink_text(s, "# written by cloth.h " CLOTH_VERSION_STRING "\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "v ");
        cloth__sink_real(s, m->x[3 * i], ' ');
        cloth__sink_real(s, m->x[3 * i + 1], ' ');
        cloth__sink_real(s, m->x[3 * i + 2], '\n');
    }
    for (i = 0; m->uv && i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "vt ");
        cloth__sink_real(s, m->uv[2 * i], ' ');
        cloth__sink_real(s, m->uv[2 * i + 1], '\n');
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        int k;
        cloth__sink_text(s, "f ");
        for (k = 0; k < 3; ++k) {
            int64_t v = (int64_t)m->tri[3 * i + k] + 1;
            if (m->uv) cloth__sink_int(s, v, '/');
            cloth__sink_int(s, v, k == 2 ? '\n' : ' ');
        }
    }
}

static void cloth__write_ply(cloth__sink *s, const cloth_mesh *m, cloth_file_format format)
{
    int binary = format != CLOTH_FORMAT_PLY_ASCII, big_endian = format == CLOTH_FORMAT_PLY_BINARY_BE;
    int64_t i;
    cloth__sink_text(s, "ply\nformat ");
    cloth__sink_text(s, !binary ? "ascii" : big_endian ? "binary_big_endian" : "binary_little_endian");
    cloth__sink_text(s, " 1.0\ncomment written by cloth.h " CLOTH_VERSION_STRING "\nelement vertex ");
    cloth__sink_int(s, m->vertex_count, '\n');
    cloth__sink_text(s, "property double x\nproperty double y\nproperty double z\n");
    if (m->uv) cloth__sink_text(s, "property double u\nproperty double v\n");
    cloth__sink_text(s, "element face ");
    cloth__sink_int(s, m->triangle_count, '\n');
    cloth__sink_text(s, "property list uchar int vertex_indices\nend_header\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[40];
            size_t n = m->uv ? 40 : 24;
            cloth__store_f64(record, (double)m->x[3 * i], big_endian);
            cloth__store_f64(record + 8, (double)m->x[3 * i + 1], big_endian);
            cloth__store_f64(record + 16, (double)m->x[3 * i + 2], big_endian);
            if (m->uv) {
                cloth__store_f64(record + 24, (double)m->uv[2 * i], big_endian);
                cloth__store_f64(record + 32, (double)m->uv[2 * i + 1], big_endian);
            }
            cloth__sink_bytes(s, record, n);
        } else {
            cloth__sink_real(s, m->x[3 * i], ' ');
            cloth__sink_real(s, m->x[3 * i + 1], ' ');
            cloth__sink_real(s, m->x[3 * i + 2], m->uv ? ' ' : '\n');
            if (m->uv) {
                cloth__sink_real(s, m->uv[2 * i], ' ');
                cloth__sink_real(s, m->uv[2 * i + 1], '\n');
            }
        }
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        const int32_t *t = m->tri + 3 * i;
        if (binary) {
            unsigned char record[13];
            record[0] = 3;
            cloth__store_u32(record + 1, (uint32_t)t[0], big_endian);
            cloth__store_u32(record + 5, (uint32_t)t[1], big_endian);
            cloth__store_u32(record + 9, (uint32_t)t[2], big_endian);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "3 ");
            cloth__sink_int(s, t[0], ' ');
            cloth__sink_int(s, t[1], ' ');
            cloth__sink_int(s, t[2], '\n');
        }
    }
}

static void cloth__write_vtk(cloth__sink *s, const cloth_mesh *m, int binary)
{
    int64_t i;
    cloth__sink_text(s, "# vtk DataFile Version 4.2\nwritten by cloth.h " CLOTH_VERSION_STRING "\n");
    cloth__sink_text(s, binary ? "BINARY\n" : "ASCII\n");
    cloth__sink_text(s, "DATASET UNSTRUCTURED_GRID\nPOINTS ");
    cloth__sink_int(s, m->vertex_count, ' ');
    cloth__sink_text(s, "double\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[24];
            cloth__store_f64(record, (double)m->x[3 * i], 1);
            cloth__store_f64(record + 8, (double)m->x[3 * i + 1], 1);
            cloth__store_f64(record + 16, (double)m->x[3 * i + 2], 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_real(s, m->x[3 * i], ' ');
            cloth__sink_real(s, m->x[3 * i + 1], ' ');
            cloth__sink_real(s, m->x[3 * i + 2], '\n');
        }
    }
    cloth__sink_text(s, binary ? "\nCELLS " : "CELLS ");
    cloth__sink_int(s, m->triangle_count, ' ');
    cloth__sink_int(s, 4 * (int64_t)m->triangle_count, '\n');
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        const int32_t *t = m->tri + 3 * i;
        if (binary) {
            unsigned char record[16];
            cloth__store_u32(record, 3, 1);
            cloth__store_u32(record + 4, (uint32_t)t[0], 1);
            cloth__store_u32(record + 8, (uint32_t)t[1], 1);
            cloth__store_u32(record + 12, (uint32_t)t[2], 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "3 ");
            cloth__sink_int(s, t[0], ' ');
            cloth__sink_int(s, t[1], ' ');
            cloth__sink_int(s, t[2], '\n');
        }
    }
    cloth__sink_text(s, binary ? "\nCELL_TYPES " : "CELL_TYPES ");
    cloth__sink_int(s, m->triangle_count, '\n');
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        if (binary) {
            unsigned char record[4];
            cloth__store_u32(record, 5, 1);
            cloth__sink_bytes(s, record, sizeof record);
        } else {
            cloth__sink_text(s, "5\n");
        }
    }
    if (binary) cloth__sink_text(s, "\n");
}

static void cloth__write_off(cloth__sink *s, const cloth_mesh *m)
{
    int64_t i;
    cloth__sink_text(s, "OFF\n");
    cloth__sink_int(s, m->vertex_count, ' ');
    cloth__sink_int(s, m->triangle_count, ' ');
    cloth__sink_text(s, "0\n");
    for (i = 0; i < m->vertex_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_real(s, m->x[3 * i], ' ');
        cloth__sink_real(s, m->x[3 * i + 1], ' ');
        cloth__sink_real(s, m->x[3 * i + 2], '\n');
    }
    for (i = 0; i < m->triangle_count && s->result == CLOTH_SUCCESS; ++i) {
        cloth__sink_text(s, "3 ");
        cloth__sink_int(s, m->tri[3 * i], ' ');
        cloth__sink_int(s, m->tri[3 * i + 1], ' ');
        cloth__sink_int(s, m->tri[3 * i + 2], '\n');
    }
}

static cloth_result cloth__write_sink(cloth__sink *s, const cloth_mesh *mesh, cloth_file_format format)
{
    cloth_result r = cloth__write_check(mesh);
    if (r != CLOTH_SUCCESS) return r;
    switch (format) {
    case CLOTH_FORMAT_OBJ: cloth__write_obj(s, mesh); break;
    case CLOTH_FORMAT_PLY_ASCII:
    case CLOTH_FORMAT_PLY_BINARY_LE:
    case CLOTH_FORMAT_PLY_BINARY_BE: cloth__write_ply(s, mesh, format); break;
    case CLOTH_FORMAT_VTK_ASCII:
    case CLOTH_FORMAT_VTK_BINARY: cloth__write_vtk(s, mesh, format == CLOTH_FORMAT_VTK_BINARY); break;
    case CLOTH_FORMAT_OFF: cloth__write_off(s, mesh); break;
    default: return CLOTH_ERROR_INVALID_ARGUMENT;
    }
    return s->result;
}

CLOTH_API cloth_result cloth_mesh_write_memory(const cloth_mesh *mesh, cloth_file_format format, void **data, size_t *size,
                                               const cloth_allocator *allocator)
{
    cloth__sink s;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL && data != NULL && size != NULL);
    *data = NULL;
    *size = 0;
    memset(&s, 0, sizeof s);
    s.allocator = cloth__allocator_or_default(allocator);
    r = cloth__write_sink(&s, mesh, format);
    if (r != CLOTH_SUCCESS) {
        cloth__free(&s.allocator, s.data);
        return r;
    }
    *data = s.data;
    *size = s.size;
    return CLOTH_SUCCESS;
}

#ifndef CLOTH_NO_STDIO
/* The whole file at path in a buffer from the allocator. */
static cloth_result cloth__read_whole_file(const char *path, const cloth_allocator *allocator, unsigned char **data, size_t *size,
                                           cloth_io_error *error)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buffer = NULL;
    size_t used = 0, capacity = 0;
    long length;
    int first;
    *data = NULL;
    *size = 0;
    if (!f) {
        snprintf(error->message, sizeof error->message, "cannot open '%.120s'", path);
        return CLOTH_ERROR_FILE_OPEN;
    }
    /* The size when the file can tell it (after a first byte could be read: a directory may
       claim any size), then grow for files that grow or cannot seek. */
    if (fseek(f, 0, SEEK_END) == 0 && (length = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0) capacity = (size_t)length + 1;
    else rewind(f);
    first = fgetc(f);
    if (first == EOF) {
        int failed = ferror(f);
        fclose(f);
        if (failed) {
            snprintf(error->message, sizeof error->message, "cannot read '%.120s'", path);
            return CLOTH_ERROR_FILE_READ;
        }
        *data = (unsigned char *)cloth__alloc_array(allocator, 0, 1); /* an empty file: an empty buffer */
        if (*data) return CLOTH_SUCCESS;
        snprintf(error->message, sizeof error->message, "out of memory");
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    if (capacity < 4096) capacity = 4096;
    for (;;) {
        size_t got;
        if (!buffer || used == capacity) {
            unsigned char *grown;
            size_t next = buffer ? capacity * 2 : capacity;
            if (buffer && capacity > SIZE_MAX / 2) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "'%.120s' is too large", path);
                return CLOTH_ERROR_SIZE_OVERFLOW;
            }
            grown = (unsigned char *)cloth__alloc_array(allocator, next, 1);
            if (!grown) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "cannot allocate %lu bytes for '%.100s'", (unsigned long)next,
                         path);
                return CLOTH_ERROR_OUT_OF_MEMORY;
            }
            if (used) memcpy(grown, buffer, used);
            else grown[used++] = (unsigned char)first;
            cloth__free(allocator, buffer);
            buffer = grown;
            capacity = next;
        }
        got = fread(buffer + used, 1, capacity - used, f);
        used += got;
        if (got == 0 || used < capacity) {
            if (ferror(f)) {
                cloth__free(allocator, buffer);
                fclose(f);
                snprintf(error->message, sizeof error->message, "cannot read '%.120s'", path);
                return CLOTH_ERROR_FILE_READ;
            }
            if (feof(f)) break;
        }
    }
    fclose(f);
    *data = buffer;
    *size = used;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_mesh_read_file(cloth_mesh *mesh, const char *path, cloth_file_format format, cloth_io_error *error,
                                            const cloth_allocator *allocator)
{
    cloth_io_error local;
    cloth_allocator a = cloth__allocator_or_default(allocator);
    unsigned char *data = NULL;
    size_t size = 0;
    cloth_result r;
    CLOTH_ASSERT(mesh != NULL && path != NULL);
    if (!error) error = &local;
    memset(mesh, 0, sizeof *mesh);
    memset(error, 0, sizeof *error);
    r = cloth__read_whole_file(path, &a, &data, &size, error);
    if (r != CLOTH_SUCCESS) return r;
    r = cloth__read_format(mesh, data, size, format, error, &a, path);
    cloth__free(&a, data);
    return r;
}

CLOTH_API cloth_result cloth_mesh_write_file(const cloth_mesh *mesh, const char *path, cloth_file_format format)
{
    unsigned char buffer[16384];
    cloth__sink s;
    cloth_result r;
    FILE *f;
    CLOTH_ASSERT(mesh != NULL && path != NULL);
    if (format == CLOTH_FORMAT_AUTO) format = cloth__format_of_path(path, 1);
    if (format == CLOTH_FORMAT_AUTO) return CLOTH_ERROR_INVALID_ARGUMENT;
    if ((r = cloth__write_check(mesh)) != CLOTH_SUCCESS) return r;
    f = fopen(path, "wb");
    if (!f) return CLOTH_ERROR_FILE_OPEN;
    memset(&s, 0, sizeof s);
    s.data = buffer;
    s.capacity = sizeof buffer;
    s.file = f;
    r = cloth__write_sink(&s, mesh, format);
    if (r == CLOTH_SUCCESS && s.size && fwrite(s.data, 1, s.size, f) != s.size) r = CLOTH_ERROR_FILE_WRITE;
    if (fclose(f) != 0 && r == CLOTH_SUCCESS) r = CLOTH_ERROR_FILE_WRITE;
    return r;
}
#endif /* CLOTH_NO_STDIO */

/* ------------------------------------------------------------------------------------- */
/* material                                                                              */
/* ------------------------------------------------------------------------------------- */

/* The factor of the bending frequency estimate omega^2 ~ factor * B / (rho L^4) (see
   cloth_material_stable_time_step), and 12 sqrt(3), the bound on the rate of relative
   damping per c / (rho L^2). */
#define CLOTH__BENDING_FREQUENCY_FACTOR 64.0
#define CLOTH__RELATIVE_DAMPING_FACTOR 20.784609690826528

static int cloth__finite_d(double v) { return v == v && v - v == 0; }

/* The membrane part of a material's checks. */
static cloth_result cloth__membrane_check(double c11, double c12, double c22, double c33)
{
    if (!cloth__finite_d(c11) || !cloth__finite_d(c12) || !cloth__finite_d(c22) || !cloth__finite_d(c33))
        return CLOTH_ERROR_NOT_FINITE;
    if (!(c11 > 0) || !(c22 > 0) || !(c33 > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!(c11 * c22 - c12 * c12 > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_material_validate(const cloth_material *material)
{
    const cloth_material *m = material;
    CLOTH_ASSERT(material);
    if (!cloth__is_finite(m->areal_density) || !cloth__is_finite(m->stretch_warp) || !cloth__is_finite(m->stretch_weft) ||
        !cloth__is_finite(m->stretch_coupling) || !cloth__is_finite(m->shear) || !cloth__is_finite(m->bend_warp) ||
        !cloth__is_finite(m->bend_weft) || !cloth__is_finite(m->damping_stiffness) ||
        !cloth__is_finite(m->damping_relative))
        return CLOTH_ERROR_NOT_FINITE;
    if (!(m->areal_density > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!(m->bend_warp >= 0) || !(m->bend_weft >= 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!(m->damping_stiffness >= 0) || !(m->damping_relative >= 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    return cloth__membrane_check((double)m->stretch_warp, (double)m->stretch_coupling, (double)m->stretch_weft,
                                 (double)m->shear);
}

/* ---- membrane conversions ---------------------------------------------------------- */

/* Write C11, C12, C22, C33 into material if they make a valid membrane. */
static cloth_result cloth__set_membrane(cloth_material *material, double c11, double c12, double c22, double c33)
{
    cloth_result r = cloth__membrane_check(c11, c12, c22, c33);
    if (r != CLOTH_SUCCESS) return r;
    material->stretch_warp = (cloth_real)c11;
    material->stretch_coupling = (cloth_real)c12;
    material->stretch_weft = (cloth_real)c22;
    material->shear = (cloth_real)c33;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_material_set_engineering(cloth_material *material,
                                                      const cloth_membrane_engineering *constants)
{
    double y1, y2, nu12, g, nu21, delta;
    CLOTH_ASSERT(material && constants);
    y1 = (double)constants->tensile_warp;
    y2 = (double)constants->tensile_weft;
    nu12 = (double)constants->poisson_warp_weft;
    g = (double)constants->shear;
    if (!cloth__finite_d(y1) || !cloth__finite_d(y2) || !cloth__finite_d(nu12) || !cloth__finite_d(g))
        return CLOTH_ERROR_NOT_FINITE;
    if (!(y1 > 0) || !(y2 > 0) || !(g > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    nu21 = nu12 * y2 / y1;
    delta = 1.0 - nu12 * nu21;
    if (!(delta > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    return cloth__set_membrane(material, y1 / delta, nu12 * y2 / delta, y2 / delta, g);
}

CLOTH_API cloth_result cloth_material_engineering(const cloth_material *material, cloth_membrane_engineering *constants)
{
    double c11, c12, c22, c33;
    cloth_result r;
    CLOTH_ASSERT(material && constants);
    c11 = (double)material->stretch_warp;
    c12 = (double)material->stretch_coupling;
    c22 = (double)material->stretch_weft;
    c33 = (double)material->shear;
    r = cloth__membrane_check(c11, c12, c22, c33);
    if (r != CLOTH_SUCCESS) return r;
    constants->tensile_warp = (cloth_real)(c11 - c12 * c12 / c22);
    constants->tensile_weft = (cloth_real)(c22 - c12 * c12 / c11);
    constants->poisson_warp_weft = (cloth_real)(c12 / c22);
    constants->shear = (cloth_real)c33;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_material_set_isotropic(cloth_material *material, cloth_real tensile, cloth_real poisson)
{
    double y = (double)tensile, nu = (double)poisson, c11;
    CLOTH_ASSERT(material);
    if (!cloth__finite_d(y) || !cloth__finite_d(nu)) return CLOTH_ERROR_NOT_FINITE;
    if (!(y > 0) || !(nu > -1.0 && nu < 1.0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    c11 = y / (1.0 - nu * nu);
    return cloth__set_membrane(material, c11, nu * c11, c11, y / (2.0 * (1.0 + nu)));
}

CLOTH_API cloth_result cloth_material_set_lame(cloth_material *material, cloth_real lame_lambda, cloth_real lame_mu)
{
    double lambda = (double)lame_lambda, mu = (double)lame_mu;
    CLOTH_ASSERT(material);
    if (!cloth__finite_d(lambda) || !cloth__finite_d(mu)) return CLOTH_ERROR_NOT_FINITE;
    if (!(mu > 0) || !(lambda + mu > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    return cloth__set_membrane(material, lambda + 2.0 * mu, lambda, lambda + 2.0 * mu, mu);
}

/* ---- fitted and measured materials ------------------------------------------------- */

/* A material with no stiffness set: density given, everything else zero. */
static cloth_material cloth__material_zero(double areal_density)
{
    cloth_material m;
    memset(&m, 0, sizeof m);
    m.areal_density = (cloth_real)areal_density;
    return m;
}

/* Validate a finished material and copy it out. */
static cloth_result cloth__material_finish(const cloth_material *m, cloth_material *out)
{
    cloth_result r = cloth_material_validate(m);
    if (r == CLOTH_SUCCESS) *out = *m;
    return r;
}

CLOTH_API cloth_result cloth_material_from_fem_fit(cloth_real lambda0, cloth_real lambda1, cloth_real lambda2,
                                                   cloth_real areal_density, cloth_material *material)
{
    cloth_material m = cloth__material_zero((double)areal_density);
    cloth_result r;
    CLOTH_ASSERT(material);
    if (!cloth__is_finite(lambda0)) return CLOTH_ERROR_NOT_FINITE;
    r = cloth_material_set_lame(&m, lambda1, lambda2);
    if (r != CLOTH_SUCCESS) return r;
    m.bend_warp = lambda0;
    m.bend_weft = lambda0;
    return cloth__material_finish(&m, material);
}

CLOTH_API cloth_result cloth_material_from_arcsim(cloth_real density, const cloth_real *stretching,
                                                  cloth_real bending_u_edges, cloth_real bending_v_edges,
                                                  cloth_material *material)
{
    cloth_material m = cloth__material_zero((double)density);
    double k[4];
    int i;
    CLOTH_ASSERT(stretching && material);
    for (i = 0; i < 4; ++i) {
        k[i] = (double)stretching[i];
        if (!cloth__finite_d(k[i])) return CLOTH_ERROR_NOT_FINITE;
        if (k[i] < 0) k[i] = 0; /* ARCSim clamps negative samples */
    }
    m.stretch_warp = (cloth_real)(2.0 * k[0]);
    m.stretch_coupling = (cloth_real)(2.0 * k[1]);
    m.stretch_weft = (cloth_real)(2.0 * k[2]);
    m.shear = (cloth_real)k[3];
    /* A hinge edge along u folds the sheet about u: curvature along v, the weft. */
    m.bend_weft = (cloth_real)(0.25 * (double)bending_u_edges);
    m.bend_warp = (cloth_real)(0.25 * (double)bending_v_edges);
    return cloth__material_finish(&m, material);
}

/* ---- Kawabata KES-F units ------------------------------------------------------------ */

/* gf/cm in N/m: 9.80665e-3 N / 1e-2 m. */
#define CLOTH__GF_PER_CM 0.980665

CLOTH_API cloth_real cloth_kes_bending_to_si(cloth_real gf_cm2_per_cm)
{ return (cloth_real)((double)gf_cm2_per_cm * (CLOTH_GRAM_FORCE * 1e-4 / 1e-2)); }
CLOTH_API cloth_real cloth_kes_bending_from_si(cloth_real newton_metre)
{ return (cloth_real)((double)newton_metre / (CLOTH_GRAM_FORCE * 1e-4 / 1e-2)); }
CLOTH_API cloth_real cloth_kes_shear_to_si(cloth_real gf_per_cm_degree)
{ return (cloth_real)((double)gf_per_cm_degree * CLOTH__GF_PER_CM * (180.0 / 3.14159265358979323846)); }
CLOTH_API cloth_real cloth_kes_shear_from_si(cloth_real newton_per_metre)
{ return (cloth_real)((double)newton_per_metre / (CLOTH__GF_PER_CM * (180.0 / 3.14159265358979323846))); }
CLOTH_API cloth_real cloth_kes_mass_to_si(cloth_real mg_per_cm2) { return (cloth_real)((double)mg_per_cm2 * (1e-6 / 1e-4)); }
CLOTH_API cloth_real cloth_kes_mass_from_si(cloth_real kg_per_m2) { return (cloth_real)((double)kg_per_m2 / (1e-6 / 1e-4)); }
CLOTH_API cloth_real cloth_kes_load_to_si(cloth_real gf_per_cm) { return (cloth_real)((double)gf_per_cm * CLOTH__GF_PER_CM); }
CLOTH_API cloth_real cloth_kes_tensile_energy_to_si(cloth_real gf_cm_per_cm2)
{ return (cloth_real)((double)gf_cm_per_cm2 * (CLOTH_GRAM_FORCE * 1e-2 / 1e-4)); }

CLOTH_API cloth_result cloth_kes_tensile_stiffness(cloth_real extension_percent, cloth_real linearity,
                                                   cloth_real max_load_gf_per_cm, cloth_real *stiffness)
{
    double em = (double)extension_percent / 100.0, lt = (double)linearity, fm = (double)max_load_gf_per_cm;
    CLOTH_ASSERT(stiffness);
    if (!cloth__finite_d(em) || !cloth__finite_d(lt) || !cloth__finite_d(fm)) return CLOTH_ERROR_NOT_FINITE;
    if (!(em > 0) || !(lt > 0) || !(fm > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    *stiffness = (cloth_real)(lt * fm * CLOTH__GF_PER_CM / em);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_kes_tensile_stiffness_from_energy(cloth_real tensile_energy, cloth_real extension_percent,
                                                               cloth_real *stiffness)
{
    double wt = (double)tensile_energy, em = (double)extension_percent / 100.0;
    CLOTH_ASSERT(stiffness);
    if (!cloth__finite_d(wt) || !cloth__finite_d(em)) return CLOTH_ERROR_NOT_FINITE;
    if (!(wt > 0) || !(em > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    *stiffness = (cloth_real)(2.0 * wt * CLOTH__GF_PER_CM / (em * em));
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_material_from_kes(const cloth_kes_measurement *kes, cloth_real poisson_warp_weft,
                                               cloth_material *material)
{
    cloth_material m;
    cloth_membrane_engineering e;
    cloth_result r;
    CLOTH_ASSERT(kes && material);
    if (!cloth__is_finite(kes->mass) || !cloth__is_finite(kes->shear_rigidity) || !cloth__is_finite(kes->bending_warp) ||
        !cloth__is_finite(kes->bending_weft))
        return CLOTH_ERROR_NOT_FINITE;
    m = cloth__material_zero((double)cloth_kes_mass_to_si(kes->mass));
    r = cloth_kes_tensile_stiffness(kes->extension_warp, kes->linearity_warp, kes->max_load, &e.tensile_warp);
    if (r != CLOTH_SUCCESS) return r;
    r = cloth_kes_tensile_stiffness(kes->extension_weft, kes->linearity_weft, kes->max_load, &e.tensile_weft);
    if (r != CLOTH_SUCCESS) return r;
    e.poisson_warp_weft = poisson_warp_weft;
    e.shear = cloth_kes_shear_to_si(kes->shear_rigidity);
    r = cloth_material_set_engineering(&m, &e);
    if (r != CLOTH_SUCCESS) return r;
    m.bend_warp = cloth_kes_bending_to_si(kes->bending_warp);
    m.bend_weft = cloth_kes_bending_to_si(kes->bending_weft);
    return cloth__material_finish(&m, material);
}

/* ---- presets ----------------------------------------------------------------------- */

typedef enum cloth__preset_kind { CLOTH__PRESET_KES = 0, CLOTH__PRESET_FEM_FIT = 1, CLOTH__PRESET_ARCSIM = 2 } cloth__preset_kind;

/* A preset is the recipe that makes it: the source's own numbers and the mapping to apply.
   KES:     p = W, EMT1, EMT2, LT1, LT2, Fm, G, B1, B2, and nu12 in p[9]
   FEM_FIT: p = lambda0, lambda1, lambda2, areal density
   ARCSIM:  p = density, k0, k1, k2, k3 (stretching row 0), ke of u edges (bending row 0,
            sample 0), ke of v edges (bending row 2, sample 0) */
typedef struct cloth__material_preset {
    const char *name;
    const char *source;
    cloth__preset_kind kind;
    double p[10];
} cloth__material_preset;

static const cloth__material_preset cloth__material_presets[] = {
    { "cotton", "mid-weight plain-woven cotton from representative KES-F values of the class (W 15 mg/cm^2, EMT 4/6 %, "
      "LT 0.65, G 1.0 gf/cm/deg, B 0.10/0.08 gf cm^2/cm) and an assumed Poisson ratio 0.3; the default material",
      CLOTH__PRESET_KES, { 15.0, 4.0, 6.0, 0.65, 0.65, 500.0, 1.0, 0.10, 0.08, 0.3 } },
    { "silk", "seed 002 Table 2 (1.0e-5, 50, 50) as bending, Lame lambda, Lame mu; density 0.07 kg/m^2 assumed (16 momme)",
      CLOTH__PRESET_FEM_FIT, { 1.0e-5, 50.0, 50.0, 0.07 } },
    { "fleece", "seed 002 Table 2 (6.9376e-6, 19.3822, 69.654) as bending, Lame lambda, Lame mu; density 0.25 kg/m^2 "
      "assumed (mid-weight polar fleece)", CLOTH__PRESET_FEM_FIT, { 6.9376e-6, 19.3822, 69.654, 0.25 } },
    { "denim", "seed 002 Table 2 (7.7720e-6, 20.2884, 32.6492) as bending, Lame lambda, Lame mu; density 0.324 kg/m^2 "
      "(the measured 11 oz denim)", CLOTH__PRESET_FEM_FIT, { 7.7720e-6, 20.2884, 32.6492, 0.324 } },
    { "linen", "seed 002 Table 2 (8.4776e-6, 20.1119, 50.830) as bending, Lame lambda, Lame mu; density 0.18 kg/m^2 "
      "assumed (dress linen)", CLOTH__PRESET_FEM_FIT, { 8.4776e-6, 20.1119, 50.830, 0.18 } },
    { "denim_11oz", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/11oz-black-denim.json (jeans, 99% cotton "
      "1% spandex)", CLOTH__PRESET_ARCSIM,
      { 0.324, 205.352005, 10.234077, 1013.88629, 53.387184, 64.196457e-6, 96.951576e-6 } },
    { "ponte_roma", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/camel-ponte-roma.json (jacket, 60% polyester "
      "40% rayon)", CLOTH__PRESET_ARCSIM,
      { 0.284, 31.146198, -12.802702, 44.028667, 31.896357, 36.348366e-6, 37.157593e-6 } },
    { "rib_knit", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/ivory-rib-knit.json (underwear, 95% cotton "
      "5% spandex)", CLOTH__PRESET_ARCSIM,
      { 0.276, 42.871021, -0.234556, 65.166023, 83.175644, 46.237591e-6, 32.243889e-6 } },
    { "blanket", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/pink-ribbon-brown.json (blanket, 100% "
      "polyester)", CLOTH__PRESET_ARCSIM,
      { 0.228, 151.503906, 106.028160, 244.830673, 30.250183, 117.070122e-6, 59.774277e-6 } },
    { "sweater", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/navy-sparkle-sweat.json (sweater, 96% "
      "polyester 4% spandex)", CLOTH__PRESET_ARCSIM,
      { 0.224, 12.486332, -19.875324, 3.272434, 17.616289, 59.469658e-6, 45.625023e-6 } },
    { "pants", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/royal-target.json (pants, 65% cotton 35% "
      "polyester)", CLOTH__PRESET_ARCSIM,
      { 0.220, 2016.55456, 9.170511, 2034.97644, 104.759674, 125.409805e-6, 125.409805e-6 } },
    { "swimsuit", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/white-swim-solid.json (swimsuit, 87% nylon "
      "13% spandex)", CLOTH__PRESET_ARCSIM,
      { 0.204, 47.971176, 6.834521, 104.615456, 60.773663, 60.237942e-6, 51.018833e-6 } },
    { "interlock", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/gray-interlock.json (t-shirt, 60% cotton "
      "40% polyester)", CLOTH__PRESET_ARCSIM,
      { 0.187, 16.593832, -14.695990, 34.477123, 36.860302, 23.191698e-6, 14.267624e-6 } },
    { "tablecloth", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/white-dots-on-blk.json (tablecloth, 100% "
      "polyester)", CLOTH__PRESET_ARCSIM,
      { 0.128, 2002.08618, 0.345588, 2027.48559, 19.189022, 51.713814e-6, 31.282822e-6 } },
    { "jet_set", "Wang, O'Brien, Ramamoorthi 2011 via ARCSim materials/tango-red-jet-set.json (jacket, 100% "
      "polyester)", CLOTH__PRESET_ARCSIM,
      { 0.113, 43.067627, 54.373299, 171.424835, 14.314700, 14.293814e-6, 20.345654e-6 } }
};

#define CLOTH__MATERIAL_PRESET_COUNT ((int32_t)(sizeof cloth__material_presets / sizeof cloth__material_presets[0]))

CLOTH_API int32_t cloth_material_preset_count(void) { return CLOTH__MATERIAL_PRESET_COUNT; }

CLOTH_API const char *cloth_material_preset_name(int32_t i)
{
    return i >= 0 && i < CLOTH__MATERIAL_PRESET_COUNT ? cloth__material_presets[i].name : NULL;
}

CLOTH_API const char *cloth_material_preset_source(int32_t i)
{
    return i >= 0 && i < CLOTH__MATERIAL_PRESET_COUNT ? cloth__material_presets[i].source : NULL;
}

CLOTH_API cloth_result cloth_material_preset_at(int32_t i, cloth_material *material)
{
    const cloth__material_preset *p;
    CLOTH_ASSERT(material);
    if (i < 0 || i >= CLOTH__MATERIAL_PRESET_COUNT) return CLOTH_ERROR_INVALID_ARGUMENT;
    p = &cloth__material_presets[i];
    switch (p->kind) {
    case CLOTH__PRESET_KES: {
        cloth_kes_measurement k;
        k.mass = (cloth_real)p->p[0];
        k.extension_warp = (cloth_real)p->p[1];
        k.extension_weft = (cloth_real)p->p[2];
        k.linearity_warp = (cloth_real)p->p[3];
        k.linearity_weft = (cloth_real)p->p[4];
        k.max_load = (cloth_real)p->p[5];
        k.shear_rigidity = (cloth_real)p->p[6];
        k.bending_warp = (cloth_real)p->p[7];
        k.bending_weft = (cloth_real)p->p[8];
        return cloth_material_from_kes(&k, (cloth_real)p->p[9], material);
    }
    case CLOTH__PRESET_FEM_FIT:
        return cloth_material_from_fem_fit((cloth_real)p->p[0], (cloth_real)p->p[1], (cloth_real)p->p[2],
                                           (cloth_real)p->p[3], material);
    case CLOTH__PRESET_ARCSIM: {
        cloth_real k[4];
        k[0] = (cloth_real)p->p[1];
        k[1] = (cloth_real)p->p[2];
        k[2] = (cloth_real)p->p[3];
        k[3] = (cloth_real)p->p[4];
        return cloth_material_from_arcsim((cloth_real)p->p[0], k, (cloth_real)p->p[5], (cloth_real)p->p[6], material);
    }
    }
    return CLOTH_ERROR_INVALID_ARGUMENT;
}

static int cloth__preset_name_lower(int c) { return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c; }

CLOTH_API cloth_result cloth_material_preset(const char *name, cloth_material *material)
{
    int32_t i;
    CLOTH_ASSERT(material);
    if (!name) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < CLOTH__MATERIAL_PRESET_COUNT; ++i) {
        const char *a = cloth__material_presets[i].name, *b = name;
        while (*a && cloth__preset_name_lower((unsigned char)*b) == *a) { ++a; ++b; }
        if (!*a && !*b) return cloth_material_preset_at(i, material);
    }
    return CLOTH_ERROR_INVALID_ARGUMENT;
}

CLOTH_API cloth_material cloth_default_material(void)
{
    cloth_material m;
    cloth_result r = cloth_material_preset_at(0, &m);
    CLOTH_ASSERT(r == CLOTH_SUCCESS);
    (void)r;
    return m;
}

/* ---- Peirce's cantilever ----------------------------------------------------------- */

CLOTH_API cloth_result cloth_bending_length(cloth_real bending, cloth_real areal_density, cloth_real gravity,
                                            cloth_real *length)
{
    double b = (double)bending, rho = (double)areal_density, g = (double)gravity;
    CLOTH_ASSERT(length);
    if (!cloth__finite_d(b) || !cloth__finite_d(rho) || !cloth__finite_d(g)) return CLOTH_ERROR_NOT_FINITE;
    if (!(b >= 0) || !(rho > 0) || !(g > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    *length = (cloth_real)cbrt(b / (rho * g));
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_cantilever_rigidity(cloth_real overhang, cloth_real areal_density, cloth_real gravity,
                                                 cloth_real *bending)
{
    double l = (double)overhang, rho = (double)areal_density, g = (double)gravity, c;
    CLOTH_ASSERT(bending);
    if (!cloth__finite_d(l) || !cloth__finite_d(rho) || !cloth__finite_d(g)) return CLOTH_ERROR_NOT_FINITE;
    if (!(l > 0) || !(rho > 0) || !(g > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    c = 0.5 * l;
    *bending = (cloth_real)(rho * g * c * c * c);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_cantilever_overhang(cloth_real bending, cloth_real areal_density, cloth_real gravity,
                                                 cloth_real *overhang)
{
    cloth_real c;
    cloth_result r;
    CLOTH_ASSERT(overhang);
    r = cloth_bending_length(bending, areal_density, gravity, &c);
    if (r != CLOTH_SUCCESS) return r;
    *overhang = (cloth_real)(2.0 * (double)c);
    return CLOTH_SUCCESS;
}

/* ---- stable time step ---------------------------------------------------------------- */

CLOTH_API cloth_result cloth_explicit_time_step_limit(cloth_real omega_max, cloth_real damping_rate_max,
                                                      cloth_real *time_step)
{
    double w = (double)omega_max, k = (double)damping_rate_max;
    CLOTH_ASSERT(time_step);
    if (!cloth__finite_d(w) || !cloth__finite_d(k)) return CLOTH_ERROR_NOT_FINITE;
    if (!(w >= 0) || !(k >= 0) || !(w > 0 || k > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    /* the positive root of h^2 w^2 + 2 h k - 4 = 0, written without cancellation */
    *time_step = (cloth_real)(4.0 / (k + sqrt(k * k + 4.0 * w * w)));
    return CLOTH_SUCCESS;
}

/* Shape function gradient moments of a rest triangle: a = sum gx^2, b = sum gy^2,
   c = sum gx gy, and its area; 0 when degenerate or not finite. */
static int cloth__triangle_moments(const cloth_real *uv0, const cloth_real *uv1, const cloth_real *uv2, double *a,
                                   double *b, double *c, double *area)
{
    const cloth_real *p[3];
    double twice_area, s;
    int i;
    p[0] = uv0; p[1] = uv1; p[2] = uv2;
    for (i = 0; i < 3; ++i)
        if (!cloth__is_finite(p[i][0]) || !cloth__is_finite(p[i][1])) return 0;
    twice_area = ((double)uv1[0] - (double)uv0[0]) * ((double)uv2[1] - (double)uv0[1]) -
                 ((double)uv2[0] - (double)uv0[0]) * ((double)uv1[1] - (double)uv0[1]);
    if (!(twice_area != 0) || !cloth__finite_d(twice_area)) return 0;
    *a = *b = *c = 0;
    for (i = 0; i < 3; ++i) {
        /* grad N_i = perp(opposite edge) / (2 area): the edge from p[i+1] to p[i+2] rotated */
        const cloth_real *q = p[(i + 1) % 3], *r = p[(i + 2) % 3];
        double gx = ((double)q[1] - (double)r[1]) / twice_area;
        double gy = ((double)r[0] - (double)q[0]) / twice_area;
        *a += gx * gx;
        *b += gy * gy;
        *c += gx * gy;
    }
    *area = 0.5 * fabs(twice_area);
    s = *a + *b;
    /* a degenerate (needle) triangle at the limit of double precision */
    if (!cloth__finite_d(s) || !(s > 0)) return 0;
    return 1;
}

/* The largest eigenvalue of a 2x2 symmetric [a c; c b]. */
static double cloth__sym2_max_eigenvalue(double a, double b, double c)
{
    double h = 0.5 * (a - b);
    return 0.5 * (a + b) + sqrt(h * h + c * c);
}

CLOTH_API cloth_real cloth_triangle_stability_length(const cloth_real *uv0, const cloth_real *uv1, const cloth_real *uv2)
{
    double a, b, c, area;
    CLOTH_ASSERT(uv0 && uv1 && uv2);
    if (!cloth__triangle_moments(uv0, uv1, uv2, &a, &b, &c, &area)) return 0;
    return (cloth_real)sqrt(2.0 / cloth__sym2_max_eigenvalue(a, b, c));
}

/* The largest eigenvalue of a symmetric 3x3 matrix m (row-major) by the trigonometric
   solution of its characteristic cubic (all roots real). */
static double cloth__sym3_max_eigenvalue(const double *m)
{
    double q = (m[0] + m[4] + m[8]) / 3.0;
    double p1 = m[1] * m[1] + m[2] * m[2] + m[5] * m[5];
    double d0 = m[0] - q, d1 = m[4] - q, d2 = m[8] - q;
    double p2 = d0 * d0 + d1 * d1 + d2 * d2 + 2.0 * p1;
    double p, r, phi, det;
    if (!(p2 > 0)) return q;
    p = sqrt(p2 / 6.0);
    /* det((m - q I) / p) / 2 */
    det = d0 * (d1 * d2 - m[5] * m[5]) - m[1] * (m[1] * d2 - m[5] * m[2]) + m[2] * (m[1] * m[5] - d1 * m[2]);
    r = det / (2.0 * p * p * p);
    if (r <= -1.0) phi = 3.14159265358979323846 / 3.0;
    else if (r >= 1.0) phi = 0;
    else phi = acos(r) / 3.0;
    return q + 2.0 * p * cos(phi);
}

/* The largest eigenvalue of the membrane constitutive matrix D. */
static double cloth__membrane_max_eigenvalue(const cloth_material *m)
{
    double d = cloth__sym2_max_eigenvalue((double)m->stretch_warp, (double)m->stretch_weft, (double)m->stretch_coupling);
    return d > (double)m->shear ? d : (double)m->shear;
}

/* The step from the membrane frequency bound w2m (rad^2/s^2), the stability length and area
   lower bound used for bending and relative damping. */
static cloth_result cloth__material_step(const cloth_material *m, double w2_membrane, double length,
                                         double relative_rate_per_c, cloth_real *time_step)
{
    double rho = (double)m->areal_density;
    double bend = (double)m->bend_warp > (double)m->bend_weft ? (double)m->bend_warp : (double)m->bend_weft;
    double l2 = length * length;
    double w2 = w2_membrane + CLOTH__BENDING_FREQUENCY_FACTOR * bend / (rho * l2 * l2);
    double kappa = (double)m->damping_stiffness * w2 + relative_rate_per_c * (double)m->damping_relative;
    if (!cloth__finite_d(w2) || !cloth__finite_d(kappa)) return CLOTH_ERROR_NOT_FINITE;
    return cloth_explicit_time_step_limit((cloth_real)sqrt(w2), (cloth_real)kappa, time_step);
}

CLOTH_API cloth_result cloth_material_stable_time_step(const cloth_material *material, cloth_real length,
                                                       cloth_real *time_step)
{
    double l = (double)length, rho;
    cloth_result r;
    CLOTH_ASSERT(material && time_step);
    r = cloth_material_validate(material);
    if (r != CLOTH_SUCCESS) return r;
    if (!cloth__finite_d(l)) return CLOTH_ERROR_NOT_FINITE;
    if (!(l > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    rho = (double)material->areal_density;
    return cloth__material_step(material, 12.0 * cloth__membrane_max_eigenvalue(material) / (rho * l * l), l,
                                CLOTH__RELATIVE_DAMPING_FACTOR / (rho * l * l), time_step);
}

CLOTH_API cloth_result cloth_material_triangle_time_step(const cloth_material *material, const cloth_real *uv0,
                                                         const cloth_real *uv1, const cloth_real *uv2,
                                                         cloth_real *time_step)
{
    double a, b, c, area, rho, r11, r21, r22, r33, s[9], t[9], mm[9], length;
    int i, j, k;
    cloth_result r;
    CLOTH_ASSERT(material && uv0 && uv1 && uv2 && time_step);
    r = cloth_material_validate(material);
    if (r != CLOTH_SUCCESS) return r;
    if (!cloth__is_finite(uv0[0]) || !cloth__is_finite(uv0[1]) || !cloth__is_finite(uv1[0]) ||
        !cloth__is_finite(uv1[1]) || !cloth__is_finite(uv2[0]) || !cloth__is_finite(uv2[1]))
        return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__triangle_moments(uv0, uv1, uv2, &a, &b, &c, &area)) return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    rho = (double)material->areal_density;
    /* B B^T over the strains (E11, E22, gamma) and D = R R^T (Cholesky, D is positive definite);
       lambda_max(B^T D B) = lambda_max(D B B^T) = lambda_max(R^T (B B^T) R). */
    s[0] = a; s[1] = 0; s[2] = c;
    s[3] = 0; s[4] = b; s[5] = c;
    s[6] = c; s[7] = c; s[8] = a + b;
    r11 = sqrt((double)material->stretch_warp);
    r21 = (double)material->stretch_coupling / r11;
    r22 = sqrt((double)material->stretch_weft - r21 * r21);
    r33 = sqrt((double)material->shear);
    {
        /* R = [r11 0 0; r21 r22 0; 0 0 r33]; t = (B B^T) R, mm = R^T t */
        double rm[9];
        rm[0] = r11; rm[1] = 0; rm[2] = 0;
        rm[3] = r21; rm[4] = r22; rm[5] = 0;
        rm[6] = 0; rm[7] = 0; rm[8] = r33;
        for (i = 0; i < 3; ++i)
            for (j = 0; j < 3; ++j) {
                double sum = 0;
                for (k = 0; k < 3; ++k) sum += s[3 * i + k] * rm[3 * k + j];
                t[3 * i + j] = sum;
            }
        for (i = 0; i < 3; ++i)
            for (j = 0; j < 3; ++j) {
                double sum = 0;
                for (k = 0; k < 3; ++k) sum += rm[3 * k + i] * t[3 * k + j];
                mm[3 * i + j] = sum;
            }
    }
    length = sqrt(2.0 / cloth__sym2_max_eigenvalue(a, b, c));
    return cloth__material_step(material, 3.0 * cloth__sym3_max_eigenvalue(mm) / rho, length, 9.0 / (rho * area),
                                time_step);
}

/* ------------------------------------------------------------------------------------- */
/* forces                                                                                */
/* ------------------------------------------------------------------------------------- */

/* The relative size below which a length or an area counts as zero in the kernels. */
#define CLOTH__FORCES_EPSILON (sizeof(cloth_real) < sizeof(double) ? (cloth_real)FLT_EPSILON : (cloth_real)DBL_EPSILON)

static void cloth__forces_zero(cloth_real *a, int n)
{
    int i;
    if (a)
        for (i = 0; i < n; ++i) a[i] = 0;
}

/* Add s * block (3x3) to the (a, b) block of an n-vertex Hessian. */
static void cloth__forces_add_block(cloth_real *hessian, int n, int a, int b, cloth_real s, const cloth_real *block)
{
    int r, c;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) hessian[(3 * a + r) * 3 * n + 3 * b + c] += s * block[3 * r + c];
}

/* Make a dense square matrix exactly symmetric: (H + H^T) / 2. */
static void cloth__forces_symmetrize(cloth_real *h, int dim)
{
    int r, c;
    for (r = 0; r < dim; ++r)
        for (c = r + 1; c < dim; ++c) {
            cloth_real m = (h[r * dim + c] + h[c * dim + r]) / 2;
            h[r * dim + c] = m;
            h[c * dim + r] = m;
        }
}

/* ---- springs ---------------------------------------------------------------------- */

CLOTH_API cloth_real cloth_spring_energy(const cloth_real *xi, const cloth_real *xj, cloth_real stiffness,
                                         cloth_real rest_length, cloth_real *gradient, cloth_real *hessian,
                                         cloth_hessian_form form)
{
    cloth_real d[3], l, stretch, transverse, k_block[9];
    int r, c;
    cloth__v3_sub(xi, xj, d);
    l = cloth__v3_norm(d);
    if (rest_length == 0) {
        /* A seam: E = k/2 |d|^2, smooth everywhere. */
        if (gradient) {
            cloth__v3_scale(d, stiffness, gradient);
            cloth__v3_scale(d, -stiffness, gradient + 3);
        }
        if (hessian) {
            for (r = 0; r < 9; ++r) k_block[r] = 0;
            k_block[0] = k_block[4] = k_block[8] = stiffness;
        }
    } else if (l == 0) {
        cloth__forces_zero(gradient, 6);
        cloth__forces_zero(hessian, 36);
        return stiffness / 2 * rest_length * rest_length;
    } else {
        stretch = l - rest_length;
        cloth__v3_scale(d, 1 / l, d);
        if (gradient) {
            cloth__v3_scale(d, stiffness * stretch, gradient);
            cloth__v3_scale(d, -stiffness * stretch, gradient + 3);
        }
        if (hessian) {
            transverse = 1 - rest_length / l;
            if (form != CLOTH_HESSIAN_EXACT && transverse < 0) transverse = 0;
            for (r = 0; r < 3; ++r)
                for (c = r; c < 3; ++c) {
                    k_block[3 * r + c] = stiffness * ((1 - transverse) * d[r] * d[c] + (r == c ? transverse : 0));
                    k_block[3 * c + r] = k_block[3 * r + c];
                }
        }
    }
    if (hessian) {
        cloth__forces_zero(hessian, 36);
        cloth__forces_add_block(hessian, 2, 0, 0, 1, k_block);
        cloth__forces_add_block(hessian, 2, 1, 1, 1, k_block);
        cloth__forces_add_block(hessian, 2, 0, 1, -1, k_block);
        cloth__forces_add_block(hessian, 2, 1, 0, -1, k_block);
    }
    return stiffness / 2 * (l - rest_length) * (l - rest_length);
}

CLOTH_API cloth_real cloth_attachment_energy(const cloth_real *x, const cloth_real *target, cloth_real stiffness,
                                             cloth_real *gradient, cloth_real *hessian)
{
    cloth_real d[3];
    cloth__v3_sub(x, target, d);
    if (gradient) cloth__v3_scale(d, stiffness, gradient);
    if (hessian) {
        cloth__forces_zero(hessian, 9);
        hessian[0] = hessian[4] = hessian[8] = stiffness;
    }
    return stiffness / 2 * cloth__v3_dot(d, d);
}

CLOTH_API cloth_real cloth_strain_limit_energy(const cloth_real *xi, const cloth_real *xj, cloth_real stiffness,
                                               cloth_real rest_length, cloth_real limit, cloth_real *gradient,
                                               cloth_real *hessian)
{
    cloth_real d[3], engaged = (1 + limit) * rest_length;
    cloth__v3_sub(xi, xj, d);
    if (!(cloth__v3_norm(d) > engaged)) {
        cloth__forces_zero(gradient, 6);
        cloth__forces_zero(hessian, 36);
        return 0;
    }
    return cloth_spring_energy(xi, xj, stiffness, engaged, gradient, hessian, CLOTH_HESSIAN_EXACT);
}

/* Append a spring when there is room to write (pair != NULL), always count it. */
static void cloth__spring_emit(int32_t *pair, int32_t *kind, int64_t *n, int32_t a, int32_t b, int32_t k)
{
    if (pair) {
        pair[2 * *n] = a < b ? a : b;
        pair[2 * *n + 1] = a < b ? b : a;
        if (kind) kind[*n] = k;
    }
    ++*n;
}

static int64_t cloth__grid_spring_count(int64_t nx, int64_t ny, int kinds)
{
    int64_t n = 0;
    if (kinds & CLOTH_SPRING_STRUCTURAL) n += (nx - 1) * ny + nx * (ny - 1);
    if (kinds & CLOTH_SPRING_SHEAR) n += 2 * (nx - 1) * (ny - 1);
    if (kinds & CLOTH_SPRING_BEND) n += (nx > 2 ? (nx - 2) * ny : 0) + (ny > 2 ? nx * (ny - 2) : 0);
    return n;
}

CLOTH_API cloth_result cloth_grid_springs(int32_t nx, int32_t ny, int kinds, int32_t *pair, int32_t *kind,
                                          int32_t capacity, int32_t *count)
{
    int64_t total, n = 0;
    int32_t i, j;
    CLOTH_ASSERT(count);
    *count = 0;
    if (nx < 2 || ny < 2 || kinds < 0 || (kinds & ~(int)CLOTH_SPRING_ALL)) return CLOTH_ERROR_INVALID_ARGUMENT;
    total = cloth__grid_spring_count(nx, ny, kinds);
    if (total > INT32_MAX || (int64_t)nx * ny > INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
    *count = (int32_t)total;
    if (!pair) return CLOTH_SUCCESS;
    if (capacity < total) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (kinds & CLOTH_SPRING_STRUCTURAL)
        for (j = 0; j < ny; ++j)
            for (i = 0; i < nx; ++i) {
                int32_t v = j * nx + i;
                if (i + 1 < nx) cloth__spring_emit(pair, kind, &n, v, v + 1, CLOTH_SPRING_STRUCTURAL);
                if (j + 1 < ny) cloth__spring_emit(pair, kind, &n, v, v + nx, CLOTH_SPRING_STRUCTURAL);
            }
    if (kinds & CLOTH_SPRING_SHEAR)
        for (j = 0; j + 1 < ny; ++j)
            for (i = 0; i + 1 < nx; ++i) {
                int32_t v = j * nx + i;
                cloth__spring_emit(pair, kind, &n, v, v + nx + 1, CLOTH_SPRING_SHEAR);
                cloth__spring_emit(pair, kind, &n, v + 1, v + nx, CLOTH_SPRING_SHEAR);
            }
    if (kinds & CLOTH_SPRING_BEND)
        for (j = 0; j < ny; ++j)
            for (i = 0; i < nx; ++i) {
                int32_t v = j * nx + i;
                if (i + 2 < nx) cloth__spring_emit(pair, kind, &n, v, v + 2, CLOTH_SPRING_BEND);
                if (j + 2 < ny) cloth__spring_emit(pair, kind, &n, v, v + 2 * nx, CLOTH_SPRING_BEND);
            }
    return CLOTH_SUCCESS;
}

static int cloth__topology_bend_ok(const cloth_topology *topology, int32_t e)
{
    int32_t a = topology->edge_opposite[2 * e], b = topology->edge_opposite[2 * e + 1];
    return a >= 0 && b >= 0 && a != b;
}

CLOTH_API cloth_result cloth_topology_springs(const cloth_topology *topology, int kinds, int32_t *pair,
                                              int32_t *kind, int32_t capacity, int32_t *count)
{
    int64_t total = 0, n = 0;
    int32_t e;
    CLOTH_ASSERT(topology && count);
    *count = 0;
    if (kinds < 0 || (kinds & ~(int)CLOTH_SPRING_ALL) || topology->edge_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (kinds & CLOTH_SPRING_STRUCTURAL) total += topology->edge_count;
    if (kinds & CLOTH_SPRING_BEND)
        for (e = 0; e < topology->edge_count; ++e) total += cloth__topology_bend_ok(topology, e);
    if (total > INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
    *count = (int32_t)total;
    if (!pair) return CLOTH_SUCCESS;
    if (capacity < total) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (kinds & CLOTH_SPRING_STRUCTURAL)
        for (e = 0; e < topology->edge_count; ++e)
            cloth__spring_emit(pair, kind, &n, topology->edge_vertex[2 * e], topology->edge_vertex[2 * e + 1],
                               CLOTH_SPRING_STRUCTURAL);
    if (kinds & CLOTH_SPRING_BEND)
        for (e = 0; e < topology->edge_count; ++e)
            if (cloth__topology_bend_ok(topology, e))
                cloth__spring_emit(pair, kind, &n, topology->edge_opposite[2 * e], topology->edge_opposite[2 * e + 1],
                                   CLOTH_SPRING_BEND);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_spring_rest_lengths(const cloth_real *points, int dimension, int32_t point_count,
                                                 const int32_t *pair, int32_t count, cloth_real *rest_length)
{
    int32_t s;
    int k;
    if ((dimension != 2 && dimension != 3) || count < 0 || point_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (count == 0) return CLOTH_SUCCESS;
    CLOTH_ASSERT(points && pair && rest_length);
    for (s = 0; s < 2 * count; ++s)
        if (pair[s] < 0 || pair[s] >= point_count) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    for (s = 0; s < count; ++s) {
        const cloth_real *a = points + (size_t)dimension * (size_t)pair[2 * s];
        const cloth_real *b = points + (size_t)dimension * (size_t)pair[2 * s + 1];
        double sum = 0;
        for (k = 0; k < dimension; ++k) sum += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
        rest_length[s] = (cloth_real)sqrt(sum);
    }
    return CLOTH_SUCCESS;
}

/* ---- FEM membrane ---------------------------------------------------------------- */

/* Twice the signed area of a 2D triangle and whether it passes the quality test used by
   cloth_mesh_validate: 2 area > tolerance * (longest edge)^2. */
static int cloth__pattern_triangle_ok(const cloth_real *a, const cloth_real *b, const cloth_real *c, double *twice_area)
{
    double e1u = (double)b[0] - a[0], e1v = (double)b[1] - a[1];
    double e2u = (double)c[0] - a[0], e2v = (double)c[1] - a[1];
    double e3u = (double)c[0] - b[0], e3v = (double)c[1] - b[1];
    double l1 = e1u * e1u + e1v * e1v, l2 = e2u * e2u + e2v * e2v, l3 = e3u * e3u + e3v * e3v;
    double longest = l1 > l2 ? (l1 > l3 ? l1 : l3) : (l2 > l3 ? l2 : l3);
    *twice_area = e1u * e2v - e1v * e2u;
    return fabs(*twice_area) > CLOTH_MESH_QUALITY_TOLERANCE * longest && longest > 0;
}

static int cloth__all_finite_n(const cloth_real *const *p, int count, int dimension)
{
    int i, k;
    for (i = 0; i < count; ++i)
        for (k = 0; k < dimension; ++k)
            if (!cloth__is_finite(p[i][k])) return 0;
    return 1;
}

CLOTH_API cloth_result cloth_membrane_rest_make(cloth_membrane_rest *rest, const cloth_real *uv0,
                                                const cloth_real *uv1, const cloth_real *uv2)
{
    const cloth_real *p[3];
    double det, inv;
    CLOTH_ASSERT(rest && uv0 && uv1 && uv2);
    memset(rest, 0, sizeof *rest);
    p[0] = uv0; p[1] = uv1; p[2] = uv2;
    if (!cloth__all_finite_n(p, 3, 2)) return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__pattern_triangle_ok(uv0, uv1, uv2, &det)) return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    /* Dm = [[u1 - u0, u2 - u0], [v1 - v0, v2 - v0]], det = det Dm. */
    inv = 1 / det;
    rest->dm_inverse[0] = (cloth_real)(((double)uv2[1] - uv0[1]) * inv);
    rest->dm_inverse[1] = (cloth_real)(-((double)uv2[0] - uv0[0]) * inv);
    rest->dm_inverse[2] = (cloth_real)(-((double)uv1[1] - uv0[1]) * inv);
    rest->dm_inverse[3] = (cloth_real)(((double)uv1[0] - uv0[0]) * inv);
    rest->area = (cloth_real)(fabs(det) / 2);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_membrane_stiffness cloth_membrane_stiffness_isotropic(cloth_real young_modulus, cloth_real thickness,
                                                                      cloth_real poisson_ratio)
{
    cloth_membrane_stiffness s;
    cloth_real yt = young_modulus * thickness;
    s.c11 = s.c22 = yt / (1 - poisson_ratio * poisson_ratio);
    s.c12 = poisson_ratio * s.c11;
    s.c33 = yt / (2 * (1 + poisson_ratio));
    return s;
}

CLOTH_API cloth_membrane_stiffness cloth_membrane_stiffness_orthotropic(cloth_real young_warp, cloth_real young_weft,
                                                                        cloth_real poisson_warp_weft,
                                                                        cloth_real shear_modulus, cloth_real thickness)
{
    cloth_membrane_stiffness s;
    cloth_real nu21 = poisson_warp_weft * young_weft / young_warp;
    cloth_real d = 1 - poisson_warp_weft * nu21;
    s.c11 = young_warp * thickness / d;
    s.c22 = young_weft * thickness / d;
    s.c12 = poisson_warp_weft * young_weft * thickness / d;
    s.c33 = shear_modulus * thickness;
    return s;
}

/* The two columns f0, f1 of F = Ds Dm^-1 and the vertex weights D (3x2, row-major:
   f_p = sum_a D[2a + p] x_a). */
static void cloth__membrane_deformation(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                        const cloth_membrane_rest *rest, cloth_real *f0, cloth_real *f1, cloth_real *d)
{
    cloth_real e1[3], e2[3];
    const cloth_real *m = rest->dm_inverse;
    int k;
    cloth__v3_sub(x1, x0, e1);
    cloth__v3_sub(x2, x0, e2);
    for (k = 0; k < 3; ++k) {
        f0[k] = e1[k] * m[0] + e2[k] * m[2];
        f1[k] = e1[k] * m[1] + e2[k] * m[3];
    }
    d[0] = -(m[0] + m[2]);
    d[1] = -(m[1] + m[3]);
    d[2] = m[0];
    d[3] = m[1];
    d[4] = m[2];
    d[5] = m[3];
}

CLOTH_API void cloth_membrane_strain(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                     const cloth_membrane_rest *rest, cloth_real *strain)
{
    cloth_real f0[3], f1[3], d[6];
    cloth__membrane_deformation(x0, x1, x2, rest, f0, f1, d);
    strain[0] = (cloth__v3_dot(f0, f0) - 1) / 2;
    strain[1] = (cloth__v3_dot(f1, f1) - 1) / 2;
    strain[2] = cloth__v3_dot(f0, f1) / 2;
}

/* The absolute value of a symmetric 2x2 matrix S = [[a, b], [b, c]] (stored a, b, c): its
   eigenvalues replaced by their magnitudes. With eigenvalues lo < 0 < hi and the projectors
   (S - lo I) / (hi - lo) and (hi I - S) / (hi - lo), |S| = ((hi + lo) S - 2 hi lo I) / (hi - lo). */
static void cloth__sym2_absolute(const cloth_real *s, cloth_real *out)
{
    double a = s[0], b = s[1], c = s[2];
    double mid = (a + c) / 2, rad = sqrt((a - c) * (a - c) / 4 + b * b);
    double lo = mid - rad, hi = mid + rad;
    if (lo >= 0) { out[0] = s[0]; out[1] = s[1]; out[2] = s[2]; return; }
    if (hi <= 0) { out[0] = -s[0]; out[1] = -s[1]; out[2] = -s[2]; return; }
    out[0] = (cloth_real)(((hi + lo) * a - 2 * hi * lo) / (hi - lo));
    out[1] = (cloth_real)((hi + lo) * b / (hi - lo));
    out[2] = (cloth_real)(((hi + lo) * c - 2 * hi * lo) / (hi - lo));
}

/* The membrane's energy, and its gradient (9) and Hessian when asked: the Hessian as its six
   blocks (a, b), a <= b, in the order (0,0) (0,1) (0,2) (1,1) (1,2) (2,2), 9 each (row-major),
   block (b, a) being the transpose of (a, b). With the strain's derivatives per vertex a,
   u_a = D_a0 f0, v_a = D_a1 f1 and s_a = D_a0 f1 + D_a1 f0 (those of E11, E22 and 2 E12),
       block (a, b) = area (c11 u_a + c12 v_a) u_b^T + area (c22 v_a + c12 u_a) v_b^T
                      + area c33 s_a s_b^T + g_ab I,
       g_ab = area (D_a0 D_b0 S11 + (D_a0 D_b1 + D_a1 D_b0) S12 + D_a1 D_b1 S22),
   the material part (dS/dE) and the geometric part (the stress S, or |S| for the projected
   form). A diagonal block's upper triangle is computed and mirrored: exactly symmetric. */
static cloth_real cloth__membrane_terms(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                        const cloth_membrane_rest *rest, const cloth_membrane_stiffness *stiffness,
                                        cloth_real *gradient, cloth_real *blocks, cloth_hessian_form form)
{
    cloth_real f0[3], f1[3], d[6], e11, e22, e12, s[3], w, area = rest->area;
    cloth_real c11 = stiffness->c11, c12 = stiffness->c12, c22 = stiffness->c22, c33 = stiffness->c33;
    int a, b, k;
    cloth__membrane_deformation(x0, x1, x2, rest, f0, f1, d);
    e11 = (cloth__v3_dot(f0, f0) - 1) / 2;
    e22 = (cloth__v3_dot(f1, f1) - 1) / 2;
    e12 = cloth__v3_dot(f0, f1) / 2;
    /* Second Piola-Kirchhoff stress, stored as [S11, S12, S22]. */
    s[0] = c11 * e11 + c12 * e22;
    s[1] = 2 * c33 * e12;
    s[2] = c12 * e11 + c22 * e22;
    w = (c11 * e11 * e11 + 2 * c12 * e11 * e22 + c22 * e22 * e22) / 2 + 2 * c33 * e12 * e12;
    if (gradient) {
        /* First Piola-Kirchhoff stress P = F S, columns p0, p1; dE/dx_a = area sum_p D_ap p_p. */
        cloth_real p0[3], p1[3];
        for (k = 0; k < 3; ++k) {
            p0[k] = s[0] * f0[k] + s[1] * f1[k];
            p1[k] = s[1] * f0[k] + s[2] * f1[k];
        }
        for (a = 0; a < 3; ++a) {
            const cloth_real da0 = d[2 * a], da1 = d[2 * a + 1];
            gradient[3 * a] = area * (da0 * p0[0] + da1 * p1[0]);
            gradient[3 * a + 1] = area * (da0 * p0[1] + da1 * p1[1]);
            gradient[3 * a + 2] = area * (da0 * p0[2] + da1 * p1[2]);
        }
    }
    if (blocks) {
        cloth_real u[3][3], v[3][3], t[3][3], pu[3][3], qv[3][3], st[3][3], sg[3];
        if (form == CLOTH_HESSIAN_EXACT) { sg[0] = s[0]; sg[1] = s[1]; sg[2] = s[2]; }
        else cloth__sym2_absolute(s, sg);
        for (a = 0; a < 3; ++a)
            for (k = 0; k < 3; ++k) {
                u[a][k] = d[2 * a] * f0[k];
                v[a][k] = d[2 * a + 1] * f1[k];
                t[a][k] = d[2 * a] * f1[k] + d[2 * a + 1] * f0[k];
                pu[a][k] = area * (c11 * u[a][k] + c12 * v[a][k]);
                qv[a][k] = area * (c22 * v[a][k] + c12 * u[a][k]);
                st[a][k] = area * c33 * t[a][k];
            }
        for (k = 0; k < 6; ++k) {
            static const int pair_a[6] = { 0, 0, 0, 1, 1, 2 }, pair_b[6] = { 0, 1, 2, 1, 2, 2 };
            cloth_real *o = blocks + 9 * k;
            cloth_real g;
            a = pair_a[k];
            b = pair_b[k];
            g = area * (d[2 * a] * d[2 * b] * sg[0] + (d[2 * a] * d[2 * b + 1] + d[2 * a + 1] * d[2 * b]) * sg[1] +
                        d[2 * a + 1] * d[2 * b + 1] * sg[2]);
            /* written out for the compiler, g added to the diagonal last */
            o[0] = pu[a][0] * u[b][0] + qv[a][0] * v[b][0] + st[a][0] * t[b][0] + g;
            o[1] = pu[a][0] * u[b][1] + qv[a][0] * v[b][1] + st[a][0] * t[b][1];
            o[2] = pu[a][0] * u[b][2] + qv[a][0] * v[b][2] + st[a][0] * t[b][2];
            o[3] = pu[a][1] * u[b][0] + qv[a][1] * v[b][0] + st[a][1] * t[b][0];
            o[4] = pu[a][1] * u[b][1] + qv[a][1] * v[b][1] + st[a][1] * t[b][1] + g;
            o[5] = pu[a][1] * u[b][2] + qv[a][1] * v[b][2] + st[a][1] * t[b][2];
            o[6] = pu[a][2] * u[b][0] + qv[a][2] * v[b][0] + st[a][2] * t[b][0];
            o[7] = pu[a][2] * u[b][1] + qv[a][2] * v[b][1] + st[a][2] * t[b][1];
            o[8] = pu[a][2] * u[b][2] + qv[a][2] * v[b][2] + st[a][2] * t[b][2] + g;
            if (a == b) { /* the upper triangle mirrored */
                o[3] = o[1];
                o[6] = o[2];
                o[7] = o[5];
            }
        }
    }
    return area * w;
}

CLOTH_API cloth_real cloth_membrane_energy(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                           const cloth_membrane_rest *rest, const cloth_membrane_stiffness *stiffness,
                                           cloth_real *gradient, cloth_real *hessian, cloth_hessian_form form)
{
    cloth_real blocks[54];
    cloth_real energy = cloth__membrane_terms(x0, x1, x2, rest, stiffness, gradient, hessian ? blocks : NULL, form);
    int a, b, r, c;
    if (hessian)
        for (a = 0; a < 3; ++a)
            for (b = a; b < 3; ++b) {
                const cloth_real *o = blocks + 9 * (a == 0 ? b : a == 1 ? 2 + b : 5);
                for (r = 0; r < 3; ++r)
                    for (c = 0; c < 3; ++c) {
                        hessian[(3 * a + r) * 9 + 3 * b + c] = o[3 * r + c];
                        hessian[(3 * b + c) * 9 + 3 * a + r] = o[3 * r + c];
                    }
            }
    return energy;
}

/* ---- dihedral bending ------------------------------------------------------------ */

/* The geometry of a bending stencil: edge e = x1 - x0, unnormalised face normals
   n0 = e x (x2 - x0), n1 = (x0 - x1) x (x3 - x1) (|n| = twice the face area), and whether
   it is degenerate (a face or the edge of near-zero size). */
typedef struct cloth__hinge {
    cloth_real e[3], n0[3], n1[3], l2, l, n0sq, n1sq;
} cloth__hinge;

static int cloth__hinge_make(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2, const cloth_real *x3,
                             cloth__hinge *h)
{
    cloth_real a[3], b[3], eps = CLOTH__FORCES_EPSILON;
    cloth__v3_sub(x1, x0, h->e);
    cloth__v3_sub(x2, x0, a);
    cloth__v3_cross(h->e, a, h->n0);
    cloth__v3_sub(x3, x1, b);
    cloth__v3_cross(b, h->e, h->n1);
    h->l2 = cloth__v3_dot(h->e, h->e);
    h->l = (cloth_real)sqrt((double)h->l2);
    h->n0sq = cloth__v3_dot(h->n0, h->n0);
    h->n1sq = cloth__v3_dot(h->n1, h->n1);
    /* |n| is twice the area = l times the height; a height below eps l is degenerate. */
    return h->l2 > 0 && h->n0sq > eps * eps * h->l2 * h->l2 && h->n1sq > eps * eps * h->l2 * h->l2;
}

static cloth_real cloth__hinge_angle(const cloth__hinge *h)
{
    cloth_real c[3];
    cloth__v3_cross(h->n0, h->n1, c);
    return (cloth_real)cloth__atan2((double)(cloth__v3_dot(c, h->e) / h->l), (double)cloth__v3_dot(h->n0, h->n1));
}

CLOTH_API cloth_real cloth_dihedral_angle(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                          const cloth_real *x3)
{
    cloth__hinge h;
    if (!cloth__hinge_make(x0, x1, x2, x3, &h)) return 0;
    return cloth__hinge_angle(&h);
}

/* weight = l^2 / (2 (a0 + a1)) from the edge length squared and twice the two areas. */
static cloth_real cloth__bending_weight(double l2, double twice_a0, double twice_a1)
{
    return (cloth_real)(l2 / (fabs(twice_a0) + fabs(twice_a1)));
}

CLOTH_API cloth_result cloth_bending_rest_make(cloth_bending_rest *rest, const cloth_real *uv0, const cloth_real *uv1,
                                               const cloth_real *uv2, const cloth_real *uv3, cloth_real rest_angle)
{
    const cloth_real *p[4];
    double a0, a1, eu, ev;
    CLOTH_ASSERT(rest && uv0 && uv1 && uv2 && uv3);
    memset(rest, 0, sizeof *rest);
    p[0] = uv0; p[1] = uv1; p[2] = uv2; p[3] = uv3;
    if (!cloth__all_finite_n(p, 4, 2) || !cloth__is_finite(rest_angle)) return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__pattern_triangle_ok(uv0, uv1, uv2, &a0) || !cloth__pattern_triangle_ok(uv1, uv0, uv3, &a1))
        return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    eu = (double)uv1[0] - uv0[0];
    ev = (double)uv1[1] - uv0[1];
    rest->weight = cloth__bending_weight(eu * eu + ev * ev, a0, a1);
    rest->rest_angle = rest_angle;
    return CLOTH_SUCCESS;
}

/* The 3D counterpart of cloth__pattern_triangle_ok, on twice the area |n|. */
static int cloth__shape_triangle_ok(const cloth_real *a, const cloth_real *b, const cloth_real *c, double *twice_area)
{
    double e[3][3], n[3], longest = 0, l;
    int k;
    for (k = 0; k < 3; ++k) {
        e[0][k] = (double)b[k] - a[k];
        e[1][k] = (double)c[k] - a[k];
        e[2][k] = (double)c[k] - b[k];
    }
    n[0] = e[0][1] * e[1][2] - e[0][2] * e[1][1];
    n[1] = e[0][2] * e[1][0] - e[0][0] * e[1][2];
    n[2] = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    for (k = 0; k < 3; ++k) {
        l = e[k][0] * e[k][0] + e[k][1] * e[k][1] + e[k][2] * e[k][2];
        if (l > longest) longest = l;
    }
    *twice_area = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    return *twice_area > CLOTH_MESH_QUALITY_TOLERANCE * longest && longest > 0;
}

CLOTH_API cloth_result cloth_bending_rest_from_shape(cloth_bending_rest *rest, const cloth_real *x0,
                                                     const cloth_real *x1, const cloth_real *x2, const cloth_real *x3)
{
    const cloth_real *p[4];
    double a0, a1, l2 = 0;
    int k;
    CLOTH_ASSERT(rest && x0 && x1 && x2 && x3);
    memset(rest, 0, sizeof *rest);
    p[0] = x0; p[1] = x1; p[2] = x2; p[3] = x3;
    if (!cloth__all_finite_n(p, 4, 3)) return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__shape_triangle_ok(x0, x1, x2, &a0) || !cloth__shape_triangle_ok(x1, x0, x3, &a1))
        return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    for (k = 0; k < 3; ++k) l2 += ((double)x1[k] - x0[k]) * ((double)x1[k] - x0[k]);
    rest->weight = cloth__bending_weight(l2, a0, a1);
    rest->rest_angle = cloth_dihedral_angle(x0, x1, x2, x3);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_real cloth_bending_stiffness_orthotropic(cloth_real bend_warp, cloth_real bend_weft, const cloth_real *uv0,
                                                         const cloth_real *uv1)
{
    double du = (double)uv1[0] - uv0[0], dv = (double)uv1[1] - uv0[1], l2 = du * du + dv * dv;
    if (!(l2 > 0)) return (bend_warp + bend_weft) / 2;
    return (cloth_real)(((double)bend_warp * dv * dv + (double)bend_weft * du * du) / l2);
}

/* Cross-product matrix [v]x (row-major), so that [v]x w = v x w. */
static void cloth__cross_matrix(const cloth_real *v, cloth_real *m)
{
    m[0] = 0;     m[1] = -v[2]; m[2] = v[1];
    m[3] = v[2];  m[4] = 0;     m[5] = -v[0];
    m[6] = -v[1]; m[7] = v[0];  m[8] = 0;
}

/* The Jacobian (3x12, row-major, 12 = 4 vertices x 3) of G = l n / |n|^2 = (unit normal) /
   (height) for one face, given n's Jacobian blocks dn/dx_a (3x3, row-major, 4 of them). */
static void cloth__hinge_g_jacobian(const cloth__hinge *h, const cloth_real *n, cloth_real nsq,
                                    const cloth_real *dn, cloth_real *jac)
{
    cloth_real g_over_l[3], unit_e[3], proj[9], scale = h->l / nsq;
    int a, r, c, q;
    cloth__v3_scale(n, 1 / nsq, g_over_l);
    cloth__v3_scale(h->e, 1 / h->l, unit_e);
    /* d(n/|n|^2) = (I - 2 nhat nhat^T) dn / |n|^2 */
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) proj[3 * r + c] = (r == c ? 1 : 0) - 2 * n[r] * n[c] / nsq;
    for (a = 0; a < 4; ++a)
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) {
                /* dl/dx_a = -unit_e (a = 0), +unit_e (a = 1), 0 otherwise */
                cloth_real v = a == 0 ? -g_over_l[r] * unit_e[c] : a == 1 ? g_over_l[r] * unit_e[c] : 0;
                for (q = 0; q < 3; ++q) v += scale * proj[3 * r + q] * dn[9 * a + 3 * q + c];
                jac[12 * r + 3 * a + c] = v;
            }
}

/* The Hessian of theta (12x12, row-major) from the derivative of its closed-form gradient. */
static void cloth__hinge_angle_hessian(const cloth__hinge *h, const cloth_real *x0, const cloth_real *x2,
                                       const cloth_real *x3, cloth_real t0, cloth_real t1, const cloth_real *g0,
                                       const cloth_real *g1, cloth_real *hess)
{
    cloth_real dn0[36], dn1[36], jg0[36], jg1[36], jt0[12], jt1[12], v[3], w[3], m[9];
    cloth_real d20[3], d30[3], d21[3];
    int r, c, k;
    cloth__v3_sub(x2, x0, d20);
    cloth__v3_sub(x3, x0, d30);
    /* n0 = e x (x2 - x0): dn0/dx0 = [x2 - x1]x, dn0/dx1 = -[x2 - x0]x, dn0/dx2 = [e]x, dn0/dx3 = 0 */
    cloth__v3_sub(d20, h->e, d21); /* x2 - x1 */
    cloth__cross_matrix(d21, dn0);
    cloth__cross_matrix(d20, m);
    for (k = 0; k < 9; ++k) dn0[9 + k] = -m[k];
    cloth__cross_matrix(h->e, dn0 + 18);
    for (k = 0; k < 9; ++k) dn0[27 + k] = 0;
    /* n1 = (x3 - x1) x e: dn1/dx0 = -[x3 - x1]x, dn1/dx1 = [x3 - x0]x, dn1/dx2 = 0, dn1/dx3 = -[e]x */
    cloth__v3_sub(d30, h->e, v); /* x3 - x1 */
    cloth__cross_matrix(v, m);
    for (k = 0; k < 9; ++k) dn1[k] = -m[k];
    cloth__cross_matrix(d30, dn1 + 9);
    for (k = 0; k < 9; ++k) dn1[18 + k] = 0;
    cloth__cross_matrix(h->e, m);
    for (k = 0; k < 9; ++k) dn1[27 + k] = -m[k];
    cloth__hinge_g_jacobian(h, h->n0, h->n0sq, dn0, jg0);
    cloth__hinge_g_jacobian(h, h->n1, h->n1sq, dn1, jg1);
    /* t = (p - x0) . e / l^2 for p = x2 (t0) and x3 (t1):
       dt/dx0 = (-e - (p - x0) + 2 t e) / l^2, dt/dx1 = ((p - x0) - 2 t e) / l^2, dt/dp = e / l^2 */
    for (k = 0; k < 3; ++k) {
        v[k] = h->e[k] / h->l2;
        w[k] = d20[k] / h->l2;
        jt0[k] = -v[k] - w[k] + 2 * t0 * v[k];
        jt0[3 + k] = w[k] - 2 * t0 * v[k];
        jt0[6 + k] = v[k];
        jt0[9 + k] = 0;
        w[k] = d30[k] / h->l2;
        jt1[k] = -v[k] - w[k] + 2 * t1 * v[k];
        jt1[3 + k] = w[k] - 2 * t1 * v[k];
        jt1[6 + k] = 0;
        jt1[9 + k] = v[k];
    }
    /* grad theta = [(1-t0) G0 + (1-t1) G1, t0 G0 + t1 G1, -G0, -G1]; differentiate row by row. */
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 12; ++c) {
            cloth_real dg0 = jg0[12 * r + c], dg1 = jg1[12 * r + c];
            cloth_real tg = g0[r] * jt0[c] + g1[r] * jt1[c];
            hess[(0 + r) * 12 + c] = (1 - t0) * dg0 + (1 - t1) * dg1 - tg;
            hess[(3 + r) * 12 + c] = t0 * dg0 + t1 * dg1 + tg;
            hess[(6 + r) * 12 + c] = -dg0;
            hess[(9 + r) * 12 + c] = -dg1;
        }
}

/* The angle terms of the dihedral energy E = k (theta - rest)^2, k = stiffness x the hinge's
   weight, at one configuration: the gradient of theta (grad[12]) and what its Hessian needs.
   E's gradient is 2 k dtheta grad; its projected Hessian the rank-one 2 k grad grad^T.
   ok = 0 for a degenerate hinge (no normal), whose terms are all zero. */
typedef struct cloth__bend_terms {
    cloth__hinge h;
    cloth_real energy, dtheta, k, t0, t1, g0[3], g1[3], grad[12];
    int ok;
} cloth__bend_terms;

/* Fills b; energy_only skips the gradient (grad, t0, t1, g0, g1 are then unset). */
static void cloth__bending_terms(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2, const cloth_real *x3,
                                 const cloth_bending_rest *rest, cloth_real stiffness, int energy_only, cloth__bend_terms *b)
{
    const cloth_real pi = (cloth_real)3.14159265358979323846;
    cloth_real d[3];
    int a;
    b->energy = b->dtheta = b->k = 0;
    b->ok = cloth__hinge_make(x0, x1, x2, x3, &b->h);
    if (!b->ok) {
        for (a = 0; a < 12; ++a) b->grad[a] = 0;
        return;
    }
    b->dtheta = cloth__hinge_angle(&b->h) - rest->rest_angle;
    if (b->dtheta > pi) b->dtheta -= 2 * pi;
    else if (b->dtheta <= -pi) b->dtheta += 2 * pi;
    b->k = stiffness * rest->weight;
    b->energy = b->k * b->dtheta * b->dtheta;
    if (energy_only) return;
    /* G = l n / |n|^2 = (unit normal) / (height over the edge), one per face. */
    cloth__v3_scale(b->h.n0, b->h.l / b->h.n0sq, b->g0);
    cloth__v3_scale(b->h.n1, b->h.l / b->h.n1sq, b->g1);
    cloth__v3_sub(x2, x0, d);
    b->t0 = cloth__v3_dot(d, b->h.e) / b->h.l2;
    cloth__v3_sub(x3, x0, d);
    b->t1 = cloth__v3_dot(d, b->h.e) / b->h.l2;
    for (a = 0; a < 3; ++a) {
        b->grad[a] = (1 - b->t0) * b->g0[a] + (1 - b->t1) * b->g1[a];
        b->grad[3 + a] = b->t0 * b->g0[a] + b->t1 * b->g1[a];
        b->grad[6 + a] = -b->g0[a];
        b->grad[9 + a] = -b->g1[a];
    }
}

CLOTH_API cloth_real cloth_bending_energy(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                          const cloth_real *x3, const cloth_bending_rest *rest, cloth_real stiffness,
                                          cloth_real *gradient, cloth_real *hessian, cloth_hessian_form form)
{
    cloth__bend_terms b;
    int a, c;
    cloth__bending_terms(x0, x1, x2, x3, rest, stiffness, !gradient && !hessian, &b);
    if (!b.ok) {
        cloth__forces_zero(gradient, 12);
        cloth__forces_zero(hessian, 144);
        return 0;
    }
    if (gradient)
        for (a = 0; a < 12; ++a) gradient[a] = 2 * b.k * b.dtheta * b.grad[a];
    if (hessian) {
        if (form == CLOTH_HESSIAN_EXACT) {
            cloth__hinge_angle_hessian(&b.h, x0, x2, x3, b.t0, b.t1, b.g0, b.g1, hessian);
            for (a = 0; a < 144; ++a) hessian[a] *= 2 * b.k * b.dtheta;
        } else {
            cloth__forces_zero(hessian, 144);
        }
        /* 2 k (grad_a grad_c): the same value above and below the diagonal */
        for (a = 0; a < 12; ++a)
            for (c = 0; c < 12; ++c) hessian[12 * a + c] += 2 * b.k * (b.grad[a] * b.grad[c]);
        cloth__forces_symmetrize(hessian, 12);
    }
    return b.energy;
}

/* ---- quadratic bending ----------------------------------------------------------- */

/* Whether w is one of the other vertices of the faces of v listed before face slot f (so
   that each neighbour is counted once, at its first face). */
static int cloth__ring_seen(const cloth_mesh *mesh, const cloth_topology *topo, int32_t v, int32_t f, int32_t w)
{
    int32_t s;
    for (s = topo->vertex_face_start[v]; s < f; ++s) {
        const int32_t *t = mesh->tri + 3 * (size_t)topo->vertex_face[s];
        if (t[0] == w || t[1] == w || t[2] == w) return 1;
    }
    return 0;
}

/* The number of neighbours of v, and when ring is not NULL v and then its neighbours in ring[]. */
static int32_t cloth__ring(const cloth_mesh *mesh, const cloth_topology *topo, int32_t v, int32_t *ring)
{
    int32_t f, n = 0;
    int k;
    if (ring) ring[0] = v;
    for (f = topo->vertex_face_start[v]; f < topo->vertex_face_start[v + 1]; ++f) {
        const int32_t *t = mesh->tri + 3 * (size_t)topo->vertex_face[f];
        for (k = 0; k < 3; ++k)
            if (t[k] != v && !cloth__ring_seen(mesh, topo, v, f, t[k])) {
                ++n;
                if (ring) ring[n] = t[k];
            }
    }
    return n;
}

static int32_t cloth__ring_slot(const int32_t *ring, int32_t n, int32_t w)
{
    int32_t a;
    for (a = 0; a < n; ++a)
        if (ring[a] == w) return a;
    return 0; /* not reached: every vertex of a face of v is in its ring */
}

/* The gradients of the three hat functions of a pattern triangle (2 each, 1/m) and twice its
   signed area. */
static void cloth__hat_gradients(const cloth_real *p0, const cloth_real *p1, const cloth_real *p2, double *grad, double *twice_area)
{
    const cloth_real *p[3];
    int k;
    p[0] = p0; p[1] = p1; p[2] = p2;
    *twice_area = ((double)p1[0] - p0[0]) * ((double)p2[1] - p0[1]) - ((double)p1[1] - p0[1]) * ((double)p2[0] - p0[0]);
    for (k = 0; k < 3; ++k) {
        const cloth_real *b = p[(k + 1) % 3], *c = p[(k + 2) % 3];
        grad[2 * k] = -((double)c[1] - b[1]) / *twice_area;
        grad[2 * k + 1] = ((double)c[0] - b[0]) / *twice_area;
    }
}

/* The mixed Voronoi area (Meyer et al. 2003) that face (p0, p1, p2) gives its corner p0. */
static double cloth__mixed_area(const cloth_real *p0, const cloth_real *p1, const cloth_real *p2, double twice_area)
{
    double a[2], b[2], c[2], d0, d1, d2, area = fabs(twice_area) / 2;
    a[0] = (double)p1[0] - p0[0]; a[1] = (double)p1[1] - p0[1]; /* p0 -> p1 */
    b[0] = (double)p2[0] - p0[0]; b[1] = (double)p2[1] - p0[1]; /* p0 -> p2 */
    c[0] = (double)p2[0] - p1[0]; c[1] = (double)p2[1] - p1[1]; /* p1 -> p2 */
    d0 = a[0] * b[0] + a[1] * b[1];    /* the angle at p0 is obtuse when < 0 */
    d1 = -(a[0] * c[0] + a[1] * c[1]); /* at p1 */
    d2 = b[0] * c[0] + b[1] * c[1];    /* at p2 */
    if (d0 < 0) return area / 2;
    if (d1 < 0 || d2 < 0) return area / 4;
    /* Voronoi: (|p0 p1|^2 cot(angle at p2) + |p0 p2|^2 cot(angle at p1)) / 8, cot = dot / |cross| */
    return ((a[0] * a[0] + a[1] * a[1]) * d2 + (b[0] * b[0] + b[1] * b[1]) * d1) / (8 * fabs(twice_area));
}

/* Whether face t is clamped: all three of its vertices pinned (pinned may be NULL: none). */
static int cloth__face_clamped(const int32_t *t, const int32_t *pinned)
{
    return pinned && pinned[t[0]] && pinned[t[1]] && pinned[t[2]];
}

/* One vertex's stencil: ring[n] (the vertex first) in; weight[3n] (rows uu, vv, uv) and the
   vertex's area out. Only the free faces (not clamped) count: their weak derivatives, their
   share of the vertex's area. Where the free region ends, the boundary term of the weak
   derivative, N_a g_b with N_a = the integral of phi_v n_a over the region's boundary, takes the
   slope g of the surface there: on a clamp edge (a free face's edge shared with a clamped face)
   the clamp's, the area-weighted mean gradient of the vertex's clamped faces; on a free edge
   the free faces' own. */
static void cloth__quadratic_bending_row(const cloth_mesh *mesh, const cloth_topology *topo, int32_t v, const int32_t *ring,
                                         int32_t n, const int32_t *pinned, const double *stiffness, cloth_real *weight,
                                         double *area)
{
    const cloth_real *uv = mesh->uv;
    double flux[3][2], clamp_flux[3][2], clamp_normal[2] = { 0, 0 }, total = 0, clamp_total = 0, a_v = 0, g[6], d;
    int32_t f, f2, a;
    int k, m;
    for (a = 0; a < 3 * n; ++a) weight[a] = 0;
    /* weak second derivatives: row m of -sum_t area_t d_a(phi_v) d_b(phi_k), (a, b) = uu, vv, uv (symmetrized) */
    for (f = topo->vertex_face_start[v]; f < topo->vertex_face_start[v + 1]; ++f) {
        const int32_t *t = mesh->tri + 3 * (size_t)topo->vertex_face[f];
        int corner = t[0] == v ? 0 : t[1] == v ? 1 : 2;
        const double *gv;
        cloth__hat_gradients(uv + 2 * t[0], uv + 2 * t[1], uv + 2 * t[2], g, &d);
        if (cloth__face_clamped(t, pinned)) {
            clamp_total += fabs(d) / 2;
            continue;
        }
        gv = g + 2 * corner;
        for (k = 0; k < 3; ++k) {
            cloth_real *w = weight + 3 * cloth__ring_slot(ring, n, t[k]);
            w[0] -= (cloth_real)(fabs(d) / 2 * gv[0] * g[2 * k]);
            w[1] -= (cloth_real)(fabs(d) / 2 * gv[1] * g[2 * k + 1]);
            w[2] -= (cloth_real)(fabs(d) / 4 * (gv[0] * g[2 * k + 1] + gv[1] * g[2 * k]));
        }
        a_v += cloth__mixed_area(uv + 2 * t[corner], uv + 2 * t[(corner + 1) % 3], uv + 2 * t[(corner + 2) % 3], d);
        total += fabs(d) / 2;
        /* its clamp edges (v, e): phi_v integrates to |e| / 2 along one, so N += |e| n / 2 with n
           the unit normal pointing out of this face (away from its third vertex o) */
        for (k = 1; k < 3 && pinned; ++k) {
            int32_t e = t[(corner + k) % 3], o = t[(corner + 3 - k) % 3], clamp = 0;
            double r[2];
            for (f2 = topo->vertex_face_start[v]; f2 < topo->vertex_face_start[v + 1] && !clamp; ++f2) {
                const int32_t *t2 = mesh->tri + 3 * (size_t)topo->vertex_face[f2];
                clamp = f2 != f && (t2[0] == e || t2[1] == e || t2[2] == e) && cloth__face_clamped(t2, pinned);
            }
            if (!clamp) continue;
            r[0] = (double)uv[2 * e + 1] - uv[2 * v + 1]; /* the edge turned by -90 degrees */
            r[1] = -((double)uv[2 * e] - uv[2 * v]);
            if (r[0] * ((double)uv[2 * o] - uv[2 * v]) + r[1] * ((double)uv[2 * o + 1] - uv[2 * v + 1]) > 0) {
                r[0] = -r[0];
                r[1] = -r[1];
            }
            clamp_normal[0] += r[0] / 2;
            clamp_normal[1] += r[1] / 2;
        }
    }
    /* each row's response to the pattern coordinates, -N_a delta_b (zero at interior vertices) */
    for (m = 0; m < 3; ++m) {
        flux[m][0] = flux[m][1] = 0;
        for (a = 0; a < n; ++a) {
            flux[m][0] += (double)weight[3 * a + m] * ((double)uv[2 * ring[a]] - uv[2 * v]);
            flux[m][1] += (double)weight[3 * a + m] * ((double)uv[2 * ring[a] + 1] - uv[2 * v + 1]);
        }
    }
    /* the clamp edges' part of it (uu: (-N_u, 0), vv: (0, -N_v), uv: (-N_v, -N_u) / 2), and the
       free edges' the rest */
    clamp_flux[0][0] = -clamp_normal[0]; clamp_flux[0][1] = 0;
    clamp_flux[1][0] = 0;                clamp_flux[1][1] = -clamp_normal[1];
    clamp_flux[2][0] = -clamp_normal[1] / 2; clamp_flux[2][1] = -clamp_normal[0] / 2;
    for (m = 0; m < 3; ++m) {
        flux[m][0] -= clamp_flux[m][0];
        flux[m][1] -= clamp_flux[m][1];
    }
    /* minus flux . (the gradient estimate: the area-weighted mean of the faces' gradients, the
       free faces' for the free edges and the clamped faces' for the clamp edges) */
    if (total > 0)
        for (f = topo->vertex_face_start[v]; f < topo->vertex_face_start[v + 1]; ++f) {
            const int32_t *t = mesh->tri + 3 * (size_t)topo->vertex_face[f];
            int clamped = cloth__face_clamped(t, pinned);
            double (*fl)[2] = clamped ? clamp_flux : flux, share;
            if (clamped && !(clamp_total > 0)) continue;
            cloth__hat_gradients(uv + 2 * t[0], uv + 2 * t[1], uv + 2 * t[2], g, &d);
            share = fabs(d) / 2 / (clamped ? clamp_total : total);
            for (k = 0; k < 3; ++k) {
                cloth_real *w = weight + 3 * cloth__ring_slot(ring, n, t[k]);
                for (m = 0; m < 3; ++m) w[m] -= (cloth_real)(share * (fl[m][0] * g[2 * k] + fl[m][1] * g[2 * k + 1]));
            }
        }
    /* H_ab = row / area; E = area / 2 sum_m stiffness_m |H_m|^2 = 1/2 sum_m |sqrt(stiffness_m / area) row|^2 */
    for (a = 0; a < n; ++a)
        for (m = 0; m < 3; ++m) weight[3 * a + m] = a_v > 0 ? (cloth_real)((double)weight[3 * a + m] * sqrt(stiffness[m] / a_v)) : 0;
    *area = a_v;
}

CLOTH_API cloth_result cloth_quadratic_bending_stencils(const cloth_mesh *mesh, const cloth_topology *topology,
                                                        cloth_real bend_warp, cloth_real bend_weft, const int32_t *pinned,
                                                        int32_t *start, int32_t *vertex, cloth_real *weight, cloth_real *area,
                                                        int32_t capacity, int32_t *count)
{
    int64_t total = 0;
    int32_t v, t;
    double stiffness[3], twice;
    CLOTH_ASSERT(mesh && topology && count);
    *count = 0;
    if (!mesh->uv) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!cloth__is_finite(bend_warp) || !cloth__is_finite(bend_weft)) return CLOTH_ERROR_NOT_FINITE;
    if (bend_warp < 0 || bend_weft < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (v = 0; v < mesh->vertex_count; ++v)
        if (!cloth__is_finite(mesh->uv[2 * v]) || !cloth__is_finite(mesh->uv[2 * v + 1])) return CLOTH_ERROR_NOT_FINITE;
    for (t = 0; t < mesh->triangle_count; ++t) {
        const int32_t *q = mesh->tri + 3 * (size_t)t;
        if (!cloth__pattern_triangle_ok(mesh->uv + 2 * q[0], mesh->uv + 2 * q[1], mesh->uv + 2 * q[2], &twice))
            return CLOTH_ERROR_DEGENERATE_TRIANGLE;
    }
    for (v = 0; v < mesh->vertex_count; ++v) total += 1 + cloth__ring(mesh, topology, v, NULL);
    if (total > INT32_MAX / 3) return CLOTH_ERROR_SIZE_OVERFLOW;
    *count = (int32_t)total;
    if (!vertex) return CLOTH_SUCCESS;
    CLOTH_ASSERT(start && weight);
    if (capacity < *count) return CLOTH_ERROR_INVALID_ARGUMENT;
    stiffness[0] = bend_warp;
    stiffness[1] = bend_weft;
    stiffness[2] = 2 * sqrt((double)bend_warp * bend_weft);
    start[0] = 0;
    for (v = 0; v < mesh->vertex_count; ++v) {
        int32_t s = start[v], n = 1 + cloth__ring(mesh, topology, v, vertex + s);
        double a_v;
        cloth__quadratic_bending_row(mesh, topology, v, vertex + s, n, pinned, stiffness, weight + 3 * (size_t)s, &a_v);
        if (area) area[v] = (cloth_real)a_v;
        start[v + 1] = s + n;
    }
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_real cloth_quadratic_bending_energy(const cloth_real *x, const int32_t *vertex, const cloth_real *weight,
                                                    int32_t count, cloth_real *gradient, cloth_real *hessian)
{
    cloth_real k[3][3], energy = 0;
    int32_t a, b, stride = 3 * count;
    int m, r;
    for (m = 0; m < 3; ++m) {
        for (r = 0; r < 3; ++r) k[m][r] = 0;
        for (a = 0; a < count; ++a)
            for (r = 0; r < 3; ++r) k[m][r] += weight[3 * a + m] * x[3 * (size_t)vertex[a] + r];
        energy += cloth__v3_dot(k[m], k[m]) / 2;
    }
    if (gradient)
        for (a = 0; a < count; ++a)
            for (r = 0; r < 3; ++r)
                gradient[3 * a + r] = weight[3 * a] * k[0][r] + weight[3 * a + 1] * k[1][r] + weight[3 * a + 2] * k[2][r];
    if (hessian) {
        cloth__forces_zero(hessian, stride * stride);
        for (a = 0; a < count; ++a)
            for (b = 0; b < count; ++b) {
                cloth_real h = weight[3 * a] * weight[3 * b] + weight[3 * a + 1] * weight[3 * b + 1] + weight[3 * a + 2] * weight[3 * b + 2];
                for (r = 0; r < 3; ++r) hessian[(size_t)(3 * a + r) * (size_t)stride + 3 * b + r] = h;
            }
    }
    return energy;
}

/* ---- gravity --------------------------------------------------------------------- */

CLOTH_API cloth_real cloth_gravity_energy(const cloth_real *x, cloth_real mass, const cloth_real *gravity,
                                          cloth_real *gradient, cloth_real *hessian)
{
    if (gradient) cloth__v3_scale(gravity, -mass, gradient);
    cloth__forces_zero(hessian, 9);
    return -mass * cloth__v3_dot(gravity, x);
}

/* ---- aerodynamics ---------------------------------------------------------------- */

CLOTH_API cloth_aerodynamics cloth_default_aerodynamics(void)
{
    cloth_aerodynamics air;
    air.air_density = (cloth_real)1.225;
    air.normal_coefficient = (cloth_real)1.28;
    air.tangential_coefficient = 0;
    return air;
}

CLOTH_API void cloth_aerodynamic_force(const cloth_real *x0, const cloth_real *x1, const cloth_real *x2,
                                       const cloth_real *v0, const cloth_real *v1, const cloth_real *v2,
                                       const cloth_real *wind, const cloth_aerodynamics *air, cloth_real *force,
                                       cloth_real *velocity_jacobian)
{
    cloth_real e1[3], e2[3], n[3], u[3], ut[3], f[3], twice_area, un, utn, q;
    int r, c, k;
    cloth__v3_sub(x1, x0, e1);
    cloth__v3_sub(x2, x0, e2);
    cloth__v3_cross(e1, e2, n);
    twice_area = cloth__v3_norm(n);
    cloth__forces_zero(force, 9);
    cloth__forces_zero(velocity_jacobian, 81);
    if (!(twice_area > 0)) return;
    cloth__v3_scale(n, 1 / twice_area, n);
    for (k = 0; k < 3; ++k) u[k] = wind[k] - (v0[k] + v1[k] + v2[k]) / 3;
    un = cloth__v3_dot(u, n);
    for (k = 0; k < 3; ++k) ut[k] = u[k] - un * n[k];
    utn = cloth__v3_norm(ut);
    q = air->air_density * twice_area / 4; /* 1/2 rho A */
    for (k = 0; k < 3; ++k)
        f[k] = q * (air->normal_coefficient * un * (cloth_real)fabs((double)un) * n[k] +
                    air->tangential_coefficient * utn * ut[k]);
    if (force)
        for (k = 0; k < 9; ++k) force[k] = f[k % 3] / 3;
    if (velocity_jacobian) {
        /* df/du, then df_a/dv_b = (1/3) df/du (-1/3 I) for every pair (a, b). */
        cloth_real dfdu[9];
        for (r = 0; r < 3; ++r)
            for (c = r; c < 3; ++c) {
                cloth_real v = 2 * air->normal_coefficient * (cloth_real)fabs((double)un) * n[r] * n[c];
                if (utn > 0)
                    v += air->tangential_coefficient *
                         (utn * ((r == c ? 1 : 0) - n[r] * n[c]) + ut[r] * ut[c] / utn);
                dfdu[3 * r + c] = dfdu[3 * c + r] = q * v;
            }
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) cloth__forces_add_block(velocity_jacobian, 3, r, c, (cloth_real)-1 / 9, dfdu);
    }
}

CLOTH_API cloth_gust_def cloth_default_gust_def(void)
{
    cloth_gust_def def;
    int k;
    for (k = 0; k < 3; ++k) def.mean[k] = def.deviation[k] = 0;
    def.correlation_time = 1;
    def.seed = 1;
    return def;
}

CLOTH_API cloth_result cloth_gust_init(cloth_gust *gust, const cloth_gust_def *def)
{
    int k;
    CLOTH_ASSERT(gust && def);
    memset(gust, 0, sizeof *gust);
    for (k = 0; k < 3; ++k)
        if (!cloth__is_finite(def->mean[k]) || !cloth__is_finite(def->deviation[k])) return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__is_finite(def->correlation_time)) return CLOTH_ERROR_NOT_FINITE;
    for (k = 0; k < 3; ++k)
        if (def->deviation[k] < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!(def->correlation_time > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    gust->def = *def;
    gust->rng = cloth_rng_make(def->seed);
    for (k = 0; k < 3; ++k) gust->gust[k] = def->deviation[k] * cloth_rng_normal(&gust->rng);
    gust->time = 0;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_gust_advance(cloth_gust *gust, cloth_real dt)
{
    double decay, spread;
    int k;
    CLOTH_ASSERT(gust);
    if (!cloth__is_finite(dt) || dt < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (dt == 0) return CLOTH_SUCCESS; /* draws nothing, so a zero step leaves the future unchanged */
    decay = exp(-(double)dt / (double)gust->def.correlation_time);
    spread = sqrt(1 - decay * decay);
    for (k = 0; k < 3; ++k)
        gust->gust[k] = (cloth_real)(decay * gust->gust[k] +
                                     spread * (double)gust->def.deviation[k] * (double)cloth_rng_normal(&gust->rng));
    gust->time += (double)dt;
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_gust_wind(const cloth_gust *gust, cloth_real *wind)
{
    CLOTH_ASSERT(gust && wind);
    cloth__v3_add(gust->def.mean, gust->gust, wind);
}

/* ---- damping --------------------------------------------------------------------- */

CLOTH_API void cloth_relative_damping_force(const cloth_real *v0, const cloth_real *v1, const cloth_real *v2,
                                            const cloth_real *v3, cloth_real coefficient, cloth_real *force,
                                            cloth_real *velocity_jacobian)
{
    const cloth_real *velocity[4];
    int a, b, k, n;
    CLOTH_ASSERT(v0 && v1 && (v2 || !v3));
    velocity[0] = v0;
    velocity[1] = v1;
    velocity[2] = v2;
    velocity[3] = v3;
    n = v2 ? (v3 ? 4 : 3) : 2;
    if (force)
        for (a = 0; a < n; ++a)
            for (k = 0; k < 3; ++k) {
                cloth_real sum = 0;
                for (b = 0; b < n; ++b) sum += velocity[a][k] - velocity[b][k];
                force[3 * a + k] = -coefficient * sum;
            }
    if (velocity_jacobian) {
        cloth_real identity[9];
        cloth__forces_zero(identity, 9);
        identity[0] = identity[4] = identity[8] = 1;
        cloth__forces_zero(velocity_jacobian, 9 * n * n);
        for (a = 0; a < n; ++a)
            for (b = 0; b < n; ++b)
                cloth__forces_add_block(velocity_jacobian, n, a, b, -coefficient * (cloth_real)(a == b ? n - 1 : -1),
                                        identity);
    }
}

CLOTH_API void cloth_air_drag_force(const cloth_real *velocity, cloth_real coefficient, cloth_real *force,
                                    cloth_real *velocity_jacobian)
{
    if (force) cloth__v3_scale(velocity, -coefficient, force);
    if (velocity_jacobian) {
        cloth__forces_zero(velocity_jacobian, 9);
        velocity_jacobian[0] = velocity_jacobian[4] = velocity_jacobian[8] = -coefficient;
    }
}

/* ------------------------------------------------------------------------------------- */
/* linsolve                                                                              */
/* ------------------------------------------------------------------------------------- */

CLOTH_API cloth_result cloth_block_matrix_create(cloth_block_matrix *matrix, int32_t vertex_count,
                                                 const int32_t *pair, int32_t pair_count,
                                                 const cloth_allocator *allocator)
{
    cloth_allocator a;
    size_t n, entry_count, distinct_count, i, k, out;
    size_t *raw_start = NULL, *cursor = NULL;
    int32_t *raw = NULL, *sorted = NULL;
    int32_t pk;
    int ok = 1;
    cloth_result result = CLOTH_SUCCESS;

    CLOTH_ASSERT(matrix);
    memset(matrix, 0, sizeof *matrix);
    if (vertex_count < 0 || pair_count < 0 || (pair_count > 0 && !pair)) return CLOTH_ERROR_INVALID_ARGUMENT;
    n = (size_t)vertex_count;
    entry_count = n; /* with repetitions: one diagonal entry per row, two per pair of distinct vertices */
    for (pk = 0; pk < pair_count; ++pk) {
        int32_t u = pair[2 * (size_t)pk], v = pair[2 * (size_t)pk + 1];
        if (u < 0 || u >= vertex_count || v < 0 || v >= vertex_count) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
        if (u != v) entry_count = cloth__size_mul_add(2, 1, entry_count, &ok);
    }
    cloth__size_mul_add(entry_count, sizeof(int32_t), 0, &ok);
    cloth__size_mul_add(n + 1, sizeof(size_t), 0, &ok);
    if (!ok) return CLOTH_ERROR_SIZE_OVERFLOW;
    a = cloth__allocator_or_default(allocator);

    raw_start = (size_t *)cloth__alloc_array(&a, n + 1, sizeof(size_t));
    cursor = (size_t *)cloth__alloc_array(&a, n, sizeof(size_t));
    raw = (int32_t *)cloth__alloc_array(&a, entry_count, sizeof(int32_t));
    sorted = (int32_t *)cloth__alloc_array(&a, entry_count, sizeof(int32_t));
    if (!raw_start || !cursor || !raw || !sorted) { result = CLOTH_ERROR_OUT_OF_MEMORY; goto done; }

    /* The entries of each row, unsorted and with repetitions. */
    raw_start[0] = 0;
    for (i = 0; i < n; ++i) raw_start[i + 1] = 1;
    for (pk = 0; pk < pair_count; ++pk) {
        int32_t u = pair[2 * (size_t)pk], v = pair[2 * (size_t)pk + 1];
        if (u != v) { ++raw_start[(size_t)u + 1]; ++raw_start[(size_t)v + 1]; }
    }
    for (i = 0; i < n; ++i) raw_start[i + 1] += raw_start[i];
    for (i = 0; i < n; ++i) { cursor[i] = raw_start[i]; raw[cursor[i]++] = (int32_t)i; }
    for (pk = 0; pk < pair_count; ++pk) {
        int32_t u = pair[2 * (size_t)pk], v = pair[2 * (size_t)pk + 1];
        if (u != v) { raw[cursor[u]++] = v; raw[cursor[v]++] = u; }
    }

    /* Sort every row at once by a counting transpose: visit the columns c in increasing order
       and append c to each row that holds it. The entry set is symmetric, so the rows that hold
       column c are the entries of row c. */
    for (i = 0; i < n; ++i) cursor[i] = raw_start[i];
    for (i = 0; i < n; ++i)
        for (k = raw_start[i]; k < raw_start[i + 1]; ++k) sorted[cursor[raw[k]]++] = (int32_t)i;

    distinct_count = 0;
    for (i = 0; i < n; ++i)
        for (k = raw_start[i]; k < raw_start[i + 1]; ++k)
            if (k == raw_start[i] || sorted[k] != sorted[k - 1]) ++distinct_count;
    cloth__size_mul_add(distinct_count, 9 * sizeof(cloth_real), 0, &ok);
    if (!ok || distinct_count > (size_t)INT32_MAX) { result = CLOTH_ERROR_SIZE_OVERFLOW; goto done; }

    matrix->row_start = (int32_t *)cloth__alloc_array(&a, n + 1, sizeof(int32_t));
    matrix->column = (int32_t *)cloth__alloc_array(&a, distinct_count, sizeof(int32_t));
    matrix->diagonal = (int32_t *)cloth__alloc_array(&a, n, sizeof(int32_t));
    matrix->value = (cloth_real *)cloth__alloc_array(&a, distinct_count, 9 * sizeof(cloth_real));
    if (!matrix->row_start || !matrix->column || !matrix->diagonal || !matrix->value) {
        result = CLOTH_ERROR_OUT_OF_MEMORY;
        goto done;
    }
    out = 0;
    matrix->row_start[0] = 0;
    for (i = 0; i < n; ++i) {
        for (k = raw_start[i]; k < raw_start[i + 1]; ++k) {
            if (k != raw_start[i] && sorted[k] == sorted[k - 1]) continue;
            if ((size_t)sorted[k] == i) matrix->diagonal[i] = (int32_t)out;
            matrix->column[out++] = sorted[k];
        }
        matrix->row_start[i + 1] = (int32_t)out;
    }
    for (k = 0; k < 9 * distinct_count; ++k) matrix->value[k] = 0;
    matrix->vertex_count = vertex_count;
    matrix->block_count = (int32_t)distinct_count;
    matrix->allocator = a;

done:
    cloth__free(&a, raw_start);
    cloth__free(&a, cursor);
    cloth__free(&a, raw);
    cloth__free(&a, sorted);
    if (result != CLOTH_SUCCESS) {
        cloth__free(&a, matrix->row_start);
        cloth__free(&a, matrix->column);
        cloth__free(&a, matrix->diagonal);
        cloth__free(&a, matrix->value);
        memset(matrix, 0, sizeof *matrix);
    }
    return result;
}

CLOTH_API void cloth_block_matrix_free(cloth_block_matrix *matrix)
{
    cloth_allocator a;
    CLOTH_ASSERT(matrix);
    a = cloth__allocator_or_default(&matrix->allocator);
    cloth__free(&a, matrix->row_start);
    cloth__free(&a, matrix->column);
    cloth__free(&a, matrix->diagonal);
    cloth__free(&a, matrix->value);
    memset(matrix, 0, sizeof *matrix);
}

CLOTH_API int32_t cloth_block_matrix_find(const cloth_block_matrix *matrix, int32_t row, int32_t column)
{
    int32_t lo, hi;
    CLOTH_ASSERT(matrix);
    if (row < 0 || row >= matrix->vertex_count || column < 0 || column >= matrix->vertex_count) return -1;
    lo = matrix->row_start[row];
    hi = matrix->row_start[row + 1];
    while (lo < hi) {
        int32_t mid = lo + (hi - lo) / 2;
        int32_t c = matrix->column[mid];
        if (c == column) return mid;
        if (c < column) lo = mid + 1;
        else hi = mid;
    }
    return -1;
}

CLOTH_API void cloth_block_matrix_zero(cloth_block_matrix *matrix)
{
    size_t k, count;
    CLOTH_ASSERT(matrix);
    count = 9 * (size_t)matrix->block_count;
    for (k = 0; k < count; ++k) matrix->value[k] = 0;
}

CLOTH_API void cloth_block_matrix_add_block(cloth_block_matrix *matrix, int32_t block, cloth_real scale,
                                            const cloth_real *b)
{
    cloth_real *v;
    int e;
    CLOTH_ASSERT(matrix && b && block >= 0 && block < matrix->block_count);
    v = matrix->value + 9 * (size_t)block;
    for (e = 0; e < 9; ++e) v[e] += scale * b[e];
}

CLOTH_API void cloth_block_matrix_add_block_transposed(cloth_block_matrix *matrix, int32_t block, cloth_real scale,
                                                       const cloth_real *b)
{
    cloth_real *v;
    int r, c;
    CLOTH_ASSERT(matrix && b && block >= 0 && block < matrix->block_count);
    v = matrix->value + 9 * (size_t)block;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) v[3 * r + c] += scale * b[3 * c + r];
}

CLOTH_API void cloth_block_matrix_add_diagonal(cloth_block_matrix *matrix, cloth_real scale, const cloth_real *weight)
{
    int32_t i;
    CLOTH_ASSERT(matrix);
    for (i = 0; i < matrix->vertex_count; ++i) {
        cloth_real *v = matrix->value + 9 * (size_t)matrix->diagonal[i];
        cloth_real d = weight ? scale * weight[i] : scale;
        v[0] += d;
        v[4] += d;
        v[8] += d;
    }
}

/* (A x) restricted to block row i, summed over the row's blocks in column order. */
static void cloth__block_row_product(const cloth_block_matrix *matrix, int32_t i, const cloth_real *x, cloth_real *out)
{
    cloth_real s0 = 0, s1 = 0, s2 = 0;
    int32_t k, end = matrix->row_start[i + 1];
    for (k = matrix->row_start[i]; k < end; ++k) {
        const cloth_real *m = matrix->value + 9 * (size_t)k;
        const cloth_real *xj = x + 3 * (size_t)matrix->column[k];
        s0 += m[0] * xj[0] + m[1] * xj[1] + m[2] * xj[2];
        s1 += m[3] * xj[0] + m[4] * xj[1] + m[5] * xj[2];
        s2 += m[6] * xj[0] + m[7] * xj[1] + m[8] * xj[2];
    }
    out[0] = s0;
    out[1] = s1;
    out[2] = s2;
}

CLOTH_API void cloth_block_matrix_multiply(const cloth_block_matrix *matrix, const cloth_real *x, cloth_real *y)
{
    int32_t i;
    CLOTH_ASSERT(matrix && x && y && x != y);
    for (i = 0; i < matrix->vertex_count; ++i) cloth__block_row_product(matrix, i, x, y + 3 * (size_t)i);
}

CLOTH_API void cloth_block_matrix_multiply_add(const cloth_block_matrix *matrix, cloth_real scale, const cloth_real *x,
                                               cloth_real *y)
{
    int32_t i;
    CLOTH_ASSERT(matrix && x && y && x != y);
    for (i = 0; i < matrix->vertex_count; ++i) {
        cloth_real t[3], *yi = y + 3 * (size_t)i;
        cloth__block_row_product(matrix, i, x, t);
        yi[0] += scale * t[0];
        yi[1] += scale * t[1];
        yi[2] += scale * t[2];
    }
}

/* ---- filtered preconditioned conjugate gradient ------------------------------------ */

/* Vertices per chunk of the solver's parallel loops. Dot products are summed in index order
   within a chunk and the chunk sums added in chunk order, whatever the thread count. */
#define CLOTH__CHUNK 256

CLOTH_API cloth_pcg_options cloth_default_pcg_options(void)
{
    cloth_pcg_options o;
    o.tolerance = sizeof(cloth_real) < sizeof(double) ? (cloth_real)1e-4 : (cloth_real)1e-6;
    o.max_iterations = 1000;
    o.preconditioner = CLOTH_PRECONDITIONER_BLOCK_JACOBI;
    o.multigrid_update = 1;
    o.reference_norm = 0;
    return o;
}

CLOTH_API cloth_result cloth_pcg_workspace_create(cloth_pcg_workspace *workspace, int32_t vertex_count,
                                                  const cloth_allocator *allocator)
{
    int ok = 1;
    CLOTH_ASSERT(workspace);
    memset(workspace, 0, sizeof *workspace);
    if (vertex_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    /* 24 reals per vertex, then one double per chunk for the solver's partial sums */
    cloth__size_mul_add((size_t)vertex_count, 24 * sizeof(cloth_real), 0, &ok);
    if (!ok) return CLOTH_ERROR_SIZE_OVERFLOW;
    workspace->allocator = cloth__allocator_or_default(allocator);
    workspace->memory = (cloth_real *)cloth__alloc_array(&workspace->allocator, 24 * (size_t)vertex_count
                                                         + 2 * ((size_t)vertex_count / CLOTH__CHUNK + 1), sizeof(cloth_real));
    if (!workspace->memory) {
        memset(workspace, 0, sizeof *workspace);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    workspace->vertex_count = vertex_count;
    return CLOTH_SUCCESS;
}

static void cloth__mg_free(struct cloth__multigrid *mg);

CLOTH_API void cloth_pcg_workspace_free(cloth_pcg_workspace *workspace)
{
    cloth_allocator a;
    CLOTH_ASSERT(workspace);
    a = cloth__allocator_or_default(&workspace->allocator);
    cloth__free(&a, workspace->memory);
    cloth__mg_free(workspace->multigrid);
    if (workspace->pool_owned) cloth__pool_destroy(workspace->pool);
    memset(workspace, 0, sizeof *workspace);
}

CLOTH_API cloth_result cloth_pcg_workspace_set_threads(cloth_pcg_workspace *workspace, int32_t threads)
{
#ifdef CLOTH_THREADS
    cloth_allocator a;
#endif
    CLOTH_ASSERT(workspace);
    if (threads < 0 || threads > CLOTH__MAX_THREADS) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (workspace->pool_owned) cloth__pool_destroy(workspace->pool);
    workspace->pool = NULL;
    workspace->pool_owned = 0;
#ifdef CLOTH_THREADS
    if (threads < 2) return CLOTH_SUCCESS;
    a = cloth__allocator_or_default(&workspace->allocator);
    workspace->pool = cloth__pool_create(threads, &a);
    if (!workspace->pool) return CLOTH_ERROR_OUT_OF_MEMORY;
    workspace->pool_owned = 1;
#endif
    return CLOTH_SUCCESS;
}

static int cloth__is_finite_double(double v) { return v == v && v - v == 0; }

/* 1 when all count values are finite: v - v is 0 for a finite v and NaN otherwise (four sums,
   so that the additions do not wait on each other). */
static int cloth__all_finite(const cloth_real *v, size_t count)
{
    cloth_real a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    size_t k;
    for (k = 0; k + 4 <= count; k += 4) {
        a0 += v[k] - v[k];
        a1 += v[k + 1] - v[k + 1];
        a2 += v[k + 2] - v[k + 2];
        a3 += v[k + 3] - v[k + 3];
    }
    for (; k < count; ++k) a0 += v[k] - v[k];
    return a0 + a1 + a2 + a3 == 0;
}

/* cloth__all_finite over count values split evenly into `chunks` parts on the pool (flag:
   one double per part). */
typedef struct cloth__finite_job {
    const cloth_real *v;
    size_t count;
    int32_t chunks;
    double *flag;
} cloth__finite_job;

static void cloth__finite_task(void *context, int32_t part)
{
    const cloth__finite_job *job = (const cloth__finite_job *)context;
    const size_t size = job->count / (size_t)job->chunks, k0 = size * (size_t)part;
    const size_t k1 = part + 1 == job->chunks ? job->count : k0 + size;
    job->flag[part] = cloth__all_finite(job->v + k0, k1 - k0);
}

static int cloth__all_finite_pool(cloth__pool *pool, const cloth_real *v, size_t count, int32_t chunks, double *flag)
{
    cloth__finite_job job;
    int32_t c;
    job.v = v;
    job.count = count;
    job.chunks = chunks;
    job.flag = flag;
    cloth__pool_run(pool, chunks, cloth__finite_task, &job);
    for (c = 0; c < chunks; ++c)
        if (flag[c] == 0) return 0;
    return 1;
}

/* a . b over count reals, accumulated in double in index order. */
static double cloth__dot_long(const cloth_real *a, const cloth_real *b, size_t count)
{
    double s = 0;
    size_t k;
    for (k = 0; k < count; ++k) s += (double)a[k] * (double)b[k];
    return s;
}

/* The filter S_i of a vertex with `count` constrained directions, in the form the solver keeps:
   for 1, d is the unit constrained direction p (S = I - p p^T); for 2, d is the unit free
   direction f (S = f f^T). v <- S v, in place. */
static void cloth__filter_apply(int32_t count, const cloth_real *d, cloth_real *v)
{
    cloth_real t;
    switch (count) {
    case 0:
        return;
    case 1:
        t = cloth__v3_dot(d, v);
        v[0] -= t * d[0];
        v[1] -= t * d[1];
        v[2] -= t * d[2];
        return;
    case 2:
        t = cloth__v3_dot(d, v);
        v[0] = t * d[0];
        v[1] = t * d[1];
        v[2] = t * d[2];
        return;
    default:
        v[0] = v[1] = v[2] = 0;
        return;
    }
}

/* out <- (I - S) v, the constrained part of v. */
static void cloth__filter_complement(int32_t count, const cloth_real *d, const cloth_real *v, cloth_real *out)
{
    cloth_real t;
    switch (count) {
    case 0:
        out[0] = out[1] = out[2] = 0;
        return;
    case 1:
        t = cloth__v3_dot(d, v);
        out[0] = t * d[0];
        out[1] = t * d[1];
        out[2] = t * d[2];
        return;
    case 2:
        t = cloth__v3_dot(d, v);
        out[0] = v[0] - t * d[0];
        out[1] = v[1] - t * d[1];
        out[2] = v[2] - t * d[2];
        return;
    default:
        out[0] = v[0];
        out[1] = v[1];
        out[2] = v[2];
        return;
    }
}

/* v / |v| in double, scaled first so that no square overflows; 0 when v is zero. */
static int cloth__unit_double(const double *v, double *out)
{
    double m = fabs(v[0]), len;
    if (fabs(v[1]) > m) m = fabs(v[1]);
    if (fabs(v[2]) > m) m = fabs(v[2]);
    if (!(m > 0)) return 0;
    out[0] = v[0] / m;
    out[1] = v[1] / m;
    out[2] = v[2] / m;
    len = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    out[0] /= len;
    out[1] /= len;
    out[2] /= len;
    return 1;
}

/* Check the filter and write each constrained vertex's direction (see cloth__filter_apply). */
static cloth_result cloth__pcg_prepare_filter(int32_t n, const int32_t *constrained, const cloth_real *direction,
                                              cloth_real *d)
{
    int32_t i;
    if (!constrained) return CLOTH_SUCCESS;
    for (i = 0; i < n; ++i) {
        int32_t count = constrained[i];
        const cloth_real *pq;
        double p[3], q[3], qn[3], f[3], t;
        int e;
        if (count < 0 || count > 3) return CLOTH_ERROR_INVALID_ARGUMENT;
        if (count == 0 || count == 3) continue;
        if (!direction) return CLOTH_ERROR_INVALID_ARGUMENT;
        pq = direction + 6 * (size_t)i;
        if (!cloth__all_finite(pq, (size_t)(count == 1 ? 3 : 6))) return CLOTH_ERROR_NOT_FINITE;
        for (e = 0; e < 3; ++e) { p[e] = (double)pq[e]; q[e] = (double)pq[3 + e]; }
        if (!cloth__unit_double(p, p)) return CLOTH_ERROR_INVALID_ARGUMENT;
        if (count == 1) {
            for (e = 0; e < 3; ++e) d[3 * (size_t)i + e] = (cloth_real)p[e];
            continue;
        }
        /* q without its component along p must keep a thousandth of q's length */
        if (!cloth__unit_double(q, q)) return CLOTH_ERROR_INVALID_ARGUMENT;
        t = p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
        for (e = 0; e < 3; ++e) qn[e] = q[e] - t * p[e];
        if (!(qn[0] * qn[0] + qn[1] * qn[1] + qn[2] * qn[2] >= 1e-6)) return CLOTH_ERROR_INVALID_ARGUMENT;
        f[0] = p[1] * qn[2] - p[2] * qn[1];
        f[1] = p[2] * qn[0] - p[0] * qn[2];
        f[2] = p[0] * qn[1] - p[1] * qn[0];
        cloth__unit_double(f, f);
        for (e = 0; e < 3; ++e) d[3 * (size_t)i + e] = (cloth_real)f[e];
    }
    return CLOTH_SUCCESS;
}

/* The inverse of a symmetric positive definite 3x3 matrix through its Cholesky factor
   m = L L^T: m^-1 = L^-T L^-1. Returns 0 when a pivot is not positive. */
static int cloth__spd_inverse3(const double *m, double *inv)
{
    double l00, l10, l20, l11, l21, l22, d, i00, i10, i20, i11, i21, i22;
    if (!(m[0] > 0)) return 0;
    l00 = sqrt(m[0]);
    l10 = m[3] / l00;
    l20 = m[6] / l00;
    d = m[4] - l10 * l10;
    if (!(d > 0)) return 0;
    l11 = sqrt(d);
    l21 = (m[7] - l20 * l10) / l11;
    d = m[8] - l20 * l20 - l21 * l21;
    if (!(d > 0)) return 0;
    l22 = sqrt(d);
    /* L^-1, lower triangular */
    i00 = 1 / l00;
    i11 = 1 / l11;
    i22 = 1 / l22;
    i10 = -l10 * i00 * i11;
    i21 = -l21 * i11 * i22;
    i20 = -(l20 * i00 + l21 * i10) * i22;
    /* L^-T L^-1 */
    inv[0] = i00 * i00 + i10 * i10 + i20 * i20;
    inv[1] = i10 * i11 + i20 * i21;
    inv[2] = i20 * i22;
    inv[4] = i11 * i11 + i21 * i21;
    inv[5] = i21 * i22;
    inv[8] = i22 * i22;
    inv[3] = inv[1];
    inv[6] = inv[2];
    inv[7] = inv[5];
    return 1;
}

/* out = S_i P_i^-1 S_i for the Jacobi and block-Jacobi preconditioners (see
   cloth_preconditioner), from the filtered diagonal block M_i = S A_ii S + c (I - S) of a
   vertex with count constrained directions (d: its prepared direction). */
static cloth_result cloth__filtered_block_inverse(const cloth_real *a, int32_t count, const cloth_real *di,
                                                  cloth_preconditioner kind, cloth_real *out)
{
    double s[9], as[9], sa[9], m[9], inv[9], b[9], c;
    int r, k, e;
    if (count == 3) {
        for (e = 0; e < 9; ++e) out[e] = 0;
        return CLOTH_SUCCESS;
    }
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) {
            double dr = count ? (double)di[r] : 0, dk = count ? (double)di[k] : 0;
            as[3 * r + k] = 0.5 * ((double)a[3 * r + k] + (double)a[3 * k + r]);
            if (count == 0) s[3 * r + k] = r == k ? 1.0 : 0.0;
            else if (count == 1) s[3 * r + k] = (r == k ? 1.0 : 0.0) - dr * dk;
            else s[3 * r + k] = dr * dk;
        }
    /* m = S as S, then c = trace / free count, m += c (I - S) */
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) sa[3 * r + k] = s[3 * r] * as[k] + s[3 * r + 1] * as[3 + k] + s[3 * r + 2] * as[6 + k];
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) m[3 * r + k] = sa[3 * r] * s[k] + sa[3 * r + 1] * s[3 + k] + sa[3 * r + 2] * s[6 + k];
    c = (m[0] + m[4] + m[8]) / (double)(3 - count);
    if (!(c > 0)) return CLOTH_ERROR_NOT_POSITIVE_DEFINITE;
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) m[3 * r + k] += c * ((r == k ? 1.0 : 0.0) - s[3 * r + k]);
    if (kind == CLOTH_PRECONDITIONER_JACOBI) {
        for (e = 0; e < 9; ++e) inv[e] = 0;
        for (r = 0; r < 3; ++r) {
            if (!(m[4 * r] > 0)) return CLOTH_ERROR_NOT_POSITIVE_DEFINITE;
            inv[4 * r] = 1 / m[4 * r];
        }
    } else if (!cloth__spd_inverse3(m, inv)) {
        return CLOTH_ERROR_NOT_POSITIVE_DEFINITE;
    }
    /* b = S inv S, made exactly symmetric */
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) sa[3 * r + k] = s[3 * r] * inv[k] + s[3 * r + 1] * inv[3 + k] + s[3 * r + 2] * inv[6 + k];
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) b[3 * r + k] = sa[3 * r] * s[k] + sa[3 * r + 1] * s[3 + k] + sa[3 * r + 2] * s[6 + k];
    for (r = 0; r < 3; ++r)
        for (k = 0; k < 3; ++k) out[3 * r + k] = (cloth_real)(0.5 * (b[3 * r + k] + b[3 * k + r]));
    return CLOTH_SUCCESS;
}

/* pre[9i..9i+8] = S_i P_i^-1 S_i for the Jacobi and block-Jacobi preconditioners, from the
   filtered diagonal blocks (cloth__filtered_block_inverse). */
static cloth_result cloth__pcg_build_preconditioner(const cloth_block_matrix *matrix, const int32_t *constrained,
                                                    const cloth_real *d, cloth_preconditioner kind, cloth_real *pre)
{
    int32_t i;
    if (kind == CLOTH_PRECONDITIONER_NONE) return CLOTH_SUCCESS;
    for (i = 0; i < matrix->vertex_count; ++i) {
        cloth_result result = cloth__filtered_block_inverse(matrix->value + 9 * (size_t)matrix->diagonal[i],
                                                            constrained ? constrained[i] : 0, d + 3 * (size_t)i, kind,
                                                            pre + 9 * (size_t)i);
        if (result != CLOTH_SUCCESS) return result;
    }
    return CLOTH_SUCCESS;
}

/* s = P^-1 r. */
static void cloth__pcg_precondition(int32_t n, cloth_preconditioner kind, const cloth_real *pre, const cloth_real *r,
                                    cloth_real *s)
{
    size_t i, count = (size_t)n;
    if (kind == CLOTH_PRECONDITIONER_NONE) {
        for (i = 0; i < 3 * count; ++i) s[i] = r[i];
        return;
    }
    for (i = 0; i < count; ++i) {
        const cloth_real *m = pre + 9 * i, *ri = r + 3 * i;
        cloth_real *si = s + 3 * i;
        si[0] = m[0] * ri[0] + m[1] * ri[1] + m[2] * ri[2];
        si[1] = m[3] * ri[0] + m[4] * ri[1] + m[5] * ri[2];
        si[2] = m[6] * ri[0] + m[7] * ri[1] + m[8] * ri[2];
    }
}

/* x = S x + (I - S) z: keep the free part, impose the constrained one. */
static void cloth__pcg_impose(int32_t n, const int32_t *constrained, const cloth_real *d, const cloth_real *z,
                              cloth_real *x)
{
    static const cloth_real zero[3] = { 0, 0, 0 };
    int32_t i;
    if (!constrained) return;
    for (i = 0; i < n; ++i) {
        size_t o = 3 * (size_t)i;
        cloth_real c[3];
        cloth__filter_apply(constrained[i], d + o, x + o);
        cloth__filter_complement(constrained[i], d + o, z ? z + o : zero, c);
        x[o] += c[0];
        x[o + 1] += c[1];
        x[o + 2] += c[2];
    }
}

/* ---- the solver's loops over fixed chunks of rows ---- */

static int32_t cloth__chunk_count(int32_t n) { return (n + CLOTH__CHUNK - 1) / CLOTH__CHUNK; }

/* Rows *begin .. *end - 1 of chunk `chunk` of n rows. */
static void cloth__chunk_rows(int32_t n, int32_t chunk, int32_t *begin, int32_t *end)
{
    *begin = chunk * CLOTH__CHUNK;
    *end = *begin + CLOTH__CHUNK < n ? *begin + CLOTH__CHUNK : n;
}

/* What the chunk tasks of one solve read and write. */
typedef struct cloth__pcg_job {
    const cloth_block_matrix *matrix;
    const int32_t *constrained;
    const cloth_real *d, *pre, *b;
    cloth_preconditioner kind;
    cloth_real *x, *r, *s, *p, *q;
    const cloth_real *u, *v;      /* the dot task's operands */
    cloth_real alpha, beta;
    int32_t n;
    double *partial;              /* one sum per chunk */
    float *fb;                    /* multigrid: level 0's right-hand side (4 floats a row), loaded by the update */
    const float *fx;              /* multigrid: level 0's solution, stored into s by the store task */
} cloth__pcg_job;

/* The chunk sums, added in order. */
static double cloth__chunk_total(const cloth__pcg_job *job)
{
    double total = 0;
    int32_t c, count = cloth__chunk_count(job->n);
    for (c = 0; c < count; ++c) total += job->partial[c];
    return total;
}

/* q = S A p and p^T q on a chunk. */
static void cloth__pcg_task_product(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    double pq = 0;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        size_t o = 3 * (size_t)i;
        cloth__block_row_product(job->matrix, i, job->p, job->q + o);
        if (job->constrained) cloth__filter_apply(job->constrained[i], job->d + o, job->q + o);
        pq += (double)job->p[o] * (double)job->q[o];
        pq += (double)job->p[o + 1] * (double)job->q[o + 1];
        pq += (double)job->p[o + 2] * (double)job->q[o + 2];
    }
    job->partial[part] = pq;
}

/* r = S (b - A x) and |r|^2 on a chunk. */
static void cloth__pcg_task_residual(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    double rr = 0;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        size_t o = 3 * (size_t)i;
        cloth_real t[3];
        cloth__block_row_product(job->matrix, i, job->u, t);
        job->r[o] = job->b[o] - t[0];
        job->r[o + 1] = job->b[o + 1] - t[1];
        job->r[o + 2] = job->b[o + 2] - t[2];
        if (job->constrained) cloth__filter_apply(job->constrained[i], job->d + o, job->r + o);
        rr += (double)job->r[o] * (double)job->r[o] + (double)job->r[o + 1] * (double)job->r[o + 1] +
              (double)job->r[o + 2] * (double)job->r[o + 2];
    }
    job->partial[part] = rr;
}

/* u . v on a chunk. */
static void cloth__pcg_task_dot(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    int32_t begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    job->partial[part] = cloth__dot_long(job->u + 3 * (size_t)begin, job->v + 3 * (size_t)begin, 3 * (size_t)(end - begin));
}

/* x += alpha p, r -= alpha q, s = P^-1 r ((block-)Jacobi or none) and r^T s, on a chunk. */
static void cloth__pcg_task_update(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    const cloth_real alpha = job->alpha;
    double rs = 0;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        size_t o = 3 * (size_t)i;
        cloth_real *ri = job->r + o, *si = job->s + o;
        int e;
        for (e = 0; e < 3; ++e) {
            job->x[o + e] += alpha * job->p[o + e];
            ri[e] -= alpha * job->q[o + e];
        }
        if (job->kind == CLOTH_PRECONDITIONER_NONE) {
            si[0] = ri[0];
            si[1] = ri[1];
            si[2] = ri[2];
        } else {
            const cloth_real *m = job->pre + 9 * (size_t)i;
            si[0] = m[0] * ri[0] + m[1] * ri[1] + m[2] * ri[2];
            si[1] = m[3] * ri[0] + m[4] * ri[1] + m[5] * ri[2];
            si[2] = m[6] * ri[0] + m[7] * ri[1] + m[8] * ri[2];
        }
        rs += (double)ri[0] * (double)si[0];
        rs += (double)ri[1] * (double)si[1];
        rs += (double)ri[2] * (double)si[2];
    }
    job->partial[part] = rs;
}

/* Multigrid: x += alpha p, r -= alpha q, and the V-cycle's right-hand side fb = r in single
   precision, on a chunk (the pass the V-cycle's load would make again). */
static void cloth__pcg_task_update_load(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    const cloth_real alpha = job->alpha;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        size_t o = 3 * (size_t)i;
        int e;
        for (e = 0; e < 3; ++e) {
            job->x[o + e] += alpha * job->p[o + e];
            job->r[o + e] -= alpha * job->q[o + e];
            job->fb[4 * (size_t)i + (size_t)e] = (float)job->r[o + e];
        }
    }
}

/* Multigrid: s = fx in double (the V-cycle's store) and the chunk's r^T s, as the dot task
   sums it. */
static void cloth__pcg_task_store_dot(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        int e;
        for (e = 0; e < 3; ++e) job->s[3 * (size_t)i + (size_t)e] = (cloth_real)job->fx[4 * (size_t)i + (size_t)e];
    }
    job->partial[part] = cloth__dot_long(job->r + 3 * (size_t)begin, job->s + 3 * (size_t)begin, 3 * (size_t)(end - begin));
}

/* p = S (s + beta p) on a chunk. */
static void cloth__pcg_task_direction(void *context, int32_t part)
{
    const cloth__pcg_job *job = (const cloth__pcg_job *)context;
    const cloth_real beta = job->beta;
    int32_t i, begin, end;
    cloth__chunk_rows(job->n, part, &begin, &end);
    for (i = begin; i < end; ++i) {
        size_t o = 3 * (size_t)i;
        job->p[o] = job->s[o] + beta * job->p[o];
        job->p[o + 1] = job->s[o + 1] + beta * job->p[o + 1];
        job->p[o + 2] = job->s[o + 2] + beta * job->p[o + 2];
        if (job->constrained) cloth__filter_apply(job->constrained[i], job->d + o, job->p + o);
    }
}

/* u . v over the job's vectors, summed per chunk. */
static double cloth__pcg_dot(cloth__pool *pool, cloth__pcg_job *job, const cloth_real *u, const cloth_real *v)
{
    job->u = u;
    job->v = v;
    cloth__pool_run(pool, cloth__chunk_count(job->n), cloth__pcg_task_dot, job);
    return cloth__chunk_total(job);
}

/* r = S (b - A x); returns |r|^2, summed per chunk. */
static double cloth__pcg_residual(cloth__pool *pool, cloth__pcg_job *job, const cloth_real *x)
{
    job->u = x;
    cloth__pool_run(pool, cloth__chunk_count(job->n), cloth__pcg_task_residual, job);
    return cloth__chunk_total(job);
}

/* ---- multigrid ------------------------------------------------------------------------ */

/* Level 0's Gauss-Seidel sweeps in parts that run side by side (options.sweep_parts, see
   cloth__mg_sweep_order): automatic, one part per CLOTH__MG_PART_ROWS rows; asked for, at
   least CLOTH__MG_MIN_PART_ROWS rows a part. */
#define CLOTH__MG_MAX_PARTS CLOTH_MULTIGRID_MAX_SWEEP_PARTS
#define CLOTH__MG_PART_ROWS 1024
#define CLOTH__MG_MIN_PART_ROWS 256

/* One level of the hierarchy. Level 0's operator is the caller's matrix under the filter;
   the other levels own theirs. The transfer fields lead to the next coarser level and are
   absent on the coarsest. */
typedef struct cloth__mg_level {
    int32_t n;                    /* nodes */
    cloth_block_matrix a;         /* levels >= 1: the Galerkin operator */
    int32_t *mirror;              /* per block of the operator: the index of its transpose */
    cloth_real *dinv;             /* levels >= 1: the smoother's 3x3 (pseudo-)inverse diagonal blocks */
    float *x, *b, *t;             /* the V-cycle's correction, right-hand side and residual scratch */
    cloth_real *nullspace;        /* levels >= 1: 9 per node, the 3 near-null-space columns (row-major) */
    double omega_smoother;        /* Jacobi's weight 4/3 / rho */
    /* towards level + 1 */
    int32_t coarse_n;             /* nodes of level + 1; 0 on the coarsest */
    int32_t *aggregate;           /* n: the coarse node of each node, -1 for none */
    int32_t *member_start, *member; /* the nodes of each aggregate, increasing */
    int32_t max_members;
    unsigned char *strong;        /* per block: 1 for a strong off-diagonal coupling */
    cloth_real *tentative;        /* 9 per node: its block of T */
    int32_t p_count, ap_count;
    int32_t *p_start, *p_column, *p_row; /* P: n x coarse_n blocks, CSR */
    int32_t p_row_max;            /* the most blocks in a row of P */
    float *p_float;               /* P, padded rows: the V-cycle's and the Galerkin products' */
    int32_t *pt_start, *pt_block; /* P's blocks by column, rows increasing */
    int32_t *ap_start, *ap_column; /* A P, CSR */
    float *ap_float;              /* A P's blocks, padded rows (CLOTH__MG_B floats each) */
    float *ac_float;              /* the next level's operator as the products sum it, padded */
    /* the V-cycle's single-precision copy of the operator (see cloth__mg_split_alloc); absent
       on a coarsest level that is factored */
    int32_t *lower_start, *lower_column;
    int32_t *lower_source;        /* per lower block: its block in the operator */
    float *lower, *diagonal_block, *smoother;
    /* the smoother's sweep order (see cloth__mg_sweep_order): the rows of part q at positions
       part_end[q] .. part_end[q + 1] - 1 of order, the separator rows after part_end[parts];
       order NULL: the rows in turn, one part */
    int32_t parts;
    int32_t *order;
    int32_t part_end[CLOTH__MG_MAX_PARTS + 1];
} cloth__mg_level;

struct cloth__multigrid {
    cloth_multigrid_options options;
    cloth_allocator allocator;
    int32_t level_count, vertex_count, block_count;
    int32_t *pattern_start, *pattern_column; /* a copy of the fine pattern, to check matrices against */
    int ready;                    /* the values of the last numeric phase are complete */
    size_t bytes;
    cloth__mg_level level[CLOTH_MULTIGRID_MAX_LEVELS];
    int32_t dense_n;              /* unknowns of the dense coarsest factor; 0: the coarsest is smoothed */
    double *dense, *dense_rhs;    /* (dense_n)^2, lower triangle; dense_n */
    double *qr;                   /* 9 qr_capacity per part: tentative-prolongator scratch */
    size_t qr_capacity;
    cloth_real *p_rows;           /* 9 p_rows_capacity blocks per part: a row of P as it is
                                     summed in double, before its single-precision copy */
    size_t p_rows_capacity;
    int32_t *marker, *stamp;      /* vertex_count each: pattern and product scratch */
    cloth_real *scratch;          /* 9 vertex_count */
    double *partial;              /* 2 per chunk of level 0's rows: the numeric phase's sums */
    /* the numeric phase's row-parallel products: parts (the workspace's threads at setup, at
       least 1), each with its own marker (part 0: marker), run on pool (the workspace's) */
    int32_t part_count;
    int32_t *part_marker;         /* (part_count - 1) vertex_count */
    struct cloth__pool *pool;
};

/* The unit roundoff of cloth_real. */
#define CLOTH__REAL_EPS (sizeof(cloth_real) < sizeof(double) ? 1.1920928955078125e-7 : 2.220446049250313e-16)

CLOTH_API cloth_multigrid_options cloth_default_multigrid_options(void)
{
    cloth_multigrid_options o;
    o.strength_threshold = (cloth_real)0.04;
    o.prolongator_damping = (cloth_real)(4.0 / 3.0);
    o.coarse_size = 32;
    o.max_levels = 10;
    o.smoothing_steps = 1;
    o.smoother = CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL;
    o.sweep_parts = 1;
    return o;
}

static int cloth__mg_options_valid(const cloth_multigrid_options *o)
{
    return cloth__is_finite(o->strength_threshold) && o->strength_threshold >= 0 && o->strength_threshold < 1 &&
           cloth__is_finite(o->prolongator_damping) && o->prolongator_damping >= 0 && o->prolongator_damping <= 2 &&
           o->coarse_size >= 1 && o->max_levels >= 1 && o->max_levels <= CLOTH_MULTIGRID_MAX_LEVELS &&
           o->smoothing_steps >= 1 && o->sweep_parts >= 0 && o->sweep_parts <= CLOTH_MULTIGRID_MAX_SWEEP_PARTS &&
           (o->smoother == CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL || o->smoother == CLOTH_MULTIGRID_SMOOTHER_JACOBI);
}

static void cloth__mg_free(struct cloth__multigrid *mg)
{
    cloth_allocator a;
    int l;
    if (!mg) return;
    a = mg->allocator;
    for (l = 0; l < CLOTH_MULTIGRID_MAX_LEVELS; ++l) {
        cloth__mg_level *v = &mg->level[l];
        void *arrays[40];
        int k, count = 0;
        arrays[count++] = v->a.row_start; arrays[count++] = v->a.column; arrays[count++] = v->a.diagonal;
        arrays[count++] = v->a.value; arrays[count++] = v->mirror; arrays[count++] = v->dinv;
        arrays[count++] = v->x; arrays[count++] = v->b; arrays[count++] = v->t; arrays[count++] = v->nullspace;
        arrays[count++] = v->aggregate; arrays[count++] = v->member_start; arrays[count++] = v->member;
        arrays[count++] = v->strong; arrays[count++] = v->tentative; arrays[count++] = v->p_start;
        arrays[count++] = v->p_column; arrays[count++] = v->p_row;
        arrays[count++] = v->pt_start; arrays[count++] = v->pt_block; arrays[count++] = v->ap_start;
        arrays[count++] = v->ap_column; arrays[count++] = v->ap_float; arrays[count++] = v->ac_float;
        arrays[count++] = v->lower_start; arrays[count++] = v->lower_column; arrays[count++] = v->lower;
        arrays[count++] = v->diagonal_block; arrays[count++] = v->smoother; arrays[count++] = v->p_float;
        arrays[count++] = v->lower_source; arrays[count++] = v->order;
        for (k = 0; k < count; ++k) cloth__free(&a, arrays[k]);
    }
    cloth__free(&a, mg->dense);
    cloth__free(&a, mg->dense_rhs);
    cloth__free(&a, mg->qr);
    cloth__free(&a, mg->p_rows);
    cloth__free(&a, mg->marker);
    cloth__free(&a, mg->part_marker);
    cloth__free(&a, mg->stamp);
    cloth__free(&a, mg->scratch);
    cloth__free(&a, mg->partial);
    cloth__free(&a, mg->pattern_start);
    cloth__free(&a, mg->pattern_column);
    cloth__free(&a, mg);
}

/* count elements of size bytes from the hierarchy's allocator, counted in mg->bytes; NULL (and
   *ok = 0) on failure. */
static void *cloth__mg_alloc(struct cloth__multigrid *mg, size_t count, size_t size, int *ok)
{
    void *p;
    if (!*ok) return NULL;
    p = cloth__alloc_array(&mg->allocator, count, size);
    if (!p) { *ok = 0; return NULL; }
    mg->bytes += count * size;
    return p;
}

/* ---- 3x3 block arithmetic, row-major ---- */

/* out = a b */
static void cloth__m3_mul(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    int r;
    for (r = 0; r < 3; ++r) {
        const cloth_real a0 = a[3 * r], a1 = a[3 * r + 1], a2 = a[3 * r + 2];
        out[3 * r] = a0 * b[0] + a1 * b[3] + a2 * b[6];
        out[3 * r + 1] = a0 * b[1] + a1 * b[4] + a2 * b[7];
        out[3 * r + 2] = a0 * b[2] + a1 * b[5] + a2 * b[8];
    }
}

/* out += a b */
static void cloth__m3_mul_add(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    int r;
    for (r = 0; r < 3; ++r) {
        const cloth_real a0 = a[3 * r], a1 = a[3 * r + 1], a2 = a[3 * r + 2];
        out[3 * r] += a0 * b[0] + a1 * b[3] + a2 * b[6];
        out[3 * r + 1] += a0 * b[1] + a1 * b[4] + a2 * b[7];
        out[3 * r + 2] += a0 * b[2] + a1 * b[5] + a2 * b[8];
    }
}

/* out += a^T b */
static void cloth__m3_tmul_add(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    int r;
    for (r = 0; r < 3; ++r) {
        const cloth_real a0 = a[r], a1 = a[3 + r], a2 = a[6 + r];
        out[3 * r] += a0 * b[0] + a1 * b[3] + a2 * b[6];
        out[3 * r + 1] += a0 * b[1] + a1 * b[4] + a2 * b[7];
        out[3 * r + 2] += a0 * b[2] + a1 * b[5] + a2 * b[8];
    }
}

/* out = m v. */
static void cloth__m3_apply(const cloth_real *m, const cloth_real *v, cloth_real *out)
{
    out[0] = m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
    out[1] = m[3] * v[0] + m[4] * v[1] + m[5] * v[2];
    out[2] = m[6] * v[0] + m[7] * v[1] + m[8] * v[2];
}

/* The largest absolute row sum. */
static double cloth__m3_norm_inf(const cloth_real *m)
{
    double best = 0;
    int r;
    for (r = 0; r < 3; ++r) {
        double s = fabs((double)m[3 * r]) + fabs((double)m[3 * r + 1]) + fabs((double)m[3 * r + 2]);
        if (s > best) best = s;
    }
    return best;
}

static double cloth__m3_frobenius2(const cloth_real *m)
{
    double s = 0;
    int e;
    for (e = 0; e < 9; ++e) s += (double)m[e] * (double)m[e];
    return s;
}

/* The filter S of a vertex in the form of cloth__pcg_prepare_filter, as a 3x3 matrix. */
static void cloth__filter_matrix(int32_t count, const cloth_real *d, double *s)
{
    int r, c;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) {
            double id = r == c ? 1.0 : 0.0;
            if (count == 0) s[3 * r + c] = id;
            else if (count == 1) s[3 * r + c] = id - (double)d[r] * (double)d[c];
            else if (count == 2) s[3 * r + c] = (double)d[r] * (double)d[c];
            else s[3 * r + c] = 0;
        }
}

/* ---- dense Cholesky with dropped pivots ---- */

/* In-place Cholesky factor of the symmetric positive semidefinite n x n row-major a (lower
   triangle read and written). A pivot at most tol times its column's diagonal entry (or a
   diagonal entry that is not positive) drops the column: its entries in L are set to 0, so
   the factor is that of the submatrix of the kept unknowns, and solves give 0 for a dropped
   unknown. Returns the number of dropped columns. */
static int32_t cloth__dense_cholesky_dropping(double *a, int32_t n, double tol)
{
    int32_t i, j, k, dropped = 0;
    for (j = 0; j < n; ++j) {
        double *rj = a + (size_t)j * (size_t)n, ajj = rj[j], d = ajj;
        for (k = 0; k < j; ++k) d -= rj[k] * rj[k];
        if (!(ajj > 0) || !(d > tol * ajj)) {
            for (i = j; i < n; ++i) a[(size_t)i * (size_t)n + (size_t)j] = 0;
            ++dropped;
            continue;
        }
        d = sqrt(d);
        rj[j] = d;
        for (i = j + 1; i < n; ++i) {
            double *ri = a + (size_t)i * (size_t)n, s = ri[j];
            for (k = 0; k < j; ++k) s -= ri[k] * rj[k];
            ri[j] = s / d;
        }
    }
    return dropped;
}

/* x <- (L L^T)^+ x with the factor above (a dropped unknown gets 0). */
static void cloth__dense_cholesky_solve(const double *l, int32_t n, double *x)
{
    int32_t i, k;
    for (i = 0; i < n; ++i) {
        const double *ri = l + (size_t)i * (size_t)n;
        double s = x[i];
        if (ri[i] == 0) { x[i] = 0; continue; }
        for (k = 0; k < i; ++k) s -= ri[k] * x[k];
        x[i] = s / ri[i];
    }
    for (i = n - 1; i >= 0; --i) {
        double s = x[i], lii = l[(size_t)i * (size_t)n + (size_t)i];
        if (lii == 0) { x[i] = 0; continue; }
        for (k = i + 1; k < n; ++k) s -= l[(size_t)k * (size_t)n + (size_t)i] * x[k];
        x[i] = s / lii;
    }
}

/* inv = the (pseudo-)inverse of a symmetric positive semidefinite 3x3 block through the
   dropping Cholesky factor: exactly symmetric, zero on dropped unknowns. */
static void cloth__psd_inverse3(const cloth_real *m, cloth_real *inv)
{
    double l[9], col[3], out[9];
    int r, c;
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) l[3 * r + c] = 0.5 * ((double)m[3 * r + c] + (double)m[3 * c + r]);
    cloth__dense_cholesky_dropping(l, 3, 64 * CLOTH__REAL_EPS);
    for (c = 0; c < 3; ++c) {
        col[0] = col[1] = col[2] = 0;
        col[c] = 1;
        cloth__dense_cholesky_solve(l, 3, col);
        for (r = 0; r < 3; ++r) out[3 * r + c] = col[r];
    }
    for (r = 0; r < 3; ++r)
        for (c = 0; c < 3; ++c) inv[3 * r + c] = (cloth_real)(0.5 * (out[3 * r + c] + out[3 * c + r]));
}

/* ---- the V-cycle ---- */

/* The V-cycle's vectors hold CLOTH__MG_W = 4 floats per node (the 3 unknowns and a zero) and
   its 3x3 blocks CLOTH__MG_B = 12 floats (3 rows of 3 values and a zero), so that each block
   operation is a few operations on 4 lanes, which compilers vectorize (SSE, NEON) from plain
   loops. Every lane's arithmetic is the scalar one, so vectorized or not the result is the
   same bits. The fourth lane of every vector stays 0. */
#define CLOTH__MG_W 4
#define CLOTH__MG_B 12

static void cloth__mg_zero_vectors(cloth__mg_level *lev)
{
    size_t k, count = CLOTH__MG_W * (size_t)lev->n;
    for (k = 0; k < count; ++k) lev->x[k] = lev->b[k] = lev->t[k] = 0;
}

/* out = the padded single-precision copy of the 3x3 block m (transposed when transpose is
   set: the product helpers below read rows as the columns of what they apply). */
static void cloth__mg_block_float(const cloth_real *m, int transpose, float *out)
{
    if (transpose) {
        out[0] = (float)m[0]; out[1] = (float)m[3]; out[2] = (float)m[6];
        out[4] = (float)m[1]; out[5] = (float)m[4]; out[6] = (float)m[7];
        out[8] = (float)m[2]; out[9] = (float)m[5]; out[10] = (float)m[8];
    } else {
        out[0] = (float)m[0]; out[1] = (float)m[1]; out[2] = (float)m[2];
        out[4] = (float)m[3]; out[5] = (float)m[4]; out[6] = (float)m[5];
        out[8] = (float)m[6]; out[9] = (float)m[7]; out[10] = (float)m[8];
    }
    out[3] = out[7] = out[11] = 0;
}

/* out += s0 row0 + s1 row1 + s2 row2 over 4 lanes: m^T s for a padded block m. A macro with
   the lanes written out, every load before any store: compilers then vectorize it (a loop over
   4 lanes, or a function, is not reliably unrolled or inlined at -O2). */
#define CLOTH__MG_ROWS_ADD(m, s0, s1, s2, out)                                                   \
    do {                                                                                         \
        const float *m_ = (m);                                                                   \
        float *out_ = (out);                                                                     \
        const float a_ = (s0), b_ = (s1), c_ = (s2);                                             \
        const float t0_ = m_[0] * a_ + m_[4] * b_ + m_[8] * c_, t1_ = m_[1] * a_ + m_[5] * b_ + m_[9] * c_; \
        const float t2_ = m_[2] * a_ + m_[6] * b_ + m_[10] * c_, t3_ = m_[3] * a_ + m_[7] * b_ + m_[11] * c_; \
        out_[0] += t0_;                                                                          \
        out_[1] += t1_;                                                                          \
        out_[2] += t2_;                                                                          \
        out_[3] += t3_;                                                                          \
    } while (0)

/* The smoother's sweep order on level 0: the rows split into parts of consecutive indices,
   the rows of a part that couple with a row of a later part set apart as separators, so that
   the parts' remaining rows couple with no other part's. A Gauss-Seidel sweep in the order
   "part 0, part 1, ..., then the separators" is then an exact sweep whose parts run side by
   side: no row of a part reads or writes a row of another. The number of parts follows from
   options.sweep_parts and the rows alone, never from the threads, so the results are the same
   bits on any number of threads. On a grid's rows (a strip of rows per part) the separators
   are the two rows at each cut; with vertices in no spatial order they would be most rows,
   and one part is kept instead. */
static cloth_result cloth__mg_sweep_order(struct cloth__multigrid *mg, cloth__mg_level *lev, const cloth_block_matrix *A)
{
    const int32_t n = A->vertex_count, asked = mg->options.sweep_parts;
    int32_t parts = asked == 0 ? n / CLOTH__MG_PART_ROWS : asked, q, i, k, at = 0, separators = 0;
    unsigned char *cut;
    int ok = 1;
    lev->parts = 1;
    lev->order = NULL;
    if (asked >= 2 && parts > n / CLOTH__MG_MIN_PART_ROWS) parts = n / CLOTH__MG_MIN_PART_ROWS;
    if (parts > CLOTH__MG_MAX_PARTS) parts = CLOTH__MG_MAX_PARTS;
    if (parts < 2) return CLOTH_SUCCESS;
    cut = (unsigned char *)cloth__alloc_array(&mg->allocator, (size_t)n, 1);
    if (!cut) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (q = 0; q < parts; ++q) {
        const int32_t hi = (int32_t)((int64_t)n * (q + 1) / parts);
        for (i = (int32_t)((int64_t)n * q / parts); i < hi; ++i) {
            cut[i] = 0;
            for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k)
                if (A->column[k] >= hi) cut[i] = 1;
            separators += cut[i];
        }
    }
    if (2 * separators > n) {
        cloth__free(&mg->allocator, cut);
        return CLOTH_SUCCESS;
    }
    lev->order = (int32_t *)cloth__mg_alloc(mg, (size_t)n, sizeof(int32_t), &ok);
    if (!ok) {
        cloth__free(&mg->allocator, cut);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    lev->parts = parts;
    for (q = 0; q < parts; ++q) {
        const int32_t hi = (int32_t)((int64_t)n * (q + 1) / parts);
        lev->part_end[q] = at;
        for (i = (int32_t)((int64_t)n * q / parts); i < hi; ++i)
            if (!cut[i]) lev->order[at++] = i;
    }
    lev->part_end[parts] = at;
    for (i = 0; i < n; ++i)
        if (cut[i]) lev->order[at++] = i;
    cloth__free(&mg->allocator, cut);
    return CLOTH_SUCCESS;
}

/* The smoother's copy of a level's operator: per row its strictly lower blocks (the blocks
   of the rows before it in the sweep order: by index, unless the level has an order) and its
   diagonal block, and the smoother's inverse diagonal blocks, all in single precision. The
   strictly upper part is the transpose of the lower one (the operator is symmetric), so a
   product or a sweep reads each lower block once and uses it twice: gathered for its own row,
   scattered transposed into the row of its column. The V-cycle reads these and nothing else of
   the operator: a sixth of the bytes of the double-precision matrix read twice. (The rounding
   makes the V-cycle that of a nearby matrix: still symmetric positive definite, and CG stays
   exact, for it multiplies with the caller's matrix.) */
static cloth_result cloth__mg_split_alloc(struct cloth__multigrid *mg, cloth__mg_level *lev, const cloth_block_matrix *A)
{
    const int32_t n = A->vertex_count;
    int32_t i, k, lower = 0, *position = NULL;
    int ok = 1;
    cloth_result result = lev == mg->level ? cloth__mg_sweep_order(mg, lev, A) : CLOTH_SUCCESS;
    if (result != CLOTH_SUCCESS) return result;
    lev->lower_start = (int32_t *)cloth__mg_alloc(mg, (size_t)n + 1, sizeof(int32_t), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    if (lev->order) {
        position = (int32_t *)cloth__alloc_array(&mg->allocator, (size_t)n, sizeof(int32_t));
        if (!position) return CLOTH_ERROR_OUT_OF_MEMORY;
        for (i = 0; i < n; ++i) position[lev->order[i]] = i;
    }
#define CLOTH__MG_BEFORE(j, i) (position ? position[j] < position[i] : (j) < (i))
    lev->lower_start[0] = 0;
    for (i = 0; i < n; ++i) {
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) lower += CLOTH__MG_BEFORE(A->column[k], i);
        lev->lower_start[i + 1] = lower;
    }
    lev->lower_column = (int32_t *)cloth__mg_alloc(mg, (size_t)lower, sizeof(int32_t), &ok);
    lev->lower_source = (int32_t *)cloth__mg_alloc(mg, (size_t)lower, sizeof(int32_t), &ok);
    lev->lower = (float *)cloth__mg_alloc(mg, (size_t)lower, CLOTH__MG_B * sizeof(float), &ok);
    lev->diagonal_block = (float *)cloth__mg_alloc(mg, (size_t)n, CLOTH__MG_B * sizeof(float), &ok);
    lev->smoother = (float *)cloth__mg_alloc(mg, (size_t)n, CLOTH__MG_B * sizeof(float), &ok);
    if (ok)
        for (i = 0; i < n; ++i) {
            int32_t at = lev->lower_start[i];
            for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k)
                if (CLOTH__MG_BEFORE(A->column[k], i)) {
                    lev->lower_column[at] = A->column[k];
                    lev->lower_source[at++] = k;
                }
        }
#undef CLOTH__MG_BEFORE
    cloth__free(&mg->allocator, position);
    return ok ? CLOTH_SUCCESS : CLOTH_ERROR_OUT_OF_MEMORY;
}

/* Copy A's lower and diagonal values and the smoother blocks dinv into the single-precision
   copy. */
static void cloth__mg_split_rows(cloth__mg_level *lev, const cloth_block_matrix *A, const cloth_real *dinv, int32_t i0,
                                 int32_t i1)
{
    int32_t i, k;
    for (i = i0; i < i1; ++i) {
        for (k = lev->lower_start[i]; k < lev->lower_start[i + 1]; ++k)
            cloth__mg_block_float(A->value + 9 * (size_t)lev->lower_source[k], 0, lev->lower + CLOTH__MG_B * (size_t)k);
        cloth__mg_block_float(A->value + 9 * (size_t)A->diagonal[i], 1, lev->diagonal_block + CLOTH__MG_B * (size_t)i);
        cloth__mg_block_float(dinv + 9 * (size_t)i, 1, lev->smoother + CLOTH__MG_B * (size_t)i);
    }
}

static void cloth__mg_split_refresh(cloth__mg_level *lev, const cloth_block_matrix *A, const cloth_real *dinv)
{
    cloth__mg_split_rows(lev, A, dinv, 0, A->vertex_count);
}

/* x = M s for a block M stored transposed (cloth__mg_block_float with transpose set): the
   stored rows are M's columns. x's fourth lane is 0. */
static void cloth__mg_block_apply(const float *m, const float *s, float *x)
{
    const float s0 = s[0], s1 = s[1], s2 = s[2];
    const float t0 = m[0] * s0 + m[4] * s1 + m[8] * s2, t1 = m[1] * s0 + m[5] * s1 + m[9] * s2;
    const float t2 = m[2] * s0 + m[6] * s1 + m[10] * s2, t3 = m[3] * s0 + m[7] * s1 + m[11] * s2;
    x[0] = t0;
    x[1] = t1;
    x[2] = t2;
    x[3] = t3;
}

/* s -= sum over row i's strictly lower blocks of L_ij x_j: per output row a 4-lane partial
   sum over the blocks (lane c holds the products with x_j[c]), reduced at the end. */
static void cloth__mg_gather_lower(const cloth__mg_level *lev, int32_t i, const float *x, float *s)
{
    float u[4] = { 0, 0, 0, 0 }, v[4] = { 0, 0, 0, 0 }, w[4] = { 0, 0, 0, 0 };
    const int32_t end = lev->lower_start[i + 1];
    int32_t k;
    int c;
    for (k = lev->lower_start[i]; k < end; ++k) {
        const float *a = lev->lower + CLOTH__MG_B * (size_t)k, *xj = x + CLOTH__MG_W * (size_t)lev->lower_column[k];
        for (c = 0; c < 4; ++c) {
            u[c] += a[c] * xj[c];
            v[c] += a[4 + c] * xj[c];
            w[c] += a[8 + c] * xj[c];
        }
    }
    s[0] -= (u[0] + u[1]) + (u[2] + u[3]);
    s[1] -= (v[0] + v[1]) + (v[2] + v[3]);
    s[2] -= (w[0] + w[1]) + (w[2] + w[3]);
}

/* acc_j += sign L_ij^T xi over row i's strictly lower blocks: the transposed (upper) blocks
   (j, i) applied to x_i, added into the rows j < i. */
static void cloth__mg_scatter_lower(const cloth__mg_level *lev, int32_t i, const float *xi, float sign, float *acc)
{
    const float x0 = sign * xi[0], x1 = sign * xi[1], x2 = sign * xi[2];
    const int32_t end = lev->lower_start[i + 1];
    int32_t k;
    for (k = lev->lower_start[i]; k < end; ++k)
        CLOTH__MG_ROWS_ADD(lev->lower + CLOTH__MG_B * (size_t)k, x0, x1, x2, acc + CLOTH__MG_W * (size_t)lev->lower_column[k]);
}

/* v <- S v in single precision (see cloth__filter_apply). */
static void cloth__filter_apply_float(int32_t count, const cloth_real *dr, float *v)
{
    float d[3], t;
    if (count == 0) return;
    if (count == 3) { v[0] = v[1] = v[2] = 0; return; }
    d[0] = (float)dr[0];
    d[1] = (float)dr[1];
    d[2] = (float)dr[2];
    t = d[0] * v[0] + d[1] * v[1] + d[2] * v[2];
    if (count == 1) {
        v[0] -= t * d[0];
        v[1] -= t * d[1];
        v[2] -= t * d[2];
    } else {
        v[0] = t * d[0];
        v[1] = t * d[1];
        v[2] = t * d[2];
    }
}

/* The sweeps and products of the V-cycle, row by row in the level's sweep order ("before"
   and "after" below are in that order; the lower blocks of a row are those of the rows before
   it). Each runs over the parts side by side (on the pool), then over the separators, each
   row's sums in a fixed order: the same bits on any number of threads. The operations:
     forward from zero   x_i = D_i^+ (b_i - sum_{j before i} A_ij x_j), a forward Gauss-Seidel
                         sweep from x = 0, and into acc the residual it leaves,
                         acc_j = -sum_{i after j} A_ji x_i (row j's upper blocks against the
                         new x: the rest of the row's residual is zero by construction);
     forward             x_i = D_i^+ (b_i - acc_i - sum_{j before i} A_ij x_j) with acc = U x
                         of the old x made first (the upper blocks meet the old x_j);
     backward            the same in reverse order, the upper blocks meeting the x_j already
                         updated: their sum scattered into acc (zeroed first) as rows finish;
     residual            acc = b - A x (acc holds b first);
     upper               acc += U x, the strictly upper part (the lower blocks transposed). */
enum { CLOTH__MG_FORWARD_ZERO, CLOTH__MG_FORWARD, CLOTH__MG_BACKWARD, CLOTH__MG_RESIDUAL, CLOTH__MG_UPPER };

typedef struct cloth__mg_sweep {
    const cloth__mg_level *lev;
    int op;
    const float *b;
    float *x, *acc;
} cloth__mg_sweep;

/* The operation on the rows at positions p0 .. p1 - 1 of the sweep order (backward: from
   p1 - 1 down); a loop per operation, the row in the sweep order through CLOTH__MG_ROW. */
static void cloth__mg_sweep_rows(const cloth__mg_sweep *job, int32_t p0, int32_t p1)
{
    const cloth__mg_level *lev = job->lev;
    const int32_t *order = lev->order;
    const float *b = job->b;
    float *x = job->x, *acc = job->acc;
    int32_t p, i;
    size_t o;
    float s[4];
    int c;
#define CLOTH__MG_ROW(p) (i = order ? order[p] : (p), o = CLOTH__MG_W * (size_t)i)
    switch (job->op) {
    case CLOTH__MG_FORWARD_ZERO:
        for (p = p0; p < p1; ++p) {
            CLOTH__MG_ROW(p);
            s[0] = b[o];
            s[1] = b[o + 1];
            s[2] = b[o + 2];
            cloth__mg_gather_lower(lev, i, x, s);
            cloth__mg_block_apply(lev->smoother + CLOTH__MG_B * (size_t)i, s, x + o);
            cloth__mg_scatter_lower(lev, i, x + o, -1, acc);
        }
        break;
    case CLOTH__MG_FORWARD:
    case CLOTH__MG_BACKWARD:
        for (p = p0; p < p1; ++p) {
            CLOTH__MG_ROW(job->op == CLOTH__MG_BACKWARD ? p0 + p1 - 1 - p : p);
            s[0] = b[o] - acc[o];
            s[1] = b[o + 1] - acc[o + 1];
            s[2] = b[o + 2] - acc[o + 2];
            cloth__mg_gather_lower(lev, i, x, s);
            cloth__mg_block_apply(lev->smoother + CLOTH__MG_B * (size_t)i, s, x + o);
            if (job->op == CLOTH__MG_BACKWARD) cloth__mg_scatter_lower(lev, i, x + o, 1, acc);
        }
        break;
    case CLOTH__MG_RESIDUAL:
        for (p = p0; p < p1; ++p) {
            CLOTH__MG_ROW(p);
            cloth__mg_block_apply(lev->diagonal_block + CLOTH__MG_B * (size_t)i, x + o, s);
            for (c = 0; c < 4; ++c) acc[o + c] -= s[c];
            cloth__mg_gather_lower(lev, i, x, acc + o);
            cloth__mg_scatter_lower(lev, i, x + o, -1, acc);
        }
        break;
    default: /* CLOTH__MG_UPPER */
        for (p = p0; p < p1; ++p) {
            CLOTH__MG_ROW(p);
            cloth__mg_scatter_lower(lev, i, x + o, 1, acc);
        }
        break;
    }
#undef CLOTH__MG_ROW
}

static void cloth__mg_sweep_task(void *context, int32_t part)
{
    const cloth__mg_sweep *job = (const cloth__mg_sweep *)context;
    cloth__mg_sweep_rows(job, job->lev->part_end[part], job->lev->part_end[part + 1]);
}

/* One operation over a level: the parts side by side, then the separators (backward: the
   separators first). acc is prepared by the caller. */
static void cloth__mg_sweep_run(struct cloth__pool *pool, const cloth__mg_level *lev, int op, const float *b, float *x,
                                float *acc)
{
    cloth__mg_sweep job;
    job.lev = lev;
    job.op = op;
    job.b = b;
    job.x = x;
    job.acc = acc;
    if (!lev->order) {
        cloth__mg_sweep_rows(&job, 0, lev->n);
        return;
    }
    if (op == CLOTH__MG_BACKWARD) cloth__mg_sweep_rows(&job, lev->part_end[lev->parts], lev->n);
    cloth__pool_run(pool, lev->parts, cloth__mg_sweep_task, &job);
    if (op != CLOTH__MG_BACKWARD) cloth__mg_sweep_rows(&job, lev->part_end[lev->parts], lev->n);
}

/* One Gauss-Seidel sweep, forward from x = 0 (the residual it leaves in acc), forward from x
   or backward (acc: scratch). */
static void cloth__mg_gs_sweep(struct cloth__pool *pool, const cloth__mg_level *lev, const float *b, float *x, int op,
                               float *acc)
{
    int32_t k;
    for (k = 0; k < CLOTH__MG_W * lev->n; ++k) acc[k] = 0;
    if (op == CLOTH__MG_FORWARD) cloth__mg_sweep_run(pool, lev, CLOTH__MG_UPPER, b, x, acc);
    cloth__mg_sweep_run(pool, lev, op, b, x, acc);
}

/* res = b - A x. */
static void cloth__mg_residual(struct cloth__pool *pool, const cloth__mg_level *lev, const float *b, float *x, float *res)
{
    int32_t k;
    for (k = 0; k < CLOTH__MG_W * lev->n; ++k) res[k] = b[k];
    cloth__mg_sweep_run(pool, lev, CLOTH__MG_RESIDUAL, b, x, res);
}

/* One damped Jacobi sweep x += omega D^+ (b - A x); from_zero: x = omega D^+ b. t: scratch. */
static void cloth__mg_jacobi(struct cloth__pool *pool, const cloth__mg_level *lev, const float *b, float *x, float *t,
                             int from_zero)
{
    const float w = (float)lev->omega_smoother;
    int32_t i;
    int c;
    if (!from_zero) cloth__mg_residual(pool, lev, b, x, t);
    for (i = 0; i < lev->n; ++i) {
        size_t o = CLOTH__MG_W * (size_t)i;
        float y[4];
        cloth__mg_block_apply(lev->smoother + CLOTH__MG_B * (size_t)i, from_zero ? b + o : t + o, y);
        if (from_zero)
            for (c = 0; c < 4; ++c) x[o + c] = w * y[c];
        else
            for (c = 0; c < 4; ++c) x[o + c] += w * y[c];
    }
}

/* The V-cycle's transfers between levels and precisions, row by row: every row's result is
   summed in a fixed order whichever rows a part holds, so the pool may split the rows in any
   way (the same bits on any number of threads). The operations:
     load       b = r in single precision (level 0);
     filter     res_i = S_i res_i on the constrained rows (level 0);
     restrict   bc = P^T res, each coarse row gathered over P's blocks of its column, fine
                rows increasing (pt_start, pt_block): the order of a scatter by fine rows;
     prolong    x += S P xc (S: the filter, on level 0);
     store      s = x in double (level 0). */
enum { CLOTH__MG_LOAD, CLOTH__MG_FILTER, CLOTH__MG_RESTRICT, CLOTH__MG_PROLONG, CLOTH__MG_STORE };

typedef struct cloth__mg_transfer {
    const cloth__mg_level *lev;
    int op;
    int32_t parts;
    const int32_t *constrained;   /* level 0's filter, or NULL */
    const cloth_real *d, *r;
    cloth_real *s;
    float *fine, *coarse;         /* the level's vector and the next level's */
} cloth__mg_transfer;

static void cloth__mg_transfer_task(void *context, int32_t part)
{
    const cloth__mg_transfer *job = (const cloth__mg_transfer *)context;
    const cloth__mg_level *lev = job->lev;
    int32_t i0, i1, i, k;
    int e;
    cloth__part_rows(job->op == CLOTH__MG_RESTRICT ? lev->coarse_n : lev->n, part, job->parts, &i0, &i1);
    for (i = i0; i < i1; ++i) {
        float *fi = job->fine + CLOTH__MG_W * (size_t)i;
        switch (job->op) {
        case CLOTH__MG_LOAD:
            for (e = 0; e < 3; ++e) fi[e] = (float)job->r[3 * (size_t)i + (size_t)e];
            break;
        case CLOTH__MG_FILTER:
            if (job->constrained[i]) cloth__filter_apply_float(job->constrained[i], job->d + 3 * (size_t)i, fi);
            break;
        case CLOTH__MG_RESTRICT: {
            float u[4] = { 0, 0, 0, 0 }, *bc = job->coarse + CLOTH__MG_W * (size_t)i;
            for (k = lev->pt_start[i]; k < lev->pt_start[i + 1]; ++k) {
                const int32_t pk = lev->pt_block[k];
                const float *ri = job->fine + CLOTH__MG_W * (size_t)lev->p_row[pk];
                CLOTH__MG_ROWS_ADD(lev->p_float + CLOTH__MG_B * (size_t)pk, ri[0], ri[1], ri[2], u);
            }
            for (e = 0; e < 4; ++e) bc[e] = u[e];
            break;
        }
        case CLOTH__MG_PROLONG: {
            float u[4] = { 0, 0, 0, 0 }, v[4] = { 0, 0, 0, 0 }, w[4] = { 0, 0, 0, 0 }, c[3];
            const int32_t end = lev->p_start[i + 1];
            if (lev->p_start[i] == end) break;
            for (k = lev->p_start[i]; k < end; ++k) {
                const float *p = lev->p_float + CLOTH__MG_B * (size_t)k, *xj = job->coarse + CLOTH__MG_W * (size_t)lev->p_column[k];
                for (e = 0; e < 4; ++e) {
                    u[e] += p[e] * xj[e];
                    v[e] += p[4 + e] * xj[e];
                    w[e] += p[8 + e] * xj[e];
                }
            }
            c[0] = (u[0] + u[1]) + (u[2] + u[3]);
            c[1] = (v[0] + v[1]) + (v[2] + v[3]);
            c[2] = (w[0] + w[1]) + (w[2] + w[3]);
            if (job->constrained) cloth__filter_apply_float(job->constrained[i], job->d + 3 * (size_t)i, c);
            fi[0] += c[0];
            fi[1] += c[1];
            fi[2] += c[2];
            break;
        }
        default: /* CLOTH__MG_STORE */
            for (e = 0; e < 3; ++e) job->s[3 * (size_t)i + (size_t)e] = (cloth_real)fi[e];
            break;
        }
    }
}

/* One transfer over the rows of job->lev (its next level's for restrict), on the pool when
   job->lev is level 0 (the coarser ones are too small to pay for waking it). */
static void cloth__mg_transfer_run(struct cloth__multigrid *mg, cloth__mg_transfer *job, int op)
{
    job->op = op;
    job->parts = job->lev == mg->level ? mg->part_count : 1;
    cloth__pool_run(job->parts > 1 ? mg->pool : NULL, job->parts, cloth__mg_transfer_task, job);
}

/* One symmetric V-cycle from x = 0 on level 0's single-precision right-hand side b, its
   result in level 0's x, with level 0 under the filter (constrained, d). */
static void cloth__mg_vcycle_float(struct cloth__multigrid *mg, const int32_t *constrained, const cloth_real *d)
{
    const int32_t levels = mg->level_count, nu = mg->options.smoothing_steps;
    const int gs = mg->options.smoother == CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL;
    int32_t l, k;
    cloth__mg_transfer job;
    job.d = d;
    job.r = NULL;
    job.s = NULL;
    for (l = 0; l < levels; ++l) {
        cloth__mg_level *lev = mg->level + l;
        const int32_t *con = l ? NULL : constrained;
        if (lev->coarse_n == 0 && mg->dense_n > 0) { /* the coarsest, factored */
            int32_t e;
            for (e = 0; e < mg->dense_n; ++e) mg->dense_rhs[e] = (double)lev->b[CLOTH__MG_W * (size_t)(e / 3) + (size_t)(e % 3)];
            cloth__dense_cholesky_solve(mg->dense, mg->dense_n, mg->dense_rhs);
            for (e = 0; e < mg->dense_n; ++e) lev->x[CLOTH__MG_W * (size_t)(e / 3) + (size_t)(e % 3)] = (float)mg->dense_rhs[e];
            if (con)
                for (e = 0; e < lev->n; ++e) cloth__filter_apply_float(con[e], d + 3 * (size_t)e, lev->x + CLOTH__MG_W * (size_t)e);
            break;
        }
        if (gs) {
            cloth__mg_gs_sweep(mg->pool, lev, lev->b, lev->x, CLOTH__MG_FORWARD_ZERO, lev->t);
            for (k = 1; k < nu; ++k) cloth__mg_gs_sweep(mg->pool, lev, lev->b, lev->x, CLOTH__MG_FORWARD, lev->t);
        } else {
            cloth__mg_jacobi(mg->pool, lev, lev->b, lev->x, lev->t, 1);
            for (k = 1; k < nu; ++k) cloth__mg_jacobi(mg->pool, lev, lev->b, lev->x, lev->t, 0);
        }
        if (lev->coarse_n == 0) { /* the coarsest, smoothed: the adjoint sweeps follow */
            for (k = 0; k < nu; ++k) {
                if (gs) cloth__mg_gs_sweep(mg->pool, lev, lev->b, lev->x, CLOTH__MG_BACKWARD, lev->t);
                else cloth__mg_jacobi(mg->pool, lev, lev->b, lev->x, lev->t, 0);
            }
            break;
        }
        /* the residual: left in t by the first Gauss-Seidel sweep, else computed */
        if (!gs || nu > 1) cloth__mg_residual(mg->pool, lev, lev->b, lev->x, lev->t);
        job.lev = lev;
        job.constrained = con;
        job.fine = lev->t;
        job.coarse = lev[1].b;
        if (con) cloth__mg_transfer_run(mg, &job, CLOTH__MG_FILTER);
        cloth__mg_transfer_run(mg, &job, CLOTH__MG_RESTRICT);
    }
    for (l = levels - 2; l >= 0; --l) {
        cloth__mg_level *lev = mg->level + l;
        job.lev = lev;
        job.constrained = l ? NULL : constrained;
        job.fine = lev->x;
        job.coarse = lev[1].x;
        cloth__mg_transfer_run(mg, &job, CLOTH__MG_PROLONG);
        for (k = 0; k < nu; ++k) {
            if (gs) cloth__mg_gs_sweep(mg->pool, lev, lev->b, lev->x, CLOTH__MG_BACKWARD, lev->t);
            else cloth__mg_jacobi(mg->pool, lev, lev->b, lev->x, lev->t, 0);
        }
    }
}

/* s = B r: r loaded into level 0, the cycle, level 0's solution stored into s. */
static void cloth__mg_vcycle(struct cloth__multigrid *mg, const int32_t *constrained, const cloth_real *d,
                             const cloth_real *r, cloth_real *s)
{
    cloth__mg_transfer job;
    job.lev = mg->level;
    job.constrained = NULL;
    job.d = d;
    job.r = r;
    job.s = s;
    job.fine = mg->level[0].b;
    job.coarse = NULL;
    cloth__mg_transfer_run(mg, &job, CLOTH__MG_LOAD);
    cloth__mg_vcycle_float(mg, constrained, d);
    job.fine = mg->level[0].x;
    cloth__mg_transfer_run(mg, &job, CLOTH__MG_STORE);
}

/* ---- symbolic phase ---- */

/* Sort a short list in place. */
static void cloth__sort_small(int32_t *v, int32_t count)
{
    int32_t i, j;
    for (i = 1; i < count; ++i) {
        int32_t t = v[i];
        for (j = i; j > 0 && v[j - 1] > t; --j) v[j] = v[j - 1];
        v[j] = t;
    }
}

/* mirror[k] = the index of block (j, i) for block k = (i, j), on a symmetric pattern: the
   blocks (j, i), i < j, of row j come in increasing i, the order in which rows i meet them. */
static void cloth__mg_mirror(const cloth_block_matrix *m, int32_t *mirror, int32_t *cursor)
{
    int32_t i, k;
    for (i = 0; i < m->vertex_count; ++i) cursor[i] = m->row_start[i];
    for (i = 0; i < m->vertex_count; ++i)
        for (k = m->row_start[i]; k < m->row_start[i + 1]; ++k) {
            int32_t j = m->column[k];
            if (j < i) continue;
            if (j == i) { mirror[k] = k; continue; }
            mirror[k] = cursor[j];
            mirror[cursor[j]] = k;
            ++cursor[j];
        }
}

/* Level l is the coarsest: a dense factor when it is small enough, else smoothing only. */
static cloth_result cloth__mg_make_coarsest(struct cloth__multigrid *mg, int32_t l, const cloth_block_matrix *A)
{
    int32_t n = mg->level[l].n;
    int ok = 1;
    mg->level[l].coarse_n = 0;
    mg->level_count = l + 1;
    mg->dense_n = 0;
    if (n > 0 && n <= 4 * mg->options.coarse_size) {
        size_t dn = 3 * (size_t)n;
        mg->dense = (double *)cloth__mg_alloc(mg, dn * dn, sizeof(double), &ok);
        mg->dense_rhs = (double *)cloth__mg_alloc(mg, dn, sizeof(double), &ok);
        if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
        mg->dense_n = 3 * n;
        return CLOTH_SUCCESS;
    }
    return cloth__mg_split_alloc(mg, mg->level + l, A);
}

/* The symbolic phase of level l (its operator A holds values): strength, aggregates, the
   patterns of P, P^T, A P and the next level's operator, and the next level's memory; or the
   decision that l is the coarsest. */
static cloth_result cloth__mg_symbolic(struct cloth__multigrid *mg, int32_t l, const cloth_block_matrix *A)
{
    cloth__mg_level *lev = mg->level + l, *next = lev + 1;
    const cloth_multigrid_options *o = &mg->options;
    const int32_t n = A->vertex_count;
    int32_t *agg, *marker = mg->marker, *stamp = mg->stamp;
    int32_t i, k, m, nc = 0;
    double theta2 = (double)o->strength_threshold * (double)o->strength_threshold, *dn;
    size_t count;
    int ok = 1, smooth = o->prolongator_damping > 0;

    if (l + 1 >= o->max_levels || n <= o->coarse_size) return cloth__mg_make_coarsest(mg, l, A);
    dn = (double *)cloth__alloc_array(&mg->allocator, (size_t)n, sizeof(double));
    lev->strong = (unsigned char *)cloth__mg_alloc(mg, (size_t)A->block_count, 1, &ok);
    lev->aggregate = agg = (int32_t *)cloth__mg_alloc(mg, (size_t)n, sizeof(int32_t), &ok);
    if (!dn || !ok) { cloth__free(&mg->allocator, dn); return CLOTH_ERROR_OUT_OF_MEMORY; }

    /* strength: |A_ij|_F^2 > theta^2 |A_ii|_F |A_jj|_F, with |A_ij|_F^2 averaged over (i, j)
       and (j, i) so that the graph is symmetric whatever the rounding of the values */
    for (i = 0; i < n; ++i) dn[i] = sqrt(cloth__m3_frobenius2(A->value + 9 * (size_t)A->diagonal[i]));
    for (i = 0; i < n; ++i)
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            int32_t j = A->column[k];
            double f;
            if (j == i) { lev->strong[k] = 0; continue; }
            f = 0.5 * (cloth__m3_frobenius2(A->value + 9 * (size_t)k) +
                       cloth__m3_frobenius2(A->value + 9 * (size_t)lev->mirror[k]));
            lev->strong[k] = (unsigned char)(f > 0 && f > theta2 * dn[i] * dn[j]);
        }

    /* aggregation (Vanek, Mandel & Brezina), vertices in index order. Phase 1: a vertex whose
       strong neighbours are all free makes an aggregate of itself and them. */
    for (i = 0; i < n; ++i) agg[i] = -1;
    for (i = 0; i < n; ++i) {
        int has = 0, all_free = 1;
        if (agg[i] >= 0) continue;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            if (!lev->strong[k]) continue;
            has = 1;
            if (agg[A->column[k]] >= 0) { all_free = 0; break; }
        }
        if (!has || !all_free) continue;
        agg[i] = nc;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k)
            if (lev->strong[k]) agg[A->column[k]] = nc;
        ++nc;
    }
    /* phase 2: a vertex left joins the phase-1 aggregate of its strongest neighbour */
    for (i = 0; i < n; ++i) stamp[i] = agg[i] >= 0;
    for (i = 0; i < n; ++i) {
        int32_t best = -1;
        double best_value = -1;
        if (agg[i] >= 0) continue;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            int32_t j = A->column[k];
            double v;
            if (!lev->strong[k] || !stamp[j]) continue;
            v = cloth__m3_frobenius2(A->value + 9 * (size_t)k);
            if (dn[i] * dn[j] > 0) v /= dn[i] * dn[j];
            if (v > best_value) { best_value = v; best = agg[j]; }
        }
        if (best >= 0) agg[i] = best;
    }
    /* phase 3: what is left with strong neighbours makes aggregates with its free ones;
       vertices without strong neighbours stay out (the smoother alone treats them) */
    for (i = 0; i < n; ++i) {
        int has = 0;
        if (agg[i] >= 0) continue;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) has |= lev->strong[k];
        if (!has) continue;
        agg[i] = nc;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k)
            if (lev->strong[k] && agg[A->column[k]] < 0) agg[A->column[k]] = nc;
        ++nc;
    }
    cloth__free(&mg->allocator, dn);
    if (nc == 0 || nc >= n) return cloth__mg_make_coarsest(mg, l, A);
    lev->coarse_n = nc;
    next->n = nc;
    if (cloth__mg_split_alloc(mg, lev, A) != CLOTH_SUCCESS) return CLOTH_ERROR_OUT_OF_MEMORY;

    /* the members of each aggregate */
    lev->member_start = (int32_t *)cloth__mg_alloc(mg, (size_t)nc + 1, sizeof(int32_t), &ok);
    lev->member = (int32_t *)cloth__mg_alloc(mg, (size_t)n, sizeof(int32_t), &ok);
    lev->tentative = (cloth_real *)cloth__mg_alloc(mg, (size_t)n, 9 * sizeof(cloth_real), &ok);
    lev->p_start = (int32_t *)cloth__mg_alloc(mg, (size_t)n + 1, sizeof(int32_t), &ok);
    lev->ap_start = (int32_t *)cloth__mg_alloc(mg, (size_t)n + 1, sizeof(int32_t), &ok);
    lev->pt_start = (int32_t *)cloth__mg_alloc(mg, (size_t)nc + 1, sizeof(int32_t), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (m = 0; m <= nc; ++m) lev->member_start[m] = 0;
    for (i = 0; i < n; ++i)
        if (agg[i] >= 0) ++lev->member_start[agg[i] + 1];
    lev->max_members = 0;
    for (m = 0; m < nc; ++m) {
        if (lev->member_start[m + 1] > lev->max_members) lev->max_members = lev->member_start[m + 1];
        lev->member_start[m + 1] += lev->member_start[m];
    }
    for (m = 0; m < nc; ++m) marker[m] = lev->member_start[m];
    for (i = 0; i < n; ++i)
        if (agg[i] >= 0) lev->member[marker[agg[i]]++] = i;

    /* P's pattern: row i reaches the aggregates of i and of its strong neighbours (those of i
       alone without smoothing). Two passes: count, then fill. */
    for (m = 0; m < nc; ++m) marker[m] = -1;
    count = 0;
    lev->p_start[0] = 0;
    for (i = 0; i < n; ++i) {
        if (agg[i] >= 0) { marker[agg[i]] = i; ++count; }
        if (smooth)
            for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
                int32_t c = agg[A->column[k]];
                if (lev->strong[k] && c >= 0 && marker[c] != i) { marker[c] = i; ++count; }
            }
        if (count > (size_t)INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
        lev->p_start[i + 1] = (int32_t)count;
        if (lev->p_start[i + 1] - lev->p_start[i] > lev->p_row_max) lev->p_row_max = lev->p_start[i + 1] - lev->p_start[i];
    }
    lev->p_count = (int32_t)count;
    lev->p_column = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    lev->p_row = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    lev->p_float = (float *)cloth__mg_alloc(mg, count, CLOTH__MG_B * sizeof(float), &ok);
    lev->pt_block = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (m = 0; m < nc; ++m) marker[m] = -1;
    for (i = 0; i < n; ++i) {
        int32_t out = lev->p_start[i];
        if (agg[i] >= 0) { marker[agg[i]] = i; lev->p_column[out++] = agg[i]; }
        if (smooth)
            for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
                int32_t c = agg[A->column[k]];
                if (lev->strong[k] && c >= 0 && marker[c] != i) { marker[c] = i; lev->p_column[out++] = c; }
            }
        cloth__sort_small(lev->p_column + lev->p_start[i], out - lev->p_start[i]);
        for (k = lev->p_start[i]; k < out; ++k) lev->p_row[k] = i;
    }
    /* P's blocks by column, rows increasing */
    for (m = 0; m <= nc; ++m) lev->pt_start[m] = 0;
    for (k = 0; k < lev->p_count; ++k) ++lev->pt_start[lev->p_column[k] + 1];
    for (m = 0; m < nc; ++m) lev->pt_start[m + 1] += lev->pt_start[m];
    for (m = 0; m < nc; ++m) marker[m] = lev->pt_start[m];
    for (k = 0; k < lev->p_count; ++k) lev->pt_block[marker[lev->p_column[k]]++] = k;

    /* A P's pattern: row i reaches the columns of P's rows j over A's row i */
    for (m = 0; m < nc; ++m) marker[m] = -1;
    count = 0;
    lev->ap_start[0] = 0;
    for (i = 0; i < n; ++i) {
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            int32_t j = A->column[k], q;
            for (q = lev->p_start[j]; q < lev->p_start[j + 1]; ++q)
                if (marker[lev->p_column[q]] != i) { marker[lev->p_column[q]] = i; ++count; }
        }
        if (count > (size_t)INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
        lev->ap_start[i + 1] = (int32_t)count;
    }
    lev->ap_count = (int32_t)count;
    lev->ap_column = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    lev->ap_float = (float *)cloth__mg_alloc(mg, count, CLOTH__MG_B * sizeof(float), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (m = 0; m < nc; ++m) marker[m] = -1;
    for (i = 0; i < n; ++i) {
        int32_t out = lev->ap_start[i];
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            int32_t j = A->column[k], q;
            for (q = lev->p_start[j]; q < lev->p_start[j + 1]; ++q)
                if (marker[lev->p_column[q]] != i) { marker[lev->p_column[q]] = i; lev->ap_column[out++] = lev->p_column[q]; }
        }
        cloth__sort_small(lev->ap_column + lev->ap_start[i], out - lev->ap_start[i]);
    }

    /* the next level's pattern: row I reaches the columns of A P's rows i over P's column I */
    next->a.row_start = (int32_t *)cloth__mg_alloc(mg, (size_t)nc + 1, sizeof(int32_t), &ok);
    next->a.diagonal = (int32_t *)cloth__mg_alloc(mg, (size_t)nc, sizeof(int32_t), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (m = 0; m < nc; ++m) marker[m] = -1;
    count = 0;
    next->a.row_start[0] = 0;
    for (m = 0; m < nc; ++m) {
        int32_t t;
        for (t = lev->pt_start[m]; t < lev->pt_start[m + 1]; ++t) {
            int32_t row = lev->p_row[lev->pt_block[t]], q;
            for (q = lev->ap_start[row]; q < lev->ap_start[row + 1]; ++q)
                if (marker[lev->ap_column[q]] != m) { marker[lev->ap_column[q]] = m; ++count; }
        }
        if (count > (size_t)INT32_MAX) return CLOTH_ERROR_SIZE_OVERFLOW;
        next->a.row_start[m + 1] = (int32_t)count;
    }
    next->a.vertex_count = nc;
    next->a.block_count = (int32_t)count;
    next->a.allocator = mg->allocator;
    next->a.column = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    next->a.value = (cloth_real *)cloth__mg_alloc(mg, count, 9 * sizeof(cloth_real), &ok);
    lev->ac_float = (float *)cloth__mg_alloc(mg, count, CLOTH__MG_B * sizeof(float), &ok);
    next->mirror = (int32_t *)cloth__mg_alloc(mg, count, sizeof(int32_t), &ok);
    next->dinv = (cloth_real *)cloth__mg_alloc(mg, (size_t)nc, 9 * sizeof(cloth_real), &ok);
    next->nullspace = (cloth_real *)cloth__mg_alloc(mg, (size_t)nc, 9 * sizeof(cloth_real), &ok);
    next->x = (float *)cloth__mg_alloc(mg, (size_t)nc, CLOTH__MG_W * sizeof(float), &ok);
    next->b = (float *)cloth__mg_alloc(mg, (size_t)nc, CLOTH__MG_W * sizeof(float), &ok);
    next->t = (float *)cloth__mg_alloc(mg, (size_t)nc, CLOTH__MG_W * sizeof(float), &ok);
    if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
    cloth__mg_zero_vectors(next);
    for (m = 0; m < nc; ++m) marker[m] = -1;
    for (m = 0; m < nc; ++m) {
        int32_t t, out = next->a.row_start[m];
        for (t = lev->pt_start[m]; t < lev->pt_start[m + 1]; ++t) {
            int32_t row = lev->p_row[lev->pt_block[t]], q;
            for (q = lev->ap_start[row]; q < lev->ap_start[row + 1]; ++q)
                if (marker[lev->ap_column[q]] != m) { marker[lev->ap_column[q]] = m; next->a.column[out++] = lev->ap_column[q]; }
        }
        cloth__sort_small(next->a.column + next->a.row_start[m], out - next->a.row_start[m]);
        next->a.diagonal[m] = -1;
        for (k = next->a.row_start[m]; k < out; ++k)
            if (next->a.column[k] == m) next->a.diagonal[m] = k;
        /* every aggregate has a member i with P_im and (A P)_im, so the diagonal is there */
        CLOTH_ASSERT(next->a.diagonal[m] >= 0);
    }
    cloth__mg_mirror(&next->a, next->mirror, marker);
    for (k = 0; k < next->a.block_count * 9; ++k) next->a.value[k] = 0;
    if ((size_t)lev->max_members > mg->qr_capacity) {
        cloth__free(&mg->allocator, mg->qr);
        mg->bytes -= mg->qr_capacity * (size_t)mg->part_count * 9 * sizeof(double);
        mg->qr = (double *)cloth__mg_alloc(mg, (size_t)lev->max_members * (size_t)mg->part_count, 9 * sizeof(double), &ok);
        if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
        mg->qr_capacity = (size_t)lev->max_members;
    }
    if ((size_t)lev->p_row_max > mg->p_rows_capacity) {
        cloth__free(&mg->allocator, mg->p_rows);
        mg->bytes -= mg->p_rows_capacity * (size_t)mg->part_count * 9 * sizeof(cloth_real);
        mg->p_rows = (cloth_real *)cloth__mg_alloc(mg, (size_t)lev->p_row_max * (size_t)mg->part_count, 9 * sizeof(cloth_real), &ok);
        if (!ok) return CLOTH_ERROR_OUT_OF_MEMORY;
        mg->p_rows_capacity = (size_t)lev->p_row_max;
    }
    return CLOTH_SUCCESS;
}

/* ---- numeric phase ---- */

/* An upper bound on rho(D^+ A) for the Jacobi smoother's weight, Gershgorin's in the symmetric
   scaling: with D^+ = G G^T (G from the Cholesky factor of each smoother block), D^+ A is
   similar to the symmetric G^T A G, whose largest eigenvalue is at most
   max_i sum_j |G_i^T A_ij G_j| (infinity norm). Gershgorin's bound on D^+ A itself would be a
   hundred times too large on cloth, where a stiff in-plane direction meets a soft normal one;
   this one is about 2.5 times. g: 9 scratch reals per node. */
static double cloth__mg_rho_bound(const cloth_block_matrix *A, const cloth_real *dinv, cloth_real *g)
{
    double rho = 0;
    int32_t i, k;
    int r, c;
    for (i = 0; i < A->vertex_count; ++i) {
        double l[9];
        for (r = 0; r < 9; ++r) l[r] = (double)dinv[9 * (size_t)i + r];
        cloth__dense_cholesky_dropping(l, 3, 64 * 2.220446049250313e-16);
        for (r = 0; r < 3; ++r)
            for (c = 0; c < 3; ++c) g[9 * (size_t)i + 3 * r + c] = c <= r ? (cloth_real)l[3 * r + c] : 0;
    }
    for (i = 0; i < A->vertex_count; ++i) {
        const cloth_real *gi = g + 9 * (size_t)i;
        double s = 0;
        if (gi[0] == 0 && gi[4] == 0 && gi[8] == 0) continue;
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            cloth_real w[9], z[9];
            for (r = 0; r < 9; ++r) w[r] = 0;
            cloth__m3_tmul_add(gi, A->value + 9 * (size_t)k, w);
            cloth__m3_mul(w, g + 9 * (size_t)A->column[k], z);
            s += cloth__m3_norm_inf(z);
        }
        if (s > rho) rho = s;
    }
    return rho;
}

/* The Jacobi smoother's weight 4/3 / rho (rho bounded over whole rows, so that the weighted
   sweep converges: weight * rho(D^+ A) <= 4/3 < 2). */
static double cloth__mg_jacobi_weight(const cloth_block_matrix *A, const cloth_real *dinv, cloth_real *g)
{
    double rho = cloth__mg_rho_bound(A, dinv, g);
    return rho > 0 ? 4.0 / 3.0 / rho : 0.0;
}

/* The dense matrix of the coarsest level l (lower triangle enough, all written); on level 0
   the filtered S A S + c (I - S) of the block-Jacobi preconditioner. */
static void cloth__mg_dense_fill(struct cloth__multigrid *mg, const cloth_block_matrix *A, const int32_t *constrained,
                                 const cloth_real *d)
{
    const size_t N = (size_t)mg->dense_n;
    int32_t i, k;
    int r, c, u, v;
    for (k = 0; k < (int32_t)(N * N); ++k) mg->dense[k] = 0;
    for (i = 0; i < A->vertex_count; ++i) {
        double si[9], sj[9];
        int32_t ci = constrained ? constrained[i] : 0;
        cloth__filter_matrix(ci, d + 3 * (size_t)i, si);
        for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
            int32_t j = A->column[k], cj = constrained ? constrained[j] : 0;
            const cloth_real *b = A->value + 9 * (size_t)k;
            double out[9];
            cloth__filter_matrix(cj, d + 3 * (size_t)j, sj);
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) {
                    double s = 0;
                    if (ci == 0 && cj == 0) s = (double)b[3 * r + c];
                    else
                        for (u = 0; u < 3; ++u)
                            for (v = 0; v < 3; ++v) s += si[3 * r + u] * (double)b[3 * u + v] * sj[3 * v + c];
                    out[3 * r + c] = s;
                }
            if (j == i && ci != 0) {
                /* the constrained directions get the mean of the free ones (1 if none) */
                double tr = out[0] + out[4] + out[8], cst = ci < 3 ? tr / (double)(3 - ci) : 1.0;
                if (!(cst > 0)) cst = 1.0;
                for (r = 0; r < 3; ++r)
                    for (c = 0; c < 3; ++c) out[3 * r + c] += cst * ((r == c ? 1.0 : 0.0) - si[3 * r + c]);
            }
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) mg->dense[(3 * (size_t)i + r) * N + 3 * (size_t)j + c] = out[3 * r + c];
        }
    }
    /* exactly symmetric: the lower triangle from the mean of both */
    for (k = 0; k < (int32_t)N; ++k) {
        size_t a, b;
        for (a = (size_t)k + 1; a < N; ++a) {
            b = (size_t)k;
            mg->dense[a * N + b] = 0.5 * (mg->dense[a * N + b] + mg->dense[b * N + a]);
        }
    }
}

/* The tentative prolongator of level l: per aggregate, the near-null-space rows of its
   members (level 0: the filters S_i, the filtered translations; above: the R factors of the
   level below) orthonormalized by modified Gram-Schmidt in double. A column left with less
   than sqrt(eps) of its length is dropped (zero in T and on R's diagonal). T's rows go to
   lev->tentative, R to the next level's near null space. The aggregates agg0 .. agg1 - 1, with
   the scratch q (9 qr_capacity); T's rows are zeroed before (an aggregate of free vertices
   writes only its blocks' diagonals). */
static void cloth__mg_tentative(struct cloth__multigrid *mg, int32_t l, const int32_t *constrained, const cloth_real *d,
                                int32_t agg0, int32_t agg1, double *q)
{
    cloth__mg_level *lev = mg->level + l, *next = lev + 1;
    const double drop = sqrt(CLOTH__REAL_EPS);
    int32_t agg, k;
    for (agg = agg0; agg < agg1; ++agg) {
        const int32_t first = lev->member_start[agg], m = lev->member_start[agg + 1] - first;
        const size_t len = 3 * (size_t)m;
        double rr[9];
        int c, c2, r, kept[3] = { 0, 0, 0 }, free_only = l == 0;
        for (k = 0; k < m && free_only; ++k) free_only = !constrained || constrained[lev->member[first + k]] == 0;
        if (free_only) {
            /* m identity blocks: what the general path computes, directly (bit for bit) */
            double root = sqrt((double)m);
            cloth_real t = (cloth_real)(1.0 / root);
            for (k = 0; k < m; ++k) {
                cloth_real *tk = lev->tentative + 9 * (size_t)lev->member[first + k];
                tk[0] = tk[4] = tk[8] = t;
            }
            for (r = 0; r < 9; ++r) next->nullspace[9 * (size_t)agg + r] = (cloth_real)(r % 4 == 0 ? root : 0.0);
            continue;
        }
        /* column c of the stacked rows at q + c len */
        for (k = 0; k < m; ++k) {
            int32_t node = lev->member[first + k];
            double b[9];
            if (l == 0) cloth__filter_matrix(constrained ? constrained[node] : 0, d + 3 * (size_t)node, b);
            else
                for (r = 0; r < 9; ++r) b[r] = (double)lev->nullspace[9 * (size_t)node + r];
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) q[(size_t)c * len + 3 * (size_t)k + r] = b[3 * r + c];
        }
        for (r = 0; r < 9; ++r) rr[r] = 0;
        for (c = 0; c < 3; ++c) {
            double *v = q + (size_t)c * len, norm0 = 0, norm = 0;
            size_t e;
            for (e = 0; e < len; ++e) norm0 += v[e] * v[e];
            for (c2 = 0; c2 < c; ++c2) {
                const double *w = q + (size_t)c2 * len;
                double t = 0;
                if (!kept[c2]) continue;
                for (e = 0; e < len; ++e) t += w[e] * v[e];
                rr[3 * c2 + c] = t;
                for (e = 0; e < len; ++e) v[e] -= t * w[e];
            }
            for (e = 0; e < len; ++e) norm += v[e] * v[e];
            norm = sqrt(norm);
            kept[c] = norm0 > 0 && norm > drop * sqrt(norm0);
            if (kept[c]) {
                rr[3 * c + c] = norm;
                for (e = 0; e < len; ++e) v[e] /= norm;
            } else {
                for (e = 0; e < len; ++e) v[e] = 0;
            }
        }
        for (k = 0; k < m; ++k) {
            cloth_real *t = lev->tentative + 9 * (size_t)lev->member[first + k];
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) t[3 * r + c] = (cloth_real)q[(size_t)c * len + 3 * (size_t)k + r];
        }
        for (r = 0; r < 9; ++r) next->nullspace[9 * (size_t)agg + r] = (cloth_real)rr[r];
    }
}

/* The numeric phase's products of one level by rows, for the part job->part of the rows:
   stage 0 the rows of P = T - omega D^+ A_s T, stage 1 the rows of A P, stage 2 the coarse
   rows of P^T (A P) on the upper triangle (rows of P^T in increasing fine row order). A row
   reads only rows finished by an earlier stage, so the rows of a stage run in any order. */
typedef struct cloth__mg_job {
    struct cloth__multigrid *mg;
    cloth__mg_level *lev;
    const cloth_block_matrix *A;
    const cloth_real *dinv;
    double omega;
    cloth_real om;
    int stage;
    int32_t level;
    const int32_t *constrained;   /* level 0's filter */
    const cloth_real *d;
    int *part_finite;             /* stage 2: per part, 1 while its values are finite */
} cloth__mg_job;

static void cloth__mg_product_task(void *context, int32_t part)
{
    const cloth__mg_job *job = (const cloth__mg_job *)context;
    struct cloth__multigrid *mg = job->mg;
    cloth__mg_level *lev = job->lev, *next = lev + 1;
    const cloth_block_matrix *A = job->A;
    const cloth_real *dinv = job->dinv;
    const double omega = job->omega;
    const cloth_real om = job->om;
    int32_t *marker = part == 0 ? mg->marker : mg->part_marker + (size_t)(part - 1) * (size_t)mg->vertex_count;
    int32_t i0, i1, i, k, q;
    cloth__part_rows(job->stage == 2 ? lev->coarse_n : lev->n, part, mg->part_count, &i0, &i1);
    if (job->stage == 0) {
        /* row i of P in double in this part's scratch (its block k at k - p_start[i]) */
        cloth_real *row = mg->p_rows + 9 * (size_t)part * mg->p_rows_capacity;
        for (i = i0; i < i1; ++i) {
            const cloth_real *di = dinv + 9 * (size_t)i;
            for (k = lev->p_start[i]; k < lev->p_start[i + 1]; ++k) {
                marker[lev->p_column[k]] = k - lev->p_start[i];
                for (q = 0; q < 9; ++q) row[9 * (size_t)(k - lev->p_start[i]) + q] = 0;
            }
            if (lev->p_start[i] == lev->p_start[i + 1]) continue;
            if (omega > 0)
                for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
                    int32_t j = A->column[k], c = lev->aggregate[j];
                    const cloth_real *t = lev->tentative + 9 * (size_t)j, *a = A->value + 9 * (size_t)k;
                    cloth_real *o;
                    if (c < 0 || !(lev->strong[k] || k == A->diagonal[i])) continue;
                    o = row + 9 * (size_t)marker[c];
                    if (t[1] == 0 && t[2] == 0 && t[3] == 0 && t[5] == 0 && t[6] == 0 && t[7] == 0 && t[0] == t[4] && t[0] == t[8]) {
                        /* a free vertex's block of T on level 0: a multiple of I */
                        for (q = 0; q < 9; ++q) o[q] += a[q] * t[0];
                    } else {
                        cloth__m3_mul_add(a, t, o);
                    }
                }
            for (k = lev->p_start[i]; k < lev->p_start[i + 1]; ++k) {
                cloth_real *p = row + 9 * (size_t)(k - lev->p_start[i]), w[9];
                cloth__m3_mul(di, p, w);
                for (q = 0; q < 9; ++q) p[q] = -om * w[q];
                if (lev->p_column[k] == lev->aggregate[i])
                    for (q = 0; q < 9; ++q) p[q] += lev->tentative[9 * (size_t)i + q];
                cloth__mg_block_float(p, 0, lev->p_float + CLOTH__MG_B * (size_t)k);
            }
        }
    } else if (job->stage == 1) {
        /* A P */
        for (i = i0; i < i1; ++i) {
            for (k = lev->ap_start[i]; k < lev->ap_start[i + 1]; ++k) {
                marker[lev->ap_column[k]] = k;
                for (q = 0; q < CLOTH__MG_B; ++q) lev->ap_float[CLOTH__MG_B * (size_t)k + q] = 0;
            }
            for (k = A->row_start[i]; k < A->row_start[i + 1]; ++k) {
                int32_t j = A->column[k];
                const cloth_real *a = A->value + 9 * (size_t)k;
                const float a0 = (float)a[0], a1 = (float)a[1], a2 = (float)a[2], a3 = (float)a[3], a4 = (float)a[4],
                            a5 = (float)a[5], a6 = (float)a[6], a7 = (float)a[7], a8 = (float)a[8];
                /* row r of A_ij P_jc: a_r0 P_0 + a_r1 P_1 + a_r2 P_2 over P's padded rows */
                for (q = lev->p_start[j]; q < lev->p_start[j + 1]; ++q) {
                    const float *b = lev->p_float + CLOTH__MG_B * (size_t)q;
                    float *out = lev->ap_float + CLOTH__MG_B * (size_t)marker[lev->p_column[q]];
                    CLOTH__MG_ROWS_ADD(b, a0, a1, a2, out);
                    CLOTH__MG_ROWS_ADD(b, a3, a4, a5, out + 4);
                    CLOTH__MG_ROWS_ADD(b, a6, a7, a8, out + 8);
                }
            }
        }
    } else {
        /* P^T (A P) on the upper triangle, rows of P^T in increasing fine row order; then the
           lower triangle as its transpose and the diagonal blocks symmetrized */
        for (i = i0; i < i1; ++i) {
            int32_t t;
            for (k = next->a.row_start[i]; k < next->a.row_start[i + 1]; ++k) {
                if (next->a.column[k] < i) continue;
                marker[next->a.column[k]] = k;
                for (q = 0; q < CLOTH__MG_B; ++q) lev->ac_float[CLOTH__MG_B * (size_t)k + q] = 0;
            }
            for (t = lev->pt_start[i]; t < lev->pt_start[i + 1]; ++t) {
                int32_t pk = lev->pt_block[t], row = lev->p_row[pk];
                const float *p = lev->p_float + CLOTH__MG_B * (size_t)pk;
                for (q = lev->ap_start[row]; q < lev->ap_start[row + 1]; ++q) {
                    int32_t c = lev->ap_column[q];
                    const float *ap = lev->ap_float + CLOTH__MG_B * (size_t)q;
                    float *out;
                    if (c < i) continue;
                    /* row r of P^T (A P): P_0r (A P)_0 + P_1r (A P)_1 + P_2r (A P)_2 */
                    out = lev->ac_float + CLOTH__MG_B * (size_t)marker[c];
                    CLOTH__MG_ROWS_ADD(ap, p[0], p[4], p[8], out);
                    CLOTH__MG_ROWS_ADD(ap, p[1], p[5], p[9], out + 4);
                    CLOTH__MG_ROWS_ADD(ap, p[2], p[6], p[10], out + 8);
                }
            }
            /* the row's blocks in cloth_real, the diagonal one symmetrized, each upper one
               copied transposed into its lower place (a block of a later row that only this
               row writes); all finite when the upper ones are */
            for (k = next->a.row_start[i]; k < next->a.row_start[i + 1]; ++k) {
                const float *v = lev->ac_float + CLOTH__MG_B * (size_t)k;
                cloth_real *o = next->a.value + 9 * (size_t)k;
                int r, c;
                if (next->a.column[k] < i) continue;
                for (q = 0; q < 3; ++q) {
                    o[3 * q] = (cloth_real)v[4 * q];
                    o[3 * q + 1] = (cloth_real)v[4 * q + 1];
                    o[3 * q + 2] = (cloth_real)v[4 * q + 2];
                }
                if (next->a.column[k] == i) {
                    for (r = 0; r < 3; ++r)
                        for (c = r + 1; c < 3; ++c) o[3 * r + c] = o[3 * c + r] = (cloth_real)0.5 * (o[3 * r + c] + o[3 * c + r]);
                } else {
                    cloth_real *w = next->a.value + 9 * (size_t)next->mirror[k];
                    for (r = 0; r < 3; ++r)
                        for (c = 0; c < 3; ++c) w[3 * c + r] = o[3 * r + c];
                }
                if (!cloth__all_finite(o, 9)) job->part_finite[part] = 0;
            }
        }
    }
}

/* The numeric phase's passes by chunks of a level's rows (parts of CLOTH__CHUNK rows, on the
   pool; every row's work is the same whichever thread runs it). Stage 0: the smoother's
   blocks (above level 0 D^+ itself, the psd inverse of the diagonal block), their
   single-precision copies for the sweeps, and T's rows zeroed. The rho estimate's: stage 3
   its start x (mg->scratch) of fixed pseudo-random entries in [-1, 1] (a hash of the row),
   filtered on level 0; stage 1 the power step's product y = A x (mg->scratch + 3 n) and the
   chunk's x^T A x and x^T D x (D the diagonal blocks) in mg->partial; stage 2 x = D^+ y. */
static void cloth__mg_row_task(void *context, int32_t chunk)
{
    const cloth__mg_job *job = (const cloth__mg_job *)context;
    struct cloth__multigrid *mg = job->mg;
    cloth__mg_level *lev = job->lev;
    const cloth_block_matrix *A = job->A;
    const int32_t n = lev->n;
    cloth_real *x = mg->scratch, *y = x + 3 * (size_t)n;
    int32_t i, i0, i1;
    int c;
    cloth__chunk_rows(n, chunk, &i0, &i1);
    if (job->stage == 0) {
        if (job->level > 0)
            for (i = i0; i < i1; ++i) cloth__psd_inverse3(A->value + 9 * (size_t)A->diagonal[i], lev->dinv + 9 * (size_t)i);
        if (lev->lower_start) cloth__mg_split_rows(lev, A, job->dinv, i0, i1);
        if (lev->coarse_n > 0) memset(lev->tentative + 9 * (size_t)i0, 0, 9 * (size_t)(i1 - i0) * sizeof(cloth_real));
    } else if (job->stage == 3) {
        for (i = i0; i < i1; ++i) {
            cloth_real *xi = x + 3 * (size_t)i;
            for (c = 0; c < 3; ++c) {
                uint64_t state = 0x6d67u + 3 * (uint64_t)i + (uint64_t)c;
                double u = (double)(cloth__splitmix64(&state) >> 11) * (1.0 / 9007199254740992.0); /* [0, 1) */
                xi[c] = (cloth_real)(2 * u - 1);
            }
            if (job->constrained) cloth__filter_apply(job->constrained[i], job->d + 3 * (size_t)i, xi);
        }
    } else if (job->stage == 1) {
        double xax = 0, xdx = 0;
        for (i = i0; i < i1; ++i) {
            const cloth_real *xi = x + 3 * (size_t)i;
            cloth_real *yi = y + 3 * (size_t)i, dx[3];
            cloth__block_row_product(A, i, x, yi);
            cloth__m3_apply(A->value + 9 * (size_t)A->diagonal[i], xi, dx);
            for (c = 0; c < 3; ++c) {
                xax += (double)xi[c] * (double)yi[c];
                xdx += (double)xi[c] * (double)dx[c];
            }
        }
        mg->partial[2 * (size_t)chunk] = xax;
        mg->partial[2 * (size_t)chunk + 1] = xdx;
    } else {
        for (i = i0; i < i1; ++i) cloth__m3_apply(job->dinv + 9 * (size_t)i, y + 3 * (size_t)i, x + 3 * (size_t)i);
    }
}

/* The tentative prolongator's aggregates by parts (mg->part_count, each with its QR scratch). */
static void cloth__mg_tentative_task(void *context, int32_t part)
{
    const cloth__mg_job *job = (const cloth__mg_job *)context;
    struct cloth__multigrid *mg = job->mg;
    int32_t agg0, agg1;
    cloth__part_rows(job->lev->coarse_n, part, mg->part_count, &agg0, &agg1);
    cloth__mg_tentative(mg, job->level, job->constrained, job->d, agg0, agg1, mg->qr + 9 * (size_t)part * mg->qr_capacity);
}

/* An estimate of rho(D^+ A) from below: the Rayleigh quotient x^T A x / x^T D x after `steps`
   steps of the power method on D^+ A from a fixed start (cloth__mg_row_task's stages 3, 1
   and 2), in cloth_real with the sums in double, each chunk's in order, then the chunks' in
   order (the same on any number of threads). x is not normalized: it grows by at most rho per
   step. Uses mg->scratch. */
static double cloth__mg_rho_estimate(cloth__mg_job *job, int steps)
{
    struct cloth__multigrid *mg = job->mg;
    const int32_t chunks = cloth__chunk_count(job->lev->n);
    double rq = 0;
    int32_t c;
    int step;
    job->stage = 3;
    cloth__pool_run(mg->pool, chunks, cloth__mg_row_task, job);
    for (step = 0; step < steps; ++step) {
        double xax = 0, xdx = 0;
        if (step > 0) {
            job->stage = 2;
            cloth__pool_run(mg->pool, chunks, cloth__mg_row_task, job);
        }
        job->stage = 1;
        cloth__pool_run(mg->pool, chunks, cloth__mg_row_task, job);
        for (c = 0; c < chunks; ++c) {
            xax += mg->partial[2 * (size_t)c];
            xdx += mg->partial[2 * (size_t)c + 1];
        }
        if (!(xdx > 0)) break;
        rq = xax / xdx;
    }
    return rq;
}

/* The numeric phase of level l: the smoother's blocks, and unless l is the coarsest T, P,
   A P and the next level's values P^T A P; on the coarsest the dense factor. pre is level 0's
   smoother (the filtered block-Jacobi inverse), d the prepared filter directions. */
static cloth_result cloth__mg_numeric_level(struct cloth__multigrid *mg, int32_t l, const cloth_block_matrix *fine,
                                            const int32_t *constrained, const cloth_real *d, const cloth_real *pre)
{
    cloth__mg_level *lev = mg->level + l;
    const cloth_block_matrix *A = l ? &lev->a : fine;
    const cloth_real *dinv = l ? lev->dinv : pre;
    const int32_t n = lev->n, nc = lev->coarse_n;
    double omega = 0;
    cloth__mg_job job;
    int part_finite[CLOTH__MAX_THREADS];
    int32_t p;

    job.mg = mg;
    job.lev = lev;
    job.A = A;
    job.dinv = dinv;
    job.level = l;
    job.constrained = l ? NULL : constrained;
    job.d = d;
    job.part_finite = part_finite;
    /* the smoother's blocks by rows on the pool */
    job.stage = 0;
    cloth__pool_run(mg->pool, cloth__chunk_count(n), cloth__mg_row_task, &job);
    if (mg->options.smoother == CLOTH_MULTIGRID_SMOOTHER_JACOBI) lev->omega_smoother = cloth__mg_jacobi_weight(A, dinv, mg->scratch);
    if (nc == 0) {
        if (mg->dense_n > 0) {
            int32_t dropped;
            cloth__mg_dense_fill(mg, A, l ? NULL : constrained, d);
            dropped = cloth__dense_cholesky_dropping(mg->dense, mg->dense_n, 64 * 2.220446049250313e-16);
            /* dropping is harmless under a smoothed level; alone, it would make the
               preconditioner singular */
            if (l == 0 && dropped > 0) return CLOTH_ERROR_NOT_POSITIVE_DEFINITE;
        }
        return CLOTH_SUCCESS;
    }

    cloth__pool_run(mg->pool, mg->part_count, cloth__mg_tentative_task, &job);

    /* P = T - omega D^+ A_s T, omega = damping / rho(D^+ A_s) */
    if (mg->options.prolongator_damping > 0) {
        /* two power steps estimate rho from below (by 15 to 30 % on cloth): 1.3 times that
           smooths as well as the true rho does, and better than the Gershgorin bound, which is
           2.5 times too large (bench/linsolve.c) */
        double rho = 1.3 * cloth__mg_rho_estimate(&job, 2);
        if (rho > 0) omega = (double)mg->options.prolongator_damping / rho;
    }
    /* P, A P and P^T A P by rows, parts on the pool: every row's sums run as serially */
    job.omega = omega;
    job.om = (cloth_real)omega;
    for (p = 0; p < mg->part_count; ++p) part_finite[p] = 1;
    job.stage = 0;
    cloth__pool_run(mg->pool, mg->part_count, cloth__mg_product_task, &job);
    job.stage = 1;
    cloth__pool_run(mg->pool, mg->part_count, cloth__mg_product_task, &job);
    job.stage = 2;
    cloth__pool_run(mg->pool, mg->part_count, cloth__mg_product_task, &job);
    for (p = 0; p < mg->part_count; ++p)
        if (!part_finite[p]) return CLOTH_ERROR_NOT_FINITE;
    return CLOTH_SUCCESS;
}

/* Level 0's smoother blocks: the filtered block-Jacobi inverses of
   CLOTH_PRECONDITIONER_BLOCK_JACOBI (zero for a pinned vertex), a free vertex's computed
   directly as the inverse of its symmetrized diagonal block. */
static cloth_result cloth__mg_fine_smoother_rows(const cloth_block_matrix *matrix, const int32_t *constrained,
                                                 const cloth_real *d, cloth_real *pre, int32_t i0, int32_t i1)
{
    int32_t i;
    for (i = i0; i < i1; ++i) {
        const cloth_real *a = matrix->value + 9 * (size_t)matrix->diagonal[i];
        cloth_real *out = pre + 9 * (size_t)i;
        int32_t count = constrained ? constrained[i] : 0;
        if (count == 0) {
            double m[9], inv[9];
            int r, c;
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) m[3 * r + c] = 0.5 * ((double)a[3 * r + c] + (double)a[3 * c + r]);
            if (!cloth__spd_inverse3(m, inv)) return CLOTH_ERROR_NOT_POSITIVE_DEFINITE;
            for (r = 0; r < 9; ++r) out[r] = (cloth_real)inv[r];
        } else {
            cloth_result result = cloth__filtered_block_inverse(a, count, d + 3 * (size_t)i, CLOTH_PRECONDITIONER_BLOCK_JACOBI, out);
            if (result != CLOTH_SUCCESS) return result;
        }
    }
    return CLOTH_SUCCESS;
}

/* The same by chunks of rows on the pool (NULL: in order here): each chunk's result (as a
   double) in result[chunk]; the first failure in chunk order is a serial pass's. */
typedef struct cloth__mg_smoother_job {
    const cloth_block_matrix *matrix;
    const int32_t *constrained;
    const cloth_real *d;
    cloth_real *pre;
    double *result;
} cloth__mg_smoother_job;

static void cloth__mg_fine_smoother_task(void *context, int32_t chunk)
{
    const cloth__mg_smoother_job *job = (const cloth__mg_smoother_job *)context;
    int32_t i0, i1;
    cloth__chunk_rows(job->matrix->vertex_count, chunk, &i0, &i1);
    job->result[chunk] = (double)cloth__mg_fine_smoother_rows(job->matrix, job->constrained, job->d, job->pre, i0, i1);
}

static cloth_result cloth__mg_fine_smoother_pool(cloth__pool *pool, const cloth_block_matrix *matrix,
                                                 const int32_t *constrained, const cloth_real *d, cloth_real *pre,
                                                 double *result)
{
    cloth__mg_smoother_job job;
    const int32_t chunks = cloth__chunk_count(matrix->vertex_count);
    int32_t c;
    job.matrix = matrix;
    job.constrained = constrained;
    job.d = d;
    job.pre = pre;
    job.result = result;
    cloth__pool_run(pool, chunks, cloth__mg_fine_smoother_task, &job);
    for (c = 0; c < chunks; ++c)
        if (result[c] != (double)CLOTH_SUCCESS) return (cloth_result)(int)result[c];
    return CLOTH_SUCCESS;
}

/* Check the filter and the matrix and make level 0's smoother, as cloth_pcg_solve does: d and
   pre in the workspace's memory. */
static cloth_result cloth__mg_prepare(const cloth_block_matrix *matrix, const cloth_pcg_filter *filter,
                                      cloth_pcg_workspace *workspace, cloth_real **pre, cloth_real **d)
{
    const int32_t n = matrix->vertex_count;
    const int32_t *constrained = filter ? filter->constrained : NULL;
    double *partial = (double *)(void *)(workspace->memory + 24 * (size_t)workspace->vertex_count); /* one per chunk */
    cloth_result result;
    *pre = workspace->memory + 12 * (size_t)n;
    *d = *pre + 9 * (size_t)n;
    result = cloth__pcg_prepare_filter(n, constrained, filter ? filter->direction : NULL, *d);
    if (result != CLOTH_SUCCESS) return result;
    if (!cloth__all_finite_pool(workspace->pool, matrix->value, 9 * (size_t)matrix->block_count, cloth__chunk_count(n),
                                partial))
        return CLOTH_ERROR_NOT_FINITE;
    return cloth__mg_fine_smoother_pool(workspace->pool, matrix, constrained, *d, *pre, partial);
}

static cloth_result cloth__mg_numeric(struct cloth__multigrid *mg, const cloth_block_matrix *matrix,
                                      const int32_t *constrained, const cloth_real *d, const cloth_real *pre)
{
    int32_t l;
    mg->ready = 0;
    for (l = 0; l < mg->level_count; ++l) {
        cloth_result result = cloth__mg_numeric_level(mg, l, matrix, constrained, d, pre);
        if (result != CLOTH_SUCCESS) return result;
    }
    mg->ready = 1;
    return CLOTH_SUCCESS;
}

/* The hierarchy was made for this matrix's pattern. */
static int cloth__mg_matches(const struct cloth__multigrid *mg, const cloth_block_matrix *matrix)
{
    if (!mg || mg->vertex_count != matrix->vertex_count || mg->block_count != matrix->block_count) return 0;
    if (matrix->vertex_count == 0) return 1;
    return memcmp(mg->pattern_start, matrix->row_start, ((size_t)matrix->vertex_count + 1) * sizeof(int32_t)) == 0 &&
           memcmp(mg->pattern_column, matrix->column, (size_t)matrix->block_count * sizeof(int32_t)) == 0;
}

CLOTH_API cloth_result cloth_pcg_multigrid_setup(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                 const cloth_pcg_filter *filter, const cloth_multigrid_options *options)
{
    cloth_multigrid_options o;
    cloth_allocator a;
    struct cloth__multigrid *mg;
    cloth_real *pre = NULL, *d = NULL;
    const int32_t *constrained = filter ? filter->constrained : NULL;
    int32_t n, l;
    int ok = 1;
    cloth_result result;

    CLOTH_ASSERT(workspace && matrix);
    cloth__mg_free(workspace->multigrid);
    workspace->multigrid = NULL;
    o = options ? *options : cloth_default_multigrid_options();
    n = matrix->vertex_count;
    if (!cloth__mg_options_valid(&o) || workspace->vertex_count < n || (n > 0 && !workspace->memory))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if (n > 0) {
        result = cloth__mg_prepare(matrix, filter, workspace, &pre, &d);
        if (result != CLOTH_SUCCESS) return result;
    }
    a = cloth__allocator_or_default(&workspace->allocator);
    mg = (struct cloth__multigrid *)cloth__alloc_array(&a, 1, sizeof *mg);
    if (!mg) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(mg, 0, sizeof *mg);
    mg->allocator = a;
    mg->options = o;
    mg->vertex_count = n;
    mg->block_count = matrix->block_count;
    mg->bytes = sizeof *mg;
    mg->level[0].n = n;
    mg->level_count = 1;
    if (n == 0) {
        mg->ready = 1;
        workspace->multigrid = mg;
        return CLOTH_SUCCESS;
    }
    mg->level[0].mirror = (int32_t *)cloth__mg_alloc(mg, (size_t)matrix->block_count, sizeof(int32_t), &ok);
    mg->level[0].x = (float *)cloth__mg_alloc(mg, (size_t)n, CLOTH__MG_W * sizeof(float), &ok);
    mg->level[0].b = (float *)cloth__mg_alloc(mg, (size_t)n, CLOTH__MG_W * sizeof(float), &ok);
    mg->level[0].t = (float *)cloth__mg_alloc(mg, (size_t)n, CLOTH__MG_W * sizeof(float), &ok);
    if (ok) cloth__mg_zero_vectors(mg->level);
    mg->marker = (int32_t *)cloth__mg_alloc(mg, (size_t)n, sizeof(int32_t), &ok);
    mg->pool = workspace->pool;
    mg->part_count = cloth__pool_threads(workspace->pool);
    if (mg->part_count > 1)
        mg->part_marker = (int32_t *)cloth__mg_alloc(mg, (size_t)(mg->part_count - 1) * (size_t)n, sizeof(int32_t), &ok);
    mg->stamp = (int32_t *)cloth__mg_alloc(mg, (size_t)n, sizeof(int32_t), &ok);
    mg->scratch = (cloth_real *)cloth__mg_alloc(mg, (size_t)n, 9 * sizeof(cloth_real), &ok);
    mg->partial = (double *)cloth__mg_alloc(mg, (size_t)cloth__chunk_count(n), 2 * sizeof(double), &ok);
    mg->pattern_start = (int32_t *)cloth__mg_alloc(mg, (size_t)n + 1, sizeof(int32_t), &ok);
    mg->pattern_column = (int32_t *)cloth__mg_alloc(mg, (size_t)matrix->block_count, sizeof(int32_t), &ok);
    if (!ok) { result = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
    memcpy(mg->pattern_start, matrix->row_start, ((size_t)n + 1) * sizeof(int32_t));
    memcpy(mg->pattern_column, matrix->column, (size_t)matrix->block_count * sizeof(int32_t));
    cloth__mg_mirror(matrix, mg->level[0].mirror, mg->marker);
    for (l = 0;; ++l) {
        result = cloth__mg_symbolic(mg, l, l ? &mg->level[l].a : matrix);
        if (result != CLOTH_SUCCESS) goto fail;
        result = cloth__mg_numeric_level(mg, l, matrix, constrained, d, pre);
        if (result != CLOTH_SUCCESS) goto fail;
        if (mg->level[l].coarse_n == 0) break;
    }
    mg->ready = 1;
    workspace->multigrid = mg;
    return CLOTH_SUCCESS;
fail:
    cloth__mg_free(mg);
    return result;
}

CLOTH_API cloth_result cloth_pcg_multigrid_update(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                  const cloth_pcg_filter *filter)
{
    struct cloth__multigrid *mg;
    cloth_real *pre, *d;
    cloth_result result;
    CLOTH_ASSERT(workspace && matrix);
    mg = workspace->multigrid;
    if (!cloth__mg_matches(mg, matrix) || workspace->vertex_count < matrix->vertex_count) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (matrix->vertex_count == 0) return CLOTH_SUCCESS;
    mg->ready = 0;
    mg->pool = workspace->pool;
    result = cloth__mg_prepare(matrix, filter, workspace, &pre, &d);
    if (result != CLOTH_SUCCESS) return result;
    return cloth__mg_numeric(mg, matrix, filter ? filter->constrained : NULL, d, pre);
}

CLOTH_API void cloth_pcg_multigrid_info(const cloth_pcg_workspace *workspace, cloth_multigrid_info *info)
{
    const struct cloth__multigrid *mg;
    int32_t l;
    double blocks = 0;
    CLOTH_ASSERT(workspace && info);
    memset(info, 0, sizeof *info);
    mg = workspace->multigrid;
    if (!mg) return;
    info->level_count = mg->level_count;
    for (l = 0; l < mg->level_count; ++l) {
        const cloth__mg_level *lev = mg->level + l;
        info->node_count[l] = lev->n;
        info->block_count[l] = l ? lev->a.block_count : mg->block_count;
        info->prolongator_block_count[l] = lev->coarse_n ? lev->p_count : 0;
        blocks += (double)info->block_count[l];
    }
    info->operator_complexity = mg->block_count > 0 ? blocks / (double)mg->block_count : 1.0;
    info->coarsest_dense = mg->dense_n > 0 || mg->vertex_count == 0;
    info->bytes = mg->bytes;
    info->sweep_parts = mg->level[0].lower_start ? mg->level[0].parts : 1;
}

CLOTH_API cloth_result cloth_pcg_solve(const cloth_block_matrix *matrix, const cloth_real *b, cloth_real *x,
                                       const cloth_pcg_filter *filter, const cloth_pcg_options *options,
                                       cloth_pcg_workspace *workspace, cloth_pcg_stats *stats)
{
    return cloth_pcg_solve_preconditioned(matrix, matrix, b, x, filter, options, workspace, stats);
}

CLOTH_API cloth_result cloth_pcg_solve_preconditioned(const cloth_block_matrix *matrix, const cloth_block_matrix *approximation,
                                                      const cloth_real *b, cloth_real *x, const cloth_pcg_filter *filter,
                                                      const cloth_pcg_options *options, cloth_pcg_workspace *workspace,
                                                      cloth_pcg_stats *stats)
{
    static const cloth_real zero[3] = { 0, 0, 0 };
    cloth_pcg_options opt;
    cloth_pcg_stats st;
    const int32_t *constrained;
    const cloth_real *z;
    cloth_real *r, *s, *p, *q, *pre, *d;
    struct cloth__multigrid *mg = NULL;
    cloth__pool *pool;
    cloth__pcg_job job;
    size_t n3, k;
    int32_t n, i, chunks;
    int has_constrained_part = 0;
    double bhat2, delta0, delta, tol2, scale2;
    cloth_result result;

    CLOTH_ASSERT(matrix && approximation && b && x && workspace);
    st.iterations = 0;
    st.residual = 0;
    st.preconditioned_residual = 0;
    st.rhs_norm = 0;
    st.converged = 0;
    if (stats) *stats = st;

    opt = options ? *options : cloth_default_pcg_options();
    if (!cloth__is_finite(opt.tolerance) || opt.tolerance < 0 || opt.max_iterations < 0 ||
        !cloth__is_finite(opt.reference_norm) || opt.reference_norm < 0 ||
        (opt.preconditioner != CLOTH_PRECONDITIONER_NONE && opt.preconditioner != CLOTH_PRECONDITIONER_JACOBI &&
         opt.preconditioner != CLOTH_PRECONDITIONER_BLOCK_JACOBI && opt.preconditioner != CLOTH_PRECONDITIONER_MULTIGRID))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    n = matrix->vertex_count;
    n3 = 3 * (size_t)n;
    if (workspace->vertex_count < n || (n > 0 && !workspace->memory) || approximation->vertex_count != n)
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if (n == 0) {
        st.converged = 1;
        if (stats) *stats = st;
        return CLOTH_SUCCESS;
    }
    if (opt.preconditioner == CLOTH_PRECONDITIONER_MULTIGRID) {
        mg = workspace->multigrid;
        if (!cloth__mg_matches(mg, approximation) || (!opt.multigrid_update && !mg->ready)) return CLOTH_ERROR_INVALID_ARGUMENT;
        mg->pool = workspace->pool;
    }
    r = workspace->memory;
    s = r + n3;
    p = s + n3;
    q = p + n3;
    pre = q + n3;
    d = pre + 3 * n3;
    constrained = filter ? filter->constrained : NULL;
    z = filter ? filter->value : NULL;
    pool = workspace->pool;
    chunks = cloth__chunk_count(n);
    memset(&job, 0, sizeof job);
    job.matrix = matrix;
    job.constrained = constrained;
    job.d = d;
    job.pre = pre;
    job.b = b;
    job.kind = opt.preconditioner;
    job.x = x;
    job.r = r;
    job.s = s;
    job.p = p;
    job.q = q;
    job.n = n;
    job.partial = (double *)(void *)(workspace->memory + 24 * (size_t)workspace->vertex_count);

    /* Everything that can fail before x is touched. */
    result = cloth__pcg_prepare_filter(n, constrained, filter ? filter->direction : NULL, d);
    if (result != CLOTH_SUCCESS) return result;
    if (!cloth__all_finite(b, n3) || (z && !cloth__all_finite(z, n3)) || !cloth__all_finite(x, n3) ||
        !cloth__all_finite_pool(pool, matrix->value, 9 * (size_t)matrix->block_count, chunks, job.partial))
        return CLOTH_ERROR_NOT_FINITE;
    if (approximation != matrix &&
        !cloth__all_finite_pool(pool, approximation->value, 9 * (size_t)approximation->block_count, chunks, job.partial))
        return CLOTH_ERROR_NOT_FINITE;
    if (mg) result = cloth__mg_fine_smoother_pool(pool, approximation, constrained, d, pre, job.partial);
    else result = cloth__pcg_build_preconditioner(approximation, constrained, d, opt.preconditioner, pre);
    if (result != CLOTH_SUCCESS) return result;
    if (mg) {
        /* the hierarchy's values for this system, or at least level 0's smoother (pre, above) */
        if (opt.multigrid_update) {
            result = cloth__mg_numeric(mg, approximation, constrained, d, pre);
            if (result != CLOTH_SUCCESS) return result;
        } else if (mg->level[0].lower_start) {
            if (mg->options.smoother == CLOTH_MULTIGRID_SMOOTHER_JACOBI)
                mg->level[0].omega_smoother = cloth__mg_jacobi_weight(approximation, pre, mg->scratch);
            cloth__mg_split_refresh(mg->level, approximation, pre);
        }
    }

    /* q = (I - S) z, the constrained part. */
    for (i = 0; i < n; ++i) {
        size_t o = 3 * (size_t)i;
        if (constrained) cloth__filter_complement(constrained[i], d + o, z ? z + o : zero, q + o);
        else q[o] = q[o + 1] = q[o + 2] = 0;
        if (q[o] != 0 || q[o + 1] != 0 || q[o + 2] != 0) has_constrained_part = 1;
    }

    /* The reduced right-hand side bhat = S (b - A q) (Ascher & Boxerman) and its
       preconditioned norm delta0, the scale of the stopping test. */
    if (has_constrained_part) {
        bhat2 = cloth__pcg_residual(pool, &job, q);
    } else {
        for (k = 0; k < n3; ++k) r[k] = b[k];
        if (constrained)
            for (i = 0; i < n; ++i) cloth__filter_apply(constrained[i], d + 3 * (size_t)i, r + 3 * (size_t)i);
        bhat2 = cloth__pcg_dot(pool, &job, r, r);
    }
    if (mg) cloth__mg_vcycle(mg, constrained, d, r, s);
    else cloth__pcg_precondition(n, opt.preconditioner, pre, r, s);
    delta0 = cloth__pcg_dot(pool, &job, r, s);
    if (!cloth__is_finite_double(bhat2) || !cloth__is_finite_double(delta0)) return CLOTH_ERROR_NOT_FINITE;
    if (!(delta0 > 0)) {
        /* bhat = 0: the reduced solution is zero, x is the constrained part alone. */
        for (k = 0; k < n3; ++k) x[k] = q[k];
        st.converged = 1;
        if (stats) *stats = st;
        return CLOTH_SUCCESS;
    }

    /* The start x = S x + q, its residual r = S (b - A x), s = P^-1 r, p = S s. */
    for (i = 0; i < n; ++i) {
        size_t o = 3 * (size_t)i;
        if (constrained) cloth__filter_apply(constrained[i], d + o, x + o);
        x[o] += q[o];
        x[o + 1] += q[o + 1];
        x[o + 2] += q[o + 2];
    }
    cloth__pcg_residual(pool, &job, x);
    if (mg) cloth__mg_vcycle(mg, constrained, d, r, s);
    else cloth__pcg_precondition(n, opt.preconditioner, pre, r, s);
    delta = cloth__pcg_dot(pool, &job, r, s);
    for (k = 0; k < n3; ++k) p[k] = s[k];
    if (constrained)
        for (i = 0; i < n; ++i) cloth__filter_apply(constrained[i], d + 3 * (size_t)i, p + 3 * (size_t)i);

    tol2 = (double)opt.tolerance * (double)opt.tolerance;
    st.rhs_norm = (cloth_real)sqrt(delta0);
    scale2 = (double)opt.reference_norm * (double)opt.reference_norm;
    if (scale2 < delta0) scale2 = delta0;
    result = CLOTH_SUCCESS;
    while (!(delta <= tol2 * scale2)) {
        double pq, alpha, beta, delta_new;
        if (st.iterations >= opt.max_iterations) { result = CLOTH_ERROR_CG_NOT_CONVERGED; break; }
        /* q = S A p and p^T q by chunks of rows */
        cloth__pool_run(pool, chunks, cloth__pcg_task_product, &job);
        pq = cloth__chunk_total(&job);
        if (!cloth__is_finite_double(pq) || !cloth__is_finite_double(delta)) { result = CLOTH_ERROR_NOT_FINITE; break; }
        if (!(pq > 0)) { result = CLOTH_ERROR_NOT_POSITIVE_DEFINITE; break; }
        alpha = delta / pq;
        job.alpha = (cloth_real)alpha;
        /* x += alpha p, r -= alpha q, and (block-)Jacobi: s = P^-1 r and r^T s in the same pass,
           too short to gain from the pool (a wake-up costs more): the same chunks on this
           thread. Multigrid: the update also loads the V-cycle's right-hand side and the
           V-cycle's store also sums r^T s, both on the pool, each chunk as a serial pass would
           make it (bit for bit); the V-cycle's own passes run there anyway. */
        if (mg) {
            job.fb = mg->level[0].b;
            job.fx = mg->level[0].x;
            cloth__pool_run(pool, chunks, cloth__pcg_task_update_load, &job);
            cloth__mg_vcycle_float(mg, constrained, d);
            cloth__pool_run(pool, chunks, cloth__pcg_task_store_dot, &job);
            delta_new = cloth__chunk_total(&job);
        } else {
            cloth__pool_run(NULL, chunks, cloth__pcg_task_update, &job);
            delta_new = cloth__chunk_total(&job);
        }
        beta = delta_new / delta;
        /* p = S (s + beta p) */
        job.beta = (cloth_real)beta;
        cloth__pool_run(NULL, chunks, cloth__pcg_task_direction, &job);
        delta = delta_new;
        ++st.iterations;
    }

    /* Re-impose the constrained part, so that rounding in the iterations does not drift it,
       and report the true residual of the returned x. */
    cloth__pcg_impose(n, constrained, d, z, x);
    st.residual = (cloth_real)sqrt(cloth__pcg_residual(pool, &job, x) / bhat2);
    st.preconditioned_residual = (cloth_real)sqrt(delta / delta0);
    st.converged = delta <= tol2 * scale2;
    if (stats) *stats = st;
    return result;
}


/* ------------------------------------------------------------------------------------- */
/* bvh                                                                                   */
/* ------------------------------------------------------------------------------------- */

#define CLOTH__BVH_DEF_COOKIE 0x42564831 /* "BVH1" */
#define CLOTH__BVH_BINS 16
/* From this depth on every split is a median split: each halves the count, and a tree has
   at most 2^30 triangles, so no leaf lies deeper than CLOTH_BVH_MAX_DEPTH - 2. */
#define CLOTH__BVH_MEDIAN_DEPTH (CLOTH_BVH_MAX_DEPTH / 2)
/* Traversal stacks, in node pairs. A self traversal leaves at most two pending tasks per
   level of the self part of its current path and one per step of its cross part (at most two
   steps per level), so 2 * depth + 3 entries; a pair traversal leaves one per step, so at most
   depth_a + depth_b + 2; a box query depth + 2. The sizes below have room to spare. */
#define CLOTH__BVH_SELF_STACK (4 * CLOTH_BVH_MAX_DEPTH + 8)
#define CLOTH__BVH_PAIR_STACK (2 * CLOTH_BVH_MAX_DEPTH + 8)
#define CLOTH__BVH_QUERY_STACK (CLOTH_BVH_MAX_DEPTH + 8)

CLOTH_API cloth_bvh_def cloth_default_bvh_def(void)
{
    cloth_bvh_def def;
    memset(&def, 0, sizeof def);
    def.thickness = 0;
    def.leaf_size = 2;
    def.split = CLOTH_BVH_SPLIT_SAH;
    def.rebuild_ratio = 2;
    def.internal_cookie = CLOTH__BVH_DEF_COOKIE;
    return def;
}

static cloth_real cloth__bvh_min(cloth_real a, cloth_real b) { return b < a ? b : a; }
static cloth_real cloth__bvh_max(cloth_real a, cloth_real b) { return b > a ? b : a; }

/* Closed intervals overlap on all three axes. */
static int cloth__bvh_overlap(const cloth_bvh_box *a, const cloth_bvh_box *b)
{
    return a->lo[0] <= b->hi[0] && b->lo[0] <= a->hi[0] &&
           a->lo[1] <= b->hi[1] && b->lo[1] <= a->hi[1] &&
           a->lo[2] <= b->hi[2] && b->lo[2] <= a->hi[2];
}

/* Half the surface area: the SAH only compares ratios of areas. */
static cloth_real cloth__bvh_half_area(const cloth_bvh_box *b)
{
    cloth_real dx = b->hi[0] - b->lo[0], dy = b->hi[1] - b->lo[1], dz = b->hi[2] - b->lo[2];
    return dx * dy + dy * dz + dz * dx;
}

static void cloth__bvh_box_empty(cloth_bvh_box *b)
{
    int k;
    for (k = 0; k < 3; ++k) { b->lo[k] = (cloth_real)HUGE_VAL; b->hi[k] = -(cloth_real)HUGE_VAL; }
}

static void cloth__bvh_box_grow(cloth_bvh_box *b, const cloth_bvh_box *add)
{
    int k;
    for (k = 0; k < 3; ++k) {
        b->lo[k] = cloth__bvh_min(b->lo[k], add->lo[k]);
        b->hi[k] = cloth__bvh_max(b->hi[k], add->hi[k]);
    }
}

static int cloth__bvh_def_valid(const cloth_bvh_def *def)
{
    return def->thickness >= 0 && cloth__is_finite(def->thickness) &&
           def->leaf_size >= 1 && def->leaf_size <= CLOTH_BVH_MAX_LEAF_SIZE &&
           (def->split == CLOTH_BVH_SPLIT_SAH || def->split == CLOTH_BVH_SPLIT_MEDIAN) &&
           def->rebuild_ratio >= 1;
}

static cloth_result cloth__bvh_check_positions(const cloth_real *x, int32_t vertex_count)
{
    size_t i, n = 3 * (size_t)vertex_count;
    for (i = 0; i < n; ++i)
        if (!cloth__is_finite(x[i])) return CLOTH_ERROR_NOT_FINITE;
    return CLOTH_SUCCESS;
}

/* What refit and rebuild check before they touch the tree. */
static cloth_result cloth__bvh_check_update(const cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1)
{
    cloth_result r;
    if (bvh->vertex_count > 0 && !x) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!(bvh->def.thickness >= 0) || !cloth__is_finite(bvh->def.thickness)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (bvh->vertex_count == 0) return CLOTH_SUCCESS;
    r = cloth__bvh_check_positions(x, bvh->vertex_count);
    if (r == CLOTH_SUCCESS && x1) r = cloth__bvh_check_positions(x1, bvh->vertex_count);
    return r;
}

/* Each item's box: its vertices at x (and x1), grown by the thickness. */
static void cloth__bvh_item_boxes(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1)
{
    const cloth_real t = bvh->def.thickness;
    int32_t i;
    for (i = 0; i < bvh->triangle_count; ++i) {
        const int32_t *v = bvh->item_vertex + 3 * (size_t)i;
        const cloth_real *p0 = x + 3 * (size_t)v[0], *p1 = x + 3 * (size_t)v[1], *p2 = x + 3 * (size_t)v[2];
        cloth_bvh_box *b = bvh->item_box + i;
        int k;
        for (k = 0; k < 3; ++k) {
            cloth_real lo = cloth__bvh_min(cloth__bvh_min(p0[k], p1[k]), p2[k]);
            cloth_real hi = cloth__bvh_max(cloth__bvh_max(p0[k], p1[k]), p2[k]);
            if (x1) {
                const cloth_real *q0 = x1 + 3 * (size_t)v[0], *q1 = x1 + 3 * (size_t)v[1], *q2 = x1 + 3 * (size_t)v[2];
                lo = cloth__bvh_min(lo, cloth__bvh_min(cloth__bvh_min(q0[k], q1[k]), q2[k]));
                hi = cloth__bvh_max(hi, cloth__bvh_max(cloth__bvh_max(q0[k], q1[k]), q2[k]));
            }
            b->lo[k] = lo - t;
            b->hi[k] = hi + t;
        }
    }
}

/* Node boxes bottom-up (children always follow their parent) and the cost: the SAH sum of the
   node areas (leaves weighted by their counts) over the sum of the items' areas. */
static void cloth__bvh_fit_nodes(cloth_bvh *bvh)
{
    cloth_real node_area = 0, item_area = 0, cost;
    int32_t i, internal_count = 0;
    for (i = bvh->node_count - 1; i >= 0; --i) {
        cloth_bvh_node *n = bvh->nodes + i;
        if (n->count > 0) {
            int32_t j;
            n->box = bvh->item_box[n->first];
            item_area += cloth__bvh_half_area(&n->box);
            for (j = 1; j < n->count; ++j) {
                cloth__bvh_box_grow(&n->box, bvh->item_box + n->first + j);
                item_area += cloth__bvh_half_area(bvh->item_box + n->first + j);
            }
            node_area += (cloth_real)n->count * cloth__bvh_half_area(&n->box);
        } else {
            n->box = bvh->nodes[n->first].box;
            cloth__bvh_box_grow(&n->box, &bvh->nodes[n->first + 1].box);
            node_area += cloth__bvh_half_area(&n->box);
            ++internal_count;
        }
    }
    cost = item_area > 0 ? node_area / item_area : (cloth_real)0;
    /* Boxes without area (thickness 0 and triangles that are segments or points), or areas
       beyond the range of cloth_real: every node counts as one item. */
    if (!(item_area > 0) || !cloth__is_finite(cost))
        cost = (cloth_real)internal_count + (cloth_real)bvh->triangle_count;
    bvh->cost = bvh->node_count > 0 ? cost : (cloth_real)0;
}

static void cloth__bvh_swap_items(cloth_bvh *bvh, int32_t i, int32_t j)
{
    cloth_bvh_box b = bvh->item_box[i];
    int32_t t = bvh->item_triangle[i], k;
    bvh->item_box[i] = bvh->item_box[j];
    bvh->item_box[j] = b;
    bvh->item_triangle[i] = bvh->item_triangle[j];
    bvh->item_triangle[j] = t;
    for (k = 0; k < 3; ++k) {
        t = bvh->item_vertex[3 * (size_t)i + k];
        bvh->item_vertex[3 * (size_t)i + k] = bvh->item_vertex[3 * (size_t)j + k];
        bvh->item_vertex[3 * (size_t)j + k] = t;
    }
}

/* Twice the centre of an item's box along an axis. */
static cloth_real cloth__bvh_centroid(const cloth_bvh *bvh, int32_t i, int axis)
{
    return bvh->item_box[i].lo[axis] + bvh->item_box[i].hi[axis];
}

static void cloth__bvh_centroid_bounds(const cloth_bvh *bvh, int32_t begin, int32_t end, cloth_real *cmin, cloth_real *cmax)
{
    int32_t i;
    int k;
    for (k = 0; k < 3; ++k) { cmin[k] = (cloth_real)HUGE_VAL; cmax[k] = -(cloth_real)HUGE_VAL; }
    for (i = begin; i < end; ++i)
        for (k = 0; k < 3; ++k) {
            cloth_real c = cloth__bvh_centroid(bvh, i, k);
            cmin[k] = cloth__bvh_min(cmin[k], c);
            cmax[k] = cloth__bvh_max(cmax[k], c);
        }
}

/* Items ordered by centroid along the axis, ties by triangle number: a strict order, so the
   median split does not depend on the order the items arrive in. */
static int cloth__bvh_item_less(const cloth_bvh *bvh, int32_t i, int32_t j, int axis)
{
    cloth_real ci = cloth__bvh_centroid(bvh, i, axis), cj = cloth__bvh_centroid(bvh, j, axis);
    if (ci < cj) return 1;
    if (cj < ci) return 0;
    return bvh->item_triangle[i] < bvh->item_triangle[j];
}

/* Split [begin, end) at its middle: quickselect (median of three pivots) along the longest
   axis of the centroids, so items before the middle sort before it and items after after. */
static int32_t cloth__bvh_split_median(cloth_bvh *bvh, int32_t begin, int32_t end)
{
    cloth_real cmin[3], cmax[3];
    int32_t lo = begin, hi = end - 1, mid = begin + (end - begin) / 2;
    int axis = 0, k;
    cloth__bvh_centroid_bounds(bvh, begin, end, cmin, cmax);
    for (k = 1; k < 3; ++k)
        if (cmax[k] - cmin[k] > cmax[axis] - cmin[axis]) axis = k;
    while (lo < hi) {
        int32_t p = lo + (hi - lo) / 2, store, i;
        if (cloth__bvh_item_less(bvh, p, lo, axis)) cloth__bvh_swap_items(bvh, p, lo);
        if (cloth__bvh_item_less(bvh, hi, lo, axis)) cloth__bvh_swap_items(bvh, hi, lo);
        if (cloth__bvh_item_less(bvh, hi, p, axis)) cloth__bvh_swap_items(bvh, hi, p);
        cloth__bvh_swap_items(bvh, p, hi); /* the median of the three is the pivot, at hi */
        store = lo;
        for (i = lo; i < hi; ++i)
            if (cloth__bvh_item_less(bvh, i, hi, axis)) cloth__bvh_swap_items(bvh, i, store++);
        cloth__bvh_swap_items(bvh, store, hi);
        if (store == mid) break;
        if (mid < store) hi = store - 1;
        else lo = store + 1;
    }
    return mid;
}

static int cloth__bvh_bin(cloth_real c, cloth_real cmin, cloth_real scale)
{
    cloth_real t = (c - cmin) * scale;
    if (!(t > 0)) return 0;
    if (t >= (cloth_real)(CLOTH__BVH_BINS - 1)) return CLOTH__BVH_BINS - 1;
    return (int)t;
}

/* Split [begin, end) by the binned surface area heuristic: on each axis the centroids are
   sorted into CLOTH__BVH_BINS equal bins and every plane between bins is costed as
   area(left) * count(left) + area(right) * count(right); the cheapest wins, ties going to
   the more even split, then to the lower axis and plane. Falls back to the median split when
   the centroids do not spread. Returns the first item of the right half. */
static int32_t cloth__bvh_split_sah(cloth_bvh *bvh, int32_t begin, int32_t end)
{
    cloth_bvh_box bin_box[CLOTH__BVH_BINS];
    int32_t bin_count[CLOTH__BVH_BINS], right_count[CLOTH__BVH_BINS];
    cloth_real right_area[CLOTH__BVH_BINS];
    cloth_real cmin[3], cmax[3], scale[3], best_cost = 0;
    int32_t best_balance = 0, i, j;
    int axis, b, best_axis = -1, best_bin = 0;
    cloth__bvh_centroid_bounds(bvh, begin, end, cmin, cmax);
    for (axis = 0; axis < 3; ++axis) {
        cloth_real extent = cmax[axis] - cmin[axis];
        cloth_bvh_box acc;
        int32_t count;
        scale[axis] = 0;
        if (!(extent > 0)) continue;
        scale[axis] = (cloth_real)CLOTH__BVH_BINS / extent;
        if (!cloth__is_finite(scale[axis])) continue;
        for (b = 0; b < CLOTH__BVH_BINS; ++b) { bin_count[b] = 0; cloth__bvh_box_empty(&bin_box[b]); }
        for (i = begin; i < end; ++i) {
            b = cloth__bvh_bin(cloth__bvh_centroid(bvh, i, axis), cmin[axis], scale[axis]);
            ++bin_count[b];
            cloth__bvh_box_grow(&bin_box[b], bvh->item_box + i);
        }
        cloth__bvh_box_empty(&acc);
        count = 0;
        for (b = CLOTH__BVH_BINS - 1; b > 0; --b) {
            if (bin_count[b] > 0) { cloth__bvh_box_grow(&acc, &bin_box[b]); count += bin_count[b]; }
            right_count[b] = count;
            right_area[b] = count > 0 ? cloth__bvh_half_area(&acc) : (cloth_real)0;
        }
        cloth__bvh_box_empty(&acc);
        count = 0;
        for (b = 1; b < CLOTH__BVH_BINS; ++b) {
            cloth_real cost;
            int32_t balance;
            if (bin_count[b - 1] > 0) { cloth__bvh_box_grow(&acc, &bin_box[b - 1]); count += bin_count[b - 1]; }
            if (count == 0 || right_count[b] == 0) continue;
            cost = cloth__bvh_half_area(&acc) * (cloth_real)count + right_area[b] * (cloth_real)right_count[b];
            balance = count > right_count[b] ? count - right_count[b] : right_count[b] - count;
            if (best_axis < 0 || cost < best_cost || (cost == best_cost && balance < best_balance)) {
                best_axis = axis;
                best_bin = b;
                best_cost = cost;
                best_balance = balance;
            }
        }
    }
    if (best_axis < 0) return cloth__bvh_split_median(bvh, begin, end);
    /* Items in bins below best_bin go left; the bins were filled by the same computation. */
    i = begin;
    j = end - 1;
    while (i <= j) {
        if (cloth__bvh_bin(cloth__bvh_centroid(bvh, i, best_axis), cmin[best_axis], scale[best_axis]) < best_bin) ++i;
        else cloth__bvh_swap_items(bvh, i, j--);
    }
    /* Both sides are non-empty as binned; should a compiler evaluate the two binnings at
       different precisions (x87), never make an empty node. */
    if (i == begin || i == end) return cloth__bvh_split_median(bvh, begin, end);
    return i;
}

typedef struct cloth__bvh_task { int32_t node, begin, end, depth; } cloth__bvh_task;

/* Make the nodes over the items (whose boxes are current), reordering the items so that each
   leaf's are contiguous. Children are made in pairs after their parent. */
static void cloth__bvh_build_nodes(cloth_bvh *bvh)
{
    cloth__bvh_task stack[CLOTH_BVH_MAX_DEPTH + 2];
    int top = 0;
    int32_t node_count = 0, depth = 0;
    if (bvh->triangle_count > 0) {
        stack[0].node = 0;
        stack[0].begin = 0;
        stack[0].end = bvh->triangle_count;
        stack[0].depth = 0;
        top = 1;
        node_count = 1;
    }
    while (top > 0) {
        cloth__bvh_task t = stack[--top];
        cloth_bvh_node *n = bvh->nodes + t.node;
        int32_t mid, child;
        if (t.depth > depth) depth = t.depth;
        if (t.end - t.begin <= bvh->def.leaf_size) {
            n->first = t.begin;
            n->count = t.end - t.begin;
            continue;
        }
        if (bvh->def.split == CLOTH_BVH_SPLIT_SAH && t.depth < CLOTH__BVH_MEDIAN_DEPTH)
            mid = cloth__bvh_split_sah(bvh, t.begin, t.end);
        else
            mid = cloth__bvh_split_median(bvh, t.begin, t.end);
        child = node_count;
        node_count += 2;
        n->first = child;
        n->count = 0;
        CLOTH_ASSERT(top + 2 <= (int)(sizeof stack / sizeof stack[0]));
        stack[top].node = child + 1;
        stack[top].begin = mid;
        stack[top].end = t.end;
        stack[top].depth = t.depth + 1;
        ++top;
        stack[top].node = child;
        stack[top].begin = t.begin;
        stack[top].end = mid;
        stack[top].depth = t.depth + 1;
        ++top;
    }
    bvh->node_count = node_count;
    bvh->depth = depth;
}

CLOTH_API void cloth_bvh_free(cloth_bvh *bvh)
{
    if (!bvh) return;
    if (bvh->allocator.free) {
        cloth__free(&bvh->allocator, bvh->nodes);
        cloth__free(&bvh->allocator, bvh->item_box);
        cloth__free(&bvh->allocator, bvh->item_triangle);
        cloth__free(&bvh->allocator, bvh->item_vertex);
    }
    memset(bvh, 0, sizeof *bvh);
}

CLOTH_API cloth_result cloth_bvh_build(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1, int32_t vertex_count,
                                       const int32_t *tri, int32_t triangle_count, const cloth_bvh_def *def,
                                       const cloth_allocator *allocator)
{
    cloth_bvh_def d;
    cloth_result r;
    size_t k, m3;
    int32_t i;
    CLOTH_ASSERT(bvh);
    memset(bvh, 0, sizeof *bvh);
    if (def) {
        CLOTH_ASSERT(def->internal_cookie == CLOTH__BVH_DEF_COOKIE); /* made by cloth_default_bvh_def? */
        if (def->internal_cookie != CLOTH__BVH_DEF_COOKIE) return CLOTH_ERROR_INVALID_ARGUMENT;
        d = *def;
    } else {
        d = cloth_default_bvh_def();
    }
    if (vertex_count < 0 || triangle_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    if ((vertex_count > 0 && !x) || (triangle_count > 0 && !tri)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!cloth__bvh_def_valid(&d)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (triangle_count > ((int32_t)1 << 30)) return CLOTH_ERROR_SIZE_OVERFLOW;
    m3 = 3 * (size_t)triangle_count;
    for (k = 0; k < m3; ++k)
        if (tri[k] < 0 || tri[k] >= vertex_count) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (vertex_count > 0) {
        r = cloth__bvh_check_positions(x, vertex_count);
        if (r == CLOTH_SUCCESS && x1) r = cloth__bvh_check_positions(x1, vertex_count);
        if (r != CLOTH_SUCCESS) return r;
    }

    bvh->allocator = cloth__allocator_or_default(allocator);
    bvh->nodes = (cloth_bvh_node *)cloth__alloc_array(&bvh->allocator, triangle_count > 0 ? 2 * (size_t)triangle_count - 1 : 0,
                                                      sizeof(cloth_bvh_node));
    bvh->item_box = (cloth_bvh_box *)cloth__alloc_array(&bvh->allocator, (size_t)triangle_count, sizeof(cloth_bvh_box));
    bvh->item_triangle = (int32_t *)cloth__alloc_array(&bvh->allocator, (size_t)triangle_count, sizeof(int32_t));
    bvh->item_vertex = (int32_t *)cloth__alloc_array(&bvh->allocator, m3, sizeof(int32_t));
    if (!bvh->nodes || !bvh->item_box || !bvh->item_triangle || !bvh->item_vertex) {
        cloth_bvh_free(bvh);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    bvh->vertex_count = vertex_count;
    bvh->triangle_count = triangle_count;
    bvh->def = d;
    for (i = 0; i < triangle_count; ++i) bvh->item_triangle[i] = i;
    if (m3 > 0) memcpy(bvh->item_vertex, tri, m3 * sizeof(int32_t));
    cloth__bvh_item_boxes(bvh, x, x1);
    cloth__bvh_build_nodes(bvh);
    cloth__bvh_fit_nodes(bvh);
    bvh->build_cost = bvh->cost;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_bvh_refit(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1)
{
    cloth_result r;
    CLOTH_ASSERT(bvh);
    r = cloth__bvh_check_update(bvh, x, x1);
    if (r != CLOTH_SUCCESS) return r;
    cloth__bvh_item_boxes(bvh, x, x1);
    cloth__bvh_fit_nodes(bvh);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_bvh_rebuild(cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1)
{
    cloth_result r;
    CLOTH_ASSERT(bvh);
    if (!cloth__bvh_def_valid(&bvh->def)) return CLOTH_ERROR_INVALID_ARGUMENT;
    r = cloth__bvh_check_update(bvh, x, x1);
    if (r != CLOTH_SUCCESS) return r;
    /* Back to the triangles' own order, so that the result equals a fresh build. The slots
       hold a permutation of the triangles: follow its cycles. */
    {
        int32_t i;
        for (i = 0; i < bvh->triangle_count; ++i)
            while (bvh->item_triangle[i] != i) cloth__bvh_swap_items(bvh, i, bvh->item_triangle[i]);
    }
    cloth__bvh_item_boxes(bvh, x, x1);
    cloth__bvh_build_nodes(bvh);
    cloth__bvh_fit_nodes(bvh);
    bvh->build_cost = bvh->cost;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_real cloth_bvh_quality(const cloth_bvh *bvh)
{
    CLOTH_ASSERT(bvh);
    if (bvh->node_count == 0 || !(bvh->build_cost > 0)) return 1;
    return bvh->cost / bvh->build_cost;
}

CLOTH_API int cloth_bvh_needs_rebuild(const cloth_bvh *bvh)
{
    CLOTH_ASSERT(bvh);
    return cloth_bvh_quality(bvh) > bvh->def.rebuild_ratio;
}

/* Whether two triangles share a vertex. */
static int cloth__bvh_adjacent(const int32_t *vi, const int32_t *vj)
{
    return vi[0] == vj[0] || vi[0] == vj[1] || vi[0] == vj[2] ||
           vi[1] == vj[0] || vi[1] == vj[1] || vi[1] == vj[2] ||
           vi[2] == vj[0] || vi[2] == vj[1] || vi[2] == vj[2];
}

/* Report the pair of slots i, j of one tree as triangles a < b, unless adjacent. */
static int cloth__bvh_self_item_pair(const cloth_bvh *bvh, int32_t i, int32_t j, cloth_bvh_pair_fn fn, void *user)
{
    int32_t a, b;
    if (!cloth__bvh_overlap(bvh->item_box + i, bvh->item_box + j)) return 0;
    if (cloth__bvh_adjacent(bvh->item_vertex + 3 * (size_t)i, bvh->item_vertex + 3 * (size_t)j)) return 0;
    a = bvh->item_triangle[i];
    b = bvh->item_triangle[j];
    return a < b ? fn(a, b, user) : fn(b, a, user);
}

/* cloth_bvh_self_pairs, leaving out the pairs of nodes that are both unmarked when node_mark
   is given (a node marked when any triangle under it is): the pairs left come in the same
   order as without marks. */
static int cloth__bvh_self_pairs_from(const cloth_bvh *bvh, const unsigned char *node_mark, int32_t seed_a,
                                      int32_t seed_b, cloth_bvh_pair_fn fn, void *user)
{
    int32_t stack[2 * CLOTH__BVH_SELF_STACK];
    int top = 0, r;
    CLOTH_ASSERT(bvh && fn);
    CLOTH_ASSERT(bvh->depth <= CLOTH_BVH_MAX_DEPTH);
    if (bvh->node_count == 0) return 0;
    stack[0] = seed_a;
    stack[1] = seed_b;
    top = 1;
    while (top > 0) {
        int32_t ia, ib;
        const cloth_bvh_node *a, *b;
        --top;
        ia = stack[2 * top];
        ib = stack[2 * top + 1];
        if (node_mark && !node_mark[ia] && !node_mark[ib]) continue;
        a = bvh->nodes + ia;
        b = bvh->nodes + ib;
        CLOTH_ASSERT(top + 3 <= CLOTH__BVH_SELF_STACK);
        if (ia == ib) { /* the pairs inside one subtree */
            if (a->count > 0) {
                int32_t i, j, end = a->first + a->count;
                for (i = a->first; i < end; ++i)
                    for (j = i + 1; j < end; ++j)
                        if ((r = cloth__bvh_self_item_pair(bvh, i, j, fn, user)) != 0) return r;
            } else {
                int32_t c = a->first;
                stack[2 * top] = c; stack[2 * top + 1] = c + 1; ++top;
                stack[2 * top] = c + 1; stack[2 * top + 1] = c + 1; ++top;
                stack[2 * top] = c; stack[2 * top + 1] = c; ++top;
            }
            continue;
        }
        /* the pairs between two disjoint subtrees */
        if (!cloth__bvh_overlap(&a->box, &b->box)) continue;
        if (a->count > 0 && b->count > 0) {
            int32_t i, j, end_a = a->first + a->count, end_b = b->first + b->count;
            for (i = a->first; i < end_a; ++i) {
                if (!cloth__bvh_overlap(bvh->item_box + i, &b->box)) continue;
                for (j = b->first; j < end_b; ++j)
                    if ((r = cloth__bvh_self_item_pair(bvh, i, j, fn, user)) != 0) return r;
            }
        } else if (b->count > 0 || (a->count == 0 && cloth__bvh_half_area(&a->box) >= cloth__bvh_half_area(&b->box))) {
            stack[2 * top] = a->first + 1; stack[2 * top + 1] = ib; ++top;
            stack[2 * top] = a->first; stack[2 * top + 1] = ib; ++top;
        } else {
            stack[2 * top] = ia; stack[2 * top + 1] = b->first + 1; ++top;
            stack[2 * top] = ia; stack[2 * top + 1] = b->first; ++top;
        }
    }
    return 0;
}

static int cloth__bvh_self_pairs_marked(const cloth_bvh *bvh, const unsigned char *node_mark, cloth_bvh_pair_fn fn,
                                        void *user)
{
    return cloth__bvh_self_pairs_from(bvh, node_mark, 0, 0, fn, user);
}

/* The self traversal cut into node pairs (seeds, 2 each) whose traversals one after another
   (cloth__bvh_self_pairs_from) give the whole traversal's pairs in its order: from the root
   pair, level by level, each pair replaced by the pairs the traversal pushes for it, in the
   order it pops them, and dropped where the traversal would skip it (no mark, boxes apart);
   a pair of leaves stays. Stops once there are `want` seeds or more, or nothing splits. seeds
   and scratch hold 6 want entries each. Returns the number of seeds. */
static int32_t cloth__bvh_self_seeds(const cloth_bvh *bvh, const unsigned char *node_mark, int32_t want, int32_t *out,
                                     int32_t *scratch)
{
    int32_t count = 0, k, *seeds = out;
    int split = 1;
    if (bvh->node_count == 0) return 0;
    seeds[0] = seeds[1] = 0;
    count = 1;
    while (count < want && split) {
        int32_t next = 0, *t;
        split = 0;
        for (k = 0; k < count; ++k) {
            const int32_t ia = seeds[2 * k], ib = seeds[2 * k + 1];
            const cloth_bvh_node *a = bvh->nodes + ia, *b = bvh->nodes + ib;
#define CLOTH__SEED(u, v) (scratch[2 * next] = (u), scratch[2 * next + 1] = (v), ++next)
            if (node_mark && !node_mark[ia] && !node_mark[ib]) continue;
            if (ia == ib) {
                if (a->count > 0) { CLOTH__SEED(ia, ib); continue; }
                CLOTH__SEED(a->first, a->first);
                CLOTH__SEED(a->first + 1, a->first + 1);
                CLOTH__SEED(a->first, a->first + 1);
            } else if (!cloth__bvh_overlap(&a->box, &b->box)) {
                continue;
            } else if (a->count > 0 && b->count > 0) {
                CLOTH__SEED(ia, ib);
                continue;
            } else if (b->count > 0 || (a->count == 0 && cloth__bvh_half_area(&a->box) >= cloth__bvh_half_area(&b->box))) {
                CLOTH__SEED(a->first, ib);
                CLOTH__SEED(a->first + 1, ib);
            } else {
                CLOTH__SEED(ia, b->first);
                CLOTH__SEED(ia, b->first + 1);
            }
#undef CLOTH__SEED
            split = 1;
        }
        t = seeds;
        seeds = scratch;
        scratch = t;
        count = next;
    }
    /* after an odd number of rounds the last level is in the caller's scratch */
    if (seeds != out) memcpy(out, seeds, 2 * (size_t)count * sizeof(int32_t));
    return count;
}

CLOTH_API int cloth_bvh_self_pairs(const cloth_bvh *bvh, cloth_bvh_pair_fn fn, void *user)
{
    return cloth__bvh_self_pairs_marked(bvh, NULL, fn, user);
}

CLOTH_API int cloth_bvh_pairs(const cloth_bvh *tree_a, const cloth_bvh *tree_b, cloth_bvh_pair_fn fn, void *user)
{
    int32_t stack[2 * CLOTH__BVH_PAIR_STACK];
    int top, r;
    CLOTH_ASSERT(tree_a && tree_b && fn);
    CLOTH_ASSERT(tree_a->depth <= CLOTH_BVH_MAX_DEPTH && tree_b->depth <= CLOTH_BVH_MAX_DEPTH);
    if (tree_a->node_count == 0 || tree_b->node_count == 0) return 0;
    stack[0] = 0;
    stack[1] = 0;
    top = 1;
    while (top > 0) {
        int32_t ia, ib;
        const cloth_bvh_node *a, *b;
        --top;
        ia = stack[2 * top];
        ib = stack[2 * top + 1];
        a = tree_a->nodes + ia;
        b = tree_b->nodes + ib;
        if (!cloth__bvh_overlap(&a->box, &b->box)) continue;
        CLOTH_ASSERT(top + 2 <= CLOTH__BVH_PAIR_STACK);
        if (a->count > 0 && b->count > 0) {
            int32_t i, j, end_a = a->first + a->count, end_b = b->first + b->count;
            for (i = a->first; i < end_a; ++i) {
                if (!cloth__bvh_overlap(tree_a->item_box + i, &b->box)) continue;
                for (j = b->first; j < end_b; ++j)
                    if (cloth__bvh_overlap(tree_a->item_box + i, tree_b->item_box + j) &&
                        (r = fn(tree_a->item_triangle[i], tree_b->item_triangle[j], user)) != 0)
                        return r;
            }
        } else if (b->count > 0 || (a->count == 0 && cloth__bvh_half_area(&a->box) >= cloth__bvh_half_area(&b->box))) {
            stack[2 * top] = a->first + 1; stack[2 * top + 1] = ib; ++top;
            stack[2 * top] = a->first; stack[2 * top + 1] = ib; ++top;
        } else {
            stack[2 * top] = ia; stack[2 * top + 1] = b->first + 1; ++top;
            stack[2 * top] = ia; stack[2 * top + 1] = b->first; ++top;
        }
    }
    return 0;
}

CLOTH_API int cloth_bvh_query_box(const cloth_bvh *bvh, const cloth_real lo[3], const cloth_real hi[3],
                                  cloth_bvh_triangle_fn fn, void *user)
{
    int32_t stack[CLOTH__BVH_QUERY_STACK];
    cloth_bvh_box q;
    int top, r, k;
    CLOTH_ASSERT(bvh && lo && hi && fn);
    CLOTH_ASSERT(bvh->depth <= CLOTH_BVH_MAX_DEPTH);
    if (bvh->node_count == 0) return 0;
    for (k = 0; k < 3; ++k) { q.lo[k] = lo[k]; q.hi[k] = hi[k]; }
    stack[0] = 0;
    top = 1;
    while (top > 0) {
        const cloth_bvh_node *n = bvh->nodes + stack[--top];
        if (!cloth__bvh_overlap(&n->box, &q)) continue;
        if (n->count > 0) {
            int32_t i, end = n->first + n->count;
            for (i = n->first; i < end; ++i)
                if (cloth__bvh_overlap(bvh->item_box + i, &q) && (r = fn(bvh->item_triangle[i], user)) != 0) return r;
        } else {
            CLOTH_ASSERT(top + 2 <= CLOTH__BVH_QUERY_STACK);
            stack[top++] = n->first + 1;
            stack[top++] = n->first;
        }
    }
    return 0;
}

/* ------------------------------------------------------------------------------------- */
/* ccd                                                                                   */
/* ------------------------------------------------------------------------------------- */

/* Everything here computes in double whatever cloth_real is (float inputs convert exactly). */

static void cloth__d3_sub(const double *a, const double *b, double *out)
{ out[0] = a[0] - b[0]; out[1] = a[1] - b[1]; out[2] = a[2] - b[2]; }
static double cloth__d3_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static void cloth__d3_cross(const double *a, const double *b, double *out)
{
    double c0 = a[1] * b[2] - a[2] * b[1];
    double c1 = a[2] * b[0] - a[0] * b[2];
    double c2 = a[0] * b[1] - a[1] * b[0];
    out[0] = c0; out[1] = c1; out[2] = c2;
}
/* |a + s e - p|^2 */
static double cloth__d3_dist2_along(const double *p, const double *a, const double *e, double s)
{
    double d[3];
    d[0] = a[0] + s * e[0] - p[0];
    d[1] = a[1] + s * e[1] - p[1];
    d[2] = a[2] + s * e[2] - p[2];
    return cloth__d3_dot(d, d);
}

/* ---- proximity ---------------------------------------------------------------------- */

/* Copies n points into double and scales them by one power of two so that the largest
   magnitude lies in [0.5, 1): the squares and cross products of the largest differences then
   neither overflow nor underflow, whatever the scale of the input. Returns the
   power of two to scale distances back with (0 for all-zero input), or INT_MIN when an input
   is not finite. */
static int cloth__prox_load(const cloth_real *const *in, int n, double (*out)[3])
{
    double m = 0;
    int i, k, e = 0;
    for (i = 0; i < n; ++i)
        for (k = 0; k < 3; ++k) {
            if (!cloth__is_finite(in[i][k])) return INT_MIN;
            out[i][k] = (double)in[i][k];
            if (fabs(out[i][k]) > m) m = fabs(out[i][k]);
        }
    if (m == 0) return 0;
    (void)frexp(m, &e);
    if (e > -1000 && e < 1000) {
        /* a product with 2^-e, itself exact here, rounds as ldexp does */
        const double scale = ldexp(1.0, -e);
        for (i = 0; i < n; ++i)
            for (k = 0; k < 3; ++k) out[i][k] *= scale;
    } else {
        for (i = 0; i < n; ++i)
            for (k = 0; k < 3; ++k) out[i][k] = ldexp(out[i][k], -e);
    }
    return e;
}

/* Closest point of segment a + s (b - a), s in [0,1], to p: returns the squared distance and s.
   A zero-length segment is its point a. */
static double cloth__point_segment(const double *p, const double *a, const double *b, double *s_out)
{
    double e[3], w[3], ee, s = 0;
    cloth__d3_sub(b, a, e);
    cloth__d3_sub(p, a, w);
    ee = cloth__d3_dot(e, e);
    if (ee > 0) {
        s = cloth__d3_dot(w, e) / ee;
        s = s < 0 ? 0 : (s > 1 ? 1 : s);
    }
    *s_out = s;
    return cloth__d3_dist2_along(p, a, e, s);
}

CLOTH_API cloth_real cloth_distance_vertex_face(const cloth_real p[3], const cloth_real f0[3], const cloth_real f1[3],
                                                const cloth_real f2[3], cloth_real weights[3])
{
    /* The closest point is the projection onto the plane when that falls inside the triangle,
       and otherwise lies on an edge. All four candidates are tried and the nearest kept, so a
       degenerate or nearly degenerate triangle (no usable plane) falls back on its edges, and
       the distance returned is always measured to the point the weights name. */
    const cloth_real *in[4];
    double x[4][3], w[3], best, d2, s;
    double e1[3], e2[3], r[3], n[3], c[3], nn;
    int e;
    in[0] = p; in[1] = f0; in[2] = f1; in[3] = f2;
    CLOTH_ASSERT(p && f0 && f1 && f2);
    e = cloth__prox_load(in, 4, x);
    if (e == INT_MIN) {
        if (weights) weights[0] = weights[1] = weights[2] = (cloth_real)NAN;
        return (cloth_real)NAN;
    }
    best = -1;
    w[0] = 1; w[1] = 0; w[2] = 0;
    cloth__d3_sub(x[2], x[1], e1);
    cloth__d3_sub(x[3], x[1], e2);
    cloth__d3_sub(x[0], x[1], r);
    cloth__d3_cross(e1, e2, n);
    nn = cloth__d3_dot(n, n);
    if (nn > 0) {
        double u, v;
        cloth__d3_cross(r, e2, c);
        u = cloth__d3_dot(c, n) / nn;
        cloth__d3_cross(e1, r, c);
        v = cloth__d3_dot(c, n) / nn;
        if (u >= 0 && v >= 0 && u + v <= 1) {
            double q[3];
            int k;
            for (k = 0; k < 3; ++k) q[k] = x[1][k] + u * e1[k] + v * e2[k];
            cloth__d3_sub(x[0], q, q);
            best = cloth__d3_dot(q, q);
            w[0] = 1 - (u + v); w[1] = u; w[2] = v;
        }
    }
    d2 = cloth__point_segment(x[0], x[1], x[2], &s);
    if (best < 0 || d2 < best) { best = d2; w[0] = 1 - s; w[1] = s; w[2] = 0; }
    d2 = cloth__point_segment(x[0], x[2], x[3], &s);
    if (d2 < best) { best = d2; w[0] = 0; w[1] = 1 - s; w[2] = s; }
    d2 = cloth__point_segment(x[0], x[3], x[1], &s);
    if (d2 < best) { best = d2; w[0] = s; w[1] = 0; w[2] = 1 - s; }
    if (weights) { weights[0] = (cloth_real)w[0]; weights[1] = (cloth_real)w[1]; weights[2] = (cloth_real)w[2]; }
    return (cloth_real)ldexp(sqrt(best), e);
}

CLOTH_API cloth_real cloth_distance_edge_edge(const cloth_real a0[3], const cloth_real a1[3], const cloth_real b0[3],
                                              const cloth_real b1[3], cloth_real params[2])
{
    /* The squared distance is a convex quadratic over (s,t) in [0,1]^2: its minimum is the
       interior critical point when the segments are not parallel and that point lies in the
       square, and otherwise lies on a side of the square, where one endpoint is fixed and the
       problem is point-segment. Parallel and zero-length segments have no usable critical
       point and are answered by the sides alone. */
    const cloth_real *in[4];
    double x[4][3], ea[3], eb[3], r[3], n[3], c[3], nn, best = -1, d2, s = 0, t = 0, u;
    int e;
    in[0] = a0; in[1] = a1; in[2] = b0; in[3] = b1;
    CLOTH_ASSERT(a0 && a1 && b0 && b1);
    e = cloth__prox_load(in, 4, x);
    if (e == INT_MIN) {
        if (params) params[0] = params[1] = (cloth_real)NAN;
        return (cloth_real)NAN;
    }
    cloth__d3_sub(x[1], x[0], ea);
    cloth__d3_sub(x[3], x[2], eb);
    cloth__d3_sub(x[2], x[0], r);
    cloth__d3_cross(ea, eb, n);
    nn = cloth__d3_dot(n, n);
    if (nn > 0) {
        double si, ti;
        cloth__d3_cross(r, eb, c);
        si = cloth__d3_dot(c, n) / nn;
        cloth__d3_cross(r, ea, c);
        ti = cloth__d3_dot(c, n) / nn;
        if (si >= 0 && si <= 1 && ti >= 0 && ti <= 1) {
            double d[3];
            int k;
            for (k = 0; k < 3; ++k) d[k] = (x[0][k] + si * ea[k]) - (x[2][k] + ti * eb[k]);
            best = cloth__d3_dot(d, d);
            s = si; t = ti;
        }
    }
    d2 = cloth__point_segment(x[0], x[2], x[3], &u);
    if (best < 0 || d2 < best) { best = d2; s = 0; t = u; }
    d2 = cloth__point_segment(x[1], x[2], x[3], &u);
    if (d2 < best) { best = d2; s = 1; t = u; }
    d2 = cloth__point_segment(x[2], x[0], x[1], &u);
    if (d2 < best) { best = d2; s = u; t = 0; }
    d2 = cloth__point_segment(x[3], x[0], x[1], &u);
    if (d2 < best) { best = d2; s = u; t = 1; }
    if (params) { params[0] = (cloth_real)s; params[1] = (cloth_real)t; }
    return (cloth_real)ldexp(sqrt(best), e);
}

/* ---- continuous collision detection ------------------------------------------------- */

#define CLOTH__CCD_COOKIE 0x43434431
#define CLOTH__CCD_MAX_COORDINATE 1e300
/* A box side is not split below 2^-50, so a box is at most about 3 * 51 splits deep (a rounded
   midpoint may leave a half slightly wider than half). */
#define CLOTH__CCD_MIN_WIDTH (1.0 / 1125899906842624.0)
/* The depth-first stack holds at most one box per level plus one; the heap of waiting boxes
   has a fixed size too: a query uses about 35 KB of the caller's stack and allocates nothing. */
#define CLOTH__CCD_STACK 200
#define CLOTH__CCD_HEAP 512

CLOTH_API cloth_ccd_options cloth_ccd_default_options(void)
{
    cloth_ccd_options o;
    o.tolerance = (cloth_real)1e-6;
    o.max_checks = 1000000;
    o.refine_checks = 62500;
    o.minimum_separation = 0;
    o.internal_cookie = CLOTH__CCD_COOKIE;
    return o;
}

/* A box of the parameter domain. */
typedef struct cloth__ccd_box { double t0, t1, u0, u1, v0, v1; } cloth__ccd_box;

/* A query ready for the search: vertex positions at t = 0 and their motion over the step, in
   the order p, f0, f1, f2 (vertex-face) or a0, a1, b0, b1 (edge-edge). */
typedef struct cloth__ccd_problem {
    int edge_edge;
    double x0[3][4];  /* x0[k][j]: axis k of vertex j at t = 0 */
    double dx[3][4];  /* fl(x1 - x0) */
    double reach[3];  /* >= minimum separation + error bound on axis k: a box is dropped when F_k
                         on it lies wholly above reach or wholly below -reach */
    double eps[3];    /* the error bound alone */
    double separation;
} cloth__ccd_problem;

/* The error bound. Let U = 2^-53 (unit roundoff), M the largest magnitude of the eight input
   coordinates on an axis, and t, u, v exact doubles in [0,1]. The corner values are computed as

       x(t) = x0 + t * fl(x1 - x0)                                   for each vertex
       vertex-face:  F = ((p(t) - f0(t)) - u * (f1(t) - f0(t))) - v * (f2(t) - f0(t))
       edge-edge:    F = (a0(t) + u * (a1(t) - a0(t))) - (b0(t) + v * (b1(t) - b0(t)))

   Carrying a bound B on the exact value and E on the error of each intermediate through
   |fl(a +- b) - (a +- b)| <= Ea + Eb + U (Ba + Bb + Ea + Eb) and
   |fl(a b) - a b| <= Ba Eb + Bb Ea + Ea Eb + U (Ba + Ea)(Bb + Eb):
   fl(x1 - x0): B 2M, E 2UM;  t * that: E 4UM;  x(t): B M (a convex combination), E 5UM;
   vertex-face: differences of two x(t): B 2M, E 12UM; u or v times one: E 14UM;
   (p - f0) - u (f1 - f0): B 2M, E 28UM; F: B 4M (u + v may reach 2 in a box), E 46UM;
   edge-edge: a0 + u (a1 - a0): B M, E 20UM; F: B 2M, E 42UM; each to first order, the
   second-order terms being below 100 U^2 M. So 64 U M = 32 DBL_EPSILON M bounds the error of
   every corner value. A fused multiply-add rounds once where two operations rounded, and its
   error is at most U times the magnitude bound already charged to the sum, so the bound also
   holds under -ffp-contract=fast. Underflow adds at most 2^-1075 per product (DBL_MIN per
   operation even with flush-to-zero), covered by the 64 DBL_MIN term. The exact F over a box
   lies between its smallest and largest exact corner values (F is multilinear), hence within
   [min computed - eps, max computed + eps]. */
static void cloth__ccd_setup(cloth__ccd_problem *q, int edge_edge, const double (*x)[3], double separation)
{
    int j, k;
    q->edge_edge = edge_edge;
    q->separation = separation;
    for (k = 0; k < 3; ++k) {
        double m = 0;
        for (j = 0; j < 4; ++j) {
            q->x0[k][j] = x[j][k];
            q->dx[k][j] = x[4 + j][k] - x[j][k];
            if (fabs(x[j][k]) > m) m = fabs(x[j][k]);
            if (fabs(x[4 + j][k]) > m) m = fabs(x[4 + j][k]);
        }
        q->eps[k] = 32 * DBL_EPSILON * m + 64 * DBL_MIN;
        /* fl(d + eps) >= (d + eps)(1 - U); the product with 1 + 8U, rounded, is >= d + eps. */
        q->reach[k] = (separation + q->eps[k]) * (1 + 4 * DBL_EPSILON);
    }
}

/* Corner values of F over box b on all three axes, corner[k][4 it + 2 iu + iv] with it, iu,
   iv = 0 for the lower bound of t, u, v and 1 for the upper; lo and hi are their extremes.
   Returns 0 when the box is proven free of collisions on some axis (then later axes are left
   unevaluated) or along a fourth direction, 1 otherwise. */
static int cloth__ccd_check(const cloth__ccd_problem *q, const cloth__ccd_box *b, double lo[3], double hi[3],
                            double corner[3][8])
{
    double ts[2], us[2], vs[2];
    int k, it, iu, iv, j;
    ts[0] = b->t0; ts[1] = b->t1; us[0] = b->u0; us[1] = b->u1; vs[0] = b->v0; vs[1] = b->v1;
    for (k = 0; k < 3; ++k) {
        double mn, mx;
        for (it = 0; it < 2; ++it) {
            double xt[4];
            for (j = 0; j < 4; ++j) xt[j] = q->x0[k][j] + ts[it] * q->dx[k][j];
            if (q->edge_edge) {
                double da = xt[1] - xt[0], db = xt[3] - xt[2];
                for (iu = 0; iu < 2; ++iu) {
                    double pa = xt[0] + us[iu] * da;
                    for (iv = 0; iv < 2; ++iv) corner[k][4 * it + 2 * iu + iv] = pa - (xt[2] + vs[iv] * db);
                }
            } else {
                double w = xt[0] - xt[1], e1 = xt[2] - xt[1], e2 = xt[3] - xt[1];
                for (iu = 0; iu < 2; ++iu) {
                    double s = w - us[iu] * e1;
                    for (iv = 0; iv < 2; ++iv) corner[k][4 * it + 2 * iu + iv] = s - vs[iv] * e2;
                }
            }
        }
        mn = mx = corner[k][0];
        for (j = 1; j < 8; ++j) {
            if (corner[k][j] < mn) mn = corner[k][j];
            if (corner[k][j] > mx) mx = corner[k][j];
        }
        lo[k] = mn; hi[k] = mx;
        if (mx < -q->reach[k] || mn > q->reach[k]) return 0;
    }
    /* A fourth direction n: the normal of the triangle (vertex-face) or of the two edges
       (edge-edge) at the middle of the box's time span, divided by its largest component. Any
       n gives a valid test, since n.F is multilinear too: its exact range over the box lies
       between its exact corner values, each within sum |n_k| eps_k (the corner errors) plus
       the rounding of the dot product (below 2 DBL_EPSILON sum |n_k F_k|, fused or not, plus
       DBL_MIN for underflow) of the computed one. A collision (|F_k| <= d on every axis) has
       |n.F| <= d sum |n_k|. Along n, F is close to the distance from the plane, nearly
       independent of u and v, which prunes near misses that the axes alone leave open. */
    {
        double tm = 0.5 * (b->t0 + b->t1), ea[3], eb[3], n[3], m, sum = 0, err = DBL_MIN, reach, g, gmin, gmax;
        int c;
        for (k = 0; k < 3; ++k) {
            double y[4];
            for (j = 0; j < 4; ++j) y[j] = q->x0[k][j] + tm * q->dx[k][j];
            ea[k] = q->edge_edge ? y[1] - y[0] : y[2] - y[1];
            eb[k] = q->edge_edge ? y[3] - y[2] : y[3] - y[1];
        }
        n[0] = ea[1] * eb[2] - ea[2] * eb[1];
        n[1] = ea[2] * eb[0] - ea[0] * eb[2];
        n[2] = ea[0] * eb[1] - ea[1] * eb[0];
        m = fabs(n[0]) > fabs(n[1]) ? fabs(n[0]) : fabs(n[1]);
        if (fabs(n[2]) > m) m = fabs(n[2]);
        if (!(m > DBL_MIN && m <= DBL_MAX)) return 1; /* no usable normal */
        for (k = 0; k < 3; ++k) {
            double big = fabs(lo[k]) > fabs(hi[k]) ? fabs(lo[k]) : fabs(hi[k]);
            n[k] /= m;
            sum += fabs(n[k]);
            err += fabs(n[k]) * (q->eps[k] + 2 * DBL_EPSILON * big);
        }
        /* the rounding of this sum of nonnegative terms is covered by the 1 + 8 DBL_EPSILON */
        reach = (q->separation * sum + err) * (1 + 8 * DBL_EPSILON);
        gmin = gmax = n[0] * corner[0][0] + n[1] * corner[1][0] + n[2] * corner[2][0];
        for (c = 1; c < 8; ++c) {
            g = n[0] * corner[0][c] + n[1] * corner[1][c] + n[2] * corner[2][c];
            if (g < gmin) gmin = g;
            if (g > gmax) gmax = g;
        }
        if (gmax < -reach || gmin > reach) return 0;
    }
    return 1;
}

/* The largest change of F along t, u and v across a box (any axis), from its corner values:
   F is multilinear, so its partial derivative along one parameter is extremal at corners, and
   these are exactly what each side contributes to the spread of F over the box. Only steers
   the search; the guarantee does not depend on it. */
static void cloth__ccd_spread(double corner[3][8], double spread[3])
{
    int k, c;
    spread[0] = spread[1] = spread[2] = 0;
    for (k = 0; k < 3; ++k)
        for (c = 0; c < 8; ++c) {
            double dt = (c & 4) ? 0 : fabs(corner[k][c | 4] - corner[k][c]);
            double du = (c & 2) ? 0 : fabs(corner[k][c | 2] - corner[k][c]);
            double dv = (c & 1) ? 0 : fabs(corner[k][c | 1] - corner[k][c]);
            if (dt > spread[0]) spread[0] = dt;
            if (du > spread[1]) spread[1] = du;
            if (dv > spread[2]) spread[2] = dv;
        }
}

/* A min-heap of boxes by t0, for the best-first phase of the search. */
static void cloth__ccd_heap_push(cloth__ccd_box *h, int *n, const cloth__ccd_box *b)
{
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].t0 > b->t0) { h[i] = h[(i - 1) / 2]; i = (i - 1) / 2; }
    h[i] = *b;
}
static cloth__ccd_box cloth__ccd_heap_pop(cloth__ccd_box *h, int *n)
{
    cloth__ccd_box top = h[0], last = h[--*n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= *n) break;
        if (c + 1 < *n && h[c + 1].t0 < h[c].t0) ++c;
        if (h[c].t0 >= last.t0) break;
        h[i] = h[c];
        i = c;
    }
    if (*n > 0) h[i] = last;
    return top;
}

/* The search. A box is checked; one that survives is accepted as a collision when F lies
   wholly within the separation band over it, when F varies by at most delta over it on every
   axis, or when no side that may still be halved (sides stop at 2^-50) changes F, and its t0
   becomes the best time; otherwise the side along which F changes most over the box is
   halved.

   Boxes are explored depth first, earlier half of t first (a stack of one box per level),
   until a box is accepted. From then on only times before the cut, the best time less the
   time resolution (delta over three times the largest change of F along t over the step),
   matter: a box starting no earlier is dropped, one reaching past it is cut there, so that
   each later acceptance improves the best time by at least the resolution. The boxes still
   waiting go to a min-heap on t0 and are taken earliest first, each explored depth first
   again until the next acceptance. (Depth first alone reaches a first contact quickly but may
   then lower the best time in tiny steps across a surface of contacts; earliest first alone
   goes breadth first along a curve of contacts at one time.) The search stops when no box is
   left before the cut or when the budget runs out; once a contact is found the budget left is
   cut to refine_checks, since what remains only tightens toi (along a curve of
   contacts at one time, certifying that no earlier contact exists costs more the tighter the
   bound). When the heap is full the waiting boxes stay on the stack and the search stays
   depth first, so memory is fixed.

   Every root lies in a box that was accepted (so at or after the best time), dropped or cut
   for lying after the cut, or still waiting; so the smallest of the cut and the waiting boxes'
   t0 is a lower bound on the earliest root, and it is what is returned. Box bounds need not be
   exact midpoints: a rounded midpoint still splits a box into two that cover it, and the error
   bound holds for any double t, u, v in [0,1]. */
static void cloth__ccd_search(const cloth__ccd_problem *q, double delta, int64_t max_checks, int64_t refine_checks,
                              cloth_ccd_report *report)
{
    cloth__ccd_box stack[CLOTH__CCD_STACK], heap[CLOTH__CCD_HEAP];
    double best = 2, cut = 2, lowest, time_resolution = 0;
    int64_t checks = 0, limit = max_checks;
    int n = 0, nh = 0, i, exhausted = 0;
    stack[0].t0 = stack[0].u0 = stack[0].v0 = 0;
    stack[0].t1 = stack[0].u1 = stack[0].v1 = 1;
    n = 1;
    for (;;) {
        cloth__ccd_box b, c0, c1;
        double lo[3], hi[3], corner[3][8], spread[3], w[3], most = -1, mid;
        int k, split = -1, accept, sweep;
        if (n == 0) {
            if (nh == 0 || heap[0].t0 >= cut) { nh = 0; break; }
            b = cloth__ccd_heap_pop(heap, &nh);
            sweep = 1;
        } else {
            b = stack[--n];
            sweep = 0;
        }
        if (b.t0 >= cut) continue;
        if (b.t1 > cut) b.t1 = cut;
        if (!q->edge_edge && b.u0 + b.v0 > 1) continue; /* outside the triangle (rounding can only keep a box) */
        if (checks >= limit || n + 2 > CLOTH__CCD_STACK) {
            exhausted = best > 1 || checks >= max_checks || n + 2 > CLOTH__CCD_STACK; /* not the refinement's limit */
            stack[n++] = b;
            break;
        }
        ++checks;
        if (!cloth__ccd_check(q, &b, lo, hi, corner)) continue;
        cloth__ccd_spread(corner, spread);
        if (checks == 1) time_resolution = spread[0] > 0 ? delta / (3 * spread[0]) : 2; /* the whole domain */
        w[0] = b.t1 - b.t0; w[1] = b.u1 - b.u0; w[2] = b.v1 - b.v0;
        for (k = 0; k < 3; ++k)
            if (w[k] > CLOTH__CCD_MIN_WIDTH && spread[k] > most) { most = spread[k]; split = k; }
        accept = split < 0 || most <= 0;
        if (!accept) {
            int inside = 1, narrow = 1;
            for (k = 0; k < 3; ++k) {
                if (lo[k] - 2 * q->eps[k] < -q->reach[k] || hi[k] + 2 * q->eps[k] > q->reach[k]) inside = 0;
                if (hi[k] - lo[k] > delta) narrow = 0;
            }
            accept = inside || narrow;
        }
        if (accept) {
            if (best > 1 && refine_checks < limit - checks) limit = checks + refine_checks;
            best = b.t0;
            cut = best - time_resolution;
            if (nh + n <= CLOTH__CCD_HEAP) /* the rest is taken earliest first */
                while (n > 0) { --n; if (stack[n].t0 < cut) cloth__ccd_heap_push(heap, &nh, &stack[n]); }
            continue;
        }
        c0 = c1 = b;
        if (split == 0) { mid = 0.5 * (b.t0 + b.t1); c0.t1 = mid; c1.t0 = mid; }
        else if (split == 1) { mid = 0.5 * (b.u0 + b.u1); c0.u1 = mid; c1.u0 = mid; }
        else { mid = 0.5 * (b.v0 + b.v1); c0.v1 = mid; c1.v0 = mid; }
        if (sweep && nh + 2 <= CLOTH__CCD_HEAP) {
            cloth__ccd_heap_push(heap, &nh, &c0);
            cloth__ccd_heap_push(heap, &nh, &c1);
        } else {
            stack[n++] = c1; /* the upper half waits; the lower (earlier) half is searched first */
            stack[n++] = c0;
        }
    }
    lowest = best <= 1 ? (cut > 0 ? cut : 0) : 2;
    for (i = 0; i < n; ++i)
        if (stack[i].t0 < lowest && (q->edge_edge || stack[i].u0 + stack[i].v0 <= 1)) lowest = stack[i].t0;
    for (i = 0; i < nh; ++i)
        if (heap[i].t0 < lowest && (q->edge_edge || heap[i].u0 + heap[i].v0 <= 1)) lowest = heap[i].t0;
    report->checks = checks;
    report->budget_exhausted = exhausted;
    report->may_collide = lowest <= 1;
    if (lowest > 1) {
        report->toi = 1;
    } else {
        /* round down into cloth_real: toi stays a lower bound */
        cloth_real r = (cloth_real)lowest;
        if ((double)r > lowest) r = sizeof(cloth_real) == sizeof(float) ? (cloth_real)nextafterf((float)r, -1.0f)
                                                                      : (cloth_real)nextafter((double)r, -1.0);
        report->toi = r;
    }
}

static cloth_result cloth__ccd_run(int edge_edge, const cloth_real *const *v, const cloth_ccd_options *options,
                                   cloth_ccd_report *report)
{
    cloth_ccd_options opt = options ? *options : cloth_ccd_default_options();
    cloth__ccd_problem q;
    double x[8][3];
    int i, k;
    CLOTH_ASSERT(report);
    CLOTH_ASSERT(opt.internal_cookie == CLOTH__CCD_COOKIE); /* options not made by cloth_ccd_default_options */
    report->may_collide = 1;
    report->toi = 0;
    report->checks = 0;
    report->budget_exhausted = 0;
    if (!(opt.tolerance > 0) || !cloth__is_finite(opt.tolerance) || opt.max_checks < 1 || opt.refine_checks < 0 ||
        !(opt.minimum_separation >= 0) || !((double)opt.minimum_separation <= CLOTH__CCD_MAX_COORDINATE))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < 8; ++i) {
        CLOTH_ASSERT(v[i]);
        for (k = 0; k < 3; ++k) {
            if (!cloth__is_finite(v[i][k])) return CLOTH_ERROR_NOT_FINITE;
            x[i][k] = (double)v[i][k];
        }
    }
    for (i = 0; i < 8; ++i)
        for (k = 0; k < 3; ++k)
            if (fabs(x[i][k]) > CLOTH__CCD_MAX_COORDINATE) return CLOTH_ERROR_INVALID_ARGUMENT;
    cloth__ccd_setup(&q, edge_edge, (const double (*)[3])x, (double)opt.minimum_separation);
    cloth__ccd_search(&q, (double)opt.tolerance, opt.max_checks, opt.refine_checks, report);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_ccd_vertex_face(const cloth_real p_t0[3], const cloth_real f0_t0[3], const cloth_real f1_t0[3],
                                             const cloth_real f2_t0[3], const cloth_real p_t1[3], const cloth_real f0_t1[3],
                                             const cloth_real f1_t1[3], const cloth_real f2_t1[3],
                                             const cloth_ccd_options *options, cloth_ccd_report *report)
{
    const cloth_real *v[8];
    v[0] = p_t0; v[1] = f0_t0; v[2] = f1_t0; v[3] = f2_t0;
    v[4] = p_t1; v[5] = f0_t1; v[6] = f1_t1; v[7] = f2_t1;
    return cloth__ccd_run(0, v, options, report);
}

CLOTH_API cloth_result cloth_ccd_edge_edge(const cloth_real a0_t0[3], const cloth_real a1_t0[3], const cloth_real b0_t0[3],
                                           const cloth_real b1_t0[3], const cloth_real a0_t1[3], const cloth_real a1_t1[3],
                                           const cloth_real b0_t1[3], const cloth_real b1_t1[3],
                                           const cloth_ccd_options *options, cloth_ccd_report *report)
{
    const cloth_real *v[8];
    v[0] = a0_t0; v[1] = a1_t0; v[2] = b0_t0; v[3] = b1_t0;
    v[4] = a0_t1; v[5] = a1_t1; v[6] = b0_t1; v[7] = b1_t1;
    return cloth__ccd_run(1, v, options, report);
}


/* ------------------------------------------------------------------------------------- */
/* qp                                                                                    */
/* ------------------------------------------------------------------------------------- */

/* Everything here computes in double whatever cloth_real is. Notation: n vertices, m rows,
   N = 3 n coordinates; row j in the scaled space y = sqrt(W) (z - x) is the sparse vector
   A_j = sum_e c_je (e_(v_je) (x) n_j) over its distinct vertices e, c_je = a_je sqrt(m_(v_je)),
   and the constraint reads A_j . y >= b_j with b_j = g_j(x) (see the module's banner). */

#define CLOTH__QP_COOKIE 0x51501a5e

/* The solver's view of one problem: arrays carved from the workspace. */
typedef struct cloth__qp {
    int32_t n, m;      /* vertices, rows */
    int32_t qmax;      /* the largest working set possible: min(m, 3 movable vertices) */
    int32_t q;         /* size of the working set */
    int32_t ncap, mcap, ld; /* the arrays' capacities: vertices, rows, and working rows (the
                              length of R's rows; it grows with q, up to qmax) */
    cloth_qp_workspace *ws; /* the block the arrays are carved from */
    int fresh;         /* 1 while R is what cloth__qp_refactor would make of the working set:
                          it was built by additions alone since the start or the last
                          refactorization (a deletion clears it) */
    double *x;         /* 3n positions */
    double *mi;        /* n inverse weights m_i */
    double *smi;       /* n square roots of the inverse weights */
    double *y;         /* 3n scaled displacement sqrt(W) (z - x), 0 at immovable vertices */
    double *dir;       /* 3n: the part of a row orthogonal to the working rows */
    double *zd;        /* 3n: the solution (forward), p = dL/dx (backward) */
    double *a;         /* 4m: a_je, the weights merged per distinct vertex */
    double *c;         /* 4m: c_je = a_je sqrt(m_(v_je)) */
    double *nrm;       /* 3m normals */
    double *t;         /* m thicknesses */
    double *b;         /* m: b_j = g_j(x) = t_j - sum_e a_je n_j . x_(v_je) */
    double *sigma;     /* m: |t_j| + sum_e |a_je| |n_j| |x_(v_je)|, the size of the terms of b_j */
    double *anorm;     /* m: |A_j| */
    double *u;         /* qmax multipliers of the working rows */
    double *r;         /* qmax: a_p = A_S^T r + dir after cloth__qp_orthogonalize */
    double *rr;        /* qmax: R r, the forward solves' results (the new column of R) */
    double *w;         /* qmax scratch */
    double *d;         /* qmax: the last correction of the refinement */
    double *R;         /* ld x ld, row major (R_ij at i ld + j), upper triangular:
                          A_S A_S^T = R^T R; every pass over it walks rows (see
                          cloth__qp_solve_rtr) */
    int32_t *v;        /* 4m: v_je, -1 past the row's count */
    int32_t *cnt;      /* m: distinct vertices of each row */
    int32_t *pos;      /* m: position of the row in the working set, or -1 */
    int32_t *state;    /* m: cloth_qp_row_state being built */
    int32_t *set;      /* ld: the working rows in order */
} cloth__qp;

/* The head of a workspace's block: what cloth_qp_project_more needs to continue the last
   projection (the arrays after it keep the problem, the working set, R, u and y). */
typedef struct cloth__qp_saved {
    int32_t cookie;          /* CLOTH__QP_COOKIE while the block holds a solution */
    int32_t n, m, q, fresh;  /* the problem solved and its working set */
    int32_t ncap, mcap, ld;  /* how the block is carved */
} cloth__qp_saved;

/* Bytes before the arrays (a multiple of 16, so that the doubles stay aligned). */
#define CLOTH__QP_HEAD ((sizeof(cloth__qp_saved) + 15) / 16 * 16)

CLOTH_API cloth_qp_options cloth_qp_default_options(void)
{
    cloth_qp_options o;
    o.feasibility_tolerance = (cloth_real)1e-12;
    o.kkt_tolerance = (cloth_real)1e-9;
    /* A row independent of others by less than the rounding of its data is not independent:
       for float data that is about 100 roundings; data computed in double carries more than
       one rounding, hence 1e-10 (about 5e5 roundings) for double. */
    o.dependency_tolerance = (cloth_real)(sizeof(cloth_real) < sizeof(double) ? 1e-5 : 1e-10);
    o.max_iterations = 0;
    o.internal_cookie = CLOTH__QP_COOKIE;
    return o;
}

static int cloth__qp_options_valid(const cloth_qp_options *o)
{
    return o->feasibility_tolerance > 0 && cloth__is_finite(o->feasibility_tolerance) && o->kkt_tolerance > 0 &&
           cloth__is_finite(o->kkt_tolerance) && o->dependency_tolerance > 0 && o->dependency_tolerance < 1 &&
           o->max_iterations >= 0;
}

/* ---- memory ------------------------------------------------------------------------ */

/* Bytes of the block for ncap vertices, mcap rows and working sets of up to ld rows: the head,
   doubles, then int32_t, so that every array is aligned as the allocator aligns the block. */
static size_t cloth__qp_bytes(int32_t ncap, int32_t mcap, int32_t ld, int *ok)
{
    size_t nd, ni, bytes;
    nd = cloth__size_mul_add((size_t)ncap, 14, 0, ok);
    nd = cloth__size_mul_add((size_t)mcap, 16, nd, ok);
    nd = cloth__size_mul_add((size_t)ld, 5, nd, ok);
    nd = cloth__size_mul_add((size_t)ld, (size_t)ld, nd, ok);
    ni = cloth__size_mul_add((size_t)mcap, 7, (size_t)ld, ok);
    bytes = cloth__size_mul_add(nd, sizeof(double), CLOTH__QP_HEAD, ok);
    bytes = cloth__size_mul_add(ni, sizeof(int32_t), bytes, ok);
    return bytes;
}

static int32_t cloth__qp_qmax(int32_t m, int32_t movable)
{
    int64_t coords = 3 * (int64_t)movable;
    return (int64_t)m < coords ? m : (int32_t)coords;
}

static cloth__qp_saved *cloth__qp_head(const cloth_qp_workspace *ws)
{
    return (cloth__qp_saved *)ws->memory;
}

/* Make the workspace hold at least the block for (ncap, mcap, ld); the block's contents are
   not kept, and it holds no solution afterwards. */
static cloth_result cloth__qp_reserve(cloth_qp_workspace *ws, int32_t ncap, int32_t mcap, int32_t ld)
{
    int ok = 1;
    size_t bytes = cloth__qp_bytes(ncap, mcap, ld, &ok);
    cloth_allocator a;
    if (!ok) return CLOTH_ERROR_SIZE_OVERFLOW;
    if (ws->memory && ws->capacity >= bytes) {
        cloth__qp_head(ws)->cookie = 0;
        return CLOTH_SUCCESS;
    }
    a = cloth__allocator_or_default(&ws->allocator);
    cloth__free(&a, ws->memory);
    ws->memory = NULL;
    ws->capacity = 0;
    ws->memory = cloth__alloc_array(&a, bytes, 1);
    if (!ws->memory) return CLOTH_ERROR_OUT_OF_MEMORY;
    ws->capacity = bytes;
    cloth__qp_head(ws)->cookie = 0;
    return CLOTH_SUCCESS;
}

static void cloth__qp_carve(cloth__qp *P, cloth_qp_workspace *ws, int32_t ncap, int32_t mcap, int32_t ld)
{
    double *d = (double *)(void *)((char *)ws->memory + CLOTH__QP_HEAD);
    int32_t *ip;
    size_t N = 3 * (size_t)ncap, M = (size_t)mcap, Q = (size_t)ld;
    P->ws = ws;
    P->ncap = ncap;
    P->mcap = mcap;
    P->ld = ld;
    P->n = ncap;
    P->m = mcap;
    P->qmax = ld;
    P->q = 0;
    P->fresh = 1;
    P->x = d; d += N;
    P->mi = d; d += (size_t)ncap;
    P->smi = d; d += (size_t)ncap;
    P->y = d; d += N;
    P->dir = d; d += N;
    P->zd = d; d += N;
    P->a = d; d += 4 * M;
    P->c = d; d += 4 * M;
    P->nrm = d; d += 3 * M;
    P->t = d; d += M;
    P->b = d; d += M;
    P->sigma = d; d += M;
    P->anorm = d; d += M;
    P->u = d; d += Q;
    P->r = d; d += Q;
    P->rr = d; d += Q;
    P->w = d; d += Q;
    P->d = d; d += Q;
    P->R = d; d += Q * Q;
    ip = (int32_t *)(void *)d;
    P->v = ip; ip += 4 * M;
    P->cnt = ip; ip += M;
    P->pos = ip; ip += M;
    P->state = ip; ip += M;
    P->set = ip;
}

/* Move the problem, its working set, R, u, y and zd into a new block carved for (ncap, mcap,
   ld) (each at least what is in use) and free the old one; the other scratch arrays are not
   kept. On failure nothing changes. */
static cloth_result cloth__qp_relocate(cloth__qp *P, int32_t ncap, int32_t mcap, int32_t ld)
{
    int ok = 1;
    size_t bytes = cloth__qp_bytes(ncap, mcap, ld, &ok), N = 3 * (size_t)P->n, M = (size_t)P->m, i;
    cloth_qp_workspace *ws = P->ws, moved;
    cloth_allocator a;
    cloth__qp Q;
    if (!ok) return CLOTH_ERROR_SIZE_OVERFLOW;
    a = cloth__allocator_or_default(&ws->allocator);
    moved = *ws;
    moved.memory = cloth__alloc_array(&a, bytes, 1);
    if (!moved.memory) return CLOTH_ERROR_OUT_OF_MEMORY;
    moved.capacity = bytes;
    *cloth__qp_head(&moved) = *cloth__qp_head(ws);
    cloth__qp_carve(&Q, &moved, ncap, mcap, ld);
    memcpy(Q.x, P->x, N * sizeof(double));
    memcpy(Q.mi, P->mi, (size_t)P->n * sizeof(double));
    memcpy(Q.smi, P->smi, (size_t)P->n * sizeof(double));
    memcpy(Q.y, P->y, N * sizeof(double));
    memcpy(Q.zd, P->zd, N * sizeof(double)); /* the solution, when cloth__qp_finish grows R */
    memcpy(Q.a, P->a, 4 * M * sizeof(double));
    memcpy(Q.c, P->c, 4 * M * sizeof(double));
    memcpy(Q.nrm, P->nrm, 3 * M * sizeof(double));
    memcpy(Q.t, P->t, M * sizeof(double));
    memcpy(Q.b, P->b, M * sizeof(double));
    memcpy(Q.sigma, P->sigma, M * sizeof(double));
    memcpy(Q.anorm, P->anorm, M * sizeof(double));
    memcpy(Q.v, P->v, 4 * M * sizeof(int32_t));
    memcpy(Q.cnt, P->cnt, M * sizeof(int32_t));
    memcpy(Q.pos, P->pos, M * sizeof(int32_t));
    memcpy(Q.state, P->state, M * sizeof(int32_t));
    memcpy(Q.u, P->u, (size_t)P->q * sizeof(double));
    memcpy(Q.set, P->set, (size_t)P->q * sizeof(int32_t));
    for (i = 0; i < (size_t)P->q; ++i) memcpy(Q.R + i * (size_t)ld, P->R + i * (size_t)P->ld, (size_t)P->q * sizeof(double));
    Q.n = P->n;
    Q.m = P->m;
    Q.qmax = P->qmax;
    Q.q = P->q;
    Q.fresh = P->fresh;
    Q.ws = ws;
    cloth__free(&a, ws->memory);
    *ws = moved;
    *P = Q;
    return CLOTH_SUCCESS;
}

/* Room in R for one more working row. A projection from the start has R's rows as long as
   qmax; one that goes on (cloth_qp_project_more) keeps its R while more rows raise qmax, and
   R's rows grow by half (at least to 64) when the working set reaches their length. */
static cloth_result cloth__qp_make_room(cloth__qp *P)
{
    int64_t ld;
    if (P->q < P->ld || P->ld >= P->qmax) return CLOTH_SUCCESS;
    ld = (int64_t)P->ld + P->ld / 2;
    if (ld < 64) ld = 64;
    if (ld > P->qmax) ld = P->qmax;
    return cloth__qp_relocate(P, P->ncap, P->mcap, (int32_t)ld);
}

CLOTH_API cloth_result cloth_qp_workspace_create(cloth_qp_workspace *workspace, int32_t vertex_count,
                                                 int32_t row_count, const cloth_allocator *allocator)
{
    cloth_result res;
    CLOTH_ASSERT(workspace);
    workspace->memory = NULL;
    workspace->capacity = 0;
    workspace->allocator = cloth__allocator_or_default(allocator);
    if (vertex_count < 0 || row_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    res = cloth__qp_reserve(workspace, vertex_count, row_count, cloth__qp_qmax(row_count, vertex_count));
    return res;
}

CLOTH_API void cloth_qp_workspace_free(cloth_qp_workspace *workspace)
{
    cloth_allocator a;
    if (!workspace) return;
    a = cloth__allocator_or_default(&workspace->allocator);
    cloth__free(&a, workspace->memory);
    workspace->memory = NULL;
    workspace->capacity = 0;
}

/* ---- input ------------------------------------------------------------------------- */

/* The first problem of the input, in the documented order (non-finite, index, negative
   weight), without touching memory; counts the movable vertices. */
static cloth_result cloth__qp_validate(const cloth_qp_problem *pr, int32_t *movable)
{
    int32_t n = pr->vertex_count, m = pr->row_count, i, j, k;
    size_t N = 3 * (size_t)n, s;
    *movable = 0;
    if (n < 0 || m < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    CLOTH_ASSERT(n == 0 || pr->x);
    CLOTH_ASSERT(m == 0 || pr->rows);
    for (s = 0; s < N; ++s)
        if (!cloth__is_finite(pr->x[s])) return CLOTH_ERROR_NOT_FINITE;
    if (pr->inverse_weight)
        for (i = 0; i < n; ++i)
            if (!cloth__is_finite(pr->inverse_weight[i])) return CLOTH_ERROR_NOT_FINITE;
    for (j = 0; j < m; ++j) {
        const cloth_qp_row *row = &pr->rows[j];
        for (k = 0; k < 4; ++k)
            if (row->vertex[k] != -1 && !cloth__is_finite(row->weight[k])) return CLOTH_ERROR_NOT_FINITE;
        for (k = 0; k < 3; ++k)
            if (!cloth__is_finite(row->normal[k])) return CLOTH_ERROR_NOT_FINITE;
        if (!cloth__is_finite(row->thickness)) return CLOTH_ERROR_NOT_FINITE;
    }
    for (j = 0; j < m; ++j)
        for (k = 0; k < 4; ++k)
            if (pr->rows[j].vertex[k] < -1 || pr->rows[j].vertex[k] >= n) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    for (i = 0; i < n; ++i) {
        cloth_real mi = pr->inverse_weight ? pr->inverse_weight[i] : (cloth_real)1;
        if (mi < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
        if (mi > 0) ++*movable;
    }
    return CLOTH_SUCCESS;
}

/* A row's distinct vertices v[0..count) with their weights merged, a[], in double (-1 and 0
   past count); returns count. */
static int32_t cloth__qp_row_form(const cloth_qp_row *row, int32_t v[4], double a[4])
{
    int32_t k, e, count = 0;
    for (k = 0; k < 4; ++k) { v[k] = -1; a[k] = 0; }
    for (k = 0; k < 4; ++k) {
        int32_t vk = row->vertex[k];
        if (vk < 0) continue;
        for (e = 0; e < count; ++e)
            if (v[e] == vk) break;
        if (e == count) { v[count] = vk; a[count] = 0; ++count; }
        a[e] += (double)row->weight[k];
    }
    return count;
}

/* Copy the problem into the workspace in double and build the rows (none in the working
   set). Fails with CLOTH_ERROR_NOT_FINITE when a derived quantity overflows. */
static cloth_result cloth__qp_load(cloth__qp *P, const cloth_qp_problem *pr)
{
    int32_t i, j, k, e;
    size_t s, N = 3 * (size_t)P->n;
    for (s = 0; s < N; ++s) P->x[s] = (double)pr->x[s];
    for (i = 0; i < P->n; ++i) {
        P->mi[i] = pr->inverse_weight ? (double)pr->inverse_weight[i] : 1.0;
        P->smi[i] = sqrt(P->mi[i]);
    }
    for (j = 0; j < P->m; ++j) {
        const cloth_qp_row *row = &pr->rows[j];
        double *nj = P->nrm + 3 * (size_t)j, nn, ss = 0;
        int32_t *vj = P->v + 4 * (size_t)j;
        double *aj = P->a + 4 * (size_t)j, *cj = P->c + 4 * (size_t)j;
        int32_t count = cloth__qp_row_form(row, vj, aj);
        for (k = 0; k < 4; ++k) cj[k] = 0;
        P->cnt[j] = count;
        for (k = 0; k < 3; ++k) nj[k] = (double)row->normal[k];
        nn = sqrt(nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2]);
        P->t[j] = (double)row->thickness;
        P->b[j] = P->t[j];
        P->sigma[j] = fabs(P->t[j]);
        for (e = 0; e < count; ++e) {
            const double *xv = P->x + 3 * (size_t)vj[e];
            cj[e] = aj[e] * P->smi[vj[e]];
            ss += cj[e] * cj[e];
            P->b[j] -= aj[e] * (nj[0] * xv[0] + nj[1] * xv[1] + nj[2] * xv[2]);
            P->sigma[j] += fabs(aj[e]) * nn * sqrt(xv[0] * xv[0] + xv[1] * xv[1] + xv[2] * xv[2]);
        }
        P->anorm[j] = nn * sqrt(ss);
        P->pos[j] = -1;
        P->state[j] = CLOTH_QP_INACTIVE;
        if (!(fabs(P->b[j]) <= DBL_MAX) || !(P->sigma[j] <= DBL_MAX) || !(P->anorm[j] <= DBL_MAX))
            return CLOTH_ERROR_NOT_FINITE;
    }
    return CLOTH_SUCCESS;
}

/* Whether the first n0 vertices' inverse weights and the first m0 rows of the problem are,
   bit for bit in double, the ones the workspace holds (cloth_qp_project_more's condition for
   going on; the positions may differ). */
static int cloth__qp_extends(const cloth__qp *P, const cloth_qp_problem *pr, int32_t n0, int32_t m0)
{
    int32_t i, j, k;
    for (i = 0; i < n0; ++i)
        if (P->mi[i] != (pr->inverse_weight ? (double)pr->inverse_weight[i] : 1.0)) return 0;
    for (j = 0; j < m0; ++j) {
        const cloth_qp_row *row = &pr->rows[j];
        int32_t v[4];
        double a[4];
        if (cloth__qp_row_form(row, v, a) != P->cnt[j] || P->t[j] != (double)row->thickness) return 0;
        for (k = 0; k < 4; ++k)
            if (v[k] != P->v[4 * (size_t)j + k] || a[k] != P->a[4 * (size_t)j + k]) return 0;
        for (k = 0; k < 3; ++k)
            if (P->nrm[3 * (size_t)j + k] != (double)row->normal[k]) return 0;
    }
    return 1;
}

/* ---- sparse rows --------------------------------------------------------------------- */

/* A_i . A_j */
static double cloth__qp_row_dot(const cloth__qp *P, int32_t i, int32_t j)
{
    const int32_t *vi = P->v + 4 * (size_t)i, *vj = P->v + 4 * (size_t)j;
    const double *ci = P->c + 4 * (size_t)i, *cj = P->c + 4 * (size_t)j;
    const double *ni = P->nrm + 3 * (size_t)i, *nj = P->nrm + 3 * (size_t)j;
    double s = 0;
    int32_t k, l;
    for (k = 0; k < P->cnt[i]; ++k)
        for (l = 0; l < P->cnt[j]; ++l)
            if (vi[k] == vj[l]) s += ci[k] * cj[l];
    if (s == 0) return 0;
    return s * (ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2]);
}

/* A_j . vec (vec of 3n) */
static double cloth__qp_row_apply(const cloth__qp *P, int32_t j, const double *vec)
{
    const int32_t *vj = P->v + 4 * (size_t)j;
    const double *cj = P->c + 4 * (size_t)j, *nj = P->nrm + 3 * (size_t)j;
    double s = 0;
    int32_t e;
    for (e = 0; e < P->cnt[j]; ++e) {
        const double *p = vec + 3 * (size_t)vj[e];
        if (cj[e] != 0) s += cj[e] * (nj[0] * p[0] + nj[1] * p[1] + nj[2] * p[2]);
    }
    return s;
}

/* vec += alpha A_j */
static void cloth__qp_row_axpy(const cloth__qp *P, int32_t j, double alpha, double *vec)
{
    const int32_t *vj = P->v + 4 * (size_t)j;
    const double *cj = P->c + 4 * (size_t)j, *nj = P->nrm + 3 * (size_t)j;
    int32_t e;
    for (e = 0; e < P->cnt[j]; ++e) {
        double *p = vec + 3 * (size_t)vj[e];
        double f = alpha * cj[e];
        if (cj[e] == 0) continue;
        p[0] += f * nj[0];
        p[1] += f * nj[1];
        p[2] += f * nj[2];
    }
}

static double cloth__qp_norm(const double *vec, size_t len)
{
    double s = 0;
    size_t i;
    for (i = 0; i < len; ++i) s += vec[i] * vec[i];
    return sqrt(s);
}

/* ---- the factor R of the working set ------------------------------------------------ */

/* Overwrite rhs (q values) with the solution of R^T x = rhs (cloth__qp_solve_rt, whose rhs is
   zero before entry `first`), of
   R x = rhs (cloth__qp_solve_r), or of R^T R x = rhs (both). The triangular solves walk
   R by rows, which are contiguous, so that a zone of a few thousand working rows (R tens of
   megabytes) does not read a cache line per entry: R^T x = rhs by columns of R^T (x_j found,
   then R_jk x_j taken from every later rhs_k, in increasing j as in the textbook loop), R x =
   rhs by rows, each row's products summed in four chains (one chain of q - i dependent
   additions per row made the backward solve latency-bound). */
static void cloth__qp_solve_rt(const cloth__qp *P, double *rhs, int32_t first)
{
    const double *R = P->R;
    size_t ld = (size_t)P->ld;
    int32_t i, j, q = P->q;
    /* leading zeros (a new row's products with the working rows are zero but for the few
       rows that share a vertex with it) stay zero and take nothing from the later entries */
    for (j = first; j < q; ++j) {
        const double *row = R + (size_t)j * ld;
        double xj = rhs[j] / row[j];
        rhs[j] = xj;
        for (i = j + 1; i < q; ++i) rhs[i] -= row[i] * xj;
    }
}

static void cloth__qp_solve_r(const cloth__qp *P, double *rhs)
{
    const double *R = P->R;
    size_t ld = (size_t)P->ld;
    int32_t i, j, q = P->q;
    for (i = q - 1; i >= 0; --i) {
        /* the row's products in four running sums (j = i + 1 + 4 k + lane), added pairwise:
           four independent chains instead of one, in a fixed order */
        const double *row = R + (size_t)i * ld;
        double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
        for (j = i + 1; j + 3 < q; j += 4) {
            s0 += row[j] * rhs[j];
            s1 += row[j + 1] * rhs[j + 1];
            s2 += row[j + 2] * rhs[j + 2];
            s3 += row[j + 3] * rhs[j + 3];
        }
        for (; j < q; ++j) s0 += row[j] * rhs[j];
        rhs[i] = (rhs[i] - ((s0 + s1) + (s2 + s3))) / row[i];
    }
}

static void cloth__qp_solve_rtr(const cloth__qp *P, double *rhs)
{
    cloth__qp_solve_rt(P, rhs, 0);
    cloth__qp_solve_r(P, rhs);
}

/* Split row p into A_S^T r (r in P->r) plus the part dir orthogonal to the working rows (in
   P->dir), and return |dir|. The first projection goes through R (the normal equations), whose
   rounding can leave dir slightly off orthogonal on an ill-conditioned working set; a second
   projection of dir removes that, and is skipped when dir is already orthogonal to every
   working row to a few roundings (|A_i . dir| <= 4 eps |A_i| |A_p|). */
static double cloth__qp_orthogonalize(cloth__qp *P, int32_t p)
{
    size_t N = 3 * (size_t)P->n;
    int32_t i, pass, q = P->q;
    memset(P->dir, 0, N * sizeof(double));
    cloth__qp_row_axpy(P, p, 1.0, P->dir);
    for (i = 0; i < q; ++i) P->r[i] = P->rr[i] = 0;
    for (pass = 0; pass < 2 && q > 0; ++pass) {
        int needed = pass == 0;
        for (i = 0; i < q; ++i) {
            if (pass == 0) {
                P->w[i] = cloth__qp_row_dot(P, P->set[i], p);
            } else {
                P->w[i] = cloth__qp_row_apply(P, P->set[i], P->dir);
                if (fabs(P->w[i]) > 4 * DBL_EPSILON * P->anorm[P->set[i]] * P->anorm[p]) needed = 1;
            }
        }
        if (!needed) break;
        /* the products' leading zeros; all zero: a row that shares no vertex with the working
           rows is orthogonal to them already, r = 0 and dir = a_p, without the two passes
           over R (the same bits) */
        for (i = 0; i < q && P->w[i] == 0; ++i) continue;
        if (i == q) break;
        cloth__qp_solve_rt(P, P->w, i);
        for (i = 0; i < q; ++i) P->rr[i] += P->w[i];
        cloth__qp_solve_r(P, P->w);
        for (i = 0; i < q; ++i) {
            cloth__qp_row_axpy(P, P->set[i], -P->w[i], P->dir);
            P->r[i] += P->w[i];
        }
    }
    return cloth__qp_norm(P->dir, N);
}

/* Append row p (just orthogonalized: P->r, P->rr and |dir| = dir_norm) with multiplier up.
   The new column of R is [R r; |dir|], since a_p = A_S^T r + dir with dir orthogonal to A_S;
   R r is the sum of the forward solves' results R^-T (A_S ...) that made r, so it costs no
   pass over R. */
static void cloth__qp_add(cloth__qp *P, int32_t p, double dir_norm, double up)
{
    size_t ld = (size_t)P->ld;
    int32_t i, q = P->q;
    for (i = 0; i < q; ++i) P->R[(size_t)i * ld + (size_t)q] = P->rr[i];
    P->R[(size_t)q * ld + (size_t)q] = dir_norm;
    P->u[q] = up;
    P->set[q] = p;
    P->pos[p] = q;
    P->q = q + 1;
}

/* Remove the working row at position k: shift the later columns of R left and restore the
   triangle with Givens rotations on rows k..q-1 (R^T R stays A_S A_S^T), row by row. */
static void cloth__qp_drop(cloth__qp *P, int32_t k)
{
    size_t ld = (size_t)P->ld;
    double *R = P->R;
    int32_t i, j, q = P->q;
    P->pos[P->set[k]] = -1;
    P->fresh = 0;
    for (j = k; j < q - 1; ++j) {
        P->set[j] = P->set[j + 1];
        P->u[j] = P->u[j + 1];
        P->pos[P->set[j]] = j;
    }
    /* column j + 1 into column j for j = k .. q - 2, rows 0 .. j + 1: row i's entries from
       column max(k, i - 1) on move one to the left */
    for (i = 0; i < q; ++i) {
        double *row = R + (size_t)i * ld;
        for (j = i - 1 > k ? i - 1 : k; j < q - 1; ++j) row[j] = row[j + 1];
    }
    q -= 1;
    for (i = k; i < q; ++i) {
        double *ri = R + (size_t)i * ld, *rn = ri + ld;
        double a = ri[i], bb = rn[i];
        double h = hypot(a, bb), cs, sn;
        if (h == 0) continue;
        cs = a / h;
        sn = bb / h;
        ri[i] = h;
        rn[i] = 0;
        for (j = i + 1; j < q; ++j) {
            double r1 = ri[j], r2 = rn[j];
            ri[j] = cs * r1 + sn * r2;
            rn[j] = cs * r2 - sn * r1;
        }
    }
    P->q = q;
}

/* ---- the dual active-set method ------------------------------------------------------ */

/* Solve A_S A_S^T u = rhs (q values, not aliasing P->u, P->w or P->d) into P->u with R, and
   y = A_S^T u into P->y; then refine: the residual rhs - A_S y is formed from the sparse rows,
   solved with R again, and its correction added to u and to y, as long as that shrinks the
   residual (at most 6 rounds; a correction that does not is taken back). y is accumulated
   rather than formed again from u, so that it can become more accurate than the cancellation
   in A_S^T u allows when the multipliers are much larger than y (nearly dependent rows).
   Uses P->dir for the last correction of y. */
static void cloth__qp_solve_refined(cloth__qp *P, const double *rhs)
{
    size_t s, N = 3 * (size_t)P->n;
    int32_t i, round, q = P->q;
    double last = 0;
    for (i = 0; i < q; ++i) P->u[i] = rhs[i];
    cloth__qp_solve_rtr(P, P->u);
    memset(P->y, 0, N * sizeof(double));
    for (i = 0; i < q; ++i) cloth__qp_row_axpy(P, P->set[i], P->u[i], P->y);
    for (round = 0; round < 6; ++round) {
        double big = 0;
        for (i = 0; i < q; ++i) {
            P->w[i] = rhs[i] - cloth__qp_row_apply(P, P->set[i], P->y);
            if (fabs(P->w[i]) > big) big = fabs(P->w[i]);
        }
        if (round > 0 && !(big < last)) {
            /* at the rounding floor: take the last correction back */
            for (i = 0; i < q; ++i) P->u[i] -= P->d[i];
            for (s = 0; s < N; ++s) P->y[s] -= P->dir[s];
            break;
        }
        if (big == 0 || (round > 0 && !(big < 0.5 * last))) break;
        last = big;
        cloth__qp_solve_rtr(P, P->w);
        memset(P->dir, 0, N * sizeof(double));
        for (i = 0; i < q; ++i) {
            P->d[i] = P->w[i];
            P->u[i] += P->w[i];
            cloth__qp_row_axpy(P, P->set[i], P->w[i], P->dir);
        }
        for (s = 0; s < N; ++s) P->y[s] += P->dir[s];
    }
}

/* Factor the working set afresh, in its order: the updates of many steps leave R a factor of
   a slightly different matrix, which would slow the refinement down on ill-conditioned sets.
   Projecting a row against fewer rows than when it was added leaves more of it, so every row
   stays independent. Row i's column of R is R^-T (A_S a_p), one forward solve; the last
   entry, |dir| = sqrt(|a_p|^2 - |column|^2), is taken from those lengths when dir keeps more
   than half of a_p (the subtraction then loses at most a factor 4 of its rounding) and from
   the full orthogonalization (two passes, dir formed) otherwise: no backward solve for most
   rows, which halves the refactorization (a zone of 3,600 working rows 20% faster in all). */
static void cloth__qp_refactor(cloth__qp *P)
{
    int32_t i, j, q = P->q;
    for (i = 0; i < q; ++i) {
        int32_t p = P->set[i], first;
        double dn, ui = P->u[i], cc = 0, ap = P->anorm[p];
        P->q = i;
        for (j = 0; j < i; ++j) P->rr[j] = cloth__qp_row_dot(P, P->set[j], p);
        for (first = 0; first < i && P->rr[first] == 0; ++first) continue;
        if (first < i) cloth__qp_solve_rt(P, P->rr, first);
        for (j = first; j < i; ++j) cc += P->rr[j] * P->rr[j];
        dn = ap * ap - cc;
        dn = dn > 0.25 * ap * ap ? sqrt(dn) : cloth__qp_orthogonalize(P, p);
        cloth__qp_add(P, p, dn > 0 ? dn : DBL_MIN, ui);
    }
    P->fresh = 1;
}

/* The multipliers of the working set from scratch (the working rows as equalities), and
   y from them: removes the rounding the steps of the method accumulated. Multipliers that
   come out negative (rounding, or an ill-conditioned working set) take their rows out of the
   working set and the rest is solved again, so that u >= 0 and the method takes those rows up
   again if they are violated. */
static void cloth__qp_polish(cloth__qp *P)
{
    int32_t i;
    int dropped = 1;
    /* a factor built by additions alone is already this one: each row was orthogonalized
       against the rows before it in the working set, as the refactorization does (to
       rounding); only deletions' rotations leave it a factor of a slightly different matrix */
    if (!P->fresh) cloth__qp_refactor(P);
    while (dropped) {
        dropped = 0;
        /* P->r serves as the right-hand side: it is free between steps. */
        for (i = 0; i < P->q; ++i) P->r[i] = P->b[P->set[i]];
        cloth__qp_solve_refined(P, P->r);
        for (i = P->q - 1; i >= 0; --i)
            if (P->u[i] < 0) {
                cloth__qp_drop(P, i);
                dropped = 1;
            }
    }
}

/* A_j . y, and in *size the sum of the magnitudes of its terms |c_je| |n_j| |y_v|. */
static double cloth__qp_row_apply_size(const cloth__qp *P, int32_t j, const double *vec, double *size)
{
    const int32_t *vj = P->v + 4 * (size_t)j;
    const double *cj = P->c + 4 * (size_t)j, *nj = P->nrm + 3 * (size_t)j;
    double s = 0, sz = 0, nn = sqrt(nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2]);
    int32_t e;
    for (e = 0; e < P->cnt[j]; ++e) {
        const double *p = vec + 3 * (size_t)vj[e];
        if (cj[e] == 0) continue;
        s += cj[e] * (nj[0] * p[0] + nj[1] * p[1] + nj[2] * p[2]);
        sz += fabs(cj[e]) * nn * sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    }
    *size = sz;
    return s;
}

/* The most violated row outside the working set (largest violation over |A_j|, the lower
   index on a tie), or -1 when none is violated beyond the tolerance; its slack in *slack.
   The tolerance of row j is ftol times the size of the terms of its slack. */
static int32_t cloth__qp_most_violated(const cloth__qp *P, double ftol, double *slack)
{
    double best = 0;
    int32_t j, p = -1;
    for (j = 0; j < P->m; ++j) {
        double s, score, size;
        if (P->pos[j] >= 0 || P->anorm[j] == 0) continue;
        s = cloth__qp_row_apply_size(P, j, P->y, &size) - P->b[j];
        if (!(s < -ftol * (P->sigma[j] + size))) continue;
        score = s / P->anorm[j];
        if (p < 0 || score < best) {
            best = score;
            p = j;
            *slack = s;
        }
    }
    return p;
}

/* u_S -= t r, keeping u >= 0 against rounding. */
static void cloth__qp_dual_step(cloth__qp *P, double t)
{
    int32_t i;
    for (i = 0; i < P->q; ++i) {
        double ui = P->u[i] - t * P->r[i];
        P->u[i] = ui > 0 ? ui : 0;
    }
}

/* Goldfarb-Idnani on min |y|^2/2, A y >= b, from y = 0, or (resume) from the working set and
   factor R in P, kept from a problem with the same first rows and weights (R depends on
   nothing else): its multipliers are solved again for this b, and rows whose multiplier
   turns negative leave, which makes a dual feasible start. Notation of the paper: r is the
   dual step direction (a_p = A_S^T r + dir), t1 the partial step (a working multiplier
   reaches 0), t2 the full step (row p becomes tight). Returns CLOTH_SUCCESS with the working
   set, u and y of the solution, CLOTH_ERROR_COLLISION_UNRESOLVED (infeasible, or
   max_iterations steps) or CLOTH_ERROR_OUT_OF_MEMORY (R could not grow). */
static cloth_result cloth__qp_solve(cloth__qp *P, int resume, double ftol, double dtol, int64_t max_iterations,
                                    int32_t *iterations)
{
    size_t s, N = 3 * (size_t)P->n;
    int32_t j, polishes = 0;
    int polished = 0;
    int64_t it = 0;
    cloth_result result = CLOTH_SUCCESS;
    if (!resume) {
        P->q = 0;
        P->fresh = 1;
        memset(P->y, 0, N * sizeof(double));
    } else {
        /* the kept working set and its factor (which depend on the rows alone) with the
           multipliers and y solved for this x; rows whose multiplier comes out negative
           leave: a dual feasible start */
        cloth__qp_polish(P);
        polished = 1;
    }
    /* Rows that no vertex can move are constants. */
    for (j = 0; j < P->m; ++j)
        if (P->anorm[j] == 0 && P->b[j] > ftol * P->sigma[j]) { result = CLOTH_ERROR_COLLISION_UNRESOLVED; goto done; }
    for (;;) {
        double sp = 0, up = 0;
        int32_t p = cloth__qp_most_violated(P, ftol, &sp);
        if (p < 0) {
            /* Optimal for the working set. Polish once; a row the polish pushed over its
               bound, or took out of the working set, sends the method on (at most 3 times). */
            if (polished || polishes >= 3) break;
            cloth__qp_polish(P);
            polished = 1;
            ++polishes;
            continue;
        }
        polished = 0;
        for (;;) {
            double dn, ad = 0, t1 = 0, t2;
            int32_t i, k = -1;
            if (it >= max_iterations) { result = CLOTH_ERROR_COLLISION_UNRESOLVED; goto done; }
            ++it;
            if ((result = cloth__qp_make_room(P)) != CLOTH_SUCCESS) goto done;
            dn = cloth__qp_orthogonalize(P, p);
            if (dn > dtol * P->anorm[p] && P->q < P->qmax) ad = cloth__qp_row_apply(P, p, P->dir);
            /* Partial step: the first working multiplier to reach 0 as u_p grows. */
            for (i = 0; i < P->q; ++i)
                if (P->r[i] > 0) {
                    double ratio = P->u[i] / P->r[i];
                    if (k < 0 || ratio < t1) { t1 = ratio; k = i; }
                }
            if (!(ad > 0)) {
                /* Row p depends on the working rows: a pure dual step drops one of them, or,
                   when none can go, a_p = A_S^T r with r <= 0 proves the rows contradict. */
                if (k < 0) { result = CLOTH_ERROR_COLLISION_UNRESOLVED; goto done; }
                cloth__qp_dual_step(P, t1);
                up += t1;
                cloth__qp_drop(P, k);
                continue;
            }
            t2 = -sp / ad;
            if (k < 0 || t2 <= t1) {
                /* Full step: row p becomes tight and joins the working set. */
                for (s = 0; s < N; ++s) P->y[s] += t2 * P->dir[s];
                cloth__qp_dual_step(P, t2);
                cloth__qp_add(P, p, dn, up + t2);
                break;
            }
            for (s = 0; s < N; ++s) P->y[s] += t1 * P->dir[s];
            cloth__qp_dual_step(P, t1);
            up += t1;
            sp += t1 * ad;
            cloth__qp_drop(P, k);
        }
    }
done:
    *iterations = (int32_t)it;
    return result;
}

/* ---- results ------------------------------------------------------------------------- */

/* g_j(z) and scale_j at positions z (3n doubles). */
static double cloth__qp_violation(const cloth__qp *P, int32_t j, const double *z, double *scale)
{
    const int32_t *vj = P->v + 4 * (size_t)j;
    const double *aj = P->a + 4 * (size_t)j, *nj = P->nrm + 3 * (size_t)j;
    double g = P->t[j], sc = fabs(P->t[j]), nn = sqrt(nj[0] * nj[0] + nj[1] * nj[1] + nj[2] * nj[2]);
    int32_t e;
    for (e = 0; e < P->cnt[j]; ++e) {
        const double *p = z + 3 * (size_t)vj[e];
        g -= aj[e] * (nj[0] * p[0] + nj[1] * p[1] + nj[2] * p[2]);
        sc += fabs(aj[e]) * nn * sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    }
    *scale = sc;
    return g;
}

/* vec += alpha sum_e a_je n_j at the vertices of row j (the unscaled form of the row). */
static void cloth__qp_row_spread(const cloth__qp *P, int32_t j, double alpha, double *vec)
{
    const int32_t *vj = P->v + 4 * (size_t)j;
    const double *aj = P->a + 4 * (size_t)j, *nj = P->nrm + 3 * (size_t)j;
    int32_t e;
    for (e = 0; e < P->cnt[j]; ++e) {
        double f = alpha * aj[e];
        double *p = vec + 3 * (size_t)vj[e];
        p[0] += f * nj[0];
        p[1] += f * nj[1];
        p[2] += f * nj[2];
    }
}

/* The result: z = x + sqrt(M) y (= x + M sum_S u_j a_j n_j) in P->zd, checked (every row
   met, every row with a positive multiplier tight, to ktol times the size of its terms;
   CLOTH_ERROR_NOT_FINITE on overflow, CLOTH_ERROR_COLLISION_UNRESOLVED when the check
   fails; CLOTH_ERROR_OUT_OF_MEMORY when R cannot grow), and, when states is 1, the row
   states in P->state: the working set extended by the tight rows independent of it (each
   tight row outside the working set costs an orthogonalization, O(q^2)). */
static cloth_result cloth__qp_finish(cloth__qp *P, double ktol, double dtol, int states)
{
    size_t s, N = 3 * (size_t)P->n;
    int32_t i, j;
    for (i = 0; i < P->n; ++i)
        for (s = 3 * (size_t)i; s < 3 * (size_t)i + 3; ++s)
            P->zd[s] = P->mi[i] > 0 ? P->x[s] + P->smi[i] * P->y[s] : P->x[s];
    for (s = 0; s < N; ++s)
        if (!(fabs(P->zd[s]) <= DBL_MAX)) return CLOTH_ERROR_NOT_FINITE;
    for (j = 0; j < P->m; ++j) {
        double scale, g = cloth__qp_violation(P, j, P->zd, &scale);
        if (!(g <= ktol * scale)) return CLOTH_ERROR_COLLISION_UNRESOLVED;
        if (P->pos[j] >= 0) {
            if (P->u[P->pos[j]] > 0 && !(g >= -ktol * scale)) return CLOTH_ERROR_COLLISION_UNRESOLVED;
            P->state[j] = CLOTH_QP_ACTIVE;
            continue;
        }
        if (!(g >= -ktol * scale)) {
            P->state[j] = CLOTH_QP_INACTIVE;
            continue;
        }
        P->state[j] = CLOTH_QP_TIGHT;
        if (states && P->anorm[j] > 0 && P->q < P->qmax) {
            double dn;
            cloth_result grown = cloth__qp_make_room(P);
            if (grown != CLOTH_SUCCESS) return grown;
            dn = cloth__qp_orthogonalize(P, j);
            if (dn > dtol * P->anorm[j]) {
                cloth__qp_add(P, j, dn, 0.0);
                P->state[j] = CLOTH_QP_ACTIVE;
            }
        }
    }
    return CLOTH_SUCCESS;
}

/* The statistics of the returned z and lambda (as cloth_real), in double. Leaves y (which
   cloth_qp_project_more goes on from) as it is. */
static void cloth__qp_measure(cloth__qp *P, const cloth_real *zr, cloth_qp_stats *st)
{
    size_t s0, N = 3 * (size_t)P->n;
    int32_t i, j, k;
    double obj = 0, res = 0, scale = 0, viol = 0, comp = 0;
    /* dir: sum_j lambda_j a n at each vertex; zd: the same with absolute values, then z. */
    memset(P->dir, 0, N * sizeof(double));
    memset(P->zd, 0, N * sizeof(double));
    for (i = 0; i < P->q; ++i) {
        int32_t e, jr = P->set[i];
        double lam = (double)(cloth_real)P->u[i];
        if (lam == 0) continue;
        cloth__qp_row_spread(P, jr, lam, P->dir);
        for (e = 0; e < P->cnt[jr]; ++e) {
            double *yv = P->zd + 3 * (size_t)P->v[4 * (size_t)jr + e];
            double f = fabs(lam * P->a[4 * (size_t)jr + e]);
            for (k = 0; k < 3; ++k) yv[k] += f * fabs(P->nrm[3 * (size_t)jr + (size_t)k]);
        }
    }
    for (i = 0; i < P->n; ++i) {
        if (P->mi[i] == 0) continue;
        for (k = 0; k < 3; ++k) {
            size_t s = 3 * (size_t)i + (size_t)k;
            double d = (double)zr[s] - P->x[s];
            double rr = fabs(d - P->mi[i] * P->dir[s]);
            obj += 0.5 * d * d / P->mi[i];
            if (rr > res) res = rr;
            if (fabs(d) > scale) scale = fabs(d);
            if (P->mi[i] * P->zd[s] > scale) scale = P->mi[i] * P->zd[s];
        }
    }
    for (s0 = 0; s0 < N; ++s0) P->zd[s0] = (double)zr[s0];
    for (j = 0; j < P->m; ++j) {
        double sc, g = cloth__qp_violation(P, j, P->zd, &sc), lam = 0;
        if (sc == 0) continue;
        if (P->pos[j] >= 0) lam = (double)(cloth_real)P->u[P->pos[j]];
        if (g > 0 && g / sc > viol) viol = g / sc;
        if (lam > 0 && fabs(g) / sc > comp) comp = fabs(g) / sc;
    }
    st->objective = (cloth_real)obj;
    st->stationarity = (cloth_real)(scale > 0 ? res / scale : 0);
    st->primal_violation = (cloth_real)viol;
    st->complementarity = (cloth_real)comp;
}

/* z = x, lambda = 0, active = INACTIVE: the answer of every error. */
static void cloth__qp_fallback(const cloth_qp_problem *pr, cloth_real *z, cloth_real *lambda, int32_t *active)
{
    int32_t j;
    if (pr->vertex_count < 0 || pr->row_count < 0) return;
    if (z != pr->x && pr->x && pr->vertex_count > 0) memmove(z, pr->x, 3 * (size_t)pr->vertex_count * sizeof(cloth_real));
    for (j = 0; j < pr->row_count; ++j) {
        if (lambda) lambda[j] = 0;
        if (active) active[j] = CLOTH_QP_INACTIVE;
    }
}

/* A capacity for count items with room to grow by a quarter (cloth_qp_project_more's
   problems grow round after round). */
static int32_t cloth__qp_slack(int32_t count)
{
    int64_t c = (int64_t)count + count / 4 + 16;
    return c > INT32_MAX ? INT32_MAX : (int32_t)c;
}

/* cloth_qp_project (more = 0) and cloth_qp_project_more (more = 1). */
static cloth_result cloth__qp_project(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                      const cloth_qp_options *options, cloth_real *z, cloth_real *lambda,
                                      int32_t *active, cloth_qp_stats *stats, int more)
{
    cloth_qp_options opt = options ? *options : cloth_qp_default_options();
    cloth_qp_workspace local;
    cloth_qp_workspace *ws = workspace;
    cloth_qp_stats st;
    cloth__qp P;
    cloth_result res;
    int32_t movable = 0, j, iterations = 0, qmax = 0, q_solved = 0;
    int resume = 0;
    int64_t cap;
    size_t s;
    CLOTH_ASSERT(problem);
    CLOTH_ASSERT(z);
    CLOTH_ASSERT(opt.internal_cookie == CLOTH__QP_COOKIE); /* options not made by cloth_qp_default_options */
    memset(&st, 0, sizeof st);
    memset(&local, 0, sizeof local);
    if (!ws) ws = &local;
    res = cloth__qp_options_valid(&opt) ? cloth__qp_validate(problem, &movable) : CLOTH_ERROR_INVALID_ARGUMENT;
    if (res == CLOTH_SUCCESS) qmax = cloth__qp_qmax(problem->row_count, movable);
    if (res == CLOTH_SUCCESS && more && ws->memory) {
        /* go on when the block holds a solution and this problem extends its problem */
        const cloth__qp_saved *h = cloth__qp_head(ws);
        if (h->cookie == CLOTH__QP_COOKIE && problem->vertex_count >= h->n && problem->row_count >= h->m) {
            cloth__qp_carve(&P, ws, h->ncap, h->mcap, h->ld);
            P.n = h->n;
            P.m = h->m;
            P.q = h->q;
            P.fresh = h->fresh;
            resume = cloth__qp_extends(&P, problem, h->n, h->m);
        }
    }
    if (res == CLOTH_SUCCESS && resume) {
        if (problem->vertex_count > P.ncap || problem->row_count > P.mcap)
            res = cloth__qp_relocate(&P, problem->vertex_count > P.ncap ? cloth__qp_slack(problem->vertex_count) : P.ncap,
                                     problem->row_count > P.mcap ? cloth__qp_slack(problem->row_count) : P.mcap, P.ld);
        if (res == CLOTH_SUCCESS) {
            int32_t i;
            P.n = problem->vertex_count;
            P.m = problem->row_count;
            P.qmax = qmax;
            /* every row again (x, and with it every b_j, may have moved); the working set
               keeps its rows */
            res = cloth__qp_load(&P, problem);
            for (i = 0; i < P.q; ++i) P.pos[P.set[i]] = i;
            st.continued = 1;
        }
    } else if (res == CLOTH_SUCCESS) {
        res = cloth__qp_reserve(ws, problem->vertex_count, problem->row_count, qmax);
        if (res == CLOTH_SUCCESS) {
            cloth__qp_carve(&P, ws, problem->vertex_count, problem->row_count, qmax);
            res = cloth__qp_load(&P, problem);
        }
    }
    if (res == CLOTH_SUCCESS) {
        cap = opt.max_iterations > 0 ? (int64_t)opt.max_iterations
                                     : 10 * ((int64_t)P.m + 3 * (int64_t)P.n) + 100;
        res = cloth__qp_solve(&P, resume, (double)opt.feasibility_tolerance, (double)opt.dependency_tolerance, cap,
                              &iterations);
        st.iterations = iterations;
    }
    if (res == CLOTH_SUCCESS) {
        q_solved = P.q;
        res = cloth__qp_finish(&P, (double)opt.kkt_tolerance, (double)opt.dependency_tolerance, active != NULL);
    }
    if (res == CLOTH_SUCCESS) {
        /* what does not fit cloth_real (float) is an overflow */
        for (s = 0; s < 3 * (size_t)P.n && res == CLOTH_SUCCESS; ++s)
            if (!cloth__is_finite((cloth_real)P.zd[s])) res = CLOTH_ERROR_NOT_FINITE;
        for (j = 0; j < P.q && res == CLOTH_SUCCESS; ++j)
            if (!cloth__is_finite((cloth_real)P.u[j])) res = CLOTH_ERROR_NOT_FINITE;
    }
    if (res != CLOTH_SUCCESS) {
        if (ws->memory) cloth__qp_head(ws)->cookie = 0;
        cloth__qp_fallback(problem, z, lambda, active);
        if (stats) *stats = st;
        if (ws == &local) cloth_qp_workspace_free(&local);
        return res;
    }
    for (s = 0; s < 3 * (size_t)P.n; ++s) z[s] = (cloth_real)P.zd[s];
    for (j = 0; j < P.m; ++j) {
        if (lambda) lambda[j] = P.pos[j] >= 0 ? (cloth_real)P.u[P.pos[j]] : (cloth_real)0;
        if (active) active[j] = P.state[j];
        if (P.state[j] == CLOTH_QP_ACTIVE) ++st.active_count;
        if (P.state[j] == CLOTH_QP_TIGHT) ++st.tight_count;
    }
    if (!active) st.active_count = st.tight_count = -1; /* the states were not formed */
    if (stats) {
        cloth__qp_measure(&P, z, &st);
        *stats = st;
    }
    {
        /* kept for cloth_qp_project_more: the working set without the tight rows the result
           added at multiplier 0 (the last rows of R, so its leading part is their factor) */
        cloth__qp_saved *h = cloth__qp_head(ws);
        for (j = q_solved; j < P.q; ++j) P.pos[P.set[j]] = -1;
        P.q = q_solved;
        h->n = P.n;
        h->m = P.m;
        h->q = P.q;
        h->fresh = P.fresh;
        h->ncap = P.ncap;
        h->mcap = P.mcap;
        h->ld = P.ld;
        h->cookie = CLOTH__QP_COOKIE;
    }
    if (ws == &local) cloth_qp_workspace_free(&local);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_qp_project(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                        const cloth_qp_options *options, cloth_real *z, cloth_real *lambda,
                                        int32_t *active, cloth_qp_stats *stats)
{
    return cloth__qp_project(workspace, problem, options, z, lambda, active, stats, 0);
}

CLOTH_API cloth_result cloth_qp_project_more(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                             const cloth_qp_options *options, cloth_real *z, cloth_real *lambda,
                                             int32_t *active, cloth_qp_stats *stats)
{
    return cloth__qp_project(workspace, problem, options, z, lambda, active, stats, 1);
}

/* ---- backward ---------------------------------------------------------------------- */

static void cloth__qp_zero_gradient(const cloth_qp_problem *pr, const cloth_qp_gradient *g)
{
    size_t s, n = pr->vertex_count > 0 ? (size_t)pr->vertex_count : 0, m = pr->row_count > 0 ? (size_t)pr->row_count : 0;
    for (s = 0; s < 3 * n; ++s)
        if (g->x) g->x[s] = 0;
    for (s = 0; s < n; ++s)
        if (g->inverse_weight) g->inverse_weight[s] = 0;
    for (s = 0; s < m; ++s) {
        if (g->normal) g->normal[3 * s] = g->normal[3 * s + 1] = g->normal[3 * s + 2] = 0;
        if (g->weight) g->weight[4 * s] = g->weight[4 * s + 1] = g->weight[4 * s + 2] = g->weight[4 * s + 3] = 0;
        if (g->thickness) g->thickness[s] = 0;
    }
}

CLOTH_API cloth_result cloth_qp_backward(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
                                         const cloth_qp_options *options, const cloth_real *z,
                                         const cloth_real *lambda, const int32_t *active, const cloth_real *grad_z,
                                         const cloth_real *grad_lambda, const cloth_qp_gradient *gradient)
{
    cloth_qp_options opt = options ? *options : cloth_qp_default_options();
    cloth_qp_workspace local;
    cloth_qp_workspace *ws = workspace;
    cloth__qp P;
    cloth_result res;
    int32_t movable = 0, i, j, k, qmax;
    size_t s, N;
    double dtol;
    CLOTH_ASSERT(problem && z && lambda && active && grad_z && gradient);
    CLOTH_ASSERT(opt.internal_cookie == CLOTH__QP_COOKIE); /* options not made by cloth_qp_default_options */
    memset(&local, 0, sizeof local);
    if (!ws) ws = &local;
    cloth__qp_zero_gradient(problem, gradient);
    res = cloth__qp_options_valid(&opt) ? cloth__qp_validate(problem, &movable) : CLOTH_ERROR_INVALID_ARGUMENT;
    if (res != CLOTH_SUCCESS) return res;
    N = 3 * (size_t)problem->vertex_count;
    for (s = 0; s < N; ++s)
        if (!cloth__is_finite(z[s]) || !cloth__is_finite(grad_z[s])) return CLOTH_ERROR_NOT_FINITE;
    for (j = 0; j < problem->row_count; ++j)
        if (!cloth__is_finite(lambda[j]) || (grad_lambda && !cloth__is_finite(grad_lambda[j]))) return CLOTH_ERROR_NOT_FINITE;
    for (j = 0; j < problem->row_count; ++j)
        if (active[j] != CLOTH_QP_INACTIVE && active[j] != CLOTH_QP_ACTIVE && active[j] != CLOTH_QP_TIGHT)
            return CLOTH_ERROR_INVALID_ARGUMENT;
    qmax = cloth__qp_qmax(problem->row_count, movable);
    res = cloth__qp_reserve(ws, problem->vertex_count, problem->row_count, qmax);
    if (res == CLOTH_SUCCESS) {
        cloth__qp_carve(&P, ws, problem->vertex_count, problem->row_count, qmax);
        res = cloth__qp_load(&P, problem);
    }
    if (res != CLOTH_SUCCESS) {
        if (ws == &local) cloth_qp_workspace_free(&local);
        return res;
    }
    dtol = (double)opt.dependency_tolerance;

    /* The equalities: the active rows, factored in order, dependent ones left out. */
    for (j = 0; j < P.m; ++j) {
        double dn;
        if (active[j] != CLOTH_QP_ACTIVE || P.anorm[j] == 0 || P.q >= P.qmax) continue;
        dn = cloth__qp_orthogonalize(&P, j);
        if (dn > dtol * P.anorm[j]) cloth__qp_add(&P, j, dn, 0.0);
    }
    /* v = (G_A M G_A^T)^-1 (G_A M dL/dz - dL/dlambda_A) into P.u; the right-hand side in
       P.r. G_j M g = -sum_e a_je m_v n_j . g_v. */
    for (i = 0; i < P.q; ++i) {
        int32_t e, jr = P.set[i];
        const double *nj = P.nrm + 3 * (size_t)jr;
        double sum = 0;
        for (e = 0; e < P.cnt[jr]; ++e) {
            size_t vv = 3 * (size_t)P.v[4 * (size_t)jr + e];
            sum -= P.a[4 * (size_t)jr + e] * P.mi[P.v[4 * (size_t)jr + e]] *
                   (nj[0] * (double)grad_z[vv] + nj[1] * (double)grad_z[vv + 1] + nj[2] * (double)grad_z[vv + 2]);
        }
        if (grad_lambda) sum -= (double)grad_lambda[jr];
        P.r[i] = sum;
    }
    cloth__qp_solve_refined(&P, P.r);
    /* p = dL/dz - G_A^T v = dL/dz + sum_j v_j a_j n_j, in P.zd. */
    for (s = 0; s < N; ++s) P.zd[s] = (double)grad_z[s];
    for (i = 0; i < P.q; ++i) cloth__qp_row_spread(&P, P.set[i], P.u[i], P.zd);
    for (s = 0; s < N; ++s)
        if (!(fabs(P.zd[s]) <= DBL_MAX)) { res = CLOTH_ERROR_NOT_FINITE; break; }
    if (res == CLOTH_SUCCESS) {
        if (gradient->x)
            for (s = 0; s < N; ++s) gradient->x[s] = (cloth_real)P.zd[s];
        if (gradient->inverse_weight) {
            /* dL/dm_i = -p_i . (G_A^T lambda)_i = p_i . sum_j lambda_j a_ji n_j */
            memset(P.dir, 0, N * sizeof(double));
            for (j = 0; j < P.m; ++j)
                if (active[j] == CLOTH_QP_ACTIVE && lambda[j] != 0) cloth__qp_row_spread(&P, j, (double)lambda[j], P.dir);
            for (i = 0; i < P.n; ++i) {
                const double *p = P.zd + 3 * (size_t)i, *d = P.dir + 3 * (size_t)i;
                gradient->inverse_weight[i] = (cloth_real)(p[0] * d[0] + p[1] * d[1] + p[2] * d[2]);
            }
        }
        for (j = 0; j < P.m; ++j) {
            const double *nj = P.nrm + 3 * (size_t)j;
            double vj, lam, gn[3] = { 0, 0, 0 }, dG[4][3] = { { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 }, { 0, 0, 0 } };
            int32_t e;
            if (active[j] != CLOTH_QP_ACTIVE) continue;
            vj = P.pos[j] >= 0 ? P.u[P.pos[j]] : 0;
            lam = (double)lambda[j];
            /* dL/dG_(j,v) = -m_v lambda_j p_v - v_j z_v; G_(j,v) = -a_jv n_j. */
            for (e = 0; e < P.cnt[j]; ++e) {
                int32_t vv = P.v[4 * (size_t)j + e];
                double ae = P.a[4 * (size_t)j + e];
                for (k = 0; k < 3; ++k) {
                    size_t sk = 3 * (size_t)vv + (size_t)k;
                    dG[e][k] = -P.mi[vv] * lam * P.zd[sk] - vj * (double)z[sk];
                    gn[k] -= ae * dG[e][k];
                }
            }
            if (gradient->normal)
                for (k = 0; k < 3; ++k) gradient->normal[3 * (size_t)j + (size_t)k] = (cloth_real)gn[k];
            if (gradient->weight)
                for (k = 0; k < 4; ++k) {
                    int32_t vk = problem->rows[j].vertex[k];
                    if (vk < 0) continue;
                    for (e = 0; e < P.cnt[j]; ++e)
                        if (P.v[4 * (size_t)j + e] == vk) break;
                    gradient->weight[4 * (size_t)j + (size_t)k] =
                        (cloth_real)(-(nj[0] * dG[e][0] + nj[1] * dG[e][1] + nj[2] * dG[e][2]));
                }
            if (gradient->thickness) gradient->thickness[j] = (cloth_real)(-vj);
        }
    }
    if (res != CLOTH_SUCCESS) cloth__qp_zero_gradient(problem, gradient);
    if (ws == &local) cloth_qp_workspace_free(&local);
    return res;
}


/* ------------------------------------------------------------------------------------- */
/* contact                                                                               */
/* ------------------------------------------------------------------------------------- */

#define CLOTH__CONTACT_COOKIE 0xC10C7AC7u
#define CLOTH__OBSTACLE_COOKIE 0xC10B5AC1u
/* Newton steps of the analytic entry time before it is taken where it stands (conservative). */
#define CLOTH__CONTACT_NEWTON_STEPS 64
#define CLOTH__CONTACT_PROXY_SUBDIVISIONS 1 /* a sphere's inner proxy: 42 vertices (PROXY) */
/* Sweeps over the analytic obstacles for one vertex (a vertex in a corner between two). */
#define CLOTH__CONTACT_ANALYTIC_SWEEPS 4
/* Projected Gauss-Seidel sweeps of the velocity pass over the impact rows. */
#define CLOTH__CONTACT_VELOCITY_SWEEPS 4
/* Pairs closer than this at x0 (m) cannot be guarded by a separation and are not tested. */
#define CLOTH__CONTACT_MIN_SEPARATION 1e-11
#define CLOTH__CONTACT_SQRT3 1.7320508075688772

/* A growable scratch buffer: capacity in elements of the size it was grown with. */
typedef struct cloth__contact_buf {
    void *data;
    size_t capacity;
} cloth__contact_buf;

#define CLOTH__CONTACT_AT(buf, type) ((type *)(buf).data)

/* An obstacle as the contact keeps it. For a mesh: its own copy of the local vertices and the
   triangles, world positions at the start and end of the step, topology and tree. Mesh
   vertices are nodes n + node_offset + i of the impact rows (n the cloth's vertex count). */
typedef struct cloth__contact_obstacle {
    cloth_obstacle_def def; /* mesh pointers cleared */
    cloth_pose start, end;
    int32_t vertex_count, triangle_count, node_offset;
    cloth_real *local_x, *x_start, *x_end;
    int32_t *tri;
    cloth_topology topology;
    cloth_bvh bvh;
    int moved; /* the tree has not been refitted since the positions changed */
} cloth__contact_obstacle;

/* An impact found by CCD, and later a row of its zone's QP. */
typedef struct cloth__contact_impact {
    int32_t node[4];          /* vertex-face: p, f0, f1, f2; edge-edge: a0, a1, b0, b1 */
    cloth_real w[4];          /* row weights */
    cloth_real normal[3];
    cloth_real thickness, toi, mu_s, mu_k;
    cloth_real impulse;       /* normal impulse of the projections (N s) */
    cloth_real vel_normal;    /* normal impulse of the velocity pass (N s) */
    cloth_real vel_friction[3]; /* tangential impulse of the velocity pass (N s) */
    int32_t edge_edge;
    int32_t stale;            /* its row already held at x1 when found (see cloth__contact_test) */
    int32_t friction_used;    /* scratch of the velocity pass */
} cloth__contact_impact;

/* A primitive pair of the narrow phase that makes an impact or needs a CCD query. The
   enumeration (serial) records them in order; the queries then run on the pool, each on its
   own record; impacts are added from the records in order afterwards
   (cloth__contact_finish_pending), so the impacts, their order and the stats do not depend on
   the thread count. */
typedef struct cloth__contact_pending {
    int32_t node[4];
    int32_t edge_edge;
    int32_t query;            /* 1: a CCD query, whose answer sets toi, proximity and impact */
    int32_t impact;           /* an impact at toi is added (a query: it found one, or proximity) */
    int32_t proximity;        /* the impact is a proximity row (at toi 1) */
    int32_t budget_exhausted; /* the query's */
    cloth_real thickness, mu_s, mu_k;
    double toi, dp;           /* the impact's time, the separation tested */
    int64_t checks;           /* the query's */
} cloth__contact_pending;

/* A pair of triangles that share a vertex (skipped by the BVH) with the primitive pairs it
   owns (bits, see cloth__contact_owned). */
typedef struct cloth__contact_adjacent_pair {
    int32_t a, b, owned;
} cloth__contact_adjacent_pair;

/* Part of the self traversal run on the pool (cloth__contact_self_pairs): the traversal from
   one seed, its candidates culled and owned as cloth__contact_on_self_pair does, the pairs
   left (a, b, owned, as cloth__contact_adjacent_pair) kept in order for the serial tests. */
typedef struct cloth__contact_self_task {
    int32_t seed_a, seed_b;
    int32_t first, count, capacity; /* its pairs in c->self_found */
    int32_t candidates, culled;
    int overflow;                   /* more pairs than the capacity: the task runs again serially */
    struct cloth_contact *c;
} cloth__contact_self_task;

/* A vertex in contact with an analytic obstacle during the step. */
typedef struct cloth__contact_touch {
    int32_t vertex, obstacle, next;
    cloth_real normal[3]; /* world, at the end of the step */
    cloth_real point[3];  /* world: the point of the thickness layer under the vertex */
} cloth__contact_touch;

struct cloth_contact {
    cloth_contact_def def; /* tri and triangle_piece point to the copies below */
    cloth_allocator allocator;
    int32_t n, m;
    int32_t *tri, *piece;
    cloth_topology topology;
    cloth_bvh bvh;
    int bvh_built;
    /* The pairs of triangles that share a vertex and own primitive pairs (see
       cloth__contact_adjacent_pairs), in the order of their enumeration, made once at
       create: the topology and the enabled pairs never change. */
    cloth__contact_adjacent_pair *adjacent;
    int32_t adjacent_count;
    cloth__contact_obstacle *obstacles;
    int32_t obstacle_count, obstacle_capacity, obstacle_nodes, analytic_count, mesh_count;
    cloth_qp_workspace qp;

    /* the call in progress */
    const cloth_real *x0;
    cloth_real *x1;
    const cloth_real *inverse_mass;
    cloth_real h;
    cloth_contact_stats stats;
    cloth_result error;
    int32_t round, all_touched, found_count, impact_count, touch_count, stamp;
    int32_t pending_count, pending_queries, pending_parts; /* records of this round, of them CCD queries, parts */
    struct cloth__pool *pool;       /* the world's, for the narrow phase's CCD queries; NULL: serial */

    /* scratch, grown geometrically and kept */
    cloth__contact_buf x_in;        /* cloth_real 3n: x1 as it came in */
    cloth__contact_buf touch_stamp; /* int32 n: round from which a vertex's pairs are tested */
    cloth__contact_buf node_mark;   /* unsigned char per tree node: a triangle under it touched */
    cloth__contact_buf dirty_stamp; /* int32 n: round whose analytic pass must see the vertex */
    cloth__contact_buf parent;      /* int32 n: union-find of zones */
    cloth__contact_buf zsize;       /* int32 n: zone sizes at roots */
    cloth__contact_buf zstate;      /* int32 n: fail-safe state at roots: 0, 1 rigid, 2 frozen */
    cloth__contact_buf zflag;       /* int32 n: 1 at roots of zones with immovable members */
    cloth__contact_buf zmark;       /* int32 n: stamps (c->stamp) at vertices and roots */
    cloth__contact_buf zslot;       /* int32 n: fail-safe: a marked root's slot in rigid_sum */
    cloth__contact_buf rigid_sum;   /* cloth_real 4 per slot: mass-weighted displacement, mass */
    cloth__contact_buf touch_head;  /* int32 n: first analytic touch of a vertex, -1 */
    cloth__contact_buf touches;     /* cloth__contact_touch */
    cloth__contact_buf pending;     /* cloth__contact_pending: this round's, in enumeration order */
    cloth__contact_buf found;       /* cloth__contact_impact: this round's */
    cloth__contact_buf impacts;     /* cloth__contact_impact: the step's rows */
    cloth__contact_buf order;       /* int32 */
    cloth__contact_buf order_tmp;   /* int32 */
    cloth__contact_buf key;         /* int32 */
    cloth__contact_buf node_local;  /* int32 n + obstacle nodes: -1 or a zone-local index */
    cloth__contact_buf local_node;  /* int32: zone-local index -> node (-1 virtual) */
    cloth__contact_buf qp_x;        /* cloth_real 3 per local */
    cloth__contact_buf qp_w;        /* cloth_real per local */
    cloth__contact_buf qp_z;        /* cloth_real 3 per local */
    cloth__contact_buf qp_rows;     /* cloth_qp_row */
    cloth__contact_buf qp_row_impact; /* int32 per row: impact, -1 for touch rows */
    cloth__contact_buf qp_lambda;   /* cloth_real per row */
    cloth__contact_buf self_seeds;  /* int32: the parallel self traversal's seeds and their scratch, */
    cloth__contact_buf self_tasks;  /* cloth__contact_self_task: its parts, */
    cloth__contact_buf self_found;  /* cloth__contact_adjacent_pair: their pairs, self_capacity a part */
    int32_t self_capacity, self_count, self_parts;
    const unsigned char *self_mark; /* the pass's node marks (NULL: every node) */
};

/* ---- small helpers ------------------------------------------------------------------ */

static double cloth__contact_dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double cloth__contact_len(const double *a) { return sqrt(cloth__contact_dot(a, a)); }
static void cloth__contact_cross(const double *a, const double *b, double *out)
{
    double c0 = a[1] * b[2] - a[2] * b[1], c1 = a[2] * b[0] - a[0] * b[2], c2 = a[0] * b[1] - a[1] * b[0];
    out[0] = c0; out[1] = c1; out[2] = c2;
}
static void cloth__contact_load(const cloth_real *p, double *out) { out[0] = (double)p[0]; out[1] = (double)p[1]; out[2] = (double)p[2]; }
static int cloth__contact_finite(double v) { return v == v && v - v == 0; }
static double cloth__contact_clock_default(void *user) { (void)user; return (double)clock() / (double)CLOCKS_PER_SEC; }
static double cloth__contact_now(const cloth_contact *c)
{
    return c->def.clock ? c->def.clock(c->def.clock_user) : cloth__contact_clock_default(NULL);
}

/* Make room for `need` elements of `elem` bytes, keeping the contents; capacity doubles. */
static int cloth__contact_grow(cloth_contact *c, cloth__contact_buf *b, size_t need, size_t elem)
{
    size_t cap;
    void *p;
    if (need <= b->capacity) return 1;
    cap = b->capacity ? b->capacity : 64;
    while (cap < need) {
        if (cap > SIZE_MAX / 2 / elem) return 0;
        cap *= 2;
    }
    p = cloth__alloc_array(&c->allocator, cap, elem);
    if (!p) return 0;
    if (b->capacity && b->data) memcpy(p, b->data, b->capacity * elem);
    cloth__free(&c->allocator, b->data);
    b->data = p;
    b->capacity = cap;
    return 1;
}

static void cloth__contact_buf_free(cloth_contact *c, cloth__contact_buf *b)
{
    cloth__free(&c->allocator, b->data);
    b->data = NULL;
    b->capacity = 0;
}

/* ---- poses -------------------------------------------------------------------------- */

CLOTH_API cloth_pose cloth_pose_identity(void)
{
    cloth_pose p;
    int i;
    for (i = 0; i < 9; ++i) p.rotation[i] = (cloth_real)(i % 4 == 0 ? 1 : 0);
    p.translation[0] = p.translation[1] = p.translation[2] = 0;
    return p;
}

CLOTH_API cloth_pose cloth_pose_make(const cloth_real translation[3], const cloth_real axis[3], cloth_real angle)
{
    cloth_pose p = cloth_pose_identity();
    double a[3] = {0, 0, 0}, len, c, s, t;
    int i, j;
    if (translation)
        for (i = 0; i < 3; ++i) p.translation[i] = translation[i];
    if (!axis) return p;
    cloth__contact_load(axis, a);
    len = cloth__contact_len(a);
    if (!(len > 0) || !cloth__contact_finite(len)) return p;
    for (i = 0; i < 3; ++i) a[i] /= len;
    c = cos((double)angle);
    s = sin((double)angle);
    t = 1 - c;
    /* Rodrigues: R = c I + s [a]x + t a a^T */
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) p.rotation[3 * i + j] = (cloth_real)(t * a[i] * a[j] + (i == j ? c : 0));
    p.rotation[1] -= (cloth_real)(s * a[2]);
    p.rotation[2] += (cloth_real)(s * a[1]);
    p.rotation[3] += (cloth_real)(s * a[2]);
    p.rotation[5] -= (cloth_real)(s * a[0]);
    p.rotation[6] -= (cloth_real)(s * a[1]);
    p.rotation[7] += (cloth_real)(s * a[0]);
    return p;
}

/* In double: world = R local + t, local = R^T (world - t). */
CLOTH_API cloth_pose cloth_pose_interpolate(const cloth_pose *a, const cloth_pose *b, cloth_real f)
{
    cloth_pose out, turn;
    double rel[9], w[3], axis[3], sine, cosine, angle;
    int i, j, k;
    CLOTH_ASSERT(a && b);
    for (i = 0; i < 3; ++i) out.translation[i] = a->translation[i] + f * (b->translation[i] - a->translation[i]);
    /* rel = Rb Ra^T, the rotation from a's orientation to b's */
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            double sum = 0;
            for (k = 0; k < 3; ++k) sum += (double)b->rotation[3 * i + k] * (double)a->rotation[3 * j + k];
            rel[3 * i + j] = sum;
        }
    /* its axis and angle: 2 sin(angle) axis = the skew part, 1 + 2 cos(angle) = the trace */
    w[0] = rel[7] - rel[5];
    w[1] = rel[2] - rel[6];
    w[2] = rel[3] - rel[1];
    sine = cloth__contact_len(w) / 2;
    cosine = (rel[0] + rel[4] + rel[8] - 1) / 2;
    angle = atan2(sine, cosine);
    if (sine > 1e-6) {
        for (i = 0; i < 3; ++i) axis[i] = w[i] / (2 * sine);
    } else if (cosine < 0) {
        /* near a half turn the skew part vanishes: the axis from the symmetric part,
           rel + I = 2 axis axis^T, its largest column */
        int best = 0;
        double len;
        for (i = 1; i < 3; ++i)
            if (rel[4 * i] > rel[4 * best]) best = i;
        for (i = 0; i < 3; ++i) axis[i] = (rel[3 * i + best] + rel[3 * best + i]) / 2 + (i == best ? 1 : 0);
        len = cloth__contact_len(axis);
        for (i = 0; i < 3; ++i) axis[i] = len > 0 ? axis[i] / len : (i == 0);
        if (cloth__contact_dot(axis, w) < 0)
            for (i = 0; i < 3; ++i) axis[i] = -axis[i];
    } else {
        axis[0] = 1; axis[1] = axis[2] = 0; /* no turn */
        angle = 0;
    }
    {
        cloth_real ax[3];
        for (i = 0; i < 3; ++i) ax[i] = (cloth_real)axis[i];
        turn = cloth_pose_make(NULL, ax, (cloth_real)(f * angle));
    }
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            double sum = 0;
            for (k = 0; k < 3; ++k) sum += (double)turn.rotation[3 * i + k] * (double)a->rotation[3 * k + j];
            out.rotation[3 * i + j] = (cloth_real)sum;
        }
    return out;
}

static void cloth__contact_pose_to_world(const cloth_pose *pose, const double *p, double *out)
{
    const cloth_real *R = pose->rotation;
    double q[3];
    int i;
    for (i = 0; i < 3; ++i)
        q[i] = (double)R[3 * i] * p[0] + (double)R[3 * i + 1] * p[1] + (double)R[3 * i + 2] * p[2] + (double)pose->translation[i];
    out[0] = q[0]; out[1] = q[1]; out[2] = q[2];
}
static void cloth__contact_pose_to_local(const cloth_pose *pose, const double *p, double *out)
{
    const cloth_real *R = pose->rotation;
    double d[3], q[3];
    int i;
    for (i = 0; i < 3; ++i) d[i] = p[i] - (double)pose->translation[i];
    for (i = 0; i < 3; ++i) q[i] = (double)R[i] * d[0] + (double)R[3 + i] * d[1] + (double)R[6 + i] * d[2];
    out[0] = q[0]; out[1] = q[1]; out[2] = q[2];
}
static void cloth__contact_rotate(const cloth_pose *pose, const double *v, double *out)
{
    const cloth_real *R = pose->rotation;
    double q[3];
    int i;
    for (i = 0; i < 3; ++i) q[i] = (double)R[3 * i] * v[0] + (double)R[3 * i + 1] * v[1] + (double)R[3 * i + 2] * v[2];
    out[0] = q[0]; out[1] = q[1]; out[2] = q[2];
}

CLOTH_API void cloth_pose_apply(const cloth_pose *pose, const cloth_real p[3], cloth_real out[3])
{
    double a[3];
    CLOTH_ASSERT(pose && p && out);
    cloth__contact_load(p, a);
    cloth__contact_pose_to_world(pose, a, a);
    out[0] = (cloth_real)a[0]; out[1] = (cloth_real)a[1]; out[2] = (cloth_real)a[2];
}

CLOTH_API void cloth_pose_apply_inverse(const cloth_pose *pose, const cloth_real p[3], cloth_real out[3])
{
    double a[3];
    CLOTH_ASSERT(pose && p && out);
    cloth__contact_load(p, a);
    cloth__contact_pose_to_local(pose, a, a);
    out[0] = (cloth_real)a[0]; out[1] = (cloth_real)a[1]; out[2] = (cloth_real)a[2];
}

static int cloth__contact_pose_finite(const cloth_pose *p)
{
    int i;
    for (i = 0; i < 9; ++i)
        if (!cloth__is_finite(p->rotation[i])) return 0;
    for (i = 0; i < 3; ++i)
        if (!cloth__is_finite(p->translation[i])) return 0;
    return 1;
}

/* ---- defaults, setup ---------------------------------------------------------------- */

CLOTH_API cloth_obstacle_def cloth_default_obstacle_def(void)
{
    cloth_obstacle_def d;
    memset(&d, 0, sizeof d);
    d.cookie = CLOTH__OBSTACLE_COOKIE;
    d.shape = CLOTH_OBSTACLE_PLANE;
    d.radius = (cloth_real)0.5;
    d.half_length = (cloth_real)0.5;
    d.half_extents[0] = d.half_extents[1] = d.half_extents[2] = (cloth_real)0.5;
    d.pose = cloth_pose_identity();
    d.thickness = (cloth_real)1e-3;
    d.friction_static = (cloth_real)0.5;
    d.friction_kinetic = (cloth_real)0.5;
    return d;
}

CLOTH_API cloth_contact_def cloth_default_contact_def(void)
{
    cloth_contact_def d;
    memset(&d, 0, sizeof d);
    d.cookie = CLOTH__CONTACT_COOKIE;
    d.thickness = (cloth_real)1e-3;
    d.detection_ratio = (cloth_real)0.25;
    d.friction_static = (cloth_real)0.3;
    d.friction_kinetic = (cloth_real)0.3;
    d.max_rounds = 100;
    d.max_rigid_rounds = 50;
    d.ccd_relative_tolerance = (cloth_real)0.25;
    d.impacts_per_vertex = 2;
    d.ccd_max_checks = 100000;
    d.ccd_refine_checks = 64;
    return d;
}

static void cloth__contact_obstacle_free(cloth_contact *c, cloth__contact_obstacle *o)
{
    cloth__free(&c->allocator, o->local_x);
    cloth__free(&c->allocator, o->x_start);
    cloth__free(&c->allocator, o->x_end);
    cloth__free(&c->allocator, o->tri);
    cloth_topology_free(&o->topology);
    cloth_bvh_free(&o->bvh);
    memset(o, 0, sizeof *o);
}

CLOTH_API void cloth_contact_destroy(cloth_contact *c)
{
    cloth_allocator a;
    int32_t i;
    if (!c) return;
    a = c->allocator;
    for (i = 0; i < c->obstacle_count; ++i) cloth__contact_obstacle_free(c, &c->obstacles[i]);
    cloth__free(&a, c->obstacles);
    cloth__free(&a, c->adjacent);
    cloth__free(&a, c->tri);
    cloth__free(&a, c->piece);
    cloth_topology_free(&c->topology);
    cloth_bvh_free(&c->bvh);
    cloth_qp_workspace_free(&c->qp);
    cloth__contact_buf_free(c, &c->x_in);
    cloth__contact_buf_free(c, &c->touch_stamp);
    cloth__contact_buf_free(c, &c->node_mark);
    cloth__contact_buf_free(c, &c->dirty_stamp);
    cloth__contact_buf_free(c, &c->parent);
    cloth__contact_buf_free(c, &c->zsize);
    cloth__contact_buf_free(c, &c->zstate);
    cloth__contact_buf_free(c, &c->zflag);
    cloth__contact_buf_free(c, &c->zmark);
    cloth__contact_buf_free(c, &c->zslot);
    cloth__contact_buf_free(c, &c->rigid_sum);
    cloth__contact_buf_free(c, &c->touch_head);
    cloth__contact_buf_free(c, &c->touches);
    cloth__contact_buf_free(c, &c->pending);
    cloth__contact_buf_free(c, &c->found);
    cloth__contact_buf_free(c, &c->impacts);
    cloth__contact_buf_free(c, &c->order);
    cloth__contact_buf_free(c, &c->order_tmp);
    cloth__contact_buf_free(c, &c->key);
    cloth__contact_buf_free(c, &c->node_local);
    cloth__contact_buf_free(c, &c->local_node);
    cloth__contact_buf_free(c, &c->qp_x);
    cloth__contact_buf_free(c, &c->qp_w);
    cloth__contact_buf_free(c, &c->qp_z);
    cloth__contact_buf_free(c, &c->qp_rows);
    cloth__contact_buf_free(c, &c->qp_row_impact);
    cloth__contact_buf_free(c, &c->qp_lambda);
    cloth__contact_buf_free(c, &c->self_seeds);
    cloth__contact_buf_free(c, &c->self_tasks);
    cloth__contact_buf_free(c, &c->self_found);
    a.free(c, a.user);
}

static int32_t cloth__contact_list_adjacent(const cloth_contact *c, cloth__contact_adjacent_pair *out);

CLOTH_API cloth_result cloth_contact_create(cloth_contact **out, const cloth_contact_def *def)
{
    cloth_allocator a;
    cloth_contact *c;
    cloth_result r;
    int32_t i;
    CLOTH_ASSERT(out && def);
    *out = NULL;
    CLOTH_ASSERT(def->cookie == CLOTH__CONTACT_COOKIE); /* def not made by cloth_default_contact_def */
    if (def->vertex_count < 0 || def->triangle_count < 0 || (def->triangle_count > 0 && !def->tri) ||
        !(def->thickness > 0) || !cloth__is_finite(def->thickness) || !(def->detection_ratio > 0) ||
        !(def->detection_ratio <= (cloth_real)0.5) || !(def->friction_static >= 0) || !(def->friction_kinetic >= 0) ||
        !(def->friction_kinetic <= def->friction_static) || !cloth__is_finite(def->friction_static) || def->max_rounds < 1 ||
        def->max_rigid_rounds < 0 || !(def->ccd_relative_tolerance > 0) || !(def->detection_ratio * (1 + def->ccd_relative_tolerance) <= (cloth_real)0.4) ||
        def->impacts_per_vertex < 1 ||
        def->ccd_max_checks < 1 || def->ccd_refine_checks < 0 || (def->triangle_count > 0 && def->vertex_count == 0))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if (def->triangle_count > (INT32_MAX - 1) / 3) return CLOTH_ERROR_SIZE_OVERFLOW;
    a = cloth__allocator_or_default(&def->allocator);
    c = (cloth_contact *)a.alloc(sizeof *c, a.user);
    if (!c) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(c, 0, sizeof *c);
    c->allocator = a;
    c->def = *def;
    c->def.allocator = a;
    c->n = def->vertex_count;
    c->m = def->triangle_count;
    c->qp.allocator = a;
    c->tri = (int32_t *)cloth__alloc_array(&a, (size_t)c->m * 3, sizeof(int32_t));
    c->piece = (int32_t *)cloth__alloc_array(&a, (size_t)c->m, sizeof(int32_t));
    if (!c->tri || !c->piece) { cloth_contact_destroy(c); return CLOTH_ERROR_OUT_OF_MEMORY; }
    if (c->m) memcpy(c->tri, def->tri, (size_t)c->m * 3 * sizeof(int32_t));
    for (i = 0; i < c->m; ++i) c->piece[i] = def->triangle_piece ? def->triangle_piece[i] : 0;
    c->def.tri = c->tri;
    c->def.triangle_piece = c->piece;
    {
        cloth_mesh view;
        memset(&view, 0, sizeof view);
        view.vertex_count = c->n;
        view.triangle_count = c->m;
        view.tri = c->tri;
        r = cloth_topology_build(&c->topology, &view, &a);
        if (r != CLOTH_SUCCESS) { cloth_contact_destroy(c); return r; }
    }
    c->adjacent_count = cloth__contact_list_adjacent(c, NULL);
    if (c->adjacent_count > 0) {
        c->adjacent = (cloth__contact_adjacent_pair *)cloth__alloc_array(&a, (size_t)c->adjacent_count, sizeof *c->adjacent);
        if (!c->adjacent) { cloth_contact_destroy(c); return CLOTH_ERROR_OUT_OF_MEMORY; }
        cloth__contact_list_adjacent(c, c->adjacent);
    }
    *out = c;
    return CLOTH_SUCCESS;
}

CLOTH_API const cloth_contact_def *cloth_contact_get_def(const cloth_contact *c)
{
    CLOTH_ASSERT(c);
    return &c->def;
}

CLOTH_API int32_t cloth_contact_obstacle_count(const cloth_contact *c)
{
    CLOTH_ASSERT(c);
    return c->obstacle_count;
}

/* World positions of a mesh obstacle from its local vertices and a pose. */
static void cloth__contact_pose_mesh(const cloth__contact_obstacle *o, const cloth_pose *pose, cloth_real *out)
{
    int32_t i;
    for (i = 0; i < o->vertex_count; ++i) {
        double p[3];
        cloth__contact_load(o->local_x + 3 * i, p);
        cloth__contact_pose_to_world(pose, p, p);
        out[3 * i] = (cloth_real)p[0]; out[3 * i + 1] = (cloth_real)p[1]; out[3 * i + 2] = (cloth_real)p[2];
    }
}

CLOTH_API cloth_result cloth_contact_add_obstacle(cloth_contact *c, const cloth_obstacle_def *def, int32_t *index)
{
    cloth__contact_obstacle o;
    cloth_result r;
    CLOTH_ASSERT(c && def);
    CLOTH_ASSERT(def->cookie == CLOTH__OBSTACLE_COOKIE); /* def not made by cloth_default_obstacle_def */
    if (index) *index = -1;
    if ((int)def->shape < (int)CLOTH_OBSTACLE_PLANE || (int)def->shape > (int)CLOTH_OBSTACLE_MESH ||
        !(def->thickness > 0) || !cloth__is_finite(def->thickness) || !(def->friction_static >= 0) ||
        !cloth__is_finite(def->friction_static) || !(def->friction_kinetic >= 0) ||
        !(def->friction_kinetic <= def->friction_static) || !cloth__contact_pose_finite(&def->pose))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if ((def->shape == CLOTH_OBSTACLE_SPHERE || def->shape == CLOTH_OBSTACLE_CAPSULE) &&
        (!(def->radius >= 0) || !cloth__is_finite(def->radius)))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if (def->shape == CLOTH_OBSTACLE_CAPSULE && (!(def->half_length >= 0) || !cloth__is_finite(def->half_length)))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if (def->shape == CLOTH_OBSTACLE_BOX) {
        int k;
        for (k = 0; k < 3; ++k)
            if (!(def->half_extents[k] >= 0) || !cloth__is_finite(def->half_extents[k])) return CLOTH_ERROR_INVALID_ARGUMENT;
    }
    memset(&o, 0, sizeof o);
    o.def = *def;
    o.def.mesh_x = NULL;
    o.def.mesh_tri = NULL;
    o.start = o.end = def->pose;
    if (def->shape == CLOTH_OBSTACLE_MESH || ((def->shape == CLOTH_OBSTACLE_SPHERE || def->shape == CLOTH_OBSTACLE_CAPSULE) && def->radius > 0) ||
        (def->shape == CLOTH_OBSTACLE_BOX && def->half_extents[0] > 0 && def->half_extents[1] > 0 && def->half_extents[2] > 0)) {
        /* a mesh obstacle's mesh, or a sphere's, capsule's or box's inner proxy (PROXY above) */
        cloth_mesh proxy;
        const cloth_real *mx = def->mesh_x;
        const int32_t *mt = def->mesh_tri;
        int32_t nv = def->mesh_vertex_count, nt = def->mesh_triangle_count, i;
        cloth_mesh view;
        cloth_bvh_def bd;
        memset(&proxy, 0, sizeof proxy);
        if (def->shape != CLOTH_OBSTACLE_MESH) {
            if (def->shape == CLOTH_OBSTACLE_SPHERE)
                r = cloth_mesh_icosphere(&proxy, def->radius / 2, CLOTH__CONTACT_PROXY_SUBDIVISIONS, &c->allocator);
            else if (def->shape == CLOTH_OBSTACLE_CAPSULE)
                r = cloth_mesh_capsule(&proxy, def->radius / 2, 2 * def->half_length, 12, 2, &c->allocator);
            else
                r = cloth_mesh_box(&proxy, def->half_extents[0] / 2, def->half_extents[1] / 2, def->half_extents[2] / 2, 1, &c->allocator);
            if (r != CLOTH_SUCCESS) return r;
            mx = proxy.x;
            mt = proxy.tri;
            nv = proxy.vertex_count;
            nt = proxy.triangle_count;
        }
        if (nv <= 0 || nt <= 0 || !mx || !mt) { cloth_mesh_free(&proxy); return CLOTH_ERROR_INVALID_ARGUMENT; }
        if (nt > (INT32_MAX - 1) / 3 || nv > (INT32_MAX - 1) / 3 || (int64_t)c->obstacle_nodes + nv + c->n > INT32_MAX) {
            cloth_mesh_free(&proxy);
            return CLOTH_ERROR_SIZE_OVERFLOW;
        }
        for (i = 0; i < 3 * nv; ++i)
            if (!cloth__is_finite(mx[i])) { cloth_mesh_free(&proxy); return CLOTH_ERROR_NOT_FINITE; }
        o.vertex_count = nv;
        o.triangle_count = nt;
        o.local_x = (cloth_real *)cloth__alloc_array(&c->allocator, (size_t)nv * 3, sizeof(cloth_real));
        o.x_start = (cloth_real *)cloth__alloc_array(&c->allocator, (size_t)nv * 3, sizeof(cloth_real));
        o.x_end = (cloth_real *)cloth__alloc_array(&c->allocator, (size_t)nv * 3, sizeof(cloth_real));
        o.tri = (int32_t *)cloth__alloc_array(&c->allocator, (size_t)nt * 3, sizeof(int32_t));
        if (!o.local_x || !o.x_start || !o.x_end || !o.tri) {
            cloth_mesh_free(&proxy);
            cloth__contact_obstacle_free(c, &o);
            return CLOTH_ERROR_OUT_OF_MEMORY;
        }
        memcpy(o.local_x, mx, (size_t)nv * 3 * sizeof(cloth_real));
        memcpy(o.tri, mt, (size_t)nt * 3 * sizeof(int32_t));
        cloth_mesh_free(&proxy);
        memset(&view, 0, sizeof view);
        view.vertex_count = nv;
        view.triangle_count = nt;
        view.tri = o.tri;
        r = cloth_topology_build(&o.topology, &view, &c->allocator);
        if (r != CLOTH_SUCCESS) { cloth__contact_obstacle_free(c, &o); return r; }
        cloth__contact_pose_mesh(&o, &o.start, o.x_start);
        memcpy(o.x_end, o.x_start, (size_t)nv * 3 * sizeof(cloth_real));
        bd = cloth_default_bvh_def();
        r = cloth_bvh_build(&o.bvh, o.x_start, o.x_end, nv, o.tri, nt, &bd, &c->allocator);
        if (r != CLOTH_SUCCESS) { cloth__contact_obstacle_free(c, &o); return r; }
        o.moved = 1;
        o.node_offset = c->obstacle_nodes;
    }
    if (c->obstacle_count == c->obstacle_capacity) {
        int32_t cap = c->obstacle_capacity ? 2 * c->obstacle_capacity : 4;
        cloth__contact_obstacle *p = (cloth__contact_obstacle *)cloth__alloc_array(&c->allocator, (size_t)cap, sizeof *p);
        if (!p) { cloth__contact_obstacle_free(c, &o); return CLOTH_ERROR_OUT_OF_MEMORY; }
        if (c->obstacle_count) memcpy(p, c->obstacles, (size_t)c->obstacle_count * sizeof *p);
        cloth__free(&c->allocator, c->obstacles);
        c->obstacles = p;
        c->obstacle_capacity = cap;
    }
    c->obstacles[c->obstacle_count] = o;
    c->obstacle_nodes += o.vertex_count;
    if (o.triangle_count > 0) c->mesh_count++; /* met by CCD: meshes, and spheres' proxies */
    if (def->shape != CLOTH_OBSTACLE_MESH) c->analytic_count++;
    if (index) *index = c->obstacle_count;
    c->obstacle_count++;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_contact_move_obstacle(cloth_contact *c, int32_t obstacle, const cloth_pose *start,
                                                   const cloth_pose *end)
{
    cloth__contact_obstacle *o;
    CLOTH_ASSERT(c && start && end);
    if (obstacle < 0 || obstacle >= c->obstacle_count || !cloth__contact_pose_finite(start) || !cloth__contact_pose_finite(end))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    o = &c->obstacles[obstacle];
    o->start = *start;
    o->end = *end;
    if (o->vertex_count > 0) { /* a mesh, or a sphere's proxy */
        cloth__contact_pose_mesh(o, start, o->x_start);
        cloth__contact_pose_mesh(o, end, o->x_end);
        o->moved = 1;
    }
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_contact_set_obstacle_vertices(cloth_contact *c, int32_t obstacle, const cloth_real *x_start,
                                                           const cloth_real *x_end)
{
    cloth__contact_obstacle *o;
    int32_t i;
    CLOTH_ASSERT(c && x_start);
    if (obstacle < 0 || obstacle >= c->obstacle_count || c->obstacles[obstacle].def.shape != CLOTH_OBSTACLE_MESH)
        return CLOTH_ERROR_INVALID_ARGUMENT;
    o = &c->obstacles[obstacle];
    if (!x_end) x_end = x_start;
    for (i = 0; i < 3 * o->vertex_count; ++i)
        if (!cloth__is_finite(x_start[i]) || !cloth__is_finite(x_end[i])) return CLOTH_ERROR_NOT_FINITE;
    memcpy(o->x_start, x_start, (size_t)o->vertex_count * 3 * sizeof(cloth_real));
    memcpy(o->x_end, x_end, (size_t)o->vertex_count * 3 * sizeof(cloth_real));
    o->moved = 1;
    return CLOTH_SUCCESS;
}

/* ---- analytic obstacles ------------------------------------------------------------- */

/* Signed distance of local point p to an analytic shape, outward unit normal in n. Each is
   the exact Euclidean signed distance of a convex set, so it is 1-Lipschitz and convex. */
static double cloth__contact_sdf(const cloth_obstacle_def *d, const double *p, double *n)
{
    double r, q[3];
    int k;
    switch (d->shape) {
    case CLOTH_OBSTACLE_SPHERE:
    case CLOTH_OBSTACLE_CAPSULE:
        q[0] = p[0];
        if (d->shape == CLOTH_OBSTACLE_CAPSULE) {
            double L = (double)d->half_length;
            q[0] = p[0] > L ? p[0] - L : (p[0] < -L ? p[0] + L : 0);
        }
        q[1] = p[1];
        q[2] = p[2];
        r = cloth__contact_len(q);
        if (r > 0) { n[0] = q[0] / r; n[1] = q[1] / r; n[2] = q[2] / r; }
        else { n[0] = 0; n[1] = 1; n[2] = 0; }
        return r - (double)d->radius;
    case CLOTH_OBSTACLE_BOX: {
        double o[3], out = 0, best = -HUGE_VAL;
        int kb = 0;
        for (k = 0; k < 3; ++k) {
            q[k] = fabs(p[k]) - (double)d->half_extents[k];
            o[k] = q[k] > 0 ? q[k] : 0;
            out += o[k] * o[k];
            if (q[k] > best) { best = q[k]; kb = k; }
        }
        if (out > 0) {
            out = sqrt(out);
            for (k = 0; k < 3; ++k) n[k] = (p[k] < 0 ? -o[k] : o[k]) / out;
            return out;
        }
        n[0] = n[1] = n[2] = 0;
        n[kb] = p[kb] < 0 ? -1 : 1;
        return best;
    }
    case CLOTH_OBSTACLE_PLANE:
    case CLOTH_OBSTACLE_MESH:
    default:
        n[0] = 0; n[1] = 1; n[2] = 0;
        return p[1];
    }
}

/* The first time t in [0,1] at which p0 + t d enters the layer sdf <= th. f(t) = sdf - th is
   convex, so a Newton step from a point left of the first root stays left of it (the
   tangent lies below f) and the iteration increases monotonically to the root; a
   non-negative slope proves there is none. Capped: the last iterate (before any root). */
static int cloth__contact_entry(const cloth_obstacle_def *d, const double *p0, const double *dp, double th, double *t_out,
                                double *pc, double *n, double *s_out)
{
    double t = 0, p[3], s, f, len = cloth__contact_len(dp), tol = 1e-7 * th + 1e-15;
    int it;
    p[0] = p0[0]; p[1] = p0[1]; p[2] = p0[2];
    s = cloth__contact_sdf(d, p, n);
    f = s - th;
    if (f > tol && f >= len) return 0; /* 1-Lipschitz: cannot reach the layer this step */
    for (it = 0; f > tol && it < CLOTH__CONTACT_NEWTON_STEPS; ++it) {
        double g = cloth__contact_dot(n, dp);
        if (!(g < 0)) return 0;
        t += f / -g;
        if (t > 1) return 0;
        p[0] = p0[0] + t * dp[0]; p[1] = p0[1] + t * dp[1]; p[2] = p0[2] + t * dp[2];
        s = cloth__contact_sdf(d, p, n);
        f = s - th;
    }
    *t_out = t;
    pc[0] = p[0]; pc[1] = p[1]; pc[2] = p[2];
    *s_out = s;
    return 1;
}

static int32_t cloth__contact_find_touch(const cloth_contact *c, int32_t v, int32_t obstacle)
{
    const cloth__contact_touch *t = CLOTH__CONTACT_AT(c->touches, cloth__contact_touch);
    int32_t i = CLOTH__CONTACT_AT(c->touch_head, int32_t)[v];
    for (; i >= 0; i = t[i].next)
        if (t[i].obstacle == obstacle) return i;
    return -1;
}

/* Respond vertex v to analytic obstacle oi. Returns 1 when x1[v] changed, 0 when not, -1 when
   a pinned vertex needs a response, -2 out of memory. */
static int cloth__contact_respond(cloth_contact *c, int32_t v, int32_t oi)
{
    const cloth__contact_obstacle *o = &c->obstacles[oi];
    double x0w[3], x1w[3], p0[3], p1[3], dp[3], t, pc[3], n[3], sc, r[3], rn, rt[3], delta, pf[3], s, nf[3], wpos[3];
    double th = (double)o->def.thickness;
    cloth__contact_touch *tt;
    int32_t ti;
    int k, it, changed = 0;
    cloth_real *x = c->x1 + 3 * (size_t)v;
    cloth__contact_load(c->x0 + 3 * (size_t)v, x0w);
    cloth__contact_load(x, x1w);
    cloth__contact_pose_to_local(&o->start, x0w, p0);
    cloth__contact_pose_to_local(&o->end, x1w, p1);
    for (k = 0; k < 3; ++k) dp[k] = p1[k] - p0[k];
    if (!cloth__contact_entry(&o->def, p0, dp, th, &t, pc, n, &sc)) return 0;
    for (k = 0; k < 3; ++k) r[k] = (1 - t) * dp[k];
    /* Which linearization: the end point's own (closest point of the layer to p1) when p1 is
       in the layer on the side where the vertex entered and the path did not go through the
       body and out again; else the contact point's (a fast vertex, one that tunnelled). */
    {
        double n1[3], s1 = cloth__contact_sdf(&o->def, p1, n1), tb, pb[3], nb[3], sb;
        int through = s1 > 0 && cloth__contact_entry(&o->def, p0, dp, 0, &tb, pb, nb, &sb);
        if (s1 >= th) {
            if (!through) return 0; /* grazed the layer, ends outside it */
            rn = cloth__contact_dot(r, n);
            delta = th - sc - rn;
        } else if (!through && cloth__contact_dot(n1, n) > 0.5) {
            for (k = 0; k < 3; ++k) n[k] = n1[k];
            rn = cloth__contact_dot(r, n);
            delta = th - s1;
        } else {
            rn = cloth__contact_dot(r, n);
            delta = th - sc - rn;
        }
    }
    for (k = 0; k < 3; ++k) rt[k] = r[k] - rn * n[k];
    if (!(delta > 0)) return 0; /* leaving the layer */
    if (c->inverse_mass && c->inverse_mass[v] == 0) return delta > 1e-6 * th + 1e-12 ? -1 : 0;
    ti = cloth__contact_find_touch(c, v, oi);
    /* p1 + delta n - (friction) r_t, written from the contact point so that a vertex that
       sticks stays exactly where it entered: p_c + (r_n + delta) n + keep r_t */
    {
        double keep = 1;
        if (ti < 0) { /* the first response of this vertex to this obstacle in the step: friction */
            double lt = cloth__contact_len(rt), mus = (double)o->def.friction_static, muk = (double)o->def.friction_kinetic;
            if (lt <= mus * delta) keep = 0;
            else keep = 1 - muk * delta / lt;
            if (keep < 0) keep = 0;
        }
        for (k = 0; k < 3; ++k) pf[k] = pc[k] + (rn + delta) * n[k] + (keep != 0 ? keep * rt[k] : 0);
    }
    /* on a curved surface the linearization may leave it a little inside: push out */
    s = cloth__contact_sdf(&o->def, pf, nf);
    for (it = 0; it < 4 && s < th; ++it) {
        for (k = 0; k < 3; ++k) pf[k] += (th - s) * nf[k];
        s = cloth__contact_sdf(&o->def, pf, nf);
    }
    cloth__contact_pose_to_world(&o->end, pf, wpos);
    for (k = 0; k < 3; ++k) {
        cloth_real nv = (cloth_real)wpos[k];
        if (nv != x[k]) changed = 1;
        x[k] = nv;
    }
    if (ti < 0) {
        if (!cloth__contact_grow(c, &c->touches, (size_t)c->touch_count + 1, sizeof(cloth__contact_touch))) return -2;
        ti = c->touch_count++;
        tt = CLOTH__CONTACT_AT(c->touches, cloth__contact_touch) + ti;
        tt->vertex = v;
        tt->obstacle = oi;
        tt->next = CLOTH__CONTACT_AT(c->touch_head, int32_t)[v];
        CLOTH__CONTACT_AT(c->touch_head, int32_t)[v] = ti;
    }
    tt = CLOTH__CONTACT_AT(c->touches, cloth__contact_touch) + ti;
    {
        double nw[3], pl[3], pw[3];
        cloth__contact_rotate(&o->end, nf, nw);
        for (k = 0; k < 3; ++k) pl[k] = pf[k] - (s - th) * nf[k];
        cloth__contact_pose_to_world(&o->end, pl, pw);
        for (k = 0; k < 3; ++k) { tt->normal[k] = (cloth_real)nw[k]; tt->point[k] = (cloth_real)pw[k]; }
    }
    c->stats.obstacle_contacts++;
    return changed;
}

/* Vertex v against every analytic obstacle, sweeping until nothing changes. */
static int cloth__contact_analytic_vertex(cloth_contact *c, int32_t v)
{
    int sweep, any = 0;
    for (sweep = 0; sweep < CLOTH__CONTACT_ANALYTIC_SWEEPS; ++sweep) {
        int changed = 0;
        int32_t oi;
        for (oi = 0; oi < c->obstacle_count; ++oi) {
            int r;
            if (c->obstacles[oi].def.shape == CLOTH_OBSTACLE_MESH) continue;
            r = cloth__contact_respond(c, v, oi);
            if (r < 0) return r;
            if (r > 0) changed = 1;
        }
        if (!changed) break;
        any = 1;
    }
    return any;
}

CLOTH_API cloth_real cloth_contact_obstacle_distance(const cloth_contact *c, int32_t obstacle, const cloth_real p[3],
                                                     cloth_real normal[3])
{
    const cloth__contact_obstacle *o;
    double q[3], n[3], s;
    int k;
    CLOTH_ASSERT(c && p);
    if (obstacle < 0 || obstacle >= c->obstacle_count) return (cloth_real)HUGE_VAL;
    o = &c->obstacles[obstacle];
    if (o->def.shape == CLOTH_OBSTACLE_MESH) {
        int32_t f;
        double best = HUGE_VAL;
        n[0] = 0; n[1] = 1; n[2] = 0;
        for (f = 0; f < o->triangle_count; ++f) {
            cloth_real w[3];
            const int32_t *t = o->tri + 3 * f;
            cloth_real d = cloth_distance_vertex_face(p, o->x_end + 3 * t[0], o->x_end + 3 * t[1], o->x_end + 3 * t[2], w);
            if ((double)d < best) {
                best = (double)d;
                for (k = 0; k < 3; ++k)
                    n[k] = (double)p[k] - ((double)w[0] * o->x_end[3 * t[0] + k] + (double)w[1] * o->x_end[3 * t[1] + k] +
                                           (double)w[2] * o->x_end[3 * t[2] + k]);
            }
        }
        s = cloth__contact_len(n);
        if (s > 0) for (k = 0; k < 3; ++k) n[k] /= s;
        if (normal) for (k = 0; k < 3; ++k) normal[k] = (cloth_real)n[k];
        return (cloth_real)best;
    }
    cloth__contact_load(p, q);
    cloth__contact_pose_to_local(&o->end, q, q);
    s = cloth__contact_sdf(&o->def, q, n);
    if (normal) {
        cloth__contact_rotate(&o->end, n, n);
        for (k = 0; k < 3; ++k) normal[k] = (cloth_real)n[k];
    }
    return (cloth_real)s;
}

/* Whether p lies certainly farther than `beyond` from analytic obstacle `obstacle` (a
   sphere, capsule or box: each lies in the ball of its bounding radius about its pose's
   origin, and its distance is at least the ball's) at the end of the step; 0 when unsure, for
   a plane and for a mesh. A cheap test before cloth_contact_obstacle_distance, with a margin
   far above the rounding of either. */
static int cloth__contact_obstacle_far(const cloth_contact *c, int32_t obstacle, const cloth_real *p, double beyond)
{
    const cloth__contact_obstacle *o = &c->obstacles[obstacle];
    const cloth_obstacle_def *d = &o->def;
    double bound, q[3], r2, reach;
    int k;
    switch (d->shape) {
    case CLOTH_OBSTACLE_SPHERE: bound = (double)d->radius; break;
    case CLOTH_OBSTACLE_CAPSULE: bound = (double)d->half_length + (double)d->radius; break;
    case CLOTH_OBSTACLE_BOX:
        bound = sqrt((double)d->half_extents[0] * d->half_extents[0] + (double)d->half_extents[1] * d->half_extents[1] +
                     (double)d->half_extents[2] * d->half_extents[2]);
        break;
    default: return 0;
    }
    for (k = 0; k < 3; ++k) q[k] = (double)p[k] - (double)o->end.translation[k];
    r2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    reach = (bound + beyond) * (1 + 1e-6) + 1e-9;
    return r2 > reach * reach;
}

/* ---- narrow phase ------------------------------------------------------------------- */

/* The obstacle whose vertex a node past the cloth's vertices is (a mesh obstacle or an
   analytic obstacle's inner proxy). */
static int32_t cloth__contact_node_obstacle(const cloth_contact *c, int32_t node)
{
    int32_t i;
    node -= c->n;
    for (i = 0; i < c->obstacle_count; ++i) {
        const cloth__contact_obstacle *o = &c->obstacles[i];
        if (o->vertex_count > 0 && node < o->node_offset + o->vertex_count) return i;
    }
    CLOTH_ASSERT(0);
    return 0;
}

/* Positions of a node (cloth vertex or mesh obstacle vertex) at the start and end of the step. */
static void cloth__contact_node(const cloth_contact *c, int32_t node, const cloth_real **p0, const cloth_real **p1)
{
    const cloth__contact_obstacle *o;
    if (node < c->n) {
        *p0 = c->x0 + 3 * (size_t)node;
        *p1 = c->x1 + 3 * (size_t)node;
        return;
    }
    o = &c->obstacles[cloth__contact_node_obstacle(c, node)];
    node -= c->n + o->node_offset;
    *p0 = o->x_start + 3 * (size_t)node;
    *p1 = o->x_end + 3 * (size_t)node;
}

static cloth_real cloth__contact_inverse_mass(const cloth_contact *c, int32_t node)
{
    if (node >= c->n) return 0;
    return c->inverse_mass ? c->inverse_mass[node] : (cloth_real)1;
}

/* The weights of a vertex-face (p, f0, f1, f2) or edge-edge (a0, a1, b0, b1) pair's closest
   points on its four nodes (1, -b0, -b1, -b2 or 1 - s, s, -(1 - t), -t), and d = sum_k w_k p_k,
   the vector from the second primitive's closest point to the first's. */
static void cloth__contact_closest_weights(int edge_edge, const cloth_real *const p[4], cloth_real w[4], double d[3])
{
    cloth_real prm[3];
    int j, k;
    if (!edge_edge) {
        cloth_distance_vertex_face(p[0], p[1], p[2], p[3], prm);
        w[0] = 1; w[1] = -prm[0]; w[2] = -prm[1]; w[3] = -prm[2];
    } else {
        cloth_distance_edge_edge(p[0], p[1], p[2], p[3], prm);
        w[0] = 1 - prm[0]; w[1] = prm[0]; w[2] = -(1 - prm[1]); w[3] = -prm[1];
    }
    for (k = 0; k < 3; ++k) {
        d[k] = 0;
        for (j = 0; j < 4; ++j) d[k] += (double)w[j] * (double)p[j][k];
    }
}

/* The row of an impact evaluated at time toi: weights from the closest points, the normal from
   their direction (or the face / edge-pair normal when they nearly coincide), oriented by the
   configuration at t = 0 (by the relative velocity when that is level). */
static void cloth__contact_make_row(const cloth_contact *c, cloth__contact_impact *im, double dp, double toi)
{
    const cloth_real *p0[4], *p1[4], *pt[4];
    cloth_real xt[4][3];
    double b[3], diff[3], nrm[3], len, s0, vr, e1[3], e2[3], lim = 0;
    int j, k;
    for (j = 0; j < 4; ++j) {
        cloth__contact_node(c, im->node[j], &p0[j], &p1[j]);
        for (k = 0; k < 3; ++k) xt[j][k] = (cloth_real)((double)p0[j][k] + toi * ((double)p1[j][k] - (double)p0[j][k]));
        pt[j] = xt[j];
    }
    cloth__contact_closest_weights(im->edge_edge, pt, im->w, diff);
    len = cloth__contact_len(diff);
    for (k = 0; k < 3; ++k) {
        double s = 0;
        for (j = 0; j < 4; ++j) s += fabs((double)xt[j][k]);
        if (s > lim) lim = s;
    }
    if (len > 0.01 * dp && len > 1e-12 * lim) {
        for (k = 0; k < 3; ++k) nrm[k] = diff[k] / len;
    } else {
        /* the face normal (vertex-face) or the edges' cross product (edge-edge), at toi, then at
           the start and the end of the step */
        int tries;
        len = 0;
        for (tries = 0; tries < 3 && !(len > 0); ++tries) {
            double y[4][3];
            for (j = 0; j < 4; ++j)
                for (k = 0; k < 3; ++k)
                    y[j][k] = tries == 0 ? (double)xt[j][k] : tries == 1 ? (double)p0[j][k] : (double)p1[j][k];
            for (k = 0; k < 3; ++k) {
                e1[k] = im->edge_edge ? y[1][k] - y[0][k] : y[2][k] - y[1][k];
                e2[k] = im->edge_edge ? y[3][k] - y[2][k] : y[3][k] - y[1][k];
            }
            cloth__contact_cross(e1, e2, nrm);
            len = cloth__contact_len(nrm);
            if (!(len > 1e-14 * cloth__contact_len(e1) * cloth__contact_len(e2))) len = 0;
        }
        if (len > 0) {
            for (k = 0; k < 3; ++k) nrm[k] /= len;
        } else {
            /* parallel edges or a collapsed face: anything perpendicular to e1 */
            double ax[3] = {0, 0, 0};
            int m = fabs(e1[0]) <= fabs(e1[1]) && fabs(e1[0]) <= fabs(e1[2]) ? 0 : (fabs(e1[1]) <= fabs(e1[2]) ? 1 : 2);
            ax[m] = 1;
            cloth__contact_cross(e1, ax, nrm);
            len = cloth__contact_len(nrm);
            if (len > 0) for (k = 0; k < 3; ++k) nrm[k] /= len;
            else { nrm[0] = 0; nrm[1] = 1; nrm[2] = 0; }
        }
    }
    /* orientation: the first primitive in front at t = 0, else approaching along -n */
    s0 = 0;
    vr = 0;
    for (k = 0; k < 3; ++k) {
        double q0 = 0, q1 = 0;
        for (j = 0; j < 4; ++j) {
            q0 += (double)im->w[j] * (double)p0[j][k];
            q1 += (double)im->w[j] * (double)p1[j][k];
        }
        s0 += nrm[k] * q0;
        vr += nrm[k] * (q1 - q0);
        b[k] = q0;
    }
    if (fabs(s0) > 0.01 * dp ? s0 < 0 : (vr != 0 ? vr > 0 : s0 < 0)) {
        for (k = 0; k < 3; ++k) nrm[k] = -nrm[k];
        s0 = -s0;
    }
    /* Along n the two material points of the row are apart by s0 at t = 0 and by at least the
       thickness at t = 1 once the row holds, hence by min(s0, thickness) all along the
       straight motion. When s0 is below twice the detection separation (the closest points at
       toi were apart sideways, as for nearly parallel edges), that proves too little and the
       pair would be found again: take the direction between the points at t = 0 instead. */
    {
        double l0 = cloth__contact_len(b), d = (double)c->def.detection_ratio * (double)im->thickness;
        if (s0 < 2 * d && l0 > 2 * d)
            for (k = 0; k < 3; ++k) nrm[k] = b[k] / l0;
    }
    for (k = 0; k < 3; ++k) im->normal[k] = (cloth_real)nrm[k];
}

/* How far a row is from holding at x1: sum_k w_k n . x1_k - thickness (negative: violated). */
static double cloth__contact_gap(const cloth_contact *c, const cloth__contact_impact *im)
{
    double g = -(double)im->thickness;
    int j, k;
    for (j = 0; j < 4; ++j) {
        const cloth_real *p0, *p1;
        cloth__contact_node(c, im->node[j], &p0, &p1);
        for (k = 0; k < 3; ++k) g += (double)im->w[j] * (double)im->normal[k] * (double)p1[k];
    }
    return g;
}

/* Whether any cloth node of a primitive pair has to be tested in this round. */
static int cloth__contact_pair_touched(const cloth_contact *c, const int32_t *node)
{
    const int32_t *st = CLOTH__CONTACT_AT(c->touch_stamp, int32_t);
    int j;
    if (c->all_touched) return 1;
    for (j = 0; j < 4; ++j)
        if (node[j] < c->n && st[node[j]] >= c->round) return 1;
    return 0;
}

/* Append an impact of a primitive pair found at time toi (1 for a proximity row) with the
   separation dp it was tested at. Returns 0, or 1 after an error (c->error set). */
static int cloth__contact_add_impact(cloth_contact *c, int edge_edge, const int32_t *node, cloth_real thickness, cloth_real mu_s,
                                     cloth_real mu_k, double toi, double dp, int proximity)
{
    cloth__contact_impact *im;
    int j;
    if (!cloth__contact_grow(c, &c->found, (size_t)c->found_count + 1, sizeof(cloth__contact_impact))) {
        c->error = CLOTH_ERROR_OUT_OF_MEMORY;
        return 1;
    }
    im = CLOTH__CONTACT_AT(c->found, cloth__contact_impact) + c->found_count++;
    memset(im, 0, sizeof *im);
    for (j = 0; j < 4; ++j) im->node[j] = node[j];
    im->edge_edge = edge_edge;
    im->toi = (cloth_real)toi;
    im->thickness = thickness;
    im->mu_s = mu_s;
    im->mu_k = mu_k;
    /* The row from the time of impact; when it already holds at x1 (the time was a
       conservative bound, or the closest points at that time were not the ones that cross),
       rows from the end of the step and from halfway are tried: a row that holds cannot move
       anything. If none is violated the impact is stale: it is not kept as a row, and a round
       that finds only stale impacts goes to the fail-safe. */
    {
        double times[3], tl = 1e-6 * (double)thickness;
        int q;
        times[0] = toi; times[1] = 1; times[2] = 0.5 * (1 + toi);
        for (q = 0; q < 3; ++q) {
            cloth__contact_make_row(c, im, dp, times[q]);
            if (cloth__contact_gap(c, im) < -tl) break;
        }
        if (q == 3) {
            cloth__contact_make_row(c, im, dp, times[0]);
            im->stale = 1;
            c->stats.stale_impacts++;
        }
    }
    if (proximity) c->stats.proximity_impacts++;
    else if (edge_edge) c->stats.edge_edge_impacts++;
    else c->stats.vertex_face_impacts++;
    c->stats.impacts++;
    return 0;
}

/* Record a pair for cloth__contact_detect: an impact at toi (query 0), or a CCD query (query
   1; proximity: a proximity row if the query finds nothing). Returns 0, or 1 after an error
   (c->error set). */
static int cloth__contact_defer(cloth_contact *c, int edge_edge, const int32_t *node, cloth_real thickness, cloth_real mu_s,
                                cloth_real mu_k, double toi, double dp, int query, int proximity)
{
    cloth__contact_pending *e;
    if (!cloth__contact_grow(c, &c->pending, (size_t)c->pending_count + 1, sizeof(cloth__contact_pending))) {
        c->error = CLOTH_ERROR_OUT_OF_MEMORY;
        return 1;
    }
    e = CLOTH__CONTACT_AT(c->pending, cloth__contact_pending) + c->pending_count++;
    memset(e, 0, sizeof *e);
    memcpy(e->node, node, sizeof e->node);
    e->edge_edge = edge_edge;
    e->query = query;
    e->impact = !query;
    e->proximity = proximity;
    c->pending_queries += query;
    e->thickness = thickness;
    e->mu_s = mu_s;
    e->mu_k = mu_k;
    e->toi = toi;
    e->dp = dp;
    return 0;
}

/* The separation per axis beyond which cloth__contact_test neither reports nor guards a pair
   of the given thickness: the reach of its box test, d (1 + 2 tol), or the distance below
   which a pair is close, 1.01 sqrt(3) d (1 + tol), whichever is larger. */
static double cloth__contact_pair_reach(const cloth_contact *c, cloth_real thickness)
{
    double d = (double)c->def.detection_ratio * (double)thickness, tol = (double)c->def.ccd_relative_tolerance;
    double box = d * (1 + 2 * tol), close = 1.01 * CLOTH__CONTACT_SQRT3 * d * (1 + tol);
    return box > close ? box : close;
}

/* Whether two triangles (nodes a[3], b[3]) stay farther apart than reach over the whole step,
   proven on one of nine axes (the coordinate axes and the six face diagonals, e.g. (1, 1, 0)
   / sqrt 2) in a frame that moves with their mean displacement u: node j's path
   x0_j + t (x1_j - x0_j) is, less the common translation t u (which changes no distance), a
   segment from x0_j to x1_j - u, so each triangle's projection stays between those of the
   ends. A cloth that translates as a whole (falling, carried) culls here every pair that the
   traversal's world-frame boxes pass, and the diagonal axes separate the neighbours on a grid
   whose boxes touch at a corner or side. The rounding of the ends and projections is covered
   by a margin of 64 ulps of the largest coordinate. */
static int cloth__contact_triangles_apart(const cloth_contact *c, const int32_t *a, const int32_t *b, double reach)
{
    /* the axes, unnormalized: x, y, z, x + y, x - y, x + z, x - z, y + z, y - z; along a
       diagonal the projections are sqrt 2 times the distances */
    static const double axis[9][3] = { { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 1, 1, 0 }, { 1, -1, 0 },
                                       { 1, 0, 1 }, { 1, 0, -1 }, { 0, 1, 1 }, { 0, 1, -1 } };
    const cloth_real *p0[6], *p1[6];
    double u[3] = { 0, 0, 0 }, e[12][3], scale = 0;
    int j, k;
    for (j = 0; j < 6; ++j) {
        cloth__contact_node(c, j < 3 ? a[j] : b[j - 3], &p0[j], &p1[j]);
        for (k = 0; k < 3; ++k) u[k] += (double)p1[j][k] - (double)p0[j][k];
    }
    for (k = 0; k < 3; ++k) u[k] /= 6;
    for (j = 0; j < 6; ++j)
        for (k = 0; k < 3; ++k) {
            double x0 = (double)p0[j][k], x1 = (double)p1[j][k];
            e[2 * j][k] = x0;
            e[2 * j + 1][k] = x1 - u[k];
            if (fabs(x0) > scale) scale = fabs(x0);
            if (fabs(x1) > scale) scale = fabs(x1);
        }
    reach += 64 * 2.220446049250313e-16 * scale;
    for (k = 0; k < 9; ++k) {
        const double *n = axis[k], r = k < 3 ? reach : 1.4142135623730951 * reach;
        double alo = HUGE_VAL, ahi = -HUGE_VAL, blo = HUGE_VAL, bhi = -HUGE_VAL;
        for (j = 0; j < 6; ++j) {
            double v = n[0] * e[j][0] + n[1] * e[j][1] + n[2] * e[j][2];
            if (v < alo) alo = v;
            if (v > ahi) ahi = v;
        }
        for (j = 6; j < 12; ++j) {
            double v = n[0] * e[j][0] + n[1] * e[j][1] + n[2] * e[j][2];
            if (v < blo) blo = v;
            if (v > bhi) bhi = v;
        }
        if (alo > bhi + r || blo > ahi + r) return 1;
    }
    return 0;
}

/* Test one primitive pair: returns 0, or 1 after an error (c->error set). */
static int cloth__contact_test(cloth_contact *c, int edge_edge, int32_t n0, int32_t n1, int32_t n2, int32_t n3, cloth_real thickness,
                               cloth_real mu_s, cloth_real mu_k)
{
    const cloth_real *p0[4], *p1[4];
    int32_t node[4];
    double d = (double)c->def.detection_ratio * (double)thickness, tol = (double)c->def.ccd_relative_tolerance, dp, dist0,
           dist1, margin;
    int j, k, first = edge_edge ? 2 : 1, close;
    node[0] = n0; node[1] = n1; node[2] = n2; node[3] = n3;
    if (!cloth__contact_pair_touched(c, node)) return 0;
    for (j = 0; j < 4; ++j) cloth__contact_node(c, node[j], &p0[j], &p1[j]);
    /* swept boxes of the two primitives, within d plus the CCD tolerance */
    margin = d * (1 + 2 * tol);
    for (k = 0; k < 3; ++k) {
        double alo = HUGE_VAL, ahi = -HUGE_VAL, blo = HUGE_VAL, bhi = -HUGE_VAL;
        for (j = 0; j < 4; ++j) {
            double u = (double)p0[j][k], w = (double)p1[j][k], lo = u < w ? u : w, hi = u < w ? w : u;
            if (j < first) { if (lo < alo) alo = lo; if (hi > ahi) ahi = hi; }
            else { if (lo < blo) blo = lo; if (hi > bhi) bhi = hi; }
        }
        if (alo > bhi + margin || blo > ahi + margin) return 0;
    }
    dist0 = edge_edge ? (double)cloth_distance_edge_edge(p0[0], p0[1], p0[2], p0[3], NULL)
                      : (double)cloth_distance_vertex_face(p0[0], p0[1], p0[2], p0[3], NULL);
    dist1 = edge_edge ? (double)cloth_distance_edge_edge(p1[0], p1[1], p1[2], p1[3], NULL)
                      : (double)cloth_distance_vertex_face(p1[0], p1[1], p1[2], p1[3], NULL);
    /* The CCD reports a pair within reach = d (1 + tol) per axis, so within sqrt(3) reach in
       distance. A pair that starts inside that band (set down too close, or left near d by an
       earlier step) is guarded at half its starting per-axis bound instead, so that it is not
       found at t = 0; and if it ends closer than it started, it gets a proximity row (made at
       t = 1) that pushes it back to the thickness, so that close pairs cannot creep together
       from step to step under shrinking guards. */
    close = dist0 <= 1.01 * CLOTH__CONTACT_SQRT3 * d * (1 + tol);
    dp = close ? 0.5 * dist0 / (CLOTH__CONTACT_SQRT3 * (1 + tol)) : d;
    if (!(dp >= CLOTH__CONTACT_MIN_SEPARATION)) {
        c->stats.initially_touching++;
        return 0;
    }
    /* A cheap proof of no contact: the distance between the primitives is L-Lipschitz in t,
       L the largest displacement of a vertex of one relative to a vertex of the other (any
       point's relative motion is a convex combination of those), so it stays above
       (D(0) + D(1) - L) / 2 over the step. Resting layers that move together pass here. */
    {
        double L = 0, slack, toi;
        int a, b;
        for (a = 0; a < first; ++a)
            for (b = first; b < 4; ++b) {
                double q = 0;
                for (k = 0; k < 3; ++k) {
                    double e = ((double)p1[a][k] - (double)p0[a][k]) - ((double)p1[b][k] - (double)p0[b][k]);
                    q += e * e;
                }
                if (q > L) L = q;
            }
        L = sqrt(L);
        /* rounding of the distances is far below the slack */
        slack = CLOTH__CONTACT_SQRT3 * dp * (1 + 2 * tol) + 1e-12 * (1 + dist0 + dist1 + L);
        if (0.5 * (dist0 + dist1 - L) > slack) {
            c->stats.ccd_culled++;
            if (close && dist1 < dist0) return cloth__contact_defer(c, edge_edge, node, thickness, mu_s, mu_k, 1, dp, 0, 1);
            return 0;
        }
        /* A certain contact: the pair ends within dp, which the CCD reports whatever the path
           (within dp in distance is within dp on every axis). Its time needs no search either:
           the distance falls by at most L over the step, so the pair comes within the CCD's
           reach (below slack in distance) no earlier than (D(0) - slack) / L, a lower bound
           like the CCD's own. Taken only for slow pairs (L at most the thickness), whose
           geometry hardly changes over the step, so that the time matters little to the row:
           pairs of resting layers pressed together, found every step. */
        if (dist1 <= dp && L <= (double)thickness) {
            toi = L > 0 ? (dist0 - slack) / L * (1 - 1e-9) : 0;
            toi = toi > 0 ? (toi < 1 ? toi : 1) : 0;
            c->stats.ccd_certain++;
            return cloth__contact_defer(c, edge_edge, node, thickness, mu_s, mu_k, toi, dp, 0, 0);
        }
    }
    return cloth__contact_defer(c, edge_edge, node, thickness, mu_s, mu_k, 1, dp, 1, close && dist1 < dist0);
}

/* The CCD queries of this round's records, part `part` of c->pending_parts: the records
   part, part + parts, ... (interleaved, because the enumeration meets the costly queries in
   spatial clusters); each query reads the positions and writes its own record only. */
static void cloth__contact_query_task(void *context, int32_t part)
{
    cloth_contact *c = (cloth_contact *)context;
    cloth__contact_pending *all = CLOTH__CONTACT_AT(c->pending, cloth__contact_pending);
    const int32_t count = c->pending_count, parts = c->pending_parts;
    const double tol = (double)c->def.ccd_relative_tolerance;
    int32_t i;
    for (i = part; i < count; i += parts) {
        cloth__contact_pending *e = all + i;
        const cloth_real *p0[4], *p1[4];
        cloth_ccd_options opt;
        cloth_ccd_report rep;
        int j;
        if (!e->query) continue;
        for (j = 0; j < 4; ++j) cloth__contact_node(c, e->node[j], &p0[j], &p1[j]);
        opt = cloth_ccd_default_options();
        opt.minimum_separation = (cloth_real)e->dp;
        opt.tolerance = (cloth_real)(tol * e->dp);
        opt.max_checks = c->def.ccd_max_checks;
        opt.refine_checks = c->def.ccd_refine_checks;
        /* on an error the report says may_collide at toi 0, which is safe */
        if (e->edge_edge) (void)cloth_ccd_edge_edge(p0[0], p0[1], p0[2], p0[3], p1[0], p1[1], p1[2], p1[3], &opt, &rep);
        else (void)cloth_ccd_vertex_face(p0[0], p0[1], p0[2], p0[3], p1[0], p1[1], p1[2], p1[3], &opt, &rep);
        e->budget_exhausted = rep.budget_exhausted != 0;
        e->checks = rep.checks;
        if (rep.may_collide) {
            e->toi = (double)rep.toi;
            e->proximity = 0;
        } else {
            e->toi = 1;
        }
        e->impact = rep.may_collide || e->proximity;
    }
}

/* This round's records: the queries (on the pool), then the impacts in enumeration order.
   Returns 0, or 1 after an error (c->error set). */
static int cloth__contact_finish_pending(cloth_contact *c)
{
    const cloth__contact_pending *all = CLOTH__CONTACT_AT(c->pending, cloth__contact_pending);
    int32_t i;
    if (c->pending_queries > 0) {
        /* about 32 records a part, at most 256 parts: the answers do not depend on the split */
        c->pending_parts = c->pending_count / 32 < 1 ? 1 : (c->pending_count / 32 > 256 ? 256 : c->pending_count / 32);
        cloth__pool_run(c->pool, c->pending_parts, cloth__contact_query_task, c);
    }
    for (i = 0; i < c->pending_count; ++i) {
        const cloth__contact_pending *e = all + i;
        if (e->query) {
            c->stats.ccd_queries++;
            c->stats.ccd_checks += e->checks;
            if (e->budget_exhausted) c->stats.ccd_budget_exhausted++;
        }
        if (e->impact &&
            cloth__contact_add_impact(c, e->edge_edge, e->node, e->thickness, e->mu_s, e->mu_k, e->toi, e->dp, e->proximity))
            return 1;
    }
    return 0;
}

/* ---- candidates ---------------------------------------------------------------------- */
/* Each primitive pair is tested once per round. A vertex-face pair (v, B) belongs to the first
   triangle around v that shares no vertex with B: the BVH reports that triangle with B
   whenever v can reach B (every triangle around v holds v's swept path in its box). When
   every triangle around v shares a vertex with B (which the BVH skips as adjacent), it
   belongs to the pair (first triangle around v, B) of the enumeration of adjacent triangles.
   An edge-edge pair belongs likewise to the first pair of non-adjacent faces of its two edges
   (the lower edge index first), or, if all are adjacent, to their first faces. */

static int cloth__contact_adjacent(const cloth_contact *c, int32_t a, int32_t b)
{
    const int32_t *ta = c->tri + 3 * (size_t)a, *tb = c->tri + 3 * (size_t)b;
    int i, j;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j)
            if (ta[i] == tb[j]) return 1;
    return 0;
}

static int cloth__contact_has(const int32_t *t, int32_t v) { return t[0] == v || t[1] == v || t[2] == v; }

static int cloth__contact_pair_enabled(const cloth_contact *c, int32_t a, int32_t b)
{
    return c->piece[a] == c->piece[b] ? c->def.self_collision : c->def.piece_collision;
}

/* The owner of the vertex-face pair (v, b): the first triangle around v that makes an enabled
   pair with b and shares no vertex with it; when there is none (all share one), -2 - the
   first triangle around v that makes an enabled pair with b (the adjacent enumeration's
   owner); -1 when no triangle around v makes an enabled pair with b. */
static int32_t cloth__contact_vf_owner(const cloth_contact *c, int32_t v, int32_t b)
{
    const cloth_topology *t = &c->topology;
    int32_t i, first = -1;
    for (i = t->vertex_face_start[v]; i < t->vertex_face_start[v + 1]; ++i) {
        int32_t f = t->vertex_face[i];
        if (!cloth__contact_pair_enabled(c, f, b)) continue;
        if (!cloth__contact_adjacent(c, f, b)) return f;
        if (first < 0) first = f;
    }
    return first < 0 ? -1 : -2 - first;
}

/* Whether the unordered triangle pair {a, b} owns the edge pair (e, f): the first enabled pair
   of their faces (lower edge index first) that shares no vertex, or, when every enabled pair
   shares one, the first enabled pair (in the enumeration of adjacent triangles). */
static int cloth__contact_ee_owner(const cloth_contact *c, int32_t e, int32_t f, int32_t a, int32_t b, int adjacent)
{
    const int32_t *ef = c->topology.edge_face;
    int32_t lo = e < f ? e : f, hi = e < f ? f : e, fp = -1, fq = -1;
    int i, j;
    for (i = 0; i < 2; ++i)
        for (j = 0; j < 2; ++j) {
            int32_t p = ef[2 * lo + i], q = ef[2 * hi + j];
            if (p < 0 || q < 0 || p == q || !cloth__contact_pair_enabled(c, p, q)) continue;
            if (cloth__contact_adjacent(c, p, q)) {
                if (fp < 0) { fp = p; fq = q; }
                continue;
            }
            return !adjacent && ((p == a && q == b) || (p == b && q == a));
        }
    if (!adjacent || fp < 0) return 0;
    return (fp == a && fq == b) || (fp == b && fq == a);
}

/* The primitive pairs of cloth triangles a and b (non-adjacent from the BVH, or adjacent) that
   the triangle pair owns, as bits: vertex-face pairs at bit 3 side + i (vertex i of a against
   face b on side 0, of b against a on side 1), edge-edge pairs at bit 6 + 3 i + j (edge i of a
   against edge j of b). */
#define CLOTH__CONTACT_EDGE_BIT 6
static int32_t cloth__contact_owned(const cloth_contact *c, int32_t a, int32_t b, int adjacent)
{
    const int32_t *ta = c->tri + 3 * (size_t)a, *tb = c->tri + 3 * (size_t)b;
    const cloth_topology *t = &c->topology;
    int32_t owned = 0;
    int i, j, side;
    for (side = 0; side < 2; ++side) {
        const int32_t *tv = side ? tb : ta, *tf = side ? ta : tb;
        int32_t self = side ? b : a, face = side ? a : b;
        for (i = 0; i < 3; ++i) {
            int32_t v = tv[i], owner;
            if (cloth__contact_has(tf, v)) continue;
            owner = cloth__contact_vf_owner(c, v, face);
            if (adjacent ? owner == -2 - self : owner == self) owned |= (int32_t)1 << (3 * side + i);
        }
    }
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j) {
            int32_t e = t->face_edge[3 * a + i], f = t->face_edge[3 * b + j];
            int32_t e0 = t->edge_vertex[2 * e], e1 = t->edge_vertex[2 * e + 1];
            int32_t f0 = t->edge_vertex[2 * f], f1 = t->edge_vertex[2 * f + 1];
            if (e0 == f0 || e0 == f1 || e1 == f0 || e1 == f1) continue;
            if (cloth__contact_ee_owner(c, e, f, a, b, adjacent)) owned |= (int32_t)1 << (CLOTH__CONTACT_EDGE_BIT + 3 * i + j);
        }
    return owned;
}

/* Test the primitive pairs of triangles a and b in the set owned (cloth__contact_owned), in
   the order of its bits. */
static int cloth__contact_cloth_pair(cloth_contact *c, int32_t a, int32_t b, int32_t owned)
{
    const int32_t *ta = c->tri + 3 * (size_t)a, *tb = c->tri + 3 * (size_t)b;
    const cloth_topology *t = &c->topology;
    cloth_real th = c->def.thickness, mus = c->def.friction_static, muk = c->def.friction_kinetic;
    int bit;
    for (bit = 0; bit < CLOTH__CONTACT_EDGE_BIT + 9; ++bit) {
        if (!(owned >> bit & 1)) continue;
        if (bit < CLOTH__CONTACT_EDGE_BIT) {
            const int32_t *tv = bit < 3 ? ta : tb, *tf = bit < 3 ? tb : ta;
            if (cloth__contact_test(c, 0, tv[bit % 3], tf[0], tf[1], tf[2], th, mus, muk)) return 1;
        } else {
            int32_t e = t->face_edge[3 * a + (bit - CLOTH__CONTACT_EDGE_BIT) / 3];
            int32_t f = t->face_edge[3 * b + (bit - CLOTH__CONTACT_EDGE_BIT) % 3];
            if (cloth__contact_test(c, 1, t->edge_vertex[2 * e], t->edge_vertex[2 * e + 1], t->edge_vertex[2 * f],
                                    t->edge_vertex[2 * f + 1], th, mus, muk))
                return 1;
        }
    }
    return 0;
}

/* Whether a vertex of cloth triangle a moved or collided in the last round (every one does in
   the first): a triangle pair's primitive pairs are tested only when one of its triangles is
   touched (cloth__contact_pair_touched). */
static int cloth__contact_triangle_touched(const cloth_contact *c, int32_t a)
{
    const int32_t *st = CLOTH__CONTACT_AT(c->touch_stamp, int32_t);
    const int32_t *ta = c->tri + 3 * (size_t)a;
    return c->all_touched || st[ta[0]] >= c->round || st[ta[1]] >= c->round || st[ta[2]] >= c->round;
}

static int cloth__contact_triangles_touched(const cloth_contact *c, int32_t a, int32_t b)
{
    return cloth__contact_triangle_touched(c, a) || cloth__contact_triangle_touched(c, b);
}

/* Later rounds: mark[node] = 1 when a touched triangle lies under the node of the cloth's tree,
   made bottom-up (a node's children come after it). */
static void cloth__contact_mark_nodes(const cloth_contact *c, unsigned char *mark)
{
    const cloth_bvh *t = &c->bvh;
    int32_t i, j;
    for (i = t->node_count - 1; i >= 0; --i) {
        const cloth_bvh_node *nd = t->nodes + i;
        if (nd->count == 0) {
            mark[i] = (unsigned char)(mark[nd->first] | mark[nd->first + 1]);
            continue;
        }
        mark[i] = 0;
        for (j = nd->first; j < nd->first + nd->count && !mark[i]; ++j)
            mark[i] = (unsigned char)cloth__contact_triangle_touched(c, t->item_triangle[j]);
    }
}

/* A candidate pair of the self traversal, counted: 0 when disabled, untouched or culled in
   its moving frame (counted too), else the primitive pairs it owns (cloth__contact_owned).
   Reads c only. */
static int32_t cloth__contact_self_candidate(const cloth_contact *c, int32_t a, int32_t b, int32_t *candidates,
                                             int32_t *culled)
{
    ++*candidates;
    if (!cloth__contact_pair_enabled(c, a, b) || !cloth__contact_triangles_touched(c, a, b)) return 0;
    if (cloth__contact_triangles_apart(c, c->tri + 3 * (size_t)a, c->tri + 3 * (size_t)b,
                                       cloth__contact_pair_reach(c, c->def.thickness))) {
        ++*culled;
        return 0;
    }
    return cloth__contact_owned(c, a, b, 0);
}

static int cloth__contact_on_self_pair(int32_t a, int32_t b, void *user)
{
    cloth_contact *c = (cloth_contact *)user;
    int32_t owned = cloth__contact_self_candidate(c, a, b, &c->stats.candidate_pairs, &c->stats.pairs_culled);
    return owned ? cloth__contact_cloth_pair(c, a, b, owned) : 0;
}

/* A part of the parallel self traversal: the pairs it reports, culled and owned as
   cloth__contact_on_self_pair does, kept in its slice of self_found; reads c only. */
static int cloth__contact_on_self_pair_kept(int32_t a, int32_t b, void *user)
{
    cloth__contact_self_task *t = (cloth__contact_self_task *)user;
    cloth__contact_adjacent_pair *out;
    const int32_t owned = cloth__contact_self_candidate(t->c, a, b, &t->candidates, &t->culled);
    if (!owned) return 0;
    if (t->count == t->capacity) {
        t->overflow = 1;
        return 1;
    }
    out = CLOTH__CONTACT_AT(t->c->self_found, cloth__contact_adjacent_pair) + t->first + t->count++;
    out->a = a;
    out->b = b;
    out->owned = owned;
    return 0;
}

/* Part `part` of the parallel self traversal: the seeds part, part + parts, ... (interleaved:
   the costly seeds come in runs). */
static void cloth__contact_self_task_run(void *context, int32_t part)
{
    cloth_contact *c = (cloth_contact *)context;
    cloth__contact_self_task *tasks = CLOTH__CONTACT_AT(c->self_tasks, cloth__contact_self_task);
    int32_t k;
    for (k = part; k < c->self_count; k += c->self_parts) {
        cloth__contact_self_task *t = tasks + k;
        (void)cloth__bvh_self_pairs_from(&c->bvh, c->self_mark, t->seed_a, t->seed_b, cloth__contact_on_self_pair_kept, t);
    }
}

/* The self traversal's candidates (non-adjacent cloth triangle pairs), tested. With the
   world's threads: the traversal cut into seeds (cloth__bvh_self_seeds, 16 per thread), their
   traversals, culls and ownership on the pool, then the pairs' tests here in the serial
   traversal's order (a part that overflowed its slice runs again here, in its turn): the
   same tests in the same order as one thread. Returns 0, or 1 after an error (c->error). */
static int cloth__contact_self_pairs(cloth_contact *c, const unsigned char *mark)
{
    const int32_t threads = cloth__pool_threads(c->pool), want = 16 * threads;
    int32_t count, k, *seeds;
    int overflow = 0;
    cloth__contact_self_task *tasks;
    if (threads < 2) return cloth__bvh_self_pairs_marked(&c->bvh, mark, cloth__contact_on_self_pair, c);
    if (c->self_capacity < 64) c->self_capacity = 64;
    if (!cloth__contact_grow(c, &c->self_seeds, 12 * (size_t)want, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->self_tasks, 3 * (size_t)want, sizeof(cloth__contact_self_task)) ||
        !cloth__contact_grow(c, &c->self_found, 3 * (size_t)want * (size_t)c->self_capacity, sizeof(cloth__contact_adjacent_pair))) {
        c->error = CLOTH_ERROR_OUT_OF_MEMORY;
        return 1;
    }
    seeds = CLOTH__CONTACT_AT(c->self_seeds, int32_t);
    tasks = CLOTH__CONTACT_AT(c->self_tasks, cloth__contact_self_task);
    count = cloth__bvh_self_seeds(&c->bvh, mark, want, seeds, seeds + 6 * (size_t)want);
    for (k = 0; k < count; ++k) {
        cloth__contact_self_task *t = tasks + k;
        t->seed_a = seeds[2 * k];
        t->seed_b = seeds[2 * k + 1];
        t->first = k * c->self_capacity;
        t->count = t->candidates = t->culled = t->overflow = 0;
        t->capacity = c->self_capacity;
        t->c = c;
    }
    c->self_mark = mark;
    c->self_count = count;
    c->self_parts = threads;
    cloth__pool_run(c->pool, threads, cloth__contact_self_task_run, c);
    for (k = 0; k < count; ++k) {
        const cloth__contact_self_task *t = tasks + k;
        const cloth__contact_adjacent_pair *pair = CLOTH__CONTACT_AT(c->self_found, cloth__contact_adjacent_pair) + t->first;
        int32_t i;
        if (t->overflow) {
            overflow = 1;
            if (cloth__bvh_self_pairs_from(&c->bvh, mark, t->seed_a, t->seed_b, cloth__contact_on_self_pair, c)) return 1;
            continue;
        }
        c->stats.candidate_pairs += t->candidates;
        c->stats.pairs_culled += t->culled;
        for (i = 0; i < t->count; ++i)
            if (cloth__contact_cloth_pair(c, pair[i].a, pair[i].b, pair[i].owned)) return 1;
    }
    /* slices twice as long for the next pass */
    if (overflow && c->self_capacity <= INT32_MAX / 2 / (3 * want)) c->self_capacity *= 2;
    return 0;
}

/* The adjacent pairs that own primitive pairs, each once (at its smallest shared vertex),
   in the order of the vertices and of their triangles; out NULL only counts them. */
static int32_t cloth__contact_list_adjacent(const cloth_contact *c, cloth__contact_adjacent_pair *out)
{
    const cloth_topology *t = &c->topology;
    int32_t u, i, j, count = 0;
    for (u = 0; u < c->n; ++u) {
        int32_t s = t->vertex_face_start[u], e = t->vertex_face_start[u + 1];
        for (i = s; i < e; ++i)
            for (j = i + 1; j < e; ++j) {
                int32_t a = t->vertex_face[i], b = t->vertex_face[j], lowest = INT32_MAX, owned;
                const int32_t *ta = c->tri + 3 * (size_t)a, *tb = c->tri + 3 * (size_t)b;
                int k;
                for (k = 0; k < 3; ++k)
                    if (cloth__contact_has(tb, ta[k]) && ta[k] < lowest) lowest = ta[k];
                if (lowest != u || !cloth__contact_pair_enabled(c, a, b)) continue;
                owned = cloth__contact_owned(c, a, b, 1);
                if (!owned) continue;
                if (out) {
                    out[count].a = a;
                    out[count].b = b;
                    out[count].owned = owned;
                }
                count++;
            }
    }
    return count;
}

/* The adjacent pairs' primitive pairs, those of pairs with a vertex moved since the last
   round (every pair in the first). */
static int cloth__contact_adjacent_pairs(cloth_contact *c)
{
    int32_t p;
    for (p = 0; p < c->adjacent_count; ++p) {
        const cloth__contact_adjacent_pair *q = c->adjacent + p;
        if (!cloth__contact_triangles_touched(c, q->a, q->b)) continue;
        if (cloth__contact_cloth_pair(c, q->a, q->b, q->owned)) return 1;
    }
    return 0;
}

typedef struct cloth__contact_obstacle_visit {
    cloth_contact *c;
    int32_t obstacle;
} cloth__contact_obstacle_visit;

/* Cloth triangle a against triangle b of a mesh obstacle. */
static int cloth__contact_on_obstacle_pair(int32_t a, int32_t b, void *user)
{
    cloth__contact_obstacle_visit *vis = (cloth__contact_obstacle_visit *)user;
    cloth_contact *c = vis->c;
    const cloth__contact_obstacle *o = &c->obstacles[vis->obstacle];
    const cloth_topology *t = &c->topology, *ot = &o->topology;
    const int32_t *ta = c->tri + 3 * (size_t)a, *tb = o->tri + 3 * (size_t)b;
    int32_t base = c->n + o->node_offset;
    cloth_real th = o->def.thickness, mus = o->def.friction_static, muk = o->def.friction_kinetic;
    int i, j;
    c->stats.candidate_pairs++;
    if (!cloth__contact_triangle_touched(c, a)) return 0; /* the obstacle's vertices never are */
    {
        int32_t nb[3];
        nb[0] = base + tb[0];
        nb[1] = base + tb[1];
        nb[2] = base + tb[2];
        if (cloth__contact_triangles_apart(c, ta, nb, cloth__contact_pair_reach(c, th))) {
            c->stats.pairs_culled++;
            return 0;
        }
    }
    for (i = 0; i < 3; ++i) {
        int32_t v = ta[i];
        if (t->vertex_face[t->vertex_face_start[v]] != a) continue;
        if (cloth__contact_test(c, 0, v, base + tb[0], base + tb[1], base + tb[2], th, mus, muk)) return 1;
    }
    for (i = 0; i < 3; ++i) {
        int32_t w = tb[i];
        if (ot->vertex_face[ot->vertex_face_start[w]] != b) continue;
        if (cloth__contact_test(c, 0, base + w, ta[0], ta[1], ta[2], th, mus, muk)) return 1;
    }
    for (i = 0; i < 3; ++i) {
        int32_t e = t->face_edge[3 * a + i];
        if (t->edge_face[2 * e] != a) continue;
        for (j = 0; j < 3; ++j) {
            int32_t f = ot->face_edge[3 * b + j];
            if (ot->edge_face[2 * f] != b) continue;
            if (cloth__contact_test(c, 1, t->edge_vertex[2 * e], t->edge_vertex[2 * e + 1], base + ot->edge_vertex[2 * f],
                                    base + ot->edge_vertex[2 * f + 1], th, mus, muk))
                return 1;
        }
    }
    return 0;
}

/* The BVH thickness: half the largest detection separation grown by the CCD's tolerance, so
   that every pair the CCD could report overlaps. */
static cloth_real cloth__contact_bvh_thickness(const cloth_contact *c)
{
    double d = (double)c->def.thickness;
    int32_t i;
    for (i = 0; i < c->obstacle_count; ++i)
        if (c->obstacles[i].triangle_count > 0 && (double)c->obstacles[i].def.thickness > d)
            d = (double)c->obstacles[i].def.thickness;
    return (cloth_real)(0.5 * (double)c->def.detection_ratio * d * (1 + 2 * (double)c->def.ccd_relative_tolerance));
}

/* One detection pass over every candidate; the impacts go to c->found. */
static cloth_result cloth__contact_detect(cloth_contact *c)
{
    cloth_result r;
    int32_t i;
    double t0 = cloth__contact_now(c), t1;
    int cloth_pairs = c->m > 0 && (c->def.self_collision || c->def.piece_collision);
    c->found_count = 0;
    c->pending_count = c->pending_queries = 0;
    c->error = CLOTH_SUCCESS;
    if (c->m > 0 && (cloth_pairs || c->mesh_count > 0)) {
        cloth_real th = cloth__contact_bvh_thickness(c);
        if (!c->bvh_built) {
            cloth_bvh_def bd = cloth_default_bvh_def();
            bd.thickness = th;
            r = cloth_bvh_build(&c->bvh, c->x0, c->x1, c->n, c->tri, c->m, &bd, &c->allocator);
            if (r != CLOTH_SUCCESS) return r;
            c->bvh_built = 1;
        } else {
            c->bvh.def.thickness = th;
            r = cloth_bvh_refit(&c->bvh, c->x0, c->x1);
            if (r == CLOTH_SUCCESS && cloth_bvh_needs_rebuild(&c->bvh)) r = cloth_bvh_rebuild(&c->bvh, c->x0, c->x1);
            if (r != CLOTH_SUCCESS) return r;
        }
        for (i = 0; i < c->obstacle_count; ++i) {
            cloth__contact_obstacle *o = &c->obstacles[i];
            if (o->triangle_count == 0) continue;
            if (o->moved || o->bvh.def.thickness != th) {
                o->bvh.def.thickness = th;
                r = cloth_bvh_refit(&o->bvh, o->x_start, o->x_end);
                if (r == CLOTH_SUCCESS && cloth_bvh_needs_rebuild(&o->bvh)) r = cloth_bvh_rebuild(&o->bvh, o->x_start, o->x_end);
                if (r != CLOTH_SUCCESS) return r;
                o->moved = 0;
            }
        }
    }
    t1 = cloth__contact_now(c);
    c->stats.time_bvh += t1 - t0;
    /* The traversals call the narrow phase as they go; its time is counted as CCD. */
    if (cloth_pairs) {
        /* a later round: only subtrees with a touched triangle can give pairs to test */
        unsigned char *mark = c->all_touched ? NULL : CLOTH__CONTACT_AT(c->node_mark, unsigned char);
        if (mark) cloth__contact_mark_nodes(c, mark);
        if (cloth__contact_self_pairs(c, mark)) return c->error;
        if (cloth__contact_adjacent_pairs(c)) return c->error;
    }
    for (i = 0; i < c->obstacle_count && c->m > 0; ++i) {
        cloth__contact_obstacle_visit vis;
        if (c->obstacles[i].triangle_count == 0) continue;
        vis.c = c;
        vis.obstacle = i;
        if (cloth_bvh_pairs(&c->bvh, &c->obstacles[i].bvh, cloth__contact_on_obstacle_pair, &vis)) return c->error;
    }
    if (cloth__contact_finish_pending(c)) return c->error;
    c->stats.time_ccd += cloth__contact_now(c) - t1;
    return CLOTH_SUCCESS;
}

/* ---- zones --------------------------------------------------------------------------- */

static int32_t cloth__contact_find(cloth_contact *c, int32_t v)
{
    int32_t *p = CLOTH__CONTACT_AT(c->parent, int32_t);
    while (p[v] != v) {
        p[v] = p[p[v]];
        v = p[v];
    }
    return v;
}

static int32_t cloth__contact_union(cloth_contact *c, int32_t a, int32_t b)
{
    int32_t *p = CLOTH__CONTACT_AT(c->parent, int32_t), *sz = CLOTH__CONTACT_AT(c->zsize, int32_t);
    int32_t *state = CLOTH__CONTACT_AT(c->zstate, int32_t), *flag = CLOTH__CONTACT_AT(c->zflag, int32_t);
    a = cloth__contact_find(c, a);
    b = cloth__contact_find(c, b);
    if (a == b) return a;
    if (sz[a] < sz[b] || (sz[a] == sz[b] && b < a)) { int32_t t = a; a = b; b = t; }
    p[b] = a;
    sz[a] += sz[b];
    if (state[b] > state[a]) state[a] = state[b];
    flag[a] |= flag[b];
    return a;
}

static int cloth__contact_movable(const cloth_contact *c, int32_t node)
{
    return node < c->n && cloth__contact_inverse_mass(c, node) > 0;
}

/* Merge the movable nodes of an impact into one zone; returns the root, or -1 when the impact
   has no movable node. Immovable nodes mark the zone (for the fail-safe). */
static int32_t cloth__contact_merge(cloth_contact *c, const cloth__contact_impact *im)
{
    int32_t root = -1, *flag = CLOTH__CONTACT_AT(c->zflag, int32_t);
    int j, immovable = 0;
    for (j = 0; j < 4; ++j) {
        if (!cloth__contact_movable(c, im->node[j])) { immovable = 1; continue; }
        root = root < 0 ? cloth__contact_find(c, im->node[j]) : cloth__contact_union(c, root, im->node[j]);
    }
    if (root >= 0 && immovable) flag[root] = 1;
    return root;
}

/* The zone of an impact (the root of its first movable node), or -1. */
static int32_t cloth__contact_zone(cloth_contact *c, const cloth__contact_impact *im)
{
    int j;
    for (j = 0; j < 4; ++j)
        if (cloth__contact_movable(c, im->node[j])) return cloth__contact_find(c, im->node[j]);
    return -1;
}

/* Stable merge sort of idx[0..count) by key[idx] (ties keep their order). */
static void cloth__contact_sort(int32_t *idx, int32_t *tmp, const int32_t *key, int32_t count)
{
    int32_t width, i;
    for (width = 1; width < count; width *= 2) {
        for (i = 0; i < count; i += 2 * width) {
            int32_t lo = i, mid = i + width < count ? i + width : count, hi = i + 2 * width < count ? i + 2 * width : count;
            int32_t a = lo, b = mid, k = lo;
            while (a < mid && b < hi) tmp[k++] = key[idx[b]] < key[idx[a]] ? idx[b++] : idx[a++];
            while (a < mid) tmp[k++] = idx[a++];
            while (b < hi) tmp[k++] = idx[b++];
        }
        memcpy(idx, tmp, (size_t)count * sizeof(int32_t));
    }
}

/* The impacts of a round kept as rows: earliest first (ties: the order they were found in),
   stale ones left out, at most def.impacts_per_vertex on any movable vertex (1: impacts that
   share no movable vertex, Harmon's independent impacts). Their indices go to
   order[0 .. *kept). The zmark stamps of a vertex count its kept impacts. */
static cloth_result cloth__contact_keep_independent(cloth_contact *c, int32_t *kept)
{
    const cloth__contact_impact *f = CLOTH__CONTACT_AT(c->found, cloth__contact_impact);
    int32_t *order, *tmp, *mark = CLOTH__CONTACT_AT(c->zmark, int32_t), i, width, count = c->found_count, stamp;
    if (!cloth__contact_grow(c, &c->order, (size_t)count, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->order_tmp, (size_t)count, sizeof(int32_t)))
        return CLOTH_ERROR_OUT_OF_MEMORY;
    order = CLOTH__CONTACT_AT(c->order, int32_t);
    tmp = CLOTH__CONTACT_AT(c->order_tmp, int32_t);
    for (i = 0; i < count; ++i) order[i] = i;
    for (width = 1; width < count; width *= 2) { /* stable merge sort by toi */
        for (i = 0; i < count; i += 2 * width) {
            int32_t lo = i, mid = i + width < count ? i + width : count, hi = i + 2 * width < count ? i + 2 * width : count;
            int32_t a = lo, b = mid, k = lo;
            while (a < mid && b < hi) tmp[k++] = f[order[b]].toi < f[order[a]].toi ? order[b++] : order[a++];
            while (a < mid) tmp[k++] = order[a++];
            while (b < hi) tmp[k++] = order[b++];
        }
        memcpy(order, tmp, (size_t)count * sizeof(int32_t));
    }
    stamp = c->stamp + 1;
    c->stamp += c->def.impacts_per_vertex + 1;
    *kept = 0;
    for (i = 0; i < count; ++i) {
        const cloth__contact_impact *im = &f[order[i]];
        int j, clash = 0;
        if (im->stale) continue;
        for (j = 0; j < 4; ++j)
            if (cloth__contact_movable(c, im->node[j]) && mark[im->node[j]] >= stamp + c->def.impacts_per_vertex - 1) clash = 1;
        if (clash) continue;
        for (j = 0; j < 4; ++j)
            if (cloth__contact_movable(c, im->node[j])) mark[im->node[j]] = mark[im->node[j]] >= stamp ? mark[im->node[j]] + 1 : stamp;
        order[(*kept)++] = order[i];
    }
    return CLOTH_SUCCESS;
}

/* Append impact rows to the step's list. */
static int cloth__contact_append(cloth_contact *c, const cloth__contact_impact *im)
{
    if (!cloth__contact_grow(c, &c->impacts, (size_t)c->impact_count + 1, sizeof(cloth__contact_impact))) return 0;
    CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact)[c->impact_count++] = *im;
    return 1;
}

/* Project the zones named in key[] (key[i]: the zone of impact i when it is to be projected
   this round, else -1), each with all its rows. Returns CLOTH_ERROR_COLLISION_UNRESOLVED when a
   zone's QP is infeasible (the zones before it stay projected). */
static cloth_result cloth__contact_project(cloth_contact *c)
{
    cloth__contact_impact *all = CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact);
    int32_t *order, *tmp, *key, *node_local, g, i, count = c->impact_count;
    cloth_result r;
    if (!cloth__contact_grow(c, &c->order, (size_t)count, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->order_tmp, (size_t)count, sizeof(int32_t)))
        return CLOTH_ERROR_OUT_OF_MEMORY;
    order = CLOTH__CONTACT_AT(c->order, int32_t);
    tmp = CLOTH__CONTACT_AT(c->order_tmp, int32_t);
    key = CLOTH__CONTACT_AT(c->key, int32_t);
    node_local = CLOTH__CONTACT_AT(c->node_local, int32_t);
    /* key[i] holds the root of impact i when its zone is projected this round, else -1 */
    {
        int32_t k = 0;
        for (i = 0; i < c->impact_count; ++i)
            if (key[i] >= 0) order[k++] = i;
        count = k;
    }
    cloth__contact_sort(order, tmp, key, count);
    for (g = 0; g < count;) {
        int32_t root = key[order[g]], end = g, nl = 0, nrows = 0, nmov = 0, j;
        double mean = 0;
        cloth_real *qx, *qw, *qz, *lam;
        cloth_qp_row *rows;
        int32_t *lnode, *rimp;
        cloth_qp_problem prob;
        cloth_qp_stats qs;
        while (end < count && key[order[end]] == root) ++end;
        /* locals: the zone's nodes, then one virtual node per analytic touch of a movable node */
        for (i = g; i < end; ++i) {
            const cloth__contact_impact *im = &all[order[i]];
            for (j = 0; j < 4; ++j) {
                int32_t nd = im->node[j];
                if (node_local[nd] >= 0) continue;
                if (!cloth__contact_grow(c, &c->local_node, (size_t)nl + 1, sizeof(int32_t))) {
                    for (j = 0; j < nl; ++j) node_local[CLOTH__CONTACT_AT(c->local_node, int32_t)[j]] = -1;
                    return CLOTH_ERROR_OUT_OF_MEMORY;
                }
                node_local[nd] = nl;
                CLOTH__CONTACT_AT(c->local_node, int32_t)[nl++] = nd;
            }
        }
        lnode = CLOTH__CONTACT_AT(c->local_node, int32_t);
        {
            int32_t real_count = nl, touch_rows = 0;
            const int32_t *head = CLOTH__CONTACT_AT(c->touch_head, int32_t);
            const cloth__contact_touch *tt = CLOTH__CONTACT_AT(c->touches, cloth__contact_touch);
            for (i = 0; i < real_count; ++i)
                if (cloth__contact_movable(c, lnode[i])) {
                    int32_t t;
                    mean += (double)cloth__contact_inverse_mass(c, lnode[i]);
                    ++nmov;
                    for (t = head[lnode[i]]; t >= 0; t = tt[t].next) ++touch_rows;
                }
            nrows = (end - g) + touch_rows;
            if (!cloth__contact_grow(c, &c->local_node, (size_t)nl + (size_t)touch_rows, sizeof(int32_t)) ||
                !cloth__contact_grow(c, &c->qp_x, 3 * ((size_t)nl + (size_t)touch_rows), sizeof(cloth_real)) ||
                !cloth__contact_grow(c, &c->qp_z, 3 * ((size_t)nl + (size_t)touch_rows), sizeof(cloth_real)) ||
                !cloth__contact_grow(c, &c->qp_w, (size_t)nl + (size_t)touch_rows, sizeof(cloth_real)) ||
                !cloth__contact_grow(c, &c->qp_rows, (size_t)nrows, sizeof(cloth_qp_row)) ||
                !cloth__contact_grow(c, &c->qp_row_impact, (size_t)nrows, sizeof(int32_t)) ||
                !cloth__contact_grow(c, &c->qp_lambda, (size_t)nrows, sizeof(cloth_real))) {
                lnode = CLOTH__CONTACT_AT(c->local_node, int32_t);
                for (i = 0; i < real_count; ++i) node_local[lnode[i]] = -1;
                return CLOTH_ERROR_OUT_OF_MEMORY;
            }
            lnode = CLOTH__CONTACT_AT(c->local_node, int32_t);
            qx = CLOTH__CONTACT_AT(c->qp_x, cloth_real);
            qz = CLOTH__CONTACT_AT(c->qp_z, cloth_real);
            qw = CLOTH__CONTACT_AT(c->qp_w, cloth_real);
            rows = CLOTH__CONTACT_AT(c->qp_rows, cloth_qp_row);
            rimp = CLOTH__CONTACT_AT(c->qp_row_impact, int32_t);
            lam = CLOTH__CONTACT_AT(c->qp_lambda, cloth_real);
            mean = nmov > 0 ? mean / nmov : 1;
            for (i = 0; i < real_count; ++i) {
                const cloth_real *p0, *p1;
                cloth__contact_node(c, lnode[i], &p0, &p1);
                for (j = 0; j < 3; ++j) qx[3 * i + j] = p1[j];
                qw[i] = cloth__contact_movable(c, lnode[i]) ? (cloth_real)((double)cloth__contact_inverse_mass(c, lnode[i]) / mean)
                                                          : (cloth_real)0;
            }
            nrows = 0;
            for (i = g; i < end; ++i) {
                const cloth__contact_impact *im = &all[order[i]];
                cloth_qp_row *row = &rows[nrows];
                for (j = 0; j < 4; ++j) {
                    row->vertex[j] = node_local[im->node[j]];
                    row->weight[j] = im->w[j];
                }
                for (j = 0; j < 3; ++j) row->normal[j] = im->normal[j];
                row->thickness = im->thickness;
                rimp[nrows++] = order[i];
            }
            /* a movable node touching an analytic obstacle keeps to the outside of the
               obstacle's tangent plane at the contact: n . (z - point) >= 0 */
            for (i = 0; i < real_count; ++i) {
                int32_t t;
                if (!cloth__contact_movable(c, lnode[i])) continue;
                for (t = head[lnode[i]]; t >= 0; t = tt[t].next) {
                    cloth_qp_row *row = &rows[nrows];
                    lnode[nl] = -1;
                    for (j = 0; j < 3; ++j) qx[3 * nl + j] = tt[t].point[j];
                    qw[nl] = 0;
                    row->vertex[0] = i; row->weight[0] = 1;
                    row->vertex[1] = nl; row->weight[1] = -1;
                    row->vertex[2] = row->vertex[3] = -1;
                    row->weight[2] = row->weight[3] = 0;
                    for (j = 0; j < 3; ++j) row->normal[j] = tt[t].normal[j];
                    row->thickness = 0;
                    rimp[nrows++] = -1;
                    ++nl;
                }
            }
        }
        prob.vertex_count = nl;
        prob.x = qx;
        prob.inverse_weight = qw;
        prob.rows = rows;
        prob.row_count = nrows;
        /* no row states: the resolve uses z and lambda only (cloth_qp_project's states would
           factor the zone's tight rows outside the working set, more work than the solve on
           large zones) */
        r = cloth_qp_project(&c->qp, &prob, NULL, qz, lam, NULL, &qs);
        c->stats.qp_solves++;
        c->stats.qp_iterations += qs.iterations;
        if (r == CLOTH_SUCCESS) {
            for (i = 0; i < nl; ++i) {
                int32_t nd = lnode[i];
                int changed = 0;
                if (nd < 0 || !cloth__contact_movable(c, nd)) continue;
                for (j = 0; j < 3; ++j) {
                    if (c->x1[3 * (size_t)nd + j] != qz[3 * i + j]) changed = 1;
                    c->x1[3 * (size_t)nd + j] = qz[3 * i + j];
                }
                if (changed) {
                    CLOTH__CONTACT_AT(c->touch_stamp, int32_t)[nd] = c->round + 1;
                    CLOTH__CONTACT_AT(c->dirty_stamp, int32_t)[nd] = c->round + 1;
                }
            }
            for (i = 0; i < nrows; ++i)
                if (rimp[i] >= 0) all[rimp[i]].impulse += (cloth_real)((double)lam[i] / (mean * (double)c->h));
        }
        for (i = 0; i < nl; ++i)
            if (lnode[i] >= 0) node_local[lnode[i]] = -1;
        if (r != CLOTH_SUCCESS) return r;
        g = end;
    }
    return CLOTH_SUCCESS;
}

/* One fail-safe round over this round's impacts (all of them): merge them into zones, then
   translate every zone they touch rigidly the first time (by the mass-weighted mean of its
   vertices' proposed displacements x_in - x0), and stop it at x0 the next time, or at once
   when it holds immovable nodes or analytic touches. Returns CLOTH_ERROR_COLLISION_UNRESOLVED
   when an impact has no vertex left that could move. */
static cloth_result cloth__contact_rigid(cloth_contact *c)
{
    const cloth__contact_impact *f = CLOTH__CONTACT_AT(c->found, cloth__contact_impact);
    const cloth_real *xin = CLOTH__CONTACT_AT(c->x_in, cloth_real);
    int32_t *state, *flag, *mark, *slot, *head, i, v, roots = 0, stamp;
    cloth_real *sum;
    if (!cloth__contact_grow(c, &c->zslot, (size_t)c->n + 1, sizeof(int32_t))) return CLOTH_ERROR_OUT_OF_MEMORY;
    state = CLOTH__CONTACT_AT(c->zstate, int32_t);
    flag = CLOTH__CONTACT_AT(c->zflag, int32_t);
    mark = CLOTH__CONTACT_AT(c->zmark, int32_t);
    slot = CLOTH__CONTACT_AT(c->zslot, int32_t);
    head = CLOTH__CONTACT_AT(c->touch_head, int32_t);
    for (i = 0; i < c->found_count; ++i) {
        int j, live = 0;
        for (j = 0; j < 4; ++j)
            if (cloth__contact_movable(c, f[i].node[j]) && state[cloth__contact_find(c, f[i].node[j])] < 2) live = 1;
        if (!live) return CLOTH_ERROR_COLLISION_UNRESOLVED;
        cloth__contact_merge(c, &f[i]);
        if (!cloth__contact_append(c, &f[i])) return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    for (v = 0; v < c->n; ++v)
        if (head[v] >= 0 && cloth__contact_movable(c, v)) flag[cloth__contact_find(c, v)] = 1;
    stamp = ++c->stamp;
    for (i = 0; i < c->found_count; ++i) {
        int32_t z = cloth__contact_zone(c, &f[i]);
        if (z >= 0 && mark[z] != stamp) { mark[z] = stamp; slot[z] = roots++; }
    }
    if (!cloth__contact_grow(c, &c->rigid_sum, 4 * (size_t)roots + 1, sizeof(cloth_real))) return CLOTH_ERROR_OUT_OF_MEMORY;
    sum = CLOTH__CONTACT_AT(c->rigid_sum, cloth_real);
    for (i = 0; i < 4 * roots; ++i) sum[i] = 0;
    for (v = 0; v < c->n; ++v) { /* sums in vertex order: deterministic */
        int32_t z, k;
        double mass;
        if (!cloth__contact_movable(c, v)) continue;
        z = cloth__contact_find(c, v);
        if (mark[z] != stamp) continue;
        mass = 1 / (double)cloth__contact_inverse_mass(c, v);
        for (k = 0; k < 3; ++k) sum[4 * slot[z] + k] += (cloth_real)(mass * ((double)xin[3 * v + k] - (double)c->x0[3 * v + k]));
        sum[4 * slot[z] + 3] += (cloth_real)mass;
    }
    for (v = 0; v < c->n; ++v) {
        int32_t z, k;
        int translate;
        if (!cloth__contact_movable(c, v)) continue;
        z = cloth__contact_find(c, v);
        if (mark[z] != stamp) continue;
        translate = state[z] == 0 && !flag[z];
        for (k = 0; k < 3; ++k) {
            double dx = translate ? (double)sum[4 * slot[z] + k] / (double)sum[4 * slot[z] + 3] : 0;
            c->x1[3 * (size_t)v + k] = (cloth_real)((double)c->x0[3 * (size_t)v + k] + dx);
        }
        CLOTH__CONTACT_AT(c->touch_stamp, int32_t)[v] = c->round + 1;
        CLOTH__CONTACT_AT(c->dirty_stamp, int32_t)[v] = c->round + 1;
    }
    for (i = 0; i < c->found_count; ++i) { /* the states advance once per zone */
        int32_t z = cloth__contact_zone(c, &f[i]);
        if (z < 0 || mark[z] != stamp) continue;
        mark[z] = 0;
        if (state[z] == 0 && !flag[z]) { state[z] = 1; c->stats.rigid_zones++; }
        else { state[z] = 2; c->stats.frozen_zones++; }
    }
    return CLOTH_SUCCESS;
}

/* ---- velocities ---------------------------------------------------------------------- */

static void cloth__contact_velocities(cloth_contact *c, cloth_real *v)
{
    const cloth__contact_touch *tt = CLOTH__CONTACT_AT(c->touches, cloth__contact_touch);
    cloth__contact_impact *all = CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact);
    double h = (double)c->h;
    int32_t i, sweep;
    size_t k;
    for (k = 0; k < 3 * (size_t)c->n; ++k) v[k] = (cloth_real)(((double)c->x1[k] - (double)c->x0[k]) / h);
    /* analytic contacts: no approach relative to the surface, Coulomb friction on what it buys */
    for (i = 0; i < c->touch_count; ++i) {
        const cloth__contact_obstacle *o = &c->obstacles[tt[i].obstacle];
        int32_t vx = tt[i].vertex;
        double x0w[3], x1w[3], p0[3], p1[3], n[3], vr[3], vn, vt[3], lt, dv[3];
        int j;
        if (!cloth__contact_movable(c, vx)) continue;
        cloth__contact_load(c->x0 + 3 * (size_t)vx, x0w);
        cloth__contact_load(c->x1 + 3 * (size_t)vx, x1w);
        cloth__contact_pose_to_local(&o->start, x0w, p0);
        cloth__contact_pose_to_local(&o->end, x1w, p1);
        (void)cloth__contact_sdf(&o->def, p1, n);
        for (j = 0; j < 3; ++j) vr[j] = (p1[j] - p0[j]) / h;
        vn = cloth__contact_dot(vr, n);
        if (!(vn < 0)) continue;
        for (j = 0; j < 3; ++j) { vt[j] = vr[j] - vn * n[j]; dv[j] = -vn * n[j]; }
        lt = cloth__contact_len(vt);
        if (lt <= (double)o->def.friction_static * -vn) {
            for (j = 0; j < 3; ++j) dv[j] -= vt[j];
        } else if (lt > 0) {
            double f = (double)o->def.friction_kinetic * -vn / lt;
            if (f > 1) f = 1;
            for (j = 0; j < 3; ++j) dv[j] -= f * vt[j];
        }
        cloth__contact_rotate(&o->end, dv, dv);
        for (j = 0; j < 3; ++j) v[3 * (size_t)vx + j] = (cloth_real)((double)v[3 * (size_t)vx + j] + dv[j]);
    }
    /* impact rows: projected Gauss-Seidel on the relative velocities */
    for (i = 0; i < c->impact_count; ++i) {
        all[i].vel_normal = 0;
        all[i].vel_friction[0] = all[i].vel_friction[1] = all[i].vel_friction[2] = 0;
        all[i].friction_used = 0;
    }
    for (sweep = 0; sweep < CLOTH__CONTACT_VELOCITY_SWEEPS; ++sweep)
        for (i = 0; i < c->impact_count; ++i) {
            cloth__contact_impact *im = &all[i];
            const cloth_real *p0[4], *p1[4];
            double vel[4][3], u[3], n[3], K = 0, gap = -(double)im->thickness, un, P, Pn, ut[3], F[3], lf, cap;
            int j, q;
            for (q = 0; q < 3; ++q) n[q] = (double)im->normal[q];
            for (j = 0; j < 4; ++j) {
                double im_ = (double)cloth__contact_inverse_mass(c, im->node[j]);
                if (!cloth__contact_movable(c, im->node[j])) im_ = 0;
                cloth__contact_node(c, im->node[j], &p0[j], &p1[j]);
                K += (double)im->w[j] * (double)im->w[j] * im_;
                for (q = 0; q < 3; ++q) gap += (double)im->w[j] * n[q] * (double)p1[j][q];
                for (q = 0; q < 3; ++q)
                    vel[j][q] = im->node[j] < c->n ? (double)v[3 * (size_t)im->node[j] + q]
                                                   : ((double)p1[j][q] - (double)p0[j][q]) / h;
            }
            if (!(K > 0) || gap > 0.1 * (double)im->thickness) continue;
            for (q = 0; q < 3; ++q) {
                u[q] = 0;
                for (j = 0; j < 4; ++j) u[q] += (double)im->w[j] * vel[j][q];
            }
            un = cloth__contact_dot(u, n);
            Pn = (double)im->vel_normal - un / K;
            if (Pn < 0) Pn = 0;
            P = Pn - (double)im->vel_normal;
            im->vel_normal = (cloth_real)Pn;
            for (q = 0; q < 3; ++q) u[q] += K * P * n[q];
            /* friction, capped by mu times the normal impulse of the step */
            cap = (double)im->impulse + Pn;
            for (q = 0; q < 3; ++q) ut[q] = u[q] - cloth__contact_dot(u, n) * n[q];
            for (q = 0; q < 3; ++q) F[q] = (double)im->vel_friction[q] - ut[q] / K;
            lf = cloth__contact_len(F);
            if (lf > (double)im->mu_s * cap) {
                double sc = lf > 0 ? (double)im->mu_k * cap / lf : 0;
                for (q = 0; q < 3; ++q) F[q] *= sc;
            }
            {
                double dF[3];
                for (q = 0; q < 3; ++q) dF[q] = F[q] - (double)im->vel_friction[q];
                if (cloth__contact_len(dF) > 0) im->friction_used = 1;
                for (j = 0; j < 4; ++j) {
                    int32_t nd = im->node[j];
                    double im_;
                    if (!cloth__contact_movable(c, nd)) continue;
                    im_ = (double)cloth__contact_inverse_mass(c, nd) * (double)im->w[j];
                    for (q = 0; q < 3; ++q)
                        v[3 * (size_t)nd + q] = (cloth_real)((double)v[3 * (size_t)nd + q] + im_ * (P * n[q] + dF[q]));
                }
                for (q = 0; q < 3; ++q) im->vel_friction[q] = (cloth_real)F[q];
            }
        }
    for (i = 0; i < c->impact_count; ++i)
        if (all[i].friction_used) c->stats.friction_rows++;
}

/* ---- resolve ------------------------------------------------------------------------- */

CLOTH_API cloth_result cloth_contact_resolve(cloth_contact *c, const cloth_real *x0, cloth_real *x1,
                                            const cloth_real *inverse_mass, cloth_real h, cloth_real *v,
                                            cloth_contact_stats *stats)
{
    size_t n3, i;
    int32_t vtx, nn, rigid = 0, need_ccd, projections = 0;
    cloth_result r = CLOTH_SUCCESS;
    double t_begin, t0;
    CLOTH_ASSERT(c);
    CLOTH_ASSERT((x0 && x1) || c->n == 0);
    t_begin = cloth__contact_now(c);
    memset(&c->stats, 0, sizeof c->stats);
    if (stats) memset(stats, 0, sizeof *stats);
    if (!(h > 0) || !cloth__is_finite(h)) return CLOTH_ERROR_INVALID_ARGUMENT;
    n3 = 3 * (size_t)c->n;
    for (i = 0; i < n3; ++i)
        if (!cloth__is_finite(x0[i]) || !cloth__is_finite(x1[i])) return CLOTH_ERROR_NOT_FINITE;
    if (inverse_mass)
        for (vtx = 0; vtx < c->n; ++vtx) {
            if (!cloth__is_finite(inverse_mass[vtx])) return CLOTH_ERROR_NOT_FINITE;
            if (inverse_mass[vtx] < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
        }
    nn = c->n + c->obstacle_nodes;
    if (!cloth__contact_grow(c, &c->x_in, n3 ? n3 : 1, sizeof(cloth_real)) ||
        !cloth__contact_grow(c, &c->touch_stamp, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->node_mark, 2 * (size_t)c->m + 1, 1) ||
        !cloth__contact_grow(c, &c->dirty_stamp, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->parent, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->zsize, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->zstate, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->zflag, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->zmark, (size_t)c->n + 1, sizeof(int32_t)) ||
        !cloth__contact_grow(c, &c->touch_head, (size_t)c->n + 1, sizeof(int32_t)))
        return CLOTH_ERROR_OUT_OF_MEMORY;
    if (c->node_local.capacity < (size_t)nn + 1) {
        size_t old = c->node_local.capacity;
        if (!cloth__contact_grow(c, &c->node_local, (size_t)nn + 1, sizeof(int32_t))) return CLOTH_ERROR_OUT_OF_MEMORY;
        for (i = old; i < c->node_local.capacity; ++i) CLOTH__CONTACT_AT(c->node_local, int32_t)[i] = -1;
    }
    c->x0 = x0;
    c->x1 = x1;
    c->inverse_mass = inverse_mass;
    c->h = h;
    c->touch_count = 0;
    c->impact_count = 0;
    c->found_count = 0;
    if (n3) memcpy(c->x_in.data, x1, n3 * sizeof(cloth_real));
    for (vtx = 0; vtx < c->n; ++vtx) {
        CLOTH__CONTACT_AT(c->touch_stamp, int32_t)[vtx] = -1;
        CLOTH__CONTACT_AT(c->dirty_stamp, int32_t)[vtx] = -1;
        CLOTH__CONTACT_AT(c->parent, int32_t)[vtx] = vtx;
        CLOTH__CONTACT_AT(c->zsize, int32_t)[vtx] = 1;
        CLOTH__CONTACT_AT(c->zstate, int32_t)[vtx] = 0;
        CLOTH__CONTACT_AT(c->zflag, int32_t)[vtx] = 0;
        CLOTH__CONTACT_AT(c->zmark, int32_t)[vtx] = 0;
        CLOTH__CONTACT_AT(c->touch_head, int32_t)[vtx] = -1;
    }
    c->stamp = 0;
    need_ccd = c->m > 0 && (c->def.self_collision || c->def.piece_collision || c->mesh_count > 0);
    for (c->round = 0;; c->round++) {
        int32_t k, first;
        /* 1. analytic obstacles: every vertex in the first round, then those the zones moved */
        if (c->analytic_count > 0) {
            t0 = cloth__contact_now(c);
            for (vtx = 0; vtx < c->n; ++vtx) {
                int a;
                if (c->round > 0 && CLOTH__CONTACT_AT(c->dirty_stamp, int32_t)[vtx] != c->round) continue;
                a = cloth__contact_analytic_vertex(c, vtx);
                if (a == -2) { r = CLOTH_ERROR_OUT_OF_MEMORY; break; }
                if (a < 0) { r = CLOTH_ERROR_COLLISION_UNRESOLVED; break; }
                if (a > 0) CLOTH__CONTACT_AT(c->touch_stamp, int32_t)[vtx] = c->round;
            }
            c->stats.time_response += cloth__contact_now(c) - t0;
            if (r != CLOTH_SUCCESS) break;
        }
        if (!need_ccd) break;
        /* 2. continuous detection (pairs with a vertex that moved or collided) */
        c->all_touched = c->round == 0;
        r = cloth__contact_detect(c);
        c->stats.rounds++;
        if (r != CLOTH_SUCCESS || c->found_count == 0) break;
        t0 = cloth__contact_now(c);
        {
            const cloth__contact_impact *f = CLOTH__CONTACT_AT(c->found, cloth__contact_impact);
            int32_t *st = CLOTH__CONTACT_AT(c->touch_stamp, int32_t);
            int j;
            for (k = 0; k < c->found_count; ++k)
                for (j = 0; j < 4; ++j)
                    if (f[k].node[j] < c->n) st[f[k].node[j]] = c->round + 1;
        }
        /* 3. impact zones, projected exactly */
        if (!rigid && projections >= c->def.max_rounds) rigid = 1;
        if (!rigid) {
            int32_t kept = 0, *order, *key, *mark, stamp;
            cloth__contact_impact *f, *all;
            ++projections;
            first = c->impact_count;
            r = cloth__contact_keep_independent(c, &kept);
            if (r != CLOTH_SUCCESS) break;
            order = CLOTH__CONTACT_AT(c->order, int32_t);
            f = CLOTH__CONTACT_AT(c->found, cloth__contact_impact);
            for (k = 0; k < kept && r == CLOTH_SUCCESS; ++k) {
                if (cloth__contact_merge(c, &f[order[k]]) < 0) r = CLOTH_ERROR_COLLISION_UNRESOLVED; /* nothing can move */
                else if (!cloth__contact_append(c, &f[order[k]])) r = CLOTH_ERROR_OUT_OF_MEMORY;
            }
            c->stats.impact_rows += kept;
            if (r != CLOTH_SUCCESS) break;
            if (kept == 0) rigid = 1; /* only stale impacts: projection cannot progress */
            if (!cloth__contact_grow(c, &c->key, (size_t)c->impact_count + 1, sizeof(int32_t))) { r = CLOTH_ERROR_OUT_OF_MEMORY; break; }
            key = CLOTH__CONTACT_AT(c->key, int32_t);
            mark = CLOTH__CONTACT_AT(c->zmark, int32_t);
            all = CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact);
            stamp = ++c->stamp;
            for (k = first; k < c->impact_count; ++k) mark[cloth__contact_zone(c, &all[k])] = stamp;
            for (k = 0; k < c->impact_count; ++k) {
                int32_t z = cloth__contact_zone(c, &all[k]);
                key[k] = z >= 0 && mark[z] == stamp ? z : -1;
            }
            r = kept > 0 ? cloth__contact_project(c) : CLOTH_ERROR_COLLISION_UNRESOLVED;
            if (r == CLOTH_SUCCESS) { c->stats.time_response += cloth__contact_now(c) - t0; continue; }
            if (r != CLOTH_ERROR_COLLISION_UNRESOLVED) break;
            /* infeasible: the fail-safe takes this round's impacts */
            c->impact_count = first;
            rigid = 1;
            r = CLOTH_SUCCESS;
        }
        /* 4. fail-safe: rigid impact zones */
        if (c->stats.rigid_rounds >= c->def.max_rigid_rounds) { r = CLOTH_ERROR_COLLISION_UNRESOLVED; break; }
        c->stats.rigid_rounds++;
        r = cloth__contact_rigid(c);
        c->stats.time_response += cloth__contact_now(c) - t0;
        if (r != CLOTH_SUCCESS) break;
    }
    /* every vertex outside every analytic obstacle by its thickness (to rounding) */
    if (r == CLOTH_SUCCESS && c->analytic_count > 0) {
        int32_t oi;
        for (vtx = 0; vtx < c->n && r == CLOTH_SUCCESS; ++vtx)
            for (oi = 0; oi < c->obstacle_count; ++oi) {
                const cloth__contact_obstacle *o = &c->obstacles[oi];
                double p[3], nrm[3], th = (double)o->def.thickness, tol, s;
                if (o->def.shape == CLOTH_OBSTACLE_MESH) continue;
                cloth__contact_load(x1 + 3 * (size_t)vtx, p);
                tol = 1e-6 * th + 64 * (sizeof(cloth_real) == sizeof(float) ? 6e-8 : 1.2e-16) *
                                      (fabs(p[0]) + fabs(p[1]) + fabs(p[2]) + fabs((double)o->end.translation[0]) +
                                       fabs((double)o->end.translation[1]) + fabs((double)o->end.translation[2]) + th);
                cloth__contact_pose_to_local(&o->end, p, p);
                s = cloth__contact_sdf(&o->def, p, nrm);
                if (s < th - tol) { r = CLOTH_ERROR_COLLISION_UNRESOLVED; break; }
            }
    }
    if (r == CLOTH_SUCCESS) {
        /* zones at the end */
        cloth__contact_impact *all = CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact);
        int32_t *mark = CLOTH__CONTACT_AT(c->zmark, int32_t), k, stamp = ++c->stamp;
        for (k = 0; k < c->impact_count; ++k) {
            int32_t z = cloth__contact_zone(c, &all[k]);
            if (z < 0 || mark[z] == stamp) continue;
            mark[z] = stamp;
            c->stats.impact_zones++;
            if (CLOTH__CONTACT_AT(c->zsize, int32_t)[z] > c->stats.largest_zone) c->stats.largest_zone = CLOTH__CONTACT_AT(c->zsize, int32_t)[z];
        }
        if (v) {
            t0 = cloth__contact_now(c);
            cloth__contact_velocities(c, v);
            c->stats.time_response += cloth__contact_now(c) - t0;
        }
    } else if (n3) {
        memcpy(x1, c->x_in.data, n3 * sizeof(cloth_real));
    }
    c->stats.time_total = cloth__contact_now(c) - t_begin;
    if (stats) *stats = c->stats;
    return r;
}


/* ------------------------------------------------------------------------------------- */
/* integrate                                                                             */
/* ------------------------------------------------------------------------------------- */

#define CLOTH__WORLD_COOKIE 0xC107D0E1u
#define CLOTH__PIECE_COOKIE 0xC107B1ECu

CLOTH_API cloth_world_def cloth_default_world_def(void)
{
    cloth_world_def d;
    memset(&d, 0, sizeof d);
    d.cookie = CLOTH__WORLD_COOKIE;
    d.gravity[1] = (cloth_real)-9.81;
    d.integrator = CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    d.substeps = 1;
    d.newton_max_iterations = 20;
    d.newton_tolerance = (cloth_real)1e-5;
    d.cg = cloth_default_pcg_options();
    d.cg.preconditioner = CLOTH_PRECONDITIONER_MULTIGRID;
    d.cg.tolerance = (cloth_real)1e-4;
    d.multigrid = cloth_default_multigrid_options();
    d.air_density = (cloth_real)1.2;
    d.gust_time = (cloth_real)0.5;
    d.seed = 1;
    d.max_speed = 1000;
    d.collision_thickness = (cloth_real)1e-3;
    d.cloth_friction = (cloth_real)0.3;
    d.proximity_stiffness = 100;
    d.obstacle_constraints = 1;
    d.obstacle_iterations = 4;
    d.obstacle_hold_touching_only = 1;
    d.collision_strain_limit = (cloth_real)0.1;
    d.step_strain_limit = (cloth_real)0.25;
    d.max_substep_doublings = 3;
    return d;
}

CLOTH_API cloth_piece_def cloth_default_piece_def(void)
{
    cloth_piece_def d;
    memset(&d, 0, sizeof d);
    d.cookie = CLOTH__PIECE_COOKIE;
    d.material = cloth_default_material();
    d.model = CLOTH_MODEL_MEMBRANE;
    d.bending = 1;
    d.bending_model = CLOTH_BENDING_DIHEDRAL;
    d.wind = 1;
    d.drag_coefficient = 1;
    d.strain_limit = 0;
    d.strain_limit_stiffening = 100;
    return d;
}

/* One piece: a range of the world's vertices and triangles and what it was made with. */
typedef struct cloth__piece {
    int32_t first_vertex, vertex_count;
    int32_t first_triangle, triangle_count;
    cloth_piece_def def;
    int32_t *tri;          /* piece-local triangles, 3 per triangle */
    cloth_real *uv;        /* the pattern, or NULL */
    int32_t edge_count;
    int32_t *edge;         /* piece-local edges, 2 each */
    cloth_real *edge_rest; /* rest lengths */
} cloth__piece;

/* A handle: a pinned vertex whose target follows a trajectory. */
typedef struct cloth__handle { int32_t vertex; cloth_trajectory_fn position; void *user; } cloth__handle;

/* A tie between two weighted points: E = k/2 |sum_a w_a x_{v_a}|^2 over up to 4 vertices
   (v_a = -1 unused): the seams. Attachments keep their vertex in v[0] and their stiffness in k,
   their fixed points apart in attach_point (E = k/2 |x_v0 - point|^2). */
typedef struct cloth__tie { int32_t v[4]; cloth_real w[4]; cloth_real k; } cloth__tie;

/* An obstacle as the world keeps it: the def (with its own copies of mesh arrays), the pose
   now and the pose at the end of the next step, and the mesh's world vertices now and next. */
typedef struct cloth__obstacle {
    cloth_obstacle_def def;
    cloth_real *mesh_x, *mesh_now, *mesh_next, *mesh_s0, *mesh_s1; /* s0, s1: a substep's ends */
    int32_t *mesh_tri;
    cloth_pose now, next;
    cloth_pose s0, s1;            /* analytic: the current substep's start and end */
} cloth__obstacle;

/* A growable array of fixed-size records. */
typedef struct cloth__array { void *data; int32_t count, capacity; } cloth__array;

/* A contact spring (def.proximity_stiffness): an impact row of the collide phase between
   cloth and cloth or a mesh obstacle, kept for the following solves. Its separation is
   s = normal . sum_k weight[k] x_(vertex[k]). */
typedef struct cloth__prox_pair {
    int32_t vertex[4];     /* vertex-face: p, f0, f1, f2; edge-edge: a0, a1, b0, b1; the contact
                              module's nodes: cloth vertices, then mesh obstacle vertices */
    cloth_real weight[4];  /* 1, -b0, -b1, -b2 or 1 - s, s, -(1 - t), -t (closest points) */
    cloth_real normal[3];  /* from the second primitive towards the first */
    cloth_real thickness;  /* the separation it holds */
    int32_t edge_edge;
} cloth__prox_pair;

struct cloth_world {
    cloth_world_def def;
    cloth_allocator allocator;
    int stepping;                 /* re-entrancy guard */
    int32_t vertex_count, triangle_count;
    cloth__array pieces;          /* cloth__piece */
    cloth__array handles;         /* cloth__handle */
    cloth__array ties;            /* cloth__tie (seams) */
    cloth__array attachments;     /* cloth__tie with w = 1 and the point in `attach_point` */
    cloth__array attach_point;    /* cloth_real[3] per attachment */
    /* per vertex */
    cloth_real *x, *v, *x_prev, *v_prev, *mass, *drag, *f_ext, *pin_target;
    int32_t *constrained;         /* 0 free, 3 pinned */
    int32_t *tri;                 /* all triangles, world vertex indices */
    int32_t *tri_piece;           /* the piece of each triangle */
    int history_valid;            /* x_prev, v_prev hold the previous step (BDF2) */
    double time;
    int64_t step_count;
    cloth_gust gust;
    /* elements (built lazily before the first step after a structural change) */
    int structure_dirty;
    int32_t spring_count, membrane_count, bend_count;
    int32_t *spring_v;            /* 2 each */
    cloth_real *spring_k, *spring_rest, *spring_beta;
    cloth_real *spring_limit;     /* 0: a spring; > 0: a strain limiter with this limit */
    int32_t limiter_count;        /* springs that are strain limiters */
    int32_t *membrane_v;          /* 3 each */
    cloth_membrane_rest *membrane_rest;
    cloth_membrane_stiffness *membrane_stiffness;
    cloth_real *membrane_beta, *membrane_relative_damping;
    int32_t *bend_v;              /* 4 each */
    cloth_bending_rest *bend_rest;
    cloth_real *bend_k, *bend_beta;
    unsigned char *bend_lumped;   /* 1: the hinge's wing-tip coupling lumped (its piece's def.bending_lumped) */
    int32_t qbend_count;          /* quadratic bending: one stencil per vertex of such pieces */
    int32_t *qbend_start, *qbend_v, *qbend_block_start, *qbend_block; /* entries start[s] .. start[s+1]-1 */
    cloth_real *qbend_w, *qbend_beta; /* 3 weights per entry; beta per stencil */
    unsigned char *qbend_lumped;  /* 1: the stencil's couplings off the pattern lumped (its piece's def.bending_lumped) */
    /* per block of the matrix, the coefficient c of the c I that the quadratic bending's
       Hessians (constant: they depend on the weights alone) put there, lumping included;
       made with the weights, it starts each assembly (NULL without quadratic bending) */
    cloth_real *qbend_diagonal;
    int qbend_pins_dirty;         /* pins changed since the weights were made (they depend on them) */
    cloth_topology *topos;        /* each piece's, from the last build */
    int32_t topo_count;
    int32_t *spring_block, *membrane_block, *bend_block, *tie_block, *attach_block; /* k*k block indices each */
    cloth_block_matrix matrix;
    /* Lumped bending in the preconditioner only (pieces with bending_lumped = 2): the matrix
       the preconditioner is made from, on the pattern without those pieces' couplings that no
       edge carries (it exists when pmatrix_map does); pmatrix_map[k] is the system block of
       its block k; pmatrix_omitted the system blocks (i, j), i < j, it lacks, 3 each (block,
       i, j). */
    cloth_block_matrix pmatrix;
    int32_t *pmatrix_map, *pmatrix_omitted, pmatrix_omitted_count;
    cloth_real *damping_value;    /* the damping matrix on the same pattern */
    cloth_pcg_workspace pcg;
    cloth__pool *pool;            /* def.threads > 1 with CLOTH_THREADS: the step's workers; else NULL */
    struct cloth__elastic_part *elastic_parts; /* with a pool: the assembly's partition (one part per thread) */
    int32_t elastic_part_count;
    int32_t *elastic_list;        /* the parts' element lists */
    cloth_real *elastic_energy;   /* per element energy term, added in order after a parallel assembly */
    size_t elastic_terms;
    int need_damping_matrix, need_wind;
    cloth_contact *contact;       /* the collide phase, when the scene has collisions */
    cloth__array obstacles;       /* cloth__obstacle */
    cloth_real *s_inverse_mass;   /* for the contact module */
    /* contact springs (def.proximity_stiffness, scenes with self, piece or mesh-obstacle collisions) */
    struct cloth__prox_pair *prox, *b_prox; /* the springs, and a copy from before the step */
    int32_t prox_count, b_prox_count, prox_capacity;
    int32_t *prox_slot;           /* open hash of the springs by their vertices: 2 x capacity, -1 empty */
    cloth_real prox_h;            /* h_eff of the solve in progress (k = stiffness m / h^2) */
    int prox_on;                  /* the implicit solve in progress includes them */
    /* obstacle constraints of the solve (def.obstacle_constraints, scenes with analytic obstacles) */
    int analytic_obstacles;       /* how many obstacles are analytic */
    int32_t *s_held;              /* per vertex: the obstacle holding it in this solve, or -1 */
    int32_t *s_switched;          /* per vertex: stick and slip switched in this substep */
    int32_t *b_held;              /* s_held before a step (its releases carry to the next step) */
    cloth_real *s_direction;      /* 6 per vertex: the filter's directions (the layer's normal first) */
    int32_t adapt_level;          /* the substep doublings the last step needed (adaptive steps) */
    int32_t adapt_wait;           /* steps left before the next try one doubling below adapt_level */
    int32_t adapt_failed_tries;   /* failed tries in a row, at most 4 */
    cloth_real *s_plane;          /* per vertex: c of the plane n . x = c a held vertex stays on */
    cloth_real *s_value;          /* 3 per vertex: the filter's prescribed updates */
    cloth_real *s_anchor;         /* 3 per vertex: where a sticking vertex stays */
    cloth_real *s_friction;       /* 3 per vertex: a slipping vertex's kinetic friction, h_eff^2 N */
    cloth_real stable_step;       /* symplectic Euler's estimated limit; re-estimated every 32 substeps */
    int32_t stable_step_age;
    /* scratch, 3 per vertex each */
    cloth_real *s_x0, *s_xhat, *s_xbase, *s_grad, *s_dx, *s_rhs, *s_trial, *s_tmp, *s_phi, *s_wind;
    int32_t *s_fixed;             /* the solver's filter: 3 for pinned or massless vertices */
    /* the state before a step, for restoring it on failure */
    cloth_real *b_x, *b_v, *b_x_prev, *b_v_prev;
};

static double cloth__clock_default(void *user) { (void)user; return (double)clock() / (double)CLOCKS_PER_SEC; }
static double cloth__now(const cloth_world *w) { return w->def.clock ? w->def.clock(w->def.clock_user) : cloth__clock_default(NULL); }

static cloth_result cloth__array_reserve(const cloth_allocator *a, cloth__array *arr, int32_t count, size_t elem)
{
    void *bigger;
    int32_t cap;
    if (count <= arr->capacity) return CLOTH_SUCCESS;
    cap = arr->capacity ? arr->capacity : 8;
    while (cap < count) {
        if (cap > INT32_MAX / 2) return CLOTH_ERROR_SIZE_OVERFLOW;
        cap *= 2;
    }
    bigger = cloth__alloc_array(a, (size_t)cap, elem);
    if (!bigger) return CLOTH_ERROR_OUT_OF_MEMORY;
    if (arr->count) memcpy(bigger, arr->data, (size_t)arr->count * elem);
    cloth__free(a, arr->data);
    arr->data = bigger;
    arr->capacity = cap;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__array_push(const cloth_allocator *a, cloth__array *arr, const void *item, size_t elem)
{
    cloth_result r = cloth__array_reserve(a, arr, arr->count + 1, elem);
    if (r != CLOTH_SUCCESS) return r;
    memcpy((char *)arr->data + (size_t)arr->count * elem, item, elem);
    arr->count++;
    return CLOTH_SUCCESS;
}

#define CLOTH__PIECES(w) ((cloth__piece *)(w)->pieces.data)
#define CLOTH__TIES(w) ((cloth__tie *)(w)->ties.data)
#define CLOTH__ATTACH(w) ((cloth__tie *)(w)->attachments.data)
#define CLOTH__ATTACH_POINT(w) ((cloth_real *)(w)->attach_point.data)
#define CLOTH__HANDLES(w) ((cloth__handle *)(w)->handles.data)
#define CLOTH__OBSTACLES(w) ((cloth__obstacle *)(w)->obstacles.data)

static cloth_result cloth__elastic_parts_build(cloth_world *w);
static void cloth__qbend_diagonal_make(cloth_world *w);

/* Free the element lists, the matrix and the scratch (everything rebuilt before a step). */
static void cloth__world_free_elements(cloth_world *w)
{
    const cloth_allocator *a = &w->allocator;
    cloth__free(a, w->spring_v); cloth__free(a, w->spring_k); cloth__free(a, w->spring_rest); cloth__free(a, w->spring_beta);
    cloth__free(a, w->spring_limit);
    cloth__free(a, w->membrane_v); cloth__free(a, w->membrane_rest); cloth__free(a, w->membrane_stiffness);
    cloth__free(a, w->membrane_beta); cloth__free(a, w->membrane_relative_damping);
    cloth__free(a, w->bend_v); cloth__free(a, w->bend_rest); cloth__free(a, w->bend_k); cloth__free(a, w->bend_beta);
    cloth__free(a, w->bend_lumped);
    cloth__free(a, w->qbend_start); cloth__free(a, w->qbend_v); cloth__free(a, w->qbend_block_start);
    cloth__free(a, w->qbend_block); cloth__free(a, w->qbend_w); cloth__free(a, w->qbend_beta);
    cloth__free(a, w->qbend_lumped); cloth__free(a, w->qbend_diagonal);
    if (w->topos) {
        int32_t p;
        for (p = 0; p < w->topo_count; ++p) cloth_topology_free(w->topos + p);
        cloth__free(a, w->topos);
    }
    w->topos = NULL;
    w->topo_count = 0;
    cloth__free(a, w->spring_block); cloth__free(a, w->membrane_block); cloth__free(a, w->bend_block);
    cloth__free(a, w->tie_block); cloth__free(a, w->attach_block);
    cloth__free(a, w->damping_value);
    cloth__free(a, w->elastic_parts); cloth__free(a, w->elastic_list); cloth__free(a, w->elastic_energy);
    w->elastic_parts = NULL;
    w->elastic_list = NULL;
    w->elastic_energy = NULL;
    w->elastic_part_count = 0;
    w->elastic_terms = 0;
    cloth_block_matrix_free(&w->matrix);
    cloth_block_matrix_free(&w->pmatrix);
    cloth__free(a, w->pmatrix_map); cloth__free(a, w->pmatrix_omitted);
    w->pmatrix_map = w->pmatrix_omitted = NULL;
    w->pmatrix_omitted_count = 0;
    cloth_pcg_workspace_free(&w->pcg);
    cloth_contact_destroy(w->contact);
    w->contact = NULL;
    cloth__free(a, w->s_inverse_mass);
    w->s_inverse_mass = NULL;
    cloth__free(a, w->prox);
    cloth__free(a, w->b_prox);
    cloth__free(a, w->prox_slot);
    w->prox = w->b_prox = NULL;
    w->prox_slot = NULL;
    w->prox_count = w->b_prox_count = w->prox_capacity = 0;
    cloth__free(a, w->s_held);
    cloth__free(a, w->s_switched);
    cloth__free(a, w->b_held);
    w->s_switched = w->b_held = NULL;
    cloth__free(a, w->s_direction);
    cloth__free(a, w->s_plane);
    cloth__free(a, w->s_value);
    cloth__free(a, w->s_anchor);
    cloth__free(a, w->s_friction);
    w->s_plane = w->s_value = w->s_anchor = w->s_friction = NULL;
    w->s_held = NULL;
    w->s_direction = NULL;
    w->analytic_obstacles = 0;
    cloth__free(a, w->s_x0); cloth__free(a, w->s_xhat); cloth__free(a, w->s_xbase); cloth__free(a, w->s_grad);
    cloth__free(a, w->s_dx); cloth__free(a, w->s_rhs); cloth__free(a, w->s_trial); cloth__free(a, w->s_tmp);
    cloth__free(a, w->s_wind); cloth__free(a, w->s_phi); cloth__free(a, w->s_fixed);
    cloth__free(a, w->b_x); cloth__free(a, w->b_v); cloth__free(a, w->b_x_prev); cloth__free(a, w->b_v_prev);
    w->spring_v = w->spring_block = w->membrane_v = w->membrane_block = w->bend_v = w->bend_block = NULL;
    w->tie_block = w->attach_block = NULL;
    w->spring_k = w->spring_rest = w->spring_beta = w->spring_limit = w->membrane_beta = w->membrane_relative_damping = NULL;
    w->membrane_rest = NULL;
    w->membrane_stiffness = NULL;
    w->bend_rest = NULL;
    w->bend_k = w->bend_beta = w->damping_value = NULL;
    w->bend_lumped = NULL;
    w->qbend_start = w->qbend_v = w->qbend_block_start = w->qbend_block = NULL;
    w->qbend_w = w->qbend_beta = NULL;
    w->qbend_lumped = NULL;
    w->qbend_diagonal = NULL;
    w->qbend_count = 0;
    w->qbend_pins_dirty = 0;
    w->s_x0 = w->s_xhat = w->s_xbase = w->s_grad = w->s_dx = w->s_rhs = w->s_trial = w->s_tmp = w->s_wind = w->s_phi = NULL;
    w->s_fixed = NULL;
    w->b_x = w->b_v = w->b_x_prev = w->b_v_prev = NULL;
    w->spring_count = w->membrane_count = w->bend_count = w->limiter_count = 0;
    w->structure_dirty = 1;
}

CLOTH_API cloth_result cloth_world_create(cloth_world **out, const cloth_world_def *def)
{
    cloth_allocator a;
    cloth_world *w;
    cloth_gust_def g;
    cloth_result r;
    int k;
    CLOTH_ASSERT(out && def);
    *out = NULL;
    CLOTH_ASSERT(def->cookie == CLOTH__WORLD_COOKIE); /* make defs with cloth_default_world_def() */
    if (def->substeps < 1 || def->newton_max_iterations < 1 || !(def->newton_tolerance > 0) || !(def->max_speed > 0) ||
        (int)def->integrator < 0 || (int)def->integrator > 3 || !(def->air_density >= 0) || !(def->gust_strength >= 0) ||
        (def->obstacle_constraints != 0 && def->obstacle_constraints != 1) || !(def->collision_strain_limit >= 0) || !(def->step_strain_limit >= 0) ||
        !(def->proximity_stiffness >= 0) || !cloth__is_finite(def->proximity_stiffness) ||
        def->obstacle_iterations < 1 || def->obstacle_iterations > 64 || !(def->obstacle_trial_tolerance >= 0) ||
        !(def->obstacle_trial_tolerance < 1) ||
        (def->obstacle_hold_touching_only != 0 && def->obstacle_hold_touching_only != 1) ||
        !cloth__mg_options_valid(&def->multigrid) ||
        def->max_substep_doublings < 0 || def->max_substep_doublings > 16 || def->threads < 0 ||
        def->threads > CLOTH__MAX_THREADS ||
        (def->tasks.enqueue_task &&
         (!def->tasks.finish_task || def->tasks.worker_count < 1 || def->tasks.worker_count > CLOTH__MAX_THREADS)))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 3; ++k)
        if (!cloth__is_finite(def->gravity[k]) || !cloth__is_finite(def->wind[k])) return CLOTH_ERROR_NOT_FINITE;
    g = cloth_default_gust_def();
    for (k = 0; k < 3; ++k) { g.mean[k] = def->wind[k]; g.deviation[k] = def->gust_strength; }
    if (def->gust_time > 0) g.correlation_time = def->gust_time;
    g.seed = def->seed;
    a = cloth__allocator_or_default(&def->allocator);
    w = (cloth_world *)a.alloc(sizeof *w, a.user);
    if (!w) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(w, 0, sizeof *w);
    w->def = *def;
    w->def.allocator = a;
    w->allocator = a;
    w->structure_dirty = 1;
    r = cloth_gust_init(&w->gust, &g);
    if (r != CLOTH_SUCCESS) { a.free(w, a.user); return r; }
    if (def->tasks.enqueue_task) {
        w->pool = cloth__pool_create_host(&def->tasks, &a);
        if (!w->pool) { a.free(w, a.user); return CLOTH_ERROR_OUT_OF_MEMORY; }
    }
#ifdef CLOTH_THREADS
    else if (def->threads > 1) {
        w->pool = cloth__pool_create(def->threads, &a);
        if (!w->pool) { a.free(w, a.user); return CLOTH_ERROR_OUT_OF_MEMORY; }
    }
#endif
    *out = w;
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_world_destroy(cloth_world *w)
{
    const cloth_allocator *a;
    int32_t p;
    if (!w) return;
    CLOTH_ASSERT(!w->stepping);
    a = &w->allocator;
    cloth__world_free_elements(w);
    for (p = 0; p < w->pieces.count; ++p) {
        cloth__piece *pc = CLOTH__PIECES(w) + p;
        cloth__free(a, pc->tri); cloth__free(a, pc->uv); cloth__free(a, pc->edge); cloth__free(a, pc->edge_rest);
    }
    for (p = 0; p < w->obstacles.count; ++p) {
        cloth__obstacle *ob = CLOTH__OBSTACLES(w) + p;
        cloth__free(a, ob->mesh_x); cloth__free(a, ob->mesh_now); cloth__free(a, ob->mesh_next); cloth__free(a, ob->mesh_tri);
        cloth__free(a, ob->mesh_s0); cloth__free(a, ob->mesh_s1);
    }
    cloth__free(a, w->obstacles.data);
    cloth__free(a, w->pieces.data); cloth__free(a, w->handles.data); cloth__free(a, w->ties.data);
    cloth__free(a, w->attachments.data); cloth__free(a, w->attach_point.data);
    cloth__free(a, w->x); cloth__free(a, w->v); cloth__free(a, w->x_prev); cloth__free(a, w->v_prev);
    cloth__free(a, w->mass); cloth__free(a, w->drag); cloth__free(a, w->f_ext); cloth__free(a, w->pin_target);
    cloth__free(a, w->constrained); cloth__free(a, w->tri); cloth__free(a, w->tri_piece);
    cloth__pool_destroy(w->pool);
    a->free(w, a->user);
}

CLOTH_API const cloth_world_def *cloth_world_get_def(const cloth_world *w) { CLOTH_ASSERT(w); return &w->def; }
CLOTH_API int32_t cloth_world_piece_count(const cloth_world *w) { CLOTH_ASSERT(w); return w->pieces.count; }
CLOTH_API double cloth_world_time(const cloth_world *w) { CLOTH_ASSERT(w); return w->time; }

static const cloth__piece *cloth__piece_get(const cloth_world *w, int32_t piece)
{
    if (piece < 0 || piece >= w->pieces.count) return NULL;
    return CLOTH__PIECES(w) + piece;
}

CLOTH_API int32_t cloth_world_vertex_count(const cloth_world *w, int32_t piece)
{
    const cloth__piece *p;
    CLOTH_ASSERT(w);
    p = cloth__piece_get(w, piece);
    return p ? p->vertex_count : 0;
}

/* Grow a per-vertex (or per-triangle) array of `per` values from old_n to new_n entries, keeping
   the old values and zeroing the new ones. */
static cloth_result cloth__grow_real(const cloth_allocator *a, cloth_real **arr, int32_t old_n, int32_t new_n, int per)
{
    cloth_real *bigger = (cloth_real *)cloth__alloc_array(a, (size_t)new_n * (size_t)per, sizeof(cloth_real));
    if (!bigger) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(bigger, 0, (size_t)new_n * (size_t)per * sizeof(cloth_real));
    if (*arr && old_n) memcpy(bigger, *arr, (size_t)old_n * (size_t)per * sizeof(cloth_real));
    cloth__free(a, *arr);
    *arr = bigger;
    return CLOTH_SUCCESS;
}

static cloth_result cloth__grow_int(const cloth_allocator *a, int32_t **arr, int32_t old_n, int32_t new_n, int per)
{
    int32_t *bigger = (int32_t *)cloth__alloc_array(a, (size_t)new_n * (size_t)per, sizeof(int32_t));
    if (!bigger) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(bigger, 0, (size_t)new_n * (size_t)per * sizeof(int32_t));
    if (*arr && old_n) memcpy(bigger, *arr, (size_t)old_n * (size_t)per * sizeof(int32_t));
    cloth__free(a, *arr);
    *arr = bigger;
    return CLOTH_SUCCESS;
}

/* A triangle's rest area: from uv, or from the positions when the piece has no pattern. */
static cloth_real cloth__rest_area(const cloth__piece *p, const int32_t *local_tri, const cloth_real *rest_x)
{
    if (p->uv) {
        const cloth_real *a = p->uv + 2 * local_tri[0], *b = p->uv + 2 * local_tri[1], *c = p->uv + 2 * local_tri[2];
        cloth_real cr = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        return (cr < 0 ? -cr : cr) / 2;
    } else {
        cloth_real e0[3], e1[3], n[3];
        cloth__v3_sub(rest_x + 3 * local_tri[1], rest_x + 3 * local_tri[0], e0);
        cloth__v3_sub(rest_x + 3 * local_tri[2], rest_x + 3 * local_tri[0], e1);
        cloth__v3_cross(e0, e1, n);
        return cloth__v3_norm(n) / 2;
    }
}

CLOTH_API cloth_result cloth_world_add_piece(cloth_world *w, const cloth_mesh *mesh, const cloth_piece_def *def, int32_t *piece)
{
    const cloth_allocator *a;
    cloth__piece p;
    cloth_topology topo;
    cloth_result r;
    int32_t n, m, i, old_n, old_m;
    CLOTH_ASSERT(w && mesh && def);
    CLOTH_ASSERT(def->cookie == CLOTH__PIECE_COOKIE); /* make defs with cloth_default_piece_def() */
    CLOTH_ASSERT(!w->stepping);
    a = &w->allocator;
    if (piece) *piece = -1;
    r = cloth_material_validate(&def->material);
    if (r != CLOTH_SUCCESS) return r;
    if ((int)def->model < 0 || (int)def->model > 1 || (int)def->bending_model < 0 || (int)def->bending_model > 1 ||
        def->bending_lumped < 0 || def->bending_lumped > 2 ||
        !(def->drag >= 0) || !(def->drag_coefficient >= 0) || !(def->strain_limit >= 0) ||
        !cloth__is_finite(def->strain_limit) || !(def->strain_limit_stiffening > 0) ||
        !cloth__is_finite(def->strain_limit_stiffening))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    r = cloth_mesh_validate(mesh, 0, NULL, a);
    if (r != CLOTH_SUCCESS) return r;
    n = mesh->vertex_count;
    m = mesh->triangle_count;
    if (def->model == CLOTH_MODEL_MASS_SPRING && (def->grid_nx || def->grid_ny) &&
        (def->grid_nx < 2 || def->grid_ny < 2 || (int64_t)def->grid_nx * def->grid_ny != n))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    if ((int64_t)w->vertex_count + n > INT32_MAX / 3 || (int64_t)w->triangle_count + m > INT32_MAX / 3)
        return CLOTH_ERROR_SIZE_OVERFLOW;
    memset(&p, 0, sizeof p);
    p.def = *def;
    p.first_vertex = w->vertex_count;
    p.vertex_count = n;
    p.first_triangle = w->triangle_count;
    p.triangle_count = m;
    r = cloth_topology_build(&topo, mesh, a);
    if (r != CLOTH_SUCCESS) return r;
    p.tri = (int32_t *)cloth__alloc_array(a, (size_t)m, 3 * sizeof(int32_t));
    p.uv = mesh->uv ? (cloth_real *)cloth__alloc_array(a, (size_t)n, 2 * sizeof(cloth_real)) : NULL;
    p.edge = (int32_t *)cloth__alloc_array(a, (size_t)topo.edge_count, 2 * sizeof(int32_t));
    p.edge_rest = (cloth_real *)cloth__alloc_array(a, (size_t)topo.edge_count, sizeof(cloth_real));
    r = CLOTH_SUCCESS;
    if (!p.tri || (mesh->uv && !p.uv) || !p.edge || !p.edge_rest) r = CLOTH_ERROR_OUT_OF_MEMORY;
    if (r == CLOTH_SUCCESS) r = cloth__array_reserve(a, &w->pieces, w->pieces.count + 1, sizeof(cloth__piece));
    /* grow the per-vertex and per-triangle arrays (each keeps its old contents) */
    old_n = w->vertex_count;
    old_m = w->triangle_count;
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->x, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->v, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->x_prev, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->v_prev, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->mass, old_n, old_n + n, 1);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->drag, old_n, old_n + n, 1);
    if (r == CLOTH_SUCCESS) r = cloth__grow_real(a, &w->pin_target, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS && w->f_ext) r = cloth__grow_real(a, &w->f_ext, old_n, old_n + n, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_int(a, &w->constrained, old_n, old_n + n, 1);
    if (r == CLOTH_SUCCESS) r = cloth__grow_int(a, &w->tri, old_m, old_m + m, 3);
    if (r == CLOTH_SUCCESS) r = cloth__grow_int(a, &w->tri_piece, old_m, old_m + m, 1);
    if (r != CLOTH_SUCCESS) {
        /* Arrays that grew keep the old data and zeroed tails; the counts below are unchanged,
           so the world is as it was. */
        cloth__free(a, p.tri); cloth__free(a, p.uv); cloth__free(a, p.edge); cloth__free(a, p.edge_rest);
        cloth_topology_free(&topo);
        return r;
    }
    memcpy(p.tri, mesh->tri, (size_t)m * 3 * sizeof(int32_t));
    if (p.uv) memcpy(p.uv, mesh->uv, (size_t)n * 2 * sizeof(cloth_real));
    memcpy(w->x + 3 * (size_t)old_n, mesh->x, (size_t)n * 3 * sizeof(cloth_real));
    for (i = 0; i < 3 * m; ++i) w->tri[3 * (size_t)old_m + i] = mesh->tri[i] + old_n;
    for (i = 0; i < m; ++i) w->tri_piece[old_m + i] = w->pieces.count;
    /* lumped masses and drag from rest areas */
    for (i = 0; i < m; ++i) {
        cloth_real area = cloth__rest_area(&p, mesh->tri + 3 * i, mesh->x);
        int k;
        for (k = 0; k < 3; ++k) {
            w->mass[old_n + mesh->tri[3 * i + k]] += def->material.areal_density * area / 3;
            w->drag[old_n + mesh->tri[3 * i + k]] += def->drag * area / 3;
        }
    }
    /* edges and their rest lengths, for strain measurement */
    p.edge_count = topo.edge_count;
    for (i = 0; i < topo.edge_count; ++i) {
        int32_t e0 = topo.edge_vertex[2 * i], e1 = topo.edge_vertex[2 * i + 1];
        p.edge[2 * i] = e0;
        p.edge[2 * i + 1] = e1;
        if (p.uv) {
            cloth_real du = p.uv[2 * e0] - p.uv[2 * e1], dv = p.uv[2 * e0 + 1] - p.uv[2 * e1 + 1];
            p.edge_rest[i] = (cloth_real)sqrt((double)(du * du + dv * dv));
        } else {
            cloth_real d[3];
            cloth__v3_sub(mesh->x + 3 * e0, mesh->x + 3 * e1, d);
            p.edge_rest[i] = cloth__v3_norm(d);
        }
    }
    cloth_topology_free(&topo);
    memcpy((cloth__piece *)w->pieces.data + w->pieces.count, &p, sizeof p);
    w->pieces.count++;
    w->vertex_count += n;
    w->triangle_count += m;
    w->history_valid = 0;
    cloth__world_free_elements(w);
    if (piece) *piece = w->pieces.count - 1;
    return CLOTH_SUCCESS;
}

CLOTH_API const cloth_real *cloth_world_positions(const cloth_world *w, int32_t piece)
{
    const cloth__piece *p;
    CLOTH_ASSERT(w);
    p = cloth__piece_get(w, piece);
    return p ? w->x + 3 * (size_t)p->first_vertex : NULL;
}

CLOTH_API const cloth_real *cloth_world_velocities(const cloth_world *w, int32_t piece)
{
    const cloth__piece *p;
    CLOTH_ASSERT(w);
    p = cloth__piece_get(w, piece);
    return p ? w->v + 3 * (size_t)p->first_vertex : NULL;
}

static cloth_result cloth__set_state(cloth_world *w, int32_t piece, const cloth_real *values, cloth_real *dst_all)
{
    const cloth__piece *p;
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    p = cloth__piece_get(w, piece);
    if (!p || !values) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (i = 0; i < 3 * p->vertex_count; ++i)
        if (!cloth__is_finite(values[i])) return CLOTH_ERROR_NOT_FINITE;
    memcpy(dst_all + 3 * (size_t)p->first_vertex, values, (size_t)p->vertex_count * 3 * sizeof(cloth_real));
    w->history_valid = 0;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_set_positions(cloth_world *w, int32_t piece, const cloth_real *x)
{
    return cloth__set_state(w, piece, x, w->x);
}

CLOTH_API cloth_result cloth_world_set_velocities(cloth_world *w, int32_t piece, const cloth_real *v)
{
    return cloth__set_state(w, piece, v, w->v);
}

CLOTH_API cloth_mesh cloth_world_mesh(const cloth_world *w, int32_t piece)
{
    cloth_mesh m;
    const cloth__piece *p;
    CLOTH_ASSERT(w);
    memset(&m, 0, sizeof m);
    p = cloth__piece_get(w, piece);
    if (!p) return m;
    m.vertex_count = p->vertex_count;
    m.triangle_count = p->triangle_count;
    m.x = w->x + 3 * (size_t)p->first_vertex;
    m.uv = p->uv;
    m.tri = p->tri;
    m.allocator = w->allocator;
    return m;
}

/* The world index of a piece's vertex, or -1. */
static int32_t cloth__vertex_index(const cloth_world *w, int32_t piece, int32_t vertex)
{
    const cloth__piece *p = cloth__piece_get(w, piece);
    if (!p || vertex < 0 || vertex >= p->vertex_count) return -1;
    return p->first_vertex + vertex;
}

static int cloth__finite3(const cloth_real *p)
{
    return cloth__is_finite(p[0]) && cloth__is_finite(p[1]) && cloth__is_finite(p[2]);
}

CLOTH_API cloth_result cloth_world_pin(cloth_world *w, int32_t piece, int32_t vertex, const cloth_real *target)
{
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    i = cloth__vertex_index(w, piece, vertex);
    if (i < 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (target && !cloth__finite3(target)) return CLOTH_ERROR_NOT_FINITE;
    memcpy(w->pin_target + 3 * (size_t)i, target ? target : w->x + 3 * (size_t)i, 3 * sizeof(cloth_real));
    w->qbend_pins_dirty |= w->constrained[i] == 0;
    w->constrained[i] = 3;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_set_pin_target(cloth_world *w, int32_t piece, int32_t vertex, const cloth_real *target)
{
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    i = cloth__vertex_index(w, piece, vertex);
    if (i < 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (!w->constrained[i] || !target) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!cloth__finite3(target)) return CLOTH_ERROR_NOT_FINITE;
    memcpy(w->pin_target + 3 * (size_t)i, target, 3 * sizeof(cloth_real));
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_unpin(cloth_world *w, int32_t piece, int32_t vertex)
{
    int32_t i, h;
    CLOTH_ASSERT(w && !w->stepping);
    i = cloth__vertex_index(w, piece, vertex);
    if (i < 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    w->qbend_pins_dirty |= w->constrained[i] != 0;
    w->constrained[i] = 0;
    for (h = 0; h < w->handles.count; ++h)
        if (CLOTH__HANDLES(w)[h].vertex == i) {
            CLOTH__HANDLES(w)[h] = CLOTH__HANDLES(w)[w->handles.count - 1];
            w->handles.count--;
            break;
        }
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_set_handle(cloth_world *w, int32_t piece, int32_t vertex, cloth_trajectory_fn position,
                                              void *user)
{
    cloth__handle hd;
    cloth_result r;
    int32_t i, h;
    CLOTH_ASSERT(w && !w->stepping);
    i = cloth__vertex_index(w, piece, vertex);
    if (i < 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (!position) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (h = 0; h < w->handles.count; ++h)
        if (CLOTH__HANDLES(w)[h].vertex == i) {
            CLOTH__HANDLES(w)[h].position = position;
            CLOTH__HANDLES(w)[h].user = user;
            return CLOTH_SUCCESS;
        }
    hd.vertex = i;
    hd.position = position;
    hd.user = user;
    r = cloth__array_push(&w->allocator, &w->handles, &hd, sizeof hd);
    if (r != CLOTH_SUCCESS) return r;
    memcpy(w->pin_target + 3 * (size_t)i, w->x + 3 * (size_t)i, 3 * sizeof(cloth_real));
    w->qbend_pins_dirty |= w->constrained[i] == 0;
    w->constrained[i] = 3;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_attach(cloth_world *w, int32_t piece, int32_t vertex, const cloth_real point[3],
                                          cloth_real stiffness)
{
    cloth__tie t;
    cloth_result r;
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    i = cloth__vertex_index(w, piece, vertex);
    if (i < 0) return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (!point) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (!cloth__finite3(point) || !cloth__is_finite(stiffness)) return CLOTH_ERROR_NOT_FINITE;
    if (!(stiffness > 0)) return CLOTH_ERROR_INVALID_ARGUMENT;
    memset(&t, 0, sizeof t);
    t.v[0] = i; t.v[1] = t.v[2] = t.v[3] = -1;
    t.w[0] = 1;
    t.k = stiffness;
    r = cloth__array_reserve(&w->allocator, &w->attach_point, w->attach_point.count + 1, 3 * sizeof(cloth_real));
    if (r == CLOTH_SUCCESS) r = cloth__array_push(&w->allocator, &w->attachments, &t, sizeof t);
    if (r != CLOTH_SUCCESS) return r;
    r = cloth__array_push(&w->allocator, &w->attach_point, point, 3 * sizeof(cloth_real));
    CLOTH_ASSERT(r == CLOTH_SUCCESS); /* reserved above */
    w->structure_dirty = 1;
    cloth__world_free_elements(w);
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_add_seam(cloth_world *w, int32_t piece_a, const int32_t *a, int32_t piece_b,
                                            const int32_t *b, int32_t count, cloth_real stiffness)
{
    int32_t s, old = w ? w->ties.count : 0;
    cloth_result r;
    CLOTH_ASSERT(w && !w->stepping);
    if (count < 0 || (count > 0 && (!a || !b)) || !(stiffness > 0) || !cloth__is_finite(stiffness)) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (s = 0; s < count; ++s)
        if (cloth__vertex_index(w, piece_a, a[s]) < 0 || cloth__vertex_index(w, piece_b, b[s]) < 0)
            return CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    r = cloth__array_reserve(&w->allocator, &w->ties, old + count, sizeof(cloth__tie));
    if (r != CLOTH_SUCCESS) return r;
    for (s = 0; s < count; ++s) {
        cloth__tie t;
        memset(&t, 0, sizeof t);
        t.v[0] = cloth__vertex_index(w, piece_a, a[s]);
        t.v[1] = cloth__vertex_index(w, piece_b, b[s]);
        t.v[2] = t.v[3] = -1;
        t.w[0] = 1;
        t.w[1] = -1;
        t.k = stiffness;
        CLOTH__TIES(w)[w->ties.count++] = t;
    }
    cloth__world_free_elements(w);
    return CLOTH_SUCCESS;
}

/* Arc-length fractions along a polyline of world vertices (rest positions: current x). */
static void cloth__polyline_fractions(const cloth_world *w, const int32_t *idx, int32_t count, cloth_real *frac)
{
    int32_t i;
    cloth_real total = 0;
    frac[0] = 0;
    for (i = 1; i < count; ++i) {
        cloth_real d[3];
        cloth__v3_sub(w->x + 3 * (size_t)idx[i], w->x + 3 * (size_t)idx[i - 1], d);
        total += cloth__v3_norm(d);
        frac[i] = total;
    }
    for (i = 1; i < count; ++i) frac[i] = total > 0 ? frac[i] / total : (cloth_real)i / (cloth_real)(count - 1);
}

CLOTH_API cloth_result cloth_world_add_seam_polyline(cloth_world *w, int32_t piece_a, const int32_t *a, int32_t count_a,
                                                     int32_t piece_b, const int32_t *b, int32_t count_b, cloth_real stiffness)
{
    const cloth_allocator *al;
    int32_t *ia, *ib, s, side;
    cloth_real *fa, *fb;
    cloth_result r = CLOTH_SUCCESS;
    CLOTH_ASSERT(w && !w->stepping);
    al = &w->allocator;
    if (count_a < 2 || count_b < 2 || !a || !b || !(stiffness > 0) || !cloth__is_finite(stiffness)) return CLOTH_ERROR_INVALID_ARGUMENT;
    ia = (int32_t *)cloth__alloc_array(al, (size_t)count_a, sizeof(int32_t));
    ib = (int32_t *)cloth__alloc_array(al, (size_t)count_b, sizeof(int32_t));
    fa = (cloth_real *)cloth__alloc_array(al, (size_t)count_a, sizeof(cloth_real));
    fb = (cloth_real *)cloth__alloc_array(al, (size_t)count_b, sizeof(cloth_real));
    if (!ia || !ib || !fa || !fb) r = CLOTH_ERROR_OUT_OF_MEMORY;
    for (s = 0; r == CLOTH_SUCCESS && s < count_a; ++s)
        if ((ia[s] = cloth__vertex_index(w, piece_a, a[s])) < 0) r = CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    for (s = 0; r == CLOTH_SUCCESS && s < count_b; ++s)
        if ((ib[s] = cloth__vertex_index(w, piece_b, b[s])) < 0) r = CLOTH_ERROR_INDEX_OUT_OF_RANGE;
    if (r == CLOTH_SUCCESS) r = cloth__array_reserve(al, &w->ties, w->ties.count + count_a + count_b, sizeof(cloth__tie));
    if (r == CLOTH_SUCCESS) {
        cloth__polyline_fractions(w, ia, count_a, fa);
        cloth__polyline_fractions(w, ib, count_b, fb);
        /* each vertex of one polyline to the point at the same fraction on the other */
        for (side = 0; side < 2; ++side) {
            const int32_t *from = side ? ib : ia, *onto = side ? ia : ib;
            const cloth_real *ffrom = side ? fb : fa, *fonto = side ? fa : fb;
            int32_t nfrom = side ? count_b : count_a, nonto = side ? count_a : count_b, seg = 0;
            for (s = 0; s < nfrom; ++s) {
                cloth__tie t;
                cloth_real f = ffrom[s], len, u;
                while (seg < nonto - 2 && fonto[seg + 1] < f) ++seg;
                len = fonto[seg + 1] - fonto[seg];
                u = len > 0 ? (f - fonto[seg]) / len : 0;
                if (u < 0) u = 0;
                if (u > 1) u = 1;
                memset(&t, 0, sizeof t);
                t.v[0] = from[s]; t.w[0] = 1;
                t.v[1] = onto[seg]; t.w[1] = -(1 - u);
                t.v[2] = onto[seg + 1]; t.w[2] = -u;
                t.v[3] = -1;
                t.k = stiffness;
                CLOTH__TIES(w)[w->ties.count++] = t;
            }
        }
        cloth__world_free_elements(w);
    }
    cloth__free(al, ia); cloth__free(al, ib); cloth__free(al, fa); cloth__free(al, fb);
    return r;
}

/* sum_a w_a x_{v_a} */
static void cloth__tie_gap(const cloth__tie *t, const cloth_real *x, cloth_real *gap)
{
    int a, k;
    gap[0] = gap[1] = gap[2] = 0;
    for (a = 0; a < 4; ++a)
        if (t->v[a] >= 0)
            for (k = 0; k < 3; ++k) gap[k] += t->w[a] * x[3 * (size_t)t->v[a] + k];
}

CLOTH_API cloth_real cloth_world_seam_sewn_fraction(const cloth_world *w, cloth_real tolerance)
{
    int32_t s, sewn = 0;
    CLOTH_ASSERT(w);
    if (w->ties.count == 0) return 1;
    for (s = 0; s < w->ties.count; ++s) {
        cloth_real gap[3];
        cloth__tie_gap(CLOTH__TIES(w) + s, w->x, gap);
        sewn += cloth__v3_norm(gap) < tolerance;
    }
    return (cloth_real)sewn / (cloth_real)w->ties.count;
}

CLOTH_API cloth_result cloth_world_set_external_forces(cloth_world *w, int32_t piece, const cloth_real *force)
{
    const cloth__piece *p;
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    p = cloth__piece_get(w, piece);
    if (!p) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (force)
        for (i = 0; i < 3 * p->vertex_count; ++i)
            if (!cloth__is_finite(force[i])) return CLOTH_ERROR_NOT_FINITE;
    if (!w->f_ext) {
        if (!force) return CLOTH_SUCCESS;
        w->f_ext = (cloth_real *)cloth__alloc_array(&w->allocator, (size_t)w->vertex_count, 3 * sizeof(cloth_real));
        if (!w->f_ext) return CLOTH_ERROR_OUT_OF_MEMORY;
        memset(w->f_ext, 0, (size_t)w->vertex_count * 3 * sizeof(cloth_real));
    }
    if (force) memcpy(w->f_ext + 3 * (size_t)p->first_vertex, force, (size_t)p->vertex_count * 3 * sizeof(cloth_real));
    else memset(w->f_ext + 3 * (size_t)p->first_vertex, 0, (size_t)p->vertex_count * 3 * sizeof(cloth_real));
    return CLOTH_SUCCESS;
}

/* ---- elements, the matrix pattern and the scratch: built before the first step ---- */

/* The physical parameters a piece's material gives the force kernels. */
typedef struct cloth__piece_params {
    cloth_membrane_stiffness membrane;
    cloth_real bend_warp, bend_weft;   /* N m */
    cloth_real beta;                   /* stiffness-proportional damping, s */
    cloth_real relative_damping;       /* seed 002 relative-velocity damping per triangle, N s/m */
    cloth_real spring_stretch, spring_shear, spring_bend; /* mass-spring stiffnesses, N/m */
} cloth__piece_params;

/* Material to kernel parameters. The membrane takes the material's C11, C12, C22, C33 as they
   are. Mass-spring: structural springs stiffness (C11 + C22)/2, shear springs C33 (in a square
   grid a spring of stiffness k carries a tension k * strain per unit width, matching the
   membrane's to first order); bending springs get B / L^2 per spring (set when springs are
   made, from the rest length L). */
static cloth__piece_params cloth__params_of(const cloth_piece_def *d)
{
    cloth__piece_params p;
    const cloth_material *m = &d->material;
    p.membrane.c11 = m->stretch_warp;
    p.membrane.c22 = m->stretch_weft;
    p.membrane.c12 = m->stretch_coupling;
    p.membrane.c33 = m->shear;
    p.bend_warp = m->bend_warp;
    p.bend_weft = m->bend_weft;
    p.beta = m->damping_stiffness;
    p.relative_damping = m->damping_relative;
    p.spring_stretch = (m->stretch_warp + m->stretch_weft) / 2;
    p.spring_shear = m->shear;
    p.spring_bend = (m->bend_warp + m->bend_weft) / 2; /* divided by L^2 per spring */
    return p;
}

/* Whether a piece bends by the quadratic energy: a membrane piece with bending, the quadratic
   model and a flat pattern (without uv the rest shape may be curved: the dihedral energy). */
static int cloth__piece_quadratic_bending(const cloth__piece *pc)
{
    return pc->def.bending && pc->def.model == CLOTH_MODEL_MEMBRANE && pc->def.bending_model == CLOTH_BENDING_QUADRATIC &&
           pc->uv != NULL;
}

/* Cache the block index of every vertex pair (a, b) of an element of k vertices (k*k entries;
   -1 for an unused vertex). */
static void cloth__element_blocks(const cloth_block_matrix *m, const int32_t *v, int k, int32_t *blocks)
{
    int a, b;
    for (a = 0; a < k; ++a)
        for (b = 0; b < k; ++b)
            blocks[a * k + b] = (v[a] >= 0 && v[b] >= 0) ? cloth_block_matrix_find(m, v[a], v[b]) : -1;
}

/* Piece p's quadratic bending stencils (one per vertex) from stencil q on, with its pins as
   they are now: offsets made global, vertices made world indices; capacity counts entries. */
static cloth_result cloth__piece_quadratic_stencils(cloth_world *w, int32_t p, const cloth_topology *topo, int32_t q,
                                                    int32_t capacity)
{
    const cloth__piece *pc = CLOTH__PIECES(w) + p;
    cloth__piece_params pp = cloth__params_of(&pc->def);
    cloth_mesh view = cloth_world_mesh(w, p);
    int32_t base = w->qbend_start[q], count = 0, i, *st = w->qbend_start + q, off = pc->first_vertex;
    cloth_result r = cloth_quadratic_bending_stencils(&view, topo, pp.bend_warp, pp.bend_weft, w->constrained + off, st,
                                                      w->qbend_v + base, w->qbend_w + 3 * (size_t)base, NULL, capacity - base,
                                                      &count);
    if (r != CLOTH_SUCCESS) return r;
    for (i = 0; i <= pc->vertex_count; ++i) st[i] += base;
    for (i = 0; i < count; ++i) w->qbend_v[base + i] += off;
    return CLOTH_SUCCESS;
}

/* The strain limiters of a piece (cloth_piece_def's strain_limit), one per edge, appended to
   the springs: the piece's edges and rest lengths (those the strain is measured on; the
   topology's edges, in its order), stiffness k_e = Y A_e / L_e^2 with
   Y = strain_limit_stiffening * max(C11, C22) and A_e a third of the rest area of the faces
   beside the edge. */
static void cloth__piece_strain_limiters(cloth_world *w, const cloth__piece *pc, const cloth_mesh *view,
                                         const cloth_topology *topo)
{
    const cloth_material *m = &pc->def.material;
    double young = (double)pc->def.strain_limit_stiffening * (double)(m->stretch_warp > m->stretch_weft ? m->stretch_warp : m->stretch_weft);
    int32_t i;
    CLOTH_ASSERT(topo->edge_count == pc->edge_count);
    for (i = 0; i < pc->edge_count; ++i) {
        const int32_t e = w->spring_count;
        double area = 0, length = (double)pc->edge_rest[i];
        int side;
        for (side = 0; side < 2; ++side) {
            int32_t f = topo->edge_face[2 * (size_t)i + side];
            if (f >= 0) area += (double)cloth__rest_area(pc, pc->tri + 3 * (size_t)f, view->x) / 3;
        }
        w->spring_v[2 * (size_t)e] = pc->edge[2 * (size_t)i] + pc->first_vertex;
        w->spring_v[2 * (size_t)e + 1] = pc->edge[2 * (size_t)i + 1] + pc->first_vertex;
        w->spring_rest[e] = pc->edge_rest[i];
        w->spring_k[e] = length > 0 ? (cloth_real)(young * area / (length * length)) : 0;
        w->spring_beta[e] = 0;
        w->spring_limit[e] = pc->def.strain_limit;
        w->spring_count++;
        w->limiter_count++;
    }
}

/* The pattern's pairs: every pair of vertices that share an element, except the bending
   couplings no edge carries of the pieces whose bending_lumped is at least 1 and at most
   `lumped` (1: the system matrix's, which lacks those of lumped steps; 2: the preconditioner's,
   which lacks those of bending_lumped = 2 too). Returns the count; pairs has room for all. */
static int32_t cloth__world_pairs(const cloth_world *w, int32_t *pairs, int lumped)
{
    int32_t e, s0, s1, pair_count = 0;
#define CLOTH__PAIR(i_, j_) do { pairs[2 * pair_count] = (i_); pairs[2 * pair_count + 1] = (j_); ++pair_count; } while (0)
#define CLOTH__OMITTED(flag_) ((flag_) >= 1 && (flag_) <= lumped)
    for (e = 0; e < w->spring_count; ++e) CLOTH__PAIR(w->spring_v[2 * e], w->spring_v[2 * e + 1]);
    for (e = 0; e < w->membrane_count; ++e) {
        const int32_t *v = w->membrane_v + 3 * e;
        CLOTH__PAIR(v[0], v[1]); CLOTH__PAIR(v[1], v[2]); CLOTH__PAIR(v[2], v[0]);
    }
    for (e = 0; e < w->bend_count; ++e) {
        const int32_t *v = w->bend_v + 4 * e;
        CLOTH__PAIR(v[0], v[1]); CLOTH__PAIR(v[0], v[2]); CLOTH__PAIR(v[0], v[3]);
        CLOTH__PAIR(v[1], v[2]); CLOTH__PAIR(v[1], v[3]);
        if (!CLOTH__OMITTED(w->bend_lumped[e])) CLOTH__PAIR(v[2], v[3]);
    }
    /* a lumped stencil adds its centre's pairs only (its neighbours' pairs that no edge joins
       are lumped) */
    for (e = 0; e < w->qbend_count; ++e)
        for (s0 = w->qbend_start[e]; s0 < (CLOTH__OMITTED(w->qbend_lumped[e]) ? w->qbend_start[e] + 1 : w->qbend_start[e + 1]); ++s0)
            for (s1 = s0 + 1; s1 < w->qbend_start[e + 1]; ++s1) CLOTH__PAIR(w->qbend_v[s0], w->qbend_v[s1]);
    for (e = 0; e < w->ties.count; ++e) {
        const int32_t *v = CLOTH__TIES(w)[e].v;
        int x0, x1;
        for (x0 = 0; x0 < 4; ++x0)
            for (x1 = x0 + 1; x1 < 4; ++x1)
                if (v[x0] >= 0 && v[x1] >= 0) CLOTH__PAIR(v[x0], v[x1]);
    }
#undef CLOTH__OMITTED
#undef CLOTH__PAIR
    return pair_count;
}

/* pmatrix_map and pmatrix_omitted from the two patterns. */
static cloth_result cloth__world_pmatrix_maps(cloth_world *w)
{
    cloth_allocator *a = &w->allocator;
    int32_t i, k, count = 0;
    w->pmatrix_map = (int32_t *)cloth__alloc_array(a, (size_t)w->pmatrix.block_count, sizeof(int32_t));
    for (i = 0; i < w->vertex_count; ++i)
        for (k = w->matrix.row_start[i]; k < w->matrix.row_start[i + 1]; ++k)
            count += w->matrix.column[k] > i && cloth_block_matrix_find(&w->pmatrix, i, w->matrix.column[k]) < 0;
    w->pmatrix_omitted = (int32_t *)cloth__alloc_array(a, (size_t)count + 1, 3 * sizeof(int32_t));
    if (!w->pmatrix_map || !w->pmatrix_omitted) return CLOTH_ERROR_OUT_OF_MEMORY;
    for (i = 0; i < w->vertex_count; ++i)
        for (k = w->pmatrix.row_start[i]; k < w->pmatrix.row_start[i + 1]; ++k)
            w->pmatrix_map[k] = cloth_block_matrix_find(&w->matrix, i, w->pmatrix.column[k]);
    w->pmatrix_omitted_count = 0;
    for (i = 0; i < w->vertex_count; ++i)
        for (k = w->matrix.row_start[i]; k < w->matrix.row_start[i + 1]; ++k) {
            int32_t j = w->matrix.column[k];
            if (j <= i || cloth_block_matrix_find(&w->pmatrix, i, j) >= 0) continue;
            w->pmatrix_omitted[3 * w->pmatrix_omitted_count] = k;
            w->pmatrix_omitted[3 * w->pmatrix_omitted_count + 1] = i;
            w->pmatrix_omitted[3 * w->pmatrix_omitted_count + 2] = j;
            w->pmatrix_omitted_count++;
        }
    return CLOTH_SUCCESS;
}

/* The preconditioner's matrix from the system matrix as it goes into the solve: its blocks
   copied, and each system block B_ij it lacks (i < j) lumped as |B_ij|_F I onto both
   diagonal blocks (a bound from above: 2 |x^T B y| <= |B| (|x|^2 + |y|^2)). */
static void cloth__world_pmatrix_fill(cloth_world *w)
{
    int32_t k, q;
    for (k = 0; k < w->pmatrix.block_count; ++k) {
        const cloth_real *from = w->matrix.value + 9 * (size_t)w->pmatrix_map[k];
        cloth_real *to = w->pmatrix.value + 9 * (size_t)k;
        for (q = 0; q < 9; ++q) to[q] = from[q];
    }
    for (k = 0; k < w->pmatrix_omitted_count; ++k) {
        const int32_t *o = w->pmatrix_omitted + 3 * k;
        const cloth_real *b = w->matrix.value + 9 * (size_t)o[0];
        double f = 0;
        int side;
        for (q = 0; q < 9; ++q) f += (double)b[q] * b[q];
        f = sqrt(f);
        for (side = 1; side <= 2; ++side) {
            cloth_real *d = w->pmatrix.value + 9 * (size_t)w->pmatrix.diagonal[o[side]];
            d[0] += (cloth_real)f;
            d[4] += (cloth_real)f;
            d[8] += (cloth_real)f;
        }
    }
}

static cloth_result cloth__world_build(cloth_world *w)
{
    const cloth_allocator *a = &w->allocator;
    int32_t p, i, pair_count = 0, ns = 0, nm = 0, nb = 0, nq = 0, nqe = 0, t;
    int32_t *pairs = NULL;
    int lumped_preconditioner = 0; /* a piece with bending_lumped = 2: the preconditioner's own matrix */
    cloth_topology *topos; /* each piece's topology, made once for both passes below */
    cloth_result r = CLOTH_SUCCESS;
    size_t n3 = (size_t)w->vertex_count * 3;
    cloth__world_free_elements(w);
    topos = (cloth_topology *)cloth__alloc_array(a, (size_t)w->pieces.count, sizeof(cloth_topology));
    if (!topos) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(topos, 0, (size_t)w->pieces.count * sizeof(cloth_topology));
    /* count elements */
    for (p = 0; p < w->pieces.count; ++p) {
        const cloth__piece *pc = CLOTH__PIECES(w) + p;
        cloth_mesh view = cloth_world_mesh(w, p);
        int32_t count = 0;
        if (pc->def.model == CLOTH_MODEL_MEMBRANE) nm += pc->triangle_count;
        r = cloth_topology_build(topos + p, &view, a);
        if (r != CLOTH_SUCCESS) goto fail;
        if (pc->def.model == CLOTH_MODEL_MASS_SPRING) {
            if (pc->def.grid_nx) r = cloth_grid_springs(pc->def.grid_nx, pc->def.grid_ny, CLOTH_SPRING_ALL, NULL, NULL, 0, &count);
            else r = cloth_topology_springs(topos + p, CLOTH_SPRING_ALL, NULL, NULL, 0, &count);
            ns += count;
        }
        if (r == CLOTH_SUCCESS && cloth__piece_quadratic_bending(pc)) {
            cloth__piece_params pp = cloth__params_of(&pc->def);
            r = cloth_quadratic_bending_stencils(&view, topos + p, pp.bend_warp, pp.bend_weft, NULL, NULL, NULL, NULL, NULL, 0, &count);
            if (r == CLOTH_SUCCESS && (int64_t)nqe + count > INT32_MAX / 3) r = CLOTH_ERROR_SIZE_OVERFLOW;
            nq += pc->vertex_count;
            nqe += count;
        } else if (pc->def.bending && pc->def.model == CLOTH_MODEL_MEMBRANE)
            for (i = 0; i < topos[p].edge_count; ++i) nb += topos[p].edge_face[2 * i + 1] >= 0;
        if (r == CLOTH_SUCCESS && pc->def.strain_limit > 0) {
            if ((int64_t)ns + topos[p].edge_count > INT32_MAX / 2) r = CLOTH_ERROR_SIZE_OVERFLOW;
            ns += topos[p].edge_count;
        }
        if (r != CLOTH_SUCCESS) goto fail;
    }
    w->spring_v = (int32_t *)cloth__alloc_array(a, (size_t)ns, 2 * sizeof(int32_t));
    w->spring_k = (cloth_real *)cloth__alloc_array(a, (size_t)ns, sizeof(cloth_real));
    w->spring_rest = (cloth_real *)cloth__alloc_array(a, (size_t)ns, sizeof(cloth_real));
    w->spring_beta = (cloth_real *)cloth__alloc_array(a, (size_t)ns, sizeof(cloth_real));
    w->spring_limit = (cloth_real *)cloth__alloc_array(a, (size_t)ns, sizeof(cloth_real));
    w->membrane_v = (int32_t *)cloth__alloc_array(a, (size_t)nm, 3 * sizeof(int32_t));
    w->membrane_rest = (cloth_membrane_rest *)cloth__alloc_array(a, (size_t)nm, sizeof(cloth_membrane_rest));
    w->membrane_stiffness = (cloth_membrane_stiffness *)cloth__alloc_array(a, (size_t)nm, sizeof(cloth_membrane_stiffness));
    w->membrane_beta = (cloth_real *)cloth__alloc_array(a, (size_t)nm, sizeof(cloth_real));
    w->membrane_relative_damping = (cloth_real *)cloth__alloc_array(a, (size_t)nm, sizeof(cloth_real));
    w->bend_v = (int32_t *)cloth__alloc_array(a, (size_t)nb, 4 * sizeof(int32_t));
    w->bend_rest = (cloth_bending_rest *)cloth__alloc_array(a, (size_t)nb, sizeof(cloth_bending_rest));
    w->bend_k = (cloth_real *)cloth__alloc_array(a, (size_t)nb, sizeof(cloth_real));
    w->bend_beta = (cloth_real *)cloth__alloc_array(a, (size_t)nb, sizeof(cloth_real));
    w->bend_lumped = (unsigned char *)cloth__alloc_array(a, (size_t)nb, 1);
    w->qbend_start = (int32_t *)cloth__alloc_array(a, (size_t)nq + 1, sizeof(int32_t));
    w->qbend_v = (int32_t *)cloth__alloc_array(a, (size_t)nqe, sizeof(int32_t));
    w->qbend_w = (cloth_real *)cloth__alloc_array(a, (size_t)nqe, 3 * sizeof(cloth_real));
    w->qbend_beta = (cloth_real *)cloth__alloc_array(a, (size_t)nq, sizeof(cloth_real));
    w->qbend_lumped = (unsigned char *)cloth__alloc_array(a, (size_t)nq, 1);
    if (!w->spring_v || !w->spring_k || !w->spring_rest || !w->spring_beta || !w->spring_limit || !w->membrane_v || !w->membrane_rest ||
        !w->membrane_stiffness || !w->membrane_beta || !w->membrane_relative_damping || !w->bend_v || !w->bend_rest ||
        !w->bend_k || !w->bend_beta || !w->bend_lumped || !w->qbend_start || !w->qbend_v || !w->qbend_w || !w->qbend_beta || !w->qbend_lumped) {
        r = CLOTH_ERROR_OUT_OF_MEMORY;
        goto fail;
    }
    w->qbend_start[0] = 0;
    /* fill elements, piece by piece */
    for (p = 0; p < w->pieces.count; ++p) {
        const cloth__piece *pc = CLOTH__PIECES(w) + p;
        cloth__piece_params pp = cloth__params_of(&pc->def);
        cloth_mesh view = cloth_world_mesh(w, p);
        const cloth_topology *topo = topos + p;
        int32_t off = pc->first_vertex;
        if (pc->def.model == CLOTH_MODEL_MEMBRANE) {
            for (t = 0; t < pc->triangle_count && r == CLOTH_SUCCESS; ++t) {
                const int32_t *lt = pc->tri + 3 * t;
                int k;
                for (k = 0; k < 3; ++k) w->membrane_v[3 * w->membrane_count + k] = lt[k] + off;
                if (pc->uv) r = cloth_membrane_rest_make(w->membrane_rest + w->membrane_count, pc->uv + 2 * lt[0], pc->uv + 2 * lt[1], pc->uv + 2 * lt[2]);
                else {
                    /* rest shape from the initial positions, in the triangle's own plane */
                    cloth_real e0[3], e1[3], n[3], ax[3], ay[3], uv[6];
                    cloth__v3_sub(view.x + 3 * lt[1], view.x + 3 * lt[0], e0);
                    cloth__v3_sub(view.x + 3 * lt[2], view.x + 3 * lt[0], e1);
                    cloth__v3_cross(e0, e1, n);
                    cloth__v3_scale(e0, 1 / cloth__v3_norm(e0), ax);
                    cloth__v3_cross(n, ax, ay);
                    cloth__v3_scale(ay, 1 / cloth__v3_norm(ay), ay);
                    uv[0] = uv[1] = 0;
                    uv[2] = cloth__v3_dot(e0, ax); uv[3] = cloth__v3_dot(e0, ay);
                    uv[4] = cloth__v3_dot(e1, ax); uv[5] = cloth__v3_dot(e1, ay);
                    r = cloth_membrane_rest_make(w->membrane_rest + w->membrane_count, uv, uv + 2, uv + 4);
                }
                w->membrane_stiffness[w->membrane_count] = pp.membrane;
                w->membrane_beta[w->membrane_count] = pp.beta;
                w->membrane_relative_damping[w->membrane_count] = pp.relative_damping;
                w->membrane_count++;
            }
            if (cloth__piece_quadratic_bending(pc)) {
                r = cloth__piece_quadratic_stencils(w, p, topo, w->qbend_count, nqe);
                for (i = 0; r == CLOTH_SUCCESS && i < pc->vertex_count; ++i) {
                    w->qbend_beta[w->qbend_count + i] = pp.beta;
                    w->qbend_lumped[w->qbend_count + i] = (unsigned char)pc->def.bending_lumped;
                }
                if (r == CLOTH_SUCCESS) w->qbend_count += pc->vertex_count;
            }
            else if (pc->def.bending)
                for (i = 0; i < topo->edge_count && r == CLOTH_SUCCESS; ++i) {
                    int32_t s[4];
                    int k;
                    if (topo->edge_face[2 * i + 1] < 0) continue;
                    s[0] = topo->edge_vertex[2 * i]; s[1] = topo->edge_vertex[2 * i + 1];
                    s[2] = topo->edge_opposite[2 * i]; s[3] = topo->edge_opposite[2 * i + 1];
                    /* the stencil wants face (x0, x1, x2) counter-clockwise: slot 0 runs lo -> hi */
                    if (pc->uv) r = cloth_bending_rest_make(w->bend_rest + w->bend_count, pc->uv + 2 * s[0], pc->uv + 2 * s[1], pc->uv + 2 * s[2], pc->uv + 2 * s[3], 0);
                    else r = cloth_bending_rest_from_shape(w->bend_rest + w->bend_count, view.x + 3 * s[0], view.x + 3 * s[1], view.x + 3 * s[2], view.x + 3 * s[3]);
                    w->bend_k[w->bend_count] = pc->uv ? cloth_bending_stiffness_orthotropic(pp.bend_warp, pp.bend_weft, pc->uv + 2 * s[0], pc->uv + 2 * s[1])
                                                    : pp.bend_warp;
                    w->bend_beta[w->bend_count] = pp.beta;
                    w->bend_lumped[w->bend_count] = (unsigned char)pc->def.bending_lumped;
                    for (k = 0; k < 4; ++k) w->bend_v[4 * w->bend_count + k] = s[k] + off;
                    w->bend_count++;
                }
        } else {
            int32_t count = 0, *kind, first = w->spring_count;
            kind = (int32_t *)cloth__alloc_array(a, (size_t)(ns - first), sizeof(int32_t));
            if (!kind) r = CLOTH_ERROR_OUT_OF_MEMORY;
            else if (pc->def.grid_nx) r = cloth_grid_springs(pc->def.grid_nx, pc->def.grid_ny, CLOTH_SPRING_ALL, w->spring_v + 2 * first, kind, ns - first, &count);
            else r = cloth_topology_springs(topo, CLOTH_SPRING_ALL, w->spring_v + 2 * first, kind, ns - first, &count);
            if (r == CLOTH_SUCCESS)
                r = pc->uv ? cloth_spring_rest_lengths(pc->uv, 2, pc->vertex_count, w->spring_v + 2 * first, count, w->spring_rest + first)
                           : cloth_spring_rest_lengths(view.x, 3, pc->vertex_count, w->spring_v + 2 * first, count, w->spring_rest + first);
            for (i = 0; r == CLOTH_SUCCESS && i < count; ++i) {
                w->spring_v[2 * (first + i)] += off;
                w->spring_v[2 * (first + i) + 1] += off;
                cloth_real L = w->spring_rest[first + i];
                w->spring_k[first + i] = kind[i] == CLOTH_SPRING_STRUCTURAL ? pp.spring_stretch
                                       : kind[i] == CLOTH_SPRING_SHEAR      ? pp.spring_shear
                                       : (L > 0 ? pp.spring_bend / (L * L) : 0);
                w->spring_beta[first + i] = pp.beta;
                w->spring_limit[first + i] = 0;
            }
            if (r == CLOTH_SUCCESS) w->spring_count += count;
            cloth__free(a, kind);
        }
        if (r == CLOTH_SUCCESS && pc->def.strain_limit > 0) cloth__piece_strain_limiters(w, pc, &view, topo);
        if (r != CLOTH_SUCCESS) goto fail;
    }
    /* the pattern: every pair of vertices that share an element */
    {
        size_t cap = (size_t)w->spring_count + 3 * (size_t)w->membrane_count + 6 * (size_t)w->bend_count + 6 * (size_t)w->ties.count;
        int32_t e;
        for (e = 0; e < w->qbend_count; ++e) {
            size_t n = (size_t)(w->qbend_start[e + 1] - w->qbend_start[e]);
            cap += n * (n - (n > 0)) / 2;
        }
        if (cap > (size_t)INT32_MAX) { r = CLOTH_ERROR_SIZE_OVERFLOW; goto fail; }
        pairs = (int32_t *)cloth__alloc_array(a, cap, 2 * sizeof(int32_t));
        if (!pairs) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
        pair_count = cloth__world_pairs(w, pairs, 1);
        for (e = 0; e < w->bend_count; ++e) lumped_preconditioner |= w->bend_lumped[e] == 2;
        for (e = 0; e < w->qbend_count; ++e) lumped_preconditioner |= w->qbend_lumped[e] == 2;
    }
    r = cloth_block_matrix_create(&w->matrix, w->vertex_count, pairs, pair_count, a);
    if (r == CLOTH_SUCCESS && lumped_preconditioner) {
        pair_count = cloth__world_pairs(w, pairs, 2);
        r = cloth_block_matrix_create(&w->pmatrix, w->vertex_count, pairs, pair_count, a);
        if (r == CLOTH_SUCCESS) r = cloth__world_pmatrix_maps(w);
    }
    cloth__free(a, pairs);
    if (r != CLOTH_SUCCESS) goto fail;
    r = cloth_pcg_workspace_create(&w->pcg, w->vertex_count, a);
    if (r != CLOTH_SUCCESS) goto fail;
    w->pcg.pool = w->pool; /* borrowed: the world frees its pool */
    w->spring_block = (int32_t *)cloth__alloc_array(a, (size_t)w->spring_count, 4 * sizeof(int32_t));
    w->membrane_block = (int32_t *)cloth__alloc_array(a, (size_t)w->membrane_count, 9 * sizeof(int32_t));
    w->bend_block = (int32_t *)cloth__alloc_array(a, (size_t)w->bend_count, 16 * sizeof(int32_t));
    w->tie_block = (int32_t *)cloth__alloc_array(a, (size_t)w->ties.count, 16 * sizeof(int32_t));
    w->attach_block = (int32_t *)cloth__alloc_array(a, (size_t)w->attachments.count, sizeof(int32_t));
    w->qbend_block_start = (int32_t *)cloth__alloc_array(a, (size_t)w->qbend_count + 1, sizeof(int32_t));
    if (!w->spring_block || !w->membrane_block || !w->bend_block || !w->tie_block || !w->attach_block || !w->qbend_block_start) {
        r = CLOTH_ERROR_OUT_OF_MEMORY;
        goto fail;
    }
    {
        /* the blocks of every stencil's n x n entry pairs */
        size_t total = 0;
        for (i = 0; i < w->qbend_count; ++i) {
            size_t n = (size_t)(w->qbend_start[i + 1] - w->qbend_start[i]);
            w->qbend_block_start[i] = (int32_t)total;
            total += n * n;
            if (total > (size_t)INT32_MAX) { r = CLOTH_ERROR_SIZE_OVERFLOW; goto fail; }
        }
        w->qbend_block_start[w->qbend_count] = (int32_t)total;
        w->qbend_block = (int32_t *)cloth__alloc_array(a, total, sizeof(int32_t));
        if (!w->qbend_block) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
        for (i = 0; i < w->qbend_count; ++i)
            cloth__element_blocks(&w->matrix, w->qbend_v + w->qbend_start[i], w->qbend_start[i + 1] - w->qbend_start[i],
                                  w->qbend_block + w->qbend_block_start[i]);
    }
    for (i = 0; i < w->spring_count; ++i) cloth__element_blocks(&w->matrix, w->spring_v + 2 * i, 2, w->spring_block + 4 * i);
    for (i = 0; i < w->membrane_count; ++i) cloth__element_blocks(&w->matrix, w->membrane_v + 3 * i, 3, w->membrane_block + 9 * i);
    for (i = 0; i < w->bend_count; ++i) {
        cloth__element_blocks(&w->matrix, w->bend_v + 4 * i, 4, w->bend_block + 16 * i);
        /* a lumped hinge never writes its wing tips' coupling, even where another element
           put that block in the pattern: the same hinge adds the same everywhere */
        if (w->bend_lumped[i] == 1) w->bend_block[16 * i + 2 * 4 + 3] = w->bend_block[16 * i + 3 * 4 + 2] = -1;
    }
    for (i = 0; i < w->ties.count; ++i) cloth__element_blocks(&w->matrix, CLOTH__TIES(w)[i].v, 4, w->tie_block + 16 * i);
    for (i = 0; i < w->attachments.count; ++i) w->attach_block[i] = w->matrix.diagonal[CLOTH__ATTACH(w)[i].v[0]];
    /* which optional parts the scene uses */
    w->need_damping_matrix = 0;
    for (i = 0; i < w->vertex_count; ++i) w->need_damping_matrix |= w->drag[i] > 0;
    for (i = 0; i < w->spring_count; ++i) w->need_damping_matrix |= w->spring_beta[i] > 0;
    for (i = 0; i < w->membrane_count; ++i) w->need_damping_matrix |= w->membrane_beta[i] > 0 || w->membrane_relative_damping[i] > 0;
    for (i = 0; i < w->bend_count; ++i) w->need_damping_matrix |= w->bend_beta[i] > 0;
    for (i = 0; i < w->qbend_count; ++i) w->need_damping_matrix |= w->qbend_beta[i] > 0;
    /* the damping matrix exists only in scenes with damping */
    if (w->need_damping_matrix) {
        w->damping_value = (cloth_real *)cloth__alloc_array(a, (size_t)w->matrix.block_count, 9 * sizeof(cloth_real));
        if (!w->damping_value) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
    }
    w->need_wind = 0;
    if (w->def.air_density > 0 && (w->def.wind[0] != 0 || w->def.wind[1] != 0 || w->def.wind[2] != 0 || w->def.gust_strength > 0))
        for (p = 0; p < w->pieces.count; ++p) w->need_wind |= CLOTH__PIECES(w)[p].def.wind != 0;
    /* scratch and backup vectors */
    {
        cloth_real **vecs[14];
        int k;
        vecs[0] = &w->s_x0; vecs[1] = &w->s_xhat; vecs[2] = &w->s_xbase; vecs[3] = &w->s_grad; vecs[4] = &w->s_dx;
        vecs[5] = &w->s_rhs; vecs[6] = &w->s_trial; vecs[7] = &w->s_tmp; vecs[8] = &w->s_wind;
        vecs[9] = &w->b_x; vecs[10] = &w->b_v; vecs[11] = &w->b_x_prev; vecs[12] = &w->b_v_prev; vecs[13] = &w->s_phi;
        for (k = 0; k < 14; ++k) {
            *vecs[k] = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
            if (!*vecs[k]) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
        }
        w->s_fixed = (int32_t *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(int32_t));
        if (!w->s_fixed) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
    }
    /* the collide phase, when the scene has anything to collide */
    if (w->obstacles.count > 0 || w->def.self_collision || w->def.piece_collision) {
        cloth_contact_def cd = cloth_default_contact_def();
        cd.vertex_count = w->vertex_count;
        cd.tri = w->tri;
        cd.triangle_count = w->triangle_count;
        cd.triangle_piece = w->tri_piece;
        cd.self_collision = w->def.self_collision;
        cd.piece_collision = w->def.piece_collision;
        cd.thickness = w->def.collision_thickness;
        cd.friction_static = cd.friction_kinetic = w->def.cloth_friction;
        cd.allocator = w->allocator;
        cd.clock = w->def.clock;
        cd.clock_user = w->def.clock_user;
        r = cloth_contact_create(&w->contact, &cd);
        if (r == CLOTH_SUCCESS) w->contact->pool = w->pool; /* the narrow phase's queries on the world's threads */
        for (p = 0; r == CLOTH_SUCCESS && p < w->obstacles.count; ++p) r = cloth_contact_add_obstacle(w->contact, &CLOTH__OBSTACLES(w)[p].def, NULL);
        if (r != CLOTH_SUCCESS) goto fail;
        w->s_inverse_mass = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(cloth_real));
        if (!w->s_inverse_mass) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
        for (p = 0; p < w->obstacles.count; ++p) w->analytic_obstacles += CLOTH__OBSTACLES(w)[p].def.shape != CLOTH_OBSTACLE_MESH;
        if ((w->def.self_collision || w->def.piece_collision || w->analytic_obstacles < w->obstacles.count) &&
            w->def.proximity_stiffness > 0) {
            /* at most 4 springs per vertex (resting layers make one or two), a fixed budget */
            w->prox_capacity = w->vertex_count > INT32_MAX / 16 ? INT32_MAX / 4 : 4 * w->vertex_count + 64;
            w->prox = (struct cloth__prox_pair *)cloth__alloc_array(a, (size_t)w->prox_capacity, sizeof(struct cloth__prox_pair));
            w->b_prox = (struct cloth__prox_pair *)cloth__alloc_array(a, (size_t)w->prox_capacity, sizeof(struct cloth__prox_pair));
            w->prox_slot = (int32_t *)cloth__alloc_array(a, 2 * (size_t)w->prox_capacity, sizeof(int32_t));
            if (!w->prox || !w->b_prox || !w->prox_slot) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
            w->prox_count = 0;
        }
        if (w->analytic_obstacles > 0 && w->def.obstacle_constraints) {
            w->s_held = (int32_t *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(int32_t));
            w->s_switched = (int32_t *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(int32_t));
            w->b_held = (int32_t *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(int32_t));
            w->s_direction = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, 6 * sizeof(cloth_real));
            w->s_plane = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, sizeof(cloth_real));
            w->s_value = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, 3 * sizeof(cloth_real));
            w->s_anchor = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, 3 * sizeof(cloth_real));
            w->s_friction = (cloth_real *)cloth__alloc_array(a, (size_t)w->vertex_count, 3 * sizeof(cloth_real));
            if (!w->s_held || !w->s_switched || !w->b_held || !w->s_direction || !w->s_plane || !w->s_value || !w->s_anchor || !w->s_friction) {
                r = CLOTH_ERROR_OUT_OF_MEMORY;
                goto fail;
            }
            for (i = 0; i < w->vertex_count; ++i) w->s_held[i] = -1;
        }
    }
    if (w->qbend_count > 0) {
        w->qbend_diagonal = (cloth_real *)cloth__alloc_array(a, (size_t)w->matrix.block_count, sizeof(cloth_real));
        if (!w->qbend_diagonal) { r = CLOTH_ERROR_OUT_OF_MEMORY; goto fail; }
        cloth__qbend_diagonal_make(w);
    }
    r = cloth__elastic_parts_build(w);
    if (r != CLOTH_SUCCESS) goto fail;
    w->stable_step_age = 0;
    w->structure_dirty = 0;
    w->qbend_pins_dirty = 0;
    w->topos = topos; /* kept: the quadratic bending's stencils follow the pins */
    w->topo_count = w->pieces.count;
    return CLOTH_SUCCESS;
fail:
    for (p = 0; p < w->pieces.count; ++p) cloth_topology_free(topos + p);
    cloth__free(a, topos);
    cloth__world_free_elements(w);
    return r;
}

/* After pins changed (cloth_world_pin, _unpin, _set_handle): the quadratic bending's weights
   again, with the structure (stencils' entries, the matrix pattern) as it is. */
static cloth_result cloth__world_refresh_pins(cloth_world *w)
{
    int32_t p, q = 0;
    cloth_result r = CLOTH_SUCCESS;
    for (p = 0; p < w->pieces.count && r == CLOTH_SUCCESS; ++p) {
        const cloth__piece *pc = CLOTH__PIECES(w) + p;
        if (!cloth__piece_quadratic_bending(pc)) continue;
        r = cloth__piece_quadratic_stencils(w, p, w->topos + p, q, w->qbend_start[w->qbend_count]);
        q += pc->vertex_count;
    }
    if (r == CLOTH_SUCCESS) {
        cloth__qbend_diagonal_make(w);
        w->qbend_pins_dirty = 0;
    }
    return r;
}

/* The world's elements up to date before a step or a query: the structure after a structural
   change, the quadratic bending's weights after a change of pins. */
static cloth_result cloth__world_ready(cloth_world *w)
{
    if (w->structure_dirty) return cloth__world_build(w);
    if (w->qbend_pins_dirty) return cloth__world_refresh_pins(w);
    return CLOTH_SUCCESS;
}

/* ---- energies and assembly ---------------------------------------------------------- */

/* The rows [lo, hi) that one part of the assembly writes, and the elements that touch them
   (kinds: springs, membranes, bending hinges, quadratic bending stencils, seams, attachments;
   list NULL: every element of the kind). */
#define CLOTH__KINDS 6
typedef struct cloth__elastic_part {
    int32_t lo, hi;
    int32_t *list[CLOTH__KINDS];
    int32_t count[CLOTH__KINDS];
} cloth__elastic_part;

/* values[block] += scale * the (a, b) 3x3 block of an element Hessian of k vertices, for the
   rows a whose vertex v[a] is in [lo, hi). */
static void cloth__add_element_hessian(cloth_real *values, const int32_t *blocks, const int32_t *v, int k,
                                       const cloth_real *hessian, cloth_real scale, int32_t lo, int32_t hi)
{
    const int stride = 3 * k;
    int a, b, r;
    for (a = 0; a < k; ++a) {
        if (v[a] < lo || v[a] >= hi) continue;
        for (b = 0; b < k; ++b) {
            const cloth_real *h = hessian + 3 * a * stride + 3 * b;
            cloth_real *dst;
            if (blocks[a * k + b] < 0) continue;
            dst = values + 9 * (size_t)blocks[a * k + b];
            /* rows written out (the assembly's hot loop); scale 1, the system matrix, skips the products */
            if (scale == 1)
                for (r = 0; r < 3; ++r, h += stride, dst += 3) {
                    dst[0] += h[0];
                    dst[1] += h[1];
                    dst[2] += h[2];
                }
            else
                for (r = 0; r < 3; ++r, h += stride, dst += 3) {
                    dst[0] += scale * h[0];
                    dst[1] += scale * h[1];
                    dst[2] += scale * h[2];
                }
        }
    }
}

/* values[block] += scale * the (a, b) block of a triangle's Hessian given as its six blocks
   a <= b (cloth__membrane_terms), the blocks (b, a) transposed, for the rows a whose vertex
   v[a] is in [lo, hi). */
static void cloth__add_triangle_blocks(cloth_real *values, const int32_t *blocks, const int32_t *v, const cloth_real *six,
                                       cloth_real scale, int32_t lo, int32_t hi)
{
    static const int at[9] = { 0, 1, 2, 1, 3, 4, 2, 4, 5 };
    int a, b, r;
    for (a = 0; a < 3; ++a) {
        if (v[a] < lo || v[a] >= hi) continue;
        for (b = 0; b < 3; ++b) {
            const cloth_real *h = six + 9 * at[3 * a + b];
            cloth_real *dst;
            if (blocks[3 * a + b] < 0) continue;
            dst = values + 9 * (size_t)blocks[3 * a + b];
            if (a <= b) {
                if (scale == 1)
                    for (r = 0; r < 9; ++r) dst[r] += h[r];
                else
                    for (r = 0; r < 9; ++r) dst[r] += scale * h[r];
            } else {
                for (r = 0; r < 3; ++r) {
                    dst[3 * r] += scale * h[r];
                    dst[3 * r + 1] += scale * h[3 + r];
                    dst[3 * r + 2] += scale * h[6 + r];
                }
            }
        }
    }
}

/* values[block] += c (u_a u_b^T), the (a, b) block of a rank-one element Hessian c u u^T
   (u of 3k entries), for the rows a whose vertex v[a] is in [lo, hi); each entry c (u_i u_j),
   so the blocks are exactly symmetric. */
static void cloth__add_element_rank_one(cloth_real *values, const int32_t *blocks, const int32_t *v, int k,
                                        const cloth_real *u, cloth_real c, int32_t lo, int32_t hi)
{
    int a, b, r;
    for (a = 0; a < k; ++a) {
        const cloth_real *ua = u + 3 * a;
        if (v[a] < lo || v[a] >= hi) continue;
        for (b = 0; b < k; ++b) {
            const cloth_real *ub = u + 3 * b;
            cloth_real *dst;
            if (blocks[a * k + b] < 0) continue;
            dst = values + 9 * (size_t)blocks[a * k + b];
            for (r = 0; r < 3; ++r, dst += 3) {
                dst[0] += c * (ua[r] * ub[0]);
                dst[1] += c * (ua[r] * ub[1]);
                dst[2] += c * (ua[r] * ub[2]);
            }
        }
    }
}

/* The rank-one Hessian c u u^T of a hinge (u: the angle's gradient, 12 entries) whose wing
   tips' coupling blocks (2, 3) and (3, 2) are absent (-1: a lumped hinge, its piece's
   def.bending_lumped). Adds c u u^T + c w w^T with w = (0, 0, s u2, -u3 / s): the two missing
   blocks cancel, every other block of c u u^T is kept, and the sum bounds c u u^T from above
   (w w^T is positive semidefinite), so the linearized step stays stable. s^2 = |u3| / |u2|
   makes w vanish on a translation along the normal of a flat hinge (u2 and u3 both lie along
   it, |u_a| = 1 / the tip's height), so a falling sheet is not slowed however its triangles
   differ. A rotation of the two wings about the hinge edge cannot be freed of w (terms on
   the tips always have a moment about the edge, and the edge's ends have none to cancel it),
   so it is damped (README, "Lumped bending"). The tips' diagonal blocks get the extra
   c s^2 u2 u2^T and c u3 u3^T / s^2. */
static void cloth__add_hinge_lumped(cloth_real *values, const int32_t *blocks, const int32_t *v, const cloth_real *u,
                                    cloth_real c, int32_t lo, int32_t hi)
{
    cloth_real n2 = cloth__v3_norm(u + 6), n3 = cloth__v3_norm(u + 9);
    cloth__add_element_rank_one(values, blocks, v, 4, u, c, lo, hi);
    if (!(n2 > 0) || !(n3 > 0)) return; /* a zero tip gradient couples nothing */
    /* each tip's extra term: a one-vertex rank-one element on its diagonal block */
    cloth__add_element_rank_one(values, blocks + 2 * 4 + 2, v + 2, 1, u + 6, c * (n3 / n2), lo, hi);
    cloth__add_element_rank_one(values, blocks + 3 * 4 + 3, v + 3, 1, u + 9, c * (n2 / n3), lo, hi);
}

/* The part of a quadratic bending stencil's Hessian (blocks sum_m c_am c_bm I; entry 0 the
   centre, the others its neighbours) that a lumped stencil (its piece's def.bending_lumped)
   cannot write: the pairs of neighbours with no block (-1: no edge joins them). Each such
   pair's h = sum_m c_am c_bm becomes scale |h| w w^T with w = e_a - e_b when h > 0 and
   w = e_a + e_b - 2 e_centre when h < 0: it cancels the missing blocks, adds only on the
   pattern (the diagonal and the centre's row and column), bounds the exact Hessian from above
   and vanishes on a translation (w sums to zero), so a falling sheet is not slowed. Rows in
   [lo, hi) only. */
static void cloth__add_stencil_lumped(cloth_real *values, int stride, const int32_t *blocks, const int32_t *v,
                                      const cloth_real *c, int32_t n, cloth_real scale, int32_t lo, int32_t hi)
{
    int32_t a, b, q;
#define CLOTH__STENCIL_H(p_, q_) (c[3 * (p_)] * c[3 * (q_)] + c[3 * (p_) + 1] * c[3 * (q_) + 1] + c[3 * (p_) + 2] * c[3 * (q_) + 2])
#define CLOTH__ADD_I(block_, amount_) do { cloth_real *o_ = values + (size_t)stride * (size_t)(block_); \
        o_[0] += (amount_); if (stride == 9) { o_[4] += (amount_); o_[8] += (amount_); } } while (0)
    if (v[0] >= lo && v[0] < hi) /* the centre's row: the pairs with h < 0 */
        for (b = 1; b < n; ++b)
            for (q = b + 1; q < n; ++q) {
                cloth_real h;
                if (blocks[b * n + q] >= 0) continue;
                h = CLOTH__STENCIL_H(b, q);
                if (!(h < 0)) continue;
                CLOTH__ADD_I(blocks[0], -4 * scale * h);
                CLOTH__ADD_I(blocks[b], 2 * scale * h);
                CLOTH__ADD_I(blocks[q], 2 * scale * h);
            }
    for (a = 1; a < n; ++a) { /* a neighbour's row: its own lumped pairs */
        if (v[a] < lo || v[a] >= hi) continue;
        for (b = 1; b < n; ++b) {
            cloth_real h;
            if (b == a || blocks[a * n + b] >= 0) continue;
            h = CLOTH__STENCIL_H(a, b);
            CLOTH__ADD_I(blocks[a * n + a], scale * (h < 0 ? -h : h));
            if (h < 0) CLOTH__ADD_I(blocks[a * n], 2 * scale * h);
        }
    }
#undef CLOTH__ADD_I
#undef CLOTH__STENCIL_H
}

/* scale times quadratic bending stencil e's Hessian (blocks sum_m c_am c_bm I, the lumped
   part included when the stencil is lumped) added to the rows in [lo, hi): into 3x3 blocks
   (stride 9) or into one coefficient per block (stride 1, w->qbend_diagonal). */
static void cloth__add_qbend_hessian(const cloth_world *w, int32_t e, cloth_real *values, int stride, cloth_real scale,
                                     int32_t lo, int32_t hi)
{
    const int32_t s = w->qbend_start[e], n = w->qbend_start[e + 1] - s;
    const int32_t *v = w->qbend_v + s, *blocks = w->qbend_block + w->qbend_block_start[e];
    const cloth_real *c = w->qbend_w + 3 * (size_t)s;
    int32_t a, b;
    for (a = 0; a < n; ++a) {
        if (v[a] < lo || v[a] >= hi) continue;
        for (b = 0; b < n; ++b) {
            cloth_real h = scale * (c[3 * a] * c[3 * b] + c[3 * a + 1] * c[3 * b + 1] + c[3 * a + 2] * c[3 * b + 2]);
            cloth_real *o;
            if (blocks[a * n + b] < 0) continue; /* lumped below */
            o = values + (size_t)stride * (size_t)blocks[a * n + b];
            o[0] += h;
            if (stride == 9) {
                o[4] += h;
                o[8] += h;
            }
        }
    }
    if (w->qbend_lumped[e] == 1) cloth__add_stencil_lumped(values, stride, blocks, v, c, n, scale, lo, hi);
}

/* w->qbend_diagonal from the stencils' weights as they are now. */
static void cloth__qbend_diagonal_make(cloth_world *w)
{
    int32_t e;
    if (!w->qbend_diagonal) return;
    memset(w->qbend_diagonal, 0, (size_t)w->matrix.block_count * sizeof(cloth_real));
    for (e = 0; e < w->qbend_count; ++e) cloth__add_qbend_hessian(w, e, w->qbend_diagonal, 1, 1, 0, w->vertex_count);
}

/* grad[v[a]] += g[a] for the vertices in [lo, hi). */
static void cloth__add_element_gradient(cloth_real *grad, const int32_t *v, int k, const cloth_real *g, int32_t lo, int32_t hi)
{
    int a;
    for (a = 0; a < k; ++a)
        if (v[a] >= lo && v[a] < hi) {
            grad[3 * (size_t)v[a]] += g[3 * a];
            grad[3 * (size_t)v[a] + 1] += g[3 * a + 1];
            grad[3 * (size_t)v[a] + 2] += g[3 * a + 2];
        }
}

/* The first vertex of an element (its energy's owner among the parts), -1 for none. */
static int32_t cloth__first_vertex(const int32_t *v, int32_t k)
{
    int32_t a;
    for (a = 0; a < k; ++a)
        if (v[a] >= 0) return v[a];
    return -1;
}

/* One part of cloth__elastic: zero the part's rows of grad, the matrix and damping, then add
   every element's contributions to them, element by element in the serial order, so each entry
   receives the same additions in the same order whatever the partition. The energy: summed
   into the return value when energy is NULL (one part over all rows), else each element's
   terms written to energy[] by the part that holds the element's first vertex (the quadratic
   bending's three terms apart). */
static cloth_real cloth__elastic_part_run(cloth_world *w, const cloth_real *x, cloth_real *grad, int assemble,
                                          cloth_real *damping, const cloth__elastic_part *part, cloth_real *energy)
{
    const int32_t lo = part->lo, hi = part->hi;
    cloth_real sum = 0, g[12], hess[144], en;
    cloth_real *gp = grad ? g : NULL, *hp = (assemble || damping) ? hess : NULL;
    size_t off = 0;
    int32_t idx, e;
#define CLOTH__ELEMENT(kind) (part->list[kind] ? part->list[kind][idx] : idx)
#define CLOTH__ENERGY(value, owner, slot)                                                          \
    do {                                                                                           \
        if (!energy) sum += (value);                                                               \
        else if ((owner) >= lo && (owner) < hi) energy[slot] = (value);                            \
    } while (0)
    if (grad) memset(grad + 3 * (size_t)lo, 0, (size_t)(hi - lo) * 3 * sizeof(cloth_real));
    if (assemble || damping) {
        size_t b0 = 9 * (size_t)w->matrix.row_start[lo], b1 = 9 * (size_t)w->matrix.row_start[hi];
        if (assemble && w->qbend_diagonal) {
            /* the quadratic bending's constant Hessian c I, then the other terms on top */
            const cloth_real *qd = w->qbend_diagonal + b0 / 9;
            cloth_real *m = w->matrix.value + b0;
            size_t k;
            for (k = 0; k < (b1 - b0) / 9; ++k, m += 9) {
                m[0] = m[4] = m[8] = qd[k];
                m[1] = m[2] = m[3] = m[5] = m[6] = m[7] = 0;
            }
        } else if (assemble) {
            memset(w->matrix.value + b0, 0, (b1 - b0) * sizeof(cloth_real));
        }
        if (damping) memset(damping + b0, 0, (b1 - b0) * sizeof(cloth_real));
    }
    for (idx = 0; idx < part->count[0]; ++idx) {
        const int32_t *v;
        e = CLOTH__ELEMENT(0);
        v = w->spring_v + 2 * e;
        if (w->spring_limit[e] > 0) {
            /* a limiter below its limit (most of them) adds nothing: cloth_strain_limit_energy's
               own test, without its zeroed gradient and Hessian, and the limiter skipped */
            cloth_real dv[3];
            cloth__v3_sub(x + 3 * (size_t)v[0], x + 3 * (size_t)v[1], dv);
            if (!(cloth__v3_norm(dv) > (1 + w->spring_limit[e]) * w->spring_rest[e])) {
                CLOTH__ENERGY(0, v[0], off + (size_t)e);
                continue;
            }
        }
        if (w->spring_limit[e] > 0)
            en = cloth_strain_limit_energy(x + 3 * (size_t)v[0], x + 3 * (size_t)v[1], w->spring_k[e], w->spring_rest[e],
                                           w->spring_limit[e], gp, hp);
        else
            en = cloth_spring_energy(x + 3 * (size_t)v[0], x + 3 * (size_t)v[1], w->spring_k[e], w->spring_rest[e], gp, hp,
                                     CLOTH_HESSIAN_PROJECTED);
        CLOTH__ENERGY(en, v[0], off + (size_t)e);
        if (grad) cloth__add_element_gradient(grad, v, 2, g, lo, hi);
        if (assemble) cloth__add_element_hessian(w->matrix.value, w->spring_block + 4 * e, v, 2, hess, 1, lo, hi);
        if (damping && w->spring_beta[e] > 0)
            cloth__add_element_hessian(damping, w->spring_block + 4 * e, v, 2, hess, w->spring_beta[e], lo, hi);
    }
    off += (size_t)w->spring_count;
    for (idx = 0; idx < part->count[1]; ++idx) {
        const int32_t *v;
        e = CLOTH__ELEMENT(1);
        v = w->membrane_v + 3 * e;
        en = cloth__membrane_terms(x + 3 * (size_t)v[0], x + 3 * (size_t)v[1], x + 3 * (size_t)v[2], w->membrane_rest + e,
                                   w->membrane_stiffness + e, gp, hp, CLOTH_HESSIAN_PROJECTED);
        CLOTH__ENERGY(en, v[0], off + (size_t)e);
        if (grad) cloth__add_element_gradient(grad, v, 3, g, lo, hi);
        if (assemble) cloth__add_triangle_blocks(w->matrix.value, w->membrane_block + 9 * e, v, hess, 1, lo, hi);
        if (damping && w->membrane_beta[e] > 0)
            cloth__add_triangle_blocks(damping, w->membrane_block + 9 * e, v, hess, w->membrane_beta[e], lo, hi);
    }
    off += (size_t)w->membrane_count;
    for (idx = 0; idx < part->count[2]; ++idx) {
        const int32_t *v;
        cloth__bend_terms b;
        int a;
        e = CLOTH__ELEMENT(2);
        v = w->bend_v + 4 * e;
        /* cloth_bending_energy's terms, its projected Hessian 2 k grad grad^T scattered as the
           rank-one product it is */
        cloth__bending_terms(x + 3 * (size_t)v[0], x + 3 * (size_t)v[1], x + 3 * (size_t)v[2], x + 3 * (size_t)v[3],
                             w->bend_rest + e, w->bend_k[e], !grad && !hp, &b);
        CLOTH__ENERGY(b.energy, cloth__first_vertex(v, 4), off + (size_t)e);
        if (!b.ok) continue;
        if (grad) {
            for (a = 0; a < 12; ++a) g[a] = 2 * b.k * b.dtheta * b.grad[a];
            cloth__add_element_gradient(grad, v, 4, g, lo, hi);
        }
        if (w->bend_lumped[e] == 1) {
            if (assemble) cloth__add_hinge_lumped(w->matrix.value, w->bend_block + 16 * e, v, b.grad, 2 * b.k, lo, hi);
            if (damping && w->bend_beta[e] > 0)
                cloth__add_hinge_lumped(damping, w->bend_block + 16 * e, v, b.grad, w->bend_beta[e] * (2 * b.k), lo, hi);
            continue;
        }
        if (assemble) cloth__add_element_rank_one(w->matrix.value, w->bend_block + 16 * e, v, 4, b.grad, 2 * b.k, lo, hi);
        if (damping && w->bend_beta[e] > 0)
            cloth__add_element_rank_one(damping, w->bend_block + 16 * e, v, 4, b.grad, w->bend_beta[e] * (2 * b.k), lo, hi);
    }
    off += (size_t)w->bend_count;
    for (idx = 0; idx < part->count[3]; ++idx) {
        /* quadratic bending, E = 1/2 sum_m |k_m|^2 with k_m = sum_a w_am x_a: gradient sum_m w_am k_m,
           Hessian blocks sum_m w_am w_bm I */
        int32_t s, n, a;
        const int32_t *v;
        const cloth_real *c;
        cloth_real k[3][3];
        int m;
        e = CLOTH__ELEMENT(3);
        s = w->qbend_start[e];
        n = w->qbend_start[e + 1] - s;
        v = w->qbend_v + s;
        c = w->qbend_w + 3 * (size_t)s;
        {
            /* the nine sums in registers, each in the order of a (the compiler cannot keep an
               array's entries there across the stores) */
            cloth_real k00 = 0, k01 = 0, k02 = 0, k10 = 0, k11 = 0, k12 = 0, k20 = 0, k21 = 0, k22 = 0;
            for (a = 0; a < n; ++a) {
                const cloth_real *xa = x + 3 * (size_t)v[a], *ca = c + 3 * a;
                k00 += ca[0] * xa[0]; k01 += ca[0] * xa[1]; k02 += ca[0] * xa[2];
                k10 += ca[1] * xa[0]; k11 += ca[1] * xa[1]; k12 += ca[1] * xa[2];
                k20 += ca[2] * xa[0]; k21 += ca[2] * xa[1]; k22 += ca[2] * xa[2];
            }
            k[0][0] = k00; k[0][1] = k01; k[0][2] = k02;
            k[1][0] = k10; k[1][1] = k11; k[1][2] = k12;
            k[2][0] = k20; k[2][1] = k21; k[2][2] = k22;
            for (m = 0; m < 3; ++m)
                CLOTH__ENERGY(cloth__v3_dot(k[m], k[m]) / 2, cloth__first_vertex(v, n), off + 3 * (size_t)e + (size_t)m);
            if (grad)
                for (a = 0; a < n; ++a) {
                    const cloth_real *ca = c + 3 * a;
                    cloth_real *ga = grad + 3 * (size_t)v[a];
                    if (v[a] < lo || v[a] >= hi) continue;
                    ga[0] += ca[0] * k00 + ca[1] * k10 + ca[2] * k20;
                    ga[1] += ca[0] * k01 + ca[1] * k11 + ca[2] * k21;
                    ga[2] += ca[0] * k02 + ca[1] * k12 + ca[2] * k22;
                }
        }
        /* the Hessian is constant: the matrix starts from it (w->qbend_diagonal, above) */
        if (damping && w->qbend_beta[e] > 0) cloth__add_qbend_hessian(w, e, damping, 9, w->qbend_beta[e], lo, hi);
    }
    off += 3 * (size_t)w->qbend_count;
    for (idx = 0; idx < part->count[4]; ++idx) {
        /* E = k/2 |gap|^2, gap = sum_a w_a x_a: gradient k w_a gap, Hessian blocks k w_a w_b I */
        const cloth__tie *t;
        cloth_real gap[3];
        int a, b;
        e = CLOTH__ELEMENT(4);
        t = CLOTH__TIES(w) + e;
        cloth__tie_gap(t, x, gap);
        CLOTH__ENERGY(t->k / 2 * cloth__v3_dot(gap, gap), cloth__first_vertex(t->v, 4), off + (size_t)e);
        for (a = 0; a < 4; ++a) {
            if (t->v[a] < 0 || t->v[a] < lo || t->v[a] >= hi) continue;
            if (grad) {
                grad[3 * (size_t)t->v[a]] += t->k * t->w[a] * gap[0];
                grad[3 * (size_t)t->v[a] + 1] += t->k * t->w[a] * gap[1];
                grad[3 * (size_t)t->v[a] + 2] += t->k * t->w[a] * gap[2];
            }
            if (assemble)
                for (b = 0; b < 4; ++b) {
                    cloth_real *dst;
                    if (t->v[b] < 0) continue;
                    dst = w->matrix.value + 9 * (size_t)w->tie_block[16 * e + 4 * a + b];
                    dst[0] += t->k * t->w[a] * t->w[b];
                    dst[4] += t->k * t->w[a] * t->w[b];
                    dst[8] += t->k * t->w[a] * t->w[b];
                }
        }
    }
    off += (size_t)w->ties.count;
    for (idx = 0; idx < part->count[5]; ++idx) {
        const cloth__tie *t;
        int32_t i;
        e = CLOTH__ELEMENT(5);
        t = CLOTH__ATTACH(w) + e;
        i = t->v[0];
        en = cloth_attachment_energy(x + 3 * (size_t)i, CLOTH__ATTACH_POINT(w) + 3 * e, t->k, gp, hp);
        CLOTH__ENERGY(en, i, off + (size_t)e);
        if (i < lo || i >= hi) continue;
        if (grad) { grad[3 * (size_t)i] += g[0]; grad[3 * (size_t)i + 1] += g[1]; grad[3 * (size_t)i + 2] += g[2]; }
        if (assemble) {
            cloth_real *dst = w->matrix.value + 9 * (size_t)w->attach_block[e];
            int k;
            for (k = 0; k < 9; ++k) dst[k] += hess[k];
        }
    }
#undef CLOTH__ELEMENT
#undef CLOTH__ENERGY
    return sum;
}

/* The element counts per kind (quadratic bending stencils once, not their three terms). */
static void cloth__element_counts(const cloth_world *w, int32_t *count)
{
    count[0] = w->spring_count;
    count[1] = w->membrane_count;
    count[2] = w->bend_count;
    count[3] = w->qbend_count;
    count[4] = w->ties.count;
    count[5] = w->attachments.count;
}

/* The vertices of element e of a kind (NULL entries of a tie are -1); *k gets their number. */
static const int32_t *cloth__element_vertices(const cloth_world *w, int kind, int32_t e, int32_t *k)
{
    switch (kind) {
    case 0: *k = 2; return w->spring_v + 2 * e;
    case 1: *k = 3; return w->membrane_v + 3 * e;
    case 2: *k = 4; return w->bend_v + 4 * e;
    case 3: *k = w->qbend_start[e + 1] - w->qbend_start[e]; return w->qbend_v + w->qbend_start[e];
    case 4: *k = 4; return CLOTH__TIES(w)[e].v;
    default: *k = 1; return CLOTH__ATTACH(w)[e].v;
    }
}

/* The part of the parallel assembly's partition that holds vertex v. */
static int32_t cloth__part_of(const cloth_world *w, int32_t v)
{
    int32_t p = 0;
    while (v >= w->elastic_parts[p].hi) ++p;
    return p;
}

/* The parallel assembly's partition (a world with a pool): one part per thread, rows split
   evenly, each with the elements that touch its rows in increasing order, and room for the
   per-element energy terms. Made when the element lists are (re)built. */
static cloth_result cloth__elastic_parts_build(cloth_world *w)
{
    const cloth_allocator *a = &w->allocator;
    const int32_t parts = cloth__pool_threads(w->pool), n = w->vertex_count;
    int32_t count[CLOTH__KINDS], p, kind, e, k, q, pass;
    size_t total = 0, terms;
    if (parts < 2 || n < parts) return CLOTH_SUCCESS;
    cloth__element_counts(w, count);
    w->elastic_parts = (cloth__elastic_part *)cloth__alloc_array(a, (size_t)parts, sizeof(cloth__elastic_part));
    if (!w->elastic_parts) return CLOTH_ERROR_OUT_OF_MEMORY;
    memset(w->elastic_parts, 0, (size_t)parts * sizeof(cloth__elastic_part));
    w->elastic_part_count = parts;
    for (p = 0; p < parts; ++p) cloth__part_rows(n, p, parts, &w->elastic_parts[p].lo, &w->elastic_parts[p].hi);
    /* pass 0 counts, pass 1 fills: element e joins every part that holds one of its vertices */
    for (pass = 0; pass < 2; ++pass) {
        size_t at = 0;
        for (kind = 0; kind < CLOTH__KINDS; ++kind)
            for (p = 0; p < parts; ++p) {
                cloth__elastic_part *part = w->elastic_parts + p;
                if (pass == 1) { part->list[kind] = w->elastic_list + at; at += (size_t)part->count[kind]; }
                part->count[kind] = 0;
            }
        for (kind = 0; kind < CLOTH__KINDS; ++kind)
            for (e = 0; e < count[kind]; ++e) {
                const int32_t *v = cloth__element_vertices(w, kind, e, &k);
                int32_t last = -1;
                /* the parts of the vertices, each once (p increasing) */
                for (;;) {
                    int32_t next = parts;
                    for (q = 0; q < k; ++q)
                        if (v[q] >= 0) {
                            int32_t pq = cloth__part_of(w, v[q]);
                            if (pq > last && pq < next) next = pq;
                        }
                    if (next == parts) break;
                    if (pass == 1) w->elastic_parts[next].list[kind][w->elastic_parts[next].count[kind]] = e;
                    w->elastic_parts[next].count[kind]++;
                    last = next;
                }
            }
        if (pass == 0) {
            for (kind = 0; kind < CLOTH__KINDS; ++kind)
                for (p = 0; p < parts; ++p) total += (size_t)w->elastic_parts[p].count[kind];
            w->elastic_list = (int32_t *)cloth__alloc_array(a, total, sizeof(int32_t));
            if (!w->elastic_list) return CLOTH_ERROR_OUT_OF_MEMORY;
        }
    }
    terms = (size_t)count[0] + (size_t)count[1] + (size_t)count[2] + 3 * (size_t)count[3] + (size_t)count[4] + (size_t)count[5];
    w->elastic_energy = (cloth_real *)cloth__alloc_array(a, terms, sizeof(cloth_real));
    if (!w->elastic_energy) return CLOTH_ERROR_OUT_OF_MEMORY;
    w->elastic_terms = terms;
    return CLOTH_SUCCESS;
}

typedef struct cloth__elastic_job {
    cloth_world *w;
    const cloth_real *x;
    cloth_real *grad, *damping;
    int assemble;
} cloth__elastic_job;

static void cloth__elastic_task(void *context, int32_t part)
{
    const cloth__elastic_job *job = (const cloth__elastic_job *)context;
    cloth__elastic_part_run(job->w, job->x, job->grad, job->assemble, job->damping, job->w->elastic_parts + part,
                            job->w->elastic_energy);
}

/* ---- contact springs (def.proximity_stiffness) -----------------------------------------

   Each spring is an impact row of an earlier collide phase between cloth and cloth or cloth
   and a mesh obstacle: weights w_k on four vertices (a mesh obstacle's at its pose at the end
   of the substep being solved, fixed), a normal n and a thickness t. With
   s = n . sum_k w_k x_k its energy is E = k/2 (t - s)^2 while s < t (nothing beyond), k = stiffness m / h^2, where
   m = 1 / sum_k (w_k^2 / m_k) is the pair's mass along n (movable vertices only) and h the
   solve's step: the spring is as strong as stiffness times the pair's inertia, whatever the
   mass and step. The gradient is exact. The Hessian k (w n)(w n)^T couples vertices the
   matrix's fixed pattern does not; the solve gets the diagonal majorant
   k |w_i| (sum_j |w_j|) n n^T instead (w w^T <= diag(|w_i| sum_j |w_j|)), which keeps the
   linearized step a descent step of the spring for any k: with k large the pair's
   separation deficit is made up in one step. */

/* Where a spring's node is: a cloth vertex in x, or a mesh obstacle's vertex where the contact
   module has it at the end of the substep. */
static const cloth_real *cloth__prox_point(const cloth_world *w, const cloth_real *x, int32_t node)
{
    const cloth_real *p0, *p1;
    if (node < w->vertex_count) return x + 3 * (size_t)node;
    cloth__contact_node(w->contact, node, &p0, &p1);
    return p1;
}

/* The springs' energy at x; their gradient into grad and their majorant into the matrix's
   diagonal blocks when asked. */
static double cloth__prox_term(cloth_world *w, const cloth_real *x, cloth_real *grad, int assemble)
{
    double energy = 0, h2 = (double)w->prox_h * (double)w->prox_h;
    int32_t p;
    for (p = 0; p < w->prox_count; ++p) {
        const cloth__prox_pair *q = w->prox + p;
        double sep = 0, inv = 0, wsum = 0, k, deficit, f;
        int j, r, c;
        for (j = 0; j < 4; ++j) {
            int32_t v = q->vertex[j];
            double wj = (double)q->weight[j];
            const cloth_real *y = cloth__prox_point(w, x, v);
            sep += wj * ((double)q->normal[0] * (double)y[0] + (double)q->normal[1] * (double)y[1] + (double)q->normal[2] * (double)y[2]);
            wsum += fabs(wj);
            if (v < w->vertex_count && w->mass[v] > 0 && !w->constrained[v]) inv += wj * wj / (double)w->mass[v]; /* movable */
        }
        deficit = (double)q->thickness - sep;
        if (!(deficit > 0) || !(inv > 0)) continue;
        k = (double)w->def.proximity_stiffness / (inv * h2);
        energy += 0.5 * k * deficit * deficit;
        for (j = 0; j < 4; ++j) {
            int32_t v = q->vertex[j];
            double wj = (double)q->weight[j];
            if (v >= w->vertex_count) continue; /* an obstacle's vertex */
            if (grad) {
                f = -k * deficit * wj;
                for (r = 0; r < 3; ++r) grad[3 * (size_t)v + r] += (cloth_real)(f * (double)q->normal[r]);
            }
            if (assemble) {
                cloth_real *blk = w->matrix.value + 9 * (size_t)w->matrix.diagonal[v];
                f = k * fabs(wj) * wsum;
                for (r = 0; r < 3; ++r)
                    for (c = 0; c < 3; ++c) blk[3 * r + c] += (cloth_real)(f * (double)q->normal[r] * (double)q->normal[c]);
            }
        }
    }
    return energy;
}

static uint32_t cloth__prox_hash(const int32_t *v, int32_t edge_edge)
{
    uint32_t h = 2166136261u ^ (uint32_t)edge_edge;
    int j;
    for (j = 0; j < 4; ++j) h = (h ^ (uint32_t)v[j]) * 16777619u;
    return h;
}

/* The slot of the spring on these vertices, or of the empty slot where it would go. */
static int32_t cloth__prox_find(const cloth_world *w, const int32_t *v, int32_t edge_edge)
{
    uint32_t mask = (uint32_t)(2 * (size_t)w->prox_capacity), i = cloth__prox_hash(v, edge_edge) % mask;
    for (;; i = (i + 1) % mask) {
        int32_t e = w->prox_slot[i];
        const cloth__prox_pair *q;
        if (e < 0) return (int32_t)i;
        q = w->prox + e;
        if (q->edge_edge == edge_edge && q->vertex[0] == v[0] && q->vertex[1] == v[1] && q->vertex[2] == v[2] && q->vertex[3] == v[3])
            return (int32_t)i;
    }
}

/* Closest points of the spring's primitives at x: its weights, and its normal when they are
   apart enough to give one (it keeps its side: the collide phase never lets a pair cross).
   Returns their distance. */
static double cloth__prox_refresh(const cloth_world *w, cloth__prox_pair *q, const cloth_real *x)
{
    const cloth_real *p[4];
    double d[3], len;
    int j, k;
    for (j = 0; j < 4; ++j) p[j] = cloth__prox_point(w, x, q->vertex[j]);
    cloth__contact_closest_weights(q->edge_edge, p, q->weight, d);
    len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (len > 0.25 * (double)q->thickness &&
        d[0] * (double)q->normal[0] + d[1] * (double)q->normal[1] + d[2] * (double)q->normal[2] > 0)
        for (k = 0; k < 3; ++k) q->normal[k] = (cloth_real)(d[k] / len);
    return len;
}

/* After a collide phase: the springs whose pairs are still within twice their thickness stay
   (refreshed), and the phase's impact rows become springs (an existing one takes the row's
   normal); beyond the fixed budget new rows are left out. */
static void cloth__prox_update(cloth_world *w)
{
    const cloth_contact *c = w->contact;
    const cloth__contact_impact *row = CLOTH__CONTACT_AT(c->impacts, cloth__contact_impact);
    int32_t p, kept = 0, k;
    memset(w->prox_slot, 0xff, 2 * (size_t)w->prox_capacity * sizeof(int32_t)); /* every slot -1 */
    for (p = 0; p < w->prox_count; ++p) {
        cloth__prox_pair q = w->prox[p];
        if (!(cloth__prox_refresh(w, &q, w->x) <= 2 * (double)q.thickness)) continue;
        w->prox[kept] = q;
        w->prox_slot[cloth__prox_find(w, q.vertex, q.edge_edge)] = kept;
        ++kept;
    }
    w->prox_count = kept;
    for (k = 0; k < c->impact_count; ++k) {
        const cloth__contact_impact *im = row + k;
        int32_t slot, j, proxy = 0;
        cloth__prox_pair *q;
        /* an analytic obstacle's inner proxy is a last line of defence, not a surface to rest
           on: no springs to it */
        for (j = 0; j < 4; ++j)
            if (im->node[j] >= c->n) proxy |= c->obstacles[cloth__contact_node_obstacle(c, im->node[j])].def.shape != CLOTH_OBSTACLE_MESH;
        if (proxy) continue;
        slot = cloth__prox_find(w, im->node, im->edge_edge);
        if (w->prox_slot[slot] >= 0) {
            q = w->prox + w->prox_slot[slot];
        } else {
            if (w->prox_count >= w->prox_capacity) continue;
            w->prox_slot[slot] = w->prox_count;
            q = w->prox + w->prox_count++;
            for (j = 0; j < 4; ++j) q->vertex[j] = im->node[j];
            q->edge_edge = im->edge_edge;
        }
        for (j = 0; j < 4; ++j) q->weight[j] = im->w[j];
        for (j = 0; j < 3; ++j) q->normal[j] = im->normal[j];
        q->thickness = im->thickness;
    }
}

/* The elastic energy (springs, membranes, bending, seams, attachments) at x. When grad is not
   NULL it receives the gradient (overwritten); when assemble is set the matrix values receive
   the projected Hessian (overwritten); when damping is not NULL it receives (overwritten) the
   stiffness-proportional damping matrix: each element's Hessian times its beta. With a pool the
   parts of the partition run on its threads and the energy terms are added afterwards in the
   serial order: the results are bit-identical to one part over all rows. */
static cloth_real cloth__elastic_parts(cloth_world *w, const cloth_real *x, cloth_real *grad, int assemble, cloth_real *damping)
{
    if (w->elastic_parts) {
        cloth__elastic_job job;
        cloth_real energy = 0;
        size_t t;
        job.w = w;
        job.x = x;
        job.grad = grad;
        job.damping = damping;
        job.assemble = assemble;
        cloth__pool_run(w->pool, w->elastic_part_count, cloth__elastic_task, &job);
        for (t = 0; t < w->elastic_terms; ++t) energy += w->elastic_energy[t];
        return energy;
    } else {
        cloth__elastic_part all;
        int kind;
        all.lo = 0;
        all.hi = w->vertex_count;
        cloth__element_counts(w, all.count);
        for (kind = 0; kind < CLOTH__KINDS; ++kind) all.list[kind] = NULL;
        return cloth__elastic_part_run(w, x, grad, assemble, damping, &all, NULL);
    }
}

/* Every elastic term of the world, and the contact springs during an implicit solve. */
static cloth_real cloth__elastic(cloth_world *w, const cloth_real *x, cloth_real *grad, int assemble, cloth_real *damping)
{
    cloth_real e = cloth__elastic_parts(w, x, grad, assemble, damping);
    /* the parts zero grad and the matrix before they add to them: the springs come after */
    if (w->prox_on) e = (cloth_real)((double)e + cloth__prox_term(w, x, grad, assemble));
    return e;
}

/* The system matrix from the assembled Hessian K (and damping D) in place:
   M + h^2 K (+ h^2 kappa D), row by row: on the pool over the elastic parts' rows when the
   world has them (each row the same bits either way). */
typedef struct cloth__system_job {
    cloth_world *w;
    cloth_real h, kappa;
} cloth__system_job;

static void cloth__system_rows(const cloth__system_job *job, int32_t lo, int32_t hi)
{
    cloth_world *w = job->w;
    const cloth_real h = job->h, kappa = job->kappa;
    const size_t b1 = 9 * (size_t)w->matrix.row_start[hi];
    size_t j;
    int32_t i;
    for (j = 9 * (size_t)w->matrix.row_start[lo]; j < b1; ++j) {
        w->matrix.value[j] *= h * h;
        if (w->need_damping_matrix) w->matrix.value[j] += h * h * kappa * w->damping_value[j];
    }
    for (i = lo; i < hi; ++i) {
        cloth_real *v = w->matrix.value + 9 * (size_t)w->matrix.diagonal[i];
        v[0] += w->mass[i];
        v[4] += w->mass[i];
        v[8] += w->mass[i];
    }
}

static void cloth__system_task(void *context, int32_t part)
{
    const cloth__system_job *job = (const cloth__system_job *)context;
    cloth__system_rows(job, job->w->elastic_parts[part].lo, job->w->elastic_parts[part].hi);
}

static void cloth__system_matrix(cloth_world *w, cloth_real h, cloth_real kappa)
{
    cloth__system_job job;
    job.w = w;
    job.h = h;
    job.kappa = kappa;
    if (w->elastic_parts) cloth__pool_run(w->pool, w->elastic_part_count, cloth__system_task, &job);
    else cloth__system_rows(&job, 0, w->vertex_count);
}

/* Add the velocity-proportional damping that needs no Hessian (air drag, seed 002's relative
   damping over each membrane triangle) to a damping matrix on the pattern. */
static void cloth__add_linear_damping(cloth_world *w, cloth_real *damping)
{
    int32_t i, e;
    for (i = 0; i < w->vertex_count; ++i)
        if (w->drag[i] > 0) {
            cloth_real *d = damping + 9 * (size_t)w->matrix.diagonal[i];
            d[0] += w->drag[i]; d[4] += w->drag[i]; d[8] += w->drag[i];
        }
    for (e = 0; e < w->membrane_count; ++e) {
        cloth_real c = w->membrane_relative_damping[e];
        int a, b;
        if (!(c > 0)) continue;
        /* D = -df/dv = c (3 delta_ab - 1) I */
        for (a = 0; a < 3; ++a)
            for (b = 0; b < 3; ++b) {
                cloth_real *d = damping + 9 * (size_t)w->membrane_block[9 * e + 3 * a + b];
                cloth_real s = c * (cloth_real)(a == b ? 2 : -1);
                d[0] += s; d[4] += s; d[8] += s;
            }
    }
}

/* y = D x with the damping values on the matrix's pattern. */
static void cloth__damping_multiply(cloth_world *w, const cloth_real *x, cloth_real *y)
{
    cloth_block_matrix view = w->matrix;
    view.value = w->damping_value;
    cloth_block_matrix_multiply(&view, x, y);
}

/* Wind forces (explicit, at the current state) into s_wind; zero when the scene has no wind. */
static void cloth__wind_forces(cloth_world *w)
{
    cloth_real wind[3], f[9];
    cloth_aerodynamics air = cloth_default_aerodynamics();
    int32_t t;
    memset(w->s_wind, 0, (size_t)w->vertex_count * 3 * sizeof(cloth_real));
    if (!w->need_wind) return;
    cloth_gust_wind(&w->gust, wind);
    air.air_density = w->def.air_density;
    for (t = 0; t < w->triangle_count; ++t) {
        const cloth__piece *pc = CLOTH__PIECES(w) + w->tri_piece[t];
        const int32_t *v = w->tri + 3 * (size_t)t;
        int a;
        if (!pc->def.wind) continue;
        air.normal_coefficient = pc->def.drag_coefficient;
        cloth_aerodynamic_force(w->x + 3 * (size_t)v[0], w->x + 3 * (size_t)v[1], w->x + 3 * (size_t)v[2], w->v + 3 * (size_t)v[0],
                                w->v + 3 * (size_t)v[1], w->v + 3 * (size_t)v[2], wind, &air, f, NULL);
        for (a = 0; a < 3; ++a) {
            w->s_wind[3 * (size_t)v[a]] += f[3 * a];
            w->s_wind[3 * (size_t)v[a] + 1] += f[3 * a + 1];
            w->s_wind[3 * (size_t)v[a] + 2] += f[3 * a + 2];
        }
    }
}

/* A vertex that does not move on its own: pinned, or massless (referenced by no triangle). */
static int cloth__fixed(const cloth_world *w, int32_t i) { return w->constrained[i] != 0 || !(w->mass[i] > 0); }

/* Targets of pinned vertices at the end of the substep (handles evaluated at time t_end). */
static void cloth__update_handles(cloth_world *w, double t_end)
{
    int32_t h;
    for (h = 0; h < w->handles.count; ++h) {
        const cloth__handle *hd = CLOTH__HANDLES(w) + h;
        hd->position(t_end, w->pin_target + 3 * (size_t)hd->vertex, hd->user);
    }
}

/* The incremental potential at x (see cloth_integrator), given the elastic energy there.
   Uses s_phi and s_tmp as scratch. */
static double cloth__incremental_potential(cloth_world *w, const cloth_real *x, cloth_real elastic, cloth_real h_eff, cloth_real kappa)
{
    double inertia = 0, dissipation = 0;
    int32_t i;
    for (i = 0; i < w->vertex_count; ++i) {
        int k;
        if (cloth__fixed(w, i)) continue;
        for (k = 0; k < 3; ++k) {
            double d = (double)x[3 * (size_t)i + k] - (double)w->s_xhat[3 * (size_t)i + k];
            inertia += w->mass[i] * d * d;
        }
    }
    if (w->need_damping_matrix) {
        for (i = 0; i < 3 * w->vertex_count; ++i) w->s_phi[i] = x[i] - w->s_xbase[i];
        cloth__damping_multiply(w, w->s_phi, w->s_tmp);
        for (i = 0; i < 3 * w->vertex_count; ++i) dissipation += (double)w->s_phi[i] * w->s_tmp[i];
    }
    return inertia / (2.0 * h_eff * h_eff) + elastic + kappa / 2.0 * dissipation;
}

/* ---- obstacle constraints of the solve (def.obstacle_constraints) ---------------------

   HOLDING. Before the solve, every free vertex whose probe lies inside an analytic obstacle's
   thickness layer (at the obstacle's pose at the end of the substep) is held by the deepest
   such obstacle on a plane n . x = c tangent to the layer. The probe is the vertex's inertial
   target xhat when it touches a layer at the start (x0 closer than 1.01 thickness to the
   obstacle at that same pose, so that a moving obstacle about to reach it counts) or when
   def.obstacle_hold_touching_only is 0, and otherwise xhat without the h^2 a of the
   substep's forces: where its velocity alone takes it (a vertex the cloth holds up just
   above the layer is not pulled onto it, to be released as adhesive). The plane is
   the layer's tangent at the closest point to the probe when its normal there agrees
   with the normal at the start of the step (n(probe) . n(x0) > 1/2), and otherwise the tangent
   at the closest point to x0: for a convex obstacle that plane supports the layer, so a fast
   vertex, or one whose target went past the middle of a thin obstacle, is never held on the
   far side.

   STICK AND SLIP (Coulomb friction inside the solve). A held vertex starts out sticking: the
   solver's filter prescribes its whole update, onto the plane along n and, along the plane,
   to its anchor: where its path from x0 to the probe meets the plane (x0 itself when it starts
   on or below it), carried along by the obstacle's surface from the start of the substep to
   its end (nothing for a static obstacle). After a solve
   of A dx = b the constraint force that held vertex i is r_i = (A dx - b)_i (h_eff^2 times a
   force, since A = M + h_eff^2 K and b = h_eff^2 f): its normal part lambda = r_i . n, its
   tangential part r_t = r_i - lambda n. Then
     * lambda < 0 (beyond a hundredth of the vertex's weight, so that solver rounding does not
       release vertices at rest): the plane pulled the vertex towards the obstacle; it is
       released for the rest of the substep (the Baraff-Witkin rule), in stages and never
       unchecked. While two more solves may follow, a vertex that sticks (and has not slipped
       in this substep) first slips, without friction (mu lambda bounds none), and one that
       slips is released. After the solve before the last, none is released: adhesive vertices
       stay held along n (those sticking slip, once a substep as below; a release there went
       into the last solve, whose result no solve checks, and threw free vertices off the
       layer: 15 mm on the sphere drape). After
       the last solve a release holds for the next substep, whose inertial target does not
       hold the vertex again;
     * a sticking vertex with |r_t| > mu_s lambda slips: only its normal stays prescribed, and
       the kinetic friction force mu_k lambda r_t / |r_t| (along the force that held it, which
       opposes the motion it would make) joins the right-hand side;
     * a slipping vertex that ends the solve on the friction force's side of its anchor
       (friction overshot: it would slide backwards) sticks again;
     * a vertex starts slipping at most once per substep (no chatter at the edge of the
       friction cone: one that sticks again stays stuck, which friction can always do);
   and vertices the solve moved into a layer (probe x + dx) are held. While the held set or a
   state changes, the linearized integrator solves its linear system again under the new
   constraints, warm-started from the last solution (at most def.obstacle_iterations solves in
   all; the system is not re-linearized at the last solution: a Newton step from there has no
   line search, and where the membrane is compressed it threw vertices centimetres off the
   surface), and the Newton integrators do not stop; the states carry over from iteration to
   iteration. With def.obstacle_trial_tolerance the linearized integrator's first solve is a
   looser trial from which the states are decided, and one more solve at the CG tolerance
   always follows it. */

/* A vertex at x touches an analytic obstacle's layer: closer than 1.01 times its thickness. */
static int cloth__touches_layer(const cloth_world *w, const cloth_real *x)
{
    int32_t o;
    for (o = 0; o < w->obstacles.count; ++o) {
        const cloth__obstacle *ob = CLOTH__OBSTACLES(w) + o;
        cloth_real n[3], reach = ob->def.thickness * (cloth_real)1.01;
        if (ob->def.shape == CLOTH_OBSTACLE_MESH || cloth__contact_obstacle_far(w->contact, o, x, reach)) continue;
        if (cloth_contact_obstacle_distance(w->contact, o, x, n) < reach) return 1;
    }
    return 0;
}

/* Hold the free vertices i0 .. i1 - 1 not held yet whose probe position (3 per vertex) lies
   in a layer, sticking; the number newly held. Vertices released in this substep
   (s_held = -2) stay free. With touching_probe, a vertex touching a layer at x0 is probed
   there instead. */
static int32_t cloth__hold_rows(cloth_world *w, const cloth_real *probe, const cloth_real *touching_probe, int32_t i0,
                                int32_t i1)
{
    int32_t i, o, held = 0;
    for (i = i0; i < i1; ++i) {
        cloth_real *dir = w->s_direction + 6 * (size_t)i, *anchor = w->s_anchor + 3 * (size_t)i;
        const cloth_real *pi = probe + 3 * (size_t)i, *x0 = w->s_x0 + 3 * (size_t)i;
        double deepest = 0, plane_n[3] = { 0, 0, 0 }, plane_c = 0;
        int32_t best = -1;
        int k;
        if (w->s_fixed[i] || w->s_held[i] != -1) continue;
        if (touching_probe && cloth__touches_layer(w, x0)) pi = touching_probe + 3 * (size_t)i;
        for (o = 0; o < w->obstacles.count; ++o) {
            const cloth__obstacle *ob = CLOTH__OBSTACLES(w) + o;
            cloth_real n1[3], n0[3], s1, s0;
            double th = (double)ob->def.thickness;
            if (ob->def.shape == CLOTH_OBSTACLE_MESH || cloth__contact_obstacle_far(w->contact, o, pi, th)) continue;
            s1 = cloth_contact_obstacle_distance(w->contact, o, pi, n1);
            if (!((double)s1 < th) || !(th - (double)s1 > deepest)) continue;
            s0 = cloth_contact_obstacle_distance(w->contact, o, x0, n0);
            deepest = th - (double)s1;
            best = o;
            if (cloth__v3_dot(n1, n0) > (cloth_real)0.5) {
                for (k = 0; k < 3; ++k) plane_n[k] = (double)n1[k];
                plane_c = (double)cloth__v3_dot(n1, pi) + th - (double)s1;
            } else {
                for (k = 0; k < 3; ++k) plane_n[k] = (double)n0[k];
                plane_c = (double)cloth__v3_dot(n0, x0) + th - (double)s0;
            }
        }
        if (best < 0) continue;
        for (k = 0; k < 3; ++k) {
            dir[k] = (cloth_real)plane_n[k];
            dir[3 + k] = 0;
        }
        {
            /* the anchor: where the path x0 -> probe meets the plane (x0 itself when it starts
               on or below it), carried by the surface from pose s0 to pose s1 */
            const cloth__obstacle *ob = CLOTH__OBSTACLES(w) + best;
            double above = (double)cloth__v3_dot(dir, x0) - plane_c, fall = 0, t = 0;
            cloth_real entry[3], local[3];
            for (k = 0; k < 3; ++k) fall += (double)dir[k] * ((double)pi[k] - (double)x0[k]);
            if (above > 0 && fall < 0) t = above / -fall;
            if (t > 1) t = 1;
            for (k = 0; k < 3; ++k) entry[k] = (cloth_real)((double)x0[k] + t * ((double)pi[k] - (double)x0[k]));
            cloth_pose_apply_inverse(&ob->s0, entry, local);
            cloth_pose_apply(&ob->s1, local, anchor);
        }
        w->s_plane[i] = (cloth_real)plane_c;
        w->s_fixed[i] = 3;
        w->s_held[i] = best;
        w->s_friction[3 * (size_t)i] = w->s_friction[3 * (size_t)i + 1] = w->s_friction[3 * (size_t)i + 2] = 0;
        held++;
    }
    return held;
}

/* The same over the world's pool: each vertex decides alone (the obstacles' distance queries
   only read), the counts summed per part. */
typedef struct cloth__hold_job {
    cloth_world *w;
    const cloth_real *probe, *touching_probe;
    int32_t parts;
    int32_t held[CLOTH__MAX_THREADS];
} cloth__hold_job;

static void cloth__hold_task(void *context, int32_t part)
{
    cloth__hold_job *job = (cloth__hold_job *)context;
    int32_t lo, hi;
    cloth__part_rows(job->w->vertex_count, part, job->parts, &lo, &hi);
    job->held[part] = cloth__hold_rows(job->w, job->probe, job->touching_probe, lo, hi);
}

static int32_t cloth__hold_on_obstacles(cloth_world *w, const cloth_real *probe, const cloth_real *touching_probe)
{
    cloth__hold_job job;
    int32_t p, held = 0;
    job.w = w;
    job.probe = probe;
    job.touching_probe = touching_probe;
    job.parts = cloth__pool_threads(w->pool);
    cloth__pool_run(w->pool, job.parts, cloth__hold_task, &job);
    for (p = 0; p < job.parts; ++p) held += job.held[p];
    return held;
}

/* The filter's values for the held vertices at the iterate x: the update that puts each on
   its plane and, when it sticks, at its anchor along the plane. */
static void cloth__hold_values(cloth_world *w, const cloth_real *x)
{
    int32_t i;
    for (i = 0; i < w->vertex_count; ++i) {
        cloth_real *z = w->s_value + 3 * (size_t)i;
        const cloth_real *n = w->s_direction + 6 * (size_t)i, *xi = x + 3 * (size_t)i;
        cloth_real gap;
        int k;
        if (w->s_held[i] < 0) { z[0] = z[1] = z[2] = 0; continue; }
        gap = w->s_plane[i] - cloth__v3_dot(n, xi);
        if (w->s_fixed[i] == 3) {
            const cloth_real *anchor = w->s_anchor + 3 * (size_t)i;
            cloth_real d[3], dn;
            for (k = 0; k < 3; ++k) d[k] = anchor[k] - xi[k];
            dn = cloth__v3_dot(d, n);
            for (k = 0; k < 3; ++k) z[k] = d[k] - dn * n[k] + gap * n[k];
        } else
            for (k = 0; k < 3; ++k) z[k] = gap * n[k];
    }
}

/* Add the kinetic friction forces of the slipping vertices to the right-hand side. */
static void cloth__add_friction(cloth_world *w)
{
    int32_t i;
    for (i = 0; i < w->vertex_count; ++i)
        if (w->s_held[i] >= 0 && w->s_fixed[i] == 1) {
            int k;
            for (k = 0; k < 3; ++k) w->s_rhs[3 * (size_t)i + k] += w->s_friction[3 * (size_t)i + k];
        }
}

/* After a solve: release, slip and re-stick as described above; the number of changes.
   solves_left: how many more solves the substep allows after this one. *released counts the
   releases. */
static int32_t cloth__update_holds_rows(cloth_world *w, cloth_real h_eff, int32_t solves_left, int32_t i0, int32_t i1,
                                        int32_t *released)
{
    const cloth_block_matrix *A = &w->matrix;
    double g = (double)cloth__v3_norm(w->def.gravity);
    int32_t i, b, changes = 0;
    *released = 0;
    for (i = i0; i < i1; ++i) {
        const cloth_real *n = w->s_direction + 6 * (size_t)i;
        cloth_real *fr = w->s_friction + 3 * (size_t)i;
        const cloth__obstacle *ob;
        double r[3], rt[3], lambda, lt;
        int k, c, adhesive;
        if (w->s_held[i] < 0) continue;
        ob = CLOTH__OBSTACLES(w) + w->s_held[i];
        /* r = A dx - b, with b the right-hand side the solve used (friction included) */
        for (k = 0; k < 3; ++k) r[k] = -(double)w->s_rhs[3 * (size_t)i + k];
        for (b = A->row_start[i]; b < A->row_start[i + 1]; ++b) {
            const cloth_real *blk = A->value + 9 * (size_t)b, *d = w->s_dx + 3 * (size_t)A->column[b];
            for (k = 0; k < 3; ++k)
                for (c = 0; c < 3; ++c) r[k] += (double)blk[3 * k + c] * (double)d[c];
        }
        lambda = r[0] * (double)n[0] + r[1] * (double)n[1] + r[2] * (double)n[2];
        for (k = 0; k < 3; ++k) rt[k] = r[k] - lambda * (double)n[k];
        lt = sqrt(rt[0] * rt[0] + rt[1] * rt[1] + rt[2] * rt[2]);
        adhesive = lambda < -0.01 * (double)w->mass[i] * g * (double)h_eff * (double)h_eff;
        /* a release never goes into the last solve unchecked, and while two solves remain a
           vertex that sticks slips (without friction: its normal force is a pull) first */
        if (adhesive && solves_left != 1 && !(solves_left >= 2 && w->s_fixed[i] == 3 && !w->s_switched[i])) {
            w->s_held[i] = -2;
            w->s_fixed[i] = 0;
            (*released)++;
            changes++;
        } else if (w->s_fixed[i] == 3) {
            /* one slip per substep: no stick-slip chatter at the cone's edge */
            if (!w->s_switched[i] && lt > (double)ob->def.friction_static * (lambda > 0 ? lambda : 0)) {
                double f = lt > 0 ? (double)ob->def.friction_kinetic * (lambda > 0 ? lambda : 0) / lt : 0;
                for (k = 0; k < 3; ++k) fr[k] = (cloth_real)(f * rt[k]);
                w->s_fixed[i] = 1;
                w->s_switched[i] = 1;
                changes++;
            }
        } else {
            /* slipping: did its motion from the anchor turn to the friction's side? */
            const cloth_real *d = w->s_dx + 3 * (size_t)i, *xi = w->x + 3 * (size_t)i, *anchor = w->s_anchor + 3 * (size_t)i;
            cloth_real moved[3];
            for (k = 0; k < 3; ++k) moved[k] = xi[k] + d[k] - anchor[k];
            if (cloth__v3_dot(moved, fr) > 0) {
                w->s_fixed[i] = 3;
                changes++;
            } else {
                /* keep the kinetic force in step with the normal force */
                double fl = sqrt((double)cloth__v3_dot(fr, fr)), f;
                f = fl > 0 ? (double)ob->def.friction_kinetic * (lambda > 0 ? lambda : 0) / fl : 0;
                for (k = 0; k < 3; ++k) fr[k] = (cloth_real)(f * (double)fr[k]);
            }
        }
    }
    return changes;
}

/* The same over the world's pool: each vertex decides alone, so any split of the rows gives
   the same states; the counts are summed per part. */
typedef struct cloth__holds_job {
    cloth_world *w;
    cloth_real h_eff;
    int32_t solves_left, parts;
    int32_t changes[CLOTH__MAX_THREADS], released[CLOTH__MAX_THREADS];
} cloth__holds_job;

static void cloth__update_holds_task(void *context, int32_t part)
{
    cloth__holds_job *job = (cloth__holds_job *)context;
    int32_t lo, hi;
    cloth__part_rows(job->w->vertex_count, part, job->parts, &lo, &hi);
    job->changes[part] = cloth__update_holds_rows(job->w, job->h_eff, job->solves_left, lo, hi, job->released + part);
}

static int32_t cloth__update_holds(cloth_world *w, cloth_real h_eff, int32_t solves_left, int32_t *released)
{
    cloth__holds_job job;
    int32_t p, changes = 0;
    job.w = w;
    job.h_eff = h_eff;
    job.solves_left = solves_left;
    job.parts = cloth__pool_threads(w->pool);
    cloth__pool_run(w->pool, job.parts, cloth__update_holds_task, &job);
    *released = 0;
    for (p = 0; p < job.parts; ++p) {
        changes += job.changes[p];
        *released += job.released[p];
    }
    return changes;
}

static cloth_result cloth__implicit_substep(cloth_world *w, cloth_real h, cloth_step_stats *st)
{
    const cloth_real *g = w->def.gravity;
    int bdf2 = w->def.integrator == CLOTH_INTEGRATOR_BDF2 && w->history_valid;
    int iterate = w->def.integrator != CLOTH_INTEGRATOR_BACKWARD_EULER_LINEARIZED;
    cloth_real h_eff = bdf2 ? h * 2 / 3 : h, kappa = bdf2 ? 3 / (2 * h) : 1 / h;
    size_t n3 = (size_t)w->vertex_count * 3, j;
    int32_t i, it;
    cloth_pcg_filter filter;
    cloth_real *x = w->x;
    double t0;
    int converged = 0, trial = 0, keep_hierarchy = 0;
    int32_t held = 0, last_solve = w->def.newton_max_iterations - 1;
    w->prox_h = h_eff;
    if (!iterate && w->def.obstacle_iterations < w->def.newton_max_iterations) last_solve = w->def.obstacle_iterations - 1;
    memcpy(w->s_x0, w->x, n3 * sizeof(cloth_real));
    /* xbase (v = kappa (x - xbase)) and the inertial target xhat */
    for (i = 0; i < w->vertex_count; ++i) {
        int k;
        for (k = 0; k < 3; ++k) {
            size_t q = 3 * (size_t)i + k;
            cloth_real accel = g[k];
            if (w->mass[i] > 0) accel += (w->s_wind[q] + (w->f_ext ? w->f_ext[q] : 0)) / w->mass[i];
            if (bdf2) {
                w->s_xbase[q] = (4 * w->s_x0[q] - w->x_prev[q]) / 3;
                w->s_xhat[q] = w->s_xbase[q] + (cloth_real)2 / 9 * h * (4 * w->v[q] - w->v_prev[q]) + h_eff * h_eff * accel;
            } else {
                w->s_xbase[q] = w->s_x0[q];
                w->s_xhat[q] = w->s_x0[q] + h * w->v[q] + h * h * accel;
            }
            w->s_trial[q] = w->s_xhat[q] - h_eff * h_eff * accel; /* where the velocity alone goes */
        }
    }
    /* the start: where we are, with pinned vertices at their targets */
    for (i = 0; i < w->vertex_count; ++i)
        if (w->constrained[i]) memcpy(x + 3 * (size_t)i, w->pin_target + 3 * (size_t)i, 3 * sizeof(cloth_real));
    /* the solver's filter: pinned vertices, and massless ones (held where they are) */
    for (i = 0; i < w->vertex_count; ++i) w->s_fixed[i] = cloth__fixed(w, i) ? 3 : 0;
    /* vertices held on analytic obstacles (one constrained direction each) */
    if (w->s_held) {
        /* a vertex released in the last substep is held again only when a solve moves it
           into a layer, not on its inertial target alone (no release-and-hold every step) */
        for (i = 0; i < w->vertex_count; ++i) {
            w->s_held[i] = w->s_held[i] == -2 ? -3 : -1;
            w->s_switched[i] = 0;
        }
        if (w->def.obstacle_hold_touching_only) {
            /* the others on their target without the substep's forces (s_trial, below) */
            held = cloth__hold_on_obstacles(w, w->s_trial, w->s_xhat);
        } else {
            held = cloth__hold_on_obstacles(w, w->s_xhat, NULL);
        }
        st->obstacle_constraints += held;
        for (i = 0; i < w->vertex_count; ++i)
            if (w->s_held[i] == -3) w->s_held[i] = -1;
    }
    filter.constrained = w->s_fixed;
    filter.direction = w->s_held ? w->s_direction : NULL;
    filter.value = w->s_held ? w->s_value : NULL;
    for (it = 0; it < w->def.newton_max_iterations; ++it) {
        cloth_real elastic = 0, max_dx = 0, alpha = 1;
        double slope = 0, phi0 = 0;
        cloth_pcg_stats ps;
        cloth_pcg_options cg = w->def.cg;
        const cloth_block_matrix *approximation;
        cloth_result r;
        int32_t holds_changed = 0;
        /* the first solve a trial when the def asks for one and a solve can follow it */
        trial = !iterate && it == 0 && held > 0 && w->def.obstacle_trial_tolerance > w->def.cg.tolerance &&
                w->def.obstacle_iterations > 1 && w->def.newton_max_iterations > 1;
        if (trial) cg.tolerance = w->def.obstacle_trial_tolerance;
        if (keep_hierarchy) cg.multigrid_update = 0; /* the same matrix and constraints as the trial's */
        t0 = cloth__now(w);
        if (iterate || it == 0) {
            elastic = cloth__elastic(w, x, w->s_grad, 1, (it == 0 && w->need_damping_matrix) ? w->damping_value : NULL);
            if (it == 0 && w->need_damping_matrix) cloth__add_linear_damping(w, w->damping_value);
            /* gradient of Phi, and the system matrix h_eff^2 * Hessian of Phi */
            if (w->need_damping_matrix) {
                for (j = 0; j < n3; ++j) w->s_trial[j] = x[j] - w->s_xbase[j];
                cloth__damping_multiply(w, w->s_trial, w->s_tmp);
                for (j = 0; j < n3; ++j) w->s_grad[j] += kappa * w->s_tmp[j];
            }
            for (i = 0; i < w->vertex_count; ++i) {
                const cloth_real m_h2 = w->mass[i] / (h_eff * h_eff);
                int k;
                for (k = 0; k < 3; ++k) {
                    size_t q = 3 * (size_t)i + k;
                    w->s_grad[q] += m_h2 * (x[q] - w->s_xhat[q]);
                }
            }
            cloth__system_matrix(w, h_eff, kappa);
        }
        /* the linearized integrator's later iterations (obstacle constraints changed) solve the
           same linear system again, under the new constraints: no re-linearization */
        for (j = 0; j < n3; ++j) w->s_rhs[j] = -h_eff * h_eff * w->s_grad[j];
        st->time_assembly += cloth__now(w) - t0;
        /* solve */
        t0 = cloth__now(w);
        /* warm start: the first update from the last step's velocity (x1 - x0 ~ h v); the
           linearized integrator's later ones from the last solution, the Newton integrators'
           corrections from 0 */
        if (it == 0)
            for (j = 0; j < n3; ++j) w->s_dx[j] = w->s_fixed[j / 3] == 3 ? 0 : h * w->v[j];
        else if (iterate)
            memset(w->s_dx, 0, n3 * sizeof(cloth_real));
        if (w->s_held) {
            cloth__hold_values(w, x);
            cloth__add_friction(w);
        }
        /* the matrix the preconditioner is made from: the system's, or its lumped copy */
        if (w->pmatrix_map) cloth__world_pmatrix_fill(w);
        approximation = w->pmatrix_map ? &w->pmatrix : &w->matrix;
        if (w->def.cg.preconditioner == CLOTH_PRECONDITIONER_MULTIGRID && !w->pcg.multigrid) {
            /* once per matrix pattern (the workspace is remade when the world is rebuilt); every
               solve then refreshes the hierarchy's values and picks up changed pins */
            r = cloth_pcg_multigrid_setup(&w->pcg, approximation, &filter, &w->def.multigrid);
            if (r != CLOTH_SUCCESS) return r;
        }
        r = cloth_pcg_solve_preconditioned(&w->matrix, approximation, w->s_rhs, w->s_dx, &filter, &cg, &w->pcg, &ps);
        st->cg_iterations += ps.iterations;
        st->cg_residual = ps.residual;
        if (r == CLOTH_ERROR_CG_NOT_CONVERGED)
            cloth__log(&w->def.logger, CLOTH_LOG_WARNING, "cloth: conjugate gradient stopped at %d iterations, residual %g",
                       (int)ps.iterations, (double)ps.residual);
        else if (r != CLOTH_SUCCESS) return r;
        if (w->s_held) {
            /* release the vertices the solve pulled towards their obstacle, switch stick and
               slip, hold those it moved into a layer; any change takes another iteration */
            int32_t released, added;
            holds_changed = cloth__update_holds(w, h_eff, last_solve - it, &released);
            st->obstacle_releases += released;
            for (j = 0; j < n3; ++j) w->s_trial[j] = x[j] + w->s_dx[j];
            added = cloth__hold_on_obstacles(w, w->s_trial, NULL);
            st->obstacle_constraints += added;
            holds_changed += added;
        }
        st->time_solve += cloth__now(w) - t0;
        st->newton_iterations++;
        /* line search on Phi (Newton modes) */
        if (iterate) {
            t0 = cloth__now(w);
            for (j = 0; j < n3; ++j) slope += (double)w->s_grad[j] * w->s_dx[j];
            phi0 = cloth__incremental_potential(w, x, elastic, h_eff, kappa);
            if (slope < 0) {
                int halvings;
                for (halvings = 0; halvings < 30; ++halvings) {
                    double phi;
                    for (j = 0; j < n3; ++j) w->s_trial[j] = x[j] + alpha * w->s_dx[j];
                    phi = cloth__elastic(w, w->s_trial, NULL, 0, NULL);
                    phi = cloth__incremental_potential(w, w->s_trial, (cloth_real)phi, h_eff, kappa);
                    if (phi == phi && phi <= phi0 + 1e-4 * alpha * slope) break; /* NaN: keep halving */
                    alpha /= 2;
                    st->line_search_halvings++;
                }
            }
            st->time_assembly += cloth__now(w) - t0;
        }
        /* the linearized integrator: one solve, or more (at most def.obstacle_iterations) of the
           same system while the obstacle constraints change, and always after a trial; x
           moves once, by the last */
        if (!iterate && (holds_changed || trial) && it + 1 < w->def.obstacle_iterations && it + 1 < w->def.newton_max_iterations) {
            st->obstacle_resolves++;
            keep_hierarchy = trial && holds_changed == 0;
            continue;
        }
        for (j = 0; j < n3; ++j) {
            cloth_real d = alpha * w->s_dx[j];
            x[j] += d;
            if ((d < 0 ? -d : d) > max_dx) max_dx = d < 0 ? -d : d;
        }
        if (!iterate) { converged = 1; break; }
        if (max_dx <= w->def.newton_tolerance * h && holds_changed == 0) { converged = 1; break; }
    }
    if (!converged) {
        st->newton_converged = 0;
        cloth__log(&w->def.logger, CLOTH_LOG_WARNING, "cloth: Newton stopped at %d iterations", (int)w->def.newton_max_iterations);
    }
    /* held vertices slid along tangent planes: put those a curved layer left inside back on
       it along its normal, so that the collide phase (whose friction is for vertices the solve
       did not hold) finds them outside */
    if (w->s_held)
        for (i = 0; i < w->vertex_count; ++i)
            if (w->s_held[i] >= 0) {
                const cloth__obstacle *ob = CLOTH__OBSTACLES(w) + w->s_held[i];
                cloth_real n[3], *xi = x + 3 * (size_t)i, th = ob->def.thickness;
                cloth_real sd = cloth_contact_obstacle_distance(w->contact, w->s_held[i], xi, n);
                if (sd < th) {
                    cloth_real push = (th - sd) + th * (cloth_real)1e-6;
                    xi[0] += push * n[0]; xi[1] += push * n[1]; xi[2] += push * n[2];
                }
            }
    /* velocities, history */
    memcpy(w->x_prev, w->s_x0, n3 * sizeof(cloth_real));
    memcpy(w->v_prev, w->v, n3 * sizeof(cloth_real));
    for (j = 0; j < n3; ++j) w->v[j] = kappa * (x[j] - w->s_xbase[j]);
    for (i = 0; i < w->vertex_count; ++i)
        if (!(w->mass[i] > 0) && !w->constrained[i]) memset(w->v + 3 * (size_t)i, 0, 3 * sizeof(cloth_real));
    w->history_valid = 1;
    return CLOTH_SUCCESS;
}

/* The largest eigenvalue of M^-1 K bounded by Gershgorin's theorem on the projected Hessian at
   the current positions, strain limiters counted as engaged; the stable symplectic step is
   then 2 / sqrt(lambda). */
static cloth_real cloth__stable_step(cloth_world *w)
{
    double lambda = 0;
    int32_t i, e;
    cloth__elastic(w, w->x, NULL, 1, NULL);
    /* a strain limiter idle now may engage before the estimate is made again: its Hessian
       blocks +-k d d^T have absolute row sums of at most sqrt(3) k each, whatever d, so both
       vertices' rows get 2 sqrt(3) k, added to their diagonal entries (the matrix is
       reassembled before any other use) */
    for (e = 0; e < w->spring_count; ++e) {
        const int32_t *v = w->spring_v + 2 * (size_t)e;
        cloth_real d[3], bound = (cloth_real)(2 * 1.7320508075688772) * w->spring_k[e];
        if (!(w->spring_limit[e] > 0)) continue;
        cloth__v3_sub(w->x + 3 * (size_t)v[0], w->x + 3 * (size_t)v[1], d);
        if (cloth__v3_norm(d) > (1 + w->spring_limit[e]) * w->spring_rest[e]) continue; /* engaged: assembled */
        for (i = 0; i < 2; ++i) {
            cloth_real *blk = w->matrix.value + 9 * (size_t)w->matrix.diagonal[v[i]];
            blk[0] += bound;
            blk[4] += bound;
            blk[8] += bound;
        }
    }
    for (i = 0; i < w->vertex_count; ++i) {
        double row[3] = { 0, 0, 0 };
        int32_t b;
        int r, c;
        if (cloth__fixed(w, i)) continue;
        for (b = w->matrix.row_start[i]; b < w->matrix.row_start[i + 1]; ++b)
            for (r = 0; r < 3; ++r)
                for (c = 0; c < 3; ++c) row[r] += fabs((double)w->matrix.value[9 * (size_t)b + 3 * r + c]);
        for (r = 0; r < 3; ++r)
            if (row[r] / w->mass[i] > lambda) lambda = row[r] / w->mass[i];
    }
    return lambda > 0 ? (cloth_real)(2.0 / sqrt(lambda)) : (cloth_real)1e30;
}

static cloth_result cloth__symplectic_substep(cloth_world *w, cloth_real h, cloth_step_stats *st)
{
    size_t n3 = (size_t)w->vertex_count * 3, j;
    int32_t i;
    double t0 = cloth__now(w);
    cloth_real limit;
    if (w->stable_step_age <= 0) {
        w->stable_step = cloth__stable_step(w);
        w->stable_step_age = 32;
    }
    w->stable_step_age--;
    limit = w->stable_step;
    if (h > limit) {
        cloth__log(&w->def.logger, CLOTH_LOG_ERROR, "cloth: symplectic Euler step %g s exceeds the stable step %g s", (double)h, (double)limit);
        return CLOTH_ERROR_UNSTABLE;
    }
    /* forces at x0: -dE/dx + gravity + external + wind - D v */
    cloth__elastic(w, w->x, w->s_grad, 0, w->need_damping_matrix ? w->damping_value : NULL);
    if (w->need_damping_matrix) {
        cloth__add_linear_damping(w, w->damping_value);
        cloth__damping_multiply(w, w->v, w->s_tmp);
        for (j = 0; j < n3; ++j) w->s_grad[j] += w->s_tmp[j];
    }
    memcpy(w->x_prev, w->x, n3 * sizeof(cloth_real));
    memcpy(w->v_prev, w->v, n3 * sizeof(cloth_real));
    for (i = 0; i < w->vertex_count; ++i) {
        int k;
        for (k = 0; k < 3; ++k) {
            size_t q = 3 * (size_t)i + k;
            if (w->constrained[i]) w->v[q] = (w->pin_target[q] - w->x[q]) / h;
            else if (!(w->mass[i] > 0)) w->v[q] = 0;
            else w->v[q] += h * (w->def.gravity[k] + (w->s_wind[q] + (w->f_ext ? w->f_ext[q] : 0) - w->s_grad[q]) / w->mass[i]);
            w->x[q] += h * w->v[q];
        }
        if (w->constrained[i]) memcpy(w->x + 3 * (size_t)i, w->pin_target + 3 * (size_t)i, 3 * sizeof(cloth_real));
    }
    w->history_valid = 1;
    st->time_assembly += cloth__now(w) - t0;
    return CLOTH_SUCCESS;
}

/* After a substep: every number finite, no vertex faster than max_speed. */
static cloth_result cloth__health_check(const cloth_world *w)
{
    size_t n3 = (size_t)w->vertex_count * 3, j;
    cloth_real limit2 = w->def.max_speed * w->def.max_speed;
    int32_t i;
    for (j = 0; j < n3; ++j)
        if (!cloth__is_finite(w->x[j]) || !cloth__is_finite(w->v[j])) return CLOTH_ERROR_NOT_FINITE;
    for (i = 0; i < w->vertex_count; ++i)
        if (cloth__v3_dot(w->v + 3 * (size_t)i, w->v + 3 * (size_t)i) > limit2) return CLOTH_ERROR_UNSTABLE;
    return CLOTH_SUCCESS;
}

/* Obstacles move to their poses (or vertices) at the start and the end of substep s, for the
   solve's obstacle constraints and for the collide phase. Rotations are interpolated over the
   substeps like translations (cloth_pose_interpolate). */
static cloth_result cloth__move_obstacles(cloth_world *w, int substep, int count)
{
    cloth_real f0 = (cloth_real)substep / (cloth_real)count, f1 = (cloth_real)(substep + 1) / (cloth_real)count;
    int32_t o;
    cloth_result r;
    for (o = 0; o < w->obstacles.count; ++o) {
        cloth__obstacle *ob = CLOTH__OBSTACLES(w) + o;
        if (ob->def.shape == CLOTH_OBSTACLE_MESH) {
            size_t k, n3 = 3 * (size_t)ob->def.mesh_vertex_count;
            for (k = 0; k < n3; ++k) {
                ob->mesh_s0[k] = ob->mesh_now[k] + f0 * (ob->mesh_next[k] - ob->mesh_now[k]);
                ob->mesh_s1[k] = ob->mesh_now[k] + f1 * (ob->mesh_next[k] - ob->mesh_now[k]);
            }
            r = cloth_contact_set_obstacle_vertices(w->contact, o, ob->mesh_s0, ob->mesh_s1);
        } else {
            ob->s0 = substep == 0 ? ob->now : cloth_pose_interpolate(&ob->now, &ob->next, f0);
            ob->s1 = substep + 1 == count ? ob->next : cloth_pose_interpolate(&ob->now, &ob->next, f1);
            r = cloth_contact_move_obstacle(w->contact, o, &ob->s0, &ob->s1);
        }
        if (r != CLOTH_SUCCESS) return r;
    }
    return CLOTH_SUCCESS;
}

typedef struct cloth__stretch_job {
    const cloth_world *w;
    const cloth_real *a, *b;
    int32_t parts;
    cloth_real most[CLOTH__MAX_THREADS];
} cloth__stretch_job;

/* Part `part` of every piece's edges. */
static void cloth__max_stretch_task(void *context, int32_t part)
{
    cloth__stretch_job *job = (cloth__stretch_job *)context;
    const cloth_world *w = job->w;
    const cloth_real *a = job->a, *b = job->b;
    cloth_real most = 0;
    int32_t p, e, e0, e1;
    for (p = 0; p < w->pieces.count; ++p) {
        const cloth__piece *pc = CLOTH__PIECES(w) + p;
        cloth__part_rows(pc->edge_count, part, job->parts, &e0, &e1);
        for (e = e0; e < e1; ++e) {
            size_t i = 3 * (size_t)(pc->first_vertex + pc->edge[2 * e]), j = 3 * (size_t)(pc->first_vertex + pc->edge[2 * e + 1]);
            cloth_real d0[3], d1[3], stretch;
            if (!(pc->edge_rest[e] > 0)) continue;
            cloth__v3_sub(a + i, a + j, d0);
            cloth__v3_sub(b + i, b + j, d1);
            stretch = (cloth__v3_norm(d1) - cloth__v3_norm(d0)) / pc->edge_rest[e];
            if (stretch > most) most = stretch;
        }
    }
    job->most[part] = most;
}

/* The most any edge of any piece got longer from positions a to positions b, over its rest
   length (the largest of the parts', on the world's pool: the same whatever the split). */
static cloth_real cloth__max_stretch(const cloth_world *w, const cloth_real *a, const cloth_real *b)
{
    cloth__stretch_job job;
    cloth_real most = 0;
    int32_t p;
    job.w = w;
    job.a = a;
    job.b = b;
    job.parts = cloth__pool_threads(w->pool);
    cloth__pool_run(w->pool, job.parts, cloth__max_stretch_task, &job);
    for (p = 0; p < job.parts; ++p)
        if (job.most[p] > most) most = job.most[p];
    return most;
}

/* Whether a substep from a to b carried a strain limiter's edge past its limit by more than a
   quarter of the limit beyond where the edge started (the linearized step meets a limiter
   only once it is engaged at the step's start, so a fast pull overshoots within the step). */
static int cloth__limiters_overshot(const cloth_world *w, const cloth_real *a, const cloth_real *b)
{
    int32_t e;
    for (e = 0; e < w->spring_count; ++e) {
        const int32_t *v = w->spring_v + 2 * (size_t)e;
        cloth_real limit = w->spring_limit[e], d0[3], d1[3], start, end;
        if (!(limit > 0) || !(w->spring_rest[e] > 0)) continue;
        cloth__v3_sub(b + 3 * (size_t)v[0], b + 3 * (size_t)v[1], d1);
        {
            /* an overshoot needs end > 5/4 limit: an edge clearly shorter (the margin 1e-5
               covers the rounding of either test, in float too) is passed without the roots */
            const double reach = (1 + 1.25 * (double)limit) * (double)w->spring_rest[e];
            if ((double)cloth__v3_dot(d1, d1) < reach * reach * (1 - 1e-5)) continue;
        }
        cloth__v3_sub(a + 3 * (size_t)v[0], a + 3 * (size_t)v[1], d0);
        start = cloth__v3_norm(d0) / w->spring_rest[e] - 1;
        end = cloth__v3_norm(d1) / w->spring_rest[e] - 1;
        if (end - (start > limit ? start : limit) > limit / 4) return 1;
    }
    return 0;
}

/* The collide phase of a substep (obstacles already at their substep poses): the contact
   module makes the motion x_prev -> x collision-free and writes the end-of-step velocities
   (contact impulses and friction included). */
static cloth_result cloth__collide(cloth_world *w, cloth_real h, cloth_step_stats *st)
{
    cloth_contact_stats cs;
    int32_t i;
    cloth_result r;
    for (i = 0; i < w->vertex_count; ++i) w->s_inverse_mass[i] = cloth__fixed(w, i) ? 0 : 1 / w->mass[i];
    memcpy(w->s_trial, w->x, 3 * (size_t)w->vertex_count * sizeof(cloth_real));
    r = cloth_contact_resolve(w->contact, w->x_prev, w->x, w->s_inverse_mass, h, w->v, &cs);
    if (r == CLOTH_SUCCESS && w->prox) cloth__prox_update(w);
    if (r == CLOTH_SUCCESS) {
        for (i = 0; i < w->vertex_count; ++i) {
            cloth_real d[3], len;
            cloth__v3_sub(w->x + 3 * (size_t)i, w->s_trial + 3 * (size_t)i, d);
            len = cloth__v3_norm(d);
            if (len > st->collision_correction) st->collision_correction = len;
        }
        cloth_real stretch = cloth__max_stretch(w, w->s_trial, w->x);
        if (stretch > st->collision_strain) st->collision_strain = stretch;
    }
    st->time_collide += cs.time_total;
    st->time_bvh += cs.time_bvh;
    st->time_ccd += cs.time_ccd;
    st->time_response += cs.time_response;
    st->impacts += cs.impacts;
    st->impact_zones = cs.impact_zones;
    if (cs.largest_zone > st->largest_zone) st->largest_zone = cs.largest_zone;
    st->ccd_rounds += cs.rounds;
    st->qp_iterations += cs.qp_iterations;
    st->rigid_zones += cs.rigid_zones;
    st->frozen_zones += cs.frozen_zones;
    st->obstacle_contacts += cs.obstacle_contacts;
    return r;
}

CLOTH_API cloth_result cloth_world_add_obstacle(cloth_world *w, const cloth_obstacle_def *def, int32_t *index)
{
    const cloth_allocator *a;
    cloth__obstacle ob;
    cloth_contact *probe = NULL;
    cloth_contact_def cd;
    cloth_result r;
    CLOTH_ASSERT(w && def && !w->stepping);
    a = &w->allocator;
    if (index) *index = -1;
    /* validate through the contact module itself, on an empty contact */
    cd = cloth_default_contact_def();
    cd.allocator = w->allocator;
    r = cloth_contact_create(&probe, &cd);
    if (r == CLOTH_SUCCESS) r = cloth_contact_add_obstacle(probe, def, NULL);
    cloth_contact_destroy(probe);
    if (r != CLOTH_SUCCESS) return r;
    memset(&ob, 0, sizeof ob);
    ob.def = *def;
    ob.now = ob.next = def->pose;
    if (def->shape == CLOTH_OBSTACLE_MESH) {
        size_t n3 = 3 * (size_t)def->mesh_vertex_count, t3 = 3 * (size_t)def->mesh_triangle_count, k;
        ob.mesh_x = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
        ob.mesh_now = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
        ob.mesh_next = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
        ob.mesh_tri = (int32_t *)cloth__alloc_array(a, t3, sizeof(int32_t));
        ob.mesh_s0 = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
        ob.mesh_s1 = (cloth_real *)cloth__alloc_array(a, n3, sizeof(cloth_real));
        if (!ob.mesh_x || !ob.mesh_now || !ob.mesh_next || !ob.mesh_tri || !ob.mesh_s0 || !ob.mesh_s1) {
            cloth__free(a, ob.mesh_x); cloth__free(a, ob.mesh_now); cloth__free(a, ob.mesh_next); cloth__free(a, ob.mesh_tri);
            cloth__free(a, ob.mesh_s0); cloth__free(a, ob.mesh_s1);
            return CLOTH_ERROR_OUT_OF_MEMORY;
        }
        memcpy(ob.mesh_x, def->mesh_x, n3 * sizeof(cloth_real));
        memcpy(ob.mesh_tri, def->mesh_tri, t3 * sizeof(int32_t));
        for (k = 0; k < n3; k += 3) cloth_pose_apply(&def->pose, ob.mesh_x + k, ob.mesh_now + k);
        memcpy(ob.mesh_next, ob.mesh_now, n3 * sizeof(cloth_real));
        ob.def.mesh_x = ob.mesh_x;
        ob.def.mesh_tri = ob.mesh_tri;
    }
    r = cloth__array_push(a, &w->obstacles, &ob, sizeof ob);
    if (r != CLOTH_SUCCESS) {
        cloth__free(a, ob.mesh_x); cloth__free(a, ob.mesh_now); cloth__free(a, ob.mesh_next); cloth__free(a, ob.mesh_tri);
        cloth__free(a, ob.mesh_s0); cloth__free(a, ob.mesh_s1);
        return r;
    }
    cloth__world_free_elements(w);
    if (index) *index = w->obstacles.count - 1;
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_set_obstacle_pose(cloth_world *w, int32_t obstacle, const cloth_pose *pose)
{
    int k;
    CLOTH_ASSERT(w && !w->stepping);
    if (obstacle < 0 || obstacle >= w->obstacles.count || !pose) return CLOTH_ERROR_INVALID_ARGUMENT;
    for (k = 0; k < 9; ++k)
        if (!cloth__is_finite(pose->rotation[k])) return CLOTH_ERROR_NOT_FINITE;
    if (!cloth__finite3(pose->translation)) return CLOTH_ERROR_NOT_FINITE;
    CLOTH__OBSTACLES(w)[obstacle].next = *pose;
    if (CLOTH__OBSTACLES(w)[obstacle].def.shape == CLOTH_OBSTACLE_MESH) {
        cloth__obstacle *ob = CLOTH__OBSTACLES(w) + obstacle;
        size_t i, n3 = 3 * (size_t)ob->def.mesh_vertex_count;
        for (i = 0; i < n3; i += 3) cloth_pose_apply(pose, ob->mesh_x + i, ob->mesh_next + i);
    }
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_result cloth_world_set_obstacle_vertices(cloth_world *w, int32_t obstacle, const cloth_real *x)
{
    cloth__obstacle *ob;
    size_t i, n3;
    CLOTH_ASSERT(w && !w->stepping);
    if (obstacle < 0 || obstacle >= w->obstacles.count || !x) return CLOTH_ERROR_INVALID_ARGUMENT;
    ob = CLOTH__OBSTACLES(w) + obstacle;
    if (ob->def.shape != CLOTH_OBSTACLE_MESH) return CLOTH_ERROR_INVALID_ARGUMENT;
    n3 = 3 * (size_t)ob->def.mesh_vertex_count;
    for (i = 0; i < n3; ++i)
        if (!cloth__is_finite(x[i])) return CLOTH_ERROR_NOT_FINITE;
    memcpy(ob->mesh_next, x, n3 * sizeof(cloth_real));
    return CLOTH_SUCCESS;
}

CLOTH_API cloth_real cloth_world_obstacle_distance(cloth_world *w, int32_t obstacle, const cloth_real p[3])
{
    CLOTH_ASSERT(w && p);
    if (obstacle < 0 || obstacle >= w->obstacles.count) return 0;
    if (cloth__world_ready(w) != CLOTH_SUCCESS) return 0;
    return cloth_contact_obstacle_distance(w->contact, obstacle, p, NULL);
}

CLOTH_API cloth_result cloth_world_step(cloth_world *w, cloth_real dt, cloth_step_stats *stats)
{
    cloth_step_stats local;
    cloth_step_stats *st = stats ? stats : &local;
    size_t n3;
    cloth_result r = CLOTH_SUCCESS;
    cloth_gust gust_before;
    double time_before, t_start;
    int64_t steps_before;
    int history_before, s, doublings, first_doublings, lower_try = 0;
    cloth_real h;
    CLOTH_ASSERT(w);
    CLOTH_ASSERT(!w->stepping); /* cloth_world_step is not re-entrant */
    memset(st, 0, sizeof *st);
    st->newton_converged = 1;
    if (!(dt > 0) || !cloth__is_finite(dt)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (w->vertex_count == 0) return CLOTH_ERROR_EMPTY_MESH;
    r = cloth__world_ready(w);
    if (r != CLOTH_SUCCESS) return r;
    w->stepping = 1;
    t_start = cloth__now(w);
    n3 = (size_t)w->vertex_count * 3;
    /* everything a failed step must give back */
    memcpy(w->b_x, w->x, n3 * sizeof(cloth_real));
    memcpy(w->b_v, w->v, n3 * sizeof(cloth_real));
    memcpy(w->b_x_prev, w->x_prev, n3 * sizeof(cloth_real));
    memcpy(w->b_v_prev, w->v_prev, n3 * sizeof(cloth_real));
    if (w->s_held) memcpy(w->b_held, w->s_held, (size_t)w->vertex_count * sizeof(int32_t));
    if (w->prox) {
        memcpy(w->b_prox, w->prox, (size_t)w->prox_count * sizeof(struct cloth__prox_pair));
        w->b_prox_count = w->prox_count;
    }
    gust_before = w->gust;
    time_before = w->time;
    steps_before = w->step_count;
    history_before = w->history_valid;
    /* start from what the last step needed, and try one level below it unless a try failed
       recently (adapt_wait), so that a run of violent steps does not pay for failed attempts
       every time */
    doublings = w->adapt_level > w->def.max_substep_doublings ? w->def.max_substep_doublings : w->adapt_level;
    if (doublings > 0 && w->adapt_wait == 0) {
        --doublings;
        lower_try = 1;
    }
    first_doublings = doublings;
    for (;; ++doublings) {
        int count = w->def.substeps << doublings, retry = 0;
        int adaptive = w->def.integrator != CLOTH_INTEGRATOR_SYMPLECTIC_EULER &&
                       ((w->contact && (w->def.collision_strain_limit > 0 || w->def.step_strain_limit > 0)) ||
                        w->limiter_count > 0) &&
                       doublings < w->def.max_substep_doublings;
        h = dt / (cloth_real)count;
        r = CLOTH_SUCCESS;
        st->collision_correction = st->collision_strain = st->step_strain = 0;
        for (s = 0; s < count && r == CLOTH_SUCCESS; ++s) {
            if (w->need_wind) {
                cloth__wind_forces(w);
                r = cloth_gust_advance(&w->gust, h);
                if (r != CLOTH_SUCCESS) break;
            } else
                memset(w->s_wind, 0, n3 * sizeof(cloth_real));
            cloth__update_handles(w, w->time + (double)h);
            if (w->contact) {
                r = cloth__move_obstacles(w, s, count);
                if (r != CLOTH_SUCCESS) break;
            }
            if (w->def.integrator == CLOTH_INTEGRATOR_SYMPLECTIC_EULER) r = cloth__symplectic_substep(w, h, st);
            else {
                w->prox_on = w->prox_count > 0;
                r = cloth__implicit_substep(w, h, st);
                w->prox_on = 0;
            }
            if (r == CLOTH_SUCCESS && w->contact) r = cloth__collide(w, h, st);
            if (r == CLOTH_SUCCESS) r = cloth__health_check(w);
            if (r == CLOTH_SUCCESS && w->contact) {
                cloth_real stretch = cloth__max_stretch(w, w->x_prev, w->x);
                if (stretch > st->step_strain) st->step_strain = stretch;
            }
            if (r == CLOTH_SUCCESS && adaptive &&
                ((w->def.collision_strain_limit > 0 && st->collision_strain > w->def.collision_strain_limit) ||
                 (w->def.step_strain_limit > 0 && st->step_strain > w->def.step_strain_limit) ||
                 (w->limiter_count > 0 && cloth__limiters_overshot(w, w->x_prev, w->x)))) {
                retry = 1;
                break;
            }
            if (r == CLOTH_SUCCESS) {
                w->time += (double)h;
                w->step_count++;
                st->substeps++;
            }
        }
        if (adaptive && (r == CLOTH_ERROR_COLLISION_UNRESOLVED || r == CLOTH_ERROR_UNSTABLE || r == CLOTH_ERROR_NOT_FINITE))
            retry = 1;
        if (r == CLOTH_SUCCESS && !retry) break;
        /* back to the start of the step: for good (a failure) or for a retry */
        memcpy(w->x, w->b_x, n3 * sizeof(cloth_real));
        memcpy(w->v, w->b_v, n3 * sizeof(cloth_real));
        memcpy(w->x_prev, w->b_x_prev, n3 * sizeof(cloth_real));
        memcpy(w->v_prev, w->b_v_prev, n3 * sizeof(cloth_real));
        if (w->s_held) memcpy(w->s_held, w->b_held, (size_t)w->vertex_count * sizeof(int32_t));
        if (w->prox) {
            memcpy(w->prox, w->b_prox, (size_t)w->b_prox_count * sizeof(struct cloth__prox_pair));
            w->prox_count = w->b_prox_count;
        }
        w->gust = gust_before;
        w->time = time_before;
        w->step_count = steps_before;
        w->history_valid = history_before;
        if (!retry) {
            /* the contact module's obstacles back where the world has them now (the attempt
               left them at its last substep's poses) */
            int32_t o;
            for (o = 0; o < w->obstacles.count && w->contact; ++o) {
                cloth__obstacle *ob = CLOTH__OBSTACLES(w) + o;
                if (ob->def.shape == CLOTH_OBSTACLE_MESH) cloth_contact_set_obstacle_vertices(w->contact, o, ob->mesh_now, ob->mesh_now);
                else cloth_contact_move_obstacle(w->contact, o, &ob->now, &ob->now);
            }
            cloth__log(&w->def.logger, CLOTH_LOG_ERROR, "cloth: step failed (%s); state restored", cloth_result_string(r));
            break;
        }
        st->substeps = 0;
        st->substep_redos++;
    }
    if (r == CLOTH_SUCCESS) {
        int32_t o;
        st->contact_springs = w->prox_count;
        st->substep_doublings = doublings;
        if (lower_try && doublings > first_doublings) {
            /* the lower level failed: after two failed tries in a row, wait 1, 2, then 4
               steps before the next */
            if (w->adapt_failed_tries < 4) ++w->adapt_failed_tries;
            w->adapt_wait = w->adapt_failed_tries < 2 ? 0 : 1 << (w->adapt_failed_tries - 2);
        } else if (lower_try) {
            w->adapt_failed_tries = 0;
        } else if (w->adapt_wait > 0) {
            --w->adapt_wait;
        }
        w->adapt_level = doublings;
        for (o = 0; o < w->obstacles.count; ++o) {
            cloth__obstacle *ob = CLOTH__OBSTACLES(w) + o;
            ob->now = ob->next;
            if (ob->def.shape == CLOTH_OBSTACLE_MESH)
                memcpy(ob->mesh_now, ob->mesh_next, 3 * (size_t)ob->def.mesh_vertex_count * sizeof(cloth_real));
        }
    }
    st->time_total = cloth__now(w) - t_start;
    w->stepping = 0;
    return r;
}

CLOTH_API void cloth_world_energy(cloth_world *w, cloth_real *kinetic, cloth_real *gravitational, cloth_real *elastic)
{
    double ke = 0, pe = 0;
    int32_t i;
    CLOTH_ASSERT(w && !w->stepping);
    for (i = 0; i < w->vertex_count; ++i) {
        ke += 0.5 * w->mass[i] * cloth__v3_dot(w->v + 3 * (size_t)i, w->v + 3 * (size_t)i);
        pe -= w->mass[i] * cloth__v3_dot(w->def.gravity, w->x + 3 * (size_t)i);
    }
    if (kinetic) *kinetic = (cloth_real)ke;
    if (gravitational) *gravitational = (cloth_real)pe;
    if (elastic) {
        *elastic = 0;
        if (cloth__world_ready(w) != CLOTH_SUCCESS) return;
        *elastic = cloth__elastic(w, w->x, NULL, 0, NULL);
    }
}

CLOTH_API cloth_real cloth_world_stable_time_step(cloth_world *w)
{
    CLOTH_ASSERT(w && !w->stepping);
    if (cloth__world_ready(w) != CLOTH_SUCCESS) return 0;
    return cloth__stable_step(w);
}

CLOTH_API cloth_real cloth_world_max_edge_strain(const cloth_world *w, int32_t piece)
{
    const cloth__piece *p;
    const cloth_real *x;
    cloth_real worst = 0;
    int32_t e;
    CLOTH_ASSERT(w);
    p = cloth__piece_get(w, piece);
    if (!p) return 0;
    x = w->x + 3 * (size_t)p->first_vertex;
    for (e = 0; e < p->edge_count; ++e) {
        cloth_real d[3], strain;
        if (!(p->edge_rest[e] > 0)) continue;
        cloth__v3_sub(x + 3 * (size_t)p->edge[2 * e], x + 3 * (size_t)p->edge[2 * e + 1], d);
        strain = cloth__v3_norm(d) / p->edge_rest[e] - 1;
        if (strain > worst) worst = strain;
    }
    return worst;
}


#ifdef __cplusplus
}
#endif

#endif /* CLOTH_IMPLEMENTATION_DONE */
#endif /* CLOTH_IMPLEMENTATION */

/*
------------------------------------------------------------------------------
This software is available under 2 licenses -- choose whichever you prefer.
------------------------------------------------------------------------------
ALTERNATIVE A - MIT License
Copyright (c) 2026 the cloth.h authors
Permission is hereby granted, free of charge, to any person obtaining a copy of
this software and associated documentation files (the "Software"), to deal in
the Software without restriction, including without limitation the rights to
use, copy, modify, merge, publish, distribute, sublicense, and/or sell copies
of the Software, and to permit persons to whom the Software is furnished to do
so, subject to the following conditions:
The above copyright notice and this permission notice shall be included in all
copies or substantial portions of the Software.
THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
SOFTWARE.
------------------------------------------------------------------------------
ALTERNATIVE B - Public Domain (www.unlicense.org)
This is free and unencumbered software released into the public domain.
Anyone is free to copy, modify, publish, use, compile, sell, or distribute this
software, either in source code form or as a compiled binary, for any purpose,
commercial or non-commercial, and by any means.
In jurisdictions that recognize copyright laws, the author or authors of this
software dedicate any and all copyright interest in the software to the public
domain. We make this dedication in perpetuity for the benefit of the software
to the public and to the benefit of the community.
------------------------------------------------------------------------------
*/
