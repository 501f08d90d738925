/* GPU vs CPU agreement of the narrow phase, pair by pair: for each reference
 * shape, `count` random overlapping pairs (each of two particles of its own)
 * go through poly_gpu_compute and through poly_overlap_d/f/m +
 * poly_contact_evaluate on the host; prints the worst relative difference of
 * V, centroid, normal, depth, forces, torques and history. The per-particle
 * sums of the fast path (no per-pair results) must equal the per-pair forces
 * exactly, and its history the per-pair path's. Usage:
 * gpu_agreement SHAPES_DIR COUNT double|single|mixed [gpu-only|bed [SHAPE]|shallow]
 * gpu-only: throughput only, no host comparison, with COUNT pairs scaled by
 * 8 / triangles per shape (at least 2000), so the GPU is filled for small
 * shapes and large ones finish in seconds.
 * bed: as gpu-only, but the pairs are a packed bed's mix (tools/bench_gpu.sh):
 * half in contact with an overlap of 0.1 to 3 % of the particle volume
 * (log-uniform, the distance bisected on the host as tools/bench_overlap.c
 * does), half with touching bounding spheres but bodies apart (distance
 * uniform between touching and the sum of the bounding radii); at most 4096
 * distinct poses per shape (fewer for large shapes), repeated over the pairs.
 * Prints pairs per second of the kernels alone and of the whole step. SHAPE:
 * only the shape of that name (file name without extension), which is then the
 * only shape uploaded, as in a deck of one particle template.
 * shallow: the checks below on pairs all in contact, each with an overlap of
 * 1e-6 to 1e-4 of the particle volume (log-uniform, bisected as for bed), and
 * per shape the median and the worst relative difference of V over them, each
 * against its own V (what rounding leaves of shallow contacts): at most 1e-10
 * in double; in single and mixed a median of 1e-4 and a worst of 9e-2 and
 * 3e-2, the accuracy doc/pair_polyhedral_volumetric.md states for shallow
 * contacts in those precisions.
 *
 * Scales: V and depth relative to themselves for overlaps above 1e-3 of the
 * particle volume (below that, relative to 1e-3 V_p: a grazing overlap's own
 * size is not a meaningful scale, its absolute error is); centroid relative to
 * the particle size; centroid, normal, forces and torques for overlaps above
 * 1e-3 V_p (the centroid of a grazing overlap is a ratio of two tiny sums).
 * A contact found by one side only is an error unless its volume is below the
 * precision floor (1e-6 V_p in single, 1e-12 V_p in double): the contact
 * threshold of 1e-12 V_p is then decided by round-off. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <algorithm>
#include <vector>

#include "poly_gpu.h"
#include "poly_overlap.h"

static double uniform(unsigned long long *state)
{
  *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*state >> 11) / 9007199254740992.0;
}

static void random_quaternion(unsigned long long *state, double q[4])
{
  for (int k = 0; k < 4; k++) q[k] = 2.0 * uniform(state) - 1.0;
  poly_quat_normalize(q);
}

// A bed-like relative pose of B (position offset and both orientations) for
// shape `shape`: in contact with the given overlap fraction, or (fraction 0)
// apart, somewhere between touching and the sum of the bounding radii.
static void bed_pose(const poly_shape_view_d &shape, double volume, double radius, double fraction,
                     unsigned long long *state, poly_overlap_workspace_d *ws, double offset[3], double qa[4],
                     double qb[4])
{
  poly_pose a, b;
  double direction[3], length = 0.0;
  while (length < 0.1) {
    for (int k = 0; k < 3; k++) direction[k] = 2.0 * uniform(state) - 1.0;
    length = sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
  }
  for (int k = 0; k < 3; k++) direction[k] /= length;
  random_quaternion(state, qa);
  random_quaternion(state, qb);
  memset(&a, 0, sizeof a);
  memcpy(a.quaternion, qa, sizeof a.quaternion);
  memcpy(b.quaternion, qb, sizeof b.quaternion);
  double near = 0.0, far = 2.0 * radius;
  for (int iteration = 0; iteration < 30; iteration++) {
    double middle = 0.5 * (near + far);
    for (int k = 0; k < 3; k++) b.position[k] = middle * direction[k];
    poly_overlap_result result;
    poly_overlap_d(&shape, &a, &shape, &b, ws, &result);
    if (result.volume > fraction * volume) near = middle;
    else far = middle;
  }
  double distance = fraction > 0.0 ? near : far + (2.0 * radius - far) * uniform(state);
  for (int k = 0; k < 3; k++) offset[k] = distance * direction[k];
}

static double seconds_since(const struct timespec &start)
{
  struct timespec stop;
  clock_gettime(CLOCK_MONOTONIC, &stop);
  return (stop.tv_sec - start.tv_sec) + 1e-9 * (stop.tv_nsec - start.tv_nsec);
}

int main(int argc, char **argv)
{
  if (argc < 4 || argc > 6) return 2;
  const bool bed = argc >= 5 && strcmp(argv[4], "bed") == 0;
  const bool shallow = argc == 5 && strcmp(argv[4], "shallow") == 0;
  const bool gpu_only = bed || (argc == 5 && strcmp(argv[4], "gpu-only") == 0);
  const char *only = bed && argc == 6 ? argv[5] : "";
  const char *names[] = {"schoenhardt.stl", "cube.stl", "tetrahedron.obj", "icosphere_80.off", "icosphere_320.off",
                         "icosphere_1280.off", "rock_10.obj", "rock_40.obj", "rock_70.obj", "rock_1000.obj"};
  const int num_shapes = 10;
  const int requested = atoi(argv[2]);
  int precision = strcmp(argv[3], "single") == 0  ? POLY_PRECISION_SINGLE
                  : strcmp(argv[3], "mixed") == 0 ? POLY_PRECISION_MIXED
                                                  : POLY_PRECISION_DOUBLE;
  std::vector<poly_shape> shapes(num_shapes);
  std::vector<const poly_shape *> pointers(num_shapes);
  int max_vertices = 1, max_triangles = 1;
  for (int s = 0; s < num_shapes; s++) {
    char path[1024], message[512];
    snprintf(path, sizeof path, "%s/%s", argv[1], names[s]);
    if (poly_shape_load(path, 0.01, &shapes[s], message, sizeof message) != POLY_OK) {
      printf("FAIL %s\n", message);
      return 1;
    }
    pointers[s] = &shapes[s];
    if (shapes[s].num_vertices > max_vertices) max_vertices = shapes[s].num_vertices;
    if (shapes[s].num_triangles > max_triangles) max_triangles = shapes[s].num_triangles;
  }
  // A bed of one shape (SHAPE given) uploads only that shape, as a deck of one template does: the kernels'
  // memory is sized for the shapes uploaded.
  int first_uploaded = 0, num_uploaded = num_shapes;
  for (int s = 0; *only && s < num_shapes; s++)
    if (strlen(only) == strcspn(names[s], ".") && strncmp(names[s], only, strlen(only)) == 0) {
      first_uploaded = s;
      num_uploaded = 1;
    }
  char message[512];
  if (poly_gpu_init(0, num_uploaded, &pointers[first_uploaded], message, sizeof message) != 0) {
    printf("FAIL %s\n", message);
    return 1;
  }
  // One atom type: materials indexed type_i * 2 + type_j.
  poly_material_pair material, materials[4];
  poly_material_pair_make(1e7, 0.25, 1e7, 0.25, poly_damping_beta_for_restitution(0.5), 0.5, &material);
  for (int m = 0; m < 4; m++) materials[m] = material;
  poly_overlap_workspace_d ws_d;
  poly_overlap_workspace_f ws_f;
  poly_overlap_workspace_create_d(&ws_d, max_vertices, max_triangles);
  poly_overlap_workspace_create_f(&ws_f, max_vertices, max_triangles);
  poly_gpu_settings settings;
  settings.precision = precision;
  settings.tangential = 1;
  settings.damping = 1;
  settings.rocking = 1;
  settings.dt = 1e-6;
  // The pair style's default; POLY_GPU_PARTING_SEARCH=0 in the environment turns it off (a check, or timings).
  const char *parting = getenv("POLY_GPU_PARTING_SEARCH");
  settings.parting_search = !(parting && strcmp(parting, "0") == 0);
  ws_d.want_second_moment = ws_f.want_second_moment = 1;  // the rocking damping, as the pair style's default

  int failures = 0;
  long handed_before = 0;
  double tolerance = precision == POLY_PRECISION_DOUBLE ? 1e-10 : 1e-4;
  for (int s = 0; s < num_shapes; s++) {
    size_t stem = strcspn(names[s], ".");
    if (*only && (strlen(only) != stem || strncmp(names[s], only, stem) != 0)) continue;
    int count = requested;
    if (gpu_only) {
      long scaled = (long)requested * 8 / shapes[s].num_triangles;
      count = (int)(scaled < 2000 ? 2000 : scaled > requested ? requested : scaled);
    }
    unsigned long long state = 12345 + s;
    std::vector<poly_gpu_particle> particles(2 * count);
    std::vector<poly_gpu_motion> motion(2 * count);
    std::vector<int> pair_i(count), pair_j(count);
    std::vector<double> history(POLY_HISTORY_SIZE * count);
    // Bed poses: half of them in contact; shallow ones: all in contact, shallowly.
    const bool posed = bed || shallow;
    int num_poses = posed ? 32768 / shapes[s].num_triangles : 0;
    num_poses = num_poses < 256 ? 256 : num_poses > 4096 ? 4096 : num_poses;
    std::vector<double> poses(posed ? 11 * num_poses : 0);
    poly_shape_view_d bed_view = poly_shape_view_of(&shapes[s]);
    for (int n = 0; posed && n < num_poses; n++)
      bed_pose(bed_view, shapes[s].volume, shapes[s].bounding_radius,
               shallow  ? pow(10.0, -6.0 + 2.0 * uniform(&state))
               : n % 2 ? 0.0
                        : pow(10.0, -3.0 + log10(30.0) * uniform(&state)),
               &state, &ws_d, &poses[11 * n], &poses[11 * n + 3], &poses[11 * n + 7]);
    for (int p = 0; p < count; p++) {
      poly_gpu_motion &a = motion[2 * p], &b = motion[2 * p + 1];
      double r = shapes[s].bounding_radius;
      for (int k = 0; k < 3; k++) {
        a.position[k] = 10.0 * uniform(&state);
        a.velocity[k] = uniform(&state) - 0.5;
        b.velocity[k] = uniform(&state) - 0.5;
        a.omega[k] = 20.0 * (uniform(&state) - 0.5);
        b.omega[k] = 20.0 * (uniform(&state) - 0.5);
      }
      if (posed) {
        const double *pose = &poses[11 * (p % num_poses)];
        for (int k = 0; k < 3; k++) b.position[k] = a.position[k] + pose[k];
        memcpy(a.quaternion, pose + 3, sizeof a.quaternion);
        memcpy(b.quaternion, pose + 7, sizeof b.quaternion);
      } else if (p % 8 == 7) {
        // Same orientation, B moved along A's body x axis: faces parallel to that axis are flush (for cubes,
        // four pairs of them), which the warp kernel hands to the one-thread kernel's smoothing.
        double distance = r * (0.8 + 0.9 * uniform(&state)), rotation[9];
        random_quaternion(&state, a.quaternion);
        memcpy(b.quaternion, a.quaternion, sizeof b.quaternion);
        poly_quat_to_matrix(a.quaternion, rotation);
        for (int k = 0; k < 3; k++) b.position[k] = a.position[k] + distance * rotation[3 * k];
      } else {
        double direction[4];
        random_quaternion(&state, direction);
        double distance = r * (0.8 + 0.9 * uniform(&state));
        for (int k = 0; k < 3; k++) b.position[k] = a.position[k] + distance * direction[k + 1];
        random_quaternion(&state, a.quaternion);
        random_quaternion(&state, b.quaternion);
      }
      for (int n = 2 * p; n <= 2 * p + 1; n++) {
        particles[n].shape = s - first_uploaded;
        particles[n].type = 1;
        particles[n].mass = 2500.0 * shapes[s].volume;
        particles[n].negligible_volume = 1e-12 * shapes[s].volume;
        particles[n].bounding_radius = shapes[s].bounding_radius;
      }
      pair_i[p] = 2 * p;
      pair_j[p] = 2 * p + 1;
      for (int d = 0; d < 3; d++) history[POLY_HISTORY_SIZE * p + d] = 1e-3 * (uniform(&state) - 0.5);
      history[POLY_HISTORY_SIZE * p + 3] = 1e4;
      history[POLY_HISTORY_SIZE * p + 4] = 1.0;
    }
    std::vector<double> host_history = history, gpu_history(history.size()), fast_history(history.size());
    std::vector<int> contact_flags(count);
    std::vector<poly_gpu_result> results(count);
    std::vector<double> sums(6 * 2 * count);
    int num_contacts = 0, fast_contacts = 0;
    // Per-pair path, history advanced; then the fast path from the same start: a
    // warm-up call (allocations) and a timed step.
    struct timespec start;
    double seconds = 0.0, kernel_seconds = 0.0;
    long kept = 0;
    bool ok = poly_gpu_set_pairs(2 * count, 2 * count, &particles[0], count, &pair_i[0], &pair_j[0], &history[0], 1,
                                 materials, message, sizeof message) == 0;
    if (ok) {
      memcpy(poly_gpu_motion_buffer(), &motion[0], sizeof(poly_gpu_motion) * motion.size());
      settings.advance_history = 1;
      ok = poly_gpu_compute(&settings, &results[0], &num_contacts, message, sizeof message) == 0 &&
           poly_gpu_get_history(&gpu_history[0], &contact_flags[0], message, sizeof message) == 0 &&
           poly_gpu_set_pairs(2 * count, 2 * count, &particles[0], count, &pair_i[0], &pair_j[0], &history[0], 1,
                              materials, message, sizeof message) == 0;
    }
    if (ok) {
      memcpy(poly_gpu_motion_buffer(), &motion[0], sizeof(poly_gpu_motion) * motion.size());
      settings.advance_history = 0;
      ok = poly_gpu_compute(&settings, NULL, &fast_contacts, message, sizeof message) == 0;
      settings.advance_history = 1;
      kernel_seconds = poly_gpu_timings().kernels;
      kept = poly_gpu_timings().kept;
      clock_gettime(CLOCK_MONOTONIC, &start);
      ok = ok && poly_gpu_compute(&settings, NULL, &fast_contacts, message, sizeof message) == 0;
      seconds = seconds_since(start);
      kernel_seconds = poly_gpu_timings().kernels - kernel_seconds;
      kept = poly_gpu_timings().kept - kept;
      if (ok) memcpy(&sums[0], poly_gpu_force_torque(), sizeof(double) * sums.size());
      ok = ok && poly_gpu_get_history(&fast_history[0], &contact_flags[0], message, sizeof message) == 0;
    }
    if (!ok) {
      printf("FAIL %s\n", message);
      return 1;
    }
    // The fast path: same contacts, same history, and each particle's sum is its one pair's share.
    int fast_mismatches = fast_contacts != num_contacts;
    for (int p = 0; p < count; p++) {
      const poly_gpu_result &r = results[p];
      for (int k = 0; k < 3; k++) {
        double expected[4] = {r.contact ? -r.force_j[k] : 0.0, r.contact ? r.torque_i[k] : 0.0,
                              r.contact ? r.force_j[k] : 0.0, r.contact ? r.torque_j[k] : 0.0};
        double got[4] = {sums[12 * p + k], sums[12 * p + 3 + k], sums[12 * p + 6 + k], sums[12 * p + 9 + k]};
        for (int c = 0; c < 4; c++) fast_mismatches += expected[c] != got[c];
      }
      for (int d = 0; d < POLY_HISTORY_SIZE; d++)
        fast_mismatches += fast_history[POLY_HISTORY_SIZE * p + d] != gpu_history[POLY_HISTORY_SIZE * p + d];
      fast_mismatches += contact_flags[p] != r.contact;
    }
    if (fast_mismatches) {
      printf("FAIL shape %s: per-particle sums, contacts or history of the fast path differ from the per-pair path "
             "in %d values\n", names[s], fast_mismatches);
      failures++;
    }

    if (bed) {
      printf("%-20s %s: %7d bed pairs (%d poses), %7d contacts, %7ld past the pre-filter; GPU %.3g pairs/s in the "
             "kernels, %.3g pairs/s for the step (poses up, forces down); %ld handed to the one-thread kernel in all "
             "calls\n", names[s], argv[3], count, num_poses, num_contacts, kept, count / kernel_seconds,
             count / seconds, poly_gpu_timings().handed_back);
      continue;
    }
    if (gpu_only) {
      printf("%-20s %s: %7d pairs, %7d contacts; GPU %.3g pairs/s (one step: poses up, forces down)\n", names[s],
             argv[3], count, num_contacts, count / seconds);
      continue;
    }
    poly_shape_view_d view_d = poly_shape_view_of(&shapes[s]);
    poly_shape_view_f view_f;
    poly_shape_view_make_f(&shapes[s], &view_f);
    double worst = 0.0;
    const char *worst_what = "-";
    int contacts = 0;
    std::vector<double> volume_differences;
    struct timespec host_start;
    clock_gettime(CLOCK_MONOTONIC, &host_start);
    for (int p = 0; p < count; p++) {
      const poly_gpu_motion &a = motion[2 * p], &b = motion[2 * p + 1];
      const poly_gpu_particle &body = particles[2 * p];
      poly_pose pose_i, pose_j;
      memcpy(pose_i.position, a.position, sizeof pose_i.position);
      memcpy(pose_i.quaternion, a.quaternion, sizeof pose_i.quaternion);
      memcpy(pose_j.position, b.position, sizeof pose_j.position);
      memcpy(pose_j.quaternion, b.quaternion, sizeof pose_j.quaternion);
      poly_overlap_result g;
      if (precision == POLY_PRECISION_SINGLE) poly_overlap_f(&view_f, &pose_i, &view_f, &pose_j, &ws_f, &g);
      else if (precision == POLY_PRECISION_MIXED) poly_overlap_m(&view_f, &pose_i, &view_f, &pose_j, &ws_f, &g);
      else poly_overlap_d(&view_d, &pose_i, &view_d, &pose_j, &ws_d, &g);
      double centroid[3], b_from_a[3];
      for (int k = 0; k < 3; k++) centroid[k] = g.centroid[k] - a.position[k], b_from_a[k] = b.position[k] - a.position[k];
      int contact = g.volume > body.negligible_volume && g.depth > 0.0 &&
                    poly_contact_centroid_within(centroid, b_from_a, body.bounding_radius, body.bounding_radius);
      double floor_volume = (precision == POLY_PRECISION_DOUBLE ? 1e-12 : 1e-6) * shapes[s].volume;
      if (contact != results[p].contact && (g.volume > floor_volume || results[p].volume > floor_volume)) {
        printf("FAIL shape %s pair %d: contact %d on the host, %d on the GPU\n", names[s], p, contact,
               results[p].contact);
        failures++;
        continue;
      }
      if (!contact || !results[p].contact) continue;
      contacts++;
      poly_contact_input in;
      const double depth = poly_contact_pair_depth(g.volume, g.depth, g.projected_area);  // the pair style's
      poly_contact_input_set_geometry(&in, g.volume, depth, g.normal, g.centroid);
      poly_contact_input_set_second_moment(&in, g.second_moment);
      poly_contact_input_set_bodies(&in, a.position, a.velocity, a.omega, body.mass, b.position, b.velocity, b.omega,
                                    body.mass, 1e-6);
      poly_contact_output out;
      poly_contact_evaluate(&in, &material, 1, 1, &host_history[POLY_HISTORY_SIZE * p], &out);
      const poly_gpu_result &r = results[p];
      double size = shapes[s].bounding_radius;
      double small = 1e-3 * shapes[s].volume;
      double volume_scale = g.volume > small ? g.volume : small;
      int substantial = g.volume > small;
      double force_scale = fabs(out.normal_force) + 1e-300;
      volume_differences.push_back(fabs(r.volume - g.volume) / g.volume);
      struct { const char *what; double host, gpu, scale; int check; } checks[] = {
          {"volume", g.volume, r.volume, volume_scale, 1}, {"depth", depth, r.depth, depth, substantial},
          {"centroid x", g.centroid[0], r.centroid[0], size, substantial},
          {"centroid y", g.centroid[1], r.centroid[1], size, substantial},
          {"centroid z", g.centroid[2], r.centroid[2], size, substantial}, {"normal x", g.normal[0], r.normal[0], 1.0, substantial},
          {"normal y", g.normal[1], r.normal[1], 1.0, substantial}, {"normal z", g.normal[2], r.normal[2], 1.0, substantial},
          {"force x", out.force_j[0], r.force_j[0], force_scale, substantial}, {"force y", out.force_j[1], r.force_j[1], force_scale, substantial},
          {"force z", out.force_j[2], r.force_j[2], force_scale, substantial},
          {"torque i x", out.torque_i[0], r.torque_i[0], force_scale * size, substantial},
          {"torque i y", out.torque_i[1], r.torque_i[1], force_scale * size, substantial},
          {"torque i z", out.torque_i[2], r.torque_i[2], force_scale * size, substantial},
          {"torque j x", out.torque_j[0], r.torque_j[0], force_scale * size, substantial},
          {"torque j y", out.torque_j[1], r.torque_j[1], force_scale * size, substantial},
          {"torque j z", out.torque_j[2], r.torque_j[2], force_scale * size, substantial},
          {"history x", host_history[POLY_HISTORY_SIZE * p], gpu_history[POLY_HISTORY_SIZE * p], force_scale, substantial},
      };
      for (size_t c = 0; c < sizeof checks / sizeof checks[0]; c++) {
        if (!checks[c].check) continue;
        double difference = fabs(checks[c].host - checks[c].gpu) / checks[c].scale;
        if (difference > worst) {
          worst = difference;
          worst_what = checks[c].what;
        }
      }
    }
    double host_seconds = seconds_since(host_start);
    long handed = poly_gpu_timings().handed_back;
    printf("%-20s %s: %5d pairs, %5d contacts, worst relative difference %.2e (%s); GPU %.3g pairs/s "
           "(one step: poses up, forces down), one CPU core %.3g pairs/s (same code, checks included); %ld pairs "
           "handed from the warp to the one-thread kernel over its 3 calls\n", names[s], argv[3], count, contacts, worst, worst_what,
           count / seconds, count / host_seconds, handed - handed_before);
    handed_before = handed;
    if (shallow && !volume_differences.empty()) {
      std::vector<double> &v = volume_differences;
      std::sort(v.begin(), v.end());
      printf("%-20s %s: shallow contacts (1e-6 to 1e-4 of the particle volume): relative difference of V median "
             "%.2e, worst %.2e\n", names[s], argv[3], v[v.size() / 2], v.back());
      const double median_limit = precision == POLY_PRECISION_DOUBLE ? 1e-10 : 1e-4,
                   worst_limit = precision == POLY_PRECISION_DOUBLE ? 1e-10
                                 : precision == POLY_PRECISION_SINGLE ? 9e-2
                                                                      : 3e-2;
      if (v[v.size() / 2] > median_limit || v.back() > worst_limit) {
        printf("FAIL shape %s: shallow contacts' V beyond its limits (median %.0e, worst %.0e)\n", names[s],
               median_limit, worst_limit);
        failures++;
      }
    }
    if (worst > tolerance) failures++;
    if (contacts < count / 4) {
      printf("FAIL too few contacts\n");
      failures++;
    }
    poly_shape_view_free_f(&view_f);
  }
  printf("device memory %.1f MiB; clipping warp kernel: %d pairs a warp, %ld bytes of shared memory a warp\n",
         poly_gpu_bytes() / 1048576.0, poly_gpu_timings().clip_warp_pairs, poly_gpu_timings().clip_warp_bytes);
  poly_gpu_clear();
  printf(failures ? "FAIL\n" : "OK\n");
  return failures ? 1 : 0;
}
