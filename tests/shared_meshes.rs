//! Loads every mesh in `$GNG3D_MESHES` and checks counts, boundary, topology and size against
//! the table in `$GNG3D_MESHES/README.md`, parsed at test time. Fails when `CI` is set and the
//! folder is missing; otherwise skips with a message.

use gng3d::mesh;
use std::path::Path;

/// One row of the README table.
#[derive(Debug)]
struct Expected {
    file: String,
    vertices: usize,
    faces: usize,
    boundary_edges: usize,
    boundary_loops: usize,
    non_manifold_vertices: usize,
    genus: i64,
    euler: i64,
    bbox_diagonal: f64,
}

fn int(text: &str) -> i64 {
    text.trim()
        .replace(',', "")
        .parse()
        .unwrap_or_else(|_| panic!("not an integer: {text:?}"))
}

/// The number right before `word` in `text` (e.g. "556 edges" → 556), or 0 if absent.
fn count_before(text: &str, word: &str) -> usize {
    let words: Vec<&str> = text
        .split(|c: char| c.is_whitespace() || c == ';' || c == '/')
        .collect();
    words
        .windows(2)
        .find(|w| w[1].starts_with(word))
        .map_or(0, |w| int(w[0]) as usize)
}

fn parse_table(readme: &str) -> Vec<Expected> {
    readme
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|line| {
            let cells: Vec<&str> = line
                .trim()
                .trim_matches('|')
                .split('|')
                .map(str::trim)
                .collect();
            assert_eq!(cells.len(), 13, "unexpected table row: {line}");
            let boundary = cells[7];
            let (boundary_edges, boundary_loops) = if boundary.starts_with("boundary:") {
                (
                    count_before(boundary, "edges"),
                    count_before(boundary, "loops"),
                )
            } else {
                assert!(boundary.starts_with("closed"), "{boundary}");
                (0, 0)
            };
            Expected {
                file: cells[0].trim_matches('`').to_string(),
                vertices: int(cells[5]) as usize,
                faces: int(cells[6]) as usize,
                boundary_edges,
                boundary_loops,
                non_manifold_vertices: count_before(boundary, "non-manifold"),
                genus: int(cells[8]),
                euler: int(cells[9].split_whitespace().next().unwrap()),
                bbox_diagonal: cells[10].replace(',', "").parse().unwrap(),
            }
        })
        .collect()
}

#[test]
fn shared_meshes_match_the_readme_table() {
    let Some(dir) = mesh::fixtures::shared_meshes_dir("README.md") else {
        return;
    };
    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let table = parse_table(&readme);
    assert!(table.len() >= 14, "README table has {} rows", table.len());
    // Every mesh file in the folder has a row, and every row has a file.
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| mesh::io::Format::from_path(Path::new(n)).is_some())
        .collect();
    files.sort();
    let mut rows: Vec<String> = table.iter().map(|e| e.file.clone()).collect();
    rows.sort();
    assert_eq!(files, rows);

    for e in &table {
        let loaded = mesh::io::load(&dir.join(&e.file)).unwrap_or_else(|err| panic!("{err}"));
        let m = &loaded.mesh;
        // Data the loader does not read (many_small_holes.ply's vertex `quality`) is named in a
        // warning; nothing is repaired or dropped from the mesh itself.
        let repairs: Vec<_> = (loaded.warnings.iter())
            .filter(|w| !matches!(w, mesh::error::MeshWarning::IgnoredData { .. }))
            .collect();
        assert!(repairs.is_empty(), "{}: {:?}", e.file, loaded.warnings);
        let t = mesh::topology::analyze(m);
        let got = (
            t.vertices,
            t.faces,
            t.boundary_edges,
            t.boundary_loops,
            t.non_manifold_vertices,
            t.non_manifold_edges,
            t.genus,
            t.euler_characteristic,
        );
        let want = (
            e.vertices,
            e.faces,
            e.boundary_edges,
            e.boundary_loops,
            e.non_manifold_vertices,
            0,
            Some(e.genus),
            e.euler,
        );
        assert_eq!(got, want, "{}", e.file);
        // The README gives six significant digits.
        let rel = (m.bbox_diagonal() - e.bbox_diagonal).abs() / e.bbox_diagonal;
        assert!(
            rel < 1e-5,
            "{}: bbox diagonal {} vs {}",
            e.file,
            m.bbox_diagonal(),
            e.bbox_diagonal
        );
    }
}

#[test]
fn table_parser_reads_boundary_descriptions() {
    assert_eq!(
        count_before(
            "boundary: 556 edges / 32 loops; 6 non-manifold vertices",
            "edges"
        ),
        556
    );
    assert_eq!(
        count_before(
            "boundary: 556 edges / 32 loops; 6 non-manifold vertices",
            "loops"
        ),
        32
    );
    assert_eq!(
        count_before("closed; 1 non-manifold vertex", "non-manifold"),
        1
    );
    assert_eq!(count_before("closed", "non-manifold"), 0);
    assert_eq!(int("1,074,744"), 1_074_744);
}
