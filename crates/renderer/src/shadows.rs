//! Shadows: cascaded shadow maps of directional lights, a perspective map per spot light
//! and a cube of six per point light; their settings, their placement (on the CPU, per
//! frame), the maps' image and the depth-only pipeline that renders the scene's objects
//! into them (through [`crate::mesh_draw`]). The lighting
//! pass samples them (shaders/include/shadows.glsl); docs/shadows.md states the rules.
//!
//! Placement (one place for each rule):
//! - **Range**: the cascades cover the camera's view from its near plane to the *shadow
//!   distance*: the camera's far plane, or less where the scene ends sooner (the
//!   farthest corner of the scene's bounds along the view direction), rounded up to a
//!   power of 2^(1/4) so that it changes in steps, not with every camera move.
//! - **Splits**: the practical split scheme (Zhang et al. 2006), the mean of the
//!   logarithmic and the uniform split weighted [`SPLIT_LOGARITHMIC_WEIGHT`].
//! - **Stability**: each cascade is the bounding sphere of its slice of the view frustum
//!   (its radius depends only on the slice and the field of view, not on the camera's
//!   orientation), seen by an orthographic projection 2R wide whose centre is snapped to
//!   whole texels in light space: a moving or turning camera moves the map by whole
//!   texels, so shadow edges do not shimmer.
//! - **Depth**: along the light, every map spans the scene's whole bounds (the casters
//!   out of view included), whatever the camera's range: casters far larger than the
//!   view change the depth range (32-bit float), never the maps' texel size.

use std::sync::Arc;

use combustion_scene::{box_corners, Camera, Light};
use combustion_vk::{vk, Device, Image, ImageDesc, ImageView, Sampler};
use glam::{Mat4, Vec3};

use crate::error::RenderError;
use crate::gpu_types::GpuShadowCascade;

/// Directional lights that cast shadows in one frame, at most: the first ones of the
/// frame's lights; later ones light without shadows.
pub const MAX_SHADOWED_LIGHTS: usize = 4;
/// Cascades per directional light, at most.
pub const MAX_CASCADES: u32 = 4;
/// The shadow maps' format: 32-bit float depth.
pub const SHADOW_MAP_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// Smallest shadow map side accepted.
pub const MIN_SHADOW_MAP_SIZE: u32 = 64;
/// The weight of the logarithmic split in the practical split scheme (1 − it: the
/// uniform split's).
pub const SPLIT_LOGARITHMIC_WEIGHT: f32 = 0.75;
/// Radius of the PCF kernel, in shadow-map texels (the Vogel disk's; [`ShadowFilter`]).
pub const PCF_RADIUS_TEXELS: f32 = 1.5;
/// The share of a cascade's slice of the view, at its end, over which it fades into the
/// next one.
pub const CASCADE_BLEND_BAND: f32 = 0.1;
/// Depth reads of the blocker search, and comparisons of the filter, of a light with a
/// size (contact-hardening PCF, PCSS).
pub const SOFT_TAPS: u32 = 16;
/// The widest blocker search and filter of a light with a size, in texels (the
/// penumbra is capped at twice this).
pub const SOFT_MAX_RADIUS_TEXELS: f32 = 16.0;

/// How shadow-map lookups are filtered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShadowFilter {
    /// One depth comparison, bilinearly weighted over the 2×2 texels around the lookup
    /// (the sampler's own percentage-closer filtering): hard edges. The default: on
    /// lavapipe each further comparison costs about as much as this one.
    #[default]
    Hard,
    /// Percentage-closer filtering over 16 comparisons on a Vogel disk of
    /// [`PCF_RADIUS_TEXELS`], rotated per pixel (interleaved gradient noise), each one
    /// itself bilinearly weighted.
    Pcf16,
    /// As [`ShadowFilter::Pcf16`] with 8 taps.
    Pcf8,
    /// As [`ShadowFilter::Pcf16`] with 32 taps.
    Pcf32,
}

impl ShadowFilter {
    /// Every filter, in the order the viewer cycles them.
    pub const ALL: [ShadowFilter; 4] = [
        ShadowFilter::Hard,
        ShadowFilter::Pcf8,
        ShadowFilter::Pcf16,
        ShadowFilter::Pcf32,
    ];

