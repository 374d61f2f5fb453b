//! GNG3D-Q's decimation ([`crate::Step::Decimate`]): the oversampled network's mesh
//! goes down to the output count with Garland–Heckbert QEM (the `qem` crate) plus a small
//! edge-length term. Quadrics come from the network's mesh, which after quadric placement and
//! the refit lies on the original surface.

use mesh::TriMesh;
use mesh::cancel::Cancel;

/// [`qem::QemParams::edge_length_weight`] of GNG3D-Q's decimation. Without it QEM removes the
/// network's vertices in flat regions in arbitrary order (their quadric cost is ≈ 0) and leaves
/// gaps wider than its own: E_max lost to QEM in 12 of the survey's 45 runs. Swept on bunny,
/// gargoyle-10k, spot and rocker-arm at 10 % (ratio of E_max to QEM's / of the mean surface
/// distance): 1e-4 bunny 1.34 / 0.91, gargoyle 1.01 / 0.98; 1e-3 0.96 / 0.91, 1.12 / 0.99;
/// **3e-3** 0.84 / 0.92, 0.76 / 0.99 (and 50 %: mean distance 0-5 % higher than without, E_max
/// 0.38-0.71); 1e-2 0.74 / 0.95, 0.60 / 1.00 (50 %: mean 7-9 % higher); 1e-1 mean 4-14 % higher.
/// It also makes the triangles rounder (bunny 10 %: 4.8 → 3.4 % under 20°). docs/notes/gngq.md.
pub const EDGE_LENGTH_WEIGHT: f64 = 3e-3;

/// The normal checks ([`qem::QemParams::min_normal_cos`], default 0.2), in turn, of the
/// contractions that [`decimate`] still needs after QEM stopped above its target: a face may
/// turn by up to 90°, then up to 120° (short of a fold), for those few. Measured on casting at
/// 1 % (282 → 51 vertices): the default stops at 52, 0 reaches 51. A sweep of `simplify
/// --method gng` over 13 shared meshes at 1-95 %, two seeds (234 runs), stopped early only
/// there and where holes or a tiny target block (many_small_holes at 1 %, the 502-vertex knight
/// at 1 %, i.e. 5 vertices).
pub const RELAXED_NORMAL_COS: [f64; 2] = [0.0, -0.5];

/// Garland–Heckbert QEM with its defaults (edges only, topology kept) plus
/// [`EDGE_LENGTH_WEIGHT`], down to `target_vertices` vertices.
///
/// When QEM stops above the target because its normal check rejects every remaining
/// contraction (coarse meshes of high genus: casting at 1 %, genus 9, stopped at 52 of 51
/// vertices), the remainder is contracted with that check relaxed in the steps of
/// [`RELAXED_NORMAL_COS`], so that the count is met; the link condition (manifoldness, genus)
/// is never relaxed. What still cannot be contracted (holes need three vertices each) is left
/// to the caller's warning. With `cancel` set, QEM stops with [`qem::QemError::Cancelled`].
pub(crate) fn decimate(
    mesh: &TriMesh,
    target_vertices: usize,
    cancel: Option<&Cancel>,
) -> Result<TriMesh, qem::QemError> {
    let params = qem::QemParams {
        edge_length_weight: EDGE_LENGTH_WEIGHT,
        cancel: cancel.cloned(),
        ..qem::QemParams::with_target(qem::Target::Vertices(target_vertices))
    };
    let simplify = |model: &mesh::Model, params: &qem::QemParams| {
        qem::simplify(model, params).map(|(model, _)| model)
    };
    let first = simplify(&mesh::Model::from(mesh.clone()), &params)?;
    relaxing(first, &params, target_vertices, |m| &m.mesh, simplify).map(|m| m.mesh)
}

