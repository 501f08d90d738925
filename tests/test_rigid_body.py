"""fix nve/polyhedron and compute erotate/polyhedron against closed forms and an
independent integration of Euler's equations."""
import math

import numpy as np

import decks

DENSITY = 1000.0
SCALE = 0.1  # box 0.1 x 0.2 x 0.3 m


def box_moments():
    """Principal moments of the 1x2x3 box scaled by SCALE, ascending (long axis first)."""
    a, b, c = SCALE * 1.0, SCALE * 2.0, SCALE * 3.0
    mass = DENSITY * a * b * c
    return mass, sorted([mass * (b * b + c * c) / 12.0, mass * (a * a + c * c) / 12.0,
                         mass * (a * a + b * b) / 12.0])


def rotation_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def euler_reference(moments, omega0, t_end, dt):
    """Body angular velocity of a free asymmetric top by classical RK4 on Euler's
    equations (plain floats: fast enough for 10^5 steps)."""
    i1, i2, i3 = moments
    a, b, c = (i2 - i3) / i1, (i3 - i1) / i2, (i1 - i2) / i3

    def rate(w1, w2, w3):
        return a * w2 * w3, b * w3 * w1, c * w1 * w2

    w = tuple(float(v) for v in omega0)
    times, history = [0.0], [w]
    for n in range(int(round(t_end / dt))):
        k1 = rate(*w)
        k2 = rate(*(w[k] + 0.5 * dt * k1[k] for k in range(3)))
        k3 = rate(*(w[k] + 0.5 * dt * k2[k] for k in range(3)))
        k4 = rate(*(w[k] + dt * k3[k] for k in range(3)))
        w = tuple(w[k] + dt / 6.0 * (k1[k] + 2 * k2[k] + 2 * k3[k] + k4[k]) for k in range(3))
        times.append((n + 1) * dt)
        history.append(w)
    return np.array(times), np.array(history)


def sign_changes(times, values):
    """Times where `values` crosses zero (linear interpolation)."""
    crossings = []
    for k in range(1, len(values)):
        if values[k - 1] * values[k] < 0.0:
            t0, t1 = times[k - 1], times[k]
            crossings.append(t0 + (t1 - t0) * values[k - 1] / (values[k - 1] - values[k]))
    return crossings


def test_free_fall_matches_closed_form(run_deck):
    steps, dt, g = 2000, 1e-4, 9.81
    x0, v0 = np.array([0.3, 0.5, 0.9]), np.array([0.2, -0.1, 1.5])
    deck = (decks.header(boundary="f f f", lo=-5.0, hi=5.0) + decks.template("cube", "cube.stl", scale=0.01) +
            f"create_polyhedron cube {x0[0]} {x0[1]} {x0[2]} vel {v0[0]} {v0[1]} {v0[2]} omega 3 -2 1\n"
            f"fix integrate all nve/polyhedron\nfix gravity all gravity {g} vector 0 0 -1\n"
            f"timestep {dt}\n"
            "dump final all custom %d final.txt id x y z vx vy vz\n"
            "dump_modify final format \"%%d %%.17g %%.17g %%.17g %%.17g %%.17g %%.17g\"\n"
            "run %d\n" % (steps, steps))
    result = run_deck(deck)
    assert result.returncode == 0, result.output
    _, rows = decks.read_dump(result.workdir / "final.txt")
    t = steps * dt
    expected_x = x0 + v0 * t + 0.5 * np.array([0.0, 0.0, -g]) * t * t
    expected_v = v0 + np.array([0.0, 0.0, -g]) * t
    x, v = np.array(rows[1][1:4]), np.array(rows[1][4:7])
    # Velocity Verlet is exact for constant acceleration: only round-off remains.
    assert np.max(np.abs(x - expected_x)) < 1e-12, (x, expected_x)
    assert np.max(np.abs(v - expected_v)) < 1e-12, (v, expected_v)


