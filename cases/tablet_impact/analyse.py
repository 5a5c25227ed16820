"""Compares a tablet_impact run with the book's Eqs. 4.25-4.27 (Kureck et al. 2019) and writes
result.json and tablet_impact.png beside it.

Rebound of a rigid body from one contact point on a frictionless plane, restitution gamma = 1
(book Eqs. 4.25, 4.26; v_y- = -1 m/s, y the plane's normal, here z):
  w_z+ = m v_y- (1 + gamma) r_x / (I_zz + m r_x^2)
  v_y+ = w_z+ r_x - gamma v_y-
r_x is the horizontal distance from the centroid to the contact point and I_zz the inertia about
the spin axis (a transverse axis of the tablet). The spin axis is y here, and w_y of the run is
the book's w_z (same sign).

(a) The modelled body: m and I_zz of the simulated body (checkpoint), r_x of its contact point.
    A dilated polyhedron touches a plane below the core's lowest vertex (the only local minimum of
    the height on a convex core; the force acts along the normal through it), so r_x is the
    horizontal offset of the core's lowest vertex from the centroid, with the core placed as the
    engine placed it (fitted to the surface the run draws at 1 ms, see `placed_core`). The smooth
    core's r_x (the offset tablet's lowest point: rim R1c sin(theta - alpha_c), cap d cos theta)
    is given beside it; the two differ on the caps, where the lowest vertex is up to half a ring
    step from the sphere's lowest point.
(b) The book's ideal tablet: Eq. 4.27 with R1, R2, alpha, beta and the ideal solid's m and I_zz
    (digest A6.4), drawn dotted.

Relative errors: |measured - analytic| over the largest magnitude of the analytic curve over
0-90 degrees (w_z+: the modelled body's largest |w|, about 336 rad/s; v_y+: 1 m/s), because both
cross zero. `max_rel_error` is the largest of the two over the angles above 22 degrees.

usage: analyse.py RUN_DIR OUTPUT_DIR"""
import glob
import json
import math
import os
import re
import sys
import zlib

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_scene  # noqa: E402
import make_tablet as tab  # noqa: E402

V_MINUS = -make_scene.SPEED
GAMMA = 1.0
# Book digest A6.4 (ideal tablet: band cylinder and two spherical caps, rho = 958.9 kg/m3).
DIGEST_IDEAL_MASS = 4.517e-4
DIGEST_IDEAL_INERTIA = 4.041e-9


# ----------------------------------------------------------------------------------- reading
def appended_arrays(path):
    """The arrays of a VTK XML file with appended, zlib-compressed data, by name."""
    raw = open(path, "rb").read()
    start = raw.index(b"<AppendedData")
    data = raw[raw.index(b"_", start) + 1:]
    header = raw[:start].decode()
    arrays = {}
    kinds = {"Float64": "<f8", "Int64": "<i8", "Int32": "<i4"}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)"[^>]*?offset="\s*(\d+)', header):
        kind, name, offset = m.group(1), m.group(2), int(m.group(3))
        blocks = int(np.frombuffer(data[offset:offset + 8], "<u8")[0])
        sizes = np.frombuffer(data[offset + 24:offset + 24 + 8 * blocks], "<u8")
        p, out = offset + 24 + 8 * blocks, b""
        for s in sizes:
            out += zlib.decompress(data[p:p + int(s)])
            p += int(s)
        arrays[name] = np.frombuffer(out, kinds[kind])
    return arrays


def rotation(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def state(path):
    """Per body, ordered by angle: the checkpoint's fields."""
    with h5py.File(path, "r") as f:
        source = f["particles/source"][:, 0]
        names = f["source_names"][()].decode().split()
        angles = np.array([int(names[s].split("_")[1]) for s in source])
        order = np.argsort(angles)
        fields = {k: f["particles/" + k][...][order] for k in
                  ("id", "position", "velocity", "angular_velocity", "mass", "inertia",
                   "orientation")}
        fields["time"] = float(f["time"][()])
    fields["angles"] = angles[order]
    return fields


def pseudonormals(vertices, triangles):
    """Angle-weighted vertex normals of the core (the engine moves the drawn surface out by r
    along them)."""
    normals = np.zeros_like(vertices)
    p = vertices[triangles]
    face = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    face /= np.linalg.norm(face, axis=1)[:, None]
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        angle = np.arccos(np.clip(np.einsum("ij,ij->i", a, b) /
                                  (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1)), -1, 1))
        np.add.at(normals, triangles[:, k], angle[:, None] * face)
    return normals / np.linalg.norm(normals, axis=1)[:, None]


