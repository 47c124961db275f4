//! The C interface of harmonic-planner (`harmonic_planner.h`): a Nav2-style costmap and a goal
//! in, a planner built once (mesh, assemble, solve), poses out for as many starts as asked, from
//! as many threads as asked. Over the library's map planner ([`planner::map::OccupancyMap`]),
//! not a second planner: the same clear cells, the same completeness, the same paths.
//!
//! Nothing unwinds across the boundary: every entry point catches panics and answers
//! [`HpStatus::HP_INTERNAL`]; every failure is a status and one line in [`hp_last_error`].
//!
//! Costs are Nav2's: 0 free, 1–252 graded, 253 inscribed, 254 lethal, 255 unknown. A cell whose
//! cost is at least `obstacle_cost` is blocked, 255 too unless `unknown_is_free`. Graded costs
//! below it shape the field when `cost_weight` > 0 ([`planner::map::MapOptions::cost_weight`]):
//! a cell of cost c conducts 1 / (1 + w·0.016·c) of a free cell's flow, so paths keep away from
//! costly cells when a free route is not much longer; at weight 1 the costliest cell resists 5
//! times a free one, as NavFn's step through it costs 5 times a free step. The costliest cells
//! (next to obstacles, in an inflated costmap) also absorb
//! ([`planner::map::cost_absorption`]), so the walls behind them keep their pull on paths.

#![allow(non_camel_case_types)] // the contract's C names: HP_OK, ...

use std::cell::RefCell;
use std::ffi::{CString, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Arc;

use planner::map::{Cell, MAX_GRADED_COST, MapError, MapOptions, OccupancyMap, UnknownCells};
use planner::planner::{PlanError, PlannerOptions};
use planner::trajectory::TraceStatus;
use planner::{Planner, Point};

/// What a call did.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HpStatus {
    /// Done.
    HP_OK = 0,
    /// A null pointer, a size of 0, a number not finite, a resolution ≤ 0, …
    HP_INVALID_ARGUMENT = 1,
    /// The start's cell is blocked (cost ≥ obstacle_cost) or closer than the robot radius to
    /// one.
    HP_START_OCCUPIED = 2,
    /// Likewise for the goal, after goal_tolerance.
    HP_GOAL_OCCUPIED = 3,
    /// The start lies outside the costmap.
    HP_START_OUTSIDE_MAP = 4,
    /// The goal lies outside the costmap.
    HP_GOAL_OUTSIDE_MAP = 5,
    /// The start is not connected to the goal through clear cells.
    HP_NO_VALID_PATH = 6,
    /// The cancel callback asked to stop.
    HP_CANCELLED = 7,
    /// A bug: the message says what; never a crash.
    HP_INTERNAL = 8,
}

/// A pose in the map frame: metres, radians.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HpPose {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Heading, radians.
    pub theta: f64,
}

/// A costmap in Nav2's `Costmap2D` layout: `data[my * size_x + mx]`, row 0 the lowest y.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct HpCostmap {
    /// Cells along x.
    pub size_x: u32,
    /// Cells along y.
    pub size_y: u32,
    /// Metres per cell.
    pub resolution: f64,
    /// World x of cell (0, 0)'s lower-left corner.
    pub origin_x: f64,
    /// World y of cell (0, 0)'s lower-left corner.
    pub origin_y: f64,
    /// `size_x * size_y` costs.
    pub data: *const u8,
}

/// How to build a planner ([`hp_options_default`] gives the defaults).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct HpOptions {
    /// Metres kept from blocked cells; 0 for a costmap already inflated.
    pub robot_radius: f64,
    /// Cells with a cost at least this are blocked (default 253).
    pub obstacle_cost: u8,
    /// 0 (default): cost 255 is blocked; 1: it is free.
    pub unknown_is_free: c_int,
    /// 0: graded costs ignored; > 0: graded costs (1..252) shape the field, a cell of cost c
    /// conducting 1 / (1 + w·0.016·c) of a free cell's flow (default 1, NavFn's weighting)
    /// and absorbing w·0.016·c·(c/252)³ / (0.05 m)²; at most 1e6.
    pub cost_weight: f64,
    /// Metres: a blocked goal moves to the nearest clear cell within this distance (default 0).
    pub goal_tolerance: f64,
    /// 1 (default): the last pose's theta is the goal's; 0: the path's tangent.
    pub use_goal_heading: c_int,
    /// Optional: asked at each stage of the build (meshing, assembling, solving); non-zero
    /// cancels.
    pub cancel: Option<unsafe extern "C" fn(user: *mut c_void) -> c_int>,
    /// Passed to `cancel`.
    pub cancel_user: *mut c_void,
    /// Threads for the build; 0 (default): all cores (`RAYON_NUM_THREADS` respected).
    pub threads: u32,
}

