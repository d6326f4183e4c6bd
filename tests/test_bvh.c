/* Tests of the bvh module: every traversal is compared, as a set of pairs, with brute force
   over all pairs of triangles whose boxes (built here the same way the library documents
   them) overlap; the tree's own invariants are checked after every build, refit and rebuild. */
#include "runner.h"
#include "../cloth.h"
#include <stdlib.h>
#include <string.h>

/* ---- helpers -------------------------------------------------------------------------- */

typedef struct counting_allocator { long allocs, frees, live, fail_after; } counting_allocator;

static void *counting_alloc(size_t size, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (c->fail_after >= 0 && c->allocs >= c->fail_after) return NULL;
    ++c->allocs;
    ++c->live;
    return malloc(size);
}

static void counting_free(void *p, void *user)
{
    counting_allocator *c = (counting_allocator *)user;
    if (!p) return;
    ++c->frees;
    --c->live;
    free(p);
}

static cloth_allocator make_counting(counting_allocator *c, long fail_after)
{
    cloth_allocator a;
    memset(c, 0, sizeof *c);
    c->fail_after = fail_after;
    a.alloc = counting_alloc;
    a.free = counting_free;
    a.user = c;
    return a;
}

/* A growing list of pairs; stop_after > 0 makes the collector ask to stop after that many. */
typedef struct pair_list { int32_t *ab; size_t count, cap; size_t stop_after; } pair_list;

static void pairs_init(pair_list *p) { memset(p, 0, sizeof *p); }
static void pairs_free(pair_list *p) { free(p->ab); memset(p, 0, sizeof *p); }

static void pairs_push(pair_list *p, int32_t a, int32_t b)
{
    if (p->count == p->cap) {
        p->cap = p->cap ? 2 * p->cap : 64;
        p->ab = (int32_t *)realloc(p->ab, 2 * p->cap * sizeof(int32_t));
        if (!p->ab) abort();
    }
    p->ab[2 * p->count] = a;
    p->ab[2 * p->count + 1] = b;
    ++p->count;
}

static int collect_pair(int32_t a, int32_t b, void *user)
{
    pair_list *p = (pair_list *)user;
    pairs_push(p, a, b);
    return p->stop_after > 0 && p->count >= p->stop_after ? 7 : 0;
}

static int collect_triangle(int32_t t, void *user)
{
    pair_list *p = (pair_list *)user;
    pairs_push(p, t, 0);
    return p->stop_after > 0 && p->count >= p->stop_after ? 9 : 0;
}

static int pair_cmp(const void *pa, const void *pb)
{
    const int32_t *a = (const int32_t *)pa, *b = (const int32_t *)pb;
    if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
    if (a[1] != b[1]) return a[1] < b[1] ? -1 : 1;
    return 0;
}

static void pairs_sort(pair_list *p)
{
    if (p->count > 1) qsort(p->ab, p->count, 2 * sizeof(int32_t), pair_cmp);
}

/* Sorted copies equal: the same multiset, and brute force has no repeats, so no pair is
   missing, none extra and none reported twice. */
static int pairs_same_set(pair_list *got, pair_list *want)
{
    pairs_sort(got);
    pairs_sort(want);
    return got->count == want->count && (got->count == 0 || memcmp(got->ab, want->ab, 2 * got->count * sizeof(int32_t)) == 0);
}

static int pairs_identical(const pair_list *a, const pair_list *b)
{
    return a->count == b->count && (a->count == 0 || memcmp(a->ab, b->ab, 2 * a->count * sizeof(int32_t)) == 0);
}

static cloth_real rmin(cloth_real a, cloth_real b) { return a < b ? a : b; }
static cloth_real rmax(cloth_real a, cloth_real b) { return a > b ? a : b; }

/* A triangle's box as documented: its vertices at x (and x1), grown by the thickness. */
static void tri_box(const cloth_real *x, const cloth_real *x1, const int32_t *tri, int32_t t, cloth_real thickness,
                    cloth_real *lo, cloth_real *hi)
{
    int k, c;
    for (k = 0; k < 3; ++k) {
        lo[k] = x[3 * tri[3 * t] + k];
        hi[k] = lo[k];
        for (c = 0; c < 3; ++c) {
            lo[k] = rmin(lo[k], x[3 * tri[3 * t + c] + k]);
            hi[k] = rmax(hi[k], x[3 * tri[3 * t + c] + k]);
            if (x1) {
                lo[k] = rmin(lo[k], x1[3 * tri[3 * t + c] + k]);
                hi[k] = rmax(hi[k], x1[3 * tri[3 * t + c] + k]);
            }
        }
        lo[k] -= thickness;
        hi[k] += thickness;
    }
}

static int boxes_overlap(const cloth_real *alo, const cloth_real *ahi, const cloth_real *blo, const cloth_real *bhi)
{
    int k;
    for (k = 0; k < 3; ++k)
        if (alo[k] > bhi[k] || blo[k] > ahi[k]) return 0;
    return 1;
}

static int share_vertex(const int32_t *ta, const int32_t *tb)
{
    int i, j;
    for (i = 0; i < 3; ++i)
        for (j = 0; j < 3; ++j)
            if (ta[i] == tb[j]) return 1;
    return 0;
}

static cloth_real *all_boxes(const cloth_real *x, const cloth_real *x1, const int32_t *tri, int32_t m, cloth_real thickness)
{
    cloth_real *b = (cloth_real *)malloc((size_t)(m > 0 ? m : 1) * 6 * sizeof(cloth_real));
    int32_t t;
    if (!b) abort();
    for (t = 0; t < m; ++t) tri_box(x, x1, tri, t, thickness, b + 6 * t, b + 6 * t + 3);
    return b;
}

static void brute_self(pair_list *out, const cloth_real *x, const cloth_real *x1, const int32_t *tri, int32_t m,
                       cloth_real thickness)
{
    cloth_real *b = all_boxes(x, x1, tri, m, thickness);
    int32_t i, j;
    for (i = 0; i < m; ++i)
        for (j = i + 1; j < m; ++j)
            if (boxes_overlap(b + 6 * i, b + 6 * i + 3, b + 6 * j, b + 6 * j + 3) && !share_vertex(tri + 3 * i, tri + 3 * j))
                pairs_push(out, i, j);
    free(b);
}

static void brute_pairs_swept(pair_list *out, const cloth_real *xa, const cloth_real *xa1, const int32_t *tria, int32_t ma,
                              cloth_real ta, const cloth_real *xb, const cloth_real *xb1, const int32_t *trib, int32_t mb,
                              cloth_real tb)
{
    cloth_real *ba = all_boxes(xa, xa1, tria, ma, ta), *bb = all_boxes(xb, xb1, trib, mb, tb);
    int32_t i, j;
    for (i = 0; i < ma; ++i)
        for (j = 0; j < mb; ++j)
            if (boxes_overlap(ba + 6 * i, ba + 6 * i + 3, bb + 6 * j, bb + 6 * j + 3)) pairs_push(out, i, j);
    free(ba);
    free(bb);
}

static void brute_pairs(pair_list *out, const cloth_real *xa, const int32_t *tria, int32_t ma, cloth_real ta,
                        const cloth_real *xb, const int32_t *trib, int32_t mb, cloth_real tb)
{
    brute_pairs_swept(out, xa, NULL, tria, ma, ta, xb, NULL, trib, mb, tb);
}

static int box_contains(const cloth_bvh_box *outer, const cloth_bvh_box *inner)
{
    int k;
    for (k = 0; k < 3; ++k)
        if (outer->lo[k] > inner->lo[k] || outer->hi[k] < inner->hi[k]) return 0;
    return 1;
}

static int box_equal(const cloth_bvh_box *a, const cloth_real *lo, const cloth_real *hi)
{
    int k;
    for (k = 0; k < 3; ++k)
        if (a->lo[k] != lo[k] || a->hi[k] != hi[k]) return 0;
    return 1;
}

