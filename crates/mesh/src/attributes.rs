//! Per-corner attributes with seams: normals, texture coordinates, colours and materials kept
//! next to a [`TriMesh`] without changing it.
//!
//! A *wedge* is one attribute set of one position vertex: a vertex on a UV or normal seam has
//! one wedge per side, every other vertex one. [`Attributes`] maps each wedge to its vertex and
//! each triangle corner to its wedge, so the algorithms keep working on the one surface of
//! [`TriMesh::positions`] and [`TriMesh::triangles`] while the seams stay seams.
//!
//! ```
//! use gng3d_mesh::attributes::{AttributeKind, Attributes};
//! use glam::{Vec2, Vec3};
//! // Two triangles sharing the edge 1-2, which is a UV seam: vertices 1 and 2 have two wedges.
//! let mesh = gng3d_mesh::TriMesh::new(
//!     vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::ONE],
//!     vec![[0, 1, 2], [1, 3, 2]],
//! );
//! let attributes = Attributes {
//!     wedge_vertex: vec![0, 1, 2, 1, 3, 2],
//!     corners: vec![[0, 1, 2], [3, 4, 5]],
//!     uv0: Some(vec![Vec2::ZERO, Vec2::X, Vec2::Y, Vec2::ONE, Vec2::ONE, Vec2::ONE]),
//!     ..Attributes::default()
//! };
//! attributes.validate(&mesh).unwrap();
//! assert_eq!(attributes.seam_edges(&mesh).len(), 1);
//! assert_eq!(attributes.kinds(), vec![AttributeKind::Uv0]);
//! assert_eq!(AttributeKind::Uv0.to_string(), "uv0");
//! ```

use crate::TriMesh;
use glam::{Vec2, Vec3, Vec4};
use gltf_assets::GltfAssets;
use std::path::PathBuf;

pub(crate) mod gltf_assets;

/// One kind of attribute ([`Attributes::kinds`]). It prints (and serializes) as the name that
/// reports, `gng3d simplify --json` and Python use: `normals`, `uv0`, `uv1`, `colors`,
/// `materials`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum AttributeKind {
    /// Normals ([`Attributes::normals`]), `normals`.
    Normals,
    /// First texture coordinates ([`Attributes::uv0`]), `uv0`.
    Uv0,
    /// Second texture coordinates ([`Attributes::uv1`]), `uv1`.
    Uv1,
    /// Colours ([`Attributes::colors`]), `colors`.
    Colors,
    /// Materials of the faces ([`Attributes::face_material`]), `materials`.
    Materials,
}

impl AttributeKind {
    /// The kind's name: `normals`, `uv0`, `uv1`, `colors` or `materials` (what it prints as).
    pub fn name(self) -> &'static str {
        match self {
            AttributeKind::Normals => "normals",
            AttributeKind::Uv0 => "uv0",
            AttributeKind::Uv1 => "uv1",
            AttributeKind::Colors => "colors",
            AttributeKind::Materials => "materials",
        }
    }

    /// `kinds` as messages write them: their names, separated by `, ` (`uv1, materials`).
    pub fn list(kinds: &[AttributeKind]) -> String {
        let names: Vec<&str> = kinds.iter().map(|k| k.name()).collect();
        names.join(", ")
    }
}

impl std::fmt::Display for AttributeKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Attributes of a mesh's triangle corners, stored per wedge (see the module docs).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Attributes {
    /// For each wedge, the position vertex it belongs to.
    pub wedge_vertex: Vec<u32>,
    /// For each triangle of the mesh, the wedge of each corner (same order as the triangle).
    pub corners: Vec<[u32; 3]>,
    /// Unit normals, per wedge.
    pub normals: Option<Vec<Vec3>>,
    /// First texture coordinates (OBJ `vt`, PLY `s t`, glTF `TEXCOORD_0`), per wedge.
    pub uv0: Option<Vec<Vec2>>,
    /// Second texture coordinates (glTF `TEXCOORD_1`), per wedge.
    pub uv1: Option<Vec<Vec2>>,
    /// Linear RGBA colours in [0, 1], per wedge.
    pub colors: Option<Vec<Vec4>>,
    /// For each triangle, its material: an index into [`Materials::names`].
    pub face_material: Option<Vec<u32>>,
}

