"""Simplify many mesh files at once: on a local process pool, or on a Dask cluster.

File paths travel to the workers, not arrays: each worker loads, simplifies and writes its
files itself with :func:`gng3d.simplify_file` (atomically, as :func:`gng3d.save` does, keeping
normals, texture coordinates, colours and materials where the output format stores them). Every file gives one status row -- ok,
skipped (its output was already there) or error with its message -- instead of an exception,
so one broken file never stops the others, and nothing is retried silently (a file that fails
says so in its row). Rows are written to ``stats.csv`` in the output folder as files complete,
so a killed run resumes where it stopped: outputs that exist are complete (atomic writes) and
are skipped.

Example (local, two processes)::

    from gng3d import batch
    rows = batch.simplify_files("meshes/", "out/", ratio=0.1, jobs=2)
    print(batch.summary(rows))

On a Dask cluster (``pip install ./crates/python[dask]``)::

    from dask.distributed import Client
    client = Client("tcp://scheduler:8786")   # or Client(LocalCluster(n_workers=2))
    rows = batch.simplify_files(paths, "/shared/out", ratio=0.1, client=client)

Workers on other hosts need gng3d installed and the input and output paths visible under
the same names (a shared file system); nothing else changes.

The command-line form for schedulers without Dask (Slurm arrays, ``xargs -P``) shards the
files statically and prints one JSON line per file::

    python -m gng3d.batch meshes/ --out out/ --ratio 0.1 --rank 0 --world-size 4
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

from . import _gng3d

MESH_EXTENSIONS = (".obj", ".ply", ".stl", ".gltf", ".glb")
STATS_FIELDS = [
    "input",
    "output",
    "status",
    "error",
    "warnings",
    "method",
    "input_vertices",
    "input_faces",
    "vertices",
    "faces",
    "seconds",
    "hausdorff_max",
    "hausdorff_mean",
]

PathLike = Union[str, "os.PathLike[str]"]


def list_inputs(source: Union[PathLike, Iterable[PathLike]]) -> List[Path]:
    """The mesh files of ``source``: a folder (its .obj, .ply, .stl, .gltf and .glb files, sorted), a
    manifest (a text file with one path per line; relative paths are relative to it), or an
    iterable of paths (kept in its order)."""
    if isinstance(source, (str, os.PathLike)):
        path = Path(source)
        if path.is_dir():
            return sorted(p for p in path.iterdir() if p.suffix.lower() in MESH_EXTENSIONS)
        if path.suffix.lower() in MESH_EXTENSIONS:
            return [path]
        lines = path.read_text().splitlines()
        return [
            (path.parent / line.strip())
            for line in lines
            if line.strip() and not line.lstrip().startswith("#")
        ]
    return [Path(p) for p in source]


def shard(paths: Sequence[Path], rank: int, world_size: int) -> List[Path]:
    """The files of ``rank`` among ``world_size`` (every ``world_size``-th, from ``rank``)."""
    if world_size < 1 or not 0 <= rank < world_size:
        raise ValueError(f"rank must be in [0, world_size), got rank {rank}, world size {world_size}")
    return list(paths[rank::world_size])


def output_path(path: Path, out_dir: Path, suffix: Optional[str]) -> Path:
    """Where ``path``'s result goes: same name in ``out_dir`` (``suffix`` changes the format)."""
    return out_dir / (path.stem + (suffix or path.suffix))


def _row(path: Path, out: Path, method: str) -> Dict[str, Any]:
    row: Dict[str, Any] = {k: None for k in STATS_FIELDS}
    row.update(input=str(path), output=str(out), method=method, warnings="")
    return row


