use std::ffi::{c_void, CStr};
use std::fmt;
use std::mem::ManuallyDrop;
use std::str::FromStr;
use std::sync::{Arc, Mutex, MutexGuard};

use ash::{ext, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use crate::error::{VkError, VkResultExt};
use crate::probe::{DeviceCounters, DeviceProbe, InjectedFault};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Which physical device to use.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// Prefer a discrete GPU, then integrated, virtual, and finally a CPU device
    /// (lavapipe) — so lavapipe is picked when it is the only device.
    #[default]
    Auto,
    /// The n-th device in the order the loader enumerates them (see `combustion devices`).
    Index(usize),
    /// The first device whose name contains this text (case-insensitive), e.g. `llvmpipe`.
    NameContains(String),
}

impl DeviceSelector {
    /// Environment variable read by [`DeviceSelector::from_env`].
    pub const ENV_VAR: &'static str = "COMBUSTION_DEVICE";

    /// The selector named by `COMBUSTION_DEVICE`, or `Auto` when it is unset.
    ///
    /// # Errors
    /// [`VkError::BadDeviceSelector`] when the variable is set but empty;
    /// [`VkError::DeviceSelectorNotText`] when it is not UTF-8 (not ignored: the device
    /// asked for would silently not be the one used).
    pub fn from_env() -> Result<Self, VkError> {
        match std::env::var(Self::ENV_VAR) {
            Ok(text) => text.parse(),
            Err(std::env::VarError::NotPresent) => Ok(Self::Auto),
            Err(std::env::VarError::NotUnicode(_)) => Err(VkError::DeviceSelectorNotText),
        }
    }
}

/// `auto` (any case) is [`DeviceSelector::Auto`], a number an index, anything else part
/// of a name; surrounding whitespace is ignored, and empty text is
/// [`VkError::BadDeviceSelector`].
impl FromStr for DeviceSelector {
    type Err = VkError;
    fn from_str(text: &str) -> Result<Self, VkError> {
        let text = text.trim();
        if text.is_empty() {
            return Err(VkError::BadDeviceSelector(text.to_owned()));
        }
        if text.eq_ignore_ascii_case("auto") {
            return Ok(Self::Auto);
        }
        Ok(match text.parse::<usize>() {
            Ok(index) => Self::Index(index),
            Err(_) => Self::NameContains(text.to_owned()),
        })
    }
}

impl fmt::Display for DeviceSelector {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Auto => write!(f, "auto"),
            Self::Index(i) => write!(f, "{i}"),
            Self::NameContains(name) => write!(f, "{name}"),
        }
    }
}

/// How to create a [`Device`].
#[derive(Clone, Debug, Default)]
pub struct DeviceDesc {
    /// Which physical device to use.
    pub selector: DeviceSelector,
    /// Enable VK_LAYER_KHRONOS_validation; its warnings and errors go to the `log`
    /// facade and to the device's [`ValidationLog`]. An error if the layer is missing.
    pub validation: bool,
    /// With `validation`: also the layer's synchronization validation (hazards between
    /// commands, missing barriers, wrong layouts), reported like every other message.
    pub synchronization_validation: bool,
    /// Extra instance extensions, e.g. a window system's surface extensions
    /// ([`crate::Surface::instance_extensions`]). Empty for headless rendering.
    pub instance_extensions: Vec<&'static CStr>,
    /// Enable `VK_KHR_swapchain` on the device (to present to a window); off for
    /// headless rendering. An error if the chosen device lacks it.
    pub swapchain: bool,
    /// Whether to enable ray queries where the device has them
    /// ([`RayQueries::WhenAvailable`], the default) or not ([`RayQueries::Off`]: the
    /// raster paths only, as on a device without them).
    pub ray_queries: RayQueries,
    /// What the process's allocator does with the memory a CPU device frees at its
    /// heap's top ([`HeapTrim::KeptOnCpuDevice`], the default, or the system's
    /// behaviour). Only CPU devices and glibc's allocator are concerned.
    pub heap_trim: HeapTrim,
}

/// Whether memory freed at the top of the process's heap is given back to the system
/// when the device is a CPU (lavapipe) ([`DeviceDesc::heap_trim`]).
///
/// A CPU device allocates each frame's binned triangles in the process's heap and frees
/// them when the frame is drawn. glibc gives freed memory at a heap's top back to the
/// system beyond a threshold that it raises by itself only after a large enough mapped
/// block was freed, so depending on what the process did before, each frame's tens of
/// megabytes may be faulted in and zeroed anew: builtin:grid-7x7 at 1280×720 took
/// 175,000–207,000 page faults in 30 frames and a G-buffer pass of 36–39 ms instead of
/// 29,900 and 26–29 ms (docs/performance.md). Kept, the thresholds are
/// [`KEPT_HEAP_TRIM_THRESHOLD`] and [`KEPT_HEAP_MMAP_THRESHOLD`] from the device's
/// creation on — a process-wide setting of the allocator, which a host that tunes its
/// allocator itself turns off with [`HeapTrim::SystemDefault`]. A process whose
/// environment sets either threshold (`MALLOC_TRIM_THRESHOLD_`, `MALLOC_MMAP_THRESHOLD_`
/// or `GLIBC_TUNABLES`' `glibc.malloc.trim_threshold`, `glibc.malloc.mmap_threshold`)
/// keeps its own. Devices made by [`Device::new`] only: a host's own device
/// ([`HostDevice`]) leaves the allocator to the host.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum HeapTrim {
    /// On a CPU device, glibc's trim threshold is set to [`KEPT_HEAP_TRIM_THRESHOLD`] and
    /// its mapping threshold to [`KEPT_HEAP_MMAP_THRESHOLD`] (`mallopt`): setting one
    /// stops glibc moving the other by itself, so both are set, or blocks of 128 KiB and
    /// more would be mapped and unmapped at each use.
    #[default]
    KeptOnCpuDevice,
    /// The allocator is left as the process has it.
    SystemDefault,
}

/// The bytes freed at a heap's top that glibc keeps for reuse on a CPU device
/// ([`HeapTrim::KeptOnCpuDevice`]): above the ~23 MB a frame of builtin:grid-7x7 churns
/// at 1280×720, with room for larger scenes.
pub const KEPT_HEAP_TRIM_THRESHOLD: usize = 256 << 20;

/// The smallest block glibc maps on its own rather than takes from the heap, on a CPU
/// device ([`HeapTrim::KeptOnCpuDevice`]): glibc's largest (32 MiB on 64-bit systems),
/// so that a frame's blocks below it are reused from the heap, not mapped anew.
pub const KEPT_HEAP_MMAP_THRESHOLD: usize = 32 << 20;

