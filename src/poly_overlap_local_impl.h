/* The overlap in the local frame, from the passes of poly_overlap_impl.h:
 * the re-evaluation of inconsistent pairs and the smoothing of flush faces.
 * Included by poly_overlap_impl.h once per precision (no include guard). */
/* The overlap in the local frame (body frame of A shifted to ws->origin).
 * `rotation` (row-major) and `translation` take B's body frame to A's.
 *
 * Two things can make one evaluation not the answer:
 * - Inconsistent edges (crossings that disagree with the inside state of an
 *   edge's ends). The predicates are exact, so none should remain; if one does,
 *   the pair is evaluated again on the path without the half-space filter
 *   (whose slab is the only rounded decision) and result->recomputed says so.
 * - Flush faces (a face of A in the plane of a face of B, either way round).
 *   Volume and centroid are continuous there, but the area vector of A's
 *   surface inside B (eq. 4.19) is not: the strip of a flush face counts
 *   wholly or not at all, by the direction of the perturbation, and the two
 *   one-sided limits differ (two cubes meeting head on with their side faces
 *   flush: a normal tilted by 0.016 rad, spurious torques). Where a pass finds
 *   flush faces, area and area vector are the mean of two evaluations with B
 *   shifted by +h and -h along the perturbation direction, h a fixed length
 *   (smoothing_length) of the size: the mean of the two one-sided limits, to
 *   O(h), and a continuous function of the poses, so nearly flush faces (as
 *   rounding of rotated poses leaves them) give the same answer. Volume,
 *   centroid and nodes stay those of the unshifted evaluation. */
