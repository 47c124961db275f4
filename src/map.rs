//! Occupancy-grid maps in the ROS `map_server` format, turned into planners.
//!
//! A map is a YAML file (`image`, `resolution`, `origin: [x, y, yaw]`, `occupied_thresh`,
//! `free_thresh`, `negate`, `mode`) naming a PGM or PNG image. Each pixel becomes a free,
//! occupied or unknown cell by the `map_server` rules.
//!
//! Both meshers work in the robot's free configuration space on the grid; the default,
//! [`MapMesher::Auto`], takes the traced one wherever its margin changes nothing a path needs
//! and the quadtree (complete on every grid, one-cell doors included) elsewhere. The traced
//! mesher ([`MapMesher::Traced`]) works from the start on the grid: the cells whose squares keep the robot radius (plus a small
//! tracing margin, [`MapPolygons::margin`]) from every blocked cell are found exactly, 64
//! cells a word; the goal's 4-connected component of them is traced by marching squares and
//! simplified by Douglas–Peucker ([`MapOptions::simplify_cells`], about a cell) without
//! changing its topology. The margin is what the tracing and the simplification may move the
//! boundary by, so every point of the polygons, and of the region they bound, keeps the
//! radius from every occupied (and unknown) cell: no polygon is offset, no booleans run.
//! [`OccupancyMap::to_scene`] returns those polygons as a [`Scene`] of a point robot, so the
//! planner, the command line and the pictures work on maps unchanged. The mesh is sized for
//! the robot: triangles with edges of about six robot radii on open floor, graded down by the
//! refinement near walls and in narrow passages (smallest angle 15°, down to about 7.5°
//! next to the midpoints that split wall-to-wall edges). Free areas not
//! connected to the goal, and passages too narrow for the robot, are outside the scene.
//!
//! ```
//! use harmonic_planner::map::{Cell, MapOptions, OccupancyMap};
//! use harmonic_planner::Planner;
//! // A 40 × 30 cell room at 10 cm with a wall in the middle that leaves a 1.4 m door at the
//! // top; a robot of radius 0.2 m.
//! let (w, h) = (40, 30);
//! let mut cells = vec![Cell::Free; w * h];
//! for j in 0..16 {
//!     for i in 19..21 {
//!         cells[j * w + i] = Cell::Occupied;
//!     }
//! }
//! let map = OccupancyMap::from_cells(w, h, 0.1, [0.0, 0.0, 0.0], cells)?;
//! let scene = map.to_scene([3.5, 0.5], 0.2, &MapOptions::default())?;
//! let planner = Planner::new(&scene)?;
//! let path = planner.plan([0.5, 0.5]);
//! assert!(path.status.reached_goal());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde_yaml_ng::Value;

use harmonic_mesh::quadtree::{Block, BlockGrid, QuadtreeOptions, quadtree_mesh};
use harmonic_mesh::{Bridges, MeshOptions, Point};

use crate::planner::{Entry, PlanError, Planner, PlannerOptions};
use crate::scene::{Goals, MeshSpec, Region, RobotSpec, Scene};
use crate::workspace::Workspace;
use harmonic_fem::SolveMethod;

mod bits;
mod cells;
mod load;
pub mod movingai;
mod quadtree;
mod trace;
mod traced;

use bits::BitGrid;

/// One cell of an occupancy grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    /// Known to be free.
    Free,
    /// Known to be occupied.
    Occupied,
    /// Not observed (grey in a `map_server` image).
    Unknown,
}

/// How `map_server` reads pixel values (`mode` in the YAML).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Occupied, free or unknown by the two thresholds (the default).
    Trinary,
    /// As trinary, but a value between the thresholds is a free cell with a graded cost (1 at
    /// the free threshold … 252 at the occupied one; [`MapOptions::cost_weight`]).
    Scale,
    /// The pixel value is the occupancy in percent (0 free … 100 occupied, above 100 unknown),
    /// compared with the thresholds (between them: graded costs, as `Scale`); `negate` does
    /// not apply.
    Raw,
}

/// What the map's unknown cells are to the planner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UnknownCells {
    /// Unknown cells are obstacles (the safe default).
    #[default]
    Obstacle,
    /// Unknown cells are free space.
    Free,
}

/// How [`OccupancyMap::planner`] meshes a map's free space.
///
/// Every choice plans on the same free space, the robot's clear cells; they differ in speed
/// and in whether the planner is complete on every map. [`MapMesher::Auto`] (the default) is
/// complete on every map and as fast as the traced mesher wherever that one is complete too.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MapMesher {
    /// The traced mesher where its tracing margin changes nothing a path needs (the goal's
    /// cell keeps the margin, every clear cell connected to the goal is within a lead-in of
    /// the traced region, and the margin closes no loop of the free space: the same Euler
    /// number) at [`MapOptions::simplify_cells`] or, failing that, with no simplification
    /// (a quarter-cell margin), else the quadtree. A map with graded costs (free cells of
    /// cost > 0) is always meshed by the quadtree, at every [`MapOptions::cost_weight`], 0
    /// included, so that two weights give two fields on one mesh. The default.
    #[default]
    Auto,
    /// The robot's free configuration space on the map's own grid: the cells whose square
    /// keeps the robot radius from every blocked cell's square, exactly, with no margin
    /// (snapped to blocks on open floor, [`MapOptions::snap`]), meshed by a balanced
    /// quadtree of right isosceles triangles ([`harmonic_mesh::quadtree`]) on half cells
    /// that keeps a vertex off the walls in every passage, one-cell doors included: no
    /// tracing, no polygon booleans, no refinement. Complete: every start on a clear cell
    /// 4-connected to the goal's reaches the goal.
    Quadtree,
    /// The traced, simplified polygons of [`OccupancyMap::to_scene`], meshed by constrained
    /// Delaunay refinement like any scene: the fewest triangles and the fastest first plan,
    /// but the tracing margin ([`MapPolygons::margin`], 1.25 cells at the default
    /// simplification) closes passages narrower than about two margins and refuses goals
    /// that close to a wall.
    Traced,
}

