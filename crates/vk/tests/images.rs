//! Images as the backend creates them, on lavapipe with validation (synchronization
//! included): the aspect of depth and stencil formats.

use std::sync::Arc;

use combustion_vk::{vk, Device, DeviceDesc, DeviceSelector, Image, ImageDesc};

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
