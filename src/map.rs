//! Occupancy-grid maps in the ROS `map_server` format, turned into scenes.
//!
//! A map is a YAML file (`image`, `resolution`, `origin: [x, y, yaw]`, `occupied_thresh`,
//! `free_thresh`, `negate`, `mode`) naming a PGM or PNG image. Each pixel becomes a free,
//! occupied or unknown cell by the `map_server` rules. [`OccupancyMap::to_scene`] traces the
//! free area that holds the goal (marching squares on the cell centres), simplifies its
//! boundary (Douglas–Peucker, about half a cell, coarser up to 1.5 cells while the boundary
//! has more than [`MapOptions::boundary_budget`] vertices) and returns a [`Scene`] whose
//! workspace is that area's outer boundary and whose obstacles are its holes, so the planner,
//! the command line and the pictures work on maps unchanged. The mesh is sized for the robot:
//! triangles with edges of about four robot radii on open floor, graded down by the
//! refinement near walls and in narrow passages (smallest angle 25°).
//!
//! The traced polygons never expose an occupied cell: free space is traced a quarter cell
//! inside the free cells, free gaps narrower than three cells are closed first (no robot passes
//! them), and the scene's robot radius is the requested one plus [`MapPolygons::margin`], the
//! most the simplified polygons can cut into an occupied cell (a simplified ring stays within
//! the tolerance of the traced one, so the polygons offset by it hold every occupied cell). A path that keeps the scene's
//! radius from the polygons therefore keeps the requested radius from every occupied cell.
//! Free islands inside occupied blobs (a closed room) and free areas not connected to the
//! goal are outside the scene.
//!
//! ```
//! use harmonic_planner::map::{Cell, MapOptions, OccupancyMap};
//! use harmonic_planner::Planner;
//! // A 40 × 30 cell room at 10 cm with a wall in the middle that leaves a door at the top.
//! let (w, h) = (40, 30);
//! let mut cells = vec![Cell::Free; w * h];
//! for j in 0..22 {
//!     for i in 19..21 {
//!         cells[j * w + i] = Cell::Occupied;
//!     }
//! }
//! let map = OccupancyMap::from_cells(w, h, 0.1, [0.0, 0.0, 0.0], cells)?;
//! let scene = map.to_scene([3.5, 0.5], 0.0, &MapOptions::default())?;
//! let planner = Planner::new(&scene)?;
//! let path = planner.plan([0.5, 0.5]);
//! assert!(path.status.reached_goal());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};

use geo::{Coord, LineString, Simplify};
use serde_yaml_ng::Value;

use harmonic_mesh::Point;
use harmonic_mesh::quadtree::{Block, BlockGrid, QuadtreeOptions, quadtree_mesh};

use crate::planner::{PlanError, Planner, PlannerOptions};
use crate::scene::{Goals, MeshSpec, Region, RobotSpec, Scene};
use harmonic_fem::SolveMethod;

