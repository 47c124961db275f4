//! Meshing a [`VolumeDomain`]: isosurface stuffing at the spacing implied by the largest
//! tetrahedron volume, then an exact check that the mesh stays inside the true free space.
//!
//! Stuffing puts its boundary vertices *on* the (inflated) obstacle surfaces, so a boundary
//! face is a chord: across a curved or a sharp convex obstacle it dips into it (by about
//! h²/8R on a ball of radius R, and by up to a fraction of h across a box edge that is not
//! on a lattice plane). A path sliding along such a face would graze the real obstacle. So
//! every wall or obstacle face is measured against the exact solids (parry3d distances) and,
//! where one comes closer than the robot radius, the obstacles are inflated (and the workspace
//! shrunk) by a margin and the domain meshed again, until no face falls short. The first
//! margins come from the tetrahedra at the surface alone, before the whole domain is stuffed
//! (on me766, 5.58 M tetrahedra, meshing took 3.2–3.9 s with two whole passes, 1.6–1.8 s
//! with the first look and one whole pass, side by side on 2 cores).

use std::time::Instant;

use serde::Serialize;

use harmonic_types::BoundaryTag;

use crate::carve::{GoalHole, carve_goals};
use crate::domain::{GoalRegion, VolumeDomain};
use crate::error::VolumeError;
use crate::implicit::ImplicitDomain;
use crate::solid::{Point, Solid};
use crate::stuffing::{StuffingOptions, lattice_tetrahedra, stuff};
use harmonic_types::TetMesh;

/// The default tetrahedron budget: meshes whose lattice would hold more are refused.
pub const DEFAULT_MAX_TETRAHEDRA: u64 = 20_000_000;

/// Options of [`VolumeDomain::mesh`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    /// The largest tetrahedron volume: the lattice spacing is `h = (12·max_volume)^{1/3}`
    /// (lattice tetrahedra have volume h³/12; clipped ones are smaller).
    pub max_volume: f64,
    /// Refuse lattices with more tetrahedra than this (before allocating them).
    pub max_tetrahedra: u64,
    /// Check the boundary faces against the exact solids and remesh with a safety margin
    /// until none comes closer to an obstacle or a wall than the robot radius.
    pub conservative: bool,
    /// Tolerance of that check (absolute length).
    pub clearance_tolerance: f64,
}

impl MeshOptions {
    /// Options with the given largest tetrahedron volume and the defaults otherwise
    /// (20 M tetrahedra budget, conservative, tolerance 1e-10).
    pub fn with_max_volume(max_volume: f64) -> Self {
        MeshOptions {
            max_volume,
            max_tetrahedra: DEFAULT_MAX_TETRAHEDRA,
            conservative: true,
            clearance_tolerance: 1e-10,
        }
    }
}

/// What meshing did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshReport {
    /// The lattice spacing h.
    pub spacing: f64,
    /// The radius given to point goals.
    pub point_goal_radius: f64,
    /// The largest safety margin finally added to the robot radius (per obstacle, walls).
    pub margin: f64,
    /// How many margin settings were tried: 1 where none was needed (the first look at the
    /// surface found no deficit and the whole mesh none either), 2 where that first look
    /// raised the margins once and the whole mesh needed no more.
    pub passes: usize,
    /// Lattice vertices evaluated in the last pass.
    pub lattice_vertices: usize,
    /// Lattice vertices warped onto the boundary in the last pass.
    pub warped: usize,
    /// Flat tetrahedra dropped in the last pass.
    pub dropped_flat: usize,
    /// The largest clearance deficit of a wall or obstacle face in the final mesh
    /// (≤ `clearance_tolerance` when conservative; `-inf` when there are no such faces;
    /// NaN when not checked).
    pub clearance_deficit: f64,
    /// Lattice edges bisected to grade the lattice down to narrow passages and thin parts.
    pub graded: usize,
    /// Edges bisected to grade the mesh down to goals smaller than the lattice.
    pub refined: usize,
    /// Per goal, the tetrahedra carved out of it (0 for a goal the stuffing resolved).
    pub goal_tetrahedra: Vec<usize>,
    /// Wall-clock seconds spent.
    pub seconds: f64,
}

impl VolumeDomain {
    /// The lattice spacing for a largest tetrahedron volume.
    pub fn spacing_for(max_volume: f64) -> f64 {
        (12.0 * max_volume).cbrt()
    }

