//! The geometry of a glTF file: the mesh instances that the scene's nodes place
//! ([`instances`]), and their triangle primitives read into one set of world-space vertices
//! (one wedge each) and triangles ([`read_geometry`]), with what was not read.

use super::COMPRESSION;
use super::buffers::Source;
use crate::error::{MeshError, MeshWarning};
use ::gltf::mesh::Mode;
use glam::{DMat4, DVec3, Mat3, Mat4, Vec2, Vec3, Vec4};
use serde_json::{Map, Value};
use std::collections::{BTreeSet, HashMap};

/// The attributes read from a primitive; all others are reported as ignored.
const READ_ATTRIBUTES: [&str; 5] = ["POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "COLOR_0"];

/// A mesh instance: the mesh, its world transform, and (with a far origin) its world transform
/// in f64.
pub(super) type Instance<'a> = (::gltf::Mesh<'a>, Mat4, DMat4);

/// The mesh instances that the default scene's nodes place (the first scene when none is the
/// default; every mesh once, untransformed, when there is no scene): (mesh, world transform).
/// With a far `origin`, the world transforms again in f64 from the JSON (the `gltf` crate
/// reads them as f32, which rounds a georeferenced translation to decimetres).
pub(super) fn instances<'a>(
    doc: &'a ::gltf::Document,
    root_json: &Map<String, Value>,
    source: &Source,
    origin: DVec3,
) -> Result<Vec<Instance<'a>>, MeshError> {
    let mut instances: Vec<Instance<'a>> = Vec::new();
    match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(scene) => {
            // glTF nodes form trees (one parent each): a node reached twice is a cycle or a
            // shared child, either of which could make the walk endless or exponential.
            let mut seen = vec![false; doc.nodes().len()];
            let mut stack: Vec<(::gltf::Node, Mat4, DMat4)> = scene
                .nodes()
                .map(|n| (n, Mat4::IDENTITY, DMat4::IDENTITY))
                .collect();
            stack.reverse();
            while let Some((node, parent, parent64)) = stack.pop() {
                if std::mem::replace(&mut seen[node.index()], true) {
                    return Err(source.error(
                        format!("node {}", node.index()),
                        "the node is reached twice from the scene (the node hierarchy has a \
                         cycle or a node with two parents; glTF nodes form trees)",
                    ));
                }
                let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
                let world64 = if origin == DVec3::ZERO {
                    DMat4::IDENTITY
                } else {
                    parent64 * local_transform_f64(&root_json["nodes"][node.index()])
                };
                if let Some(mesh) = node.mesh() {
                    instances.push((mesh, world, world64));
                }
                let children: Vec<_> = node.children().collect();
                for child in children.into_iter().rev() {
                    stack.push((child, world, world64));
                }
            }
        }
        None => instances.extend(doc.meshes().map(|m| (m, Mat4::IDENTITY, DMat4::IDENTITY))),
    }
    Ok(instances)
}

/// A node's local transform in f64 from its JSON: `matrix` (column-major), or translation,
/// rotation and scale (identity where absent or malformed; the `gltf` crate validated them).
fn local_transform_f64(node: &Value) -> DMat4 {
    let numbers = |key: &str, n: usize| -> Option<Vec<f64>> {
        let v: Vec<f64> = node[key]
            .as_array()?
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        (v.len() == n).then_some(v)
    };
    if let Some(m) = numbers("matrix", 16) {
        let mut cols = [0.0; 16];
        cols.copy_from_slice(&m);
        return DMat4::from_cols_array(&cols);
    }
    let t = numbers("translation", 3).map_or(DVec3::ZERO, |v| DVec3::new(v[0], v[1], v[2]));
    let r = numbers("rotation", 4).map_or(glam::DQuat::IDENTITY, |v| {
        glam::DQuat::from_xyzw(v[0], v[1], v[2], v[3]).normalize()
    });
    let s = numbers("scale", 3).map_or(DVec3::ONE, |v| DVec3::new(v[0], v[1], v[2]));
    DMat4::from_scale_rotation_translation(s, r, t)
}

/// The glTF vertices read so far (one wedge each), in world space.
#[derive(Default)]
pub(super) struct Vertices {
    pub(super) positions: Vec<Vec3>,
    pub(super) normals: Vec<Vec3>,
    pub(super) uv0: Vec<Vec2>,
    pub(super) uv1: Vec<Vec2>,
    pub(super) colors: Vec<Vec4>,
    /// Vertices of vertex sets without NORMAL / TEXCOORD_0 / TEXCOORD_1 / COLOR_0.
    missing: [usize; 4],
    /// Whether any vertex set has NORMAL / TEXCOORD_0 / TEXCOORD_1 / COLOR_0.
    pub(super) present: [bool; 4],
}

