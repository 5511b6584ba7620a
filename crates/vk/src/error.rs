use ash::vk;

/// Everything the Vulkan backend can fail with. Messages are one line and, where the
/// cure is an install, say what to install.
///
/// A host reacts to [`VkError::DeviceLost`] by recreating the device and everything made
/// on it, and to [`VkError::OutOfMemory`] by freeing memory or lowering resolution; most
/// other variants describe a setup that cannot work and are reported to the user as they
/// are. [`VkError::InvalidArgument`] is a caller's mistake.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    /// The Vulkan loader (`libvulkan.so.1`) could not be loaded; the text is the
    /// loader library's own error.
    #[error("no Vulkan loader could be loaded ({0}); install the loader and a driver, e.g. `apt-get install libvulkan1 mesa-vulkan-drivers`")]
    LoaderMissing(String),
    /// The loader found no physical device (no driver is installed, or none supports
    /// Vulkan 1.3).
    #[error("no Vulkan device found; install a driver, e.g. `apt-get install mesa-vulkan-drivers` for lavapipe (CPU Vulkan)")]
    NoDevice,
    /// Devices exist but none meets [`crate::Requirements`]; the text lists each
    /// device and what it lacks.
    #[error("no Vulkan device offers what Combustion needs (Vulkan 1.3 with dynamicRendering, synchronization2 and shaderDemoteToHelperInvocation, and a queue family with graphics and compute): {0}")]
    NoSuitableDevice(String),
    /// A [`crate::DeviceSelector`] (index or name) matched no device.
    #[error("no Vulkan device matches `{selector}`; devices: {available}")]
    DeviceNotFound {
        /// The selector, as the user gave it.
        selector: String,
        /// The devices the loader reports, as `index: name` pairs.
        available: String,
    },
    /// A device selector given as text (e.g. `COMBUSTION_DEVICE`) was empty.
    #[error("device selector `{0}` is empty; give a device index or part of its name")]
    BadDeviceSelector(String),
    /// `COMBUSTION_DEVICE` is set to bytes that are not UTF-8 (no device name is).
    #[error("COMBUSTION_DEVICE is not valid UTF-8 text; give a device index or part of its name")]
    DeviceSelectorNotText,
    /// [`crate::DeviceDesc::validation`] was set but `VK_LAYER_KHRONOS_validation` is
    /// not installed.
    #[error("validation was requested but VK_LAYER_KHRONOS_validation is not installed; install it, e.g. `apt-get install vulkan-validationlayers`")]
    ValidationLayerMissing,
    /// A Vulkan call failed with a result that has no variant of its own (device loss
    /// and out-of-memory do: see [`VkError::from_result`]).
    #[error("{what} failed: {result}")]
    Vk {
        /// The Vulkan function that failed, e.g. `vkCreateImage`.
        what: &'static str,
        /// What it returned.
        result: vk::Result,
    },
    /// gpu-allocator failed for a reason other than running out of memory.
    #[error("allocating memory for {name} failed: {source}")]
    Allocation {
        /// The name of the buffer or image the memory was for.
        name: String,
        /// The allocator's error.
        source: gpu_allocator::AllocationError,
    },
    /// A shader could not be compiled: missing source or include, or glslang's
    /// `file:line: message` diagnostics joined on one line.
    #[error("{0}")]
    Shader(String),
    /// The device, window system or format cannot do what was asked (no timestamps, no
    /// presentation to this window, an image outside the device's limits, a buffer that
    /// is not host-visible, ...); the text says what and why.
    #[error("{0}")]
    Unsupported(String),
    /// [`crate::Device::from_host`]: the host's device lacks what Combustion needs; the
    /// text lists everything missing, separated by `; `.
    #[error("the host's Vulkan device cannot run Combustion: {0}")]
    HostDeviceUnsuitable(String),
    /// An operation only the owner of the device may do (such as `vkDeviceWaitIdle`)
    /// was asked of a host's device; the text names the operation.
    #[error("{0} is not called on a device Combustion does not own")]
    NotOwned(&'static str),
    /// The device was lost (`VK_ERROR_DEVICE_LOST`): every object made on it must be
    /// dropped and the device created again.
    #[error(
        "the Vulkan device was lost ({what}); the renderer and its resources must be recreated"
    )]
    DeviceLost {
        /// The Vulkan function that reported the loss.
        what: &'static str,
    },
    /// Host or device memory ran out, in a Vulkan call or in the allocator.
    #[error("out of {kind} memory ({what})")]
    OutOfMemory {
        /// What was being done: a Vulkan function's name, or `allocating NAME`.
        what: String,
        /// `"host"` or `"device"`.
        kind: &'static str,
    },
    /// A function was called with an argument it cannot accept (a mistake of the
    /// caller, not of the device), e.g. a timestamp pool of no timestamps.
    #[error("{what}: {why}")]
    InvalidArgument {
        /// The function refusing the argument, e.g. `TimestampQueries::new`.
        what: &'static str,
        /// What is wrong with it.
        why: String,
    },
}

/// Attaches the name of the failed call to a raw `vk::Result`.
pub trait VkResultExt<T> {
    /// The result, its error turned into a [`VkError`] naming `what` (the Vulkan
    /// function called) through [`VkError::from_result`].
    ///
    /// # Errors
    /// [`VkError::DeviceLost`], [`VkError::OutOfMemory`] or [`VkError::Vk`], by the
    /// `vk::Result`.
    fn what(self, what: &'static str) -> Result<T, VkError>;
}

impl<T> VkResultExt<T> for Result<T, vk::Result> {
    fn what(self, what: &'static str) -> Result<T, VkError> {
        self.map_err(|result| VkError::from_result(what, result))
    }
}

impl VkError {
    /// A failed call's result, with device loss and out-of-memory as their own variants
    /// (a host reacts to those differently from other failures).
    pub fn from_result(what: &'static str, result: vk::Result) -> VkError {
        match result {
            vk::Result::ERROR_DEVICE_LOST => VkError::DeviceLost { what },
            vk::Result::ERROR_OUT_OF_DEVICE_MEMORY => VkError::OutOfMemory {
                what: what.to_owned(),
                kind: "device",
            },
            vk::Result::ERROR_OUT_OF_HOST_MEMORY => VkError::OutOfMemory {
                what: what.to_owned(),
                kind: "host",
            },
            result => VkError::Vk { what, result },
        }
    }

    /// An allocator failure for `name`; running out of memory is
    /// [`VkError::OutOfMemory`], like the same failure of a Vulkan call.
    pub fn allocation(name: &str, source: gpu_allocator::AllocationError) -> VkError {
        match source {
            gpu_allocator::AllocationError::OutOfMemory => VkError::OutOfMemory {
                what: format!("allocating {name}"),
                kind: "device",
            },
            source => VkError::Allocation {
                name: name.to_owned(),
                source,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_unsuitable_device_message_names_the_queue_combustion_needs() {
        let message =
            VkError::NoSuitableDevice("lavapipe lacks synchronization2".into()).to_string();
        assert!(
            message.contains("a queue family with graphics and compute"),
            "{message}"
        );
    }
}
