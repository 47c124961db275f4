//! Goal regions of any size: the mesh graded down to each goal by bisection, then the goal
//! carved out of it.
//!
//! Stuffing resolves a surface only where the lattice is finer than it: a goal ball smaller
//! than the spacing gets no face, a goal tolerance of 0.05 rad in a lattice of 0.4 none
//! either. Such goals are left out of the stuffed function; the stuffed mesh is refined by
//! longest-edge bisection ([`crate::refine_where`]) wherever a tetrahedron is larger than the
//! goal's own size plus half its distance from the goal (so sizes grow back to the lattice's
//! smoothly), and every tetrahedron whose four corners lie in the goal is removed. The faces
//! left around the hole have all their corners in the goal: a path that reaches one has
//! reached the goal, and the goal's boundary condition holds on vertices inside it.

use rayon::prelude::*;

use crate::refine::{RefineReport, longest_edge, refine_where};
use crate::solid::Point;

/// How fast sizes grow away from a goal: a tetrahedron at distance d may be
/// `size + GRADING·d` long.
pub const GRADING: f64 = 0.5;

/// The first size tried at a goal, in multiples of its [`GoalHole::size`].
const COARSEST: f64 = 8.0;

/// A goal region to resolve by refinement and carving.
pub struct GoalHole<'a> {
    /// The goal's function: ≤ 0 exactly in the goal, and outside it at most `lipschitz`
    /// times the distance to the goal.
    pub value: &'a (dyn Fn(&Point) -> f64 + Sync),
    /// The Lipschitz constant of `value` (1 for a signed distance).
    pub lipschitz: f64,
    /// The smallest longest edge refinement goes down to at the goal: small enough that
    /// whole tetrahedra fit in it. Sizes are tried coarse to fine, down to this one, until
    /// one tetrahedron fits.
    pub size: f64,
}

/// What [`carve_goals`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CarveReport {
    /// The refinement.
    pub refine: RefineReport,
    /// Per goal, the tetrahedra carved out of it.
    pub carved: Vec<usize>,
    /// Per vertex of the result, the vertex it was before carving (new ones numbered after
    /// the input's).
    pub kept: Vec<u32>,
}

/// Refines `(vertices, tets)` towards every goal of `goals`, carves the goals out and drops
/// the vertices no tetrahedron uses any more (see the module docs). `frozen` vertices are
/// not refined around; refinement stops at `max_tets` tetrahedra.
pub fn carve_goals(
    vertices: &mut Vec<Point>,
    tets: &mut Vec<[u32; 4]>,
    goals: &[GoalHole<'_>],
    frozen: &dyn Fn(u32) -> bool,
    max_tets: usize,
) -> CarveReport {
    // Coarse to fine: each goal's size is halved from 8× its floor until a whole
    // tetrahedron fits in the goal (or the floor is reached), so a thick goal region is not
    // refined further than it needs.
    let mut sizes: Vec<f64> = goals.iter().map(|g| COARSEST * g.size).collect();
    let mut settled = vec![false; goals.len()];
    let mut refine = RefineReport::default();
    loop {
        let want = |p: &[Point; 4]| {
            let l = longest_edge(p);
            let c = Point::from((p[0].coords + p[1].coords + p[2].coords + p[3].coords) / 4.0);
            goals
                .iter()
                .zip(&sizes)
                .any(|(g, &s)| l > s && l > s + GRADING * ((g.value)(&c) / g.lipschitz).max(0.0))
        };
        let rank = |p: &Point| {
            goals
                .iter()
                .map(|g| (g.value)(p) / g.lipschitz)
                .fold(f64::INFINITY, f64::min)
        };
        let r = refine_where(vertices, tets, frozen, &want, &rank, max_tets);
        refine.bisections += r.bisections;
        refine.passes += r.passes;
        refine.frozen += r.frozen;
        refine.budget_reached |= r.budget_reached;
        if r.budget_reached {
            break;
        }
        let mut again = false;
        for (j, g) in goals.iter().enumerate() {
            if settled[j] {
                continue;
            }
            let inside: Vec<bool> = vertices.par_iter().map(|p| (g.value)(p) <= 0.0).collect();
            let fits = tets
                .par_iter()
                .any(|tet| tet.iter().all(|&v| inside[v as usize]));
            if fits || sizes[j] <= g.size {
                settled[j] = true;
            } else {
                sizes[j] = (0.5 * sizes[j]).max(g.size);
                again = true;
            }
        }
        if !again {
            break;
        }
    }
    let mut carved = vec![0; goals.len()];
    let inside: Vec<Vec<bool>> = goals
        .iter()
        .map(|g| vertices.par_iter().map(|p| (g.value)(p) <= 0.0).collect())
        .collect();
    tets.retain(|tet| {
        for (j, ins) in inside.iter().enumerate() {
            if tet.iter().all(|&v| ins[v as usize]) {
                carved[j] += 1;
                return false;
            }
        }
        true
    });
    let mut new_of = vec![u32::MAX; vertices.len()];
    let mut kept = Vec::new();
    for tet in tets.iter() {
        for &v in tet {
            if new_of[v as usize] == u32::MAX {
                new_of[v as usize] = kept.len() as u32;
                kept.push(v);
            }
        }
    }
    if kept.len() < vertices.len() || kept.iter().enumerate().any(|(i, &v)| i as u32 != v) {
        for tet in tets.iter_mut() {
            *tet = tet.map(|v| new_of[v as usize]);
        }
        *vertices = kept.iter().map(|&v| vertices[v as usize]).collect();
    }
    CarveReport {
        refine,
        carved,
        kept,
    }
}