    /// Meshes free space (see the module docs).
    pub fn mesh(&self, opts: &MeshOptions) -> Result<(TetMesh, MeshReport), VolumeError> {
        let start = Instant::now();
        if !(opts.max_volume.is_finite() && opts.max_volume > 0.0) {
            return Err(VolumeError::BadMaxVolume {
                value: opts.max_volume,
            });
        }
        let h = Self::spacing_for(opts.max_volume);
        let estimated = lattice_tetrahedra(self.workspace().bounds(), h);
        if estimated > opts.max_tetrahedra {
            return Err(VolumeError::TooManyTetrahedra {
                estimated,
                budget: opts.max_tetrahedra,
            });
        }
        let goal_radius = self.point_goal_radius(h)?;
        let mut carved = self.carved_goals(h);
        let mut margins = vec![0.0; self.obstacles().len()];
        let mut wall_margin = 0.0;
        let mut passes = 0;
        // First only the tetrahedra at the surface, to find the margins the boundary faces
        // need without stuffing the whole domain for it (most scenes need one: a face across
        // a sharp box edge or a curved surface is a chord); then the whole, checked again.
        let mut surface_first = opts.conservative;
        let tol = opts.clearance_tolerance;
        loop {
            passes += 1;
            let implicit = self
                .implicit(goal_radius, &margins, wall_margin)
                .carving(&carved);
            if std::mem::take(&mut surface_first) {
                let (obstacles, wall) =
                    self.surface_clearance_deficits(&implicit, &carved, h, opts)?;
                if raise_margins(&mut margins, &mut wall_margin, &obstacles, wall, tol, h) {
                    continue;
                }
            }
            let mut stuffed = stuff(
                &implicit,
                &StuffingOptions {
                    spacing: h,
                    max_tetrahedra: opts.max_tetrahedra,
                },
            )?;
            if stuffed.tetrahedra.is_empty() {
                return Err(VolumeError::NoFreeSpace { spacing: h });
            }
            let graded = stuffed.graded;
            let (lattice_vertices, warped, dropped_flat) = (
                stuffed.lattice_vertices,
                stuffed.warped,
                stuffed.dropped_flat,
            );
            let (refined, goal_tets) = self.carve(&mut stuffed, &carved, goal_radius, opts);
            if let Some(j) = (0..carved.len()).find(|&j| carved[j] && goal_tets[j] == 0) {
                return Err(self.goal_unmeshed(j, goal_radius, opts.max_tetrahedra));
            }
            let mut mesh =
                TetMesh::new(stuffed.vertices, stuffed.tetrahedra, &|p| implicit.tag(p))?;
            // A carved goal's faces are exactly those with their three corners in it (the
            // faces carving left, and wall or obstacle faces wholly inside the goal).
            let solids = implicit.goal_solids().to_vec();
            let tol = 1e-9 * h;
            mesh.retag(&|c, tag| {
                (0..carved.len())
                    .find(|&j| carved[j] && c.iter().all(|p| solids[j].signed_distance(p) <= tol))
                    .map_or(tag, |j| BoundaryTag::Goal(j as u32))
            });
            // A stuffed goal that an obstacle left too little of for the lattice: carve it.
            let mut faced = vec![false; carved.len()];
            for f in mesh.boundary_faces() {
                if let BoundaryTag::Goal(j) = f.tag {
                    faced[j as usize] = true;
                }
            }
            if let Some(j) = (0..carved.len()).find(|&j| !carved[j] && !faced[j]) {
                carved[j] = true;
                continue;
            }
            let (obstacle_deficits, wall_deficit) = if opts.conservative {
                self.mesh_clearance_deficits(&mesh)
            } else {
                (Vec::new(), f64::NAN)
            };
            let deficit = obstacle_deficits
                .iter()
                .copied()
                .fold(wall_deficit, f64::max);
            let done = !opts.conservative || deficit <= opts.clearance_tolerance || passes >= 6;
            if done {
                let report = MeshReport {
                    spacing: h,
                    point_goal_radius: goal_radius,
                    margin: margins.iter().copied().fold(wall_margin, f64::max),
                    passes,
                    lattice_vertices,
                    warped,
                    dropped_flat,
                    clearance_deficit: deficit,
                    graded,
                    refined,
                    goal_tetrahedra: goal_tets,
                    seconds: start.elapsed().as_secs_f64(),
                };
                return Ok((mesh, report));
            }
            raise_margins(
                &mut margins,
                &mut wall_margin,
                &obstacle_deficits,
                wall_deficit,
                tol,
                h,
            );
        }
    }

