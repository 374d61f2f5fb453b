//! Hostile models for the containment tests (`hostile_references.rs`) and the fuzz corpus
//! (`fuzz.rs`): glTF, GLB and OBJ files whose *references* point outside their folder, at
//! devices and FIFOs, through links, or carry names and media types meant to break out, plus a
//! canary folder next to the working folder whose bytes must never be read into an output and
//! whose files must never change.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The bytes every canary file starts with; a distinctive run that appears in an output only if
/// a canary file was read.
pub const CANARY: &[u8] = b"CANARY-7f3a9c21-do-not-read!";

/// Tetrahedron: positions (4 x f32x3), texture coordinates (4 x f32x2), indices (12 x u16).
pub fn geometry() -> Vec<u8> {
    let p: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
    let t: [[f32; 2]; 4] = [[0., 0.], [1., 0.], [0., 1.], [1., 1.]];
    let i: [u16; 12] = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];
    let mut b = Vec::new();
    p.iter().flatten().for_each(|x| b.extend(x.to_le_bytes()));
    t.iter().flatten().for_each(|x| b.extend(x.to_le_bytes()));
    i.iter().for_each(|x| b.extend(x.to_le_bytes()));
    b
}

/// A canary buffer: a valid geometry buffer (so a reader that follows the reference gets a
/// mesh) whose positions are the canary's bytes' neighbours: the first 48 bytes are positions,
/// then the canary after the indices. Its positions are distinctive floats.
pub fn canary_geometry() -> Vec<u8> {
    let p: [[f32; 3]; 4] = [
        [0.123_456_79, 7.654_321, 3.161_592_7],
        [9.876_543, 0.111_111_11, 2.718_281_7],
        [5.555_555_5, 4.444_444_5, 0.333_333_34],
        [1.424_213_5, 1.762_050_8, 2.256_068],
    ];
    let mut b = Vec::new();
    p.iter().flatten().for_each(|x| b.extend(x.to_le_bytes()));
    b.extend_from_slice(&geometry()[48..]);
    b.extend_from_slice(CANARY);
    b
}

/// The position bytes of [`canary_geometry`]: found in an output only if it was read.
pub fn canary_positions() -> Vec<u8> {
    canary_geometry()[..48].to_vec()
}

/// What a glTF document names besides its geometry.
#[derive(Default, Clone)]
pub struct Spec<'a> {
    /// The buffer's URI (`None`: the GLB BIN chunk).
    pub buffer_uri: Option<&'a str>,
    /// A material with this name and a base colour texture.
    pub material: Option<&'a str>,
    /// The texture's image: a URI, or embedded in the BIN chunk with this media type.
    pub image_uri: Option<&'a str>,
    pub image_mime: Option<&'a str>,
    /// Extra glTF images (URIs) before the textured one.
    pub extra_image_uris: Vec<&'a str>,
}

/// The glTF JSON of `spec` with the buffer of `bin_len` bytes (the geometry, then an embedded
/// image of `image_len` bytes).
fn json(spec: &Spec, bin_len: usize, image_len: usize) -> String {
    let mut buffer = serde_json::json!({ "byteLength": bin_len });
    if let Some(uri) = spec.buffer_uri {
        buffer["uri"] = uri.into();
    }
    let mut views = vec![
        serde_json::json!({"buffer": 0, "byteOffset": 0, "byteLength": 48}),
        serde_json::json!({"buffer": 0, "byteOffset": 48, "byteLength": 32}),
        serde_json::json!({"buffer": 0, "byteOffset": 80, "byteLength": 24}),
    ];
    let mut primitive = serde_json::json!({
        "attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "mode": 4
    });
    let mut doc = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"}
        ],
    });
    if let Some(name) = spec.material {
        primitive["material"] = 0.into();
        let mut images: Vec<serde_json::Value> = spec
            .extra_image_uris
            .iter()
            .map(|u| serde_json::json!({ "uri": u }))
            .collect();
        let mut image = serde_json::json!({});
        if let Some(uri) = spec.image_uri {
            image["uri"] = uri.into();
        } else {
            views
                .push(serde_json::json!({"buffer": 0, "byteOffset": 104, "byteLength": image_len}));
            image["bufferView"] = 3.into();
            image["mimeType"] = spec.image_mime.unwrap_or("image/png").into();
        }
        images.push(image);
        let source = images.len() - 1;
        doc["images"] = images.into();
        doc["textures"] = serde_json::json!([{ "source": source }]);
        doc["materials"] = serde_json::json!([{
            "name": name,
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}
        }]);
    }
    doc["meshes"] = serde_json::json!([{ "primitives": [primitive] }]);
    doc["bufferViews"] = views.into();
    doc["buffers"] = serde_json::json!([buffer]);
    doc.to_string()
}

