//! `gng3d metrics --image-error`: the image-space error of a textured model (the fandisk atlas
//! with its checker.png) in `--json` and as PNGs, larger for a coarser simplification, the same
//! through a glTF output (its texture embedded, its texture coordinates flipped), and a missing
//! texture named in the error.

use std::path::{Path, PathBuf};
use std::process::Output;
mod common;
use common::{gng3d, s};

fn ok(o: Output) -> Output {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o
}

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets")
}

fn image_error(original: &Path, simplified: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "metrics",
        s(original),
        s(simplified),
        "--samples",
        "2000",
        "--image-error",
        "--json",
    ];
    args.extend_from_slice(extra);
    let o = ok(gng3d(&args));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // The rest of the report is still there.
    assert!(json["hausdorff"]["max"].is_number(), "{json}");
    json["image_error"].clone()
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn image_error_of_a_textured_model() {
    let dir = tempfile::tempdir().unwrap();
    let original = assets().join("fandisk_atlas.obj");
    let simplified = |ratio: &str, name: &str| {
        let out = dir.path().join(name);
        ok(gng3d(&[
            "simplify",
            s(&original),
            s(&out),
            "--method",
            "qem",
            "--ratio",
            ratio,
        ]));
        out
    };
    let (q10, q50) = (simplified("0.1", "q10.obj"), simplified("0.5", "q50.obj"));
    let pngs = dir.path().join("png");
    let e10 = image_error(&original, &q10, &["--image-out", s(&pngs)]);
    let e50 = image_error(&original, &q50, &["--image-size", "128"]);
    for (e, size) in [(&e10, 256), (&e50, 128)] {
        assert_eq!(e["shading"], "texture", "{e}");
        assert!(
            e["texture"].as_str().unwrap().ends_with("checker.png"),
            "{e}"
        );
        assert_eq!(e["size"], size);
        assert_eq!(e["views"].as_array().unwrap().len(), 14);
        let o = &e["overall"];
        assert!(f(&o["pixels"]) > 0.0);
        assert!(f(&o["rmse"]) > 0.0 && f(&o["rmse"]) < 0.5, "{o}");
        assert!(f(&o["mean_abs"]) <= f(&o["rmse"]), "{o}");
        assert!(
            (f(&o["psnr_db"]) + 20.0 * f(&o["rmse"]).log10()).abs() < 1e-9,
            "{o}"
        );
        for share in ["over_threshold", "coverage_mismatch"] {
            assert!((0.0..=1.0).contains(&f(&o[share])), "{o}");
        }
        assert!(f(&e["seconds"]) > 0.0);
    }
    // A coarser simplification looks worse.
    assert!(
        f(&e10["overall"]["rmse"]) > f(&e50["overall"]["rmse"]),
        "10 %: {}, 50 %: {}",
        e10["overall"],
        e50["overall"]
    );
    // One PNG per view, three panels side by side.
    let mut files: Vec<_> = std::fs::read_dir(&pngs)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert_eq!(files.len(), 14, "{files:?}");
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        assert_eq!(&bytes[1..4], b"PNG", "{}", file.display());
        // IHDR: width and height, big-endian, at bytes 16 and 20.
        let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
        assert_eq!((word(16), word(20)), (3 * 256, 256), "{}", file.display());
    }

    // The same simplification written as GLB: its texture embedded and its texture coordinates
    // in glTF's convention (v = 0 at the top); the picture is the same.
    let glb = simplified("0.5", "q50.glb");
    let g50 = image_error(&original, &glb, &["--image-size", "128"]);
    assert_eq!(
        g50["texture"], e50["texture"],
        "the original's texture is named"
    );
    assert!(
        (f(&g50["overall"]["rmse"]) - f(&e50["overall"]["rmse"])).abs() < 2e-3,
        "glb {} vs obj {}",
        g50["overall"],
        e50["overall"]
    );

    // Identical meshes: no error, an infinite PSNR (null in JSON).
    let same = image_error(&original, &original, &[]);
    assert_eq!(f(&same["overall"]["rmse"]), 0.0, "{same}");
    assert!(same["overall"]["psnr_db"].is_null(), "{same}");

    // Text output.
    let o = ok(gng3d(&[
        "metrics",
        s(&original),
        s(&q10),
        "--samples",
        "2000",
        "--image-error",
    ]));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("image error           14 views of 256² px"),
        "{text}"
    );
    assert!(text.contains("PSNR"), "{text}");
}

