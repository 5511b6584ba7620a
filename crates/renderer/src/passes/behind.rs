//! What lies behind the transmissive objects: the lit HDR image as the lighting pass
//! left it (the opaque surfaces and the background), copied before the forward pass
//! draws over it, with every mip level made by linear blits (a rough transmissive
//! surface reads a coarser level). Runs in frames whose forward pass draws transmissive
//! objects.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::graph::ImageUse;
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct Behind;

impl FramePass for Behind {
    fn name(&self) -> &'static str {
        PassTimings::BEHIND
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        // The targets of a TRANSMISSION variant have the behind image (TargetKey::of).
        frame.variant.transmission && super::forward::draws(frame.variant)
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let behind = frame.targets.behind.as_ref().expect("runs only with it");
        PassIo::new(self.name())
            .touches((&frame.targets.hdr).into(), ImageUse::TransferSource)
            .touches(behind.into(), ImageUse::MipChainWrite)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let behind = frame.targets.behind.as_ref().expect("runs only with it");
        let region = crate::commands::level_zero_copy(
            vk::ImageAspectFlags::COLOR,
            frame.targets.hdr.extent(),
        );
        // SAFETY: recording state; both images are in the layouts `io` declared.
        unsafe {
            frame.device.raw().cmd_copy_image(
                cmd,
                frame.targets.hdr.raw(),
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
