//! Reference optics for Combustion: every BRDF and Fresnel term of the design notes
//! (`shared/reference/rendering-notes.txt`), in f64 as the oracle and in f32 as the GPU
//! computes it, with the GLSL mirrors in `shaders/include/` (`constants.glsl`,
//! `microfacet.glsl`, `fresnel.glsl`, `diffuse.glsl`, `brdf.glsl`).
//!
//! Each function is written once, generic over [`Real`] (`f32`, `f64`), so the f32 path
//! is the same arrangement as the reference and as the shader. Each term is a small
//! function named for its model, with a one-line citation.
//!
//! * [`microfacet`]: GGX D (isotropic, anisotropic), Beckmann D, Smith Λ and G₁ for GGX,
//!   separable and height-correlated G₂, the height-correlated visibility, Cook–Torrance
//!   G, the microfacet specular normalisation, and the roughness mappings.
//! * [`fresnel`]: dielectric–conductor Fresnel with an outside medium (R_s, R_p),
//!   dielectric Fresnel with total internal reflection and its transmittance, the
//!   Cook–Torrance (g, c) form, Schlick, F0 ↔ η.
//! * [`diffuse`]: Lambert, Oren–Nayar qualitative and full, the σ mapping.
//! * [`brdf`]: [`brdf_evaluate`], the assembled BRDF the lighting pass evaluates.
//! * [`coat`]: a clear dielectric coat over it (KHR_materials_clearcoat): its own GGX
//!   lobe with the exact Fresnel reflectance from the outside medium, and the base
//!   attenuated by the coat's transmittance both ways.
//! * [`sheen`]: the sheen of fibres (KHR_materials_sheen): the Charlie lobe with Estevez
//!   & Kulla's visibility, the base scaled by the sheen's directional albedo.
//! * [`thin_film`]: a thin dielectric film over the base (KHR_materials_iridescence):
//!   the Airy summation of Belcour & Barla with the base's exact complex Fresnel
//!   amplitudes, mixed into the base's Fresnel by the film's weight ([`brdf_view_with_film`]).
//! * [`specular`]: the dielectric's specular strength and colour
//!   (KHR_materials_specular): its Fresnel reflectance rescaled from F₀′ = min(F₀ colour, 1)
//!   to 1 and weighted by the factor ([`brdf::brdf_view_layered`]).
//! * [`real`], [`vec3`]: the scalar trait, a 3-vector, the [`ShadingFrame`].
//!
//! # Conventions
//!
//! * **Directions** are unit vectors pointing *away* from the surface (v to the viewer,
//!   l to the light). Every term takes them **in the shading frame** — x = tangent,
//!   y = bitangent, z = normal — so n·m = m.z and sin²θ = |n × m|² = m.x² + m.y², formed
//!   without cancellation. [`brdf_evaluate`] takes world-space vectors and builds the frame
//!   with [`ShadingFrame::new`] (normalises, orthogonalises, falls back on degenerate
//!   tangents; a zero normal yields 0).
//! * **Roughness.** Materials store *perceptual* roughness r ∈ [0, 1]; GGX
//!   α = max(r², [`ALPHA_MIN`]) is applied in exactly one function,
//!   [`microfacet::alpha_from_perceptual_roughness`]. Every function taking α clamps it to
//!   the interval from [`ALPHA_MIN`] to 1, so α = 0 gives the finite `ALPHA_MIN` lobe,
//!   never 0/0.
//! * **Anisotropy** follows KHR_materials_anisotropy:
//!   [`microfacet::anisotropic_alphas`]`(α, s) = (α_t, α_b) = (mix(α, 1, s²), α)`, α_t
//!   along the tangent (x), α_b along the bitangent (y). The anisotropy rotation is
//!   applied by whoever builds the tangent.
//! * **Oren–Nayar σ** is the standard deviation of the facet slope angle in radians:
//!   [`diffuse::oren_nayar_sigma_from_roughness`]`(r) = r²/√2` — the per-axis slope
//!   deviation of a microfacet lobe of width α = r² (exact for Beckmann, whose slopes are
//!   Gaussian with variance α²/2 per axis), so diffuse and specular describe one surface.
//!   r = 1 gives σ = 0.71 rad (40°); r = 0 gives Lambert.
//! * **Polarisation.** R_s is s-polarised (perpendicular), R_p p-polarised (parallel);
//!   [`fresnel::Polarised::weighted`]`(w) = (1 − w)R_s + w R_p`: w = 0 s, w = 1 p, ½
//!   unpolarised.
//! * **IORs.** η_i is the outside medium (air 1, water 1.33), η_t + i k_t the inside.
//!   IORs are clamped to the interval from [`ETA_MIN`] to [`ETA_MAX`], k from 0 to
//!   `ETA_MAX`.
//! * **Bad input never panics and never yields NaN** from [`brdf_evaluate`] or the
//!   Fresnel functions: values are clamped (NaN → the lower bound), documented per
//!   field in [`BrdfInputs`]. The local-frame terms accept any finite vectors.
//! * **Grazing.** A cosine that is divided by is first raised to [`COS_MIN`], so the BRDF
//!   stays finite at double grazing (where the true value diverges like 1/cos).
//!
//! # The assembled BRDF ([`brdf_evaluate`])
//!
//! f = (1 − metalness) [S·R_w(v·h; η_i, η_d) + T_w(n·l) T_w(n·v) · f_diffuse(ρ)]
//!   + metalness · S·R_w(v·h; η_i, η + ik)
//!
//! with S = D_GGX,aniso(h) · G₂,height-correlated/(4 n·v n·l), v·h = |v + l|/2, R_w the
//! polarisation-weighted Fresnel reflectance (dielectric with TIR; conductor per channel)
//! and T_w = 1 − R_w the dielectric transmittance. **Diffuse weighting:** the diffuse
//! substrate is reached through the interface and left through it, so its lobe is
//! weighted by the transmittance of both crossings at the macro-surface angles; the
//! product is symmetric in v and l (reciprocity holds to rounding: measured 0 ε) and
//! ∫ f cos ≤ 1 is verified by quadrature for every diffuse model at white albedo (largest
//! albedo found 0.99875, a smooth surface seen from inside glass past the critical angle,
//! i.e. total internal reflection).
//!
//! # Seed-notes, point by point
//!
//! Numbered as in `shared/reference/seed-notes.md`, "Equations that need care".
//!
//! 1. **Lambert** is ρ/π ([`diffuse::diffuse_lambert`]); N·L belongs to the rendering
//!    equation and is applied by the caller. Test: `identities::lambert_albedo_is_rho`.
//! 2. **Cook–Torrance normalisation.** Every D here is normalised (∫D(m)(n·m)dω = 1,
//!    `identities::distributions_are_normalised`, |error| ≤ 3e-12 for α ∈ [0.02, 1],
//!    isotropic and anisotropic), so the specular BRDF divides by 4(n·v)(n·l)
//!    ([`microfacet::specular_microfacet`]); `identities::specular_normalisation_is_four_not_pi`
//!    shows the notes' π would return 4/π of the light.
//! 3. **Beckmann "simplified to:"** was lost; [`microfacet::d_beckmann`] is the
//!    normalised form the notes print (tested with the other D's).
//! 4. **GGX G₁.** χ⁺'s argument is (v·m)/(v·n), evaluated as a sign test; Λ and G₁ are
//!    evaluated as α²sin²θ/(2c(√(c² + α²sin²θ) + c)) and 2c/(c + √(c² + α²sin²θ)): no
//!    tan²θ, no cancellation (f32 error ≤ 2.3 ε measured down to cosθ = 1e-6,
//!    `f32_accuracy::masking_f32_matches_f64_at_grazing`; the weak white furnace holds to
//!    7e-10, `identities::weak_white_furnace`).
//! 5. **Oren–Nayar.** The notes' "full form" is the qualitative model
//!    ([`diffuse::diffuse_oren_nayar_qualitative`], A-constant as a parameter); the
//!    paper's full model with C1, C2, C3 and interreflection is
//!    [`diffuse::diffuse_oren_nayar_full`]. Measured against the full model, the paper's
//!    0.33 is closer than the notes' 0.57 for every σ at albedo ≤ 0.5, so the BRDF uses
//!    0.33 ([`diffuse::OREN_NAYAR_A_CONSTANT_BRDF`], table there;
//!    `identities::oren_nayar_a_constant_choice`). The α/β clash is avoided by naming
//!    them θ_max/θ_min. Found on the way: the paper's single-scattering term goes
//!    negative for σ ≳ 0.6 at grazing forward scattering; it is clamped at 0. Both
//!    models tend to Lambert as σ² (`identities::oren_nayar_tends_to_lambert`).
//! 6. **Wavelength weighting** and 7. **averaging η, k vs averaging reflectance** are
//!    spectral reductions and live in `combustion-spectra` (`band_weighted_mean`, whose
//!    denominator is over the normalised t so a constant comes back unchanged, and
//!    `compare_averaging_methods`, tested there), which evaluates the Fresnel equations
//!    of this crate ([`fresnel::fresnel_conductor`]) per wavelength.
//! 8. **η from F0** ([`fresnel::eta_from_f0`]) returns the *relative* index η_t/η_i; it
//!    is the absolute η_t only in air (`fresnel::tests::eta_from_f0_is_relative_to_the_outside_medium`).
//! 9. **External IOR.** Every Fresnel function takes η_i. With η_i > η_t the dielectric
//!    reflectance is exactly 1 at and past the critical angle, with no square root of a
//!    negative number, in both [`fresnel::fresnel_dielectric`] and
//!    [`fresnel::fresnel_conductor`] (k = 0), f32 and f64
//!    (`identities::total_internal_reflection`, `identities::conductor_with_zero_k_is_dielectric`).
//! 10. **Cancellation in the Fresnel equations.** R_s's numerator is (a − c)² + b² with
//!     a − c = (a² − c²)/(a + c) and a² − c² formed from sums of same-sign terms; R_p's
//!     factor uses a c − s² = (c²(a² − c²) + (c − s)(c + s))/(a c + s²); the dielectric
//!     uses (η_t − η_i)(η_t + η_i). The notes' printed form in f32 is off by a factor 23
//!     at η = 1.0001 and by 1.5e-5 for glass in water; these stay within 16 ε times the
//!     problem's condition number (`f32_accuracy::notes_form_cancels_in_f32_and_ours_does_not`).
//!
//! **Hard cases** (the list at the end of seed-notes.md): grazing v, l and both, negative
//! cosines, α → 0 and α = 1, anisotropy 0 and 1, V = −L, 1 − (n·h)² in f32, η = 1,
//! η = 1.0001, glass in water, k = 0, k large, η < 1, TIR at/above/below the critical
//! angle, non-unit, skewed, zero and NaN normals and tangents: `tests/hard_cases.rs`
//! (fixed table and property tests: finite, ≥ 0, reciprocal, F ∈ [0, 1], R_p ≤ R_s,
//! R + T = 1, G ∈ [0, 1], f32 within the error model below).
//!
//! # f32 against f64
//!
//! Same inputs (f32 values widened exactly), so the difference is the f32 arithmetic of
//! the arrangement alone. ε = f32::EPSILON = 1.19e-7. Bounds as asserted in
//! `tests/f32_accuracy.rs`, where the reason for each is written next to it; "measured"
//! is the worst over ≥ 20 000 deterministic cases plus property tests.
//!
//! | quantity | bound | measured |
//! |---|---|---|
//! | R_s, R_p (conductor, dielectric), \|ΔR\|/R_s | 16 ε κ_F | 5.7 ε κ_F |
//! | T_s, T_p (dielectric), relative | 16 ε κ_F | 1.8 ε κ_F |
//! | D: GGX iso/aniso, Beckmann (tan²θ/α² ≤ 4), relative | 16 ε | 4.8 ε |
//! | Λ, G₁, V (to cosθ = 1e-6), relative | 8 ε | 2.3 ε |
//! | Oren–Nayar qualitative and full, relative to the terms' magnitude | 16 ε | 4.4 ε |
//! | BRDF, inputs in the shading frame, relative | (16 + κ_D + κ_F) ε | 7.8 ε; 0.67 ε κ_D; 0.17 ε κ_F |
//! | BRDF, world-space inputs, relative | 1.5 (16 + κ_D + κ_F,w) ε | 0.54 ε κ_F,w; worst 0.53 × bound |
//!
//! The condition numbers are those of the problem, not of the arrangement:
//! κ_F = 1 + η_i² cos²θ/|η_t² − k² − η_i² sin²θ + 2iη_t k| (≤ 2 except near a critical
//! angle, where R ∝ √(cos²θ − cos²θ_c)); κ_D = 1/(α_min cosθ_h) (D's sensitivity to the
//! rounding of h; large for narrow lobes and for nearly opposite v, l); κ_F,w = κ_F/cos
//! at the cosine where it is largest (a cosine computed from world vectors carries an
//! absolute rounding ≈ ε). R_p is measured relative to R_s because it vanishes at
//! Brewster's angle; for polarisation weight w > ½ the BRDF error is relative to the
//! value at w = ½. In practice (α ≥ 0.01, cosθ_h ≥ 0.1, away from critical angles) the
//! f32 BRDF is within ≈ 1e-4 relative of f64; at α = `ALPHA_MIN` the bound is
//! ≈ 1.2e-4/cosθ_h.
//! The GLSL mirror uses the same arrangements; GPU transcendental precision (atan, exp,
//! sqrt are not correctly rounded in Vulkan) is the renderer's parity test's to measure.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod brdf;
pub mod coat;
pub mod diffuse;
pub mod display;
pub mod environment;
pub mod fresnel;
pub mod layers;
pub mod microfacet;
pub mod readable;
pub mod real;
pub mod sheen;
pub mod specular;
pub mod thin_film;
pub mod variants;
pub mod vec3;

