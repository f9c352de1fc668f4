#!/usr/bin/python3
"""Side-by-side granular benchmark: ringdem, LAMMPS (GRANULAR) and LIGGGHTS on the same beds.

Called by scripts/bench/peer_granular.sh, which installs the packages and builds ringdem.
Each (variant, size) is run by every code in turn, `repeats` times interleaved, on one rank.
Each code's own loop time is read from its output (ringdem: the loop's particle-step rate in
summary.json; LAMMPS and LIGGGHTS: "Loop time of"), set-up excluded; peak resident memory of
the whole process from /usr/bin/time. Medians are printed.

Variants (issue 12, docs/performance.md):
  bed   resting bed: spheres of 5 mm on a jittered 10.5 mm lattice above a floor plane
  poly  polydisperse bed: radii 5-25 mm (uniform), stacked in columns on a 50.5 mm grid, plus
        one 0.4 m boulder on top (ringdem reads it from a CSV sphere file, a share of the
        lines per rank; LAMMPS from a data file)
  flow  a block (10.1 mm lattice) moving at 1 m/s down a 35 degree incline (gravity tilted
        over the floor plane). Its grains do not touch within its 500 steps (the block falls and
        slides as one, 1 mm above the floor): it measures the candidate pairs, not contacts
  dense a packing in contact: 5 mm spheres on a 9.98 mm simple cubic lattice (every grain
        pressed 20 um into each of its 6 neighbours and the bottom layer 10 um into the floor),
        jittered by up to 5 um, moving at 1 m/s down the 35 degree incline. Every grain has
        about 6 touching contacts every step; the surfaces spring off, the jitter's unbalanced
        forces make the interior rattle, the floor's friction shears the bottom. Both codes read
        the same positions (a CSV sphere file, a LAMMPS data file)
  mixed the dense packing with its grains listed in random order, as a flow that has sheared
        for a while leaves them: the same physics, but neighbours in space are far apart in the
        input order (ringdem keeps its grains in the order they were made; LAMMPS sorts its
        atoms by space as it goes)
Rock: E = 1 GPa, nu = 0.25, e = 0.3, mu = 0.5, 2600 kg/m^3, Hertz-Mindlin, dt = 1.31e-5 s.

Codes: ringdem (with its energy ledger, the default), ringdem_noledger (the same case with
`simulation.energy_ledger: false`: no dissipation booked, as the peers book none), lammps,
liggghts.
"""
import argparse
import json
import math
import os
import random
import re
import statistics
import subprocess
import sys
import tempfile

E, NU, REST, MU, RHO, DT = 1.0e9, 0.25, 0.3, 0.5, 2600.0, 1.31e-5
STEPS = {"bed": 153, "poly": 153, "flow": 500, "dense": 500, "mixed": 500}
PACKINGS = ("dense", "mixed")  # the packings in contact
SLOPE = math.radians(35.0)


def lattice_counts(variant, n):
    """Lattice counts (nx, ny, nz) for about n grains."""
    if variant in ("flow",) + PACKINGS:  # a long, shallow block: 25 x 4 x 1 in shape
        k = round((n / 100.0) ** (1.0 / 3.0))
        return (25 * k, 4 * k, k)
    side = round(math.sqrt(n / 10.0)) if n <= 2e5 else round(n ** (1.0 / 3.0))
    return (side, side, max(1, round(n / side / side)))


def gravity(variant):
    if variant in ("flow",) + PACKINGS:
        return (9.81 * math.sin(SLOPE), 0.0, -9.81 * math.cos(SLOPE))
    return (0.0, 0.0, -9.81)


def lattice_spec(variant, n):
    nx, ny, nz = lattice_counts(variant, n)
    spacing = 0.0101 if variant == "flow" else 0.0105
    jitter = 0.9 if variant == "flow" else 0.5
    velocity = (1.0, 0.0, 0.0) if variant == "flow" else (0.0, 0.0, 0.0)
    return dict(nx=nx, ny=ny, nz=nz, spacing=spacing, radius=0.005, jitter=jitter,
                velocity=velocity, origin=(0.0, 0.0, 0.006))


