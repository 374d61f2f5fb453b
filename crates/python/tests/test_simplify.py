"""gng3d.simplify: exact counts, results, reports, warnings, agreement with the CLI."""

import json
import subprocess
import warnings

import numpy as np
import pytest

import gng3d
from conftest import cli_binary, shared_meshes, torus

# The fields of `gng3d simplify --method gng --json` (crates/cli/src/cli/simplify/gng.rs).
GNG_FIELDS = {
    "method", "input_vertices", "input_faces", "vertices", "faces", "iterations", "seconds",
    "training_seconds",
    "target_vertices", "nodes", "oversample", "network_vertices", "placement", "signals",
    "flips", "refit", "detail_rounds", "detail_nodes", "relax", "relaxed_vertices",
    "repair_deviations", "deviation_moves", "deviation_flips", "shape", "creases", "steps",
    "warnings", "closed",
    "manifold", "genus", "boundary_edges", "non_manifold_edges",
}  # fmt: skip
# `gng3d simplify --method qem --json`, plus the warnings the CLI prints on stderr.
QEM_FIELDS = {"method", "vertices", "faces", "seconds", "report", "warnings"}


@pytest.mark.parametrize("method", ["gng", "paper"])
@pytest.mark.parametrize("target", [20, 50, 400, 1000])
def test_gng_gives_the_exact_vertex_count(small_torus, method, target):
    v, f = small_torus
    result = gng3d.simplify(v, f, vertices_target=target, method=method, seed=3)
    assert result.vertices.shape == (target, 3)
    assert result.report["vertices"] == target
    assert result.report["target_vertices"] == target
    assert result.faces.shape[1] == 3 and len(result.faces) > 0
    assert result.faces.min() >= 0 and result.faces.max() < target


def test_shape_and_creases_reach_the_run(small_torus):
    """shape="round" / "fit" and creases=True go through the job's one mapping (as the CLI's
    --shape=round and --creases): the report names them, the shape pass runs and changes the
    mesh; creases change nothing on a torus, which has no crease (only a CAD part is cut along
    its creases); an unknown shape is a ValueError naming the three settings."""
    v, f = small_torus
    plain = gng3d.simplify(v, f, method="gng", vertices_target=200)
    shaped = gng3d.simplify(v, f, method="gng", vertices_target=200, shape="round")
    fit = gng3d.simplify(v, f, method="gng", vertices_target=200, shape="fit")
    creased = gng3d.simplify(v, f, method="gng", vertices_target=200, creases=True)
    steps = lambda r: [s["step"] for s in r.report["steps"]]  # noqa: E731
    assert [r.report["shape"] for r in (plain, fit, shaped)] == ["off", "fit", "round"]
    assert "shape" in steps(fit)
    with pytest.raises(ValueError, match=r"shape.*'off', 'fit' or 'round'"):
        gng3d.simplify(v, f, method="gng", vertices_target=200, shape="square")
    assert (plain.report["creases"], creased.report["creases"]) == (False, True)
    assert "shape" not in steps(plain) and "shape" in steps(shaped)
    assert shaped.vertices.shape == plain.vertices.shape == (200, 3)
    assert not np.array_equal(shaped.vertices, plain.vertices)
    assert np.array_equal(creased.vertices, plain.vertices)
    assert np.array_equal(creased.faces, plain.faces)


def test_result_types_and_unpacking(small_torus):
    v, f = small_torus
    result = gng3d.simplify(v, f, method="gng", ratio=0.25)
    vertices, faces = result
    assert vertices is not None and vertices.dtype == np.float64 and vertices.shape[1] == 3
    assert faces.dtype == np.int64 and faces.shape[1] == 3
    np.testing.assert_array_equal(vertices, result.vertices)
    np.testing.assert_array_equal(faces, result.faces)
    assert len(result) == 2 and result[0] is not None and result[-1] is not None
    assert "SimplifyResult(method='gng'" in repr(result)
    json.dumps(result.report)  # plain JSON types


def test_ratio_is_a_share_of_the_input_vertices_for_every_method(small_torus):
    v, f = small_torus  # 1152 vertices, 2304 faces
    gng = gng3d.simplify(v, f, method="gng", ratio=0.25)
    assert len(gng.vertices) == round(0.25 * len(v)) == 288
    qem = gng3d.simplify(v, f, ratio=0.25, method="qem")
    assert len(qem.vertices) == 288
    faces = gng3d.simplify(v, f, faces_target=500, method="qem")
    assert len(faces.faces) in (499, 500)


def test_report_fields_are_the_cli_json_fields(small_torus):
    v, f = small_torus
    gng = gng3d.simplify(v, f, method="gng", vertices_target=200)
    assert set(gng.report) == GNG_FIELDS
    assert gng.report["method"] == "gng" and gng.report["warnings"] == []
    assert gng.report["placement"] == "quadric" and gng.report["closed"]
    qem = gng3d.simplify(v, f, vertices_target=200, method="qem")
    assert set(qem.report) == QEM_FIELDS
    assert qem.report["report"]["stop_reason"] == "target_reached"
    paper = gng3d.simplify(v, f, vertices_target=200, method="paper")
    assert paper.report["placement"] == "node" and paper.report["oversample"] == 1.0


def test_same_seed_same_mesh_other_seed_other_mesh(small_torus):
    v, f = small_torus
    a = gng3d.simplify(v, f, method="gng", vertices_target=300, seed=5)
    b = gng3d.simplify(v, f, method="gng", vertices_target=300, seed=5)
    c = gng3d.simplify(v, f, method="gng", vertices_target=300, seed=6)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    np.testing.assert_array_equal(a.faces, b.faces)
    assert not np.array_equal(a.vertices, c.vertices)


