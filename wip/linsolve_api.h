/* ===================================================================================== */
/* linsolve: a symmetric 3x3 block sparse matrix whose pattern is fixed at setup, SpMV,    */
/*           and the filtered preconditioned conjugate gradient of Baraff & Witkin (1998)  */
/*           with the correction of Ascher & Boxerman (2003)                              */
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
/* Memory: the matrix and the workspace allocate at setup only; cloth_block_matrix_zero,  */
/* the add and multiply functions and cloth_pcg_solve allocate nothing.                   */
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
       cloth_pcg_multigrid_setup; far fewer iterations than block-Jacobi on stiff cloth. */
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
       of the workspace's hierarchy from this matrix and filter (what
       cloth_pcg_multigrid_update does), the best preconditioner for this system. 0: it keeps
       the values of the last setup or update and only refreshes the finest level's smoother;
       the preconditioner stays symmetric positive definite, so the solve is as exact as ever,
       but it converges more slowly as the matrix drifts from the one the values came from. */
    int multigrid_update;
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
    int converged;               /* 1 when preconditioned_residual <= tolerance */
} cloth_pcg_stats;

/* Scratch memory for solves over up to vertex_count vertices: 24 reals per vertex, and the
   multigrid hierarchy once cloth_pcg_multigrid_setup has made one. Make one at setup and reuse
   it; one workspace serves one solve at a time. A zero-filled workspace is a valid empty one. */
