//! Metro-style attribute deviation ([`attribute_deviation`]): how far a simplified mesh's
//! texture coordinates, normals and colours are from the original's where the surfaces meet.
//!
//! One direction samples the *source* surface (area-weighted face samples, the sampler of
//! [`crate::hausdorff`]), interpolates the source's attribute at each sample on that triangle's
//! corner wedges, finds the sample's exact closest point on the *target* (the
//! [`SurfaceDistanceIndex`] of the distances) and compares with the target's attribute
//! interpolated there on the target triangle's wedges. Where the closest point lies on a seam
//! (an edge or corner whose triangles hold different wedges) every triangle around it that is
//! equally close (within [`TIE`] of the original's bounding-box diagonal) is a candidate, and
//! the one whose value is nearest counts: a point exactly on a seam has both sides' values, and
//! the sample is not blamed for the side the search happened to return.
//!
//! Both directions are measured: `backward` (samples on the simplified mesh, closest points on
//! the original: what a renderer shows, the direction of docs/notes/attributes.md) and
//! `forward` (samples on the original, closest points on the simplified mesh: detail the
//! simplified mesh lost). Only attributes present in both meshes are compared.
//!
//! This module holds the parameters, the report and the driver ([`attribute_deviation`]); one
//! direction is measured in [`direction`].

mod direction;

use direction::{Target, Which, one_direction};

use crate::frame::Frame;
use crate::hausdorff::{DistanceStats, HausdorffParams, MAX_SAMPLES_PER_DIRECTION};
use crate::index::SurfaceDistanceIndex;
use crate::{MetricsError, validate_mesh};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::sampling::{EdgeSampling, FaceSampling};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Two closest points count as equally close when their distances differ by at most this
/// share of the original's bounding-box diagonal (about one unit of the frame distances are
/// measured in): the two sides of a seam through the closest point.
pub const TIE: f64 = 1e-9;

/// Parameters of [`attribute_deviation`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AttributeParams {
    /// Face samples per direction; `None`: 10 × the larger face count (Metro's default, as
    /// [`HausdorffParams::samples`]), at most [`MAX_SAMPLES_PER_DIRECTION`] / 2. At least 1.
    pub samples: Option<usize>,
    /// Seed of the sampler (the two directions use seeds derived from it).
    pub seed: u64,
    /// Side of the (square) texture, in texels, that UV distances are also reported in:
    /// 1 UV unit = `texture_size` texels. At least 1; default 1024.
    pub texture_size: u32,
    /// A sample whose UV distance is above this (UV units) counts in
    /// [`UvDeviation::over_threshold`]. A number ≥ 0; default 0.05.
    pub uv_threshold: f64,
}

impl Default for AttributeParams {
    fn default() -> Self {
        AttributeParams {
            samples: None,
            seed: 1,
            texture_size: 1024,
            uv_threshold: 0.05,
        }
    }
}

impl AttributeParams {
    /// Checks the parameters (see the fields for the accepted ranges).
    pub fn validate(&self) -> Result<(), MetricsError> {
        self.hausdorff(1).validate()?;
        if self.texture_size == 0 {
            return Err(MetricsError::Parameter {
                name: "texture_size",
                message: "must be at least 1 texel".into(),
            });
        }
        if !(self.uv_threshold >= 0.0 && self.uv_threshold.is_finite()) {
            return Err(MetricsError::Parameter {
                name: "uv_threshold",
                message: format!("{} is not a finite UV distance >= 0", self.uv_threshold),
            });
        }
        Ok(())
    }

    /// The sampling of one direction: `samples` face samples, no vertices, no edges.
    fn hausdorff(&self, default: usize) -> HausdorffParams {
        HausdorffParams {
            samples: Some(self.samples.unwrap_or(default)),
            seed: self.seed,
            vertices: false,
            edges: EdgeSampling::None,
            faces: FaceSampling::Random,
            ..HausdorffParams::default()
        }
    }
}

/// Texture-coordinate deviation of one direction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct UvDeviation {
    /// Mean, RMS and largest UV distance over the samples, UV units (the texture is 1 × 1).
    pub uv: DistanceStats,
    /// The same in texels of a `texture_size`² texture.
    pub texels: DistanceStats,
    /// Share of the samples (0 to 1) whose UV distance is above `uv_threshold`.
    pub over_threshold: f64,
}

