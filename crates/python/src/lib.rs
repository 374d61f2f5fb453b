//! `gng3d._gng3d`, the native module of the `gng3d` Python package (PyO3): numpy meshes in and
//! out of the workspace's libraries, with the options checked by the libraries themselves and
//! the GIL released while they work. The package (python/gng3d) re-exports it; its docstrings
//! are the doc comments here.

mod batch;
mod convert;
mod file;
mod keywords;
mod partition;
mod run;
mod trainer;

use convert::{mesh_error, mesh_from};
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pyo3::types::PyTuple;
use std::path::PathBuf;

pyo3::create_exception!(
    gng3d,
    Gng3dWarning,
    PyUserWarning,
    "What kept a result from being exactly what was asked for (the CLI's `warning:` lines)."
);

/// Raises each sentence as a `gng3d.Gng3dWarning`.
fn warn_all(py: Python<'_>, messages: &[String]) -> PyResult<()> {
    let category = py.get_type::<Gng3dWarning>();
    for m in messages {
        PyErr::warn(py, &category, &std::ffi::CString::new(m.as_str())?, 1)?;
    }
    Ok(())
}

/// Raises each of `messages` as a `gng3d.Gng3dWarning` that names what it is about
/// (`subject: message`, as the CLI's `warning:` lines name the file).
fn warn_about(
    py: Python<'_>,
    subject: impl std::fmt::Display,
    messages: &[impl std::fmt::Display],
) -> PyResult<()> {
    let sentences: Vec<String> = messages.iter().map(|m| format!("{subject}: {m}")).collect();
    warn_all(py, &sentences)
}

/// A JSON value as the Python object `json.loads` makes of it.
pub(crate) fn to_python<'py>(
    py: Python<'py>,
    value: &serde_json::Value,
) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?
        .call_method1("loads", (value.to_string(),))
}

/// The result of :func:`gng3d.simplify` and :meth:`gng3d.Trainer.mesh`.
///
/// Attributes:
///     vertices: float64 array of shape (n, 3).
///     faces: int64 array of shape (m, 3), counter-clockwise seen from outside.
///     report: dict with the fields of ``gng3d simplify --json`` (``warnings`` included, each
///         with its ``message``).
///
/// Unpacks as a pair: ``vertices, faces = gng3d.simplify(...)``.
#[pyclass(module = "gng3d", frozen)]
struct SimplifyResult {
    vertices: Py<PyAny>,
    faces: Py<PyAny>,
    report: Py<PyAny>,
}

#[pymethods]
impl SimplifyResult {
    /// float64 array of shape (n, 3): the simplified mesh's vertex positions.
    #[getter]
    fn vertices(&self, py: Python<'_>) -> Py<PyAny> {
        self.vertices.clone_ref(py)
    }

    /// int64 array of shape (m, 3): the simplified mesh's triangles.
    #[getter]
    fn faces(&self, py: Python<'_>) -> Py<PyAny> {
        self.faces.clone_ref(py)
    }

    /// dict: the fields of ``gng3d simplify --json``.
    #[getter]
    fn report(&self, py: Python<'_>) -> Py<PyAny> {
        self.report.clone_ref(py)
    }

    fn __len__(&self) -> usize {
        2
    }

    fn __getitem__(&self, py: Python<'_>, index: isize) -> PyResult<Py<PyAny>> {
        match index {
            0 | -2 => Ok(self.vertices.clone_ref(py)),
            1 | -1 => Ok(self.faces.clone_ref(py)),
            _ => Err(pyo3::exceptions::PyIndexError::new_err(
                "SimplifyResult unpacks as (vertices, faces)",
            )),
        }
    }

    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pair = PyTuple::new(py, [self.vertices.clone_ref(py), self.faces.clone_ref(py)])?;
        Ok(pair.as_any().try_iter()?.into_any())
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let report = self.report.bind(py);
        let get = |k: &str| -> PyResult<String> { Ok(report.get_item(k)?.str()?.to_string()) };
        Ok(format!(
            "SimplifyResult(method={}, vertices={}, faces={}, seconds={}, warnings={})",
            report.get_item("method")?.repr()?,
            get("vertices")?,
            get("faces")?,
            get("seconds")?,
            report.get_item("warnings")?.len()?
        ))
    }
}

