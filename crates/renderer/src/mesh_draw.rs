//! The scene's objects as draws, for every pass that rasterises the scene: the object
//! iteration in the object table's order, each mesh's vertex streams and indices bound
//! when they change, the cull mode of each object's material (double-sided or not), and
//! one instanced indexed draw per run of consecutive objects of one mesh and material.
//! The G-buffer pass uses it; a depth-only pass (a shadow map) uses it too, with its own
//! pipeline and per-draw push constants.

use combustion_vk::ash;
use combustion_vk::{vk, Pipeline, PipelineLayout};

use combustion_scene::Topology;

use crate::gpu_types::GBufferPush;
use crate::scene_upload::GpuScene;

/// Which faces of each object a pass rasterises.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Faces {
    /// As its material says: front faces only, both for a double-sided material (what
    /// the camera sees).
    OfMaterial,
    /// Both faces of every object (shadow casters: a face blocks light either way).
    Both,
    /// Back faces only, double-sided or not (the far sides of transmissive volumes).
    Back,
}

/// The vertex streams besides the first (`GpuVertex`) that [`draw_objects`] binds for
/// every mesh: the second coordinate set and the colours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ExtraStream {
    /// Stream 1: `Vertex::uv1`, two f32 per vertex.
    SecondCoordinates,
    /// Stream 2: `Vertex::color`, four f32 per vertex (a mesh without colours binds
    /// another buffer there, see [`draw_objects`]).
    Colors,
}

impl ExtraStream {
    /// The binding and the attribute a pipeline declares to read this stream at shader
    /// input `location`.
    pub(crate) fn declare(
        self,
        location: u32,
        bindings: &mut Vec<vk::VertexInputBindingDescription>,
        attributes: &mut Vec<vk::VertexInputAttributeDescription>,
    ) {
        let (binding, format, stride) = match self {
            Self::SecondCoordinates => (1, vk::Format::R32G32_SFLOAT, 8),
            Self::Colors => (2, vk::Format::R32G32B32A32_SFLOAT, 16),
        };
        bindings.push(vk::VertexInputBindingDescription {
            binding,
            stride,
            input_rate: vk::VertexInputRate::VERTEX,
        });
        attributes.push(vk::VertexInputAttributeDescription {
            location,
            binding,
            format,
            offset: 0,
        });
    }
}

/// A pipeline that rasterises the scene's objects with depth (written, `DEPTH_FORMAT`)
/// into one colour target of `color_format`, reading the vec3 attributes of the first
/// vertex stream (`GpuVertex`) at `attributes` (shader location, byte offset), with push
/// constants of `push_size` bytes to `push_stages`: the back faces' pass and the motion
/// pass.
#[allow(clippy::too_many_arguments)]
pub(crate) fn first_stream_pipeline(
    device: &std::sync::Arc<combustion_vk::Device>,
    compiler: &combustion_vk::ShaderCompiler,
    cache: &combustion_vk::PipelineCache,
    set_layout: &combustion_vk::DescriptorSetLayout,
    (vertex_shader, fragment_shader): (&str, &str),
    (push_stages, push_size): (vk::ShaderStageFlags, u32),
    attributes: &[(u32, usize)],
    color_format: vk::Format,
) -> Result<(PipelineLayout, Pipeline), crate::error::RenderError> {
    use combustion_vk::{ShaderModule, ShaderStage};
    let push = [vk::PushConstantRange {
        stage_flags: push_stages,
        offset: 0,
        size: push_size,
    }];
    let layout = PipelineLayout::new(device, &[set_layout], &push)?;
    let module = |file: &str, stage| -> Result<ShaderModule, crate::error::RenderError> {
        Ok(ShaderModule::new(
            device,
            &compiler.compile(file, stage, &[])?,
            stage,
        )?)
    };
    let vertex = module(vertex_shader, ShaderStage::Vertex)?;
    let fragment = module(fragment_shader, ShaderStage::Fragment)?;
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<crate::gpu_types::GpuVertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let attributes: Vec<_> = attributes
        .iter()
        .map(|&(location, offset)| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: offset as u32,
        })
        .collect();
    let pipeline = Pipeline::graphics(
        device,
        &combustion_vk::GraphicsPipelineDesc {
            vertex: &vertex,
            fragment: &fragment,
            layout: &layout,
            vertex_bindings: &bindings,
            vertex_attributes: &attributes,
            color_formats: &[color_format],
            depth_format: Some(crate::gbuffer::DEPTH_FORMAT),
            depth_write: true,
            depth_compare: vk::CompareOp::LESS,
            blend: combustion_vk::ColorBlend::Replace,
            cache: Some(cache),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
        },
    )?;
    Ok((layout, pipeline))
}

