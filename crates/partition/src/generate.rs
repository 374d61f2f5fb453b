//! The test surface of any size: a sphere displaced by octaves of smooth value noise, written
//! as binary little-endian PLY while it is generated (one ring of vertices at a time, then the
//! faces by formula), so a mesh of a billion faces needs no more memory than one of a hundred.
//!
//! Steps of [`write_displaced_sphere`]:
//! 1. **Grid**: a UV sphere of `rows` latitude bands and `cols` meridians, the pair whose face
//!    count `2 · cols · (rows − 1)` is nearest the request with `cols ≈ 2 (rows − 1)` (near
//!    square cells at the equator) ([`SphereGrid::for_faces`]).
//! 2. **Vertices**: the north pole, the rings from north to south, the south pole; each at radius
//!    `1 + Σ aₒ · noise(2ᵒ⁺¹ · direction)`, octaves down to the grid's spacing, amplitudes falling
//!    by 0.55 an octave. The radius is a function of the direction, so the surface is a radial
//!    graph: closed, manifold and never self-intersecting whatever the noise.
//! 3. **Faces**: the pole fans and two triangles per cell between rings, outward oriented.

use crate::PartitionError;
use std::io::{BufWriter, Write};
use std::path::Path;

/// The UV-sphere grid of a generated surface and its counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SphereGrid {
    /// Latitude bands (pole to pole); the rings of vertices are `rows − 1`.
    pub rows: usize,
    /// Vertices per ring.
    pub cols: usize,
}

impl SphereGrid {
    /// The grid whose face count is nearest `faces` (at least 12 faces: 2 bands of 3 meridians).
    ///
    /// ```
    /// use partition::generate::SphereGrid;
    /// assert_eq!(SphereGrid::for_faces(90_000).faces(), 90_000); // 150 bands of 300
    /// let grid = SphereGrid::for_faces(100_000); // the nearest: 158 bands of 316
    /// assert_eq!(grid.faces(), 99_856);
    /// assert_eq!(grid.vertices(), grid.faces() / 2 + 2); // Euler: closed genus 0
    /// ```
    pub fn for_faces(faces: usize) -> SphereGrid {
        // faces = 2 · cols · (rows − 1) with cols = 2 (rows − 1): rows − 1 = sqrt(faces / 4).
        let bands = ((faces as f64 / 4.0).sqrt().round() as usize).max(1);
        let cols = ((faces as f64 / (2 * bands) as f64).round() as usize).max(3);
        SphereGrid {
            rows: bands + 1,
            cols,
        }
    }

    /// Vertices: two poles and `rows − 1` rings of `cols`.
    pub fn vertices(&self) -> usize {
        2 + (self.rows - 1) * self.cols
    }

    /// Faces: `2 · cols · (rows − 1)`.
    pub fn faces(&self) -> usize {
        2 * self.cols * (self.rows - 1)
    }
}

/// Amplitude of the first noise octave (radius 1): the sum over all octaves stays below
/// 0.15 / (1 − 0.55) = 0.33, so the radius stays in [0.67, 1.33].
const FIRST_AMPLITUDE: f64 = 0.15;
/// Amplitude ratio of consecutive octaves (frequency ratio 2): a little above 1/2, so the
/// finest octaves still show at the grid's spacing (detail at every scale).
const PERSISTENCE: f64 = 0.55;

/// Write the displaced sphere with the face count nearest `faces` ([`SphereGrid::for_faces`])
/// to `path` as binary little-endian PLY (`float x y z`, `list uchar int vertex_indices`),
/// written to a temporary sibling and renamed; the same `seed` gives the same bytes.
pub fn write_displaced_sphere(
    path: &Path,
    faces: usize,
    seed: u64,
) -> Result<SphereGrid, PartitionError> {
    let grid = SphereGrid::for_faces(faces);
    let tmp = crate::chunk::temporary_sibling(path);
    let io = |source| PartitionError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(&tmp).map_err(io)?;
    let mut out = BufWriter::with_capacity(1 << 20, file);
    write_sphere(&mut out, grid, seed)
        .and_then(|()| out.flush())
        .map_err(io)?;
    drop(out);
    std::fs::rename(&tmp, path).map_err(io)?;
    Ok(grid)
}

