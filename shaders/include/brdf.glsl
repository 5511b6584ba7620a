// The assembled BRDF of the lighting pass. GLSL mirror of crates/optics/src/brdf.rs
// (brdf_evaluate, BrdfInputs, DiffuseModel) and of ShadingFrame / Vec3::normalize in
// crates/optics/src/vec3.rs: same names, inputs in the same order, same arrangements,
// so the CPU reference and this shader can be compared per pixel.
#ifndef COMBUSTION_BRDF_GLSL
#define COMBUSTION_BRDF_GLSL

#include "constants.glsl"
#include "microfacet.glsl"
#include "fresnel.glsl"
#include "diffuse.glsl"
#ifdef IRIDESCENCE
#include "thin_film.glsl"
#endif

// The comparison variants that replace the Fresnel equations by a curve through exact
// points (FRESNEL_SCHLICK: Schlick's, through F0; FRESNEL_F82: Hoffman's F82, through F0
// and F(1/7)). Neither has total internal reflection beyond what its points see.
#if defined(FRESNEL_SCHLICK) || defined(FRESNEL_F82)
#define FRESNEL_CURVE
#endif

#ifdef ENERGY_COMPENSATION
// Multiple-scattering energy compensation (combustion_renderer::Renderer::
// set_energy_compensation): E(μ, α), the white GGX lobe's directional albedo, defined by
// the shader that includes this file (lighting.frag, from its table).
float energy_white_albedo_lookup(float cos_v, float alpha);
#endif

// DiffuseModel discriminants (Rust: #[repr(u32)] enum DiffuseModel). Any other value
// evaluates as Lambert here; the Rust side rejects it in TryFrom<u32>.
#define DIFFUSE_MODEL_LAMBERT 0u
#define DIFFUSE_MODEL_OREN_NAYAR_QUALITATIVE 1u
#define DIFFUSE_MODEL_OREN_NAYAR_FULL 2u

#ifdef SPECULAR
// KHR_materials_specular at a point (Rust: combustion_optics::specular::
// DielectricSpecular): the factor × its texture's A, the linear colour × its texture's RGB.
struct DielectricSpecular {
    float factor;
    vec3 color;
};
#endif

struct BrdfInputs {
    vec3 base_color;          // linear RGB albedo of the dielectric part
    float metalness;          // 0 dielectric .. 1 conductor, linear blend of the lobes
    float alpha_x;            // GGX α along the tangent (already mapped)
    float alpha_y;            // GGX α along the bitangent
    vec3 conductor_eta;       // conductor η per channel (complex IOR η + ik)
    vec3 conductor_k;         // conductor k per channel
    float dielectric_eta;     // real IOR of the dielectric part
    float outside_eta;        // η_i of the surrounding medium
    float polarisation_weight;  // 0 = s, 1 = p, 0.5 unpolarised
    uint diffuse_model;       // DIFFUSE_MODEL_*
    float oren_nayar_sigma;   // radians
};

// v/|v|, or 0 when |v|² is 0, underflows, or is not finite (Rust: Vec3::normalize).
vec3 safe_normalize(vec3 v) {
    float l2 = dot(v, v);
    if (l2 > 0.0 && !isinf(l2)) {
        return v * (1.0 / sqrt(l2));
    }
    return vec3(0.0);
}

// Unit vector along the part of v orthogonal to unit n (Gram–Schmidt twice), or 0 if v
// is degenerate (zero, not finite, or within TANGENT_DEGENERATE_FRACTION_SQ of ±n).
vec3 shading_frame_orthogonal_unit(vec3 n, vec3 v) {
    float v2 = dot(v, v);
    if (!(v2 > 0.0 && !isinf(v2))) {
        return vec3(0.0);
    }
    vec3 r = v - n * dot(n, v);
    r = r - n * dot(n, r);
    if (dot(r, r) > TANGENT_DEGENERATE_FRACTION_SQ * v2) {
        return safe_normalize(r);
    }
    return vec3(0.0);
}