def placed_core(run_dir, before):
    """How the engine placed the core in each body: the rotation from the mesh's frame to the body
    frame and the mesh origin in the body frame (the body frame is the engine's principal frame,
    centroid at its origin), fitted (Kabsch) to the surface drawn at the step of the checkpoint
    `before` (the core moved out by r along its vertex normals)."""
    vertices, triangles = tab.tablet_mesh()
    vertices = vertices * 1e-3
    drawn_in_mesh = vertices + tab.R_DIL * pseudonormals(vertices, triangles)
    step = int(round(before["time"] / make_scene.TIME_STEP))
    arrays = appended_arrays(os.path.join(run_dir, "frames", f"shapes_{step:08d}.vtp"))
    points, ids = arrays["Points"].reshape(-1, 3), arrays["id"]
    def kabsch(a, b):
        ca, cb = a.mean(0), b.mean(0)
        u, _, vt = np.linalg.svd((a - ca).T @ (b - cb))
        d = np.sign(np.linalg.det(u @ vt))
        r = (u @ np.diag([1, 1, d]) @ vt).T
        return r, cb - r @ ca

    fits = []
    for k in range(len(before["angles"])):
        world = points[ids == before["id"][k, 0]]
        rq = rotation(before["orientation"][k])
        body = (world - before["position"][k]) @ rq   # rows: R_q^T (w - x)
        # The engine numbers a few vertices otherwise than the file (its surface is the same):
        # fit, pair each vertex with the nearest drawn point, fit again.
        r_mb, origin = kabsch(drawn_in_mesh, body)
        moved = drawn_in_mesh @ r_mb.T + origin
        nearest = np.argmin(((moved[:, None, :] - body[None, :, :]) ** 2).sum(-1), axis=1)
        r_mb, origin = kabsch(drawn_in_mesh, body[nearest])
        residual = np.abs(drawn_in_mesh @ r_mb.T + origin - body[nearest]).max()
        fits.append((r_mb, origin, residual, int((nearest != np.arange(len(body))).sum())))
    return vertices, fits


# ---------------------------------------------------------------------------------- geometry
def tilt(theta):
    """The scene's orientation at the impact angle theta (rad, axis to plane): about +y by
    90 deg - theta."""
    psi = math.pi / 2 - theta
    return np.array([[math.cos(psi), 0, math.sin(psi)], [0, 1, 0], [-math.sin(psi), 0, math.cos(psi)]])


def contact_arm(core_body, theta):
    """The lowest core vertex of the body at angle theta relative to the centroid (world axes) and
    the height of the next lowest vertex above it."""
    world = core_body @ tilt(theta).T
    order = np.argsort(world[:, 2])
    return world[order[0]], world[order[1], 2] - world[order[0], 2]


def smooth_core_arm(theta):
    """r_x of the smooth core (the tablet offset inward by r), exactly: band at 0, rim below
    90 deg - beta_c, cap above."""
    if theta == 0:
        return 0.0
    if theta <= math.pi / 2 - tab.CORE_BETA:
        return tab.CORE_R1 * math.sin(theta - tab.CORE_ALPHA)
    return tab.D_CAP * math.cos(theta)


def book_arm(theta):
    """Eq. 4.27 as printed (digest A6.4), the ideal tablet."""
    if theta <= tab.ALPHA:
        return 0.0
    if theta <= math.pi / 2 - tab.BETA:
        return tab.R1 * math.sin(theta - tab.ALPHA)
    return tab.D_CAP * math.cos(theta)


def rebound(mass, inertia, arm):
    """Eqs. 4.25, 4.26."""
    spin = mass * V_MINUS * (1 + GAMMA) * arm / (inertia + mass * arm ** 2)
    return spin, spin * arm - GAMMA * V_MINUS


def impulse_3d(mass, inertia_world, arm):
    """The same rigid-body impulse in three dimensions (a contact point off the tilt plane, as the
    engine's placement makes it): velocity and angular velocity after."""
    n = np.array([0.0, 0.0, 1.0])
    inverse = np.linalg.inv(inertia_world)
    rn = np.cross(arm, n)
    impulse = -(1 + GAMMA) * V_MINUS / (1 / mass + rn @ inverse @ rn)
    return np.array([0, 0, V_MINUS]) + impulse * n / mass, inverse @ (impulse * rn)


