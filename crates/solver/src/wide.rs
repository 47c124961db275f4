//! [`Wide`]: a real number with an `f64` mantissa and a separate `i32` binary exponent, for
//! quantities far outside the double range (ψ ≈ e^(−πL/w) in a corridor of L/w ≫ 230 widths
//! is 1e-1364 at 1000 widths).
//!
//! Every operation rounds once, as an `f64` operation does (the exponent is exact), so an
//! error analysis written for floating point carries over with the range restriction removed.
//! The extended LDLᵀ ([`crate::WideLdlt`]) is the only user in this crate; the FEM potential
//! keeps ψ in this form where it leaves the double range.

use std::cmp::Ordering;
use std::ops::{Add, AddAssign, Div, Mul, MulAssign};

/// A real number `m · 2^e` with `1 ≤ |m| < 2` (or `m = 0`, `e = 0`): an unbounded-range float.
///
/// ```
/// use harmonic_solver::Wide;
/// let tiny = Wide::from_f64(1e-300);
/// let product = tiny * tiny * tiny; // 1e-900: no f64 holds it
/// assert!((product.log10() + 900.0).abs() < 1e-12);
/// assert_eq!(product.to_f64(), 0.0); // underflows on the way out
/// assert!(((product / (tiny * tiny)).to_f64() / 1e-300 - 1.0).abs() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Wide {
    m: f64,
    e: i32,
}

/// Exponent differences beyond which the smaller addend is below half an ulp of the larger.
const ALIGN_LIMIT: i64 = 60;

/// `2^k` for `k` in the normal exponent range `[-1022, 1023]`.
#[inline]
fn pow2(k: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&k));
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// Splits a finite non-zero `x` into `(m, e)` with `1 ≤ |m| < 2`, `x = m · 2^e`.
#[inline]
fn split(x: f64) -> (f64, i32) {
    let (x, shift) = if x.abs() < f64::MIN_POSITIVE {
        (x * pow2(64), -64)
    } else {
        (x, 0)
    };
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let m = f64::from_bits((bits & !(0x7ff << 52)) | (1023 << 52));
    (m, biased - 1023 + shift)
}

/// Clamps an exponent computed in `i64` into `i32` (values beyond are ±infinity or zero in
/// every practical sense: 2^(±2³¹)).
#[inline]
fn clamp_exponent(e: i64) -> i32 {
    e.clamp(i32::MIN as i64 / 2, i32::MAX as i64 / 2) as i32
}

impl Wide {
    /// Zero.
    pub const ZERO: Wide = Wide { m: 0.0, e: 0 };
    /// One.
    pub const ONE: Wide = Wide { m: 1.0, e: 0 };

    /// The value of a finite `f64` (non-finite input gives zero; callers validate first).
    #[inline]
    pub fn from_f64(x: f64) -> Wide {
        if x == 0.0 || !x.is_finite() {
            return Wide::ZERO;
        }
        let (m, e) = split(x);
        Wide { m, e }
    }

    /// `mantissa · 2^exponent` for any finite mantissa (normalised here).
    #[inline]
    pub fn from_parts(mantissa: f64, exponent: i32) -> Wide {
        if mantissa == 0.0 || !mantissa.is_finite() {
            return Wide::ZERO;
        }
        let (m, e) = split(mantissa);
        Wide {
            m,
            e: clamp_exponent(e as i64 + exponent as i64),
        }
    }

    /// `2^x` for a finite `x` (e.g. from a logarithm: `Wide::exp2(k · log2 λ)` is `λ^k`).
    pub fn exp2(x: f64) -> Wide {
        if !x.is_finite() {
            return if x > 0.0 {
                Wide::from_parts(1.0, i32::MAX / 2)
            } else {
                Wide::ZERO
            };
        }
        let k = x.floor();
        Wide::from_parts((x - k).exp2(), clamp_exponent(k as i64))
    }

    /// The mantissa `m` (`1 ≤ |m| < 2`, or 0).
    #[inline]
    pub fn mantissa(self) -> f64 {
        self.m
    }

    /// The binary exponent `e` (0 for zero).
    #[inline]
    pub fn exponent(self) -> i32 {
        self.e
    }

    /// |self|.
    #[inline]
    pub fn abs(self) -> Wide {
        Wide {
            m: self.m.abs(),
            e: self.e,
        }
    }

    /// Whether the value is zero.
    #[inline]
    pub fn is_zero(self) -> bool {
        self.m == 0.0
    }

    /// The nearest `f64`: underflows to (signed) zero below 2^-1074, overflows to ±infinity.
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.scaled(0)
    }

    /// `self · 2^(−exponent)` as an `f64` (zero if that underflows): the value on the scale of
    /// another number with the given exponent, e.g. a triangle's largest.
    #[inline]
    pub fn scaled(self, exponent: i32) -> f64 {
        if self.m == 0.0 {
            return 0.0;
        }
        let k = self.e as i64 - exponent as i64;
        if k > 1023 {
            self.m * f64::INFINITY
        } else if k >= -1022 {
            self.m * pow2(k as i32)
        } else if k >= -1022 - 54 {
            // Subnormal: one rounding, in the second product.
            self.m * pow2(-1022) * pow2((k + 1022) as i32)
        } else {
            self.m * 0.0
        }
    }

    /// log₂ |self| (−∞ for zero).
    #[inline]
    pub fn log2(self) -> f64 {
        if self.m == 0.0 {
            f64::NEG_INFINITY
        } else {
            self.m.abs().log2() + self.e as f64
        }
    }

    /// log₁₀ |self| (−∞ for zero).
    #[inline]
    pub fn log10(self) -> f64 {
        self.log2() * std::f64::consts::LOG10_2
    }

    /// ln |self| (−∞ for zero).
    #[inline]
    pub fn ln(self) -> f64 {
        if self.m == 0.0 {
            f64::NEG_INFINITY
        } else {
            self.m.abs().ln() + self.e as f64 * std::f64::consts::LN_2
        }
    }

    /// Renormalises a mantissa that left `[1, 2)` after one operation.
    #[inline]
    fn renormalised(m: f64, e: i64) -> Wide {
        let a = m.abs();
        if (1.0..2.0).contains(&a) {
            Wide {
                m,
                e: clamp_exponent(e),
            }
        } else if (2.0..4.0).contains(&a) {
            Wide {
                m: m * 0.5,
                e: clamp_exponent(e + 1),
            }
        } else if m == 0.0 {
            Wide::ZERO
        } else {
            let (mm, k) = split(m);
            Wide {
                m: mm,
                e: clamp_exponent(e + k as i64),
            }
        }
    }
}