pub use brdf::{
    brdf_evaluate, brdf_evaluate_layered, brdf_evaluate_view, brdf_evaluate_with_film, brdf_view,
    brdf_view_layered, brdf_view_with_film, BrdfInputs, BrdfView, DiffuseModel,
    UnknownDiffuseModel,
};
pub use readable::{escaped, finite_number, readable, shortened};
pub use real::Real;
pub use vec3::{ShadingFrame, Vec3};

/// Smallest GGX/Beckmann α (perceptual roughness ≈ 0.032); every function taking α clamps
/// to [ALPHA_MIN, 1], and [`microfacet::alpha_from_perceptual_roughness`] applies it.
///
/// Why 1e-3: the lobe is then ≈ 0.06° wide, about one pixel of a 1280-pixel, 60° view,
/// so a narrower lobe would only alias under point lights; D peaks at
/// 1/(π α²) ≈ 3.2e5, comfortably finite in f32; and the f32 BRDF's error term
/// κ_D ε = ε/(α cosθ_h) stays ≈ 1.2e-4 at normal half vectors.
pub const ALPHA_MIN: f64 = 1.0e-3;

/// A cosine in (0, COS_MIN) is raised to COS_MIN before anything is divided by it.
///
/// BRDFs diverge like 1/cos at double grazing (f·cos stays bounded); this keeps f finite
/// in f32 (V ≤ 1/(4 α COS_MIN) ≈ 2.5e8 at `ALPHA_MIN`) while changing the evaluated
/// direction by less than 1e-6 rad. A cosine computed in f32 from world vectors is only
/// good to ≈ 1e-7 absolute anyway.
pub const COS_MIN: f64 = 1.0e-6;

