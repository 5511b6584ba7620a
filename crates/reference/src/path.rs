//! Light that bounces, in f64: a unidirectional path tracer over the scene alone, the
//! ground truth that the renderer's GPU path tracer and its real-time frame are measured
//! against. It shares nothing with the GPU path but the [`combustion_scene::Scene`]: the
//! surfaces are [`crate::shading`]'s (the scene's materials and textures read in f64),
//! their reflection the optics crate's f64 BRDF under its layers, the rays this crate's
//! BVH.
//!
//! Each pixel's estimate is the mean of [`PathTracing::samples`] independent paths, with
//! its standard error from their spread ([`Estimate`]). A path:
//!
//! - **Starts** where the pixel's primary ray meets the scene, through the pixel's centre,
//!   its textures filtered at the pixel's footprint: the one-bounce reference's surface
//!   ([`SceneShading::surface`]). Blended surfaces in front of it (alphaMode BLEND) are
//!   each the start of a path of their own and composited over it as the one-bounce
//!   reference composites them.
//! - **At every surface it meets** adds the surface's emission (every emissive surface is
//!   a light that paths find by their own sampling: no light sampling of emitters, so no
//!   weight), and each punctual light's f(v, l) E (n·l) times its exact visibility
//!   through the shadow casters (next-event estimation: the one-bounce reference's
//!   direct light, with exact visibility). A surface of an unlit material
//!   (KHR_materials_unlit) shows its base colour and ends the path.
//! - **Bounces** by sampling the surface's reflection: one of the strategies the
//!   environment's integral combines (GGX's visible normals of the base lobe reflected
//!   about v, Heitz 2018, isotropic or anisotropic; cosine-weighted directions for the
//!   diffuse and the sheen; a coat's visible normals about its own normal where there is
//!   a coat), chosen uniformly, the sample weighted by f (n·l) over the strategies' mean
//!   density (the one-sample balance heuristic, so every strategy's lobe is covered and
//!   none is counted twice). Directions below the shading normal's horizon carry
//!   nothing, as the one-bounce reference lights nothing from there.
//! - **Meets** the next surface along the sampled direction (back faces of single-sided
//!   materials passed, as the primary rays pass them; a blended surface is met with
//!   probability α, else passed), or escapes to the environment, whose radiance it then
//!   adds (the environment is found by the bounces' own sampling, like emitters).
//! - **Ends** after [`PathTracing::max_depth`] surfaces have been lit (1: direct light
//!   alone, the one-bounce reference with the environment traced), or earlier by Russian
//!   roulette from the [`ROULETTE_START`]th surface on: the path goes on with
//!   probability q = min(0.95, max channel of its throughput) and its throughput is
//!   divided by q, which keeps the estimate unbiased.
//!
//! glTF occlusion textures are not applied: the path meets the geometry they stand for.
//! Light through transmissive surfaces (KHR_materials_transmission, volume) is followed
//! as the one-bounce reference follows it (`crate::transmission`: refracted exactly,
//! what lies beyond shaded by its direct light and environment); only their reflection
//! bounces. Deterministic: the same settings give the same estimates.

use combustion_optics::brdf::{brdf_evaluate_view, brdf_view_layered, BrdfView};
use combustion_optics::environment::{
    pdf_ggx_vndf_reflection, sample_cosine, sample_ggx_vndf, Estimate, SplitMix64,
};
use combustion_optics::layers::{layered_radiance, layers_view, LayersView};
use combustion_optics::microfacet::clamp_alpha;
use combustion_optics::vec3::{ShadingFrame, Vec3 as OpticsVec3};
use glam::DVec3;

use crate::primary::{next_seen, per_pixel, seen_surface};
use crate::shading::{SceneShading, SurfacePoint};
use crate::transmission::TRANSMISSION_DEPTH;
use crate::visibility::surface_offset;
use crate::{Ray, SceneBvh};

/// The surface (counted from 1, the one the primary ray meets) from which Russian
/// roulette may end a path.
pub const ROULETTE_START: u32 = 3;

/// The largest survival probability Russian roulette gives a path.
const ROULETTE_MAX: f64 = 0.95;

/// How a path-traced frame is sampled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PathTracing {
    /// Paths per pixel (at least 2 for a standard error).
    pub samples: u32,
    /// The most surfaces a path lights (1: direct light alone).
    pub max_depth: u32,
    /// The pseudo-random sequence's seed: the same seed gives the same image.
    pub seed: u64,
}

impl Default for PathTracing {
    /// 64 paths a pixel of up to 16 surfaces, seed 0.
    fn default() -> Self {
        PathTracing {
            samples: 64,
            max_depth: 16,
            seed: 0,
        }
    }
}

