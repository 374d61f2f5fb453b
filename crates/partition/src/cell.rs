//! Step 2: one cell simplified with its shared vertices locked, and its output chunk.
//!
//! Output chunk `cell-NNNNN.out`: the magic `GNG3DCL2`, the ratio it was simplified with (`f64`:
//! an output made for another target is not reused), `u32` vertex and face counts, the
//! vertices (a `u32` global id for a shared vertex, `u32::MAX` for one of this cell only, then
//! three `f32`), the triangles over those. Written to a temporary sibling and renamed, so an
//! output that exists is complete ([`CellChunk::output_complete`] checks its length and ratio).

use crate::PartitionError;
use crate::chunk::{CellChunk, VERTEX_RECORD, read_all};
use glam::Vec3;
use mesh::TriMesh;
use qem::{Lock, QemParams, Target};
use rustc_hash::FxHashMap;
use std::path::Path;

const MAGIC: &[u8; 8] = b"GNG3DCL2";
/// Bytes before the vertex records: magic, ratio, counts.
const HEADER: usize = 24;
/// The id of an output vertex that is not shared.
pub(crate) const OWN: u32 = u32::MAX;
/// A cell stops at this many times its share of the target (plus its locked band), so that the
/// final pass, which sees the whole surface, makes the last half of the collapses where they
/// cost least globally instead of where each cell's share forced them.
const CELL_SLACK: f64 = 2.0;

/// What [`simplify_cell`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct CellReport {
    /// Triangles of the cell.
    pub input_faces: usize,
    /// Its locked (shared) vertices.
    pub locked: usize,
    /// Triangles of its output.
    pub faces: usize,
}

impl CellChunk {
    /// Whether the cell's output exists, is whole and was made with `ratio` (a previous run
    /// finished this cell for the same target). Reads its header only.
    pub fn output_complete(&self, ratio: f64) -> bool {
        use std::io::Read;
        let mut header = [0u8; HEADER];
        let Ok(mut file) = std::fs::File::open(&self.output) else {
            return false;
        };
        let len = file.metadata().map_or(0, |m| m.len());
        file.read_exact(&mut header).is_ok() && parse_header(&header, len) == Some(ratio.to_bits())
    }
}

/// [`simplify_cell`], unless the cell's output from an earlier run with this `ratio` is
/// complete ([`CellChunk::output_complete`]): then `None`, and the cell is not redone (resume).
pub fn resume_or_simplify_cell(
    chunk: &CellChunk,
    ratio: f64,
) -> Result<Option<CellReport>, PartitionError> {
    if chunk.output_complete(ratio) {
        return Ok(None);
    }
    simplify_cell(chunk, ratio).map(Some)
}

