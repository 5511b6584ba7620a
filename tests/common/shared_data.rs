//! The shared sample data beside the workspace (`../shared`), for the tests of every
//! crate: tests/common includes this module, and the member crates' tests include it by
//! path (`#[path = "../../../tests/common/shared_data.rs"]`).

use std::path::{Path, PathBuf};

/// Set (CI sets it) to make a missing `../shared` a failure rather than a skip.
pub const REQUIRE_SHARED: &str = "COMBUSTION_REQUIRE_SHARED";

/// `../shared/data/gltf` beside the workspace (the nearest folder above the crate that
/// holds Cargo.lock), or `None` (with a note on stderr) when it is not there; panics
/// instead when [`REQUIRE_SHARED`] is set.
pub fn shared_gltf_samples() -> Option<PathBuf> {
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let workspace = crate_dir
        .ancestors()
        .find(|d| d.join("Cargo.lock").is_file())
        .unwrap_or(crate_dir);
    let root = workspace.join("../shared/data/gltf");
    if root.is_dir() {
        return Some(root);
    }
    assert!(
        std::env::var_os(REQUIRE_SHARED).is_none(),
        "{} is missing and {REQUIRE_SHARED} is set",
        root.display()
    );
    eprintln!(
        "skipped: {} is not present (the Khronos sample models live in the shared data folder, not in the repository)",
        root.display()
    );
    None
}
