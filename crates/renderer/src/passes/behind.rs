//! What lies behind the transmissive objects: the lit HDR image as the lighting pass
//! left it (the opaque surfaces and the background), copied before the forward pass
//! draws over it, with every mip level made by linear blits (a rough transmissive
//! surface reads a coarser level). Runs in frames whose forward pass draws transmissive
//! objects by screen-space refraction (traced refraction reads no image of it).

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::graph::ImageUse;
use crate::options::RendererSettings;
use crate::pass_io::PassIo;
use crate::results::PassTimings;
use crate::targets::ImageRequest;
use crate::variant::ShaderVariant;

pub(crate) struct Behind;

/// The name of the image of what lies behind the transmissive objects: the lit HDR
/// image before the forward pass, with every mip level (rough transmission reads coarser
/// levels).
pub(crate) const BEHIND: &str = "hdr radiance behind transmissive objects";

/// Whether frames of `variant` refract by looking up what lies behind on the screen:
/// TRANSMISSION variants that do not trace refraction
/// ([`super::ray_traced_refraction::wanted`]: forward.frag's traced variant reads
/// neither this pass's image nor the back faces').
pub(super) fn screen_space_refraction(variant: ShaderVariant) -> bool {
    variant.transmission && !super::ray_traced_refraction::wanted(variant)
}

impl FramePass for Behind {
    fn name(&self) -> &'static str {
        PassTimings::BEHIND
    }

    fn images(&self, variant: ShaderVariant, settings: &RendererSettings) -> Vec<ImageRequest> {
        if !screen_space_refraction(variant) {
            return Vec::new();
        }
        vec![ImageRequest::new(
            BEHIND,
            settings.hdr_format.vk(),
            vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::TRANSFER_DST,
        )
        .with_full_mips()]
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        // Those frames have the behind image (`images`).
        screen_space_refraction(frame.variant) && super::forward::draws(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let behind = frame.images.get(BEHIND);
        PassIo::new(self.name())
            .touches(frame.hdr.into(), ImageUse::TransferSource)
            .touches(behind.into(), ImageUse::MipChainWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let behind = frame.images.get(BEHIND);
        let region =
            crate::commands::level_zero_copy(vk::ImageAspectFlags::COLOR, frame.hdr.extent());
        // SAFETY: recording state; both images are in the layouts `io` declared.
        unsafe {
            frame.device.raw().cmd_copy_image(
                cmd,
                frame.hdr.raw(),
                ImageUse::TransferSource.state().layout,
                behind.raw(),
                ImageUse::MipChainWrite.state().layout,
                &[region],
            )
        };
        let after = ImageUse::MipChainWrite.state();
        behind.record_mip_chain(cmd, (after.stage, after.access, after.layout));
    }
}
