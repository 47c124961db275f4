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
pub mod movingai;
mod trace;

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
    /// number), else the quadtree. A map with graded costs (free cells of cost > 0) is
    /// always meshed by the quadtree, at every [`MapOptions::cost_weight`], 0 included, so
    /// that two weights give two fields on one mesh. The default.
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
    /// shape the field: a cell of cost c (1 … 252) conducts k = 1 / (1 + w·0.016·c) of a
    /// free cell's flow ([`COST_RESISTANCE`]), so paths go around costly cells when a free
    /// route is not much longer. A weight of 1 is NavFn's default: the costliest cell resists
    /// 5 times as much as a free one, as NavFn's step through it costs 5 times a free step;
    /// 0 ignores the costs (they plan as free cells). With costs and a positive weight the map is meshed by the
    /// quadtree, whose right triangles keep the system an M-matrix for any k. Default 1.
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

/// A grid's place in the world: cells of `resolution` from `origin` `[x, y, yaw]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GridFrame {
    resolution: f64,
    origin: [f64; 3],
}

impl GridFrame {
    fn grid_to_world(&self, g: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.origin[2].sin_cos();
        let (x, y) = (g[0] * self.resolution, g[1] * self.resolution);
        [
            self.origin[0] + c * x - s * y,
            self.origin[1] + s * x + c * y,
        ]
    }