impl SimplifyResult {
    /// The Python result of a finished run; its warnings are raised as `Gng3dWarning`s.
    /// `origin`: where the input's positions were recentred from (zero for most inputs).
    fn new(
        py: Python<'_>,
        outcome: &job::Outcome,
        origin: glam::DVec3,
    ) -> PyResult<SimplifyResult> {
        warn_all(py, &outcome.warnings)?;
        let report = outcome.summary.to_json(&outcome.warnings);
        SimplifyResult::build(py, &outcome.model.mesh, &report, origin)
    }

    /// The Python result of `mesh` and `report` (warnings already raised).
    fn build(
        py: Python<'_>,
        mesh: &mesh::TriMesh,
        report: &serde_json::Value,
        origin: glam::DVec3,
    ) -> PyResult<SimplifyResult> {
        Ok(SimplifyResult {
            vertices: convert::positions_array(py, &mesh.positions, origin)
                .into_any()
                .unbind(),
            faces: convert::index_array(py, &mesh.triangles)
                .into_any()
                .unbind(),
            report: to_python(py, report)?.unbind(),
        })
    }
}

/// The input of a run: checked as the loader checks a file, then welded and cleaned as the CLI
/// prepares what it loads (`mesh::clean::prepare`) unless `weld` is false. Float64 vertices far
/// from their coordinates' origin are recentred first (the origin is returned, for the output).
fn prepared(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    weld: bool,
) -> PyResult<(mesh::TriMesh, glam::DVec3)> {
    let (input, warnings, origin) = mesh_from(vertices, faces, "input", None)?;
    warn_about(py, "input", &warnings)?;
    if !weld {
        return Ok((input, origin));
    }
    Ok((
        py.detach(|| mesh::clean::prepare(&input.into()).0.mesh),
        origin,
    ))
}

