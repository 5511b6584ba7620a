//! A scene's data on the GPU: one vertex and one index buffer for all meshes, the
//! object table, the material table and the light list. Uploaded once, drawn many times.

use std::sync::Arc;

use combustion_scene::Scene;
use combustion_vk::{vk, Buffer, DescriptorSetLayout, Device};

use crate::gpu_types::{conductor_from_base_color_table, material_table, GpuObject};
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
    pub(crate) indices: Buffer,
    pub(crate) objects: Buffer,
    pub(crate) materials: Buffer,
    /// `conductor_from_base_color_table()`, or one dummy entry when no material needs it.
    pub(crate) conductor_table: Buffer,
    pub(crate) textures: SceneTextures,
    pub(crate) draws: Vec<Draw>,
    /// Per draw: render back faces too (double-sided material).
    pub(crate) double_sided: Vec<bool>,
    /// Per draw: the material (index into `textures.material_sets`).
    pub(crate) draw_materials: Vec<usize>,
    /// Shader features this scene needs (selects the pipeline variant).
    pub(crate) variant: crate::ShaderVariant,
    /// The scene as uploaded. Its camera and lights are what [`crate::FrameInputs::of_scene`]
    /// gives; each frame may bring its own.
    pub scene: Scene,
}

impl GpuScene {
    pub fn new(
        device: &Arc<Device>,
        scene: &Scene,
        material_set_layout: &DescriptorSetLayout,
    ) -> Result<Self, RenderError> {
        scene.validate()?;
        let mut vertices = Vec::new();
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
            vertices.extend_from_slice(&mesh.vertices);
            indices.extend_from_slice(&mesh.indices);
        }
        let draws = scene.objects.iter().map(|o| mesh_ranges[o.mesh]).collect();
        let objects: Vec<GpuObject> = scene.objects.iter().map(GpuObject::new).collect();
        let textures = SceneTextures::new(device, scene, material_set_layout)?;
        let materials = material_table(scene, &textures.material_indices);
        let needs_table = scene.materials.iter().any(|m| m.conductor_from_base_color);
        let conductor_table: &[[f32; 2]] = if needs_table {
            conductor_from_base_color_table()
        } else {
            &[[1.0, 0.0]]
        };
        let variant = crate::ShaderVariant {
            emissive: scene
                .materials
                .iter()
                .any(|m| m.emissive_strength > 0.0 && m.emissive_factor.iter().any(|&e| e > 0.0)),
            // The Fresnel model is the renderer's setting, applied at render time.
            schlick: false,
        };
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Self {
            vertices: Buffer::with_data(
                device,
                "vertices",
                bytemuck::cast_slice(&vertices),
                vk::BufferUsageFlags::VERTEX_BUFFER,
            )?,
            indices: Buffer::with_data(
                device,
                "indices",
                bytemuck::cast_slice(&indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
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
            textures,
            double_sided: scene
                .objects
                .iter()
                .map(|o| scene.materials[o.material].double_sided)
                .collect(),
            draw_materials: scene.objects.iter().map(|o| o.material).collect(),
            variant,
            draws,
            scene: scene.clone(),
        })
    }
}
