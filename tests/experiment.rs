//! Cross-crate tests of the paper's experiment: `compare`, `reproduce` and their reports.

use gng3d::experiment::compare::{CompareParams, compare};
use gng3d::experiment::reproduce::{ReproduceParams, ReproduceReport, reproduce};
use gng3d::mesh::procedural;
use gng3d::metrics::HausdorffParams;
use gng3d::report::compare::comparison_table;
use gng3d::report::paper::{checkpoint_table, write_reproduction};

fn small_params(epochs: u64) -> ReproduceParams {
    ReproduceParams {
        epochs,
        target_ratio: 0.5,
        hausdorff: HausdorffParams::with_samples(20_000),
        ..Default::default()
    }
}

#[test]
fn reproduce_table_has_paper_columns_and_falling_error() {
    let sphere = procedural::icosphere(4); // 2,562 vertices
    let start = std::time::Instant::now();
    let report = reproduce(&sphere, &small_params(8), |_| {}).unwrap();
    assert!(start.elapsed().as_secs_f64() < 60.0);
    assert_eq!(report.original_vertices, 2562);
    assert_eq!(report.target_vertices, 1281);
    assert!(report.checkpoints.len() >= 8, "one checkpoint per epoch");
    // Iterations increase strictly, one epoch of |V| signals apart.
    for w in report.checkpoints.windows(2) {
        assert_eq!(w[1].iteration - w[0].iteration, report.signals_per_epoch);
    }
    let first = report.checkpoints.first().unwrap();
    let last = report.checkpoints.last().unwrap();
    assert!(
        last.gng.e_avg < first.gng.e_avg,
        "E_avg should fall: {} -> {}",
        first.gng.e_avg,
        last.gng.e_avg
    );
    // QEM at equal count really has the GNG3D mesh's vertex count (± 1 for the last collapse).
    for c in &report.checkpoints {
        assert!(c.qem_equal.vertices.abs_diff(c.gng.vertices) <= 1, "{c:?}");
        assert!(c.gng.vertices <= c.nodes);
    }
    // E_sur is the plain area difference: check it independently for QEM at the target.
    assert!(report.qem_fixed.e_sur_signed.abs() < 0.05 * report.original_area);

    let table = checkpoint_table(&report);
    assert_eq!(
        &table.headers[..6],
        &["iteration", "vertices", "faces", "E_avg", "E_max", "E_sur"]
    );
    assert_eq!(table.rows.len(), report.checkpoints.len());
}

#[test]
fn reproduce_files_parse_back() {
    let torus = procedural::torus(1.0, 0.35, 40, 20);
    let report = reproduce(&torus, &small_params(4), |_| {}).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let written = write_reproduction(&report, "torus", dir.path()).unwrap();
    for name in [
        "table.csv",
        "table.md",
        "report.json",
        "figure1_esur.svg",
        "figure1_esur.png",
        "e_avg.png",
        "e_max.svg",
        "hausdorff.png",
    ] {
        let p = dir.path().join(name);
        assert!(written.contains(&p), "{name} not reported");
        assert!(std::fs::metadata(&p).unwrap().len() > 100, "{name} empty");
    }
    let back: ReproduceReport =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).unwrap())
            .unwrap();
    assert_eq!(back, report);
    let mut csv = csv::Reader::from_path(dir.path().join("table.csv")).unwrap();
    assert_eq!(csv.records().count(), report.checkpoints.len());
}

