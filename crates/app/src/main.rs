//! The `lightpick` binary: headless subcommands, or the desktop app when none is given.

use std::process::ExitCode;

fn main() -> ExitCode {
    lightpick::cli::main()
}
