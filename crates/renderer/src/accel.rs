//! Acceleration structures for ray queries, on devices that have them
//! ([`Device::ray_queries`]): a bottom-level structure per triangle mesh
//! ([`MeshStructures`]), built when a scene is uploaded for frames with a pass that traces
//! (`FramePass::traces`), and a top-level structure per frame slot ([`SceneStructure`]),
//! rebuilt by that pass in each of its frames from where the frame places its objects.
//!
//! What is in them (chosen once per scene): every object whose mesh is a triangle
//! list, that casts shadows (`Object::casts_shadows`: an object that casts none occludes
//! nothing) and that is neither blended nor transmissive (glass lets light through).
//! Points and lines are never in them, nor what exceeds the device's limits ([`Limits`]:
//! left out with a warning). Cut-outs (alphaMode MASK) are tested where a ray
//! meets them ([`TracedCutouts`]): their instances are not opaque, and the shaders'
//! `scene_blocks` (traced_scene.glsl) confirms a hit only where the material's alpha —
//! its factor × the base colour texture's alpha at level 0, filtered by the sampler's
//! magnification filter × the vertex colour's alpha — reaches the cutoff, as the f64
//! reference's ray casts do. Every other instance is opaque: its hits cost no test.
//!
//! Skinned and morphed objects ([`DeformedStructure`]) are traced in the shape the frame
//! draws: each has a bottom-level structure of its own over the deform pass's posed
//! vertices, rebuilt (a full build, preferring a fast build to a fast trace) before the
//! top-level one in each traced frame whose pose differs from the one they were last
//! built in — frames in the same pose (a still scene at rest, a paused animation) do
//! not pay for them.

use std::sync::{Arc, Mutex};

use combustion_scene::{Scene, Topology};
use combustion_vk::gpu_allocator::MemoryLocation;
use combustion_vk::{vk, Buffer, Device, OneShot, VkError, VkResultExt};

use crate::error::RenderError;

/// How far along the normal the environment's visibility rays start, per metre of the
/// point's distance from the eye: the ray-traced occlusion pass's rule and the sampled
/// environment's (past the 32-bit depth's rounding, which can put a reconstructed point
/// below its surface); the f64 reference's too.
pub const ENVIRONMENT_RAY_OFFSET: f64 = 2e-4;

/// The functions of VK_KHR_acceleration_structure (a device without ray queries has
/// none: callers check [`Device::ray_queries`] first).
fn functions(
    device: &Device,
) -> Result<&combustion_vk::ash::khr::acceleration_structure::Device, RenderError> {
    device.acceleration_structure().ok_or_else(|| {
        RenderError::Vulkan(VkError::Unsupported(
            "acceleration structures on a device without ray queries".into(),
        ))
    })
}

/// The device's acceleration-structure properties.
fn properties(device: &Device) -> vk::PhysicalDeviceAccelerationStructurePropertiesKHR<'static> {
    let mut properties = vk::PhysicalDeviceAccelerationStructurePropertiesKHR::default();
    let mut properties2 = vk::PhysicalDeviceProperties2::default().push_next(&mut properties);
    // SAFETY: valid physical device; the chain outlives the call.
    unsafe {
        device
            .instance()
            .get_physical_device_properties2(device.physical_device(), &mut properties2)
    };
    properties.p_next = std::ptr::null_mut();
    properties
}

/// The alignment of a build's scratch memory on `device`.
fn scratch_alignment(device: &Device) -> u64 {
    u64::from(properties(device).min_acceleration_structure_scratch_offset_alignment).max(1)
}

/// How much one scene's structures may hold on a device: triangles in one bottom-level
/// structure, instances in the top level (both at most 2²⁴ − 1, the instance's custom
/// index, which names a cut-out's entry, has 24 bits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Limits {
    pub triangles: u64,
    pub instances: u64,
}

impl Limits {
    /// `device`'s limits.
    fn of(device: &Device) -> Self {
        let p = properties(device);
        let custom_index = (1 << 24) - 1;
        Self {
            triangles: p.max_primitive_count.min(custom_index),
            instances: p.max_instance_count.min(custom_index),
        }
    }

    /// Which of the meshes of `triangles` (a count each) a structure can hold, and how
    /// many of `occluders` instances the top level keeps; a warning line for each mesh
    /// left out and for the instances left out, naming the limit: what they hold is
    /// then missing from the traced passes (they occlude nothing), never an error.
    pub(crate) fn fit(
        &self,
        meshes: &[(&str, u64)],
        occluders: usize,
    ) -> (Vec<bool>, usize, Vec<String>) {
        let mut warnings = Vec::new();
        let fits: Vec<bool> = meshes
            .iter()
            .map(|&(name, triangles)| {
                let fits = triangles <= self.triangles;
                if !fits {
                    warnings.push(format!(
                        "mesh `{}`: {triangles} triangles, more than the device's acceleration structures hold ({}); the traced passes leave it out (it occludes nothing there)",
                        combustion_optics::shortened(name),
                        self.triangles
                    ));
                }
                fits
            })
            .collect();
        let kept = (occluders as u64).min(self.instances) as usize;
        if kept < occluders {
            warnings.push(format!(
                "{occluders} objects occlude, more than the device's acceleration structures place ({}); the traced passes leave out the last {}",
                self.instances,
                occluders - kept
            ));
        }
        (fits, kept, warnings)
    }
}

/// Device-address usages of the buffers a build reads.
const BUILD_INPUT: vk::BufferUsageFlags = vk::BufferUsageFlags::from_raw(
    vk::BufferUsageFlags::ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_KHR.as_raw()
        | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS.as_raw(),
);

/// An acceleration structure and the buffer that holds it.
pub(crate) struct AccelerationStructure {
    device: Arc<Device>,
    buffer: Buffer,
    handle: vk::AccelerationStructureKHR,
    address: vk::DeviceAddress,
}

impl AccelerationStructure {
    fn new(
        device: &Arc<Device>,
        ty: vk::AccelerationStructureTypeKHR,
        size: u64,
        name: &str,
    ) -> Result<Self, RenderError> {
        let functions = functions(device)?;
        let buffer = Buffer::new(
            device,
            name,
            size,
            vk::BufferUsageFlags::ACCELERATION_STRUCTURE_STORAGE_KHR
                | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
            MemoryLocation::GpuOnly,
        )?;
        let info = vk::AccelerationStructureCreateInfoKHR::default()
            .buffer(buffer.raw())
            .size(size)
            .ty(ty);
        // SAFETY: valid create info; the structure is destroyed in Drop, before its buffer.
        let handle = unsafe { functions.create_acceleration_structure(&info, None) }
            .what("vkCreateAccelerationStructureKHR")?;
        // SAFETY: the structure was just created.
        let address = unsafe {
            functions.get_acceleration_structure_device_address(
                &vk::AccelerationStructureDeviceAddressInfoKHR::default()
                    .acceleration_structure(handle),
            )
        };
        Ok(Self {
            device: device.clone(),
            buffer,
            handle,
            address,
        })
    }

