//! Growing uniform grid over the network's nodes for exact nearest and second-nearest queries
//! (after Fišer, Faigl and Kulich 2013): intrusive per-cell linked lists, O(1) insert, remove
//! and move, ring-by-ring search that stops once the two best candidates are closer than the
//! border of the scanned block of cells.

use glam::Vec3;

/// Marker for "no node" in the intrusive lists.
pub(crate) const NONE: u32 = u32::MAX;

/// Uniform grid over a fixed bounding box; cells hold intrusive doubly linked lists of nodes.
#[derive(Debug, Clone)]
pub(crate) struct Grid {
    /// Minimum corner of the gridded box.
    origin: Vec3,
    /// Extent of the gridded box (each component > 0).
    extent: Vec3,
    /// Side length of a cubic cell, model units.
    cell: f32,
    /// Reciprocal of `cell`.
    inv_cell: f32,
    /// Cell counts along x, y, z (each >= 1).
    dims: [i32; 3],
    /// First node of each cell's list.
    head: Vec<u32>,
    /// Next node in the same cell, per node slot.
    next: Vec<u32>,
    /// Previous node in the same cell, per node slot.
    prev: Vec<u32>,
    /// Cell holding each node slot (`NONE` when not in the grid).
    cell_of: Vec<u32>,
    /// Number of nodes currently in the grid.
    len: usize,
}

/// Result of a two-nearest query: slots and squared distances (`NONE`/infinity when missing).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Nearest2 {
    /// Nearest node slot.
    pub first: u32,
    /// Squared distance to `first`.
    pub first_d2: f32,
    /// Second-nearest node slot.
    pub second: u32,
    /// Squared distance to `second`.
    pub second_d2: f32,
}

impl Nearest2 {
    /// No candidate yet.
    pub const EMPTY: Nearest2 = Nearest2 {
        first: NONE,
        first_d2: f32::INFINITY,
        second: NONE,
        second_d2: f32::INFINITY,
    };

    /// Offer candidate `node` at squared distance `d2`.
    #[inline(always)]
    pub fn offer(&mut self, node: u32, d2: f32) {
        if d2 < self.second_d2 {
            if d2 < self.first_d2 {
                self.second = self.first;
                self.second_d2 = self.first_d2;
                self.first = node;
                self.first_d2 = d2;
            } else {
                self.second = node;
                self.second_d2 = d2;
            }
        }
    }
}

/// `x.floor() as i32` without the `floorf` library call that baseline x86-64 (no SSE4.1
/// `roundss`) emits for `f32::floor`: truncate, then step down for negative non-integers.
/// Saturates like `as i32` for values outside the `i32` range.
#[inline(always)]
fn floor_i32(x: f32) -> i32 {
    let t = x as i32;
    t - i32::from((t as f32) > x)
}

impl Grid {
    /// A grid over the box `[min, max]` with about `cells` cells (at least one).
    pub fn new(min: Vec3, max: Vec3, cells: usize) -> Grid {
        let diag = (max - min).length().max(1e-12);
        // Pad the box a little so points on its faces fall inside, and give flat boxes thickness.
        let pad = Vec3::splat(diag * 1e-4);
        let origin = min - pad;
        let extent = (max - min + 2.0 * pad).max(Vec3::splat(diag * 1e-3));
        let mut grid = Grid {
            origin,
            extent,
            cell: 1.0,
            inv_cell: 1.0,
            dims: [1, 1, 1],
            head: Vec::new(),
            next: Vec::new(),
            prev: Vec::new(),
            cell_of: Vec::new(),
            len: 0,
        };
        grid.set_resolution(cells);
        grid
    }

    /// Volume of the gridded box, model units cubed.
    pub fn volume(&self) -> f64 {
        self.extent.x as f64 * self.extent.y as f64 * self.extent.z as f64
    }

    /// Cell of node `slot` (`NONE` when absent).
    pub fn cell_of(&self, slot: u32) -> u32 {
        self.cell_of.get(slot as usize).copied().unwrap_or(NONE)
    }

