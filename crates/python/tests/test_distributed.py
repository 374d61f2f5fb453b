"""gng3d.distributed (issue 50): the partitioned simplification with its cells on Dask workers
gives the exact count, a closed manifold output from a closed input, the CLI's bytes for the
same target and budget, and resumes from the finished cells."""

import subprocess
import warnings

import numpy as np
import pytest

import gng3d
from gng3d import distributed

from conftest import cli_binary, torus


def closed_manifold(faces):
    """Every edge in exactly two faces, each direction once (independent of the library)."""
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    pairs = set(map(tuple, directed.tolist()))
    return len(pairs) == len(directed) and all((b, a) in pairs for a, b in pairs)


@pytest.fixture
def big_torus(tmp_path):
    """A closed torus of 19,200 faces (9,600 vertices) as PLY."""
    v, f = torus(160, 60)
    path = tmp_path / "torus.ply"
    gng3d.save(path, v, f)
    return path


def test_dask_cells_exact_closed_same_as_cli_and_resume(big_torus, tmp_path):
    dask = pytest.importorskip("dask.distributed")
    out, work = tmp_path / "coarse.ply", tmp_path / "work"
    seen = []
    with dask.LocalCluster(n_workers=2, threads_per_worker=1, processes=False) as cluster:
        with dask.Client(cluster) as client:
            report = distributed.simplify(
                big_torus, out, faces=2000, client=client, memory_per_worker="256KiB",
                work_dir=work, keep_work=True, progress=lambda d, t: seen.append((d, t)),
            )  # fmt: skip
            assert report["cells"] > 4 and report["cells_resumed"] == 0
            assert seen[-1] == (report["cells"], report["cells"]) and len(seen) == report["cells"]
            v, f = gng3d.load(out)
            assert 1999 <= len(f) <= 2000 and report["faces"] == len(f)
            assert closed_manifold(f)
            first = out.read_bytes()

            # A killed run: two cells' outputs lost; the rerun redoes those two only.
            lost = sorted(work.glob("*.out"))[:2]
            for p in lost:
                p.unlink()
            again = distributed.simplify(
                big_torus, out, faces=2000, client=client, memory_per_worker="256KiB",
                work_dir=work,
            )  # fmt: skip
            assert again["cells_resumed"] == report["cells"] - 2
            assert out.read_bytes() == first
            assert not work.exists()

    # No client: the cells on local threads, the same bytes.
    local = tmp_path / "local.ply"
    distributed.simplify(big_torus, local, faces=2000, memory_per_worker="256KiB")
    assert local.read_bytes() == first

    cli = cli_binary()
    if not cli:
        print("SKIPPED: the CLI comparison needs the gng3d CLI (GNG3D_CLI)")
        return
    by_cli = tmp_path / "cli.ply"
    done = subprocess.run(
        [cli, "simplify", str(big_torus), str(by_cli), "--faces", "2000", "--partition", "auto",
         "--memory-budget", "256KiB"], capture_output=True, text=True,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert by_cli.read_bytes() == first


def test_distributed_refuses_what_the_cli_refuses(big_torus, tmp_path):
    out = tmp_path / "out.ply"
    with pytest.raises(ValueError, match="partition applies to QEM only|method 'qem' only"):
        distributed.simplify(big_torus, out, ratio=0.1, method="gng")
    with pytest.raises(ValueError, match="lock_border does not apply with partition"):
        distributed.simplify(big_torus, out, faces=100, lock_border=True)
    with pytest.raises(ValueError, match="memory_budget"):
        distributed.simplify(big_torus, out, faces=100, memory_per_worker="2 parsecs")
    # A share of the vertices rounds to a count of them, as the CLI's --ratio.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        report = distributed.simplify(big_torus, out, ratio=0.1, memory_per_worker="256KiB")
    assert report["vertices"] == 960


def test_a_second_run_on_a_work_folder_in_use_is_refused(big_torus, tmp_path):
    out, work = tmp_path / "out.ply", tmp_path / "work"
    # Another run (here: its lock, as a driver holds it from plan to finish) has the folder.
    held = gng3d._gng3d.partition_lock(str(work))
    with pytest.raises(OSError, match="in use by another run") as refused:
        distributed.simplify(big_torus, out, faces=2000, memory_per_worker="256KiB", work_dir=work)
    assert str(work) in str(refused.value)
    assert not out.exists()
    held.release()
    # Released (as the system releases a killed run's lock): the run goes through.
    report = distributed.simplify(
        big_torus, out, faces=2000, memory_per_worker="256KiB", work_dir=work
    )
    assert 1999 <= report["faces"] <= 2000
    # A refused request does not leave the folder its lock made.
    fresh = tmp_path / "fresh-work"
    with pytest.raises(ValueError):
        distributed.simplify(big_torus, out, faces=100, lock_border=True, work_dir=fresh)
    assert not fresh.exists()
