/* Rigid-body kinematics for polyhedral particles: quaternions, rotation
 * matrices and the NO_SQUISH free-rotor splitting (Miller et al., J. Chem.
 * Phys. 116, 8649 (2002)).
 *
 * NO_SQUISH advances the orientation by five exact rotations about the body
 * principal axes (3,2,1,2,3). Each sub-step is the exact flow of one term of
 * the kinetic energy, so the scheme is symplectic and time-reversible: energy
 * errors stay bounded instead of drifting, |q| stays 1 to round-off, and the
 * world angular momentum is conserved to round-off because every sub-flow is
 * invariant under world rotations.
 *
 * Quaternions are (w, i, j, k) and rotate body vectors into the world:
 * x_world = R(q) x_body. Header-only, plain C so nvcc can use it too.
 */
#ifndef POLY_RIGID_H
#define POLY_RIGID_H

#include <math.h>

#include "poly_inline.h"

/* The per-particle integrator kernels below are small and called once per particle
 * and step: POLY_HOT_INLINE, so that their loops run without call overhead or spills. */

POLY_INLINE void poly_quat_normalize(double q[4])
{
  double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  double inv = n > 0.0 ? 1.0 / n : 0.0;
  if (n == 0.0) { q[0] = 1.0; q[1] = q[2] = q[3] = 0.0; return; }
  q[0] *= inv; q[1] *= inv; q[2] *= inv; q[3] *= inv;
}

/* Row-major rotation matrix of a unit quaternion. */
POLY_INLINE void poly_quat_to_matrix(const double q[4], double r[9])
{
  double w = q[0], x = q[1], y = q[2], z = q[3];
  r[0] = 1.0 - 2.0 * (y * y + z * z); r[1] = 2.0 * (x * y - w * z);       r[2] = 2.0 * (x * z + w * y);
  r[3] = 2.0 * (x * y + w * z);       r[4] = 1.0 - 2.0 * (x * x + z * z); r[5] = 2.0 * (y * z - w * x);
  r[6] = 2.0 * (x * z - w * y);       r[7] = 2.0 * (y * z + w * x);       r[8] = 1.0 - 2.0 * (x * x + y * y);
}

/* Unit quaternion of a proper rotation matrix (row-major), Shepperd's branch choice. */
POLY_INLINE void poly_matrix_to_quat(const double r[9], double q[4])
{
  double trace = r[0] + r[4] + r[8];
  if (trace > r[0] && trace > r[4] && trace > r[8]) {
    double s = 2.0 * sqrt(1.0 + trace);
    q[0] = 0.25 * s; q[1] = (r[7] - r[5]) / s; q[2] = (r[2] - r[6]) / s; q[3] = (r[3] - r[1]) / s;
  } else if (r[0] >= r[4] && r[0] >= r[8]) {
    double s = 2.0 * sqrt(1.0 + r[0] - r[4] - r[8]);
    q[0] = (r[7] - r[5]) / s; q[1] = 0.25 * s; q[2] = (r[1] + r[3]) / s; q[3] = (r[2] + r[6]) / s;
  } else if (r[4] >= r[8]) {
    double s = 2.0 * sqrt(1.0 + r[4] - r[0] - r[8]);
    q[0] = (r[2] - r[6]) / s; q[1] = (r[1] + r[3]) / s; q[2] = 0.25 * s; q[3] = (r[5] + r[7]) / s;
  } else {
    double s = 2.0 * sqrt(1.0 + r[8] - r[0] - r[4]);
    q[0] = (r[3] - r[1]) / s; q[1] = (r[2] + r[6]) / s; q[2] = (r[5] + r[7]) / s; q[3] = 0.25 * s;
  }
  if (q[0] < 0.0) { q[0] = -q[0]; q[1] = -q[1]; q[2] = -q[2]; q[3] = -q[3]; }
  poly_quat_normalize(q);
}

