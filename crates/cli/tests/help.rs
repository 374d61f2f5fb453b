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
