//! The one adapter between the viewer and the algorithm crates (gng3d-core, qem, metrics, mesh
//! I/O). Everything the UI and the worker threads need from them goes through this module, so an
//! API change there touches only this file.

use crate::error::{Result, ViewerError};
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
    pub fn new(mesh: &TriMesh, params: &TrainParams) -> Result<Engine> {
        gng3d_core::Trainer::new(mesh, params.clone())
            .map(|trainer| Engine { trainer })
            .map_err(|e| ViewerError::Gng(e.to_string()))
    }

    /// The signal budget this run resolved to (the crate's default when none was given).
    pub fn max_signals(&self) -> u64 {
        self.trainer.stats().max_signals
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
    pub fn reconstruct(&mut self) -> Result<TriMesh> {
        if self.trainer.node_count() < 3 {
            return Err(ViewerError::Gng(
                "the network has fewer than 3 nodes".into(),
            ));
        }
        let params = self.trainer.params().reconstruction.clone();
        let reconstruction = self.trainer.reconstruct(&params);
        if reconstruction.mesh.face_count() == 0 {
            return Err(ViewerError::Gng(
                "the reconstruction has no faces yet".into(),
            ));
        }
        Ok(reconstruction.mesh)
    }
}

/// QEM simplification of `mesh` to `target_vertices` vertices.
pub fn qem_simplify(mesh: &TriMesh, target_vertices: usize) -> Result<TriMesh> {
    let params = qem::QemParams::with_target(qem::Target::Vertices(target_vertices));
    qem::simplify(mesh, &params)
        .map(|(mesh, _report)| mesh)
        .map_err(|e| ViewerError::Qem(e.to_string()))
}

/// Most surface samples per direction for the Hausdorff distance (keeps evaluation to seconds).
const HAUSDORFF_SAMPLES: usize = 200_000;

/// Errors and triangle shape of a simplified mesh against the original: what the plots and the
/// table show, for GNG3D and QEM alike.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Evaluation {
    /// Vertices of the simplified mesh.
    pub vertices: usize,
    /// Faces of the simplified mesh.
    pub faces: usize,
    /// The paper's E_avg: mean squared distance from each original vertex to its nearest
    /// simplified vertex, squared model units.
    pub e_avg: f64,
    /// The paper's E_max: the largest of those squared distances, squared model units.
    pub e_max: f64,
    /// The paper's E_sur, signed like the CLI's: Area(original) − Area(simplified), squared
    /// model units (positive: the simplified mesh lost area).
    pub e_sur: f64,
    /// Symmetric Hausdorff distance, model units (`None` when it could not be computed).
    pub hausdorff: Option<f64>,
    /// Mean over triangles of the smallest interior angle, degrees (60 = all equilateral).
    pub mean_min_angle_degrees: f64,
    /// Share of triangles whose smallest angle is under 30°, 0–1.
    pub below_30_degrees: f64,
}

/// The viewer's one evaluation of `simplified` against `original` (runs on the calling thread;
/// the session calls it from a background job). Hausdorff is sampled Metro-style with
/// min(10 × faces, 200 000) samples per direction.
pub fn evaluate(original: &TriMesh, simplified: &TriMesh) -> Evaluation {
    let (e_avg, e_max) = metrics::vertex_errors(&original.positions, &simplified.positions)
        .map_or((0.0, 0.0), |e| (e.e_avg, e.e_max));
    let faces = original.face_count().max(simplified.face_count());
    let hausdorff_params =
        metrics::HausdorffParams::with_samples((faces * 10).min(HAUSDORFF_SAMPLES));
    let quality = metrics::triangle_quality(simplified);
    Evaluation {
        vertices: simplified.vertex_count(),
        faces: simplified.face_count(),
        e_avg,
        e_max,
        e_sur: metrics::surface_error(original, simplified).e_sur,
        hausdorff: metrics::hausdorff(original, simplified, &hausdorff_params)
            .ok()
            .map(|h| h.max),
        mean_min_angle_degrees: quality.mean_min_angle_degrees,
        below_30_degrees: quality.below_30_degrees,
    }
}

/// E_avg/E_max (squared model units) of the live network's nodes against the original
/// vertices, for the live plot; `None` without nodes.
pub fn network_errors(original: &TriMesh, nodes: &[glam::Vec3]) -> Option<(f64, f64)> {
    metrics::vertex_errors(&original.positions, nodes).map(|e| (e.e_avg, e.e_max))
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
pub fn load_mesh(path: &Path) -> Result<Loaded> {
    let loaded = mesh::io::load(path).map_err(|e| ViewerError::Load {
        path: path.to_path_buf(),
        // The mesh crate's message already starts with the file name.
        message: e
            .to_string()
            .trim_start_matches(&format!("{}: ", path.display()))
            .to_string(),
    })?;
    let mut warnings: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    let (mesh, report) = mesh::clean::prepare(&loaded.mesh);
    if report.welded_vertices > 0 || report.unreferenced_vertices > 0 {
        warnings.push(format!(
            "cleaned: {} vertices welded, {} unreferenced removed",
            report.welded_vertices, report.unreferenced_vertices
        ));
    }
    if mesh.face_count() == 0 {
        return Err(ViewerError::Load {
            path: path.to_path_buf(),
            message: "the mesh has no usable faces".into(),
        });
    }
    Ok(Loaded { mesh, warnings })
}

/// Save a mesh; the format follows the extension (obj, ply, stl).
pub fn save_mesh(mesh: &TriMesh, path: &Path) -> Result<()> {
    mesh::io::save(mesh, path).map_err(|e| ViewerError::Save {
        path: path.to_path_buf(),
        message: e
            .to_string()
            .trim_start_matches(&format!("{}: ", path.display()))
            .to_string(),
    })
}

/// The built-in model shown without a file argument.
pub fn default_model() -> (String, TriMesh) {
    ("blob (procedural)".into(), mesh::procedural::blob())
}