mod cells;

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
    /// As trinary; values between the thresholds would be costs, and a binary planner treats
    /// them as unknown.
    Scale,
    /// The pixel value is the occupancy in percent (0 free … 100 occupied, above 100 unknown),
    /// compared with the thresholds; `negate` does not apply.
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
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MapMesher {
    /// The robot's free configuration space on the map's own grid: the cells whose square
    /// keeps the robot radius from every blocked cell's square, exactly, with no margin
    /// (snapped to blocks on open floor, [`MapOptions::snap`]), meshed by a balanced
    /// quadtree of right isosceles triangles ([`harmonic_mesh::quadtree`]): no tracing, no
    /// polygon booleans, no refinement.
    Quadtree,
    /// The traced, simplified polygons of [`OccupancyMap::to_scene`], meshed by constrained
    /// Delaunay refinement like any scene (the default: on Nav2's maps the faster first plan
    /// on five of six, see the README's map table).
    #[default]
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

/// Options of [`OccupancyMap::planner`] and [`OccupancyMap::to_scene`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapOptions {
    /// What unknown cells are.
    pub unknown: UnknownCells,
    /// How [`OccupancyMap::planner`] meshes the map.
    pub mesher: MapMesher,
    /// For [`MapMesher::Quadtree`]: how the clear cells are snapped to blocks.
    pub snap: Snap,
    /// The finest Douglas–Peucker tolerance of the traced polygons, in cells (0 keeps every
    /// traced vertex; at most 0.5).
    pub simplify_cells: f64,
    /// The traced boundary's vertex budget: while the polygons have more vertices, the
    /// tolerance grows (by half each time) up to [`MapOptions::max_simplify_cells`]. A large
    /// map's staircase boundaries otherwise force tens of thousands of small triangles.
    pub boundary_budget: usize,
    /// The coarsest tolerance the budget may reach, in cells (at most 3). Whatever the
    /// tolerance, [`MapPolygons::margin`] grows with it, so the clearance from occupied cells
    /// is kept (the polygons are simplified, then offset by the error through the robot's
    /// radius).
    pub max_simplify_cells: f64,
    /// Largest triangle area of the scene's mesh (m²); `None`: from the robot's radius (edges
    /// of about four radii on open floor, [`OccupancyMap::to_scene`]), or the mesher's
    /// default for a point robot.
    pub max_area: Option<f64>,
    /// The mesh's smallest angle, in degrees (the scene's `mesh.min_angle_deg`): 25 rather
    /// than the 30 of scene files, which halves the triangles a map's many short boundary
    /// edges force (the mesh stays constrained Delaunay, so the maximum principle holds).
    pub min_angle_deg: f64,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions {
            unknown: UnknownCells::Obstacle,
            mesher: MapMesher::Traced,
            snap: Snap::OpenFloor,
            simplify_cells: 0.45,
            boundary_budget: 1000,
            max_simplify_cells: 1.5,
            max_area: None,
            min_angle_deg: 25.0,
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
        /// The field of [`MapOptions`] (`simplify_cells`, `max_simplify_cells`, `max_area`).
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
    /// The goal's free cell is in a gap narrower than three cells.
    #[error(
        "goal ({x}, {y}) (column {column}, row {row} from the bottom of {file}) is in a free gap narrower than three cells next to an obstacle; move it into open space"
    )]
    GoalInNarrowGap {
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
    },
    /// The goal's cell is free but closer than the robot radius to a blocked cell.
    #[error(
        "goal ({x}, {y}) is closer than the robot radius {radius} to an occupied or unknown cell of {file} (or to the map's edge); move it into open space"
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
    source: String,
}

/// The traced geometry of a map, in world coordinates, before any inflation.
#[derive(Clone, Debug)]
pub struct MapPolygons {
    /// The outer boundary of the free area holding the goal (counter-clockwise).
    pub workspace: Vec<[f64; 2]>,
    /// The holes of that area: obstacles, each a simple polygon (clockwise).
    pub obstacles: Vec<Vec<[f64; 2]>>,
    /// How far (in world units) the polygons may cut into an occupied cell: a quarter-cell
    /// chamfer at cell corners plus the simplification tolerance.
    pub margin: f64,
    /// The Douglas–Peucker tolerance used, in cells (see [`MapOptions::boundary_budget`]).
    pub simplify_cells: f64,
}

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

