//! An example host: an application with its own Vulkan device that embeds Combustion the
//! way a game engine does — Combustion records its deferred frame into the host's command
//! buffer and image, with frames in flight, and the host composes the result on the
//! device. See docs/integration.md.
//!
//! ```sh
//! cargo run --example host -- --frames 120                 # headless (offscreen final image)
//! cargo run --example host -- --soak 10000                 # edits, resizes, memory every 1,000 frames
//! cargo run --example host -- --frames 300 --validate      # validation + synchronization validation
//! cargo run --example host -- --window                     # in a window (X11); Escape to quit
//! cargo run --example host -- --frames 30 --screenshot host.png   # the last frame as PNG
//! cargo run --example host -- --soak 1000 --validate --scene builtin:all --scene model.glb
//! ```
//!
//! `--scene SOURCE` (repeatable): `builtin:NAME`, `builtin:all` (every built-in scene) or a
//! glTF file; the soak alternates between them (default: builtin:spheres and
//! builtin:hard-cases). Frames without `--soak` show the first.

mod app;
mod headless;
mod vulkan;
mod window;

use std::time::Instant;

use combustion::scene::builtin_scene;
use combustion::vk::ash::vk;

struct Options {
    frames: u64,
    soak: Option<u64>,
    frames_in_flight: usize,
    width: u32,
    height: u32,
    validate: bool,
    device: String,
    window: bool,
    frames_given: bool,
    screenshot: Option<String>,
    scenes: Vec<String>,
}

fn parse(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        frames: 120,
        soak: None,
        frames_in_flight: 2,
        width: 640,
        height: 360,
        validate: false,
        device: String::new(),
        window: false,
        frames_given: false,
        screenshot: None,
        scenes: Vec::new(),
    };
    let mut i = 0;
    while i < args.len() {
        let flag = args[i].as_str();
        let value = || {
            args.get(i + 1)
                .ok_or_else(|| format!("{flag} needs a value"))
        };
        let number = |v: &String| {
            v.parse::<u64>()
                .map_err(|_| format!("{flag} takes a whole number, not `{v}`"))
        };
        match flag {
            "--frames" => {
                o.frames = number(value()?)?;
                o.frames_given = true;
            }
            "--soak" => o.soak = Some(number(value()?)?),
            "--frames-in-flight" => o.frames_in_flight = number(value()?)? as usize,
            "--width" => o.width = number(value()?)? as u32,
            "--height" => o.height = number(value()?)? as u32,
            "--device" => o.device = value()?.clone(),
            "--screenshot" => o.screenshot = Some(value()?.clone()),
            "--scene" => o.scenes.push(value()?.clone()),
            "--validate" => {
                o.validate = true;
                i += 1;
                continue;
            }
            "--window" => {
                o.window = true;
                i += 1;
                continue;
            }
            _ => return Err(format!("unknown argument `{flag}`")),
        }
        i += 2;
    }
    if o.width <= 2 * app::BORDER || o.height <= 2 * app::BORDER {
        return Err(format!(
            "the image must be larger than {0}x{0}",
            2 * app::BORDER
        ));
    }
    Ok(o)
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Err(e) = parse(&args).and_then(|o| run(&o)) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The scenes `--scene` names, in order (`builtin:all`: every built-in scene).
fn load_scenes(sources: &[String]) -> Result<Vec<combustion::scene::Scene>, String> {
    let defaults = [
        "builtin:spheres".to_owned(),
        "builtin:hard-cases".to_owned(),
    ];
    let sources = if sources.is_empty() {
        &defaults[..]
    } else {
        sources
    };
    let mut scenes = Vec::new();
    for source in sources {
        if source == "builtin:all" {
            for name in combustion::scene::BUILTIN_SCENES {
                scenes.push(builtin_scene(name).map_err(|e| e.to_string())?);
            }
        } else {
            scenes.push(
                combustion::SceneSource::parse(source)
                    .load()
                    .map_err(|e| format!("{source}: {e}"))?,
            );
        }
    }
    Ok(scenes)
}

