//! Materials across OBJ and glTF: the MTL reader, the fandisk atlas (OBJ + MTL + checker.png)
//! to `.glb` and `.gltf` and back to OBJ, and the warnings for what does not cross.

use super::matconv::parse_mtl;
use super::*;
use crate::Model;
use serde_json::json;

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/assets")
}

fn checker_png() -> Vec<u8> {
    std::fs::read(assets().join("checker.png")).unwrap()
}

/// What [`save`] says it dropped or did not copy, one sentence each.
fn save_dropped(
    mesh: &crate::TriMesh,
    a: &crate::attributes::Attributes,
    materials: Option<&crate::attributes::Materials>,
    path: &Path,
) -> Vec<String> {
    save(
        &Model::new(mesh.clone(), Some(a.clone()), materials.cloned()),
        path,
    )
    .unwrap_or_else(|e| panic!("{e}"))
    .dropped
}

/// The carried glTF JSON of a loaded glTF.
fn gltf_json(l: &LoadedMesh) -> &serde_json::Map<String, serde_json::Value> {
    l.materials.as_ref().unwrap().gltf.as_ref().unwrap().json()
}

#[test]
fn the_mtl_reader_keeps_what_converts_and_names_the_rest() {
    let text = b"# comment\nKa 1 1 1\nnewmtl a\nKa 0.1 0.1 0.1\nKd 0.5 0.25 1\nKs 1 1 1\n\
        Ns 98\nd 0.5\nillum 2\nmap_Kd -s 2 2 1 -clamp on my tex.png\nbump n.png\n\
        newmtl b\nKd 0.3\nTr 0.25\nPr 0.4\nPm 1\nKe 1 0 0\nmap_Kd t.jpg\nKd x y z\n";
    let (m, dropped) = parse_mtl(text);
    assert_eq!(m.len(), 2);
    assert_eq!(m[0].name, "a");
    assert_eq!(m[0].kd, Some([0.5, 0.25, 1.0]));
    assert_eq!(m[0].opacity, Some(0.5));
    assert_eq!(m[0].ns, Some(98.0));
    assert_eq!(m[0].map_kd.as_deref(), Some("my tex.png"));
    assert_eq!(m[1].kd, Some([0.3; 3]), "Kd with one value is grey");
    assert_eq!(m[1].opacity, Some(0.75), "Tr is transparency");
    assert_eq!((m[1].pr, m[1].pm), (Some(0.4), Some(1.0)));
    assert_eq!(m[1].ke, Some([1.0, 0.0, 0.0]));
    assert_eq!(m[1].map_kd.as_deref(), Some("t.jpg"));
    assert_eq!(
        dropped.into_iter().collect::<Vec<_>>(),
        [
            "Ka",
            "Ka (before any newmtl)",
            "Kd (unreadable values)",
            "Ks",
            "bump",
            "illum",
            "map_Kd option -clamp",
            "map_Kd option -s"
        ]
    );
}

#[test]
fn the_obj_atlas_becomes_a_glb_with_its_colour_and_embedded_texture() {
    let obj = load(&assets().join("fandisk_atlas.obj")).unwrap();
    let a = obj.attributes.as_ref().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("atlas.glb");
    let warnings = save_dropped(&obj.mesh, a, obj.materials.as_ref(), &path);
    assert!(warnings.is_empty(), "{warnings:?}");
    // Nothing but the .glb is written: the texture is inside it.
    let files: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert_eq!(files.len(), 1);
    let back = load(&path).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    let j = gltf_json(&back);
    assert_eq!(
        j["materials"],
        json!([{"name": "checker", "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 1.0, 1.0, 1.0], "baseColorTexture": {"index": 0},
            "metallicFactor": 0.0, "roughnessFactor": 1.0}}])
    );
    assert_eq!(j["textures"], json!([{"source": 0, "sampler": 0}]));
    assert_eq!(j["images"], json!([{"mimeType": "image/png"}]));
    let assets = back.materials.as_ref().unwrap().gltf.as_ref().unwrap();
    assert_eq!(assets.embedded_images.len(), 1);
    assert_eq!(&assets.embedded_images[0].1[..], &checker_png()[..]);
    // One glTF vertex per wedge, in order; v counted from the image's top edge.
    let (uv, back_uv) = (
        a.uv0.as_ref().unwrap(),
        back.attributes.as_ref().unwrap().uv0.as_ref().unwrap(),
    );
    assert_eq!(uv.len(), back_uv.len());
    for (p, q) in uv.iter().zip(back_uv) {
        assert_eq!(p.x, q.x);
        assert!((1.0 - p.y - q.y).abs() < 1e-6, "{p} vs {q}");
    }
}

