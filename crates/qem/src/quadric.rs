//! The Garland–Heckbert quadric lives in [`mesh::quadric`] (shared with GNG3D-Q's vertex
//! placement); re-exported here so qem's paths stay `crate::quadric::…`.

pub use mesh::quadric::*;