#[test]
fn compare_hits_target_and_reports_both_methods() {
    let blob = procedural::blob();
    let n = blob.vertex_count() / 4;
    let mut params = CompareParams::new(n);
    params.metrics.hausdorff = HausdorffParams::with_samples(30_000);
    let result = compare(&blob, &params).unwrap();
    let r = &result.report;
    assert!(
        r.qem.vertices.abs_diff(n) <= 1,
        "QEM {} vs {n}",
        r.qem.vertices
    );
    assert!(
        r.gng.vertices <= n && r.gng.vertices * 10 >= n * 9,
        "GNG {}",
        r.gng.vertices
    );
    assert_eq!(result.qem_mesh.vertex_count(), r.qem.vertices);
    assert_eq!(result.gng_mesh.face_count(), r.gng.faces);
    // Independent check of E_sur for both methods.
    let area = blob.area();
    assert!((r.qem.metrics.e_sur_signed - (area - result.qem_mesh.area())).abs() < 1e-9 * area);
    assert!((r.gng.metrics.e_sur_signed - (area - result.gng_mesh.area())).abs() < 1e-9 * area);
    let json = serde_json::to_string(r).unwrap();
    let back: gng3d::experiment::compare::CompareReport = serde_json::from_str(&json).unwrap();
    assert_eq!(&back, r);
    let text = comparison_table(r).to_text();
    assert!(text.contains("E_avg") && text.contains("Hausdorff max"));
    // Issue 11 item 6: triangle quality next to the distances, checked against metrics.
    assert!(
        text.contains("median min angle") && text.contains("min angle < 20°"),
        "{text}"
    );
    let q = gng3d::metrics::triangle_quality(&result.gng_mesh);
    assert_eq!(
        r.gng.metrics.quality.simplified.median_min_angle_degrees,
        q.median_min_angle_degrees
    );
    assert!(
        text.contains(&format!("{:.2}°", q.median_min_angle_degrees)),
        "{text}"
    );
}

#[test]
fn compare_errors_are_said_once() {
    // An option error from the job's one check, not a panic and not a doubled message.
    let sphere = procedural::icosphere(2);
    let mut params = CompareParams::new(40);
    params.request.time_limit = Some(0.0);
    let e = compare(&sphere, &params).unwrap_err();
    let chain = anyhow_like(&e);
    assert_eq!(chain.matches("time limit").count(), 1, "{chain}");
}

/// The error and its sources joined by ": " (what `{:#}` of anyhow prints).
fn anyhow_like(e: &dyn std::error::Error) -> String {
    let mut out = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        out.push_str(": ");
        out.push_str(&s.to_string());
        source = s.source();
    }
    out
}

#[test]
fn compare_rejects_impossible_targets() {
    let sphere = procedural::icosphere(2);
    assert!(compare(&sphere, &CompareParams::new(2)).is_err());
    assert!(compare(&sphere, &CompareParams::new(sphere.vertex_count() + 1)).is_err());
}

/// A shared mesh, prepared (welded, cleaned) as every front end does; `None` (skip) without
/// `GNG3D_MESHES`, a failure when `CI` is set.
fn shared(name: &str) -> Option<gng3d::mesh::TriMesh> {
    let path = mesh::fixtures::shared_meshes_dir("README.md")?.join(name);
    let raw = gng3d::mesh::io::load(&path)
        .unwrap_or_else(|e| panic!("{e}"))
        .mesh;
    Some(gng3d::mesh::clean::prepare(&raw.into()).0.mesh)
}

#[test]
fn gngq_at_half_the_vertices_keeps_its_triangle_and_e_avg_wins() {
    // Issue 11's "≥ 90 % of runs" rule at the ratio where GNG3D-Q used to lose it: at 50 % the
    // budget capped at 30 epochs left 60 signals per node (cow: median smallest angle 30.3° vs
    // QEM's 31.6°, 28 % of triangles under 20° vs 17 %, E_avg 1.6× QEM's). Measured now (survey):
    // cow 36.0° / 8.8 %, spot 40.4° / 2.6 %, E_avg 0.8× and 0.7× QEM's.
    for name in ["cow.obj", "spot.obj"] {
        let Some(m) = shared(name) else {
            return;
        };
        let n = (m.vertex_count() as f64 * 0.5).round() as usize;
        let mut params = CompareParams::new(n);
        params.metrics.hausdorff = HausdorffParams::with_samples(20_000);
        let r = compare(&m, &params).unwrap().report;
        assert_eq!(r.gng.vertices, n, "{name}: exact vertex count");
        let (g, q) = (&r.gng.metrics, &r.qem.metrics);
        let (gq, qq) = (&g.quality.simplified, &q.quality.simplified);
        assert!(
            gq.median_min_angle_degrees > qq.median_min_angle_degrees + 1.0,
            "{name}: median min angle {} vs QEM {}",
            gq.median_min_angle_degrees,
            qq.median_min_angle_degrees
        );
        assert!(
            gq.below_20_degrees < 0.75 * qq.below_20_degrees,
            "{name}: under 20° {} vs QEM {}",
            gq.below_20_degrees,
            qq.below_20_degrees
        );
        assert!(
            g.e_avg < q.e_avg,
            "{name}: E_avg {} vs QEM {}",
            g.e_avg,
            q.e_avg
        );
    }
}

