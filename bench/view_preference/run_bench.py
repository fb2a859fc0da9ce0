#!/usr/bin/env python3
"""Measures the tour's first frame against the view-preference labels (issue 37).

For every model of labels.json found on disk, runs

    meshtour path MODEL --path feature-orbit --up U --camera-frames FRAMES.csv -o PATH.json

(the path `meshtour tour MODEL --up U` renders, with the tour's default frames, size and lens; no
rendering), takes frame 0's eye direction about its target in the labels' convention (labels.json
"convention": azimuth from the turntable's front F counter-clockwise seen from the up axis U,
elevation above the plane through the target), and prints per model the chosen and the labelled
view, the angle between the two directions (the nearer of azimuth_deg and mirror_azimuth_deg),
pass or fail at 30 degrees, and the pass rate over the models measured. `--first-view best-covering`
measures the rule before the view preference (the view that covers most) the same way.

The models: the six shared meshes in ../shared/meshes (beside the repository) and the files that
fetch_models.sh writes into a directory (default ./view-preference-models). Each file's SHA-256 is
checked against labels.json; a model whose file is missing or differs is listed and not counted.

Usage: bench/view_preference/run_bench.py [--models DIR] [--shared DIR] [--meshtour BIN]
                                          [--first-view preferred|best-covering]
                                          [--threads N] [--only NAME,...] [--json OUT]
Not used by CI (it needs the models and a Release build; a few minutes on two cores).
"""
import argparse
import csv
import hashlib
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PASS_DEG = 30.0


def fetched_names():
    """(repository, path) -> file name written by fetch_models.sh (FBX: the Blender OBJ)."""
    names = {}
    with open(os.path.join(HERE, "fetch_models.sh")) as f:
        for line in f:
            m = re.match(r'\s*"(\S+) ([0-9a-f]{40}) (\S+) (\S+)"\s*$', line)
            if m:
                repo, _, path, name = m.groups()
                if name.endswith(".fbx"):
                    name = "ds_" + name[:-4] + ".obj"
                names[(repo, path)] = name
    return names


def axis(name):
    """'+y' -> (1, +1.0): index and sign of a signed coordinate axis."""
    return "xyz".index(name[1]), (1.0 if name[0] == "+" else -1.0)


def unit(i, sign=1.0):
    v = [0.0, 0.0, 0.0]
    v[i] = sign
    return v


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def normalized(a):
    n = math.sqrt(dot(a, a))
    return [x / n for x in a]


def frame_of(up):
    """U, F, S of the convention: F = +Z for a +-x or +-y up, -Y for a +-z up; S = U x F."""
    i, sign = axis(up)
    u = unit(i, sign)
    f = unit(2) if i in (0, 1) else unit(1, -1.0)
    return u, f, cross(u, f)


def direction(az_deg, el_deg, up):
    u, f, s = frame_of(up)
    az, el = math.radians(az_deg), math.radians(el_deg)
    return [math.cos(el) * (math.cos(az) * fi + math.sin(az) * si) + math.sin(el) * ui for ui, fi, si in zip(u, f, s)]


def angles(d, up):
    u, f, s = frame_of(up)
    az = math.degrees(math.atan2(dot(d, s), dot(d, f))) % 360.0
    el = math.degrees(math.asin(max(-1.0, min(1.0, dot(d, u)))))
    return az, el


def angle_between(a, b):
    return math.degrees(math.acos(max(-1.0, min(1.0, dot(normalized(a), normalized(b))))))


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.file_digest(f, "sha256").hexdigest()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", default="view-preference-models", help="directory fetch_models.sh wrote")
    ap.add_argument("--shared", default=os.path.join(ROOT, "..", "shared", "meshes"), help="the shared meshes")
    ap.add_argument("--meshtour", default=os.path.join(ROOT, "build-test", "cli", "meshtour"))
    ap.add_argument("--first-view", default="preferred", choices=["preferred", "best-covering"])
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--only", default="", help="comma-separated model names")
    ap.add_argument("--json", default="", help="also write the rows as JSON")
    args = ap.parse_args()

    labels = json.load(open(os.path.join(HERE, "labels.json")))
    names = fetched_names()
    only = set(filter(None, args.only.split(",")))
    rows, skipped = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for m in labels["models"]:
            if only and m["name"] not in only:
                continue
            if m["repository"].startswith(".."):
                path = os.path.join(args.shared, m["path"])
            else:
                path = os.path.join(args.models, names[(m["repository"], m["path"])])
            if not os.path.exists(path):
                skipped.append((m["name"], "missing: " + path))
                continue
            if sha256(path) != m["sha256"]:
                skipped.append((m["name"], "SHA-256 differs from labels.json: " + path))
                continue
            frames = os.path.join(tmp, m["name"] + ".csv")
            cmd = [args.meshtour, "path", path, "--path", "feature-orbit", "--up", m["up"], "--first-view", args.first_view,
                   "--threads", str(args.threads),
                   "-o", os.path.join(tmp, m["name"] + ".path.json"), "--camera-frames", frames]
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                skipped.append((m["name"], "meshtour failed: " + run.stderr.strip().splitlines()[-1]))
                continue
            with open(frames) as f:
                cameras = list(csv.DictReader(f))
            candidates = [m["azimuth_deg"]] + ([m["mirror_azimuth_deg"]] if "mirror_azimuth_deg" in m else [])

            def measured(camera):
                eye = [float(camera["eye_" + c]) for c in "xyz"]
                target = [float(camera["target_" + c]) for c in "xyz"]
                d = normalized([e - t for e, t in zip(eye, target)])
                return d, min(angle_between(d, direction(a, m["elevation_deg"], m["up"])) for a in candidates)

            d, distance = measured(cameras[0])
            az, el = angles(d, m["up"])
            tie = re.search(r"(\d+) starts within", run.stderr)
            rows.append({"name": m["name"], "up": m["up"], "chosen_azimuth": round(az, 1), "chosen_elevation": round(el, 1),
                         "label_azimuth": m["azimuth_deg"], "label_mirror": m.get("mirror_azimuth_deg"),
                         "label_elevation": m["elevation_deg"], "confidence": m["confidence"],
                         "distance": round(distance, 1), "pass": distance <= PASS_DEG,
                         "starts_tied": int(tie.group(1)) if tie else None})
            r = rows[-1]
            label = f'{r["label_azimuth"]}' + (f'({r["label_mirror"]})' if r["label_mirror"] is not None else "")
            print(f'{r["name"]:<20} {r["up"]:>3}  chosen az {az:6.1f} el {el:5.1f}   label az {label:>9} el {r["label_elevation"]:>3}'
                  f'   {distance:6.1f} deg  {"pass" if r["pass"] else "FAIL"}  ({r["confidence"]}'
                  f'{", tie rule: " + str(r["starts_tied"]) + " starts" if r["starts_tied"] and r["starts_tied"] > 1 else ""})',
                  flush=True)
    for name, why in skipped:
        print(f"{name:<20} not measured: {why}")
    passed = sum(r["pass"] for r in rows)
    if rows:
        print(f"\n{passed} of {len(rows)} within {PASS_DEG:g} degrees of the label: {100.0 * passed / len(rows):.1f} %"
              f" ({len(skipped)} of {len(rows) + len(skipped)} labelled models not measured)")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"rows": rows, "skipped": skipped, "passed": passed, "measured": len(rows)}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
