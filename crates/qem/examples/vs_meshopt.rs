//! Whole-process comparison of `qem::simplify` and meshoptimizer (`meshopt::simplify`, the same
//! C++ library as the Python `meshoptimizer` package) on the same input in the same layout:
//!
//! ```sh
//! cargo build --release -p gng3d-qem --example vs_meshopt
//! # alternate one process per call, REPS calls each; prints best / median wall, whole-process
//! # CPU (getrusage RUSAGE_SELF: all threads) and peak RSS, and the ratios qem / meshopt:
//! REPS=7 target/release/examples/vs_meshopt bench MESH RATIO [SUBDIVISIONS]
//! # one call in this process (what `bench` spawns); prints one JSON line:
//! target/release/examples/vs_meshopt run qem|meshopt MESH RATIO [SUBDIVISIONS]
//! ```
//!
//! `SUBDIVISIONS` (default 0) splits every face 1-to-4 at its edge midpoints that many times
//! after loading (igea-1m with 1 gives the 4.3M-face input; it is made here, never stored). The
//! input is prepared (`mesh::clean::prepare`) as the CLI does; both algorithms get the same
//! prepared positions and indices. `RAYON_NUM_THREADS` is passed through to the children.
//! Peak RSS includes loading and preparing, identical for both; `rss_before_mib` is the RSS
//! right before the algorithm runs, so `peak - before` is what the algorithm itself added;
//! `page_faults` counts the minor faults during the call (fresh pages the algorithm touched).

mod common;

use common::{meshopt_adapter, meshopt_simplify};
use mesh::TriMesh;
use std::collections::HashMap;
use std::process::Command;
use std::time::Instant;

/// User + system CPU seconds of the whole process so far, its peak RSS in bytes and its minor
/// page faults (first touches of fresh pages: 2.1-2.4 µs each on the development VM).
fn rusage() -> (f64, u64, u64) {
    // SAFETY: getrusage only writes into the zeroed struct we pass.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    (
        secs(u.ru_utime) + secs(u.ru_stime),
        u.ru_maxrss as u64 * 1024,
        u.ru_minflt as u64,
    )
}

/// Current resident set size in bytes (from /proc/self/statm).
fn rss_now() -> u64 {
    std::fs::read_to_string("/proc/self/statm")
        .ok()
        .and_then(|s| s.split_whitespace().nth(1)?.parse::<u64>().ok())
        .map_or(0, |pages| pages * 4096)
}