/// How [`MapMesher::Quadtree`] snaps the robot's clear cells to blocks of `b × b` cells,
/// keeping a partly clear block's cells or dropping them. Dropping gives up at most a
/// block's width of clear space along a wall and lets the wall's staircase step by blocks,
/// so the mesh needs fewer one-cell leaves there.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Snap {
    /// Every clear cell is meshed.
    Off,
    /// Snap on open floor only: blocks of the largest power of two of cells at most half the
    /// robot radius wide (none for a point robot); a partly clear block is dropped when the
    /// wholly clear blocks beside it all lie in squares of wholly clear blocks about four
    /// robot radii (at least four blocks) across, so rooms snap but passages and doors
    /// narrower than that keep their full width. If snapping changes the free space's
    /// topology (its Euler number: a passage closed, a region cut off) nothing is snapped.
    #[default]
    OpenFloor,
    /// Snap everywhere to blocks of this many cells (a power of two from 1 to 64): the
    /// fewest triangles, but passages narrow too (and the potential's flow through them).
    Blocks(usize),
}

/// The costliest graded cost of a free cell (Nav2's: 253 is inscribed, 254 lethal).
pub const MAX_GRADED_COST: u8 = 252;

/// The resistance a unit of graded cost adds at [`MapOptions::cost_weight`] 1, relative to a
/// free cell's: NavFn's, whose step costs 50 (`COST_NEUTRAL`) plus 0.8 (`COST_FACTOR`) per
/// unit of cost, so 0.8 / 50 — a cell of cost 252 resists 5 times as much as a free cell.
pub const COST_RESISTANCE: f64 = 0.8 / 50.0;

/// The largest [`MapOptions::cost_weight`]: at 10⁶ the cheapest graded cell already resists
/// 16 000 times a free one, and larger weights would take the conductivity toward 0 and the
/// absorption toward the float range's end.
pub const MAX_COST_WEIGHT: f64 = 1e6;

/// `x` as `{}` prints it, or in exponent form where that would take more than 16 digits.
fn short_number(x: f64) -> String {
    if x.is_finite() && x.abs() >= 1e16 {
        format!("{x:e}")
    } else {
        x.to_string()
    }
}

/// The length that sets the scale of a graded cost's absorption ([`cost_absorption`]): 5 cm,
/// a Nav2 costmap's usual cell. In metres, not cells, so that the same place mapped at
/// another resolution plans the same paths.
pub const COST_ABSORPTION_LENGTH: f64 = 0.05;

/// The absorption σ·ℓ² (ℓ = [`COST_ABSORPTION_LENGTH`]) that a cell of graded cost `c` adds
/// at [`MapOptions::cost_weight`] 1: its added resistance 0.016·c times (c / 252)³, about 4
/// for the costliest cell and falling off fast below it (0.5 at 150, 0.1 at 100, 0.013 at 60).
///
/// A conductivity alone screens the walls: a costly band along a wall conducts poorly, so
/// little of the potential's drop to the wall reaches the open floor beyond it, and paths
/// there pass closer to walls than they do without costs (measured on Nav2's maps with its
/// inflated costmaps: 8 of 18 paths narrower at their narrowest, by up to 0.26 m). The
/// absorption restores the walls' pull: it draws the potential toward the walls' level in
/// the costliest cells, next to obstacles, as a thin soft wall would (at weight 1, ψ falls
/// e-fold every 2.5 cm through cells of cost 252, every 7 cm through cells of cost 150).
/// Its cubic factor keeps it off the moderate costs of corridors' middles and open lanes,
/// where an absorption would act as a penalty on length and let paths cut corners.
pub fn cost_absorption(c: u8) -> f64 {
    let c = f64::from(c);
    let share = c / f64::from(MAX_GRADED_COST);
    COST_RESISTANCE * c * share * share * share
}

