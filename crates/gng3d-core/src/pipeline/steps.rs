//! The step adapters: the state the steps pass along ([`Work`]) and one method per [`Step`]
//! that calls the pass doing it (labelling, cells, faces, placement, flips, refit, detail
//! rounds, seams, decimation, relaxation, repair) and counts what it changed.

use super::budget::SEAM_DISTANCE_RATIO;
use super::plan::Step;
use super::{Input, Output, StepRecord};
use crate::domain::Pieces;
use crate::params::ReconstructionParams;
use crate::reconstruct::{self, Attachment, Candidate, OriginalTables, ReconstructionReport};
use glam::Vec3;
use mesh::TriMesh;
use mesh::cancel::Cancel;
use mesh::quadric::Quadric;
use std::borrow::Cow;
use std::time::Instant;

/// The state the steps pass along.
pub(super) struct Work<'a> {
    original: &'a TriMesh,
    pieces: &'a Pieces,
    tables: Option<Cow<'a, OriginalTables>>,
    gng_edges: &'a [[u32; 2]],
    params: &'a ReconstructionParams,
    decimate_to: Option<usize>,
    /// The original's chart of each triangle, when it has seams.
    charts: Option<&'a [u32]>,
    /// The original's creases, when it has some.
    creases: Option<&'a crate::finish::creases::Creases>,
    /// Whether `charts` follow attribute seams (not only creases).
    attribute_seams: bool,
    /// After [`Step::CutSeams`]: the chart of each triangle of the mesh (until a decimation
    /// that could not keep the seams).
    triangle_charts: Option<Vec<u32>>,
    /// After [`Step::CutSeams`]: the network's mesh before the cut, for the decimation's
    /// comparison.
    uncut: Option<TriMesh>,
    /// The original's closest-point grid, once built ([`Step::CutSeams`]).
    grid: Option<mesh::transfer::FaceGrid<'a>>,
    /// The original's closest-point structure of the shape pass and the deviation repair
    /// ([`crate::finish::surface`]), built by the first of them that runs.
    surface: Option<crate::surface::Surface<'a>>,
    /// The decimation did not follow the seams: the ratio of [`GngWarning::SeamsNotFollowed`].
    seams_not_followed: Option<Option<f64>>,
    /// Most threads the steps use, the caller's included.
    threads: usize,
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
    /// Whether the last build is done (its counts are in the report).
    pub(super) build_ended: bool,
    /// Whether the decimation removed vertices (the relaxation and the repair run only then).
    decimated: bool,
    /// When the current step should end to leave the rest of the plan its time (steps that
    /// can stop early: the deviation repair between its rounds).
    pub(super) step_deadline: Option<Instant>,
    /// The run's cancel flag, handed to the decimation's QEM runs.
    pub(super) cancel: Option<Cancel>,
}

