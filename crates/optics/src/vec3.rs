//! A minimal 3-vector and the orthonormal shading frame.

use crate::real::Real;
use core::ops::{Add, Mul, Neg, Sub};

/// A 3-vector of [`Real`]s.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3<T> {
    /// x component (tangent direction in the shading frame).
    pub x: T,
    /// y component (bitangent direction in the shading frame).
    pub y: T,
    /// z component (normal direction in the shading frame).
    pub z: T,
}

impl<T: Real> Vec3<T> {
    /// `(x, y, z)`.
    #[inline]
    pub const fn new(x: T, y: T, z: T) -> Self {
        Self { x, y, z }
    }

    /// The zero vector.
    #[inline]
    pub fn zero() -> Self {
        Self::new(T::ZERO, T::ZERO, T::ZERO)
    }

    /// Components converted to another [`Real`] (nearest value).
    #[inline]
    pub fn convert<U: Real>(self) -> Vec3<U> {
        Vec3::new(
            U::from_f64(self.x.to_f64()),
            U::from_f64(self.y.to_f64()),
            U::from_f64(self.z.to_f64()),
        )
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: Self) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product `self × o`.
    #[inline]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// |self|².
    #[inline]
    pub fn length_squared(self) -> T {
        self.dot(self)
    }

    /// |self|.
    #[inline]
    pub fn length(self) -> T {
        self.length_squared().sqrt()
    }

    /// `self / |self|`, or the zero vector when |self|² is 0, subnormal-underflowed,
    /// infinite or NaN. Never produces NaN. (GLSL: `safe_normalize`.)
    #[inline]
    pub fn normalize(self) -> Self {
        let l2 = self.length_squared();
        if l2 > T::ZERO && l2.is_finite() {
            self * (T::ONE / l2.sqrt())
        } else {
            Self::zero()
        }
    }

    /// The component of `self` orthogonal to the unit vector `n`, `self − n (n·self)`.
    #[inline]
    pub fn reject_from(self, n: Self) -> Self {
        self - n * n.dot(self)
    }
}

impl<T: Real> Add for Vec3<T> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl<T: Real> Sub for Vec3<T> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl<T: Real> Neg for Vec3<T> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl<T: Real> Mul<T> for Vec3<T> {
    type Output = Self;
    #[inline]
    fn mul(self, s: T) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// The shading normal `n` made to face the unit direction to the eye `v`: unchanged
/// where n·v ≥ [`FACING_COS_MIN`](crate::FACING_COS_MIN), else turned towards `v` in the
/// plane of `n` and `v` just until n·v = `FACING_COS_MIN` (continuous at the threshold,
/// unit length). A normal exactly opposite `v` (no plane) turns towards an arbitrary
/// direction across `v`. Apply it after a double-sided material's back faces are
/// reversed, and build the tangent frame from the result ([`ShadingFrame::new`]
/// re-orthogonalises the tangent). GLSL: `facing_view` in brdf.glsl.
pub fn facing_view<T: Real>(n: Vec3<T>, v: Vec3<T>) -> Vec3<T> {
    let c_min = T::from_f64(crate::FACING_COS_MIN);
    let c = n.dot(v);
    if c >= c_min {
        return n;
    }
    // n's part across v, projected twice (Gram–Schmidt) so that it stays orthogonal to
    // v to rounding when n is nearly opposite v.
    let across = n - v * c;
    let across = across - v * v.dot(across);
    let across2 = across.length_squared();
    let across = if across2 > T::from_f64(1e-20) && across2.is_finite() {
        across * (T::ONE / across2.sqrt())
    } else {
        ShadingFrame::basis_from_normal(v)
    };
    v * c_min + across * (T::ONE - c_min * c_min).sqrt()
}

/// A tangent whose component orthogonal to the normal is shorter than this fraction of
/// its length, squared (|t⊥|² ≤ 1e-6 |t|², i.e. t within 0.057° of ±n), carries no usable
/// direction; [`ShadingFrame::new`] then falls back to the bitangent, then to a frame
/// built from the normal alone.
pub const TANGENT_DEGENERATE_FRACTION_SQ: f64 = 1.0e-6;

/// An orthonormal shading frame: `t` (x, tangent), `b` (y, bitangent), `n` (z, normal).
///
/// All microfacet and diffuse functions of this crate take directions *in this frame*
/// ("local" vectors): n·m = m.z, t·m = m.x, b·m = m.y, and |n × m|² = m.x² + m.y²
/// exactly, which is how the crate avoids forming 1 − (n·m)² (seed-notes, hard cases).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingFrame<T> {
    /// Unit tangent (x axis), orthogonal to `n`.
    pub t: Vec3<T>,
    /// Unit bitangent (y axis), `n × t`.
    pub b: Vec3<T>,
    /// Unit normal (z axis), or zero if the given normal was zero/non-finite.
    pub n: Vec3<T>,
}

