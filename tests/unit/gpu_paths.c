/* The GPU narrow phase's code paths, checked on the CPU (tests/test_gpu.py):
 *
 * - the pre-filter of gpu/poly_gpu.cu's bounding kernel (poly_overlap_slab on
 *   poly_overlap_relative_pose) drops only pairs that do not overlap: for
 *   random pairs of every reference shape, deep to separated, a pair it calls
 *   separated has no volume in poly_overlap without the filter (use_filter 0:
 *   all triangles, no early exit), and filtered_out set with it;
 * - the overlap computed in a workspace carved from a block of
 *   POLY_GPU_LOCAL_WORKSPACE_REALS scalars (the contact kernel's local-memory
 *   array) equals, bit for bit, the one in the host's own workspace, for every
 *   shape whose workspace fits; and the shapes gpu/poly_gpu.h names do fit.
 *
 * gpu_paths SHAPES_DIR; prints a line per shape and precision, then OK or FAIL. */
/* As the CUDA build lays the workspace out (poly_overlap_impl.h). */
#define POLY_OVERLAP_RECORDS 0
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "poly_gpu.h"
#include "poly_overlap.h"

#include "poly_overlap_instances.h"

static unsigned long long rng = 88172645463325252ULL;

static double uniform(void)
{
  rng ^= rng << 13;
  rng ^= rng >> 7;
  rng ^= rng << 17;
  return (double)(rng >> 11) / 9007199254740992.0;
}

/* A random unit vector of n components (direction or orientation). */
static void random_unit(double *v, int n)
{
  double length = 0.0;
  while (length < 0.1) {
    length = 0.0;
    for (int k = 0; k < n; k++) {
      v[k] = 2.0 * uniform() - 1.0;
      length += v[k] * v[k];
    }
    length = sqrt(length);
  }
  for (int k = 0; k < n; k++) v[k] /= length;
}

