/* The gap a filtered-out evaluation proves (poly_overlap_result's gap; proved_gap in src/poly_overlap_impl.h), which
 * the pair style lets a pair wait on (`skip_apart`, tests/test_skip_apart.py): pairs of shapes of any sizes, at
 * random poses with their bounding spheres overlapping, and those found apart with a gap moved by 0.5, 0.9, 0.99
 * and 0.999 of FACTOR times it, the travel split at random between B's shift towards A along the centre line (the
 * way the gap closes fastest), A's shift and both turns (2 r |dq| of travel for a turn dq, as the pair style counts
 * it). Each moved pose evaluated as the pair style would (the default paths) and without any filter or special
 * path (ws->use_filter, use_clip, use_convex 0: every triangle, exact predicates), both of which must find no
 * volume while FACTOR is at most 1. With FACTOR 3 they must find some: the gap is tight enough for the check to fail.
 * Every other pair parted by a supporting triangle takes the gap of poly_overlap_still_separated (the pair style's
 * hint at a later step) instead.
 *
 *   apart_gap A_FILE A_SCALE B_FILE B_SCALE CASES double|single|mixed FACTOR [far] [seek]
 *
 * `far`: the pair 1e3 sizes from the origin. `seek`: the evaluations search a parting plane where no filter parts
 * the pair (ws->last_evaluation POLY_LAST_APART, poly_overlap_parting_impl.h), as the pair style does for pairs
 * not touching at their last evaluation.
 * Prints the pairs found apart with a gap, those moved by the hint's gap, the poses tested, and those with a volume
 * by either evaluation; with `seek` also the pairs only the search parted (`by_search`: apart, with a gap or not,
 * found so by no filter without it, or found apart by the clipping path without it but with no gap), of them those
 * whose evaluation without any filter finds a volume where they are (`by_search_overlapping`, which must be 0), and
 * of their moved poses those tested (`by_search_tested`) and those with a volume without any filter
 * (`by_search_moved_overlapping`). */
#define _POSIX_C_SOURCE 199309L
#include <string.h>

#include "../../tools/bench_common.h" /* uniform(), random_quaternion(), load_shape() */
#include "poly_overlap.h"
#include "poly_rigid.h"

static int precision;
static poly_shape_view_d da, db;
static poly_shape_view_f fa, fb;

static void evaluate(const poly_pose *a, const poly_pose *b, poly_overlap_workspace_d *wd, poly_overlap_workspace_f *wf,
                     poly_overlap_result *r)
{
  memset(r, 0, sizeof *r);
  if (precision == POLY_PRECISION_SINGLE) poly_overlap_f(&fa, a, &fb, b, wf, r);
  else if (precision == POLY_PRECISION_MIXED) poly_overlap_m(&fa, a, &fb, b, wf, r);
  else poly_overlap_d(&da, a, &db, b, wd, r);
}

static void random_unit(double *u)
{
  const double z = 2.0 * uniform() - 1.0, angle = 2.0 * PI * uniform(), r = sqrt(1.0 - z * z);
  u[0] = r * cos(angle), u[1] = r * sin(angle), u[2] = z;
}

/* q turned about a random axis so that |q' - q| = chord (2 sin(theta/4) = chord). */
static void turn(double *q, double chord)
{
  const double angle = 4.0 * asin(chord < 2.0 ? 0.5 * chord : 1.0);
  double axis[3], out[4];
  random_unit(axis);
  double by[4] = {cos(0.5 * angle), sin(0.5 * angle) * axis[0], sin(0.5 * angle) * axis[1], sin(0.5 * angle) * axis[2]};
  poly_quat_multiply(by, q, out);
  for (int k = 0; k < 4; k++) q[k] = out[k];
}

