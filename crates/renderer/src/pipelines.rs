//! The registry that builds and keeps every pipeline, never while a frame is recorded:
//! each pass builds its own (`passes::FramePass::prepare`) under keys of its own (its
//! name, its shaders' defines, the formats it writes), and finds them there when it
//! records; the registry holds the tools they are built with — the descriptor-set
//! layouts every pipeline and frame slot share, the shader compiler and the pipeline
//! cache — and knows which shader variants have every pass's pipelines.

use std::any::Any;
use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use combustion_vk::{vk, DescriptorSetLayout, Device, PipelineCache, ShaderCompiler};

use crate::error::RenderError;
use crate::variant::ShaderVariant;
use crate::{bindings, shader_sources};

/// What a pass's pipelines are kept under: the pass (or bake) they are for, the part of
/// the shader variant they are built from (which sets their `#define`s and which of
/// their pipelines exist: a cut-out or a line-list pipeline beside the plain one), the
/// other `#define`s they are compiled with, and the formats they write where they vary.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) struct PipelineKey {
    pub(crate) pass: &'static str,
    pub(crate) variant: Option<ShaderVariant>,
    pub(crate) defines: Vec<(&'static str, Option<&'static str>)>,
    pub(crate) formats: Vec<vk::Format>,
}

impl PipelineKey {
    /// The key of `pass`'s pipelines with no defines and no formats of their own.
    pub(crate) fn named(pass: &'static str) -> Self {
        Self {
            pass,
            variant: None,
            defines: Vec::new(),
            formats: Vec::new(),
        }
    }
}

/// What building a pipeline takes.
pub(crate) struct PipelineTools<'a> {
    pub(crate) device: &'a Arc<Device>,
    pub(crate) compiler: &'a ShaderCompiler,
    pub(crate) cache: &'a PipelineCache,
    pub(crate) layouts: &'a SetLayouts,
}

