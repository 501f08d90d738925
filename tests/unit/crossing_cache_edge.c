/* The crossing cache (src/poly_overlap_cache_impl.h) at the edge of its certificates (tests/test_crossing_cache.py):
 * pairs of shapes of any sizes, certified in a contact or a near miss, then B moved by 0.5, 0.9, 0.99 and 0.999 of
 * the certificate's margin, the motion split at random between a turn and a shift in random directions; each pose
 * evaluated from the cache and by a search, which must give the same bits. Built with the certificates inflated
 * twice (-DPOLY_CACHE_MARGIN_SCALE=2) it must find differences.
 *
 * With `recheck`, the edge of the watched pairs' rechecks (cache_recheck) instead: B moved past the first watched
 * pair's margin (within the certificate) and evaluated twice there, so that the reached pairs are decided again and
 * their margins from that pose made, then moved from it by those fractions of the least of them; built with the
 * rechecks' margins twice as long (-DPOLY_CACHE_RECHECK_SCALE=2) it must find differences.
 *
 *   crossing_cache_edge A_FILE A_SCALE B_FILE B_SCALE CASES TRIALS double|single [near] [recheck]
 *
 * Prints the certificates, the poses tested, those evaluated from the cache and those whose results differ; with
 * `recheck` also the rechecks made and the poses whose watched decisions they spared. */
#define _POSIX_C_SOURCE 199309L
#include <string.h>

#include "../../tools/bench_common.h" /* uniform(), random_quaternion(), load_shape() */
#include "poly_overlap.h"
#include "poly_rigid.h"

static int single;
static poly_shape_view_d da, db;
static poly_shape_view_f fa, fb;
static void evaluate(const poly_pose *a, const poly_pose *b, poly_overlap_workspace_d *wd, poly_overlap_workspace_f *wf,
                     poly_overlap_result *r)
{
  memset(r, 0, sizeof *r);
  if (single) poly_overlap_f(&fa, a, &fb, b, wf, r);
  else poly_overlap_d(&da, a, &db, b, wd, r);
}
static int same(const poly_overlap_result *x, const poly_overlap_result *y)
{
  return x->volume == y->volume && !memcmp(x->centroid, y->centroid, sizeof x->centroid) &&
         !memcmp(x->normal, y->normal, sizeof x->normal) && x->depth == y->depth && x->area == y->area &&
         x->num_nodes == y->num_nodes && x->filtered_out == y->filtered_out && x->separating == y->separating;
}
static void random_unit(double *u)
{
  const double z = 2.0 * uniform() - 1.0, angle = 2.0 * PI * uniform(), r = sqrt(1.0 - z * z);
  u[0] = r * cos(angle), u[1] = r * sin(angle), u[2] = z;
}
/* B's pose b moved by the cache's motion m (less its rounding term): |R - R0|_F rb = s m and |dT| = (1 - s) m for a
 * random s, about a random axis and along a random direction. */
