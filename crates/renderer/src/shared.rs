//! What the frame's passes read besides their own pipelines and the frame's targets:
//! placeholders bound where a frame has no such resource, the samplers, the tables some
//! variants read, and the overlay's font and image. One per renderer, made with it;
//! a table replaces its placeholder the first time a variant needs it.

use std::sync::Arc;

use combustion_vk::{vk, Buffer, Device, Image, Sampler};

use crate::environment::{self, GpuEnvironment};
use crate::error::RenderError;
use crate::options::RendererSettings;
use crate::overlay::{self, OverlayFont};
use crate::{buffers, placeholders, shadows};

/// The renderer's shared resources (module documentation).
pub(crate) struct SharedResources {
    /// Bound in the lighting set for scenes without an environment.
    pub(crate) no_environment: GpuEnvironment,
    /// Bound where the frame's G-buffer has no such target (emissive, coat, sheen, film,
    /// specular) and where a frame has no image behind its glass.
    pub(crate) absent_target: Image,
    /// [`environment::white_specular_albedo_table`] once compensation was asked for (a
    /// 16-byte placeholder before: the binding exists in every lighting layout).
    pub(crate) energy_table: Buffer,
    /// [`combustion_optics::sheen::sheen_albedo_table`] once a variant with sheen was
    /// prepared (a 16-byte placeholder before, likewise).
    pub(crate) sheen_table: Buffer,
    /// The shadow maps' comparison sampler.
    pub(crate) shadow_sampler: Sampler,
    /// The sampler of the image behind transmissive objects (trilinear, clamped).
    pub(crate) behind_sampler: Sampler,
    /// The overlay's font: its text layout.
    pub(crate) overlay_font: OverlayFont,
    /// The font's atlas, read by the overlay's fragment shader.
    pub(crate) overlay_atlas: Buffer,
    /// The overlay image and its size; or a one-texel placeholder, bound when no image is
    /// shown.
    pub(crate) overlay_image: (Buffer, Option<[u32; 2]>),
    /// An empty top-level acceleration structure and cut-out tables, bound where a set's
    /// ray queries trace nothing this frame (devices with ray queries only).
    pub(crate) no_scene: Option<(crate::accel::TopLevel, crate::accel::TracedCutouts)>,
    /// The auto exposure's histogram of log2 luminance (zeros between frames: the
    /// adaptation pass clears what the metering pass counted).
    pub(crate) exposure_histogram: Buffer,
    /// The auto exposure's state ([`crate::MeteredExposure`]'s bytes): the exposure the
    /// output pass applies, the EV100 the next frame adapts from.
    pub(crate) exposure_state: Buffer,
    /// Bloom's partial sums, scale and totals (`passes::bloom`; written and read within
    /// a frame).
    pub(crate) bloom_sums: Buffer,
    /// A surface table of one empty entry, bound where a set could path-trace but its
    /// frame does not (devices with ray queries only).
    pub(crate) no_surfaces: Option<crate::accel::TracedSurfaces>,
}

