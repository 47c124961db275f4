//! Kim & Khosla's panel method as they published it (1992, §§3–4), beside the bounded
//! variant of [`crate::panel`]: the *unbounded* plane (no wall panels), one body of panels per
//! obstacle, a uniform stream from the start toward the goal (their eqs. 27 and 38), a goal
//! sink of strength `λ_g` (eq. 26), the strengths from the desired outward normal velocities
//! `V_i` at the panels' centre points (eqs. 29–35), then the two checks of their §4:
//!
//! - the **obstacle strength** `λ_o = Σ λ_i L_i` of each obstacle must satisfy
//!   `−λ_g < λ_o < 0` (eqs. 39–40; [`PanelField::lambda_o_check`]);
//! - each obstacle must have **one stagnation point**, a zero of the rate of flow
//!   `q = √(u² + v²)` (eq. 41; [`PanelField::stagnation_points`]); where an obstacle has more,
//!   the paper's remedy raises that obstacle's `V_i` until it has one
//!   ([`PanelField::published_with_remedy`]).
//!
//! **Signs.** The paper writes a source as `λ < 0` in eq. 11 and prints its Table 1 that way
//! (obstacle strength −7.503: net source, repulsive), while its eq. 24 counts a source panel's
//! strength positive. Our [`PanelField::strengths`] are positive for sources (outward normal
//! velocity `+λ/2`); [`PanelField::paper_strengths`] and [`ObstacleStrength::lambda_o`] are in
//! the sign of the paper's tables (`−` ours).

use std::ops::Range;

use harmonic_mesh::geom::{point_segment_distance, polygon_contains};
use harmonic_mesh::{Point, Vector};

use crate::BaselineError;
use crate::geometry::{check_point, check_polygon, check_positive};
use crate::panel::{Panel, PanelField, edge_panels};

/// One obstacle of a published field: its polygon and the range of its panels.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Body {
    pub(crate) polygon: Vec<Point>,
    pub(crate) panels: Range<usize>,
}

/// The inputs of the paper's setting (their eq. 50 for the bar robot, eq. 51 for the arm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PublishedSetting {
    /// Strength `U` of the uniform flow (eq. 27); its direction is start → goal (eq. 38).
    pub uniform_speed: f64,
    /// Strength `λ_g > 0` of the goal sink (eq. 26): the flux it swallows.
    pub goal_strength: f64,
    /// The desired outward normal velocity `V_i` at every panel's centre point (eq. 29).
    pub normal_velocity: f64,
    /// Edges longer than this are split into equal panels; `f64::INFINITY` gives one panel
    /// per edge, as in the paper's figures.
    pub max_panel_length: f64,
}

impl PublishedSetting {
    /// The bar-shaped robot's setting, eq. 50: `U = 1`, `λ_g = 30`, `V_i = 0.5`.
    pub const BAR_ROBOT: PublishedSetting = PublishedSetting {
        uniform_speed: 1.0,
        goal_strength: 30.0,
        normal_velocity: 0.5,
        max_panel_length: f64::INFINITY,
    };
    /// The redundant manipulator's setting, eq. 51: `U = 1`, `λ_g = 30`, `V_i = 1`.
    pub const MANIPULATOR: PublishedSetting = PublishedSetting {
        uniform_speed: 1.0,
        goal_strength: 30.0,
        normal_velocity: 1.0,
        max_panel_length: f64::INFINITY,
    };
}

impl Default for PublishedSetting {
    fn default() -> Self {
        PublishedSetting::BAR_ROBOT
    }
}

/// What eq. 39 says of an obstacle's strength `λ_o` (in the paper's sign).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StrengthCheck {
    /// `−λ_g < λ_o < 0`: more source than sink, and less than the goal swallows.
    Satisfied,
    /// `λ_o ≥ 0`: the obstacle is a net sink and attracts the robot (V_i too small).
    Attractive,
    /// `λ_o ≤ −λ_g`: the obstacle emits at least what the goal swallows, and the robot can be
    /// carried past the goal by the stream (V_i too large).
    OverwhelmsGoal,
}

/// The obstacle strength of one obstacle (eq. 40) and its check (eq. 39).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ObstacleStrength {
    /// Index of the obstacle.
    pub obstacle: usize,
    /// `λ_o = Σ λ_i L_i` over its panels, in the paper's sign (negative: net source).
    pub lambda_o: f64,
    /// Eq. 39 against the field's goal strength.
    pub check: StrengthCheck,
}

