//! The time the GPU itself spends in a renderer's sample passes.
//!
//! With [`wgpu::Features::TIMESTAMP_QUERY`] every compute pass writes a timestamp at its
//! beginning and at its end (`ComputePassTimestampWrites`); the pass time is
//! `(end − begin)·period`, with `period` the queue's nanoseconds per tick. That is the
//! device's own clock over the pass alone: nothing else queued on the device (another
//! renderer, egui's frame) is counted. Without the feature, or on a software rasterizer,
//! the pass is timed on the CPU's clock, but alone: the timer first waits until the device
//! is idle, so the interval from submit to completion holds this pass only (and its
//! submission overhead).
//!
//! Why not timestamps on a software rasterizer: lavapipe offers `TIMESTAMP_QUERY`, and on a
//! device of its own its pass times match the wall clock; but on the device eframe shares
//! with egui's drawing they came out 8–10× shorter than the pass itself took (3.9 ns per
//! sample where the pass alone takes 32). There the device *is* the CPU, so the wall clock
//! of the pass alone is the device's time.

use std::time::Instant;

use super::{GpuContext, GpuError};

/// Timestamp pairs a timer holds before it must be read (each pass uses one pair).
const PAIRS: u32 = 64;

/// Where pass times come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum PassClock {
    /// The device's timestamps at the beginning and end of each compute pass.
    Timestamps,
    /// The CPU's monotonic clock from submit to completion, after the device went idle.
    IdleWallClock,
}

impl PassClock {
    /// A short description for people ("GPU timestamps").
    pub fn describe(self) -> &'static str {
        match self {
            PassClock::Timestamps => "GPU timestamps",
            PassClock::IdleWallClock => "CPU clock, pass alone on an idle queue",
        }
    }
}

/// The timestamp queries of one renderer.
#[derive(Debug)]
struct Queries {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    /// Pairs written since the last read.
    used: u32,
    /// Nanoseconds per tick.
    period_ns: f64,
}

/// Accumulates the seconds a renderer's compute passes take (see the module docs).
#[derive(Debug)]
pub struct PassTimer {
    queries: Option<Queries>,
    /// Seconds read (or measured on the CPU clock) and not yet taken.
    seconds: f64,
    /// The CPU-clock start of the pass being timed ([`PassClock::IdleWallClock`]).
    started: Option<Instant>,
}

impl PassTimer {
    /// A timer on `ctx`: timestamps when the device has [`wgpu::Features::TIMESTAMP_QUERY`]
    /// and is not a software rasterizer (see the module docs).
    pub fn new(ctx: &GpuContext) -> Self {
        let device = ctx.device();
        let queries = (device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
            && !ctx.is_software())
        .then(|| Queries {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("lightpick pass timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * PAIRS,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("lightpick pass timestamps (resolved)"),
                size: u64::from(2 * PAIRS) * 8,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            used: 0,
            period_ns: f64::from(ctx.queue().get_timestamp_period()),
        });
        Self {
            queries,
            seconds: 0.0,
            started: None,
        }
    }

    /// Which clock this timer reads.
    pub fn clock(&self) -> PassClock {
        if self.queries.is_some() {
            PassClock::Timestamps
        } else {
            PassClock::IdleWallClock
        }
    }

    /// Prepares to time one pass: reads the timestamps first when every pair is used, or
    /// (CPU clock) waits for the device to be idle and starts the clock. Returns the
    /// timestamp writes to give the pass, if any.
    pub(crate) fn begin_pass(
        &mut self,
        ctx: &GpuContext,
    ) -> Result<Option<wgpu::ComputePassTimestampWrites<'_>>, GpuError> {
        if self.queries.as_ref().is_some_and(|q| q.used == PAIRS) {
            self.read(ctx)?;
        }
        if let Some(q) = &mut self.queries {
            let pair = q.used;
            q.used += 1;
            return Ok(Some(wgpu::ComputePassTimestampWrites {
                query_set: &q.set,
                beginning_of_pass_write_index: Some(2 * pair),
                end_of_pass_write_index: Some(2 * pair + 1),
            }));
        }
        wait_idle(ctx)?;
        self.started = Some(Instant::now());
        Ok(None)
    }

    /// After the pass was submitted: on the CPU clock, waits for it and stops the clock.
    pub(crate) fn end_pass(&mut self, ctx: &GpuContext) -> Result<(), GpuError> {
        if let Some(started) = self.started.take() {
            wait_idle(ctx)?;
            self.seconds += started.elapsed().as_secs_f64();
        }
        Ok(())
    }

    /// The seconds of every pass timed since the last call (waits for their timestamps).
    pub fn take_seconds(&mut self, ctx: &GpuContext) -> Result<f64, GpuError> {
        self.read(ctx)?;
        Ok(std::mem::take(&mut self.seconds))
    }

    /// Resolves and reads the timestamps written so far into `seconds`.
    fn read(&mut self, ctx: &GpuContext) -> Result<(), GpuError> {
        let Some(q) = &mut self.queries else {
            return Ok(());
        };
        if q.used == 0 {
            return Ok(());
        }
        let count = 2 * q.used;
        let mut encoder = ctx
            .device()
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("lightpick resolve timestamps"),
            });
        encoder.resolve_query_set(&q.set, 0..count, &q.resolve, 0);
        ctx.queue().submit([encoder.finish()]);
        let bytes = super::read_buffer(ctx, "pass timestamps", &q.resolve, u64::from(count) * 8)?;
        let ticks: Vec<u64> = bytes
            .chunks_exact(8)
            .map(|b| u64::from_ne_bytes(b.try_into().unwrap_or([0; 8])))
            .collect();
        for pair in ticks.chunks_exact(2) {
            // A pass whose end reads before its beginning (a reset or wrapped counter on
            // some drivers) counts as zero rather than as an enormous interval.
            let elapsed = pair[1].saturating_sub(pair[0]);
            self.seconds += elapsed as f64 * q.period_ns * 1e-9;
        }
        q.used = 0;
        Ok(())
    }
}

/// Blocks until every submitted command has completed.
fn wait_idle(ctx: &GpuContext) -> Result<(), GpuError> {
    ctx.device()
        .poll(wgpu::PollType::wait_indefinitely())
        .map(|_| ())
        .map_err(|e| GpuError::Readback {
            what: "idle queue",
            reason: e.to_string(),
        })
}