// Orthonormal frame as mat3 columns (t, b, n) from a possibly non-unit, non-orthogonal
// normal, tangent and bitangent (Rust: ShadingFrame::new). Tangent fallback: b⊥ × n,
// then a basis from n alone (Duff et al. 2017). A zero normal gives the zero matrix.
mat3 shading_frame(vec3 n_in, vec3 t_in, vec3 b_in) {
    vec3 n = safe_normalize(n_in);
    if (dot(n, n) == 0.0) {
        return mat3(0.0);
    }
    vec3 t = shading_frame_orthogonal_unit(n, t_in);
    if (dot(t, t) == 0.0) {
        vec3 bb = shading_frame_orthogonal_unit(n, b_in);
        if (dot(bb, bb) > 0.0) {
            t = cross(bb, n);
        } else {
            float sgn = n.z >= 0.0 ? 1.0 : -1.0;
            float a = -1.0 / (sgn + n.z);
            float bxy = n.x * n.y * a;
            t = vec3(1.0 + sgn * n.x * n.x * a, sgn * bxy, -sgn * n.x);
        }
    }
    return mat3(t, cross(n, t), n);
}

// The shading normal n made to face the unit direction to the eye v (Rust:
// combustion_optics::vec3::facing_view): kept where n·v ≥ FACING_COS_MIN, else turned
// towards v in the plane of n and v until n·v = FACING_COS_MIN (a normal exactly opposite
// v turns towards an arbitrary direction across v). Every pass that shades applies it to
// the base's and the coat's normals before building their frames; shading_frame then
// re-orthogonalises the tangent.
vec3 facing_view(vec3 n, vec3 v) {
    float c = dot(n, v);
    if (c >= FACING_COS_MIN) {
        return n;
    }
    vec3 across = n - v * c;
    across -= v * dot(v, across);  // twice (Gram–Schmidt): orthogonal to rounding
    float across2 = dot(across, across);
    if (across2 > 1e-20 && !isinf(across2)) {
        across *= 1.0 / sqrt(across2);
    } else {
        float sgn = v.z >= 0.0 ? 1.0 : -1.0;
        float a = -1.0 / (sgn + v.z);
        across = vec3(1.0 + sgn * v.x * v.x * a, sgn * v.x * v.y * a, -sgn * v.x);
    }
    return v * FACING_COS_MIN + across * sqrt(1.0 - FACING_COS_MIN * FACING_COS_MIN);
}

// World → local: (t·v, b·v, n·v) (Rust: ShadingFrame::to_local).
vec3 shading_frame_to_local(mat3 frame, vec3 v) {
    return vec3(dot(frame[0], v), dot(frame[1], v), dot(frame[2], v));
}

// Everything of f(v, l) that depends on the view alone (Rust: BrdfView): computed once
// per pixel by brdf_view, reused for every light by brdf_evaluate_view.
struct BrdfView {
    mat3 frame;
    vec3 v;                // v in the shading frame
    float ax;
    float ay;
    float metal;
    float w;
    vec2 visibility_half;  // (c_v, S_v) of smith_ggx_visibility_half
    float transmittance_v; // T_w(n·v) of the dielectric part (1 when there is none)
#if defined(FRESNEL_CURVE) || defined(ENERGY_COMPENSATION)
    float f0_dielectric;   // exact normal-incidence reflectances (seen from ηi): where the
    vec3 f0_conductor;     // Fresnel curves start, and what energy compensation scales by
#endif
#ifdef FRESNEL_F82
    float b_dielectric;    // F82 coefficients (fresnel_f82_coefficient) from the exact
    vec3 b_conductor;      // reflectance at cos θ = F82_COS
#endif
#ifdef D_BECKMANN
    float lambda_v;        // Beckmann's Smith Λ(v) (comparison variant)
#endif
#ifdef IRIDESCENCE
    // A thin film over the base (Rust: BrdfView::film; weight 0 where there is none) and
    // the dielectric's transmittance at n·v with it mixed in, per channel.
    ThinFilm film;
    vec3 film_reflectance_v;    // the film's R_w(n·v) over the dielectric (environment's)
    vec3 film_transmittance_v;
#endif
#ifdef ENERGY_COMPENSATION
    // Turquin 2019: each specular lobe × 1 + F₀ (1 − E)/E, F₀ the exact reflectance at
    // normal incidence (the outside medium's), E = E(n·v, α) of the white lobe.
    vec3 compensation_conductor;
    float compensation_dielectric;
#endif
#ifdef SPECULAR
    // The dielectric's specular strength and colour (Rust: BrdfView::specular), where
    // they are not the neutral 1 and 1 (specular_present): the clamped factor, F₀′ =
    // min(F₀ colour, 1) per channel and the bare dielectric's F₀.
    bool specular_present;
    float specular_factor;
    vec3 specular_f0;
    float bare_f0;
#endif
};

