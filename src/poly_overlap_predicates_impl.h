/* The orientation predicates of the overlap computation, written once for a
 * scalar type: included by poly_overlap_impl.h (with its POLY_REAL, POLY_FN
 * and R defined) once per precision, so no include guard. Every sign they
 * return is exact, and an exact zero is decided by the symbolic perturbation
 * of B (see poly_overlap.h). */

/* The exact orientation of the four points of R, -poly_overlap_orient(x0, x1, x2, x): out of line on the CPU, so
 * that plane_side, which needs it rarely, stays small enough to inline. */
POLY_CPU_OUT_OF_LINE double POLY_FN(exact_side)(const R *x0, const R *x1, const R *x2, const R *x)
{
  double a[3], b[3], c[3], d[3];
  POLY_FN(to_double)(x0, a);
  POLY_FN(to_double)(x1, b);
  POLY_FN(to_double)(x2, c);
  POLY_FN(to_double)(x, d);
  return -poly_overlap_orient(a, b, c, d);
}

/* Which side of the plane of `tri` the point x is on: (v1-v0)x(v2-v0).(x-v0),
 * from the precomputed `plane` when the error bound proves its sign, else with
 * the exact sign of poly_orient (on the scalar-type inputs, so single
 * precision is exact too). Inlined by order into the crossing search (as a
 * call it cost a fifth more in a flow). */
POLY_HOT_INLINE R POLY_FN(plane_side)(const R *x, const R *vertices, const int *tri, const R *plane)
{
  const R *c0 = vertices + 3 * tri[0];
  R offset[3];
  POLY_FN(sub)(x, c0, offset);
  R side = POLY_FN(dot)(plane, offset);
  R bound = (R)32 * POLY_FN(epsilon)() * plane[3] * POLY_FN(norm1)(offset);
  if (side > bound || -side > bound) return side;
  double exact = POLY_FN(exact_side)(c0, vertices + 3 * tri[1], vertices + 3 * tri[2], x);
  if (exact == 0.0) return (R)0;
  if ((exact > 0) == (side > 0) && side != 0) return side;
  return exact > 0 ? (R)1e-30 : (R)-1e-30;
}

/* Sign of det(p1 - p0, q0 - p0, q1 - p0), exact. */
POLY_INLINE R POLY_FN(edge_side)(const R *p0, const R *p1, const R *q0, const R *q1)
{
  R d[3], a[3], b[3];
  POLY_FN(sub)(p1, p0, d);
  POLY_FN(sub)(q0, p0, a);
  POLY_FN(sub)(q1, p0, b);
  R value = POLY_FN(det)(d, a, b);
  R bound = (R)32 * POLY_FN(epsilon)() * POLY_FN(norm1)(d) * POLY_FN(norm1)(a) * POLY_FN(norm1)(b);
  if (value > bound || -value > bound) return value;
  double pp0[3], pp1[3], qq0[3], qq1[3];
  POLY_FN(to_double)(p0, pp0);
  POLY_FN(to_double)(p1, pp1);
  POLY_FN(to_double)(q0, qq0);
  POLY_FN(to_double)(q1, qq1);
  double exact = poly_overlap_orient(pp1, qq0, qq1, pp0);
  return exact > 0 ? (R)1 : (exact < 0 ? (R)-1 : (R)0);
}

/* Sign of a plane_side value of a point of B (point_in_b) or of A, with the
 * symbolic perturbation deciding an exact zero. */
POLY_INLINE int POLY_FN(side_sign)(R side, int point_in_b, const R *vertices, const int *tri, const R *plane)
{
  if (side > 0) return 1;
  if (side < 0) return -1;
  /* The tie-break (v1-v0)x(v2-v0).u must have an exact sign too: rounded, it
   * can disagree with another predicate's about the same perturbation. */
  (void)plane;
  double c0[3], c1[3], c2[3], ud[3];
  POLY_FN(to_double)(vertices + 3 * tri[0], c0);
  POLY_FN(to_double)(vertices + 3 * tri[1], c1);
  POLY_FN(to_double)(vertices + 3 * tri[2], c2);
  R u[3];
  POLY_FN(perturbation)(u);
  POLY_FN(to_double)(u, ud);
  const double *high[3] = {c1, c2, ud}, *low[3] = {c0, c0, 0};
  return POLY_FN(perturbed_sign)(0, (R)((point_in_b ? 1 : -1) * poly_overlap_det_sign(high, low)));
}

