//! The formats the loader reads, told apart by magic bytes and extension.

/// The formats [`super::load`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SceneFormat {
    /// lightpick's scene JSON.
    Json,
    /// glTF 2.0, JSON form (`.gltf`).
    Gltf,
    /// glTF 2.0, binary form (`.glb`).
    Glb,
    /// A CSV or white-space list of `x, y, z, power`.
    Csv,
}

impl SceneFormat {
    /// The format's short name (`json`, `gltf`, `glb`, `csv`).
    pub fn name(self) -> &'static str {
        match self {
            SceneFormat::Json => "json",
            SceneFormat::Gltf => "gltf",
            SceneFormat::Glb => "glb",
            SceneFormat::Csv => "csv",
        }
    }

    /// The file extensions of each format, for file choosers.
    pub const EXTENSIONS: [&'static str; 6] = ["json", "gltf", "glb", "csv", "txt", "tsv"];

    /// The format a file of extension `ext` (lower case, no dot) holds, if known.
    pub fn from_extension(ext: &str) -> Option<SceneFormat> {
        match ext {
            "json" => Some(SceneFormat::Json),
            "gltf" => Some(SceneFormat::Gltf),
            "glb" => Some(SceneFormat::Glb),
            "csv" | "txt" | "tsv" => Some(SceneFormat::Csv),
            _ => None,
        }
    }

    /// The format of `bytes` read from a file with extension `ext`: the magic bytes first
    /// (`glTF` is a GLB whatever the name; a JSON object with a top-level `"asset"` is glTF),
    /// then the extension; a JSON object defaults to lightpick JSON and anything else to a
    /// light list.
    pub fn detect(bytes: &[u8], ext: Option<&str>) -> SceneFormat {
        if bytes.starts_with(b"glTF") {
            return SceneFormat::Glb;
        }
        if let Some(format) = ext.and_then(SceneFormat::from_extension) {
            return format;
        }
        let text = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
        if text.trim_start().starts_with('{') {
            if text.contains("\"asset\"") {
                SceneFormat::Gltf
            } else {
                SceneFormat::Json
            }
        } else {
            SceneFormat::Csv
        }
    }
}
