//! One `qem::simplify` call on a model with attributes, or on its mesh alone, or one
//! meshoptimizer `simplifyWithAttributes` call on the same input (all weights 0, as the
//! `attributes` bench), for callgrind:
//!
//! ```sh
//! cargo build --profile profiling -p gng3d-qem --example attr_call
//! RAYON_NUM_THREADS=1 valgrind --tool=callgrind --dump-instr=no \
//!     target/profiling/examples/attr_call MESH RATIO attributes|positions|meshopt
//! callgrind_annotate --inclusive=yes callgrind.out.PID | grep -E 'qem::simplify|meshopt_simplify'
//! ```
//!
//! The inclusive Ir of `gng3d_qem::simplify` (or `meshopt_simplifyWithAttributes`) is the call's;
//! loading and preparing the model (`mesh::clean::prepare`, as the CLI does) come before it.

extern crate gng3d_qem as qem;

use mesh::Model;
#[path = "common/wedge_buffers.rs"]
mod wedge_buffers;
use wedge_buffers::wedge_buffers;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: attr_call MESH RATIO attributes|positions|meshopt";
    let path = args.get(1).expect(usage);
    let ratio: f64 = args.get(2).expect(usage).parse().expect("RATIO");
    let what = args.get(3).map_or("attributes", String::as_str);
    let loaded = mesh::io::load(std::path::Path::new(path)).unwrap_or_else(|e| panic!("{e}"));
    let model = mesh::clean::prepare(&loaded.into()).0;
    let input_faces = model.mesh.face_count();
    let faces = (input_faces as f64 * ratio) as usize;
    let out = match what {
        "attributes" | "positions" => {
            let model = if what == "positions" {
                Model::from(model.mesh.clone())
            } else {
                model
            };
            let params = qem::QemParams::with_target(qem::Target::Faces(faces));
            let (out, _) = qem::simplify(&model, &params).expect("qem");
            out.mesh.face_count()
        }
        "meshopt" => meshopt_call(&model, faces),
        _ => panic!("{usage}"),
    };
    println!("{what}: {input_faces} -> {out} faces");
}

/// meshoptimizer's call on one vertex per wedge (position and attributes, f32), weights 0.
fn meshopt_call(model: &Model, faces: usize) -> usize {
    let a = model.attributes.as_ref().expect("the model has attributes");
    wedge_buffers(&model.mesh, a).simplify(faces)
}