/// The descriptor-set layout of every declared set, shared by every
/// variant's pipelines and every frame slot.
pub(crate) struct SetLayouts {
    by_name: Vec<(&'static str, DescriptorSetLayout)>,
}

impl SetLayouts {
    pub(crate) fn new(
        device: &Arc<Device>,
        sets: &[&'static bindings::SetDecl],
    ) -> Result<Self, RenderError> {
        let by_name = sets
            .iter()
            .map(|decl| Ok((decl.name, decl.layout(device)?)))
            .collect::<Result<_, RenderError>>()?;
        Ok(Self { by_name })
    }

    /// The layout of `decl` (one of the sets it was made with).
    pub(crate) fn of(&self, decl: &bindings::SetDecl) -> &DescriptorSetLayout {
        self.by_name
            .iter()
            .find(|(name, _)| *name == decl.name)
            .map(|(_, layout)| layout)
            .unwrap_or_else(|| panic!("set {} is not declared", decl.name))
    }
}

/// Every pipeline built, by key (module documentation), and the variants whose passes
/// have all of theirs.
pub(crate) struct PipelineRegistry {
    device: Arc<Device>,
    pub(crate) compiler: ShaderCompiler,
    pub(crate) cache: PipelineCache,
    pub(crate) layouts: SetLayouts,
    entries: HashMap<PipelineKey, Box<dyn Any + Send + Sync>>,
    /// Variants every pass of the frame has prepared.
    prepared: HashSet<ShaderVariant>,
    /// The target formats whose output passes are built, in the order they were.
    output_formats: Vec<vk::Format>,
    /// Pipelines built so far ([`crate::RendererStats::pipelines_built`]).
    pub(crate) built: u64,
}

impl PipelineRegistry {
    /// The compiler (with the shader sources, `headers` generated for them, and the
    /// SPIR-V cache), the layouts of `sets` and a pipeline cache primed from
    /// `cache_data`; no pipeline yet.
    pub(crate) fn new(
        device: &Arc<Device>,
        cache_data: &[u8],
        sets: &[&'static bindings::SetDecl],
        headers: Vec<(String, String)>,
    ) -> Result<Self, RenderError> {
        let compiler = ShaderCompiler::new(shader_sources::sources(headers))?
            .with_spirv_cache(combustion_vk::default_spirv_cache_dir());
        Ok(Self {
            device: device.clone(),
            compiler,
            cache: PipelineCache::new(device, cache_data)?,
            layouts: SetLayouts::new(device, sets)?,
            entries: HashMap::new(),
            prepared: HashSet::new(),
            output_formats: Vec::new(),
            built: 0,
        })
    }

    /// The pipelines kept under `key`, if they are built (and of type `T`).
    pub(crate) fn get<T: Any>(&self, key: &PipelineKey) -> Option<&T> {
        self.entries.get(key).and_then(|e| e.downcast_ref())
    }

    /// The pipelines under `key`, built by `make` (which returns them and how many
    /// pipelines it built) unless they are there.
    pub(crate) fn build<T: Any + Send + Sync>(
        &mut self,
        key: PipelineKey,
        make: impl FnOnce(&PipelineTools<'_>) -> Result<(T, u64), RenderError>,
    ) -> Result<&mut T, RenderError> {
        if !self.entries.contains_key(&key) {
            let (made, count) = make(&self.tools())?;
            self.built += count;
            self.entries.insert(key.clone(), Box::new(made));
        }
        Ok(self
            .entries
            .get_mut(&key)
            .and_then(|e| e.downcast_mut())
            .expect("built under this key with this type"))
    }

    /// Adds to the pipelines under `key` (if they are built): `change` returns how many
    /// pipelines it built.
    pub(crate) fn update<T: Any>(
        &mut self,
        key: &PipelineKey,
        change: impl FnOnce(&mut T, &PipelineTools<'_>) -> Result<u64, RenderError>,
    ) -> Result<(), RenderError> {
        let tools = PipelineTools {
            device: &self.device,
            compiler: &self.compiler,
            cache: &self.cache,
            layouts: &self.layouts,
        };
        if let Some(entry) = self.entries.get_mut(key).and_then(|e| e.downcast_mut()) {
            self.built += change(entry, &tools)?;
        }
        Ok(())
    }

    /// What building a pipeline takes.
    pub(crate) fn tools(&self) -> PipelineTools<'_> {
        PipelineTools {
            device: &self.device,
            compiler: &self.compiler,
            cache: &self.cache,
            layouts: &self.layouts,
        }
    }

    /// Whether every pass has built its pipelines for `variant`.
    pub(crate) fn is_prepared(&self, variant: &ShaderVariant) -> bool {
        self.prepared.contains(variant)
    }

    /// Records that every pass has built its pipelines for `variant`.
    pub(crate) fn mark_prepared(&mut self, variant: ShaderVariant) {
        self.prepared.insert(variant);
    }

    /// The variants every pass has built its pipelines for.
    pub(crate) fn prepared_variants(&self) -> Vec<ShaderVariant> {
        self.prepared.iter().copied().collect()
    }

    /// Records that the output passes into targets of `format` are built.
    pub(crate) fn mark_output_format(&mut self, format: vk::Format) {
        if !self.output_formats.contains(&format) {
            self.output_formats.push(format);
        }
    }

    /// The target formats whose output passes are built.
    pub(crate) fn output_formats(&self) -> Vec<vk::Format> {
        self.output_formats.clone()
    }

    /// The environment bake's pipelines, built on first use.
    pub(crate) fn environment_baker(
        &mut self,
    ) -> Result<&crate::environment::EnvironmentBaker, RenderError> {
        let baker = self.build(PipelineKey::named("environment bake"), |t| {
            let baker = crate::environment::EnvironmentBaker::new(
                t.device,
                t.compiler,
                t.cache,
                crate::environment::default_environment_cache_dir(),
            )?;
            // Its pipelines are counted as bakes, not here.
            Ok((baker, 0))
        })?;
        Ok(&*baker)
    }
}
