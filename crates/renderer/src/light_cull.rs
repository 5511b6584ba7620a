//! Tiled light culling (`light_cull.comp`): per 16×16-pixel tile, the list of the
//! frame's lights that can reach a pixel of it, for the lighting pass to loop over
//! instead of every light. Only lights with a range (KHR_lights_punctual) can be left
//! out; the lists keep index order, so a culled frame is the same sum as an unculled
//! one, less terms that are exactly zero (tests/light_culling.rs checks bit equality).
//! Here: when frames cull and the tile grid; the pass itself is `passes/light_cull.rs`.

use combustion_vk::vk;

/// Tile edge in pixels (`TILE_SIZE` in light_cull.comp and lighting.frag, from the
/// generated `bindings/constants.glsl`).
pub const TILE_SIZE: u32 = 16;

/// The most lights a frame can cull (each tile's list has room for every light: at
/// 1280×720, 3,600 tiles × 1,025 words = 14.8 MB); frames with more light every pixel
/// with every light.
pub const MAX_CULLED_LIGHTS: usize = 1024;

/// When frames cull their lights.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightCulling {
    /// When some light of the frame has a range (the only lights culling can leave out),
    /// and the frame has at most [`MAX_CULLED_LIGHTS`] lights.
    #[default]
    Auto,
    /// Every frame with 1 to [`MAX_CULLED_LIGHTS`] lights (for tests and measurements).
    Always,
    /// Never: every pixel loops over every light.
    Never,
}

impl LightCulling {
    /// Every choice, in the order the command line lists them.
    pub const ALL: [LightCulling; 3] = [Self::Auto, Self::Always, Self::Never];

    /// The name the command line gives it (`auto`, `always`, `never`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Always => "always",
            Self::Never => "never",
        }
    }

    /// Whether a frame with `lights` culls them.
    pub fn culls(self, lights: &[combustion_scene::Light]) -> bool {
        let fits = !lights.is_empty() && lights.len() <= MAX_CULLED_LIGHTS;
        match self {
            Self::Never => false,
            Self::Always => fits,
            Self::Auto => fits && lights.iter().any(|l| l.range().is_some()),
        }
    }
}

/// The tile grid of a target: tiles across and down.
pub fn tiles(extent: vk::Extent2D) -> (u32, u32) {
    (
        extent.width.div_ceil(TILE_SIZE),
        extent.height.div_ceil(TILE_SIZE),
    )
}