// The dielectric part's reflectance on the variant's curve (FRESNEL_CURVE variants).
#ifdef FRESNEL_CURVE
float brdf_dielectric_curve(BrdfView view, float cos_theta) {
#ifdef FRESNEL_F82
    return fresnel_f82(cos_theta, view.f0_dielectric, view.b_dielectric);
#else
    return fresnel_schlick(cos_theta, view.f0_dielectric);
#endif
}
#endif

BrdfView brdf_view(BrdfInputs m, vec3 n, vec3 t, vec3 b, vec3 v) {
    BrdfView view;
    view.frame = shading_frame(n, t, b);
    view.v = shading_frame_to_local(view.frame, safe_normalize(v));
    view.ax = clamp_alpha(m.alpha_x);
    view.ay = clamp_alpha(m.alpha_y);
    view.metal = min(max(m.metalness, 0.0), 1.0);
    view.w = min(max(m.polarisation_weight, 0.0), 1.0);
    view.visibility_half = smith_ggx_visibility_half(view.v, view.ax, view.ay);
#ifdef D_BECKMANN
    view.lambda_v = lambda_beckmann_anisotropic(view.v, view.ax, view.ay);
#endif
#if defined(FRESNEL_CURVE) || defined(ENERGY_COMPENSATION)
    view.f0_dielectric = polarised_weighted(fresnel_dielectric(1.0, m.outside_eta, m.dielectric_eta), view.w);
    view.f0_conductor = fresnel_conductor_rgb(1.0, m.outside_eta, m.conductor_eta, m.conductor_k, view.w);
#endif
#ifdef FRESNEL_CURVE
    // The cheaper, approximate variants (renderer setting FresnelModel::Schlick or F82;
    // their error against the full equations is measured in tests/parity.rs and the
    // report): a curve through the exact normal-incidence reflectance of η (dielectric)
    // and η + ik (conductor) seen from ηi (F82: and through the exact reflectance at
    // cos θ = 1/7), and 1 − F for the diffuse transmittance.
#ifdef FRESNEL_F82
    view.b_dielectric = fresnel_f82_coefficient(view.f0_dielectric,
        polarised_weighted(fresnel_dielectric(F82_COS, m.outside_eta, m.dielectric_eta), view.w));
    vec3 at_f82 = fresnel_conductor_rgb(F82_COS, m.outside_eta, m.conductor_eta, m.conductor_k, view.w);
    view.b_conductor = vec3(
        fresnel_f82_coefficient(view.f0_conductor.x, at_f82.x),
        fresnel_f82_coefficient(view.f0_conductor.y, at_f82.y),
        fresnel_f82_coefficient(view.f0_conductor.z, at_f82.z));
#endif
    view.transmittance_v = 1.0 - brdf_dielectric_curve(view, view.v.z);
#elif defined(NO_DIELECTRICS)
    view.transmittance_v = 1.0;
#else
    view.transmittance_v = view.metal < 1.0
        ? polarised_weighted(fresnel_dielectric_transmittance(view.v.z, m.outside_eta, m.dielectric_eta), view.w)
        : 1.0;
#endif
#ifdef ENERGY_COMPENSATION
    {
        float e = max(energy_white_albedo_lookup(view.v.z, 0.5 * (view.ax + view.ay)), 1e-3);
        float lost = (1.0 - e) / e;
        view.compensation_conductor = 1.0 + view.f0_conductor * lost;
        view.compensation_dielectric = 1.0 + view.f0_dielectric * lost;
    }
#endif
#ifdef IRIDESCENCE
    view.film = ThinFilm(0.0, 1.0, 0.0);
    view.film_reflectance_v = vec3(0.0);
    view.film_transmittance_v = vec3(view.transmittance_v);
#endif
#ifdef SPECULAR
    view.specular_present = false;
    view.specular_factor = 1.0;
    view.specular_f0 = vec3(0.0);
    view.bare_f0 = 0.0;
#endif
    return view;
}

#ifdef IRIDESCENCE
// brdf_view for a surface under a thin film (Rust: brdf_view_with_film): every Fresnel
// reflectance R becomes R + weight (R_film − R) per channel, the dielectric's
// transmittances T + weight ((1 − R_film) − T). No film where the weight or the
// thickness is 0.
// The film laid over a view (after its specular strength and colour, where the variant
// has them: the film lies over that interface).
void brdf_view_apply_film(inout BrdfView view, BrdfInputs m, ThinFilm film) {
    if (thin_film_is_present(film)) {
        view.film = ThinFilm(min(film.weight, 1.0), film.eta, film.thickness_nm);
        view.film_reflectance_v = thin_film_reflectance_weighted(
            view.v.z, m.outside_eta, view.film, vec3(m.dielectric_eta), vec3(0.0), view.w);
        view.film_transmittance_v = view.transmittance_v
            + view.film.weight * ((1.0 - view.film_reflectance_v) - view.transmittance_v);
    }
}