/* The sign an exactly zero edge orientation (p0 -> p1 against the edge
 * q0 -> q1) takes under the perturbation u of B: the exact sign of
 * det(p1 - p0, u, q1 - q0), turned for a segment of B. For a segment nearly
 * parallel to the edge a rounded value would be noise. */
POLY_INLINE R POLY_FN(edge_tie_break)(const R *p0, const R *p1, const R *q0, const R *q1, int segment_in_b)
{
  R u[3];
  POLY_FN(perturbation)(u);
  double pp0[3], pp1[3], qq0[3], qq1[3], ud[3];
  POLY_FN(to_double)(p0, pp0);
  POLY_FN(to_double)(p1, pp1);
  POLY_FN(to_double)(q0, qq0);
  POLY_FN(to_double)(q1, qq1);
  POLY_FN(to_double)(u, ud);
  const double *high[3] = {pp1, ud, qq1}, *low[3] = {pp0, 0, qq0};
  return (R)((segment_in_b ? -1 : 1) * poly_overlap_det_sign(high, low));
}

/* Where along p0 -> p1 a segment with plane_side values side0, side1 (of
 * opposite perturbed signs) meets the plane: exactly 0 or 1 at an end on it,
 * else clamped to [0, 1] against rounding. */
POLY_INLINE R POLY_FN(crossing_parameter)(R side0, R side1)
{
  if (side0 == 0) return 0;
  if (side1 == 0) return 1;
  R t = side0 / (side0 - side1);
  return t < 0 ? 0 : (t > 1 ? 1 : t);
}

/* The second half of segment_crosses_triangle: whether the segment p0 -> p1,
 * whose ends lie on opposite sides of the plane of `tri` (plane_side values
 * side0, side1; perturbed side of p0 sign0), crosses it inside the triangle. */
POLY_INLINE int POLY_FN(crossing_in_triangle)(const R *p0, const R *p1, int segment_in_b, const R *vertices,
                                              const int *tri, R side0, R side1, int sign0, R *lambda)
{
  int common = 0;
  for (int k = 0; k < 3; k++) {
    int from = tri[k], to = tri[k == 2 ? 0 : k + 1];
    int low = from < to ? from : to, high = from < to ? to : from;
    const R *q0 = vertices + 3 * low, *q1 = vertices + 3 * high;
    R orientation = POLY_FN(edge_side)(p0, p1, q0, q1);
    R first_order = orientation == 0 ? POLY_FN(edge_tie_break)(p0, p1, q0, q1, segment_in_b) : 0;
    int sign = POLY_FN(perturbed_sign)(orientation, first_order) * (from < to ? 1 : -1);
    if (k == 0) common = sign;
    else if (sign != common) return 0;
  }
  *lambda = POLY_FN(crossing_parameter)(side0, side1);
  return sign0;
}

/* Does the segment p0 -> p1 of one body cross triangle `tri` (vertices in
 * `vertices`; `plane` holds (v1-v0) x (v2-v0) and |v1-v0|_1 |v2-v0|_1) of the
 * other body? `segment_in_b` says which body the
 * segment belongs to: B carries the perturbation. Triangle edges are evaluated
 * in ascending vertex order so the two triangles sharing an edge see the
 * identical number. On a crossing, *lambda is the crossing parameter and the
 * return value the perturbed side of p0 (+1: outside the other body's face
 * plane, so the segment enters there; -1: it leaves); 0: no crossing. */
POLY_INLINE int POLY_FN(segment_crosses_triangle)(const R *p0, const R *p1, int segment_in_b, const R *vertices,
                                                   const int *tri, const R *plane, R *lambda)
{
  R side0 = POLY_FN(plane_side)(p0, vertices, tri, plane);
  R side1 = POLY_FN(plane_side)(p1, vertices, tri, plane);
  int sign0 = POLY_FN(side_sign)(side0, segment_in_b, vertices, tri, plane);
  int sign1 = POLY_FN(side_sign)(side1, segment_in_b, vertices, tri, plane);
  if (sign0 == sign1) return 0;
  return POLY_FN(crossing_in_triangle)(p0, p1, segment_in_b, vertices, tri, side0, side1, sign0, lambda);
}
