/* How long a contact's crossing structure lasts in a settled pile: the measurement behind the design of a
 * narrow phase that reuses it from step to step (doc/benchmarks.md, "Eleventh step: the crossing cache").
 *
 *   bash tools/coherence_study.sh [cube|rock] [steps]     (forms the pile, dumps every step, runs this)
 *   coherence_study SHAPES_DIR SHAPE_FILE SCALE DUMP
 *
 * DUMP holds consecutive snapshots (id x y z quatw quati quatj quatk, sorted by id) of one shape. For every pair
 * in contact in the first snapshot (poly_overlap_d), in A's body frame:
 *   - the crossing structure: the (edge, triangle) pairs, both ways, where an edge of one body crosses a
 *     triangle of the other (floating-point orientations: a study, not the narrow phase), and the first
 *     snapshot at which it differs from the first one's;
 *   - a certificate: the smallest motion that could change any (edge, triangle) decision, the clearance: for a
 *     pair decided by its ends' sides of the triangle's plane, their distances to it; by an orientation
 *     det(p1 - p0, q0 - p0, q1 - p0), |det| / (|p1 - p0| (|q0 - p0| + |q1 - p0|)), which bounds the motion of
 *     the q's that can turn its sign; a crossing needs all five, a rejection one. B's displacement relative to
 *     A since the first snapshot is the largest of its vertices' in A's frame, doubled to cover the points
 *     between them; the certificate lasts while it stays below the clearance.
 * Prints the contacts, how many keep their structure through all snapshots, and percentiles of the snapshots
 * the structure and the certificate last. */
#define _POSIX_C_SOURCE 199309L
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "poly_overlap.h"

#define MAX_PARTICLES 4096
#define MAX_SNAPSHOTS 4096

/* The next snapshot of `file` into poses (by id - 1); its particle count, or 0 at the end. */
static int read_snapshot(FILE *file, poly_pose *poses)
{
  char line[1024];
  int count = 0;
  while (fgets(line, sizeof line, file))
    if (strstr(line, "ITEM: NUMBER OF ATOMS")) break;
  if (!fgets(line, sizeof line, file) || sscanf(line, "%d", &count) != 1) return 0;
  while (fgets(line, sizeof line, file))
    if (strstr(line, "ITEM: ATOMS")) break;
  for (int n = 0; n < count; n++) {
    int id;
    poly_pose p;
    if (fscanf(file, "%d %lf %lf %lf %lf %lf %lf %lf", &id, &p.position[0], &p.position[1], &p.position[2],
               &p.quaternion[0], &p.quaternion[1], &p.quaternion[2], &p.quaternion[3]) != 8 ||
        id < 1 || id > MAX_PARTICLES)
      return 0;
    poses[id - 1] = p;
  }
  return count;
}

static void sub3(const double *a, const double *b, double *out)
{
  for (int k = 0; k < 3; k++) out[k] = a[k] - b[k];
}
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double *a) { return sqrt(dot3(a, a)); }
static void cross3(const double *a, const double *b, double *out)
{
  out[0] = a[1] * b[2] - a[2] * b[1], out[1] = a[2] * b[0] - a[0] * b[2], out[2] = a[0] * b[1] - a[1] * b[0];
}

/* B's vertices in A's body frame. */
static void in_frame_of_a(const poly_shape *shape, const poly_pose *a, const poly_pose *b, double *out)
{
  double ra[9], rb[9];
  poly_quat_to_matrix(a->quaternion, ra);
  poly_quat_to_matrix(b->quaternion, rb);
  for (int v = 0; v < shape->num_vertices; v++) {
    double world[3], d[3];
    poly_matrix_apply(rb, shape->vertices + 3 * v, world);
    for (int k = 0; k < 3; k++) d[k] = world[k] + b->position[k] - a->position[k];
    poly_matrix_apply_transpose(ra, d, out + 3 * v);
  }
}

/* The gap between the boxes of the segment p0 p1 and of the triangle (0 when they meet). */
static double box_gap(const double *p0, const double *p1, const double *const q[3])
{
  double gap = 0.0;
  for (int k = 0; k < 3; k++) {
    double low_p = fmin(p0[k], p1[k]), high_p = fmax(p0[k], p1[k]);
    double low_q = fmin(fmin(q[0][k], q[1][k]), q[2][k]), high_q = fmax(fmax(q[0][k], q[1][k]), q[2][k]);
    gap = fmax(gap, fmax(low_q - high_p, low_p - high_q));
  }
  return gap;
}

/* Edge p0 p1 against triangle q: 1 when it crosses; *clearance the motion its decision survives: for a
 * crossing, the least of its five predicates' margins; for a miss, the largest margin of a reason it misses
 * (both ends on one side of the plane, an orientation against the others, the boxes apart). */
