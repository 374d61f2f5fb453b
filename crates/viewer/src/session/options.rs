//! Start-up options ([`ViewerOptions`]) and what they decide: the validated GNG3D parameters
//! ([`train_params`], window and headless alike), the default vertex target and the training
//! speed.

use crate::engine::TrainParams;
use crate::error::{Result, ViewerError};
use crate::worker::Speed;
use std::path::PathBuf;
/// Default length of a watched run, training and the steps after it: the signal budget is
/// spread over the training's share of this many seconds, so the network visibly grows whatever
/// the mesh size (issue 13: "roughly 10–20 s"), and the final mesh comes about this long after
/// the start ([`crate::worker::run_time_limit`], [`crate::worker::pace_seconds`]).
pub const DEFAULT_WATCH_SECONDS: f64 = 12.0;

/// Start-up options (from the command line).
#[derive(Debug, Clone, Default)]
pub struct ViewerOptions {
    /// Mesh to open (`None`: the built-in procedural model).
    pub path: Option<PathBuf>,
    /// Close the window after this many seconds.
    pub quit_after: Option<f64>,
    /// Save a PNG of the window just before quitting (needs `quit_after`).
    pub screenshot: Option<PathBuf>,
    /// Vertex target for both methods.
    pub target: Option<usize>,
    /// GNG3D time limit, seconds.
    pub time_limit: Option<f64>,
    /// Seed of the training signals.
    pub seed: Option<u64>,
    /// GNG3D signal budget (`None`: the crate's default, `DEFAULT_SIGNALS_PER_NODE` × output vertices).
    pub max_signals: Option<u64>,
    /// λ, signals between insertions (`None`: the crate's automatic choice).
    pub lambda: Option<u32>,
    /// Length of a watched run in seconds (`None`: [`DEFAULT_WATCH_SECONDS`]; 0: as fast as
    /// possible).
    pub watch_seconds: Option<f64>,
    /// Reconstruct and evaluate every this many signals (`None`: every |V| signals, the paper's
    /// protocol; 0: only at the end and on request).
    pub checkpoint_every: Option<u64>,
    /// Start paused instead of training right away.
    pub paused: bool,
    /// Print frame and training statistics to stdout when quitting.
    pub print_stats: bool,
    /// Inner window size in points (default 1600×900).
    pub window_size: Option<[f32; 2]>,
    /// Start with the parameter panel open (`true`) or closed (`false`); `None`: open where
    /// the window is at least 1350 points wide and the plots panel keeps its wanted height
    /// with it ([`crate::app::Panels::for_width`]: 1600×900 yes, 1366×768 no).
    pub controls: Option<bool>,
}

