//! The grid of cells: sized from a sample of the vertex positions so that the fullest cell's
//! faces fit the memory budget.

/// Bytes a face takes while `qem::simplify` runs on a cell (measured ~160 B on 17.2M faces:
/// 2.7 GB), plus the cell's own copy of its mesh.
pub(crate) const BYTES_PER_FACE: u64 = 200;
/// At most this many cells: pass 2 keeps one open file and one write buffer per cell.
pub(crate) const MAX_CELLS: usize = 256;
/// Positions sampled in pass 1 to size the grid (every `n / SAMPLE`-th vertex).
pub(crate) const SAMPLE: usize = 1 << 18;

/// A regular grid over a box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Grid {
    pub(crate) min: [f64; 3],
    /// Cell edge length.
    pub(crate) size: f64,
    pub(crate) dims: [u32; 3],
}

impl Grid {
    /// The cell of `p` (points outside the box are clamped into it).
    pub(crate) fn cell(&self, p: [f64; 3]) -> u16 {
        let mut k = 0usize;
        for i in (0..3).rev() {
            let d = self.dims[i] as usize;
            let c = ((p[i] - self.min[i]) / self.size)
                .floor()
                .clamp(0.0, (d - 1) as f64) as usize;
            k = k * d + c;
        }
        k as u16
    }

    /// Cells in all.
    pub(crate) fn len(&self) -> usize {
        self.dims.iter().map(|&d| d as usize).product()
    }

    /// The coarsest grid of cubic cells over `[min, max]` whose fullest cell, estimated from
    /// `sample` (each point standing for `weight` vertices, a vertex for `faces_per_vertex`
    /// faces), holds at most `max_faces` faces; at most [`MAX_CELLS`] cells.
    pub(crate) fn sized(
        min: [f64; 3],
        max: [f64; 3],
        sample: &[[f64; 3]],
        faces_per_sample: f64,
        max_faces: f64,
    ) -> Grid {
        let extent = [0, 1, 2].map(|i| (max[i] - min[i]).max(0.0));
        let longest = extent
            .iter()
            .cloned()
            .fold(0.0, f64::max)
            .max(f64::MIN_POSITIVE);
        let mut best = Grid {
            min,
            size: longest * (1.0 + 1e-9),
            dims: [1, 1, 1],
        };
        // Cells along the longest axis, 1, 2, 3, …: the first grid whose fullest cell fits.
        for k in 1..=MAX_CELLS {
            let size = longest / k as f64 * (1.0 + 1e-9);
            let dims = extent.map(|e| ((e / size).ceil() as u32).max(1));
            let grid = Grid { min, size, dims };
            if grid.len() > MAX_CELLS {
                break;
            }
            best = grid;
            let mut counts = vec![0u32; grid.len()];
            for &p in sample {
                counts[grid.cell(p) as usize] += 1;
            }
            let fullest = counts.iter().copied().max().unwrap_or(0) as f64;
            if fullest * faces_per_sample <= max_faces {
                break;
            }
        }
        best
    }
}
