//! A scene's data on the GPU: vertex and index buffers per mesh, the textures, the
//! object table and the material table. Uploaded once, drawn many times; edited between
//! frames by uploading only the meshes and images an edit adds or changes and rebuilding
//! the small tables (lights are each frame's own, in `FrameInputs`).

use std::mem::ManuallyDrop;
use std::sync::Arc;

use combustion_scene::{Material, Mesh, Scene, Topology};
use combustion_vk::{vk, Buffer, DescriptorSetLayout, Device};

use crate::error::RenderError;
use crate::gpu_types::{
    conductor_from_base_color_table, material_table, GpuMaterial, GpuObject, GpuVertex,
};
use crate::retire::{RetireQueue, Retired};
use crate::scene_edit::{MaterialId, MeshId, ObjectId, SceneIds};
use crate::textures::SceneTextures;

/// A validated scene uploaded to the GPU by one [`crate::Renderer`]
/// ([`crate::Renderer::upload`]), drawn by that renderer's frames.
///
/// Dropping it is safe at any time: its buffers, images and environment go to the
/// renderer's retire queue and are freed only once every frame recorded before the drop
/// has completed (when the renderer next reuses that frame's slot), never while the GPU
/// may still read them.
pub struct GpuScene {
    /// What the GPU reads; handed to the retire queue on drop.
    pub(crate) gpu: ManuallyDrop<SceneResources>,
    /// Per draw (object i of the object table): its mesh (index into `gpu.meshes`).
    pub(crate) draw_meshes: Vec<usize>,
    /// Per draw: render back faces too (double-sided material).
    pub(crate) double_sided: Vec<bool>,
    /// Per draw: a cut-out material (`AlphaMode::Mask`), drawn by the passes' alpha-testing
    /// pipelines after the opaque draws.
    pub(crate) masked: Vec<bool>,
    /// Per draw: drawn by the forward pass only (not into the G-buffer, casting no
    /// shadow): a blended (`AlphaMode::Blend`) or transmissive material.
    pub(crate) forward: Vec<bool>,
    /// The draws whose material is transmissive with a volume (KHR_materials_volume),
    /// in object-table order: what the back faces pass draws.
    pub(crate) volumes: Vec<usize>,
    /// Per draw: the object casts shadows (drawn into shadow maps).
    pub(crate) casts_shadows: Vec<bool>,
    /// Per draw: the material (index into `textures.material_sets`).
    pub(crate) draw_materials: Vec<usize>,
    /// Shader features this scene needs (selects the pipeline variant).
    pub(crate) variant: crate::variant::ShaderVariant,
    /// The shader features of its frames lit by a [`crate::FrameEnvironment`].
    pub(crate) lit_variant: crate::variant::ShaderVariant,
    /// Whether a [`crate::FrameEnvironment`] was baked for it: then
    /// [`crate::Renderer::prepare`] and edits build `lit_variant`'s pipelines too.
    pub(crate) frame_environments: std::sync::atomic::AtomicBool,
    /// Its material table as the environment bake reads it (what a
    /// [`crate::FrameEnvironment`] must have been baked for).
    pub(crate) bake_materials: Vec<u8>,
    /// The world-space bounds of its objects ([`Scene::world_bounds`]), kept so that a
    /// frame's shadow cascades need not walk the vertices.
    pub(crate) world_bounds: Option<(glam::Vec3, glam::Vec3)>,
    /// Each object's world-space box (shadow casters are culled by them).
    pub(crate) object_bounds: Vec<Option<(glam::Vec3, glam::Vec3)>>,
    /// Each mesh's box in its own space (a posed frame places them).
    pub(crate) mesh_bounds: Vec<Option<(glam::Vec3, glam::Vec3)>>,
    /// Whether each mesh has vertex colours ([`Mesh::has_colors`], a walk over its
    /// vertices): found once here, read by every object table made from the scene.
    pub(crate) mesh_colors: Vec<bool>,
    /// Unique to this scene's geometry as uploaded or last edited (no two scenes, and no
    /// two states of one, share one): shadow maps rendered from it are kept while it
    /// and their placement stay the same.
    pub(crate) geometry_version: u64,
    /// The scene as uploaded (or last edited).
    scene: Scene,
    /// The handles of its objects, materials and meshes.
    pub(crate) ids: SceneIds,
    /// The uploading renderer's retire queue.
    retire: Arc<RetireQueue>,
}

