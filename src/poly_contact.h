/* Volumetric Hertz-Mindlin-Deresiewicz contact law (document 000, sec. 4.2).
 *
 * For two bodies whose overlap has volume V, depth delta (extent along the
 * normal; for particle pairs at most 3 V / A, poly_contact_pair_depth), normal n (from body i to body j) and
 * centroid c:
 *   normal:      F_n = 4/(3 sqrt(pi)) E* sqrt(V delta) - gamma_n (u . n)     (4.16)
 *                k_n = 2 E* sqrt(V / (pi delta))                             (4.17)
 *   tangential:  k_t = 8 G* sqrt(V / (pi delta))                             (4.18)
 *                F_te += -k_t u_t dt, rescaled by k_t/k_t_old when unloading (4.8, 4.9)
 *                F_t = F_te - gamma_t u_t, limited to mu F_n                 (4.12, 4.13)
 * with u the velocity of j relative to i at c and u_t its tangential part.
 * For a sphere pair V ~ pi delta^2 R, so sqrt(V/(pi delta)) = sqrt(R delta)
 * and the law is LIGGGHTS' `model hertz`: the same E* and G* (G* as LIGGGHTS
 * defines it), and damping from the restitution coefficient e as LIGGGHTS does,
 *   gamma = 2 sqrt(5/6) |beta| sqrt(S m*),  beta = ln e / sqrt(ln^2 e + pi^2),
 * with S = k_n for the normal and S = k_t for the tangential direction, and
 * beta as below.
 * The force acts at the overlap centroid, so both bodies feel torques.
 * No attractive normal force from the law itself: F_n is clamped at zero (cohesion, when the material has
 * it, is a separate attraction k A, below). LIGGGHTS' beta(e) is
 * exact only when the force may turn attractive at the end of the contact
 * (with the clamp it gives e = 0.55 for a requested 0.5), so beta is instead
 * chosen such that the clamped Hertz contact rebounds with exactly the
 * requested e (poly_damping_beta_for_restitution). With e = 1 (no damping)
 * the normal law is LIGGGHTS' Hertz force for spheres. The tangential spring
 * follows document 000 (eqs. 4.8, 4.9: stiffness rescaling on unloading only),
 * not LIGGGHTS' `tangential history`, which rescales on loading too.
 *
 * Rocking damping (on when the caller gives the overlap's second moment Q
 * about c; zero Q: off). The damping above acts on u_n at c only, so a block
 * rocking on an edge or a face, whose overlap turns about c, is barely damped.
 * Spread over the overlap as dashpots per unit volume, the same damping is the
 * traction -(gamma_n/V) v_n(x) n with v_n(x) = u_n + n.(w x (x - c)),
 * w = omega_j - omega_i. Its resultant is exactly -gamma_n u_n n (the integral
 * of x - c vanishes), and it adds the couple on j
 *   T_r = -(gamma_n/V) [n]x Q [n]x^T w = -(gamma_n/V) (tr(Q_t) P - Q_t) w,
 * P = I - n n^T, Q_t = P Q P; the tangential dashpots give likewise, for the
 * twist about n (with `tangential history`),
 *   T_s = -(gamma_t/V) tr(Q_t) (w.n) n.
 * No implied pressure may pull, and no twist exceed friction: |T_r| is capped
 * at F_n sqrt(tr(Q_t)/V) and |T_s| at mu F_n (2/3) sqrt(2 tr(Q_t)/V) (a disc's
 * friction couple). T_r, normal to n, is applied as what it is, a shift of the
 * centre of pressure: the whole contact force acts at c + s, s = n x T_r / F_n
 * (|s| <= the overlap's radius of gyration), so a wall's stress module, which
 * takes forces at points, sees it too. T_s is a pure couple, applied only where
 * the caller allows one (`couples`: pairs and primitive walls, not meshes).
 * Translation and equal spins (w = 0), which is every sphere test against
 * LIGGGHTS, give no shift and no couple.
 *
 * Header-only C for the CPU style and the CUDA kernels alike.
 */
#ifndef POLY_CONTACT_H
#define POLY_CONTACT_H

#include <math.h>

#include "poly_rigid.h"

#define POLY_PI 3.14159265358979323846

/* Per-contact history, stored from the point of view of body i: the elastic
 * tangential force on j (which flips sign when the pair is seen from j), the
 * tangential stiffness and normal force of the previous step. */
