//! The training domain: what the network learns and how many nodes each piece gets.
//!
//! Steps, in order:
//! 1. **Distinct points**: referenced vertex positions, exact duplicates counted once (unwelded
//!    input behaves like welded input).
//! 2. **Components**: pieces connected through faces (union-find over distinct points), so
//!    separate pieces of a scan get their own network and never share a node.
//! 3. **Frame and stray points**: per component, a local frame centred on the coordinate-wise
//!    median and scaled by a power of two near the component's robust radius (the 90th
//!    percentile distance from that median). Coordinates of 1e30 or far-away pieces then train
//!    in f32 without overflow or lost precision. Vertices farther than [`STRAY_RADII`] robust
//!    radii are stray points: they are no training signal and do not size the grid.
//! 4. **Allocation**: the target N is split over components in proportion to their signal mass
//!    (point count for vertex signals, area for surface signals) by largest remainder, capped at
//!    each component's capacity (its point count for vertex signals). Components whose share
//!    is below [`MIN_COMPONENT_NODES`] nodes are dropped, smallest first, and their share goes
//!    to the others (reported as a warning).
//! 5. **Halves** (with [`GngParams::split_training`]): a piece allotted at least
//!    [`SPLIT_MIN_NODES`] nodes is trained as two networks, one per half of its points cut at
//!    the median of its longest axis, so that the two can train on two threads. Training only:
//!    the reconstruction labels across the cut (the halves are one component there), so the
//!    output has no seam.

use crate::error::GngError;
use crate::params::{GngParams, SignalSource};
use crate::report::GngWarning;
use crate::tuning::{MIN_COMPONENT_NODES, SPLIT_MIN_NODES, STRAY_RADII};
use glam::{DVec3, Vec3};
use mesh::TriMesh;

/// Percentile of the distances from the median that defines the robust radius.
const RADIUS_PERCENTILE: f64 = 0.9;

/// A similarity transform `local = (world - center) / scale`, `scale` a power of two.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    /// World-space origin of the frame.
    pub center: DVec3,
    /// World units per local unit (a power of two, so scaling is exact).
    pub scale: f64,
}

impl Frame {
    /// World to local coordinates.
    #[inline]
    pub fn to_local(self, p: Vec3) -> Vec3 {
        ((p.as_dvec3() - self.center) / self.scale).as_vec3()
    }

    /// Local to world coordinates.
    #[inline]
    pub fn to_world(self, p: Vec3) -> Vec3 {
        (p.as_dvec3() * self.scale + self.center).as_vec3()
    }
}

/// One connected piece of the input, ready for training.
#[derive(Debug, Clone)]
pub(crate) struct Piece {
    /// Local frame.
    pub frame: Frame,
    /// Distinct non-stray points, local coordinates.
    pub points: Vec<Vec3>,
    /// Faces with only non-stray corners, local coordinates (for surface signals; empty for
    /// vertex signals, which need no faces).
    pub surface: TriMesh,
    /// Area of those faces, local units² (sizes the search grid).
    pub area: f64,
    /// Nodes allotted to this piece.
    pub target: usize,
    /// Connected component of the input this piece belongs to (two halves share one).
    pub component: usize,
}

/// The pieces to train and what was left out.
#[derive(Debug, Clone)]
pub(crate) struct Domain {
    /// Pieces with at least one node, largest first.
    pub pieces: Vec<Piece>,
    /// Distinct referenced vertex positions of the whole input, world coordinates.
    pub distinct: usize,
    /// What was dropped or cannot be held.
    pub warnings: Vec<GngWarning>,
}

/// The distinct points of an input mesh and their face-connected components (steps 1 and 2):
/// computed once per input and shared by training ([`Domain::build`]) and reconstruction
/// (component-aware labels), which used to compute both again (igea: ~30 ms of phase 2).
#[derive(Debug, Clone)]
pub(crate) struct Pieces {
    /// Distinct id of each mesh vertex (`u32::MAX`: unreferenced).
    pub ids: Vec<u32>,
    /// Position of each distinct id, world coordinates.
    pub distinct: Vec<Vec3>,
    /// Component of each distinct id (dense, first-seen order).
    pub comp: Vec<u32>,
    /// Number of components.
    pub count: usize,
}