/// The GPU resources of a [`GpuScene`].
pub(crate) struct SceneResources {
    /// Per mesh of the scene: its buffers.
    pub(crate) meshes: Vec<Arc<MeshBuffers>>,
    pub(crate) objects: Buffer,
    pub(crate) materials: Buffer,
    /// `conductor_from_base_color_table()`, or one dummy entry when no material needs it.
    pub(crate) conductor_table: Buffer,
    pub(crate) textures: SceneTextures,
    /// Its environment, baked ([`crate::Renderer::upload`]; None without one).
    pub(crate) environment: Option<crate::environment::GpuEnvironment>,
    /// Its deformed objects' buffers (None without morphed or skinned objects).
    pub(crate) deform: Option<crate::deform::SceneDeform>,
    /// Its acceleration structures, for frames with a pass that traces rays (built by
    /// `Renderer::upload`, `prepare` or `set_shading` when such a pass is asked for, on a
    /// device with ray queries; unset otherwise).
    pub(crate) structures: std::sync::OnceLock<crate::accel::SceneStructure>,
}

impl Drop for GpuScene {
    fn drop(&mut self) {
        // SAFETY: `gpu` is taken once, here, and never touched again.
        let gpu = unsafe { ManuallyDrop::take(&mut self.gpu) };
        self.retire.push(Box::new(gpu));
    }
}

impl GpuScene {
    /// The scene as uploaded, or as the last [`crate::Renderer::edit_scene`] left it.
    /// Its camera and lights are what [`crate::FrameInputs::of_scene`] gives; each
    /// frame may bring its own.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Its environment as baked for its materials (None without one).
    pub fn environment(&self) -> Option<&crate::environment::GpuEnvironment> {
        self.gpu.environment.as_ref()
    }

    /// The handles of the scene's objects, index for index with `scene().objects`.
    pub fn object_ids(&self) -> &[ObjectId] {
        &self.ids.objects
    }

    /// The handles of the scene's materials, index for index.
    pub fn material_ids(&self) -> &[MaterialId] {
        &self.ids.materials
    }

    /// The handles of the scene's meshes, index for index.
    pub fn mesh_ids(&self) -> &[MeshId] {
        &self.ids.meshes
    }

    /// Whether `queue` is the retire queue of the renderer that uploaded this scene.
    pub(crate) fn belongs_to(&self, queue: &Arc<RetireQueue>) -> bool {
        Arc::ptr_eq(&self.retire, queue)
    }
}

/// What [`crate::Renderer::edit_scene`] rebuilt. Parts not named were kept as they were.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneEditReport {
    /// The mesh list (meshes changed).
    pub geometry: bool,
    /// Meshes uploaded: those the scene did not have before (a mesh kept unchanged, at
    /// any index, keeps its buffers).
    pub meshes_uploaded: usize,
    /// The per-material texture sets and samplers (the materials' textures changed).
    pub textures: bool,
    /// Images uploaded: those the scene did not have before (an image it kept, the same
    /// `Arc`, is never uploaded again).
    pub images_uploaded: usize,
    /// The object and material tables and the draw list (always: they are small).
    pub tables: bool,
    /// Pipelines built because the edit needs a shader feature the renderer had not built.
    pub pipelines_built: u64,
    /// The environment's cubes and tables, baked again (the environment, or the material
    /// table the bake reads, changed).
    pub environment: bool,
}

/// A fresh [`GpuScene::geometry_version`].
fn next_geometry_version() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// Whether `object` is drawn as a surface (its mesh is triangles), not points or lines.
fn is_surface(scene: &Scene, object: &combustion_scene::Object) -> bool {
    scene
        .meshes
        .get(object.mesh)
        .is_some_and(|m| m.topology == Topology::Triangles)
}

/// Whether some object of `scene` whose mesh is `topology` is drawn.
fn draws(scene: &Scene, topology: Topology) -> bool {
    scene.objects.iter().any(|o| {
        scene
            .meshes
            .get(o.mesh)
            .is_some_and(|m| m.topology == topology)
    })
}

