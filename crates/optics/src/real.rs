//! The scalar type every function of this crate is generic over.
//!
//! [`Real`] is implemented for `f64` (the reference) and `f32` (the precision the GPU
//! lighting pass works in). Each formula is written once, generically, so the f32 path is
//! *the same arrangement* as the f64 one and as the GLSL mirror in `shaders/include/`.
//!
//! Constants that enter formulas are written as `T::from_f64(0.45)`: for `f32` that is the
//! nearest `f32` to the decimal literal, the same value a GLSL `0.45` literal compiles to.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A floating-point scalar: `f32` or `f64`.
///
/// `max`/`min` follow IEEE 754 `maxNum`/`minNum` (as Rust's `f64::max`): if one operand
/// is NaN the other is returned. The crate relies on that to sanitise NaN inputs with
/// clamps (`x.max(lo).min(hi)` maps NaN to `lo`).
pub trait Real:
    Copy
    + Debug
    + Display
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Send
    + Sync
    + 'static
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 1/2.
    const HALF: Self;
    /// π.
    const PI: Self;
    /// 1/π.
    const FRAC_1_PI: Self;
    /// 2/π.
    const FRAC_2_PI: Self;
    /// 1/√2.
    const FRAC_1_SQRT_2: Self;
    /// Machine epsilon (distance from 1 to the next larger number).
    const EPSILON: Self;
    /// Largest finite value.
    const MAX: Self;

    /// The nearest value of this type to `x` (round to nearest even).
    fn from_f64(x: f64) -> Self;
    /// Exact widening (f32 → f64) or identity.
    fn to_f64(self) -> f64;
    /// Square root.
    fn sqrt(self) -> Self;
    /// eˣ.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// |x|.
    fn abs(self) -> Self;
    /// IEEE `maxNum`: the larger operand, or the non-NaN one.
    fn max(self, other: Self) -> Self;
    /// IEEE `minNum`: the smaller operand, or the non-NaN one.
    fn min(self, other: Self) -> Self;
    /// Four-quadrant arctangent of `self / x` (`self` is y), in [−π, π].
    fn atan2(self, x: Self) -> Self;
    /// tan x.
    fn tan(self) -> Self;
    /// cos x.
    fn cos(self) -> Self;
    /// sin x.
    fn sin(self) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// NaN.
    fn is_nan(self) -> bool;

    /// `self > 0`; false for NaN. The guards of this crate are written
    /// `if !x.is_positive() { return 0 }` so that NaN takes the early exit.
    #[inline]
    fn is_positive(self) -> bool {
        self > Self::ZERO
    }

    /// `self` limited to `[lo, hi]`; NaN maps to `lo` (see the trait docs).
    #[inline]
    fn clamp_to(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }

    /// `self` limited to `[0, 1]`; NaN maps to 0.
    #[inline]
    fn saturate(self) -> Self {
        self.clamp_to(Self::ZERO, Self::ONE)
    }

    /// `self²`.
    #[inline]
    fn sq(self) -> Self {
        self * self
    }
}

macro_rules! impl_real {
    ($t:ident) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const TWO: Self = 2.0;
            const HALF: Self = 0.5;
            const PI: Self = core::$t::consts::PI;
            const FRAC_1_PI: Self = core::$t::consts::FRAC_1_PI;
            const FRAC_2_PI: Self = core::$t::consts::FRAC_2_PI;
            const FRAC_1_SQRT_2: Self = core::$t::consts::FRAC_1_SQRT_2;
            const EPSILON: Self = $t::EPSILON;
            const MAX: Self = $t::MAX;

            #[inline]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline]
            fn sqrt(self) -> Self {
                $t::sqrt(self)
            }
            #[inline]
            fn exp(self) -> Self {
                $t::exp(self)
            }
            #[inline]
            fn ln(self) -> Self {
                $t::ln(self)
            }
            #[inline]
            fn abs(self) -> Self {
                $t::abs(self)
            }
            #[inline]
            fn max(self, other: Self) -> Self {
                $t::max(self, other)
            }
            #[inline]
            fn min(self, other: Self) -> Self {
                $t::min(self, other)
            }
            #[inline]
            fn atan2(self, x: Self) -> Self {
                $t::atan2(self, x)
            }
            #[inline]
            fn tan(self) -> Self {
                $t::tan(self)
            }
            #[inline]
            fn cos(self) -> Self {
                $t::cos(self)
            }
            #[inline]
            fn sin(self) -> Self {
                $t::sin(self)
            }
            #[inline]
            fn is_finite(self) -> bool {
                $t::is_finite(self)
            }
            #[inline]
            fn is_nan(self) -> bool {
                $t::is_nan(self)
            }
        }
    };
}

impl_real!(f32);
impl_real!(f64);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_f64_rounds_like_a_glsl_literal() {
        // A GLSL float literal is the nearest f32 to its decimal value; `as f32` is too.
        assert_eq!(<f32 as Real>::from_f64(0.45), 0.45_f32);
        assert_eq!(
            <f32 as Real>::from_f64(core::f64::consts::PI),
            core::f32::consts::PI
        );
        assert_eq!(<f64 as Real>::from_f64(0.1), 0.1);
    }

    #[test]
    fn clamps_map_nan_to_the_lower_bound() {
        assert_eq!(f32::NAN.saturate(), 0.0);
        assert_eq!(f64::NAN.clamp_to(2.0, 3.0), 2.0);
        assert_eq!(5.0_f64.clamp_to(2.0, 3.0), 3.0);
        assert_eq!(f64::NEG_INFINITY.saturate(), 0.0);
    }
}
