//! The simplifier, as a list of named passes (the shape of meshoptimizer's `meshopt_simplify`):
//!
//! 1. [`prepare`]: validate, normalise, Morton renumbering, face sort, vertex → face lists;
//! 2. [`setup`]: per vertex, quadric, boundary planes and flag, edges;
//! 3. [`add_virtual_pairs`](passes::add_virtual_pairs): non-edge pairs within `pair_threshold`
//!    (optional);
//! 4. initial costing and sort of the candidate list;
//! 5. the contraction loop: [`Schedule::one_pass`](passes::Schedule::one_pass), then either
//!    [`Schedule::rebuild`](passes::Schedule::rebuild) after a stall or
//!    [`Schedule::next_list`](passes::Schedule::next_list) for the next pass;
//! 6. [`Engine::output`](engine::Engine::output): compact into a `TriMesh` (via `mesh::clean`).
//!
//! Large meshes on a multi-threaded pool go through [`partition`] instead: passes 2–6 on spatial
//! parts in parallel (shared vertices locked), then once more over the stitched result.
//!
//! Contractions are scheduled in passes over a sorted candidate list instead of a heap. Each pass
//! walks the pairs in increasing cost and contracts every pair whose endpoints were not touched
//! earlier in the pass, up to a cost cap (1.5 × the cost at the middle of the pass's goal), so the
//! order stays close to the greedy order of Garland & Heckbert. Pairs of untouched vertices keep
//! their exact cost and order for the next pass; pairs of the merged vertices are evaluated
//! afresh, sorted, and merged in. This keeps memory access sequential (no heap sift misses).
//!
//! This module holds the entry points and the checks of the parameters; passes 2–6 are in
//! [`passes`]. The modules import downwards only: at the bottom the shared pieces ([`triangle`],
//! [`vertex`], [`resources`], [`view`], [`seams`], [`candidates`]); above them the attribute
//! term and values ([`attribute_error`], [`wedges`]), then [`prepare`], [`setup`] and the
//! [`engine`]; on top the drivers ([`passes`], [`partition`], [`attributes`]).

mod attribute_error;
mod attributes;
mod candidates;
mod engine;
mod partition;
mod passes;
mod prepare;
mod resources;
mod seams;
mod setup;
mod triangle;
mod vertex;
mod view;
mod wedges;

use crate::{QemError, QemParams, QemReport, StopReason, Target};
use mesh::TriMesh;
use passes::simplify_prepared;
use std::time::Instant;

/// [`QemError::Cancelled`] when the run's [`QemParams::cancel`] flag is set.
fn check_cancel(params: &QemParams) -> Result<(), QemError> {
    match &params.cancel {
        Some(c) if c.is_cancelled() => Err(QemError::Cancelled),
        _ => Ok(()),
    }
}

/// Run the whole simplification.
pub fn run(input: &TriMesh, params: &QemParams) -> Result<(TriMesh, QemReport), QemError> {
    let started = Instant::now();
    validate(params)?;
    check_cancel(params)?;
    let prepared = prepare::prepare(input)?;
    check_pair_threshold(params.pair_threshold, prepared.frame.scale)?;
    check_cancel(params)?;
    let input_faces = prepared.faces.len();
    let input_vertices = prepared.pos.len();
    let run = if let Some(plan) = partition::plan(&prepared, params) {
        partition::run(prepared, params, plan)?
    } else {
        simplify_prepared(prepared, params, None)?.0
    };
    let report = report(&run, input_vertices, input_faces, started);
    Ok((run.mesh, report))
}

/// Run the whole simplification keeping `attributes` (see `attributes`); vertices flagged in
/// `locked` (input numbering) are never contracted.
pub fn run_with_attributes(
    input: &TriMesh,
    attributes: &mesh::attributes::Attributes,
    params: &QemParams,
    locked: Option<&[bool]>,
) -> Result<(TriMesh, mesh::attributes::Attributes, QemReport), QemError> {
    check_lock_mask(input, locked)?;
    attributes::run(input, attributes, params, locked)
}

/// Run the whole simplification with the input vertices flagged in `locked` never contracted
/// (the sequential engine: the two-thread parts lock their shared vertices themselves, and the
/// result must not depend on the thread count).
pub fn run_locked(
    input: &TriMesh,
    params: &QemParams,
    locked: &[bool],
) -> Result<(TriMesh, QemReport), QemError> {
    let started = Instant::now();
    validate(params)?;
    check_lock_mask(input, Some(locked))?;
    check_cancel(params)?;
    let (prepared, index) = prepare::prepare_with_index(input, true)?;
    let new_index = index.vertex;
    check_pair_threshold(params.pair_threshold, prepared.frame.scale)?;
    check_cancel(params)?;
    let input_faces = prepared.faces.len();
    let input_vertices = prepared.pos.len();
    let mut prepared_locked = vec![false; input_vertices];
    for (&k, &l) in new_index.iter().zip(locked) {
        if l && k != u32::MAX {
            prepared_locked[k as usize] = true;
        }
    }
    drop(new_index);
    let run = simplify_prepared(prepared, params, Some(&prepared_locked))?.0;
    let report = report(&run, input_vertices, input_faces, started);
    Ok((run.mesh, report))
}

/// A lock mask has one flag per input vertex.
fn check_lock_mask(input: &TriMesh, locked: Option<&[bool]>) -> Result<(), QemError> {
    match locked {
        Some(l) if l.len() != input.positions.len() => Err(QemError::InvalidParameter(format!(
            "the lock mask has {} flags for {} vertices",
            l.len(),
            input.positions.len()
        ))),
        _ => Ok(()),
    }
}

