//! Surface sampling: seeded area-weighted Monte Carlo samples and Metro-style stratified samples.
//!
//! Two samplers live here:
//! - [`AreaSampler`] draws one uniformly distributed surface point at a time from any RNG
//!   (Walker/Vose alias table over triangle areas, O(1) per draw); [`sample_surface`] is the
//!   seeded batch form. GNG training uses it as a signal source.
//! - [`sample_stratified`] reproduces the Metro sampling plan (Cignoni, Rocchini, Scopigno 1998):
//!   every referenced vertex, every unique edge at `sqrt(density)` samples per unit length, and
//!   the faces at `density` samples per unit area with the fractional remainder carried from
//!   face to face. Samples come out grouped (vertices, then edges, then faces) and in mesh order,
//!   so neighbouring samples are usually close in space.
//!
//! All samplers are deterministic for a given seed (PCG-64 MCG generator).

use crate::TriMesh;
use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// A point on a mesh surface and the triangle it lies on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SurfaceSample {
    /// Position in model units.
    pub position: Vec3,
    /// Index of the triangle the sample lies on (for vertex and edge samples: one incident triangle).
    pub face: u32,
}

/// Why a mesh cannot be sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SamplingError {
    /// A triangle refers to a vertex index that does not exist.
    #[error("triangle {face} refers to vertex {vertex}, but the mesh has {vertex_count} vertices")]
    InvalidIndex {
        /// The offending triangle.
        face: usize,
        /// The out-of-range vertex index.
        vertex: u32,
        /// Number of vertex records.
        vertex_count: usize,
    },
    /// A referenced vertex has a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFinite {
        /// The offending vertex.
        vertex: usize,
    },
    /// The mesh has no triangle with positive area.
    #[error("the mesh has no triangle with positive area")]
    ZeroArea,
}

/// Checks that every triangle index is in range and every referenced vertex is finite.
pub fn validate(mesh: &TriMesh) -> Result<(), SamplingError> {
    let n = mesh.positions.len();
    for (face, tri) in mesh.triangles.iter().enumerate() {
        for &vertex in tri {
            let Some(p) = mesh.positions.get(vertex as usize) else {
                return Err(SamplingError::InvalidIndex {
                    face,
                    vertex,
                    vertex_count: n,
                });
            };
            if !p.is_finite() {
                return Err(SamplingError::NonFinite {
                    vertex: vertex as usize,
                });
            }
        }
    }
    Ok(())
}

/// Uniform random barycentric coordinates `(u, v)` of a point in a triangle `a + u·ab + v·ac`
/// (parallelogram folding: two uniforms, no rejection).
#[inline]
fn random_barycentric<R: Rng + ?Sized>(rng: &mut R) -> (f64, f64) {
    let u: f64 = rng.random();
    let v: f64 = rng.random();
    if u + v > 1.0 {
        (1.0 - u, 1.0 - v)
    } else {
        (u, v)
    }
}

/// One alias-table slot: keep this face with probability `keep`, otherwise take `alias`.
#[derive(Debug, Clone, Copy)]
struct AliasSlot {
    keep: f64,
    alias: u32,
}

/// Draws area-weighted uniform surface samples one at a time (alias method, O(1) per draw).
///
/// The sampler owns a copy of the triangle corners, so it does not borrow the mesh.
#[derive(Debug, Clone)]
pub struct AreaSampler {
    /// Per sampleable triangle: corner `a`, edge `b - a`, edge `c - a`.
    corners: Vec<[Vec3; 3]>,
    /// Original face index of each sampleable triangle.
    faces: Vec<u32>,
    table: Vec<AliasSlot>,
    area: f64,
}

impl AreaSampler {
    /// Builds the sampler over all triangles with positive area.
    pub fn new(mesh: &TriMesh) -> Result<AreaSampler, SamplingError> {
        AreaSampler::weighted(mesh, |_, area| area)
    }

