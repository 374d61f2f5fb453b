//! One direction of the attribute deviation: which attributes are compared ([`Which`]), their
//! values interpolated at a point of a triangle, the deviations between two sets of values, and
//! [`one_direction`], which samples the source, finds each sample's closest points on the
//! [`Target`] (every equally close triangle around a seam) and sums the deviations per chunk.

use super::{AngleDeviation, AttributeErrors, AttributeParams, TIE, UvDeviation};
use crate::MetricsError;
use crate::frame::Frame;
use crate::hausdorff::{DistanceStats, draw};
use crate::index::{NO_SLOT, SurfaceDistanceIndex};
use glam::{DVec2, DVec3};
use mesh::TriMesh;
use mesh::attributes::Attributes;
use mesh::geometry::closest_point_triangle;
use mesh::transfer::barycentric;
use rayon::prelude::*;

/// Samples per work chunk (fixed so that results do not depend on the thread count).
const CHUNK: usize = 8192;

/// Which attributes are compared, in the order of [`Attributes::names`] (materials aside).
#[derive(Clone, Copy, Default)]
pub(super) struct Which {
    pub(super) normals: bool,
    pub(super) uv0: bool,
    pub(super) uv1: bool,
    pub(super) colors: bool,
}

impl Which {
    pub(super) fn of(a: &Attributes, b: &Attributes) -> Which {
        Which {
            normals: a.normals.is_some() && b.normals.is_some(),
            uv0: a.uv0.is_some() && b.uv0.is_some(),
            uv1: a.uv1.is_some() && b.uv1.is_some(),
            colors: a.colors.is_some() && b.colors.is_some(),
        }
    }

    pub(super) fn names(self) -> Vec<String> {
        [
            (self.normals, "normals"),
            (self.uv0, "uv0"),
            (self.uv1, "uv1"),
            (self.colors, "colors"),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, n)| n.to_string())
        .collect()
    }

    pub(super) fn any(self) -> bool {
        self.normals || self.uv0 || self.uv1 || self.colors
    }
}

/// The attribute values at one point of a surface (those not compared stay zero).
#[derive(Clone, Copy, Default)]
struct Values {
    normal: DVec3,
    uv0: DVec2,
    uv1: DVec2,
    color: DVec3,
}

/// The values of `attributes` on triangle `face` at barycentric weights `w`; the normal is
/// renormalised (the corner of largest weight's when the blend cancels out).
fn interpolate(which: Which, attributes: &Attributes, face: u32, w: [f64; 3]) -> Values {
    let c = attributes.corners[face as usize].map(|x| x as usize);
    let mut out = Values::default();
    if which.normals
        && let Some(n) = &attributes.normals
    {
        let sum: DVec3 = (0..3).map(|k| n[c[k]].as_dvec3() * w[k]).sum();
        let top = (0..3).max_by(|&i, &j| w[i].total_cmp(&w[j])).unwrap_or(0);
        out.normal = sum
            .try_normalize()
            .unwrap_or_else(|| n[c[top]].as_dvec3().normalize_or_zero());
    }
    if which.uv0
        && let Some(uv) = &attributes.uv0
    {
        out.uv0 = (0..3).map(|k| uv[c[k]].as_dvec2() * w[k]).sum();
    }
    if which.uv1
        && let Some(uv) = &attributes.uv1
    {
        out.uv1 = (0..3).map(|k| uv[c[k]].as_dvec2() * w[k]).sum();
    }
    if which.colors
        && let Some(col) = &attributes.colors
    {
        out.color = (0..3).map(|k| col[c[k]].truncate().as_dvec3() * w[k]).sum();
    }
    out
}

/// The deviations between two sets of values: UV distances, normal angle in degrees, colour
/// distance (`[normal, uv0, uv1, color]`).
fn deviations(a: &Values, b: &Values) -> [f64; 4] {
    let cos = a.normal.dot(b.normal).clamp(-1.0, 1.0);
    [
        cos.acos().to_degrees(),
        a.uv0.distance(b.uv0),
        a.uv1.distance(b.uv1),
        a.color.distance(b.color),
    ]
}

/// Sums of one measure over a chunk of samples.
#[derive(Clone, Copy, Default)]
struct Acc {
    sum: f64,
    sum2: f64,
    max: f64,
    over: usize,
}

impl Acc {
    fn add(&mut self, d: f64, threshold: f64) {
        self.sum += d;
        self.sum2 += d * d;
        self.max = self.max.max(d);
        self.over += usize::from(d > threshold);
    }

    fn merge(mut self, o: Acc) -> Acc {
        self.sum += o.sum;
        self.sum2 += o.sum2;
        self.max = self.max.max(o.max);
        self.over += o.over;
        self
    }

    fn stats(&self, n: usize) -> DistanceStats {
        let n = n.max(1) as f64;
        DistanceStats {
            max: self.max,
            mean: self.sum / n,
            rms: (self.sum2 / n).sqrt(),
        }
    }
}

/// The target of one direction: its mesh, attributes and index, and what the seam rule needs.
pub(super) struct Target<'a> {
    mesh: &'a TriMesh,
    attributes: &'a Attributes,
    index: &'a SurfaceDistanceIndex,
    /// The faces around each vertex: `fan_faces[fan_start[v]..fan_start[v + 1]]`.
    fan_start: Vec<u32>,
    fan_faces: Vec<u32>,
    /// Vertices whose corners hold more than one set of values (on a seam).
    seam: Vec<bool>,
}

