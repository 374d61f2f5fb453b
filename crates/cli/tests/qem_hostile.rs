//! Issue 33, QEM rows: the `gng3d` binary on inputs that used to take minutes (a fan around one
//! hub, an unbounded `--threshold`). Inputs are generated, so these need no shared data.

mod common;
use common::{gng3d, s};

/// `--threshold` above the mesh's bounding-box diagonal is refused with exit 1, naming the limit,
/// and nothing is written (`1e30` on a 100k-vertex sphere searched all pairs for 38-53 s); the
/// limit it names is accepted.
#[test]
fn threshold_above_the_diagonal_is_refused_naming_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.obj");
    // 10,242 vertices on the unit sphere: a box of about ±1, diagonal about 3.4641.
    mesh::io::save(&mesh::procedural::icosphere(5).into(), &input).unwrap();
    let out = dir.path().join("out.ply");
    let simplify = |threshold: &str| {
        let flag = format!("--threshold={threshold}");
        gng3d(&[
            "simplify",
            s(&input),
            s(&out),
            "--method",
            "qem",
            "--ratio",
            "0.1",
            &flag,
        ])
    };
    for threshold in ["1e30", "3.5", "1.7976931348623157e308"] {
        let o = simplify(threshold);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{threshold}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.contains("error:")
                && err.contains("pair threshold")
                && err.contains("above the limit 3.46")
                && err.contains("bounding-box diagonal"),
            "{threshold}: {err}"
        );
        assert!(!out.exists(), "{threshold}: an output was written");
    }
    for threshold in ["inf", "-1", "nan"] {
        let o = simplify(threshold);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{threshold}: {err}");
        assert!(
            err.contains("--threshold must be a finite distance >= 0"),
            "{err}"
        );
    }
    // The limit the message names is accepted.
    let o = simplify("0");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&simplify("1e30").stderr).into_owned();
    let limit = err
        .split("above the limit ")
        .nth(1)
        .and_then(|rest| rest.split(',').next())
        .expect("the limit in the message");
    std::fs::remove_file(&out).unwrap();
    let o = simplify(limit);
    assert!(
        o.status.success(),
        "--threshold {limit}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.exists());
}
