//! What an animation may ask for: the limits of its figures, the checks that refuse the rest
//! (naming the CLI flag, as `lightpick plot animation` and the app's export window both
//! report them), and the samples per pixel of each frame ([`frame_spp`]).

use anyhow::bail;

use super::Recording;

/// The most frames an animation may have.
pub const MAX_FRAMES: u32 = 240;
/// The largest `--max-spp`.
pub const MAX_SPP: u32 = 1 << 16;
/// Image sides (pixels) an animation accepts: from 8 to 512.
pub const SIDE_RANGE: std::ops::RangeInclusive<u32> = 8..=512;
/// Frame delays (milliseconds) an animation accepts: GIF counts in hundredths of a second,
/// and browsers show delays under 20 ms slower than asked.
pub const DELAY_RANGE: std::ops::RangeInclusive<u32> = 20..=60_000;

/// The samples per pixel of each of `frames` frames ending at `max_spp`: strictly
/// increasing whole numbers from 1 (a single frame: `max_spp` alone), as close as possible to
/// the geometric sequence `max_spp^(k/(frames−1))`.
///
/// Rounding the geometric sequence repeats small counts (1, 1, 2, 2, …), so each count is
/// raised to one more than the one before (a forward pass) and then lowered to one less than
/// the one after (a backward pass from `max_spp`); with `frames ≤ max_spp` the result starts
/// at 1, ends at `max_spp` and increases strictly.
///
/// # Panics
/// If `frames == 0` or `frames > max_spp` (refused earlier by [`Recording::check`]).
pub fn frame_spp(frames: u32, max_spp: u32) -> Vec<u32> {
    assert!(
        frames >= 1 && frames <= max_spp,
        "frame_spp needs 1 ≤ frames ≤ max_spp"
    );
    if frames == 1 {
        return vec![max_spp];
    }
    let last = frames - 1;
    let mut spp: Vec<u32> = (0..frames)
        .map(|k| {
            (f64::from(max_spp)
                .powf(f64::from(k) / f64::from(last))
                .round() as u32)
                .clamp(1, max_spp)
        })
        .collect();
    for k in 1..spp.len() {
        spp[k] = spp[k].max(spp[k - 1] + 1);
    }
    spp[last as usize] = max_spp;
    for k in (0..last as usize).rev() {
        spp[k] = spp[k].min(spp[k + 1] - 1);
    }
    spp
}

/// The figures of a recording that need no scene.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    /// Frames.
    pub frames: u32,
    /// Samples per pixel of the last frame.
    pub max_spp: u32,
    /// Milliseconds each frame is shown.
    pub delay_ms: u32,
    /// Milliseconds the last frame is shown.
    pub hold_ms: u32,
    /// Tonemap exposure, when given.
    pub exposure: Option<f64>,
}

impl Timing {
    /// Refuses out-of-range figures, naming the CLI flag.
    pub fn check(self) -> anyhow::Result<()> {
        if !(1..=MAX_FRAMES).contains(&self.frames) {
            bail!(
                "--frames must be between 1 and {MAX_FRAMES} (got {})",
                self.frames
            );
        }
        if !(1..=MAX_SPP).contains(&self.max_spp) {
            bail!(
                "--max-spp must be between 1 and {MAX_SPP} (got {})",
                self.max_spp
            );
        }
        if self.frames > self.max_spp {
            bail!(
                "--frames {} needs --max-spp of at least {} (every frame adds samples)",
                self.frames,
                self.frames
            );
        }
        for (flag, ms) in [("--delay-ms", self.delay_ms), ("--hold-ms", self.hold_ms)] {
            if !DELAY_RANGE.contains(&ms) {
                bail!(
                    "{flag} must be between {} and {} (got {ms})",
                    DELAY_RANGE.start(),
                    DELAY_RANGE.end()
                );
            }
        }
        if let Some(e) = self.exposure
            && !(e.is_finite() && e > 0.0)
        {
            bail!("--exposure must be a positive finite number (got {e})");
        }
        Ok(())
    }
}

/// Refuses an image side outside [`SIDE_RANGE`], naming `flag`.
pub fn check_side(flag: &str, side: u32) -> anyhow::Result<()> {
    if !SIDE_RANGE.contains(&side) {
        bail!(
            "{flag} must be between {} and {} (got {side})",
            SIDE_RANGE.start(),
            SIDE_RANGE.end()
        );
    }
    Ok(())
}

impl Recording {
    /// Refuses what cannot be recorded, naming the CLI flag.
    pub fn check(&self) -> anyhow::Result<()> {
        Timing {
            frames: self.frames,
            max_spp: self.max_spp,
            delay_ms: self.delay_ms,
            hold_ms: self.hold_ms,
            exposure: self.exposure,
        }
        .check()?;
        check_side("--width", self.scene.plane.width)?;
        check_side("--height", self.scene.plane.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::recording::size_scene;
    use lightpick_core::draw::Theme;
    use lightpick_core::scene::Scene;

    #[test]
    fn frames_are_spaced_geometrically_and_strictly() {
        assert_eq!(frame_spp(1, 64), vec![64]);
        assert_eq!(frame_spp(7, 64), vec![1, 2, 4, 8, 16, 32, 64]);
        assert_eq!(frame_spp(4, 4), vec![1, 2, 3, 4]);
        for (frames, max) in [(24, 256), (24, 24), (2, 1 << 16), (240, 300), (5, 7)] {
            let s = frame_spp(frames, max);
            assert_eq!(s.len(), frames as usize);
            assert_eq!(s[0], 1, "{frames} {max}");
            assert_eq!(*s.last().expect("frames"), max);
            assert!(s.windows(2).all(|w| w[0] < w[1]), "{s:?}");
        }
    }

    #[test]
    fn recordings_are_checked() {
        let mut scene = Scene::preset("worked-example").expect("preset");
        size_scene(&mut scene, Some(16), None);
        assert_eq!((scene.plane.width, scene.plane.height), (16, 16));
        let ok = Recording {
            scene,
            seed: 1,
            exposure: None,
            frames: 4,
            max_spp: 8,
            delay_ms: 100,
            hold_ms: 100,
            theme: Theme::Light,
        };
        ok.check().expect("valid");
        let err = |r: Recording| r.check().expect_err("refused").to_string();
        assert!(
            err(Recording {
                frames: 0,
                ..ok.clone()
            })
            .starts_with("--frames must be")
        );
        assert!(
            err(Recording {
                frames: 9,
                ..ok.clone()
            })
            .contains("--max-spp of at least 9")
        );
        assert!(
            err(Recording {
                delay_ms: 5,
                ..ok.clone()
            })
            .starts_with("--delay-ms")
        );
        assert!(
            err(Recording {
                exposure: Some(f64::NAN),
                ..ok.clone()
            })
            .starts_with("--exposure")
        );
        let mut wide = ok.clone();
        wide.scene.plane.width = 4096;
        assert!(err(wide).starts_with("--width must be between 8 and 512"));
    }
}
