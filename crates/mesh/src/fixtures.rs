//! Test and benchmark helpers (cargo feature `fixtures`; never needed by a product build).
//!
//! - [`shared_meshes_dir`]: locating the shared real meshes (`GNG3D_MESHES`) with the project's
//!   rule: without them a test skips with a message, except under `CI`, where it fails
//!   ([`find_shared_meshes`]: the same search, silent).
//! - [`skip`] / [`skip_unless_ci`]: the message of a test that skips, one `SKIPPED <test>:
//!   <reason>` line that a plain `cargo test` shows, and when the test binary exits one line
//!   counting its skips and the `cargo test` run's so far, by reason (docs/testing.md).
//! - [`fuzz`]: the seed files and byte mutations shared by the loader fuzz tests (mesh) and the
//!   CLI fuzz tests and driver (crates/cli).
//! - [`attribute_values_near`]: the brute-force oracle of an attribute's value on a surface,
//!   which the attribute tests of qem and the CLI check transferred values against.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, PoisonError};

/// Name of the environment variable that points at the shared meshes folder.
pub const MESHES_ENV: &str = "GNG3D_MESHES";

/// The folder named by `GNG3D_MESHES`, provided it holds the file `probe` (e.g. `"README.md"`,
/// or the mesh a test needs). Otherwise `None` after a [`skip`] line on stderr, or a panic when
/// the environment variable `CI` is set: tests that need the meshes must fail, not skip, in CI.
///
/// A relative folder is looked up from the current folder and then from each folder above it:
/// `cargo test` runs every test in its own package's folder, so `GNG3D_MESHES=../shared/meshes`
/// set at the workspace root works for the tests of every crate.
pub fn shared_meshes_dir(probe: &str) -> Option<PathBuf> {
    match find_shared_meshes(probe) {
        Ok(dir) => Some(dir),
        Err(reason) => {
            skip_unless_ci(&reason);
            None
        }
    }
}

/// The folder [`shared_meshes_dir`] returns, or why there is none (the reason it would report),
/// without reporting anything: for a test that looks for something next to the meshes.
pub fn find_shared_meshes(probe: &str) -> Result<PathBuf, String> {
    let cwd = std::env::current_dir().ok();
    locate(std::env::var_os(MESHES_ENV), cwd.as_deref(), probe)
}

/// [`find_shared_meshes`] for a given value of `GNG3D_MESHES` and current folder.
fn locate(value: Option<OsString>, cwd: Option<&Path>, probe: &str) -> Result<PathBuf, String> {
    let Some(value) = value else {
        return Err(format!(
            "{MESHES_ENV} not set (export {MESHES_ENV}=/path/to/the/test/meshes, docs/testing.md)"
        ));
    };
    let dir = PathBuf::from(value);
    let candidates: Vec<PathBuf> = match cwd {
        Some(cwd) if dir.is_relative() => cwd.ancestors().map(|a| a.join(&dir)).collect(),
        _ => vec![dir.clone()],
    };
    candidates
        .into_iter()
        .find(|d| d.join(probe).is_file())
        .ok_or_else(|| format!("{MESHES_ENV}={} does not hold {probe}", dir.display()))
}

/// A requirement of the running test is missing (the shared meshes, a GPU adapter, a tool):
/// under `CI` this panics with `reason`, since no test may skip there; otherwise it reports the
/// skip with [`skip`] and the caller returns.
pub fn skip_unless_ci(reason: &str) {
    assert!(std::env::var_os("CI").is_none(), "CI is set but {reason}");
    skip(reason);
}

