#!/usr/bin/env python3
"""Opens a ringdem frame file (or its XDMF sidecar) and checks it the way a reader would:
each frame's rows [0, n_f) in increasing gid (or bond id) order, each frame's bond topology
(particle rows of that frame) within range and joining the bond's gid pairs, frame times
increasing, every per-frame dataset with one row block per frame, finite positions, every HDF
dataset the XDMF sidecar names present with the dimensions it states, each frame of the
sidecar selecting that frame's rows, the rigid bodies' surface meshes (offsets, triangles
within their body's vertices), and each sidecar frame showing the bodies in play and no other.
Files whose particle and bond counts change between frames
(/frames/particles, /frames/bonds, /frames/connectivity) and files written before those existed
(constant counts, one topology) are both read. Prints a short summary; exit code 1 on any
problem.

usage: check_frames.py frames_0000.h5|frames_0000.xdmf
"""
import html
import os
import re
import sys

import h5py
import numpy as np


def check_body_surfaces(f, nf, nbody):
    """The rigid bodies' surface meshes (/bodies/surface) and in-play flags (/bodies/active),
    absent from files written before them: (problems, active flags per frame or None)."""
    if "bodies" not in f or "surface" not in f["bodies"]:
        return [], None
    problems = []
    s = f["bodies/surface"]
    vf, tf = s["vertex_first"][()], s["triangle_first"][()]
    tri, pts = s["triangles"][()], s["points"]
    active = f["bodies/active"][()]
    if len(vf) != nbody + 1 or len(tf) != nbody + 1 or vf[0] != 0 or tf[0] != 0:
        return [f"bodies/surface: vertex_first/triangle_first do not have {nbody} + 1 offsets"], None
    if np.any(np.diff(vf) < 0) or np.any(np.diff(tf) < 0):
        problems.append("bodies/surface: offsets decrease")
    if tri.shape != (tf[-1], 3) or pts.shape != (nf, vf[-1], 3):
        problems.append(f"bodies/surface: triangles {tri.shape}, points {pts.shape}, "
                        f"expected ({tf[-1]}, 3) and ({nf}, {vf[-1]}, 3)")
    for b in range(nbody):
        t = tri[tf[b]:tf[b + 1]]
        if t.size and (t.min() < 0 or t.max() >= vf[b + 1] - vf[b]):
            problems.append(f"bodies/surface: body {b} has triangles outside its vertices")
    if active.shape != (nf, nbody) or not np.all((active == 0) | (active == 1)):
        problems.append(f"bodies/active has shape {active.shape} or values other than 0 and 1")
        return problems, None
    if nbody and not np.all(np.isfinite(pts[()])):
        problems.append("bodies/surface: non-finite points")
    return problems, active


