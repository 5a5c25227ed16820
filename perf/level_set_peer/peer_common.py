"""What the kdem side of the level-set peer comparison shares (impact.py, packing.py): the two
superquadrics (kdem_bench_level_set_accuracy's, scaled to a = 10 mm), random rotations, scene
entries, kdem checkpoints."""
import json
import math
import os

import h5py
import numpy as np

SHAPES = {  # name: half-axes (m), n1 (along z), n2 (xy section): the bench's two, a = 10 mm
    "ellipsoid": ((10e-3, 7e-3, 5e-3), 2.0, 2.0),
    "blocky": ((10e-3, 8e-3, 6e-3), 4.0, 4.0)}

BENCH_SCALE = 10e-3  # the bench's shapes have a = 1


def random_rotation(rng):
    """Uniform: a normalised 4-d Gaussian quaternion."""
    q = rng.normal(size=4)
    return rotation_of(q / np.linalg.norm(q))


def quaternion(r):
    """[w, x, y, z] of a rotation matrix (Shepperd)."""
    t = np.trace(r)
    if t > 0:
        s = 2 * math.sqrt(1 + t)
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0] * 4
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = s / 4
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    return q


def shape_entry(name, family):
    (a, b, c), n1, n2 = SHAPES[name]
    if family == "level_set":
        return (f"  - name: {name}\n    level_set: {{superquadric: {{a: {a}, b: {b}, c: {c}, "
                f"n1: {n1}, n2: {n2}}}}}\n")
    return (f"  - name: {name}\n    superquadric: {{half_axes: [{a}, {b}, {c}], "
            f"blockiness: [{n1}, {n2}]}}\n")


def source_entry(body, half):
    lo = ", ".join(f"{v - half:.12g}" for v in body["centre"])
    hi = ", ".join(f"{v + half:.12g}" for v in body["centre"])
    q = ", ".join(f"{v:.17g}" for v in quaternion(body["rotation"]))
    v = ", ".join(f"{v:.17g}" for v in body["velocity"])
    return (f"  - name: {body['name']}\n    material: grains\n    shape: {body['shape']}\n"
            f"    orientation: [{q}]\n    velocity: [{v}]\n    count: 1\n"
            f"    region: {{box: {{min: [{lo}], max: [{hi}]}}}}\n")


def write(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def checkpoint_bodies(path):
    """Per source name: the body's fields from a kdem checkpoint."""
    with h5py.File(path, "r") as f:
        names = f["source_names"][()].decode().split()
        fields = {k: f["particles/" + k][...] for k in
                  ("position", "velocity", "angular_velocity", "mass", "inertia", "orientation",
                   "radius")}
        return {names[s]: {k: v[i] for k, v in fields.items()}
                for i, s in enumerate(f["particles/source"][:, 0])}


def rotation_of(q):
    """The matrix of the unit quaternion [w, x, y, z]."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def read_radii(folder, prefix, scenes, target):
    """The engine's bounding radius per scene and shape, from the one-step runs'
    checkpoints (FOLDER/PREFIX_SCENE/checkpoint.h5), as JSON."""
    radii = {}
    for scene in scenes:
        found = checkpoint_bodies(os.path.join(folder, f"{prefix}_{scene}", "checkpoint.h5"))
        radii[scene] = {name: max(float(b["radius"][0]) for n, b in found.items()
                                  if n.startswith(name + "_")) for name in SHAPES}
    write(target, json.dumps(radii, indent=1))


def kinetic_energy(body):
    """Translational and rotational (the inertia is principal, the spin in the world frame)."""
    m = float(np.ravel(body["mass"])[0])
    v = np.asarray(body["velocity"])
    turn = (np.reshape(body["rotation"], (3, 3)) if "rotation" in body
            else rotation_of(body["orientation"]))
    w_body = turn.T @ np.asarray(body["angular_velocity"])
    return 0.5 * m * v @ v, 0.5 * w_body @ (np.asarray(body["inertia"]) * w_body)


def case_for_yade(bodies, **settings):
    """What the Yade scripts read: the settings, the shapes, and every body (its rotation as 9
    numbers, row by row)."""
    return dict(settings,
                shapes={name: {"half_axes": list(axes), "n1": n1, "n2": n2}
                        for name, (axes, n1, n2) in SHAPES.items()},
                bodies=[dict(b, rotation=[float(x) for x in b["rotation"].flatten()])
                        for b in bodies])


def write_scenes(folder, prefix, scene_names, scene_text, yade_case, radii_path):
    """Writes FOLDER/PREFIX_<scene>.yaml per scene and, once the radii are known (RADII.json),
    FOLDER/PREFIX_case.json for Yade."""
    radii = None
    if radii_path:
        with open(radii_path) as f:
            radii = json.load(f)
    os.makedirs(folder, exist_ok=True)
    for scene in scene_names:
        write(os.path.join(folder, f"{prefix}_{scene}.yaml"), scene_text(scene, radii))
    if radii:
        write(os.path.join(folder, f"{prefix}_case.json"), json.dumps(yade_case(radii), indent=1))
