//! `combustion`: render built-in scenes headless, benchmark the passes, list devices.

use std::path::PathBuf;
use std::process::ExitCode;

use combustion::renderer::{Readback, RendererSettings};
use combustion::vk::{DeviceDesc, DeviceSelector};
use combustion::{check_validation, output, Error, Headless, HeadlessDesc, SceneSource};

const USAGE: &str = "\
combustion — Vulkan deferred renderer with physically based shading

USAGE:
  combustion render [SCENE] [-o OUT.png] [--hdr OUT.exr] [--width N] [--height N]
                    [--exposure X] [--device SEL] [--validate]
  combustion bench  [SCENE] [--width N] [--height N] [--frames N] [--device SEL] [--validate]
  combustion eval TERM [--theta-v DEG --theta-l DEG ... | --v x,y,z --l x,y,z]
                    [--alpha A | --roughness R | --alpha-x A --alpha-y A] [--eta E|r,g,b]
                    [--k K|r,g,b] [--eta-i E] [--sigma S] [--polarisation W] [--rho R|r,g,b]
                    [--metalness M] [--dielectric-eta E] [--diffuse MODEL] [--f0 F]
  combustion eval --list
  combustion devices
  combustion help

SCENE is builtin:NAME (built-in scenes: spheres); default builtin:spheres.
--device SEL picks a Vulkan device by index or by part of its name (e.g. llvmpipe);
the COMBUSTION_DEVICE environment variable does the same. --validate turns on the
Khronos validation layer and fails if it reports anything.
Logging: COMBUSTION_LOG=error|warn|info|debug|trace (default warn).";

struct StderrLogger;

impl log::Log for StderrLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::max_level()
    }
    fn log(&self, record: &log::Record<'_>) {
        if self.enabled(record.metadata()) {
            eprintln!("[{} {}] {}", record.level(), record.target(), record.args());
        }
    }
    fn flush(&self) {}
}

fn init_logging() {
    let level = std::env::var("COMBUSTION_LOG")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(log::LevelFilter::Warn);
    static LOGGER: StderrLogger = StderrLogger;
    let _ = log::set_logger(&LOGGER);
    log::set_max_level(level);
}

/// Options common to `render` and `bench`.
struct Options {
    scene: SceneSource,
    width: u32,
    height: u32,
    output: Option<PathBuf>,
    hdr: Option<PathBuf>,
    exposure: f32,
    frames: u32,
    device: Option<DeviceSelector>,
    validate: bool,
}

fn number<T: std::str::FromStr>(flag: &str, value: &str) -> Result<T, Error> {
    value
        .parse()
        .map_err(|_| Error::Usage(format!("{flag}: `{value}` is not a valid number")))
}

fn parse_options(args: &[String], command: &str) -> Result<Options, Error> {
    let mut o = Options {
        scene: SceneSource::parse("builtin:spheres"),
        width: 1280,
        height: 720,
        output: None,
        hdr: None,
        exposure: 1.0,
        frames: 30,
        device: None,
        validate: false,
    };
    let mut scene_given = false;
    let mut i = 0;
    while i < args.len() {
        let flag = args[i].as_str();
        let mut value = || -> Result<&str, Error> {
            i += 1;
            args.get(i)
                .map(String::as_str)
                .ok_or_else(|| Error::Usage(format!("{flag} needs a value")))
        };
        match flag {
            "--scene" => {
                o.scene = SceneSource::parse(value()?);
                scene_given = true;
            }
            "--width" => o.width = number(flag, value()?)?,
            "--height" => o.height = number(flag, value()?)?,
            "-o" | "--output" if command == "render" => o.output = Some(PathBuf::from(value()?)),
            "--hdr" if command == "render" => o.hdr = Some(PathBuf::from(value()?)),
            "--exposure" => o.exposure = number(flag, value()?)?,
            "--frames" if command == "bench" => o.frames = number(flag, value()?)?,
            "--device" => o.device = Some(value()?.parse()?),
            "--validate" => o.validate = true,
            _ if !flag.starts_with('-') && !scene_given => {
                o.scene = SceneSource::parse(flag);
                scene_given = true;
            }
            _ => {
                return Err(Error::Usage(format!(
                    "unknown argument `{flag}` for `combustion {command}` (see `combustion help`)"
                )))
            }
        }
        i += 1;
    }
    if command == "render" && o.output.is_none() && o.hdr.is_none() {
        o.output = Some(PathBuf::from("out.png"));
    }
    if o.width == 0 || o.height == 0 {
        return Err(Error::Usage(format!(
            "image size {}x{} is empty; --width and --height must be at least 1",
            o.width, o.height
        )));
    }
    if command == "bench" && o.frames == 0 {
        return Err(Error::Usage("--frames must be at least 1".into()));
    }
    Ok(o)
}

fn headless(o: &Options) -> Result<Headless, Error> {
    let selector = match &o.device {
        Some(s) => s.clone(),
        None => DeviceSelector::from_env()?,
    };
    Headless::new(&HeadlessDesc {
        device: DeviceDesc {
            selector,
            validation: o.validate,
        },
        settings: RendererSettings {
            exposure: o.exposure,
            ..RendererSettings::default()
        },
    })
}