    /// The clearance deficits ([`VolumeDomain::mesh_clearance_deficits`]) of the wall and
    /// obstacle faces that stuffing `implicit` at spacing `h` gives
    /// ([`VolumeDomain::surface_faces`]).
    fn surface_clearance_deficits(
        &self,
        implicit: &crate::domain::DomainImplicit<'_>,
        carved: &[bool],
        h: f64,
        opts: &MeshOptions,
    ) -> Result<(Vec<f64>, f64), VolumeError> {
        let mut obstacles = vec![f64::NEG_INFINITY; self.obstacles().len()];
        let mut wall = f64::NEG_INFINITY;
        for tri in self.surface_faces(implicit, carved, h, opts)? {
            self.raise_clearance_deficits(tri, &mut obstacles, &mut wall);
        }
        Ok((obstacles, wall))
    }

    /// The wall and obstacle faces of stuffing `implicit` at spacing `h`, from the
    /// tetrahedra at its surface alone ([`crate::stuffing::stuff_surface`]): the faces that
    /// no other of them shares and whose corners all lie on the surface, less those the
    /// goals own (the `carved` goals' faces as the whole mesh tags them after carving).
    fn surface_faces(
        &self,
        implicit: &crate::domain::DomainImplicit<'_>,
        carved: &[bool],
        h: f64,
        opts: &MeshOptions,
    ) -> Result<Vec<[Point; 3]>, VolumeError> {
        let (shell, surface) = crate::stuffing::stuff_surface(
            implicit,
            &StuffingOptions {
                spacing: h,
                max_tetrahedra: opts.max_tetrahedra,
            },
        )?;
        let solids = implicit.goal_solids();
        let tol = 1e-9 * h;
        let neighbors = harmonic_types::face_neighbors(&shell.tetrahedra)?;
        let mut faces = Vec::new();
        for (tet, across) in shell.tetrahedra.iter().zip(&neighbors) {
            for (k, &n) in across.iter().enumerate() {
                let face = harmonic_types::FACES[k].map(|l| tet[l]);
                if n != harmonic_types::NO_NEIGHBOR || !face.iter().all(|&v| surface[v as usize]) {
                    continue;
                }
                let tri = face.map(|v| shell.vertices[v as usize]);
                let centroid = Point::from((tri[0].coords + tri[1].coords + tri[2].coords) / 3.0);
                // As the whole mesh's faces are tagged: a goal's by the centroid, a carved
                // goal's by all three corners.
                let goal = matches!(implicit.tag(&centroid), BoundaryTag::Goal(_))
                    || (0..carved.len()).any(|j| {
                        carved[j] && tri.iter().all(|p| solids[j].signed_distance(p) <= tol)
                    });
                if !goal {
                    faces.push(tri);
                }
            }
        }
        Ok(faces)
    }

    /// The radius of the balls point goals are carved as: at most the spacing and half the
    /// clearance of the nearest point goal, so the last straight step to the point is free.
    fn point_goal_radius(&self, h: f64) -> Result<f64, VolumeError> {
        let mut radius = h;
        for (j, g) in self.goals().iter().enumerate() {
            if let GoalRegion::Point(p) = g {
                let clearance = self.free_clearance(p).map_err(|e| e.for_goal(j))?;
                radius = radius.min(0.5 * clearance);
            }
        }
        Ok(radius)
    }

    /// How far `p` is from the robot's inflated obstacles and walls, or which of them it is in.
    fn free_clearance(&self, p: &Point) -> Result<f64, VolumeError> {
        let r = self.robot_radius();
        let wall = -self.workspace().signed_distance(p) - r;
        if wall <= 0.0 {
            return Err(VolumeError::GoalOutsideWorkspace { goal: 0, radius: r });
        }
        let mut clearance = wall;
        for (i, o) in self.obstacles().iter().enumerate() {
            let d = o.signed_distance(p) - r;
            if d <= 0.0 {
                return Err(VolumeError::GoalInObstacle {
                    goal: 0,
                    obstacle: i,
                    radius: r,
                });
            }
            clearance = clearance.min(d);
        }
        Ok(clearance)
    }

    /// Which goals are carved rather than stuffed: those too small for the lattice to resolve
    /// (an inscribed ball narrower than the spacing: every point of space lies within 0.56 h
    /// of a lattice vertex) and every point goal.
    fn carved_goals(&self, h: f64) -> Vec<bool> {
        self.goals()
            .iter()
            .map(|g| match g {
                GoalRegion::Sphere(s) => s.radius < h,
                GoalRegion::Box(b) => 0.5 * (b.max - b.min).min() < h,
                GoalRegion::Point(_) => true,
            })
            .collect()
    }