def integrated_rebound(mass, inertia, core_body, theta, equivalent_radius, dt=1e-7):
    """The impact integrated in time in the tilt plane (RK4): the body turns and the force acts at
    whichever core vertex is lowest, Hertz with the engine's radius (the body's volume-equivalent
    radius) and E* = E / (2 (1 - nu^2)), no damping. What is left between this and the impulse
    theory is the contact's finite duration."""
    e_star = make_scene.YOUNGS_MODULUS / (2 * (1 - make_scene.POISSON_RATIO ** 2))
    stiffness = 4.0 / 3.0 * e_star * math.sqrt(equivalent_radius)
    points = core_body @ tilt(theta).T
    xz = points[:, [0, 2]]

    def lowest(angle):   # the lowest vertex after a turn by `angle` about +y (x to -z)
        c, s = math.cos(angle), math.sin(angle)
        x = c * xz[:, 0] + s * xz[:, 1]
        z = -s * xz[:, 0] + c * xz[:, 1]
        k = np.argmin(z)
        return x[k], z[k]

    def rates(y):
        z, angle, v, w = y
        x_c, z_c = lowest(angle)
        depth = -(z + z_c - tab.R_DIL)
        force = stiffness * depth ** 1.5 if depth > 0 else 0.0
        # torque about +y of a force +z at x_c: -x_c F (w = d angle/dt about +y)
        return np.array([v, w, force / mass, -x_c * force / inertia]), depth

    y = np.array([-lowest(0.0)[1] + tab.R_DIL, 0.0, V_MINUS, 0.0])  # touching, falling
    touched = False
    for _ in range(200000):
        k1, depth = rates(y)
        if depth > 0:
            touched = True
        elif touched:
            break
        k2, _ = rates(y + dt / 2 * k1)
        k3, _ = rates(y + dt / 2 * k2)
        k4, _ = rates(y + dt * k3)
        y = y + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return float(y[3]), float(y[2])


def profile_body(core_radius_at, z_lo, z_hi, dilation, density):
    """Mass and transverse and axial inertia of a convex solid of revolution: the core's radius
    at height z (0 outside), Minkowski-summed with a ball of radius `dilation` (0: the core), by
    integration over its meridian."""
    zc = np.linspace(z_lo, z_hi, 40001)
    rc = core_radius_at(zc)
    z = np.linspace(z_lo - dilation, z_hi + dilation, 8001)
    if dilation > 0:
        rho = np.zeros_like(z)
        for k, zz in enumerate(z):
            near = np.abs(zc - zz) <= dilation
            rho[k] = np.max(rc[near] + np.sqrt(dilation ** 2 - (zc[near] - zz) ** 2))
    else:
        z, rho = zc, rc
    mass = density * np.trapz(np.pi * rho ** 2, z)
    axial = density * np.trapz(np.pi * rho ** 4 / 2, z)
    transverse = density * np.trapz(np.pi * rho ** 4 / 4 + np.pi * rho ** 2 * z ** 2, z)
    return mass, transverse, axial


def tablet_radius(band_radius, cap_radius, band_half):
    def radius(z):
        cap = np.sqrt(np.clip(cap_radius ** 2 - (np.abs(z) + tab.D_CAP) ** 2, 0, None))
        return np.where(np.abs(z) <= band_half, band_radius, cap)
    return radius


# ---------------------------------------------------------------------------------- analysis
def contact_times(run_dir):
    """Times (s) of the series rows with wall contacts: first, last, and whether any row after
    the last contact-free row following the landing has contacts again."""
    data = np.genfromtxt(os.path.join(run_dir, "series.csv"), delimiter=",", names=True)
    touching = data["wall_contacts"] > 0
    times = data["time"][touching]
    first, last = times.min(), times.max()
    gaps = np.diff(np.flatnonzero(touching))
    return first, last, bool(np.any(gaps > 1)), float(data["time"][-1]), int(data["wall_contacts"].max())


