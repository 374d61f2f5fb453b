//! User-facing GNG3D options and the one place that turns them into [`GngParams`].
//!
//! Front ends (the `gng3d` CLI's `simplify`, `compare` and `reproduce`, the viewer, headless
//! runs) collect what the user typed into a [`GngOptions`] and call [`GngOptions::resolve`]
//! against the input mesh. `resolve` validates every knob up front — NaN, negative or zero time
//! limits, ratios outside (0, 1], zero λ, zero budgets, out-of-range targets — and returns one
//! [`GngError`] naming the offending option, before any training starts. Fields not exposed to
//! users keep the [`GngParams`] defaults.
//! The crate's front page has the whole story with an example.

mod oversample;

pub use oversample::{DEFAULT_DETAIL_ROUNDS, DETAIL_MIN_RATIO, RELAX_MAX_RATIO};

use crate::{GngError, GngParameter, GngParams, ReconstructionParams, SignalSource};
use mesh::TriMesh;
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};
use std::time::Duration;

/// How the user states the output size: always in vertices (GNG nodes). Note that the `qem`
/// crate's `Target::Ratio` is a share of the input's *faces*; for a closed mesh that is about
/// the same share of vertices, but not for open or unwelded ones.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum GngTarget {
    /// Exactly this many output vertices (GNG nodes).
    Vertices(usize),
    /// This share of the input's referenced vertices, in (0, 1], rounded to the nearest count.
    #[cfg_attr(feature = "serde", serde(alias = "Ratio"))]
    VertexRatio(f64),
}

impl GngTarget {
    /// The output vertex count this target asks for on `input`: `Vertices(n)` is n,
    /// `VertexRatio(r)` is r × the input's referenced vertices, rounded to the nearest count.
    /// Every front end turns a ratio into a vertex count here, for GNG3D-Q, the paper's GNG3D
    /// and QEM alike (`gng3d simplify --ratio`, the Python package's `ratio=`), so one ratio
    /// gives one output size whatever the method. A ratio outside (0, 1] is an error naming it.
    pub fn vertex_count(&self, input: &TriMesh) -> Result<usize, GngError> {
        self.vertex_count_of(referenced_vertices(input))
    }

    /// [`Self::vertex_count`] on an input with `available` referenced vertices.
    fn vertex_count_of(&self, available: usize) -> Result<usize, GngError> {
        match *self {
            GngTarget::Vertices(n) => Ok(n),
            GngTarget::VertexRatio(r) if r > 0.0 && r <= 1.0 => {
                Ok(((available as f64) * r).round() as usize)
            }
            GngTarget::VertexRatio(r) => {
                Err(bad(GngParameter::TargetRatio, r, "must be in (0, 1]"))
            }
        }
    }
}

impl Default for GngTarget {
    fn default() -> Self {
        GngTarget::Vertices(GngParams::default().target_vertices)
    }
}