/// Reports that the running test skips (all of it, or the part that needs what is missing):
/// one line `SKIPPED <test>: <reason>` on the process's stderr, once per test. The line goes
/// to stderr directly, not through `eprintln!`, which the test harness captures (and shows only
/// for a failing test), so a plain `cargo test` shows every skip. `<test>` is the test's name
/// (its thread's), or the executable's for a benchmark.
///
/// libtest counts a skipped test as passed, so every skip is also recorded: when the process
/// exits it prints one line `skipped: N tests of <binary>; M in this cargo run so far — ...`
/// after libtest's `test result` line, the reasons counted (see [`summary`]).
pub fn skip(reason: &str) {
    use std::io::Write;
    let test = match std::thread::current().name() {
        Some(name) if name != "main" => name.to_string(),
        _ => executable_name(),
    };
    let mut reported = SKIPPED.lock().unwrap_or_else(PoisonError::into_inner);
    if reported.iter().any(|(t, _)| *t == test) {
        return;
    }
    let _ = writeln!(std::io::stderr().lock(), "SKIPPED {test}: {reason}");
    if reported.is_empty() {
        // SAFETY: `atexit` is the C runtime's; the handler is a plain function that only
        // writes to stderr and a file.
        unsafe { atexit(report_skips_at_exit) };
    }
    reported.push((test, reason.to_string()));
    run_log::record(reason);
}

/// The tests of this process that skipped, and why, in the order they skipped.
static SKIPPED: Mutex<Vec<(String, String)>> = Mutex::new(Vec::new());

unsafe extern "C" {
    fn atexit(handler: extern "C" fn()) -> std::ffi::c_int;
}