/// The map_server rule for one pixel, from the average of its colour channels (0..=255).
fn classify(avg: f64, h: &Header) -> Cell {
    let occ = match h.mode {
        Mode::Raw => {
            if avg > 100.0 {
                return Cell::Unknown;
            }
            avg / 100.0
        }
        Mode::Trinary | Mode::Scale => {
            let v = if h.negate { 255.0 - avg } else { avg };
            (255.0 - v) / 255.0
        }
    };
    if occ > h.occupied_thresh {
        Cell::Occupied
    } else if occ < h.free_thresh {
        Cell::Free
    } else {
        Cell::Unknown
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
        for (x, y, p) in rgb.enumerate_pixels() {
            let avg = (f64::from(p[0]) + f64::from(p[1]) + f64::from(p[2])) / 3.0;
            let row = height - 1 - y as usize;
            cells[row * width + x as usize] = classify(avg, &header);
        }
        let mut map =
            OccupancyMap::from_cells(width, height, header.resolution, header.origin, cells)?;
        map.source = file;
        Ok(map)
    }

    /// A map from cells listed row by row, row 0 at the bottom.
    pub fn from_cells(
        width: usize,
        height: usize,
        resolution: f64,
        origin: [f64; 3],
        cells: Vec<Cell>,
    ) -> Result<OccupancyMap, MapError> {
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
        Ok(OccupancyMap {
            width,
            height,
            resolution,
            origin,
            cells,
            source: "map".into(),
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

    /// Traces the free area that holds `goal` and its holes (see the module documentation).
    pub fn polygons(&self, goal: [f64; 2], opts: &MapOptions) -> Result<MapPolygons, MapError> {
        if !(opts.simplify_cells.is_finite() && (0.0..=0.5).contains(&opts.simplify_cells)) {
            return Err(MapError::BadOption {
                option: "simplify_cells",
                message: format!(
                    "must be between 0 and 0.5 cells, got {}",
                    opts.simplify_cells
                ),
            });
        }
        if !(opts.max_simplify_cells.is_finite()
            && (opts.simplify_cells..=3.0).contains(&opts.max_simplify_cells))
        {
            return Err(MapError::BadOption {
                option: "max_simplify_cells",
                message: format!(
                    "must be between simplify_cells ({}) and 3 cells, got {}",
                    opts.simplify_cells, opts.max_simplify_cells
                ),
            });
        }
        let (w, h) = (self.width, self.height);
        let free: Vec<bool> = (0..w * h)
            .map(|k| !self.is_blocked(k % w, k / w, opts.unknown))
            .collect();
        if !free.iter().any(|&f| f) {
            return Err(MapError::EmptyMap {
                file: self.source.clone(),
            });
        }
        let (gc, gr) = self.goal_cell(goal, opts.unknown)?;
        let open = opening(&free, w, h);
        if !open[gr * w + gc] {
            return Err(MapError::GoalInNarrowGap {
                file: self.source.clone(),
                x: goal[0],
                y: goal[1],
                column: gc,
                row: gr,
            });
        }
        let component = flood_fill(&open, w, h, gr * w + gc);
        let rings = march(&component, w, h);
        let (eps, rings) = simplify_to_budget(rings, opts);
        let mut workspace: Option<(f64, Vec<[f64; 2]>)> = None;
        let mut obstacles = Vec::new();
        for ring in rings {
            let area = signed_area(&ring);
            let world: Vec<[f64; 2]> = ring.iter().map(|&g| self.grid_to_world(g)).collect();
            if area > 0.0 {
                // One outer ring is expected (the component is connected); keep the largest.
                if workspace.as_ref().is_none_or(|(a, _)| area > *a) {
                    workspace = Some((area, world));
                }
            } else if area < 0.0 {
                obstacles.push(world);
            }
        }
        let (_, workspace) = workspace.ok_or_else(|| MapError::EmptyMap {
            file: self.source.clone(),
        })?;
        Ok(MapPolygons {
            workspace,
            obstacles,
            margin: self.resolution * ((1.0 - CROSSING) / std::f64::consts::SQRT_2 + eps),
            simplify_cells: eps,
        })
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
        let plan_error = |source| MapError::Plan {
            file: self.source.clone(),
            source,
        };
        match opts.mesher {
            MapMesher::Traced => {
                let scene = self.to_scene(goal, robot_radius, opts)?;
                Planner::with_options(&scene, planner).map_err(plan_error)
            }
            MapMesher::Quadtree => {
                planner.stage(crate::planner::Stage::Meshing);
                let t = std::time::Instant::now();
                let (mesh, entry) = self.cell_space(goal, robot_radius, opts)?;
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
                Planner::from_mesh(mesh, &planner)
                    .map(|p| p.with_mesh_time(ms).with_entry(std::sync::Arc::new(entry)))
                    .map_err(plan_error)
            }
        }
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
        Ok(self.cell_space(goal, robot_radius, opts)?.0)
    }

    /// [`OccupancyMap::cell_mesh`] and the lead-in from clear cells the blocks left out (or
    /// that touch the mesh only at a corner).
    fn cell_space(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
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
        let blocked: Vec<bool> = self
            .cells
            .iter()
            .map(|&c| match c {
                Cell::Free => false,
                Cell::Occupied => true,
                Cell::Unknown => opts.unknown == UnknownCells::Obstacle,
            })
            .collect();
        let clear = cells::clear_cells(&blocked, w, h, robot_radius / res);
        drop(blocked);
        let too_close = || MapError::GoalTooClose {
            file: self.source.clone(),
            x: goal[0],
            y: goal[1],
            radius: robot_radius,
        };
        if !clear[gr * w + gc] {
            return Err(too_close());
        }
        let goal_cell = gr * w + gc;
        let exact = || flood_fill(&clear, w, h, goal_cell);
        let (component, block) = match opts.snap {
            Snap::Off => (exact(), 1),
            Snap::Blocks(b) => {
                let free = cells::snapped(&clear, w, h, b);
                if !free[goal_cell] {
                    return Err(too_close());
                }
                (flood_fill(&free, w, h, goal_cell), b)
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
                        let snapped = flood_fill(&free, w, h, goal_cell);
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
        let clear_area = component.iter().filter(|&&c| c).count() as f64 * res * res;
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
        let mut meshed = component;
        meshed[goal_cell] = false;
        let entry = cells::CellEntry {
            width: w,
            height: h,
            clear,
            meshed,
            frame: self.frame(),
            reach: 4 * block,
        };
        // The largest leaf: triangles of at most max_area (a leaf is two of them), else
        // about four robot radii across, else (a point robot) the scene default's size.
        let leaf = match opts.max_area {
            Some(a) => (2.0 * a).sqrt(),
            None if robot_radius > 0.0 => 4.0 * robot_radius,
            None => (2.0 * clear_area / 20_000.0).sqrt(),
        };
        let mut max_level = 0u8;
        while max_level < 15 && (2usize << max_level) as f64 * res <= leaf {
            max_level += 1;
        }
        let mesh_error = |e: harmonic_mesh::MeshError| MapError::Plan {
            file: self.source.clone(),
            source: e.into(),
        };
        let grid = BlockGrid::new(w, h, labels).map_err(mesh_error)?;
        let mesh = quadtree_mesh(&grid, &QuadtreeOptions { max_level }, |x, y| {
            let p = self.grid_to_world([x, y]);
            Point::new(p[0], p[1])
        })
        .map_err(mesh_error)?;
        Ok((mesh, entry))
    }

    /// A scene for planning towards `goal` (world coordinates) with a disc robot of
    /// `robot_radius`: the workspace and obstacles of [`OccupancyMap::polygons`], a point goal,
    /// and a robot radius of `robot_radius` plus the tracing margin.
    pub fn to_scene(
        &self,
        goal: [f64; 2],
        robot_radius: f64,
        opts: &MapOptions,
    ) -> Result<Scene, MapError> {
        check_radius_and_area(robot_radius, opts)?;
        let polys = self.polygons(goal, opts)?;
        let radius = robot_radius + polys.margin;
        let max_area = opts
            .max_area
            .or_else(|| robot_area(&polys, robot_radius, radius));
        Ok(Scene {
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
                max_area,
                min_angle_deg: Some(opts.min_angle_deg),
                grading: None,
                simplify: None,
            },
            robot: RobotSpec { radius },
        })
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

/// Where the traced boundary crosses a lattice edge between a blocked and a free cell centre,
/// as a fraction of the way from the blocked one: a quarter cell past the cell edge, inside
/// the free cell.
const CROSSING: f64 = 0.75;

/// Morphological opening of the free cells by a 3 × 3 square: free cells that are in no
/// all-free 3 × 3 block (gaps narrower than three cells) become blocked. Outside the grid is
/// blocked. Separable: a 3 × 3 erosion is a 3-wide erosion of rows then of columns, and so is
/// the dilation, each a pass over contiguous rows.
fn opening(free: &[bool], w: usize, h: usize) -> Vec<bool> {
    let eroded = vertical(&horizontal(free, w, h, Pass::Erode), w, h, Pass::Erode);
    let dilated = vertical(&horizontal(&eroded, w, h, Pass::Dilate), w, h, Pass::Dilate);
    dilated.iter().zip(free).map(|(&d, &f)| d && f).collect()
}

/// A 3-wide erosion (all three set) or dilation (any of three set); outside the grid is unset.
#[derive(Clone, Copy)]
enum Pass {
    Erode,
    Dilate,
}

impl Pass {
    #[inline]
    fn apply(self, a: bool, b: bool, c: bool) -> bool {
        match self {
            Pass::Erode => a && b && c,
            Pass::Dilate => a || b || c,
        }
    }
}

/// [`Pass`] along each row.
fn horizontal(cells: &[bool], w: usize, h: usize, pass: Pass) -> Vec<bool> {
    let mut out = vec![false; w * h];
    for (row, out) in cells.chunks_exact(w).zip(out.chunks_exact_mut(w)).take(h) {
        for i in 0..w {
            let left = i > 0 && row[i - 1];
            let right = i + 1 < w && row[i + 1];
            out[i] = pass.apply(left, row[i], right);
        }
    }
    out
}

/// [`Pass`] along each column, row against row.
fn vertical(cells: &[bool], w: usize, h: usize, pass: Pass) -> Vec<bool> {
    let mut out = vec![false; w * h];
    let none = vec![false; w];
    for j in 0..h {
        let below = if j > 0 {
            &cells[(j - 1) * w..j * w]
        } else {
            &none[..]
        };
        let above = if j + 1 < h {
            &cells[(j + 1) * w..(j + 2) * w]
        } else {
            &none[..]
        };
        let row = &cells[j * w..(j + 1) * w];
        for (i, o) in out[j * w..(j + 1) * w].iter_mut().enumerate() {
            *o = pass.apply(below[i], row[i], above[i]);
        }
    }
    out
}

/// The 4-connected set of `cells` holding `seed`.
fn flood_fill(cells: &[bool], w: usize, h: usize, seed: usize) -> Vec<bool> {
    // Scanline fill: each popped seed grows to its whole run of the row, then seeds the runs
    // of the rows below and above that touch it (4-connected).
    let mut inside = vec![false; w * h];
    if !cells[seed] {
        return inside;
    }
    let mut stack = vec![seed];
    while let Some(k) = stack.pop() {
        if inside[k] {
            continue;
        }
        let (row, i) = (k / w, k % w);
        let line = &cells[row * w..(row + 1) * w];
        let (mut lo, mut hi) = (i, i);
        while lo > 0 && line[lo - 1] && !inside[row * w + lo - 1] {
            lo -= 1;
        }
        while hi + 1 < w && line[hi + 1] && !inside[row * w + hi + 1] {
            hi += 1;
        }
        inside[row * w + lo..=row * w + hi].fill(true);
        for r in [row.wrapping_sub(1), row + 1] {
            if r >= h {
                continue;
            }
            let (next, done) = (&cells[r * w..(r + 1) * w], &inside[r * w..(r + 1) * w]);
            let mut x = lo;
            while x <= hi {
                if next[x] && !done[x] {
                    stack.push(r * w + x);
                    // One seed per run.
                    while x <= hi && next[x] {
                        x += 1;
                    }
                } else {
                    x += 1;
                }
            }
        }
    }
    inside
}

/// Marching squares on the cell centres of the `inside` indicator (outside the grid counts
/// as not inside). Returns closed rings in grid coordinates with the inside on their left:
/// outer rings counter-clockwise, holes clockwise. Where two inside cells touch only
/// diagonally, the outside cells between them are taken as connected, so the inside never
/// squeezes through a corner.
fn march(inside: &[bool], w: usize, h: usize) -> Vec<Vec<[f64; 2]>> {
    // Lattice nodes (I, J) = cell centres (I - 1, J - 1), with a ring of outside nodes.
    let (nx, ny) = (w + 2, h + 2);
    // The nodes with their outside ring, row by row, so the scan reads two rows in order.
    let mut padded = vec![false; nx * ny];
    for j in 0..h {
        padded[(j + 1) * nx + 1..(j + 1) * nx + 1 + w].copy_from_slice(&inside[j * w..(j + 1) * w]);
    }
    let node = |i: usize, j: usize| -> bool { padded[j * nx + i] };
    // Edge ids: horizontal (I, J)–(I+1, J) is 2 (I ny + J), vertical (I, J)–(I, J+1) is +1.
    let hid = |i: usize, j: usize| 2 * (i * ny + j);
    let vid = |i: usize, j: usize| 2 * (i * ny + j) + 1;
    // Only boundary edges get a successor: a map, and the order they were found in (so the
    // rings come out the same on every run).
    let mut next: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut found: Vec<usize> = Vec::new();
    for j in 0..ny - 1 {
        // Row by row over contiguous cells; a square with four equal corners has no boundary.
        let (below, above) = (
            &padded[j * nx..(j + 1) * nx],
            &padded[(j + 1) * nx..(j + 2) * nx],
        );
        if below == above && below.iter().all(|&b| b == below[0]) {
            continue;
        }
        for i in 0..nx - 1 {
            let v = [below[i], below[i + 1], above[i + 1], above[i]];
            if v[0] == v[1] && v[1] == v[2] && v[2] == v[3] {
                continue;
            }
            // Counter-clockwise edges: k joins corner k to corner k + 1.
            let e = [hid(i, j), vid(i + 1, j), hid(i, j + 1), vid(i, j)];
            for k in 0..4 {
                if v[k] && !v[(k + 1) % 4] {
                    // Leaving the inside at edge k: the boundary runs to the nearest edge
                    // before it where the inside is entered.
                    let m = (1..4)
                        .map(|d| (k + 4 - d) % 4)
                        .find(|&m| !v[m] && v[(m + 1) % 4])
                        .expect("a cell with an exit has an entry");
                    next.insert(e[k], e[m]);
                    found.push(e[k]);
                }
            }
        }
    }
    let point = |id: usize| -> [f64; 2] {
        let (i, j) = ((id / 2) / ny, (id / 2) % ny);
        let (a, b) = if id.is_multiple_of(2) {
            ((i, j), (i + 1, j))
        } else {
            ((i, j), (i, j + 1))
        };
        let (blocked, open) = if node(a.0, a.1) { (b, a) } else { (a, b) };
        let p = |n: (usize, usize)| [n.0 as f64 - 0.5, n.1 as f64 - 0.5];
        let (pb, po) = (p(blocked), p(open));
        [
            pb[0] + CROSSING * (po[0] - pb[0]),
            pb[1] + CROSSING * (po[1] - pb[1]),
        ]
    };
    let mut rings = Vec::new();
    for start in found {
        if !next.contains_key(&start) {
            continue;
        }
        let mut ring = Vec::new();
        let mut id = start;
        while let Some(n) = next.remove(&id) {
            ring.push(point(id));
            id = n;
        }
        rings.push(ring);
    }
    rings
}

/// The traced rings simplified with the finest tolerance from `opts.simplify_cells` (growing
/// by half up to `opts.max_simplify_cells`) whose rings have at most `opts.boundary_budget`
/// vertices in all; returns the tolerance used.
fn simplify_to_budget(rings: Vec<Vec<[f64; 2]>>, opts: &MapOptions) -> (f64, Vec<Vec<[f64; 2]>>) {
    let mut eps = opts.simplify_cells;
    loop {
        let simplified: Vec<Vec<[f64; 2]>> =
            rings.iter().map(|r| simplify(r.clone(), eps)).collect();
        let vertices: usize = simplified.iter().map(Vec::len).sum();
        if vertices <= opts.boundary_budget || eps >= opts.max_simplify_cells {
            return (eps, simplified);
        }
        eps = (eps.max(0.1) * 1.5).min(opts.max_simplify_cells);
    }
}

/// Douglas–Peucker on a closed ring (tolerance in cells); rings that would collapse are kept.
fn simplify(ring: Vec<[f64; 2]>, eps: f64) -> Vec<[f64; 2]> {
    if eps <= 0.0 {
        return ring;
    }
    let mut coords: Vec<Coord<f64>> = ring.iter().map(|p| Coord { x: p[0], y: p[1] }).collect();
    coords.push(coords[0]);
    let simplified = LineString::new(coords).simplify(eps);
    let mut out: Vec<[f64; 2]> = simplified.0.iter().map(|c| [c.x, c.y]).collect();
    out.pop();
    if out.len() < 3 { ring } else { out }
}

/// The mesh a disc robot needs on open floor: triangles with edges of about four radii
/// (inflated radius `radius`), unless the mesher's default (workspace area / 20 000) is coarser;
/// near walls and in narrow passages the refinement's angle bound grades the mesh down to
/// the boundary's own detail. `None` (the mesher's default) for a point robot.
fn robot_area(polys: &MapPolygons, robot_radius: f64, radius: f64) -> Option<f64> {
    if robot_radius <= 0.0 {
        return None;
    }
    let workspace = signed_area(&polys.workspace).abs();
    let edge = 4.0 * radius;
    let robot = 3f64.sqrt() / 4.0 * edge * edge;
    Some(robot.max(workspace / 20_000.0))
}

fn signed_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    (0..n)
        .map(|k| {
            let (p, q) = (ring[k], ring[(k + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(rows: &[&str]) -> (Vec<bool>, usize, usize) {
        let h = rows.len();
        let w = rows[0].len();
        let mut v = vec![false; w * h];
        for (r, line) in rows.iter().enumerate() {
            for (i, ch) in line.chars().enumerate() {
                v[(h - 1 - r) * w + i] = ch == '.';
            }
        }
        (v, w, h)
    }

    #[test]
    fn the_scanline_fill_is_the_4_connected_component() {
        let (w, h) = (37, 29);
        let mut rng = harmonic_fixtures::Rng(99);
        let cells: Vec<bool> = (0..w * h).map(|_| rng.next_f64() < 0.6).collect();
        for seed in (0..w * h).filter(|&k| cells[k]).step_by(97) {
            // Breadth-first, cell by cell.
            let mut want = vec![false; w * h];
            want[seed] = true;
            let mut queue = std::collections::VecDeque::from([seed]);
            while let Some(k) = queue.pop_front() {
                let (i, j) = (k % w, k / w);
                let around = [
                    (i > 0).then(|| k - 1),
                    (i + 1 < w).then(|| k + 1),
                    (j > 0).then(|| k - w),
                    (j + 1 < h).then(|| k + w),
                ];
                for n in around.into_iter().flatten() {
                    if cells[n] && !want[n] {
                        want[n] = true;
                        queue.push_back(n);
                    }
                }
            }
            assert_eq!(flood_fill(&cells, w, h, seed), want, "seed {seed}");
        }
    }

    #[test]
    fn a_free_square_traces_one_counter_clockwise_ring() {
        let (v, w, h) = grid(&["...", "...", "..."]);
        let rings = march(&v, w, h);
        assert_eq!(rings.len(), 1);
        let s = simplify(rings[0].clone(), 0.1);
        // A quarter cell inside the 3 × 3 cells, corners cut by a quarter cell.
        assert_eq!(s.len(), 8, "{s:?}");
        assert!((signed_area(&s) - (2.5 * 2.5 - 4.0 * 0.25 * 0.25 / 2.0)).abs() < 1e-12);
    }

    #[test]
    fn a_blocked_cell_inside_is_a_clockwise_hole_and_diagonals_stay_blocked() {
        let (v, w, h) = grid(&[".....", ".#...", "..#..", ".....", "....."]);
        let rings = march(&v, w, h);
        assert_eq!(rings.len(), 2, "the two diagonal cells make one hole");
        let holes: Vec<_> = rings.iter().filter(|r| signed_area(r) < 0.0).collect();
        assert_eq!(holes.len(), 1);
        // Both blocked centres are inside the hole.
        for c in [[1.5, 3.5], [2.5, 2.5]] {
            assert!(inside_ring(holes[0], c), "{c:?}");
        }
    }

    #[test]
    fn opening_closes_gaps_narrower_than_three_cells() {
        let (v, w, h) = grid(&["...#...", "...#...", ".......", "...#...", "...#..."]);
        let o = opening(&v, w, h);
        // The one-cell door in the middle column closes; the open sides stay.
        assert!(!o[2 * w + 3]);
        assert!(o[2 * w + 1] && o[2 * w + 5]);
    }

    fn inside_ring(ring: &[[f64; 2]], p: [f64; 2]) -> bool {
        let n = ring.len();
        let mut c = false;
        for k in 0..n {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            if (a[1] > p[1]) != (b[1] > p[1])
                && p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1])
            {
                c = !c;
            }
        }
        c
    }
}