/// Every GNG3D knob a front end exposes, in user units (seconds as `f64`, targets as counts or
/// ratios). `Default` gives the library defaults; set the public fields, then [`Self::resolve`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct GngOptions {
    /// Output size.
    pub target: GngTarget,
    /// Maximum running time in seconds (finite, > 0): training and every step after it
    /// ([`GngParams::time_limit`]); `None`: no limit.
    pub time_limit_seconds: Option<f64>,
    /// Seed of the random generator (equal seeds give identical results).
    pub seed: u64,
    /// Signal budget in signals; `None`: the library default. Exclusive with `epochs`.
    pub max_signals: Option<u64>,
    /// Signal budget in epochs of |V| signals (the paper's protocol uses 30); > 0. Exclusive with
    /// `max_signals`.
    pub epochs: Option<f64>,
    /// λ, signals between node insertions (≥ 1); `None`: chosen from the budget.
    pub lambda: Option<u32>,
    /// ε_b, winner step in [0, 1]; `None`: the library default (0.05).
    pub eps_winner: Option<f32>,
    /// ε_n, neighbour step in [0, 1]; `None`: the library default (0.0006).
    pub eps_neighbour: Option<f32>,
    /// Where training signals come from.
    pub signal_source: SignalSource,
    /// Phase-2 (reconstruction) options.
    pub reconstruction: ReconstructionParams,
    /// Oversampling factor k in [1, 4]: train `ceil(k·N)` nodes (at most the input's vertices
    /// with vertex signals), reconstruct, then decimate error first to N
    /// ([`GngParams::network_vertices`]). `Some(1.0)` turns it off. `None` (the default) takes
    /// [`GngOptions::default_oversample`] of `reconstruction.placement` when the options are
    /// resolved: 1.5 for GNG3D-Q, 1 (off) for the paper's placement, whatever the order in
    /// which the fields were set. The library, the CLI and the viewer share this default.
    pub oversample: Option<f64>,
    /// Rounds of detail nodes in oversampled runs (reconstruction option (g), at most 8);
    /// `None`: [`GngOptions::resolve`]'s rule (3 rounds for outputs of at least 5 % of the
    /// input's vertices, 0 below). Runs that are not oversampled have none (the nodes they add
    /// would break the exact count).
    #[cfg_attr(feature = "serde", serde(default))]
    pub detail_rounds: Option<usize>,
    /// Most threads the run uses, the caller's included (≥ 1; [`GngParams::threads`]); `None`:
    /// the machine's available parallelism, at most 4. `Some(1)` starts no thread. The output
    /// is the same for any count.
    #[cfg_attr(
        feature = "serde",
        serde(default, skip_serializing_if = "Option::is_none")
    )]
    pub threads: Option<usize>,
}

/// The oversampling factor of GNG3D-Q in the front ends (`gng3d simplify --method gng`,
/// `compare`, the survey's GNG3D-Q column, the viewer): 1.5. Over the survey of the shared
/// meshes at 10/25/50 % (45 runs, QEM at the same vertex count, 200k samples; docs/results.md)
/// k = 1 → 1.5 (with the facade's QEM decimator and its edge-length term) took the median mean
/// surface distance ratio to QEM from 1.53 to 1.18 and the Hausdorff ratio from 2.75 to 2.30,
/// with E_avg, E_max and triangle quality won in 42, 43 and 42 of 45 runs. k = 1.25 gave less
/// (spot 10 %: 0.95 vs 0.90× QEM's mean distance); k = 2 (capped at 0.8 |V|) was 4-11 % closer
/// at 10-25 % but lost E_avg on armadillo and cow (docs/notes/gngq.md).
pub const DEFAULT_OVERSAMPLE: f64 = 1.5;

/// Most rounds of detail nodes a user may ask for.
pub const MAX_DETAIL_ROUNDS: usize = 8;

/// Largest signal budget a user may ask for (`max_signals`, or `epochs` × the input's
/// vertices): 10¹⁰ signals, about an hour of training at the 3-5 M signals/s measured here.
/// Above it a typo (`--epochs 1e12`) would train for days or wrap the product to nothing.
pub const MAX_SIGNALS: u64 = 10_000_000_000;

/// With surface or curvature signals a network may have more nodes than the input has
/// vertices, up to this many times them: `--vertices 18446744073709551615 --signals surface`
/// panicked on a capacity overflow and 4·10⁹ aborted on a 72 GB allocation.
pub const MAX_SURFACE_NODES_PER_VERTEX: usize = 16;

impl Default for GngOptions {
    fn default() -> Self {
        let p = GngParams::default();
        GngOptions {
            target: GngTarget::default(),
            time_limit_seconds: None,
            seed: p.seed,
            max_signals: None,
            epochs: None,
            lambda: None,
            eps_winner: None,
            eps_neighbour: None,
            signal_source: p.signal_source,
            reconstruction: p.reconstruction,
            oversample: None,
            detail_rounds: None,
            threads: None,
        }
    }
}

/// An out-of-range option and the rule it breaks.
fn bad(parameter: GngParameter, value: f64, rule: &'static str) -> GngError {
    GngError::Parameter {
        parameter,
        value,
        rule,
    }
}

