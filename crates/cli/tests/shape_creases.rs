//! `--shape` and `--creases` (GNG3D-Q's triangle-shape pass and CAD creases,
//! `ReconstructionParams::{shape, creases}`) reach the run through the job's one mapping: the
//! JSON report names them and the step they add, the output changes the way each promises, and
//! QEM refuses them with the message of the other GNG3D-only options.

mod common;
use common::{gng3d, json_of, s, stderr};

/// `gng3d simplify INPUT OUTPUT --method gng --vertices N --json` plus `extra`: its JSON and
/// the mesh it wrote.
fn simplify_gng(
    input: &std::path::Path,
    output: &std::path::Path,
    vertices: usize,
    extra: &[&str],
) -> (serde_json::Value, mesh::TriMesh) {
    let n = vertices.to_string();
    let mut args = vec![
        "simplify",
        s(input),
        s(output),
        "--method",
        "gng",
        "--vertices",
        &n,
        "--json",
    ];
    args.extend_from_slice(extra);
    let report = json_of(&gng3d(&args));
    let out = mesh::io::load(output).unwrap().mesh;
    assert_eq!(out.vertex_count(), vertices);
    (report, out)
}

/// The names of the steps the report lists.
fn steps(report: &serde_json::Value) -> Vec<String> {
    report["steps"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["step"].as_str().unwrap().to_string())
        .collect()
}

/// The share of `m`'s triangles whose smallest angle is under `degrees` (computed here from
/// the positions, not by the metrics crate).
fn share_under(m: &mesh::TriMesh, degrees: f64) -> f64 {
    let under = (0..m.face_count())
        .filter(|&f| {
            let [a, b, c] = m.triangle_f64(f);
            let angle = |p: glam::DVec3, q: glam::DVec3, r: glam::DVec3| {
                (q - p).angle_between(r - p).to_degrees()
            };
            angle(a, b, c).min(angle(b, c, a)).min(angle(c, a, b)) < degrees
        })
        .count();
    under as f64 / m.face_count() as f64
}

/// The mean distance of `m`'s face centroids from the torus of radii 1 and 0.3 around z
/// (computed here, in closed form).
fn off_torus(m: &mesh::TriMesh) -> f64 {
    let sum: f64 = (0..m.face_count())
        .map(|f| {
            let [a, b, c] = m.triangle_f64(f);
            let p = (a + b + c) / 3.0;
            let ring = (p.x.hypot(p.y) - 1.0).hypot(p.z);
            (ring - 0.3).abs()
        })
        .sum();
    sum / m.face_count() as f64
}

#[test]
fn shape_flag_reaches_the_run_and_rounds_the_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("torus.obj");
    // 1,536 vertices; the inner side bends 1.7 × more than the outer side.
    let torus = mesh::procedural::torus(1.0, 0.3, 64, 24);
    mesh::io::save(&torus.into(), &input).unwrap();
    let n = 200;
    let (plain, plain_mesh) = simplify_gng(&input, &dir.path().join("plain.obj"), n, &[]);
    // `--shape` alone is `--shape=fit`.
    let (fit, fit_mesh) = simplify_gng(&input, &dir.path().join("fit.obj"), n, &["--shape"]);
    let (round, round_mesh) =
        simplify_gng(&input, &dir.path().join("round.obj"), n, &["--shape=round"]);
    assert_eq!(
        [&plain, &fit, &round].map(|r| r["shape"].as_str()),
        [Some("off"), Some("fit"), Some("round")]
    );
    assert!(!steps(&plain).contains(&"shape".to_string()), "{plain}");
    assert!(steps(&fit).contains(&"shape".to_string()), "{fit}");
    assert!(steps(&round).contains(&"shape".to_string()), "{round}");
    assert_ne!(plain_mesh.positions, round_mesh.positions);
    // What `round` buys: fewer thin triangles than the same run without the pass.
    let [before, with_fit, with_round] =
        [&plain_mesh, &fit_mesh, &round_mesh].map(|m| share_under(m, 30.0));
    assert!(
        with_round < before && with_fit <= before,
        "triangles under 30°: {before} without, {with_fit} fit, {with_round} round"
    );
    // What `fit` keeps: the distance to the torus, which `round` gives up some of.
    let [d_plain, d_fit, d_round] = [&plain_mesh, &fit_mesh, &round_mesh].map(off_torus);
    assert!(
        d_fit <= d_round && d_fit <= 1.5 * d_plain,
        "mean distance from the torus: {d_plain:.3e} without, {d_fit:.3e} fit, {d_round:.3e} round"
    );
}

