"""The faults of the hostile-input review (issue 46): a trainer read from another thread, a
huge or negative thread count, Ctrl-C in a long call, messages without the parameter's name,
and the default seed."""

import os
import pathlib
import signal
import subprocess
import sys
import textwrap
import threading
import time

import numpy as np
import pytest

import gng3d
from conftest import cli_binary, torus

HERE = pathlib.Path(__file__).resolve().parent


def test_trainer_reads_wait_while_another_thread_steps():
    """The pattern of Trainer's docstring: one thread trains, another reads the progress for a
    plot. The reads wait for the running step's chunk instead of failing with "busy", and the
    values they see only grow."""
    v, f = torus(96, 48)
    t = gng3d.Trainer(v, f, vertices_target=1500, epochs=5000, seed=1)
    failures = []
    stop = threading.Event()

    def train():
        try:
            while not stop.is_set() and not t.finished:
                t.step(20_000)
        except BaseException as e:  # noqa: BLE001 - reported below
            failures.append(e)

    worker = threading.Thread(target=train)
    worker.start()
    seen = []
    try:
        for _ in range(60):
            p = t.progress
            seen.append((p["signals"], p["nodes"]))
            assert isinstance(t.finished, bool)
            positions, edges = t.snapshot()
            assert positions.shape[1] == 3 and edges.shape[1] == 2
            errors = t.errors()
            assert errors["e_max"] >= errors["e_avg"] >= 0.0
            assert "Trainer(" in repr(t)
        still_training = worker.is_alive()
    finally:
        stop.set()
        worker.join()
    assert not failures, failures
    signals = [s for s, _ in seen]
    assert signals == sorted(signals), "the signal count went back"
    # The reads overlapped the training (otherwise this test would check nothing).
    assert still_training and len(set(signals)) > 5, signals


@pytest.mark.parametrize("threads", [0, -1, 10_000, 2**70])
def test_threads_out_of_range_is_a_value_error_naming_it(small_torus, tmp_path, threads):
    v, f = small_torus
    limit = gng3d.MAX_THREADS
    message = out_of_range("threads", threads, "at least 1" if threads < 1 else f"at most {limit}")
    start = time.perf_counter()
    with pytest.raises(ValueError, match=message):
        gng3d.simplify(v, f, method="gng", vertices_target=100, threads=threads)
    with pytest.raises(ValueError, match=message):
        gng3d.simplify(v, f, faces_target=100, method="qem", threads=threads)
    with pytest.raises(ValueError, match=message):
        gng3d.Trainer(v, f, vertices_target=100, threads=threads)
    source = tmp_path / "in.ply"
    gng3d.save(source, v, f)
    with pytest.raises(ValueError, match=message):
        gng3d.simplify_file(source, tmp_path / "out.ply", ratio=0.1, threads=threads)
    with pytest.raises(ValueError, match=message):
        gng3d.batch.simplify_files([source], tmp_path / "out", ratio=0.1, threads=threads)
    assert time.perf_counter() - start < 5.0


def test_threads_up_to_the_limit_run(small_torus):
    v, f = small_torus
    assert gng3d.MAX_THREADS == 256
    a = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=2, threads=gng3d.MAX_THREADS)
    b = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=2, threads=1)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    with pytest.raises(TypeError, match=r"^threads must be an int, got float$"):
        gng3d.simplify(v, f, method="gng", vertices_target=200, threads=2.0)


def out_of_range(name, value, bound):
    return rf"^parameter {name} = {value} is out of range: must be {bound}$"


def test_step_and_train_counts_name_their_parameter(small_torus):
    v, f = small_torus
    t = gng3d.Trainer(v, f, vertices_target=100)
    with pytest.raises(ValueError, match=out_of_range("signals", -5, "at least 0")):
        t.step(-5)
    with pytest.raises(ValueError, match=out_of_range("signals", -(2**80), "at least 0")):
        t.step(-(2**80))
    assert t.step(0)["signals"] == 0
    assert t.step(np.int64(1000))["signals"] >= 1000
    with pytest.raises(ValueError, match=out_of_range("every", 0, "at least 1")):
        t.train(every=0)
    with pytest.raises(ValueError, match=out_of_range("seed", -1, "at least 0")):
        gng3d.simplify(v, f, method="gng", vertices_target=100, seed=-1)
    with pytest.raises(ValueError, match=out_of_range("seed", 2**64, f"at most {2**64 - 1}")):
        gng3d.simplify(v, f, vertices_target=100, seed=2**64)


