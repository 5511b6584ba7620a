//! The validation layer is really on in tests, and it really catches what we claim it
//! catches: a leaked object at device destruction is reported and would fail a test.

use crate::common;

use combustion::vk::{vk, Device, DeviceDesc, DeviceSelector};

fn lavapipe_device() -> std::sync::Arc<Device> {
    Device::new(&DeviceDesc {
        selector: DeviceSelector::NameContains("llvmpipe".into()),
        validation: true,
        ..DeviceDesc::default()
    })
    .expect("lavapipe with validation")
}

#[test]
fn a_leaked_object_is_reported_at_device_destruction() {
    let device = lavapipe_device();
    let log = device.validation_log();
    // Deliberately leak a sampler: created through the raw device, never destroyed.
    let info = vk::SamplerCreateInfo::default();
    let _leaked = unsafe { device.raw().create_sampler(&info, None) }.expect("sampler");
    assert!(
        log.is_empty(),
        "nothing to report before destruction: {:?}",
        log.messages()
    );
    drop(device);
    let messages = log.messages();
    assert!(
        messages.iter().any(|m| m.contains("VkSampler")),
        "the layer must report the leaked sampler, got {messages:?}"
    );
}

#[test]
fn misuse_of_the_api_is_reported() {
    let device = lavapipe_device();
    let log = device.validation_log();
    // A buffer of size 0 is invalid usage (VUID-VkBufferCreateInfo-size-00912).
    let info = vk::BufferCreateInfo::default()
        .size(0)
        .usage(vk::BufferUsageFlags::STORAGE_BUFFER);
    if let Ok(buffer) = unsafe { device.raw().create_buffer(&info, None) } {
        unsafe { device.raw().destroy_buffer(buffer, None) };
    }
    drop(device);
    assert!(
        log.messages().iter().any(|m| m.contains("size")),
        "the layer must report a zero-size buffer, got {:?}",
        log.messages()
    );
}

#[test]
fn a_full_frame_with_readback_is_clean() {
    let scene = combustion::scene::builtin_scene("spheres").unwrap();
    // common::render fails on any validation message, including leaks at teardown.
    let frame = common::render(
        &scene,
        64,
        48,
        Default::default(),
        combustion::renderer::Readback::ALL,
    );
    assert_eq!(frame.ldr.len(), 64 * 48);
    assert_eq!(frame.hdr.len(), 64 * 48);
    assert_eq!(
        frame.gbuffer.as_ref().map(|g| g.texels.len()),
        Some(64 * 48)
    );
}

#[test]
fn an_invalid_scene_is_refused_before_anything_is_uploaded() {
    let mut scene = combustion::scene::builtin_scene("spheres").unwrap();
    scene.objects[3].material = 999;
    let mut headless = common::lavapipe(Default::default());
    let error = match headless.renderer().upload(&scene) {
        Ok(_) => panic!("an object with a missing material must be refused"),
        Err(e) => e.to_string(),
    };
    assert!(error.contains("object 3 uses material 999"), "{error}");
    // Nothing was left behind: the device tears down without a leak report.
    common::finish(headless);
}
