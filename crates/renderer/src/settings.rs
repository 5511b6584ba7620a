//! The renderer's options changed between frames ([`Renderer::set_fresnel`] and its
//! siblings, and their getters), the image the frames' overlay shows
//! ([`Renderer::set_overlay_image`]), and the settings' validation at construction. A
//! changed option takes effect from the next frame; its pipelines are built by
//! [`Renderer::prepare`] or the next upload or edit.

use std::sync::Arc;

use combustion_scene::DiffuseModel;
use combustion_vk::Device;

use crate::error::RenderError;
use crate::light_cull::LightCulling;
use crate::options::{
    DebugView, Distribution, FresnelModel, Masking, MeasurementFloor, RendererSettings,
    MAX_FRAMES_IN_FLIGHT,
};
use crate::overlay::OverlayImage;
use crate::scene_upload::GpuScene;
use crate::variant::LightingFeatures;
use crate::{buffers, environment, overlay, Renderer};

impl RendererSettings {
    pub(crate) fn validate(&self) -> Result<(), RenderError> {
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
    /// Switches the Fresnel term between frames (the Schlick comparison variant, or the
    /// full equations). Pipelines are built by [`Renderer::prepare`] or the next upload
    /// or edit, never by a frame's recording.
    pub fn set_fresnel(&mut self, model: FresnelModel) {
        self.settings.fresnel = model;
    }

    /// The masking–shadowing term from the next frame on (the exact height-correlated
    /// form by default; the others are comparison variants). Pipelines as for
    /// [`Renderer::set_fresnel`].
    pub fn set_masking(&mut self, masking: Masking) {
        self.masking = masking;
    }

    /// The masking–shadowing term ([`Renderer::set_masking`]).
    pub fn masking(&self) -> Masking {
        self.masking
    }

    /// The microfacet normal distribution from the next frame on (GGX by default;
    /// Beckmann is a comparison variant). Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_distribution(&mut self, distribution: Distribution) {
        self.distribution = distribution;
    }

    /// The normal distribution ([`Renderer::set_distribution`]).
    pub fn distribution(&self) -> Distribution {
        self.distribution
    }

    /// Multiple-scattering energy compensation from the next frame on (off by default):
    /// every specular lobe, of lights and of the environment, is scaled by
    /// 1 + F₀ (1 − E)/E (Turquin 2019), E the white lobe's directional albedo at the
    /// pixel's n·v and roughness ([`environment::white_specular_albedo_table`]) and F₀
    /// the exact Fresnel reflectance at normal incidence (per channel, with the outside
    /// medium), so a white rough conductor keeps the energy single scattering loses.
    /// The f64 reference stays single-scattering: the difference is this option's
    /// measured deviation from it. The table is built on first use (not in a frame).
    pub fn set_energy_compensation(&mut self, on: bool) -> Result<(), RenderError> {
        if on && self.energy_table.size() <= 16 {
            let table = buffers::filled_storage_buffer(
                &self.device,
                "white specular albedo table",
                bytemuck::cast_slice(&environment::white_specular_albedo_table()),
            )?;
            let placeholder = std::mem::replace(&mut self.energy_table, table);
            self.retire(placeholder);
        }
        self.energy_compensation = on;
        Ok(())
    }

    /// Whether energy compensation is on ([`Renderer::set_energy_compensation`]).
    pub fn energy_compensation(&self) -> bool {
        self.energy_compensation
    }

    /// One diffuse model for every material's dielectric part from the next frame on
    /// (a comparison variant: the f64 reference keeps each material's own model), or
    /// `None` for each material's own (the default). Pipelines as for
    /// [`Renderer::set_fresnel`].
    pub fn set_diffuse_override(&mut self, model: Option<DiffuseModel>) {
        self.diffuse_override = model;
    }

    /// The diffuse model every material is shaded with, if any
    /// ([`Renderer::set_diffuse_override`]).
    pub fn diffuse_override(&self) -> Option<DiffuseModel> {
        self.diffuse_override
    }

    /// Renders a [`MeasurementFloor`] instead of the real pass (or the real passes
    /// again), to time a frame against what it would cost without shading. Pipelines
    /// as for [`Renderer::set_fresnel`].
    pub fn set_measurement_floor(&mut self, floor: Option<MeasurementFloor>) {
        self.floor = floor;
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

    /// Lighting pipelines specialised to each scene's features ([`LightingFeatures::of`];
    /// the default), or the general pipeline for every scene (to compare the two).
    /// Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_specialised(&mut self, specialised: bool) {
        self.specialised = specialised;
    }

    /// Whether lighting pipelines are specialised to each scene
    /// ([`Renderer::set_specialised`]).
    pub fn specialised(&self) -> bool {
        self.specialised
    }

    /// Shows a G-buffer channel or a BRDF term instead of radiance from the next frame
    /// on (render it at exposure 1). Pipelines as for [`Renderer::set_fresnel`].
    pub fn set_debug_view(&mut self, view: DebugView) {
        self.debug_view = view;
    }

    /// What the lighting pass shows ([`Renderer::set_debug_view`]).
    pub fn debug_view(&self) -> DebugView {
        self.debug_view
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