/// A planner for one goal on one costmap (opaque; immutable after creation).
pub struct HpPlanner {
    map: OccupancyMap,
    planner: Planner,
    unknown: UnknownCells,
    robot_radius: f64,
    /// Where the goal is (moved within the tolerance where it was blocked).
    goal: [f64; 2],
    /// The goal's heading when the last pose is to carry it.
    goal_heading: Option<f64>,
}

/// A planned path (opaque).
pub struct HpPath {
    poses: Vec<HpPose>,
    length: f64,
    min_clearance: f64,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

/// Records `message` as this thread's last error ("" on success).
fn set_error(message: &str) {
    let c = CString::new(message.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

/// A failure: its status and its one-line message.
type Failure = (HpStatus, String);

/// Runs `f`, catching any panic; records the message and returns the status.
fn guarded(f: impl FnOnce() -> Result<(), Failure>) -> HpStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => {
            set_error("");
            HpStatus::HP_OK
        }
        Ok(Err((status, message))) => {
            set_error(&message);
            status
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            set_error(&format!("internal error (a bug; please report it): {what}"));
            HpStatus::HP_INTERNAL
        }
    }
}

fn invalid(message: impl Into<String>) -> Failure {
    (HpStatus::HP_INVALID_ARGUMENT, message.into())
}

/// The default options: radius 0, obstacle cost 253, unknown blocked, cost weight 1, goal
/// tolerance 0, goal heading used, no cancel callback, all cores.
#[unsafe(no_mangle)]
pub extern "C" fn hp_options_default() -> HpOptions {
    HpOptions {
        robot_radius: 0.0,
        obstacle_cost: 253,
        unknown_is_free: 0,
        cost_weight: 1.0,
        goal_tolerance: 0.0,
        use_goal_heading: 1,
        cancel: None,
        cancel_user: std::ptr::null_mut(),
        threads: 0,
    }
}

/// The library's version, a static string such as "0.1.0".
#[unsafe(no_mangle)]
pub extern "C" fn hp_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// Why the last call on this thread failed, in one line ("" after a success); valid until the
/// next call on this thread.
#[unsafe(no_mangle)]
pub extern "C" fn hp_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

/// The cancel callback and its argument, handed to the build's threads.
struct CancelHook {
    check: unsafe extern "C" fn(*mut c_void) -> c_int,
    user: *mut c_void,
}
// SAFETY: the contract makes the callback the caller's to keep callable from the build's
// threads with its `cancel_user`; we only pass the pointer back.
unsafe impl Send for CancelHook {}
// SAFETY: as above.
unsafe impl Sync for CancelHook {}

impl CancelHook {
    fn cancelled(&self) -> bool {
        // SAFETY: the callback and its argument are the caller's, callable by the contract.
        unsafe { (self.check)(self.user) != 0 }
    }
}

/// Builds the field for one goal on one costmap: the costly step (mesh, assemble, solve). The
/// costmap is copied; the caller may free it afterwards. On failure `*out` is NULL.
///
/// # Safety
/// `map` must point to a valid [`HpCostmap`] whose `data` holds `size_x * size_y` bytes,
/// `options` to a valid [`HpOptions`] or be NULL (the defaults), `out` to writable storage.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_planner_new(
    map: *const HpCostmap,
    goal: HpPose,
    options: *const HpOptions,
    out: *mut *mut HpPlanner,
) -> HpStatus {
    guarded(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        // SAFETY: `out` is non-null and writable by the contract.
        unsafe { *out = std::ptr::null_mut() };
        if map.is_null() {
            return Err(invalid("map is NULL"));
        }
        // SAFETY: non-null and valid by the contract.
        let map = unsafe { &*map };
        let options = if options.is_null() {
            hp_options_default()
        } else {
            // SAFETY: non-null and valid by the contract.
            unsafe { *options }
        };
        let (cells, costs) = costmap_cells(map, &options)?;
        let planner = build(map, cells, costs, goal, &options)?;
        // SAFETY: as above.
        unsafe { *out = Box::into_raw(Box::new(planner)) };
        Ok(())
    })
}

