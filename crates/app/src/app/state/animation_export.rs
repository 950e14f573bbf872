//! File → "Export animation…": the convergence animation of `lightpick plot animation`
//! ([`crate::recording`]) recorded from the app's running state — its scene, seed,
//! exposure, image size and theme — on a worker thread, so the window stays responsive,
//! with the progress and the outcome for the export window and the status bar.
//!
//! The same scene, seed, exposure, size, frames and samples give the same GIF as the CLI:
//! `lightpick plot animation --scene S --seed K --exposure E --width W --height H`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::Instant;

use lightpick_core::draw::Theme;

use super::AppState;
use crate::app::background::{Polled, Worker};
use crate::recording::{self, Recording};

/// Images larger than this many pixels a side are exported smaller (same aspect), so a
/// large scene's frames stay slide-sized and the export takes seconds, not minutes.
pub const MAX_EXPORT_SIDE: u32 = 256;

/// What one export records and where it writes.
#[derive(Clone, Debug)]
pub struct ExportJob {
    /// The animation (scene at its export size, seed, exposure, frames, theme).
    pub recording: Recording,
    /// The GIF file to write.
    pub path: PathBuf,
}

/// A written animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Exported {
    /// The file written (absolute when the working directory is known).
    pub path: PathBuf,
    /// Frames in the file.
    pub frames: usize,
    /// The file's size in bytes.
    pub bytes: usize,
    /// Frame width and height in pixels.
    pub frame_size: (u32, u32),
    /// Seconds the recording took.
    pub seconds: f64,
}

impl Exported {
    /// The status-bar sentence: what was written where.
    pub fn message(&self) -> String {
        format!(
            "exported animation {} ({} frame{}, {}×{} px, {} kB, {:.1} s)",
            self.path.display(),
            self.frames,
            if self.frames == 1 { "" } else { "s" },
            self.frame_size.0,
            self.frame_size.1,
            self.bytes.div_ceil(1000),
            self.seconds
        )
    }
}