#[test]
fn a_missing_texture_or_a_bad_option_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    // The model and its material library without the image they name.
    for name in ["fandisk_atlas.obj", "fandisk_atlas.mtl"] {
        std::fs::copy(assets().join(name), dir.path().join(name)).unwrap();
    }
    let model = dir.path().join("fandisk_atlas.obj");
    let o = gng3d(&["metrics", s(&model), s(&model), "--image-error"]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("checker.png"), "{err}");
    // Without --image-error the texture is not needed.
    ok(gng3d(&[
        "metrics",
        s(&model),
        s(&model),
        "--samples",
        "500",
    ]));

    let original = assets().join("knight_colors.ply");
    let o = gng3d(&[
        "metrics",
        s(&original),
        s(&original),
        "--image-error",
        "--image-size",
        "8",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--image-size"));
    let o = gng3d(&["metrics", s(&original), s(&original), "--image-size", "64"]);
    assert!(!o.status.success(), "--image-size needs --image-error");
    // Vertex colours: the knight's shading.
    let e = image_error(&original, &original, &["--image-size", "64"]);
    assert_eq!(e["shading"], "colors", "{e}");
    assert!(e["texture"].is_null());
}

/// `compare --image-error` on the textured fandisk at 10 %: each method's output rendered with
/// the original's texture against the original, in the table, in `--json` and in compare.json,
/// with one folder of PNGs per method; a bad option names its flag before any work.
#[test]
fn compare_reports_each_methods_image_error() {
    let dir = tempfile::tempdir().unwrap();
    let original = assets().join("fandisk_atlas.obj");
    let (out, pngs) = (dir.path().join("out"), dir.path().join("png"));
    let compare = |extra: &[&str]| {
        let mut args = vec![
            "compare",
            s(&original),
            "--vertices",
            "648",
            "--samples",
            "2000",
            "--image-error",
            "--image-size",
            "64",
        ];
        args.extend_from_slice(extra);
        ok(gng3d(&args))
    };
    let o = compare(&["--json", "--out", s(&out), "--image-out", s(&pngs)]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    // The texture is used now: the warning says what else --out leaves out.
    assert!(
        stderr.contains("materials used for the image error's texture only"),
        "{stderr}"
    );
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let written: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("compare.json")).unwrap()).unwrap();
    assert_eq!(json, written, "compare.json is what --json prints");
    for method in ["qem", "gng"] {
        let e = &json[method]["metrics"]["image_error"];
        assert_eq!(e["shading"], "texture", "{method}: {e}");
        assert!(
            e["texture"].as_str().unwrap().ends_with("checker.png"),
            "{e}"
        );
        assert_eq!(e["size"], 64);
        assert_eq!(e["views"].as_array().unwrap().len(), 14);
        let o = &e["overall"];
        for key in [
            "rmse",
            "mean_abs",
            "psnr_db",
            "over_threshold",
            "coverage_mismatch",
        ] {
            assert!(f(&o[key]).is_finite(), "{method} {key}: {o}");
        }
        assert!(
            f(&o["rmse"]) > 0.0 && f(&o["psnr_db"]) > 0.0,
            "{method}: {o}"
        );
        assert!(
            (f(&o["psnr_db"]) + 20.0 * f(&o["rmse"]).log10()).abs() < 1e-9,
            "{o}"
        );
        for share in ["over_threshold", "coverage_mismatch"] {
            assert!((0.0..=1.0).contains(&f(&o[share])), "{method} {share}: {o}");
        }
        // The rest of the method's report is still there, attributes included.
        assert!(json[method]["metrics"]["hausdorff"]["max"].is_number());
        assert!(json[method]["metrics"]["attributes"]["backward"]["uv0"].is_object());
        // One PNG per view, three panels of 64 pixels side by side.
        let folder = pngs.join(method);
        let files: Vec<_> = std::fs::read_dir(&folder)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        assert_eq!(files.len(), 14, "{files:?}");
        let bytes = std::fs::read(folder.join("view+x.png")).unwrap();
        let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
        assert_eq!((word(16), word(20)), (3 * 64, 64));
    }

    // The text table has the four image rows with both methods' figures.
    let o = compare(&[]);
    let text = String::from_utf8_lossy(&o.stdout);
    for row in [
        "image RMSE (RGB 0-1)",
        "image PSNR",
        "image pixels off by > 0.1",
        "image silhouette mismatch",
    ] {
        let line = text
            .lines()
            .find(|l| l.starts_with(row))
            .unwrap_or_else(|| panic!("no {row:?} row in {text}"));
        assert!(
            line.ends_with("QEM") || line.ends_with("GNG3D") || line.ends_with("tie"),
            "{line}"
        );
    }
    assert!(
        text.contains("14 views of 64² px") && text.contains("checker.png"),
        "{text}"
    );

    // Checked before loading or simplifying anything, the flag named.
    for (flag, value) in [("--image-size", "8"), ("--image-threshold", "2")] {
        let o = gng3d(&[
            "compare",
            s(&original),
            "--vertices",
            "648",
            "--image-error",
            flag,
            value,
        ]);
        assert_eq!(o.status.code(), Some(1), "{flag} {value}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(&format!("{flag}: ")), "{err}");
        assert!(!err.contains("warning"), "nothing loaded: {err}");
    }
    let o = gng3d(&[
        "compare",
        s(&original),
        "--vertices",
        "648",
        "--image-size",
        "64",
    ]);
    assert!(!o.status.success(), "--image-size needs --image-error");
}