    /// Drop every node and size the per-slot arrays for `slots` slots.
    pub fn clear(&mut self, slots: usize) {
        self.head.iter_mut().for_each(|h| *h = NONE);
        self.next.clear();
        self.prev.clear();
        self.cell_of.clear();
        self.next.resize(slots, NONE);
        self.prev.resize(slots, NONE);
        self.cell_of.resize(slots, NONE);
        self.len = 0;
    }

    /// Number of nodes stored.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Choose cubic cells so the box holds about `cells` of them and clear all lists.
    fn set_resolution(&mut self, cells: usize) {
        let cells = cells.clamp(1, 1 << 26) as f32;
        let volume = self.extent.x * self.extent.y * self.extent.z;
        let mut side = (volume / cells).cbrt();
        // Never more cells along an axis than requested in total.
        side = side.max(self.extent.max_element() / cells);
        let dims = (self.extent / side).ceil().max(Vec3::ONE);
        self.dims = [dims.x as i32, dims.y as i32, dims.z as i32];
        self.cell = side;
        self.inv_cell = 1.0 / side;
        let n = self.dims.iter().map(|&d| d as usize).product();
        self.head.clear();
        self.head.resize(n, NONE);
        self.cell_of.iter_mut().for_each(|c| *c = NONE);
        self.len = 0;
    }

    /// Rebuild with about `cells` cells and re-insert the given `(slot, position)` pairs.
    pub fn rebuild(&mut self, cells: usize, nodes: impl Iterator<Item = (u32, Vec3)>) {
        self.set_resolution(cells);
        for (slot, p) in nodes {
            self.insert(slot, p);
        }
    }

    /// Integer cell coordinates of `p`, clamped into the grid.
    #[inline(always)]
    fn coords(&self, p: Vec3) -> [i32; 3] {
        // Truncation equals floor for the non-negative values that matter; negatives clamp to 0.
        let c = (p - self.origin) * self.inv_cell;
        [
            (c.x as i32).max(0).min(self.dims[0] - 1),
            (c.y as i32).max(0).min(self.dims[1] - 1),
            (c.z as i32).max(0).min(self.dims[2] - 1),
        ]
    }

    /// Linear cell index of integer coordinates.
    #[inline(always)]
    fn index(&self, c: [i32; 3]) -> u32 {
        ((c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]) as u32
    }

    /// Make sure per-slot arrays cover `slot`.
    #[inline]
    fn ensure_slot(&mut self, slot: u32) {
        let need = slot as usize + 1;
        if self.next.len() < need {
            self.next.resize(need, NONE);
            self.prev.resize(need, NONE);
            self.cell_of.resize(need, NONE);
        }
    }

    /// Add node `slot` at position `p`.
    pub fn insert(&mut self, slot: u32, p: Vec3) {
        self.ensure_slot(slot);
        let cell = self.index(self.coords(p));
        self.link(slot, cell);
        self.len += 1;
    }

    #[inline(always)]
    fn link(&mut self, slot: u32, cell: u32) {
        let s = slot as usize;
        let h = self.head[cell as usize];
        self.next[s] = h;
        self.prev[s] = NONE;
        if h != NONE {
            self.prev[h as usize] = slot;
        }
        self.head[cell as usize] = slot;
        self.cell_of[s] = cell;
    }

    #[inline(always)]
    fn unlink(&mut self, slot: u32) {
        let s = slot as usize;
        let (n, p) = (self.next[s], self.prev[s]);
        if p != NONE {
            self.next[p as usize] = n;
        } else {
            self.head[self.cell_of[s] as usize] = n;
        }
        if n != NONE {
            self.prev[n as usize] = p;
        }
        self.cell_of[s] = NONE;
    }

    /// Remove node `slot` (no-op when absent).
    pub fn remove(&mut self, slot: u32) {
        if (slot as usize) < self.cell_of.len() && self.cell_of[slot as usize] != NONE {
            self.unlink(slot);
            self.len -= 1;
        }
    }

