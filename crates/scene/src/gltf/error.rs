use std::path::{Path, PathBuf};

use crate::SceneError;

/// Why a glTF file could not be imported: the file and the problem.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", file.display())]
pub struct ImportError {
    /// The `.gltf`/`.glb` file being imported (`<memory>` for `import_slice`).
    pub file: PathBuf,
    /// What is wrong.
    pub problem: ImportProblem,
}

impl ImportError {
    pub(crate) fn new(file: &Path, problem: ImportProblem) -> Self {
        Self {
            file: file.to_path_buf(),
            problem,
        }
    }
}

/// What is wrong with a glTF file. Each message names the glTF object (by index and, when
/// it has one, by name) and the problem.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportProblem {
    /// The glTF or GLB file itself cannot be read: missing, not a regular file, or
    /// larger than [`ImportOptions::max_file_bytes`](super::ImportOptions::max_file_bytes).
    #[error("cannot read the file: {0}")]
    Io(#[source] std::io::Error),
    /// The JSON does not parse as glTF (the message says where; a truncated file says so).
    #[error("malformed JSON: {0}")]
    Json(String),
    /// The GLB container is broken: its header, version or chunks.
    #[error("malformed GLB: {0}")]
    Glb(String),
    /// The file breaks a rule of glTF 2.0 (its schema, an index out of range, a node
    /// hierarchy that is not a forest, ...) or asks for more than the importer takes
    /// (too many materials or objects); the message names the place.
    #[error("invalid glTF: {0}")]
    Invalid(String),
    /// The file requires an extension the importer does not understand
    /// ([`SUPPORTED_EXTENSIONS`](super::SUPPORTED_EXTENSIONS)).
    #[error(
        "requires the extension `{name}`, which Combustion does not support (supported: {supported})"
    )]
    UnsupportedExtension {
        /// The extension required.
        name: String,
        /// The supported extensions, comma-separated.
        supported: String,
    },
    /// A URI was not followed: it leaves the scene's folder, is absolute or a `file:`
    /// URI without [`ImportOptions::allow_external_uris`](super::ImportOptions::allow_external_uris),
    /// uses a network scheme, is a malformed data URI, or cannot be resolved (from memory).
    #[error("URI `{uri}` refused: {reason}")]
    UriRefused {
        /// The URI as the file gives it (shortened when very long).
        uri: String,
        /// Why it was refused.
        reason: String,
    },
    /// A file a URI names (a buffer, image or spectral table) cannot be read: missing,
    /// not a regular file, or larger than
    /// [`ImportOptions::max_file_bytes`](super::ImportOptions::max_file_bytes).
    #[error("cannot read `{uri}` ({}): {source}", path.display())]
    ExternalIo {
        /// The URI as the file gives it.
        uri: String,
        /// The path it resolved to.
        path: PathBuf,
        /// The error reading it.
        #[source]
        source: std::io::Error,
    },
    /// A buffer does not exist, has no data (no URI and no GLB binary chunk), or is
    /// shorter than its `byteLength`. (Found while reading an accessor or an image, such
    /// a problem currently reaches the caller inside that [`ImportProblem::Primitive`]'s
    /// or [`ImportProblem::Image`]'s message, in this variant's words.)
    #[error("buffer {index}: {message}")]
    Buffer {
        /// Index into the file's `buffers`.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// A mesh primitive cannot be built: a missing or malformed attribute or index
    /// accessor (its type, its byte range in its buffer view, the view's range in its
    /// buffer, the buffer itself, its sparse values), attributes of different lengths, a
    /// non-finite attribute value, an index out of range, only degenerate triangles, or
    /// more mesh data than the file may ask for. The message names the attribute and
    /// the accessor where one is at fault.
    #[error("mesh {mesh}{} primitive {primitive}: {message}", name_suffix(name))]
    Primitive {
        /// Index into the file's `meshes`.
        mesh: usize,
        /// The mesh's `name`, if any.
        name: Option<String>,
        /// Index into the mesh's `primitives`.
        primitive: usize,
        /// What is wrong.
        message: String,
    },
    /// An image cannot be used: its data cannot be read (URI, buffer view), it is
    /// undecodable or not PNG or JPEG, or it takes the decoded pixels over
    /// [`ImportOptions::max_decoded_pixels`](super::ImportOptions::max_decoded_pixels).
    #[error("image {index}{}: {message}", name_suffix(name))]
    Image {
        /// Index into the file's `images`.
        index: usize,
        /// The image's `name`, if any.
        name: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// An image is wider or taller than
    /// [`ImportOptions::max_image_dimension`](super::ImportOptions::max_image_dimension)
    /// (found from its header, before decoding).
    #[error(
        "image {index}{} is {width}×{height} pixels, larger than the limit of {limit} per side",
        name_suffix(name)
    )]
    ImageTooLarge {
        /// Index into the file's `images`.
        index: usize,
        /// The image's `name`, if any.
        name: Option<String>,
        /// Its width, pixels.
        width: u32,
        /// Its height, pixels.
        height: u32,
        /// The limit per side, pixels.
        limit: u32,
    },
    /// A material's values, textures or extensions are out of range or malformed.
    #[error("material {index}{}: {message}", name_suffix(name))]
    Material {
        /// Index into the file's `materials`.
        index: usize,
        /// The material's `name`, if any.
        name: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A node's transform is not finite (its own or its world transform), its rotation
    /// is not a quaternion, it is reached twice, or it places a mesh beyond what f32
    /// holds.
    #[error("node {index}{}: {message}", name_suffix(name))]
    Node {
        /// Index into the file's `nodes`.
        index: usize,
        /// The node's `name`, if any.
        name: Option<String>,
        /// What is wrong.
        message: String,
    },
    /// A camera cannot be used. Every perspective camera placed in the scene is checked
    /// at import, used or not: `yfov` in (0, π), `znear` finite and above 0, `zfar`
    /// (if given) finite and above `znear`, `aspectRatio` (if given) finite and above 0,
    /// and a placing node whose world transform is finite and invertible. Also the
    /// camera [`ImportOptions::camera`](super::ImportOptions::camera) asks for when it
    /// does not exist, is orthographic or is not placed.
    #[error("camera {index}: {message}")]
    Camera {
        /// Index into the file's `cameras`.
        index: usize,
        /// What is wrong (naming the node, for a problem of the placement).
        message: String,
    },
    /// A KHR_lights_punctual light placed in the scene has a negative or non-finite
    /// power, a bad range or cone angles, or a placement that gives it no direction.
    #[error("light {index}: {message}")]
    Light {
        /// Index into the file's KHR_lights_punctual `lights`.
        index: usize,
        /// What is wrong.
        message: String,
    },
    /// The scene built fails [`Scene::validate`](crate::Scene::validate) (a check the
    /// importer's own did not catch first).
    #[error("the imported scene is invalid: {}", invalid_reason(.0))]
    Scene(#[source] SceneError),
    /// The importer panicked (a bug); the panic's message.
    #[error("internal error in the importer (a bug; please report it with this file): {0}")]
    Internal(String),
}

/// What makes an imported scene invalid, said once ("invalid scene" is the sentence's
/// start already).
fn invalid_reason(error: &SceneError) -> String {
    match error {
        SceneError::Invalid(reason) => reason.clone(),
        other => other.to_string(),
    }
}

fn name_suffix(name: &Option<String>) -> String {
    match name {
        Some(name) if !name.is_empty() => format!(" (`{name}`)"),
        _ => String::new(),
    }
}

/// Why a scene could not be saved as glTF.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", file.display())]
pub struct SaveError {
    /// The file being written (the `.gltf`, its `.bin` or an image).
    pub file: PathBuf,
    /// What went wrong.
    pub problem: SaveProblem,
}

/// What went wrong while saving.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SaveProblem {
    /// The scene fails [`Scene::validate`](crate::Scene::validate); nothing is written.
    #[error("the scene is invalid: {0}")]
    Scene(#[source] SceneError),
    /// The scene or path holds something glTF output cannot (a mesh without triangles,
    /// a path without a file name, ...).
    #[error("{0}")]
    Unsupported(String),
    /// Writing a file failed.
    #[error("cannot write: {0}")]
    Io(#[source] std::io::Error),
    /// An image could not be encoded as PNG.
    #[error("cannot encode the image as PNG: {0}")]
    Png(String),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An imported scene that fails the scene's own check says "invalid" once; other
    /// scene errors keep their own words.
    #[test]
    fn an_invalid_imported_scene_is_said_invalid_once() {
        let invalid = ImportProblem::Scene(SceneError::Invalid(
            "material `m`: conductor η must be positive".into(),
        ));
        assert_eq!(
            invalid.to_string(),
            "the imported scene is invalid: material `m`: conductor η must be positive"
        );
        let camera = ImportProblem::Scene(SceneError::InvalidCamera(
            crate::CameraProblem::FieldOfView(0.0),
        ));
        assert!(
            camera
                .to_string()
                .starts_with("the imported scene is invalid: invalid camera: "),
            "{camera}"
        );
    }
}
