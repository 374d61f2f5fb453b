//! Untrusted models: what a file *points at* (glTF buffers and images, OBJ `mtllib`, MTL
//! `map_Kd`) and where outputs *go* stay inside the allowed folders (issue 46). Each hostile
//! model of `hostile::models` goes through `gng3d simplify` (the binary, under a timeout, so a
//! FIFO or `/dev/zero` that blocked would fail the test) to PLY, OBJ and GLB, and after every
//! run the canary folder beside the working folder is unchanged and no output holds a canary's
//! bytes.

mod hostile;

use hostile::Arena;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs `gng3d ARGS` with a 30 s limit; (exit success, stderr).
fn gng3d(args: &[&str]) -> (bool, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_gng3d"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
            return (status.success(), err);
        }
        if start.elapsed() > Duration::from_secs(30) {
            let _ = child.kill();
            panic!("gng3d {args:?} hung (over 30 s)");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn simplify(input: &Path, output: &Path) -> (bool, String) {
    gng3d(&[
        "simplify",
        input.to_str().unwrap(),
        output.to_str().unwrap(),
        "--ratio",
        "1",
    ])
}

#[test]
fn hostile_references_stay_inside_their_folders() {
    let arena = Arena::new();
    let inputs = hostile::write_models(&arena);
    for input in &inputs {
        let name = input.file_name().unwrap().to_str().unwrap();
        let stem = input.file_stem().unwrap().to_str().unwrap();
        for ext in ["ply", "obj", "glb", "gltf"] {
            let out_dir = arena.work.join(format!("out-{stem}-{ext}"));
            std::fs::create_dir_all(&out_dir).unwrap();
            // The folder an earlier image's URI would make the copy step create, so that a
            // media type with `/..` in it could climb out of it.
            std::fs::create_dir_all(out_dir.join("x_image1.x")).unwrap();
            let output = out_dir.join(format!("x.{ext}"));
            let (ok, err) = simplify(input, &output);
            arena.check(&format!("{name} -> {ext}"));
            if name.starts_with("buffer") {
                assert!(!ok, "{name}: a buffer outside the folder was read");
                assert!(
                    err.contains("not read") && err.contains(name),
                    "{name}: {err}"
                );
                assert!(!output.exists());
                continue;
            }
            assert!(ok, "{name} -> {ext}: {err}");
            if name.starts_with("mtllib") {
                assert!(
                    err.contains("mtllib") && err.contains("not read"),
                    "{name}: {err}"
                );
            }
            if ext == "obj" {
                let text = std::fs::read_to_string(&output).unwrap();
                let vertices = text.lines().filter(|l| l.starts_with("v ")).count();
                assert_eq!(vertices, 4, "{name}: lines were added to the OBJ:\n{text}");
                for line in text.lines() {
                    assert!(
                        !line.starts_with("mtllib")
                            || line == "mtllib x.mtl"
                            || line == "mtllib inside.mtl",
                        "{name}: {line}"
                    );
                }
                // Every file written beside the output is inside its folder with a plain name.
                for (path, _) in hostile::snapshot(&out_dir) {
                    let file = path.file_name().unwrap().to_str().unwrap();
                    assert!(!file.chars().any(char::is_control), "{path:?}");
                }
            }
        }
    }
}

#[test]
fn embedded_image_names_take_a_fixed_extension() {
    let arena = Arena::new();
    let spec = hostile::Spec {
        material: Some("m"),
        image_mime: Some("image/x/../../victim"),
        ..hostile::Spec::default()
    };
    let input = arena.work.join("mime.glb");
    std::fs::write(&input, hostile::glb(&spec, b"not an image")).unwrap();
    let out = arena.work.join("out");
    std::fs::create_dir_all(out.join("x_image0.x")).unwrap();
    let (ok, err) = simplify(&input, &out.join("x.obj"));
    assert!(ok, "{err}");
    arena.check("mime");
    let mtl = std::fs::read_to_string(out.join("x.mtl")).unwrap();
    assert!(mtl.contains("map_Kd x_image0.bin"), "{mtl}");
    assert_eq!(
        std::fs::read(out.join("x_image0.bin")).unwrap(),
        b"not an image"
    );
}

#[test]
fn material_names_cannot_add_lines() {
    let arena = Arena::new();
    let spec = hostile::Spec {
        material: Some("evil\nmtllib /etc/passwd\nv 9 9 9"),
        image_mime: Some("image/png"),
        ..hostile::Spec::default()
    };
    let input = arena.work.join("named.glb");
    std::fs::write(&input, hostile::glb(&spec, b"\x89PNG\r\n\x1a\n")).unwrap();
    let out = arena.work.join("named.obj");
    let (ok, err) = simplify(&input, &out);
    assert!(ok, "{err}");
    let obj = std::fs::read_to_string(&out).unwrap();
    assert!(
        obj.contains("usemtl evil_mtllib /etc/passwd_v 9 9 9\n"),
        "{obj}"
    );
    let mtl = std::fs::read_to_string(arena.work.join("named.mtl")).unwrap();
    assert!(
        mtl.contains("newmtl evil_mtllib /etc/passwd_v 9 9 9\n"),
        "{mtl}"
    );
    assert!(!mtl.lines().any(|l| l.starts_with("mtllib")), "{mtl}");
    // The OBJ reads back with the glTF's four vertices and its one material, named as written.
    let back = mesh::io::load(&out).unwrap();
    assert_eq!(back.mesh.vertex_count(), 4);
    assert_eq!(
        back.materials.unwrap().names,
        vec!["evil_mtllib /etc/passwd_v 9 9 9"]
    );
}

#[test]
fn a_library_outside_is_neither_copied_nor_read() {
    let arena = Arena::new();
    let input = arena.work.join("m.obj");
    std::fs::write(&input, hostile::obj("../outside/secret.mtl")).unwrap();
    let out = arena.work.join("out");
    std::fs::create_dir_all(&out).unwrap();
    for ext in ["obj", "glb", "gltf"] {
        let (ok, err) = simplify(&input, &out.join(format!("m.{ext}")));
        assert!(ok, "{err}");
        assert!(
            err.contains(
                "mtllib ../outside/secret.mtl not read or written: it leaves the model's folder"
            ),
            "{err}"
        );
    }
    assert!(!out.join("secret.mtl").exists());
    arena.check("mtllib");
}

#[test]
fn a_texture_outside_is_not_embedded() {
    let arena = Arena::new();
    let input = arena.work.join("t.obj");
    std::fs::write(&input, hostile::obj("t.mtl")).unwrap();
    std::fs::write(
        arena.work.join("t.mtl"),
        "newmtl m\nKd 1 0 0\nmap_Kd ../outside/secret.png\n",
    )
    .unwrap();
    let (ok, err) = simplify(&input, &arena.work.join("t-out.glb"));
    assert!(ok, "{err}");
    assert!(
        err.contains("secret.png of material m not read or written: it leaves the model's folder"),
        "{err}"
    );
    arena.check("texture");
}

#[cfg(unix)]
#[test]
fn a_fifo_or_a_device_as_the_model_is_refused_at_once() {
    let arena = Arena::new();
    let fifo = arena.work.join("model.obj");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    let (ok, err) = gng3d(&["info", fifo.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("not a regular file"), "{err}");
    let zero = arena.work.join("zero.ply");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    let (ok, err) = gng3d(&["info", zero.to_str().unwrap()]);
    assert!(!ok);
    assert!(err.contains("not a regular file"), "{err}");
}

#[test]
fn outputs_never_replace_inputs_or_what_they_read() {
    let arena = Arena::new();
    let w = &arena.work;
    // A glTF whose buffer is `data.bin`, as exporters name it.
    std::fs::write(w.join("data.bin"), hostile::geometry()).unwrap();
    let scene = w.join("scene.gltf");
    let spec = hostile::Spec {
        buffer_uri: Some("data.bin"),
        ..hostile::Spec::default()
    };
    std::fs::write(&scene, hostile::gltf(&spec)).unwrap();
    let before = hostile::snapshot(w);
    let s = |a: &str, b: &str, extra: &[&str]| {
        let (a, b) = (w.join(a), w.join(b));
        let mut args = vec!["simplify", a.to_str().unwrap(), b.to_str().unwrap()];
        args.extend_from_slice(extra);
        gng3d(&args)
    };
    for (input, output, extra, replaced) in [
        ("scene.gltf", "data.gltf", &["--ratio", "1"][..], "data.bin"),
        (
            "scene.gltf",
            "./scene.gltf",
            &["--ratio", "1"][..],
            "scene.gltf",
        ),
        (
            "scene.gltf",
            "scene.gltf",
            &["--method", "gng", "--vertices", "4"][..],
            "scene.gltf",
        ),
        ("scene.gltf", "data-lod1.gltf", &["--ratio", "1"][..], ""),
        (
            "data-lod1.gltf",
            "data.gltf",
            &["--lods", "1,0.9"][..],
            "data-lod1.gltf",
        ),
    ] {
        let (ok, err) = s(input, output, extra);
        if replaced.is_empty() {
            assert!(ok, "{err}");
            continue;
        }
        assert!(
            !ok,
            "simplify {input} {output} {extra:?} replaced {replaced}"
        );
        assert!(
            err.contains(&format!(
                "would replace {}",
                w.join(replaced).canonicalize().unwrap().display()
            )),
            "{err}"
        );
    }
    // Nothing but the one allowed output (and its buffer) was written or changed.
    let after = hostile::snapshot(w);
    for (path, bytes) in &before {
        assert!(after[path] == *bytes, "{path:?} changed");
    }
    assert_eq!(after.len(), before.len() + 2, "{:?}", after.keys());
    arena.check("outputs");
}

#[test]
fn opting_in_reads_references_outside_but_still_only_regular_files() {
    let arena = Arena::new();
    let w = &arena.work;
    std::fs::write(arena.outside.join("geometry.bin"), hostile::geometry()).unwrap();
    let spec = hostile::Spec {
        buffer_uri: Some("../outside/geometry.bin"),
        ..hostile::Spec::default()
    };
    let model = w.join("beside.gltf");
    std::fs::write(&model, hostile::gltf(&spec)).unwrap();
    let out = w.join("beside.ply");
    let args = |opt_in: bool| {
        let mut a = vec![
            "simplify",
            model.to_str().unwrap(),
            out.to_str().unwrap(),
            "--ratio",
            "1",
        ];
        if opt_in {
            a.insert(0, "--allow-outside-references");
        }
        a
    };
    let (ok, err) = gng3d(&args(false));
    assert!(!ok && err.contains("leaves the model's folder"), "{err}");
    let (ok, err) = gng3d(&args(true));
    assert!(ok, "{err}");
    assert_eq!(mesh::io::load(&out).unwrap().mesh.vertex_count(), 4);
    // The flag may also follow the subcommand; a device is still refused.
    let spec = hostile::Spec {
        buffer_uri: Some("/dev/zero"),
        ..hostile::Spec::default()
    };
    let zero = w.join("zero.gltf");
    std::fs::write(&zero, hostile::gltf(&spec)).unwrap();
    let (ok, err) = gng3d(&[
        "simplify",
        zero.to_str().unwrap(),
        w.join("zero.ply").to_str().unwrap(),
        "--ratio",
        "1",
        "--allow-outside-references",
    ]);
    assert!(!ok && err.contains("not a regular file"), "{err}");
    // Nothing outside changed (the outside files were read, never written).
    let after = hostile::snapshot(&arena.outside);
    assert_eq!(after.len(), 5, "{:?}", after.keys());
}
