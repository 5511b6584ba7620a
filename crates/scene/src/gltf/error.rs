use std::path::{Path, PathBuf};

use crate::SceneError;

/// Why a glTF file could not be imported: the file and the problem.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", file.display())]
pub struct ImportError {
    /// The `.gltf`/`.glb` file being imported (`<memory>` for `import_slice`).
    pub file: PathBuf,
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
    #[error("cannot read the file: {0}")]
    Io(#[source] std::io::Error),
    #[error("malformed JSON: {0}")]
    Json(String),
    #[error("malformed GLB: {0}")]
    Glb(String),
    #[error("invalid glTF: {0}")]
    Invalid(String),
    #[error(
        "requires the extension `{name}`, which Combustion does not support (supported: {supported})"
    )]
    UnsupportedExtension { name: String, supported: String },
    #[error("URI `{uri}` refused: {reason}")]
    UriRefused { uri: String, reason: String },
    #[error("cannot read `{uri}` ({}): {source}", path.display())]
    ExternalIo {
        uri: String,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("buffer {index}: {message}")]
    Buffer { index: usize, message: String },
    #[error("mesh {mesh}{} primitive {primitive}: {message}", name_suffix(name))]
    Primitive {
        mesh: usize,
        name: Option<String>,
        primitive: usize,
        message: String,
    },
    #[error("image {index}{}: {message}", name_suffix(name))]
    Image {
        index: usize,
        name: Option<String>,
        message: String,
    },
    #[error(
        "image {index}{} is {width}×{height} pixels, larger than the limit of {limit} per side (ImportOptions::max_image_dimension)",
        name_suffix(name)
    )]
    ImageTooLarge {
        index: usize,
        name: Option<String>,
        width: u32,
        height: u32,
        limit: u32,
    },
    #[error("material {index}{}: {message}", name_suffix(name))]
    Material {
        index: usize,
        name: Option<String>,
        message: String,
    },
    #[error("node {index}{}: {message}", name_suffix(name))]
    Node {
        index: usize,
        name: Option<String>,
        message: String,
    },
    #[error("camera {index}: {message}")]
    Camera { index: usize, message: String },
    #[error("light {index}: {message}")]
    Light { index: usize, message: String },
    #[error("the imported scene is invalid: {0}")]
    Scene(#[source] SceneError),
    #[error("internal error in the importer (a bug; please report it with this file): {0}")]
    Internal(String),
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
    pub problem: SaveProblem,
}

/// What went wrong while saving.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SaveProblem {
    #[error("the scene is invalid: {0}")]
    Scene(#[source] SceneError),
    #[error("{0}")]
    Unsupported(String),
    #[error("cannot write: {0}")]
    Io(#[source] std::io::Error),
    #[error("cannot encode the image as PNG: {0}")]
    Png(String),
}
