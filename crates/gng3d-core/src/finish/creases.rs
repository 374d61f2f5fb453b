//! Creases and corners of a CAD part kept by GNG3D-Q: the original's feature lines become
//! seams of the same cut and decimation that keep attribute seams ([`crate::Step::CutSeams`],
//! [`crate::Step::Decimate`] along the charts), and the vertices on them are pulled onto the
//! lines. Without this the network's triangles cut every sharp edge and corner (Hausdorff
//! distance 5-7× QEM's on fandisk, docs/notes/creases.md).
//!
//! Steps:
//! 1. **Feature edges** ([`detect`]): interior edges of the original whose two faces' normals
//!    differ by more than [`ANGLE_DEGREES`], kept when their connected line has at least
//!    [`MIN_LINE`] edges (a scan's isolated sharp edges are noise, not creases); the input is a
//!    CAD part only when they are at least [`MIN_SHARE`] of its interior edges.
//! 2. **Corners**: vertices where three or more feature edges meet.
//! 3. **Patches**: the original's faces grown breadth first across the edges that are not
//!    feature edges; each patch is a chart of the cut (the caller splits a line that ends inside
//!    one patch into its two sides, as for attribute seams: `seams::split_inner_chains`).
//! 4. **Pull** ([`Creases::pull`], after the cut and again after the decimation): each vertex
//!    between two or more charts moves to the closest point of a feature edge between two of
//!    its charts, when one lies within its longest edge; then, for each corner, the closest
//!    vertex between three or more charts within its longest edge moves onto the corner. The
//!    cut alone puts its vertices where the closest original triangle changes, which across a
//!    convex crease is inside the part, off the line.
//!
//! On real parts this does not always pay (soft and curved creases, few vertices per line):
//! the decimation along the creases is kept only when its largest distance to the original is
//! not above the plain decimation's ([`crate::Step::Decimate`]). Measured in
//! docs/notes/creases.md: fandisk at 10 % Hausdorff ×0.77, the grid cube's corners and edges
//! exact; rocker-arm and casting keep the plain decimation.

use glam::Vec3;
use mesh::TriMesh;
use mesh::topology::{EdgeTable, UnionFind};
use mesh::transfer::FaceGrid;
use rustc_hash::FxHashMap as HashMap;

/// Smallest angle between the normals of an edge's two faces for a feature edge, degrees.
/// Measured (docs/notes/creases.md) on fandisk, rocker-arm, casting and the organic meshes.
const ANGLE_DEGREES: f64 = 45.0;

/// Fewest edges of a connected feature line that is kept (measured with [`ANGLE_DEGREES`]).
const MIN_LINE: usize = 4;

/// Smallest share of the interior edges that must be feature edges (on lines of [`MIN_LINE`])
/// for the input to count as a CAD part. Measured: fandisk 3.6 %, casting 5.5 %; the scans
/// stay far below (armadillo 225 of 130k edges, bunny 222 of 104k, igea 244 of 403k, horse
/// and gargoyle-10k under 1 %), where cutting along their noise only cost time (igea at 10 %:
/// 5.4 → 25 s with the same distance).
const MIN_SHARE: f64 = 0.02;

/// The feature lines and corners of an original and its smooth patches.
#[derive(Debug, Clone)]
pub(crate) struct Creases {
    /// Feature edges (original vertex pairs, smaller first).
    edges: Vec<[u32; 2]>,
    /// The two faces of each feature edge.
    faces: Vec<[u32; 2]>,
    /// Corner vertices (three or more feature edges).
    corners: Vec<u32>,
    /// Ends of feature lines inside a patch (one feature edge), sorted.
    ends: Vec<u32>,
    /// Each original triangle's patch.
    pub patches: Vec<u32>,
}

/// The creases of `mesh` ([`Creases`], module docs); `None` when it has no feature line.
pub(crate) fn detect(mesh: &TriMesh) -> Option<Creases> {
    let table = EdgeTable::new(mesh);
    let normals = mesh.face_normals();
    let min_cos = ANGLE_DEGREES.to_radians().cos() as f32;
    // 1. Sharp interior edges.
    let sharp: Vec<usize> = (0..table.len())
        .filter(|&e| {
            if table.face_count(e) != 2 {
                return false;
            }
            let mut f = table.faces(e);
            let (a, b) = (f.next().unwrap_or(0), f.next().unwrap_or(0));
            let (na, nb) = (normals[a as usize], normals[b as usize]);
            na != Vec3::ZERO && nb != Vec3::ZERO && na.dot(nb) < min_cos
        })
        .collect();
    if sharp.is_empty() {
        return None;
    }
    // ... on lines of at least MIN_LINE edges.
    let mut lines = UnionFind::new(mesh.positions.len());
    for &e in &sharp {
        let [u, v] = table.edges[e];
        lines.union(u, v);
    }
    let mut line_edges: HashMap<u32, usize> = HashMap::default();
    for &e in &sharp {
        *line_edges.entry(lines.find(table.edges[e][0])).or_default() += 1;
    }
    let feature: Vec<usize> = sharp
        .into_iter()
        .filter(|&e| line_edges[&lines.find(table.edges[e][0])] >= MIN_LINE)
        .collect();
    let interior = (0..table.len())
        .filter(|&e| table.face_count(e) == 2)
        .count();
    if (feature.len() as f64) < MIN_SHARE * interior as f64 {
        return None;
    }
    let mut is_feature = vec![false; table.len()];
    let mut degree = vec![0u32; mesh.positions.len()];
    for &e in &feature {
        is_feature[e] = true;
        for v in table.edges[e] {
            degree[v as usize] += 1;
        }
    }
    // 2. Corners.
    let corners = (0..degree.len() as u32)
        .filter(|&v| degree[v as usize] >= 3)
        .collect();
    let ends = (0..degree.len() as u32)
        .filter(|&v| degree[v as usize] == 1)
        .collect();
    // 3. Patches, breadth first across the other edges.
    let mut patches = vec![u32::MAX; mesh.triangles.len()];
    let mut next = 0;
    let mut queue = std::collections::VecDeque::new();
    for seed in 0..mesh.triangles.len() {
        if patches[seed] != u32::MAX {
            continue;
        }
        patches[seed] = next;
        queue.push_back(seed);
        while let Some(f) = queue.pop_front() {
            for e in table.face_edges[f] {
                if is_feature[e as usize] {
                    continue;
                }
                for g in table.faces(e as usize) {
                    if patches[g as usize] == u32::MAX {
                        patches[g as usize] = next;
                        queue.push_back(g as usize);
                    }
                }
            }
        }
        next += 1;
    }
    let faces = feature
        .iter()
        .map(|&e| {
            let mut f = table.faces(e);
            [f.next().unwrap_or(0), f.next().unwrap_or(0)]
        })
        .collect();
    Some(Creases {
        edges: feature.iter().map(|&e| table.edges[e]).collect(),
        faces,
        corners,
        ends,
        patches,
    })
}

