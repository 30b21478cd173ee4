#!/usr/bin/env python3
"""Writes config/scripts/biopsy_12core.yaml: an expert's systematic 12-core TRUS biopsy of
config/biopsy.yaml that aims only by moving the probe, the needle riding in the probe's biopsy
guide.

For each planned site the probe is rolled about its axis, tilted toward anterior, yawed, shifted
and pushed or pulled so that the guide's line passes through the site's centre with the probe as
far inside the rectal lumen as the site allows (aim(), below: the apex is reached by tilting the
probe, not by pulling it back onto the lumen's closed lower end); the needle is then advanced so
that, after the gun's throw, the centre of its notch lies on the site's centre, the gun fired and
the needle withdrawn into the guide. The site centres (peripheral-zone centroid of each of the 12
sites, at rest) are read from a session's metrics.json (biopsy.planned_site_centres_mm), e.g.

  prostatesim replay config/biopsy.yaml --script config/scripts/biopsy.yaml --report out/plan
  python3 scripts/biopsy_12core_plan.py out/plan/metrics.json > config/scripts/biopsy_12core.yaml

The probe and guide geometry (entry, axis, anterior, radius, length, needle_guide angle and back
distance) and the gun (22 mm throw, notch 5 + 18 mm behind the tip) are those of
config/biopsy.yaml and the biopsy_18g preset; the rectal lumen that of assets/anatomy. Standard
library only; about three minutes.
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

ADVANCE_MM_S = 40.0          # needle pushed to its firing depth
WITHDRAW_MM_S = 80.0         # and pulled back into the guide after the core
PROBE_MM_S, PROBE_DEG_S = 25.0, 30.0  # mean speeds of the probe moves: peaks (1.5x) inside its limits (50 mm/s, 60 deg/s)

HEADER = """\
# Systematic 12-core TRUS biopsy of config/biopsy.yaml by an expert who aims only by moving the
# probe: for each site the probe is rolled, tilted toward anterior, yawed, shifted and pushed or
# pulled so that the guide's line passes through the site's centre (peripheral zone) with the probe
# as far inside the rectal lumen as the site allows (the apex and the lateral mid-gland by tilting
# the probe's tip anteriorly, which steepens the needle), the needle advanced so that the notch is
# centred there after the throw, the gun fired, the needle withdrawn into the guide (re-armed).
# At the base the notch lies short of the centre: the tip ends at most 3 mm above the gland's base
# (the bladder neck beyond). Written by scripts/biopsy_12core_plan.py (the site centres from a
# session's metrics.json). Release build, docs/needle.md ("The 12-core script"):
#   prostatesim replay config/biopsy.yaml --script config/scripts/biopsy_12core.yaml --report out/12core
# 12 cores at the 12 distinct sites, mean notch-to-site error 0.66 mm, no structure hit; six throws
# end out of the gland through its capsule (1 point each, docs/metrics.md): score 91.4.
"""

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


# The rectal lumen at rest (assets/anatomy, engine/anatomy/pelvis.h RectumParams): the points
# within LUMEN_RADIUS of the rectum's axis, straight along z from its lower end up to z = 10 mm, then
# bending posteriorly (radius 60 mm, 35 degrees). Below the lower end the membrane closes (a
# hemispherical cap down to z = -52 mm, 10 mm above the perineum), so a probe pulled far back
# presses that cap.
LUMEN_RADIUS = 15.0
RECTUM_AXIS = [(0.0, -30.6, -37.0), (0.0, -30.6, 10.0)] + [
    (0.0, -30.6 - 60.0 * (1 - math.cos(math.radians(35.0) * k / 10)), 10.0 + 60.0 * math.sin(math.radians(35.0) * k / 10))
    for k in range(1, 11)]
# a base core's throw ends beyond the site, toward the bladder neck: the needle's depth is cut so
# that its tip, after the throw, lies at most TIP_ABOVE_BASE_MM above the gland's base
# (prostate_base_mm of assets/anatomy/landmarks.yaml, at rest); measured: a throw ending 7.8 mm
# above it punctured the bladder wall (right base medial), one ending 5.6 mm above it did not
BASE_Z = 18.5
TIP_ABOVE_BASE_MM = 3.0
LENGTH = 45.0                # probe.length_mm: tip-hemisphere centre to back-hemisphere centre
# the search: tilt (toward anterior) and yaw of the probe in 1-degree steps up to MAX_TILT_DEG
# in all, a transverse offset of the pivot up to MAX_OFFSET_MM (step 1 mm)
MAX_TILT_DEG = 24
MAX_OFFSET_MM = 6


def guide(roll, tilt, yaw, insertion, offset):
    """exit and direction of the guide at a pose (engine/tools/probe/probe_geometry.cpp), and the probe's
    tip and axis. offset: transverse shift (x, y) of the pivot [mm]."""
    lateral = cross(AXIS, ANTERIOR)
    def pose(v):  # AA(tilt, lateral) * AA(yaw, -anterior) * AA(roll, axial) v
        return rotate(rotate(rotate(v, AXIS, roll), scale(ANTERIOR, -1.0), yaw), lateral, tilt)
    d, n = pose(AXIS), pose(ANTERIOR)
    pivot = (ENTRY[0] + offset[0], ENTRY[1] + offset[1], ENTRY[2])
    tip = tuple(pivot[i] + insertion * d[i] for i in range(3))
    exit_ = tuple(tip[i] - GUIDE_BACK * d[i] + RADIUS * n[i] for i in range(3))
    direction = tuple(math.cos(GUIDE_ANGLE) * d[i] + math.sin(GUIDE_ANGLE) * n[i] for i in range(3))
    return exit_, direction, tip, d


def lumen_excess(tip, d):
    """how far [mm] the probe (a capsule of RADIUS about the segment tip .. tip - LENGTH d) reaches
    past the rectal lumen at rest: > 0 where it presses the wall, or the closed lower end."""
    worst = -1e9
    for k in range(0, int(LENGTH) + 1, 3):
        p = tuple(tip[i] - k * d[i] for i in range(3))
        dist = 1e9
        for a, b in zip(RECTUM_AXIS, RECTUM_AXIS[1:]):
            ab, ap = sub(b, a), sub(p, a)
            t = max(0.0, min(1.0, dot(ap, ab) / dot(ab, ab)))
            r = sub(ap, scale(ab, t))
            dist = min(dist, math.sqrt(dot(r, r)))
        worst = max(worst, dist + RADIUS - LUMEN_RADIUS)
    return worst


def solve(centre, tilt, yaw, offset):
    """roll [rad] and insertion [mm] that put the guide's line through centre at this tilt, yaw and
    offset; None when the line cannot pass through it."""
    lateral = cross(AXIS, ANTERIOR)
    q = sub(centre, ENTRY)
    roll = math.atan2(dot(q, lateral), dot(q, ANTERIOR))
    insertion = START_INSERTION

    def vec(r, i):
        e, u, _, _ = guide(r, tilt, yaw, i, offset)
        w = sub(centre, e)
        return sub(w, scale(u, dot(w, u)))
    for _ in range(50):  # Gauss-Newton on (roll, insertion), numeric Jacobian of the miss vector
        f = vec(roll, insertion)
        if dot(f, f) < 1e-12:
            break
        jr = scale(sub(vec(roll + 1e-6, insertion), f), 1e6)
        ji = scale(sub(vec(roll, insertion + 1e-6), f), 1e6)
        a11, a12, a22 = dot(jr, jr), dot(jr, ji), dot(ji, ji)
        b1, b2 = -dot(jr, f), -dot(ji, f)
        det = a11 * a22 - a12 * a12
        if abs(det) < 1e-18:
            return None
        roll += (b1 * a22 - b2 * a12) / det
        insertion += (a11 * b2 - a12 * b1) / det
    if dot(vec(roll, insertion), vec(roll, insertion)) > 1e-4:
        return None
    return roll, insertion


def aim(centre):
    """The pose (roll, tilt, yaw [deg], offset [mm], insertion [mm]), the needle depth before firing
    [mm] that put the notch on centre, and how far [mm] the probe then reaches past the rectal lumen
    at rest: the probe inside the lumen as far as the site allows. A 25-degree guide on a probe lying along the lumen meets the posterior surface of the
    gland at mid-gland and base; the apex (and the lateral mid-gland) is reached by tilting the
    probe's tip anteriorly (and yawing it toward the site's side), which steepens the needle; pulled
    back instead, the probe's back end would press deep into the lumen's closed lower end. Of the poses the one whose probe reaches least past the lumen, then the least tilted and
    shifted (a degree of tilt or a millimetre of offset weighs as 0.01 mm of excess)."""
    best = None
    for phi in range(0, MAX_TILT_DEG + 1):
        for side in ((0.0,) if phi == 0 else (-45.0, -30.0, -15.0, 0.0, 15.0, 30.0, 45.0)):
            tilt, yaw = math.radians(phi * math.cos(math.radians(side))), math.radians(phi * math.sin(math.radians(side)))
            for ox in range(-MAX_OFFSET_MM, MAX_OFFSET_MM + 1, 2):
                for oy in range(-MAX_OFFSET_MM, MAX_OFFSET_MM + 1):
                    sol = solve(centre, tilt, yaw, (ox, oy))
                    if sol is None:
                        continue
                    roll, insertion = sol
                    e, u, tip, d = guide(roll, tilt, yaw, insertion, (ox, oy))
                    s = dot(sub(centre, e), u)
                    if s < 12.0:  # the notch's centre lies 8 mm ahead of the armed tip's throw start
                        continue
                    excess = max(0.0, lumen_excess(tip, d))
                    key = excess + 0.01 * (phi + abs(ox) + abs(oy))
                    if best is None or key < best[0]:
                        best = (key, roll, tilt, yaw, (ox, oy), insertion, s, excess)
    _, roll, tilt, yaw, off, insertion, s, excess = best
    return math.degrees(roll), math.degrees(tilt), math.degrees(yaw), off, insertion, s - STROKE + NOTCH_BACK, excess


def base_cut(centre, pose):
    """how much shallower [mm] than the site's centre the notch must lie for the tip, after the
    throw, to stay at most TIP_ABOVE_BASE_MM above the gland's base (0 for most sites)"""
    roll, tilt, yaw, off, insertion = pose
    e, u, _, _ = guide(math.radians(roll), math.radians(tilt), math.radians(yaw), insertion, off)
    tip_z = e[2] + (dot(sub(centre, e), u) + NOTCH_BACK) * u[2]
    return max(0.0, (tip_z - BASE_Z - TIP_ABOVE_BASE_MM) / u[2])