/// Number of vertices referenced by at least one triangle.
fn referenced_vertices(mesh: &TriMesh) -> usize {
    let mut used = vec![false; mesh.positions.len()];
    for &v in mesh.triangles.iter().flatten() {
        if let Some(u) = used.get_mut(v as usize) {
            *u = true;
        }
    }
    used.iter().filter(|&&u| u).count()
}

impl GngOptions {
    /// Options with the given target and defaults elsewhere.
    pub fn for_target(target: GngTarget) -> GngOptions {
        GngOptions {
            target,
            ..GngOptions::default()
        }
    }

    /// The published GNG3D (Álvarez et al. 2007) for this target: a budget of 30 epochs and
    /// the paper's reconstruction ([`ReconstructionParams::paper`]: vertices at the trained
    /// nodes, no flips, refit, relaxation or repair), so no oversampling either; it resolves to
    /// [`GngParams::paper`] of the target. Other fields are the defaults.
    pub fn paper(target: GngTarget) -> GngOptions {
        GngOptions {
            epochs: Some(crate::params::PAPER_EPOCHS),
            reconstruction: ReconstructionParams::paper(),
            ..GngOptions::for_target(target)
        }
    }

    /// The oversampling factor a front end with a decimator uses when the user gave none:
    /// 1.5 for GNG3D-Q ([`crate::Placement::Quadric`]), 1 (off) for the
    /// paper's node placement and for projection, so that `--placement node` stays the paper.
    pub fn default_oversample(placement: crate::Placement) -> f64 {
        if placement == crate::Placement::Quadric {
            DEFAULT_OVERSAMPLE
        } else {
            1.0
        }
    }

    /// The oversampling factor these options resolve to: `oversample`, or when it is `None`
    /// [`GngOptions::default_oversample`] of the placement.
    pub fn oversample_factor(&self) -> f64 {
        self.oversample
            .unwrap_or_else(|| Self::default_oversample(self.reconstruction.placement))
    }

    /// Checks every option without a mesh (what can be checked before loading the input).
    pub fn validate(&self) -> Result<(), GngError> {
        if let GngTarget::VertexRatio(r) = self.target
            && !(r > 0.0 && r <= 1.0)
        {
            return Err(bad(GngParameter::TargetRatio, r, "must be in (0, 1]"));
        }
        if let Some(s) = self.time_limit_seconds
            && (!(s > 0.0 && s.is_finite()) || Duration::try_from_secs_f64(s).is_err())
        {
            return Err(bad(
                GngParameter::TimeLimit,
                s,
                "must be a finite number of seconds > 0",
            ));
        }
        if self.max_signals == Some(0) {
            return Err(bad(
                GngParameter::MaxSignals,
                0.0,
                "must be at least 1 signal",
            ));
        }
        if let Some(m) = self.max_signals
            && m > MAX_SIGNALS
        {
            return Err(bad(
                GngParameter::MaxSignals,
                m as f64,
                "must be at most 1e10 signals",
            ));
        }
        if let Some(e) = self.epochs
            && !(e > 0.0 && e.is_finite())
        {
            return Err(bad(GngParameter::Epochs, e, "must be a finite number > 0"));
        }
        if self.epochs.is_some() && self.max_signals.is_some() {
            return Err(bad(
                GngParameter::MaxSignals,
                self.max_signals.unwrap_or(0) as f64,
                "give epochs or max_signals, not both",
            ));
        }
        if self.lambda == Some(0) {
            return Err(bad(
                GngParameter::Lambda,
                0.0,
                "signals between insertions, must be >= 1",
            ));
        }
        if let Some(k) = self.oversample
            && !(1.0..=4.0).contains(&k)
        {
            return Err(bad(GngParameter::Oversample, k, "must be in [1, 4]"));
        }
        if let Some(r) = self.detail_rounds
            && r > MAX_DETAIL_ROUNDS
        {
            return Err(bad(
                GngParameter::DetailRounds,
                r as f64,
                "must be at most 8",
            ));
        }
        for (parameter, eps) in [
            (GngParameter::EpsWinner, self.eps_winner),
            (GngParameter::EpsNeighbour, self.eps_neighbour),
        ] {
            if let Some(e) = eps
                && !((0.0..=1.0).contains(&e))
            {
                return Err(bad(parameter, e as f64, "must be in [0, 1]"));
            }
        }
        if self.threads == Some(0) {
            return Err(bad(GngParameter::Threads, 0.0, "must be at least 1"));
        }
        Ok(())
    }

