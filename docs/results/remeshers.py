"""GNG3D-Q against the fixed-count isotropic remeshers, in one run (issue 49's table).

For each mesh and share of its vertices (default 2 % and 10 %):
- ACVD (`pyacvd`, approximated centroidal Voronoi clustering) and Instant Meshes
  (`pyinstantmeshes`, triangle mode: rosy=6, posy=3) run in this process, both asked for the
  share's vertex count N. Neither hits N exactly;
- our CLI runs as a process, `gng3d simplify --method gng` (and `--shape` with --shape) and
  `--method qem`, at exactly the count ACVD reached (so GNG3D-Q, QEM and ACVD have the same
  vertex count; Instant Meshes' own count is in the table);
- every output is measured by the same code, `gng3d metrics ORIGINAL OUT --json`: Hausdorff
  (symmetric max), mean distance (the two directions' area-weighted means, averaged), median
  smallest angle of the triangles, share of triangles with an angle under 20°.

Times are of the algorithm alone: the peers' remesh call (after reading and welding the mesh
with pyvista), our runs' `"seconds"` from `--json` (the run from the loaded mesh to the output,
loading and saving excluded).

Usage (a throw-away venv for the peers, measurement only):
    python3 -m venv /tmp/remeshvenv
    /tmp/remeshvenv/bin/pip install numpy pyacvd pyvista pyinstantmeshes
    cargo build --release -p gng3d-cli
    /tmp/remeshvenv/bin/python docs/results/remeshers.py --gng3d target/release/gng3d \\
        --shape $GNG3D_MESHES armadillo.obj igea.ply rocker-arm.obj fandisk.obj

Prints the markdown table on stdout (progress on stderr); every output mesh, its metrics and
a results.json with every number go to --out (default /tmp/remeshers).
"""

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pyacvd
import pyinstantmeshes
import pyvista as pv