/// The materials a mesh file names, for writing them back.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Materials {
    /// Material names, indexed by [`Attributes::face_material`].
    pub names: Vec<String>,
    /// Material libraries (OBJ `mtllib`), resolved against the folder of the file that named
    /// them; written as their file names next to the output, where they are copied with the
    /// textures they name.
    pub libraries: Vec<PathBuf>,
    /// What a glTF input holds besides geometry (materials, textures, images, samplers),
    /// written back unchanged by a glTF output; `None` for other formats.
    pub gltf: Option<GltfAssets>,
}

impl Attributes {
    /// Attributes with one wedge per vertex (no seams) for `mesh`: wedge `i` is vertex `i`,
    /// corners equal the triangles; no attribute arrays yet.
    pub fn per_vertex(mesh: &TriMesh) -> Attributes {
        Attributes {
            wedge_vertex: (0..mesh.positions.len() as u32).collect(),
            corners: mesh.triangles.clone(),
            ..Attributes::default()
        }
    }

    /// Number of wedges.
    pub fn wedge_count(&self) -> usize {
        self.wedge_vertex.len()
    }

    /// Whether no attribute (normals, texture coordinates, colours, materials) is present.
    pub fn is_empty(&self) -> bool {
        self.kinds().is_empty()
    }

    /// Whether per-corner values are present: normals, texture coordinates or colours
    /// (materials alone do not count).
    pub fn has_values(&self) -> bool {
        self.normals.is_some() || self.uv0.is_some() || self.uv1.is_some() || self.colors.is_some()
    }

    /// The attributes present, in a fixed order: normals, uv0, uv1, colors, materials (as
    /// `gng3d simplify --json` reports them).
    pub fn kinds(&self) -> Vec<AttributeKind> {
        [
            (self.normals.is_some(), AttributeKind::Normals),
            (self.uv0.is_some(), AttributeKind::Uv0),
            (self.uv1.is_some(), AttributeKind::Uv1),
            (self.colors.is_some(), AttributeKind::Colors),
            (self.face_material.is_some(), AttributeKind::Materials),
        ]
        .into_iter()
        .filter_map(|(present, kind)| present.then_some(kind))
        .collect()
    }

    /// Checks that the arrays fit `mesh`: one corner triple and material per triangle, wedge
    /// indices in range, each corner's wedge on that corner's vertex, one value per wedge in
    /// every attribute array, finite values. The error says what does not fit.
    pub fn validate(&self, mesh: &TriMesh) -> Result<(), String> {
        let w = self.wedge_vertex.len();
        if self.corners.len() != mesh.triangles.len() {
            return Err(format!(
                "{} corner triples for {} triangles",
                self.corners.len(),
                mesh.triangles.len()
            ));
        }
        if let Some(v) = self
            .wedge_vertex
            .iter()
            .find(|&&v| v as usize >= mesh.positions.len())
        {
            return Err(format!(
                "a wedge refers to vertex {v}, but there are {} vertices",
                mesh.positions.len()
            ));
        }
        for (f, (c, t)) in self.corners.iter().zip(&mesh.triangles).enumerate() {
            for k in 0..3 {
                if c[k] as usize >= w {
                    return Err(format!(
                        "triangle {f} refers to wedge {}, but there are {w} wedges",
                        c[k]
                    ));
                }
                if self.wedge_vertex[c[k] as usize] != t[k] {
                    return Err(format!(
                        "corner {k} of triangle {f} is vertex {} but its wedge {} belongs to vertex {}",
                        t[k], c[k], self.wedge_vertex[c[k] as usize]
                    ));
                }
            }
        }
        let check = |name: &str, len: Option<usize>, finite: bool| -> Result<(), String> {
            match len {
                Some(l) if l != w => Err(format!("{name}: {l} values for {w} wedges")),
                Some(_) if !finite => Err(format!("{name}: a value is not finite")),
                _ => Ok(()),
            }
        };
        check(
            "normals",
            self.normals.as_ref().map(Vec::len),
            self.normals.iter().flatten().all(|v| v.is_finite()),
        )?;
        check(
            "uv0",
            self.uv0.as_ref().map(Vec::len),
            self.uv0.iter().flatten().all(|v| v.is_finite()),
        )?;
        check(
            "uv1",
            self.uv1.as_ref().map(Vec::len),
            self.uv1.iter().flatten().all(|v| v.is_finite()),
        )?;
        check(
            "colors",
            self.colors.as_ref().map(Vec::len),
            self.colors.iter().flatten().all(|v| v.is_finite()),
        )?;
        if let Some(m) = &self.face_material
            && m.len() != mesh.triangles.len()
        {
            return Err(format!(
                "{} face materials for {} triangles",
                m.len(),
                mesh.triangles.len()
            ));
        }
        Ok(())
    }

