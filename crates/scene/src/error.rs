/// Why a scene can't be built or used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("unknown built-in scene `{name}`; built-in scenes: {known}")]
    UnknownBuiltin { name: String, known: String },
    #[error("invalid scene: {0}")]
    Invalid(String),
    #[error("environment image {path}: {reason}")]
    EnvironmentImage { path: String, reason: String },
}
