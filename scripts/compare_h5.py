#!/usr/bin/env python3
"""Compares two ringdem HDF5 files (frames or checkpoints) dataset by dataset, bit for bit.

usage: compare_h5.py A.h5 B.h5 [--groups particles bonds ...] [--frame N] [--skip group/name ...]

--frame N compares frame N (negative counts from the end) of each per-frame dataset of A with
frame N of B; fixed datasets are compared whole. Exit code 1 when anything differs.
"""
import argparse
import sys

import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--groups", nargs="+", default=["particles", "bonds"])
    ap.add_argument("--frame", type=int)
    ap.add_argument("--skip", nargs="*", default=[])
    args = ap.parse_args()
    differ = 0
    compared = 0
    with h5py.File(args.a, "r") as fa, h5py.File(args.b, "r") as fb:
        per_frame = args.frame is not None and "frames" in fa
        for g in args.groups:
            if g not in fa:
                print(f"{args.a}: no group {g}")
                differ += 1
                continue
            for name in sorted(fa[g]):
                path = f"{g}/{name}"
                if path in args.skip:
                    continue
                if path not in fb:
                    print(f"{args.b}: no dataset {path}")
                    differ += 1
                    continue
                da, db = fa[path], fb[path]
                if per_frame and name != "connectivity":
                    x, y = da[args.frame], db[args.frame]
                else:
                    x, y = da[()], db[()]
                compared += 1
                if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                    detail = ""
                    if x.shape == y.shape and np.issubdtype(x.dtype, np.number):
                        diff = np.abs(x.astype(float) - y.astype(float))
                        detail = f": {np.count_nonzero(diff)} values differ, largest by {diff.max():.3g}"
                    print(f"DIFFERS {path}{detail}")
                    differ += 1
    print(f"{compared} datasets compared, {differ} differ")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