#[test]
fn the_obj_atlas_becomes_a_gltf_with_its_texture_copied() {
    let obj = load(&assets().join("fandisk_atlas.obj")).unwrap();
    let a = obj.attributes.as_ref().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("atlas.gltf");
    let warnings = save_dropped(&obj.mesh, a, obj.materials.as_ref(), &path);
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(
        std::fs::read(dir.path().join("checker.png")).unwrap(),
        checker_png()
    );
    let back = load(&path).unwrap();
    assert_eq!(gltf_json(&back)["images"], json!([{"uri": "checker.png"}]));
    assert_eq!(
        gltf_json(&back)["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"],
        json!({"index": 0})
    );
    // A caller writing the bytes itself (as `gng3d simplify` does) copies with
    // `copy_gltf_images`: the texture for a .gltf, nothing for a .glb.
    let other = tempfile::tempdir().unwrap();
    let m = obj.materials.as_ref().unwrap();
    let (bytes, w) = encode_with_attributes(&obj.mesh, a, Some(m), Format::Gltf, &path).unwrap();
    assert!(w.is_empty(), "{w:?}");
    let to = other.path().join("x.gltf");
    write_atomic(&to, &bytes).unwrap();
    assert!(copy_gltf_images(m, &other.path().join("y.glb")).is_empty());
    assert!(!other.path().join("checker.png").exists());
    assert!(copy_gltf_images(m, &to).is_empty());
    assert_eq!(
        std::fs::read(other.path().join("checker.png")).unwrap(),
        checker_png()
    );
    let l = load(&to).unwrap();
    assert_eq!(l.mesh.face_count(), obj.mesh.face_count());
}

#[test]
fn glb_materials_become_an_mtl_with_the_image_next_to_the_obj() {
    let obj = load(&assets().join("fandisk_atlas.obj")).unwrap();
    let a = obj.attributes.as_ref().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let glb = dir.path().join("atlas.glb");
    save(
        &Model::new(obj.mesh.clone(), Some(a.clone()), obj.materials.clone()),
        &glb,
    )
    .unwrap();
    let g = load(&glb).unwrap();
    // Into another folder, so that nothing is there before.
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    let path = out.join("back.obj");
    let warnings = save_dropped(
        &g.mesh,
        g.attributes.as_ref().unwrap(),
        g.materials.as_ref(),
        &path,
    );
    assert!(warnings.is_empty(), "{}", warnings.join("\n"));
    let mtl = std::fs::read_to_string(out.join("back.mtl")).unwrap();
    assert_eq!(
        mtl,
        "# written by gng3d from glTF materials\n\nnewmtl checker\nKd 1 1 1\nNs 0\nPr 1\nPm 0\n\
         map_Kd back_image0.png\n"
    );
    assert_eq!(
        std::fs::read(out.join("back_image0.png")).unwrap(),
        checker_png()
    );
    let back = load(&path).unwrap();
    assert!(back.warnings.is_empty(), "{:?}", back.warnings);
    let m = back.materials.as_ref().unwrap();
    assert_eq!(m.names, ["checker"]);
    assert_eq!(m.libraries, [out.join("back.mtl")]);
    // The texture coordinates are the OBJ's again (v flipped twice).
    let (uv, back_uv) = (
        a.uv0.as_ref().unwrap(),
        back.attributes.as_ref().unwrap().uv0.as_ref().unwrap(),
    );
    assert_eq!(uv.len(), back_uv.len());
    for (p, q) in uv.iter().zip(back_uv) {
        assert!((*p - *q).abs().max_element() < 1e-6, "{p} vs {q}");
    }
    // And the library reads back as the same glTF material.
    let again = out.join("again.glb");
    let w = save_dropped(
        &back.mesh,
        back.attributes.as_ref().unwrap(),
        Some(m),
        &again,
    );
    assert!(w.is_empty(), "{w:?}");
    let l = load(&again).unwrap();
    assert_eq!(gltf_json(&l)["materials"], gltf_json(&g)["materials"]);

    // A .gltf naming its image by URI: the image keeps its name and is copied.
    let gltf = dir.path().join("atlas.gltf");
    save(
        &Model::new(obj.mesh.clone(), Some(a.clone()), obj.materials.clone()),
        &gltf,
    )
    .unwrap();
    let g = load(&gltf).unwrap();
    let out2 = dir.path().join("out2");
    std::fs::create_dir(&out2).unwrap();
    let w = save_dropped(
        &g.mesh,
        g.attributes.as_ref().unwrap(),
        g.materials.as_ref(),
        &out2.join("u.obj"),
    );
    assert!(w.is_empty(), "{w:?}");
    assert!(
        std::fs::read_to_string(out2.join("u.mtl"))
            .unwrap()
            .contains("map_Kd checker.png\n")
    );
    assert_eq!(
        std::fs::read(out2.join("checker.png")).unwrap(),
        checker_png()
    );
}

