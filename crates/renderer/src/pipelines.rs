//! The pipelines a renderer builds, never while a frame is recorded, and the registry
//! that keeps them: per shader variant (G-buffer and lighting, forward and back faces),
//! per target format (output pass and overlay), the shadow casters', the deform and
//! light-culling passes' and the environment bake's; the descriptor-set layouts they
//! share, the shader compiler and the pipeline cache.

use std::collections::HashMap;
use std::sync::Arc;

use combustion_vk::{vk, DescriptorSetLayout, Device, PipelineCache, ShaderCompiler};

use crate::error::RenderError;
use crate::fullscreen::FullscreenPass;
use crate::gbuffer::GBufferPass;
use crate::gpu_types::{LightingPush, TonemapPush};
use crate::host::{AntiAliasing, OutputEncoding};
use crate::options::RendererSettings;
use crate::variant::ShaderVariant;
use crate::{bindings, overlay, shader_sources};

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
    /// it (`Renderer::prepare_anti_aliasing`).
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

/// Every pipeline the renderer has built, and what builds them: the frame's passes read
/// theirs here (`passes::FrameContext::pipelines`), the renderer asks for them to be
/// built before a frame needs them.
pub(crate) struct PipelineRegistry {
    device: Arc<Device>,
    pub(crate) compiler: ShaderCompiler,
    pub(crate) cache: PipelineCache,
    pub(crate) layouts: SetLayouts,
    variants: HashMap<ShaderVariant, VariantPasses>,
    /// G-buffer pipelines by [`ShaderVariant::gbuffer_part`].
    gbuffer_passes: HashMap<ShaderVariant, Arc<GBufferPass>>,
    /// The back faces pass (variant-independent: built once, for the first variant with
    /// a glass volume, and shared by every such variant).
    back_faces_pass: Option<Arc<crate::back_faces::BackFacesPass>>,
    /// Output passes (and overlays) by target format.
    outputs: HashMap<vk::Format, OutputPasses>,
    /// The light-culling pass (built with the registry).
    pub(crate) light_cull: crate::light_cull::LightCullPass,
    /// The deform pass's pipeline, built when the first scene with deformed objects is
    /// uploaded.
    pub(crate) deform: Option<crate::deform::DeformPipeline>,
    /// The shadow maps' pipeline, built with the first variant that has shadows.
    pub(crate) shadow_casters: Option<crate::shadows::ShadowCasterPass>,
    /// The environment bake's pipelines, built for the first scene with an environment.
    environment_baker: Option<crate::environment::EnvironmentBaker>,
    /// Pipelines built so far ([`crate::RendererStats::pipelines_built`]).
    pub(crate) built: u64,
}

impl PipelineRegistry {
    /// The compiler (with the shader sources and the SPIR-V cache), the set layouts, a
    /// pipeline cache primed from `cache_data` and the light-culling pass; nothing else
    /// is built yet.
    pub(crate) fn new(device: &Arc<Device>, cache_data: &[u8]) -> Result<Self, RenderError> {
        let compiler = ShaderCompiler::new(shader_sources::sources())?
            .with_spirv_cache(combustion_vk::default_spirv_cache_dir());
        let layouts = SetLayouts::new(device)?;
        let cache = PipelineCache::new(device, cache_data)?;
        let light_cull = crate::light_cull::LightCullPass::new(
            device,
            &compiler,
            &cache,
            layouts.of(&bindings::LIGHT_CULL),
        )?;
        Ok(Self {
            device: device.clone(),
            compiler,
            cache,
            layouts,
            variants: HashMap::new(),
            gbuffer_passes: HashMap::new(),
            back_faces_pass: None,
            outputs: HashMap::new(),
            light_cull,
            deform: None,
            shadow_casters: None,
            environment_baker: None,
            built: 0,
        })
    }

    /// The pipelines of `variant`, if they are built.
    pub(crate) fn variant(&self, variant: &ShaderVariant) -> Option<&VariantPasses> {
        self.variants.get(variant)
    }

    /// The output passes of targets of `format`, if they are built.
    pub(crate) fn output(&self, format: vk::Format) -> Option<&OutputPasses> {
        self.outputs.get(&format)
    }