    /// Depth comparisons per lookup (each bilinearly weighted).
    pub fn taps(self) -> u32 {
        match self {
            Self::Hard => 1,
            Self::Pcf8 => 8,
            Self::Pcf16 => 16,
            Self::Pcf32 => 32,
        }
    }

    /// The same count as the shader's `#define` value.
    fn taps_define(self) -> &'static str {
        match self {
            Self::Hard => "1",
            Self::Pcf8 => "8",
            Self::Pcf16 => "16",
            Self::Pcf32 => "32",
        }
    }

    /// A short name for titles and tables (`hard`, `pcf16`, …).
    pub fn name(self) -> &'static str {
        match self {
            Self::Hard => "hard",
            Self::Pcf8 => "pcf8",
            Self::Pcf16 => "pcf16",
            Self::Pcf32 => "pcf32",
        }
    }
}

/// Shadows of directional lights ([`crate::ShadingOptions::shadows`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShadowSettings {
    /// Cascades per light, 1 to [`MAX_CASCADES`].
    pub cascades: u32,
    /// Each cascade's map side in texels, [`MIN_SHADOW_MAP_SIZE`] to the device's largest
    /// 2D image side.
    pub map_size: u32,
    /// The side in texels of each map of a spot or point light (one per spot light, six
    /// per point light), in the same range.
    pub local_map_size: u32,
    /// How lookups are filtered.
    pub filter: ShadowFilter,
}

impl ShadowSettings {
    /// Four cascades of 2048², spot and point lights' maps of 1024², the hard (bilinear)
    /// filter.
    pub const DEFAULT: ShadowSettings = ShadowSettings {
        cascades: 4,
        map_size: 2048,
        local_map_size: 1024,
        filter: ShadowFilter::Hard,
    };

    /// Checks the ranges the fields state, against a device whose 2D images are at most
    /// `max_image_side` texels a side.
    ///
    /// # Errors
    /// [`RenderError::InvalidShadowSettings`] naming the field.
    pub fn validate(&self, max_image_side: u32) -> Result<(), RenderError> {
        if !(1..=MAX_CASCADES).contains(&self.cascades) {
            return Err(RenderError::InvalidShadowSettings(format!(
                "{} cascades; use 1 to {MAX_CASCADES}",
                self.cascades
            )));
        }
        for (what, size) in [
            ("a shadow map", self.map_size),
            ("a local light's shadow map", self.local_map_size),
        ] {
            if !(MIN_SHADOW_MAP_SIZE..=max_image_side).contains(&size) {
                return Err(RenderError::InvalidShadowSettings(format!(
                    "{what} of {size}x{size}; the side must be {MIN_SHADOW_MAP_SIZE} to {max_image_side} on this device"
                )));
            }
        }
        Ok(())
    }

    /// What the lighting shader's variant needs of these settings, for a scene whose
    /// lights cast `kinds` of shadow.
    pub(crate) fn shader(&self, kinds: ShadowKinds) -> ShadowShader {
        ShadowShader {
            cascades: self.cascades,
            filter: self.filter,
            kinds,
        }
    }
}

impl Default for ShadowSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The kinds of shadow a scene's lights cast (those whose `casts_shadows` is set): the
/// lighting pipeline compiles only their code. A frame's lights of another kind (a host
/// may bring its own) light it unshadowed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ShadowKinds {
    /// Directional lights: cascades.
    pub cascaded: bool,
    /// Spot and point lights: perspective maps and cubes.
    pub local: bool,
    /// Lights with a size: contact-hardening soft shadows.
    pub soft: bool,
}

impl ShadowKinds {
    /// The kinds `lights` cast.
    pub fn of(lights: &[Light]) -> ShadowKinds {
        let mut kinds = ShadowKinds::default();
        for light in lights.iter().filter(|l| l.casts_shadows()) {
            match *light {
                Light::Directional {
                    angular_diameter, ..
                } => {
                    kinds.cascaded = true;
                    kinds.soft |= angular_diameter > 0.0;
                }
                Light::Point { radius, .. } | Light::Spot { radius, .. } => {
                    kinds.local = true;
                    kinds.soft |= radius > 0.0;
                }
            }
        }
        kinds
    }

    /// Whether `light` casts a shadow of these kinds.
    pub fn cast_by(&self, light: &Light) -> bool {
        light.casts_shadows()
            && match light {
                Light::Directional { .. } => self.cascaded,
                Light::Point { .. } | Light::Spot { .. } => self.local,
            }
    }
}

