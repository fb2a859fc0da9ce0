#!/usr/bin/env python3
"""Soak test of a catalogue job: hundreds of items through `meshtour batch` (and, where a local
Slurm can run, `meshtour farm slurm --manifest`) while faults are injected, then run to the end
and checked against a clean run.

  scripts/soak.py --meshtour build/cli/meshtour [--short | --items N] [--work DIR] [--seed S]
                  [--farm auto|yes|no] [--farm-items N] [--shared DIR] [--keep] [--resume]

--short is the CI form (32 items, 2 faults of each kind within 40 rounds, about 2 minutes); the default is the long form (500 items,
at least 50 faults of each kind). What it does:
 1. Makes the items in WORK/inputs: generated meshes in every format (PLY ascii/binary, OBJ, STL,
    OFF), textured OBJ and GLB, a few shared meshes (../shared/meshes, when present), and bad ones:
    truncated, corrupt and empty files, out-of-range indices, NaN coordinates, a mesh over
    --max-memory, missing, hostile (a 68-byte PNG claiming 100,000 x 100,000 pixels) and KTX2
    textures, a missing file, duplicate output names.
 2. A clean run: `batch --web` into WORK/clean, no faults. It says which items are valid.
 3. The faulty runs into WORK/faulty, round after round, each one or two `batch` processes at once
    on the same folder (two operators re-running the job), with scripts/soak/fault_shim.c preloaded:
    kills inside chosen stages (SIGTERM then SIGKILL after a grace, or SIGKILL at once; counted
    per stage: load, path, render, encode, poster, page), windows of a full disk (every write to
    the folder fails with ENOSPC), and failing write, fsync and rename calls (EIO). Then runs
    without faults until one ends normally.
 4. The same with the farm: the array of `batch --item i` tasks submitted twice at once, tasks
    killed by the shim and by scancel (SIGTERM, then SIGKILL), re-submitted until done, then the
    page job.
 5. Checks, for each output folder: every valid item's files byte-identical to the clean run's;
    every bad item reported once, with its reason and exit class, in the summaries and on the
    contact sheet; no partial file anywhere and no file the clean run does not have; no item
    started again after all its files were in place (from the shim's log of item starts and
    renames); every process's peak memory within --max-memory.
Exit status 0 when every check passed, 1 when one failed (each failure printed), 2 for bad usage.
The figures (items, faults by kind, kills by stage, renders per item, peak memory, times) are
printed as a table at the end and written to WORK/report.md.
"""
import argparse
import collections
import hashlib
import html
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
STAGES = ["load", "path", "render", "encode", "poster", "page"]
FAULT_KINDS = ["disk-full", "write", "fsync", "rename"]
RENDER = ["--frames", "4", "--width", "64", "--height", "36", "--spp", "1", "--crf", "30"]
MAX_MEMORY = "600M"


def log(*words):
    print("[soak %s]" % time.strftime("%H:%M:%S"), *words, file=sys.stderr, flush=True)


# ---------------------------------------------------------------------------------------------
# Inputs
# ---------------------------------------------------------------------------------------------

def sphere(rng, rings, segments, bumps):
    """A UV sphere with seeded bumps: (positions, triangles)."""
    import math
    phase = [rng.uniform(0, 6.3) for _ in range(3)]
    v = [(0.0, 1.0, 0.0)]
    for i in range(1, rings):
        t = math.pi * i / rings
        for j in range(segments):
            p = 2 * math.pi * j / segments
            r = 1.0 + bumps * math.sin(3 * t + phase[0]) * math.cos(2 * p + phase[1]) + 0.5 * bumps * math.sin(5 * p + phase[2])
            v.append((r * math.sin(t) * math.cos(p), r * math.cos(t), r * math.sin(t) * math.sin(p)))
    v.append((0.0, -1.0, 0.0))
    f = []
    for j in range(segments):
        f.append((0, 1 + (j + 1) % segments, 1 + j))
    for i in range(rings - 2):
        a, b = 1 + i * segments, 1 + (i + 1) * segments
        for j in range(segments):
            j1 = (j + 1) % segments
            f.append((a + j, a + j1, b + j))
            f.append((a + j1, b + j1, b + j))
    last = len(v) - 1
    base = 1 + (rings - 2) * segments
    for j in range(segments):
        f.append((base + j, base + (j + 1) % segments, last))
    return v, f


def grid(n):
    """An n x n height field: 2 n^2 triangles (the mesh over --max-memory)."""
    v = [(i / n, 0.1 * ((i * 7 + j * 13) % 17) / 17.0, j / n) for i in range(n + 1) for j in range(n + 1)]
    f = []
    for i in range(n):
        for j in range(n):
            a = i * (n + 1) + j
            f.append((a, a + 1, a + n + 1))
            f.append((a + 1, a + n + 2, a + n + 1))
    return v, f