def simplify_file(
    path: PathLike,
    out: PathLike,
    options: Dict[str, Any],
    skip_existing: bool = True,
    measure: bool = False,
    samples: Optional[int] = None,
) -> Dict[str, Any]:
    """Simplify one file into ``out`` with :func:`gng3d.simplify_file`, which keeps its
    normals, texture coordinates, colours and materials where the output format stores them
    (what it cannot keep is one of the row's ``warnings``); never raises: any error is the
    row's ``error``. ``input_vertices`` and ``input_faces`` are the file's vertex records and
    triangles, as :func:`gng3d.load` counts them."""
    import gng3d

    path, out = Path(path), Path(out)
    row = _row(path, out, options.get("method", _gng3d.DEFAULT_METHOD))
    start = time.perf_counter()
    if skip_existing and out.exists():
        row["status"] = "skipped"
        return row
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            result = gng3d.simplify_file(path, out, **options)
        row["input_vertices"] = result.report["file_vertices"]
        row["input_faces"] = result.report["file_faces"]
        row["warnings"] = "; ".join(str(w.message) for w in caught)
        row["vertices"], row["faces"] = len(result.vertices), len(result.faces)
        if measure:
            # The geometry only: the file's warnings were raised (and recorded) above.
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", gng3d.Gng3dWarning)
                v, f = gng3d.load(path)
            m = gng3d.metrics(v, f, result.vertices, result.faces, samples=samples)
            row["hausdorff_max"] = m["hausdorff"]["max"]
            row["hausdorff_mean"] = m["hausdorff"]["mean"]
        row["status"] = "ok"
    except Exception as e:  # a row, never a stop: the batch goes on with the other files
        row["status"] = "error"
        row["error"] = f"{type(e).__name__}: {e}"
    row["seconds"] = round(time.perf_counter() - start, 6)
    return row


def _simplify_chunk(jobs: List[tuple], options, skip_existing, measure, samples):
    return [simplify_file(p, o, options, skip_existing, measure, samples) for p, o in jobs]


class _Stats:
    """stats.csv, a row appended (and flushed) as each file completes; rows of an earlier run
    of the same outputs are kept, the newest row of a file wins when it is read back."""

    def __init__(self, path: Optional[Path]):
        self.path = path
        self.file = None
        # The rows of an earlier run, by output: a skipped file keeps its counts and metrics.
        self.previous: Dict[str, Dict[str, Any]] = {}
        if path is not None and path.exists():
            with open(path, newline="") as f:
                for row in csv.DictReader(f):
                    if row.get("status") == "ok":
                        self.previous[row["output"]] = row
        if path is not None:
            new = not path.exists() or path.stat().st_size == 0
            self.file = open(path, "a", newline="")
            self.writer = csv.DictWriter(self.file, fieldnames=STATS_FIELDS)
            if new:
                self.writer.writeheader()
                self.file.flush()

    def add(self, row: Dict[str, Any]) -> Dict[str, Any]:
        """Records ``row`` and returns it; a skipped file that an earlier run recorded is not
        written again and comes back with that run's counts (status "skipped")."""
        earlier = self.previous.get(row["output"])
        if row["status"] == "skipped" and earlier is not None:
            kept = dict(earlier, status="skipped")
            for key in ("input_vertices", "input_faces", "vertices", "faces"):
                kept[key] = int(kept[key]) if kept.get(key) else None
            for key in ("seconds", "hausdorff_max", "hausdorff_mean"):
                kept[key] = float(kept[key]) if kept.get(key) else None
            kept["error"] = kept.get("error") or None
            return kept
        if self.file is not None:
            self.writer.writerow(row)
            self.file.flush()
        return row

    def close(self) -> None:
        if self.file is not None:
            self.file.close()


def summary(rows: Sequence[Dict[str, Any]], seconds: Optional[float] = None) -> str:
    """One line: how many files were ok, skipped and failed (and the wall time)."""
    count = {s: sum(1 for r in rows if r["status"] == s) for s in ("ok", "skipped", "error")}
    line = (
        f"{len(rows)} files: {count['ok']} ok, {count['skipped']} skipped, "
        f"{count['error']} errors"
    )
    if seconds is not None:
        line += f" in {seconds:.2f} s"
    return line


