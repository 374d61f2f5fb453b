//! Garland–Heckbert quadric error metric (QEM) simplification of triangle meshes.
//!
//! [`simplify`] contracts vertex pairs (mesh edges, plus non-edge pairs closer than
//! [`QemParams::pair_threshold`]) in order of increasing area-weighted quadric error, placing each
//! merged vertex at the quadric minimiser (with segment / endpoint fallbacks). Boundary edges get
//! weighted perpendicular constraint planes, and with [`QemParams::preserve_topology`] collapses
//! that break the link condition or flip a face are rejected. All arithmetic is in f64.
//!
//! Contractions are scheduled in passes over a cost-sorted candidate list (see `simplifier`):
//! within a pass pairs are taken in increasing cost while their endpoints are untouched, up to a
//! cost cap, which keeps the order close to the greedy heap order of the paper at a fraction of
//! the memory traffic.
//!
//! Threads: the set-up steps use the rayon pool (same result for any thread count). Meshes of at
//! least 500,000 faces on a pool of more than one thread are simplified by spatial parts in
//! parallel (shared vertices locked, then one sequential pass over the stitched result), so their
//! output depends on the number of threads; with `RAYON_NUM_THREADS=1`, or below that size, the
//! sequential engine runs and the output is the same for every thread count.
//!
//! One entry point, [`simplify`], takes a [`mesh::Model`]: with attributes (normals, texture
//! coordinates, colours, materials) they are kept through the contractions, and
//! [`QemParams::lock`] keeps chosen vertices ([`Lock`]) where they are.
//!
//! ```
//! use gng3d_qem::{QemParams, Target, simplify};
//! let sphere = mesh::Model::from(mesh::procedural::icosphere(4)); // 2,562 vertices, 5,120 faces
//! let params = QemParams::with_target(Target::Vertices(500));
//! let (coarse, report) = simplify(&sphere, &params).unwrap();
//! let coarse = coarse.mesh;
//! assert!(coarse.vertex_count() <= 500 && coarse.face_count() > 900);
//! // The unit sphere stays a unit sphere: every vertex within 1 % of radius 1.
//! assert!(coarse.positions.iter().all(|p| (p.length() - 1.0).abs() < 0.01));
//! println!("{} collapses in {:.3} s", report.collapses, report.seconds);
//! ```

mod pairs;
pub mod quadric;
mod radix;
mod simplifier;

pub use quadric::Quadric;

use mesh::cancel::Cancel;
use mesh::{Model, TriMesh};
use serde::{Deserialize, Serialize};

/// What to simplify down to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Target {
    /// Stop at this many referenced vertices.
    Vertices(usize),
    /// Stop at this many faces (the result may have one face fewer: an interior collapse removes two).
    Faces(usize),
    /// Stop at this fraction of the input face count, in (0, 1].
    Ratio(f64),
}