/* One precision: SUFFIX the overlap instance, GEOMETRY its shape views'. */
#define POLY_CHECK_PRECISION(SUFFIX, GEOMETRY, REAL)                                                                 \
  static int check##SUFFIX(const char *name, const poly_shape_view##GEOMETRY *view, double volume, int pairs,        \
                           int *fits)                                                                                \
  {                                                                                                                  \
    poly_overlap_workspace##GEOMETRY host;                                                                           \
    if (poly_overlap_workspace_create##GEOMETRY(&host, view->num_vertices, view->num_triangles)) return 1;          \
    host.use_convex = 0; /* the device has no convex path: the host's general path gives the device's bits */        \
    host.use_clip = 0;   /* nor the clipping path in this kernel (clip_contact_kernel has it; test_gpu.py) */       \
    size_t local_bytes = POLY_GPU_LOCAL_WORKSPACE_REALS * sizeof(REAL);                                              \
    size_t needed = poly_overlap_workspace_layout##SUFFIX(NULL, NULL, view->num_vertices, view->num_triangles);     \
    *fits = needed <= local_bytes;                                                                                   \
    double *block = (double *)malloc(local_bytes);                                                                   \
    poly_overlap_workspace##GEOMETRY local;                                                                          \
    if (*fits) poly_overlap_workspace_layout##SUFFIX(&local, block, view->num_vertices, view->num_triangles);       \
    int failures = 0, separated = 0, contacts = 0;                                                                   \
    for (int p = 0; p < pairs; p++) {                                                                                \
      poly_pose a, b;                                                                                                \
      memset(&a, 0, sizeof a);                                                                                       \
      random_unit(a.quaternion, 4);                                                                                  \
      random_unit(b.quaternion, 4);                                                                                  \
      random_unit(b.position, 3);                                                                                    \
      double distance = 2.0 * (double)view->bounding_radius * (0.3 + 0.8 * uniform());                               \
      for (int k = 0; k < 3; k++) b.position[k] *= distance;                                                         \
      double rotation_a[9], rotation[9], translation[3], axis[3], extent_a, extent_b;                                \
      poly_overlap_relative_pose(a.position, a.quaternion, b.position, b.quaternion, rotation_a, rotation,           \
                                 translation);                                                                       \
      int cut = poly_overlap_slab##SUFFIX(view, view, rotation, translation, axis, &extent_a, &extent_b);            \
      poly_overlap_result reference, unfiltered;                                                                     \
      poly_overlap##SUFFIX(view, &a, view, &b, &host, &reference);                                                   \
      host.use_filter = 0;                                                                                           \
      poly_overlap##SUFFIX(view, &a, view, &b, &host, &unfiltered);                                                  \
      host.use_filter = 1;                                                                                           \
      separated += cut;                                                                                              \
      contacts += reference.volume > 1e-12 * volume;                                                                 \
      if (cut && !(reference.filtered_out && unfiltered.volume <= 1e-12 * volume) && failures++ < 5) {              \
        printf("FAIL %s" #SUFFIX " pair %d: the pre-filter drops an overlap of volume %g\n", name, p,                \
               unfiltered.volume);                                                                                   \
      }                                                                                                              \
      if (*fits) {                                                                                                   \
        /* Zeroed first: poly_overlap_local leaves the world-frame fields and the padding alone. */                  \
        poly_overlap_result in_block, again;                                                                         \
        memset(&in_block, 0, sizeof in_block);                                                                       \
        memset(&again, 0, sizeof again);                                                                             \
        double centroid[3] = {0, 0, 0}, normal[3] = {0, 0, 0}, host_centroid[3] = {0, 0, 0},                         \
               host_normal[3] = {0, 0, 0};                                                                           \
        poly_overlap_local##SUFFIX(view, view, rotation, translation, &local, centroid, normal, &in_block);         \
        poly_overlap_local##SUFFIX(view, view, rotation, translation, &host, host_centroid, host_normal, &again);    \
        if (memcmp(&in_block, &again, sizeof again) || memcmp(centroid, host_centroid, sizeof centroid) ||           \
            memcmp(normal, host_normal, sizeof normal) || in_block.volume != reference.volume) {                     \
          if (failures++ < 5)                                                                                        \
            printf("FAIL %s" #SUFFIX " pair %d: the local-memory workspace gives another result\n", name, p);        \
        }                                                                                                            \
      }                                                                                                              \
    }                                                                                                                \
    printf("%-20s %s: %d pairs, %d in contact, %d dropped by the pre-filter; workspace %zu bytes, %s\n", name,       \
           #SUFFIX, pairs, contacts, separated, needed, *fits ? "local memory" : "global scratch");                  \
    if (contacts < pairs / 10 || separated < pairs / 20) {                                                           \
      printf("FAIL %s" #SUFFIX ": too few contacts or separated pairs to test anything\n", name);                    \
      failures++;                                                                                                    \
    }                                                                                                                \
    free(block);                                                                                                     \
    poly_overlap_workspace_destroy##GEOMETRY(&host);                                                                 \
    return failures;                                                                                                 \
  }

POLY_CHECK_PRECISION(_d, _d, double)
POLY_CHECK_PRECISION(_f, _f, float)
POLY_CHECK_PRECISION(_m, _f, float)

int main(int argc, char **argv)
{
  if (argc != 2) return 2;
  const char *names[] = {"schoenhardt.stl", "cube.stl", "tetrahedron.obj", "rock_10.obj", "icosphere_20.off",
                         "icosphere_80.off", "rock_40.obj", "rock_70.obj", "icosphere_320.off", "box_1x2x3.off"};
  /* The shapes gpu/poly_gpu.h says fit in local memory in double (and so in single and mixed). */
  const int local_in_double = 4;
  int failures = 0;
  for (int s = 0; s < (int)(sizeof names / sizeof names[0]); s++) {
    char path[1024], message[512];
    snprintf(path, sizeof path, "%s/%s", argv[1], names[s]);
    poly_shape shape;
    if (poly_shape_load(path, 0.01, &shape, message, sizeof message) != POLY_OK) {
      printf("FAIL %s\n", message);
      return 1;
    }
    int pairs = 20000 / shape.num_triangles;
    pairs = pairs < 100 ? 100 : pairs > 2000 ? 2000 : pairs;
    poly_shape_view_d view_d = poly_shape_view_of(&shape);
    poly_shape_view_f view_f;
    if (poly_shape_view_make_f(&shape, &view_f)) return 1;
    int fits[3];
    failures += check_d(names[s], &view_d, shape.volume, pairs, &fits[0]) +
                check_f(names[s], &view_f, shape.volume, pairs, &fits[1]) +
                check_m(names[s], &view_f, shape.volume, pairs, &fits[2]);
    for (int p = 0; p < 3; p++) {
      if (s < local_in_double && !fits[p]) {
        printf("FAIL %s: its workspace does not fit in POLY_GPU_LOCAL_WORKSPACE_REALS\n", names[s]);
        failures++;
      }
    }
    poly_shape_view_free_f(&view_f);
    poly_shape_free(&shape);
  }
  printf(failures ? "FAIL\n" : "OK\n");
  return failures ? 1 : 0;
}
