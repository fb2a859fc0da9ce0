#!/usr/bin/env python3
"""Does the same shape get the same tour? (issue 37; results in docs/EVALUATION.md, "The same tour for the same shape")

Runs `meshtour path --path feature-orbit` (the tour's default path) with the default settings (or the
ones given after --) on a base mesh and on
other files of the same shape (the base split 1-to-4 at edge midpoints, or the same model in another
file format), exports every frame's camera (--camera-frames) and compares each frame's view
direction with the base's: elevation above the plane perpendicular to the model's up axis, and
azimuth around that axis, of the eye about the target. The goal is every frame within 1 degree of
elevation and 2 degrees of azimuth.

  bench/tour_consistency.py [--meshtour BIN] [--work DIR] [--up AXIS] BASE OTHER... [-- PATH-ARGS]
  bench/tour_consistency.py --splits LEVELS [--meshtour BIN] [--up AXIS] BASE [-- PATH-ARGS]

--splits "1 2" writes BASE split 1, 2, ... times (binary PLY, float x y z, triangles) into the work
folder and compares each with BASE. --up gives the axis for the angles (x, y, z, -x, ...; default:
the up vector of the base path's first camera, which is the model's up axis for every path mode)
and is passed to meshtour too when given. Needs only Python 3's standard library. Splitting a
4.5M-face mesh here takes minutes and several GB: for the bunny's big levels use the PLY files
`build-test/bench/load_bench --benchmark_filter='Ply/N/'` writes to build-test/bench-meshes/.
"""
import argparse
import csv
import math
import os
import struct
import subprocess
import sys
import tempfile
import time

PLY_TYPES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
             "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
             "double": "d", "float64": "d"}


def read_ply(path):
    """Positions and triangles of a binary little-endian or ASCII PLY (other properties skipped)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    while data[end:end + 1] in (b"\r", b"\n"):
        end += 1
    header = data[:end].decode("ascii", "replace").splitlines()
    fmt, elements = None, []
    for line in header:
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append([w[1], int(w[2]), []])
        elif w[0] == "property":
            elements[-1][2].append(w[1:])
    if fmt not in ("binary_little_endian", "ascii"):
        sys.exit(f"tour_consistency: {path}: PLY format {fmt} is not read here (binary_little_endian or ascii)")
    positions, triangles = [], []
    if fmt == "ascii":
        tokens = data[end:].split()
        pos = 0
        for name, count, props in elements:
            for _ in range(count):
                values = {}
                for p in props:
                    if p[0] == "list":
                        n = int(tokens[pos]); pos += 1
                        values[p[3]] = [int(t) for t in tokens[pos:pos + n]]; pos += n
                    else:
                        values[p[1]] = float(tokens[pos]); pos += 1
                if name == "vertex":
                    positions.append((values["x"], values["y"], values["z"]))
                elif name == "face":
                    idx = values.get("vertex_indices", values.get("vertex_index"))
                    for k in range(1, len(idx) - 1):
                        triangles.append((idx[0], idx[k], idx[k + 1]))
        return positions, triangles
    pos = end
    for name, count, props in elements:
        if all(p[0] != "list" for p in props):
            row = struct.Struct("<" + "".join(PLY_TYPES[p[0]] for p in props))
            names = [p[1] for p in props]
            ix, iy, iz = (names.index(c) for c in "xyz") if name == "vertex" else (0, 0, 0)
            for values in row.iter_unpack(data[pos:pos + row.size * count]):
                if name == "vertex":
                    positions.append((values[ix], values[iy], values[iz]))
            pos += row.size * count
            continue
        for _ in range(count):
            for p in props:
                if p[0] == "list":
                    cs, ts = struct.Struct("<" + PLY_TYPES[p[1]]), PLY_TYPES[p[2]]
                    (n,) = cs.unpack_from(data, pos); pos += cs.size
                    vs = struct.Struct("<" + ts * n)
                    idx = vs.unpack_from(data, pos); pos += vs.size
                    if name == "face":
                        for k in range(1, n - 1):
                            triangles.append((idx[0], idx[k], idx[k + 1]))
                else:
                    pos += struct.calcsize("<" + PLY_TYPES[p[0]])
    return positions, triangles


def split_at_midpoints(positions, triangles):
    """Every triangle into four at its edges' midpoints (the shape stays the same)."""
    positions = list(positions)
    midpoint = {}

    def mid(a, b):
        key = (a, b) if a < b else (b, a)
        m = midpoint.get(key)
        if m is None:
            pa, pb = positions[a], positions[b]
            m = len(positions)
            positions.append(((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2))
            midpoint[key] = m
        return m

    out = []
    for a, b, c in triangles:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return positions, out


def write_ply(path, positions, triangles):
    with open(path + ".part", "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                 "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                 % (len(positions), len(triangles))).encode())
        f.write(b"".join(struct.pack("<fff", *p) for p in positions))
        f.write(b"".join(struct.pack("<Biii", 3, *t) for t in triangles))
    os.replace(path + ".part", path)


AXES = {"x": (1, 0, 0), "y": (0, 1, 0), "z": (0, 0, 1), "-x": (-1, 0, 0), "-y": (0, -1, 0), "-z": (0, 0, -1)}