    /// Builds a sampler whose triangle probabilities are `weight(face, area)` instead of the
    /// area (e.g. curvature-weighted areas); triangles with zero area or a non-positive or
    /// non-finite weight are never drawn. Points stay uniform inside each triangle.
    pub fn weighted(
        mesh: &TriMesh,
        weight: impl Fn(usize, f64) -> f64,
    ) -> Result<AreaSampler, SamplingError> {
        validate(mesh)?;
        let mut corners = Vec::with_capacity(mesh.triangles.len());
        let mut faces = Vec::with_capacity(mesh.triangles.len());
        let mut areas = Vec::with_capacity(mesh.triangles.len());
        for f in 0..mesh.triangles.len() {
            let area = mesh.triangle_area(f);
            let w = if area > 0.0 && area.is_finite() {
                weight(f, area)
            } else {
                0.0
            };
            if w > 0.0 && w.is_finite() {
                let [a, b, c] = mesh.triangle(f);
                corners.push([a, b - a, c - a]);
                faces.push(f as u32);
                areas.push(w);
            }
        }
        if areas.is_empty() {
            return Err(SamplingError::ZeroArea);
        }
        let area: f64 = areas.iter().sum();
        let table = alias_table(&areas, area);
        Ok(AreaSampler {
            corners,
            faces,
            table,
            area,
        })
    }

    /// Total area of the sampled triangles, in squared model units.
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Draws one uniformly distributed surface point (three uniform draws from `rng`).
    #[inline]
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> SurfaceSample {
        let n = self.table.len();
        let x: f64 = rng.random::<f64>() * n as f64;
        let slot = (x as usize).min(n - 1);
        let frac = x - slot as f64;
        let entry = self.table[slot];
        let chosen = if frac < entry.keep {
            slot
        } else {
            entry.alias as usize
        };
        let (u, v) = random_barycentric(rng);
        let [a, ab, ac] = self.corners[chosen];
        SurfaceSample {
            position: a + ab * u as f32 + ac * v as f32,
            face: self.faces[chosen],
        }
    }
}

/// Vose's alias table for the discrete distribution `weights / total`.
fn alias_table(weights: &[f64], total: f64) -> Vec<AliasSlot> {
    let n = weights.len();
    let mut scaled: Vec<f64> = weights.iter().map(|w| w * n as f64 / total).collect();
    let mut table = vec![
        AliasSlot {
            keep: 1.0,
            alias: 0,
        };
        n
    ];
    let mut small: Vec<u32> = Vec::new();
    let mut large: Vec<u32> = Vec::new();
    for (i, &s) in scaled.iter().enumerate() {
        if s < 1.0 {
            small.push(i as u32);
        } else {
            large.push(i as u32);
        }
    }
    while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
        small.pop();
        table[s as usize] = AliasSlot {
            keep: scaled[s as usize],
            alias: l,
        };
        scaled[l as usize] -= 1.0 - scaled[s as usize];
        if scaled[l as usize] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    // Leftovers (rounding) keep themselves with probability 1.
    for i in small.into_iter().chain(large) {
        table[i as usize] = AliasSlot {
            keep: 1.0,
            alias: i,
        };
    }
    table
}

/// `count` area-weighted uniform random surface samples, reproducible for a given `seed`.
///
/// Returns an empty vector when the mesh cannot be sampled (no positive-area triangle, bad
/// indices or non-finite coordinates; use [`AreaSampler::new`] to get the reason).
pub fn sample_surface(mesh: &TriMesh, count: usize, seed: u64) -> Vec<SurfaceSample> {
    let Ok(sampler) = AreaSampler::new(mesh) else {
        return Vec::new();
    };
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    (0..count).map(|_| sampler.sample(&mut rng)).collect()
}

/// How face samples are placed inside each triangle by [`sample_stratified`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FaceSampling {
    /// Per-face count from the carried remainder, points uniformly random inside the face.
    #[default]
    Random,
    /// Per-face count from the carried remainder rounded down to a square `m²`; the points are the
    /// centroids of the `m²` similar sub-triangles (deterministic lattice). The rest carries on.
    SimilarTriangles,
}

/// How many edge samples [`sample_stratified`] draws. Edge samples are interior points of the
/// unique edges, spread by length with carried remainders.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EdgeSampling {
    /// No edge samples.
    None,
    /// Metro: `sqrt(total / area)` samples per unit length, capped at half of what the vertex
    /// samples leave of the budget.
    #[default]
    Metro,
    /// This share (0..=1) of what the vertex samples leave of the budget. MeshLab's Hausdorff
    /// filter with vertex, edge and face sampling draws all vertices plus `samplenum` edge and
    /// `samplenum` face samples, i.e. `Share(0.5)` of `total = vertices + 2 · samplenum`.
    Share(f64),
}