/// Symmetric mean surface distance between `original` and `simplified` (50k samples a
/// direction), as the GNG3D-Q with/without comparisons below measure it.
fn mean_distance(original: &gng3d::mesh::TriMesh, simplified: &gng3d::mesh::TriMesh) -> f64 {
    let hp = HausdorffParams::with_samples(50_000);
    gng3d::metrics::hausdorff(original, simplified, &hp)
        .unwrap()
        .mean
}

/// Share of `mesh`'s triangles whose smallest angle is under 20°.
fn share_under_20(mesh: &gng3d::mesh::TriMesh) -> f64 {
    gng3d::metrics::triangle_quality(mesh).below_20_degrees
}

#[test]
fn surface_refit_lowers_the_distance_without_adding_slivers() {
    // GNG3D-Q's last step (gng3d_core::refit) moves vertices so the triangles fit the original.
    // The same trained network reconstructed with and without it: the symmetric mean surface
    // distance must fall clearly (measured: cow 10 % −19 %, spot 10 % −23 %) and, thanks to the
    // refit's shape rule, the share of triangles under 20° must not grow (measured: cow 9.9 →
    // 7.3 %, spot 6.2 → 3.8 %; without the rule cow went to 13.9 %).
    use gng3d::gng3d_core::{GngParams, ReconstructionParams, Trainer};
    for name in ["cow.obj", "spot.obj"] {
        let Some(m) = shared(name) else {
            return;
        };
        let n = (m.vertex_count() as f64 * 0.1).round() as usize;
        let mut trainer = Trainer::new(&m.clone().into(), GngParams::for_target(n)).unwrap();
        while !trainer.is_finished() {
            trainer.step(u64::MAX);
        }
        let with = trainer.reconstruct(&ReconstructionParams::default());
        let without = trainer.reconstruct(&ReconstructionParams {
            refit: false,
            ..ReconstructionParams::default()
        });
        assert!(with.report.refit_moves > 0 && without.report.refit_moves == 0);
        assert_eq!(
            with.mesh.triangles, without.mesh.triangles,
            "{name}: same faces"
        );
        let (dw, dn) = (
            mean_distance(&m, &with.mesh),
            mean_distance(&m, &without.mesh),
        );
        assert!(dw < 0.9 * dn, "{name}: mean distance {dn:.3e} -> {dw:.3e}");
        let (qw, qn) = (share_under_20(&with.mesh), share_under_20(&without.mesh));
        assert!(qw <= qn, "{name}: share under 20° {qn:.4} -> {qw:.4}");
    }
}

