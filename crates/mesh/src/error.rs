//! Typed errors and warnings for mesh loading, saving and validation.

use std::fmt;
use std::path::PathBuf;

/// Everything that can go wrong reading, validating or writing a mesh file; every variant names
/// the file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The file is missing or could not be read.
    #[error("{}: cannot read file", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying I/O error.
        source: std::io::Error,
    },
    /// The extension is not one of obj, ply, stl, gltf, glb (case-insensitive).
    #[error("{}: unknown mesh format (expected .obj, .ply, .stl, .gltf or .glb)", path.display())]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file content is malformed.
    #[error("{}: parse error at {location}: {message}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// Where: "line N", "vertex N", "face N", "header", "byte N", ...
        location: String,
        /// What is wrong.
        message: String,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("{}: vertex {vertex} has a non-finite coordinate", path.display())]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Zero-based vertex index.
        vertex: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("{}: face {face} refers to vertex {index}, but there are only {vertex_count} vertices", path.display())]
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// Zero-based face index (face record in the file).
        face: usize,
        /// The offending (zero-based) vertex index.
        index: i64,
        /// Number of vertices in the file.
        vertex_count: usize,
    },
    /// An OBJ face refers to a vertex that does not exist (yet): `index` is the number as
    /// written in the file (1-based, or negative counting back from the last vertex so far).
    #[error(
        "{}: line {line}: face refers to vertex {index}, but {vertex_count} vertices are defined \
         before it (OBJ indices are 1-based; negative ones count back from the last vertex)",
        path.display()
    )]
    ObjIndex {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// The index as written in the file.
        index: i64,
        /// Vertices defined before that line.
        vertex_count: usize,
    },
    /// The file has no vertices.
    #[error("{}: the mesh has no vertices", path.display())]
    Empty {
        /// The file.
        path: PathBuf,
    },
    /// The file has vertices but no faces (a point cloud).
    #[error("{}: the mesh has {vertex_count} vertices but no faces (point cloud)", path.display())]
    NoFaces {
        /// The file.
        path: PathBuf,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A glTF file whose primitives are all points or lines (modes 0 to 3): vertices, but no
    /// triangles.
    #[error(
        "{}: the file has {vertex_count} vertices but only point/line primitives ({primitives}) \
         and no triangles",
        path.display()
    )]
    NoTriangles {
        /// The file.
        path: PathBuf,
        /// Vertices of the point and line primitives.
        vertex_count: usize,
        /// Number of point and line primitives.
        primitives: usize,
    },
    /// Writing the output failed.
    #[error("{}: cannot write mesh: {message}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl MeshError {
    /// A [`MeshError::Parse`] for `path` at `location`.
    pub fn parse(
        path: impl Into<PathBuf>,
        location: impl Into<String>,
        message: impl Into<String>,
    ) -> MeshError {
        MeshError::Parse {
            path: path.into(),
            location: location.into(),
            message: message.into(),
        }
    }
}