/// Normal deviation of one direction: the angle between the interpolated (renormalised)
/// normals, degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AngleDeviation {
    /// Mean angle, degrees.
    pub mean_degrees: f64,
    /// Largest angle, degrees.
    pub max_degrees: f64,
}

/// One direction's deviations, per attribute; `None` where the attribute is not in both meshes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AttributeErrors {
    /// Samples measured (face samples of the source).
    pub samples: usize,
    /// First texture coordinates.
    pub uv0: Option<UvDeviation>,
    /// Second texture coordinates.
    pub uv1: Option<UvDeviation>,
    /// Normals.
    pub normals: Option<AngleDeviation>,
    /// Colours: Euclidean distance in linear RGB, each channel 0 to 1 (alpha not counted).
    pub colors: Option<DistanceStats>,
}

/// Attribute deviation between an original and a simplified mesh (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttributeDeviation {
    /// Samples on the simplified mesh against the original at their closest points.
    pub backward: AttributeErrors,
    /// Samples on the original against the simplified mesh at their closest points.
    pub forward: AttributeErrors,
    /// Attributes compared (present in both): of `normals`, `uv0`, `uv1`, `colors`.
    pub compared: Vec<String>,
    /// Attributes of the original the simplified mesh does not have (not measured).
    pub missing: Vec<String>,
    /// Texels per UV unit of the texel figures.
    pub texture_size: u32,
    /// The threshold of [`UvDeviation::over_threshold`], UV units.
    pub uv_threshold: f64,
    /// Wall-clock time of the measurement, seconds.
    pub seconds: f64,
}

/// Checks that `attributes` fit `mesh`, naming the mesh in the error.
fn check_attributes(
    mesh: &TriMesh,
    attributes: &Attributes,
    which: &'static str,
) -> Result<(), MetricsError> {
    attributes
        .validate(mesh)
        .map_err(|problem| MetricsError::Attributes {
            mesh: which,
            problem,
        })
}

