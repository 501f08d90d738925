/* The crossing cache (src/poly_overlap_cache_impl.h) with a body thinner than a certificate's reach
 * (tests/test_crossing_cache.py): a big rock A and a tiny tetrahedron B (r_B = RATIO r_A) by each face of A, once
 * just outside it (a near miss) and once just inside A, certified there, then moved through the face in one
 * evaluation, so that every edge-triangle decision is again what it was (no crossing) while B has gone inside A or
 * out of it. The cached evaluation must give the search's volume.
 *
 *   crossing_cache_thin SHAPE_A TETRAHEDRON [RATIO]
 *
 * Prints, per way (into, out of), the poses tried, those certified, those evaluated from the cache, and the
 * evaluations whose volume differs from a search's. */
#define _POSIX_C_SOURCE 199309L
#include <string.h>

#include "../../tools/bench_common.h" /* uniform(), random_quaternion(), load_shape() */
#include "poly_overlap.h"
#include "poly_rigid.h"

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: crossing_cache_thin SHAPE_A TETRAHEDRON [RATIO]\n");
    return 2;
  }
  const double ratio = argc > 3 ? atof(argv[3]) : 1e-3;
  poly_shape sa, sb, unit;
  if (load_shape(".", argv[1], 1.0, &sa) || load_shape(".", argv[2], 1.0, &unit)) return 1;
  const double scale = ratio * sa.bounding_radius / unit.bounding_radius;
  poly_shape_free(&unit);
  if (load_shape(".", argv[2], scale, &sb)) return 1;
  poly_shape_view_d view_a = poly_shape_view_of(&sa), view_b = poly_shape_view_of(&sb);
  const int vertices = sa.num_vertices > sb.num_vertices ? sa.num_vertices : sb.num_vertices;
  const int triangles = sa.num_triangles > sb.num_triangles ? sa.num_triangles : sb.num_triangles;
  poly_overlap_workspace_d cached, plain;
  if (poly_overlap_workspace_create_d(&cached, vertices, triangles) ||
      poly_overlap_workspace_create_d(&plain, vertices, triangles))
    return 1;
  poly_crossing_cache cache;
  cached.crossing_cache = &cache;
  const poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}};
  for (int into = 1; into >= 0; into--) {
    int tried = 0, certified = 0, replayed = 0, wrong = 0;
    for (int t = 0; t < sa.num_triangles; t++)
      for (int repeat = 0; repeat < 4; repeat++) {
        /* A point of the face, B turned at random, its extent along the face's normal. */
        const int *tri = sa.triangles + 3 * t;
        const double *n = sa.face_normals + 3 * t;
        double w[3] = {uniform(), uniform(), uniform()}, c[3], r[9], low = 1e300, high = -1e300;
        const double sum = w[0] + w[1] + w[2];
        for (int k = 0; k < 3; k++)
          c[k] = (w[0] * sa.vertices[3 * tri[0] + k] + w[1] * sa.vertices[3 * tri[1] + k] +
                  w[2] * sa.vertices[3 * tri[2] + k]) / sum;
        poly_pose b;
        random_quaternion(b.quaternion);
        poly_quat_to_matrix(b.quaternion, r);
        for (int j = 0; j < sb.num_vertices; j++) {
          const double *v = sb.vertices + 3 * j;
          double along = 0.0;
          for (int k = 0; k < 3; k++) along += n[k] * (r[3 * k] * v[0] + r[3 * k + 1] * v[1] + r[3 * k + 2] * v[2]);
          low = along < low ? along : low;
          high = along > high ? along : high;
        }
        /* Outside by a twentieth of B's extent (into A), or inside by as much (out of A); then through. */
        const double gap = 0.05 * (high - low), depth = 3.0 * gap + (high - low);
        for (int k = 0; k < 3; k++) b.position[k] = c[k] + n[k] * (into ? gap - low : -gap - high);
        poly_overlap_result first, with, without;
        poly_overlap_d(&view_a, &a, &view_b, &b, &plain, &first);
        if (first.filtered_out || (into ? first.volume > 0.0 : !(first.volume > 0.99 * sb.volume))) continue;
        tried++;
        memset(&cache, 0, sizeof cache);
        poly_overlap_d(&view_a, &a, &view_b, &b, &cached, &with); /* the pose */
        poly_overlap_d(&view_a, &a, &view_b, &b, &cached, &with); /* not moved: a certificate */
        certified += cache.margin > 0.0;
        poly_pose moved = b;
        for (int k = 0; k < 3; k++) moved.position[k] += (into ? -depth : depth) * n[k];
        const long hits = cached.cache_hits;
        poly_overlap_d(&view_a, &a, &view_b, &moved, &cached, &with);
        poly_overlap_d(&view_a, &a, &view_b, &moved, &plain, &without);
        replayed += cached.cache_hits > hits;
        wrong += with.volume != without.volume;
      }
    printf("%s tried %d certified %d replayed %d wrong %d\n", into ? "into" : "out", tried, certified, replayed,
           wrong);
  }
  poly_overlap_workspace_destroy_d(&cached);
  poly_overlap_workspace_destroy_d(&plain);
  poly_shape_free(&sa);
  poly_shape_free(&sb);
  return 0;
}
