#!/usr/bin/env python3
"""QEM with attributes (`gng3d simplify --method qem`) against meshoptimizer's
`meshopt_simplifyWithAttributes` and MeshLab's quadric edge collapse (with texture where the
mesh has texture coordinates) at equal face count (docs/notes/attributes.md).

Usage (from the repository root, after `cargo build --release -p gng3d-cli`):

    /tmp/pyvenv/bin/python docs/results/attributes_vs_meshopt.py \
        --gng3d $CARGO_TARGET_DIR/release/gng3d [--meshes DIR] [--samples N] [--repeats K]

Needs numpy and the `meshoptimizer` package (its shared library is called through ctypes with
the argument types declared here: the package's own wrapper declares none); with `pymeshlab`
installed, MeshLab runs too (`meshing_decimation_quadric_edge_collapse_with_texture` for a mesh
with texture coordinates, else `meshing_decimation_quadric_edge_collapse`; MeshLab's defaults,
the target face count; it reads the file itself and keeps per-vertex normals and colours).

Both outputs are measured the same way, independently of either simplifier:
- geometry: N points sampled uniformly by area on the output and N on the input; each point's
  exact closest point on the other mesh; Hausdorff = the largest of both directions (with every
  vertex of both meshes sampled too, as Metro does), mean = the mean of both directions' means
  (area samples only), both as a share of the input's bounding-box diagonal;
- attributes: at each output sample, the output's value (interpolated over its triangle, the
  wedge values of that triangle's corners) against the input's value interpolated at the
  closest point of the input's surface (its closest triangle): UV distance (texture 1 × 1),
  RGBA distance (0-1 per channel), normal angle in degrees (both normalised);
- time: the simplification alone, min of K runs alternating the two (gng3d: the `seconds` of
  `--json`, which excludes loading and saving; meshoptimizer: the C call).
"""

import argparse
import ctypes
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


# --- I/O: OBJ with v/vt/vn, binary PLY with xyz + uchar rgba (what the test meshes hold) ---