/* a * b (Hamilton product). */
POLY_INLINE void poly_quat_multiply(const double a[4], const double b[4], double out[4])
{
  double w = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
  double x = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
  double y = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
  double z = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
  out[0] = w; out[1] = x; out[2] = y; out[3] = z;
}

POLY_INLINE void poly_cross3_d(const double a[3], const double b[3], double out[3])
{
  double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
  out[0] = x; out[1] = y; out[2] = z;
}

/* Second moments of volume, as 6 numbers (xx, yy, zz, xy, xz, yz). The
 * tetrahedron (0, a, b, c) of signed volume V = v6/6 has
 * int x x^T dV = V/20 (a a^T + b b^T + c c^T + s s^T), s = a + b + c:
 * this adds v6 times the bracket (divide the sum by 120). */
/* Inlined by order: GCC kept it a call from add_segment, 5 % of a settled pile's time (the replays' sums). */
POLY_HOT_INLINE void poly_second_moment_add(double m[6], double v6, const double a[3], const double b[3], const double c[3])
{
  double s[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
  /* Written out: the contact loop adds one per boundary segment, and the indexed loop did not unroll. */
#define POLY_SECOND_TERM(i, j) (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j])
  m[0] += v6 * POLY_SECOND_TERM(0, 0);
  m[1] += v6 * POLY_SECOND_TERM(1, 1);
  m[2] += v6 * POLY_SECOND_TERM(2, 2);
  m[3] += v6 * POLY_SECOND_TERM(0, 1);
  m[4] += v6 * POLY_SECOND_TERM(0, 2);
  m[5] += v6 * POLY_SECOND_TERM(1, 2);
#undef POLY_SECOND_TERM
}

/* m about the origin -> about the centroid c of the volume V (parallel axes). */
POLY_INLINE void poly_second_moment_to_centroid(double m[6], double volume, const double c[3])
{
  const int row[6] = {0, 1, 2, 0, 0, 1}, column[6] = {0, 1, 2, 1, 2, 2};
  for (int e = 0; e < 6; e++) m[e] -= volume * c[row[e]] * c[column[e]];
}

/* R m R^T for a rotation R (row-major). */
POLY_INLINE void poly_second_moment_rotate(const double r[9], const double m[6], double out[6])
{
  double full[9] = {m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2]}, rm[9];
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) rm[3 * i + j] = r[3 * i] * full[j] + r[3 * i + 1] * full[3 + j] + r[3 * i + 2] * full[6 + j];
  const int row[6] = {0, 1, 2, 0, 0, 1}, column[6] = {0, 1, 2, 1, 2, 2};
  for (int e = 0; e < 6; e++) {
    int i = row[e], j = column[e];
    out[e] = rm[3 * i] * r[3 * j] + rm[3 * i + 1] * r[3 * j + 1] + rm[3 * i + 2] * r[3 * j + 2];
  }
}

POLY_INLINE void poly_matrix_apply(const double r[9], const double v[3], double out[3])
{
  double x = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
  double y = r[3] * v[0] + r[4] * v[1] + r[5] * v[2];
  double z = r[6] * v[0] + r[7] * v[1] + r[8] * v[2];
  out[0] = x; out[1] = y; out[2] = z;
}

POLY_INLINE void poly_matrix_apply_transpose(const double r[9], const double v[3], double out[3])
{
  double x = r[0] * v[0] + r[3] * v[1] + r[6] * v[2];
  double y = r[1] * v[0] + r[4] * v[1] + r[7] * v[2];
  double z = r[2] * v[0] + r[5] * v[1] + r[8] * v[2];
  out[0] = x; out[1] = y; out[2] = z;
}

/* World angular velocity from world angular momentum and body principal moments.
 * A zero moment (a point mass) gets zero angular velocity about that axis. */
POLY_INLINE void poly_angmom_to_omega(const double q[4], const double moments[3],
                                      const double angmom[3], double omega[3])
{
  double r[9], body[3];
  poly_quat_to_matrix(q, r);
  poly_matrix_apply_transpose(r, angmom, body);
  for (int k = 0; k < 3; k++) body[k] = moments[k] > 0.0 ? body[k] / moments[k] : 0.0;
  poly_matrix_apply(r, body, omega);
}