/// The part of [`ShadowSettings`] compiled into the lighting pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ShadowShader {
    /// Cascades per light.
    pub cascades: u32,
    /// The lookup filter.
    pub filter: ShadowFilter,
    /// The kinds of shadow compiled in (the scene's lights').
    pub kinds: ShadowKinds,
}

impl ShadowShader {
    /// Its `#define`s: `SHADOWS`, `SHADOW_CASCADES`, `SHADOW_TAPS`, and
    /// `SHADOW_CASCADED`, `SHADOW_LOCAL`, `SHADOW_SOFT` by its kinds.
    pub(crate) fn defines(&self, defines: &mut Vec<(&'static str, Option<&'static str>)>) {
        const COUNTS: [&str; MAX_CASCADES as usize] = ["1", "2", "3", "4"];
        defines.push((crate::variant::SHADOWS.define, None));
        for (present, define) in [
            (self.kinds.cascaded, "SHADOW_CASCADED"),
            (self.kinds.local, "SHADOW_LOCAL"),
            (self.kinds.soft, "SHADOW_SOFT"),
        ] {
            if present {
                defines.push((define, None));
            }
        }
        defines.push((
            "SHADOW_CASCADES",
            Some(COUNTS[(self.cascades.clamp(1, MAX_CASCADES) - 1) as usize]),
        ));
        defines.push(("SHADOW_TAPS", Some(self.filter.taps_define())));
    }
}

/// One cascade of one light, placed for a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cascade {
    /// World space to the map's clip space (x, y in [−1, 1] across the map, depth in
    /// [0, 1] along the light): what the caster pass renders with.
    pub world_to_clip: Mat4,
    /// The side of one map texel, metres.
    pub texel_world: f32,
    /// Metres of the scene along the light per unit of map depth.
    pub depth_range: f32,
    /// The view-frustum slice it covers, as distances along the view direction.
    pub slice: [f32; 2],
    /// The camera's unit view direction (what the slice's distances are measured along).
    pub view_forward: Vec3,
}

impl Cascade {
    /// The table entry the lighting pass reads.
    pub(crate) fn gpu(&self) -> GpuShadowCascade {
        GpuShadowCascade {
            world_to_clip: self.world_to_clip.to_cols_array(),
            texel_depth_slice: [self.texel_world, self.depth_range, self.slice[1], 0.0],
            view_forward: self.view_forward.extend(0.0).to_array(),
        }
    }
}

/// The practical split distances of `count` cascades over [near, far]: count + 1
/// values from `near` to `far`.
pub fn cascade_splits(near: f32, far: f32, count: u32) -> Vec<f32> {
    (0..=count)
        .map(|i| {
            let t = i as f32 / count as f32;
            let logarithmic = near * (far / near).powf(t);
            let uniform = near + (far - near) * t;
            SPLIT_LOGARITHMIC_WEIGHT * logarithmic + (1.0 - SPLIT_LOGARITHMIC_WEIGHT) * uniform
        })
        .collect()
}

/// The shadow distance of `camera` for a scene within `bounds` (see the module's
/// rules): at most the far plane, at least a little beyond the near plane.
pub fn shadow_distance(camera: &Camera, bounds: Option<(Vec3, Vec3)>) -> f32 {
    let forward = (camera.target - camera.position).normalize();
    let farthest = bounds.map_or(camera.far, |(min, max)| {
        box_corners(min, max)
            .iter()
            .map(|corner| (*corner - camera.position).dot(forward))
            .fold(f32::MIN, f32::max)
    });
    // Rounded up to a power of 2^(1/4): the splits change in steps as the camera moves.
    let quarter_octaves = (farthest.max(camera.near * 2.0) / camera.near).log2() * 4.0;
    let stepped = camera.near * (quarter_octaves.ceil() / 4.0).exp2();
    stepped.clamp(camera.near * 1.01, camera.far)
}

/// A unit vector not parallel to `direction`, for the light's view basis.
fn light_up(direction: Vec3) -> Vec3 {
    if direction.y.abs() < 0.99 {
        Vec3::Y
    } else {
        Vec3::Z
    }
}