def polydata(vertices: np.ndarray, faces: np.ndarray) -> pv.PolyData:
    """A triangle PolyData (quads, if any, split in two)."""
    faces = np.asarray(faces, dtype=np.int64)
    if faces.shape[1] == 4:
        faces = np.vstack([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    cells = np.hstack([np.full((len(faces), 1), 3, dtype=np.int64), faces]).ravel()
    return pv.PolyData(np.asarray(vertices, dtype=np.float64), cells)


def acvd(surface: pv.PolyData, n: int, out: Path) -> dict:
    start = time.perf_counter()
    clustering = pyacvd.Clustering(surface)
    clustering.cluster(n)
    remeshed = clustering.create_mesh()
    seconds = time.perf_counter() - start
    remeshed.save(str(out), binary=True)
    return {"vertices": int(remeshed.n_points), "seconds": seconds}


def instant_meshes(surface: pv.PolyData, n: int, out: Path) -> dict:
    vertices = np.asarray(surface.points, dtype=np.float32)
    faces = np.asarray(surface.faces.reshape(-1, 4)[:, 1:], dtype=np.int32)
    # Instant Meshes logs on the process's stdout: sent to stderr, stdout is the table's.
    sys.stdout.flush()
    saved = os.dup(1)
    os.dup2(2, 1)
    try:
        start = time.perf_counter()
        v, f = pyinstantmeshes.remesh(vertices, faces, target_vertex_count=n, rosy=6, posy=3)
        seconds = time.perf_counter() - start
    finally:
        os.dup2(saved, 1)
        os.close(saved)
    polydata(v, f).save(str(out), binary=True)
    return {"vertices": int(len(v)), "seconds": seconds}


def ours(gng3d: str, original: Path, n: int, out: Path, options: list[str]) -> dict:
    command = [gng3d, "simplify", str(original), str(out), "--vertices", str(n), "--json"]
    run = subprocess.run(command + options, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{' '.join(command + options)} failed:\n{run.stderr}")
    report = json.loads(run.stdout)
    return {"vertices": report["vertices"], "seconds": report["seconds"]}


def measure(gng3d: str, original: Path, out: Path, samples: int) -> dict:
    command = [gng3d, "metrics", str(original), str(out), "--json", "--samples", str(samples)]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{run.stderr}")
    out.with_suffix(".metrics.json").write_text(run.stdout)
    m = json.loads(run.stdout)
    h, q = m["hausdorff"], m["quality"]["simplified"]
    return {
        "hausdorff": h["max"],
        "mean": (h["forward"]["area_mean"] + h["backward"]["area_mean"]) / 2,
        "median_angle": q["median_min_angle_degrees"],
        "under_20": q["below_20_degrees"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mesh_dir", type=Path)
    parser.add_argument("meshes", nargs="+")
    parser.add_argument("--gng3d", default="target/release/gng3d", help="the CLI to run")
    parser.add_argument("--shares", type=float, nargs="+", default=[0.02, 0.10])
    parser.add_argument("--shape", action="store_true", help="also GNG3D-Q with --shape")
    parser.add_argument("--samples", type=int, default=200_000, help="gng3d metrics --samples")
    parser.add_argument("--out", type=Path, default=Path("/tmp/remeshers"))
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)

    methods = ["acvd", "instant", "gng"] + (["shape"] if args.shape else []) + ["qem"]
    results = []
    for name in args.meshes:
        original = args.mesh_dir / name
        surface = pv.read(str(original)).triangulate().clean()  # welded, as our loader does
        stem = Path(name).stem
        for share in args.shares:
            n = round(surface.n_points * share)
            tag = f"{stem}-{round(share * 100)}"
            out = {m: args.out / f"{tag}-{m}.ply" for m in methods}
            print(f"{tag}: N = {n}", file=sys.stderr)
            runs = {"acvd": acvd(surface, n, out["acvd"])}
            runs["instant"] = instant_meshes(surface, n, out["instant"])
            # Ours at the count ACVD reached (it does not hit N exactly).
            count = runs["acvd"]["vertices"]
            runs["gng"] = ours(args.gng3d, original, count, out["gng"], ["--method", "gng"])
            if args.shape:
                runs["shape"] = ours(
                    args.gng3d, original, count, out["shape"], ["--method", "gng", "--shape"]
                )
            runs["qem"] = ours(args.gng3d, original, count, out["qem"], ["--method", "qem"])
            for m in methods:
                runs[m].update(measure(args.gng3d, original, out[m], args.samples))
                print(f"  {m}: {runs[m]}", file=sys.stderr)
            results.append({"mesh": stem, "share": share, "target": n, "runs": runs})
    (args.out / "results.json").write_text(json.dumps(results, indent=1))
    print(table(results, args.shape))


def table(results: list[dict], shape: bool) -> str:
    def quality(r: dict) -> str:
        return f"{r['median_angle']:.1f}° / {100 * r['under_20']:.1f} %"

    def versus(a: dict, b: dict) -> str:
        return f"×{a['mean'] / b['mean']:.2f}, ×{a['hausdorff'] / b['hausdorff']:.2f}"

    head = ["mesh @ share (vertices: ACVD / Instant)", "GNG3D-Q angle / <20°"]
    head += ["GNG3D-Q --shape"] if shape else []
    head += ["ACVD", "Instant Meshes", "QEM", "GNG3D-Q mean, Hausdorff vs QEM"]
    head += ["--shape vs QEM"] if shape else []
    head += ["GNG3D-Q vs ACVD", "GNG3D-Q time vs ACVD / Instant"]
    head += ["--shape time vs ACVD"] if shape else []
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for row in results:
        r = row["runs"]
        g, a, i, q = r["gng"], r["acvd"], r["instant"], r["qem"]
        cells = [
            f"{row['mesh']} {round(row['share'] * 100)} % ({a['vertices']} / {i['vertices']})",
            quality(g),
        ]
        cells += [quality(r["shape"])] if shape else []
        cells += [quality(a), quality(i), quality(q), versus(g, q)]
        cells += [versus(r["shape"], q)] if shape else []
        cells += [
            versus(g, a),
            f"×{g['seconds'] / a['seconds']:.2f} / ×{g['seconds'] / i['seconds']:.2f}",
        ]
        cells += [f"×{r['shape']['seconds'] / a['seconds']:.2f}"] if shape else []
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