    /// The bytes its buffer holds.
    fn bytes(&self) -> u64 {
        self.buffer.size()
    }

    /// The structure, for descriptor writes.
    pub(crate) fn handle(&self) -> vk::AccelerationStructureKHR {
        self.handle
    }
}

impl Drop for AccelerationStructure {
    fn drop(&mut self) {
        if let Some(functions) = self.device.acceleration_structure() {
            // SAFETY: created on this device; no pending work uses it (the owner's
            // retirement waits for the frames that did).
            unsafe { functions.destroy_acceleration_structure(self.handle, None) };
        }
    }
}

/// Scratch memory for a build of `size` bytes, and its aligned address.
fn scratch(device: &Arc<Device>, size: u64, name: &str) -> Result<(Buffer, u64), RenderError> {
    let alignment = scratch_alignment(device);
    let buffer = Buffer::new(
        device,
        name,
        size + alignment,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS,
        MemoryLocation::GpuOnly,
    )?;
    let address = device
        .buffer_address(buffer.raw())
        .next_multiple_of(alignment);
    Ok((buffer, address))
}

/// Flags of the meshes' builds: built once, traced every frame, compacted after.
const MESH_BUILD: vk::BuildAccelerationStructureFlagsKHR =
    vk::BuildAccelerationStructureFlagsKHR::from_raw(
        vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE.as_raw()
            | vk::BuildAccelerationStructureFlagsKHR::ALLOW_COMPACTION.as_raw(),
    );

/// Replaces each built structure of `structures` by its compacted copy: their compacted
/// sizes queried after the builds (one submission, waited for), then each copied into a
/// structure of that size (a second); the originals dropped once the copies completed.
fn compact(
    device: &Arc<Device>,
    structures: &mut [Option<AccelerationStructure>],
) -> Result<(), RenderError> {
    let functions = functions(device)?;
    let built: Vec<usize> = (0..structures.len())
        .filter(|&i| structures[i].is_some())
        .collect();
    if built.is_empty() {
        return Ok(());
    }
    let handles: Vec<vk::AccelerationStructureKHR> = built
        .iter()
        .map(|&i| structures[i].as_ref().expect("built").handle)
        .collect();
    let raw = device.raw();
    let pool_info = vk::QueryPoolCreateInfo::default()
        .query_type(vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR)
        .query_count(handles.len() as u32);
    // SAFETY: valid create info; destroyed below on every path.
    let pool = unsafe { raw.create_query_pool(&pool_info, None) }.what("vkCreateQueryPool")?;
    let sizes = (|| -> Result<Vec<u64>, RenderError> {
        let mut commands = OneShot::new(device)?;
        let cmd = commands.begin()?;
        // SAFETY: recording; the structures were built by a submission that completed.
        unsafe {
            raw.cmd_reset_query_pool(cmd, pool, 0, handles.len() as u32);
            functions.cmd_write_acceleration_structures_properties(
                cmd,
                &handles,
                vk::QueryType::ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                pool,
                0,
            );
        }
        commands.submit_and_wait()?;
        let mut sizes = vec![0u64; handles.len()];
        // SAFETY: every query was written by the completed submission.
        unsafe {
            raw.get_query_pool_results(
                pool,
                0,
                &mut sizes,
                vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT,
            )
        }
        .what("vkGetQueryPoolResults")?;
        Ok(sizes)
    })();
    // SAFETY: the submission that used the pool has completed (or none was made).
    unsafe { raw.destroy_query_pool(pool, None) };
    let sizes = sizes?;
    let mut compacted = Vec::with_capacity(built.len());
    for &size in &sizes {
        compacted.push(AccelerationStructure::new(
            device,
            vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
            size,
            "mesh acceleration structure",
        )?);
    }
    let mut commands = OneShot::new(device)?;
    let cmd = commands.begin()?;
    for (source, destination) in handles.iter().zip(&compacted) {
        let copy = vk::CopyAccelerationStructureInfoKHR::default()
            .src(*source)
            .dst(destination.handle)
            .mode(vk::CopyAccelerationStructureModeKHR::COMPACT);
        // SAFETY: recording; both structures live until the submission completes.
        unsafe { functions.cmd_copy_acceleration_structure(cmd, &copy) };
    }
    commands.submit_and_wait()?;
    for (&i, structure) in built.iter().zip(compacted) {
        structures[i] = Some(structure);
    }
    Ok(())
}

/// What a path tracer meets where its ray hits an instance of the top level: per
/// instance (in the top level's order: `rayQueryGetIntersectionInstanceIdEXT`),
/// [`SURFACE_ROWS`] `uvec4` — the device addresses of its mesh's vertices (`GpuVertex`,
/// object space) and indices (u32), low word first; then its material, its object, its
/// flags ([`SURFACE_DOUBLE_SIDED`], [`SURFACE_BLENDED`]) and its triangle count; then the
/// device address of its mesh's second texture-coordinate set and vertex colours (six
/// floats a vertex; 0 where the mesh has neither) — and the buffers each names. Then the
/// scene's textures as hits read them (traced_textures.glsl): per texture of the
/// material table's texture array one `uvec4` — the device address of its image's level
/// 0 (RGBA8), its width and height (16 bits each) and its flags — and each image's texels.
/// Skinned and morphed occluders are read in their pose, in the deform pass's output
/// (the vertices their own structures are built over).
pub(crate) struct TracedSurfaces {
    pub(crate) table: Buffer,
    pub(crate) textures: Buffer,
    meshes: Vec<Buffer>,
    texels: Vec<Buffer>,
}

/// The surface table's `uvec4` rows per instance (path_trace.glsl's SURFACE_ROWS).
const SURFACE_ROWS: usize = 3;

/// A traced surface's flag: its material is double-sided (both faces are seen).
const SURFACE_DOUBLE_SIDED: u32 = 1;

/// A traced surface's flag: its material is blended (alphaMode BLEND: a path meets it
/// with probability α).
const SURFACE_BLENDED: u32 = 2;

/// The instance mask of what blocks light (every ray query's: traced_scene.glsl).
pub(crate) const OCCLUDES: u8 = 1;

/// The instance mask of what only paths see (path_trace.glsl).
pub(crate) const SEEN_ONLY: u8 = 2;

/// A traced texture's flag: the image is sRGB-encoded (decoded per texel, before
/// filtering).
const TEXTURE_SRGB: u32 = 1 << 5;

