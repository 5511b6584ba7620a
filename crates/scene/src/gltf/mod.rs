//! glTF 2.0 import and export (CPU side): `.gltf` (+ `.bin`, images) and `.glb` into a
//! [`Scene`], and a [`Scene`] back to `.gltf`. The mapping, the units and the project
//! extension `COMBUSTION_materials_optics` are documented in `docs/gltf.md`.
//!
//! glTF's conventions are Combustion's (right-handed, y up, metres, linear RGB factors,
//! texture coordinates with v down), so positions, directions and colours are taken as
//! they are.
//!
//! Import never panics on bad input and never returns a half-built scene: every problem
//! is an [`ImportError`] naming the file and what is wrong; recoverable oddities
//! (degenerate triangles, unknown optional extensions, ...) are `log::warn!`ed and listed
//! in [`ImportReport::warnings`]. The scene returned has passed [`Scene::validate`].

mod accessor;
mod animation;
mod counts;
mod error;
mod geometry;
mod image;
pub use image::png_error_message;
pub(crate) mod import;
mod material;
mod optics_ext;
mod source;
mod spec_gloss;
mod writer;

pub use source::{read_regular_file, read_text};

use std::fmt;
use std::path::{Path, PathBuf};

pub use error::{ImportError, ImportProblem, SaveError, SaveProblem};
pub use material::KHR_IOR_ZERO_MEANS;
pub use writer::save_gltf;

use crate::Scene;

/// Name of the project extension (materials and scene level), see `docs/gltf.md`.
pub const OPTICS_EXTENSION: &str = "COMBUSTION_materials_optics";

/// Name of the project's shadow extension: on a KHR_lights_punctual light, whether it
/// casts shadows and its size; on a node, whether its mesh casts shadows. See
/// `docs/gltf.md`.
pub const SHADOW_EXTENSION: &str = "COMBUSTION_shadows";

/// Extensions the importer understands; a file that *requires* any other is refused.
pub const SUPPORTED_EXTENSIONS: &[&str] = &[
    SHADOW_EXTENSION,
    "EXT_mesh_gpu_instancing",
    "EXT_texture_webp",
    "KHR_lights_punctual",
    "KHR_materials_ior",
    "KHR_materials_specular",
    "KHR_materials_emissive_strength",
    "KHR_materials_anisotropy",
    "KHR_materials_clearcoat",
    "KHR_materials_iridescence",
    "KHR_materials_pbrSpecularGlossiness",
    "KHR_materials_sheen",
    "KHR_materials_unlit",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_mesh_quantization",
    "KHR_texture_transform",
    OPTICS_EXTENSION,
];

/// What the importer may do.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ImportOptions {
    /// Images wider or taller than this many pixels are refused (before decoding).
    pub max_image_dimension: u32,
    /// Allow URIs that leave the scene's folder (`../`), absolute paths and `file:` URIs.
    /// Network schemes (`http:` ...) are refused regardless; `data:` URIs and relative
    /// paths inside the scene's folder are always allowed.
    pub allow_external_uris: bool,
    /// Index into the glTF `cameras` array of the camera to use (it must be a
    /// perspective camera placed by a node of the scene, or the import fails with
    /// [`ImportProblem::Camera`]); `None`: the lowest-numbered perspective camera placed
    /// in the scene, else a camera framing the scene.
    pub camera: Option<usize>,
    /// How the RGB η, k of a `COMBUSTION_materials_optics` conductor given by a
    /// measured spectrum (`metal` or `spectrum`) are derived, where the material does not
    /// say (`conductor.colour`): the rendering notes' bands by default.
    pub metal_colour: combustion_spectra::MetalColour,
    /// Largest file read (the glTF itself, each buffer, image and spectral table), in
    /// bytes, checked before reading. Only regular files are read: a device, FIFO or
    /// socket is refused without being opened.
    pub max_file_bytes: u64,
    /// Largest total of image pixels held (width × height summed over the scene's
    /// images: each distinct image source once per colour space it is used in; it is
    /// decoded once, however many images name it, and its first use keeps the decoded
    /// pixels themselves). A decode under way counts too: an image is decoded only if
    /// its decoder's peak memory, read from its header and counted in pixels of 4
    /// bytes (4.5× its pixels for a progressive RGB JPEG), fits beside the pixels
    /// already held.
    pub max_decoded_pixels: u64,
}

impl Default for ImportOptions {
    fn default() -> Self {
        Self {
            max_image_dimension: 8192,
            allow_external_uris: false,
            camera: None,
            metal_colour: combustion_spectra::MetalColour::Bands,
            // 2 GiB: more than any glTF buffer or image a real scene ships.
            max_file_bytes: 1 << 31,
            // 2²⁸ pixels (1 GiB as RGBA8): sixteen 4096² images.
            max_decoded_pixels: 1 << 28,
        }
    }
}

/// Where the scene's camera came from.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum CameraSource {
    /// A camera of the file, placed by a node of the scene.
    Gltf {
        /// Index into the file's `cameras` array.
        index: usize,
        /// Index into the file's `nodes` array of the node placing it.
        node: usize,
    },
    /// No usable camera in the file: one looking at the scene's bounding box.
    #[default]
    Framing,
}

