//! Phase-2 attach step: every trained node becomes an output vertex (the exact vertex count).
//! A node that no surviving triangle references is inserted into the nearest output triangle
//! around its cell by an edge or a face split.

use super::{Candidate, half_edges};
use glam::{DVec3, Vec3};
use mesh::TriMesh;
use mesh::geometry::closest_point_triangle;

/// Share of a triangle's area below which the opposite corner's barycentric weight counts as
/// "on the edge": the node is then inserted by splitting that edge (two faces into four, or a
/// boundary face into two) instead of the face (one into three), which avoids the needle
/// triangles a face split next to an edge would make.
const EDGE_SPLIT_WEIGHT: f64 = 0.2;

/// An attached node is put on its split edge no nearer to an end than this share of the edge,
/// and on its split face at this blend toward the centroid: the nearest point is often a corner
/// (the node lies beyond it), and a node put there would make zero-area triangles
/// (fandisk at 50 %: 10 degenerate faces without it).
const SPLIT_POINT_MARGIN: f64 = 0.25;

/// Step: every node an output vertex. A node whose cell produced no surviving triangle (its
/// labels fell into degenerate, merged or fin faces; or no vertex chose it) is inserted into the
/// output triangle nearest to it among those around its cell (triangles of its GNG neighbours
/// and of the nodes labelling vertices next to its cell); nodes with no such triangle yet wait
/// for their neighbours, and as a last resort take the nearest triangle of their own piece
/// (`node_comp`), never one of another piece.
/// Edge and face splits keep a closed manifold closed, manifold and consistently oriented.
///
/// An attached node is moved onto the point of the triangle it split (`nodes` is updated):
/// such a node won no original vertex, so its trained position says nothing about the surface,
/// and it may sit far off it (a node inserted late, between two nodes across a concavity; on
/// fandisk at 50 % one sat 6 % of the bounding-box diagonal away and set the Hausdorff max).
/// On the triangle it adds no deviation. Returns the attachments in the order they were made,
/// so a later placement can move the node with its triangle ([`Attachment`]).
pub(crate) fn attach_unreferenced(
    faces: &mut Vec<Candidate>,
    nodes: &mut [Vec3],
    edges: &[[u32; 2]],
    original: &TriMesh,
    labels: &[u32],
    node_comp: &[u32],
) -> Vec<Attachment> {
    let mut referenced = vec![false; nodes.len()];
    for c in faces.iter() {
        for &v in &c.tri {
            referenced[v as usize] = true;
        }
    }
    let missing: Vec<u32> = (0..nodes.len() as u32)
        .filter(|&v| !referenced[v as usize])
        .collect();
    let mut attached = Vec::new();
    if missing.is_empty() || faces.is_empty() {
        return attached;
    }
    // Nodes near each missing node: GNG neighbours and labels adjacent to its cell.
    let mut slot = vec![u32::MAX; nodes.len()];
    for (k, &m) in missing.iter().enumerate() {
        slot[m as usize] = k as u32;
    }
    let mut near: Vec<Vec<u32>> = vec![Vec::new(); missing.len()];
    for e in edges {
        for (a, b) in [(e[0], e[1]), (e[1], e[0])] {
            if (a as usize) < slot.len() && slot[a as usize] != u32::MAX {
                near[slot[a as usize] as usize].push(b);
            }
        }
    }
    for t in &original.triangles {
        let l = t.map(|v| labels[v as usize]);
        for k in 0..3 {
            let a = l[k];
            if a != u32::MAX && slot[a as usize] != u32::MAX {
                for &b in &[l[(k + 1) % 3], l[(k + 2) % 3]] {
                    if b != a && b != u32::MAX {
                        near[slot[a as usize] as usize].push(b);
                    }
                }
            }
        }
    }
    for n in &mut near {
        n.sort_unstable();
        n.dedup();
    }
    // Faces around each node, kept up to date by the splits.
    let mut vf =
        mesh::topology::VertexFaces::grouped(nodes.len(), faces.len(), |f| faces[f].tri).to_lists();
    let mut pending: Vec<u32> = missing;
    let mut candidates: Vec<u32> = Vec::new();
    // The nearest face of the node's piece, over all of them, for the nodes whose
    // neighbourhood has none (built when the first such node comes).
    let mut global: Option<FaceGrid> = None;
    while !pending.is_empty() {
        let before = pending.len();
        let mut next = Vec::new();
        for &m in &pending {
            let p = nodes[m as usize].as_dvec3();
            let best = if let Some(grid) = &mut global {
                let c = node_comp[m as usize];
                grid.nearest(p, faces, nodes, |f| {
                    node_comp[faces[f as usize].tri[0] as usize] == c
                })
            } else {
                candidates.clear();
                for &x in &near[slot[m as usize] as usize] {
                    candidates.extend_from_slice(&vf[x as usize]);
                }
                candidates.sort_unstable();
                candidates.dedup();
                candidates
                    .iter()
                    .map(|&f| distance_to_face(p, faces, nodes, f))
                    .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)))
            };
            let Some((_, f, q)) = best else {
                next.push(m);
                continue;
            };
            let added = faces.len();
            let at = split_for(faces, &mut vf, nodes, f, m, q);
            nodes[m as usize] = at.point(nodes).as_vec3();
            // The split's new faces lie inside the faces they came from; the grid takes them
            // at their own cells (a split face keeps its cells: it only shrank).
            if let Some(grid) = &mut global {
                for g in added..faces.len() {
                    grid.insert(g as u32, faces, nodes);
                }
            }
            attached.push(at);
        }
        pending = next;
        if pending.len() == before {
            if global.is_some() {
                break;
            }
            global = Some(FaceGrid::new(faces, nodes));
        }
    }
    attached
}

