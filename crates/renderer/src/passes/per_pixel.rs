//! What the optional per-pixel compute passes share (ambient occlusion, ray-traced
//! occlusion, ray-traced shadows): one compute shader over the frame's pixels in 8×8
//! groups, built with the G-buffer storage's defines, reading the depth and the normals
//! through its own set and writing one image of its own that a later pass reads.

use combustion_vk::vk;

use super::FrameContext;
use crate::bindings::SetDecl;
use crate::compute::ComputePass;
use crate::error::RenderError;
use crate::graph::ImageUse;
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::pipelines::{PipelineKey, PipelineRegistry};
use crate::targets::ImageRequest;

/// One per-pixel compute pass's fixed parts.
pub(super) struct PerPixel {
    /// The pass's name (its pipeline's key).
    pub name: &'static str,
    /// Its compute shader.
    pub shader: &'static str,
    /// Its set (binding `gbuffer_depth` and `gbuffer_normal_roughness_anisotropy`).
    pub set: &'static SetDecl,
    /// The size of its push constants.
    pub push_size: usize,
    /// The image it writes, by name, and its format.
    pub image: (&'static str, vk::Format),
}

impl PerPixel {
    /// Its pipeline, reading `settings`' G-buffer storage.
    fn key(&self, settings: &RendererSettings) -> PipelineKey {
        PipelineKey {
            defines: settings.gbuffer.defines(),
            ..PipelineKey::named(self.name)
        }
    }

    /// Builds its pipeline, if frames of the variant run it (`wanted`).
    pub fn prepare(
        &self,
        wanted: bool,
        settings: &RendererSettings,
        registry: &mut PipelineRegistry,
    ) -> Result<(), RenderError> {
        if wanted {
            registry.build(self.key(settings), |t| {
                let pass = ComputePass::new(
                    t.device,
                    t.compiler,
                    t.cache,
                    t.layouts.of(self.set),
                    self.shader,
                    &settings.gbuffer.defines(),
                    self.push_size,
                )?;
                Ok((pass, 1))
            })?;
        }
        Ok(())
    }

    /// Its image, if frames of the variant run it (`wanted`).
    pub fn images(&self, wanted: bool) -> Vec<ImageRequest> {
        if !wanted {
            return Vec::new();
        }
        let (name, format) = self.image;
        vec![ImageRequest::new(
            name,
            format,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::SAMPLED,
        )]
    }

    /// Its set with the depth and the normals bound; the pass adds the rest.
    pub fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let g = &frame.gbuffer;
        PassIo::new(self.name)
            .slot_set(frame.slot, self.set)
            .image("gbuffer_depth", g.depth, ImageUse::DepthComputeSampled)
            .image(
                "gbuffer_normal_roughness_anisotropy",
                g.normal_roughness_anisotropy,
                ImageUse::ComputeSampled,
            )
    }

    /// Its image, to bind for writing (frames that run it asked for it).
    pub fn output<'a>(&self, frame: &FrameContext<'a>) -> &'a combustion_vk::Image {
        frame.images.get(self.image.0)
    }

    /// Dispatches it over the frame's pixels with `push`.
    pub fn dispatch(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer, push: &[u8]) {
        let pass: &ComputePass = frame
            .registry
            .get(&self.key(frame.settings))
            .expect("prepared for the frame's variant");
        let extent = frame.extent();
        pass.dispatch(
            frame.device,
            cmd,
            frame.slot.set(self.set),
            push,
            [extent.width.div_ceil(8), extent.height.div_ceil(8), 1],
        );
    }
}
