//! The rendering equation against an environment, in f64: the oracle that image-based
//! lighting is measured against.
//!
//! L_o(v) = ∫_Ω f(v, l) L(l) (n·l) dl, estimated by Monte Carlo with multiple importance
//! sampling (balance heuristic) of two strategies, one sample of each per iteration:
//! the GGX distribution of visible normals (Heitz 2018) reflected about v, which follows
//! the specular lobe however sharp, and cosine-weighted directions, which follow the
//! diffuse lobe. The sequence is a fixed pseudo-random one (so results reproduce), and
//! the estimate comes with its standard error σ/√N from the samples' own variance.

use crate::brdf::{brdf_evaluate_view, brdf_view_layered, BrdfInputs};
use crate::layers::{layered_radiance, layers_view, Layers};
use crate::microfacet::{clamp_alpha, d_ggx_anisotropic, lambda_ggx_anisotropic};
use crate::vec3::{ShadingFrame, Vec3};

/// A Monte Carlo estimate per RGB channel with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The estimated integral.
    pub mean: [f64; 3],
    /// σ/√N of each channel (one standard deviation of the mean).
    pub standard_error: [f64; 3],
}

/// How many samples an estimate takes, and where its pseudo-random sequence starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampling {
    /// Samples of each strategy.
    pub iterations: u32,
    /// The sequence's seed: the same seed gives the same estimate.
    pub seed: u64,
}

/// A small, fast, reproducible generator (SplitMix64): uniform f64 in [0, 1).
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator started from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1), 53 random bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// A microfacet normal drawn from GGX's distribution of normals visible from `v` (local
/// frame, v.z > 0), for uniform `u1`, `u2` in [0, 1) (Heitz 2018, "Sampling the GGX
/// Distribution of Visible Normals").
pub fn sample_ggx_vndf(v: Vec3<f64>, alpha_x: f64, alpha_y: f64, u1: f64, u2: f64) -> Vec3<f64> {
    let (ax, ay) = (clamp_alpha(alpha_x), clamp_alpha(alpha_y));
    // The view in the hemisphere configuration.
    let vh = Vec3::new(ax * v.x, ay * v.y, v.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3::new(-vh.y, vh.x, 0.0) * (1.0 / len2.sqrt())
    } else {
        Vec3::new(1.0, 0.0, 0.0)
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = 2.0 * std::f64::consts::PI * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let p3 = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    let nh = t1 * p1 + t2 * p2 + vh * p3;
    Vec3::new(ax * nh.x, ay * nh.y, nh.z.max(0.0)).normalize()
}

/// The density (per steradian of l) of [`sample_ggx_vndf`]'s normal reflected about v:
/// D(h) G₁(v) / (4 v.z), h = (v + l)/|v + l|; 0 below either horizon.
pub fn pdf_ggx_vndf_reflection(v: Vec3<f64>, l: Vec3<f64>, alpha_x: f64, alpha_y: f64) -> f64 {
    if !(v.z > 0.0 && l.z > 0.0) {
        return 0.0;
    }
    let h = (v + l).normalize();
    let g1 = 1.0 / (1.0 + lambda_ggx_anisotropic(v, alpha_x, alpha_y));
    d_ggx_anisotropic(h, alpha_x, alpha_y) * g1 / (4.0 * v.z)
}

/// A cosine-weighted direction about z (density z/π), for uniform `u1`, `u2`.
pub fn sample_cosine(u1: f64, u2: f64) -> Vec3<f64> {
    let r = u1.sqrt();
    let phi = 2.0 * std::f64::consts::PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u1).max(0.0).sqrt())
}

/// Lagarde & de Rousiers' (2014, eq. 58) specular occlusion from a glTF occlusion value
/// `occlusion` (in [0, 1]) at the cosine `nv` of the view to the normal and the lobe's α:
/// weaker than the diffuse occlusion at normal incidence and on smooth surfaces. GLSL
/// twin: lighting_terms.glsl's `specular_occlusion_of`.
pub fn specular_occlusion(nv: f64, alpha: f64, occlusion: f64) -> f64 {
    ((nv.max(0.0) + occlusion).powf((-16.0 * alpha - 1.0).exp2()) - 1.0 + occlusion).clamp(0.0, 1.0)
}