/// Squared distance from `p` to face `f`, the face, and its closest point.
fn distance_to_face(p: DVec3, faces: &[Candidate], nodes: &[Vec3], f: u32) -> (f64, u32, DVec3) {
    let [a, b, c] = faces[f as usize].tri.map(|v| nodes[v as usize].as_dvec3());
    let q = closest_point_triangle(p, a, b, c);
    ((q - p).length_squared(), f, q)
}

/// Faces by the cells of a uniform grid that their bounding boxes overlap, for the exact
/// nearest face of a node far from every face near it (nodes whose cells lost all their
/// vertices, e.g. detail nodes relabelled away). Scanning every face for each of those cost
/// armadillo at 50 % 0.7-0.9 s in each of its last two builds (3,000 nodes attached); the
/// grid visits rings of cells around the node until the next ring is farther than the best
/// face, so the answer is the same face (ties by index).
struct FaceGrid {
    min: DVec3,
    cell: f64,
    dims: [usize; 3],
    cells: Vec<Vec<u32>>,
    /// Stamp of the query that last visited each face (faces sit in several cells).
    seen: Vec<u32>,
    query: u32,
}

impl FaceGrid {
    /// A grid of cells about twice a typical face across (at most ~4 cells a face).
    fn new(faces: &[Candidate], nodes: &[Vec3]) -> FaceGrid {
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        let mut area = 0.0;
        for c in faces {
            let [a, b, d] = c.tri.map(|v| nodes[v as usize].as_dvec3());
            lo = lo.min(a).min(b).min(d);
            hi = hi.max(a).max(b).max(d);
            area += 0.5 * (b - a).cross(d - a).length();
        }
        let n = faces.len().max(1);
        let extent = (hi - lo).max(DVec3::splat(0.0));
        let mut cell = 2.0 * (2.0 * area / n as f64).sqrt();
        if !(cell > 0.0 && cell.is_finite()) {
            cell = extent.max_element().max(f64::MIN_POSITIVE);
        }
        let dims_for = |cell: f64| {
            (extent / cell)
                .floor()
                .as_uvec3()
                .to_array()
                .map(|d| d as usize + 1)
        };
        let mut dims = dims_for(cell);
        // Counted in f64: three dimensions of up to 2^32 cells each (a cell size far below
        // the extent, from near-zero-area faces) overflowed the usize product to 0 and left
        // the grid without cells (found by the CLI fuzz).
        let cell_count = |dims: [usize; 3]| dims.iter().map(|&d| d as f64).product::<f64>();
        while cell_count(dims) > (4 * n + 64) as f64 {
            cell *= 1.5;
            dims = dims_for(cell);
        }
        let mut grid = FaceGrid {
            min: lo,
            cell,
            dims,
            cells: vec![Vec::new(); dims.iter().product()],
            seen: Vec::new(),
            query: 0,
        };
        for f in 0..faces.len() as u32 {
            grid.insert(f, faces, nodes);
        }
        grid
    }

    /// Cell coordinates of `p`, clamped to the grid.
    fn coords(&self, p: DVec3) -> [usize; 3] {
        let c = ((p - self.min) / self.cell).floor();
        [0, 1, 2].map(|k| (c[k].max(0.0) as usize).min(self.dims[k] - 1))
    }

