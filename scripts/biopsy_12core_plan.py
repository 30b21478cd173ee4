#!/usr/bin/env python3
"""Writes config/scripts/biopsy_12core.yaml: an expert's systematic 12-core TRUS biopsy of
config/biopsy.yaml that aims only by moving the probe (roll about its axis, push / pull), the
needle riding in the probe's biopsy guide.

For each planned site the probe is rolled, angled (tilt, toward anterior) and pushed or pulled so
that the guide's line passes through the site's centre, keeping the probe as near its working
insertion as a tilt of at most 10 degrees allows; the needle is then advanced so that, after the
gun's throw, the centre of its notch lies on the site's centre. The site centres (peripheral-zone centroid of each of the 12 sites, at rest) are
read from a session's metrics.json (biopsy.planned_site_centres_mm), e.g.

  prostatesim replay config/biopsy.yaml --script config/scripts/biopsy.yaml --report out/plan
  python3 scripts/biopsy_12core_plan.py out/plan/metrics.json > config/scripts/biopsy_12core.yaml

The probe and guide geometry (entry, axis, anterior, needle_guide angle and back distance, radius)
and the gun (22 mm throw, notch 5 + 18 mm behind the tip) are those of config/biopsy.yaml and the
biopsy_18g preset; yaw stays 0. Standard library only.
"""
import json
import math
import sys

ENTRY = (0.0, -30.6, -32.0)  # probe.entry_mm: the pivot on the rectal axis [mm]
AXIS = (0.0, 0.0, 1.0)       # probe.axis
ANTERIOR = (0.0, 1.0, 0.0)   # probe.anterior
RADIUS = 10.0                # probe.radius_mm
GUIDE_ANGLE = math.radians(25.0)  # probe.needle_guide.angle_deg
GUIDE_BACK = 32.0            # probe.needle_guide.back_mm: exit behind the tip-hemisphere centre
STROKE = 22.0                # gun throw [mm]
NOTCH_BACK = 5.0 + 18.0 / 2  # notch centre behind the tip after the throw [mm]
START_INSERTION = 40.0       # probe.pose.insertion_mm
# tilts of up to 20 deg (the window's range) pressed the rectal wall near the anal pivot until the
# watchdog stopped a run (energy growth in the rectum at t = 18.5 s): the plan keeps to 10 deg
MAX_TILT_DEG = 10

ADVANCE_MM_S = 40.0          # needle pushed to its firing depth
WITHDRAW_MM_S = 80.0         # and pulled back into the guide after the core
PROBE_MM_S, PROBE_DEG_S = 40.0, 45.0  # mean speeds of the probe moves: peaks (1.5x) well inside its limits (100 mm/s, 90 deg/s)

ORDER = ["right base lateral", "right mid lateral", "right apex lateral", "right apex medial", "right mid medial",
         "right base medial", "left base medial", "left mid medial", "left apex medial", "left apex lateral",
         "left mid lateral", "left base lateral"]


def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def scale(a, s): return tuple(x * s for x in a)
def cross(a, b): return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def rotate(v, axis, angle):
    """v rotated by angle about the unit axis (Rodrigues)."""
    c, s = math.cos(angle), math.sin(angle)
    return tuple(v[i] * c + cross(axis, v)[i] * s + axis[i] * dot(axis, v) * (1 - c) for i in range(3))


def guide(roll, tilt, insertion):
    """exit and direction of the guide at a pose (engine/tools/probe_geometry.cpp, yaw 0)."""
    lateral = cross(AXIS, ANTERIOR)
    def pose(v):  # AA(tilt, lateral) * AA(roll, axial) v
        return rotate(rotate(v, AXIS, roll), lateral, tilt)
    d, n = pose(AXIS), pose(ANTERIOR)
    tip = tuple(ENTRY[i] + insertion * d[i] for i in range(3))
    exit_ = tuple(tip[i] - GUIDE_BACK * d[i] + RADIUS * n[i] for i in range(3))
    direction = tuple(math.cos(GUIDE_ANGLE) * d[i] + math.sin(GUIDE_ANGLE) * n[i] for i in range(3))
    return exit_, direction


def miss(centre, roll, tilt, insertion):
    e, u = guide(roll, tilt, insertion)
    q = sub(centre, e)
    s = dot(q, u)
    r = sub(q, scale(u, s))
    return math.sqrt(dot(r, r)), s


