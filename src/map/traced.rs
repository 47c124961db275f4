//! The traced mesher's side of a map: the clear cells traced to rings (`trace.rs`), checked
//! as a domain, meshed by Delaunay refinement; whether its margin changes nothing a path
//! needs (`MapMesher::Auto`); the map as polygons or a scene; a workspace for many goals.

use super::*;

impl OccupancyMap {
    /// The robot's free configuration space around `goal` for a disc robot of
    /// `robot_radius`, traced as polygons (see the module documentation): the region the
    /// robot's centre may take, every point of it at least the radius from every blocked
    /// cell and from the map's edge.
    pub fn polygons(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<MapPolygons, MapError> {
        Ok(self
            .traced(goal, robot_radius, opts, &[], Known::default())?
            .polygons)
    }

    /// [`OccupancyMap::polygons`], the blocked cells they were traced from, and the domain
    /// of the polygons with `goals` in it and its mesh options. The domain's validation
    /// ([`harmonic_mesh::Domain::of_rings`]) is the check that keeps simplified rings from
    /// crossing or changing their nesting: a ring it refuses is kept as traced.
    pub(super) fn traced(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        goals: &[harmonic_mesh::GoalShape],
        known: Known,
    ) -> Result<TracedDomain, MapError> {
        check_radius_and_area(robot_radius, opts)?;
        if !(opts.simplify_cells.is_finite()
            && (0.0..=MAX_SIMPLIFY_CELLS).contains(&opts.simplify_cells))
        {
            return Err(MapError::BadOption {
                option: "simplify_cells",
                message: format!(
                    "must be between 0 and {MAX_SIMPLIFY_CELLS} cells, got {}",
                    opts.simplify_cells
                ),
            });
        }
        let blocked = self.blocked(opts.unknown);
        if blocked.all() {
            return Err(MapError::EmptyMap {
                file: self.source.clone(),
            });
        }
        let (gc, gr) = self.goal_cell(goal, opts.unknown)?;
        let eps = opts.simplify_cells;
        let margin = (eps + trace::CONTOUR_CUT + trace::JITTER) * self.resolution;
        let clear = known.narrow.unwrap_or_else(|| {
            bits::clear_cells(&blocked, (robot_radius + margin) / self.resolution)
        });
        let too_close = || self.goal_too_close(goal, robot_radius, margin, &clear, &blocked);
        if !clear.get(gc as isize, gr as isize) {
            return Err(too_close());
        }
        let check = |rings: &trace::Traced| {
            let polygons = self.world_polygons(rings, margin, eps);
            let mesh_options = mesh_options(&polygons, robot_radius, opts);
            let point = |p: &[f64; 2]| Point::new(p[0], p[1]);
            let outer: Vec<Point> = polygons.workspace.iter().map(point).collect();
            let holes: Vec<Vec<Point>> = polygons
                .obstacles
                .iter()
                .map(|r| r.iter().map(point).collect())
                .collect();
            match harmonic_mesh::Domain::of_rings(&outer, &holes, goals, &mesh_options) {
                Ok(domain) => Ok((polygons, domain, mesh_options)),
                Err(error) => Err(refused(rings, error)),
            }
        };
        let (_, (polygons, domain, mesh_options)) = trace::trace(
            &clear,
            (gc, gr),
            self.frame().offset,
            eps,
            self.frame().whole().world_to_grid(goal),
            check,
        )
        .map_err(|e| MapError::Plan {
            file: self.source.clone(),
            source: e.into(),
        })?
        .ok_or_else(too_close)?;
        Ok(TracedDomain {
            polygons,
            blocked,
            domain,
            mesh_options,
        })
    }

    /// Traced rings (in the whole map's cells, as [`trace::trace`] gives them) in world
    /// coordinates: the outer ring the workspace, the holes its obstacles.
    pub(super) fn world_polygons(
        &self,
        rings: &trace::Traced,
        margin: f64,
        eps: f64,
    ) -> MapPolygons {
        let frame = self.frame().whole();
        let world = |k: usize| -> Vec<[f64; 2]> {
            rings.rings[k]
                .iter()
                .map(|&g| frame.grid_to_world(g))
                .collect()
        };
        MapPolygons {
            workspace: rings.outer().map(world).unwrap_or_default(),
            obstacles: rings.holes().map(world).collect(),
            margin,
            simplify_cells: eps,
        }
    }

    /// The simplification at which the traced mesher plans every start the exact clear
    /// cells connect to `goal` (see [`MapMesher::Auto`]), if any: the goal's cell keeps the
    /// radius plus the tracing margin, every clear cell 4-connected to the goal's lies within
    /// a lead-in's reach of a cell that keeps the margin too, and the margin closes no loop
    /// (same Euler number). `opts.simplify_cells` is tried first; where its margin closes
    /// something, no simplification (a margin of a quarter cell, outlines kept as traced),
    /// which still meshes a map in a tenth of the quadtree's triangles (depot: 2 495 against
    /// 20 715). What it found is handed on, so the chosen mesher does not find it again.
    pub(super) fn traced_is_complete(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<(Option<f64>, Known), MapError> {
        check_radius_and_area(robot_radius, opts)?;
        let (gc, gr) = self.goal_cell(goal, opts.unknown)?;
        let res = self.resolution;
        let blocked = self.blocked(opts.unknown);
        let exact = bits::clear_cells(&blocked, robot_radius / res);
        let all = bits::component(&exact, gc, gr);
        let complete_at = |eps: f64| {
            let margin = eps + trace::CONTOUR_CUT + trace::JITTER;
            let narrow = bits::clear_cells(&blocked, robot_radius / res + margin);
            let complete = narrow.get(gc as isize, gr as isize) && {
                let kept = bits::component(&narrow, gc, gr);
                // The lead-in searches margin + 4 cells around a start; a cell within
                // margin + 1 of a kept cell is well inside that.
                all.subset_of(&kept.dilated(margin.ceil() as usize + 1))
                    && all.euler_number() == kept.euler_number()
            };
            (complete, narrow)
        };
        let mut eps = opts.simplify_cells;
        let (mut complete, mut narrow) = complete_at(eps);
        if !complete && eps > 0.0 {
            eps = 0.0;
            (complete, narrow) = complete_at(eps);
        }
        let known = Known {
            narrow: Some(narrow),
            exact: Some(exact),
            reachable: Some(all),
        };
        Ok((complete.then_some(eps), known))
    }

    /// The smooth tracer's local error per step on this map: [`TRACE_TOLERANCE_CELLS`] of a
    /// cell. A map places its obstacles to a cell, so following the field more closely
    /// buys nothing (the clearance is kept by the mesh either way); the scene default,
    /// 10⁻⁵ of the scene's size, is a tenth of this on Nav2's 384² maps, where it cost a
    /// quarter of the first plan's time.
    pub(super) fn trace_tolerance(&self) -> f64 {
        TRACE_TOLERANCE_CELLS * self.resolution
    }

    /// A workspace (factored once, goals later: [`Workspace::planner`]) on the robot's free
    /// configuration space around `around`, traced as [`OccupancyMap::polygons`] traces it;
    /// its planners lead starts the tracing margin left out in over the clear cells, as
    /// [`OccupancyMap::planner`]'s do. Goals must lie in the component of `around`.
    pub fn workspace(
        &self,
        around: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        planner: &PlannerOptions,
    ) -> Result<Workspace, MapError> {
        let plan_error = |source| MapError::Plan {
            file: self.source.clone(),
            source,
        };
        planner
            .stage(crate::planner::Stage::Meshing)
            .map_err(plan_error)?;
        let t = std::time::Instant::now();
        let (domain, mesh_options, entry) =
            self.traced_domain(around, robot_radius, opts, &[], Known::default())?;
        let meshed =
            crate::planner::Meshed::of_domain(domain, &mesh_options, t).map_err(plan_error)?;
        let entry = Entry {
            start: Arc::new(entry),
            trace_tolerance: self.trace_tolerance(),
            mesh_ms: 0.0,
        };
        Workspace::factored(meshed, &Default::default(), planner, Some(entry)).map_err(plan_error)
    }

    /// The traced configuration space around `goal` as a domain with `goals` in it (no
    /// booleans: the rings are simple and disjoint), its mesh options, and the lead-in for
    /// starts the margin leaves out.
    pub(super) fn traced_domain(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        goals: &[harmonic_mesh::GoalShape],
        mut known: Known,
    ) -> Result<(harmonic_mesh::Domain, MeshOptions, cells::CellEntry), MapError> {
        let reachable = known.reachable.take();
        let exact = known.exact.take();
        let TracedDomain {
            polygons,
            blocked,
            domain,
            mesh_options,
        } = self.traced(goal, robot_radius, opts, goals, known)?;
        let gc_gr = self.goal_cell(goal, opts.unknown)?;
        let entry = cells::CellEntry {
            blocked,
            radius: robot_radius / self.resolution,
            clear: exact,
            frame: self.frame(),
            reach: (polygons.margin / self.resolution).ceil() as usize + 4,
            goal: (!goals.is_empty()).then_some((gc_gr, goal)),
            reachable: reachable.map(Into::into).unwrap_or_default(),
        };
        Ok((domain, mesh_options, entry))
    }

    /// A scene for planning towards `goal` (world coordinates) with a disc robot of
    /// `robot_radius`: the robot's free configuration space of [`OccupancyMap::polygons`] as
    /// the workspace and its obstacles, a point goal, a point robot (the radius is in the
    /// polygons already) and a mesh sized for the robot (triangles with edges of about six
    /// robot radii on open floor, graded down by the refinement near walls and in narrow
    /// passages).
    pub fn to_scene(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<Scene, MapError> {
        let polys = self.polygons(goal, robot_radius, opts)?;
        Ok(self.scene_of(polys, goal, robot_radius, opts))
    }

    /// The scene of [`OccupancyMap::to_scene`] on traced polygons.
    pub(super) fn scene_of(
        &self,
        polys: MapPolygons,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Scene {
        let mesh = mesh_options(&polys, robot_radius, opts);
        Scene {
            name: Some(self.source.clone()),
            workspace: polys.workspace,
            obstacles: polys
                .obstacles
                .into_iter()
                .map(|p| Region {
                    polygon: Some(p),
                    ..Region::default()
                })
                .collect(),
            goal: Goals(vec![Region {
                point: Some(goal),
                ..Region::default()
            }]),
            starts: Vec::new(),
            boundary: Default::default(),
            mesh: MeshSpec {
                max_area: mesh.max_area,
                min_angle_deg: Some(mesh.min_angle_deg),
                grading: None,
                simplify: None,
            },
            robot: RobotSpec { radius: 0.0 },
        }
    }
}

/// What [`OccupancyMap::traced`] makes: the polygons, the blocked cells they were traced
/// from, and their domain with its mesh options.
pub(super) struct TracedDomain {
    polygons: MapPolygons,
    blocked: BitGrid,
    domain: harmonic_mesh::Domain,
    mesh_options: MeshOptions,
}

/// `error` from [`harmonic_mesh::Domain::of_rings`] on `rings` (its workspace the outer ring,
/// its obstacles the holes in order), with the rings it blames: both rings of a crossing or a
/// wrong nesting, and a hole outside the outer ring with the outer ring.
pub(super) fn refused(rings: &trace::Traced, error: harmonic_mesh::MeshError) -> trace::Refused {
    use harmonic_mesh::{MeshError, Part};
    let holes: Vec<usize> = rings.holes().collect();
    let ring = |part: &Part| match part {
        Part::Workspace => rings.outer(),
        Part::Obstacle(i) => holes.get(*i).copied(),
        _ => None,
    };
    let blamed: Vec<usize> = match &error {
        MeshError::RingsMeet { part, other } | MeshError::HoleInHole { part, other } => {
            [part, other].into_iter().filter_map(ring).collect()
        }
        MeshError::OutsideWorkspace { part } => [&Part::Workspace, part]
            .into_iter()
            .filter_map(ring)
            .collect(),
        _ => Vec::new(),
    };
    trace::Refused {
        rings: blamed,
        error,
    }
}

/// The mesh a disc robot needs on open floor: triangles with edges of about six robot radii
/// (three diameters; the potential is smooth there, and the smooth tracer follows its
/// recovered gradient), unless the mesher's default (free area / 20 000) is coarser; near
/// walls and in narrow passages the refinement's angle bound grades the mesh down to the
/// boundary's own detail. The mesher's default for a point robot. [`MapOptions::max_area`]
/// overrides. (Against edges of four radii: a fifth fewer triangles on depot, 30 % on the
/// 2000² maps, and their first plans 20–35 % faster, at path lengths within 1 %.)
///
/// Bridges (interior edges joining two wall vertices) are split at their midpoints and the
/// midpoints kept as they are ([`Bridges::Midpoints`]): the walls are Dirichlet, so the
/// system stays an M-matrix, and the second refinement pass that [`Bridges::Refined`] runs would
/// cost a quarter of a small map's first plan (tb3_sandbox at a 20° bound: 608 → 485
/// triangles, smallest angle 20° → 10.5°, the mesh a third faster, path lengths within 1 %).
fn mesh_options(polys: &MapPolygons, robot_radius: f64, opts: &MapOptions) -> MeshOptions {
    let robot = (robot_radius > 0.0).then(|| {
        let outer = harmonic_mesh::geom::signed_area(&polys.workspace).abs();
        let edge = 6.0 * robot_radius;
        (3f64.sqrt() / 4.0 * edge * edge).max(outer / 20_000.0)
    });
    MeshOptions {
        max_area: opts.max_area.or(robot),
        min_angle_deg: opts.min_angle_deg,
        bridges: Bridges::Midpoints,
        ..MeshOptions::default()
    }
}
