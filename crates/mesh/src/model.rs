//! [`Model`]: what a front end loads, simplifies and saves — the mesh with the attributes of its
//! corners, the materials they name and the origin its positions are relative to.

use crate::TriMesh;
use crate::attributes::{Attributes, Materials};
use glam::DVec3;

/// A mesh with everything a file gives it besides positions and triangles. The one value that
/// flows model → algorithm → model through every front end (`gng3d-job`'s run).
///
/// ```
/// let model = gng3d_mesh::Model::from(gng3d_mesh::procedural::icosphere(1));
/// assert_eq!(model.mesh.vertex_count(), 42);
/// assert!(model.attributes.is_none() && model.materials.is_none());
/// ```
#[derive(Debug, Clone, Default)]
pub struct Model {
    /// Positions (relative to [`Model::origin`]) and triangles.
    pub mesh: TriMesh,
    /// Normals, texture coordinates, colours and materials of the corners, when there are any
    /// (never an empty set: `None` then).
    pub attributes: Option<Attributes>,
    /// The materials the attributes name (material libraries, glTF materials and images).
    pub materials: Option<Materials>,
    /// Where the positions' origin lies in the file's coordinates (`io::LoadedMesh::origin`):
    /// zero unless the model was recentred for `f32` precision; writers add it back.
    pub origin: DVec3,
}

impl From<TriMesh> for Model {
    /// A model of positions and triangles only, at the origin.
    fn from(mesh: TriMesh) -> Model {
        Model {
            mesh,
            ..Model::default()
        }
    }
}

impl From<crate::io::LoadedMesh> for Model {
    /// The model a file holds: its mesh, attributes (`None` when the file has none), materials
    /// and origin, as stored (its warnings and file names aside).
    fn from(loaded: crate::io::LoadedMesh) -> Model {
        Model {
            mesh: loaded.mesh,
            attributes: loaded.attributes.filter(|a| !a.is_empty()),
            materials: loaded.materials,
            origin: loaded.origin,
        }
    }
}

impl Model {
    /// A model of `mesh` with `attributes` and `materials`, at the origin.
    pub fn new(
        mesh: TriMesh,
        attributes: Option<Attributes>,
        materials: Option<Materials>,
    ) -> Model {
        Model {
            mesh,
            attributes,
            materials,
            origin: DVec3::ZERO,
        }
    }

    /// The same model with `mesh` and `attributes` in place of its own (materials and origin
    /// kept): what an algorithm returns for its input.
    pub fn with_mesh(&self, mesh: TriMesh, attributes: Option<Attributes>) -> Model {
        Model {
            mesh,
            attributes,
            materials: self.materials.clone(),
            origin: self.origin,
        }
    }

    /// The model without its attributes and materials: positions and triangles only, as if the
    /// file had none.
    pub fn without_attributes(self) -> Model {
        Model {
            attributes: None,
            materials: None,
            ..self
        }
    }
}