    /// The triangles whose `keep` entry is true (corners and materials), wedges unchanged.
    pub fn select_faces(&self, keep: &[bool]) -> Attributes {
        let pick = |f: usize| keep.get(f).copied().unwrap_or(false);
        Attributes {
            wedge_vertex: self.wedge_vertex.clone(),
            corners: (self.corners.iter().enumerate())
                .filter(|(f, _)| pick(*f))
                .map(|(_, c)| *c)
                .collect(),
            face_material: self.face_material.as_ref().map(|m| {
                m.iter()
                    .enumerate()
                    .filter(|(f, _)| pick(*f))
                    .map(|(_, m)| *m)
                    .collect()
            }),
            ..self.clone_arrays()
        }
    }

    /// The per-wedge arrays only (wedge list, corners and materials empty).
    fn clone_arrays(&self) -> Attributes {
        Attributes {
            wedge_vertex: Vec::new(),
            corners: Vec::new(),
            normals: self.normals.clone(),
            uv0: self.uv0.clone(),
            uv1: self.uv1.clone(),
            colors: self.colors.clone(),
            face_material: None,
        }
    }

    /// Wedges moved to new vertices: wedge `w` now belongs to `map[wedge_vertex[w]]` (a weld or
    /// a renumbering of the positions).
    pub fn remap_vertices(&mut self, map: &[u32]) {
        for v in &mut self.wedge_vertex {
            *v = map[*v as usize];
        }
    }

    /// Drops wedges no corner uses and merges wedges of one vertex whose attribute values are
    /// bit-identical, keeping the order of the first of each; corners are renumbered.
    pub fn compact(&mut self) {
        let n = self.wedge_vertex.len();
        let mut used = vec![false; n];
        for c in &self.corners {
            for &w in c {
                used[w as usize] = true;
            }
        }
        // Bit-identical values (`-0.0` and `0.0` apart, a NaN equal to itself), as a key of the
        // values' bits would compare them.
        fn same_bits<T: Copy + Into<[f32; N]>, const N: usize>(
            v: &Option<Vec<T>>,
            a: usize,
            b: usize,
        ) -> bool {
            v.as_ref().is_none_or(|v| {
                let (x, y): ([f32; N], [f32; N]) = (v[a].into(), v[b].into());
                x.iter().zip(&y).all(|(x, y)| x.to_bits() == y.to_bits())
            })
        }
        let same = |a: usize, b: usize| {
            same_bits(&self.normals, a, b)
                && same_bits(&self.uv0, a, b)
                && same_bits(&self.uv1, a, b)
                && same_bits(&self.colors, a, b)
        };
        // The kept wedges of each vertex, chained from `first[vertex]` through `next_kept`: a
        // wedge is compared with those of its own vertex only (one to three, typically),
        // instead of hashing every wedge's values (a `Vec` key per wedge and SipHash were 1.0
        // of QEM's 31 M instructions on spot with attributes).
        let vertices = self
            .wedge_vertex
            .iter()
            .max()
            .map_or(0, |&v| v as usize + 1);
        let mut first = vec![u32::MAX; vertices];
        let mut next_kept = vec![u32::MAX; n];
        let mut new_index = vec![u32::MAX; n];
        let mut kept: Vec<usize> = Vec::new();
        for w in 0..n {
            if !used[w] {
                continue;
            }
            let v = self.wedge_vertex[w] as usize;
            let mut k = first[v];
            while k != u32::MAX && !same(k as usize, w) {
                k = next_kept[k as usize];
            }
            new_index[w] = if k == u32::MAX {
                next_kept[w] = first[v];
                first[v] = w as u32;
                kept.push(w);
                kept.len() as u32 - 1
            } else {
                new_index[k as usize]
            };
        }
        for c in &mut self.corners {
            for w in c.iter_mut() {
                *w = new_index[*w as usize];
            }
        }
        fn gather<T: Copy>(a: &mut Option<Vec<T>>, kept: &[usize]) {
            if let Some(v) = a {
                *v = kept.iter().map(|&w| v[w]).collect();
            }
        }
        self.wedge_vertex = kept.iter().map(|&w| self.wedge_vertex[w]).collect();
        gather(&mut self.normals, &kept);
        gather(&mut self.uv0, &kept);
        gather(&mut self.uv1, &kept);
        gather(&mut self.colors, &kept);
    }