/// How [`PanelField::stagnation_points`] searches for zeros of the rate of flow.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StagnationSearch {
    /// Samples per side of each obstacle's search box.
    pub samples: usize,
    /// The box is the obstacle's bounding box grown by this fraction of its diagonal on
    /// every side (the paper: stagnation points lie "in the front of each obstacle").
    pub margin: f64,
    /// A Newton-refined point is a stagnation point when `q` is below this times `U`
    /// (or times 1 without a stream).
    pub tolerance: f64,
    /// Zeros closer to a panel's end point than this fraction of the panel's length are left
    /// out: a constant-strength panel's velocity is log-singular at its ends (the paper's
    /// §3.1: "a single panel has a singular point on each edge"), and the zeros it makes
    /// beside a convex corner belong to the discretisation, not to the flow.
    pub end_exclusion: f64,
}

impl Default for StagnationSearch {
    fn default() -> Self {
        StagnationSearch {
            samples: 48,
            margin: 0.5,
            tolerance: 1e-9,
            end_exclusion: 0.05,
        }
    }
}

/// A zero of the rate of flow `q` (eq. 41): a saddle of the potential.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StagnationPoint {
    /// Where.
    #[serde(serialize_with = "point_xy")]
    pub at: Point,
    /// `q` there (below the search tolerance).
    pub speed: f64,
    /// The obstacle it belongs to (the nearest), or `None` when the goal is nearer than
    /// every obstacle (the stagnation point downstream of the goal sink, where the stream
    /// and the sink cancel).
    pub obstacle: Option<usize>,
}

fn point_xy<S: serde::Serializer>(p: &Point, s: S) -> Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&[p.x, p.y], s)
}

/// The paper's remedy for an obstacle with more than one stagnation point (§4.3): raise its
/// `V_i` and solve again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Remedy {
    /// Added to an offending obstacle's `V_i` per round.
    pub increase: f64,
    /// Rounds before giving up.
    pub max_rounds: usize,
}

impl Default for Remedy {
    fn default() -> Self {
        Remedy {
            increase: 0.5,
            max_rounds: 8,
        }
    }
}

/// One solve of [`PanelField::published_with_remedy`].
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RemedyRound {
    /// `V_i` of each obstacle in this round.
    pub normal_velocities: Vec<f64>,
    /// Stagnation points found per obstacle.
    pub stagnation_counts: Vec<usize>,
    /// Eq. 39 per obstacle.
    pub strengths: Vec<ObstacleStrength>,
}

/// How the remedy ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case", tag = "outcome")]
pub enum RemedyOutcome {
    /// Every obstacle has at most one stagnation point and satisfies eq. 39.
    OneStagnationPointEach,
    /// Raising `V_i` broke eq. 39 for this obstacle before it had one stagnation point.
    StrengthOutOfBounds {
        /// The obstacle.
        obstacle: usize,
    },
    /// Some obstacle still had more than one stagnation point after the last round.
    GaveUp,
}

/// The field [`PanelField::published_with_remedy`] settled on, with every round it solved.
#[derive(Clone, Debug)]
pub struct Remedied {
    /// The field to follow: the last one solved, or, when raising `V_i` broke eq. 39, the
    /// last one that kept it (the first, if even that one broke it).
    pub field: PanelField,
    /// Every solve, the first with the setting's `V_i`.
    pub rounds: Vec<RemedyRound>,
    /// How it ended.
    pub outcome: RemedyOutcome,
    /// The stagnation points of [`Remedied::field`].
    pub stagnation_points: Vec<StagnationPoint>,
}

