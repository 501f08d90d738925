/* The slab's highest and lowest vertices from the table of src/poly_extremes.h against a scan of every vertex
 * (tests/test_extreme_table.py): for each shape given, poses of B about A (random turns and centre lines, and centre
 * lines on the cells' edges and corners, the cube map's diagonals and the coordinate axes, where the cell of a
 * direction is decided by rounding and where symmetric shapes have vertices tied), in double, single and mixed
 * precision, overlap_slab_extremes with the shapes' tables and with none. Every output (axis, extents, extreme
 * vertices) must be the same bits.
 *
 *   extreme_table POSES SHAPE...
 *
 * Prints per shape its candidates a cell, the comparisons and the differences. */
#define _POSIX_C_SOURCE 199309L
#include <string.h>

#include "../../tools/bench_common.h" /* uniform(), random_quaternion(), load_shape() */
#include "poly_overlap_instances.h"
#include "poly_rigid.h"

static void random_direction(double d[3])
{
  const double z = 2.0 * uniform() - 1.0, phi = 2.0 * PI * uniform(), r = sqrt(1.0 - z * z);
  d[0] = r * cos(phi), d[1] = r * sin(phi), d[2] = z;
}

#define COMPARE(SUFFIX, VIEW_A, VIEW_B, BARE_A, BARE_B)                                                               \
  {                                                                                                                   \
    double axis[3], high, low, axis0[3], high0, low0;                                                                 \
    int ea = 0, eb = 0, ea0 = 0, eb0 = 0;                                                                             \
    int s1 = poly_overlap_slab_extremes##SUFFIX(&VIEW_A, &VIEW_B, rotation, translation, axis, &high, &low, &ea, &eb); \
    int s0 = poly_overlap_slab_extremes##SUFFIX(&BARE_A, &BARE_B, rotation, translation, axis0, &high0, &low0, &ea0,  \
                                                &eb0);                                                                \
    compared++;                                                                                                       \
    if (s1 != s0 || ea != ea0 || eb != eb0 || memcmp(&high, &high0, sizeof high) ||                                   \
        memcmp(&low, &low0, sizeof low) || memcmp(axis, axis0, sizeof axis))                                          \
      differ++;                                                                                                       \
  }

int main(int argc, char **argv)
{
  if (argc < 3) {
    fprintf(stderr, "usage: extreme_table POSES SHAPE...\n");
    return 2;
  }
  const int poses = atoi(argv[1]);
  long total_differ = 0;
  for (int s = 2; s < argc; s++) {
    poly_shape shape;
    if (load_shape(".", argv[s], 1.0, &shape)) return 1;
    if (!shape.extreme_start) {
      printf("%s: no table (%d vertices)\n", argv[s], shape.num_vertices);
      poly_shape_free(&shape);
      continue;
    }
    poly_shape_view_d view_d = poly_shape_view_of(&shape), bare_d = view_d;
    poly_shape_view_f view_f, bare_f;
    if (poly_shape_view_make_f(&shape, &view_f)) return 1;
    bare_f = view_f;
    bare_d.extreme_start = bare_d.extreme_vertices = NULL;
    bare_f.extreme_start = bare_f.extreme_vertices = NULL;
    long compared = 0, differ = 0;
    for (int p = 0; p < poses; p++) {
      double quaternion[4], rotation[9], direction[3];
      random_quaternion(quaternion);
      poly_quat_to_matrix(quaternion, rotation);
      const int kind = p % 4;
      if (kind == 0) {
        random_direction(direction);
      } else {
        /* A cell edge or corner of the cube map (a multiple of 2 / SIDE), or a diagonal or axis, turned by signs. */
        const int side = POLY_EXTREME_SIDE;
        for (int k = 0; k < 3; k++) {
          const int bin = (int)(uniform() * (side + 1));
          direction[k] = kind == 1 ? 2.0 * bin / side - 1.0 : (kind == 2 ? (uniform() < 0.5 ? 1.0 : -1.0) : 0.0);
        }
        if (kind == 1) direction[(int)(uniform() * 3) % 3] = uniform() < 0.5 ? 1.0 : -1.0;
        if (kind == 2 && uniform() < 0.5) direction[(int)(uniform() * 3) % 3] = 0.0;
        if (kind == 3) direction[(int)(uniform() * 3) % 3] = uniform() < 0.5 ? 1.0 : -1.0;
        if (kind == 3 && uniform() < 0.5) memcpy(quaternion, (double[4]){1, 0, 0, 0}, sizeof quaternion);
        poly_quat_to_matrix(quaternion, rotation);
      }
      const double distance = shape.bounding_radius * (0.2 + 1.8 * uniform());
      double translation[3];
      for (int k = 0; k < 3; k++) translation[k] = distance * direction[k];
      COMPARE(_d, view_d, view_d, bare_d, bare_d)
      COMPARE(_f, view_f, view_f, bare_f, bare_f)
      COMPARE(_m, view_f, view_f, bare_f, bare_f)
    }
    printf("%s: %d vertices, %.2f candidates a cell; %ld slabs compared, %ld differ\n", argv[s], shape.num_vertices,
           (double)shape.extreme_start[POLY_EXTREME_CELLS] / POLY_EXTREME_CELLS, compared, differ);
    total_differ += differ;
    poly_shape_view_free_f(&view_f);
    poly_shape_free(&shape);
  }
  printf("differences: %ld\n", total_differ);
  return 0;
}
