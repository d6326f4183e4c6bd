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