/// The costmap's cells as the library's, and the graded costs of the free ones (empty when
/// no free cell has one), after checking the costmap and options.
fn costmap_cells(map: &HpCostmap, options: &HpOptions) -> Result<(Vec<Cell>, Vec<u8>), Failure> {
    if map.size_x == 0 || map.size_y == 0 {
        return Err(invalid(format!(
            "the costmap is {} × {} cells: both sizes must be positive",
            map.size_x, map.size_y
        )));
    }
    if !(map.resolution.is_finite() && map.resolution > 0.0) {
        return Err(invalid(format!(
            "resolution must be a positive number of metres, got {}",
            map.resolution
        )));
    }
    if !(map.origin_x.is_finite() && map.origin_y.is_finite()) {
        return Err(invalid(format!(
            "origin must be finite, got ({}, {})",
            map.origin_x, map.origin_y
        )));
    }
    if map.data.is_null() {
        return Err(invalid("costmap data is NULL"));
    }
    if !(options.robot_radius.is_finite() && options.robot_radius >= 0.0) {
        return Err(invalid(format!(
            "robot_radius must be zero or positive, got {}",
            options.robot_radius
        )));
    }
    if !(0.0..=planner::map::MAX_COST_WEIGHT).contains(&options.cost_weight) {
        return Err(invalid(format!(
            "cost_weight must be between 0 and {:e}, got {:e}",
            planner::map::MAX_COST_WEIGHT,
            options.cost_weight
        )));
    }
    if !(options.goal_tolerance.is_finite() && options.goal_tolerance >= 0.0) {
        return Err(invalid(format!(
            "goal_tolerance must be zero or positive, got {}",
            options.goal_tolerance
        )));
    }
    if options.obstacle_cost == 0 {
        return Err(invalid("obstacle_cost 0 would block every cell"));
    }
    let n = (map.size_x as usize)
        .checked_mul(map.size_y as usize)
        .ok_or_else(|| invalid("the costmap's size overflows"))?;
    // SAFETY: `data` holds `size_x * size_y` bytes by the contract.
    let data = unsafe { std::slice::from_raw_parts(map.data, n) };
    // Every cost byte's cell and whether it is a graded cost, tabled once; then one pass
    // over the costmap (a bare occupancy grid is copied once, its costs not at all).
    let cell_of: [Cell; 256] = std::array::from_fn(|c| match c as u8 {
        255 if options.unknown_is_free != 0 => Cell::Free,
        255 => Cell::Unknown,
        c if c >= options.obstacle_cost => Cell::Occupied,
        _ => Cell::Free,
    });
    let graded = |c: u8| c > 0 && c < options.obstacle_cost && c != 255;
    let mut seen = [false; 256];
    let cells = data
        .iter()
        .map(|&c| {
            seen[c as usize] = true;
            cell_of[c as usize]
        })
        .collect();
    let any_graded = (0..=255u8).any(|c| seen[c as usize] && graded(c));
    let costs = if any_graded {
        data.iter()
            .map(|&c| if graded(c) { c.min(MAX_GRADED_COST) } else { 0 })
            .collect()
    } else {
        Vec::new()
    };
    Ok((cells, costs))
}

