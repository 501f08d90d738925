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

#if defined(__CUDACC__)
#define POLY_INLINE static inline __host__ __device__
#else
#define POLY_INLINE static inline
#endif

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

/* Conjugate quaternion momentum p = 2 q (0, L_body) of NO_SQUISH, and back. */
POLY_INLINE void poly_angmom_to_conjugate(const double q[4], const double angmom[3], double p[4])
{
  double r[9], body[4];
  poly_quat_to_matrix(q, r);
  body[0] = 0.0;
  poly_matrix_apply_transpose(r, angmom, body + 1);
  poly_quat_multiply(q, body, p);
  p[0] *= 2.0; p[1] *= 2.0; p[2] *= 2.0; p[3] *= 2.0;
}

POLY_INLINE void poly_conjugate_to_angmom(const double q[4], const double p[4], double angmom[3])
{
  double conj[4] = {q[0], -q[1], -q[2], -q[3]}, body[4], r[9];
  poly_quat_multiply(conj, p, body);
  body[1] *= 0.5; body[2] *= 0.5; body[3] *= 0.5;
  poly_quat_to_matrix(q, r);
  poly_matrix_apply(r, body + 1, angmom);
}

/* P_k q: the quaternion of an infinitesimal body rotation about principal axis k. */
POLY_INLINE void poly_no_squish_permute(int axis, const double q[4], double out[4])
{
  if (axis == 1)      { out[0] = -q[1]; out[1] =  q[0]; out[2] =  q[3]; out[3] = -q[2]; }
  else if (axis == 2) { out[0] = -q[2]; out[1] = -q[3]; out[2] =  q[0]; out[3] =  q[1]; }
  else                { out[0] = -q[3]; out[1] =  q[2]; out[2] = -q[1]; out[3] =  q[0]; }
}

/* Exact free rotation about body axis `axis` (1..3) for time dt. */
POLY_INLINE void poly_no_squish_rotate(int axis, double p[4], double q[4],
                                       const double moments[3], double dt)
{
  double kq[4], kp[4];
  double moment = moments[axis - 1];
  if (!(moment > 0.0)) return;
  poly_no_squish_permute(axis, q, kq);
  poly_no_squish_permute(axis, p, kp);
  double phi = (p[0] * kq[0] + p[1] * kq[1] + p[2] * kq[2] + p[3] * kq[3]) / (4.0 * moment);
  double c = cos(dt * phi), s = sin(dt * phi);
  for (int i = 0; i < 4; i++) {
    double p_new = c * p[i] + s * kp[i];
    double q_new = c * q[i] + s * kq[i];
    p[i] = p_new;
    q[i] = q_new;
  }
}

/* Torque-free rotation of (q, L_world) over dt by the symmetric 3-2-1-2-3 splitting.
 * L_world is unchanged by a free rotation; only q moves. */
POLY_INLINE void poly_free_rotation(double q[4], const double moments[3],
                                    const double angmom[3], double dt)
{
  double p[4];
  poly_angmom_to_conjugate(q, angmom, p);
  poly_no_squish_rotate(3, p, q, moments, 0.5 * dt);
  poly_no_squish_rotate(2, p, q, moments, 0.5 * dt);
  poly_no_squish_rotate(1, p, q, moments, dt);
  poly_no_squish_rotate(2, p, q, moments, 0.5 * dt);
  poly_no_squish_rotate(3, p, q, moments, 0.5 * dt);
  /* |q| is preserved exactly in exact arithmetic; renormalising only removes round-off. */
  poly_quat_normalize(q);
}

#endif
