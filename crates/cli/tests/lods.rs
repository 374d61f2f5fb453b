//! `simplify --lods`: a chain of QEM levels in one run, each from the one before, attributes
//! kept; the first level is exactly `--ratio`'s output; bad chains are errors.

mod common;
use common::{gng3d, succeeded};

#[test]
fn lods_chain_levels_and_keep_attributes() {
    let dir = tempfile::tempdir().unwrap();
    let (sphere, uv) = gng3d::mesh::procedural::textured_sphere(24, 48);
    let input = dir.path().join("sphere.obj");
    gng3d::mesh::io::save(
        &gng3d::mesh::Model::new(sphere.clone(), Some(uv.clone()), None),
        &input,
    )
    .unwrap();
    let (i, out) = (input.to_str().unwrap(), dir.path().join("out.obj"));
    let o = succeeded(gng3d(&[
        "simplify",
        i,
        out.to_str().unwrap(),
        "--lods",
        "0.5,0.25,0.1",
        "--json",
    ]));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let levels = json["levels"].as_array().unwrap();
    assert_eq!(levels.len(), 3);
    let mut previous = sphere.positions.len() as u64;
    for (k, level) in levels.iter().enumerate() {
        let path = dir.path().join(format!("out-lod{}.obj", k + 1));
        assert_eq!(level["output"].as_str().unwrap(), path.to_str().unwrap());
        let loaded = gng3d::mesh::io::load(&path).unwrap();
        let vertices = level["vertices"].as_u64().unwrap();
        assert!(
            vertices < previous,
            "level {k}: {vertices} after {previous}"
        );
        previous = vertices;
        // Each level made from the one before: its input is the previous level.
        assert!(level["report"]["input_vertices"].as_u64().unwrap() > vertices);
        let attributes = loaded.attributes.expect("texture coordinates kept");
        assert!(attributes.uv0.is_some());
        attributes.validate(&loaded.mesh).unwrap();
        assert_eq!(level["attributes"]["kept"][0], "normals");
    }
    // Level 1 is exactly the single run at the same share; later levels hit the same counts.
    for (k, ratio) in [(0, "0.5"), (2, "0.1")] {
        let single = dir.path().join(format!("single{k}.obj"));
        let s = gng3d(&[
            "simplify",
            i,
            single.to_str().unwrap(),
            "--ratio",
            ratio,
            "--json",
        ]);
        let summary: serde_json::Value = serde_json::from_slice(&s.stdout).unwrap();
        assert_eq!(summary["vertices"], levels[k]["vertices"]);
        if k == 0 {
            let lod1 = dir.path().join("out-lod1.obj");
            assert_eq!(
                std::fs::read(&single).unwrap(),
                std::fs::read(&lod1).unwrap()
            );
        }
    }

    for (args, says) in [
        (vec!["--lods", "0.5,0.6"], "must decrease"),
        (vec!["--lods", "0.5,0"], "(0, 1]"),
        (vec!["--lods", "0.5", "--method", "gng"], "to QEM only"),
    ] {
        let bad = dir.path().join("bad.obj");
        let mut a = vec!["simplify", i, bad.to_str().unwrap()];
        a.extend(args);
        let o = gng3d(&a);
        assert_eq!(o.status.code(), Some(1));
        assert!(String::from_utf8_lossy(&o.stderr).contains(says), "{says}");
        assert!(!dir.path().join("bad-lod1.obj").exists());
    }
}

/// Issue 46: a share that rounds below a mesh's fewest vertices was run as a target of 0 with
/// no warning, and a level that stopped short of its target said nothing.
#[test]
fn lods_too_small_is_an_error_and_a_short_level_is_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    let (sphere, uv) = gng3d::mesh::procedural::textured_sphere(12, 24);
    let input = dir.path().join("sphere.obj");
    gng3d::mesh::io::save(
        &gng3d::mesh::Model::new(sphere.clone(), Some(uv.clone()), None),
        &input,
    )
    .unwrap();
    let i = input.to_str().unwrap();
    let available = gng3d::mesh::io::load(&input)
        .unwrap()
        .mesh
        .triangles
        .iter()
        .flatten()
        .collect::<std::collections::BTreeSet<_>>()
        .len();

    let out = dir.path().join("out.obj");
    let o = gng3d(&["simplify", i, out.to_str().unwrap(), "--lods", "0.5,1e-300"]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!(
            "--lods: level 2's share 1e-300 gives 0 of the {available} vertices of {i}; a level \
             needs at least 3"
        )),
        "{stderr}"
    );
    assert!(!dir.path().join("out-lod1.obj").exists());

    // A target of 3 on a closed, textured sphere: QEM stops short (at least a tetrahedron's
    // 4 vertices; seams hold more) and says so.
    let share = format!("{}", 3.2 / available as f64);
    let o = gng3d(&[
        "simplify",
        i,
        out.to_str().unwrap(),
        "--lods",
        &format!("0.5,{share}"),
    ]);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stderr}");
    let lod2 = dir.path().join("out-lod2.obj");
    let warning = stderr
        .lines()
        .find(|l| l.starts_with("warning: "))
        .unwrap_or_else(|| panic!("no warning: {stderr}"));
    let reached = warning
        .strip_prefix(&format!(
            "warning: level 2 ({}): QEM stopped at ",
            lod2.display()
        ))
        .and_then(|rest| rest.split_once(" of 3 vertices: "))
        .unwrap_or_else(|| panic!("{warning}"))
        .0;
    assert!(reached.parse::<usize>().unwrap() >= 4, "{warning}");
    assert_eq!(stderr.matches("warning: ").count(), 1, "{stderr}");
}
