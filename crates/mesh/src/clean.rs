//! Cleaning: welding exact duplicate positions, dropping degenerate/duplicate faces and
//! unreferenced vertices.
