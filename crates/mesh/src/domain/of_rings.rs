//! Free space given as its boundary rings already (the robot's configuration space traced on
//! an occupancy map): checked and tagged, with no booleans, no offsets and no snapping.

use super::{
    Clearance, Constraints, Domain, GoalShape, Region, TaggedRing, bbox_of, boundary_index,
    circle_polygon, edge_for_area, options_to_unit, point_goal_polygon,
};
use crate::geom::{SegmentIndex, polygon_contains, segments_intersect};
use crate::{BoundaryTag, Frame, MeshError, MeshOptions, Part, Point};

/// A user ring in unit coordinates, counter-clockwise (`ccw`) or clockwise, checked for
/// finite coordinates, three vertices and an area.
fn unit_ring(
    part: Part,
    ring: &[Point],
    frame: &Frame,
    ccw: bool,
) -> Result<Vec<Point>, MeshError> {
    if let Some(vertex) = ring
        .iter()
        .position(|p| !(p.x.is_finite() && p.y.is_finite()))
    {
        return Err(MeshError::NonFinite { part, vertex });
    }
    oriented(
        part,
        ring.iter().map(|&p| frame.input_to_unit(p)).collect(),
        ccw,
    )
}

/// `unit` without repeated vertices, counter-clockwise (`ccw`) or clockwise.
fn oriented(part: Part, mut unit: Vec<Point>, ccw: bool) -> Result<Vec<Point>, MeshError> {
    unit.dedup();
    while unit.len() > 1 && unit[0] == unit[unit.len() - 1] {
        unit.pop();
    }
    if unit.len() < 3 {
        return Err(MeshError::TooFewVertices {
            part,
            count: unit.len(),
        });
    }
    let area = crate::geom::signed_area(&unit);
    if area == 0.0 {
        return Err(MeshError::ZeroArea { part });
    }
    if (area > 0.0) != ccw {
        unit.reverse();
    }
    Ok(unit)
}

/// The first two edges of `rings` (ring, edge) that touch or cross and are not neighbours on
/// one ring, by `index`, the R-tree of their edges numbered ring after ring (the domain's
/// boundary index).
fn first_meeting(
    rings: &[&[Point]],
    index: &SegmentIndex,
) -> Option<((usize, usize), (usize, usize))> {
    let mut offsets = Vec::with_capacity(rings.len() + 1);
    let mut n = 0u32;
    for r in rings {
        offsets.push(n);
        n += r.len() as u32;
    }
    offsets.push(n);
    let of = |id: u32| {
        let r = offsets.partition_point(|&o| o <= id) - 1;
        (r, (id - offsets[r]) as usize)
    };
    let edge = |(r, e): (usize, usize)| {
        let ring = rings[r];
        (ring[e], ring[(e + 1) % ring.len()])
    };
    let mut first: Option<((usize, usize), (usize, usize))> = None;
    for id in 0..n {
        let here = of(id);
        let (a, b) = edge(here);
        let (lo, hi) = bbox_of(&[a, b]);
        for (c, d, other) in index.in_box(lo, hi) {
            if other <= id {
                continue;
            }
            let there = of(other);
            let len = rings[here.0].len();
            if here.0 == there.0 && (there.1 == (here.1 + 1) % len || here.1 == (there.1 + 1) % len)
            {
                continue;
            }
            if segments_intersect(a, b, c, d) && first.is_none_or(|f| (here, there) < f) {
                first = Some((here, there));
            }
        }
    }
    first
}