BrdfView brdf_view_with_film(BrdfInputs m, ThinFilm film, vec3 n, vec3 t, vec3 b, vec3 v) {
    BrdfView view = brdf_view(m, n, t, b, v);
    brdf_view_apply_film(view, m, film);
    return view;
}
#endif

// The material's diffuse lobe (Lambert or Oren–Nayar, by m.diffuse_model) for v and l
// in the shading frame.
// Specialised: only the models the scene has are tested for (NO_* defines); the last
// one left needs no test.
vec3 brdf_diffuse_lobe(BrdfInputs m, vec3 vl, vec3 ll) {
    vec3 rho = min(max(m.base_color, vec3(0.0)), vec3(1.0));
#if !defined(NO_LAMBERT) || !defined(NO_OREN_NAYAR_FULL)
#ifndef NO_OREN_NAYAR_QUALITATIVE
    if (m.diffuse_model == DIFFUSE_MODEL_OREN_NAYAR_QUALITATIVE) {
        return diffuse_oren_nayar_qualitative(rho, m.oren_nayar_sigma, OREN_NAYAR_A_CONSTANT_BRDF, vl, ll);
    }
#endif
#ifndef NO_LAMBERT
#ifndef NO_OREN_NAYAR_FULL
    if (m.diffuse_model == DIFFUSE_MODEL_OREN_NAYAR_FULL) {
        return diffuse_oren_nayar_full(rho, m.oren_nayar_sigma, vl, ll);
    }
#endif
    return diffuse_lambert(rho);
#else
    return diffuse_oren_nayar_full(rho, m.oren_nayar_sigma, vl, ll);
#endif
#else
    return diffuse_oren_nayar_qualitative(rho, m.oren_nayar_sigma, OREN_NAYAR_A_CONSTANT_BRDF, vl, ll);
#endif
}

// Reflectance of the dielectric part at the microfacet angle cos_h (full equations with
// the outside medium, or the comparison curve of a FRESNEL_CURVE variant).
float brdf_dielectric_fresnel(BrdfInputs m, BrdfView view, float cos_h) {
#ifdef FRESNEL_CURVE
    return brdf_dielectric_curve(view, cos_h);
#else
    return polarised_weighted(fresnel_dielectric(cos_h, m.outside_eta, m.dielectric_eta), view.w);
#endif
}

// Reflectance of the conductor part per channel at cos_h (as above).
vec3 brdf_conductor_fresnel(BrdfInputs m, BrdfView view, float cos_h) {
#ifdef FRESNEL_CURVE
    float x = 1.0 - cos_h;
    float x2 = x * x;
    vec3 schlick = view.f0_conductor + (1.0 - view.f0_conductor) * (x2 * x2 * x);
#ifdef FRESNEL_F82
    return clamp(schlick - view.b_conductor * (cos_h * x2 * x2 * x2), 0.0, 1.0);
#else
    return schlick;
#endif
#else
    return fresnel_conductor_rgb(cos_h, m.outside_eta, m.conductor_eta, m.conductor_k, view.w);
#endif
}

#ifdef SPECULAR
// KHR_materials_specular (Rust: DielectricSpecular::reflectance, ::transmittance): the
// dielectric's reflectance f (its curve's, at some angle) rescaled from F₀′ to 1 and
// weighted by the factor, F′ = factor (F₀′ + (1 − F₀′)(f − F₀)/(1 − F₀)) in [0, 1]; and
// what reaches the diffuse substrate, 1 − max_c F′_c.
vec3 specular_reflectance(BrdfView view, float f) {
    float shape = view.bare_f0 < 1.0 ? (f - view.bare_f0) / (1.0 - view.bare_f0) : 1.0;
    vec3 g = view.specular_f0;
    return clamp(view.specular_factor * (g + (1.0 - g) * shape), 0.0, 1.0);
}

float specular_transmittance(BrdfView view, float f) {
    vec3 r = specular_reflectance(view, f);
    return 1.0 - max(r.x, max(r.y, r.z));
}

