"""load/save round trips, metrics, the Trainer, and the GIL released during the work."""

import os
import threading
import time

import numpy as np
import pytest

import gng3d
from conftest import torus


@pytest.mark.parametrize("ext", ["ply", "obj", "stl"])
def test_save_load_round_trip(tmp_path, small_torus, ext):
    v, f = small_torus
    path = tmp_path / f"torus.{ext}"
    gng3d.save(path, v, f)
    v2, f2 = gng3d.load(str(path))
    assert v2.dtype == np.float64 and f2.dtype == np.int64
    if ext == "stl":  # STL stores three corners per face: compare the triangles' corners
        np.testing.assert_array_equal(v2[f2], v.astype(np.float32)[f].astype(np.float64))
    else:
        np.testing.assert_array_equal(v2, v.astype(np.float32).astype(np.float64))
        np.testing.assert_array_equal(f2, f)
    assert [p.name for p in tmp_path.iterdir()] == [path.name]  # no temporary left


def test_save_is_atomic_and_checked(tmp_path, small_torus):
    v, f = small_torus
    path = tmp_path / "mesh.ply"
    gng3d.save(path, v, f)
    before = path.read_bytes()
    bad = v.copy()
    bad[5, 1] = np.nan
    with pytest.raises(ValueError, match=r"mesh\.ply: vertex 5 has a non-finite coordinate$"):
        gng3d.save(path, bad, f)
    assert path.read_bytes() == before  # the old file is untouched
    with pytest.raises(ValueError, match=r"unknown mesh format"):
        gng3d.save(tmp_path / "mesh.xyz", v, f)
    with pytest.raises(OSError):
        gng3d.save(tmp_path / "missing" / "mesh.ply", v, f)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mesh.ply"]


def test_load_errors(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"nothing\.ply: cannot read file"):
        gng3d.load(tmp_path / "nothing.ply")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")
    with pytest.raises(ValueError, match=r"bad\.obj: line 3: face refers to vertex 7"):
        gng3d.load(bad)
    with pytest.raises(ValueError, match=r"unknown mesh format"):
        gng3d.load(tmp_path / "mesh.txt")


def test_metrics_fields_and_values(small_torus):
    v, f = small_torus
    same = gng3d.metrics(v, f, v, f, samples=5000)
    for key in ["hausdorff", "e_avg", "e_max", "e_sur_signed", "normal_deviation", "quality",
                "topology", "meshes", "bbox_diagonal", "seconds"]:  # fmt: skip
        assert key in same
    assert same["hausdorff"]["max"] < 1e-6  # float rounding only
    v2, f2 = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=1)
    m = gng3d.metrics(v, f, v2, f2, samples=20000)
    assert 0.0 < m["hausdorff"]["mean"] < m["hausdorff"]["max"] < 0.1
    assert m["topology"]["simplified"]["genus"] == 1
    meshlab = gng3d.metrics(v, f, v2, f2, samples=2000, meshlab=True)
    assert meshlab["hausdorff"]["forward"]["vertex_samples"] == len(v)


def test_metrics_image_error(small_torus):
    v, f = small_torus
    # Identical meshes render identically: no error, an infinite PSNR (None, as JSON's null).
    same = gng3d.metrics(v, f, v, f, samples=2000, image_error=True, image_size=64)
    e = same["image_error"]
    assert e["size"] == 64 and len(e["views"]) == 14 and e["shading"] == "white"
    assert e["overall"]["rmse"] == 0.0 and e["overall"]["over_threshold"] == 0.0
    assert e["overall"]["coverage_mismatch"] == 0.0 and e["overall"]["psnr_db"] is None
    assert e["overall"]["pixels"] > 0
    assert "images" not in same
    # A copy moved by a fifth of the torus's tube radius: its silhouette and shading move.
    moved = gng3d.metrics(v, f, v + [0.06, 0.0, 0.0], f, samples=2000, image_error=True,
                          image_size=64, images=True)  # fmt: skip
    o = moved["image_error"]["overall"]
    assert 0.0 < o["rmse"] < 1.0 and o["psnr_db"] > 0.0
    assert 0.0 < o["over_threshold"] <= 1.0 and 0.0 < o["coverage_mismatch"] <= 1.0
    assert o["mean_abs"] <= o["rmse"]
    # A heavy simplification (24 of 1152 vertices) is off by more than a light one.
    def rmse(target):
        v2, f2 = gng3d.simplify(v, f, vertices_target=target, method="qem")
        m = gng3d.metrics(v, f, v2, f2, samples=2000, image_error=True, image_size=64)
        return m["image_error"]["overall"]["rmse"]

    assert rmse(24) > rmse(600) > 0.0
    # The renderings as arrays, consistent with the figures: the masks differ where the
    # silhouettes do, and the colours are RGB in 0-1 with black outside the mesh.
    views = moved["images"]
    assert [x["view"] for x in views] == [x["view"] for x in moved["image_error"]["views"]]
    first = views[0]
    assert first["original"].shape == (64, 64, 3) and first["original"].dtype == np.float32
    assert first["covered_original"].shape == (64, 64) and first["covered_original"].dtype == bool
    assert first["simplified"].min() >= 0.0 and first["simplified"].max() <= 1.0
    assert not first["original"][~first["covered_original"]].any()
    mismatch = sum(int((x["covered_original"] != x["covered_simplified"]).sum()) for x in views)
    covered = sum(int((x["covered_original"] | x["covered_simplified"]).sum()) for x in views)
    assert covered == o["pixels"]
    assert mismatch / covered == pytest.approx(o["coverage_mismatch"])


