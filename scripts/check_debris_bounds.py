#!/usr/bin/env python3
"""Hydrodynamic-bounds check of a debris-flow run with scenario.barrier (issue 13,
docs/debris.md "Barrier measures"): the peak normal force on the barrier must lie between the
hydrostatic load and the hydrodynamic load of the design guidance for flexible barriers,

    F_low  = 1/2 k_min rho g h^2 w
    F_high = alpha_max rho v^2 h w + 1/2 k_max rho g h^2 w
    F_low <= F_peak <= F_high

with the coefficients taken at the ends of their published ranges (the lower bound with the
smallest k, the upper one with the largest alpha and k), so that the check fails only when the
computed force is outside everything the guidance allows.

usage: check_debris_bounds.py OUTDIR (--width W | --case CASE.yaml) [--barrier flexible|rigid]
                              [--force mean|sample] [--alpha MIN,MAX] [--k MIN,MAX] [--g G]
                              [--window SECONDS|grain]

Inputs (all from OUTDIR, as ringdem wrote them):
- F_peak, --force mean (the default where the run wrote it): summary.json
  barrier.peak_mean_force_N, the largest mean force (net + posts, along the flow direction)
  over one series interval, from the impulses of every step (momentum ledger, docs/physics.md
  "Momentum balance"); it must equal the largest barrier_mean_force_N of series.csv. This is
  the load of the flow over each interval, as the design guidance means it.
  --force sample: barrier.peak_force_N, the largest of the instantaneous contact forces
  sampled every simulation.series_interval (barrier_force_N), so a single grain striking the
  net or a post shows as a spike (the guidance treats such boulder impacts apart, e.g. by the
  Hertz equation in GEO Report 270). --window T judges instead the largest mean of the force
  column over T seconds (trailing, over whole series rows, at least one), the load of the flow
  as a load cell of that response time would see it; its time is the window's end. T = 0
  judges the summary's peak itself.
  --window grain (the default where the run recorded the grain size): T = d / v, the time the
  flow takes to advance by its coarsest grain's diameter d at the gauge (summary.json
  barrier.largest_gauge_grain_diameter_m) at the largest gauge velocity v of the run. The
  guidance's loads are those of a continuum, the momentum flux rho v^2 h w and the earth
  pressure of the flow; over less than a grain's passage the load is that of single grains
  striking the barrier, which the guidance treats apart as boulder impact. So d / v is the
  shortest window over which a computed load can be compared with the flow's formula (the
  demo's rows: docs/debris.md). Runs of an older ringdem, without that diameter, get T = 0.
- h, v, rho: series.csv flow_depth_m, flow_velocity_m_s and bulk_density_kg_m3 at the upstream
  gauge. Rows used: every row with time_s <= the time of the peak force and a non-empty gauge
  (flow_depth_m > 0), i.e. the approaching flow up to the peak; h, v and rho are each the
  largest value over those rows (the "peaks before the peak force"). Taking the maxima makes
  the upper bound as loose and the lower bound as strict as those rows allow. Rows after the
  peak are not used: by then the deposit has backed up to the gauge and what it measures is no
  longer the flow that made the peak.
  Note how ringdem measures them: h is the highest grain top above the bed in the gauge (a
  saltating grain raises it), rho = gauge mass / (gauge length x scenario.barrier.width x h),
  so rho h is the solid mass per unit bed area and does not depend on how h is defined, while
  rho g h^2 grows with h: an overestimated h raises both bounds. --depth centroid takes h
  from flow_depth_centroid_m instead, twice the mass-weighted mean height of the gauge's grain
  centres (the depth of a uniform layer with the same centroid; a saltating grain moves it by
  its mass share only), and rho = the same gauge mass over that h. It assumes a layer resting
  on the bed: over a sparse front of grains off the bed it exceeds the top depth (a lone grain
  at height z gives 2 z), and the largest over the rows used may come from there.
- w: the barrier width, --width (or scenario.barrier.width of --case); rho is used as the run
  measured it, whatever --width says.
- g = 9.81 m/s^2 (the guidance's g, not its component normal to an inclined bed; --g changes it).

Published ranges (defaults; --alpha and --k override them). alpha is the dynamic pressure
coefficient, k the static (earth) pressure coefficient of the same formula:
- flexible barriers (the default, --barrier flexible): alpha in [0.7, 2.0], k = 1.0.
  * Wendeler, C. (2016). Debris-Flow Protection Systems for Mountain Torrents - Basic
    Principles for Planning and Calculation of Flexible Barriers. WSL Berichte 44, Swiss Federal
    Institute for Forest, Snow and Landscape Research WSL, Birmensdorf, 279 pp.
  * Volkwein, A. (2014). Flexible debris flow barriers. Design and application. WSL Berichte 18,
    WSL, Birmensdorf, 29 pp.
    Both give the pressure coefficient of the dynamic load on a flexible ring-net barrier as
    0.7 to 2 (back-analysed from the Illgraben field barrier and flume tests) with a
    hydrostatic (k = 1) static part.
  * Kwan, J.S.H. & Cheung, R.W.M. (2012). Suggestions on design approaches for flexible
    debris-resisting barriers. Discussion Note DN 1/2012, Geotechnical Engineering Office,
    Hong Kong: alpha = 2.0 and k = 1.0 for flexible barriers (the upper end of the range above).
- rigid barriers (--barrier rigid; a wall or post, as in tests/scripts/debris_bounds.sh):
  alpha in [0.7, 2.5], k = 1.0.
  * Kwan, J.S.H. (2012). Supplementary Technical Guidance on Design of Rigid Debris-resisting
    Barriers. GEO Report No. 270, Geotechnical Engineering Office, Hong Kong, 88 pp.:
    alpha = 2.5 for rigid barriers.
  The coefficient values above are as these documents are commonly quoted; their full texts
  could not be opened when this script was written, so confirm them against the originals
  before relying on the bounds for design.
- For comparison only (not used as defaults): Hübl, J., Suda, J., Proske, D., Kaitna, R. &
  Scheidl, C. (2009). Debris flow impact estimation. Proc. 11th Int. Symp. on Water Management
  and Hydraulic Engineering, Ohrid, Macedonia, 1-5 Sept. 2009, paper A56, compile the
  hydrodynamic (p = a rho v^2) and hydrostatic (p = k rho g h) formulas for rigid structures;
  their purely hydrostatic formulas use k well above 1 because k there also carries the
  dynamic part, which the alpha term carries here.

Prints every number and the verdict; exit code 0 when the bound holds, 1 when it fails (or
when no flow reached the gauge before the peak), 2 on unusable input.
"""
import argparse
import csv
import json
import math
import os
import sys