/* Everything a tree promises: each triangle in exactly one slot with its own vertices and its
   documented box, leaves covering the slots once with 1..leaf_size items, children after
   their parent, every box containing its children's, the depth as stated. Returns 0 when all
   hold, else a number saying which failed. */
static int tree_problem(const cloth_bvh *bvh, const cloth_real *x, const cloth_real *x1, const int32_t *tri)
{
    int32_t m = bvh->triangle_count, i, max_depth = 0;
    int32_t *seen = (int32_t *)calloc((size_t)m + 1, sizeof(int32_t));
    int32_t *covered = (int32_t *)calloc((size_t)m + 1, sizeof(int32_t));
    int32_t *node_depth = (int32_t *)calloc((size_t)bvh->node_count + 1, sizeof(int32_t));
    int32_t *parents = (int32_t *)calloc((size_t)bvh->node_count + 1, sizeof(int32_t));
    int problem = 0;
    if (!seen || !covered || !node_depth || !parents) abort();
    if (m == 0 && bvh->node_count != 0) problem = 1;
    if (m > 0 && (bvh->node_count < 1 || bvh->node_count > 2 * m - 1)) problem = 2;
    for (i = 0; i < m && !problem; ++i) {
        int32_t t = bvh->item_triangle[i];
        cloth_real lo[3], hi[3];
        if (t < 0 || t >= m || seen[t]++) { problem = 3; break; }
        if (bvh->item_vertex[3 * i] != tri[3 * t] || bvh->item_vertex[3 * i + 1] != tri[3 * t + 1] ||
            bvh->item_vertex[3 * i + 2] != tri[3 * t + 2]) { problem = 4; break; }
        tri_box(x, x1, tri, t, bvh->def.thickness, lo, hi);
        if (!box_equal(&bvh->item_box[i], lo, hi)) { problem = 5; break; }
    }
    for (i = 0; i < bvh->node_count && !problem; ++i) {
        const cloth_bvh_node *n = bvh->nodes + i;
        if (i > 0 && parents[i] != 1) { problem = 6; break; }
        if (n->count > 0) {
            int32_t j;
            if (n->count > bvh->def.leaf_size || n->first < 0 || n->first + n->count > m) { problem = 7; break; }
            for (j = n->first; j < n->first + n->count; ++j) {
                if (covered[j]++) problem = 8;
                if (!box_contains(&n->box, &bvh->item_box[j])) problem = 9;
            }
            if (node_depth[i] > max_depth) max_depth = node_depth[i];
        } else {
            if (n->first <= i || n->first + 1 >= bvh->node_count) { problem = 10; break; }
            ++parents[n->first];
            ++parents[n->first + 1];
            node_depth[n->first] = node_depth[n->first + 1] = node_depth[i] + 1;
            if (!box_contains(&n->box, &bvh->nodes[n->first].box) || !box_contains(&n->box, &bvh->nodes[n->first + 1].box))
                problem = 11;
        }
    }
    for (i = 0; i < m && !problem; ++i)
        if (covered[i] != 1) problem = 12;
    if (!problem && (max_depth != bvh->depth || bvh->depth > CLOTH_BVH_MAX_DEPTH)) problem = 13;
    free(seen);
    free(covered);
    free(node_depth);
    free(parents);
    return problem;
}

/* A grid of nx * ny vertices in the plane y = 0 over [0, w] x [0, w], two triangles a quad
   with alternating diagonals. Arrays are malloc'd. */
static void make_grid(int32_t nx, int32_t ny, cloth_real w, cloth_real **x, int32_t **tri, int32_t *n, int32_t *m)
{
    int32_t i, j, t = 0;
    *n = nx * ny;
    *m = 2 * (nx - 1) * (ny - 1);
    *x = (cloth_real *)malloc(3 * (size_t)*n * sizeof(cloth_real));
    *tri = (int32_t *)malloc(3 * (size_t)*m * sizeof(int32_t));
    if (!*x || !*tri) abort();
    for (j = 0; j < ny; ++j)
        for (i = 0; i < nx; ++i) {
            cloth_real *p = *x + 3 * (j * nx + i);
            p[0] = w * (cloth_real)i / (cloth_real)(nx - 1);
            p[1] = 0;
            p[2] = w * (cloth_real)j / (cloth_real)(ny - 1);
        }
    for (j = 0; j + 1 < ny; ++j)
        for (i = 0; i + 1 < nx; ++i) {
            int32_t v00 = j * nx + i, v10 = v00 + 1, v01 = v00 + nx, v11 = v01 + 1;
            int32_t *q = *tri + 3 * t;
            if ((i + j) % 2 == 0) {
                q[0] = v00; q[1] = v01; q[2] = v11; q[3] = v00; q[4] = v11; q[5] = v10;
            } else {
                q[0] = v00; q[1] = v01; q[2] = v10; q[3] = v10; q[4] = v01; q[5] = v11;
            }
            t += 2;
        }
}

/* Fold a grid made by make_grid (side w, in the plane y = 0) over the line x = w / 2 around a
   cylinder of the given radius, so the far half lies flat at y = 2 radius above the near half. */
static void fold_grid(cloth_real *x, int32_t n, cloth_real w, cloth_real radius)
{
    int32_t v;
    for (v = 0; v < n; ++v) {
        cloth_real s = x[3 * v] - w / 2, arc = (cloth_real)3.14159265358979 * radius;
        if (s <= 0) continue;
        if (s <= arc) {
            cloth_real th = s / radius;
            x[3 * v] = w / 2 + radius * (cloth_real)sin((double)th);
            x[3 * v + 1] = radius - radius * (cloth_real)cos((double)th);
        } else {
            x[3 * v] = w / 2 - (s - arc);
            x[3 * v + 1] = 2 * radius;
        }
    }
}

/* A soup of m triangles. Separate vertices (shared == 0): each triangle has three of its own,
   around a centre uniform in [0, extent]^3 at distances of about `size`. Shared vertices:
   a pool of m / 2 + 3 vertices uniform in [0, extent]^3, each triangle picks three at random
   (repeats allowed), so many triangles share vertices. */
static void make_soup(cloth_rng *rng, int32_t m, cloth_real extent, cloth_real size, int shared, cloth_real **x,
                      int32_t **tri, int32_t *n)
{
    int32_t t, v;
    *n = shared ? m / 2 + 3 : 3 * m;
    *x = (cloth_real *)malloc(3 * (size_t)(*n > 0 ? *n : 1) * sizeof(cloth_real));
    *tri = (int32_t *)malloc(3 * (size_t)(m > 0 ? m : 1) * sizeof(int32_t));
    if (!*x || !*tri) abort();
    if (shared) {
        for (v = 0; v < 3 * *n; ++v) (*x)[v] = extent * cloth_rng_uniform(rng);
        for (t = 0; t < 3 * m; ++t) (*tri)[t] = (int32_t)(cloth_rng_next(rng) % (uint64_t)*n);
        return;
    }
    for (t = 0; t < m; ++t) {
        cloth_real c[3];
        int k, corner;
        for (k = 0; k < 3; ++k) c[k] = extent * cloth_rng_uniform(rng);
        for (corner = 0; corner < 3; ++corner) {
            (*tri)[3 * t + corner] = 3 * t + corner;
            for (k = 0; k < 3; ++k) (*x)[3 * (3 * t + corner) + k] = c[k] + size * cloth_rng_normal(rng);
        }
    }
}

/* Build over the arrays, check the tree, compare the self pairs with brute force. Returns 0
   when all agree, else a code (100 + tree problem, 2 build failed, 3 pairs differ, 4 a pair
   not a < b). */