/// Simplify a triangle mesh with QEM (default), GNG3D-Q or the paper's GNG3D.
///
/// Args:
///     vertices: array-like of shape (n, 3), any real dtype (read as float32, as the mesh
///         files are).
///     faces: integer array-like of shape (m, 3), zero-based vertex indices.
///     vertices_target: the output's vertex count (GNG3D gives exactly this many).
///     faces_target: the output's face count (method="qem" only).
///     ratio: the share of the input's vertices to keep, in (0, 1], for every method
///         (0.1 keeps a tenth of the vertices), as the CLI's ``--ratio`` is for every method.
///         It is *not* a reduction (fast_simplification's ``target_reduction=0.9`` is
///         ``ratio=0.1`` here) and not a share of faces (the CLI's ``--face-ratio``, QEM only:
///         use ``faces_target`` for that). Give exactly one of the three targets.
///     method: "qem" (Garland-Heckbert; the default of every front end, ``gng3d.DEFAULT_METHOD``:
///         the closest to the surface of the simplifiers measured, and it keeps attributes),
///         "gng" (GNG3D-Q, the CLI's ``--method gng``: exactly N vertices, even triangles) or
///         "paper" (the published GNG3D: node placement, 30 epochs).
///     time_limit: GNG3D's most seconds for the whole run (steps are left out to keep it;
///         each is a warning); the vertex count stays exact.
///     seed: GNG3D's random seed, an int in 0 to 2**64 - 1 (the same seed gives the same
///         mesh as ``gng3d simplify --method gng --seed S``). Default (None):
///         ``gng3d.DEFAULT_SEED``, the library's default and the CLI's, so a call without a
///         seed gives the mesh of ``gng3d simplify`` (and ``gng3d batch``) without one.
///     weld: weld exact duplicate positions and drop degenerate faces and unreferenced
///         vertices first, as the CLI does (``weld=False`` is its ``--no-weld``).
///     placement, flips, refit, relax, deviation_repair, epochs, signals, oversample,
///         detail_rounds, shape, creases: GNG3D's variant, as the CLI's flags (``flips=False``
///         is ``--no-flips``, ``placement="node"`` is ``--placement node``, ``shape="fit"`` is
///         ``--shape``: rounder triangles at about the same distance, ``shape="round"``
///         rounder still for 1.05-1.5× QEM's mean distance, docs/notes/shape.md;
///         ``creases=True`` is ``--creases``: a CAD part's sharp edges kept where that is
///         closer, docs/notes/creases.md).
///     attributes: "keep" (default) or "drop": :func:`simplify_file` carries the file's
///         normals, texture coordinates, colours and materials, or drops them (positions only).
///     threshold: QEM's pair distance threshold in model units (0: edges only).
///     lock_border: QEM: never contract the vertices on the input's border edges.
///     max_error: QEM's stop rule as a share of the bounding-box diagonal (alone, without a
///         target, it simplifies as far as it allows).
///     threads: most threads the run uses, 1 to ``gng3d.MAX_THREADS`` (256; default: the
///         machine's cores, GNG3D's training at most 4); ``threads=1`` for many runs side by
///         side (:mod:`gng3d.batch` does). The mesh is the same for any count, except QEM on
///         500,000 faces or more (split into parts on more than one thread).
///
/// Returns:
///     SimplifyResult: ``.vertices`` (float64, (n, 3)), ``.faces`` (int64, (m, 3)),
///     ``.report`` (dict, the fields of ``gng3d simplify --json``); it unpacks as
///     ``(vertices, faces)``. What kept the result from the request (a target above what
///     the mesh holds, a time limit) is in ``report["warnings"]`` and raised as
///     :class:`gng3d.Gng3dWarning`.
///
/// Raises:
///     ValueError: bad input (wrong shape, NaN, an index out of range, no faces) or options,
///         with the library's message (or one naming the keyword, e.g. ``threads``).
///     RuntimeError: a run that ended without a mesh (e.g. a time limit too short to train).
///     KeyboardInterrupt: Ctrl-C, within a fraction of a second, with either method (GNG3D's
///         training and the steps after it, QEM's contractions).
///
/// The GIL is released while the mesh is simplified, so threads run in parallel.
///
/// Example:
///     >>> import gng3d, numpy as np
///     >>> v, f = gng3d.load("bunny.ply")                      # doctest: +SKIP
///     >>> result = gng3d.simplify(v, f, ratio=0.1, seed=1)    # doctest: +SKIP
///     >>> result.report["vertices"] == round(0.1 * len(v))    # doctest: +SKIP
///     True
///     >>> v2, f2 = gng3d.simplify(v, f, faces_target=5000, method="qem")  # doctest: +SKIP
#[pyfunction]
#[pyo3(signature = (vertices, faces, **options))]
fn simplify(
    py: Python<'_>,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<SimplifyResult> {
    let request = keywords::request(py, "simplify", options, &keywords::KEYWORDS)?;
    let (input, origin) = prepared(py, vertices, faces, request.weld)?;
    let model = mesh::Model {
        origin,
        ..mesh::Model::from(input)
    };
    let outcome = run_job(py, &model, &request)?;
    SimplifyResult::new(py, &outcome, origin)
}

/// The job on `model`, the GIL released, Ctrl-C stopping it (`run::interruptible`).
fn run_job(py: Python<'_>, model: &mesh::Model, request: &job::Request) -> PyResult<job::Outcome> {
    let job = py
        .detach(|| job::Job::new(model, request))
        .map_err(keywords::job_error)?;
    let cancel = job.cancel();
    run::interruptible(py, &cancel, || job.run(&mut ()))?.map_err(keywords::job_error)
}

/// A Python exception of `e`'s type with its message behind `path` ("spot.obj: ..."), unless
/// the message names it already.
pub(crate) fn naming(py: Python<'_>, e: PyErr, path: &std::path::Path) -> PyErr {
    let name = path.display().to_string();
    let message = e.value(py).to_string();
    if message.starts_with(&name) {
        return e;
    }
    let named = PyErr::from_type(e.get_type(py), format!("{name}: {message}"));
    named.set_cause(py, Some(e));
    named
}

