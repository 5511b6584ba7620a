//! The f64 optics reference applied to a rendered frame: every pixel shaded again on the
//! CPU in f64 (`combustion_optics`) from exactly the G-buffer values the GPU wrote, and
//! the same f32 matrices, materials and lights it got, then compared with the GPU's HDR
//! radiance. The parity tests assert bounds on it; the viewer's error view shows it.
//!
//! With [`ReferenceShading::with_exact_visibility`], each light's term is also
//! multiplied by its exact visibility from the pixel's point, ray cast in f64 against the
//! scene's triangles (`combustion_reference`, which shares no code with the renderer):
//! the reference for frames with shadows, and [`shadow_mismatch`] counts the pixels
//! whose shadow-map verdict differs from it.

use combustion_optics::brdf::{brdf_evaluate_layered, BrdfInputs, DiffuseModel};
use combustion_optics::coat::{CoatInputs, CoatLayer};
use combustion_optics::diffuse::oren_nayar_sigma_from_roughness;
use combustion_optics::environment::{
    integrate_environment_layered, occluded_environment, Estimate, Sampling,
};
use combustion_optics::layers::{layered_radiance, layers_face, layers_view, Layers};
use combustion_optics::microfacet::{alpha_from_perceptual_roughness, anisotropic_alphas};
use combustion_optics::sheen::SheenInputs;
use combustion_optics::specular::DielectricSpecular;
use combustion_optics::thin_film::ThinFilm;
use combustion_optics::variants::{
    brdf_evaluate_variant, BrdfVariant, DistributionForm, FresnelForm, MaskingForm,
};
use combustion_optics::vec3::{facing_view, Vec3 as V};
use combustion_reference::SceneBvh;
use combustion_scene::{Environment, Light, Scene};

use crate::gbuffer::{anisotropy_direction_decode, octahedral_decode, GBufferTexel};
use crate::gpu_types::{
    conductor_from_base_color_table, material_table, GpuLight, GpuMaterial, LightingPush,
    LIGHT_KIND_DIRECTIONAL,
};
use crate::host::FrameInputs;
use crate::options::{Distribution, FresnelModel, Masking, ShadingOptions};
use crate::results::Frame;

/// Samples per axis of a light with a size in the exact visibility
/// ([`ReferenceShading::with_exact_visibility`]): 12² = 144 stratified shadow rays, whose
/// standard error at a penumbra is ≤ 0.56·√ℓ·N^(−3/4) ≈ 0.03 for a boundary crossing the
/// light's disc (`combustion_reference::visibility`).
pub const SIZED_LIGHT_SAMPLES_PER_AXIS: u32 = 12;

/// Radiance below which errors are measured absolutely: 1e-4 W·sr⁻¹·m⁻² is a third of an
/// 8-bit step after the tone curve and sRGB encoding at black (1e-4 · 12.92 · 255 = 0.33).
pub const RADIANCE_FLOOR: f64 = 1e-4;

/// A pixel as the lighting pass sees it, in f64: the BRDF inputs, the normal, tangent
/// and bitangent, the direction to the eye and the world position.
#[derive(Clone, Copy, Debug)]
pub struct PixelInputs {
    /// The BRDF's inputs, decoded from the G-buffer.
    pub brdf: BrdfInputs<f64>,
    /// The unit shading normal (world space).
    pub n: [f64; 3],
    /// The unit tangent (world space; the anisotropy direction).
    pub t: [f64; 3],
    /// The unit bitangent (world space), completing t and n.
    pub b: [f64; 3],
    /// The unit direction from the surface point to the eye.
    pub v: [f64; 3],
    /// The surface point's world position, reconstructed from depth.
    pub position: [f64; 3],
    /// The clear coat and the sheen over the BRDF, decoded from their targets.
    pub layers: Layers,
}

/// How the reference integrates an environment in [`error_map`]: Monte Carlo with
/// `iterations` samples of each strategy at one pixel in `stride` along each axis (the
/// pixel at stride/2 of each `stride`×`stride` block); the other pixels are not compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EnvironmentSampling {
    /// Samples of each strategy per compared pixel.
    pub iterations: u32,
    /// One pixel compared in each `stride` × `stride` block (at least 1).
    pub stride: u32,
}

/// What the lighting pass reads besides the G-buffer, as the GPU got it (f32).
pub struct ReferenceShading {
    /// The environment [`ReferenceShading::shade`] adds, and how it is sampled.
    environment: Option<(Environment, EnvironmentSampling)>,
    push: LightingPush,
    materials: Vec<GpuMaterial>,
    lights: Vec<GpuLight>,
    /// Per material: it emits (the reference adds the emission the G-buffer stored, as
    /// the lighting pass does; counted in [`ErrorMap::emissive_pixels`]).
    emits: Vec<bool>,
    /// The screen rectangles (x0, y0, x1, y1, inclusive) that hold every blended or
    /// transmissive object (the forward pass draws them over the G-buffer's surfaces,
    /// which is all this reference sees), their world boxes projected.
    blended: Vec<[u32; 4]>,
    /// Exact visibility: the scene's triangles and the frame's lights as given.
    visibility: Option<(std::sync::Arc<SceneBvh>, Vec<Light>)>,
    /// The environment's visibility: the scene's triangles and the rays per axis of
    /// each pixel's stratified cosine-distributed set
    /// ([`Self::with_environment_visibility`]).
    environment_visibility: Option<(std::sync::Arc<SceneBvh>, u32)>,
    /// Whether each direction the environment's integral samples is traced
    /// ([`Self::with_traced_environment`]) rather than the occlusion passes' V applied.
    environment_traced: bool,
    /// The BRDF's terms ([`BrdfVariant::EXACT`] unless [`ReferenceShading::with_variant`]).
    variant: BrdfVariant,
    /// One diffuse model for every material, as [`ShadingOptions::diffuse_override`].
    diffuse_override: Option<DiffuseModel>,
    width: u32,
    height: u32,
}

