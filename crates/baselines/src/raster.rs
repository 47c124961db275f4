//! Occupancy grids: a scene rasterised onto square-ish cells by point-in-polygon tests of the
//! cell centres.

use harmonic_mesh::{Domain, Point};

use crate::BaselineError;
use crate::geometry::check_polygon;

/// What a grid cell holds, decided at its centre.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Cell {
    /// Free space the robot may enter.
    Free,
    /// Outside the workspace, or on the grid's outer ring.
    Wall,
    /// Inside input obstacle `i`.
    Obstacle(u32),
    /// Inside input goal region `j`.
    Goal(u32),
}

impl Cell {
    /// True for cells the robot may occupy (free or goal).
    pub fn is_traversable(self) -> bool {
        matches!(self, Cell::Free | Cell::Goal(_))
    }
}

/// A scene rasterised on an `n × n` grid.
///
/// The grid covers the workspace's bounding box plus a margin of one cell on every side, so
/// its outer ring lies outside the workspace and is always [`Cell::Wall`]. Cell `(i, j)`
/// (column `i`, row `j`, stored at index `j * n + i`) is centred at
/// `origin + ((i + ½)·hx, (j + ½)·hy)`. Each cell centre is classified by point-in-polygon
/// tests (even–odd scanline fill): outside the workspace → wall, then obstacles, then goals
/// (a goal overrides an obstacle). A goal region too small to contain any cell centre still
/// gets the one cell holding its vertex average, so small goal discs are never lost.
#[derive(Clone, Debug, PartialEq)]
pub struct Raster {
    n: usize,
    origin: Point,
    hx: f64,
    hy: f64,
    cells: Vec<Cell>,
}

/// Smallest accepted number of cells a side (the wall ring plus a 2 × 2 interior).
pub const MIN_GRID: usize = 4;

