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

CLOTH_API cloth_pcg_options cloth_default_pcg_options(void)
{
    cloth_pcg_options o;
    o.tolerance = sizeof(cloth_real) < sizeof(double) ? (cloth_real)1e-4 : (cloth_real)1e-6;
    o.max_iterations = 1000;
    o.preconditioner = CLOTH_PRECONDITIONER_BLOCK_JACOBI;
    return o;
}

CLOTH_API cloth_result cloth_pcg_workspace_create(cloth_pcg_workspace *workspace, int32_t vertex_count,
                                                  const cloth_allocator *allocator)
{
    int ok = 1;
    CLOTH_ASSERT(workspace);
    memset(workspace, 0, sizeof *workspace);
    if (vertex_count < 0) return CLOTH_ERROR_INVALID_ARGUMENT;
    cloth__size_mul_add((size_t)vertex_count, 24 * sizeof(cloth_real), 0, &ok);
    if (!ok) return CLOTH_ERROR_SIZE_OVERFLOW;
    workspace->allocator = cloth__allocator_or_default(allocator);
    workspace->memory = (cloth_real *)cloth__alloc_array(&workspace->allocator, (size_t)vertex_count,
                                                         24 * sizeof(cloth_real));
    if (!workspace->memory) {
        memset(workspace, 0, sizeof *workspace);
        return CLOTH_ERROR_OUT_OF_MEMORY;
    }
    workspace->vertex_count = vertex_count;
    return CLOTH_SUCCESS;
}

CLOTH_API void cloth_pcg_workspace_free(cloth_pcg_workspace *workspace)
{
    cloth_allocator a;
    CLOTH_ASSERT(workspace);
    a = cloth__allocator_or_default(&workspace->allocator);
    cloth__free(&a, workspace->memory);
    memset(workspace, 0, sizeof *workspace);
}

static int cloth__is_finite_double(double v) { return v == v && v - v == 0; }

