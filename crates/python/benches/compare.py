"""GNG3D-Q and QEM (gng3d) against fast-simplification, meshoptimizer and pymeshlab on the same
numpy arrays, at equal face count: time and symmetric surface distance (gng3d.metrics).

    pip install fast-simplification meshoptimizer pymeshlab
    python crates/python/benches/compare.py [--ratio 0.1] [--meshes spot.obj,igea.ply]

The face count is what GNG3D-Q gives for ``ratio`` of the input's vertices; every other tool is
asked for that many faces. Times are the best of ``--repeat`` runs of the call alone (arrays in
memory); distances are relative to the original's bounding-box diagonal, 10^-3 units.
"""

import argparse
import os
import time
import warnings
from pathlib import Path

import numpy as np

import gng3d


def best_time(fn, repeat):
    best, out = None, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        t = time.perf_counter() - start
        best = t if best is None else min(best, t)
    return best, out


def compact(v, f):
    """Drop unreferenced vertices (meshoptimizer returns indices into the input's vertices)."""
    used, inverse = np.unique(f.reshape(-1), return_inverse=True)
    return v[used], inverse.reshape(-1, 3)


def tools(faces_target, ratio, seed):
    def gng(v, f):
        r = gng3d.simplify(v, f, ratio=ratio, seed=seed)
        return r.vertices, r.faces

    def qem(v, f):
        r = gng3d.simplify(v, f, faces_target=faces_target, method="qem")
        return r.vertices, r.faces

    out = {"gng3d GNG3D-Q": gng, "gng3d QEM": qem}
    try:
        import fast_simplification

        out["fast-simplification"] = lambda v, f: fast_simplification.simplify(
            v.astype(np.float32), f.astype(np.int32), target_count=faces_target
        )
    except ImportError:
        pass
    try:
        import meshoptimizer

        def mo(v, f):
            indices = f.astype(np.uint32).reshape(-1)
            dest = np.zeros_like(indices)
            n = meshoptimizer.simplify(dest, indices, v.astype(np.float32),
                                       target_index_count=3 * faces_target,
                                       target_error=1.0)  # fmt: skip
            return compact(v, dest[:n].reshape(-1, 3).astype(np.int64))

        out["meshoptimizer"] = mo
    except ImportError:
        pass
    try:
        import pymeshlab

        def ml(v, f):
            ms = pymeshlab.MeshSet()
            ms.add_mesh(pymeshlab.Mesh(v, f.astype(np.int32)))
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=faces_target)
            m = ms.current_mesh()
            return m.vertex_matrix(), m.face_matrix()

        out["pymeshlab"] = ml
    except ImportError:
        pass
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ratio", type=float, default=0.1)
    parser.add_argument("--meshes", default="stanford-bunny.obj,spot.obj,fandisk.obj,horse.ply,armadillo.obj,igea.ply")
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--samples", type=int, default=200_000)
    args = parser.parse_args()
    folder = Path(os.environ.get("GNG3D_MESHES", Path(__file__).resolve().parents[3].parent / "shared" / "meshes"))
    warnings.simplefilter("ignore")
    print(f"| mesh | faces in -> out | tool | seconds | Hausdorff max | mean | (x 1e-3 diag, ratio {args.ratio}) |")
    print("|---|---|---|---|---|---|")
    for name in args.meshes.split(","):
        v, f = gng3d.load(folder / name)
        ref = gng3d.simplify(v, f, ratio=args.ratio, seed=1)
        target = len(ref.faces)
        for tool, fn in tools(target, args.ratio, 1).items():
            try:
                seconds, (v2, f2) = best_time(lambda: fn(v, f), args.repeat)
                m = gng3d.metrics(v, f, v2, f2, samples=args.samples)
                d = m["bbox_diagonal"]
                h = m["hausdorff"]
                print(f"| {name} | {len(f)} -> {len(f2)} | {tool} | {seconds:.3f} | "
                      f"{1e3 * h['max'] / d:.3f} | {1e3 * h['mean'] / d:.4f} |")  # fmt: skip
            except Exception as e:
                print(f"| {name} | {len(f)} -> ? | {tool} | error: {type(e).__name__}: {e} | | |")


if __name__ == "__main__":
    main()
