#!/usr/bin/python3
"""The plastic bond next to the elastic one on the tensile rigs (docs/tensile.md, "The plastic
bond"; issue 14 point 2).

  plot_tensile_plastic.py --pair TITLE ELASTIC_DIR PLASTIC_DIR [--pair ...] [-o curves.png]
                          [--unload TITLE ELASTIC_DIR PLASTIC_DIR ...] [--unload-out unload.png]

Each DIR is a tensile-test output folder (series.csv, summary.json). For every pair it draws both
load-displacement curves in one panel and prints one table row per curve (markdown):

  peak load, displacement at the peak, the hinge-fit stage transition of summary.json, the
  tangent-stiffness transition and the load-level transition (below), the load at the elastic
  curve's hinge-fit transition, the plastic work at the end.

Tangent-stiffness transition: the tangent stiffness is the least-squares slope of the curve
over a window of 2 mm of travel (11 rows at the default record interval); the transition is the
first displacement (window centre) at which it exceeds --stiffness-threshold (2 MN/m: the onset
of the steep rise, 4 times the bending-stage and a sixth of the tensile-stage stiffness of the
4-pin ring). Load-level transition: the first
displacement at which the load exceeds 10 % of the elastic curve's peak. Both curves of a pair
use the same thresholds, so their numbers are measured the same way.

--unload pairs are runs with scenario.tensile_test.unload_at: their loading and unloading
branches go into one panel each, with the residual displacement of summary.json marked.

Needs numpy and matplotlib (use /usr/bin/python3).
"""
import argparse
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

WINDOW_M = 2e-3


def read_run(run_dir):
    data = np.genfromtxt(os.path.join(run_dir, "series.csv"), delimiter=",", names=True)
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    return data, summary


def tangent_transition(u, p, threshold):
    """First window centre (up to the peak) where the windowed slope exceeds threshold."""
    peak = int(np.argmax(p))
    for i in range(peak + 1):
        sel = (u >= u[i] - WINDOW_M / 2) & (u <= u[i] + WINDOW_M / 2)
        sel[peak + 1:] = False
        if sel.sum() < 3:
            continue
        slope = np.polyfit(u[sel], p[sel], 1)[0]
        if slope > threshold:
            return u[i]
    return None


def mm(x):
    return "–" if x is None else f"{1e3 * x:.1f}"


def kn(x):
    return "–" if x is None else f"{1e-3 * x:.1f}"


def pair_rows(title, elastic_dir, plastic_dir, threshold):
    e_data, e_sum = read_run(elastic_dir)
    level = 0.1 * e_sum["peak_load_N"]
    e_hinge = e_sum.get("stage_transition_displacement_m")
    rows = []
    for name, run_dir in (("elastic", elastic_dir), ("plastic", plastic_dir)):
        data, s = read_run(run_dir)
        u, p = data["displacement_m"], data["load_N"]
        ut = tangent_transition(u, p, threshold)
        above = np.nonzero(p > level)[0]
        ul = u[above[0]] if above.size else None
        at_hinge = None if e_hinge is None else float(np.interp(e_hinge, u, p))
        rows.append(
            f"| {title} | {name} | {kn(s['peak_load_N'])} | {mm(s['displacement_at_peak_m'])} | "
            f"{mm(s.get('stage_transition_displacement_m'))} | {mm(ut)} | {mm(ul)} | {kn(at_hinge)} | "
            f"{s.get('plastic_work_J', 0.0):.0f} | {s['broken_bonds']} |")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--pair", nargs=3, action="append", default=[],
                    metavar=("TITLE", "ELASTIC", "PLASTIC"))
    ap.add_argument("--unload", nargs=3, action="append", default=[],
                    metavar=("TITLE", "ELASTIC", "PLASTIC"))
    ap.add_argument("-o", "--output", default="plastic_vs_elastic.png")
    ap.add_argument("--stiffness-threshold", type=float, default=2e6,
                    help="tangent stiffness (N/m) that marks the tensile stage")
    ap.add_argument("--unload-out", default="plastic_unloading.png")
    args = ap.parse_args()

    if args.pair:
        print("| rig | bond | peak load (kN) | at (mm) | tensile stage, hinge fit (mm) | "
              f"tangent > {1e-6 * args.stiffness_threshold:g} MN/m (mm) | load > 10 % of elastic peak (mm) | "
              "load at the elastic hinge-fit transition (kN) | plastic work (J) | broken bonds |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        n = len(args.pair)
        cols = 2 if n > 1 else 1
        fig, axes = plt.subplots((n + cols - 1) // cols, cols, figsize=(6 * cols, 4.2 * ((n + 1) // cols)),
                                 squeeze=False)
        for ax, (title, e_dir, p_dir) in zip(axes.flat, args.pair):
            threshold = args.stiffness_threshold
            rows = pair_rows(title, e_dir, p_dir, threshold)
            print("\n".join(rows))
            for name, run_dir, style in (("elastic", e_dir, "-"), ("plastic", p_dir, "-")):
                data, s = read_run(run_dir)
                u, p = data["displacement_m"], data["load_N"]
                (line,) = ax.plot(1e3 * u, 1e-3 * p, style, lw=1.2, label=f"{name} bond")
                ut = tangent_transition(u, p, threshold)
                if ut is not None:
                    ax.axvline(1e3 * ut, color=line.get_color(), ls=":", lw=0.9)
                ax.plot(1e3 * s["displacement_at_peak_m"], 1e-3 * s["peak_load_N"], "v",
                        color=line.get_color(), ms=5)
            ax.axhline(300, color="grey", ls="--", lw=0.8, label="300 kN bound (validation.md)")
            ax.set_title(f"{title} (dotted: tangent stiffness > {1e-6 * threshold:.2f} MN/m)",
                         fontsize=9)
            ax.set_xlabel("displacement (mm)")
            ax.set_ylabel("load (kN)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        for ax in list(axes.flat)[n:]:
            ax.set_visible(False)
        fig.tight_layout()
        fig.savefig(args.output, dpi=120)
        print(f"wrote {args.output}")

    if args.unload:
        print("| rig | bond | turned at (mm) | load there (kN) | residual displacement (mm) | "
              "plastic work (J) |")
        print("|---|---|---|---|---|---|")
        n = len(args.unload)
        fig, axes = plt.subplots(1, n, figsize=(6 * n, 4.2), squeeze=False)
        for ax, (title, e_dir, p_dir) in zip(axes.flat, args.unload):
            for name, run_dir in (("elastic", e_dir), ("plastic", p_dir)):
                data, s = read_run(run_dir)
                u, p = data["displacement_m"], data["load_N"]
                turn = s.get("unload_turn_displacement_m")
                i_turn = int(np.argmax(u))
                (line,) = ax.plot(1e3 * u, 1e-3 * p, lw=1.2, label=f"{name} bond")
                res = s.get("residual_displacement_m")
                if res is not None:
                    ax.plot(1e3 * res, 0.0, "o", color=line.get_color(), ms=5)
                print(f"| {title} | {name} | {mm(turn)} | {kn(p[i_turn])} | "
                      f"{'–' if res is None else f'{1e3 * res:.2f}'} | "
                      f"{s.get('plastic_work_J', 0.0):.0f} |")
            ax.set_title(f"{title}: loading and unloading (dot: residual displacement)",
                         fontsize=9)
            ax.set_xlabel("displacement (mm)")
            ax.set_ylabel("load (kN)")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.unload_out, dpi=120)
        print(f"wrote {args.unload_out}")


if __name__ == "__main__":
    main()