typedef struct cloth_pcg_workspace {
    int32_t vertex_count;
    cloth_real *memory;
    cloth_allocator allocator;
    struct cloth__multigrid *multigrid; /* private; NULL until cloth_pcg_multigrid_setup */
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
   matrix's pattern (cloth_pcg_multigrid_setup), else CLOTH_ERROR_INVALID_ARGUMENT with x
   unchanged; the numeric phase the solve runs first (options->multigrid_update) can fail with
   CLOTH_ERROR_NOT_POSITIVE_DEFINITE or CLOTH_ERROR_NOT_FINITE, x unchanged.
   When bhat = 0 (a zero right-hand side for the reduced system) x becomes (I - S) z at once
   with 0 iterations. */
CLOTH_API cloth_result cloth_pcg_solve(const cloth_block_matrix *matrix, const cloth_real *b, cloth_real *x,
                                       const cloth_pcg_filter *filter, const cloth_pcg_options *options,
                                       cloth_pcg_workspace *workspace, cloth_pcg_stats *stats);

/* ---- multigrid ---------------------------------------------------------------------- */

/* Smoothed-aggregation algebraic multigrid (Vanek, Mandel & Brezina 1996; for cloth,
   Tamstorf, Jones & McCormick 2015) as the preconditioner of cloth_pcg_solve.

   The hierarchy. Level 0 is the caller's matrix under the constraint filter. Each level's
   vertices ("nodes") are grouped into aggregates by the strength of their coupling blocks
   (block (i, j) is strong when |A_ij|_F^2 > theta^2 |A_ii|_F |A_jj|_F); each aggregate is a
   node of the next level, with 3 unknowns: the aggregate's translations. The tentative
   prolongator T maps them onto the aggregate's vertices (the filtered translations S_i,
   orthonormalized per aggregate; a direction the filter removes from every vertex of an
   aggregate is dropped); the prolongator is T smoothed by one damped Jacobi step,
   P = (I - omega D^-1 A_s) T, with D the filtered diagonal blocks, A_s the diagonal and strong
   blocks, omega = 4/3 / rho and rho a Gershgorin bound on rho(D^-1 A_s). The next level's
   matrix is the Galerkin product P^T A P (computed on its upper triangle and mirrored, so it is
   exactly symmetric). Coarsening stops at coarse_size nodes or max_levels levels, and the
   coarsest level is solved by a dense Cholesky factorization (in double).

   The V-cycle. From the finest level down: smoothing_steps pre-smoothing sweeps (block
   Gauss-Seidel forward, or damped block Jacobi), the residual restricted by P^T; the coarsest
   solve; then back up: the correction prolongated by P, and as many post-smoothing sweeps
   (Gauss-Seidel backward, or Jacobi). Pre- and post-smoothing are adjoint, so the V-cycle is
   a symmetric positive definite operator and CG's theory holds.

   The filter. The finest level works on the filtered system S A S: its smoother inverts the
   filtered diagonal blocks as the block-Jacobi preconditioner does (a pinned vertex gets 0),
   residuals are filtered, and prolongated corrections are filtered again with the filter of
   the current solve, so a hierarchy built under an older filter (other pins) still gives a
   symmetric positive definite preconditioner on the free directions, only a weaker one.
   Fully pinned vertices therefore need no special treatment: they drop out of T.

   Setup and cost. cloth_pcg_multigrid_setup is the symbolic phase plus the first numeric
   phase: it chooses the aggregates from the values it is given, fixes every level's pattern and
   allocates. cloth_pcg_multigrid_update is the numeric phase alone: for a matrix with the same
   pattern and new values (and any filter), it recomputes T, P, the Galerkin products and the
   coarsest factor in the memory of the setup, allocating nothing. Its result depends only on the
   hierarchy's patterns and the values passed, never on the values of an earlier update: an
   update gives bit-identical results to a fresh setup that chose the same aggregates.
   A change of pattern needs a new setup; a change of pins or of the other filter values needs
   only an update (cloth_pcg_solve does one itself unless options->multigrid_update is 0).

   Determinism: every sum runs in a fixed order, the aggregation visits vertices in index
   order, and nothing depends on addresses or timing. */

/* The most levels a hierarchy can have. */
#define CLOTH_MULTIGRID_MAX_LEVELS 16

typedef enum cloth_multigrid_smoother {
    /* Block Gauss-Seidel: forward sweeps before the coarse correction, backward after. */
    CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL = 0,
    /* Damped block Jacobi, weight 4/3 / rho with rho the Gershgorin bound above. */
    CLOTH_MULTIGRID_SMOOTHER_JACOBI = 1
} cloth_multigrid_smoother;

/* Options of a hierarchy. Make them with cloth_default_multigrid_options() and change what you
   need. The defaults were tuned on the hang scene's matrices (bench/linsolve.c). */
typedef struct cloth_multigrid_options {
    /* theta, the strength threshold, finite, in [0, 1). Default 0.08 (bending couplings, far
       weaker than stretching ones, are then not strong). */
    cloth_real strength_threshold;
    /* The factor 4/3 in omega = factor / rho, finite, in [0, 2]; 0 gives unsmoothed (plain)
       aggregation, cheaper per setup and weaker. Default 4/3. */
    cloth_real prolongator_damping;
    /* Stop coarsening at this many nodes or fewer, >= 1; default 32. A level of up to
       4 coarse_size nodes is factored densely; a coarsest level that aggregation could not make
       that small is smoothed instead (smoothing_steps symmetric Gauss-Seidel sweeps). */
    int32_t coarse_size;
    /* The most levels, 1..CLOTH_MULTIGRID_MAX_LEVELS, finest included; default 10. With 1 the
       preconditioner is the dense factor of the whole filtered matrix (small systems only). */
    int32_t max_levels;
    /* Pre- and post-smoothing sweeps per level, >= 1; default 1. */
    int32_t smoothing_steps;
    /* Default CLOTH_MULTIGRID_SMOOTHER_GAUSS_SEIDEL. */
    cloth_multigrid_smoother smoother;
} cloth_multigrid_options;

/* What a hierarchy is made of (cloth_pcg_multigrid_info). */
typedef struct cloth_multigrid_info {
    int32_t level_count;                                    /* 0: no hierarchy */
    int32_t node_count[CLOTH_MULTIGRID_MAX_LEVELS];         /* nodes (3 unknowns each) per level */
    int32_t block_count[CLOTH_MULTIGRID_MAX_LEVELS];        /* stored 3x3 blocks of each level's matrix */
    int32_t prolongator_block_count[CLOTH_MULTIGRID_MAX_LEVELS]; /* blocks of P from the next level; 0 on the coarsest */
    /* the blocks of all levels over those of level 0: the memory and work of a V-cycle's
       matrix products relative to one product with the fine matrix */
    double operator_complexity;
    int coarsest_dense;          /* 1: the coarsest level is factored densely; 0: smoothed */
    size_t bytes;                /* memory the hierarchy holds */
} cloth_multigrid_info;

/* The default options (see cloth_multigrid_options). */
CLOTH_API cloth_multigrid_options cloth_default_multigrid_options(void);

/* Build a multigrid hierarchy for this matrix on the workspace (replacing any it holds): the
   symbolic phase, which aggregates by the strength of the values given here and fixes every
   pattern, then a numeric phase for these values and this filter (as cloth_pcg_solve reads
   them: filter may be NULL). Call it once the matrix holds representative values (after the
   first assembly of a time step, not on the zero values of a fresh matrix), again when the
   pattern changes; options == NULL means the defaults. The workspace must cover the matrix
   (workspace->vertex_count >= matrix->vertex_count). Allocates with the workspace's allocator.
   Fails with CLOTH_ERROR_INVALID_ARGUMENT (bad options or filter, a workspace too small),
   CLOTH_ERROR_NOT_FINITE, CLOTH_ERROR_NOT_POSITIVE_DEFINITE (a filtered diagonal block that is
   not positive definite on its free directions, or a dense coarsest factor of the whole
   problem that is not), CLOTH_ERROR_SIZE_OVERFLOW or CLOTH_ERROR_OUT_OF_MEMORY; the workspace
   then holds no hierarchy. */
CLOTH_API cloth_result cloth_pcg_multigrid_setup(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                 const cloth_pcg_filter *filter,
                                                 const cloth_multigrid_options *options);

/* The numeric phase alone: recompute the hierarchy's values for a matrix with the pattern of
   the setup and new values, under this filter. Allocates nothing. Fails with
   CLOTH_ERROR_INVALID_ARGUMENT (no hierarchy, another pattern, a bad filter),
   CLOTH_ERROR_NOT_FINITE or CLOTH_ERROR_NOT_POSITIVE_DEFINITE; after a failure the hierarchy
   keeps its patterns but has no values, and solves that do not update it
   (multigrid_update = 0) fail with CLOTH_ERROR_INVALID_ARGUMENT until an update succeeds. */
CLOTH_API cloth_result cloth_pcg_multigrid_update(cloth_pcg_workspace *workspace, const cloth_block_matrix *matrix,
                                                  const cloth_pcg_filter *filter);

/* Describe the workspace's hierarchy (level_count = 0 when it has none). */
CLOTH_API void cloth_pcg_multigrid_info(const cloth_pcg_workspace *workspace, cloth_multigrid_info *info);

#ifdef __cplusplus
}
#endif
