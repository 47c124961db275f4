//! harmonic-planner (being written)