impl TracedSurfaces {
    /// The table of `objects` of `scene` (object indices, in the top level's order);
    /// `posed`: the device address of each deformed object's posed vertices.
    fn new(
        device: &Arc<Device>,
        scene: &Scene,
        objects: &[usize],
        posed: &[(usize, u64)],
    ) -> Result<Self, RenderError> {
        let usage =
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let mut meshes = Vec::new();
        let mut addresses: Vec<Option<[u64; 3]>> = vec![None; scene.meshes.len()];
        let mut table: Vec<[u32; 4]> = Vec::with_capacity(SURFACE_ROWS * objects.len());
        let split = |address: u64| [address as u32, (address >> 32) as u32];
        for &object in objects {
            let o = &scene.objects[object];
            let mesh_index = o.mesh;
            if addresses[mesh_index].is_none() {
                let mesh = &scene.meshes[mesh_index];
                let vertices: Vec<crate::gpu_types::GpuVertex> = mesh
                    .vertices
                    .iter()
                    .map(crate::gpu_types::GpuVertex::new)
                    .collect();
                let mut buffer = |name: &str, bytes: &[u8]| -> Result<u64, RenderError> {
                    let buffer = Buffer::with_data(device, name, bytes, usage)?;
                    let address = device.buffer_address(buffer.raw());
                    meshes.push(buffer);
                    Ok(address)
                };
                let vertices_at = buffer("traced vertices", bytemuck::cast_slice(&vertices))?;
                let indices_at = buffer("traced indices", bytemuck::cast_slice(&mesh.indices))?;
                let second_set = mesh.vertices.iter().any(|v| v.uv1 != [0.0; 2]);
                let extras_at = if second_set || mesh.has_colors() {
                    let extras: Vec<[f32; 6]> = mesh
                        .vertices
                        .iter()
                        .map(|v| {
                            let [u, w] = v.uv1;
                            let [r, g, b, a] = v.color;
                            [u, w, r, g, b, a]
                        })
                        .collect();
                    buffer("traced vertex extras", bytemuck::cast_slice(&extras))?
                } else {
                    0
                };
                addresses[mesh_index] = Some([vertices_at, indices_at, extras_at]);
            }
            let [rest_at, indices_at, extras_at] = addresses[mesh_index].expect("set above");
            let vertices_at = posed
                .iter()
                .find(|&&(posed_object, _)| posed_object == object)
                .map_or(rest_at, |&(_, at)| at);
            let material = scene.materials.get(o.material);
            let flags = if material.is_some_and(|m| m.double_sided) {
                SURFACE_DOUBLE_SIDED
            } else {
                0
            } | if material.is_some_and(combustion_scene::Material::is_blended) {
                SURFACE_BLENDED
            } else {
                0
            };
            let [v0, v1] = split(vertices_at);
            let [i0, i1] = split(indices_at);
            let [e0, e1] = split(extras_at);
            table.push([v0, v1, i0, i1]);
            table.push([
                o.material as u32,
                object as u32,
                flags,
                (scene.meshes[mesh_index].indices.len() / 3) as u32,
            ]);
            table.push([e0, e1, 0, 0]);
        }
        if table.is_empty() {
            table.resize(SURFACE_ROWS, [0; 4]);
        }
        let (textures, texels) = Self::textures(device, scene)?;
        Ok(Self {
            table: Buffer::with_data(
                device,
                "traced surfaces",
                bytemuck::cast_slice(&table),
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )?,
            textures,
            meshes,
            texels,
        })
    }

    /// The texture table of `scene`'s texture array (`Scene::texture_table`, the indices
    /// its materials' rows hold) and the texels of each image it names (level 0, RGBA8).
    fn textures(device: &Arc<Device>, scene: &Scene) -> Result<(Buffer, Vec<Buffer>), RenderError> {
        let usage =
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::SHADER_DEVICE_ADDRESS;
        let table = scene.texture_table();
        let mut texels = Vec::with_capacity(table.images.len());
        let mut image_addresses = Vec::with_capacity(table.images.len());
        for image in &table.images {
            if image.width > u32::from(u16::MAX) || image.height > u32::from(u16::MAX) {
                return Err(RenderError::TooLarge(format!(
                    "image `{}` is {}×{}: a path's hits read images of at most 65,535 texels a side",
                    image.name, image.width, image.height
                )));
            }
            let buffer = Buffer::with_data(device, "traced texels", &image.pixels, usage)?;
            image_addresses.push(device.buffer_address(buffer.raw()));
            texels.push(buffer);
        }
        let mut entries: Vec<[u32; 4]> = table
            .textures
            .iter()
            .map(|texture| {
                let image = &table.images[texture.image];
                let address = image_addresses[texture.image];
                let sampler = &texture.sampler;
                let linear = sampler.mag_filter == combustion_scene::Filter::Linear;
                let srgb = image.color_space == combustion_scene::ColorSpace::Srgb;
                [
                    address as u32,
                    (address >> 32) as u32,
                    image.width | image.height << 16,
                    wrap_bits(sampler.wrap_u)
                        | wrap_bits(sampler.wrap_v) << 2
                        | if linear { CUTOUT_LINEAR } else { 0 }
                        | if srgb { TEXTURE_SRGB } else { 0 },
                ]
            })
            .collect();
        if entries.is_empty() {
            entries.push([0; 4]);
        }
        let textures = Buffer::with_data(
            device,
            "traced textures",
            bytemuck::cast_slice(&entries),
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        Ok((textures, texels))
    }

    /// A table of one empty entry: what a set binds where a frame path-traces nothing.
    pub(crate) fn none(device: &Arc<Device>) -> Result<Self, RenderError> {
        let empty = |name: &str, bytes: usize| {
            Buffer::with_data(
                device,
                name,
                &vec![0; bytes],
                vk::BufferUsageFlags::STORAGE_BUFFER,
            )
        };
        Ok(Self {
            table: empty("traced surfaces", 16 * SURFACE_ROWS)?,
            textures: empty("traced textures", 16)?,
            meshes: Vec::new(),
            texels: Vec::new(),
        })
    }

    /// The bytes its buffers hold.
    fn bytes(&self) -> u64 {
        self.table.size()
            + self.textures.size()
            + self
                .meshes
                .iter()
                .chain(&self.texels)
                .map(Buffer::size)
                .sum::<u64>()
    }
}

/// An instance of the bottom-level structure at `address` placed by `transform`, with
/// its custom index and mask, and `flags`.
fn placed_instance(
    transform: glam::Mat4,
    (custom_index, mask): (u32, u8),
    flags: vk::GeometryInstanceFlagsKHR,
    address: u64,
) -> vk::AccelerationStructureInstanceKHR {
    let rows = transform.transpose().to_cols_array();
    vk::AccelerationStructureInstanceKHR {
        transform: vk::TransformMatrixKHR {
            matrix: [
                rows[0], rows[1], rows[2], rows[3], rows[4], rows[5], rows[6], rows[7], rows[8],
                rows[9], rows[10], rows[11],
            ],
        },
        instance_custom_index_and_mask: vk::Packed24_8::new(custom_index, mask),
        instance_shader_binding_table_record_offset_and_flags: vk::Packed24_8::new(
            0,
            flags.as_raw() as u8,
        ),
        acceleration_structure_reference: vk::AccelerationStructureReferenceKHR {
            device_handle: address,
        },
    }
}

/// The bottom-level structure of each mesh that has one (triangle lists with triangles).
pub(crate) struct MeshStructures {
    per_mesh: Vec<Option<AccelerationStructure>>,
}

impl MeshStructures {
    /// Builds the structure of every triangle mesh of `scene` that `fits` (one
    /// submission, waited for: at upload, never in a frame).
    pub(crate) fn build(
        device: &Arc<Device>,
        scene: &Scene,
        fits: &[bool],
    ) -> Result<Self, RenderError> {
        let functions = functions(device)?;
        let mut per_mesh = Vec::with_capacity(scene.meshes.len());
        // Inputs and scratch live until the submission has completed.
        let mut kept: Vec<Buffer> = Vec::new();
        let mut builds: Vec<(usize, u64, u64, u32, u32, u64)> = Vec::new();
        for (index, mesh) in scene.meshes.iter().enumerate() {
            let triangles = (mesh.indices.len() / 3) as u32;
            if mesh.topology != Topology::Triangles
                || triangles == 0
                || mesh.vertices.is_empty()
                || !fits[index]
            {
                per_mesh.push(None);
                continue;
            }
            let positions: Vec<[f32; 3]> = mesh.vertices.iter().map(|v| v.position).collect();
            let position_buffer = Buffer::with_data(
                device,
                "acceleration structure positions",
                bytemuck::cast_slice(&positions),
                BUILD_INPUT,
            )?;
            let index_buffer = Buffer::with_data(
                device,
                "acceleration structure indices",
                bytemuck::cast_slice(&mesh.indices[..triangles as usize * 3]),
                BUILD_INPUT,
            )?;
            let (positions_at, indices_at) = (
                device.buffer_address(position_buffer.raw()),
                device.buffer_address(index_buffer.raw()),
            );
            kept.push(position_buffer);
            kept.push(index_buffer);
            let geometry =
                triangle_geometry(positions_at, indices_at, mesh.vertices.len() as u32 - 1);
            let (structure, scratch_buffer, scratch_at) =
                sized_bottom_level(device, geometry, MESH_BUILD, triangles, "mesh")?;
            kept.push(scratch_buffer);
            builds.push((
                index,
                positions_at,
                indices_at,
                mesh.vertices.len() as u32 - 1,
                triangles,
                scratch_at,
            ));
            per_mesh.push(Some(structure));
        }
        if !builds.is_empty() {
            let mut commands = OneShot::new(device)?;
            let cmd = commands.begin()?;
            for &(index, positions_at, indices_at, max_vertex, triangles, scratch_at) in &builds {
                let structure = per_mesh[index].as_ref().expect("built above");
                let geometries = [triangle_geometry(positions_at, indices_at, max_vertex)];
                let info = bottom_level_info(&geometries, MESH_BUILD)
                    .dst_acceleration_structure(structure.handle)
                    .scratch_data(vk::DeviceOrHostAddressKHR {
                        device_address: scratch_at,
                    });
                let range = [vk::AccelerationStructureBuildRangeInfoKHR::default()
                    .primitive_count(triangles)];
                // SAFETY: recording; the inputs, scratch and destination live until the
                // submission completes (waited for below).
                unsafe { functions.cmd_build_acceleration_structures(cmd, &[info], &[&range]) };
            }
            commands.submit_and_wait()?;
            drop(kept);
            compact(device, &mut per_mesh)?;
        }
        Ok(Self { per_mesh })
    }