/// Options of [`OccupancyMap::planner`] and [`OccupancyMap::to_scene`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// What unknown cells are.
    pub unknown: UnknownCells,
    /// How [`OccupancyMap::planner`] meshes the map.
    pub mesher: MapMesher,
    /// For [`MapMesher::Quadtree`]: how the clear cells are snapped to blocks.
    pub snap: Snap,
    /// The Douglas–Peucker tolerance of the traced polygons, in cells (0 keeps every traced
    /// vertex; at most [`MAX_SIMPLIFY_CELLS`]). It is part of the tracing margin the cells
    /// are cleared with ([`MapPolygons::margin`]): a coarser outline has fewer vertices (and
    /// the mesh fewer triangles) but keeps a little more than the robot radius from walls.
    pub simplify_cells: f64,
    /// Largest triangle area of the traced mesher's mesh (m²); `None`: from the robot's
    /// radius (edges of about six radii on open floor, [`OccupancyMap::to_scene`]), or the
    /// mesher's default for a point robot.
    pub max_area: Option<f64>,
    /// The mesh's smallest angle, in degrees (the scene's `mesh.min_angle_deg`): 15 rather
    /// than the 30 of scene files. A map's many short boundary edges and its narrow passages,
    /// whose wall-to-wall edges are split so every passage has unknowns inside, force most
    /// of its triangles, and refinement with the midpoints is a fifth of a small map's first
    /// plan: tb3_sandbox's mesh has 463 triangles at 20° and 476 at 15°, but its first plan
    /// costs 4.87 M instructions at 20° and 4.72 M at 15° (map_circular 5.07 M and
    /// 4.65 M with 474 and 444 triangles; warehouse 4 490 and 3 902 triangles). Path lengths
    /// on Nav2's maps move by at most 2 % either way between 20° and 15°. The bound holds
    /// except next to the midpoints that split wall-to-wall edges ([`Bridges::Midpoints`]).
    /// The mesh stays constrained Delaunay and the walls are Dirichlet, so the system is an
    /// M-matrix and the maximum principle holds at any bound.
    pub min_angle_deg: f64,
    /// How much a map's graded costs ([`OccupancyMap::with_costs`]; `scale` and `raw` maps)
    /// shape the field, −∇·(k∇φ) + σ(φ − 1) = 0: a cell of cost c (1 … 252) conducts
    /// k = 1 / (1 + w·0.016·c) of a free cell's flow ([`COST_RESISTANCE`]), so paths go
    /// around costly cells when a free route is not much longer, and absorbs
    /// σ = w·[`cost_absorption`]`(c)` / (0.05 m)², which draws the potential
    /// toward the walls' level in the costliest cells so that walls keep their pull behind a
    /// costly band. A weight of 1 is NavFn's default: the costliest cell resists 5 times as
    /// much as a free one, as NavFn's step through it costs 5 times a free step; 0 ignores
    /// the costs (they plan as free cells). With costs and a positive weight the map is
    /// meshed by the quadtree, whose right triangles keep the system an M-matrix for any k,
    /// and the lumped absorption only adds to its diagonal. From 0 to [`MAX_COST_WEIGHT`];
    /// default 1.
    pub cost_weight: f64,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions {
            unknown: UnknownCells::Obstacle,
            mesher: MapMesher::Auto,
            snap: Snap::OpenFloor,
            simplify_cells: 1.0,
            max_area: None,
            min_angle_deg: 15.0,
            cost_weight: 1.0,
        }
    }
}

