//! Where the fields the reader keeps sit among an element's properties (the vertex layout,
//! the face list), and the warnings for what it skips.

use super::header::{Element, Header, Property, Scalar};
use crate::error::{MeshError, MeshWarning};
use std::path::Path;

/// Where the vertex fields we want sit among the vertex element's properties.
pub(super) struct VertexLayout {
    pub(super) position: [usize; 3],
    pub(super) normal: Option<[usize; 3]>,
    /// `s t`, `u v`, `texture_u texture_v` or `texture_s texture_t`.
    pub(super) uv: Option<[usize; 2]>,
    /// `red green blue [alpha]` (alpha 1 when absent) and the factor to [0, 1].
    pub(super) color: Option<([usize; 3], Option<usize>, f64)>,
}

/// The colour factor to [0, 1] for a channel of type `ty`.
pub(super) fn color_scale(ty: Scalar) -> f64 {
    match ty {
        Scalar::U8 | Scalar::I8 => 1.0 / 255.0,
        Scalar::U16 | Scalar::I16 => 1.0 / 65535.0,
        Scalar::U32 | Scalar::I32 => 1.0 / 4294967295.0,
        Scalar::F32 | Scalar::F64 => 1.0,
    }
}

/// The vertex properties this reader reads.
const VERTEX_PROPERTIES: [&str; 16] = [
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "s",
    "t",
    "u",
    "v",
    "texture_u",
    "texture_v",
    "red",
    "green",
    "blue",
    "alpha",
];

/// Warnings for what the header declares and this reader skips: vertex properties it does not
/// read, face properties other than the index list, other elements.
pub(super) fn ignored_data(header: &Header) -> Vec<MeshWarning> {
    let mut out = Vec::new();
    let mut seen_vertex = false;
    for element in &header.elements {
        let names = |skip: &dyn Fn(&str) -> bool| -> Vec<String> {
            element
                .properties
                .iter()
                .map(|p| match p {
                    Property::Scalar(n, _) | Property::List(n, _, _) => n.clone(),
                })
                .filter(|n| !skip(n))
                .collect()
        };
        let (what, list) = match element.name.as_str() {
            "vertex" if !seen_vertex => {
                seen_vertex = true;
                (
                    "vertex",
                    names(&|n| {
                        VERTEX_PROPERTIES.contains(&n) || n == "texture_s" || n == "texture_t"
                    }),
                )
            }
            "face" => (
                "face",
                names(&|n| n == "vertex_indices" || n == "vertex_index"),
            ),
            _ => {
                if element.count > 0 {
                    out.push(MeshWarning::IgnoredData {
                        what: format!("PLY element {} ({} records)", element.name, element.count),
                    });
                }
                continue;
            }
        };
        if !list.is_empty() && element.count > 0 {
            out.push(MeshWarning::IgnoredData {
                what: format!("PLY {what} properties {}", list.join(", ")),
            });
        }
        if what == "vertex" && element.count > 0 {
            out.extend(partial_vertex_properties(element));
        }
    }
    out
}

/// Vertex properties of a known name that are not read: a group without all its members
/// (`red green` without `blue`, `nx ny` without `nz`) or a list instead of a scalar.
pub(super) fn partial_vertex_properties(element: &Element) -> Vec<MeshWarning> {
    let scalar = |name: &str| {
        element
            .properties
            .iter()
            .any(|p| matches!(p, Property::Scalar(n, _) if n == name))
    };
    let mut out = Vec::new();
    for group in [
        &["nx", "ny", "nz"][..],
        &["red", "green", "blue"],
        &["s", "t"],
        &["u", "v"],
        &["texture_u", "texture_v"],
        &["texture_s", "texture_t"],
    ] {
        let (have, lack): (Vec<&str>, Vec<&str>) = group.iter().partition(|n| scalar(n));
        if !have.is_empty() && !lack.is_empty() {
            out.push(MeshWarning::IgnoredData {
                what: format!(
                    "PLY vertex properties {} (without {})",
                    have.join(", "),
                    lack.join(", ")
                ),
            });
        }
    }
    for p in &element.properties {
        if let Property::List(n, _, _) = p
            && (VERTEX_PROPERTIES.contains(&n.as_str()) || n == "texture_s" || n == "texture_t")
        {
            out.push(MeshWarning::IgnoredData {
                what: format!("PLY vertex property {n} (a list, where a number is read)"),
            });
        }
    }
    out
}

pub(super) fn vertex_layout(element: &Element, path: &Path) -> Result<VertexLayout, MeshError> {
    let find = |name: &str| {
        element
            .properties
            .iter()
            .position(|p| matches!(p, Property::Scalar(n, _) if n == name))
    };
    let position = match (find("x"), find("y"), find("z")) {
        (Some(x), Some(y), Some(z)) => [x, y, z],
        _ => {
            return Err(MeshError::parse(
                path,
                "header",
                "vertex element lacks scalar x, y, z properties",
            ));
        }
    };
    let normal = match (find("nx"), find("ny"), find("nz")) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z]),
        _ => None,
    };
    let uv = [
        ("s", "t"),
        ("u", "v"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ]
    .iter()
    .find_map(|(a, b)| Some([find(a)?, find(b)?]));
    let color = match (find("red"), find("green"), find("blue")) {
        (Some(r), Some(g), Some(b)) => {
            let scale = match &element.properties[r] {
                Property::Scalar(_, ty) => color_scale(*ty),
                Property::List(..) => 1.0,
            };
            Some(([r, g, b], find("alpha"), scale))
        }
        _ => None,
    };
    Ok(VertexLayout {
        position,
        normal,
        uv,
        color,
    })
}

pub(super) fn face_list_index(element: &Element) -> Option<usize> {
    element.properties.iter().position(
        |p| matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index"),
    )
}
