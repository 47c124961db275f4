//! The fem tests' structured mesh: a square with a square hole on `harmonic_fixtures`'s grid
//! (right isosceles triangles along alternating diagonals, so Delaunay), outer sides tagged
//! separately; and a comparison of solutions.
#![allow(dead_code)] // each test binary uses a subset

use harmonic_fixtures::{Cell, Grid, Side, p};
use harmonic_mesh::{BoundaryTag, Mesh};

/// The square [x0, x0 + 2]×[y0, y0 + 2] minus the hole [x0 + 0.5, x0 + 1.5]×[y0 + 0.5, y0 + 1.5]
/// (obstacle 0), `n` cells per side (`n` a multiple of 4), each cell split along a diagonal
/// chosen in alternating directions. `tag(side)` gives the tag of each outer side. The
/// vertices inside the hole are dropped (the others keep their row-by-row order).
pub fn square_with_hole(n: usize, x0: f64, y0: f64, tag: impl Fn(Side) -> BoundaryTag) -> Mesh {
    assert!(n.is_multiple_of(4));
    let mut grid = Grid::new(n, n, 2.0 / n as f64).with_origin(p(x0, y0));
    grid.mark_cells(n / 4..3 * n / 4, n / 4..3 * n / 4, Cell::Obstacle(0));
    grid.parts(tag).without_unused_vertices().mesh()
}

/// The usual split: left side goal 0, other sides walls (and the hole obstacle 0).
pub fn three_part_tags(side: Side) -> BoundaryTag {
    match side {
        Side::Left => BoundaryTag::Goal(0),
        _ => BoundaryTag::Wall,
    }
}

/// The largest |a_i − b_i|.
pub fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