/// The shader features `scene` needs.
pub(crate) fn scene_variant(scene: &Scene) -> crate::variant::ShaderVariant {
    crate::variant::ShaderVariant {
        emissive: scene
            .materials
            .iter()
            .any(|m| m.emissive_strength > 0.0 && m.emissive_factor.iter().any(|&e| e > 0.0)),
        alpha_mask: scene.materials.iter().any(|m| m.is_masked()),
        // Points and lines are drawn opaque into the G-buffer, whatever their material.
        blend: scene.objects.iter().any(|o| {
            is_surface(scene, o)
                && scene
                    .materials
                    .get(o.material)
                    .is_some_and(|m| m.is_blended())
        }),
        transmission: scene.objects.iter().any(|o| {
            is_surface(scene, o)
                && scene
                    .materials
                    .get(o.material)
                    .is_some_and(|m| m.is_transmissive())
        }),
        volume: scene.objects.iter().any(|o| {
            is_surface(scene, o)
                && scene
                    .materials
                    .get(o.material)
                    .is_some_and(|m| m.is_transmissive() && m.volume.is_some())
        }),
        clearcoat: scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material)
                .is_some_and(Material::is_coated)
        }),
        sheen: scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material)
                .is_some_and(Material::has_sheen)
        }),
        iridescence: scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material)
                .is_some_and(Material::is_iridescent)
        }),
        specular: scene.objects.iter().any(|o| {
            scene
                .materials
                .get(o.material)
                .is_some_and(Material::has_specular)
        }),
        vertex_colors: scene
            .objects
            .iter()
            .any(|o| scene.meshes.get(o.mesh).is_some_and(Mesh::has_colors)),
        lines: draws(scene, Topology::Lines),
        points: draws(scene, Topology::Points),
        textures: scene
            .materials
            .iter()
            .any(|m| m.texture_slots().iter().any(|(_, t)| t.is_some())),
        texture_transforms: scene.materials.iter().any(|m| {
            m.texture_slots()
                .iter()
                .any(|(_, t)| t.is_some_and(|t| t.maps_coordinates()))
        }),
        // The Fresnel model and the debug views are the renderer's settings.
        fresnel: crate::options::FresnelModel::Full,
        debug_views: false,
        features: crate::variant::LightingFeatures::of(scene),
        floor: None,
        masking: crate::options::Masking::HeightCorrelated,
        distribution: crate::options::Distribution::Ggx,
        environment: scene.environment.is_some(),
        occlusion: scene.environment.is_some() && has_occlusion_textures(scene),
        // Renderer settings.
        energy_compensation: false,
        shadows: None,
        shadow_kinds: crate::shadows::ShadowKinds::of(&scene.lights),
        environment_samples: 0,
        optional_passes: Default::default(),
    }
}

/// The shader features `scene`'s frames need when an environment lights them, its own
/// or a [`crate::FrameEnvironment`].
pub(crate) fn lit_scene_variant(scene: &Scene) -> crate::variant::ShaderVariant {
    let mut variant = scene_variant(scene);
    variant.environment = true;
    variant.occlusion = has_occlusion_textures(scene);
    variant
}

/// Whether a material darkens the environment's light by an occlusion texture.
fn has_occlusion_textures(scene: &Scene) -> bool {
    scene
        .materials
        .iter()
        .any(|m| m.occlusion_texture.is_some() && m.occlusion_strength > 0.0)
}

/// One mesh's vertex streams and indices on the GPU. Shared (`Arc`) by a scene and the
/// scene an edit makes of it while the mesh is unchanged, so that an edit uploads only
/// the meshes it adds or changes.
pub(crate) struct MeshBuffers {
    pub(crate) vertices: Buffer,
    /// Every vertex's second coordinate set (the TEXTURE_TRANSFORMS variant's stream).
    pub(crate) uv1: Buffer,
    /// Every vertex's colour (RGBA32F; the VERTEX_COLORS variant's stream), for a mesh
    /// with colours other than white ([`Mesh::has_colors`]) only.
    pub(crate) colors: Option<Buffer>,
    pub(crate) indices: Buffer,
    pub(crate) index_count: u32,
    /// What the indices make (the G-buffer pass draws points and lines apart).
    pub(crate) topology: combustion_scene::Topology,
}