def cameras(meshtour, mesh, work, extra):
    out = os.path.join(work, os.path.basename(mesh) + ".cameras.csv")
    cmd = [meshtour, "path", mesh, "--camera-frames", out, "-q"] + extra
    start = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"tour_consistency: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr.strip()}")
    with open(out) as f:
        rows = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]
    return rows, time.monotonic() - start


def angles(row, up):
    d = [row["eye_" + c] - row["target_" + c] for c in "xyz"]
    n = math.sqrt(sum(v * v for v in d))
    d = [v / n for v in d]
    elevation = math.degrees(math.asin(max(-1.0, min(1.0, sum(a * b for a, b in zip(d, up))))))
    # A right-handed frame of the plane perpendicular to up, for the azimuth.
    ref = (0, 0, 1) if abs(up[2]) < 0.9 else (0, -1, 0)
    dot = sum(a * b for a, b in zip(ref, up))
    e1 = [r - dot * u for r, u in zip(ref, up)]
    n1 = math.sqrt(sum(v * v for v in e1))
    e1 = [v / n1 for v in e1]
    e2 = [up[1] * e1[2] - up[2] * e1[1], up[2] * e1[0] - up[0] * e1[2], up[0] * e1[1] - up[1] * e1[0]]
    azimuth = math.degrees(math.atan2(sum(a * b for a, b in zip(d, e2)), sum(a * b for a, b in zip(d, e1))))
    return elevation, azimuth


def main():
    argv = sys.argv[1:]
    extra = []
    if "--" in argv:
        extra = argv[argv.index("--") + 1:]
        argv = argv[:argv.index("--")]
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--meshtour", default=None, help="the meshtour binary (default: build-test/cli/meshtour, else build/cli/meshtour)")
    ap.add_argument("--work", default=None, help="folder for split meshes and camera files (default: a temporary one)")
    ap.add_argument("--splits", default=None, help='split levels to compare with BASE, e.g. "1 2"')
    ap.add_argument("--up", default=None, help="the model's up axis for the angles (and for meshtour)")
    ap.add_argument("--elevation-limit", type=float, default=1.0)
    ap.add_argument("--azimuth-limit", type=float, default=2.0)
    ap.add_argument("base")
    ap.add_argument("others", nargs="*")
    a = ap.parse_args(argv)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    meshtour = a.meshtour or next((p for p in (os.path.join(root, "build-test/cli/meshtour"), os.path.join(root, "build/cli/meshtour"))
                                   if os.access(p, os.X_OK)), None)
    if not meshtour:
        sys.exit("tour_consistency: no meshtour binary (build it, or pass --meshtour)")
    tmp = None
    work = a.work
    if not work:
        tmp = tempfile.TemporaryDirectory(prefix="tour-consistency-")
        work = tmp.name
    os.makedirs(work, exist_ok=True)
    if a.up:
        extra = ["--up", a.up] + extra
    if "--path" not in extra:  # `path` alone makes the paper's path; the tour's default is the feature orbit
        extra = ["--path", "feature-orbit"] + extra
    others = list(a.others)
    if a.splits:
        positions, triangles = read_ply(a.base)
        levels = sorted(int(s) for s in a.splits.split())
        level = 0
        for target in levels:
            while level < target:
                positions, triangles = split_at_midpoints(positions, triangles)
                level += 1
            out = os.path.join(work, os.path.splitext(os.path.basename(a.base))[0] + f"-split{level}.ply")
            if not os.path.exists(out):
                write_ply(out, positions, triangles)
            others.append(out)
    if not others:
        sys.exit("tour_consistency: nothing to compare with the base (give files or --splits)")
    base, base_s = cameras(meshtour, a.base, work, extra)
    up = AXES[a.up.lstrip("+")] if a.up and a.up.lstrip("+") in AXES else None
    if up is None:
        u = [base[0]["up_" + c] for c in "xyz"]
        n = math.sqrt(sum(v * v for v in u))
        up = [v / n for v in u]
    print(f"base {a.base}: {len(base)} frames, {base_s:.1f} s; up {tuple(round(v, 3) for v in up)}; path args: {' '.join(extra) or '(defaults)'}")
    print(f"{'file':<48} {'frames':>6} {'max d-elev':>10} {'max d-azim':>10} {'frame0 d-az':>11} {'seconds':>8}  result")
    failed = 0
    for other in others:
        rows, secs = cameras(meshtour, other, work, extra)
        if len(rows) != len(base):
            print(f"{os.path.basename(other):<48} {len(rows):>6} frame counts differ"); failed += 1; continue
        de = da = 0.0
        da0 = None
        for ra, rb in zip(base, rows):
            ea, aa = angles(ra, up)
            eb, ab = angles(rb, up)
            de = max(de, abs(ea - eb))
            turn = abs((aa - ab + 180.0) % 360.0 - 180.0)
            da = max(da, turn)
            if da0 is None:
                da0 = turn
        ok = de <= a.elevation_limit and da <= a.azimuth_limit
        failed += not ok
        print(f"{os.path.basename(other):<48} {len(rows):>6} {de:>10.3f} {da:>10.3f} {da0:>11.3f} {secs:>8.1f}  {'ok' if ok else 'DIFFERENT'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
