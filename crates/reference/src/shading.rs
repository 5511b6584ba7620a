//! A frame shaded in f64 from the scene alone: the second half of the end-to-end
//! reference. For each pixel, the primary ray's hit ([`crate::primary`]) is turned into
//! the BRDF's inputs from the scene's own description — the mesh's vertex attributes
//! interpolated with the hit's barycentrics, the material's factors times its textures
//! (sampled by [`crate::texture`]'s f64 filtering at a level of detail from ray
//! differentials), glTF's normal-map and KHR_materials_anisotropy rules, a conductor
//! derived from the textured base colour where the material says so — and lit by the
//! scene's lights as their types define them (inverse-square law, KHR_lights_punctual's
//! spot cone and the range window), shaded with the optics crate's f64 BRDF, plus the
//! material's emission. A clear coat (KHR_materials_clearcoat: weight × its texture's R,
//! roughness × its texture's G, its own normal map on the geometry's normal, index 1.5)
//! is layered over the BRDF by the optics crate's coat.
//!
//! It reads nothing the renderer computes: not its material table, light buffer,
//! matrices, G-buffer or encodings. So the difference between a rendered frame and this
//! reference is every error the renderer makes: rasterisation, interpolation, texture
//! filtering, the G-buffer's storage precision, the conversion of lights and materials,
//! and the lighting pass's f32 arithmetic.
//!
//! A shading normal that faces away from the eye is bent towards it by the optics
//! crate's rule (`combustion_optics::vec3::facing_view`, the same rule the renderer
//! applies in GLSL) before anything is shaded.
//!
//! Not modelled (a frame that uses them is compared only where they do not act): the
//! environment's light, KHR_materials_specular (the renderer does not shade it either),
//! and shadows unless [`SceneShading::with_visibility`] adds exact visibility.

use combustion_optics::brdf::{brdf_evaluate_layered, BrdfInputs, DiffuseModel as OpticsDiffuse};
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
use combustion_optics::vec3::{facing_view, Vec3 as OpticsVec3};
use combustion_scene::{
    conductor_from_reflectivity, range_window, DiffuseModel, Light, Material, Scene, TextureRef,
    Vertex, CLEARCOAT_IOR,
};
use glam::{DMat3, DVec2, DVec3};
use std::collections::HashMap;
use std::sync::Arc;

use crate::primary::{camera_ray, per_pixel, primary_hit, primary_layers, PrimaryHit};
use crate::texture::{
    level_of_detail, srgb_decode, srgb_encode, transformed_derivative, transformed_uv, MipChain,
};
use crate::SceneBvh;

/// Samples per axis of a light with a size when [`SceneShading::with_visibility`]
/// gives exact visibility: 12² = 144 stratified shadow rays.
pub const SIZED_LIGHT_SAMPLES: u32 = 12;

/// What the reference finds at one pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadedPixel {
    /// The object the pixel's primary ray hits.
    pub object: usize,
    /// That object's material.
    pub material: usize,
    /// The radiance towards the eye, W/(sr·m²) per linear RGB channel: reflected light
    /// plus emission.
    pub radiance: [f64; 3],
    /// The emitted part of `radiance`.
    pub emitted: [f64; 3],
}

/// The surface at a pixel, as the scene describes it, in f64.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// The primary ray's hit.
    pub hit: PrimaryHit,
    /// The BRDF's inputs there (factors times textures).
    pub brdf: BrdfInputs<f64>,
    /// The unit shading normal (normal map applied, facing the eye's side for a
    /// double-sided material seen from behind).
    pub n: DVec3,
    /// The unit anisotropy direction, orthogonal to `n`.
    pub t: DVec3,
    /// n × t.
    pub b: DVec3,
    /// The unit direction to the eye.
    pub v: DVec3,
    /// Emitted radiance (factor × strength × texture).
    pub emitted: [f64; 3],
    /// The perceptual roughness r the BRDF's α come from (factor × texture).
    pub roughness: f64,
    /// Texture coordinates (sets 0 and 1) at the hit, before any KHR_texture_transform.
    pub uv: [[f64; 2]; 2],
    /// The largest level of detail λ at which a texture was sampled here (`None`: the
    /// material has no texture); below 0 the textures are magnified.
    pub texture_lod: Option<f64>,
    /// The largest difference between neighbouring texels any texture's filter read
    /// here ([`MipChain::footprint_contrast`], in stored units: code / 255).
    pub texture_contrast: f64,
    /// The anisotropy strength s (factor × texture).
    pub anisotropy_strength: f64,
    /// Alpha: the base colour factor's × its texture's × the vertex colour's (what a
    /// blended material covers what is behind it by; 1 where nothing lowers it).
    pub alpha: f64,
    /// KHR_materials_transmission: the factor × its texture's R (0: opaque).
    pub transmission: f64,
    /// How fast the vertex colour (glTF COLOR_0) changes across the image here: the
    /// largest change of a channel from this pixel's centre to a neighbour's (central
    /// differences along x and y, the rays met on the hit triangle's plane); 0 for a
    /// mesh of one colour.
    pub vertex_color_gradient: f64,
    /// The clear coat and the sheen over the BRDF (each `None` where there is none, or
    /// a weight or colour of 0 here).
    pub layers: Layers,
    /// glTF occlusion, 1 + strength × (the occlusion texture's R − 1); 1 without an
    /// occlusion texture. It darkens the environment's light only, as the split sum
    /// applies it ([`occluded_environment`]).
    pub occlusion: f64,
}

/// The scene shaded per pixel in f64 for a `width` × `height` frame of its own camera.
pub struct SceneShading<'a> {
    pub(crate) scene: &'a Scene,
    pub(crate) bvh: &'a SceneBvh,
    lights: &'a [Light],
    width: u32,
    height: u32,
    /// Every image the materials use, decoded once, by its address.
    mips: HashMap<usize, MipChain>,
    visibility: Option<&'a SceneBvh>,
    lod_bias: f64,
    /// Samples of each strategy of the environment's integral (`None`: the environment,
    /// if the scene has one, is left out).
    environment_samples: Option<u32>,
    /// Some material is blended or transmissive (else no ray looks past a first hit).
    see_through: bool,
}

fn optics_vec(v: DVec3) -> OpticsVec3<f64> {
    OpticsVec3::new(v.x, v.y, v.z)
}

/// `n` made to face `v` by the optics crate's rule ([`facing_view`]).
fn facing(n: DVec3, v: DVec3) -> DVec3 {
    let f = facing_view(optics_vec(n), optics_vec(v));
    DVec3::new(f.x, f.y, f.z)
}

fn optics_diffuse(model: DiffuseModel) -> OpticsDiffuse {
    match model {
        DiffuseModel::Lambert => OpticsDiffuse::Lambert,
        DiffuseModel::OrenNayarQualitative => OpticsDiffuse::OrenNayarQualitative,
        DiffuseModel::OrenNayarFull => OpticsDiffuse::OrenNayarFull,
    }
}

