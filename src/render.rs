//! Pictures and exports: SVG of workspace, obstacles, goals, mesh, potential isolines and
//! paths; VTK (`.vtu`) for ParaView.
//!
//! The renderer takes plain geometry (rings of points, triangles, nodal values), so it draws
//! any planner's output the same way.

use std::fmt::Write as _;

use harmonic_mesh::{Mesh, Point, Vector};

/// What to draw.
#[derive(Default)]
pub struct Picture<'a> {
    /// Outer boundary rings of free space (workspace after cut-outs).
    pub workspace: Vec<Vec<Point>>,
    /// Obstacle rings (after merging and inflation).
    pub obstacles: Vec<Vec<Point>>,
    /// Shaded regions under everything else, each with its darkness in [0, 1] (a map's
    /// graded costs).
    pub shaded: Vec<(Vec<Point>, f64)>,
    /// Goal rings.
    pub goals: Vec<Vec<Point>>,
    /// The mesh, drawn thin when `show_mesh` is set, and the carrier of the isolines.
    pub mesh: Option<&'a Mesh>,
    /// Draw mesh edges.
    pub show_mesh: bool,
    /// ψ = φ_wall − φ at every mesh vertex (positive, 1 on the goal); isolines are drawn on a
    /// log scale of ψ where the field is flat.
    pub psi: Option<&'a [f64]>,
    /// log₁₀ ψ at every mesh vertex (−∞ where ψ = 0), for a ψ past the double range; when
    /// given, the isolines follow it (about 40 levels, evenly spaced in decades) instead of
    /// `psi`, and leave out the triangles touching ψ = 0 (where every level crowds in).
    pub log10_psi: Option<&'a [f64]>,
    /// Paths as polylines, each with a colour.
    pub paths: Vec<(Vec<Point>, &'static str)>,
    /// Car poses (x, y, θ) drawn as footprints of the given length and width.
    pub car_poses: Vec<Vec<[f64; 3]>>,
    /// Footprint length and width of the car.
    pub car_size: (f64, f64),
    /// A title in the corner.
    pub title: Option<String>,
}

/// Colours cycled through by paths.
pub const PATH_COLOURS: [&str; 6] = [
    "#d62728", "#1f77b4", "#9467bd", "#ff7f0e", "#17becf", "#8c564b",
];

