"""Array-likes in, bad input out: every row raises ValueError with the library's sentence."""

import numpy as np
import pytest

import gng3d

TRI_V = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]


def test_any_array_like_gives_the_same_result(small_torus):
    v, f = small_torus
    expected = gng3d.simplify(v, f, method="gng", vertices_target=200, seed=1)
    wide = np.zeros((len(v), 6))
    wide[:, ::2] = v  # a strided, non-contiguous view
    variants = [
        (v.tolist(), f.tolist()),  # plain lists
        (wide[:, ::2], f),  # non-contiguous vertices
        (np.asfortranarray(v), np.asfortranarray(f)),  # column-major
        (v.astype(np.float32), f.astype(np.int32)),
        (v, f.astype(np.uint32)),
        (v, f.astype(np.uint64)),
        (v, f.astype(np.int16)),
        (tuple(map(tuple, v)), tuple(map(tuple, f))),
    ]
    for vv, ff in variants:
        got = gng3d.simplify(vv, ff, method="gng", vertices_target=200, seed=1)
        np.testing.assert_array_equal(got.vertices, expected.vertices)
        np.testing.assert_array_equal(got.faces, expected.faces)


def test_float32_input_is_read_without_loss(small_torus):
    v, f = small_torus
    v32 = v.astype(np.float32)
    result = gng3d.simplify(v32, f, vertices_target=len(v), method="qem")
    assert result.vertices.dtype == np.float64
    # Every output vertex is an input vertex (nothing collapsed), exactly.
    assert set(map(tuple, result.vertices)) == set(map(tuple, v32.astype(np.float64)))


BAD_INPUT = [
    ("vertices 2 columns", np.zeros((3, 2)), [[0, 1, 2]],
     r"^vertices must have shape \(n, 3\) \(x, y, z per vertex\), got shape \(3, 2\)$"),
    ("vertices 1-d", [0.0, 1.0, 2.0], [[0, 1, 2]],
     r"^vertices must have shape \(n, 3\) .*got shape \(3\)$"),
    ("faces 4 columns", TRI_V, [[0, 1, 2, 0]],
     r"^faces must have shape \(n, 3\) \(three vertex indices per triangle\), got shape \(1, 4\)$"),
    ("ragged", [[0, 0, 0], [1, 0]], [[0, 1, 2]], r"^vertices must be an array of shape \(n, 3\)"),
    ("NaN", [[0, 0, 0], [1, 0, 0], [np.nan, 0, 0]], [[0, 1, 2]],
     r"^input: vertex 2 has a non-finite coordinate$"),
    ("inf", [[0, 0, 0], [np.inf, 0, 0], [0, 1, 0]], [[0, 1, 2]],
     r"^input: vertex 1 has a non-finite coordinate$"),
    ("index too large", TRI_V, [[0, 1, 3]],
     r"^input: face 0 refers to vertex 3, but there are only 3 vertices$"),
    ("negative index", TRI_V, [[0, 1, 2], [0, -1, 2]],
     r"^input: face 1 refers to vertex -1, but there are only 3 vertices$"),
    ("huge unsigned index", TRI_V, np.array([[0, 1, 2**63 + 5]], dtype=np.uint64),
     r"^input: face 0 refers to vertex \d+, but there are only 3 vertices$"),
    ("no vertices", np.zeros((0, 3)), np.zeros((0, 3), dtype=int),
     r"^input: the mesh has no vertices$"),
    ("empty lists", [], [], r"^input: the mesh has no vertices$"),
    ("no faces", TRI_V, np.zeros((0, 3), dtype=int),
     r"^input: the mesh has 3 vertices but no faces \(point cloud\)$"),
    ("only degenerate faces", TRI_V, [[0, 1, 1]],
     r"^input: the mesh has 3 vertices but no faces \(point cloud\)$"),
    ("float faces", TRI_V, [[0.0, 1.0, 2.0]],
     r"^faces must be integer vertex indices, got dtype float64$"),
    ("string vertices", [["a", "b", "c"]] * 3, [[0, 1, 2]],
     r"^vertices must be numbers, got dtype <U1$"),
]  # fmt: skip


@pytest.mark.parametrize("method", ["gng", "qem"])
@pytest.mark.parametrize("name,vertices,faces,message", BAD_INPUT, ids=[b[0] for b in BAD_INPUT])
def test_bad_input_raises_value_error(method, name, vertices, faces, message):
    with pytest.raises(ValueError, match=message):
        gng3d.simplify(vertices, faces, vertices_target=3, method=method)