def test_metrics_image_error_options_are_checked(small_torus):
    v, f = small_torus
    for size in [8, 5000]:
        with pytest.raises(ValueError, match=r"^image_size: .* is not in 16 to 4096 pixels"):
            gng3d.metrics(v, f, v, f, image_error=True, image_size=size)
    with pytest.raises(ValueError, match=r"^image_threshold: 1\.5 is not a colour difference"):
        gng3d.metrics(v, f, v, f, image_error=True, image_threshold=1.5)
    with pytest.raises(ValueError, match=r"^image_size applies with image_error=True only"):
        gng3d.metrics(v, f, v, f, image_size=64)
    with pytest.raises(ValueError, match=r"^images applies with image_error=True only"):
        gng3d.metrics(v, f, v, f, images=True)


def test_trainer_steps_snapshots_and_mesh(small_torus):
    v, f = small_torus
    t = gng3d.Trainer(v, f, vertices_target=300, seed=4)
    assert not t.finished and "Trainer(method=\"gng\"" in repr(t)
    p = t.step(2000)
    assert p["signals"] >= 2000 and p["nodes"] >= 2 and p["target"] >= 300
    positions, edges = t.snapshot()
    assert positions.shape == (p["nodes"], 3) and edges.shape[1] == 2
    assert edges.max() < len(positions)
    errors = t.errors()
    assert errors["e_max"] >= errors["e_avg"] > 0.0
    preview = t.mesh()  # a preview while training
    assert preview.faces.shape[1] == 3
    seen = []
    final = t.train(callback=seen.append, every=5000)
    assert final["finished"] and t.finished and seen and seen[-1]["finished"]
    result = t.mesh()
    # Step by step gives what one call gives for the same options and seed.
    direct = gng3d.simplify(v, f, method="gng", vertices_target=300, seed=4)
    np.testing.assert_array_equal(result.vertices, direct.vertices)
    np.testing.assert_array_equal(result.faces, direct.faces)
    assert len(result.vertices) == 300


def test_trainer_callback_can_stop_training(small_torus):
    v, f = small_torus
    t = gng3d.Trainer(v, f, vertices_target=300, method="paper")
    calls = []

    def stop_at_second(progress):
        calls.append(progress)
        return len(calls) < 2

    t.train(callback=stop_at_second, every=1000)
    assert len(calls) == 2 and not calls[-1]["finished"]
    with pytest.raises(ValueError, match=r"^Trainer runs GNG3D"):
        gng3d.Trainer(v, f, vertices_target=300, method="qem")


def test_gil_is_released_while_simplifying():
    """Python code runs in another thread while a simplification works."""
    v, f = torus(400, 200)
    ticks = 0
    done = threading.Event()

    def work():
        gng3d.simplify(v, f, ratio=0.05, method="qem")
        done.set()

    thread = threading.Thread(target=work)
    start = time.perf_counter()
    thread.start()
    while not done.is_set():
        ticks += 1
    thread.join()
    elapsed = time.perf_counter() - start
    # With the GIL held the loop would run only at the switch before and after the call.
    assert elapsed > 0.05 and ticks > 10_000


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two cores")
def test_simplify_releases_the_gil():
    """While one thread is inside simplify, another runs Python code: it could not if the call
    held the GIL. Independent of the machine's load (no timing bound): the main thread records
    when it ran, the worker when its call started and ended, and some of the main thread's
    steps must fall well inside the call."""
    mesh = torus(600, 300)
    window = {}

    def work():
        window["start"] = time.perf_counter()
        gng3d.simplify(mesh[0], mesh[1], ratio=0.05, method="qem")
        window["end"] = time.perf_counter()

    worker = threading.Thread(target=work)
    ran = []
    worker.start()
    while worker.is_alive():
        ran.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    start, end = window["start"], window["end"]
    margin = 0.1 * (end - start)
    inside = [t for t in ran if start + margin < t < end - margin]
    assert inside, f"the main thread never ran during the {end - start:.3f} s call"


def test_two_threads_run_in_parallel():
    """Two simplifications in two threads take clearly less wall time than one after another
    (QEM below 500,000 faces runs on one thread, so two runs can use two cores)."""
    # A wall-time ratio needs two free cores: the 1-minute load average lags (after a build it
    # stays high for a while although the cores are free), so this measures only on a machine
    # that has been quiet (test_simplify_releases_the_gil checks the GIL under any load).
    if os.getloadavg()[0] > 0.75 * (os.cpu_count() or 1):
        pytest.skip("the machine is busy with other work: no two cores are free to measure with")
    meshes = [torus(600, 300), torus(599, 301)]

    def run(mesh):
        gng3d.simplify(mesh[0], mesh[1], ratio=0.05, method="qem")

    run(meshes[0])  # warm-up
    best = None
    for _ in range(5):
        start = time.perf_counter()
        for m in meshes:
            run(m)
        serial = time.perf_counter() - start
        threads = [threading.Thread(target=run, args=(m,)) for m in meshes]
        start = time.perf_counter()
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        parallel = time.perf_counter() - start
        ratio = parallel / serial
        best = ratio if best is None else min(best, ratio)
        if best < 0.8:
            break
    # Ideal 0.5 on two idle cores; 0.8 leaves room for a loaded machine.
    assert best < 0.8, f"parallel/serial wall time {best:.2f}"
