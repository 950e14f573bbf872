//! A standard output closed early (`lightpick table --preset million --json | head -c 80`)
//! ends the program quietly, as it ends `cat` or `yes`, rather than in a panic of `print!`.

/// Gives `SIGPIPE` back its default action, ending the process, on Unix. Rust's runtime
/// ignores the signal, so a write to a closed pipe fails with `EPIPE` and `print!` panics
/// on it. The subcommands only write their results to standard output, and a reader that
/// stopped reading wants no more of them: ending there is what a shell pipeline expects
/// (its status reads 141, `128 + SIGPIPE`). The desktop app keeps the runtime's choice
/// (its sockets report a closed peer as an error).
pub(super) fn end_quietly_on_closed_output() {
    #[cfg(unix)]
    #[allow(unsafe_code)]
    {
        // SAFETY: `signal` only sets the process's action for `SIGPIPE`, to the default
        // one, which runs no code of this program; it is called before any thread of the
        // subcommand starts.
        unsafe {
            libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        }
    }
}