/// Prints [`summary`] of this process's skips, with the run's total where it is known.
extern "C" fn report_skips_at_exit() {
    use std::io::Write;
    // A test thread still holding the lock at exit (a panic elsewhere): no summary then.
    let Ok(reported) = SKIPPED.try_lock() else {
        return;
    };
    let reasons: Vec<&str> = reported.iter().map(|(_, r)| r.as_str()).collect();
    let line = summary(&executable_name(), &reasons, run_log::total());
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// The line printed when a test binary that skipped exits, e.g. `skipped: 3 tests of cli; 7 in
/// this cargo run so far — 2: GNG3D_MESHES not set (…); 1: no /dev/full on this system`:
/// `reasons` one per skipped test, grouped in order of first appearance; `run_total` the
/// skips of the whole `cargo test` run up to this binary, where known.
pub fn summary(binary: &str, reasons: &[&str], run_total: Option<usize>) -> String {
    let mut groups: Vec<(&str, usize)> = Vec::new();
    for &r in reasons {
        match groups.iter_mut().find(|(g, _)| *g == r) {
            Some((_, n)) => *n += 1,
            None => groups.push((r, 1)),
        }
    }
    let n = reasons.len();
    let mut line = format!(
        "skipped: {n} test{} of {binary}",
        if n == 1 { "" } else { "s" }
    );
    if let Some(total) = run_total {
        line.push_str(&format!("; {total} in this cargo run so far"));
    }
    let why: Vec<String> = groups.iter().map(|(r, n)| format!("{n}: {r}")).collect();
    line.push_str(&format!(" — {}", why.join("; ")));
    line
}

/// The skips of one `cargo test` run, across its test binaries: cargo runs them one after the
/// other as children of one process, so each binary appends its skips to a file named after
/// that process (its id and start time, from `/proc`) in `skipped-tests/` beside the test
/// executables (`target/debug/`), where files of earlier runs are removed. Linux only;
/// elsewhere the summary counts one binary's skips.
mod run_log {
    use std::io::Write;
    use std::path::PathBuf;

    /// This run's file, or `None` when the parent cannot be identified.
    #[cfg(target_os = "linux")]
    fn file() -> Option<PathBuf> {
        let parent = std::os::unix::process::parent_id();
        let stat = std::fs::read_to_string(format!("/proc/{parent}/stat")).ok()?;
        // Field 22 (start time); the fields after the command name, which may hold spaces,
        // start at field 3.
        let started = stat.rsplit_once(')')?.1.split_whitespace().nth(19)?;
        let exe = std::env::current_exe().ok()?;
        // target/debug/deps/<test> (tests) or target/debug/<binary>.
        let profile_dir = match exe.parent()? {
            d if d.ends_with("deps") => d.parent()?,
            d => d,
        };
        Some(
            profile_dir
                .join("skipped-tests")
                .join(format!("{parent}-{started}")),
        )
    }

    /// No run-wide count off Linux.
    #[cfg(not(target_os = "linux"))]
    fn file() -> Option<PathBuf> {
        None
    }

    /// Appends one skip to this run's file (a line holding `reason`).
    pub(super) fn record(reason: &str) {
        let Some(path) = file() else { return };
        let dir = path.parent().expect("a file in skipped-tests/");
        if !path.exists() {
            let _ = std::fs::create_dir_all(dir);
            for old in std::fs::read_dir(dir).into_iter().flatten().flatten() {
                let _ = std::fs::remove_file(old.path());
            }
        }
        let line = reason.replace('\n', " ");
        if let Ok(mut f) = std::fs::OpenOptions::new()
            .create(true)
            .append(true)
            .open(&path)
        {
            let _ = writeln!(f, "{line}");
        }
    }

    /// The number of skips recorded in this run so far.
    pub(super) fn total() -> Option<usize> {
        let text = std::fs::read_to_string(file()?).ok()?;
        Some(text.lines().count())
    }
}

/// This executable's name without cargo's hash suffix.
fn executable_name() -> String {
    let exe = std::env::args_os().next().unwrap_or_default();
    let stem = Path::new(&exe).file_stem().unwrap_or_default();
    without_hash(&stem.to_string_lossy()).to_string()
}

/// `topology-0123456789abcdef` -> `topology`; other names unchanged.
fn without_hash(stem: &str) -> &str {
    match stem.rsplit_once('-') {
        Some((name, hash)) if hash.len() == 16 && hash.bytes().all(|b| b.is_ascii_hexdigit()) => {
            name
        }
        _ => stem,
    }
}

/// Seeds and mutations for fuzzing the loaders and everything behind them.
pub mod fuzz {
    use mesh::TriMesh;
    use mesh::io::{Format, encode};
    use mesh::procedural::icosphere;
    use std::path::Path;

    /// Bytes that [`Mutation::Insert`] draws from: digits, signs, separators and record letters,
    /// which turn valid text into nearly-valid text.
    pub const INSERTED: &[u8] = b"0123456789-. \nefv/";

    /// One edit to a byte string (positions are taken modulo the length).
    #[derive(Debug, Clone)]
    pub enum Mutation {
        /// Overwrite one byte.
        Set(usize, u8),
        /// Cut the file short.
        Truncate(usize),
        /// Insert one byte.
        Insert(usize, u8),
        /// Delete one byte.
        Remove(usize),
    }

    /// Applies `m` to `bytes` (no-op on an empty string).
    pub fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
        if bytes.is_empty() {
            return;
        }
        let n = bytes.len();
        match *m {
            Mutation::Set(i, b) => bytes[i % n] = b,
            Mutation::Truncate(i) => bytes.truncate(i % n),
            Mutation::Insert(i, b) => bytes.insert(i % (n + 1), b),
            Mutation::Remove(i) => {
                bytes.remove(i % n);
            }
        }
    }

    /// A random mutation from a 64-bit random value (for drivers without proptest). Mostly
    /// in-place byte changes (11/16), which keep binary layouts intact so that many mutants
    /// still load and reach the algorithms; insertions 3/16, removals and truncations 1/16 each.
    pub fn random_mutation(r: u64) -> Mutation {
        let pos = (r >> 8) as usize;
        match r & 15 {
            0..=10 => Mutation::Set(pos, (r >> 56) as u8),
            11..=13 => Mutation::Insert(pos, INSERTED[(r >> 58) as usize % INSERTED.len()]),
            14 => Mutation::Remove(pos),
            _ => Mutation::Truncate(pos),
        }
    }

    fn bytes(m: &TriMesh, format: Format) -> Vec<u8> {
        encode(m, format, Path::new("seed")).expect("procedural meshes encode")
    }

    /// A binary big-endian PLY of `m` (the writer only writes little-endian).
    pub fn big_endian_ply(m: &TriMesh) -> Vec<u8> {
        let mut out = format!(
            "ply\nformat binary_big_endian 1.0\nelement vertex {}\nproperty float x\n\
             property float y\nproperty float z\nelement face {}\n\
             property list uchar int vertex_indices\nend_header\n",
            m.positions.len(),
            m.triangles.len()
        )
        .into_bytes();
        for p in &m.positions {
            for c in p.to_array() {
                out.extend_from_slice(&c.to_be_bytes());
            }
        }
        for t in &m.triangles {
            out.push(3);
            for &i in t {
                out.extend_from_slice(&(i as i32).to_be_bytes());
            }
        }
        out
    }

    /// Valid files of every encoding the loaders read, small (< 600 bytes) and a few kB:
    /// 0-2 OBJ / binary LE PLY / binary STL of a 12-vertex sphere; 3-5 the same at 162 / 162 /
    /// 42 vertices (4-16 kB); 6-7 binary big-endian PLY (12, 162 vertices); 8 OBJ with a BOM,
    /// a quad and negative indices; 9 ASCII PLY with an extra property and a quad; 10 ASCII STL;
    /// 11 ASCII STL with a bare `solid` line; 12 an 80-facet ASCII STL; and issue 33's hostile
    /// shapes: 13 a fan of 200 triangles around one vertex (PLY), 14 a fan-capped cylinder of
    /// 48 segments (OBJ), 15 120 disjoint triangles (binary STL), 16-17 a 42-vertex sphere at
    /// coordinates scaled by 1e-20 (PLY) and by 1e18 (OBJ); 18-20 a textured sphere (UV seam,
    /// normals) as OBJ, PLY and GLB, 21 a PLY sphere with vertex colours.
    pub fn seeds() -> Vec<(Format, Vec<u8>)> {
        let small = icosphere(0);
        let mut out = vec![
            (Format::Obj, bytes(&small, Format::Obj)),
            (Format::Ply, bytes(&small, Format::Ply)),
            (Format::Stl, bytes(&small, Format::Stl)),
            (Format::Obj, bytes(&icosphere(2), Format::Obj)),
            (Format::Ply, bytes(&icosphere(2), Format::Ply)),
            (Format::Stl, bytes(&icosphere(1), Format::Stl)),
            (Format::Ply, big_endian_ply(&small)),
            (Format::Ply, big_endian_ply(&icosphere(2))),
        ];
        let mut bom = b"\xEF\xBB\xBF# bom\n".to_vec();
        bom.extend_from_slice(
            b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 5\nf -1 -2 -3\n",
        );
        out.push((Format::Obj, bom));
        let mut ascii_ply = String::from(
            "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
             property float z\nproperty uchar red\nelement face 2\n\
             property list uchar int vertex_indices\nend_header\n",
        );
        ascii_ply.push_str("0 0 0 1\n1 0 0 2\n0 1 0 3\n0 0 1 4\n3 0 1 2\n4 0 1 2 3\n");
        out.push((Format::Ply, ascii_ply.into_bytes()));
        let ascii_stl = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                         vertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
        out.push((Format::Stl, ascii_stl.as_bytes().to_vec()));
        out.push((
            Format::Stl,
            ascii_stl.replacen("solid s", "solid", 1).into_bytes(),
        ));
        let sphere = icosphere(1);
        let mut text = String::from("solid sphere\n");
        for f in 0..sphere.face_count() {
            text.push_str("facet normal 0 0 0\nouter loop\n");
            for p in sphere.triangle(f) {
                text.push_str(&format!("vertex {} {} {}\n", p.x, p.y, p.z));
            }
            text.push_str("endloop\nendfacet\n");
        }
        text.push_str("endsolid sphere\n");
        out.push((Format::Stl, text.into_bytes()));
        out.push((Format::Ply, bytes(&mesh::procedural::fan(200), Format::Ply)));
        out.push((
            Format::Obj,
            bytes(&mesh::procedural::fan_capped_cylinder(48), Format::Obj),
        ));
        let pieces = TriMesh::new(
            (0..120)
                .flat_map(|i| {
                    let x = i as f32;
                    [
                        glam::Vec3::new(x, 0.0, 0.0),
                        glam::Vec3::new(x + 0.5, 0.0, 0.1),
                        glam::Vec3::new(x, 0.5, 0.2),
                    ]
                })
                .collect(),
            (0..120u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect(),
        );
        out.push((Format::Stl, bytes(&pieces, Format::Stl)));
        for (scale, format) in [(1e-20f32, Format::Ply), (1e18, Format::Obj)] {
            let mut scaled = icosphere(1);
            for p in &mut scaled.positions {
                *p *= scale;
            }
            out.push((format, bytes(&scaled, format)));
        }
        // Attributes (issue 35): a textured sphere (UV seam, normals) as OBJ with `vt`/`vn`,
        // PLY with normals and `s t`, and GLB; colours as PLY.
        let (sphere, attributes) = mesh::procedural::textured_sphere(4, 8);
        for format in [Format::Obj, Format::Ply, Format::Glb] {
            let (encoded, _) = mesh::io::encode_with_attributes(
                &sphere,
                &attributes,
                None,
                format,
                Path::new("seed"),
            )
            .expect("procedural attributes encode");
            out.push((format, encoded));
        }
        let mut coloured = mesh::attributes::Attributes::per_vertex(&sphere);
        coloured.colors = Some(
            sphere
                .positions
                .iter()
                .map(|p| glam::Vec4::new(p.x.abs(), p.y.abs(), p.z.abs(), 1.0))
                .collect(),
        );
        let (encoded, _) = mesh::io::encode_with_attributes(
            &sphere,
            &coloured,
            None,
            Format::Ply,
            Path::new("seed"),
        )
        .expect("procedural colours encode");
        out.push((Format::Ply, encoded));
        out
    }
}

/// The topology analysis before its counting-sort rewrite (one global sort of all half-edge
/// keys, then a global union-find over the 3F corners), kept as an independent oracle for
/// `topology`'s tests and as the baseline of its bench.
pub mod previous_topology {
    use mesh::TriMesh;
    use mesh::topology::{EdgeTable, TopologyReport, UnionFind};

    /// Edge table by sorting all packed half-edge keys at once (the previous implementation).
    pub fn edge_table(mesh: &TriMesh) -> EdgeTable {
        let f = mesh.triangles.len();
        let mut half: Vec<(u64, u32)> = Vec::with_capacity(3 * f);
        for (fi, t) in mesh.triangles.iter().enumerate() {
            for i in 0..3 {
                let (a, b) = (t[i], t[(i + 1) % 3]);
                let key = ((a.min(b) as u64) << 32) | a.max(b) as u64;
                half.push((key, (3 * fi + i) as u32));
            }
        }
        half.sort_unstable();
        let mut edges = Vec::with_capacity(3 * f / 2 + 1);
        let mut offsets = Vec::with_capacity(3 * f / 2 + 2);
        let mut edge_corners = Vec::with_capacity(3 * f);
        let mut face_edges = vec![[0u32; 3]; f];
        let mut last = u64::MAX;
        for &(key, corner) in &half {
            if key != last {
                offsets.push(edge_corners.len() as u32);
                edges.push([(key >> 32) as u32, key as u32]);
                last = key;
            }
            let e = (edges.len() - 1) as u32;
            face_edges[corner as usize / 3][corner as usize % 3] = e;
            edge_corners.push(corner);
        }
        offsets.push(edge_corners.len() as u32);
        EdgeTable {
            edges,
            offsets,
            edge_corners,
            face_edges,
        }
    }

    /// The previous global corner union-find implementation, kept as an independent check.
    pub fn analyze(mesh: &TriMesh) -> TopologyReport {
        let table = &edge_table(mesh);
        let v = mesh.positions.len();
        let f = mesh.triangles.len();
        let mut referenced = vec![false; v];
        for t in &mesh.triangles {
            for &i in t {
                referenced[i as usize] = true;
            }
        }
        let referenced_vertices = referenced.iter().filter(|&&r| r).count();

        let mut boundary_edges = 0;
        let mut non_manifold_edges = 0;
        let mut boundary_graph = UnionFind::new(v);
        let mut on_boundary = vec![false; v];
        let mut faces_uf = UnionFind::new(f);
        // Corners 3*face+i; corners of the same vertex joined across shared edges form fans.
        let mut fans_uf = UnionFind::new(3 * f);
        let corner_of = |face: u32, vertex: u32| -> u32 {
            let t = mesh.triangles[face as usize];
            let i = t.iter().position(|&x| x == vertex).unwrap_or(0);
            3 * face + i as u32
        };
        for e in 0..table.len() {
            let corners = table.corners(e);
            match corners.len() {
                1 => {
                    boundary_edges += 1;
                    let [a, b] = table.edges[e];
                    boundary_graph.union(a, b);
                    on_boundary[a as usize] = true;
                    on_boundary[b as usize] = true;
                }
                2 => {}
                _ => non_manifold_edges += 1,
            }
            let [a, b] = table.edges[e];
            let first = corners[0] / 3;
            for &c in &corners[1..] {
                let face = c / 3;
                faces_uf.union(first, face);
                fans_uf.union(corner_of(first, a), corner_of(face, a));
                fans_uf.union(corner_of(first, b), corner_of(face, b));
            }
        }
        let boundary_loops = (0..v as u32)
            .filter(|&i| on_boundary[i as usize] && boundary_graph.find(i) == i)
            .count();
        let components = (0..f as u32).filter(|&i| faces_uf.find(i) == i).count();
        let mut fans_at = vec![0u32; v];
        let mut fans_total = 0i64;
        for c in 0..3 * f as u32 {
            if fans_uf.find(c) == c {
                fans_total += 1;
                fans_at[mesh.triangles[c as usize / 3][c as usize % 3] as usize] += 1;
            }
        }
        let non_manifold_vertices = fans_at.iter().filter(|&&n| n > 1).count();
        let edges = table.len() as i64;
        let euler = referenced_vertices as i64 - edges + f as i64;
        let euler_split = fans_total - edges + f as i64;
        let twice_genus = 2 * components as i64 - euler_split - boundary_loops as i64;
        let genus = (non_manifold_edges == 0 && twice_genus % 2 == 0).then_some(twice_genus / 2);
        TopologyReport {
            vertices: v,
            referenced_vertices,
            faces: f,
            edges: table.len(),
            boundary_edges,
            boundary_loops,
            non_manifold_edges,
            non_manifold_vertices,
            components,
            euler_characteristic: euler,
            euler_characteristic_split: euler_split,
            genus,
            closed: boundary_edges == 0,
            manifold: non_manifold_edges == 0 && non_manifold_vertices == 0,
        }
    }
}

/// Every value of the per-wedge attribute `values` (of `attributes` on `mesh`) at the points of
/// the surface within `reach` of the closest distance to `p`: brute force over every face,
/// barycentric interpolation of the corners' values; on a seam, one value per side. The
/// independent computation that transferred attributes are checked against.
pub fn attribute_values_near<T: Copy + std::iter::Sum + std::ops::Mul<f32, Output = T>>(
    mesh: &mesh::TriMesh,
    attributes: &mesh::attributes::Attributes,
    values: &[T],
    p: glam::Vec3,
    reach: f64,
) -> Vec<T> {
    let p = p.as_dvec3();
    let found: Vec<(f64, T)> = attributes
        .corners
        .iter()
        .enumerate()
        .map(|(f, c)| {
            let [x, y, z] = mesh.triangle_f64(f);
            let q = mesh::geometry::closest_point_triangle(p, x, y, z);
            let w = mesh::transfer::barycentric(q, x, y, z);
            (
                q.distance(p),
                (0..3).map(|k| values[c[k] as usize] * w[k] as f32).sum(),
            )
        })
        .collect();
    let best = found.iter().map(|f| f.0).fold(f64::INFINITY, f64::min);
    found
        .into_iter()
        .filter(|f| f.0 <= best + reach)
        .map(|f| f.1)
        .collect()
}

/// The Khronos glTF-Validator's report (one JSON object: `errors`, `warnings`, ...) of each of
/// `files`, run with `node` through `crates/mesh/tests/support/validate_gltf.cjs` (the npm module
/// `gltf-validator`, found through GLTF_VALIDATOR_MODULE, docs/testing.md); `None` after a
/// [`skip`] line when node or the module is missing. The glTF tests of mesh and the CLI's.
pub fn validate_gltf(files: &[PathBuf]) -> Option<Vec<serde_json::Value>> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/support/validate_gltf.cjs");
    let out = match std::process::Command::new("node")
        .arg(&script)
        .args(files)
        .output()
    {
        Ok(out) => out,
        Err(e) => {
            skip(&format!("glTF validator not run: node not found ({e})"));
            return None;
        }
    };
    if out.status.code() == Some(3) {
        let why = String::from_utf8_lossy(&out.stderr);
        let why = why.lines().next().unwrap_or("").trim();
        skip(&format!(
            "glTF validator not run: {why} (GLTF_VALIDATOR_MODULE, docs/testing.md)"
        ));
        return None;
    }
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let text = String::from_utf8_lossy(&out.stdout);
    Some(
        text.lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect(),
    )
}

