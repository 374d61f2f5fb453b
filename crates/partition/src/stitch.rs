//! Steps 3 and 4: the cells' outputs stitched into one mesh by global vertex id, and the final
//! unlocked QEM pass down to the exact target.

use crate::cell::{OWN, read_output};
use crate::{Manifest, PartitionError};
use mesh::TriMesh;
use qem::{QemParams, Target};
use rustc_hash::FxHashMap;
use std::path::Path;

/// Step 3: join the outputs of the cells of `manifest` in `work`, simplified with `ratio` (an
/// output made with another is refused). A shared vertex (locked in
/// every cell that has it, so at the same position on every side) becomes one vertex; the
/// others are each cell's own. Cells are joined in order, so the result is the same for any
/// order in which they were simplified.
pub fn stitch(work: &Path, manifest: &Manifest, ratio: f64) -> Result<TriMesh, PartitionError> {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    let mut shared: FxHashMap<u32, u32> = FxHashMap::default();
    for k in 0..manifest.cell_faces.len() {
        if manifest.cell_faces[k] == 0 {
            continue;
        }
        let path = manifest.chunk(work, k).output;
        let (ids, cell) = read_output(&path, ratio)?;
        let mut index = Vec::with_capacity(ids.len());
        for (&g, &p) in ids.iter().zip(&cell.positions) {
            let next = positions.len() as u32;
            let i = if g == OWN {
                next
            } else {
                let i = *shared.entry(g).or_insert(next);
                if i != next && positions[i as usize] != p {
                    return Err(PartitionError::BadChunk {
                        path,
                        problem: format!("shared vertex {g} moved"),
                    });
                }
                i
            };
            if i == next {
                positions.push(p);
            }
            index.push(i);
        }
        triangles.extend(cell.triangles.iter().map(|t| t.map(|v| index[v as usize])));
    }
    Ok(TriMesh::new(positions, triangles))
}

/// Step 4: simplify the stitched mesh with nothing locked to `target` (a ratio is of the
/// input's faces, `manifest.faces`). `output` only names the run in an error.
pub fn finish(
    stitched: TriMesh,
    target: Target,
    manifest: &Manifest,
    output: &Path,
) -> Result<TriMesh, PartitionError> {
    let target = match target {
        Target::Ratio(r) => Target::Faces((manifest.faces as f64 * r).round() as usize),
        t => t,
    };
    let params = QemParams::with_target(target);
    qem::simplify(&mesh::Model::from(stitched), &params)
        .map(|(m, _)| m.mesh)
        .map_err(|source| PartitionError::Qem {
            path: output.to_path_buf(),
            source,
        })
}