    /// Node `slot` moved to `p`: relink it when its cell changed.
    #[inline(always)]
    pub fn moved(&mut self, slot: u32, p: Vec3) {
        let cell = self.index(self.coords(p));
        if cell != self.cell_of[slot as usize] {
            self.unlink(slot);
            self.link(slot, cell);
        }
    }

    /// Exact nearest and second-nearest nodes to `q` among those in the grid.
    ///
    /// Scans blocks of 2k x 2k x 2k cells (k = 1, 2, ...) placed so that `q` lies in the central
    /// two cells of each axis, which puts every block border at least (k - 1/2) cells away; it
    /// stops once the second-best distance is within that border.
    #[inline]
    pub fn nearest2(&self, q: Vec3, positions: &[Vec3]) -> Nearest2 {
        let mut best = Nearest2::EMPTY;
        let u = (q - self.origin) * self.inv_cell - Vec3::splat(0.5);
        // Lower cell of the central pair on each axis (may be -1 or dims-1 at the grid border).
        let b = [
            floor_i32(u.x).max(-1).min(self.dims[0] - 1),
            floor_i32(u.y).max(-1).min(self.dims[1] - 1),
            floor_i32(u.z).max(-1).min(self.dims[2] - 1),
        ];
        let mut k = 1i32;
        loop {
            self.scan_block_shell(b, k, q, positions, &mut best);
            // Distance from q to the border of the block; sides at the grid boundary do not count.
            let mut border = f32::INFINITY;
            for axis in 0..3 {
                let lo_cell = b[axis] - (k - 1);
                let hi_cell = b[axis] + k;
                if lo_cell > 0 {
                    let lo = self.origin[axis] + lo_cell as f32 * self.cell;
                    border = border.min(q[axis] - lo);
                }
                if hi_cell < self.dims[axis] - 1 {
                    let hi = self.origin[axis] + (hi_cell + 1) as f32 * self.cell;
                    border = border.min(hi - q[axis]);
                }
            }
            if border == f32::INFINITY {
                return best;
            }
            let border = border.max(0.0);
            if best.second_d2 <= border * border {
                return best;
            }
            if best.second_d2.is_finite() {
                // Both candidates known: the true answers lie within their radius, so visit the
                // remaining cells that the sphere touches, pruned by their distance to q.
                self.scan_sphere_rest(b, k, q, positions, &mut best);
                return best;
            }
            k += 1;
        }
    }

    /// Visit cells outside block `k` that intersect the sphere of radius sqrt(second_d2) about
    /// `q`, skipping cells farther than the (shrinking) second-best distance.
    #[inline(always)]
    fn scan_sphere_rest(
        &self,
        b: [i32; 3],
        k: i32,
        q: Vec3,
        positions: &[Vec3],
        best: &mut Nearest2,
    ) {
        let r = best.second_d2.sqrt();
        let u = (q - self.origin) * self.inv_cell;
        let range = |a: usize| {
            let lo = floor_i32(u[a] - r * self.inv_cell)
                .max(0)
                .min(self.dims[a] - 1);
            let hi = floor_i32(u[a] + r * self.inv_cell)
                .max(0)
                .min(self.dims[a] - 1);
            (lo, hi)
        };
        // Squared distance from q to the slab of cell index i along axis a.
        let gap = |a: usize, i: i32| {
            let lo = self.origin[a] + i as f32 * self.cell;
            let d = (lo - q[a]).max(q[a] - (lo + self.cell)).max(0.0);
            d * d
        };
        let inside = |a: usize, v: i32| v >= b[a] - (k - 1) && v <= b[a] + k;
        let (x0, x1) = range(0);
        let (y0, y1) = range(1);
        let (z0, z1) = range(2);
        for z in z0..=z1 {
            let gz = gap(2, z);
            if gz >= best.second_d2 {
                continue;
            }
            for y in y0..=y1 {
                let gy = gz + gap(1, y);
                if gy >= best.second_d2 {
                    continue;
                }
                let yz_inside = inside(2, z) && inside(1, y);
                let row = ((z * self.dims[1] + y) * self.dims[0]) as usize;
                for x in x0..=x1 {
                    if yz_inside && inside(0, x) {
                        continue;
                    }
                    if gy + gap(0, x) < best.second_d2 {
                        self.scan_cell(row + x as usize, q, positions, best);
                    }
                }
            }
        }
    }

