//! Parallel simplification of large meshes by spatial partition (the scheme of cluster-level LOD
//! builds): the Morton-ordered vertices are cut into `parts` equal index ranges (i.e. spatial
//! blocks), every face goes to the part of its smallest vertex, each part is simplified to its
//! share of the target on its own thread with the vertices it shares with another part locked,
//! and one sequential run over the stitched result finishes the borders down to the exact target.
//!
//! Used only when the rayon pool has more than one thread and the mesh has at least
//! [`PARTITION_MIN_FACES`] faces, so the output of `RAYON_NUM_THREADS=1` is the sequential one;
//! with more threads it depends on the number of parts (`threads`, at most [`MAX_PARTS`]). What
//! it costs in Hausdorff distance is measured in docs/notes/qem.md.

use super::checks::check_cancel;
use super::outcome::Run;
use super::passes::simplify_prepared;
use super::prepare::{self, Prepared};
use super::resources::{release_freed_memory, sequential};
use crate::{QemError, QemParams, Target};
use glam::DVec3;
use mesh::TriMesh;
use rayon::prelude::*;

/// Smaller meshes are simplified sequentially: below this the final border pass and the stitching
/// cost more than the second thread saves.
pub(super) const PARTITION_MIN_FACES: usize = 500_000;
/// At most this many parts (more parts mean more locked border and a longer final pass).
const MAX_PARTS: usize = 8;

/// How [`run`] cuts a mesh: the number of parts, the range of faces of each part (`bounds[k]..
/// bounds[k + 1]`) and, per vertex, the parts that reference it (bit `k`: part `k`).
pub(super) struct Plan {
    parts: usize,
    bounds: Vec<usize>,
    mask: Vec<u8>,
}

/// The cut of `prepared` if it is simplified by parts with `params`: large enough, more than one
/// thread, no non-edge pairs (those could cross a cut), and at most half of the faces in the
/// parts' locked bands. A part cannot touch the faces around the vertices it shares, so where
/// the bands are most of the mesh the parts are pure overhead before the sequential run: on a
/// fan of 1,000,000 triangles around one hub every face has the shared hub (issue 33: 1.01 s on
/// two threads against 0.87 s on one; igea-1m's bands are about 1 % of its faces).
pub(super) fn plan(prepared: &Prepared, params: &QemParams) -> Option<Plan> {
    let worth_it = prepared.faces.len() >= PARTITION_MIN_FACES
        && params.pair_threshold <= 0.0
        && rayon::current_num_threads() > 1;
    if !worth_it {
        return None;
    }
    let parts = rayon::current_num_threads().clamp(2, MAX_PARTS);
    let (faces, n) = (&prepared.faces, prepared.pos.len());
    let smallest = |t: &[u32; 3]| t[0].min(t[1]).min(t[2]) as usize;
    let bounds: Vec<usize> = (0..=parts)
        .map(|k| faces.partition_point(|t| smallest(t) < n * k / parts))
        .collect();
    let mut mask = vec![0u8; n];
    for k in 0..parts {
        for t in &faces[bounds[k]..bounds[k + 1]] {
            for &v in t {
                mask[v as usize] |= 1 << k;
            }
        }
    }
    let shared = |v: u32| mask[v as usize].count_ones() > 1;
    let band = faces
        .iter()
        .filter(|t| t.iter().any(|&v| shared(v)))
        .count();
    (2 * band <= faces.len()).then_some(Plan {
        parts,
        bounds,
        mask,
    })
}

/// One part: its vertices (global indices, increasing) and their positions, its faces over local
/// indices, and which of its vertices are shared with another part.
struct Part {
    globals: Vec<u32>,
    /// Positions of `globals` (normalised frame).
    pos: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
    locked: Vec<bool>,
}