static void move(const poly_pose *b, double m, double rb, double size, poly_pose *moved)
{
  const double rounding = 16.0 * (single ? 5.9604645e-8 : 1.1102230246251565e-16) * (2.0 * size + 4.0 * size);
  const double s = uniform(), budget = m - rounding;
  const double frob = s * budget / rb, angle = 2.0 * asin(frob / (2.0 * sqrt(2.0)));
  double axis[3], u[3];
  random_unit(axis);
  random_unit(u);
  *moved = *b;
  double turn[4] = {cos(0.5 * angle), sin(0.5 * angle) * axis[0], sin(0.5 * angle) * axis[1], sin(0.5 * angle) * axis[2]}, q[4];
  poly_quat_multiply(turn, b->quaternion, q);
  for (int k = 0; k < 4; k++) moved->quaternion[k] = q[k];
  for (int k = 0; k < 3; k++) moved->position[k] = b->position[k] + (1.0 - s) * budget * u[k];
}
int main(int argc, char **argv)
{
  if (argc < 8) {
    fprintf(stderr, "usage: crossing_cache_edge A_FILE A_SCALE B_FILE B_SCALE CASES TRIALS double|single [near] "
                    "[recheck]\n");
    return 2;
  }
  poly_shape sa, sb;
  if (load_shape(".", argv[1], atof(argv[2]), &sa) || load_shape(".", argv[3], atof(argv[4]), &sb)) return 1;
  const int cases = atoi(argv[5]), trials = atoi(argv[6]);
  int near = 0, recheck = 0;
  for (int i = 8; i < argc; i++) {
    near |= !strcmp(argv[i], "near");
    recheck |= !strcmp(argv[i], "recheck");
  }
  single = !strcmp(argv[7], "single");
  da = poly_shape_view_of(&sa), db = poly_shape_view_of(&sb);
  if (poly_shape_view_make_f(&sa, &fa) || poly_shape_view_make_f(&sb, &fb)) return 1;
  int nv = sa.num_vertices > sb.num_vertices ? sa.num_vertices : sb.num_vertices;
  int nt = sa.num_triangles > sb.num_triangles ? sa.num_triangles : sb.num_triangles;
  poly_overlap_workspace_d cd, pd;
  poly_overlap_workspace_f cf, pf;
  if (poly_overlap_workspace_create_d(&cd, nv, nt) || poly_overlap_workspace_create_d(&pd, nv, nt) ||
      poly_overlap_workspace_create_f(&cf, nv, nt) || poly_overlap_workspace_create_f(&pf, nv, nt))
    return 1;
  poly_crossing_cache cache, saved;
  cd.crossing_cache = cf.crossing_cache = &cache;
  const double rb = sb.bounding_radius, size = sa.bounding_radius + sb.bounding_radius;
  long tested = 0, hits = 0, differ = 0, certs = 0, rechecked = 0, spared = 0;
  const double fractions[4] = {0.5, 0.9, 0.99, 0.999};
  for (int c = 0; c < cases; c++) {
    poly_pose a = {{0, 0, 0}, {1, 0, 0, 0}}, b;
    random_quaternion(b.quaternion);
    double dir[3], low = 0.0, high = 2.0 * size;
    random_unit(dir);
    double target = near ? 0.0 : pow(10.0, -3.0 + 1.5 * uniform()) * (sa.volume < sb.volume ? sa.volume : sb.volume);
    for (int i = 0; i < 60; i++) {
      double mid = 0.5 * (low + high);
      for (int k = 0; k < 3; k++) b.position[k] = mid * dir[k];
      poly_overlap_result r;
      evaluate(&a, &b, &pd, &pf, &r);
      if (r.volume > target) low = mid; else high = mid;
    }
    if (near) for (int k = 0; k < 3; k++) b.position[k] = (high + size * pow(10.0, -5.0 + 2.0 * uniform())) * dir[k];
    memset(&cache, 0, sizeof cache);
    poly_overlap_result r;
    evaluate(&a, &b, &cd, &cf, &r);
    evaluate(&a, &b, &cd, &cf, &r);
    if (!(cache.margin > 0.0)) continue;
    certs++;
    if (recheck && cache.num_watch == 0) continue;
    saved = cache;
    for (int t = 0; t < trials; t++) {
      cache = saved;
      poly_pose from = b;
      poly_crossing_cache start = saved;
      if (recheck) {
        /* Past the first watched pair's margin, within the certificate: evaluated twice, the second rechecks. */
        poly_overlap_result r1;
        move(&b, saved.watch_margin[0] + uniform() * 0.5 * (saved.margin - saved.watch_margin[0]), rb, size, &from);
        evaluate(&a, &from, &cd, &cf, &r1);
        evaluate(&a, &from, &cd, &cf, &r1);
        if (!(cache.recheck_count > 0 && cache.recheck_margin > 0.0 && cache.margin > 0.0)) continue;
        rechecked++;
        start = cache;
      }
      for (int f = 0; f < (recheck ? 8 : 1); f++) {
        cache = start;
        const double fraction = fractions[(recheck ? f : t) % 4];
        const double m = fraction * (recheck ? start.recheck_margin : start.margin) * (1.0 - 1e-9);
        poly_pose b1;
        move(&from, m, rb, size, &b1);
        const int skips = cache.recheck_skips;
        long h0 = cd.cache_hits + cf.cache_hits;
        poly_overlap_result with, without;
        evaluate(&a, &b1, &cd, &cf, &with);
        evaluate(&a, &b1, &pd, &pf, &without);
        tested++;
        spared += cache.recheck_skips > skips;
        hits += cd.cache_hits + cf.cache_hits > h0;
        if (!same(&with, &without)) {
          if (differ < 5) fprintf(stderr, "case %d trial %d frac %g: volume %.17g vs %.17g\n", c, t, fraction, with.volume, without.volume);
          differ++;
        }
      }
    }
  }
  printf("certificates %ld tested %ld hits %ld differ %ld", certs, tested, hits, differ);
  if (recheck) printf(" rechecked %ld spared %ld", rechecked, spared);
  printf("\n");
  return 0;
}