/// What a pass learns of each object before it is drawn.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObjectDraw {
    /// The object's index in the object table (what shaders index it by).
    pub object_index: u32,
    /// Its material's index (the scene's material table and texture sets).
    pub material: usize,
    /// Its material is a cut-out (`AlphaMode::Mask`): drawn by a pass's alpha-testing
    /// pipeline.
    pub masked: bool,
    /// Its material is blended (`AlphaMode::Blend`) or transmissive: drawn by the
    /// forward pass only.
    pub forward: bool,
    /// What its mesh's indices make: points and lines are drawn by the G-buffer pass's
    /// pipelines for them, in a round of their own ([`TwoRounds::record_strokes`]), and
    /// by no other pass.
    pub topology: Topology,
}

impl ObjectDraw {
    /// Whether a pass that draws its objects in two rounds, the opaque ones and then the
    /// cut-outs through its alpha-testing pipeline (if it has one: `cut_out_pipeline`),
    /// draws this object in the cut-out round (`cut_out_round`) or the first. Without the
    /// pipeline, cut-outs are drawn opaque in the first round. Blended and transmissive
    /// objects are in neither (the forward pass draws them), nor are points and lines.
    pub(crate) fn in_round(&self, cut_out_round: bool, cut_out_pipeline: bool) -> bool {
        if self.forward || self.topology != Topology::Triangles {
            false
        } else if cut_out_round {
            self.masked
        } else {
            !self.masked || !cut_out_pipeline
        }
    }
}

/// Records `scene`'s objects into `cmd` (recording, inside a rendering instance whose
/// pipeline reads vertex stream 0 — and stream 1, the second coordinate set, and stream
/// 2, the colours, if it declares them), culling the faces `faces` says: the objects
/// `keep` keeps, consecutive ones of one mesh and one material (an instanced glTF node's
/// copies, a mesh placed many times) in one instanced draw whose instance i is object
/// `first + i` (the vertex stages index the object table by the pushed object index plus
/// `gl_InstanceIndex`). `before_draw` runs before each draw with its first object, to bind
/// what the pass binds per material and push its constants. A pass that draws the opaque
/// and the cut-out objects with different pipelines calls this once for each.
pub(crate) fn draw_objects(
    raw: &ash::Device,
    cmd: vk::CommandBuffer,
    scene: &GpuScene,
    faces: Faces,
    mut keep: impl FnMut(ObjectDraw) -> bool,
    mut before_draw: impl FnMut(ObjectDraw),
) {
    let count = scene.draw_meshes.len();
    let object = |i: usize| ObjectDraw {
        object_index: i as u32,
        material: scene.draw_materials[i],
        masked: scene.masked[i],
        forward: scene.forward[i],
        topology: scene.gpu.meshes[scene.draw_meshes[i]].topology,
    };
    // A deformed object draws its own posed vertices: alone.
    let posed = |i: usize| scene.gpu.deform.as_ref().and_then(|d| d.posed_offsets[i]);
    let same_draw = |a: usize, b: usize| {
        scene.draw_meshes[a] == scene.draw_meshes[b]
            && scene.draw_materials[a] == scene.draw_materials[b]
            && posed(a).is_none()
            && posed(b).is_none()
    };
    let mut bound_mesh = None;
    let mut first = 0;
    while first < count {
        if !keep(object(first)) {
            first += 1;
            continue;
        }
        let mut end = first + 1;
        while end < count && same_draw(first, end) && keep(object(end)) {
            end += 1;
        }
        before_draw(object(first));
        draw_run(raw, cmd, scene, faces, first..end, &mut bound_mesh);
        first = end;
    }
}

