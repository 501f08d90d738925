/* Overlap of a closed triangulated shape with the solid of an infinite cylinder wall about the z axis
 * (fix wall/polyhedral primitive zcylinder R CX CY).
 *
 * Which solid: as LIGGGHTS' zcylinder primitive, the surface holds particles from either side. A particle
 * whose centre is inside the cylinder (a drum) meets the solid r > R; one whose centre is outside meets
 * the filled cylinder r < R (a pillar); r is the distance from the axis through (CX, CY).
 *
 * The approximant. The circle is replaced by a regular polygon of N sides, fixed in space (facet k spans
 * the angles [k, k+1] 2 pi / N), each facet at the distance h = R sqrt((d/2) / tan(d/2)) from the axis,
 * d = 2 pi / N, so that every sector of the polygon has the area of the circle's sector (the volume error
 * of a particle spanning whole facets cancels to leading order). The polygon then departs from the circle
 * radially by at most s = max(R - h, h / cos(d/2) - R) ~ R d^2 / 12, the sagitta bound; N is the fewest
 * sides that keep s below the tolerance (poly_cylinder_facets). The wall solid of the approximant is the
 * union over k of sector k (between the half-planes at its two angles, which meet on the axis) intersected
 * with the solid side of facet k's plane. Every point of the particle whose classification differs from the
 * exact cylinder's lies within s of the circle, so |V - V_exact| <= s * (z extent of that band of the
 * particle) * (arc length of the circle inside the particle's projection); the tests measure it.
 *
 * Exact for the approximant, with no cap: every face of the wall solid is vertical (parallel to z), so by
 * the divergence theorem with the fields (0, 0, z), (0, 0, x z), (0, 0, y z), (0, 0, z^2 / 2), whose flux
 * through vertical faces vanishes, the volume and first moment of (particle n solid) are integrals over the
 * particle's own surface inside the solid only. Each triangle is clipped to each sector's three half-planes
 * (a convex polygon, Sutherland-Hodgman, no division by the triangle's tilt) and integrated exactly (linear
 * and quadratic integrands over triangles); a vertical triangle adds nothing. The contact normal is the
 * direction of the summed area vectors of the particle's surface inside the solid (as for mesh walls; it
 * is minus the cap's, horizontal), the depth the deepest point's radial distance into the exact cylinder. */
#ifndef POLY_CYLINDER_H
#define POLY_CYLINDER_H

#include "poly_overlap.h"

#define POLY_CYLINDER_MIN_FACETS 8
#define POLY_CYLINDER_MAX_FACETS (1 << 22)

/* Distance from the axis of the facets of the N-gon standing in for the circle of radius R. */
POLY_INLINE double poly_cylinder_facet_distance(double radius, int facets)
{
  double half = 3.14159265358979323846 / facets;
  return radius * sqrt(half / tan(half));
}

/* The largest radial distance between the N-gon and the circle. */
POLY_INLINE double poly_cylinder_sagitta(double radius, int facets)
{
  double h = poly_cylinder_facet_distance(radius, facets);
  double inward = radius - h, outward = h / cos(3.14159265358979323846 / facets) - radius;
  return inward > outward ? inward : outward;
}

/* The fewest facets whose polygon departs from the circle by at most max_sagitta (capped). */
POLY_INLINE int poly_cylinder_facets(double radius, double max_sagitta)
{
  double step = sqrt(12.0 * max_sagitta / radius);   /* s ~ R d^2 / 12 */
  double estimate = step > 0.0 ? ceil(2.0 * 3.14159265358979323846 / step) : POLY_CYLINDER_MAX_FACETS;
  int facets = estimate < POLY_CYLINDER_MIN_FACETS ? POLY_CYLINDER_MIN_FACETS
               : estimate > POLY_CYLINDER_MAX_FACETS ? POLY_CYLINDER_MAX_FACETS : (int)estimate;
  while (facets > POLY_CYLINDER_MIN_FACETS && poly_cylinder_sagitta(radius, facets - 1) <= max_sagitta) facets--;
  while (facets < POLY_CYLINDER_MAX_FACETS && poly_cylinder_sagitta(radius, facets) > max_sagitta) facets++;
  return facets;
}

/* Keeps the part of a polygon (3D points, xy relative to the axis) where a x + b y + c > 0 (>= 0 when
 * inclusive). Returns the new corner count; out has room for count + 1 corners. */