impl<T: Real> ShadingFrame<T> {
    /// Builds an orthonormal frame from a possibly non-unit, non-orthogonal normal,
    /// tangent and bitangent (e.g. from a normal map and interpolated vertex tangents).
    ///
    /// * `n` is normalised. A zero or non-finite `n` gives an all-zero frame, so every
    ///   local vector has z = 0 and the BRDF returns 0 (no NaN).
    /// * `t` is Gram–Schmidt orthogonalised against `n` (twice, so the result is
    ///   orthogonal to rounding) and normalised. If it is degenerate (zero, non-finite or
    ///   within [`TANGENT_DEGENERATE_FRACTION_SQ`] of ±n), the frame's tangent is
    ///   `b⊥ × n` from the bitangent instead; if that is degenerate too, an arbitrary
    ///   tangent is built from `n` (Duff et al. 2017, "Building an Orthonormal Basis,
    ///   Revisited"). Only matters for anisotropic α: isotropic results do not depend on
    ///   the tangent.
    /// * The frame's bitangent is always `n × t`: the input bitangent's handedness is not
    ///   used, since every anisotropic term depends only on (t·m)² and (b·m)².
    pub fn new(n: Vec3<T>, t: Vec3<T>, b: Vec3<T>) -> Self {
        let n = n.normalize();
        if n.length_squared() == T::ZERO {
            return Self {
                t: Vec3::zero(),
                b: Vec3::zero(),
                n,
            };
        }
        let tangent = Self::orthogonal_unit(n, t)
            .or_else(|| Self::orthogonal_unit(n, b).map(|bb| bb.cross(n)))
            .unwrap_or_else(|| Self::basis_from_normal(n));
        Self {
            t: tangent,
            b: n.cross(tangent),
            n,
        }
    }

    /// The frame with the given unit normal and an arbitrary tangent (Duff et al. 2017).
    pub fn from_normal(n: Vec3<T>) -> Self {
        Self::new(n, Vec3::zero(), Vec3::zero())
    }

    /// The identity frame (t = x, b = y, n = z).
    pub fn identity() -> Self {
        Self {
            t: Vec3::new(T::ONE, T::ZERO, T::ZERO),
            b: Vec3::new(T::ZERO, T::ONE, T::ZERO),
            n: Vec3::new(T::ZERO, T::ZERO, T::ONE),
        }
    }

    /// World → local: `(t·v, b·v, n·v)`.
    #[inline]
    pub fn to_local(&self, v: Vec3<T>) -> Vec3<T> {
        Vec3::new(self.t.dot(v), self.b.dot(v), self.n.dot(v))
    }

    /// Local → world: `x t + y b + z n`.
    #[inline]
    pub fn to_world(&self, v: Vec3<T>) -> Vec3<T> {
        self.t * v.x + self.b * v.y + self.n * v.z
    }

    /// Unit vector along the part of `v` orthogonal to unit `n`, or `None` if degenerate.
    fn orthogonal_unit(n: Vec3<T>, v: Vec3<T>) -> Option<Vec3<T>> {
        let v2 = v.length_squared();
        if !(v2.is_positive() && v2.is_finite()) {
            return None;
        }
        let r = v.reject_from(n);
        let r = r.reject_from(n);
        if r.length_squared() > T::from_f64(TANGENT_DEGENERATE_FRACTION_SQ) * v2 {
            Some(r.normalize())
        } else {
            None
        }
    }

