#!/usr/bin/env python3
"""Figures of a debris-flow run with scenario.barrier (issue 13, docs/debris.md).

usage: plot_debris.py OUTDIR [-o FIGDIR] [--direction X,Y,Z] [--up X,Y,Z] [--barrier X,Y,Z]

Reads OUTDIR/series.csv and OUTDIR/summary.json (the columns of docs/debris.md "Barrier
measures") and writes into FIGDIR (default OUTDIR):
- debris_force.png: the normal force on the barrier against time: net (the load on the
  shackles that hold it), posts, and the two together, with the peak marked;
- debris_mass.png: retained mass (grains within retention_length upstream of the barrier),
  overflow (past the barrier plane, still in the model) and, when the run has an outflow box,
  what it removed downstream (and what inlets brought in), against time;
- debris_flow.png: what the upstream gauge saw (flow depth, velocity, bulk density) and the
  net's response (largest deflection, largest bond utilisation);
- debris_deposit.png: a side view of the last frame (frames_NNNN.h5, read with h5py; skipped
  with a message when h5py or the frames are missing): grains as circles of their radius,
  coloured by speed, the net's particles and the shackles, along the flow direction s from the
  barrier plane (s < 0 upstream) against the height above the bed. Distances are measured
  from --barrier along --direction and --up (defaults: the barrier plane through the origin,
  the flow along +x, the bed normal +z, as in inputs/debris/*.yaml). The net's particles are
  those bonds join, the fixed ones (shackles) those that never move, the rest are grains.
"""
import argparse
import csv
import glob
import json
import os
import sys

from run_folder import run_folder  # scripts/run_folder.py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def number(text):
    return float("nan") if text in ("", "null", "nan") else float(text)


