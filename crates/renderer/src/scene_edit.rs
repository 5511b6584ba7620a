//! Stable handles to a [`crate::GpuScene`]'s objects, materials and meshes, and the
//! editor that keeps them while an edit adds, removes and changes items
//! ([`crate::Renderer::try_edit_scene`]). A handle names the same item across edits,
//! whatever is removed before it, so a host can undo an edit (remove what it added, add
//! back what it removed) without tracking indices.

use combustion_scene::{Material, Mesh, Object, Scene};

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(u64);
    };
}

handle!(
    /// One object of a [`crate::GpuScene`], for as long as it is in the scene.
    ObjectId
);
handle!(
    /// One material of a [`crate::GpuScene`], for as long as it is in the scene.
    MaterialId
);
handle!(
    /// One mesh of a [`crate::GpuScene`], for as long as it is in the scene.
    MeshId
);

/// Why an edit was refused (the scene is then unchanged).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EditError {
    /// The object is not in the scene (removed, or of another scene).
    #[error("{0:?} is not in the scene (removed, or of another scene)")]
    UnknownObject(ObjectId),
    /// The material is not in the scene (removed, or of another scene).
    #[error("{0:?} is not in the scene (removed, or of another scene)")]
    UnknownMaterial(MaterialId),
    /// The mesh is not in the scene (removed, or of another scene).
    #[error("{0:?} is not in the scene (removed, or of another scene)")]
    UnknownMesh(MeshId),
    /// The material cannot be removed while objects use it.
    #[error("{material:?} is used by {objects} object(s); remove or change them first")]
    MaterialInUse {
        /// The material.
        material: MaterialId,
        /// How many objects use it.
        objects: usize,
    },
    /// The mesh cannot be removed while objects use it.
    #[error("{mesh:?} is used by {objects} object(s); remove or change them first")]
    MeshInUse {
        /// The mesh.
        mesh: MeshId,
        /// How many objects use it.
        objects: usize,
    },
}

/// The handles of a scene's items, index for index.
#[derive(Clone, Debug, Default)]
pub(crate) struct SceneIds {
    pub(crate) objects: Vec<ObjectId>,
    pub(crate) materials: Vec<MaterialId>,
    pub(crate) meshes: Vec<MeshId>,
    /// The next handle's number (handles are never reused within a scene).
    next: u64,
}

impl SceneIds {
    /// Fresh handles for every item of `scene`.
    pub(crate) fn new(scene: &Scene) -> Self {
        let mut ids = SceneIds::default();
        ids.fit(scene);
        ids
    }

    fn fresh(&mut self) -> u64 {
        self.next += 1;
        self.next
    }

    /// After an edit by index: handles follow positions — lists that shrank lose their
    /// last handles, lists that grew get fresh ones.
    fn fit(&mut self, scene: &Scene) {
        fn fit_list<T>(list: &mut Vec<T>, len: usize, mut fresh: impl FnMut() -> T) {
            list.truncate(len);
            while list.len() < len {
                list.push(fresh());
            }
        }
        let mut next = self.next;
        let mut fresh = || {
            next += 1;
            next
        };
        fit_list(&mut self.objects, scene.objects.len(), || ObjectId(fresh()));
        fit_list(&mut self.materials, scene.materials.len(), || {
            MaterialId(fresh())
        });
        fit_list(&mut self.meshes, scene.meshes.len(), || MeshId(fresh()));
        self.next = next;
    }
}

/// An edit in progress: a copy of the scene, changed by handle or by index, applied as
/// one edit when the closure given to [`crate::Renderer::try_edit_scene`] returns `Ok`.
pub struct SceneEditor {
    scene: Scene,
    ids: SceneIds,
}

impl SceneEditor {
    pub(crate) fn new(scene: Scene, ids: SceneIds) -> Self {
        Self { scene, ids }
    }

    pub(crate) fn finish(mut self) -> (Scene, SceneIds) {
        self.ids.fit(&self.scene);
        (self.scene, self.ids)
    }

    /// The scene as edited so far.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene to change by index (lights, camera, the outside medium, or anything
    /// else). Handles follow positions across such changes: an item removed by index
    /// takes the handle of the last one with it, so prefer the methods below for
    /// adding and removing objects, materials and meshes.
    pub fn scene_mut(&mut self) -> &mut Scene {
        &mut self.scene
    }

    /// Adds a mesh; objects place it by its handle.
    pub fn add_mesh(&mut self, mesh: Mesh) -> MeshId {
        self.ids.fit(&self.scene);
        self.scene.meshes.push(mesh);
        let id = MeshId(self.ids.fresh());
        self.ids.meshes.push(id);
        id
    }

