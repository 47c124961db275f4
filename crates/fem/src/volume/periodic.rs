//! P1 on a periodic mesh (a configuration space whose angles wrap around): the system of the
//! slab of one period (`harmonic_volume::PeriodicMesh::slab`) is assembled as any other, its
//! two end surfaces given the natural condition (no term), and then *folded*: every pair of
//! identified vertices becomes one unknown, `A' = Pᵀ A P` and `b' = Pᵀ b` with `P` the 0/1
//! map from the slab's unknowns to the periodic ones. Every element's stiffness is counted
//! once, so `A'` is exactly the stiffness of the periodic mesh; folding adds rows of a
//! diagonally dominant M-matrix (identified vertices share no edge), so it stays one and the
//! accurate elimination applies as before. A vertex of one end may lie on a held face while
//! its image at the other end does not (the face belongs to the other end's tetrahedra): the
//! assembler is told the identification (`VolumeAssembler::with_identified`) so that both
//! are held alike.

use std::sync::Arc;

use harmonic_solver::SymmetricCsc;
use harmonic_types::{SEAM_PART, TetMesh};

use super::FemError;
use super::assemble::{NegativeWeights, VolumeAssembler, VolumeAssemblyOptions, VolumeSystem};
use super::potential::VolumePotential;
use super::solve::{VolumeSolveReport, planning_solve};
use crate::bc::{BoundaryCondition, BoundaryConditions};

/// `bcs` with the slab's end faces (`Obstacle(SEAM_PART)`) under the natural condition.
pub fn periodic_conditions(bcs: &BoundaryConditions) -> BoundaryConditions {
    let mut out = bcs.clone();
    out.obstacle_overrides
        .insert(SEAM_PART, BoundaryCondition::Neumann(0.0));
    out
}

