//! Topology report: edges, boundary loops, non-manifold elements, components, Euler
//! characteristic and genus.