/// The report of `run` on an input of `input_vertices` referenced vertices and `input_faces`
/// usable faces, started at `started`.
fn report(run: &Run, input_vertices: usize, input_faces: usize, started: Instant) -> QemReport {
    QemReport {
        input_vertices,
        input_faces,
        collapses: run.collapses,
        vertices: run.mesh.positions.len(),
        faces: run.mesh.triangles.len(),
        max_error: run.max_error,
        seconds: started.elapsed().as_secs_f64(),
        target_reached: run.stop_reason == StopReason::TargetReached,
        stop_reason: run.stop_reason,
        rejected: run.rejected,
        virtual_pairs: run.virtual_pairs,
        passes: run.passes,
        max_relative_error: run.max_relative_error,
    }
}

/// What the passes made of one prepared mesh.
struct Run {
    /// The simplified mesh, model units.
    mesh: TriMesh,
    /// Contractions performed.
    collapses: usize,
    /// Contractions rejected by the topology / normal checks.
    rejected: usize,
    /// Largest cost of a performed contraction, model units⁴.
    max_error: f64,
    /// Contraction passes.
    passes: usize,
    /// Why the loop ended.
    stop_reason: StopReason,
    /// Non-edge pairs found.
    virtual_pairs: usize,
    /// With `max_relative_error`: the largest relative error of a performed contraction.
    max_relative_error: Option<f64>,
}

impl Run {
    /// `mesh` as it is (nothing was left to do).
    fn unchanged(mesh: TriMesh) -> Run {
        Run {
            mesh,
            collapses: 0,
            rejected: 0,
            max_error: 0.0,
            passes: 0,
            stop_reason: StopReason::NoValidPairs,
            virtual_pairs: 0,
            max_relative_error: None,
        }
    }
}

/// The largest pair threshold, in units of the bounding-box diagonal of the referenced vertices
/// (the normalised frame's unit): beyond it every vertex is within `t` of every other, so larger
/// values (a typo such as `1e30`) mean nothing more and are refused.
const MAX_PAIR_THRESHOLD: f64 = 1.0;
/// The largest `max_pairs_per_vertex`: the pair search and the pairs' memory grow with it.
const MAX_PAIRS_PER_VERTEX: usize = 64;

/// Refuse a pair threshold above [`MAX_PAIR_THRESHOLD`] diagonals of a mesh whose frame has
/// `scale` (1 / diagonal), naming the limit in model units (rounded down, so that the value shown
/// is accepted).
fn check_pair_threshold(t: f64, scale: f64) -> Result<(), QemError> {
    if t * scale <= MAX_PAIR_THRESHOLD {
        return Ok(());
    }
    let limit = MAX_PAIR_THRESHOLD / scale;
    // Six significant digits, rounded down.
    let digits = 5 - limit.log10().floor() as i32;
    let shown = if (0..=15).contains(&digits) {
        let unit = 10f64.powi(digits);
        format!("{:.*}", digits as usize, (limit * unit).floor() / unit)
    } else {
        format!("{limit:e}")
    };
    let t = if t >= 1e6 {
        format!("{t:e}")
    } else {
        t.to_string()
    };
    Err(QemError::InvalidParameter(format!(
        "pair threshold {t} is above the limit {shown}, the bounding-box diagonal of the mesh \
         (beyond it every vertex is paired with every other)"
    )))
}

pub(crate) fn validate(p: &QemParams) -> Result<(), QemError> {
    let bad = |s: String| Err(QemError::InvalidParameter(s));
    if let Target::Ratio(r) = p.target
        && !(r > 0.0 && r <= 1.0)
    {
        return bad(format!("target ratio {r} is not in (0, 1]"));
    }
    if !(p.pair_threshold >= 0.0 && p.pair_threshold.is_finite()) {
        return bad(format!(
            "pair threshold {} must be finite and >= 0",
            p.pair_threshold
        ));
    }
    if p.max_pairs_per_vertex > MAX_PAIRS_PER_VERTEX {
        return bad(format!(
            "max pairs per vertex {} is above the limit {MAX_PAIRS_PER_VERTEX}",
            p.max_pairs_per_vertex
        ));
    }
    if !(p.boundary_weight >= 0.0 && p.boundary_weight.is_finite()) {
        return bad(format!(
            "boundary weight {} must be finite and >= 0",
            p.boundary_weight
        ));
    }
    if !(p.seam_weight >= 0.0 && p.seam_weight.is_finite()) {
        return bad(format!(
            "seam weight {} must be finite and >= 0",
            p.seam_weight
        ));
    }
    if let Some(m) = p.max_error
        && m.is_nan()
    {
        return bad("max error is NaN".into());
    }
    if let Some(m) = p.max_relative_error
        && !(m >= 0.0 && m.is_finite())
    {
        return bad(format!(
            "max relative error {m} must be a finite share of the bounding-box diagonal >= 0"
        ));
    }
    let w = p.attribute_weights;
    for (name, v) in [("uv", w.uv), ("normal", w.normal), ("color", w.color)] {
        if !(v >= 0.0 && v.is_finite()) {
            return bad(format!(
                "attribute weight {name}={v} must be finite and >= 0"
            ));
        }
    }
    if !(p.edge_length_weight >= 0.0 && p.edge_length_weight.is_finite()) {
        return bad(format!(
            "edge length weight {} must be finite and >= 0",
            p.edge_length_weight
        ));
    }
    if !(-1.0..=1.0).contains(&p.min_normal_cos) {
        return bad(format!(
            "min_normal_cos {} is not in [-1, 1]",
            p.min_normal_cos
        ));
    }
    Ok(())
}