impl Raster {
    /// Rasterises a workspace polygon with obstacle and goal polygons (any orientation) on an
    /// `n × n` grid.
    ///
    /// Errors if a polygon has fewer than three vertices or a non-finite coordinate, if
    /// `n < MIN_GRID`, if there is no goal, or if a goal region falls entirely outside the
    /// free cells.
    ///
    /// ```
    /// use harmonic_baselines::{Cell, Raster};
    /// use harmonic_mesh::Point;
    /// let square = vec![Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(4.0, 4.0), Point::new(0.0, 4.0)];
    /// let goal = vec![Point::new(3.0, 3.0), Point::new(4.0, 3.0), Point::new(4.0, 4.0), Point::new(3.0, 4.0)];
    /// let r = Raster::from_polygons(&square, &[], &[goal], 10).unwrap();
    /// assert_eq!(r.cell_at(Point::new(0.5, 0.5)), Some(Cell::Free));
    /// assert_eq!(r.cell_at(Point::new(3.5, 3.5)), Some(Cell::Goal(0)));
    /// assert_eq!(r.cell(0, 0), Some(Cell::Wall));
    /// ```
    pub fn from_polygons(
        workspace: &[Point],
        obstacles: &[Vec<Point>],
        goals: &[Vec<Point>],
        n: usize,
    ) -> Result<Self, BaselineError> {
        check_polygon(|| "workspace".to_string(), workspace)?;
        for (i, o) in obstacles.iter().enumerate() {
            check_polygon(|| format!("obstacle {i}"), o)?;
        }
        for (j, g) in goals.iter().enumerate() {
            check_polygon(|| format!("goal {j}"), g)?;
        }
        if goals.is_empty() {
            return Err(BaselineError::NoGoal);
        }
        if n < MIN_GRID {
            return Err(BaselineError::GridTooSmall { n, min: MIN_GRID });
        }
        let (mut lo, mut hi) = (workspace[0], workspace[0]);
        for p in workspace {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        let obstacles: Vec<(u32, Vec<&[Point]>)> = obstacles
            .iter()
            .enumerate()
            .map(|(i, o)| (i as u32, vec![o.as_slice()]))
            .collect();
        let goals: Vec<(u32, Vec<&[Point]>)> = goals
            .iter()
            .enumerate()
            .map(|(j, g)| (j as u32, vec![g.as_slice()]))
            .collect();
        Self::build(lo, hi, n, &[vec![workspace]], &obstacles, &goals)
    }

    /// Rasterises a validated [`Domain`] (after the robot-radius inflation, merging and
    /// clipping it did) on an `n × n` grid. A merged obstacle or goal region is labelled with
    /// the first input index it came from.
    ///
    /// Errors if `n < MIN_GRID`, the domain has no goal, or a goal falls outside the free cells.
    pub fn from_domain(domain: &Domain, n: usize) -> Result<Self, BaselineError> {
        if n < MIN_GRID {
            return Err(BaselineError::GridTooSmall { n, min: MIN_GRID });
        }
        if domain.goal_polygons().is_empty() {
            return Err(BaselineError::NoGoal);
        }
        // (`Region` is not exported by harmonic-mesh, so its fields are reached through
        // inference.)
        let workspace: Vec<Vec<&[Point]>> = domain
            .workspace_rings()
            .iter()
            .map(|r| {
                std::iter::once(r.exterior.as_slice())
                    .chain(r.holes.iter().map(Vec::as_slice))
                    .collect()
            })
            .collect();
        macro_rules! labelled {
            ($regions:expr) => {
                $regions
                    .iter()
                    .enumerate()
                    .map(|(k, r)| {
                        let rings: Vec<&[Point]> = std::iter::once(r.exterior.as_slice())
                            .chain(r.holes.iter().map(Vec::as_slice))
                            .collect();
                        (r.sources.first().copied().unwrap_or(k as u32), rings)
                    })
                    .collect::<Vec<_>>()
            };
        }
        let obstacles = labelled!(domain.obstacle_polygons());
        let goals = labelled!(domain.goal_polygons());
        let (lo, hi) = domain.bounding_box();
        Self::build(lo, hi, n, &workspace, &obstacles, &goals)
    }

    /// Lays an `n × n` grid over the box `lo..hi` plus a one-cell margin, then fills the
    /// workspace regions as free, the obstacles and the goals (each a set of rings filled by
    /// the even–odd rule, so holes stay out).
    fn build(
        lo: Point,
        hi: Point,
        n: usize,
        workspace: &[Vec<&[Point]>],
        obstacles: &[(u32, Vec<&[Point]>)],
        goals: &[(u32, Vec<&[Point]>)],
    ) -> Result<Self, BaselineError> {
        let inner = (n - 2) as f64;
        let hx = (hi.x - lo.x) / inner;
        let hy = (hi.y - lo.y) / inner;
        if !(hx > 0.0 && hy > 0.0 && hx.is_finite() && hy.is_finite()) {
            return Err(BaselineError::InvalidParameter {
                name: "workspace extent",
                value: hx.min(hy),
                reason: "the workspace must have positive, finite width and height",
            });
        }
        let mut raster = Raster {
            n,
            origin: Point::new(lo.x - hx, lo.y - hy),
            hx,
            hy,
            cells: vec![Cell::Wall; n * n],
        };
        let mut xs = Vec::new();
        for w in workspace {
            raster.fill(w, Cell::Free, &mut xs);
        }
        for (i, o) in obstacles {
            raster.fill(o, Cell::Obstacle(*i), &mut xs);
        }
        for (j, g) in goals {
            let kind = Cell::Goal(*j);
            if raster.fill(g, kind, &mut xs) == 0 {
                let outer = g[0];
                let c = outer.iter().fold(Point::origin(), |acc, p| {
                    acc + p.coords / outer.len() as f64
                });
                match raster.index_of(c) {
                    Some(k) if raster.cells[k] != Cell::Wall => raster.cells[k] = kind,
                    _ => return Err(BaselineError::NoGoalCell { goal: *j as usize }),
                }
            }
        }
        // The ring lies outside the workspace's bounding box, but a goal or obstacle polygon
        // sticking out of the workspace could reach it: force it back to wall.
        for k in 0..n {
            for idx in [k, (n - 1) * n + k, k * n, k * n + n - 1] {
                raster.cells[idx] = Cell::Wall;
            }
        }
        if !raster.cells.iter().any(|c| matches!(c, Cell::Goal(_))) {
            return Err(BaselineError::NoGoalCell { goal: 0 });
        }
        Ok(raster)
    }

    /// Sets every cell whose centre lies inside the rings (even–odd rule) to `kind`; returns
    /// how many cells were set. `xs` is scratch space for the scanline crossings.
    fn fill(&mut self, rings: &[&[Point]], kind: Cell, xs: &mut Vec<f64>) -> usize {
        let mut count = 0;
        let n = self.n;
        for j in 0..n {
            let y = self.origin.y + (j as f64 + 0.5) * self.hy;
            xs.clear();
            for poly in rings {
                for (k, a) in poly.iter().enumerate() {
                    let b = poly[(k + 1) % poly.len()];
                    if (a.y <= y) != (b.y <= y) {
                        xs.push(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
                    }
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                // Cells whose centre x lies in [pair[0], pair[1]).
                let first = ((pair[0] - self.origin.x) / self.hx - 0.5).ceil().max(0.0);
                let end = ((pair[1] - self.origin.x) / self.hx - 0.5)
                    .ceil()
                    .clamp(0.0, n as f64);
                let (first, end) = (first as usize, end as usize);
                for c in &mut self.cells[j * n + first.min(end)..j * n + end] {
                    *c = kind;
                    count += 1;
                }
            }
        }
        count
    }

    /// Cells per side.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Lower-left corner of cell `(0, 0)`.
    pub fn origin(&self) -> Point {
        self.origin
    }

    /// Cell width and height.
    pub fn cell_size(&self) -> (f64, f64) {
        (self.hx, self.hy)
    }

    /// All cells, row by row (`index = j * n + i`).
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// The cell in column `i`, row `j`, or `None` outside the grid.
    pub fn cell(&self, i: usize, j: usize) -> Option<Cell> {
        (i < self.n && j < self.n).then(|| self.cells[j * self.n + i])
    }

    /// Centre of the cell with flat index `k`.
    pub fn centre(&self, k: usize) -> Point {
        let (i, j) = (k % self.n, k / self.n);
        Point::new(
            self.origin.x + (i as f64 + 0.5) * self.hx,
            self.origin.y + (j as f64 + 0.5) * self.hy,
        )
    }

    /// Flat index of the cell containing `p`, or `None` outside the grid.
    pub fn index_of(&self, p: Point) -> Option<usize> {
        let u = (p.x - self.origin.x) / self.hx;
        let v = (p.y - self.origin.y) / self.hy;
        let n = self.n as f64;
        if !(u >= 0.0 && v >= 0.0 && u < n && v < n) {
            return None;
        }
        Some(v as usize * self.n + u as usize)
    }

    /// The cell containing `p`, or `None` outside the grid.
    pub fn cell_at(&self, p: Point) -> Option<Cell> {
        self.index_of(p).map(|k| self.cells[k])
    }

    /// Number of cells of each kind: `(free, goal, blocked)` where blocked counts walls and
    /// obstacles.
    pub fn counts(&self) -> (usize, usize, usize) {
        let mut c = (0, 0, 0);
        for cell in &self.cells {
            match cell {
                Cell::Free => c.0 += 1,
                Cell::Goal(_) => c.1 += 1,
                Cell::Wall | Cell::Obstacle(_) => c.2 += 1,
            }
        }
        c
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

    #[test]
    fn classifies_cell_centres_and_keeps_the_ring_as_wall() {
        // n = 12 over [0, 10]²: unit cells, origin (−1, −1).
        let r = Raster::from_polygons(
            &rect(0.0, 0.0, 10.0, 10.0),
            &[vec![
                Point::new(2.0, 2.0),
                Point::new(2.0, 4.0),
                Point::new(4.0, 4.0),
                Point::new(4.0, 2.0),
            ]],
            &[rect(8.0, 8.0, 9.0, 9.0)],
            12,
        )
        .unwrap();
        assert_eq!(r.cell_size(), (1.0, 1.0));
        assert_eq!(r.origin(), Point::new(-1.0, -1.0));
        assert_eq!(r.cell_at(Point::new(2.5, 3.5)), Some(Cell::Obstacle(0)));
        assert_eq!(r.cell_at(Point::new(4.5, 3.5)), Some(Cell::Free));
        assert_eq!(r.cell_at(Point::new(8.5, 8.5)), Some(Cell::Goal(0)));
        assert_eq!(r.cell_at(Point::new(-0.5, 5.0)), Some(Cell::Wall));
        assert_eq!(r.cell_at(Point::new(-1.5, 5.0)), None);
        assert_eq!(r.cell(12, 0), None);
        assert_eq!(r.counts(), (100 - 4 - 1, 1, 144 - 100 + 4));
        for k in 0..12 {
            assert_eq!(r.cell(k, 0), Some(Cell::Wall));
            assert_eq!(r.cell(11, k), Some(Cell::Wall));
        }
    }

    #[test]
    fn rasterises_a_domain_with_inflated_obstacles() {
        use harmonic_mesh::{DomainSpec, GoalShape, MeshOptions, Shape};
        let spec = DomainSpec {
            workspace: rect(0.0, 0.0, 10.0, 10.0),
            obstacles: vec![
                Shape::Polygon(rect(2.0, 2.0, 3.0, 8.0)),
                Shape::Circle {
                    center: Point::new(6.5, 6.5),
                    radius: 0.6,
                },
            ],
            goals: vec![GoalShape::Circle {
                center: Point::new(8.5, 1.5),
                radius: 0.3,
            }],
            robot_radius: 0.25,
        };
        let domain = Domain::new(&spec, &MeshOptions::default()).unwrap();
        let r = Raster::from_domain(&domain, 102).unwrap();
        assert_eq!(r.cell_size(), (0.1, 0.1));
        // Inflated by the robot radius: (1.85, 5) is within 0.25 of the rectangle.
        assert_eq!(r.cell_at(Point::new(1.85, 5.05)), Some(Cell::Obstacle(0)));
        assert_eq!(r.cell_at(Point::new(1.65, 5.05)), Some(Cell::Free));
        assert_eq!(r.cell_at(Point::new(6.55, 6.55)), Some(Cell::Obstacle(1)));
        assert_eq!(r.cell_at(Point::new(8.55, 1.55)), Some(Cell::Goal(0)));
        // The workspace shrinks by the robot radius too.
        assert_eq!(r.cell_at(Point::new(0.15, 5.05)), Some(Cell::Wall));
        assert_eq!(r.cell_at(Point::new(0.35, 5.05)), Some(Cell::Free));
    }

    #[test]
    fn a_goal_smaller_than_a_cell_still_gets_one() {
        let tiny = rect(4.1, 4.1, 4.2, 4.2);
        let r = Raster::from_polygons(&rect(0.0, 0.0, 10.0, 10.0), &[], &[tiny], 12).unwrap();
        assert_eq!(r.counts().1, 1);
        assert_eq!(r.cell_at(Point::new(4.15, 4.15)), Some(Cell::Goal(0)));
    }

    #[test]
    fn rejects_bad_input() {
        let ws = rect(0.0, 0.0, 1.0, 1.0);
        let g = vec![rect(0.4, 0.4, 0.6, 0.6)];
        assert_eq!(
            Raster::from_polygons(&ws[..2], &[], &g, 8),
            Err(BaselineError::TooFewVertices {
                what: "workspace".into(),
                count: 2
            })
        );
        assert!(matches!(
            Raster::from_polygons(&ws, &[vec![Point::new(f64::NAN, 0.0); 3]], &g, 8),
            Err(BaselineError::NonFinite { .. })
        ));
        assert_eq!(
            Raster::from_polygons(&ws, &[], &[], 8),
            Err(BaselineError::NoGoal)
        );
        assert_eq!(
            Raster::from_polygons(&ws, &[], &g, 3),
            Err(BaselineError::GridTooSmall {
                n: 3,
                min: MIN_GRID
            })
        );
        assert_eq!(
            Raster::from_polygons(&ws, &[], &[rect(5.0, 5.0, 6.0, 6.0)], 8),
            Err(BaselineError::NoGoalCell { goal: 0 })
        );
    }
}

/// Which neighbours of a grid cell count as adjacent.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Connectivity {
    /// The 4 edge neighbours.
    #[default]
    Four,
    /// The 8 edge and corner neighbours; a diagonal move needs both cells it cuts past to be
    /// traversable, so paths never squeeze between two blocked cells touching at a corner.
    Eight,
}

/// Marks a cell that no wavefront reached.
pub const UNREACHED: u32 = u32::MAX;

impl Raster {
    /// The traversable neighbours of cell `k` (an interior cell) under `connectivity`, edge
    /// neighbours first.
    pub(crate) fn neighbours(&self, k: usize, connectivity: Connectivity) -> ([usize; 8], usize) {
        let n = self.n;
        let mut out = [0; 8];
        let mut len = 0;
        let ok = |m: usize| self.cells[m].is_traversable();
        for m in [k - 1, k + 1, k - n, k + n] {
            if ok(m) {
                out[len] = m;
                len += 1;
            }
        }
        if connectivity == Connectivity::Eight {
            for (dx, dy) in [
                (k - 1, k - n),
                (k + 1, k - n),
                (k - 1, k + n),
                (k + 1, k + n),
            ] {
                let diagonal = dy + dx - k;
                if ok(dx) && ok(dy) && ok(diagonal) {
                    out[len] = diagonal;
                    len += 1;
                }
            }
        }
        (out, len)
    }

    /// Brushfire from the goal cells: the number of moves from every traversable cell to the
    /// nearest goal cell ([`UNREACHED`] for cells cut off from every goal and for blocked
    /// cells). Goal cells get 0.
    pub fn goal_distances(&self, connectivity: Connectivity) -> Vec<u32> {
        let mut dist = vec![UNREACHED; self.cells.len()];
        let mut queue = std::collections::VecDeque::new();
        for (k, c) in self.cells.iter().enumerate() {
            if matches!(c, Cell::Goal(_)) {
                dist[k] = 0;
                queue.push_back(k);
            }
        }
        while let Some(k) = queue.pop_front() {
            let (nb, len) = self.neighbours(k, connectivity);
            for &m in &nb[..len] {
                if dist[m] == UNREACHED {
                    dist[m] = dist[k] + 1;
                    queue.push_back(m);
                }
            }
        }
        dist
    }
}