/// The cascades of a directional light travelling along `direction` (unit), for a
/// frame of `camera` at `aspect` (width / height) over a scene within `bounds`, with
/// maps of `map_size` texels a side.
pub fn directional_cascades(
    camera: &Camera,
    aspect: f32,
    direction: Vec3,
    bounds: Option<(Vec3, Vec3)>,
    cascades: u32,
    map_size: u32,
) -> Vec<Cascade> {
    let forward = (camera.target - camera.position).normalize();
    let far = shadow_distance(camera, bounds);
    let splits = cascade_splits(camera.near, far, cascades);
    // The half-diagonal of the view frustum per metre of distance.
    let half_height = (camera.vertical_fov * 0.5).tan();
    let k2 = half_height * half_height * (1.0 + aspect * aspect);
    // Light space: rotation only (the light looks along `direction`).
    let light_view = Mat4::look_to_rh(Vec3::ZERO, direction, light_up(direction));
    // The scene's extent along the light (view-space z is minus the distance along it).
    let scene_depth = bounds.map(|(min, max)| {
        box_corners(min, max)
            .iter()
            .fold((f32::MAX, f32::MIN), |(lo, hi), corner| {
                let z = light_view.transform_point3(*corner).z;
                (lo.min(z), hi.max(z))
            })
    });
    splits
        .windows(2)
        .map(|slice| {
            let (n, f) = (slice[0], slice[1]);
            // The slice's bounding sphere, centred on the view axis at depth c, equally
            // far from the near and the far corners (or at the far plane's centre when
            // that is closer).
            let c = (0.5 * (n + f) * (1.0 + k2)).min(f);
            let radius = ((f - c) * (f - c) + f * f * k2).sqrt();
            // Rounded up to 1/64 of itself in steps: a constant radius for a constant slice.
            let radius = radius * (1.0 + 1.0 / 64.0);
            let centre = camera.position + forward * c;
            let texel = 2.0 * radius / map_size as f32;
            let mut centre_light = light_view.transform_point3(centre);
            centre_light.x = (centre_light.x / texel).round() * texel;
            centre_light.y = (centre_light.y / texel).round() * texel;
            // Depth: the whole scene along the light, and at least the sphere.
            let (mut lo, mut hi) = (centre_light.z - radius, centre_light.z + radius);
            if let Some((scene_lo, scene_hi)) = scene_depth {
                lo = lo.min(scene_lo);
                hi = hi.max(scene_hi);
            }
            // A little margin, so casters on the bounds are not clipped by rounding.
            let margin = (hi - lo) * 1e-3 + 1e-3;
            let (near_plane, far_plane) = (-(hi + margin), -(lo - margin));
            let projection = Mat4::orthographic_rh(
                centre_light.x - radius,
                centre_light.x + radius,
                centre_light.y - radius,
                centre_light.y + radius,
                near_plane,
                far_plane,
            );
            Cascade {
                world_to_clip: projection * light_view,
                texel_world: texel,
                depth_range: far_plane - near_plane,
                slice: [n, f],
                view_forward: forward,
            }
        })
        .collect()
}

/// A shadow-map layer of the frame: the matrix its casters are rendered with, and what
/// the lighting pass reads of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShadowLayer {
    /// What the lighting pass reads; its `world_to_clip` is also what the casters are
    /// rendered with ([`ShadowLayer::world_to_clip`]).
    pub(crate) gpu: GpuShadowCascade,
    /// A spot or point light's layer (in the local lights' maps), not a cascade.
    pub(crate) local: bool,
}

impl ShadowLayer {
    /// The matrix the layer's casters are rendered with.
    pub(crate) fn world_to_clip(&self) -> Mat4 {
        Mat4::from_cols_array(&self.gpu.world_to_clip)
    }
}

/// `GpuShadowCascade::texel_depth_slice.w` of a spot light's one perspective layer (0: a
/// directional light's orthographic cascade).
pub const LAYER_PERSPECTIVE: f32 = 1.0;
/// `GpuShadowCascade::texel_depth_slice.w` of a face of a light's cube of six layers.
pub const LAYER_CUBE_FACE: f32 = 2.0;