/// Applies `trim` for a device of `device_type`: see [`HeapTrim`].
fn apply_heap_trim(trim: HeapTrim, device_type: vk::PhysicalDeviceType) {
    if trim != HeapTrim::KeptOnCpuDevice || device_type != vk::PhysicalDeviceType::CPU {
        return;
    }
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        let tunables = std::env::var("GLIBC_TUNABLES").unwrap_or_default();
        let set_by_environment = |variable: &str, tunable: &str| {
            std::env::var_os(variable).is_some() || tunables.contains(tunable)
        };
        if set_by_environment("MALLOC_TRIM_THRESHOLD_", "glibc.malloc.trim_threshold")
            || set_by_environment("MALLOC_MMAP_THRESHOLD_", "glibc.malloc.mmap_threshold")
        {
            return;
        }
        for (parameter, bytes) in [
            (libc::M_MMAP_THRESHOLD, KEPT_HEAP_MMAP_THRESHOLD),
            (libc::M_TRIM_THRESHOLD, KEPT_HEAP_TRIM_THRESHOLD),
        ] {
            let value = std::ffi::c_int::try_from(bytes).unwrap_or(std::ffi::c_int::MAX);
            // SAFETY: mallopt changes the allocator's parameters only; glibc serialises
            // it with allocations. A refusal (0) leaves the system's behaviour, which is
            // correct, only slower.
            let _ = unsafe { libc::mallopt(parameter, value) };
        }
    }
}

/// Whether a device is created with ray queries ([`DeviceDesc::ray_queries`]): the
/// extensions VK_KHR_acceleration_structure, VK_KHR_ray_query and
/// VK_KHR_deferred_host_operations and the features accelerationStructure, rayQuery and
/// bufferDeviceAddress ([`Device::ray_queries`] says whether it was).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RayQueries {
    /// Enabled when the device has every extension and feature they need.
    #[default]
    WhenAvailable,
    /// Never enabled.
    Off,
}

/// The device extensions ray queries need.
const RAY_QUERY_EXTENSIONS: [&CStr; 3] = [
    ash::khr::acceleration_structure::NAME,
    ash::khr::ray_query::NAME,
    ash::khr::deferred_host_operations::NAME,
];

/// Whether `physical_device` has every extension and feature ray queries need.
fn has_ray_queries(instance: &ash::Instance, physical_device: vk::PhysicalDevice) -> bool {
    // SAFETY: valid physical device.
    let Ok(available) =
        (unsafe { instance.enumerate_device_extension_properties(physical_device) })
    else {
        return false;
    };
    let extensions = RAY_QUERY_EXTENSIONS.iter().all(|name| {
        available
            .iter()
            .any(|e| e.extension_name_as_c_str() == Ok(*name))
    });
    if !extensions {
        return false;
    }
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut acceleration = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default();
    let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default();
    let mut features2 = vk::PhysicalDeviceFeatures2::default()
        .push_next(&mut f12)
        .push_next(&mut acceleration)
        .push_next(&mut ray_query);
    // SAFETY: valid physical device; the chain's structures outlive the call.
    unsafe { instance.get_physical_device_features2(physical_device, &mut features2) };
    f12.buffer_device_address == vk::TRUE
        && acceleration.acceleration_structure == vk::TRUE
        && ray_query.ray_query == vk::TRUE
}

/// What the loader reports of one physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// The position in the loader's enumeration ([`DeviceSelector::Index`]); 0 for a
    /// host's device.
    pub index: usize,
    /// The device name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Discrete, integrated, virtual or CPU.
    pub device_type: vk::PhysicalDeviceType,
    /// The Vulkan version the device supports: (major, minor, patch).
    pub api_version: (u32, u32, u32),
    /// The driver's name and version information; empty for a host's device.
    pub driver: String,
    /// Why the device can't be used by Combustion, or `None` when it can.
    pub unsuitable_because: Option<String>,
    /// The largest side of a 2D image the device makes (`maxImageDimension2D`).
    pub max_image_dimension_2d: u32,
}

impl DeviceInfo {
    /// The device type in words: `discrete GPU`, `integrated GPU`, `virtual GPU`, `CPU`
    /// or `other device`.
    pub fn kind(&self) -> &'static str {
        match self.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other device",
        }
    }
}

/// Validation-layer warnings and errors seen by a device's messenger. Clone it before the
/// device is dropped to read the leak report issued at device destruction.
#[derive(Clone, Default)]
pub struct ValidationLog(Arc<Mutex<Vec<String>>>);

impl ValidationLog {
    fn lock(&self) -> MutexGuard<'_, Vec<String>> {
        self.0
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }
    /// All warning and error messages so far.
    pub fn messages(&self) -> Vec<String> {
        self.lock().clone()
    }
    /// Whether no warning or error was reported (what tests assert after dropping the
    /// device).
    pub fn is_empty(&self) -> bool {
        self.lock().is_empty()
    }
}

unsafe extern "system" fn validation_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let message = if data.is_null() || (*data).p_message.is_null() {
        "(no message)".to_owned()
    } else {
        CStr::from_ptr((*data).p_message)
            .to_string_lossy()
            .into_owned()
    };
    if severity.intersects(
        vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
            | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
    ) {
        // The message's kinds in words (not the flags' Rust form): "validation", …
        let kinds = [
            (vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION, "validation"),
            (
                vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                "performance",
            ),
            (vk::DebugUtilsMessageTypeFlagsEXT::GENERAL, "general"),
        ]
        .iter()
        .filter(|(flag, _)| kind.contains(*flag))
        .map(|(_, name)| *name)
        .collect::<Vec<_>>()
        .join(" and ");
        if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            log::error!(target: "vulkan", "Vulkan {kinds} message: {message}");
        } else {
            log::warn!(target: "vulkan", "Vulkan {kinds} message: {message}");
        }
        if !user.is_null() {
            let log = &*(user as *const Mutex<Vec<String>>);
            log.lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner())
                .push(format!("{severity:?} {kind:?}: {message}"));
        }
    } else {
        log::debug!(target: "vulkan", "{kind:?}: {message}");
    }
    vk::FALSE
}

/// A queue and the lock that serialises every call on it (`vkQueueSubmit2`,
/// `vkQueuePresentKHR`). A host that shares its queue with Combustion gives the same
/// `Arc` to [`HostDevice::queue`] and takes the lock around its own queue calls.
pub type QueueLock = Arc<Mutex<vk::Queue>>;

/// An allocator shared between a host and Combustion (gpu-allocator's, behind the
/// host's mutex).
pub type SharedAllocator = Arc<Mutex<Allocator>>;