/// A scene's frame path traced in f64: [`SceneShading`]'s surfaces, lit by its lights
/// through `casters` (the shadow casters, [`SceneBvh::shadow_casters`]) and its
/// environment.
pub struct PathTracer<'s, 'a> {
    shading: &'s SceneShading<'a>,
    casters: &'s SceneBvh,
    tracing: PathTracing,
}

/// One surface's reflection prepared for its view: what [`PathTracer`] samples and
/// evaluates.
struct Reflection {
    view: BrdfView<f64>,
    layered: LayersView,
    frame: ShadingFrame<f64>,
    v_local: OpticsVec3<f64>,
    alpha: (f64, f64),
    /// The coat's frame, v in it and its α, where there is a coat.
    coat: Option<(ShadingFrame<f64>, OpticsVec3<f64>, f64)>,
}

fn optics(v: DVec3) -> OpticsVec3<f64> {
    OpticsVec3::new(v.x, v.y, v.z)
}

fn glam(v: OpticsVec3<f64>) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

impl Reflection {
    /// `surface`'s reflection towards its viewer; `None` where the viewer is below its
    /// shading normal's horizon (nothing is reflected).
    fn of(surface: &SurfacePoint) -> Option<Reflection> {
        let (n, t, b, v) = (
            optics(surface.n),
            optics(surface.t),
            optics(surface.b),
            optics(surface.v),
        );
        let frame = ShadingFrame::new(n, t, b);
        let v_local = frame.to_local(v.normalize());
        if v_local.z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let m = &surface.brdf;
        let coat = surface
            .layers
            .coat
            .filter(|c| c.inputs.factor > 0.0)
            .and_then(|c| {
                let coat_frame = ShadingFrame::from_normal(c.normal);
                let coat_v = coat_frame.to_local(v.normalize());
                (coat_v.z > 0.0).then_some((coat_frame, coat_v, clamp_alpha(c.inputs.alpha)))
            });
        Some(Reflection {
            view: brdf_view_layered(
                m,
                surface.layers.film.as_ref(),
                surface.layers.specular.as_ref(),
                n,
                t,
                b,
                v,
            ),
            layered: layers_view(&surface.layers, n, v),
            frame,
            v_local,
            alpha: (clamp_alpha(m.alpha_x), clamp_alpha(m.alpha_y)),
            coat,
        })
    }

    fn strategies(&self) -> u32 {
        if self.coat.is_some() {
            3
        } else {
            2
        }
    }

    /// The strategies' mean density of the world direction `l` (per steradian).
    fn density(&self, l: OpticsVec3<f64>) -> f64 {
        let local = self.frame.to_local(l);
        let (ax, ay) = self.alpha;
        let mut sum = pdf_ggx_vndf_reflection(self.v_local, local, ax, ay)
            + local.z.max(0.0) * std::f64::consts::FRAC_1_PI;
        if let Some((coat_frame, coat_v, coat_alpha)) = &self.coat {
            sum +=
                pdf_ggx_vndf_reflection(*coat_v, coat_frame.to_local(l), *coat_alpha, *coat_alpha);
        }
        sum / f64::from(self.strategies())
    }

    /// The radiance reflected towards the viewer per unit radiance arriving from the
    /// world direction `l`, times the cosine: f(v, l) (n·l) under the layers.
    fn reflected(
        &self,
        m: &combustion_optics::brdf::BrdfInputs<f64>,
        l: OpticsVec3<f64>,
    ) -> [f64; 3] {
        let f = brdf_evaluate_view(m, &self.view, l);
        layered_radiance(&self.layered, f, self.frame.to_local(l).z, l)
    }

    /// A sampled world direction and its weight f (n·l) / density; `None` where the
    /// sample carries nothing (below the horizon, zero density).
    fn sample(
        &self,
        m: &combustion_optics::brdf::BrdfInputs<f64>,
        random: &mut SplitMix64,
    ) -> Option<(DVec3, [f64; 3])> {
        let pick = random.next_f64() * f64::from(self.strategies());
        let (u1, u2) = (random.next_f64(), random.next_f64());
        let (ax, ay) = self.alpha;
        let l = if pick < 1.0 {
            let h = sample_ggx_vndf(self.v_local, ax, ay, u1, u2);
            self.frame
                .to_world(h * (2.0 * self.v_local.dot(h)) - self.v_local)
        } else if pick < 2.0 || self.coat.is_none() {
            self.frame.to_world(sample_cosine(u1, u2))
        } else {
            let (coat_frame, coat_v, coat_alpha) = self.coat?;
            let h = sample_ggx_vndf(coat_v, coat_alpha, coat_alpha, u1, u2);
            coat_frame.to_world(h * (2.0 * coat_v.dot(h)) - coat_v)
        }
        .normalize();
        // Nothing is lit from below the base's horizon unless a coat's normal faces it.
        let below_base =
            self.frame.to_local(l).z.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
        let below_coat = self
            .coat
            .is_none_or(|(coat_frame, _, _)| coat_frame.to_local(l).z <= 0.0);
        if below_base && below_coat {
            return None;
        }
        let density = self.density(l);
        if !(density > 0.0 && density.is_finite()) {
            return None;
        }
        let reflected = self.reflected(m, l);
        let weight = reflected.map(|r| r / density);
        weight
            .iter()
            .all(|w| w.is_finite())
            .then_some((glam(l), weight))
    }
}

