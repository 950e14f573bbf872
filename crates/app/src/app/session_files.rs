//! The session's files on disk, in eframe's storage folder (`eframe::storage_dir("lightpick")`,
//! e.g. `~/.local/share/lightpick`): eframe's own `app.ron` (the settings, the layout, a small
//! scene) and, beside it, the last scene of any size in a compact file.
//!
//! - **A scene of any size comes back.** A scene too large for `app.ron` (over
//!   `PERSIST_SCENE_LIMIT` lights) that is not an unedited preset is written to
//!   [`SCENE_FILE`], atomically (`lightpick_core::atomic_file::write_bytes_atomically`),
//!   each time the session is saved with a new scene: a header line of JSON (name,
//!   plane, light count) and the positions and powers as little-endian `f64`s, 32 bytes a
//!   light (a scene with spots, ranges or names is kept as lightpick JSON instead). It is
//!   read back at the next start.
//! - **A damaged session is reported, never dropped in silence.** eframe starts on empty
//!   storage when `app.ron` cannot be parsed; [`damaged_session`] reads the file itself, and
//!   when it holds something that does not parse, moves it aside
//!   (`app.ron.damaged-SECONDS`) before eframe overwrites it, and says why.
//! - **The session is written whole or not at all.** eframe writes `app.ron` in place; each
//!   save also writes lightpick's keys to [`SESSION_COPY`] atomically, and a start whose
//!   `app.ron` is damaged restores from that copy.

use std::io::Read as _;
use std::path::{Path, PathBuf};

use lightpick_core::LightPowers;
use lightpick_core::atomic_file::write_atomically;
use lightpick_core::scene::{ReceiverPlane, Scene};

/// The compact scene file's name in the session folder.
pub const SCENE_FILE: &str = "last-scene.lpscene";
/// The session's own copy of what lightpick keeps in eframe's storage, written whole or not
/// at all (eframe writes `app.ron` in place): what the app restores when `app.ron` is
/// damaged.
pub const SESSION_COPY: &str = "session.json";
/// eframe's session file in its storage folder.
const RON_FILE: &str = "app.ron";
/// The first line of a compact scene file (point lights, raw `f64`s).
const BINARY_MAGIC: &[u8] = b"lightpick scene 1 binary\n";
/// The first line of a compact scene file holding lightpick JSON.
const JSON_MAGIC: &[u8] = b"lightpick scene 1 json\n";

/// The session folder of the desktop app, when the platform has one.
pub fn default_session_dir() -> Option<PathBuf> {
    eframe::storage_dir("lightpick")
}

/// What the binary form's header line holds.
#[derive(serde::Serialize, serde::Deserialize)]
struct Header {
    name: String,
    plane: ReceiverPlane,
    count: usize,
}

/// Writes `scene` to `path` atomically: positions and powers as raw little-endian `f64`s for
/// point lights, lightpick JSON when the scene has spots, ranges or names.
pub fn write_scene(path: &Path, scene: &Scene) -> std::io::Result<()> {
    if scene.emission.is_some() || scene.names.is_some() {
        let json = scene.to_json();
        return write_atomically(path, |w| {
            w.write_all(JSON_MAGIC)?;
            w.write_all(json.as_bytes())
        });
    }
    let header = Header {
        name: scene.name.clone(),
        plane: scene.plane.clone(),
        count: scene.light_count(),
    };
    let header = serde_json::to_string(&header).map_err(std::io::Error::other)?;
    write_atomically(path, |w| {
        w.write_all(BINARY_MAGIC)?;
        w.write_all(header.as_bytes())?;
        w.write_all(b"\n")?;
        for p in scene.positions.iter() {
            for v in [p.x, p.y, p.z] {
                w.write_all(&v.to_le_bytes())?;
            }
        }
        for v in scene.powers.as_slice() {
            w.write_all(&v.to_le_bytes())?;
        }
        Ok(())
    })
}

/// Reads a scene written by [`write_scene`]; the error names the file and what is wrong.
pub fn read_scene(path: &Path) -> Result<Scene, String> {
    let fail = |what: String| format!("{}: {what}", path.display());
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| fail(e.to_string()))?;
    if let Some(json) = bytes.strip_prefix(JSON_MAGIC) {
        let text = std::str::from_utf8(json).map_err(|e| fail(e.to_string()))?;
        return Scene::from_json_str(text).map_err(|e| fail(e.to_string()));
    }
    let rest = bytes
        .strip_prefix(BINARY_MAGIC)
        .ok_or_else(|| fail("not a lightpick scene file".to_owned()))?;
    let end = rest
        .iter()
        .position(|&b| b == b'\n')
        .ok_or_else(|| fail("no header line".to_owned()))?;
    let header: Header =
        serde_json::from_slice(&rest[..end]).map_err(|e| fail(format!("header: {e}")))?;
    let body = &rest[end + 1..];
    let n = header.count;
    if body.len() != n * 32 {
        return Err(fail(format!(
            "{} bytes of lights where {n} lights need {} (a cut file)",
            body.len(),
            n * 32
        )));
    }
    let float = |k: usize| {
        let mut word = [0u8; 8];
        word.copy_from_slice(&body[8 * k..8 * k + 8]);
        f64::from_le_bytes(word)
    };
    let positions: Vec<glam::DVec3> = (0..n)
        .map(|i| glam::dvec3(float(3 * i), float(3 * i + 1), float(3 * i + 2)))
        .collect();
    let powers: Vec<f64> = (0..n).map(|i| float(3 * n + i)).collect();
    let powers = LightPowers::new(powers).map_err(|e| fail(e.to_string()))?;
    Ok(Scene::new(header.name, header.plane, positions, powers))
}