POLY_INLINE void POLY_FN(overlap_local)(const POLY_FN(shape_view) *a, const POLY_FN(shape_view) *b,
                                        const double *rotation, const double *translation,
                                        POLY_FN(overlap_workspace) *ws, double *local_centroid,
                                        double *local_normal, poly_overlap_result *result)
{
  result->volume = result->depth = result->area = result->projected_area = 0.0;
  result->num_nodes = result->num_inconsistent = 0;
  result->filtered_out = result->recomputed = result->smoothed = 0;
  result->separating = -1;
  result->gap = 0.0;
  for (int e = 0; e < 6; e++) result->second_moment[e] = 0.0;
  ws->num_points = 0;

  double smoothing = POLY_FN(smoothing_length)() * ((double)a->bounding_radius + (double)b->bounding_radius);
  double flush_tolerance = 4.0 * POLY_FN(smoothing_length)();
  R u[3];
  POLY_FN(perturbation)(u);
  POLY_FN(pass) main_pass, shifted;
  ACC area_normal[3] = {0, 0, 0}, area = 0;
  /* Stages, through one call site (the GPU inlines it once): 0 the pass;
   * 1 again without the filter; 2, 3 shifted by +h, -h; 4 the unshifted pass
   * again, when its nodes did not fit the workspace and the shifted passes
   * have overwritten what node_extent needs. */
  int stage = 0, use_filter = ws->use_filter;
  while (stage >= 0) {
    double moved[3];
    double shift = stage == 2 ? smoothing : (stage == 3 ? -smoothing : 0.0);
    for (int k = 0; k < 3; k++) moved[k] = translation[k] + shift * (double)u[k];
    int keep_points = stage < 2 || stage == 4;
#if POLY_OVERLAP_RECORDS
    ws->cache_pass = stage == 0 && use_filter;
#endif
    POLY_FN(overlap_pass)(a, b, rotation, moved, stage == 1 ? 0 : use_filter, stage < 2 ? flush_tolerance : 0.0,
                          keep_points, ws, keep_points ? &main_pass : &shifted);
    if (stage == 0 && main_pass.num_inconsistent > 0 && use_filter) {
      result->recomputed = 1;
      stage = 1;
      continue;
    }
    if (stage < 2) {
      if (!main_pass.flush || !((double)main_pass.acc.volume6 > 0.0)) break;
      result->smoothed = 1;
      stage = 2;
      continue;
    }
    if (stage == 2 || stage == 3) {
      area += (ACC)0.5 * shifted.acc.area;
      for (int k = 0; k < 3; k++) area_normal[k] += (ACC)0.5 * shifted.acc.area_normal[k];
      stage = stage == 2 ? 3 : (main_pass.num_points > ws->capacity_points ? 4 : -1);
      continue;
    }
    break;
  }
#if POLY_OVERLAP_RECORDS
  ws->cache_pass = 0;
  /* A pair evaluated again (inconsistent edges, flush faces) keeps no certificate. */
  if ((result->recomputed || result->smoothed) && ws->crossing_cache) ws->crossing_cache->margin = 0.0;
#endif
  if (result->smoothed) {
    main_pass.acc.area = area;
    for (int k = 0; k < 3; k++) main_pass.acc.area_normal[k] = area_normal[k];
  }
  POLY_FN(accumulator) acc = main_pass.acc;
  int num_points = main_pass.num_points;
  double origin[3] = {main_pass.origin[0], main_pass.origin[1], main_pass.origin[2]};
  double axis_d[3] = {main_pass.axis[0], main_pass.axis[1], main_pass.axis[2]};
  result->filtered_out = main_pass.filtered_out;
  result->separating = main_pass.separating;
  if (main_pass.filtered_out) {
    result->gap = main_pass.gap;
    return;
  }

  result->num_nodes = num_points;
  ws->num_points = num_points;
  result->num_inconsistent = main_pass.num_inconsistent;
  double volume = (double)acc.volume6 / 6.0;
  if (!(volume > 0.0)) return;
  result->volume = volume;
  for (int k = 0; k < 3; k++)
    local_centroid[k] = (double)acc.moment24[k] / (24.0 * volume) + (double)acc.reference[k] + origin[k];
  result->area = (double)acc.area;
  for (int e = 0; e < 6; e++) result->second_moment[e] = acc.second120[e] / 120.0;
  if (acc.want_second) {
    double from_reference[3];
    for (int k = 0; k < 3; k++) from_reference[k] = (double)acc.moment24[k] / (24.0 * volume);
    poly_second_moment_to_centroid(result->second_moment, volume, from_reference);
  }

  /* Normal (eq. 4.19). When A's surface inside B sums to nothing (one body
   * wholly inside the other), fall back to the centre line. */
  double normal[3] = {(double)acc.area_normal[0], (double)acc.area_normal[1], (double)acc.area_normal[2]};
  double length = sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  result->projected_area = length;
  if (length > 1e-9 * (double)acc.area && length > 0.0)
    for (int k = 0; k < 3; k++) local_normal[k] = normal[k] / length;
  else
    for (int k = 0; k < 3; k++) local_normal[k] = axis_d[k];

  /* Depth: extent of the intersection nodes along the normal. */
  double low = 1e300, high = -1e300;
  if (num_points <= ws->capacity_points) {
    for (int p = 0; p < num_points; p++) {
      const R *x = ws->points + 3 * p;
      double along = local_normal[0] * x[0] + local_normal[1] * x[1] + local_normal[2] * x[2];
      if (along < low) low = along;
      if (along > high) high = along;
    }
  } else {
    /* More nodes than the workspace holds (very rare: long edges crossing many
     * faces): find them again rather than guess. */
    const R *va = ws->vertices_a, *vb = ws->vertices_b;
    POLY_FN(node_extent)(a, va, ws->inside_a, 0, b, vb, ws->planes_b, ws->kept_list_b, main_pass.num_kept_b, local_normal, &low,
                         &high);
    POLY_FN(node_extent)(b, vb, ws->inside_b, 1, a, va, ws->planes_a, ws->kept_list_a, main_pass.num_kept_a, local_normal, &low,
                         &high);
  }
  result->depth = high > low ? high - low : 0.0;
}