def next_landing(position, velocity, spin, rq, core_body, horizon=0.01, dt=1e-6):
    """Time after the run's end at which the body, moving freely (constant velocity and world
    angular velocity), touches the plane again (its lowest core vertex r above it); inf if not
    within `horizon`."""
    w = np.linalg.norm(spin)
    axis = spin / w if w > 0 else np.array([0.0, 0.0, 1.0])
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    t = 0.0
    while t < horizon:
        a = w * t
        turn = np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * (k @ k)
        lowest = position[2] + velocity[2] * t + (core_body @ (turn @ rq).T)[:, 2].min()
        if lowest - tab.R_DIL <= 0:
            return t
        t += dt
    return math.inf


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    run_dir, out_dir = sys.argv[1:]
    end = state(os.path.join(run_dir, "checkpoint.h5"))
    checkpoints = sorted(glob.glob(os.path.join(run_dir, "checkpoints", "checkpoint_*.h5")))
    before = state(checkpoints[0])
    angles = end["angles"]
    if list(angles) != make_scene.ANGLES:
        sys.exit(f"expected the angles {make_scene.ANGLES}, found {list(angles)}")
    vertices, fits = placed_core(run_dir, before)
    r_mb, origin, fit_residual, renumbered = fits[0]
    core_body = vertices @ r_mb.T + origin           # the core in the body frame (centroid 0)
    axis_body = r_mb @ np.array([0.0, 0.0, 1.0])
    turn_about_axis = math.degrees(math.atan2(r_mb[1, 0], r_mb[0, 0]))
    same_placement = max(np.abs(f[0] - r_mb).max() for f in fits)

    mass = float(end["mass"][0, 0])
    principal = end["inertia"][0]
    first, last, touched_again, t_end, most_contacts = contact_times(run_dir)
    equivalent_radius = (3 * mass / make_scene.DENSITY / (4 * math.pi)) ** (1 / 3)

    rows, smooth_rows = [], []
    for k, a in enumerate(angles):
        theta = math.radians(a)
        rq = rotation(before["orientation"][k])
        inertia_world = rq @ np.diag(principal) @ rq.T
        i_zz = float(inertia_world[1, 1])
        arm, second_gap = contact_arm(core_body, theta)
        if a == 0:   # the band lies on the plane: a line of vertices, symmetric about the centroid
            arm = np.array([0.0, arm[1], arm[2]])
        w_model, v_model = rebound(mass, i_zz, arm[0])
        smooth = smooth_core_arm(theta)
        w_smooth, v_smooth = rebound(mass, i_zz, smooth)
        w_ideal, v_ideal = rebound(DIGEST_IDEAL_MASS, DIGEST_IDEAL_INERTIA, book_arm(theta))
        v3, w3 = impulse_3d(mass, inertia_world, arm)
        if a == 0:   # a line of vertices: symmetric, no turn
            w_int, v_int = w_model, v_model
        else:
            w_int, v_int = integrated_rebound(mass, i_zz, core_body, theta, equivalent_radius)
        v, w = end["velocity"][k], end["angular_velocity"][k]
        r_end = rotation(end["orientation"][k])
        ke_after = 0.5 * mass * v @ v + 0.5 * w @ (r_end @ np.diag(principal) @ r_end.T) @ w
        ke_before = 0.5 * mass * V_MINUS ** 2
        rows.append({
            "theta_degrees": int(a),
            "w_z_plus": float(w[1]), "v_y_plus": float(v[2]),
            "w_z_plus_model": w_model, "v_y_plus_model": v_model,
            "w_z_plus_ideal": w_ideal, "v_y_plus_ideal": v_ideal,
            "r_x_model_mm": float(arm[0] * 1e3), "r_x_smooth_core_mm": smooth * 1e3,
            "r_x_ideal_mm": book_arm(theta) * 1e3,
            "contact_point_off_tilt_plane_mm": float(arm[1] * 1e3),
            "next_vertex_above_lowest_um": float(second_gap * 1e6),
            "w_x_plus": float(w[0]), "w_x_plus_3d_impulse": float(w3[0]),
            "w_z_plus_3d_impulse": float(w3[1]), "v_y_plus_3d_impulse": float(v3[2]),
            "w_z_plus_smooth_core": w_smooth, "v_y_plus_smooth_core": v_smooth,
            "w_z_plus_integrated": w_int, "v_y_plus_integrated": v_int,
            "energy_error": float(ke_after / ke_before - 1),
            "second_contact_after_end_ms": 1e3 * next_landing(end["position"][k], v, w, r_end,
                                                              core_body),
        })
    # The curves' scales: the largest magnitudes over 0-90 degrees (0.1 degree steps).
    grid = np.radians(np.linspace(0, 90, 901))
    i_t = float(principal[0])
    model_curve = [rebound(mass, i_t, contact_arm(core_body, t)[0][0] if t > 0 else 0.0)
                   for t in grid]
    w_scale = max(abs(w) for w, _ in model_curve)
    v_scale = max(abs(v) for _, v in model_curve)
    for row in rows:
        for key, model in (("", "model"), ("_smooth_core", "smooth_core"), ("_ideal", "ideal")):
            row[f"w_z_plus_rel_error{key}"] = abs(row["w_z_plus"] - row[f"w_z_plus_{model}"]) / w_scale
            row[f"v_y_plus_rel_error{key}"] = abs(row["v_y_plus"] - row[f"v_y_plus_{model}"]) / v_scale
    above = [r for r in rows if r["theta_degrees"] > 22]
    below = [r for r in rows if r["theta_degrees"] < 22]

    def largest(key, subset):
        return max(max(r[f"w_z_plus_{key}"], r[f"v_y_plus_{key}"]) for r in subset)

    # Mass properties: the digest's ideal tablet, the same by integration, and the smooth modelled
    # body (the tablet with its rim rounded to r: the smooth core plus r).
    ideal = profile_body(tablet_radius(tab.L3 / 2, tab.R2, tab.L1 / 2), -tab.L2 / 2, tab.L2 / 2, 0.0,
                         make_scene.DENSITY)
    rounded = profile_body(tablet_radius(tab.CORE_RADIUS, tab.CORE_CAP_RADIUS, tab.CORE_RIM_Z),
                           -tab.CORE_APEX_Z, tab.CORE_APEX_Z, tab.R_DIL, make_scene.DENSITY)
    result = {
        "case": "tablet_impact",
        "reference": "book Sect. 4.3.1, Fig. 4.15, Eqs. 4.25-4.27 (Kureck et al. 2019): rigid-body "
                     "impulse of one contact point, gamma = 1, frictionless; book digest A6.4",
        "theta": "angle between the tablet's axis and the plane (90 deg: axis along the normal, "
                 "landing on a cap's apex; 0: landing on the band), the angle of Eq. 4.27",
        "quantities": "w_z_plus (rad/s, the book's w_z: here w_y, spin axis y) and v_y_plus (m/s, "
                      "the book's y: here z, the plane's normal) after the impact at v_y- = -1 m/s",
        "relative_error": "|measured - analytic| / the analytic curve's largest magnitude over "
                          "0-90 deg (w: scale_w_rad_s, v: scale_v_m_s), as both cross zero",
        "scale_w_rad_s": w_scale, "scale_v_m_s": v_scale,
        "max_rel_error": largest("rel_error", above),
        "max_rel_error_w": max(r["w_z_plus_rel_error"] for r in above),
        "max_rel_error_v": max(r["v_y_plus_rel_error"] for r in above),
        "max_rel_error_all_angles": largest("rel_error", rows),
        "max_rel_error_smooth_core_above_22deg": largest("rel_error_smooth_core", above),
        "max_rel_error_ideal_above_22deg": largest("rel_error_ideal", above),
        "max_abs_spin_below_22deg": max(abs(r["w_z_plus"]) for r in below),
        "max_abs_energy_error": max(abs(r["energy_error"]) for r in rows),
        "max_rel_difference_from_time_integration": max(
            max(abs(r["w_z_plus"] - r["w_z_plus_integrated"]) / w_scale,
                abs(r["v_y_plus"] - r["v_y_plus_integrated"]) / v_scale) for r in rows),
        "max_abs_w_x_plus": max(abs(r["w_x_plus"]) for r in rows),
        "max_abs_w_x_error_against_3d_impulse": max(abs(r["w_x_plus"] - r["w_x_plus_3d_impulse"])
                                                    for r in rows),
        "parameters": {
            "L1_band_thickness_m": tab.L1, "L2_total_thickness_m": tab.L2,
            "L3_rim_diameter_m": tab.L3, "dilation_radius_m": tab.R_DIL,
            "R1_m": tab.R1, "R2_m": tab.R2, "alpha_degrees": math.degrees(tab.ALPHA),
            "beta_degrees": math.degrees(tab.BETA), "cap_centre_from_centroid_m": tab.D_CAP,
            "core_band_radius_m": tab.CORE_RADIUS, "core_cap_radius_m": tab.CORE_CAP_RADIUS,
            "core_rim_height_m": tab.CORE_RIM_Z, "core_R1_m": tab.CORE_R1,
            "core_alpha_degrees": math.degrees(tab.CORE_ALPHA),
            "core_beta_degrees": math.degrees(tab.CORE_BETA),
            "rim_to_cap_switch_degrees_core": 90 - math.degrees(tab.CORE_BETA),
            "mesh": {"vertices": len(vertices), "triangles": 2 * len(vertices) - 4,
                     "nodes_per_ring": tab.NODES_PER_RING, "cap_rings": tab.CAP_RINGS,
                     "band_intervals": tab.BAND_INTERVALS},
            "youngs_modulus_Pa": make_scene.YOUNGS_MODULUS, "poisson_ratio": make_scene.POISSON_RATIO,
            "density_kg_m3": make_scene.DENSITY, "restitution": GAMMA, "friction": 0.0,
            "v_y_minus_m_s": V_MINUS, "time_step_s": make_scene.TIME_STEP,
            "start_gap_m": make_scene.FALL, "duration_s": make_scene.DURATION,
        },
        "body": {
            "mass_kg": mass, "principal_inertia_kg_m2": [float(x) for x in principal],
            "smooth_rounded_tablet_mass_kg": rounded[0],
            "smooth_rounded_tablet_inertia_transverse_axial": [rounded[1], rounded[2]],
            "ideal_tablet_mass_kg_integrated": ideal[0],
            "ideal_tablet_inertia_transverse_axial_integrated": [ideal[1], ideal[2]],
            "ideal_tablet_mass_kg_digest": DIGEST_IDEAL_MASS,
            "ideal_tablet_inertia_transverse_digest": DIGEST_IDEAL_INERTIA,
            "mass_error_against_smooth_rounded": mass / rounded[0] - 1,
            "mass_error_against_ideal": mass / DIGEST_IDEAL_MASS - 1,
            "engine_frame_turn_about_axis_degrees": turn_about_axis,
            "engine_frame_axis_tilt_degrees": math.degrees(math.acos(min(1.0, abs(axis_body[2])))),
            "mesh_origin_in_body_frame_m": [float(x) for x in origin],
            "placement_fit_residual_m": float(fit_residual),
            "vertices_numbered_otherwise_by_the_engine": renumbered,
            "placement_spread_between_bodies": float(same_placement),
        },
        "contacts": {"first_s": first, "last_s": last, "run_end_s": t_end,
                     "touched_again_within_run": touched_again, "most_at_once": most_contacts,
                     "earliest_second_contact_after_end_ms":
                         min(r["second_contact_after_end_ms"] for r in rows)},
        "rows": rows,
    }
    os.makedirs(out_dir, exist_ok=True)
    write_json(os.path.join(out_dir, "result.json"), result)
    plot(os.path.join(out_dir, "tablet_impact.png"), rows, grid, model_curve, mass, i_t)
    print(f"tablet_impact: max_rel_error {result['max_rel_error']:.2e} (above 22 deg; smooth core "
          f"{result['max_rel_error_smooth_core_above_22deg']:.2e}), max |w| below 22 deg "
          f"{result['max_abs_spin_below_22deg']:.1f} rad/s, max |energy error| "
          f"{result['max_abs_energy_error']:.1e}; engine frame turned "
          f"{turn_about_axis:.3f} deg about the axis")


