use ash::vk;

/// Everything the Vulkan backend can fail with. Messages are one line and, where the
/// cure is an install, say what to install.
#[derive(Debug, thiserror::Error)]
pub enum VkError {
    #[error("no Vulkan loader could be loaded ({0}); install the loader and a driver, e.g. `apt-get install libvulkan1 mesa-vulkan-drivers`")]
    LoaderMissing(String),
    #[error("no Vulkan device found; install a driver, e.g. `apt-get install mesa-vulkan-drivers` for lavapipe (CPU Vulkan)")]
    NoDevice,
    #[error("no Vulkan device offers what Combustion needs (Vulkan 1.3 with dynamicRendering and synchronization2, and a queue family with graphics and compute): {0}")]
    NoSuitableDevice(String),
    #[error("no Vulkan device matches `{selector}`; devices: {available}")]
    DeviceNotFound { selector: String, available: String },
    #[error("device selector `{0}` is empty; give a device index or part of its name")]
    BadDeviceSelector(String),
    #[error("validation was requested but VK_LAYER_KHRONOS_validation is not installed; install it, e.g. `apt-get install vulkan-validationlayers`")]
    ValidationLayerMissing,
    #[error("{what} failed: {result}")]
    Vk {
        what: &'static str,
        result: vk::Result,
    },
    #[error("allocating memory for {name} failed: {source}")]
    Allocation {
        name: String,
        source: gpu_allocator::AllocationError,
    },
    #[error("{0}")]
    Shader(String),
    #[error("{0}")]
    Unsupported(String),
    #[error("the host's Vulkan device cannot run Combustion: {0}")]
    HostDeviceUnsuitable(String),
    #[error("{0} is not called on a device Combustion does not own")]
    NotOwned(&'static str),
    #[error(
        "the Vulkan device was lost ({what}); the renderer and its resources must be recreated"
    )]
    DeviceLost { what: &'static str },
    #[error("out of {kind} memory ({what})")]
    OutOfMemory { what: String, kind: &'static str },
    #[error("{what}: {why}")]
    InvalidArgument { what: &'static str, why: String },
}

/// Attaches the name of the failed call to a raw `vk::Result`.
pub trait VkResultExt<T> {
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