impl PanelField {
    /// The flow of Kim & Khosla's unbounded panel method: the panels of each obstacle (in the
    /// order of its vertices, so clockwise polygons number their panels clockwise as the
    /// paper does; normals always point out of the obstacle), a uniform stream of strength
    /// `U` from `start` toward `goal`, a sink of strength `λ_g` at `goal`, and every panel's
    /// outward normal velocity `V_i` at its centre point. No wall carries panels.
    ///
    /// Errors on polygons with fewer than three vertices, non-finite input, a non-positive
    /// `λ_g` or panel length, or a singular system (obstacles that overlap or share edges).
    ///
    /// ```
    /// use harmonic_baselines::{PanelField, PublishedSetting, StrengthCheck};
    /// use harmonic_mesh::Point;
    /// let square = vec![Point::new(4.0, 4.0), Point::new(6.0, 4.0), Point::new(6.0, 6.0), Point::new(4.0, 6.0)];
    /// let field = PanelField::published(&[square], Point::new(0.0, 5.0), Point::new(10.0, 5.0),
    ///     &PublishedSetting::BAR_ROBOT).unwrap();
    /// assert_eq!(field.panels().len(), 4);
    /// assert_eq!(field.lambda_o_check()[0].check, StrengthCheck::Satisfied);
    /// ```
    pub fn published(
        obstacles: &[Vec<Point>],
        start: Point,
        goal: Point,
        setting: &PublishedSetting,
    ) -> Result<PanelField, BaselineError> {
        let velocities = vec![setting.normal_velocity; obstacles.len()];
        PanelField::published_with_velocities(obstacles, start, goal, setting, &velocities)
    }

    /// [`PanelField::published`] with its own `V_i` for each obstacle (the remedy's rounds).
    pub fn published_with_velocities(
        obstacles: &[Vec<Point>],
        start: Point,
        goal: Point,
        setting: &PublishedSetting,
        velocities: &[f64],
    ) -> Result<PanelField, BaselineError> {
        for (i, o) in obstacles.iter().enumerate() {
            check_polygon(|| format!("obstacle {i}"), o)?;
        }
        check_point(|| "start".to_string(), start)?;
        check_point(|| "goal".to_string(), goal)?;
        check_positive("goal_strength", setting.goal_strength)?;
        if setting.max_panel_length.is_nan() || setting.max_panel_length <= 0.0 {
            return Err(BaselineError::InvalidParameter {
                name: "max_panel_length",
                value: setting.max_panel_length,
                reason: "must be positive (infinite: one panel per edge)",
            });
        }
        for (name, v) in [
            ("uniform_speed", setting.uniform_speed),
            ("normal_velocity", setting.normal_velocity),
        ] {
            if !v.is_finite() {
                return Err(BaselineError::NonFinite {
                    what: name.to_string(),
                    value: v,
                });
            }
        }
        if velocities.len() != obstacles.len() {
            return Err(BaselineError::InvalidParameter {
                name: "velocities",
                value: velocities.len() as f64,
                reason: "needs one normal velocity per obstacle",
            });
        }
        let mut panels: Vec<Panel> = Vec::new();
        let mut bodies = Vec::with_capacity(obstacles.len());
        let mut normal = Vec::new();
        for (o, &v) in obstacles.iter().zip(velocities) {
            let first = panels.len();
            edge_panels(o, true, setting.max_panel_length, &mut panels);
            normal.resize(panels.len(), v);
            bodies.push(Body {
                polygon: o.clone(),
                panels: first..panels.len(),
            });
        }
        let dir = goal - start;
        let uniform = if dir.norm() > 0.0 {
            dir.normalize() * setting.uniform_speed
        } else {
            Vector::zeros()
        };
        let mut field = PanelField::solve(
            panels,
            &normal,
            uniform,
            Some((goal, setting.goal_strength)),
        )?;
        field.bodies = bodies;
        Ok(field)
    }

    /// The panel strengths in the sign of the paper's tables (negative: source).
    pub fn paper_strengths(&self) -> Vec<f64> {
        self.strengths().iter().map(|s| -s).collect()
    }

    /// The panel ranges of the obstacles (one range over every panel for a field built by
    /// [`PanelField::solve`]).
    pub fn obstacle_panels(&self) -> Vec<Range<usize>> {
        if self.bodies.is_empty() {
            std::iter::once(0..self.panels().len()).collect()
        } else {
            self.bodies.iter().map(|b| b.panels.clone()).collect()
        }
    }