def write_json(path, value):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(value, f, indent=2, default=lambda x: None if x == math.inf else x)
        f.write("\n")
    os.replace(tmp, path)


def plot(path, rows, grid, model_curve, mass, inertia):
    deg = np.degrees(grid)
    ideal = [rebound(DIGEST_IDEAL_MASS, DIGEST_IDEAL_INERTIA, book_arm(t)) for t in grid]
    smooth = [rebound(mass, inertia, smooth_core_arm(t)) for t in grid]
    theta = [r["theta_degrees"] for r in rows]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, k, key, label in ((axes[0], 0, "w_z_plus", r"$\omega_z^+$ (rad/s)"),
                              (axes[1], 1, "v_y_plus", r"$v_y^+$ (m/s)")):
        ax.plot(deg, [c[k] for c in model_curve], "-", color="C0", lw=1.2,
                label="Eqs. 4.25-4.26, this body (its lowest core vertex)")
        ax.plot(deg, [c[k] for c in smooth], "--", color="C2", lw=0.9,
                label="Eqs. 4.25-4.26, this body, smooth core")
        ax.plot(deg, [c[k] for c in ideal], ":", color="k", lw=1.2,
                label="Eqs. 4.25-4.27, ideal tablet (book)")
        ax.plot(theta, [r[key] for r in rows], "o", color="C3", ms=5, label="kdem")
        ax.set_xlabel(r"impact angle $\theta$ (degrees, axis to plane)")
        ax.set_ylabel(label)
        ax.set_xticks(range(0, 91, 10))
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=7)
    fig.suptitle("Tablet (dilated polyhedron, r = 1 mm) on a frictionless plane, elastic, 1 m/s")
    fig.tight_layout()
    tmp = path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, path)


if __name__ == "__main__":
    main()
