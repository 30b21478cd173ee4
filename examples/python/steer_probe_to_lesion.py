#!/usr/bin/env python3
"""Closed-loop probe steering: bring the lesion onto the biopsy guide line.

The loop a robotics researcher writes for an uncalibrated probe holder: the error is the
lesion's offset from the guide line (the needle's path through the probe's guide), split into
its component across the sagittal plane (fixed by rolling the probe) and its component in that
plane (fixed by pushing the probe in or pulling it out); the image Jacobian from the two probe
joints (roll, insertion) to the error is estimated by two probing moves, then each step moves
the probe by a damped Gauss-Newton step and updates the Jacobian with Broyden's rule. The
tissue moves under the probe, so the lesion is re-measured after every move (its centroid from
the simulation's particles tagged `lesion`). Writes steering.png (error per step, the sagittal
TRUS plane before and after, with the guide line drawn by the scanner) and steering.csv.

    PYTHONPATH=build/python python3 examples/python/steer_probe_to_lesion.py --out out/steer
    ... --quick    # at most 6 steps (what CI runs)
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


def measure(s, lesion):
    """Lesion offset from the guide line [mm]: (across the sagittal plane, in it), and its distance."""
    snap = s.snapshot()
    g = snap["guide"]
    probe = next(t for t in snap["tools"] if t["kind"] == "probe")
    entry, d, axis = np.array(g["entry_mm"]), np.array(g["direction"]), np.array(probe["axis"])
    c = s.positions()[lesion].mean(axis=0)
    v = c - entry
    perp = v - v.dot(d) * d                   # from the line to the lesion
    across = np.cross(d, axis)                # normal of the sagittal plane (guide and axis span it)
    across /= np.linalg.norm(across)
    inplane = np.cross(across, d)             # in the plane, across the guide
    return np.array([perp.dot(across), perp.dot(inplane)]), np.linalg.norm(perp)


def move(s, q, settle_s):
    """Commands joints q = (roll_deg, insertion_mm) and lets the tissue follow."""
    s.command({"probe": {"roll_deg": float(q[0]), "insertion_mm": float(q[1])}, "over_s": 0.6 * settle_s})
    s.step(int(round(settle_s / s.dt)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenario", default=str(ROOT / "config" / "biopsy.yaml"))
    ap.add_argument("--steps", type=int, default=12)
    ap.add_argument("--tolerance-mm", type=float, default=0.5)
    ap.add_argument("--settle-s", type=float, default=0.25, help="simulated time per move")
    ap.add_argument("--quick", action="store_true", help="at most 6 steps (CI)")
    ap.add_argument("--out", default="out/steer_probe_to_lesion")
    a = ap.parse_args()
    if a.quick:
        a.steps = 6
    os.makedirs(a.out, exist_ok=True)

    s = prostatesim.Scene(a.scenario)
    lesion = s.tagged("lesion")
    # start where a trainee would: the probe in the rectum, 45 mm deep, rolled 8 degrees off
    q = np.array([8.0, 45.0])
    move(s, q, 0.5)
    before = s.ultrasound("sagittal")
    e, dist = measure(s, lesion)
    log = [(0, *q, *e, dist)]
    print(f"start: lesion {dist:.2f} mm from the guide line (across {e[0]:+.2f}, in plane {e[1]:+.2f})")

    # image Jacobian by two probing moves (1 degree of roll, 1 mm of insertion)
    J = np.zeros((2, 2))
    for k, dq in enumerate(([1.0, 0.0], [0.0, 1.0])):
        move(s, q + dq, a.settle_s)
        e1, _ = measure(s, lesion)
        J[:, k] = (e1 - e) / np.linalg.norm(dq)
        move(s, q, a.settle_s)
        e, dist = measure(s, lesion)
    for step in range(1, a.steps + 1):
        if dist < a.tolerance_mm:
            break
        dq = -np.linalg.lstsq(J, e, rcond=None)[0] * 0.8         # damped Gauss-Newton
        dq = np.clip(dq, [-5.0, -5.0], [5.0, 5.0])                # per-step limits: 5 deg, 5 mm
        q = q + dq
        move(s, q, a.settle_s)
        e_new, dist = measure(s, lesion)
        J += np.outer((e_new - e) - J @ dq, dq) / dq.dot(dq)       # Broyden update
        e = e_new
        log.append((step, *q, *e, dist))
        print(f"step {step}: roll {q[0]:+.2f} deg, insertion {q[1]:.2f} mm -> {dist:.2f} mm "
              f"(across {e[0]:+.2f}, in plane {e[1]:+.2f})")
    after = s.ultrasound("sagittal")

    with open(os.path.join(a.out, "steering.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["step", "roll_deg", "insertion_mm", "across_mm", "in_plane_mm", "distance_mm"])
        w.writerows(log)
    fig, ax = plt.subplots(1, 3, figsize=(13, 4.2), dpi=100)
    steps = [r[0] for r in log]
    ax[0].plot(steps, [r[5] for r in log], "o-", label="distance")
    ax[0].plot(steps, [r[3] for r in log], "s--", label="across the plane")
    ax[0].plot(steps, [r[4] for r in log], "^--", label="in the plane")
    ax[0].axhline(0, color="k", lw=0.5)
    ax[0].set_xlabel("step")
    ax[0].set_ylabel("lesion from the guide line [mm]")
    ax[0].legend()
    ax[0].grid(alpha=0.3)
    for k, (img, title) in enumerate(((before, "sagittal TRUS, start"), (after, "sagittal TRUS, steered"))):
        ax[k + 1].imshow(img, cmap="gray", vmin=0, vmax=255)
        ax[k + 1].set_title(title)
        ax[k + 1].axis("off")
    fig.suptitle(f"probe steered to the lesion: {log[0][5]:.1f} mm -> {dist:.2f} mm in {log[-1][0]} steps")
    fig.tight_layout()
    png = os.path.join(a.out, "steering.png")
    fig.savefig(png)
    print(f"wrote {png} and steering.csv")
    if dist > log[0][5]:
        raise SystemExit("the loop moved the lesion away from the guide line")


if __name__ == "__main__":
    main()
