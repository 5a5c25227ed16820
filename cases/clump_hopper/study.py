#!/usr/bin/env python3
"""The book's multi-superquadric hopper discharge (Sect. 3.3.2, Figs. 3.13-3.16): spheres,
cylinders, spherocylinders and concave clumps of equal volume (volume-equivalent diameter
D0 = 5 mm) poured into the 75 mm square hopper with a 30 mm orifice and walls 30 degrees from
the horizontal, then discharged into the 225 x 225 x 75 mm container below. See README.md.

usage: study.py scenes|run|analyse OUT_DIR [--jobs 2]
"""
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "square_hopper"))
import hopper_study as hs  # noqa: E402

TITLE = "book 3.3.2: hopper discharge of multi-superquadric clumps"
PLOT = "clump_hopper.png"
D0 = 0.005  # m, volume-equivalent diameter of every shape (book: D0 = 5 mm)
COUNT = 1000  # book: 4000 (see README.md: fewer, for the run time here)
TIME_STEP = 2.0e-5
DISCHARGE_TIME = 2.0  # s after the gate opens
ROD_BLOCKINESS = (8, 2)  # cylinder-like rods (the book's element exponents are in the figure only)
ROD_LENGTH_TO_DIAMETER = 3.0  # book: L:D = 3:1
HOPPER = hs.Hopper(top_half=0.0375, orifice_half=0.015, angle_degrees=30.0, bin_height=0.15)

TURN_X_TO_Z = (math.sqrt(0.5), 0.0, math.sqrt(0.5), 0.0)  # element axis z turned onto x
TURN_Y_TO_Z = (math.sqrt(0.5), -math.sqrt(0.5), 0.0, 0.0)  # element axis z turned onto y


def rod(position, orientation=None, half_length=ROD_LENGTH_TO_DIAMETER,
        blockiness=ROD_BLOCKINESS):
    """A cylinder-like superquadric element of unit radius (L:D = 3:1 unless `half_length`
    says otherwise), axis z unless turned."""
    return {"kind": "superquadric", "position": position, "orientation": orientation,
            "half_axes": (1.0, 1.0, half_length), "blockiness": blockiness}


def ball(position, radius=1.0):
    return {"kind": "sphere", "position": position, "radius": radius}


def element_bound(element, centre=(0.0, 0.0, 0.0)):
    """An upper bound of the distance from `centre` to the element's farthest point."""
    distance = math.sqrt(sum((p - c) ** 2 for p, c in zip(element["position"], centre)))
    if element["kind"] == "sphere":
        return distance + element["radius"]
    a, b, c = element["half_axes"]
    return distance + math.sqrt(max(a, b) ** 2 + c ** 2)


def element_volume(element):
    if element["kind"] == "sphere":
        return hs.sphere_volume(2 * element["radius"])
    return hs.superquadric_volume(element["half_axes"], element["blockiness"])


def element_lines(element):
    if element["kind"] == "sphere":
        lines = [f"- sphere: {{radius: {element['radius']:.9g}}}"]
    else:
        lines = [f"- superquadric: {{half_axes: {hs.fmt(element['half_axes'])}, "
                 f"blockiness: {hs.fmt(element['blockiness'])}}}"]
    lines.append(f"  position: {hs.fmt(element['position'])}")
    if element.get("orientation"):
        lines.append(f"  orientation: {hs.fmt(element['orientation'])}")
    return lines


def clump_shape(name, label, elements):
    """A clump scaled by kdem to D0 (`equivalent_diameter`); its bounding radius here from
    the elements' summed volume, which is at least the union's, so the scale (and the bound)
    is grown by the largest overlap share of these clumps (the jack's, 17 %) to stay above,
    about the elements' volume-weighted centre (the centroid, overlaps aside)."""
    volumes = [element_volume(e) for e in elements]
    scale = (hs.sphere_volume(D0) / sum(volumes) / 0.83) ** (1 / 3)
    centre = [sum(v * e["position"][k] for v, e in zip(volumes, elements)) / sum(volumes)
              for k in range(3)]
    lines = [f"- name: {name}", "  clump:", "    elements:"]
    for element in elements:
        lines += ["      " + line for line in element_lines(element)]
    lines.append(f"    equivalent_diameter: {D0}")
    bound = max(element_bound(e, centre) for e in elements)
    return hs.Shape(name, label, lines, scale * bound, D0)


def cylinder_shape():
    """One cylinder-like superquadric of L:D = 3:1 scaled to D0 in closed form."""
    unit = rod((0, 0, 0))
    r = (hs.sphere_volume(D0) / element_volume(unit)) ** (1 / 3)
    half_axes = [r * x for x in unit["half_axes"]]
    lines = ["- name: cylinder", f"  superquadric: {{half_axes: {hs.fmt(half_axes)}, "
             f"blockiness: {hs.fmt(ROD_BLOCKINESS)}}}"]
    return hs.Shape("cylinder", "cylinder", lines, r * element_bound(unit), D0)


def shapes():
    h = ROD_LENGTH_TO_DIAMETER - 1.0  # a spherocylinder's cylinder half-length, L:D = 3:1
    arm = ROD_LENGTH_TO_DIAMETER - 1.0  # an L's rods end flush at the corner
    return [
        hs.Shape("sphere", "sphere", [], D0 / 2, D0, sphere=True),
        cylinder_shape(),
        clump_shape("spherocylinder", "spherocylinder",
                    [rod((0, 0, 0), half_length=h, blockiness=(10, 2)),
                     ball((0, 0, h)), ball((0, 0, -h))]),
        clump_shape("ell", "L (2 rods)",
                    [rod((arm, 0, 0), TURN_X_TO_Z), rod((0, arm, 0), TURN_Y_TO_Z)]),
        clump_shape("cross", "cross (2 rods)", [rod((0, 0, 0), TURN_X_TO_Z),
                                                  rod((0, 0, 0), TURN_Y_TO_Z)]),
        clump_shape("jack", "jack (3 rods)", [rod((0, 0, 0), TURN_X_TO_Z),
                                                rod((0, 0, 0), TURN_Y_TO_Z), rod((0, 0, 0))]),
    ]