impl<'s, 'a> PathTracer<'s, 'a> {
    /// `shading`'s frame path traced with `tracing`'s settings, its lights' visibility
    /// through `casters`. The shading's own visibility and environment settings are not
    /// used: paths trace both.
    pub fn new(shading: &'s SceneShading<'a>, casters: &'s SceneBvh, tracing: PathTracing) -> Self {
        PathTracer {
            shading,
            casters,
            tracing,
        }
    }

    /// The radiance pixel (`x`, `y`) shows, with its standard error; `None` where its
    /// ray meets no opaque surface.
    pub fn pixel(&self, x: u32, y: u32) -> Option<Estimate> {
        let opaque = self.shading.surface(x, y)?;
        let blended = self.shading.blended_surfaces(x, y);
        let width = u64::from(self.shading.width());
        let pixel = u64::from(y) * width + u64::from(x);
        let samples = self.tracing.samples.max(1);
        let (mut sum, mut squares) = ([0.0; 3], [0.0; 3]);
        for sample in 0..samples {
            let mut random = SplitMix64::new(
                self.tracing
                    .seed
                    .wrapping_mul(0x9E37_79B9_7F4A_7C15)
                    .wrapping_add(pixel.wrapping_mul(0xD1B5_4A32_D192_ED03))
                    .wrapping_add(u64::from(sample).wrapping_mul(0x8CB9_2BA7_2F3D_8DD7)),
            );
            let behind = self.path(&opaque, &mut random);
            let layers: Vec<(SurfacePoint, [f64; 3])> = blended
                .iter()
                .map(|surface| (*surface, self.path(surface, &mut random)))
                .collect();
            let radiance = SceneShading::blended_over(&layers, behind);
            for c in 0..3 {
                sum[c] += radiance[c];
                squares[c] += radiance[c] * radiance[c];
            }
        }
        let count = f64::from(samples);
        let mean = sum.map(|s| s / count);
        let standard_error = std::array::from_fn(|c| {
            let variance =
                (squares[c] / count - mean[c] * mean[c]).max(0.0) * count / (count - 1.0).max(1.0);
            (variance / count).sqrt()
        });
        Some(Estimate {
            mean,
            standard_error,
        })
    }

    /// [`PathTracer::pixel`] for every pixel, row-major from the top-left, on up to
    /// `threads` threads.
    pub fn render(&self, threads: usize) -> Vec<Option<Estimate>> {
        per_pixel(
            self.shading.width(),
            self.shading.height(),
            threads,
            |x, y| self.pixel(x, y),
        )
    }

    /// One path's radiance from `first` towards its viewer.
    fn path(&self, first: &SurfacePoint, random: &mut SplitMix64) -> [f64; 3] {
        let mut radiance = [0.0; 3];
        let mut throughput = [1.0; 3];
        let mut surface = *first;
        let add = |radiance: &mut [f64; 3], throughput: &[f64; 3], light: [f64; 3]| {
            for c in 0..3 {
                radiance[c] += throughput[c] * light[c];
            }
        };
        for depth in 1..=self.tracing.max_depth {
            let Some(material) = self.material(&surface) else {
                break;
            };
            if material.unlit {
                add(&mut radiance, &throughput, surface.brdf.base_color);
                break;
            }
            add(&mut radiance, &throughput, surface.emitted);
            // A transmissive surface reflects with the diffuse share 1 − transmission;
            // what passes through it is followed as the one-bounce reference does.
            let mut reflecting = surface;
            if material.is_transmissive() {
                reflecting.brdf.base_color = surface
                    .brdf
                    .base_color
                    .map(|c| c * (1.0 - surface.transmission));
                let through = self
                    .shading
                    .transmitted(&surface, material, TRANSMISSION_DEPTH - 1);
                let out = layers_view(&surface.layers, optics(surface.n), optics(surface.v))
                    .through_layers_v();
                let weight = (1.0 - surface.brdf.metalness) * surface.transmission * out;
                let passed =
                    std::array::from_fn(|c| weight * surface.brdf.base_color[c] * through[c]);
                add(&mut radiance, &throughput, passed);
            }
            add(
                &mut radiance,
                &throughput,
                self.shading.direct_light(&reflecting, Some(self.casters)),
            );
            if depth == self.tracing.max_depth {
                break;
            }
            // Bounce.
            let Some(reflection) = Reflection::of(&reflecting) else {
                break;
            };
            let Some((direction, weight)) = reflection.sample(&reflecting.brdf, random) else {
                break;
            };
            for c in 0..3 {
                throughput[c] *= weight[c];
            }
            if depth >= ROULETTE_START {
                let q = throughput
                    .iter()
                    .fold(0.0f64, |m, &t| m.max(t))
                    .min(ROULETTE_MAX);
                if random.next_f64() >= q {
                    break;
                }
                throughput = throughput.map(|t| t / q);
            }
            let origin = DVec3::from(surface.hit.position);
            match self.next_surface(origin, direction, random) {
                Some(next) => surface = next,
                None => {
                    if let Some(environment) = &self.shading.scene.environment {
                        add(
                            &mut radiance,
                            &throughput,
                            environment.radiance(direction.to_array()),
                        );
                    }
                    break;
                }
            }
        }
        radiance
    }

