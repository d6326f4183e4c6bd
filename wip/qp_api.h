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
   1983) on the primal, in the scaled variables y = sqrt(W) (z - x) of the immovable-free part,
   where the problem becomes the minimum-norm point of a polyhedron: minimize |y|^2 / 2 subject
   to A y >= b (A_j = -G_j sqrt(W)^-1 restricted to movable vertices, b_j = g_j(x)). It starts
   from the unconstrained minimum z = x and repeatedly takes the most violated row (violation
   divided by |A_j|), adds it to a working set of rows held as equalities, and drops rows
   whose multiplier would turn negative. It keeps the Cholesky factor R of A_S A_S^T (S the
   working set), that is the R of the QR factorization A_S^T = Q R, updated by one column on
   each addition (from the projection of the new row off the working rows, computed twice
   over so that rounding does not accumulate) and by Givens rotations on each deletion. The
   rows are sparse (at most 4 vertices), so one step costs O(q^2 + (rows + vertices)) for a
   working set of q rows and no dense matrix of the zone's size is ever formed. When no row is
   violated the multipliers of the working set are solved for again from R with two steps of
   iterative refinement, and z is formed from them: the answer is the exact solution to
   rounding, not the end of an iteration with a tolerance. The method is finite: each addition
   strictly increases |y|, so no working set repeats.

   DEGENERACY. A row is linearly dependent on the working set when its projection off the
   working rows keeps at most dependency_tolerance of its length (duplicate rows, more than
   three rows on one vertex, parallel normals on a vertex pair...). Such a row is never added;
   instead (Goldfarb-Idnani's pure dual step) a working row is dropped in exchange when that
   keeps the multipliers non-negative, and the problem is infeasible when none can be: then
   the row contradicts the working rows (a Farkas certificate). So the working set stays
   linearly independent and the multipliers are supported on it: among duplicate rows, the
   one added first carries the whole multiplier and the others get 0. Rows over immovable
   vertices only (or with zero weights or normal) are constants: satisfied, they never act;
   violated, the problem is infeasible.

   RESULT. active[j] says how row j stands at z (cloth_qp_row_state): CLOTH_QP_ACTIVE rows form
   a maximal linearly independent set of the tight rows, namely the working set (which carries
   all of lambda) extended, in row order, by tight rows independent of it (lambda_j = 0);
   CLOTH_QP_TIGHT rows meet their bound too but depend on the active rows (lambda_j = 0);
   CLOTH_QP_INACTIVE rows have slack (lambda_j = 0). "Tight" means
   g_j(z) >= -active_tolerance scale_j with scale_j = |t_j| + sum_k |a_jk| |n_j| |z_(v_jk)|, the
   size of the terms whose rounding g_j suffers. The active rows are those the backward pass
   treats as equalities, which is the choice of DiffSim (all rows with |g_j| below a
   tolerance, dependent columns dropped).

   ERRORS. Infeasible problems (a violated row over immovable vertices only, contradictory
   rows) return CLOTH_ERROR_COLLISION_UNRESOLVED, as does the (never expected) iteration cap.
   On every error z = x, lambda = 0 and active = CLOTH_QP_INACTIVE, so a caller can keep going
   with the positions it had.

   PRECISION. Everything is computed in double whatever cloth_real is; with CLOTH_REAL float
   the results are rounded to float at the end, so the returned z meets the rows to float
   rounding (about 1e-7 of the coordinates), not to double rounding. The row states are decided
   on the double solution. Results are deterministic: the same inputs give bit-identical
   outputs (fixed loop orders, ties broken by the lower row index).

   MEMORY. A cloth_qp_workspace holds all scratch memory in one block of about
   8 (21 n + 21 m + q_max^2) bytes (n vertices, m rows, q_max = min(m, 3 movable vertices)); it
   grows when a problem exceeds every problem before it and allocates nothing otherwise.
   Passing NULL for the workspace makes a temporary one with the default allocator.
   One workspace serves one call at a time.

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
    CLOTH_QP_INACTIVE = 0, /* slack: g_j(z) < -active_tolerance scale_j; lambda_j = 0 */
    CLOTH_QP_ACTIVE = 1,   /* tight and part of a linearly independent set that carries the
                              multipliers; lambda_j >= 0; an equality for the backward pass */
    CLOTH_QP_TIGHT = 2     /* tight but linearly dependent on the active rows (or a constant
                              row over immovable vertices only); lambda_j = 0 */
} cloth_qp_row_state;