    /// The output vertex count these options ask for on `input`.
    pub fn target_vertices(&self, input: &TriMesh) -> Result<usize, GngError> {
        self.target_vertices_of(referenced_vertices(input))
    }

    /// The output vertex count these options ask for on an input with `available` referenced
    /// vertices.
    fn target_vertices_of(&self, available: usize) -> Result<usize, GngError> {
        self.validate()?;
        let n = self.target.vertex_count_of(available)?;
        let vertex_bound = self.signal_source == SignalSource::Vertices;
        if n < 3 || (vertex_bound && n > available) {
            return Err(GngError::Target {
                target: n,
                available,
            });
        }
        if !vertex_bound && n > available.saturating_mul(MAX_SURFACE_NODES_PER_VERTEX) {
            return Err(bad(
                GngParameter::TargetVertices,
                n as f64,
                "with surface signals at most 16 times the input's vertices",
            ));
        }
        if let Some(e) = self.epochs
            && e * available as f64 > MAX_SIGNALS as f64
        {
            return Err(bad(
                GngParameter::Epochs,
                e,
                "the signal budget, epochs x vertices, must be at most 1e10 signals",
            ));
        }
        Ok(n)
    }

    /// Validates every option against `input` and returns the algorithm parameters.
    ///
    /// Errors name the option (`GngError::Parameter`) or the target (`GngError::Target`); the
    /// trainer's own checks (mesh validity, distinct vertices) still run in `Trainer::new`.
    pub fn resolve(&self, input: &TriMesh) -> Result<GngParams, GngError> {
        self.resolve_for_vertex_count(referenced_vertices(input))
    }