    /// Builds the pipelines of `variant` (in `settings`' G-buffer storage and HDR
    /// format) if they are not built yet.
    pub(crate) fn prepare_variant(
        &mut self,
        variant: ShaderVariant,
        settings: &RendererSettings,
    ) -> Result<(), RenderError> {
        if self.variants.contains_key(&variant) {
            return Ok(());
        }
        if variant.shadows.is_some() && self.shadow_casters.is_none() {
            self.shadow_casters = Some(crate::shadows::ShadowCasterPass::new(
                &self.device,
                &self.compiler,
                &self.cache,
                [
                    self.layouts.of(&bindings::SHADOW_CASTERS),
                    self.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
            )?);
            self.built += 1;
        }
        if let Some(casters) = self
            .shadow_casters
            .as_mut()
            .filter(|c| variant.shadows.is_some() && variant.alpha_mask && !c.has_masked())
        {
            casters.add_masked(&self.device, &self.compiler, &self.cache)?;
            self.built += 1;
        }
        let gbuffer_key = variant.gbuffer_part();
        let gbuffer = match self.gbuffer_passes.get(&gbuffer_key) {
            Some(pass) => pass.clone(),
            None => {
                let pass = Arc::new(GBufferPass::new(
                    &self.device,
                    &self.compiler,
                    &self.cache,
                    [
                        self.layouts.of(&bindings::GBUFFER),
                        self.layouts.of(&bindings::MATERIAL_TEXTURES),
                    ],
                    gbuffer_key,
                    settings.gbuffer,
                    settings.hdr_format.vk(),
                )?);
                self.built += 1 + pass.stroke_pipelines();
                self.gbuffer_passes.insert(gbuffer_key, pass.clone());
                pass
            }
        };
        let mut defines = variant.defines();
        defines.extend(settings.gbuffer.defines());
        let lighting = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.cache,
            "lighting.frag",
            &defines,
            self.layouts.of(&bindings::LIGHTING),
            std::mem::size_of::<LightingPush>() as u32,
            settings.hdr_format.vk(),
        )?;
        self.built += 1;
        let forward = if (variant.blend || variant.transmission)
            && !variant.debug_views
            && variant.floor.is_none()
        {
            self.built += 1;
            Some(crate::forward::ForwardPass::new(
                &self.device,
                &self.compiler,
                &self.cache,
                [
                    self.layouts.of(&bindings::FORWARD),
                    self.layouts.of(&bindings::MATERIAL_TEXTURES),
                ],
                variant,
                settings.hdr_format.vk(),
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
                        &self.cache,
                        self.layouts.of(&bindings::BACK_FACES),
                    )?);
                    self.built += 1;
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

    /// Builds the output pass (and the overlay over it) for targets of `format`.
    pub(crate) fn prepare_output(&mut self, format: vk::Format) -> Result<(), RenderError> {
        if self.outputs.contains_key(&format) {
            return Ok(());
        }
        let encoding =
            OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
        let output = FullscreenPass::new(
            &self.device,
            &self.compiler,
            &self.cache,
            "tonemap.frag",
            &encoding.defines(),
            self.layouts.of(&bindings::OUTPUT),
            std::mem::size_of::<TonemapPush>() as u32,
            format,
        )?;
        let overlay = overlay::OverlayPass::new(
            &self.device,
            &self.compiler,
            &self.cache,
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
        self.built += 2;
        Ok(())
    }

    /// Prepares `format` and, for [`AntiAliasing::Fxaa`] into a display format, the
    /// output pipeline with FXAA (linear formats get no anti-aliasing).
    pub(crate) fn prepare_anti_aliasing(
        &mut self,
        format: vk::Format,
        anti_aliasing: AntiAliasing,
    ) -> Result<(), RenderError> {
        self.prepare_output(format)?;
        let encoding =
            OutputEncoding::of(format).ok_or(RenderError::UnsupportedOutputFormat(format))?;
        if anti_aliasing != AntiAliasing::Fxaa
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
            &self.cache,
            "tonemap.frag",
            &defines,
            self.layouts.of(&bindings::OUTPUT),
            std::mem::size_of::<TonemapPush>() as u32,
            format,
        )?;
        self.outputs.get_mut(&format).expect("prepared above").fxaa = Some(fxaa);
        self.built += 1;
        Ok(())
    }

    /// Builds the deform pass's pipeline if it is not built yet.
    pub(crate) fn prepare_deform(&mut self) -> Result<(), RenderError> {
        if self.deform.is_none() {
            self.deform = Some(crate::deform::DeformPipeline::new(
                &self.device,
                &self.compiler,
                &self.cache,
                self.layouts.of(&bindings::DEFORM),
            )?);
            self.built += 1;
        }
        Ok(())
    }

    /// The environment bake's pipelines, built on first use.
    pub(crate) fn environment_baker(
        &mut self,
    ) -> Result<&crate::environment::EnvironmentBaker, RenderError> {
        if self.environment_baker.is_none() {
            self.environment_baker = Some(crate::environment::EnvironmentBaker::new(
                &self.device,
                &self.compiler,
                &self.cache,
                crate::environment::default_environment_cache_dir(),
            )?);
        }
        Ok(self.environment_baker.as_ref().expect("built above"))
    }
}
