#!/usr/bin/env python3
"""Insertion-speed sweep: the biopsy needle pushed along the probe's guide at several speeds,
its axial tissue force plotted against its depth (from first tissue contact), one curve per
speed. Writes force_depth.png and force_depth.csv (speed_mm_s, depth_mm, force_n) to --out.

    PYTHONPATH=build/python python3 examples/python/insertion_speed_sweep.py --out out/sweep
    ... --quick    # two speeds, 30 mm (what CI runs)
"""
import argparse
import csv
import os
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import prostatesim  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def insert(scenario, needle, speed_mm_s, plan_depth_mm):
    """One insertion: the probe placed as in config/scripts/biopsy.yaml, then the needle advanced
    at a constant speed to plan_depth_mm along its path. Returns (depth_mm, force_n) per tick."""
    s = prostatesim.Scene(scenario)
    s.command({"probe": {"insertion_mm": 45}, "over_s": 0.4})
    s.step(int(round(0.5 / s.dt)))
    s.command({"select": needle})
    s.command({"advance": needle, "speed_mm_s": speed_mm_s})
    depth, force = [], []
    for _ in range(int(round(plan_depth_mm / speed_mm_s / s.dt))):
        s.step()
        ro = next(t for t in s.snapshot()["tools"] if t["kind"] == "needle" and t["name"] == needle)
        if ro["depth_mm"] > 0:  # in tissue
            depth.append(ro["depth_mm"])
            force.append(ro["force_n"])
    return np.array(depth), np.array(force)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", default=str(ROOT / "config" / "biopsy.yaml"))
    ap.add_argument("--needle", default="biopsy_1")
    ap.add_argument("--speeds", default="2.5,5,10,20,40", help="mm/s, comma-separated")
    ap.add_argument("--depth-mm", type=float, default=35.0, help="planned depth along the needle's path")
    ap.add_argument("--quick", action="store_true", help="two speeds to 30 mm (CI)")
    ap.add_argument("--out", default="out/insertion_speed_sweep")
    a = ap.parse_args()
    speeds = [float(v) for v in a.speeds.split(",")]
    if a.quick:
        speeds, a.depth_mm = [10.0, 40.0], 30.0
    os.makedirs(a.out, exist_ok=True)

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    rows = []
    for v in speeds:
        d, f = insert(a.scenario, a.needle, v, a.depth_mm)
        rows += [(v, di, fi) for di, fi in zip(d, f)]
        ax.plot(d, f, label=f"{v:g} mm/s")
        peak = f.max() if len(f) else float("nan")
        print(f"{v:6.1f} mm/s: {len(d)} ticks in tissue, to {d.max() if len(d) else 0:.1f} mm, peak {peak:.2f} N")
    ax.set_xlabel("depth from first contact [mm]")
    ax.set_ylabel("axial tissue force [N]")
    ax.set_title(f"{a.needle}: force against depth at each insertion speed")
    ax.grid(alpha=0.3)
    ax.legend(title="speed")
    fig.tight_layout()
    png = os.path.join(a.out, "force_depth.png")
    fig.savefig(png)
    with open(os.path.join(a.out, "force_depth.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["speed_mm_s", "depth_mm", "force_n"])
        w.writerows(rows)
    print(f"wrote {png} and force_depth.csv")
    if not rows:
        raise SystemExit("the needle never reached tissue")


if __name__ == "__main__":
    main()
