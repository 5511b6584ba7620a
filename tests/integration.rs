//! The integration tests, one test binary: each file below is a module (one binary
//! links the renderer once, where a binary per file linked it 29 times: docs/build.md, "Build
//! cost"). `cargo nextest run` still runs each test in its own process; a test's name is
//! its file's, then its own: `cli::supersampling_and_anti_aliasing_on_the_command_line`.

mod common;

// The example host (examples/host), whose modules name each other from the crate root:
// tests/host.rs drives it.
#[path = "../examples/host/app.rs"]
mod app;
#[path = "../examples/host/headless.rs"]
mod headless;
#[path = "../examples/host/vulkan.rs"]
mod vulkan;
#[path = "../examples/host/window.rs"]
mod window;

mod ambient_occlusion;
mod animation;
mod anti_aliasing;
mod batch;
mod blending;
mod bloom;
mod cli;
mod cpu_device;
mod cutouts;
mod debug_views;
mod edits;
mod end_to_end;
mod environment;
mod exposure;
mod faults;
mod figures;
mod fuzz_corpus;
mod gltf;
mod guide_engine;
mod guide_snippets;
mod host;
mod identities;
mod images;
mod light_culling;
mod overlay;
mod parity;
mod path_trace;
mod points_and_lines;
mod reflections;
mod refraction;
mod report;
mod shading_options;
mod shadows;
mod specialisation;
mod temporal;
mod texture_transform;
mod tone_mapping;
mod transmission;
mod validation;
mod viewer;
