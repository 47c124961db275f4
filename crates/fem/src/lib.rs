//! harmonic-fem (being written)