fn render(o: &Options) -> Result<(), Error> {
    // Fail on an unwritable destination before spending time on the render.
    for path in o.output.iter().chain(o.hdr.iter()) {
        output::check_writable(path)?;
    }
    let scene = o.scene.load()?;
    let mut headless = headless(o)?;
    let frame = headless.render(&scene, o.width, o.height)?;
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    if let Some(path) = &o.output {
        output::write_png(path, frame.width, frame.height, &frame.ldr)?;
        println!(
            "wrote {} ({}x{})",
            path.display(),
            frame.width,
            frame.height
        );
    }
    if let Some(path) = &o.hdr {
        output::write_exr(path, frame.width, frame.height, &frame.hdr)?;
        println!(
            "wrote {} ({}x{}, linear float)",
            path.display(),
            frame.width,
            frame.height
        );
    }
    let t = frame.timings;
    println!(
        "GPU time: G-buffer {:.2} ms, lighting {:.2} ms, tonemap {:.2} ms, total {:.2} ms (one frame; `combustion bench` for medians)",
        t.gbuffer_ms, t.lighting_ms, t.tonemap_ms, t.total_ms
    );
    Ok(())
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    let index = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[index]
}

fn bench(o: &Options) -> Result<(), Error> {
    let scene = o.scene.load()?;
    let mut headless = headless(o)?;
    let device_name = {
        let renderer = headless.renderer();
        renderer.device().info().name.clone()
    };
    let renderer = headless.renderer();
    let gpu_scene = renderer.upload(&scene)?;
    // One warm-up frame (pipeline caches, first-touch allocations) is not counted.
    renderer.render(&gpu_scene, o.width, o.height, Readback::default())?;
    let mut samples: [Vec<f64>; 4] = Default::default();
    for _ in 0..o.frames {
        let t = renderer
            .render(&gpu_scene, o.width, o.height, Readback::default())?
            .timings;
        for (list, value) in
            samples
                .iter_mut()
                .zip([t.gbuffer_ms, t.lighting_ms, t.tonemap_ms, t.total_ms])
        {
            list.push(value);
        }
    }
    drop(gpu_scene);
    let validation = headless.validation_log();
    drop(headless);
    check_validation(&validation)?;
    println!(
        "scene {:?} at {}x{} on {device_name}, n={} frames (GPU timestamps, ms):",
        o.scene, o.width, o.height, o.frames
    );
    println!("{:<10} {:>9} {:>9} {:>9}", "pass", "median", "p10", "p90");
    for (name, list) in ["G-buffer", "lighting", "tonemap", "total"]
        .iter()
        .zip(&mut samples)
    {
        list.sort_by(f64::total_cmp);
        println!(
            "{:<10} {:>9.2} {:>9.2} {:>9.2}",
            name,
            percentile(list, 0.5),
            percentile(list, 0.1),
            percentile(list, 0.9)
        );
    }
    Ok(())
}

fn devices() -> Result<(), Error> {
    let devices = combustion::vk::Device::enumerate()?;
    if devices.is_empty() {
        return Err(Error::Vulkan(combustion::vk::VkError::NoDevice));
    }
    for d in devices {
        println!(
            "{}: {} ({:?}, Vulkan {}.{}.{}, {}){}",
            d.index,
            d.name,
            d.device_type,
            d.api_version.0,
            d.api_version.1,
            d.api_version.2,
            d.driver,
            d.unsuitable_because
                .map(|why| format!(" — unusable: {why}"))
                .unwrap_or_default()
        );
    }
    Ok(())
}

fn eval(args: &[String]) -> Result<(), Error> {
    match args.split_first() {
        None => Err(Error::Usage(
            "`combustion eval` needs a term; `combustion eval --list` lists them".into(),
        )),
        Some((list, _)) if list == "--list" => {
            for (name, what) in combustion::eval::TERMS {
                println!("{name:<24} {what}");
            }
            Ok(())
        }
        Some((term, rest)) => {
            println!("{}", combustion::eval::evaluate(term, rest)?);
            Ok(())
        }
    }
}

fn run(args: &[String]) -> Result<(), Error> {
    let (command, rest) = match args.split_first() {
        Some((c, rest)) => (c.as_str(), rest),
        None => ("help", &[][..]),
    };
    match command {
        "render" => render(&parse_options(rest, "render")?),
        "bench" => bench(&parse_options(rest, "bench")?),
        "devices" => devices(),
        "eval" => eval(rest),
        "help" | "--help" | "-h" => {
            println!("{USAGE}");
            Ok(())
        }
        "--version" | "-V" => {
            println!("combustion {}", env!("CARGO_PKG_VERSION"));
            Ok(())
        }
        other => Err(Error::Usage(format!(
            "unknown command `{other}` (commands: render, bench, eval, devices, help)"
        ))),
    }
}

fn main() -> ExitCode {
    init_logging();
    let args: Vec<String> = std::env::args().skip(1).collect();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            match e {
                Error::Usage(_) => ExitCode::from(2),
                _ => ExitCode::FAILURE,
            }
        }
    }
}