    /// Eqs. 39–40 per obstacle: `λ_o = Σ λ_i L_i` (paper's sign) against `−λ_g < λ_o < 0`,
    /// `λ_g` the goal sink's strength (0 without a sink, so a net source then overwhelms it).
    pub fn lambda_o_check(&self) -> Vec<ObstacleStrength> {
        let lambda_g = self.sink().map_or(0.0, |(_, q)| q);
        self.obstacle_panels()
            .into_iter()
            .enumerate()
            .map(|(obstacle, range)| {
                let lambda_o: f64 = range
                    .map(|j| {
                        let p = self.panels()[j];
                        -self.strengths()[j] * (p.end - p.start).norm()
                    })
                    .sum();
                let check = if lambda_o >= 0.0 {
                    StrengthCheck::Attractive
                } else if lambda_o <= -lambda_g {
                    StrengthCheck::OverwhelmsGoal
                } else {
                    StrengthCheck::Satisfied
                };
                ObstacleStrength {
                    obstacle,
                    lambda_o,
                    check,
                }
            })
            .collect()
    }

    fn inside_body(&self, p: Point) -> bool {
        self.bodies.iter().any(|b| polygon_contains(&b.polygon, p))
    }

    /// The stagnation points near the obstacles (eq. 41): over each obstacle's search box,
    /// the samples outside every obstacle where `q` is no larger than at its eight neighbours
    /// are refined by Newton's method on the velocity (Jacobian by central differences) and
    /// kept where `q` falls below the tolerance and not beside a panel's end point; each is given to the nearest obstacle (or to
    /// none when the goal is nearer). A field without obstacles (built by
    /// [`PanelField::solve`]) is searched around the bounding box of all its panels.
    pub fn stagnation_points(&self, search: &StagnationSearch) -> Vec<StagnationPoint> {
        let boxes: Vec<(Point, Point)> = if self.bodies.is_empty() {
            vec![bbox(self.panels().iter().flat_map(|p| [p.start, p.end]))]
        } else {
            self.bodies
                .iter()
                .map(|b| bbox(b.polygon.iter().copied()))
                .collect()
        };
        let stream = self.uniform().norm();
        let tol = search.tolerance * if stream > 0.0 { stream } else { 1.0 };
        let n = search.samples.max(3);
        let mut found: Vec<StagnationPoint> = Vec::new();
        for (lo, hi) in boxes {
            let diag = (hi - lo).norm().max(f64::MIN_POSITIVE);
            let grow = Vector::new(1.0, 1.0) * (search.margin * diag);
            let (lo, hi) = (lo - grow, hi + grow);
            let h = Vector::new(
                (hi.x - lo.x) / (n - 1) as f64,
                (hi.y - lo.y) / (n - 1) as f64,
            );
            let at = |i: usize, j: usize| Point::new(lo.x + h.x * i as f64, lo.y + h.y * j as f64);
            let q: Vec<f64> = (0..n * n)
                .map(|k| {
                    let p = at(k % n, k / n);
                    if self.inside_body(p) {
                        f64::INFINITY
                    } else {
                        let s = self.velocity(p).norm();
                        if s.is_finite() { s } else { f64::INFINITY }
                    }
                })
                .collect();
            for j in 0..n {
                for i in 0..n {
                    let qc = q[j * n + i];
                    if !qc.is_finite() {
                        continue;
                    }
                    let is_min = (-1i64..=1).all(|dj| {
                        (-1i64..=1).all(|di| {
                            let (ii, jj) = (i as i64 + di, j as i64 + dj);
                            (di == 0 && dj == 0)
                                || ii < 0
                                || jj < 0
                                || ii >= n as i64
                                || jj >= n as i64
                                || q[jj as usize * n + ii as usize] >= qc
                        })
                    });
                    if !is_min {
                        continue;
                    }
                    if let Some(p) = self.newton_stagnation(at(i, j), h.norm(), diag, tol) {
                        let at_panel_end = self.panels().iter().any(|pl| {
                            let cut = search.end_exclusion * (pl.end - pl.start).norm();
                            (p - pl.start).norm() < cut || (p - pl.end).norm() < cut
                        });
                        if !at_panel_end && !found.iter().any(|s| (s.at - p).norm() < 1e-6 * diag) {
                            found.push(StagnationPoint {
                                at: p,
                                speed: self.velocity(p).norm(),
                                obstacle: self.owner(p),
                            });
                        }
                    }
                }
            }
        }
        found.sort_by(|a, b| a.at.x.total_cmp(&b.at.x).then(a.at.y.total_cmp(&b.at.y)));
        found
    }

