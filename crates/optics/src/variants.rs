//! The comparison variants' BRDFs, each from its own formula, so the GPU's variant
//! shaders can be checked against what they claim to evaluate (not only measured
//! against the exact model): Schlick's and Hoffman's F82 Fresnel curves, the separable
//! and Hammon's approximate masking–shadowing, Beckmann's distribution with its own
//! Smith Λ. The assembly (dielectric specular + transmitted diffuse, conductor
//! specular, blended by metalness) is [`crate::brdf::brdf_evaluate`]'s; only the
//! chosen terms change.
//!
//! - **Schlick** (1994): F(μ) = F₀ + (1 − F₀)(1 − μ)⁵ through the exact normal-incidence
//!   reflectance F₀ of η (dielectric) and η + ik (conductor) seen from the outside medium;
//!   the diffuse transmittance is 1 − F on the same curve, in and out.
//! - **F82** (Hoffman 2019): Schlick's curve less b μ(1 − μ)⁶, b chosen so that the
//!   curve passes through the exact reflectance at μ = 1/7 ([`fresnel_f82_coefficient`]).
//! - **Separable masking**: G₂ = G₁(v) G₁(l) = 1/((1 + Λ(v))(1 + Λ(l))).
//! - **Approximate masking** (Hammon 2017): V = G₂/(4 n·v n·l) ≈ ½ / lerp(2 n·l n·v,
//!   n·l + n·v, α), α = √(α_x α_y); a fit of GGX's height-correlated term, so with
//!   Beckmann's distribution it is the height-correlated form.
//! - **Beckmann** (Walter et al. 2007): D_Beckmann with Beckmann's Λ in either Smith
//!   form.
//! - **Energy compensation** (multiple scattering, in the form of Fdez-Agüera 2019 and
//!   Turquin 2019): each specular lobe × (1 + F₀ (1 − E)/E), E = E(n·v, ½(α_x + α_y)) the
//!   white GGX lobe's single-scattering albedo ([`specular_albedo_white`], at least
//!   10⁻³), F₀ the exact normal-incidence reflectance of that lobe (per channel for the
//!   conductor); the diffuse lobe unchanged.

use crate::brdf::BrdfInputs;
use crate::diffuse::{
    diffuse_lambert, diffuse_oren_nayar_full, diffuse_oren_nayar_qualitative,
    OREN_NAYAR_A_CONSTANT_BRDF,
};
use crate::environment::specular_albedo_white;
use crate::fresnel::{
    fresnel_conductor, fresnel_dielectric, fresnel_dielectric_transmittance, fresnel_f82,
    fresnel_f82_coefficient, fresnel_schlick, F82_COS,
};
use crate::microfacet::{
    clamp_alpha, d_beckmann_anisotropic, d_ggx_anisotropic, lambda_beckmann_anisotropic,
    lambda_ggx_anisotropic,
};
use crate::vec3::{ShadingFrame, Vec3};
use crate::DiffuseModel;

/// The Fresnel term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum FresnelForm {
    /// The full equations with the outside medium (the exact model).
    #[default]
    Full,
    /// Schlick's curve through the exact F₀.
    Schlick,
    /// Hoffman's F82 curve through the exact F₀ and the exact reflectance at μ = 1/7.
    F82,
}

/// The masking–shadowing term.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum MaskingForm {
    /// Smith's height-correlated G₂ (the exact model).
    #[default]
    HeightCorrelated,
    /// G₁(v) G₁(l).
    Separable,
    /// Hammon 2017's fit of the height-correlated V (GGX only).
    Approximate,
}

/// The microfacet normal distribution.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum DistributionForm {
    /// GGX / Trowbridge–Reitz (the exact model).
    #[default]
    Ggx,
    /// Beckmann, with Beckmann's Smith Λ.
    Beckmann,
}

/// Which form of each term a BRDF evaluates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct BrdfVariant {
    /// The Fresnel term.
    pub fresnel: FresnelForm,
    /// The masking–shadowing term.
    pub masking: MaskingForm,
    /// The normal distribution.
    pub distribution: DistributionForm,
    /// Multiple-scattering energy compensation of the specular lobes.
    pub energy_compensation: bool,
}

