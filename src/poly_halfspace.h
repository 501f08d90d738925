/* Exact overlap of a closed triangulated shape with a solid half-space: the
 * geometry of a particle against a plane wall (fix wall/polyhedral primitive).
 *
 * The wall solid is {x : n.x < d}, n the unit normal pointing out of the wall
 * into the free space. The overlap is bounded by the particle's triangles
 * clipped to the solid and by the cap, the part of the plane inside the
 * particle. As in poly_overlap.h, the volume and first moment are sums of
 * signed tetrahedra over that boundary, a fan per clipped triangle, all with
 * their apex at the foot of the particle's centre of mass on the plane. The
 * computation runs in the body frame, so accuracy does not depend on where
 * the particle is; with the apex on the plane the cap adds nothing (its
 * tetrahedra are flat), so the cap polygon, which may be several polygons for
 * a non-convex particle, is never assembled; and the tetrahedra stay of the
 * size of the overlap, so a shallow overlap keeps its centroid. The contact normal is -n
 * exactly (eq. 4.19: the particle's facets inside the solid sum to minus the
 * cap), the depth the deepest vertex's distance below the plane. A vertex
 * exactly on the plane counts as outside, consistently for every triangle
 * sharing it, so the clip segments of neighbouring triangles match. */
#ifndef POLY_HALFSPACE_H
#define POLY_HALFSPACE_H

#include "poly_overlap.h"

/* Shapes of up to this many vertices keep their vertices' penetrations on the stack. */
#define POLY_HALFSPACE_STACK_VERTICES 256

/* shape: double-precision view (body frame). rotation: body to world (row
 * major), position: centre of mass. On return result has volume, centroid,
 * normal (from the particle into the wall), depth and area (of the particle's
 * surface inside the wall), world frame, and the second moment about the
 * centroid if want_second_moment (zero otherwise: only rocking damping reads
 * it, and it was a third of this function's time); all zero without overlap. */
POLY_INLINE void poly_halfspace_overlap(const poly_shape_view_d *shape, const double rotation[9],
                                        const double position[3], const double plane_normal[3], double plane_offset,
                                        int want_second_moment, poly_overlap_result *result)
{
  result->volume = result->depth = result->area = result->projected_area = result->gap = 0.0;
  for (int k = 0; k < 3; k++) result->centroid[k] = result->normal[k] = 0.0;
  result->num_nodes = result->num_inconsistent = result->filtered_out = result->recomputed = result->smoothed = 0;
  for (int e = 0; e < 6; e++) result->second_moment[e] = 0.0;

  /* The plane in the body frame: n_b . y < d_b inside the wall. */
  double n[3];
  poly_matrix_apply_transpose(rotation, plane_normal, n);
  double d = plane_offset - (plane_normal[0] * position[0] + plane_normal[1] * position[1] +
                             plane_normal[2] * position[2]);
  if (d <= -shape->bounding_radius) {
    result->filtered_out = 1;
    return;
  }
  double foot[3] = {d * n[0], d * n[1], d * n[2]};

  /* Each vertex's penetration below the plane (> 0 inside the wall), once: a particle near a wall mostly
   * does not touch it, and a vertex is shared by about six triangles. */
  double penetration[POLY_HALFSPACE_STACK_VERTICES], deepest = 0.0;
  const int stored = shape->num_vertices <= POLY_HALFSPACE_STACK_VERTICES; /* larger shapes: per triangle */
  int inside_vertices = 0;
  for (int i = 0; i < shape->num_vertices; i++) {
    const double *y = shape->vertices + 3 * i;
    double s = d - (n[0] * y[0] + n[1] * y[1] + n[2] * y[2]);
    if (stored) penetration[i] = s;
    if (s > 0.0) {
      inside_vertices++;
      if (s > deepest) deepest = s;
    }
  }
  double volume6 = 0.0, moment24[3] = {0.0, 0.0, 0.0}, area = 0.0, along_normal = 0.0;
  double second120[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
  for (int t = 0; t < shape->num_triangles && inside_vertices > 0; t++) {
    const int *tri = shape->triangles + 3 * t;
    const double *v[3];
    double s[3];  /* penetration below the plane: > 0 inside the wall */
    int inside = 0;
    for (int c = 0; c < 3; c++) {
      v[c] = shape->vertices + 3 * tri[c];
      s[c] = stored ? penetration[tri[c]] : d - (n[0] * v[c][0] + n[1] * v[c][1] + n[2] * v[c][2]);
      inside += s[c] > 0.0;
    }
    if (inside == 0) continue;
    /* Clip the triangle to the wall (at most 4 corners), in its own order, relative to the foot. */
    double polygon[4][3];
    int corners = 0;
    for (int c = 0; c < 3; c++) {
      int next = (c + 1) % 3;
      if (s[c] > 0.0) {
        for (int k = 0; k < 3; k++) polygon[corners][k] = v[c][k] - foot[k];
        corners++;
      }
      if ((s[c] > 0.0) != (s[next] > 0.0)) {
        double w = s[c] / (s[c] - s[next]);
        for (int k = 0; k < 3; k++) polygon[corners][k] = v[c][k] + w * (v[next][k] - v[c][k]) - foot[k];
        corners++;
      }
    }
    for (int m = 1; m + 1 < corners; m++) {
      const double *a = polygon[0], *b = polygon[m], *c = polygon[m + 1];
      double v6 = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                  a[2] * (b[0] * c[1] - b[1] * c[0]);
      volume6 += v6;
      for (int k = 0; k < 3; k++) moment24[k] += v6 * (a[k] + b[k] + c[k]);
      if (want_second_moment) poly_second_moment_add(second120, v6, a, b, c);
      double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      double cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      area += 0.5 * sqrt(cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]);
      along_normal -= 0.5 * (n[0] * cross[0] + n[1] * cross[1] + n[2] * cross[2]);
    }
  }
  double volume = volume6 / 6.0;
  if (!(volume > 0.0)) return;
  double local_centroid[3];
  for (int k = 0; k < 3; k++) local_centroid[k] = moment24[k] / (24.0 * volume) + foot[k];
  poly_matrix_apply(rotation, local_centroid, result->centroid);
  for (int k = 0; k < 3; k++) {
    result->centroid[k] += position[k];
    result->normal[k] = -plane_normal[k];
  }
  result->volume = volume;
  result->depth = deepest;
  result->area = area;
  result->projected_area = along_normal;   /* the facets' area vectors sum to -n times this */
  result->num_nodes = inside_vertices;
  if (!want_second_moment) return;
  double from_foot[3] = {local_centroid[0] - foot[0], local_centroid[1] - foot[1], local_centroid[2] - foot[2]};
  for (int e = 0; e < 6; e++) second120[e] /= 120.0;
  poly_second_moment_to_centroid(second120, volume, from_foot);
  poly_second_moment_rotate(rotation, second120, result->second_moment);
}

#endif