/// The one mapping from user options to GNG3D parameters, shared by the window and headless
/// mode. Rejects values that would panic or silently mean something else (negative or NaN
/// seconds, zero budgets) with an error naming the option.
pub fn train_params(options: &ViewerOptions) -> Result<TrainParams> {
    fn invalid(option: &'static str, problem: impl Into<String>) -> ViewerError {
        ViewerError::InvalidOption {
            option,
            problem: problem.into(),
        }
    }
    let target = options.target.unwrap_or(1000);
    if target < 4 {
        return Err(invalid(
            "--target",
            format!("{target} (at least 4 vertices)"),
        ));
    }
    let gng = gng3d_core::GngOptions {
        target: gng3d_core::GngTarget::Vertices(target),
        time_limit_seconds: options.time_limit,
        max_signals: options.max_signals,
        lambda: options.lambda,
        seed: options
            .seed
            .unwrap_or(gng3d_core::GngParams::default().seed),
        ..gng3d_core::GngOptions::default()
    };
    // The library's one validation of GNG3D options (the CLI uses the same); the option name
    // the user typed is added here, and only the rule of the library's message is kept (no
    // parameter names of the library's, issue 37).
    let flag_and_problem = |e: &gng3d_core::GngError| {
        use gng3d_core::{GngError, GngParameter};
        match e {
            GngError::Parameter {
                parameter,
                value,
                rule,
            } => {
                let flag = match parameter {
                    GngParameter::TimeLimit => "--time-limit",
                    GngParameter::MaxSignals => "--max-signals",
                    GngParameter::Lambda => "--lambda",
                    _ => "--target",
                };
                (flag, format!("{value}: {rule}"))
            }
            other => ("--target", other.to_string()),
        }
    };
    // The input's size is not known yet: the options are checked here, once, and resolved
    // against the mesh when a run starts (`Engine::new`, the one resolution). The parameters
    // the UI shows and edits are the user's choices over the library's defaults.
    gng.validate().map_err(|e| {
        let (flag, problem) = flag_and_problem(&e);
        invalid(flag, problem)
    })?;
    let params = TrainParams {
        lambda: gng.lambda,
        max_signals: gng.max_signals,
        time_limit: gng
            .time_limit_seconds
            .map(std::time::Duration::from_secs_f64),
        seed: gng.seed,
        reconstruction: gng.reconstruction.clone(),
        ..TrainParams::for_target(target)
    };
    if let Some(seconds) = options.watch_seconds
        && !(seconds.is_finite() && seconds >= 0.0)
    {
        return Err(invalid(
            "--watch",
            format!("{seconds} (seconds >= 0; 0 = as fast as possible)"),
        ));
    }
    if let Some(v) = options.quit_after
        && !(v.is_finite() && v >= 0.0)
    {
        return Err(invalid("--quit-after", format!("{v} (seconds >= 0)")));
    }
    // A scripted screenshot that cannot happen is an error before any window opens, not a
    // message in a window that then exits 0.
    if let Some(path) = &options.screenshot {
        let shown = path.display();
        if options.quit_after.is_none() {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: needs --quit-after SECS (it is taken just before quitting)"),
            ));
        }
        if !path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: screenshots are PNG files (give a .png path)"),
            ));
        }
        let dir = path
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(std::path::Path::new("."));
        if !dir.is_dir() {
            return Err(invalid(
                "--screenshot",
                format!("{shown}: the folder {} does not exist", dir.display()),
            ));
        }
    }
    Ok(params)
}

/// The vertex target of a mesh of `vertices` vertices when the user gave none (window and
/// headless alike): a tenth of the vertices, 200 to 10,000.
pub fn default_target(vertices: usize) -> usize {
    (vertices / 10).clamp(200, 10_000).min(vertices.max(4))
}

/// The training speed the options ask for.
pub fn speed_for(watch_seconds: Option<f64>) -> Speed {
    match watch_seconds.unwrap_or(DEFAULT_WATCH_SECONDS) {
        s if s > 0.0 && s.is_finite() => Speed::Paced { seconds: s },
        _ => Speed::Unlimited,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Session;
    use std::time::Duration;

    /// The UI's step switches start as the library's defaults (the deviation repair on):
    /// resolving against an unknown input size must not decide them.
    #[test]
    fn the_step_switches_start_as_the_library_defaults() {
        let params = train_params(&ViewerOptions::default()).unwrap();
        assert_eq!(
            params.reconstruction,
            gng3d_core::ReconstructionParams::default()
        );
        assert!(params.reconstruction.repair_deviations);
    }

    #[test]
    fn bad_options_are_errors_naming_the_option() {
        // Each flag with a value it rejects.
        type Set = fn(&mut ViewerOptions);
        let cases: [(&str, Set); 6] = [
            ("--time-limit", |o| o.time_limit = Some(-1.0)),
            ("--time-limit", |o| o.time_limit = Some(f64::NAN)),
            ("--target", |o| o.target = Some(2)),
            ("--watch", |o| o.watch_seconds = Some(f64::INFINITY)),
            ("--quit-after", |o| o.quit_after = Some(-3.0)),
            ("--max-signals", |o| o.max_signals = Some(0)),
        ];
        for (flag, set) in cases {
            let mut options = ViewerOptions::default();
            set(&mut options);
            let err = train_params(&options).unwrap_err();
            assert!(err.to_string().contains(flag), "{err}");
            assert!(Session::new(options, None).is_err());
        }
        let params = train_params(&ViewerOptions {
            time_limit: Some(2.5),
            target: Some(300),
            seed: Some(9),
            ..Default::default()
        })
        .unwrap();
        assert_eq!(params.time_limit, Some(Duration::from_secs_f64(2.5)));
        assert_eq!((params.target_vertices, params.seed), (300, 9));
        assert_eq!(speed_for(Some(0.0)), Speed::Unlimited);
        assert_eq!(
            speed_for(None),
            Speed::Paced {
                seconds: DEFAULT_WATCH_SECONDS
            }
        );
    }
}
