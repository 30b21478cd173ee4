#!/usr/bin/env python3
"""Independent CalculiX (ccx) references for the ProstateSim validation cases
``punch_halfspace`` and ``sphere_indentation`` (app/checks/validate_indentation.cpp).

A block of a linear elastic, nearly incompressible solid (E = 10 kPa,
nu = 0.49, small deformation) stands on a bonded base (z = 0: ux=uy=uz=0).
Only the quarter x, y in [0, 60] mm, z in [0, 60] mm is meshed: the planes
x = 0 (ux = 0) and y = 0 (uy = 0) are planes of symmetry, so the full block
is 120 x 120 x 60 mm with the load at the centre of its top face z = 60.

  punch   rigid flat frictionless circular punch of radius a = 10 mm pressed
          d = 2 mm: top nodes with r <= a get uz = -d (ux, uy free).
          Boussinesq (half-space): u_z(r) = (2d/pi) asin(a/r) for r > a,
          force 2 a d E/(1 - nu^2).
  sphere  rigid frictionless sphere of radius R = 40 mm pressed to depths
          1.5 mm and 3 mm (Hertz contact radius sqrt(R d) = 7.7, 11.0 mm).
          Contact is solved by an active set around ccx: a top node is in
          contact when the sphere surface z_s(x + ux, y + uy) is below it;
          contact nodes get uz = z_s - 60; a node whose reaction pulls the
          surface up is released; repeat until the set does not change.
          Hertz (half-space): F = (4/3) E/(1 - nu^2) sqrt(R) d^1.5.

Mesh: C3D8I bricks (incompatible modes: no volumetric or shear locking at
nu = 0.49) on a tensor grid whose lines pass through every multiple of
5 mm; inside x, y < 20 mm and z > 40 mm (the loaded corner) the grid step
is 2.5/k mm.  --k 1, 2, 4 is the refinement study; the file written for the
simulator is the finest run (k = 4 by default).

Output (--out FILE): the displacement of every node on the 5 mm grid,
"x y z ux uy uz" in mm (the simulator samples its particles there, so no
interpolation), after a header with the case, the load and the total force
on the indenter (full block, N).

Usage (python3 only, standard library; needs `ccx` on PATH):
    python3 docs/reference/indent_fem.py --case punch --k 4 --out docs/reference/punch_fem_field.txt
    python3 docs/reference/indent_fem.py --case sphere --k 4 --out docs/reference/sphere_fem_field.txt
    python3 docs/reference/indent_fem.py --study --k 8 --case punch --out ...  # k = 1, 2, 4, 8 and the field change between them
"""
import argparse
import math
import os
import shutil
import subprocess
import tempfile
import time

W = 60.0        # quarter block half-width [mm]
H = 60.0        # block height [mm]
FINE_XY = 20.0  # refined region x, y < FINE_XY
FINE_Z = 40.0   # ... and z > FINE_Z
GRID = 5.0       # output grid step [mm]: every multiple of it is a node
E = 0.01        # [MPa] = 10 kPa
NU = 0.49
PUNCH_A, PUNCH_D = 10.0, 2.0
SPHERE_R, SPHERE_DEPTHS = 40.0, (1.5, 3.0)


def axis(lo, hi, fine_lo, fine_hi, k):
    """Grid coordinates on [lo, hi]: step GRID, GRID/k inside [fine_lo, fine_hi]."""
    out = [lo]
    x = lo
    while x < hi - 1e-9:
        step = GRID / k if fine_lo - 1e-9 <= x < fine_hi - 1e-9 else GRID
        x = round(x + step, 9)
        out.append(x)
    return out


def build(k):
    cx = axis(0.0, W, 0.0, FINE_XY, k)
    cz = axis(0.0, H, FINE_Z, H, k)
    nx, nz = len(cx), len(cz)
    nid = lambda i, j, l: 1 + i + nx * (j + nx * l)
    nodes = {nid(i, j, l): (cx[i], cx[j], cz[l]) for l in range(nz) for j in range(nx) for i in range(nx)}
    elems = []
    for l in range(nz - 1):
        for j in range(nx - 1):
            for i in range(nx - 1):
                elems.append([nid(i, j, l), nid(i + 1, j, l), nid(i + 1, j + 1, l), nid(i, j + 1, l),
                              nid(i, j, l + 1), nid(i + 1, j, l + 1), nid(i + 1, j + 1, l + 1), nid(i, j + 1, l + 1)])
    return nodes, elems


def on_grid(c):
    return abs(c / GRID - round(c / GRID)) < 1e-9


