//! `combustion`: render built-in scenes headless, benchmark the passes, list devices,
//! evaluate optics terms, plot reflectance and spectra, describe scenes.
//!
//! The command line is the library's [`combustion::cli`] (src/cli: clap's derive API in
//! `args.rs`, one module per command beside it, and the mapping of errors to exit codes);
//! this file keeps `main` and the log's format.

use std::process::ExitCode;

use combustion::output;

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
            // On one line, control characters (a file name's) as escapes: the rule of
            // the command's own errors.
            let prefix = match record.level() {
                log::Level::Error => "error",
                log::Level::Warn => "warning",
                level => {
                    eprintln!("[{level} {}] {}", record.target(), record.args());
                    return;
                }
            };
            eprintln!(
                "{prefix}: {}",
                combustion::cli::one_line(&record.args().to_string())
            );
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

fn main() -> ExitCode {
    // First, before any thread starts: an interrupted write leaves no partial file.
    output::remove_partial_files_on_termination();
    init_logging();
    combustion::cli::run_command_line()
}