// The dielectric's specular strength and colour laid on a view (before a film): the
// neutral 1 and 1 leave it as it is, bit for bit.
void brdf_view_apply_specular(inout BrdfView view, BrdfInputs m, DielectricSpecular s) {
    if (s.factor == 1.0 && all(equal(s.color, vec3(1.0)))) {
        return;
    }
    view.specular_present = true;
    view.specular_factor = clamp(s.factor, 0.0, 1.0);
    view.bare_f0 = polarised_weighted(fresnel_dielectric(1.0, m.outside_eta, m.dielectric_eta), 0.5);
    view.specular_f0 = min(view.bare_f0 * max(s.color, vec3(0.0)), vec3(1.0));
    if (view.metal < 1.0) {
        view.transmittance_v = specular_transmittance(view, brdf_dielectric_fresnel(m, view, view.v.z));
    }
#ifdef IRIDESCENCE
    view.film_transmittance_v = vec3(view.transmittance_v);
#endif
#ifdef ENERGY_COMPENSATION
    // Turquin's factor from the largest channel's F₀ = factor F₀′ (one factor for the
    // lobe, as without the extension).
    float e = max(energy_white_albedo_lookup(view.v.z, 0.5 * (view.ax + view.ay)), 1e-3);
    vec3 f0 = view.specular_factor * view.specular_f0;
    view.compensation_dielectric = 1.0 + max(f0.x, max(f0.y, f0.z)) * (1.0 - e) / e;
#endif
}
#endif

// The dispatchers: each slot of the lobe (distribution × visibility, the dielectric's
// Fresnel and transmittance, the conductor's Fresnel, the thin film, the energy
// compensation) as the variant's defines choose it. The #ifs live here alone, so that
// brdf_evaluate_view reads as the formula.

// D(h) · V(v, l): GGX (isotropic where the scene has no anisotropy) with the
// height-correlated Smith visibility by default; Beckmann's D with its own Λ, or the
// separable or approximate visibility, in the comparison variants.
float brdf_specular_lobe(BrdfView view, vec3 vl, vec3 ll, vec3 h) {
    float ax = view.ax;
    float ay = view.ay;
#ifdef D_BECKMANN
    // Comparison variant (combustion_renderer::Distribution::Beckmann): Beckmann's D with
    // its own Smith Λ, height-correlated 1/(1 + Λ_v + Λ_l) or, with SMITH_SEPARABLE,
    // 1/((1 + Λ_v)(1 + Λ_l)); V = G₂/(4 n·v n·l). (Hammon's fit is of GGX's term: with
    // Beckmann, SMITH_APPROXIMATE evaluates the height-correlated form.)
    float lambda_l = lambda_beckmann_anisotropic(ll, ax, ay);
#ifdef SMITH_SEPARABLE
    float g2 = 1.0 / ((1.0 + view.lambda_v) * (1.0 + lambda_l));
#else
    float g2 = 1.0 / (1.0 + view.lambda_v + lambda_l);
#endif
    return d_beckmann_anisotropic(h, ax, ay) * g2 / (4.0 * max(vl.z, COS_MIN) * max(ll.z, COS_MIN));
#else
    vec2 light_half = smith_ggx_visibility_half(ll, ax, ay);
#if defined(SMITH_SEPARABLE)
    // Comparison variant (combustion_renderer::Masking::Separable): G₁(v)·G₁(l), the form
    // of Cook–Torrance and several offline renderers; V = 1/((c_v + S_v)(c_l + S_l)).
    float visibility = 1.0 / ((view.visibility_half.x + view.visibility_half.y) * (light_half.x + light_half.y));
#elif defined(SMITH_APPROXIMATE)
    // Comparison variant (Masking::Approximate): Hammon 2017's fit of the
    // height-correlated term, V ≈ ½ / mix(2 n·l n·v, n·l + n·v, α), α = √(α_x α_y).
    float visibility = 0.5 / mix(2.0 * light_half.x * view.visibility_half.x, light_half.x + view.visibility_half.x, sqrt(ax * ay));
#else
    float visibility = 0.5 / (light_half.x * view.visibility_half.y + view.visibility_half.x * light_half.y);
#endif
#ifdef NO_ANISOTROPY
    return d_ggx(h, ax) * visibility;  // α_x = α_y: the isotropic form
#else
    return d_ggx_anisotropic(h, ax, ay) * visibility;
#endif
#endif  // D_BECKMANN
}

