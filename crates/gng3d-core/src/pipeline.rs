//! Phase 2 and everything after it, written once: a [`Plan`] (the ordered [`Step`]s, built
//! from the parameters in one place, [`Plan::of`]) and one driver that runs it, one line per
//! step. The trainer hands over its network and stops there; [`crate::finish`], the viewer's
//! previews and [`crate::reconstruct`] all run this driver.
//!
//! The steps, in the order they run (those a plan leaves out are named in [`Plan::of`]):
//!
//! | step | what it does |
//! |---|---|
//! | [`Step::Label`] | every original vertex takes its nearest node of its own piece |
//! | [`Step::ConnectCells`] | each node's cell (its vertices) is made edge-connected |
//! | [`Step::MapFaces`] | original faces become label triples; duplicates merged, orientation voted, fins removed, small holes filled |
//! | [`Step::SplitBadCells`] | cells that are not discs or line a new hole get new nodes; faces mapped again (≤ 8 rounds) |
//! | [`Step::Attach`] | nodes no face uses are inserted into the nearest face; unused nodes compacted away |
//! | [`Step::Place`] | output vertices placed (node, projection or cell quadric) |
//! | [`Step::Flip`] | edges flipped toward the original surface |
//! | [`Step::Refit`] | vertices refitted so the triangles, not only the corners, fit the surface |
//! | [`Step::DetailRound`] | new nodes where the mesh stays farthest from the original; the build steps above run again |
//! | [`Step::Decimate`] | the oversampled network's mesh is decimated (QEM) to the output count |
//! | [`Step::Relax`] | decimated vertices relax toward the original vertices they stand for |
//! | [`Step::RepairDeviations`] | vertices standing off the original move back; edges across grooves flip |
//!
//! Each step that ran is a [`StepRecord`] in [`crate::GngReport::steps`] (and in `gng3d
//! simplify --json`): its time and what it changed.

use crate::domain::Pieces;
use crate::params::ReconstructionParams;
use crate::reconstruct::{self, Attachment, Candidate, OriginalTables, ReconstructionReport};
use glam::Vec3;
use mesh::TriMesh;
use mesh::quadric::Quadric;
use serde::Serialize;
use std::borrow::Cow;
use std::time::Instant;

/// One step of the pipeline after training.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
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
    /// QEM decimation of an oversampled network's mesh to the output count.
    Decimate,
    /// Tangential relaxation of the decimated mesh (option (h)).
    Relax,
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
            Step::Decimate => "decimate",
            Step::Relax => "relax",
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
            Step::Decimate => "vertices removed",
            Step::Relax => "vertices moved",
            Step::RepairDeviations => "vertex moves and flips",
        }
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct PlannedStep {
    /// The step.
    pub step: Step,
    /// Its build round.
    pub round: usize,
}

/// The ordered steps of a run after training.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Plan {
    steps: Vec<PlannedStep>,
}