def test_torque_free_asymmetric_top(run_deck):
    """Spin mostly about the intermediate axis: the Dzhanibekov flip must appear at the
    times Euler's equations predict, with bounded energy error and conserved |L|."""
    steps, dt, every = 100000, 1e-4, 100
    mass, moments = box_moments()
    omega_body = np.array([0.05, 10.0, 0.05])  # identity orientation: body frame = world frame
    deck = (decks.header(boundary="f f f", lo=-1.0, hi=1.0) + decks.template("box", "box_1x2x3.off", scale=SCALE,
                                                                           density=DENSITY) +
            "create_polyhedron box 0 0 0 omega %.17g %.17g %.17g\n" % tuple(omega_body) +
            "fix integrate all nve/polyhedron\n"
            "compute erot all erotate/polyhedron\n"
            "compute orientation all property/polyhedron quatw quati quatj quatk\n"
            f"timestep {dt}\n"
            f"thermo_style custom step c_erot\nthermo_modify format float %.15g\nthermo {every}\n"
            f"dump state all custom {every} state.txt id omegax omegay omegaz angmomx angmomy angmomz "
            "c_orientation[1] c_orientation[2] c_orientation[3] c_orientation[4]\n"
            "dump_modify state format \"%d" + " %.17g" * 10 + "\"\n"
            f"run {steps}\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output

    # The template must have the box's moments and the box's long axis as body axis 1.
    energy0 = 0.5 * float(np.dot(moments, omega_body ** 2))
    energies = np.array(result.thermo("c_erot")["c_erot"])
    assert abs(energies[0] - energy0) < 1e-12 * energy0, (energies[0], energy0)
    energy_error = np.max(np.abs(energies / energy0 - 1.0))
    print(f"asymmetric top, {steps} steps: max relative energy error {energy_error:.3e}")
    assert energy_error < 1e-6, energy_error

    snapshots = decks.read_all_dump_snapshots(result.workdir / "state.txt")
    times, body_omega, angmom = [], [], []
    for step, _, rows in snapshots:
        values = rows[1]
        rotation = rotation_matrix(values[7:11])
        times.append(step * dt)
        body_omega.append(rotation.T @ np.array(values[1:4]))
        angmom.append(values[4:7])
    times, body_omega, angmom = np.array(times), np.array(body_omega), np.array(angmom)
    angmom0 = np.array(moments) * omega_body
    angmom_error = np.max(np.abs(angmom - angmom0)) / np.linalg.norm(angmom0)
    print(f"asymmetric top: max relative angular momentum error {angmom_error:.3e}")
    assert angmom_error < 1e-10

    ref_times, ref_omega = euler_reference(moments, omega_body, steps * dt, dt)
    flips = sign_changes(times, body_omega[:, 1])
    ref_flips = sign_changes(ref_times, ref_omega[:, 1])
    assert len(ref_flips) >= 2, ref_flips  # the set-up really shows the intermediate-axis instability
    assert len(flips) == len(ref_flips), (flips, ref_flips)
    period = ref_flips[1] - ref_flips[0]
    print("flip times (s): measured " + " ".join(f"{t:.5f}" for t in flips) +
          " / Euler RK4 " + " ".join(f"{t:.5f}" for t in ref_flips))
    for measured, reference in zip(flips, ref_flips):
        assert abs(measured - reference) < 0.01 * period, (flips, ref_flips)
    # And along the whole run the body angular velocity follows the reference.
    sampled = ref_omega[::every]
    assert np.max(np.abs(body_omega - sampled[:len(body_omega)])) < 0.05 * omega_body[1]


def quat_multiply(a, b):
    return np.array([a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                     a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                     a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                     a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]])