def write_ply(path, v, f, binary):
    with open(path, "wb") as out:
        head = "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" \
               "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (
                   "binary_little_endian" if binary else "ascii", len(v), len(f))
        out.write(head.encode())
        if binary:
            out.write(b"".join(struct.pack("<3f", *p) for p in v))
            out.write(b"".join(struct.pack("<B3i", 3, *t) for t in f))
        else:
            out.write("".join("%.6f %.6f %.6f\n" % p for p in v).encode())
            out.write("".join("3 %d %d %d\n" % t for t in f).encode())


def write_obj(path, v, f, mtl=None, uvs=None):
    with open(path, "w") as out:
        if mtl:
            out.write("mtllib %s\nusemtl skin\n" % mtl)
        out.writelines("v %.6f %.6f %.6f\n" % p for p in v)
        if uvs:
            out.writelines("vt %.4f %.4f\n" % uv for uv in uvs)
            out.writelines("f %d/%d %d/%d %d/%d\n" % (t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1, t[2] + 1) for t in f)
        else:
            out.writelines("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1) for t in f)


def write_stl(path, v, f):
    with open(path, "wb") as out:
        out.write(b"soak".ljust(80, b" ") + struct.pack("<I", len(f)))
        for t in f:
            out.write(struct.pack("<3f", 0, 0, 0) + b"".join(struct.pack("<3f", *v[i]) for i in t) + b"\0\0")


def write_off(path, v, f):
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(v), len(f)))
        out.writelines("%.6f %.6f %.6f\n" % p for p in v)
        out.writelines("3 %d %d %d\n" % t for t in f)