/* World angular momentum from world angular velocity. */
POLY_INLINE void poly_omega_to_angmom(const double q[4], const double moments[3],
                                      const double omega[3], double angmom[3])
{
  double r[9], body[3];
  poly_quat_to_matrix(q, r);
  poly_matrix_apply_transpose(r, omega, body);
  for (int k = 0; k < 3; k++) body[k] *= moments[k];
  poly_matrix_apply(r, body, angmom);
}

/* Rotational kinetic energy 1/2 sum L_k^2 / I_k in the body frame. */
POLY_INLINE double poly_rotational_energy(const double q[4], const double moments[3],
                                          const double angmom[3])
{
  double r[9], body[3], energy = 0.0;
  poly_quat_to_matrix(q, r);
  poly_matrix_apply_transpose(r, angmom, body);
  for (int k = 0; k < 3; k++)
    if (moments[k] > 0.0) energy += 0.5 * body[k] * body[k] / moments[k];
  return energy;
}

/* sin a and cos a for |a| <= 1/8 by their Taylor polynomials through a^11 and a^10: the
 * first omitted terms, a^13/13! and a^12/12!, are below 3e-20 relative, far under
 * round-off, so the results agree with libm's to about an ulp, without its call and range
 * reduction (and the loops that call this vectorise). */
POLY_HOT_INLINE void poly_sincos_small(double a, double *s, double *c)
{
  double a2 = a * a;
  *s = a + a * a2 * (-1.0 / 6.0 + a2 * (1.0 / 120.0 + a2 * (-1.0 / 5040.0 + a2 * (1.0 / 362880.0 +
                     a2 * (-1.0 / 39916800.0)))));
  *c = 1.0 + a2 * (-0.5 + a2 * (1.0 / 24.0 + a2 * (-1.0 / 720.0 + a2 * (1.0 / 40320.0 +
                   a2 * (-1.0 / 3628800.0)))));
}

/* sin a and cos a: poly_sincos_small where it applies (every NO_SQUISH sub-rotation of a
 * DEM time step: the angle is half the rotation of the particle about one axis in that
 * (half) step), libm beyond. */
POLY_HOT_INLINE void poly_sincos(double a, double *s, double *c)
{
  if (fabs(a) <= 0.125) {
    poly_sincos_small(a, s, c);
  } else {
    *s = sin(a);
    *c = cos(a);
  }
}

/* poly_angmom_to_omega, with one division per moment and everything in registers
 * (scalars, not arrays: a vector reload of freshly stored scalars stalls). */
POLY_HOT_INLINE void poly_angmom_to_omega_fast(const double q[4], const double moments[3],
                                               double l0, double l1, double l2, double omega[3])
{
  double r[9];
  poly_quat_to_matrix(q, r);
  double i0 = moments[0] > 0.0 ? 1.0 / moments[0] : 0.0;
  double i1 = moments[1] > 0.0 ? 1.0 / moments[1] : 0.0;
  double i2 = moments[2] > 0.0 ? 1.0 / moments[2] : 0.0;
  double b0 = (r[0] * l0 + r[3] * l1 + r[6] * l2) * i0;
  double b1 = (r[1] * l0 + r[4] * l1 + r[7] * l2) * i1;
  double b2 = (r[2] * l0 + r[5] * l1 + r[8] * l2) * i2;
  omega[0] = r[0] * b0 + r[1] * b1 + r[2] * b2;
  omega[1] = r[3] * b0 + r[4] * b1 + r[5] * b2;
  omega[2] = r[6] * b0 + r[7] * b1 + r[8] * b2;
}