    fn world_to_grid(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.origin[2].sin_cos();
        let (dx, dy) = (p[0] - self.origin[0], p[1] - self.origin[1]);
        [
            (c * dx + s * dy) / self.resolution,
            (-s * dx + c * dy) / self.resolution,
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

fn field<'a>(doc: &'a Value, file: &str, name: &'static str) -> Result<&'a Value, MapError> {
    doc.get(name).ok_or_else(|| MapError::MissingField {
        file: file.to_string(),
        field: name,
    })
}

fn bad(file: &str, field: &'static str, message: String) -> MapError {
    MapError::BadField {
        file: file.to_string(),
        field,
        message,
    }
}

fn number(v: &Value, file: &str, name: &'static str) -> Result<f64, MapError> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| bad(file, name, format!("expected a finite number, got {v:?}")))
}

/// The map_server header of a map.
struct Header {
    image: PathBuf,
    resolution: f64,
    origin: [f64; 3],
    occupied_thresh: f64,
    free_thresh: f64,
    negate: bool,
    mode: Mode,
}

fn parse_header(text: &str, file: &str, dir: &Path) -> Result<Header, MapError> {
    let doc: Value = serde_yaml_ng::from_str(text).map_err(|e| MapError::Yaml {
        file: file.to_string(),
        message: e.to_string(),
    })?;
    if !doc.is_mapping() {
        return Err(MapError::Yaml {
            file: file.to_string(),
            message: "expected a mapping of fields (image, resolution, origin, ...)".into(),
        });
    }
    let image = field(&doc, file, "image")?;
    let image = image.as_str().filter(|s| !s.is_empty()).ok_or_else(|| {
        bad(
            file,
            "image",
            format!("expected a file name, got {image:?}"),
        )
    })?;
    let resolution = number(field(&doc, file, "resolution")?, file, "resolution")?;
    if resolution <= 0.0 {
        return Err(bad(
            file,
            "resolution",
            format!("must be positive (metres per cell), got {resolution}"),
        ));
    }
    let origin_v = field(&doc, file, "origin")?;
    let origin_seq = origin_v
        .as_sequence()
        .filter(|s| s.len() == 3 || s.len() == 2)
        .ok_or_else(|| {
            bad(
                file,
                "origin",
                format!("expected [x, y, yaw], got {origin_v:?}"),
            )
        })?;
    let mut origin = [0.0; 3];
    for (o, v) in origin.iter_mut().zip(origin_seq) {
        *o = number(v, file, "origin")?;
    }
    let thresh = |name: &'static str, default: f64| -> Result<f64, MapError> {
        match doc.get(name) {
            None => Ok(default),
            Some(v) => {
                let t = number(v, file, name)?;
                if (0.0..=1.0).contains(&t) {
                    Ok(t)
                } else {
                    Err(bad(file, name, format!("must be between 0 and 1, got {t}")))
                }
            }
        }
    };
    let occupied_thresh = thresh("occupied_thresh", 0.65)?;
    let free_thresh = thresh("free_thresh", 0.196)?;
    if free_thresh > occupied_thresh {
        return Err(bad(
            file,
            "free_thresh",
            format!("{free_thresh} is above occupied_thresh {occupied_thresh}"),
        ));
    }
    let negate = match doc.get("negate") {
        None => false,
        Some(v) => match (v.as_bool(), v.as_i64()) {
            (Some(b), _) => b,
            (None, Some(0)) => false,
            (None, Some(1)) => true,
            _ => return Err(bad(file, "negate", format!("expected 0 or 1, got {v:?}"))),
        },
    };
    let mode = match doc.get("mode") {
        None => Mode::Trinary,
        Some(v) => match v.as_str() {
            Some("trinary") => Mode::Trinary,
            Some("scale") => Mode::Scale,
            Some("raw") => Mode::Raw,
            Some(other) => {
                return Err(MapError::UnsupportedMode {
                    file: file.to_string(),
                    mode: other.to_string(),
                });
            }
            None => return Err(bad(file, "mode", format!("expected a name, got {v:?}"))),
        },
    };
    Ok(Header {
        image: dir.join(image),
        resolution,
        origin,
        occupied_thresh,
        free_thresh,
        negate,
        mode,
    })
}

/// The map_server rule for one pixel, from the average of its colour channels (0..=255):
/// the cell, and its graded cost. In `scale` and `raw` modes a value between the thresholds
/// is a free cell with a cost rising from 1 at the free threshold to 252 at the occupied one
/// (as Nav2's static layer reads such maps); in `trinary` mode it is unknown.
fn classify(avg: f64, h: &Header) -> (Cell, u8) {
    let occ = match h.mode {
        Mode::Raw => {
            if avg > 100.0 {
                return (Cell::Unknown, 0);
            }
            avg / 100.0
        }
        Mode::Trinary | Mode::Scale => {
            let v = if h.negate { 255.0 - avg } else { avg };
            (255.0 - v) / 255.0
        }
    };
    if occ > h.occupied_thresh {
        (Cell::Occupied, 0)
    } else if occ < h.free_thresh {
        (Cell::Free, 0)
    } else if h.mode == Mode::Trinary {
        (Cell::Unknown, 0)
    } else {
        let span = (h.occupied_thresh - h.free_thresh).max(f64::MIN_POSITIVE);
        let cost = 1.0 + 251.0 * ((occ - h.free_thresh) / span).clamp(0.0, 1.0);
        (Cell::Free, cost.round() as u8)
    }
}

impl OccupancyMap {
    /// Reads a `map_server` YAML file and the image it names (relative to the YAML's folder).
    pub fn load(yaml: impl AsRef<Path>) -> Result<OccupancyMap, MapError> {
        let yaml = yaml.as_ref();
        let file = yaml.display().to_string();
        let text = std::fs::read_to_string(yaml).map_err(|source| MapError::Io {
            file: file.clone(),
            source,
        })?;
        let dir = yaml.parent().unwrap_or(Path::new("."));
        let header = parse_header(&text, &file, dir)?;
        let image_file = header.image.display().to_string();
        let bytes = std::fs::read(&header.image).map_err(|source| MapError::Io {
            file: format!("{image_file} (field `image` of {file})"),
            source,
        })?;
        let mut map = OccupancyMap::decoded(&header, &bytes, image_file)?;
        map.source = file;
        Ok(map)
    }

    /// A map from the text of a `map_server` YAML document and the bytes of its image (its
    /// `image` field must name a file, which is not read: the image is `image`); `name`
    /// stands for the files in messages. What [`OccupancyMap::load`] does once the files are
    /// read, for maps that come from elsewhere than files (and for fuzzing).
    pub fn from_bytes(yaml: &str, image: &[u8], name: &str) -> Result<OccupancyMap, MapError> {
        let header = parse_header(yaml, name, Path::new(""))?;
        let mut map = OccupancyMap::decoded(&header, image, name.to_string())?;
        map.source = name.to_string();
        Ok(map)
    }

    /// Decodes the image `bytes` (PGM or PNG, named `image_file` in messages) and classifies
    /// its pixels by `header`.
    fn decoded(
        header: &Header,
        bytes: &[u8],
        image_file: String,
    ) -> Result<OccupancyMap, MapError> {
        let img = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| MapError::Image {
                file: image_file.clone(),
                message: e.to_string(),
            })?
            .decode()
            .map_err(|e| MapError::Image {
                file: image_file.clone(),
                message: e.to_string(),
            })?;
        let (width, height) = (img.width() as usize, img.height() as usize);
        if width == 0 || height == 0 {
            return Err(MapError::EmptyMap { file: image_file });
        }
        let rgb = img.to_rgb8();
        let mut cells = vec![Cell::Unknown; width * height];
        let mut costs = vec![0u8; width * height];
        for (x, y, p) in rgb.enumerate_pixels() {
            let avg = (f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0;
            let row = height - 1 - y as usize;
            (
                cells[row * width + x as usize],
                costs[row * width + x as usize],
            ) = classify(avg, header);
        }
        let map = OccupancyMap::from_cells(width, height, header.resolution, header.origin, cells)?;
        if costs.iter().any(|&c| c > 0) {
            map.with_costs(costs)
        } else {
            Ok(map)
        }
    }

    /// A map from cells listed row by row, row 0 at the bottom.
    pub fn from_cells(
        width: usize,
        height: usize,
        resolution: f64,
        origin: [f64; 3],
        cells: Vec<Cell>,
    ) -> Result<OccupancyMap, MapError> {
        if width.saturating_mul(height) > MAX_MAP_CELLS {
            return Err(MapError::BadGrid(format!(
                "a {width} × {height} grid has more than {MAX_MAP_CELLS} cells, the most a map may have"
            )));
        }
        if width == 0 || height == 0 || cells.len() != width * height {
            return Err(MapError::BadGrid(format!(
                "a {width} × {height} grid needs {} cells, got {}",
                width * height,
                cells.len()
            )));
        }
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(MapError::BadGrid(format!(
                "resolution must be positive, got {resolution}"
            )));
        }
        if !origin.iter().all(|v| v.is_finite()) {
            return Err(MapError::BadGrid(format!(
                "origin must be finite, got {origin:?}"
            )));
        }
        let bits = |kind: Cell| BitGrid::from_slice(width, height, &cells, |c| c == kind);
        Ok(OccupancyMap {
            width,
            height,
            resolution,
            origin,
            occupied: bits(Cell::Occupied),
            unknown: bits(Cell::Unknown),
            cells,
            costs: None,
            source: "map".into(),
        })
    }

    /// The map with graded costs for its free cells, row by row as the cells (0 none, 1 …
    /// 252 the costliest; values above 252 are refused, and costs of blocked cells are
    /// ignored). With [`MapOptions::cost_weight`] w > 0 they shape the field: a cell of cost
    /// c conducts 1 / (1 + w·0.016·c) of a free cell's flow.
    pub fn with_costs(mut self, costs: Vec<u8>) -> Result<OccupancyMap, MapError> {
        if costs.len() != self.cells.len() {
            return Err(MapError::BadGrid(format!(
                "{} costs for a {} × {} grid",
                costs.len(),
                self.width,
                self.height
            )));
        }
        if let Some(i) = costs.iter().position(|&c| c > MAX_GRADED_COST) {
            return Err(MapError::BadGrid(format!(
                "cost {} of cell (column {}, row {}) is above {MAX_GRADED_COST}, the costliest free cell",
                costs[i],
                i % self.width,
                i / self.width
            )));
        }
        self.costs = Some(Arc::new(costs));
        Ok(self)
    }

    /// The graded cost of cell `(column, row)` (0 without costs).
    pub fn cost(&self, column: usize, row: usize) -> u8 {
        self.costs
            .as_ref()
            .and_then(|c| c.get(row * self.width + column).copied())
            .unwrap_or(0)
    }

    /// The conductivity of the cell under a point for `weight`: 1 / (1 + weight·0.016·c)
    /// for a cell of cost c (1 off the map and on cells without cost).
    fn conductivity(&self, weight: f64) -> crate::planner::Conductivity {
        let costs = self.costs.clone().unwrap_or_default();
        let frame = GridFrame {
            resolution: self.resolution,
            origin: self.origin,
        };
        let (w, h) = (self.width, self.height);
        Arc::new(move |p: Point| {
            let g = frame.world_to_grid([p.x, p.y]);
            let (i, j) = (g[0].floor(), g[1].floor());
            let cost = if i >= 0.0 && j >= 0.0 && (i as usize) < w && (j as usize) < h {
                costs.get(j as usize * w + i as usize).copied().unwrap_or(0)
            } else {
                0
            };
            1.0 / (1.0 + weight * COST_RESISTANCE * f64::from(cost))
        })
    }

    /// The graded costs as rectangles for a picture: runs of equal cost along each row, in
    /// world coordinates, each with its cost / 252 ([`crate::planner::SvgOptions::shaded`]).
    pub fn cost_shading(&self) -> Vec<(Vec<[f64; 2]>, f64)> {
        let mut out = Vec::new();
        let Some(costs) = &self.costs else {
            return out;
        };
        for row in 0..self.height {
            let mut column = 0;
            while column < self.width {
                let c = costs[row * self.width + column];
                let mut end = column + 1;
                while end < self.width && costs[row * self.width + end] == c {
                    end += 1;
                }
                if c > 0 {
                    let (x0, x1, y0, y1) =
                        (column as f64, end as f64, row as f64, row as f64 + 1.0);
                    let ring = [[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
                        .map(|g| self.grid_to_world(g))
                        .to_vec();
                    out.push((ring, f64::from(c) / f64::from(MAX_GRADED_COST)));
                }
                column = end;
            }
        }
        out
    }

    /// Whether some free cell has a graded cost.
    fn has_graded_costs(&self, unknown: UnknownCells) -> bool {
        self.costs.as_ref().is_some_and(|costs| {
            costs
                .iter()
                .enumerate()
                .any(|(i, &c)| c > 0 && !self.is_blocked(i % self.width, i / self.width, unknown))
        })
    }

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
    fn traced(
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
        let (_, (polygons, domain, mesh_options)) =
            trace::trace(&clear, gc, gr, eps, self.world_to_grid(goal), check)
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

    /// Traced rings (grid coordinates) in world coordinates: the outer ring the workspace,
    /// the holes its obstacles.
    fn world_polygons(&self, rings: &trace::Traced, margin: f64, eps: f64) -> MapPolygons {
        let world = |k: usize| -> Vec<[f64; 2]> {
            rings.rings[k]
                .iter()
                .map(|&g| self.grid_to_world(g))
                .collect()
        };
        MapPolygons {
            workspace: rings.outer().map(world).unwrap_or_default(),
            obstacles: rings.holes().map(world).collect(),
            margin,
            simplify_cells: eps,
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
    /// [`OccupancyMap::to_scene`] ([`MapMesher::Traced`], the default). A start on a clear
    /// cell outside the quadtree's mesh is led in over clear cells. Either way a path
    /// keeps at least `robot_radius` from every occupied cell (and unknown cell, unless
    /// [`MapOptions::unknown`] says they are free).
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
        let plan_error = |source| MapError::Plan {
            file: self.source.clone(),
            source,
        };
        planner
            .stage(crate::planner::Stage::Meshing)
            .map_err(plan_error)?;
        if !(opts.cost_weight.is_finite() && opts.cost_weight >= 0.0) {
            return Err(MapError::BadOption {
                option: "cost_weight",
                message: format!("must be zero or positive, got {}", opts.cost_weight),
            });
        }
        // Graded costs shape the field through a conductivity, on the quadtree's right
        // triangles (any positive conductivity keeps their system an M-matrix). A map with
        // graded costs is meshed that way at every weight, 0 included, so that the weight
        // alone tells two fields apart.
        let has_costs = self.has_graded_costs(opts.unknown);
        let graded = opts.cost_weight > 0.0 && has_costs;
        let with_costs;
        let planner = if graded {
            with_costs = PlannerOptions {
                conductivity: Some(self.conductivity(opts.cost_weight)),
                ..planner.clone()
            };
            &with_costs
        } else {
            planner
        };
        let checked = std::time::Instant::now();
        let (traced, known) = match opts.mesher {
            _ if graded => (false, Known::default()),
            MapMesher::Traced => (true, Known::default()),
            MapMesher::Quadtree => (false, Known::default()),
            MapMesher::Auto if has_costs => (false, Known::default()),
            MapMesher::Auto => self.traced_is_complete(goal, robot_radius, opts)?,
        };
        let check_ms = checked.elapsed().as_secs_f64() * 1e3;
        match traced {
            true => {
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
            false => {
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

    /// Whether the traced mesher plans every start the exact clear cells connect to `goal`
    /// (see [`MapMesher::Auto`]): the goal's cell keeps the radius plus the tracing margin,
    /// every clear cell 4-connected to the goal's lies within a lead-in's reach of a cell
    /// that keeps the margin too, and the margin closes no loop (same Euler number).
    /// What it found is handed on, so the chosen mesher does not find it again.
    fn traced_is_complete(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<(bool, Known), MapError> {
        check_radius_and_area(robot_radius, opts)?;
        let (gc, gr) = self.goal_cell(goal, opts.unknown)?;
        let res = self.resolution;
        let blocked = self.blocked(opts.unknown);
        let exact = bits::clear_cells(&blocked, robot_radius / res);
        let all = bits::component(&exact, gc, gr);
        let margin = opts.simplify_cells + trace::CONTOUR_CUT + trace::JITTER;
        let narrow = bits::clear_cells(&blocked, robot_radius / res + margin);
        let complete = narrow.get(gc as isize, gr as isize) && {
            let kept = bits::component(&narrow, gc, gr);
            // The lead-in searches margin + 4 cells around a start; a cell within
            // margin + 1 of a kept cell is well inside that.
            all.subset_of(&kept.dilated(margin.ceil() as usize + 1))
                && all.euler_number() == kept.euler_number()
        };
        let known = Known {
            narrow: Some(narrow),
            exact: Some(exact),
            reachable: Some(all),
        };
        Ok((complete, known))
    }

    /// The smooth tracer's local error per step on this map: [`TRACE_TOLERANCE_CELLS`] of a
    /// cell. A map places its obstacles to a cell, so following the field more closely
    /// buys nothing (the clearance is kept by the mesh either way); the scene default,
    /// 10⁻⁵ of the scene's size, is a tenth of this on Nav2's 384² maps, where it cost a
    /// quarter of the first plan's time.
    fn trace_tolerance(&self) -> f64 {
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
    fn traced_domain(
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
    fn cell_space(
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
        let clear = clear_bits.to_bools();
        let too_close = || self.goal_too_close(goal, robot_radius, 0.0, &clear_bits, &blocked);
        // The 4-connected component of `cells` holding the goal's cell.
        let fill = |cells: &[bool]| {
            bits::component(&BitGrid::from_slice(w, h, cells, |c| c), gc, gr).to_bools()
        };
        if !clear[gr * w + gc] {
            return Err(too_close());
        }
        let goal_cell = gr * w + gc;
        let exact = || fill(&clear);
        let (component, block) = match opts.snap {
            Snap::Off => (exact(), 1),
            Snap::Blocks(b) => {
                let free = cells::snapped(&clear, w, h, b);
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
                let free = (b > 1).then(|| cells::snapped_on_open_floor(&clear, w, h, b, square));
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
            .iter()
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
        let halves: Vec<Block> = (0..2 * h)
            .flat_map(|j| (0..2 * w).map(move |i| (i, j)))
            .map(|(i, j)| labels[(j / 2) * w + i / 2])
            .collect();
        drop(labels);
        let grid = BlockGrid::new(2 * w, 2 * h, halves).map_err(mesh_error)?;
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
    fn scene_of(
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

/// What [`OccupancyMap::traced`] makes: the polygons, the blocked cells they were traced
/// from, and their domain with its mesh options.
struct TracedDomain {
    polygons: MapPolygons,
    blocked: BitGrid,
    domain: harmonic_mesh::Domain,
    mesh_options: MeshOptions,
}

/// `error` from [`harmonic_mesh::Domain::of_rings`] on `rings` (its workspace the outer ring,
/// its obstacles the holes in order), with the rings it blames: both rings of a crossing or a
/// wrong nesting, and a hole outside the outer ring with the outer ring.
fn refused(rings: &trace::Traced, error: harmonic_mesh::MeshError) -> trace::Refused {
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