impl MeshBuffers {
    fn new(device: &Arc<Device>, mesh: &Mesh) -> Result<Self, RenderError> {
        let index_count = u32::try_from(mesh.indices.len()).map_err(|_| {
            RenderError::TooLarge(format!(
                "mesh `{}`: 2³² indices or more (at most 2³² − 1)",
                mesh.name
            ))
        })?;
        let vertices: Vec<GpuVertex> = mesh.vertices.iter().map(GpuVertex::new).collect();
        let uv1: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv1).collect();
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
            colors: if mesh.has_colors() {
                let colors: Vec<[f32; 4]> = mesh.vertices.iter().map(|v| v.color).collect();
                Some(Buffer::with_data(
                    device,
                    "vertex colours",
                    bytemuck::cast_slice(&colors),
                    vk::BufferUsageFlags::VERTEX_BUFFER,
                )?)
            } else {
                None
            },
            indices: Buffer::with_data(
                device,
                "indices",
                bytemuck::cast_slice(&mesh.indices),
                vk::BufferUsageFlags::INDEX_BUFFER,
            )?,
            index_count,
            topology: mesh.topology,
        })
    }
}

/// The GPU buffers of `meshes`: a mesh equal to one of `previous` (the meshes before an
/// edit, with their buffers) shares its buffers — the same index first, then any —
/// and the others are uploaded. Also returns how many were uploaded.
fn mesh_buffers(
    device: &Arc<Device>,
    meshes: &[Mesh],
    previous: Option<(&[Mesh], &[Arc<MeshBuffers>])>,
) -> Result<(Vec<Arc<MeshBuffers>>, usize), RenderError> {
    let mut uploaded = 0;
    let mut buffers = Vec::with_capacity(meshes.len());
    for (i, mesh) in meshes.iter().enumerate() {
        let kept = previous.and_then(|(old, old_buffers)| {
            let same = |j: &usize| old[*j] == *mesh;
            Some(i)
                .filter(|&i| i < old.len())
                .filter(same)
                .or_else(|| (0..old.len()).find(same))
                .map(|j| old_buffers[j].clone())
        });
        buffers.push(match kept {
            Some(b) => b,
            None => {
                uploaded += 1;
                Arc::new(MeshBuffers::new(device, mesh)?)
            }
        });
    }
    Ok((buffers, uploaded))
}

/// The object and material tables, the conductor table, and the draw list.
struct Tables {
    objects: Buffer,
    materials: Buffer,
    conductor_table: Buffer,
    draw_meshes: Vec<usize>,
    double_sided: Vec<bool>,
    masked: Vec<bool>,
    forward: Vec<bool>,
    volumes: Vec<usize>,
    draw_materials: Vec<usize>,
    variant: crate::variant::ShaderVariant,
    lit_variant: crate::variant::ShaderVariant,
    bake_materials: Vec<u8>,
    world_bounds: Option<(glam::Vec3, glam::Vec3)>,
    object_bounds: Vec<Option<(glam::Vec3, glam::Vec3)>>,
    mesh_bounds: Vec<Option<(glam::Vec3, glam::Vec3)>>,
    mesh_colors: Vec<bool>,
    casts_shadows: Vec<bool>,
}