enum { POLY_HISTORY_SIZE = 5 };

typedef struct poly_material_pair {
  double youngs_effective;   /* E*: 1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j */
  double shear_effective;    /* G*: 1/G* = 2(2-nu_i)(1+nu_i)/E_i + 2(2-nu_j)(1+nu_j)/E_j */
  double damping_beta;       /* poly_damping_beta_for_restitution(e) */
  double friction;           /* mu */
  double cohesion;           /* k, LIGGGHTS' cohesionEnergyDensity (J/m^3): attraction k A (0: none) */
} poly_material_pair;

typedef struct poly_contact_input {
  double volume, depth;
  double contact_area;       /* A: the overlap's cross-section normal to n (its projected area), for cohesion */
  double normal[3];          /* unit, from i to j */
  double centroid[3];
  double second_moment[6];   /* of the overlap about c (xx yy zz xy xz yz); zero: no rocking damping */
  int couples;               /* 1: the twist couple may be applied (0: a mesh wall, whose stress takes forces only) */
  double position_i[3], position_j[3];
  double velocity_i[3], velocity_j[3];
  double omega_i[3], omega_j[3];
  double mass_i, mass_j;     /* a wall has mass_j = 0 meaning infinite */
  double dt;
} poly_contact_input;

typedef struct poly_contact_output {
  double force_j[3];         /* on j; i gets the opposite */
  double torque_i[3], torque_j[3];
  double normal_force;       /* >= 0: the repulsive part */
  double cohesive_force;     /* >= 0: the attraction k A, along -n on j */
  double tangential_force[3];/* on j */
  double normal_stiffness, tangential_stiffness;
  double pressure_shift[3];  /* the force acts at centroid + pressure_shift (rocking damping) */
} poly_contact_output;

/* Whether an overlap's centroid (relative to particle i's centre; j's centre at j_from_i) lies within both
 * particles' bounding spheres (radii radius_i, radius_j; 1e-6 of them to spare). The centroid of an overlap lies
 * inside both particles, so one that does not is rounding: a sliver thinner than the precision resolves, whose
 * moment over its volume came out anywhere (in a settled bed in single precision far outside the particles, a lever
 * that spun particles up: tests/test_single_precision.py). Such an overlap is no contact. */
POLY_INLINE int poly_contact_centroid_within(const double *centroid, const double *j_from_i, double radius_i,
                                             double radius_j)
{
  double from_i = 0.0, from_j = 0.0;
  for (int k = 0; k < 3; k++) {
    from_i += centroid[k] * centroid[k];
    from_j += (centroid[k] - j_from_i[k]) * (centroid[k] - j_from_i[k]);
  }
  const double reach_i = (1.0 + 1e-6) * radius_i, reach_j = (1.0 + 1e-6) * radius_j;
  return from_i <= reach_i * reach_i && from_j <= reach_j * reach_j;
}

/* The depth the law takes for a particle pair: the overlap's extent along the normal (document 000, sec. 4.2),
 * at most 3 V / A, A_vec the area vector of the first body's surface S inside the second, A its length
 * (projected_area), n = A_vec / A. A convex overlap K always has V >= A delta / 3: for p in K let
 * f(p) = 1/3 int_S (x - p).n dS, the volume of the cones from p over S, each non-negative as K is convex, and
 * together at most V; f is affine in p with gradient -A_vec / 3, so V >= f(p_low) - f(p_high) = A delta / 3 for the
 * extreme points of K along n. Equality is a vertex pressed into a face; a lens has 3 V / A = 1.5 delta, a face on
 * a face 3 delta. So every one-spot contact of convex bodies keeps its extent (the cap 1e-6 above 3 V / A, which
 * rounding leaves it). One contact per pair means that a pair of non-convex particles touching at several spots
 * has the spots' spread along the normal as its extent, a particle size for spots of microns, and a normal force
 * that grows with sqrt(V delta) by orders of magnitude; capped, such a contact's depth is of the order of its
 * spots' own where their normals are within about 90 degrees of each other (two face spots of depth d whose
 * normals are theta apart: 3 d / cos(theta / 2)). Spots facing apart cancel in A_vec, and a particle wedged across
 * a slot (theta = 180 degrees) keeps the spread. */