/// Parameters of the Metro-style stratified sampling plan.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StratifiedParams {
    /// Requested total number of samples (vertices + edges + faces).
    pub total: usize,
    /// Include the referenced vertices (all of them, or a seeded random half of the budget when
    /// there are more than `total / 2`).
    pub vertices: bool,
    /// Number of edge samples.
    pub edges: EdgeSampling,
    /// Placement of the face samples.
    pub faces: FaceSampling,
}

impl Default for StratifiedParams {
    fn default() -> Self {
        StratifiedParams {
            total: 100_000,
            vertices: true,
            edges: EdgeSampling::Metro,
            faces: FaceSampling::Random,
        }
    }
}

/// Stratified samples, grouped: `samples[..vertex_count]` are vertices, the next `edge_count`
/// are edge points and the last `face_count` are area-weighted face points.
#[derive(Debug, Clone, PartialEq)]
pub struct StratifiedSamples {
    /// All samples in group order.
    pub samples: Vec<SurfaceSample>,
    /// Number of vertex samples at the front.
    pub vertex_count: usize,
    /// Number of edge samples after the vertices.
    pub edge_count: usize,
    /// Number of face samples at the end.
    pub face_count: usize,
}

/// A unique undirected edge, its length in model units and one incident triangle.
#[derive(Debug, Clone, Copy)]
struct Edge {
    v: [u32; 2],
    face: u32,
}

/// Unique undirected edges in (lower vertex, higher vertex) order, each with the lowest incident
/// face index, from the one edge builder of the crate ([`crate::topology::EdgeTable`], whose
/// half-edges are sorted by id within an edge); edges of a degenerate face that join a vertex
/// to itself are skipped.
fn unique_edges(mesh: &TriMesh) -> Vec<Edge> {
    let table = crate::topology::EdgeTable::new(mesh);
    table
        .edges
        .iter()
        .enumerate()
        .filter(|(_, v)| v[0] != v[1])
        .map(|(e, &v)| Edge {
            v,
            face: table.edge_corners[table.offsets[e] as usize] / 3,
        })
        .collect()
}