def nset(f, name, ids):
    f.write("*NSET,NSET=%s\n" % name)
    for a in range(0, len(ids), 12):
        f.write(",".join(str(i) for i in ids[a:a + 12]) + "\n")


def write_deck(path, nodes, elems, held):
    """held: {node: uz} prescribed on the top face."""
    sel = lambda f: sorted(i for i, p in nodes.items() if f(p))
    with open(path, "w") as f:
        f.write("** units: mm, N, MPa\n*NODE\n")
        for i in sorted(nodes):
            f.write("%d,%.10g,%.10g,%.10g\n" % ((i,) + nodes[i]))
        f.write("*ELEMENT,TYPE=C3D8I,ELSET=EALL\n")
        for e, conn in enumerate(elems, 1):
            f.write(",".join(map(str, [e] + conn)) + "\n")
        nset(f, "NBOT", sel(lambda p: p[2] < 1e-9))
        nset(f, "NX0", sel(lambda p: p[0] < 1e-9))
        nset(f, "NY0", sel(lambda p: p[1] < 1e-9))
        nset(f, "NTOP", sel(lambda p: p[2] > H - 1e-9))
        nset(f, "NOUT", sel(lambda p: on_grid(p[0]) and on_grid(p[1]) and on_grid(p[2])))
        nset(f, "NCON", sorted(held))
        f.write("*MATERIAL,NAME=TISSUE\n*ELASTIC\n%.10g,%.10g\n" % (E, NU))
        f.write("*SOLID SECTION,ELSET=EALL,MATERIAL=TISSUE\n")
        f.write("*STEP\n*STATIC\n*BOUNDARY\nNBOT,1,3,0.\nNX0,1,1,0.\nNY0,2,2,0.\n")
        for i in sorted(held):
            f.write("%d,3,3,%.10g\n" % (i, held[i]))
        f.write("*NODE PRINT,NSET=NTOP\nU\n*NODE PRINT,NSET=NOUT\nU\n*NODE PRINT,NSET=NCON\nRF\n*END STEP\n")


def parse_dat(path):
    u, rf, block = {}, {}, None
    with open(path) as f:
        for line in f:
            t = line.strip()
            if not t:
                continue
            if t.startswith("displacements"):
                block = "u"
                continue
            if t.startswith("forces"):
                block = "rf"
                continue
            if t[0].isalpha():
                block = None
                continue
            v = t.split()
            if block and len(v) == 4:
                (u if block == "u" else rf)[int(v[0])] = tuple(float(a) for a in v[1:])
    return u, rf


