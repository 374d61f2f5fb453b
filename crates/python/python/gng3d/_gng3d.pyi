"""Type stubs of the native module gng3d._gng3d (re-exported by the gng3d package)."""

import os
from typing import Any, Callable, Iterator, Literal, Optional, Tuple, TypedDict, Union, final

from typing_extensions import Unpack

import numpy as np
import numpy.typing as npt

__all__ = [
    "Gng3dWarning",
    "SimplifyResult",
    "Trainer",
    "load",
    "metrics",
    "save",
    "simplify",
    "simplify_file",
]

_ArrayLike = npt.ArrayLike
_Vertices = npt.NDArray[np.float64]
_Faces = npt.NDArray[np.int64]
_PathLike = Union[str, "os.PathLike[str]"]
_Method = Literal["gng", "paper", "qem"]

class Gng3dWarning(UserWarning):
    """What kept a result from being exactly what was asked for."""

@final
class SimplifyResult:
    """The result of :func:`simplify`; unpacks as ``(vertices, faces)``."""

    @property
    def vertices(self) -> _Vertices: ...
    @property
    def faces(self) -> _Faces: ...
    @property
    def report(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...
    def __getitem__(self, index: int, /) -> Union[_Vertices, _Faces]: ...
    def __iter__(self) -> Iterator[Union[_Vertices, _Faces]]: ...

DEFAULT_SEED: int
"""GNG3D's seed when a call gives none: the job's default, every front end's."""
DEFAULT_METHOD: str
"""The method when a call names none ("qem"), every front end's."""
KEYWORDS: list[str]
"""The keywords of :func:`simplify` and :func:`simplify_file`, in the order of these stubs."""
MAX_THREADS: int
"""The most ``threads=`` a call may ask for (a larger count is a ValueError)."""

class Options(TypedDict, total=False):
    """The keywords of :func:`simplify` and :func:`simplify_file` (``gng3d.KEYWORDS``, the
    binding's one table, in its order; the defaults are the job's, every front end's)."""

    vertices_target: Optional[int]
    faces_target: Optional[int]
    ratio: Optional[float]
    method: _Method
    time_limit: Optional[float]
    seed: Optional[int]
    weld: bool
    attributes: Literal["keep", "drop"]
    placement: Optional[Literal["node", "project", "quadric"]]
    flips: Optional[bool]
    refit: Optional[bool]
    relax: Optional[bool]
    deviation_repair: Optional[bool]
    epochs: Optional[float]
    signals: Optional[Literal["vertices", "surface", "curvature"]]
    oversample: Optional[float]
    detail_rounds: Optional[int]
    shape: Optional[Literal["off", "fit", "round"]]
    creases: Optional[bool]
    threshold: Optional[float]
    lock_border: bool
    max_error: Optional[float]
    threads: Optional[int]

def simplify(
    vertices: _ArrayLike,
    faces: _ArrayLike,
    **options: Unpack[Options],
) -> SimplifyResult:
    """Simplify a mesh; ``ratio`` is a share of the input's vertices for every method."""

def simplify_file(
    input: _PathLike,
    output: _PathLike,
    **options: Unpack[Options],
) -> SimplifyResult:
    """Simplify ``input`` into ``output`` (written atomically), keeping normals, texture
    coordinates, colours and materials where the output format stores them.

    The options are :func:`simplify`'s. ``report`` also holds ``input``, ``output``,
    ``file_vertices``, ``file_faces`` and ``attributes`` (``input``, ``kept``, ``dropped``,
    as ``gng3d simplify --json``); what is dropped is also a :class:`Gng3dWarning`.
    """

def metrics(
    v0: _ArrayLike,
    f0: _ArrayLike,
    v1: _ArrayLike,
    f1: _ArrayLike,
    *,
    samples: Optional[int] = None,
    meshlab: bool = False,
    seed: int = 1,
    image_error: bool = False,
    image_size: Optional[int] = None,
    image_threshold: Optional[float] = None,
    image_flat: bool = False,
    images: bool = False,
) -> dict[str, Any]:
    """The fields of ``gng3d metrics --json`` for an original and a simplified mesh.

    With ``image_error=True`` also ``image_error`` (``gng3d metrics --image-error``'s figures);
    with ``images=True`` also ``images``, one dict of numpy arrays per view.
    """

def load(path: _PathLike) -> Tuple[_Vertices, _Faces]:
    """Read an OBJ, PLY or STL file as ``(vertices, faces)``.

    Warns (:class:`Gng3dWarning`) when the file holds normals, texture coordinates, colours or
    materials, which are not returned (:func:`simplify_file` keeps them).
    """

def save(path: _PathLike, vertices: _ArrayLike, faces: _ArrayLike) -> None:
    """Write an OBJ, PLY or STL file atomically."""

def allow_outside_references(allowed: bool) -> None:
    """Let models read the files they name outside their own folder (process-wide; trusted
    models only)."""

# The partitioned simplification's steps (`gng3d.distributed`, issue 50).

@final
class PartitionLock:
    """The lock of a work folder for one run, from :func:`partition_lock`."""
    def release(self) -> None:
        """Release the lock (again: nothing)."""

def partition_lock(work_dir: _PathLike) -> PartitionLock:
    """Lock ``work_dir`` (created if missing) for this run; ``OSError`` naming the folder when
    another run holds it. A killed run's lock is released by the system."""

def partition_plan(
    input: _PathLike, output: _PathLike, work_dir: _PathLike, memory_budget: int, **options: Unpack[Options]
) -> dict[str, Any]:
    """Check the request for a partitioned run (QEM, positions only), resolve the target, cut
    ``input`` (PLY, OBJ or STL) into cells of ``memory_budget`` bytes in ``work_dir`` (or reuse an
    earlier cut): ``cells``, ``ratio``, ``target``, ``input_vertices``, ``input_faces``,
    ``shared_vertices``, ``warnings``, ``seconds``."""

def partition_cell(work_dir: _PathLike, cell: int, ratio: float) -> dict[str, Any]:
    """Simplify one cell from the work folder's files (skipped when finished earlier):
    ``cell``, ``resumed``, ``input_faces``, ``locked``, ``faces``, ``seconds``."""

def partition_finish(work_dir: _PathLike, output: _PathLike, target: str) -> dict[str, Any]:
    """Stitch the finished cells, simplify to the plan's ``target``, write ``output``:
    ``vertices``, ``faces``, ``stitched_faces``, ``seconds``."""

def parse_size(text: str) -> int:
    """A size such as ``"2GB"`` or ``"512MiB"`` in bytes, as the CLI's ``--memory-budget``."""

def partition_work_dir(output: _PathLike) -> _PathLike:
    """The default work folder of a partitioned run writing ``output``."""

@final
class Trainer:
    """GNG3D step by step."""

    def __new__(
        cls,
        vertices: _ArrayLike,
        faces: _ArrayLike,
        *,
        vertices_target: Optional[int] = None,
        ratio: Optional[float] = None,
        method: Literal["gng", "paper"] = "gng",
        time_limit: Optional[float] = None,
        seed: Optional[int] = None,
        weld: bool = True,
        placement: Optional[Literal["node", "project", "quadric"]] = None,
        flips: Optional[bool] = None,
        refit: Optional[bool] = None,
        relax: Optional[bool] = None,
        deviation_repair: Optional[bool] = None,
        epochs: Optional[float] = None,
        signals: Optional[Literal["vertices", "surface", "curvature"]] = None,
        oversample: Optional[float] = None,
        detail_rounds: Optional[int] = None,
        shape: Optional[Literal["off", "fit", "round"]] = None,
        creases: Optional[bool] = None,
        threads: Optional[int] = None,
    ) -> "Trainer": ...
    def step(self, signals: int = 10000) -> dict[str, Any]: ...
    def train(
        self,
        callback: Optional[Callable[[dict[str, Any]], Optional[bool]]] = None,
        every: Optional[int] = None,
    ) -> dict[str, Any]: ...
    @property
    def progress(self) -> dict[str, Any]: ...
    @property
    def finished(self) -> bool: ...
    def snapshot(self) -> Tuple[_Vertices, npt.NDArray[np.int64]]: ...
    def errors(self) -> dict[str, float]: ...
    def stop(self) -> None: ...
    def mesh(self) -> SimplifyResult: ...