/// Parameters of [`simplify`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QemParams {
    /// Size to reach.
    pub target: Target,
    /// Stop before the first contraction whose quadric error exceeds this (model units⁴: area ×
    /// squared distance, the same units as [`QemReport::max_error`]).
    pub max_error: Option<f64>,
    /// Pair distance threshold `t` in model units: 0 contracts edges only, `t > 0` also contracts
    /// non-edge vertex pairs closer than `t` (aggregation of nearby parts): each vertex is paired
    /// with its [`max_pairs_per_vertex`](Self::max_pairs_per_vertex) closest vertices within `t`,
    /// found with a k-d tree, so the search costs about the same for any `t`. At most the
    /// bounding-box diagonal of the mesh's referenced vertices: larger values are refused with
    /// [`QemError::InvalidParameter`] naming that limit (beyond it every vertex is within `t` of
    /// every other). With `preserve_topology` a non-edge pair is only merged when the two
    /// vertices share no neighbour (so no non-manifold edge appears); the merge itself joins parts
    /// at a vertex, i.e. it changes topology by design.
    pub pair_threshold: f64,
    /// At most this many non-edge pairs (the closest ones) per vertex when `pair_threshold > 0`;
    /// at most 64 (refused above: the search and the pairs' memory grow with it).
    pub max_pairs_per_vertex: usize,
    /// Add perpendicular constraint planes along boundary edges.
    pub preserve_boundary: bool,
    /// Weight of the boundary constraint planes (multiplied by the squared edge length).
    pub boundary_weight: f64,
    /// Weight of the seams' constraint planes when the model has attributes (multiplied by
    /// the squared edge length; ignored without). Default 1, meshoptimizer's seam weight: the
    /// planes keep a seam from sliding across the surface, but they also make every contraction
    /// of a seam vertex costlier, so where seams are dense (texture atlases of many small charts)
    /// heavy planes leave the seams finely sampled and take the vertices from the charts'
    /// insides. A seam vertex contracted along its seam stays in its seam edge's plane instead
    /// (the engine's placement). On two 10,000-face atlases of 190 and 250 charts (14.5 and
    /// 16.4 % of the edges on seams) at 30 / 20 / 15 / 10 % of the faces, Hausdorff distance
    /// against meshoptimizer's `simplifyWithAttributes` 1.86 / 1.81 / 1.38 / 2.40 × at weight
    /// 15, 1.06-1.13 / 1.14-1.22 / 1.02-1.20 / 1.17-1.23 × at 1, mean distance 0.72-1.03 ×,
    /// UV error 0.89-1.02 × meshoptimizer's (docs/notes/attributes.md "Seam plane weight,
    /// again").
    #[serde(default = "default_seam_weight")]
    pub seam_weight: f64,
    /// Reject contractions that break the link condition (manifoldness, genus) or flip faces.
    pub preserve_topology: bool,
    /// With `preserve_topology`: a contraction is rejected if some face normal would turn so that
    /// cos(angle between old and new normal) falls to or below this value.
    pub min_normal_cos: f64,
    /// Weight `w` of an edge-length term added to every contraction's cost, `w · |a − b|⁴` in
    /// the normalised frame (unit box diagonal; the quadric costs there are area × squared
    /// distance, also length⁴). 0 (default) is Garland–Heckbert. A small weight breaks the ties
    /// of flat regions (quadric cost ≈ 0) in favour of short edges, so the vertices that remain
    /// stay evenly spread there: GNG3D-Q's oversampled decimation uses it to keep the uniform
    /// network's small vertex gaps (E_max).
    #[serde(default)]
    pub edge_length_weight: f64,
    /// Stop rule as a distance: no contraction whose error, as a distance, exceeds this
    /// fraction of the bounding-box diagonal of the referenced vertices (`None`: no such rule).
    /// The distance of a contraction is `sqrt(cost / area)`: its quadric cost (area × squared
    /// distance in the normalised frame whose box diagonal is 1; attribute runs add the weighted
    /// attribute error) over the summed area of the faces its two quadrics were built from, i.e.
    /// the area-weighted RMS distance of the merged vertex to the planes of those faces, as
    /// meshoptimizer's relative `target_error`. Pairs above the bound are skipped (they come back
    /// when a neighbouring contraction changes them); the run ends when the size target is
    /// reached or no contraction within the bound is left ([`StopReason::MaxError`]). With
    /// [`Target::Faces`]`(0)` it is the only stop rule. The largest such distance of a performed
    /// contraction is [`QemReport::max_relative_error`].
    #[serde(default)]
    pub max_relative_error: Option<f64>,
    /// Weights of the attribute error in the collapse cost when the model has attributes
    /// (ignored without).
    #[serde(default)]
    pub attribute_weights: AttributeWeights,
    /// The vertices never contracted ([`Lock`]; default none). Serialized only when some are.
    #[serde(default, skip_serializing_if = "Lock::is_none")]
    pub lock: Lock,
    /// Stops the run from another thread: when the flag is set, [`simplify`] returns
    /// [`QemError::Cancelled`] at its next check (between the set-up steps, between passes and
    /// every few thousand contractions), never a partial mesh. `None` (the default): not
    /// cancellable. Not part of the serialized parameters; equal when both are `None` or share
    /// one flag.
    #[serde(skip)]
    pub cancel: Option<Cancel>,
}

/// Weights of the attribute error (Hoppe 1999's attribute quadrics, minimised over the value at
/// the geometric placement; docs/notes/qem.md "Attribute error") in the collapse cost of
/// [`simplify`] on a model with attributes. A weight scales its attribute's values before the
/// error is taken, so an attribute deviation `δ` costs as much as a distance `weight · δ` in
/// units of the bounding-box diagonal. 0 leaves the attribute out of the cost (all 0: the order
/// is the geometric one), which is the default: measured, a weight bought less attribute error
/// than it cost geometry on the test assets except normals at CAD creases
/// (docs/notes/attributes.md).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct AttributeWeights {
    /// Texture coordinates (both sets; a texture is 1 × 1 in UV units).
    pub uv: f64,
    /// Unit normals.
    pub normal: f64,
    /// RGBA colours in [0, 1].
    pub color: f64,
}