    /// The bytes the structures hold.
    fn bytes(&self) -> u64 {
        self.per_mesh
            .iter()
            .flatten()
            .map(AccelerationStructure::bytes)
            .sum()
    }

    /// The structure of mesh `index`, if it has one.
    fn of(&self, index: usize) -> Option<&AccelerationStructure> {
        self.per_mesh.get(index).and_then(Option::as_ref)
    }
}

/// A bottom-level build of `geometries` with `flags` (no destination or scratch yet).
fn bottom_level_info<'a>(
    geometries: &'a [vk::AccelerationStructureGeometryKHR<'a>],
    flags: vk::BuildAccelerationStructureFlagsKHR,
) -> vk::AccelerationStructureBuildGeometryInfoKHR<'a> {
    vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL)
        .flags(flags)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(geometries)
}

/// A bottom-level structure sized for `triangles` of `geometry` built with `flags`, and
/// scratch for that build (its buffer and aligned address); `what` names them.
fn sized_bottom_level(
    device: &Arc<Device>,
    geometry: vk::AccelerationStructureGeometryKHR<'static>,
    flags: vk::BuildAccelerationStructureFlagsKHR,
    triangles: u32,
    what: &str,
) -> Result<(AccelerationStructure, Buffer, u64), RenderError> {
    let functions = functions(device)?;
    let geometries = [geometry];
    let info = bottom_level_info(&geometries, flags);
    let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
    // SAFETY: valid build info.
    unsafe {
        functions.get_acceleration_structure_build_sizes(
            vk::AccelerationStructureBuildTypeKHR::DEVICE,
            &info,
            &[triangles],
            &mut sizes,
        )
    };
    let structure = AccelerationStructure::new(
        device,
        vk::AccelerationStructureTypeKHR::BOTTOM_LEVEL,
        sizes.acceleration_structure_size,
        &format!("{what} acceleration structure"),
    )?;
    let (buffer, at) = scratch(
        device,
        sizes.build_scratch_size,
        &format!("{what} acceleration structure scratch"),
    )?;
    Ok((structure, buffer, at))
}

/// One triangle geometry of a bottom-level build: f32 positions, u32 indices, opaque.
fn triangle_geometry(
    positions_at: u64,
    indices_at: u64,
    max_vertex: u32,
) -> vk::AccelerationStructureGeometryKHR<'static> {
    let triangles = vk::AccelerationStructureGeometryTrianglesDataKHR::default()
        .vertex_format(vk::Format::R32G32B32_SFLOAT)
        .vertex_data(vk::DeviceOrHostAddressConstKHR {
            device_address: positions_at,
        })
        .vertex_stride(12)
        .max_vertex(max_vertex)
        .index_type(vk::IndexType::UINT32)
        .index_data(vk::DeviceOrHostAddressConstKHR {
            device_address: indices_at,
        });
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::TRIANGLES)
        .geometry(vk::AccelerationStructureGeometryDataKHR { triangles })
        .flags(vk::GeometryFlagsKHR::OPAQUE)
}

/// What the traced shaders read to test cut-outs (traced_scene.glsl): per cut-out
/// instance (its custom index) two `uvec4`s — its first corner and first alpha texel,
/// its texture's width and height; then its wrap modes and filter (bits 0–1 and 2–3: 0
/// repeat, 1 mirrored repeat, 2 clamp to edge; bit 4 linear magnification; bit 5
/// textured), its alpha factor and its cutoff (as f32 bits) — each of its mesh's
/// triangle corners (the base colour texture's coordinates, transformed, and the vertex
/// colour's alpha), and the alpha bytes of its textures' level 0, four to a word.
pub(crate) struct TracedCutouts {
    pub(crate) entries: Buffer,
    pub(crate) corners: Buffer,
    pub(crate) alphas: Buffer,
}

