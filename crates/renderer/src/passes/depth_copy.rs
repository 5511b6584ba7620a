//! The scene's depth copied into the host's depth image (frames given one), so the
//! host can draw its own geometry depth-tested against the scene.

use combustion_vk::vk;

use super::{FrameContext, FramePass};
use crate::graph::ImageUse;
use crate::pass_io::PassIo;
use crate::results::PassTimings;

pub(crate) struct DepthCopy;

impl FramePass for DepthCopy {
    fn name(&self) -> &'static str {
        PassTimings::DEPTH_COPY
    }

    fn runs(&self, frame: &FrameContext<'_>) -> bool {
        frame.host_depth.is_some()
    }

    fn io(&self, frame: &FrameContext<'_>) -> PassIo {
        let host_depth = frame.host_depth.expect("runs only with a depth image");
        PassIo::new(self.name())
            .touches((frame.gbuffer.depth).into(), ImageUse::TransferSource)
            .touches(host_depth, ImageUse::TransferDestination)
    }

    fn record(&self, frame: &FrameContext<'_>, cmd: vk::CommandBuffer) {
        let host_depth = frame.host_depth.expect("runs only with a depth image");
        let region = crate::commands::level_zero_copy(vk::ImageAspectFlags::DEPTH, frame.extent());
        // SAFETY: recording state; both images are in the layouts `io` declared.
        unsafe {
            frame.device.raw().cmd_copy_image(
                cmd,
                frame.gbuffer.depth.raw(),
                ImageUse::TransferSource.state().layout,
                host_depth.raw,
                ImageUse::TransferDestination.state().layout,
                &[region],
            )
        };
    }
}
