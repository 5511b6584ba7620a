//! The pipelines a renderer builds, never while a frame is recorded: per shader variant
//! (G-buffer and lighting), per target format (output pass and overlay), and the
//! descriptor-set layouts they share.

use std::sync::atomic::Ordering;
use std::sync::Arc;

use combustion_vk::{vk, DescriptorSetLayout, Device};

use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::gbuffer::GBufferPass;
use crate::gpu_types::{LightingPush, TonemapPush};
use crate::host::OutputEncoding;
use crate::scene_upload::GpuScene;
use crate::variant::ShaderVariant;
use crate::{bindings, overlay, Renderer};
#[cfg(doc)]
use crate::{FrameEnvironment, DISPLAY_FORMAT};

/// The G-buffer and lighting pipelines of one [`ShaderVariant`]. Variants that differ
/// only in what the lighting pass reads share one G-buffer pipeline.
pub(crate) struct VariantPasses {
    pub(crate) gbuffer: Arc<GBufferPass>,
    pub(crate) lighting: FullscreenPass,
    /// The blended objects' forward pass, in variants of scenes that have one (and that
    /// show radiance: not debug views or measurement floors).
    pub(crate) forward: Option<crate::forward::ForwardPass>,
    /// The transmissive volumes' back faces pass (the renderer's one), in variants with a
    /// forward pass and a transmissive object with a volume.
    pub(crate) back_faces: Option<Arc<crate::back_faces::BackFacesPass>>,
}

/// The descriptor-set layout of every declared set ([`bindings::ALL`]), shared by every
/// variant's pipelines and every frame slot.
pub(crate) struct SetLayouts {
    by_name: Vec<(&'static str, DescriptorSetLayout)>,
}

/// The passes that write a target of one format: the output pass and the overlay
/// drawn over it.
pub(crate) struct OutputPasses {
    pub(crate) output: FullscreenPass,
    /// The output pass with FXAA (`FXAA`), for display formats once a frame is to use
    /// it ([`Renderer::prepare_anti_aliasing`]).
    pub(crate) fxaa: Option<FullscreenPass>,
    pub(crate) overlay: overlay::OverlayPass,
}

impl SetLayouts {
    pub(crate) fn new(device: &Arc<Device>) -> Result<Self, RenderError> {
        let by_name = bindings::ALL
            .iter()
            .map(|decl| Ok((decl.name, decl.layout(device)?)))
            .collect::<Result<_, RenderError>>()?;
        Ok(Self { by_name })
    }