impl Default for AttributeWeights {
    fn default() -> Self {
        AttributeWeights {
            uv: DEFAULT_UV_WEIGHT,
            normal: DEFAULT_NORMAL_WEIGHT,
            color: DEFAULT_COLOR_WEIGHT,
        }
    }
}

impl AttributeWeights {
    /// No attribute in the cost: the collapse order is the geometric one.
    pub const NONE: AttributeWeights = AttributeWeights {
        uv: 0.0,
        normal: 0.0,
        color: 0.0,
    };
}

// Default attribute weights: none, the geometric order (docs/notes/attributes.md, "Attribute
// weights"). Measured at 10 % with the harness docs/results/attributes_vs_meshopt.py after the
// chart-per-triangle transfer: with all weights 0 QEM's UV error on spot (mean / 99th pct
// 3.9e-3 / 2.4e-2, 1 UV-flipped triangle of 586) and on the fandisk atlas (2.0e-4 mean) is
// already below meshoptimizer's at the same weights, and its geometry is the best; uv 0.25 cost
// spot 22 % Hausdorff for a worse UV error, colour 0.25 cost the knight 12 % for 1 % less colour
// error, and every normal weight tried (0.02-0.1) took fandisk's Hausdorff 2.7-3.3 × up (its
// smoothed normals change fastest at the creases) for normals at creases within 2-3° instead of
// 45° at the 99th percentile: a trade a user makes with `--attribute-weights normal=0.05`, not
// a default.
const DEFAULT_UV_WEIGHT: f64 = 0.0;
const DEFAULT_NORMAL_WEIGHT: f64 = 0.0;
const DEFAULT_COLOR_WEIGHT: f64 = 0.0;

fn default_seam_weight() -> f64 {
    1.0
}

impl Default for QemParams {
    fn default() -> Self {
        QemParams {
            target: Target::Ratio(0.5),
            max_error: None,
            pair_threshold: 0.0,
            max_pairs_per_vertex: 8,
            preserve_boundary: true,
            boundary_weight: 1000.0,
            seam_weight: default_seam_weight(),
            preserve_topology: true,
            min_normal_cos: 0.2,
            edge_length_weight: 0.0,
            max_relative_error: None,
            attribute_weights: AttributeWeights::default(),
            lock: Lock::None,
            cancel: None,
        }
    }
}

impl QemParams {
    /// Check every parameter (the same checks [`simplify`] makes first): front ends call this
    /// before loading a mesh so that a bad option costs nothing.
    pub fn validate(&self) -> Result<(), QemError> {
        simplifier::validate(self)
    }

    /// Default parameters with the given target.
    pub fn with_target(target: Target) -> Self {
        QemParams {
            target,
            ..Default::default()
        }
    }
}

/// The vertices [`simplify`] never contracts ([`QemParams::lock`]): they keep their positions
/// and stay in the output, as do the faces between them. Meant for borders shared with other
/// meshes (tiles, parts of an assembly) and vertices a rig or a gameplay script refers to. A
/// lock runs the sequential engine (no spatial parts), so the result does not depend on the
/// thread count.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Lock {
    /// None: every vertex may be contracted.
    #[default]
    None,
    /// The vertices on the mesh's border edges ([`border_vertices`]; `--lock-border`).
    Border,
    /// The vertices flagged here, one flag per vertex of the mesh (another length is refused
    /// with [`QemError::InvalidParameter`]).
    Vertices(Vec<bool>),
}

impl Lock {
    /// Whether no vertex is locked ([`Lock::None`]).
    pub fn is_none(&self) -> bool {
        *self == Lock::None
    }
}

/// Why the contraction loop ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The requested vertex or face count was reached.
    TargetReached,
    /// The next contraction would have exceeded `max_error`.
    MaxError,
    /// No valid contraction was left (topology / flip checks blocked the rest): best effort.
    NoValidPairs,
    /// No valid contraction was left in a run that keeps attributes, and most vertices left
    /// are where the attributes' seams end or cross ([`QemReport::fixed_seam_vertices`]),
    /// which such a run never contracts (nor does meshoptimizer's): the texture layout is the
    /// floor. The same mesh without its attributes goes further.
    Seams,
}

