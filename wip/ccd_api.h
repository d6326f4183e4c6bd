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
                                      with the earliest time not yet ruled out; once a contact
                                      is found, at most max_checks / 16 more go into tightening
                                      toi. 1000000 */
    cloth_real minimum_separation; /* d >= 0 (m): report the pair when it comes within d per
                                      axis. 0 */
    int32_t internal_cookie;       /* set by cloth_ccd_default_options; catches an uninitialised struct */
} cloth_ccd_options;

/* The default options (tolerance 1e-6, max_checks 1e6, minimum_separation 0). */
CLOTH_API cloth_ccd_options cloth_ccd_default_options(void);

/* The answer of a CCD query. */
typedef struct cloth_ccd_report {
    int may_collide;      /* 1: a collision (within the minimum separation) may happen in [0,1];
                             0: it certainly does not */
    cloth_real toi;       /* time of impact, a lower bound on the earliest time of contact,
                             in [0,1]; 1 when may_collide is 0 */
    int64_t checks;       /* boxes checked */
    int budget_exhausted; /* 1 when the checks ran out (may_collide is then 1 and toi the
                             earliest time not yet ruled out) */
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
