//! QEM's quality against MeshLab's own result (the `../shared/reference` pairs), measured with
//! `metrics` (a root test, so that `qem` needs no dev-dependency on `metrics`).

use mesh::TriMesh;
use qem::{QemParams, Target};

/// A shared mesh, prepared (welded, cleaned) as every front end does.
fn load(name: &str) -> Option<TriMesh> {
    let path = mesh::fixtures::shared_meshes_dir("README.md")?.join(name);
    let raw = mesh::io::load(&path).unwrap_or_else(|e| panic!("{e}")).mesh;
    Some(mesh::clean::prepare(&raw.into()).0.mesh)
}

fn params(target: Target) -> QemParams {
    QemParams::with_target(target)
}

#[test]
fn beats_meshlab_hausdorff_on_armadillo_at_ten_percent() {
    let Some(m) = load("armadillo.obj") else {
        return;
    };
    let Some(dir) = mesh::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let reference_path = dir.join("../reference/armadillo-meshlab-8648.obj");
    if !reference_path.exists() {
        mesh::fixtures::skip(&format!(
            "no MeshLab reference at {}",
            reference_path.display()
        ));
        return;
    }
    let reference = mesh::io::load(&reference_path).unwrap().mesh;
    let target = params(Target::Faces(reference.face_count()));
    let out = qem::simplify(&mesh::Model::from(m.clone()), &target)
        .unwrap()
        .0
        .mesh;
    assert!(out.face_count().abs_diff(reference.face_count()) <= 2);
    let hp = metrics::HausdorffParams::with_samples(200_000);
    let ours = metrics::hausdorff(&m, &out, &hp).unwrap();
    let theirs = metrics::hausdorff(&m, &reference, &hp).unwrap();
    assert!(
        ours.max <= theirs.max,
        "max {} vs MeshLab {}",
        ours.max,
        theirs.max
    );
    assert!(
        ours.mean <= theirs.mean,
        "mean {} vs MeshLab {}",
        ours.mean,
        theirs.mean
    );
}