def read_series(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{path}: no rows")
    return {k: np.array([number(r[k]) for r in rows]) for k in rows[0]}


def vec(text):
    v = np.array([float(x) for x in text.split(",")])
    if v.shape != (3,):
        raise argparse.ArgumentTypeError(f"need X,Y,Z, got {text}")
    return v


def force_figure(ser, b, name, out):
    t = ser["time_s"]
    fig, ax = plt.subplots(figsize=(8, 4.8))
    if "barrier_mean_force_N" in ser:
        # Means over each series interval, from the impulses of every step (the value of a row
        # holds for the interval that ends there), and the instantaneous samples behind them.
        ax.plot(t, ser["barrier_force_N"] / 1e3, color="0.75", lw=0.6,
                label="total, instantaneous samples")
        step = dict(drawstyle="steps-pre")
        ax.plot(t, ser["barrier_mean_force_N"] / 1e3, color="k", lw=1.4,
                label="total (net + posts), interval mean", **step)
        ax.plot(t, ser["barrier_mean_net_force_N"] / 1e3, color="tab:blue", lw=1.0,
                label="net (load on the shackles), interval mean", **step)
        ax.plot(t, ser["barrier_mean_posts_force_N"] / 1e3, color="tab:orange", lw=1.0,
                label="posts, interval mean", **step)
        ax.plot([b["peak_mean_force_time_s"]], [b["peak_mean_force_N"] / 1e3], "o",
                color="tab:red", label=f"peak mean {b['peak_mean_force_N'] / 1e3:.3g} kN at "
                f"{b['peak_mean_force_time_s']:.3f} s (sampled peak {b['peak_force_N'] / 1e3:.3g} kN)")
    else:
        ax.plot(t, ser["barrier_force_N"] / 1e3, color="k", lw=1.4, label="total (net + posts)")
        ax.plot(t, ser["barrier_net_force_N"] / 1e3, color="tab:blue", lw=1.0,
                label="net (load on the shackles)")
        ax.plot(t, ser["barrier_posts_force_N"] / 1e3, color="tab:orange", lw=1.0, label="posts")
        ax.plot([b["peak_force_time_s"]], [b["peak_force_N"] / 1e3], "o", color="tab:red",
                label=f"peak {b['peak_force_N'] / 1e3:.3g} kN at {b['peak_force_time_s']:.3f} s")
    ax.axhline(0, color="0.6", lw=0.5)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("force along the flow direction (kN)")
    ax.set_title(f"{name}: normal force on the barrier")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "debris_force.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def mass_figure(ser, name, out):
    t = ser["time_s"]
    fig, ax = plt.subplots(figsize=(8, 4.8))
    ax.plot(t, ser["retained_mass_kg"], color="tab:green", lw=1.4, label="retained (grains within retention_length upstream)")
    ax.plot(t, ser["overflow_mass_kg"], color="tab:red", lw=1.2, label="overflow (past the barrier plane)")
    if "outflow_mass_kg" in ser and np.nanmax(ser["outflow_mass_kg"]) > 0:
        ax.plot(t, ser["outflow_mass_kg"], color="tab:purple", lw=1.0, ls="--",
                label="taken out by the outflow box (cumulative)")
        ax.plot(t, ser["overflow_mass_kg"] + ser["outflow_mass_kg"], color="tab:red", lw=0.8, ls=":",
                label="overflow + taken out")
    if "inflow_mass_kg" in ser and np.nanmax(ser["inflow_mass_kg"]) > 0:
        ax.plot(t, ser["inflow_mass_kg"], color="0.4", lw=0.8, ls="-.", label="brought in by inlets (cumulative)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("mass (kg)")
    ax.set_title(f"{name}: retained mass and overflow")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(out, "debris_mass.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def flow_figure(ser, b, name, out):
    t = ser["time_s"]
    fig, axes = plt.subplots(2, 1, figsize=(8, 6.4), sharex=True)
    ax = axes[0]
    ax.plot(t, ser["flow_depth_m"], color="tab:blue", lw=1.2, label="flow depth h (m)")
    ax.plot(t, ser["flow_velocity_m_s"], color="tab:orange", lw=1.2, label="gauge velocity v (m/s)")
    ax.set_ylabel("h (m), v (m/s)")
    ax2 = ax.twinx()
    ax2.plot(t, ser["bulk_density_kg_m3"], color="tab:green", lw=0.8, alpha=0.7, label="bulk density ρ")
    ax2.set_ylabel("ρ (kg/m³)", color="tab:green")
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=8, loc="upper right")
    ax.set_title(f"{name}: upstream gauge and net")
    ax.grid(alpha=0.3)
    ax = axes[1]
    ax.plot(t, ser["net_deflection_m"], color="tab:purple", lw=1.2, label="largest net deflection (m)")
    ax.set_ylabel("deflection (m)")
    ax.set_xlabel("time (s)")
    ax.grid(alpha=0.3)
    ax3 = ax.twinx()
    ax3.plot(t, ser["net_max_utilisation"], color="tab:red", lw=0.8, label="largest bond utilisation")
    ax3.set_ylabel("bond utilisation (1 = failure)", color="tab:red")
    lines = ax.get_legend_handles_labels()
    lines3 = ax3.get_legend_handles_labels()
    ax.legend(lines[0] + lines3[0], lines[1] + lines3[1], fontsize=8, loc="upper left")
    fig.tight_layout()
    path = os.path.join(out, "debris_flow.png")
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def deposit_figure(folder, name, out, d, up, origin):
    frames = sorted(glob.glob(os.path.join(folder, "frames_*.h5")))
    if not frames:
        print("no frames_*.h5 in", folder, "- skipping the deposit side view (set output.frame_interval)")
        return None
    try:
        import h5py
    except ImportError:
        print("h5py is missing (apt-get install python3-h5py) - skipping the deposit side view")
        return None
    from matplotlib.collections import EllipseCollection

    path = frames[-1]
    with h5py.File(path, "r") as f:
        i = len(f["frames/time"]) - 1
        t = float(f["frames/time"][i])
        n = int(f["frames/particles"][i]) if "frames/particles" in f else f["particles/position"].shape[1]
        nb = int(f["frames/bonds"][i]) if "frames/bonds" in f else f["bonds/id"].shape[1]
        c0 = int(f["frames/connectivity"][i]) if "frames/connectivity" in f else 0
        pos = f["particles/position"][i, :n]
        vel = f["particles/velocity"][i, :n]
        rad = f["particles/radius"][i, :n]
        group = f["particles/group"][i, :n]
        conn = f["bonds/connectivity"][c0:c0 + nb] if nb else np.zeros((0, 2), dtype=int)
        # Fixed particles: never moved between the first frame and this one (same gid rows).
        gid = f["particles/gid"][i, :n]
        n0 = int(f["frames/particles"][0]) if "frames/particles" in f else n
        gid0 = f["particles/gid"][0, :n0]
        pos0 = f["particles/position"][0, :n0]
    bonded = np.zeros(n, dtype=bool)
    bonded[np.unique(conn)] = True
    net_groups = set(np.unique(group[bonded]).tolist())
    if i > 0:
        moved = np.ones(n, dtype=bool)
        _, a, b0 = np.intersect1d(gid, gid0, return_indices=True)
        moved[a] = np.any(pos[a] != pos0[b0], axis=1)
    else:  # a single frame: the fixed particles are those at rest
        moved = np.any(vel != 0, axis=1)
    fixed_groups = {g for g in np.unique(group).tolist() if g not in net_groups and not moved[group == g].any()}
    is_net = np.isin(group, list(net_groups))
    is_fixed = np.isin(group, list(fixed_groups))
    is_grain = ~is_net & ~is_fixed
    d = d / np.linalg.norm(d)
    up = up - np.dot(up, d) * d
    up = up / np.linalg.norm(up)
    s = (pos - origin) @ d
    z = (pos - origin) @ up
    speed = np.linalg.norm(vel, axis=1)

    fig, ax = plt.subplots(figsize=(13, 4.8))
    if is_grain.any():
        gs = s[is_grain]
        lo = max(gs.min() - 0.1, -3.0)
        hi = max(gs.max() + 0.1, 0.5)
    else:
        lo, hi = -2.0, 0.5
    sel = is_grain & (s > lo - 0.2) & (s < hi + 0.2)
    # Behind-first drawing: grains farther across the channel are drawn first.
    across = np.cross(d, up)
    order = np.argsort((pos[sel] - origin) @ across)
    ec = EllipseCollection(2 * rad[sel][order], 2 * rad[sel][order], np.zeros(order.size), units="xy",
                           offsets=np.column_stack([s[sel][order], z[sel][order]]),
                           transOffset=ax.transData, cmap="viridis", edgecolors="0.2", linewidths=0.2)
    ec.set_array(speed[sel][order])
    ec.set_clim(0, max(1e-6, np.percentile(speed[is_grain], 99) if is_grain.any() else 1))
    ax.add_collection(ec)
    fig.colorbar(ec, ax=ax, label="grain speed (m/s)", shrink=0.9, pad=0.01)
    ax.plot(s[is_net], z[is_net], ".", ms=1.5, color="tab:red", label="net (ring particles)")
    ax.plot(s[is_fixed], z[is_fixed], ".", ms=2.5, color="k", label="shackles (fixed)")
    # Deposit surface: the highest grain top in 5 cm bins along s.
    if is_grain.any():
        edges = np.arange(lo, hi + 0.05, 0.05)
        k = np.digitize(s[is_grain], edges) - 1
        top = z[is_grain] + rad[is_grain]
        prof = np.full(edges.size - 1, np.nan)
        for j in range(edges.size - 1):
            m = k == j
            if m.any():
                prof[j] = top[m].max()
        ax.step(edges[:-1], prof, where="post", color="tab:blue", lw=1.0, label="highest grain top (5 cm bins)")
    ax.axvline(0, color="0.5", lw=0.8, ls="--", label="barrier plane")
    ax.axhline(0, color="0.3", lw=1.0)
    ax.set_xlim(lo, hi)
    zmax = max(z[is_net].max() if is_net.any() else 0, z[is_grain].max() if is_grain.any() else 0) + 0.1
    ax.set_ylim(-0.05, zmax)
    ax.set_aspect("equal")
    ax.set_xlabel("s: distance along the flow from the barrier plane (m)")
    ax.set_ylabel("height above the bed (m)")
    ax.set_title(f"{name}: deposit behind the net, side view at t = {t:.3f} s "
                 f"({int(is_grain.sum())} grains)")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    out_path = os.path.join(out, "debris_deposit.png")
    fig.savefig(out_path, dpi=130)
    plt.close(fig)
    return out_path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir", type=run_folder)
    ap.add_argument("-o", "--out", default=None, help="folder for the PNGs (default OUTDIR)")
    ap.add_argument("--direction", type=vec, default=vec("1,0,0"), help="flow direction (scenario.barrier.direction)")
    ap.add_argument("--up", type=vec, default=vec("0,0,1"), help="bed normal")
    ap.add_argument("--barrier", type=vec, default=vec("0,0,0"), help="a point of the barrier plane (scenario.barrier.position)")
    a = ap.parse_args()
    out = a.out or a.outdir
    os.makedirs(out, exist_ok=True)
    summary = json.load(open(os.path.join(a.outdir, "summary.json")))
    if "barrier" not in summary:
        sys.exit("summary.json has no barrier object: the run had no scenario.barrier")
    ser = read_series(os.path.join(a.outdir, "series.csv"))
    name = summary.get("case", os.path.basename(a.outdir.rstrip("/")))
    b = summary["barrier"]
    for p in (force_figure(ser, b, name, out), mass_figure(ser, name, out), flow_figure(ser, b, name, out),
              deposit_figure(a.outdir, name, out, a.direction, a.up, a.barrier)):
        if p:
            print("wrote", p)


if __name__ == "__main__":
    main()