    /// Grades the stuffed mesh down to the carved goals and carves them out; the edges
    /// bisected and the tetrahedra carved per goal.
    fn carve(
        &self,
        stuffed: &mut crate::stuffing::Stuffed,
        carved: &[bool],
        point_goal_radius: f64,
        opts: &MeshOptions,
    ) -> (usize, Vec<usize>) {
        if !carved.contains(&true) {
            return (0, vec![0; carved.len()]);
        }
        let solids = self.goal_solids(point_goal_radius);
        let regions: Vec<(usize, &Solid, f64)> = solids
            .iter()
            .enumerate()
            .filter(|&(j, _)| carved[j])
            .map(|(j, s)| {
                let size = match s {
                    Solid::Sphere(b) => 0.5 * b.radius,
                    Solid::Box(b) => 0.25 * (b.max - b.min).min(),
                    Solid::Surface(_) => f64::INFINITY,
                };
                (j, s, size)
            })
            .collect();
        let values: Vec<_> = regions
            .iter()
            .map(|&(_, s, _)| move |p: &Point| s.signed_distance(p))
            .collect();
        let holes: Vec<GoalHole<'_>> = regions
            .iter()
            .zip(&values)
            .map(|(&(_, _, size), value)| GoalHole {
                value,
                lipschitz: 1.0,
                size,
            })
            .collect();
        let budget = usize::try_from(opts.max_tetrahedra).unwrap_or(usize::MAX);
        let report = carve_goals(
            &mut stuffed.vertices,
            &mut stuffed.tetrahedra,
            &holes,
            &|_| false,
            budget,
        );
        let mut per_goal = vec![0; carved.len()];
        for (k, &(j, _, _)) in regions.iter().enumerate() {
            per_goal[j] = report.carved[k];
        }
        (report.refine.bisections, per_goal)
    }

    /// Why carved goal `j` kept no tetrahedron: it lies in an obstacle or outside the
    /// workspace (for the robot's radius), or the budget stopped refinement first.
    fn goal_unmeshed(&self, j: usize, point_goal_radius: f64, budget: u64) -> VolumeError {
        let centre = match self.goal_solids(point_goal_radius)[j] {
            Solid::Sphere(s) => s.center,
            Solid::Box(b) => nalgebra::center(&b.min, &b.max),
            Solid::Surface(_) => return VolumeError::GoalNotResolved { goal: j, budget },
        };
        match self.free_clearance(&centre) {
            Err(e) => e.for_goal(j),
            Ok(_) => VolumeError::GoalNotResolved { goal: j, budget },
        }
    }

    /// The largest clearance deficits (see [`VolumeDomain::raise_clearance_deficits`]) over
    /// the mesh's wall and obstacle faces: per obstacle, and of the walls (`-inf` where no
    /// face comes near).
    pub fn mesh_clearance_deficits(&self, mesh: &TetMesh) -> (Vec<f64>, f64) {
        let mut obstacles = vec![f64::NEG_INFINITY; self.obstacles().len()];
        let mut wall = f64::NEG_INFINITY;
        for f in mesh.boundary_faces() {
            if !matches!(f.tag, BoundaryTag::Goal(_)) {
                let tri = f.vertices.map(|v| mesh.vertices()[v as usize]);
                self.raise_clearance_deficits(tri, &mut obstacles, &mut wall);
            }
        }
        (obstacles, wall)
    }
}

