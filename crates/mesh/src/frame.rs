//! The unit frame: every scene is meshed in coordinates of about unit size.
//!
//! [`Domain::new`](crate::Domain::new) maps the scene by `u = (p − offset) / scale`, with
//! `offset` the lower-left corner of the workspace's bounding box and `scale` a tenth of its
//! larger side, so the unit scene fills `[0, 10]` along its larger side whatever the scene's
//! units and position (sides of about 10: the size the bundled reference scene already has,
//! which the map therefore leaves exactly as it is). A scene scaled by any factor and moved
//! by any offset gives the same unit scene up to the rounding of its own coordinates, and so
//! the same mesh, scaled. (The triangulator is not equivariant under scaling by itself:
//! spade splits constraint edges at power-of-two lengths in absolute terms, so without the
//! unit frame a scene at 1e6 gets another mesh than at 1.)
//!
//! Every tolerance of the domain and the mesher (snapping, collinearity, the triangulator's
//! coordinate range) is therefore relative to the scene's size, and spade never sees a
//! coordinate too small or too large for it. The mesh is handed back in the user's
//! coordinates; [`Frame::check_user_mesh`] refuses, in one line, a scene whose triangles
//! would not be representable there (areas below f64's normal range, or overflowing).

use crate::{MeshError, Point};

/// Unit coordinates whose magnitude is below this are set to zero: a vertex 2^-200 of the
/// scene's size from an axis is on it for every purpose of meshing, and spade refuses
/// non-zero coordinates below about 1e-43.
const FLUSH: f64 = 1.0 / (1u128 << 100) as f64 / (1u128 << 100) as f64;

/// The most decimals an input coordinate is rounded to in the unit frame.
const MAX_DECIMALS: i32 = 12;

/// The most significant decimal digits an input length or area is rounded to.
const MAX_DIGITS: usize = 15;

/// `v` as the shortest decimal with at most [`MAX_DECIMALS`] decimals within `tol` of it
/// (as its nearest double, which is the double of the decimal literal); `v` if none is.
fn shortest_decimal(v: f64, tol: f64) -> f64 {
    if !v.is_finite() {
        return v;
    }
    let mut ten = 1.0;
    for _ in 0..=MAX_DECIMALS {
        let n = round_half_away(v * ten);
        if n.abs() >= 9e15 {
            break;
        }
        let q = n / ten;
        if (q - v).abs() <= tol {
            return q;
        }
        ten *= 10.0;
    }
    v
}

/// `x.round()` without a call into libm (the baseline x86-64 target has no rounding
/// instruction, and [`shortest_decimal`] rounds up to 13 times per coordinate): the same
/// value wherever `|x| < 2^63`; beyond, ±2^63, which is as far past [`shortest_decimal`]'s
/// limit.
fn round_half_away(x: f64) -> f64 {
    let t = x as i64 as f64; // truncated toward zero, exact below 2^63
    let f = x - t; // exact: t is x without its fraction bits
    if f >= 0.5 {
        t + 1.0
    } else if f <= -0.5 {
        t - 1.0
    } else {
        t
    }
}

/// `v` with the fewest significant decimal digits (at most [`MAX_DIGITS`]) within the
/// relative tolerance `rel`; `v` if none is.
fn fewest_digits(v: f64, rel: f64) -> f64 {
    if !v.is_finite() || v == 0.0 {
        return v;
    }
    for digits in 1..=MAX_DIGITS {
        if let Ok(q) = format!("{:.*e}", digits - 1, v).parse::<f64>()
            && (q - v).abs() <= rel * v.abs()
        {
            return q;
        }
    }
    v
}

/// The larger side of the workspace in unit coordinates.
pub const UNIT_SIDE: f64 = 10.0;

/// A similarity `u = (p − offset) / scale` onto coordinates of unit size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// A tenth of the workspace's larger bounding-box side (10 units of the unit
    /// scene are the larger side).
    pub scale: f64,
    /// The lower-left corner of the workspace's bounding box.
    pub offset: Point,
    /// `(|lo| + |hi|) / scale` (largest coordinates of the bounding-box corners): how much
    /// rounding the map adds to what it maps, in units of ε.
    spread: f64,
}

impl Frame {
    /// The identity (scale 1, no offset).
    pub fn identity() -> Frame {
        Frame {
            scale: 1.0,
            offset: Point::new(0.0, 0.0),
            spread: 0.0,
        }
    }