from run_folder import run_folder  # scripts/run_folder.py

RANGES = {  # barrier kind: (alpha_min, alpha_max), (k_min, k_max)
    "flexible": ((0.7, 2.0), (1.0, 1.0)),
    "rigid": ((0.7, 2.5), (1.0, 1.0)),
}


def pair(text):
    lo, hi = (float(x) for x in text.split(","))
    if not 0 < lo <= hi:
        raise argparse.ArgumentTypeError(f"need 0 < MIN <= MAX, got {text}")
    return lo, hi


def number(text):
    return float("nan") if text in ("", "null", "nan") else float(text)


def width_from_case(path):
    import yaml  # python3-yaml; only needed for --case

    with open(path) as f:
        case = yaml.safe_load(f)
    w = float(((case.get("scenario") or {}).get("barrier") or {}).get("width", 0.0))
    if w <= 0:
        raise ValueError(f"{path}: scenario.barrier.width is not set (> 0)")
    return w


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outdir", type=run_folder)
    ap.add_argument("--width", type=float, help="barrier width w (m)")
    ap.add_argument("--case", help="case file whose scenario.barrier.width is w")
    ap.add_argument("--barrier", choices=sorted(RANGES), default="flexible")
    ap.add_argument("--alpha", type=pair, help="alpha range MIN,MAX (overrides --barrier)")
    ap.add_argument("--k", type=pair, help="k range MIN,MAX (overrides --barrier)")
    ap.add_argument("--g", type=float, default=9.81, help="g in the static term (m/s^2)")
    ap.add_argument("--depth", choices=("top", "centroid"), default="top",
                    help="h: the highest grain top (flow_depth_m) or twice the mass-weighted "
                         "mean height of the grain centres (flow_depth_centroid_m)")
    ap.add_argument("--force", choices=("mean", "sample"),
                    help="judge the interval-mean force (default where written) or the sampled one")
    ap.add_argument("--window", default="grain",
                    help="judge the largest mean force over this many seconds (0: the peak "
                         "itself), or 'grain' (the default): over the passage time d / v of the "
                         "coarsest grain at the gauge")
    a = ap.parse_args()

    try:
        if a.width is not None:
            w = a.width
        elif a.case:
            w = width_from_case(a.case)
        else:
            raise ValueError("give the barrier width: --width W or --case CASE.yaml")
        if not w > 0:
            raise ValueError(f"--width must be > 0, got {w}")
        summary = json.load(open(os.path.join(a.outdir, "summary.json")))
        if "barrier" not in summary:
            raise ValueError("summary.json has no barrier object (the case has no scenario.barrier)")
        with open(os.path.join(a.outdir, "series.csv")) as f:
            rows = list(csv.DictReader(f))
        has_mean = bool(rows) and "barrier_mean_force_N" in rows[0] and \
            "peak_mean_force_N" in summary["barrier"]
        kind = a.force or ("mean" if has_mean else "sample")
        if kind == "mean" and not has_mean:
            raise ValueError("--force mean: the run wrote no barrier_mean_force_N (older ringdem)")
        force_col = "barrier_mean_force_N" if kind == "mean" else "barrier_force_N"
        need = ("time_s", force_col, "flow_depth_m", "flow_velocity_m_s", "bulk_density_kg_m3")
        if a.depth == "centroid":
            need += ("flow_depth_centroid_m",)
        missing = [c for c in need if not rows or c not in rows[0]]
        if missing:
            raise ValueError(f"series.csv lacks {', '.join(missing)}")
        grain_window = a.window == "grain"
        try:
            window = 0.0 if grain_window else float(a.window)
        except ValueError:
            window = math.nan
        if not (window >= 0 and math.isfinite(window)):
            raise ValueError(f"--window must be 'grain' or seconds >= 0, got {a.window}")
    except (OSError, ValueError, json.JSONDecodeError) as e:
        print(f"check_debris_bounds: {e}", file=sys.stderr)
        return 2

    (alpha_min, alpha_max), (k_min, k_max) = RANGES[a.barrier]
    if a.alpha:
        alpha_min, alpha_max = a.alpha
    if a.k:
        k_min, k_max = a.k
    b = summary["barrier"]
    key = "peak_mean_force" if kind == "mean" else "peak_force"
    f_peak, t_peak = float(b[key + "_N"]), float(b[key + "_time_s"])
    col = {c: [number(r[c]) for r in rows] for c in need}
    # The first row has no interval before it: its mean is NaN.
    col[force_col] = [0.0 if math.isnan(x) else x for x in col[force_col]]
    f_series = max(col[force_col])
    ok = True
    print(f"run: {a.outdir} ({summary.get('case', '?')}, {len(rows)} series rows)")
    print(f"peak barrier force      F_peak = {f_peak:.6g} N at t = {t_peak:.6g} s "
          f"({'mean over a series interval' if kind == 'mean' else 'instantaneous sample'}; "
          f"net {b.get(key.replace('force', 'net_force') + '_N', 0):.4g} N, "
          f"posts {b.get(key.replace('force', 'posts_force') + '_N', 0):.4g} N peaks)")
    if not math.isclose(f_peak, f_series, rel_tol=1e-9, abs_tol=1e-9):
        print(f"FAIL: summary {key}_N {f_peak:.9g} differs from the largest series "
              f"{force_col} {f_series:.9g}")
        ok = False
    times, force = col["time_s"], col[force_col]
    step = (times[-1] - times[0]) / max(1, len(times) - 1)
    n = max(1, int(round(window / step)))
    if grain_window:
        d = float(b.get("largest_gauge_grain_diameter_m", 0.0))
        v_gauge = max([x for x, h in zip(col["flow_velocity_m_s"], col["flow_depth_m"]) if h > 0],
                      default=0.0)
        if d > 0 and v_gauge > 0:
            window = d / v_gauge
            # At least the passage time: whole rows, rounded up (a 1e-9 margin for round-off).
            n = max(1, math.ceil(window / step - 1e-9))
            print(f"window: the coarsest grain's passage at the gauge, d / v = {d:.4g} m / "
                  f"{v_gauge:.4g} m/s = {window:.4g} s ({n} rows)")
        else:
            print("window: none (the run recorded no grain size at the gauge, an older ringdem, "
                  "or no flow reached it): the peak itself")
    if n > 1 or window > 0:
        if n > len(force):
            print(f"check_debris_bounds: a window of {n * step:.4g} s is longer than the run",
                  file=sys.stderr)
            return 2
        run = [sum(force[i - n + 1:i + 1]) / n for i in range(n - 1, len(force))]
        j = max(range(len(run)), key=run.__getitem__)
        f_peak, t_peak = run[j], times[j + n - 1]
        print(f"judged: the largest {n}-row mean ({n * step:.4g} s window) F_peak = {f_peak:.6g} N, "
              f"window ending at t = {t_peak:.6g} s")

    use = [i for i, t in enumerate(col["time_s"]) if t <= t_peak + 1e-12 and col["flow_depth_m"][i] > 0]
    if not use:
        print("FAIL: no series row before the peak force has flow at the gauge "
              "(flow_depth_m > 0): the gauge saw no approaching flow")
        return 1
    v = max(col["flow_velocity_m_s"][i] for i in use)
    if a.depth == "centroid":
        # The same gauge mass over the centroid depth: rho h stays what the run measured.
        h = max(col["flow_depth_centroid_m"][i] for i in use)
        rho = max(col["bulk_density_kg_m3"][i] * col["flow_depth_m"][i] /
                  col["flow_depth_centroid_m"][i] for i in use if col["flow_depth_centroid_m"][i] > 0)
    else:
        h = max(col["flow_depth_m"][i] for i in use)
        rho = max(col["bulk_density_kg_m3"][i] for i in use)
    t0, t1 = col["time_s"][use[0]], col["time_s"][use[-1]]
    print(f"gauge rows used         {len(use)} rows, t = {t0:.6g} .. {t1:.6g} s (flow at the gauge, up to the peak)")
    print(f"flow depth              h     = {h:.6g} m (largest; "
          f"{'centroid depth' if a.depth == 'centroid' else 'highest grain top'})")
    print(f"flow velocity           v     = {v:.6g} m/s (largest)")
    print(f"bulk density            rho   = {rho:.6g} kg/m^3 (largest)")
    print(f"barrier width           w     = {w:.6g} m")
    print(f"Froude number           v / sqrt(g h) = {v / math.sqrt(a.g * h):.4g}")
    print(f"coefficients            alpha in [{alpha_min:g}, {alpha_max:g}], k in [{k_min:g}, {k_max:g}] "
          f"({'given' if a.alpha or a.k else a.barrier + ' barrier'})")
    if rho <= 0:
        print("FAIL: bulk density is 0 (scenario.barrier.width not set in the run?)")
        return 1
    dyn = rho * v * v * h * w          # rho v^2 h w
    stat = 0.5 * rho * a.g * h * h * w  # 1/2 rho g h^2 w
    f_low = k_min * stat
    f_high = alpha_max * dyn + k_max * stat
    print(f"momentum flux           rho v^2 h w     = {dyn:.6g} N")
    print(f"static load (k = 1)     1/2 rho g h^2 w = {stat:.6g} N")
    print(f"lower bound (hydrostatic, k_min)               F_low  = {f_low:.6g} N")
    print(f"upper bound (hydrodynamic, alpha_max, k_max)   F_high = {f_high:.6g} N")
    print(f"F_peak / F_low = {f_peak / f_low:.4g}, F_peak / F_high = {f_peak / f_high:.4g}; "
          f"alpha implied with k_max: {(f_peak - k_max * stat) / dyn:.4g}")
    if f_peak < f_low:
        print("FAIL: the peak force is below the hydrostatic load")
        ok = False
    if f_peak > f_high:
        print("FAIL: the peak force is above the hydrodynamic load")
        ok = False
    print("OK: F_low <= F_peak <= F_high" if ok else "bounds check FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