impl Tables {
    fn new(
        device: &Arc<Device>,
        scene: &Scene,
        textures: &SceneTextures,
        deform: Option<&crate::deform::SceneDeform>,
    ) -> Result<Self, RenderError> {
        // Deformed objects at rest: a skinned one in world space (its transform the
        // identity), its box around its vertices as posed.
        // A skinned object is placed by its joints, in world space: its transform is
        // the identity.
        let mesh_colors: Vec<bool> = scene.meshes.iter().map(Mesh::has_colors).collect();
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        // Written into the mapped table a band of entries at a time, not built whole
        // beside it first (a million objects' table is 144 MB).
        const BAND: usize = 4096;
        let entry_bytes = std::mem::size_of::<GpuObject>();
        let mut objects = Buffer::new(
            device,
            "object table",
            (scene.objects.len() * entry_bytes) as u64,
            storage,
            combustion_vk::gpu_allocator::MemoryLocation::CpuToGpu,
        )?;
        let mut band: Vec<GpuObject> = Vec::with_capacity(BAND.min(scene.objects.len()));
        for start in (0..scene.objects.len()).step_by(BAND) {
            band.clear();
            band.extend(
                scene.objects[start..(start + BAND).min(scene.objects.len())]
                    .iter()
                    .enumerate()
                    .map(|(k, o)| {
                        let entry = GpuObject::new(o, mesh_colors[o.mesh]);
                        if crate::deform::deformation(scene, start + k).0 {
                            entry.placed(&glam::Mat4::IDENTITY)
                        } else {
                            entry
                        }
                    }),
            );
            objects.write(start * entry_bytes, bytemuck::cast_slice(&band))?;
        }
        let mesh_bounds: Vec<_> = scene.meshes.iter().map(Mesh::bounds).collect();
        let mut object_bounds: Vec<_> = scene
            .objects
            .iter()
            .map(|o| combustion_scene::placed_bounds(mesh_bounds[o.mesh], &o.transform))
            .collect();
        // Deformed objects: their boxes at rest, as a frame without a pose draws them.
        if let Some(deform) = deform {
            for (object, bounds) in deform.bounds(&deform.rest_poses) {
                object_bounds[object] = bounds;
            }
        }
        let materials = material_table(scene, &textures.material_indices);
        let needs_table = scene.materials.iter().any(|m| m.conductor_from_base_color);
        let conductor_table: &[[f32; 2]] = if needs_table {
            conductor_from_base_color_table()
        } else {
            &[[1.0, 0.0]]
        };
        Ok(Self {
            objects,
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
            draw_meshes: scene.objects.iter().map(|o| o.mesh).collect(),
            double_sided: scene
                .objects
                .iter()
                .map(|o| scene.materials[o.material].double_sided)
                .collect(),
            masked: scene
                .objects
                .iter()
                .map(|o| scene.materials[o.material].is_masked())
                .collect(),
            forward: scene
                .objects
                .iter()
                .map(|o| is_surface(scene, o) && scene.materials[o.material].is_see_through())
                .collect(),
            volumes: (0..scene.objects.len())
                .filter(|&i| {
                    let o = &scene.objects[i];
                    let m = &scene.materials[o.material];
                    is_surface(scene, o) && m.is_transmissive() && m.volume.is_some()
                })
                .collect(),
            draw_materials: scene.objects.iter().map(|o| o.material).collect(),
            variant: scene_variant(scene),
            lit_variant: lit_scene_variant(scene),
            // The table without texture indices, from the entries just made (not made
            // again: a cut-out's alpha scales walk its texture's mip levels).
            bake_materials: bytemuck::cast_slice(
                &materials
                    .iter()
                    .map(GpuMaterial::without_textures)
                    .collect::<Vec<_>>(),
            )
            .to_vec(),
            // The world box is the objects' boxes together (one walk over the vertices).
            world_bounds: object_bounds
                .iter()
                .flatten()
                .copied()
                .reduce(|(a, b), (c, d)| (a.min(c), b.max(d))),
            object_bounds,
            mesh_bounds,
            mesh_colors,
            casts_shadows: scene.objects.iter().map(|o| o.casts_shadows).collect(),
        })
    }
}

impl GpuScene {
    /// Uploads `scene`, validated by the caller, with its `environment` baked, for the
    /// renderer whose retire queue is `retire`.
    pub(crate) fn new(
        device: &Arc<Device>,
        scene: Scene,
        material_set_layout: &DescriptorSetLayout,
        environment: Option<crate::environment::GpuEnvironment>,
        retire: Arc<RetireQueue>,
    ) -> Result<Self, RenderError> {
        let (meshes, _) = mesh_buffers(device, &scene.meshes, None)?;
        let (textures, _) = SceneTextures::new(device, &scene, material_set_layout, None)?;
        let deform = crate::deform::SceneDeform::new(device, &scene)?;
        let tables = Tables::new(device, &scene, &textures, deform.as_ref())?;
        let ids = SceneIds::new(&scene);
        Ok(Self {
            gpu: ManuallyDrop::new(SceneResources {
                meshes,
                objects: tables.objects,
                materials: tables.materials,
                conductor_table: tables.conductor_table,
                textures,
                environment,
                deform,
                structures: std::sync::OnceLock::new(),
            }),
            draw_meshes: tables.draw_meshes,
            double_sided: tables.double_sided,
            masked: tables.masked,
            forward: tables.forward,
            volumes: tables.volumes,
            casts_shadows: tables.casts_shadows,
            draw_materials: tables.draw_materials,
            variant: tables.variant,
            lit_variant: tables.lit_variant,
            frame_environments: false.into(),
            bake_materials: tables.bake_materials,
            world_bounds: tables.world_bounds,
            object_bounds: tables.object_bounds,
            mesh_bounds: tables.mesh_bounds,
            mesh_colors: tables.mesh_colors,
            geometry_version: next_geometry_version(),
            scene,
            ids,
            retire,
        })
    }

