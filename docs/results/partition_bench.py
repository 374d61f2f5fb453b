"""Bench of the partitioned simplification (issue 50): one generated mesh of N faces simplified
by ``gng3d.distributed.simplify`` on a local Dask cluster with 1 and with 2 worker processes
(a memory limit set on each worker), and by the single-process ``gng3d simplify`` (whole mesh in
memory); prints the wall time, the throughput (input faces a second) and the peak RSS of every
process: this driver (which partitions, stitches and finishes), each Dask worker, each nanny,
and the CLI.

Usage (from the repository root, with the Python package installed in the running Python and
the CLI and the generator built in release)::

    cargo build --release -p gng3d-cli -p gng3d-partition --example generate
    python docs/results/partition_bench.py --faces 1000000 --ratio 0.01 \\
        --budget 64MiB --memory-limit 3GB --dir /tmp/partition-bench

Peaks: a worker's from ``getrusage`` inside it (exact); a nanny's sampled every 50 ms with
psutil (when installed); the CLI's from ``wait4``; this driver's from ``getrusage``, which
covers its whole life, so the 1-worker run goes first and the driver's peak is read after it
and again at the end.
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import threading
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def kib_to_mb(kib: int) -> float:
    """ru_maxrss is in KiB on Linux."""
    return kib * 1024 / 1e6


def worker_peak_kib() -> int:
    import resource as r

    return r.getrusage(r.RUSAGE_SELF).ru_maxrss


class NannySampler:
    """The peak RSS of this process's child processes (the nannies and their workers), sampled."""

    def __init__(self) -> None:
        self.peaks: dict[int, tuple[str, int]] = {}
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def _run(self) -> None:
        try:
            import psutil
        except ImportError:
            return
        me = psutil.Process()
        while not self._stop.is_set():
            for child in me.children(recursive=True):
                try:
                    rss = child.memory_info().rss
                    name = " ".join(child.cmdline()[-2:])[:40]
                except psutil.Error:
                    continue
                old = self.peaks.get(child.pid, (name, 0))[1]
                self.peaks[child.pid] = (name, max(old, rss))
            time.sleep(0.05)

    def __enter__(self) -> "NannySampler":
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join()


def run_dask(mesh: Path, out: Path, work: Path, workers: int, args: argparse.Namespace) -> None:
    from dask.distributed import Client, LocalCluster

    from gng3d import distributed

    with NannySampler() as sampler:
        with LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            memory_limit=args.memory_limit,
            dashboard_address=None,
        ) as cluster, Client(cluster) as client:
            start = time.perf_counter()
            report = distributed.simplify(
                mesh, out, ratio=args.ratio, client=client,
                memory_per_worker=args.budget, work_dir=work,
            )  # fmt: skip
            seconds = time.perf_counter() - start
            peaks = client.run(worker_peak_kib)
    faces = report["input_faces"]
    steps = ", ".join(f"{k} {v:.2f} s" for k, v in report["step_seconds"].items())
    print(
        f"dask, {workers} worker(s): {seconds:.2f} s, {faces / seconds / 1e6:.2f} M faces/s, "
        f"{report['cells']} cells ({steps}), {report['faces']} faces out"
    )
    for address, kib in sorted(peaks.items()):
        print(f"  worker {address}: peak RSS {kib_to_mb(kib):.0f} MB")
    for pid, (name, rss) in sorted(sampler.peaks.items()):
        print(f"  child process {pid} ({name}): peak RSS {rss / 1e6:.0f} MB (sampled)")
    driver = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(f"  driver (partition, stitch, finish): peak RSS so far {kib_to_mb(driver):.0f} MB")


def run_cli(mesh: Path, out: Path, args: argparse.Namespace) -> None:
    cli = args.cli or str(REPO / "target" / "release" / "gng3d")
    start = time.perf_counter()
    proc = subprocess.Popen(
        [cli, "simplify", str(mesh), str(out), "--ratio", str(args.ratio)],
        stdout=subprocess.DEVNULL,
    )
    _, status, usage = os.wait4(proc.pid, 0)
    seconds = time.perf_counter() - start
    if status != 0:
        sys.exit(f"{cli} failed ({status})")
    faces = args.input_faces
    print(
        f"single-process gng3d simplify: {seconds:.2f} s, {faces / seconds / 1e6:.2f} M faces/s, "
        f"peak RSS {kib_to_mb(usage.ru_maxrss):.0f} MB"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--faces", type=int, default=1_000_000)
    parser.add_argument("--ratio", type=float, default=0.01)
    parser.add_argument("--budget", default="64MiB", help="memory_per_worker: bytes a cell")
    parser.add_argument("--memory-limit", default="3GB", help="Dask's limit on each worker")
    parser.add_argument("--dir", type=Path, default=Path("/tmp/partition-bench"))
    parser.add_argument("--cli", help="the gng3d binary (default target/release/gng3d)")
    parser.add_argument("--generator", help="default target/release/examples/generate")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    mesh = args.dir / f"sphere-{args.faces}.ply"
    if not mesh.exists():
        generator = args.generator or str(REPO / "target" / "release" / "examples" / "generate")
        subprocess.run([generator, str(args.faces), str(mesh)], check=True)
    from gng3d import distributed  # noqa: F401  (fails early when the package is missing)

    # The input's face count, from the header (the same numbers the runs report).
    header = mesh.open("rb").read(4096).split(b"end_header")[0].decode()
    args.input_faces = int(header.split("element face ")[1].split()[0])
    print(f"{mesh}: {args.input_faces} faces, ratio {args.ratio}, cell budget {args.budget}, "
          f"worker memory limit {args.memory_limit}")  # fmt: skip
    for workers in (1, 2):
        run_dask(mesh, args.dir / f"out-{workers}.ply", args.dir / f"work-{workers}", workers, args)
    run_cli(mesh, args.dir / "out-cli.ply", args)


if __name__ == "__main__":
    main()
