//! A scene's data on the GPU: one vertex and one index buffer for all meshes, the
//! textures, the object table and the material table. Uploaded once, drawn many times;
//! edited between frames by rebuilding only the parts an edit touches (lights are each
//! frame's own, in `FrameInputs`).

use std::sync::Arc;

use combustion_scene::Scene;
use combustion_vk::{vk, Buffer, DescriptorSetLayout, Device};

use crate::gpu_types::{conductor_from_base_color_table, material_table, GpuObject, GpuVertex};
use crate::textures::SceneTextures;
use crate::RenderError;

/// One draw of the G-buffer pass (object i of the object table).
#[derive(Clone, Copy, Debug)]
pub struct Draw {
    pub first_index: u32,
    pub index_count: u32,
    pub vertex_offset: i32,
}

/// A validated scene uploaded to the GPU.
pub struct GpuScene {
    pub(crate) vertices: Buffer,
    /// Every vertex's second coordinate set (the TEXTURE_TRANSFORMS variant's stream).
    pub(crate) uv1: Buffer,
    pub(crate) indices: Buffer,
    pub(crate) objects: Buffer,
    pub(crate) materials: Buffer,
    /// `conductor_from_base_color_table()`, or one dummy entry when no material needs it.
    pub(crate) conductor_table: Buffer,
    pub(crate) textures: SceneTextures,
    /// Per mesh: its range in the vertex and index buffers.
    mesh_ranges: Vec<Draw>,
    pub(crate) draws: Vec<Draw>,
    /// Per draw: render back faces too (double-sided material).
    pub(crate) double_sided: Vec<bool>,
    /// Per draw: the material (index into `textures.material_sets`).
    pub(crate) draw_materials: Vec<usize>,
    /// Shader features this scene needs (selects the pipeline variant).
    pub(crate) variant: crate::ShaderVariant,
    /// Its environment, baked ([`crate::Renderer::upload`]; None without one).
    pub environment: Option<crate::environment::GpuEnvironment>,
    /// The scene as uploaded. Its camera and lights are what [`crate::FrameInputs::of_scene`]
    /// gives; each frame may bring its own.
    pub scene: Scene,
}

/// What [`crate::Renderer::edit_scene`] rebuilt. Parts not named were kept as they were.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneEditReport {
    /// The vertex and index buffers (meshes changed).
    pub geometry: bool,
    /// The textures and the per-material texture sets (images, textures or samplers changed).
    pub textures: bool,
    /// The object and material tables and the draw list (always: they are small).
    pub tables: bool,
    /// Pipelines built because the edit needs a shader feature the renderer had not built.
    pub pipelines_built: u64,
    /// The environment's cubes and tables, baked again (the environment, or the material
    /// table the bake reads, changed).
    pub environment: bool,
}

/// The shader features `scene` needs.
pub(crate) fn scene_variant(scene: &Scene) -> crate::ShaderVariant {
    crate::ShaderVariant {
        emissive: scene
            .materials
            .iter()
            .any(|m| m.emissive_strength > 0.0 && m.emissive_factor.iter().any(|&e| e > 0.0)),
        texture_transforms: scene.materials.iter().any(|m| {
            m.texture_slots()
                .iter()
                .any(|(_, t)| t.is_some_and(|t| t.maps_coordinates()))
        }),
        // The Fresnel model and the debug views are the renderer's settings.
        fresnel: crate::FresnelModel::Full,
        debug_views: false,
        features: crate::LightingFeatures::of(scene),
        floor: None,
        masking: crate::Masking::HeightCorrelated,
        distribution: crate::Distribution::Ggx,
        environment: scene.environment.is_some(),
        occlusion: scene.environment.is_some()
            && scene
                .materials
                .iter()
                .any(|m| m.occlusion_texture.is_some() && m.occlusion_strength > 0.0),
        // A renderer setting.
        energy_compensation: false,
    }
}

/// The vertex and index buffers of every mesh, and each mesh's range in them.
struct Geometry {
    vertices: Buffer,
    uv1: Buffer,
    indices: Buffer,
    mesh_ranges: Vec<Draw>,
}

