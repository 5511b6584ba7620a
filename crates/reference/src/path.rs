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
//!   its textures read at their finest level, as at every other surface a path meets
//!   (a ray through the pixel's centre has no footprint; the one-bounce reference
//!   filters its primary surfaces over the pixel's footprint). Blended surfaces in front of it (alphaMode BLEND) are
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
//!   alone — the lights, and the emitters and environment the last surface's sampled
//!   direction finds: the one-bounce reference with the environment traced), or earlier by Russian
//!   roulette from the [`ROULETTE_START`]th surface on: the path goes on with
//!   probability q = min(0.95, max channel of its throughput) and its throughput is
//!   divided by q, which keeps the estimate unbiased.
//!
//! - **Passes through** a transmissive surface (KHR_materials_transmission) with
//!   probability ½ (else it samples the reflection, whose diffuse share is then
//!   1 − transmission), weighted by (1 − metalness) · transmission · base colour and what
//!   a coat or sheen lets out, by the rules of the one-bounce reference's transmission
//!   (crate::transmission), each polarisation's Fresnel term mixed by the material's
//!   polarisation weight at every interface:
//!   - a thin wall (no volume) passes (1 − R)/(1 + R) of the light, straight through
//!     where it is smooth; a rough one's direction is drawn from the spread of its two
//!     rough interfaces by rejection (the one-bounce reference integrates the same
//!     spread);
//!   - a volume (KHR_materials_volume) takes the entry's transmittance, refracts into
//!     the medium (η_outside/η_material), is absorbed on its way (Beer–Lambert), and at
//!     every interface it meets inside (whichever object's) leaves or is reflected back
//!     with the Fresnel equations' probabilities (always reflected past the critical
//!     angle), for up to [`VOLUME_INTERFACES`]; where it leaves, the path goes on. A
//!     rough volume's interfaces refract about the shading normal, as the one-bounce
//!     reference's do.
//!
//! glTF occlusion textures are not applied: the path meets the geometry they stand for.
//! Shadow rays pass blended and transmissive objects, as the renderer's shadows do (they
//! cast none); paths that reach a light through glass do so by their bounces only
//! where the light is found by sampling (emitters, the environment). Deterministic: the
//! same settings give the same estimates.

use combustion_optics::brdf::{brdf_evaluate_view, brdf_view_layered, BrdfView};
use combustion_optics::environment::{
    pdf_ggx_vndf_reflection, sample_cosine, sample_ggx_vndf, Estimate, SplitMix64,
};
use combustion_optics::layers::{layered_radiance, layers_view, LayersView};
use combustion_optics::microfacet::{clamp_alpha, lambda_ggx_anisotropic};
use combustion_optics::vec3::{ShadingFrame, Vec3 as OpticsVec3};
use glam::DVec3;

use crate::primary::{next_seen, per_pixel, seen_surface};
use crate::shading::{SceneShading, SurfacePoint};
use crate::transmission::{crossing, facing, refract, refract_local};
use crate::visibility::surface_offset;
use crate::{Ray, SceneBvh};

/// The surface (counted from 1, the one the primary ray meets) from which Russian
/// roulette may end a path.
pub const ROULETTE_START: u32 = 3;

/// The largest survival probability Russian roulette gives a path.
const ROULETTE_MAX: f64 = 0.95;

/// The probability with which a path at a transmissive surface passes through it rather
/// than sampling its reflection.
const TRANSMISSION_CHOICE: f64 = 0.5;

/// The most interfaces a path crosses or is reflected at inside one volume before it is
/// dropped (its light lost).
pub const VOLUME_INTERFACES: u32 = 64;