CONCAVE = ["ell", "cross", "jack"]  # in order of shape complexity (arms: 2, 4, 6)


def claims(records):
    """The book's ranking (Fig. 3.16 and its text), each checked on the measured figures. A
    figure not measured (no heap where an arch stopped the flow) is left out of the comparisons
    and listed with every claim as `not_measured`."""
    by = {r["shape"]: r for r in records}
    if not all(name in by for name in ["sphere", "cylinder", "spherocylinder"] + CONCAVE):
        return []
    rate = {k: r["mean_rate_kg_per_s"] for k, r in by.items()}
    angle = {k: r["angle_of_repose_degrees"] for k, r in by.items()}
    stalled = {k: r["stalled_interval_share"] for k, r in by.items()}
    left = {k: 1.0 - r["discharged_fraction"] for k, r in by.items()}
    others = [k for k in by if k != "sphere"]
    convex = ["cylinder", "spherocylinder"]
    figures = {"mean_rate_kg_per_s": rate, "angle_of_repose_degrees": angle}
    unmeasured = sorted(k for k in by if math.isnan(angle[k]) or math.isnan(rate[k]))

    def below(low, high):
        """Every pair measured is in order (at least one pair is); a pair with a figure not
        measured is left out and named in the claim."""
        measured = [(x, y) for x, y in zip(low, high) if not (math.isnan(x) or math.isnan(y))]
        return bool(measured) and all(x < y for x, y in measured)

    def flow_interrupted(k):  # stalls, or an arch stopped it with half the bed in the hopper
        return stalled[k] > max(stalled["sphere"], stalled["spherocylinder"]) or left[k] > 0.5

    found = [
        hs.claim("spheres flow fastest", below([rate[k] for k in others],
                                               [rate["sphere"]] * len(others)),
                 mean_rate_kg_per_s=rate),
        hs.claim("spheres have the smallest angle of repose",
                 below([angle["sphere"]] * len(others), [angle[k] for k in others]),
                 angle_of_repose_degrees=angle),
        hs.claim("cylinders and spherocylinders flow faster than the concave clumps",
                 below([max(rate[k] for k in CONCAVE)], [min(rate[k] for k in convex)]),
                 **figures),
        hs.claim("cylinders and spherocylinders have smaller angles than the concave clumps",
                 below([max(angle[k] for k in convex)] * 3, [angle[k] for k in CONCAVE]),
                 **figures),
        hs.claim("spherocylinders flow faster than cylinders",
                 below([rate["cylinder"]], [rate["spherocylinder"]]), mean_rate_kg_per_s=rate),
        hs.claim("spherocylinders have a smaller angle than cylinders",
                 below([angle["spherocylinder"]], [angle["cylinder"]]),
                 angle_of_repose_degrees=angle),
        hs.claim("the concave clumps flow slower with shape complexity (L, cross, jack)",
                 below([rate["cross"], rate["jack"]], [rate["ell"], rate["cross"]]),
                 mean_rate_kg_per_s=rate),
        hs.claim("the concave clumps' angle of repose grows with shape complexity",
                 below([angle["ell"], angle["cross"]], [angle["cross"], angle["jack"]]),
                 angle_of_repose_degrees=angle),
        hs.claim("spheres and spherocylinders flow continuously, concave clumps intermittently "
                 "(more checkpoint intervals without discharge than either, or stopped by an "
                 "arch with more than half the bed left)",
                 all(flow_interrupted(k) for k in CONCAVE), stalled_interval_share=stalled,
                 mass_share_left=left),
    ]
    for c in found:
        c["not_measured"] = unmeasured
    return found


def plot(records, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    order = [s.name for s in shapes()]
    records = sorted(records, key=lambda r: order.index(r["shape"]))
    fig, (left, middle, right) = plt.subplots(1, 3, figsize=(16, 4.6))
    hs.plot_discharge(left, records)
    left.legend(fontsize=8)
    left.set_title("discharge (%d particles, D0 = 5 mm)" % records[0]["count"])
    names = [r["label"] for r in records]
    middle.bar(range(len(records)), [1e3 * r["mean_rate_kg_per_s"] for r in records],
               color="tab:blue")
    middle.set_xticks(range(len(records)), names, rotation=30, ha="right", fontsize=8)
    middle.set_ylabel("mean rate over the first %g s (g/s)" % hs.MEAN_RATE_TIME)
    twin = middle.twinx()
    twin.errorbar(range(len(records)), [r["angle_of_repose_degrees"] for r in records],
                  yerr=[r.get("angle_standard_error_degrees", 0) for r in records], fmt="o",
                  color="tab:red")
    twin.set_ylabel("angle of repose (degrees)", color="tab:red")
    twin.set_ylim(bottom=0)
    middle.set_title("rate (bars) and angle of repose (dots)")
    hs.plot_heaps(right, records)
    right.legend(fontsize=7)
    right.set_title("heaps in the container")
    fig.tight_layout()
    fig.savefig(path + ".tmp.png", dpi=110)
    os.replace(path + ".tmp.png", path)


# The clumps first: the longest runs start first when two run at once.
CASES = [hs.Case(s.name, s, HOPPER, COUNT, DISCHARGE_TIME) for s in shapes()[::-1]]

if __name__ == "__main__":
    hs.main(sys.modules[__name__])
