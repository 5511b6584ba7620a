//! The renderer's options changed between frames ([`Renderer::set_shading`], which
//! builds the pipelines the new shading options need before it switches, and
//! [`Renderer::set_light_culling`]), the image the frames' overlay shows
//! ([`Renderer::set_overlay_image`]), and the settings' validation at construction.

use std::sync::atomic::Ordering;
use std::sync::Arc;

use combustion_vk::Device;

use crate::error::RenderError;
use crate::light_cull::LightCulling;
use crate::options::{RendererSettings, ShadingOptions, MAX_FRAMES_IN_FLIGHT};
use crate::overlay::OverlayImage;
use crate::scene_upload::GpuScene;
use crate::variant::LightingFeatures;
use crate::{buffers, environment, overlay, Renderer};

impl RendererSettings {
    /// Checks every field; the shadow maps' size against `device`'s limit.
    pub(crate) fn validate(&self, device: &Device) -> Result<(), RenderError> {
        if let Some(shadows) = &self.shading.shadows {
            shadows.validate(device.limits().max_image_dimension2_d)?;
        }
        self.shading.validate_environment_samples()?;
        if !(self.exposure.is_finite() && self.exposure > 0.0) {
            return Err(RenderError::InvalidExposure(self.exposure));
        }
        if !(1..=MAX_FRAMES_IN_FLIGHT).contains(&self.frames_in_flight) {
            return Err(RenderError::InvalidFramesInFlight(self.frames_in_flight));
        }
        Ok(())
    }
}

impl Renderer {
    /// Switches to `options` from the next frame on, all at once: first builds every
    /// pipeline the new options need for `scenes` (each scene's own, and those of frames
    /// lit by a [`crate::FrameEnvironment`] baked for it) and, when energy compensation
    /// is turned on for the first time, its table; then switches. The scenes listed need
    /// no [`Renderer::prepare`] before their next frame; a scene left out needs one (its
    /// frames fail with [`RenderError::VariantNotPrepared`] until then), and scenes
    /// uploaded or edited later get theirs then.
    ///
    /// # Errors
    /// [`RenderError::SceneOfAnotherRenderer`] for a scene another renderer uploaded;
    /// [`RenderError::Vulkan`] if a pipeline or the table cannot be built. On error the
    /// options stay as they were, and so do the frames rendered with them (pipelines
    /// already built for the new options are kept, unused until asked for).
    pub fn set_shading(
        &mut self,
        options: ShadingOptions,
        scenes: &[&GpuScene],
    ) -> Result<(), RenderError> {
        if let Some(shadows) = &options.shadows {
            shadows.validate(self.device.limits().max_image_dimension2_d)?;
        }
        options.validate_environment_samples()?;
        for scene in scenes {
            if !scene.belongs_to(&self.retire_queue) {
                return Err(RenderError::SceneOfAnotherRenderer);
            }
            self.prepare_variant(options.variant(scene.variant))?;
            if scene.frame_environments.load(Ordering::Relaxed) {
                self.prepare_variant(options.variant(scene.lit_variant))?;
            }
        }
        if options.energy_compensation && self.energy_table.size() <= 16 {
            let table = energy_table(&self.device, true)?;
            let placeholder = std::mem::replace(&mut self.energy_table, table);
            self.retire(placeholder);
        }
        self.settings.shading = options;
        Ok(())
    }

    /// The shading options frames are rendered with ([`Renderer::set_shading`]).
    pub fn shading(&self) -> ShadingOptions {
        self.settings.shading
    }

    /// When frames cull their lights (tiled light lists, [`LightCulling`]); from the next
    /// frame on. Culling never changes a pixel: it leaves out only lights whose range
    /// window is exactly 0 over a whole tile.
    pub fn set_light_culling(&mut self, culling: LightCulling) {
        self.light_culling = culling;
    }

    /// When frames cull their lights ([`Renderer::set_light_culling`]).
    pub fn light_culling(&self) -> LightCulling {
        self.light_culling
    }

    /// The lighting features of the pipeline `scene`'s frames use now.
    pub fn lighting_features(&self, scene: &GpuScene) -> LightingFeatures {
        self.variant_of(scene.variant).features
    }
}

impl Renderer {
    /// Shows `image` over the frames recorded from now on (under their text panels, at
    /// the top-left, one texel a pixel), or no image. The previous image is kept until
    /// the frames in flight that show it have completed.
    pub fn set_overlay_image(&mut self, image: Option<&OverlayImage>) -> Result<(), RenderError> {
        let next = match image {
            Some(i) => {
                self.check_size(i.width, i.height)?;
                let texels = u64::from(i.width) * u64::from(i.height);
                if i.rgba.len() as u64 != texels {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} needs {texels} texels, not {}",
                        i.width,
                        i.height,
                        i.rgba.len()
                    )));
                }
                let range = u64::from(self.device.limits().max_storage_buffer_range);
                if texels * 4 > range {
                    return Err(RenderError::Overlay(format!(
                        "an overlay image of {}x{} takes {} bytes; this device reads at most {range} from one buffer",
                        i.width,
                        i.height,
                        texels * 4
                    )));
                }
                (
                    overlay_image_buffer(&self.device, &i.rgba)?,
                    Some([i.width, i.height]),
                )
            }
            None => (overlay_image_buffer(&self.device, &[[0; 4]])?, None),
        };
        let old = std::mem::replace(&mut self.overlay_image, next);
        self.retire(old.0);
        Ok(())
    }

    /// The overlay's font (its atlas and text layout), e.g. to check a frame's overlay.
    pub fn overlay_font(&self) -> &overlay::OverlayFont {
        &self.overlay_font
    }
}

/// The table energy compensation reads ([`environment::white_specular_albedo_table`])
/// when `on`, else a 16-byte placeholder (the binding exists in every lighting layout).
pub(crate) fn energy_table(
    device: &Arc<Device>,
    on: bool,
) -> Result<combustion_vk::Buffer, RenderError> {
    Ok(if on {
        buffers::filled_storage_buffer(
            device,
            "white specular albedo table",
            bytemuck::cast_slice(&environment::white_specular_albedo_table()),
        )?
    } else {
        buffers::filled_storage_buffer(device, "energy table placeholder", &[0; 16])?
    })
}

/// The sheen's albedo table (`combustion_optics::sheen::sheen_albedo_table`, then
/// `sheen_scaling_table`, as f32) when `on`, else a 16-byte placeholder (the binding exists in every lighting layout).
pub(crate) fn sheen_table(
    device: &Arc<Device>,
    on: bool,
) -> Result<combustion_vk::Buffer, RenderError> {
    Ok(if on {
        // E, then M (combustion_optics::sheen::sheen_scaling_table), each SHEEN_TABLE_SIZE².
        let table: Vec<f32> = combustion_optics::sheen::sheen_albedo_table()
            .iter()
            .chain(combustion_optics::sheen::sheen_scaling_table())
            .map(|&e| e as f32)
            .collect();
        buffers::filled_storage_buffer(device, "sheen albedo table", bytemuck::cast_slice(&table))?
    } else {
        buffers::filled_storage_buffer(device, "sheen table placeholder", &[0; 16])?
    })
}

/// A host-visible buffer holding RGBA8 texels, as the overlay reads them.
pub(crate) fn overlay_image_buffer(
    device: &Arc<Device>,
    rgba: &[[u8; 4]],
) -> Result<combustion_vk::Buffer, RenderError> {
    Ok(buffers::filled_storage_buffer(
        device,
        "overlay image",
        bytemuck::cast_slice(rgba),
    )?)
}