/// Which of `lights` get shadow maps, with the layers each takes, in the order of
/// `lights`: of those that cast shadows of `kinds`, the first [`MAX_SHADOWED_LIGHTS`]
/// directional lights (a layer per cascade), spot lights (one perspective layer; six, as
/// a point light, when the cone is wider than [`MAX_SPOT_CONE_ONE_LAYER`]) and point
/// lights (six faces of a cube), as long as the layers fit [`MAX_SHADOW_LAYERS`]; a
/// light whose layers do not fit casts none (the command line says which).
pub fn shadowed_lights(
    lights: &[Light],
    settings: &ShadowSettings,
    kinds: ShadowKinds,
) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut layers = 0;
    let mut suns = 0;
    for (index, light) in lights.iter().enumerate() {
        if !kinds.cast_by(light) {
            continue;
        }
        let count = match *light {
            Light::Directional { .. } => {
                if suns == MAX_SHADOWED_LIGHTS {
                    continue;
                }
                suns += 1;
                settings.cascades as usize
            }
            Light::Spot { outer_cone, .. } if outer_cone <= MAX_SPOT_CONE_ONE_LAYER => 1,
            Light::Spot { .. } | Light::Point { .. } => 6,
        };
        if layers + count > MAX_SHADOW_LAYERS {
            continue;
        }
        layers += count;
        out.push((index, count));
    }
    out
}

/// The frame's shadowed lights ([`shadowed_lights`]), each with its index and its layers
/// (light after light, in the maps' layer order).
pub(crate) fn frame_shadows(
    lights: &[Light],
    camera: &Camera,
    aspect: f32,
    bounds: Option<(Vec3, Vec3)>,
    settings: &ShadowSettings,
    kinds: ShadowKinds,
) -> Vec<(usize, Vec<ShadowLayer>)> {
    shadowed_lights(lights, settings, kinds)
        .into_iter()
        .map(|(index, count)| {
            let layers: Vec<ShadowLayer> = match lights[index] {
                Light::Directional { direction, .. } => directional_cascades(
                    camera,
                    aspect,
                    direction.normalize(),
                    bounds,
                    settings.cascades,
                    settings.map_size,
                )
                .iter()
                .map(|c| ShadowLayer {
                    gpu: c.gpu(),
                    local: false,
                })
                .collect(),
                Light::Spot {
                    position,
                    direction,
                    outer_cone,
                    range,
                    ..
                } if outer_cone <= MAX_SPOT_CONE_ONE_LAYER => {
                    let (near, far) = local_depth_range(position, range, bounds);
                    vec![perspective_layer(
                        position,
                        direction.normalize(),
                        outer_cone,
                        near,
                        far,
                        settings.local_map_size,
                        LAYER_PERSPECTIVE,
                    )]
                }
                Light::Spot {
                    position, range, ..
                }
                | Light::Point {
                    position, range, ..
                } => {
                    let (near, far) = local_depth_range(position, range, bounds);
                    cube_layers(position, near, far, settings.local_map_size)
                }
            };
            debug_assert_eq!(layers.len(), count, "the layers shadowed_lights counted");
            (index, layers)
        })
        .collect()
}

/// The side of a shadow-map texel of the spot or point `light` per metre of distance
/// from it (a texel at distance d is d times this wide), with maps of `map_size`
/// ([`ShadowSettings::local_map_size`]); `None` for a directional light (its cascades'
/// texels: [`Cascade::texel_world`]).
pub fn local_texel_per_metre(light: &Light, map_size: u32) -> Option<f32> {
    let half_angle = match *light {
        Light::Directional { .. } => return None,
        Light::Spot { outer_cone, .. } if outer_cone <= MAX_SPOT_CONE_ONE_LAYER => outer_cone,
        Light::Spot { .. } | Light::Point { .. } => std::f32::consts::FRAC_PI_4,
    };
    Some(texel_per_metre(half_angle, map_size))
}

/// A texel's side per metre of depth along the axis of a layer covering a cone of
/// `half_angle` (widened for the filter) with `map_size` texels a side.
fn texel_per_metre(half_angle: f32, map_size: u32) -> f32 {
    2.0 * widened(half_angle, map_size).tan() / map_size as f32
}

/// Shadow-map layers one frame may use, at most (a directional light takes one per
/// cascade, a spot light one, a point light six).
pub const MAX_SHADOW_LAYERS: usize = 32;