impl Pieces {
    /// Distinct points and components of `mesh`.
    pub fn of(mesh: &TriMesh) -> Pieces {
        let (ids, distinct) = distinct_ids(mesh);
        let (comp, count) = components(mesh, &ids, distinct.len());
        Pieces {
            ids,
            distinct,
            comp,
            count,
        }
    }
}

/// Distinct position id of each vertex (`u32::MAX` when unreferenced) and the positions.
/// Ids are numbered in first-seen order over the faces. Found by sorting the referenced
/// vertices by position bits: a hash map of igea's 134k positions missed the cache on every
/// insert (22–28 ms); the sort takes 10–13 ms.
pub(crate) fn distinct_ids(mesh: &TriMesh) -> (Vec<u32>, Vec<Vec3>) {
    // 1. Referenced vertices in first-seen order.
    let mut id = vec![u32::MAX; mesh.positions.len()];
    let mut first: Vec<u32> = Vec::with_capacity(mesh.positions.len());
    for t in &mesh.triangles {
        for &v in t {
            if id[v as usize] == u32::MAX {
                id[v as usize] = first.len() as u32;
                first.push(v);
            }
        }
    }
    // 2. Sort by position bits, ties by first-seen rank: each run of equal positions starts
    //    with its earliest vertex, which represents it. The four 32-bit fields are packed into
    //    one u128 (the same order as comparing them in turn; igea: 6.5 → 5.2 ms).
    let key = |k: u32| {
        let [x, y, z] = mesh.positions[first[k as usize] as usize]
            .to_array()
            .map(f32::to_bits);
        (u128::from(x) << 96) | (u128::from(y) << 64) | (u128::from(z) << 32) | u128::from(k)
    };
    let mut order: Vec<u128> = (0..first.len() as u32).map(key).collect();
    order.sort_unstable();
    let mut rep = vec![0u32; first.len()];
    let mut run_start = 0;
    for i in 0..order.len() {
        // The position bits are the upper 96.
        if order[run_start] >> 32 != order[i] >> 32 {
            run_start = i;
        }
        rep[order[i] as u32 as usize] = order[run_start] as u32;
    }
    // 3. Dense ids in first-seen order of the representatives (the vertices that represent
    //    themselves).
    let mut dense = vec![u32::MAX; first.len()];
    let mut out = Vec::new();
    for k in 0..first.len() {
        if rep[k] == k as u32 {
            dense[k] = out.len() as u32;
            out.push(mesh.positions[first[k] as usize]);
        }
    }
    for v in id.iter_mut() {
        if *v != u32::MAX {
            *v = dense[rep[*v as usize] as usize];
        }
    }
    (id, out)
}

/// Face-connected components over distinct ids: component of each distinct point (dense,
/// numbered in first-seen order) and the component count.
pub(crate) fn components(mesh: &TriMesh, ids: &[u32], distinct: usize) -> (Vec<u32>, usize) {
    // Components are numbered by their first member below, whatever the roots are.
    let mut parent = mesh::topology::UnionFind::new(distinct);
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|v| ids[v as usize]);
        parent.union(a, b);
        parent.union(b, c);
    }
    let mut dense = vec![u32::MAX; distinct];
    let mut comp = vec![0u32; distinct];
    let mut count = 0;
    for i in 0..distinct as u32 {
        let r = parent.find(i) as usize;
        if dense[r] == u32::MAX {
            dense[r] = count;
            count += 1;
        }
        comp[i as usize] = dense[r];
    }
    (comp, count as usize)
}

/// Frame of a point set: median centre, power-of-two scale near the robust radius; also the
/// robust radius in world units.
fn frame_of(points: &[DVec3]) -> (Frame, f64) {
    let mut axis: Vec<f64> = Vec::with_capacity(points.len());
    let mut center = DVec3::ZERO;
    for a in 0..3 {
        axis.clear();
        axis.extend(points.iter().map(|p| p[a]));
        let mid = axis.len() / 2;
        let (_, m, _) = axis.select_nth_unstable_by(mid, f64::total_cmp);
        center[a] = *m;
    }
    let mut dist: Vec<f64> = points.iter().map(|p| (*p - center).length()).collect();
    let k = ((dist.len() as f64 * RADIUS_PERCENTILE) as usize).min(dist.len() - 1);
    let (_, r, _) = dist.select_nth_unstable_by(k, f64::total_cmp);
    let mut radius = *r;
    if !(radius > 0.0 && radius.is_finite()) {
        radius = dist
            .iter()
            .copied()
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max);
    }
    let scale = if radius > 0.0 && radius.is_finite() {
        2f64.powi(radius.log2().ceil() as i32)
    } else {
        1.0
    };
    (Frame { center, scale }, radius)
}

