//! A spinner on stderr naming the planner's stage (indicatif draws it only on a terminal).

use std::sync::Arc;
use std::time::Duration;

use harmonic_planner::planner::{Stage, StageObserver};

/// An observer for [`harmonic_planner::PlannerOptions::on_stage`] that shows the stage in a
/// spinner, or `None` when `quiet`.
pub fn spinner(quiet: bool) -> Option<StageObserver> {
    if quiet {
        return None;
    }
    let bar = indicatif::ProgressBar::new_spinner();
    bar.enable_steady_tick(Duration::from_millis(120));
    Some(Arc::new(move |stage| match stage {
        Stage::Meshing => bar.set_message("meshing"),
        Stage::Assembling => bar.set_message("assembling"),
        Stage::Solving => bar.set_message("solving"),
        Stage::Done => bar.finish_and_clear(),
    }))
}