/// A two-triangle ASCII STL whose first line is `first` (`solid`, `solid name`, ...): the STL
/// loader's tests and the CLI's.
pub fn ascii_stl(first: &str) -> String {
    format!(
        "{first}\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n\
         endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\n\
         vertex 0 1 0\nendloop\nendfacet\nendsolid\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn missing_probe_is_none_outside_ci_and_a_panic_in_ci() {
        // The probe name cannot exist in any folder, so the outcome depends only on `CI`.
        let probe = "no such file \u{1}.obj";
        let reason = find_shared_meshes(probe).unwrap_err();
        assert!(reason.starts_with(MESHES_ENV), "{reason}");
        if std::env::var_os("CI").is_some() {
            let result = std::panic::catch_unwind(|| shared_meshes_dir(probe));
            assert!(result.is_err(), "must panic under CI");
        }
    }

    #[test]
    fn a_relative_folder_is_found_from_the_current_folder_or_a_parent() {
        // Run in crates/mesh: `src` holds lib.rs right here, `crates/mesh/src` only seen from
        // the workspace root two folders up; an absolute folder is taken as it is.
        let cwd = std::env::current_dir().unwrap();
        let src = cwd.join("src");
        let found = |value: &str| locate(Some(value.into()), Some(&cwd), "lib.rs");
        assert_eq!(found("src"), Ok(src.clone()));
        let from_root = found("crates/mesh/src").unwrap();
        assert_eq!(
            from_root.canonicalize().unwrap(),
            src.canonicalize().unwrap()
        );
        assert_eq!(found(src.to_str().unwrap()), Ok(src.clone()));
        let missing = found("no such folder").unwrap_err();
        assert_eq!(missing, "GNG3D_MESHES=no such folder does not hold lib.rs");
        let unset = locate(None, Some(&cwd), "lib.rs").unwrap_err();
        assert!(
            unset.starts_with("GNG3D_MESHES not set (export GNG3D_MESHES="),
            "{unset}"
        );
    }

    #[test]
    fn the_summary_counts_skips_by_reason() {
        let reasons = ["no meshes", "no GPU", "no meshes"];
        assert_eq!(
            summary("ui", &reasons, Some(5)),
            "skipped: 3 tests of ui; 5 in this cargo run so far — 2: no meshes; 1: no GPU"
        );
        assert_eq!(
            summary("bench", &["no meshes"], None),
            "skipped: 1 test of bench — 1: no meshes"
        );
    }

    #[test]
    fn benchmark_names_lose_cargos_hash() {
        assert_eq!(without_hash("topology-0123456789abcdef"), "topology");
        assert_eq!(without_hash("hostile-fan"), "hostile-fan");
        assert_eq!(without_hash("gng3d"), "gng3d");
    }
}
