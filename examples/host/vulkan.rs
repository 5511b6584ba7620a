#![allow(dead_code)] // shared with tests/host.rs, which uses a different part of it
//! The host's own Vulkan: instance (with validation and synchronization validation when
//! asked), device, queue and its lock, and a gpu-allocator allocator shared with
//! Combustion. Nothing here is Combustion's: it is what any engine already has.

use std::ffi::{c_void, CStr};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use combustion::vk::ash::{self, ext, vk};
use combustion::vk::gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use combustion::vk::{EnabledFeatures, HostDevice, Requirements};

/// Validation messages the host's messenger received.
pub type Messages = Arc<Mutex<Vec<String>>>;

pub struct HostVulkan {
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    messenger: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    /// Boxed so its address stays fixed for the messenger's user data.
    messages: Box<Messages>,
    pub physical_device: vk::PhysicalDevice,
    pub device: ash::Device,
    pub queue_family: u32,
    pub queue: Arc<Mutex<vk::Queue>>,
    pub allocator: ManuallyDrop<Arc<Mutex<Allocator>>>,
    /// What the device was created with, read from its create info.
    enabled: EnabledFeatures,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if severity.intersects(
        vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
            | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
    ) && !data.is_null()
        && !user.is_null()
    {
        let text = if (*data).p_message.is_null() {
            "(no message)".to_owned()
        } else {
            CStr::from_ptr((*data).p_message)
                .to_string_lossy()
                .into_owned()
        };
        let messages = &*(user as *const Messages);
        if let Ok(mut list) = messages.lock() {
            list.push(text);
        }
    }
    vk::FALSE
}