static int self_matches(const cloth_real *x, const cloth_real *x1, int32_t n, const int32_t *tri, int32_t m,
                        const cloth_bvh_def *def, cloth_bvh *keep)
{
    cloth_bvh bvh;
    pair_list got, want;
    int code = 0, problem;
    size_t k;
    if (cloth_bvh_build(&bvh, x, x1, n, tri, m, def, NULL) != CLOTH_SUCCESS) return 2;
    problem = tree_problem(&bvh, x, x1, tri);
    if (problem) code = 100 + problem;
    pairs_init(&got);
    pairs_init(&want);
    if (!code && cloth_bvh_self_pairs(&bvh, collect_pair, &got) != 0) code = 5;
    for (k = 0; k < got.count && !code; ++k)
        if (!(got.ab[2 * k] < got.ab[2 * k + 1])) code = 4;
    brute_self(&want, x, x1, tri, m, def ? def->thickness : 0);
    if (!code && !pairs_same_set(&got, &want)) code = 3;
    pairs_free(&got);
    pairs_free(&want);
    if (keep) *keep = bvh;
    else cloth_bvh_free(&bvh);
    return code;
}

/* ---- tests ---------------------------------------------------------------------------- */

TEST(bvh_default_def)
{
    cloth_bvh_def def = cloth_default_bvh_def();
    ENSURE(def.thickness == 0);
    ENSURE(def.leaf_size == 2);
    ENSURE(def.split == CLOTH_BVH_SPLIT_SAH);
    ENSURE(def.rebuild_ratio == 2);
}

TEST(bvh_self_random_soups)
{
    static const int32_t sizes[] = { 2, 3, 5, 17, 64, 301, 1200 };
    static const double tri_sizes[] = { 0.002, 0.03, 0.2 };
    cloth_rng rng = cloth_rng_make(1);
    size_t s, z;
    int config = 0;
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; ++s)
        for (z = 0; z < sizeof tri_sizes / sizeof tri_sizes[0]; ++z) {
            cloth_real *x;
            int32_t *tri, n;
            cloth_bvh_def def = cloth_default_bvh_def();
            int shared = config % 3 == 2;
            make_soup(&rng, sizes[s], 1, (cloth_real)tri_sizes[z], shared, &x, &tri, &n);
            def.thickness = (cloth_real)(config % 2 ? 0.0 : 0.01);
            def.leaf_size = 1 + config % 8;
            def.split = config % 4 == 3 ? CLOTH_BVH_SPLIT_MEDIAN : CLOTH_BVH_SPLIT_SAH;
            ENSURE(self_matches(x, NULL, n, tri, sizes[s], &def, NULL) == 0);
            ++config;
            free(x);
            free(tri);
        }
}

/* cloth_bvh_self_pairs_within: the pairs whose boxes come within the margin, those of a tree
   whose boxes are grown by half the margin (brute force), on random soups; margin 0 gives
   cloth_bvh_self_pairs' pairs, and a larger margin never fewer; a negative, NaN or infinite
   margin is refused without a call. */
TEST(bvh_self_pairs_within_a_margin)
{
    static const double margins[] = { 0, 0.004, 0.03, 0.2 };
    cloth_rng rng = cloth_rng_make(5);
    int config;
    for (config = 0; config < 12; ++config) {
        cloth_real *x;
        int32_t *tri, n, m = config < 6 ? 200 : 700;
        cloth_bvh bvh;
        cloth_bvh_def def = cloth_default_bvh_def();
        size_t z, last = 0;
        make_soup(&rng, m, 1, (cloth_real)(config % 3 == 0 ? 0.01 : 0.04), config % 3 == 2, &x, &tri, &n);
        def.thickness = (cloth_real)(config % 2 ? 0.0 : 0.01);
        def.leaf_size = 1 + config % 4;
        ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
        for (z = 0; z < sizeof margins / sizeof margins[0]; ++z) {
            pair_list got, want;
            pairs_init(&got);
            pairs_init(&want);
            ENSURE(cloth_bvh_self_pairs_within(&bvh, (cloth_real)margins[z], collect_pair, &got) == 0);
            brute_self(&want, x, NULL, tri, m, (cloth_real)((double)def.thickness + margins[z] / 2));
            ENSURE(pairs_same_set(&got, &want));
            ENSURE(got.count >= last);
            last = got.count;
            if (z == 0) {
                pair_list plain;
                pairs_init(&plain);
                ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &plain) == 0);
                ENSURE(pairs_same_set(&got, &plain));
                pairs_free(&plain);
            }
            pairs_free(&got);
            pairs_free(&want);
        }
        ENSURE(last > 0);
        {
            pair_list none;
            pairs_init(&none);
            ENSURE(cloth_bvh_self_pairs_within(&bvh, (cloth_real)-0.01, collect_pair, &none) == CLOTH_ERROR_INVALID_ARGUMENT);
            ENSURE(cloth_bvh_self_pairs_within(&bvh, (cloth_real)NAN, collect_pair, &none) == CLOTH_ERROR_INVALID_ARGUMENT);
            ENSURE(cloth_bvh_self_pairs_within(&bvh, (cloth_real)INFINITY, collect_pair, &none) == CLOTH_ERROR_INVALID_ARGUMENT);
            ENSURE(none.count == 0);
            pairs_free(&none);
        }
        cloth_bvh_free(&bvh);
        free(x);
        free(tri);
    }
}

TEST(bvh_self_shared_vertex_soup_skips_adjacent)
{
    /* Large triangles over a small pool: nearly all boxes overlap, many share vertices. */
    cloth_rng rng = cloth_rng_make(2);
    cloth_real *x;
    int32_t *tri, n, m = 150;
    cloth_bvh bvh;
    pair_list got;
    size_t k;
    int adjacent_reported = 0;
    make_soup(&rng, m, 1, 0, 1, &x, &tri, &n);
    ENSURE(self_matches(x, NULL, n, tri, m, NULL, NULL) == 0);
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, NULL, NULL) == CLOTH_SUCCESS);
    pairs_init(&got);
    cloth_bvh_self_pairs(&bvh, collect_pair, &got);
    for (k = 0; k < got.count; ++k)
        if (share_vertex(tri + 3 * got.ab[2 * k], tri + 3 * got.ab[2 * k + 1])) adjacent_reported = 1;
    ENSURE(!adjacent_reported);
    ENSURE(got.count > 0);
    pairs_free(&got);
    cloth_bvh_free(&bvh);
    free(x);
    free(tri);
}

TEST(bvh_self_flat_and_degenerate_boxes)
{
    cloth_rng rng = cloth_rng_make(3);
    int kind;
    for (kind = 0; kind < 5; ++kind) {
        cloth_real *x;
        int32_t *tri, n, m = 240, v;
        cloth_bvh_def def = cloth_default_bvh_def();
        make_soup(&rng, m, 1, (cloth_real)0.05, 0, &x, &tri, &n);
        for (v = 0; v < n; ++v) {
            cloth_real *p = x + 3 * v;
            if (kind == 0) p[2] = 0;                               /* all in the plane z = 0: flat boxes */
            if (kind == 1) { p[1] = 0; p[2] = 0; }                 /* all on the x axis: boxes without area */
            if (kind == 2) { p[0] = (cloth_real)0.5; p[1] = (cloth_real)0.25; p[2] = 0; } /* one point */
            if (kind == 3) x[3 * v + 0] = x[3 * (v % 3) + 0];      /* a few x values: equal centroids */
            if (kind == 4) { p[0] = (cloth_real)floor((double)p[0] * 4) / 4; p[1] = 0; p[2] = (cloth_real)floor((double)p[2] * 4) / 4; }
        }
        def.thickness = kind == 2 ? 0 : (cloth_real)0.001;
        ENSURE(self_matches(x, NULL, n, tri, m, &def, NULL) == 0);
        def.thickness = 0;
        def.split = CLOTH_BVH_SPLIT_MEDIAN;
        ENSURE(self_matches(x, NULL, n, tri, m, &def, NULL) == 0);
        free(x);
        free(tri);
    }
}

