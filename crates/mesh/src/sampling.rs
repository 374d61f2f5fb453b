//! Surface sampling: seeded area-weighted Monte Carlo samples and Metro-style stratified samples.