#[test]
fn creases_flag_reaches_the_run_and_keeps_a_cubes_corners() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cube.obj");
    mesh::io::save(&mesh::procedural::grid_cube(16).into(), &input).unwrap();
    let (plain, plain_mesh) = simplify_gng(&input, &dir.path().join("plain.obj"), 120, &[]);
    let (creased, creased_mesh) =
        simplify_gng(&input, &dir.path().join("creases.obj"), 120, &["--creases"]);
    assert_eq!(
        (plain["creases"].as_bool(), creased["creases"].as_bool()),
        (Some(false), Some(true))
    );
    // The cube's creases are cut along (the seams' step, which the plain run has no need of).
    assert!(!steps(&plain).contains(&"cut_seams".to_string()), "{plain}");
    assert!(
        steps(&creased).contains(&"cut_seams".to_string()),
        "{creased}"
    );
    // Every corner of the unit cube has an output vertex on it with --creases.
    let farthest_corner = |m: &mesh::TriMesh| {
        (0..8)
            .map(|c| {
                let corner =
                    glam::DVec3::new((c & 1) as f64, ((c >> 1) & 1) as f64, ((c >> 2) & 1) as f64);
                m.positions
                    .iter()
                    .map(|p| p.as_dvec3().distance(corner))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    let (without, with) = (farthest_corner(&plain_mesh), farthest_corner(&creased_mesh));
    assert!(
        with < 1e-3,
        "a corner {with} from the nearest vertex with --creases"
    );
    assert!(
        with < without,
        "corners: {without} without, {with} with --creases"
    );
}

#[test]
fn qem_refuses_shape_and_creases_naming_them() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.obj");
    mesh::io::save(&mesh::procedural::icosphere(2).into(), &input).unwrap();
    let output = dir.path().join("q.obj");
    for flag in ["--shape", "--creases"] {
        let o = gng3d(&[
            "simplify",
            s(&input),
            s(&output),
            "--method",
            "qem",
            "--vertices",
            "50",
            flag,
        ]);
        assert_eq!(o.status.code(), Some(1), "{flag}");
        let e = stderr(&o);
        assert!(
            e.contains(flag) && e.contains("--method gng"),
            "{flag}: {e}"
        );
        assert!(!output.exists(), "{flag}: an output was written");
    }
    // The batch checks its options with `simplify`'s parser and checks: the same refusal.
    let o = gng3d(&[
        "batch",
        s(dir.path()),
        "--out",
        s(&dir.path().join("out")),
        "--vertices",
        "50",
        "--",
        "--shape",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("--shape"), "{}", stderr(&o));
}

#[test]
fn compare_takes_shape_and_creases_and_names_them() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.obj");
    mesh::io::save(&mesh::procedural::icosphere(3).into(), &input).unwrap();
    let compare = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            s(&input),
            "--vertices",
            "160",
            "--samples",
            "2000",
            "--json",
        ];
        args.extend_from_slice(extra);
        json_of(&gng3d(&args))
    };
    let plain = compare(&[]);
    let both = compare(&["--shape", "--creases"]);
    let label = both["gng_variant"].as_str().unwrap();
    assert!(
        label.contains("shape pass") && label.contains("creases"),
        "{label}"
    );
    let plain_label = plain["gng_variant"].as_str().unwrap();
    assert!(
        !plain_label.contains("shape") && !plain_label.contains("creases"),
        "{plain_label}"
    );
    // The shape pass ran: the GNG3D-Q column's triangles changed, QEM's did not.
    let angle = |v: &serde_json::Value, method: &str| {
        v[method]["metrics"]["quality"]["simplified"]["median_min_angle_degrees"]
            .as_f64()
            .unwrap()
    };
    assert_ne!(angle(&plain, "gng"), angle(&both, "gng"));
    assert_eq!(angle(&plain, "qem"), angle(&both, "qem"));
    // `--paper` has no decimation for them to act on: refused by the parser.
    let o = gng3d(&[
        "compare",
        s(&input),
        "--vertices",
        "160",
        "--paper",
        "--shape",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}