def main(path):
    problems = []
    base = os.path.splitext(path)[0]
    h5_path, xdmf_path = base + ".h5", base + ".xdmf"
    with h5py.File(h5_path, "r") as f:
        fmt = f.attrs.get("format", b"")
        fmt = fmt.decode() if isinstance(fmt, bytes) else str(fmt)
        if fmt != "ringdem-frames":
            problems.append(f"format attribute is '{fmt}', not ringdem-frames")
        n = int(f.attrs["particles"])
        nb = int(f.attrs["bonds"])
        times = f["frames/time"][()]
        nf = len(times)
        if nf == 0:
            problems.append("no frames")
        if np.any(np.diff(times) <= 0):
            problems.append("frame times do not increase")
        nbody = f["bodies/position"].shape[1] if "bodies" in f and "position" in f["bodies"] else 0
        for g, rows in (("particles", n), ("bonds", nb), ("bodies", nbody)):
            if g not in f:
                continue
            for name, d in f[g].items():
                if name in ("connectivity", "surface"):
                    continue
                if rows == 0 and d.size == 0:
                    continue  # nothing of this kind (a case without rigid bodies): no rows to check
                if d.shape[0] != nf or d.shape[1] != rows:
                    problems.append(f"{g}/{name} has shape {d.shape}, expected ({nf}, {rows}, ...)")
        body_problems, active = check_body_surfaces(f, nf, nbody)
        problems += body_problems
        # Per-frame counts and topology blocks; older files: constant counts, one topology.
        counts = f["frames/particles"][()] if "frames/particles" in f else np.full(nf, n)
        bond_counts = f["frames/bonds"][()] if "frames/bonds" in f else np.full(nf, nb)
        first = f["frames/connectivity"][()] if "frames/connectivity" in f else np.zeros(nf, int)
        if np.any(counts > n) or np.any(bond_counts > nb):
            problems.append("a frame has more rows than its datasets")
        gid = f["particles/gid"]
        pos = f["particles/position"]
        conn = f["bonds/connectivity"][()] if nb else np.zeros((0, 2), int)
        broken = 0
        for i in range(nf):
            ni, nbi, c0 = int(counts[i]), int(bond_counts[i]), int(first[i])
            g = gid[i, :ni]
            if np.any(np.diff(g) <= 0) or (ni and g[0] < 0):
                problems.append(f"frame {i}: particle rows are not in increasing gid order")
            if not np.all(np.isfinite(pos[i, :ni])):
                problems.append(f"frame {i}: non-finite positions")
            if nbi == 0:
                continue
            if np.any(np.diff(f["bonds/id"][i, :nbi]) <= 0):
                problems.append(f"frame {i}: bond rows are not in increasing id order")
            if c0 < 0 or c0 + nbi > len(conn):
                problems.append(f"frame {i}: its topology lies outside /bonds/connectivity")
                continue
            c = conn[c0:c0 + nbi]
            if c.min() < 0 or c.max() >= ni:
                problems.append(f"frame {i}: bond connectivity out of range")
            elif not (np.array_equal(g[c[:, 0]], f["bonds/gid_a"][i, :nbi])
                      and np.array_equal(g[c[:, 1]], f["bonds/gid_b"][i, :nbi])):
                problems.append(f"frame {i}: connectivity differs from the bond gid pairs")
            if i == nf - 1:
                broken = int(f["bonds/broken"][i, :nbi].sum())
        if os.path.exists(xdmf_path):
            text = open(xdmf_path).read()
            items = re.findall(r'<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">([^:<]+):([^<]+)</DataItem>', text)
            for dims, fname, dpath in items:
                if fname != os.path.basename(h5_path):
                    problems.append(f"sidecar names file {fname}")
                elif dpath not in f:
                    problems.append(f"sidecar names missing dataset {dpath}")
                elif tuple(int(x) for x in dims.split()) != f[dpath].shape:
                    problems.append(f"sidecar says {dpath} is {dims}, file has {f[dpath].shape}")
            grids = len(re.findall(r'CollectionType="Spatial"', text))
            if grids != nf:
                problems.append(f"sidecar lists {grids} frames, file has {nf}")
            # Each frame's grids name that frame's counts.
            for i, block in enumerate(re.split(r'<Grid Name="frame_\d+"', text)[1:]):
                m = re.search(r'Polyvertex" NumberOfElements="(\d+)"', block)
                if i < nf and (m is None or int(m.group(1)) != counts[i]):
                    problems.append(f"sidecar frame {i} does not hold its {counts[i]} particles")
                m = re.search(r'Polyline" NumberOfElements="(\d+)"', block)
                if i < nf and bond_counts[i] and (m is None or int(m.group(1)) != bond_counts[i]):
                    problems.append(f"sidecar frame {i} does not hold its {bond_counts[i]} bonds")
            # Each frame lists a surface grid for each body in play, none for the others.
            if active is not None:
                names = f["bodies"].attrs.get("names", b"")
                names = (names.decode() if isinstance(names, bytes) else str(names)).split("\n")
                for i, block in enumerate(re.split(r'<Grid Name="frame_\d+"', text)[1:nf + 1]):
                    listed = [html.unescape(n) for n in re.findall(r'<Grid Name="body_([^"]*)"', block)]
                    expected = [n for n, a in zip(names, active[i]) if a]
                    if listed != expected:
                        problems.append(f"sidecar frame {i} shows bodies {listed}, in play {expected}")
        else:
            items = []
            problems.append(f"no sidecar {xdmf_path}")
        last = pos[nf - 1, :int(counts[-1])] if nf and counts[-1] else np.zeros((1, 3))
        lo, hi = last.min(axis=0), last.max(axis=0)

        def span(c, full):
            return f"{full}" if nf == 0 or c.min() == c.max() else f"{c.min()}..{c.max()}"

        particles, bonds = span(counts, n), span(bond_counts, nb)
        print(f"{h5_path}: {nf} frames, t = {times[0]:.6g} .. {times[-1]:.6g} s, {particles} particles, {bonds} bonds "
              f"({broken} broken at the last frame); last frame spans x {lo[0]:.3f}..{hi[0]:.3f}, "
              f"y {lo[1]:.3f}..{hi[1]:.3f}, z {lo[2]:.3f}..{hi[2]:.3f} m; sidecar: {len(items)} data items checked")
    for p in problems:
        print("PROBLEM:", p)
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
