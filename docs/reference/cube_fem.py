#!/usr/bin/env python3
"""Independent CalculiX (ccx) reference for the ProstateSim validation case
``cube_bonded``.

An 80 mm cube of a nearly incompressible neo-Hookean solid (nu = 0.499,
E = 10 kPa unless told otherwise) is compressed by 10 mm (12.5 %) between two
rigid plates, geometric nonlinearity on (*STEP, NLGEOM).

  bonded        z=0: ux=uy=uz=0;  z=80: ux=uy=0, uz=-10   (no slip)
  frictionless  z=0: uz=0;        z=80: uz=-10, plus symmetry planes
                x=40 (ux=0) and y=40 (uy=0) to remove rigid motion
                -> analytic uniform bulge 40*(1/sqrt(0.875)-1) = 2.762 mm

Reported: ux of the node at the centre of face x=80 (y=40, z=40) and the
maximum ux over that face (mm).

CalculiX 2.20 (Debian calculix-ccx) has no hybrid (C3D8H/C3D20H) bricks, so
the locking-free element choices used are C3D8I (incompatible modes, linear)
and C3D20R (quadratic, reduced integration); fully integrated C3D20 is run too
as a cross-check.

The problem is symmetric about x=40 and y=40 and anti-symmetric about the
mid-height plane (z -> 80-z maps the solution onto itself after a rigid shift
of 10 mm), so --model quarter (x,y in [40,80]) and --model eighth (x,y in
[40,80], z in [0,40] with uz=-5 mm on z=40) give the full-cube answer at a
fraction of the cost; the study checks that, then refines the 1/8 model,
uniformly and graded toward the bonded edges (--bias).

Usage (python3 only, no extra packages; needs `ccx` on PATH):
    python3 docs/reference/cube_fem.py              # default study (~10 min)
    python3 docs/reference/cube_fem.py --study fine # slow extra meshes
    python3 docs/reference/cube_fem.py --case bonded --elem C3D20R --n 16 \
        --model eighth --bias 0.7                    # one run
    python3 docs/reference/cube_fem.py --keep DIR   # keep decks/results in DIR
"""
import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

L = 80.0          # cube edge, mm
DZ = 10.0         # plate travel, mm (12.5 %)
ANALYTIC_FRICTIONLESS = (L / 2.0) * (1.0 / math.sqrt(1.0 - DZ / L) - 1.0)

# C3D20 mid-edge nodes 9..20 as pairs of corner nodes (1-based, Abaqus order)
C3D20_EDGES = [(1, 2), (2, 3), (3, 4), (4, 1), (5, 6), (6, 7), (7, 8), (8, 5),
               (1, 5), (2, 6), (3, 7), (4, 8)]
# corner offsets (i,j,k) in units of one element, Abaqus/ccx ordering
CORNERS = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0),
           (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]


def axis_coords(a, b, ne, bias, quadratic):
    """Grid coordinates on [a, b] with ne elements.  The cube is graded
    symmetrically about its mid-plane (bias=0: uniform; bias>0 clusters
    elements toward the cube faces x,y,z = 0 and 80, where the bonded edges
    are).  Mid-side nodes of quadratic elements sit at the arithmetic mean of
    the corner coordinates, so every element stays an affine brick."""
    def g(x):  # map of [0, L] onto itself, fixed points 0, L/2, L
        t = x / L
        return L * ((1 - bias) * t + bias * 0.5 * (1 - math.cos(math.pi * t)))
    c = [g(a + (b - a) * i / ne) for i in range(ne + 1)]
    if not quadratic:
        return c
    out = []
    for i in range(ne):
        out += [c[i], 0.5 * (c[i] + c[i + 1])]
    return out + [c[-1]]


