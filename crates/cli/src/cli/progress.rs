//! Progress on stderr for runs that can last more than a second: shown only when stderr is a
//! terminal and the run prints no `--json` (so logs and pipes get no control characters), and
//! ticking on its own, so a long step that reports nothing still shows time passing.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::Duration;

/// Whether progress is drawn: stderr is a terminal and the output is not JSON.
pub(crate) fn shown(json: bool) -> bool {
    !json && std::io::stderr().is_terminal()
}

/// A bar of `len` units drawn with `template` (hidden unless [`shown`]), ticking every 100 ms.
pub(crate) fn bar(len: u64, template: &str, json: bool) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(
        Some(len),
        if shown(json) {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        },
    );
    bar.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.enable_steady_tick(Duration::from_millis(100));
    bar
}

/// A spinner with the elapsed time and a message naming what runs now.
pub(crate) fn spinner(json: bool) -> ProgressBar {
    bar(0, "{spinner} [{elapsed_precise}] {msg}", json)
}
