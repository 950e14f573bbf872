//! Writing a file without ever leaving a half-written one in place of a good one.
//!
//! [`write_atomically`] writes to a temporary file in the target's own folder (so the rename
//! stays on one file system), flushes it to disk, then renames it over the target: a reader
//! sees the old file or the new one, never a part. If anything fails (a full disk, a
//! read-only folder, a writer that errs halfway) the temporary file is removed and the old
//! file is untouched. Scene files, the app's exports (PNG, GIF, EXR, CSV), `render --stats`
//! and the app's saved session all go through it.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU32, Ordering};

/// Distinguishes the temporary files of writes running at once in one process.
static NEXT: AtomicU32 = AtomicU32::new(0);

/// The temporary file a write of `path` goes through: `.NAME.PID-K.tmp` beside it.
fn temporary_beside(path: &Path) -> io::Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("{} names no file", path.display()),
        )
    })?;
    let k = NEXT.fetch_add(1, Ordering::Relaxed);
    let temporary = format!(".{}.{}-{k}.tmp", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(temporary))
}

/// Writes `path` through `write` (given a buffered writer over a temporary file beside
/// `path`), then renames the temporary file over `path`. On any error the temporary file is
/// removed, `path` keeps its old contents (or stays absent), and the error says what failed.
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    let temporary = temporary_beside(path)?;
    let result = (|| {
        let file = File::create(&temporary)?;
        let mut writer = BufWriter::new(file);
        write(&mut writer)?;
        let file = writer
            .into_inner()
            .map_err(io::IntoInnerError::into_error)?;
        file.sync_all()?;
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// [`write_atomically`] of `bytes`.
pub fn write_bytes_atomically(path: &Path, bytes: &[u8]) -> io::Result<()> {
    write_atomically(path, |w| w.write_all(bytes))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("lightpick-atomic-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("readable")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn a_write_replaces_the_file_whole() {
        let dir = scratch("whole");
        let path = dir.join("scene.json");
        write_bytes_atomically(&path, b"old").expect("written");
        write_bytes_atomically(&path, b"new contents").expect("written");
        assert_eq!(std::fs::read(&path).expect("read"), b"new contents");
        assert_eq!(entries(&dir), ["scene.json"], "no temporary file left");
    }

    #[test]
    fn a_write_that_fails_halfway_leaves_the_old_file_and_no_temporary() {
        let dir = scratch("halfway");
        let path = dir.join("images.png");
        write_bytes_atomically(&path, b"the good file").expect("written");
        let err = write_atomically(&path, |w| {
            w.write_all(b"half of a new")?;
            Err(io::Error::new(
                io::ErrorKind::StorageFull,
                "no space left on device",
            ))
        })
        .expect_err("the writer failed");
        assert_eq!(err.kind(), io::ErrorKind::StorageFull);
        assert_eq!(std::fs::read(&path).expect("read"), b"the good file");
        assert_eq!(entries(&dir), ["images.png"]);
    }

    #[test]
    fn a_folder_that_cannot_take_the_file_is_an_error_and_writes_nothing() {
        let dir = scratch("missing");
        let err = write_bytes_atomically(&dir.join("no-such-folder/x.png"), b"x")
            .expect_err("no such folder");
        assert_eq!(err.kind(), io::ErrorKind::NotFound);
        // A folder in the target's place: the rename is refused, nothing is left behind.
        std::fs::create_dir(dir.join("taken")).expect("a folder");
        assert!(write_bytes_atomically(&dir.join("taken"), b"x").is_err());
        assert_eq!(entries(&dir), ["taken"]);
        assert!(write_bytes_atomically(Path::new("/"), b"x").is_err());
    }
}