#[test]
fn relaxation_after_the_decimation_wins_e_avg_back_at_a_small_cost_in_distance() {
    // Option (h) (gng3d_core::relax): the decimated vertices move half-way toward the centroid
    // of the original vertices nearest to them. Survey runs where GNG3D-Q lost E_avg to QEM
    // without it: cow and armadillo at 10 % (1.034 / 1.023× QEM's); with it 0.995 / 0.978×.
    // Same trained network and decimation with and without the step (seeded), so the faces
    // are the same and only the positions differ.
    use gng3d::gng3d_core::tuning::DEFAULT_OVERSAMPLE;
    use gng3d::gng3d_core::{GngOptions, GngTarget};
    let Some(m) = shared("cow.obj") else {
        return;
    };
    let n = (m.vertex_count() as f64 * 0.1).round() as usize;
    let run = |relax: bool| {
        let mut options = GngOptions::for_target(GngTarget::Vertices(n));
        options.reconstruction.relax = relax;
        // The deviation repair after it would flip different edges in the two runs.
        options.reconstruction.repair_deviations = false;
        options.oversample = Some(DEFAULT_OVERSAMPLE);
        gng3d::gng3d_core::simplify(&m.clone().into(), &options).unwrap()
    };
    let (with, without) = (run(true), run(false));
    let (rw, rn) = (&with.report.reconstruction, &without.report.reconstruction);
    assert!(
        rw.relaxed_vertices > n / 2 && rn.relaxed_vertices == 0,
        "{rw:?}"
    );
    assert_eq!(with.mesh.triangles, without.mesh.triangles);
    assert_eq!(with.mesh.vertex_count(), n);
    let e_avg = |s: &gng3d::mesh::TriMesh| {
        gng3d::metrics::vertex_errors(&m.positions, &s.positions)
            .unwrap()
            .e_avg
    };
    let (ew, en) = (e_avg(&with.mesh), e_avg(&without.mesh));
    assert!(ew < 0.97 * en, "E_avg {en:.4e} -> {ew:.4e}");
    // Measured: mean distance +2 %, share of triangles under 20° not up.
    let (dw, dn) = (
        mean_distance(&m, &with.mesh),
        mean_distance(&m, &without.mesh),
    );
    assert!(dw < 1.06 * dn, "mean distance {dn:.4e} -> {dw:.4e}");
    let (qw, qn) = (share_under_20(&with.mesh), share_under_20(&without.mesh));
    eprintln!(
        "E_avg {en:.4e} -> {ew:.4e}, mean {dn:.4e} -> {dw:.4e}, under 20° {qn:.4} -> {qw:.4}"
    );
    assert!(qw <= qn + 0.005, "share under 20° {qn:.4} -> {qw:.4}");
}

#[test]
fn deviation_repair_lowers_the_output_to_original_maximum_at_no_cost_in_mean_distance() {
    // Option (i) (gng3d_core::deviation): after the decimation, vertices standing off the
    // original move back onto it and edges spanning a groove flip. On the gargoyle-10k at 25 %
    // the output's farthest point from the original was a vertex 4.9× farther than its
    // neighbours (5.5e-3, twice the original → output maximum). Measured with the repair
    // (200k samples): output → original max 5.53e-3 → 2.78e-3, mean distance +0.7 %. Same
    // trained network, reconstruction and decimation with and without it (seeded).
    use gng3d::gng3d_core::tuning::DEFAULT_OVERSAMPLE;
    use gng3d::gng3d_core::{GngOptions, GngTarget};
    let Some(m) = shared("gargoyle-10k.obj") else {
        return;
    };
    let n = (m.vertex_count() as f64 * 0.25).round() as usize;
    let run = |repair: bool| {
        let mut options = GngOptions::for_target(GngTarget::Vertices(n));
        options.reconstruction.repair_deviations = repair;
        options.oversample = Some(DEFAULT_OVERSAMPLE);
        gng3d::gng3d_core::simplify(&m.clone().into(), &options).unwrap()
    };
    let (with, without) = (run(true), run(false));
    let (rw, rn) = (&with.report.reconstruction, &without.report.reconstruction);
    assert!(
        rw.deviation_moves + rw.deviation_flips > 0 && rn.deviation_moves + rn.deviation_flips == 0,
        "{rw:?}"
    );
    assert_eq!(
        (with.mesh.vertex_count(), without.mesh.vertex_count()),
        (n, n)
    );
    let hp = HausdorffParams::with_samples(100_000);
    let h = |s: &gng3d::mesh::TriMesh| gng3d::metrics::hausdorff(&m, s, &hp).unwrap();
    let (hw, hn) = (h(&with.mesh), h(&without.mesh));
    eprintln!(
        "output -> original max {:.3e} -> {:.3e}, mean {:.4e} -> {:.4e}, {rw:?}",
        hn.backward.max, hw.backward.max, hn.mean, hw.mean
    );
    assert!(
        hw.backward.max < 0.75 * hn.backward.max,
        "output -> original max {:.3e} -> {:.3e}",
        hn.backward.max,
        hw.backward.max
    );
    assert!(
        hw.max < hn.max,
        "Hausdorff {:.3e} -> {:.3e}",
        hn.max,
        hw.max
    );
    assert!(
        hw.mean < 1.02 * hn.mean,
        "mean {:.4e} -> {:.4e}",
        hn.mean,
        hw.mean
    );
    let (qw, qn) = (share_under_20(&with.mesh), share_under_20(&without.mesh));
    assert!(qw <= qn + 0.005, "share under 20° {qn:.4} -> {qw:.4}");
}

