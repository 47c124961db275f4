//! The quadtree mesher's side of a map: the clear cells themselves, snapped to blocks
//! (`cells.rs`) and meshed by a balanced quadtree (`harmonic_mesh::quadtree`), complete on
//! every grid.

use rayon::prelude::*;

use super::*;

impl OccupancyMap {
    /// The quadtree mesh of the robot's free configuration space around `goal` (see
    /// [`MapMesher::Quadtree`]): the cells whose square keeps `robot_radius` from every
    /// blocked cell's square and from the map's edge (snapped to blocks as
    /// [`MapOptions::snap`] says), those 4-connected to the goal's cell meshed by
    /// [`harmonic_mesh::quadtree`] with leaves up to about four robot radii across (or
    /// triangles up to [`MapOptions::max_area`]). The goal's cell is a hole whose sides are
    /// tagged `Goal(0)`; every other boundary edge is a wall.
    pub fn cell_mesh(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<harmonic_mesh::Mesh, MapError> {
        Ok(self
            .cell_space(goal, robot_radius, opts, Known::default())?
            .0)
    }

    /// [`OccupancyMap::cell_mesh`] and the lead-in from clear cells the blocks left out (or
    /// that touch the mesh only at a corner).
    pub(super) fn cell_space(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        known: Known,
    ) -> Result<(harmonic_mesh::Mesh, cells::CellEntry), MapError> {
        check_radius_and_area(robot_radius, opts)?;
        let res = self.resolution;
        if let Snap::Blocks(b) = opts.snap
            && !(b.is_power_of_two() && b <= 64)
        {
            return Err(MapError::BadOption {
                option: "snap",
                message: format!("blocks must be a power of two from 1 to 64 cells, got {b}"),
            });
        }
        let (w, h) = (self.width, self.height);
        let (gc, gr) = self.goal_cell(goal, opts.unknown)?;
        let blocked = self.blocked(opts.unknown);
        let clear_bits = known
            .exact
            .unwrap_or_else(|| bits::clear_cells(&blocked, robot_radius / res));
        let too_close = || self.goal_too_close(goal, robot_radius, 0.0, &clear_bits, &blocked);
        // The 4-connected component of `cells` holding the goal's cell.
        let fill = |cells: &[bool]| {
            bits::component(&BitGrid::from_slice(w, h, cells, |c| c), gc, gr).to_bools()
        };
        if !clear_bits.get(gc as isize, gr as isize) {
            return Err(too_close());
        }
        let goal_cell = gr * w + gc;
        // The component of the clear cells themselves, found on their bits.
        let exact = || bits::component(&clear_bits, gc, gr).to_bools();
        let (component, block) = match opts.snap {
            Snap::Off => (exact(), 1),
            Snap::Blocks(b) => {
                let free = cells::snapped(&clear_bits.to_bools(), w, h, b);
                if !free[goal_cell] {
                    return Err(too_close());
                }
                (fill(&free), b)
            }
            Snap::OpenFloor => {
                let mut b = 1;
                while b < 64 && 2.0 * (2 * b) as f64 * res <= robot_radius {
                    b *= 2;
                }
                let square = ((4.0 * robot_radius / (b as f64 * res)).ceil() as usize).max(4);
                let free = (b > 1)
                    .then(|| cells::snapped_on_open_floor(&clear_bits.to_bools(), w, h, b, square));
                match free.filter(|f| f[goal_cell]) {
                    None => (exact(), 1),
                    Some(free) => {
                        let snapped = fill(&free);
                        let exact = exact();
                        if cells::euler_number(&snapped, w, h) == cells::euler_number(&exact, w, h)
                        {
                            (snapped, b)
                        } else {
                            (exact, 1)
                        }
                    }
                }
            }
        };
        let clear_count = component.iter().filter(|&&c| c).count();
        if clear_count <= 1 {
            return Err(MapError::GoalEnclosed {
                file: self.source.clone(),
                x: goal[0],
                y: goal[1],
                column: gc,
                row: gr,
                radius: robot_radius,
            });
        }
        let clear_area = clear_count as f64 * res * res;
        // The goal's cell is a hole of the mesh (its sides the goal boundary); the rest of the
        // component is meshed.
        let labels: Vec<Block> = component
            .par_iter()
            .enumerate()
            .map(|(k, &c)| match (k == goal_cell, c) {
                (true, _) => Block::Goal,
                (false, true) => Block::Free,
                (false, false) => Block::Blocked,
            })
            .collect();
        let entry = cells::CellEntry {
            blocked,
            radius: robot_radius / res,
            clear: Some(clear_bits),
            frame: self.frame(),
            reach: 4 * block,
            goal: Some(((gc, gr), goal)),
            reachable: known.reachable.map(Into::into).unwrap_or_default(),
        };
        // The largest leaf: triangles of at most max_area (a leaf is two of them), else
        // about four robot radii across, else (a point robot) the scene default's size.
        let leaf = match opts.max_area {
            Some(a) => (2.0 * a).sqrt(),
            None if robot_radius > 0.0 => 4.0 * robot_radius,
            None => (2.0 * clear_area / 20_000.0).sqrt(),
        };
        // Blocks of half a cell, and leaves that keep the interior joined through vertices
        // off the boundary: a cell with no such corner is split into its half cells around
        // a centre vertex, so a door or corridor one cell wide carries the flow (see
        // `QuadtreeOptions::interior_vertices`).
        let mut max_level = 1u8;
        while max_level < 15 && (1usize << max_level) as f64 * res <= leaf {
            max_level += 1;
        }
        let mesh_error = |e: harmonic_mesh::MeshError| MapError::Plan {
            file: self.source.clone(),
            source: e.into(),
        };
        let grid = BlockGrid::halved(w, h, labels).map_err(mesh_error)?;
        let quadtree = QuadtreeOptions {
            max_level,
            interior_vertices: true,
        };
        let mesh = quadtree_mesh(&grid, &quadtree, |x, y| {
            let p = self.grid_to_world([0.5 * x, 0.5 * y]);
            Point::new(p[0], p[1])
        })
        .map_err(mesh_error)?;
        Ok((mesh, entry))
    }
}