static int edge_triangle(const double *p0, const double *p1, const double *q0, const double *q1, const double *q2,
                         double *clearance)
{
  const double *q[3] = {q0, q1, q2};
  double e1[3], e2[3], normal[3], o0[3], o1[3], d[3];
  sub3(q1, q0, e1);
  sub3(q2, q0, e2);
  cross3(e1, e2, normal);
  const double size = norm3(normal);
  sub3(p0, q0, o0);
  sub3(p1, q0, o1);
  const double d0 = dot3(normal, o0) / size, d1 = dot3(normal, o1) / size;
  const double sides = fmin(fabs(d0), fabs(d1));
  const int straddles = (d0 > 0) != (d1 > 0);
  sub3(p1, p0, d);
  const double length = norm3(d);
  int signs[3];
  double margins[3];
  for (int k = 0; k < 3; k++) {
    double a[3], b[3], c[3];
    sub3(q[k], p0, a);
    sub3(q[(k + 1) % 3], p0, b);
    cross3(a, b, c);
    const double det = dot3(d, c);
    signs[k] = det > 0 ? 1 : -1;
    margins[k] = fabs(det) / (length * (norm3(a) + norm3(b)));
  }
  const int agree = signs[0] == signs[1] && signs[1] == signs[2];
  if (straddles && agree) {
    *clearance = fmin(sides, fmin(margins[0], fmin(margins[1], margins[2])));
    return 1;
  }
  double reason = fmax(straddles ? 0.0 : sides, box_gap(p0, p1, q));
  if (!agree) {
    const int majority = signs[0] + signs[1] + signs[2] > 0 ? 1 : -1;
    for (int k = 0; k < 3; k++)
      if (signs[k] != majority) reason = fmax(reason, margins[k]);
  }
  *clearance = reason;
  return 0;
}

/* The crossing structure of edges of `p` (vertices xp) against triangles of `q` (vertices xq) as bits of `bits`
 * (edge * triangles + triangle), and the least clearance over all their pairs. */
static double structure(const poly_shape *p, const double *xp, const poly_shape *q, const double *xq,
                        unsigned char *bits)
{
  double least = DBL_MAX;
  for (int e = 0; e < p->num_edges; e++) {
    const double *p0 = xp + 3 * p->edges[2 * e], *p1 = xp + 3 * p->edges[2 * e + 1];
    for (int t = 0; t < q->num_triangles; t++) {
      const int *tri = q->triangles + 3 * t;
      double clearance;
      bits[e * q->num_triangles + t] =
          (unsigned char)edge_triangle(p0, p1, xq + 3 * tri[0], xq + 3 * tri[1], xq + 3 * tri[2], &clearance);
      if (clearance < least) least = clearance;
    }
  }
  return least;
}

