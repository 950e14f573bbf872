//! The egui/eframe desktop app.

/// Opens the app on the seed scene. Returns an error (exit code 2) when no display exists.
pub fn run() -> anyhow::Result<()> {
    anyhow::bail!(
        "the desktop app is not built yet; use the headless subcommands (lightpick --help)"
    )
}