/// Records one draw of the objects `run` (consecutive, of one mesh and one material):
/// binds their mesh's streams and indices unless `bound_mesh` says they are bound, sets
/// the cull mode `faces` and their material say, and draws the mesh `run.len()` times
/// (instance i is object `run.start + i`).
fn draw_run(
    raw: &ash::Device,
    cmd: vk::CommandBuffer,
    scene: &GpuScene,
    faces: Faces,
    run: std::ops::Range<usize>,
    bound_mesh: &mut Option<(usize, Option<u64>)>,
) {
    let mesh = scene.draw_meshes[run.start];
    let buffers = &scene.gpu.meshes[mesh];
    // Stream 0: a deformed object's posed vertices, else its mesh's.
    let deform = scene.gpu.deform.as_ref();
    let posed = deform.and_then(|d| d.posed_offsets[run.start]);
    let (stream0, offset0) = match (deform, posed) {
        (Some(d), Some(offset)) => (&d.posed, offset),
        _ => (&buffers.vertices, 0),
    };
    // SAFETY: recording state (the caller's); the buffers live as long as the scene,
    // which outlives the frame (a dropped scene is retired, not freed).
    unsafe {
        if *bound_mesh != Some((mesh, posed)) {
            // Stream 2, the colours: a mesh without them binds its first stream there (in
            // range: 48 bytes per vertex against the 16 read), which the vertex stage does
            // not use (the object's has-colours flag is 0).
            let colors = buffers.colors.as_ref().unwrap_or(&buffers.vertices);
            raw.cmd_bind_vertex_buffers(
                cmd,
                0,
                &[stream0.raw(), buffers.uv1.raw(), colors.raw()],
                &[offset0, 0, 0],
            );
            raw.cmd_bind_index_buffer(cmd, buffers.indices.raw(), 0, vk::IndexType::UINT32);
            *bound_mesh = Some((mesh, posed));
        }
        raw.cmd_set_cull_mode(
            cmd,
            match faces {
                Faces::Back => vk::CullModeFlags::FRONT,
                Faces::Both => vk::CullModeFlags::NONE,
                Faces::OfMaterial if scene.double_sided[run.start] => vk::CullModeFlags::NONE,
                Faces::OfMaterial => vk::CullModeFlags::BACK,
            },
        );
        raw.cmd_draw_indexed(cmd, buffers.index_count, run.len() as u32, 0, 0, 0);
    }
}

/// The objects the forward pass draws (blended, `AlphaMode::Blend`, and transmissive
/// ones) in the order it draws them, back to front: by the distance from `eye` to the centre of each object's
/// world-space box, farthest first (ties: the object table's order). Per object, not per
/// triangle: objects that interpenetrate, a large object around a smaller one, and the
/// faces of one mesh that overlap on screen (a double-sided or concave blended mesh) are
/// not sorted against each other.
pub(crate) fn back_to_front(
    scene: &GpuScene,
    bounds: &[Option<(glam::Vec3, glam::Vec3)>],
    eye: glam::Vec3,
) -> Vec<usize> {
    let distance = |i: usize| bounds[i].map_or(0.0, |(min, max)| eye.distance((min + max) * 0.5));
    let mut order: Vec<(f32, usize)> = (0..scene.forward.len())
        .filter(|&i| scene.forward[i])
        .map(|i| (distance(i), i))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    order.into_iter().map(|(_, i)| i).collect()
}

/// Records `objects` (object-table indices) one draw each, in that order, with the faces
/// `faces` says; `before_draw` runs before each (recording state, inside a rendering
/// instance whose pipeline reads the streams [`draw_objects`] binds).
pub(crate) fn draw_in_order(
    raw: &ash::Device,
    cmd: vk::CommandBuffer,
    scene: &GpuScene,
    faces: Faces,
    objects: &[usize],
    mut before_draw: impl FnMut(usize),
) {
    let mut bound_mesh = None;
    for &i in objects {
        before_draw(i);
        draw_run(raw, cmd, scene, faces, i..i + 1, &mut bound_mesh);
    }
}

