#!/usr/bin/env python3
"""The default scene's TRUS planes side by side (docs/ultrasound.md, docs/images/trus_planes.png).

Runs `prostatesim ultrasound` on config/biopsy.yaml (settled 0.1 s, the probe at its default pose)
and on copies of it with the probe turned about its axis, then tiles the planes, each halved to
256 x 256 px (2 x 2 mean), into one 8-bit grayscale PNG:

  row 1: transverse at the base, at mid-gland, at the apex (the plane moved back along the probe
         with --transverse-back-mm, as a stepper would step it; the tissue as the default pose
         deforms it)
  row 2: transverse at the seminal vesicles (the default pose's own plane), sagittal in the
         midline (the default pose), sagittal turned 25 degrees to the patient's right

    python3 scripts/us_planes_figure.py [--bin build/app/prostatesim] [--out docs/images/trus_planes.png]

Needs only the Python standard library (the PNGs are read and written with zlib).
"""
import argparse
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# transverse planes behind the tip-hemisphere centre [mm] at the default pose (tip at z = +26 mm):
# base z = +12, mid-gland z = 0, apex z = -14 mm (the gland spans z -21.5 .. +18.5 mm)
TRANSVERSE_BACK_MM = {"base": 14, "mid": 26, "apex": 40}


def read_gray_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, w = 8, b"", 0
    while pos < len(data):
        (n,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour != 0 or interlace != 0:
                sys.exit(f"{path}: expected an 8-bit grayscale, non-interlaced PNG")
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    raw, rows, prev = zlib.decompress(idat), [], bytearray(w)
    for j in range(h):
        f, line = raw[j * (w + 1)], bytearray(raw[j * (w + 1) + 1:(j + 1) * (w + 1)])
        for i in range(w):
            a = line[i - 1] if i else 0
            b, c = prev[i], prev[i - 1] if i else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return rows


def write_gray_png(path, rows):
    h, w = len(rows), len(rows[0])
    raw = b"".join(b"\x01" + bytes((r[i] - (r[i - 1] if i else 0)) & 255 for i in range(w)) for r in rows)  # filter: sub

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


def halve(rows):
    return [bytearray((rows[2 * j][2 * i] + rows[2 * j][2 * i + 1] + rows[2 * j + 1][2 * i] + rows[2 * j + 1][2 * i + 1] + 2) // 4
                      for i in range(len(rows[0]) // 2)) for j in range(len(rows) // 2)]


def scenario_copy(tmp, name, roll_deg):
    """config/biopsy.yaml with the probe turned by roll_deg and its mesh paths made absolute."""
    text = open(os.path.join(ROOT, "config", "biopsy.yaml")).read()
    text = text.replace("../assets/", os.path.join(ROOT, "assets") + "/")
    text, n = re.subn(r"pose: \{insertion_mm: ([0-9.]+)\}", r"pose: {insertion_mm: \1, roll_deg: %g}" % roll_deg, text)
    if n != 1:
        sys.exit("config/biopsy.yaml: no `pose: {insertion_mm: N}` line to turn the probe in")
    path = os.path.join(tmp, name + ".yaml")
    open(path, "w").write(text)
    return path


def ultrasound(binary, scenario, out, view, back_mm=0):
    subprocess.run([binary, "ultrasound", scenario, "--out", out, "--time", "0.1", "--views", view,
                    "--transverse-back-mm", str(back_mm)], check=True, stdout=subprocess.DEVNULL)
    return halve(read_gray_png(os.path.join(out, view + ".png")))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "app", "prostatesim"))
    ap.add_argument("--out", default=os.path.join(ROOT, "docs", "images", "trus_planes.png"))
    a = ap.parse_args()
    scen = os.path.join(ROOT, "config", "biopsy.yaml")
    with tempfile.TemporaryDirectory() as tmp:
        tiles = [ultrasound(a.bin, scen, os.path.join(tmp, k), "us_transverse", b) for k, b in TRANSVERSE_BACK_MM.items()]
        tiles.append(ultrasound(a.bin, scen, os.path.join(tmp, "sv"), "us_transverse"))
        tiles.append(ultrasound(a.bin, scen, os.path.join(tmp, "sag"), "us_sagittal"))
        # roll: positive turns the probe's anterior towards its lateral side, the patient's left
        tiles.append(ultrasound(a.bin, scenario_copy(tmp, "right", -25), os.path.join(tmp, "sag_right"), "us_sagittal"))
    gap = 4
    side = len(tiles[0])
    rows = []
    for r in range(2):
        for j in range(side):
            line = bytearray()
            for c in range(3):
                line += tiles[3 * r + c][j] + (bytearray(gap) if c < 2 else bytearray())
            rows.append(line)
        if r == 0:
            rows += [bytearray(len(rows[0])) for _ in range(gap)]
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    write_gray_png(a.out, rows)
    print(f"{a.out}: {len(rows[0])} x {len(rows)} px, {os.path.getsize(a.out) / 1024:.0f} KB")


if __name__ == "__main__":
    main()