/// Outcome of [`simplify`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct QemReport {
    /// Referenced vertices of the input.
    pub input_vertices: usize,
    /// Faces of the input that were used (faces repeating a vertex index are dropped).
    pub input_faces: usize,
    /// Contractions performed.
    pub collapses: usize,
    /// Vertices of the output.
    pub vertices: usize,
    /// Faces of the output.
    pub faces: usize,
    /// Largest quadric error of a performed contraction (model units⁴).
    pub max_error: f64,
    /// Wall-clock seconds spent in [`simplify`].
    pub seconds: f64,
    /// Whether the target was reached.
    pub target_reached: bool,
    /// Why the loop ended.
    pub stop_reason: StopReason,
    /// Contractions rejected by the topology / normal checks.
    pub rejected: usize,
    /// Non-edge pairs found within `pair_threshold`.
    pub virtual_pairs: usize,
    /// Contraction passes over the sorted candidate list.
    pub passes: usize,
    /// With [`QemParams::max_relative_error`]: the largest error of a performed contraction as
    /// a distance, a fraction of the input's bounding-box diagonal (`sqrt(cost / area)`, see
    /// there); `None` without it.
    #[serde(default)]
    pub max_relative_error: Option<f64>,
    /// Vertices of the output where the attributes' seams end or cross (a run that keeps
    /// attributes never contracts them); 0 without attributes.
    #[serde(default)]
    pub fixed_seam_vertices: usize,
}

impl QemReport {
    /// The sentence front ends show when the run stopped before `target` (the target it was
    /// given), `None` when it reached it, e.g. "QEM stopped at 118 of 40 vertices: no further
    /// contraction keeps the mesh's topology or passes the normal check".
    ///
    /// ```
    /// use gng3d_qem::{QemParams, Target};
    /// // 12 vertices, closed: 4 at best (a tetrahedron)
    /// let ico = mesh::Model::from(mesh::procedural::icosphere(0));
    /// let target = Target::Vertices(3);
    /// let (out, report) = gng3d_qem::simplify(&ico, &QemParams::with_target(target)).unwrap();
    /// let note = report.shortfall(target).unwrap();
    /// let vertices = out.mesh.vertex_count();
    /// assert!(note.starts_with(&format!("QEM stopped at {vertices} of 3 vertices")));
    /// let params = QemParams::with_target(Target::Vertices(6));
    /// let (_, reached) = gng3d_qem::simplify(&ico, &params).unwrap();
    /// assert_eq!(reached.shortfall(Target::Vertices(6)), None);
    /// ```
    pub fn shortfall(&self, target: Target) -> Option<String> {
        if self.target_reached {
            return None;
        }
        let at = match target {
            Target::Vertices(n) => format!("{} of {n} vertices", self.vertices),
            Target::Faces(n) => format!("{} of {n} faces", self.faces),
            Target::Ratio(r) => format!(
                "{} faces, {:.4} of the input's {} (target {r})",
                self.faces,
                self.faces as f64 / self.input_faces.max(1) as f64,
                self.input_faces
            ),
        };
        let why = match self.stop_reason {
            StopReason::TargetReached => "target reached".to_string(),
            StopReason::MaxError => {
                "no further contraction stays within the error bound".to_string()
            }
            StopReason::NoValidPairs => {
                "no further contraction keeps the mesh's topology or passes the normal check"
                    .to_string()
            }
            StopReason::Seams => format!(
                "{} of the vertices left are where texture or attribute seams end or cross, \
                 which a run that keeps the attributes does not contract; with the \
                 attributes dropped it goes further",
                self.fixed_seam_vertices
            ),
        };
        Some(format!("QEM stopped at {at}: {why}"))
    }
}

/// Errors of [`simplify`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum QemError {
    /// The mesh has no usable face.
    #[error("the mesh has no (non-degenerate) faces")]
    EmptyMesh,
    /// A face references a vertex that does not exist.
    #[error("face {face} references vertex {index}, but the mesh has {vertices} vertices")]
    InvalidIndex {
        /// Face index.
        face: usize,
        /// Offending vertex index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A referenced vertex has a NaN or infinite coordinate.
    #[error("vertex {0} has a non-finite coordinate")]
    NonFiniteVertex(usize),
    /// A parameter is out of range.
    #[error("invalid parameter: {0}")]
    InvalidParameter(String),
    /// The model's attributes do not fit its mesh.
    #[error("the attributes do not fit the mesh: {0}")]
    InvalidAttributes(String),
    /// The run was stopped through [`QemParams::cancel`].
    #[error("simplification cancelled")]
    Cancelled,
}

