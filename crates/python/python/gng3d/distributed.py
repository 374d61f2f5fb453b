"""One mesh larger than a machine: the partitioned simplification with its cells on a Dask
cluster (issue 50).

The steps are those of ``gng3d simplify BIG OUT --partition auto`` (the ``partition`` crate,
through ``gng3d._gng3d``), the cells run apart:

1. **Plan** (here): the request checked as the CLI checks it, the target resolved, the input
   (PLY, OBJ or STL) cut in a streaming pass into cells of ``memory_per_worker`` bytes in the work
   folder -- or an earlier cut of the same input reused.
2. **Cells** (on the workers, one task each, ``retries=2`` so a lost worker's cell is run
   again): each worker reads its cell's chunk files from the work folder and writes the cell's
   output there atomically. A cell finished by an earlier run is not redone: rerunning with the
   same ``work_dir`` resumes a killed run.
3. **Finish** (here): the cells stitched and simplified to the exact target, written to
   ``out``.

The work folder is locked from the plan to the finish: a second run on it is refused with an
``OSError`` naming it (a killed run's lock is released by the system).

QEM on positions only for now: an input's normals, texture coordinates, colours and materials
are dropped, with a :class:`gng3d.Gng3dWarning` naming them (``attributes="drop"`` to say so).
The output is the CLI's for the same target and budget, byte for byte.

Workers on other hosts need gng3d installed and the work folder visible under the same name
(a shared file system).

Example::

    from dask.distributed import Client
    from gng3d import distributed
    client = Client("tcp://scheduler:8786")
    report = distributed.simplify("/shared/city.ply", "/shared/city-1m.ply",
                                  faces=1_000_000, client=client, memory_per_worker="4GB",
                                  work_dir="/shared/city-work")
"""

from __future__ import annotations

import os
import shutil
import time
import warnings
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path
from typing import Any, Callable, Dict, Optional, Union

from . import _gng3d

PathLike = Union[str, "os.PathLike[str]"]


def _cell(work_dir: str, cell: int, ratio: float) -> Dict[str, Any]:
    """One cell, on a worker (the GIL released while it runs)."""
    return _gng3d.partition_cell(work_dir, cell, ratio)


def simplify(
    path: PathLike,
    out: PathLike,
    ratio: Optional[float] = None,
    vertices: Optional[int] = None,
    faces: Optional[int] = None,
    client: Any = None,
    memory_per_worker: Union[str, int] = "2GB",
    work_dir: Optional[PathLike] = None,
    progress: Optional[Callable[[int, int], None]] = None,
    keep_work: bool = False,
    **options: Any,
) -> Dict[str, Any]:
    """Simplify the mesh file ``path`` into ``out`` without holding it (see the module).

    Args:
        path: the input, PLY, OBJ or STL.
        out: the output (.obj, .ply, .stl, .gltf, .glb), written atomically.
        ratio, vertices, faces: the target, one of them: a share of the input's vertex
            records (rounded to a count of them), a vertex count or a face count, as the CLI's
            ``--ratio``, ``--vertices`` and ``--faces`` with ``--partition auto``.
        client: a ``dask.distributed.Client``: one task per cell on its workers, each retried
            twice. ``None``: the cells run in this process on a pool of threads (each releases
            the GIL).
        memory_per_worker: bytes one cell may take, or a size such as ``"2GB"`` (as the CLI's
            ``--memory-budget``).
        work_dir: the folder of the chunk files, visible to every worker; default: ``out``'s
            name with ``.gng3d-work``, beside it (as the CLI's). Rerunning with the same folder
            resumes from the finished cells.
        progress: called with (cells done, cells in all) as cells complete.
        keep_work: keep the work folder after success (otherwise removed when it was made
            by this run or an earlier one).
        **options: ``attributes``, ``threads`` (the final pass's), as for
            :func:`gng3d.simplify_file`; QEM's other options are refused, as the CLI refuses
            them.

    Returns:
        dict: ``vertices``, ``faces``, ``input_vertices``, ``input_faces``, ``cells``,
        ``cells_resumed``, ``shared_vertices``, ``stitched_faces``, ``step_seconds``
        (``partition``, ``cells``, ``finish``), ``seconds``, ``work_dir``, ``warnings``.

    Raises:
        ValueError: bad options or a malformed input; OSError: a file that cannot be read or
        written. A cell that fails on every try raises its worker's error.
    """
    start = time.perf_counter()
    targets = {"ratio": ratio, "vertices_target": vertices, "faces_target": faces}
    options.update({k: v for k, v in targets.items() if v is not None})
    budget = (
        _gng3d.parse_size(memory_per_worker)
        if isinstance(memory_per_worker, str)
        else int(memory_per_worker)
    )
    work = Path(work_dir) if work_dir is not None else Path(_gng3d.partition_work_dir(str(out)))
    # Removed at the end only when it is the partition's: new, or an earlier run's.
    removable = not work.exists() or (work / "manifest").is_file()
    # One run per work folder: another run on it is refused (OSError naming it); the lock of a
    # killed run is released by the system, so a rerun resumes.
    existed = work.exists()
    lock = _gng3d.partition_lock(str(work))
    try:
        plan = _gng3d.partition_plan(str(path), str(out), str(work), budget, **options)
        for message in plan["warnings"]:
            warnings.warn(f"{path}: {message}", _gng3d.Gng3dWarning, stacklevel=2)
        cells, cell_ratio = plan["cells"], plan["ratio"]
        total = len(cells)
        cells_start = time.perf_counter()
        done = []
        if client is None:
            workers = max(1, min(total, os.cpu_count() or 1))
            with ThreadPoolExecutor(max_workers=workers) as pool:
                futures = [pool.submit(_cell, str(work), k, cell_ratio) for k in cells]
                for future in as_completed(futures):
                    done.append(future.result())
                    if progress is not None:
                        progress(len(done), total)
        else:
            from dask.distributed import as_completed as dask_completed

            futures = [
                client.submit(_cell, str(work), k, cell_ratio, pure=False, retries=2) for k in cells
            ]
            for future in dask_completed(futures):
                done.append(future.result())
                if progress is not None:
                    progress(len(done), total)
        cells_seconds = time.perf_counter() - cells_start
        finished = _gng3d.partition_finish(str(work), str(out), plan["target"])
    except BaseException:
        lock.release()
        # A refused request leaves no folder behind (a failed run's chunks stay, to resume).
        if not existed and [p.name for p in work.iterdir()] == ["lock"]:
            shutil.rmtree(work, ignore_errors=True)
        raise
    finally:
        lock.release()
    if not keep_work and removable:
        shutil.rmtree(work, ignore_errors=True)
    return {
        "method": "qem",
        "partition": "auto",
        "input_vertices": plan["input_vertices"],
        "input_faces": plan["input_faces"],
        "vertices": finished["vertices"],
        "faces": finished["faces"],
        "seconds": time.perf_counter() - start,
        "cells": total,
        "cells_resumed": sum(1 for d in done if d["resumed"]),
        "shared_vertices": plan["shared_vertices"],
        "stitched_faces": finished["stitched_faces"],
        "step_seconds": {
            "partition": plan["seconds"],
            "cells": cells_seconds,
            "finish": finished["seconds"],
        },
        "work_dir": str(work),
        "warnings": list(plan["warnings"]),
    }
