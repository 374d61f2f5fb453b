//! The checks of a run's input: the parameters ([`validate`], [`check_pair_threshold`]), the lock
//! mask ([`check_lock_mask`]) and the cancel flag ([`check_cancel`]).

use crate::{QemError, QemParams, Target};
use mesh::TriMesh;

/// [`QemError::Cancelled`] when the run's [`QemParams::cancel`] flag is set.
pub(super) fn check_cancel(params: &QemParams) -> Result<(), QemError> {
    match &params.cancel {
        Some(c) if c.is_cancelled() => Err(QemError::Cancelled),
        _ => Ok(()),
    }
}

/// A lock mask has one flag per input vertex.
pub(super) fn check_lock_mask(input: &TriMesh, locked: Option<&[bool]>) -> Result<(), QemError> {
    match locked {
        Some(l) if l.len() != input.positions.len() => Err(QemError::InvalidParameter(format!(
            "the lock mask has {} flags for {} vertices",
            l.len(),
            input.positions.len()
        ))),
        _ => Ok(()),
    }
}

/// The largest pair threshold, in units of the bounding-box diagonal of the referenced vertices
/// (the normalised frame's unit): beyond it every vertex is within `t` of every other, so larger
/// values (a typo such as `1e30`) mean nothing more and are refused.
const MAX_PAIR_THRESHOLD: f64 = 1.0;
/// The largest `max_pairs_per_vertex`: the pair search and the pairs' memory grow with it.
const MAX_PAIRS_PER_VERTEX: usize = 64;

/// Refuse a pair threshold above [`MAX_PAIR_THRESHOLD`] diagonals of a mesh whose frame has
/// `scale` (1 / diagonal), naming the limit in model units (rounded down, so that the value shown
/// is accepted).
pub(super) fn check_pair_threshold(t: f64, scale: f64) -> Result<(), QemError> {
    if t * scale <= MAX_PAIR_THRESHOLD {
        return Ok(());
    }
    let limit = MAX_PAIR_THRESHOLD / scale;
    // Six significant digits, rounded down.
    let digits = 5 - limit.log10().floor() as i32;
    let shown = if (0..=15).contains(&digits) {
        let unit = 10f64.powi(digits);
        format!("{:.*}", digits as usize, (limit * unit).floor() / unit)
    } else {
        format!("{limit:e}")
    };
    let t = if t >= 1e6 {
        format!("{t:e}")
    } else {
        t.to_string()
    };
    Err(QemError::InvalidParameter(format!(
        "pair threshold {t} is above the limit {shown}, the bounding-box diagonal of the mesh \
         (beyond it every vertex is paired with every other)"
    )))
}

pub(crate) fn validate(p: &QemParams) -> Result<(), QemError> {
    let bad = |s: String| Err(QemError::InvalidParameter(s));
    if let Target::Ratio(r) = p.target
        && !(r > 0.0 && r <= 1.0)
    {
        return bad(format!("target ratio {r} is not in (0, 1]"));
    }
    if !(p.pair_threshold >= 0.0 && p.pair_threshold.is_finite()) {
        return bad(format!(
            "pair threshold {} must be finite and >= 0",
            p.pair_threshold
        ));
    }
    if p.max_pairs_per_vertex > MAX_PAIRS_PER_VERTEX {
        return bad(format!(
            "max pairs per vertex {} is above the limit {MAX_PAIRS_PER_VERTEX}",
            p.max_pairs_per_vertex
        ));
    }
    if !(p.boundary_weight >= 0.0 && p.boundary_weight.is_finite()) {
        return bad(format!(
            "boundary weight {} must be finite and >= 0",
            p.boundary_weight
        ));
    }
    if !(p.seam_weight >= 0.0 && p.seam_weight.is_finite()) {
        return bad(format!(
            "seam weight {} must be finite and >= 0",
            p.seam_weight
        ));
    }
    if let Some(m) = p.max_error
        && m.is_nan()
    {
        return bad("max error is NaN".into());
    }
    if let Some(m) = p.max_relative_error
        && !(m >= 0.0 && m.is_finite())
    {
        return bad(format!(
            "max relative error {m} must be a finite share of the bounding-box diagonal >= 0"
        ));
    }
    let w = p.attribute_weights;
    for (name, v) in [("uv", w.uv), ("normal", w.normal), ("color", w.color)] {
        if !(v >= 0.0 && v.is_finite()) {
            return bad(format!(
                "attribute weight {name}={v} must be finite and >= 0"
            ));
        }
    }
    if !(p.edge_length_weight >= 0.0 && p.edge_length_weight.is_finite()) {
        return bad(format!(
            "edge length weight {} must be finite and >= 0",
            p.edge_length_weight
        ));
    }
    if !(-1.0..=1.0).contains(&p.min_normal_cos) {
        return bad(format!(
            "min_normal_cos {} is not in [-1, 1]",
            p.min_normal_cos
        ));
    }
    Ok(())
}
