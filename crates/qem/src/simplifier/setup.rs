//! The vertex setup pass: per vertex, its area-weighted plane quadric, the boundary planes of its
//! boundary edges, its boundary flag and its edges to higher-numbered neighbours, each vertex an
//! independent task (parallel for large meshes; the result does not depend on the thread count).

use super::candidates::Cand;
use super::resources::{PARALLEL_CHUNK, PARALLEL_MIN, parallel};
use super::seams::Seams;
use super::vertex::Vertex;
use crate::{QemParams, Quadric};
use glam::DVec3;
use rayon::prelude::*;

/// What [`vertex_setup`] produces.
pub(super) struct VertexSetup {
    /// Per vertex: position, quadric (face planes plus boundary planes), face list (`len` faces
    /// from `face_start`), valence and boundary flag.
    pub(super) vx: Vec<Vertex>,
    /// The mesh edges `(u, v)`, `u < v`, in order of `u` (costs not yet evaluated).
    pub(super) list: Vec<Cand>,
}

/// Up to this many faces around a vertex, [`vertex_setup`] finds ring neighbours by linear search.
const RING_SEARCH_MAX: usize = 32;
/// Vertices per parallel task of [`vertex_setup`].
const VERTEX_CHUNK: usize = 2_048;

/// Per-vertex setup over the vertex → face lists `refs` (vertex `u`'s faces start at
/// `face_start[u]`), one independent task per chunk of vertices: each vertex sums the area-weighted
/// plane quadrics of its faces (every face's plane is computed by each of its corners, identically)
/// and, from its ring of distinct neighbours with the number of faces on each edge, gets its
/// boundary flag, the perpendicular boundary planes of its boundary edges (computed from the
/// lower-numbered end, so both ends add the same plane) and its edges to higher-numbered vertices
/// (not those with a `locked` end, nor those the attribute `seams` forbid).
pub(super) fn vertex_setup(
    pos: &[DVec3],
    faces: &[[u32; 3]],
    refs: &[u32],
    face_start: &[u32],
    params: &QemParams,
    locked: Option<&[bool]>,
    seams: Option<&Seams>,
) -> VertexSetup {
    let is_locked = |v: usize| locked.is_some_and(|l| l[v]);
    let seams_allow = |u: usize, v: usize| seams.is_none_or(|s| s.pair_ok(u, v));
    let n = pos.len();
    // Face planes scaled so that the plane quadric is their outer product (the shared
    // definition GNG3D-Q's placement uses too; zero for degenerate faces).
    let plane = |t: &[u32; 3]| -> [f64; 4] {
        let [p0, p1, p2] = t.map(|w| pos[w as usize]);
        mesh::quadric::area_weighted_plane(p0, p1, p2)
    };
    let in_parallel = parallel(n, PARALLEL_MIN / 4);
    // On a pool, every face's plane is computed once into a buffer the tasks read; on one
    // thread, where the vertices are visited in order, only a window of them is kept for large
    // meshes (see `Planes`), without the buffer's 32 B a face beside the records (the one-thread
    // peak of the set-up on igea-1m until 2026-12-05).
    let windowed = !in_parallel && faces.len() >= WINDOWED_MIN_FACES;
    let planes: Vec<[f64; 4]> = if windowed {
        Vec::new()
    } else if parallel(faces.len(), PARALLEL_MIN) {
        faces
            .par_iter()
            .with_min_len(PARALLEL_CHUNK)
            .map(plane)
            .collect()
    } else {
        faces.iter().map(plane).collect()
    };
    let mut vx: Vec<Vertex> = Vec::with_capacity(n);
    let chunk = |first: usize, out: &mut [std::mem::MaybeUninit<Vertex>]| {
        let mut window = Planes::new(&planes, faces.len());
        let mut edges = Vec::with_capacity(out.len() * 3 + 16);
        // (neighbour, faces on the edge, last such face)
        let mut ring: Vec<(u32, u32, u32)> = Vec::with_capacity(64);
        for (k, slot) in out.iter_mut().enumerate() {
            let u = first + k;
            let uu = u as u32;
            let list = &refs[face_start[u] as usize..face_start[u + 1] as usize];
            let mut q = Quadric::default();
            ring.clear();
            for &f in list {
                let tri = faces[f as usize];
                let [gx, gy, gz, gd] = window.get(f as usize, |g| plane(&faces[g]));
                q += Quadric::from_plane(DVec3::new(gx, gy, gz), gd, 1.0);
                // The two other corners (every face in the list has `u` exactly once).
                let others = if tri[0] == uu {
                    [tri[1], tri[2]]
                } else if tri[1] == uu {
                    [tri[2], tri[0]]
                } else {
                    [tri[0], tri[1]]
                };
                if list.len() <= RING_SEARCH_MAX {
                    for v in others {
                        match ring.iter_mut().find(|r| r.0 == v) {
                            Some(r) => {
                                r.1 += 1;
                                r.2 = f;
                            }
                            None => ring.push((v, 1, f)),
                        }
                    }
                } else {
                    ring.extend(others.map(|v| (v, 1, f)));
                }
            }
            if list.len() > RING_SEARCH_MAX {
                // High valence: group by sorting instead of searching (stable: keeps the last face).
                ring.sort_by_key(|r| r.0);
                let mut w = 0;
                for r in 0..ring.len() {
                    if w > 0 && ring[w - 1].0 == ring[r].0 {
                        ring[w - 1].1 += 1;
                        ring[w - 1].2 = ring[r].2;
                    } else {
                        ring[w] = ring[r];
                        w += 1;
                    }
                }
                ring.truncate(w);
            }
            let mut on_boundary = false;
            for &(v, count, f) in &ring {
                on_boundary |= count != 2;
                if count == 1 && params.preserve_boundary {
                    let (lo, hi) = (uu.min(v) as usize, uu.max(v) as usize);
                    let [p0, p1, p2] = faces[f as usize].map(|w| pos[w as usize]);
                    let face_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                    let edge = pos[hi] - pos[lo];
                    let m = edge.cross(face_normal).normalize_or_zero();
                    if m != DVec3::ZERO {
                        let w = params.boundary_weight * edge.length_squared();
                        q += Quadric::from_plane(m, -m.dot(pos[lo]), w);
                    }
                }
                if v > uu && !is_locked(u) && !is_locked(v as usize) && seams_allow(u, v as usize) {
                    edges.push(Cand::pair(uu, v));
                }
            }
            slot.write(Vertex {
                p: pos[u],
                mark: 0,
                valence: list.len() as u32,
                q,
                start: face_start[u],
                len: list.len() as u32,
                touched: 0,
                alive: true,
                boundary: on_boundary,
                locked: is_locked(u),
            });
        }
        edges
    };
    let out = &mut vx.spare_capacity_mut()[..n];
    let lists: Vec<Vec<Cand>> = if in_parallel {
        out.par_chunks_mut(VERTEX_CHUNK)
            .enumerate()
            .map(|(c, o)| chunk(c * VERTEX_CHUNK, o))
            .collect()
    } else {
        vec![chunk(0, out)]
    };
    // SAFETY: every chunk wrote each of its slots exactly once, and the chunks cover `0..n`.
    unsafe { vx.set_len(n) };
    let list = if lists.len() == 1 {
        lists.into_iter().next().unwrap_or_default()
    } else {
        let mut list = Vec::with_capacity(lists.iter().map(Vec::len).sum());
        for l in &lists {
            list.extend_from_slice(l);
        }
        list
    };
    VertexSetup { vx, list }
}