/// The environment's light at a surface under a glTF occlusion value `occlusion`, as the
/// split sum applies it (docs/gbuffer.md): the diffuse term × `occlusion`, the rest ×
/// [`specular_occlusion`] at `nv` and the lobe's `alpha`. `whole` is the unoccluded
/// estimate and `without_diffuse` the same samples' estimate with a black base colour
/// (every strategy's directions and pdfs are independent of it), so the diffuse term is
/// their difference, sample for sample. A coat's and a sheen's lobes count as the rest.
/// The standard error is `whole`'s (both factors are at most 1). An occlusion of 1 (or
/// NaN: none) returns `whole`.
pub fn occluded_environment(
    whole: Estimate,
    without_diffuse: &Estimate,
    nv: f64,
    alpha: f64,
    occlusion: f64,
) -> Estimate {
    if occlusion.is_nan() || occlusion >= 1.0 {
        return whole;
    }
    let specular = specular_occlusion(nv, alpha, occlusion);
    Estimate {
        mean: std::array::from_fn(|c| {
            without_diffuse.mean[c] * specular
                + (whole.mean[c] - without_diffuse.mean[c]) * occlusion
        }),
        standard_error: whole.standard_error,
    }
}

/// L_o(v) = ∫ f(v, l) L(l) (n·l) dl for the BRDF `m` at a surface with normal, tangent
/// and bitangent `n`, `t`, `b` (world space, as [`crate::brdf::brdf_evaluate`] takes
/// them), viewed from `v`, under the environment `radiance` (world direction the light
/// comes from → W·sr⁻¹·m⁻² per channel), with `sampling`'s samples of each strategy.
/// Zero when n·v ≤ 0.
pub fn integrate_environment(
    m: &BrdfInputs<f64>,
    n: Vec3<f64>,
    t: Vec3<f64>,
    b: Vec3<f64>,
    v: Vec3<f64>,
    radiance: impl Fn([f64; 3]) -> [f64; 3],
    sampling: Sampling,
) -> Estimate {
    integrate_environment_layered(m, &Layers::default(), n, t, b, v, radiance, sampling)
}

