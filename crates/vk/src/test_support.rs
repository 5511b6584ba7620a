//! What the crate's unit tests share: a lavapipe device with validation, and the check
//! that it reported nothing.

use std::sync::Arc;

use crate::device::{Device, DeviceDesc, DeviceSelector, ValidationLog};

/// Lavapipe with validation, synchronization validation included.
pub(crate) fn device() -> Arc<Device> {
    Device::new(&DeviceDesc {
        selector: DeviceSelector::NameContains("llvmpipe".into()),
        validation: true,
        synchronization_validation: true,
        ..DeviceDesc::default()
    })
    .expect("lavapipe with validation")
}

/// Drops `device` (so its leak report reaches `log`) and fails on any validation message.
pub(crate) fn finish(device: Arc<Device>, log: ValidationLog) {
    drop(device);
    let messages = log.messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}