def main():
    centres = json.load(open(sys.argv[1]))["biopsy"]["planned_site_centres_mm"]
    lines = []
    t, roll0, tilt0, yaw0, off0, ins0 = 0.2, 0.0, 0.0, 0.0, (0, 0), START_INSERTION
    for site in ORDER:
        roll, tilt, yaw, off, ins, pre, excess = aim(centres[site])
        cut = base_cut(centres[site], (roll, tilt, yaw, off, ins))
        pre -= cut
        lin = abs(ins - ins0) + math.hypot(off[0] - off0[0], off[1] - off0[1])
        ang = abs(roll - roll0) + abs(tilt - tilt0) + abs(yaw - yaw0)
        over = max(0.3, lin / PROBE_MM_S, ang / PROBE_DEG_S)
        lines.append(f"  # {site}: centre {', '.join(f'{c:.1f}' for c in centres[site])} mm; "
                     f"the probe {excess:.1f} mm past the lumen at rest"
                     + (f", the notch {cut:.1f} mm short of the centre (the bladder neck)" if cut > 0 else ""))
        lines.append(f"  - {{t: {t:.2f}, probe: {{insertion_mm: {ins:.2f}, offset_mm: [{off[0]}, {off[1]}, 0], "
                     f"roll_deg: {roll:.2f}, tilt_deg: {tilt:.2f}, yaw_deg: {yaw:.2f}}}, over_s: {over:.2f}}}")
        t += over + 0.1
        t_in = t + pre / ADVANCE_MM_S
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: 0}}")
        lines.append(f"  - {{t: {t_in:.2f}, needle: biopsy_1, depth_mm: {pre:.2f}}}")
        # held there: a depth key moves the needle toward the next key, and the next one (after the
        # core) counts the throw, so the advance at speed 0 keeps the tip still until the gun fires
        lines.append(f"  - {{t: {t_in:.2f}, advance: biopsy_1, speed_mm_s: 0}}")
        t = t_in + 0.05
        lines.append(f"  - {{t: {t:.2f}, fire: biopsy_1}}")
        t += 0.1  # the throw (15 ms) and the core (5 ms after), held: the tip at the depth plus the throw
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: {pre + STROKE:.2f}}}")
        t += (pre + STROKE) / WITHDRAW_MM_S
        lines.append(f"  - {{t: {t:.2f}, needle: biopsy_1, depth_mm: 0}}")
        t += 0.1
        roll0, tilt0, yaw0, off0, ins0 = roll, tilt, yaw, off, ins
    print(HEADER, end="")
    print("scenario: biopsy")
    print(f"duration_s: {t + 0.2:.2f}")
    print("timeline:")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