TEST(bvh_self_folded_grid)
{
    cloth_real *x;
    int32_t *tri, n, m;
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    pair_list got;
    size_t k;
    int32_t cross_layer = 0;
    make_grid(31, 31, 1, &x, &tri, &n, &m);
    fold_grid(x, n, 1, (cloth_real)0.004);
    def.thickness = (cloth_real)0.005;
    ENSURE(self_matches(x, NULL, n, tri, m, &def, &bvh) == 0);
    /* The fold brings the two halves within the thickness: most pairs join the layers. */
    pairs_init(&got);
    cloth_bvh_self_pairs(&bvh, collect_pair, &got);
    for (k = 0; k < got.count; ++k) {
        const cloth_real *pa = x + 3 * tri[3 * got.ab[2 * k]], *pb = x + 3 * tri[3 * got.ab[2 * k + 1]];
        if (fabs((double)(pa[1] - pb[1])) > 0.006) ++cross_layer;
    }
    ENSURE(cross_layer > m / 2);
    def.split = CLOTH_BVH_SPLIT_MEDIAN;
    def.leaf_size = 1;
    ENSURE(self_matches(x, NULL, n, tri, m, &def, NULL) == 0);
    pairs_free(&got);
    cloth_bvh_free(&bvh);
    free(x);
    free(tri);
}

TEST(bvh_pairs_two_overlapping_meshes)
{
    cloth_real *xa, *xb;
    int32_t *ta, *tb, na, nb, ma, mb, v;
    cloth_bvh a, b;
    cloth_bvh_def da = cloth_default_bvh_def(), db = cloth_default_bvh_def();
    pair_list got, want, swapped;
    size_t k;
    make_grid(25, 25, 1, &xa, &ta, &na, &ma);
    make_grid(18, 18, (cloth_real)0.8, &xb, &tb, &nb, &mb);
    for (v = 0; v < na; ++v) xa[3 * v + 1] = (cloth_real)(0.05 * sin(6.0 * (double)xa[3 * v]) * cos(5.0 * (double)xa[3 * v + 2]));
    for (v = 0; v < nb; ++v) { /* a tilted, shifted sheet through the first */
        cloth_real px = xb[3 * v], pz = xb[3 * v + 2];
        xb[3 * v] = px + (cloth_real)0.13;
        xb[3 * v + 1] = (cloth_real)0.3 * (pz - (cloth_real)0.4);
        xb[3 * v + 2] = pz + (cloth_real)0.07;
    }
    da.thickness = (cloth_real)0.002;
    db.thickness = (cloth_real)0.01;
    db.leaf_size = 2;
    db.split = CLOTH_BVH_SPLIT_MEDIAN;
    ENSURE(cloth_bvh_build(&a, xa, NULL, na, ta, ma, &da, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&b, xb, NULL, nb, tb, mb, &db, NULL) == CLOTH_SUCCESS);
    pairs_init(&got);
    pairs_init(&want);
    pairs_init(&swapped);
    ENSURE(cloth_bvh_pairs(&a, &b, collect_pair, &got) == 0);
    brute_pairs(&want, xa, ta, ma, da.thickness, xb, tb, mb, db.thickness);
    ENSURE(want.count > 50);
    ENSURE(pairs_same_set(&got, &want));
    /* B against A gives the same pairs, transposed. */
    ENSURE(cloth_bvh_pairs(&b, &a, collect_pair, &swapped) == 0);
    for (k = 0; k < swapped.count; ++k) {
        int32_t t = swapped.ab[2 * k];
        swapped.ab[2 * k] = swapped.ab[2 * k + 1];
        swapped.ab[2 * k + 1] = t;
    }
    ENSURE(pairs_same_set(&swapped, &want));
    pairs_free(&got);
    pairs_free(&want);
    pairs_free(&swapped);
    cloth_bvh_free(&a);
    cloth_bvh_free(&b);
    free(xa);
    free(xb);
    free(ta);
    free(tb);
}

TEST(bvh_pairs_random_soups)
{
    cloth_rng rng = cloth_rng_make(4);
    int round;
    for (round = 0; round < 6; ++round) {
        cloth_real *xa, *xb;
        int32_t *ta, *tb, na, nb, ma = 1 + round * 97, mb = 1 + (5 - round) * 61;
        cloth_bvh a, b;
        cloth_bvh_def def = cloth_default_bvh_def();
        pair_list got, want;
        make_soup(&rng, ma, 1, (cloth_real)0.04, round % 2, &xa, &ta, &na);
        make_soup(&rng, mb, 1, (cloth_real)0.02, 0, &xb, &tb, &nb);
        def.thickness = (cloth_real)0.003 * (cloth_real)round;
        def.leaf_size = 1 + round;
        ENSURE(cloth_bvh_build(&a, xa, NULL, na, ta, ma, &def, NULL) == CLOTH_SUCCESS);
        ENSURE(cloth_bvh_build(&b, xb, NULL, nb, tb, mb, NULL, NULL) == CLOTH_SUCCESS);
        pairs_init(&got);
        pairs_init(&want);
        ENSURE(cloth_bvh_pairs(&a, &b, collect_pair, &got) == 0);
        brute_pairs(&want, xa, ta, ma, def.thickness, xb, tb, mb, 0);
        ENSURE(pairs_same_set(&got, &want));
        pairs_free(&got);
        pairs_free(&want);
        cloth_bvh_free(&a);
        cloth_bvh_free(&b);
        free(xa);
        free(xb);
        free(ta);
        free(tb);
    }
}

TEST(bvh_query_box_matches_brute_force)
{
    cloth_rng rng = cloth_rng_make(5);
    cloth_real *x, *boxes;
    int32_t *tri, n, m = 500, q;
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    int hits = 0;
    make_soup(&rng, m, 1, (cloth_real)0.03, 0, &x, &tri, &n);
    def.thickness = (cloth_real)0.004;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    boxes = all_boxes(x, NULL, tri, m, def.thickness);
    for (q = 0; q < 50; ++q) {
        cloth_real lo[3], hi[3];
        pair_list got, want;
        int k;
        int32_t t;
        for (k = 0; k < 3; ++k) {
            lo[k] = cloth_rng_uniform(&rng);
            hi[k] = lo[k] + (cloth_real)0.2 * cloth_rng_uniform(&rng) * (cloth_real)(q % 3);
        }
        pairs_init(&got);
        pairs_init(&want);
        ENSURE(cloth_bvh_query_box(&bvh, lo, hi, collect_triangle, &got) == 0);
        for (t = 0; t < m; ++t)
            if (boxes_overlap(boxes + 6 * t, boxes + 6 * t + 3, lo, hi)) pairs_push(&want, t, 0);
        hits += (int)want.count;
        ENSURE(pairs_same_set(&got, &want));
        pairs_free(&got);
        pairs_free(&want);
    }
    ENSURE(hits > 50);
    free(boxes);
    cloth_bvh_free(&bvh);
    free(x);
    free(tri);
}