#[test]
fn what_does_not_convert_is_named_and_the_geometry_still_writes() {
    let dir = tempfile::tempdir().unwrap();
    let obj = "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
        usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 2/2 4/4 3/3\nusemtl c\nf 1/1 3/3 4/4\n\
        usemtl d\nf 1/1 2/2 4/4\n";
    let mtl = "newmtl a\nKa 0 0 0\nKd 1 0 0\nKs 0.5 0.5 0.5\nillum 2\nmap_Kd -s 2 2 1 missing.png\n\
        bump n.png\nnewmtl b\nKd 0.5 0 0\nd 0.5\nNs 100\nnewmtl d\nmap_Kd tex.tga\n";
    std::fs::write(dir.path().join("q.obj"), obj).unwrap();
    std::fs::write(dir.path().join("m.mtl"), mtl).unwrap();
    std::fs::write(dir.path().join("tex.tga"), [0u8, 0, 2, 0, 0, 0]).unwrap();
    let l = load(&dir.path().join("q.obj")).unwrap();
    let path = dir.path().join("q.glb");
    let w = save_dropped(
        &l.mesh,
        l.attributes.as_ref().unwrap(),
        l.materials.as_ref(),
        &path,
    );
    let missing = dir.path().join("missing.png");
    let tga = dir.path().join("tex.tga");
    assert_eq!(w.len(), 4, "{w:?}");
    assert!(
        w[0].starts_with(&format!(
            "texture {} of material a not read or written: ",
            missing.display()
        )) && w[0].contains("the material is written without it"),
        "{w:?}"
    );
    assert_eq!(
        w[1..],
        [
            format!(
                "dropped texture {} of material d: glTF takes PNG and JPEG images only",
                tga.display()
            ),
            "dropped the look of material(s) c: no material library defines them; the glTF \
             materials have their names only"
                .to_string(),
            "dropped MTL statements Ka, Ks, bump, illum, map_Kd option -s: a glTF material takes \
             Kd, d/Tr, Ns or Pr, Pm, Ke and map_Kd (without options) only"
                .to_string(),
        ]
    );
    let back = load(&path).unwrap();
    assert_eq!(back.mesh.face_count(), 4);
    let m = &gltf_json(&back)["materials"];
    assert_eq!(
        m[0]["pbrMetallicRoughness"]["baseColorFactor"],
        json!([1.0, 0.0, 0.0, 1.0])
    );
    assert!(m[0]["pbrMetallicRoughness"]["baseColorTexture"].is_null());
    assert_eq!(m[1]["alphaMode"], "BLEND");
    assert_eq!(
        m[1]["pbrMetallicRoughness"]["baseColorFactor"],
        json!([0.5, 0.0, 0.0, 0.5])
    );
    let r = m[1]["pbrMetallicRoughness"]["roughnessFactor"]
        .as_f64()
        .unwrap();
    assert!((r - (2.0f64 / 102.0).sqrt()).abs() < 1e-6, "{r}");
    assert_eq!(m[2], json!({"name": "c"}));
    assert!(gltf_json(&back).get("images").is_none());
    // No texture crossed: the texture coordinates are written as read.
    let (p, q) = (
        l.attributes.unwrap().uv0.unwrap(),
        back.attributes.unwrap().uv0.unwrap(),
    );
    assert_eq!(p, q);
}

#[test]
fn the_base_color_texture_is_found_in_obj_glb_and_gltf_materials() {
    let obj = load(&assets().join("fandisk_atlas.obj")).unwrap();
    let materials = obj.materials.as_ref().unwrap();
    let t = base_color_texture(materials).unwrap();
    assert_eq!(t.material, "checker");
    assert!(t.source.ends_with("checker.png"), "{}", t.source);
    assert_eq!(&t.bytes.unwrap()[..], &checker_png()[..]);
    assert!(!t.v_down, "OBJ: v = 0 is the bottom row");
    let a = obj.attributes.as_ref().unwrap();
    let dir = tempfile::tempdir().unwrap();
    for name in ["atlas.glb", "atlas.gltf"] {
        let path = dir.path().join(name);
        save(
            &Model::new(obj.mesh.clone(), Some(a.clone()), Some(materials.clone())),
            &path,
        )
        .unwrap();
        let back = load(&path).unwrap();
        let t = base_color_texture(back.materials.as_ref().unwrap()).unwrap();
        assert_eq!(t.material, "checker");
        assert_eq!(&t.bytes.unwrap()[..], &checker_png()[..], "{name}");
        assert!(t.v_down, "glTF: v = 0 is the top row");
    }
    // A material library naming a missing image: found, with the reason it cannot be read.
    let lonely = dir.path().join("lonely");
    std::fs::create_dir(&lonely).unwrap();
    for name in ["fandisk_atlas.obj", "fandisk_atlas.mtl"] {
        std::fs::copy(assets().join(name), lonely.join(name)).unwrap();
    }
    let loaded = load(&lonely.join("fandisk_atlas.obj")).unwrap();
    let t = base_color_texture(loaded.materials.as_ref().unwrap()).unwrap();
    assert!(
        t.source.ends_with("checker.png") && t.bytes.is_err(),
        "{t:?}"
    );
    // No texture: none.
    assert!(base_color_texture(&Materials::default()).is_none());
}
