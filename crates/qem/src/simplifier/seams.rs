//! The seam rules of an attribute run ([`Seams`]): which pairs the seams allow, which end of a
//! pair stays, how the sides of the two ends match, and the seams' update after a contraction.

/// The attribute seams of a run that keeps attributes: a seam vertex (on exactly two seam
/// edges; seam ends and crossings are fixed) moves only along its seam, contracted with one of
/// its two seam neighbours, or into a fixed one, which stays where it is (meshoptimizer's seam
/// vertex collapsing onto a locked one along its loop); a vertex off the seams is contracted with
/// another vertex off the seams, or into a seam vertex, which then stays where it is (as
/// meshoptimizer lets a manifold vertex collapse onto a seam vertex). So every triangle stays on
/// one side of every seam and the seams are simplified along themselves down to the edges between
/// their fixed vertices.
pub(super) struct Seams {
    /// Per vertex: on a seam.
    pub(super) seam: Vec<bool>,
    /// Per seam vertex: its two neighbours along the seam.
    pub(super) along: Vec<[u32; 2]>,
}

impl Seams {
    /// Whether `a` and `b` may be contracted. The test of two seam vertices out of line: most
    /// pairs have an end off the seams, and the whole test as a call was 14.0 M instructions on
    /// the 268k-face igea atlas at 10 % (1.0 M calls; 2.4 M now, callgrind).
    #[inline(always)]
    pub(super) fn pair_ok(&self, a: usize, b: usize) -> bool {
        !(self.seam[a] && self.seam[b]) || self.seam_pair_ok(a, b)
    }

    /// [`Seams::pair_ok`] for two seam vertices.
    #[inline(never)]
    fn seam_pair_ok(&self, a: usize, b: usize) -> bool {
        match (self.seam[a], self.seam[b]) {
            (false, false) => true,
            (true, true) if self.is_fixed(a) || self.is_fixed(b) => {
                // A movable seam vertex into a fixed one next to it along its seam (the fixed
                // one stays, [`Seams::anchor`]). Without this rule each seam between two fixed
                // vertices kept a vertex inside: a 10,000-face atlas of 190 charts stopped at
                // 1,616 faces, `no_valid_pairs` (docs/notes/attributes.md, "Seams that bend").
                let (m, f) = if self.is_fixed(a) { (b, a) } else { (a, b) };
                let n = self.along[m];
                let x = if n[0] == f as u32 { n[1] } else { n[0] };
                !self.is_fixed(m)
                    && n.contains(&(f as u32))
                    && n[0] != n[1]
                    // A seam loop of three (f, m, x) would fold onto the edge f-x.
                    && !self.along.get(x as usize).is_some_and(|nx| nx.contains(&(f as u32)))
            }
            (true, true) => {
                let (na, nb) = (self.along[a], self.along[b]);
                let other = |n: [u32; 2], v: usize| {
                    if n[0] == v as u32 { n[1] } else { n[0] }
                };
                na.contains(&(b as u32))
                    && nb.contains(&(a as u32))
                    && na[0] != na[1]
                    && nb[0] != nb[1]
                    // A seam loop of three would fold onto itself.
                    && other(na, b) != other(nb, a)
            }
            // Off the seams into a seam vertex, which stays. Without this rule the faces next
            // to a seam could not be simplified at all: spot at 586 faces had 1.40 × the
            // positions-only run's Hausdorff distance and 1.71 × its mean distance
            // (docs/notes/attributes.md, "Values from the contractions"). A fixed seam vertex
            // (an end, a crossing, a pole) takes them too ([`Seams::is_fixed`]): spot at 292
            // faces had 1.35 × meshoptimizer's Hausdorff distance without.
            (true, false) | (false, true) => true,
        }
    }

    /// Whether seam vertex `v` is fixed: a seam end, a crossing, or a vertex whose values differ
    /// around it without a seam (a pole). It is never contracted, and keeps its corners' input
    /// wedges; a vertex off the seams may still be contracted into it.
    #[inline]
    pub(super) fn is_fixed(&self, v: usize) -> bool {
        self.seam[v] && self.along[v][0] == u32::MAX
    }

    /// For a pair the seams allow: the vertex that must survive and stay where it is (the seam
    /// vertex of a pair with one end off the seams, the fixed vertex of a pair along a seam), if
    /// any.
    #[inline]
    pub(super) fn anchor(&self, a: usize, b: usize) -> Option<usize> {
        match (self.seam[a], self.seam[b]) {
            (true, false) => Some(a),
            (false, true) => Some(b),
            (true, true) if self.is_fixed(a) => Some(a),
            (true, true) if self.is_fixed(b) => Some(b),
            _ => None,
        }
    }

    /// The sides of `b` that merge with `a`'s sides 0 and 1 (`a`, `b` a pair the seams allow).
    #[inline]
    pub(super) fn matching(&self, a: usize, b: usize) -> [usize; 2] {
        if !self.seam[a] {
            return [0, 1];
        }
        // Walking a's seam from along[0] to along[1] goes a → b iff along[a][1] = b; b's walk
        // goes a → b iff along[b][0] = a. Same direction: the left sides match.
        let a_forward = self.along[a][1] == b as u32;
        let b_forward = self.along[b][0] == a as u32;
        if a_forward == b_forward {
            [0, 1]
        } else {
            [1, 0]
        }
    }

    /// `b` was contracted into `a`: `a` takes `b`'s place along the seam.
    pub(super) fn merge(&mut self, a: usize, b: usize) {
        if !self.seam[b] {
            return;
        }
        let nb = self.along[b];
        let x = if nb[0] == a as u32 { nb[1] } else { nb[0] };
        for slot in self.along[a].iter_mut() {
            if *slot == b as u32 {
                *slot = x;
            }
        }
        if let Some(nx) = self.along.get_mut(x as usize) {
            for slot in nx.iter_mut() {
                if *slot == b as u32 {
                    *slot = a as u32;
                }
            }
        }
        self.along[b] = [u32::MAX; 2];
    }
}