pub use crate::accel::ENVIRONMENT_RAY_OFFSET;

fn v3(a: [f64; 3]) -> V<f64> {
    V::new(a[0], a[1], a[2])
}

/// Unit normal `n` made to face the unit direction to the eye `v` ([`facing_view`]).
fn facing(n: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let f = facing_view(v3(n), v3(v));
    [f.x, f.y, f.z]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|c| c / l)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl ReferenceShading {
    /// For a frame of `scene` (as uploaded) with `inputs`' camera and lights, at
    /// `width`×`height`.
    pub fn new(scene: &Scene, inputs: &FrameInputs<'_>, width: u32, height: u32) -> Self {
        let camera = &inputs.camera;
        Self {
            push: LightingPush::new(
                camera.view_projection(width as f32 / height as f32),
                camera.position,
                inputs.lights.len() as u32,
                0,
            ),
            materials: material_table(scene, &[]),
            lights: inputs.lights.iter().map(GpuLight::new).collect(),
            emits: scene
                .materials
                .iter()
                .map(|m| {
                    m.emissive_texture.is_some()
                        || m.emissive_factor
                            .iter()
                            .any(|&e| e * m.emissive_strength != 0.0)
                })
                .collect(),
            blended: blended_rectangles(scene, inputs, width, height),
            width,
            height,
            environment: None,
            visibility: None,
            environment_visibility: None,
            environment_traced: false,
            variant: BrdfVariant::EXACT,
            diffuse_override: None,
        }
    }

    /// The same, shaded with the terms a comparison variant evaluates (its Fresnel curve,
    /// masking form, distribution, energy compensation and forced diffuse model; from
    /// [`combustion_optics::variants`], written from each term's own formula): what a
    /// frame rendered with `options` must match, so each variant's shader is checked
    /// against its claim, not only measured against the exact model.
    pub fn with_variant(self, options: &ShadingOptions) -> Self {
        Self {
            variant: brdf_variant(options),
            diffuse_override: options.diffuse_override.map(|d| match d {
                combustion_scene::DiffuseModel::Lambert => DiffuseModel::Lambert,
                combustion_scene::DiffuseModel::OrenNayarQualitative => {
                    DiffuseModel::OrenNayarQualitative
                }
                combustion_scene::DiffuseModel::OrenNayarFull => DiffuseModel::OrenNayarFull,
            }),
            ..self
        }
    }

    /// The same, with each light's term multiplied by its exact visibility from the
    /// pixel's point ([`SceneBvh::light_visible_fraction`], shadow rays leaving along the
    /// shading normal; the visible fraction of a light with a size, sampled with
    /// [`SIZED_LIGHT_SAMPLES_PER_AXIS`]² rays): `bvh` holds the frame's scene's shadow
    /// casters ([`SceneBvh::shadow_casters`]), `lights` the frame's lights (those
    /// [`ReferenceShading::new`] was given). The reference for frames with shadows.
    pub fn with_exact_visibility(self, bvh: std::sync::Arc<SceneBvh>, lights: &[Light]) -> Self {
        Self {
            visibility: Some((bvh, lights.to_vec())),
            ..self
        }
    }

    /// The same, with the environment blocked by the scene as the occlusion passes block
    /// it (`ambient-occlusion`, `ray-traced-occlusion`: one definition): the
    /// environment's light at each pixel as [`Self::shade_environment`] integrates it,
    /// with glTF occlusion and the cosine-weighted visibility V of the hemisphere
    /// combined by their minimum and applied as the split sum applies occlusion. V is
    /// the share of `rays_per_axis`² stratified cosine-distributed rays that hit none of
    /// `bvh`'s triangles, starting [`ENVIRONMENT_RAY_OFFSET`] × the distance from the eye
    /// along the normal, as the pass's do (its standard
    /// error at most 1/(2·rays_per_axis) for stratified rays; not in the estimate's).
    pub fn with_environment_visibility(
        self,
        bvh: std::sync::Arc<SceneBvh>,
        rays_per_axis: u32,
    ) -> Self {
        self.with_environment_blocked(bvh, rays_per_axis, false)
    }

    /// The environment blocked by `bvh`'s triangles, each sampled direction traced or
    /// (`traced` false) the visibility applied as the split sum applies occlusion.
    fn with_environment_blocked(
        self,
        bvh: std::sync::Arc<SceneBvh>,
        rays_per_axis: u32,
        traced: bool,
    ) -> Self {
        Self {
            environment_visibility: Some((bvh, rays_per_axis.max(1))),
            environment_traced: traced,
            ..self
        }
    }

    /// The same, with the environment blocked as the sampled environment with
    /// ray-traced occlusion blocks it: every direction the integral samples traced
    /// against `bvh`'s triangles from the pixel's point (offset as
    /// [`Self::with_environment_visibility`]'s rays), the environment's radiance 0 where
    /// a triangle is in the way — the rendering equation's direct environment light
    /// with the scene's geometry. glTF occlusion then applies what the traced directions
    /// have not already counted, as the split sum applies occlusion: min(1, occlusion /
    /// V), V the cosine-weighted visibility from `rays_per_axis`² stratified rays (so
    /// that the diffuse visibility is min(occlusion, V), the passes' rule).
    pub fn with_traced_environment(
        self,
        bvh: std::sync::Arc<SceneBvh>,
        rays_per_axis: u32,
    ) -> Self {
        self.with_environment_blocked(bvh, rays_per_axis, true)
    }

    /// Where the pixel at `p` (normal `n`) starts its environment visibility rays.
    fn environment_ray_origin(&self, p: [f64; 3], n: [f64; 3]) -> glam::DVec3 {
        let (n, p) = (glam::DVec3::from(n), glam::DVec3::from(p));
        p + n * (ENVIRONMENT_RAY_OFFSET * p.distance(glam::DVec3::from(self.camera_position())))
    }

    /// The cosine-weighted visibility of the hemisphere above `p` (normal `n`) against
    /// `bvh`: the share of `per_axis`² stratified cosine-distributed rays that leave.
    fn environment_visible(&self, bvh: &SceneBvh, p: [f64; 3], n: [f64; 3], per_axis: u32) -> f64 {
        // The ray-traced occlusion pass's offset: 2·10⁻⁴ of the distance from the eye
        // along the normal (past the depth's rounding at that distance).
        let origin = self.environment_ray_origin(p, n).to_array();
        let n = glam::DVec3::from(n);
        let t = n.any_orthonormal_vector();
        let b = n.cross(t);
        let mut open = 0u32;
        for i in 0..per_axis * per_axis {
            let u = (f64::from(i % per_axis) + 0.5) / f64::from(per_axis);
            let w = (f64::from(i / per_axis) + 0.5) / f64::from(per_axis);
            let (r, phi) = (u.sqrt(), std::f64::consts::TAU * w);
            let direction =
                t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u).max(0.0).sqrt();
            if bvh.direction_visible(origin, direction.to_array()) {
                open += 1;
            }
        }
        f64::from(open) / f64::from(per_axis * per_axis)
    }

    /// The exact visibility (1 or 0; a fraction for a light with a size) of the frame's
    /// light `light` at pixel (`x`, `y`)
    /// from its G-buffer texel, and n·l there: `None` on the background, without exact
    /// visibility, or where the light cannot light the pixel whether blocked or not
    /// (below its horizon, n·l ≤ 0; outside a spot light's cone or beyond a range).
    pub fn exact_visibility(
        &self,
        texel: &GBufferTexel,
        x: u32,
        y: u32,
        light: usize,
    ) -> Option<(f64, f64)> {
        let (bvh, lights) = self.visibility.as_ref()?;
        let p = self.pixel(texel, x, y)?;
        let gpu_light = self.lights.get(light)?;
        let (l, irradiance) = self.light_direction(gpu_light, p.position);
        let cos = p.n[0] * l[0] + p.n[1] * l[1] + p.n[2] * l[2];
        let reaches = irradiance.iter().any(|&e| e > 0.0);
        (cos > 0.0 && reaches).then(|| {
            let visible = bvh.light_visible_fraction(
                p.position,
                p.n,
                &lights[light],
                SIZED_LIGHT_SAMPLES_PER_AXIS,
            );
            (visible, cos)
        })
    }

    /// The unit direction from `position` to `light` and the irradiance it gives a
    /// surface facing it there (attenuation and range window included).
    fn light_direction(&self, light: &GpuLight, position: [f64; 3]) -> ([f64; 3], [f64; 3]) {
        let f = |a: [f32; 4]| a.map(f64::from);
        let p = f(light.position_or_direction);
        let power = f(light.power_kind);
        if light.power_kind[3] != LIGHT_KIND_DIRECTIONAL {
            let to = [p[0] - position[0], p[1] - position[1], p[2] - position[2]];
            let d2 = (to[0] * to[0] + to[1] * to[1] + to[2] * to[2]).max(1e-12);
            let l = normalize(to);
            let a = light.attenuation(l) * light.range_attenuation(d2) / d2;
            (l, [power[0] * a, power[1] * a, power[2] * a])
        } else {
            ([-p[0], -p[1], -p[2]], [power[0], power[1], power[2]])
        }
    }

    /// The same, adding the environment's radiance, integrated as `sampling` says
    /// ([`Self::shade_environment`]): the reference for frames of scenes lit by one.
    pub fn with_environment(self, environment: Environment, sampling: EnvironmentSampling) -> Self {
        Self {
            environment: Some((
                environment,
                EnvironmentSampling {
                    stride: sampling.stride.max(1),
                    ..sampling
                },
            )),
            ..self
        }
    }

    /// Whether a blended object (alphaMode BLEND) may cover pixel (`x`, `y`): the
    /// forward pass's surfaces are not in the G-buffer this reference shades from, so
    /// such pixels are not compared (the f64 scene reference, `combustion::end_to_end`,
    /// composites them).
    pub fn under_blended(&self, x: u32, y: u32) -> bool {
        self.blended
            .iter()
            .any(|r| (r[0]..=r[2]).contains(&x) && (r[1]..=r[3]).contains(&y))
    }

    /// Whether pixel (`x`, `y`) is compared: every pixel, or with an environment one
    /// per `stride`×`stride` block.
    pub fn compares(&self, x: u32, y: u32) -> bool {
        match &self.environment {
            Some((_, s)) => x % s.stride == s.stride / 2 && y % s.stride == s.stride / 2,
            None => true,
        }
    }

    /// The f64 radiance of pixel (`x`, `y`) from its G-buffer texel (`None`: background)
    /// under the frame's lights (not the environment: see [`Self::shade_environment`]).
    pub fn shade(&self, texel: &GBufferTexel, x: u32, y: u32) -> Option<[f64; 3]> {
        let pixel = self.pixel(texel, x, y)?;
        // KHR_materials_unlit: the base colour as the G-buffer stores it, unlit.
        if self
            .materials
            .get(usize::from(texel.material_direction[0]))
            .is_some_and(GpuMaterial::unlit)
        {
            return Some(pixel.brdf.base_color);
        }
        // The emission the lighting pass adds, as the G-buffer stored it.
        let mut radiance = self.shade_lights(&pixel);
        for (r, e) in radiance.iter_mut().zip(&texel.emissive_occlusion) {
            *r += e;
        }
        if let Some((environment, sampling)) = &self.environment {
            let from_environment = self
                .shade_environment(texel, x, y, environment, sampling.iterations)
                .map_or([0.0; 3], |e| e.mean);
            for c in 0..3 {
                radiance[c] += from_environment[c];
            }
        }
        Some(radiance)
    }

    /// The radiance the frame's lights give a pixel reconstructed as `p` (exact
    /// visibility included with [`ReferenceShading::with_exact_visibility`], the
    /// environment not): what [`ReferenceShading::shade`] adds up, open to a caller
    /// that perturbs the inputs (to measure how sensitive a pixel is to them).
    pub fn shade_lights(&self, p: &PixelInputs) -> [f64; 3] {
        let PixelInputs {
            brdf: m,
            n,
            t,
            b,
            v,
            position,
            layers,
        } = *p;
        let layered = layers_view(&layers, v3(n), v3(v));
        let mut radiance = [0.0; 3];
        for (index, light) in self.lights.iter().enumerate() {
            let (l, e) = self.light_direction(light, position);
            let cos = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
            // A coat with its own normal may face a light the base does not.
            if !layers_face(&layered, cos, v3(l)) {
                continue;
            }
            let mut visible = 1.0;
            if let Some((bvh, lights)) = &self.visibility {
                visible = bvh.light_visible_fraction(
                    position,
                    n,
                    &lights[index],
                    SIZED_LIGHT_SAMPLES_PER_AXIS,
                );
                if visible == 0.0 {
                    continue;
                }
            }
            // The comparison variants change the base's Fresnel only; a thin film and a
            // specular strength or colour are evaluated in the exact form.
            let brdf = if self.variant == BrdfVariant::EXACT
                || layers.film.is_some()
                || layers.specular.is_some()
            {
                brdf_evaluate_layered(
                    &m,
                    layers.film.as_ref(),
                    layers.specular.as_ref(),
                    v3(n),
                    v3(t),
                    v3(b),
                    v3(v),
                    v3(l),
                )
            } else {
                brdf_evaluate_variant(&m, &self.variant, v3(n), v3(t), v3(b), v3(v), v3(l))
            };
            let reflected = layered_radiance(&layered, brdf, cos, v3(l));
            for c in 0..3 {
                radiance[c] += reflected[c] * e[c] * visible;
            }
        }
        radiance
    }

    /// The camera position the frame was rendered from (f32, as the GPU got it).
    pub fn camera_position(&self) -> [f64; 3] {
        let [x, y, z, _] = self.push.camera_position.map(f64::from);
        [x, y, z]
    }

    /// The f64 environment oracle at pixel (`x`, `y`): the rendering equation
    /// ∫ f(v, l) L(l) (n·l) dl against `environment` for the pixel's G-buffer texel,
    /// integrated by Monte Carlo ([`integrate_environment_layered`], under the pixel's
    /// clear coat and sheen if it has them; `iterations` samples of each strategy, with its
    /// standard error). `None` on the background.
    pub fn shade_environment(
        &self,
        texel: &GBufferTexel,
        x: u32,
        y: u32,
        environment: &Environment,
        iterations: u32,
    ) -> Option<Estimate> {
        let p = self.pixel(texel, x, y)?;
        let seed = u64::from(y) << 32 | u64::from(x);
        // With traced directions, the environment is dark along those that meet the scene.
        let traced = match &self.environment_visibility {
            Some((bvh, _)) if self.environment_traced => {
                Some((bvh, self.environment_ray_origin(p.position, p.n).to_array()))
            }
            _ => None,
        };
        let integrate = |brdf: &BrdfInputs<f64>| {
            integrate_environment_layered(
                brdf,
                &p.layers,
                v3(p.n),
                v3(p.t),
                v3(p.b),
                v3(p.v),
                |l| match traced {
                    Some((bvh, origin)) if !bvh.direction_visible(origin, l) => [0.0; 3],
                    _ => environment.radiance(l),
                },
                Sampling { iterations, seed },
            )
        };
        let whole = integrate(&p.brdf);
        let mut occlusion = texel.emissive_occlusion[3];
        if occlusion.is_nan() {
            occlusion = 1.0;
        }
        if let Some((bvh, per_axis)) = &self.environment_visibility {
            let visible = || self.environment_visible(bvh, p.position, p.n, *per_axis);
            if !self.environment_traced {
                occlusion = occlusion.min(visible());
            } else if occlusion < 1.0 {
                let visible = visible();
                occlusion = if visible > 0.0 {
                    (occlusion / visible).min(1.0)
                } else {
                    1.0
                };
            }
        }
        if occlusion >= 1.0 {
            return Some(whole);
        }
        // glTF occlusion as the split sum applies it (`occluded_environment`), at the
        // lobe's α (an anisotropic lobe's mean α).
        let without_diffuse = integrate(&BrdfInputs {
            base_color: [0.0; 3],
            ..p.brdf
        });
        let nv = p.n[0] * p.v[0] + p.n[1] * p.v[1] + p.n[2] * p.v[2];
        let roughness = texel.normal_roughness_anisotropy[2];
        let alpha = if p.brdf.alpha_x == p.brdf.alpha_y {
            roughness * roughness
        } else {
            0.5 * (p.brdf.alpha_x + p.brdf.alpha_y)
        };
        Some(occluded_environment(
            whole,
            &without_diffuse,
            nv,
            alpha,
            occlusion,
        ))
    }

    /// What the lighting pass reconstructs at pixel (`x`, `y`) from its texel, in f64.
    pub fn pixel(&self, texel: &GBufferTexel, x: u32, y: u32) -> Option<PixelInputs> {
        if texel.depth >= 1.0 {
            return None;
        }
        let (push, materials) = (&self.push, &self.materials);
        let base_color = texel.base_color();
        let metalness = texel.base_color_metalness[3];
        let [nx, ny, roughness, strength] = texel.normal_roughness_anisotropy;
        let stored_n = octahedral_decode([nx, ny]);
        let [material_index, direction] = texel.material_direction;
        let material = &materials[material_index as usize];
        let t = anisotropy_direction_decode(stored_n, direction);

        let inv = push.inverse_view_projection.map(f64::from);
        let ndc = [
            (f64::from(x) + 0.5) / f64::from(self.width) * 2.0 - 1.0,
            (f64::from(y) + 0.5) / f64::from(self.height) * 2.0 - 1.0,
            f64::from(texel.depth),
            1.0,
        ];
        let mut world = [0.0; 4];
        for (row, w) in world.iter_mut().enumerate() {
            *w = (0..4).map(|col| inv[col * 4 + row] * ndc[col]).sum();
        }
        let position = [
            world[0] / world[3],
            world[1] / world[3],
            world[2] / world[3],
        ];
        let camera = push.camera_position.map(f64::from);
        let v = normalize([
            camera[0] - position[0],
            camera[1] - position[1],
            camera[2] - position[2],
        ]);

        // The stored normal made to face the eye, as the lighting pass does (the optics
        // crate's `facing_view`); the BRDF's frame re-orthogonalises `t` against it.
        let n = facing(stored_n, v);
        let b = cross(n, t);

        let alpha = alpha_from_perceptual_roughness(roughness);
        let (alpha_x, alpha_y) = anisotropic_alphas(alpha, strength);
        let f = |a: [f32; 4]| a.map(f64::from);
        let (rai, eta_out, k_pol) = (
            f(material.roughness_anisotropy_ior),
            f(material.conductor_eta_outside_ior),
            f(material.conductor_k_polarisation),
        );
        // Conductors derived from the base colour look η, k up per channel by stored code.
        let (mut conductor_eta, mut conductor_k) = (
            [eta_out[0], eta_out[1], eta_out[2]],
            [k_pol[0], k_pol[1], k_pol[2]],
        );
        if material.conductor_from_base_color() {
            let table = conductor_from_base_color_table();
            for (c, code) in texel.base_color_srgb8_code().into_iter().enumerate() {
                conductor_eta[c] = f64::from(table[code as usize][0]);
                conductor_k[c] = f64::from(table[code as usize][1]);
            }
        }
        let m = BrdfInputs {
            base_color,
            metalness,
            alpha_x,
            alpha_y,
            conductor_eta,
            conductor_k,
            dielectric_eta: rai[3],
            outside_eta: eta_out[3],
            polarisation_weight: k_pol[3],
            // The shader evaluates an unknown code as Lambert; so does its mirror.
            diffuse_model: self.diffuse_override.unwrap_or(
                DiffuseModel::try_from(material.diffuse_model_flags[0])
                    .unwrap_or(DiffuseModel::Lambert),
            ),
            oren_nayar_sigma: oren_nayar_sigma_from_roughness(roughness),
        };
        // The coat's target: octahedral normal, perceptual roughness, weight.
        let [cx, cy, coat_roughness, coat_weight] = texel.clearcoat;
        let coat = (coat_weight > 0.0).then(|| CoatLayer {
            inputs: CoatInputs {
                factor: coat_weight,
                alpha: alpha_from_perceptual_roughness(coat_roughness),
                eta: f64::from(material.clearcoat[2]),
                outside_eta: m.outside_eta,
                polarisation_weight: m.polarisation_weight,
            },
            normal: v3(facing(octahedral_decode([cx, cy]), v)),
        });
        // The thin film's target: weight, thickness in nm; its IOR from the material.
        let [film_weight, film_thickness_nm] = texel.film;
        let film = (film_weight > 0.0 && film_thickness_nm > 0.0).then(|| ThinFilm {
            weight: film_weight,
            eta: f64::from(material.film[1]),
            thickness_nm: film_thickness_nm,
        });
        // The specular target: colour (rgb), factor (a); none where it is the neutral 1.
        let [specular_r, specular_g, specular_b, specular_factor] = texel.specular;
        let specular = Some(DielectricSpecular {
            factor: specular_factor,
            color: [specular_r, specular_g, specular_b],
        })
        .filter(DielectricSpecular::is_present);
        // The sheen's target: linear colour, perceptual roughness.
        let [sr, sg, sb, sheen_roughness] = texel.sheen;
        let sheen = (sr.max(sg).max(sb) > 0.0).then_some(SheenInputs {
            color: [sr, sg, sb],
            alpha: sheen_roughness * sheen_roughness,
        });
        Some(PixelInputs {
            brdf: m,
            n,
            t,
            b,
            v,
            position,
            layers: Layers {
                coat,
                sheen,
                film,
                specular,
            },
        })
    }

    fn emits(&self, texel: &GBufferTexel) -> bool {
        self.emits
            .get(texel.material_direction[0] as usize)
            .copied()
            .unwrap_or(false)
    }
}

