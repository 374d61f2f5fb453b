//! The passes that finish an oversampled run's mesh after the reconstruction (GNG3D-Q): the
//! QEM decimation to the target count ([`decimate`]), along the original's attribute seams
//! ([`seams`]) and a CAD part's creases ([`creases`]), the relaxation of the decimated vertices
//! ([`relax`]), the triangle shape pass ([`shape`]) and the deviation repair ([`deviation`]). They borrow their helpers from [`crate::surface`], never from each other
//! or from the reconstruction's passes.

pub(crate) mod creases;
pub(crate) mod decimate;
pub(crate) mod deviation;
pub(crate) mod relax;
pub(crate) mod seams;
pub(crate) mod shape;

/// The original's closest-point structure that the shape pass and the deviation repair query
/// ([`deviation::NEIGHBOURS`] original vertices' faces a query), built once for both; `None`
/// for an original without faces (then neither has anything to do).
pub(crate) fn surface(original: &mesh::TriMesh) -> Option<crate::surface::Surface<'_>> {
    if original.triangles.is_empty() {
        return None;
    }
    crate::surface::Surface::new(
        original,
        std::num::NonZeroUsize::new(deviation::NEIGHBOURS).expect("NEIGHBOURS > 0"),
    )
}