TEST(bvh_refit_after_motion)
{
    cloth_rng rng = cloth_rng_make(6);
    cloth_real *x, *x0;
    int32_t *tri, n, m, v, step;
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    make_grid(28, 28, 1, &x, &tri, &n, &m);
    x0 = (cloth_real *)malloc(3 * (size_t)n * sizeof(cloth_real));
    if (!x0) abort();
    def.thickness = (cloth_real)0.003;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    memcpy(x0, x, 3 * (size_t)n * sizeof(cloth_real));
    for (step = 1; step <= 6; ++step) {
        pair_list got, want;
        /* crumple progressively: a wave that folds the sheet onto itself, plus noise */
        for (v = 0; v < n; ++v) {
            cloth_real u = x0[3 * v], w = x0[3 * v + 2], a = (cloth_real)0.25 * (cloth_real)step;
            x[3 * v] = (cloth_real)0.5 + (cloth_real)(0.5 * cos((double)(a * 3 * u))) * (u - (cloth_real)0.5) * 2 / (1 + a);
            x[3 * v + 1] = (cloth_real)(0.1 * sin((double)(a * 9 * u))) + (cloth_real)0.002 * cloth_rng_normal(&rng);
            x[3 * v + 2] = w + (cloth_real)0.01 * cloth_rng_normal(&rng);
        }
        ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
        ENSURE(tree_problem(&bvh, x, NULL, tri) == 0);
        /* a connected sheet keeps its neighbours: the tree stays as tight as a new one */
        ENSURE(cloth_bvh_quality(&bvh) < (cloth_real)1.5 && !cloth_bvh_needs_rebuild(&bvh));
        pairs_init(&got);
        pairs_init(&want);
        ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
        brute_self(&want, x, NULL, tri, m, def.thickness);
        ENSURE(pairs_same_set(&got, &want));
        pairs_free(&got);
        pairs_free(&want);
    }
    /* the thickness may change between refits */
    bvh.def.thickness = (cloth_real)0.02;
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(tree_problem(&bvh, x, NULL, tri) == 0);
    ENSURE(self_matches(x, NULL, n, tri, m, &bvh.def, NULL) == 0);
    cloth_bvh_free(&bvh);
    free(x);
    free(x0);
    free(tri);
}

TEST(bvh_swept_boxes)
{
    cloth_rng rng = cloth_rng_make(7);
    cloth_real *x0, *x1;
    int32_t *tri, n, m = 400, i, v;
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    pair_list got, want;
    make_soup(&rng, m, 1, (cloth_real)0.01, 0, &x0, &tri, &n);
    x1 = (cloth_real *)malloc(3 * (size_t)n * sizeof(cloth_real));
    if (!x1) abort();
    for (v = 0; v < 3 * n; ++v) x1[v] = x0[v] + (cloth_real)0.05 * cloth_rng_normal(&rng);
    def.thickness = (cloth_real)0.001;
    ENSURE(self_matches(x0, x1, n, tri, m, &def, &bvh) == 0);
    /* every box holds its triangle at both ends of the step, grown by the thickness, and the
       midpoint of the motion */
    for (i = 0; i < m; ++i) {
        const cloth_bvh_box *b = bvh.item_box + i;
        int32_t t = bvh.item_triangle[i];
        int c, k;
        for (c = 0; c < 3; ++c)
            for (k = 0; k < 3; ++k) {
                cloth_real p = x0[3 * tri[3 * t + c] + k], q = x1[3 * tri[3 * t + c] + k], mid = (p + q) / 2;
                ENSURE(b->lo[k] <= p - def.thickness && b->hi[k] >= p + def.thickness);
                ENSURE(b->lo[k] <= q - def.thickness && b->hi[k] >= q + def.thickness);
                ENSURE(b->lo[k] <= mid && b->hi[k] >= mid);
            }
    }
    /* a refit with the ends swapped gives the same boxes; one without x1 the static ones */
    ENSURE(cloth_bvh_refit(&bvh, x1, x0) == CLOTH_SUCCESS);
    ENSURE(tree_problem(&bvh, x0, x1, tri) == 0);
    ENSURE(cloth_bvh_refit(&bvh, x1, NULL) == CLOTH_SUCCESS);
    ENSURE(tree_problem(&bvh, x1, NULL, tri) == 0);
    pairs_init(&got);
    pairs_init(&want);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    brute_self(&want, x1, NULL, tri, m, def.thickness);
    ENSURE(pairs_same_set(&got, &want));
    pairs_free(&got);
    pairs_free(&want);
    cloth_bvh_free(&bvh);
    free(x0);
    free(x1);
    free(tri);
}

TEST(bvh_swept_finds_pass_through)
{
    /* A triangle falls through another during the step: apart at both ends, met in between. */
    const cloth_real x0[18] = { 0, 0, 0, 1, 0, 0, 0, 0, 1,   0.2f, 1, 0.2f, 0.7f, 1, 0.2f, 0.2f, 1, 0.7f };
    cloth_real x1[18];
    const int32_t tri[6] = { 0, 1, 2, 3, 4, 5 };
    cloth_bvh bvh;
    pair_list got;
    int v;
    memcpy(x1, x0, sizeof x1);
    for (v = 3; v < 6; ++v) x1[3 * v + 1] = -1;
    pairs_init(&got);
    ENSURE(cloth_bvh_build(&bvh, x0, NULL, 6, tri, 2, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    ENSURE(got.count == 0);
    ENSURE(cloth_bvh_refit(&bvh, x1, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    ENSURE(got.count == 0);
    ENSURE(cloth_bvh_refit(&bvh, x0, x1) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    ENSURE(got.count == 1 && got.ab[0] == 0 && got.ab[1] == 1);
    pairs_free(&got);
    cloth_bvh_free(&bvh);
}

TEST(bvh_quality_and_rebuild)
{
    cloth_rng rng = cloth_rng_make(8);
    cloth_real *x, *x0;
    int32_t *tri, n, m, v;
    cloth_bvh bvh, fresh;
    cloth_bvh_def def = cloth_default_bvh_def();
    cloth_real scrambled_cost;
    pair_list a, b;
    make_grid(30, 30, 1, &x, &tri, &n, &m);
    x0 = (cloth_real *)malloc(3 * (size_t)n * sizeof(cloth_real));
    if (!x0) abort();
    memcpy(x0, x, 3 * (size_t)n * sizeof(cloth_real));
    def.thickness = (cloth_real)0.001;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) == 1);
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) == 1);
    ENSURE(!cloth_bvh_needs_rebuild(&bvh));
    /* a gentle wave and a translation keep the layout: the quality stays near 1 */
    for (v = 0; v < n; ++v) {
        x[3 * v] = x0[3 * v] + 3;
        x[3 * v + 1] = (cloth_real)(0.05 * sin(4.0 * (double)x0[3 * v]));
    }
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) > (cloth_real)0.8 && cloth_bvh_quality(&bvh) < (cloth_real)1.25);
    ENSURE(!cloth_bvh_needs_rebuild(&bvh));
    /* scramble: every vertex jumps to a random place in the same square. The triangles grow
       long, the tree with them, and a new tree would be little tighter: the quality does
       not ask for a rebuild (it compares nodes with the triangles they hold). */
    for (v = 0; v < n; ++v) {
        x[3 * v] = cloth_rng_uniform(&rng);
        x[3 * v + 1] = (cloth_real)0.01 * cloth_rng_uniform(&rng);
        x[3 * v + 2] = cloth_rng_uniform(&rng);
    }
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) < 2);
    ENSURE(!cloth_bvh_needs_rebuild(&bvh));
    scrambled_cost = bvh.cost;
    ENSURE(cloth_bvh_rebuild(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) == 1);
    ENSURE(!cloth_bvh_needs_rebuild(&bvh));
    ENSURE(bvh.cost < scrambled_cost && bvh.cost > scrambled_cost / 2);
    ENSURE(tree_problem(&bvh, x, NULL, tri) == 0);
    /* a rebuild equals a fresh build: same nodes, same slots, same pairs in the same order */
    ENSURE(cloth_bvh_build(&fresh, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    ENSURE(fresh.node_count == bvh.node_count && fresh.depth == bvh.depth);
    ENSURE(memcmp(fresh.nodes, bvh.nodes, (size_t)bvh.node_count * sizeof(cloth_bvh_node)) == 0);
    ENSURE(memcmp(fresh.item_triangle, bvh.item_triangle, (size_t)m * sizeof(int32_t)) == 0);
    pairs_init(&a);
    pairs_init(&b);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &a) == 0);
    ENSURE(cloth_bvh_self_pairs(&fresh, collect_pair, &b) == 0);
    ENSURE(a.count > 0 && pairs_identical(&a, &b));
    pairs_free(&b);
    brute_self(&b, x, NULL, tri, m, def.thickness);
    ENSURE(pairs_same_set(&a, &b));
    /* the rule follows the ratio */
    bvh.def.rebuild_ratio = 1;
    ENSURE(cloth_bvh_needs_rebuild(&bvh) == (cloth_bvh_quality(&bvh) > 1));
    ENSURE(cloth_bvh_refit(&bvh, x0, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_needs_rebuild(&bvh) == (cloth_bvh_quality(&bvh) > 1));
    /* a rebuild may change the leaf size and split */
    bvh.def.leaf_size = 1;
    bvh.def.split = CLOTH_BVH_SPLIT_MEDIAN;
    ENSURE(cloth_bvh_rebuild(&bvh, x0, NULL) == CLOTH_SUCCESS);
    ENSURE(tree_problem(&bvh, x0, NULL, tri) == 0);
    ENSURE(bvh.node_count == 2 * m - 1);
    bvh.def.leaf_size = 0;
    ENSURE(cloth_bvh_rebuild(&bvh, x0, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    pairs_free(&a);
    pairs_free(&b);
    cloth_bvh_free(&bvh);
    cloth_bvh_free(&fresh);
    free(x);
    free(x0);
    free(tri);
}

TEST(bvh_quality_after_teleport)
{
    /* Small separate triangles each jump to a random place keeping their shape: the old
       splits are useless, a new tree is as good as the first. */
    cloth_rng rng = cloth_rng_make(10);
    cloth_real *x;
    int32_t *tri, n, m = 2000, t;
    cloth_bvh bvh;
    cloth_real first_cost, teleported_cost;
    make_soup(&rng, m, 1, (cloth_real)0.005, 0, &x, &tri, &n);
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, NULL, NULL) == CLOTH_SUCCESS);
    first_cost = bvh.cost;
    for (t = 0; t < m; ++t) {
        cloth_real d[3];
        int k, c;
        for (k = 0; k < 3; ++k) d[k] = cloth_rng_uniform(&rng) - x[9 * t + k];
        for (c = 0; c < 3; ++c)
            for (k = 0; k < 3; ++k) x[9 * t + 3 * c + k] += d[k];
    }
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    teleported_cost = bvh.cost;
    ENSURE(cloth_bvh_quality(&bvh) > 10);
    ENSURE(cloth_bvh_needs_rebuild(&bvh));
    bvh.def.rebuild_ratio = (cloth_real)HUGE_VAL; /* a ratio never reached never asks */
    ENSURE(!cloth_bvh_needs_rebuild(&bvh));
    bvh.def.rebuild_ratio = 2;
    ENSURE(cloth_bvh_rebuild(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&bvh) == 1);
    ENSURE(bvh.cost < teleported_cost / 10);
    ENSURE(bvh.cost < first_cost * 2 && bvh.cost > first_cost / 2);
    ENSURE(self_matches(x, NULL, n, tri, m, NULL, NULL) == 0);
    cloth_bvh_free(&bvh);
    free(x);
    free(tri);
}

