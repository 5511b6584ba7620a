//! Combustion's own frames: rendered into the renderer's display image with its own
//! frame ring, either submitted and waited for with readback ([`Renderer::render`], for
//! the command line and the tests) or pipelined with frames in flight
//! ([`Renderer::submit_offscreen`], for benchmarks and soak runs). Both go through
//! [`Renderer::record`], exactly as a host's frames do.

use std::sync::Arc;

use combustion_vk::{
    gpu_allocator::MemoryLocation, vk, Buffer, Device, FrameRing, Image, ImageDesc, ImageState,
    RingFrame, VkError,
};

use crate::color::f16_to_f32;
use crate::error::RenderError;
use crate::frame::display_after;
use crate::gbuffer::{GBufferReadback, GBufferTexel};
use crate::graph::{BufferUse, ImageUse, PassUses, TrackedImage};
use crate::host::{ColorTarget, FrameInputs, FrameTarget, DISPLAY_FORMAT};
use crate::options::{BaseColorStorage, GBufferStorage, HdrFormat, Readback, SurfaceStorage};
use crate::results::Frame;
use crate::scene_upload::GpuScene;
use crate::targets::TargetKey;
use crate::Renderer;

/// Display image sizes kept (the least recently used beyond this is retired).
const DISPLAY_SIZES_KEPT: usize = 4;

/// The renderer's own submissions.
pub(crate) struct Offscreen {
    ring: FrameRing,
    /// Display images (sRGB-encoded RGBA8) by size and the state each was left in, the
    /// one in use last; a few sizes are kept so that alternating sizes rebuild nothing.
    displays: Vec<(Image, ImageState)>,
    readback: Option<ReadbackBuffers>,
}