POLY_INLINE int poly_cylinder_clip(const double (*in)[3], int count, double a, double b, double c, int inclusive,
                                   double (*out)[3])
{
  double value[10];
  for (int i = 0; i < count; i++) value[i] = a * in[i][0] + b * in[i][1] + c;
  int corners = 0;
  for (int i = 0; i < count; i++) {
    int next = (i + 1) % count;
    int keep = inclusive ? value[i] >= 0.0 : value[i] > 0.0;
    int keep_next = inclusive ? value[next] >= 0.0 : value[next] > 0.0;
    if (keep) {
      for (int k = 0; k < 3; k++) out[corners][k] = in[i][k];
      corners++;
    }
    if (keep != keep_next) {
      double w = value[i] / (value[i] - value[next]);
      for (int k = 0; k < 3; k++) out[corners][k] = in[i][k] + w * (in[next][k] - in[i][k]);
      corners++;
    }
  }
  return corners;
}

/* Distance in the xy plane from the axis (the origin) to the projection of triangle p. */
POLY_INLINE double poly_cylinder_axis_distance(const double (*p)[3])
{
  double orientation[3], best = -1.0;
  for (int c = 0; c < 3; c++) {
    const double *a = p[c], *b = p[(c + 1) % 3];
    orientation[c] = a[0] * b[1] - a[1] * b[0];   /* side of the origin relative to edge a->b */
    double ex = b[0] - a[0], ey = b[1] - a[1], length2 = ex * ex + ey * ey;
    double t = length2 > 0.0 ? -(a[0] * ex + a[1] * ey) / length2 : 0.0;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double dx = a[0] + t * ex, dy = a[1] + t * ey, distance = sqrt(dx * dx + dy * dy);
    if (best < 0.0 || distance < best) best = distance;
  }
  if ((orientation[0] >= 0.0 && orientation[1] >= 0.0 && orientation[2] >= 0.0) ||
      (orientation[0] <= 0.0 && orientation[1] <= 0.0 && orientation[2] <= 0.0))
    return 0.0;
  return best;
}

/* shape: double-precision view (body frame). rotation: body to world (row major), position: centre of mass.
 * axis: (CX, CY); facets: of the polygon standing in for the circle (poly_cylinder_facets). On return result
 * has volume, centroid, normal (from the particle into the wall, horizontal), depth, area and projected_area
 * (of the particle's surface inside the wall), world frame; all zero without overlap. */