/// The unit direction to `light` from `point` and the irradiance it gives a surface
/// facing it there, from the light's definition ([`Light`]): I/d² for point and spot
/// lights, times the range window ([`range_window`]) where there is a range and, for a
/// spot, KHR_lights_punctual's cone falloff as its specification implements it (the
/// square of the linear ramp in the cosine from the outer to the inner cone, clamped to
/// [0, 1], the ramp's width at least 0.001); E along −direction for a directional
/// light. Zero irradiance outside a spot's cone or beyond a range.
pub fn light_at(light: &Light, point: DVec3) -> (DVec3, [f64; 3]) {
    let f3 = |a: [f32; 3]| a.map(f64::from);
    match *light {
        Light::Directional {
            direction,
            irradiance,
            ..
        } => (-direction.as_dvec3().normalize(), f3(irradiance)),
        Light::Point {
            position,
            intensity,
            range,
            ..
        } => point_light(position.as_dvec3() - point, f3(intensity), range, 1.0),
        Light::Spot {
            position,
            direction,
            intensity,
            inner_cone,
            outer_cone,
            range,
            ..
        } => {
            let to_light = position.as_dvec3() - point;
            let cos_axis = (-to_light.normalize()).dot(direction.as_dvec3().normalize());
            let (cos_outer, cos_inner) = (f64::from(outer_cone).cos(), f64::from(inner_cone).cos());
            let width = (cos_inner - cos_outer).max(1e-3);
            let ramp = ((cos_axis - cos_outer) / width).clamp(0.0, 1.0);
            point_light(to_light, f3(intensity), range, ramp * ramp)
        }
    }
}

fn point_light(
    to_light: DVec3,
    intensity: [f64; 3],
    range: Option<f32>,
    cone: f64,
) -> (DVec3, [f64; 3]) {
    let d2 = to_light.length_squared();
    let window = range.map_or(1.0, |r| range_window(d2.sqrt(), f64::from(r)));
    let scale = cone * window / d2;
    (to_light.normalize(), intensity.map(|i| i * scale))
}

/// An image's identity: the address of the shared image (a scene's textures share
/// them by `Arc`).
fn image_key(image: &Arc<combustion_scene::Image>) -> usize {
    Arc::as_ptr(image) as usize
}

/// A texture's value at a surface point, with the derivatives of its coordinate sets.
struct TextureLookup<'m> {
    mips: &'m HashMap<usize, MipChain>,
    lod_bias: f64,
    /// The largest level of detail sampled so far.
    largest_lod: std::cell::Cell<Option<f64>>,
    /// The largest footprint contrast sampled so far.
    contrast: std::cell::Cell<f64>,
    uv: [DVec2; 2],
    duv_dx: [DVec2; 2],
    duv_dy: [DVec2; 2],
}

impl TextureLookup<'_> {
    fn sample(&self, texture: &TextureRef) -> [f64; 4] {
        let set = (texture.tex_coord as usize).min(1);
        let uv = transformed_uv(texture, self.uv[set].to_array());
        let dx = transformed_derivative(texture, self.duv_dx[set].to_array());
        let dy = transformed_derivative(texture, self.duv_dy[set].to_array());
        match self.mips.get(&image_key(&texture.texture.image)) {
            Some(chain) => {
                let lod = level_of_detail(chain.size(), dx, dy) + self.lod_bias;
                let largest = self.largest_lod.get().map_or(lod, |l| l.max(lod));
                self.largest_lod.set(Some(largest));
                let sampler = &texture.texture.sampler;
                let contrast = chain.footprint_contrast(sampler, uv, lod);
                self.contrast.set(self.contrast.get().max(contrast));
                chain.sample(sampler, uv, lod)
            }
            None => [1.0; 4],
        }
    }

    fn sample_or(&self, texture: Option<&TextureRef>, absent: [f64; 4]) -> [f64; 4] {
        texture.map_or(absent, |t| self.sample(t))
    }
}

impl<'a> SceneShading<'a> {
    /// For `scene` seen by its camera at `width` × `height`, its triangles in `bvh`
    /// ([`SceneBvh::new`]), lit by `lights` (the frame's: usually the scene's own).
    /// Decodes every image the materials use.
    pub fn new(
        scene: &'a Scene,
        bvh: &'a SceneBvh,
        lights: &'a [Light],
        width: u32,
        height: u32,
    ) -> Self {
        let mut mips = HashMap::new();
        for material in &scene.materials {
            for (_, texture) in material.texture_slots() {
                if let Some(texture) = texture {
                    let image = &texture.texture.image;
                    mips.entry(image_key(image))
                        .or_insert_with(|| MipChain::new(image));
                }
            }
        }
        SceneShading {
            scene,
            bvh,
            lights,
            width,
            height,
            mips,
            visibility: None,
            lod_bias: 0.0,
            environment_samples: None,
            see_through: scene.materials.iter().any(|m| m.is_see_through()),
        }
    }

    /// The frame's width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// The frame's height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The same, with the scene's environment (if it has one) lighting every point:
    /// L = ∫ f(v, l) L_env(l) (n·l) dl over the hemisphere, estimated by
    /// [`integrate_environment_layered`] with `samples` samples of each strategy (BRDF and
    /// cosine sampling, combined by multiple importance), the sequence seeded by the
    /// point's position (so one point always gets one estimate). The environment reaches
    /// every point from every direction above it (the renderer's environment casts no
    /// shadows either), darkened only by a glTF occlusion texture, as the split sum
    /// applies it ([`occluded_environment`]). [`SceneShading::environment_estimate`]
    /// gives its standard error.
    pub fn with_environment(self, samples: u32) -> Self {
        SceneShading {
            environment_samples: Some(samples),
            ..self
        }
    }

    /// The environment's share of `surface`'s radiance with its standard error, where
    /// [`SceneShading::with_environment`] asked for it and the scene has an environment.
    pub fn environment_estimate(&self, surface: &SurfacePoint) -> Option<Estimate> {
        let (environment, samples) = (self.scene.environment.as_ref()?, self.environment_samples?);
        let seed = surface
            .hit
            .position
            .iter()
            .fold(0x9e37_79b9_7f4a_7c15u64, |h, c| {
                (h ^ c.to_bits()).wrapping_mul(0x1000_0000_01b3)
            });
        let integrate = |brdf: &BrdfInputs<f64>| {
            integrate_environment_layered(
                brdf,
                &surface.layers,
                optics_vec(surface.n),
                optics_vec(surface.t),
                optics_vec(surface.b),
                optics_vec(surface.v),
                |l| environment.radiance(l),
                Sampling {
                    iterations: samples,
                    seed,
                },
            )
        };
        let whole = integrate(&surface.brdf);
        if surface.occlusion.is_nan() || surface.occlusion >= 1.0 {
            return Some(whole);
        }
        // The lobe's α as the split sum takes it: an anisotropic lobe's mean α.
        let alpha = if surface.brdf.alpha_x == surface.brdf.alpha_y {
            surface.roughness * surface.roughness
        } else {
            0.5 * (surface.brdf.alpha_x + surface.brdf.alpha_y)
        };
        let without_diffuse = integrate(&BrdfInputs {
            base_color: [0.0; 3],
            ..surface.brdf
        });
        Some(occluded_environment(
            whole,
            &without_diffuse,
            surface.n.dot(surface.v),
            alpha,
            surface.occlusion,
        ))
    }

