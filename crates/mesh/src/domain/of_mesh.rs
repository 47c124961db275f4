//! The domain of a mesh made elsewhere (Triangle, gmsh): its boundary loops as the tagged
//! rings, so the clearance and inside queries, the pictures and the planner work on it as on
//! a domain of a scene.

use super::{Constraints, Domain, Region, TaggedRing, bbox_of};
use crate::{BoundaryTag, Frame, Mesh, MeshError, Point};

/// The boundary loops of `mesh` as vertex numbers with the tag of each edge (edge `k` runs
/// from vertex `k` to `k + 1`), free space on their left. Where the boundary meets itself at
/// a vertex a loop turns the sharpest way, so every loop is a simple ring.
fn loops(mesh: &Mesh) -> Vec<(Vec<u32>, Vec<BoundaryTag>)> {
    let v = mesh.vertices();
    let edges = mesh.boundary_edges();
    // The boundary edges leaving each vertex, `from[a]..from[a + 1]` of `leaving`.
    let mut from = vec![0usize; v.len() + 1];
    for e in edges {
        from[e.vertices[0] as usize + 1] += 1;
    }
    for a in 0..v.len() {
        from[a + 1] += from[a];
    }
    let mut leaving = vec![0usize; edges.len()];
    let mut fill = from.clone();
    for (i, e) in edges.iter().enumerate() {
        let a = e.vertices[0] as usize;
        leaving[fill[a]] = i;
        fill[a] += 1;
    }
    let mut used = vec![false; edges.len()];
    let mut out = Vec::new();
    for first in 0..edges.len() {
        if used[first] {
            continue;
        }
        let (mut ring, mut tags) = (Vec::new(), Vec::new());
        let mut e = first;
        loop {
            used[e] = true;
            let [a, b] = edges[e].vertices;
            ring.push(a);
            tags.push(edges[e].tag);
            if b == edges[first].vertices[0] {
                break;
            }
            let back = v[a as usize] - v[b as usize];
            let turn = |k: usize| {
                let d = v[edges[k].vertices[1] as usize] - v[b as usize];
                let c = -(back.x * d.y - back.y * d.x).atan2(back.dot(&d));
                if c <= 0.0 {
                    c + std::f64::consts::TAU
                } else {
                    c
                }
            };
            let next = leaving[from[b as usize]..from[b as usize + 1]]
                .iter()
                .copied()
                .filter(|&k| !used[k])
                .min_by(|&x, &y| turn(x).total_cmp(&turn(y)));
            match next {
                Some(k) => e = k,
                None => break,
            }
        }
        if ring.len() >= 3 {
            out.push((ring, tags));
        }
    }
    out
}

impl Domain {
    /// The domain of a mesh made elsewhere: its boundary loops, with the mesh's edge tags,
    /// are the rings (counter-clockwise loops are workspace, clockwise ones obstacles), so
    /// [`Domain::segment_clearance`], [`Domain::contains_free`] and the pictures answer on
    /// its exact boundary. Goal-tagged edges count as goal boundary, not as walls, in the
    /// clearance. Such a domain describes the mesh; it is not meant to be meshed again.
    ///
    /// ```
    /// use harmonic_mesh::{BoundaryTag, Domain, Mesh, Point};
    /// let square = vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)];
    /// let walls = [(0, 1, BoundaryTag::Wall), (1, 2, BoundaryTag::Wall),
    ///              (2, 3, BoundaryTag::Goal(0)), (3, 0, BoundaryTag::Wall)];
    /// let mesh = Mesh::from_parts(square, vec![[0, 1, 2], [0, 2, 3]], &walls)?;
    /// let domain = Domain::of_mesh(&mesh)?;
    /// assert!(domain.contains_free(Point::new(0.5, 0.5)));
    /// assert!(!domain.contains_free(Point::new(1.5, 0.5)));
    /// // The goal edge (y = 1) is no wall: the nearest wall of (0.5, 0.9) is 0.5 away.
    /// assert!((domain.distance_to_obstacles(Point::new(0.5, 0.9)) - 0.5).abs() < 1e-12);
    /// # Ok::<(), harmonic_mesh::MeshError>(())
    /// ```
    pub fn of_mesh(mesh: &Mesh) -> Result<Domain, MeshError> {
        let loops = loops(mesh);
        if loops.is_empty() {
            return Err(MeshError::NoBoundaryLoop);
        }
        let frame = Frame::of(mesh.vertices());
        let user_free: Vec<TaggedRing> = loops
            .iter()
            .map(|(ring, tags)| TaggedRing {
                points: ring.iter().map(|&i| mesh.vertices()[i as usize]).collect(),
                tags: tags.clone(),
            })
            .collect();
        let free: Vec<TaggedRing> = user_free
            .iter()
            .map(|r| TaggedRing {
                points: r.points.iter().map(|&p| frame.to_unit(p)).collect(),
                tags: r.tags.clone(),
            })
            .collect();
        let (mut workspace, mut obstacles) = (Vec::new(), Vec::new());
        for r in &user_free {
            if crate::geom::signed_area(&r.points) > 0.0 {
                workspace.push(Region {
                    exterior: r.points.clone(),
                    holes: Vec::new(),
                    sources: Vec::new(),
                });
            } else {
                obstacles.push(Region {
                    exterior: r.points.iter().rev().copied().collect(),
                    holes: Vec::new(),
                    sources: Vec::new(),
                });
            }
        }
        let all: Vec<Point> = free.iter().flat_map(|r| r.points.iter().copied()).collect();
        let bbox = bbox_of(&all);
        let free_area: f64 = free
            .iter()
            .map(|r| crate::geom::signed_area(&r.points))
            .sum();
        let triangles = mesh.triangles().len().max(1) as f64;
        Ok(Domain {
            free,
            workspace,
            obstacles,
            goals: Vec::new(),
            free_area,
            scale: (bbox.1 - bbox.0).norm(),
            bbox,
            target_edge: super::edge_for_area(free_area / triangles),
            robot_radius: 0.0,
            // Built at the first query or beside the solve (`prepare_queries`).
            boundary_index: std::sync::OnceLock::new(),
            goal_edges: std::sync::OnceLock::new(),
            frame,
            user_free,
            constraints: Constraints::default(),
        })
    }
}