def png_bytes(width, height, pixel, claimed=None):
    """An RGB PNG; `claimed` = (w, h) written in the header instead (a decompression bomb)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    w, h = claimed or (width, height)
    rows = b"".join(b"\0" + b"".join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) + \
        chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")


def checker(x, y):
    return (230, 90, 40) if (x // 2 + y // 2) % 2 else (40, 120, 220)


def textured_obj(folder, name, texture_file, texture_bytes):
    """A UV sphere with an MTL whose map_Kd is `texture_file` (bytes None = the file is missing)."""
    import math
    v, f = sphere(random.Random(len(name)), 10, 16, 0.05)
    uvs = [(0.5 + math.atan2(p[2], p[0]) / (2 * math.pi), 0.5 + p[1] / 2) for p in v]
    write_obj(os.path.join(folder, name + ".obj"), v, f, mtl=name + ".mtl", uvs=uvs)
    with open(os.path.join(folder, name + ".mtl"), "w") as out:
        out.write("newmtl skin\nKd 1 1 1\nmap_Kd %s\n" % texture_file)
    if texture_bytes is not None:
        with open(os.path.join(folder, texture_file), "wb") as out:
            out.write(texture_bytes)
    return name + ".obj"


def write_glb(path, texture):
    """A textured box as GLB: positions, UVs, indices and an embedded PNG."""
    pos, uv, idx = [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = sign, a * sign, b
                pos.append(p)
                uv.append(((a + 1) / 2, (b + 1) / 2))
            idx += [base, base + 1, base + 2, base, base + 2, base + 3]
    blob = b"".join(struct.pack("<3f", *p) for p in pos)
    uv_at = len(blob)
    blob += b"".join(struct.pack("<2f", *t) for t in uv)
    idx_at = len(blob)
    blob += b"".join(struct.pack("<H", i) for i in idx)
    blob += b"\0" * (-len(blob) % 4)
    img_at = len(blob)
    blob += texture + b"\0" * (-len(texture) % 4)
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"bufferView": 3, "mimeType": "image/png"}],
        "buffers": [{"byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": uv_at},
                        {"buffer": 0, "byteOffset": uv_at, "byteLength": idx_at - uv_at},
                        {"buffer": 0, "byteOffset": idx_at, "byteLength": len(idx) * 2},
                        {"buffer": 0, "byteOffset": img_at, "byteLength": len(texture)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos), "type": "VEC3",
                       "min": [-1, -1, -1], "max": [1, 1, 1]},
                      {"bufferView": 1, "componentType": 5126, "count": len(uv), "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": len(idx), "type": "SCALAR"}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    body = struct.pack("<I4s", len(text), b"JSON") + text + struct.pack("<I4s", len(blob), b"BIN\0") + blob
    with open(path, "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


def make_items(folder, count, rng, shared):
    """Writes the inputs and returns the manifest rows: (mesh, output, extra columns, kind)."""
    os.makedirs(folder, exist_ok=True)
    rows = []
    big = None

    def add(mesh, kind, **columns):
        rows.append((mesh, "item%03d.mp4" % len(rows), columns, kind))

    shared_meshes = [m for m in ("kitten.ply", "bear.ply", "horse.ply") if shared and os.path.exists(os.path.join(shared, m))]
    bad_kinds = ["truncated-ply", "corrupt-stl", "empty-obj", "index-out-of-range", "nan-coordinates", "over-max-memory",
                 "missing-texture", "png-bomb", "truncated-png", "ktx2-texture", "missing-file", "duplicate-output"]
    for n in range(count):
        r = rng.random()
        name = "m%03d" % n
        if n % 4 == 3:  # a quarter of the items are bad, every kind in turn
            kind = bad_kinds[(n // 4) % len(bad_kinds)]
            path = os.path.join(folder, name)
            if kind == "truncated-ply":
                v, f = sphere(rng, 8, 12, 0.1)
                write_ply(path + ".ply", v, f, True)
                data = open(path + ".ply", "rb").read()
                open(path + ".ply", "wb").write(data[: len(data) * 2 // 3])
                add(name + ".ply", kind)
            elif kind == "corrupt-stl":
                open(path + ".stl", "wb").write(bytes(rng.randrange(256) for _ in range(700)))
                add(name + ".stl", kind)
            elif kind == "empty-obj":
                open(path + ".obj", "w").close()
                add(name + ".obj", kind)
            elif kind == "index-out-of-range":
                open(path + ".obj", "w").write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n")
                add(name + ".obj", kind)
            elif kind == "nan-coordinates":
                open(path + ".off", "w").write("OFF\n3 1 0\n0 0 0\nnan 1 0\n0 1 0\n3 0 1 2\n")
                add(name + ".off", kind)
            elif kind == "over-max-memory":
                if big is None:
                    big = "big-grid.ply"
                    v, f = grid(700)  # 980,000 faces: its estimate is over --max-memory
                    write_ply(os.path.join(folder, big), v, f, True)
                add(big, kind)
            elif kind == "missing-texture":
                add(textured_obj(folder, name, name + "-gone.png", None), kind)
            elif kind == "png-bomb":
                add(textured_obj(folder, name, name + ".png", png_bytes(1, 1, checker, claimed=(100000, 100000))), kind)
            elif kind == "truncated-png":
                data = png_bytes(64, 64, lambda x, y: ((x * 37) % 256, (y * 91) % 256, (x * y) % 256))
                add(textured_obj(folder, name, name + ".png", data[: len(data) // 2]), kind)
            elif kind == "ktx2-texture":
                add(textured_obj(folder, name, name + ".ktx2", b"\xabKTX 20\xbb\r\n\x1a\n" + bytes(64)), kind)
            elif kind == "missing-file":
                add(name + "-not-there.ply", kind)
            elif kind == "duplicate-output":
                mesh, output, columns, _ = rows[-1] if rows else ("m000.ply", "item000.mp4", {}, "")
                rows.append((mesh, output, {}, kind))
            continue
        if shared_meshes and n % 25 == 0:
            add(os.path.join(shared, shared_meshes[(n // 25) % len(shared_meshes)]), "shared")
            continue
        if r < 0.1:
            add(textured_obj(folder, name, name + ".png", png_bytes(8, 8, checker)), "textured-obj")
            continue
        if r < 0.2:
            write_glb(os.path.join(folder, name + ".glb"), png_bytes(8, 8, checker))
            add(name + ".glb", "textured-glb")
            continue
        v, f = sphere(rng, rng.randrange(6, 24), rng.randrange(8, 40), rng.uniform(0, 0.2))
        fmt = ["ply-ascii", "ply-binary", "obj", "stl", "off"][n % 5]
        ext = {"ply-ascii": ".ply", "ply-binary": ".ply", "obj": ".obj", "stl": ".stl", "off": ".off"}[fmt]
        path = os.path.join(folder, name + ext)
        if fmt.startswith("ply"):
            write_ply(path, v, f, fmt == "ply-binary")
        elif fmt == "obj":
            write_obj(path, v, f)
        elif fmt == "stl":
            write_stl(path, v, f)
        else:
            write_off(path, v, f)
        columns = {}
        if n % 7 == 0:
            columns["path"] = "turntable"
        if n % 11 == 0:
            columns["caption"] = "Item %d" % n
        add(name + ext, fmt, **columns)
    return rows


def write_manifest(path, rows):
    keys = ["path", "caption"]
    with open(path, "w") as out:
        out.write("mesh,output," + ",".join(keys) + "\n")
        for mesh, output, columns, _ in rows:
            out.write(",".join([mesh, output] + [columns.get(k, "") for k in keys]) + "\n")


# ---------------------------------------------------------------------------------------------
# Runs
# ---------------------------------------------------------------------------------------------

class Faults:
    """The fault plan of the shim and the driver's disk-full windows; the counts so far."""

    def __init__(self, work, out_dir, seed, targets):
        self.work, self.out_dir, self.seed, self.targets = work, out_dir, seed, targets
        self.flag = os.path.join(work, "disk-full")
        self.log = os.path.join(work, "faults-%s.log" % os.path.basename(out_dir))
        self.windows = 0
        self.stop = threading.Event()
        self.thread = None

    def counts(self):
        kills, faults = collections.Counter(), collections.Counter()
        if os.path.exists(self.log):
            for line in open(self.log, errors="replace"):
                w = line.split()
                if len(w) >= 4 and w[2] == "kill" and w[4] in ("TERM", "KILL"):
                    kills[w[3]] += 1
                elif len(w) >= 4 and w[2] == "fault":
                    faults[w[3]] += 1
                elif len(w) >= 4 and w[2] == "window":
                    faults["disk-full windows"] += 1
        return kills, faults

    def env(self, rng, enabled=True):
        e = dict(os.environ)
        e.update({"LD_PRELOAD": os.path.join(self.work, "fault_shim.so"), "MESHTOUR_FAULT_LOG": self.log,
                  "MESHTOUR_FAULT_DIR": self.out_dir, "MESHTOUR_FAULT_SEED": str(rng.randrange(1 << 30))})
        if not enabled:
            return e
        kills, faults = self.counts()
        need = self.targets
        plan = []
        short = [s for s in STAGES if kills[s] < need]
        for stage in STAGES + ["bvh", "shading"]:
            # The short stages (encode, poster: milliseconds for these small items) more often. Not
            # "check": every bad item passes it in every run, so kills there would stop every run
            # before the end (and the page).
            # The poster stage is reached once per valid item that gets that far (a handful of
            # passes in the short form, not one per round): at 0.15 a short soak missed it in one
            # run of 120 rounds (2026-12-04, fresh clone), so it is killed there half the time.
            p = {"page": 0.5, "render": 0.2, "encode": 0.25, "poster": 0.5, "bvh": 0.02, "shading": 0.02}.get(stage, 0.12)
            if stage not in short:
                p = 0.0 if short == ["page"] else 0.01  # enough of these; only the page left: let runs reach it
            elif stage != "page" and len(short) <= 3:
                p = max(p, 0.3)  # the stages still short of kills (the short ones: render, encode, poster)
            plan.append("%s:%g" % (stage, p))
        e.update({"MESHTOUR_FAULT_DISK_FULL": self.flag, "MESHTOUR_FAULT_KILL": ",".join(plan),
                  "MESHTOUR_FAULT_KILL_DELAY_MS": str(rng.choice([0, 5, 40])),
                  "MESHTOUR_FAULT_GRACE_MS": str(rng.choice([0, 300, 1500])),
                  "MESHTOUR_FAULT_P_WRITE": "%g" % (0.03 if faults["write"] < need else 0.0),
                  "MESHTOUR_FAULT_P_FSYNC": "%g" % (0.03 if faults["fsync"] < need else 0.002),
                  "MESHTOUR_FAULT_P_RENAME": "%g" % (0.03 if faults["rename"] < need else 0.002)})
        return e

    def start_windows(self, rng):
        """Opens and closes windows of a full disk until stop_windows()."""
        def run():
            while not self.stop.wait(rng.uniform(0.5, 3.0)):
                # Enough windows, and writes failed inside them (a window while no run writes
                # fails nothing: on a loaded machine 4 windows once caught no write at all).
                counts = self.counts()[1]
                if counts["disk-full windows"] >= self.targets * 2 and counts["disk-full"] >= self.targets:
                    continue
                open(self.flag, "w").close()
                self.windows += 1
                with open(self.log, "a") as f:
                    f.write("%d 0 window open\n" % time.time_ns())
                self.stop.wait(rng.uniform(0.1, 0.8))
                os.unlink(self.flag)
        self.stop.clear()
        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()

    def stop_windows(self):
        self.stop.set()
        if self.thread:
            self.thread.join()
        if os.path.exists(self.flag):
            os.unlink(self.flag)