    fn index(&self, c: [usize; 3]) -> usize {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    /// Register face `f` in every cell its bounding box overlaps.
    fn insert(&mut self, f: u32, faces: &[Candidate], nodes: &[Vec3]) {
        let [a, b, c] = faces[f as usize].tri.map(|v| nodes[v as usize].as_dvec3());
        let (lo, hi) = (self.coords(a.min(b).min(c)), self.coords(a.max(b).max(c)));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    let i = self.index([x, y, z]);
                    self.cells[i].push(f);
                }
            }
        }
    }

    /// The nearest face to `p` among those `keep` accepts (smallest index among equals), as
    /// [`distance_to_face`] gives it. Exact: a face outside the rings visited so far is at
    /// least (rings − 1) cells away (for `p` outside the grid too: the grid box is convex, so
    /// `p` is no nearer to it than its projection on it, which lies in the start cell).
    fn nearest(
        &mut self,
        p: DVec3,
        faces: &[Candidate],
        nodes: &[Vec3],
        keep: impl Fn(u32) -> bool,
    ) -> Option<(f64, u32, DVec3)> {
        self.seen.resize(faces.len(), 0);
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.seen.fill(0);
            self.query = 1;
        }
        let start = self.coords(p).map(|c| c as i64);
        let widest = *self.dims.iter().max().unwrap_or(&1) as i64;
        let mut best: Option<(f64, u32, DVec3)> = None;
        let dims = self.dims;
        let clamp = |c: i64, k: usize| c.clamp(0, dims[k] as i64 - 1);
        for r in 0..=widest {
            // Every face not yet seen is at least (r - 1) cells away.
            let bound = (r - 1).max(0) as f64 * self.cell;
            if best.is_some_and(|b| b.0 < bound * bound) {
                break;
            }
            // The cells at Chebyshev distance r from the start cell, within the grid.
            for z in clamp(start[2] - r, 2)..=clamp(start[2] + r, 2) {
                for y in clamp(start[1] - r, 1)..=clamp(start[1] + r, 1) {
                    let shell = (z - start[2]).abs() == r || (y - start[1]).abs() == r;
                    let xs: &[i64] = if shell {
                        &[]
                    } else {
                        &[start[0] - r, start[0] + r]
                    };
                    let row = clamp(start[0] - r, 0)..=clamp(start[0] + r, 0);
                    let mut visit = |x: i64| {
                        if x < 0 || x >= dims[0] as i64 {
                            return;
                        }
                        let i = ((z as usize * dims[1]) + y as usize) * dims[0] + x as usize;
                        for &f in &self.cells[i] {
                            if self.seen[f as usize] == self.query || !keep(f) {
                                continue;
                            }
                            self.seen[f as usize] = self.query;
                            let d = distance_to_face(p, faces, nodes, f);
                            if best.is_none_or(|b| d.0 < b.0 || (d.0 == b.0 && d.1 < b.1)) {
                                best = Some(d);
                            }
                        }
                    };
                    if shell {
                        row.for_each(&mut visit);
                    } else {
                        xs.iter().for_each(|&x| visit(x));
                    }
                }
            }
            // Every cell visited: nothing farther to find.
            if (0..3).all(|k| start[k] - r <= 0 && start[k] + r >= dims[k] as i64 - 1) {
                break;
            }
        }
        best
    }
}

/// Where an attached node sits: `weights` (summing to 1) of the `corners` of the triangle or
/// edge it split, at the time of the split.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Attachment {
    /// The attached node.
    pub node: u32,
    /// Nodes of the split triangle (an edge split repeats no corner: its third weight is 0).
    pub corners: [u32; 3],
    /// Barycentric weights of `corners`.
    pub weights: [f64; 3],
}

impl Attachment {
    /// The point of the split triangle the node sits on, with the corners at `positions`.
    pub(crate) fn point(&self, positions: &[Vec3]) -> DVec3 {
        (0..3)
            .map(|i| positions[self.corners[i] as usize].as_dvec3() * self.weights[i])
            .sum()
    }
}

