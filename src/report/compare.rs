//! `gng3d compare`'s table: QEM and GNG3D side by side with the better one per measure.

use super::eng;
use super::table::Table;
use crate::experiment::compare::CompareReport;

/// Which side a lower-is-better value favours: "QEM", "GNG3D" or "tie" (equal within 1e-9
/// relative).
pub fn winner(qem: f64, gng: f64) -> &'static str {
    let scale = qem.abs().max(gng.abs());
    if (qem - gng).abs() <= 1e-9 * scale {
        "tie"
    } else if qem < gng {
        "QEM"
    } else {
        "GNG3D"
    }
}

/// The comparison as a table of metric rows with QEM, GNG3D and the winner. The surface
/// distance means are given both ways: "mean" is MeshLab's mean over all samples (vertices,
/// edges and faces), "area-weighted mean" the headline `(1/A)∫d dA` over face samples.
pub fn comparison_table(report: &CompareReport) -> Table {
    let mut t = Table::new(["measure", "QEM", "GNG3D", "better"]);
    let (q, g) = (&report.qem, &report.gng);
    let (qm, gm) = (&q.metrics, &g.metrics);
    let mut num = |name: &str, a: f64, b: f64, lower_better: Option<bool>| {
        let w = match lower_better {
            Some(true) => winner(a, b),
            Some(false) => winner(-a, -b),
            None => "",
        };
        t.push([name.to_string(), eng(a), eng(b), w.to_string()]);
    };
    let lower = Some(true);
    num("E_avg (units²)", qm.e_avg, gm.e_avg, lower);
    num("E_max (units²)", qm.e_max, gm.e_max, lower);
    num("|E_sur| (units²)", qm.e_sur_abs, gm.e_sur_abs, lower);
    num(
        "E_sur signed (units²)",
        qm.e_sur_signed,
        gm.e_sur_signed,
        None,
    );
    num(
        "Hausdorff max (units)",
        qm.hausdorff.max,
        gm.hausdorff.max,
        lower,
    );
    let area_mean = |h: &metrics::Hausdorff| 0.5 * (h.forward.area_mean + h.backward.area_mean);
    num(
        "area-weighted mean distance (units)",
        area_mean(&qm.hausdorff),
        area_mean(&gm.hausdorff),
        lower,
    );
    num(
        "mean distance, all samples (units)",
        qm.hausdorff.mean,
        gm.hausdorff.mean,
        lower,
    );
    num(
        "RMS distance (units)",
        qm.hausdorff.rms,
        gm.hausdorff.rms,
        lower,
    );
    num(
        "Hausdorff max / diagonal",
        qm.hausdorff.relative.max,
        gm.hausdorff.relative.max,
        lower,
    );
    let (qq, gq) = (&qm.quality.simplified, &gm.quality.simplified);
    let mut fixed = |name: &str, a: f64, b: f64, lower_better: bool, unit: &str, scale: f64| {
        let w = if lower_better {
            winner(a, b)
        } else {
            winner(-a, -b)
        };
        t.push([
            name.to_string(),
            format!("{:.2}{unit}", a * scale),
            format!("{:.2}{unit}", b * scale),
            w.to_string(),
        ]);
    };
    fixed(
        "normal deviation, mean",
        qm.normal_deviation.forward.mean_degrees,
        gm.normal_deviation.forward.mean_degrees,
        true,
        "°",
        1.0,
    );
    fixed(
        "median min angle",
        qq.median_min_angle_degrees,
        gq.median_min_angle_degrees,
        false,
        "°",
        1.0,
    );
    fixed(
        "triangles with min angle < 20°",
        qq.below_20_degrees,
        gq.below_20_degrees,
        true,
        "%",
        100.0,
    );
    attribute_rows(&mut t, qm.attributes.as_ref(), gm.attributes.as_ref());
    image_rows(&mut t, qm.image_error.as_ref(), gm.image_error.as_ref());
    let mut int =
        |name: &str, a: String, b: String| t.push([name.to_string(), a, b, String::new()]);
    int("vertices", q.vertices.to_string(), g.vertices.to_string());
    int("faces", q.faces.to_string(), g.faces.to_string());
    int(
        "time",
        format!("{:.3} s", q.seconds),
        format!("{:.3} s", g.seconds),
    );
    let (qt, gt) = (&qm.topology.simplified, &gm.topology.simplified);
    int(
        "boundary edges",
        qt.boundary_edges.to_string(),
        gt.boundary_edges.to_string(),
    );
    int(
        "non-manifold edges",
        qt.non_manifold_edges.to_string(),
        gt.non_manifold_edges.to_string(),
    );
    int(
        "non-manifold vertices",
        qt.non_manifold_vertices.to_string(),
        gt.non_manifold_vertices.to_string(),
    );
    let yes_no = |b: bool| if b { "yes" } else { "no" }.to_string();
    int("closed", yes_no(qt.closed), yes_no(gt.closed));
    int("manifold", yes_no(qt.manifold), yes_no(gt.manifold));
    let genus = |g: Option<i64>| g.map_or("-".to_string(), |g| g.to_string());
    int("genus", genus(qt.genus), genus(gt.genus));
    int(
        "smallest angle",
        format!("{:.2}°", qq.min_angle_degrees),
        format!("{:.2}°", gq.min_angle_degrees),
    );
    t
}

