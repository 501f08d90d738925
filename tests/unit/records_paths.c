/* The two paths of one overlap pass against each other (tests/test_records_path.py):
 * the crossing records (ws.use_records = 1, the default) and the reference path
 * (ray parity per vertex, every kept triangle pair examined; use_records = 0).
 *
 *   records_paths SHAPE_FILE NUM_POSES PRECISION(double|single|mixed) [CAPACITY|convex|clip]
 *
 * With `convex`, it compares instead the convex path (ws.use_convex = 1, the
 * default, for shapes found convex) with the general records path
 * (use_convex = 0); the node counts then differ (the convex path does not
 * clip the diagonals of flat faces), and are not compared.
 * Poses: random orientations at centre distances from deep to grazing, B
 * resting on A (one in eight: face on face for blocks, as in a pile), and
 * degenerate ones (both at the identity, or one turned by a multiple of 90
 * degrees about z, moved along axes by fractions of the size that make faces
 * flush, vertices touch faces and edges meet edges; B identical to A).
 * CAPACITY (optional) shrinks the records capacity to force the fallback.
 * Prints per quantity the largest difference (relative to the particle size)
 * and the number of poses whose flags (filtered_out, smoothed, recomputed,
 * inconsistent, num_nodes) differ. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_overlap.h"

static unsigned long long state = 0x2545F4914F6CDD1Dull;

static double uniform(void)
{
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return (double)(state >> 11) * (1.0 / 9007199254740992.0);
}

static void random_quaternion(double *q)
{
  double norm = 0.0;
  for (int k = 0; k < 4; k++) {
    q[k] = 2.0 * uniform() - 1.0;
    norm += q[k] * q[k];
  }
  for (int k = 0; k < 4; k++) q[k] /= sqrt(norm);
}

typedef struct outcome {
  poly_overlap_result result;
} outcome;

static int precision;
static poly_shape_view_d view_d;
static poly_shape_view_f view_f;
static poly_overlap_workspace_d ws_d;
static poly_overlap_workspace_f ws_f;

static int convex_mode, clip_mode;

static void evaluate(const poly_pose *a, const poly_pose *b, int use_records, poly_overlap_result *result)
{
  /* First evaluation: the path under test; second: what it is checked against. clip: the clipping path
   * (poly_clip.h) against the general records path; otherwise the clipping path is off. */
  int use_convex = convex_mode && use_records;
  ws_d.use_clip = ws_f.use_clip = clip_mode && use_records;
  if (convex_mode || clip_mode) use_records = 1;
  ws_d.use_convex = ws_f.use_convex = use_convex;
  if (precision == POLY_PRECISION_DOUBLE) {
    ws_d.use_records = use_records;
    poly_overlap_d(&view_d, a, &view_d, b, &ws_d, result);
  } else {
    ws_f.use_records = use_records;
    if (precision == POLY_PRECISION_SINGLE)
      poly_overlap_f(&view_f, a, &view_f, b, &ws_f, result);
    else
      poly_overlap_m(&view_f, a, &view_f, b, &ws_f, result);
  }
}

/* B resting on A as blocks rest in a pile: A at the identity, B above it turned about z by a random angle and
 * tilted by up to 0.01 rad, moved sideways by up to a tenth of the size, 1e-4 to 1e-2 of the size deep. */
static void resting_pose(const poly_shape *shape, double size, poly_pose *b)
{
  double turn = 2 * 3.14159265358979323846 * uniform(), tilt = 0.01 * uniform();
  double azimuth = 2 * 3.14159265358979323846 * uniform();
  double about_z[4] = {cos(0.5 * turn), 0, 0, sin(0.5 * turn)};
  double tilted[4] = {cos(0.5 * tilt), sin(0.5 * tilt) * cos(azimuth), sin(0.5 * tilt) * sin(azimuth), 0};
  poly_quat_multiply(tilted, about_z, b->quaternion);
  double rotation[9], top = -1e300, bottom = 1e300;
  poly_quat_to_matrix(b->quaternion, rotation);
  for (int v = 0; v < shape->num_vertices; v++) {
    const double *x = shape->vertices + 3 * v;
    double turned[3];
    poly_matrix_apply(rotation, x, turned);
    if (x[2] > top) top = x[2];
    if (turned[2] < bottom) bottom = turned[2];
  }
  double depth = size * pow(10.0, -4.0 + 2.0 * uniform());
  b->position[0] = 0.1 * size * (2 * uniform() - 1);
  b->position[1] = 0.1 * size * (2 * uniform() - 1);
  b->position[2] = top - bottom - depth;
}