/// `out` (QEM's run with `params`), contracted again with the normal check relaxed in the steps
/// of [`RELAXED_NORMAL_COS`] (by `again`, on the last result) while its mesh (`mesh_of`) has
/// more than `target_vertices` vertices: the one relaxation of [`decimate`] and
/// [`decimate_along_seams`].
fn relaxing<T>(
    mut out: T,
    params: &qem::QemParams,
    target_vertices: usize,
    mesh_of: impl Fn(&T) -> &TriMesh,
    mut again: impl FnMut(&T, &qem::QemParams) -> Result<T, qem::QemError>,
) -> Result<T, qem::QemError> {
    for min_normal_cos in RELAXED_NORMAL_COS {
        if mesh_of(&out).vertex_count() <= target_vertices {
            break;
        }
        let relaxed = qem::QemParams {
            min_normal_cos,
            ..params.clone()
        };
        out = again(&out, &relaxed)?;
    }
    Ok(out)
}

/// Weight of the seams' and the borders' constraint planes in [`decimate_along_seams`]
/// ([`qem::QemParams::seam_weight`] and [`qem::QemParams::boundary_weight`]; QEM's defaults are
/// 15 and 1000). Swept on spot at 5, 10 and 20 % and the fandisk atlas at 10 %
/// (docs/notes/attributes.md): from 1000 down to 30 the mean surface distance falls by 2-8 %
/// with the share of the area more than 0.05 UV off about the same (2.5 → 2.3 %, 0.67 → 0.68 %,
/// 0.39 → 0.40 %, 0.21 → 0.21 %); 10 lowers the distance by up to 3 % more and raises the share
/// off by up to 10 %. Seams whose planes weigh less are contracted more, so fewer of the
/// output's vertices are spent on them. QEM's default went to 15 for its Hausdorff distance on
/// spot at 5 %; here the network's vertices already hold the surface, and the share off (about
/// 5 × QEM's) is what a lower weight would raise.
pub const SEAM_WEIGHT: f64 = 30.0;

/// [`decimate`] of a mesh cut along the original's seams ([`crate::finish::seams::cut`];
/// `charts`: each triangle's chart): QEM's attribute path (`qem::simplify` of a model with
/// attributes) with the charts as materials, so every chart border is a seam that QEM keeps
/// (contracted only along itself, seam ends and crossings kept, constraint planes along it) and
/// every output triangle stays in one chart. Same parameters and relaxed normal checks as
/// [`decimate`] (the seams' planes weighted by [`SEAM_WEIGHT`]); when the seams' fixed vertices
/// leave more than `target_vertices` (tiny targets on a many-chart atlas), plain
/// [`decimate`] takes the rest, so the count is met. Returns the mesh and each triangle's chart
/// (`None` after that fallback).
pub(crate) fn decimate_along_seams(
    mesh: &TriMesh,
    charts: &[u32],
    target_vertices: usize,
    cancel: Option<&Cancel>,
) -> Result<(TriMesh, Option<Vec<u32>>), qem::QemError> {
    let attributes = mesh::attributes::Attributes {
        wedge_vertex: (0..mesh.positions.len() as u32).collect(),
        corners: mesh.triangles.clone(),
        face_material: Some(charts.to_vec()),
        ..mesh::attributes::Attributes::default()
    };
    let params = qem::QemParams {
        edge_length_weight: EDGE_LENGTH_WEIGHT,
        boundary_weight: SEAM_WEIGHT,
        seam_weight: SEAM_WEIGHT,
        cancel: cancel.cloned(),
        ..qem::QemParams::with_target(qem::Target::Vertices(target_vertices))
    };
    let input = mesh::Model {
        attributes: Some(attributes),
        ..mesh::Model::from(mesh.clone())
    };
    let simplify = |model: &mesh::Model, params: &qem::QemParams| {
        qem::simplify(model, params).map(|(model, _)| model)
    };
    let first = simplify(&input, &params)?;
    let out = relaxing(first, &params, target_vertices, |m| &m.mesh, simplify)?;
    if out.mesh.vertex_count() > target_vertices {
        return Ok((decimate(&out.mesh, target_vertices, cancel)?, None));
    }
    Ok((out.mesh, out.attributes.and_then(|a| a.face_material)))
}