/// Simplify a mesh file into another, keeping its normals, texture coordinates, colours and
/// materials, as ``gng3d simplify IN OUT`` does.
///
/// The file is loaded with its attributes and materials (OBJ, PLY, STL, glTF or GLB, by
/// extension), welded and cleaned with them (unless ``weld=False``), simplified with the
/// method's attribute-aware path (QEM keeps them through its contractions and its seams shape
/// the geometry; GNG3D's triangles follow the seams and take their values from the input's
/// surface), and written to ``output`` (format by extension) atomically, as :func:`save`
/// writes. An OBJ output names the input's material libraries, copied next to it with the
/// textures they name (files already there are left alone); a glTF output keeps a glTF
/// input's materials and copies its images.
///
/// Args:
///     input: the mesh file to simplify.
///     output: where the result goes (.obj, .ply, .stl, .gltf, .glb); checked before the
///         input is read.
///     vertices_target, faces_target, ratio, method, time_limit, seed, weld, placement, flips,
///         refit, relax, deviation_repair, epochs, signals, oversample, detail_rounds, shape,
///         creases, threshold, threads: as for :func:`simplify`, which this function's mesh equals for
///         a file without attributes.
///
/// Returns:
///     SimplifyResult: as :func:`simplify` returns it (the output's positions and triangles);
///     its ``.report`` also holds ``input`` and ``output`` (the paths), ``file_vertices``
///     and ``file_faces`` (the input file's vertex records and triangles, as :func:`load`
///     counts them) and ``attributes``, the CLI's ``--json`` object: ``input`` (the input's
///     attributes: ``normals``, ``uv0``, ``uv1``, ``colors``, ``materials``), ``kept`` (those
///     the output was read back with) and ``dropped`` (what was not written or not copied,
///     one sentence each).
///
/// Warnings (:class:`gng3d.Gng3dWarning`, each naming its file): the loader's, the run's (as
/// :func:`simplify`) and each entry of ``attributes["dropped"]`` (an attribute the output
/// format cannot hold, a material file that could not be copied).
///
/// Raises:
///     FileNotFoundError / OSError: the input cannot be read or the output written (its
///         folder missing or read-only); the message names the file.
///     ValueError: a malformed input, an unknown extension or bad options; the message names
///         the file where one is at fault.
///     RuntimeError: a run that ended without a mesh.
///     KeyboardInterrupt: Ctrl-C while simplifying, as for :func:`simplify`; the output is
///         not written then.
///
/// The GIL is released while the file is read, simplified and written.
///
/// Example:
///     >>> r = gng3d.simplify_file("spot.obj", "spot-qem.obj", ratio=0.1, method="qem")  # doctest: +SKIP
///     >>> r.report["attributes"]["kept"]                                                 # doctest: +SKIP
///     ['uv0', 'materials']
#[pyfunction]
#[pyo3(signature = (input, output, **options))]
fn simplify_file(
    py: Python<'_>,
    input: PathBuf,
    output: PathBuf,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<SimplifyResult> {
    let request = keywords::request(py, "simplify_file", options, &keywords::KEYWORDS)?;
    // The output path is checked before reading or simplifying, so a typo costs nothing.
    job::check_output(&output).map_err(keywords::job_error)?;
    // The job's steps one by one (`job::simplify_file`), so that each warning is raised as it
    // comes and Ctrl-C stops the run.
    let loaded = py
        .detach(|| job::load(&input, &request, &[&output]))
        .map_err(keywords::job_error)?;
    warn_about(py, input.display(), &loaded.warnings)?;
    let outcome = run_job(py, &loaded.model, &request).map_err(|e| naming(py, e, &input))?;
    let kept = py
        .detach(|| job::save(&outcome.model, &output))
        .map_err(|e| naming(py, keywords::job_error(e), &output))?;
    warn_about(py, input.display(), &outcome.warnings)?;
    warn_about(py, output.display(), &kept.dropped)?;
    let done = job::FileOutcome {
        outcome,
        kept,
        file_counts: (loaded.file_vertices, loaded.file_faces),
    };
    let mut report = done.to_json();
    if let serde_json::Value::Object(fields) = &mut report {
        let text = |p: &std::path::Path| serde_json::Value::String(p.display().to_string());
        fields.insert("input".into(), text(&input));
        fields.insert("output".into(), text(&output));
        fields.insert("file_vertices".into(), loaded.file_vertices.into());
        fields.insert("file_faces".into(), loaded.file_faces.into());
    }
    SimplifyResult::build(py, &done.outcome.model.mesh, &report, loaded.model.origin)
}

/// The image-space error's keywords of :func:`metrics` as checked parameters: `None` without
/// ``image_error=True`` (then none of the others may be given, as the CLI's ``--image-*``
/// flags need ``--image-error``); the ranges are `metrics::ImageErrorParams::validate`'s, its
/// errors a ValueError naming the keyword.
fn image_params(
    image_error: bool,
    size: Option<u32>,
    threshold: Option<f64>,
    flat: bool,
    images: bool,
) -> PyResult<Option<metrics::ImageErrorParams>> {
    if !image_error {
        let given = [
            ("image_size", size.is_some()),
            ("image_threshold", threshold.is_some()),
            ("image_flat", flat),
            ("images", images),
        ];
        if let Some((name, _)) = given.iter().find(|(_, given)| *given) {
            return Err(PyValueError::new_err(format!(
                "{name} applies with image_error=True only"
            )));
        }
        return Ok(None);
    }
    let defaults = metrics::ImageErrorParams::default();
    let params = metrics::ImageErrorParams {
        size: size.unwrap_or(defaults.size),
        threshold: threshold.unwrap_or(defaults.threshold),
        flat_shading: flat,
        ..defaults
    };
    params.validate().map_err(|e| match &e {
        metrics::MetricsError::Parameter { name, message } => {
            let keyword = match *name {
                "size" => "image_size",
                "threshold" => "image_threshold",
                other => other,
            };
            PyValueError::new_err(format!("{keyword}: {message}"))
        }
        _ => PyValueError::new_err(e.to_string()),
    })?;
    Ok(Some(params))
}

/// Each view's renderings as a dict of numpy arrays (see :func:`metrics`, ``images=True``).
fn view_images<'py>(
    py: Python<'py>,
    views: &[metrics::ViewImages],
) -> PyResult<Bound<'py, pyo3::types::PyList>> {
    use numpy::IntoPyArray;
    use numpy::ndarray::{Array2, Array3};
    let list = pyo3::types::PyList::empty(py);
    for view in views {
        let n = view.size as usize;
        let colours = |pixels: &[[f32; 3]]| {
            Array3::from_shape_vec((n, n, 3), pixels.iter().flatten().copied().collect())
                .map_err(|e| PyValueError::new_err(e.to_string()))
                .map(|a| a.into_pyarray(py))
        };
        let covered = |pixels: &[bool]| {
            Array2::from_shape_vec((n, n), pixels.to_vec())
                .map_err(|e| PyValueError::new_err(e.to_string()))
                .map(|a| a.into_pyarray(py))
        };
        let d = pyo3::types::PyDict::new(py);
        d.set_item("view", &view.view)?;
        d.set_item("original", colours(&view.original)?)?;
        d.set_item("simplified", colours(&view.simplified)?)?;
        d.set_item("covered_original", covered(&view.covered_original)?)?;
        d.set_item("covered_simplified", covered(&view.covered_simplified)?)?;
        list.append(d)?;
    }
    Ok(list)
}

