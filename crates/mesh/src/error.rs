//! Typed errors and warnings for mesh loading, saving and validation.