impl SharedResources {
    /// Everything at its start: placeholders for the tables no variant needs yet (the
    /// energy table made at once when `settings` turn compensation on).
    pub(crate) fn new(
        device: &Arc<Device>,
        settings: &RendererSettings,
    ) -> Result<Self, RenderError> {
        let overlay_font = OverlayFont::new()?;
        let overlay_atlas = buffers::filled_storage_buffer(
            device,
            "overlay font atlas",
            bytemuck::cast_slice(&overlay::atlas_words(&overlay_font)),
        )?;
        Ok(Self {
            no_environment: GpuEnvironment::placeholder(device)?,
            absent_target: placeholders::absent_target_placeholder(
                device,
                settings.hdr_format.vk(),
            )?,
            energy_table: energy_table(device, settings.shading.energy_compensation)?,
            sheen_table: sheen_table(device, false)?,
            shadow_sampler: shadows::shadow_sampler(device)?,
            behind_sampler: behind_sampler(device)?,
            overlay_font,
            overlay_atlas,
            overlay_image: (overlay_image_buffer(device, &[[0; 4]])?, None),
            exposure_histogram: buffers::filled_storage_buffer(
                device,
                "auto exposure histogram",
                &[0; 4 * crate::exposure::HISTOGRAM_BINS],
            )?,
            bloom_sums: buffers::storage_buffer(
                device,
                "bloom sums",
                4 * 8 * (256 + 1),
                buffers::GPU_ONLY,
            )?,
            exposure_state: Buffer::new(
                device,
                "auto exposure state",
                crate::exposure::MeteredExposure::BYTES,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
                buffers::GPU_ONLY,
            )?,
            no_scene: if device.ray_queries() {
                Some((
                    crate::accel::TopLevel::empty(device)?,
                    crate::accel::TracedCutouts::none(device)?,
                ))
            } else {
                None
            },
            no_surfaces: if device.ray_queries() {
                Some(crate::accel::TracedSurfaces::none(device)?)
            } else {
                None
            },
        })
    }

    /// Makes the energy compensation's table if it is still the placeholder; the
    /// placeholder replaced, to retire once the frames that bound it have completed.
    pub(crate) fn make_energy_table(
        &mut self,
        device: &Arc<Device>,
    ) -> Result<Option<Buffer>, RenderError> {
        if self.energy_table.size() > 16 {
            return Ok(None);
        }
        let table = energy_table(device, true)?;
        Ok(Some(std::mem::replace(&mut self.energy_table, table)))
    }

    /// Makes the sheen's albedo table (integrated in f64 once per process, ≈ 0.5 s) if it
    /// is still the placeholder; the placeholder replaced, to retire.
    pub(crate) fn make_sheen_table(
        &mut self,
        device: &Arc<Device>,
    ) -> Result<Option<Buffer>, RenderError> {
        if self.sheen_table.size() > 16 {
            return Ok(None);
        }
        let table = sheen_table(device, true)?;
        Ok(Some(std::mem::replace(&mut self.sheen_table, table)))
    }

    /// Shows `rgba` (`size` texels) as the overlay image, or none; the buffer replaced,
    /// to retire.
    pub(crate) fn replace_overlay_image(
        &mut self,
        device: &Arc<Device>,
        image: Option<(&[[u8; 4]], [u32; 2])>,
    ) -> Result<Buffer, RenderError> {
        let next = match image {
            Some((rgba, size)) => (overlay_image_buffer(device, rgba)?, Some(size)),
            None => (overlay_image_buffer(device, &[[0; 4]])?, None),
        };
        Ok(std::mem::replace(&mut self.overlay_image, next).0)
    }
}

/// The table energy compensation reads ([`environment::white_specular_albedo_table`])
/// when `on`, else a 16-byte placeholder (the binding exists in every lighting layout).
fn energy_table(device: &Arc<Device>, on: bool) -> Result<Buffer, RenderError> {
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
/// `sheen_scaling_table`, as f32) when `on`, else a 16-byte placeholder (the binding
/// exists in every lighting layout).
fn sheen_table(device: &Arc<Device>, on: bool) -> Result<Buffer, RenderError> {
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
fn overlay_image_buffer(device: &Arc<Device>, rgba: &[[u8; 4]]) -> Result<Buffer, RenderError> {
    Ok(buffers::filled_storage_buffer(
        device,
        "overlay image",
        bytemuck::cast_slice(rgba),
    )?)
}

/// The sampler the forward pass reads the image behind transmissive objects with:
/// trilinear (a rough surface's lookup reads a coarser level), clamped at the edges.
fn behind_sampler(device: &Arc<Device>) -> Result<Sampler, RenderError> {
    Ok(Sampler::new(
        device,
        &vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .min_lod(0.0)
            .max_lod(vk::LOD_CLAMP_NONE),
    )?)
}