/// Records `job`'s animation and writes it to `job.path`, calling `progress(done, total)`
/// as [`recording::record`] does. Errors are sentences for the status bar.
pub fn export(job: &ExportJob, progress: &mut dyn FnMut(u32, u32)) -> Result<Exported, String> {
    let started = Instant::now();
    let recorded = recording::record(&job.recording, progress).map_err(|e| format!("{e:#}"))?;
    lightpick_core::atomic_file::write_bytes_atomically(&job.path, &recorded.gif).map_err(|e| {
        format!(
            "cannot write {}: {e} — the old file is unchanged",
            job.path.display()
        )
    })?;
    Ok(Exported {
        path: std::path::absolute(&job.path).unwrap_or_else(|_| job.path.clone()),
        frames: recorded.frames.len(),
        bytes: recorded.gif.len(),
        frame_size: recorded.frame_size,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// What an export that ended without a result says.
const LOST: &str = "the export stopped without a result";

/// An export running on its worker thread.
#[derive(Debug)]
struct Running {
    /// Frames finished so far.
    done: Arc<AtomicU32>,
    /// Frames in all.
    total: u32,
    /// The file being written.
    path: PathBuf,
    /// The outcome, once there is one.
    worker: Worker<Result<Exported, String>>,
}

/// The export window's settings, the export in progress and the last outcome.
#[derive(Debug)]
pub struct AnimationExport {
    /// Whether the export window is shown.
    pub open: bool,
    /// The file to write, as typed (relative paths are in the working directory); empty:
    /// [`AnimationExport::default_path`] of the scene.
    pub path: String,
    /// Frames of the animation.
    pub frames: u32,
    /// Samples per pixel of the last frame.
    pub max_spp: u32,
    /// How the last export ended (`None` before the first and while one runs).
    pub last: Option<Result<Exported, String>>,
    running: Option<Running>,
}

impl Default for AnimationExport {
    fn default() -> Self {
        Self {
            open: false,
            path: String::new(),
            frames: recording::DEFAULT_FRAMES,
            max_spp: recording::DEFAULT_MAX_SPP,
            last: None,
            running: None,
        }
    }
}

impl AnimationExport {
    /// The file an export of scene `name` writes when no path is typed:
    /// `NAME-animation.gif` in the working directory.
    pub fn default_path(name: &str) -> String {
        let safe: String = name
            .chars()
            .map(|c| {
                if c.is_alphanumeric() || c == '-' || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let stem = if safe.is_empty() { "lightpick" } else { &safe };
        format!("{stem}-animation.gif")
    }

    /// Whether an export is running.
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// The running export's file and its progress `(frames done, frames)`.
    pub fn progress(&self) -> Option<(&Path, u32, u32)> {
        self.running
            .as_ref()
            .map(|r| (r.path.as_path(), r.done.load(Ordering::Relaxed), r.total))
    }

    /// Starts `job` on a worker thread (nothing when one is running already).
    pub fn start(&mut self, job: ExportJob) {
        if self.running.is_some() {
            return;
        }
        let done = Arc::new(AtomicU32::new(0));
        let total = job.recording.frames;
        let path = job.path.clone();
        let counter = Arc::clone(&done);
        let spawned = Worker::spawn("lightpick-animation", move || {
            export(&job, &mut |d, _| counter.store(d, Ordering::Relaxed))
        });
        match spawned {
            Ok(worker) => {
                self.last = None;
                self.running = Some(Running {
                    done,
                    total,
                    path,
                    worker,
                });
            }
            Err(e) => self.last = Some(Err(format!("cannot start the export: {e}"))),
        }
    }

    /// Takes a finished export's outcome into [`AnimationExport::last`]; returns it when it
    /// arrived now (call once per frame).
    pub fn poll(&mut self) -> Option<&Result<Exported, String>> {
        let running = self.running.as_ref()?;
        let outcome = match running.worker.poll() {
            Polled::Done(outcome) => outcome,
            Polled::Running => return None,
            Polled::Lost => Err(LOST.to_owned()),
        };
        self.running = None;
        self.last = Some(outcome);
        self.last.as_ref()
    }

    /// Waits for the running export and returns its outcome (tests; the app polls).
    pub fn wait(&mut self) -> Option<&Result<Exported, String>> {
        let running = self.running.take()?;
        let outcome = running
            .worker
            .wait()
            .unwrap_or_else(|| Err(LOST.to_owned()));
        self.last = Some(outcome);
        self.last.as_ref()
    }
}

/// The export size of a `width × height` image: itself when both sides are at most
/// [`MAX_EXPORT_SIDE`], else scaled down to fit (same aspect); never below 8 pixels a side.
pub fn export_size(width: u32, height: u32) -> (u32, u32) {
    let (w, h) = (width.max(1), height.max(1));
    let scale = (f64::from(MAX_EXPORT_SIDE) / f64::from(w.max(h))).min(1.0);
    let fit = |v: u32| ((f64::from(v) * scale).round() as u32).clamp(8, MAX_EXPORT_SIDE);
    (fit(w), fit(h))
}

impl AppState {
    /// The export of the running state to `path`: the current scene (its last valid table)
    /// at its image size (at most [`MAX_EXPORT_SIDE`] a side), the seed, the exposure and
    /// the theme, with the export window's frames and samples.
    pub fn animation_job(&self, path: impl Into<PathBuf>) -> ExportJob {
        let mut scene = (*self.built.scene).clone();
        let (w, h) = export_size(scene.plane.width, scene.plane.height);
        recording::size_scene(&mut scene, Some(w), Some(h));
        let settings = &self.animation_export;
        ExportJob {
            recording: Recording {
                scene,
                seed: self.settings.seed,
                exposure: Some(self.settings.exposure),
                frames: settings.frames,
                max_spp: settings.max_spp,
                delay_ms: recording::DEFAULT_DELAY_MS,
                hold_ms: recording::DEFAULT_HOLD_MS,
                theme: if self.dark() {
                    Theme::Dark
                } else {
                    Theme::Light
                },
            },
            path: path.into(),
        }
    }

    /// The file the export window writes: the typed path, or the scene's default name.
    pub fn animation_path(&self) -> PathBuf {
        let typed = self.animation_export.path.trim();
        if typed.is_empty() {
            PathBuf::from(AnimationExport::default_path(&self.edit.name))
        } else {
            PathBuf::from(typed)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_names() {
        assert_eq!(export_size(256, 256), (256, 256));
        assert_eq!(export_size(1024, 512), (256, 128));
        assert_eq!(export_size(4096, 16), (256, 8));
        assert_eq!(export_size(48, 32), (48, 32));
        assert_eq!(
            AnimationExport::default_path("heavy-tail"),
            "heavy-tail-animation.gif"
        );
        assert_eq!(
            AnimationExport::default_path("a/b c"),
            "a_b_c-animation.gif"
        );
        assert_eq!(AnimationExport::default_path(""), "lightpick-animation.gif");
    }
}
