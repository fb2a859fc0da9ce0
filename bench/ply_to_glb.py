#!/usr/bin/env python3
"""A binary little-endian PLY (float x, y, z; uchar-counted int faces, as the shared meshes are)
as a GLB with one glTF material: a scan in a glTF file, for the comparison with Cycles
(bench/cycles_gltf_compare.sh), where both renderers must read the same file. Smooth vertex
normals (the faces' area-weighted sum) are written, so that neither renderer makes its own.

    ply_to_glb.py MESH.ply OUT.glb [R G B [METALLIC ROUGHNESS]]   (linear base colour; default
                                                                 0.8 0.8 0.8, dielectric, 0.6)
"""
import json
import struct
import sys


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        if "format binary_little_endian 1.0" not in header:
            sys.exit(f"{path}: only binary little-endian PLY is read here")
        counts = {l.split()[1]: int(l.split()[2]) for l in header if l.startswith("element")}
        props = [l for l in header if l.startswith("property") and not l.startswith("property list")]
        if props[:3] != ["property float x", "property float y", "property float z"] or len(props) != 3:
            sys.exit(f"{path}: vertices must be exactly float x, y, z")
        nv, nf = counts["vertex"], counts["face"]
        positions = struct.unpack(f"<{3 * nv}f", f.read(12 * nv))
        indices = []
        for _ in range(nf):
            (n,) = struct.unpack("<B", f.read(1))
            idx = struct.unpack(f"<{n}i", f.read(4 * n))
            for k in range(1, n - 1):
                indices += [idx[0], idx[k], idx[k + 1]]
    return positions, indices


def main():
    if len(sys.argv) not in (3, 6, 8):
        sys.exit(__doc__)
    positions, indices = read_ply(sys.argv[1])
    colour = [float(x) for x in sys.argv[3:6]] if len(sys.argv) >= 6 else [0.8, 0.8, 0.8]
    metallic, roughness = (float(sys.argv[6]), float(sys.argv[7])) if len(sys.argv) == 8 else (0.0, 0.6)
    normals = [0.0] * len(positions)
    for t in range(0, len(indices), 3):
        a, b, c = indices[t], indices[t + 1], indices[t + 2]
        e1 = [positions[3 * b + k] - positions[3 * a + k] for k in range(3)]
        e2 = [positions[3 * c + k] - positions[3 * a + k] for k in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        for v in (a, b, c):
            for k in range(3):
                normals[3 * v + k] += n[k]
    for v in range(len(positions) // 3):
        length = sum(normals[3 * v + k] ** 2 for k in range(3)) ** 0.5 or 1.0
        for k in range(3):
            normals[3 * v + k] /= length
    pos_bytes = struct.pack(f"<{len(positions)}f", *positions) + struct.pack(f"<{len(normals)}f", *normals)
    idx_bytes = struct.pack(f"<{len(indices)}I", *indices)
    lo = [min(positions[k::3]) for k in range(3)]
    hi = [max(positions[k::3]) for k in range(3)]
    doc = {
        "asset": {"version": "2.0", "generator": "meshtour bench/ply_to_glb.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 2}, "indices": 1, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": colour + [1.0], "metallicFactor": metallic,
                                                "roughnessFactor": roughness}}],
        "buffers": [{"byteLength": len(pos_bytes) + len(idx_bytes)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pos_bytes) // 2, "target": 34962},
                        {"buffer": 0, "byteOffset": len(pos_bytes), "byteLength": len(idx_bytes), "target": 34963},
                        {"buffer": 0, "byteOffset": len(pos_bytes) // 2, "byteLength": len(pos_bytes) // 2, "target": 34962}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(positions) // 3, "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"},
                      {"bufferView": 2, "componentType": 5126, "count": len(positions) // 3, "type": "VEC3"}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    binary = pos_bytes + idx_bytes
    binary += b"\0" * (-len(binary) % 4)
    with open(sys.argv[2], "wb") as out:
        out.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(binary)))
        out.write(struct.pack("<II", len(text), 0x4E4F534A) + text)
        out.write(struct.pack("<II", len(binary), 0x004E4942) + binary)


if __name__ == "__main__":
    main()
