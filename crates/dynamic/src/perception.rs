//! Perception: a laser scan becomes obstacles (points the known map explains dropped, the rest
//! clustered, each cluster's hull grown by a margin).

use std::collections::BTreeMap;

use geo::{ConvexHull, Coord, MultiPoint};
use harmonic_mesh::geom;
use serde::Serialize;

use crate::dist;

/// A laser scan: hit points in the robot frame (x forward, y left) and the robot's pose
/// `[x, y, θ]` in the world when it was taken.
#[derive(Clone, Debug, Default, Serialize)]
pub struct LaserScan {
    /// Robot pose `[x, y, heading]`.
    pub pose: [f64; 3],
    /// Hit points in the robot frame.
    pub points: Vec<[f64; 2]>,
}

impl LaserScan {
    /// The hit points in world coordinates.
    pub fn world_points(&self) -> Vec<[f64; 2]> {
        let [x, y, th] = self.pose;
        let (s, c) = th.sin_cos();
        self.points
            .iter()
            .map(|p| [x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]])
            .collect()
    }
}

/// How scan points become obstacles.
#[derive(Clone, Copy, Debug)]
pub struct ScanOptions {
    /// Points closer than this are in the same cluster (default 0.3).
    pub cluster_gap: f64,
    /// Growth of each cluster's hull (default 0.1); less where the robot is closer than twice
    /// this, so the robot never ends up inside what it sensed.
    pub inflate: f64,
    /// Points within this distance of the known map's walls and obstacles are explained by
    /// the map and dropped (default 0.05).
    pub map_tolerance: f64,
}

impl Default for ScanOptions {
    fn default() -> Self {
        ScanOptions {
            cluster_gap: 0.3,
            inflate: 0.1,
            map_tolerance: 0.05,
        }
    }
}

/// Splits points into clusters: two points closer than `gap` are in the same cluster
/// (single linkage, on a grid of cells of side `gap`).
///
/// ```
/// use harmonic_dynamic::cluster_points;
/// let pts = [[0.0, 0.0], [0.1, 0.0], [2.0, 2.0], [0.2, 0.05]];
/// let clusters = cluster_points(&pts, 0.15);
/// assert_eq!(clusters.len(), 2);
/// assert_eq!(clusters[0].len(), 3);
/// ```
pub fn cluster_points(points: &[[f64; 2]], gap: f64) -> Vec<Vec<[f64; 2]>> {
    let points: Vec<[f64; 2]> = points
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    if points.is_empty() || !(gap.is_finite() && gap > 0.0) {
        return points.into_iter().map(|p| vec![p]).collect();
    }
    let cell = |p: [f64; 2]| ((p[0] / gap).floor() as i64, (p[1] / gap).floor() as i64);
    let mut grid: std::collections::HashMap<(i64, i64), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, &p) in points.iter().enumerate() {
        grid.entry(cell(p)).or_default().push(i);
    }
    // Union-find over neighbouring cells.
    let mut parent: Vec<usize> = (0..points.len()).collect();
    /// The root of `i`'s set, halving the path on the way.
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    for (i, &p) in points.iter().enumerate() {
        let (cx, cy) = cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(others) = grid.get(&(cx + dx, cy + dy)) {
                    for &j in others {
                        if j > i && dist(p, points[j]) < gap {
                            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                            parent[ri.max(rj)] = ri.min(rj);
                        }
                    }
                }
            }
        }
    }
    let mut clusters: BTreeMap<usize, Vec<[f64; 2]>> = BTreeMap::new();
    for (i, &p) in points.iter().enumerate() {
        let r = find(&mut parent, i);
        clusters.entry(r).or_default().push(p);
    }
    clusters.into_values().collect()
}

/// The convex hull of discs of radius `margin` around `points`, as a counter-clockwise polygon
/// (each disc is replaced by the octagon circumscribing it, so the result contains every disc).
pub fn inflated_hull(points: &[[f64; 2]], margin: f64) -> Vec<[f64; 2]> {
    let r = margin / (std::f64::consts::PI / 8.0).cos();
    let mut octagons = Vec::with_capacity(points.len() * 8);
    for p in points {
        for k in 0..8 {
            let a = std::f64::consts::TAU * (k as f64 + 0.5) / 8.0;
            octagons.push(Coord {
                x: p[0] + r * a.cos(),
                y: p[1] + r * a.sin(),
            });
        }
    }
    let hull = MultiPoint::from(octagons).convex_hull();
    let ring = hull.exterior();
    let mut out: Vec<[f64; 2]> = ring.coords().map(|c| [c.x, c.y]).collect();
    if out.len() > 1 && out.first() == out.last() {
        out.pop();
    }
    out
}

/// Turns a scan into obstacles in world coordinates: points within
/// [`ScanOptions::map_tolerance`] of the known map (`known_distance`, the distance to its walls
/// and obstacles) are dropped, the others clustered and each cluster replaced by its inflated
/// convex hull. The growth of a cluster is capped at half its distance to the robot.
pub fn scan_obstacles(
    scan: &LaserScan,
    known_distance: impl Fn([f64; 2]) -> f64,
    opts: &ScanOptions,
) -> Vec<Vec<[f64; 2]>> {
    let robot = [scan.pose[0], scan.pose[1]];
    let unexplained: Vec<[f64; 2]> = scan
        .world_points()
        .into_iter()
        .filter(|&p| known_distance(p) > opts.map_tolerance)
        .collect();
    cluster_points(&unexplained, opts.cluster_gap)
        .into_iter()
        .filter_map(|cluster| {
            let bare = inflated_hull(&cluster, 0.0);
            let gap = if bare.len() >= 3 {
                geom::polygon_distance(&bare, robot)
            } else {
                cluster
                    .iter()
                    .map(|&p| dist(p, robot))
                    .fold(f64::INFINITY, f64::min)
            };
            let margin = opts.inflate.min(0.5 * gap);
            (margin > 0.0).then(|| inflated_hull(&cluster, margin))
        })
        .collect()
}