    /// [`Self::resolve`] for a front end that knows only the input's referenced vertex count
    /// (`available`, which ratios and epochs are taken of), e.g. to check options before the
    /// mesh is loaded; `Trainer::new` still checks the mesh itself.
    pub fn resolve_for_vertex_count(&self, available: usize) -> Result<GngParams, GngError> {
        let target_vertices = self.target_vertices_of(available)?;
        let defaults = GngParams::default();
        let max_signals = match (self.max_signals, self.epochs) {
            (Some(s), _) => Some(s),
            (None, Some(e)) => Some(((e * available as f64).round() as u64).max(1)),
            (None, None) => defaults.max_signals,
        };
        let mut params = GngParams {
            target_vertices,
            lambda: self.lambda,
            eps_winner: self.eps_winner.unwrap_or(defaults.eps_winner),
            eps_neighbour: self.eps_neighbour.unwrap_or(defaults.eps_neighbour),
            max_signals,
            time_limit: self.time_limit_seconds.map(Duration::from_secs_f64),
            seed: self.seed,
            signal_source: self.signal_source,
            threads: self.threads,
            reconstruction: self.reconstruction.clone(),
            ..defaults
        }
        .oversampled(self.oversample_factor(), available);
        if let Some(rounds) = self.detail_rounds
            && params.decimates()
        {
            params.reconstruction.detail_rounds = rounds;
        }
        Ok(params)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere() -> TriMesh {
        mesh::procedural::icosphere(2) // 162 vertices
    }

    #[test]
    fn defaults_resolve_to_library_defaults() {
        let opts = GngOptions {
            oversample: Some(1.0),
            ..GngOptions::for_target(GngTarget::Vertices(50))
        };
        let p = opts.resolve(&sphere()).unwrap();
        assert_eq!(p, GngParams::for_target(50));
    }

    #[test]
    fn ratio_and_epochs_follow_the_input() {
        let opts = GngOptions {
            target: GngTarget::VertexRatio(0.5),
            epochs: Some(30.0),
            seed: 9,
            lambda: Some(7),
            time_limit_seconds: Some(0.25),
            ..GngOptions::default()
        };
        let p = opts.resolve(&sphere()).unwrap();
        assert_eq!(p.target_vertices, 81);
        assert_eq!(p.max_signals, Some(30 * 162));
        assert_eq!(p.seed, 9);
        assert_eq!(p.lambda, Some(7));
        assert_eq!(p.time_limit, Some(Duration::from_millis(250)));
    }

    #[test]
    fn bad_options_are_rejected_with_one_message_naming_them() {
        let m = sphere();
        let cases: Vec<(GngOptions, &str)> = vec![
            (
                GngOptions {
                    time_limit_seconds: Some(-1.0),
                    ..Default::default()
                },
                "time limit",
            ),
            (
                GngOptions {
                    time_limit_seconds: Some(f64::NAN),
                    ..Default::default()
                },
                "time limit",
            ),
            (
                GngOptions {
                    time_limit_seconds: Some(0.0),
                    ..Default::default()
                },
                "time limit",
            ),
            (
                GngOptions {
                    time_limit_seconds: Some(1e300),
                    ..Default::default()
                },
                "time limit",
            ),
            (
                GngOptions::for_target(GngTarget::VertexRatio(0.0)),
                "target ratio",
            ),
            (
                GngOptions::for_target(GngTarget::VertexRatio(f64::NAN)),
                "target ratio",
            ),
            (
                GngOptions::for_target(GngTarget::VertexRatio(1.5)),
                "target ratio",
            ),
            (
                GngOptions {
                    lambda: Some(0),
                    ..Default::default()
                },
                "lambda",
            ),
            (
                GngOptions {
                    max_signals: Some(0),
                    ..Default::default()
                },
                "signal budget",
            ),
            (
                GngOptions {
                    epochs: Some(-3.0),
                    ..Default::default()
                },
                "epochs",
            ),
            (
                GngOptions {
                    eps_winner: Some(2.0),
                    ..Default::default()
                },
                "eps_winner",
            ),
            (GngOptions::for_target(GngTarget::Vertices(2)), "target"),
            (GngOptions::for_target(GngTarget::Vertices(163)), "162"),
        ];
        for (opts, needle) in cases {
            let msg = opts.resolve(&m).unwrap_err().to_string();
            assert!(msg.contains(needle), "{opts:?}: {msg}");
            // One statement, not the same text twice.
            let half = &msg[..msg.len() / 2];
            assert!(!msg[msg.len() / 2..].contains(half), "doubled: {msg}");
        }
    }

    /// Absurd budgets and targets are refused up front with the limit named (a typo must not
    /// train for days, wrap to nothing or abort on an allocation).
    #[test]
    fn absurd_budgets_and_surface_targets_are_refused_with_the_limit() {
        let m = sphere(); // 162 vertices
        let err = |o: GngOptions| o.resolve(&m).unwrap_err().to_string();
        let e = err(GngOptions {
            epochs: Some(1e12),
            ..GngOptions::for_target(GngTarget::Vertices(50))
        });
        assert!(e.contains("epochs") && e.contains("1e10"), "{e}");
        let e = err(GngOptions {
            max_signals: Some(MAX_SIGNALS + 1),
            ..GngOptions::for_target(GngTarget::Vertices(50))
        });
        assert!(e.contains("signal budget") && e.contains("1e10"), "{e}");
        for n in [usize::MAX, 4_000_000_000, 162 * 16 + 1] {
            let e = err(GngOptions {
                signal_source: SignalSource::Surface,
                ..GngOptions::for_target(GngTarget::Vertices(n))
            });
            assert!(e.contains("16 times"), "{n}: {e}");
        }
        // At the limits they resolve.
        let ok = GngOptions {
            signal_source: SignalSource::Surface,
            max_signals: Some(MAX_SIGNALS),
            ..GngOptions::for_target(GngTarget::Vertices(162 * 16))
        };
        assert_eq!(ok.resolve(&m).unwrap().target_vertices, 162 * 16);
    }

    #[test]
    fn resolved_params_train() {
        let opts = GngOptions::for_target(GngTarget::VertexRatio(0.5));
        let m = sphere();
        let r = crate::simplify(&m.clone().into(), &opts).unwrap();
        assert_eq!(r.mesh.vertex_count(), 81);
    }
}