impl Picture<'_> {
    /// Renders the picture as an SVG document about `width_px` pixels wide.
    pub fn to_svg(&self, width_px: f64) -> String {
        let (lo, hi) = self.bounds();
        let span = (hi - lo).map(|v| v.max(1e-12));
        let margin = 0.03 * span.x.max(span.y);
        let (x0, y0) = (lo.x - margin, lo.y - margin);
        let (w, h) = (span.x + 2.0 * margin, span.y + 2.0 * margin);
        let scale = width_px / w;
        let height_px = h * scale;
        // World y points up; SVG y points down: flip inside one group transform.
        let mut s = String::with_capacity(1 << 16);
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width_px:.0}" height="{height_px:.0}" viewBox="0 0 {width_px:.3} {height_px:.3}">"#
        );
        let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
        let _ = writeln!(
            s,
            r#"<g transform="matrix({scale} 0 0 {neg} {tx} {ty})" stroke-linejoin="round" stroke-linecap="round">"#,
            neg = -scale,
            tx = -x0 * scale,
            ty = (y0 + h) * scale,
        );
        let px = 1.0 / scale; // one pixel in world units
        let ring_path = |rings: &[Vec<Point>]| {
            let mut d = String::new();
            for r in rings {
                for (i, p) in r.iter().enumerate() {
                    let _ = write!(d, "{}{:.5} {:.5}", if i == 0 { "M" } else { "L" }, p.x, p.y);
                }
                d.push('Z');
            }
            d
        };
        // Free space, then holes over it.
        let _ = writeln!(
            s,
            r##"<path d="{}" fill="#f7f7f2" stroke="#222" stroke-width="{:.5}" fill-rule="evenodd"/>"##,
            ring_path(&self.workspace),
            1.5 * px
        );
        for (ring, darkness) in &self.shaded {
            let _ = writeln!(
                s,
                r##"<path d="{}" fill="#b5651d" fill-opacity="{:.3}" stroke="none"/>"##,
                ring_path(std::slice::from_ref(ring)),
                0.6 * darkness.clamp(0.0, 1.0)
            );
        }
        if let (Some(mesh), true) = (self.mesh, self.show_mesh) {
            let mut d = String::new();
            for (t, tri) in mesh.triangles().iter().enumerate() {
                for k in 0..3 {
                    // Each interior edge once: from the triangle with the smaller index.
                    let nb = mesh.neighbors()[t][k];
                    if nb != harmonic_mesh::NO_NEIGHBOR && (nb as usize) < t {
                        continue;
                    }
                    let a = mesh.vertices()[tri[(k + 1) % 3] as usize];
                    let b = mesh.vertices()[tri[(k + 2) % 3] as usize];
                    let _ = write!(d, "M{:.5} {:.5}L{:.5} {:.5}", a.x, a.y, b.x, b.y);
                }
            }
            let _ = writeln!(
                s,
                r##"<path d="{d}" fill="none" stroke="#9ab" stroke-width="{:.5}"/>"##,
                0.4 * px
            );
        }
        type Path = fn(&Mesh, &[f64], f64) -> String;
        let isolines = match (self.mesh, self.log10_psi, self.psi) {
            (Some(mesh), Some(log), _) => {
                Some((mesh, log, log_isoline_levels(log), log_isoline_path as Path))
            }
            (Some(mesh), None, Some(psi)) => {
                Some((mesh, psi, isoline_levels(psi), isoline_path as Path))
            }
            _ => None,
        };
        if let Some((mesh, values, levels, path)) = isolines {
            for (level, strong) in levels {
                let d = path(mesh, values, level);
                if !d.is_empty() {
                    let _ = writeln!(
                        s,
                        r##"<path d="{d}" fill="none" stroke="{}" stroke-width="{:.5}"/>"##,
                        if strong { "#4a7fb0" } else { "#9cc0de" },
                        if strong { 1.0 } else { 0.7 } * px
                    );
                }
            }
        }
        let _ = writeln!(
            s,
            r##"<path d="{}" fill="#555" stroke="#222" stroke-width="{:.5}" fill-rule="evenodd"/>"##,
            ring_path(&self.obstacles),
            1.0 * px
        );
        let _ = writeln!(
            s,
            r##"<path d="{}" fill="#2ca02c" stroke="#145214" stroke-width="{:.5}"/>"##,
            ring_path(&self.goals),
            1.0 * px
        );
        for (path, colour) in &self.paths {
            if let Some(first) = path.first() {
                let mut d = String::new();
                for (i, p) in path.iter().enumerate() {
                    let _ = write!(d, "{}{:.5} {:.5}", if i == 0 { "M" } else { "L" }, p.x, p.y);
                }
                let _ = writeln!(
                    s,
                    r#"<path d="{d}" fill="none" stroke="{colour}" stroke-width="{:.5}"/>"#,
                    2.0 * px
                );
                let _ = writeln!(
                    s,
                    r##"<circle cx="{:.5}" cy="{:.5}" r="{:.5}" fill="{colour}" stroke="#fff" stroke-width="{:.5}"/>"##,
                    first.x,
                    first.y,
                    4.0 * px,
                    1.0 * px
                );
            }
        }
        let (len, wid) = self.car_size;
        for (i, poses) in self.car_poses.iter().enumerate() {
            let colour = PATH_COLOURS[i % PATH_COLOURS.len()];
            let every = (poses.len() / 40).max(1);
            let mut d = String::new();
            let mut trail = String::new();
            for (k, q) in poses.iter().enumerate() {
                let _ = write!(
                    trail,
                    "{}{:.5} {:.5}",
                    if k == 0 { "M" } else { "L" },
                    q[0],
                    q[1]
                );
                if k % every == 0 || k + 1 == poses.len() {
                    for (j, c) in car_footprint(*q, len, wid).iter().enumerate() {
                        let _ =
                            write!(d, "{}{:.5} {:.5}", if j == 0 { "M" } else { "L" }, c.x, c.y);
                    }
                    d.push('Z');
                }
            }
            let _ = writeln!(
                s,
                r#"<path d="{trail}" fill="none" stroke="{colour}" stroke-width="{:.5}"/>"#,
                1.5 * px
            );
            let _ = writeln!(
                s,
                r#"<path d="{d}" fill="{colour}" fill-opacity="0.15" stroke="{colour}" stroke-width="{:.5}"/>"#,
                0.8 * px
            );
        }
        s.push_str("</g>\n");
        if let Some(title) = &self.title {
            let _ = writeln!(
                s,
                r##"<text x="8" y="18" font-family="sans-serif" font-size="14" fill="#222">{}</text>"##,
                xml_escape(title)
            );
        }
        s.push_str("</svg>\n");
        s
    }

    fn bounds(&self) -> (Vector, Vector) {
        let mut lo = Vector::new(f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        let rings = self
            .workspace
            .iter()
            .chain(&self.obstacles)
            .chain(&self.goals);
        for p in rings.flatten() {
            lo = lo.inf(&p.coords);
            hi = hi.sup(&p.coords);
        }
        if !lo.x.is_finite() {
            return (Vector::zeros(), Vector::new(1.0, 1.0));
        }
        (lo, hi)
    }
}