POLY_INLINE void poly_cylinder_overlap(const poly_shape_view_d *shape, const double rotation[9],
                                       const double position[3], const double axis[2], double radius, int facets,
                                       poly_overlap_result *result)
{
  const double two_pi = 2.0 * 3.14159265358979323846;
  result->volume = result->depth = result->area = result->projected_area = 0.0;
  for (int k = 0; k < 3; k++) result->centroid[k] = result->normal[k] = 0.0;
  result->num_nodes = result->num_inconsistent = result->filtered_out = 0;

  /* Coordinates relative to (CX, CY, z of the particle's centre). */
  const double offset[3] = {position[0] - axis[0], position[1] - axis[1], 0.0};
  double centre_distance = sqrt(offset[0] * offset[0] + offset[1] * offset[1]);
  const int drum = centre_distance < radius;   /* wall solid r > R; else the filled cylinder r < R */
  double reach = shape->bounding_radius;
  if ((drum && centre_distance + reach <= radius) || (!drum && centre_distance - reach >= radius)) {
    result->filtered_out = 1;
    return;
  }
  const double step = two_pi / facets, h = poly_cylinder_facet_distance(radius, facets);
  const double corner_radius = h / cos(0.5 * step), side = drum ? 1.0 : -1.0;

  double volume = 0.0, moment[3] = {0.0, 0.0, 0.0}, area = 0.0, area_vector[3] = {0.0, 0.0, 0.0};
  double deepest = 0.0, nearest = -1.0;
  for (int t = 0; t < shape->num_triangles; t++) {
    const int *tri = shape->triangles + 3 * t;
    double p[3][3], r2[3];
    for (int c = 0; c < 3; c++) {
      double world[3];
      poly_matrix_apply(rotation, shape->vertices + 3 * tri[c], world);
      for (int k = 0; k < 3; k++) p[c][k] = world[k] + offset[k];
      r2[c] = p[c][0] * p[c][0] + p[c][1] * p[c][1];
    }
    /* Triangles wholly off the solid of the polygon: inside its inscribed circle (the drum, convex), or
     * farther from the axis than its corners (the pillar). */
    if (drum) {
      if (r2[0] < h * h && r2[1] < h * h && r2[2] < h * h) continue;
    } else {
      double distance = poly_cylinder_axis_distance((const double (*)[3])p);
      if (nearest < 0.0 || distance < nearest) nearest = distance;
      if (distance >= corner_radius) continue;
    }
    /* The sectors the triangle's projection spans; all of them if it surrounds or touches the axis. */
    int first = 0, last = facets - 1;
    if (poly_cylinder_axis_distance((const double (*)[3])p) > 0.0) {
      double angle0 = atan2(p[0][1], p[0][0]), low = angle0, high = angle0;
      for (int c = 1; c < 3; c++) {
        double angle = angle0 + remainder(atan2(p[c][1], p[c][0]) - angle0, two_pi);
        low = angle < low ? angle : low;
        high = angle > high ? angle : high;
      }
      first = (int)floor(low / step) - 1;    /* one spare sector each side for rounding at sector borders */
      last = (int)floor(high / step) + 1;
    }
    for (int s = first; s <= last; s++) {
      int sector = ((s % facets) + facets) % facets;
      /* the ray at `end` computed as its neighbour's `start`, so that the two sectors meet exactly */
      double start = sector * step, end = ((sector + 1) % facets) * step, middle = (sector + 0.5) * step;
      double polygon_a[10][3], polygon_b[10][3];
      /* left of the ray at `start` (inclusive), right of the ray at `end` (its neighbour's inclusive side
       * negated), then the solid side of the facet. */
      int corners = poly_cylinder_clip((const double (*)[3])p, 3, -sin(start), cos(start), 0.0, 1, polygon_a);
      if (corners < 3) continue;
      corners = poly_cylinder_clip((const double (*)[3])polygon_a, corners, sin(end), -cos(end), 0.0, 0, polygon_b);
      if (corners < 3) continue;
      corners = poly_cylinder_clip((const double (*)[3])polygon_b, corners, side * cos(middle), side * sin(middle),
                                   -side * h, 0, polygon_a);
      for (int m = 1; m + 1 < corners; m++) {
        const double *a = polygon_a[0], *b = polygon_a[m], *c = polygon_a[m + 1];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
        double projected = 0.5 * cross[2];   /* n_z dA over the piece */
        double sum_z = a[2] + b[2] + c[2];
        volume += projected * sum_z / 3.0;
        for (int k = 0; k < 2; k++)
          moment[k] += projected * (a[k] * a[2] + b[k] * b[2] + c[k] * c[2] + (a[k] + b[k] + c[k]) * sum_z) / 12.0;
        moment[2] += projected * (a[2] * a[2] + b[2] * b[2] + c[2] * c[2] + sum_z * sum_z) / 24.0;
        for (int k = 0; k < 3; k++) area_vector[k] += 0.5 * cross[k];
        area += 0.5 * sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
      }
    }
  }
  if (!(volume > 0.0)) return;

  int inside_vertices = 0;
  for (int i = 0; i < shape->num_vertices; i++) {
    double world[3];
    poly_matrix_apply(rotation, shape->vertices + 3 * i, world);
    double x = world[0] + offset[0], y = world[1] + offset[1], r = sqrt(x * x + y * y);
    double into = drum ? r - radius : radius - r;
    if (into > 0.0) {
      inside_vertices++;
      if (drum && into > deepest) deepest = into;
    }
  }
  if (!drum) deepest = nearest >= 0.0 && nearest < radius ? radius - nearest : 0.0;

  double horizontal = sqrt(area_vector[0] * area_vector[0] + area_vector[1] * area_vector[1]);
  if (horizontal > 0.0) {
    result->normal[0] = area_vector[0] / horizontal;
    result->normal[1] = area_vector[1] / horizontal;
  }
  for (int k = 0; k < 3; k++) result->centroid[k] = moment[k] / volume + position[k] - offset[k];
  result->volume = volume;
  result->depth = deepest;
  result->area = area;
  result->projected_area = horizontal;
  result->num_nodes = inside_vertices;
}

#endif
