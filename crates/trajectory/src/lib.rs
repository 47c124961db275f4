//! harmonic-trajectory (being written)