    /// The same, each light's term multiplied by its exact visibility from the shaded
    /// point ([`SceneBvh::light_visible_fraction`] with [`SIZED_LIGHT_SAMPLES`]² rays for
    /// a light with a size): `casters` holds the scene's shadow casters
    /// ([`SceneBvh::shadow_casters`]). The reference for frames with shadows.
    pub fn with_visibility(self, casters: &'a SceneBvh) -> Self {
        SceneShading {
            visibility: Some(casters),
            ..self
        }
    }

    /// The same, every texture sampled at its level of detail plus `bias` (levels). The
    /// Vulkan specification lets an implementation take the scale factor ρ anywhere
    /// between the largest derivative component and the sum of the components, which
    /// is λ within ±½ of the exact λ this reference uses: shading with a bias of ±½
    /// bounds what a conforming GPU may sample.
    pub fn with_lod_bias(self, bias: f64) -> Self {
        SceneShading {
            lod_bias: bias,
            ..self
        }
    }

    /// The world-space vertices and scene vertices of `hit`'s triangle.
    fn triangle(&self, hit: &PrimaryHit) -> Option<([DVec3; 3], [Vertex; 3])> {
        let object = self.scene.objects.get(hit.object)?;
        let mesh = self.scene.meshes.get(object.mesh)?;
        let transform = object.transform.as_dmat4();
        let mut world = [DVec3::ZERO; 3];
        let mut vertices = [Vertex::default(); 3];
        for k in 0..3 {
            let index = *mesh.indices.get(3 * hit.triangle + k)? as usize;
            vertices[k] = *mesh.vertices.get(index)?;
            world[k] = transform.transform_point3(DVec3::from(vertices[k].position.map(f64::from)));
        }
        Some((world, vertices))
    }

    /// The opaque surface pixel (`x`, `y`) shows, `None` where its ray hits nothing
    /// opaque (blended surfaces in front of it: [`SceneShading::blended_surfaces`]).
    pub fn surface(&self, x: u32, y: u32) -> Option<SurfacePoint> {
        let hit = primary_hit(self.scene, self.bvh, self.width, self.height, x, y)?;
        self.surface_at(hit, x, y)
    }

    /// The blended (alphaMode BLEND) and transmissive surfaces pixel (`x`, `y`)'s ray
    /// passes through before its opaque surface, nearest first (empty in a scene without
    /// any). A transmissive surface that is not blended covers what is behind it wholly
    /// (`alpha` 1): its radiance holds what it lets through.
    pub fn blended_surfaces(&self, x: u32, y: u32) -> Vec<SurfacePoint> {
        if !self.see_through {
            return Vec::new();
        }
        primary_layers(self.scene, self.bvh, self.width, self.height, x, y)
            .blended
            .into_iter()
            .filter_map(|hit| self.surface_at(hit, x, y))
            .collect()
    }

    /// What pixel (`x`, `y`)'s ray meets — the blended surfaces in front, nearest first
    /// ([`SceneShading::blended_surfaces`]), and the opaque one — with their textures
    /// read at their finest level, as a path from the eye through the pixel's centre
    /// reads them (such a path has no footprint).
    pub(crate) fn layers_at_finest_level(
        &self,
        x: u32,
        y: u32,
    ) -> (Vec<SurfacePoint>, Option<SurfacePoint>) {
        let layers = primary_layers(self.scene, self.bvh, self.width, self.height, x, y);
        let eye = self.scene.camera.position.as_dvec3();
        let blended = if self.see_through {
            layers
                .blended
                .into_iter()
                .filter_map(|hit| self.surface_seen_from(hit, eye))
                .collect()
        } else {
            Vec::new()
        };
        let opaque = layers
            .opaque
            .and_then(|hit| self.surface_seen_from(hit, eye));
        (blended, opaque)
    }

    /// The radiance a pixel shows where `blended` (nearest first, with their radiance)
    /// lie in front of a surface of radiance `behind`: each blended over what is behind
    /// it, farthest first, as glTF's straight alpha defines it (L α + behind (1 − α),
    /// α = [`SurfacePoint::alpha`] clamped to [0, 1]).
    pub fn blended_over(blended: &[(SurfacePoint, [f64; 3])], behind: [f64; 3]) -> [f64; 3] {
        blended
            .iter()
            .rev()
            .fold(behind, |behind, (surface, radiance)| {
                let alpha = surface.alpha.clamp(0.0, 1.0);
                std::array::from_fn(|c| radiance[c] * alpha + behind[c] * (1.0 - alpha))
            })
    }

    /// The surface `hit` shows to a ray from `from` (a secondary ray: through glass, say),
    /// its textures read at their finest level (such a ray has no pixel footprint).
    pub(crate) fn surface_seen_from(&self, hit: PrimaryHit, from: DVec3) -> Option<SurfacePoint> {
        let material = self
            .scene
            .materials
            .get(self.scene.objects.get(hit.object)?.material)?;
        let (_, vertices) = self.triangle(&hit)?;
        let [b1, b2] = hit.barycentrics;
        let weights = [1.0 - b1 - b2, b1, b2];
        let mix2 = |f: fn(&Vertex) -> [f32; 2]| -> DVec2 {
            (0..3)
                .map(|k| DVec2::from(f(&vertices[k]).map(f64::from)) * weights[k])
                .sum()
        };
        let lookup = TextureLookup {
            mips: &self.mips,
            lod_bias: self.lod_bias,
            largest_lod: std::cell::Cell::new(None),
            contrast: std::cell::Cell::new(0.0),
            uv: [mix2(|v| v.uv), mix2(|v| v.uv1)],
            duv_dx: [DVec2::ZERO; 2],
            duv_dy: [DVec2::ZERO; 2],
        };
        Some(self.shade_inputs(hit, material, &vertices, weights, &lookup, from))
    }