impl<'a> Target<'a> {
    pub(super) fn new(
        mesh: &'a TriMesh,
        attributes: &'a Attributes,
        index: &'a SurfaceDistanceIndex,
    ) -> Target<'a> {
        let n = mesh.positions.len();
        let mut fan_start = vec![0u32; n + 1];
        for t in &mesh.triangles {
            for &v in t {
                fan_start[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            fan_start[v + 1] += fan_start[v];
        }
        let mut fill = fan_start.clone();
        let mut fan_faces = vec![0u32; 3 * mesh.triangles.len()];
        let mut first = vec![u32::MAX; n];
        let mut seam = vec![false; n];
        for (f, (t, c)) in mesh.triangles.iter().zip(&attributes.corners).enumerate() {
            for k in 0..3 {
                let v = t[k] as usize;
                fan_faces[fill[v] as usize] = f as u32;
                fill[v] += 1;
                if first[v] == u32::MAX {
                    first[v] = c[k];
                } else if !attributes.same_values(first[v], c[k]) {
                    seam[v] = true;
                }
            }
        }
        Target {
            mesh,
            attributes,
            index,
            fan_start,
            fan_faces,
            seam,
        }
    }

    /// Triangle `face` in frame coordinates (f64).
    fn triangle(&self, frame: &Frame, face: u32) -> [DVec3; 3] {
        self.mesh.triangles[face as usize].map(|v| frame.to_frame(self.mesh.positions[v as usize]))
    }
}

/// One direction: `samples` face samples of `source`, compared with `target`.
pub(super) fn one_direction(
    source: &TriMesh,
    source_attributes: &Attributes,
    target: &Target,
    which: Which,
    params: &AttributeParams,
    samples: usize,
    seed: u64,
) -> Result<AttributeErrors, MetricsError> {
    let frame = *target.index.frame();
    let drawn = draw(source, &frame, &params.hausdorff(samples), samples, seed)?;
    let drawn = drawn.samples();
    let threshold = params.uv_threshold;
    let partials: Vec<(usize, [Acc; 4])> = drawn
        .par_chunks(CHUNK)
        .map(|batch| {
            let mut acc = [Acc::default(); 4];
            let mut stack = Vec::with_capacity(64);
            let mut hint = NO_SLOT;
            for s in batch {
                let [a, b, c] = source.triangles[s.face as usize]
                    .map(|v| frame.to_frame(source.positions[v as usize]));
                let p = s.position.as_dvec3();
                let mine = interpolate(which, source_attributes, s.face, barycentric(p, a, b, c));
                let slot = target.index.nearest_or_scan(p, hint, &mut stack);
                hint = slot;
                let face = target.index.exact(p, slot).face;
                // Distance and values on the index's triangle, from the same f64 corners the
                // seam's other candidates are measured with.
                let at = |f: u32| {
                    let [x, y, z] = target.triangle(&frame, f);
                    let q = closest_point_triangle(p, x, y, z);
                    (q.distance(p), barycentric(q, x, y, z))
                };
                let (d, w) = at(face);
                let theirs = interpolate(which, target.attributes, face, w);
                let mut best = deviations(&mine, &theirs);
                let corners = target.mesh.triangles[face as usize];
                for v in corners {
                    if !target.seam[v as usize] {
                        continue;
                    }
                    let v = v as usize;
                    let fan = &target.fan_faces
                        [target.fan_start[v] as usize..target.fan_start[v + 1] as usize];
                    for &g in fan {
                        if g == face {
                            continue;
                        }
                        let (dg, wg) = at(g);
                        if dg > d + TIE {
                            continue;
                        }
                        let other = interpolate(which, target.attributes, g, wg);
                        for (x, y) in best.iter_mut().zip(deviations(&mine, &other)) {
                            *x = x.min(y);
                        }
                    }
                }
                acc[0].add(best[0], f64::INFINITY);
                acc[1].add(best[1], threshold);
                acc[2].add(best[2], threshold);
                acc[3].add(best[3], f64::INFINITY);
            }
            (batch.len(), acc)
        })
        .collect();
    let (n, acc) = partials
        .into_iter()
        .fold((0usize, [Acc::default(); 4]), |(n, a), (m, b)| {
            (
                n + m,
                [
                    a[0].merge(b[0]),
                    a[1].merge(b[1]),
                    a[2].merge(b[2]),
                    a[3].merge(b[3]),
                ],
            )
        });
    let texture = f64::from(params.texture_size);
    let uv = |acc: &Acc| {
        let uv = acc.stats(n);
        UvDeviation {
            uv,
            texels: DistanceStats {
                max: uv.max * texture,
                mean: uv.mean * texture,
                rms: uv.rms * texture,
            },
            over_threshold: acc.over as f64 / n.max(1) as f64,
        }
    };
    Ok(AttributeErrors {
        samples: n,
        normals: which.normals.then(|| {
            let s = acc[0].stats(n);
            AngleDeviation {
                mean_degrees: s.mean,
                max_degrees: s.max,
            }
        }),
        uv0: which.uv0.then(|| uv(&acc[1])),
        uv1: which.uv1.then(|| uv(&acc[2])),
        colors: which.colors.then(|| acc[3].stats(n)),
    })
}