/// Where an instance's primitives go: its world transform and what follows from it.
struct Placement {
    /// The world transform.
    world: Mat4,
    /// The world transform in f64 (with a far `origin` only).
    world64: DMat4,
    /// The transform of the normals.
    normal_matrix: Mat3,
    /// Whether the transform mirrors (the triangles' winding is turned back).
    flip: bool,
    /// Whether the transform is the identity (positions keep their bits).
    identity: bool,
    /// The model-space point the positions are made relative to.
    origin: DVec3,
}

/// A vertex set: (instance, accessors of [`READ_ATTRIBUTES`]); primitives sharing their
/// accessors share their vertices.
type SetKey = (usize, [Option<usize>; 5]);

/// The geometry read ([`Geometry::finish`]): the vertices (one wedge each), the triangles (wedge
/// indices) and the glTF material of each triangle (`u32::MAX`: none).
pub(super) type Triangles = (Vertices, Vec<[u32; 3]>, Vec<u32>);

/// The triangles of the instances' primitives, their vertices, and what was not read.
#[derive(Default)]
pub(super) struct Geometry {
    /// The glTF vertices, one wedge each.
    v: Vertices,
    /// The triangles (wedge indices).
    corners: Vec<[u32; 3]>,
    /// The glTF material of each triangle (`u32::MAX`: none).
    face_material: Vec<u32>,
    /// The vertex sets read: (first wedge, count).
    sets: HashMap<SetKey, (u32, usize)>,
    /// Vertex attributes not read.
    ignored_attributes: BTreeSet<String>,
    /// Primitive extensions not applied.
    ignored_extensions: BTreeSet<String>,
    /// Primitives of points or lines.
    not_triangles: usize,
    /// The vertex count of the vertex sets of points and lines, by (instance, POSITION accessor).
    point_line_sets: HashMap<(usize, usize), usize>,
    /// Primitives without POSITION.
    no_position: usize,
    /// Primitives with morph targets.
    morphed: usize,
}

/// Every triangle primitive of `instances`, placed in world space (relative to `origin`).
pub(super) fn read_geometry(
    instances: &[Instance],
    root_json: &Map<String, Value>,
    source: &Source,
    origin: DVec3,
) -> Result<Geometry, MeshError> {
    let mut g = Geometry::default();
    for (instance, (mesh, world, world64)) in instances.iter().enumerate() {
        let place = Placement {
            world: *world,
            world64: *world64,
            normal_matrix: Mat3::from_mat4(*world).inverse().transpose(),
            flip: world.determinant() < 0.0,
            identity: *world == Mat4::IDENTITY,
            origin,
        };
        for prim in mesh.primitives() {
            g.primitive(instance, mesh, &prim, &place, root_json, source)?;
        }
    }
    Ok(g)
}