/* NO_SQUISH (Miller et al. 2002) for many particles at once (fix nve/polyhedron): the
 * symmetric 3-2-1-2-3 splitting of the free rotation. The sub-rotation about body axis k
 * over h is the exact flow of L_k^2 / 2 I_k: q -> q (cos x, sin x e_k) with x = h L_k / 2 I_k
 * (NO_SQUISH's c q + s P_k q with P_k q = q e_k and conjugate momentum p = 2 q (0, L_body)),
 * while the body angular momentum turns by -2x about axis k (the world L stays put).
 * Tracking L_body instead of p is the same map with shorter dependency chains; and a block
 * of particles is advanced side by side, in structure-of-arrays form, so that their
 * independent chains overlap and the compiler can vectorise them. */
#define POLY_ROTATION_BLOCK 8

/* One sub-rotation about body axis `axis` (1..3) over h for a whole block. */
POLY_HOT_INLINE void poly_no_squish_block_axis(int axis, double q[4][POLY_ROTATION_BLOCK],
                                               double body[3][POLY_ROTATION_BLOCK],
                                               const double inverse_moments[3][POLY_ROTATION_BLOCK],
                                               double h)
{
  enum { B = POLY_ROTATION_BLOCK };
  const int a = axis - 1, i = axis % 3, j = (axis + 1) % 3;  /* (a, i, j) cyclic */
  double x[B], s[B], c[B];
  int large = 0;
  for (int n = 0; n < B; n++) x[n] = 0.5 * h * (body[a][n] * inverse_moments[a][n]);
  for (int n = 0; n < B; n++) large |= !(fabs(x[n]) <= 0.125);
  if (large) {
    for (int n = 0; n < B; n++) poly_sincos(x[n], &s[n], &c[n]);
  } else {
    for (int n = 0; n < B; n++) poly_sincos_small(x[n], &s[n], &c[n]);
  }
  for (int n = 0; n < B; n++) {
    double w = q[0][n], qx = q[1][n], qy = q[2][n], qz = q[3][n], k0, k1, k2, k3;
    /* P_k q = q e_k */
    if (axis == 1)      { k0 = -qx; k1 =  w;  k2 =  qz; k3 = -qy; }
    else if (axis == 2) { k0 = -qy; k1 = -qz; k2 =  w;  k3 =  qx; }
    else                { k0 = -qz; k1 =  qy; k2 = -qx; k3 =  w;  }
    q[0][n] = c[n] * w + s[n] * k0;
    q[1][n] = c[n] * qx + s[n] * k1;
    q[2][n] = c[n] * qy + s[n] * k2;
    q[3][n] = c[n] * qz + s[n] * k3;
    /* the body frame turns by 2x: L_body turns by -2x */
    double c2 = 1.0 - 2.0 * s[n] * s[n], s2 = 2.0 * s[n] * c[n];
    double li = body[i][n], lj = body[j][n];
    body[i][n] = c2 * li + s2 * lj;
    body[j][n] = c2 * lj - s2 * li;
  }
}

/* Loads count (1..POLY_ROTATION_BLOCK) particles into a block: orientations, world angular
 * momenta and inverse moments (0 for a zero moment). Unused lanes repeat the last
 * particle (and are not stored back). */
POLY_HOT_INLINE void poly_block_load(int count, const double *const quaternion[], const double *const moments[],
                                     const double *const angmom[], double q[4][POLY_ROTATION_BLOCK],
                                     double world[3][POLY_ROTATION_BLOCK],
                                     double inverse[3][POLY_ROTATION_BLOCK])
{
  for (int n = 0; n < POLY_ROTATION_BLOCK; n++) {
    int m = n < count ? n : count - 1;
    const double *qm = quaternion[m], *lm = angmom[m], *im = moments[m];
    q[0][n] = qm[0]; q[1][n] = qm[1]; q[2][n] = qm[2]; q[3][n] = qm[3];
    world[0][n] = lm[0]; world[1][n] = lm[1]; world[2][n] = lm[2];
    for (int k = 0; k < 3; k++) inverse[k][n] = im[k] > 0.0 ? 1.0 / im[k] : 0.0;
  }
}