def test_mesh_before_any_step_says_so_in_words(small_torus):
    v, f = small_torus
    t = gng3d.Trainer(v, f, vertices_target=100)
    with pytest.raises(RuntimeError) as raised:
        t.mesh()
    message = str(raised.value)
    assert "None" not in message and "Some(" not in message, message
    assert "too few for a mesh" in message and "train it first" in message, message


def test_default_seed_is_the_library_and_cli_default(small_torus):
    v, f = small_torus
    assert gng3d.DEFAULT_SEED == 1
    default = gng3d.simplify(v, f, method="gng", vertices_target=200)
    one = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=1)
    np.testing.assert_array_equal(default.vertices, one.vertices)
    t = gng3d.Trainer(v, f, vertices_target=200)
    t.train()
    np.testing.assert_array_equal(t.mesh().vertices, one.vertices)


def test_batch_without_a_seed_writes_what_the_cli_writes(tmp_path, small_torus):
    cli = cli_binary()
    if not cli:
        pytest.skip("needs the gng3d CLI (GNG3D_CLI)")
    source = tmp_path / "in"
    source.mkdir()
    gng3d.save(source / "torus.ply", *small_torus)
    subprocess.run([cli, "simplify", str(source / "torus.ply"), str(tmp_path / "cli.ply"),
                    "--method", "gng", "--vertices", "200"],
                   check=True, capture_output=True)  # fmt: skip
    code = gng3d.batch.main([str(source), "--out", str(tmp_path / "py"), "--vertices", "200",
                             "--method", "gng", "--jobs", "1"])  # fmt: skip
    assert code == 0
    cli_v, cli_f = gng3d.load(tmp_path / "cli.ply")
    py_v, py_f = gng3d.load(tmp_path / "py" / "torus.ply")
    np.testing.assert_array_equal(cli_v, py_v)
    np.testing.assert_array_equal(cli_f, py_f)


def test_simplify_docstring_says_ratio_is_a_share_of_vertices_for_qem_too():
    doc = gng3d.simplify.__doc__
    assert "``--ratio`` with ``--method qem`` is one of faces" not in doc
    assert "as the CLI's ``--ratio`` is for every method" in doc