def poly_spheres(n, seed=7):
    """Polydisperse grains in columns on a 50.5 mm square grid, each column a stack with 0.2 mm
    gaps (a bed with neighbours, like the monodisperse one), plus one 0.4 m boulder on top."""
    side = round(math.sqrt(n / 10.0))
    nz = max(1, round(n / side / side))
    pitch, gap = 0.0505, 0.0002
    rng = random.Random(seed)
    out = []
    top = 0.0
    for i in range(side):
        for j in range(side):
            z = 0.0
            for _ in range(nz):
                r = rng.uniform(0.005, 0.025)
                slack = 0.5 * pitch - r
                z += gap + r
                out.append((i * pitch + rng.uniform(-0.2, 0.2) * slack,
                            j * pitch + rng.uniform(-0.2, 0.2) * slack, z, r))
                z += r
            top = max(top, z)
    centre = 0.5 * (side - 1) * pitch
    out.append((centre, centre, top + 0.4 + 0.01, 0.4))
    return out


DENSE_SPACING, DENSE_JITTER, DENSE_FLOOR_OVERLAP = 0.00998, 5e-6, 1e-5


def dense_spheres(n, seed=11):
    """The dense variant: radius 5 mm on a simple cubic lattice closer than a diameter, each
    coordinate jittered uniformly by up to DENSE_JITTER; the bottom layer overlaps the floor."""
    nx, ny, nz = lattice_counts("dense", n)
    rng = random.Random(seed)
    a, j, r = DENSE_SPACING, DENSE_JITTER, 0.005
    z0 = r - DENSE_FLOOR_OVERLAP
    out = []
    for k in range(nz):
        for jy in range(ny):
            for i in range(nx):
                out.append((i * a + rng.uniform(-j, j), jy * a + rng.uniform(-j, j),
                            z0 + k * a + (rng.uniform(-j, j) if k else 0.0), r))
    return out


def file_spheres(variant, n):
    if variant == "poly":
        return poly_spheres(n)
    spheres = dense_spheres(n)
    if variant == "mixed":
        random.Random(13).shuffle(spheres)
    return spheres


def write_ringdem(work, variant, n, ledger=True):
    g = gravity(variant)
    lines = [
        "schema_version: 1", f"name: peer_{variant}",
        f"simulation: {{dt: {DT}, end_time: {STEPS[variant] * DT * (1 - 1e-6)}, "
        f"gravity: [{g[0]!r}, {g[1]!r}, {g[2]!r}], skin: 0.001"
        f"{'' if ledger else ', energy_ledger: false'}"
        f"{', allow_initial_overlap: true' if variant in PACKINGS else ''}}}",
        "output: {frame_interval: 0, checkpoint_interval: 0}",
        "materials:",
        f"  - {{name: rock, density: {RHO}, youngs_modulus: {E}, poisson_ratio: {NU}, "
        f"restitution: {REST}, friction: {MU}}}",
        "particles:"]
    if variant in ("poly",) + PACKINGS:
        # A sphere file beside the case: each rank reads its share of the lines.
        spheres = os.path.join(work, f"{variant}_{n}.csv")
        if not os.path.exists(spheres):
            with open(spheres, "w") as f:
                f.write("x,y,z,radius\n")
                for x, y, z, r in file_spheres(variant, n):
                    f.write(f"{x:.9f},{y:.9f},{z:.9f},{r:.6f}\n")
        velocity = ", velocity: [1.0, 0.0, 0.0]" if variant in PACKINGS else ""
        lines += ["  sphere_files:",
                  f"    - {{path: {os.path.basename(spheres)}, material: rock{velocity}}}"]
    else:
        s = lattice_spec(variant, n)
        v = s["velocity"]
        lines += ["  lattices:",
                  f"    - {{material: rock, origin: [0, 0, {s['origin'][2]}], "
                  f"count: [{s['nx']}, {s['ny']}, {s['nz']}], spacing: {s['spacing']}, "
                  f"particle_radius: {s['radius']}, jitter: {s['jitter']}, seed: 3, "
                  f"velocity: [{v[0]}, {v[1]}, {v[2]}]}}"]
    lines += ["rigid_bodies:",
              "  - {name: floor, shape: plane, position: [0, 0, 0], normal: [0, 0, 1], "
              "material: rock, motion: fixed}"]
    path = os.path.join(work, f"{variant}_{n}{'' if ledger else '_noledger'}.yaml")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def write_lammps_data(work, variant, n):
    spheres = file_spheres(variant, n)
    # Each axis's extent with a margin (a square box over a long block would give LAMMPS
    # millions of empty bins).
    lo = [min(s[c] - s[3] for s in spheres) - 0.05 for c in (0, 1)]
    hi = [max(s[c] + s[3] for s in spheres) + 0.05 for c in (0, 1)]
    top = max(s[2] + s[3] for s in spheres) + 0.05
    path = os.path.join(work, f"{variant}_{n}.data")
    with open(path, "w") as f:
        f.write(f"peer {variant}\n\n{len(spheres)} atoms\n1 atom types\n\n")
        f.write(f"{lo[0]} {hi[0]} xlo xhi\n{lo[1]} {hi[1]} ylo yhi\n-0.01 {top} zlo zhi\n\n"
                "Atoms # sphere\n\n")
        for k, (x, y, z, r) in enumerate(spheres, 1):
            f.write(f"{k} 1 {2 * r:.6f} {RHO} {x:.9f} {y:.9f} {z:.9f}\n")
    return path


