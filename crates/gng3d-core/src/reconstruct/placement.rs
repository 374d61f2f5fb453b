//! Output vertex placement of phase 2 ([`Placement`]): where the vertex that represents a node's
//! cell (the original vertices labelled with the node) is put.
//!
//! Steps, per output vertex:
//! 1. **Cell faces**: the original faces with at least one corner in the cell (CSR by counting
//!    sort, no per-vertex allocation).
//! 2. **Project** (p0): the closest point to the node on those faces.
//! 3. **Quadric**: the sum of the Garland–Heckbert quadrics of the cell's original vertices
//!    (area-weighted face planes plus boundary constraint planes, [`mesh::quadric`], the same
//!    ones qem builds) is minimised from p0 with the rank-truncated solve
//!    ([`Quadric::minimizer_near`]): flat cells only move onto their plane, creases onto the
//!    crease line, corners to the corner. The result falls back to p0 when it is not finite,
//!    lies farther than [`MAX_JUMP_CELL_RADII`] cell radii from the node, or farther than
//!    [`MAX_OFF_SURFACE_CELL_RADII`] from every face of the cell.
//!
//! GNG3D as published (Node) keeps the node positions: they sit at the centroid of their
//! signals, i.e. inside curved surfaces and off creases.

use super::Attachment;
use crate::params::Placement;
use crate::surface::{CellFaces, cell_faces, closest_on_faces};
use glam::{DVec3, Vec3};
use mesh::TriMesh;
use mesh::geometry::{box_distance2, closest_point_triangle};
use mesh::quadric::Quadric;
use mesh::topology::EdgeTable;

/// Eigenvalues of a cell quadric below this fraction of the largest are treated as zero by the
/// truncated solve. 1e-3 keeps real corners (three planes at ≥ ~2° apart) and drops the noise
/// directions of almost flat cells; the prototype used the same value.
pub const EIGEN_REL_TOL: f64 = 1e-3;

/// A quadric solution farther than this many cell radii (largest node-to-cell-vertex distance)
/// from the node is rejected in favour of the projected point: the minimiser of a quadric is
/// only meaningful near the planes it was built from.
pub const MAX_JUMP_CELL_RADII: f64 = 2.0;

/// A quadric solution farther than this many cell radii from every face of its cell is
/// rejected too: it means a near-degenerate quadric pulled the vertex off the surface (the
/// stanford-bunny at 10 % had one vertex a whole edge length off, 7.5× QEM's Hausdorff;
/// with 0.5: 4.1×, mean distance 1.56 → 1.43× QEM). Tighter bounds (0.25, 0.1) cost mean
/// distance elsewhere: the good solutions do sit off the surface, by the sagitta.
pub const MAX_OFF_SURFACE_CELL_RADII: f64 = 0.5;

/// Below this many output vertices per thread the per-vertex steps stay on one thread.
const MIN_VERTICES_PER_THREAD: usize = 512;

/// Boundary constraint weight, qem's default (`QemParams::boundary_weight`), so that open
/// borders stay where the original's are.
pub const BOUNDARY_WEIGHT: f64 = 1000.0;

/// Output vertex of each original vertex (`u32::MAX` when its node is not in the output).
pub(crate) fn owners(labels: &[u32], node_of_vertex: &[u32], node_count: usize) -> Vec<u32> {
    let mut out_of_node = vec![u32::MAX; node_count];
    for (o, &n) in node_of_vertex.iter().enumerate() {
        out_of_node[n as usize] = o as u32;
    }
    labels
        .iter()
        .map(|&l| out_of_node.get(l as usize).copied().unwrap_or(u32::MAX))
        .collect()
}

/// What [`place`] did.
pub(crate) struct Placed {
    /// Vertices moved.
    pub moved: usize,
    /// Each output vertex's cell quadric of face planes, without the boundary planes (Quadric
    /// placement only; zero for attached vertices, which have no cell; empty for the other
    /// placements). The refit keeps vertices near it.
    pub quadrics: Vec<Quadric>,
}