    /// The surface `hit` shows at pixel (`x`, `y`).
    fn surface_at(&self, hit: PrimaryHit, x: u32, y: u32) -> Option<SurfacePoint> {
        let scene = self.scene;
        let object = &scene.objects[hit.object];
        let material = scene.materials.get(object.material)?;
        let (world, vertices) = self.triangle(&hit)?;
        let [b1, b2] = hit.barycentrics;
        let weights = [1.0 - b1 - b2, b1, b2];
        let mix2 = |f: fn(&Vertex) -> [f32; 2], w: [f64; 3]| -> DVec2 {
            (0..3)
                .map(|k| DVec2::from(f(&vertices[k]).map(f64::from)) * w[k])
                .sum()
        };
        let uv = [mix2(|v| v.uv, weights), mix2(|v| v.uv1, weights)];

        // Texture-coordinate derivatives per pixel: the rays through the neighbouring
        // pixels' centres (x ± 1, y ± 1), met on the hit triangle's plane, central
        // differences of their (extrapolated) barycentric interpolation.
        let camera = &scene.camera;
        let edge1 = world[1] - world[0];
        let edge2 = world[2] - world[0];
        let plane_normal = edge1.cross(edge2);
        let barycentrics_along = |px: f64, py: f64| -> Option<[f64; 3]> {
            let ray = camera_ray(camera, self.width, self.height, px, py);
            let (o, d) = (DVec3::from(ray.origin), DVec3::from(ray.direction));
            let t = (world[0] - o).dot(plane_normal) / d.dot(plane_normal);
            let p = o + d * t;
            let area = plane_normal.length_squared();
            let w1 = (p - world[0]).cross(edge2).dot(plane_normal) / area;
            let w2 = edge1.cross(p - world[0]).dot(plane_normal) / area;
            let w = [1.0 - w1 - w2, w1, w2];
            w.iter().all(|c| c.is_finite()).then_some(w)
        };
        let (cx, cy) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
        let derivative = |a: Option<[f64; 3]>, b: Option<[f64; 3]>| -> [DVec2; 2] {
            match (a, b) {
                (Some(a), Some(b)) => {
                    let w = [0, 1, 2].map(|k| (b[k] - a[k]) * 0.5);
                    [mix2(|v| v.uv, w), mix2(|v| v.uv1, w)]
                }
                _ => [DVec2::ZERO; 2],
            }
        };
        let lookup = TextureLookup {
            mips: &self.mips,
            lod_bias: self.lod_bias,
            largest_lod: std::cell::Cell::new(None),
            contrast: std::cell::Cell::new(0.0),
            uv,
            duv_dx: derivative(
                barycentrics_along(cx - 1.0, cy),
                barycentrics_along(cx + 1.0, cy),
            ),
            duv_dy: derivative(
                barycentrics_along(cx, cy - 1.0),
                barycentrics_along(cx, cy + 1.0),
            ),
        };
        let color_along = |w: Option<[f64; 3]>| -> Option<[f64; 4]> {
            let w = w?;
            Some(std::array::from_fn(|c| {
                (0..3).map(|k| f64::from(vertices[k].color[c]) * w[k]).sum()
            }))
        };
        let vertex_color_gradient = [
            (
                barycentrics_along(cx - 1.0, cy),
                barycentrics_along(cx + 1.0, cy),
            ),
            (
                barycentrics_along(cx, cy - 1.0),
                barycentrics_along(cx, cy + 1.0),
            ),
        ]
        .into_iter()
        .filter_map(|(a, b)| Some((color_along(a)?, color_along(b)?)))
        .flat_map(|(a, b)| (0..4).map(move |c| 0.5 * (b[c] - a[c]).abs()))
        .fold(0.0, f64::max);
        let eye = scene.camera.position.as_dvec3();
        let mut surface = self.shade_inputs(hit, material, &vertices, weights, &lookup, eye);
        surface.vertex_color_gradient = vertex_color_gradient;
        Some(surface)
    }

