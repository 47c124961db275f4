//! harmonic-solver (being written)
