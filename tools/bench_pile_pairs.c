/* The narrow phase on a settled pile's own pairs: every pair of a LIGGGHTS dump (id x y z quatw quati quatj
 * quatk, one shape) whose centres are within two bounding radii, through poly_overlap_d as the pair style calls
 * it (double, second moments on: the default rocking damping asks for them). Prints the pairs, the contacts, the
 * time of one pass over all pairs (median and fastest of `repeats`, microseconds) and a hash of every result
 * field, which is the same before and after a change that keeps the bits:
 *
 *   bash tools/bench_pile_pairs.sh [cube|rock] [repeats]     (runs the pile deck for the dump, then this)
 *   bench_pile_pairs SHAPES_DIR SHAPE_FILE SCALE DUMP [repeats]
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_common.h"
#include "poly_overlap.h"
#include "result_hash.h"

#define MAX_PARTICLES 100000

typedef struct pile_pairs {
  const poly_shape_view_d *view;
  poly_pose *a, *b;
  int count;
  poly_overlap_workspace_d *workspace;
} pile_pairs;

static volatile double sink;

static void one_pass(void *context)
{
  pile_pairs *pairs = (pile_pairs *)context;
  double volume = 0.0;
  for (int p = 0; p < pairs->count; p++) {
    poly_overlap_result result;
    poly_overlap_d(pairs->view, &pairs->a[p], pairs->view, &pairs->b[p], pairs->workspace, &result);
    volume += result.volume;
  }
  sink = volume;
}

/* The hash of every result field over the pairs (tools/result_hash.h), and the contacts. */
static unsigned long long result_hash(const pile_pairs *pairs, int *contacts)
{
  unsigned long long hash = RESULT_HASH_START;
  *contacts = 0;
  for (int p = 0; p < pairs->count; p++) {
    poly_overlap_result r;
    poly_overlap_d(pairs->view, &pairs->a[p], pairs->view, &pairs->b[p], pairs->workspace, &r);
    *contacts += r.volume > 0.0;
    hash = result_hash_add(hash, &r);
  }
  return hash;
}

static int read_dump(const char *path, poly_pose *poses)
{
  FILE *file = fopen(path, "r");
  if (!file) return -1;
  char line[1024];
  while (fgets(line, sizeof line, file) && !strstr(line, "ITEM: ATOMS")) {}
  int count = 0, id;
  while (count < MAX_PARTICLES) {
    poly_pose *p = &poses[count];
    if (fscanf(file, "%d %lf %lf %lf %lf %lf %lf %lf", &id, &p->position[0], &p->position[1], &p->position[2],
               &p->quaternion[0], &p->quaternion[1], &p->quaternion[2], &p->quaternion[3]) != 8)
      break;
    count++;
  }
  fclose(file);
  return count;
}

int main(int argc, char **argv)
{
  if (argc < 5) {
    fprintf(stderr, "usage: %s SHAPES_DIR SHAPE_FILE SCALE DUMP [repeats]\n", argv[0]);
    return 2;
  }
  poly_shape shape;
  if (load_shape(argv[1], argv[2], atof(argv[3]), &shape)) return 1;
  const int repeats = argc > 5 ? atoi(argv[5]) : 7;
  poly_pose *poses = calloc(MAX_PARTICLES, sizeof *poses);
  const int particles = read_dump(argv[4], poses);
  if (particles <= 0) {
    fprintf(stderr, "no particles read from %s\n", argv[4]);
    return 1;
  }
  int capacity = 1024;
  pile_pairs pairs = {0};
  pairs.a = malloc(sizeof(poly_pose) * (size_t)capacity);
  pairs.b = malloc(sizeof(poly_pose) * (size_t)capacity);
  const double reach = 2.0 * shape.bounding_radius;
  for (int i = 0; i < particles; i++)
    for (int j = i + 1; j < particles; j++) {
      double d2 = 0.0;
      for (int k = 0; k < 3; k++) d2 += (poses[i].position[k] - poses[j].position[k]) *
                                        (poses[i].position[k] - poses[j].position[k]);
      if (d2 >= reach * reach) continue;
      if (pairs.count == capacity) {
        capacity *= 2;
        pairs.a = realloc(pairs.a, sizeof(poly_pose) * (size_t)capacity);
        pairs.b = realloc(pairs.b, sizeof(poly_pose) * (size_t)capacity);
      }
      pairs.a[pairs.count] = poses[i];
      pairs.b[pairs.count++] = poses[j];
    }
  poly_shape_view_d view = poly_shape_view_of(&shape);
  poly_overlap_workspace_d workspace;
  if (poly_overlap_workspace_create_d(&workspace, shape.num_vertices, shape.num_triangles) != 0) return 1;
  workspace.want_second_moment = 1;
  pairs.view = &view;
  pairs.workspace = &workspace;
  int contacts;
  const unsigned long long hash = result_hash(&pairs, &contacts);
  double fastest;
  const double median = median_time_us(one_pass, &pairs, 1, repeats, &fastest);
  printf("%s x %s: %d particles, %d pairs within two bounding radii, %d in contact\n", argv[2], argv[3], particles,
         pairs.count, contacts);
  printf("one pass over the pairs: %.1f us median, %.1f fastest (%d repeats); %.3f us per contact\n", median, fastest,
         repeats, median / contacts);
  printf("results hash %016llx\n", hash);
  poly_overlap_workspace_destroy_d(&workspace);
  free(pairs.a);
  free(pairs.b);
  free(poses);
  return 0;
}
