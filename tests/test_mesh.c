/* Tests of the mesh module: generators, topology, validation, subdivision. */
#include "runner.h"
#include "../cloth.h"
#include <stdlib.h>
#include <string.h>

/* An allocator that counts what is outstanding and can fail the k-th allocation
   or any allocation above a size. */
typedef struct counting { long live, total, fail_at; size_t max_request, fail_above; } counting;
static void *counting_alloc(size_t size, void *user)
{
    counting *c = (counting *)user;
    if (size > c->max_request) c->max_request = size;
    if (c->fail_at >= 0 && c->total == c->fail_at) { c->total++; return NULL; }
    if (c->fail_above && size > c->fail_above) return NULL;
    c->total++;
    c->live++;
    return malloc(size);
}
static void counting_free(void *p, void *user)
{
    counting *c = (counting *)user;
    if (p) { c->live--; free(p); }
}
static cloth_allocator counting_allocator(counting *c)
{
    cloth_allocator a;
    memset(c, 0, sizeof *c);
    c->fail_at = -1;
    a.alloc = counting_alloc;
    a.free = counting_free;
    a.user = c;
    return a;
}

static void face_normal(const cloth_mesh *m, int32_t f, double n[3])
{
    const int32_t *t = m->tri + 3 * f;
    const cloth_real *a = m->x + 3 * t[0], *b = m->x + 3 * t[1], *c = m->x + 3 * t[2];
    double e0[3], e1[3];
    int k;
    for (k = 0; k < 3; ++k) { e0[k] = b[k] - a[k]; e1[k] = c[k] - a[k]; }
    n[0] = e0[1] * e1[2] - e0[2] * e1[1];
    n[1] = e0[2] * e1[0] - e0[0] * e1[2];
    n[2] = e0[0] * e1[1] - e0[1] * e1[0];
}

/* Signed volume by the divergence theorem: positive for a closed outward mesh. */
static double mesh_volume(const cloth_mesh *m)
{
    double v = 0;
    int32_t f;
    for (f = 0; f < m->triangle_count; ++f) {
        const cloth_real *a = m->x + 3 * m->tri[3 * f], *b = m->x + 3 * m->tri[3 * f + 1], *c = m->x + 3 * m->tri[3 * f + 2];
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0;
    }
    return v;
}

/* Every face's normal points away from the origin (convex shapes around it). */
static int all_outward(const cloth_mesh *m)
{
    int32_t f;
    for (f = 0; f < m->triangle_count; ++f) {
        double n[3], c[3] = { 0, 0, 0 };
        int k, j;
        face_normal(m, f, n);
        for (k = 0; k < 3; ++k)
            for (j = 0; j < 3; ++j) c[j] += m->x[3 * m->tri[3 * f + k] + j];
        if (n[0] * c[0] + n[1] * c[1] + n[2] * c[2] <= 0) return 0;
    }
    return 1;
}

/* A closed manifold genus-0 surface: valid, no boundary, V - E + F = 2. */
static int closed_sphere_like(const cloth_mesh *m)
{
    cloth_topology t;
    int ok;
    if (cloth_mesh_validate(m, 0, NULL, NULL) != CLOTH_SUCCESS) return 0;
    if (cloth_topology_build(&t, m, NULL) != CLOTH_SUCCESS) return 0;
    ok = t.boundary_edge_count == 0 && t.loop_count == 0 && t.nonmanifold_edge_count == 0 &&
         m->vertex_count - t.edge_count + m->triangle_count == 2;
    cloth_topology_free(&t);
    return ok;
}

