#!/usr/bin/env python3
"""Make the textured and coloured test meshes in this folder from the shared meshes.

    python3 -m venv /tmp/assets-venv && /tmp/assets-venv/bin/pip install xatlas numpy
    /tmp/assets-venv/bin/python tests/assets/make_assets.py $GNG3D_MESHES

Writes, next to this script:
- fandisk_atlas.obj + fandisk_atlas.mtl + checker.png: fandisk (6,475 vertices) with a real UV
  atlas from xatlas (many charts, so many UV seams), per-chart normals (normal seams on the chart
  borders) and one material whose diffuse map is a procedural 64 x 64 checker;
- knight_colors.ply: decimated-knight (502 vertices) with per-vertex RGBA colours from its
  normals (binary PLY, uchar red green blue alpha).
Deterministic for a given xatlas version (0.0.11 made the committed files).

    for m in igea igea-1m; do gng3d simplify $GNG3D_MESHES/$m.ply DIR/$m.obj --face-ratio 1; done
    /tmp/assets-venv/bin/python tests/assets/make_assets.py --large DIR

writes instead, into DIR (not committed: 27 and 112 MB), igea_atlas.obj and igea-1m_atlas.obj:
igea (268,686 faces) and igea-1m (1,074,744 faces) with xatlas UV atlases and per-chart normals
as the fandisk atlas has, for timing the attribute path at scale (`GNG3D_ATTRIBUTE_MESHES` of
`cargo bench -p gng3d-qem --bench attributes`).
"""
import struct
import sys
import zlib
from pathlib import Path

import numpy as np
import xatlas

HERE = Path(__file__).resolve().parent


def read_obj(path):
    vertices, faces = [], []
    for line in path.read_text(errors="replace").splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append([float(x) for x in parts[1:4]])
        elif parts[0] == "f":
            idx = [int(p.split("/")[0]) - 1 for p in parts[1:]]
            for i in range(1, len(idx) - 1):
                faces.append([idx[0], idx[i], idx[i + 1]])
    return np.array(vertices, dtype=np.float32), np.array(faces, dtype=np.uint32)


def face_normals(v, f):
    n = np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]])
    return n  # area-weighted (twice the area)


def png(path, size=64, cell=8):
    rows = b""
    for y in range(size):
        row = bytearray([0])
        for x in range(size):
            on = ((x // cell) + (y // cell)) % 2
            row += bytes([230, 200, 60] if on else [40, 60, 160])
        rows += bytes(row)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(rows, 9))
        + chunk(b"IEND", b"")
    )


def atlas_obj(v, f, header, material=None):
    """OBJ text of (v, f) with an xatlas UV atlas and per-chart normals (atlas vertices split at
    chart borders, each with the area-weighted normal of its faces); `material`, a pair
    (library file, material name), is named for every face."""
    vmapping, indices, uvs = xatlas.parametrize(v, f)
    fn = face_normals(v, f)
    wn = np.zeros((len(vmapping), 3))
    for k in range(3):
        np.add.at(wn, indices[:, k], fn)
    wn /= np.maximum(np.linalg.norm(wn, axis=1, keepdims=True), 1e-30)
    lines = [header]
    if material:
        lines.append(f"mtllib {material[0]}")
    lines += [f"v {x:.6g} {y:.6g} {z:.6g}" for x, y, z in v]
    lines += [f"vt {s:.6f} {t:.6f}" for s, t in uvs]
    lines += [f"vn {x:.5f} {y:.5f} {z:.5f}" for x, y, z in wn]
    if material:
        lines.append(f"usemtl {material[1]}")
    for t in indices:
        lines.append("f " + " ".join(f"{vmapping[w] + 1}/{w + 1}/{w + 1}" for w in t))
    return "\n".join(lines) + "\n"


def large(out):
    """The atlases of `out`/igea.obj and `out`/igea-1m.obj (the scans as the project cleans
    them, written by `gng3d simplify ... --face-ratio 1`: welded, degenerate faces of the
    unrolled triangle strips dropped; xatlas asserts on and crawls over the raw files)."""
    for name in ["igea", "igea-1m"]:
        v, f = read_obj(out / f"{name}.obj")
        text = atlas_obj(v, f, f"# {name} with an xatlas UV atlas (tests/assets/make_assets.py --large)")
        (out / f"{name}_atlas.obj").write_text(text)


def fandisk(meshes):
    v, f = read_obj(meshes / "fandisk.obj")
    header = "# fandisk with an xatlas UV atlas (tests/assets/make_assets.py)"
    text = atlas_obj(v, f, header, ("fandisk_atlas.mtl", "checker"))
    (HERE / "fandisk_atlas.obj").write_text(text)
    (HERE / "fandisk_atlas.mtl").write_text(
        "newmtl checker\nKd 1 1 1\nmap_Kd checker.png\n"
    )
    png(HERE / "checker.png")


def knight(meshes):
    v, f = read_obj(meshes / "decimated-knight.obj")
    fn = face_normals(v, f)
    vn = np.zeros_like(v, dtype=np.float64)
    for k in range(3):
        np.add.at(vn, f[:, k], fn)
    vn /= np.maximum(np.linalg.norm(vn, axis=1, keepdims=True), 1e-30)
    rgb = np.clip(np.round((vn * 0.5 + 0.5) * 255), 0, 255).astype(np.uint8)
    header = (
        "ply\nformat binary_little_endian 1.0\ncomment tests/assets/make_assets.py\n"
        f"element vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
        f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    out = bytearray(header.encode())
    for p, c in zip(v, rgb):
        out += struct.pack("<fffBBBB", *p, *c, 255)
    for t in f:
        out += struct.pack("<Biii", 3, *t)
    (HERE / "knight_colors.ply").write_bytes(bytes(out))


if __name__ == "__main__":
    meshes = Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/meshes")
    if "--large" in sys.argv:
        large(Path(sys.argv[sys.argv.index("--large") + 1]))
    else:
        fandisk(meshes)
        knight(meshes)
