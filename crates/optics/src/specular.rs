//! The dielectric's specular strength and colour (KHR_materials_specular).
//!
//! The extension scales the dielectric's Fresnel reflectance: its normal-incidence
//! reflectance F₀ becomes F₀′ = min(F₀ · colour, 1) per channel, and the whole
//! reflectance is weighted by the specular factor:
//!
//! F′_c(θ) = factor · (F₀′_c + (1 − F₀′_c) · s(θ)),
//!
//! with s the Fresnel curve's shape between F₀ and 1. The extension writes s with
//! Schlick's (1 − cos θ)⁵; here s(θ) = (F(θ) − F₀)/(1 − F₀) of the **exact** dielectric
//! reflectance F (outside medium, polarisation weight, total internal reflection
//! included), which is Schlick's polynomial exactly when F is Schlick's curve
//! (the FRESNEL_SCHLICK comparison variant). F′ is clamped to [0, 1] (a polarised
//! reflectance dips below F₀ at Brewster's angle).
//!
//! What the dielectric does not reflect reaches its diffuse substrate, as the extension's
//! `fresnel_mix` weights it: T′(θ) = 1 − max_c F′_c(θ), one value for every channel (a
//! coloured specular does not tint the diffuse lobe).
//!
//! Identities (tests/specular.rs): factor 1 and colour 1 is not present
//! ([`DielectricSpecular::is_present`]): the BRDF is today's bit for bit; the mapping
//! itself returns F there to rounding; factor 0 removes the dielectric's specular lobe and
//! lets all light reach the diffuse lobe (T′ = 1).

use crate::real::Real;

/// KHR_materials_specular's values at a point: `specularFactor` × the strength texture's
/// A, and `specularColorFactor` × the colour texture's RGB (linear).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DielectricSpecular<T> {
    /// The strength of the dielectric's reflection, in [0, 1] (clamped where used; NaN
    /// reads 0).
    pub factor: T,
    /// Its colour at normal incidence, linear RGB, ≥ 0 (may exceed 1; negative or NaN
    /// reads 0).
    pub color: [T; 3],
}

impl<T: Real> DielectricSpecular<T> {
    /// The extension's default: factor 1, colour 1 (today's dielectric).
    pub fn neutral() -> Self {
        Self {
            factor: T::ONE,
            color: [T::ONE; 3],
        }
    }

    /// Whether it changes anything: a factor or a colour channel other than exactly 1.
    pub fn is_present(&self) -> bool {
        self.factor != T::ONE || self.color.iter().any(|&c| c != T::ONE)
    }

    /// The clamped factor in [0, 1].
    pub fn clamped_factor(&self) -> T {
        self.factor.saturate()
    }

    /// F₀′ = min(F₀ · colour, 1) per channel, the colour read as ≥ 0.
    pub fn f0(&self, f0: T) -> [T; 3] {
        self.color.map(|c| (f0 * c.max(T::ZERO)).min(T::ONE))
    }

    /// F′ per channel from the bare dielectric's reflectance `f` at this angle and at
    /// normal incidence `f0` (see the module's docs).
    pub fn reflectance(&self, f: T, f0: T) -> [T; 3] {
        let shape = if f0 < T::ONE {
            (f - f0) / (T::ONE - f0)
        } else {
            T::ONE
        };
        let factor = self.clamped_factor();
        self.f0(f0)
            .map(|g| (factor * (g + (T::ONE - g) * shape)).saturate())
    }

    /// T′ = 1 − max_c F′_c: what reaches the diffuse substrate through this interface.
    pub fn transmittance(&self, f: T, f0: T) -> T {
        let r = self.reflectance(f, f0);
        T::ONE - r[0].max(r[1]).max(r[2])
    }

    /// The same values in another precision.
    pub fn convert<U: Real>(&self) -> DielectricSpecular<U> {
        DielectricSpecular {
            factor: U::from_f64(self.factor.to_f64()),
            color: self.color.map(|c| U::from_f64(c.to_f64())),
        }
    }
}
