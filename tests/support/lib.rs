//! Helpers shared by lightpick's workspace-level tests.

use std::path::PathBuf;

/// The workspace root (where `Cargo.toml` and `assets/` live).
pub fn workspace_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}