/// Hammersley samples of E(μ, α) in [`brdf_evaluate_variant`]'s energy compensation (as
/// many as each entry of the renderer's table has).
pub const ENERGY_ALBEDO_SAMPLES: u32 = 1024;

impl BrdfVariant {
    /// The exact model: full Fresnel, height-correlated Smith, GGX
    /// ([`crate::brdf::brdf_evaluate`]).
    pub const EXACT: BrdfVariant = BrdfVariant {
        fresnel: FresnelForm::Full,
        masking: MaskingForm::HeightCorrelated,
        distribution: DistributionForm::Ggx,
        energy_compensation: false,
    };
}

/// One reflectance curve: the exact equations, or a curve through the exact F₀ (and,
/// for F82, its coefficient b).
#[derive(Clone, Copy)]
enum Curve {
    Exact,
    Schlick { f0: f64 },
    F82 { f0: f64, b: f64 },
}

impl Curve {
    fn new(form: FresnelForm, exact: impl Fn(f64) -> f64) -> Curve {
        match form {
            FresnelForm::Full => Curve::Exact,
            FresnelForm::Schlick => Curve::Schlick { f0: exact(1.0) },
            FresnelForm::F82 => {
                let f0 = exact(1.0);
                Curve::F82 {
                    f0,
                    b: fresnel_f82_coefficient(f0, exact(F82_COS)),
                }
            }
        }
    }

    fn at(&self, mu: f64, exact: impl Fn(f64) -> f64) -> f64 {
        match *self {
            Curve::Exact => exact(mu),
            Curve::Schlick { f0 } => fresnel_schlick(mu, f0),
            Curve::F82 { f0, b } => fresnel_f82(mu, f0, b),
        }
    }
}