impl Geometry {
    /// Reads primitive `prim` of `mesh` (instance `instance`): its vertex set, unless an earlier
    /// primitive of the instance read it, and its triangles; primitives of points or lines and
    /// those without POSITION are counted.
    fn primitive(
        &mut self,
        instance: usize,
        mesh: &::gltf::Mesh,
        prim: &::gltf::Primitive,
        place: &Placement,
        root_json: &Map<String, Value>,
        source: &Source,
    ) -> Result<(), MeshError> {
        let at = format!("mesh {} primitive {}", mesh.index(), prim.index());
        let prim_json = &root_json["meshes"][mesh.index()]["primitives"][prim.index()];
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.not_triangles += 1;
            // Their vertices, once per vertex set, for the error of a file of only these.
            if let Some(i) = prim_json["attributes"]["POSITION"].as_u64()
                && let Some(a) = source.doc.accessors().nth(i as usize)
            {
                self.point_line_sets
                    .insert((instance, a.index()), a.count());
            }
            return Ok(());
        }
        let mut accessor_of = [None; 5];
        if let Some(attributes) = prim_json["attributes"].as_object() {
            for (name, index) in attributes {
                match READ_ATTRIBUTES.iter().position(|a| a == name) {
                    Some(k) => accessor_of[k] = index.as_u64().map(|i| i as usize),
                    None => {
                        self.ignored_attributes.insert(name.clone());
                    }
                }
            }
        }
        if prim_json
            .get("targets")
            .is_some_and(|t| t.as_array().is_some_and(|a| !a.is_empty()))
        {
            self.morphed += 1;
        }
        if let Some(ext) = prim_json["extensions"].as_object() {
            self.ignored_extensions.extend(ext.keys().cloned());
        }
        let Some(position_index) = accessor_of[0] else {
            self.no_position += 1;
            return Ok(());
        };
        let key = (instance, accessor_of);
        let (base, count) = match self.sets.get(&key) {
            Some(&set) => set,
            None => {
                let set = self
                    .v
                    .read_set(position_index, &accessor_of, place, source, &at)?;
                self.sets.insert(key, set);
                set
            }
        };
        let indices = primitive_indices(prim, source, count, &at)?;
        let material = prim.material().index().map_or(u32::MAX, |m| m as u32);
        self.push_triangles(mode, &indices, base, place.flip, material);
        Ok(())
    }

    /// Appends the triangles of `indices` (into the vertex set at `base`) as `mode` lays them
    /// out, turned back when `flip`, with `material`.
    fn push_triangles(
        &mut self,
        mode: Mode,
        indices: &[u32],
        base: u32,
        flip: bool,
        material: u32,
    ) {
        let corners = &mut self.corners;
        let before = corners.len();
        match mode {
            Mode::Triangles => {
                corners.extend(indices.chunks_exact(3).map(|t| [t[0], t[1], t[2]]));
            }
            Mode::TriangleStrip => {
                corners.extend(indices.windows(3).enumerate().map(|(i, t)| {
                    if i % 2 == 0 {
                        [t[0], t[1], t[2]]
                    } else {
                        [t[0], t[2], t[1]]
                    }
                }));
            }
            _ => {
                if let Some((&first, rest)) = indices.split_first() {
                    corners.extend(rest.windows(2).map(|t| [t[0], t[1], first]));
                }
            }
        }
        for c in &mut corners[before..] {
            *c = c.map(|i| i + base);
            if flip {
                c.swap(1, 2);
            }
        }
        self.face_material.resize(corners.len(), material);
    }

    /// The vertices, triangles and triangle materials read; an error for a file whose
    /// primitives are all points or lines, and warnings for what was not read.
    pub(super) fn finish(
        self,
        source: &Source,
        warnings: &mut Vec<MeshWarning>,
    ) -> Result<Triangles, MeshError> {
        let Geometry {
            v,
            corners,
            face_material,
            sets: _,
            ignored_attributes,
            mut ignored_extensions,
            not_triangles,
            point_line_sets,
            no_position,
            morphed,
        } = self;
        let point_line_vertices: usize = point_line_sets.values().sum();
        if corners.is_empty() && not_triangles > 0 && point_line_vertices > 0 {
            return Err(MeshError::NoTriangles {
                path: source.path.to_path_buf(),
                vertex_count: v.positions.len() + point_line_vertices,
                primitives: not_triangles,
            });
        }
        if not_triangles > 0 {
            warnings.push(MeshWarning::IgnoredData {
                what: format!("{not_triangles} glTF primitive(s) of points or lines"),
            });
        }
        if no_position > 0 {
            warnings.push(MeshWarning::IgnoredData {
                what: format!("{no_position} glTF primitive(s) without POSITION"),
            });
        }
        if !ignored_attributes.is_empty() {
            warnings.push(MeshWarning::IgnoredData {
                what: format!(
                    "glTF vertex attributes {}",
                    ignored_attributes
                        .into_iter()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
        if morphed > 0 {
            warnings.push(MeshWarning::IgnoredData {
                what: format!("glTF morph targets of {morphed} primitive(s)"),
            });
        }
        ignored_extensions.retain(|e| !COMPRESSION.contains(&e.as_str()));
        if !ignored_extensions.is_empty() {
            warnings.push(MeshWarning::IgnoredData {
                what: format!(
                    "glTF primitive extensions {}",
                    ignored_extensions
                        .into_iter()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
        for (k, name) in ["normals", "uv0", "uv1"].iter().enumerate() {
            if v.present[k] && v.missing[k] > 0 {
                warnings.push(MeshWarning::MissingCornerAttribute {
                    attribute: name.to_string(),
                    count: v.missing[k],
                });
            }
        }
        Ok((v, corners, face_material))
    }
}

/// The index of each corner of `prim` in its vertex set of `count` vertices (its index
/// accessor, or `0..count` without one), checked to lie in the set.
fn primitive_indices(
    prim: &::gltf::Primitive,
    source: &Source,
    count: usize,
    at: &str,
) -> Result<Vec<u32>, MeshError> {
    Ok(match prim.indices() {
        Some(a) => {
            let indices = source.indices(&a, "indices")?;
            if let Some(&bad) = indices.iter().find(|&&i| i as usize >= count) {
                return Err(source.error(
                    at,
                    format!(
                        "index {bad} (accessor {}) refers to vertex {bad}, but the \
                         primitive has {count} vertices",
                        a.index()
                    ),
                ));
            }
            indices
        }
        None => (0..count as u32).collect(),
    })
}

/// Accessor `i` of the document; an error at `at` when there is none.
fn accessor<'a>(
    source: &Source<'a>,
    at: &str,
    i: usize,
) -> Result<::gltf::Accessor<'a>, MeshError> {
    source
        .doc
        .accessors()
        .nth(i)
        .ok_or_else(|| source.error(at, format!("accessor {i} does not exist")))
}

impl Vertices {
    /// Reads a vertex set: the POSITION accessor `position_index` and the other
    /// [`READ_ATTRIBUTES`] that `accessor_of` names (defaults for those it does not), placed by
    /// `place`; returns its first wedge and its count.
    fn read_set(
        &mut self,
        position_index: usize,
        accessor_of: &[Option<usize>; 5],
        place: &Placement,
        source: &Source,
        at: &str,
    ) -> Result<(u32, usize), MeshError> {
        let v = self;
        let base = v.positions.len() as u32;
        let (p, _) = source.floats(&accessor(source, at, position_index)?, "POSITION", &[3])?;
        let count = p.len() / 3;
        if v.positions.len() + count > u32::MAX as usize {
            return Err(source.error(at, "more than 2^32 vertices"));
        }
        let Placement {
            world,
            world64,
            identity,
            origin,
            ..
        } = *place;
        v.positions.extend(
            p.chunks_exact(3)
                .map(|c| Vec3::new(c[0], c[1], c[2]))
                // Untransformed instances keep their bits (also -0.0).
                .map(|p| {
                    if origin != DVec3::ZERO {
                        (world64.transform_point3(p.as_dvec3()) - origin).as_vec3()
                    } else if identity {
                        p
                    } else {
                        world.transform_point3(p)
                    }
                }),
        );
        for (k, &index) in accessor_of.iter().enumerate().skip(1) {
            v.read_attribute(k, index, count, place.normal_matrix, source, at)?;
        }
        Ok((base, count))
    }

    /// Reads attribute `k` of [`READ_ATTRIBUTES`] of a vertex set of `count` vertices from
    /// accessor `index` (normals transformed by `normal_matrix`), or its default without one.
    fn read_attribute(
        &mut self,
        k: usize,
        index: Option<usize>,
        count: usize,
        normal_matrix: Mat3,
        source: &Source,
        at: &str,
    ) -> Result<(), MeshError> {
        let v = self;
        let name = READ_ATTRIBUTES[k];
        let Some(index) = index else {
            v.missing[k - 1] += count;
            match k {
                1 => v.normals.resize(v.positions.len(), Vec3::ZERO),
                2 => v.uv0.resize(v.positions.len(), Vec2::ZERO),
                3 => v.uv1.resize(v.positions.len(), Vec2::ZERO),
                _ => v.colors.resize(v.positions.len(), Vec4::ONE),
            }
            return Ok(());
        };
        let dims: &[usize] = match k {
            1 => &[3],
            2 | 3 => &[2],
            _ => &[3, 4],
        };
        let (a, n) = source.floats(&accessor(source, at, index)?, name, dims)?;
        if a.len() / n != count {
            return Err(source.error(
                at,
                format!(
                    "{name} has {} elements, but POSITION has {count}",
                    a.len() / n
                ),
            ));
        }
        v.present[k - 1] = true;
        match k {
            1 => v.normals.extend(a.chunks_exact(3).map(|c| {
                let n = Vec3::new(c[0], c[1], c[2]);
                // Normals of untransformed instances keep their bits.
                if normal_matrix == Mat3::IDENTITY {
                    n
                } else {
                    (normal_matrix * n).normalize_or_zero()
                }
            })),
            2 => v
                .uv0
                .extend(a.chunks_exact(2).map(|c| Vec2::new(c[0], c[1]))),
            3 => v
                .uv1
                .extend(a.chunks_exact(2).map(|c| Vec2::new(c[0], c[1]))),
            _ => v.colors.extend(
                a.chunks_exact(n)
                    .map(|c| Vec4::new(c[0], c[1], c[2], if n == 4 { c[3] } else { 1.0 })),
            ),
        }
        Ok(())
    }
}
