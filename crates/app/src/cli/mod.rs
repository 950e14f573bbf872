//! The headless subcommands. Every one prints text for people or, with `--json`, one JSON
//! object for scripts. Any error prints one line `error: …` on stderr and exits with code 2.

mod bench;
mod device;
mod estimate;
mod input;
mod plot;
mod precision;
mod render;
mod sample;
mod table;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

pub use input::PowersArgs;

/// `lightpick`: teach and measure point-light importance sampling.
#[derive(Debug, Parser)]
#[command(
    name = "lightpick",
    version,
    about = "Teach and measure point-light importance sampling (Walker alias tables).",
    long_about = "Teach and measure point-light importance sampling (Walker alias tables).\n\n\
                  Without a subcommand, opens the desktop app on the seed scene \
                  (powers 2, 5, 20)."
)]
pub struct Cli {
    /// What to do; none opens the desktop app.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The headless subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print the alias table (pmf, threshold, alias) of a set of powers.
    Table(table::TableArgs),
    /// Draw light indices with a scheme and test the counts against the pmf (chi-square).
    Sample(sample::SampleArgs),
    /// Estimate a sum of light contributions by sampling one light at a time.
    Estimate(estimate::EstimateArgs),
    /// Draw the app's pictures headless: table, histogram, convergence, sheet (PNG).
    Plot(plot::PlotArgs),
    /// Render a scene progressively; report its error against the exact reference.
    Render(render::RenderArgs),
    /// Time the tables, the peers, the GPU and the renders (performance is measured here).
    Bench(bench::BenchArgs),
    /// The precision lab: what f32, one random or f32(u)·N would cost, computed exactly.
    Precision(precision::PrecisionArgs),
}

/// Parses the command line, runs it, and maps errors to one `error:` line and exit code 2.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => return clap_exit(&err),
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {}", one_line(&err));
            ExitCode::from(2)
        }
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> anyhow::Result<()> {
    match cli.command {
        None => crate::app::run(),
        Some(Command::Table(args)) => table::run(&args),
        Some(Command::Sample(args)) => sample::run(&args),
        Some(Command::Estimate(args)) => estimate::run(&args),
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Plot(args)) => plot::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Precision(args)) => precision::run(&args),
    }
}

/// Help and version go to stdout with code 0; usage errors become one `error:` line, code 2.
fn clap_exit(err: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    match err.kind() {
        ErrorKind::DisplayHelp
        | ErrorKind::DisplayVersion
        | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            print!("{}", err.render());
            ExitCode::SUCCESS
        }
        _ => {
            let rendered = err.render().to_string();
            let first = rendered
                .lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("error: invalid command line");
            eprintln!("{first}");
            ExitCode::from(2)
        }
    }
}

/// The error and its causes on one line: `outer: inner: innermost`.
fn one_line(err: &anyhow::Error) -> String {
    err.chain()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(": ")
        .replace('\n', " ")
}

/// Prints `value` as one line of JSON on stdout.
pub(crate) fn print_json(value: &serde_json::Value) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string(value)?);
    Ok(())
}
