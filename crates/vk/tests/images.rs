//! Images as the backend creates and fills them, on lavapipe with validation
//! (synchronization included): the aspect of depth and stencil formats, and uploads with
//! mip generation into every layer of arrays and cube maps.

use std::sync::Arc;

use combustion_vk::gpu_allocator::MemoryLocation;
use combustion_vk::{vk, Buffer, Device, DeviceDesc, DeviceSelector, Image, ImageDesc, OneShot};

fn device() -> Arc<Device> {
    Device::new(&DeviceDesc {
        selector: DeviceSelector::NameContains("llvmpipe".into()),
        validation: true,
        synchronization_validation: true,
        ..DeviceDesc::default()
    })
    .expect("lavapipe with validation")
}

/// Whether the device can make `format` an optimally tiled image with `features`.
fn supports(device: &Device, format: vk::Format, features: vk::FormatFeatureFlags) -> bool {
    // SAFETY: plain query on the device's own physical device.
    let properties = unsafe {
        device
            .instance()
            .get_physical_device_format_properties(device.physical_device(), format)
    };
    properties.optimal_tiling_features.contains(features)
}

#[test]
fn depth_and_stencil_images_get_the_aspect_of_their_format() {
    let device = device();
    let log = device.validation_log();
    use vk::ImageAspectFlags as A;
    let cases = [
        (vk::Format::D16_UNORM, A::DEPTH),
        (vk::Format::D32_SFLOAT, A::DEPTH),
        (vk::Format::X8_D24_UNORM_PACK32, A::DEPTH),
        (vk::Format::D16_UNORM_S8_UINT, A::DEPTH | A::STENCIL),
        (vk::Format::D24_UNORM_S8_UINT, A::DEPTH | A::STENCIL),
        (vk::Format::D32_SFLOAT_S8_UINT, A::DEPTH | A::STENCIL),
        (vk::Format::S8_UINT, A::STENCIL),
        (vk::Format::R8G8B8A8_UNORM, A::COLOR),
    ];
    let mut made = Vec::new();
    for (format, aspect) in cases {
        let (usage, feature) = if aspect == A::COLOR {
            (
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
                vk::FormatFeatureFlags::COLOR_ATTACHMENT,
            )
        } else {
            (
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT,
            )
        };
        if !supports(&device, format, feature) {
            continue;
        }
        let image = Image::new(&device, &ImageDesc::new("attachment", format, 8, 8, usage))
            .unwrap_or_else(|e| panic!("{format:?}: {e}"));
        assert_eq!(image.aspect(), aspect, "{format:?}");
        assert_eq!(image.subresource_range().aspect_mask, aspect, "{format:?}");
        made.push(format);
    }
    // Lavapipe has these two at least; a combined format must have been tried.
    assert!(made.contains(&vk::Format::D32_SFLOAT), "{made:?}");
    assert!(made.contains(&vk::Format::D32_SFLOAT_S8_UINT), "{made:?}");
    drop(device);
    let messages = log.messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}

/// A distinct, non-zero RGBA8 colour for each layer.
fn layer_colour(layer: u32) -> [u8; 4] {
    [
        10 + 40 * layer as u8,
        200 - 30 * layer as u8,
        7 * layer as u8 + 1,
        255,
    ]
}

/// Uploads `desc` (RGBA8, every layer one colour) with [`Image::record_upload_with_mips`]
/// and reads every level of every layer back.
fn upload_and_read_back(device: &Arc<Device>, desc: &ImageDesc<'_>) {
    let image = Image::new(device, desc).unwrap();
    let (width, height) = (desc.width as usize, desc.height as usize);
    let pixels: Vec<u8> = (0..desc.layers)
        .flat_map(|layer| std::iter::repeat_n(layer_colour(layer), width * height).flatten())
        .collect();
    let staging = Buffer::with_data(
        device,
        "staging",
        &pixels,
        vk::BufferUsageFlags::TRANSFER_SRC,
    )
    .unwrap();
    let mut commands = OneShot::new(device).unwrap();
    let cmd = commands.begin().unwrap();
    image.record_upload_with_mips(cmd, &staging);
    commands.submit_and_wait().unwrap();

    let readbacks: Vec<(u32, u32, Buffer)> = (0..image.mip_levels())
        .flat_map(|level| (0..image.layers()).map(move |layer| (level, layer)))
        .map(|(level, layer)| {
            let e = image.mip_extent(level);
            let buffer = Buffer::new(
                device,
                "readback",
                u64::from(e.width * e.height * 4),
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
            .unwrap();
            (level, layer, buffer)
        })
        .collect();
    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
    let cmd = commands.begin().unwrap();
    let raw = device.raw();
    let to_copy = [image.barrier(
        (
            S::FRAGMENT_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        ),
        (S::COPY, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
    )];
    // SAFETY: recording into our own command buffer.
    unsafe {
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&to_copy),
        )
    };
    for (level, layer, buffer) in &readbacks {
        image.record_level_copy_to_buffer(cmd, buffer, *level, *layer);
    }
    let to_host = [vk::MemoryBarrier2::default()
        .src_stage_mask(S::COPY)
        .src_access_mask(A::TRANSFER_WRITE)
        .dst_stage_mask(S::HOST)
        .dst_access_mask(A::HOST_READ)];
    // SAFETY: as above.
    unsafe {
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&to_host),
        )
    };
    commands.submit_and_wait().unwrap();
    for (level, layer, buffer) in &readbacks {
        let texels = buffer.mapped().unwrap();
        for (i, texel) in texels.chunks_exact(4).enumerate() {
            assert_eq!(
                texel,
                layer_colour(*layer),
                "{}: level {level}, layer {layer}, texel {i}",
                desc.name
            );
        }
    }
}

#[test]
fn uploads_fill_every_level_of_every_layer_of_arrays_and_cube_maps() {
    let device = device();
    let log = device.validation_log();
    let usage = vk::ImageUsageFlags::SAMPLED
        | vk::ImageUsageFlags::TRANSFER_DST
        | vk::ImageUsageFlags::TRANSFER_SRC;
    let format = vk::Format::R8G8B8A8_UNORM;
    upload_and_read_back(
        &device,
        &ImageDesc::new("plain", format, 8, 4, usage).full_mips(),
    );
    upload_and_read_back(
        &device,
        &ImageDesc::new("array", format, 8, 4, usage)
            .array(3)
            .full_mips(),
    );
    upload_and_read_back(
        &device,
        &ImageDesc::cube("cube", format, 8, usage).full_mips(),
    );
    upload_and_read_back(
        &device,
        &ImageDesc::cube("cube without mips", format, 4, usage),
    );
    drop(device);
    let messages = log.messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}