/// Metro-style deviation of the attributes of `simplified` (with `simplified_attributes`) from
/// those of `original` (with `original_attributes`), both directions (see the module docs).
/// Only attributes present in both are measured (listed in `compared`; those only the original
/// has are listed in `missing`); with none in common nothing is sampled (`samples` 0).
///
/// UV distances are in UV units and in texels of a `params.texture_size`² texture, normal
/// deviations in degrees, colour distances in RGB units (0 to 1 per channel). Deterministic for
/// a given `params.seed`, whatever the thread count.
///
/// ```
/// use gng3d_metrics::{AttributeParams, attribute_deviation};
/// let (sphere, attributes) = mesh::procedural::textured_sphere(16, 32);
/// let params = AttributeParams { samples: Some(5_000), ..AttributeParams::default() };
/// let same = attribute_deviation(&sphere, &attributes, &sphere, &attributes, &params).unwrap();
/// let uv = same.backward.uv0.unwrap();
/// assert!(uv.uv.max < 1e-6 && uv.over_threshold == 0.0);
/// assert_eq!(same.compared, ["normals", "uv0"]);
/// ```
pub fn attribute_deviation(
    original: &TriMesh,
    original_attributes: &Attributes,
    simplified: &TriMesh,
    simplified_attributes: &Attributes,
    params: &AttributeParams,
) -> Result<AttributeDeviation, MetricsError> {
    let start = Instant::now();
    params.validate()?;
    validate_mesh(original, "original")?;
    validate_mesh(simplified, "simplified")?;
    check_attributes(original, original_attributes, "original")?;
    check_attributes(simplified, simplified_attributes, "simplified")?;
    let which = Which::of(original_attributes, simplified_attributes);
    let present = Which::of(original_attributes, original_attributes);
    let missing = Which {
        normals: present.normals && !which.normals,
        uv0: present.uv0 && !which.uv0,
        uv1: present.uv1 && !which.uv1,
        colors: present.colors && !which.colors,
    };
    let none = AttributeErrors {
        samples: 0,
        uv0: None,
        uv1: None,
        normals: None,
        colors: None,
    };
    let mut out = AttributeDeviation {
        backward: none,
        forward: none,
        compared: which.names(),
        missing: missing.names(),
        texture_size: params.texture_size,
        uv_threshold: params.uv_threshold,
        seconds: 0.0,
    };
    if which.any() {
        let samples = params.samples.unwrap_or(
            (10 * original.face_count().max(simplified.face_count()))
                .clamp(1, MAX_SAMPLES_PER_DIRECTION / 2),
        );
        let frame = Frame::of_mesh(original);
        frame.check_span(simplified, "simplified", false)?;
        let (original_index, simplified_index) = rayon::join(
            || SurfaceDistanceIndex::in_frame(original, frame),
            || SurfaceDistanceIndex::in_frame(simplified, frame),
        );
        let (original_index, simplified_index) = (original_index?, simplified_index?);
        let to_original = Target::new(original, original_attributes, &original_index);
        let to_simplified = Target::new(simplified, simplified_attributes, &simplified_index);
        let (backward, forward) = rayon::join(
            || {
                one_direction(
                    simplified,
                    simplified_attributes,
                    &to_original,
                    which,
                    params,
                    samples,
                    crate::hausdorff::derive_seed(params.seed, 2),
                )
            },
            || {
                one_direction(
                    original,
                    original_attributes,
                    &to_simplified,
                    which,
                    params,
                    samples,
                    crate::hausdorff::derive_seed(params.seed, 1),
                )
            },
        );
        out.backward = backward.map_err(|e| crate::hausdorff::rename(e, "simplified"))?;
        out.forward = forward.map_err(|e| crate::hausdorff::rename(e, "original"))?;
    }
    out.seconds = start.elapsed().as_secs_f64();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec2, Quat, Vec2, Vec3, Vec4};
    use mesh::fixtures::attribute_values_near;
    use mesh::procedural::textured_sphere;
    use mesh::sampling::{StratifiedParams, sample_stratified};
    use mesh::transfer::barycentric;

    fn params(samples: usize) -> AttributeParams {
        AttributeParams {
            samples: Some(samples),
            ..AttributeParams::default()
        }
    }

    /// Brute force, sharing nothing with the module but the sampler: the face samples the
    /// direction draws (same plan, seed and frame), and for each every face of `target` within
    /// `TIE` of the closest distance (exhaustive search, model units), the nearest of their UVs.
    /// Mean, RMS and max of the UV distance.
    fn brute_uv(
        source: &TriMesh,
        source_attributes: &Attributes,
        target: &TriMesh,
        target_attributes: &Attributes,
        frame_of: &TriMesh,
        samples: usize,
        salt: u64,
    ) -> DistanceStats {
        let frame = Frame::of_mesh(frame_of);
        let scale = frame.scale();
        let local = frame.apply(source);
        let plan = StratifiedParams {
            total: samples,
            vertices: false,
            edges: EdgeSampling::None,
            faces: FaceSampling::Random,
        };
        let seed = crate::hausdorff::derive_seed(1, salt);
        let drawn = sample_stratified(&local, &plan, seed).unwrap();
        let su = source_attributes.uv0.as_ref().unwrap();
        let tu = target_attributes.uv0.as_ref().unwrap();
        let (mut sum, mut sum2, mut max) = (0.0f64, 0.0f64, 0.0f64);
        for s in &drawn.samples {
            let p = frame.to_model(s.position.as_dvec3());
            let [a, b, c] = source.triangle_f64(s.face as usize);
            let w = barycentric(p, a, b, c);
            let cs = source_attributes.corners[s.face as usize];
            let mine: DVec2 = (0..3).map(|k| su[cs[k] as usize].as_dvec2() * w[k]).sum();
            let near =
                attribute_values_near(target, target_attributes, tu, p.as_vec3(), TIE * scale);
            let d = near
                .iter()
                .map(|v| v.as_dvec2().distance(mine))
                .fold(f64::INFINITY, f64::min);
            sum += d;
            sum2 += d * d;
            max = max.max(d);
        }
        let n = drawn.samples.len() as f64;
        DistanceStats {
            max,
            mean: sum / n,
            rms: (sum2 / n).sqrt(),
        }
    }

    fn close(a: DistanceStats, b: DistanceStats, tol: f64) {
        for (x, y) in [(a.max, b.max), (a.mean, b.mean), (a.rms, b.rms)] {
            assert!((x - y).abs() <= tol, "{a:?} vs {b:?}");
        }
    }

    #[test]
    fn a_mesh_against_itself_deviates_by_nothing() {
        let (sphere, attributes) = textured_sphere(12, 24);
        let r = attribute_deviation(&sphere, &attributes, &sphere, &attributes, &params(20_000))
            .unwrap();
        for dir in [&r.backward, &r.forward] {
            assert_eq!(dir.samples, 20_000);
            let uv = dir.uv0.unwrap();
            assert!(uv.uv.max < 1e-6, "{uv:?}");
            assert_eq!(uv.over_threshold, 0.0);
            assert!(dir.normals.unwrap().max_degrees < 0.05, "{dir:?}");
            assert!(dir.uv1.is_none() && dir.colors.is_none());
        }
        assert_eq!(r.compared, ["normals", "uv0"]);
        assert!(r.missing.is_empty());
    }

    #[test]
    fn both_directions_match_brute_force_on_a_coarser_sphere() {
        let (fine, fa) = textured_sphere(16, 32);
        let (coarse, ca) = textured_sphere(8, 16);
        let n = 4_000;
        let r = attribute_deviation(&fine, &fa, &coarse, &ca, &params(n)).unwrap();
        let backward = brute_uv(&coarse, &ca, &fine, &fa, &fine, n, 2);
        let forward = brute_uv(&fine, &fa, &coarse, &ca, &fine, n, 1);
        // The fixture interpolates in f32.
        close(r.backward.uv0.unwrap().uv, backward, 1e-6);
        close(r.forward.uv0.unwrap().uv, forward, 1e-6);
        // Not nothing: the coarse sphere's chords cross the fine one's UV lattice.
        assert!(backward.mean > 1e-4, "{backward:?}");
        // Fine samples outside the coarse sphere near its seam meridian have their closest point
        // on the seam edge: the rule takes the nearer side; the far side (the other end of the
        // texture) would be a whole UV unit away.
        assert!(forward.max < 0.1, "{forward:?}");
    }

    #[test]
    fn shifted_uvs_deviate_by_the_shift_in_uv_units_and_texels() {
        let (sphere, attributes) = textured_sphere(10, 20);
        let mut shifted = attributes.clone();
        let offset = Vec2::new(0.01, 0.02);
        for uv in shifted.uv0.as_mut().unwrap() {
            *uv += offset;
        }
        let len = offset.as_dvec2().length();
        for (texture_size, threshold, over) in [(1024, 0.05, 0.0), (4096, 0.02, 1.0)] {
            let p = AttributeParams {
                texture_size,
                uv_threshold: threshold,
                ..params(10_000)
            };
            let r = attribute_deviation(&sphere, &attributes, &sphere, &shifted, &p).unwrap();
            for dir in [&r.backward, &r.forward] {
                let uv = dir.uv0.unwrap();
                let want = DistanceStats {
                    max: len,
                    mean: len,
                    rms: len,
                };
                close(uv.uv, want, 1e-6);
                let t = f64::from(texture_size);
                close(
                    uv.texels,
                    DistanceStats {
                        max: len * t,
                        mean: len * t,
                        rms: len * t,
                    },
                    1e-6 * t,
                );
                assert_eq!(uv.over_threshold, over);
            }
        }
    }

    #[test]
    fn rotated_normals_deviate_by_the_angle() {
        // A flat grid with normals along z, and the same with every normal turned 10° about
        // x (a rotation moves only a normal perpendicular to its axis by the full angle).
        let grid = mesh::procedural::unit_square_grid(8);
        let mut up = Attributes::per_vertex(&grid);
        up.normals = Some(vec![Vec3::Z; grid.vertex_count()]);
        let mut turned = up.clone();
        let q = Quat::from_axis_angle(Vec3::X, 10f32.to_radians());
        turned.normals = Some(vec![q * Vec3::Z; grid.vertex_count()]);
        let r = attribute_deviation(&grid, &up, &grid, &turned, &params(10_000)).unwrap();
        for dir in [&r.backward, &r.forward] {
            let n = dir.normals.unwrap();
            assert!((n.mean_degrees - 10.0).abs() < 1e-4, "{n:?}");
            assert!((n.max_degrees - 10.0).abs() < 1e-4, "{n:?}");
        }
        // On the sphere, with radial normals turned about a fixed axis: each sample by the
        // angle its normal makes with the axis, 2·asin(sin 5° · |n × axis|), at most 10°.
        let (sphere, attributes) = textured_sphere(10, 20);
        let mut rotated = attributes.clone();
        for n in rotated.normals.as_mut().unwrap() {
            *n = q * *n;
        }
        let r =
            attribute_deviation(&sphere, &attributes, &sphere, &rotated, &params(10_000)).unwrap();
        let n = r.backward.normals.unwrap();
        assert!(n.max_degrees <= 10.0 + 1e-4 && n.max_degrees > 9.9, "{n:?}");
        // The mean of 2·asin(sin 5° · sin θ) over the sphere (θ from the x axis) is about
        // 10° · π/4 for a small angle.
        assert!(
            (n.mean_degrees - 2.5 * std::f64::consts::PI).abs() < 0.05,
            "{n:?}"
        );
    }

    #[test]
    fn colours_deviate_by_their_rgb_distance_and_alpha_is_not_counted() {
        let (sphere, mut attributes) = textured_sphere(10, 20);
        attributes.colors = Some(
            (attributes.wedge_vertex.iter())
                .map(|&v| {
                    let p = sphere.positions[v as usize] * 0.5 + 0.5;
                    p.extend(1.0)
                })
                .collect(),
        );
        let mut changed = attributes.clone();
        for c in changed.colors.as_mut().unwrap() {
            *c += Vec4::new(0.1, -0.2, 0.0, -0.5);
        }
        let r =
            attribute_deviation(&sphere, &attributes, &sphere, &changed, &params(10_000)).unwrap();
        let want = 0.05f64.sqrt();
        for dir in [&r.backward, &r.forward] {
            let c = dir.colors.unwrap();
            close(
                c,
                DistanceStats {
                    max: want,
                    mean: want,
                    rms: want,
                },
                1e-6,
            );
        }
        assert_eq!(r.compared, ["normals", "uv0", "colors"]);
    }

    #[test]
    fn only_shared_attributes_are_measured_and_the_rest_are_named() {
        let (sphere, attributes) = textured_sphere(8, 16);
        let mut uv_only = attributes.clone();
        uv_only.normals = None;
        let r =
            attribute_deviation(&sphere, &attributes, &sphere, &uv_only, &params(1_000)).unwrap();
        assert_eq!(r.compared, ["uv0"]);
        assert_eq!(r.missing, ["normals"]);
        assert!(r.backward.normals.is_none() && r.backward.uv0.is_some());
        let bare = Attributes::per_vertex(&sphere);
        let r = attribute_deviation(&sphere, &attributes, &sphere, &bare, &params(1_000)).unwrap();
        assert!(r.compared.is_empty());
        assert_eq!(r.missing, ["normals", "uv0"]);
        assert_eq!(r.backward.samples, 0);
    }

    #[test]
    fn deterministic_regardless_of_thread_count() {
        let (fine, fa) = textured_sphere(16, 32);
        let (coarse, ca) = textured_sphere(6, 12);
        let run = |threads| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| attribute_deviation(&fine, &fa, &coarse, &ca, &params(20_000)))
                .unwrap()
        };
        let (mut one, mut three) = (run(1), run(3));
        one.seconds = 0.0;
        three.seconds = 0.0;
        assert_eq!(one, three);
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let (sphere, attributes) = textured_sphere(6, 12);
        let mut bad = attributes.clone();
        bad.uv0.as_mut().unwrap().pop();
        let e = attribute_deviation(&sphere, &attributes, &sphere, &bad, &params(100)).unwrap_err();
        assert!(
            matches!(
                e,
                MetricsError::Attributes {
                    mesh: "simplified",
                    ..
                }
            ),
            "{e}"
        );
        for p in [
            params(0),
            AttributeParams {
                texture_size: 0,
                ..params(10)
            },
            AttributeParams {
                uv_threshold: f64::NAN,
                ..params(10)
            },
        ] {
            let e = attribute_deviation(&sphere, &attributes, &sphere, &attributes, &p);
            assert!(matches!(e, Err(MetricsError::Parameter { .. })), "{e:?}");
        }
    }
}
