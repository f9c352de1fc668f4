#!/usr/bin/env python3
"""Figures of rockfall runs (scenario rockfall, docs/rockfall.md).

usage: plot_rockfall.py RESULT_DIR [RESULT_DIR ...] [-o OUT_DIR]

- rockfall_acceleration.png: the boulder acceleration against time from the first contact for
  every run given (the equivalent of the paper's Fig. 14), peaks marked, in m/s^2 and g;
- rockfall_energy.png: the energy ledger of the first run (where the 24.3 kJ go);
- rockfall_snapshot_<case>.png: side and top views of the deformed net of each run at its
  deepest deflection, bonds coloured by utilisation, from its frame file (if it has frames).
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
    return {k: np.array([number(r[k]) for r in rows]) for k in rows[0]}


def label_of(summary, folder):
    return summary.get("case", os.path.basename(folder.rstrip("/")))


def snapshot(folder, summary, series, out):
    frames = sorted(glob.glob(os.path.join(folder, "frames_*.h5")))
    if not frames:
        return None
    import h5py

    t_contact = summary["first_contact_time_s"]
    stop = summary.get("stopping_time_s")  # null: the boulder had not turned by the end
    t_deep = t_contact + stop if stop is not None and stop > 0 else None
    best = None
    for path in frames:
        with h5py.File(path, "r") as f:
            times = f["frames/time"][()]
            for i, t in enumerate(times):
                score = abs(t - t_deep) if t_deep is not None else -t
                if best is None or score < best[0]:
                    best = (score, path, i, t)
    _, path, i, t = best
    with h5py.File(path, "r") as f:
        # Frame i's rows; files whose counts may change say how many (docs/output.md).
        n = int(f["frames/particles"][i]) if "frames/particles" in f else f["particles/position"].shape[1]
        nb = int(f["frames/bonds"][i]) if "frames/bonds" in f else f["bonds/utilisation"].shape[1]
        c0 = int(f["frames/connectivity"][i]) if "frames/connectivity" in f else 0
        pos = f["particles/position"][i, :n]
        group = f["particles/group"][i, :n]
        conn = f["bonds/connectivity"][c0:c0 + nb]  # particle rows of frame i
        util = f["bonds/utilisation"][i, :nb]
        broken = f["bonds/broken"][i, :nb].astype(bool)
    k = int(np.argmin(np.abs(series["time_s"] - t)))
    bx, bz, by = series["boulder_x_m"][k], series["boulder_z_m"][k], series["boulder_y_m"][k]
    r = summary["boulder_radius_m"]
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    from matplotlib.collections import LineCollection

    for ax, (a, b, bb, name) in zip(axes, ((0, 2, (bx, bz), "side view (x-z)"), (0, 1, (bx, by), "top view (x-y)"))):
        segs = np.stack([pos[conn[~broken, 0]][:, [a, b]], pos[conn[~broken, 1]][:, [a, b]]], axis=1)
        lc = LineCollection(segs, cmap="viridis", linewidths=0.6)
        lc.set_array(np.clip(util[~broken], 0, 1))
        lc.set_clim(0, 1)
        ax.add_collection(lc)
        fixed = group != np.bincount(group).argmax()
        ax.plot(pos[fixed, a], pos[fixed, b], ".", ms=1.5, color="0.4", label="shackles")
        ax.add_patch(plt.Circle(bb, r, fill=False, color="tab:red", lw=1.5, label="boulder"))
        ax.set_aspect("equal")
        ax.autoscale_view()
        ax.set_xlabel(["x", "y", "z"][a] + " (m)")
        ax.set_ylabel(["x", "y", "z"][b] + " (m)")
        ax.set_title(name)
    fig.colorbar(lc, ax=axes, label="bond utilisation (1 = failure)", shrink=0.8)
    fig.suptitle(f"{label_of(summary, folder)}: t = {t - t_contact:.3f} s after first contact "
                 f"({int(broken.sum())} broken bonds)")
    name = os.path.join(out, f"rockfall_snapshot_{label_of(summary, folder)}.png")
    fig.savefig(name, dpi=130)
    plt.close(fig)
    return name


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", nargs="+", type=run_folder)
    ap.add_argument("-o", "--out", default=None)
    args = ap.parse_args()
    out = args.out or args.results[0]
    os.makedirs(out, exist_ok=True)
    runs = []
    for folder in args.results:
        summary = json.load(open(os.path.join(folder, "summary.json")))
        runs.append((folder, summary, read_series(os.path.join(folder, "series.csv"))))

    g = 9.81
    fig, ax = plt.subplots(figsize=(8, 5))
    for folder, s, ser in runs:
        t = ser["time_from_contact_s"]
        ok = np.isfinite(t)
        # Repeated impacts (scenario.rockfall.impacts): each from its own first contact.
        impact = ser.get("impact", np.ones_like(t))
        entries = s.get("impacts") or [s]
        for k, i in enumerate(entries, start=1):
            sel = ok & (impact == k)
            name = label_of(s, folder) + (f", impact {k}" if len(entries) > 1 else "")
            line, = ax.plot(t[sel], ser["acceleration_m_s2"][sel], lw=1.2,
                            label=f"{name}: peak {i['peak_acceleration_m_s2']:.0f} m/s² "
                                  f"({i['peak_acceleration_g']:.1f} g) at {i['time_of_peak_s']:.3f} s")
            ax.plot([i["time_of_peak_s"]], [i["peak_acceleration_m_s2"]], "o", color=line.get_color())
    ax.set_xlabel("time from first contact (s)")
    ax.set_ylabel("boulder acceleration (m/s²)")
    sec = ax.secondary_yaxis("right", functions=(lambda a: a / g, lambda a: a * g))
    sec.set_ylabel("(g)")
    ax.set_xlim(left=-0.02)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("Boulder acceleration (contact force / mass), cf. paper Fig. 14")
    fig.tight_layout()
    name = os.path.join(out, "rockfall_acceleration.png")
    fig.savefig(name, dpi=130)
    plt.close(fig)
    print("wrote", name)

    folder, s, ser = runs[0]
    if "impact" in ser:  # the ledger of the first impact (the boulder leaves it at its removal)
        first = ser["impact"] == 1
        ser = {k: v[first] for k, v in ser.items()}
    t = ser["time_s"] - s["first_contact_time_s"]
    fig, ax = plt.subplots(figsize=(8, 5))
    # Where the energy is: kinetic and elastic now, dissipated since the release.
    parts = [("kinetic_J", "kinetic", False), ("bond_elastic_J", "bond elastic", False),
             ("contact_elastic_J", "contact elastic", False), ("contact_damping_J", "contact damping", True),
             ("friction_J", "friction", True), ("global_damping_J", "global damping", True),
             ("broken_bonds_J", "broken bonds", True)]
    if "plastic_work_J" in ser:  # series of runs before the plastic bond lack it
        parts.append(("plastic_work_J", "plastic work", True))
    if "brake_work_J" in ser and max(ser["brake_work_J"].max(), ser["brake_elastic_J"].max()) > 0.0:
        # braked shackles, support ropes
        parts += [("brake_elastic_J", "brake springs, ropes", False), ("brake_work_J", "brakes", True)]
    ax.stackplot(t, *[ser[k] - (ser[k][0] if since else 0.0) for k, _, since in parts],
                 labels=[n + (" (dissipated)" if since else "") for _, n, since in parts])
    supplied = sum(ser[k][0] for k, _, since in parts if not since) \
        - (ser["potential_J"] - ser["potential_J"][0]) + (ser["boundary_work_J"] - ser["boundary_work_J"][0])
    ax.plot(t, supplied, "k--", lw=1, label="energy at release + potential energy released")
    ax.plot(t, ser["balance_error_J"], "r:", lw=1, label="ledger error")
    ax.set_xlabel("time from first contact (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title(f"{label_of(s, folder)}: energy ledger (balance within "
                 f"{100 * s['energy_balance_error']:.3g} % of {s['impact_energy_J'] / 1e3:.1f} kJ)")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    name = os.path.join(out, "rockfall_energy.png")
    fig.savefig(name, dpi=130)
    plt.close(fig)
    print("wrote", name)

    for folder, s, ser in runs:
        name = snapshot(folder, s, ser, out)
        if name:
            print("wrote", name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
