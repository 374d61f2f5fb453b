"""ACVD (pyacvd) as an outside reference for docs/results.md.

For each mesh: cluster the original surface into N Voronoi regions with pyacvd (N = 10 % of
the welded vertex count, the survey's 0.10 ratio), write the remeshed surface as PLY, then the
caller measures it with `gng3d metrics ORIGINAL ACVD.ply --json` and runs
`gng3d compare ORIGINAL --vertices <ACVD's output count> --json` (GNG3D-Q and QEM at exactly
ACVD's vertex count, same surface sampling).

Usage: python acvd.py MESH_DIR OUT_DIR mesh1 [mesh2 ...]
Prints one line per mesh: name, target, output vertex count, PLY path.
Needs pyvista and pyacvd (a throw-away venv: pip install pyacvd pyvista).
"""

import sys
from pathlib import Path

import pyacvd
import pyvista as pv


def remesh(path: Path, out_dir: Path, ratio: float = 0.10) -> tuple[int, int, Path]:
    surface = pv.read(str(path)).triangulate().clean()  # weld, drop unreferenced vertices
    target = round(surface.n_points * ratio)
    clus = pyacvd.Clustering(surface)
    clus.cluster(target)
    remeshed = clus.create_mesh()
    out = out_dir / (path.stem + "-acvd.ply")
    remeshed.save(str(out), binary=True)
    return target, remeshed.n_points, out


def main() -> None:
    mesh_dir, out_dir = Path(sys.argv[1]), Path(sys.argv[2])
    out_dir.mkdir(parents=True, exist_ok=True)
    for name in sys.argv[3:]:
        target, got, out = remesh(mesh_dir / name, out_dir)
        print(f"{name} {target} {got} {out}")


if __name__ == "__main__":
    main()