/// Bits of a cut-out's flags (traced_scene.glsl).
const CUTOUT_LINEAR: u32 = 1 << 4;
const CUTOUT_TEXTURED: u32 = 1 << 5;

fn wrap_bits(mode: combustion_scene::WrapMode) -> u32 {
    match mode {
        combustion_scene::WrapMode::Repeat => 0,
        combustion_scene::WrapMode::MirroredRepeat => 1,
        combustion_scene::WrapMode::ClampToEdge => 2,
    }
}

impl TracedCutouts {
    /// Buffers of `entries`, `corners` and `alphas` (a placeholder word where one is
    /// empty: a binding needs a buffer).
    fn upload(
        device: &Arc<Device>,
        entries: &[[u32; 4]],
        corners: &[[f32; 4]],
        alphas: &[u8],
    ) -> Result<Self, RenderError> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let filled = |name: &str, bytes: &[u8]| -> Result<Buffer, RenderError> {
            let mut padded = bytes.to_vec();
            padded.resize(bytes.len().next_multiple_of(16).max(16), 0);
            Ok(Buffer::with_data(device, name, &padded, storage)?)
        };
        Ok(Self {
            entries: filled("traced cut-outs", bytemuck::cast_slice(entries))?,
            corners: filled("traced cut-out corners", bytemuck::cast_slice(corners))?,
            alphas: filled("traced cut-out alphas", alphas)?,
        })
    }

    /// None to test: what a set binds where it traces nothing, or a scene without
    /// cut-outs.
    pub(crate) fn none(device: &Arc<Device>) -> Result<Self, RenderError> {
        Self::upload(device, &[], &[], &[])
    }

    /// The cut-outs among `objects` of `scene` (object indices): the custom index of
    /// each one's instance (None for the others), and the buffers.
    fn of(
        device: &Arc<Device>,
        scene: &Scene,
        objects: &[usize],
    ) -> Result<(Vec<Option<u32>>, Self), RenderError> {
        let mut entries: Vec<[u32; 4]> = Vec::new();
        let mut corners: Vec<[f32; 4]> = Vec::new();
        let mut alphas: Vec<u8> = Vec::new();
        let mut images: Vec<(*const combustion_scene::Image, u32)> = Vec::new();
        let mut indices = Vec::with_capacity(objects.len());
        let too_large =
            || RenderError::TooLarge("the cut-outs' texels and corners exceed 2³² entries".into());
        for &object in objects {
            let o = &scene.objects[object];
            let material = &scene.materials[o.material];
            let Some(cutoff) = material.alpha_mode.cutoff() else {
                indices.push(None);
                continue;
            };
            let mesh = &scene.meshes[o.mesh];
            let texture = material.base_color_texture.as_ref();
            let first_corner = u32::try_from(corners.len()).map_err(|_| too_large())?;
            let triangles = mesh.indices.len() / 3;
            for &i in &mesh.indices[..triangles * 3] {
                let vertex = &mesh.vertices[i as usize];
                let [u, v] = texture.map_or([0.0; 2], |slot| {
                    slot.transform.apply(if slot.tex_coord == 1 {
                        vertex.uv1
                    } else {
                        vertex.uv
                    })
                });
                corners.push([u, v, vertex.color[3], 0.0]);
            }
            let (first_texel, width, height, flags) = match texture {
                None => (0, 0, 0, 0),
                Some(slot) => {
                    let image = &slot.texture.image;
                    let key = std::sync::Arc::as_ptr(image);
                    let first = match images.iter().find(|(k, _)| *k == key) {
                        Some(&(_, first)) => first,
                        None => {
                            let first = u32::try_from(alphas.len()).map_err(|_| too_large())?;
                            alphas.extend(image.pixels.chunks_exact(4).map(|p| p[3]));
                            images.push((key, first));
                            first
                        }
                    };
                    let sampler = &slot.texture.sampler;
                    let linear = sampler.mag_filter == combustion_scene::Filter::Linear;
                    (
                        first,
                        image.width,
                        image.height,
                        wrap_bits(sampler.wrap_u)
                            | wrap_bits(sampler.wrap_v) << 2
                            | if linear { CUTOUT_LINEAR } else { 0 }
                            | CUTOUT_TEXTURED,
                    )
                }
            };
            indices.push(Some(entries.len() as u32 / 2));
            entries.push([first_corner, first_texel, width, height]);
            entries.push([flags, material.alpha.to_bits(), cutoff.to_bits(), 0]);
        }
        Ok((indices, Self::upload(device, &entries, &corners, &alphas)?))
    }

    /// The bytes its buffers hold.
    fn bytes(&self) -> u64 {
        self.entries.size() + self.corners.size() + self.alphas.size()
    }
}

/// A skinned or morphed occluder's bottom-level structure, over its posed vertices in
/// the deform pass's output (`SceneDeform::posed`, read in place) and its mesh's indices.
struct DeformedStructure {
    /// The object it is the shape of.
    object: usize,
    /// Whether only paths meet it (a skinned or morphed object that blocks no light:
    /// built only in frames that path-trace).
    paths_only: bool,
    structure: AccelerationStructure,
    /// The mesh's indices, as the build reads them.
    _indices: Buffer,
    indices_at: u64,
    /// The address of its first posed vertex (`GpuVertex`, position first).
    vertices_at: u64,
    max_vertex: u32,
    triangles: u32,
    _scratch: Buffer,
    scratch_at: u64,
}

/// Flags of the deformed objects' builds: rebuilt whenever the pose changes.
const DEFORMED_BUILD: vk::BuildAccelerationStructureFlagsKHR =
    vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_BUILD;

impl DeformedStructure {
    /// The structure of deformed object `object` of `scene`, whose posed vertices are at
    /// `offset` bytes in `deform.posed` (not built: each traced frame builds it).
    fn new(
        device: &Arc<Device>,
        scene: &Scene,
        (object, paths_only): (usize, bool),
        deform: &crate::deform::SceneDeform,
        offset: u64,
    ) -> Result<Option<Self>, RenderError> {
        let mesh = &scene.meshes[scene.objects[object].mesh];
        let triangles = (mesh.indices.len() / 3) as u32;
        if mesh.topology != Topology::Triangles || triangles == 0 || mesh.vertices.is_empty() {
            return Ok(None);
        }
        let indices = Buffer::with_data(
            device,
            "deformed acceleration structure indices",
            bytemuck::cast_slice(&mesh.indices[..triangles as usize * 3]),
            BUILD_INPUT,
        )?;
        let indices_at = device.buffer_address(indices.raw());
        let vertices_at = device.buffer_address(deform.posed.raw()) + offset;
        let max_vertex = mesh.vertices.len() as u32 - 1;
        let geometry = posed_geometry(vertices_at, indices_at, max_vertex);
        let (structure, scratch_buffer, scratch_at) = sized_bottom_level(
            device,
            geometry,
            DEFORMED_BUILD,
            triangles,
            "deformed object",
        )?;
        Ok(Some(Self {
            object,
            paths_only,
            structure,
            _indices: indices,
            indices_at,
            vertices_at,
            max_vertex,
            triangles,
            _scratch: scratch_buffer,
            scratch_at,
        }))
    }