/// What an import found and did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportReport {
    /// The file imported (`<memory>` for [`import_slice`]).
    pub file: PathBuf,
    /// `asset.generator` of the file.
    pub generator: Option<String>,
    /// Meshes of the scene (one per distinct glTF primitive used).
    pub meshes: usize,
    /// Triangles in those meshes (each mesh counted once), after dropping degenerate ones.
    pub triangles: usize,
    /// Triangles drawn: every object's mesh counted.
    pub instanced_triangles: usize,
    /// Objects of the scene (placed primitives; those with a singular transform are left
    /// out, with a warning).
    pub objects: usize,
    /// Materials of the scene: those the placed primitives use, plus glTF's default
    /// material when a primitive names none.
    pub materials: usize,
    /// Distinct decoded images (an image used both as colour and as data counts twice).
    pub images: usize,
    /// Distinct (image, sampler) textures.
    pub textures: usize,
    /// Lights of the scene (KHR_lights_punctual lights placed by nodes, each placement
    /// counted).
    pub lights: usize,
    /// Cameras defined in the file.
    pub cameras: usize,
    /// The perspective cameras placed in the scene, in (camera, node) order; the scene's
    /// camera is one of them unless it frames the scene. Each was checked at import
    /// (a placed camera with bad parameters or placement refuses the file, with
    /// [`ImportProblem::Camera`]); orthographic cameras are not supported and not listed.
    pub scene_cameras: Vec<PlacedCamera>,
    /// Where the scene's camera came from.
    pub camera: CameraSource,
    /// The file's `extensionsUsed`.
    pub extensions_used: Vec<String>,
    /// The file's `extensionsRequired` (all of them supported, or the import fails).
    pub extensions_required: Vec<String>,
    /// Optional extensions the importer does not understand and ignored.
    pub extensions_ignored: Vec<String>,
    /// Degenerate (zero-area) triangles dropped.
    pub degenerate_triangles: usize,
    /// Primitives whose normals were generated (flat, glTF's rule) or repaired.
    pub generated_normals: usize,
    /// Primitives whose tangents were generated with MikkTSpace.
    pub generated_tangents: usize,
    /// Everything the importer let pass with a change or an omission, one message
    /// each, in the order found (also logged with `log::warn!`).
    pub warnings: Vec<String>,
}

/// A glTF camera placed by a node of the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedCamera {
    /// Index into the file's `cameras` array.
    pub index: usize,
    /// Index into the file's `nodes` array of the node placing it.
    pub node: usize,
    /// The glTF camera's `name`, if it has one.
    pub name: Option<String>,
    /// The view it gives: the node's world position, looking along its −Z axis with its
    /// +Y up; `yfov`, `znear` and `zfar` as given (an infinite projection gets a far
    /// plane 1.5 times as far as the scene's farthest bounding-box corner).
    pub camera: crate::Camera,
}

impl fmt::Display for ImportReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "file: {}", self.file.display())?;
        if let Some(generator) = &self.generator {
            writeln!(f, "generator: {generator}")?;
        }
        writeln!(
            f,
            "meshes: {} ({} triangles; {} drawn), objects: {}",
            self.meshes, self.triangles, self.instanced_triangles, self.objects
        )?;
        writeln!(
            f,
            "materials: {}, textures: {}, images: {}",
            self.materials, self.textures, self.images
        )?;
        writeln!(
            f,
            "lights: {}, cameras in file: {}",
            self.lights, self.cameras
        )?;
        match self.camera {
            CameraSource::Gltf { index, node } => {
                writeln!(f, "camera: glTF camera {index} (node {node})")?
            }
            CameraSource::Framing => writeln!(f, "camera: framing the scene's bounds")?,
        }
        let list = |v: &[String]| {
            if v.is_empty() {
                "none".to_owned()
            } else {
                v.join(", ")
            }
        };
        writeln!(f, "extensions used: {}", list(&self.extensions_used))?;
        writeln!(
            f,
            "extensions required: {}",
            list(&self.extensions_required)
        )?;
        writeln!(f, "extensions ignored: {}", list(&self.extensions_ignored))?;
        writeln!(
            f,
            "generated: normals for {} primitive(s), tangents for {}; {} degenerate triangle(s) dropped",
            self.generated_normals, self.generated_tangents, self.degenerate_triangles
        )?;
        write!(f, "warnings: {}", self.warnings.len())?;
        for warning in &self.warnings {
            write!(f, "\n  {warning}")?;
        }
        Ok(())
    }
}

/// Imports a `.gltf` (with its `.bin` and image files) or a `.glb` file. The format is
/// told by the content (GLB magic), not by the extension.
pub fn import(path: &Path, options: &ImportOptions) -> Result<(Scene, ImportReport), ImportError> {
    let bytes = source::read_regular_file(path, options.max_file_bytes, source::SCENE_FILE)
        .map_err(|e| ImportError::new(path, ImportProblem::Io(e)))?;
    let base = path.parent().map(|p| {
        if p.as_os_str().is_empty() {
            PathBuf::from(".")
        } else {
            p.to_path_buf()
        }
    });
    import::import_bytes(&bytes, path, base.as_deref(), options)
}

/// Imports glTF JSON or GLB from memory. Relative URIs cannot be resolved (there is no
/// folder): only `data:` URIs and the GLB's binary chunk can supply buffers and images.
pub fn import_slice(
    bytes: &[u8],
    options: &ImportOptions,
) -> Result<(Scene, ImportReport), ImportError> {
    import::import_bytes(bytes, Path::new("<memory>"), None, options)
}