/// Faces whose planes [`Planes`] keeps on one thread (2 MiB).
const PLANE_WINDOW: usize = 1 << 16;
/// Below this many faces the planes are all kept on one thread too: the buffer is not at a peak
/// that matters there (12 MiB at most), and on armadillo the window was not measurably faster
/// (±2 % noise); the output is the same either way.
const WINDOWED_MIN_FACES: usize = 400_000;

/// The face planes the vertex set-up reads: all of them, computed beforehand (on a pool), or a
/// window of the most recent ones (on one thread, vertices in order). Faces are sorted by their
/// smallest vertex, so all faces of vertex `u` lie in the blocks of vertices up to `u`, and the
/// largest face index read only moves forward as the vertices are visited in order: the window
/// computes each plane once as it does, and a face more than [`PLANE_WINDOW`] behind it (a Morton
/// neighbour far away in index order; rare) is computed again. The same function of the same
/// corners: the same bits either way.
struct Planes<'a> {
    /// All planes (empty: windowed).
    all: &'a [[f64; 4]],
    /// Plane of face `f` at `f % ring.len()` (a power of two), for the last `ring.len()` faces
    /// below `computed`.
    ring: Vec<[f64; 4]>,
    /// Faces below this have been computed into the ring.
    computed: usize,
}