/// Move the output vertices (`positions`, initially the node positions) according to
/// `placement`; `edges` is the original's edge table (for its boundary planes), `owner` the
/// output vertex of each original vertex ([`owners`]); the `attached` vertices (in output
/// indices) have no cell and follow their split triangles ([`place_attached`]).
pub(crate) fn place(
    original: &TriMesh,
    edges: &EdgeTable,
    owner: &[u32],
    placement: Placement,
    attached: &[Attachment],
    positions: &mut [Vec3],
    threads: usize,
) -> Placed {
    let mut placed = Placed {
        moved: 0,
        quadrics: Vec::new(),
    };
    if placement == Placement::Node || positions.is_empty() {
        return placed;
    }
    let cells = cell_faces(original, owner, positions.len());
    let pos = |v: u32| original.positions[v as usize].as_dvec3();

    // Step 2: p0, the closest point on the cell's faces. The search starts from the nearest
    // cell vertex (a point of the surface, so an upper bound) and skips every face whose
    // bounding box is farther than the best so far: on igea at 1 % a cell has ~300 faces and
    // nearly all of them are culled by the box test, which costs a fraction of the exact one.
    let mut best: Vec<(f64, DVec3)> = positions
        .iter()
        .map(|p| (f64::INFINITY, p.as_dvec3()))
        .collect();
    for (v, &o) in owner.iter().enumerate() {
        if o != u32::MAX {
            let p = original.positions[v].as_dvec3();
            let node = positions[o as usize].as_dvec3();
            let d = (p - node).length_squared();
            if d < best[o as usize].0 {
                best[o as usize] = (d, p);
            }
        }
    }
    // Per output vertex and independent: on all cores (same result for any count).
    let projected: Vec<Option<DVec3>> = {
        let positions = &*positions;
        crate::parallel::map_indexed(positions.len(), threads, MIN_VERTICES_PER_THREAD, |o| {
            let node = positions[o].as_dvec3();
            let (best_d, best_q) = closest_on_faces(original, cells.of(o), node, best[o]);
            best_d.is_finite().then_some(best_q)
        })
    };
    if placement == Placement::Project {
        for (p, p0) in positions.iter_mut().zip(&projected) {
            if let Some(q) = p0 {
                *p = q.as_vec3();
                placed.moved += 1;
            }
        }
        place_attached(original, &cells, attached, positions);
        return placed;
    }

    // Step 3: cell quadrics. Summing the vertex quadrics of the cell adds every face plane once
    // per corner in the cell, and every boundary plane once per end in the cell.
    let mut quadrics = vec![Quadric::default(); positions.len()];
    for t in &original.triangles {
        let q = Quadric::from_triangle(pos(t[0]), pos(t[1]), pos(t[2]));
        if q == Quadric::default() {
            continue;
        }
        for &v in t {
            let o = owner[v as usize];
            if o != u32::MAX {
                quadrics[o as usize] += q;
            }
        }
    }
    // The refit's anchor: face planes only (it holds open borders with its own boundary
    // samples; with these 1000-weight planes in its anchor the bunny's rim vertices at 10 % rose
    // off the base, Hausdorff 1.7 → 7.3× QEM).
    placed.quadrics = quadrics.clone();
    for e in 0..edges.len() {
        if !edges.is_boundary(e) {
            continue;
        }
        let [lo, hi] = edges.edges[e];
        let face = edges.corners(e)[0] / 3;
        let corners = original.triangles[face as usize].map(pos);
        let q = Quadric::from_boundary_edge(pos(lo), pos(hi), corners, BOUNDARY_WEIGHT);
        for v in [lo, hi] {
            let o = owner[v as usize];
            if o != u32::MAX {
                quadrics[o as usize] += q;
            }
        }
    }
    // Cell radii (squared): the farthest cell vertex from its node.
    let mut radius2 = vec![0.0f64; positions.len()];
    for (v, &o) in owner.iter().enumerate() {
        if o != u32::MAX {
            let d = (original.positions[v].as_dvec3() - positions[o as usize].as_dvec3())
                .length_squared();
            radius2[o as usize] = radius2[o as usize].max(d);
        }
    }
    let solved: Vec<Option<DVec3>> = {
        let positions = &*positions;
        crate::parallel::map_indexed(positions.len(), threads, MIN_VERTICES_PER_THREAD, |o| {
            let p0 = projected[o]?;
            let node = positions[o].as_dvec3();
            let x = quadrics[o].minimizer_near(p0, EIGEN_REL_TOL);
            let limit2 = MAX_JUMP_CELL_RADII * MAX_JUMP_CELL_RADII * radius2[o];
            let off2 = MAX_OFF_SURFACE_CELL_RADII * MAX_OFF_SURFACE_CELL_RADII * radius2[o];
            let fits = x.is_finite()
                && (x - node).length_squared() <= limit2
                && any_face_within(original, cells.of(o), x, off2);
            Some(if fits { x } else { p0 })
        })
    };
    for (p, x) in positions.iter_mut().zip(&solved) {
        if let Some(x) = x {
            *p = x.as_vec3();
            placed.moved += 1;
        }
    }
    place_attached(original, &cells, attached, positions);
    placed
}

