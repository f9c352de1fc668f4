#!/usr/bin/env python3
"""Opens a ringdem frame file (or its XDMF sidecar) and checks it the way a reader would:
rows in gid order in every frame, bond connectivity within range and equal to the bond gid
pairs, frame times increasing, every per-frame dataset with one row block per frame, finite
positions, and every HDF dataset the XDMF sidecar names present with the dimensions it states.
Prints a short summary; exit code 1 on any problem.

usage: check_frames.py frames_0000.h5|frames_0000.xdmf
"""
import os
import re
import sys

import h5py
import numpy as np


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
                if name == "connectivity":
                    continue
                if rows == 0 and d.size == 0:
                    continue  # nothing of this kind (a case without rigid bodies): no rows to check
                if d.shape[0] != nf or d.shape[1] != rows:
                    problems.append(f"{g}/{name} has shape {d.shape}, expected ({nf}, {rows}, ...)")
        gid = f["particles/gid"][()]
        if not np.all(gid == np.arange(n)[None, :]):
            problems.append("particle rows are not in gid order")
        pos = f["particles/position"][()]
        if not np.all(np.isfinite(pos)):
            problems.append("non-finite positions")
        if nb:
            conn = f["bonds/connectivity"][()]
            if conn.min() < 0 or conn.max() >= n:
                problems.append("bond connectivity out of range")
            if not (np.array_equal(conn[:, 0], f["bonds/gid_a"][0]) and np.array_equal(conn[:, 1], f["bonds/gid_b"][0])):
                problems.append("connectivity differs from the bond gid pairs")
            broken = int(f["bonds/broken"][-1].sum())
        else:
            broken = 0
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
        else:
            items = []
            problems.append(f"no sidecar {xdmf_path}")
        lo, hi = pos[-1].min(axis=0), pos[-1].max(axis=0)
        print(f"{h5_path}: {nf} frames, t = {times[0]:.6g} .. {times[-1]:.6g} s, {n} particles, {nb} bonds "
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
