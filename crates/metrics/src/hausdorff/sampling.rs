//! The samples of one direction: the sampling parameters ([`HausdorffParams`], [`SamplingPlan`]),
//! the per-direction seeds, MeshLab's vertex samples and [`draw`], which samples a source mesh in
//! the target index's frame.

use crate::frame::Frame;
use crate::{MetricsError, validate_all_vertices};
use glam::Vec3;
use mesh::TriMesh;
use mesh::sampling::{
    EdgeSampling, FaceSampling, StratifiedParams, StratifiedSamples, SurfaceSample,
    sample_stratified,
};
use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64Mcg;
use serde::{Deserialize, Serialize};

/// Most samples one direction may draw (each costs 16 bytes while it is measured, so two
/// directions at this limit hold about 1.6 GB). Larger requests are refused with
/// [`MetricsError::Parameter`] instead of aborting on allocation; Metro's default
/// (10 × faces) is capped here.
pub const MAX_SAMPLES_PER_DIRECTION: usize = 50_000_000;

/// How `samples` is turned into vertex, edge and face samples per direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum SamplingPlan {
    /// `samples` is the total per direction (vertices + edges + faces), split as `vertices`,
    /// `edges` and `faces` say (Metro's plan; the default).
    #[default]
    Budget,
    /// MeshLab's Hausdorff filter with vertex, edge and face sampling and `samplenum = samples`:
    /// every vertex record of the source, **unreferenced ones included** (MeshLab's
    /// `VertexUniform` takes every vertex of the mesh), or a random `samples` of them when there
    /// are more; plus `samples` edge samples, plus `samples` face samples (e.g. 2,001,407
    /// samples for `samples` = 1,000,000 on a 1,407-vertex mesh). The `vertices` and `edges`
    /// fields are ignored. Every vertex record must then be finite.
    MeshLab,
}

/// Parameters of the sampled surface distance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HausdorffParams {
    /// Samples per direction (see `plan`); `None` uses Metro's default, 10 × the larger face
    /// count (at most [`MAX_SAMPLES_PER_DIRECTION`]). At least 1, at most
    /// [`MAX_SAMPLES_PER_DIRECTION`].
    pub samples: Option<usize>,
    /// How `samples` is split into vertex, edge and face samples.
    #[serde(default)]
    pub plan: SamplingPlan,
    /// Seed of the sampler (the two directions use seeds derived from it).
    pub seed: u64,
    /// Sample the source's referenced vertices.
    pub vertices: bool,
    /// Number of edge samples (Metro's `sqrt(density)` per unit length by default).
    pub edges: EdgeSampling,
    /// Placement of the face samples.
    pub faces: FaceSampling,
    /// Samples with no target point within this distance (model units) are excluded from all
    /// statistics and counted in `excluded` (MeshLab's `maxdist`); `None` keeps every sample.
    pub max_distance: Option<f64>,
}

impl Default for HausdorffParams {
    fn default() -> Self {
        HausdorffParams {
            samples: None,
            plan: SamplingPlan::Budget,
            seed: 1,
            vertices: true,
            edges: EdgeSampling::Metro,
            faces: FaceSampling::Random,
            max_distance: None,
        }
    }
}

impl HausdorffParams {
    /// Default parameters with `samples` samples per direction.
    pub fn with_samples(samples: usize) -> HausdorffParams {
        HausdorffParams {
            samples: Some(samples),
            ..Default::default()
        }
    }

    /// MeshLab's plan ([`SamplingPlan::MeshLab`]) with `samplenum` = `samples`.
    pub fn meshlab(samples: usize) -> HausdorffParams {
        HausdorffParams {
            samples: Some(samples),
            plan: SamplingPlan::MeshLab,
            ..Default::default()
        }
    }

    /// Checks the parameters: `samples` in 1..=[`MAX_SAMPLES_PER_DIRECTION`], an edge share in
    /// [0, 1], a `max_distance` that is a number ≥ 0.
    pub fn validate(&self) -> Result<(), MetricsError> {
        if let Some(n) = self.samples {
            if n == 0 {
                return Err(MetricsError::Parameter {
                    name: "samples",
                    message: "must be at least 1 (0 samples would measure nothing)".into(),
                });
            }
            let factor = if self.plan == SamplingPlan::MeshLab {
                2
            } else {
                1
            };
            if n.saturating_mul(factor) > MAX_SAMPLES_PER_DIRECTION {
                return Err(MetricsError::Parameter {
                    name: "samples",
                    message: format!(
                        "{n} is above the limit of {} samples per direction{}",
                        MAX_SAMPLES_PER_DIRECTION / factor,
                        if factor == 2 {
                            " for the MeshLab plan (edge and face samples each)"
                        } else {
                            ""
                        }
                    ),
                });
            }
        }
        if let EdgeSampling::Share(x) = self.edges
            && !(0.0..=1.0).contains(&x)
        {
            return Err(MetricsError::Parameter {
                name: "edge share",
                message: format!("{x} is outside [0, 1]"),
            });
        }
        if let Some(d) = self.max_distance
            && (d.is_nan() || d < 0.0)
        {
            return Err(MetricsError::Parameter {
                name: "max_distance",
                message: format!("{d} is not a distance >= 0"),
            });
        }
        Ok(())
    }

