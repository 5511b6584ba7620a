//! The smallest program that renders a scene through Combustion's public API:
//! `cargo run --example minimal -- out.png`.

use combustion::{output, Headless, HeadlessDesc, SceneSource};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), combustion::Error> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "minimal.png".into());
    let scene = SceneSource::parse("builtin:spheres").load()?;
    let mut headless = Headless::new(&HeadlessDesc::from_env(false)?)?;
    let frame = headless.render(&scene, 640, 360)?;
    output::write_png(path.as_ref(), frame.width, frame.height, &frame.ldr)?;
    println!("wrote {path}");
    Ok(())
}
