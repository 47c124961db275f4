//! Pictures: the workspace, the obstacles and the robot drawn at intervals along its motions
//! (the start in blue, the end in green, the poses between fading from one to the other),
//! with the trace of the reference point (a rigid robot's origin, an arm's tip).

use std::fmt::Write as _;

use crate::geometry::World;
use crate::robot::Robot;

/// Options of [`motion_svg`].
#[derive(Clone, Debug, PartialEq)]
pub struct MotionSvgOptions {
    /// Robot drawings per path (at equal shares of the path's sweep).
    pub frames: usize,
    /// Picture width in pixels.
    pub width: f64,
    /// A title.
    pub title: Option<String>,
}

impl Default for MotionSvgOptions {
    fn default() -> Self {
        MotionSvgOptions {
            frames: 14,
            width: 640.0,
            title: None,
        }
    }
}

fn poly(s: &mut String, pts: &[[f64; 2]], tf: &dyn Fn([f64; 2]) -> (f64, f64), style: &str) {
    let mut d = String::new();
    for p in pts {
        let (x, y) = tf(*p);
        let _ = write!(d, "{x:.2},{y:.2} ");
    }
    let tag = if pts.len() == 2 {
        "polyline"
    } else {
        "polygon"
    };
    let _ = writeln!(s, r#"<{tag} points="{}" {style}/>"#, d.trim_end());
}

/// The scene and the robot along `paths` (configurations), as SVG.
pub fn motion_svg(
    robot: &Robot,
    world: &World,
    paths: &[Vec<Vec<f64>>],
    goal_marker: Option<[f64; 2]>,
    opts: &MotionSvgOptions,
) -> String {
    let (lo, hi) = world.bounds();
    let (w, h) = (hi[0] - lo[0], hi[1] - lo[1]);
    let margin = 0.04 * w.max(h);
    let scale = opts.width / (w + 2.0 * margin);
    let height = (h + 2.0 * margin) * scale;
    let tf = move |p: [f64; 2]| {
        (
            (p[0] - lo[0] + margin) * scale,
            (hi[1] - p[1] + margin) * scale,
        )
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.2} {:.2}">"#,
        opts.width, height, opts.width, height
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    poly(
        &mut s,
        &world.workspace,
        &tf,
        r##"fill="#f7f7f2" stroke="#333" stroke-width="2""##,
    );
    for o in &world.obstacles {
        if let Some(ring) = &o.ring {
            poly(
                &mut s,
                ring,
                &tf,
                r##"fill="#9a9a9a" stroke="#555" stroke-width="1""##,
            );
        }
        if let Some((c, r)) = o.disc {
            let (x, y) = tf(c);
            let _ = writeln!(
                s,
                r##"<circle cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="#9a9a9a" stroke="#555"/>"##,
                r * scale
            );
        }
    }
    if let Some(g) = goal_marker {
        let (x, y) = tf(g);
        let _ = writeln!(
            s,
            r##"<circle cx="{x:.2}" cy="{y:.2}" r="5" fill="none" stroke="#1a8f3c" stroke-width="2"/>"##
        );
    }
    for path in paths {
        if path.is_empty() {
            continue;
        }
        // Cumulative sweep, to place the frames evenly along the motion.
        let mut acc = vec![0.0];
        for w in path.windows(2) {
            let last = acc[acc.len() - 1];
            acc.push(last + robot.sweep_bound(&w[0], &w[1]));
        }
        let total = acc[acc.len() - 1];
        let frames = opts.frames.max(2);
        for f in 0..frames {
            let target = total * f as f64 / (frames - 1) as f64;
            let i = acc.partition_point(|&a| a < target).min(path.len() - 1);
            let t = f as f64 / (frames - 1) as f64;
            let (r, g, b) = (
                (40.0 + t * 0.0) as u8,
                (90.0 + t * 70.0) as u8,
                (200.0 - t * 140.0) as u8,
            );
            let opacity = if f == 0 || f == frames - 1 { 0.9 } else { 0.35 };
            let style = format!(
                r##"fill="rgb({r},{g},{b})" fill-opacity="{opacity}" stroke="rgb({r},{g},{b})" stroke-width="{}""##,
                if matches!(robot, Robot::Arm(a) if a.width == 0.0) {
                    3
                } else {
                    1
                }
            );
            for outline in robot.outlines(&path[i]) {
                poly(&mut s, &outline, &tf, &style);
            }
        }
        let trace: Vec<[f64; 2]> = path
            .iter()
            .map(|q| match robot {
                Robot::Rigid(_) => [q[0], q[1]],
                Robot::Arm(a) => a.tip(q),
            })
            .collect();
        let mut d = String::new();
        for p in &trace {
            let (x, y) = tf(*p);
            let _ = write!(d, "{x:.2},{y:.2} ");
        }
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#d33" stroke-width="1.5"/>"##,
            d.trim_end()
        );
    }
    if let Some(t) = &opts.title {
        let t = t.replace('&', "&amp;").replace('<', "&lt;");
        let _ = writeln!(
            s,
            r##"<text x="8" y="18" font-family="sans-serif" font-size="14" fill="#222">{t}</text>"##
        );
    }
    s.push_str("</svg>\n");
    s
}