def ccx(work, tag, nodes, elems, held, threads):
    inp = os.path.join(work, tag + ".inp")
    write_deck(inp, nodes, elems, held)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_EQUATION_SOLVER=str(threads),
               CCX_NPROC_RESULTS=str(threads), CCX_NPROC_STIFFNESS=str(threads))
    p = subprocess.run(["ccx", "-i", tag], cwd=work, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    dat = os.path.join(work, tag + ".dat")
    if p.returncode != 0 or "*ERROR" in p.stdout or not os.path.exists(dat):
        raise RuntimeError("ccx failed for %s in %s:\n%s" % (tag, work, "\n".join(p.stdout.splitlines()[-15:])))
    return parse_dat(dat)


def sphere_z(x, y, d):
    """Lowest point of the sphere surface above (x, y) [mm], or None outside its radius."""
    r2 = x * x + y * y
    if r2 >= SPHERE_R * SPHERE_R:
        return None
    return H - d + SPHERE_R - math.sqrt(SPHERE_R * SPHERE_R - r2)


def solve(case, k, depth, threads=2, keep=None):
    nodes, elems = build(k)
    work = keep or tempfile.mkdtemp(prefix="ccx_indent_")
    os.makedirs(work, exist_ok=True)
    top = [i for i, p in nodes.items() if p[2] > H - 1e-9]
    t0 = time.time()
    iters = 0
    if case == "punch":
        held = {i: -depth for i in top if math.hypot(nodes[i][0], nodes[i][1]) <= PUNCH_A + 1e-9}
        u, rf = ccx(work, "punch_k%d" % k, nodes, elems, held, threads)
        iters = 1
    else:
        held = {}
        for i in top:
            zs = sphere_z(nodes[i][0], nodes[i][1], depth)
            if zs is not None and zs < H:
                held[i] = zs - H
        while True:
            iters += 1
            u, rf = ccx(work, "sphere_k%d_d%g" % (k, depth), nodes, elems, held, threads)
            new = {}
            for i in top:
                x, y, z = nodes[i]
                ux, uy, uz = u[i]
                zs = sphere_z(x + ux, y + uy, depth)
                if zs is None:
                    continue
                if i in held:
                    if rf[i][2] > 0.0:  # the sphere would pull the surface up: release
                        continue
                    new[i] = zs - z
                elif z + uz > zs + 1e-9:  # penetrates: add
                    new[i] = zs - z
            changed = set(new) != set(held)
            shift = max([abs(new[i] - held.get(i, 0.0)) for i in new] + [0.0])
            held = new
            if (not changed and shift < 1e-6) or iters >= 20:
                break
    force = -4.0 * sum(rf[i][2] for i in held)  # quarter -> full block, on the indenter [N]
    out = {i: u[i] for i, p in nodes.items() if on_grid(p[0]) and on_grid(p[1]) and on_grid(p[2])}
    if keep is None:
        shutil.rmtree(work, ignore_errors=True)
    return dict(case=case, k=k, depth=depth, nodes=nodes, out=out, force=force, held=len(held),
                iters=iters, nnode=len(nodes), nelem=len(elems), wall=time.time() - t0)


def analytic_force(case, depth):
    Es = E / (1 - NU * NU)
    if case == "punch":
        return 2 * PUNCH_A * depth * Es
    return 4.0 / 3.0 * Es * math.sqrt(SPHERE_R) * depth ** 1.5


def write_field(path, res, extra):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("# ProstateSim reference field, docs/reference/indent_fem.py (CalculiX %s)\n" % "C3D8I")
        f.write("# case %s k %d nodes %d elements %d E_kPa %g nu %g\n"
                % (res["case"], res["k"], res["nnode"], res["nelem"], E * 1000, NU))
        for line in extra:
            f.write("# " + line + "\n")
        f.write("# x_mm y_mm z_mm ux_mm uy_mm uz_mm (quarter block, grid %g mm)\n" % GRID)
        for i in sorted(res["out"], key=lambda i: (res["nodes"][i][2], res["nodes"][i][1], res["nodes"][i][0])):
            p = res["nodes"][i]
            f.write("%g %g %g %.6g %.6g %.6g\n" % (p + res["out"][i]))
    os.replace(tmp, path)


def field_change(a, b):
    """RMS and max |u_a - u_b| over the shared grid nodes, relative to max |u_b|."""
    pa = {a["nodes"][i]: v for i, v in a["out"].items()}
    pb = {b["nodes"][i]: v for i, v in b["out"].items()}
    umax = max(math.sqrt(sum(c * c for c in v)) for v in pb.values())
    d = [math.sqrt(sum((x - y) ** 2 for x, y in zip(pa[p], pb[p]))) for p in pb if p in pa]
    return math.sqrt(sum(x * x for x in d) / len(d)) / umax, max(d) / umax


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", choices=["punch", "sphere"])
    ap.add_argument("--k", type=int, default=4)
    ap.add_argument("--out")
    ap.add_argument("--study", action="store_true")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--keep")
    a = ap.parse_args()
    cases = [a.case] if a.case else ["punch", "sphere"]
    ks = ([1, 2, 4, 8][:[1, 2, 4, 8].index(a.k) + 1] if a.k in (1, 2, 4, 8) else [a.k]) if a.study else [a.k]
    print("%-7s %2s %6s %7s %7s %9s %9s %6s %5s %7s %s" % ("case", "k", "depth", "nodes", "elems", "force[N]",
                                                           "analytic", "held", "iters", "t[s]", "field change vs previous k (rms, max)"))
    for case in cases:
        depths = [PUNCH_D] if case == "punch" else list(SPHERE_DEPTHS)
        prev = None
        for k in ks:
            runs = [solve(case, k, d, a.threads, a.keep) for d in depths]
            for r in runs:
                print("%-7s %2d %6g %7d %7d %9.5f %9.5f %6d %5d %7.1f" % (case, k, r["depth"], r["nnode"], r["nelem"],
                                                                       r["force"], analytic_force(case, r["depth"]),
                                                                       r["held"], r["iters"], r["wall"]), end="")
                print("")
            last = runs[-1]
            if prev is not None:
                rms, mx = field_change(prev, last)
                print("        field change k=%d -> k=%d at depth %g: rms %.4f, max %.4f of max|u|" % (prev["k"], k, last["depth"], rms, mx))
            prev = last
            if a.out and k == ks[-1]:
                extra = ["%s depth_mm %g force_N %.6g analytic_force_N %.6g" % (case, r["depth"], r["force"], analytic_force(case, r["depth"])) for r in runs]
                write_field(a.out, last, extra)


if __name__ == "__main__":
    main()
