//! Connolly et al. (1990): the §4 procedure on the reconstructed §5 grids leaves no flat
//! region, and the §3 counter-example holds — superposed point potentials cannot give the
//! four required directions, the harmonic solution does.

use harmonic_baselines::IntegerOutcome;
use harmonic_bench::connolly::{connolly_table, superposition_counterexample};

#[test]
fn the_integer_procedure_leaves_no_flat_region_on_the_reconstructed_grids() {
    let rows = connolly_table().expect("grids solve");
    assert_eq!(rows.len(), 4);
    for r in &rows {
        assert_eq!(
            r.outcome,
            IntegerOutcome::NoFlatRegion,
            "figure {}",
            r.figure
        );
        assert!(
            r.shifted_bits <= 80,
            "figure {}: {} bits",
            r.figure,
            r.shifted_bits
        );
        assert_eq!(r.passes.last().map(|p| p.flat_nodes), Some(0));
    }
    // The maze at the paper's 64 bits, one pass: no flat node either.
    assert_eq!(rows[0].grid, (55, 44));
    assert_eq!(rows[0].fixed_flat_nodes, 0);
}

#[test]
fn superposition_cannot_give_the_required_directions_and_the_harmonic_solution_does() {
    let s = superposition_counterexample().expect("mazes solve");
    assert_eq!(s.desired_dot, -4.0);
    assert!(s.superposition_dot > 0.0);
    assert!(s.difference_mismatch < 1e-12);
    assert!(
        s.mazes.iter().all(|m| m.harmonic == m.desired),
        "{:?}",
        s.mazes
    );
    assert!(s.mazes.iter().any(|m| m.superposition != m.desired));
}
