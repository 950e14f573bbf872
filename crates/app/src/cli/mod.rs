//! The headless subcommands. Every one prints text for people or, with `--json`, one JSON
//! object for scripts. Any error prints one line `error: …` on stderr and exits with code 2.

pub mod animation;
mod bench;
mod closed_output;
mod device;
mod estimate;
mod input;
mod plot;
mod plot_output;
mod plot_tree;
mod precision;
mod render;
mod sample;
mod scene;
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
                  Without a subcommand, opens the desktop app on the worked example \
                  (powers 2, 5, 20), or on FILE (glTF, CSV or lightpick JSON)."
)]
#[command(args_conflicts_with_subcommands = true)]
pub struct Cli {
    /// What to do; none opens the desktop app.
    #[command(subcommand)]
    pub command: Option<Command>,
    /// A scene file to open the app on (glTF .gltf/.glb, CSV, lightpick JSON): what a
    /// desktop's "Open with" passes.
    #[arg(value_name = "FILE")]
    pub file: Option<std::path::PathBuf>,
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
    /// Draw the app's pictures headless: table, histogram, convergence, sheet, the light tree
    /// from above, the variance maps (PNG), and the convergence animation (GIF).
    Plot(plot::PlotArgs),
    /// Render a scene progressively; report its error against the exact reference.
    Render(render::RenderArgs),
    /// Time the tables, the peers, the GPU and the renders (performance is measured here).
    Bench(bench::BenchArgs),
    /// The precision lab: what f32, one random or f32(u)·N would cost, computed exactly.
    Precision(precision::PrecisionArgs),
    /// What a scene file holds (glTF, CSV, JSON): lights by kind, powers, skipped lights;
    /// `--out` writes it as lightpick JSON.
    Scene(scene::SceneCommandArgs),
}

/// Parses the command line, runs it, and maps errors to one `error:` line and exit code 2.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(err) => {
            closed_output::end_quietly_on_closed_output();
            return clap_exit(&err);
        }
    };
    if cli.command.is_some() {
        closed_output::end_quietly_on_closed_output();
    }
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
        None => {
            // The desktop app holds large scenes for long: before anything is allocated,
            // large blocks get their own mappings (see the function).
            crate::app::map_large_allocations();
            let opened = match &cli.file {
                Some(path) if !path.exists() => anyhow::bail!(
                    "'{}' is neither a subcommand nor a file (see `lightpick --help`)",
                    path.display()
                ),
                Some(path) => Some((path.clone(), input::read_scene(path, None, None)?)),
                None => None,
            };
            crate::app::run(opened)
        }
        Some(Command::Table(args)) => table::run(&args),
        Some(Command::Sample(args)) => sample::run(&args),
        Some(Command::Estimate(args)) => estimate::run(&args),
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Plot(args)) => plot::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        Some(Command::Precision(args)) => precision::run(&args),
        Some(Command::Scene(args)) => scene::run(&args),
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
            eprintln!("{}", clap_error_line(err));
            ExitCode::from(2)
        }
    }
}

/// A clap usage error as one `error: …` line that keeps what clap says on several lines:
///
/// * a missing required argument is named: `error: missing required argument --contrib
///   <CONTRIB>` (several: `arguments --a <A>, --b <B>`);
/// * every other kind keeps clap's message lines before its usage block, joined by spaces,
///   with `tip:` lines in parentheses: `error: unexpected argument '--foo' found (tip: a
///   similar argument exists: '--powers')`, `error: invalid value 'x' for '--axis <AXIS>'
///   [possible values: spp, seconds]`.
fn clap_error_line(err: &clap::Error) -> String {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    if err.kind() == ErrorKind::MissingRequiredArgument
        && let Some(ContextValue::Strings(missing)) = err.get(ContextKind::InvalidArg)
        && !missing.is_empty()
    {
        let noun = if missing.len() == 1 {
            "argument"
        } else {
            "arguments"
        };
        return format!("error: missing required {noun} {}", missing.join(", "));
    }
    one_clap_line(&err.render().to_string())
}

/// Joins the message lines of rendered clap output (those before `Usage:` or `For more
/// information`) into one line starting with `error:`.
fn one_clap_line(rendered: &str) -> String {
    let mut line = String::new();
    for part in rendered
        .lines()
        .map(str::trim)
        .take_while(|l| !l.starts_with("Usage:") && !l.starts_with("For more information"))
        .filter(|l| !l.is_empty())
    {
        if line.is_empty() {
            line.push_str(part);
        } else if part.starts_with("tip:") {
            line.push_str(" (");
            line.push_str(part);
            line.push(')');
        } else {
            line.push(' ');
            line.push_str(part);
        }
    }
    if line.is_empty() {
        return "error: invalid command line".to_owned();
    }
    if line.starts_with("error:") {
        line
    } else {
        format!("error: {line}")
    }
}

/// The error and its causes on one line: `outer: inner: innermost`, a cause that its
/// parent's message already ends with (`…: No such file or directory`) said once.
fn one_line(err: &anyhow::Error) -> String {
    let mut parts: Vec<String> = Vec::new();
    for cause in err.chain().map(ToString::to_string) {
        if parts.last().is_some_and(|last| last.ends_with(&cause)) {
            continue;
        }
        parts.push(cause);
    }
    parts.join(": ").replace('\n', " ")
}

/// Prints `value` as one line of JSON on stdout.
pub(crate) fn print_json(value: &serde_json::Value) -> anyhow::Result<()> {
    println!("{}", serde_json::to_string(value)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clap_messages_become_one_line() {
        let rendered = "error: unexpected argument '--foo' found\n\n  tip: a similar argument \
                        exists: '--powers'\n\nUsage: lightpick table --powers <LIST>\n\n\
                        For more information, try '--help'.\n";
        assert_eq!(
            one_clap_line(rendered),
            "error: unexpected argument '--foo' found (tip: a similar argument exists: '--powers')"
        );
        assert_eq!(one_clap_line(""), "error: invalid command line");
        assert_eq!(one_clap_line("bad\n"), "error: bad");
    }

    #[test]
    fn a_missing_argument_is_named() {
        let err = Cli::try_parse_from(["lightpick", "estimate", "--powers", "2,5,20"])
            .expect_err("--contrib is required");
        assert_eq!(
            clap_error_line(&err),
            "error: missing required argument --contrib <LIST>"
        );
    }
}