/// Nodes a piece of `points` distinct points can hold: one per point with vertex signals
/// (`vertex_bound`), which cannot place two nodes on one point; unbounded with surface signals.
fn capacity_of(points: usize, vertex_bound: bool) -> usize {
    if vertex_bound { points } else { usize::MAX / 4 }
}

/// Split `target` over `mass` by largest remainder with per-entry `capacity`; returns the
/// allotment (sum = min(target, total capacity)).
pub(crate) fn allot(target: usize, mass: &[f64], capacity: &[usize]) -> Vec<usize> {
    let n = mass.len();
    let mut out = vec![0usize; n];
    let mut open: Vec<usize> = (0..n).collect();
    let mut left = target;
    // Water-filling: entries whose proportional share exceeds their capacity take the
    // capacity; the rest is shared again among the others.
    loop {
        let total: f64 = open.iter().map(|&i| mass[i]).sum();
        if open.is_empty() || left == 0 || total <= 0.0 {
            break;
        }
        let full: Vec<usize> = open
            .iter()
            .copied()
            .filter(|&i| left as f64 * mass[i] / total >= capacity[i] as f64)
            .collect();
        if full.is_empty() {
            let share: Vec<f64> = open
                .iter()
                .map(|&i| left as f64 * mass[i] / total)
                .collect();
            let mut given = 0;
            for (k, &i) in open.iter().enumerate() {
                out[i] = share[k].floor() as usize;
                given += out[i];
            }
            let mut order: Vec<usize> = (0..open.len()).collect();
            order.sort_by(|&a, &b| {
                let (fa, fb) = (share[a] - share[a].floor(), share[b] - share[b].floor());
                fb.total_cmp(&fa).then(a.cmp(&b))
            });
            for &k in order.iter().cycle().take(left.saturating_sub(given)) {
                out[open[k]] += 1;
            }
            break;
        }
        for &i in &full {
            out[i] = capacity[i];
            left -= capacity[i];
        }
        open.retain(|i| !full.contains(i));
    }
    out
}