/// What Combustion needs of a Vulkan device: the API version, the features, and a queue
/// family with both graphics and compute (timestamps are optional: pass timings are then
/// unavailable).
/// A host that creates its own device enables these; [`Device::from_host`] checks them.
pub struct Requirements;

impl Requirements {
    /// The Vulkan API version (instance and device).
    pub const API_VERSION: u32 = vk::API_VERSION_1_3;
    /// Device extensions, as names: none (Vulkan 1.3 core covers what Combustion uses).
    pub const DEVICE_EXTENSIONS: &'static [&'static CStr] = &[];
    /// Vulkan 1.3 features, by name.
    /// shaderDemoteToHelperInvocation (mandatory in Vulkan 1.3) is what a `discard` compiles
    /// to for SPIR-V 1.6: the cut-out pipelines' alpha test.
    pub const FEATURES_13: &'static [&'static str] = &[
        "dynamicRendering",
        "synchronization2",
        "shaderDemoteToHelperInvocation",
    ];
    /// What the queue family Combustion submits to must support: graphics (the G-buffer,
    /// lighting and output passes) and compute (light culling), on the same queue.
    pub const QUEUE_FLAGS: vk::QueueFlags = vk::QueueFlags::from_raw(
        vk::QueueFlags::GRAPHICS.as_raw() | vk::QueueFlags::COMPUTE.as_raw(),
    );

    /// The Vulkan 1.3 features to chain into `VkDeviceCreateInfo`.
    pub fn features_13() -> vk::PhysicalDeviceVulkan13Features<'static> {
        vk::PhysicalDeviceVulkan13Features::default()
            .dynamic_rendering(true)
            .synchronization2(true)
            .shader_demote_to_helper_invocation(true)
    }
}

/// What a host enabled when it created its device, read from the very create info it
/// created the device with ([`EnabledFeatures::from_create_info`]): Vulkan cannot be
/// asked which features a device was created with, so the host hands over what it
/// passed to `vkCreateDevice` rather than a statement of it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EnabledFeatures {
    /// The `apiVersion` of the host's `VkApplicationInfo`.
    api_version: u32,
    dynamic_rendering: bool,
    synchronization2: bool,
    shader_demote_to_helper_invocation: bool,
    /// bufferDeviceAddress, accelerationStructure and rayQuery (what ray queries need
    /// besides their extensions).
    buffer_device_address: bool,
    acceleration_structure: bool,
    ray_query: bool,
    /// Device extensions the host enabled.
    device_extensions: Vec<String>,
}