/// Metro-style stratified sampling: vertices, edges and faces, reproducible for a given `seed`.
///
/// Budget: `V` vertex samples (all referenced vertices, or a random subset of `total / 2`), then
/// `E` edge samples (see [`EdgeSampling`]; Metro's default is
/// `min(sqrt(total / A) · L, (total - V) / 2)` for total edge length `L`) spread over the unique
/// edges by length with carried remainders, then exactly `total - V - E` face samples
/// spread over the faces by area with carried remainders (so face samples are area-weighted and
/// stratified: each face gets `floor` or `ceil` of its expected share).
pub fn sample_stratified(
    mesh: &TriMesh,
    params: &StratifiedParams,
    seed: u64,
) -> Result<StratifiedSamples, SamplingError> {
    validate(mesh)?;
    let areas: Vec<f64> = (0..mesh.triangles.len())
        .map(|f| mesh.triangle_area(f))
        .collect();
    let area: f64 = areas.iter().sum();
    if !(area > 0.0 && area.is_finite()) {
        return Err(SamplingError::ZeroArea);
    }
    let mut rng = Pcg64Mcg::seed_from_u64(seed);
    let total = params.total;
    let mut samples: Vec<SurfaceSample> = Vec::with_capacity(total + 16);

    // 1. Vertices: one incident face per referenced vertex.
    if params.vertices {
        let mut incident = vec![u32::MAX; mesh.positions.len()];
        for (f, t) in mesh.triangles.iter().enumerate() {
            for &v in t {
                if incident[v as usize] == u32::MAX {
                    incident[v as usize] = f as u32;
                }
            }
        }
        let mut referenced: Vec<u32> = (0..mesh.positions.len() as u32)
            .filter(|&v| incident[v as usize] != u32::MAX)
            .collect();
        let budget = total / 2;
        if referenced.len() > budget {
            // Partial Fisher-Yates: a uniform random subset, then back into index order.
            for i in 0..budget {
                let j = rng.random_range(i..referenced.len());
                referenced.swap(i, j);
            }
            referenced.truncate(budget);
            referenced.sort_unstable();
        }
        samples.extend(referenced.iter().map(|&v| SurfaceSample {
            position: mesh.positions[v as usize],
            face: incident[v as usize],
        }));
    }
    let vertex_count = samples.len();

    // 2. Edges: interior points at a uniform linear density, remainders carried along.
    if params.edges != EdgeSampling::None {
        let edges = unique_edges(mesh);
        let length = |e: &Edge| {
            (mesh.positions[e.v[1] as usize].as_dvec3()
                - mesh.positions[e.v[0] as usize].as_dvec3())
            .length()
        };
        let total_length: f64 = edges.iter().map(length).sum();
        if total_length > 0.0 {
            let rest = total.saturating_sub(vertex_count) as f64;
            let wanted = match params.edges {
                EdgeSampling::Share(share) => (rest * share.clamp(0.0, 1.0)).round(),
                _ => ((total as f64 / area).sqrt() * total_length).min((rest / 2.0).floor()),
            };
            // A hair above the wanted density so the carried remainder reaches the exact count.
            let per_length = wanted / total_length * (1.0 + 1e-12);
            let mut carry = 0.0f64;
            for e in &edges {
                carry += length(e) * per_length;
                let k = carry.floor();
                carry -= k;
                let k = k as usize;
                let p0 = mesh.positions[e.v[0] as usize].as_dvec3();
                let p1 = mesh.positions[e.v[1] as usize].as_dvec3();
                for i in 0..k {
                    let t = (i + 1) as f64 / (k + 1) as f64;
                    samples.push(SurfaceSample {
                        position: p0.lerp(p1, t).as_vec3(),
                        face: e.face,
                    });
                }
            }
        }
    }
    let edge_count = samples.len() - vertex_count;

    // 3. Faces: exactly `budget` samples; face f gets floor(C_f) - floor(C_{f-1}) where C is the
    // cumulative expected count, i.e. Metro's carried remainder without drift.
    let budget = total.saturating_sub(vertex_count + edge_count);
    let mut cumulative = 0.0f64;
    let mut emitted = 0usize;
    let mut lattice_carry = 0usize;
    let faces = mesh.triangles.len();
    for (f, &face_area) in areas.iter().enumerate() {
        cumulative += face_area;
        let upto = if f + 1 == faces {
            budget
        } else {
            ((cumulative / area * budget as f64).floor() as usize).min(budget)
        };
        let k = upto.saturating_sub(emitted);
        emitted += k;
        if k == 0 && lattice_carry == 0 {
            continue;
        }
        let [a, b, c] = mesh.triangle_f64(f);
        let (ab, ac) = (b - a, c - a);
        let push = |samples: &mut Vec<SurfaceSample>, u: f64, v: f64| {
            samples.push(SurfaceSample {
                position: (a + ab * u + ac * v).as_vec3(),
                face: f as u32,
            });
        };
        match params.faces {
            FaceSampling::Random => {
                for _ in 0..k {
                    let (u, v) = random_barycentric(&mut rng);
                    push(&mut samples, u, v);
                }
            }
            FaceSampling::SimilarTriangles => {
                let wanted = k + lattice_carry;
                if face_area <= 0.0 {
                    lattice_carry = wanted;
                    continue;
                }
                let m = (wanted as f64).sqrt().floor() as usize;
                lattice_carry = wanted - m * m;
                let inv = 1.0 / m.max(1) as f64;
                for i in 0..m {
                    for j in 0..m - i {
                        // "Upward" sub-triangle with corner (i, j).
                        push(
                            &mut samples,
                            (i as f64 + 1.0 / 3.0) * inv,
                            (j as f64 + 1.0 / 3.0) * inv,
                        );
                        if i + j + 2 <= m {
                            // "Downward" sub-triangle sharing the same lattice cell.
                            push(
                                &mut samples,
                                (i as f64 + 2.0 / 3.0) * inv,
                                (j as f64 + 2.0 / 3.0) * inv,
                            );
                        }
                    }
                }
            }
        }
    }
    let face_count = samples.len() - vertex_count - edge_count;
    Ok(StratifiedSamples {
        samples,
        vertex_count,
        edge_count,
        face_count,
    })
}