/// As [`integrate_environment`], under `layers` ([`crate::layers`]: a clear coat, each
/// layer lit with the cosine to its own normal, and a sheen): with a third strategy
/// where there is a coat, GGX's visible normals of the coat about its own normal, in the
/// balance heuristic (the sheen's broad lobe is covered by the cosine-weighted one).
#[allow(clippy::too_many_arguments)] // the surface's frame, as integrate_environment's
pub fn integrate_environment_layered(
    m: &BrdfInputs<f64>,
    layers: &Layers,
    n: Vec3<f64>,
    t: Vec3<f64>,
    b: Vec3<f64>,
    v: Vec3<f64>,
    radiance: impl Fn([f64; 3]) -> [f64; 3],
    sampling: Sampling,
) -> Estimate {
    let Sampling { iterations, seed } = sampling;
    let view = brdf_view_layered(
        m,
        layers.film.as_ref(),
        layers.specular.as_ref(),
        n,
        t,
        b,
        v,
    );
    let frame = ShadingFrame::new(n, t, b);
    let v_local = frame.to_local(v.normalize());
    let zero = Estimate {
        mean: [0.0; 3],
        standard_error: [0.0; 3],
    };
    if v_local.z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || iterations == 0 {
        return zero;
    }
    let (ax, ay) = (clamp_alpha(m.alpha_x), clamp_alpha(m.alpha_y));
    let layered = layers_view(layers, frame.to_world(Vec3::new(0.0, 0.0, 1.0)), v);
    // The coat's frame, v in it and its α: the third strategy samples its lobe.
    let coat = layers.coat.filter(|c| c.inputs.factor > 0.0).map(|c| {
        let coat_frame = ShadingFrame::from_normal(c.normal);
        (
            coat_frame,
            coat_frame.to_local(v.normalize()),
            clamp_alpha(c.inputs.alpha),
        )
    });
    let strategies = if coat.is_some() { 3 } else { 2 };
    let mut rng = SplitMix64::new(seed);
    let mut sum = [0.0; 3];
    let mut sum_squares = [0.0; 3];
    for _ in 0..iterations {
        // One sample of each strategy; their balance-heuristic weights make the set's
        // sum one unbiased sample of the integral.
        let mut pair = [0.0; 3];
        for strategy in 0..strategies {
            let (u1, u2) = (rng.next_f64(), rng.next_f64());
            let world = match (strategy, &coat) {
                (0, _) => {
                    let h = sample_ggx_vndf(v_local, ax, ay, u1, u2);
                    frame.to_world(h * (2.0 * v_local.dot(h)) - v_local)
                }
                (1, _) => frame.to_world(sample_cosine(u1, u2)),
                (_, Some((coat_frame, coat_v, coat_alpha))) => {
                    if coat_v.z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                        continue;
                    }
                    let h = sample_ggx_vndf(*coat_v, *coat_alpha, *coat_alpha, u1, u2);
                    coat_frame.to_world(h * (2.0 * coat_v.dot(h)) - *coat_v)
                }
                _ => unreachable!("two strategies without a coat"),
            };
            let l = frame.to_local(world);
            let mut pdf_sum = pdf_ggx_vndf_reflection(v_local, l, ax, ay)
                + l.z.max(0.0) * std::f64::consts::FRAC_1_PI;
            let f = brdf_evaluate_view(m, &view, world);
            match &coat {
                None => {
                    if l.z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                        continue;
                    }
                }
                Some((coat_frame, coat_v, coat_alpha)) => {
                    let coat_l = coat_frame.to_local(world);
                    pdf_sum += pdf_ggx_vndf_reflection(*coat_v, coat_l, *coat_alpha, *coat_alpha);
                }
            }
            let reflected = layered_radiance(&layered, f, l.z, world);
            if !(pdf_sum > 0.0 && pdf_sum.is_finite()) {
                continue;
            }
            let light = radiance([world.x, world.y, world.z]);
            // Balance heuristic: weight pdf_s / Σ pdf, over pdf_s: 1 / Σ pdf.
            for c in 0..3 {
                pair[c] += reflected[c] * light[c] / pdf_sum;
            }
        }
        for c in 0..3 {
            sum[c] += pair[c];
            sum_squares[c] += pair[c] * pair[c];
        }
    }
    let count = f64::from(iterations);
    let mut out = zero;
    for c in 0..3 {
        let mean = sum[c] / count;
        let variance = (sum_squares[c] / count - mean * mean).max(0.0);
        out.mean[c] = mean;
        out.standard_error[c] = (variance / count).sqrt();
    }
    out
}

/// The directional albedo ∫ f(v, l) (n·l) dl: [`integrate_environment`] under a uniform
/// environment of radiance 1 (a white furnace).
pub fn directional_albedo(
    m: &BrdfInputs<f64>,
    n: Vec3<f64>,
    t: Vec3<f64>,
    b: Vec3<f64>,
    v: Vec3<f64>,
    sampling: Sampling,
) -> Estimate {
    integrate_environment(m, n, t, b, v, |_| [1.0; 3], sampling)
}

/// Where the GGX albedo tables over (μ = n·v, r) put their entries (the renderer's
/// environment and energy-compensation tables; the sheen's stay cell-centred, whose
/// steep rise at grazing wants an entry at μ = 1/64): vertex-centred, entry i
/// of `size` at i/(size − 1), so that r = 1 and μ = 1 (normal incidence on the roughest
/// surface) are entries, not clamped edges (cell-centred tables stopped at (size − ½)/size
/// and overstated the albedo at r = 1 by up to 5 %). μ's first entry is evaluated at
/// [`TABLE_MU_MIN`] (the integrals degenerate at μ = 0).
pub fn table_coordinate(i: usize, size: usize) -> f64 {
    i as f64 / (size - 1) as f64
}