impl Plan {
    /// The plan of a run with these reconstruction options, decimated to the output count when
    /// `decimates` (an oversampled network). The one place that decides which steps run:
    /// - [`Step::ConnectCells`] with `connected_cells`;
    /// - the build ([`Step::MapFaces`], [`Step::SplitBadCells`] with `split_bad_cells`,
    ///   [`Step::Attach`], [`Step::Place`], [`Step::Flip`] with `flip_edges`, [`Step::Refit`]
    ///   when [`ReconstructionParams::refits`]) once, then once more after each of the
    ///   `detail_rounds` [`Step::DetailRound`]s;
    /// - [`Step::Decimate`], then [`Step::Relax`] and [`Step::RepairDeviations`] when asked
    ///   for, only when `decimates`.
    pub fn of(params: &ReconstructionParams, decimates: bool) -> Plan {
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
        if decimates {
            let last = detail_rounds;
            add(Step::Decimate, last);
            if params.relax {
                add(Step::Relax, last);
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
}

/// A step that ran: how long it took and what it changed.
#[derive(Debug, Clone, PartialEq, Serialize)]
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

/// What the pipeline works on: the original with what training already knows of it.
pub(crate) struct Input<'a> {
    /// The mesh being simplified.
    pub original: &'a TriMesh,
    /// Its distinct points and components.
    pub pieces: &'a Pieces,
    /// Its edge table and vertex adjacency, when a helper thread already built them.
    pub tables: Option<&'a OriginalTables>,
    /// The trained nodes (world coordinates) and GNG edges.
    pub nodes: &'a [Vec3],
    /// GNG edges between `nodes`.
    pub edges: &'a [[u32; 2]],
    /// The reconstruction options.
    pub params: &'a ReconstructionParams,
    /// The output count of an oversampled run (the decimation's target).
    pub decimate_to: Option<usize>,
}

/// The pipeline's result.
pub(crate) struct Output {
    /// The final mesh.
    pub mesh: TriMesh,
    /// For each vertex of the network's mesh (before any decimation), its node.
    pub node_of_vertex: Vec<u32>,
    /// Counters of the reconstruction (the network's mesh) and the topology of the output.
    pub report: ReconstructionReport,
    /// Vertices of the network's mesh (before the decimation).
    pub network_vertices: usize,
    /// Every step that ran.
    pub steps: Vec<StepRecord>,
}

/// Run `plan` on `input`; `on_step` sees each step's record as it finishes. Errors are the
/// decimator's.
pub(crate) fn run(
    input: &Input<'_>,
    plan: &Plan,
    mut on_step: impl FnMut(&StepRecord),
) -> Result<Output, String> {
    let start = Instant::now();
    let mut work = Work::new(input);
    let mut steps = Vec::with_capacity(plan.steps().len());
    // Build rounds after this one are not run: a detail round found nothing to add, so the
    // mesh of this round is the last build.
    let mut last_round = usize::MAX;
    let mut build_seconds = 0.0;
    for &PlannedStep { step, round } in plan.steps() {
        if round > last_round && !work.after_build(step) {
            continue;
        }
        let t = Instant::now();
        let changed = match step {
            Step::Label => work.label(),
            Step::ConnectCells => work.connect_cells(),
            Step::MapFaces => work.map_faces(),
            Step::SplitBadCells => work.split_bad_cells(),
            Step::Attach => work.attach(),
            Step::Place => work.place(),
            Step::Flip => work.flip(),
            Step::Refit => work.refit(),
            Step::DetailRound => match work.detail_round() {
                0 => {
                    last_round = round - 1;
                    0
                }
                added => added,
            },
            Step::Decimate => {
                work.end_build(start, build_seconds);
                work.decimate()?
            }
            Step::Relax => work.relax(),
            Step::RepairDeviations => work.repair_deviations(),
        };
        let seconds = t.elapsed().as_secs_f64();
        if !work.after_build(step) {
            build_seconds += seconds;
        }
        let record = StepRecord {
            step,
            round,
            seconds,
            changed,
        };
        on_step(&record);
        steps.push(record);
    }
    if !work.build_ended {
        work.end_build(start, build_seconds);
    }
    Ok(work.output(steps))
}

/// The state the steps pass along.
struct Work<'a> {
    original: &'a TriMesh,
    pieces: &'a Pieces,
    tables: Option<Cow<'a, OriginalTables>>,
    gng_edges: &'a [[u32; 2]],
    params: &'a ReconstructionParams,
    decimate_to: Option<usize>,
    /// Node of each original vertex (`u32::MAX`: none).
    labels: Vec<u32>,
    /// Piece of each node.
    node_comp: Vec<u32>,
    /// Trained nodes plus those the split and detail steps added, where training left them.
    nodes: Vec<Vec3>,
    /// Mapped faces in node indices.
    faces: Vec<Candidate>,
    /// Per node: whether its cell holds a vertex of an original border.
    on_border: Vec<bool>,
    /// Split rounds of the current build.
    split_rounds: usize,
    /// Attached nodes, in output indices.
    attachments: Vec<Attachment>,
    positions: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    node_of_vertex: Vec<u32>,
    /// Output vertex of each original vertex (`u32::MAX`: none).
    owner: Vec<u32>,
    /// Cell quadrics of the placement (for the refit).
    quadrics: Vec<Quadric>,
    report: ReconstructionReport,
    /// Vertices of the network's mesh, once the last build is done.
    network_vertices: usize,
    build_ended: bool,
    /// Whether the decimation removed vertices (the relaxation and the repair run only then).
    decimated: bool,
}

impl<'a> Work<'a> {
    fn new(input: &Input<'a>) -> Work<'a> {
        Work {
            original: input.original,
            pieces: input.pieces,
            tables: input.tables.map(Cow::Borrowed),
            gng_edges: input.edges,
            params: input.params,
            decimate_to: input.decimate_to,
            labels: Vec::new(),
            node_comp: Vec::new(),
            nodes: input.nodes.to_vec(),
            faces: Vec::new(),
            on_border: Vec::new(),
            split_rounds: 0,
            attachments: Vec::new(),
            positions: Vec::new(),
            triangles: Vec::new(),
            node_of_vertex: Vec::new(),
            owner: Vec::new(),
            quadrics: Vec::new(),
            report: ReconstructionReport::empty(input.original.triangles.len()),
            network_vertices: 0,
            build_ended: false,
            decimated: false,
        }
    }

    /// Whether `step` works on the network's finished mesh (not part of a build round).
    fn after_build(&self, step: Step) -> bool {
        matches!(step, Step::Decimate | Step::Relax | Step::RepairDeviations)
    }

    /// [`Step::Label`]. When no helper thread built the original's tables, they are built on a
    /// second thread while this one labels (igea, 134k vertices: ~45 ms off the critical path);
    /// otherwise all cores label.
    fn label(&mut self) -> usize {
        let (original, pieces) = (self.original, self.pieces);
        let (nodes, edges) = (&self.nodes[..], self.gng_edges);
        let (labels, node_comp) = if self.tables.is_some() {
            let threads = crate::parallel::threads();
            reconstruct::labels_and_node_components(original, pieces, nodes, edges, threads)
        } else {
            let (labelled, tables) = std::thread::scope(|scope| {
                let tables = scope.spawn(|| OriginalTables::of(original));
                let labelled =
                    reconstruct::labels_and_node_components(original, pieces, nodes, edges, 1);
                // A panic on the table thread is a bug; rebuilding here keeps phase 2 alive.
                let tables = tables
                    .join()
                    .unwrap_or_else(|_| OriginalTables::of(original));
                (labelled, tables)
            });
            self.tables = Some(Cow::Owned(tables));
            labelled
        };
        self.labels = labels;
        self.node_comp = node_comp;
        self.labels.iter().filter(|&&l| l != u32::MAX).count()
    }

    /// [`Step::ConnectCells`].
    fn connect_cells(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let moved =
            reconstruct::make_cells_connected(self.original, tables, &self.nodes, &mut self.labels);
        self.report.relabelled_vertices += moved;
        moved
    }

    /// [`Step::MapFaces`]: the first mapping of a build.
    fn map_faces(&mut self) -> usize {
        self.split_rounds = 0;
        self.map_again();
        self.faces.len()
    }

    fn map_again(&mut self) {
        let tables = self.tables.as_deref().expect("labelled");
        let (faces, on_border) = reconstruct::map_faces(
            self.original,
            &tables.edges,
            &self.labels,
            &self.nodes,
            self.gng_edges,
            self.params,
            &mut self.report,
        );
        self.faces = faces;
        self.on_border = on_border;
    }

    /// [`Step::SplitBadCells`]: up to [`reconstruct::SPLIT_ROUNDS`] rounds of split-and-map;
    /// the new nodes of all builds together stay within [`reconstruct::SPLIT_BUDGET`] of the
    /// original's vertices without a node.
    fn split_bad_cells(&mut self) -> usize {
        let budget = (self
            .original
            .positions
            .len()
            .saturating_sub(self.nodes.len()) as f64
            * reconstruct::SPLIT_BUDGET) as usize;
        let mut added_here = 0;
        while self.split_rounds < reconstruct::SPLIT_ROUNDS {
            let tables = self.tables.as_deref().expect("labelled");
            let bad = reconstruct::split::bad_cells(
                self.original,
                tables,
                &self.labels,
                self.nodes.len(),
                &self.faces,
                &self.on_border,
            );
            let added = reconstruct::split::split_cells(
                self.original,
                tables,
                &mut self.labels,
                &mut self.nodes,
                &mut self.node_comp,
                &bad,
                budget.saturating_sub(self.report.split_cells),
            );
            if added == 0 {
                break;
            }
            self.report.split_cells += added;
            self.report.split_rounds += 1;
            self.split_rounds += 1;
            added_here += added;
            self.map_again();
        }
        added_here
    }

    /// [`Step::Attach`]: nodes no face uses are inserted into the nearest face (moved onto it,
    /// in a copy: `nodes` stay where training left them for the detail rounds' labels), then
    /// the referenced nodes become the output vertices, in node order.
    fn attach(&mut self) -> usize {
        let mut nodes = self.nodes.clone();
        let attachments = reconstruct::attach::attach_unreferenced(
            &mut self.faces,
            &mut nodes,
            self.gng_edges,
            self.original,
            &self.labels,
            &self.node_comp,
        );
        self.report.attached_nodes = attachments.len();
        let mut remap = vec![u32::MAX; nodes.len()];
        for c in &self.faces {
            for &v in &c.tri {
                remap[v as usize] = 0;
            }
        }
        self.node_of_vertex.clear();
        self.positions.clear();
        for (i, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = self.positions.len() as u32;
                self.positions.push(nodes[i]);
                self.node_of_vertex.push(i as u32);
            }
        }
        self.report.unreferenced_nodes = nodes.len() - self.positions.len();
        self.triangles = self
            .faces
            .iter()
            .map(|c| c.tri.map(|v| remap[v as usize]))
            .collect();
        // Attached nodes, in output indices, follow their split triangles in the placement.
        self.attachments = attachments
            .iter()
            .map(|a| Attachment {
                node: remap[a.node as usize],
                corners: a.corners.map(|c| remap[c as usize]),
                weights: a.weights,
            })
            .collect();
        self.owner = crate::placement::owners(&self.labels, &self.node_of_vertex, nodes.len());
        attachments.len()
    }