/// Simplify one cell: read its chunks, lock its shared vertices, reduce it to
/// `ratio × (faces − band) × 2 + band` faces (`band`: the faces touching a locked vertex, which
/// the cell cannot reduce) and write its output chunk atomically. A function of the chunk files
/// only, so any process or worker with the work folder can run it.
pub fn simplify_cell(chunk: &CellChunk, ratio: f64) -> Result<CellReport, PartitionError> {
    let bad = |path: &Path, problem: &str| PartitionError::BadChunk {
        path: path.to_path_buf(),
        problem: problem.to_string(),
    };
    let bytes = read_all(&chunk.faces)?;
    if bytes.len() % 12 != 0 {
        return Err(bad(&chunk.faces, "length not a multiple of 12"));
    }
    let global_faces: Vec<[u32; 3]> = bytes
        .chunks_exact(12)
        .map(|t| [word(t, 0), word(t, 4), word(t, 8)])
        .collect();
    drop(bytes);
    // Local ids: this cell's own vertices, then the shared ones its faces use.
    let mut table = Vertices::default();
    table.read(&chunk.vertices, None)?;
    let own = table.gids.len();
    let mut needed: FxHashMap<u32, ()> = FxHashMap::default();
    for t in &global_faces {
        for &g in t {
            if !table.local.contains_key(&g) {
                needed.insert(g, ());
            }
        }
    }
    table.read(&chunk.shared, Some(&needed))?;
    let Vertices {
        local,
        gids,
        positions,
    } = table;
    let mut triangles = Vec::with_capacity(global_faces.len());
    for t in &global_faces {
        let mut out = [0u32; 3];
        for (o, g) in out.iter_mut().zip(t) {
            *o = *local
                .get(g)
                .ok_or_else(|| bad(&chunk.faces, "a face names a vertex of no chunk"))?;
        }
        triangles.push(out);
    }
    drop(global_faces);
    let locked: Vec<bool> = (0..gids.len()).map(|i| i >= own).collect();
    let band = triangles
        .iter()
        .filter(|t| t.iter().any(|&v| locked[v as usize]))
        .count();
    let input_faces = triangles.len();
    let target = (((input_faces - band) as f64 * ratio * CELL_SLACK).round() as usize + band)
        .min(input_faces);
    // The locked vertices, to be found in the output by position.
    let pinned: Vec<(u32, Vec3)> = (own..gids.len()).map(|i| (gids[i], positions[i])).collect();
    let diagonal = mesh::Aabb::from_points(&positions).diagonal();
    let locked_count = gids.len() - own;
    drop((gids, local));
    let cell = mesh::Model::from(TriMesh::new(positions, triangles));
    let params = QemParams {
        lock: Lock::Vertices(locked),
        ..QemParams::with_target(Target::Faces(target))
    };
    let coarse = match qem::simplify(&cell, &params) {
        Ok((model, _)) => model.mesh,
        // Every face of the cell degenerate: nothing of it remains.
        Err(qem::QemError::EmptyMesh) => TriMesh::new(Vec::new(), Vec::new()),
        Err(source) => {
            return Err(PartitionError::Qem {
                path: chunk.output.clone(),
                source,
            });
        }
    };
    drop(cell);
    let mut coarse = coarse;
    let ids = find_pinned(&mut coarse, &pinned, diagonal).ok_or_else(|| {
        bad(
            &chunk.output,
            "a locked vertex is missing from QEM's output",
        )
    })?;
    write_output(&chunk.output, ratio, &ids, &coarse)?;
    Ok(CellReport {
        input_faces,
        locked: locked_count,
        faces: coarse.face_count(),
    })
}

/// How far QEM may move a locked vertex, relative to the cell's diagonal: it computes in a
/// normalised `f64` frame and rounds back to `f32`, so a locked vertex comes back within a few
/// `f32` ulps of where it was, not always bit-exact, and in its own (Morton) order.
const PINNED_TOLERANCE: f64 = 1e-5;

/// The id of each vertex of `coarse`: the global id of the locked vertex of `pinned` it is (the
/// nearest output vertex within [`PINNED_TOLERANCE`] of it, which gets that vertex's exact
/// position back, so that every cell holding it agrees bit for bit), [`OWN`] for the others;
/// `None` when a locked vertex has no output vertex near it.
fn find_pinned(coarse: &mut TriMesh, pinned: &[(u32, Vec3)], diagonal: f64) -> Option<Vec<u32>> {
    let eps = (PINNED_TOLERANCE * diagonal).max(f64::from(f32::MIN_POSITIVE)) as f32;
    let key = |p: Vec3| (p / eps).floor().as_ivec3().to_array();
    let mut buckets: FxHashMap<[i32; 3], Vec<u32>> = FxHashMap::default();
    for (i, &p) in coarse.positions.iter().enumerate() {
        buckets.entry(key(p)).or_default().push(i as u32);
    }
    let mut ids = vec![OWN; coarse.positions.len()];
    for &(g, p) in pinned {
        let k = key(p);
        let mut best: Option<(f32, u32)> = None;
        for d in 0..27 {
            let at = [k[0] + d % 3 - 1, k[1] + d / 3 % 3 - 1, k[2] + d / 9 - 1];
            for &i in buckets.get(&at).map_or(&[][..], Vec::as_slice) {
                let dist = coarse.positions[i as usize].distance(p);
                if dist <= eps && best.is_none_or(|(b, _)| dist < b) {
                    best = Some((dist, i));
                }
            }
        }
        let (_, i) = best?;
        ids[i as usize] = g;
        coarse.positions[i as usize] = p;
    }
    Some(ids)
}

