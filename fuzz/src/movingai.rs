//! What the `movingai` fuzz target runs on every input, shared with the corpus replay in
//! `tests/grid_completeness.rs` (which includes this file with `#[path]`): bytes (as lossy
//! UTF-8) → the MovingAI readers `read_map` and `read_scen`; when the bytes hold a zero, the
//! part before it is also read as a `.map` file and the part after as a `.scen` file, and
//! each scenario is checked against the map. Errors are expected; a panic, an error message
//! of more than one line or a map that does not read back the same after being written out
//! is a finding.

use harmonic_planner::map::movingai::{read_map, read_scen};
use harmonic_planner::map::{Cell, OccupancyMap};

/// Maps up to this many cells are written out and read back.
const MAX_ROUND_TRIP_CELLS: usize = 64 * 64;

/// Reads `text` as a `.map` file; checks the error message, or that the map reads back.
fn map(text: &str) -> Option<OccupancyMap> {
    match read_map(text, "fuzz.map", 1.0) {
        Ok(map) => {
            let (w, h) = (map.width(), map.height());
            if w * h <= MAX_ROUND_TRIP_CELLS {
                let mut again = format!("type octile\nheight {h}\nwidth {w}\nmap\n");
                for j in (0..h).rev() {
                    again.extend((0..w).map(|i| match map.cell(i, j) {
                        Cell::Free => '.',
                        _ => '@',
                    }));
                    again.push('\n');
                }
                let back = read_map(&again, "again.map", 1.0).expect("a written map reads back");
                assert_eq!((back.width(), back.height()), (w, h));
                for j in 0..h {
                    for i in 0..w {
                        assert_eq!(back.cell(i, j), map.cell(i, j), "cell ({i}, {j})");
                    }
                }
            }
            Some(map)
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.starts_with("fuzz.map") && !message.contains(['\n', '\r']),
                "{message:?}"
            );
            None
        }
    }
}

/// Reads `text` as a `.scen` file; checks the error message, or the scenarios' cells (and
/// them against `map`, if there is one).
fn scen(text: &str, map: Option<&OccupancyMap>) {
    match read_scen(text, "fuzz.scen") {
        Ok(list) => {
            for s in &list {
                assert!(s.start.0 < s.width && s.start.1 < s.height, "{s:?}");
                assert!(s.goal.0 < s.width && s.goal.1 < s.height, "{s:?}");
                assert!(s.optimal.is_finite() && s.optimal >= 0.0, "{s:?}");
                if let Some(map) = map
                    && let Err(e) = s.check_against(map)
                {
                    assert!(!e.to_string().contains(['\n', '\r']), "{e}");
                }
            }
        }
        Err(e) => {
            let message = e.to_string();
            assert!(
                message.starts_with("fuzz.scen") && !message.contains(['\n', '\r']),
                "{message:?}"
            );
        }
    }
}

/// One fuzz case: the readers on `data` (see the module documentation).
pub fn run_movingai(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    map(&text);
    scen(&text, None);
    if let Some(split) = data.iter().position(|&b| b == 0) {
        let parsed = map(&String::from_utf8_lossy(&data[..split]));
        scen(
            &String::from_utf8_lossy(&data[split + 1..]),
            parsed.as_ref(),
        );
    }
}