    /// [`Step::Place`].
    fn place(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let placed = crate::placement::place(
            self.original,
            &tables.edges,
            &self.owner,
            self.params.placement,
            &self.attachments,
            &mut self.positions,
        );
        self.quadrics = placed.quadrics;
        self.report.placed_vertices = placed.moved;
        placed.moved
    }

    /// [`Step::Flip`].
    fn flip(&mut self) -> usize {
        let flips = crate::flip::flip_edges(
            &self.positions,
            &mut self.triangles,
            &self.original.positions,
            &self.owner,
        );
        self.report.flipped_edges = flips.flips;
        flips.flips
    }

    /// [`Step::Refit`], after the flips: it fits the final triangles (before them, measured on
    /// four meshes at 10 % and 50 %: 4-6 % more mean distance and a higher Hausdorff max in 7
    /// of 8).
    fn refit(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let refit = crate::refit::refit(
            &mut self.positions,
            &self.triangles,
            self.original,
            &tables.edges,
            &self.owner,
            &self.quadrics,
        );
        self.report.refit_moves = refit.moves;
        refit.moves
    }

    /// [`Step::DetailRound`]: new nodes at the original vertices farthest from the mesh built
    /// so far; 0 when there is none to add (the last build is then the network's mesh).
    fn detail_round(&mut self) -> usize {
        let budget =
            (reconstruct::detail::NODES_PER_ROUND * self.positions.len() as f64).ceil() as usize;
        let tables = self.tables.as_deref().expect("labelled");
        let chosen = reconstruct::detail::farthest_vertices(
            self.original,
            tables,
            &self.owner,
            &self.positions,
            &self.triangles,
            budget,
        );
        if chosen.is_empty() {
            return 0;
        }
        reconstruct::detail::insert_nodes(
            self.original,
            tables,
            &chosen,
            &mut self.labels,
            &mut self.nodes,
            &mut self.node_comp,
        );
        if self.params.connected_cells {
            self.report.relabelled_vertices += reconstruct::make_cells_connected(
                self.original,
                tables,
                &self.nodes,
                &mut self.labels,
            );
        }
        self.report.detail_nodes += chosen.len();
        chosen.len()
    }

