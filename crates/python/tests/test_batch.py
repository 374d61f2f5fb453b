"""gng3d.batch: a folder of files on a process pool or Dask; rows, not exceptions; resume."""

import csv
import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import gng3d
from gng3d import batch
from conftest import cli_binary, shared_meshes, torus


@pytest.fixture
def folder(tmp_path):
    """Four small tori and one broken file."""
    src = tmp_path / "in"
    src.mkdir()
    for i, (rings, segments) in enumerate([(40, 20), (44, 22), (48, 24), (52, 26)]):
        v, f = torus(rings, segments)
        gng3d.save(src / f"torus{i}.ply", v, f)
    (src / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    return src


def outputs(folder):
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.suffix == ".ply"}


def test_largest_files_start_first(folder):
    """Longest-processing-time-first: the start order is by size on disk, largest first (an
    independent sort of the sizes), and every file is started once."""
    files = batch.list_inputs(folder)
    order = batch.largest_first(files)
    assert sorted(order) == list(range(len(files)))
    sizes = [os.path.getsize(files[i]) for i in order]
    assert sizes == sorted(sizes, reverse=True)
    assert files[order[0]].name == "torus3.ply" and files[order[-1]].name == "broken.obj"


def test_local_pool_rows_outputs_and_stats(folder, tmp_path):
    out = tmp_path / "out"
    rows = batch.simplify_files(folder, out, ratio=0.2, jobs=2)
    by_name = {os.path.basename(r["input"]): r for r in rows}
    assert [r["status"] for r in rows] == ["error"] + ["ok"] * 4  # sorted: broken.obj first
    broken = by_name["broken.obj"]
    assert broken["error"].startswith("ValueError: ") and "face refers to vertex 9" in broken["error"]
    for i in range(4):
        row = by_name[f"torus{i}.ply"]
        assert row["vertices"] == round(0.2 * row["input_vertices"]) and row["seconds"] > 0
    assert set(outputs(out)) == {f"torus{i}.ply" for i in range(4)}
    with open(out / "stats.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert sorted(r["status"] for r in table) == ["error", "ok", "ok", "ok", "ok"]
    assert batch.summary(rows) == "5 files: 4 ok, 0 skipped, 1 errors"


def test_same_files_as_a_serial_run_and_resume(folder, tmp_path):
    serial = tmp_path / "serial"
    for p in sorted(folder.glob("*.ply")):
        v, f = gng3d.load(p)
        gng3d.save(serial / p.name if serial.exists() else _mkdir(serial) / p.name,
                   *gng3d.simplify(v, f, ratio=0.2))  # fmt: skip
    out = tmp_path / "out"
    # A first run over part of the files (as if killed), then the whole folder.
    batch.simplify_files(sorted(folder.glob("*.ply"))[:2], out, ratio=0.2, jobs=2)
    rows = batch.simplify_files(folder, out, ratio=0.2, jobs=2)
    status = {os.path.basename(r["input"]): r["status"] for r in rows}
    assert status == {"broken.obj": "error", "torus0.ply": "skipped", "torus1.ply": "skipped",
                      "torus2.ply": "ok", "torus3.ply": "ok"}  # fmt: skip
    skipped = [r for r in rows if r["status"] == "skipped"]
    assert all(r["vertices"] and r["faces"] for r in skipped)  # counts of the earlier run
    assert outputs(out) == outputs(serial)


def _mkdir(path):
    path.mkdir()
    return path


def test_bad_options_are_one_error_before_any_file(folder, tmp_path):
    with pytest.raises(ValueError, match=r"^ratio must be in \(0, 1\], got 2"):
        batch.simplify_files(folder, tmp_path / "out", ratio=2.0)
    with pytest.raises(ValueError, match=r"^faces_target applies to method 'qem' only"):
        batch.simplify_files(folder, tmp_path / "out", faces_target=100, method="gng")


def test_command_line_shards_and_resumes_after_a_kill(folder, tmp_path):
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "gng3d.batch", str(folder), "--out", str(out), "--ratio",
           "0.2", "--jobs", "1", "--skip-existing"]  # fmt: skip
    # Shard 1 of 2: every second file from the second.
    proc = subprocess.run(cmd + ["--rank", "1", "--world-size", "2"], capture_output=True,
                          text=True)  # fmt: skip
    lines = [json.loads(line) for line in proc.stdout.splitlines()]
    assert [os.path.basename(r["input"]) for r in lines] == ["torus0.ply", "torus2.ply"]
    assert proc.returncode == 0 and "2 files: 2 ok" in proc.stderr
    # The whole folder, killed once the first new output appears, then run again.
    for p in out.glob("*.ply"):
        p.unlink()
    run = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.time() + 60
    while time.time() < deadline and not list(out.glob("*.ply")) and run.poll() is None:
        time.sleep(0.01)
    run.send_signal(signal.SIGKILL)
    run.wait()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    rows = [json.loads(line) for line in proc.stdout.splitlines()]
    assert proc.returncode == 1  # the broken file
    assert {r["status"] for r in rows if r["input"].endswith(".ply")} <= {"ok", "skipped"}
    assert set(outputs(out)) == {f"torus{i}.ply" for i in range(4)}
    for name, data in outputs(out).items():  # complete files: they load
        v, f = gng3d.load(out / name)
        assert len(f) > 0


