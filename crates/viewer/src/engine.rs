//! The one adapter between the viewer and the algorithm crates (gng3d-core, qem, metrics, mesh
//! I/O). Everything the UI and the worker threads need from them goes through this module, so an
//! API change there touches only this file.

use glam::Vec3;
use mesh::TriMesh;
use std::path::Path;

/// GNG3D parameters as edited in the UI.
pub type TrainParams = gng3d_core::GngParams;
/// Where GNG training signals come from.
pub type SignalSourceKind = gng3d_core::SignalSource;
/// A cheap copy of the live network: node positions and GNG edges.
pub type NetworkSnapshot = gng3d_core::Snapshot;

/// Every signal source, in menu order, with its label.
pub const SIGNAL_SOURCES: [(SignalSourceKind, &str); 2] = [
    (SignalSourceKind::Vertices, "original vertices (paper)"),
    (SignalSourceKind::Surface, "surface samples"),
];

/// Label of a signal source.
pub fn signal_source_label(source: SignalSourceKind) -> &'static str {
    SIGNAL_SOURCES
        .iter()
        .find(|(s, _)| *s == source)
        .map_or("?", |(_, l)| l)
}

/// Default parameters for `target_vertices` nodes.
pub fn default_params(target_vertices: usize) -> TrainParams {
    TrainParams::for_target(target_vertices)
}

/// A running GNG3D training session.
pub struct Engine {
    trainer: gng3d_core::Trainer,
}

impl Engine {
    /// Start training on `mesh` (already cleaned) with `params`.
    pub fn new(mesh: &TriMesh, params: &TrainParams) -> Result<Engine, String> {
        gng3d_core::Trainer::new(mesh, params.clone())
            .map(|trainer| Engine { trainer })
            .map_err(|e| e.to_string())
    }

    /// Present up to `signals` more training signals; returns how many were presented.
    pub fn step(&mut self, signals: u64) -> u64 {
        self.trainer.step(signals)
    }

    /// Whether training has reached its budget or limits.
    pub fn is_finished(&self) -> bool {
        self.trainer.is_finished()
    }

    /// Signals presented so far.
    pub fn signals(&self) -> u64 {
        self.trainer.signals()
    }

    /// Copy of the network for display.
    pub fn snapshot(&self) -> NetworkSnapshot {
        self.trainer.snapshot()
    }

    /// Build a triangle mesh from the current network.
    pub fn reconstruct(&mut self) -> Result<TriMesh, String> {
        if self.trainer.node_count() < 3 {
            return Err("the network has fewer than 3 nodes".into());
        }
        let params = self.trainer.params().reconstruction.clone();
        let reconstruction = self.trainer.reconstruct(&params);
        if reconstruction.mesh.face_count() == 0 {
            return Err("the reconstruction has no faces yet".into());
        }
        Ok(reconstruction.mesh)
    }
}

/// QEM simplification of `mesh` to `target_vertices` vertices.
pub fn qem_simplify(mesh: &TriMesh, target_vertices: usize) -> Result<TriMesh, String> {
    let params = qem::QemParams::with_target(qem::Target::Vertices(target_vertices));
    qem::simplify(mesh, &params)
        .map(|(mesh, _report)| mesh)
        .map_err(|e| e.to_string())
}

/// The paper's E_avg/E_max (squared model units) of `original` vertices against `simplified`.
pub fn vertex_errors(original: &[Vec3], simplified: &[Vec3]) -> Option<(f64, f64)> {
    metrics::vertex_errors(original, simplified).map(|e| (e.e_avg, e.e_max))
}

/// The paper's E_sur = |Area(original) − Area(simplified)|, in squared model units.
pub fn surface_error(original: &TriMesh, simplified: &TriMesh) -> f64 {
    metrics::surface_error(original, simplified).e_sur_abs
}

/// Most surface samples per direction for the Hausdorff distance (keeps evaluation to seconds).
const HAUSDORFF_SAMPLES: usize = 200_000;

/// Symmetric Hausdorff distance (model units), Metro-style sampling, `None` if it fails.
pub fn hausdorff(original: &TriMesh, simplified: &TriMesh) -> Option<f64> {
    let faces = original.face_count().max(simplified.face_count());
    let params = metrics::HausdorffParams::with_samples((faces * 10).min(HAUSDORFF_SAMPLES));
    metrics::hausdorff(original, simplified, &params)
        .ok()
        .map(|h| h.max)
}

/// A mesh loaded from disk plus non-fatal warnings.
pub struct Loaded {
    /// The cleaned mesh the algorithms see (welded, no degenerate/duplicate faces, no
    /// unreferenced vertices).
    pub mesh: TriMesh,
    /// Human-readable loader and cleaning notes.
    pub warnings: Vec<String>,
}

/// Load a mesh file (OBJ/PLY/STL) and clean it for display and training.
pub fn load_mesh(path: &Path) -> Result<Loaded, String> {
    let loaded = mesh::io::load(path).map_err(|e| e.to_string())?;
    let mut warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    let (mesh, report) = mesh::clean::prepare(&loaded.mesh);
    if report.welded_vertices > 0 || report.unreferenced_vertices > 0 {
        warnings.push(format!(
            "cleaned: {} vertices welded, {} unreferenced removed",
            report.welded_vertices, report.unreferenced_vertices
        ));
    }
    if mesh.face_count() == 0 {
        return Err(format!("{}: the mesh has no usable faces", path.display()));
    }
    Ok(Loaded { mesh, warnings })
}

/// Save a mesh; the format follows the extension (obj, ply, stl).
pub fn save_mesh(mesh: &TriMesh, path: &Path) -> Result<(), String> {
    mesh::io::save(mesh, path).map_err(|e| e.to_string())
}

/// The built-in model shown without a file argument.
pub fn default_model() -> (String, TriMesh) {
    ("blob (procedural)".into(), mesh::procedural::blob())
}