    /// A unit tangent orthogonal to unit `n` (Duff et al. 2017, branch-free up to the sign).
    pub(crate) fn basis_from_normal(n: Vec3<T>) -> Vec3<T> {
        let sign = if n.z >= T::ZERO { T::ONE } else { -T::ONE };
        let a = -T::ONE / (sign + n.z);
        let b = n.x * n.y * a;
        Vec3::new(T::ONE + sign * n.x * n.x * a, sign * b, -sign * n.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal(f: &ShadingFrame<f64>, tol: f64) {
        for (u, name) in [(f.t, "t"), (f.b, "b"), (f.n, "n")] {
            assert!((u.length() - 1.0).abs() < tol, "{name} not unit: {u:?}");
        }
        assert!(f.t.dot(f.n).abs() < tol);
        assert!(f.b.dot(f.n).abs() < tol);
        assert!(f.t.dot(f.b).abs() < tol);
        // right-handed: t × b = n
        assert!((f.t.cross(f.b) - f.n).length() < tol);
    }

    #[test]
    fn normalize_of_zero_and_non_finite_is_zero() {
        assert_eq!(Vec3::<f32>::zero().normalize(), Vec3::zero());
        assert_eq!(Vec3::new(f32::NAN, 1.0, 0.0).normalize(), Vec3::zero());
        assert_eq!(Vec3::new(f64::INFINITY, 1.0, 0.0).normalize(), Vec3::zero());
        let v = Vec3::new(3.0_f64, 0.0, 4.0).normalize();
        assert!((v - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-15);
    }

    #[test]
    fn frame_orthonormalises_skewed_tangents() {
        let n = Vec3::new(0.3, -0.2, 2.0);
        let t = Vec3::new(1.0, 0.5, 0.7); // not orthogonal to n, not unit
        let f = ShadingFrame::new(n, t, Vec3::zero());
        assert_orthonormal(&f, 1e-14);
        // The frame's tangent lies in the plane of n and t, on t's side.
        assert!(f.t.dot(t) > 0.0);
        assert!(f.t.dot(n.cross(t)).abs() < 1e-14);
    }

    #[test]
    fn frame_falls_back_to_bitangent_then_to_normal() {
        let n = Vec3::new(0.0, 0.0, 1.0);
        // tangent parallel to n: use the bitangent; t = b × n
        let f = ShadingFrame::new(n, n * 3.0, Vec3::new(0.0, 2.0, 0.0));
        assert_orthonormal(&f, 1e-15);
        assert_eq!(f.t, Vec3::new(1.0, 0.0, 0.0));
        // both degenerate: any orthonormal frame around n, for many normals incl. -z
        for n in [
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 2.0, -3.0),
            Vec3::new(-1e-3, 1.0, 1e-9),
        ] {
            let f = ShadingFrame::new(n, Vec3::zero(), Vec3::new(f64::NAN, 0.0, 0.0));
            assert_orthonormal(&f, 1e-14);
            assert!((f.n - n.normalize()).length() < 1e-15);
        }
    }

    #[test]
    fn zero_normal_gives_zero_frame() {
        let f = ShadingFrame::new(Vec3::<f32>::zero(), Vec3::new(1.0, 0.0, 0.0), Vec3::zero());
        assert_eq!(f.to_local(Vec3::new(0.2, 0.3, 0.9)), Vec3::zero());
    }

    /// The facing rule: a normal that faces the eye by at least FACING_COS_MIN is kept
    /// bit for bit; one that does not is unit, faces it by exactly FACING_COS_MIN, lies
    /// in the plane of n and v on n's side of v, and the rule is continuous at the
    /// threshold; n = −v still gives a unit normal facing v.
    #[test]
    fn facing_view_bends_just_enough() {
        let c_min = crate::FACING_COS_MIN;
        let v = Vec3::new(0.2_f64, -0.3, 0.9).normalize();
        let mut rng = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut kept, mut bent) = (0, 0);
        for _ in 0..20_000 {
            let n = Vec3::new(next(), next(), next()).normalize();
            let f = facing_view(n, v);
            if n.dot(v) >= c_min {
                assert_eq!(f, n);
                kept += 1;
                continue;
            }
            bent += 1;
            assert!((f.length() - 1.0).abs() < 1e-14, "{f:?}");
            assert!((f.dot(v) - c_min).abs() < 1e-14, "{}", f.dot(v));
            // In the plane of n and v, on n's side of v.
            assert!(f.dot(n.cross(v)).abs() < 1e-14);
            assert!(f.reject_from(v).dot(n.reject_from(v)) >= 0.0);
        }
        assert!(kept > 1000 && bent > 1000, "{kept} kept, {bent} bent");
        // Continuous at the threshold: a normal just below it moves by about as much as
        // its cosine is short.
        let across = Vec3::new(1.0, 0.0, 0.0).reject_from(v).normalize();
        let at = |c: f64| v * c + across * (1.0 - c * c).sqrt();
        let below = at(c_min - 1e-9);
        assert!((facing_view(below, v) - below).length() < 1e-8);
        assert_eq!(facing_view(at(c_min + 1e-9), v), at(c_min + 1e-9));
        // Exactly away: still unit and facing.
        let f = facing_view(-v, v);
        assert!((f.length() - 1.0).abs() < 1e-14 && (f.dot(v) - c_min).abs() < 1e-14);
        // f32 as the GPU computes it: facing by FACING_COS_MIN to rounding.
        let f32_bent = facing_view(Vec3::new(0.0_f32, 0.0, -1.0), Vec3::new(0.6, 0.0, 0.8));
        assert!((f32_bent.dot(Vec3::new(0.6, 0.0, 0.8)) - c_min as f32).abs() < 1e-6);
    }

    #[test]
    fn local_and_world_round_trip() {
        let f = ShadingFrame::new(
            Vec3::new(0.1, 0.9, 0.2),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::zero(),
        );
        let v = Vec3::new(0.3, -0.4, 0.5);
        assert!((f.to_world(f.to_local(v)) - v).length() < 1e-15);
    }
}
