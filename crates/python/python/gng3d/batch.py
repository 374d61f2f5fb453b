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

The engine is the one ``gng3d batch`` runs (``job::batch``, through ``gng3d._gng3d``): the
list of files, their output names and the checks before anything is written (no two files to
one output, no result over an input), the sharding, each file's run and its row (the schema
of ``STATS_FIELDS``), the stats table and resuming. This module only orchestrates: a process
pool or a Dask client, and the command line.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from multiprocessing import get_context
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Union

from . import _gng3d

STATS_FIELDS = list(_gng3d.BATCH_FIELDS)

PathLike = Union[str, "os.PathLike[str]"]


def list_inputs(source: Union[PathLike, Iterable[PathLike]]) -> List[Path]:
    """The mesh files of ``source``: a folder (its .obj, .ply, .stl, .gltf and .glb files, sorted), a
    manifest (a text file with one path per line; relative paths are relative to it), or an
    iterable of paths (kept in its order)."""
    if isinstance(source, (str, os.PathLike)):
        return [Path(p) for p in _gng3d.batch_list_inputs(source)]
    return [Path(p) for p in source]


def simplify_file(
    path: PathLike,
    out: PathLike,
    options: Dict[str, Any],
    skip_existing: bool = True,
    measure: bool = False,
    samples: Optional[int] = None,
) -> Dict[str, Any]:
    """Simplify one file into ``out`` as :func:`gng3d.simplify_file` does (keeping its
    normals, texture coordinates, colours and materials where the output format stores them;
    what it cannot keep is one of the row's ``warnings``), in this process with the GIL
    released; never raises for the file's own failure: it is the row's ``error``
    (``"ValueError: ..."``). ``input_vertices`` and ``input_faces`` count the mesh the run
    was given (welded and cleaned), as ``gng3d batch`` and ``gng3d simplify --json`` do."""
    return _gng3d.batch_run(path, out, skip_existing, measure, samples, **options)


def _simplify_chunk(jobs: List[tuple], options, skip_existing, measure, samples):
    return [simplify_file(p, o, options, skip_existing, measure, samples) for p, o in jobs]


def summary(rows: Sequence[Dict[str, Any]], seconds: Optional[float] = None) -> str:
    """One line: how many files were ok, skipped and failed (and the wall time)."""
    return _gng3d.batch_summary([r["status"] for r in rows], seconds)


def largest_first(files: Sequence[PathLike]) -> List[int]:
    """The order files are started in: largest first (by bytes on disk, a stand-in for the
    work), so that the big files do not start last and leave one worker running alone at the
    end (longest-processing-time-first scheduling); rows still come back in the input order.
    Files that cannot be read sort last."""
    return _gng3d.batch_largest_first([str(f) for f in files])


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
    stats: Union[bool, str, None] = True,
    rank: int = 0,
    world_size: int = 1,
    tasks_per_worker: int = 10,
    **options: Any,
) -> List[Dict[str, Any]]:
    """Simplify every file of ``paths`` into ``out_dir``; returns one status row per file.

    Args:
        paths: a folder, a manifest file (one path per line) or an iterable of paths.
        out_dir: the output folder (created); each result keeps its input's name (``suffix``,
            e.g. ``".ply"``, changes the format). Refused before any file is read: two files
            to one output file, a result over an input.
        method, vertices_target, faces_target, ratio, seed, **options: as for
            :func:`gng3d.simplify` (checked once before any file is read); ``threads``
            defaults to the cores shared out among the processes (1 on Dask).
        client: a ``dask.distributed.Client``: the files run as tasks on its workers
            (about ``tasks_per_worker`` tasks per worker, no retries). ``None``: a local pool of
            ``jobs`` processes (default: the number of cores).
        skip_existing: files whose output exists are skipped (a killed run resumes).
        measure: also measure each result (``hausdorff_max``/``hausdorff_mean``, ``samples``
            per direction).
        stats: the CSV written in ``out_dir`` as files complete: True its default name
            (``stats.csv``, ``stats-R-of-W.csv`` when sharded), a name, or None/False: none.
        rank, world_size: this process's shard of the files (every ``world_size``-th from
            ``rank``); the checks cover every file.

    Returns:
        list of dict, in the order of ``paths``: ``input``, ``output``, ``status`` ("ok",
        "skipped" or "error"), ``error``, ``warnings``, ``method``, counts, ``seconds``, and
        the metrics when measured (the keys of ``STATS_FIELDS``).
    """
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
    _gng3d.batch_check(**simplify_options)
    if isinstance(paths, (str, os.PathLike)):
        source, files = paths, None
    else:
        source, files = None, [str(p) for p in paths]
    items, stats_name = _gng3d.batch_plan(source, files, out_dir, suffix, rank, world_size)
    table_name = stats_name if stats is True else (stats or None)
    start = time.perf_counter()
    table = _gng3d.BatchTable(Path(out_dir) / table_name if table_name else None)
    rows: Dict[int, Dict[str, Any]] = {}
    order = _gng3d.batch_largest_first([i for i, _ in items])
    run = (simplify_options, skip_existing, measure, samples)
    if client is None:
        _run_local(items, order, run, jobs, rows, table)
    else:
        _run_dask(client, items, order, run, tasks_per_worker, rows, table)
    ordered = [rows[i] for i in range(len(items))]
    elapsed = time.perf_counter() - start
    print(summary(ordered, elapsed), file=sys.stderr)
    return ordered


def _failed(item, options, e: BaseException) -> Dict[str, Any]:
    """The row of a file whose worker or task was lost."""
    return _gng3d.batch_failed_row(*item, options["method"], f"{type(e).__name__}: {e}")


def _run_local(items, order, run, jobs, rows, table):
    jobs = jobs or os.cpu_count() or 1
    # Spawned workers: the parent's library threads are not forked into a child.
    with ProcessPoolExecutor(max_workers=jobs, mp_context=get_context("spawn")) as pool:
        futures = {pool.submit(simplify_file, *items[i], *run): i for i in order}
        for future in as_completed(futures):
            i = futures[future]
            try:
                row = future.result()
            except Exception as e:  # the worker process died (memory, a signal)
                row = _failed(items[i], run[0], e)
            rows[i] = table.add(row)


def _run_dask(client, items, order, run, tasks_per_worker, rows, table):
    from distributed import as_completed as dask_completed

    workers = max(1, len(client.scheduler_info().get("workers", {})))
    n_tasks = max(1, min(len(items), tasks_per_worker * workers))
    size = -(-len(items) // n_tasks) if items else 1
    chunks = [order[s : s + size] for s in range(0, len(items), size)]
    futures = {}
    for chunk in chunks:
        jobs = [tuple(str(p) for p in items[i]) for i in chunk]
        futures[client.submit(_simplify_chunk, jobs, *run, pure=False, retries=0)] = chunk
    for future in dask_completed(list(futures)):
        chunk = futures[future]
        try:
            chunk_rows = future.result()
        except Exception as e:  # the task itself failed (a worker lost, KilledWorker)
            chunk_rows = [_failed(items[i], run[0], e) for i in chunk]
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
    try:
        rows = simplify_files(
            args.source,
            args.out,
            method=args.method,
            vertices_target=args.vertices_target,
            faces_target=args.faces_target,
            ratio=args.ratio,
            seed=args.seed,
            jobs=args.jobs,
            skip_existing=args.skip_existing,
            measure=args.measure,
            rank=args.rank,
            world_size=args.world_size,
        )
    except (ValueError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    for row in rows:
        print(json.dumps(row))
    return 1 if any(r["status"] == "error" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