int main(int argc, char **argv)
{
  if (argc < 8) {
    fprintf(stderr, "usage: apart_gap A_FILE A_SCALE B_FILE B_SCALE CASES double|single|mixed FACTOR [far] [seek]\n");
    return 2;
  }
  poly_shape sa, sb;
  if (load_shape(".", argv[1], atof(argv[2]), &sa) || load_shape(".", argv[3], atof(argv[4]), &sb)) return 1;
  const int cases = atoi(argv[5]);
  precision = !strcmp(argv[6], "single") ? POLY_PRECISION_SINGLE
                                         : (!strcmp(argv[6], "mixed") ? POLY_PRECISION_MIXED : POLY_PRECISION_DOUBLE);
  const double factor = atof(argv[7]);
  int far = 0, seek = 0;
  for (int k = 8; k < argc; k++) far |= !strcmp(argv[k], "far"), seek |= !strcmp(argv[k], "seek");
  da = poly_shape_view_of(&sa), db = poly_shape_view_of(&sb);
  if (poly_shape_view_make_f(&sa, &fa) || poly_shape_view_make_f(&sb, &fb)) return 1;
  int nv = sa.num_vertices > sb.num_vertices ? sa.num_vertices : sb.num_vertices;
  int nt = sa.num_triangles > sb.num_triangles ? sa.num_triangles : sb.num_triangles;
  poly_overlap_workspace_d wd, bare_d;
  poly_overlap_workspace_f wf, bare_f;
  if (poly_overlap_workspace_create_d(&wd, nv, nt) || poly_overlap_workspace_create_d(&bare_d, nv, nt) ||
      poly_overlap_workspace_create_f(&wf, nv, nt) || poly_overlap_workspace_create_f(&bare_f, nv, nt))
    return 1;
  bare_d.use_filter = bare_d.use_clip = bare_d.use_convex = 0;
  bare_f.use_filter = bare_f.use_clip = bare_f.use_convex = 0;
  wd.last_evaluation = wf.last_evaluation = seek ? POLY_LAST_APART : POLY_LAST_UNKNOWN;
  const double ra = sa.bounding_radius, rb = sb.bounding_radius, reach = ra + rb;
  const double fractions[4] = {0.5, 0.9, 0.99, 0.999};
  long apart = 0, hinted = 0, tested = 0, found = 0, found_bare = 0, by_search = 0, by_search_overlapping = 0;
  long by_search_tested = 0, by_search_moved_overlapping = 0;
  for (int c = 0; c < cases; c++) {
    poly_pose a, b;
    double offset[3] = {0.0, 0.0, 0.0};
    if (far) random_unit(offset);
    random_quaternion(a.quaternion);
    random_quaternion(b.quaternion);
    double u[3];
    random_unit(u);
    const double distance = (0.4 + 0.6 * uniform()) * reach;
    for (int k = 0; k < 3; k++) {
      a.position[k] = 1e3 * reach * offset[k];
      b.position[k] = a.position[k] + distance * u[k];
    }
    poly_overlap_result r;
    evaluate(&a, &b, &wd, &wf, &r);
    if (!r.filtered_out) continue;
    int searched = 0;
    if (seek) {
      /* Parted by the search alone (with a gap or not): the filters without it leave the pair to the general
       * path, or the clipping finds it apart with no gap, and neither may find a volume, nor may the evaluation
       * without any filter. */
      poly_overlap_result unsought, bare;
      wd.last_evaluation = wf.last_evaluation = POLY_LAST_UNKNOWN;
      evaluate(&a, &b, &wd, &wf, &unsought);
      wd.last_evaluation = wf.last_evaluation = POLY_LAST_APART;
      if (!unsought.filtered_out || (!(unsought.gap > 0.0) && r.gap > 0.0)) {
        searched = 1;
        by_search++;
        memset(&bare, 0, sizeof bare);
        if (precision == POLY_PRECISION_DOUBLE) poly_overlap_d(&da, &a, &db, &b, &bare_d, &bare);
        else poly_overlap_f(&fa, &a, &fb, &b, &bare_f, &bare);
        by_search_overlapping += bare.volume > 0.0 || unsought.volume > 0.0;
      }
    }
    if (!(r.gap > 0.0)) continue;
    apart++;
    /* Every other pair parted by a supporting triangle moves by the gap the pair style's hint gives instead. */
    double gap = r.gap;
    if (r.separating >= 0 && c % 2 && precision != POLY_PRECISION_MIXED) {
      double hint_gap = 0.0;
      if (precision == POLY_PRECISION_DOUBLE) poly_overlap_still_separated_d(&da, &a, &db, &b, r.separating, &hint_gap);
      else poly_overlap_still_separated_f(&fa, &a, &fb, &b, r.separating, &hint_gap);
      if (hint_gap > 0.0) gap = hint_gap, hinted++;
    }
    for (int f = 0; f < 4; f++) {
      /* The travel, split at random: B towards A, A anywhere, A's and B's turns. */
      double w[4], sum = 0.0;
      for (int m = 0; m < 4; m++) sum += (w[m] = uniform());
      const double travel = factor * fractions[f] * gap;
      poly_pose ma = a, mb = b;
      double v[3];
      random_unit(v);
      for (int k = 0; k < 3; k++) {
        mb.position[k] -= travel * w[0] / sum * u[k];
        ma.position[k] += travel * w[1] / sum * v[k];
      }
      turn(ma.quaternion, travel * w[2] / sum / (2.0 * ra));
      turn(mb.quaternion, travel * w[3] / sum / (2.0 * rb));
      poly_overlap_result moved, bare;
      evaluate(&ma, &mb, &wd, &wf, &moved);
      memset(&bare, 0, sizeof bare);
      if (precision == POLY_PRECISION_DOUBLE) poly_overlap_d(&da, &ma, &db, &mb, &bare_d, &bare);
      else poly_overlap_f(&fa, &ma, &fb, &mb, &bare_f, &bare);
      tested++;
      found += moved.volume > 0.0;
      found_bare += bare.volume > 0.0;
      by_search_tested += searched;
      by_search_moved_overlapping += searched && bare.volume > 0.0;
    }
  }
  printf("apart %ld by_hint %ld tested %ld overlapping %ld overlapping_unfiltered %ld by_search %ld "
         "by_search_overlapping %ld by_search_tested %ld by_search_moved_overlapping %ld\n",
         apart, hinted, tested, found, found_bare, by_search, by_search_overlapping, by_search_tested,
         by_search_moved_overlapping);
  return 0;
}