    fn shade_inputs(
        &self,
        hit: PrimaryHit,
        material: &Material,
        vertices: &[Vertex; 3],
        weights: [f64; 3],
        lookup: &TextureLookup<'_>,
        eye: DVec3,
    ) -> SurfacePoint {
        let object = &self.scene.objects[hit.object];
        let linear = DMat3::from_mat4(object.transform.as_dmat4());
        let position = DVec3::from(hit.position);
        let v = (eye - position).normalize();

        // The tangent frame: interpolated normal (world, by the inverse transpose:
        // `hit.normal`), interpolated tangent carried by the transform and made
        // orthogonal to it, bitangent n × t times the tangent's sign.
        let mut n = DVec3::from(hit.normal);
        let tangent_local: DVec3 = (0..3)
            .map(|k| glam::Vec4::from(vertices[k].tangent).truncate().as_dvec3() * weights[k])
            .sum();
        let sign = if (0..3)
            .map(|k| f64::from(vertices[k].tangent[3]) * weights[k])
            .sum::<f64>()
            < 0.0
        {
            -1.0
        } else {
            1.0
        };
        // A tangent along the normal (or not finite) gives way to any orthogonal one.
        let t_carried = (linear * tangent_local).reject_from_normalized(n);
        let mut t = if t_carried.length_squared() > 1e-30 {
            t_carried.normalize()
        } else {
            n.any_orthonormal_vector()
        };
        let mut b = n.cross(t) * sign;
        // The clear coat's normal: its own normal map in the geometry's frame (not the
        // base's normal map), else the geometry's normal.
        let mut coat_normal = n;
        if let Some(normal_map) = material
            .clearcoat_normal_texture
            .as_ref()
            .filter(|_| material.is_coated())
        {
            let m = lookup.sample(normal_map);
            let scale = f64::from(material.clearcoat_normal_scale);
            let mapped = t * ((m[0] * 2.0 - 1.0) * scale)
                + b * ((m[1] * 2.0 - 1.0) * scale)
                + n * (m[2] * 2.0 - 1.0);
            if mapped.length_squared() > 1e-30 {
                coat_normal = mapped.normalize();
            }
        }

        // Normal map: n' = TBN · ((m · 2 − 1) ⊙ (scale, scale, 1)), normalised.
        if let Some(normal_map) = &material.normal_texture {
            let m = lookup.sample(normal_map);
            let scale = f64::from(material.normal_scale);
            let mapped = t * ((m[0] * 2.0 - 1.0) * scale)
                + b * ((m[1] * 2.0 - 1.0) * scale)
                + n * (m[2] * 2.0 - 1.0);
            if mapped.length_squared() > 1e-30 {
                n = mapped.normalize();
                t = t.reject_from_normalized(n).normalize();
                b = n.cross(t) * sign;
            }
        }
        // glTF: a back face of a double-sided material is shaded with the normal
        // reversed (primary hits see no other back faces).
        if DVec3::from(hit.geometric_normal).dot(position - eye) > 0.0 {
            n = -n;
            b = -b;
            coat_normal = -coat_normal;
        }
        // A shading normal that faces away from the eye (an interpolated normal at a
        // silhouette, a normal map on a fold) is bent towards it until their cosine is
        // combustion_optics::FACING_COS_MIN (`facing_view`), the base's and the coat's
        // alike, as the renderer's passes do before shading. The anisotropy direction
        // below is made orthogonal to the bent normal; `t` and `b` stay the unbent
        // frame the direction is given in (the G-buffer stores it in that plane).
        n = facing(n, v);
        coat_normal = facing(coat_normal, v);

        let base_texture = lookup.sample_or(material.base_color_texture.as_ref(), [1.0; 4]);
        // The vertex colour (glTF COLOR_0), interpolated in f64.
        let vertex_color = |c: usize| -> f64 {
            (0..3)
                .map(|k| f64::from(vertices[k].color[c]) * weights[k])
                .sum()
        };
        let base_color: [f64; 3] = std::array::from_fn(|c| {
            f64::from(material.base_color[c]) * base_texture[c] * vertex_color(c)
        });
        // Only a blended material covers by its alpha (a cut-out's is the hierarchy's,
        // an opaque one's is ignored).
        let coverage = if material.is_blended() {
            f64::from(material.alpha) * base_texture[3] * vertex_color(3)
        } else {
            1.0
        };
        let metal_rough = lookup.sample_or(material.metallic_roughness_texture.as_ref(), [1.0; 4]);
        let metalness = f64::from(material.metalness) * metal_rough[2];
        let roughness = f64::from(material.roughness) * metal_rough[1];

        // KHR_materials_anisotropy: the direction (1, 0) or the texture's RG mapped to
        // [−1, 1], turned by the rotation, in the (t, b) plane; strength × texture B.
        let mut strength = f64::from(material.anisotropy_strength);
        let mut along = DVec2::X;
        if let Some(texture) = &material.anisotropy_texture {
            let a = lookup.sample(texture);
            along = DVec2::new(a[0] * 2.0 - 1.0, a[1] * 2.0 - 1.0);
            strength *= a[2];
        }
        let along = DVec2::from_angle(f64::from(material.anisotropy_rotation)).rotate(along);
        let direction = t * along.x + b * along.y;
        let anisotropy_t = if direction.length_squared() > 1e-30 {
            direction.reject_from_normalized(n).normalize()
        } else {
            t
        };
        let anisotropy_b = n.cross(anisotropy_t);

        let alpha = alpha_from_perceptual_roughness(roughness);
        let (alpha_x, alpha_y) = anisotropic_alphas(alpha, strength);
        let conductor = if material.conductor_from_base_color {
            conductor_from_reflectivity(base_color.map(|c| c as f32))
        } else {
            material.conductor
        };
        let brdf = BrdfInputs {
            base_color,
            metalness,
            alpha_x,
            alpha_y,
            conductor_eta: conductor.eta.map(f64::from),
            conductor_k: conductor.k.map(f64::from),
            dielectric_eta: f64::from(material.dielectric_ior),
            outside_eta: f64::from(self.scene.outside_ior_of(material)),
            polarisation_weight: f64::from(material.polarisation_weight),
            diffuse_model: optics_diffuse(material.diffuse_model),
            oren_nayar_sigma: oren_nayar_sigma_from_roughness(roughness),
        };

        let coat = material.is_coated().then(|| {
            let weight = f64::from(material.clearcoat)
                * lookup.sample_or(material.clearcoat_texture.as_ref(), [1.0; 4])[0];
            let roughness = f64::from(material.clearcoat_roughness)
                * lookup.sample_or(material.clearcoat_roughness_texture.as_ref(), [1.0; 4])[1];
            CoatLayer {
                inputs: CoatInputs {
                    factor: weight,
                    alpha: alpha_from_perceptual_roughness(roughness),
                    eta: f64::from(CLEARCOAT_IOR),
                    outside_eta: brdf.outside_eta,
                    polarisation_weight: brdf.polarisation_weight,
                },
                normal: optics_vec(coat_normal),
            }
        });
        let coat = coat.filter(|c| c.inputs.factor > 0.0);
        // KHR_materials_sheen: colour × its texture's RGB (sRGB), roughness × its A.
        let sheen = material.has_sheen().then(|| {
            let texture = lookup.sample_or(material.sheen_color_texture.as_ref(), [1.0; 4]);
            let roughness = f64::from(material.sheen_roughness)
                * lookup.sample_or(material.sheen_roughness_texture.as_ref(), [1.0; 4])[3];
            SheenInputs {
                color: std::array::from_fn(|c| f64::from(material.sheen_color[c]) * texture[c]),
                alpha: roughness * roughness,
            }
        });
        let sheen = sheen.filter(|s| s.color.iter().any(|&c| c > 0.0));
        // KHR_materials_iridescence: the factor × its texture's R; the thickness from the
        // minimum to the maximum by its thickness texture's G (the maximum without one).
        let film = material
            .film()
            .map(|f| {
                let weight = f64::from(f.factor)
                    * lookup.sample_or(material.iridescence_texture.as_ref(), [1.0; 4])[0];
                let (min, max) = (f64::from(f.thickness_min_nm), f64::from(f.thickness_max_nm));
                let thickness_nm = match material.iridescence_thickness_texture.as_ref() {
                    Some(t) => min + (max - min) * lookup.sample(t)[1],
                    None => max,
                };
                ThinFilm {
                    weight,
                    eta: f64::from(f.ior),
                    thickness_nm,
                }
            })
            .filter(ThinFilm::is_present);
        // KHR_materials_specular: the factor × its texture's A, the colour × its colour
        // texture's RGB (sRGB); none where both are the neutral 1.
        let specular = material
            .has_specular()
            .then(|| {
                let strength = lookup.sample_or(material.specular_texture.as_ref(), [1.0; 4])[3];
                let color = lookup.sample_or(material.specular_color_texture.as_ref(), [1.0; 4]);
                DielectricSpecular {
                    factor: f64::from(material.specular_factor) * strength,
                    color: std::array::from_fn(|c| {
                        f64::from(material.specular_color_factor[c]) * color[c]
                    }),
                }
            })
            .filter(DielectricSpecular::is_present);
        let emissive_texture = lookup.sample_or(material.emissive_texture.as_ref(), [1.0; 4]);
        let emitted = std::array::from_fn(|c| {
            f64::from(material.emissive_factor[c])
                * f64::from(material.emissive_strength)
                * emissive_texture[c]
        });
        SurfacePoint {
            hit,
            brdf,
            n,
            t: anisotropy_t,
            b: anisotropy_b,
            v,
            emitted,
            roughness,
            uv: lookup.uv.map(|uv| uv.to_array()),
            texture_lod: lookup.largest_lod.get(),
            texture_contrast: lookup.contrast.get(),
            vertex_color_gradient: 0.0,
            anisotropy_strength: strength,
            alpha: coverage,
            transmission: f64::from(material.transmission)
                * lookup.sample_or(material.transmission_texture.as_ref(), [1.0; 4])[0],
            layers: Layers {
                coat,
                sheen,
                film,
                specular,
            },
            occlusion: material.occlusion_texture.as_ref().map_or(1.0, |texture| {
                1.0 + f64::from(material.occlusion_strength) * (lookup.sample(texture)[0] - 1.0)
            }),
        }
    }

    /// The radiance pixel (`x`, `y`) shows and what it hits; `None` where its ray hits
    /// nothing.
    pub fn pixel(&self, x: u32, y: u32) -> Option<ShadedPixel> {
        let surface = self.surface(x, y)?;
        let object = surface.hit.object;
        Some(ShadedPixel {
            object,
            material: self.scene.objects[object].material,
            radiance: self.radiance(&surface),
            emitted: surface.emitted,
        })
    }

    /// The radiance `surface` sends to the eye: its emission plus each light's
    /// f(v, l) E (n·l), times the light's exact visibility with
    /// [`SceneShading::with_visibility`], plus the environment's integral with
    /// [`SceneShading::with_environment`]; for an unlit material (KHR_materials_unlit),
    /// its base colour.
    pub fn radiance(&self, surface: &SurfacePoint) -> [f64; 3] {
        self.radiance_followed(surface, crate::transmission::TRANSMISSION_DEPTH)
    }