    /// The layout of `decl` (one of [`bindings::ALL`]).
    pub(crate) fn of(&self, decl: &bindings::SetDecl) -> &DescriptorSetLayout {
        self.by_name
            .iter()
            .find(|(name, _)| *name == decl.name)
            .map(|(_, layout)| layout)
            .unwrap_or_else(|| panic!("set {} is not in bindings::ALL", decl.name))
    }
}

impl Renderer {
    /// Builds the pipelines of `variant` if they are not built yet.
    pub(crate) fn prepare_variant(&mut self, variant: ShaderVariant) -> Result<(), RenderError> {
        if self.variants.contains_key(&variant) {
            return Ok(());
        }
        if variant.sheen && self.sheen_table.size() <= 16 {
            // The sheen's albedo table, integrated in f64 once per process (≈ 0.5 s),
            // for the first variant with sheen.
            let table = crate::settings::sheen_table(&self.device, true)?;
            let placeholder = std::mem::replace(&mut self.sheen_table, table);
            self.retire(placeholder);
        }
        if variant.shadows.is_some() && self.shadow_casters.is_none() {
            self.shadow_casters = Some(crate::shadows::ShadowCasterPass::new(
                &self.device,
                &self.compiler,
                &self.pipeline_cache,
                [
                    self.layouts.of(&bindings::SHADOW_CASTERS),
                    self.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
            )?);
            self.stats.pipelines_built += 1;
        }
        if let Some(casters) = self
            .shadow_casters
            .as_mut()
            .filter(|c| variant.shadows.is_some() && variant.alpha_mask && !c.has_masked())
        {
            casters.add_masked(&self.device, &self.compiler, &self.pipeline_cache)?;
            self.stats.pipelines_built += 1;
        }
        let gbuffer_key = variant.gbuffer_part();
        let gbuffer = match self.gbuffer_passes.get(&gbuffer_key) {
            Some(pass) => pass.clone(),
            None => {
                let pass = Arc::new(GBufferPass::new(
                    &self.device,
                    &self.compiler,
                    &self.pipeline_cache,
                    [
                        self.layouts.of(&bindings::GBUFFER),
                        self.layouts.of(&bindings::MATERIAL_TEXTURES),
                    ],
                    gbuffer_key,
                    self.settings.gbuffer,
                    self.settings.hdr_format.vk(),
                )?);
                self.stats.pipelines_built += 1 + pass.stroke_pipelines();
                self.gbuffer_passes.insert(gbuffer_key, pass.clone());
                pass
            }
        };
        let mut defines = variant.defines();
        defines.extend(self.settings.gbuffer.defines());
        let lighting = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            "lighting.frag",
            &defines,
            self.layouts.of(&bindings::LIGHTING),
            std::mem::size_of::<LightingPush>() as u32,
            self.settings.hdr_format.vk(),
        )?;
        self.stats.pipelines_built += 1;
        let forward = if (variant.blend || variant.transmission)
            && !variant.debug_views
            && variant.floor.is_none()
        {
            self.stats.pipelines_built += 1;
            Some(crate::forward::ForwardPass::new(
                &self.device,
                &self.compiler,
                &self.pipeline_cache,
                [
                    self.layouts.of(&bindings::FORWARD),
                    self.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
                variant,
                self.settings.hdr_format.vk(),
            )?)
        } else {
            None
        };
        let back_faces = if variant.volume && forward.is_some() {
            Some(match &self.back_faces_pass {
                Some(pass) => pass.clone(),
                None => {
                    let pass = Arc::new(crate::back_faces::BackFacesPass::new(
                        &self.device,
                        &self.compiler,
                        &self.pipeline_cache,
                        self.layouts.of(&bindings::BACK_FACES),
                    )?);
                    self.stats.pipelines_built += 1;
                    self.back_faces_pass = Some(pass.clone());
                    pass
                }
            })
        } else {
            None
        };
        self.variants.insert(
            variant,
            VariantPasses {
                gbuffer,
                lighting,
                forward,
                back_faces,
            },
        );
        Ok(())
    }

    /// Builds the output pass (and the overlay over it) for targets of `format`, so that [`Renderer::record`] can
    /// render into them. [`DISPLAY_FORMAT`] is prepared by [`Renderer::new`]. Formats:
    /// see [`OutputEncoding::of`].
    pub fn prepare_output(&mut self, format: vk::Format) -> Result<(), RenderError> {
        if self.outputs.contains_key(&format) {
            return Ok(());
        }
        let encoding =
            OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
        let output = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            "tonemap.frag",
            &encoding.defines(),
            self.layouts.of(&bindings::OUTPUT),
            std::mem::size_of::<TonemapPush>() as u32,
            format,
        )?;
        let overlay = overlay::OverlayPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            self.layouts.of(&bindings::OVERLAY),
            &encoding.defines(),
            format,
        )?;
        self.outputs.insert(
            format,
            OutputPasses {
                output,
                fxaa: None,
                overlay,
            },
        );
        self.stats.pipelines_built += 2;
        Ok(())
    }

    /// Prepares `format` ([`Renderer::prepare_output`]) and what frames of
    /// `anti_aliasing` need there: for [`AntiAliasing::Fxaa`] into a display format, the
    /// output pipeline with FXAA (linear formats get no anti-aliasing). Call it before
    /// recording such frames (their recording never compiles a shader); the offscreen
    /// paths ([`Renderer::render_with`], [`Renderer::submit_offscreen_with`]) call it.
    ///
    /// # Errors
    /// As [`Renderer::prepare_output`]; [`RenderError::Vulkan`] if the shader does not
    /// compile or the pipeline cannot be built.
    ///
    /// [`AntiAliasing::Fxaa`]: crate::AntiAliasing::Fxaa
    pub fn prepare_anti_aliasing(
        &mut self,
        format: vk::Format,
        anti_aliasing: crate::AntiAliasing,
    ) -> Result<(), RenderError> {
        self.prepare_output(format)?;
        let encoding =
            OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
        if anti_aliasing != crate::AntiAliasing::Fxaa
            || encoding == OutputEncoding::Linear
            || self.outputs[&format].fxaa.is_some()
        {
            return Ok(());
        }
        let mut defines = encoding.defines();
        defines.push(("FXAA", None));
        let fxaa = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.pipeline_cache,
            "tonemap.frag",
            &defines,
            self.layouts.of(&bindings::OUTPUT),
            std::mem::size_of::<TonemapPush>() as u32,
            format,
        )?;
        self.outputs.get_mut(&format).expect("prepared above").fxaa = Some(fxaa);
        self.stats.pipelines_built += 1;
        Ok(())
    }

    /// Builds the pipelines `scene` needs with the current shading options, if they are
    /// not built yet: for a scene left out of [`Renderer::set_shading`]'s list (uploads
    /// and edits build their own). Frames lit by a [`FrameEnvironment`] baked for the
    /// scene get theirs too.
    pub fn prepare(&mut self, scene: &GpuScene) -> Result<(), RenderError> {
        self.prepare_variant(self.variant_of(scene.variant))?;
        if scene.frame_environments.load(Ordering::Relaxed) {
            self.prepare_variant(self.variant_of(scene.lit_variant))?;
        }
        Ok(())
    }
}