POLY_INLINE double poly_contact_pair_depth(double volume, double depth, double projected_area)
{
  if (!(projected_area > 0.0)) return depth;
  const double cap = (1.0 + 1e-6) * 3.0 * volume / projected_area;
  return depth < cap ? depth : cap;
}

/* Whether a particle pair's law depth (poly_contact_pair_depth) is many times its overlap's mean depth 3 V / S, S the
 * area of the first body's surface inside the second: spots whose normals face apart (a particle wedged across a
 * slot of one that is not convex), whose area vectors cancel, so that the cap leaves the spots' spread as the depth
 * and the force far above the spots' own, along what is left of A_vec. The cap makes the ratio at most S / A for
 * every contact: about 1 for a face on a face (where the extent makes it a third), at most sqrt 3 for a cube's
 * corner, over 30 for one spot only for a tip whose faces lie within 2 degrees of the normal (or a plate pushed
 * edge-on deeper than about 45 times its thickness); for two spots whose normals are theta apart 1 / cos(theta / 2),
 * 30 at 176 degrees. Such a contact is not one the method represents, and the pair styles say so. */
#define POLY_CONTACT_SPOTS_APART 30.0
POLY_INLINE int poly_contact_spots_facing_apart(double volume, double law_depth, double area)
{
  return area > 0.0 && law_depth * area > POLY_CONTACT_SPOTS_APART * 3.0 * volume;
}

/* The two bodies of a contact input: positions, velocities, angular
 * velocities, masses (mass_j = 0: a wall) and the time step. */
POLY_INLINE void poly_contact_input_set_geometry(poly_contact_input *in, double volume, double depth,
                                                 const double *normal, const double *centroid)
{
  in->volume = volume;
  in->depth = depth;
  in->contact_area = 0.0;
  for (int k = 0; k < 3; k++) {
    in->normal[k] = normal[k];
    in->centroid[k] = centroid[k];
  }
  for (int e = 0; e < 6; e++) in->second_moment[e] = 0.0;
  in->couples = 1;
}

/* The overlap's second moment about its centroid, for the rocking damping. */
POLY_INLINE void poly_contact_input_set_second_moment(poly_contact_input *in, const double *second_moment)
{
  for (int e = 0; e < 6; e++) in->second_moment[e] = second_moment[e];
}

/* The rocking couple T_r on j as the shift of the centre of pressure, and the
 * twist couple T_s on j (see the header), from the damping coefficients of the
 * normal and tangential directions. */
POLY_INLINE void poly_rocking_damping(const poly_contact_input *in, double gamma_n, double gamma_t, double normal_force,
                                      double friction, double shift[3], double twist_j[3])
{
  const double *n = in->normal, *m = in->second_moment;
  for (int k = 0; k < 3; k++) shift[k] = twist_j[k] = 0.0;
  if (!(in->volume > 0.0) || !(normal_force > 0.0)) return;
  double q[9] = {m[0], m[3], m[4], m[3], m[1], m[5], m[4], m[5], m[2]};
  double qn[3], w[3];
  for (int k = 0; k < 3; k++) {
    qn[k] = q[3 * k] * n[0] + q[3 * k + 1] * n[1] + q[3 * k + 2] * n[2];
    w[k] = in->omega_j[k] - in->omega_i[k];
  }
  double trace_t = m[0] + m[1] + m[2] - (n[0] * qn[0] + n[1] * qn[1] + n[2] * qn[2]);
  if (!(trace_t > 0.0)) return;
  /* [n]x Q [n]x^T w = n x (Q (w x n)), with [n]x^T w = w x n. */
  double wxn[3], qwxn[3], rocking[3];
  poly_cross3_d(w, n, wxn);
  for (int k = 0; k < 3; k++) qwxn[k] = q[3 * k] * wxn[0] + q[3 * k + 1] * wxn[1] + q[3 * k + 2] * wxn[2];
  poly_cross3_d(n, qwxn, rocking);
  double scale = -gamma_n / in->volume, size = 0.0;
  for (int k = 0; k < 3; k++) {
    rocking[k] *= scale;
    size += rocking[k] * rocking[k];
  }
  size = sqrt(size);
  double limit = normal_force * sqrt(trace_t / in->volume);
  double keep = size > limit ? limit / size : 1.0;
  double n_x_rocking[3];
  poly_cross3_d(n, rocking, n_x_rocking);
  for (int k = 0; k < 3; k++) shift[k] = keep * n_x_rocking[k] / normal_force;
  double spin = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
  double twist = -gamma_t / in->volume * trace_t * spin;
  double twist_limit = friction * normal_force * (2.0 / 3.0) * sqrt(2.0 * trace_t / in->volume);
  if (twist > twist_limit) twist = twist_limit;
  if (twist < -twist_limit) twist = -twist_limit;
  for (int k = 0; k < 3; k++) twist_j[k] = in->couples ? twist * n[k] : 0.0;
}