/// Writes the session's keys to [`SESSION_COPY`] in `dir`, atomically.
pub fn write_session_copy(
    dir: &Path,
    keys: &std::collections::BTreeMap<String, String>,
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let json = serde_json::to_vec(keys).map_err(std::io::Error::other)?;
    lightpick_core::atomic_file::write_bytes_atomically(&dir.join(SESSION_COPY), &json)
}

/// The session's keys from [`SESSION_COPY`] in `dir`, when it is there and reads.
pub fn read_session_copy(dir: &Path) -> Option<std::collections::BTreeMap<String, String>> {
    let bytes = std::fs::read(dir.join(SESSION_COPY)).ok()?;
    serde_json::from_slice(&bytes).ok()
}

/// eframe's storage as a map of keys (what the session copy restores through).
#[derive(Debug, Default)]
pub struct MapStorage(pub std::collections::BTreeMap<String, String>);

impl eframe::Storage for MapStorage {
    fn get_string(&self, key: &str) -> Option<String> {
        self.0.get(key).cloned()
    }
    fn set_string(&mut self, key: &str, value: String) {
        self.0.insert(key.to_owned(), value);
    }
    fn remove_string(&mut self, key: &str) {
        self.0.remove(key);
    }
    fn flush(&mut self) {}
}

/// When eframe's session file in `dir` holds something that does not parse (eframe then
/// starts on empty storage): moves it aside and returns the sentence for the status bar,
/// "last session could not be read: …; kept as …". `None` when there is no such file, it
/// is empty, or it parses.
pub fn damaged_session(dir: &Path) -> Option<String> {
    let path = dir.join(RON_FILE);
    let text = std::fs::read(&path).ok()?;
    if text.iter().all(u8::is_ascii_whitespace) {
        return None;
    }
    let problem = match std::str::from_utf8(&text) {
        Err(e) => format!("not text ({e})"),
        Ok(text) => match ron::from_str::<std::collections::HashMap<String, String>>(text) {
            Ok(_) => return None,
            Err(e) => e.to_string(),
        },
    };
    let seconds = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let aside = dir.join(format!("{RON_FILE}.damaged-{seconds}"));
    let kept = match std::fs::rename(&path, &aside) {
        Ok(()) => format!("kept as {}", aside.display()),
        Err(e) => format!("it could not be moved aside ({e}) and will be replaced"),
    };
    Some(format!(
        "last session could not be read: {problem}; {kept}; the app starts on defaults"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("lightpick-session-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a scratch folder");
        dir
    }

    #[test]
    fn a_scene_comes_back_bit_for_bit_in_either_form() {
        let dir = scratch("forms");
        let path = dir.join(SCENE_FILE);
        let mut scene = lightpick_core::scene::Scene::preset("heavy-tail").expect("preset");
        scene.name = "my lights".to_owned();
        write_scene(&path, &scene).expect("written");
        let bytes = std::fs::read(&path).expect("bytes");
        let header = bytes[BINARY_MAGIC.len()..]
            .iter()
            .position(|&b| b == b'\n')
            .expect("a header line");
        assert_eq!(
            bytes.len(),
            BINARY_MAGIC.len() + header + 1 + 32 * scene.light_count(),
            "32 bytes a light past the header"
        );
        assert_eq!(read_scene(&path).expect("read"), scene);
        let stage = lightpick_core::scene::Scene::preset("stage").expect("preset");
        write_scene(&path, &stage).expect("written");
        assert_eq!(read_scene(&path).expect("read"), stage);
    }

    #[test]
    fn a_cut_scene_file_is_named_not_read() {
        let dir = scratch("cut");
        let path = dir.join(SCENE_FILE);
        let scene = lightpick_core::scene::Scene::preset("heavy-tail").expect("preset");
        write_scene(&path, &scene).expect("written");
        let bytes = std::fs::read(&path).expect("bytes");
        std::fs::write(&path, &bytes[..bytes.len() / 2]).expect("cut");
        let err = read_scene(&path).expect_err("a cut file");
        assert!(
            err.contains("a cut file") && err.contains(SCENE_FILE),
            "{err}"
        );
    }

    #[test]
    fn a_damaged_session_is_moved_aside_and_said() {
        let dir = scratch("damaged");
        assert_eq!(damaged_session(&dir), None, "no file: nothing to say");
        std::fs::write(dir.join(RON_FILE), "{\"lightpick.settings\": \"(spp_per").expect("w");
        let said = damaged_session(&dir).expect("reported");
        assert!(
            said.starts_with("last session could not be read: "),
            "{said}"
        );
        assert!(
            said.contains("kept as ") && said.contains("app.ron.damaged-"),
            "{said}"
        );
        assert!(!dir.join(RON_FILE).exists(), "moved aside");
        let kept: Vec<_> = std::fs::read_dir(&dir).expect("dir").collect();
        assert_eq!(kept.len(), 1);
        // A good file is left alone.
        std::fs::write(dir.join(RON_FILE), "{\"a\": \"b\"}").expect("w");
        assert_eq!(damaged_session(&dir), None);
        assert!(dir.join(RON_FILE).exists());
    }
}