    /// The network's mesh is done: its counts go to the report.
    fn end_build(&mut self, start: Instant, build_seconds: f64) {
        self.build_ended = true;
        self.network_vertices = self.positions.len();
        self.report.vertices = self.positions.len();
        self.report.faces = self.triangles.len();
        // Phase 2 proper (the decimation and what follows are not counted).
        self.report.seconds = build_seconds.min(start.elapsed().as_secs_f64());
    }

    /// [`Step::Decimate`]: error first down to the output count, when the network's mesh has
    /// more vertices.
    fn decimate(&mut self) -> Result<usize, String> {
        let Some(n) = self.decimate_to else {
            return Ok(0);
        };
        if self.positions.len() <= n {
            return Ok(0);
        }
        let mesh = TriMesh::new(
            std::mem::take(&mut self.positions),
            std::mem::take(&mut self.triangles),
        );
        let before = mesh.vertex_count();
        let out = crate::decimate::decimate(&mesh, n)?;
        self.decimated = true;
        let TriMesh {
            positions,
            triangles,
        } = out;
        self.positions = positions;
        self.triangles = triangles;
        Ok(before - self.positions.len())
    }

    /// [`Step::Relax`]: the decimation placed its vertices for the surface; relax them toward
    /// the original vertices they stand for.
    fn relax(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let relaxed = crate::relax::relax(&mut self.positions, &self.triangles, self.original);
        self.report.relaxed_vertices = relaxed.moves;
        relaxed.moves
    }

    /// [`Step::RepairDeviations`]: then bring back what stands farthest off the original.
    fn repair_deviations(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let repaired =
            crate::deviation::repair(&mut self.positions, &mut self.triangles, self.original);
        self.report.deviation_moves = repaired.moves;
        self.report.deviation_flips = repaired.flips;
        repaired.moves + repaired.flips
    }

    fn output(mut self, steps: Vec<StepRecord>) -> Output {
        let mesh = TriMesh::new(self.positions, self.triangles);
        self.report.topology = mesh::topology::analyze(&mesh);
        Output {
            mesh,
            node_of_vertex: self.node_of_vertex,
            report: self.report,
            network_vertices: self.network_vertices,
            steps,
        }
    }
}