/// Simplify `model` by quadric-error pair contraction; returns the simplified model (no
/// unreferenced vertices, no degenerate or duplicate faces; the input's materials and origin,
/// [`Model::with_mesh`]) and a report. The vertices of [`QemParams::lock`] are never contracted.
///
/// With attributes (`model.attributes`, which must fit the mesh:
/// [`mesh::attributes::Attributes::validate`]) the output keeps the normals, texture
/// coordinates, colours and materials. The collapse order and placement are then still
/// Garland–Heckbert's (plus [`QemParams::attribute_weights`], none by default). Seams (edges
/// across which a value or the material changes) keep their place: each seam edge gets a
/// constraint plane as a boundary edge does (weight [`QemParams::seam_weight`]), a vertex on a
/// seam moves only along it (contracted with a neighbour along the same seam), a vertex off the
/// seams is contracted with another vertex off them or into a seam vertex, which then stays
/// where it is (as meshoptimizer lets a manifold vertex collapse onto a seam), and seam ends,
/// crossings and vertices whose values differ around them without a seam (a sphere's pole) are
/// not contracted; so every output triangle lies on one side of every seam. The values travel
/// with the contractions, one set per side of a seam: a vertex never contracted keeps each
/// corner's input values exactly; a merged vertex gets, for texture coordinates and colours,
/// the area-weighted least-squares fit of the linear functions of the original faces merged
/// into it, evaluated at its new position (Hoppe 1999's attribute optimum; colours clamped to
/// [0, 1]), and for normals their interpolation along the contracted edges, normalised. Always
/// runs the sequential engine (no spatial parts), so the result does not depend on the thread
/// count.
///
/// ```
/// use gng3d_qem::{QemParams, Target, simplify};
/// let (sphere, uv) = mesh::procedural::textured_sphere(24, 48); // UV sphere, meridian seam
/// let model = mesh::Model {
///     attributes: Some(uv),
///     ..mesh::Model::from(sphere)
/// };
/// let params = QemParams::with_target(Target::Ratio(0.25));
/// let (coarse, report) = simplify(&model, &params).unwrap();
/// let attributes = coarse.attributes.unwrap();
/// attributes.validate(&coarse.mesh).unwrap();
/// assert!(report.faces < model.mesh.face_count() / 3);
/// assert!(!attributes.seam_edges(&coarse.mesh).is_empty()); // the meridian is still a seam
/// ```
///
/// A lock:
///
/// ```
/// use gng3d_qem::{Lock, QemParams, Target, border_vertices, simplify};
/// let grid = mesh::Model::from(mesh::procedural::unit_square_grid(20)); // a square border
/// let params = QemParams {
///     lock: Lock::Border,
///     ..QemParams::with_target(Target::Ratio(0.1))
/// };
/// let (coarse, _) = simplify(&grid, &params).unwrap();
/// // every border vertex is still there, where it was
/// let border = border_vertices(&grid.mesh);
/// for (v, _) in border.iter().enumerate().filter(|&(_, &l)| l) {
///     assert!(coarse.mesh.positions.contains(&grid.mesh.positions[v]));
/// }
/// ```
pub fn simplify(model: &Model, params: &QemParams) -> Result<(Model, QemReport), QemError> {
    let input = &model.mesh;
    let border;
    let locked = match &params.lock {
        Lock::None => None,
        // A face naming a missing vertex: no mask to make; the run refuses the mesh.
        Lock::Border if !indices_in_range(input) => None,
        Lock::Border => {
            border = border_vertices(input);
            Some(border.as_slice())
        }
        Lock::Vertices(mask) => Some(mask.as_slice()),
    };
    let (mesh, attributes, report) = match (&model.attributes, locked) {
        (Some(a), locked) => simplifier::run_with_attributes(input, a, params, locked)
            .map(|(m, a, r)| (m, Some(a), r))?,
        (None, Some(locked)) => {
            simplifier::run_locked(input, params, locked).map(|(m, r)| (m, None, r))?
        }
        (None, None) => simplifier::run(input, params).map(|(m, r)| (m, None, r))?,
    };
    Ok((model.with_mesh(mesh, attributes), report))
}

/// Whether every face of `mesh` names existing vertices.
fn indices_in_range(mesh: &TriMesh) -> bool {
    let n = mesh.positions.len();
    mesh.triangles.iter().flatten().all(|&v| (v as usize) < n)
}

/// The vertices of `mesh` on a border edge (an edge with one face): the mask of [`Lock::Border`]
/// (`--lock-border`).
pub fn border_vertices(mesh: &TriMesh) -> Vec<bool> {
    let table = mesh::topology::EdgeTable::new(mesh);
    let mut border = vec![false; mesh.positions.len()];
    for (e, &[a, b]) in table.edges.iter().enumerate() {
        if table.is_boundary(e) {
            border[a as usize] = true;
            border[b as usize] = true;
        }
    }
    border
}
