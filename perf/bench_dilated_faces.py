"""Cost per particle-step of dilated polyhedra against their core's face count (issue: dilated
polyhedra, item 7). For each node count M of the builders' superquadric lattice (2M - 4 faces),
a bed of ellipsoid-like dilated polyhedra (core half-axes 1.8, 1.2, 0.8 mm, dilation 0.2 mm) is
poured into a box and settled (`--settle` seconds), then restarted from its checkpoint and run
`--steps` steps: the settled part alone is timed (median of `--repeat` restarts, one thread).
Spheres of the same volume-equivalent radius in the same box are the reference.

usage: bench_dilated_faces.py [--kdem PATH] [--count N] [--nodes 50,200,...] [--steps S]
                              [--repeat R] [--settle T] [--out FILE.json] [--reuse]
                              [--settle-only]
Writes the JSON (atomically) and a plot beside it. --reuse: a node count whose settling and
timed runs are all in the work folder already is read from there instead of run again (to
gather a series run in parts). --settle-only: settle the beds and stop (settling is not timed, so
beds may settle side by side; the timed restarts then run alone with --reuse)."""
import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

BOX = 0.015  # m, half-width of the box's floor
DILATION = 0.2e-3
CORE = (1.8e-3, 1.2e-3, 0.8e-3)
TIME_STEP = 4e-6  # about 1/100 of the Hertz contact time at 1 m/s


def scene(shape_entry, count, duration, directory):
    return f"""time_step: {TIME_STEP}
duration: {duration}
domain: {{min: [{-BOX}, {-BOX}, -0.001], max: [{BOX}, {BOX}, 0.06]}}
materials:
  - {{name: grains, density: 2500, youngs_modulus: 1.0e8, poisson_ratio: 0.3, restitution: 0.3,
     friction: 0.4}}
{shape_entry}
particles:
  - name: bed
    material: grains
{'    shape: grain' if shape_entry else '    size: {radius: 0.00122}'}
    region: {{box: {{min: [{-BOX + 0.0025}, {-BOX + 0.0025}, 0.003], max: [{BOX - 0.0025}, {BOX - 0.0025}, 0.055]}}}}
    count: {count}
    velocity: [0, 0, -0.5]
    seed: 5
walls:
  - {{name: floor, material: grains, plane: {{point: [0, 0, 0], normal: [0, 0, 1]}}}}
  - {{name: x0, material: grains, plane: {{point: [{-BOX}, 0, 0], normal: [1, 0, 0]}}}}
  - {{name: x1, material: grains, plane: {{point: [{BOX}, 0, 0], normal: [-1, 0, 0]}}}}
  - {{name: y0, material: grains, plane: {{point: [0, {-BOX}, 0], normal: [0, 1, 0]}}}}
  - {{name: y1, material: grains, plane: {{point: [0, {BOX}, 0], normal: [0, -1, 0]}}}}
output:
  directory: {directory}
"""


def shape_entry(nodes):
    if nodes == 0:
        return ""
    a, b, c = CORE
    return (f"shapes:\n  - name: grain\n    dilated_polyhedron: {{superquadric: {{a: {a}, b: {b}, "
            f"c: {c}, n1: 2, n2: 2}}, nodes: {nodes}, dilation_radius: {DILATION}}}")


def run(kdem, scene_path, out, extra=(), reuse=False):
    done = os.path.join(out, "run.json")
    if reuse and os.path.exists(done):
        with open(done) as f:
            return json.load(f)
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    subprocess.run([kdem, "run", scene_path, "--out", out, "--quiet", *extra], check=True, env=env)
    with open(os.path.join(out, "run.json")) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--kdem", default=os.path.join(ROOT, "build/openmp/bin/kdem"))
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--nodes", default="0,50,100,200,500,1000,2000,5000")
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--settle", type=float, default=0.12)
    parser.add_argument("--out", default=os.path.join(ROOT, "perf/results/dilated_faces.json"))
    parser.add_argument("--work", default=os.path.join(ROOT, "out/bench_dilated_faces"))
    parser.add_argument("--reuse", action="store_true")
    parser.add_argument("--settle-only", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    rows = []
    for nodes in [int(n) for n in args.nodes.split(",")]:
        name = f"nodes_{nodes}" if nodes else "spheres"
        path = os.path.join(args.work, name + ".yaml")
        with open(path, "w") as f:
            f.write(scene(shape_entry(nodes), args.count, args.settle, os.path.join(args.work, name)))
        settled = run(args.kdem, path, os.path.join(args.work, name, "settle"), reuse=args.reuse)
        if args.settle_only:
            continue
        checkpoint = os.path.join(args.work, name, "settle", "checkpoint.h5")
        # The same scene, its duration `--steps` steps longer: the restart runs those.
        timed_path = os.path.join(args.work, name + "_timed.yaml")
        with open(timed_path, "w") as f:
            f.write(scene(shape_entry(nodes), args.count,
                          args.settle + (args.steps + 0.5) * TIME_STEP,
                          os.path.join(args.work, name)))
        rates = []
        for r in range(args.repeat):
            timed = run(args.kdem, timed_path, os.path.join(args.work, name, f"timed_{r}"),
                        ("--restart", checkpoint), reuse=args.reuse)
            rates.append(timed["particle_steps_per_second"])
        rate = statistics.median(rates)
        rows.append({"nodes": nodes, "faces": 2 * nodes - 4 if nodes else 0,
                     "particles": timed["particles"],
                     "microseconds_per_particle_step": 1e6 / rate,
                     "particle_steps_per_second_runs": rates,
                     "pair_contacts": timed["extra"].get("pair_contacts"),
                     "settle_wall_seconds": settled["wall_seconds"],
                     "git_hash": timed["git_hash"]})
        print(f"{name}: {1e6 / rate:.2f} us per particle-step, {timed['extra'].get('pair_contacts')}"
              " pair contacts", file=sys.stderr)
    if args.settle_only:
        return
    result = {"benchmark": "dilated_faces", "count": args.count, "steps": args.steps,
              "repeat": args.repeat, "settle_seconds": args.settle, "threads": 1, "runs": rows}
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(result, f, indent=1)
    os.replace(tmp, args.out)
    plot(result, os.path.splitext(args.out)[0] + ".png")
    print("wrote", args.out)


def plot(result, target):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = [r for r in result["runs"] if r["nodes"]]
    spheres = [r for r in result["runs"] if not r["nodes"]]
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.loglog([r["faces"] for r in runs], [r["microseconds_per_particle_step"] for r in runs], "o-",
              label="dilated polyhedra (ellipsoid lattice)")
    for r in spheres:
        ax.axhline(r["microseconds_per_particle_step"], color="k", ls="--", lw=0.8,
                   label="spheres, same bed")
    ax.set_xlabel("core faces")
    ax.set_ylabel("microseconds per particle-step (one thread)")
    ax.set_title(f"Settled bed of {result['count']} particles", fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(target, dpi=120)


if __name__ == "__main__":
    main()
