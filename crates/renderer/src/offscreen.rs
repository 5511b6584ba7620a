//! Combustion's own frames: rendered into the renderer's display image with its own
//! frame ring, either submitted and waited for with readback ([`Renderer::render`], for
//! the command line and the tests) or pipelined with frames in flight
//! ([`Renderer::submit_offscreen`], for benchmarks and soak runs). Both go through
//! [`Renderer::record`], exactly as a host's frames do.

use std::sync::Arc;

use combustion_vk::{
    gpu_allocator::MemoryLocation, vk, Buffer, Device, FrameRing, Image, ImageState, VkError,
};

use crate::color::f16_to_f32;
use crate::error::RenderError;
use crate::gbuffer::{GBufferReadback, GBufferTargets, GBufferTexel};
use crate::graph::{BufferUse, ImageStates, ImageUse, PassUses, TrackedImage};
use crate::options::{
    BaseColorStorage, GBufferStorage, HdrFormat, Readback, RendererSettings, SurfaceStorage,
};
use crate::results::{Frame, PassTimings};
#[cfg(doc)]
use crate::Renderer;

/// Display image sizes kept (the least recently used beyond this is retired).
pub(crate) const DISPLAY_SIZES_KEPT: usize = 4;

/// The renderer's own submissions.
pub(crate) struct Offscreen {
    pub(crate) ring: FrameRing,
    /// Display images (sRGB-encoded RGBA8) by size and the state each was left in, the
    /// one in use last; a few sizes are kept so that alternating sizes rebuild nothing.
    pub(crate) displays: Vec<(Image, ImageState)>,
    pub(crate) readback: Option<ReadbackBuffers>,
}

/// Host-visible copies of one frame's images.
pub(crate) struct ReadbackBuffers {
    pub(crate) extent: vk::Extent2D,
    hdr: Buffer,
    ldr: Buffer,
    /// The three colour targets every variant has, and depth.
    gbuffer: [Buffer; 4],
    /// The clear coat's target (in frames whose variant has it), made with the first
    /// G-buffer readback asked for (`with_gbuffer_layers`): frames read back only as
    /// images do not carry it.
    pub(crate) clearcoat: Option<Buffer>,
    /// The sheen's target, likewise.
    sheen: Option<Buffer>,
    /// The thin film's target, likewise.
    film: Option<Buffer>,
    /// The specular target, likewise.
    specular: Option<Buffer>,
    /// The emissive + occlusion target (in the HDR image's format), likewise.
    emissive: Option<Buffer>,
}

impl ReadbackBuffers {
    pub(crate) fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        hdr_format: HdrFormat,
        storage: GBufferStorage,
        with_gbuffer_layers: bool,
    ) -> Result<Self, VkError> {
        let pixels = u64::from(extent.width) * u64::from(extent.height);
        let buffer = |name: &str, bytes_per_pixel: u64| {
            Buffer::new(
                device,
                name,
                pixels * bytes_per_pixel,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
        };
        Ok(Self {
            extent,
            hdr: buffer("hdr readback", hdr_format.bytes_per_pixel())?,
            ldr: buffer("display readback", 4)?,
            gbuffer: [
                buffer(
                    "gbuffer readback 0",
                    storage.base_color.bytes_per_pixel().into(),
                )?,
                buffer(
                    "gbuffer readback 1",
                    storage.surface.bytes_per_pixel().into(),
                )?,
                buffer("gbuffer readback 2", 4)?,
                buffer("depth readback", 4)?,
            ],
            clearcoat: if with_gbuffer_layers {
                Some(buffer("clear coat readback", 8)?)
            } else {
                None
            },
            sheen: if with_gbuffer_layers {
                Some(buffer("sheen readback", 8)?)
            } else {
                None
            },
            film: if with_gbuffer_layers {
                Some(buffer("thin film readback", 8)?)
            } else {
                None
            },
            specular: if with_gbuffer_layers {
                Some(buffer("specular readback", 8)?)
            } else {
                None
            },
            emissive: if with_gbuffer_layers {
                Some(buffer(
                    "emissive + occlusion readback",
                    hdr_format.bytes_per_pixel(),
                )?)
            } else {
                None
            },
        })
    }
}