impl<'a> Planes<'a> {
    fn new(all: &'a [[f64; 4]], faces: usize) -> Planes<'a> {
        let ring = if all.is_empty() {
            vec![[0.0; 4]; faces.next_power_of_two().min(PLANE_WINDOW)]
        } else {
            Vec::new()
        };
        Planes {
            all,
            ring,
            computed: 0,
        }
    }

    /// The plane of face `f`, by `plane` when not stored.
    #[inline]
    fn get(&mut self, f: usize, plane: impl Fn(usize) -> [f64; 4]) -> [f64; 4] {
        if !self.all.is_empty() {
            return self.all[f];
        }
        let w = self.ring.len();
        if f >= self.computed {
            for g in self.computed.max((f + 1).saturating_sub(w))..=f {
                self.ring[g & (w - 1)] = plane(g);
            }
            self.computed = f + 1;
        } else if f + w < self.computed {
            return plane(f);
        }
        self.ring[f & (w - 1)]
    }
}

/// Seam constraint planes: for each seam edge `[u, v]` (prepared numbering), the plane through
/// the edge perpendicular to its two faces' mean normal, weighted by
/// `params.seam_weight × |edge|²` (as a boundary edge's by `boundary_weight`), added to both
/// ends' quadrics.
pub(super) fn seam_planes(
    vx: &mut [Vertex],
    pos: &[DVec3],
    faces: &[[u32; 3]],
    refs: &[u32],
    face_start: &[u32],
    edges: &[[u32; 2]],
    params: &QemParams,
) {
    for &[u, v] in edges {
        let (u, v) = (u as usize, v as usize);
        let end = face_start.get(u + 1).map_or(refs.len(), |&e| e as usize);
        let mut normal = DVec3::ZERO;
        for &f in &refs[face_start[u] as usize..end] {
            let t = faces[f as usize];
            if t.contains(&(v as u32)) {
                let [p0, p1, p2] = t.map(|w| pos[w as usize]);
                normal += (p1 - p0).cross(p2 - p0).normalize_or_zero();
            }
        }
        let edge = pos[v] - pos[u];
        let m = edge.cross(normal).normalize_or_zero();
        if m != DVec3::ZERO {
            let w = params.seam_weight * edge.length_squared();
            let q = Quadric::from_plane(m, -m.dot(pos[u]), w);
            vx[u].q += q;
            vx[v].q += q;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_plane_window_returns_each_face_s_own_plane() {
        let faces = 3 * PLANE_WINDOW + 17;
        let plane = |g: usize| [g as f64, 1.0, -(g as f64), 0.5];
        let mut window = Planes::new(&[], faces);
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        let mut top = 0usize;
        while top < faces {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Mostly forward in small steps; now and then a face far behind (outside the
            // window) or a jump ahead past the whole window.
            let f = match x % 16 {
                0 => (top as u64 * (x >> 40) / (1 << 24)) as usize,
                1 => (top + PLANE_WINDOW + 5).min(faces - 1),
                _ => (top + (x >> 60) as usize).min(faces - 1),
            };
            top = top.max(f) + 1;
            assert_eq!(window.get(f, plane), plane(f), "face {f}");
            let back = f.saturating_sub((x >> 50) as usize % PLANE_WINDOW);
            assert_eq!(window.get(back, plane), plane(back), "face {back}");
        }
    }
}