    /// [`SceneShading::radiance`], following light through transmissive surfaces for
    /// `depth` more interfaces (crate::transmission).
    pub(crate) fn radiance_followed(&self, surface: &SurfacePoint, depth: u32) -> [f64; 3] {
        let material = self
            .scene
            .objects
            .get(surface.hit.object)
            .and_then(|o| self.scene.materials.get(o.material));
        // KHR_materials_unlit: the base colour (factor × texture × vertex colour) is the
        // radiance; nothing lights it.
        if material.is_some_and(|m| m.unlit) {
            return surface.brdf.base_color;
        }
        // KHR_materials_transmission: the diffuse lobe keeps 1 − transmission of the
        // light through the surface; the rest passes on through the object.
        if let Some(m) = material.filter(|m| m.is_transmissive()) {
            let transmission = surface.transmission;
            let mut reflecting = *surface;
            reflecting.brdf.base_color = surface.brdf.base_color.map(|c| c * (1.0 - transmission));
            let mut radiance = self.reflected(&reflecting);
            if depth > 0 {
                let through = self.transmitted(surface, m, depth - 1);
                // What passes through leaves through the layers towards the eye: a coat's
                // A(v), a sheen's 1 − max(c) E(n·v).
                let out = layers_view(
                    &surface.layers,
                    optics_vec(surface.n),
                    optics_vec(surface.v),
                )
                .through_layers_v();
                let weight = (1.0 - surface.brdf.metalness) * transmission * out;
                for c in 0..3 {
                    radiance[c] += weight * surface.brdf.base_color[c] * through[c];
                }
            }
            return radiance;
        }
        self.reflected(surface)
    }

    /// What `surface` reflects and emits: its emission, each light's f(v, l) E (n·l)
    /// (times visibility) and the environment's integral.
    fn reflected(&self, surface: &SurfacePoint) -> [f64; 3] {
        let mut radiance = surface.emitted;
        let direct = self.direct_light(surface, self.visibility);
        for (r, d) in radiance.iter_mut().zip(direct) {
            *r += d;
        }
        if let Some(estimate) = self.environment_estimate(surface) {
            for (r, e) in radiance.iter_mut().zip(estimate.mean) {
                *r += e;
            }
        }
        radiance
    }

    /// What `surface` reflects of the scene's lights: each light's f(v, l) E (n·l), times
    /// its exact visibility through `casters` ([`SceneBvh::light_visible_fraction`] with
    /// [`SIZED_LIGHT_SAMPLES`]² rays for a light with a size) where they are given.
    pub(crate) fn direct_light(
        &self,
        surface: &SurfacePoint,
        casters: Option<&SceneBvh>,
    ) -> [f64; 3] {
        let position = DVec3::from(surface.hit.position);
        let mut radiance = [0.0; 3];
        let layered = layers_view(
            &surface.layers,
            optics_vec(surface.n),
            optics_vec(surface.v),
        );
        for light in self.lights {
            let (l, irradiance) = light_at(light, position);
            let cos = surface.n.dot(l);
            // NaN compares false: a light that cannot be evaluated adds nothing. A coat
            // with its own normal may face a light the base does not.
            let faces_light = layers_face(&layered, cos, optics_vec(l));
            if !faces_light || irradiance.iter().all(|&e| e <= 0.0) {
                continue;
            }
            let visible = match casters {
                Some(casters) => casters.light_visible_fraction(
                    surface.hit.position,
                    surface.n.to_array(),
                    light,
                    SIZED_LIGHT_SAMPLES,
                ),
                None => 1.0,
            };
            if visible == 0.0 {
                continue;
            }
            let f = brdf_evaluate_layered(
                &surface.brdf,
                surface.layers.film.as_ref(),
                surface.layers.specular.as_ref(),
                optics_vec(surface.n),
                optics_vec(surface.t),
                optics_vec(surface.b),
                optics_vec(surface.v),
                optics_vec(l),
            );
            let reflected = layered_radiance(&layered, f, cos, optics_vec(l));
            for c in 0..3 {
                radiance[c] += reflected[c] * irradiance[c] * visible;
            }
        }
        radiance
    }

    /// [`SceneShading::surface`] for every pixel, row-major from the top-left, on up to
    /// `threads` threads.
    pub fn surfaces(&self, threads: usize) -> Vec<Option<SurfacePoint>> {
        per_pixel(self.width, self.height, threads, |x, y| self.surface(x, y))
    }

    /// [`SceneShading::pixel`] for every pixel, row-major from the top-left, on up to
    /// `threads` threads.
    pub fn render(&self, threads: usize) -> Vec<Option<ShadedPixel>> {
        per_pixel(self.width, self.height, threads, |x, y| self.pixel(x, y))
    }
}

/// How one G-buffer value is stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoredValue {
    /// An unsigned normalised integer of this many bits: the value rounded to the
    /// nearest of 2ⁿ − 1 steps over [0, 1] (the base colour through the sRGB curve).
    Unorm(u32),
    /// An IEEE half float (11 significant bits; the base colour linear).
    Half,
}

/// What a G-buffer keeps of a surface: the precision each stored input is rounded to
/// before the lighting pass reads it, so the reference can shade a surface both exactly
/// and as stored, and a frame's error splits into the storage's share and the rest.
/// The formats are Combustion's documented G-buffer (docs/gbuffer.md); this models
/// their rounding from that description, not from the renderer's code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct GBufferPrecision {
    /// The base colour: through the sRGB curve in unorm, or linear in f16.
    pub base_color: StoredValue,
    /// The metalness (linear).
    pub metalness: StoredValue,
    /// Bits of the perceptual roughness and of the anisotropy strength (linear unorm).
    pub roughness_bits: u32,
    /// Bits of each of the normal's two octahedral coordinates (unorm).
    pub normal_octahedral_bits: u32,
}

/// How near a tie (in steps) a stored value's exact form must lie for
/// [`GBufferPrecision::store_other_way_near_ties`] to round it the other way.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TieMargins {
    /// For every unorm value but the normal's coordinates.
    pub values: f64,
    /// For the octahedral normal's coordinates (whose GPU form carries the
    /// interpolation's error).
    pub normal: f64,
}

/// Bits of the base colour's sRGB code that index the conductor tables of materials
/// whose conductor is derived from the base colour, whatever the storage.
pub const CONDUCTOR_CODE_BITS: u32 = 8;

impl GBufferPrecision {
    /// 8-bit sRGB base colour, 8-bit metalness, 16-bit roughness, anisotropy strength
    /// and octahedral normal (Combustion's `srgb8+unorm16` storage).
    pub const SRGB8: GBufferPrecision = GBufferPrecision {
        base_color: StoredValue::Unorm(8),
        metalness: StoredValue::Unorm(8),
        roughness_bits: 16,
        normal_octahedral_bits: 16,
    };