/// Why a map could not be read or turned into a scene.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// A file could not be read.
    #[error("cannot read {file}: {source}")]
    Io {
        /// The file: the YAML, or the image with the YAML that names it.
        file: String,
        /// The operating system's error.
        #[source]
        source: std::io::Error,
    },
    /// The YAML is malformed.
    #[error("{file}: not valid YAML: {message}")]
    Yaml {
        /// The YAML file.
        file: String,
        /// The parser's message, or what the document should have been.
        message: String,
    },
    /// A required field is missing.
    #[error("{file}: missing field `{field}`")]
    MissingField {
        /// The YAML file.
        file: String,
        /// The missing field (`image`, `resolution`, `origin`, ...).
        field: &'static str,
    },
    /// A field has a wrong type or value.
    #[error("{file}: field `{field}`: {message}")]
    BadField {
        /// The YAML file.
        file: String,
        /// The field with the bad value.
        field: &'static str,
        /// What is wrong with the value.
        message: String,
    },
    /// `mode` names none of trinary, scale, raw.
    #[error("{file}: field `mode`: unsupported mode `{mode}` (expected trinary, scale or raw)")]
    UnsupportedMode {
        /// The YAML file.
        file: String,
        /// The mode as written.
        mode: String,
    },
    /// The image could not be decoded.
    #[error("{file}: cannot decode the map image: {message}")]
    Image {
        /// The image file.
        file: String,
        /// The decoder's message.
        message: String,
    },
    /// The grid has no cells, or the cell list does not match its size.
    #[error("{0}")]
    BadGrid(
        /// What is wrong: the cell count against the size, the resolution or the origin.
        String,
    ),
    /// A region to change is not a range of the map's cells.
    #[error(
        "{file}: cannot change columns {columns:?}, rows {rows:?}: the map has columns 0..{width}, rows 0..{height}"
    )]
    RegionOffMap {
        /// The map's source: its YAML file, or `map` for [`OccupancyMap::from_cells`].
        file: String,
        /// The columns asked for.
        columns: std::ops::Range<usize>,
        /// The rows asked for.
        rows: std::ops::Range<usize>,
        /// The map's columns.
        width: usize,
        /// The map's rows.
        height: usize,
    },
    /// No cell is free.
    #[error("{file}: the map has no free cell")]
    EmptyMap {
        /// The image file, or the map's source (its YAML file, or `map` for
        /// [`OccupancyMap::from_cells`]).
        file: String,
    },
    /// A map option is out of range.
    #[error("map option `{option}`: {message}")]
    BadOption {
        /// The field of [`MapOptions`] (`simplify_cells`, `max_area`, `snap`).
        option: &'static str,
        /// The allowed range and the value given.
        message: String,
    },
    /// The goal lies outside the map.
    #[error("goal ({x}, {y}) is outside the map ({file}), which covers x {x0}..{x1}, y {y0}..{y1}")]
    GoalOutsideMap {
        /// The map's source: its YAML file, or `map` for [`OccupancyMap::from_cells`].
        file: String,
        /// The goal's x, in world coordinates.
        x: f64,
        /// The goal's y, in world coordinates.
        y: f64,
        /// Smallest x of the map's corners, in world coordinates.
        x0: f64,
        /// Largest x of the map's corners.
        x1: f64,
        /// Smallest y of the map's corners.
        y0: f64,
        /// Largest y of the map's corners.
        y1: f64,
    },
    /// The goal lies in a cell that is not free.
    #[error(
        "goal ({x}, {y}) is in {what} cell (column {column}, row {row} from the bottom) of {file}"
    )]
    GoalNotFree {
        /// The map's source: its YAML file, or `map` for [`OccupancyMap::from_cells`].
        file: String,
        /// The goal's x, in world coordinates.
        x: f64,
        /// The goal's y, in world coordinates.
        y: f64,
        /// The column of the goal's cell, from the left.
        column: usize,
        /// The row of the goal's cell, from the bottom (the image's last line is row 0).
        row: usize,
        /// `an occupied` or `an unknown`.
        what: &'static str,
    },
    /// The goal's cell is free but closer than the robot radius (plus the tracing margin of
    /// the traced mesher) to a blocked cell or the map's edge.
    #[error(
        "goal ({x}, {y}) is closer than the robot radius {radius}{} to {} of {file}: {distance:.3} away; {}",
        if *margin > 0.0 { format!(" plus the tracing margin {margin:.3} of the traced mesher") } else { String::new() },
        match blocker {
            Some((c, r, what)) => format!("{what} cell (column {c}, row {r} from the bottom)"),
            None => "the map's edge".to_string(),
        },
        match nearest_clear {
            Some((c, r, d)) => format!("the nearest cell that keeps it is column {c}, row {r}, {d:.3} away: move the goal there or into open space"),
            None => "no cell of the map keeps it".to_string(),
        }
    )]
    GoalTooClose {
        /// The map's source: its YAML file, or `map` for [`OccupancyMap::from_cells`].
        file: String,
        /// The goal's x, in world coordinates.
        x: f64,
        /// The goal's y, in world coordinates.
        y: f64,
        /// The robot radius.
        radius: f64,
        /// The clearance the traced polygons add to the radius (the simplification tolerance
        /// and a quarter cell, see [`MapPolygons::margin`]); zero for the quadtree mesher.
        margin: f64,
        /// The nearest blocked cell, `(column, row, "an occupied" or "an unknown")`, or
        /// `None` when the map's edge is nearer.
        blocker: Option<(u32, u32, &'static str)>,
        /// How far the goal is from it, in world units.
        distance: f64,
        /// The nearest cell that keeps the radius (and margin), `(column, row, distance from
        /// the goal to its centre)`, if any.
        nearest_clear: Option<(u32, u32, f64)>,
    },
    /// The goal's cell is clear for the robot but none of its neighbours is: nothing outside
    /// the cell can reach it.
    #[error(
        "goal ({x}, {y}) is enclosed in {file}: its cell (column {column}, row {row} from the bottom) keeps the robot radius {radius}, but no cell beside it does, so no start outside that cell can reach it; move it into open space"
    )]
    GoalEnclosed {
        /// The map's source: its YAML file, or `map` for [`OccupancyMap::from_cells`].
        file: String,
        /// The goal's x, in world coordinates.
        x: f64,
        /// The goal's y, in world coordinates.
        y: f64,
        /// The column of the goal's cell, from the left.
        column: usize,
        /// The row of the goal's cell, from the bottom.
        row: usize,
        /// The robot radius.
        radius: f64,
    },
    /// The map's free space could not be meshed or solved.
    #[error("{file}: {source}")]
    Plan {
        /// The map's source.
        file: String,
        /// What went wrong.
        #[source]
        source: PlanError,
    },
    /// The robot radius is negative or not a number.
    #[error("robot radius must be zero or positive, got {0}")]
    BadRadius(
        /// The radius given, in world units.
        f64,
    ),
}

/// The cell of `clear` whose centre is nearest to `g` (grid coordinates), ring by ring around
/// `g`'s cell: `(column, row, distance in cells)`.
fn nearest_clear(g: [f64; 2], clear: &BitGrid) -> Option<(usize, usize, f64)> {
    let (w, h) = (clear.width() as isize, clear.height() as isize);
    let (gi, gj) = (g[0].floor() as isize, g[1].floor() as isize);
    let mut nearest: Option<(usize, usize, f64)> = None;
    for k in 0..w.max(h) {
        if nearest.is_some_and(|(_, _, d)| (k as f64 - 1.0) > d) {
            break;
        }
        for j in (gj - k).max(0)..(gj + k + 1).min(h) {
            let step = if j == gj - k || j == gj + k {
                1
            } else {
                (2 * k).max(1)
            };
            let mut i = gi - k;
            while i <= gi + k {
                if i >= 0 && i < w && clear.get(i, j) {
                    let d = (i as f64 + 0.5 - g[0]).hypot(j as f64 + 0.5 - g[1]);
                    if nearest.is_none_or(|(_, _, b)| d < b) {
                        nearest = Some((i as usize, j as usize, d));
                    }
                }
                i += step;
            }
        }
    }
    nearest
}

