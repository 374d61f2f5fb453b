//! Loading and saving meshes (OBJ, PLY, STL), chosen by file extension.