impl Creases {
    /// The feature edges (original vertex pairs, smaller first, sorted).
    pub(crate) fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Step 4 of the module docs on `mesh` (each triangle's chart in `triangle_charts`,
    /// numbered as the original's `charts`): returns the vertices moved.
    pub(crate) fn pull(
        &self,
        original: &TriMesh,
        grid: &FaceGrid,
        charts: &[u32],
        mesh: &mut TriMesh,
        triangle_charts: &[u32],
        threads: usize,
    ) -> usize {
        let TriMesh {
            positions,
            triangles,
        } = mesh;
        // Charts around each vertex and its longest edge.
        let mut around: Vec<Vec<u32>> = vec![Vec::new(); positions.len()];
        let mut longest = vec![0.0f32; positions.len()];
        for (t, &c) in triangles.iter().zip(triangle_charts) {
            for k in 0..3 {
                let (u, v) = (t[k] as usize, t[(k + 1) % 3] as usize);
                if !around[u].contains(&c) {
                    around[u].push(c);
                }
                let length = positions[u].distance(positions[v]);
                longest[u] = longest[u].max(length);
                longest[v] = longest[v].max(length);
            }
        }
        let mut by_face: HashMap<u32, Vec<usize>> = HashMap::default();
        for (i, f) in self.faces.iter().enumerate() {
            for &f in f {
                by_face.entry(f).or_default().push(i);
            }
        }
        let point = |v: u32| original.positions[v as usize].as_dvec3();
        // The closest point of a feature edge between two charts of `v`.
        let on_line = |v: usize| -> Option<Vec3> {
            let charts_here = &around[v];
            if charts_here.len() < 2 {
                return None;
            }
            let between = |i: usize| {
                let [a, b] = self.faces[i].map(|f| charts[f as usize]);
                a != b && charts_here.contains(&a) && charts_here.contains(&b)
            };
            let p = positions[v];
            let (f, _) = grid.closest(p, |f| {
                by_face
                    .get(&f)
                    .is_some_and(|edges| edges.iter().any(|&i| between(i)))
            })?;
            let q = by_face[&f]
                .iter()
                .filter(|&&i| between(i))
                .filter_map(|&i| {
                    let [a, b] = self.edges[i];
                    let q = mesh::geometry::closest_point_segment(p.as_dvec3(), point(a), point(b));
                    // Not onto a line's loose end: the labels of its two sides meet beyond it,
                    // along no crease.
                    let loose = |v: u32| q == point(v) && self.ends.binary_search(&v).is_ok();
                    (!loose(a) && !loose(b)).then_some(q.as_vec3())
                })
                .min_by(|a, b| a.distance_squared(p).total_cmp(&b.distance_squared(p)))?;
            (q.distance(p) <= longest[v]).then_some(q)
        };
        let pulled = crate::parallel::map_indexed(positions.len(), threads, 256, on_line);
        let mut moved = 0;
        for (p, q) in positions.iter_mut().zip(pulled) {
            if let Some(q) = q {
                *p = q;
                moved += 1;
            }
        }
        // Corners: the closest vertex between three or more charts within its longest edge.
        let junctions: Vec<usize> = (0..positions.len())
            .filter(|&v| around[v].len() >= 3)
            .collect();
        let mut taken = vec![false; positions.len()];
        for &c in &self.corners {
            let corner = original.positions[c as usize];
            let best = junctions
                .iter()
                .copied()
                .filter(|&v| !taken[v] && positions[v].distance(corner) <= longest[v])
                .min_by(|&a, &b| {
                    positions[a]
                        .distance_squared(corner)
                        .total_cmp(&positions[b].distance_squared(corner))
                });
            if let Some(v) = best {
                positions[v] = corner;
                taken[v] = true;
                moved += 1;
            }
        }
        moved
    }
}