/// The four corners of a car footprint with its rear-axle midpoint at (x, y), heading θ.
/// The footprint reaches from a quarter of its length behind the rear axle to the front.
pub fn car_footprint(q: [f64; 3], length: f64, width: f64) -> [Point; 4] {
    let (s, c) = q[2].sin_cos();
    let fwd = Vector::new(c, s);
    let left = Vector::new(-s, c);
    let o = Point::new(q[0], q[1]);
    let back = -0.2 * length;
    let front = 0.8 * length;
    let half = 0.5 * width;
    [
        o + fwd * back - left * half,
        o + fwd * front - left * half,
        o + fwd * front + left * half,
        o + fwd * back + left * half,
    ]
}

/// Isoline levels of ψ with a flag for the stronger ones: linear steps of 0.1 near the goal,
/// then one per decade (and three per decade, lighter) down to the smallest positive ψ.
pub fn isoline_levels(psi: &[f64]) -> Vec<(f64, bool)> {
    let mut levels: Vec<(f64, bool)> = (1..10).map(|i| (i as f64 / 10.0, i % 5 == 0)).collect();
    let smallest = psi
        .iter()
        .copied()
        .filter(|&v| v > 0.0)
        .fold(f64::INFINITY, f64::min);
    if smallest.is_finite() {
        let lowest_decade = smallest.log10().floor().max(-300.0) as i32;
        let step = if lowest_decade < -60 {
            10
        } else if lowest_decade < -20 {
            3
        } else {
            1
        };
        let mut d = -2;
        while d >= lowest_decade {
            let strong = d % (5 * step) == 0;
            levels.push((10f64.powi(d), strong));
            if step == 1 && d > -20 {
                levels.push((10f64.powf(d as f64 + 0.5), false));
            }
            d -= step;
        }
        if d + step != lowest_decade && lowest_decade < -2 {
            levels.push((10f64.powi(lowest_decade), false));
        }
        levels.push((10f64.powf(-1.5), false));
    }
    levels
}

/// Isoline levels of log₁₀ ψ for a ψ past the double range: about 40 levels evenly spaced in
/// decades from the smallest value to 0 (a strong one every fifth), so a corridor of 1000
/// widths shows its exponential decay as evenly spaced lines.
pub fn log_isoline_levels(log10_psi: &[f64]) -> Vec<(f64, bool)> {
    let lowest = log10_psi
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::min);
    let step = (-lowest / 40.0).ceil().max(1.0);
    let mut levels = Vec::new();
    let mut k = 1;
    while -(k as f64) * step > lowest {
        levels.push((-(k as f64) * step, k % 5 == 0));
        k += 1;
    }
    levels
}