def run_processes(commands, envs, logs):
    """Starts the commands at once; returns [(exit status, peak resident KiB)]."""
    procs = []
    for cmd, env, log_file in zip(commands, envs, logs):
        with open(log_file, "w") as err:
            procs.append(subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=err))
    results = {}
    while len(results) < len(procs):
        pid, status, usage = os.wait4(-1, 0)
        for i, p in enumerate(procs):
            if p.pid == pid:
                p.returncode = os.waitstatus_to_exitcode(status)
                results[i] = (p.returncode, usage.ru_maxrss)
    return [results[i] for i in range(len(procs))]


def batch_command(meshtour, manifest, out_dir):
    return [meshtour, "batch", manifest, "--out-dir", out_dir, "--web", "--max-memory", MAX_MEMORY, "--progress", "json",
            "--threads", "2"] + RENDER


def soak_batch(args, rng, manifest, out_dir, faults, stats):
    """Rounds of one or two faulty batch runs, then clean runs until one ends normally."""
    logs = os.path.join(args.work, "logs")
    os.makedirs(logs, exist_ok=True)
    faults.start_windows(rng)
    round_no, start = 0, time.time()
    try:
        while True:
            kills, counts = faults.counts()
            short_of = [s for s in STAGES if kills[s] < args.faults] + \
                       [k for k in ("write", "fsync", "rename") if counts[k] < args.faults]
            if counts["disk-full windows"] < args.faults or counts["disk-full"] == 0:
                short_of.append("disk-full")
            # Past --max-rounds the rounds go on (to three times as many) only while the check's
            # minimum is not met: one of each kind, a failed write in a full-disk window, a race.
            # On a loaded machine 40 rounds once left the full-disk windows without a write.
            minimum_met = all(kills[s] >= 1 for s in STAGES) and all(counts[k] >= 1 for k in ("write", "fsync", "rename")) and \
                counts["disk-full"] > 0 and counts["disk-full windows"] >= 1 and stats["races"] > 0
            if not short_of or (round_no >= args.max_rounds and (minimum_met or round_no >= 3 * args.max_rounds)):
                break
            racing = rng.random() < 0.3
            n = 2 if racing else 1
            stats["races"] += racing
            command = batch_command(args.meshtour, manifest, out_dir)
            if short_of == ["page"]:
                # Only page kills missing: the page alone, as the farm's last job makes it (a whole
                # run passes every item first).
                command = [args.meshtour, "batch", manifest, "--page-only", "--out-dir", out_dir, "--progress", "json"]
                stats["page_only_runs"] += n
            results = run_processes([command] * n,
                                    [faults.env(rng) for _ in range(n)],
                                    [os.path.join(logs, "%s-round%04d-%d.err" % (os.path.basename(out_dir), round_no, i)) for i in range(n)])
            for code, peak in results:
                stats["processes"] += 1
                stats["exits"][code] += 1
                stats["peak_kib"] = max(stats["peak_kib"], peak)
            round_no += 1
            if round_no % 20 == 0:
                log("%s: round %d, %.0f s, short of %s" % (out_dir, round_no, time.time() - start, ", ".join(short_of)))
    finally:
        faults.stop_windows()
    stats["rounds"] = round_no
    for attempt in range(5):  # to the end, no faults
        [(code, peak)] = run_processes([batch_command(args.meshtour, manifest, out_dir)], [faults.env(rng, enabled=False)],
                                       [os.path.join(logs, "%s-final%d.err" % (os.path.basename(out_dir), attempt))])
        stats["processes"] += 1
        stats["peak_kib"] = max(stats["peak_kib"], peak)
        if code in (0, 5):
            return code
    raise SystemExit("soak: the final runs of %s did not end normally (exit %d)" % (out_dir, code))