def interrupted_after(script: str, seconds: float = 1.0):
    """Runs `script` in a subprocess; SIGINT `seconds` after it prints "ready". Returns the
    process's stderr and the seconds from the signal to its exit."""
    env = dict(os.environ, PYTHONPATH=str(HERE) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    process = subprocess.Popen(
        [sys.executable, "-c", textwrap.dedent(script)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=env,
    )
    try:
        line = process.stdout.readline()
        assert line.strip() == "ready", (line, process.stderr.read())
        time.sleep(seconds)
        process.send_signal(signal.SIGINT)
        sent = time.perf_counter()
        try:
            _, stderr = process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            pytest.fail("the process ignored SIGINT for 30 s")
        return stderr, time.perf_counter() - sent
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()


def test_ctrl_c_stops_a_long_trainer_step():
    stderr, waited = interrupted_after(
        """
        import gng3d
        from conftest import torus
        v, f = torus(96, 48)
        t = gng3d.Trainer(v, f, vertices_target=1500, epochs=5000)
        print("ready", flush=True)
        t.step(10**9)
        print("not interrupted", flush=True)
        """
    )
    assert "KeyboardInterrupt" in stderr, stderr
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to exit"


def test_ctrl_c_stops_simplify_file_in_training_and_writes_nothing(tmp_path):
    source = tmp_path / "in.ply"
    gng3d.save(source, *torus(96, 48))
    output = tmp_path / "out.ply"
    stderr, waited = interrupted_after(
        f"""
        import gng3d
        print("ready", flush=True)
        gng3d.simplify_file({str(source)!r}, {str(output)!r}, vertices_target=1500, epochs=2000, method="gng")
        """
    )
    assert "KeyboardInterrupt" in stderr, stderr
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to exit"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply"]


# Ctrl-C in every long call (issue 46, item 5): QEM, GNG3D's steps after training
# (Trainer.mesh), the metrics, and simplify_file, which then writes nothing.


def interrupts_itself(setup: str, call: str, warm: str = "pass"):
    """Runs `setup`, then times `warm` (the same call's work before the part that can be
    stopped: reading the arrays or the file, the set-up), then runs `call` with a timer that
    sends the process SIGINT 0.3 s after that time, so that it arrives in the middle of the
    work (0.3 s: a fast idle machine finishes a 2.56M-face QEM in about 1.5 s). Returns the
    seconds from the signal to the KeyboardInterrupt; fails when the call ends first or raises
    something else."""
    script = "\n".join(
        [
            "import os, signal, threading, time",
            "import gng3d",
            "from conftest import torus",
            textwrap.dedent(setup),
            "started = time.perf_counter()",
            textwrap.dedent(warm),
            "delay = time.perf_counter() - started + 0.3",
            "sent = []",
            "def interrupt():",
            "    sent.append(time.perf_counter())",
            "    os.kill(os.getpid(), signal.SIGINT)",
            "threading.Timer(delay, interrupt).start()",
            "try:",
            textwrap.indent(textwrap.dedent(call), "    "),
            "    print('not interrupted', flush=True)",
            "except KeyboardInterrupt:",
            "    print('interrupted', time.perf_counter() - sent[0], flush=True)",
        ]
    )
    env = dict(os.environ, PYTHONPATH=str(HERE) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300
    )
    words = done.stdout.split()
    assert done.returncode == 0 and words[:1] == ["interrupted"], (done.stdout, done.stderr)
    print(f"KeyboardInterrupt {float(words[1]):.3f} s after SIGINT")  # shown with pytest -s
    return float(words[1])


def test_ctrl_c_stops_a_long_qem_simplify():
    waited = interrupts_itself(
        setup="v, f = torus(1600, 800)  # 1.28 M vertices, 2.56 M faces",
        # The arrays' conversion alone (the ratio is refused after it).
        warm="""
        try:
            gng3d.simplify(v, f, method="qem", ratio=0.0, weld=False)
        except ValueError:
            pass
        """,
        call='gng3d.simplify(v, f, method="qem", ratio=0.01, weld=False)',
    )
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to KeyboardInterrupt"


def test_ctrl_c_stops_a_long_trainer_mesh():
    # A network stopped early on a large original: the steps after training (labelling the
    # original's vertices, placement, flips, refit, decimation, ...) take seconds.
    waited = interrupts_itself(
        setup="""
        v, f = torus(1200, 600)
        t = gng3d.Trainer(v, f, vertices_target=60000, weld=False)
        t.step(400_000)
        t.stop()
        t.step(1)
        assert t.finished
        """,
        call="t.mesh()",
    )
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to KeyboardInterrupt"


@pytest.mark.parametrize(
    "meshes, call",
    [
        # Metro's sampling, 4M samples.
        ((800, 400, 80, 40), "gng3d.metrics(v0, f0, v1, f1, samples=4_000_000)"),
        # The image-space error at 2048².
        (
            (1200, 600, 60, 30),
            "gng3d.metrics(v0, f0, v1, f1, samples=1000, image_error=True, image_size=2048)",
        ),
    ],
    ids=["sampling", "image_error"],
)
def test_ctrl_c_stops_long_metrics(meshes, call):
    a, b, c, d = meshes
    waited = interrupts_itself(
        setup=f"v0, f0 = torus({a}, {b})\nv1, f1 = torus({c}, {d})",
        warm="gng3d.metrics(v0, f0, v1, f1, samples=1000)",
        call=call,
    )
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to KeyboardInterrupt"


def test_ctrl_c_stops_simplify_file_in_qem_and_writes_nothing(tmp_path):
    source = tmp_path / "in.ply"
    gng3d.save(source, *torus(1200, 600))
    output = tmp_path / "out.ply"
    waited = interrupts_itself(
        setup="",
        # Reading and welding the file alone (the ratio is refused after them).
        warm=f"""
        try:
            gng3d.simplify_file({str(source)!r}, {str(output)!r}, method="qem", ratio=0.0)
        except ValueError:
            pass
        """,
        call=f"gng3d.simplify_file({str(source)!r}, {str(output)!r}, method='qem', ratio=0.01)",
    )
    assert waited < 1.0, f"{waited:.2f} s from SIGINT to KeyboardInterrupt"
    assert not output.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.ply"]


# Georeferenced data (issue 46): float64 coordinates far from their origin keep their
# precision through every call, and files keep their coordinates.
OFFSET = np.array([450_000.0, 5_400_000.0, 120.0])


def _nearest(a, b):
    """For each row of a, the distance to the nearest row of b."""
    d = np.sqrt(((a[:, None, :] - b[None, :, :]) ** 2).sum(-1))
    return d.min(axis=1)


def test_georeferenced_arrays_keep_their_coordinates(tmp_path):
    from conftest import torus

    v, f = torus(48, 24, r_major=10.0, r_minor=3.0)
    v = v + OFFSET
    extent = 26.0 * np.sqrt(3.0)
    # QEM at ratio 1 keeps every vertex: none merged, none moved beyond 1e-6 of the extent.
    result = gng3d.simplify(v, f, method="qem", ratio=1.0)
    assert result.vertices.shape == v.shape
    assert _nearest(result.vertices, v).max() <= 1e-6 * extent
    # GNG3D-Q's output lies on the surface where it was, not 0.25 m off.
    gng = gng3d.simplify(v, f, method="gng", ratio=0.25)
    assert np.abs(gng.vertices.mean(axis=0) - v.mean(axis=0)).max() < 1.0
    # A file written from such arrays and loaded back keeps the coordinates.
    path = tmp_path / "far.ply"
    gng3d.save(str(path), v, f)
    back, _ = gng3d.load(str(path))
    assert _nearest(back, v).max() <= 1e-6 * extent
    # simplify_file keeps them too (OBJ text in f64).
    obj = tmp_path / "far-out.obj"
    gng3d.simplify_file(str(path), str(obj), method="qem", ratio=1.0)
    rows = [l.split()[1:4] for l in obj.read_text().splitlines() if l.startswith("v ")]
    out = np.array(rows, dtype=np.float64)
    assert len(out) == len(v)
    assert _nearest(out, v).max() <= 1e-6 * extent


# Files from strangers (issue 46): what a model points at stays inside its folder, through the
# Python API as through the CLI (the same mesh::io rule).
def _tetra_gltf(buffer_uri, image_uri=None):
    import json
    import struct

    pos = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
    uv = struct.pack("<8f", 0, 0, 1, 0, 0, 1, 1, 1)
    idx = struct.pack("<12H", 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"},
        ],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 32},
            {"buffer": 0, "byteOffset": 80, "byteLength": 24},
        ],
        "buffers": [{"byteLength": 104, "uri": buffer_uri}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1},
                                     "indices": 2}]}],
    }
    if image_uri:
        doc["meshes"][0]["primitives"][0]["material"] = 0
        doc["materials"] = [{"name": "m", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
        doc["textures"] = [{"source": 0}]
        doc["images"] = [{"uri": image_uri}]
    return json.dumps(doc), pos + uv + idx


def test_references_outside_the_models_folder_are_not_read(tmp_path):
    work, outside = tmp_path / "work", tmp_path / "outside"
    work.mkdir()
    outside.mkdir()
    doc, geometry = _tetra_gltf("../outside/secret.bin")
    (outside / "secret.bin").write_bytes(geometry)
    (outside / "secret.png").write_bytes(b"\x89PNG\r\n\x1a\nCANARY")
    (work / "g.bin").write_bytes(geometry)
    (work / "escape.gltf").write_text(doc)
    with pytest.raises(Exception, match="not read: it leaves the model's folder"):
        gng3d.load(str(work / "escape.gltf"))
    with pytest.raises(Exception, match="not read"):
        gng3d.simplify_file(str(work / "escape.gltf"), str(work / "out.ply"), ratio=1.0)
    assert not (work / "out.ply").exists()
    # A texture outside: the mesh is written, the texture neither copied nor embedded.
    doc, _ = _tetra_gltf("g.bin", image_uri="../outside/secret.png")
    (work / "tex.gltf").write_text(doc)
    with pytest.warns(gng3d.Gng3dWarning, match="leaves the model's folder"):
        gng3d.simplify_file(str(work / "tex.gltf"), str(work / "tex-out.glb"), method="qem", ratio=1.0)
    assert b"CANARY" not in (work / "tex-out.glb").read_bytes()
    assert sorted(p.name for p in outside.iterdir()) == ["secret.bin", "secret.png"]
    # The output never replaces the input or the buffer it reads.
    for target in ["tex.gltf", "g.gltf"]:
        with pytest.raises(Exception, match="would replace"):
            gng3d.simplify_file(str(work / "tex.gltf"), str(work / target), method="qem", ratio=1.0)
    assert (work / "g.bin").read_bytes() == geometry


def test_allow_outside_references_is_an_explicit_opt_in(tmp_path):
    work, outside = tmp_path / "work", tmp_path / "outside"
    work.mkdir()
    outside.mkdir()
    doc, geometry = _tetra_gltf("../outside/g.bin")
    (outside / "g.bin").write_bytes(geometry)
    (work / "beside.gltf").write_text(doc)
    with pytest.raises(Exception, match="leaves the model's folder"):
        gng3d.load(str(work / "beside.gltf"))
    gng3d.allow_outside_references(True)
    try:
        v, f = gng3d.load(str(work / "beside.gltf"))
        assert v.shape == (4, 3) and f.shape == (4, 3)
    finally:
        gng3d.allow_outside_references(False)
    with pytest.raises(Exception, match="leaves the model's folder"):
        gng3d.load(str(work / "beside.gltf"))
