#![deny(clippy::arithmetic_side_effects, clippy::indexing_slicing)]
//! The import driver: container → JSON → validation → node hierarchy → materials,
//! meshes, objects, lights, camera → a validated [`Scene`].

use crate::gltf::PlacedCamera;
use std::collections::btree_map::Entry;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

use glam::{Mat4, Quat, Vec3};
use gltf::json;
use gltf::json::validation::{Checked, Validate};

use super::accessor::{read_colors, read_floats, read_indices};
use super::geometry::{build_mesh, build_strokes, PrimitiveData};
use super::material::default_material;
use super::optics_ext;
use super::source::{split_container, Buffers, Container};
use super::{
    CameraSource, ImportError, ImportOptions, ImportProblem, ImportReport, OPTICS_EXTENSION,
    SHADOW_EXTENSION, SUPPORTED_EXTENSIONS,
};
use crate::{Camera, ColorSpace, Image, Light, Material, Object, Scene};

/// Where an image's bytes come from.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub(crate) enum ImageSource {
    Uri(String),
    BufferView(usize),
}

/// Everything an import in progress holds.
pub(crate) struct Importer<'a> {
    pub file: &'a Path,
    pub root: &'a json::Root,
    pub buffers: Buffers<'a>,
    pub base: Option<&'a Path>,
    pub options: &'a ImportOptions,
    pub warnings: Vec<String>,
    /// Per image source (a URI or a buffer view) and colour space, the scene's image:
    /// each source is decoded once, however many `images` entries name it, and held once
    /// per colour space it is used in.
    pub images: HashMap<(ImageSource, ColorSpace), Arc<Image>>,
    /// Pixels decoded so far (against `ImportOptions::max_decoded_pixels`).
    pub decoded_pixels: u64,
    /// The bytes of the glTF or GLB file itself.
    pub file_bytes: u64,
    /// Bytes of meshes (vertices, indices, joint influences, morph targets), skins and
    /// animations built so far, against
    /// [`Importer::charge_mesh_bytes`]'s budget.
    pub mesh_bytes: u64,
}

impl Importer<'_> {
    pub(crate) fn warn(&mut self, message: String) {
        log::warn!("{}: {message}", self.file.display());
        self.warnings.push(message);
    }
}

pub(crate) fn import_bytes(
    bytes: &[u8],
    file: &Path,
    base: Option<&Path>,
    options: &ImportOptions,
) -> Result<(Scene, ImportReport), ImportError> {
    // The importer is written not to panic; should it anyway, the caller still gets an
    // error naming the file rather than an abort.
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        import_inner(bytes, file, base, options)
    }));
    match result {
        Ok(result) => result.map_err(|problem| ImportError::new(file, problem)),
        Err(panic) => {
            let message = panic
                .downcast_ref::<&str>()
                .map(|s| (*s).to_owned())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            Err(ImportError::new(file, ImportProblem::Internal(message)))
        }
    }
}

/// Placed primitives (objects) an import accepts: far beyond real scenes, but it bounds
/// the memory a small file can ask for by instancing many primitives many times.
const MAX_OBJECTS: usize = 1 << 21;

/// The meshes a file builds may take, together, this many bytes (vertices and indices)
/// whatever the file holds, and [`MESH_BYTES_PER_BYTE_READ`] more per byte of the file
/// and the buffers it read. Meshes legitimately grow past their data (a 2-byte index
/// becomes a 72-byte vertex for a mesh without normals; strips triple their indices;
/// primitives sharing one vertex buffer each get all of it), but not without end: a few
/// kilobytes of JSON naming one buffer from a thousand primitives are refused.
const MESH_BYTES_FLOOR: u64 = 256 << 20;
/// See [`MESH_BYTES_FLOOR`].
const MESH_BYTES_PER_BYTE_READ: u64 = 256;

/// The vertex attributes a [`crate::Mesh`] is built from.
const MESH_ATTRIBUTES: [&str; 6] = [
    "POSITION",
    "NORMAL",
    "TANGENT",
    "TEXCOORD_0",
    "TEXCOORD_1",
    "COLOR_0",
];

/// A primitive's vertex attributes (name, accessor), shared by every placement of it (a
/// file may place one primitive two million times).
type MeshAttributes = Rc<[(String, usize)]>;

/// What placements of one glTF primitive share: the mesh they become and their
/// material (a file may place one primitive two million times; each placement names its
/// kind instead of holding a copy).
struct PlacementKind {
    /// The glTF (mesh, primitive): meshes are ordered by their first.
    primitive: (usize, usize),
    key: MeshKey,
    /// Index into the glTF materials, `None` for the default material.
    material: Option<usize>,
}

/// What tells placement kinds apart: the mesh key, the material and the glTF (mesh,
/// primitive).
type KindKey = (MeshKey, Option<usize>, (usize, usize));

/// One placement of a primitive: 80 bytes.
struct Instance {
    /// Index into the walk's placement kinds.
    kind: u32,
    /// The node that places it.
    node: u32,
    /// Index into the walk's EXT_mesh_gpu_instancing transforms (the instance's within
    /// its node); `None`: the node's own.
    offset: Option<u32>,
    world: Mat4,
}
const _: () = assert!(std::mem::size_of::<Instance>() == 80);

impl MeshKey {
    /// Whether the primitive is points or lines (glTF modes 0–3).
    fn is_strokes(&self) -> bool {
        self.mode < 4
    }
}

/// What makes two primitives the same [`crate::Mesh`]: the same accessors, topology and
/// the same generated data.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct MeshKey {
    attributes: MeshAttributes,
    indices: Option<usize>,
    mode: u32,
    flip: bool,
    uv_tangents: bool,
    /// The skin placing it (its `JOINTS_n`/`WEIGHTS_n` are among `attributes`).
    skin: Option<usize>,
    /// The (mesh, primitive) whose morph targets it has.
    targets: Option<(usize, usize)>,
}

/// glTF's `asset.minVersion`: `MAJOR.MINOR`, at most the asset's own version, and at
/// most 2.0, the version this importer reads (a file that needs a later one is refused).
fn check_min_version(min_version: &str, version: &str) -> Result<(), String> {
    let parse = |text: &str| -> Option<(u64, u64)> {
        let (major, minor) = text.split_once('.')?;
        let number = |part: &str| {
            (!part.is_empty() && part.bytes().all(|b| b.is_ascii_digit()))
                .then(|| part.parse::<u64>().ok())
                .flatten()
        };
        Some((number(major)?, number(minor)?))
    };
    let shown = super::source::truncate(min_version);
    let Some(minimum) = parse(min_version) else {
        return Err(format!(
            "asset.minVersion `{shown}` is not a version of the form MAJOR.MINOR"
        ));
    };
    if parse(version).is_some_and(|v| minimum > v) {
        return Err(format!(
            "asset.minVersion {shown} is above the file's own version {}",
            super::source::truncate(version)
        ));
    }
    if minimum > (2, 0) {
        return Err(format!(
            "asset.minVersion is {shown}: the file needs glTF {shown} or later, and this importer reads glTF 2.0"
        ));
    }
    Ok(())
}

fn semantic_name(s: &json::mesh::Semantic) -> String {
    use json::mesh::Semantic;
    match s {
        Semantic::Positions => "POSITION".into(),
        Semantic::Normals => "NORMAL".into(),
        Semantic::Tangents => "TANGENT".into(),
        Semantic::Colors(n) => format!("COLOR_{n}"),
        Semantic::TexCoords(n) => format!("TEXCOORD_{n}"),
        Semantic::Joints(n) => format!("JOINTS_{n}"),
        Semantic::Weights(n) => format!("WEIGHTS_{n}"),
        // gltf-json keeps an application-specific name without its leading underscore:
        // put it back, so that `_POSITION` can never stand for `POSITION`.
        Semantic::Extras(name) => format!("_{name}"),
    }
}

