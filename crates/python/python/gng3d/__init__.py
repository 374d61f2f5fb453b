"""Triangle mesh simplification with GNG3D and QEM on numpy arrays.

- :func:`simplify` -- GNG3D-Q (default, exact vertex counts), the published GNG3D
  (``method="paper"``) or Garland-Heckbert QEM (``method="qem"``).
- :func:`simplify_file` -- a mesh file into another, keeping its normals, texture
  coordinates, colours and materials (as ``gng3d simplify IN OUT``).
- :func:`metrics` -- the paper's errors and the symmetric surface (Hausdorff) distance.
- :func:`load` / :func:`save` -- OBJ, PLY and STL files as positions and triangles (writes are
  atomic; ``load`` warns when a file holds attributes it does not return).
- :class:`Trainer` -- GNG3D step by step (live plots in notebooks).
- :mod:`gng3d.batch` -- many files at once, on a process pool or a Dask cluster.
- :mod:`gng3d.distributed` -- one mesh larger than memory, its cells on a Dask cluster.

The Rust libraries of the gng3d project do the work, with the same options, checks and
reports as the ``gng3d`` command-line tool, and release the GIL while they do.

Example::

    import gng3d
    v, f = gng3d.load("bunny.ply")
    v2, f2 = gng3d.simplify(v, f, ratio=0.1)     # keep a tenth of the vertices
    print(gng3d.metrics(v, f, v2, f2)["hausdorff"]["max"])
"""

from ._gng3d import (
    DEFAULT_METHOD,
    DEFAULT_SEED,
    KEYWORDS,
    MAX_THREADS,
    Gng3dWarning,
    SimplifyResult,
    Trainer,
    allow_outside_references,
    load,
    metrics,
    save,
    simplify,
    simplify_file,
)

__all__ = [
    "DEFAULT_METHOD",
    "DEFAULT_SEED",
    "KEYWORDS",
    "MAX_THREADS",
    "Gng3dWarning",
    "SimplifyResult",
    "Trainer",
    "allow_outside_references",
    "load",
    "metrics",
    "save",
    "simplify",
    "simplify_file",
]


def __getattr__(name: str):
    # `gng3d.batch` without importing it (and its optional Dask) on `import gng3d`.
    if name == "batch":
        import importlib

        return importlib.import_module(".batch", __name__)
    raise AttributeError(f"module 'gng3d' has no attribute {name!r}")