impl Add for Wide {
    type Output = Wide;
    #[inline]
    fn add(self, rhs: Wide) -> Wide {
        if rhs.m == 0.0 {
            return self;
        }
        if self.m == 0.0 {
            return rhs;
        }
        let (big, small) = if self.e >= rhs.e {
            (self, rhs)
        } else {
            (rhs, self)
        };
        let d = big.e as i64 - small.e as i64;
        if d > ALIGN_LIMIT {
            return big;
        }
        Wide::renormalised(big.m + small.m * pow2(-(d as i32)), big.e as i64)
    }
}

impl AddAssign for Wide {
    #[inline]
    fn add_assign(&mut self, rhs: Wide) {
        *self = *self + rhs;
    }
}

impl Mul for Wide {
    type Output = Wide;
    #[inline]
    fn mul(self, rhs: Wide) -> Wide {
        if self.m == 0.0 || rhs.m == 0.0 {
            return Wide::ZERO;
        }
        Wide::renormalised(self.m * rhs.m, self.e as i64 + rhs.e as i64)
    }
}

impl MulAssign for Wide {
    #[inline]
    fn mul_assign(&mut self, rhs: Wide) {
        *self = *self * rhs;
    }
}

impl Div for Wide {
    type Output = Wide;
    /// Division; dividing by zero gives ±infinity in the mantissa (callers check pivots).
    #[inline]
    fn div(self, rhs: Wide) -> Wide {
        if self.m == 0.0 {
            return Wide::ZERO;
        }
        let m = self.m / rhs.m;
        if !m.is_finite() {
            return Wide { m, e: 0 };
        }
        let e = self.e as i64 - rhs.e as i64;
        if (1.0..2.0).contains(&m.abs()) {
            Wide {
                m,
                e: clamp_exponent(e),
            }
        } else {
            Wide::renormalised(m * 2.0, e - 1)
        }
    }
}

impl PartialOrd for Wide {
    fn partial_cmp(&self, other: &Wide) -> Option<Ordering> {
        if self.m.is_nan() || other.m.is_nan() {
            return None;
        }
        let sign = |w: &Wide| {
            if w.m > 0.0 {
                1
            } else if w.m < 0.0 {
                -1
            } else {
                0
            }
        };
        let (sa, sb) = (sign(self), sign(other));
        if sa != sb || sa == 0 {
            return sa.partial_cmp(&sb);
        }
        let magnitude = self
            .e
            .cmp(&other.e)
            .then(self.m.abs().total_cmp(&other.m.abs()));
        Some(if sa > 0 {
            magnitude
        } else {
            magnitude.reverse()
        })
    }
}

impl From<f64> for Wide {
    fn from(x: f64) -> Wide {
        Wide::from_f64(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_normal_and_subnormal_floats() {
        for x in [
            1.0,
            -3.5,
            1e-300,
            4.9e-324,
            2.2e-308,
            1e300,
            f64::MAX,
            -1e-320,
        ] {
            assert_eq!(Wide::from_f64(x).to_f64(), x, "{x:e}");
        }
        assert_eq!(Wide::from_f64(0.0), Wide::ZERO);
    }

    #[test]
    fn arithmetic_matches_f64_in_range() {
        let xs = [1.0, 3.0, 0.1, 7.25e-5, 123456.789, 2.0f64.powi(-40)];
        for &a in &xs {
            for &b in &xs {
                let (wa, wb) = (Wide::from_f64(a), Wide::from_f64(b));
                assert_eq!((wa + wb).to_f64(), a + b);
                assert_eq!((wa * wb).to_f64(), a * b);
                assert_eq!((wa / wb).to_f64(), a / b);
                assert_eq!(wa.partial_cmp(&wb), a.partial_cmp(&b));
            }
        }
    }

    #[test]
    fn far_below_the_double_range() {
        let t = Wide::from_f64(1e-200);
        let x = t * t * t * t * t; // 1e-1000
        assert!((x.log10() + 1000.0).abs() < 1e-12);
        assert_eq!(x.to_f64(), 0.0);
        // Adding a much smaller number changes nothing; a comparable one adds.
        assert_eq!(x + x * t, x);
        assert!(((x + x).log2() - x.log2() - 1.0).abs() < 1e-15);
        assert!(x * t < x && Wide::ZERO < x * t);
        // Rescaled by its own exponent it is an ordinary number.
        assert!((1.0..2.0).contains(&x.scaled(x.exponent())));
        assert!((Wide::exp2(-3000.5).log2() + 3000.5).abs() < 1e-12);
    }

    #[test]
    fn signs_and_cancellation() {
        let a = Wide::from_f64(-2.5);
        assert_eq!((a + Wide::from_f64(2.5)).to_f64(), 0.0);
        assert_eq!((a * a).to_f64(), 6.25);
        assert!(a < Wide::ZERO && a < Wide::from_f64(-1.0));
    }
}