#[test]
fn oversampled_gngq_is_closer_to_the_surface_at_exactly_the_target() {
    // GNG3D-Q's default: a network of 1.5 N nodes, reconstructed, then decimated to N by QEM
    // (gng3d_core::simplify). Against the same options without oversampling, on two meshes at
    // 10 %: exactly N vertices, closed and manifold where the input is, and the symmetric mean
    // surface distance clearly lower (measured, 50k samples: cow 10 % −19 %, spot 10 % −17 %).
    use gng3d::gng3d_core::tuning::DEFAULT_OVERSAMPLE;
    use gng3d::gng3d_core::{GngOptions, GngTarget};
    for name in ["cow.obj", "spot.obj"] {
        let Some(m) = shared(name) else {
            return;
        };
        let n = (m.vertex_count() as f64 * 0.1).round() as usize;
        let run = |oversample: f64| {
            let p = GngOptions {
                oversample: Some(oversample),
                ..GngOptions::for_target(GngTarget::Vertices(n))
            }
            .resolve(&m)
            .unwrap();
            run_params(&m, &p)
        };
        let (plain, over) = (run(1.0), run(DEFAULT_OVERSAMPLE));
        assert_eq!(plain.mesh.vertex_count(), n, "{name}");
        assert_eq!(over.mesh.vertex_count(), n, "{name}: exact vertex count");
        // The trained nodes, plus those the topology repair split off (option (f)) and the
        // detail rounds added (option (g)).
        let rec = &over.report.reconstruction;
        assert_eq!(
            over.report.network_vertices,
            (n as f64 * DEFAULT_OVERSAMPLE).ceil() as usize + rec.split_cells + rec.detail_nodes,
            "{name}: network size"
        );
        assert!(
            over.report.warnings.is_empty(),
            "{name}: {:?}",
            over.report.warnings
        );
        // Spot is closed and manifold, and so must its result be (the cow has a non-manifold
        // vertex; its thin parts are the next test's).
        let t = gng3d::mesh::topology::analyze(&over.mesh);
        let input = gng3d::mesh::topology::analyze(&m);
        if input.closed && input.manifold {
            assert!(t.closed && t.manifold, "{name}: {t:?}");
        }
        let (dp, dov) = (
            mean_distance(&m, &plain.mesh),
            mean_distance(&m, &over.mesh),
        );
        eprintln!(
            "{name}: mean distance {dp:.4e} -> {dov:.4e} ({:.3})",
            dov / dp
        );
        assert!(
            dov < 0.9 * dp,
            "{name}: mean distance {dp:.3e} -> {dov:.3e}"
        );
    }
}