/// The planner: the map, the goal (moved within the tolerance where it is blocked), the
/// field, in the pool of `options.threads`.
fn build(
    costmap: &HpCostmap,
    cells: Vec<Cell>,
    costs: Vec<u8>,
    goal: HpPose,
    options: &HpOptions,
) -> Result<HpPlanner, Failure> {
    if !(goal.x.is_finite() && goal.y.is_finite() && goal.theta.is_finite()) {
        return Err(invalid(format!(
            "goal ({}, {}, {}) is not finite",
            goal.x, goal.y, goal.theta
        )));
    }
    let map = OccupancyMap::from_cells(
        costmap.size_x as usize,
        costmap.size_y as usize,
        costmap.resolution,
        [costmap.origin_x, costmap.origin_y, 0.0],
        cells,
    )
    .and_then(|m| {
        // Graded costs only where some cell has one: a bare occupancy grid plans as one.
        if !costs.is_empty() {
            m.with_costs(costs)
        } else {
            Ok(m)
        }
    })
    .map_err(|e| invalid(e.to_string()))?;
    let unknown = if options.unknown_is_free != 0 {
        UnknownCells::Free
    } else {
        UnknownCells::Obstacle
    };
    let radius = options.robot_radius;
    if map.cell_at([goal.x, goal.y]).is_none() {
        return Err((
            HpStatus::HP_GOAL_OUTSIDE_MAP,
            format!(
                "goal ({}, {}) is outside the costmap, which covers x {}..{}, y {}..{}",
                goal.x,
                goal.y,
                costmap.origin_x,
                costmap.origin_x + costmap.size_x as f64 * costmap.resolution,
                costmap.origin_y,
                costmap.origin_y + costmap.size_y as f64 * costmap.resolution
            ),
        ));
    }
    // NavFn's tolerance: a blocked goal moves to the nearest clear cell within it.
    let at = if options.goal_tolerance > 0.0 {
        map.nearest_clear_point([goal.x, goal.y], radius, unknown, options.goal_tolerance)
            .unwrap_or([goal.x, goal.y])
    } else {
        [goal.x, goal.y]
    };
    let mut planner_options = PlannerOptions::default();
    if let Some(check) = options.cancel {
        let hook = CancelHook {
            check,
            user: options.cancel_user,
        };
        planner_options.cancel = Some(Arc::new(move || hook.cancelled()));
    }
    let map_options = MapOptions {
        unknown,
        cost_weight: options.cost_weight,
        ..MapOptions::default()
    };
    planner_options.threads = (options.threads > 0).then_some(options.threads as usize);
    let planner = map
        .planner(at, radius, &map_options, &planner_options)
        .map_err(|e| map_failure(e, options.goal_tolerance))?;
    Ok(HpPlanner {
        map,
        planner,
        unknown,
        robot_radius: radius,
        goal: at,
        goal_heading: (options.use_goal_heading != 0).then_some(goal.theta),
    })
}

/// The status of a failed build.
fn map_failure(e: MapError, tolerance: f64) -> Failure {
    let message = e.to_string();
    let status = match &e {
        MapError::GoalOutsideMap { .. } => HpStatus::HP_GOAL_OUTSIDE_MAP,
        MapError::GoalNotFree { .. }
        | MapError::GoalTooClose { .. }
        | MapError::GoalEnclosed { .. }
        | MapError::EmptyMap { .. } => HpStatus::HP_GOAL_OCCUPIED,
        MapError::Plan {
            source: PlanError::Cancelled { .. },
            ..
        } => HpStatus::HP_CANCELLED,
        MapError::BadGrid(_) | MapError::BadRadius(_) | MapError::BadOption { .. } => {
            HpStatus::HP_INVALID_ARGUMENT
        }
        _ => HpStatus::HP_INTERNAL,
    };
    let message = if status == HpStatus::HP_GOAL_OCCUPIED && tolerance > 0.0 {
        format!("{message} (no clear cell within the goal tolerance {tolerance} m)")
    } else {
        message
    };
    (status, message)
}

/// A path from `start` to the goal: the field is only traced (milliseconds). Poses carry the
/// path's tangent heading; the first is the start, the last the goal position (its heading
/// per `use_goal_heading`). Safe to call from several threads on the same planner at once. On
/// failure `*out` is NULL.
///
/// # Safety
/// `planner` must come from [`hp_planner_new`] and not be freed, `out` must be writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_planner_plan(
    planner: *const HpPlanner,
    start: HpPose,
    out: *mut *mut HpPath,
) -> HpStatus {
    guarded(|| {
        if out.is_null() {
            return Err(invalid("out is NULL"));
        }
        // SAFETY: non-null and writable by the contract.
        unsafe { *out = std::ptr::null_mut() };
        if planner.is_null() {
            return Err(invalid("planner is NULL"));
        }
        // SAFETY: a live planner by the contract.
        let p = unsafe { &*planner };
        let path = plan(p, start)?;
        // SAFETY: as above.
        unsafe { *out = Box::into_raw(Box::new(path)) };
        Ok(())
    })
}