def test_principal_axis_spins_of_many_particles_are_exact(run_deck):
    """A spin about a body principal axis is a steady rotation, and NO_SQUISH turns it
    exactly: q(t) = q0 (cos wt/2, sin wt/2 e_k). Eleven particles, so that the integrator's
    blocks of particles are full and partial, with one not spinning (q stays, omega = 0),
    spins about all three axes, and one rate whose sub-rotation angle (0.2 rad) is beyond
    the polynomial sin/cos range."""
    steps, dt = 1000, 1e-3
    spins = [(1, 3.0), (3, 1.0), (2, 2.0), (0, 0.0), (3, 7.0), (1, 40.0), (3, 60.0), (2, 5.0),
             (1, 400.0), (3, 150.0), (1, -25.0)]
    rng = np.random.default_rng(3)
    deck = (decks.header(boundary="f f f", lo=-3.0, hi=3.0) +
            decks.template("box", "box_1x2x3.off", scale=SCALE, density=DENSITY))
    initial = []
    for n, (axis, rate) in enumerate(spins):
        q0 = rng.normal(size=4)
        q0 /= np.linalg.norm(q0)
        omega_body = np.zeros(3)
        if axis:
            omega_body[axis - 1] = rate
        omega_world = rotation_matrix(q0) @ omega_body
        initial.append((q0, omega_body))
        deck += ("create_polyhedron box %.17g 0 0 quat %.17g %.17g %.17g %.17g omega %.17g %.17g %.17g\n"
                 % ((-2.5 + 0.5 * n,) + tuple(q0) + tuple(omega_world)))
    deck += ("fix integrate all nve/polyhedron\n"
             "compute orientation all property/polyhedron quatw quati quatj quatk\n"
             f"timestep {dt}\n"
             f"dump state all custom {steps} state.txt id omegax omegay omegaz "
             "c_orientation[1] c_orientation[2] c_orientation[3] c_orientation[4]\n"
             "dump_modify state format \"%d" + " %.17g" * 7 + "\"\n"
             f"run {steps}\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output
    snapshots = decks.read_all_dump_snapshots(result.workdir / "state.txt")
    (first, _, start), (last, _, rows) = snapshots[0], snapshots[-1]
    assert (first, last) == (0, steps)
    t = steps * dt
    for n, (axis, rate) in enumerate(spins):
        q0, omega_body = initial[n]
        values = rows[n + 1]
        q = np.array(values[4:8])
        if not axis:
            assert np.max(np.abs(q - np.array(start[n + 1][4:8]))) < 1e-15, (q, start[n + 1])
            assert not np.any(np.array(values[1:4])), values
            continue
        turn = np.zeros(4)
        turn[0] = math.cos(0.5 * rate * t)
        turn[axis] = math.sin(0.5 * rate * t)
        expected_q = quat_multiply(q0, turn)
        assert np.max(np.abs(q - expected_q)) < 1e-11, (n, q, expected_q)
        expected_omega = rotation_matrix(expected_q) @ omega_body
        assert np.max(np.abs(np.array(values[1:4]) - expected_omega)) < 1e-11 * abs(rate), (n, values, expected_omega)


def test_erotate_matches_half_omega_dot_l_for_arbitrary_orientation(run_deck):
    mass, moments = box_moments()
    q = np.array([0.8, 0.3, -0.4, 0.34])
    q /= np.linalg.norm(q)
    omega_world = np.array([1.5, -2.0, 0.7])
    deck = (decks.header(boundary="f f f", lo=-1.0, hi=1.0) +
            decks.template("box", "box_1x2x3.off", scale=SCALE, density=DENSITY) +
            "create_polyhedron box 0 0 0 quat %.17g %.17g %.17g %.17g omega %.17g %.17g %.17g\n"
            % (tuple(q) + tuple(omega_world)) +
            "compute erot all erotate/polyhedron\nthermo_style custom step c_erot\n"
            "thermo_modify format float %.15g\nfix integrate all nve/polyhedron\nrun 0\n")
    result = run_deck(deck)
    assert result.returncode == 0, result.output
    rotation = rotation_matrix(q)
    inertia_world = rotation @ np.diag(moments) @ rotation.T
    expected = 0.5 * omega_world @ inertia_world @ omega_world
    measured = result.thermo("c_erot")["c_erot"][0]
    assert abs(measured - expected) < 1e-12 * expected, (measured, expected)