/// The widest spot cone (half-angle, radians) shadowed by one perspective layer: 60°.
/// Wider cones get a point light's six faces.
pub const MAX_SPOT_CONE_ONE_LAYER: f32 = std::f32::consts::FRAC_PI_3;

/// The near and far planes of a local light's maps: far is the light's range, or the
/// farthest corner of the scene's bounds (the nearest of the two), near a
/// ten-thousandth of it (at least 1 mm).
fn local_depth_range(
    position: Vec3,
    range: Option<f32>,
    bounds: Option<(Vec3, Vec3)>,
) -> (f32, f32) {
    let to_bounds = bounds.map(|(min, max)| {
        box_corners(min, max)
            .iter()
            .map(|corner| corner.distance(position))
            .fold(0.0f32, f32::max)
    });
    let far = match (range, to_bounds) {
        (Some(r), Some(b)) => r.min(b),
        (Some(r), None) => r,
        (None, Some(b)) => b,
        (None, None) => 1.0,
    }
    .max(1e-2)
        * 1.01;
    ((far * 1e-4).max(1e-3).min(far * 0.5), far)
}

/// The half-angle, beyond `half_angle`, a local light's layer reaches so that every
/// tap of the filter around a point inside `half_angle` stays on the map:
/// PCF_RADIUS_TEXELS + 2 texels more on each side.
fn widened(half_angle: f32, map_size: u32) -> f32 {
    let extra = 2.0 * (PCF_RADIUS_TEXELS + 2.0) / map_size as f32;
    (half_angle.tan() * (1.0 + extra)).atan()
}

/// A perspective layer from `position` along `axis` covering the cone of `half_angle`.
fn perspective_layer(
    position: Vec3,
    axis: Vec3,
    half_angle: f32,
    near: f32,
    far: f32,
    map_size: u32,
    kind: f32,
) -> ShadowLayer {
    let view = Mat4::look_to_rh(position, axis, light_up(axis));
    let world_to_clip =
        Mat4::perspective_rh(2.0 * widened(half_angle, map_size), 1.0, near, far) * view;
    ShadowLayer {
        gpu: GpuShadowCascade {
            world_to_clip: world_to_clip.to_cols_array(),
            texel_depth_slice: [texel_per_metre(half_angle, map_size), near, far, kind],
            // The layer in its array (filled in when the frame's layers are counted).
            view_forward: [0.0; 4],
        },
        local: true,
    }
}

/// The six faces of a cube around `position`, in the order +X, −X, +Y, −Y, +Z, −Z (the
/// lighting pass picks the face by the major axis of the direction from the light), each
/// a little wider than 90° so a filter near a face's edge stays on its map: the faces
/// meet without a seam.
fn cube_layers(position: Vec3, near: f32, far: f32, map_size: u32) -> Vec<ShadowLayer> {
    [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z]
        .iter()
        .map(|&axis| {
            perspective_layer(
                position,
                axis,
                std::f32::consts::FRAC_PI_4,
                near,
                far,
                map_size,
                LAYER_CUBE_FACE,
            )
        })
        .collect()
}

/// One array of shadow maps (the cascades' or the local lights'): a depth image with a
/// layer per map, a view of each layer to render into, and one of them all to sample. Shared by every frame slot: frames are submitted in order on one
/// queue, and the barriers order a frame's caster pass after the previous frame's reads.
pub(crate) struct ShadowMaps {
    /// What the layers hold: the geometry version of the scene rendered into them
    /// ([`GpuScene::geometry_version`]), its pose's digest (0 at rest) and each layer's
    /// world-to-clip matrix; `None` before the first render. A frame whose scene, pose
    /// and cascades are the same renders nothing and reads them as they are.
    pub(crate) contents: Option<(u64, u64, Vec<[f32; 16]>)>,
    /// A 2D view of each layer, for rendering (dropped before the image).
    pub(crate) layer_views: Vec<ImageView>,
    /// A 2D-array view of every layer, for sampling (also when there is one layer).
    pub(crate) array_view: ImageView,
    /// The maps (`layers` layers of `size`², [`SHADOW_MAP_FORMAT`]).
    pub(crate) image: Image,
}