    /// The stratified plan of one direction for `samples` requested samples (for MeshLab's
    /// plan: its edge and face samples; the vertices are drawn by [`meshlab_vertices`]).
    fn plan_for(&self, samples: usize) -> StratifiedParams {
        match self.plan {
            SamplingPlan::Budget => StratifiedParams {
                total: samples,
                vertices: self.vertices,
                edges: self.edges,
                faces: self.faces,
            },
            SamplingPlan::MeshLab => StratifiedParams {
                total: 2 * samples,
                vertices: false,
                edges: EdgeSampling::Share(0.5),
                faces: self.faces,
            },
        }
    }

    /// True when the plan samples every vertex record, unreferenced ones included.
    pub(crate) fn samples_every_vertex(&self) -> bool {
        self.plan == SamplingPlan::MeshLab
    }
}

/// MeshLab's vertex samples (`VertexUniform`): every vertex record of `mesh`, referenced or not,
/// in index order, or a seeded random `samples` of them when there are more. A vertex sample's
/// face is its first incident face (`u32::MAX` for an unreferenced vertex; vertex samples'
/// faces are never read).
fn meshlab_vertices(mesh: &TriMesh, samples: usize, seed: u64) -> Vec<SurfaceSample> {
    let mut incident = vec![u32::MAX; mesh.positions.len()];
    for (f, t) in mesh.triangles.iter().enumerate() {
        for &v in t {
            if incident[v as usize] == u32::MAX {
                incident[v as usize] = f as u32;
            }
        }
    }
    let mut chosen: Vec<u32> = (0..mesh.positions.len() as u32).collect();
    if chosen.len() > samples {
        // Partial Fisher-Yates: a uniform random subset, then back into index order.
        let mut rng = Pcg64Mcg::seed_from_u64(seed);
        for i in 0..samples {
            let j = rng.random_range(i..chosen.len());
            chosen.swap(i, j);
        }
        chosen.truncate(samples);
        chosen.sort_unstable();
    }
    chosen
        .into_iter()
        .map(|v| SurfaceSample {
            position: mesh.positions[v as usize],
            face: incident[v as usize],
        })
        .collect()
}

/// Derives the per-direction seed (splitmix64 finaliser of `seed + salt`).
pub(crate) fn derive_seed(seed: u64, salt: u64) -> u64 {
    let mut z = seed.wrapping_add(salt.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The samples of one direction, ready to be measured, in the frame of the target.
pub(crate) struct Drawn {
    pub(super) samples: StratifiedSamples,
    pub(super) normals: Vec<Vec3>,
}

impl Drawn {
    /// The samples, in the target's frame.
    pub(crate) fn samples(&self) -> &[SurfaceSample] {
        &self.samples.samples
    }
}

/// Draws the samples of one direction on `source` (validated), held in `frame` (the target
/// index's).
pub(crate) fn draw(
    source: &TriMesh,
    frame: &Frame,
    params: &HausdorffParams,
    samples: usize,
    seed: u64,
) -> Result<Drawn, MetricsError> {
    if source.triangles.is_empty() {
        return Err(MetricsError::NoTriangles { mesh: "source" });
    }
    let every_vertex = params.samples_every_vertex();
    if every_vertex {
        validate_all_vertices(source, "source")?;
    }
    frame.check_span(source, "source", every_vertex)?;
    let local = frame.apply(source);
    let plan = params.plan_for(samples);
    let mut drawn =
        sample_stratified(&local, &plan, seed).map_err(|problem| MetricsError::Invalid {
            mesh: "source",
            problem,
        })?;
    if every_vertex {
        // Own seed, so the edge and face samples are those of a mesh without the extra vertices.
        let mut all = meshlab_vertices(&local, samples, derive_seed(seed, 3));
        drawn.vertex_count = all.len();
        all.append(&mut drawn.samples);
        drawn.samples = all;
    }
    Ok(Drawn {
        samples: drawn,
        normals: local.face_normals(),
    })
}