/// Insert node `m` (nearest point `q` on face `f`) by an edge split when `q` is near an edge
/// with at most one other face, else by a face split.
fn split_for(
    faces: &mut Vec<Candidate>,
    vf: &mut [Vec<u32>],
    nodes: &[Vec3],
    f: u32,
    m: u32,
    q: DVec3,
) -> Attachment {
    let tri = faces[f as usize].tri;
    let [a, b, c] = tri.map(|v| nodes[v as usize].as_dvec3());
    let area = (b - a).cross(c - a).length();
    // Barycentric weight of each corner = area of the sub-triangle opposite it.
    let w = [
        (c - b).cross(q - b).length(),
        (a - c).cross(q - c).length(),
        (b - a).cross(q - a).length(),
    ];
    let (k, wk) = w
        .iter()
        .copied()
        .enumerate()
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap_or((0, 0.0));
    if area > 0.0 && wk <= EDGE_SPLIT_WEIGHT * area {
        // Edge opposite corner k, directed as in the face: (tri[k+1], tri[k+2]).
        let (ea, eb) = (tri[(k + 1) % 3], tri[(k + 2) % 3]);
        let shared: Vec<u32> = vf[ea as usize]
            .iter()
            .copied()
            .filter(|g| vf[eb as usize].contains(g))
            .collect();
        let twins: Vec<u32> = shared
            .iter()
            .copied()
            .filter(|&g| g != f && half_edges(faces[g as usize].tri).contains(&(eb, ea)))
            .collect();
        if shared.len() <= 2 && twins.len() == shared.len() - 1 {
            split_edge_of(faces, vf, f, ea, eb, m);
            if let Some(&g) = twins.first() {
                split_edge_of(faces, vf, g, eb, ea, m);
            }
            // q projected onto the edge, as a parameter along it.
            let (pa, pb) = (nodes[ea as usize].as_dvec3(), nodes[eb as usize].as_dvec3());
            let len2 = (pb - pa).length_squared();
            let t = if len2 > 0.0 {
                ((q - pa).dot(pb - pa) / len2).clamp(SPLIT_POINT_MARGIN, 1.0 - SPLIT_POINT_MARGIN)
            } else {
                0.5
            };
            return Attachment {
                node: m,
                corners: [ea, eb, tri[k]],
                weights: [1.0 - t, t, 0.0],
            };
        }
    }
    let weights = if area > 0.0 {
        let sum = w[0] + w[1] + w[2];
        w.map(|x| (1.0 - 2.0 * SPLIT_POINT_MARGIN) * x / sum + 2.0 * SPLIT_POINT_MARGIN / 3.0)
    } else {
        [1.0 / 3.0; 3]
    };
    // Face split [a, b, c] -> [a, b, m], [b, c, m], [c, a, m].
    let [ta, tb, tc] = tri;
    let support = faces[f as usize].support;
    faces[f as usize].tri = [ta, tb, m];
    vf[tc as usize].retain(|&g| g != f);
    vf[m as usize].push(f);
    for t in [[tb, tc, m], [tc, ta, m]] {
        let id = faces.len() as u32;
        faces.push(Candidate { tri: t, support });
        for &v in &t {
            vf[v as usize].push(id);
        }
    }
    Attachment {
        node: m,
        corners: tri,
        weights,
    }
}

/// Split directed edge (ea, eb) of face `f` at node `m`: [ea, eb, c] -> [ea, m, c], [m, eb, c].
fn split_edge_of(
    faces: &mut Vec<Candidate>,
    vf: &mut [Vec<u32>],
    f: u32,
    ea: u32,
    eb: u32,
    m: u32,
) {
    let t = faces[f as usize].tri;
    let k = (0..3).find(|&k| t[k] == ea).unwrap_or(0);
    let c = t[(k + 2) % 3];
    let support = faces[f as usize].support;
    faces[f as usize].tri = [ea, m, c];
    vf[eb as usize].retain(|&g| g != f);
    vf[m as usize].push(f);
    let id = faces.len() as u32;
    faces.push(Candidate {
        tri: [m, eb, c],
        support,
    });
    for v in [m, eb, c] {
        vf[v as usize].push(id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Faces of almost no area spread over a large extent gave a cell size so small that the
    /// cell count overflowed (a panic found by the CLI fuzz); the grid stays bounded and finds
    /// the nearest face.
    #[test]
    fn face_grid_survives_near_zero_area_faces() {
        let nodes = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0e6, 0.0, 0.0),
            Vec3::new(0.0, 1.0e-30, 0.0),
            Vec3::new(0.0, 0.0, 1.0e6),
            Vec3::new(1.0e-30, 0.0, 1.0e6),
        ];
        let faces = vec![
            Candidate {
                tri: [0, 1, 2],
                support: 1,
            },
            Candidate {
                tri: [3, 4, 0],
                support: 1,
            },
        ];
        let mut grid = FaceGrid::new(&faces, &nodes);
        let cells: usize = grid.dims.iter().product();
        assert!(
            cells >= 1 && cells <= 4 * faces.len() + 64,
            "{:?}",
            grid.dims
        );
        let (d, f, _) = grid
            .nearest(DVec3::new(5.0e5, 1.0, 0.0), &faces, &nodes, |_| true)
            .expect("a face");
        assert_eq!(f, 0);
        assert!((d - 1.0).abs() < 1e-6, "{d}");
    }
}
