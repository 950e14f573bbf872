//! Why a scene was refused. Every message starts with the path of the offending field in
//! the scene file (`plane.width`, `lights[3].power`, `generator.power.shape`, …), so a user
//! can find it without reading code.

use std::path::PathBuf;

/// Why a scene could not be read, parsed, validated or generated.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("cannot read scene file '{}': {source}", path.display())]
    Io {
        /// The file that was asked for.
        path: PathBuf,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// Malformed JSON, a missing or unknown field, or a value of the wrong type.
    #[error("{path}: {message} (line {line}, column {column})")]
    Json {
        /// Where the parser was, as a field path (`.` for the document itself).
        path: String,
        /// serde's description of the problem.
        message: String,
        /// 1-based line of the problem in the text.
        line: usize,
        /// 1-based column of the problem in the text.
        column: usize,
    },
    /// `Scene::preset` was given a name that is not in `PRESET_NAMES`.
    #[error("unknown preset '{name}' (expected one of: {expected})")]
    UnknownPreset {
        /// The name asked for.
        name: String,
        /// The known names, comma separated.
        expected: String,
    },
    /// A number outside its accepted range (sizes, counts, fractions, distribution
    /// parameters).
    #[error("{field}: must be between {min} and {max} (got {value})")]
    OutOfRange {
        /// Path of the field.
        field: String,
        /// The value found, as written.
        value: String,
        /// The smallest accepted value, as written.
        min: String,
        /// The largest accepted value, as written.
        max: String,
    },
    /// A NaN or infinite number (a position, a power, a plane corner).
    #[error("{field}: not finite ({value})")]
    NotFinite {
        /// Path of the field.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A negative power.
    #[error("{field}: negative ({value})")]
    Negative {
        /// Path of the field.
        field: String,
        /// The value found.
        value: f64,
    },
    /// A structural problem: both or neither of `lights` and `generator`, an empty
    /// rectangle, a box with `min > max`, mismatched lengths.
    #[error("{field}: {reason}")]
    Invalid {
        /// Path of the field (or of the object holding the conflicting fields).
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A file that is not what its format requires: a GLB header or chunk, glTF's JSON or
    /// its validation, text that is not UTF-8.
    #[error("{format}: {message}")]
    Import {
        /// The format being read (`glb`, `gltf`, `csv`, `json`).
        format: &'static str,
        /// What is wrong, and where.
        message: String,
    },
    /// Every light has power zero: nothing emits light.
    #[error("{field}: all {count} powers are zero: nothing emits light")]
    AllZero {
        /// `lights` or `generator`.
        field: String,
        /// How many lights there are.
        count: usize,
    },
    /// The total power `Σ Φ_i` is not a finite `f64` (each power is, their sum is not).
    #[error("{field}: the total power of {count} lights overflows f64")]
    TotalPowerOverflow {
        /// `lights` or `generator`.
        field: String,
        /// How many lights there are.
        count: usize,
    },
}

impl SceneError {
    /// Shorthand for [`SceneError::Invalid`].
    pub(crate) fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Self {
        SceneError::Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// Shorthand for [`SceneError::OutOfRange`].
    pub(crate) fn out_of_range(
        field: impl Into<String>,
        value: impl std::fmt::Display,
        min: impl std::fmt::Display,
        max: impl std::fmt::Display,
    ) -> Self {
        SceneError::OutOfRange {
            field: field.into(),
            value: value.to_string(),
            min: min.to_string(),
            max: max.to_string(),
        }
    }

    /// The path of the offending field, where the error has one.
    pub fn field(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. }
            | SceneError::UnknownPreset { .. }
            | SceneError::Import { .. } => None,
            SceneError::Json { path, .. } => Some(path),
            SceneError::OutOfRange { field, .. }
            | SceneError::NotFinite { field, .. }
            | SceneError::Negative { field, .. }
            | SceneError::Invalid { field, .. }
            | SceneError::AllZero { field, .. }
            | SceneError::TotalPowerOverflow { field, .. } => Some(field),
        }
    }
}