fn plan(p: &HpPlanner, start: HpPose) -> Result<HpPath, Failure> {
    if !(start.x.is_finite() && start.y.is_finite() && start.theta.is_finite()) {
        return Err(invalid(format!(
            "start ({}, {}, {}) is not finite",
            start.x, start.y, start.theta
        )));
    }
    let Some((column, row)) = p.map.cell_at([start.x, start.y]) else {
        return Err((
            HpStatus::HP_START_OUTSIDE_MAP,
            format!("start ({}, {}) is outside the costmap", start.x, start.y),
        ));
    };
    let path = p.planner.plan(Point::new(start.x, start.y));
    match path.status {
        TraceStatus::ReachedGoal(_) => {}
        TraceStatus::StartInObstacle | TraceStatus::OutsideWorkspace => {
            let why = if p.map.is_blocked(column, row, p.unknown) {
                "is blocked".to_string()
            } else {
                format!(
                    "is closer than the robot radius {} to a blocked cell",
                    p.robot_radius
                )
            };
            return Err((
                HpStatus::HP_START_OCCUPIED,
                format!(
                    "start ({}, {}): its cell (column {column}, row {row}) {why}",
                    start.x, start.y
                ),
            ));
        }
        TraceStatus::Unreachable => {
            return Err((
                HpStatus::HP_NO_VALID_PATH,
                format!(
                    "start ({}, {}) is not connected to the goal through clear cells",
                    start.x, start.y
                ),
            ));
        }
        other => {
            return Err((
                HpStatus::HP_NO_VALID_PATH,
                format!(
                    "from ({}, {}) the path ended {} after {:.3} m",
                    start.x,
                    start.y,
                    other.as_str(),
                    path.length
                ),
            ));
        }
    }
    let poses = path
        .poses(Some(start.theta), p.goal_heading)
        .into_iter()
        .map(|[x, y, theta]| HpPose { x, y, theta })
        .collect();
    Ok(HpPath {
        poses,
        length: path.length,
        min_clearance: path.min_clearance,
    })
}

/// The number of poses of `path` (0 for NULL).
///
/// # Safety
/// `path` must come from [`hp_planner_plan`] and not be freed, or be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_path_size(path: *const HpPath) -> usize {
    // SAFETY: a live path or NULL by the contract.
    unsafe { path.as_ref() }.map_or(0, |p| p.poses.len())
}

/// The poses of `path` (NULL for NULL), valid until [`hp_path_free`].
///
/// # Safety
/// As [`hp_path_size`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_path_poses(path: *const HpPath) -> *const HpPose {
    // SAFETY: a live path or NULL by the contract.
    unsafe { path.as_ref() }.map_or(std::ptr::null(), |p| p.poses.as_ptr())
}

/// The length of `path` in metres (NaN for NULL).
///
/// # Safety
/// As [`hp_path_size`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_path_length(path: *const HpPath) -> f64 {
    // SAFETY: a live path or NULL by the contract.
    unsafe { path.as_ref() }.map_or(f64::NAN, |p| p.length)
}

/// The smallest distance from `path` to a blocked cell, in metres (NaN for NULL).
///
/// # Safety
/// As [`hp_path_size`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_path_min_clearance(path: *const HpPath) -> f64 {
    // SAFETY: a live path or NULL by the contract.
    unsafe { path.as_ref() }.map_or(f64::NAN, |p| p.min_clearance)
}

/// Frees `path` (NULL is fine).
///
/// # Safety
/// `path` must come from [`hp_planner_plan`] and not be freed already, or be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_path_free(path: *mut HpPath) {
    if !path.is_null() {
        // SAFETY: a path of ours, freed once, by the contract.
        drop(unsafe { Box::from_raw(path) });
    }
}

/// Frees `planner` (NULL is fine).
///
/// # Safety
/// `planner` must come from [`hp_planner_new`], not be freed already and not be in use by
/// another thread, or be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_planner_free(planner: *mut HpPlanner) {
    if !planner.is_null() {
        // SAFETY: a planner of ours, freed once, by the contract.
        drop(unsafe { Box::from_raw(planner) });
    }
}

/// The potential φ at `(x, y)` (0 at the goal, 1 at blocked cells), NaN outside the free
/// space or for NULL: for pictures and debugging.
///
/// # Safety
/// `planner` must come from [`hp_planner_new`] and not be freed, or be NULL.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn hp_planner_potential(planner: *const HpPlanner, x: f64, y: f64) -> f64 {
    // SAFETY: a live planner or NULL by the contract.
    let Some(p) = (unsafe { planner.as_ref() }) else {
        return f64::NAN;
    };
    let phi = catch_unwind(AssertUnwindSafe(|| {
        p.planner.potential().phi_at(Point::new(x, y), None).ok()
    }))
    .ok()
    .flatten()
    .filter(|phi| phi.is_finite());
    match phi {
        Some(phi) => phi,
        // The goal is a small hole in the mesh around its point, held at φ = 0.
        None if (x - p.goal[0]).hypot(y - p.goal[1]) <= p.map.resolution() => 0.0,
        None => f64::NAN,
    }
}
