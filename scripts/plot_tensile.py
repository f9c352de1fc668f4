#!/usr/bin/python3
"""Load-displacement curves of ringdem tensile tests (docs/tensile.md).

  plot_tensile.py RUN_DIR [RUN_DIR ...] [-o curves.png] [--labels a,b,...]
      one curve per run folder (its series.csv), the detected start of the tensile stage and
      the peak marked from summary.json.
  plot_tensile.py --sweep SWEEP_DIR [-o PREFIX]
      the output of `ringdem sweep`: PREFIX_curves.png (every case's curve, labelled by the
      swept value, as Figs. 7a-9a) and PREFIX_trends.png (breaking load and elongation at
      failure against the swept value, as Figs. 7b,c-9b,c). PREFIX defaults to
      SWEEP_DIR/sweep.

Needs numpy and matplotlib (use /usr/bin/python3).
"""
import argparse
import csv
import json
import math
import os
import sys

from run_folder import folder_with  # scripts/run_folder.py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_series(run_dir):
    data = np.genfromtxt(os.path.join(run_dir, "series.csv"), delimiter=",", names=True)
    return np.atleast_1d(data["displacement_m"]), np.atleast_1d(data["load_N"])


def read_summary(run_dir):
    path = os.path.join(run_dir, "summary.json")
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def plot_curve(ax, run_dir, label):
    u, p = read_series(run_dir)
    (line,) = ax.plot(1e3 * u, 1e-3 * p, label=label, lw=1.2)
    s = read_summary(run_dir)
    ut = s.get("stage_transition_displacement_m")
    if ut is not None:
        ax.plot(1e3 * ut, 1e-3 * np.interp(ut, u, p), "o", color=line.get_color(), ms=4)
    if s.get("peak_load_N") is not None:
        ax.plot(1e3 * s["displacement_at_peak_m"], 1e-3 * s["peak_load_N"], "v",
                color=line.get_color(), ms=5)


def style(ax, title):
    ax.set_xlabel("displacement (mm)")
    ax.set_ylabel("load (kN)")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def plot_runs(run_dirs, labels, output):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for run_dir, label in zip(run_dirs, labels):
        plot_curve(ax, run_dir, label)
    style(ax, "ring tensile tests (o: start of tensile stage, v: peak)")
    fig.tight_layout()
    fig.savefig(output, dpi=150)
    print(output)


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def plot_sweep(sweep_dir, prefix):
    with open(os.path.join(sweep_dir, "sweep.csv")) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{sweep_dir}/sweep.csv has no cases")
    fixed = {"case", "folder"}
    summary_keys = {"stop_reason", "peak_load_N", "displacement_at_peak_m",
                    "elongation_at_failure_m", "first_bond_break_time_s", "broken_bonds",
                    "stage_transition_displacement_m", "bending_stage_stiffness_N_per_m",
                    "tensile_stage_stiffness_N_per_m", "steps", "wall_time_s",
                    "particle_steps_per_s"}
    parameters = [k for k in rows[0].keys() if k not in fixed and k not in summary_keys]
    key = parameters[0]
    name = os.path.basename(os.path.normpath(sweep_dir))

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    for row in rows:
        label = ", ".join(f"{k.split('.')[-1]} = {row[k]}" for k in parameters)
        plot_curve(ax, os.path.join(sweep_dir, row["folder"]), label)
    style(ax, f"{name}: load-displacement")
    fig.tight_layout()
    fig.savefig(prefix + "_curves.png", dpi=150)
    print(prefix + "_curves.png")

    x = np.array([number(r[key]) for r in rows])
    peak = np.array([number(r["peak_load_N"]) for r in rows])
    elongation = np.array([number(r["elongation_at_failure_m"]) for r in rows])
    order = np.argsort(x)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(9, 3.6))
    a1.plot(x[order], 1e-3 * peak[order], "o-")
    a1.set_ylabel("breaking load (kN)")
    a2.plot(x[order], 1e3 * elongation[order], "s-")
    a2.set_ylabel("elongation at failure (mm)")
    for a in (a1, a2):
        a.set_xlabel(key)
        a.grid(alpha=0.3)
    fig.suptitle(name, fontsize=10)
    fig.tight_layout()
    fig.savefig(prefix + "_trends.png", dpi=150)
    print(prefix + "_trends.png")


def main():
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("runs", nargs="*", type=folder_with("series.csv"),
                        help="run folders (series.csv, summary.json)")
    parser.add_argument("--sweep", help="output folder of ringdem sweep (sweep.csv)")
    parser.add_argument("--labels", help="comma-separated curve labels (default: folder names)")
    parser.add_argument("-o", "--output", help="PNG file (runs) or prefix (--sweep)")
    args = parser.parse_args()
    if args.sweep:
        plot_sweep(args.sweep, args.output or os.path.join(args.sweep, "sweep"))
        return
    if not args.runs:
        parser.error("give run folders or --sweep")
    labels = args.labels.split(",") if args.labels else [
        os.path.basename(os.path.normpath(r)) for r in args.runs]
    if len(labels) != len(args.runs):
        parser.error("--labels needs one label per run folder")
    plot_runs(args.runs, labels, args.output or "tensile_curves.png")


if __name__ == "__main__":
    main()
