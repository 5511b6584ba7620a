//! A clear coat over the material (KHR_materials_clearcoat), and its CPU reference.
//!
//! GLSL mirror: `shaders/include/brdf.glsl` (`struct CoatInputs`, `coat_view`,
//! `coat_evaluate_view`, `coated`, `coated_radiance`). Same names, inputs in the same
//! order.
//!
//! The coat is a clear dielectric layer of real index η_c (glTF: 1.5) over the material,
//! of weight c ∈ [0, 1] (the clearcoat factor: where it is 0 there is no coat), with its
//! own isotropic GGX roughness α_c and its own normal n_c. With η_i the outside medium's
//! index (the material's):
//!
//! f = c · S_c(v, l) · R_w(v·h; η_i, η_c) + A(v) A(l) · f_base(v, l),
//! A(ω) = 1 − c · R_w(n_c·ω; η_i, η_c),
//!
//! each layer lit with the cosine to its own normal where the two differ (a coat with
//! its own normal map: [`coated_radiance`]),
//!
//! S_c = D_GGX(h) V_Smith,height-correlated(v, l) in the coat's frame (0 unless n_c·v > 0
//! and n_c·l > 0), R_w the **exact** dielectric Fresnel reflectance
//! ([`fresnel_dielectric`], polarisation-weighted; total internal reflection when
//! η_i > η_c). The base is attenuated by the coat's Fresnel transmittance on the way in
//! and on the way out, at the macro-surface angles about n_c (A is 1 − c below the coat's
//! horizon, where R_w = 1): symmetric in v and l, so f stays reciprocal.
//!
//! The outside medium matters: a 1.5 coat reflects R₀ = 0.040 in air but 0.0035 under
//! water (η_i = 1.333), so a coated surface under water shows its base almost uncoated.
//! An index-matched coat (η_c = η_i) reflects and attenuates nothing: f = f_base.
//!
//! Not modelled, as in the glTF specification: the refraction of directions in the coat
//! (the base is lit and seen along v and l as if uncoated), absorption in the coat, and
//! light reflected between coat and base more than once. The attenuation uses the
//! smooth interface's transmittance at the macro-surface angle, not the rough coat's
//! directional albedo, so a rough coat over a white base keeps ∫f cos ≤ 1 only up to the
//! single-scattering GGX lobe's own energy (measured in `tests/identities.rs`).

use crate::fresnel::fresnel_dielectric;
use crate::microfacet::{clamp_alpha, d_ggx, smith_ggx_visibility_half};
use crate::real::Real;
use crate::vec3::{ShadingFrame, Vec3};

/// The coat's inputs, as the lighting pass reads them (G-buffer and material table).
/// Out-of-range values are clamped where they are used, as [`crate::brdf::BrdfInputs`]'s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatInputs<T> {
    /// Weight c ∈ [0, 1] of the coat (KHR_materials_clearcoat `clearcoatFactor` × its
    /// texture's R); 0: no coat.
    pub factor: T,
    /// GGX α of the coat (isotropic; α = r² of the coat's perceptual roughness).
    pub alpha: T,
    /// Real IOR η_c of the coat (glTF: 1.5).
    pub eta: T,
    /// η_i, IOR of the medium above the coat (air 1.0, water 1.33).
    pub outside_eta: T,
    /// 0 = s (perpendicular), 1 = p (parallel), 0.5 unpolarised.
    pub polarisation_weight: T,
}

impl<T: Real> CoatInputs<T> {
    /// The same inputs in another precision (nearest values).
    pub fn convert<U: Real>(&self) -> CoatInputs<U> {
        let c = |x: T| U::from_f64(x.to_f64());
        CoatInputs {
            factor: c(self.factor),
            alpha: c(self.alpha),
            eta: c(self.eta),
            outside_eta: c(self.outside_eta),
            polarisation_weight: c(self.polarisation_weight),
        }
    }
}

/// A coat as a surface carries it: its inputs and its normal (world space).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatLayer<T> {
    /// The coat's inputs.
    pub inputs: CoatInputs<T>,
    /// Its normal (world space; its own normal map applied, else the geometry's).
    pub normal: Vec3<T>,
}

/// Everything of the coat's terms that depends on the view alone: its frame about n_c,
/// v in it, the clamped parameters, the view's half of the Smith visibility and A(v).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatView<T> {
    frame: ShadingFrame<T>,
    v: Vec3<T>,
    alpha: T,
    factor: T,
    w: T,
    cv: T,
    sv: T,
    /// A(v) = 1 − c R_w(n_c·v).
    attenuation_v: T,
}

impl<T: Real> CoatView<T> {
    /// A(v): what of the base's light the coat lets out towards the viewer.
    pub fn attenuation_v(&self) -> T {
        self.attenuation_v
    }

    /// The coat's unit normal (world space; zero for a zero normal).
    pub fn normal(&self) -> Vec3<T> {
        self.frame.to_world(Vec3::new(T::ZERO, T::ZERO, T::ONE))
    }
}