/// The terms `options` shades with, as the optics crate's variant names them.
pub fn brdf_variant(options: &ShadingOptions) -> BrdfVariant {
    BrdfVariant {
        fresnel: match options.fresnel {
            FresnelModel::Full => FresnelForm::Full,
            FresnelModel::Schlick => FresnelForm::Schlick,
            FresnelModel::F82 => FresnelForm::F82,
        },
        masking: match options.masking {
            Masking::HeightCorrelated => MaskingForm::HeightCorrelated,
            Masking::Separable => MaskingForm::Separable,
            Masking::Approximate => MaskingForm::Approximate,
        },
        distribution: match options.distribution {
            Distribution::Ggx => DistributionForm::Ggx,
            Distribution::Beckmann => DistributionForm::Beckmann,
        },
        energy_compensation: options.energy_compensation,
    }
}

/// The screen rectangles holding `scene`'s blended objects seen by `inputs`' camera at
/// `width` × `height` (each object's world box, its eight corners projected; the whole
/// frame for a box reaching behind the eye's near plane).
fn blended_rectangles(
    scene: &Scene,
    inputs: &FrameInputs<'_>,
    width: u32,
    height: u32,
) -> Vec<[u32; 4]> {
    // Blended and transmissive objects: the forward pass draws both.
    let blended = |o: &combustion_scene::Object| {
        scene
            .materials
            .get(o.material)
            .is_some_and(|m| m.is_see_through())
    };
    if !scene.objects.iter().any(blended) {
        return Vec::new();
    }
    let clip = inputs
        .camera
        .view_projection(width as f32 / height as f32)
        .as_dmat4();
    let whole = [0, 0, width.saturating_sub(1), height.saturating_sub(1)];
    scene
        .objects
        .iter()
        .zip(scene.object_bounds())
        .filter(|(o, _)| blended(o))
        .map(|(_, bounds)| {
            let Some((min, max)) = bounds else {
                return whole;
            };
            let (min, max) = (min.as_dvec3(), max.as_dvec3());
            let mut lo = glam::DVec2::INFINITY;
            let mut hi = glam::DVec2::NEG_INFINITY;
            for corner in 0..8 {
                let pick = |bit: usize, a: f64, b: f64| if corner & bit == 0 { a } else { b };
                let p = glam::DVec3::new(
                    pick(1, min.x, max.x),
                    pick(2, min.y, max.y),
                    pick(4, min.z, max.z),
                );
                let c = clip * p.extend(1.0);
                // Behind the eye's plane, or not a number: the box may be anywhere.
                if c.w.is_nan() || c.w <= 1e-9 {
                    return whole;
                }
                // NDC to pixels (Vulkan's NDC has y down, as pixel rows), one pixel of
                // margin for the rasteriser's edges.
                let s = glam::DVec2::new(
                    (c.x / c.w * 0.5 + 0.5) * f64::from(width),
                    (c.y / c.w * 0.5 + 0.5) * f64::from(height),
                );
                lo = lo.min(s);
                hi = hi.max(s);
            }
            let pixel = |v: f64, size: u32| v.clamp(0.0, f64::from(size.saturating_sub(1))) as u32;
            [
                pixel(lo.x.floor() - 1.0, width),
                pixel(lo.y.floor() - 1.0, height),
                pixel(hi.x.ceil() + 1.0, width),
                pixel(hi.y.ceil() + 1.0, height),
            ]
        })
        .collect()
}