    /// `surface` as the G-buffer stores it, for a material whose conductor is derived
    /// from the base colour when `conductor_from_base_color` (then derived again from
    /// the stored base colour's [`CONDUCTOR_CODE_BITS`]-bit sRGB code): each input
    /// rounded to the nearest stored value.
    pub fn store(&self, surface: &SurfacePoint, conductor_from_base_color: bool) -> SurfacePoint {
        self.store_rounded(surface, conductor_from_base_color, &f64::round, &f64::round)
    }

    /// As [`GBufferPrecision::store`], but each unorm value whose scaled form lies
    /// within a margin (a fraction of a step: `margins.normal` for the octahedral
    /// normal's coordinates, `margins.values` for the rest) of a tie between two codes
    /// rounded to the other one, and every half float rounded to its other neighbour.
    /// Vulkan lets a float-to-unorm conversion return either neighbouring code ("should"
    /// round to nearest), and a write to a 16-bit float target round toward zero instead
    /// of to nearest; a GPU's arithmetic may land on either side of a tie.
    pub fn store_other_way_near_ties(
        &self,
        surface: &SurfacePoint,
        conductor_from_base_color: bool,
        margins: TieMargins,
    ) -> SurfacePoint {
        let other_way = |margin: f64| {
            move |scaled: f64| {
                let nearest = scaled.round();
                if scaled == nearest {
                    nearest // stored exactly: no rounding to go either way
                } else if (scaled - scaled.floor() - 0.5).abs() < margin {
                    if nearest > scaled {
                        nearest - 1.0
                    } else {
                        nearest + 1.0
                    }
                } else {
                    nearest
                }
            }
        };
        let mut stored = self.store_rounded(
            surface,
            conductor_from_base_color,
            &other_way(margins.values),
            &other_way(f64::INFINITY),
        );
        let normal = self.store_rounded(
            surface,
            conductor_from_base_color,
            &other_way(margins.normal),
            &f64::round,
        );
        (stored.n, stored.t, stored.b) = (normal.n, normal.t, normal.b);
        stored
    }

    fn store_rounded(
        &self,
        surface: &SurfacePoint,
        conductor_from_base_color: bool,
        round: &dyn Fn(f64) -> f64,
        round_half: &dyn Fn(f64) -> f64,
    ) -> SurfacePoint {
        let unorm = |x: f64, bits: u32| {
            let steps = f64::from((1u32 << bits) - 1);
            round(x.clamp(0.0, 1.0) * steps).clamp(0.0, steps) / steps
        };
        let half = |x: f64| {
            let x = x.clamp(0.0, 1.0);
            // The step of x's binade (2⁻²⁴ among the subnormals below 2⁻¹⁴).
            let exponent = if x > 0.0 {
                x.log2().floor().max(-14.0)
            } else {
                -14.0
            };
            let step = (exponent - 10.0).exp2();
            (round_half(x / step) * step).clamp(0.0, 1.0)
        };
        let mut stored = *surface;
        let m = &mut stored.brdf;
        m.base_color = m.base_color.map(|c| match self.base_color {
            StoredValue::Unorm(bits) => srgb_decode(unorm(srgb_encode(c), bits)),
            StoredValue::Half => half(c),
        });
        if conductor_from_base_color {
            let code = |c: f64| {
                let steps = f64::from((1u32 << CONDUCTOR_CODE_BITS) - 1);
                srgb_decode((srgb_encode(c) * steps).round() / steps)
            };
            let conductor = conductor_from_reflectivity(m.base_color.map(|c| code(c) as f32));
            m.conductor_eta = conductor.eta.map(f64::from);
            m.conductor_k = conductor.k.map(f64::from);
        }
        m.metalness = match self.metalness {
            StoredValue::Unorm(bits) => unorm(m.metalness, bits),
            StoredValue::Half => half(m.metalness),
        };
        // α and the anisotropic α_t come from the stored r and s.
        let roughness = unorm(surface.roughness, self.roughness_bits);
        let strength = unorm(surface.anisotropy_strength, self.roughness_bits);
        (m.alpha_x, m.alpha_y) =
            anisotropic_alphas(alpha_from_perceptual_roughness(roughness), strength);
        m.oren_nayar_sigma = oren_nayar_sigma_from_roughness(roughness);
        stored.roughness = roughness;
        stored.anisotropy_strength = strength;
        let n = octahedral_decode(
            octahedral_encode(surface.n).map(|c| unorm(c, self.normal_octahedral_bits)),
        );
        stored.t = surface.t.reject_from_normalized(n).normalize_or(surface.t);
        stored.b = n.cross(stored.t);
        stored.n = n;
        // The clear coat's target: 16-bit unorm octahedral normal, roughness and weight.
        stored.layers.coat = surface.layers.coat.map(|mut c| {
            let normal = DVec3::new(c.normal.x, c.normal.y, c.normal.z).normalize();
            let stored_normal = octahedral_decode(octahedral_encode(normal).map(|x| unorm(x, 16)));
            c.normal = optics_vec(stored_normal);
            let roughness = unorm(c.inputs.alpha.sqrt(), 16);
            c.inputs.alpha = alpha_from_perceptual_roughness(roughness);
            c.inputs.factor = unorm(c.inputs.factor, 16);
            c
        });
        // The thin film's target: f32 weight and thickness.
        stored.layers.film = surface.layers.film.map(|f| ThinFilm {
            weight: f64::from(f.weight as f32),
            thickness_nm: f64::from(f.thickness_nm as f32),
            ..f
        });
        // The sheen's target: 16-bit unorm linear colour and perceptual roughness.
        stored.layers.sheen = surface.layers.sheen.map(|mut s| {
            s.color = s.color.map(|c| unorm(c, 16));
            let roughness = unorm(s.alpha.max(0.0).sqrt(), 16);
            s.alpha = roughness * roughness;
            s
        });
        stored
    }
}

/// The octahedral map of a unit vector to [0, 1]² (Cigolle et al. 2014).
pub fn octahedral_encode(n: DVec3) -> [f64; 2] {
    let p = n / (n.x.abs() + n.y.abs() + n.z.abs());
    let (x, y) = if p.z >= 0.0 {
        (p.x, p.y)
    } else {
        (
            (1.0 - p.y.abs()) * p.x.signum(),
            (1.0 - p.x.abs()) * p.y.signum(),
        )
    };
    [x * 0.5 + 0.5, y * 0.5 + 0.5]
}