    /// The bytes it holds: the structure, its indices and its scratch.
    fn bytes(&self) -> u64 {
        self.structure.bytes() + self._indices.size() + self._scratch.size()
    }
}

/// One triangle geometry over posed vertices (`GpuVertex`: f32 positions first, 48 bytes
/// apart), u32 indices, opaque.
fn posed_geometry(
    vertices_at: u64,
    indices_at: u64,
    max_vertex: u32,
) -> vk::AccelerationStructureGeometryKHR<'static> {
    let mut geometry = triangle_geometry(vertices_at, indices_at, max_vertex);
    // The union holds triangles (triangle_geometry); writing a field of it is safe.
    geometry.geometry.triangles.vertex_stride =
        std::mem::size_of::<crate::gpu_types::GpuVertex>() as u64;
    geometry
}

/// Records the builds of `deformed` from the posed vertices the frame's deform pass
/// wrote, between the barriers that order them after that pass (and after the ray
/// queries of earlier frames that traced them) and before the top-level build.
fn record_deformed_builds(
    device: &Device,
    functions: &combustion_vk::ash::khr::acceleration_structure::Device,
    cmd: vk::CommandBuffer,
    deformed: &[&DeformedStructure],
) {
    if deformed.is_empty() {
        return;
    }
    let geometries: Vec<[vk::AccelerationStructureGeometryKHR<'static>; 1]> = deformed
        .iter()
        .map(|d| [posed_geometry(d.vertices_at, d.indices_at, d.max_vertex)])
        .collect();
    let infos: Vec<vk::AccelerationStructureBuildGeometryInfoKHR<'_>> = deformed
        .iter()
        .zip(&geometries)
        .map(|(d, geometry)| {
            bottom_level_info(geometry, DEFORMED_BUILD)
                .dst_acceleration_structure(d.structure.handle)
                .scratch_data(vk::DeviceOrHostAddressKHR {
                    device_address: d.scratch_at,
                })
        })
        .collect();
    let ranges: Vec<[vk::AccelerationStructureBuildRangeInfoKHR; 1]> = deformed
        .iter()
        .map(|d| {
            [vk::AccelerationStructureBuildRangeInfoKHR::default().primitive_count(d.triangles)]
        })
        .collect();
    let range_refs: Vec<&[vk::AccelerationStructureBuildRangeInfoKHR]> =
        ranges.iter().map(|r| &r[..]).collect();
    let before = vk::MemoryBarrier2::default()
        .src_stage_mask(
            vk::PipelineStageFlags2::COMPUTE_SHADER
                | vk::PipelineStageFlags2::FRAGMENT_SHADER
                | vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR,
        )
        .src_access_mask(
            vk::AccessFlags2::SHADER_STORAGE_WRITE
                | vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR
                | vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR,
        )
        .dst_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
        .dst_access_mask(
            vk::AccessFlags2::SHADER_READ
                | vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR
                | vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR,
        );
    let after = vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
        .src_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR)
        .dst_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
        .dst_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR);
    // SAFETY: recording; the inputs (the posed vertices, written by this frame's deform
    // pass before this point), scratch and destinations belong to the scene, and the
    // barriers order the builds after their writers and earlier frames' readers.
    unsafe {
        device.raw().cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&[before]),
        );
        functions.cmd_build_acceleration_structures(cmd, &infos, &range_refs);
        device.raw().cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&[after]),
        );
    }
}

/// The top-level structure of one frame slot for one scene: its instances (host-visible,
/// written by the frame that builds it), the structure and its scratch, for up to
/// `capacity` objects.
pub(crate) struct TopLevel {
    instances: Buffer,
    instances_at: u64,
    structure: AccelerationStructure,
    scratch: Buffer,
    scratch_at: u64,
    capacity: u32,
    /// The number of the frame that last built it (0: none).
    built_for: u64,
}

/// The geometry of a top-level build over the instances at `instances_at`.
fn instance_geometry(instances_at: u64) -> vk::AccelerationStructureGeometryKHR<'static> {
    vk::AccelerationStructureGeometryKHR::default()
        .geometry_type(vk::GeometryTypeKHR::INSTANCES)
        .geometry(vk::AccelerationStructureGeometryDataKHR {
            instances: vk::AccelerationStructureGeometryInstancesDataKHR::default()
                .array_of_pointers(false)
                .data(vk::DeviceOrHostAddressConstKHR {
                    device_address: instances_at,
                }),
        })
        .flags(vk::GeometryFlagsKHR::OPAQUE)
}

/// What the top-level build of up to `capacity` instances is (the instances' address
/// set; no destination yet).
fn top_level_info<'a>(
    geometries: &'a [vk::AccelerationStructureGeometryKHR<'a>],
) -> vk::AccelerationStructureBuildGeometryInfoKHR<'a> {
    vk::AccelerationStructureBuildGeometryInfoKHR::default()
        .ty(vk::AccelerationStructureTypeKHR::TOP_LEVEL)
        .flags(vk::BuildAccelerationStructureFlagsKHR::PREFER_FAST_TRACE)
        .mode(vk::BuildAccelerationStructureModeKHR::BUILD)
        .geometries(geometries)
}

impl TopLevel {
    /// A top-level structure for up to `capacity` instances (not built).
    fn new(device: &Arc<Device>, capacity: u32) -> Result<Self, RenderError> {
        let functions = functions(device)?;
        let capacity = capacity.max(1);
        let instances = Buffer::new(
            device,
            "acceleration structure instances",
            (capacity as usize * std::mem::size_of::<vk::AccelerationStructureInstanceKHR>())
                as u64,
            BUILD_INPUT,
            MemoryLocation::CpuToGpu,
        )?;
        let instances_at = device.buffer_address(instances.raw());
        let geometries = [instance_geometry(instances_at)];
        let info = top_level_info(&geometries);
        let mut sizes = vk::AccelerationStructureBuildSizesInfoKHR::default();
        // SAFETY: valid build info.
        unsafe {
            functions.get_acceleration_structure_build_sizes(
                vk::AccelerationStructureBuildTypeKHR::DEVICE,
                &info,
                &[capacity],
                &mut sizes,
            )
        };
        let structure = AccelerationStructure::new(
            device,
            vk::AccelerationStructureTypeKHR::TOP_LEVEL,
            sizes.acceleration_structure_size,
            "scene acceleration structure",
        )?;
        let (scratch_buffer, scratch_at) = scratch(
            device,
            sizes.build_scratch_size,
            "scene acceleration structure scratch",
        )?;
        Ok(Self {
            instances,
            instances_at,
            structure,
            scratch: scratch_buffer,
            scratch_at,
            capacity,
            built_for: 0,
        })
    }