    /// The material of `surface`'s object.
    fn material(&self, surface: &SurfacePoint) -> Option<&'a combustion_scene::Material> {
        let scene = self.shading.scene;
        scene
            .materials
            .get(scene.objects.get(surface.hit.object)?.material)
    }

    /// The surface a ray from `origin` along unit `direction` meets, as seen from
    /// `origin`: back faces of single-sided materials passed, a blended surface met with
    /// probability α; `None` where it escapes.
    fn next_surface(
        &self,
        origin: DVec3,
        direction: DVec3,
        random: &mut SplitMix64,
    ) -> Option<SurfacePoint> {
        let scene = self.shading.scene;
        let ray = Ray::new(origin.to_array(), direction.to_array());
        let mut t_min = surface_offset(origin.to_array());
        loop {
            let (hit, material) =
                next_seen(scene, self.shading.bvh, &ray, &mut t_min, f64::INFINITY)?;
            let surface = seen_surface(scene, &ray, &hit)
                .and_then(|seen| self.shading.surface_seen_from(seen, origin))?;
            if !material.is_blended() || random.next_f64() < surface.alpha.clamp(0.0, 1.0) {
                return Some(surface);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use combustion_scene::builtin_scene;

    /// No lobe creates energy: for every surface the built-in scenes show (on a coarse
    /// grid of their pixels: plastics, metals of measured spectra, anisotropic metal,
    /// coats, sheens, thin films, specular colours, steep normal maps), the sampler's
    /// mean weight — its estimate of the directional albedo ∫ f (n·l) dl — is at most 1
    /// within four standard errors.
    #[test]
    fn no_lobe_reflects_more_than_arrives() {
        let mut largest: (f64, String) = (0.0, String::new());
        for name in [
            "spheres",
            "hard-cases",
            "gold-copper",
            "dielectrics",
            "diffuse-models",
            "clearcoat",
            "sheen",
            "iridescence",
            "specular",
            "normal-mapped",
        ] {
            let scene = builtin_scene(name).unwrap();
            let bvh = SceneBvh::new(&scene);
            let shading = SceneShading::new(&scene, &bvh, &scene.lights, 48, 32);
            let mut random = SplitMix64::new(7);
            for y in (1..32).step_by(4) {
                for x in (1..48).step_by(4) {
                    let Some(surface) = shading.surface(x, y) else {
                        continue;
                    };
                    let Some(reflection) = Reflection::of(&surface) else {
                        continue;
                    };
                    let samples = 4096;
                    let (mut sum, mut squares) = ([0.0; 3], [0.0; 3]);
                    for _ in 0..samples {
                        let weight = reflection
                            .sample(&surface.brdf, &mut random)
                            .map_or([0.0; 3], |(_, w)| w);
                        for c in 0..3 {
                            sum[c] += weight[c];
                            squares[c] += weight[c] * weight[c];
                        }
                    }
                    for c in 0..3 {
                        let mean = sum[c] / f64::from(samples);
                        let error = ((squares[c] / f64::from(samples) - mean * mean).max(0.0)
                            / f64::from(samples))
                        .sqrt();
                        assert!(
                            mean <= 1.0 + 4.0 * error,
                            "{name} pixel ({x}, {y}) channel {c}: albedo {mean} ± {error}"
                        );
                        if mean > largest.0 {
                            largest = (mean, format!("{name} ({x}, {y}) ± {error:.1e}"));
                        }
                    }
                }
            }
        }
        eprintln!("largest albedo: {largest:?}");
    }
}