    /// Adds a material.
    pub fn add_material(&mut self, material: Material) -> MaterialId {
        self.ids.fit(&self.scene);
        self.scene.materials.push(material);
        let id = MaterialId(self.ids.fresh());
        self.ids.materials.push(id);
        id
    }

    /// Places `mesh` with `material` at `transform` (object to world).
    pub fn add_object(
        &mut self,
        mesh: MeshId,
        material: MaterialId,
        transform: glam::Mat4,
    ) -> Result<ObjectId, EditError> {
        let object = Object {
            mesh: self.mesh_index(mesh)?,
            material: self.material_index(material)?,
            transform,
            casts_shadows: true,
            node: None,
        };
        self.scene.objects.push(object);
        let id = ObjectId(self.ids.fresh());
        self.ids.objects.push(id);
        Ok(id)
    }

    /// Removes an object; returns its mesh, material and transform (to add it back).
    pub fn remove_object(
        &mut self,
        id: ObjectId,
    ) -> Result<(MeshId, MaterialId, glam::Mat4), EditError> {
        let index = self.object_index(id)?;
        let object = self.scene.objects.remove(index);
        self.ids.objects.remove(index);
        Ok((
            self.ids.meshes[object.mesh],
            self.ids.materials[object.material],
            object.transform,
        ))
    }

    /// Removes a material no object uses; returns it.
    pub fn remove_material(&mut self, id: MaterialId) -> Result<Material, EditError> {
        let index = self.material_index(id)?;
        let users = self.unuse(index, |o| &mut o.material);
        if users > 0 {
            return Err(EditError::MaterialInUse {
                material: id,
                objects: users,
            });
        }
        self.ids.materials.remove(index);
        Ok(self.scene.materials.remove(index))
    }

    /// Removes a mesh no object uses; returns it.
    pub fn remove_mesh(&mut self, id: MeshId) -> Result<Mesh, EditError> {
        let index = self.mesh_index(id)?;
        let users = self.unuse(index, |o| &mut o.mesh);
        if users > 0 {
            return Err(EditError::MeshInUse {
                mesh: id,
                objects: users,
            });
        }
        self.ids.meshes.remove(index);
        Ok(self.scene.meshes.remove(index))
    }

    /// Ahead of removing item `index` of the list `field` points into: how many
    /// objects use it; if none, every object's index past it moves down by one.
    fn unuse(&mut self, index: usize, field: impl Fn(&mut Object) -> &mut usize) -> usize {
        let objects = &mut self.scene.objects;
        let mut users = 0;
        for object in objects.iter_mut() {
            users += usize::from(*field(object) == index);
        }
        if users == 0 {
            for object in objects.iter_mut() {
                let i = field(object);
                if *i > index {
                    *i -= 1;
                }
            }
        }
        users
    }

    /// Moves an object.
    pub fn set_transform(&mut self, id: ObjectId, transform: glam::Mat4) -> Result<(), EditError> {
        let index = self.object_index(id)?;
        self.scene.objects[index].transform = transform;
        Ok(())
    }

    /// Gives an object another material.
    pub fn set_material(&mut self, id: ObjectId, material: MaterialId) -> Result<(), EditError> {
        let (index, material) = (self.object_index(id)?, self.material_index(material)?);
        self.scene.objects[index].material = material;
        Ok(())
    }

    /// A material to change in place.
    pub fn material_mut(&mut self, id: MaterialId) -> Result<&mut Material, EditError> {
        let index = self.material_index(id)?;
        Ok(&mut self.scene.materials[index])
    }

    /// A mesh to change in place.
    pub fn mesh_mut(&mut self, id: MeshId) -> Result<&mut Mesh, EditError> {
        let index = self.mesh_index(id)?;
        Ok(&mut self.scene.meshes[index])
    }

    /// The index of an object in [`SceneEditor::scene`] now.
    pub fn object_index(&mut self, id: ObjectId) -> Result<usize, EditError> {
        self.ids.fit(&self.scene);
        position(&self.ids.objects, id).ok_or(EditError::UnknownObject(id))
    }

    /// The index of a material now.
    pub fn material_index(&mut self, id: MaterialId) -> Result<usize, EditError> {
        self.ids.fit(&self.scene);
        position(&self.ids.materials, id).ok_or(EditError::UnknownMaterial(id))
    }

    /// The index of a mesh now.
    pub fn mesh_index(&mut self, id: MeshId) -> Result<usize, EditError> {
        self.ids.fit(&self.scene);
        position(&self.ids.meshes, id).ok_or(EditError::UnknownMesh(id))
    }
}

fn position<T: PartialEq>(list: &[T], id: T) -> Option<usize> {
    list.iter().position(|x| *x == id)
}
