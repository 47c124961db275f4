//! harmonic-baselines (being written)
