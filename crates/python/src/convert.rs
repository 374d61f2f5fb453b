//! numpy in and out: any array-like becomes the mesh crate's `TriMesh` through the loader's own
//! checks (`mesh::io::from_arrays`), and results become float64 / int64 arrays.

use glam::Vec3;
use mesh::TriMesh;
use mesh::error::{MeshError, MeshWarning};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::path::Path;

/// `value` as a numpy array (no copy when it already is one), with its dtype kind and shape.
fn as_array<'py>(
    value: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<(Bound<'py, PyAny>, String, Vec<usize>)> {
    let numpy = value.py().import("numpy")?;
    let array = numpy.call_method1("asarray", (value,)).map_err(|e| {
        PyValueError::new_err(format!(
            "{what} must be an array of shape (n, 3): {}",
            e.value(value.py())
        ))
    })?;
    let kind: String = array.getattr("dtype")?.getattr("kind")?.extract()?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    Ok((array, kind, shape))
}

/// The rows of an (n, 3) array-like, or a ValueError naming `what` and the shape it has. An
/// empty array of any shape is zero rows (the mesh checks then say what is missing).
fn checked_shape(shape: &[usize], what: &str, columns: &str) -> PyResult<usize> {
    match shape {
        [n, 3] => Ok(*n),
        _ if shape.contains(&0) => Ok(0),
        _ => Err(PyValueError::new_err(format!(
            "{what} must have shape (n, 3) ({columns}), got shape ({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ))),
    }
}

/// Vertex positions from any array-like of shape (n, 3): float32 arrays are read as they are,
/// other numbers through float64; strided (non-contiguous) arrays are read in place. Returns
/// them relative to `origin`, or when `None` to the origin that `mesh::io::recentre` chooses
/// (zero unless the points lie so far from their coordinates' origin that f32 would move them
/// by more than 1e-6 of their extent: georeferenced data), and the origin used.
pub fn positions(
    value: &Bound<'_, PyAny>,
    what: &str,
    origin: Option<glam::DVec3>,
) -> PyResult<(Vec<Vec3>, glam::DVec3)> {
    let (array, kind, shape) = as_array(value, what)?;
    let rows = checked_shape(&shape, what, "x, y, z per vertex")?;
    if rows == 0 {
        return Ok((Vec::new(), origin.unwrap_or_default()));
    }
    if !matches!(kind.as_str(), "f" | "i" | "u") {
        return Err(PyValueError::new_err(format!(
            "{what} must be numbers, got dtype {}",
            array.getattr("dtype")?.str()?
        )));
    }
    if let Ok(a) = array.extract::<PyReadonlyArray2<'_, f32>>()
        && origin.is_none_or(|o| o == glam::DVec3::ZERO)
    {
        let positions = a
            .as_array()
            .rows()
            .into_iter()
            .map(|r| Vec3::new(r[0], r[1], r[2]))
            .collect();
        return Ok((positions, glam::DVec3::ZERO));
    }
    let array = array.call_method1("astype", ("float64",))?;
    let a: PyReadonlyArray2<'_, f64> = array.extract()?;
    let points: Vec<glam::DVec3> = a
        .as_array()
        .rows()
        .into_iter()
        .map(|r| glam::DVec3::new(r[0], r[1], r[2]))
        .collect();
    Ok(mesh::io::recentre(&points, origin))
}

/// Triangles from any integer array-like of shape (m, 3), as signed indices (range-checked by
/// `mesh::io::from_arrays`).
pub fn triangles(value: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<[i64; 3]>> {
    let (array, kind, shape) = as_array(value, what)?;
    let rows = checked_shape(&shape, what, "three vertex indices per triangle")?;
    if rows == 0 {
        return Ok(Vec::new());
    }
    match kind.as_str() {
        "i" => {
            let a: PyReadonlyArray2<'_, i64> = match array.extract() {
                Ok(a) => a,
                Err(_) => array.call_method1("astype", ("int64",))?.extract()?,
            };
            Ok(a.as_array()
                .rows()
                .into_iter()
                .map(|r| [r[0], r[1], r[2]])
                .collect())
        }
        "u" => {
            let a: PyReadonlyArray2<'_, u64> = match array.extract() {
                Ok(a) => a,
                Err(_) => array.call_method1("astype", ("uint64",))?.extract()?,
            };
            let signed = |i: u64| i64::try_from(i).unwrap_or(i64::MAX);
            Ok(a.as_array()
                .rows()
                .into_iter()
                .map(|r| [signed(r[0]), signed(r[1]), signed(r[2])])
                .collect())
        }
        _ => Err(PyValueError::new_err(format!(
            "{what} must be integer vertex indices, got dtype {}",
            array.getattr("dtype")?.str()?
        ))),
    }
}

/// A `MeshError` as the Python exception a user expects: `FileNotFoundError` / `OSError` for
/// files that cannot be read or written, `ValueError` for content (the loader's sentence).
pub fn mesh_error(e: MeshError) -> PyErr {
    match &e {
        MeshError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            PyFileNotFoundError::new_err(e.to_string())
        }
        MeshError::Io { .. } | MeshError::Write { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A mesh from two array-likes, checked and repaired as the loader checks a file
/// (`mesh::io::from_arrays`; `name` stands for the file in messages). Loader warnings (dropped
/// degenerate or duplicate faces) are returned for the caller to raise as Python warnings.
pub fn mesh_from(
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    name: &str,
    origin: Option<glam::DVec3>,
) -> PyResult<(TriMesh, Vec<MeshWarning>, glam::DVec3)> {
    let (positions, origin) = positions(vertices, "vertices", origin)?;
    let triangles = triangles(faces, "faces")?;
    let loaded =
        mesh::io::from_arrays(positions, triangles, Path::new(name)).map_err(mesh_error)?;
    Ok((loaded.mesh, loaded.warnings, origin))
}

/// Positions as a float64 (n, 3) array, moved by `origin` (in f64) back to their coordinates.
pub fn positions_array<'py>(
    py: Python<'py>,
    positions: &[Vec3],
    origin: glam::DVec3,
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = positions
        .iter()
        .flat_map(|p| {
            if origin == glam::DVec3::ZERO {
                p.as_dvec3().to_array()
            } else {
                (p.as_dvec3() + origin).to_array()
            }
        })
        .collect();
    Array2::from_shape_vec((positions.len(), 3), flat)
        .expect("three coordinates per position")
        .into_pyarray(py)
}

/// Index tuples (triangles or edges) as an int64 (m, K) array.
pub fn index_array<'py, const K: usize>(
    py: Python<'py>,
    rows: &[[u32; K]],
) -> Bound<'py, PyArray2<i64>> {
    let flat: Vec<i64> = rows.iter().flatten().map(|&i| i as i64).collect();
    Array2::from_shape_vec((rows.len(), K), flat)
        .expect("K indices per row")
        .into_pyarray(py)
}

/// A mesh as the `(vertices, faces)` tuple of numpy arrays.
/// `origin` (a loaded file's `LoadedMesh::origin`) is added to the positions in f64.
pub fn mesh_tuple<'py>(
    py: Python<'py>,
    mesh: &TriMesh,
    origin: glam::DVec3,
) -> PyResult<Bound<'py, PyTuple>> {
    PyTuple::new(
        py,
        [
            positions_array(py, &mesh.positions, origin).into_any(),
            index_array(py, &mesh.triangles).into_any(),
        ],
    )
}
