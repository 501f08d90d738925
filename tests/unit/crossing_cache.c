/* The crossing cache (poly_crossing_cache, src/poly_overlap_cache_impl.h) against the search
 * (tests/test_crossing_cache.py): pairs in contact moved step by step, each step evaluated twice, by a workspace
 * that keeps the pair's cache from step to step and by one without a cache; every result field must be the same
 * bits.
 *
 *   crossing_cache SHAPE_FILE SEQUENCES STEPS double|single|mixed [near] [apart]
 *
 * Each sequence: both bodies randomly turned, B along a random direction at the distance that gives an overlap of
 * 0.1 % to 3 % of the volume, then STEPS steps of a random walk of B (translation and rotation, each step's size
 * log-uniform from 1e-7 to 1e-3 of the size per sequence, so that some certificates last and some do not), with a
 * jump of 1e-2 of the size one step in 40. With `near`, each sequence starts from a near miss instead: B just
 * beyond touching (a gap of 1e-5 to 1e-3 of the size along the direction), where no plane of the filter parts the
 * bodies though they do not overlap, so that the walk's evaluations are near misses and contacts. Prints the
 * evaluations, the contacts, the near misses, those whose results differ, the cache's hits (and those of near
 * misses), searches and certificates. With `apart`, both workspaces evaluate the pair as the pair style does one
 * not touching at its last evaluation (last_evaluation POLY_LAST_APART: the parting search, also after a replay the
 * certificate does not take), and each step is evaluated once more with the former filters: the volumes must be
 * the same bits; prints also the evaluations the search alone parted (`searched`) and those whose volumes differ
 * (`volumes_differ`). */
#define _POSIX_C_SOURCE 199309L
#include <string.h>

#include "../../tools/bench_common.h" /* uniform(), random_quaternion(), load_shape() */
#include "poly_overlap.h"

static void random_unit(double *u)
{
  const double z = 2.0 * uniform() - 1.0, angle = 2.0 * PI * uniform(), r = sqrt(1.0 - z * z);
  u[0] = r * cos(angle), u[1] = r * sin(angle), u[2] = z;
}

static int precision;
static poly_shape_view_d view_d;
static poly_shape_view_f view_f;

static void evaluate(const poly_pose *a, const poly_pose *b, poly_overlap_workspace_d *wd,
                     poly_overlap_workspace_f *wf, poly_overlap_result *result)
{
  memset(result, 0, sizeof *result);
  if (precision == POLY_PRECISION_DOUBLE) poly_overlap_d(&view_d, a, &view_d, b, wd, result);
  else if (precision == POLY_PRECISION_SINGLE) poly_overlap_f(&view_f, a, &view_f, b, wf, result);
  else poly_overlap_m(&view_f, a, &view_f, b, wf, result);
}

static int same_bits(const poly_overlap_result *x, const poly_overlap_result *y)
{
  return x->volume == y->volume && !memcmp(x->centroid, y->centroid, sizeof x->centroid) &&
         !memcmp(x->normal, y->normal, sizeof x->normal) && !memcmp(&x->depth, &y->depth, sizeof x->depth) &&
         !memcmp(&x->area, &y->area, sizeof x->area) &&
         !memcmp(&x->projected_area, &y->projected_area, sizeof x->projected_area) &&
         !memcmp(x->second_moment, y->second_moment, sizeof x->second_moment) && x->num_nodes == y->num_nodes &&
         x->num_inconsistent == y->num_inconsistent && x->filtered_out == y->filtered_out &&
         x->recomputed == y->recomputed && x->smoothed == y->smoothed && x->separating == y->separating;
}