/// Steps 2 and 3 of the module: the PLY bytes of `grid` into `out`.
fn write_sphere(out: &mut impl Write, grid: SphereGrid, seed: u64) -> std::io::Result<()> {
    let SphereGrid { rows, cols } = grid;
    write!(
        out,
        "ply\nformat binary_little_endian 1.0\ncomment gng3d-partition displaced sphere \
         rows {rows} cols {cols} seed {seed}\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        grid.vertices(),
        grid.faces()
    )?;
    // Octaves from wavelength ~ the sphere down to ~ the grid's spacing (π / rows).
    let octaves = (rows as f64).log2().ceil() as u32 + 1;
    let noise = Noise { seed };
    let mut vertex = |dir: [f64; 3]| -> std::io::Result<()> {
        let mut radius = 1.0;
        let (mut amplitude, mut frequency) = (FIRST_AMPLITUDE, 2.0);
        for octave in 0..octaves {
            let p = dir.map(|c| c * frequency);
            radius += amplitude * (2.0 * noise.at(p, octave) - 1.0);
            amplitude *= PERSISTENCE;
            frequency *= 2.0;
        }
        for c in dir {
            out.write_all(&((c * radius) as f32).to_le_bytes())?;
        }
        Ok(())
    };
    vertex([0.0, 1.0, 0.0])?;
    for r in 1..rows {
        let theta = std::f64::consts::PI * r as f64 / rows as f64;
        for c in 0..cols {
            let phi = std::f64::consts::TAU * c as f64 / cols as f64;
            vertex([
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ])?;
        }
    }
    vertex([0.0, -1.0, 0.0])?;
    let south = (grid.vertices() - 1) as u32;
    let ring = |r: usize, c: usize| (1 + (r - 1) * cols + c % cols) as u32;
    let mut face = |t: [u32; 3]| -> std::io::Result<()> {
        out.write_all(&[3])?;
        for v in t {
            out.write_all(&v.to_le_bytes())?;
        }
        Ok(())
    };
    for c in 0..cols {
        face([0, ring(1, c + 1), ring(1, c)])?;
    }
    for r in 1..rows - 1 {
        for c in 0..cols {
            let (a, b) = (ring(r, c), ring(r, c + 1));
            let (d, e) = (ring(r + 1, c), ring(r + 1, c + 1));
            face([a, e, d])?;
            face([a, b, e])?;
        }
    }
    for c in 0..cols {
        face([ring(rows - 1, c), ring(rows - 1, c + 1), south])?;
    }
    Ok(())
}

/// Smooth value noise: seeded hash values on the integer lattice, interpolated with the C¹
/// smoothstep, in [0, 1].
struct Noise {
    seed: u64,
}

impl Noise {
    fn at(&self, p: [f64; 3], octave: u32) -> f64 {
        let cell = p.map(|c| c.floor());
        let f = [0, 1, 2].map(|i| {
            let t = p[i] - cell[i];
            t * t * (3.0 - 2.0 * t)
        });
        let base = cell.map(|c| c as i64);
        let mut sum = 0.0;
        for corner in 0..8u32 {
            let mut weight = 1.0;
            let mut key = [0i64; 3];
            for i in 0..3 {
                let bit = (corner >> i) & 1;
                key[i] = base[i] + bit as i64;
                weight *= if bit == 1 { f[i] } else { 1.0 - f[i] };
            }
            sum += weight * self.lattice(key, octave);
        }
        sum
    }

    /// The value at a lattice point: SplitMix64 of the point, octave and seed, in [0, 1).
    fn lattice(&self, key: [i64; 3], octave: u32) -> f64 {
        let mut z = self.seed ^ u64::from(octave).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        for k in key {
            z = (z ^ k as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
        }
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}