def test_a_target_qem_cannot_reach_is_a_warning_and_in_the_report(small_torus):
    v, f = small_torus  # a torus keeps more than 3 vertices under QEM's topology checks
    with pytest.warns(gng3d.Gng3dWarning, match="QEM stopped at"):
        result = gng3d.simplify(v, f, vertices_target=3, method="qem")
    (w,) = result.report["warnings"]
    assert w["kind"] == "target_not_reached" and w["message"].startswith("QEM stopped at")
    assert len(result.vertices) > 3


def test_gng_warnings_carry_their_sentence():
    # Two tori, one tiny: the small piece cannot hold its share -> the GNG3D warnings list.
    v1, f1 = torus(48, 24)
    v2, f2 = torus(4, 3, 0.01, 0.003)
    v = np.concatenate([v1, v2 + 5.0])
    f = np.concatenate([f1, f2 + len(v1)])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = gng3d.simplify(v, f, method="gng", vertices_target=1000)
    for w in result.report["warnings"]:
        assert isinstance(w["kind"], str) and isinstance(w["message"], str)
    messages = [str(c.message) for c in caught if issubclass(c.category, gng3d.Gng3dWarning)]
    assert messages == [w["message"] for w in result.report["warnings"]]


def test_weld_merges_a_triangle_soup(small_torus):
    v, f = small_torus
    soup_v = v[f.reshape(-1)]  # every corner its own vertex, as STL stores them
    soup_f = np.arange(len(soup_v)).reshape(-1, 3)
    welded = gng3d.simplify(soup_v, soup_f, method="gng", vertices_target=200, seed=2)
    indexed = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=2)
    assert welded.report["closed"] and len(welded.vertices) == 200
    assert welded.report["genus"] == indexed.report["genus"] == 1


def test_time_limit_keeps_the_count(small_torus):
    v, f = small_torus
    result = gng3d.simplify(v, f, method="gng", vertices_target=500, time_limit=0.5)
    assert len(result.vertices) == 500


def test_method_options_reach_the_library(small_torus):
    v, f = small_torus
    plain = gng3d.simplify(
        v, f, vertices_target=300, method="gng", placement="node", flips=False, oversample=1.0,
        epochs=5,
    )
    assert plain.report["placement"] == "node" and not plain.report["flips"]
    assert plain.report["iterations"] == 5 * len(v)
    qem = gng3d.simplify(v, f, vertices_target=300, method="qem", threshold=0.01)
    assert qem.report["report"]["virtual_pairs"] >= 0


def _cli_run(cli, tmp_path, mesh, args):
    out = tmp_path / "cli-out.ply"
    proc = subprocess.run(
        [cli, "simplify", str(mesh), str(out), "--json", *args],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(proc.stdout), gng3d.load(out)


# Meshes with positions only: the CLI also carries an input's texture coordinates, normals and
# colours through (its "attributes"), which the binding's numpy arrays do not hold.
@pytest.mark.parametrize("name", ["cow.obj", "fandisk.obj"])
@pytest.mark.parametrize(
    "method,cli_args,py_args",
    [
        ("gng", ["--method", "gng", "--ratio", "0.1", "--seed", "7"],
         dict(method="gng", ratio=0.1, seed=7)),
        ("paper", ["--method", "gng", "--vertices", "300", "--seed", "3", "--placement",
                   "node", "--no-flips", "--epochs", "30"],
         dict(method="gng", vertices_target=300, seed=3, placement="node", flips=False,
              epochs=30)),
        ("qem", ["--method", "qem", "--faces", "1000"],
         dict(method="qem", faces_target=1000)),
    ],
)  # fmt: skip
def test_same_mesh_as_the_cli(tmp_path, name, method, cli_args, py_args):
    cli = cli_binary()
    mesh = shared_meshes() / name
    if cli is None or not mesh.exists():
        pytest.skip("needs the gng3d CLI (GNG3D_CLI) and the shared meshes (GNG3D_MESHES)")
    summary, (cli_v, cli_f) = _cli_run(cli, tmp_path, mesh, cli_args)
    v, f = gng3d.load(mesh)
    result = gng3d.simplify(v, f, **py_args)
    np.testing.assert_array_equal(result.vertices, cli_v)
    np.testing.assert_array_equal(result.faces, cli_f)
    # Same report, less the times and the binding's warning sentences.
    report = dict(result.report)
    for key in ["seconds", "training_seconds", "steps", "warnings"]:
        report.pop(key, None)
        summary.pop(key, None)
    if method == "qem":
        report["report"].pop("seconds")
        summary["report"].pop("seconds")
    assert summary.pop("attributes") == {"input": [], "kept": [], "dropped": []}
    assert report == summary
    # And the same bytes once saved.
    ours = tmp_path / "py-out.ply"
    gng3d.save(ours, result.vertices, result.faces)
    assert ours.read_bytes() == (tmp_path / "cli-out.ply").read_bytes()


@pytest.mark.parametrize("method", ["gng", "qem"])
def test_thread_count_does_not_change_the_mesh(small_torus, method):
    v, f = small_torus
    one = gng3d.simplify(v, f, vertices_target=300, method=method, threads=1)
    default = gng3d.simplify(v, f, vertices_target=300, method=method)
    np.testing.assert_array_equal(one.vertices, default.vertices)
    np.testing.assert_array_equal(one.faces, default.faces)
