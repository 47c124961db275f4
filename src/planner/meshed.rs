//! The first stage of every build: a scene's free space meshed (`Meshed`), whatever the
//! input (a scene, a validated domain, a mesh made elsewhere).

use super::*;

/// A scene's free space meshed: what [`Planner`] and [`crate::Workspace`] both start from.
pub(crate) struct Meshed {
    pub(crate) domain: Arc<Domain>,
    pub(crate) mesh: Arc<Mesh>,
    pub(crate) report: MeshReport,
    /// The larger side of the domain's bounding box.
    pub(crate) scale: f64,
    /// Validating and meshing, in milliseconds.
    pub(crate) ms: f64,
    /// The levels `mesh` is the finest of, when it was refined uniformly for a multigrid
    /// solve ([`PlannerOptions::multigrid`]).
    pub(crate) hierarchy: Option<MeshHierarchy>,
}

impl Meshed {
    /// Validates and meshes `spec` with the scene's mesh options.
    pub(crate) fn new(scene: &Scene, spec: &DomainSpec) -> Result<Meshed, PlanError> {
        Meshed::constrained(scene, spec, &[], &[], Some(0))
    }

    /// [`Meshed::new`] with interior constraint segments and points the mesh must hold
    /// (see [`Domain::with_constraints`]), meshed at `4^refinements` times the scene's
    /// largest area and refined uniformly `refinements` times; `None`: decided from the
    /// mesh's estimated size ([`auto_refinements`]).
    pub(crate) fn constrained(
        scene: &Scene,
        spec: &DomainSpec,
        segments: &[[Point; 2]],
        points: &[Point],
        refinements: Option<usize>,
    ) -> Result<Meshed, PlanError> {
        let t = Instant::now();
        let mut mesh_options = scene.mesh_options();
        let mut domain = Domain::new(spec, &mesh_options)?;
        if !segments.is_empty() || !points.is_empty() {
            domain = domain.with_constraints(segments, points)?;
        }
        let refinements = match refinements {
            Some(k) => k,
            None => auto_refinements(&domain, &mesh_options)?,
        };
        if refinements == 0 {
            return Meshed::of_domain(domain, &mesh_options, t);
        }
        // Past 8 refinements any mesh is over the hierarchy's triangle budget anyway.
        let factor = 4f64.powi(refinements.min(16) as i32);
        mesh_options.max_area = mesh_options.max_area.map(|a| a * factor);
        let mut meshed = Meshed::of_domain(domain, &mesh_options, t)?;
        let coarse = Arc::try_unwrap(meshed.mesh).unwrap_or_else(|shared| (*shared).clone());
        let hierarchy = harmonic_mesh::uniform_hierarchy(coarse, refinements)?;
        meshed.mesh = Arc::clone(hierarchy.finest());
        meshed.hierarchy = Some(hierarchy);
        meshed.ms = millis(t);
        Ok(meshed)
    }

    /// Meshes a validated domain; `t` is when its validation began (counted as meshing).
    pub(crate) fn of_domain(
        domain: Domain,
        mesh_options: &MeshOptions,
        t: Instant,
    ) -> Result<Meshed, PlanError> {
        let (mesh, report) = domain.mesh(mesh_options)?;
        Ok(Meshed::of_parts(domain, Arc::new(mesh), report, millis(t)))
    }

    /// A domain and its mesh, the domain's bounding box giving the scale.
    fn of_parts(domain: Domain, mesh: Arc<Mesh>, report: MeshReport, ms: f64) -> Meshed {
        let (lo, hi) = domain.bounding_box();
        Meshed {
            domain: Arc::new(domain),
            mesh,
            report,
            scale: (hi.x - lo.x).max(hi.y - lo.y),
            ms,
            hierarchy: None,
        }
    }

    /// A mesh made elsewhere, as it is: its domain from its boundary loops
    /// ([`Domain::of_mesh`]).
    pub(crate) fn of_mesh(mesh: Mesh) -> Result<Meshed, PlanError> {
        Meshed::of_shared_mesh(Arc::new(mesh))
    }

    /// [`Meshed::of_mesh`] of a mesh already shared (with a solve running beside).
    pub(crate) fn of_shared_mesh(mesh: Arc<Mesh>) -> Result<Meshed, PlanError> {
        let t = Instant::now();
        // The domain (boundary loops and their index) and the one pass over the triangles
        // below read the mesh only: side by side on the pool.
        let (domain, (max_area, min_angle)) = rayon::join(
            || Domain::of_mesh(&mesh),
            || largest_area_smallest_angle(&mesh),
        );
        let domain = domain?;
        let report = MeshReport {
            refinement_complete: true,
            seam: None,
            input_vertices: mesh.vertices().len(),
            added_vertices: 0,
            max_area,
            min_angle_deg: min_angle.to_degrees(),
            estimated_triangles: mesh.triangles().len(),
            bridges_split: 0,
            bridges_remaining: 0,
            seam_refinements: Default::default(),
        };
        Ok(Meshed::of_parts(domain, mesh, report, millis(t)))
    }
}