/// How a pass that rasterises the scene draws it in two rounds: the opaque objects with
/// the pipeline bound when it is called, then the cut-outs (`AlphaMode::Mask`) with
/// `cut_out_pipeline` (without one, as opaque in the first round). Both pipelines share
/// `layout`: set 1 is each object's material's texture set (bound in the cut-out round,
/// and in the first where `textures_in_opaque_round`), and the vertex push constants are
/// a [`GBufferPush`] of `view_projection` and the object's index.
pub(crate) struct TwoRounds<'a> {
    pub layout: &'a PipelineLayout,
    pub cut_out_pipeline: Option<&'a Pipeline>,
    pub view_projection: glam::Mat4,
    pub textures_in_opaque_round: bool,
}

impl TwoRounds<'_> {
    /// Records the two rounds of `scene`'s objects that `keep` keeps, culling the faces
    /// `faces` says (recording state, inside the pass's rendering instance, its set 0
    /// bound).
    pub(crate) fn record(
        &self,
        raw: &ash::Device,
        cmd: vk::CommandBuffer,
        scene: &GpuScene,
        faces: Faces,
        mut keep: impl FnMut(ObjectDraw) -> bool,
    ) {
        let mut bound_material = None;
        for cut_out_round in [false, true] {
            if cut_out_round {
                let Some(pipeline) = self.cut_out_pipeline else {
                    break;
                };
                // SAFETY: recording state (the caller's).
                unsafe {
                    raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw())
                };
            }
            draw_objects(
                raw,
                cmd,
                scene,
                faces,
                |object| {
                    object.in_round(cut_out_round, self.cut_out_pipeline.is_some()) && keep(object)
                },
                |object| {
                    self.prepare_draw(
                        raw,
                        cmd,
                        scene,
                        object,
                        cut_out_round || self.textures_in_opaque_round,
                        &mut bound_material,
                    )
                },
            );
        }
    }

    /// Records `scene`'s points and lines (recording state, inside the G-buffer pass's
    /// rendering instance, its set 0 bound), after the surfaces: the objects of each
    /// topology of `pipelines` that has a pipeline, with it, opaque (a cut-out's alpha is
    /// not tested; blended and transmissive materials are drawn opaque too), textures
    /// bound. Leaves the last pipeline it used bound.
    pub(crate) fn record_strokes(
        &self,
        raw: &ash::Device,
        cmd: vk::CommandBuffer,
        scene: &GpuScene,
        pipelines: [(Topology, Option<&Pipeline>); 2],
    ) {
        let mut bound_material = None;
        for (topology, pipeline) in pipelines {
            let Some(pipeline) = pipeline else {
                continue;
            };
            // SAFETY: recording state (the caller's).
            unsafe { raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw()) };
            draw_objects(
                raw,
                cmd,
                scene,
                Faces::Both,
                |object| object.topology == topology,
                |object| self.prepare_draw(raw, cmd, scene, object, true, &mut bound_material),
            );
        }
    }

    /// Before `object`'s draw: binds its material's texture set (set 1) when
    /// `bind_textures` and `bound_material` is another, and pushes the view-projection
    /// and its index.
    fn prepare_draw(
        &self,
        raw: &ash::Device,
        cmd: vk::CommandBuffer,
        scene: &GpuScene,
        object: ObjectDraw,
        bind_textures: bool,
        bound_material: &mut Option<usize>,
    ) {
        let push = GBufferPush {
            view_projection: self.view_projection.to_cols_array(),
            object_index: object.object_index,
            _pad: [0; 3],
        };
        // SAFETY: recording state (the caller's); the material sets live as long as the
        // scene, which outlives the frame.
        unsafe {
            if bind_textures && *bound_material != Some(object.material) {
                raw.cmd_bind_descriptor_sets(
                    cmd,
                    vk::PipelineBindPoint::GRAPHICS,
                    self.layout.raw(),
                    1,
                    &[scene.gpu.textures.material_sets[object.material]],
                    &[],
                );
                *bound_material = Some(object.material);
            }
            raw.cmd_push_constants(
                cmd,
                self.layout.raw(),
                vk::ShaderStageFlags::VERTEX,
                0,
                bytemuck::bytes_of(&push),
            );
        }
    }
}