/// A `.gltf` of `spec` (the buffer named by `spec.buffer_uri`, which must be given).
pub fn gltf(spec: &Spec) -> Vec<u8> {
    json(spec, 104, 0).into_bytes()
}

/// A `.glb` of `spec`: the geometry (and an embedded image `image` when the spec has a material
/// without an image URI) in the BIN chunk.
pub fn glb(spec: &Spec, image: &[u8]) -> Vec<u8> {
    let mut bin = geometry();
    let embedded = spec.material.is_some() && spec.image_uri.is_none();
    if embedded {
        bin.extend_from_slice(image);
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let mut json = json(spec, bin.len(), if embedded { image.len() } else { 0 }).into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::new();
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(&bin);
    out
}

/// A PNG signature followed by the canary: taken for a PNG by the format sniffing.
pub fn canary_png() -> Vec<u8> {
    let mut b = b"\x89PNG\r\n\x1a\n".to_vec();
    b.extend_from_slice(CANARY);
    b
}

/// A tetrahedron OBJ with texture coordinates, naming `mtllib` and using material `m`.
pub fn obj(mtllib: &str) -> Vec<u8> {
    format!(
        "mtllib {mtllib}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\n\
         usemtl m\nf 1/1 3/3 2/2\nf 1/1 2/2 4/4\nf 1/1 4/4 3/3\nf 2/2 3/3 4/4\n"
    )
    .into_bytes()
}

/// A folder pair: `work/` (the model's and the output's folder) and `outside/` with canary
/// files (`secret.bin`, `secret.mtl`, `secret.png`), plus in `work/` a FIFO and links out.
pub struct Arena {
    pub root: tempfile::TempDir,
    pub work: PathBuf,
    pub outside: PathBuf,
    before: BTreeMap<PathBuf, Vec<u8>>,
}

impl Arena {
    pub fn new() -> Arena {
        let root = tempfile::tempdir().unwrap();
        let work = root.path().join("work");
        let outside = root.path().join("outside");
        std::fs::create_dir_all(&work).unwrap();
        std::fs::create_dir_all(&outside).unwrap();
        std::fs::write(outside.join("secret.bin"), canary_geometry()).unwrap();
        let mut mtl = b"newmtl m\nKd 1 0 0\nmap_Kd secret.png\n# ".to_vec();
        mtl.extend_from_slice(CANARY);
        std::fs::write(outside.join("secret.mtl"), mtl).unwrap();
        std::fs::write(outside.join("secret.png"), canary_png()).unwrap();
        std::fs::write(outside.join("victim.txt"), b"victim: must never change").unwrap();
        #[cfg(unix)]
        {
            let fifo = std::ffi::CString::new(work.join("fifo.bin").to_str().unwrap()).unwrap();
            assert_eq!(unsafe { libc::mkfifo(fifo.as_ptr(), 0o600) }, 0);
            std::os::unix::fs::symlink(outside.join("secret.bin"), work.join("link.bin")).unwrap();
            std::os::unix::fs::symlink(outside.join("secret.png"), work.join("link.png")).unwrap();
            std::os::unix::fs::symlink(outside.join("secret.mtl"), work.join("link.mtl")).unwrap();
            std::os::unix::fs::symlink(&outside, work.join("up")).unwrap();
        }
        let before = snapshot(&outside);
        Arena {
            root,
            work,
            outside,
            before,
        }
    }

    /// The absolute path of the outside canary `name`, as text.
    pub fn secret(&self, name: &str) -> String {
        self.outside.join(name).to_str().unwrap().to_string()
    }

    /// Panics when a file outside `work/` changed, appeared or vanished, or when a file in
    /// `work/` holds a canary's bytes. `context` names the run.
    pub fn check(&self, context: &str) {
        let after = snapshot(&self.outside);
        assert_eq!(
            self.before.keys().collect::<Vec<_>>(),
            after.keys().collect::<Vec<_>>(),
            "{context}: files outside the working folder appeared or vanished"
        );
        for (path, bytes) in &self.before {
            assert!(
                after[path] == *bytes,
                "{context}: {path:?} outside the working folder changed"
            );
        }
        let root_files: Vec<_> = std::fs::read_dir(self.root.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(
            root_files.len(),
            2,
            "{context}: a file appeared beside the folders: {root_files:?}"
        );
        let positions = canary_positions();
        for (path, bytes) in snapshot(&self.work) {
            for needle in [CANARY, positions.as_slice()] {
                assert!(
                    !bytes.windows(needle.len()).any(|w| w == needle),
                    "{context}: {path:?} holds a canary's bytes"
                );
            }
        }
    }
}

/// Every regular file under `dir` (not following links) with its bytes.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let e = e.unwrap();
            let t = e.file_type().unwrap();
            if t.is_dir() {
                stack.push(e.path());
            } else if t.is_file() {
                out.insert(e.path(), std::fs::read(e.path()).unwrap());
            }
        }
    }
    out
}

