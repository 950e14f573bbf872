//! Helpers shared by lightpick's workspace-level tests.

use std::path::{Path, PathBuf};

/// The workspace root (where `Cargo.toml` and `assets/` live): the manifest folder of the
/// package compiling this file, or, when a member crate's tests include it
/// (`crates/core/tests`), the nearest folder above that holds `tests/snapshots`.
pub fn workspace_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .find(|dir| dir.join("tests").join("snapshots").is_dir())
        .unwrap_or(manifest)
        .to_path_buf()
}

/// Where the golden PNGs live: `tests/snapshots/`.
pub fn snapshot_dir() -> PathBuf {
    workspace_root().join("tests").join("snapshots")
}

/// A pixel differs when any of its RGBA channels differs from the golden by more than this
/// (out of 255). It absorbs anti-aliasing rounding that may differ between CPU
/// architectures, never a moved line or a changed colour.
pub const SNAPSHOT_CHANNEL_TOLERANCE: u8 = 3;

/// A snapshot passes when at most this many pixels differ (beyond the channel tolerance):
/// a few edge pixels, far fewer than one changed glyph (hundreds of pixels).
pub const SNAPSHOT_MAX_DIFFERING_PIXELS: usize = 16;

/// Whether `UPDATE_SNAPSHOTS` asks for goldens to be rewritten (set, and not `0`/`false`).
pub fn update_requested() -> bool {
    std::env::var("UPDATE_SNAPSHOTS").is_ok_and(|v| !v.is_empty() && v != "0" && v != "false")
}

/// The outcome of comparing two equally sized RGBA8 images.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Comparison {
    /// Pixels whose largest channel difference exceeds [`SNAPSHOT_CHANNEL_TOLERANCE`].
    pub differing: usize,
    /// The largest channel difference anywhere.
    pub max_channel_diff: u8,
    /// A visual diff (RGBA8): the golden dimmed to grey, differing pixels red, pixels that
    /// differ within tolerance yellow.
    pub diff_rgba: Vec<u8>,
}

impl Comparison {
    /// Whether the images match under the snapshot tolerance.
    pub fn passes(&self) -> bool {
        self.differing <= SNAPSHOT_MAX_DIFFERING_PIXELS
    }
}

/// Compares two RGBA8 buffers of the same size pixel by pixel.
///
/// # Panics
/// When the buffers differ in length (compare sizes first).
pub fn compare_rgba(golden: &[u8], actual: &[u8]) -> Comparison {
    assert_eq!(golden.len(), actual.len(), "compare_rgba needs equal sizes");
    let mut differing = 0;
    let mut max_channel_diff = 0;
    let mut diff_rgba = Vec::with_capacity(golden.len());
    for (g, a) in golden.chunks_exact(4).zip(actual.chunks_exact(4)) {
        let d = g
            .iter()
            .zip(a)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        max_channel_diff = max_channel_diff.max(d);
        let pixel = if d > SNAPSHOT_CHANNEL_TOLERANCE {
            differing += 1;
            [255, 0, 0, 255]
        } else if d > 0 {
            [255, 210, 0, 255]
        } else {
            let grey = ((u32::from(g[0]) + u32::from(g[1]) + u32::from(g[2])) / 3) as u8;
            let dim = 160 + grey / 3;
            [dim, dim, dim, 255]
        };
        diff_rgba.extend_from_slice(&pixel);
    }
    Comparison {
        differing,
        max_channel_diff,
        diff_rgba,
    }
}

fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    image::save_buffer(path, rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Compares an RGBA8 image with the golden `tests/snapshots/{name}.png`.
///
/// * A match (see [`SNAPSHOT_CHANNEL_TOLERANCE`], [`SNAPSHOT_MAX_DIFFERING_PIXELS`])
///   removes stale `{name}.new.png` / `{name}.diff.png` files.
/// * A mismatch writes `{name}.new.png` (the actual image) and, when sizes agree,
///   `{name}.diff.png` next to the golden, and returns a message naming them.
/// * A missing golden is an error too (with the candidate written as `{name}.new.png`).
/// * With `UPDATE_SNAPSHOTS=1` the golden is (re)written whenever it is missing or differs
///   at all, and the check passes.
pub fn check_snapshot(name: &str, width: u32, height: u32, rgba: &[u8]) -> Result<(), String> {
    let dir = snapshot_dir();
    let golden_path = dir.join(format!("{name}.png"));
    let new_path = dir.join(format!("{name}.new.png"));
    let diff_path = dir.join(format!("{name}.diff.png"));
    let clean = || {
        // Stale artefacts of an earlier failure; absence is fine.
        let _ = std::fs::remove_file(&new_path);
        let _ = std::fs::remove_file(&diff_path);
    };
    let golden = image::open(&golden_path).ok().map(|g| g.to_rgba8());

    if update_requested() {
        let same = golden
            .as_ref()
            .is_some_and(|g| g.dimensions() == (width, height) && g.as_raw().as_slice() == rgba);
        if !same {
            write_png(&golden_path, width, height, rgba)?;
        }
        clean();
        return Ok(());
    }

    let Some(golden) = golden else {
        write_png(&new_path, width, height, rgba)?;
        return Err(format!(
            "snapshot '{name}': no golden at {}. The drawing was written to {}; look at it, \
             then accept it with `UPDATE_SNAPSHOTS=1 cargo test --test draw_snapshots`.",
            golden_path.display(),
            new_path.display()
        ));
    };
    if golden.dimensions() != (width, height) {
        write_png(&new_path, width, height, rgba)?;
        let (gw, gh) = golden.dimensions();
        return Err(format!(
            "snapshot '{name}': size {width}×{height} differs from the golden's {gw}×{gh} \
             ({}). New image: {}. If the change is intended, rerun with UPDATE_SNAPSHOTS=1.",
            golden_path.display(),
            new_path.display()
        ));
    }
    let cmp = compare_rgba(golden.as_raw(), rgba);
    if cmp.passes() {
        clean();
        return Ok(());
    }
    write_png(&new_path, width, height, rgba)?;
    write_png(&diff_path, width, height, &cmp.diff_rgba)?;
    Err(format!(
        "snapshot '{name}': {} pixels differ from {} by more than {SNAPSHOT_CHANNEL_TOLERANCE}/255 \
         (allowed: {SNAPSHOT_MAX_DIFFERING_PIXELS}; largest channel difference {}). \
         New image: {}; differences in red: {}. If the change is intended, rerun with \
         UPDATE_SNAPSHOTS=1.",
        cmp.differing,
        golden_path.display(),
        cmp.max_channel_diff,
        new_path.display(),
        diff_path.display()
    ))
}

/// [`check_snapshot`], panicking with its message on failure.
///
/// # Panics
/// When the image does not match its golden (or the golden is missing).
pub fn assert_snapshot(name: &str, width: u32, height: u32, rgba: &[u8]) {
    if let Err(message) = check_snapshot(name, width, height, rgba) {
        panic!("{message}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerance_counts_only_large_differences() {
        let golden = [10, 10, 10, 255, 0, 0, 0, 255, 50, 50, 50, 255];
        let actual = [
            10,
            10,
            10,
            255,
            SNAPSHOT_CHANNEL_TOLERANCE,
            0,
            0,
            255,
            50,
            50 + SNAPSHOT_CHANNEL_TOLERANCE + 1,
            50,
            255,
        ];
        let cmp = compare_rgba(&golden, &actual);
        assert_eq!(cmp.differing, 1);
        assert_eq!(cmp.max_channel_diff, SNAPSHOT_CHANNEL_TOLERANCE + 1);
        assert_eq!(&cmp.diff_rgba[4..8], &[255, 210, 0, 255]);
        assert_eq!(&cmp.diff_rgba[8..12], &[255, 0, 0, 255]);
        assert!(cmp.passes());
    }

    #[test]
    fn many_differing_pixels_fail() {
        let golden = vec![0u8; 4 * (SNAPSHOT_MAX_DIFFERING_PIXELS + 1)];
        let actual = vec![200u8; golden.len()];
        let cmp = compare_rgba(&golden, &actual);
        assert_eq!(cmp.differing, SNAPSHOT_MAX_DIFFERING_PIXELS + 1);
        assert!(!cmp.passes());
    }
}