impl Geometry {
    fn new(device: &Arc<Device>, scene: &Scene) -> Result<Self, RenderError> {
        let mut vertices: Vec<GpuVertex> = Vec::new();
        let mut uv1: Vec<[f32; 2]> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut mesh_ranges = Vec::with_capacity(scene.meshes.len());
        for mesh in &scene.meshes {
            let vertex_offset = i32::try_from(vertices.len())
                .map_err(|_| RenderError::TooLarge("more than 2³¹ vertices".into()))?;
            mesh_ranges.push(Draw {
                first_index: indices.len() as u32,
                index_count: mesh.indices.len() as u32,
                vertex_offset,
            });
            vertices.extend(mesh.vertices.iter().map(GpuVertex::new));
            uv1.extend(mesh.vertices.iter().map(|v| v.uv1));
            indices.extend_from_slice(&mesh.indices);
        }
        Ok(Self {
            vertices: Buffer::with_data(
                device,
                "vertices",
                bytemuck::cast_slice(&vertices),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            uv1: Buffer::with_data(
                device,
                "vertex coordinate set 1",
                bytemuck::cast_slice(&uv1),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: Buffer::with_data(
                device,
                "indices",
                bytemuck::cast_slice(&indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            mesh_ranges,
        })
    }
}

/// The object and material tables, the conductor table, and the draw list.
struct Tables {
    objects: Buffer,
    materials: Buffer,
    conductor_table: Buffer,
    draws: Vec<Draw>,
    double_sided: Vec<bool>,
    draw_materials: Vec<usize>,
    variant: crate::ShaderVariant,
}

impl Tables {
    fn new(
        device: &Arc<Device>,
        scene: &Scene,
        mesh_ranges: &[Draw],
        textures: &SceneTextures,
    ) -> Result<Self, RenderError> {
        let objects: Vec<GpuObject> = scene.objects.iter().map(GpuObject::new).collect();
        let materials = material_table(scene, &textures.material_indices);
        let needs_table = scene.materials.iter().any(|m| m.conductor_from_base_color);
        let conductor_table: &[[f32; 2]] = if needs_table {
            conductor_from_base_color_table()
        } else {
            &[[1.0, 0.0]]
        };
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Self {
            objects: Buffer::with_data(
                device,
                "object table",
                bytemuck::cast_slice(&objects),
                storage,
            )?,
            materials: Buffer::with_data(
                device,
                "material table",
                bytemuck::cast_slice(&materials),
                storage,
            )?,
            conductor_table: Buffer::with_data(
                device,
                "conductor-from-base-colour table",
                bytemuck::cast_slice(conductor_table),
                storage,
            )?,
            draws: scene.objects.iter().map(|o| mesh_ranges[o.mesh]).collect(),
            double_sided: scene
                .objects
                .iter()
                .map(|o| scene.materials[o.material].double_sided)
                .collect(),
            draw_materials: scene.objects.iter().map(|o| o.material).collect(),
            variant: scene_variant(scene),
        })
    }
}

impl GpuScene {
    pub fn new(
        device: &Arc<Device>,
        scene: &Scene,
        material_set_layout: &DescriptorSetLayout,
    ) -> Result<Self, RenderError> {
        scene.validate()?;
        let geometry = Geometry::new(device, scene)?;
        let textures = SceneTextures::new(device, scene, material_set_layout)?;
        let tables = Tables::new(device, scene, &geometry.mesh_ranges, &textures)?;
        Ok(Self::assemble(geometry, textures, tables, scene.clone()))
    }

    fn assemble(geometry: Geometry, textures: SceneTextures, tables: Tables, scene: Scene) -> Self {
        Self {
            vertices: geometry.vertices,
            uv1: geometry.uv1,
            indices: geometry.indices,
            mesh_ranges: geometry.mesh_ranges,
            objects: tables.objects,
            materials: tables.materials,
            conductor_table: tables.conductor_table,
            textures,
            draws: tables.draws,
            double_sided: tables.double_sided,
            draw_materials: tables.draw_materials,
            variant: tables.variant,
            environment: None,
            scene,
        }
    }

    /// Builds what `next` needs that differs from this scene: new geometry if the meshes
    /// changed, new textures if the texture table changed, new tables always. Returns the
    /// edited scene and this one's replaced parts (to retire), or an error with this
    /// scene untouched.
    pub(crate) fn edited(
        &mut self,
        device: &Arc<Device>,
        next: Scene,
        material_set_layout: &DescriptorSetLayout,
    ) -> Result<(SceneEditReport, Vec<Box<dyn std::any::Any + Send>>), RenderError> {
        next.validate()?;
        let mut report = SceneEditReport {
            tables: true,
            ..SceneEditReport::default()
        };
        let geometry = if next.meshes != self.scene.meshes {
            report.geometry = true;
            Some(Geometry::new(device, &next)?)
        } else {
            None
        };
        let textures = if next.texture_table() != self.scene.texture_table() {
            report.textures = true;
            Some(SceneTextures::new(device, &next, material_set_layout)?)
        } else {
            None
        };
        let mesh_ranges = geometry
            .as_ref()
            .map_or(&self.mesh_ranges, |g| &g.mesh_ranges);
        let tables = Tables::new(
            device,
            &next,
            mesh_ranges,
            textures.as_ref().unwrap_or(&self.textures),
        )?;
        // Everything new is built: swap it in and hand back what it replaces.
        let mut retired: Vec<Box<dyn std::any::Any + Send>> = Vec::new();
        if let Some(g) = geometry {
            retired.push(Box::new(std::mem::replace(&mut self.vertices, g.vertices)));
            retired.push(Box::new(std::mem::replace(&mut self.uv1, g.uv1)));
            retired.push(Box::new(std::mem::replace(&mut self.indices, g.indices)));
            self.mesh_ranges = g.mesh_ranges;
        }
        if let Some(t) = textures {
            retired.push(Box::new(std::mem::replace(&mut self.textures, t)));
        }
        retired.push(Box::new(std::mem::replace(
            &mut self.objects,
            tables.objects,
        )));
        retired.push(Box::new(std::mem::replace(
            &mut self.materials,
            tables.materials,
        )));
        retired.push(Box::new(std::mem::replace(
            &mut self.conductor_table,
            tables.conductor_table,
        )));
        self.draws = tables.draws;
        self.double_sided = tables.double_sided;
        self.draw_materials = tables.draw_materials;
        self.variant = tables.variant;
        self.scene = next;
        Ok((report, retired))
    }
}