#[test]
fn thin_parts_stay_attached_at_low_vertex_counts() {
    // Issue 11's "thin parts fall apart": the cow's legs and tail and the knight's thin parts
    // are tubes a few vertices round; a node on such a tube's axis wins a ring of it and the
    // mapping loses the tube (cow at 10 % came back in 8 pieces with 11 boundary edges). The
    // topology repair of oversampled runs (ReconstructionParams::split_bad_cells) splits those
    // cells. Measured (this test, without -> with the repair): cow 5 / 10 / 25 % 4 / 9 / 1
    // pieces -> 1 / 1 / 1; knight 10 % 5 -> 1.
    use gng3d::gng3d_core::tuning::DEFAULT_OVERSAMPLE;
    use gng3d::gng3d_core::{GngOptions, GngTarget};
    for (name, ratio) in [
        ("cow.obj", 0.05),
        ("cow.obj", 0.1),
        ("cow.obj", 0.25),
        ("decimated-knight.obj", 0.1),
    ] {
        let Some(m) = shared(name) else {
            return;
        };
        let input = gng3d::mesh::topology::analyze(&m);
        let n = (m.vertex_count() as f64 * ratio).round() as usize;
        let params = GngOptions {
            oversample: Some(DEFAULT_OVERSAMPLE),
            ..GngOptions::for_target(GngTarget::Vertices(n))
        }
        .resolve(&m)
        .unwrap();
        assert!(params.reconstruction.split_bad_cells, "on when oversampled");
        let repaired = run_params(&m, &params);
        let mut without = params.clone();
        without.reconstruction.split_bad_cells = false;
        let plain = run_params(&m, &without);
        let (t, tp) = (
            gng3d::mesh::topology::analyze(&repaired.mesh),
            gng3d::mesh::topology::analyze(&plain.mesh),
        );
        eprintln!(
            "{name} {ratio}: pieces {} -> {}, boundary edges {} -> {}, split {}",
            tp.components,
            t.components,
            tp.boundary_edges,
            t.boundary_edges,
            repaired.report.reconstruction.split_cells
        );
        assert_eq!(repaired.mesh.vertex_count(), n, "{name} {ratio}");
        assert_eq!(t.components, input.components, "{name} {ratio}: {t:?}");
        if input.closed {
            assert!(t.closed, "{name} {ratio}: {t:?}");
        }
        assert!(
            repaired.report.reconstruction.split_cells > 0,
            "{name} {ratio}"
        );
        // The check can fail: at 10 % and below, without the repair the same run comes back in
        // more pieces or with holes (measured: cow 5 % 4 pieces, 10 % 9 pieces and 39 boundary
        // edges). At 25 % the network is dense enough that the plain run is whole too (one
        // piece, no hole, with 150 signals per output vertex), so there only the result is
        // checked.
        if ratio <= 0.1 {
            assert!(
                tp.components > t.components || tp.boundary_edges > t.boundary_edges,
                "{name} {ratio}: {tp:?}"
            );
        }
    }
}

#[test]
fn compare_oversamples_gngq_and_not_the_papers_placement_set_afterwards() {
    // CompareParams::new leaves the oversampling to the placement (the job's variant), so a
    // caller who switches to the paper's placement after `new` gets the paper's method, not
    // 1.5 × N nodes decimated by QEM.
    let sphere = procedural::icosphere(3); // 642 vertices
    let mut params = CompareParams::new(120);
    params.metrics.hausdorff = HausdorffParams::with_samples(5_000);
    let q = compare(&sphere, &params).unwrap().report;
    assert!(
        q.gng_variant.contains("1.5x nodes decimated"),
        "{}",
        q.gng_variant
    );
    params.request.gng.placement = Some(gng3d::gng3d_core::Placement::Node);
    params.request.gng.flips = Some(false);
    let paper = compare(&sphere, &params).unwrap().report;
    assert!(
        !paper.gng_variant.contains("decimated"),
        "{}",
        paper.gng_variant
    );
    assert_eq!((q.gng.vertices, paper.gng.vertices), (120, 120));
}

/// A GNG3D run with these exact parameters: train, then `gng3d_core::finish`.
fn run_params(
    m: &gng3d::mesh::TriMesh,
    params: &gng3d::gng3d_core::GngParams,
) -> gng3d::gng3d_core::GngResult {
    let mut trainer = gng3d::gng3d_core::Trainer::new(&m.clone().into(), params.clone()).unwrap();
    while !trainer.is_finished() {
        trainer.step(u64::MAX);
    }
    gng3d::gng3d_core::finish(&trainer, |_| {}).unwrap()
}

#[test]
fn a_closed_input_never_returns_an_open_mesh_without_a_warning() {
    // The paper's reconstruction opens holes at low ratios (armadillo at 2 %: 6 of 8 seeds,
    // docs/notes/gng.md); GNG3D-Q's cell splits close most. Whatever the options, an open
    // output of a closed input says so (GngWarning::OpenedHoles) with its border edge count.
    use gng3d::gng3d_core::{GngOptions, GngTarget, GngWarning, ReconstructionParams};
    let Some(m) = shared("armadillo.obj") else {
        return;
    };
    assert!(gng3d::mesh::topology::analyze(&m).closed);
    let mut opened_paper_2 = 0;
    for seed in 1..=3 {
        for ratio in [0.02, 0.1] {
            for paper in [false, true] {
                let mut options = GngOptions {
                    seed,
                    ..GngOptions::for_target(GngTarget::VertexRatio(ratio))
                };
                if paper {
                    options.reconstruction = ReconstructionParams::paper();
                }
                let r = gng3d::gng3d_core::simplify(&m.clone().into(), &options).unwrap();
                let t = gng3d::mesh::topology::analyze(&r.mesh);
                let warned = r.report.warnings.iter().find_map(|w| match w {
                    GngWarning::OpenedHoles { boundary_edges, .. } => Some(*boundary_edges),
                    _ => None,
                });
                let open = (t.boundary_edges > 0).then_some(t.boundary_edges);
                assert_eq!(warned, open, "seed {seed}, {ratio}, paper {paper}");
                if paper && ratio == 0.02 && open.is_some() {
                    opened_paper_2 += 1;
                }
            }
        }
    }
    // Measured 2 of these 3 seeds (1 and 2): the check above has had open outputs to see.
    assert!(opened_paper_2 >= 1, "no open output to check");
}

