//! The plan of a run after training: its [`Step`]s, a [`Plan`] of them (built from the
//! parameters in one place, [`Plan::of`]) and the [`StepRecord`] each step that ran leaves.

#[cfg(feature = "serde")]
use serde::Serialize;

use crate::params::ReconstructionParams;

/// One step of the pipeline after training ([`crate::finish`],
/// [`crate::Trainer::reconstruct`]).
///
/// The steps, in the order they run (those a plan leaves out are named in [`Plan::of`]; each
/// that ran is a [`StepRecord`] in [`crate::GngReport::steps`] and in `gng3d simplify --json`):
///
/// | step | what it does |
/// |---|---|
/// | [`Step::Label`] | every original vertex takes its nearest node of its own piece |
/// | [`Step::ConnectCells`] | each node's cell (its vertices) is made edge-connected |
/// | [`Step::MapFaces`] | original faces become label triples; duplicates merged, orientation voted, fins removed, small holes filled |
/// | [`Step::SplitBadCells`] | cells that are not discs or line a new hole get new nodes; faces mapped again (≤ 8 rounds) |
/// | [`Step::Attach`] | nodes no face uses are inserted into the nearest face; unused nodes compacted away |
/// | [`Step::Place`] | output vertices placed (node, projection or cell quadric) |
/// | [`Step::Flip`] | edges flipped toward the original surface |
/// | [`Step::Refit`] | vertices refitted so the triangles, not only the corners, fit the surface |
/// | [`Step::DetailRound`] | new nodes where the mesh stays farthest from the original; the build steps above run again |
/// | [`Step::CutSeams`] | with an input whose attributes have seams or a CAD part's creases: the network's mesh is cut along them |
/// | [`Step::Decimate`] | the oversampled network's mesh is decimated (QEM) to the output count |
/// | [`Step::Relax`] | decimated vertices relax toward the original vertices they stand for |
/// | [`Step::Shape`] | edges flip toward valence 6, vertices slide toward their one-ring's centroid on the original |
/// | [`Step::RepairDeviations`] | vertices standing off the original move back; edges across grooves flip |
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
#[non_exhaustive]
pub enum Step {
    /// Label every original vertex with its nearest node (component-aware).
    Label,
    /// Make every node's cell edge-connected on the original.
    ConnectCells,
    /// Map the original faces to node triples and clean them up (reconstruction options (a),
    /// (b)).
    MapFaces,
    /// Split the cells that broke the topology and map again (option (f)).
    SplitBadCells,
    /// Attach every node no face uses; compact to the referenced nodes.
    Attach,
    /// Place the output vertices (option (c)).
    Place,
    /// Error-driven edge flips (option (d)).
    Flip,
    /// Surface refit (option (e)).
    Refit,
    /// One round of detail nodes (option (g)); the build steps run again after it.
    DetailRound,
    /// The network's mesh cut along the original's attribute seams and creases, for a
    /// decimation that keeps them (inputs with seams, [`crate::Trainer::new`] with attributes,
    /// or with creases: docs/notes/creases.md).
    CutSeams,
    /// QEM decimation of an oversampled network's mesh to the output count.
    Decimate,
    /// Tangential relaxation of the decimated mesh (option (h)).
    Relax,
    /// Triangle shape of the decimated mesh (option (k)): valence flips and tangential
    /// smoothing onto the original.
    Shape,
    /// Deviation repair of the decimated mesh (option (i)).
    RepairDeviations,
}

impl Step {
    /// The step's name as `--json` writes it (`"map_faces"`).
    pub fn name(self) -> &'static str {
        match self {
            Step::Label => "label",
            Step::ConnectCells => "connect_cells",
            Step::MapFaces => "map_faces",
            Step::SplitBadCells => "split_bad_cells",
            Step::Attach => "attach",
            Step::Place => "place",
            Step::Flip => "flip",
            Step::Refit => "refit",
            Step::DetailRound => "detail_round",
            Step::CutSeams => "cut_seams",
            Step::Decimate => "decimate",
            Step::Relax => "relax",
            Step::Shape => "shape",
            Step::RepairDeviations => "repair_deviations",
        }
    }

    /// What [`StepRecord::changed`] counts for this step.
    pub fn changes(self) -> &'static str {
        match self {
            Step::Label => "original vertices labelled",
            Step::ConnectCells => "vertices relabelled",
            Step::MapFaces => "faces mapped",
            Step::SplitBadCells => "nodes added",
            Step::Attach => "nodes attached",
            Step::Place => "vertices moved",
            Step::Flip => "edges flipped",
            Step::Refit => "vertex moves",
            Step::DetailRound => "nodes added",
            Step::CutSeams => "vertices added on seams",
            Step::Decimate => "vertices removed",
            Step::Relax => "vertices moved",
            Step::Shape => "vertex moves and flips",
            Step::RepairDeviations => "vertex moves and flips",
        }
    }
}

impl Step {
    /// Whether the step works on the network's finished mesh (not part of a build round).
    pub(super) fn after_build(self) -> bool {
        matches!(
            self,
            Step::CutSeams | Step::Decimate | Step::Relax | Step::Shape | Step::RepairDeviations
        )
    }