def box_and_atoms(work, variant, n, liggghts):
    """Input lines that make the grains (LAMMPS and LIGGGHTS share them)."""
    if variant == "poly":
        return [f"read_data {write_lammps_data(work, variant, n)}"]
    if variant in PACKINGS:
        return [f"read_data {write_lammps_data(work, variant, n)}",
                "velocity all set 1.0 0.0 0.0 units box"]
    s = lattice_spec(variant, n)
    a = s["spacing"]
    length = (s["nx"] - 1) * a
    extra_x = 3.0 if variant == "flow" else 0.05  # room to flow downhill
    box = (f"region box block -0.05 {length + extra_x} -0.05 {(s['ny'] - 1) * a + 0.05} "
           f"-0.01 {s['origin'][2] + s['nz'] * a + 0.05} units box")
    # Lattice sites at origin + (i, j, k) a, as ringdem's; the region picks exactly the counts.
    region = (f"region grains block {-0.5 * a} {(s['nx'] - 0.5) * a} {-0.5 * a} "
              f"{(s['ny'] - 0.5) * a} {s['origin'][2] - 0.5 * a} "
              f"{s['origin'][2] + (s['nz'] - 0.5) * a} units box")
    lines = [box, "create_box 1 box", region,
             f"lattice sc {a} origin 0 0 {s['origin'][2] / a % 1.0}",
             "create_atoms 1 region grains",
             "set group all density 2600 diameter 0.01" if liggghts else
             "set type 1 diameter 0.01\nset type 1 density 2600"]
    # LIGGGHTS 3.8 aborts on displace_atoms random: its lattice stays unjittered.
    if not liggghts:
        d = 0.5 * s["jitter"] * (a - 2 * s["radius"])
        lines.append(f"displace_atoms all random {d} {d} {d} 3 units box")
    v = s["velocity"]
    if any(v):
        lines.append(f"velocity all set {v[0]} {v[1]} {v[2]} units box")
    return lines