def build_mesh(n, quadratic, model, bias=0.0):
    """Structured hex mesh; n = elements per cube edge (full-cube equivalent).
    model: 'full'    x,y,z in [0,80]
           'quarter' x,y in [40,80], z in [0,80]   (symmetry x=40, y=40)
           'eighth'  x,y in [40,80], z in [0,40]   (symmetry x=40, y=40 and
                     the anti-symmetric mid-plane z=40: uz=-DZ/2, free ux,uy)
    Returns (nodes{id:(x,y,z)}, elements[[ids]])."""
    half = L / 2
    xa, ne_x = (0.0, n) if model == "full" else (half, n // 2)
    zb, ne_z = (L, n) if model != "eighth" else (half, n // 2)
    s = 2 if quadratic else 1
    cx = axis_coords(xa, L, ne_x, bias, quadratic)
    cz = axis_coords(0.0, zb, ne_z, bias, quadratic)
    ids, nodes = {}, {}

    def gid(i, j, k):
        key = (i, j, k)
        if key not in ids:
            nid = len(ids) + 1
            ids[key] = nid
            nodes[nid] = (cx[i], cx[j], cz[k])
        return ids[key]

    elems = []
    for k in range(ne_z):
        for j in range(ne_x):
            for i in range(ne_x):
                c = [(s * (i + a), s * (j + b), s * (k + d)) for a, b, d in CORNERS]
                conn = [gid(*p) for p in c]
                if quadratic:
                    for a, b in C3D20_EDGES:
                        pa, pb = c[a - 1], c[b - 1]
                        conn.append(gid(*[(u + v) // 2 for u, v in zip(pa, pb)]))
                elems.append(conn)
    return nodes, elems


def write_deck(path, case, elem, n, E, nu, model, material, ninc, bias):
    quadratic = elem.startswith("C3D20")
    nodes, elems = build_mesh(n, quadratic, model, bias)
    tol = 1e-6
    sel = lambda f: sorted(i for i, p in nodes.items() if f(p))
    bot = sel(lambda p: abs(p[2]) < tol)
    top = sel(lambda p: abs(p[2] - L) < tol)
    zmid = sel(lambda p: abs(p[2] - L / 2) < tol)
    face = sel(lambda p: abs(p[0] - L) < tol)
    xmid = sel(lambda p: abs(p[0] - L / 2) < tol)
    ymid = sel(lambda p: abs(p[1] - L / 2) < tol)
    centre = [i for i in face
              if abs(nodes[i][1] - L / 2) < tol and abs(nodes[i][2] - L / 2) < tol]
    if len(centre) != 1:
        raise SystemExit("mesh has no node at the face centre; use even n")

    def nset(f, name, ids):
        f.write("*NSET,NSET=%s\n" % name)
        for a in range(0, len(ids), 12):
            f.write(",".join(str(i) for i in ids[a:a + 12]) + "\n")

    mu = E / (2.0 * (1.0 + nu))
    K = E / (3.0 * (1.0 - 2.0 * nu))
    with open(path, "w") as f:
        f.write("** cube_%s  elem=%s n=%d E=%g MPa nu=%g model=%s bias=%g mat=%s\n"
                % (case, elem, n, E, nu, model, bias, material))
        f.write("** units: mm, N, MPa\n*NODE\n")
        for i in sorted(nodes):
            x, y, z = nodes[i]
            f.write("%d,%.10g,%.10g,%.10g\n" % (i, x, y, z))
        f.write("*ELEMENT,TYPE=%s,ELSET=EALL\n" % elem)
        for e, conn in enumerate(elems, 1):
            row = [e] + conn
            # ccx/Abaqus: at most 16 entries per data line
            f.write(",".join(map(str, row[:16])))
            if len(row) > 16:
                f.write(",\n" + ",".join(map(str, row[16:])))
            f.write("\n")
        nset(f, "NBOT", bot)
        nset(f, "NFACE", face)
        nset(f, "NCEN", centre)
        for name, ids in (("NTOP", top), ("NZMID", zmid), ("NXMID", xmid),
                          ("NYMID", ymid)):
            if ids:
                nset(f, name, ids)
        f.write("*MATERIAL,NAME=TISSUE\n")
        if material == "neohooke":
            # ccx/Abaqus: W = C10 (I1bar-3) + (J-1)^2 / D1,  mu = 2 C10, K = 2/D1
            f.write("*HYPERELASTIC,NEO HOOKE\n%.10g,%.10g\n" % (mu / 2.0, 2.0 / K))
        elif material == "mooney":
            # same initial shear modulus, split equally: mu = 2 (C10 + C01)
            f.write("*HYPERELASTIC,MOONEY-RIVLIN\n%.10g,%.10g,%.10g\n"
                    % (mu / 4.0, mu / 4.0, 2.0 / K))
        else:  # *ELASTIC under NLGEOM = St Venant-Kirchhoff
            f.write("*ELASTIC\n%.10g,%.10g\n" % (E, nu))
        f.write("*SOLID SECTION,ELSET=EALL,MATERIAL=TISSUE\n")
        f.write("*STEP,NLGEOM,INC=1000\n*STATIC\n%g,1.0,1e-6,%g\n"
                % (1.0 / ninc, 1.0 / ninc))
        f.write("*BOUNDARY\n")
        f.write("NBOT,1,3,0.\n" if case == "bonded" else "NBOT,3,3,0.\n")
        if model == "eighth":
            f.write("NZMID,3,3,%g\n" % (-DZ / 2))
        else:
            if case == "bonded":
                f.write("NTOP,1,2,0.\n")
            f.write("NTOP,3,3,%g\n" % (-DZ))
        if case == "frictionless" or model != "full":
            f.write("NXMID,1,1,0.\nNYMID,2,2,0.\n")
        f.write("*NODE PRINT,NSET=NFACE\nU\n")
        f.write("*NODE PRINT,NSET=NBOT,TOTALS=ONLY\nRF\n")
        f.write("*NODE FILE\nU\n")
        f.write("*END STEP\n")
    return nodes, centre[0], len(elems)


def parse_dat(path):
    """Return ({node: (ux,uy,uz)}, total RF on top) of the LAST increment."""
    disp, rf = {}, None
    block = None
    with open(path) as f:
        for line in f:
            t = line.strip()
            if not t:
                continue
            if t.startswith("displacements"):
                block, disp = "u", {}
                continue
            if t.startswith("total force"):
                block = "rf"
                continue
            if t[0].isalpha():
                block = None
                continue
            v = t.split()
            if block == "u" and len(v) == 4:
                disp[int(v[0])] = tuple(float(a) for a in v[1:])
            elif block == "rf" and len(v) == 3:
                rf = tuple(float(a) for a in v)
    return disp, rf


def run_one(case, elem, n, E=0.01, nu=0.499, model="full", material="neohooke",
            bias=0.0, ninc=5, keep=None, threads=2):
    tag = "cube_%s_%s_n%d_E%g_nu%g_%s_b%g_%s" % (case, elem, n, E * 1000, nu,
                                               model, bias, material)
    work = keep or tempfile.mkdtemp(prefix="ccx_cube_")
    os.makedirs(work, exist_ok=True)
    inp = os.path.join(work, tag + ".inp")
    nodes, cen, ne = write_deck(inp, case, elem, n, E, nu, model, material,
                                ninc, bias)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads),
               CCX_NPROC_EQUATION_SOLVER=str(threads),
               CCX_NPROC_RESULTS=str(threads), CCX_NPROC_STIFFNESS=str(threads))
    t0 = time.time()
    p = subprocess.run(["ccx", "-i", tag], cwd=work, env=env,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.time() - t0
    with open(os.path.join(work, tag + ".log"), "w") as f:
        f.write(p.stdout)
    dat = os.path.join(work, tag + ".dat")
    if p.returncode != 0 or "ERROR" in p.stdout or not os.path.exists(dat):
        tail = "\n".join(p.stdout.splitlines()[-15:])
        raise RuntimeError("ccx failed for %s (see %s):\n%s" % (tag, work, tail))
    face, rf = parse_dat(dat)
    imax = max(face, key=lambda i: face[i][0])
    # mean ux over the face sampled like the particle simulator: nodes on a
    # 10 mm grid of face x=80, plate rows z=0/80 excluded (weights restore the
    # whole face from the symmetry-reduced models).  Needs nodes at the grid
    # points (uniform meshes with n a multiple of 8); None otherwise.
    grid = {}
    for i, u in face.items():
        x, y, z = nodes[i]
        if (abs(y / 10 - round(y / 10)) < 1e-6 and abs(z / 10 - round(z / 10)) < 1e-6
                and 1e-6 < z < L - 1e-6):
            w = 1.0
            if model != "full" and abs(y - L / 2) > 1e-6:
                w *= 2
            if model == "eighth" and abs(z - L / 2) > 1e-6:
                w *= 2
            grid[(round(y), round(z))] = (w, u[0])
    expect = (9 if model == "full" else 5) * (7 if model != "eighth" else 4)
    mean10 = (sum(w * v for w, v in grid.values()) / sum(w for w, _ in grid.values())
              if len(grid) == expect else None)
    # plate force = reaction on the bottom plate, scaled to the whole cube
    sym = {"full": 1, "quarter": 4, "eighth": 4}[model]
    res = dict(case=case, elem=elem, n=n, E=E, nu=nu, model=model, bias=bias,
               material=material, nelem=ne, nnode=len(nodes),
               ux_cen=face[cen][0], ux_max=face[imax][0], at=nodes[imax], mean10=mean10,
               fz=abs(rf[2]) * sym if rf else float("nan"), wall=wall, dir=work)
    if keep is None:
        shutil.rmtree(work, ignore_errors=True)
    return res


HDR = ("%-12s %-6s %3s %6s %7s %-7s %4s %-5s %6s %6s %10s %10s %-13s %9s %6s %10s"
       % ("case", "elem", "n", "E[kPa]", "nu", "model", "bias", "mat", "elems",
          "nodes", "ux_cen[mm]", "ux_max[mm]", "at (y,z)", "|Fz|[N]", "t[s]",
          "mean10[mm]"))


def fmt(r):
    return ("%-12s %-6s %3d %6g %7g %-7s %4g %-5s %6d %6d %10.4f %10.4f "
            "(%4.1f,%5.2f) %9.4g %6.1f %10s"
            % (r["case"], r["elem"], r["n"], r["E"] * 1000, r["nu"], r["model"],
               r["bias"], r["material"][:5], r["nelem"], r["nnode"], r["ux_cen"],
               r["ux_max"], r["at"][1], r["at"][2], r["fz"], r["wall"],
               "-" if r["mean10"] is None else "%.4f" % r["mean10"]))


# studies: (case, elem, n, E[MPa], nu, model, material, bias)
# n = elements per 80 mm edge (full-cube equivalent).  Every run of the
# default study takes < ~1.5 min on 2 cores; "fine" adds the slow ones (2-10 min).
NH, MR, SVK = "neohooke", "mooney", "linear"
STUDY_DEFAULT = [
    # 1. deck check: frictionless -> uniform analytic bulge 2.762 mm
    ("frictionless", "C3D8I", 8, 0.01, 0.499, "full", NH, 0),
    ("frictionless", "C3D20R", 8, 0.01, 0.499, "full", NH, 0),
    ("frictionless", "C3D20R", 8, 0.01, 0.49999, "full", NH, 0),
    ("frictionless", "C3D20R", 8, 0.01, 0.499, "eighth", MR, 0),
    ("frictionless", "C3D20R", 8, 0.01, 0.499, "eighth", SVK, 0),
    # 2. bonded, full cube: the requested 8^3 / 16^3 linear and quadratic meshes
    #    (16^3 C3D8I as the identical 1/8 model: the full cube takes 50-150 s)
    ("bonded", "C3D8I", 8, 0.01, 0.499, "full", NH, 0),
    ("bonded", "C3D8I", 16, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D20", 8, 0.01, 0.499, "full", NH, 0),
    ("bonded", "C3D20R", 8, 0.01, 0.499, "full", NH, 0),
    # 3. E independence (displacement-only loading)
    ("bonded", "C3D20R", 8, 0.02, 0.499, "full", NH, 0),
    ("bonded", "C3D20R", 8, 1.0, 0.499, "full", NH, 0),
    # 4. the symmetry-reduced models reproduce the full cube exactly
    ("bonded", "C3D20R", 8, 0.01, 0.499, "quarter", NH, 0),
    ("bonded", "C3D20R", 8, 0.01, 0.499, "eighth", NH, 0),
    # 5. uniform refinement (1/8 model)
    ("bonded", "C3D8I", 24, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D20R", 12, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D20R", 16, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D20R", 20, 0.01, 0.499, "eighth", NH, 0),
    # 6. refinement graded toward the bonded edges (1/8 model)
    ("bonded", "C3D20R", 12, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D20R", 16, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D20R", 20, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D20R", 8, 0.01, 0.499, "eighth", NH, 1.0),
    ("bonded", "C3D20R", 12, 0.01, 0.499, "eighth", NH, 1.0),
    ("bonded", "C3D20R", 16, 0.01, 0.499, "eighth", NH, 1.0),
    # 7. sensitivity: compressibility and material law (same mesh as 6, n=12)
    ("bonded", "C3D20R", 12, 0.01, 0.4999, "eighth", NH, 0.7),
    ("bonded", "C3D20R", 12, 0.01, 0.499, "eighth", MR, 0.7),
    ("bonded", "C3D20R", 12, 0.01, 0.499, "eighth", SVK, 0.7),
]
STUDY_FINE = [
    ("bonded", "C3D8I", 16, 0.01, 0.499, "full", NH, 0),
    ("bonded", "C3D20R", 16, 0.01, 0.499, "full", NH, 0),
    ("bonded", "C3D20R", 24, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D8I", 32, 0.01, 0.499, "eighth", NH, 0),
    ("bonded", "C3D8I", 16, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D8I", 24, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D8I", 32, 0.01, 0.499, "eighth", NH, 0.7),
    ("bonded", "C3D20R", 20, 0.01, 0.499, "eighth", NH, 1.0),
    ("bonded", "C3D20R", 16, 0.01, 0.4999, "eighth", NH, 0.7),
]


def richardson(pts):
    """Three (n, f) points, n = elements per edge -> (observed order p,
    extrapolated f) assuming f(n) = f_inf + C n^-p.  None when the three
    points do not fit that form (not monotone, or the differences shrink faster
    than any power of n allows: pre-asymptotic)."""
    (n1, f1), (n2, f2), (n3, f3) = sorted(pts)
    if (f1 - f2) * (f2 - f3) <= 0:
        return None
    r = (f1 - f2) / (f2 - f3)
    g = lambda p: (n1 ** -p - n2 ** -p) / (n2 ** -p - n3 ** -p) - r
    lo, hi = 0.05, 8.0
    if g(lo) * g(hi) > 0:
        return None
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if g(lo) * g(mid) > 0 else (lo, mid)
    p = 0.5 * (lo + hi)
    return p, f3 - (f2 - f3) * n3 ** -p / (n2 ** -p - n3 ** -p)


def summarize(results):
    series = {}
    for r in results:
        if r["case"] != "bonded" or r["E"] != 0.01:
            continue
        key = (r["elem"], r["bias"], r["nu"], r["material"])
        series.setdefault(key, {})[r["n"]] = r["ux_cen"]
    print("\nRichardson extrapolation of the bonded mid-face bulge "
          "(three finest meshes of each series):")
    for (elem, bias, nu, mat), d in sorted(series.items()):
        if len(d) < 3:
            continue
        pts = sorted(d.items())[-3:]
        rr = richardson(pts)
        txt = ("no fit: not in the asymptotic range" if rr is None
               else "order p = %.2f  ->  extrapolated %.4f mm" % rr)
        print("  %-6s bias %-3g nu %-6g %-8s n = %-12s %s"
              % (elem, bias, nu, mat, ",".join(str(n) for n, _ in pts), txt))


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--study", choices=["default", "fine", "all"], default="default",
                    help="which list of runs (ignored with --case); 'fine' holds "
                         "the slow runs (2-10 min each)")
    ap.add_argument("--case", choices=["bonded", "frictionless"],
                    help="run one case instead of a study")
    ap.add_argument("--elem", default="C3D20R",
                    choices=["C3D8", "C3D8I", "C3D8R", "C3D20", "C3D20R"])
    ap.add_argument("--n", type=int, default=8,
                    help="elements per 80 mm edge, full-cube equivalent (even; "
                         "multiple of 4 for --model eighth/quarter with C3D8*)")
    ap.add_argument("--E", type=float, default=0.01, help="Young's modulus, MPa")
    ap.add_argument("--nu", type=float, default=0.499)
    ap.add_argument("--model", choices=["full", "quarter", "eighth"], default="full")
    ap.add_argument("--bias", type=float, default=0.0,
                    help="mesh grading toward the cube faces, 0..1 (0 = uniform)")
    ap.add_argument("--material", choices=["neohooke", "mooney", "linear"],
                    default="neohooke")
    ap.add_argument("--ninc", type=int, default=5, help="load increments")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--keep", help="directory to keep decks and results in")
    a = ap.parse_args()
    if shutil.which("ccx") is None:
        sys.exit("ccx not found on PATH (Debian: apt-get install calculix-ccx)")
    if a.case:
        runs = [(a.case, a.elem, a.n, a.E, a.nu, a.model, a.material, a.bias)]
    else:
        runs = {"default": STUDY_DEFAULT, "fine": STUDY_FINE,
                "all": STUDY_DEFAULT + STUDY_FINE}[a.study]
    print("ccx reference for cube_bonded: L=%g mm, plate travel %g mm (%.1f %%), "
          "NLGEOM, %d increments" % (L, DZ, 100 * DZ / L, a.ninc))
    print("analytic frictionless (incompressible) bulge per face: %.4f mm"
          % ANALYTIC_FRICTIONLESS)
    print("ux_cen: node (80,40,40); ux_max: max ux on face x=80 and where; "
          "mean10: mean ux on the 10 mm grid of that face, plate rows excluded")
    print(HDR)
    results = []
    for case, elem, n, E, nu, model, mat, bias in runs:
        r = run_one(case, elem, n, E, nu, model, mat, bias, a.ninc, a.keep,
                    a.threads)
        results.append(r)
        print(fmt(r), flush=True)
    summarize(results)


if __name__ == "__main__":
    main()