/// Whether one of the original `faces` comes within `sqrt(limit2)` of `p`: [`closest_on_faces`]
/// `<= limit2`, stopping at the first face that does (on igea at 1 % the check of the quadric
/// solutions took half of step 3 when it searched for the closest face).
fn any_face_within(original: &TriMesh, faces: &[u32], p: DVec3, limit2: f64) -> bool {
    faces.iter().any(|&f| {
        let [a, b, c] =
            original.triangles[f as usize].map(|v| original.positions[v as usize].as_dvec3());
        box_distance2(p, a, b, c) <= limit2
            && (closest_point_triangle(p, a, b, c) - p).length_squared() <= limit2
    })
}

/// Last step for Project and Quadric: the vertices of attached nodes (nodes that won no
/// original vertex, so they have no cell of their own) are put at their barycentric point on the
/// split triangle's current corners, then projected onto the original faces of those corners'
/// cells (the surface the triangle stands for). In attachment order, so a vertex attached onto
/// an earlier one's triangle sees it placed. Without the projection these vertices stay on
/// chords: on spot, rocker-arm and cow at 50 % (13 % of the nodes attached) the mean distance
/// was 2.6-4.0x QEM's.
fn place_attached(
    original: &TriMesh,
    cells: &CellFaces,
    attached: &[Attachment],
    positions: &mut [Vec3],
) {
    // A cell that many attached vertices search gets a tree (crate::fan_search): the hub of a
    // fan-triangulated cap owns thousands of faces and every vertex attached on the cap
    // searched them all (a 64k-face fan-capped cylinder at 50 %: ~1,000 vertices × 8,000
    // faces). Small or rarely searched cells are scanned, as before.
    let mut searches = vec![0u32; positions.len()];
    for a in attached {
        for &c in &a.corners {
            searches[c as usize] += 1;
        }
    }
    let corners = |f: u32| original.triangle_f64(f as usize);
    let large = crate::surface::fan_search::LargeLists::new(
        positions.len(),
        |c| {
            if searches[c] >= MIN_SEARCHES_FOR_TREE {
                cells.of(c)
            } else {
                &[]
            }
        },
        |c| positions[c].as_dvec3(),
        corners,
    );
    for a in attached {
        let p = a.point(positions);
        let best = a.corners.iter().fold((f64::INFINITY, p), |best, &c| {
            match large.tree(c as usize) {
                Some(tree) => {
                    let mut found = (best.0, u32::MAX, best.1);
                    tree.nearest(p, &mut found, |f| Some(corners(f)));
                    (found.0, found.2)
                }
                None => closest_on_faces(original, cells.of(c as usize), p, best),
            }
        });
        positions[a.node as usize] = best.1.as_vec3();
    }
}

/// Attached vertices that must search a large cell before it gets a tree (a tree costs about
/// as much to build as a few scans of its faces).
const MIN_SEARCHES_FOR_TREE: u32 = 4;
