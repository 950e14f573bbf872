//! The timing tests of the app: its time per sample against `lightpick bench`'s. They are
//! their own test binary because `cargo test` runs test binaries one after another: here
//! nothing else of the test suite shares the cores while a pass is timed (in the
//! `integration` binary forty tests run beside them on two cores, and a clock comparison
//! there measures its neighbours). Within this binary the tests take [`MACHINE`] in turn.

#[path = "../integration/common/mod.rs"]
mod common;

mod app_timing;

/// Held by each timing test for its whole run, so that the tests of this binary (which the
/// harness would run in parallel) time their passes one at a time.
static MACHINE: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Takes [`MACHINE`], whether or not an earlier test panicked while holding it.
fn machine() -> std::sync::MutexGuard<'static, ()> {
    MACHINE
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}