/// The unit vector of an octahedral map's point (the inverse of [`octahedral_encode`]).
pub fn octahedral_decode(e: [f64; 2]) -> DVec3 {
    let (x, y) = (e[0] * 2.0 - 1.0, e[1] * 2.0 - 1.0);
    let z = 1.0 - x.abs() - y.abs();
    let (x, y) = if z < 0.0 {
        ((1.0 - y.abs()) * x.signum(), (1.0 - x.abs()) * y.signum())
    } else {
        (x, y)
    };
    DVec3::new(x, y, z).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn spot(inner: f32, outer: f32, range: Option<f32>) -> Light {
        Light::Spot {
            position: Vec3::new(0.0, 2.0, 0.0),
            direction: Vec3::NEG_Y,
            intensity: [4.0, 2.0, 1.0],
            inner_cone: inner,
            outer_cone: outer,
            range,
            casts_shadows: false,
            radius: 0.0,
        }
    }

    /// A spot light by hand: on the axis 2 m below, I/d² = 1 W/m² for I = 4; at 45°
    /// off the axis of a 30°/60° cone, the ramp (cos 45° − cos 60°)/(cos 30° − cos 60°)
    /// = 0.5658, squared 0.3201, times I/d² at d = 2√2; outside the outer cone, nothing;
    /// a range of 4 m windows d = 2 by (1 − (1/2)⁴)² = 0.8789.
    #[test]
    fn spot_lights_by_hand() {
        let light = spot(30f32.to_radians(), 60f32.to_radians(), None);
        let (l, e) = light_at(&light, DVec3::ZERO);
        assert!((l - DVec3::Y).length() < 1e-12);
        assert!((e[0] - 1.0).abs() < 1e-12 && (e[2] - 0.25).abs() < 1e-12);
        let (cos30, cos45, cos60) = (0.75f64.sqrt(), 0.5f64.sqrt(), 0.5);
        let ramp = (cos45 - cos60) / (cos30 - cos60);
        let (_, e) = light_at(&light, DVec3::new(2.0, 0.0, 0.0));
        assert!((e[0] - 4.0 / 8.0 * ramp * ramp).abs() < 1e-6, "{e:?}");
        let (_, e) = light_at(&light, DVec3::new(10.0, 1.9, 0.0));
        assert_eq!(e, [0.0; 3]);
        let ranged = spot(30f32.to_radians(), 60f32.to_radians(), Some(4.0));
        let (_, e) = light_at(&ranged, DVec3::ZERO);
        assert!((e[0] - (1.0 - 1.0 / 16.0f64).powi(2)).abs() < 1e-12);
    }

    /// A directional light gives its irradiance from against its direction.
    #[test]
    fn directional_light_by_hand() {
        let light = Light::Directional {
            direction: Vec3::new(0.0, -2.0, 0.0),
            irradiance: [3.0, 2.0, 1.0],
            casts_shadows: false,
            angular_diameter: 0.0,
        };
        let (l, e) = light_at(&light, DVec3::new(5.0, 6.0, 7.0));
        assert_eq!((l, e), (DVec3::Y, [3.0, 2.0, 1.0]));
    }

    /// The octahedral map is its own inverse in f64 over the whole sphere.
    #[test]
    fn octahedral_round_trip() {
        for i in 0..2000 {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 2000.0;
            let phi = i as f64 * 2.399963;
            let r = (1.0 - z * z).sqrt();
            let n = DVec3::new(r * phi.cos(), r * phi.sin(), z);
            let back = octahedral_decode(octahedral_encode(n));
            assert!((back - n).length() < 1e-12, "{n} → {back}");
        }
    }

    /// Stored in 8-bit sRGB, a base colour of 0.8 becomes code 231, 0.79910 (1.12e-3
    /// low: the whole error of a Lambert floor of that colour); 16-bit roughness 0.3
    /// stays within 1/131070, an 8-bit metalness of 0.5 rounds to 128/255, and the
    /// normal turns by less than the octahedral format's bound.
    #[test]
    fn storage_rounds_as_the_formats_say() {
        let brdf = BrdfInputs {
            base_color: [0.8; 3],
            metalness: 0.5,
            alpha_x: 0.09,
            alpha_y: 0.09,
            conductor_eta: [1.0; 3],
            conductor_k: [0.0; 3],
            dielectric_eta: 1.5,
            outside_eta: 1.0,
            polarisation_weight: 0.5,
            diffuse_model: OpticsDiffuse::Lambert,
            oren_nayar_sigma: 0.0,
        };
        let surface = SurfacePoint {
            hit: PrimaryHit {
                object: 0,
                triangle: 0,
                barycentrics: [0.0; 2],
                position: [0.0; 3],
                normal: [0.0, 1.0, 0.0],
                geometric_normal: [0.0, 1.0, 0.0],
                view_depth: 1.0,
            },
            brdf,
            n: DVec3::Y,
            t: DVec3::X,
            b: DVec3::NEG_Z,
            v: DVec3::Y,
            emitted: [0.0; 3],
            roughness: 0.3,
            uv: [[0.0; 2]; 2],
            texture_lod: None,
            texture_contrast: 0.0,
            vertex_color_gradient: 0.0,
            anisotropy_strength: 0.0,
            alpha: 1.0,
            transmission: 0.0,
            layers: Layers::default(),
            occlusion: 1.0,
        };
        let stored = GBufferPrecision::SRGB8.store(&surface, false);
        let expected = srgb_decode(231.0 / 255.0);
        assert!((stored.brdf.base_color[0] - expected).abs() < 1e-15);
        assert!((expected / 0.8 - 1.0 + 1.1216e-3).abs() < 1e-6);
        assert_eq!(stored.brdf.metalness, 128.0 / 255.0);
        assert!((stored.roughness - 0.3).abs() <= 0.5 / 65535.0);
        // 0.5 has no 16-bit unorm code: +y moves by half a step, within the format's
        // documented 6.3e-5 rad.
        let angle = stored.n.angle_between(DVec3::Y);
        assert!(angle > 0.0 && angle < 6.3e-5, "{angle}");
        assert!(stored.t.dot(stored.n).abs() < 1e-12);

        // 16-bit sRGB: 0.8 is code 59 396.45 of 65 535, stored as 59 396.
        let srgb16 = GBufferPrecision {
            base_color: StoredValue::Unorm(16),
            metalness: StoredValue::Unorm(16),
            ..GBufferPrecision::SRGB8
        };
        let stored = srgb16.store(&surface, false);
        let expected = srgb_decode(59396.0 / 65535.0);
        assert!((stored.brdf.base_color[0] - expected).abs() < 1e-15);
        assert!((expected / 0.8 - 1.0).abs() < 2e-5);
        // f16: 0.8 lies in [0.5, 1), steps of 2⁻¹¹; 1638.4 steps round to 1638 (to
        // nearest), to 1639 the other way; 0.5 is stored exactly either way.
        let half = GBufferPrecision {
            base_color: StoredValue::Half,
            metalness: StoredValue::Half,
            ..GBufferPrecision::SRGB8
        };
        let step = 2f64.powi(-11);
        assert_eq!(
            half.store(&surface, false).brdf.base_color[0],
            1638.0 * step
        );
        let margins = TieMargins {
            values: 0.0,
            normal: 0.0,
        };
        let other_way = half.store_other_way_near_ties(&surface, false, margins);
        assert_eq!(other_way.brdf.base_color[0], 1639.0 * step);
        assert_eq!(other_way.brdf.metalness, 0.5);
        // Below 2⁻¹⁴ the subnormals' step of 2⁻²⁴.
        let mut dark = surface;
        dark.brdf.base_color = [3.3 * 2f64.powi(-24); 3];
        assert_eq!(
            half.store(&dark, false).brdf.base_color[0],
            3.0 * 2f64.powi(-24)
        );
    }
}