/// A grid's place in the world: cells of `resolution` from `origin` `[x, y, yaw]`; a grid
/// cut from a map ([`OccupancyMap::cropped`]) starts `offset` cells into the map, whose
/// `extent` (columns, rows) it keeps, so that points are placed as on the whole map.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridFrame {
    resolution: f64,
    origin: [f64; 3],
    offset: [f64; 2],
    extent: [usize; 2],
}

impl GridFrame {
    /// The frame of the whole map this grid was cut from (the same for a whole map).
    fn whole(self) -> GridFrame {
        GridFrame {
            offset: [0.0, 0.0],
            ..self
        }
    }

    /// Whether a world point lies on the whole map (not only on this grid).
    fn on_map(&self, p: [f64; 2]) -> bool {
        let [x, y] = self.whole().world_to_grid(p);
        x >= 0.0 && y >= 0.0 && x < self.extent[0] as f64 && y < self.extent[1] as f64
    }

    fn grid_to_world(&self, g: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.origin[2].sin_cos();
        let (x, y) = (
            (g[0] + self.offset[0]) * self.resolution,
            (g[1] + self.offset[1]) * self.resolution,
        );
        [
            self.origin[0] + c * x - s * y,
            self.origin[1] + s * x + c * y,
        ]
    }

    fn world_to_grid(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.origin[2].sin_cos();
        let (dx, dy) = (p[0] - self.origin[0], p[1] - self.origin[1]);
        [
            (c * dx + s * dy) / self.resolution - self.offset[0],
            (-s * dx + c * dy) / self.resolution - self.offset[1],
        ]
    }
}

/// An occupancy grid with its place in the world.
///
/// Cell `(column, row)` with row 0 at the bottom (the image's last line) covers
/// `[column, column + 1] × [row, row + 1]` cells from `origin`, rotated by the origin's yaw.
#[derive(Clone, Debug)]
pub struct OccupancyMap {
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 3],
    cells: Vec<Cell>,
    /// The occupied cells, as bits (what the planners read).
    occupied: BitGrid,
    /// The unknown cells, as bits.
    unknown: BitGrid,
    /// Graded costs of free cells (0 none … 252 the costliest), row by row, when the map has
    /// them ([`OccupancyMap::with_costs`], a `scale` or `raw` map).
    costs: Option<Arc<Vec<u8>>>,
    source: String,
    /// Where this grid's cell (0, 0) lies in the map it was cut from, and that map's size
    /// (columns, rows); `[0, 0]` and its own size for a whole map.
    offset: [usize; 2],
    extent: [usize; 2],
}

/// The robot's free configuration space on a map, traced: the region a disc robot's centre
/// may take, in world coordinates.
#[derive(Clone, Debug)]
pub struct MapPolygons {
    /// The outer boundary of the goal's component (counter-clockwise).
    pub workspace: Vec<[f64; 2]>,
    /// Its holes (clockwise): the blocked cells grown by the robot radius and the margin.
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// What the cells were cleared with beyond the robot radius, in world units: the
    /// simplification tolerance, the quarter cell the contour may cut across a cell's corner
    /// and the 10⁻⁶ cells its vertices are moved off their lattice by (so that no four are
    /// cocircular, a tie Delaunay's in-circle test resolves slowly). Every point of the polygons keeps the robot radius from every blocked cell;
    /// the boundary keeps at most about the margin plus one cell more.
    pub margin: f64,
    /// The Douglas–Peucker tolerance used, in cells.
    pub simplify_cells: f64,
}

/// The most cells a map may have (2^28, a 16 384-cell square: 800 m at 5 cm). Its cells, the
/// bits of its occupancy and a clearance pass then take about 0.4 GB.
pub const MAX_MAP_CELLS: usize = 1 << 28;

/// The coarsest [`MapOptions::simplify_cells`].
pub const MAX_SIMPLIFY_CELLS: f64 = 4.0;

/// The smooth tracer's local error per step on a map, in cells (see
/// [`harmonic_trajectory::SmoothOptions::tolerance`]).
pub const TRACE_TOLERANCE_CELLS: f64 = 0.04;