impl EnabledFeatures {
    /// What `info` enables: its extensions, and dynamicRendering and synchronization2
    /// wherever its `pNext` chain enables them (`VkPhysicalDeviceVulkan13Features`, the
    /// two features' own structures, or `VkPhysicalDeviceFeatures2` ahead of them);
    /// `instance_api_version` is the `apiVersion` of the instance's
    /// `VkApplicationInfo`.
    ///
    /// # Safety
    /// `info` is the create info the device was created with, still valid as
    /// `vkCreateDevice` required it: its `pNext` chain and extension names point to live
    /// structures and strings.
    pub unsafe fn from_create_info(
        instance_api_version: u32,
        info: &vk::DeviceCreateInfo<'_>,
    ) -> EnabledFeatures {
        let mut enabled = EnabledFeatures {
            api_version: instance_api_version,
            ..EnabledFeatures::default()
        };
        if !info.pp_enabled_extension_names.is_null() {
            for i in 0..info.enabled_extension_count as usize {
                // SAFETY: the caller's: `enabled_extension_count` valid C strings.
                let name = unsafe { CStr::from_ptr(*info.pp_enabled_extension_names.add(i)) };
                enabled
                    .device_extensions
                    .push(name.to_string_lossy().into_owned());
            }
        }
        let mut next = info.p_next as *const vk::BaseInStructure<'_>;
        while !next.is_null() {
            // SAFETY: the caller's: every element of the chain is a valid structure
            // starting with sType and pNext, of the type its sType names.
            let base = unsafe { &*next };
            match base.s_type {
                vk::StructureType::PHYSICAL_DEVICE_VULKAN_1_3_FEATURES => {
                    let f = unsafe { &*(next as *const vk::PhysicalDeviceVulkan13Features<'_>) };
                    enabled.dynamic_rendering |= f.dynamic_rendering == vk::TRUE;
                    enabled.synchronization2 |= f.synchronization2 == vk::TRUE;
                    enabled.shader_demote_to_helper_invocation |=
                        f.shader_demote_to_helper_invocation == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_SHADER_DEMOTE_TO_HELPER_INVOCATION_FEATURES => {
                    let f = unsafe {
                        &*(next as *const vk::PhysicalDeviceShaderDemoteToHelperInvocationFeatures<
                            '_,
                        >)
                    };
                    enabled.shader_demote_to_helper_invocation |=
                        f.shader_demote_to_helper_invocation == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES => {
                    let f = unsafe {
                        &*(next as *const vk::PhysicalDeviceDynamicRenderingFeatures<'_>)
                    };
                    enabled.dynamic_rendering |= f.dynamic_rendering == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES => {
                    let f = unsafe {
                        &*(next as *const vk::PhysicalDeviceSynchronization2Features<'_>)
                    };
                    enabled.synchronization2 |= f.synchronization2 == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_VULKAN_1_2_FEATURES => {
                    let f = unsafe { &*(next as *const vk::PhysicalDeviceVulkan12Features<'_>) };
                    enabled.buffer_device_address |= f.buffer_device_address == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES => {
                    let f = unsafe {
                        &*(next as *const vk::PhysicalDeviceBufferDeviceAddressFeatures<'_>)
                    };
                    enabled.buffer_device_address |= f.buffer_device_address == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR => {
                    let f = unsafe {
                        &*(next as *const vk::PhysicalDeviceAccelerationStructureFeaturesKHR<'_>)
                    };
                    enabled.acceleration_structure |= f.acceleration_structure == vk::TRUE;
                }
                vk::StructureType::PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR => {
                    let f = unsafe { &*(next as *const vk::PhysicalDeviceRayQueryFeaturesKHR<'_>) };
                    enabled.ray_query |= f.ray_query == vk::TRUE;
                }
                _ => {}
            }
            next = base.p_next;
        }
        enabled
    }

    /// The instance's `apiVersion` (encoded as by `vk::make_api_version`).
    pub fn api_version(&self) -> u32 {
        self.api_version
    }

    /// Whether the device was created with everything ray queries need: the extensions
    /// VK_KHR_acceleration_structure, VK_KHR_ray_query and VK_KHR_deferred_host_operations
    /// and the features accelerationStructure, rayQuery and bufferDeviceAddress.
    pub fn ray_queries(&self) -> bool {
        self.buffer_device_address
            && self.acceleration_structure
            && self.ray_query
            && RAY_QUERY_EXTENSIONS.iter().all(|name| {
                let name = name.to_string_lossy();
                self.device_extensions.iter().any(|e| *e == name)
            })
    }

    /// Whether the device was created with dynamicRendering.
    pub fn dynamic_rendering(&self) -> bool {
        self.dynamic_rendering
    }

    /// Whether the device was created with synchronization2.
    pub fn synchronization2(&self) -> bool {
        self.synchronization2
    }

    /// Whether the device was created with shaderDemoteToHelperInvocation.
    pub fn shader_demote_to_helper_invocation(&self) -> bool {
        self.shader_demote_to_helper_invocation
    }

    /// The device extensions the device was created with.
    pub fn device_extensions(&self) -> &[String] {
        &self.device_extensions
    }
}

/// A host's own Vulkan objects, for [`Device::from_host`]. Combustion never destroys
/// them and never waits for the device to be idle; the host keeps them alive until the
/// last Combustion object is dropped, and drops those only after the GPU has finished
/// the work Combustion recorded (see docs/integration.md).
pub struct HostDevice {
    /// The host's loaded Vulkan entry points.
    pub entry: ash::Entry,
    /// The host's instance, created with [`Requirements::API_VERSION`] or later.
    pub instance: ash::Instance,
    /// The physical device the host's device was created on.
    pub physical_device: vk::PhysicalDevice,
    /// The host's logical device.
    pub device: ash::Device,
    /// The queue family of the queue Combustion submits to (its own convenience frames
    /// and uploads only; frames recorded into the host's command buffers are submitted
    /// by the host). Must support [`Requirements::QUEUE_FLAGS`].
    pub queue_family: u32,
    /// The index of that queue within its family.
    pub queue_index: u32,
    /// The queue and the host's lock for it.
    pub queue: QueueLock,
    /// The host's allocator; `None` makes Combustion create its own on this device.
    pub allocator: Option<SharedAllocator>,
    /// What the host's device was created with ([`EnabledFeatures::from_create_info`]),
    /// checked against [`Requirements`].
    pub enabled: EnabledFeatures,
}

/// The Vulkan context a renderer runs on: instance, physical device, logical device,
/// one queue and the memory allocator — either created by Combustion ([`Device::new`],
/// which then owns and destroys them) or borrowed from a host ([`Device::from_host`]).
/// Ownership decides who destroys and who may wait for the device to be idle; nothing
/// else differs. Shared as `Arc<Device>` by every resource.
pub struct Device {
    entry: ash::Entry,
    instance: ash::Instance,
    messenger: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    validation_log: ValidationLog,
    physical_device: vk::PhysicalDevice,
    info: DeviceInfo,
    limits: vk::PhysicalDeviceLimits,
    device: ash::Device,
    queue_family: u32,
    queue: QueueLock,
    allocator: ManuallyDrop<SharedAllocator>,
    /// Created (and so destroyed) by Combustion; `false` for a host's device.
    owned: bool,
    /// Counts of submissions, waits and allocations, and the faults armed for them.
    probe: DeviceProbe,
    /// VK_KHR_acceleration_structure's functions, on a device created with ray queries.
    acceleration_structure: Option<ash::khr::acceleration_structure::Device>,
}

fn c_chars_to_string(chars: &[std::ffi::c_char]) -> String {
    let bytes: Vec<u8> = chars
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

fn load_entry() -> Result<ash::Entry, VkError> {
    // SAFETY: loading the system Vulkan loader; its symbols are used through ash only.
    unsafe { ash::Entry::load() }.map_err(|e| VkError::LoaderMissing(e.to_string()))
}

fn create_instance(
    entry: &ash::Entry,
    validation: bool,
    synchronization_validation: bool,
    extra_extensions: &[&'static CStr],
    messenger_info: &mut vk::DebugUtilsMessengerCreateInfoEXT<'_>,
) -> Result<ash::Instance, VkError> {
    let app_info = vk::ApplicationInfo::default()
        .application_name(c"combustion")
        .engine_name(c"combustion")
        .api_version(vk::API_VERSION_1_3);
    let layers = [VALIDATION_LAYER.as_ptr()];
    let mut extensions: Vec<*const std::ffi::c_char> =
        extra_extensions.iter().map(|e| e.as_ptr()).collect();
    if !extra_extensions.is_empty() {
        // SAFETY: plain enumeration call.
        let available = unsafe { entry.enumerate_instance_extension_properties(None) }
            .what("vkEnumerateInstanceExtensionProperties")?;
        let missing: Vec<String> = extra_extensions
            .iter()
            .filter(|&&name| {
                !available
                    .iter()
                    .any(|e| e.extension_name_as_c_str() == Ok(name))
            })
            .map(|name| name.to_string_lossy().into_owned())
            .collect();
        if !missing.is_empty() {
            return Err(VkError::Unsupported(format!(
                "the Vulkan loader lacks the instance extension(s) {}",
                missing.join(", ")
            )));
        }
    }
    let mut create_info = vk::InstanceCreateInfo::default().application_info(&app_info);
    if validation {
        // SAFETY: plain enumeration call.
        let available = unsafe { entry.enumerate_instance_layer_properties() }
            .what("vkEnumerateInstanceLayerProperties")?;
        let has_layer = available
            .iter()
            .any(|layer| layer.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        if !has_layer {
            return Err(VkError::ValidationLayerMissing);
        }
        extensions.push(ext::debug_utils::NAME.as_ptr());
        create_info = create_info
            .enabled_layer_names(&layers)
            .push_next(messenger_info);
    }
    let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
    let mut validation_features =
        vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
    if validation && synchronization_validation {
        create_info = create_info.push_next(&mut validation_features);
    }
    if !extensions.is_empty() {
        create_info = create_info.enabled_extension_names(&extensions);
    }
    // SAFETY: create_info and everything it points to outlive the call.
    match unsafe { entry.create_instance(&create_info, None) } {
        Ok(instance) => Ok(instance),
        Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => Err(VkError::NoDevice),
        Err(result) => Err(VkError::Vk {
            what: "vkCreateInstance",
            result,
        }),
    }
}

/// Describes every physical device, in enumeration order, and says which can be used.
fn describe_devices(
    instance: &ash::Instance,
) -> Result<Vec<(vk::PhysicalDevice, DeviceInfo, Option<u32>)>, VkError> {
    // SAFETY: instance is valid for all calls below.
    let physical_devices =
        unsafe { instance.enumerate_physical_devices() }.what("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::new();
    for (index, &pd) in physical_devices.iter().enumerate() {
        let mut driver_props = vk::PhysicalDeviceDriverProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver_props);
        unsafe { instance.get_physical_device_properties2(pd, &mut props2) };
        let props = props2.properties;
        let driver = format!(
            "{} {}",
            c_chars_to_string(&driver_props.driver_name),
            c_chars_to_string(&driver_props.driver_info)
        );
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
        unsafe { instance.get_physical_device_features2(pd, &mut features2) };
        let queue_family = unsafe { instance.get_physical_device_queue_family_properties(pd) }
            .iter()
            .position(|q| missing_queue_capabilities(q.queue_flags).is_none())
            .map(|i| i as u32);
        let v = props.api_version;
        let mut missing = Vec::new();
        if v < vk::API_VERSION_1_3 {
            missing.push("Vulkan 1.3");
        }
        if f13.dynamic_rendering == vk::FALSE {
            missing.push("dynamicRendering");
        }
        if f13.synchronization2 == vk::FALSE {
            missing.push("synchronization2");
        }
        if f13.shader_demote_to_helper_invocation == vk::FALSE {
            missing.push("shaderDemoteToHelperInvocation");
        }
        if queue_family.is_none() {
            missing.push("a queue family with graphics and compute");
        }
        let info = DeviceInfo {
            unsuitable_because: (!missing.is_empty())
                .then(|| format!("lacks {}", missing.join(", "))),
            ..device_info(index, &props, driver.trim().to_owned())
        };
        out.push((pd, info, queue_family));
    }
    Ok(out)
}

/// gpu-allocator's allocator on `device`, with default settings (and memory that buffers
/// with device addresses can use, on devices with ray queries).
fn create_allocator(
    instance: &ash::Instance,
    device: &ash::Device,
    physical_device: vk::PhysicalDevice,
    buffer_device_address: bool,
) -> Result<Allocator, VkError> {
    Allocator::new(&AllocatorCreateDesc {
        instance: instance.clone(),
        device: device.clone(),
        physical_device,
        debug_settings: Default::default(),
        buffer_device_address,
        allocation_sizes: Default::default(),
    })
    .map_err(|source| VkError::allocation("the allocator", source))
}

/// What the loader reports of a physical device, as [`DeviceInfo`] (`unsuitable_because`
/// unset).
fn device_info(index: usize, props: &vk::PhysicalDeviceProperties, driver: String) -> DeviceInfo {
    let v = props.api_version;
    DeviceInfo {
        index,
        name: c_chars_to_string(&props.device_name),
        device_type: props.device_type,
        api_version: (
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v),
        ),
        driver,
        unsuitable_because: None,
        max_image_dimension_2d: props.limits.max_image_dimension2_d,
    }
}

fn type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

impl Device {
    /// Lists the physical devices the Vulkan loader sees (no logical device is created),
    /// each with why Combustion cannot use it, if it cannot.
    ///
    /// # Errors
    /// [`VkError::LoaderMissing`] without a loader, [`VkError::NoDevice`] when no driver
    /// is compatible, or a failed Vulkan call.
    pub fn enumerate() -> Result<Vec<DeviceInfo>, VkError> {
        let entry = load_entry()?;
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default();
        let instance = create_instance(&entry, false, false, &[], &mut messenger_info)?;
        let result = describe_devices(&instance);
        // SAFETY: no object was created from this instance.
        unsafe { instance.destroy_instance(None) };
        Ok(result?.into_iter().map(|(_, info, _)| info).collect())
    }

    /// The physical device `selector` picks, as [`Device::new`] would pick it, without
    /// creating a logical device (an instance is made and destroyed): to check a
    /// selector and the device's limits before any long work.
    ///
    /// # Errors
    /// As [`Device::new`]'s selection: [`VkError::LoaderMissing`], [`VkError::NoDevice`],
    /// [`VkError::DeviceNotFound`], [`VkError::NoSuitableDevice`], or a failed Vulkan
    /// call.
    pub fn preflight(selector: &DeviceSelector) -> Result<DeviceInfo, VkError> {
        let entry = load_entry()?;
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default();
        let instance = create_instance(&entry, false, false, &[], &mut messenger_info)?;
        let result = select_device(&instance, selector);
        // SAFETY: no object was created from this instance.
        unsafe { instance.destroy_instance(None) };
        result.map(|(_, info, _)| info)
    }

    /// Creates the instance (with validation if asked), selects a physical device and
    /// creates the logical device with one queue of a family that supports
    /// [`Requirements::QUEUE_FLAGS`], and the memory allocator. Combustion owns all of
    /// them and destroys them when the last `Arc` is dropped.
    ///
    /// # Errors
    /// [`VkError::LoaderMissing`], [`VkError::NoDevice`],
    /// [`VkError::ValidationLayerMissing`], [`VkError::DeviceNotFound`] (the selector
    /// matched nothing), [`VkError::NoSuitableDevice`] (the device lacks what
    /// [`Requirements`] lists), [`VkError::Unsupported`] (a requested instance extension
    /// or the swapchain extension is missing), or a failed Vulkan call. Whatever was
    /// created before the failure is destroyed.
    pub fn new(desc: &DeviceDesc) -> Result<Arc<Device>, VkError> {
        let entry = load_entry()?;
        let validation_log = ValidationLog::default();
        let log_ptr = Arc::as_ptr(&validation_log.0) as *mut c_void;
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                    | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::INFO,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(validation_callback))
            .user_data(log_ptr);
        let instance = create_instance(
            &entry,
            desc.validation,
            desc.synchronization_validation,
            &desc.instance_extensions,
            &mut messenger_info,
        )?;
        // From here on, a failure must destroy what was created: the guard does it.
        let mut guard = PartialDevice {
            instance: Some(instance),
            messenger: None,
        };
        let instance = guard.instance.as_ref().expect("set above");
        if desc.validation {
            let loader = ext::debug_utils::Instance::new(&entry, instance);
            // SAFETY: messenger_info's user data (the log) outlives the messenger: the
            // Device keeps the Arc until after the messenger is destroyed.
            let messenger = unsafe { loader.create_debug_utils_messenger(&messenger_info, None) }
                .what("vkCreateDebugUtilsMessengerEXT")?;
            guard.messenger = Some((loader, messenger));
        }
        let (physical_device, info, queue_family) = select_device(instance, &desc.selector)?;
        // SAFETY: valid physical device.
        let limits = unsafe { instance.get_physical_device_properties(physical_device) }.limits;

        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut features13 = Requirements::features_13();
        let mut device_extensions: Vec<*const std::ffi::c_char> = Vec::new();
        let mut create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .push_next(&mut features13);
        let ray_queries = desc.ray_queries == RayQueries::WhenAvailable
            && has_ray_queries(instance, physical_device);
        let mut f12 = vk::PhysicalDeviceVulkan12Features::default().buffer_device_address(true);
        let mut acceleration = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        if ray_queries {
            device_extensions.extend(RAY_QUERY_EXTENSIONS.iter().map(|e| e.as_ptr()));
            create_info = create_info
                .push_next(&mut f12)
                .push_next(&mut acceleration)
                .push_next(&mut ray_query);
        }
        if desc.swapchain {
            // SAFETY: valid physical device.
            let available =
                unsafe { instance.enumerate_device_extension_properties(physical_device) }
                    .what("vkEnumerateDeviceExtensionProperties")?;
            if !available
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(ash::khr::swapchain::NAME))
            {
                return Err(VkError::Unsupported(format!(
                    "Vulkan device {} cannot present to windows (no VK_KHR_swapchain)",
                    info.name
                )));
            }
            device_extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        if !device_extensions.is_empty() {
            create_info = create_info.enabled_extension_names(&device_extensions);
        }
        // SAFETY: create_info outlives the call; features were checked in select_device
        // (and ray queries' by has_ray_queries).
        let device = unsafe { instance.create_device(physical_device, &create_info, None) }
            .what("vkCreateDevice")?;
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = match create_allocator(instance, &device, physical_device, ray_queries) {
            Ok(a) => a,
            Err(error) => {
                unsafe { device.destroy_device(None) };
                return Err(error);
            }
        };
        let (instance, messenger) = guard.disarm();
        // Made: the process's allocator is set for its frames (not for a device that
        // failed to be made).
        apply_heap_trim(desc.heap_trim, info.device_type);
        let acceleration_structure =
            ray_queries.then(|| ash::khr::acceleration_structure::Device::new(&instance, &device));
        log::info!(
            "Vulkan device {}: {} ({}, Vulkan {}.{}.{}, {}{})",
            info.index,
            info.name,
            info.kind(),
            info.api_version.0,
            info.api_version.1,
            info.api_version.2,
            info.driver,
            if ray_queries { ", ray queries" } else { "" }
        );
        Ok(Arc::new(Device {
            entry,
            instance,
            messenger,
            validation_log,
            physical_device,
            info,
            limits,
            device,
            queue_family,
            queue: Arc::new(Mutex::new(queue)),
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            owned: true,
            probe: DeviceProbe::default(),
            acceleration_structure,
        }))
    }

    /// A context on a host's own instance, device and queue (and optionally its
    /// allocator). Checks everything Combustion needs and fails with one
    /// [`VkError::HostDeviceUnsuitable`] listing all that is missing. Nothing here is
    /// destroyed by Combustion, and it never waits for this device to be idle.
    ///
    /// The handles in `host` must be valid and stay valid until the returned `Arc` and
    /// every resource made from it have been dropped (see [`HostDevice`]).
    ///
    /// # Errors
    /// [`VkError::HostDeviceUnsuitable`] as above; [`VkError::Allocation`] or
    /// [`VkError::OutOfMemory`] when Combustion's own allocator cannot be created.
    pub fn from_host(host: HostDevice) -> Result<Arc<Device>, VkError> {
        let instance = &host.instance;
        let pd = host.physical_device;
        // SAFETY: the host guarantees valid handles.
        let props = unsafe { instance.get_physical_device_properties(pd) };
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
        unsafe { instance.get_physical_device_features2(pd, &mut features2) };
        let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
        let mut missing = Vec::new();
        let version = |v: u32| format!("{}.{}", vk::api_version_major(v), vk::api_version_minor(v));
        if props.api_version < Requirements::API_VERSION {
            missing.push(format!(
                "the physical device supports Vulkan {}, Combustion needs {}",
                version(props.api_version),
                version(Requirements::API_VERSION)
            ));
        }
        if host.enabled.api_version < Requirements::API_VERSION {
            missing.push(format!(
                "the instance was created for Vulkan {} (apiVersion), Combustion needs {}",
                version(host.enabled.api_version),
                version(Requirements::API_VERSION)
            ));
        }
        for (name, supported, enabled) in [
            (
                "dynamicRendering",
                f13.dynamic_rendering,
                host.enabled.dynamic_rendering,
            ),
            (
                "synchronization2",
                f13.synchronization2,
                host.enabled.synchronization2,
            ),
            (
                "shaderDemoteToHelperInvocation",
                f13.shader_demote_to_helper_invocation,
                host.enabled.shader_demote_to_helper_invocation,
            ),
        ] {
            if supported == vk::FALSE {
                missing.push(format!("the physical device lacks the feature {name}"));
            } else if !enabled {
                missing.push(format!("the feature {name} is not enabled on the device"));
            }
        }
        for extension in Requirements::DEVICE_EXTENSIONS {
            let name = extension.to_string_lossy();
            if !host.enabled.device_extensions.iter().any(|e| *e == name) {
                missing.push(format!("the device extension {name} is not enabled"));
            }
        }
        match families.get(host.queue_family as usize) {
            None => missing.push(format!(
                "queue family {} does not exist ({} families)",
                host.queue_family,
                families.len()
            )),
            Some(family) => {
                if let Some(lacks) = missing_queue_capabilities(family.queue_flags) {
                    missing.push(format!(
                        "queue family {} lacks {lacks} (Combustion needs graphics and compute on one queue: light culling dispatches compute work between its graphics passes)",
                        host.queue_family
                    ));
                }
                if host.queue_index >= family.queue_count {
                    missing.push(format!(
                        "queue index {} is outside family {}'s {} queue(s)",
                        host.queue_index, host.queue_family, family.queue_count
                    ));
                } else {
                    // SAFETY: family and index exist; the device was created with them
                    // if the host's queue is right, which is what this checks.
                    let queue = unsafe {
                        host.device
                            .get_device_queue(host.queue_family, host.queue_index)
                    };
                    let given = *host.queue.lock().unwrap_or_else(|p| p.into_inner());
                    if queue != given {
                        missing.push(format!(
                            "the queue given is not queue {} of family {}",
                            host.queue_index, host.queue_family
                        ));
                    }
                }
            }
        }
        if !missing.is_empty() {
            return Err(VkError::HostDeviceUnsuitable(missing.join("; ")));
        }
        // Ray queries where the host enabled all they need (the raster paths otherwise);
        // their buffers take device addresses, so a shared allocator must allocate them
        // (created with buffer_device_address, as for any device with the feature).
        let ray_queries = host.enabled.ray_queries();
        let allocator = match host.allocator {
            Some(shared) => shared,
            None => Arc::new(Mutex::new(create_allocator(
                &host.instance,
                &host.device,
                pd,
                ray_queries,
            )?)),
        };
        let acceleration_structure = ray_queries
            .then(|| ash::khr::acceleration_structure::Device::new(&host.instance, &host.device));
        let info = device_info(0, &props, String::new());
        log::info!(
            "Combustion on the host's Vulkan device {}{}",
            info.name,
            if ray_queries { ", ray queries" } else { "" }
        );
        Ok(Arc::new(Device {
            entry: host.entry,
            instance: host.instance,
            messenger: None,
            validation_log: ValidationLog::default(),
            physical_device: pd,
            info,
            limits: props.limits,
            device: host.device,
            queue_family: host.queue_family,
            queue: host.queue,
            allocator: ManuallyDrop::new(allocator),
            owned: false,
            probe: DeviceProbe::default(),
            acceleration_structure,
        }))
    }

    /// Whether Combustion created this device (and so destroys it and may wait idle).
    pub fn is_owned(&self) -> bool {
        self.owned
    }

    /// The logical device, for Vulkan calls the crate does not wrap. Objects created
    /// through it are the caller's to destroy, before the `Device` is dropped.
    pub fn raw(&self) -> &ash::Device {
        &self.device
    }
    /// The instance the device was created on.
    pub fn instance(&self) -> &ash::Instance {
        &self.instance
    }
    /// The loaded Vulkan entry points.
    pub fn entry(&self) -> &ash::Entry {
        &self.entry
    }
    /// The physical device the logical device runs on.
    pub fn physical_device(&self) -> vk::PhysicalDevice {
        self.physical_device
    }
    /// Whether the device was created with ray queries ([`RayQueries`]): acceleration
    /// structures, ray queries in shaders, buffer device addresses.
    pub fn ray_queries(&self) -> bool {
        self.acceleration_structure.is_some()
    }
    /// VK_KHR_acceleration_structure's functions, on a device with ray queries.
    pub fn acceleration_structure(&self) -> Option<&ash::khr::acceleration_structure::Device> {
        self.acceleration_structure.as_ref()
    }
    /// The device address of `buffer` (created with SHADER_DEVICE_ADDRESS usage, on a
    /// device with ray queries).
    pub fn buffer_address(&self, buffer: vk::Buffer) -> vk::DeviceAddress {
        // SAFETY: valid buffer with the device-address usage (the caller's).
        unsafe {
            self.device
                .get_buffer_device_address(&vk::BufferDeviceAddressInfo::default().buffer(buffer))
        }
    }
    /// What the loader reports of the physical device.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }
    /// The physical device's limits (image sizes, timestamp period, alignments, ...).
    pub fn limits(&self) -> &vk::PhysicalDeviceLimits {
        &self.limits
    }
    /// The queue family of the queue Combustion submits to; command pools for
    /// Combustion's work are created on it.
    pub fn queue_family(&self) -> u32 {
        self.queue_family
    }
    /// The validation messages seen so far (empty without validation).
    pub fn validation_log(&self) -> ValidationLog {
        self.validation_log.clone()
    }
    /// The device's queue, locked (queue operations must be externally synchronised).
    pub(crate) fn queue(&self) -> MutexGuard<'_, vk::Queue> {
        self.queue.lock().unwrap_or_else(|p| p.into_inner())
    }
    /// The memory allocator, locked. Hold the guard briefly: every buffer and image
    /// creation and drop takes the same lock (a host's, when the allocator is shared).
    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Submits command buffers on the device's queue (`vkQueueSubmit2`), holding the
    /// queue lock for the call; `fence` (or `vk::Fence::null()`) signals when they
    /// complete. The submit infos must be valid: command buffers ended, semaphores and
    /// the fence in the states Vulkan requires.
    ///
    /// # Errors
    /// [`VkError`] when the submission fails; nothing was submitted then, and `fence`
    /// will not be signalled.
    pub fn submit(&self, submits: &[vk::SubmitInfo2<'_>], fence: vk::Fence) -> Result<(), VkError> {
        if let Some(fault) = self.probe.submission() {
            let code = match fault {
                InjectedFault::DeviceLost => vk::Result::ERROR_DEVICE_LOST,
                InjectedFault::OutOfMemory => vk::Result::ERROR_OUT_OF_DEVICE_MEMORY,
            };
            return Err(VkError::from_result("vkQueueSubmit2", code));
        }
        let queue = self.queue.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: the queue is externally synchronised by the mutex.
        unsafe { self.device.queue_submit2(*queue, submits, fence) }.what("vkQueueSubmit2")
    }

    /// Waits up to `timeout_ns` for every one of `fences` (fences of this device's own
    /// submissions): the one way the crate waits for the GPU, so that tests can count
    /// the waits.
    pub(crate) fn wait_fences(
        &self,
        fences: &[vk::Fence],
        timeout_ns: u64,
    ) -> Result<(), vk::Result> {
        self.probe.fences_waited(fences.len());
        // SAFETY: the fences are this device's.
        unsafe { self.device.wait_for_fences(fences, true, timeout_ns) }
    }

    /// Waits until the device is idle (used before tearing resources down). Only on a
    /// device Combustion owns: a host's device fails with [`VkError::NotOwned`], since
    /// only the host may stall its own device.
    ///
    /// # Errors
    /// [`VkError::NotOwned`] on a host's device; [`VkError`] when the wait fails.
    pub fn wait_idle(&self) -> Result<(), VkError> {
        if !self.owned {
            return Err(VkError::NotOwned("vkDeviceWaitIdle"));
        }
        self.probe.idle_wait();
        // SAFETY: plain wait.
        unsafe { self.device.device_wait_idle() }.what("vkDeviceWaitIdle")
    }

    /// Waits until the queue Combustion submits to is idle (`vkQueueWaitIdle`, under the
    /// queue's lock — the host's, on a host's device): every submission on it so far has
    /// completed, the host's own included. Used at teardown, so that nothing a submitted
    /// frame reads is freed under it; on a host's device it waits for that one queue,
    /// never the whole device.
    ///
    /// # Errors
    /// [`VkError`] when the wait fails (a lost device).
    pub fn wait_queue_idle(&self) -> Result<(), VkError> {
        let queue = self.queue.lock().unwrap_or_else(|p| p.into_inner());
        self.probe.queue_wait();
        // SAFETY: the queue is externally synchronised by its lock.
        unsafe { self.device.queue_wait_idle(*queue) }.what("vkQueueWaitIdle")
    }

    /// Allocates memory from the device's allocator (every allocation Combustion makes
    /// goes through here, counted in [`Device::counters`]).
    ///
    /// # Errors
    /// The allocator's error; `OutOfMemory` when [`Device::fail_allocation`] armed it.
    pub fn allocate(
        &self,
        desc: &gpu_allocator::vulkan::AllocationCreateDesc<'_>,
    ) -> Result<gpu_allocator::vulkan::Allocation, gpu_allocator::AllocationError> {
        if self.probe.allocation_fails() {
            return Err(gpu_allocator::AllocationError::OutOfMemory);
        }
        self.allocator().allocate(desc)
    }

    /// What the device was asked to do since it was made: submissions, fence waits,
    /// idle waits and allocations through it (not a host's own calls on the raw device).
    pub fn counters(&self) -> DeviceCounters {
        self.probe.counters()
    }

    /// Arms a fault: the submission after the next `after` ones (0: the next) fails
    /// with `fault` without submitting anything, as a driver's would. For testing how
    /// a renderer or host handles failure; it fires once.
    pub fn fail_submission(&self, after: u64, fault: InjectedFault) {
        self.probe.fail_submission(after, fault);
    }

    /// Arms a fault: the allocation after the next `after` ones (0: the next) fails as
    /// out of device memory. For testing; it fires once.
    pub fn fail_allocation(&self, after: u64) {
        self.probe.fail_allocation(after);
    }

    /// Disarms every fault armed by [`Device::fail_submission`] and
    /// [`Device::fail_allocation`] that has not fired.
    pub fn clear_faults(&self) {
        self.probe.clear_faults();
    }

    /// The maximum 2D image side the device allows, in texels.
    pub fn max_image_dimension_2d(&self) -> u32 {
        self.limits.max_image_dimension2_d
    }
}

fn select_device(
    instance: &ash::Instance,
    selector: &DeviceSelector,
) -> Result<(vk::PhysicalDevice, DeviceInfo, u32), VkError> {
    let devices = describe_devices(instance)?;
    if devices.is_empty() {
        return Err(VkError::NoDevice);
    }
    let listing = || {
        devices
            .iter()
            .map(|(_, i, _)| format!("{}: {}", i.index, i.name))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let chosen = match selector {
        DeviceSelector::Auto => {
            let best = devices
                .iter()
                .filter(|(_, info, _)| info.unsuitable_because.is_none())
                .min_by_key(|(_, info, _)| (type_rank(info.device_type), info.index));
            match best {
                Some(d) => d,
                None => {
                    let why = devices
                        .iter()
                        .map(|(_, i, _)| {
                            format!(
                                "{} {}",
                                i.name,
                                i.unsuitable_because.as_deref().unwrap_or("")
                            )
                        })
                        .collect::<Vec<_>>()
                        .join("; ");
                    return Err(VkError::NoSuitableDevice(why));
                }
            }
        }
        DeviceSelector::Index(index) => {
            devices.get(*index).ok_or_else(|| VkError::DeviceNotFound {
                selector: selector.to_string(),
                available: listing(),
            })?
        }
        DeviceSelector::NameContains(name) => {
            let needle = name.to_lowercase();
            devices
                .iter()
                .find(|(_, info, _)| info.name.to_lowercase().contains(&needle))
                .ok_or_else(|| VkError::DeviceNotFound {
                    selector: selector.to_string(),
                    available: listing(),
                })?
        }
    };
    let (pd, info, queue_family) = chosen;
    if let Some(why) = &info.unsuitable_because {
        return Err(VkError::NoSuitableDevice(format!("{} {why}", info.name)));
    }
    // A suitable device has such a family (describe_devices says why otherwise).
    let queue_family = queue_family.ok_or_else(|| {
        VkError::NoSuitableDevice(format!(
            "{} lacks a queue family with graphics and compute",
            info.name
        ))
    })?;
    Ok((*pd, info.clone(), queue_family))
}

/// What a queue family of `flags` lacks of [`Requirements::QUEUE_FLAGS`], named for a
/// message (`"compute"`, `"graphics"` or `"graphics and compute"`); `None` when it has
/// both.
fn missing_queue_capabilities(flags: vk::QueueFlags) -> Option<&'static str> {
    match (
        flags.contains(vk::QueueFlags::GRAPHICS),
        flags.contains(vk::QueueFlags::COMPUTE),
    ) {
        (true, true) => None,
        (true, false) => Some("compute"),
        (false, true) => Some("graphics"),
        (false, false) => Some("graphics and compute"),
    }
}

/// Destroys a half-built instance if device creation fails part-way.
struct PartialDevice {
    instance: Option<ash::Instance>,
    messenger: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
}

impl PartialDevice {
    #[allow(clippy::type_complexity)]
    fn disarm(
        mut self,
    ) -> (
        ash::Instance,
        Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    ) {
        (
            self.instance.take().expect("disarmed once"),
            self.messenger.take(),
        )
    }
}

impl Drop for PartialDevice {
    fn drop(&mut self) {
        // SAFETY: nothing else was created from these handles.
        unsafe {
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            if let Some(instance) = self.instance.take() {
                instance.destroy_instance(None);
            }
        }
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        if !self.owned {
            // A host's device: release our handle on the allocator (the host's, or the
            // one made for this context) and leave every Vulkan object to the host.
            // SAFETY: not used after this.
            unsafe { ManuallyDrop::drop(&mut self.allocator) };
            return;
        }
        // SAFETY: every resource holds an Arc<Device>, so none is alive here; the
        // allocator is dropped before the device, the messenger after it so that the
        // layer's leak report at vkDestroyDevice reaches the validation log.
        unsafe {
            let _ = self.device.device_wait_idle();
            ManuallyDrop::drop(&mut self.allocator);
            self.device.destroy_device(None);
            if let Some((loader, messenger)) = self.messenger.take() {
                loader.destroy_debug_utils_messenger(messenger, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}

impl fmt::Debug for Device {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Device").field("info", &self.info).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_queue_family_is_told_what_it_lacks() {
        use vk::QueueFlags as Q;
        assert_eq!(missing_queue_capabilities(Requirements::QUEUE_FLAGS), None);
        assert_eq!(
            missing_queue_capabilities(Q::GRAPHICS | Q::COMPUTE | Q::TRANSFER),
            None
        );
        assert_eq!(
            missing_queue_capabilities(Q::GRAPHICS | Q::TRANSFER),
            Some("compute")
        );
        assert_eq!(
            missing_queue_capabilities(Q::COMPUTE | Q::TRANSFER),
            Some("graphics")
        );
        assert_eq!(
            missing_queue_capabilities(Q::TRANSFER),
            Some("graphics and compute")
        );
    }
}