impl Domain {
    /// Build the domain of `mesh` (with its distinct points and components, `input`) for
    /// `params` (see the module docs for the steps).
    pub fn build(mesh: &TriMesh, input: &Pieces, params: &GngParams) -> Result<Domain, GngError> {
        // 1. Distinct points.
        let (ids, distinct) = (&input.ids, &input.distinct);
        if distinct.len() < 3 {
            return Err(GngError::TooFewVertices {
                vertices: distinct.len(),
            });
        }
        let target = params.network_target();
        let vertex_bound = params.signal_source == SignalSource::Vertices;
        if target < 3 || (vertex_bound && target > distinct.len()) {
            return Err(GngError::Target {
                target,
                available: distinct.len(),
            });
        }
        // 2. Components.
        let (comp, count) = (&input.comp, input.count);
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); count];
        for (i, &c) in comp.iter().enumerate() {
            members[c as usize].push(i as u32);
        }
        // 3. Frames and stray points.
        let mut warnings = Vec::new();
        let mut stray_total = 0;
        let mut pieces = Vec::with_capacity(count);
        let mut mass = Vec::with_capacity(count);
        let mut capacity = Vec::with_capacity(count);
        let mut local_of = vec![u32::MAX; distinct.len()];
        for ids_c in members.iter() {
            let world: Vec<DVec3> = ids_c
                .iter()
                .map(|&i| distinct[i as usize].as_dvec3())
                .collect();
            let (frame, radius) = frame_of(&world);
            let limit = STRAY_RADII * radius;
            let mut points = Vec::with_capacity(ids_c.len());
            for (k, &i) in ids_c.iter().enumerate() {
                if (world[k] - frame.center).length() <= limit {
                    local_of[i as usize] = points.len() as u32;
                    points.push(frame.to_local(distinct[i as usize]));
                } else {
                    stray_total += 1;
                }
            }
            capacity.push(capacity_of(points.len(), vertex_bound));
            pieces.push(Piece {
                frame,
                points,
                surface: TriMesh::default(),
                area: 0.0,
                target: 0,
                component: pieces.len(),
            });
        }
        // Faces with only non-stray corners, in local coordinates, in one pass over the input:
        // their area sizes the grid; surface signals also keep them (vertex signals need no
        // faces: no copy of igea's 269k).
        let keep_faces = params.signal_source != SignalSource::Vertices;
        let mut faces: Vec<Vec<[u32; 3]>> = vec![Vec::new(); count];
        for t in &mesh.triangles {
            let d = t.map(|v| ids[v as usize]);
            let c = comp[d[0] as usize] as usize;
            let l = d.map(|i| local_of[i as usize]);
            if l.contains(&u32::MAX) {
                continue;
            }
            let piece = &mut pieces[c];
            let [a, b, p] = l.map(|v| piece.points[v as usize].as_dvec3());
            piece.area += 0.5 * (b - a).cross(p - a).length();
            if keep_faces {
                faces[c].push(l);
            }
        }
        for (piece, faces) in pieces.iter_mut().zip(faces) {
            let m = match params.signal_source {
                SignalSource::Vertices => piece.points.len() as f64,
                SignalSource::Surface | SignalSource::Curvature => {
                    piece.surface = TriMesh::new(piece.points.clone(), faces);
                    piece.area * piece.frame.scale * piece.frame.scale
                }
            };
            mass.push(if m.is_finite() { m } else { 0.0 });
        }
        if stray_total > 0 {
            warnings.push(GngWarning::StrayVertices {
                vertices: stray_total,
            });
        }
        // 4. Allocation: drop the smallest components whose share is below the minimum.
        let mut keep: Vec<usize> = (0..count)
            .filter(|&c| mass[c] > 0.0 && pieces[c].points.len() >= 3)
            .collect();
        keep.sort_by(|&a, &b| mass[b].total_cmp(&mass[a]).then(a.cmp(&b)));
        // The kept total after each drop: prefix sums in the same order as a sum over the kept
        // list (the same value to the bit), instead of summing the list again at every drop,
        // which made 300k pieces take 28 s.
        let mut prefix = Vec::with_capacity(keep.len() + 1);
        prefix.push(0.0f64);
        for &c in &keep {
            prefix.push(prefix[prefix.len() - 1] + mass[c]);
        }
        loop {
            let total = prefix[keep.len()];
            match keep.last() {
                Some(&c)
                    if keep.len() > 1
                        && (target as f64 * mass[c] / total) < MIN_COMPONENT_NODES as f64 =>
                {
                    keep.pop();
                }
                _ => break,
            }
        }
        if keep.is_empty() {
            return Err(GngError::TooFewVertices { vertices: 0 });
        }
        let dropped = count - keep.len();
        if dropped > 0 {
            let mut kept = vec![false; count];
            for &c in &keep {
                kept[c] = true;
            }
            let vertices: usize = (0..count)
                .filter(|&c| !kept[c])
                .map(|c| members[c].len())
                .sum();
            warnings.push(GngWarning::DroppedComponents {
                components: dropped,
                vertices,
                kept: keep.len(),
            });
        }
        let km: Vec<f64> = keep.iter().map(|&c| mass[c]).collect();
        let kc: Vec<usize> = keep.iter().map(|&c| capacity[c]).collect();
        let alloc = allot(target, &km, &kc);
        let held: usize = alloc.iter().sum();
        if held < target {
            warnings.push(GngWarning::TargetAboveCapacity {
                target,
                capacity: held,
            });
        }
        // Kept pieces move out (no copy of their points and faces).
        let mut pieces: Vec<Option<Piece>> = pieces.into_iter().map(Some).collect();
        let mut chosen = Vec::with_capacity(keep.len());
        for (k, &c) in keep.iter().enumerate() {
            if alloc[k] >= 2
                && let Some(mut p) = pieces[c].take()
            {
                p.target = alloc[k];
                if params.split_training && p.target >= SPLIT_MIN_NODES {
                    chosen.extend(p.halves(vertex_bound));
                } else {
                    chosen.push(p);
                }
            }
        }
        Ok(Domain {
            pieces: chosen,
            distinct: distinct.len(),
            warnings,
        })
    }
}