    /// Newton's method on `v(p) = 0` from `p`, steps capped at a sample spacing; `None` if
    /// it does not converge, wanders more than two spacings or ends inside an obstacle.
    fn newton_stagnation(&self, p0: Point, spacing: f64, scale: f64, tol: f64) -> Option<Point> {
        let mut p = p0;
        let fd = 1e-7 * scale;
        for _ in 0..60 {
            let v = self.velocity(p);
            if !v.norm().is_finite() {
                return None;
            }
            if v.norm() <= tol {
                return (!self.inside_body(p)).then_some(p);
            }
            let dx = (self.velocity(p + Vector::x() * fd) - self.velocity(p - Vector::x() * fd))
                / (2.0 * fd);
            let dy = (self.velocity(p + Vector::y() * fd) - self.velocity(p - Vector::y() * fd))
                / (2.0 * fd);
            let jac = nalgebra::Matrix2::from_columns(&[dx, dy]);
            let mut step = jac.lu().solve(&(-v))?;
            if step.norm() > spacing {
                step *= spacing / step.norm();
            }
            p += step;
            if (p - p0).norm() > 2.0 * spacing {
                return None;
            }
        }
        None
    }

    /// The obstacle nearest `p` (by distance to its panels), unless the goal is nearer.
    fn owner(&self, p: Point) -> Option<usize> {
        let ranges = self.obstacle_panels();
        let (best, dist) = ranges
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let d = self.panels()[r.clone()]
                    .iter()
                    .map(|pl| point_segment_distance(p, pl.start, pl.end))
                    .fold(f64::INFINITY, f64::min);
                (k, d)
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        match self.sink() {
            Some((g, _)) if (p - g).norm() < dist => None,
            _ => Some(best),
        }
    }

    /// Kim & Khosla's procedure (§4.3): solve with the setting's `V_i`; while an obstacle has
    /// more than one stagnation point, raise its `V_i` by `remedy.increase` and solve again,
    /// stopping when eq. 39 fails for a raised obstacle or after `remedy.max_rounds` rounds.
    pub fn published_with_remedy(
        obstacles: &[Vec<Point>],
        start: Point,
        goal: Point,
        setting: &PublishedSetting,
        search: &StagnationSearch,
        remedy: &Remedy,
    ) -> Result<Remedied, BaselineError> {
        check_positive("remedy.increase", remedy.increase)?;
        let mut velocities = vec![setting.normal_velocity; obstacles.len()];
        let mut rounds = Vec::new();
        let mut kept: Option<(PanelField, Vec<StagnationPoint>)> = None;
        loop {
            let field = PanelField::published_with_velocities(
                obstacles,
                start,
                goal,
                setting,
                &velocities,
            )?;
            let points = field.stagnation_points(search);
            let mut counts = vec![0usize; obstacles.len()];
            for s in &points {
                if let Some(o) = s.obstacle {
                    counts[o] += 1;
                }
            }
            let strengths = field.lambda_o_check();
            rounds.push(RemedyRound {
                normal_velocities: velocities.clone(),
                stagnation_counts: counts.clone(),
                strengths: strengths.clone(),
            });
            let offenders: Vec<usize> = (0..obstacles.len()).filter(|&o| counts[o] > 1).collect();
            let broken = strengths
                .iter()
                .find(|s| s.check != StrengthCheck::Satisfied)
                .map(|s| s.obstacle);
            let outcome = match (offenders.is_empty(), broken) {
                (_, Some(o)) => Some(RemedyOutcome::StrengthOutOfBounds { obstacle: o }),
                (true, None) => Some(RemedyOutcome::OneStagnationPointEach),
                (false, None) if rounds.len() > remedy.max_rounds => Some(RemedyOutcome::GaveUp),
                (false, None) => None,
            };
            if let Some(outcome) = outcome {
                let (field, stagnation_points) = match (outcome, kept) {
                    (RemedyOutcome::StrengthOutOfBounds { .. }, Some(k)) => k,
                    _ => (field, points),
                };
                return Ok(Remedied {
                    field,
                    rounds,
                    outcome,
                    stagnation_points,
                });
            }
            kept = Some((field, points));
            for o in offenders {
                velocities[o] += remedy.increase;
            }
        }
    }
}