// The dielectric part's Fresnel transmittance towards l, T_w(n·l) (1 − the curve in a
// FRESNEL_CURVE variant).
float brdf_dielectric_transmittance(BrdfInputs m, BrdfView view, float cos_l) {
#ifdef FRESNEL_CURVE
    return 1.0 - brdf_dielectric_curve(view, cos_l);
#else
    return polarised_weighted(fresnel_dielectric_transmittance(cos_l, m.outside_eta, m.dielectric_eta), view.w);
#endif
}

// The dielectric part's weights at the half angle cos_h and towards l: `fresnel`, its
// specular reflectance F(v·h), and `diffuse_weight`, T(n·l) T(n·v) on the diffuse lobe;
// each mixed with the thin film's by its weight (IRIDESCENCE variants).
void brdf_dielectric_weights(BrdfInputs m, BrdfView view, float cos_h, float cos_l,
                             out vec3 fresnel, out vec3 diffuse_weight) {
    vec3 fresnel_base = vec3(brdf_dielectric_fresnel(m, view, cos_h));
    float transmittance_l = brdf_dielectric_transmittance(m, view, cos_l);
#ifdef SPECULAR
    if (view.specular_present) {
        fresnel_base = specular_reflectance(view, fresnel_base.x);
        transmittance_l = specular_transmittance(view, brdf_dielectric_fresnel(m, view, cos_l));
    }
#endif
    fresnel = fresnel_base;
    diffuse_weight = vec3(transmittance_l * view.transmittance_v);
#ifdef IRIDESCENCE
    if (view.film.weight > 0.0) {
        float eta_i = m.outside_eta;
        float eta_d = m.dielectric_eta;
        vec3 r_h = thin_film_reflectance_weighted(cos_h, eta_i, view.film, vec3(eta_d), vec3(0.0), view.w);
        vec3 r_l = thin_film_reflectance_weighted(cos_l, eta_i, view.film, vec3(eta_d), vec3(0.0), view.w);
        fresnel = fresnel_base + view.film.weight * (r_h - fresnel_base);
        diffuse_weight = (transmittance_l + view.film.weight * ((1.0 - r_l) - transmittance_l))
                       * view.film_transmittance_v;
    }
#endif
}

// The conductor part's reflectance at cos_h per channel, mixed with the thin film's by
// its weight (IRIDESCENCE variants).
vec3 brdf_conductor_reflectance(BrdfInputs m, BrdfView view, float cos_h) {
    vec3 fresnel = brdf_conductor_fresnel(m, view, cos_h);
#ifdef IRIDESCENCE
    if (view.film.weight > 0.0) {
        vec3 r_h = thin_film_reflectance_weighted(cos_h, m.outside_eta, view.film, m.conductor_eta, m.conductor_k, view.w);
        fresnel += view.film.weight * (r_h - fresnel);
    }
#endif
    return fresnel;
}

// The energy compensation of the dielectric and the conductor lobes (Turquin 2019;
// ENERGY_COMPENSATION variants), 1 otherwise.
float brdf_dielectric_compensation(BrdfView view) {
#ifdef ENERGY_COMPENSATION
    return view.compensation_dielectric;
#else
    return 1.0;
#endif
}

vec3 brdf_conductor_compensation(BrdfView view) {
#ifdef ENERGY_COMPENSATION
    return view.compensation_conductor;
#else
    return vec3(1.0);
#endif
}

// Whether the scene's materials have a dielectric part, a conductor part (specialised
// variants leave out what none has).
#ifdef NO_DIELECTRICS
const bool BRDF_DIELECTRICS = false;
#else
const bool BRDF_DIELECTRICS = true;
#endif
#ifdef NO_CONDUCTORS
const bool BRDF_CONDUCTORS = false;
#else
const bool BRDF_CONDUCTORS = true;
#endif