    /// Whether wedges `a` and `b` hold the same values in every attribute present.
    pub fn same_values(&self, a: u32, b: u32) -> bool {
        fn eq<T: PartialEq>(v: &Option<Vec<T>>, a: u32, b: u32) -> bool {
            v.as_ref().is_none_or(|v| v[a as usize] == v[b as usize])
        }
        a == b
            || (eq(&self.normals, a, b)
                && eq(&self.uv0, a, b)
                && eq(&self.uv1, a, b)
                && eq(&self.colors, a, b))
    }

    /// The seams: edges `[u, v]` (`u < v`) of exactly two triangles across which an attribute
    /// or the material changes (the two triangles give an end different wedge values, or have
    /// different materials). Boundary and non-manifold edges are not seams. Sorted.
    pub fn seam_edges(&self, mesh: &TriMesh) -> Vec<[u32; 2]> {
        self.edge_sides(mesh)
            .into_iter()
            .filter(|e| e.seam)
            .map(|e| e.edge)
            .collect()
    }

    /// Every edge of exactly two triangles, with whether it is a seam.
    pub(crate) fn edge_sides(&self, mesh: &TriMesh) -> Vec<EdgeSides> {
        let mut half: Vec<([u32; 2], u32, u8)> = Vec::with_capacity(3 * mesh.triangles.len());
        for (f, t) in mesh.triangles.iter().enumerate() {
            for k in 0..3u8 {
                let (u, v) = (t[k as usize], t[(k as usize + 1) % 3]);
                half.push(([u.min(v), u.max(v)], f as u32, k));
            }
        }
        half.sort_unstable();
        let mut out = Vec::new();
        let mut i = 0;
        while i < half.len() {
            let mut j = i + 1;
            while j < half.len() && half[j].0 == half[i].0 {
                j += 1;
            }
            if j - i == 2 {
                let (edge, f, k) = half[i];
                let (_, g, l) = half[i + 1];
                // The wedges of each end on both sides.
                let wedge_at = |f: u32, k: u8, v: u32| {
                    let t = mesh.triangles[f as usize];
                    let c = self.corners[f as usize];
                    if t[k as usize] == v {
                        c[k as usize]
                    } else {
                        c[(k as usize + 1) % 3]
                    }
                };
                let material_differs = self
                    .face_material
                    .as_ref()
                    .is_some_and(|m| m[f as usize] != m[g as usize]);
                let seam = material_differs
                    || edge
                        .iter()
                        .any(|&v| !self.same_values(wedge_at(f, k, v), wedge_at(g, l, v)));
                out.push(EdgeSides {
                    edge,
                    faces: [f, g],
                    seam,
                });
            }
            i = j;
        }
        out
    }

    /// Charts: the triangles joined through edges that are not seams (each triangle's chart
    /// number, numbered from 0 in order of the first triangle). Within a chart the attributes
    /// are continuous.
    pub fn charts(&self, mesh: &TriMesh) -> Vec<u32> {
        charts_of(&self.edge_sides(mesh), mesh.triangles.len())
    }

    /// Vertices with more than one distinct wedge value around them (on a seam).
    pub fn seam_vertices(&self, mesh: &TriMesh) -> Vec<bool> {
        let mut seam = vec![false; mesh.positions.len()];
        for [u, v] in self.seam_edges(mesh) {
            seam[u as usize] = true;
            seam[v as usize] = true;
        }
        seam
    }
}

/// An edge of two triangles.
pub(crate) struct EdgeSides {
    /// The edge's vertices, smaller first.
    pub(crate) edge: [u32; 2],
    /// The two triangles.
    pub(crate) faces: [u32; 2],
    /// Whether an attribute or the material changes across it.
    pub(crate) seam: bool,
}

