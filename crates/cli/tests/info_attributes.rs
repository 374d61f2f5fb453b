//! `gng3d info` lists a mesh's attributes: names, wedges, seam edges, charts and materials,
//! checked against a direct reading of the OBJ file's face lines.

use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::process::Command;

fn info_json(path: &Path) -> serde_json::Value {
    let o = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(["info", path.to_str().unwrap(), "--json"])
        .output()
        .expect("run gng3d");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn info_counts_wedges_seams_and_materials_of_a_textured_obj() {
    let asset = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets/fandisk_atlas.obj");
    let text = std::fs::read_to_string(&asset).unwrap();
    // Independent reading: each face corner is `v/vt/vn`; a wedge is a distinct corner
    // token, a seam edge an edge of two faces whose tokens differ at one of its ends.
    let mut wedges = HashSet::new();
    let mut ends: HashMap<(u32, u32), Vec<(String, String)>> = HashMap::new();
    let mut materials = Vec::new();
    for line in text.lines() {
        if let Some(name) = line.strip_prefix("usemtl ")
            && !materials.contains(&name.trim().to_string())
        {
            materials.push(name.trim().to_string());
        }
        let Some(rest) = line.strip_prefix("f ") else {
            continue;
        };
        let corners: Vec<&str> = rest.split_whitespace().collect();
        assert_eq!(corners.len(), 3, "the asset is triangulated");
        let vertex = |c: &str| c.split('/').next().unwrap().parse::<u32>().unwrap();
        for k in 0..3 {
            wedges.insert(corners[k].to_string());
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let (key, tokens) = if vertex(a) < vertex(b) {
                ((vertex(a), vertex(b)), (a.to_string(), b.to_string()))
            } else {
                ((vertex(b), vertex(a)), (b.to_string(), a.to_string()))
            };
            ends.entry(key).or_default().push(tokens);
        }
    }
    let seams = ends
        .values()
        .filter(|sides| sides.len() == 2 && sides[0] != sides[1])
        .count();
    let j = info_json(&asset);
    let a = &j["attributes"];
    assert_eq!(
        a["names"],
        serde_json::json!(["normals", "uv0", "materials"]),
        "{j}"
    );
    assert_eq!(a["wedges"], wedges.len(), "{j}");
    assert_eq!(a["seam_edges"], seams, "{j}");
    assert!(seams > 100, "an atlas has seams: {seams}");
    assert!(a["charts"].as_u64().unwrap() > 1, "{j}");
    assert_eq!(a["materials"], serde_json::json!(materials), "{j}");
}

#[test]
fn info_has_no_attributes_for_a_positions_only_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("tetra.obj");
    std::fs::write(
        &path,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
    )
    .unwrap();
    let j = info_json(&path);
    assert!(j.get("attributes").is_none(), "{j}");
    assert_eq!(j["vertices"], 4);
}