/// f(v, l) per channel (not multiplied by n·l) with the terms `variant` names, in f64;
/// the arguments and the zero cases as [`crate::brdf::brdf_evaluate`], which this equals
/// for [`BrdfVariant::EXACT`].
pub fn brdf_evaluate_variant(
    m: &BrdfInputs<f64>,
    variant: &BrdfVariant,
    n: Vec3<f64>,
    t: Vec3<f64>,
    b: Vec3<f64>,
    v: Vec3<f64>,
    l: Vec3<f64>,
) -> [f64; 3] {
    let frame = ShadingFrame::new(n, t, b);
    let v = frame.to_local(v.normalize());
    let l = frame.to_local(l.normalize());
    if !(v.z > 0.0 && l.z > 0.0) {
        return [0.0; 3];
    }
    let (ax, ay) = (clamp_alpha(m.alpha_x), clamp_alpha(m.alpha_y));
    let metal = m.metalness.clamp(0.0, 1.0);
    let w = m.polarisation_weight.clamp(0.0, 1.0);
    let eta_i = m.outside_eta;

    let sum = v + l;
    let len = sum.length();
    let h = sum * (1.0 / len);
    let cos_h = (0.5 * len).min(1.0);

    let lobe = match variant.distribution {
        DistributionForm::Ggx => {
            let (lv, ll) = (
                lambda_ggx_anisotropic(v, ax, ay),
                lambda_ggx_anisotropic(l, ax, ay),
            );
            let visibility = match variant.masking {
                MaskingForm::HeightCorrelated => 1.0 / (1.0 + lv + ll) / (4.0 * v.z * l.z),
                MaskingForm::Separable => 1.0 / ((1.0 + lv) * (1.0 + ll)) / (4.0 * v.z * l.z),
                MaskingForm::Approximate => {
                    let alpha = (ax * ay).sqrt();
                    let (a, b) = (2.0 * l.z * v.z, l.z + v.z);
                    0.5 / (a + (b - a) * alpha)
                }
            };
            d_ggx_anisotropic(h, ax, ay) * visibility
        }
        DistributionForm::Beckmann => {
            let (lv, ll) = (
                lambda_beckmann_anisotropic(v, ax, ay),
                lambda_beckmann_anisotropic(l, ax, ay),
            );
            let g2 = match variant.masking {
                MaskingForm::Separable => 1.0 / ((1.0 + lv) * (1.0 + ll)),
                MaskingForm::HeightCorrelated | MaskingForm::Approximate => 1.0 / (1.0 + lv + ll),
            };
            d_beckmann_anisotropic(h, ax, ay) * g2 / (4.0 * v.z * l.z)
        }
    };

    // Energy compensation's (1 − E)/E, or 0.
    let lost = if variant.energy_compensation {
        let e = specular_albedo_white(v.z, 0.5 * (ax + ay), ENERGY_ALBEDO_SAMPLES).max(1e-3);
        (1.0 - e) / e
    } else {
        0.0
    };
    let mut out = [0.0; 3];
    if metal < 1.0 {
        let eta_d = m.dielectric_eta;
        let exact = |mu: f64| fresnel_dielectric(mu, eta_i, eta_d).weighted(w);
        let curve = Curve::new(variant.fresnel, exact);
        let spec = lobe * curve.at(cos_h, exact) * (1.0 + exact(1.0) * lost);
        let transmittance = |mu: f64| match curve {
            Curve::Exact => fresnel_dielectric_transmittance(mu, eta_i, eta_d).weighted(w),
            _ => 1.0 - curve.at(mu, exact),
        };
        let diffuse_weight = transmittance(l.z) * transmittance(v.z);
        let sigma = m.oren_nayar_sigma;
        for (o, &rho) in out.iter_mut().zip(&m.base_color) {
            let rho = rho.clamp(0.0, 1.0);
            let diffuse = match m.diffuse_model {
                DiffuseModel::Lambert => diffuse_lambert(rho),
                DiffuseModel::OrenNayarQualitative => {
                    diffuse_oren_nayar_qualitative(rho, sigma, OREN_NAYAR_A_CONSTANT_BRDF, v, l)
                }
                DiffuseModel::OrenNayarFull => diffuse_oren_nayar_full(rho, sigma, v, l),
            };
            *o = (1.0 - metal) * (spec + diffuse_weight * diffuse);
        }
    }
    if metal > 0.0 {
        for (c, o) in out.iter_mut().enumerate() {
            let (eta, k) = (m.conductor_eta[c], m.conductor_k[c]);
            let exact = |mu: f64| fresnel_conductor(mu, eta_i, eta, k).weighted(w);
            let curve = Curve::new(variant.fresnel, exact);
            *o += metal * lobe * curve.at(cos_h, exact) * (1.0 + exact(1.0) * lost);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::brdf_evaluate;
    use crate::environment::SplitMix64;

    fn random_inputs(rng: &mut SplitMix64) -> (BrdfInputs<f64>, [Vec3<f64>; 2]) {
        let mut u = || rng.next_f64();
        let m = BrdfInputs {
            base_color: [u(), u(), u()],
            metalness: [0.0, 1.0, u()][(u() * 3.0) as usize % 3],
            alpha_x: 0.01 + u(),
            alpha_y: 0.01 + u() * 0.5,
            conductor_eta: [0.2 + u(), 0.2 + u(), 0.2 + u()],
            conductor_k: [3.0 * u(), 3.0 * u(), 3.0 * u()],
            dielectric_eta: 1.0 + u(),
            outside_eta: [1.0, 1.33][(u() * 2.0) as usize % 2],
            polarisation_weight: u(),
            diffuse_model: [
                DiffuseModel::Lambert,
                DiffuseModel::OrenNayarQualitative,
                DiffuseModel::OrenNayarFull,
            ][(u() * 3.0) as usize % 3],
            oren_nayar_sigma: u(),
        };
        let mut direction = || {
            let (z, phi) = (u(), u() * std::f64::consts::TAU);
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        };
        (m, [direction(), direction()])
    }

    const FRAME: [Vec3<f64>; 3] = [
        Vec3 {
            x: 0.0,
            y: 0.0,
            z: 1.0,
        },
        Vec3 {
            x: 1.0,
            y: 0.0,
            z: 0.0,
        },
        Vec3 {
            x: 0.0,
            y: 1.0,
            z: 0.0,
        },
    ];

    /// Energy compensation keeps a white furnace white: a conductor reflecting
    /// everything (F = 1 to 4e-8) has, compensated, a directional albedo ∫ f (n·l) dl of
    /// E (1 + (1 − E)/E) = 1 (to the quadrature's and E's sampling error), where single
    /// scattering alone keeps E < 1; a dielectric's lobe grows by F₀ (1 − E)/E of itself
    /// (F₀ = 0.04 for η = 1.5), its diffuse lobe not at all.
    #[test]
    fn energy_compensation_gives_back_what_single_scattering_loses() {
        let white = BrdfInputs {
            base_color: [0.0; 3],
            metalness: 1.0,
            alpha_x: 0.5,
            alpha_y: 0.5,
            conductor_eta: [1.0; 3],
            conductor_k: [1.0e4; 3],
            dielectric_eta: 1.5,
            outside_eta: 1.0,
            polarisation_weight: 0.5,
            diffuse_model: DiffuseModel::Lambert,
            oren_nayar_sigma: 0.0,
        };
        let compensated = BrdfVariant {
            energy_compensation: true,
            ..BrdfVariant::EXACT
        };
        let [n, t, b] = FRAME;
        let albedo = |m: &BrdfInputs<f64>, variant: &BrdfVariant, v: Vec3<f64>| {
            // Midpoint rule over (cos θ, φ): ∫ f cos θ dω = ∫∫ f cos θ d(cos θ) dφ.
            let steps = 400;
            let mut sum = 0.0;
            for i in 0..steps {
                let z = (f64::from(i) + 0.5) / f64::from(steps);
                let r = (1.0 - z * z).sqrt();
                for j in 0..steps {
                    let phi = (f64::from(j) + 0.5) / f64::from(steps) * std::f64::consts::TAU;
                    let l = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    sum += brdf_evaluate_variant(m, variant, n, t, b, v, l)[1] * z;
                }
            }
            sum * std::f64::consts::TAU / f64::from(steps * steps)
        };
        for alpha in [0.3, 0.6, 1.0] {
            for mu in [0.3f64, 0.6, 0.9] {
                let m = BrdfInputs {
                    alpha_x: alpha,
                    alpha_y: alpha,
                    ..white
                };
                let v = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
                let single = albedo(&m, &BrdfVariant::EXACT, v);
                // The compensation is one factor for every l at this v (the dielectric
                // check below holds its form on random directions): the compensated
                // albedo is the single-scattering one times it, read at one l.
                let l = Vec3::new(0.0, 0.6, 0.8);
                let factor = brdf_evaluate_variant(&m, &compensated, n, t, b, v, l)[1]
                    / brdf_evaluate_variant(&m, &BrdfVariant::EXACT, n, t, b, v, l)[1];
                let multiple = single * factor;
                assert!(
                    (multiple - 1.0).abs() < 3e-3,
                    "α {alpha}, μ {mu}: {multiple}"
                );
                if alpha == 1.0 {
                    assert!(
                        single < 0.9,
                        "α 1, μ {mu}: single scattering keeps {single}"
                    );
                }
            }
        }
        // A dielectric: the specular lobe × (1 + F₀ (1 − E)/E), the diffuse lobe as it was.
        let mut rng = SplitMix64::new(11);
        for _ in 0..500 {
            let (mut m, [v, l]) = random_inputs(&mut rng);
            m.metalness = 0.0;
            let exact = brdf_evaluate_variant(&m, &BrdfVariant::EXACT, n, t, b, v, l);
            let with = brdf_evaluate_variant(&m, &compensated, n, t, b, v, l);
            let diffuse_free = BrdfInputs {
                base_color: [0.0; 3],
                ..m
            };
            let spec = brdf_evaluate_variant(&diffuse_free, &BrdfVariant::EXACT, n, t, b, v, l)[0];
            let e = specular_albedo_white(
                v.z,
                0.5 * (clamp_alpha(m.alpha_x) + clamp_alpha(m.alpha_y)),
                ENERGY_ALBEDO_SAMPLES,
            )
            .max(1e-3);
            let f0 = fresnel_dielectric(1.0, m.outside_eta, m.dielectric_eta)
                .weighted(m.polarisation_weight.clamp(0.0, 1.0));
            for c in 0..3 {
                let expected = exact[c] + spec * f0 * (1.0 - e) / e;
                assert!(
                    (with[c] - expected).abs() <= 1e-12 * expected.abs().max(1e-12),
                    "{} against {expected}",
                    with[c]
                );
            }
        }
    }

    /// The exact variant is the exact BRDF (to rounding: the assembly is the same, the
    /// visibility written as G₂/(4 n·v n·l) instead of split halves).
    #[test]
    fn the_exact_variant_is_the_brdf() {
        let mut rng = SplitMix64::new(7);
        let [n, t, b] = FRAME;
        for _ in 0..5000 {
            let (m, [v, l]) = random_inputs(&mut rng);
            let exact = brdf_evaluate(&m, n, t, b, v, l);
            let variant = brdf_evaluate_variant(&m, &BrdfVariant::EXACT, n, t, b, v, l);
            for c in 0..3 {
                let scale = exact[c].abs().max(1e-12);
                assert!(
                    (exact[c] - variant[c]).abs() <= 1e-10 * scale,
                    "{m:?} {v:?} {l:?}: {exact:?} against {variant:?}"
                );
            }
        }
    }

    /// Each curve at normal incidence is the exact reflectance; F82 is exact at μ = 1/7
    /// too, Schlick is not; the separable form never exceeds the height-correlated one
    /// (1 + a + b ≤ (1 + a)(1 + b)); Hammon's fit is exact where it is built to be: at
    /// α = 1 (Λ(w) = (1/cos θ − 1)/2, so V = ½/(n·l + n·v)) and as α → 0 (G₂ → 1, to
    /// first order in α).
    #[test]
    fn each_term_keeps_its_defining_property() {
        let mut rng = SplitMix64::new(11);
        let [n, t, b] = FRAME;
        for _ in 0..2000 {
            let (mut m, [v, l]) = random_inputs(&mut rng);
            let eval = |m: &BrdfInputs<f64>, variant: BrdfVariant| {
                brdf_evaluate_variant(m, &variant, n, t, b, v, l)
            };
            let separable = BrdfVariant {
                masking: MaskingForm::Separable,
                ..BrdfVariant::EXACT
            };
            let approximate = BrdfVariant {
                masking: MaskingForm::Approximate,
                ..BrdfVariant::EXACT
            };
            let (exact, apart) = (eval(&m, BrdfVariant::EXACT), eval(&m, separable));
            for c in 0..3 {
                assert!(apart[c] <= exact[c] * (1.0 + 1e-12), "{apart:?} {exact:?}");
            }
            for alpha in [1.0, 1e-3] {
                (m.alpha_x, m.alpha_y) = (alpha, alpha);
                let (exact, fit) = (eval(&m, BrdfVariant::EXACT), eval(&m, approximate));
                // At small α the exact G₂ is 1 − O(α² tan² θ), and the fit's lerp moves
                // V by a relative α (1/(2 n·v) + 1/(2 n·l)) to first order: allow both.
                let tan2 = |c: f64| (1.0 - c * c) / (c * c);
                let slack = if alpha == 1.0 {
                    1e-12
                } else {
                    alpha * (1.0 / v.z + 1.0 / l.z) + 2.0 * alpha * alpha * (tan2(v.z) + tan2(l.z))
                };
                for c in 0..3 {
                    assert!(
                        (exact[c] - fit[c]).abs() <= slack * exact[c].abs().max(1e-300),
                        "α = {alpha}: {exact:?} against {fit:?} ({v:?}, {l:?})"
                    );
                }
            }
        }
        let (eta_i, eta) = (1.0, 1.5);
        let exact = |mu: f64| fresnel_dielectric(mu, eta_i, eta).unpolarised();
        for form in [FresnelForm::Schlick, FresnelForm::F82] {
            let curve = Curve::new(form, exact);
            assert!((curve.at(1.0, exact) - exact(1.0)).abs() < 1e-15);
        }
        let f82 = Curve::new(FresnelForm::F82, exact);
        let schlick = Curve::new(FresnelForm::Schlick, exact);
        assert!((f82.at(F82_COS, exact) - exact(F82_COS)).abs() < 1e-12);
        assert!((schlick.at(F82_COS, exact) - exact(F82_COS)).abs() > 1e-4);
    }
}
