/* Which vertices of a shape can be its highest along a direction: a table over the directions (a cube map of
 * POLY_EXTREME_SIDE x POLY_EXTREME_SIDE cells a face), each cell listing in ascending order the vertices that can be
 * highest for some direction in it, so that the slab of the overlap (overlap_slab_extremes) takes the highest of a
 * few vertices instead of all: in a settled pile of rock_40 that scan was 7 % of the time.
 *
 * Why the list holds every vertex that can be highest: c the cell's unit centre, r >= |d - c| for every unit d in the
 * cell (the farthest point of a spherical quadrilateral from a point in it is a corner), R the largest |v|. For any
 * vertex v, |d.v - c.v| <= r R; so a vertex highest along d has c.v >= max c.w - 2 r R. The lists take every vertex
 * within that and a pad (1e-6 R) for the rounding of the dot products, of a direction not quite unit, and of the
 * vertices in single precision: every vertex whose computed place is the highest is in the list, and the first of
 * them in ascending order is the scan's. Header-only C, host and device (the device's views carry no table). */
#ifndef POLY_EXTREMES_H
#define POLY_EXTREMES_H

#include <math.h>

#define POLY_EXTREME_SIDE 16
#define POLY_EXTREME_CELLS (6 * POLY_EXTREME_SIDE * POLY_EXTREME_SIDE)
/* Shapes of at most this many vertices have no table: the scan costs what the look-up would. */
#define POLY_EXTREME_MIN_VERTICES 16
/* Tests only (tests/test_extreme_table.py): lists made for cells this many times as wide must miss vertices. */
#ifndef POLY_EXTREME_REACH_SCALE
#define POLY_EXTREME_REACH_SCALE 1.0
#endif

#include "poly_inline.h"

/* The cell of direction d (any length): the face of its largest component, then the other two components over it,
 * each in [-1, 1], in SIDE bins. -1 for a zero or not finite direction. */
POLY_INLINE int poly_extreme_cell(const double *d)
{
  const double ax = fabs(d[0]), ay = fabs(d[1]), az = fabs(d[2]);
  const int k = ax >= ay ? (ax >= az ? 0 : 2) : (ay >= az ? 1 : 2);
  const double largest = k == 0 ? ax : (k == 1 ? ay : az);
  if (!(largest > 0.0) || !(largest < INFINITY)) return -1;
  const double scale = 0.5 * POLY_EXTREME_SIDE / largest;
  int bin[2];
  for (int i = 0; i < 2; i++) {
    const double position = (d[(k + 1 + i) % 3] + largest) * scale;
    bin[i] = position >= POLY_EXTREME_SIDE - 1 ? POLY_EXTREME_SIDE - 1 : (position > 0.0 ? (int)position : 0);
  }
  const int face = 2 * k + (d[k] < 0.0);
  return (face * POLY_EXTREME_SIDE + bin[0]) * POLY_EXTREME_SIDE + bin[1];
}

/* The unit direction at (a, b) in [0, SIDE] of face `face`'s bins (the cube map of poly_extreme_cell). */
POLY_INLINE void poly_extreme_direction(int face, double a, double b, double *d)
{
  const int k = face / 2;
  d[k] = face % 2 ? -1.0 : 1.0;
  d[(k + 1) % 3] = 2.0 * a / POLY_EXTREME_SIDE - 1.0;
  d[(k + 2) % 3] = 2.0 * b / POLY_EXTREME_SIDE - 1.0;
  const double length = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int i = 0; i < 3; i++) d[i] /= length;
}

/* Fills the table of `num_vertices` vertices (3 each) of largest length `radius`: start[c] .. start[c + 1] index
 * `list` for cell c. With `list` NULL only counts; returns the entries (at most POLY_EXTREME_CELLS * num_vertices). */
POLY_INLINE int poly_extreme_table(const double *vertices, int num_vertices, double radius, int *start, int *list)
{
  int count = 0;
  for (int face = 0; face < 6; face++)
    for (int i = 0; i < POLY_EXTREME_SIDE; i++)
      for (int j = 0; j < POLY_EXTREME_SIDE; j++) {
        double centre[3], corner[3], reach = 0.0;
        poly_extreme_direction(face, i + 0.5, j + 0.5, centre);
        for (int q = 0; q < 4; q++) {
          poly_extreme_direction(face, i + (q & 1), j + (q >> 1), corner);
          const double gap = sqrt((corner[0] - centre[0]) * (corner[0] - centre[0]) +
                                  (corner[1] - centre[1]) * (corner[1] - centre[1]) +
                                  (corner[2] - centre[2]) * (corner[2] - centre[2]));
          reach = gap > reach ? gap : reach;
        }
        reach = 1.001 * reach + 1e-9;
        double highest = -INFINITY;
        for (int v = 0; v < num_vertices; v++) {
          const double *x = vertices + 3 * v;
          const double along = centre[0] * x[0] + centre[1] * x[1] + centre[2] * x[2];
          highest = along > highest ? along : highest;
        }
        const double threshold = highest - POLY_EXTREME_REACH_SCALE * (2.0 * reach * radius + 1e-6 * radius);
        const int cell = (face * POLY_EXTREME_SIDE + i) * POLY_EXTREME_SIDE + j;
        if (start) start[cell] = count;
        for (int v = 0; v < num_vertices; v++) {
          const double *x = vertices + 3 * v;
          if (!(centre[0] * x[0] + centre[1] * x[1] + centre[2] * x[2] >= threshold)) continue;
          if (list) list[count] = v;
          count++;
        }
      }
  if (start) start[POLY_EXTREME_CELLS] = count;
  return count;
}

#endif
