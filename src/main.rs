//! `combustion`: render built-in scenes headless, benchmark the passes, list devices,
//! evaluate optics terms, plot reflectance and spectra, describe scenes.
//!
//! The command line is declared with clap's derive API in `cli/args.rs` (one module
//! per command beside it; this file keeps `main` and the mapping of errors to exit codes): every subcommand has
//! `--help`, bad usage exits 2 with clap's message, paths are taken as `OsString`s (any
//! bytes the system allows), and `combustion completions SHELL` prints completions made
//! from the same declaration.

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

use combustion::{output, shortened, Error};
use combustion_plots::PlotError;

/// Writes `text` to standard output: a closed pipe (`combustion … | head`) ends the
/// program quietly (exit 0: the reader has what it wanted); any other write error (a
/// full disk, `> /dev/full`) is reported in one line and exits 1, never ignored.
fn write_stdout(text: std::fmt::Arguments<'_>) {
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

mod cli;

use cli::{batch, bench, devices, diff, eval, info, plot, render, view, Cli, Command};

struct StderrLogger;

impl log::Log for StderrLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }
    /// Warnings and errors as a user reads them (`warning: …`, `error: …`, as the
    /// command line's own errors; no module path); the levels below for developers,
    /// with the module that logged them (`[INFO combustion_renderer::…] …`).
    fn log(&self, record: &log::Record<'_>) {
        if self.enabled(record.metadata()) {
            match record.level() {
                log::Level::Error => eprintln!("error: {}", record.args()),
                log::Level::Warn => eprintln!("warning: {}", record.args()),
                level => eprintln!("[{level} {}] {}", record.target(), record.args()),
            }
        }
    }
    fn flush(&self) {}
}

fn init_logging() {
    // A level that is not one says so (once, before anything is logged) rather than
    // being ignored.
    let level = match std::env::var_os("COMBUSTION_LOG") {
        None => log::LevelFilter::Warn,
        Some(value) => match value.to_str().and_then(|s| s.parse().ok()) {
            Some(level) => level,
            None => {
                eprintln!(
                    "warning: COMBUSTION_LOG=`{}` is not off, error, warn, info, debug or trace; logging warnings",
                    combustion::shortened(&value.to_string_lossy())
                );
                log::LevelFilter::Warn
            }
        },
    };
    static LOGGER: StderrLogger = StderrLogger;
    let _ = log::set_logger(&LOGGER);
    log::set_max_level(level);
}

/// `text` on one line: line breaks (an importer's or parser's detail) become "; ".
fn one_line(text: &str) -> String {
    text.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// A failure of the command: the facade's errors, or one of `plot`'s and `info`'s own
/// (a bad spectral table or scene file, a plot that could not be drawn).
enum CliError {
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
fn refused(mut error: clap::Error) -> ExitCode {
    use clap::error::{ContextKind, ContextValue};
    if !error.use_stderr() {
        write_stdout(format_args!("{}", error.render()));
        return ExitCode::SUCCESS;
    }
    if let Some(ContextValue::String(value)) = error.get(ContextKind::InvalidValue) {
        let short = shortened(value);
        if short != *value {
            error.insert(ContextKind::InvalidValue, ContextValue::String(short));
        }
    }
    let _ = error.print();
    ExitCode::from(u8::try_from(error.exit_code()).unwrap_or(2))
}

fn main() -> ExitCode {
    // First, before any thread starts: an interrupted write leaves no partial file.
    output::remove_partial_files_on_termination();
    init_logging();
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