POLY_INLINE void poly_contact_input_set_bodies(poly_contact_input *in, const double *position_i, const double *velocity_i,
                                               const double *omega_i, double mass_i, const double *position_j,
                                               const double *velocity_j, const double *omega_j, double mass_j,
                                               double dt)
{
  for (int k = 0; k < 3; k++) {
    in->position_i[k] = position_i[k];
    in->position_j[k] = position_j[k];
    in->velocity_i[k] = velocity_i[k];
    in->velocity_j[k] = velocity_j[k];
    in->omega_i[k] = omega_i[k];
    in->omega_j[k] = omega_j[k];
  }
  in->mass_i = mass_i;
  in->mass_j = mass_j;
  in->dt = dt;
}

/* Restitution of a Hertz contact with damping 2 sqrt(5/6) beta sqrt(k_n m*) and
 * no attraction. In units of the impact speed and the Hertz length and time it
 * is X'' = -X^(3/2) - sqrt(5) beta X^(1/4) X' (force clamped at 0), X(0) = 0,
 * X'(0) = 1: independent of speed, size and stiffness, so one integration
 * (RK4) per value of beta suffices. */
POLY_INLINE double poly_clamped_hertz_restitution(double beta)
{
  const double c = sqrt(5.0) * beta, dt = 2e-3;
  double x = 0.0, v = 1.0, t = 0.0;
  for (;;) {
    double xs[4], vs[4], ax[4], av[4];
    for (int stage = 0; stage < 4; stage++) {
      double h = stage == 0 ? 0.0 : (stage == 3 ? dt : 0.5 * dt);
      xs[stage] = x + h * (stage ? ax[stage - 1] : 0.0);
      vs[stage] = v + h * (stage ? av[stage - 1] : 0.0);
      double force = 0.0;
      if (xs[stage] > 0.0) {
        force = pow(xs[stage], 1.5) + c * pow(xs[stage], 0.25) * vs[stage];
        if (force < 0.0) force = 0.0;
      }
      ax[stage] = vs[stage];
      av[stage] = -force;
    }
    double x_next = x + dt / 6.0 * (ax[0] + 2.0 * ax[1] + 2.0 * ax[2] + ax[3]);
    double v_next = v + dt / 6.0 * (av[0] + 2.0 * av[1] + 2.0 * av[2] + av[3]);
    t += dt;
    if (x_next <= 0.0 && t > 0.1) return -(v + (v_next - v) * x / (x - x_next));
    if (t > 1e4) return 0.0; /* overdamped: the bodies never separate */
    x = x_next;
    v = v_next;
  }
}

/* The beta whose clamped Hertz contact rebounds with restitution e (bisection
 * on the monotone map above, to 1e-6 in e). */
POLY_INLINE double poly_damping_beta_for_restitution(double restitution)
{
  if (restitution >= 1.0) return 0.0;
  double low = 0.0, high = 64.0;
  for (int iteration = 0; iteration < 40 && high - low > 1e-9; iteration++) {
    double middle = 0.5 * (low + high);
    if (poly_clamped_hertz_restitution(middle) > restitution) low = middle;
    else high = middle;
  }
  return 0.5 * (low + high);
}

/* `damping_beta` from poly_damping_beta_for_restitution (which costs a few
 * hundred RK4 integrations: callers compute it once per distinct e). */
POLY_INLINE void poly_material_pair_make(double youngs_i, double poisson_i, double youngs_j, double poisson_j,
                                         double damping_beta, double friction, poly_material_pair *pair)
{
  pair->youngs_effective = 1.0 / ((1.0 - poisson_i * poisson_i) / youngs_i + (1.0 - poisson_j * poisson_j) / youngs_j);
  pair->shear_effective = 1.0 / (2.0 * (2.0 - poisson_i) * (1.0 + poisson_i) / youngs_i +
                                 2.0 * (2.0 - poisson_j) * (1.0 + poisson_j) / youngs_j);
  pair->damping_beta = damping_beta;
  pair->friction = friction;
  pair->cohesion = 0.0;
}