// f(v, l) = (1 − metal) [D V F_d (v·h) + T_d(n·l) T_d(n·v) f_diffuse] + metal D V F_c(v·h),
// each F and T with the film's mixed in, each lobe × its energy compensation.
vec3 brdf_evaluate_view(BrdfInputs m, BrdfView view, vec3 l) {
    vec3 vl = view.v;
    vec3 ll = shading_frame_to_local(view.frame, safe_normalize(l));
    if (!(vl.z > 0.0 && ll.z > 0.0)) {
        return vec3(0.0);
    }
    float metal = view.metal;
    vec3 sum = vl + ll;
    float len = sqrt(dot(sum, sum));
    vec3 h = sum * (1.0 / len);
    float cos_h = min(0.5 * len, 1.0);
    float lobe = brdf_specular_lobe(view, vl, ll, h);

    vec3 result = vec3(0.0);
    if (BRDF_DIELECTRICS && metal < 1.0) {
        vec3 fresnel;
        vec3 diffuse_weight;
        brdf_dielectric_weights(m, view, cos_h, ll.z, fresnel, diffuse_weight);
        vec3 spec = lobe * fresnel * brdf_dielectric_compensation(view);
        result = (1.0 - metal) * (spec + diffuse_weight * brdf_diffuse_lobe(m, vl, ll));
    }
    if (BRDF_CONDUCTORS && metal > 0.0) {
        result += metal * lobe * brdf_conductor_reflectance(m, view, cos_h) * brdf_conductor_compensation(view);
    }
    return result;
}

// f(v, l) per channel, NOT multiplied by n·l; 0 when n·l ≤ 0 or n·v ≤ 0.
// Specular: D_GGX,aniso(h) · V_Smith,height-correlated(v, l) · F(v·h), v·h = |v + l|/2;
// conductor lobe F = R_w(η_i; η + ik per channel), dielectric lobe F = R_w(η_i; η_d) with
// TIR (white). Diffuse (dielectric part only): base_color × diffuse model × T_w(n·l)
// T_w(n·v), the Fresnel transmittance in and out (symmetric, so f stays reciprocal).
vec3 brdf_evaluate(BrdfInputs m, vec3 n, vec3 t, vec3 b, vec3 v, vec3 l) {
    return brdf_evaluate_view(m, brdf_view(m, n, t, b, v), l);
}

// The clear coat over the BRDF (KHR_materials_clearcoat). GLSL mirror of
// crates/optics/src/coat.rs: f = c S_c(v, l) R_w(v·h; ηi, ηc) + A(v) A(l) f_base(v, l),
// A(ω) = 1 − c R_w(n_c·ω; ηi, ηc), S_c the isotropic GGX lobe about the coat's normal.
struct CoatInputs {
    float factor;             // c ∈ [0, 1]; 0: no coat
    float alpha;              // GGX α of the coat (isotropic)
    float eta;                // real IOR of the coat (glTF: 1.5)
    float outside_eta;        // η_i of the medium above it
    float polarisation_weight;  // 0 = s, 1 = p, 0.5 unpolarised
};

struct CoatView {
    mat3 frame;
    vec3 v;
    float alpha;
    float factor;
    float w;
    vec2 visibility_half;
    float attenuation_v;      // A(v)
};

// A(ω) = 1 − c R_w(cos; ηi, ηc) (1 − c below the horizon).
float coat_attenuation(CoatInputs c, float cos_theta) {
    float factor = min(max(c.factor, 0.0), 1.0);
    return 1.0 - factor * polarised_weighted(fresnel_dielectric(cos_theta, c.outside_eta, c.eta),
                                             c.polarisation_weight);
}

CoatView coat_view(CoatInputs c, vec3 n, vec3 v) {
    CoatView view;
    view.frame = shading_frame(n, vec3(0.0), vec3(0.0));
    view.v = shading_frame_to_local(view.frame, safe_normalize(v));
    view.alpha = clamp_alpha(c.alpha);
    view.factor = min(max(c.factor, 0.0), 1.0);
    view.w = min(max(c.polarisation_weight, 0.0), 1.0);
    view.visibility_half = smith_ggx_visibility_half(view.v, view.alpha, view.alpha);
    view.attenuation_v = coat_attenuation(c, view.v.z);
    return view;
}

// The coat's terms for light from l (world space; Rust: CoatTerms): x the coat's own
// reflection c S_c R_w(v·h), y A(l), z n_c·l.
vec3 coat_evaluate_view(CoatInputs c, CoatView view, vec3 l) {
    vec3 ll = shading_frame_to_local(view.frame, safe_normalize(l));
    float attenuation_l = coat_attenuation(c, ll.z);
    vec3 vl = view.v;
    if (!(vl.z > 0.0 && ll.z > 0.0) || view.factor == 0.0) {
        return vec3(0.0, attenuation_l, ll.z);
    }
    vec3 sum = vl + ll;
    float len = sqrt(dot(sum, sum));
    vec3 h = sum * (1.0 / len);
    float cos_h = min(0.5 * len, 1.0);
    vec2 light_half = smith_ggx_visibility_half(ll, view.alpha, view.alpha);
    float visibility = 0.5 / (light_half.x * view.visibility_half.y + view.visibility_half.x * light_half.y);
    float reflectance = polarised_weighted(fresnel_dielectric(cos_h, c.outside_eta, c.eta), view.w);
    return vec3(view.factor * d_ggx(h, view.alpha) * visibility * reflectance, attenuation_l, ll.z);
}