    /// Builds what `next` needs that differs from this scene: the buffers of meshes it
    /// adds or changes, the images it adds and the texture sets if the materials'
    /// textures changed, new tables always; and takes
    /// `environment` if it is baked anew. Returns what was rebuilt and this scene's
    /// replaced parts (to retire), or an error with this scene untouched.
    pub(crate) fn edited(
        &mut self,
        device: &Arc<Device>,
        next: Scene,
        ids: SceneIds,
        material_set_layout: &DescriptorSetLayout,
        environment: Option<Option<crate::environment::GpuEnvironment>>,
    ) -> Result<(SceneEditReport, Vec<Retired>), RenderError> {
        let mut report = SceneEditReport {
            tables: true,
            ..SceneEditReport::default()
        };
        let meshes = if next.meshes != self.scene.meshes {
            let (meshes, uploaded) = mesh_buffers(
                device,
                &next.meshes,
                Some((&self.scene.meshes, &self.gpu.meshes)),
            )?;
            report.geometry = true;
            report.meshes_uploaded = uploaded;
            Some(meshes)
        } else {
            None
        };
        let textures = if next.texture_table() != self.scene.texture_table() {
            let (textures, uploaded) =
                SceneTextures::new(device, &next, material_set_layout, Some(&self.gpu.textures))?;
            report.textures = true;
            report.images_uploaded = uploaded;
            Some(textures)
        } else {
            None
        };
        let deform = crate::deform::SceneDeform::new(device, &next)?;
        let tables = Tables::new(
            device,
            &next,
            textures.as_ref().unwrap_or(&self.gpu.textures),
            deform.as_ref(),
        )?;
        let structures = self
            .gpu
            .structures
            .get()
            .map(|old| {
                let structures =
                    crate::accel::SceneStructure::new(device, &next, deform.as_ref(), old.slots())?;
                // The edited scene is path-traced as the one it replaces was.
                if old.surfaces.get().is_some() {
                    structures.prepare_surfaces(device, &next)?;
                }
                Ok::<_, RenderError>(structures)
            })
            .transpose()?;
        // Everything new is built: swap it in and hand back what it replaces (buffers
        // still shared with the new parts stay alive through them).
        let gpu = &mut *self.gpu;
        let mut retired: Vec<Retired> = Vec::new();
        if let Some(old) = std::mem::replace(
            &mut gpu.structures,
            structures
                .map(std::sync::OnceLock::from)
                .unwrap_or_default(),
        )
        .into_inner()
        {
            retired.push(Box::new(old));
        }
        if let Some(old) = std::mem::replace(&mut gpu.deform, deform) {
            retired.push(Box::new(old));
        }
        if let Some(meshes) = meshes {
            retired.push(Box::new(std::mem::replace(&mut gpu.meshes, meshes)));
        }
        if let Some(t) = textures {
            retired.push(Box::new(std::mem::replace(&mut gpu.textures, t)));
        }
        retired.push(Box::new(std::mem::replace(
            &mut gpu.objects,
            tables.objects,
        )));
        retired.push(Box::new(std::mem::replace(
            &mut gpu.materials,
            tables.materials,
        )));
        retired.push(Box::new(std::mem::replace(
            &mut gpu.conductor_table,
            tables.conductor_table,
        )));
        if let Some(environment) = environment {
            report.environment = environment.is_some();
            if let Some(old) = std::mem::replace(&mut gpu.environment, environment) {
                retired.push(Box::new(old));
            }
        }
        self.draw_meshes = tables.draw_meshes;
        self.double_sided = tables.double_sided;
        self.masked = tables.masked;
        self.forward = tables.forward;
        self.volumes = tables.volumes;
        self.casts_shadows = tables.casts_shadows;
        self.draw_materials = tables.draw_materials;
        self.variant = tables.variant;
        self.lit_variant = tables.lit_variant;
        self.bake_materials = tables.bake_materials;
        self.world_bounds = tables.world_bounds;
        self.object_bounds = tables.object_bounds;
        self.mesh_bounds = tables.mesh_bounds;
        self.mesh_colors = tables.mesh_colors;
        self.geometry_version = next_geometry_version();
        self.scene = next;
        self.ids = ids;
        Ok((report, retired))
    }
}