fn bbox(points: impl Iterator<Item = Point>) -> (Point, Point) {
    points.fold(
        (
            Point::new(f64::INFINITY, f64::INFINITY),
            Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(lo, hi), p| {
            (
                Point::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A regular `n`-gon of radius `r` about `c`, counter-clockwise.
    fn ngon(c: Point, r: f64, n: usize) -> Vec<Point> {
        (0..n)
            .map(|k| {
                let t = 2.0 * PI * (k as f64 + 0.5) / n as f64;
                c + Vector::new(t.cos(), t.sin()) * r
            })
            .collect()
    }

    #[test]
    fn a_single_panel_has_one_stagnation_point_where_the_closed_form_puts_it() {
        // A panel of length 2 across a unit stream with V = 1: λ = 2(U + V) = 4 (eq. 24) and
        // the flow stops at x* = −(L/2) cot(π / (2(1 + V/U))) = −1 on the axis (their
        // Figure 4(b): "(−1, 0)").
        let panel = Panel {
            start: Point::new(0.0, 1.0),
            end: Point::new(0.0, -1.0),
        };
        let field = PanelField::solve(vec![panel], &[1.0], Vector::new(1.0, 0.0), None).unwrap();
        assert!((field.paper_strengths()[0] + 4.0).abs() < 1e-12);
        let points = field.stagnation_points(&StagnationSearch::default());
        assert_eq!(points.len(), 1, "{points:?}");
        assert!(
            (points[0].at - Point::new(-1.0, 0.0)).norm() < 1e-7,
            "{points:?}"
        );
        assert_eq!(points[0].obstacle, Some(0));
    }

    #[test]
    fn a_disc_in_a_stream_has_its_stagnation_point_at_the_rankine_distance() {
        // Uniform flow U past a disc of radius R emitting V through its surface: on the axis
        // in front, U(1 − R²/x²) − V R/|x| = 0, so |x| = R (V/2U + √(V²/4U² + 1)); for
        // U = V = R = 1 the golden ratio. The constant-strength panels converge to it at first order
        // (3.0e-2, 1.6e-2, 8.5e-3 for 32, 64, 128 sides); the 256-gon is within 5e-3.
        let disc = ngon(Point::origin(), 1.0, 256);
        let setting = PublishedSetting {
            uniform_speed: 1.0,
            goal_strength: 1e-9,
            normal_velocity: 1.0,
            max_panel_length: f64::INFINITY,
        };
        // The goal sink far downstream and negligible.
        let field = PanelField::published(
            std::slice::from_ref(&disc),
            Point::new(-1e6, 0.0),
            Point::new(1e6, 0.0),
            &setting,
        )
        .unwrap();
        let points: Vec<_> = field
            .stagnation_points(&StagnationSearch::default())
            .into_iter()
            .filter(|s| s.obstacle == Some(0))
            .collect();
        assert_eq!(points.len(), 1, "{points:?}");
        let golden = (1.0 + 5f64.sqrt()) / 2.0;
        assert!((points[0].at.x + golden).abs() < 5e-3, "{points:?}");
        assert!(points[0].at.y.abs() < 1e-6);
        // λ_o = −∮ V ≈ −2π R V: a net source ...
        let s = field.lambda_o_check()[0];
        assert!((s.lambda_o + 2.0 * PI).abs() < 2e-2 * 2.0 * PI, "{s:?}");
        // ... which overwhelms a sink this weak (eq. 39's lower bound).
        assert_eq!(s.check, StrengthCheck::OverwhelmsGoal);
    }

    #[test]
    fn lambda_o_check_has_three_outcomes() {
        // A unit square 5 m upstream of the goal: λ_o ≈ −V × perimeter = −4V.
        let sq = vec![
            Point::new(4.0, 4.5),
            Point::new(5.0, 4.5),
            Point::new(5.0, 5.5),
            Point::new(4.0, 5.5),
        ];
        let check = |v: f64, lambda_g: f64| {
            let setting = PublishedSetting {
                normal_velocity: v,
                goal_strength: lambda_g,
                ..PublishedSetting::BAR_ROBOT
            };
            let f = PanelField::published(
                std::slice::from_ref(&sq),
                Point::new(0.0, 5.0),
                Point::new(10.0, 5.0),
                &setting,
            )
            .unwrap();
            f.lambda_o_check()[0]
        };
        let ok = check(0.5, 30.0);
        assert_eq!(ok.check, StrengthCheck::Satisfied);
        assert!((ok.lambda_o + 2.0).abs() < 0.3, "{ok:?}");
        assert_eq!(check(-0.2, 30.0).check, StrengthCheck::Attractive);
        assert_eq!(check(10.0, 30.0).check, StrengthCheck::OverwhelmsGoal);
    }

    #[test]
    fn published_fields_number_panels_in_vertex_order_with_outward_normals() {
        // A clockwise square: panels follow the vertices clockwise, normals still outward.
        let cw = vec![
            Point::new(0.0, 0.0),
            Point::new(0.0, 2.0),
            Point::new(2.0, 2.0),
            Point::new(2.0, 0.0),
        ];
        let setting = PublishedSetting {
            max_panel_length: 1.0,
            ..PublishedSetting::BAR_ROBOT
        };
        let f = PanelField::published(
            std::slice::from_ref(&cw),
            Point::new(-5.0, 1.0),
            Point::new(8.0, 1.0),
            &setting,
        )
        .unwrap();
        assert_eq!(f.panels().len(), 8);
        assert_eq!(f.panels()[0].midpoint(), Point::new(0.0, 0.5));
        assert_eq!(f.panels()[1].midpoint(), Point::new(0.0, 1.5));
        assert_eq!(f.panels()[2].midpoint(), Point::new(0.5, 2.0));
        for p in f.panels() {
            assert!(!polygon_contains(&cw, p.midpoint() + p.normal() * 1e-6));
            // V_i at every centre point.
            let c = p.midpoint() + p.normal() * 1e-9;
            assert!((f.velocity(c).dot(&p.normal()) - 0.5).abs() < 1e-6);
        }
        assert_eq!(f.obstacle_panels(), vec![0..8]);
    }

    #[test]
    fn the_remedy_raises_v_until_one_stagnation_point_remains() {
        // A square standing on a corner across the stream, one panel per side: with V small
        // the flow stops both in front of the leading corner and behind the trailing one
        // (two stagnation points, the second from stream entering between control points);
        // raising V blows the rear one away.
        let diamond = ngon(Point::origin(), 1.0, 4);
        let diamond: Vec<Point> = diamond
            .iter()
            .map(|p| {
                // ngon starts half a step round; turn it so a corner faces −x.
                let t = PI / 4.0;
                Point::new(p.x * t.cos() - p.y * t.sin(), p.x * t.sin() + p.y * t.cos())
            })
            .collect();
        assert!(
            diamond
                .iter()
                .any(|p| (p - Point::new(-1.0, 0.0)).norm() < 1e-12)
        );
        let setting = PublishedSetting {
            normal_velocity: 0.05,
            ..PublishedSetting::BAR_ROBOT
        };
        let (start, goal) = (Point::new(-8.0, 0.3), Point::new(6.0, 0.3));
        let remedy = Remedy {
            increase: 0.05,
            max_rounds: 10,
        };
        let out = PanelField::published_with_remedy(
            std::slice::from_ref(&diamond),
            start,
            goal,
            &setting,
            &StagnationSearch::default(),
            &remedy,
        )
        .unwrap();
        assert_eq!(out.outcome, RemedyOutcome::OneStagnationPointEach);
        assert_eq!(out.rounds[0].stagnation_counts, vec![2], "{:?}", out.rounds);
        let last = out.rounds.last().unwrap();
        assert_eq!(last.stagnation_counts, vec![1]);
        assert!(out.rounds.len() >= 2);
        // V rose by the increase each round.
        for (k, r) in out.rounds.iter().enumerate() {
            assert!((r.normal_velocities[0] - (0.05 + 0.05 * k as f64)).abs() < 1e-12);
        }
        // The one left is in front.
        let front: Vec<_> = out
            .stagnation_points
            .iter()
            .filter(|s| s.obstacle == Some(0))
            .collect();
        assert_eq!(front.len(), 1);
        assert!(front[0].at.x < -1.0, "{front:?}");
        // Giving up and breaking eq. 39 are reported, not looped on.
        let stingy = Remedy {
            increase: 0.01,
            max_rounds: 2,
        };
        let out = PanelField::published_with_remedy(
            std::slice::from_ref(&diamond),
            start,
            goal,
            &PublishedSetting {
                normal_velocity: 0.0,
                ..setting
            },
            &StagnationSearch::default(),
            &stingy,
        )
        .unwrap();
        assert!(
            matches!(
                out.outcome,
                RemedyOutcome::GaveUp | RemedyOutcome::StrengthOutOfBounds { .. }
            ),
            "{:?}",
            out.outcome
        );
        assert!(out.rounds.len() <= 3);
    }
}
