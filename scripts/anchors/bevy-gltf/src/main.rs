//! Bevy's deferred renderer on one glTF file, seen through the file's first camera and
//! lit by the file's own lights (KHR_lights_punctual), at W×H (1280×720 by default) with
//! vsync off, in a window. Prints the median wall-clock frame time of 100 frames after 30
//! of warm-up, as the bevy-spheres anchor does: `bevy-gltf FILE.gltf`. With SCREENSHOT=
//! FILE.png it also saves the window's image at the end of the warm-up (to look at what
//! it draws beside Combustion's).
use bevy::core_pipeline::prepass::{DeferredPrepass, DepthPrepass};
use bevy::pbr::DefaultOpaqueRendererMethod;
use bevy::prelude::*;
use bevy::render::view::screenshot::{Screenshot, save_to_disk};
use bevy::window::{PresentMode, WindowResolution};

/// The file asked for, by its name in its folder (the asset root).
#[derive(Resource)]
struct Model(String);

/// Frame times after the warm-up, and the frames seen.
#[derive(Resource, Default)]
struct Frames {
    seconds: Vec<f64>,
    seen: u32,
}

const WARM_UP: u32 = 30;
const MEASURED: u32 = 100;

fn main() {
    let Some(file) = std::env::args().nth(1) else {
        eprintln!("usage: bevy-gltf FILE.gltf");
        std::process::exit(2);
    };
    let path = std::path::absolute(&file).expect("a path");
    let folder = path.parent().expect("a folder").to_string_lossy().into_owned();
    let name = path.file_name().expect("a file name").to_string_lossy().into_owned();
    let size = |var: &str, default: u32| {
        std::env::var(var).ok().and_then(|s| s.parse().ok()).unwrap_or(default)
    };
    App::new()
        .insert_resource(DefaultOpaqueRendererMethod::deferred())
        .insert_resource(Frames::default())
        .insert_resource(Model(name))
        .add_plugins(
            DefaultPlugins
                .set(WindowPlugin {
                    primary_window: Some(Window {
                        resolution: WindowResolution::new(size("W", 1280), size("H", 720)),
                        present_mode: PresentMode::AutoNoVsync,
                        ..default()
                    }),
                    ..default()
                })
                .set(AssetPlugin {
                    file_path: folder,
                    ..default()
                }),
        )
        .add_systems(Startup, load)
        .add_systems(Update, (deferred_cameras, measure))
        .run();
}

fn load(mut commands: Commands, assets: Res<AssetServer>, model: Res<Model>) {
    commands.spawn(WorldAssetRoot(
        assets.load(GltfAssetLabel::Scene(0).from_asset(model.0.clone())),
    ));
}

/// The file's cameras render deferred, without MSAA, as the sphere anchor's camera does.
fn deferred_cameras(mut commands: Commands, cameras: Query<Entity, Added<Camera3d>>) {
    for camera in &cameras {
        commands
            .entity(camera)
            .insert((Msaa::Off, DepthPrepass, DeferredPrepass));
    }
}

fn measure(
    mut commands: Commands,
    time: Res<Time<Real>>,
    mut frames: ResMut<Frames>,
    mut exit: MessageWriter<AppExit>,
) {
    frames.seen += 1;
    if frames.seen == WARM_UP {
        if let Ok(path) = std::env::var("SCREENSHOT") {
            commands
                .spawn(Screenshot::primary_window())
                .observe(save_to_disk(path));
        }
    }
    if frames.seen > WARM_UP {
        let seconds = time.delta_secs_f64();
        frames.seconds.push(seconds);
    }
    if frames.seen >= WARM_UP + MEASURED {
        let mut sorted = frames.seconds.clone();
        sorted.sort_by(f64::total_cmp);
        println!(
            "bevy deferred gltf frames={} median_ms={:.2}",
            sorted.len(),
            sorted[sorted.len() / 2] * 1e3
        );
        exit.write(AppExit::Success);
    }
}