/* Cohesion sjkr's own overlap: two flat faces held together by cohesion alone (no load) sink until the law's
 * 4/(3 sqrt(pi)) E* L delta (V = L^2 delta) equals k L^2, i.e. delta / L = 3 sqrt(pi)/4 k/E*. For a vertex
 * pressed into a face, cohesion k A and the elastic force both grow as delta^2, so a blunt enough vertex is
 * drawn in until faces meet: this depth, not the vertex's, is where a strongly cohesive contact ends. */
POLY_INLINE double poly_cohesion_face_depth_ratio(double cohesion, double youngs_effective)
{
  return 0.75 * sqrt(POLY_PI) * cohesion / youngs_effective;
}

/* How deep, as a fraction of a particle's size, a contact may be at the start of a run before the package warns
 * that it will be pushed apart violently: 1 %, or the depth at which cohesion alone holds two faces. */
POLY_INLINE double poly_initial_overlap_allowance(const poly_material_pair *material)
{
  const double cohesive = poly_cohesion_face_depth_ratio(material->cohesion, material->youngs_effective);
  return cohesive > 0.01 ? cohesive : 0.01;
}

/* The time-step estimates LIGGGHTS makes for spheres (fix check/timestep/gran): the Rayleigh time of a
 * particle of radius r, pi r sqrt(rho / G) / (0.1631 nu + 0.8766), G = E / (2 (1 + nu)), and the Hertz
 * contact time 2.87 (m^2 / (r E*^2 v))^(1/5) of mass m, radius r, effective modulus E* at approach speed v. */
POLY_INLINE double poly_rayleigh_time(double radius, double density, double youngs, double poisson)
{
  const double shear = youngs / (2.0 * (1.0 + poisson));
  return POLY_PI * radius * sqrt(density / shear) / (0.1631 * poisson + 0.8766);
}

POLY_INLINE double poly_hertz_time(double mass, double radius, double youngs_effective, double speed)
{
  return 2.87 * pow(mass * mass / (radius * youngs_effective * youngs_effective * speed), 0.2);
}

/* Evaluates the law and advances `history` (POLY_HISTORY_SIZE doubles, zero
 * for a new contact). `tangential` and `damping` switch those parts on. */