impl OccupancyMap {
    /// Cells per row.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Rows.
    pub fn height(&self) -> usize {
        self.height
    }
    /// Metres per cell.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }
    /// World pose `[x, y, yaw]` of the lower-left corner of cell (0, 0).
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }
    /// The cell in `column`, `row` (row 0 at the bottom).
    pub fn cell(&self, column: usize, row: usize) -> Cell {
        self.cells[row * self.width + column]
    }

    /// Sets the cells of `columns` × `rows` (row 0 at the bottom) to `cell`: a change sensed
    /// or told, such as a door closed, a pallet put down or an aisle cleared. Planners read the
    /// map when they are built, so a changed region is a new first plan
    /// ([`OccupancyMap::planner`] or [`OccupancyMap::workspace`] again), at the cost of a first
    /// plan; the map itself is not read again. An empty range changes nothing; a range past the
    /// map's edge is refused and changes nothing.
    ///
    /// ```
    /// use harmonic_planner::map::{Cell, MapOptions, OccupancyMap};
    /// use harmonic_planner::PlannerOptions;
    /// // A 40 × 10 cell corridor at 10 cm; a robot of radius 0.2 m.
    /// let mut map = OccupancyMap::from_cells(40, 10, 0.1, [0.0; 3], vec![Cell::Free; 400])?;
    /// let (goal, start) = ([3.5, 0.5], [0.5, 0.5]);
    /// let opts = (MapOptions::default(), PlannerOptions::default());
    /// assert!(map.planner(goal, 0.2, &opts.0, &opts.1)?.plan(start).status.reached_goal());
    /// // Something is put across the corridor: the goal can no longer be reached.
    /// map.set_region(20..22, 0..10, Cell::Occupied)?;
    /// assert!(!map.planner(goal, 0.2, &opts.0, &opts.1)?.plan(start).status.reached_goal());
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn set_region(
        &mut self,
        columns: std::ops::Range<usize>,
        rows: std::ops::Range<usize>,
        cell: Cell,
    ) -> Result<(), MapError> {
        if columns.start > columns.end
            || rows.start > rows.end
            || columns.end > self.width
            || rows.end > self.height
        {
            return Err(MapError::RegionOffMap {
                file: self.source.clone(),
                columns,
                rows,
                width: self.width,
                height: self.height,
            });
        }
        for j in rows {
            for i in columns.clone() {
                self.cells[j * self.width + i] = cell;
                self.occupied.put(i, j, cell == Cell::Occupied);
                self.unknown.put(i, j, cell == Cell::Unknown);
            }
        }
        Ok(())
    }

    fn frame(&self) -> GridFrame {
        GridFrame {
            resolution: self.resolution,
            origin: self.origin,
            offset: self.offset.map(|o| o as f64),
            extent: self.extent,
        }
    }

    /// World coordinates of a point given in cells from the origin.
    pub fn grid_to_world(&self, g: [f64; 2]) -> [f64; 2] {
        self.frame().grid_to_world(g)
    }

    /// Cells from the origin of a world point (inverse of [`OccupancyMap::grid_to_world`]).
    pub fn world_to_grid(&self, p: [f64; 2]) -> [f64; 2] {
        self.frame().world_to_grid(p)
    }

    /// The cell `(column, row)` holding a world point, if it is on the map.
    pub fn cell_at(&self, p: [f64; 2]) -> Option<(usize, usize)> {
        let g = self.world_to_grid(p);
        if g[0] >= 0.0 && g[1] >= 0.0 && g[0] < self.width as f64 && g[1] < self.height as f64 {
            Some((g[0] as usize, g[1] as usize))
        } else {
            None
        }
    }

    /// World coordinates of a cell's centre.
    pub fn cell_center(&self, column: usize, row: usize) -> [f64; 2] {
        self.grid_to_world([column as f64 + 0.5, row as f64 + 0.5])
    }

    /// Whether a cell blocks the robot under the given treatment of unknown cells.
    pub fn is_blocked(&self, column: usize, row: usize, unknown: UnknownCells) -> bool {
        match self.cell(column, row) {
            Cell::Free => false,
            Cell::Occupied => true,
            Cell::Unknown => unknown == UnknownCells::Obstacle,
        }
    }

    /// The blocked cells (occupied, and unknown unless `unknown` says they are free) as bits.
    fn blocked(&self, unknown: UnknownCells) -> BitGrid {
        match unknown {
            UnknownCells::Obstacle => self.occupied.or(&self.unknown),
            UnknownCells::Free => self.occupied.clone(),
        }
    }

    /// A planner towards `goal` (world coordinates) for a disc robot of `robot_radius`,
    /// meshed as [`MapOptions::mesher`] says: the robot's free configuration space on the
    /// grid, meshed by a quadtree ([`OccupancyMap::cell_mesh`]), or the scene of
    /// [`OccupancyMap::to_scene`] ([`MapMesher::Traced`]), or whichever of them plans every
    /// start ([`MapMesher::Auto`], the default). A start on a clear cell outside the mesh is
    /// led in over clear cells. Either way a path keeps at least `robot_radius` from every
    /// occupied cell (and unknown cell, unless [`MapOptions::unknown`] says they are free).
    /// A mostly blocked map (a small arena in a large unknown map) is planned on the part
    /// that holds its free cells, with the same result.
    pub fn planner(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        planner: &PlannerOptions,
    ) -> Result<Planner, MapError> {
        // The whole build in the pool of `planner.threads` (the inner builds get none).
        if planner.threads.is_some() {
            let refused = |source| MapError::Plan {
                file: self.source.clone(),
                source,
            };
            return crate::threads::build_in(planner, refused, |inner| {
                self.planner(goal, robot_radius, opts, inner)
            });
        }
        // A map mostly blocked (a small arena in a large unknown map, as SLAM leaves them)
        // is planned on the part that holds its free cells ([`OccupancyMap::cropped`]): the
        // same planner for a fraction of the grid work. Whatever that part refuses is asked
        // of the whole map again, so that the refusal names the map's own cells.
        let started = std::time::Instant::now();
        if let Some(part) = self.cropped(opts.unknown)
            && let Ok(built) = part.planner_from(started, goal, robot_radius, opts, planner)
        {
            return Ok(built);
        }
        self.planner_from(started, goal, robot_radius, opts, planner)
    }

    /// This map cut down to the part a planner can use, where that is at most half of it:
    /// every cell not blocked under `unknown`, with at least two blocked cells around them
    /// (a clear cell's nearest blocked cell is then inside the part), cut on multiples of 64
    /// cells (the quadtree's blocks and the traced outline's jitter fall as on the whole
    /// map). Every cell outside the part is blocked. Its frame places points as the whole
    /// map's does. `None` where the part would be more than half the map or nothing is free.
    fn cropped(&self, unknown: UnknownCells) -> Option<OccupancyMap> {
        if self.offset != [0, 0] || self.extent != [self.width, self.height] {
            return None;
        }
        let [i0, i1, j0, j1] = self.blocked(unknown).unset_bounds()?;
        let down = |x: usize| x.saturating_sub(2) / 64 * 64;
        let up = |x: usize, n: usize| ((x + 2).div_ceil(64) * 64).min(n);
        let (i0, i1, j0, j1) = (down(i0), up(i1, self.width), down(j0), up(j1, self.height));
        let (w, h) = (i1 - i0, j1 - j0);
        if 2 * w * h > self.width * self.height {
            return None;
        }
        let rows = |j: usize| j * self.width + i0..j * self.width + i1;
        let cells = (j0..j1).flat_map(|j| self.cells[rows(j)].iter().copied());
        let costs = self
            .costs
            .as_ref()
            .map(|c| Arc::new((j0..j1).flat_map(|j| c[rows(j)].iter().copied()).collect()));
        let (x0, y0) = (i0 as isize, j0 as isize);
        Some(OccupancyMap {
            width: w,
            height: h,
            resolution: self.resolution,
            origin: self.origin,
            cells: cells.collect(),
            occupied: self.occupied.window(x0, y0, w, h, false),
            unknown: self.unknown.window(x0, y0, w, h, false),
            costs,
            source: self.source.clone(),
            offset: [i0, j0],
            extent: self.extent,
        })
    }

    /// [`OccupancyMap::planner`] on this grid, the build's time counted from `started`.
    fn planner_from(
        &self,
        started: std::time::Instant,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
        planner: &PlannerOptions,
    ) -> Result<Planner, MapError> {
        let plan_error = |source| MapError::Plan {
            file: self.source.clone(),
            source,
        };
        planner
            .stage(crate::planner::Stage::Meshing)
            .map_err(plan_error)?;
        if !(0.0..=MAX_COST_WEIGHT).contains(&opts.cost_weight) {
            return Err(MapError::BadOption {
                option: "cost_weight",
                message: format!(
                    "must be between 0 and {MAX_COST_WEIGHT:e} (beyond, every graded cell is a \
                     wall to the field), got {}",
                    short_number(opts.cost_weight)
                ),
            });
        }
        // Graded costs shape the field through a conductivity and an absorption, on the
        // quadtree's right triangles (any positive conductivity keeps their system an
        // M-matrix; the lumped absorption adds to its diagonal only). A map with
        // graded costs is meshed that way at every weight, 0 included, so that the weight
        // alone tells two fields apart.
        let has_costs = self.has_graded_costs(opts.unknown);
        let graded = opts.cost_weight > 0.0 && has_costs;
        let with_costs;
        let planner = if graded {
            with_costs = PlannerOptions {
                conductivity: Some(self.conductivity(opts.cost_weight)),
                absorption: Some(self.absorption(opts.cost_weight)),
                ..planner.clone()
            };
            &with_costs
        } else {
            planner
        };
        // The simplification the traced mesher runs at, or `None` for the quadtree.
        let (traced, known) = match opts.mesher {
            _ if graded => (None, Known::default()),
            MapMesher::Traced => (Some(opts.simplify_cells), Known::default()),
            MapMesher::Quadtree => (None, Known::default()),
            MapMesher::Auto if has_costs => (None, Known::default()),
            MapMesher::Auto => self.traced_is_complete(goal, robot_radius, opts)?,
        };
        // From `started`: the cut, the planner's checks and the mesher's choice.
        let check_ms = started.elapsed().as_secs_f64() * 1e3;
        match traced {
            Some(simplify_cells) => {
                let opts = &MapOptions {
                    simplify_cells,
                    ..*opts
                };
                let t = std::time::Instant::now();
                let goal_shape = harmonic_mesh::GoalShape::Point(Point::new(goal[0], goal[1]));
                let (domain, mesh_options, entry) =
                    self.traced_domain(goal, robot_radius, opts, &[goal_shape], known)?;
                let ms = t.elapsed().as_secs_f64() * 1e3;
                let entry = Entry {
                    start: Arc::new(entry),
                    trace_tolerance: self.trace_tolerance(),
                    mesh_ms: check_ms + ms,
                };
                Planner::entered_domain(domain, &mesh_options, planner, Some(entry))
                    .map_err(plan_error)
            }
            None => {
                let t = std::time::Instant::now();
                let (mesh, entry) = self.cell_space(goal, robot_radius, opts, known)?;
                let ms = t.elapsed().as_secs_f64() * 1e3;
                // A quadtree mesh always gives an M-matrix, and on a map ψ spans many orders
                // of magnitude (it decays exponentially into dead ends), where `Auto` would
                // redo a large Cholesky solve accurately anyway: solve accurately at once.
                let planner = PlannerOptions {
                    solve: match planner.solve {
                        SolveMethod::Auto => SolveMethod::Accurate,
                        other => other,
                    },
                    ..planner.clone()
                };
                let entry = Entry {
                    start: Arc::new(entry),
                    trace_tolerance: self.trace_tolerance(),
                    mesh_ms: check_ms + ms,
                };
                Planner::entered_mesh(mesh, &planner, Some(entry)).map_err(plan_error)
            }
        }
    }

    /// [`MapError::GoalTooClose`] for `goal`: the nearest blocked cell (or the map's edge)
    /// and the nearest cell of `clear` (those that keep `radius + margin`).
    fn goal_too_close(
        &self,
        goal: [f64; 2],
        radius: f64,
        margin: f64,
        clear: &BitGrid,
        blocked: &BitGrid,
    ) -> MapError {
        let g = self.world_to_grid(goal);
        let (w, h) = (self.width as isize, self.height as isize);
        // Distance (cells) from the goal to cell (i, j)'s square.
        let to_square = |i: isize, j: isize| {
            let dx = (i as f64 - g[0]).max(g[0] - (i + 1) as f64).max(0.0);
            let dy = (j as f64 - g[1]).max(g[1] - (j + 1) as f64).max(0.0);
            dx.hypot(dy)
        };
        let edge = g[0].min(g[1]).min(w as f64 - g[0]).min(h as f64 - g[1]);
        let reach = ((radius + margin) / self.resolution).ceil() as isize + 2;
        let (gi, gj) = (g[0].floor() as isize, g[1].floor() as isize);
        let mut blocker = None;
        let mut distance = edge;
        for j in (gj - reach).max(0)..(gj + reach + 1).min(h) {
            for i in (gi - reach).max(0)..(gi + reach + 1).min(w) {
                let d = to_square(i, j);
                if blocked.get(i, j) && d < distance {
                    let what = match self.cell(i as usize, j as usize) {
                        Cell::Occupied => "an occupied",
                        _ => "an unknown",
                    };
                    blocker = Some((i as u32, j as u32, what));
                    distance = d;
                }
            }
        }
        let nearest = nearest_clear(g, clear);
        MapError::GoalTooClose {
            file: self.source.clone(),
            x: goal[0],
            y: goal[1],
            radius,
            margin,
            blocker,
            distance: distance * self.resolution,
            nearest_clear: nearest.map(|(c, r, d)| (c as u32, r as u32, d * self.resolution)),
        }
    }

    /// The centre of the cell nearest to `p` (world coordinates) where a disc robot of
    /// `robot_radius` keeps its radius from every blocked cell, if one lies within `within`
    /// of `p`: where a goal given on or beside an obstacle moves to (NavFn's goal tolerance).
    /// `p` itself (not the centre) when its own cell is clear.
    pub fn nearest_clear_point(
        &self,
        p: [f64; 2],
        robot_radius: f64,
        unknown: UnknownCells,
        within: f64,
    ) -> Option<[f64; 2]> {
        if !(robot_radius >= 0.0 && within >= 0.0 && p.iter().all(|c| c.is_finite())) {
            return None;
        }
        let blocked = self.blocked(unknown);
        let clear = bits::clear_cells(&blocked, robot_radius / self.resolution);
        let g = self.world_to_grid(p);
        let own = (g[0] >= 0.0 && g[1] >= 0.0)
            .then(|| (g[0] as isize, g[1] as isize))
            .filter(|&(i, j)| clear.get(i, j));
        if own.is_some() {
            return Some(p);
        }
        let (c, r, d) = nearest_clear(g, &clear)?;
        (d * self.resolution <= within).then(|| self.cell_center(c, r))
    }

    fn goal_cell(&self, goal: [f64; 2], unknown: UnknownCells) -> Result<(usize, usize), MapError> {
        let Some((c, r)) = self
            .cell_at(goal)
            .filter(|_| goal.iter().all(|v| v.is_finite()))
        else {
            let corners = [
                [0.0, 0.0],
                [self.width as f64, 0.0],
                [0.0, self.height as f64],
                [self.width as f64, self.height as f64],
            ]
            .map(|g| self.grid_to_world(g));
            let fold = |k: usize, f: fn(f64, f64) -> f64| {
                corners.iter().map(|p| p[k]).reduce(f).unwrap_or(0.0)
            };
            return Err(MapError::GoalOutsideMap {
                file: self.source.clone(),
                x: goal[0],
                y: goal[1],
                x0: fold(0, f64::min),
                x1: fold(0, f64::max),
                y0: fold(1, f64::min),
                y1: fold(1, f64::max),
            });
        };
        if self.is_blocked(c, r, unknown) {
            return Err(MapError::GoalNotFree {
                file: self.source.clone(),
                x: goal[0],
                y: goal[1],
                column: c,
                row: r,
                what: if self.cell(c, r) == Cell::Occupied {
                    "an occupied"
                } else {
                    "an unknown"
                },
            });
        }
        Ok((c, r))
    }
}

/// The robot radius (finite, not negative) and [`MapOptions::max_area`] (positive, if set)
/// that both meshers take.
fn check_radius_and_area(robot_radius: f64, opts: &MapOptions) -> Result<(), MapError> {
    if !(robot_radius.is_finite() && robot_radius >= 0.0) {
        return Err(MapError::BadRadius(robot_radius));
    }
    if let Some(a) = opts.max_area
        && !(a.is_finite() && a > 0.0)
    {
        return Err(MapError::BadOption {
            option: "max_area",
            message: format!("must be a positive number, got {a}"),
        });
    }
    Ok(())
}

/// Grids [`MapMesher::Auto`]'s check found, handed to the mesher it chose so that it does
/// not find them again; `None` where not known.
#[derive(Default)]
struct Known {
    /// The cells clear for the radius plus the tracing margin.
    narrow: Option<BitGrid>,
    /// The cells clear for the radius, exactly.
    exact: Option<BitGrid>,
    /// Of those, the ones 4-connected to the goal's cell.
    reachable: Option<BitGrid>,
}