def solve(centre, tilt):
    """roll [rad] and insertion [mm] that put the guide's line through centre at this tilt."""
    lateral = cross(AXIS, ANTERIOR)
    q = sub(centre, ENTRY)
    roll = math.atan2(dot(q, lateral), dot(q, ANTERIOR))
    insertion = 40.0
    for _ in range(200):  # Gauss-Newton on (roll, insertion), numeric Jacobian of the miss vector
        def vec(r, i):
            e, u = guide(r, tilt, i)
            w = sub(centre, e)
            return sub(w, scale(u, dot(w, u)))
        f = vec(roll, insertion)
        jr = scale(sub(vec(roll + 1e-6, insertion), f), 1e6)
        ji = scale(sub(vec(roll, insertion + 1e-6), f), 1e6)
        a11, a12, a22 = dot(jr, jr), dot(jr, ji), dot(ji, ji)
        b1, b2 = -dot(jr, f), -dot(ji, f)
        det = a11 * a22 - a12 * a12
        if abs(det) < 1e-18:
            break
        roll += (b1 * a22 - b2 * a12) / det
        insertion += (a11 * b2 - a12 * b1) / det
    return roll, insertion


def aim(centre):
    """(roll, tilt [deg], insertion [mm], needle depth before firing [mm]) that put the notch on
    centre: of the tilts 0..MAX_TILT_DEG the one that keeps the probe nearest its
    working insertion (40 mm), so that the apex is reached by angling the probe, not pulling it out."""
    best = None
    for k in range(0, 2 * MAX_TILT_DEG + 1):
        tilt = math.radians(0.5 * k)
        roll, insertion = solve(centre, tilt)
        d, s = miss(centre, roll, tilt, insertion)
        if d > 0.01 or s < 5.0:
            continue
        key = abs(insertion - START_INSERTION)
        if best is None or key < best[0] - 0.5:  # the least tilt that does as well within 0.5 mm
            best = (key, roll, tilt, insertion, s)
    _, roll, tilt, insertion, s = best
    return math.degrees(roll), math.degrees(tilt), insertion, s - STROKE + NOTCH_BACK


def main():
    centres = json.load(open(sys.argv[1]))["biopsy"]["planned_site_centres_mm"]
    lines = []
    t, roll0, tilt0, ins0 = 0.2, 0.0, 0.0, START_INSERTION
    for site in ORDER:
        roll, tilt, ins, pre = aim(centres[site])
        over = max(0.3, abs(ins - ins0) / PROBE_MM_S, (abs(roll - roll0) + abs(tilt - tilt0)) / PROBE_DEG_S)
        lines.append(f"  # {site}: centre {', '.join(f'{c:.1f}' for c in centres[site])} mm")
        lines.append(f"  - {{t: {t:.2f}, probe: {{insertion_mm: {ins:.2f}, roll_deg: {roll:.2f}, tilt_deg: {tilt:.2f}}}, "
                     f"over_s: {over:.2f}}}")
        t += over + 0.1
        t_in = t + pre / ADVANCE_MM_S
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: 0}}")
        lines.append(f"  - {{t: {t_in:.2f}, needle: biopsy_1, depth_mm: {pre:.2f}}}")
        t = t_in + 0.05
        lines.append(f"  - {{t: {t:.2f}, fire: biopsy_1}}")
        t += 0.1  # the throw (15 ms) and the core (5 ms after), held
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: {pre + STROKE:.2f}}}")
        t += (pre + STROKE) / WITHDRAW_MM_S
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: 0}}")
        t += 0.1
        roll0, tilt0, ins0 = roll, tilt, ins
    print("# Systematic 12-core TRUS biopsy of config/biopsy.yaml by an expert who aims only by moving the")
    print("# probe: for each site the probe is rolled and pushed / pulled so that the guide's line passes")
    print("# through the site's centre (peripheral zone), the needle advanced so that the notch is centred")
    print("# there after the throw, the gun fired, the needle withdrawn into the guide (re-armed).")
    print("# Written by scripts/biopsy_12core_plan.py (the site centres from a session's metrics.json).")
    print("#   prostatesim replay config/biopsy.yaml --script config/scripts/biopsy_12core.yaml --report out/12core")
    print("scenario: biopsy")
    print(f"duration_s: {t + 0.2:.2f}")
    print("timeline:")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