/* 1 when all count values are finite: v - v is 0 for a finite v and NaN otherwise. */
static int cloth__all_finite(const cloth_real *v, size_t count)
{
    cloth_real acc = 0;
    size_t k;
    for (k = 0; k < count; ++k) acc += v[k] - v[k];
    return acc == 0;
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

/* pre[9i..9i+8] = S_i P_i^-1 S_i for the Jacobi and block-Jacobi preconditioners (see
   cloth_preconditioner), from the filtered diagonal blocks M_i = S A_ii S + c (I - S). */
static cloth_result cloth__pcg_build_preconditioner(const cloth_block_matrix *matrix, const int32_t *constrained,
                                                    const cloth_real *d, cloth_preconditioner kind, cloth_real *pre)
{
    int32_t i;
    if (kind == CLOTH_PRECONDITIONER_NONE) return CLOTH_SUCCESS;
    for (i = 0; i < matrix->vertex_count; ++i) {
        const cloth_real *a = matrix->value + 9 * (size_t)matrix->diagonal[i];
        cloth_real *out = pre + 9 * (size_t)i;
        int32_t count = constrained ? constrained[i] : 0;
        double s[9], as[9], sa[9], m[9], inv[9], b[9], c;
        int r, k, e;
        if (count == 3) {
            for (e = 0; e < 9; ++e) out[e] = 0;
            continue;
        }
        for (r = 0; r < 3; ++r)
            for (k = 0; k < 3; ++k) {
                double dr = count ? (double)d[3 * (size_t)i + r] : 0, dk = count ? (double)d[3 * (size_t)i + k] : 0;
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

/* r = S (b - A x); returns |r|^2. */
static double cloth__pcg_residual(const cloth_block_matrix *matrix, const int32_t *constrained, const cloth_real *d,
                                  const cloth_real *b, const cloth_real *x, cloth_real *r)
{
    int32_t i;
    for (i = 0; i < matrix->vertex_count; ++i) {
        size_t o = 3 * (size_t)i;
        cloth_real t[3];
        cloth__block_row_product(matrix, i, x, t);
        r[o] = b[o] - t[0];
        r[o + 1] = b[o + 1] - t[1];
        r[o + 2] = b[o + 2] - t[2];
        if (constrained) cloth__filter_apply(constrained[i], d + o, r + o);
    }
    return cloth__dot_long(r, r, 3 * (size_t)matrix->vertex_count);
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

CLOTH_API cloth_result cloth_pcg_solve(const cloth_block_matrix *matrix, const cloth_real *b, cloth_real *x,
                                       const cloth_pcg_filter *filter, const cloth_pcg_options *options,
                                       cloth_pcg_workspace *workspace, cloth_pcg_stats *stats)
{
    static const cloth_real zero[3] = { 0, 0, 0 };
    cloth_pcg_options opt;
    cloth_pcg_stats st;
    const int32_t *constrained;
    const cloth_real *z;
    cloth_real *r, *s, *p, *q, *pre, *d;
    size_t n3, k;
    int32_t n, i;
    int has_constrained_part = 0;
    double bhat2, delta0, delta, tol2;
    cloth_result result;

    CLOTH_ASSERT(matrix && b && x && workspace);
    st.iterations = 0;
    st.residual = 0;
    st.preconditioned_residual = 0;
    st.converged = 0;
    if (stats) *stats = st;

    opt = options ? *options : cloth_default_pcg_options();
    if (!cloth__is_finite(opt.tolerance) || opt.tolerance < 0 || opt.max_iterations < 0 ||
        (opt.preconditioner != CLOTH_PRECONDITIONER_NONE && opt.preconditioner != CLOTH_PRECONDITIONER_JACOBI &&
         opt.preconditioner != CLOTH_PRECONDITIONER_BLOCK_JACOBI))
        return CLOTH_ERROR_INVALID_ARGUMENT;
    n = matrix->vertex_count;
    n3 = 3 * (size_t)n;
    if (workspace->vertex_count < n || (n > 0 && !workspace->memory)) return CLOTH_ERROR_INVALID_ARGUMENT;
    if (n == 0) {
        st.converged = 1;
        if (stats) *stats = st;
        return CLOTH_SUCCESS;
    }
    r = workspace->memory;
    s = r + n3;
    p = s + n3;
    q = p + n3;
    pre = q + n3;
    d = pre + 3 * n3;
    constrained = filter ? filter->constrained : NULL;
    z = filter ? filter->value : NULL;

    /* Everything that can fail before x is touched. */
    result = cloth__pcg_prepare_filter(n, constrained, filter ? filter->direction : NULL, d);
    if (result != CLOTH_SUCCESS) return result;
    if (!cloth__all_finite(b, n3) || (z && !cloth__all_finite(z, n3)) || !cloth__all_finite(x, n3) ||
        !cloth__all_finite(matrix->value, 9 * (size_t)matrix->block_count))
        return CLOTH_ERROR_NOT_FINITE;
    result = cloth__pcg_build_preconditioner(matrix, constrained, d, opt.preconditioner, pre);
    if (result != CLOTH_SUCCESS) return result;

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
        bhat2 = cloth__pcg_residual(matrix, constrained, d, b, q, r);
    } else {
        for (k = 0; k < n3; ++k) r[k] = b[k];
        if (constrained)
            for (i = 0; i < n; ++i) cloth__filter_apply(constrained[i], d + 3 * (size_t)i, r + 3 * (size_t)i);
        bhat2 = cloth__dot_long(r, r, n3);
    }
    cloth__pcg_precondition(n, opt.preconditioner, pre, r, s);
    delta0 = cloth__dot_long(r, s, n3);
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
    cloth__pcg_residual(matrix, constrained, d, b, x, r);
    cloth__pcg_precondition(n, opt.preconditioner, pre, r, s);
    delta = cloth__dot_long(r, s, n3);
    for (k = 0; k < n3; ++k) p[k] = s[k];
    if (constrained)
        for (i = 0; i < n; ++i) cloth__filter_apply(constrained[i], d + 3 * (size_t)i, p + 3 * (size_t)i);

    tol2 = (double)opt.tolerance * (double)opt.tolerance;
    result = CLOTH_SUCCESS;
    while (!(delta <= tol2 * delta0)) {
        double pq, alpha, beta, delta_new;
        cloth_real alpha_r, beta_r;
        if (st.iterations >= opt.max_iterations) { result = CLOTH_ERROR_CG_NOT_CONVERGED; break; }
        /* q = S A p and p^T q, vertex by vertex (the sum runs in index order as a separate
           dot product would) */
        pq = 0;
        for (i = 0; i < n; ++i) {
            size_t o = 3 * (size_t)i;
            cloth__block_row_product(matrix, i, p, q + o);
            if (constrained) cloth__filter_apply(constrained[i], d + o, q + o);
            pq += (double)p[o] * (double)q[o];
            pq += (double)p[o + 1] * (double)q[o + 1];
            pq += (double)p[o + 2] * (double)q[o + 2];
        }
        if (!cloth__is_finite_double(pq) || !cloth__is_finite_double(delta)) { result = CLOTH_ERROR_NOT_FINITE; break; }
        if (!(pq > 0)) { result = CLOTH_ERROR_NOT_POSITIVE_DEFINITE; break; }
        alpha = delta / pq;
        alpha_r = (cloth_real)alpha;
        /* x += alpha p, r -= alpha q, s = P^-1 r and r^T s in one pass */
        delta_new = 0;
        for (i = 0; i < n; ++i) {
            size_t o = 3 * (size_t)i;
            cloth_real *ri = r + o, *si = s + o;
            int e;
            for (e = 0; e < 3; ++e) {
                x[o + e] += alpha_r * p[o + e];
                ri[e] -= alpha_r * q[o + e];
            }
            if (opt.preconditioner == CLOTH_PRECONDITIONER_NONE) {
                si[0] = ri[0];
                si[1] = ri[1];
                si[2] = ri[2];
            } else {
                const cloth_real *m = pre + 9 * (size_t)i;
                si[0] = m[0] * ri[0] + m[1] * ri[1] + m[2] * ri[2];
                si[1] = m[3] * ri[0] + m[4] * ri[1] + m[5] * ri[2];
                si[2] = m[6] * ri[0] + m[7] * ri[1] + m[8] * ri[2];
            }
            delta_new += (double)ri[0] * (double)si[0];
            delta_new += (double)ri[1] * (double)si[1];
            delta_new += (double)ri[2] * (double)si[2];
        }
        beta = delta_new / delta;
        beta_r = (cloth_real)beta;
        /* p = S (s + beta p) */
        for (i = 0; i < n; ++i) {
            size_t o = 3 * (size_t)i;
            p[o] = s[o] + beta_r * p[o];
            p[o + 1] = s[o + 1] + beta_r * p[o + 1];
            p[o + 2] = s[o + 2] + beta_r * p[o + 2];
            if (constrained) cloth__filter_apply(constrained[i], d + o, p + o);
        }
        delta = delta_new;
        ++st.iterations;
    }

    /* Re-impose the constrained part, so that rounding in the iterations does not drift it,
       and report the true residual of the returned x. */
    cloth__pcg_impose(n, constrained, d, z, x);
    st.residual = (cloth_real)sqrt(cloth__pcg_residual(matrix, constrained, d, b, x, r) / bhat2);
    st.preconditioned_residual = (cloth_real)sqrt(delta / delta0);
    st.converged = delta <= tol2 * delta0;
    if (stats) *stats = st;
    return result;
}