/// The attribute-deviation rows (samples on each simplified mesh against the original), when
/// the input had attributes: per attribute of the original, the method's figure, or "dropped"
/// where its output does not have the attribute.
fn attribute_rows(
    t: &mut Table,
    qem: Option<&metrics::AttributeDeviation>,
    gng: Option<&metrics::AttributeDeviation>,
) {
    let (Some(q), Some(g)) = (qem, gng) else {
        return;
    };
    type Pick = fn(&metrics::AttributeDeviation) -> Option<f64>;
    let uv_mean: Pick = |a| a.backward.uv0.map(|u| u.texels.mean);
    let uv_max: Pick = |a| a.backward.uv0.map(|u| u.texels.max);
    let uv_over: Pick = |a| a.backward.uv0.map(|u| 100.0 * u.over_threshold);
    let normal_mean: Pick = |a| a.backward.normals.map(|n| n.mean_degrees);
    let color_mean: Pick = |a| a.backward.colors.map(|c| c.mean);
    let size = q.texture_size;
    let threshold = q.uv_threshold;
    let rows: [(String, &str, Pick, String); 5] = [
        (
            format!("UV deviation, mean (texels of {size}²)"),
            "uv0",
            uv_mean,
            String::new(),
        ),
        (
            format!("UV deviation, max (texels of {size}²)"),
            "uv0",
            uv_max,
            String::new(),
        ),
        (
            format!("UV samples off by > {threshold}"),
            "uv0",
            uv_over,
            "%".into(),
        ),
        (
            "attribute normal deviation, mean".into(),
            "normals",
            normal_mean,
            "°".into(),
        ),
        (
            "colour deviation, mean (RGB)".into(),
            "colors",
            color_mean,
            String::new(),
        ),
    ];
    let had = |a: &metrics::AttributeDeviation, name: &str| {
        a.compared.iter().chain(&a.missing).any(|n| n == name)
    };
    for (label, name, pick, unit) in rows {
        if !had(q, name) && !had(g, name) {
            continue;
        }
        let cell = |a: &metrics::AttributeDeviation| match pick(a) {
            Some(v) => format!("{v:.2}{unit}"),
            None => "dropped".to_string(),
        };
        let better = match (pick(q), pick(g)) {
            (Some(a), Some(b)) => winner(a, b),
            (Some(_), None) => "QEM",
            (None, Some(_)) => "GNG3D",
            (None, None) => "",
        };
        t.push([label, cell(q), cell(g), better.to_string()]);
    }
}

/// The image-space error rows (each output rendered against the original from the same
/// views), when both were measured: RMSE, PSNR, the share of pixels off by more than the
/// threshold and the share of silhouette mismatch, over all views.
fn image_rows(t: &mut Table, qem: Option<&metrics::ImageError>, gng: Option<&metrics::ImageError>) {
    let (Some(q), Some(g)) = (qem, gng) else {
        return;
    };
    let (qo, go) = (&q.overall, &g.overall);
    t.push([
        "image RMSE (RGB 0-1)".to_string(),
        format!("{:.4}", qo.rmse),
        format!("{:.4}", go.rmse),
        winner(qo.rmse, go.rmse).to_string(),
    ]);
    // Higher is better; identical images have an infinite PSNR.
    let psnr = |db: f64| {
        if db.is_finite() {
            format!("{db:.1} dB")
        } else {
            "∞".to_string()
        }
    };
    let better = match (qo.psnr_db.is_finite(), go.psnr_db.is_finite()) {
        (true, true) => winner(-qo.psnr_db, -go.psnr_db),
        (false, false) => "tie",
        (false, true) => "QEM",
        (true, false) => "GNG3D",
    };
    t.push([
        "image PSNR".to_string(),
        psnr(qo.psnr_db),
        psnr(go.psnr_db),
        better.to_string(),
    ]);
    for (label, a, b) in [
        (
            format!("image pixels off by > {}", q.threshold),
            qo.over_threshold,
            go.over_threshold,
        ),
        (
            "image silhouette mismatch".to_string(),
            qo.coverage_mismatch,
            go.coverage_mismatch,
        ),
    ] {
        t.push([
            label,
            format!("{:.2}%", 100.0 * a),
            format!("{:.2}%", 100.0 * b),
            winner(a, b).to_string(),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::winner;

    #[test]
    fn winner_is_the_lower_value_with_a_relative_tie() {
        assert_eq!(winner(1.0, 2.0), "QEM");
        assert_eq!(winner(2.0, 1.0), "GNG3D");
        assert_eq!(winner(1.0, 1.0 + 1e-12), "tie");
        assert_eq!(winner(0.0, 0.0), "tie");
    }
}
