//! The in-app file dialog's state: the action waiting for a path, the folder shown and its
//! listing, the path as typed and why the last attempt failed.

use super::figure::Figure;

/// A file action waiting for its path in the in-app dialog.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileAction {
    /// Open a scene file (lightpick JSON, glTF/GLB, CSV).
    OpenScene,
    /// Save the scene as JSON.
    SaveScene,
    /// Export the images as PNG files.
    ExportImages,
    /// Export one figure as a PNG file.
    ExportFigure(super::figure::Figure),
    /// Export the data behind the figures as CSV files.
    ExportData,
}

impl FileAction {
    /// The dialog title.
    pub fn title(self) -> &'static str {
        match self {
            FileAction::OpenScene => "Open scene",
            FileAction::SaveScene => "Save scene",
            FileAction::ExportImages => "Export images (PNG)",
            FileAction::ExportFigure(figure) => match figure {
                Figure::AliasTable => "Export alias-table diagram (PNG)",
                Figure::Histogram => "Export histogram of picks (PNG)",
                Figure::Convergence => "Export convergence plot (PNG)",
                Figure::Trade => "Export Trade plot (PNG)",
                Figure::LightTree => "Export light tree (PNG)",
                Figure::Images => "Export images at the figure size (PNG)",
            },
            FileAction::ExportData => "Export data (CSV)",
        }
    }

    /// The file types the action reads or writes: a label and the extensions.
    pub fn file_types(self) -> (&'static str, &'static [&'static str]) {
        match self {
            FileAction::OpenScene => (
                "Scenes (glTF, GLB, CSV, JSON)",
                &lightpick_core::scene::SceneFormat::EXTENSIONS,
            ),
            FileAction::SaveScene => ("lightpick JSON", &["json"]),
            FileAction::ExportImages | FileAction::ExportFigure(_) => ("PNG images", &["png"]),
            FileAction::ExportData => ("CSV tables", &["csv"]),
        }
    }
}

/// One entry of the folder the file dialog shows.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FolderEntry {
    /// The file or folder name.
    pub name: String,
    /// Whether it is a folder.
    pub is_dir: bool,
    /// Size in bytes (files).
    pub bytes: u64,
}

/// The in-app file chooser: a folder to browse, a path to type or pick.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FileDialog {
    /// The pending action, `None` when the dialog is closed.
    pub action: Option<FileAction>,
    /// The path being typed or picked: absolute, or relative to `folder`.
    pub path: String,
    /// Why the last attempt failed (shown in the dialog, the path stays as typed).
    pub error: Option<String>,
    /// The folder shown (`None`: the working directory).
    pub folder: Option<std::path::PathBuf>,
    /// Show every file, not only the action's types.
    pub all_files: bool,
    /// The folder's entries as last listed (folders first, then by name), or why it could
    /// not be read.
    pub listing: Option<(std::path::PathBuf, Result<Vec<FolderEntry>, String>)>,
}

impl FileDialog {
    /// The folder shown.
    pub fn folder(&self) -> std::path::PathBuf {
        self.folder
            .clone()
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_else(|| std::path::PathBuf::from("."))
    }

    /// The full path of what is typed: itself when absolute, else within the folder.
    pub fn resolved(&self) -> std::path::PathBuf {
        let typed = std::path::Path::new(self.path.trim());
        if typed.is_absolute() {
            typed.to_owned()
        } else {
            self.folder().join(typed)
        }
    }
}