static int compare_ints(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

static void print_percentiles(const char *what, int *values, int count, int snapshots)
{
  qsort(values, (size_t)count, sizeof(int), compare_ints);
  int full = 0;
  for (int n = 0; n < count; n++) full += values[n] >= snapshots - 1;
  printf("%s: 10th percentile %d, median %d, 90th %d steps; %d of %d (%.0f %%) through all %d steps\n", what,
         values[count / 10], values[count / 2], values[(9 * count) / 10], full, count, 100.0 * full / count,
         snapshots - 1);
}

int main(int argc, char **argv)
{
  if (argc < 5) {
    fprintf(stderr, "usage: %s SHAPES_DIR SHAPE_FILE SCALE DUMP\n", argv[0]);
    return 2;
  }
  poly_shape shape;
  if (load_shape(argv[1], argv[2], atof(argv[3]), &shape)) return 1;
  FILE *file = fopen(argv[4], "r");
  if (!file) {
    fprintf(stderr, "cannot open %s\n", argv[4]);
    return 1;
  }
  poly_pose *poses = calloc((size_t)MAX_SNAPSHOTS * MAX_PARTICLES, sizeof *poses);
  int snapshots = 0, particles = 0;
  while (snapshots < MAX_SNAPSHOTS && (particles = read_snapshot(file, poses + (size_t)snapshots * MAX_PARTICLES)) > 0)
    snapshots++;
  fclose(file);
  particles = 0;
  for (int i = 0; i < MAX_PARTICLES; i++)
    if (poses[i].quaternion[0] != 0.0 || poses[i].quaternion[1] != 0.0 || poses[i].quaternion[2] != 0.0 ||
        poses[i].quaternion[3] != 0.0)
      particles = i + 1;
  if (snapshots < 2 || particles == 0) {
    fprintf(stderr, "need at least two snapshots in %s\n", argv[4]);
    return 1;
  }
  poly_shape_view_d view = poly_shape_view_of(&shape);
  poly_overlap_workspace_d workspace;
  if (poly_overlap_workspace_create_d(&workspace, shape.num_vertices, shape.num_triangles) != 0) return 1;
  const size_t pairs_bits = (size_t)shape.num_edges * (size_t)shape.num_triangles;
  unsigned char *first = malloc(2 * pairs_bits), *now = malloc(2 * pairs_bits);
  double *xb = malloc(sizeof(double) * 3 * (size_t)shape.num_vertices);
  double *xa = malloc(sizeof(double) * 3 * (size_t)shape.num_vertices);
  double *previous = malloc(sizeof(double) * 3 * (size_t)shape.num_vertices);
  double *reference = malloc(sizeof(double) * 3 * (size_t)shape.num_vertices);
  int *structure_life = malloc(sizeof(int) * (size_t)particles * particles);
  int *certificate_life = malloc(sizeof(int) * (size_t)particles * particles);
  double *clearances = malloc(sizeof(double) * (size_t)particles * particles);
  double *motions = malloc(sizeof(double) * (size_t)particles * particles);
  int contacts = 0;
  memcpy(xa, shape.vertices, sizeof(double) * 3 * (size_t)shape.num_vertices);
  const double reach = 2.0 * shape.bounding_radius;
  for (int i = 0; i < particles; i++)
    for (int j = i + 1; j < particles; j++) {
      const poly_pose *a0 = &poses[i], *b0 = &poses[j];
      double d[3];
      sub3(a0->position, b0->position, d);
      if (norm3(d) >= reach) continue;
      poly_overlap_result result;
      poly_overlap_d(&view, a0, &view, b0, &workspace, &result);
      if (!(result.volume > 0.0)) continue;
      in_frame_of_a(&shape, a0, b0, xb);
      double clearance = structure(&shape, xa, &shape, xb, first);
      double other = structure(&shape, xb, &shape, xa, first + pairs_bits);
      clearance = other < clearance ? other : clearance;
      memcpy(previous, xb, sizeof(double) * 3 * (size_t)shape.num_vertices);
      memcpy(reference, xb, sizeof(double) * 3 * (size_t)shape.num_vertices);
      int same_until = snapshots - 1, certified_until = -1;
      double first_motion = 0.0;
      for (int s = 1; s < snapshots; s++) {
        const poly_pose *a = &poses[(size_t)s * MAX_PARTICLES + i], *b = &poses[(size_t)s * MAX_PARTICLES + j];
        in_frame_of_a(&shape, a, b, xb);
        /* From the first snapshot, not summed over the steps: the predicates compare the pose with that one. */
        double step = 0.0, moved = 0.0;
        for (int v = 0; v < shape.num_vertices; v++) {
          double m[3], f[3];
          sub3(xb + 3 * v, previous + 3 * v, m);
          sub3(xb + 3 * v, reference + 3 * v, f);
          step = fmax(step, norm3(m));
          moved = fmax(moved, 2.0 * norm3(f));
        }
        memcpy(previous, xb, sizeof(double) * 3 * (size_t)shape.num_vertices);
        if (s == 1) first_motion = 2.0 * step;
        if (certified_until < 0 && moved >= clearance) certified_until = s - 1;
        if (same_until == snapshots - 1) {
          structure(&shape, xa, &shape, xb, now);
          structure(&shape, xb, &shape, xa, now + pairs_bits);
          if (memcmp(first, now, 2 * pairs_bits) != 0) same_until = s - 1;
        }
      }
      if (certified_until < 0) certified_until = snapshots - 1;
      structure_life[contacts] = same_until;
      certificate_life[contacts] = certified_until;
      clearances[contacts] = clearance / shape.bounding_radius;
      motions[contacts] = first_motion / shape.bounding_radius;
      contacts++;
    }
  printf("%s x %s: %d particles, %d snapshots, %d contacts in the first\n", argv[2], argv[3], particles, snapshots,
         contacts);
  if (contacts == 0) return 1;
  qsort(clearances, (size_t)contacts, sizeof(double), compare_doubles);
  qsort(motions, (size_t)contacts, sizeof(double), compare_doubles);
  printf("clearance / bounding radius: 10th percentile %.2e, median %.2e; motion per step / bounding radius: "
         "median %.2e, 90th percentile %.2e\n",
         clearances[contacts / 10], clearances[contacts / 2], motions[contacts / 2], motions[(9 * contacts) / 10]);
  print_percentiles("crossing structure unchanged", structure_life, contacts, snapshots);
  print_percentiles("certificate holds", certificate_life, contacts, snapshots);
  poly_overlap_workspace_destroy_d(&workspace);
  free(first), free(now), free(xb), free(xa), free(previous), free(reference);
  free(structure_life), free(certificate_life), free(clearances), free(motions), free(poses);
  return 0;
}