/// log₁₀ ψ with the −∞ of ψ = 0 (vertices held at the walls' value) replaced by one decade
/// below the smallest finite value, so pictures and VTK files get finite numbers.
pub fn floored_log10(log10_psi: &[f64]) -> Vec<f64> {
    let floor = log10_psi
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0, f64::min)
        - 1.0;
    log10_psi
        .iter()
        .map(|&v| if v.is_finite() { v } else { floor })
        .collect()
}

/// The levels below which [`isoline_path`] skips the triangles touching a wall held at ψ = 0.
pub const LOG_LEVELS_BELOW: f64 = 0.05;

/// The SVG path data of the level set ψ = level over a P1 field (marching triangles).
///
/// Below [`LOG_LEVELS_BELOW`] (the log-scale levels) a triangle with a vertex at ψ = 0 (on a
/// Dirichlet wall) is skipped: every small level crosses every such triangle, so each of
/// those isolines would trace the whole boundary a hair off the walls — nothing to see, and
/// on a large map megabytes per level.
pub fn isoline_path(mesh: &Mesh, psi: &[f64], level: f64) -> String {
    let skip_walls = level < LOG_LEVELS_BELOW;
    marching(mesh, psi, level, |vals| skip_walls && vals.contains(&0.0))
}

/// The SVG path data of the level set log₁₀ ψ = level over the P1 interpolant of log₁₀ ψ
/// (for a ψ past the double range): the triangles with a vertex at ψ = 0 (log₁₀ ψ = −∞, on a
/// Dirichlet wall) are skipped, for the reason [`isoline_path`] gives.
pub fn log_isoline_path(mesh: &Mesh, log10_psi: &[f64], level: f64) -> String {
    marching(mesh, log10_psi, level, |vals| {
        vals.iter().any(|v| !v.is_finite())
    })
}