    /// The frame of a workspace polygon (its finite vertices); the identity if it has no
    /// extent (validation then refuses it).
    pub fn of(points: &[Point]) -> Frame {
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in points.iter().filter(|p| p.x.is_finite() && p.y.is_finite()) {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        // Halves, so that a side spanning most of f64's range does not overflow.
        let half = (0.5 * hi.x - 0.5 * lo.x).max(0.5 * hi.y - 0.5 * lo.y);
        if !(half.is_finite() && half > 0.0) {
            return Frame::identity();
        }
        let far = lo.x.abs().max(lo.y.abs()) + hi.x.abs().max(hi.y.abs());
        let scale = half / (0.5 * UNIT_SIDE);
        Frame {
            scale,
            offset: lo,
            spread: far / scale,
        }
    }

    /// Whether this is the identity.
    pub fn is_identity(&self) -> bool {
        self.scale == 1.0 && self.offset == Point::new(0.0, 0.0)
    }

    /// An input vertex in unit coordinates, each coordinate as its shortest decimal (at most
    /// 12 decimals) within the rounding error of the map. A coordinate written as such a
    /// decimal in the unit frame stays exactly as it is, and the same coordinate met through
    /// another scale or offset, a rounding error away, is rounded back onto it: the unit scene
    /// is the same bit for bit, and so is its mesh (spade's decisions can flip on a
    /// difference in the last bit).
    pub fn input_to_unit(&self, p: Point) -> Point {
        let u = self.to_unit(p);
        // The rounding of p itself and of lo (half an ulp each), of p − lo and of the
        // division (half an ulp of u each) and of the scale (relative ε·spread/20), with a
        // margin of 1.5.
        let lo = self.offset.x.abs().max(self.offset.y.abs()) / self.scale;
        let tol = |user: f64, unit: f64| {
            1.5 * f64::EPSILON
                * (0.5 * user.abs() / self.scale
                    + 0.5 * lo
                    + unit.abs() * (1.0 + self.spread / 20.0))
        };
        Point::new(
            shortest_decimal(u.x, tol(p.x, u.x)),
            shortest_decimal(u.y, tol(p.y, u.y)),
        )
    }

    /// An input length in unit coordinates, as its fewest significant decimal digits within
    /// the rounding error of the map.
    pub fn input_len_to_unit(&self, l: f64) -> f64 {
        fewest_digits(self.len_to_unit(l), self.length_noise())
    }

    /// An input area in unit coordinates, likewise.
    pub fn input_area_to_unit(&self, a: f64) -> f64 {
        fewest_digits(self.area_to_unit(a), 2.0 * self.length_noise())
    }

    /// The relative rounding error of a length mapped to the unit frame.
    fn length_noise(&self) -> f64 {
        1.5 * f64::EPSILON * (2.0 + self.spread / 20.0)
    }

    /// A user point in unit coordinates.
    pub fn to_unit(&self, p: Point) -> Point {
        let f = |v: f64, o: f64| {
            let u = (v - o) / self.scale;
            if u.abs() < FLUSH { 0.0 } else { u }
        };
        Point::new(f(p.x, self.offset.x), f(p.y, self.offset.y))
    }

    /// A unit point in user coordinates.
    pub fn to_user(&self, u: Point) -> Point {
        Point::new(
            u.x * self.scale + self.offset.x,
            u.y * self.scale + self.offset.y,
        )
    }

    /// A user length in unit coordinates.
    pub fn len_to_unit(&self, l: f64) -> f64 {
        l / self.scale
    }

    /// A unit length in user coordinates.
    pub fn len_to_user(&self, l: f64) -> f64 {
        l * self.scale
    }

    /// A user area in unit coordinates.
    pub fn area_to_unit(&self, a: f64) -> f64 {
        a / self.scale / self.scale
    }

    /// A unit area in user coordinates.
    pub fn area_to_user(&self, a: f64) -> f64 {
        a * self.scale * self.scale
    }

    /// Refuses a mesh whose smallest unit edge `min_edge` (and whose unit extent, about 1)
    /// cannot be represented in user coordinates: triangle areas (products of two edges)
    /// must stay within f64's normal range, and so must the squared extent.
    pub fn check_user_mesh(&self, min_edge: f64) -> Result<(), MeshError> {
        let edge = self.len_to_user(min_edge);
        let far = self.offset.x.abs().max(self.offset.y.abs()) + self.scale;
        if edge * edge < 1e4 * f64::MIN_POSITIVE || !(far * far).is_finite() {
            return Err(MeshError::ScaleOutOfRange {
                size: self.scale,
                edge,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_without_libm_is_rounding() {
        let mut cases = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -2.5,
            0.49999999999999994,
            4503599627370495.5,
        ];
        cases.extend([
            2f64.powi(52),
            2f64.powi(53) + 2.0,
            9e15,
            -9.1e15,
            1e300,
            -1e300,
        ]);
        // A spread of magnitudes and fractions, halves included.
        for k in 0..2000 {
            let x = (k as f64 * 0.3711 - 300.0) * 10f64.powi(k % 17 - 4);
            cases.extend([x, x.trunc() + 0.5, -x.trunc() - 0.5]);
        }
        for x in cases {
            let (ours, libm) = (round_half_away(x), x.round());
            if x.abs() < 2f64.powi(63) {
                assert_eq!(
                    ours.to_bits() & !(1 << 63),
                    libm.to_bits() & !(1 << 63),
                    "{x}"
                );
            } else {
                assert!(ours.abs() >= 9e15 && ours.signum() == x.signum(), "{x}");
            }
        }
    }

    #[test]
    fn the_unit_scene_starts_at_the_origin_with_side_ten() {
        for (side, at) in [
            (1.0, 0.0),
            (10.0, 5.0),
            (1e-150, 3e-148),
            (3e150, -1e153),
            (0.75, 1e6),
        ] {
            let pts = [Point::new(at, at), Point::new(at + side, at + 0.5 * side)];
            let f = Frame::of(&pts);
            let (u0, u1) = (f.to_unit(pts[0]), f.to_unit(pts[1]));
            assert_eq!(u0, Point::new(0.0, 0.0));
            assert!(
                (u1.x - 10.0).abs() < 1e-12 && (u1.y - 5.0).abs() < 1e-12,
                "{u1:?}"
            );
            let back = f.to_user(u1);
            assert!(
                (back - pts[1]).norm() <= 1e-12 * (side + at.abs()),
                "{back:?}"
            );
        }
    }

    #[test]
    fn scales_and_offsets_give_the_same_unit_scene() {
        let base = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(4.0, 7.1),
        ];
        let unit = |s: f64, o: f64| {
            let pts: Vec<Point> = base
                .iter()
                .map(|p| Point::new(p.x * s + o, p.y * s + o))
                .collect();
            let f = Frame::of(&pts);
            pts.iter().map(|&p| f.to_unit(p)).collect::<Vec<_>>()
        };
        let reference = unit(1.0, 0.0);
        for (s, o) in [(1e-150, 0.0), (1e-6, 3e-5), (1e6, -2e7), (1e150, 1e151)] {
            for (a, b) in reference.iter().zip(unit(s, o)) {
                assert!((*a - b).norm() < 1e-12, "{s} {o}: {a:?} {b:?}");
            }
        }
    }

    #[test]
    fn a_scene_in_the_unit_frame_is_left_exactly_as_it_is() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(0.2, 7.1),
        ];
        let f = Frame::of(&pts);
        assert!(f.is_identity(), "{f:?}");
    }

    #[test]
    fn tiny_unit_coordinates_are_flushed_to_zero() {
        let f = Frame::identity();
        assert_eq!(f.to_unit(Point::new(1e-70, 0.5)), Point::new(0.0, 0.5));
    }

    #[test]
    fn decimal_inputs_are_kept_and_their_rounding_at_other_scales_undone() {
        let f = Frame::identity();
        for v in [
            0.2,
            7.1,
            8.638581929877,
            std::f64::consts::FRAC_1_SQRT_2,
            1e-3,
        ] {
            assert_eq!(
                f.input_to_unit(Point::new(v, v)).x.to_bits(),
                v.to_bits(),
                "{v}"
            );
        }
        let pts = |s: f64, o: f64| [Point::new(o, o), Point::new(10.0 * s + o, 10.0 * s + o)];
        for (s, o) in [(1e-6, 3e-5), (1e6, -2e8), (1e-150, 0.0)] {
            let f = Frame::of(&pts(s, o));
            for v in [0.2, 7.1, 8.638581929877] {
                let u = f.input_to_unit(Point::new(v * s + o, v * s + o));
                assert_eq!(u.x.to_bits(), v.to_bits(), "{s} {o} {v}: {}", u.x);
            }
            assert_eq!(f.input_area_to_unit(0.0044 * s * s), 0.0044, "{s}");
        }
    }
}
