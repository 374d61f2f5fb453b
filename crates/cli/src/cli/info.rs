//! `gng3d info`: counts, topology, area and size of one mesh, as stored in the file (no
//! welding; degenerate and duplicate faces are dropped with a warning by the loader).

use clap::Args;
use mesh::topology::{TopologyReport, analyze};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `gng3d info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// Mesh file (.obj, .ply, .stl, .gltf, .glb).
    pub mesh: PathBuf,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What `gng3d info` prints; the first eight keys are the documented contract.
#[derive(Debug, Serialize)]
struct Info {
    vertices: usize,
    faces: usize,
    boundary_edges: usize,
    non_manifold_edges: usize,
    components: usize,
    genus: Option<i64>,
    /// Surface area in squared model units.
    area: f64,
    /// Diagonal of the bounding box of referenced vertices, in model units.
    bbox_diagonal: f64,
    referenced_vertices: usize,
    edges: usize,
    boundary_loops: usize,
    non_manifold_vertices: usize,
    euler_characteristic: i64,
    closed: bool,
    manifold: bool,
    has_vertex_normals: bool,
    /// Normals, texture coordinates, colours and materials, when the file has any.
    #[serde(skip_serializing_if = "Option::is_none")]
    attributes: Option<AttributeInfo>,
    load_seconds: f64,
    warnings: Vec<String>,
}

/// The attributes of a mesh with any (`--json`'s `attributes`).
#[derive(Debug, Serialize)]
struct AttributeInfo {
    /// Attribute names as `simplify --json` lists them (`normals`, `uv0`, `uv1`, `colors`,
    /// `materials`).
    names: Vec<mesh::AttributeKind>,
    /// Attribute sets (a vertex on a seam has one per side).
    wedges: usize,
    /// Edges across which a value or the material changes.
    seam_edges: usize,
    /// Regions of triangles joined across edges that are not seams.
    charts: usize,
    /// Material names, in the file's order.
    materials: Vec<String>,
}

/// Run `gng3d info`.
pub fn run(args: InfoArgs) -> anyhow::Result<()> {
    let start = std::time::Instant::now();
    // MeshError names the file already; no extra context, so the path is said once.
    crate::process::working_on(&args.mesh);
    let loaded = mesh::io::load(&args.mesh)?;
    let load_seconds = start.elapsed().as_secs_f64();
    let m = &loaded.mesh;
    let t: TopologyReport = analyze(m);
    let info = Info {
        vertices: t.vertices,
        faces: t.faces,
        boundary_edges: t.boundary_edges,
        non_manifold_edges: t.non_manifold_edges,
        components: t.components,
        genus: t.genus,
        area: m.area(),
        bbox_diagonal: m.bbox_diagonal(),
        referenced_vertices: t.referenced_vertices,
        edges: t.edges,
        boundary_loops: t.boundary_loops,
        non_manifold_vertices: t.non_manifold_vertices,
        euler_characteristic: t.euler_characteristic,
        closed: t.closed,
        manifold: t.manifold,
        has_vertex_normals: loaded.vertex_normals.is_some(),
        attributes: loaded.attributes.as_ref().map(|a| AttributeInfo {
            names: a.kinds(),
            wedges: a.wedge_count(),
            seam_edges: a.seam_edges(m).len(),
            charts: a
                .charts(m)
                .iter()
                .map(|&c| c as usize + 1)
                .max()
                .unwrap_or(0),
            materials: loaded
                .materials
                .as_ref()
                .map(|mats| mats.names.clone())
                .unwrap_or_default(),
        }),
        load_seconds,
        warnings: loaded.warnings.iter().map(|w| w.to_string()).collect(),
    };
    if args.json {
        return super::print_json(&info);
    }
    let genus = info
        .genus
        .map_or_else(|| "undefined".to_string(), |g| g.to_string());
    outln!("file                  {}", args.mesh.display());
    outln!("vertices              {}", info.vertices);
    outln!("referenced vertices   {}", info.referenced_vertices);
    outln!("faces                 {}", info.faces);
    outln!("edges                 {}", info.edges);
    outln!(
        "boundary edges        {} ({} loop(s))",
        info.boundary_edges,
        info.boundary_loops
    );
    outln!("non-manifold edges    {}", info.non_manifold_edges);
    outln!("non-manifold vertices {}", info.non_manifold_vertices);
    outln!("components            {}", info.components);
    outln!("euler characteristic  {}", info.euler_characteristic);
    outln!("genus                 {genus}");
    outln!(
        "closed                {}",
        if info.closed { "yes" } else { "no" }
    );
    outln!(
        "manifold              {}",
        if info.manifold { "yes" } else { "no" }
    );
    outln!(
        "area                  {} units²",
        gng3d::report::eng(info.area)
    );
    outln!(
        "bbox diagonal         {} units",
        gng3d::report::eng(info.bbox_diagonal)
    );
    if let Some(a) = &info.attributes {
        outln!(
            "attributes            {} ({} wedges, {} seam edges, {} charts)",
            mesh::AttributeKind::list(&a.names),
            a.wedges,
            a.seam_edges,
            a.charts
        );
        if !a.materials.is_empty() {
            outln!("materials             {}", a.materials.join(", "));
        }
    }
    outln!("load time             {:.3} s", info.load_seconds);
    for w in &info.warnings {
        outln!("warning: {w}");
    }
    Ok(())
}
