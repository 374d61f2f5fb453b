"""Regenerates meshlab_pairs.json (and the small simplified meshes next to it) with pymeshlab.

For each original in $GNG3D_MESHES and each ratio, MeshLab's quadric edge collapse makes the
simplified mesh (saved here as binary PLY when under 200 kB), then MeshLab's Hausdorff filter
measures both directions with vertex + edge + face sampling and samplenum = N: the figures our
`HausdorffParams::meshlab(N)` must match within 1 %. Run:

    python3 -m venv /tmp/venv-cli && /tmp/venv-cli/bin/pip install pymeshlab
    GNG3D_MESHES=/work/shared/meshes /tmp/venv-cli/bin/python make_pairs.py
"""

import json
import os
import sys

import pymeshlab

HERE = os.path.dirname(os.path.abspath(__file__))
MESHES = os.environ.get("GNG3D_MESHES", "/work/shared/meshes")
ORIGINALS = ["cow.obj", "rocker-arm.obj", "fertility.obj", "casting.obj", "spot.obj"]
RATIOS = [0.01, 0.10]
SAMPLES = 300_000
MAX_BYTES = 200_000


def hausdorff(ms, source, target, samples):
    r = ms.get_hausdorff_distance(
        sampledmesh=source,
        targetmesh=target,
        samplevert=True,
        sampleedge=True,
        samplefauxedge=False,
        sampleface=True,
        samplenum=samples,
        maxdist=pymeshlab.PercentageValue(100),
    )
    return {"max": r["max"], "mean": r["mean"], "RMS": r["RMS"], "n_samples": r["n_samples"]}


def main():
    pairs = []
    for name in ORIGINALS:
        for ratio in RATIOS:
            ms = pymeshlab.MeshSet()
            ms.load_new_mesh(os.path.join(MESHES, name))
            faces = ms.current_mesh().face_number()
            target = max(4, int(round(faces * ratio)))
            ms.load_new_mesh(os.path.join(MESHES, name))
            ms.meshing_decimation_quadric_edge_collapse(targetfacenum=target, preservetopology=True)
            out = f"{os.path.splitext(name)[0]}-meshlab-{int(ratio * 100)}pct.ply"
            path = os.path.join(HERE, out)
            ms.save_current_mesh(path, binary=True, save_vertex_normal=False, save_vertex_color=False,
                                 save_face_color=False, save_wedge_texcoord=False, save_vertex_quality=False,
                                 save_face_quality=False)
            size = os.path.getsize(path)
            if size > MAX_BYTES:
                os.remove(path)
                print(f"skip {out}: {size} bytes", file=sys.stderr)
                continue
            fwd = hausdorff(ms, 0, 1, SAMPLES)
            bwd = hausdorff(ms, 1, 0, SAMPLES)
            pairs.append({
                "original": name,
                "simplified": out,
                "ratio": ratio,
                "samplenum": SAMPLES,
                "simplified_faces": ms.mesh(1).face_number(),
                "meshlab_hausdorff": {
                    "forward_original_to_simplified": fwd,
                    "backward_simplified_to_original": bwd,
                },
            })
            print(out, size, fwd, bwd, file=sys.stderr)
    with open(os.path.join(HERE, "meshlab_pairs.json"), "w") as f:
        json.dump({"pymeshlab": pymeshlab.__version__ if hasattr(pymeshlab, "__version__") else "unknown",
                   "pairs": pairs}, f, indent=1)


if __name__ == "__main__":
    main()