impl ReadbackBuffers {
    pub(crate) fn all(&self) -> impl Iterator<Item = &Buffer> {
        [&self.hdr, &self.ldr]
            .into_iter()
            .chain(&self.gbuffer)
            .chain(&self.clearcoat)
            .chain(&self.sheen)
            .chain(&self.film)
            .chain(&self.specular)
            .chain(&self.emissive)
    }
}

impl Offscreen {
    /// Forgets the states the display images were left in by frames that never ran:
    /// each is overwritten whole by its next frame, from `UNDEFINED`.
    pub(crate) fn forget_display_states(&mut self) {
        for (_, state) in &mut self.displays {
            *state = ImageState::UNDEFINED;
        }
    }

    pub(crate) fn new(device: &Arc<Device>, frames_in_flight: usize) -> Result<Self, VkError> {
        Ok(Self {
            ring: FrameRing::new(device, frames_in_flight)?,
            displays: Vec::new(),
            readback: None,
        })
    }
}

/// The largest factor of [`Renderer::render_supersampled`]: 4×4 samples a pixel.
pub const MAX_SUPERSAMPLE: u32 = 4;

impl Offscreen {
    /// Records the copies `readback` asks for into host-visible buffers.
    pub(crate) fn record_copies(
        device: &Device,
        states: &mut ImageStates,
        cmd: vk::CommandBuffer,
        display: &Image,
        buffers: &ReadbackBuffers,
        (hdr, g): (&Image, &GBufferTargets<'_>),
        readback: Readback,
    ) {
        let mut copies: Vec<(&Image, &Buffer)> = Vec::new();
        if readback.images {
            copies.push((hdr, &buffers.hdr));
            copies.push((display, &buffers.ldr));
        }
        if readback.gbuffer {
            for (image, buffer) in g.colors().into_iter().zip(&buffers.gbuffer) {
                copies.push((image, buffer));
            }
            copies.push((g.depth, &buffers.gbuffer[3]));
            if let (Some(image), Some(buffer)) = (g.clearcoat, &buffers.clearcoat) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (g.sheen, &buffers.sheen) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (g.film, &buffers.film) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (g.specular, &buffers.specular) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (g.emissive, &buffers.emissive) {
                copies.push((image, buffer));
            }
        }
        if copies.is_empty() {
            return;
        }
        // The display image was left in TRANSFER_SRC by the frame; the renderer's own
        // images are moved there by their declared use.
        let uses = PassUses::images(
            "readback",
            copies
                .iter()
                .filter(|(image, _)| image.raw() != display.raw())
                .map(|(image, _)| (TrackedImage::from(*image), ImageUse::TransferSource))
                .collect(),
        )
        .with_buffers(
            copies
                .iter()
                .map(|(_, buffer)| (buffer.raw(), BufferUse::TransferDestination))
                .collect(),
        );
        let raw = device.raw();
        states.transition(raw, cmd, &uses);
        for (image, buffer) in &copies {
            image.record_copy_to_buffer(cmd, buffer);
        }
        let host_read = PassUses::images("host read", Vec::new()).with_buffers(
            copies
                .iter()
                .map(|(_, buffer)| (buffer.raw(), BufferUse::HostRead))
                .collect(),
        );
        states.transition(raw, cmd, &host_read);
    }

    /// The frame just completed, from the readback buffers (`clearcoat`, `sheen`, `film`,
    /// `specular`, `emissive`: its variant has the coat's, the sheen's, the thin film's,
    /// the specular, the emissive + occlusion target).
    pub(crate) fn read_back(
        &self,
        settings: &RendererSettings,
        timings: PassTimings,
        (width, height): (u32, u32),
        readback: Readback,
        [clearcoat, sheen, film, specular, emissive]: [bool; 5],
    ) -> Result<Frame, RenderError> {
        let mut frame = Frame {
            width,
            height,
            timings,
            ..Frame::default()
        };
        let Some(buffers) = self.readback.as_ref() else {
            return Ok(frame);
        };
        if readback.images {
            frame.hdr = hdr_texels(settings.hdr_format, buffers.hdr.mapped()?);
            frame.ldr = bytemuck::pod_collect_to_vec(buffers.ldr.mapped()?);
        }
        if readback.gbuffer {
            let [b0, b1, b2, b3] = &buffers.gbuffer;
            let storage = settings.gbuffer;
            let base = match storage.base_color {
                BaseColorStorage::Srgb8 => unorm_texels::<u8>(b0.mapped()?),
                BaseColorStorage::Srgb16 => unorm_texels::<u16>(b0.mapped()?),
                BaseColorStorage::LinearHalf => {
                    bytemuck::pod_collect_to_vec::<u8, [u16; 4]>(b0.mapped()?)
                        .into_iter()
                        .map(|p| p.map(|h| f64::from(f16_to_f32(h))))
                        .collect()
                }
            };
            let nra = match storage.surface {
                SurfaceStorage::Unorm16 => unorm_texels::<u16>(b1.mapped()?),
                SurfaceStorage::Unorm8 => unorm_texels::<u8>(b1.mapped()?),
            };
            let md: Vec<[u16; 2]> = bytemuck::pod_collect_to_vec(b2.mapped()?);
            let depth: Vec<f32> = bytemuck::pod_collect_to_vec(b3.mapped()?);
            // Only frames whose variant has the coat's target wrote it.
            let clearcoat = match &buffers.clearcoat {
                Some(buffer) if clearcoat => Some(unorm_texels::<u16>(buffer.mapped()?)),
                _ => None,
            };
            let sheen = match &buffers.sheen {
                Some(buffer) if sheen => Some(unorm_texels::<u16>(buffer.mapped()?)),
                _ => None,
            };
            let film = match &buffers.film {
                Some(buffer) if film => Some(bytemuck::pod_collect_to_vec::<u8, [f32; 2]>(
                    buffer.mapped()?,
                )),
                _ => None,
            };
            let specular = match &buffers.specular {
                Some(buffer) if specular => Some(
                    bytemuck::pod_collect_to_vec::<u8, [u16; 4]>(buffer.mapped()?)
                        .into_iter()
                        .map(|p| p.map(|h| f64::from(f16_to_f32(h))))
                        .collect::<Vec<_>>(),
                ),
                _ => None,
            };
            let emissive = match &buffers.emissive {
                Some(buffer) if emissive => Some(hdr_texels(settings.hdr_format, buffer.mapped()?)),
                _ => None,
            };
            let texels = (0..base.len())
                .map(|i| GBufferTexel {
                    base_color_metalness: base[i],
                    base_color_storage: storage.base_color,
                    normal_roughness_anisotropy: nra[i],
                    material_direction: md[i],
                    depth: depth[i],
                    clearcoat: clearcoat.as_ref().map_or([0.0; 4], |c| c[i]),
                    sheen: sheen.as_ref().map_or([0.0; 4], |s| s[i]),
                    film: film.as_ref().map_or([0.0; 2], |f| f[i].map(f64::from)),
                    specular: specular.as_ref().map_or([1.0; 4], |s| s[i]),
                    emissive_occlusion: emissive
                        .as_ref()
                        .map_or([0.0, 0.0, 0.0, 1.0], |e| e[i].map(f64::from)),
                })
                .collect();
            frame.gbuffer = Some(GBufferReadback {
                storage,
                width,
                height,
                texels,
            });
        }
        Ok(frame)
    }
}

/// An unsigned normalised code's type.
trait UnormCode: bytemuck::Pod + Into<f64> {
    /// 2ⁿ − 1.
    const MAX: f64;
}
impl UnormCode for u8 {
    const MAX: f64 = 255.0;
}
impl UnormCode for u16 {
    const MAX: f64 = 65535.0;
}

/// Four-channel unorm texels as the shaders read them: code / (2ⁿ − 1), in f64.
fn unorm_texels<T: UnormCode>(bytes: &[u8]) -> Vec<[f64; 4]> {
    bytemuck::pod_collect_to_vec::<u8, [T; 4]>(bytes)
        .into_iter()
        .map(|p| p.map(|c| c.into() / T::MAX))
        .collect()
}

/// RGBA texels of an image in the HDR image's format (f32, or f16 widened), as read back.
fn hdr_texels(format: HdrFormat, bytes: &[u8]) -> Vec<[f32; 4]> {
    match format {
        HdrFormat::Rgba32Float => bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(bytes),
        HdrFormat::Rgba16Float => bytemuck::pod_collect_to_vec::<u8, [u16; 4]>(bytes)
            .into_iter()
            .map(|p| p.map(f16_to_f32))
            .collect(),
    }
}
