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
