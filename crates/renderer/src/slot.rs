//! What one frame in flight owns: its descriptor sets (one of each declaration the
//! frame's passes bind), its lights, tile lists, overlay quads, shadow-layer table,
//! joint matrices and morph weights, its timestamps, its placement and its retire list.

use std::sync::Arc;

use combustion_vk::{vk, Buffer, DescriptorPool, Device, TimestampQueries, VkError};

use crate::bindings;
use crate::buffers::{storage_buffer, CPU_TO_GPU, GPU_ONLY};
use crate::error::RenderError;
use crate::gpu_types::GpuLight;
use crate::overlay::OverlayQuad;
use crate::pipelines::SetLayouts;

/// Timestamps a frame may write: its start, the end of each pass, and the end of its
/// last command.
pub(crate) const MAX_TIMESTAMPS: u32 = 32;

/// The slot's frame-end record: the frame's marker (8 bytes), then its timestamps, then
/// (at this offset, in frames that meter their exposure) the auto exposure's state.
pub(crate) const FRAME_END_BYTES: u64 = 8 * (1 + MAX_TIMESTAMPS as u64);

/// What one frame in flight owns. Reused only once the frame that used it last has
/// completed (the host's promise when it records into the same slot again).
pub(crate) struct FrameSlot {
    /// Its place among the renderer's slots (0 to frames in flight − 1).
    pub(crate) index: usize,
    /// One descriptor set of each declaration the frame's passes bind
    /// (`passes::FramePass::sets`), by the declaration's name.
    sets: Vec<(&'static str, vk::DescriptorSet)>,
    /// Owns the sets.
    _pool: DescriptorPool,
    /// The tile light lists of the slot's frame (device memory, written by the culling
    /// pass; grows with the tile count × lights).
    pub(crate) tile_lights: Buffer,
    /// Whether the slot's frame culls its lights, and its tile grid and list stride.
    pub(crate) culling: Option<(u32, u32)>,
    /// The frame's lights (host-visible; grows when a frame brings more lights).
    pub(crate) lights: Buffer,
    /// The frame's overlay quads (host-visible; grows as lights do).
    pub(crate) overlay_quads: Buffer,
    /// How many quads this slot's frame draws.
    pub(crate) overlay_quad_count: u32,
    /// The placement of each shadow-map layer of the slot's frame (host-visible; grows).
    pub(crate) shadow_cascades: Buffer,
    /// The world-to-map matrix of each cascade layer the slot's frame renders (empty:
    /// none rendered this frame, the maps kept or no shadows).
    pub(crate) shadow_layers: Vec<glam::Mat4>,
    /// The same for the local lights' maps.
    pub(crate) local_shadow_layers: Vec<glam::Mat4>,
    pub(crate) timestamps: Option<TimestampQueries>,
    /// What the slot's frame writes after its last command (host-visible): its marker,
    /// the frame's number + 1 (u64), then a copy of its timestamps. The GPU's own word
    /// that the frame completed: the slot check, the timings and every cache committed
    /// at record time read it, never a query.
    pub(crate) frame_end: Buffer,
    /// Whether the slot's last recorded frame metered its exposure (its frame-end record
    /// then holds the auto exposure's state).
    pub(crate) metered: bool,
    /// The marker the slot's last recorded frame writes when it completes (0: no frame
    /// recorded since the slot was last known free).
    pub(crate) recorded: u64,
    /// The passes whose end this slot's last frame stamped, in order (empty: no frame
    /// stamped since its timings were read, or no timestamps).
    pub(crate) stamped: Vec<&'static str>,
    /// Where the slot's frame places the objects (its pose's object table and boxes).
    pub(crate) placement: crate::placement::SlotPlacement,
    /// Each object's transform in the frame before the slot's frame (host-visible;
    /// grows), in frames of temporal anti-aliasing: what the motion pass measures
    /// motion from.
    pub(crate) previous_models: Buffer,
    /// Per object, the index of its first vertex in the previous posed vertices
    /// (`NOT_POSED`: it draws its mesh's own), likewise.
    pub(crate) previous_vertex_bases: Buffer,
    /// The skins' joint matrices of the slot's frame (host-visible; grows), in frames of
    /// scenes with deformed objects.
    pub(crate) joint_matrices: Buffer,
    /// The deformed objects' morph weights of the slot's frame (likewise).
    pub(crate) morph_weights: Buffer,
    /// Objects replaced while this slot's frame was the latest recorded: dropped when
    /// the slot is reused, i.e. once that frame (and so every earlier one) completed.
    pub(crate) retired: Vec<crate::retire::Retired>,
}

impl FrameSlot {
    /// A slot with one set of each of `decls` (the declarations the frame's passes
    /// bind: `passes::frame_sets`), the pool sized by them, and small buffers that grow.
    pub fn new(
        device: &Arc<Device>,
        layouts: &SetLayouts,
        decls: &[&'static bindings::SetDecl],
        index: usize,
    ) -> Result<Self, RenderError> {
        let sizes: Vec<_> = decls
            .iter()
            .flat_map(|decl| decl.pool_sizes(1, device.ray_queries()))
            .collect();
        let pool = DescriptorPool::new(device, decls.len() as u32, &sizes)?;
        let sets = decls
            .iter()
            .map(|decl| Ok((decl.name, pool.allocate(layouts.of(decl))?)))
            .collect::<Result<_, RenderError>>()?;
        let timestamps = match TimestampQueries::new(device, MAX_TIMESTAMPS) {
            Ok(t) => Some(t),
            Err(VkError::Unsupported(why)) => {
                log::warn!("pass timings unavailable: {why}");
                None
            }
            Err(e) => return Err(e.into()),
        };
        Ok(Self {
            index,
            sets,
            _pool: pool,
            tile_lights: storage_buffer(device, TILE_LISTS, 4, GPU_ONLY)?,
            culling: None,
            lights: storage_buffer(
                device,
                LIGHTS,
                4 * std::mem::size_of::<GpuLight>() as u64,
                CPU_TO_GPU,
            )?,
            overlay_quads: storage_buffer(
                device,
                OVERLAY_QUADS,
                64 * std::mem::size_of::<OverlayQuad>() as u64,
                CPU_TO_GPU,
            )?,
            overlay_quad_count: 0,
            shadow_cascades: storage_buffer(
                device,
                SHADOW_CASCADES,
                std::mem::size_of::<crate::gpu_types::GpuShadowCascade>() as u64,
                CPU_TO_GPU,
            )?,
            shadow_layers: Vec::new(),
            local_shadow_layers: Vec::new(),
            timestamps,
            frame_end: Buffer::new(
                device,
                "frame end marker and timings",
                FRAME_END_BYTES + crate::exposure::MeteredExposure::BYTES,
                vk::BufferUsageFlags::TRANSFER_DST,
                combustion_vk::gpu_allocator::MemoryLocation::GpuToCpu,
            )?,
            recorded: 0,
            metered: false,
            stamped: Vec::new(),
            placement: crate::placement::SlotPlacement::new(device)?,
            joint_matrices: storage_buffer(device, JOINT_MATRICES, 64, CPU_TO_GPU)?,
            previous_models: storage_buffer(device, PREVIOUS_MODELS, 64, CPU_TO_GPU)?,
            previous_vertex_bases: storage_buffer(device, PREVIOUS_VERTEX_BASES, 4, CPU_TO_GPU)?,
            morph_weights: storage_buffer(device, MORPH_WEIGHTS, 4, CPU_TO_GPU)?,
            retired: Vec::new(),
        })
    }

    /// The slot's set of `decl` (a set some pass of the frame declares).
    pub fn set(&self, decl: &bindings::SetDecl) -> vk::DescriptorSet {
        self.sets
            .iter()
            .find(|(name, _)| *name == decl.name)
            .map(|(_, set)| *set)
            .unwrap_or_else(|| panic!("no pass of the frame declares set {}", decl.name))
    }

    /// The marker of the last frame of this slot that has completed (0: none yet).
    pub fn completed_marker(&self) -> u64 {
        self.frame_end
            .mapped()
            .ok()
            .and_then(|bytes| bytes.get(..8))
            .map_or(0, |b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
    }

    /// Whether the slot's last recorded frame has completed (the GPU wrote its marker),
    /// or no frame was recorded into it since it was last known free.
    pub fn is_free(&self) -> bool {
        self.recorded == 0 || self.completed_marker() >= self.recorded
    }

    /// The auto exposure's state the slot's completed frame copied (frames that
    /// metered).
    pub fn completed_exposure(&self) -> Option<crate::exposure::MeteredExposure> {
        let bytes = self.frame_end.mapped().ok()?;
        let start = FRAME_END_BYTES as usize;
        let state = bytes.get(start..start + crate::exposure::MeteredExposure::BYTES as usize)?;
        Some(crate::exposure::MeteredExposure::from_bytes(state))
    }

    /// The timestamps (ticks) the slot's completed frame copied, the first `count`.
    pub fn completed_ticks(&self, count: usize) -> Vec<u64> {
        self.frame_end.mapped().map_or_else(
            |_| Vec::new(),
            |bytes| {
                bytes[8..]
                    .chunks_exact(8)
                    .take(count)
                    .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
                    .collect()
            },
        )
    }

    pub fn retire(&mut self, resource: crate::retire::Retired) {
        self.retired.push(resource);
    }
}

/// Names of the per-slot buffers (for the allocator's reports).
pub(crate) const LIGHTS: &str = "frame lights";
pub(crate) const TILE_LISTS: &str = "tile light lists";
pub(crate) const OVERLAY_QUADS: &str = "frame overlay quads";
pub(crate) const SHADOW_CASCADES: &str = "frame shadow cascades";
pub(crate) const JOINT_MATRICES: &str = "frame joint matrices";
pub(crate) const MORPH_WEIGHTS: &str = "frame morph weights";
pub(crate) const PREVIOUS_MODELS: &str = "frame previous object transforms";
pub(crate) const PREVIOUS_VERTEX_BASES: &str = "frame previous vertex bases";
