//! The simplifier, as a list of named passes (the shape of meshoptimizer's `meshopt_simplify`):
//!
//! 1. [`prepare`]: validate, normalise, Morton renumbering, face sort, vertex → face lists;
//! 2. [`setup`]: per vertex, quadric, boundary planes and flag, edges;
//! 3. `passes::add_virtual_pairs`: non-edge pairs within `pair_threshold` (optional);
//! 4. initial costing and sort of the candidate list;
//! 5. the contraction loop: `Schedule::one_pass`, then either `Schedule::rebuild` after a stall
//!    or `Schedule::next_list` for the next pass;
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
//! This module holds the entry points only; passes 2–6 are in [`passes`]. No file imports from a
//! layer above its own, a `mod.rs` and its submodules included; bottom to top: (1) the shared
//! pieces, which import no other file of the simplifier: [`triangle`], [`vertex`], [`view`],
//! [`seams`], [`candidates`], [`resources`], [`prefetch`], [`checks`], [`outcome`]; (2)
//! [`prepare`]; (3) the attribute term and values: [`attribute_error`], [`wedges`] (`sides.rs`
//! and `untangle.rs`, then `mod.rs`, then `output.rs`, which borrows pieces of the engine); (4)
//! [`setup`] and the [`engine`] (`mod.rs`, then `stages.rs`); (5) [`passes`]; (6) the drivers
//! over the passes, [`partition`] and [`attributes`]; (7) this file.

mod attribute_error;
mod attributes;
mod candidates;
mod checks;
mod engine;
mod outcome;
mod partition;
mod passes;
mod prefetch;
mod prepare;
mod resources;
mod seams;
mod setup;
mod triangle;
mod vertex;
mod view;
mod wedges;

pub(crate) use checks::validate;

use crate::{QemError, QemParams, QemReport};
use checks::{check_cancel, check_lock_mask, check_pair_threshold};
use mesh::TriMesh;
use outcome::report;
use passes::simplify_prepared;
use std::time::Instant;

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