TEST(mesh_alloc_counts_uv_and_failures)
{
    /* cloth_mesh_alloc: the counts and arrays asked for (uv only when asked), everything given
       back by cloth_mesh_free, a negative count refused and a failed allocation leaving an empty
       mesh with nothing allocated. */
    counting c;
    cloth_allocator a = counting_allocator(&c);
    cloth_mesh m;
    ENSURE(cloth_mesh_alloc(&m, 5, 3, 1, &a) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 5 && m.triangle_count == 3 && m.x && m.uv && m.tri);
    ENSURE(c.live == 3);
    cloth_mesh_free(&m);
    ENSURE(c.live == 0 && m.x == NULL && m.vertex_count == 0);
    ENSURE(cloth_mesh_alloc(&m, 5, 3, 0, &a) == CLOTH_SUCCESS);
    ENSURE(m.uv == NULL && c.live == 2);
    cloth_mesh_free(&m);
    ENSURE(cloth_mesh_alloc(&m, -1, 3, 0, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(m.x == NULL && m.tri == NULL && m.vertex_count == 0);
    ENSURE(cloth_mesh_alloc(&m, 5, -3, 0, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    c.fail_at = c.total + 1; /* the second allocation fails */
    ENSURE(cloth_mesh_alloc(&m, 5, 3, 1, &a) == CLOTH_ERROR_OUT_OF_MEMORY);
    ENSURE(m.x == NULL && m.uv == NULL && m.tri == NULL && m.vertex_count == 0 && c.live == 0);
}

TEST(grid_counts_orientation_uv)
{
    int d;
    for (d = 0; d < 2; ++d) {
        cloth_mesh m;
        int32_t f, v;
        ENSURE(cloth_mesh_grid(&m, 5, 4, 2.0, 1.5, (cloth_grid_diagonal)d, NULL) == CLOTH_SUCCESS);
        ENSURE(m.vertex_count == 20 && m.triangle_count == 24 && m.uv != NULL);
        for (f = 0; f < m.triangle_count; ++f) {
            double n[3];
            face_normal(&m, f, n);
            ENSURE(n[1] > 0 && fabs(n[0]) < 1e-15 && fabs(n[2]) < 1e-15);
            ENSURE_NEAR(n[1], 2.0 / 4 * 1.5 / 3, 1e-14); /* twice the area of a half cell */
        }
        for (v = 0; v < m.vertex_count; ++v) {
            ENSURE_NEAR(m.uv[2 * v], m.x[3 * v] + 1.0, 1e-15);
            ENSURE_NEAR(m.uv[2 * v + 1], 0.75 - m.x[3 * v + 2], 1e-15);
            ENSURE(m.x[3 * v + 1] == 0);
        }
        ENSURE_NEAR(m.x[0], -1.0, 0);
        ENSURE_NEAR(m.x[3 * 19 + 2], 0.75, 0);
        ENSURE(cloth_mesh_validate(&m, 0, NULL, NULL) == CLOTH_SUCCESS);
        cloth_mesh_free(&m);
        ENSURE(m.x == NULL && m.vertex_count == 0);
    }
}

TEST(grid_diagonal_patterns_differ)
{
    cloth_mesh a, b;
    int32_t diag_a = 0, diag_b = 0, f;
    ENSURE(cloth_mesh_grid(&a, 4, 4, 1, 1, CLOTH_GRID_DIAGONAL_REGULAR, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_grid(&b, 4, 4, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    /* Count triangles that contain the a-c diagonal of their cell (vertex (i,j) and (i+1,j+1)). */
    for (f = 0; f < a.triangle_count; ++f) {
        const int32_t *ta = a.tri + 3 * f, *tb = b.tri + 3 * f;
        int k, l;
        for (k = 0; k < 3; ++k)
            for (l = 0; l < 3; ++l) {
                diag_a += ta[l] - ta[k] == 5;
                diag_b += tb[l] - tb[k] == 5;
            }
    }
    ENSURE(diag_a == 18);      /* every triangle of all 9 cells */
    ENSURE(diag_b == 2 * 5);   /* only the 5 cells with i + j even */
    cloth_mesh_free(&a);
    cloth_mesh_free(&b);
}

TEST(grid_bad_arguments_and_overflow)
{
    cloth_mesh m;
    counting c;
    cloth_allocator a = counting_allocator(&c);
    ENSURE(cloth_mesh_grid(&m, 1, 4, 1, 1, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_grid(&m, 4, 4, 0, 1, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_grid(&m, 4, 4, NAN, 1, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_grid(&m, 4, 4, 1, INFINITY, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_grid(&m, 4, 4, 1, 1, (cloth_grid_diagonal)7, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_grid(&m, 100000, 100000, 1, 1, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_SIZE_OVERFLOW);
    ENSURE(cloth_mesh_grid(&m, INT32_MAX, 3, 1, 1, CLOTH_GRID_DIAGONAL_REGULAR, &a) == CLOTH_ERROR_SIZE_OVERFLOW);
    ENSURE(cloth_mesh_disc(&m, 1, 1000000, 1000000, &a) == CLOTH_ERROR_SIZE_OVERFLOW);
    ENSURE(cloth_mesh_capsule(&m, 1, 1, 1000000, 1000000, &a) == CLOTH_ERROR_SIZE_OVERFLOW);
    ENSURE(c.total == 0 && m.x == NULL);
}

TEST(allocation_failures_leak_nothing)
{
    long k;
    for (k = 0; k < 40; ++k) {
        counting c;
        cloth_allocator a = counting_allocator(&c);
        cloth_mesh m, fine;
        cloth_topology t;
        cloth_upsample_map map;
        cloth_result r;
        c.fail_at = k;
        r = cloth_mesh_grid(&m, 6, 5, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, &a);
        if (r == CLOTH_SUCCESS) {
            r = cloth_topology_build(&t, &m, &a);
            if (r == CLOTH_SUCCESS) cloth_topology_free(&t);
            else ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && t.edge_vertex == NULL);
            r = cloth_mesh_subdivide(&fine, &map, &m, &a);
            if (r == CLOTH_SUCCESS) { cloth_mesh_free(&fine); cloth_upsample_map_free(&map); }
            else ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && fine.x == NULL && map.start == NULL);
            r = cloth_mesh_validate(&m, 0, NULL, &a);
            ENSURE(r == CLOTH_SUCCESS || r == CLOTH_ERROR_OUT_OF_MEMORY);
            cloth_mesh_free(&m);
        } else
            ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && m.x == NULL);
        r = cloth_mesh_icosphere(&m, 1, 2, &a);
        if (r == CLOTH_SUCCESS) cloth_mesh_free(&m);
        else ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && m.x == NULL);
        r = cloth_mesh_box(&m, 1, 1, 1, 2, &a);
        if (r == CLOTH_SUCCESS) cloth_mesh_free(&m);
        else ENSURE(r == CLOTH_ERROR_OUT_OF_MEMORY && m.x == NULL);
        ENSURE(c.live == 0);
    }
}

TEST(topology_of_grid)
{
    cloth_mesh m;
    cloth_topology t;
    int32_t e, f, v, nx = 6, ny = 4;
    ENSURE(cloth_mesh_grid(&m, nx, ny, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_topology_build(&t, &m, NULL) == CLOTH_SUCCESS);
    ENSURE(t.edge_count == (nx - 1) * ny + nx * (ny - 1) + (nx - 1) * (ny - 1));
    ENSURE(t.boundary_edge_count == 2 * (nx - 1) + 2 * (ny - 1));
    ENSURE(t.nonmanifold_edge_count == 0);
    ENSURE(m.vertex_count - t.edge_count + m.triangle_count == 1);
    ENSURE(t.loop_count == 1 && t.loop_start[1] - t.loop_start[0] == t.boundary_edge_count);
    for (e = 0; e < t.edge_count; ++e) {
        int32_t lo = t.edge_vertex[2 * e], hi = t.edge_vertex[2 * e + 1], s;
        ENSURE(lo < hi);
        ENSURE(cloth_topology_find_edge(&t, hi, lo) == e);
        for (s = 0; s < 2; ++s) {
            int32_t face = t.edge_face[2 * e + s], k, hits = 0;
            if (face < 0) { ENSURE(s == 1 && t.edge_opposite[2 * e + s] == -1); continue; }
            for (k = 0; k < 3; ++k) {
                int32_t a = m.tri[3 * face + k], b = m.tri[3 * face + (k + 1) % 3];
                if ((a == lo && b == hi) || (a == hi && b == lo)) {
                    ++hits;
                    ENSURE(m.tri[3 * face + (k + 2) % 3] == t.edge_opposite[2 * e + s]);
                    ENSURE(t.face_edge[3 * face + k] == e);
                    /* slot 0 runs lo -> hi on interior edges */
                    if (s == 0 && t.edge_face[2 * e + 1] >= 0) ENSURE(a == lo);
                }
            }
            ENSURE(hits == 1);
        }
    }
    ENSURE(cloth_topology_find_edge(&t, 0, nx + 3) == -1);
    ENSURE(cloth_topology_find_edge(&t, -1, 0) == -1);
    /* Vertex to faces: each face is listed at its three corners and nowhere else. */
    ENSURE(t.vertex_face_start[m.vertex_count] == 3 * m.triangle_count);
    for (v = 0; v < m.vertex_count; ++v) {
        int32_t s;
        for (s = t.vertex_face_start[v]; s < t.vertex_face_start[v + 1]; ++s) {
            const int32_t *tr = m.tri + 3 * t.vertex_face[s];
            ENSURE(tr[0] == v || tr[1] == v || tr[2] == v);
        }
    }
    /* Boundary loop: consecutive loop vertices are joined by boundary edges, in face direction. */
    for (e = 0; e < t.boundary_edge_count; ++e) {
        int32_t a = t.loop_vertex[e], b = t.loop_vertex[(e + 1) % t.boundary_edge_count];
        int32_t edge = cloth_topology_find_edge(&t, a, b);
        ENSURE(edge >= 0 && t.edge_face[2 * edge + 1] < 0);
        f = t.edge_face[2 * edge];
        {
            int k, dir_ok = 0;
            for (k = 0; k < 3; ++k) dir_ok |= m.tri[3 * f + k] == a && m.tri[3 * f + (k + 1) % 3] == b;
            ENSURE(dir_ok);
        }
    }
    cloth_topology_free(&t);
    cloth_topology_free(&t); /* freeing an empty topology is fine */
    cloth_mesh_free(&m);
}

TEST(topology_two_loops_and_nonmanifold)
{
    /* An annulus (a disc with the middle fan removed) has two boundary loops. */
    cloth_mesh d, annulus;
    cloth_topology t;
    int32_t segments = 6;
    ENSURE(cloth_mesh_disc(&d, 1, 3, segments, NULL) == CLOTH_SUCCESS);
    annulus = d;
    annulus.tri = d.tri + 3 * segments;
    annulus.triangle_count = d.triangle_count - segments;
    ENSURE(cloth_topology_build(&t, &annulus, NULL) == CLOTH_SUCCESS);
    ENSURE(t.loop_count == 2);
    ENSURE(t.boundary_edge_count == segments + 3 * segments);
    cloth_topology_free(&t);
    cloth_mesh_free(&d);
    {
        /* three triangles on one edge */
        cloth_real x[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1 };
        int32_t tri[] = { 0, 1, 2, 1, 0, 3, 0, 1, 4 };
        cloth_mesh m;
        memset(&m, 0, sizeof m);
        m.vertex_count = 5; m.triangle_count = 3; m.x = x; m.tri = tri;
        ENSURE(cloth_topology_build(&t, &m, NULL) == CLOTH_SUCCESS);
        ENSURE(t.nonmanifold_edge_count == 1 && t.edge_count == 7);
        cloth_topology_free(&t);
        tri[8] = 7;
        ENSURE(cloth_topology_build(&t, &m, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
        tri[8] = 0;
        ENSURE(cloth_topology_build(&t, &m, NULL) == CLOTH_ERROR_DEGENERATE_TRIANGLE);
    }
}

TEST(disc)
{
    cloth_mesh m;
    cloth_topology t;
    double area = 0;
    int32_t f;
    ENSURE(cloth_mesh_disc(&m, 0.15, 8, 6, NULL) == CLOTH_SUCCESS);
    ENSURE(m.vertex_count == 1 + 6 * 8 * 9 / 2 && m.triangle_count == 6 * 64);
    for (f = 0; f < m.triangle_count; ++f) {
        double n[3];
        face_normal(&m, f, n);
        ENSURE(n[1] > 0);
        area += n[1] / 2;
    }
    /* The outer ring is a regular 48-gon of radius 0.15. */
    ENSURE_NEAR(area, 0.5 * 48 * 0.15 * 0.15 * sin(2 * 3.141592653589793 / 48), 1e-12);
    ENSURE(cloth_mesh_validate(&m, 0, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_topology_build(&t, &m, NULL) == CLOTH_SUCCESS);
    ENSURE(t.loop_count == 1 && t.boundary_edge_count == 48);
    ENSURE(m.vertex_count - t.edge_count + m.triangle_count == 1);
    cloth_topology_free(&t);
    ENSURE_NEAR(m.uv[0], 0.15, 0);
    cloth_mesh_free(&m);
    ENSURE(cloth_mesh_disc(&m, 1, 0, 6, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_mesh_disc(&m, 1, 2, 2, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
}

TEST(icosphere)
{
    int32_t k;
    for (k = 0; k <= 3; ++k) {
        cloth_mesh m;
        int32_t v, p4 = 1 << (2 * k);
        ENSURE(cloth_mesh_icosphere(&m, 0.3, k, NULL) == CLOTH_SUCCESS);
        ENSURE(m.vertex_count == 10 * p4 + 2 && m.triangle_count == 20 * p4 && m.uv == NULL);
        for (v = 0; v < m.vertex_count; ++v) ENSURE_NEAR(sqrt(m.x[3 * v] * m.x[3 * v] + m.x[3 * v + 1] * m.x[3 * v + 1] + m.x[3 * v + 2] * m.x[3 * v + 2]), 0.3, 1e-15);
        ENSURE(all_outward(&m));
        ENSURE(closed_sphere_like(&m));
        if (k == 3) ENSURE_NEAR(mesh_volume(&m), 4.0 / 3 * 3.141592653589793 * 0.027, 0.01 * 0.113);
        cloth_mesh_free(&m);
    }
    {
        cloth_mesh m;
        ENSURE(cloth_mesh_icosphere(&m, 1, 11, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(cloth_mesh_icosphere(&m, -1, 1, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    }
}

TEST(capsule)
{
    cloth_real lengths[2] = { 0.6, 0 };
    int i;
    for (i = 0; i < 2; ++i) {
        cloth_mesh m;
        int32_t v;
        double r = 0.15, l = lengths[i], exact = 3.141592653589793 * r * r * l + 4.0 / 3 * 3.141592653589793 * r * r * r;
        ENSURE(cloth_mesh_capsule(&m, (cloth_real)r, lengths[i], 48, 12, NULL) == CLOTH_SUCCESS);
        ENSURE(all_outward(&m));
        ENSURE(closed_sphere_like(&m));
        for (v = 0; v < m.vertex_count; ++v) {
            /* every vertex is at distance r from the axis segment */
            double x = m.x[3 * v], cx = x < -l / 2 ? -l / 2 : (x > l / 2 ? l / 2 : x);
            double d = sqrt((x - cx) * (x - cx) + m.x[3 * v + 1] * m.x[3 * v + 1] + m.x[3 * v + 2] * m.x[3 * v + 2]);
            ENSURE_NEAR(d, r, 1e-12);
        }
        ENSURE(mesh_volume(&m) < exact && mesh_volume(&m) > 0.97 * exact);
        cloth_mesh_free(&m);
    }
}

TEST(box)
{
    int32_t n;
    for (n = 1; n <= 4; ++n) {
        cloth_mesh m;
        ENSURE(cloth_mesh_box(&m, 0.2, 0.3, 0.5, n, NULL) == CLOTH_SUCCESS);
        ENSURE(m.vertex_count == 6 * n * n + 2 && m.triangle_count == 12 * n * n);
        ENSURE(all_outward(&m));
        ENSURE(closed_sphere_like(&m));
        ENSURE_NEAR(mesh_volume(&m), 8 * 0.2 * 0.3 * 0.5, 1e-14);
        cloth_mesh_free(&m);
    }
    {
        cloth_mesh m;
        ENSURE(cloth_mesh_box(&m, 1, 1, 1, 0, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
        ENSURE(cloth_mesh_box(&m, 1, 1, 1, 129, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    }
}

/* A 2x2-vertex square (two triangles) the validation tests break in one way each. */
typedef struct square { cloth_real x[15]; cloth_real uv[10]; int32_t tri[9]; cloth_mesh m; } square;
static void square_make(square *s)
{
    static const cloth_real x[15] = { 0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1, 5, 5, 5 };
    static const cloth_real uv[10] = { 0, 0, 1, 0, 1, 1, 0, 1, 3, 3 };
    static const int32_t tri[6] = { 0, 2, 1, 0, 3, 2 };
    memcpy(s->x, x, sizeof x);
    memcpy(s->uv, uv, sizeof uv);
    memcpy(s->tri, tri, sizeof tri);
    memset(&s->m, 0, sizeof s->m);
    s->m.vertex_count = 4;
    s->m.triangle_count = 2;
    s->m.x = s->x;
    s->m.uv = s->uv;
    s->m.tri = s->tri;
}

TEST(validate_reports_each_problem)
{
    square s;
    cloth_mesh_report rep;
    square_make(&s);
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_SUCCESS);
    ENSURE(rep.unreferenced_vertex_count == 0 && rep.first_unreferenced_vertex == -1);
    ENSURE_NEAR(rep.min_quality_world, 0.5, 1e-15);
    ENSURE_NEAR(rep.min_quality_rest, 0.5, 1e-15);
    /* unreferenced vertex: reported, not an error */
    s.m.vertex_count = 5;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_SUCCESS);
    ENSURE(rep.unreferenced_vertex_count == 1 && rep.first_unreferenced_vertex == 4);
    /* NaN and infinity */
    square_make(&s);
    s.x[3 * 2 + 1] = NAN;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_NOT_FINITE && rep.vertex == 2);
    square_make(&s);
    s.uv[2 * 3] = -INFINITY;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_NOT_FINITE && rep.vertex == 3);
    /* index out of range */
    square_make(&s);
    s.tri[4] = 4;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE && rep.triangle == 1 && rep.vertex == 4);
    s.tri[4] = -1;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_INDEX_OUT_OF_RANGE && rep.triangle == 1 && rep.vertex == -1);
    /* repeated vertex */
    square_make(&s);
    s.tri[2] = 0;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_DEGENERATE_TRIANGLE && rep.triangle == 0);
    /* zero area in world coordinates (collinear), rest fine */
    square_make(&s);
    s.x[3 * 3 + 0] = 0.5; s.x[3 * 3 + 2] = 0.5; /* vertex 3 on the diagonal 0-2 */
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_DEGENERATE_TRIANGLE && rep.triangle == 1);
    /* near-zero area: a sliver of quality 1e-9 is caught by default, accepted with a looser tolerance */
    square_make(&s);
    s.x[3 * 3 + 0] = 0.5; s.x[3 * 3 + 2] = 0.5 + 1e-9;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_DEGENERATE_TRIANGLE && rep.triangle == 1);
    ENSURE(cloth_mesh_validate(&s.m, (cloth_real)1e-12, &rep, NULL) == CLOTH_SUCCESS);
    ENSURE(rep.min_quality_world > 0 && rep.min_quality_world < 1e-8);
    /* zero area in rest coordinates, world fine */
    square_make(&s);
    s.uv[2 * 3] = 0.5; s.uv[2 * 3 + 1] = 0.5;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_DEGENERATE_TRIANGLE && rep.triangle == 1);
    s.m.uv = NULL; /* without uv only the world shape counts */
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_SUCCESS && rep.min_quality_rest == 0);
    /* inconsistent orientation: flip the second triangle */
    square_make(&s);
    s.tri[4] = 2; s.tri[5] = 3;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_INCONSISTENT_ORIENTATION);
    ENSURE(rep.triangle == 0 && rep.other_triangle == 1);
    /* empty */
    square_make(&s);
    s.m.triangle_count = 0;
    ENSURE(cloth_mesh_validate(&s.m, 0, &rep, NULL) == CLOTH_ERROR_EMPTY_MESH);
}

TEST(validate_duplicates_and_nonmanifold)
{
    cloth_real x[] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1 };
    int32_t tri[9] = { 0, 1, 2, 1, 0, 3, 0, 4, 1 };
    cloth_mesh m;
    cloth_mesh_report rep;
    memset(&m, 0, sizeof m);
    m.vertex_count = 5; m.triangle_count = 3; m.x = x; m.tri = tri;
    ENSURE(cloth_mesh_validate(&m, 0, &rep, NULL) == CLOTH_ERROR_NON_MANIFOLD_EDGE);
    ENSURE(rep.triangle == 0 && rep.vertex == 0);
    /* the same face twice (rotated): duplicate, even though the edge also has > 2 faces */
    tri[6] = 1; tri[7] = 2; tri[8] = 0;
    ENSURE(cloth_mesh_validate(&m, 0, &rep, NULL) == CLOTH_ERROR_DUPLICATE_FACE);
    ENSURE(rep.triangle == 0 && rep.other_triangle == 2);
    /* the same vertices in the opposite order: also a duplicate */
    tri[6] = 2; tri[7] = 1; tri[8] = 0;
    m.triangle_count = 3;
    ENSURE(cloth_mesh_validate(&m, 0, &rep, NULL) == CLOTH_ERROR_DUPLICATE_FACE);
}

TEST(subdivide_and_upsample)
{
    cloth_mesh coarse, fine, again;
    cloth_upsample_map map;
    cloth_topology t;
    cloth_real *up;
    double area = 0;
    int32_t f, v;
    ENSURE(cloth_mesh_grid(&coarse, 4, 3, 1.2, 0.8, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    /* bend it so midpoints are not trivially on a plane */
    for (v = 0; v < coarse.vertex_count; ++v) coarse.x[3 * v + 1] = coarse.x[3 * v] * coarse.x[3 * v];
    ENSURE(cloth_topology_build(&t, &coarse, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_subdivide(&fine, &map, &coarse, NULL) == CLOTH_SUCCESS);
    ENSURE(fine.vertex_count == coarse.vertex_count + t.edge_count);
    ENSURE(fine.triangle_count == 4 * coarse.triangle_count);
    ENSURE(map.fine_count == fine.vertex_count && map.coarse_count == coarse.vertex_count);
    ENSURE(cloth_mesh_validate(&fine, 0, NULL, NULL) == CLOTH_SUCCESS);
    /* the map reproduces positions and uv; rows sum to one */
    up = (cloth_real *)malloc(sizeof(cloth_real) * 3 * (size_t)fine.vertex_count);
    ENSURE(up != NULL);
    cloth_upsample_apply(&map, 3, coarse.x, up);
    for (v = 0; v < 3 * fine.vertex_count; ++v) ENSURE(up[v] == fine.x[v]);
    cloth_upsample_apply(&map, 2, coarse.uv, up);
    for (v = 0; v < 2 * fine.vertex_count; ++v) ENSURE(up[v] == fine.uv[v]);
    free(up);
    for (v = 0; v < fine.vertex_count; ++v) {
        double w = 0;
        int32_t s;
        for (s = map.start[v]; s < map.start[v + 1]; ++s) w += map.weight[s];
        ENSURE_NEAR(w, 1, 1e-15);
    }
    /* an edge vertex sits at the midpoint of its edge */
    for (v = 0; v < t.edge_count; ++v) {
        int32_t p = t.edge_vertex[2 * v], q = t.edge_vertex[2 * v + 1];
        ENSURE_NEAR(fine.x[3 * (coarse.vertex_count + v)], (coarse.x[3 * p] + coarse.x[3 * q]) / 2, 0);
    }
    /* rest area is preserved exactly in uv (flat), and orientation with it */
    for (f = 0; f < fine.triangle_count; ++f) {
        const cloth_real *a = fine.uv + 2 * fine.tri[3 * f], *b = fine.uv + 2 * fine.tri[3 * f + 1], *c = fine.uv + 2 * fine.tri[3 * f + 2];
        double cr = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        ENSURE(cr > 0); /* counter-clockwise in the uv plane */
        area += cr / 2;
    }
    ENSURE_NEAR(area, 1.2 * 0.8, 1e-14);
    /* subdividing twice composes */
    ENSURE(cloth_mesh_subdivide(&again, NULL, &fine, NULL) == CLOTH_SUCCESS);
    ENSURE(again.triangle_count == 16 * coarse.triangle_count);
    cloth_mesh_free(&again);
    cloth_topology_free(&t);
    cloth_upsample_map_free(&map);
    cloth_upsample_map_free(&map);
    cloth_mesh_free(&fine);
    cloth_mesh_free(&coarse);
}

TEST(copy_is_deep)
{
    cloth_mesh a, b;
    ENSURE(cloth_mesh_grid(&a, 3, 3, 1, 1, CLOTH_GRID_DIAGONAL_REGULAR, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_copy(&b, &a, NULL) == CLOTH_SUCCESS);
    ENSURE(b.x != a.x && b.uv != a.uv && b.tri != a.tri);
    ENSURE(memcmp(a.x, b.x, sizeof(cloth_real) * 27) == 0 && memcmp(a.tri, b.tri, sizeof(int32_t) * 24) == 0);
    b.x[0] = 7;
    ENSURE(a.x[0] != 7);
    cloth_mesh_free(&a);
    cloth_mesh_free(&b);
}

const test_case mesh_tests[] = {
    { "mesh_alloc_counts_uv_and_failures", mesh_alloc_counts_uv_and_failures },
    { "grid_counts_orientation_uv", grid_counts_orientation_uv },
    { "grid_diagonal_patterns_differ", grid_diagonal_patterns_differ },
    { "grid_bad_arguments_and_overflow", grid_bad_arguments_and_overflow },
    { "allocation_failures_leak_nothing", allocation_failures_leak_nothing },
    { "topology_of_grid", topology_of_grid },
    { "topology_two_loops_and_nonmanifold", topology_two_loops_and_nonmanifold },
    { "disc", disc },
    { "icosphere", icosphere },
    { "capsule", capsule },
    { "box", box },
    { "validate_reports_each_problem", validate_reports_each_problem },
    { "validate_duplicates_and_nonmanifold", validate_duplicates_and_nonmanifold },
    { "subdivide_and_upsample", subdivide_and_upsample },
    { "copy_is_deep", copy_is_deep },
    { NULL, NULL }
};