impl Domain {
    /// Free space given as its boundary rings: the region inside `outer` and outside every
    /// one of `holes` (simple polygons, either orientation, that neither touch nor cross one
    /// another), with `goals` in it. Nothing is inflated, merged or cut: the rings are the
    /// boundary as they are (a point robot; for a disc robot, pass the configuration space
    /// as an occupancy map's traced rings are). The outer ring is tagged
    /// [`BoundaryTag::Wall`], hole `i` [`BoundaryTag::Obstacle`]`(i)`, goal `j`
    /// [`BoundaryTag::Goal`]`(j)`; a point goal becomes a disc as in [`Domain::new`].
    ///
    /// Checked: finite coordinates and areas; no two ring edges (goals' included) touching
    /// or crossing, by an R-tree of the edges; every hole and goal inside the outer ring and
    /// outside the other holes. Errors name the ring ([`Part::Workspace`] for the outer one,
    /// [`Part::Obstacle`] for holes, [`Part::Goal`]).
    ///
    /// ```
    /// use harmonic_mesh::{Domain, GoalShape, MeshOptions, Point};
    /// let square = |x: f64, y: f64, s: f64| {
    ///     vec![Point::new(x, y), Point::new(x + s, y), Point::new(x + s, y + s), Point::new(x, y + s)]
    /// };
    /// let opts = MeshOptions::default();
    /// let goals = [GoalShape::Point(Point::new(1.0, 1.0))];
    /// let domain = Domain::of_rings(&square(0.0, 0.0, 10.0), &[square(4.0, 4.0, 2.0)], &goals, &opts)?;
    /// assert!((domain.free_area() - 96.0).abs() < 0.5); // less the goal's small disc
    /// let (mesh, _) = domain.mesh(&opts)?;
    /// assert!(mesh.triangles().len() > 100);
    /// // A hole across the outer ring is refused.
    /// let e = Domain::of_rings(&square(0.0, 0.0, 10.0), &[square(9.0, 4.0, 2.0)], &goals, &opts);
    /// assert!(e.unwrap_err().to_string().contains("touch or cross"));
    /// # Ok::<(), harmonic_mesh::MeshError>(())
    /// ```
    pub fn of_rings(
        outer: &[Point],
        holes: &[Vec<Point>],
        goals: &[GoalShape],
        opts: &MeshOptions,
    ) -> Result<Domain, MeshError> {
        opts.validate()?;
        let frame = Frame::of(outer);
        let unit_opts = options_to_unit(opts, &frame);
        let ws = unit_ring(Part::Workspace, outer, &frame, true)?;
        let mut rings = vec![ws];
        for (i, h) in holes.iter().enumerate() {
            rings.push(unit_ring(Part::Obstacle(i), h, &frame, false)?);
        }
        let part_of = |r: usize| match r {
            0 => Part::Workspace,
            i if i <= holes.len() => Part::Obstacle(i - 1),
            j => Part::Goal(j - 1 - holes.len()),
        };
        let hole_area: f64 = rings[1..].iter().map(|r| crate::geom::signed_area(r)).sum();
        let outer_area = crate::geom::signed_area(&rings[0]);
        let h = edge_for_area(
            unit_opts
                .max_area
                .unwrap_or((outer_area + hole_area) / 20_000.0),
        );
        // Holes inside the outer ring and outside each other (their edges are checked below:
        // with no crossings, one vertex tells).
        let boxes: Vec<(Point, Point)> = rings.iter().map(|r| bbox_of(r)).collect();
        let inside = |p: Point, r: usize| {
            let (lo, hi) = boxes[r];
            p.x >= lo.x
                && p.x <= hi.x
                && p.y >= lo.y
                && p.y <= hi.y
                && polygon_contains(&rings[r], p)
        };
        let place = |r: usize, p: Point| -> Result<(), MeshError> {
            if !inside(p, 0) {
                return Err(MeshError::OutsideWorkspace { part: part_of(r) });
            }
            if let Some(other) = (1..=holes.len()).find(|&o| o != r && inside(p, o)) {
                return Err(MeshError::HoleInHole {
                    part: part_of(r),
                    other: part_of(other),
                });
            }
            Ok(())
        };
        for (r, ring) in rings.iter().enumerate().skip(1) {
            place(r, ring[0])?;
        }
        // Goals: a point becomes a disc of twice the target edge, at most half the way to the
        // nearest ring.
        let clearance = Clearance::new(
            goals.len(),
            rings
                .iter()
                .flat_map(|r| (0..r.len()).map(move |k| (r[k], r[(k + 1) % r.len()]))),
        );
        let mut goal_rings = Vec::with_capacity(goals.len());
        for (j, g) in goals.iter().enumerate() {
            let part = Part::Goal(j);
            let ring = match g {
                GoalShape::Polygon(pts) => {
                    if let Some(vertex) = pts
                        .iter()
                        .position(|p| !(p.x.is_finite() && p.y.is_finite()))
                    {
                        return Err(MeshError::NonFinite { part, vertex });
                    }
                    pts.iter().map(|&p| frame.input_to_unit(p)).collect()
                }
                GoalShape::Circle { center, radius } => circle_polygon(
                    part,
                    frame.input_to_unit(*center),
                    frame.input_len_to_unit(*radius),
                    h,
                )?,
                GoalShape::Point(p) => {
                    let c = frame.input_to_unit(*p);
                    if !(c.x.is_finite() && c.y.is_finite()) {
                        return Err(MeshError::NonFinite { part, vertex: 0 });
                    }
                    let d = clearance.distance(c);
                    if d.is_nan() || d <= 0.0 {
                        return Err(MeshError::GoalNotInFreeSpace {
                            goal: j,
                            robot_radius: 0.0,
                        });
                    }
                    point_goal_polygon(part, c, (2.0 * h).min(0.5 * d), h)?
                }
            };
            let ring = oriented(part, ring, false)?;
            if place(usize::MAX, ring[0]).is_err() {
                return Err(MeshError::GoalNotInFreeSpace {
                    goal: j,
                    robot_radius: 0.0,
                });
            }
            goal_rings.push(ring);
        }
        rings.extend(goal_rings);
        let free: Vec<TaggedRing> = rings
            .iter()
            .enumerate()
            .map(|(r, pts)| {
                let tag = match part_of(r) {
                    Part::Workspace => BoundaryTag::Wall,
                    Part::Obstacle(i) => BoundaryTag::Obstacle(i as u32),
                    Part::Goal(j) => BoundaryTag::Goal(j as u32),
                };
                TaggedRing {
                    points: pts.clone(),
                    tags: vec![tag; pts.len()],
                }
            })
            .collect();
        let user =
            |pts: &[Point]| -> Vec<Point> { pts.iter().map(|&p| frame.to_user(p)).collect() };
        let region = |pts: Vec<Point>, source: usize| Region {
            exterior: pts,
            holes: Vec::new(),
            sources: vec![source as u32],
        };
        let ccw = |pts: &[Point]| -> Vec<Point> { pts.iter().rev().copied().collect() };
        let user_free: Vec<TaggedRing> = free
            .iter()
            .map(|r| TaggedRing {
                points: user(&r.points),
                tags: r.tags.clone(),
            })
            .collect();
        let boundary_index = boundary_index(&free);
        let refs: Vec<&[Point]> = rings.iter().map(Vec::as_slice).collect();
        if let Some(((r, _), (s, _))) = first_meeting(&refs, &boundary_index) {
            return Err(MeshError::RingsMeet {
                part: part_of(r),
                other: part_of(s),
            });
        }
        let bbox = bbox_of(&rings[0]);
        Ok(Domain {
            free_area: free
                .iter()
                .map(|r| crate::geom::signed_area(&r.points))
                .sum(),
            workspace: vec![Region {
                exterior: user(&rings[0]),
                holes: Vec::new(),
                sources: Vec::new(),
            }],
            obstacles: (1..=holes.len())
                .map(|r| region(user(&ccw(&rings[r])), r - 1))
                .collect(),
            goals: (0..goals.len())
                .map(|j| region(user(&ccw(&rings[1 + holes.len() + j])), j))
                .collect(),
            free,
            scale: (bbox.1 - bbox.0).norm(),
            bbox,
            target_edge: h,
            robot_radius: 0.0,
            boundary_index: std::sync::OnceLock::from(boundary_index),
            goal_edges: std::sync::OnceLock::new(),
            frame,
            user_free,
            constraints: Constraints::default(),
        })
    }
}