/// A cell's vertices: local id of each global id, and by local id the global id and position.
#[derive(Default)]
struct Vertices {
    local: FxHashMap<u32, u32>,
    gids: Vec<u32>,
    positions: Vec<Vec3>,
}

impl Vertices {
    /// Append the records of the vertex chunk `path` (with `wanted`: those it names only).
    fn read(
        &mut self,
        path: &Path,
        wanted: Option<&FxHashMap<u32, ()>>,
    ) -> Result<(), PartitionError> {
        let bytes = read_all(path)?;
        if bytes.len() % VERTEX_RECORD != 0 {
            return Err(PartitionError::BadChunk {
                path: path.to_path_buf(),
                problem: "length not a multiple of 16".to_string(),
            });
        }
        for r in bytes.chunks_exact(VERTEX_RECORD) {
            let g = word(r, 0);
            if wanted.is_some_and(|w| !w.contains_key(&g)) {
                continue;
            }
            let p = [4, 8, 12].map(|i| f32::from_bits(word(r, i)));
            self.local.insert(g, self.gids.len() as u32);
            self.gids.push(g);
            self.positions.push(Vec3::from(p));
        }
        Ok(())
    }
}

/// The little-endian `u32` at `i`.
fn word(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]])
}

/// The ratio (as bits) of an output chunk whose first bytes are `header` and whose length is
/// `len`, when they fit together.
fn parse_header(header: &[u8], len: u64) -> Option<u64> {
    if header.len() < HEADER || &header[..8] != MAGIC {
        return None;
    }
    let ratio = u64::from_le_bytes(header[8..16].try_into().ok()?);
    let (nv, nf) = (u64::from(word(header, 16)), u64::from(word(header, 20)));
    (len == HEADER as u64 + nv * VERTEX_RECORD as u64 + nf * 12).then_some(ratio)
}

fn write_output(
    path: &Path,
    ratio: f64,
    ids: &[u32],
    mesh: &TriMesh,
) -> Result<(), PartitionError> {
    let mut bytes =
        Vec::with_capacity(HEADER + ids.len() * VERTEX_RECORD + mesh.triangles.len() * 12);
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&ratio.to_bits().to_le_bytes());
    bytes.extend_from_slice(&(ids.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&(mesh.triangles.len() as u32).to_le_bytes());
    for (&g, p) in ids.iter().zip(&mesh.positions) {
        bytes.extend_from_slice(&g.to_le_bytes());
        for c in p.to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    for t in &mesh.triangles {
        for v in t {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    mesh::io::write_atomic(path, &bytes)?;
    Ok(())
}

/// A cell's output made with `ratio`: the ids ([`OWN`] or a global id) and positions of its
/// vertices, and its triangles over them (range-checked).
pub(crate) fn read_output(path: &Path, ratio: f64) -> Result<(Vec<u32>, TriMesh), PartitionError> {
    let bad = |problem: &str| PartitionError::BadChunk {
        path: path.to_path_buf(),
        problem: problem.to_string(),
    };
    let bytes = read_all(path)?;
    match parse_header(&bytes, bytes.len() as u64) {
        None => {
            return Err(bad(
                "no GNG3DCL2 header, or a length that does not match its counts",
            ));
        }
        Some(r) if r != ratio.to_bits() => return Err(bad("made for another target")),
        Some(_) => {}
    }
    let (nv, nf) = (word(&bytes, 16) as usize, word(&bytes, 20) as usize);
    let mut ids = Vec::with_capacity(nv);
    let mut positions = Vec::with_capacity(nv);
    for i in 0..nv {
        let at = HEADER + i * VERTEX_RECORD;
        ids.push(word(&bytes, at));
        positions.push(Vec3::from(
            [4, 8, 12].map(|o| f32::from_bits(word(&bytes, at + o))),
        ));
    }
    let base = HEADER + nv * VERTEX_RECORD;
    let mut triangles = Vec::with_capacity(nf);
    for f in 0..nf {
        let t = [0, 4, 8].map(|o| word(&bytes, base + 12 * f + o));
        if t.iter().any(|&v| v as usize >= nv) {
            return Err(bad("a triangle names a vertex it does not hold"));
        }
        triangles.push(t);
    }
    Ok((ids, TriMesh::new(positions, triangles)))
}