/// Non-fatal problems found while loading or saving: what was dropped, repaired or not kept.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum MeshWarning {
    /// Faces with a repeated vertex index, dropped.
    DegenerateFaces {
        /// How many were dropped.
        count: usize,
    },
    /// Faces with the same vertex set as an earlier face (any rotation or orientation), dropped.
    DuplicateFaces {
        /// How many were dropped.
        count: usize,
    },
    /// Polygons with more than three corners, fan-triangulated.
    PolygonsTriangulated {
        /// How many polygons were split.
        count: usize,
    },
    /// Faces with fewer than three corners (points/lines), ignored.
    ShortFaces {
        /// How many were ignored.
        count: usize,
    },
    /// A binary STL whose size is not `84 + 50 × header_triangles`: only the header's count of
    /// triangles was read, the rest of the file was ignored.
    StlSizeMismatch {
        /// Triangle count stored in the header.
        header_triangles: u64,
        /// Size of the file in bytes.
        file_bytes: u64,
    },
    /// Data in the file that this project does not read (e.g. a PLY vertex property
    /// `quality`, OBJ `vp` records); it is not carried to any output.
    IgnoredData {
        /// What was ignored, as the file names it (e.g. "PLY vertex property quality").
        what: String,
    },
    /// Some triangle corners lack an attribute that others have (an OBJ face corner without
    /// `vt` in a file with texture coordinates); they were given zeros.
    MissingCornerAttribute {
        /// The attribute (`uv0`, `normals`, `colors`).
        attribute: String,
        /// Corners (or vertices) without it.
        count: usize,
    },
    /// Attributes of the mesh that the output format or the method cannot keep, dropped.
    AttributesDropped {
        /// The attributes dropped (e.g. "uv0, materials").
        attributes: String,
        /// Why (e.g. "STL stores positions only").
        reason: String,
    },
    /// A material library or a texture it names could not be copied next to the output.
    MaterialFileNotCopied {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// Values read in another range than their type declares (8-bit colours in a float or a
    /// 32-bit field), converted: what was assumed, in words.
    ValuesReinterpreted {
        /// What was read how (e.g. "OBJ colours up to 255 read as 0-255").
        what: String,
    },
    /// A file the model names (a material library, a texture, an image) that the containment
    /// rule refuses to read or write: outside the model's folder, not a regular file, too
    /// large, or a name that would leave the output's folder. Nothing of it was read or written.
    ReferenceRefused {
        /// What the model names, as it names it (e.g. `mtllib ../../etc/passwd`).
        reference: String,
        /// Why it was refused.
        reason: String,
    },
    /// A file the input names (a texture) was copied beside the output under another name,
    /// because a different file of its name was already there; the output names the copy.
    SideFileRenamed {
        /// The name the input gives it.
        wanted: String,
        /// The name it was written under.
        written: String,
    },
}

impl fmt::Display for MeshWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshWarning::DegenerateFaces { count } => {
                write!(
                    f,
                    "dropped {count} degenerate face(s) with a repeated vertex"
                )
            }
            MeshWarning::DuplicateFaces { count } => {
                write!(f, "dropped {count} duplicate face(s)")
            }
            MeshWarning::PolygonsTriangulated { count } => {
                write!(
                    f,
                    "fan-triangulated {count} polygon(s) with more than 3 corners"
                )
            }
            MeshWarning::ShortFaces { count } => {
                write!(f, "ignored {count} face(s) with fewer than 3 corners")
            }
            MeshWarning::StlSizeMismatch {
                header_triangles,
                file_bytes,
            } => {
                let records = file_bytes.saturating_sub(84) as f64 / 50.0;
                write!(
                    f,
                    "binary STL header says {header_triangles} triangles ({} bytes), but the file \
                     has {file_bytes} bytes ({records} records); read {header_triangles} and \
                     ignored the rest",
                    84 + 50 * header_triangles
                )
            }
            MeshWarning::IgnoredData { what } => {
                write!(f, "ignored {what} (not read, not written to any output)")
            }
            MeshWarning::MissingCornerAttribute { attribute, count } => {
                write!(
                    f,
                    "{count} corner(s) lack {attribute} that other corners have; set to zero"
                )
            }
            MeshWarning::AttributesDropped { attributes, reason } => {
                write!(f, "dropped {attributes}: {reason}")
            }
            MeshWarning::MaterialFileNotCopied { path, reason } => {
                write!(f, "material file {} not copied: {reason}", path.display())
            }
            MeshWarning::ValuesReinterpreted { what } => write!(f, "{what}"),
            MeshWarning::ReferenceRefused { reference, reason } => {
                write!(f, "{reference} not read or written: {reason}")
            }
            MeshWarning::SideFileRenamed { wanted, written } => write!(
                f,
                "a different file named {wanted} is already beside the output; the input's is \
                 written as {written} and the output names that"
            ),
        }
    }
}