/// The largest triangle area and the smallest angle (radians) of `mesh` in one pass (each
/// triangle's smallest angle is the one opposite its shortest side); the full quality report
/// (Delaunay checks, boundary loops) is made when a report asks for it.
fn largest_area_smallest_angle(mesh: &Mesh) -> (f64, f64) {
    let (mut max_area, mut min_angle) = (0.0f64, std::f64::consts::PI);
    // (|cross|, dot) of the smallest angle so far with a positive dot: tan θ = |cross| / dot
    // orders the angles below 90° without an arctangent per triangle, and an angle no
    // smaller than the best (a quadtree's 45° everywhere) takes none at all.
    let mut best: Option<(f64, f64)> = None;
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| mesh.vertices()[v as usize]);
        let sides = [(b, c, a), (c, a, b), (a, b, c)];
        let (p, q, apex) = sides
            .into_iter()
            .min_by(|x, y| {
                (x.1 - x.0)
                    .norm_squared()
                    .total_cmp(&(y.1 - y.0).norm_squared())
            })
            .expect("three sides");
        let (u, v) = (p - apex, q - apex);
        let cross = u.x * v.y - u.y * v.x;
        max_area = max_area.max(0.5 * cross.abs());
        let (sine, cosine) = (cross.abs(), u.dot(&v));
        if cosine <= 0.0 || best.is_none_or(|(bs, bc)| sine * bc < bs * cosine) {
            let angle = sine.atan2(cosine);
            if angle < min_angle {
                min_angle = angle;
                if cosine > 0.0 {
                    best = Some((sine, cosine));
                }
            }
        }
    }
    (max_area, min_angle)
}

/// The uniform refinements [`PlannerOptions::multigrid`]'s automatic choice makes:
/// [`AUTO_MULTIGRID_REFINEMENTS`] for a mesh estimated at [`AUTO_MULTIGRID_FROM`] triangles
/// or more (where the multigrid route is the faster one), none below.
fn auto_refinements(domain: &Domain, mesh_options: &MeshOptions) -> Result<usize, PlanError> {
    let estimated = domain.estimated_triangles(mesh_options)?;
    Ok(if estimated >= AUTO_MULTIGRID_FROM {
        AUTO_MULTIGRID_REFINEMENTS
    } else {
        0
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_fixtures::Rng;
    use harmonic_fixtures::grid::{Diagonals, Grid};
    use harmonic_mesh::BoundaryTag;

    /// The fixtures' `n × n` grid of unit cells (diagonals alternating) with its interior
    /// vertices moved by up to `jitter / 2` along each axis; `jitter` 0 keeps its right
    /// isosceles triangles, all of 45° smallest angle.
    fn jittered(n: usize, jitter: f64, seed: u64) -> Mesh {
        let grid = Grid::new(n, n, 1.0).with_diagonals(Diagonals::Alternating);
        let mut parts = grid.parts(|_| BoundaryTag::Wall);
        let mut rng = Rng(seed);
        for j in 1..n {
            for i in 1..n {
                let p = &mut parts.vertices[grid.vertex(i, j) as usize];
                p.x += jitter * (rng.next_f64() - 0.5);
                p.y += jitter * (rng.next_f64() - 0.5);
            }
        }
        parts.mesh()
    }

    #[test]
    fn the_one_pass_agrees_with_the_quality_report() {
        for (jitter, seed) in [(0.0, 1), (0.2, 2), (0.35, 3), (0.45, 4)] {
            let mesh = jittered(12, jitter, seed);
            let (max_area, min_angle) = largest_area_smallest_angle(&mesh);
            let q = mesh.quality();
            // The report's smallest angle, on every core, is the quality report's bit for bit.
            assert_eq!(mesh.min_angle_deg().to_bits(), q.min_angle_deg.to_bits());
            assert!(
                (max_area - q.max_triangle_area).abs() <= 1e-12,
                "jitter {jitter}"
            );
            assert!(
                (min_angle.to_degrees() - q.min_angle_deg).abs() <= 1e-9,
                "jitter {jitter}: {} against {}",
                min_angle.to_degrees(),
                q.min_angle_deg
            );
        }
        let (_, right) = largest_area_smallest_angle(&jittered(8, 0.0, 5));
        assert!((right.to_degrees() - 45.0).abs() <= 1e-12);
    }
}