/// A frame's error against the reference, per pixel and in summary.
#[derive(Clone, Debug, Default)]
pub struct ErrorMap {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Per pixel (row-major from the top-left): the largest relative error of its three
    /// channels, `|gpu − f64| / max(|f64|, RADIANCE_FLOOR)`; NaN where nothing was
    /// compared (background, blended objects, non-finite GPU
    /// values).
    pub relative: Vec<f32>,
    /// The largest per-pixel relative error (at [`ErrorMap::worst_pixel`]).
    pub max_relative: f64,
    /// The mean of the per-pixel relative errors over the compared pixels.
    pub mean_relative: f64,
    /// √(mean of the squared per-pixel errors).
    pub rms_relative: f64,
    /// The pixel (x, y) with the largest error, from the top-left.
    pub worst_pixel: (u32, u32),
    /// The GPU's and the reference's radiance at the worst pixel.
    pub worst_values: ([f32; 3], [f64; 3]),
    /// Pixels compared.
    pub lit_pixels: usize,
    /// Background pixels that were not black (the GPU wrote radiance where nothing is).
    pub background_not_black: usize,
    /// Pixels of emissive materials, compared with the emission the G-buffer stored
    /// added (as the lighting pass adds it: the error is the shading's, relative to the
    /// whole).
    pub emissive_pixels: usize,
    /// Pixels a blended object may cover ([`ReferenceShading::under_blended`]), not
    /// compared.
    pub blended_pixels: usize,
    /// Pixels whose GPU or reference radiance is not finite.
    pub non_finite: usize,
    /// The reference's radiance per pixel, rounded to f32 (row-major, as `relative`):
    /// where nothing was compared, the GPU's own value (0 on the background and where
    /// either was not finite; the GPU's between an environment's grid points), so an image metric
    /// over the whole frame (the report's FLIP) sees the shading's error alone.
    /// Empty when the frame has no G-buffer or HDR image to compare.
    pub reference_radiance: Vec<[f32; 3]>,
}

