//! The wavefront planner (Choset et al., *Principles of Robot Motion*, §4.5; Barraquand &
//! Latombe): a brushfire from the goal cells over the occupancy grid, then steepest descent
//! of the move count from the start.

use std::time::{Duration, Instant};

use harmonic_mesh::Point;
use harmonic_trajectory::TraceStatus;

use crate::raster::UNREACHED;
use crate::{Cell, Connectivity, PlanResult, Raster};

/// A wavefront (brushfire) distance map to the goal, ready for queries.
#[derive(Clone, Debug)]
pub struct Wavefront {
    raster: Raster,
    connectivity: Connectivity,
    distance: Vec<u32>,
    build_time: Duration,
}

impl Wavefront {
    /// Runs the brushfire from every goal cell of `raster`.
    ///
    /// ```
    /// use harmonic_baselines::{Connectivity, Raster, Wavefront};
    /// use harmonic_mesh::Point;
    /// let ws = vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0), Point::new(10.0, 10.0), Point::new(0.0, 10.0)];
    /// let goal = vec![Point::new(8.0, 8.0), Point::new(9.0, 8.0), Point::new(9.0, 9.0), Point::new(8.0, 9.0)];
    /// let raster = Raster::from_polygons(&ws, &[], &[goal], 12).unwrap();
    /// let planner = Wavefront::new(raster, Connectivity::Eight);
    /// let plan = planner.plan(Point::new(0.5, 0.5));
    /// assert!(plan.status.reached_goal());
    /// assert_eq!(plan.points.len(), 9); // the start, then 8 diagonal moves
    /// ```
    pub fn new(raster: Raster, connectivity: Connectivity) -> Self {
        let start = Instant::now();
        let distance = raster.goal_distances(connectivity);
        Wavefront {
            raster,
            connectivity,
            distance,
            build_time: start.elapsed(),
        }
    }

    /// The move count from each cell to the nearest goal cell ([`crate::UNREACHED`] where no
    /// wave arrived).
    pub fn distances(&self) -> &[u32] {
        &self.distance
    }

    /// The occupancy grid.
    pub fn raster(&self) -> &Raster {
        &self.raster
    }

    /// Time the brushfire took.
    pub fn build_time(&self) -> Duration {
        self.build_time
    }

    /// Descends the move count from `start`: the path is `start` followed by the centres of
    /// the cells visited, each the lowest neighbour of the previous (edge neighbours win
    /// ties), ending at a goal cell's centre.
    pub fn plan(&self, start: Point) -> PlanResult {
        let clock = Instant::now();
        let mut points = vec![start];
        let status = match self.raster.index_of(start) {
            None => TraceStatus::OutsideWorkspace,
            Some(mut k) => match self.raster.cells()[k] {
                Cell::Wall => TraceStatus::OutsideWorkspace,
                Cell::Obstacle(_) => TraceStatus::StartInObstacle,
                _ if self.distance[k] == UNREACHED => TraceStatus::Unreachable,
                _ => loop {
                    if let Cell::Goal(j) = self.raster.cells()[k] {
                        break TraceStatus::ReachedGoal(j);
                    }
                    let (nb, len) = self.raster.neighbours(k, self.connectivity);
                    // A reached non-goal cell always has a neighbour one move closer.
                    let next = nb[..len]
                        .iter()
                        .copied()
                        .min_by_key(|&m| self.distance[m])
                        .expect("a reached cell has a reached neighbour");
                    k = next;
                    points.push(self.raster.centre(k));
                },
            },
        };
        PlanResult::new(points, status, clock.elapsed())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
        vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ]
    }

    /// Unit cells over [0, 10]²; a wall from y = 0 to 8 at x ∈ [4, 5]; goal at (8.5, 0.5).
    fn scene() -> Raster {
        Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[rect(4.0, 0.0, 5.0, 8.0)],
            &[rect(8.0, 0.0, 9.0, 1.0)],
            12,
        )
        .unwrap()
    }

    #[test]
    fn four_connected_path_is_a_shortest_manhattan_path_around_the_wall() {
        let w = Wavefront::new(scene(), Connectivity::Four);
        let plan = w.plan(Point::new(0.5, 0.5));
        assert_eq!(plan.status, TraceStatus::ReachedGoal(0));
        // Up to row y = 8.5, across to x = 8.5, down to y = 0.5: 8 + 8 + 8 moves.
        assert_eq!(plan.points.len(), 1 + 24);
        for pair in plan.points[1..].windows(2) {
            let d = pair[1] - pair[0];
            assert!((d.x.abs() + d.y.abs() - 1.0).abs() < 1e-12, "step {d:?}");
            assert_ne!(w.raster().cell_at(pair[1]), Some(Cell::Obstacle(0)));
        }
        assert!((plan.length - 24.0).abs() < 1e-12);
    }

    #[test]
    fn eight_connected_path_is_shorter_and_never_cuts_a_corner() {
        let four = Wavefront::new(scene(), Connectivity::Four).plan(Point::new(0.5, 0.5));
        let eight = Wavefront::new(scene(), Connectivity::Eight);
        let plan = eight.plan(Point::new(0.5, 0.5));
        assert!(plan.status.reached_goal());
        assert!(plan.points.len() < four.points.len());
        for pair in plan.points[1..].windows(2) {
            // Both cells a diagonal move passes are free.
            for corner in [
                Point::new(pair[0].x, pair[1].y),
                Point::new(pair[1].x, pair[0].y),
            ] {
                assert!(
                    eight
                        .raster()
                        .cell_at(corner)
                        .is_some_and(Cell::is_traversable)
                );
            }
        }
    }

    #[test]
    fn reports_blocked_and_cut_off_starts() {
        // A closed box around (1.5, 8.5) cuts that cell off from the goal.
        let raster = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[
                rect(4.0, 0.0, 5.0, 8.0),
                vec![
                    Point::new(0.0, 7.0),
                    Point::new(3.0, 7.0),
                    Point::new(3.0, 10.0),
                    Point::new(0.0, 10.0),
                    Point::new(0.0, 9.0),
                    Point::new(2.0, 9.0),
                    Point::new(2.0, 8.0),
                    Point::new(0.0, 8.0),
                ],
            ],
            &[rect(8.0, 0.0, 9.0, 1.0)],
            12,
        )
        .unwrap();
        let w = Wavefront::new(raster, Connectivity::Eight);
        assert_eq!(
            w.plan(Point::new(0.5, 8.5)).status,
            TraceStatus::Unreachable
        );
        assert_eq!(
            w.plan(Point::new(4.5, 3.0)).status,
            TraceStatus::StartInObstacle
        );
        assert_eq!(
            w.plan(Point::new(-0.5, 3.0)).status,
            TraceStatus::OutsideWorkspace
        );
        assert_eq!(
            w.plan(Point::new(-5.0, 3.0)).status,
            TraceStatus::OutsideWorkspace
        );
        assert_eq!(w.plan(Point::new(8.5, 0.5)).points.len(), 1);
    }
}