fn validation_problems(root: &json::Root) -> Vec<String> {
    let mut problems = Vec::new();
    // gltf-json's primitive check indexes the POSITION accessor without a bounds check
    // (it panics on an out-of-range index): check that first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for (semantic, accessor) in &primitive.attributes {
                if accessor.value() >= root.accessors.len() {
                    let name = match semantic {
                        Checked::Valid(s) => semantic_name(s),
                        Checked::Invalid => "?".into(),
                    };
                    problems.push(format!(
                        "meshes[{m}].primitives[{p}].attributes[\"{name}\"]: Index out of bounds (accessor {} of {})",
                        accessor.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    if !problems.is_empty() {
        return problems;
    }
    root.validate(root, json::Path::new, &mut |path, error| {
        let path = path().to_string();
        // Required extensions are checked (with a better message) before.
        if path.starts_with("extensionsRequired") {
            return;
        }
        // gltf-json asks every accessor for a buffer view; glTF 2.0 does not: one
        // without is zeros (plus its sparse values, if any), which the reader handles.
        if path.starts_with("accessors[")
            && path.ends_with("].bufferView")
            && error == json::validation::Error::Missing
        {
            return;
        }
        problems.push(format!("{path}: {error}"));
    });
    problems
}

fn import_inner(
    bytes: &[u8],
    file: &Path,
    base: Option<&Path>,
    options: &ImportOptions,
) -> Result<(Scene, ImportReport), ImportProblem> {
    let mut early_warnings = Vec::new();
    let container: Container = split_container(bytes, &mut early_warnings)?;
    // Each entry of a top-level array is hundreds of bytes parsed (and a node's motion
    // node and place on the walk as much again), for as few as three bytes of JSON (`{},`).
    if let Some((array, entries)) =
        super::counts::array_over(container.json, super::counts::MAX_ARRAY_ENTRIES)
    {
        return Err(ImportProblem::Invalid(format!(
            "its `{}` holds {entries} entries, more than the {} a file may have",
            combustion_optics::shortened(&array),
            super::counts::MAX_ARRAY_ENTRIES
        )));
    }
    let root: json::Root = serde_json::from_slice(container.json).map_err(|e| {
        ImportProblem::Json(if e.is_eof() {
            format!("{e} (the file is truncated)")
        } else {
            e.to_string()
        })
    })?;
    if !root.asset.version.starts_with("2.") {
        return Err(ImportProblem::Invalid(format!(
            "asset.version is `{}`; only glTF 2.x is supported",
            root.asset.version
        )));
    }
    if let Some(min_version) = &root.asset.min_version {
        check_min_version(min_version, &root.asset.version).map_err(ImportProblem::Invalid)?;
    }
    for name in &root.extensions_required {
        if !SUPPORTED_EXTENSIONS.contains(&name.as_str()) {
            return Err(ImportProblem::UnsupportedExtension {
                name: name.clone(),
                supported: SUPPORTED_EXTENSIONS.join(", "),
            });
        }
    }
    let problems = validation_problems(&root);
    if !problems.is_empty() {
        let shown: Vec<&str> = problems.iter().take(5).map(String::as_str).collect();
        let more = if problems.len() > 5 {
            format!(" (and {} more)", problems.len().saturating_sub(5))
        } else {
            String::new()
        };
        return Err(ImportProblem::Invalid(format!(
            "{}{more}",
            shown.join("; ")
        )));
    }
    // What glTF forbids anywhere in the file, also outside the scene shown: a mesh
    // without primitives, a node with two parents, a cycle of nodes.
    if let Some((i, mesh)) = root
        .meshes
        .iter()
        .enumerate()
        .find(|(_, m)| m.primitives.is_empty())
    {
        let name = mesh
            .name
            .as_deref()
            .map_or(String::new(), |n| format!(" (`{n}`)"));
        return Err(ImportProblem::Invalid(format!(
            "mesh {i}{name} has no primitives (glTF requires at least one)"
        )));
    }
    check_node_forest(&root)?;
    // Counts the renderer cannot take are refused before any work on them.
    // The materials primitives use (the importer keeps no others), and glTF's default
    // material when a primitive names none.
    let used: std::collections::BTreeSet<Option<usize>> = root
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .map(|p| p.material.map(|m| m.value()))
        .collect();
    let materials = used.len();
    if materials > usize::from(u16::MAX) {
        return Err(ImportProblem::Invalid(format!(
            "{materials} materials; at most {} fit the G-buffer's 16-bit material index",
            u16::MAX
        )));
    }

    let mut importer = Importer {
        file,
        root: &root,
        buffers: Buffers::new(
            &root,
            &container,
            base,
            options.allow_external_uris,
            options.max_file_bytes,
        ),
        base,
        options,
        warnings: Vec::new(),
        images: HashMap::new(),
        decoded_pixels: 0,
        file_bytes: bytes.len() as u64,
        mesh_bytes: 0,
    };
    for w in early_warnings {
        importer.warn(w);
    }
    let mut report = ImportReport {
        file: file.to_path_buf(),
        generator: root.asset.generator.clone(),
        cameras: root.cameras.len(),
        extensions_used: root.extensions_used.clone(),
        extensions_required: root.extensions_required.clone(),
        ..ImportReport::default()
    };
    for name in &root.extensions_used {
        if !SUPPORTED_EXTENSIONS.contains(&name.as_str()) {
            report.extensions_ignored.push(name.clone());
            importer.warn(format!(
                "ignoring the optional extension `{name}`, which Combustion does not support"
            ));
        }
    }
    importer.build(report)
}

impl Importer<'_> {
    pub(crate) fn node_error(&self, index: usize, message: String) -> ImportProblem {
        ImportProblem::Node {
            index,
            name: self.root.nodes.get(index).and_then(|n| n.name.clone()),
            message,
        }
    }

    pub(crate) fn local_transform(&self, index: usize) -> Result<Mat4, ImportProblem> {
        let node = self
            .root
            .nodes
            .get(index)
            .ok_or_else(|| ImportProblem::Invalid(format!("node {index} does not exist")))?;
        if let Some(m) = node.matrix {
            if !m.iter().all(|x| x.is_finite()) {
                return Err(self.node_error(index, "matrix has a non-finite element".into()));
            }
            return Ok(Mat4::from_cols_array(&m));
        }
        let t = node.translation.unwrap_or([0.0; 3]);
        let s = node.scale.unwrap_or([1.0; 3]);
        let r = node.rotation.map_or([0.0, 0.0, 0.0, 1.0], |q| q.0);
        if !(t.iter().chain(&s).chain(&r).all(|x| x.is_finite())) {
            return Err(self.node_error(
                index,
                "translation, rotation or scale has a non-finite element".into(),
            ));
        }
        let q = Quat::from_array(r);
        let length = q.length();
        if length < 1e-6 {
            return Err(self.node_error(
                index,
                format!(
                    "rotation {} is not a unit quaternion",
                    crate::message_numbers(&r)
                ),
            ));
        }
        Ok(Mat4::from_scale_rotation_translation(
            Vec3::from(s),
            q / length,
            Vec3::from(t),
        ))
    }

    /// The instances node `index` asks for through EXT_mesh_gpu_instancing, each as its
    /// local TRS (`None`: the node has no such extension). The attributes present
    /// (TRANSLATION, ROTATION, SCALE; at least one) must have the same count and finite
    /// values; rotations are normalised (a zero one is an error).
    fn gpu_instances(&mut self, index: usize) -> Result<Option<Vec<Mat4>>, ImportProblem> {
        let root = self.root;
        let Some(value) = root
            .nodes
            .get(index)
            .and_then(|n| n.extensions.as_ref())
            .and_then(|e| e.others.get("EXT_mesh_gpu_instancing"))
        else {
            return Ok(None);
        };
        let problem = |message: String| {
            ImportProblem::Invalid(format!("node {index}: EXT_mesh_gpu_instancing: {message}"))
        };
        let attributes = value
            .get("attributes")
            .and_then(|a| a.as_object())
            .ok_or_else(|| problem("has no `attributes` object".into()))?;
        let accessor = |name: &str| -> Result<Option<usize>, ImportProblem> {
            match attributes.get(name) {
                None => Ok(None),
                Some(v) => v
                    .as_u64()
                    .and_then(|a| usize::try_from(a).ok())
                    .map(Some)
                    .ok_or_else(|| problem(format!("{name} is not an accessor index"))),
            }
        };
        let (t, r, s) = (
            accessor("TRANSLATION")?,
            accessor("ROTATION")?,
            accessor("SCALE")?,
        );
        let read3 = |this: &mut Self, a: Option<usize>, name: &str| {
            a.map(|a| read_floats::<3>(root, &mut this.buffers, a))
                .transpose()
                .map_err(|e| problem(format!("{name}: {e}")))
        };
        let translations = read3(self, t, "TRANSLATION")?;
        let scales = read3(self, s, "SCALE")?;
        let rotations = r
            .map(|a| read_floats::<4>(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| problem(format!("ROTATION: {e}")))?;
        let counts: Vec<usize> = [
            translations.as_ref().map(Vec::len),
            rotations.as_ref().map(Vec::len),
            scales.as_ref().map(Vec::len),
        ]
        .into_iter()
        .flatten()
        .collect();
        let Some(&count) = counts.first() else {
            return Err(problem(
                "names none of TRANSLATION, ROTATION and SCALE".into(),
            ));
        };
        if counts.iter().any(|&c| c != count) {
            return Err(problem(format!(
                "its attributes have different counts ({})",
                counts
                    .iter()
                    .map(|c| c.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        let mut locals = Vec::with_capacity(count);
        for i in 0..count {
            // Each attribute present has `count` elements (checked above).
            fn at<const N: usize>(
                values: &Option<Vec<[f32; N]>>,
                i: usize,
                default: [f32; N],
            ) -> Option<[f32; N]> {
                values.as_ref().map_or(Some(default), |v| v.get(i).copied())
            }
            let (Some(t), Some(s), Some(r)) = (
                at(&translations, i, [0.0; 3]),
                at(&scales, i, [1.0; 3]),
                at(&rotations, i, [0.0, 0.0, 0.0, 1.0]),
            ) else {
                return Err(problem(format!("instance {i} is missing")));
            };
            if !t.iter().chain(&s).chain(&r).all(|x| x.is_finite()) {
                return Err(problem(format!("instance {i} is not finite")));
            }
            let q = Quat::from_array(r);
            let length = q.length();
            if length < 1e-6 {
                return Err(problem(format!(
                    "instance {i}'s rotation {} is not a unit quaternion",
                    crate::message_numbers(&r)
                )));
            }
            locals.push(Mat4::from_scale_rotation_translation(
                Vec3::from(s),
                q / length,
                Vec3::from(t),
            ));
        }
        Ok(Some(locals))
    }

    fn build(mut self, mut report: ImportReport) -> Result<(Scene, ImportReport), ImportProblem> {
        let root = self.root;
        // The scene to show: `scene`, else the first, else every root node.
        let scene_index = root
            .scene
            .map(|s| s.value())
            .or((!root.scenes.is_empty()).then_some(0));
        let roots: Vec<usize> = match scene_index {
            Some(s) => root
                .scenes
                .get(s)
                .ok_or_else(|| ImportProblem::Invalid(format!("scene {s} does not exist")))?
                .nodes
                .iter()
                .map(|n| n.value())
                .collect(),
            None => {
                let mut is_child = vec![false; root.nodes.len()];
                for node in &root.nodes {
                    for child in node.children.iter().flatten() {
                        if let Some(flag) = is_child.get_mut(child.value()) {
                            *flag = true;
                        }
                    }
                }
                if !root.nodes.is_empty() {
                    self.warn("the file has no scene; showing every root node".into());
                }
                (0..root.nodes.len())
                    .filter(|&i| is_child.get(i) == Some(&false))
                    .collect()
            }
        };

        // Walk the hierarchy (iteratively: depth is not bounded by the file).
        let mut visited = vec![false; root.nodes.len()];
        let mut stack: Vec<(usize, Option<Mat4>)> =
            roots.iter().rev().map(|&n| (n, None)).collect();
        let mut instances: Vec<Instance> = Vec::new();
        let mut kinds: Vec<PlacementKind> = Vec::new();
        let mut kind_index: HashMap<KindKey, u32> = HashMap::new();
        let mut instance_offsets: Vec<Mat4> = Vec::new();
        let mut primitive_attributes: HashMap<(usize, usize, bool), MeshAttributes> =
            HashMap::new();
        let mut cameras: Vec<(usize, usize, Mat4)> = Vec::new();
        let mut lights: Vec<(usize, Mat4)> = Vec::new();
        let mut rigid_strokes: usize = 0;
        while let Some((index, parent)) = stack.pop() {
            let node = root
                .nodes
                .get(index)
                .ok_or_else(|| ImportProblem::Invalid(format!("node {index} does not exist")))?;
            // `index` names a node (found above): `visited` has its flag.
            if visited
                .get_mut(index)
                .is_none_or(|seen| std::mem::replace(seen, true))
            {
                return Err(self.node_error(
                    index,
                    "is reached twice: the node hierarchy has a cycle or a node with two parents"
                        .into(),
                ));
            }
            let local = self.local_transform(index)?;
            let world = match parent {
                Some(parent) => parent * local,
                None => local,
            };
            if !world.is_finite() {
                return Err(self.node_error(index, "its world transform is not finite".into()));
            }
            let skin = node.skin.map(|s| s.value());
            if let Some(mesh_index) = node.mesh {
                let mesh_index = mesh_index.value();
                let mesh = root.meshes.get(mesh_index).ok_or_else(|| {
                    self.node_error(index, format!("its mesh {mesh_index} does not exist"))
                })?;
                // EXT_mesh_gpu_instancing: the node's mesh at each instance's TRS within
                // the node (world × T R S), else once at the node. A skin places every
                // instance alike: one is kept.
                let mut gpu_instances = self.gpu_instances(index)?;
                if skin.is_some() && gpu_instances.as_ref().is_some_and(|o| o.len() > 1) {
                    self.warn(format!(
                        "node {index}: {} instances of a skinned mesh: a skin places them all alike, one is drawn",
                        gpu_instances.as_ref().map_or(0, Vec::len)
                    ));
                    gpu_instances = None;
                }
                let too_many = || {
                    ImportProblem::Invalid(format!(
                        "the scene places more than {MAX_OBJECTS} primitives; refused"
                    ))
                };
                // Each offset with its index among the walk's instance transforms.
                let offsets: Vec<(Option<u32>, Mat4)> = match gpu_instances {
                    None => vec![(None, Mat4::IDENTITY)],
                    // A mesh without primitives places nothing: no offset is kept.
                    Some(_) if mesh.primitives.is_empty() => Vec::new(),
                    Some(list) => {
                        let mut numbered = Vec::with_capacity(list.len());
                        for offset in list {
                            let at = u32::try_from(instance_offsets.len())
                                .ok()
                                .filter(|&at| (at as usize) <= MAX_OBJECTS)
                                .ok_or_else(too_many)?;
                            instance_offsets.push(offset);
                            numbered.push((Some(at), offset));
                        }
                        numbered
                    }
                };
                let node_number = u32::try_from(index)
                    .map_err(|_| self.node_error(index, "its index is past 2³² nodes".into()))?;
                for (p, primitive) in mesh.primitives.iter().enumerate() {
                    use json::mesh::Mode;
                    let mode = match primitive.mode {
                        Checked::Valid(mode) => mode,
                        Checked::Invalid => {
                            return Err(ImportProblem::Invalid(format!(
                                "mesh {mesh_index} primitive {p}: invalid mode"
                            )))
                        }
                    };
                    let mode_number = match mode {
                        Mode::Points => 0,
                        Mode::Lines => 1,
                        Mode::LineLoop => 2,
                        Mode::LineStrip => 3,
                        Mode::Triangles => 4,
                        Mode::TriangleStrip => 5,
                        Mode::TriangleFan => 6,
                    };
                    // Points and lines are drawn where their node places them: a skin
                    // or morph targets do not move them (glTF allows both; rare).
                    let strokes = mode_number < 4;
                    let skin = if strokes
                        && (skin.is_some()
                            || primitive.targets.as_ref().is_some_and(|t| !t.is_empty()))
                    {
                        rigid_strokes = rigid_strokes.saturating_add(1);
                        None
                    } else {
                        skin
                    };
                    let material = primitive.material.map(|m| m.value());
                    // Only the attributes a mesh is built from: others (colours, joints,
                    // application-specific ones) would make keys differ, and copies of one
                    // mesh, without changing it.
                    // (A skinned primitive's joints and weights too.)
                    let attributes = primitive_attributes
                        .entry((mesh_index, p, skin.is_some()))
                        .or_insert_with(|| {
                            primitive
                                .attributes
                                .iter()
                                .filter_map(|(semantic, accessor)| match semantic {
                                    Checked::Valid(s) => Some((semantic_name(s), accessor.value())),
                                    Checked::Invalid => None,
                                })
                                .filter(|(name, _)| {
                                    MESH_ATTRIBUTES.contains(&name.as_str())
                                        || (skin.is_some()
                                            && (name.starts_with("JOINTS_")
                                                || name.starts_with("WEIGHTS_")))
                                })
                                .collect()
                        })
                        .clone();
                    let targets = (!strokes
                        && primitive.targets.as_ref().is_some_and(|t| !t.is_empty()))
                    .then_some((mesh_index, p));
                    // The primitive's kind, mirrored or not, found once for this node.
                    let mut kind_of_flip: [Option<u32>; 2] = [None; 2];
                    // Each primitive's placements one after another: the renderer
                    // draws consecutive objects of one mesh and material instanced.
                    for &(offset, transform) in &offsets {
                        let world = world * transform;
                        let flip = crate::normalised_axes_determinant(&world) < 0.0;
                        let slot = kind_of_flip
                            .get_mut(usize::from(flip))
                            .ok_or_else(|| ImportProblem::Internal("a flip has no slot".into()))?;
                        let kind = match *slot {
                            Some(kind) => kind,
                            None => {
                                let key = MeshKey {
                                    attributes: attributes.clone(),
                                    indices: primitive.indices.map(|i| i.value()),
                                    mode: mode_number,
                                    flip,
                                    uv_tangents: false, // set once materials are known
                                    skin,
                                    targets,
                                };
                                let next = u32::try_from(kinds.len())
                                    .ok()
                                    .filter(|&next| (next as usize) <= MAX_OBJECTS)
                                    .ok_or_else(too_many)?;
                                let kind = *kind_index
                                    .entry((key.clone(), material, (mesh_index, p)))
                                    .or_insert_with(|| {
                                        kinds.push(PlacementKind {
                                            primitive: (mesh_index, p),
                                            key,
                                            material,
                                        });
                                        next
                                    });
                                *slot = Some(kind);
                                kind
                            }
                        };
                        instances.push(Instance {
                            kind,
                            node: node_number,
                            offset,
                            world,
                        });
                        if instances.len() > MAX_OBJECTS {
                            break;
                        }
                    }
                }
            }
            if instances.len() > MAX_OBJECTS {
                return Err(ImportProblem::Invalid(format!(
                    "the scene places more than {MAX_OBJECTS} primitives; refused"
                )));
            }
            if let Some(camera) = node.camera {
                cameras.push((camera.value(), index, world));
            }
            if let Some(light) = node
                .extensions
                .as_ref()
                .and_then(|e| e.khr_lights_punctual.as_ref())
            {
                lights.push((light.light.value(), world));
            }
            for child in node.children.iter().flatten().rev() {
                stack.push((child.value(), Some(world)));
            }
        }
        if rigid_strokes > 0 {
            self.warn(format!(
                "{rigid_strokes} point or line primitive(s) of a skinned or morphed mesh drawn at rest, where the node places them"
            ));
        }
        let mut nodes = self.motion_nodes()?;
        self.node_weights(&mut nodes)?;
        let skins = self.skins()?;
        let animations = self.animations(&nodes)?;
        if !animations.is_empty() {
            log::info!(
                "{}: {} animation(s), {} skin(s)",
                self.file.display(),
                animations.len(),
                skins.len()
            );
        }
        // Every placed camera checked now, before any mesh is built, whether or not the
        // scene will use it.
        let views = self.check_cameras(&cameras)?;

        // Materials: those the triangles use in document order, the default one last;
        // then an unlit copy of each one points and lines use, in the same order
        // (docs/gltf.md, "Points and lines"). Each glTF material is read once.
        let mut loaded: BTreeMap<Option<usize>, Material> = BTreeMap::new();
        for kind in &kinds {
            if let Entry::Vacant(entry) = loaded.entry(kind.material) {
                entry.insert(match kind.material {
                    Some(m) => self.material(m)?,
                    None => default_material(),
                });
            }
        }
        let in_order = |strokes: bool| -> Vec<Option<usize>> {
            let mut used: Vec<Option<usize>> = kinds
                .iter()
                .filter(|k| k.key.is_strokes() == strokes)
                .map(|k| k.material)
                .collect();
            used.sort_unstable_by_key(|m| (m.is_none(), *m));
            used.dedup();
            used
        };
        let (surface_materials, stroke_materials) = (in_order(false), in_order(true));
        let mut materials: Vec<Material> = Vec::with_capacity(
            surface_materials
                .len()
                .saturating_add(stroke_materials.len()),
        );
        let mut material_index: HashMap<(Option<usize>, bool), usize> = HashMap::new();
        for (strokes, used) in [(false, surface_materials), (true, stroke_materials)] {
            for m in used {
                material_index.insert((m, strokes), materials.len());
                let material = loaded.get(&m).ok_or_else(|| {
                    ImportProblem::Internal(match m {
                        Some(m) => format!("material {m} was used but not loaded"),
                        None => "the default material was used but not loaded".into(),
                    })
                })?;
                materials.push(if strokes {
                    material.for_points_and_lines()
                } else {
                    material.clone()
                });
            }
        }
        // Every kind's material was given an index just above.
        let material_of = |kind: &PlacementKind| {
            material_index
                .get(&(kind.material, kind.key.is_strokes()))
                .copied()
                .ok_or_else(|| {
                    ImportProblem::Internal("a placement's material has no index".into())
                })
        };
        for kind in &mut kinds {
            let m = materials.get(material_of(kind)?).ok_or_else(|| {
                ImportProblem::Internal("a placement's material index is past the list".into())
            })?;
            kind.key.uv_tangents = !kind.key.is_strokes()
                && m.needs_uv_tangents()
                && !kind.key.attributes.iter().any(|(s, _)| s == "TANGENT");
        }

        // Meshes: one per distinct key, ordered by the first glTF (mesh, primitive) using it.
        let mut first_use: BTreeMap<MeshKey, (usize, usize)> = BTreeMap::new();
        for kind in &kinds {
            first_use
                .entry(kind.key.clone())
                .and_modify(|e| *e = (*e).min(kind.primitive))
                .or_insert(kind.primitive);
        }
        let mut keys: Vec<(&MeshKey, (usize, usize))> =
            first_use.iter().map(|(k, v)| (k, *v)).collect();
        keys.sort_by_key(|(k, mp)| (*mp, k.flip, k.uv_tangents));
        let mut meshes = Vec::with_capacity(keys.len());
        let mut mesh_index: HashMap<MeshKey, usize> = HashMap::new();
        for (key, (m, p)) in keys {
            let mesh = self.build_mesh(key, m, p, &mut report)?;
            mesh_index.insert(key.clone(), meshes.len());
            meshes.push(mesh);
        }

        // Each mesh's box once; the world box gathered from the objects as they are placed
        // (the cameras and their warnings use it).
        let boxes: Vec<_> = meshes.iter().map(crate::Mesh::bounds).collect();
        let mut bounds: Option<(Vec3, Vec3)> = None;
        let mut objects = Vec::with_capacity(instances.len());
        let mut singular: usize = 0;
        // Nodes an animation moves (or whose ancestor it moves): their objects may be
        // singular at rest (scaled to 0 until they appear) and are kept.
        let moved = {
            let mut moved = vec![false; nodes.len()];
            for channel in animations.iter().flat_map(|a| &a.channels) {
                if channel.property != crate::motion::Property::Weights {
                    if let Some(flag) = moved.get_mut(channel.node) {
                        *flag = true;
                    }
                }
            }
            let mut under_moved = moved.clone();
            for (flag, own) in under_moved.iter_mut().zip(&nodes) {
                let mut node = own.parent;
                while let (false, Some(p)) = (*flag, node) {
                    *flag = moved.get(p).copied().unwrap_or(false);
                    node = nodes.get(p).and_then(|n| n.parent);
                }
            }
            under_moved
        };
        // Each kind's mesh (every key was given one just above) and material, once.
        let mut kind_mesh: Vec<(usize, usize)> = Vec::with_capacity(kinds.len());
        for kind in &kinds {
            let mesh = mesh_index.get(&kind.key).copied().ok_or_else(|| {
                ImportProblem::Internal("a placement's mesh was not built".into())
            })?;
            kind_mesh.push((mesh, material_of(kind)?));
        }
        for instance in &instances {
            let node = instance.node as usize;
            // Singular relative to the transform's own scale: a node scale of 1e-4 on a
            // mesh 1e4 across (a centimetre export) is a 1 m object, kept.
            if crate::transform_is_degenerate(&instance.world) && moved.get(node) != Some(&true) {
                singular = singular.saturating_add(1);
                continue;
            }
            // Every kind was given a mesh just above, each mesh a box, each offset an
            // index as it was kept.
            let offset = match instance.offset {
                None => Some(Mat4::IDENTITY),
                Some(at) => instance_offsets.get(at as usize).copied(),
            };
            let (Some(&(mesh, material)), Some(offset)) =
                (kind_mesh.get(instance.kind as usize), offset)
            else {
                return Err(ImportProblem::Internal(
                    "a placement's kind or offset is past its list".into(),
                ));
            };
            let Some(&bounds_of_mesh) = boxes.get(mesh) else {
                return Err(ImportProblem::Internal("a mesh has no box".into()));
            };
            let placed = crate::placed_bounds(bounds_of_mesh, &instance.world);
            if placed.is_some_and(|(lo, hi)| {
                !(lo.is_finite() && hi.is_finite() && (hi - lo).is_finite())
            }) {
                return Err(self.node_error(
                    node,
                    "places its mesh beyond what f32 can hold: the mesh's extent times the world transform overflows".into(),
                ));
            }
            if let Some((lo, hi)) = placed {
                bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
            }
            objects.push(Object {
                mesh,
                material,
                transform: instance.world,
                casts_shadows: self.node_casts_shadows(node)?,
                node: Some(crate::NodeLink { node, offset }),
            });
        }
        drop(instances);
        if singular > 0 {
            self.warn(format!(
                "{singular} object(s) with a singular transform (e.g. scale 0) that no animation moves left out"
            ));
        }

        let lights = lights
            .into_iter()
            .map(|(light, world)| self.light(light, world))
            .collect::<Result<Vec<Light>, _>>()?;

        let motion = crate::Motion {
            nodes,
            skins,
            animations,
        };
        bounds = animated_bounds(&motion, &meshes, &objects, bounds);

        let outside_ior = self.outside_ior(scene_index)?;
        let (camera, source) = self.camera(&cameras, &views, bounds)?;
        report.scene_cameras = self.scene_cameras(&views, bounds);
        for warning in camera_range_warnings(&camera, bounds) {
            self.warn(warning);
        }

        let name = scene_index
            .and_then(|s| root.scenes.get(s))
            .and_then(|s| s.name.clone())
            .or_else(|| {
                self.file
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
            })
            .unwrap_or_else(|| "glTF scene".into());
        let mut scene = Scene {
            name,
            meshes,
            materials,
            objects,
            lights,
            camera,
            outside_ior,
            environment: None,
            motion,
        };
        scene.validate().map_err(ImportProblem::Scene)?;
        if source == CameraSource::Framing {
            if let Some(framed) = posed_bounds(&scene) {
                scene.camera = Camera::framing(Some(framed));
            }
        }
        let table = scene.texture_table();
        report.meshes = scene.meshes.len();
        report.triangles = scene.meshes.iter().map(crate::Mesh::triangle_count).sum();
        report.instanced_triangles = scene
            .objects
            .iter()
            .filter_map(|o| scene.meshes.get(o.mesh).map(crate::Mesh::triangle_count))
            .sum();
        report.objects = scene.objects.len();
        report.materials = scene.materials.len();
        report.images = table.images.len();
        report.textures = table.textures.len();
        report.lights = scene.lights.len();
        report.camera = source;
        report.warnings = std::mem::take(&mut self.warnings);
        Ok((scene, report))
    }

    fn build_mesh(
        &mut self,
        key: &MeshKey,
        mesh_index: usize,
        primitive: usize,
        report: &mut ImportReport,
    ) -> Result<crate::Mesh, ImportProblem> {
        let root = self.root;
        let gltf_mesh = root
            .meshes
            .get(mesh_index)
            .ok_or_else(|| ImportProblem::Invalid(format!("mesh {mesh_index} does not exist")))?;
        let err = |message: String| ImportProblem::Primitive {
            mesh: mesh_index,
            name: gltf_mesh.name.clone(),
            primitive,
            message,
        };
        let attribute = |name: &str| {
            key.attributes
                .iter()
                .find(|(s, _)| s == name)
                .map(|(_, a)| *a)
        };
        let position =
            attribute("POSITION").ok_or_else(|| err("has no POSITION attribute".into()))?;
        let positions = read_floats::<3>(root, &mut self.buffers, position)
            .map_err(|e| err(format!("POSITION: {e}")))?;
        let normals = attribute("NORMAL")
            .map(|a| read_floats::<3>(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| err(format!("NORMAL: {e}")))?;
        let tangents = attribute("TANGENT")
            .map(|a| read_floats::<4>(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| err(format!("TANGENT: {e}")))?;
        let uvs = attribute("TEXCOORD_0")
            .map(|a| read_floats::<2>(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| err(format!("TEXCOORD_0: {e}")))?;
        let uvs1 = attribute("TEXCOORD_1")
            .map(|a| read_floats::<2>(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| err(format!("TEXCOORD_1: {e}")))?;
        let mut colors = attribute("COLOR_0")
            .map(|a| read_colors(root, &mut self.buffers, a))
            .transpose()
            .map_err(|e| err(format!("COLOR_0: {e}")))?;
        // Float colours outside [0, 1] (the range glTF gives them) are clamped, with a
        // warning; NaN is left for the mesh's finiteness check to refuse.
        if let Some(colors) = &mut colors {
            let outside = colors
                .iter()
                .flatten()
                .filter(|c| !(0.0..=1.0).contains(*c) && c.is_finite())
                .count();
            if outside > 0 {
                for c in colors.iter_mut().flatten().filter(|c| c.is_finite()) {
                    *c = c.clamp(0.0, 1.0);
                }
                self.warn(format!(
                    "mesh {mesh_index} primitive {primitive}: {outside} COLOR_0 component(s) outside [0, 1]; clamped"
                ));
            }
        }
        let raw: Vec<u32> = match key.indices {
            Some(a) => read_indices(root, &mut self.buffers, a)
                .map_err(|e| err(format!("indices: {e}")))?,
            None => {
                let n = u32::try_from(positions.len())
                    .map_err(|_| err("has more than 2³² vertices".into()))?;
                (0..n).collect()
            }
        };
        let pairs = |closed: bool| -> Vec<u32> {
            let mut out = Vec::with_capacity(raw.len().saturating_mul(2));
            for pair in raw.windows(2) {
                out.extend_from_slice(pair);
            }
            if let (true, [first, .., last]) = (closed && raw.len() > 2, raw.as_slice()) {
                out.extend_from_slice(&[*last, *first]);
            }
            out
        };
        // The whole groups of `size` indices (a trailing partial group left out).
        let whole =
            |size: usize| -> Vec<u32> { raw.chunks_exact(size).flatten().copied().collect() };
        let indices = match key.mode {
            0 => raw.clone(),
            1 => {
                if raw.len() % 2 != 0 {
                    self.warn(format!(
                        "mesh {mesh_index} primitive {primitive}: {} line indices is not a multiple of 2; the last one ignored",
                        raw.len()
                    ));
                }
                whole(2)
            }
            2 => pairs(true),
            3 => pairs(false),
            4 => {
                if raw.len() % 3 != 0 {
                    self.warn(format!(
                        "mesh {mesh_index} primitive {primitive}: {} indices is not a multiple of 3; the last {} ignored",
                        raw.len(),
                        raw.len() % 3
                    ));
                }
                whole(3)
            }
            5 => {
                // Triangle k of a strip is (k, k+1, k+2), its odd ones wound the other way.
                let mut out = Vec::with_capacity(raw.len().saturating_sub(2).saturating_mul(3));
                for (k, window) in raw.windows(3).enumerate() {
                    if let &[a, b, c] = window {
                        out.extend_from_slice(&if k % 2 == 0 { [a, b, c] } else { [b, a, c] });
                    }
                }
                out
            }
            _ => {
                // A fan: (k+1, k+2, 0) for each k.
                let mut out = Vec::with_capacity(raw.len().saturating_sub(2).saturating_mul(3));
                if let Some((&first, rest)) = raw.split_first() {
                    for window in rest.windows(2) {
                        if let &[b, c] = window {
                            out.extend_from_slice(&[b, c, first]);
                        }
                    }
                }
                out
            }
        };
        // What the mesh will take, against the file's budget for meshes, before it is
        // built: a vertex per corner at most when normals are generated flat or MikkTSpace
        // splits the vertices (welding merges some back), else the given vertices.
        let vertex_count = positions.len();
        let per_corner =
            !key.is_strokes() && (normals.is_none() || (key.uv_tangents && uvs.is_some()));
        let vertices = if per_corner {
            positions.len().max(indices.len())
        } else {
            positions.len()
        };
        self.charge_mesh_bytes(
            (vertices as u64)
                .saturating_mul(std::mem::size_of::<crate::Vertex>() as u64)
                .saturating_add((indices.len() as u64).saturating_mul(4)),
        )
        .map_err(err)?;
        let name = match &gltf_mesh.name {
            Some(name) if gltf_mesh.primitives.len() == 1 => name.clone(),
            Some(name) => format!("{name} primitive {primitive}"),
            None if gltf_mesh.primitives.len() == 1 => format!("mesh {mesh_index}"),
            None => format!("mesh {mesh_index} primitive {primitive}"),
        };
        let data = PrimitiveData {
            positions,
            normals,
            tangents,
            uvs,
            uvs1,
            colors,
            indices,
            keep_sources_apart: key.skin.is_some() || key.targets.is_some(),
        };
        if key.is_strokes() {
            let topology = if key.mode == 0 {
                crate::Topology::Points
            } else {
                crate::Topology::Lines
            };
            return build_strokes(name, data, topology).map_err(err);
        }
        let (mesh, stats) = build_mesh(name, data, key.uv_tangents, key.flip).map_err(err)?;
        let mut mesh = mesh;
        if let Some(skin) = key.skin {
            let joints = root.skins.get(skin).map_or(0, |s| s.joints.len());
            mesh.skin = Some(
                self.skin_weights(&key.attributes, vertex_count, &stats.sources, joints)
                    .map_err(err)?,
            );
        }
        if key.targets.is_some() {
            mesh.morph_targets = self
                .morph_targets(mesh_index, primitive, vertex_count, &stats.sources)
                .map_err(err)?;
        }
        report.degenerate_triangles = report.degenerate_triangles.saturating_add(stats.degenerate);
        if stats.generated_normals || stats.repaired_normals > 0 {
            report.generated_normals = report.generated_normals.saturating_add(1);
        }
        if stats.generated_tangents {
            report.generated_tangents = report.generated_tangents.saturating_add(1);
        }
        for w in stats.warnings {
            self.warn(format!("mesh {mesh_index} primitive {primitive}: {w}"));
        }
        Ok(mesh)
    }

    /// Adds `bytes` of mesh to the file's total: an error past [`MESH_BYTES_FLOOR`] +
    /// [`MESH_BYTES_PER_BYTE_READ`] × the bytes of the file and the buffers it read.
    pub(crate) fn charge_mesh_bytes(&mut self, bytes: u64) -> Result<(), String> {
        let read = self.file_bytes.saturating_add(self.buffers.bytes_read());
        let budget = MESH_BYTES_PER_BYTE_READ
            .saturating_mul(read)
            .saturating_add(MESH_BYTES_FLOOR);
        self.mesh_bytes = self.mesh_bytes.saturating_add(bytes);
        if self.mesh_bytes > budget {
            return Err(format!(
                "the meshes, skins and animations built so far would take {} MiB, more than this file may ask for ({} MiB: {} MiB + {} × the {read} bytes of the file and its buffers)",
                crate::error::readable((self.mesh_bytes >> 20) as f64),
                budget >> 20,
                MESH_BYTES_FLOOR >> 20,
                MESH_BYTES_PER_BYTE_READ,
            ));
        }
        Ok(())
    }

    /// Whether node `node`'s mesh casts shadows: its `COMBUSTION_shadows.castsShadows`,
    /// true without one.
    fn node_casts_shadows(&self, node: usize) -> Result<bool, ImportProblem> {
        let Some(ext) = self
            .root
            .nodes
            .get(node)
            .and_then(|n| n.extensions.as_ref())
            .and_then(|e| e.others.get(SHADOW_EXTENSION))
        else {
            return Ok(true);
        };
        let problem = |message: String| self.node_error(node, message);
        let ext = ext
            .as_object()
            .ok_or_else(|| problem(format!("{SHADOW_EXTENSION} must be an object")))?;
        let mut casts = true;
        for (key, value) in ext {
            match key.as_str() {
                "castsShadows" => casts = casts_shadows_field(value).map_err(problem)?,
                other => {
                    return Err(problem(format!(
                        "{SHADOW_EXTENSION} on a node has no field `{other}` (castsShadows)"
                    )))
                }
            }
        }
        Ok(casts)
    }

    fn light(&mut self, index: usize, world: Mat4) -> Result<Light, ImportProblem> {
        use json::extensions::scene::khr_lights_punctual::Type;
        let root = self.root;
        let light = root
            .extensions
            .as_ref()
            .and_then(|e| e.khr_lights_punctual.as_ref())
            .and_then(|l| l.lights.get(index))
            .ok_or_else(|| ImportProblem::Light {
                index,
                message: "does not exist".into(),
            })?;
        let err = |message: String| ImportProblem::Light { index, message };
        let power = light.color.map(|c| c * light.intensity);
        if !power.iter().all(|x| x.is_finite() && *x >= 0.0) {
            return Err(err(format!(
                "colour {} × intensity {} must be finite and non-negative",
                crate::message_numbers(&light.color),
                crate::message_number(light.intensity)
            )));
        }
        // The range is the light's own (node scale does not change it); its window on
        // the inverse-square law is `crate::range_window`. Directional lights have none.
        let range = light.range;
        if let Some(r) = range {
            if !(r.is_finite() && r > 0.0) {
                return Err(err(format!(
                    "range {} must be a finite number above 0",
                    crate::error::readable(r)
                )));
            }
        }
        let position = world.w_axis.truncate();
        let direction = -world.z_axis.truncate();
        if !(direction.is_finite() && direction.length_squared() > 0.0) {
            return Err(err(
                "the node's transform gives no direction (its -Z axis is zero)".into(),
            ));
        }
        let shadow = light_shadow(light.extensions.as_deref()).map_err(err)?;
        let directional = matches!(light.type_, Checked::Valid(Type::Directional));
        let size_name = if directional {
            "angularDiameter"
        } else {
            "radius"
        };
        if let Some((name, _)) = shadow.sizes.iter().find(|(name, _)| *name != size_name) {
            return Err(err(format!(
                "{SHADOW_EXTENSION}.{name} is for {} lights; this one takes `{size_name}`",
                if directional {
                    "point and spot"
                } else {
                    "directional"
                }
            )));
        }
        let size = shadow.sizes.first().map_or(0.0, |(_, size)| *size);
        let casts_shadows = shadow.casts_shadows;
        Ok(match light.type_ {
            Checked::Valid(Type::Point) => Light::Point {
                position,
                intensity: power,
                range,
                casts_shadows,
                radius: size,
            },
            Checked::Valid(Type::Directional) => Light::Directional {
                direction,
                irradiance: power,
                casts_shadows,
                angular_diameter: size,
            },
            Checked::Valid(Type::Spot) => {
                let (mut inner, mut outer) = light
                    .spot
                    .as_ref()
                    .map_or((0.0, std::f32::consts::FRAC_PI_4), |s| {
                        (s.inner_cone_angle, s.outer_cone_angle)
                    });
                if !(inner.is_finite() && outer.is_finite() && outer > 0.0 && inner >= 0.0) {
                    return Err(err(format!(
                        "spot cone angles inner {inner}, outer {outer}: need 0 ≤ inner < outer ≤ π/2"
                    )));
                }
                if outer > std::f32::consts::FRAC_PI_2 {
                    self.warn(format!(
                        "light {index}: outer cone angle {} > π/2 clamped to π/2",
                        crate::error::readable(outer)
                    ));
                    outer = std::f32::consts::FRAC_PI_2;
                }
                if inner >= outer {
                    let fixed = outer * 0.999;
                    self.warn(format!(
                        "light {index}: inner cone angle {inner} ≥ outer {outer}; set to {fixed}"
                    ));
                    inner = fixed;
                }
                Light::Spot {
                    position,
                    direction,
                    intensity: power,
                    inner_cone: inner,
                    outer_cone: outer,
                    range,
                    casts_shadows,
                    radius: size,
                }
            }
            Checked::Invalid => return Err(err("invalid type".into())),
        })
    }

    fn outside_ior(&mut self, scene: Option<usize>) -> Result<f32, ImportProblem> {
        let root = self.root;
        let mut outside = 1.0;
        let mut warnings = Vec::new();
        let parse = |value: &serde_json::Value, warnings: &mut Vec<String>, at: &str| {
            optics_ext::parse_scene_level(value, warnings)
                .map_err(|e| ImportProblem::Invalid(format!("{at}: {OPTICS_EXTENSION}: {e}")))
        };
        if let Some(value) = root
            .extensions
            .as_ref()
            .and_then(|e| e.others.get(OPTICS_EXTENSION))
        {
            if let Some(ior) = parse(value, &mut warnings, "root extensions")? {
                outside = ior;
            }
        }
        if let Some(value) = scene
            .and_then(|s| root.scenes.get(s))
            .and_then(|s| s.extensions.as_ref())
            .and_then(|e| e.others.get(OPTICS_EXTENSION))
        {
            if let Some(ior) = parse(
                value,
                &mut warnings,
                &format!("scene {}", scene.unwrap_or(0)),
            )? {
                outside = ior;
            }
        }
        for w in warnings {
            self.warn(w);
        }
        Ok(outside)
    }

    /// Checks every perspective camera placed in the scene (`placed`: camera, node, world
    /// transform, in the order the nodes were reached), whether or not the scene will use
    /// it: the first problem is an [`ImportProblem::Camera`], as a bad light's is. The
    /// checked views, in (camera, node) order. Orthographic cameras are not supported and
    /// not checked (see [`Importer::camera`]).
    fn check_cameras(
        &self,
        placed: &[(usize, usize, Mat4)],
    ) -> Result<Vec<CameraView>, ImportProblem> {
        let mut views = placed
            .iter()
            .filter(|(index, _, _)| self.is_perspective(*index))
            .map(|&(index, node, world)| self.check_camera(index, node, world))
            .collect::<Result<Vec<_>, _>>()?;
        views.sort_by_key(|v| (v.index, v.node));
        Ok(views)
    }

    /// Whether glTF camera `index` is a perspective one (the only kind supported).
    fn is_perspective(&self, index: usize) -> bool {
        self.root.cameras.get(index).is_some_and(|c| {
            c.perspective.is_some()
                && matches!(c.type_, Checked::Valid(json::camera::Type::Perspective))
        })
    }

    /// Perspective camera `index` placed by `node` at `world`, checked: `yfov` in (0, π),
    /// `znear` finite and positive, `zfar` (if given) finite and above `znear`,
    /// `aspectRatio` (if given) finite and positive, and a placement that is finite,
    /// invertible and gives a view direction with an up vector off it.
    fn check_camera(
        &self,
        index: usize,
        node: usize,
        world: Mat4,
    ) -> Result<CameraView, ImportProblem> {
        let root = self.root;
        let err = |message: String| ImportProblem::Camera { index, message };
        let Some(p) = root.cameras.get(index).and_then(|c| c.perspective.as_ref()) else {
            return Err(err(
                "is not a perspective camera; only perspective cameras are supported".into(),
            ));
        };
        if !(p.yfov.is_finite() && p.yfov > 0.0 && p.yfov < std::f32::consts::PI) {
            return Err(err(format!(
                "yfov {} must lie in (0, π)",
                crate::error::readable(p.yfov)
            )));
        }
        if !(p.znear.is_finite() && p.znear > 0.0) {
            return Err(err(format!(
                "znear {} must be a finite number above 0",
                crate::error::readable(p.znear)
            )));
        }
        if let Some(zfar) = p.zfar {
            if !(zfar.is_finite() && zfar > p.znear) {
                return Err(err(format!(
                    "zfar {} must be finite and larger than znear {}",
                    crate::error::readable(zfar),
                    crate::error::readable(p.znear)
                )));
            }
        }
        if let Some(aspect) = p.aspect_ratio {
            if !(aspect.is_finite() && aspect > 0.0) {
                return Err(err(format!(
                    "aspectRatio {} must be a finite number above 0",
                    crate::error::readable(aspect)
                )));
            }
        }
        if crate::transform_is_degenerate(&world) {
            return Err(err(format!(
                "node {node} places it with a transform that is not finite or not invertible (a scale of 0 collapses an axis)"
            )));
        }
        let position = world.w_axis.truncate();
        let forward = (-world.z_axis.truncate()).normalize_or_zero();
        let mut up = world.y_axis.truncate().normalize_or_zero();
        if forward == Vec3::ZERO || up == Vec3::ZERO || forward.cross(up).length() < 1e-6 {
            return Err(err(format!("node {node} gives no usable view direction")));
        }
        let mut target = position + forward;
        // Exact look-at written by Combustion's writer (see docs/gltf.md).
        if let Some((t, u)) = exact_look_at(root.nodes.get(node).and_then(|n| n.extras.as_deref()))
        {
            let dir = (t - position).normalize_or_zero();
            if dir.dot(forward) > 0.9999 && u.cross(dir).length() > 1e-6 {
                target = t;
                up = u;
            }
        }
        if p.aspect_ratio.is_some() {
            log::debug!(
                "{}: camera {index}: aspectRatio ignored (the renderer's image size decides)",
                self.file.display()
            );
        }
        Ok(CameraView {
            index,
            node,
            position,
            target,
            up,
            vertical_fov: p.yfov,
            near: p.znear,
            far: p.zfar,
        })
    }

    /// The scene's camera: the one [`ImportOptions::camera`] asks for, else the first of
    /// `views` (checked by [`Importer::check_cameras`]), else one framing the scene.
    /// `placed` is every placed camera, orthographic ones too (for the messages).
    fn camera(
        &mut self,
        placed: &[(usize, usize, Mat4)],
        views: &[CameraView],
        bounds: Option<(Vec3, Vec3)>,
    ) -> Result<(Camera, CameraSource), ImportProblem> {
        let root = self.root;
        if let Some((lo, hi)) = bounds {
            if !(hi - lo).length().is_finite() {
                return Err(ImportProblem::Invalid(format!(
                    "the scene spans from {} to {}: more than f32 can hold (each object fits; their distances apart do not)",
                    crate::message_numbers(&lo.to_array()),
                    crate::message_numbers(&hi.to_array())
                )));
            }
        }
        let chosen = match self.options.camera {
            Some(index) => {
                let err = |message: String| ImportProblem::Camera { index, message };
                if index >= root.cameras.len() {
                    return Err(err(format!(
                        "was asked for but the file has {} camera(s)",
                        root.cameras.len()
                    )));
                }
                if !self.is_perspective(index) {
                    return Err(err(
                        "is orthographic; only perspective cameras are supported".into(),
                    ));
                }
                let view = views
                    .iter()
                    .find(|v| v.index == index)
                    .ok_or_else(|| err("is not placed by any node of the scene".into()))?;
                Some(view)
            }
            None => {
                if views.is_empty() && !placed.is_empty() {
                    self.warn("the scene's cameras are all orthographic (unsupported); using a camera framing the scene".into());
                }
                views.first()
            }
        };
        Ok(match chosen {
            Some(view) => (
                view.camera(bounds),
                CameraSource::Gltf {
                    index: view.index,
                    node: view.node,
                },
            ),
            None => (Camera::framing(bounds), CameraSource::Framing),
        })
    }

    /// Every perspective camera placed in the scene, in (camera, node) order (for viewers
    /// that switch between them).
    fn scene_cameras(
        &self,
        views: &[CameraView],
        bounds: Option<(Vec3, Vec3)>,
    ) -> Vec<PlacedCamera> {
        views
            .iter()
            .map(|view| PlacedCamera {
                index: view.index,
                node: view.node,
                name: self
                    .root
                    .cameras
                    .get(view.index)
                    .and_then(|c| c.name.clone()),
                camera: view.camera(bounds),
            })
            .collect()
    }
}

/// A placed perspective camera, checked ([`Importer::check_camera`]): its [`Camera`]
/// but for the far plane of an infinite projection, which the scene's bounds decide.
#[derive(Clone, Copy, Debug)]
struct CameraView {
    /// Index into the glTF `cameras`.
    index: usize,
    /// The node that places it.
    node: usize,
    position: Vec3,
    target: Vec3,
    up: Vec3,
    vertical_fov: f32,
    near: f32,
    /// `zfar`; `None` for an infinite projection.
    far: Option<f32>,
}

impl CameraView {
    /// The camera, with an infinite projection's far plane far enough to hold the whole
    /// scene: 1.5 × the distance to the farthest corner of `bounds`, at least 1000 × near.
    fn camera(&self, bounds: Option<(Vec3, Vec3)>) -> Camera {
        let far = self.far.unwrap_or_else(|| {
            let reach = bounds.map_or(0.0, |(lo, hi)| {
                crate::box_corners(lo, hi)
                    .iter()
                    .map(|corner| (*corner - self.position).length())
                    .fold(0.0f32, f32::max)
            });
            (reach * 1.5).max(self.near * 1000.0)
        });
        Camera {
            position: self.position,
            target: self.target,
            up: self.up,
            vertical_fov: self.vertical_fov,
            near: self.near,
            far,
        }
    }
}

/// `extras.combustion.{target, up}` of a camera node.
fn exact_look_at(extras: Option<&serde_json::value::RawValue>) -> Option<(Vec3, Vec3)> {
    let value: serde_json::Value = serde_json::from_str(extras?.get()).ok()?;
    let object = value.get("combustion")?;
    let vec = |key: &str| -> Option<Vec3> {
        let [x, y, z] = object.get(key)?.as_array()?.as_slice() else {
            return None;
        };
        let v = Vec3::new(x.as_f64()? as f32, y.as_f64()? as f32, z.as_f64()? as f32);
        v.is_finite().then_some(v)
    };
    Some((vec("target")?, vec("up")?))
}

/// World-space bounding box of every object.
pub(crate) fn world_bounds(meshes: &[crate::Mesh], objects: &[Object]) -> Option<(Vec3, Vec3)> {
    object_bounds(meshes, objects)
        .into_iter()
        .flatten()
        .reduce(|(a, b), (c, d)| (a.min(c), b.max(d)))
}

/// `bounds` grown to hold every object hanging from a node wherever the first animation
/// of `motion` takes it, at its key times (at most [`FRAMED_POSES`] of them, fewer for
/// very many objects), so that a framing camera sees the scene move. Skinned objects
/// keep their box at rest; a box that does not fit f32 is left out.
fn animated_bounds(
    motion: &crate::Motion,
    meshes: &[crate::Mesh],
    objects: &[Object],
    mut bounds: Option<(Vec3, Vec3)>,
) -> Option<(Vec3, Vec3)> {
    let Some(animation) = motion.animations.first() else {
        return bounds;
    };
    let mut times: Vec<f32> = animation
        .samplers
        .iter()
        .flat_map(|s| s.times.iter().copied())
        .collect();
    times.sort_by(f32::total_cmp);
    times.dedup();
    let poses = FRAMED_OBJECT_POSES
        .checked_div(objects.len())
        .unwrap_or(FRAMED_OBJECT_POSES)
        .clamp(2, FRAMED_POSES);
    let step = times.len().div_ceil(poses).max(1);
    let boxes: Vec<_> = meshes.iter().map(crate::Mesh::bounds).collect();
    for &time in times.iter().step_by(step).chain(times.last()) {
        let Some(pose) = motion.sample(0, time) else {
            break;
        };
        let world = motion.world_transforms(&pose);
        for object in objects {
            let Some(link) = object.node else { continue };
            let (Some(mesh), Some(node), Some(&mesh_box), Some(&node_world)) = (
                meshes.get(object.mesh),
                motion.nodes.get(link.node),
                boxes.get(object.mesh),
                world.get(link.node),
            ) else {
                continue;
            };
            if mesh.skin.is_some() && node.skin.is_some() {
                continue;
            }
            let placed = crate::placed_bounds(mesh_box, &(node_world * link.offset));
            if let Some((lo, hi)) = placed.filter(|(lo, hi)| (*hi - *lo).is_finite()) {
                bounds = Some(bounds.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
            }
        }
    }
    bounds
}

/// The box a framing camera frames when `scene` deforms a mesh (a skin, morph targets
/// hanging from a node): the scene as drawn at rest (skins by their rest joints, morphs
/// at their default weights: `Scene::as_drawn`), grown by the first animation's motion
/// of its rigid objects ([`animated_bounds`]); `None` when nothing deforms or the posed
/// box is not finite. The undeformed meshes' box can miss a morph's displacement, or
/// lie far from a skin whose bind pose is not its rest pose.
fn posed_bounds(scene: &Scene) -> Option<(Vec3, Vec3)> {
    let deforms = scene.objects.iter().any(|o| {
        scene.meshes.get(o.mesh).is_some_and(|mesh| {
            o.node.is_some() && (mesh.skin.is_some() || !mesh.morph_targets.is_empty())
        })
    });
    if !deforms {
        return None;
    }
    let drawn = scene.as_drawn(None);
    let rest = drawn
        .world_bounds()
        .filter(|(lo, hi)| (*hi - *lo).is_finite())?;
    animated_bounds(&scene.motion, &scene.meshes, &scene.objects, Some(rest))
}

/// The box a framing camera frames for `scene`: [`posed_bounds`] where a mesh deforms,
/// else every object's box grown by the first animation's motion (as the importer frames
/// a file without a camera).
pub(crate) fn framing_bounds(scene: &Scene) -> Option<(Vec3, Vec3)> {
    posed_bounds(scene).or_else(|| {
        animated_bounds(
            &scene.motion,
            &scene.meshes,
            &scene.objects,
            scene.world_bounds(),
        )
    })
}

/// At most this many poses of the first animation are framed ([`animated_bounds`]).
const FRAMED_POSES: usize = 64;
/// ... and at most about this many object placements in all.
const FRAMED_OBJECT_POSES: usize = 1 << 22;

/// Each object's world-space box (`None` for an object whose mesh is missing or has no
/// vertices).
pub(crate) fn object_bounds(
    meshes: &[crate::Mesh],
    objects: &[Object],
) -> Vec<Option<(Vec3, Vec3)>> {
    // Each mesh's own box once, not once per object that places it.
    let boxes: Vec<_> = meshes.iter().map(crate::Mesh::bounds).collect();
    objects
        .iter()
        .map(|object| crate::placed_bounds(*boxes.get(object.mesh)?, &object.transform))
        .collect()
}

/// glTF's nodes form disjoint trees: no node is the child of two nodes, and following
/// children never comes back to a node. Checked over every node, not only those the
/// scene shows.
fn check_node_forest(root: &json::Root) -> Result<(), ImportProblem> {
    let n = root.nodes.len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for (i, node) in root.nodes.iter().enumerate() {
        for child in node.children.iter().flatten() {
            let c = child.value();
            if c >= n {
                return Err(ImportProblem::Invalid(format!(
                    "node {i} names child {c}, but there are {n} nodes"
                )));
            }
            // c < n, checked above.
            if let Some(other) = parent.get_mut(c).and_then(|p| p.replace(i)) {
                return Err(ImportProblem::Invalid(format!(
                    "node {c} is a child of both node {other} and node {i} (glTF nodes form trees)"
                )));
            }
        }
    }
    // With one parent at most, a node no root reaches lies on (or under) a cycle.
    let mut reached = vec![false; n];
    let mut stack: Vec<usize> = (0..n)
        .filter(|&i| parent.get(i).is_some_and(Option::is_none))
        .collect();
    while let Some(i) = stack.pop() {
        if let (Some(flag), Some(node)) = (reached.get_mut(i), root.nodes.get(i)) {
            *flag = true;
            stack.extend(node.children.iter().flatten().map(|c| c.value()));
        }
    }
    if let Some(i) = reached.iter().position(|r| !r) {
        return Err(ImportProblem::Invalid(format!(
            "node {i} is its own ancestor: the node hierarchy has a cycle"
        )));
    }
    Ok(())
}

/// What would make a frame of `camera` black with no error: the scene (its bounding
/// sphere) wholly outside the near … far range, or a near plane so small against the
/// scene's distance that f32 depth rounds every surface to 1, the background (the
/// projection's depth is about 1 − near/z: it needs near/z above 2⁻²³ or so).
pub(crate) fn camera_range_warnings(camera: &Camera, bounds: Option<(Vec3, Vec3)>) -> Vec<String> {
    let Some((lo, hi)) = bounds else {
        return Vec::new();
    };
    let centre = (lo + hi) / 2.0;
    let radius = (hi - lo).length() / 2.0;
    let forward = (camera.target - camera.position).normalize_or_zero();
    let along = (centre - camera.position).dot(forward);
    let (nearest, farthest) = (along - radius, along + radius);
    let mut warnings = Vec::new();
    if farthest < camera.near || nearest > camera.far {
        warnings.push(format!(
            "the scene lies {:.3e} … {:.3e} in front of the camera, outside its near … far range {:.3e} … {:.3e}: the image will be empty",
            nearest, farthest, camera.near, camera.far
        ));
    } else if camera.near < farthest.max(0.0) * 2f32.powi(-22) {
        warnings.push(format!(
            "the camera's near plane ({:.3e}) is below 2⁻²² of the scene's distance ({:.3e}): f32 depth rounds its far part to the background; raise znear",
            camera.near, farthest
        ));
    }
    warnings
}

/// What a light's `COMBUSTION_shadows` says: whether it casts shadows (default
/// true) and its size (`radius` in metres for point and spot lights, `angularDiameter`
/// in radians for directional ones), by the name it was given.
struct LightShadow {
    casts_shadows: bool,
    /// The sizes given, by field name.
    sizes: Vec<(&'static str, f32)>,
}

/// Reads `COMBUSTION_shadows` from a light's raw `extensions` (absent: casts
/// shadows, no size). An error names the field.
fn light_shadow(extensions: Option<&serde_json::value::RawValue>) -> Result<LightShadow, String> {
    let mut shadow = LightShadow {
        casts_shadows: true,
        sizes: Vec::new(),
    };
    let Some(raw) = extensions else {
        return Ok(shadow);
    };
    let value: serde_json::Value = serde_json::from_str(raw.get())
        .map_err(|e| format!("its extensions are not valid JSON: {e}"))?;
    let Some(ext) = value.get(SHADOW_EXTENSION) else {
        return Ok(shadow);
    };
    let ext = ext
        .as_object()
        .ok_or_else(|| format!("{SHADOW_EXTENSION} must be an object"))?;
    for (key, value) in ext {
        match key.as_str() {
            "castsShadows" => shadow.casts_shadows = casts_shadows_field(value)?,
            "radius" | "angularDiameter" => {
                let (name, max) = if key == "radius" {
                    ("radius", crate::MAX_LIGHT_RADIUS)
                } else {
                    ("angularDiameter", crate::MAX_ANGULAR_DIAMETER)
                };
                let size = value
                    .as_f64()
                    .map(|v| v as f32)
                    .filter(|v| v.is_finite() && (0.0..=max).contains(v))
                    .ok_or_else(|| {
                        format!("{SHADOW_EXTENSION}.{name} must be a number from 0 to {max}, not {value}")
                    })?;
                shadow.sizes.push((name, size));
            }
            other => {
                return Err(format!(
                "{SHADOW_EXTENSION} has no field `{other}` (castsShadows, radius, angularDiameter)"
            ))
            }
        }
    }
    Ok(shadow)
}

/// `COMBUSTION_shadows.castsShadows`, on a light or a node: a boolean.
fn casts_shadows_field(value: &serde_json::Value) -> Result<bool, String> {
    value
        .as_bool()
        .ok_or_else(|| format!("{SHADOW_EXTENSION}.castsShadows must be true or false"))
}