/// Compares `frame` (read back with its HDR image and G-buffer) with `reference`, using
/// up to `threads` threads.
pub fn error_map(frame: &Frame, reference: &ReferenceShading, threads: usize) -> ErrorMap {
    let (width, height) = (frame.width, frame.height);
    let mut map = ErrorMap {
        width,
        height,
        relative: vec![f32::NAN; (width * height) as usize],
        ..ErrorMap::default()
    };
    let mut reference_radiance = vec![[0.0f32; 3]; map.relative.len()];
    let Some(gbuffer) = frame.gbuffer.as_ref() else {
        return map;
    };
    if frame.hdr.len() != map.relative.len() || gbuffer.texels.len() != map.relative.len() {
        return map;
    }
    let rows_per_chunk = height.div_ceil(threads.max(1) as u32).max(1) as usize;
    let row = width as usize;
    // Per chunk: its counts and worst pixel, and its sums of errors and squared errors.
    let chunks: Vec<(ErrorMap, f64, f64)> = std::thread::scope(|scope| {
        let handles: Vec<_> = map
            .relative
            .chunks_mut(rows_per_chunk * row)
            .zip(reference_radiance.chunks_mut(rows_per_chunk * row))
            .enumerate()
            .map(|(chunk, (out, radiance_out))| {
                let first = chunk * rows_per_chunk * row;
                scope.spawn(move || {
                    let mut part = ErrorMap::default();
                    let (mut sum, mut sum_squares) = (0.0, 0.0);
                    for (offset, (error, radiance)) in
                        out.iter_mut().zip(radiance_out.iter_mut()).enumerate()
                    {
                        let i = first + offset;
                        let (x, y) = ((i % row) as u32, (i / row) as u32);
                        let gpu = frame.hdr[i];
                        *radiance = [gpu[0], gpu[1], gpu[2]];
                        let texel = &gbuffer.texels[i];
                        if gpu.iter().any(|c| !c.is_finite()) {
                            part.non_finite += 1;
                            *radiance = [0.0; 3];
                            continue;
                        }
                        if reference.under_blended(x, y) {
                            part.blended_pixels += 1;
                            continue;
                        }
                        // Every pixel, compared or not (an environment's grid), is checked
                        // for non-finite values (above) and a lit background (here).
                        if texel.depth >= 1.0 {
                            if gpu[..3] != [0.0; 3] {
                                part.background_not_black += 1;
                            }
                            continue;
                        }
                        if !reference.compares(x, y) {
                            continue;
                        }
                        // `None` only for the background, handled above.
                        let Some(cpu) = reference.shade(texel, x, y) else {
                            continue;
                        };
                        if cpu.iter().any(|c| !c.is_finite()) {
                            part.non_finite += 1;
                            *radiance = [0.0; 3];
                            continue;
                        }
                        if reference.emits(texel) {
                            part.emissive_pixels += 1;
                        }
                        part.lit_pixels += 1;
                        *radiance = cpu.map(|c| c as f32);
                        let mut pixel_error = 0.0f64;
                        for c in 0..3 {
                            let e = (f64::from(gpu[c]) - cpu[c]).abs()
                                / cpu[c].abs().max(RADIANCE_FLOOR);
                            pixel_error = pixel_error.max(e);
                        }
                        *error = pixel_error as f32;
                        sum += pixel_error;
                        sum_squares += pixel_error * pixel_error;
                        if pixel_error > part.max_relative || part.lit_pixels == 1 {
                            part.max_relative = pixel_error;
                            part.worst_pixel = (x, y);
                            part.worst_values = ([gpu[0], gpu[1], gpu[2]], cpu);
                        }
                    }
                    (part, sum, sum_squares)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("an error-map thread panicked"))
            .collect()
    });
    let (mut sum, mut sum_squares) = (0.0, 0.0);
    for (part, part_sum, part_squares) in chunks {
        sum += part_sum;
        sum_squares += part_squares;
        let first_lit = map.lit_pixels == 0;
        map.lit_pixels += part.lit_pixels;
        map.background_not_black += part.background_not_black;
        map.emissive_pixels += part.emissive_pixels;
        map.blended_pixels += part.blended_pixels;
        map.non_finite += part.non_finite;
        // The first chunk in row order wins a tie, as the first pixel does within a
        // chunk, so the worst pixel does not depend on the number of threads.
        if part.lit_pixels > 0 && (first_lit || part.max_relative > map.max_relative) {
            map.max_relative = part.max_relative;
            map.worst_pixel = part.worst_pixel;
            map.worst_values = part.worst_values;
        }
    }
    // Sampled pixels only (an environment): no reference image to compare whole.
    if reference.environment.is_none() {
        map.reference_radiance = reference_radiance;
    }
    map.mean_relative = sum / map.lit_pixels.max(1) as f64;
    map.rms_relative = (sum_squares / map.lit_pixels.max(1) as f64).sqrt();
    map
}

/// How a frame's shadows differ from exact visibility, for one light: counted over the
/// pixels where the light stands above the surface (n·l above a bound, see
/// [`shadow_mismatch`]), a pixel being shadowed when the shadow-factor view
/// ([`crate::DebugView::ShadowFactor`]) shows less than ½.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ShadowMismatch {
    /// Pixels compared.
    pub compared: usize,
    /// Pixels exactly visible from the light but shadowed by the maps.
    pub shadowed_should_be_lit: usize,
    /// Pixels the light cannot see but the maps leave lit.
    pub lit_should_be_shadowed: usize,
}

impl ShadowMismatch {
    /// The share of compared pixels misclassified either way.
    pub fn fraction(&self) -> f64 {
        (self.shadowed_should_be_lit + self.lit_should_be_shadowed) as f64
            / self.compared.max(1) as f64
    }
}

/// Compares the verdict `gpu_lit(i)` of each pixel i (row-major) of `frame` (read back
/// with its G-buffer) on the first light of `reference`
/// ([`ReferenceShading::with_exact_visibility`]) with that light's exact visibility, at
/// the pixels where n·l (shading normal) exceeds `min_cos`; returns the counts and, per
/// pixel, whether it is misclassified. For a frame rendered with the shadow-factor view
/// ([`crate::DebugView::ShadowFactor`], exposure 1), `gpu_lit` is its code ≥ 128; for a
/// frame without shadows, every pixel is lit.
///
/// `min_cos` leaves out the *terminator* of tessellated curved surfaces: within about
/// one facet's angle of the shading normal's horizon, a triangle mesh shadows itself
/// (its flat facets block light its interpolated normals face), which exact visibility
/// counts and a shadow map's normal offset does not; sin of the mesh's largest angle
/// between neighbouring vertex normals bounds that band.
pub fn shadow_mismatch(
    frame: &Frame,
    gpu_lit: impl Fn(usize) -> bool,
    reference: &ReferenceShading,
    min_cos: f64,
) -> (ShadowMismatch, Vec<bool>) {
    let mut counts = ShadowMismatch::default();
    let mut wrong = vec![false; (frame.width * frame.height) as usize];
    let Some(gbuffer) = frame.gbuffer.as_ref() else {
        return (counts, wrong);
    };
    let width = frame.width as usize;
    for (i, texel) in gbuffer.texels.iter().enumerate() {
        let (x, y) = ((i % width) as u32, (i / width) as u32);
        let Some((visible, cos)) = reference.exact_visibility(texel, x, y, 0) else {
            continue;
        };
        if cos <= min_cos {
            continue;
        }
        counts.compared += 1;
        match (visible > 0.5, gpu_lit(i)) {
            (true, false) => counts.shadowed_should_be_lit += 1,
            (false, true) => counts.lit_should_be_shadowed += 1,
            _ => continue,
        }
        wrong[i] = true;
    }
    (counts, wrong)
}

/// The heat-map colour of a relative error: log-scaled from [`HEAT_MAP_RANGE`]'s lower
/// end (dark blue) through cyan, green and yellow to its upper end and above (red);
/// pixels not compared are dark grey. sRGB-encoded RGBA8.
pub fn heat_map_color(relative: f32) -> [u8; 4] {
    heat_map_color_in(relative, HEAT_MAP_RANGE)
}

/// [`heat_map_color`] over the range `(lo, hi)` of relative errors (the real-time frame
/// against light that bounces spans larger ones than the one-bounce reference).
pub fn heat_map_color_in(relative: f32, (lo, hi): (f64, f64)) -> [u8; 4] {
    if !relative.is_finite() {
        return [24, 24, 24, 255];
    }
    let t = ((f64::from(relative).max(1e-30).log10() - lo.log10()) / (hi.log10() - lo.log10()))
        .clamp(0.0, 1.0);
    const STOPS: [[f64; 3]; 5] = [
        [0.05, 0.05, 0.45],
        [0.0, 0.65, 0.9],
        [0.1, 0.8, 0.2],
        [0.95, 0.9, 0.1],
        [0.9, 0.1, 0.05],
    ];
    let scaled = t * (STOPS.len() - 1) as f64;
    let i = (scaled.floor() as usize).min(STOPS.len() - 2);
    let f = scaled - i as f64;
    let c = |k: usize| ((STOPS[i][k] * (1.0 - f) + STOPS[i + 1][k] * f) * 255.0).round() as u8;
    [c(0), c(1), c(2), 255]
}

/// The relative errors the heat map spans: f32 rounding (1e-7) to 10 %.
pub const HEAT_MAP_RANGE: (f64, f64) = (1e-7, 1e-1);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heat_map_runs_from_blue_to_red_on_a_log_scale() {
        let (lo, hi) = HEAT_MAP_RANGE;
        assert_eq!(heat_map_color(lo as f32), [13, 13, 115, 255]);
        assert_eq!(heat_map_color(hi as f32), [230, 26, 13, 255]);
        // Below and above the range: its ends; not compared: grey.
        assert_eq!(heat_map_color(0.0), heat_map_color(lo as f32));
        assert_eq!(heat_map_color(1e3), heat_map_color(hi as f32));
        assert_eq!(heat_map_color(f32::NAN), [24, 24, 24, 255]);
        // The middle stop (green) sits at the geometric mean of the range.
        let middle = heat_map_color((lo * hi).sqrt() as f32);
        let green = [26, 204, 51, 255];
        assert!(
            middle.iter().zip(green).all(|(&a, b)| a.abs_diff(b) <= 1),
            "{middle:?}"
        );
        // Ten times more error is never the same colour inside the range.
        let mut e = lo;
        while e * 10.0 <= hi {
            assert_ne!(heat_map_color(e as f32), heat_map_color((e * 10.0) as f32));
            e *= 10.0;
        }
    }
}
