//! Test matrices shaped like the FEM systems this crate serves.

use crate::csc::SymmetricCsc;

/// P1 stiffness matrix of Laplace's equation on a structured triangulation of a parallelogram
/// into equilateral triangles, with `nx × ny` interior unknowns (the boundary ring is Dirichlet
/// and eliminated). Returns the matrix (7-point pattern, an SPD M-matrix: diagonal `2√3`,
/// off-diagonals `−1/√3`) and the coordinates of the unknowns, numbered row by row.
///
/// ```
/// let (a, coords) = harmonic_solver::gallery::triangulated_grid_laplacian(3, 2);
/// assert_eq!((a.n(), coords.len()), (6, 6));
/// // 6 diagonal entries and both triangles of 9 edges: 4 horizontal, 3 vertical, 2 diagonal.
/// assert_eq!(a.nnz(), 6 + 2 * (4 + 3 + 2));
/// ```
pub fn triangulated_grid_laplacian(nx: usize, ny: usize) -> (SymmetricCsc, Vec<[f64; 2]>) {
    let n = nx * ny;
    let off = -1.0 / 3f64.sqrt();
    let diag = 2.0 * 3f64.sqrt();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(7 * n);
    let mut values = Vec::with_capacity(7 * n);
    let mut coords = Vec::with_capacity(n);
    col_ptr.push(0);
    for j in 0..ny {
        for i in 0..nx {
            let me = j * nx + i;
            // Neighbours in increasing index order: (i,j-1), (i+1,j-1), (i-1,j), self, (i+1,j),
            // (i-1,j+1), (i,j+1).
            let candidates = [
                (j > 0, me.wrapping_sub(nx)),
                (j > 0 && i + 1 < nx, me.wrapping_sub(nx) + 1),
                (i > 0, me.wrapping_sub(1)),
                (true, me),
                (i + 1 < nx, me + 1),
                (j + 1 < ny && i > 0, (me + nx).wrapping_sub(1)),
                (j + 1 < ny, me + nx),
            ];
            for (present, row) in candidates {
                if present {
                    row_idx.push(row);
                    values.push(if row == me { diag } else { off });
                }
            }
            col_ptr.push(row_idx.len());
            let (x, y) = ((i + 1) as f64, (j + 1) as f64);
            coords.push([x + 0.5 * y, y * 3f64.sqrt() / 2.0]);
        }
    }
    let a = SymmetricCsc::try_new(n, col_ptr, row_idx, values)
        .expect("the structured grid pattern is valid by construction");
    (a, coords)
}