/* Per lane: body = R(q)^T world. */
POLY_HOT_INLINE void poly_block_to_body(const double q[4][POLY_ROTATION_BLOCK],
                                        const double world[3][POLY_ROTATION_BLOCK],
                                        double body[3][POLY_ROTATION_BLOCK])
{
  for (int n = 0; n < POLY_ROTATION_BLOCK; n++) {
    double qn[4] = {q[0][n], q[1][n], q[2][n], q[3][n]}, r[9];
    poly_quat_to_matrix(qn, r);
    double v0 = world[0][n], v1 = world[1][n], v2 = world[2][n];
    body[0][n] = r[0] * v0 + r[3] * v1 + r[6] * v2;
    body[1][n] = r[1] * v0 + r[4] * v1 + r[7] * v2;
    body[2][n] = r[2] * v0 + r[5] * v1 + r[8] * v2;
  }
}

/* Per lane: world = R(q) (body * inverse): the world angular velocity of a body angular
 * momentum. */
POLY_HOT_INLINE void poly_block_to_omega(const double q[4][POLY_ROTATION_BLOCK],
                                         const double body[3][POLY_ROTATION_BLOCK],
                                         const double inverse[3][POLY_ROTATION_BLOCK],
                                         double world[3][POLY_ROTATION_BLOCK])
{
  for (int n = 0; n < POLY_ROTATION_BLOCK; n++) {
    double qn[4] = {q[0][n], q[1][n], q[2][n], q[3][n]}, r[9];
    poly_quat_to_matrix(qn, r);
    double v0 = body[0][n] * inverse[0][n], v1 = body[1][n] * inverse[1][n], v2 = body[2][n] * inverse[2][n];
    world[0][n] = r[0] * v0 + r[1] * v1 + r[2] * v2;
    world[1][n] = r[3] * v0 + r[4] * v1 + r[5] * v2;
    world[2][n] = r[6] * v0 + r[7] * v1 + r[8] * v2;
  }
}

/* The NO_SQUISH free rotation followed by poly_angmom_to_omega at the new orientation, for count
 * (1..POLY_ROTATION_BLOCK) particles: quaternion[n], moments[n] (body principal moments),
 * angmom[n] (world) and omega[n] (world, written) point at particle n's data. */
POLY_HOT_INLINE void poly_free_rotation_block(int count, double *const quaternion[], const double *const moments[],
                                              const double *const angmom[], double *const omega[], double dt)
{
  enum { B = POLY_ROTATION_BLOCK };
  double q[4][B], body[3][B], inverse[3][B], world[3][B], norm[B];
  poly_block_load(count, (const double *const *) quaternion, moments, angmom, q, world, inverse);
  poly_block_to_body(q, world, body);
  poly_no_squish_block_axis(3, q, body, inverse, 0.5 * dt);
  poly_no_squish_block_axis(2, q, body, inverse, 0.5 * dt);
  poly_no_squish_block_axis(1, q, body, inverse, dt);
  poly_no_squish_block_axis(2, q, body, inverse, 0.5 * dt);
  poly_no_squish_block_axis(3, q, body, inverse, 0.5 * dt);
  for (int n = 0; n < B; n++) {  /* poly_quat_normalize */
    norm[n] = sqrt(q[0][n] * q[0][n] + q[1][n] * q[1][n] + q[2][n] * q[2][n] + q[3][n] * q[3][n]);
    double scale = 1.0 / norm[n];
    q[0][n] *= scale; q[1][n] *= scale; q[2][n] *= scale; q[3][n] *= scale;
  }
  for (int n = 0; n < B; n++)
    if (norm[n] == 0.0) { q[0][n] = 1.0; q[1][n] = q[2][n] = q[3][n] = 0.0; }
  poly_block_to_omega(q, body, inverse, world);
  for (int n = 0; n < count; n++) {
    for (int k = 0; k < 4; k++) quaternion[n][k] = q[k][n];
    for (int k = 0; k < 3; k++) omega[n][k] = world[k][n];
  }
}

#endif