// The coated BRDF where coat and base share their normal, from the base's f(v, l) and
// the coat's terms for the same v and l: c S_c R_w + A(v) A(l) f_base.
vec3 coated(vec3 base, CoatView view, vec3 terms) {
    return vec3(terms.x) + (view.attenuation_v * terms.y) * base;
}

// The reflected radiance per unit irradiance, each layer lit with the cosine to its own
// normal: c S_c R_w (n_c·l)⁺ + A(v) A(l) f_base (n·l)⁺ (cos_base = n·l).
vec3 coated_radiance(vec3 base, float cos_base, CoatView view, vec3 terms) {
    float coat = terms.x * max(terms.z, 0.0);
    float attenuation = view.attenuation_v * terms.y * max(cos_base, 0.0);
    return vec3(coat) + attenuation * base;
}

// Sheen (KHR_materials_sheen). GLSL mirror of crates/optics/src/sheen.rs: the Charlie
// distribution and Estevez & Kulla's (2017) fitted visibility; the base under it scaled
// by min(1 − max(c) E(n·v), 1 − max(c) E(n·l)).
#define SHEEN_ALPHA_MIN 1e-3

// (2 + 1/α) sin^(1/α)θ / (2π) for a unit local microfacet normal; 0 below the horizon.
float d_charlie(vec3 m, float alpha) {
    if (!(m.z > 0.0)) {
        return 0.0;
    }
    alpha = clamp(alpha, SHEEN_ALPHA_MIN, 1.0);
    float inv = 1.0 / alpha;
    float sin2 = min(m.x * m.x + m.y * m.y, 1.0);
    if (!(sin2 > 0.0)) {
        return 0.0;
    }
    return (2.0 + inv) * pow(sin2, 0.5 * inv) / (2.0 * PI);
}

// Estevez & Kulla's L(x), coefficients blended between their α = 0 and 1 fits by (1 − α)².
float lambda_sheen_fit(float x, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t);
    float b = mix(3.82987, 3.32435, t);
    float c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t);
    float e = mix(-4.32054, -4.85967, t);
    float power = x > 0.0 ? pow(x, c) : 0.0;
    return a / (1.0 + b * power) + d * x + e;
}

// The sheen's Λ at cos θ.
float lambda_sheen(float cos_theta, float alpha) {
    alpha = clamp(alpha, SHEEN_ALPHA_MIN, 1.0);
    float c = min(abs(cos_theta), 1.0);
    return c < 0.5 ? exp(lambda_sheen_fit(c, alpha))
                   : exp(2.0 * lambda_sheen_fit(0.5, alpha) - lambda_sheen_fit(1.0 - c, alpha));
}

// 1/((1 + Λ(v) + Λ(l)) 4 n·v n·l) for local directions; 0 unless both are above.
float visibility_sheen(vec3 v, vec3 l, float alpha) {
    if (!(v.z > 0.0 && l.z > 0.0)) {
        return 0.0;
    }
    float cv = max(v.z, COS_MIN);
    float cl = max(l.z, COS_MIN);
    return 1.0 / ((1.0 + lambda_sheen(cv, alpha) + lambda_sheen(cl, alpha)) * 4.0 * cv * cl);
}

// The white sheen lobe D V for local v and l.
float sheen_lobe(vec3 v, vec3 l, float alpha) {
    if (!(v.z > 0.0 && l.z > 0.0)) {
        return 0.0;
    }
    return d_charlie(safe_normalize(v + l), alpha) * visibility_sheen(v, l, alpha);
}

// min(1 − max(c) E(n·v), 1 − max(c) E(n·l)).
float sheen_albedo_scaling(vec3 color, float albedo_v, float albedo_l) {
    float c = clamp(max(color.r, max(color.g, color.b)), 0.0, 1.0);
    return min(1.0 - c * albedo_v, 1.0 - c * albedo_l);
}

#endif // COMBUSTION_BRDF_GLSL
