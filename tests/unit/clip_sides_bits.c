/* The clipping path's SSE2 sides (src/poly_clip.h, on x86-64 hosts) against its scalar loop (the GPU's and other
 * machines'): built once as is and once with -U__SSE2__ by tests/test_convex_path.py, which compares the hashes
 * this prints. For each shape, `pairs` random pose pairs (both orientations random, centres 0.5 to 1.9 bounding
 * radii apart, and a face resting on a face, 1e-4 of the size deep, as a pile has them) through poly_overlap_d with
 * second moments; the hash covers every bit of every result field, and the counts say how many touched.
 *
 *   clip_sides_bits SHAPES_DIR PAIRS SHAPE_FILE...    -> "SHAPE contacts N hash H" per shape */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_overlap.h"
#include "../../tools/bench_common.h"  /* a fixed, portable random sequence and rotations */
#include "../../tools/result_hash.h"

int main(int argc, char **argv)
{
  if (argc < 4) {
    fprintf(stderr, "usage: %s SHAPES_DIR PAIRS SHAPE_FILE...\n", argv[0]);
    return 2;
  }
  const int pairs = atoi(argv[2]);
  for (int s = 3; s < argc; s++) {
    poly_shape shape;
    if (load_shape(argv[1], argv[s], 1.0, &shape)) return 1;
    poly_shape_view_d view = poly_shape_view_of(&shape);
    poly_overlap_workspace_d ws;
    if (poly_overlap_workspace_create_d(&ws, shape.num_vertices, shape.num_triangles) != 0) return 1;
    ws.want_second_moment = 1;
    unsigned long long hash = RESULT_HASH_START;
    int contacts = 0;
    const double size = 2.0 * shape.bounding_radius / sqrt(3.0);
    for (int p = 0; p < pairs; p++) {
      poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}}, b = {{0, 0, 0}, {1, 0, 0, 0}};
      if (p % 2 == 0) {
        random_quaternion(a.quaternion);
        random_quaternion(b.quaternion);
        double direction[3], norm = 0.0;
        for (int k = 0; k < 3; k++) {
          direction[k] = 2.0 * uniform() - 1.0;
          norm += direction[k] * direction[k];
        }
        const double distance = shape.bounding_radius * (0.5 + 1.4 * uniform());
        for (int k = 0; k < 3; k++) b.position[k] = distance * direction[k] / sqrt(norm);
      } else {
        const double turn = 6.283185307179586 * uniform(), tilt = 0.01 * uniform();
        b.quaternion[0] = cos(0.5 * tilt) * cos(0.5 * turn);
        b.quaternion[1] = sin(0.5 * tilt) * cos(0.5 * turn);
        b.quaternion[2] = sin(0.5 * tilt) * sin(0.5 * turn);
        b.quaternion[3] = cos(0.5 * tilt) * sin(0.5 * turn);
        b.position[0] = 0.1 * size * (2.0 * uniform() - 1.0);
        b.position[1] = 0.1 * size * (2.0 * uniform() - 1.0);
        b.position[2] = size * (1.0 - 1e-4);
      }
      poly_overlap_result result;
      poly_overlap_d(&view, &a, &view, &b, &ws, &result);
      contacts += result.volume > 0.0;
      hash = result_hash_add(hash, &result);
    }
    printf("%s contacts %d hash %016llx\n", argv[s], contacts, hash);
    poly_overlap_workspace_destroy_d(&ws);
  }
  return 0;
}
