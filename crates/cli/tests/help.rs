//! The help text quotes the library's policy numbers from the library's constants, so the two
//! cannot drift apart (issue 34: the numbers were written in the README, the help and the code).

use gng3d_core::tuning;
use std::process::Command;

#[test]
fn simplify_help_quotes_the_library_policy_numbers() {
    let out = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["simplify", "--help"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    for (flag, quoted) in [
        (
            "--no-relax",
            format!("at most {} %", tuning::RELAX_MAX_RATIO * 100.0),
        ),
        (
            "--no-deviation-repair",
            format!("at least {} %", tuning::DETAIL_MIN_RATIO * 100.0),
        ),
        (
            "--oversample",
            format!("Default {} with quadric", tuning::DEFAULT_OVERSAMPLE),
        ),
        (
            "--oversample",
            format!("at least {} nodes", tuning::SPLIT_MIN_NODES),
        ),
        (
            "--epochs",
            format!("budget {} × N", tuning::DEFAULT_SIGNALS_PER_NODE),
        ),
        (
            "--detail-rounds",
            format!("Default {} for", tuning::DEFAULT_DETAIL_ROUNDS),
        ),
    ] {
        let at = help.find(flag).unwrap_or_else(|| panic!("{flag} missing"));
        let text = &help[at..];
        let end = text[2..].find("\n  -").map_or(text.len(), |e| e + 2);
        assert!(
            text[..end].contains(&quoted),
            "{flag}: {quoted:?} not in {:?}",
            &text[..end]
        );
    }
}

/// The text result lines say what a user needs in words: GNG3D's stop reason in lowercase
/// (not the Rust variant), and QEM's line the output's topology as GNG3D's does (issue 37).
#[test]
fn result_lines_speak_words_and_give_the_topology() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("sphere.ply");
    mesh::io::save(&mesh::procedural::icosphere(3).into(), &input).unwrap();
    let run = |method: &str| {
        let out = Command::new(env!("CARGO_BIN_EXE_gng3d"))
            .args(["simplify", input.to_str().unwrap()])
            .arg(dir.path().join(format!("{method}.ply")))
            .args(["--method", method, "--vertices", "100"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{method}: {out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    let gng = run("gng");
    assert!(gng.contains("(completed)"), "{gng}");
    assert!(!gng.contains("Completed"), "{gng}");
    let qem = run("qem");
    assert!(
        qem.contains("closed: true, manifold: true, genus: 0"),
        "{qem}"
    );
}