impl ShadowMaps {
    /// Maps of `size`² with `layers` layers (`local`: the spot and point lights').
    pub(crate) fn new(
        device: &Arc<Device>,
        size: u32,
        layers: u32,
        local: bool,
    ) -> Result<Self, RenderError> {
        let image = Image::new(
            device,
            &ImageDesc::new(
                if local {
                    "local lights' shadow maps"
                } else {
                    "shadow cascades"
                },
                SHADOW_MAP_FORMAT,
                size,
                size,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
            )
            .array(layers),
        )?;
        let layer_views = (0..layers)
            .map(|layer| image.view_of(0..1, layer..layer + 1, vk::ImageViewType::TYPE_2D))
            .collect::<Result<_, _>>()?;
        let array_view = image.view_of(0..1, 0..layers, vk::ImageViewType::TYPE_2D_ARRAY)?;
        Ok(Self {
            contents: None,
            layer_views,
            array_view,
            image,
        })
    }

    /// Whether these maps are `size`² and have at least `layers` layers.
    pub(crate) fn fits(&self, size: u32, layers: u32) -> bool {
        self.image.extent().width == size && self.image.layers() >= layers
    }
}

/// The comparison sampler of the shadow maps: bilinear percentage-closer filtering
/// (a lookup's reference depth compared with the 2×2 texels around it, the results
/// weighted bilinearly), clamped at the edges.
pub(crate) fn shadow_sampler(device: &Arc<Device>) -> Result<Sampler, RenderError> {
    Ok(Sampler::new(
        device,
        &vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .compare_enable(true)
            .compare_op(vk::CompareOp::LESS_OR_EQUAL)
            .max_lod(0.0),
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The maps' layers go to the lights in order until they are full; the frame's layers
    /// are the ones counted.
    #[test]
    fn lights_take_layers_in_order_until_the_maps_are_full() {
        let point = |x: f32| Light::Point {
            position: Vec3::new(x, 2.0, 0.0),
            intensity: [1.0; 3],
            range: None,
            casts_shadows: true,
            radius: 0.0,
        };
        let mut lights = vec![Light::Directional {
            direction: Vec3::new(0.0, -1.0, 0.2),
            irradiance: [1.0; 3],
            casts_shadows: true,
            angular_diameter: 0.0,
        }];
        lights.extend((0..7).map(|k| point(k as f32)));
        let settings = ShadowSettings::default();
        let kinds = ShadowKinds::of(&lights);
        let shadowed = shadowed_lights(&lights, &settings, kinds);
        assert_eq!(shadowed, vec![(0, 4), (1, 6), (2, 6), (3, 6), (4, 6)]);
        let frame = frame_shadows(&lights, &camera(), 1.5, None, &settings, kinds);
        let counted: Vec<(usize, usize)> = frame.iter().map(|(i, l)| (*i, l.len())).collect();
        assert_eq!(counted, shadowed);
    }

    fn camera() -> Camera {
        Camera {
            position: Vec3::new(0.0, 3.0, 10.0),
            target: Vec3::new(0.0, 0.0, 0.0),
            up: Vec3::Y,
            vertical_fov: 0.8,
            near: 0.1,
            far: 100.0,
        }
    }

    /// Every point of the view frustum up to the shadow distance lies inside the map of
    /// the cascade whose slice holds it, and at its depth between the map's near and
    /// far planes: the cascades cover the frustum without gaps.
    #[test]
    fn cascades_cover_the_view_frustum_without_gaps() {
        let camera = camera();
        let aspect = 16.0 / 9.0;
        let bounds = Some((Vec3::new(-20.0, -1.0, -20.0), Vec3::new(20.0, 5.0, 20.0)));
        for direction in [
            Vec3::new(0.3, -1.0, 0.2),
            Vec3::new(1.0, -0.1, 0.0),
            Vec3::new(0.0, -1.0, 0.0),
        ] {
            let cascades =
                directional_cascades(&camera, aspect, direction.normalize(), bounds, 4, 1024);
            assert_eq!(cascades.len(), 4);
            let inverse = camera.view_projection(aspect).inverse();
            let view = camera.view();
            let mut checked = 0;
            for ix in 0..=16 {
                for iy in 0..=16 {
                    for iz in 0..=64 {
                        let ndc = Vec3::new(
                            ix as f32 / 8.0 - 1.0,
                            iy as f32 / 8.0 - 1.0,
                            iz as f32 / 64.0,
                        );
                        let p = inverse.project_point3(ndc);
                        let distance = -view.transform_point3(p).z;
                        let Some(cascade) = cascades
                            .iter()
                            .find(|c| distance >= c.slice[0] && distance <= c.slice[1])
                        else {
                            continue; // beyond the shadow distance
                        };
                        let clip = cascade.world_to_clip.project_point3(p);
                        assert!(
                            clip.x.abs() <= 1.0
                                && clip.y.abs() <= 1.0
                                && (0.0..=1.0).contains(&clip.z),
                            "{p} (distance {distance}) outside its cascade {:?}: {clip}",
                            cascade.slice
                        );
                        checked += 1;
                    }
                }
            }
            assert!(checked > 10_000, "{checked} points checked");
        }
    }

    /// A camera moved sideways by a fraction of a texel leaves the map where it was, and
    /// one moved by whole texels moves it by whole texels: texel snapping.
    #[test]
    fn cascades_move_by_whole_texels() {
        let direction = Vec3::new(0.3, -1.0, 0.2).normalize();
        let bounds = Some((Vec3::splat(-50.0), Vec3::splat(50.0)));
        let a = directional_cascades(&camera(), 1.5, direction, bounds, 2, 512);
        for step in [0.001f32, 0.37, 1.3] {
            let mut moved = camera();
            moved.position.x += step;
            moved.target.x += step;
            let b = directional_cascades(&moved, 1.5, direction, bounds, 2, 512);
            for (ca, cb) in a.iter().zip(&b) {
                assert_eq!(ca.texel_world, cb.texel_world);
                // The map's x, y offset in clip space, in texels: whole numbers.
                let shift = (cb.world_to_clip.w_axis - ca.world_to_clip.w_axis) * 0.5 * 512.0;
                for s in [shift.x, shift.y] {
                    assert!(
                        (s - s.round()).abs() < 2e-2,
                        "shift {s} texels at step {step}"
                    );
                }
            }
        }
    }

    /// The kinds compiled follow the lights that cast shadows: a sun alone compiles
    /// cascades only; a point light adds the local maps; a size adds soft shadows; a
    /// light that casts none adds nothing.
    #[test]
    fn shadow_kinds_follow_the_casting_lights() {
        let sun = |angular_diameter, casts_shadows| Light::Directional {
            direction: Vec3::NEG_Y,
            irradiance: [1.0; 3],
            casts_shadows,
            angular_diameter,
        };
        let point = |radius, casts_shadows| Light::Point {
            position: Vec3::Y,
            intensity: [1.0; 3],
            range: None,
            casts_shadows,
            radius,
        };
        let kinds = |cascaded, local, soft| ShadowKinds {
            cascaded,
            local,
            soft,
        };
        assert_eq!(
            ShadowKinds::of(&[sun(0.0, true)]),
            kinds(true, false, false)
        );
        assert_eq!(
            ShadowKinds::of(&[sun(0.0, true), point(0.0, true)]),
            kinds(true, true, false)
        );
        assert_eq!(
            ShadowKinds::of(&[point(0.1, true)]),
            kinds(false, true, true)
        );
        assert_eq!(
            ShadowKinds::of(&[sun(0.01, false), point(0.1, false)]),
            ShadowKinds::default()
        );
        let only_suns = kinds(true, false, false);
        assert!(only_suns.cast_by(&sun(0.0, true)) && !only_suns.cast_by(&point(0.0, true)));
    }

    #[test]
    fn splits_run_from_near_to_the_shadow_distance() {
        let s = cascade_splits(0.1, 100.0, 4);
        assert_eq!(s.len(), 5);
        assert!((s[0] - 0.1).abs() < 1e-6 && (s[4] - 100.0).abs() < 1e-3);
        assert!(s.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn settings_out_of_range_are_refused() {
        let ok = ShadowSettings::DEFAULT;
        assert!(ok.validate(16384).is_ok());
        for bad in [
            ShadowSettings { cascades: 0, ..ok },
            ShadowSettings { cascades: 5, ..ok },
            ShadowSettings { map_size: 16, ..ok },
            ShadowSettings {
                local_map_size: 0,
                ..ok
            },
            ShadowSettings {
                map_size: 32768,
                ..ok
            },
        ] {
            let e = bad.validate(16384).unwrap_err().to_string();
            assert!(e.contains("shadow"), "{e}");
        }
    }
}