/// A(ω) = 1 − c R_w(cos; η_i, η_c) for ω at `cos` to the coat's normal (clamped to
/// [0, 1]: 1 − c below the horizon).
pub fn coat_attenuation<T: Real>(c: &CoatInputs<T>, cos: T) -> T {
    let factor = c.factor.saturate();
    let r = fresnel_dielectric(cos, c.outside_eta, c.eta).weighted(c.polarisation_weight);
    T::ONE - factor * r
}

/// The per-view part of the coat (see [`CoatView`]); `n` is the coat's normal (world
/// space, any length; a zero normal gives a coat that reflects nothing and attenuates
/// by 1 − c), `v` the direction to the viewer.
pub fn coat_view<T: Real>(c: &CoatInputs<T>, n: Vec3<T>, v: Vec3<T>) -> CoatView<T> {
    let frame = ShadingFrame::from_normal(n);
    let v = frame.to_local(v.normalize());
    let alpha = clamp_alpha(c.alpha);
    let (cv, sv) = smith_ggx_visibility_half(v, alpha, alpha);
    CoatView {
        frame,
        v,
        alpha,
        factor: c.factor.saturate(),
        w: c.polarisation_weight.saturate(),
        cv,
        sv,
        attenuation_v: coat_attenuation(c, v.z),
    }
}

/// The coat's terms for one light direction ([`coat_evaluate_view`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatTerms<T> {
    /// The coat's own reflection c S_c R_w(v·h), not multiplied by a cosine.
    pub specular: T,
    /// A(l): the base's attenuation on the way in.
    pub attenuation_l: T,
    /// n_c·l, the cosine the coat's reflection is lit with.
    pub cos_l: T,
}

/// The coat's terms for light from `l` (world space).
pub fn coat_evaluate_view<T: Real>(
    c: &CoatInputs<T>,
    view: &CoatView<T>,
    l: Vec3<T>,
) -> CoatTerms<T> {
    let l = view.frame.to_local(l.normalize());
    let attenuation_l = coat_attenuation(c, l.z);
    let v = view.v;
    if !(v.z.is_positive() && l.z.is_positive()) || view.factor == T::ZERO {
        return CoatTerms {
            specular: T::ZERO,
            attenuation_l,
            cos_l: l.z,
        };
    }
    let sum = v + l;
    let len = sum.length();
    let h = sum * (T::ONE / len);
    let cos_h = (T::HALF * len).min(T::ONE);
    let (cl, sl) = smith_ggx_visibility_half(l, view.alpha, view.alpha);
    let visibility = T::HALF / (cl * view.sv + view.cv * sl);
    let reflectance = fresnel_dielectric(cos_h, c.outside_eta, c.eta).weighted(view.w);
    CoatTerms {
        specular: view.factor * d_ggx(h, view.alpha) * visibility * reflectance,
        attenuation_l,
        cos_l: l.z,
    }
}

/// The coated BRDF where the coat and the base share their normal, from the base's
/// f(v, l) (`base`, not multiplied by the cosine) and the coat's terms for the same v and
/// l: c S_c R_w + A(v) A(l) f_base, per channel.
pub fn coated<T: Real>(base: [T; 3], view: &CoatView<T>, terms: &CoatTerms<T>) -> [T; 3] {
    let attenuation = view.attenuation_v * terms.attenuation_l;
    base.map(|f| terms.specular + attenuation * f)
}

/// The reflected radiance per unit irradiance (on a plane facing the light) of a coated
/// surface whose coat and base have their own normals: each layer lit with its own
/// cosine, c S_c R_w (n_c·l)⁺ + A(v) A(l) f_base (n·l)⁺, per channel; `base` is the base's
/// f(v, l) and `cos_base` its n·l.
pub fn coated_radiance<T: Real>(
    base: [T; 3],
    cos_base: T,
    view: &CoatView<T>,
    terms: &CoatTerms<T>,
) -> [T; 3] {
    let coat = terms.specular * terms.cos_l.max(T::ZERO);
    let attenuation = view.attenuation_v * terms.attenuation_l * cos_base.max(T::ZERO);
    base.map(|f| coat + attenuation * f)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coat_of_weight_zero_changes_nothing() {
        let c = CoatInputs {
            factor: 0.0,
            alpha: 0.01,
            eta: 1.5,
            outside_eta: 1.0,
            polarisation_weight: 0.5,
        };
        let n = Vec3::new(0.0, 0.0, 1.0);
        let view = coat_view(&c, n, Vec3::new(0.3, 0.1, 0.9));
        let terms = coat_evaluate_view(&c, &view, Vec3::new(-0.3, -0.1, 0.9));
        assert_eq!(coated([0.25, 0.5, 1.0], &view, &terms), [0.25, 0.5, 1.0]);
    }
}