/// Closest distance from `p` to segment `ab` (helper for tests of sample placement).
#[cfg(test)]
fn point_segment_distance(p: glam::DVec3, a: glam::DVec3, b: glam::DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).length()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::procedural::{icosphere, torus};
    use glam::DVec3;

    /// Distance from `p` to the plane of face `f` and whether its barycentrics are inside.
    fn on_face(mesh: &TriMesh, f: usize, p: Vec3) -> bool {
        let [a, b, c] = mesh.triangle_f64(f);
        let p = p.as_dvec3();
        let n = (b - a).cross(c - a);
        let scale = (b - a).length().max((c - a).length());
        let off_plane = (p - a).dot(n.normalize()).abs();
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(u, w)| (w - u).cross(p - u).dot(n) >= -1e-6 * n.length() * scale);
        off_plane < 1e-5 * scale && inside
    }

    #[test]
    fn monte_carlo_is_reproducible_on_surface_and_area_weighted() {
        // Two triangles with areas 1 and 3: the big one should get ~75% of the samples.
        let mesh = TriMesh::new(
            vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 2.0, 0.0),
                Vec3::new(10.0, 0.0, 0.0),
                Vec3::new(13.0, 0.0, 0.0),
                Vec3::new(10.0, 0.0, 2.0),
            ],
            vec![[0, 1, 2], [3, 4, 5]],
        );
        let a = sample_surface(&mesh, 40_000, 7);
        let b = sample_surface(&mesh, 40_000, 7);
        let c = sample_surface(&mesh, 40_000, 8);
        assert_eq!(a, b);
        assert_ne!(a, c);
        for s in &a {
            assert!(on_face(&mesh, s.face as usize, s.position));
        }
        let big = a.iter().filter(|s| s.face == 1).count() as f64 / a.len() as f64;
        // Binomial standard deviation is ~0.002; allow 5 sigma.
        assert!((big - 0.75).abs() < 0.011, "fraction on big face {big}");
        // Uniform inside a face: the mean of the samples is the centroid.
        let mean = a
            .iter()
            .filter(|s| s.face == 0)
            .fold(DVec3::ZERO, |m, s| m + s.position.as_dvec3())
            / a.iter().filter(|s| s.face == 0).count() as f64;
        assert!((mean - DVec3::new(1.0 / 3.0, 2.0 / 3.0, 0.0)).length() < 0.02);
    }

    #[test]
    fn degenerate_and_bad_meshes_give_errors_not_panics() {
        let flat = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::X * 2.0], vec![[0, 1, 2]]);
        assert_eq!(
            AreaSampler::new(&flat).unwrap_err(),
            SamplingError::ZeroArea
        );
        assert!(sample_surface(&flat, 10, 1).is_empty());
        let bad = TriMesh::new(vec![Vec3::ZERO, Vec3::X], vec![[0, 1, 5]]);
        assert!(matches!(
            AreaSampler::new(&bad),
            Err(SamplingError::InvalidIndex { vertex: 5, .. })
        ));
        assert!(sample_stratified(&bad, &StratifiedParams::default(), 1).is_err());
        let nan = TriMesh::new(vec![Vec3::ZERO, Vec3::X, Vec3::NAN], vec![[0, 1, 2]]);
        assert!(matches!(
            sample_stratified(&nan, &StratifiedParams::default(), 1),
            Err(SamplingError::NonFinite { vertex: 2 })
        ));
    }

    #[test]
    fn stratified_budget_groups_and_placement() {
        let mesh = torus(1.0, 0.3, 48, 24);
        let params = StratifiedParams {
            total: 60_000,
            ..Default::default()
        };
        let s = sample_stratified(&mesh, &params, 3).unwrap();
        assert_eq!(s.vertex_count, mesh.vertex_count());
        assert!(s.edge_count > 0 && s.edge_count <= (60_000 - s.vertex_count) / 2);
        assert_eq!(s.samples.len(), 60_000);
        assert_eq!(
            s.vertex_count + s.edge_count + s.face_count,
            s.samples.len()
        );
        for (i, smp) in s.samples.iter().enumerate() {
            let f = smp.face as usize;
            assert!(on_face(&mesh, f, smp.position), "sample {i} off its face");
            if (s.vertex_count..s.vertex_count + s.edge_count).contains(&i) {
                let [a, b, c] = mesh.triangle_f64(f);
                let p = smp.position.as_dvec3();
                let d = point_segment_distance(p, a, b)
                    .min(point_segment_distance(p, b, c))
                    .min(point_segment_distance(p, c, a));
                assert!(d < 1e-6, "edge sample {i} not on an edge of its face");
            }
        }
        // Each face gets floor or ceil of its expected share.
        let mut per_face = vec![0usize; mesh.face_count()];
        for smp in &s.samples[s.vertex_count + s.edge_count..] {
            per_face[smp.face as usize] += 1;
        }
        let density = s.face_count as f64 / mesh.area();
        for (f, &n) in per_face.iter().enumerate() {
            let expected = mesh.triangle_area(f) * density;
            assert!(
                (n as f64 - expected).abs() < 1.0 + 1e-9,
                "face {f}: {n} vs {expected}"
            );
        }
        let again = sample_stratified(&mesh, &params, 3).unwrap();
        assert_eq!(s, again);
        // MeshLab's plan: all vertices, then equal edge and face counts.
        let meshlab = StratifiedParams {
            total: mesh.vertex_count() + 2 * 20_000,
            edges: EdgeSampling::Share(0.5),
            ..params
        };
        let m = sample_stratified(&mesh, &meshlab, 3).unwrap();
        assert_eq!(m.vertex_count, mesh.vertex_count());
        assert!(m.edge_count.abs_diff(20_000) <= 1, "{}", m.edge_count);
        assert_eq!(m.samples.len(), meshlab.total);
    }

    #[test]
    fn unique_edges_match_euler_counts() {
        let sphere = icosphere(3);
        // Closed triangle mesh: E = 3F / 2.
        assert_eq!(unique_edges(&sphere).len(), sphere.face_count() * 3 / 2);
        let t = torus(1.0, 0.25, 16, 8);
        assert_eq!(unique_edges(&t).len(), 3 * 16 * 8);
    }

    #[test]
    fn similar_triangles_lattice_is_uniform() {
        // One triangle, 16 samples: a 4x4 lattice whose centroid is the triangle's centroid and
        // whose points are all distinct and inside.
        let mesh = TriMesh::new(
            vec![
                Vec3::ZERO,
                Vec3::new(2.0, 0.0, 0.0),
                Vec3::new(0.0, 3.0, 0.0),
            ],
            vec![[0, 1, 2]],
        );
        let params = StratifiedParams {
            total: 16,
            vertices: false,
            edges: EdgeSampling::None,
            faces: FaceSampling::SimilarTriangles,
        };
        let s = sample_stratified(&mesh, &params, 1).unwrap();
        assert_eq!(s.face_count, 16);
        let mean = s
            .samples
            .iter()
            .fold(DVec3::ZERO, |m, p| m + p.position.as_dvec3())
            / 16.0;
        assert!((mean - DVec3::new(2.0 / 3.0, 1.0, 0.0)).length() < 1e-6);
        for (i, p) in s.samples.iter().enumerate() {
            assert!(on_face(&mesh, 0, p.position));
            for q in &s.samples[i + 1..] {
                assert!((p.position - q.position).length() > 1e-3);
            }
        }
    }

    #[test]
    fn vertex_subset_when_budget_is_small() {
        let mesh = icosphere(4); // 2562 vertices
        let params = StratifiedParams {
            total: 1000,
            ..Default::default()
        };
        let s = sample_stratified(&mesh, &params, 9).unwrap();
        assert_eq!(s.vertex_count, 500);
        assert_eq!(s.samples.len(), 1000);
        let mut seen: Vec<Vec3> = s.samples[..500].iter().map(|p| p.position).collect();
        seen.dedup();
        assert_eq!(seen.len(), 500);
    }
}