/// Compare an original and a simplified mesh: the paper's errors, the symmetric surface
/// (Hausdorff) distance, normal deviation, triangle quality and topology; with
/// ``image_error=True`` also the image-space error.
///
/// Args:
///     v0, f0: the original mesh (array-likes as for :func:`simplify`).
///     v1, f1: the simplified mesh.
///     samples: surface samples per direction (default: 10 x the larger face count, as
///         Metro); 1 to 50,000,000.
///     meshlab: MeshLab's sampling plan (every vertex, plus ``samples`` edge and ``samples``
///         face samples per direction) instead of ``samples`` in total.
///     seed: the surface sampler's seed (the CLI's default, 1).
///     image_error: also render both meshes headlessly (CPU) from 14 fixed views (6 axes, 8
///         diagonals) framing the original and compare the pictures, as ``gng3d metrics
///         --image-error`` does: RMSE and mean absolute error of RGB (0-1), PSNR (dB), the
///         share of pixels off by more than ``image_threshold`` and the share of silhouette
///         mismatch, over the pixels covered in either image. The meshes are positions only
///         here, so they are drawn white, lit by a headlight on smooth vertex normals.
///     image_size: side of the square images, pixels (16 to 4096; default 256).
///     image_threshold: a pixel is off when its largest RGB channel differs by more than this
///         (0 to 1; default 0.1).
///     image_flat: light with face normals (faceted) instead of smooth vertex normals.
///     images: also return each view's renderings as numpy arrays.
///
/// Returns:
///     dict: the fields of ``gng3d metrics --json`` (``hausdorff``, ``e_avg``, ``e_max``,
///     ``e_sur_signed``, ``normal_deviation``, ``quality``, ``topology``, ...). With
///     ``image_error=True``, ``image_error`` holds the CLI's figures (``overall`` with
///     ``rmse``, ``mean_abs``, ``psnr_db`` (None for identical images), ``over_threshold``,
///     ``coverage_mismatch``; ``views``, one per view); with ``images=True``, ``images`` is a
///     list of one dict per view: ``view`` (its name), ``original`` and ``simplified``
///     (float32, (size, size, 3), RGB 0-1, row 0 at the top), ``covered_original`` and
///     ``covered_simplified`` (bool, (size, size)).
///
/// Raises:
///     ValueError: bad arrays or options (an image option names its keyword, e.g.
///         ``image_size: 8 pixels is not in 16 to 4096 pixels``; an ``image_*`` keyword
///         without ``image_error=True``).
///     KeyboardInterrupt: Ctrl-C while measuring (within a fraction of a second).
///
/// The meshes are measured as given (as the CLI measures files: not welded). The GIL is
/// released while measuring.
///
/// Example:
///     >>> v, f = gng3d.load("bunny.ply")                          # doctest: +SKIP
///     >>> v2, f2 = gng3d.simplify(v, f, ratio=0.05)               # doctest: +SKIP
///     >>> m = gng3d.metrics(v, f, v2, f2, samples=100_000)        # doctest: +SKIP
///     >>> m["hausdorff"]["max"], m["hausdorff"]["mean"]           # doctest: +SKIP
///     >>> gng3d.metrics(v, f, v2, f2, image_error=True)["image_error"]["overall"]["rmse"]  # doctest: +SKIP
#[pyfunction(name = "metrics")]
#[pyo3(signature = (
    v0, f0, v1, f1, *, samples=None, meshlab=false, seed=1, image_error=false, image_size=None,
    image_threshold=None, image_flat=false, images=false
))]
#[allow(clippy::too_many_arguments)]
fn measure<'py>(
    py: Python<'py>,
    v0: &Bound<'py, PyAny>,
    f0: &Bound<'py, PyAny>,
    v1: &Bound<'py, PyAny>,
    f1: &Bound<'py, PyAny>,
    samples: Option<usize>,
    meshlab: bool,
    seed: u64,
    image_error: bool,
    image_size: Option<u32>,
    image_threshold: Option<f64>,
    image_flat: bool,
    images: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let params = metrics::MetricsParams {
        hausdorff: metrics::HausdorffParams {
            samples,
            seed,
            plan: if meshlab {
                metrics::SamplingPlan::MeshLab
            } else {
                metrics::SamplingPlan::Budget
            },
            ..Default::default()
        },
    };
    params
        .hausdorff
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let image = image_params(image_error, image_size, image_threshold, image_flat, images)?;
    // Both in the original's frame (recentred alike when far from their origin).
    let (original, w0, origin) = mesh_from(v0, f0, "original", None)?;
    let (simplified, w1, _) = mesh_from(v1, f1, "simplified", Some(origin))?;
    warn_about(py, "original", &w0)?;
    warn_about(py, "simplified", &w1)?;
    let cancel = mesh::cancel::Cancel::default();
    let (report, views) = run::interruptible(py, &cancel, || {
        let mut report = metrics::evaluate_cancellable(&original, &simplified, &params, &cancel)?;
        let mut views = Vec::new();
        if let Some(image) = &image {
            let (measured, rendered) = metrics::image_error_with_images(
                &metrics::Surface::new(&original).with_cancel(&cancel),
                &metrics::Surface::new(&simplified),
                image,
                images,
            )?;
            report.image_error = Some(measured);
            views = rendered;
        }
        Ok::<_, metrics::MetricsError>((report, views))
    })?
    .map_err(|e| match e {
        metrics::MetricsError::Cancelled => {
            pyo3::exceptions::PyKeyboardInterrupt::new_err(e.to_string())
        }
        _ => PyValueError::new_err(e.to_string()),
    })?;
    let value = serde_json::to_value(&report).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let dict = to_python(py, &value)?;
    if images {
        dict.set_item("images", view_images(py, &views)?)?;
    }
    Ok(dict)
}