int main(int argc, char **argv)
{
  if (argc < 5) {
    fprintf(stderr, "usage: crossing_cache SHAPE_FILE SEQUENCES STEPS double|single|mixed [near] [apart]\n");
    return 2;
  }
  poly_shape shape;
  if (load_shape(".", argv[1], 1.0, &shape)) return 1;
  const int sequences = atoi(argv[2]), steps = atoi(argv[3]);
  int near = 0, apart = 0;
  for (int k = 5; k < argc; k++) near |= !strcmp(argv[k], "near"), apart |= !strcmp(argv[k], "apart");
  precision = !strcmp(argv[4], "single") ? POLY_PRECISION_SINGLE
                                         : (!strcmp(argv[4], "mixed") ? POLY_PRECISION_MIXED : POLY_PRECISION_DOUBLE);
  view_d = poly_shape_view_of(&shape);
  if (poly_shape_view_make_f(&shape, &view_f) != 0) return 1;
  poly_overlap_workspace_d cached_d, plain_d;
  poly_overlap_workspace_f cached_f, plain_f;
  if (poly_overlap_workspace_create_d(&cached_d, shape.num_vertices, shape.num_triangles) ||
      poly_overlap_workspace_create_d(&plain_d, shape.num_vertices, shape.num_triangles) ||
      poly_overlap_workspace_create_f(&cached_f, shape.num_vertices, shape.num_triangles) ||
      poly_overlap_workspace_create_f(&plain_f, shape.num_vertices, shape.num_triangles))
    return 1;
  cached_d.want_second_moment = plain_d.want_second_moment = 1;
  cached_f.want_second_moment = plain_f.want_second_moment = 1;
  poly_crossing_cache cache;
  cached_d.crossing_cache = cached_f.crossing_cache = &cache;
  const int last = apart ? POLY_LAST_APART : POLY_LAST_UNKNOWN;
  cached_d.last_evaluation = cached_f.last_evaluation = plain_d.last_evaluation = plain_f.last_evaluation = last;
  const double size = 2.0 * shape.bounding_radius, volume = shape.volume;
  long evaluations = 0, differ = 0, contacts = 0, misses = 0, miss_hits = 0, searched = 0, volumes_differ = 0;
  for (int s = 0; s < sequences; s++) {
    poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}}, b;
    for (int attempt = 0; attempt < 1000; attempt++) {
      random_quaternion(a.quaternion);
      random_quaternion(b.quaternion);
      double direction[3], low = 0.0, high = size, target = near ? 0.0 : pow(10.0, -3.0 + 1.5 * uniform());
      random_unit(direction);
      for (int i = 0; i < 60; i++) {
        double middle = 0.5 * (low + high);
        for (int k = 0; k < 3; k++) b.position[k] = middle * direction[k];
        poly_overlap_result r;
        evaluate(&a, &b, &plain_d, &plain_f, &r);
        if (r.volume > target * volume) low = middle;
        else high = middle;
      }
      if (!near) break;
      /* Just beyond touching: a near miss when the filter does not part them (else another pose). */
      const double gap = size * pow(10.0, -5.0 + 2.0 * uniform());
      for (int k = 0; k < 3; k++) b.position[k] = (high + gap) * direction[k];
      poly_overlap_result r;
      evaluate(&a, &b, &plain_d, &plain_f, &r);
      if (!r.filtered_out && !(r.volume > 0.0)) break;
    }
    memset(&cache, 0, sizeof cache);
    const double pace = size * pow(10.0, -7.0 + 4.0 * uniform());
    for (int t = 0; t < steps; t++) {
      const double move = (t % 40 == 39) ? 1e-2 * size : pace;
      double u[3], axis[3];
      random_unit(u);
      random_unit(axis);
      for (int k = 0; k < 3; k++) b.position[k] += move * u[k];
      const double angle = move / size, turn[4] = {cos(0.5 * angle), sin(0.5 * angle) * axis[0],
                                                    sin(0.5 * angle) * axis[1], sin(0.5 * angle) * axis[2]};
      double q[4];
      poly_quat_multiply(turn, b.quaternion, q);
      double norm = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      for (int k = 0; k < 4; k++) b.quaternion[k] = q[k] / norm;
      poly_overlap_result with, without;
      const long hits_before = cached_d.cache_hits + cached_f.cache_hits;
      evaluate(&a, &b, &cached_d, &cached_f, &with);
      evaluate(&a, &b, &plain_d, &plain_f, &without);
      evaluations++;
      contacts += without.volume > 0.0;
      const int miss = !without.filtered_out && !(without.volume > 0.0);
      misses += miss;
      miss_hits += miss && cached_d.cache_hits + cached_f.cache_hits > hits_before;
      if (apart) {
        poly_overlap_result former;
        plain_d.last_evaluation = plain_f.last_evaluation = POLY_LAST_UNKNOWN;
        evaluate(&a, &b, &plain_d, &plain_f, &former);
        plain_d.last_evaluation = plain_f.last_evaluation = POLY_LAST_APART;
        searched += without.filtered_out && !former.filtered_out;
        volumes_differ += memcmp(&former.volume, &without.volume, sizeof former.volume) != 0;
      }
      if (!same_bits(&with, &without)) {
        if (differ < 5)
          fprintf(stderr, "sequence %d step %d: volume %.17g against %.17g\n", s, t, with.volume, without.volume);
        differ++;
      }
    }
  }
  const int single = precision != POLY_PRECISION_DOUBLE;
  printf("evaluations %ld contacts %ld misses %ld differ %ld hits %ld miss_hits %ld searches %ld certificates %ld "
         "searched %ld volumes_differ %ld\n",
         evaluations, contacts, misses, differ, single ? cached_f.cache_hits : cached_d.cache_hits, miss_hits,
         single ? cached_f.cache_searches : cached_d.cache_searches,
         single ? cached_f.cache_certificates : cached_d.cache_certificates, searched, volumes_differ);
  poly_overlap_workspace_destroy_d(&cached_d);
  poly_overlap_workspace_destroy_d(&plain_d);
  poly_overlap_workspace_destroy_f(&cached_f);
  poly_overlap_workspace_destroy_f(&plain_f);
  poly_shape_view_free_f(&view_f);
  poly_shape_free(&shape);
  return 0;
}