def test_cli_and_python_batches_write_the_same_bytes(folder, tmp_path):
    """One engine: `gng3d batch DIR --method gng --ratio 0.1` and `python -m gng3d.batch` with
    the same arguments write byte-identical meshes, rows of the same schema and statuses."""
    cli = cli_binary()
    if not cli:
        pytest.skip("needs the gng3d CLI (GNG3D_CLI)")
    args = [str(folder), "--method", "gng", "--ratio", "0.1", "--jobs", "2"]
    rust = subprocess.run([cli, "batch", *args, "--out", str(tmp_path / "cli")],
                          capture_output=True, text=True)  # fmt: skip
    python = subprocess.run([sys.executable, "-m", "gng3d.batch", *args, "--out",
                             str(tmp_path / "py")], capture_output=True, text=True)  # fmt: skip
    assert rust.returncode == python.returncode == 1, (rust.stderr, python.stderr)  # broken.obj
    cli_out, py_out = outputs(tmp_path / "cli"), outputs(tmp_path / "py")
    assert set(cli_out) == {f"torus{i}.ply" for i in range(4)}
    assert cli_out == py_out
    rust_rows = sorted((json.loads(l) for l in rust.stdout.splitlines()), key=lambda r: r["input"])
    py_rows = sorted((json.loads(l) for l in python.stdout.splitlines()), key=lambda r: r["input"])
    assert [list(r) for r in rust_rows] == [list(r) for r in py_rows] == [batch.STATS_FIELDS] * 5
    for a, b in zip(rust_rows, py_rows):
        assert (a["status"], a["vertices"], a["faces"]) == (b["status"], b["vertices"], b["faces"])
    for name in ("cli", "py"):
        with open(tmp_path / name / "stats.csv", newline="") as f:
            assert next(csv.reader(f)) == batch.STATS_FIELDS


def test_dask_local_cluster_same_files_as_serial(tmp_path):
    distributed = pytest.importorskip("distributed")
    meshes = shared_meshes()
    names = ["spot.obj", "fandisk.obj", "cow.obj", "rocker-arm.obj"]
    if not all((meshes / n).exists() for n in names):
        pytest.skip("needs the shared meshes (GNG3D_MESHES)")
    src = tmp_path / "in"
    src.mkdir()
    for n in names:
        (src / n).symlink_to(meshes / n)
    (src / "broken.ply").write_bytes(b"ply\nformat ascii 1.0\nelement vertex 1\nend_header\n")
    serial = tmp_path / "serial"
    serial_rows = batch.simplify_files(src, serial, ratio=0.1, jobs=1, suffix=".ply")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:  # fmt: skip
        with distributed.Client(cluster) as client:
            rows = batch.simplify_files(src, tmp_path / "dask", ratio=0.1, client=client,
                                        suffix=".ply", measure=True, samples=20000)  # fmt: skip
    assert [r["status"] for r in rows] == [r["status"] for r in serial_rows]
    (bad,) = [r for r in rows if r["status"] == "error"]
    assert bad["input"].endswith("broken.ply") and bad["error"].startswith("ValueError: ")
    assert all(r["hausdorff_max"] > 0 for r in rows if r["status"] == "ok")
    assert outputs(tmp_path / "dask") == outputs(serial)


def test_rows_count_the_input_as_the_cli_batch(tmp_path, small_torus):
    """A file with unreferenced vertices: both batch fronts count the mesh the run was given
    (welded and cleaned), the count a ratio is a share of, in the one row schema."""
    cli = cli_binary()
    if not cli:
        pytest.skip("needs the gng3d CLI (GNG3D_CLI)")
    v, f = small_torus
    folder = tmp_path / "in"
    folder.mkdir()
    gng3d.save(folder / "t.ply", np.vstack([v, v[:50] + 10.0]), f)  # 50 unreferenced vertices
    py = batch.simplify_files(folder, tmp_path / "py", ratio=0.2, jobs=1)
    subprocess.run([cli, "batch", str(folder), "--out", str(tmp_path / "cli"), "--ratio", "0.2"],
                   check=True, capture_output=True)  # fmt: skip
    with open(tmp_path / "cli" / "stats.csv", newline="") as table:
        cli_rows = list(csv.DictReader(table))
    assert py[0]["input_vertices"] == int(cli_rows[0]["input_vertices"]) == len(v)
    assert py[0]["vertices"] == int(cli_rows[0]["vertices"]) == round(0.2 * len(v))