impl<'a> Work<'a> {
    pub(super) fn new(input: &Input<'a>) -> Work<'a> {
        Work {
            original: input.original,
            pieces: input.pieces,
            tables: input.tables.map(Cow::Borrowed),
            gng_edges: input.edges,
            params: input.params,
            decimate_to: input.decimate_to,
            charts: input.charts,
            creases: input.creases,
            attribute_seams: input.attribute_seams,
            triangle_charts: None,
            uncut: None,
            grid: None,
            surface: None,
            seams_not_followed: None,
            threads: input.threads,
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
            build_ended: false,
            decimated: false,
            step_deadline: None,
            cancel: None,
        }
    }

    /// [`Step::Label`]. When no helper thread built the original's tables, they are built on a
    /// second thread while this one labels (igea, 134k vertices: ~45 ms off the critical path);
    /// otherwise all cores label.
    pub(super) fn label(&mut self) -> usize {
        let (original, pieces) = (self.original, self.pieces);
        let (nodes, edges) = (&self.nodes[..], self.gng_edges);
        let (labels, node_comp) = if self.tables.is_some() {
            reconstruct::labels_and_node_components(original, pieces, nodes, edges, self.threads)
        } else if self.threads <= 1 {
            let labelled =
                reconstruct::labels_and_node_components(original, pieces, nodes, edges, 1);
            self.tables = Some(Cow::Owned(OriginalTables::of(original)));
            labelled
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
    pub(super) fn connect_cells(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let moved =
            reconstruct::make_cells_connected(self.original, tables, &self.nodes, &mut self.labels);
        self.report.relabelled_vertices += moved;
        moved
    }

    /// [`Step::MapFaces`]: the first mapping of a build.
    pub(super) fn map_faces(&mut self) -> usize {
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
    pub(super) fn split_bad_cells(&mut self) -> usize {
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
    pub(super) fn attach(&mut self) -> usize {
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
        self.owner =
            crate::reconstruct::placement::owners(&self.labels, &self.node_of_vertex, nodes.len());
        attachments.len()
    }

    /// [`Step::Place`].
    pub(super) fn place(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let placed = crate::reconstruct::placement::place(
            self.original,
            &tables.edges,
            &self.owner,
            self.params.placement,
            &self.attachments,
            &mut self.positions,
            self.threads,
        );
        self.quadrics = placed.quadrics;
        self.report.placed_vertices = placed.moved;
        placed.moved
    }

    /// [`Step::Flip`].
    pub(super) fn flip(&mut self) -> usize {
        let flips = crate::reconstruct::flip::flip_edges(
            &self.positions,
            &mut self.triangles,
            &self.original.positions,
            &self.owner,
            self.threads,
        );
        self.report.flipped_edges = flips.flips;
        flips.flips
    }

    /// [`Step::Refit`], after the flips: it fits the final triangles (before them, measured on
    /// four meshes at 10 % and 50 %: 4-6 % more mean distance and a higher Hausdorff max in 7
    /// of 8).
    pub(super) fn refit(&mut self) -> usize {
        let tables = self.tables.as_deref().expect("labelled");
        let refit = crate::reconstruct::refit::refit(
            &mut self.positions,
            &self.triangles,
            self.original,
            &tables.edges,
            &self.owner,
            &self.quadrics,
            self.threads,
        );
        self.report.refit_moves = refit.moves;
        refit.moves
    }

    /// [`Step::DetailRound`]: new nodes at the original vertices farthest from the mesh built
    /// so far; 0 when there is none to add (the last build is then the network's mesh).
    pub(super) fn detail_round(&mut self) -> usize {
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
            self.threads,
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
    pub(super) fn end_build(&mut self, start: Instant, build_seconds: f64) {
        self.build_ended = true;
        self.report.vertices = self.positions.len();
        self.report.faces = self.triangles.len();
        // Phase 2 proper (the decimation and what follows are not counted).
        self.report.seconds = build_seconds.min(start.elapsed().as_secs_f64());
    }

    /// [`Step::CutSeams`]: the network's mesh cut along the original's seams
    /// ([`crate::finish::seams::cut`]).
    pub(super) fn cut_seams(&mut self) -> usize {
        let Some(charts) = self.charts else {
            return 0;
        };
        let original = self.original;
        let grid = self
            .grid
            .get_or_insert_with(|| mesh::transfer::FaceGrid::new(original));
        let uncut = TriMesh::new(
            std::mem::take(&mut self.positions),
            std::mem::take(&mut self.triangles),
        );
        let cut = crate::finish::seams::cut(
            self.original,
            grid,
            charts,
            &uncut.positions,
            &uncut.triangles,
            self.threads,
        );
        self.uncut = Some(uncut);
        let mut mesh = TriMesh::new(cut.positions, cut.triangles);
        if let Some(creases) = self.creases {
            creases.pull(original, grid, charts, &mut mesh, &cut.charts, self.threads);
        }
        self.positions = mesh.positions;
        self.triangles = mesh.triangles;
        self.triangle_charts = (cut.added + cut.snapped > 0).then_some(cut.charts);
        cut.added + cut.snapped
    }

    /// Vertices of the mesh between triangles of different charts (on a seam), when the mesh
    /// follows the seams: the relaxation leaves them where they are (its moves are along the
    /// surface, off the seam), the deviation repair flips no edge between two of them.
    fn seam_vertices(&self) -> Option<Vec<bool>> {
        let charts = self.triangle_charts.as_ref()?;
        let mut first = vec![u32::MAX; self.positions.len()];
        let mut seam = vec![false; self.positions.len()];
        for (t, &c) in self.triangles.iter().zip(charts) {
            for &v in t {
                let f = &mut first[v as usize];
                if *f == u32::MAX {
                    *f = c;
                } else if *f != c {
                    seam[v as usize] = true;
                }
            }
        }
        Some(seam)
    }

    /// [`Step::Decimate`]: error first down to the output count, when the network's mesh has
    /// more vertices; along the seams after [`Step::CutSeams`]
    /// ([`crate::finish::decimate::decimate_along_seams`]).
    pub(super) fn decimate(&mut self) -> Result<usize, qem::QemError> {
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
        let cancel = self.cancel.as_ref();
        let out = match (self.triangle_charts.take(), self.uncut.take()) {
            (Some(charts), Some(uncut)) => {
                let (mut along, charts) =
                    crate::finish::decimate::decimate_along_seams(&mesh, &charts, n, cancel)?;
                // The same count without the seams, from the mesh before the cut: kept when
                // the seams would cost too much of the surface (SEAM_DISTANCE_RATIO).
                let plain = if uncut.vertex_count() > n {
                    crate::finish::decimate::decimate(&uncut, n, cancel)?
                } else {
                    uncut
                };
                let original = self.original;
                let grid = self
                    .grid
                    .get_or_insert_with(|| mesh::transfer::FaceGrid::new(original));
                // QEM placed the seams' vertices by its quadrics: back onto the creases.
                if let (Some(creases), Some(original_charts), Some(charts)) =
                    (self.creases, self.charts, charts.as_ref())
                {
                    creases.pull(
                        original,
                        grid,
                        original_charts,
                        &mut along,
                        charts,
                        self.threads,
                    );
                }
                // (No charts: the decimation along the seams could not reach the count.)
                // With creases, the cut is kept only when its largest distance is not above
                // the plain decimation's too: on real CAD parts (soft and curved creases, few
                // vertices per line) it can be (docs/notes/creases.md).
                let measured = charts.as_ref().map(|_| {
                    let along = crate::finish::seams::distance_to(grid, original, &along);
                    let plain = crate::finish::seams::distance_to(grid, original, &plain);
                    (along.0 / plain.0.max(f64::MIN_POSITIVE), along.1 <= plain.1)
                });
                let ratio = measured.map(|m| m.0);
                let keep = measured.is_some_and(|(r, not_farther)| {
                    r <= SEAM_DISTANCE_RATIO && (self.creases.is_none() || not_farther)
                });
                if keep {
                    self.triangle_charts = charts;
                    along
                } else {
                    if self.attribute_seams {
                        self.seams_not_followed = Some(ratio);
                    }
                    plain
                }
            }
            _ => crate::finish::decimate::decimate(&mesh, n, cancel)?,
        };
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
    pub(super) fn relax(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let seams = self.seam_vertices();
        let relaxed = crate::finish::relax::relax(
            &mut self.positions,
            &self.triangles,
            self.original,
            seams.as_deref(),
            self.threads,
        );
        self.report.relaxed_vertices = relaxed.moves;
        relaxed.moves
    }

    /// Builds the finishing steps' closest-point structure on first use; `None` for an
    /// original without faces.
    fn build_surface(&mut self) {
        if self.surface.is_none() {
            self.surface = crate::finish::surface(self.original);
        }
    }

    /// [`Step::Shape`]: rounder triangles (valence flips, tangential smoothing onto the
    /// original).
    pub(super) fn shape(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let seams = self.seam_vertices();
        self.build_surface();
        let Some(surface) = &self.surface else {
            return 0;
        };
        let shaped = crate::finish::shape::shape(
            self.params.shape == crate::Shape::Fit,
            &mut self.positions,
            &mut self.triangles,
            surface,
            seams.as_deref(),
            self.step_deadline,
            self.threads,
        );
        shaped.moves + shaped.flips
    }

    /// [`Step::RepairDeviations`]: then bring back what stands farthest off the original.
    pub(super) fn repair_deviations(&mut self) -> usize {
        if !self.decimated {
            return 0;
        }
        let seams = self.seam_vertices();
        self.build_surface();
        let Some(surface) = &self.surface else {
            return 0;
        };
        let repaired = crate::finish::deviation::repair_until(
            &mut self.positions,
            &mut self.triangles,
            surface,
            seams.as_deref(),
            self.step_deadline,
            self.threads,
        );
        self.report.deviation_moves = repaired.moves;
        self.report.deviation_flips = repaired.flips;
        repaired.moves + repaired.flips
    }

    pub(super) fn output(mut self, steps: Vec<StepRecord>, skipped: Vec<Step>) -> Output {
        let mesh = TriMesh::new(self.positions, self.triangles);
        self.report.topology = mesh::topology::analyze(&mesh);
        Output {
            mesh,
            node_of_vertex: self.node_of_vertex,
            report: self.report,
            steps,
            skipped,
            seams_not_followed: self.seams_not_followed,
        }
    }
}