/// Read a mesh file (OBJ, PLY or STL, by extension) as ``(vertices, faces)``.
///
/// Returns every vertex record in file order (float64, (n, 3)) and the triangles (int64,
/// (m, 3)); polygons are fan-triangulated, degenerate and duplicate faces dropped with a
/// :class:`gng3d.Gng3dWarning`, as the CLI loads files. Not welded: :func:`simplify` welds.
///
/// Positions and triangles only: when the file also holds normals, texture coordinates,
/// colours or materials, a :class:`gng3d.Gng3dWarning` names them (e.g. ``spot.obj: texture
/// coordinates and 1 material not returned (load gives positions only); gng3d.simplify_file
/// keeps them``). :func:`simplify_file` simplifies a file keeping them.
///
/// Raises:
///     FileNotFoundError / OSError: the file cannot be read.
///     ValueError: the content is malformed (the message names the file and the line).
///
/// Example:
///     >>> v, f = gng3d.load("bunny.ply")   # doctest: +SKIP
///     >>> v.shape, f.shape                 # doctest: +SKIP
///     ((35947, 3), (69451, 3))
#[pyfunction]
fn load<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyTuple>> {
    let loaded = py.detach(|| mesh::io::load(&path)).map_err(mesh_error)?;
    let mut sentences: Vec<String> = loaded.warnings.iter().map(ToString::to_string).collect();
    if let Some(left_out) = file::not_returned(&loaded) {
        sentences.push(format!(
            "{left_out} not returned (load gives positions only); gng3d.simplify_file keeps them"
        ));
    }
    warn_about(py, path.display(), &sentences)?;
    convert::mesh_tuple(py, &loaded.mesh, loaded.origin)
}

