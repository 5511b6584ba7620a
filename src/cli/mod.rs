//! The command line, one module per command: `args.rs` declares every command and option;
//! the others run them. [`run_command_line`] is the `combustion` binary's `main` (src/main.rs
//! adds the log's format), with the mapping of errors to exit codes. The library holds it so
//! that the fuzz target of batch manifests (fuzz/fuzz_targets/batch_manifest.rs) reaches
//! [`manifest`] and [`batch`]'s merge as the command runs them.

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

use crate::{output, shortened, Error};
use combustion_plots::PlotError;

/// Writes `text` to standard output: a closed pipe (`combustion … | head`) ends the
/// program quietly (exit 0: the reader has what it wanted); any other write error (a
/// full disk, `> /dev/full`) is reported in one line and exits 1, never ignored.
pub(crate) fn write_stdout(text: std::fmt::Arguments<'_>) {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_fmt(text).and_then(|()| out.flush()) {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("error: cannot write to standard output: {e}");
        std::process::exit(1);
    }
}

/// `println!` through [`write_stdout`].
macro_rules! outln {
    ($($arg:tt)*) => {
        write_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

pub(crate) mod args;
pub mod batch;
mod bench;
mod diff;
mod info;
pub mod manifest;
mod plot;
mod render;
mod view;

pub(crate) use args::*;
pub(crate) use batch::batch;
pub(crate) use bench::bench;
pub(crate) use diff::diff;
pub(crate) use info::info;
pub(crate) use plot::{eval, plot};
pub(crate) use render::render;
pub(crate) use view::{devices, view};

/// `text` on one line: line breaks (an importer's or parser's detail) become "; ", and
/// any other control character — in a file name the message shows whole, say — an escape
/// (`\u{1b}`), so no message acts on the terminal. Every error the command prints, and
/// every warning or error logged (src/main.rs), goes through it.
pub fn one_line(text: &str) -> String {
    let joined = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ");
    crate::escaped(&joined)
}

/// A failure of the command: the facade's errors, or one of `plot`'s and `info`'s own
/// (a bad spectral table or scene file, a plot that could not be drawn).
pub(crate) enum CliError {
    Lib(Error),
    /// Exit status 1, message as is.
    Failed(String),
}

impl From<Error> for CliError {
    fn from(e: Error) -> Self {
        CliError::Lib(e)
    }
}

impl From<output::OutputError> for CliError {
    fn from(e: output::OutputError) -> Self {
        CliError::Lib(Error::Output(e))
    }
}

/// `plot`'s parameter errors are bad usage (exit 2); drawing and encoding failures are not.
impl From<PlotError> for CliError {
    fn from(e: PlotError) -> Self {
        match e {
            PlotError::InvalidSize { .. }
            | PlotError::InvalidParameter { .. }
            | PlotError::EmptyEtaList
            | PlotError::TooManyCurves { .. } => CliError::Lib(Error::Usage(e.to_string())),
            other => CliError::Failed(other.to_string()),
        }
    }
}

fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Render(o) => Ok(render(&o)?),
        Command::Bench(o) => Ok(bench(&o)?),
        Command::View(o) => Ok(view(&o)?),
        Command::Devices => Ok(devices()?),
        Command::Eval(o) => Ok(eval(&o)?),
        Command::Plot(kind) => plot(&kind),
        Command::Info(o) => info(&o),
        Command::Diff(o) => diff(&o),
        Command::Batch(o) => batch(&o),
        Command::Completions { shell } => {
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut Cli::command(), "combustion", &mut script);
            write_stdout(format_args!("{}", String::from_utf8_lossy(&script)));
            Ok(())
        }
    }
}

/// A command line clap refused, or `--help`/`--version`: help and version go to standard
/// output (exit 0); usage errors to standard error with clap's message (exit 2), a long
/// value shortened to 40 characters.
fn refused(error: clap::Error) -> ExitCode {
    if !error.use_stderr() {
        write_stdout(format_args!("{}", error.render()));
        return ExitCode::SUCCESS;
    }
    let error = value_shortened(error);
    let _ = error.print();
    ExitCode::from(u8::try_from(error.exit_code()).unwrap_or(2))
}

/// clap's `error` with the value it refused shortened to 40 characters (a value of
/// megabytes is not echoed whole): the command line's and a batch job's refusals alike.
pub(crate) fn value_shortened(mut error: clap::Error) -> clap::Error {
    use clap::error::{ContextKind, ContextValue};
    if let Some(ContextValue::String(value)) = error.get(ContextKind::InvalidValue) {
        let short = shortened(value);
        if short != *value {
            error.insert(ContextKind::InvalidValue, ContextValue::String(short));
        }
    }
    error
}

/// Runs the command line of this process: parses it, runs the command, prints a failure
/// on one line and returns the exit status (0; 1 for a failure; 2 for bad usage).
pub fn run_command_line() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(error) => return refused(error),
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(CliError::Lib(e)) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            match e {
                Error::Usage(_) => ExitCode::from(2),
                _ => ExitCode::FAILURE,
            }
        }
        Err(CliError::Failed(message)) => {
            eprintln!("error: {}", one_line(&message));
            ExitCode::FAILURE
        }
    }
}