    /// Offer every node in block k = cells `[b - (k-1), b + k]` per axis minus block k - 1.
    #[inline(always)]
    fn scan_block_shell(
        &self,
        b: [i32; 3],
        k: i32,
        q: Vec3,
        positions: &[Vec3],
        best: &mut Nearest2,
    ) {
        let lo = |a: usize| (b[a] - (k - 1)).max(0);
        let hi = |a: usize| (b[a] + k).min(self.dims[a] - 1);
        let inner = |a: usize, v: i32| k > 1 && v >= b[a] - (k - 2) && v < b[a] + k;
        let (x0, x1) = (lo(0), hi(0));
        let (xa, xb) = (b[0] - (k - 1), b[0] + k);
        for z in lo(2)..=hi(2) {
            let z_in = inner(2, z);
            for y in lo(1)..=hi(1) {
                let row = ((z * self.dims[1] + y) * self.dims[0]) as usize;
                if z_in && inner(1, y) {
                    if xa >= 0 {
                        self.scan_cell(row + xa as usize, q, positions, best);
                    }
                    if xb < self.dims[0] {
                        self.scan_cell(row + xb as usize, q, positions, best);
                    }
                } else {
                    for x in x0..=x1 {
                        self.scan_cell(row + x as usize, q, positions, best);
                    }
                }
            }
        }
    }

    #[inline(always)]
    fn scan_cell(&self, cell: usize, q: Vec3, positions: &[Vec3], best: &mut Nearest2) {
        let mut n = self.head[cell];
        while n != NONE {
            let d2 = (positions[n as usize] - q).length_squared();
            best.offer(n, d2);
            n = self.next[n as usize];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_i32_matches_floor() {
        for x in [
            -2.5f32,
            -2.0,
            -1.0,
            -0.75,
            -0.0,
            0.0,
            0.25,
            1.0,
            1.5,
            7.999,
            1e6 + 0.5,
        ] {
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
        }
        let mut s = 3u64;
        for _ in 0..10_000 {
            let x = (lcg(&mut s) - 0.5) * 200.0;
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
        }
    }

    fn lcg(state: &mut u64) -> f32 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 40) as f32 / (1u64 << 24) as f32
    }

    #[test]
    fn grid_matches_linear_scan_after_moves_and_removals() {
        let mut s = 7u64;
        let mut pts: Vec<Vec3> = (0..500)
            .map(|_| Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s) * 0.2))
            .collect();
        let mut grid = Grid::new(Vec3::ZERO, Vec3::new(1.0, 1.0, 0.2), 64);
        for (i, p) in pts.iter().enumerate() {
            grid.insert(i as u32, *p);
        }
        let mut alive = vec![true; pts.len()];
        for i in (0..500).step_by(3) {
            grid.remove(i as u32);
            alive[i] = false;
        }
        for i in (1..500).step_by(7) {
            pts[i] = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s) * 0.2);
            if alive[i] {
                grid.moved(i as u32, pts[i]);
            }
        }
        grid.rebuild(
            900,
            (0..500)
                .filter(|&i| alive[i])
                .map(|i| (i as u32, pts[i]))
                .collect::<Vec<_>>()
                .into_iter(),
        );
        for _ in 0..300 {
            let q = Vec3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s) * 0.2);
            let got = grid.nearest2(q, &pts);
            let mut want = Nearest2::EMPTY;
            for (i, p) in pts.iter().enumerate() {
                if alive[i] {
                    want.offer(i as u32, (*p - q).length_squared());
                }
            }
            assert_eq!(got.first_d2, want.first_d2);
            assert_eq!(got.second_d2, want.second_d2);
        }
    }
}
