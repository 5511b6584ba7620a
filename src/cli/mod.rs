//! The command line, one module per command: [`args`] declares every command and option;
//! the others run them. `main.rs` keeps `main` and the mapping of errors to exit codes.

pub(crate) mod args;
mod batch;
mod bench;
mod diff;
mod info;
mod manifest;
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