    /// An empty top-level structure, built now (one submission, waited for): what a
    /// set that traces nothing this frame binds.
    pub(crate) fn empty(device: &Arc<Device>) -> Result<Self, RenderError> {
        let functions = functions(device)?;
        let mut top = Self::new(device, 1)?;
        let mut commands = OneShot::new(device)?;
        let cmd = commands.begin()?;
        top.record(device, functions, cmd, &[]);
        commands.submit_and_wait()?;
        Ok(top)
    }

    /// The structure, for descriptor writes.
    pub(crate) fn handle(&self) -> vk::AccelerationStructureKHR {
        self.structure.handle()
    }

    /// The bytes it holds, with its instances and scratch.
    fn bytes(&self) -> u64 {
        self.structure.bytes() + self.instances.size() + self.scratch.size()
    }

    /// Records its build over `instances` (at most its capacity: the caller's), then a
    /// barrier that makes it visible to ray queries in compute and fragment shaders. No
    /// pending frame may use its instances (they are rewritten now).
    fn record(
        &mut self,
        device: &Device,
        functions: &combustion_vk::ash::khr::acceleration_structure::Device,
        cmd: vk::CommandBuffer,
        instances: &[vk::AccelerationStructureInstanceKHR],
    ) {
        // SAFETY: AccelerationStructureInstanceKHR is plain data laid out as Vulkan reads
        // it (64 bytes, no padding).
        let bytes = unsafe {
            std::slice::from_raw_parts(
                instances.as_ptr().cast::<u8>(),
                std::mem::size_of_val(instances),
            )
        };
        self.instances
            .write(0, bytes)
            .expect("the instance buffer is host-visible and holds every object");
        let geometries = [instance_geometry(self.instances_at)];
        let info = top_level_info(&geometries)
            .dst_acceleration_structure(self.structure.handle)
            .scratch_data(vk::DeviceOrHostAddressKHR {
                device_address: self.scratch_at,
            });
        let range = [vk::AccelerationStructureBuildRangeInfoKHR::default()
            .primitive_count(instances.len() as u32)];
        let built = vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ACCELERATION_STRUCTURE_BUILD_KHR)
            .src_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_WRITE_KHR)
            .dst_stage_mask(
                vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            )
            .dst_access_mask(vk::AccessFlags2::ACCELERATION_STRUCTURE_READ_KHR);
        let barriers = [built];
        // SAFETY: recording; the instances, scratch and structure are this one's, which
        // no pending frame uses.
        unsafe {
            functions.cmd_build_acceleration_structures(cmd, &[info], &[&range]);
            device.raw().cmd_pipeline_barrier2(
                cmd,
                &vk::DependencyInfo::default().memory_barriers(&barriers),
            );
        }
    }
}

/// A scene's acceleration structures: its meshes', its deformed objects', and a
/// top-level structure per frame slot (each rebuilt only by frames of its slot, whose
/// previous frame has completed).
pub(crate) struct SceneStructure {
    meshes: MeshStructures,
    /// Its skinned and morphed objects' structures, rebuilt when the pose changes: the
    /// occluders', and those only paths meet (built in frames that path-trace).
    deformed: Vec<DeformedStructure>,
    /// The pose (a frame's `Placement::key`) the deformed objects' structures were last
    /// built in: frames in the same pose find them built (forgotten when the surfaces
    /// paths meet are made, so the structures only paths meet are built then).
    deformed_pose: Mutex<Option<u64>>,
    /// What the rays can hit, chosen once per scene: each object that casts shadows and
    /// is neither blended nor transmissive, with the address of its bottom-level
    /// structure (its mesh's, or its own when it is deformed) and, for a cut-out, its
    /// entry in `cutouts` (its instance's custom index; the others are opaque).
    occluders: Vec<(usize, u64, Option<u32>)>,
    /// The objects paths see that block no light (blended, transmissive, or casting no
    /// shadow), with their structures' addresses (their meshes', or their own when they
    /// are deformed): placed in the top level (instance mask [`SEEN_ONLY`]) after the
    /// occluders, in frames that path-trace only.
    seen_only: Vec<(usize, u64)>,
    /// What the shaders test the cut-outs' hits against.
    pub(crate) cutouts: TracedCutouts,
    /// What a path meets where it hits an instance (built for frames that path-trace:
    /// [`SceneStructure::prepare_surfaces`]).
    pub(crate) surfaces: std::sync::OnceLock<TracedSurfaces>,
    per_slot: Vec<Mutex<TopLevel>>,
}

impl SceneStructure {
    /// `scene`'s mesh structures (built now), its deformed objects' (`deform`: the
    /// scene's deform buffers, if it has deformed objects; built by each traced frame)
    /// and `slots` top-level structures for all of its objects.
    pub(crate) fn new(
        device: &Arc<Device>,
        scene: &Scene,
        deform: Option<&crate::deform::SceneDeform>,
        slots: usize,
    ) -> Result<Self, RenderError> {
        let limits = Limits::of(device);
        let sizes: Vec<(&str, u64)> = scene
            .meshes
            .iter()
            .map(|m| (m.name.as_str(), (m.indices.len() / 3) as u64))
            .collect();
        let (fits, _, warnings) = limits.fit(&sizes, 0);
        for warning in &warnings {
            log::warn!("{warning}");
        }
        let meshes = MeshStructures::build(device, scene, &fits)?;
        let capacity = (scene.objects.len() as u64).min(limits.instances) as u32;
        let per_slot = (0..slots)
            .map(|_| TopLevel::new(device, capacity).map(Mutex::new))
            .collect::<Result<Vec<_>, _>>()?;
        let mut deformed = Vec::new();
        let mut occluders = Vec::new();
        let mut seen_only = Vec::new();
        for (i, o) in scene.objects.iter().enumerate() {
            let see_through = scene
                .materials
                .get(o.material)
                .is_some_and(combustion_scene::Material::is_see_through);
            let posed_at =
                deform.and_then(|d| d.posed_offsets.get(i).copied().flatten().map(|at| (d, at)));
            if !fits[o.mesh] {
                continue;
            }
            // What blocks no light (see-through, or casting no shadow) is seen by paths alone.
            let paths_only = !o.casts_shadows || see_through;
            let list = if paths_only {
                &mut seen_only
            } else {
                &mut occluders
            };
            match posed_at {
                Some((deform, offset)) => {
                    if let Some(structure) =
                        DeformedStructure::new(device, scene, (i, paths_only), deform, offset)?
                    {
                        list.push((i, structure.structure.address));
                        deformed.push(structure);
                    }
                }
                None => {
                    if let Some(structure) = meshes.of(o.mesh) {
                        list.push((i, structure.address));
                    }
                }
            }
        }
        let (_, kept, warnings) = limits.fit(&[], occluders.len());
        for warning in &warnings {
            log::warn!("{warning}");
        }
        occluders.truncate(kept);
        seen_only.truncate(capacity as usize - occluders.len().min(capacity as usize));
        let objects: Vec<usize> = occluders.iter().map(|&(object, _)| object).collect();
        let (entries, cutouts) = TracedCutouts::of(device, scene, &objects)?;
        let occluders = occluders
            .into_iter()
            .zip(entries)
            .map(|((object, address), entry)| (object, address, entry))
            .collect();
        Ok(Self {
            meshes,
            deformed,
            deformed_pose: Mutex::new(None),
            occluders,
            seen_only,
            cutouts,
            surfaces: std::sync::OnceLock::new(),
            per_slot,
        })
    }

