//! What the binary's tests share: running `gng3d` and reading what it printed. Each test file
//! is its own crate and uses a part of it.
#![allow(dead_code)]

use std::process::{Command, Output};

/// Runs the `gng3d` binary with `args` and waits for it.
pub fn gng3d(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(args)
        .output()
        .expect("run gng3d")
}

/// `p` as an argument.
pub fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

/// `o`, after checking that the run succeeded (its stderr otherwise).
pub fn succeeded(o: Output) -> Output {
    assert!(o.status.success(), "{}", stderr(&o));
    o
}

/// The JSON a run printed on stdout; fails the test with its stderr if the run failed.
pub fn json_of(o: &Output) -> serde_json::Value {
    assert!(o.status.success(), "{}", stderr(o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// What the run wrote on stderr.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The cells of one CSV line (RFC 4180: quoted cells may hold commas and doubled quotes).
pub fn csv_cells(line: &str) -> Vec<String> {
    let mut cells = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                cells.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => cells.push(String::new()),
            _ => cells.last_mut().unwrap().push(c),
        }
    }
    cells
}
