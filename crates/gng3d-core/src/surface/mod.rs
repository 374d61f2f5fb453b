//! The surface-edit kit: what the passes that edit a mesh after the reconstruction share
//! (the flips, the refit, the detail rounds, the relaxation, the deviation repair). Each pass
//! imports this kit, never another pass.
//!
//! - [`edit`]: the output's fans and edges as lists a pass edits, and an edge's flip;
//! - [`cells`]: the original's faces by output cell, the closest point on them;
//! - [`label`]: each original vertex's nearest node;
//! - [`moves`]: whether a vertex move keeps its faces sound;
//! - [`fan_search`]: nearest-face queries in fans, with trees for the large ones;
//! - [`soundness`]: the face rules (normals, angles) every edit passes.

pub(crate) mod cells;
pub(crate) mod edit;
pub(crate) mod fan_search;
pub(crate) mod label;
pub(crate) mod moves;
pub(crate) mod soundness;

pub(crate) use cells::{CellFaces, Surface, cell_faces, closest_on_faces};
pub(crate) use edit::{apply_flip, faces_on_edge, fans, has_edge, oriented, output_boundary};
pub(crate) use label::{kd_tree, label_with_threads, nearest};
pub(crate) use moves::{move_fits, normal};