/// Raises the margins of the obstacles and walls whose faces came closer than the robot
/// radius by more than `tol` (each by 1.5 times its deficit); whether any was raised.
fn raise_margins(
    margins: &mut [f64],
    wall_margin: &mut f64,
    obstacle_deficits: &[f64],
    wall_deficit: f64,
    tol: f64,
    h: f64,
) -> bool {
    let mut raised = false;
    for (m, &d) in margins.iter_mut().zip(obstacle_deficits) {
        if d > tol {
            *m += 1.5 * d + 1e-9 * h;
            raised = true;
        }
    }
    if wall_deficit > tol {
        *wall_margin += 1.5 * wall_deficit + 1e-9 * h;
        raised = true;
    }
    raised
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Part;
    use harmonic_fixtures::Rng;

    /// The first look's faces are the whole mesh's wall and obstacle faces (where a goal is
    /// carved, the whole mesh's split pieces of them) and its deficits the same, on seeded
    /// random scenes of spheres and boxes not aligned with the lattice (so their faces are
    /// chords that dip into the obstacles), with and without a robot radius, point goals
    /// (carved) and sphere goals wider than the lattice (stuffed).
    #[test]
    fn the_surface_alone_gives_the_whole_meshs_deficits() {
        let mut rng = Rng(0x05ee_d0f5_ca1e);
        for case in 0..8 {
            let mut at = |lo: f64, hi: f64| lo + (hi - lo) * rng.next_f64();
            let mut obstacles = Vec::new();
            for i in 0..3 + case % 4 {
                let c = Point::new(at(1.0, 9.0), at(1.0, 9.0), at(1.0, 9.0));
                let solid = if i % 2 == 0 {
                    Solid::new_sphere(Part::Obstacle(i), c, at(0.4, 1.5))
                } else {
                    let half = nalgebra::Vector3::new(at(0.3, 1.5), at(0.3, 1.5), at(0.3, 1.5));
                    Solid::new_box(Part::Obstacle(i), c - half, c + half)
                };
                obstacles.push(solid.unwrap());
            }
            // Point goals are carved (the mesh refined around them); a ball wider than the
            // lattice is stuffed.
            let goal = if case % 2 == 0 {
                GoalRegion::Point(Point::new(at(0.3, 0.8), at(0.3, 0.8), at(0.3, 0.8)))
            } else {
                GoalRegion::Sphere(crate::solid::SphereSolid {
                    center: Point::new(at(1.4, 1.6), at(1.4, 1.6), at(1.4, 1.6)),
                    radius: 1.15,
                })
            };
            let workspace = Solid::new_box(
                Part::Workspace,
                Point::new(0.0, 0.0, 0.0),
                Point::new(10.0, 10.0, 10.0),
            )
            .unwrap();
            let robot = [0.0, 0.15][case % 2];
            let domain = VolumeDomain::new(workspace, obstacles, vec![goal], robot).unwrap();
            let opts = MeshOptions {
                conservative: false,
                ..MeshOptions::with_max_volume(at(0.02, 0.08))
            };
            let (mesh, report) = domain.mesh(&opts).unwrap();
            let whole = domain.mesh_clearance_deficits(&mesh);
            let h = report.spacing;
            let carved = domain.carved_goals(h);
            let implicit = domain
                .implicit(report.point_goal_radius, &[], 0.0)
                .carving(&carved);
            let surface = domain
                .surface_clearance_deficits(&implicit, &carved, h, &opts)
                .unwrap();
            assert_eq!(surface, whole, "case {case}: {report:?}");
            // The faces themselves, by their corners.
            let key = |tri: [Point; 3]| {
                let mut c = tri.map(|p| [p.x, p.y, p.z]);
                c.sort_by(|a, b| a.partial_cmp(b).unwrap());
                c
            };
            let sorted = |mut faces: Vec<[[f64; 3]; 3]>| {
                faces.sort_by(|a, b| a.partial_cmp(b).unwrap());
                faces
            };
            let of_surface = domain
                .surface_faces(&implicit, &carved, h, &opts)
                .unwrap()
                .into_iter()
                .map(key)
                .collect();
            let of_whole = mesh
                .boundary_faces()
                .iter()
                .filter(|f| !matches!(f.tag, BoundaryTag::Goal(_)))
                .map(|f| key(f.vertices.map(|v| mesh.vertices()[v as usize])))
                .collect();
            let (of_surface, of_whole) = (sorted(of_surface), sorted(of_whole));
            assert!(of_whole.len() > 100, "case {case}");
            if report.refined == 0 {
                assert!(of_surface == of_whole, "case {case}: the same faces");
            } else {
                // Carving a goal bisects faces near it: the pieces tile the faces they split.
                let area = |faces: &[[[f64; 3]; 3]]| -> f64 {
                    let area = |c: &[[f64; 3]; 3]| {
                        let [a, b, d] = c.map(nalgebra::Vector3::from);
                        0.5 * (b - a).cross(&(d - a)).norm()
                    };
                    faces.iter().map(area).sum()
                };
                assert!(of_whole.len() > of_surface.len(), "case {case}");
                let (a, b) = (area(&of_surface), area(&of_whole));
                assert!(
                    (a - b).abs() <= 1e-12 * b,
                    "case {case}: area {a} against {b}"
                );
            }
            assert!(
                whole.0.iter().any(|&d| d > 1e-10),
                "case {case}: some face dips in: {whole:?}"
            );
        }
    }
}