/// The μ of a table's first entry (the view along the horizon, where the integrals
/// degenerate): 1e-3.
pub const TABLE_MU_MIN: f64 = 1e-3;

/// The μ of entry `i` of a table of `size` ([`table_coordinate`], at least
/// [`TABLE_MU_MIN`]).
pub fn table_mu(i: usize, size: usize) -> f64 {
    table_coordinate(i, size).max(TABLE_MU_MIN)
}

/// The directional albedo of the GGX specular lobe alone with a white Fresnel term (F =
/// 1), E(μ, α) = ∫ D V (n·l) dl for a view at cos θ = `mu` (isotropic α, height-
/// correlated Smith): the energy single scattering keeps, 1 − E what it loses. By
/// sampling GGX's visible normals with `samples` Hammersley points, where each sample's
/// weight is G₂/G₁(v) = (1 + Λ(v))/(1 + Λ(v) + Λ(l)) exactly.
pub fn specular_albedo_white(mu: f64, alpha: f64, samples: u32) -> f64 {
    let mu = mu.clamp(1e-6, 1.0);
    let v = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let a = clamp_alpha(alpha);
    let lambda_v = lambda_ggx_anisotropic(v, a, a);
    let mut sum = 0.0;
    for i in 0..samples {
        let u1 = f64::from(i) / f64::from(samples);
        let u2 = f64::from(i.reverse_bits()) * (1.0 / 4_294_967_296.0);
        let h = sample_ggx_vndf(v, a, a, u1, u2);
        let l = h * (2.0 * v.dot(h)) - v;
        if l.z > 0.0 {
            sum += (1.0 + lambda_v) / (1.0 + lambda_v + lambda_ggx_anisotropic(l, a, a));
        }
    }
    sum / f64::from(samples.max(1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::DiffuseModel;

    fn inputs(metalness: f64, alpha: f64) -> BrdfInputs<f64> {
        BrdfInputs {
            base_color: [0.8, 0.5, 0.2],
            metalness,
            alpha_x: alpha,
            alpha_y: alpha,
            conductor_eta: [0.18, 0.42, 1.37],
            conductor_k: [3.42, 2.35, 1.77],
            dielectric_eta: 1.5,
            outside_eta: 1.0,
            polarisation_weight: 0.5,
            diffuse_model: DiffuseModel::Lambert,
            oren_nayar_sigma: 0.0,
        }
    }

    /// Calls `visit(l, dω)` at the midpoints of a `steps` × `steps` (θ, φ) grid over the
    /// upper hemisphere.
    fn upper_hemisphere_midpoints(steps: u32, mut visit: impl FnMut(Vec3<f64>, f64)) {
        let (d_theta, d_phi) = (
            std::f64::consts::FRAC_PI_2 / f64::from(steps),
            2.0 * std::f64::consts::PI / f64::from(steps),
        );
        for i in 0..steps {
            let theta = (f64::from(i) + 0.5) * d_theta;
            for j in 0..steps {
                let phi = (f64::from(j) + 0.5) * d_phi;
                let l = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                visit(l, theta.sin() * d_theta * d_phi);
            }
        }
    }

    fn axes() -> (Vec3<f64>, Vec3<f64>, Vec3<f64>) {
        (
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
    }

    #[test]
    fn vndf_density_matches_the_sampler_above_the_horizon() {
        // ∫ pdf dl over the upper hemisphere by a fine (θ, φ) midpoint rule: 1 less what
        // the sampled normals reflect below the horizon.
        let v = Vec3::new(0.6, 0.0, 0.8);
        let (ax, ay) = (0.5, 0.25);
        let mut total = 0.0;
        upper_hemisphere_midpoints(400, |l, d_omega| {
            total += pdf_ggx_vndf_reflection(v, l, ax, ay) * d_omega;
        });
        // The sampler's own share of directions above the horizon must be that integral
        // (density and sampler agree), and a real share of them reflects below.
        let mut rng = SplitMix64::new(3);
        let draws = 400_000;
        let above = (0..draws)
            .filter(|_| {
                let h = sample_ggx_vndf(v, ax, ay, rng.next_f64(), rng.next_f64());
                (h * (2.0 * v.dot(h)) - v).z > 0.0
            })
            .count() as f64
            / f64::from(draws);
        let sigma = (above * (1.0 - above) / f64::from(draws)).sqrt();
        assert!(
            (total - above).abs() < 4.0 * sigma + 1e-3,
            "∫ pdf = {total}, sampled share above the horizon {above}"
        );
        assert!(total < 1.0 && total > 0.5, "∫ pdf = {total}");
    }

    #[test]
    fn white_specular_albedo_matches_quadrature_and_loses_energy_when_rough() {
        for (mu, alpha) in [(0.9, 0.2), (0.5, 0.6), (0.2, 1.0)] {
            let sampled = specular_albedo_white(mu, alpha, 4096);
            let v = Vec3::new((1.0f64 - mu * mu).sqrt(), 0.0, mu);
            let mut q = 0.0;
            upper_hemisphere_midpoints(800, |l, d_omega| {
                let h = (v + l).normalize();
                q += d_ggx_anisotropic(h, alpha, alpha)
                    * crate::microfacet::visibility_smith_ggx_height_correlated_anisotropic(
                        v, l, alpha, alpha,
                    )
                    * l.z
                    * d_omega;
            });
            assert!(
                (sampled - q).abs() < 2e-3,
                "μ {mu}, α {alpha}: {sampled} vs {q}"
            );
            assert!(sampled < 1.0);
        }
        // Single scattering loses a real share of the energy of rough surfaces.
        assert!(specular_albedo_white(0.5, 1.0, 4096) < 0.8);
        assert!(specular_albedo_white(0.9, 0.05, 4096) > 0.99);
    }

    #[test]
    fn lambert_with_a_matched_interface_reflects_its_albedo_exactly() {
        // η_d = η_i: no specular, T = 1, so ∫ ρ/π cos = ρ for any sample set: the
        // estimator's pair sum is exactly ρ·(pdf_cos / Σ pdf + …), unbiased with a
        // small error.
        let mut m = inputs(0.0, 0.3);
        m.dielectric_eta = 1.0;
        let (n, t, b) = axes();
        let e = directional_albedo(
            &m,
            n,
            t,
            b,
            Vec3::new(0.3, 0.1, 0.9),
            Sampling {
                iterations: 20_000,
                seed: 1,
            },
        );
        for c in 0..3 {
            assert!(
                (e.mean[c] - m.base_color[c]).abs() < 4.0 * e.standard_error[c] + 1e-12,
                "{e:?}"
            );
            assert!(e.standard_error[c] < 2e-3, "{e:?}");
        }
    }

    #[test]
    fn a_conductor_furnace_agrees_with_quadrature() {
        // The directional albedo of gold by MIS against a deterministic midpoint rule
        // over (θ, φ) of the same BRDF (rough enough for the rule to converge).
        let m = inputs(1.0, 0.5);
        let (n, t, b) = axes();
        let v = Vec3::new(0.5, 0.0, 0.866_025_403_784_438_6);
        let e = directional_albedo(
            &m,
            n,
            t,
            b,
            v,
            Sampling {
                iterations: 40_000,
                seed: 7,
            },
        );
        let view = crate::brdf_view(&m, n, t, b, v);
        let mut q = [0.0; 3];
        upper_hemisphere_midpoints(600, |l, d_omega| {
            let f = brdf_evaluate_view(&m, &view, l);
            for c in 0..3 {
                q[c] += f[c] * l.z * d_omega;
            }
        });
        for c in 0..3 {
            assert!(
                (e.mean[c] - q[c]).abs() < 4.0 * e.standard_error[c] + 1e-4,
                "MIS {e:?} against quadrature {q:?}"
            );
        }
    }
}