/// The hostile models of an arena: (file name in `work/`, bytes).
pub fn models(arena: &Arena) -> Vec<(String, Vec<u8>)> {
    let secret_bin = arena.secret("secret.bin");
    let secret_png = arena.secret("secret.png");
    let secret_mtl = arena.secret("secret.mtl");
    let mut out = Vec::new();
    for (i, uri) in [
        "../outside/secret.bin",
        "%2e%2e/outside/secret.bin",
        "..%2Foutside%2Fsecret.bin",
        secret_bin.as_str(),
        "file:///etc/passwd",
        "/dev/zero",
        "fifo.bin",
        "link.bin",
        "up/secret.bin",
        "/proc/self/environ",
    ]
    .iter()
    .enumerate()
    {
        let spec = Spec {
            buffer_uri: Some(uri),
            ..Spec::default()
        };
        out.push((format!("buffer{i}.gltf"), gltf(&spec)));
    }
    for (i, uri) in [
        "../outside/secret.png",
        secret_png.as_str(),
        "link.png",
        "up/secret.png",
        "fifo.bin",
        "/dev/zero",
    ]
    .iter()
    .enumerate()
    {
        let spec = Spec {
            material: Some("m"),
            image_uri: Some(uri),
            ..Spec::default()
        };
        out.push((format!("image{i}.glb"), glb(&spec, &[])));
    }
    for (i, mime) in [
        "image/x/../../victim",
        "image/../../../outside/victim.txt",
        "image/\nx",
    ]
    .iter()
    .enumerate()
    {
        let spec = Spec {
            material: Some("m"),
            image_mime: Some(mime),
            // An earlier image whose relative URI would make the copy step create a folder.
            extra_image_uris: vec!["x_image1.x/a.png"],
            ..Spec::default()
        };
        out.push((format!("mime{i}.glb"), glb(&spec, b"not an image")));
    }
    let spec = Spec {
        material: Some("evil\nmtllib /etc/passwd\nv 9 9 9"),
        image_mime: Some("image/png"),
        ..Spec::default()
    };
    out.push(("named.glb".into(), glb(&spec, &canary_png()[..8])));
    for (i, lib) in [
        "../outside/secret.mtl",
        secret_mtl.as_str(),
        "link.mtl",
        "up/secret.mtl",
        "/dev/zero",
        "fifo.bin",
    ]
    .iter()
    .enumerate()
    {
        out.push((format!("mtllib{i}.obj"), obj(lib)));
    }
    // A library inside the folder naming textures outside it.
    out.push(("texture.obj".into(), obj("inside.mtl")));
    out
}

/// Files the models above expect inside `work/`.
pub fn write_models(arena: &Arena) -> Vec<PathBuf> {
    let lib = format!(
        "newmtl m\nKd 1 0 0\nmap_Kd ../outside/secret.png\nnewmtl n\nmap_Kd {}\n",
        arena.secret("secret.png")
    );
    std::fs::write(arena.work.join("inside.mtl"), lib).unwrap();
    models(arena)
        .into_iter()
        .map(|(name, bytes)| {
            let path = arena.work.join(name);
            std::fs::write(&path, bytes).unwrap();
            path
        })
        .collect()
}