/// Write a mesh file (OBJ, binary PLY or binary STL, by extension) atomically.
///
/// The mesh is checked as a loaded file is (no NaN, indices in range, at least one face;
/// degenerate and duplicate faces are dropped with a warning), then written to a temporary
/// file in the same folder and renamed over ``path``, so a failed write never leaves a partial
/// file. Coordinates are stored as float32, as the mesh files are read.
///
/// Raises:
///     ValueError: bad arrays or an unknown extension.
///     OSError: the file cannot be written.
///
/// Example:
///     >>> gng3d.save("out.ply", *gng3d.simplify(v, f, ratio=0.1))   # doctest: +SKIP
#[pyfunction]
fn save(
    py: Python<'_>,
    path: PathBuf,
    vertices: &Bound<'_, PyAny>,
    faces: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let name = path.to_string_lossy().into_owned();
    let (mesh, warnings, origin) = mesh_from(vertices, faces, &name, None)?;
    warn_about(py, &name, &warnings)?;
    let model = mesh::Model {
        origin,
        ..mesh.into()
    };
    py.detach(|| mesh::io::save(&model, &path))
        .map(|_| ())
        .map_err(mesh_error)
}

/// Lets models read the files they name outside their own folder (``../textures/``, absolute
/// paths), for this process: for trusted models only. By default (``False``) a model reads only
/// regular files inside its own folder and what points elsewhere is skipped with a warning (a
/// glTF buffer outside is an error). Files written beside an output stay inside the output's
/// folder either way. The command line's ``--allow-outside-references``.
///
/// Args:
///     allowed: ``True`` to read references anywhere, ``False`` for the default.
///
/// Example:
///     >>> gng3d.allow_outside_references(False)
#[pyfunction]
fn allow_outside_references(allowed: bool) {
    mesh::io::set_reference_scope(if allowed {
        mesh::io::ReferenceScope::Anywhere
    } else {
        mesh::io::ReferenceScope::ModelFolder
    });
}

/// The module: functions, classes and the warning category.
#[pymodule]
fn _gng3d(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simplify, m)?)?;
    m.add_function(wrap_pyfunction!(simplify_file, m)?)?;
    m.add_function(wrap_pyfunction!(measure, m)?)?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(save, m)?)?;
    m.add_function(wrap_pyfunction!(allow_outside_references, m)?)?;
    m.add_class::<SimplifyResult>()?;
    m.add_class::<trainer::Trainer>()?;
    batch::register(m)?;
    partition::register(m)?;
    m.add("Gng3dWarning", m.py().get_type::<Gng3dWarning>())?;
    // GNG3D's seed when none is given: the library's default, which the CLI's is too.
    m.add("DEFAULT_SEED", run::default_seed())?;
    m.add("DEFAULT_METHOD", job::DEFAULT_METHOD.name())?;
    m.add("KEYWORDS", keywords::KEYWORDS.to_vec())?;
    // The most `threads=` a call may ask for.
    m.add("MAX_THREADS", run::MAX_THREADS)?;
    Ok(())
}