/// One 1-to-4 midpoint subdivision (shared edges get one midpoint).
fn subdivide(m: &TriMesh) -> TriMesh {
    let mut positions = m.positions.clone();
    let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(m.triangles.len() * 3 / 2);
    let mut midpoint = |a: u32, b: u32, positions: &mut Vec<glam::Vec3>| {
        *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
            positions.push(0.5 * (positions[a as usize] + positions[b as usize]));
            (positions.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(m.triangles.len() * 4);
    for &[a, b, c] in &m.triangles {
        let ab = midpoint(a, b, &mut positions);
        let bc = midpoint(b, c, &mut positions);
        let ca = midpoint(c, a, &mut positions);
        triangles.extend_from_slice(&[[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    TriMesh::new(positions, triangles)
}

fn load(path: &str, subdivisions: usize) -> TriMesh {
    let loaded = mesh::io::load(std::path::Path::new(path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let mut m = mesh::clean::prepare(&loaded.mesh.into()).0.mesh;
    for _ in 0..subdivisions {
        m = subdivide(&m);
    }
    m
}

/// One call of `method` in this process; prints a JSON line.
fn run(method: &str, path: &str, ratio: f64, subdivisions: usize) {
    let model = mesh::Model::from(load(path, subdivisions));
    let m = &model.mesh;
    let target = ((m.face_count() as f64) * ratio).round() as usize;
    let indices: Vec<u32> = m.triangles.iter().flatten().copied().collect();
    let rss_before = rss_now();
    let (cpu0, _, faults0) = rusage();
    let t = Instant::now();
    let faces = match method {
        "qem" => {
            let params = gng3d_qem::QemParams::with_target(gng3d_qem::Target::Faces(target));
            gng3d_qem::simplify(&model, &params)
                .expect("qem")
                .0
                .mesh
                .face_count()
        }
        "meshopt" => meshopt_simplify(&indices, &meshopt_adapter(&m.positions), target).len() / 3,
        other => {
            eprintln!("unknown method {other:?} (qem | meshopt)");
            std::process::exit(2)
        }
    };
    let wall = t.elapsed().as_secs_f64();
    let (cpu1, peak, faults1) = rusage();
    println!(
        "{{\"method\":\"{method}\",\"input_faces\":{},\"faces\":{faces},\"wall_s\":{wall:.6},\"cpu_s\":{:.6},\"peak_rss_mib\":{:.1},\"rss_before_mib\":{:.1},\"page_faults\":{}}}",
        m.face_count(),
        cpu1 - cpu0,
        peak as f64 / 1048576.0,
        rss_before as f64 / 1048576.0,
        faults1 - faults0
    );
}

/// The value of `"key":` in a flat JSON line.
fn field(line: &str, key: &str) -> f64 {
    let k = format!("\"{key}\":");
    let rest = &line[line.find(&k).expect("field") + k.len()..];
    let end = rest.find([',', '}']).unwrap_or(rest.len());
    rest[..end].parse().expect("number")
}

fn bench(path: &str, ratio: &str, subdivisions: &str) {
    let reps: usize = std::env::var("REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(7);
    let exe = std::env::current_exe().expect("exe");
    let mut rows: HashMap<&str, Vec<String>> = HashMap::new();
    for _ in 0..reps {
        for method in ["qem", "meshopt"] {
            let out = Command::new(&exe)
                .args(["run", method, path, ratio, subdivisions])
                .output()
                .expect("spawn");
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let line = String::from_utf8_lossy(&out.stdout).trim().to_string();
            rows.entry(method).or_default().push(line);
        }
    }
    let stat = |method: &str, key: &str| {
        let mut v: Vec<f64> = rows[method].iter().map(|l| field(l, key)).collect();
        v.sort_by(f64::total_cmp);
        (v[0], v[v.len() / 2])
    };
    let input = field(&rows["qem"][0], "input_faces");
    println!(
        "{path} x{subdivisions} subdivisions: {input} faces -> ratio {ratio}, {reps} alternating processes each, threads {}",
        std::env::var("RAYON_NUM_THREADS").unwrap_or_else(|_| "default".into())
    );
    for key in [
        "wall_s",
        "cpu_s",
        "peak_rss_mib",
        "rss_before_mib",
        "page_faults",
    ] {
        let (qb, qm) = stat("qem", key);
        let (mb, mm) = stat("meshopt", key);
        println!(
            "  {key:>15}: qem best {qb:.4} median {qm:.4} | meshopt best {mb:.4} median {mm:.4} | ratio best {:.3} median {:.3}",
            qb / mb,
            qm / mm
        );
    }
    let faces = |m: &str| field(&rows[m][0], "faces");
    println!(
        "  output faces: qem {} meshopt {}",
        faces("qem"),
        faces("meshopt")
    );
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: vs_meshopt bench MESH RATIO [SUBDIVISIONS] | run qem|meshopt MESH RATIO [SUBDIVISIONS]";
    match args.get(1).map(String::as_str) {
        Some("run") if args.len() >= 5 => run(
            &args[2],
            &args[3],
            args[4].parse().expect("ratio"),
            args.get(5).map_or(0, |s| s.parse().expect("subdivisions")),
        ),
        Some("bench") if args.len() >= 4 => {
            bench(&args[2], &args[3], args.get(4).map_or("0", String::as_str))
        }
        _ => {
            eprintln!("{usage}");
            std::process::exit(2)
        }
    }
}
