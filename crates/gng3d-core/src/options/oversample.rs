//! The oversampling rule of GNG3D-Q ([`GngParams::oversampled`]): how large the network is
//! trained for an output count, and the reconstruction's options that follow from it and from
//! the output's share of the input (cell splits, detail rounds, relaxation, deviation repair,
//! two halves).

use crate::{GngParams, SignalSource};

/// Rounds of detail nodes (reconstruction option (g)) in oversampled runs, where the rule of
/// [`crate::GngOptions::resolve`] applies. On 16 survey runs (10-50 %, 200k samples) 0 / 1 / 2 / 3 /
/// 4 rounds gave a median Hausdorff ratio to QEM of 4.12 / 3.12 (vertices only) / 1.61 / 1.74 /
/// 1.34 and a median mean-distance ratio of 1.28 / 1.22 / 1.15 / 1.12 / 1.09; each round costs
/// about one more phase 2 (docs/notes/gngq.md, "Detail nodes").
pub const DEFAULT_DETAIL_ROUNDS: usize = 3;

/// Outputs smaller than this share of the input's vertices get no detail rounds by default:
/// there the network's Hausdorff max is already at QEM's (igea at 1 %: 1.04×, armadillo at 1 %:
/// 1.08×, gargoyle-10k at 2 %: 0.83×) while a round costs as much as the rest of phase 2 (igea
/// at 1 %: +0.19 s on a 0.4 s run).
pub const DETAIL_MIN_RATIO: f64 = 0.05;

/// Outputs larger than this share of the input's vertices are not relaxed after the decimation
/// ([`crate::ReconstructionParams::relax`] is turned off by [`crate::GngOptions::resolve`]): there
/// E_avg is won without it and the step only costs surface distance. Survey runs (14 meshes,
/// GNG3D-Q / QEM medians, without → with the relaxation): at 50 % E_avg wins 13 → 13 of 14,
/// mean distance 1.153 → 1.254; at 25 % 13 → 13 of 14 (armadillo's margin 0.986 → 0.916), mean
/// distance 1.000 → 1.033; at 10 % it is what wins the cow and the armadillo (1.034 / 1.023 →
/// 0.995 / 0.978× QEM's) for 2 % more mean distance.
pub const RELAX_MAX_RATIO: f64 = 0.3;

impl GngParams {
    /// These parameters without oversampling: the network has `target_vertices` nodes and its
    /// mesh is the output (no cell splits or detail rounds, which add vertices).
    pub(crate) fn not_oversampled(self) -> GngParams {
        let mut reconstruction = self.reconstruction;
        reconstruction.split_bad_cells = false;
        reconstruction.detail_rounds = 0;
        GngParams {
            network_vertices: None,
            reconstruction,
            ..self
        }
    }