/// Each of `faces` triangles' chart ([`Attributes::charts`]) from the edge `sides` of its mesh.
pub(crate) fn charts_of(sides: &[EdgeSides], faces: usize) -> Vec<u32> {
    let mut sets = crate::topology::UnionFind::new(faces);
    for e in sides {
        if !e.seam {
            sets.union(e.faces[0], e.faces[1]);
        }
    }
    let mut label = vec![u32::MAX; faces];
    let mut chart = Vec::with_capacity(faces);
    let mut next = 0u32;
    for f in 0..faces as u32 {
        let root = sets.find(f) as usize;
        if label[root] == u32::MAX {
            label[root] = next;
            next += 1;
        }
        chart.push(label[root]);
    }
    chart
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square of two triangles whose diagonal 0-2 is a UV seam.
    fn square() -> (TriMesh, Attributes) {
        let mesh = TriMesh::new(
            vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        let attributes = Attributes {
            wedge_vertex: vec![0, 1, 2, 0, 2, 3],
            corners: vec![[0, 1, 2], [3, 4, 5]],
            uv0: Some(vec![
                Vec2::ZERO,
                Vec2::X,
                Vec2::ONE,
                Vec2::splat(5.0),
                Vec2::splat(6.0),
                Vec2::Y,
            ]),
            ..Attributes::default()
        };
        (mesh, attributes)
    }

    #[test]
    fn seams_and_charts() {
        let (mesh, a) = square();
        a.validate(&mesh).unwrap();
        assert_eq!(a.seam_edges(&mesh), vec![[0, 2]]);
        assert_eq!(a.charts(&mesh), vec![0, 1]);
        assert_eq!(a.seam_vertices(&mesh), vec![true, false, true, false]);
        // Same values on both sides: no seam, one chart.
        let mut b = a.clone();
        b.uv0.as_mut().unwrap()[3] = Vec2::ZERO;
        b.uv0.as_mut().unwrap()[4] = Vec2::ONE;
        assert!(b.seam_edges(&mesh).is_empty());
        assert_eq!(b.charts(&mesh), vec![0, 0]);
        b.compact();
        assert_eq!(b.wedge_count(), 4);
        b.validate(&mesh).unwrap();
        // A material change is a seam too.
        b.face_material = Some(vec![0, 1]);
        assert_eq!(b.seam_edges(&mesh), vec![[0, 2]]);
    }

    #[test]
    fn validate_names_the_problem() {
        let (mesh, a) = square();
        let mut bad = a.clone();
        bad.corners[1][0] = 1;
        assert!(
            bad.validate(&mesh)
                .unwrap_err()
                .contains("corner 0 of triangle 1")
        );
        let mut bad = a.clone();
        bad.uv0.as_mut().unwrap().pop();
        assert_eq!(
            bad.validate(&mesh).unwrap_err(),
            "uv0: 5 values for 6 wedges"
        );
        let mut bad = a;
        bad.face_material = Some(vec![0]);
        assert!(
            bad.validate(&mesh)
                .unwrap_err()
                .contains("1 face materials")
        );
    }

    #[test]
    fn select_and_compact() {
        let (mesh, a) = square();
        let one = a.select_faces(&[false, true]);
        assert_eq!(one.corners, vec![[3, 4, 5]]);
        let mut one = one;
        one.compact();
        assert_eq!(one.wedge_vertex, vec![0, 2, 3]);
        assert_eq!(one.corners, vec![[0, 1, 2]]);
        assert_eq!(one.uv0.unwrap()[1], Vec2::splat(6.0));
        let _ = mesh;
    }

    #[test]
    fn compact_merges_bit_identical_wedges_of_one_vertex_only() {
        // Vertex 0 has four wedges: 0 and 2 equal, 3 with -0.0 where 0 has 0.0 (bits differ),
        // 4 unused; vertex 1's wedge 1 holds the same values as wedge 0 (another vertex);
        // vertex 2's wedges 5 and 6 hold the same NaN bits.
        let nan = f32::from_bits(0x7fc0_0001);
        let mut a = Attributes {
            wedge_vertex: vec![0, 1, 0, 0, 0, 2, 2],
            corners: vec![[0, 1, 5], [2, 1, 6], [3, 1, 5]],
            uv0: Some(vec![
                Vec2::new(0.0, 0.5),
                Vec2::new(0.0, 0.5),
                Vec2::new(0.0, 0.5),
                Vec2::new(-0.0, 0.5),
                Vec2::new(9.0, 9.0),
                Vec2::new(nan, 1.0),
                Vec2::new(nan, 1.0),
            ]),
            ..Attributes::default()
        };
        a.compact();
        // Kept in wedge order: 0, 1, 3, 5; 2 → 0, 4 dropped, 6 → 5.
        assert_eq!(a.wedge_vertex, vec![0, 1, 0, 2]);
        assert_eq!(a.corners, vec![[0, 1, 3], [0, 1, 3], [2, 1, 3]]);
        let uv = a.uv0.unwrap();
        assert_eq!(uv[2].x.to_bits(), (-0.0f32).to_bits());
        assert_eq!(uv[3].x.to_bits(), nan.to_bits());
    }
}
