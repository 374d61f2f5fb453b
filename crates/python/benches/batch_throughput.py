"""gng3d.batch throughput on a Dask LocalCluster with 1 and 2 worker processes over the shared
meshes (GNG3D-Q at --ratio of each input's vertices); prints files/s and the speed-up.

    pip install ./crates/python[dask]
    python crates/python/benches/batch_throughput.py [--ratio 0.1] [--skip igea-1m.ply]
"""

import argparse
import os
import tempfile
import time
from pathlib import Path

from distributed import Client, LocalCluster

from gng3d import batch


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ratio", type=float, default=0.1)
    parser.add_argument("--skip", default="igea-1m.ply")
    args = parser.parse_args()
    root = Path(__file__).resolve().parents[3].parent / "shared" / "meshes"
    folder = Path(os.environ.get("GNG3D_MESHES", root))
    files = [p for p in batch.list_inputs(folder) if p.name not in args.skip.split(",")]
    times = {}
    for workers in (1, 2):
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:  # fmt: skip
            with tempfile.TemporaryDirectory() as out:
                start = time.perf_counter()
                rows = batch.simplify_files(files, out, ratio=args.ratio, client=client,
                                            suffix=".ply")  # fmt: skip
                times[workers] = time.perf_counter() - start
        print(f"{workers} worker(s): {len(files)} files in {times[workers]:.2f} s "
              f"({len(files) / times[workers]:.2f} files/s); {batch.summary(rows)}")  # fmt: skip
    print(f"speed-up with 2 workers: {times[1] / times[2]:.2f}x")


if __name__ == "__main__":
    main()