/// Simplify `prepared` by parts as `plan` cuts it, then finish the borders sequentially.
/// The only error is [`QemError::Cancelled`].
pub(super) fn run(prepared: Prepared, params: &QemParams, plan: Plan) -> Result<Run, QemError> {
    let n = prepared.pos.len();
    let input_faces = prepared.faces.len();
    let target_faces = match params.target {
        Target::Faces(f) => f,
        Target::Ratio(r) => ((input_faces as f64) * r).round() as usize,
        Target::Vertices(_) => usize::MAX,
    };
    let Prepared {
        pos,
        faces,
        refs,
        face_start,
        frame,
    } = prepared;
    drop((refs, face_start)); // each part builds its own face lists
    // Each part copies its positions here, so that the global ones are gone before the parts
    // run (they used to copy them at their start: 24 B a vertex more at the two-thread peak).
    check_cancel(params)?;
    let parts = split(&pos, &faces, plan);
    drop((faces, pos));
    check_cancel(params)?;
    release_freed_memory();
    check_cancel(params)?;
    let results: Vec<(Run, Vec<u32>)> = parts
        .into_par_iter()
        .map(|part| {
            let Part {
                globals,
                pos: part_pos,
                faces,
                locked,
            } = part;
            // Each part is reduced like the whole, except for the band of faces around its
            // locked vertices, which it cannot touch: that band is left at full density for the
            // final pass, so the part's target is `ratio × (rest) + band`.
            let band_faces = faces
                .iter()
                .filter(|t| t.iter().any(|&v| locked[v as usize]))
                .count();
            let band_vertices = locked.iter().filter(|&&l| l).count();
            let share = |want: usize, total: usize, own: usize, band: usize| {
                let ratio = want.min(total) as f64 / total as f64;
                ((own - band) as f64 * ratio).round() as usize + band
            };
            let target = match params.target {
                Target::Vertices(v) => Target::Vertices(share(v, n, globals.len(), band_vertices)),
                _ => Target::Faces(share(target_faces, input_faces, faces.len(), band_faces)),
            };
            let part_params = QemParams {
                target,
                ..params.clone()
            };
            let mesh::topology::VertexFaces {
                start: face_start,
                faces: refs,
            } = mesh::topology::VertexFaces::new(&faces, part_pos.len());
            let sub = Prepared {
                pos: part_pos,
                faces,
                refs,
                face_start,
                frame,
            };
            check_cancel(params)?;
            let (run, kept) = sequential(|| simplify_prepared(sub, &part_params, Some(&locked)))?;
            let kept = kept.iter().map(|&l| globals[l as usize]).collect();
            Ok((run, kept))
        })
        .collect::<Result<_, QemError>>()?;
    // Stitch: shared (locked) vertices were not moved, so both sides hold the same position.
    let mut slot = vec![u32::MAX; n];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for (run, kept) in &results {
        let local: Vec<u32> = kept
            .iter()
            .zip(&run.mesh.positions)
            .map(|(&g, &p)| {
                let s = &mut slot[g as usize];
                if *s == u32::MAX {
                    *s = positions.len() as u32;
                    positions.push(p);
                }
                *s
            })
            .collect();
        triangles.extend(
            run.mesh
                .triangles
                .iter()
                .map(|t| t.map(|v| local[v as usize])),
        );
    }
    drop(slot);
    let stitched = TriMesh::new(positions, triangles);
    let final_params = QemParams {
        target: match params.target {
            Target::Vertices(v) => Target::Vertices(v),
            _ => Target::Faces(target_faces),
        },
        ..params.clone()
    };
    let mut last = match prepare::prepare(&stitched) {
        Ok(p) => simplify_prepared(p, &final_params, None)?.0,
        // Only reachable if every part collapsed to nothing; report the stitched result as is.
        Err(_) => Run::unchanged(stitched),
    };
    for (run, _) in &results {
        last.collapses += run.collapses;
        last.rejected += run.rejected;
        last.max_error = last.max_error.max(run.max_error);
        if let Some(r) = run.max_relative_error {
            last.max_relative_error = Some(last.max_relative_error.unwrap_or(0.0).max(r));
        }
    }
    last.passes += results.iter().map(|(r, _)| r.passes).max().unwrap_or(0);
    Ok(last)
}

/// Cut the vertex range `0..n` into `plan.parts` equal blocks; a face belongs to the block of its
/// smallest vertex (the faces are sorted by it, so each part's faces are a contiguous range).
fn split(pos: &[DVec3], faces: &[[u32; 3]], plan: Plan) -> Vec<Part> {
    let n = pos.len();
    let Plan {
        parts,
        bounds,
        mask,
    } = plan;
    (0..parts)
        .into_par_iter()
        .map(|k| {
            // Every vertex of part k is at least its block's first index (faces go by smallest).
            let first = n * k / parts;
            let bit = 1u8 << k;
            let mut local = vec![u32::MAX; n - first];
            let mut globals = Vec::new();
            for v in first..n {
                if mask[v] & bit != 0 {
                    local[v - first] = globals.len() as u32;
                    globals.push(v as u32);
                }
            }
            let faces = faces[bounds[k]..bounds[k + 1]]
                .iter()
                .map(|t| t.map(|v| local[v as usize - first]))
                .collect();
            let locked = globals
                .iter()
                .map(|&g| mask[g as usize].count_ones() > 1)
                .collect();
            Part {
                pos: globals.iter().map(|&g| pos[g as usize]).collect(),
                globals,
                faces,
                locked,
            }
        })
        .collect()
}