/// The least cosine between a shading normal and the direction to the eye: a normal
/// that faces the eye less is bent towards it until it does ([`vec3::facing_view`]).
///
/// A shading normal is not the surface's normal: an interpolated vertex normal at a
/// silhouette, or a normal map on a fold, can turn away from a viewer who sees the
/// surface, and every term below the horizon is 0, so such pixels came out black. The
/// renderer (GLSL `facing_view`, brdf.glsl) and the f64 reference apply this one rule to
/// the base's and the coat's normals before anything is shaded. 1/64: the bent normal is
/// 89.1° from the view, so the light it sees is the grazing light of the surface it
/// bends, and f32 cosines (good to ≈ 1e-7) and the G-buffer's octahedral normal (≈ 1e-4
/// rad at 16 bits) are far from flipping its side.
pub const FACING_COS_MIN: f64 = 1.0 / 64.0;

/// Smallest IOR accepted (η of silver in the visible is ≈ 0.05; 1e-4 leaves margin).
pub const ETA_MIN: f64 = 1.0e-4;

/// Largest IOR and extinction coefficient accepted: covers every measured n and k in the
/// visible with margin, and keeps (η_t/η_i)² and k² (≤ 1e16) far from f32 overflow.
pub const ETA_MAX: f64 = 1.0e4;