fn run(o: &Options) -> Result<(), String> {
    let scenes = load_scenes(&o.scenes)?;
    if o.window {
        let summary = window::run(
            &window::WindowOptions {
                width: o.width,
                height: o.height,
                frames: o.frames_given.then_some(o.frames),
                frames_in_flight: o.frames_in_flight,
                validation: o.validate,
                device: o.device.clone(),
                resize_at: None,
            },
            &scenes,
        )?;
        let median = |v: &[f64]| {
            let mut v = v.to_vec();
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
        };
        println!(
            "{} frames presented, {} in flight: {:.2} ms per frame wall clock (median), Combustion's GPU time {:.2} ms (median)",
            summary.presented,
            o.frames_in_flight,
            median(&summary.frame_ms),
            median(&summary.gpu_ms)
        );
        if let Some(first) = summary.validation_messages.first() {
            return Err(format!(
                "the validation layer reported {} message(s); first: {first}",
                summary.validation_messages.len()
            ));
        }
        return Ok(());
    }
    let vulkan = vulkan::HostVulkan::new(&o.device, o.validate, &[], &[])?;
    let mut host = app::Host::new(vulkan, o.frames_in_flight, &scenes)?;
    let extent = vk::Extent2D {
        width: o.width,
        height: o.height,
    };
    println!(
        "{} scene(s): {}",
        scenes.len(),
        scenes
            .iter()
            .map(|s| s.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let start = Instant::now();
    let frames = if let Some(frames) = o.soak {
        let other = vk::Extent2D {
            width: o.width * 3 / 4,
            height: o.height * 3 / 4,
        };
        println!(
            "{:>8} {:>10} {:>12} {:>14} {:>14}",
            "frame", "RSS (MiB)", "allocations", "allocated (B)", "held (B)"
        );
        let plan = headless::SoakPlan {
            frames,
            edit_every: 5,
            scene_every: 50,
            resize_every: 250,
            report_every: 1000,
            sizes: [extent, other],
        };
        headless::soak(&mut host, &scenes, &plan, |m| {
            println!(
                "{:>8} {:>10.1} {:>12} {:>14} {:>14}",
                m.frame,
                m.rss_bytes as f64 / 1048576.0,
                m.allocations,
                m.allocated_bytes,
                m.capacity_bytes
            );
        })?;
        frames
    } else {
        let mut output = headless::FinalImage::new(&host, extent)?;
        for _ in 0..o.frames {
            headless::frame(&mut host, &mut output, 0)?;
        }
        host.wait_frames()?;
        host.renderer()
            .frames_completed()
            .map_err(|e| e.to_string())?;
        if let Some(path) = &o.screenshot {
            let bytes = headless::read_back(
                &host,
                &output.image,
                output.state,
                vk::ImageAspectFlags::COLOR,
            )?;
            let pixels: Vec<[u8; 4]> = bytes
                .chunks_exact(4)
                .map(|c| [c[0], c[1], c[2], c[3]])
                .collect();
            combustion::output::write_png(path.as_ref(), o.width, o.height, &pixels)
                .map_err(|e| e.to_string())?;
            println!("wrote {path}");
        }
        output.image.destroy(&host.vulkan);
        o.frames
    };
    let elapsed = start.elapsed().as_secs_f64();
    let timings = host.renderer().take_completed_timings();
    let mut totals: Vec<f64> = timings.iter().map(|t| t.total_ms).collect();
    totals.sort_by(f64::total_cmp);
    // What `Renderer::record` cost the host's CPU per frame (it never waits for the GPU).
    let mut record_ms: Vec<f64> = host.record_ms.iter().copied().collect();
    record_ms.sort_by(f64::total_cmp);
    let log = host.vulkan.message_log();
    drop(host);
    let messages = log.lock().map(|m| m.clone()).unwrap_or_default();
    println!(
        "{frames} frames, {} in flight: {:.2} ms per frame wall clock; Combustion's GPU time {:.2} ms median; record {:.3} ms median",
        o.frames_in_flight,
        elapsed * 1e3 / frames as f64,
        totals.get(totals.len() / 2).copied().unwrap_or(f64::NAN),
        record_ms.get(record_ms.len() / 2).copied().unwrap_or(f64::NAN)
    );
    if !messages.is_empty() {
        return Err(format!(
            "the validation layer reported {} message(s); first: {}",
            messages.len(),
            messages[0]
        ));
    }
    Ok(())
}