    /// Builds the table of what each instance's hits meet ([`TracedSurfaces`]) if it is
    /// not built yet (at upload or when the shading changes: never in a frame); the
    /// bytes it added.
    pub(crate) fn prepare_surfaces(
        &self,
        device: &Arc<Device>,
        scene: &Scene,
    ) -> Result<u64, RenderError> {
        if self.surfaces.get().is_some() {
            return Ok(0);
        }
        let objects: Vec<usize> = self
            .occluders
            .iter()
            .map(|&(o, _, _)| o)
            .chain(self.seen_only.iter().map(|&(o, _)| o))
            .collect();
        let posed: Vec<(usize, u64)> = self
            .deformed
            .iter()
            .map(|d| (d.object, d.vertices_at))
            .collect();
        let surfaces = TracedSurfaces::new(device, scene, &objects, &posed)?;
        let bytes = surfaces.bytes();
        // Set once: checked unset above, and only the renderer's `&mut self` paths call.
        let _ = self.surfaces.set(surfaces);
        // The deformed objects only paths meet are built by the next traced frame.
        *self.deformed_pose.lock().unwrap_or_else(|p| p.into_inner()) = None;
        Ok(bytes)
    }

    /// Slot `slot`'s top-level structure (what its frames' ray queries trace, once built
    /// by [`SceneStructure::record_build`]).
    pub(crate) fn top_level(&self, slot: usize) -> vk::AccelerationStructureKHR {
        self.per_slot[slot]
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .handle()
    }

    /// The bytes it holds: the meshes' and deformed objects' structures, and each slot's
    /// top-level structure with its instances and scratch.
    pub(crate) fn bytes(&self) -> u64 {
        self.meshes.bytes()
            + self.cutouts.bytes()
            + self
                .deformed
                .iter()
                .map(DeformedStructure::bytes)
                .sum::<u64>()
            + self
                .per_slot
                .iter()
                .map(|top| top.lock().unwrap_or_else(|p| p.into_inner()).bytes())
                .sum::<u64>()
            + self.surfaces.get().map_or(0, TracedSurfaces::bytes)
    }

    /// How many frame slots it has a top-level structure for.
    pub(crate) fn slots(&self) -> usize {
        self.per_slot.len()
    }

    /// Records the builds of the deformed objects' structures (from the posed vertices
    /// the frame's deform pass wrote; only when `pose`, the frame's pose digest, differs
    /// from the one they were last built in) and of slot `slot`'s top-level structure over
    /// the scene's occluders, each placed by `transform` (an object's world transform this
    /// frame), then a barrier that makes it visible to ray queries — once per frame
    /// (`frame`: the frame's number; a second pass of the same frame finds it built);
    /// returns the structure. The slot's previous frame must have completed (its
    /// instances are rewritten now).
    pub(crate) fn record_build(
        &self,
        device: &Device,
        cmd: vk::CommandBuffer,
        (slot, frame, pose): (usize, u64, u64),
        transform: impl Fn(usize) -> glam::Mat4,
    ) -> vk::AccelerationStructureKHR {
        let functions = device
            .acceleration_structure()
            .expect("a scene structure exists only on a device with ray queries");
        let mut top = self.per_slot[slot]
            .lock()
            .unwrap_or_else(|p| p.into_inner());
        if top.built_for == frame {
            return top.handle();
        }
        top.built_for = frame;
        let mut deformed_pose = self.deformed_pose.lock().unwrap_or_else(|p| p.into_inner());
        if *deformed_pose != Some(pose) {
            let paths = self.surfaces.get().is_some();
            let built: Vec<&DeformedStructure> = self
                .deformed
                .iter()
                .filter(|d| paths || !d.paths_only)
                .collect();
            record_deformed_builds(device, functions, cmd, &built);
            *deformed_pose = Some(pose);
        }
        let instances: Vec<vk::AccelerationStructureInstanceKHR> = self
            .occluders
            .iter()
            .map(|&(object, address, cutout)| {
                // A cut-out's hits are tested (custom index: its entry); the rest opaque.
                let (custom_index, flags) = match cutout {
                    Some(entry) => (entry, vk::GeometryInstanceFlagsKHR::FORCE_NO_OPAQUE),
                    None => (0, vk::GeometryInstanceFlagsKHR::FORCE_OPAQUE),
                };
                placed_instance(transform(object), (custom_index, OCCLUDES), flags, address)
            })
            .chain(
                self.seen_only
                    .iter()
                    .filter(|_| self.surfaces.get().is_some())
                    .map(|&(object, address)| {
                        let flags = vk::GeometryInstanceFlagsKHR::FORCE_OPAQUE;
                        placed_instance(transform(object), (0, SEEN_ONLY), flags, address)
                    }),
            )
            .take(top.capacity as usize)
            .collect();
        top.record(device, functions, cmd, &instances);
        top.handle()
    }
}

#[cfg(test)]
mod tests {
    use super::Limits;

    /// A mesh with more triangles than a structure holds is left out, and instances past
    /// the top level's count are dropped, each said in one line naming the limit; what
    /// fits is kept.
    #[test]
    fn what_exceeds_the_devices_limits_is_left_out_and_said() {
        let limits = Limits {
            triangles: 100,
            instances: 3,
        };
        let (fits, kept, warnings) = limits.fit(&[("small", 100), ("large", 101)], 5);
        assert_eq!(fits, [true, false]);
        assert_eq!(kept, 3);
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert!(
            warnings[0].starts_with("mesh `large`: 101 triangles") && warnings[0].contains("(100)"),
            "{}",
            warnings[0]
        );
        assert!(
            warnings[1].starts_with("5 objects occlude") && warnings[1].contains("last 2"),
            "{}",
            warnings[1]
        );
        assert!(warnings.iter().all(|w| !w.contains('\n')));
        let (fits, kept, warnings) = limits.fit(&[("small", 3)], 3);
        assert_eq!((fits, kept), (vec![true], 3));
        assert!(warnings.is_empty());
    }
}
