/* A hash of every bit of every field of poly_overlap_result (FNV-1a over the fields' bits): equal hashes over the
 * same poses say that two builds give the same results to the bit (tools/bench_pile_pairs.c,
 * tests/unit/clip_sides_bits.c). Include after poly_overlap.h. */
#ifndef RESULT_HASH_H
#define RESULT_HASH_H

#include <string.h>

#define RESULT_HASH_START 1469598103934665603ULL

static inline unsigned long long result_hash_add(unsigned long long hash, const poly_overlap_result *r)
{
  double fields[18] = {r->volume, r->depth, r->area, r->projected_area, r->centroid[0], r->centroid[1],
                       r->centroid[2], r->normal[0], r->normal[1], r->normal[2], r->second_moment[0],
                       r->second_moment[1], r->second_moment[2], r->second_moment[3], r->second_moment[4],
                       r->second_moment[5], (double)r->separating, (double)r->num_nodes};
  unsigned long long bits[18];
  memcpy(bits, fields, sizeof bits);
  for (int k = 0; k < 18; k++) hash = (hash ^ bits[k]) * 1099511628211ULL;
  return hash;
}

#endif