#[test]
fn reproduce_never_writes_an_empty_table() {
    // A tetrahedron (the target is every vertex: no training needed) has its network as the
    // one checkpoint; the table had no row, and the CLI said it wrote 11 files with exit 0.
    let tet = gng3d::mesh::TriMesh::new(
        vec![
            glam::Vec3::ZERO,
            glam::Vec3::X,
            glam::Vec3::Y,
            glam::Vec3::Z,
        ],
        vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]],
    );
    let report = reproduce(&tet, &small_params(30), |_| {}).unwrap();
    assert_eq!(report.checkpoints.len(), 1);
    assert_eq!(report.checkpoints[0].gng.vertices, 4);
    assert!(!checkpoint_table(&report).to_text().trim().is_empty());
}

#[test]
fn the_survey_measures_the_meshes_simplify_writes_for_an_input_with_seams() {
    use gng3d::experiment::survey::{SurveyParams, survey_mesh_with_attributes};
    // A UV sphere: its meridian seam shapes QEM's attribute-keeping geometry, so the positions-
    // only run differs and the survey's figures say which one it measured.
    let (sphere, uv) = procedural::textured_sphere(16, 32);
    let mut params = SurveyParams {
        ratios: vec![0.25],
        epochs: 2,
        ..SurveyParams::default()
    };
    params.hausdorff = HausdorffParams::with_samples(5_000);
    let rows = survey_mesh_with_attributes("sphere", &sphere, Some(&uv), &params).unwrap();
    let row = &rows[0];
    assert!(row.attributes.is_some(), "no attribute columns");
    let area = sphere.area();
    let target = gng3d::qem::Target::Vertices(row.qem.vertices);
    let qp = gng3d::qem::QemParams::with_target(target);
    let plain = gng3d::mesh::Model::from(sphere.clone());
    let textured = gng3d::mesh::Model {
        attributes: Some(uv.clone()),
        ..plain.clone()
    };
    let kept = gng3d::qem::simplify(&textured, &qp).unwrap().0.mesh;
    let plain = gng3d::qem::simplify(&plain, &qp).unwrap().0.mesh;
    let e_sur = |m: &gng3d::mesh::TriMesh| area - m.area();
    assert!(
        (e_sur(&kept) - e_sur(&plain)).abs() > 1e-6 * area,
        "the two QEM runs coincide: the test cannot tell them apart"
    );
    assert!(
        (row.qem.e_sur_signed - e_sur(&kept)).abs() < 1e-9 * area,
        "survey QEM E_sur {} is not the attribute-keeping run's {} (positions only: {})",
        row.qem.e_sur_signed,
        e_sur(&kept),
        e_sur(&plain)
    );
    // GNG3D-Q's triangles follow the seam as `simplify` makes them: the job's mesh.
    let vertices =
        ((sphere.vertex_count() as f64 * 0.25).round() as usize).clamp(4, sphere.vertex_count());
    let request = gng3d::job::Request::new(gng3d::job::Target::Vertices(vertices))
        .with_method(gng3d::job::Method::Gng);
    let model = gng3d::mesh::Model {
        attributes: Some(uv),
        ..gng3d::mesh::Model::from(sphere)
    };
    let gngq = gng3d::job::run(&model, &request, &mut ())
        .unwrap()
        .model
        .mesh;
    assert!(
        (row.gngq.e_sur_signed - (area - gngq.area())).abs() < 1e-9 * area,
        "survey GNG3D-Q is not the job's"
    );
}