TEST(bvh_empty_and_single_triangle)
{
    const cloth_real x[9] = { 0, 0, 0, 1, 0, 0, 0, 1, 0 };
    const int32_t tri[3] = { 0, 1, 2 };
    const cloth_real lo[3] = { 0.5f, 0.25f, -1 }, hi[3] = { 2, 2, 1 }, far_lo[3] = { 2, 2, 2 }, far_hi[3] = { 3, 3, 3 };
    cloth_bvh empty, empty2, one, one2;
    pair_list got;
    pairs_init(&got);
    ENSURE(cloth_bvh_build(&empty, NULL, NULL, 0, NULL, 0, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(empty.node_count == 0 && empty.triangle_count == 0 && empty.depth == 0);
    ENSURE(cloth_bvh_build(&empty2, x, x, 3, tri, 0, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&one, x, NULL, 3, tri, 1, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(one.node_count == 1 && one.nodes[0].count == 1 && one.depth == 0);
    ENSURE(tree_problem(&one, x, NULL, tri) == 0);
    ENSURE(cloth_bvh_build(&one2, x, NULL, 3, tri, 1, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_self_pairs(&empty, collect_pair, &got) == 0);
    ENSURE(cloth_bvh_self_pairs(&empty2, collect_pair, &got) == 0);
    ENSURE(cloth_bvh_self_pairs(&one, collect_pair, &got) == 0);
    ENSURE(cloth_bvh_pairs(&empty, &one, collect_pair, &got) == 0);
    ENSURE(cloth_bvh_pairs(&one, &empty, collect_pair, &got) == 0);
    ENSURE(cloth_bvh_query_box(&empty, lo, hi, collect_triangle, &got) == 0);
    ENSURE(cloth_bvh_query_box(&one, far_lo, far_hi, collect_triangle, &got) == 0);
    ENSURE(got.count == 0);
    ENSURE(cloth_bvh_pairs(&one, &one2, collect_pair, &got) == 0);
    ENSURE(got.count == 1 && got.ab[0] == 0 && got.ab[1] == 0);
    ENSURE(cloth_bvh_query_box(&one, lo, hi, collect_triangle, &got) == 0);
    ENSURE(got.count == 2 && got.ab[2] == 0);
    ENSURE(cloth_bvh_refit(&empty, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_rebuild(&empty, NULL, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_refit(&one, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_quality(&empty) == 1 && cloth_bvh_quality(&one) == 1);
    ENSURE(!cloth_bvh_needs_rebuild(&empty));
    pairs_free(&got);
    cloth_bvh_free(&empty);
    cloth_bvh_free(&empty2);
    cloth_bvh_free(&one);
    cloth_bvh_free(&one2);
    cloth_bvh_free(&one2); /* free leaves it empty; freeing again is harmless */
    ENSURE(one2.nodes == NULL && one2.node_count == 0);
}

static int bvh_is_empty(const cloth_bvh *b)
{
    return !b->nodes && !b->item_box && !b->item_triangle && !b->item_vertex && b->node_count == 0 && b->triangle_count == 0;
}

TEST(bvh_bad_input)
{
    cloth_real x[12] = { 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0 };
    cloth_real x1[12];
    int32_t tri[6] = { 0, 1, 2, 1, 3, 2 };
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    counting_allocator c;
    cloth_allocator a = make_counting(&c, -1);
    cloth_bvh_node saved[3];
    memcpy(x1, x, sizeof x1);
    ENSURE(cloth_bvh_build(&bvh, NULL, NULL, 4, tri, 2, NULL, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(bvh_is_empty(&bvh));
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, NULL, 2, NULL, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_bvh_build(&bvh, x, NULL, -1, tri, 2, NULL, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, -2, NULL, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.thickness = -1;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.thickness = (cloth_real)NAN;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.thickness = 0;
    def.leaf_size = 0;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.leaf_size = CLOTH_BVH_MAX_LEAF_SIZE + 1;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.leaf_size = 4;
    def.rebuild_ratio = (cloth_real)0.5;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INVALID_ARGUMENT);
    def.rebuild_ratio = 2;
    tri[4] = 4;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    ENSURE(bvh_is_empty(&bvh));
    tri[4] = -1;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    tri[4] = 3;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 3, tri, 2, &def, &a) == CLOTH_ERROR_INDEX_OUT_OF_RANGE);
    x[7] = (cloth_real)NAN;
    ENSURE(cloth_bvh_build(&bvh, x, NULL, 4, tri, 2, &def, &a) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(bvh_is_empty(&bvh));
    x[7] = 1;
    x1[11] = (cloth_real)HUGE_VAL;
    ENSURE(cloth_bvh_build(&bvh, x, x1, 4, tri, 2, &def, &a) == CLOTH_ERROR_NOT_FINITE);
    x1[11] = 0;
    ENSURE(c.allocs == 0 && c.live == 0);
    /* refit and rebuild refuse bad positions and leave the tree as it was */
    ENSURE(cloth_bvh_build(&bvh, x, x1, 4, tri, 2, &def, &a) == CLOTH_SUCCESS);
    ENSURE(bvh.node_count <= 3);
    memcpy(saved, bvh.nodes, (size_t)bvh.node_count * sizeof(cloth_bvh_node));
    x1[0] = (cloth_real)NAN;
    ENSURE(cloth_bvh_refit(&bvh, x, x1) == CLOTH_ERROR_NOT_FINITE);
    ENSURE(cloth_bvh_rebuild(&bvh, x, x1) == CLOTH_ERROR_NOT_FINITE);
    x1[0] = 5;
    x[2] = -(cloth_real)HUGE_VAL;
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_ERROR_NOT_FINITE);
    x[2] = 0;
    ENSURE(cloth_bvh_refit(&bvh, NULL, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    bvh.def.thickness = -1;
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_ERROR_INVALID_ARGUMENT);
    bvh.def.thickness = 0;
    ENSURE(memcmp(saved, bvh.nodes, (size_t)bvh.node_count * sizeof(cloth_bvh_node)) == 0);
    ENSURE(cloth_bvh_refit(&bvh, x, x1) == CLOTH_SUCCESS);
    ENSURE(bvh.nodes[0].box.hi[0] == 5);
    cloth_bvh_free(&bvh);
    ENSURE(c.live == 0);
}

TEST(bvh_allocations)
{
    cloth_real *x;
    int32_t *tri, n, m;
    cloth_bvh bvh, other;
    counting_allocator c;
    cloth_allocator a = make_counting(&c, -1);
    const cloth_real lo[3] = { 0, -1, 0 }, hi[3] = { 0.5f, 1, 0.5f };
    pair_list got;
    long after_build, k;
    make_grid(20, 20, 1, &x, &tri, &n, &m);
    ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, NULL, &a) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&other, x, x, n, tri, m, NULL, &a) == CLOTH_SUCCESS);
    after_build = c.allocs;
    ENSURE(after_build > 0 && c.live == after_build);
    pairs_init(&got);
    pairs_push(&got, 0, 0); /* the test's own list allocates before, not during, the calls */
    got.count = 0;
    x[4] = (cloth_real)0.01;
    ENSURE(cloth_bvh_refit(&bvh, x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_refit(&other, x, x) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_rebuild(&bvh, x, NULL) == CLOTH_SUCCESS);
    got.stop_after = 1;
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 7 && got.count == 1);
    got.count = 0;
    ENSURE(cloth_bvh_pairs(&bvh, &other, collect_pair, &got) == 7);
    got.count = 0;
    ENSURE(cloth_bvh_query_box(&bvh, lo, hi, collect_triangle, &got) == 9);
    ENSURE(cloth_bvh_quality(&bvh) == 1 && !cloth_bvh_needs_rebuild(&bvh));
    ENSURE(c.allocs == after_build);
    cloth_bvh_free(&bvh);
    cloth_bvh_free(&other);
    ENSURE(c.live == 0 && c.frees == after_build);
    /* a failing allocator at each allocation in turn: out of memory, nothing leaked */
    for (k = 0; k < after_build / 2; ++k) {
        a = make_counting(&c, k);
        ENSURE(cloth_bvh_build(&bvh, x, NULL, n, tri, m, NULL, &a) == CLOTH_ERROR_OUT_OF_MEMORY);
        ENSURE(bvh_is_empty(&bvh));
        ENSURE(c.live == 0);
    }
    pairs_free(&got);
    free(x);
    free(tri);
}

TEST(bvh_early_stop_and_determinism)
{
    cloth_rng rng = cloth_rng_make(9);
    cloth_real *x;
    int32_t *tri, n, m = 700;
    cloth_bvh a, b;
    cloth_bvh_def def = cloth_default_bvh_def();
    pair_list all, again, part;
    size_t k;
    make_soup(&rng, m, 1, (cloth_real)0.05, 0, &x, &tri, &n);
    def.thickness = (cloth_real)0.01;
    ENSURE(cloth_bvh_build(&a, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&b, x, NULL, n, tri, m, &def, NULL) == CLOTH_SUCCESS);
    pairs_init(&all);
    pairs_init(&again);
    ENSURE(cloth_bvh_self_pairs(&a, collect_pair, &all) == 0);
    ENSURE(cloth_bvh_self_pairs(&b, collect_pair, &again) == 0);
    ENSURE(all.count > 100);
    ENSURE(pairs_identical(&all, &again)); /* the same order, not only the same set */
    for (k = 1; k < 40; k += 7) {
        pairs_init(&part);
        part.stop_after = k;
        ENSURE(cloth_bvh_self_pairs(&a, collect_pair, &part) == 7);
        ENSURE(part.count == k && memcmp(part.ab, all.ab, 2 * k * sizeof(int32_t)) == 0);
        pairs_free(&part);
    }
    pairs_free(&again);
    pairs_init(&again);
    ENSURE(cloth_bvh_pairs(&a, &b, collect_pair, &again) == 0);
    /* the tree against its twin: every overlapping pair both ways, and each triangle with
       itself (the soup's triangles share no vertices, so the self pairs are all the others) */
    ENSURE(again.count == 2 * all.count + (size_t)m);
    pairs_free(&again);
    pairs_free(&all);
    cloth_bvh_free(&a);
    cloth_bvh_free(&b);
    free(x);
    free(tri);
}

TEST(bvh_depth_stays_bounded)
{
    /* Triangles at geometrically growing distances: the binned SAH peels off one far triangle
       at a time, so without the median fallback the tree would be as deep as it is long. */
    int32_t m = 300, t, n = 3 * m;
    cloth_real *x = (cloth_real *)malloc(3 * (size_t)n * sizeof(cloth_real));
    int32_t *tri = (int32_t *)malloc(3 * (size_t)m * sizeof(int32_t));
    cloth_bvh_def def = cloth_default_bvh_def();
    cloth_bvh bvh;
    if (!x || !tri) abort();
    for (t = 0; t < m; ++t) {
        cloth_real c = (cloth_real)pow(1.25, (double)t);
        int corner;
        for (corner = 0; corner < 3; ++corner) {
            cloth_real *p = x + 3 * (3 * t + corner);
            tri[3 * t + corner] = 3 * t + corner;
            p[0] = c + (cloth_real)(corner == 1) * c / 2;
            p[1] = (cloth_real)(corner == 2) * c / 2;
            p[2] = (cloth_real)(t % 5);
        }
    }
    def.leaf_size = 1;
    ENSURE(self_matches(x, NULL, n, tri, m, &def, &bvh) == 0);
    ENSURE(bvh.depth <= CLOTH_BVH_MAX_DEPTH);
    ENSURE(bvh.depth >= CLOTH_BVH_MAX_DEPTH / 2); /* the fallback was needed here */
    cloth_bvh_free(&bvh);
    free(x);
    free(tri);
}

/* ---- real meshes from the mesh module ------------------------------------------------ */

TEST(bvh_real_pleated_grid)
{
    /* A 48 x 48 grid pleated like an accordion: strips of width 0.1 stacked 3 mm apart, with
       noise, so that every layer lies within the thickness of the next. */
    cloth_rng rng = cloth_rng_make(11);
    cloth_mesh mesh;
    cloth_bvh bvh;
    cloth_bvh_def def = cloth_default_bvh_def();
    pair_list got, want;
    int32_t v;
    ENSURE(cloth_mesh_grid(&mesh, 48, 48, 1, 1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    for (v = 0; v < mesh.vertex_count; ++v) {
        cloth_real *p = mesh.x + 3 * v, u = p[0] + (cloth_real)0.5;
        double layer = floor((double)u / 0.1), f = (double)u / 0.1 - layer;
        p[0] = (cloth_real)(0.1 * (((int)layer % 2) ? 1.0 - f : f));
        p[1] = (cloth_real)(0.003 * (layer + (((int)layer % 2) ? 1.0 - f : f))) + (cloth_real)0.0003 * cloth_rng_normal(&rng);
    }
    def.thickness = (cloth_real)0.002;
    ENSURE(self_matches(mesh.x, NULL, mesh.vertex_count, mesh.tri, mesh.triangle_count, &def, &bvh) == 0);
    pairs_init(&got);
    pairs_init(&want);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    ENSURE(got.count > (size_t)mesh.triangle_count); /* the layers meet everywhere */
    /* move on: a refit after more noise still matches */
    for (v = 0; v < 3 * mesh.vertex_count; ++v) mesh.x[v] += (cloth_real)0.0005 * cloth_rng_normal(&rng);
    ENSURE(cloth_bvh_refit(&bvh, mesh.x, NULL) == CLOTH_SUCCESS);
    pairs_free(&got);
    ENSURE(cloth_bvh_self_pairs(&bvh, collect_pair, &got) == 0);
    brute_self(&want, mesh.x, NULL, mesh.tri, mesh.triangle_count, def.thickness);
    ENSURE(pairs_same_set(&got, &want));
    ENSURE(cloth_bvh_quality(&bvh) < (cloth_real)1.2);
    pairs_free(&got);
    pairs_free(&want);
    cloth_bvh_free(&bvh);
    cloth_mesh_free(&mesh);
}

TEST(bvh_real_icosphere)
{
    /* A round sphere: only near neighbours that share no vertex are candidates. Squashed flat,
       the top and bottom halves meet too. */
    cloth_mesh mesh;
    cloth_bvh_def def = cloth_default_bvh_def();
    pair_list want;
    int32_t v;
    ENSURE(cloth_mesh_icosphere(&mesh, 1, 3, NULL) == CLOTH_SUCCESS);
    def.thickness = (cloth_real)0.01;
    ENSURE(self_matches(mesh.x, NULL, mesh.vertex_count, mesh.tri, mesh.triangle_count, &def, NULL) == 0);
    pairs_init(&want);
    brute_self(&want, mesh.x, NULL, mesh.tri, mesh.triangle_count, def.thickness);
    ENSURE(want.count > 0);
    pairs_free(&want);
    for (v = 0; v < mesh.vertex_count; ++v) mesh.x[3 * v + 1] *= (cloth_real)0.01;
    def.split = CLOTH_BVH_SPLIT_MEDIAN;
    ENSURE(self_matches(mesh.x, NULL, mesh.vertex_count, mesh.tri, mesh.triangle_count, &def, NULL) == 0);
    def.split = CLOTH_BVH_SPLIT_SAH;
    def.leaf_size = 2;
    ENSURE(self_matches(mesh.x, NULL, mesh.vertex_count, mesh.tri, mesh.triangle_count, &def, NULL) == 0);
    cloth_mesh_free(&mesh);
}

TEST(bvh_real_cloth_falling_on_sphere)
{
    /* Cloth against obstacle: a grid falls over a step onto an icosphere; swept cloth boxes
       against the static sphere, and two overlapping grids against each other. */
    cloth_mesh cloth, sphere, other;
    cloth_real *x1;
    cloth_bvh a, b, c;
    cloth_bvh_def da = cloth_default_bvh_def(), db = cloth_default_bvh_def();
    pair_list got, want;
    int32_t v;
    ENSURE(cloth_mesh_grid(&cloth, 33, 33, 3, 3, CLOTH_GRID_DIAGONAL_REGULAR, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_icosphere(&sphere, 1, 3, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_mesh_grid(&other, 20, 30, 2, 2, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) == CLOTH_SUCCESS);
    x1 = (cloth_real *)malloc(3 * (size_t)cloth.vertex_count * sizeof(cloth_real));
    if (!x1) abort();
    for (v = 0; v < cloth.vertex_count; ++v) {
        cloth.x[3 * v + 1] = (cloth_real)1.02;
        x1[3 * v] = cloth.x[3 * v];
        x1[3 * v + 1] = (cloth_real)(1.02 - 0.1 - 0.05 * cos(2.0 * (double)cloth.x[3 * v]));
        x1[3 * v + 2] = cloth.x[3 * v + 2];
    }
    for (v = 0; v < other.vertex_count; ++v) { /* tilted through the cloth's end position */
        cloth_real px = other.x[3 * v];
        other.x[3 * v] = px * (cloth_real)0.8;
        other.x[3 * v + 1] = (cloth_real)0.9 + (cloth_real)0.6 * px;
    }
    da.thickness = (cloth_real)0.005;
    db.thickness = (cloth_real)0.001;
    ENSURE(cloth_bvh_build(&a, cloth.x, x1, cloth.vertex_count, cloth.tri, cloth.triangle_count, &da, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&b, sphere.x, NULL, sphere.vertex_count, sphere.tri, sphere.triangle_count, &db, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_build(&c, other.x, NULL, other.vertex_count, other.tri, other.triangle_count, &db, NULL) == CLOTH_SUCCESS);
    pairs_init(&got);
    pairs_init(&want);
    ENSURE(cloth_bvh_pairs(&a, &b, collect_pair, &got) == 0);
    brute_pairs_swept(&want, cloth.x, x1, cloth.tri, cloth.triangle_count, da.thickness, sphere.x, NULL, sphere.tri,
                      sphere.triangle_count, db.thickness);
    ENSURE(want.count > 0);
    ENSURE(pairs_same_set(&got, &want));
    pairs_free(&got);
    pairs_free(&want);
    ENSURE(cloth_bvh_pairs(&a, &c, collect_pair, &got) == 0);
    brute_pairs_swept(&want, cloth.x, x1, cloth.tri, cloth.triangle_count, da.thickness, other.x, NULL, other.tri,
                      other.triangle_count, db.thickness);
    ENSURE(want.count > 0);
    ENSURE(pairs_same_set(&got, &want));
    /* without the sweep the cloth at its start is clear of the sphere */
    pairs_free(&got);
    ENSURE(cloth_bvh_refit(&a, cloth.x, NULL) == CLOTH_SUCCESS);
    ENSURE(cloth_bvh_pairs(&a, &b, collect_pair, &got) == 0);
    ENSURE(got.count == 0);
    pairs_free(&got);
    pairs_free(&want);
    cloth_bvh_free(&a);
    cloth_bvh_free(&b);
    cloth_bvh_free(&c);
    cloth_mesh_free(&cloth);
    cloth_mesh_free(&sphere);
    cloth_mesh_free(&other);
    free(x1);
}

const test_case bvh_tests[] = {
    { "default_def", bvh_default_def },
    { "self_random_soups", bvh_self_random_soups },
    { "self_pairs_within_a_margin", bvh_self_pairs_within_a_margin },
    { "self_shared_vertex_soup_skips_adjacent", bvh_self_shared_vertex_soup_skips_adjacent },
    { "self_flat_and_degenerate_boxes", bvh_self_flat_and_degenerate_boxes },
    { "self_folded_grid", bvh_self_folded_grid },
    { "pairs_two_overlapping_meshes", bvh_pairs_two_overlapping_meshes },
    { "pairs_random_soups", bvh_pairs_random_soups },
    { "query_box_matches_brute_force", bvh_query_box_matches_brute_force },
    { "refit_after_motion", bvh_refit_after_motion },
    { "swept_boxes", bvh_swept_boxes },
    { "swept_finds_pass_through", bvh_swept_finds_pass_through },
    { "quality_and_rebuild", bvh_quality_and_rebuild },
    { "quality_after_teleport", bvh_quality_after_teleport },
    { "empty_and_single_triangle", bvh_empty_and_single_triangle },
    { "bad_input", bvh_bad_input },
    { "allocations", bvh_allocations },
    { "early_stop_and_determinism", bvh_early_stop_and_determinism },
    { "depth_stays_bounded", bvh_depth_stays_bounded },
    { "real_pleated_grid", bvh_real_pleated_grid },
    { "real_icosphere", bvh_real_icosphere },
    { "real_cloth_falling_on_sphere", bvh_real_cloth_falling_on_sphere },
    { NULL, NULL }
};