/* Options of cloth_qp_project and cloth_qp_backward; make them with cloth_qp_default_options()
   and change fields. All tolerances are relative. */
typedef struct cloth_qp_options {
    cloth_real feasibility_tolerance; /* > 0: the solver counts row j as violated when
                                         g_j > this x (scale_j + |A_j| |y|), the size of the
                                         rounding errors of g_j. 1e-12 */
    cloth_real active_tolerance;      /* >= 0: row j is tight at the solution when
                                         g_j(z) >= -this x scale_j (see RESULT above). 1e-9 */
    cloth_real dependency_tolerance;  /* in (0, 1): a row whose projection off the working rows
                                         (in the metric W^-1) keeps at most this fraction of its
                                         length counts as linearly dependent on them. 1e-10 */
    int32_t max_iterations;           /* >= 0: cap on additions plus deletions of working rows;
                                         0 = automatic, 10 (m + 3 n) + 100 */
    int32_t internal_cookie;          /* set by cloth_qp_default_options; catches an
                                         uninitialised struct */
} cloth_qp_options;

/* The default options (feasibility 1e-12, active 1e-9, dependency 1e-10, automatic cap). */
CLOTH_API cloth_qp_options cloth_qp_default_options(void);

/* What a projection did. The residuals are measured on the returned (cloth_real) z and lambda,
   in double, each relative to the size of its terms; all are 0 for an empty problem. */
typedef struct cloth_qp_stats {
    int32_t iterations;          /* working-set additions plus deletions */
    int32_t active_count;        /* rows returned CLOTH_QP_ACTIVE */
    int32_t tight_count;         /* rows returned CLOTH_QP_TIGHT */
    cloth_real objective;        /* 1/2 sum over movable i of |z_i - x_i|^2 / m_i */
    cloth_real stationarity;     /* max_i |z_i - x_i - m_i sum_j lambda_j a_jk n_j| over the
                                    coordinates of movable vertices, divided by the largest
                                    |z_i - x_i| or m_i sum_j |lambda_j a_jk n_j| */
    cloth_real primal_violation; /* max_j max(g_j(z), 0) / scale_j (0 when feasible) */
    cloth_real complementarity;  /* max over rows with lambda_j > 0 of |g_j(z)| / scale_j */
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
   workspace (a temporary one) may be NULL. Returns
     CLOTH_SUCCESS                     z is the solution (see the top of this module);
     CLOTH_ERROR_COLLISION_UNRESOLVED  the rows cannot all be met (or the iteration cap);
     CLOTH_ERROR_NOT_FINITE            a NaN or infinity in x, the inverse weights, or a used
                                       slot's weight, a normal or a thickness of a row (checked
                                       first), or an overflow during the solve;
     CLOTH_ERROR_INDEX_OUT_OF_RANGE    a row names a vertex outside -1..vertex_count-1;
     CLOTH_ERROR_INVALID_ARGUMENT      a negative inverse weight or count, or bad options;
     CLOTH_ERROR_OUT_OF_MEMORY, CLOTH_ERROR_SIZE_OVERFLOW  the workspace could not grow.
   On every error z = x, lambda = 0, active = CLOTH_QP_INACTIVE (when the counts are valid) and
   stats says how far the solver got. A NULL problem, x (with vertex_count > 0), rows (with
   row_count > 0) or z trips CLOTH_ASSERT. */
CLOTH_API cloth_result cloth_qp_project(cloth_qp_workspace *workspace, const cloth_qp_problem *problem,
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