def write_lammps(work, variant, n):
    g = gravity(variant)
    gn = math.sqrt(sum(c * c for c in g))
    model = f"hertz/material {E} {REST} {NU} tangential mindlin NULL 1.0 {MU} damping tsuji"
    lines = ["units si", "atom_style sphere", "atom_modify map array", "boundary f f f",
             "comm_modify vel yes", "newton off"]
    lines += box_and_atoms(work, variant, n, liggghts=False)
    lines += ["pair_style granular", f"pair_coeff * * {model}",
              f"fix floor all wall/gran granular {model} zplane 0.0 NULL",
              "fix integrate all nve/sphere",
              f"fix grav all gravity {gn} vector {g[0] / gn} {g[1] / gn} {g[2] / gn}",
              "neighbor 0.001 bin", "neigh_modify delay 0 every 1 check yes",
              f"timestep {DT}", "thermo 100", f"run {STEPS[variant]}"]
    path = os.path.join(work, f"{variant}_{n}.lmp")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def write_liggghts(work, variant, n):
    g = gravity(variant)
    gn = math.sqrt(sum(c * c for c in g))
    lines = ["atom_style granular", "atom_modify map array", "boundary f f f", "newton off",
             "communicate single vel yes", "units si"]
    atoms = box_and_atoms(work, variant, n, liggghts=True)
    lines += atoms[:2]  # the box first: the material properties need it
    lines += ["neighbor 0.001 bin", "neigh_modify delay 0",
              f"fix m1 all property/global youngsModulus peratomtype {E}",
              f"fix m2 all property/global poissonsRatio peratomtype {NU}",
              f"fix m3 all property/global coefficientRestitution peratomtypepair 1 {REST}",
              f"fix m4 all property/global coefficientFriction peratomtypepair 1 {MU}",
              "pair_style gran model hertz tangential history", "pair_coeff * *",
              f"timestep {DT}",
              f"fix grav all gravity {gn} vector {g[0] / gn} {g[1] / gn} {g[2] / gn}",
              "fix floor all wall/gran model hertz tangential history primitive type 1 "
              "zplane 0.0"]
    lines += atoms[2:]
    lines += ["fix integr all nve/sphere", "thermo 100", f"run {STEPS[variant]}"]
    path = os.path.join(work, f"{variant}_{n}.lig")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def run_one(code, path, work, ringdem):
    if code.startswith("ringdem"):
        cmd = [ringdem, "run", path, "-o", os.path.join(work, "out_" + os.path.basename(path))]
    elif code == "lammps":
        cmd = ["lmp", "-in", path, "-log", "none"]
    else:
        cmd = ["liggghts", "-in", path, "-log", "none"]
    timed = ["/usr/bin/time", "-f", "peak_rss_kb %M"] + cmd
    proc = subprocess.run(timed, cwd=work, capture_output=True, text=True)
    text = proc.stdout + proc.stderr
    if proc.returncode != 0:
        sys.exit(f"{code} failed on {path} (exit {proc.returncode}):\n{text[-3000:]}")
    rss = int(re.search(r"peak_rss_kb (\d+)", text).group(1)) * 1024
    if code.startswith("ringdem"):
        m = re.search(r"done: (\d+) steps", text)
        out = os.path.join(work, "out_" + os.path.basename(path), "summary.json")
        with open(out) as f:
            summary = json.load(f)
        # Its own loop time, as LAMMPS's "Loop time" (set-up and the first neighbour build and
        # force evaluation excluded): the steps over the loop's particle-step rate.
        steps = int(m.group(1))
        loop = summary["particles"] * steps / summary["particle_steps_per_s"]
        return dict(loop=loop, steps=steps, atoms=summary["particles"], rss=rss, pairs=None)
    m = re.search(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps with (\d+) atoms",
                  text)
    if not m:
        sys.exit(f"{code}: no loop time in its output for {path}:\n{text[-3000:]}")
    pairs = re.search(r"Total # of neighbors = (\d+)", text)
    return dict(loop=float(m.group(1)), steps=int(m.group(2)), atoms=int(m.group(3)), rss=rss,
                pairs=int(pairs.group(1)) if pairs else None)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ringdem", required=True, help="path of the ringdem binary")
    ap.add_argument("--sizes", default="1e5", help="grain counts, comma separated (1e5,1e6)")
    ap.add_argument("--variants", default="bed,poly,flow,dense",
                    help="of bed,poly,flow,dense,mixed (mixed: not run unless named)")
    ap.add_argument("--codes", default="ringdem,lammps,liggghts")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--json", help="also write the medians here")
    args = ap.parse_args()
    codes = args.codes.split(",")
    results = []
    with tempfile.TemporaryDirectory() as work:
        for size in args.sizes.split(","):
            n = int(float(size))
            for variant in args.variants.split(","):
                inputs = {}
                for code in codes:
                    writer = {"ringdem": write_ringdem,
                              "ringdem_noledger": lambda *a: write_ringdem(*a, ledger=False),
                              "lammps": write_lammps, "liggghts": write_liggghts}[code]
                    inputs[code] = writer(work, variant, n)
                runs = {c: [] for c in codes}
                for _ in range(args.repeats):  # interleaved: code by code within a round
                    for code in codes:
                        runs[code].append(run_one(code, inputs[code], work, args.ringdem))
                row = {"variant": variant, "size": n}
                for code in codes:
                    loop = statistics.median(r["loop"] for r in runs[code])
                    r0 = runs[code][0]
                    row[code] = dict(
                        atoms=r0["atoms"], steps=r0["steps"], loop_s=loop,
                        ns_per_particle_step=1e9 * loop / (r0["atoms"] * r0["steps"]),
                        bytes_per_particle=statistics.median(r["rss"] for r in runs[code]) /
                        r0["atoms"], neighbour_pairs=r0["pairs"])
                results.append(row)
                print(f"\n{variant}, {n:.0e} grains ({args.repeats} interleaved runs, medians):")
                ref = row.get("lammps")
                for code in codes:
                    c = row[code]
                    ratio = (f"  {c['ns_per_particle_step'] / ref['ns_per_particle_step']:.2f}x "
                             "LAMMPS's time" if ref and code != "lammps" else "")
                    pairs = f", {c['neighbour_pairs']} pairs" if c["neighbour_pairs"] else ""
                    print(f"  {code:16s} {c['atoms']:8d} grains {c['steps']:4d} steps  loop "
                          f"{c['loop_s']:8.3f} s  {c['ns_per_particle_step']:7.1f} ns/particle-"
                          f"step  {c['bytes_per_particle']:6.0f} B/particle{pairs}{ratio}")
                sys.stdout.flush()
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


if __name__ == "__main__":
    main()