    /// These parameters with the network oversampled by `factor` (≥ 1) for an input of
    /// `available` referenced vertices: [`GngParams::network_vertices`] becomes
    /// `ceil(factor · N)` (at most `available` with vertex signals, which cannot place more nodes
    /// than there are distinct vertices) for the output count N = `target_vertices`. A factor
    /// of 1, or no room above N, leaves the network at N. The one rule for every front end
    /// ([`GngOptions::resolve`]). It sets [`crate::ReconstructionParams::split_bad_cells`] and
    /// [`GngParams::split_training`] (on when oversampled, off otherwise), the detail rounds, the relaxation and the deviation repair by the output's share of
    /// the input.
    pub(crate) fn oversampled(self, factor: f64, available: usize) -> GngParams {
        let output_vertices = self.target_vertices;
        let wanted = (output_vertices as f64 * factor.max(1.0)).ceil() as usize;
        let network = if self.signal_source == SignalSource::Vertices {
            wanted.min(available)
        } else {
            wanted
        };
        let network_vertices = (network > output_vertices).then_some(network);
        let decimates = network_vertices.is_some();
        // The decimation restores the count, so the reconstruction may add nodes to repair
        // the topology (option (f)); without it every node must stay a vertex.
        let mut reconstruction = self.reconstruction.clone();
        reconstruction.split_bad_cells = decimates;
        // And add detail nodes where the mesh stays far from the original (option (g)), for
        // outputs of at least DETAIL_MIN_RATIO of the input.
        let detailed = output_vertices as f64 >= DETAIL_MIN_RATIO * available as f64;
        reconstruction.detail_rounds = if decimates && detailed {
            DEFAULT_DETAIL_ROUNDS
        } else {
            0
        };
        // And relax the decimated vertices (option (h)) for outputs of at most RELAX_MAX_RATIO
        // (without a decimation the option is left as it is: it does nothing there).
        if decimates {
            reconstruction.relax &= output_vertices as f64 <= RELAX_MAX_RATIO * available as f64;
            // And repair the decimated mesh's deviations (option (i)) where detail nodes are
            // added, for the same reason: below DETAIL_MIN_RATIO the Hausdorff max is already
            // at QEM's, and the repair's queries cost igea at 1 % 0.1 s of a 0.25 s run.
            reconstruction.repair_deviations &= detailed;
        }
        // And train large pieces as two halves on two threads: GNG3D-Q's placement, flips and
        // refit take the shape from the original, not from where each node converged, and on
        // 80 runs (9 meshes at 1-50 %, two seeds) halves gave the same distances as one network
        // (docs/notes/gng.md, "Two halves").
        let split_training = decimates;
        GngParams {
            network_vertices,
            reconstruction,
            split_training,
            ..self
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::options::{DEFAULT_OVERSAMPLE, MAX_DETAIL_ROUNDS};
    use crate::{GngOptions, GngTarget, ReconstructionParams};
    use mesh::TriMesh;

    fn sphere() -> TriMesh {
        mesh::procedural::icosphere(2) // 162 vertices
    }

    #[test]
    fn oversampling_trains_k_times_the_target_and_decimates_to_it() {
        let m = sphere(); // 162 vertices
        let at = |n: usize, k: f64| {
            let p = GngOptions {
                oversample: Some(k),
                ..GngOptions::for_target(GngTarget::Vertices(n))
            }
            .resolve(&m)
            .unwrap();
            (p.target_vertices, p.network_vertices)
        };
        assert_eq!(at(50, 1.0), (50, None));
        assert_eq!(at(50, 1.5), (50, Some(75)));
        assert_eq!(at(51, 1.5), (51, Some(77))); // ceil(76.5)
        // Vertex signals cannot place more nodes than there are vertices.
        assert_eq!(at(150, 1.5), (150, Some(162)));
        assert_eq!(at(162, 2.0), (162, None));
        // Surface signals can.
        let surface = GngOptions {
            oversample: Some(1.5),
            signal_source: SignalSource::Surface,
            ..GngOptions::for_target(GngTarget::Vertices(150))
        };
        let p = surface.resolve(&m).unwrap();
        assert_eq!((p.target_vertices, p.network_vertices), (150, Some(225)));
        // Applying the rule twice changes nothing.
        assert_eq!(p.clone().oversampled(1.5, 162), p);
        for k in [0.5, 4.5, f64::NAN, f64::INFINITY] {
            let e = GngOptions {
                oversample: Some(k),
                ..GngOptions::default()
            }
            .validate()
            .unwrap_err()
            .to_string();
            assert!(e.contains("oversample"), "{k}: {e}");
        }
        assert_eq!(
            GngOptions::default_oversample(crate::Placement::Quadric),
            DEFAULT_OVERSAMPLE
        );
        assert_eq!(GngOptions::default_oversample(crate::Placement::Node), 1.0);
    }

    /// `oversample: None` follows the placement at resolve time, whichever field was set last:
    /// GNG3D-Q is oversampled, the paper's placement is not.
    #[test]
    fn unset_oversampling_follows_the_placement() {
        let m = sphere(); // 162 vertices
        let mut opts = GngOptions {
            oversample: None,
            ..GngOptions::for_target(GngTarget::Vertices(50))
        };
        let p = opts.resolve(&m).unwrap();
        assert_eq!((p.target_vertices, p.network_vertices), (50, Some(75)));
        assert!(p.reconstruction.split_bad_cells);
        opts.reconstruction = ReconstructionParams::paper();
        let p = opts.resolve(&m).unwrap();
        assert_eq!((p.target_vertices, p.network_vertices), (50, None));
        assert!(!p.reconstruction.split_bad_cells);
        assert_eq!(opts.oversample_factor(), 1.0);
        // The library default is the CLI's: GNG3D-Q, oversampled.
        assert_eq!(
            GngOptions::default().oversample_factor(),
            DEFAULT_OVERSAMPLE
        );
    }

    /// Detail rounds: the rule of `oversampled` unless the user gave a count, and never
    /// without oversampling (the nodes they add would break the exact count).
    #[test]
    fn detail_rounds_follow_the_oversampling_and_the_output_ratio() {
        let m = mesh::procedural::icosphere(4); // 2,562 vertices
        let rounds = |target: usize, oversample: Option<f64>, detail: Option<usize>| {
            GngOptions {
                oversample,
                detail_rounds: detail,
                ..GngOptions::for_target(GngTarget::Vertices(target))
            }
            .resolve(&m)
            .map(|p| p.reconstruction.detail_rounds)
        };
        // 5 % of 2,562 is 128.1: 129 vertices get the default rounds, 128 none.
        assert_eq!(rounds(129, None, None), Ok(DEFAULT_DETAIL_ROUNDS));
        assert_eq!(rounds(128, None, None), Ok(0));
        assert_eq!(rounds(128, None, Some(2)), Ok(2));
        assert_eq!(rounds(500, None, Some(0)), Ok(0));
        assert_eq!(rounds(500, Some(1.0), None), Ok(0));
        assert_eq!(rounds(500, Some(1.0), Some(3)), Ok(0));
        let err = rounds(500, None, Some(MAX_DETAIL_ROUNDS + 1)).unwrap_err();
        assert!(err.to_string().contains("detail rounds"), "{err}");
    }

    #[test]
    fn relaxation_follows_the_oversampling_and_the_output_ratio() {
        let m = mesh::procedural::icosphere(4); // 2,562 vertices
        let relax = |target: usize, oversample: Option<f64>, asked: bool| {
            let mut options = GngOptions {
                oversample,
                ..GngOptions::for_target(GngTarget::Vertices(target))
            };
            options.reconstruction.relax = asked;
            options.resolve(&m).unwrap().reconstruction.relax
        };
        // 30 % of 2,562 is 768.6: 768 vertices are relaxed, 769 not.
        assert!(relax(768, None, true));
        assert!(!relax(769, None, true));
        assert!(!relax(500, None, false));
        // No decimation: left as asked (nothing to relax; the run reports 0 relaxed vertices).
        assert!(relax(500, Some(1.0), true));
        // The paper's reconstruction never relaxes.
        assert!(!crate::ReconstructionParams::paper().relax);
    }

    #[test]
    fn deviation_repair_follows_the_oversampling_and_the_output_ratio() {
        let m = mesh::procedural::icosphere(4); // 2,562 vertices
        let repair = |target: usize, oversample: Option<f64>, asked: bool| {
            let mut options = GngOptions {
                oversample,
                ..GngOptions::for_target(GngTarget::Vertices(target))
            };
            options.reconstruction.repair_deviations = asked;
            options
                .resolve(&m)
                .unwrap()
                .reconstruction
                .repair_deviations
        };
        // 5 % of 2,562 is 128.1: 129 vertices are repaired, 128 not (the detail rounds' rule).
        assert!(repair(129, None, true));
        assert!(!repair(128, None, true));
        assert!(!repair(500, None, false));
        // No decimation: left as asked (it runs only after a decimation).
        assert!(repair(100, Some(1.0), true));
        assert!(!crate::ReconstructionParams::paper().repair_deviations);
    }

    #[test]
    fn oversampled_runs_decimate_the_network_to_exactly_the_target() {
        let m = mesh::procedural::icosphere(3); // 642 vertices
        let options = GngOptions {
            oversample: Some(1.5),
            ..GngOptions::for_target(GngTarget::Vertices(200))
        };
        let r = crate::simplify(&m.clone().into(), &options).unwrap();
        // The network's 300 nodes, plus those options (f) and (g) added, decimated to 200.
        let rec = &r.report.reconstruction;
        assert_eq!(
            r.report.network_vertices,
            300 + rec.split_cells + rec.detail_nodes
        );
        assert_eq!((r.report.target_vertices, r.report.vertices), (200, 200));
        assert_eq!(r.mesh.vertex_count(), 200);
        let decimate = r
            .report
            .steps
            .iter()
            .find(|s| s.step == crate::Step::Decimate)
            .expect("a decimation step");
        assert_eq!(decimate.changed, r.report.network_vertices - 200);
    }
}