    /// Whether every run needs this step for an exact vertex count (the rest may be left out
    /// when time runs short: [`crate::GngWarning::StepSkippedForTime`]).
    pub fn is_required(self) -> bool {
        matches!(
            self,
            Step::Label
                | Step::ConnectCells
                | Step::MapFaces
                | Step::Attach
                | Step::Place
                | Step::Decimate
        )
    }
}

impl std::fmt::Display for Step {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// A step of a [`Plan`] with the build it belongs to: round 0 is the first build, round r the
/// build after the r-th [`Step::DetailRound`] (the decimation and what follows it belong to the
/// last).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct PlannedStep {
    /// The step.
    pub step: Step,
    /// Its build round.
    pub round: usize,
}

/// The ordered steps of a run after training.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct Plan {
    pub(super) steps: Vec<PlannedStep>,
}

impl Plan {
    /// The plan of a run with these reconstruction options, decimated to the output count when
    /// `decimates` (an oversampled network). The one place that decides which steps run:
    /// - [`Step::ConnectCells`] with `connected_cells`;
    /// - the build ([`Step::MapFaces`], [`Step::SplitBadCells`] with `split_bad_cells`,
    ///   [`Step::Attach`], [`Step::Place`], [`Step::Flip`] with `flip_edges`, [`Step::Refit`]
    ///   when [`ReconstructionParams::refits`]) once, then once more after each of the
    ///   `detail_rounds` [`Step::DetailRound`]s;
    /// - [`Step::Decimate`], then [`Step::Relax`], [`Step::Shape`] and
    ///   [`Step::RepairDeviations`] when asked for, only when `decimates`.
    ///
    /// For an input whose attributes have seams, [`Plan::with_seams`].
    pub fn of(params: &ReconstructionParams, decimates: bool) -> Plan {
        Plan::with_seams(params, decimates, false)
    }

    /// [`Plan::of`], and with `seams` (the input's attributes have seams,
    /// [`crate::Trainer::new`] with attributes, or it has creases) [`Step::CutSeams`] then [`Step::Decimate`] after the
    /// last build whether or not `decimates`: the cut adds vertices, the decimation takes the
    /// mesh back to the output count along the seams.
    pub fn with_seams(params: &ReconstructionParams, decimates: bool, seams: bool) -> Plan {
        let mut steps = Vec::new();
        let mut add = |step, round| steps.push(PlannedStep { step, round });
        add(Step::Label, 0);
        if params.connected_cells {
            add(Step::ConnectCells, 0);
        }
        let detail_rounds = params.detail_rounds;
        for round in 0..=detail_rounds {
            if round > 0 {
                add(Step::DetailRound, round);
            }
            add(Step::MapFaces, round);
            if params.split_bad_cells {
                add(Step::SplitBadCells, round);
            }
            add(Step::Attach, round);
            add(Step::Place, round);
            if params.flip_edges {
                add(Step::Flip, round);
            }
            if params.refits() {
                add(Step::Refit, round);
            }
        }
        if seams {
            add(Step::CutSeams, detail_rounds);
        }
        if decimates || seams {
            add(Step::Decimate, detail_rounds);
        }
        if decimates {
            let last = detail_rounds;
            if params.relax {
                add(Step::Relax, last);
            }
            if params.shape != crate::Shape::Off {
                add(Step::Shape, last);
            }
            if params.repair_deviations {
                add(Step::RepairDeviations, last);
            }
        }
        Plan { steps }
    }

    /// The steps in the order they run.
    pub fn steps(&self) -> &[PlannedStep] {
        &self.steps
    }

    /// Whether the plan has `step`.
    pub fn contains(&self, step: Step) -> bool {
        self.steps.iter().any(|s| s.step == step)
    }

    /// This plan without the flips and refits of the builds before the last.
    pub(super) fn lean_detail_builds(&self) -> Plan {
        let last = self.steps.iter().map(|s| s.round).max().unwrap_or(0);
        let steps = self
            .steps
            .iter()
            .filter(|s| s.round == last || !matches!(s.step, Step::Flip | Step::Refit))
            .copied()
            .collect();
        Plan { steps }
    }

    /// How many times the plan runs `step`.
    pub fn count(&self, step: Step) -> usize {
        self.steps.iter().filter(|s| s.step == step).count()
    }

    /// This plan without `step`: every round of it, or for [`Step::DetailRound`] the last
    /// round (the detail round and the build after it).
    pub(super) fn without(&self, step: Step) -> Plan {
        let last = self
            .steps
            .iter()
            .filter(|s| s.step == Step::DetailRound)
            .map(|s| s.round)
            .max();
        let steps = self
            .steps
            .iter()
            .filter(|s| match (step, last) {
                (Step::DetailRound, Some(last)) => s.round != last || s.step.after_build(),
                _ => s.step != step,
            })
            .copied()
            .collect();
        Plan { steps }
    }
}

/// A step that ran: how long it took and what it changed.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct StepRecord {
    /// The step.
    pub step: Step,
    /// Its build round ([`PlannedStep::round`]).
    pub round: usize,
    /// Wall time, seconds.
    pub seconds: f64,
    /// What it changed, counted in [`Step::changes`].
    pub changed: usize,
}