impl Piece {
    /// Step 5: this piece as two pieces, its points cut at the median of the longest axis of
    /// their box (points on the median go to the first), its target split by signal mass (the
    /// point count for vertex signals, the area for surface signals) capped by the point count
    /// when `vertex_bound`. Surface signals: each face goes to the half of its centroid, and
    /// each half keeps the points its faces use. The area (which sizes the search grid) is
    /// split by point share for vertex signals, which keep no faces. A cut that would leave
    /// either half with less than a quarter of the target (many points on the median plane,
    /// e.g. a fan whose rim is the far end of the box) keeps the piece whole.
    fn halves(self, vertex_bound: bool) -> Vec<Piece> {
        let bbox = mesh::Aabb::from_points(&self.points);
        let extent = bbox.max - bbox.min;
        let axis = if extent.x >= extent.y && extent.x >= extent.z {
            0
        } else if extent.y >= extent.z {
            1
        } else {
            2
        };
        let mut coords: Vec<f32> = self.points.iter().map(|p| p[axis]).collect();
        let mid = coords.len() / 2;
        let (_, median, _) = coords.select_nth_unstable_by(mid, f32::total_cmp);
        let median = *median;
        let first_half = |p: Vec3| p[axis] <= median;
        let surface_signals = !self.surface.triangles.is_empty();
        let mut halves: [(Vec<Vec3>, Vec<[u32; 3]>, f64); 2] = Default::default();
        if surface_signals {
            let mut index = [
                vec![u32::MAX; self.points.len()],
                vec![u32::MAX; self.points.len()],
            ];
            for t in &self.surface.triangles {
                let [a, b, c] = t.map(|v| self.points[v as usize]);
                let h = usize::from(!first_half((a + b + c) / 3.0));
                let (points, faces, area) = &mut halves[h];
                let local = t.map(|v| {
                    let slot = &mut index[h][v as usize];
                    if *slot == u32::MAX {
                        *slot = points.len() as u32;
                        points.push(self.points[v as usize]);
                    }
                    *slot
                });
                faces.push(local);
                *area += 0.5 * (b - a).as_dvec3().cross((c - a).as_dvec3()).length();
            }
        } else {
            for &p in &self.points {
                halves[usize::from(!first_half(p))].0.push(p);
            }
            let total = self.points.len().max(1) as f64;
            for half in &mut halves {
                half.2 = self.area * half.0.len() as f64 / total;
            }
        }
        let mass: Vec<f64> = halves
            .iter()
            .map(|(points, _, area)| {
                if surface_signals {
                    *area
                } else {
                    points.len() as f64
                }
            })
            .collect();
        let capacity: Vec<usize> = halves
            .iter()
            .map(|(points, ..)| capacity_of(points.len(), vertex_bound))
            .collect();
        let target = allot(self.target, &mass, &capacity);
        if target.iter().any(|&t| t < self.target / 4) {
            return vec![self];
        }
        let [(p0, f0, a0), (p1, f1, a1)] = halves;
        let half = |points: Vec<Vec3>, faces: Vec<[u32; 3]>, area: f64, target: usize| Piece {
            frame: self.frame,
            surface: if surface_signals {
                TriMesh::new(points.clone(), faces)
            } else {
                TriMesh::default()
            },
            points,
            area,
            target,
            component: self.component,
        };
        vec![half(p0, f0, a0, target[0]), half(p1, f1, a1, target[1])]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn halves_split_points_faces_area_and_target() {
        let sphere = mesh::procedural::icosphere(4);
        let area = sphere.area();
        for source in [SignalSource::Vertices, SignalSource::Surface] {
            let mut params = GngParams::for_target(1001);
            params.signal_source = source;
            params.split_training = true;
            let d = Domain::build(&sphere, &Pieces::of(&sphere), &params).unwrap();
            assert_eq!(d.pieces.len(), 2, "{source:?}");
            let [h0, h1] = [&d.pieces[0], &d.pieces[1]];
            assert_eq!(h0.target + h1.target, 1001);
            assert!(
                h0.target.abs_diff(h1.target) <= 60,
                "{} {}",
                h0.target,
                h1.target
            );
            assert_eq!((h0.component, h1.component), (0, 0));
            let scale2 = h0.frame.scale * h0.frame.scale;
            assert!(
                ((h0.area + h1.area) * scale2 - area).abs() < 1e-3 * area,
                "{source:?}"
            );
            match source {
                // Vertex signals: the points are split between the halves, no face kept.
                SignalSource::Vertices => {
                    assert_eq!(h0.points.len() + h1.points.len(), sphere.vertex_count());
                    assert!(h0.surface.triangles.is_empty());
                }
                // Surface signals: every face goes to one half, with the points it uses.
                _ => {
                    let faces = h0.surface.face_count() + h1.surface.face_count();
                    assert_eq!(faces, sphere.face_count());
                    for h in [h0, h1] {
                        assert_eq!(h.surface.positions.len(), h.points.len());
                        let used: std::collections::HashSet<u32> =
                            h.surface.triangles.iter().flatten().copied().collect();
                        assert_eq!(used.len(), h.points.len());
                    }
                }
            }
        }
    }

    #[test]
    fn a_cut_that_leaves_a_half_nearly_empty_keeps_the_piece_whole() {
        // A fan from the origin to 1,000 rim points at x = 1 (the box's longest side is x): the
        // median x is the rim itself, so every point is on the first side of the cut.
        let mut positions = vec![Vec3::ZERO];
        positions.extend((0..1000).map(|i| Vec3::new(1.0, i as f32 * 5e-4, 0.0)));
        let triangles = (1..1000u32).map(|i| [0, i, i + 1]).collect();
        let fan = TriMesh::new(positions, triangles);
        for source in [SignalSource::Vertices, SignalSource::Surface] {
            let mut params = GngParams::for_target(600);
            params.signal_source = source;
            params.split_training = true;
            let d = Domain::build(&fan, &Pieces::of(&fan), &params).unwrap();
            assert_eq!(d.pieces.len(), 1, "{source:?}");
            assert_eq!(d.pieces[0].target, 600);
            assert!(crate::Trainer::new(&fan.clone().into(), params).is_ok());
        }
    }

    #[test]
    fn allotment_is_proportional_capped_and_exact() {
        assert_eq!(allot(10, &[1.0, 1.0], &[100, 100]), vec![5, 5]);
        // Largest remainder: 7 * (0.5, 0.3, 0.2) = 3.5, 2.1, 1.4 -> 4, 2, 1.
        assert_eq!(allot(7, &[5.0, 3.0, 2.0], &[100, 100, 100]), vec![4, 2, 1]);
        // The capped entry gives its excess to the others.
        assert_eq!(allot(10, &[8.0, 1.0, 1.0], &[4, 100, 100]), vec![4, 3, 3]);
        // Not enough capacity: everything saturates.
        assert_eq!(allot(20, &[1.0, 1.0], &[3, 4]), vec![3, 4]);
    }

    #[test]
    fn frames_survive_huge_and_offset_coordinates() {
        let pts: Vec<DVec3> = (0..100)
            .map(|i| DVec3::new(1e30 + i as f64 * 1e28, 2e30, -(i as f64) * 1e27))
            .collect();
        let (f, r) = frame_of(&pts);
        assert!(r > 1e28 && r < 1e30, "{r}");
        for p in &pts {
            let l = f.to_local(p.as_vec3());
            assert!(l.is_finite() && l.length() <= 2.0, "{l}");
            let back = f.to_world(l).as_dvec3();
            assert!((back - *p).length() <= 1e-6 * p.length());
        }
    }

    #[test]
    fn components_weld_duplicate_positions() {
        // Two triangles sharing an edge by position only (unwelded), plus a separate one.
        let p = |x: f32, y: f32| Vec3::new(x, y, 0.0);
        let m = TriMesh::new(
            vec![
                p(0., 0.),
                p(1., 0.),
                p(0., 1.),
                p(1., 0.),
                p(1., 1.),
                p(0., 1.),
                p(5., 5.),
                p(6., 5.),
                p(5., 6.),
            ],
            vec![[0, 1, 2], [3, 4, 5], [6, 7, 8]],
        );
        let (ids, d) = distinct_ids(&m);
        assert_eq!(d.len(), 7);
        // Dense ids in first-seen order; a duplicate takes its first occurrence's id.
        assert_eq!(ids, vec![0, 1, 2, 1, 3, 2, 4, 5, 6]);
        assert_eq!(d[3], p(1., 1.));
        let (comp, count) = components(&m, &ids, d.len());
        assert_eq!(count, 2);
        assert_eq!(comp[ids[0] as usize], comp[ids[4] as usize]);
        assert_ne!(comp[ids[0] as usize], comp[ids[6] as usize]);
    }
}