POLY_INLINE void poly_contact_evaluate(const poly_contact_input *in, const poly_material_pair *material, int tangential,
                                       int damping, double *history, poly_contact_output *out)
{
  const double *n = in->normal;
  double arm_i[3], arm_j[3], contact_velocity_i[3], contact_velocity_j[3], u[3], u_t[3];
  for (int k = 0; k < 3; k++) {
    arm_i[k] = in->centroid[k] - in->position_i[k];
    arm_j[k] = in->centroid[k] - in->position_j[k];
  }
  poly_cross3_d(in->omega_i, arm_i, contact_velocity_i);
  poly_cross3_d(in->omega_j, arm_j, contact_velocity_j);
  for (int k = 0; k < 3; k++)
    u[k] = (in->velocity_j[k] + contact_velocity_j[k]) - (in->velocity_i[k] + contact_velocity_i[k]);
  double u_n = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
  for (int k = 0; k < 3; k++) u_t[k] = u[k] - u_n * n[k];

  double effective_mass = in->mass_j > 0.0 ? in->mass_i * in->mass_j / (in->mass_i + in->mass_j) : in->mass_i;
  double radius_like = in->depth > 0.0 ? sqrt(in->volume / (POLY_PI * in->depth)) : 0.0; /* sqrt(R delta) for spheres */
  double k_n = 2.0 * material->youngs_effective * radius_like;
  double k_t = 8.0 * material->shear_effective * radius_like;
  double elastic = 4.0 / (3.0 * sqrt(POLY_PI)) * material->youngs_effective * sqrt(in->volume * in->depth);
  double damping_factor = damping ? 2.0 * sqrt(5.0 / 6.0) * material->damping_beta : 0.0;
  double gamma_n = damping_factor * sqrt(k_n * effective_mass);
  double normal_force = elastic - gamma_n * u_n;
  if (normal_force < 0.0) normal_force = 0.0;

  double tangential_force[3] = {0.0, 0.0, 0.0};
  if (tangential) {
    double *elastic_t = history;
    /* Carry the stored force into the current tangent plane, keeping its size. */
    double along = elastic_t[0] * n[0] + elastic_t[1] * n[1] + elastic_t[2] * n[2];
    double before = sqrt(elastic_t[0] * elastic_t[0] + elastic_t[1] * elastic_t[1] + elastic_t[2] * elastic_t[2]);
    for (int k = 0; k < 3; k++) elastic_t[k] -= along * n[k];
    double after = sqrt(elastic_t[0] * elastic_t[0] + elastic_t[1] * elastic_t[1] + elastic_t[2] * elastic_t[2]);
    if (after > 0.0)
      for (int k = 0; k < 3; k++) elastic_t[k] *= before / after;
    /* Unloading shrinks the stuck spring with the contact (4.9). */
    double previous_stiffness = history[3], previous_normal = history[4];
    if (normal_force < previous_normal && previous_stiffness > 0.0)
      for (int k = 0; k < 3; k++) elastic_t[k] *= k_t / previous_stiffness;
    for (int k = 0; k < 3; k++) elastic_t[k] -= k_t * u_t[k] * in->dt;

    double gamma_t = damping_factor * sqrt(k_t * effective_mass);
    double elastic_size = sqrt(elastic_t[0] * elastic_t[0] + elastic_t[1] * elastic_t[1] + elastic_t[2] * elastic_t[2]);
    double limit = material->friction * normal_force;
    if (elastic_size > limit) {
      /* Sliding: the spring holds exactly the Coulomb force, no damping (as LIGGGHTS). */
      double ratio = elastic_size > 0.0 ? limit / elastic_size : 0.0;
      for (int k = 0; k < 3; k++) {
        elastic_t[k] *= ratio;
        tangential_force[k] = elastic_t[k];
      }
    } else {
      for (int k = 0; k < 3; k++) tangential_force[k] = elastic_t[k] - gamma_t * u_t[k];
    }
    history[3] = k_t;
    history[4] = normal_force;
  }

  double force_i[3], twist[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < 3; k++) {
    out->force_j[k] = normal_force * n[k] + tangential_force[k];
    out->tangential_force[k] = tangential_force[k];
    force_i[k] = -out->force_j[k];
    out->pressure_shift[k] = 0.0;
  }
  if (damping) {
    double gamma_t = tangential ? damping_factor * sqrt(k_t * effective_mass) : 0.0;
    poly_rocking_damping(in, gamma_n, gamma_t, normal_force, material->friction, out->pressure_shift, twist);
    for (int k = 0; k < 3; k++) {
      arm_i[k] += out->pressure_shift[k];
      arm_j[k] += out->pressure_shift[k];
    }
  }
  poly_cross3_d(arm_i, force_i, out->torque_i);
  poly_cross3_d(arm_j, out->force_j, out->torque_j);
  for (int k = 0; k < 3; k++) {
    out->torque_j[k] += twist[k];
    out->torque_i[k] -= twist[k];
  }
  /* Cohesion (LIGGGHTS' cohesion sjkr, with the overlap's cross-section for the spheres' contact circle): k A
   * pulls j towards i at the centroid, beside the repulsion, which keeps its friction limit. */
  const double cohesive = material->cohesion * in->contact_area;
  out->cohesive_force = cohesive;
  if (cohesive > 0.0) {
    double pull_j[3], pull_i[3], centroid_arm_i[3], centroid_arm_j[3], torque[3];
    for (int k = 0; k < 3; k++) {
      pull_j[k] = -cohesive * n[k];
      pull_i[k] = -pull_j[k];
      out->force_j[k] += pull_j[k];
      centroid_arm_i[k] = in->centroid[k] - in->position_i[k];
      centroid_arm_j[k] = in->centroid[k] - in->position_j[k];
    }
    poly_cross3_d(centroid_arm_i, pull_i, torque);
    for (int k = 0; k < 3; k++) out->torque_i[k] += torque[k];
    poly_cross3_d(centroid_arm_j, pull_j, torque);
    for (int k = 0; k < 3; k++) out->torque_j[k] += torque[k];
  }
  out->normal_force = normal_force;
  out->normal_stiffness = k_n;
  out->tangential_stiffness = k_t;
}

#endif
