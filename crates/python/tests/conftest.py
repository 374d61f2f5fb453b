"""Shared fixtures: procedural meshes (no files needed) and the shared meshes when present."""

import os
import pathlib
import shutil

import numpy as np
import pytest


def torus(rings: int = 48, segments: int = 24, r_major: float = 1.0, r_minor: float = 0.3):
    """A closed genus-1 grid torus: rings x segments vertices, 2 x rings x segments faces."""
    u = np.linspace(0.0, 2.0 * np.pi, rings, endpoint=False)
    w = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    uu, ww = np.meshgrid(u, w, indexing="ij")
    x = (r_major + r_minor * np.cos(ww)) * np.cos(uu)
    y = (r_major + r_minor * np.cos(ww)) * np.sin(uu)
    z = r_minor * np.sin(ww)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(rings), np.arange(segments), indexing="ij")
    a = i * segments + j
    b = ((i + 1) % rings) * segments + j
    c = ((i + 1) % rings) * segments + (j + 1) % segments
    d = i * segments + (j + 1) % segments
    faces = np.concatenate(
        [np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    return vertices, faces.astype(np.int64)


@pytest.fixture
def small_torus():
    return torus(48, 24)


def shared_meshes() -> pathlib.Path:
    """The shared meshes folder (GNG3D_MESHES, or ../shared/meshes beside the clone)."""
    env = os.environ.get("GNG3D_MESHES")
    if env:
        return pathlib.Path(env)
    return pathlib.Path(__file__).resolve().parents[3].parent / "shared" / "meshes"


def cli_binary():
    """The gng3d CLI to compare with: GNG3D_CLI, else a built one in the repository's target."""
    env = os.environ.get("GNG3D_CLI")
    if env:
        return env
    root = pathlib.Path(__file__).resolve().parents[3]
    for candidate in [
        root / "target" / "release" / "gng3d",
        root / "target" / "debug" / "gng3d",
    ]:
        if candidate.exists():
            return str(candidate)
    return shutil.which("gng3d")