/// Host-visible copies of one frame's images.
struct ReadbackBuffers {
    extent: vk::Extent2D,
    hdr: Buffer,
    ldr: Buffer,
    /// The three colour targets every variant has, and depth.
    gbuffer: [Buffer; 4],
    /// The clear coat's target (in frames whose variant has it), made with the first
    /// G-buffer readback asked for (`with_gbuffer_layers`): frames read back only as
    /// images do not carry it.
    clearcoat: Option<Buffer>,
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
    fn new(
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
    fn all(&self) -> impl Iterator<Item = &Buffer> {
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
    fn new(device: &Arc<Device>, frames_in_flight: usize) -> Result<Self, VkError> {
        Ok(Self {
            ring: FrameRing::new(device, frames_in_flight)?,
            displays: Vec::new(),
            readback: None,
        })
    }
}

/// The largest factor of [`Renderer::render_supersampled`]: 4×4 samples a pixel.
pub const MAX_SUPERSAMPLE: u32 = 4;

impl Renderer {
    /// A still frame of `scene` at `width`×`height` with `factor`×`factor` samples a
    /// pixel (1 to [`MAX_SUPERSAMPLE`]): rendered at `factor` times the size (the same
    /// camera, so the samples lie on a regular grid inside each pixel), its radiance
    /// averaged per pixel in f64 (a box filter: the mean radiance over the pixel's area)
    /// and then exposed and tone-mapped as the output pass does
    /// ([`crate::ToneMapping::display_codes`]). The frame's own anti-aliasing is not
    /// applied. Images only; the timings are the large frame's.
    ///
    /// # Errors
    /// [`RenderError::InvalidSupersample`] for a factor outside its range;
    /// [`RenderError::InvalidSize`] when the large frame exceeds the device's image
    /// size; as [`Renderer::render_with`] otherwise.
    pub fn render_supersampled(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        factor: u32,
    ) -> Result<Frame, RenderError> {
        if !(1..=MAX_SUPERSAMPLE).contains(&factor) {
            return Err(RenderError::InvalidSupersample(factor));
        }
        let plain = FrameInputs {
            anti_aliasing: crate::AntiAliasing::None,
            ..*inputs
        };
        let large = self.render_with(
            scene,
            &plain,
            width.saturating_mul(factor),
            height.saturating_mul(factor),
            Readback {
                images: true,
                gbuffer: false,
            },
        )?;
        let (w, h, f) = (width as usize, height as usize, factor as usize);
        let samples = (f * f) as f64;
        let mut hdr = Vec::with_capacity(w * h);
        let mut ldr = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0f64; 4];
                for sy in 0..f {
                    let row = (y * f + sy) * w * f;
                    for sx in 0..f {
                        let p = large.hdr[row + x * f + sx];
                        for c in 0..4 {
                            sum[c] += f64::from(p[c]);
                        }
                    }
                }
                let mean = sum.map(|s| s / samples);
                hdr.push(mean.map(|m| m as f32));
                let exposed = [0, 1, 2].map(|c| mean[c] * f64::from(inputs.exposure));
                let [r, g, b] = inputs.tone_mapping.display_codes(exposed);
                ldr.push([r, g, b, 255]);
            }
        }
        Ok(Frame {
            width,
            height,
            hdr,
            ldr,
            gbuffer: None,
            timings: large.timings,
        })
    }

    /// Renders `scene` (its own camera and lights, the settings' exposure) at
    /// `width`×`height`, submits, waits for the GPU and copies back what `readback`
    /// asks for. The convenience path of the command line and the tests; a host records
    /// its frames with [`Renderer::record`] instead.
    pub fn render(
        &mut self,
        scene: &GpuScene,
        width: u32,
        height: u32,
        readback: Readback,
    ) -> Result<Frame, RenderError> {
        let inputs = FrameInputs::of_scene(scene, self.settings.exposure);
        self.render_with(scene, &inputs, width, height, readback)
    }

    /// As [`Renderer::render`], with the frame's camera, exposure, lights and overlay
    /// given (e.g. a viewer's current frame, rendered again to be read back). A host
    /// that records its own frames ([`Renderer::record`]) calls it only once all of
    /// them have completed: both use the renderer's frame slots (docs/integration.md).
    pub fn render_with(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Readback,
    ) -> Result<Frame, RenderError> {
        let frame = self.submit_with_offscreen(scene, inputs, width, height, Some(readback))?;
        let offscreen = self.offscreen.as_ref().expect("created by the submission");
        offscreen.ring.wait(frame.slot)?;
        self.collect_timings(frame.slot)?;
        self.stats.readbacks += 1;
        let variant = self.variant_of(scene.variant);
        self.read_back(
            width,
            height,
            readback,
            [
                variant.clearcoat,
                variant.sheen,
                variant.iridescence,
                variant.specular,
                variant.has_emissive_occlusion_target(),
            ],
        )
    }

    /// Records and submits a frame of `scene` into the renderer's display image without
    /// waiting for it: the frame ring waits only for the frame that used the same slot
    /// (frames in flight). [`Renderer::last_completed_timings`] then gives the GPU times
    /// of the latest completed frame; [`Renderer::finish_offscreen`] waits for all.
    pub fn submit_offscreen(
        &mut self,
        scene: &GpuScene,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        let inputs = FrameInputs::of_scene(scene, self.settings.exposure);
        self.submit_with_offscreen(scene, &inputs, width, height, None)
            .map(|_| ())
    }

    /// As [`Renderer::submit_offscreen`], with the frame's camera, exposure, lights and
    /// overlay given (a camera moving from frame to frame, say).
    pub fn submit_offscreen_with(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        self.submit_with_offscreen(scene, inputs, width, height, None)
            .map(|_| ())
    }

    /// Waits for every frame submitted by [`Renderer::submit_offscreen`] and collects
    /// the timings of those not collected yet, oldest first.
    pub fn finish_offscreen(&mut self) -> Result<(), RenderError> {
        let Some(offscreen) = &self.offscreen else {
            return Ok(());
        };
        offscreen.ring.wait_all()?;
        self.frames_completed()
    }

    fn submit_with_offscreen(
        &mut self,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Option<Readback>,
    ) -> Result<RingFrame, RenderError> {
        self.check_size(width, height)?;
        // The offscreen frames' display image: its anti-aliasing's pipeline is built
        // here, before the frame is recorded (once; later frames find it built).
        self.prepare_anti_aliasing(crate::DISPLAY_FORMAT, inputs.anti_aliasing)?;
        let mut offscreen = match self.offscreen.take() {
            Some(o) => o,
            None => Offscreen::new(&self.device, self.slots.len())?,
        };
        let result = self.submit_frame(&mut offscreen, scene, inputs, width, height, readback);
        self.offscreen = Some(offscreen);
        result
    }

    fn submit_frame(
        &mut self,
        offscreen: &mut Offscreen,
        scene: &GpuScene,
        inputs: &FrameInputs<'_>,
        width: u32,
        height: u32,
        readback: Option<Readback>,
    ) -> Result<RingFrame, RenderError> {
        let extent = vk::Extent2D { width, height };
        match offscreen
            .displays
            .iter()
            .position(|(image, _)| image.extent() == extent)
        {
            Some(i) => {
                let found = offscreen.displays.remove(i);
                offscreen.displays.push(found);
            }
            None => {
                let display = Image::new(
                    &self.device,
                    &ImageDesc::new(
                        "display (sRGB-encoded)",
                        DISPLAY_FORMAT,
                        width,
                        height,
                        vk::ImageUsageFlags::COLOR_ATTACHMENT
                            | vk::ImageUsageFlags::SAMPLED
                            | vk::ImageUsageFlags::TRANSFER_SRC,
                    ),
                )?;
                self.stats.display_images_built += 1;
                offscreen.displays.push((display, ImageState::UNDEFINED));
                if offscreen.displays.len() > DISPLAY_SIZES_KEPT {
                    let (old, _) = offscreen.displays.remove(0);
                    self.retire(old);
                }
            }
        }
        let wants_copies = readback.is_some_and(|r| r.images || r.gbuffer);
        let wants_gbuffer = readback.is_some_and(|r| r.gbuffer);
        if wants_copies
            && offscreen
                .readback
                .as_ref()
                .is_none_or(|r| r.extent != extent || (wants_gbuffer && r.clearcoat.is_none()))
        {
            let buffers = ReadbackBuffers::new(
                &self.device,
                extent,
                self.settings.hdr_format,
                self.settings.gbuffer,
                wants_gbuffer,
            )?;
            if let Some(old) = offscreen.readback.replace(buffers) {
                for buffer in old.all() {
                    self.states.forget_buffer(buffer.raw());
                }
                self.retire(old);
            }
        }
        let (display, display_state) = offscreen.displays.last_mut().expect("made above");
        let after = display_after(readback.is_some_and(|r| r.images));
        let target = FrameTarget {
            color: ColorTarget {
                image: display.raw(),
                view: display.view(),
                format: DISPLAY_FORMAT,
                extent,
                usage: display.usage(),
                before: *display_state,
                after,
            },
            depth: None,
        };
        // Checked before the ring advances: a refused frame takes no slot.
        let variant = self.check_frame(offscreen.ring.next_slot(), scene, inputs, &target)?;
        let frame = offscreen.ring.begin()?;
        self.record_checked(frame.cmd, frame.slot, scene, inputs, &target, variant)?;
        *display_state = after;
        if let (Some(readback), Some(buffers)) = (readback, &offscreen.readback) {
            self.record_copies(frame.cmd, display, buffers, extent, readback, scene);
        }
        if let Err(e) = offscreen.ring.submit(frame) {
            // The frame will never run: its slot is not waiting for it.
            self.slots[frame.slot].stamped.clear();
            return Err(e.into());
        }
        Ok(frame)
    }

    /// Records the copies `readback` asks for into host-visible buffers.
    fn record_copies(
        &mut self,
        cmd: vk::CommandBuffer,
        display: &Image,
        buffers: &ReadbackBuffers,
        extent: vk::Extent2D,
        readback: Readback,
        scene: &GpuScene,
    ) {
        let key = TargetKey::of(extent, self.variant_of(scene.variant));
        let targets = &self.targets.get(&key).expect("recorded this frame").0;
        let mut copies: Vec<(&Image, &Buffer)> = Vec::new();
        if readback.images {
            copies.push((&targets.hdr, &buffers.hdr));
            copies.push((display, &buffers.ldr));
        }
        if readback.gbuffer {
            let g = &targets.gbuffer;
            for (image, buffer) in g.colors().into_iter().zip(&buffers.gbuffer) {
                copies.push((image, buffer));
            }
            copies.push((&g.depth, &buffers.gbuffer[3]));
            if let (Some(image), Some(buffer)) = (&g.clearcoat, &buffers.clearcoat) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (&g.sheen, &buffers.sheen) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (&g.film, &buffers.film) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (&g.specular, &buffers.specular) {
                copies.push((image, buffer));
            }
            if let (Some(image), Some(buffer)) = (&g.emissive, &buffers.emissive) {
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
        let raw = self.device.raw();
        let states = &mut self.states;
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
    fn read_back(
        &self,
        width: u32,
        height: u32,
        readback: Readback,
        [clearcoat, sheen, film, specular, emissive]: [bool; 5],
    ) -> Result<Frame, RenderError> {
        let mut frame = Frame {
            width,
            height,
            timings: self.last_timings.clone().unwrap_or_default(),
            ..Frame::default()
        };
        let Some(buffers) = self.offscreen.as_ref().and_then(|o| o.readback.as_ref()) else {
            return Ok(frame);
        };
        if readback.images {
            frame.hdr = hdr_texels(self.settings.hdr_format, buffers.hdr.mapped()?);
            frame.ldr = bytemuck::pod_collect_to_vec(buffers.ldr.mapped()?);
        }
        if readback.gbuffer {
            let [b0, b1, b2, b3] = &buffers.gbuffer;
            let storage = self.settings.gbuffer;
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
                Some(buffer) if emissive => {
                    Some(hdr_texels(self.settings.hdr_format, buffer.mapped()?))
                }
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