/// Folds `system` (assembled on a slab) so that vertex `v` and `images[v]` are one unknown;
/// [`VolumeSystem::expand`] of the folded system gives both the same ψ.
pub fn identify_periodic(system: &VolumeSystem, images: &[u32]) -> Result<VolumeSystem, FemError> {
    let nv = images.len();
    if system.psi_fixed.len() != nv {
        return Err(FemError::LengthMismatch {
            what: "periodic images",
            expected: system.psi_fixed.len(),
            got: nv,
        });
    }
    const NONE: usize = usize::MAX;
    let mut unknown_of = vec![NONE; nv];
    for (i, &v) in system.free.iter().enumerate() {
        unknown_of[v as usize] = i;
    }
    // New numbering: the unknowns that are their own image.
    let mut new_of_vertex = vec![NONE; nv];
    let mut free = Vec::new();
    for &v in system.free.iter() {
        if images[v as usize] == v {
            new_of_vertex[v as usize] = free.len();
            free.push(v);
        }
    }
    let mut fold = vec![NONE; system.free.len()];
    for (i, &v) in system.free.iter().enumerate() {
        let r = images[v as usize] as usize;
        if r >= nv || new_of_vertex[r] == NONE {
            return Err(FemError::PeriodicMismatch {
                vertex: v,
                image: r as u32,
            });
        }
        fold[i] = new_of_vertex[r];
    }
    // A prescribed vertex must be identified with a prescribed one.
    for v in 0..nv {
        let r = images[v] as usize;
        if r < nv && (unknown_of[v] == NONE) != (unknown_of[r] == NONE) {
            return Err(FemError::PeriodicMismatch {
                vertex: v as u32,
                image: r as u32,
            });
        }
    }
    let n = free.len();
    let a = &system.matrix;
    let mut columns: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for j in 0..a.n() {
        let (rows, vals) = a.column(j);
        let fj = fold[j];
        for (&i, &x) in rows.iter().zip(vals) {
            columns[fj].push((fold[i], x));
        }
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    col_ptr.push(0);
    for col in &mut columns {
        col.sort_unstable_by_key(|&(i, _)| i);
        for &(i, x) in col.iter() {
            if row_idx.len() > *col_ptr.last().unwrap_or(&0) && row_idx.last() == Some(&i) {
                if let Some(last) = values.last_mut() {
                    *last += x;
                }
            } else {
                row_idx.push(i);
                values.push(x);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let matrix = SymmetricCsc::try_from_symmetric_pattern(n, col_ptr, row_idx, values)?;
    let mut rhs = vec![0.0; n];
    let mut excess = vec![0.0; n];
    for (i, &f) in fold.iter().enumerate() {
        rhs[f] += system.rhs[i];
        excess[f] += system.excess[i];
    }
    Ok(VolumeSystem {
        matrix,
        rhs,
        excess,
        psi_fixed: system.psi_fixed.clone(),
        reference: system.reference,
        not_m_matrix: system.not_m_matrix,
        free: Arc::new(free),
        positive_offdiagonals: system.positive_offdiagonals,
        clamped: system.clamped,
        images: Some(Arc::new(images.to_vec())),
    })
}

/// What [`solve_periodic_for_planning`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicSolveReport {
    /// The solve that produced ψ.
    pub solve: VolumeSolveReport,
    /// Whether the clamped (M-matrix) stiffness was used.
    pub clamped: bool,
    /// Edges clamped (0 when the Galerkin field was kept).
    pub clamped_edges: usize,
    /// Positive off-diagonals of the Galerkin slab matrix.
    pub positive_offdiagonals: usize,
    /// Unknowns of the folded system.
    pub unknowns: usize,
}

/// The planning solve of [`super::solve_assembled_for_planning`] on a periodic slab: assemble
/// (ends natural), fold by `images`, solve; redo with the clamped M-matrix where the field
/// has an interior extremum or is too flat for a Cholesky solve.
pub fn solve_periodic_for_planning(
    slab: Arc<TetMesh>,
    images: &[u32],
    bcs: &BoundaryConditions,
) -> Result<(VolumePotential, PeriodicSolveReport), FemError> {
    let bcs = periodic_conditions(bcs);
    let shared = Arc::new(images.to_vec());
    let assembler = VolumeAssembler::with_identified(
        Arc::clone(&slab),
        &bcs,
        VolumeAssemblyOptions::default(),
        Arc::clone(&shared),
    )?;
    let system = identify_periodic(&assembler.assemble(&bcs)?, images)?;
    let positive_offdiagonals = system.positive_offdiagonals();
    let unknowns = system.matrix().n();
    let (potential, solve, clamped_edges) = planning_solve(
        &slab,
        &system,
        super::solve::AUTO_MULTIGRID_MIN_UNKNOWNS,
        || {
            identify_periodic(
                &assembler.assemble_weighted(&bcs, None, NegativeWeights::Clamp)?,
                images,
            )
        },
    )?;
    Ok((
        potential,
        PeriodicSolveReport {
            solve,
            clamped: clamped_edges.is_some(),
            clamped_edges: clamped_edges.unwrap_or(0),
            positive_offdiagonals,
            unknowns,
        },
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_types::BoundaryTag;
    use harmonic_volume::{
        ImplicitDomain, PeriodicMesh, Point, StuffingOptions, Vector, stuff_periodic,
    };

    /// A box periodic in z, held at φ = 1 on x = 0 and φ = 0 on x = 1 (a goal slab): the
    /// exact solution is φ = 1 − x whatever z, and the folded P1 solution reproduces it (P1
    /// holds linear functions exactly); the slab's ends carry no condition.
    struct Slab;
    impl ImplicitDomain for Slab {
        fn value(&self, p: &Point) -> f64 {
            let y = (p.y - 0.5).abs() - 0.5;
            let x = (p.x - 0.5).abs() - 0.5;
            x.max(y)
        }
        fn tag(&self, p: &Point) -> BoundaryTag {
            if p.x > 0.99 {
                BoundaryTag::Goal(0)
            } else if p.x < 0.01 {
                BoundaryTag::Wall
            } else {
                BoundaryTag::Obstacle(0)
            }
        }
        fn bounds(&self) -> (Point, Point) {
            (Point::new(0.0, 0.0, 0.0), Point::new(1.0, 1.0, 1.0))
        }
    }

    #[test]
    fn folded_slab_reproduces_a_linear_field() {
        let stuffed = stuff_periodic(
            &Slab,
            &StuffingOptions {
                spacing: 0.125,
                max_tetrahedra: 1_000_000,
            },
            [None, None, Some(8)],
        )
        .unwrap();
        let pm = PeriodicMesh::new(&stuffed, 1, &|p| Slab.tag(p)).unwrap();
        assert!(pm.seam_faces > 0);
        let mut bcs = BoundaryConditions::default();
        bcs.obstacle_overrides
            .insert(0, BoundaryCondition::Neumann(0.0));
        let slab = Arc::new(pm.slab);
        let (pot, _) = solve_periodic_for_planning(Arc::clone(&slab), &pm.images, &bcs).unwrap();
        let phi = pot.phi_at_vertices();
        for (v, p) in slab.vertices().iter().enumerate() {
            assert!((phi[v] - (1.0 - p.x)).abs() < 1e-9, "{v} {p:?} {}", phi[v]);
        }
        // The covering glues the copies: a segment across z = 1 stays inside the mesh.
        let cov = &pm.covering;
        let t = cov.locate(&Point::new(0.5, 0.5, 0.99), None).unwrap();
        let t2 = cov.walk(&Point::new(0.5, 0.5, 1.01), t);
        assert!(t2.is_some());
        let _ = Vector::zeros();
    }
}