def load_obj(path):
    """Positions (V, 3), faces (F, 3), and per corner: uv (F, 3, 2) or None, normal (F, 3, 3)
    or None."""
    v, vt, vn, fv, ft, fn = [], [], [], [], [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                v.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("vt "):
                vt.append([float(x) for x in line.split()[1:3]])
            elif line.startswith("vn "):
                vn.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                corners = [c.split("/") for c in line.split()[1:]]
                for k in range(1, len(corners) - 1):  # fan
                    tri = [corners[0], corners[k], corners[k + 1]]
                    fv.append([int(c[0]) - 1 for c in tri])
                    if len(tri[0]) > 1 and tri[0][1]:
                        ft.append([int(c[1]) - 1 for c in tri])
                    if len(tri[0]) > 2 and tri[0][2]:
                        fn.append([int(c[2]) - 1 for c in tri])
    pos = np.array(v, dtype=np.float64)
    faces = np.array(fv, dtype=np.int64)
    uv = np.array(vt)[np.array(ft)] if ft else None
    nrm = np.array(vn)[np.array(fn)] if fn else None
    return pos, faces, {"uv": uv, "normal": nrm}


def load_ply_colors(path):
    """Binary little-endian PLY with float xyz and uchar rgb(a) per vertex, uchar/int face
    lists: positions, faces, per corner colour (F, 3, 4) in [0, 1]."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode().strip()
            header.append(line)
            if line == "end_header":
                break
        body = f.read()
    props, nv, nf = [], 0, 0
    element = None
    for line in header:
        w = line.split()
        if w[0] == "element":
            element = w[1]
            if element == "vertex":
                nv = int(w[2])
            elif element == "face":
                nf = int(w[2])
        elif w[0] == "property" and element == "vertex":
            props.append((w[2], {"float": "<f4", "uchar": "u1", "double": "<f8"}[w[1]]))
    vdt = np.dtype(props)
    vert = np.frombuffer(body, dtype=vdt, count=nv)
    fdt = np.dtype([("n", "u1"), ("i", "<i4", (3,))])
    face = np.frombuffer(body, dtype=fdt, count=nf, offset=nv * vdt.itemsize)
    assert (face["n"] == 3).all()
    pos = np.stack([vert["x"], vert["y"], vert["z"]], 1).astype(np.float64)
    names = vert.dtype.names
    rgba = np.stack(
        [vert[c] if c in names else np.full(nv, 255) for c in ("red", "green", "blue", "alpha")],
        1,
    ).astype(np.float64) / 255.0
    faces = face["i"].astype(np.int64)
    return pos, faces, {"color": rgba[faces]}


def load(path):
    return load_ply_colors(path) if path.endswith(".ply") else load_obj(path)


def save_obj(path, pos, faces, attrs):
    with open(path, "w") as f:
        for p in pos:
            f.write(f"v {p[0]:.9g} {p[1]:.9g} {p[2]:.9g}\n")
        uv, nrm = attrs.get("uv"), attrs.get("normal")
        if uv is not None:
            for t in uv.reshape(-1, 2):
                f.write(f"vt {t[0]:.9g} {t[1]:.9g}\n")
        if nrm is not None:
            for n in nrm.reshape(-1, 3):
                f.write(f"vn {n[0]:.9g} {n[1]:.9g} {n[2]:.9g}\n")
        for k, t in enumerate(faces):
            c = []
            for j in range(3):
                s = str(t[j] + 1)
                w = 3 * k + j + 1
                if uv is not None and nrm is not None:
                    s += f"/{w}/{w}"
                elif uv is not None:
                    s += f"/{w}"
                elif nrm is not None:
                    s += f"//{w}"
                c.append(s)
            f.write("f " + " ".join(c) + "\n")


# --- meshoptimizer through ctypes ---


def meshopt_lib():
    import meshoptimizer

    so = glob.glob(os.path.join(os.path.dirname(meshoptimizer.__file__), "_meshoptimizer*.so"))[0]
    lib = ctypes.CDLL(so)
    f = lib.meshopt_simplifyWithAttributes
    P = ctypes.POINTER
    f.argtypes = [
        P(ctypes.c_uint), P(ctypes.c_uint), ctypes.c_size_t,  # destination, indices, count
        P(ctypes.c_float), ctypes.c_size_t, ctypes.c_size_t,  # positions, count, stride
        P(ctypes.c_float), ctypes.c_size_t,  # attributes, stride
        P(ctypes.c_float), ctypes.c_size_t,  # weights, count
        P(ctypes.c_ubyte), ctypes.c_size_t,  # lock, target index count
        ctypes.c_float, ctypes.c_uint, P(ctypes.c_float),  # target error, options, result error
    ]
    f.restype = ctypes.c_size_t
    return f


def wedge_buffers(pos, faces, attrs, weights):
    """meshoptimizer's input: one vertex per distinct (position, attribute values) corner."""
    cols, w = [], []
    for name, k in (("uv", 2), ("normal", 3), ("color", 4)):
        a = attrs.get(name)
        if a is not None:
            cols.append(a.reshape(-1, k))
            w += [weights[name]] * k
    corner_pos = pos[faces].reshape(-1, 3)
    if not cols:  # positions only: one zero-weight channel (the call needs one)
        cols, w = [np.zeros((len(corner_pos), 1))], [0.0]
    corner_attr = np.concatenate(cols, 1)
    key = np.concatenate([corner_pos, corner_attr], 1)
    uniq, inverse = np.unique(key, axis=0, return_inverse=True)
    vpos = np.ascontiguousarray(uniq[:, :3], dtype=np.float32)
    vattr = np.ascontiguousarray(uniq[:, 3:], dtype=np.float32)
    idx = np.ascontiguousarray(inverse.reshape(-1), dtype=np.uint32)
    return vpos, vattr, idx, np.array(w, dtype=np.float32)


def run_meshopt(fn, vpos, vattr, idx, weights, target_faces):
    dest = np.zeros_like(idx)
    err = ctypes.c_float(0.0)
    P = ctypes.POINTER
    t = time.perf_counter()
    n = fn(
        dest.ctypes.data_as(P(ctypes.c_uint)), idx.ctypes.data_as(P(ctypes.c_uint)), len(idx),
        vpos.ctypes.data_as(P(ctypes.c_float)), len(vpos), 12,
        vattr.ctypes.data_as(P(ctypes.c_float)), vattr.shape[1] * 4,
        weights.ctypes.data_as(P(ctypes.c_float)), len(weights),
        P(ctypes.c_ubyte)(), 3 * target_faces, ctypes.c_float(1e30), 0, ctypes.byref(err),
    )
    return time.perf_counter() - t, dest[:n].reshape(-1, 3)


def run_meshlab(path, target_faces, orig_attrs):
    """MeshLab on the file at `path` to `target_faces`: (seconds of the filter alone, output as
    (positions, faces, attributes) in the layout `load` gives)."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(path)
    uv = orig_attrs.get("uv") is not None
    t = time.perf_counter()
    if uv:
        ms.meshing_decimation_quadric_edge_collapse_with_texture(targetfacenum=target_faces)
    else:
        ms.meshing_decimation_quadric_edge_collapse(targetfacenum=target_faces)
    dt = time.perf_counter() - t
    m = ms.current_mesh()
    pos = m.vertex_matrix().astype(np.float64)
    faces = m.face_matrix().astype(np.int64)
    attrs = {}
    if uv:
        attrs["uv"] = m.wedge_tex_coord_matrix().astype(np.float64).reshape(-1, 3, 2)
    if orig_attrs.get("normal") is not None:
        attrs["normal"] = m.vertex_normal_matrix().astype(np.float64)[faces]
    if orig_attrs.get("color") is not None:
        attrs["color"] = m.vertex_color_matrix().astype(np.float64)[faces]
    return dt, (pos, faces, attrs)


def has_meshlab():
    try:
        import pymeshlab  # noqa: F401
    except ImportError:
        return False
    return True


# --- the independent measurement ---


def sample(pos, faces, n, rng):
    """n points uniformly by area: (face index, barycentrics (n, 3), points (n, 3))."""
    p = pos[faces]
    area = 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)
    f = rng.choice(len(faces), size=n, p=area / area.sum())
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    bary = np.stack([1 - s, s * (1 - r2), s * r2], 1)
    return f, bary, np.einsum("nk,nkd->nd", bary, p[f])


def closest_on_triangles(q, a, b, c):
    """Exact closest points of q (n, 3) on triangles (a, b, c) (n, 3) each (Ericson's
    region test): barycentrics (n, 3)."""
    ab, ac, ap = b - a, c - a, q - a
    d1, d2 = (ab * ap).sum(-1), (ac * ap).sum(-1)
    bp = q - b
    d3, d4 = (ab * bp).sum(-1), (ac * bp).sum(-1)
    cp = q - c
    d5, d6 = (ab * cp).sum(-1), (ac * cp).sum(-1)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        den = va + vb + vc
        v = vb / den
        w = vc / den
        out = np.stack([1 - v - w, v, w], 1)
        # edges and vertices
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    cases = [
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), lambda: np.stack([1 - t_ab, t_ab, 0 * t_ab], 1)),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), lambda: np.stack([1 - t_ac, 0 * t_ac, t_ac], 1)),
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0),
         lambda: np.stack([0 * t_bc, 1 - t_bc, t_bc], 1)),
        ((d6 >= 0) & (d5 <= d6), lambda: np.tile([0.0, 0.0, 1.0], (len(q), 1))),
        ((d3 >= 0) & (d4 <= d3), lambda: np.tile([0.0, 1.0, 0.0], (len(q), 1))),
        ((d1 <= 0) & (d2 <= 0), lambda: np.tile([1.0, 0.0, 0.0], (len(q), 1))),
    ]
    for mask, value in cases:  # later cases take precedence (vertex regions last)
        if mask.any():
            out[mask] = value()[mask]
    return out


def closest(points, pos, faces, k=48, chunk=1024):
    """For each point, the closest triangle of (pos, faces), the barycentrics of the closest
    point on it and the distance. Exact: the k triangles with the smallest lower bound
    (centroid distance − circumradius bound) are tested, and points whose best distance
    exceeds the k-th bound are redone against every triangle."""
    tri = pos[faces]
    cen = tri.mean(1)
    rad = np.linalg.norm(tri - cen[:, None], axis=2).max(1)
    n = len(points)
    best_f = np.zeros(n, np.int64)
    best_b = np.zeros((n, 3))
    best_d = np.full(n, np.inf)
    k = min(k, len(faces))
    for s in range(0, n, chunk):
        q = points[s:s + chunk]
        lower = np.sqrt(((q[:, None, :] - cen[None]) ** 2).sum(-1)) - rad[None]
        cand = np.argpartition(lower, k - 1, axis=1)[:, :k]
        kth = np.take_along_axis(lower, cand, 1).max(1)
        qq = np.repeat(q, k, 0)
        cf = cand.reshape(-1)
        bary = closest_on_triangles(qq, tri[cf, 0], tri[cf, 1], tri[cf, 2])
        pts = np.einsum("nk,nkd->nd", bary, tri[cf])
        d = np.linalg.norm(pts - qq, axis=1).reshape(len(q), k)
        j = d.argmin(1)
        rows = np.arange(len(q))
        best_d[s:s + len(q)] = d[rows, j]
        best_f[s:s + len(q)] = cand[rows, j]
        best_b[s:s + len(q)] = bary.reshape(len(q), k, 3)[rows, j]
        redo = np.nonzero(d[rows, j] > kth)[0]
        for r in redo:  # rare: a far point (brute force over all triangles)
            qr = np.repeat(q[r:r + 1], len(faces), 0)
            b = closest_on_triangles(qr, tri[:, 0], tri[:, 1], tri[:, 2])
            dd = np.linalg.norm(np.einsum("nk,nkd->nd", b, tri) - qr, axis=1)
            m = dd.argmin()
            best_d[s + r], best_f[s + r], best_b[s + r] = dd[m], m, b[m]
    return best_f, best_b, best_d


def measure(orig, out, samples, seed=1):
    (opos, ofaces, oattr), (spos, sfaces, sattr) = orig, out
    diag = np.linalg.norm(opos.max(0) - opos.min(0))
    rng = np.random.default_rng(seed)
    f_s, b_s, p_s = sample(spos, sfaces, samples, rng)
    f_o, b_o, d_so = closest(p_s, opos, ofaces)
    _, _, p_o = sample(opos, ofaces, samples, rng)
    _, _, d_os = closest(p_o, spos, sfaces)
    # Metro's vertex samples, for the Hausdorff distance only: the largest distance is often at
    # a vertex (a corner the other mesh cuts off, a vertex placed off the surface), which area
    # samples hit only by chance (spot at 20 %: two seeds of 20,000 samples ordered ours and
    # meshoptimizer's differently).
    _, _, d_sv = closest(spos[np.unique(sfaces)], opos, ofaces)
    _, _, d_ov = closest(opos[np.unique(ofaces)], spos, sfaces)
    row = {
        "hausdorff": max(d_so.max(), d_os.max(), d_sv.max(), d_ov.max()) / diag,
        "mean": 0.5 * (d_so.mean() + d_os.mean()) / diag,
    }
    for name in ("uv", "color", "normal"):
        a, b = sattr.get(name), oattr.get(name)
        if a is None or b is None:
            continue
        va = np.einsum("nk,nkd->nd", b_s, a[f_s])
        vb = np.einsum("nk,nkd->nd", b_o, b[f_o])
        if name == "normal":
            va /= np.linalg.norm(va, axis=1, keepdims=True)
            vb /= np.linalg.norm(vb, axis=1, keepdims=True)
            dev = np.degrees(np.arccos(np.clip((va * vb).sum(1), -1, 1)))
        else:
            dev = np.linalg.norm(va - vb, axis=1)
        row[name] = (dev.mean(), np.percentile(dev, 99))
    return row


def uv_flips(orig, out, samples_unused=None):
    """Output triangles whose UV orientation differs from that of the input triangle closest to
    their centroid (docs/notes/qem.md's count)."""
    (opos, ofaces, oattr), (spos, sfaces, sattr) = orig, out
    if oattr.get("uv") is None or sattr.get("uv") is None:
        return None

    def orient(uv):
        e1, e2 = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
        return np.sign(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])

    cen = spos[sfaces].mean(1)
    f, _, _ = closest(cen, opos, ofaces)
    return int((orient(sattr["uv"]) != orient(oattr["uv"][f])).sum()), len(sfaces)


def gng3d_run(exe, mesh, out, faces, extra):
    cmd = [exe, "simplify", mesh, out, "--method", "qem", "--faces", str(faces), "--json"] + extra
    r = subprocess.run(cmd, capture_output=True, text=True, check=True)
    out = json.loads(r.stdout)
    report = out["report"]
    if not report.get("target_reached", True):
        print(f"  ({os.path.basename(mesh)}: stopped, {report.get('stop_reason')}, "
              f"{report.get('faces')} faces for {faces})", file=sys.stderr)
    return out["seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gng3d", required=True)
    ap.add_argument("--meshes", default=os.environ.get("GNG3D_MESHES", "/work/shared/meshes"))
    ap.add_argument("--samples", type=int, default=100_000)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--ratios", default="0.1,0.05")
    ap.add_argument("--weights", default="uv=0,normal=0,color=0",
                    help="the attribute weights given to both (gng3d --attribute-weights)")
    ap.add_argument("--ours-weights", default=None,
                    help="gng3d's --attribute-weights when not --weights (weight experiments)")
    ap.add_argument("--only", default=None, help="comma-separated mesh file names to run")
    ap.add_argument("--files", default=None,
                    help="comma-separated mesh paths to run instead of the three test meshes "
                    "(e.g. synthetic atlases from `cargo run -p gng3d-mesh --example atlas`)")
    ap.add_argument("--no-meshlab", action="store_true", help="leave MeshLab out")
    ap.add_argument("--extra", default="", help="more gng3d simplify flags")
    args = ap.parse_args()
    weights = {k: float(v) for k, v in (kv.split("=") for kv in args.weights.split(","))}
    fn = meshopt_lib()
    meshes = [
        os.path.join(args.meshes, "spot.obj"),
        os.path.join(ROOT, "tests/assets/fandisk_atlas.obj"),
        os.path.join(ROOT, "tests/assets/knight_colors.ply"),
    ]
    if args.files:
        meshes = args.files.split(",")
    if args.only:
        meshes = [m for m in meshes if os.path.basename(m) in args.only.split(",")]
    tmp = tempfile.mkdtemp(prefix="attr_vs_meshopt_")
    meshlab = has_meshlab() and not args.no_meshlab
    if not meshlab:
        print("MeshLab: skipped (pymeshlab not installed, or --no-meshlab)")
    print(f"weights {args.weights}; {args.samples} samples per direction; time: min of "
          f"{args.repeats}, alternating")
    print("| mesh | share | method | faces | Hausdorff | mean | UV mean / 99 % | colour mean / 99 % "
          "| normal ° mean / 99 % | UV-flipped | ms |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for mesh in meshes:
        orig = load(mesh)
        vpos, vattr, idx, w = wedge_buffers(*orig, weights)
        name = os.path.basename(mesh)
        ext = ".ply" if mesh.endswith(".ply") else ".obj"
        for share in [float(r) for r in args.ratios.split(",")]:
            target = max(4, round(len(orig[1]) * share))
            ours = os.path.join(tmp, f"{name}-{share}-gng3d{ext}")
            extra = ["--attribute-weights", args.ours_weights or args.weights] + args.extra.split()
            t_ours, t_mo, t_ml = [], [], []
            ml = None
            for _ in range(args.repeats):
                t_ours.append(gng3d_run(args.gng3d, mesh, ours, target, extra))
                dt, mo_faces = run_meshopt(fn, vpos, vattr, idx, w, target)
                t_mo.append(dt)
                if meshlab:
                    dt, ml = run_meshlab(mesh, target, orig[2])
                    t_ml.append(dt)
            a = load(ours)
            # meshoptimizer's output: its kept wedge vertices with their values.
            mo_pos = vpos.astype(np.float64)
            mo_attr = {}
            col = 0
            for key, k in (("uv", 2), ("normal", 3), ("color", 4)):
                if orig[2].get(key) is not None:
                    mo_attr[key] = vattr[:, col:col + k].astype(np.float64)[mo_faces]
                    col += k
            mo = (mo_pos, mo_faces.astype(np.int64), mo_attr)
            runs = [("gng3d QEM", a, min(t_ours)), ("meshoptimizer", mo, min(t_mo))]
            if ml is not None:
                runs.append(("MeshLab", ml, min(t_ml)))
            for label, res, t in runs:
                m = measure(orig, res, args.samples)
                flips = uv_flips(orig, res)

                def pair(key, fmt):
                    return (fmt.format(*m[key]) if key in m else "-")

                print(f"| {name} | {share} | {label} | {len(res[1])} | {m['hausdorff']:.3e} | "
                      f"{m['mean']:.3e} | {pair('uv', '{:.2e} / {:.2e}')} | "
                      f"{pair('color', '{:.2e} / {:.2e}')} | {pair('normal', '{:.2f} / {:.1f}')} | "
                      f"{'-' if flips is None else f'{flips[0]} of {flips[1]}'} | "
                      f"{1e3 * t:.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