int main(int argc, char **argv)
{
  if (argc < 4) {
    fprintf(stderr, "usage: records_paths SHAPE_FILE NUM_POSES double|single|mixed [CAPACITY]\n");
    return 2;
  }
  poly_shape shape;
  char message[512];
  if (poly_shape_load(argv[1], 1.0, &shape, message, sizeof message) != POLY_OK) {
    fprintf(stderr, "%s\n", message);
    return 1;
  }
  int num_poses = atoi(argv[2]);
  precision = !strcmp(argv[3], "single") ? POLY_PRECISION_SINGLE
                                          : (!strcmp(argv[3], "mixed") ? POLY_PRECISION_MIXED : POLY_PRECISION_DOUBLE);
  view_d = poly_shape_view_of(&shape);
  poly_shape_view_make_f(&shape, &view_f);
  poly_overlap_workspace_create_d(&ws_d, shape.num_vertices, shape.num_triangles);
  poly_overlap_workspace_create_f(&ws_f, shape.num_vertices, shape.num_triangles);
  ws_d.want_second_moment = ws_f.want_second_moment = 1;
  convex_mode = argc > 4 && !strcmp(argv[4], "convex");
  clip_mode = argc > 4 && !strcmp(argv[4], "clip");
  if (argc > 4 && !convex_mode && !clip_mode) ws_d.capacity_records = ws_f.capacity_records = atoi(argv[4]);

  double size = 2.0 * shape.bounding_radius, volume_scale = size * size * size;
  double worst_volume = 0, worst_centroid = 0, worst_normal = 0, worst_area = 0, worst_depth = 0, worst_second = 0;
  double worst_normal_scaled = 0;
  int flag_differences = 0, overlapping = 0, smoothed = 0, filtered = 0, wrongly_filtered = 0, hinted = 0;
  int codes_given = 0, codes_holding = 0; /* results' own separating codes, and those that part the pair as given */
  for (int p = 0; p < num_poses; p++) {
    poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}}, b = {{0, 0, 0}, {1, 0, 0, 0}};
    if (p % 8 == 5) {
      resting_pose(&shape, size, &b);
    } else if (p % 4 != 3) {
      random_quaternion(a.quaternion);
      random_quaternion(b.quaternion);
      double direction[3], norm = 0;
      for (int k = 0; k < 3; k++) {
        direction[k] = 2 * uniform() - 1;
        norm += direction[k] * direction[k];
      }
      double distance = size * (0.2 + 0.8 * uniform());
      for (int k = 0; k < 3; k++) b.position[k] = distance * direction[k] / sqrt(norm);
    } else {
      /* Degenerate: B at A's orientation or turned by a quarter turn about z,
       * moved by multiples of 1/4 of the size (flush faces, touching
       * vertices and edges; B identical to A). */
      int turns = (int)(4 * uniform());
      double angle = turns * 0.25 * 3.14159265358979323846;
      b.quaternion[0] = cos(angle);
      b.quaternion[3] = sin(angle);
      for (int k = 0; k < 3; k++) b.position[k] = size * 0.25 * (double)((int)(5 * uniform()) - 2);
    }
    poly_overlap_result fast, reference;
    evaluate(&a, &b, 1, &fast);
    evaluate(&a, &b, 0, &reference);
    /* The blocks path also rejects pairs separated by a face plane (blocks_path): filtered there means
     * no overlap in the reference, not its filter's verdict. */
    int filtered_differ = convex_mode || clip_mode ? (fast.filtered_out && reference.volume > 0) || (reference.filtered_out && !fast.filtered_out)
                                      : fast.filtered_out != reference.filtered_out;
    if (filtered_differ || fast.smoothed != reference.smoothed ||
        fast.recomputed != reference.recomputed || (fast.num_inconsistent > 0) != (reference.num_inconsistent > 0) ||
        (!convex_mode && !clip_mode && fast.num_nodes != reference.num_nodes)) {
      flag_differences++;
      if (flag_differences <= 5)
        fprintf(stderr,
                "pose %d: filtered %d/%d smoothed %d/%d recomputed %d/%d inconsistent %d/%d nodes %d/%d V %.17g/%.17g\n",
                p, fast.filtered_out, reference.filtered_out, fast.smoothed, reference.smoothed, fast.recomputed,
                reference.recomputed, fast.num_inconsistent, reference.num_inconsistent, fast.num_nodes,
                reference.num_nodes, fast.volume, reference.volume);
    }
    /* A pair rejected before the sums (the slab, the supporting triangles, the blocks' faces), or by any
     * supporting triangle's code of poly_overlap_still_separated (the pair style's hint from the step
     * before), must have no overlap: evaluated without the filter (every triangle, no early exit), its
     * volume is round-off. */
    int parted = fast.filtered_out, codes = 2 * (shape.num_support > 32 ? 32 : shape.num_support), by_code = 0;
    double gap; /* (tests/test_skip_apart.py checks the gaps) */
    for (int code = -1; code < codes && !by_code; code++) {
      int tried = code < 0 ? fast.separating : code;
      by_code = precision == POLY_PRECISION_DOUBLE ? poly_overlap_still_separated_d(&view_d, &a, &view_d, &b, tried, &gap)
                                                   : poly_overlap_still_separated_f(&view_f, &a, &view_f, &b, tried, &gap);
    }
    hinted += by_code;
    parted |= by_code;
    if (fast.separating >= 0) {
      codes_given++;
      codes_holding += precision == POLY_PRECISION_DOUBLE
                           ? poly_overlap_still_separated_d(&view_d, &a, &view_d, &b, fast.separating, &gap)
                           : poly_overlap_still_separated_f(&view_f, &a, &view_f, &b, fast.separating, &gap);
    }
    if (parted) {
      filtered++;
      ws_d.use_filter = ws_f.use_filter = 0;
      poly_overlap_result unfiltered;
      evaluate(&a, &b, 1, &unfiltered);
      ws_d.use_filter = ws_f.use_filter = 1;
      if (unfiltered.volume > 1e-12 * volume_scale) {
        wrongly_filtered++;
        fprintf(stderr, "pose %d: parted (filtered %d), but the volume without the filter is %.17g\n", p,
                fast.filtered_out, unfiltered.volume);
      }
    }
    overlapping += reference.volume > 0;
    smoothed += reference.smoothed;
    double dv = fabs(fast.volume - reference.volume) / volume_scale;
    if (dv > worst_volume) worst_volume = dv;
    if (reference.volume > 0 && fast.volume > 0) {
      double weight = reference.volume / volume_scale; /* relative errors of small overlaps scale like 1/V */
      for (int k = 0; k < 3; k++) {
        double dc = fabs(fast.centroid[k] - reference.centroid[k]) / size * weight;
        /* The normal is the direction of the area vector (eq. 4.19), ill-conditioned where that nearly
         * cancels (one body almost inside the other): compared where it is at least a tenth of the area. */
        double dn = reference.projected_area >= 0.1 * reference.area ? fabs(fast.normal[k] - reference.normal[k]) : 0;
        if (dc > worst_centroid) worst_centroid = dc;
        if (dn > worst_normal) worst_normal = dn;
        /* A normal from polygons of extent L, with corners known to eps times the size, is good to about
         * eps size / L: this weighs that out. */
        double scaled = dn * sqrt(reference.area) / size;
        if (scaled > worst_normal_scaled) worst_normal_scaled = scaled;
      }
      double da = fabs(fast.area - reference.area) / (size * size) * weight;
      double dd = reference.projected_area >= 0.1 * reference.area ? fabs(fast.depth - reference.depth) / size : 0;
      if (da > worst_area) worst_area = da;
      if (dd > worst_depth) worst_depth = dd;
      for (int e = 0; e < 6; e++) {
        double ds = fabs(fast.second_moment[e] - reference.second_moment[e]) / (volume_scale * size * size);
        if (ds > worst_second) worst_second = ds;
      }
    }
  }
  printf("poses %d overlapping %d smoothed %d\n", num_poses, overlapping, smoothed);
  printf("overflows %d\n", precision == POLY_PRECISION_DOUBLE ? ws_d.records_overflows : ws_f.records_overflows);
  printf("convex %d fallbacks %d\n", view_d.face_of != NULL,
         clip_mode ? ws_d.clip_fallbacks : precision == POLY_PRECISION_DOUBLE ? ws_d.convex_fallbacks : ws_f.convex_fallbacks);
  printf("clip_faces %d\n", view_d.clip.num_faces);
  printf("clip_pieces %d\n", view_d.clip.num_pieces);
  printf("clip_planes %d\nclip_vertices %d\n", view_d.clip.num_planes, view_d.clip.num_vertices);
  printf("volume %.3e\ncentroid %.3e\nnormal %.3e\narea %.3e\ndepth %.3e\nsecond_moment %.3e\nflag_differences %d\n",
         worst_volume, worst_centroid, worst_normal, worst_area, worst_depth, worst_second, flag_differences);
  printf("filtered %d\nwrongly_filtered %d\nhinted %d\n", filtered, wrongly_filtered, hinted);
  printf("codes_given %d\ncodes_holding %d\n", codes_given, codes_holding);
  printf("normal_scaled %.3e\n", worst_normal_scaled);
  poly_overlap_workspace_destroy_d(&ws_d);
  poly_overlap_workspace_destroy_f(&ws_f);
  poly_shape_view_free_f(&view_f);
  poly_shape_free(&shape);
  return 0;
}