BAD_OPTIONS = [
    (dict(ratio=1.5), r"^ratio must be in \(0, 1\], got 1.5$"),
    (dict(ratio=0.0), r"^ratio must be in \(0, 1\], got 0$"),
    (dict(ratio=float("nan"), method="gng"), r"^ratio must be in \(0, 1\], got NaN"),
    (dict(ratio=1.5, method="qem"), r"^ratio must be in \(0, 1\]"),
    (dict(vertices_target=10, method="gng", time_limit=-1.0),
     r"^parameter time limit = -1 is out of range: must be a finite number of seconds > 0$"),
    (dict(vertices_target=10, method="gng", time_limit=float("inf")), r"^parameter time limit = inf"),
    (dict(vertices_target=10, method="gng", oversample=5.0),
     r"^parameter oversample = 5 is out of range: must be in \[1, 4\]$"),
    (dict(vertices_target=10, method="gng", epochs=0.0), r"^parameter epochs = 0 is out of range"),
    (dict(vertices_target=10, method="gng", detail_rounds=9), r"^parameter detail rounds = 9 is out of range"),
    (dict(vertices_target=2, method="gng"),
     r"^target of 2 vertices is out of range: it must be between 3 and the 1152 distinct"),
    (dict(vertices_target=5000, method="gng"), r"^target of 5000 vertices is out of range"),
    (dict(), r"^give a target: vertices_target=N, faces_target=N \(QEM\) or ratio=R$"),
    (dict(ratio=0.1, vertices_target=10), r"^give one target"),
    (dict(faces_target=100, method="gng"), r"^faces_target applies to method 'qem' only"),
    (dict(ratio=0.1, method="qem", flips=False, time_limit=1.0),
     r"^time_limit and flips apply to method 'gng' and 'paper' only, not 'qem'$"),
    (dict(ratio=0.1, method="qem", shape="fit", creases=True),
     r"^shape and creases apply to method 'gng' and 'paper' only, not 'qem'$"),
    (dict(ratio=0.1, method="gng", threshold=0.1), r"^threshold applies to method 'qem' only$"),
    (dict(ratio=0.1, method="qem", threshold=-1.0),
     r"^threshold must be a finite distance >= 0, got -1$"),
    (dict(ratio=0.1, method="qem", threshold=1e30),
     r"^invalid parameter: pair threshold 1e30 is above the limit"),
    (dict(ratio=0.1, threads=0), r"^parameter threads = 0 is out of range: must be at least 1$"),
    (dict(ratio=0.1, method="qem", threads=0), r"^parameter threads = 0 is out of range"),
    (dict(ratio=0.1, method="QEM"), r"^method must be 'qem', 'gng' or 'paper', got \"QEM\"$"),
    (dict(ratio=0.1, placement="nodes"), r"^placement must be 'node', 'project' or 'quadric'"),
    (dict(ratio=0.1, signals="edges"), r"^signals must be 'vertices', 'surface' or 'curvature'"),
]  # fmt: skip


@pytest.mark.parametrize("options,message", BAD_OPTIONS, ids=[m for _, m in BAD_OPTIONS])
def test_bad_options_raise_value_error(small_torus, options, message):
    v, f = small_torus
    with pytest.raises(ValueError, match=message):
        gng3d.simplify(v, f, **options)


def test_targets_are_keyword_only(small_torus):
    v, f = small_torus
    with pytest.raises(TypeError):
        gng3d.simplify(v, f, 100)  # type: ignore[misc]


def test_metrics_options_and_input_are_checked(small_torus):
    v, f = small_torus
    with pytest.raises(ValueError, match=r"^samples: must be at least 1"):
        gng3d.metrics(v, f, v, f, samples=0)
    with pytest.raises(ValueError, match=r"^simplified: vertex 0 has a non-finite coordinate$"):
        bad = v.copy()
        bad[0, 0] = np.nan
        gng3d.metrics(v, f, bad, f)
    with pytest.raises(ValueError, match=r"^original: face 0 refers to vertex 99999"):
        gng3d.metrics(v, np.array([[0, 1, 99999]]), v, f)


def test_stubs_list_the_keywords_the_binding_parses():
    """The stubs' keywords of simplify and simplify_file (their ``Options``) are exactly the
    binding's (gng3d.KEYWORDS, the one table the Rust parser reads), in its order."""
    import ast
    from pathlib import Path

    stubs = ast.parse((Path(gng3d.__file__).parent / "_gng3d.pyi").read_text())
    classes = {n.name: n for n in stubs.body if isinstance(n, ast.ClassDef)}
    keywords = [n.target.id for n in classes["Options"].body if isinstance(n, ast.AnnAssign)]
    assert keywords == list(gng3d.KEYWORDS)
    functions = {n.name: n for n in stubs.body if isinstance(n, ast.FunctionDef)}
    for name in ["simplify", "simplify_file"]:
        kwarg = functions[name].args.kwarg
        assert kwarg is not None and ast.unparse(kwarg.annotation) == "Unpack[Options]", name
    assert gng3d.DEFAULT_METHOD == "qem"