def simplify_files(
    paths: Union[PathLike, Iterable[PathLike]],
    out_dir: PathLike,
    *,
    method: str = _gng3d.DEFAULT_METHOD,
    vertices_target: Optional[int] = None,
    faces_target: Optional[int] = None,
    ratio: Optional[float] = None,
    seed: Optional[int] = None,
    client: Any = None,
    jobs: Optional[int] = None,
    skip_existing: bool = True,
    measure: bool = False,
    samples: Optional[int] = None,
    suffix: Optional[str] = None,
    stats: Optional[str] = "stats.csv",
    tasks_per_worker: int = 10,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Simplify every file of ``paths`` into ``out_dir``; returns one status row per file.

    Args:
        paths: a folder, a manifest file (one path per line) or an iterable of paths.
        out_dir: the output folder (created); each result keeps its input's name (``suffix``,
            e.g. ``".ply"``, changes the format).
        method, vertices_target, faces_target, ratio, seed, **options: as for
            :func:`gng3d.simplify` (checked once before any file is read); ``threads``
            defaults to the cores shared out among the processes (1 on Dask).
        client: a ``dask.distributed.Client``: the files run as tasks on its workers
            (about ``tasks_per_worker`` tasks per worker, no retries). ``None``: a local pool of
            ``jobs`` processes (default: the number of cores).
        skip_existing: files whose output exists are skipped (a killed run resumes).
        measure: also measure each result (``hausdorff_max``/``hausdorff_mean``, ``samples``
            per direction).
        stats: the CSV written in ``out_dir`` as files complete (None: none).

    Returns:
        list of dict, in the order of ``paths``: ``input``, ``output``, ``status`` ("ok",
        "skipped" or "error"), ``error``, ``warnings``, ``method``, counts, ``seconds``, and
        the metrics when measured.
    """
    files = list_inputs(paths)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    simplify_options = dict(
        method=method,
        vertices_target=vertices_target,
        faces_target=faces_target,
        ratio=ratio,
        seed=seed,
        **options,
    )
    if "threads" not in simplify_options:
        # One file per core: each run on one thread (the same meshes as on any count).
        cores = os.cpu_count() or 1
        simplify_options["threads"] = 1 if client is not None else max(1, cores // (jobs or cores))
    _check_options(simplify_options)
    outputs = [output_path(p, out_dir, suffix) for p in files]
    seen: Dict[Path, Path] = {}
    for p, o in zip(files, outputs):
        if o in seen:
            raise ValueError(f"{p} and {seen[o]} would both be written to {o}")
        seen[o] = p
    start = time.perf_counter()
    table = _Stats(out_dir / stats if stats else None)
    rows: Dict[int, Dict[str, Any]] = {}
    try:
        if client is None:
            _run_local(files, outputs, simplify_options, skip_existing, measure, samples,
                       jobs, rows, table)  # fmt: skip
        else:
            _run_dask(client, files, outputs, simplify_options, skip_existing, measure,
                      samples, tasks_per_worker, rows, table)  # fmt: skip
    finally:
        table.close()
    ordered = [rows[i] for i in range(len(files))]
    elapsed = time.perf_counter() - start
    print(summary(ordered, elapsed), file=sys.stderr)
    return ordered


def _check_options(options: Dict[str, Any]) -> None:
    """The library's checks of the options, on a one-triangle mesh, before any file is read:
    a bad option is one ValueError now, not one error row per file."""
    import gng3d

    tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            gng3d.simplify(tri, [[0, 1, 2]], **options)
    except ValueError as e:
        message = str(e)
        # What depends on a mesh (the target against its vertices) is each file's business.
        if not message.startswith(("target of", "input:")):
            raise
    except RuntimeError:
        pass


def largest_first(files: Sequence[Path]) -> List[int]:
    """The order files are started in: largest first (by bytes on disk, a stand-in for the
    work), so that the big files do not start last and leave one worker running alone at the
    end (longest-processing-time-first scheduling); rows still come back in the input order.
    Files that cannot be read sort last."""

    def size(i: int) -> int:
        try:
            return os.path.getsize(files[i])
        except OSError:
            return -1

    return sorted(range(len(files)), key=lambda i: (-size(i), i))


def _run_local(files, outputs, options, skip_existing, measure, samples, jobs, rows, table):
    jobs = jobs or os.cpu_count() or 1
    # Spawned workers: the parent's library threads are not forked into a child.
    with ProcessPoolExecutor(max_workers=jobs, mp_context=get_context("spawn")) as pool:
        futures = {
            pool.submit(simplify_file, files[i], outputs[i], options, skip_existing, measure,
                        samples): i
            for i in largest_first(files)
        }  # fmt: skip
        for future in as_completed(futures):
            i = futures[future]
            try:
                row = future.result()
            except Exception as e:  # the worker process died (memory, a signal)
                row = _row(files[i], outputs[i], options["method"])
                row.update(status="error", error=f"{type(e).__name__}: {e}")
            rows[i] = table.add(row)


def _run_dask(client, files, outputs, options, skip_existing, measure, samples,
              tasks_per_worker, rows, table):  # fmt: skip
    from distributed import as_completed as dask_completed

    workers = max(1, len(client.scheduler_info().get("workers", {})))
    n_tasks = max(1, min(len(files), tasks_per_worker * workers))
    size = math.ceil(len(files) / n_tasks) if files else 1
    order = largest_first(files)
    chunks = [order[s : s + size] for s in range(0, len(files), size)]
    futures = {}
    for chunk in chunks:
        jobs = [(str(files[i]), str(outputs[i])) for i in chunk]
        future = client.submit(_simplify_chunk, jobs, options, skip_existing, measure, samples,
                               pure=False, retries=0)  # fmt: skip
        futures[future] = chunk
    for future in dask_completed(list(futures)):
        chunk = futures[future]
        try:
            chunk_rows = future.result()
        except Exception as e:  # the task itself failed (a worker lost, KilledWorker)
            chunk_rows = []
            for i in chunk:
                row = _row(files[i], outputs[i], options["method"])
                row.update(status="error", error=f"{type(e).__name__}: {e}")
                chunk_rows.append(row)
        for i, row in zip(chunk, chunk_rows):
            rows[i] = table.add(row)


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m gng3d.batch``: one JSON line per file on stdout, the summary on stderr;
    exit status 1 when a file failed."""
    parser = argparse.ArgumentParser(
        prog="python -m gng3d.batch",
        description="Simplify a folder or a manifest of mesh files (static sharding).",
    )
    parser.add_argument("source", help="a folder of .obj/.ply/.stl files or a manifest")
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--method", default=_gng3d.DEFAULT_METHOD, choices=["qem", "gng", "paper"])
    target = parser.add_mutually_exclusive_group(required=True)
    target.add_argument("--vertices", type=int, dest="vertices_target")
    target.add_argument("--faces", type=int, dest="faces_target")
    target.add_argument("--ratio", type=float, help="share of each input's vertices kept")
    parser.add_argument(
        "--seed", type=int, default=None,
        help="GNG3D's seed (default: gng3d.DEFAULT_SEED, the CLI's default)",
    )  # fmt: skip
    parser.add_argument("--jobs", type=int, default=None, help="processes (default: cores)")
    parser.add_argument("--rank", type=int, default=0)
    parser.add_argument("--world-size", type=int, default=1)
    parser.add_argument("--skip-existing", action="store_true")
    parser.add_argument("--measure", action="store_true")
    args = parser.parse_args(argv)
    files = shard(list_inputs(args.source), args.rank, args.world_size)
    stats = f"stats-{args.rank}-of-{args.world_size}.csv" if args.world_size > 1 else "stats.csv"
    try:
        rows = simplify_files(
            files,
            args.out,
            method=args.method,
            vertices_target=args.vertices_target,
            faces_target=args.faces_target,
            ratio=args.ratio,
            seed=args.seed,
            jobs=args.jobs,
            skip_existing=args.skip_existing,
            measure=args.measure,
            stats=stats,
        )
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for row in rows:
        print(json.dumps(row))
    return 1 if any(r["status"] == "error" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