# ---------------------------------------------------------------------------------------------
# The farm
# ---------------------------------------------------------------------------------------------

def slurm_available():
    tools = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "scancel", "scontrol"]
    return os.geteuid() == 0 and all(shutil.which(t) for t in tools)


def soak_farm(args, rng, manifest, out_dir, faults, stats):
    cluster = os.path.join(args.work, "slurm")
    local = os.path.join(REPO, "tests", "slurm", "slurm-local.sh")
    subprocess.run([local, "start", cluster], check=True, stdout=subprocess.DEVNULL)
    env_file = os.path.join(cluster, "env.sh")
    slurm_env = dict(os.environ)
    for line in open(env_file):
        line = line.strip()
        if line.startswith("export ") and "=" in line:
            key, value = line[len("export "):].split("=", 1)
            slurm_env[key] = value.strip("'\"")

    def run(cmd, env=None, check=True):
        return subprocess.run(cmd, env=env or slurm_env, check=check, capture_output=True, text=True).stdout

    def wait(ids, scancel_kills):
        deadline = time.time() + 3600
        while True:
            queue = run(["squeue", "-h", "-o", "%i %T", "-j", ",".join(ids)], check=False)
            running = [line.split()[0] for line in queue.splitlines() if line.split()[1:] == ["RUNNING"]]
            if not queue.strip():
                return
            if scancel_kills and running and rng.random() < 0.08:  # a node's time limit: TERM, grace, KILL
                victim = rng.choice(running)
                run(["scancel", "--signal=TERM", victim], check=False)
                stats["scancel"] += 1
                time.sleep(rng.uniform(0.1, 1.0))
                run(["scancel", "--signal=KILL", victim], check=False)
            if time.time() > deadline:
                raise SystemExit("soak: farm jobs did not finish within an hour")
            time.sleep(0.2)

    try:
        cmd = [args.meshtour, "farm", "slurm", "--manifest", manifest, "--out-dir", out_dir, "--web",
               "--max-memory", MAX_MEMORY, "-q"] + RENDER
        run(cmd)
        script = os.path.join(out_dir, "batch.sbatch")
        faults.start_windows(rng)
        try:
            for round_no in range(args.farm_rounds):
                env = faults.env(rng)
                # Two submissions of the same array at once: two operators re-running the job.
                ids = [run(["sbatch", "--parsable", "--export=ALL", script], env={**slurm_env, **env}).strip().split(";")[0]
                       for _ in range(2 if round_no % 2 == 0 else 1)]
                stats["submissions"] += len(ids)
                wait(ids, scancel_kills=True)
        finally:
            faults.stop_windows()
        for attempt in range(4):  # to the end, no faults
            job = run(["sbatch", "--parsable", script]).strip().split(";")[0]
            wait([job], scancel_kills=False)
            summaries = [f for f in os.listdir(out_dir) if f.startswith("batch-summary-")]
            if len(summaries) >= stats["farm_items"]:
                break
        page = run(["sbatch", "--parsable", os.path.join(out_dir, "page.sbatch")]).strip().split(";")[0]
        wait([page], scancel_kills=False)
    finally:
        subprocess.run([local, "stop", cluster], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


# ---------------------------------------------------------------------------------------------
# Checks
# ---------------------------------------------------------------------------------------------

def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def summary_items(out_dir):
    items = {}
    names = [n for n in os.listdir(out_dir) if n.startswith("batch-summary") and n.endswith(".json")]
    for n in names:
        for item in json.load(open(os.path.join(out_dir, n)))["items"]:
            items.setdefault(item["index"], []).append(item)
    return items


# Files of the folder that are not an item's: they name paths or times of their run.
JOB_FILES = ("batch-summary", "index.html", ".meshtour-locks", "render.sbatch", "batch.sbatch", "encode.sbatch",
             "page.sbatch", "submit.sh", "logs", "path.json")


def item_files(clean_dir, output):
    stem = os.path.splitext(output)[0]
    return sorted(n for n in os.listdir(clean_dir) if os.path.splitext(n)[0] in (stem, stem + ".poster"))


def check(out_dir, clean_dir, rows, faults, failures, only_items=None):
    clean = summary_items(clean_dir)
    got = summary_items(out_dir)
    indices = [i for i in range(len(rows)) if only_items is None or i < only_items]
    valid = [i for i in indices if clean[i][0]["status"] != "failed"]
    bad = [i for i in indices if clean[i][0]["status"] == "failed"]
    name = os.path.basename(out_dir)
    # Every valid item's files byte-identical to the clean run's.
    expected = set()
    for i in valid:
        for f in item_files(clean_dir, rows[i][1]):
            expected.add(f)
            mine = os.path.join(out_dir, f)
            if not os.path.exists(mine):
                failures.append("%s: item %d: %s is missing" % (name, i, f))
            elif sha256(mine) != sha256(os.path.join(clean_dir, f)):
                failures.append("%s: item %d: %s differs from the clean run's" % (name, i, f))
    # Every bad item reported once, with its reason and exit class, in the summaries and on the page.
    page = open(os.path.join(out_dir, "index.html"), encoding="utf-8").read() if os.path.exists(os.path.join(out_dir, "index.html")) else ""
    if not page:
        failures.append("%s: no index.html" % name)
    for i in bad:
        reports = [r for r in got.get(i, []) if r["status"] == "failed"]
        if len(reports) != 1:
            failures.append("%s: bad item %d reported %d times (expected once)" % (name, i, len(reports)))
            continue
        r, c = reports[0], clean[i][0]
        if r.get("error") != c.get("error") or r.get("exit_class") != c.get("exit_class") or "exit_class" not in r:
            failures.append("%s: bad item %d: reason %r (%s), clean run %r (%s)" % (
                name, i, r.get("error"), r.get("exit_class"), c.get("error"), c.get("exit_class")))
        first_line = r.get("error", "").split("\n")[0]
        if page and "%s error: %s" % (r.get("exit_class"), first_line) not in html.unescape(page):
            failures.append("%s: bad item %d's reason is not on the contact sheet" % (name, i))
    for i in valid:
        if any(r["status"] == "failed" for r in got.get(i, [])):
            failures.append("%s: valid item %d is reported failed: %s" % (name, i, got[i]))
    # No partial file anywhere, nothing the clean run does not have.
    for f in os.listdir(out_dir):
        if ".partial-" in f:
            failures.append("%s: partial file left: %s" % (name, f))
        elif f not in expected and not f.startswith(JOB_FILES):
            failures.append("%s: unexpected file: %s" % (name, f))
    # No item started again once all its files were in place.
    outputs = {i: set(os.path.join(out_dir, f) for f in item_files(clean_dir, rows[i][1])) for i in valid}
    owner = {}
    for i, files in outputs.items():
        for f in files:
            owner[f] = i
    events = []
    if os.path.exists(faults.log):
        for line in open(faults.log, errors="replace"):
            w = line.split()
            if len(w) >= 4 and w[2] in ("start", "rename"):
                events.append((int(w[0]), w[2], w[3]))
    events.sort()
    placed = collections.defaultdict(set)
    done_at = {}
    starts = collections.Counter()
    twice = []
    for t, kind, what in events:
        if kind == "rename" and what in owner:
            i = owner[what]
            placed[i].add(what)
            if i not in done_at and placed[i] == outputs[i]:
                done_at[i] = t
        elif kind == "start":
            i = int(what)
            starts[i] += 1
            if i in done_at:
                twice.append(i)
    for i in sorted(set(twice)):
        failures.append("%s: item %d was started again after all its files were in place" % (name, i))
    return {"valid": len(valid), "bad": len(bad), "starts": {i: starts[i] for i in valid}, "done": len(done_at)}


# ---------------------------------------------------------------------------------------------

def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="\n".join(__doc__.split("\n")[1:]))
    parser.add_argument("--meshtour", required=True, help="the meshtour executable")
    parser.add_argument("--short", action="store_true", help="the CI form: 32 items, 2 faults of each kind within 40 rounds")
    parser.add_argument("--items", type=int, help="manifest items (default 500, --short 32)")
    parser.add_argument("--faults", type=int, help="faults of each kind and kills in each stage (default 50, --short 2)")
    parser.add_argument("--work", default=None, help="working folder (default: a new one in /tmp, removed on success)")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--farm", choices=["auto", "yes", "no"], default="auto",
                        help="also through a local Slurm (auto: when root and Slurm is installed)")
    parser.add_argument("--farm-items", type=int, help="items of the farm's part (default: all; --short 16)")
    parser.add_argument("--shared", default=os.path.join(REPO, "..", "shared", "meshes"), help="shared meshes, if present")
    parser.add_argument("--keep", action="store_true", help="keep the working folder")
    parser.add_argument("--resume", action="store_true",
                        help="continue a soak stopped in --work: its clean run is kept, the faulty runs go on from their counts")
    args = parser.parse_args()
    args.items = args.items or (32 if args.short else 500)
    args.faults = args.faults or (2 if args.short else 50)
    args.max_rounds = 40 if args.short else 3000
    args.farm_rounds = 2 if args.short else 6
    args.farm_items = min(args.farm_items or (10 if args.short else args.items), args.items)
    args.meshtour = os.path.abspath(args.meshtour)
    if not os.access(args.meshtour, os.X_OK):
        parser.error("%s is not an executable" % args.meshtour)
    farm = args.farm == "yes" or (args.farm == "auto" and slurm_available())
    if args.farm == "yes" and not slurm_available():
        parser.error("--farm yes needs root and Slurm (scripts/install-deps.sh --tests)")
    import tempfile
    args.work = os.path.abspath(args.work or tempfile.mkdtemp(prefix="meshtour-soak-"))
    os.makedirs(args.work, exist_ok=True)
    rng = random.Random(args.seed)
    started = time.time()

    subprocess.run(["cc", "-shared", "-fPIC", "-O2", "-o", os.path.join(args.work, "fault_shim.so"),
                    os.path.join(HERE, "soak", "fault_shim.c"), "-ldl", "-lpthread"], check=True)
    inputs = os.path.join(args.work, "inputs")
    shared = args.shared if os.path.isdir(args.shared) and not args.short else None
    rows = make_items(inputs, args.items, rng, shared)
    manifest = os.path.join(inputs, "manifest.csv")
    write_manifest(manifest, rows)
    farm_manifest = os.path.join(inputs, "farm-manifest.csv")
    write_manifest(farm_manifest, rows[: args.farm_items])
    kinds = collections.Counter(k for *_, k in rows)
    log("%d items in %s: %s" % (len(rows), inputs, ", ".join("%s %d" % kv for kv in sorted(kinds.items()))))

    clean = os.path.join(args.work, "clean")
    t = time.time()
    if args.resume and os.path.exists(os.path.join(clean, "batch-summary.json")):
        code, clean_peak = 5, 0
        log("clean run: kept from %s" % clean)
    else:
        [(code, clean_peak)] = run_processes([batch_command(args.meshtour, manifest, clean)], [dict(os.environ)],
                                             [os.path.join(args.work, "clean.err")])
    clean_seconds = time.time() - t
    if code not in (0, 5):
        raise SystemExit("soak: the clean run failed with exit %d (%s)" % (code, os.path.join(args.work, "clean.err")))
    log("clean run: exit %d in %.0f s" % (code, clean_seconds))

    failures = []
    report = []
    targets = args.faults
    faults = Faults(args.work, os.path.join(args.work, "faulty"), args.seed, targets)
    stats = {"races": 0, "processes": 0, "exits": collections.Counter(), "peak_kib": clean_peak, "rounds": 0, "page_only_runs": 0}
    t = time.time()
    soak_batch(args, rng, manifest, faults.out_dir, faults, stats)
    batch_seconds = time.time() - t
    result = check(faults.out_dir, clean, rows, faults, failures)
    kills, counts = faults.counts()
    report.append(("batch", result, kills, counts, stats, batch_seconds))

    if farm:
        farm_faults = Faults(args.work, os.path.join(args.work, "farm"), args.seed + 1, max(2, targets // 5))
        farm_stats = {"submissions": 0, "scancel": 0, "farm_items": args.farm_items, "peak_kib": 0}
        t = time.time()
        soak_farm(args, rng, farm_manifest, farm_faults.out_dir, farm_faults, farm_stats)
        farm_seconds = time.time() - t
        result = check(farm_faults.out_dir, clean, rows, farm_faults, failures, only_items=args.farm_items)
        kills, counts = farm_faults.counts()
        peaks = [r.get("peak_resident_bytes", 0) for items in summary_items(farm_faults.out_dir).values() for r in items]
        farm_stats["peak_kib"] = max(peaks or [0]) // 1024
        report.append(("farm", result, kills, counts, farm_stats, farm_seconds))
    else:
        log("the farm part is not run: %s" % ("--farm no" if args.farm == "no" else "needs root and Slurm"))

    limit_kib = int(MAX_MEMORY[:-1]) * 1024
    lines = ["| part | items (valid/bad) | processes or submissions | races | kills by stage | faults by kind | "
             "starts per valid item | peak memory | seconds |", "|---|---|---|---|---|---|---|---|---|"]
    for part, result, kills, counts, st, seconds in report:
        if st["peak_kib"] > limit_kib:
            failures.append("%s: a process peaked at %d MiB, over --max-memory %s" % (part, st["peak_kib"] // 1024, MAX_MEMORY))
        starts = sorted(result["starts"].values()) or [0]
        lines.append("| %s | %d/%d | %s | %s | %s | %s | median %d, max %d | %d MiB | %.0f |" % (
            part, result["valid"], result["bad"],
            st.get("processes", st.get("submissions")), st.get("races", st.get("submissions", 0) - args.farm_rounds),
            " ".join("%s %d" % (s, kills[s]) for s in STAGES),
            " ".join("%s %d" % (k, counts[k if k != "disk-full" else "disk-full windows"]) for k in FAULT_KINDS),
            starts[len(starts) // 2], starts[-1], st["peak_kib"] // 1024, seconds))
        if part == "batch":
            # The long form must reach its counts; the short one (a bounded number of rounds on a
            # machine of unknown speed) at least one of each.
            need = 1 if args.short else args.faults
            for s in STAGES:
                if kills[s] < need:
                    failures.append("batch: %d kills in stage %s, fewer than %d" % (kills[s], s, need))
            for k in ("write", "fsync", "rename"):
                if counts[k] < need:
                    failures.append("batch: %d %s faults, fewer than %d" % (counts[k], k, need))
            if counts["disk-full"] == 0 or counts["disk-full windows"] < need:
                failures.append("batch: %d disk-full windows (%d failed writes), fewer than %d" % (
                    counts["disk-full windows"], counts["disk-full"], need))
            if st["races"] == 0:
                failures.append("batch: no two runs raced")
    lines.append("")
    lines.append("batch: %d rounds, %d of them racing two runs; %d page-only runs (the farm's page job) for page kills; exits %s" % (
        stats["rounds"], stats["races"], stats["page_only_runs"], dict(sorted(stats["exits"].items()))))
    text = "\n".join(["soak: %d items (%s), clean run %.0f s, whole soak %.0f s" % (
        len(rows), ", ".join("%s %d" % kv for kv in sorted(kinds.items())), clean_seconds, time.time() - started), ""] + lines)
    open(os.path.join(args.work, "report.md"), "w").write(text + "\n")
    print(text)
    if failures:
        print("\nFAILED (%d):" % len(failures))
        for f in failures[:200]:
            print("  " + f)
        print("work folder kept: %s" % args.work)
        return 1
    print("\nPASSED")
    if not args.keep and args.work.startswith(tempfile.gettempdir()):
        shutil.rmtree(args.work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
