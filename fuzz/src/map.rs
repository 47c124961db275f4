//! What the `map` fuzz target runs on every input, shared with the corpus replay in
//! `tests/map.rs` (which includes this file with `#[path]`): the bytes up to the first zero
//! are a `map_server` YAML document, the rest its image (PGM or PNG); a grid of at most
//! [`MAX_CELLS`] cells is planned on by both meshers towards its free cell nearest the centre,
//! with a robot radius taken from the YAML's length, from up to [`MAX_STARTS`] other free
//! cells. Errors are expected; a panic, or a NaN in a path, is a finding.

use harmonic_planner::PlannerOptions;
use harmonic_planner::map::{Cell, MapMesher, MapOptions, OccupancyMap};

/// The largest grid planned on (decoding is bounded by the image crate's own limits).
pub const MAX_CELLS: usize = 128 * 128;

/// At most this many starts are planned per mesher.
pub const MAX_STARTS: usize = 4;

/// What happened to one input (for the replay test's messages).
#[derive(Debug, PartialEq, Eq)]
pub enum MapOutcome {
    /// No zero byte, or the YAML is not UTF-8.
    NoSplit,
    /// `OccupancyMap::from_bytes` refused it.
    BadMap,
    /// More than [`MAX_CELLS`] cells, or no free cell.
    Skipped,
    /// Planned: how many planners were built (0 to 2), how many paths reached their goal.
    Planned(usize, usize),
}

/// Splits, decodes, plans (see the module documentation).
pub fn run_map(data: &[u8]) -> MapOutcome {
    let Some(split) = data.iter().position(|&b| b == 0) else {
        return MapOutcome::NoSplit;
    };
    let Ok(yaml) = std::str::from_utf8(&data[..split]) else {
        return MapOutcome::NoSplit;
    };
    let Ok(map) = OccupancyMap::from_bytes(yaml, &data[split + 1..], "fuzz") else {
        return MapOutcome::BadMap;
    };
    let (w, h) = (map.width(), map.height());
    if w * h > MAX_CELLS {
        return MapOutcome::Skipped;
    }
    // Each cell's distance in steps (8-connected) from the nearest non-free cell or the
    // grid's edge: the goal is the free cell with the most room.
    let mut room = vec![u32::MAX; w * h];
    let mut queue = std::collections::VecDeque::new();
    for j in 0..h {
        for i in 0..w {
            if map.cell(i, j) != Cell::Free || i == 0 || j == 0 || i + 1 == w || j + 1 == h {
                room[j * w + i] = 0;
                queue.push_back((i, j));
            }
        }
    }
    while let Some((i, j)) = queue.pop_front() {
        let d = room[j * w + i] + 1;
        for (di, dj) in [
            (-1, -1),
            (0, -1),
            (1, -1),
            (-1, 0),
            (1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
        ] {
            let (x, y) = (i as isize + di, j as isize + dj);
            if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
                let k = y as usize * w + x as usize;
                if room[k] > d {
                    room[k] = d;
                    queue.push_back((x as usize, y as usize));
                }
            }
        }
    }
    let free: Vec<(usize, usize)> = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .filter(|&(i, j)| map.cell(i, j) == Cell::Free)
        .collect();
    let Some(&(gi, gj)) = free.iter().max_by_key(|&&(i, j)| room[j * w + i]) else {
        return MapOutcome::Skipped;
    };
    let goal = map.cell_center(gi, gj);
    let radius = map.resolution() * (yaml.len() % 7) as f64 * 0.5;
    let starts: Vec<[f64; 2]> = free
        .iter()
        .rev()
        .step_by((free.len() / MAX_STARTS).max(1))
        .take(MAX_STARTS)
        .map(|&(i, j)| map.cell_center(i, j))
        .collect();
    let (mut built, mut reached) = (0, 0);
    for mesher in [MapMesher::Traced, MapMesher::Quadtree] {
        let opts = MapOptions {
            mesher,
            simplify_cells: (yaml.len() % 5) as f64 * 0.5,
            ..MapOptions::default()
        };
        let Ok(planner) = map.planner(goal, radius, &opts, &PlannerOptions::default()) else {
            continue;
        };
        built += 1;
        for &s in &starts {
            let path = planner.plan(s);
            assert!(
                path.points.iter().flatten().all(|v| v.is_finite()),
                "a non-finite point on the path from {s:?} ({mesher:?})"
            );
            if path.status.reached_goal() {
                reached += 1;
            }
        }
    }
    MapOutcome::Planned(built, reached)
}
