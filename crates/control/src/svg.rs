//! Pictures of a controller run: the obstacles, the flow's streamlines, the robot drawn at
//! intervals along its motion (fading from blue at the start to green at the end), the
//! primary control point's trace, the stagnation points and the goal.

use std::fmt::Write as _;

use harmonic_mesh::{Point, Vector};

use crate::flow::{Flow, unit};
use crate::obstacles::Obstacles;

/// An SVG picture of a region of the plane (y up).
#[derive(Clone, Debug)]
pub struct Picture {
    lo: Point,
    hi: Point,
    scale: f64,
    body: String,
}

impl Picture {
    /// A picture of the box `lo`–`hi`, `width` pixels wide.
    pub fn new(lo: Point, hi: Point, width: f64) -> Self {
        let scale = width / (hi.x - lo.x).max(f64::MIN_POSITIVE);
        Picture {
            lo,
            hi,
            scale,
            body: String::new(),
        }
    }

    fn xy(&self, p: Point) -> (f64, f64) {
        (
            (p.x - self.lo.x) * self.scale,
            (self.hi.y - p.y) * self.scale,
        )
    }

    fn points(&self, pts: &[Point]) -> String {
        let mut s = String::new();
        for &p in pts {
            let (x, y) = self.xy(p);
            let _ = write!(s, "{x:.1},{y:.1} ");
        }
        s.trim_end().to_string()
    }

    /// The obstacles, filled grey.
    pub fn obstacles(&mut self, obstacles: &Obstacles) {
        for poly in obstacles.polygons() {
            let pts = self.points(poly);
            let _ = writeln!(
                self.body,
                r##"<polygon points="{pts}" fill="#9aa0a6" stroke="#3c4043" stroke-width="1"/>"##
            );
        }
    }

    /// Streamlines of `flow` from seeds along the picture's border (inset by 2 %), traced
    /// downstream at steps of 0.4 % of the width until they leave the picture, stop or reach
    /// `goal` (within `goal_radius`).
    pub fn streamlines(
        &mut self,
        flow: &dyn Flow,
        seeds_per_side: usize,
        goal: Point,
        goal_radius: f64,
    ) {
        let (w, h) = (self.hi.x - self.lo.x, self.hi.y - self.lo.y);
        let inset = 0.02 * w.max(h);
        let step = 0.004 * w.max(h);
        let mut seeds = Vec::new();
        for k in 0..seeds_per_side {
            let t = (k as f64 + 0.5) / seeds_per_side as f64;
            let x = self.lo.x + inset + t * (w - 2.0 * inset);
            let y = self.lo.y + inset + t * (h - 2.0 * inset);
            seeds.push(Point::new(x, self.lo.y + inset));
            seeds.push(Point::new(x, self.hi.y - inset));
            seeds.push(Point::new(self.lo.x + inset, y));
            seeds.push(Point::new(self.hi.x - inset, y));
        }
        let (lo, hi) = (self.lo, self.hi);
        let inside = |p: Point| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y;
        let max_steps = (4.0 * (w + h) / step) as usize;
        for seed in seeds {
            let mut line = vec![seed];
            let mut p = seed;
            for _ in 0..max_steps {
                // Midpoint rule on the unit direction.
                let Some(d1) = flow.velocity(p).and_then(unit) else {
                    break;
                };
                let mid = p + d1 * (0.5 * step);
                let Some(d2) = flow.velocity(mid).and_then(unit) else {
                    break;
                };
                if d1.dot(&d2) < 0.0 {
                    break; // a stagnation point
                }
                p += d2 * step;
                if !inside(p) || (p - goal).norm() < goal_radius {
                    break;
                }
                line.push(p);
            }
            if line.len() > 2 {
                self.polyline(
                    &line,
                    r##"fill="none" stroke="#8ab4f8" stroke-width="0.8""##,
                );
            }
        }
    }

    /// A polyline with the given SVG attributes.
    pub fn polyline(&mut self, pts: &[Point], style: &str) {
        let pts = self.points(pts);
        let _ = writeln!(self.body, r#"<polyline points="{pts}" {style}/>"#);
    }

    /// Robot drawings: each a polyline (a bar's two ends, an arm's joints), `frames` of them
    /// at equal intervals of the list, coloured from blue (first) to green (last).
    pub fn robot_frames(&mut self, bodies: &[Vec<Point>], frames: usize) {
        let n = bodies.len();
        if n == 0 {
            return;
        }
        let frames = frames.clamp(2, n.max(2));
        for f in 0..frames {
            let k = if frames == 1 {
                0
            } else {
                f * (n - 1) / (frames - 1)
            };
            let t = k as f64 / (n - 1).max(1) as f64;
            let (r, g, b) = (
                (26.0 + t * (52.0 - 26.0)) as u8,
                (115.0 + t * (168.0 - 115.0)) as u8,
                (232.0 + t * (83.0 - 232.0)) as u8,
            );
            let style = format!(
                r##"fill="none" stroke="#{r:02x}{g:02x}{b:02x}" stroke-width="3" stroke-linecap="round" stroke-linejoin="round" opacity="0.85""##
            );
            self.polyline(&bodies[k], &style);
            for &p in &bodies[k][..bodies[k].len().saturating_sub(1)] {
                let (x, y) = self.xy(p);
                let _ = writeln!(
                    self.body,
                    r##"<circle cx="{x:.1}" cy="{y:.1}" r="2.5" fill="#202124"/>"##
                );
            }
        }
    }

    /// A dot of `radius` pixels.
    pub fn dot(&mut self, p: Point, radius: f64, colour: &str) {
        let (x, y) = self.xy(p);
        let _ = writeln!(
            self.body,
            r#"<circle cx="{x:.1}" cy="{y:.1}" r="{radius}" fill="{colour}"/>"#
        );
    }

    /// A cross (a stagnation point).
    pub fn cross(&mut self, p: Point, colour: &str) {
        let d = 5.0 / self.scale;
        for (a, b) in [
            (Vector::new(-d, -d), Vector::new(d, d)),
            (Vector::new(-d, d), Vector::new(d, -d)),
        ] {
            self.polyline(
                &[p + a, p + b],
                &format!(r#"stroke="{colour}" stroke-width="2""#),
            );
        }
    }

    /// A caption at the top left.
    pub fn caption(&mut self, text: &str) {
        let escaped = text
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;");
        let _ = writeln!(
            self.body,
            r##"<text x="6" y="16" font-family="sans-serif" font-size="13" fill="#202124">{escaped}</text>"##
        );
    }

    /// The SVG document.
    pub fn finish(&self) -> String {
        let (w, h) = self.xy(Point::new(self.hi.x, self.lo.y));
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.1} {h:.1}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n{}</svg>\n",
            self.body
        )
    }
}