impl HostVulkan {
    /// Creates the host's instance and device on the first device whose name contains
    /// `device_name` (any device when empty), enabling what Combustion requires plus the
    /// host's own `instance_extensions` and `device_extensions` (a window's surface and
    /// swapchain extensions, for example).
    pub fn new(
        device_name: &str,
        validation: bool,
        instance_extensions: &[&'static CStr],
        device_extensions: &[&'static CStr],
    ) -> Result<Self, String> {
        Self::create(
            device_name,
            validation,
            instance_extensions,
            device_extensions,
            false,
        )
    }

    /// As [`HostVulkan::new`] with no extensions of the host's own, and ray queries
    /// enabled too (VK_KHR_acceleration_structure, VK_KHR_ray_query,
    /// VK_KHR_deferred_host_operations; accelerationStructure, rayQuery,
    /// bufferDeviceAddress, and the allocator made for device addresses): Combustion then
    /// runs its passes that trace rays on the host's device.
    pub fn with_ray_queries(device_name: &str, validation: bool) -> Result<Self, String> {
        Self::create(device_name, validation, &[], &[], true)
    }

    fn create(
        device_name: &str,
        validation: bool,
        instance_extensions: &[&'static CStr],
        device_extensions: &[&'static CStr],
        ray_queries: bool,
    ) -> Result<Self, String> {
        // SAFETY: loading the system Vulkan loader.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"combustion host example")
            .api_version(Requirements::API_VERSION);
        let layers = [c"VK_LAYER_KHRONOS_validation".as_ptr()];
        let mut extensions: Vec<_> = instance_extensions.iter().map(|e| e.as_ptr()).collect();
        let messages: Box<Messages> = Box::default();
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                    | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_message))
            .user_data(&*messages as *const Messages as *mut c_void);
        let sync = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app);
        if validation {
            extensions.push(ext::debug_utils::NAME.as_ptr());
            info = info
                .enabled_layer_names(&layers)
                .push_next(&mut messenger_info)
                .push_next(&mut features);
        }
        info = info.enabled_extension_names(&extensions);
        // SAFETY: everything `info` points to outlives the call.
        let instance = unsafe { entry.create_instance(&info, None) }
            .map_err(|e| format!("vkCreateInstance: {e}"))?;
        let messenger = if validation {
            let loader = ext::debug_utils::Instance::new(&entry, &instance);
            let m = unsafe { loader.create_debug_utils_messenger(&messenger_info, None) }
                .map_err(|e| format!("vkCreateDebugUtilsMessengerEXT: {e}"))?;
            Some((loader, m))
        } else {
            None
        };
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(|e| format!("vkEnumeratePhysicalDevices: {e}"))?;
        let needle = device_name.to_lowercase();
        let (physical_device, queue_family) = devices
            .iter()
            .find_map(|&pd| {
                let props = unsafe { instance.get_physical_device_properties(pd) };
                let name = props
                    .device_name_as_c_str()
                    .map(|n| n.to_string_lossy().to_lowercase())
                    .unwrap_or_default();
                if !name.contains(&needle) {
                    return None;
                }
                let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
                // Combustion records graphics and compute work (light culling) into
                // the host's command buffers: one family must do both.
                let family = families.iter().position(|f| {
                    f.queue_flags
                        .contains(vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE)
                })?;
                Some((pd, family as u32))
            })
            .ok_or_else(|| format!("no Vulkan device named like `{device_name}`"))?;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        // What Combustion requires, as its `Requirements` state.
        let mut features13 = Requirements::features_13();
        let mut device_extension_names: Vec<_> = Requirements::DEVICE_EXTENSIONS
            .iter()
            .map(|e| e.as_ptr())
            .collect();
        device_extension_names.extend(device_extensions.iter().map(|e| e.as_ptr()));
        let mut features12 =
            vk::PhysicalDeviceVulkan12Features::default().buffer_device_address(true);
        let mut acceleration = vk::PhysicalDeviceAccelerationStructureFeaturesKHR::default()
            .acceleration_structure(true);
        let mut ray_query = vk::PhysicalDeviceRayQueryFeaturesKHR::default().ray_query(true);
        if ray_queries {
            device_extension_names.extend([
                ash::khr::acceleration_structure::NAME.as_ptr(),
                ash::khr::ray_query::NAME.as_ptr(),
                ash::khr::deferred_host_operations::NAME.as_ptr(),
            ]);
        }
        let mut device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&device_extension_names)
            .push_next(&mut features13);
        if ray_queries {
            device_info = device_info
                .push_next(&mut features12)
                .push_next(&mut acceleration)
                .push_next(&mut ray_query);
        }
        let device = unsafe { instance.create_device(physical_device, &device_info, None) }
            .map_err(|e| format!("vkCreateDevice: {e}"))?;
        // SAFETY: the create info the device was just created with, still alive.
        let enabled =
            unsafe { EnabledFeatures::from_create_info(Requirements::API_VERSION, &device_info) };
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: Default::default(),
            buffer_device_address: ray_queries,
            allocation_sizes: Default::default(),
        })
        .map_err(|e| format!("allocator: {e}"))?;
        Ok(Self {
            entry,
            instance,
            messenger,
            messages,
            physical_device,
            device,
            queue_family,
            queue: Arc::new(Mutex::new(queue)),
            allocator: ManuallyDrop::new(Arc::new(Mutex::new(allocator))),
            enabled,
        })
    }

    /// What Combustion's [`combustion::vk::Device::from_host`] takes: the same objects,
    /// the same queue lock, the same allocator.
    pub fn for_combustion(&self) -> HostDevice {
        HostDevice {
            entry: self.entry.clone(),
            instance: self.instance.clone(),
            physical_device: self.physical_device,
            device: self.device.clone(),
            queue_family: self.queue_family,
            queue_index: 0,
            queue: self.queue.clone(),
            allocator: Some(Arc::clone(&self.allocator)),
            enabled: self.enabled.clone(),
        }
    }

    /// The validation messages, also readable after the device is gone (which is when
    /// the layer reports leaks).
    pub fn message_log(&self) -> Messages {
        Arc::clone(&self.messages)
    }

    /// The shared allocator's live allocations, the bytes they take (with alignment
    /// padding, so it depends on placement), and the bytes of device memory it holds.
    pub fn allocator_usage(&self) -> (usize, u64, u64) {
        self.allocator
            .lock()
            .map(|a| {
                let r = a.generate_report();
                (
                    r.allocations.len(),
                    r.total_allocated_bytes,
                    r.total_capacity_bytes,
                )
            })
            .unwrap_or_default()
    }

    /// A command pool with one primary command buffer, and a fence (signalled or not).
    pub fn command_buffer(
        &self,
        signalled: bool,
    ) -> Result<(vk::CommandPool, vk::CommandBuffer, vk::Fence), String> {
        let d = &self.device;
        let pool = unsafe {
            d.create_command_pool(
                &vk::CommandPoolCreateInfo::default().queue_family_index(self.queue_family),
                None,
            )
        }
        .map_err(|e| e.to_string())?;
        let created = unsafe {
            d.allocate_command_buffers(
                &vk::CommandBufferAllocateInfo::default()
                    .command_pool(pool)
                    .level(vk::CommandBufferLevel::PRIMARY)
                    .command_buffer_count(1),
            )
        }
        .and_then(|cmds| {
            let flags = if signalled {
                vk::FenceCreateFlags::SIGNALED
            } else {
                vk::FenceCreateFlags::empty()
            };
            let fence =
                unsafe { d.create_fence(&vk::FenceCreateInfo::default().flags(flags), None) }?;
            Ok((cmds[0], fence))
        });
        match created {
            Ok((cmd, fence)) => Ok((pool, cmd, fence)),
            Err(e) => {
                unsafe { d.destroy_command_pool(pool, None) };
                Err(e.to_string())
            }
        }
    }

    /// Submits on the shared queue, under the shared lock; optionally waits for the
    /// first semaphore (before anything touches the final image) and signals the second.
    pub fn submit(
        &self,
        cmd: vk::CommandBuffer,
        fence: vk::Fence,
        semaphores: Option<(vk::Semaphore, vk::Semaphore)>,
    ) -> Result<(), String> {
        let cmds = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
        let (waits, signals) = match semaphores {
            Some((wait, signal)) => (
                vec![vk::SemaphoreSubmitInfo::default()
                    .semaphore(wait)
                    .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)],
                vec![vk::SemaphoreSubmitInfo::default()
                    .semaphore(signal)
                    .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)],
            ),
            None => (Vec::new(), Vec::new()),
        };
        let submit = [vk::SubmitInfo2::default()
            .command_buffer_infos(&cmds)
            .wait_semaphore_infos(&waits)
            .signal_semaphore_infos(&signals)];
        let queue = self.queue.lock().map_err(|_| "queue lock poisoned")?;
        unsafe { self.device.queue_submit2(*queue, &submit, fence) }
            .map_err(|e| format!("vkQueueSubmit2: {e}"))
    }
}

impl Drop for HostVulkan {
    fn drop(&mut self) {
        // The host owns its device: it may wait idle. Combustion's objects must be gone.
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