/// The most directions drawn for a rough thin wall's spread before the path is sent
/// straight through (see [`PathTracer`]'s module docs).
const THIN_WALL_DRAWS: u32 = 64;

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
        let (blended, opaque) = self.shading.layers_at_finest_level(x, y);
        let opaque = opaque?;
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
        // One step past the deepest surface lit: what the last one's sampled direction
        // meets adds its emission (its direct light), nothing more.
        for depth in 1..=self.tracing.max_depth.saturating_add(1) {
            let Some(material) = self.material(&surface) else {
                break;
            };
            if material.unlit {
                add(&mut radiance, &throughput, surface.brdf.base_color);
                break;
            }
            add(&mut radiance, &throughput, surface.emitted);
            if depth > self.tracing.max_depth {
                break;
            }
            // A transmissive surface reflects with the diffuse share 1 − transmission; the
            // rest of what is not reflected passes through it (sampled with probability
            // ½ against the reflection).
            let mut reflecting = surface;
            let mut transmits = 0.0;
            if material.is_transmissive() {
                reflecting.brdf.base_color = surface
                    .brdf
                    .base_color
                    .map(|c| c * (1.0 - surface.transmission));
                transmits = (1.0 - surface.brdf.metalness) * surface.transmission;
            }
            add(
                &mut radiance,
                &throughput,
                self.shading.direct_light(&reflecting, Some(self.casters)),
            );
            // The last surface still samples a direction: what that finds (an emitter,
            // the environment) is its direct light; only what would be lit beyond is not.
            let last = depth == self.tracing.max_depth;
            let through = transmits > 0.0 && random.next_f64() < TRANSMISSION_CHOICE;
            let (origin, direction) = if through {
                let Some((origin, direction, weight)) = self.transmit(&surface, material, random)
                else {
                    break;
                };
                let out = layers_view(&surface.layers, optics(surface.n), optics(surface.v))
                    .through_layers_v();
                for c in 0..3 {
                    throughput[c] *= weight[c] * transmits * out * surface.brdf.base_color[c]
                        / TRANSMISSION_CHOICE;
                }
                (origin, direction)
            } else {
                let Some(reflection) = Reflection::of(&reflecting) else {
                    break;
                };
                let Some((direction, weight)) = reflection.sample(&reflecting.brdf, random) else {
                    break;
                };
                let chosen = if transmits > 0.0 {
                    1.0 - TRANSMISSION_CHOICE
                } else {
                    1.0
                };
                for c in 0..3 {
                    throughput[c] *= weight[c] / chosen;
                }
                (DVec3::from(surface.hit.position), direction)
            };
            if depth >= ROULETTE_START && !last {
                let q = throughput
                    .iter()
                    .fold(0.0f64, |m, &t| m.max(t))
                    .min(ROULETTE_MAX);
                if random.next_f64() >= q {
                    break;
                }
                throughput = throughput.map(|t| t / q);
            }
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

    /// A path through transmissive `surface` (of `material`) from its viewer: where it
    /// goes on from (the surface, or where it leaves the object's volume), its direction,
    /// and the share of light it carries through the interfaces (before the weight
    /// (1 − metalness) · transmission · base colour). `None` where it is lost.
    fn transmit(
        &self,
        surface: &SurfacePoint,
        material: &combustion_scene::Material,
        random: &mut SplitMix64,
    ) -> Option<(DVec3, DVec3, [f64; 3])> {
        let v = surface.v;
        let n = facing(surface.n, v);
        let position = DVec3::from(surface.hit.position);
        let (eta_i, eta_t) = (surface.brdf.outside_eta, surface.brdf.dielectric_eta);
        let w = surface.brdf.polarisation_weight;
        let film = surface.layers.film.as_ref();
        let (t, r) = crossing(n.dot(v).clamp(0.0, 1.0), eta_i, eta_t, film);
        match material.volume {
            None => {
                // A thin wall: both interfaces and the light between them, (1 − R)/(1 + R)
                // per polarisation.
                let through: [f64; 3] = std::array::from_fn(|c| {
                    (1.0 - w) * (1.0 - r.0[c]) / (1.0 + r.0[c])
                        + w * (1.0 - r.1[c]) / (1.0 + r.1[c])
                });
                let direction = self.thin_wall_direction(surface, n, random);
                Some((position, direction, through))
            }
            Some(volume) => {
                let inside = refract(-v, n, eta_i / eta_t)?;
                let entered: [f64; 3] = std::array::from_fn(|c| (1.0 - w) * t.0[c] + w * t.1[c]);
                let (exit, out, carried) = self.through_volume(
                    position,
                    inside,
                    (eta_t, eta_i),
                    volume.absorption(),
                    surface,
                    random,
                )?;
                Some((exit, out, std::array::from_fn(|c| entered[c] * carried[c])))
            }
        }
    }

    /// The direction light leaves a thin wall in towards its viewer's opposite side:
    /// straight on where it is smooth; a rough one's two interfaces (each of its α)
    /// refract it, in through a microfacet the view sees and out through one of the far
    /// wall's, the pair kept with probability of both refracted rays' masking (separable
    /// Smith G₁): the spread the one-bounce reference integrates (crate::transmission),
    /// drawn from exactly by rejection.
    fn thin_wall_direction(
        &self,
        surface: &SurfacePoint,
        n: DVec3,
        random: &mut SplitMix64,
    ) -> DVec3 {
        let v = surface.v;
        let (eta_i, eta_t) = (surface.brdf.outside_eta, surface.brdf.dielectric_eta);
        if surface.roughness.is_nan() || surface.roughness <= 0.0 || eta_i == eta_t {
            return -v;
        }
        let (ax, ay) = (surface.brdf.alpha_x, surface.brdf.alpha_y);
        let t = (surface.t - n * n.dot(surface.t)).normalize_or(n.any_orthonormal_vector());
        let b = n.cross(t);
        let v_local = OpticsVec3::new(v.dot(t), v.dot(b), v.dot(n));
        let g1_below = |d: OpticsVec3<f64>| {
            1.0 / (1.0 + lambda_ggx_anisotropic(OpticsVec3::new(d.x, d.y, -d.z), ax, ay))
        };
        for _ in 0..THIN_WALL_DRAWS {
            let m_in = sample_ggx_vndf(v_local, ax, ay, random.next_f64(), random.next_f64());
            let m_out_u = (random.next_f64(), random.next_f64());
            let accept = random.next_f64();
            let Some(inside) = refract_local(v_local * -1.0, m_in, eta_i / eta_t) else {
                continue;
            };
            let m_out = sample_ggx_vndf(inside * -1.0, ax, ay, m_out_u.0, m_out_u.1);
            let Some(out) = refract_local(inside, m_out, eta_t / eta_i) else {
                continue;
            };
            if inside.z < 0.0 && out.z < 0.0 && accept < g1_below(inside) * g1_below(out) {
                return (t * out.x + b * out.y + n * out.z).normalize();
            }
        }
        -v
    }

    /// Light inside a volume from `origin` along unit `direction`, the medium of index
    /// `indices.0` inside and `indices.1` outside, of absorption `sigma`: followed to the
    /// interface it meets next (whichever object's), absorbed on the way (Beer–Lambert),
    /// and there refracted out or reflected back in with the probabilities of the Fresnel
    /// equations (under `entered`'s thin film, as at the entry), until it leaves. Where it
    /// leaves, the direction it leaves in, and the share it carries (absorption, and the
    /// interfaces' transmittance where a film makes it differ from the probability). `None`
    /// where it escapes the scene without leaving a surface or is reflected inside more
    /// than [`VOLUME_INTERFACES`] times.
    fn through_volume(
        &self,
        mut origin: DVec3,
        mut direction: DVec3,
        (eta_inside, eta_outside): (f64, f64),
        sigma: [f64; 3],
        entered: &SurfacePoint,
        random: &mut SplitMix64,
    ) -> Option<(DVec3, DVec3, [f64; 3])> {
        let scene = self.shading.scene;
        let w = entered.brdf.polarisation_weight;
        let film = entered.layers.film.as_ref();
        let mut carried = [1.0; 3];
        for _ in 0..VOLUME_INTERFACES {
            let ray = Ray::new(origin.to_array(), direction.to_array());
            let hit = self.shading.bvh.closest_hit(
                &ray,
                surface_offset(origin.to_array()),
                f64::INFINITY,
            )?;
            let exit = seen_surface(scene, &ray, &hit)?;
            for (c, s) in sigma.iter().enumerate() {
                carried[c] *= (-s * hit.t).exp();
            }
            let point = DVec3::from(exit.position);
            // The exit's normal facing the way the light goes on (as the one-bounce
            // reference orients it).
            let mut outward = DVec3::from(exit.normal);
            if outward.dot(DVec3::from(exit.geometric_normal)) < 0.0 {
                outward = -outward;
            }
            if DVec3::from(exit.geometric_normal).dot(direction) < 0.0 {
                outward = -outward;
            }
            let outward = facing(outward, direction);
            let (t, r) = crossing(
                outward.dot(direction).clamp(0.0, 1.0),
                eta_inside,
                eta_outside,
                film,
            );
            let out = refract(direction, -outward, eta_inside / eta_outside);
            let transmittance: [f64; 3] = std::array::from_fn(|c| (1.0 - w) * t.0[c] + w * t.1[c]);
            let reflectance: [f64; 3] = std::array::from_fn(|c| (1.0 - w) * r.0[c] + w * r.1[c]);
            let mean = |x: [f64; 3]| (x[0] + x[1] + x[2]) / 3.0;
            let leave = match out {
                Some(_) => mean(transmittance) / (mean(transmittance) + mean(reflectance)),
                None => 0.0,
            };
            if random.next_f64() < leave {
                for c in 0..3 {
                    carried[c] *= transmittance[c] / leave;
                }
                return Some((point, out?, carried));
            }
            for c in 0..3 {
                carried[c] *= reflectance[c] / (1.0 - leave);
            }
            direction = (direction - 2.0 * direction.dot(outward) * outward).normalize();
            origin = point;
        }
        None
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