/// Marching triangles over `values`, leaving out the triangles `skip` says.
fn marching(mesh: &Mesh, values: &[f64], level: f64, skip: impl Fn(&[f64; 3]) -> bool) -> String {
    let psi = values;
    let mut d = String::new();
    let v = mesh.vertices();
    for tri in mesh.triangles() {
        let ids = tri.map(|i| i as usize);
        let vals = ids.map(|i| psi[i]);
        if skip(&vals) {
            continue;
        }
        let mut pts = [Point::origin(); 2];
        let mut n = 0;
        for k in 0..3 {
            let (i, j) = (k, (k + 1) % 3);
            let (a, b) = (vals[i], vals[j]);
            if (a < level) != (b < level) && n < 2 {
                let t = (level - a) / (b - a);
                pts[n] = v[ids[i]] + (v[ids[j]] - v[ids[i]]) * t;
                n += 1;
            }
        }
        if n == 2 {
            let _ = write!(
                d,
                "M{:.5} {:.5}L{:.5} {:.5}",
                pts[0].x, pts[0].y, pts[1].x, pts[1].y
            );
        }
    }
    d
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// Writes the mesh with φ, ψ, log₁₀ ψ (finite: see [`floored_log10`]) and ∇φ at the vertices
/// as a VTK XML unstructured grid (`.vtu`), readable by ParaView.
pub fn to_vtu(
    mesh: &Mesh,
    phi: &[f64],
    psi: &[f64],
    log10_psi: &[f64],
    grad_phi: &[Vector],
) -> String {
    let mut s = String::with_capacity(64 * mesh.vertices().len() + 32 * mesh.triangles().len());
    let nv = mesh.vertices().len();
    let nt = mesh.triangles().len();
    let _ = writeln!(s, r#"<?xml version="1.0"?>"#);
    let _ = writeln!(
        s,
        r#"<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">"#
    );
    let _ = writeln!(
        s,
        "<UnstructuredGrid><Piece NumberOfPoints=\"{nv}\" NumberOfCells=\"{nt}\">"
    );
    s.push_str("<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for p in mesh.vertices() {
        let _ = writeln!(s, "{:e} {:e} 0", p.x, p.y);
    }
    s.push_str("</DataArray></Points>\n<Cells>\n");
    s.push_str("<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    for t in mesh.triangles() {
        let _ = writeln!(s, "{} {} {}", t[0], t[1], t[2]);
    }
    s.push_str("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    for i in 1..=nt {
        let _ = writeln!(s, "{}", 3 * i);
    }
    s.push_str("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for _ in 0..nt {
        s.push_str("5\n");
    }
    s.push_str("</DataArray>\n</Cells>\n<PointData Scalars=\"phi\" Vectors=\"grad_phi\">\n");
    for (name, vals) in [("phi", phi), ("psi", psi), ("log10_psi", log10_psi)] {
        let _ = writeln!(
            s,
            "<DataArray type=\"Float64\" Name=\"{name}\" format=\"ascii\">"
        );
        for v in vals {
            let _ = writeln!(s, "{v:e}");
        }
        s.push_str("</DataArray>\n");
    }
    s.push_str("<DataArray type=\"Float64\" Name=\"grad_phi\" NumberOfComponents=\"3\" format=\"ascii\">\n");
    for g in grad_phi {
        let _ = writeln!(s, "{:e} {:e} 0", g.x, g.y);
    }
    s.push_str("</DataArray>\n</PointData>\n</Piece></UnstructuredGrid></VTKFile>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use harmonic_mesh::BoundaryTag;

    fn square() -> Mesh {
        let v = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let b = [
            (0, 1, BoundaryTag::Wall),
            (1, 2, BoundaryTag::Wall),
            (2, 3, BoundaryTag::Goal(0)),
            (3, 0, BoundaryTag::Wall),
        ];
        Mesh::from_parts(v, vec![[0, 1, 2], [0, 2, 3]], &b).expect("valid")
    }

    #[test]
    fn isolines_cross_each_triangle_once_per_level() {
        let m = square();
        let psi = [0.0, 0.0, 1.0, 1.0];
        // ψ = y on this mesh: the level 0.5 crosses both triangles in one straight line.
        let d = isoline_path(&m, &psi, 0.5);
        assert_eq!(d.matches('M').count(), 2, "{d}");
        assert!(d.contains("0.50000"), "{d}");
        assert!(isoline_path(&m, &psi, 2.0).is_empty());
    }

    #[test]
    fn small_levels_do_not_trace_the_walls() {
        let m = square();
        // ψ = 0 on the bottom side, so every level crosses both triangles near it.
        let psi = [0.0, 0.0, 1.0, 1.0];
        assert_eq!(isoline_path(&m, &psi, 0.1).matches('M').count(), 2);
        assert!(isoline_path(&m, &psi, 1e-3).is_empty());
        // Off the walls the small levels are drawn.
        let psi = [1e-4, 1e-4, 1.0, 1.0];
        assert_eq!(isoline_path(&m, &psi, 1e-3).matches('M').count(), 2);
    }

    #[test]
    fn log_levels_reach_the_smallest_value() {
        let levels = isoline_levels(&[1e-40, 0.5, 1.0]);
        let lowest = levels.iter().map(|l| l.0).fold(f64::INFINITY, f64::min);
        assert!((1e-41..=1e-39).contains(&lowest), "{lowest}");
    }

    #[test]
    fn svg_and_vtu_are_well_formed() {
        let m = square();
        let psi = [0.0, 0.0, 1.0, 1.0];
        let pic = Picture {
            workspace: vec![m.vertices().to_vec()],
            mesh: Some(&m),
            show_mesh: true,
            psi: Some(&psi),
            paths: vec![(
                vec![Point::new(0.5, 0.1), Point::new(0.5, 0.9)],
                PATH_COLOURS[0],
            )],
            car_poses: vec![vec![[0.2, 0.2, 0.0], [0.3, 0.3, 0.5]]],
            car_size: (0.1, 0.05),
            title: Some("a < b".into()),
            ..Default::default()
        };
        let svg = pic.to_svg(400.0);
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt; b"));
        let vtu = to_vtu(
            &m,
            &[1.0, 1.0, 0.0, 0.0],
            &psi,
            &floored_log10(&psi.map(f64::log10)),
            &[Vector::new(0.0, -1.0); 4],
        );
        assert_eq!(
            vtu.matches("<DataArray").count(),
            vtu.matches("</DataArray>").count()
        );
        assert!(vtu.contains("NumberOfPoints=\"4\" NumberOfCells=\"2\""));
    }
}
