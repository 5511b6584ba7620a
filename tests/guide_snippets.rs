//! The Rust snippets of docs/integration.md, compiled: each is the body of a function
//! below, word for word (the host's own objects its parameters), so a snippet that
//! stops compiling fails the build; `every_snippet_of_the_guide_is_compiled_here` fails
//! when the guide's text and these bodies part (a snippet edited in one place only).

#![allow(dead_code, clippy::too_many_arguments)]

use std::error::Error;
use std::sync::{Arc, Mutex};

use combustion::renderer::{
    AntiAliasing, Background, ColorTarget, DepthTarget, FrameInputs, FrameTarget, GpuScene,
    Renderer, RendererSettings, ToneMapping, DEFAULT_BLOOM_INTENSITY,
};
use combustion::scene::{Camera, Light, Material, Mesh, Scene};
use combustion::vk::gpu_allocator::vulkan::Allocator;
use combustion::vk::{ash, vk, Device, ImageState};
use glam::Mat4;

/// §1, "Your device".
#[rustfmt::skip]
fn your_device(
    entry: ash::Entry,
    instance: ash::Instance,
    your_instance: &ash::Instance,
    physical_device: vk::PhysicalDevice,
    app_info: vk::ApplicationInfo<'_>,
    device_info: vk::DeviceCreateInfo<'_>,
    queue_family: u32,
    your_queue_lock: &Arc<Mutex<vk::Queue>>,
    your_allocator: &Arc<Mutex<Allocator>>,
) -> Result<Arc<Device>, Box<dyn Error>> {
    use combustion_vk::{Device, EnabledFeatures, HostDevice};   // or combustion::vk::… through the facade

    // SAFETY: `device_info` and its chain are valid and alive (your own device creation).
    let device = unsafe { your_instance.create_device(physical_device, &device_info, None)? };
    // SAFETY: `device_info` is what the device was created with, still alive.
    let enabled = unsafe { EnabledFeatures::from_create_info(app_info.api_version, &device_info) };
    let device = Device::from_host(HostDevice {
        entry, instance, physical_device, device,          // your ash objects (cloned handles)
        queue_family, queue_index: 0,
        queue: your_queue_lock.clone(),                    // Arc<Mutex<vk::Queue>>: lock it around your own queue calls
        allocator: Some(your_allocator.clone()),           // Arc<Mutex<gpu_allocator::vulkan::Allocator>>, or None
        enabled,
    })?;
    Ok(device)
}

/// §2, "The renderer, once" (the guide's scene is `mut` for the edits that follow).
#[rustfmt::skip]
#[allow(unused_mut)]
fn the_renderer_once(
    device: Arc<Device>,
    saved_cache_bytes: Vec<u8>,
    cpu_scene: Scene,
) -> Result<(Renderer, GpuScene), Box<dyn Error>> {
    let mut renderer = Renderer::with_pipeline_cache(device, RendererSettings {
        frames_in_flight: 2,                               // 1..=3, your ring's length
        ..RendererSettings::default()
    }, &saved_cache_bytes)?;                               // or Renderer::new(device, settings)
    renderer.prepare_output(vk::Format::B8G8R8A8_UNORM)?; // every format you will render into
                                                           // (DISPLAY_FORMAT, RGBA8_UNORM, is prepared by new)
    let mut scene = renderer.upload(&cpu_scene)?;          // builds the pipelines the scene needs
    Ok((renderer, scene))
}

/// §3, "Every frame".
#[rustfmt::skip]
fn every_frame(
    renderer: &mut Renderer,
    cmd: vk::CommandBuffer,
    slot: usize,
    scene: GpuScene,
    camera: Camera,
    exposure: f32,
    lights: Vec<Light>,
    n: u64,
    (image, view, image_info): (vk::Image, vk::ImageView, vk::ImageCreateInfo<'_>),
    (depth, depth_info): (vk::Image, vk::ImageCreateInfo<'_>),
    (before, after): (ImageState, ImageState),
) -> Result<(), Box<dyn Error>> {
    // You waited for the fence of the frame that last used `slot` (frame n − N): the only wait.
    renderer.record(cmd, slot, &scene,
        &FrameInputs { camera, exposure, lights: &lights, overlay: &[], environment: None,
                       background: Background::None, tone_mapping: ToneMapping::Exponential,
                       pose: None, environment_seed: n as u32, anti_aliasing: AntiAliasing::Fxaa,
                       auto_exposure: None, bloom_intensity: DEFAULT_BLOOM_INTENSITY },
        &FrameTarget {
            // format, extent and usage from the create info the image was created with
            color: ColorTarget::from_create_info(image, view, &image_info, before, after)?,
            depth: Some(DepthTarget::from_create_info(depth, &depth_info, before, after)?),
        })?;
    // … your own passes, then you submit `cmd` on the same queue.
    Ok(())
}

/// "Between frames", an edit by handle and its undo.
#[rustfmt::skip]
fn between_frames(renderer: &mut Renderer, mut scene: GpuScene) -> Result<(), Box<dyn Error>> {
    let (floor, _) = renderer.try_edit_scene(&mut scene, |e| {
        let mesh = e.add_mesh(Mesh::plane("floor", 10.0));
        let material = e.add_material(Material::default());
        e.add_object(mesh, material, Mat4::IDENTITY)
    })?;
    // … later: undo
    renderer.try_edit_scene(&mut scene, |e| e.remove_object(floor).map(drop))?;
    Ok(())
}

/// The lines of each ```rust block of `markdown`, trimmed, blank lines left out.
fn rust_blocks(markdown: &str) -> Vec<Vec<String>> {
    let mut blocks = Vec::new();
    let mut current: Option<Vec<String>> = None;
    for line in markdown.lines() {
        let trimmed = line.trim();
        match (&mut current, trimmed) {
            (None, "```rust") => current = Some(Vec::new()),
            (Some(_), "```") => blocks.extend(current.take()),
            (Some(block), text) if !text.is_empty() => block.push(text.to_owned()),
            _ => {}
        }
    }
    blocks
}

#[test]
fn every_snippet_of_the_guide_is_compiled_here() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let guide = std::fs::read_to_string(root.join("docs/integration.md")).unwrap();
    let here = std::fs::read_to_string(root.join("tests/guide_snippets.rs")).unwrap();
    let lines: Vec<&str> = here
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let blocks = rust_blocks(&guide);
    assert_eq!(blocks.len(), 4, "the guide's Rust snippets");
    for block in &blocks {
        let found = lines
            .windows(block.len())
            .any(|window| window.iter().zip(block).all(|(a, b)| a == b));
        assert!(
            found,
            "this snippet of docs/integration.md is not a function body of tests/guide_snippets.rs, word for word:\n{}",
            block.join("\n")
        );
    }
}
