//! A headless engine that embeds Combustion as docs/integration.md describes, written
//! from that guide and the public API alone: its own Vulkan 1.3 instance (validation
//! with synchronisation validation, a messenger counting warnings and errors), device,
//! queue lock and allocator; its own RGBA16F colour target and D32_SFLOAT depth image;
//! three frames in flight with its own command buffers and fences; and a pass of its own
//! after Combustion's in the same command buffer (a marker cleared into the colour
//! target inside a rendering that loads the scene's depth, then a copy of the colour
//! target into an image of its own).
//!
//! Every frame moves the camera and a light; every few frames the scene changes (every
//! built-in scene and the glTF files given), an object is added or removed by handle,
//! and once the targets are resized.
//!
//! ```sh
//! cargo run --example guide_engine -- --frames 1000 [--width 160 --height 120] [FILE.gltf|DIR ...]
//! ```
//!
//! Exits 1 if any Combustion or Vulkan call failed or the validation layer reported any
//! warning or error.

use std::ffi::{c_void, CStr};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use combustion::renderer::{
    ColorTarget, DepthTarget, FrameInputs, FrameTarget, GpuScene, MaterialId, MeshId, ObjectId,
    Renderer, RendererSettings,
};
use combustion::scene::{Camera, Light, Material, Mesh, Scene, BUILTIN_SCENES};
use combustion::vk::gpu_allocator::vulkan::{
    Allocation, AllocationCreateDesc, AllocationScheme, Allocator, AllocatorCreateDesc,
};
use combustion::vk::gpu_allocator::{AllocationSizes, AllocatorDebugSettings, MemoryLocation};
use combustion::vk::{ash, vk, Device, EnabledFeatures, HostDevice, ImageState, Requirements};
use combustion::SceneSource;
use glam::{Mat4, Quat, Vec3};

/// The engine's ring of frames in flight.
const FRAMES_IN_FLIGHT: usize = 3;
/// The colour target's format: linear radiance × exposure, for the engine's own passes.
const COLOR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// What to run.
#[derive(Clone, Debug)]
pub struct Options {
    pub frames: u64,
    pub width: u32,
    pub height: u32,
    /// The extent after the one resize (at half the frames).
    pub resized: (u32, u32),
    /// glTF files (or folders holding one), loaded after the built-in scenes.
    pub gltf: Vec<PathBuf>,
    /// Frames between scene switches.
    pub switch_every: u64,
    /// Frames between scene edits (an object added, then removed again).
    pub edit_every: u64,
    /// Print progress.
    pub verbose: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            frames: 1000,
            width: 160,
            height: 120,
            resized: (200, 150),
            gltf: vec![
                PathBuf::from("/work/shared/data/gltf/LightsPunctualLamp"),
                PathBuf::from("/work/shared/data/gltf/ClearCoatTest"),
            ],
            switch_every: 80,
            edit_every: 20,
            verbose: true,
        }
    }
}

/// What a run did.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// Frames recorded and submitted.
    pub frames: u64,
    /// Validation warnings and errors reported.
    pub validation_messages: usize,
    /// Scene uploads (switches) and scene edits made.
    pub uploads: usize,
    pub edits: usize,
    pub seconds: f64,
    /// The first failure, in one line.
    pub error: Option<String>,
}

#[allow(dead_code)] // Unused where the tests include this file as a module.
fn main() {
    let options = match parse_args(std::env::args().skip(1)) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            std::process::exit(2);
        }
    };
    let report = run(&options);
    println!(
        "{} frames in {:.1} s ({} uploads, {} edits); validation messages: {}",
        report.frames, report.seconds, report.uploads, report.edits, report.validation_messages
    );
    if let Some(error) = &report.error {
        eprintln!("error: {error}");
    }
    if report.error.is_some() || report.validation_messages > 0 {
        std::process::exit(1);
    }
}

#[allow(dead_code)]
fn parse_args(mut args: impl Iterator<Item = String>) -> Result<Options, String> {
    let mut options = Options::default();
    let mut files = Vec::new();
    while let Some(arg) = args.next() {
        let mut number = |name: &str| -> Result<u64, String> {
            let value = args.next().ok_or(format!("{name} takes a value"))?;
            value
                .parse::<u64>()
                .map_err(|_| format!("{name}: `{value}` is not a whole number"))
        };
        match arg.as_str() {
            "--frames" => options.frames = number("--frames")?,
            "--width" => options.width = number("--width")? as u32,
            "--height" => options.height = number("--height")? as u32,
            "--switch-every" => options.switch_every = number("--switch-every")?.max(1),
            "--edit-every" => options.edit_every = number("--edit-every")?.max(2),
            "--quiet" => options.verbose = false,
            flag if flag.starts_with("--") => return Err(format!("unknown option `{flag}`")),
            file => files.push(PathBuf::from(file)),
        }
    }
    if options.width == 0 || options.height == 0 {
        return Err("--width and --height must be at least 1".into());
    }
    options.resized = (options.width * 5 / 4, options.height * 5 / 4);
    if !files.is_empty() {
        options.gltf = files;
    }
    Ok(options)
}

/// A .gltf or .glb file: `path` itself, or the first one found under the folder `path`.
pub fn find_gltf(path: &Path) -> Result<PathBuf, String> {
    fn search(dir: &Path) -> Option<PathBuf> {
        let mut entries: Vec<_> = std::fs::read_dir(dir).ok()?.flatten().collect();
        entries.sort_by_key(|e| e.path());
        let is_gltf =
            |p: &Path| matches!(p.extension().and_then(|e| e.to_str()), Some("gltf" | "glb"));
        for entry in &entries {
            if entry.path().is_file() && is_gltf(&entry.path()) {
                return Some(entry.path());
            }
        }
        entries
            .iter()
            .filter(|e| e.path().is_dir())
            .find_map(|e| search(&e.path()))
    }
    if path.is_dir() {
        search(path).ok_or_else(|| format!("no .gltf or .glb file under {}", path.display()))
    } else {
        Ok(path.to_path_buf())
    }
}

/// Runs the engine: every failure ends the frames, then the engine tears down.
pub fn run(options: &Options) -> Report {
    let start = Instant::now();
    let mut report = Report::default();
    let messages = Box::new(Messages::default());
    match Context::new(&messages) {
        Ok(context) => {
            match Engine::new(&context, options) {
                Ok(mut engine) => {
                    if let Err(error) = engine.frames(options, &mut report) {
                        report.error.get_or_insert(error);
                    }
                    if let Err(error) = engine.teardown() {
                        report.error.get_or_insert(error);
                    }
                }
                Err(error) => report.error = Some(error),
            }
            if let Err(error) = context.destroy() {
                report.error.get_or_insert(error);
            }
        }
        Err(error) => report.error = Some(error),
    }
    report.validation_messages = messages.count.load(Ordering::SeqCst);
    report.seconds = start.elapsed().as_secs_f64();
    report
}

/// The validation layer's warnings and errors.
#[derive(Default)]
struct Messages {
    count: AtomicUsize,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let important = vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
        | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR;
    if severity.intersects(important) && !user.is_null() {
        // SAFETY: `user` is the engine's `Messages`, alive until the instance is destroyed.
        let messages = unsafe { &*(user as *const Messages) };
        messages.count.fetch_add(1, Ordering::SeqCst);
        let text = |p: *const std::ffi::c_char| {
            if p.is_null() {
                String::new()
            } else {
                // SAFETY: the layer's NUL-terminated strings, valid during the call.
                unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
            }
        };
        // SAFETY: the layer passes valid callback data.
        let (id, message) = match unsafe { data.as_ref() } {
            Some(d) => (text(d.p_message_id_name), text(d.p_message)),
            None => (String::new(), String::new()),
        };
        eprintln!("validation {severity:?} {kind:?} [{id}]: {message}");
    }
    vk::FALSE
}

fn messenger_info(messages: &Messages) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(debug_callback))
        .user_data(messages as *const Messages as *mut c_void)
}

fn vk_err(what: &str) -> impl Fn(vk::Result) -> String + '_ {
    move |result| format!("{what} failed: {result}")
}

/// The engine's own Vulkan objects: instance, messenger, device, queue and allocator.
struct Context {
    entry: ash::Entry,
    instance: ash::Instance,
    debug_utils: ash::ext::debug_utils::Instance,
    messenger: vk::DebugUtilsMessengerEXT,
    physical_device: vk::PhysicalDevice,
    device: ash::Device,
    queue_family: u32,
    queue: Arc<Mutex<vk::Queue>>,
    allocator: Option<Arc<Mutex<Allocator>>>,
    enabled: EnabledFeatures,
}

impl Context {
    fn new(messages: &Messages) -> Result<Context, String> {
        // SAFETY: loading the system Vulkan loader.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| format!("cannot load the Vulkan loader: {e}"))?;
        // SAFETY: plain queries.
        let layers = unsafe { entry.enumerate_instance_layer_properties() }
            .map_err(vk_err("vkEnumerateInstanceLayerProperties"))?;
        if !layers
            .iter()
            .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER))
        {
            return Err("VK_LAYER_KHRONOS_validation is not installed".into());
        }
        // SAFETY: as above.
        let layer_extensions =
            unsafe { entry.enumerate_instance_extension_properties(Some(VALIDATION_LAYER)) }
                .map_err(vk_err("vkEnumerateInstanceExtensionProperties"))?;
        let has = |name: &CStr| {
            layer_extensions
                .iter()
                .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name))
        };
        if !has(ash::ext::validation_features::NAME) {
            return Err("the validation layer offers no VK_EXT_validation_features".into());
        }

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"guide_engine")
            .engine_name(c"guide_engine")
            .api_version(Requirements::API_VERSION);
        let layer_names = [VALIDATION_LAYER.as_ptr()];
        let extension_names = [
            ash::ext::debug_utils::NAME.as_ptr(),
            ash::ext::validation_features::NAME.as_ptr(),
        ];
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        // Also catches messages of instance creation and destruction.
        let mut instance_messenger = messenger_info(messages);
        let instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&extension_names)
            .push_next(&mut features)
            .push_next(&mut instance_messenger);
        // SAFETY: valid create info.
        let instance = unsafe { entry.create_instance(&instance_info, None) }
            .map_err(vk_err("vkCreateInstance"))?;
        let debug_utils = ash::ext::debug_utils::Instance::new(&entry, &instance);
        // SAFETY: valid create info; `messages` outlives the instance (run's Box).
        let messenger =
            unsafe { debug_utils.create_debug_utils_messenger(&messenger_info(messages), None) }
                .map_err(vk_err("vkCreateDebugUtilsMessengerEXT"))?;

        // A Vulkan 1.3 device with one queue family doing graphics and compute.
        // SAFETY: plain queries on a live instance.
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(vk_err("vkEnumeratePhysicalDevices"))?;
        let mut chosen = None;
        for &pd in &devices {
            // SAFETY: as above.
            let properties = unsafe { instance.get_physical_device_properties(pd) };
            if properties.api_version < Requirements::API_VERSION {
                continue;
            }
            // SAFETY: as above.
            let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
            let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
            if let Some(family) = families.iter().position(|f| f.queue_flags.contains(wanted)) {
                chosen = Some((pd, family as u32));
                break;
            }
        }
        let (physical_device, queue_family) =
            chosen.ok_or("no Vulkan 1.3 device with a graphics + compute queue")?;

        let priorities = [1.0];
        let queue_infos = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut features_13 = Requirements::features_13();
        let extensions: Vec<*const std::ffi::c_char> = Requirements::DEVICE_EXTENSIONS
            .iter()
            .map(|e| e.as_ptr())
            .collect();
        let device_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_extension_names(&extensions)
            .push_next(&mut features_13);
        // SAFETY: valid create info.
        let device = unsafe { instance.create_device(physical_device, &device_info, None) }
            .map_err(vk_err("vkCreateDevice"))?;
        // SAFETY: `device_info` is what the device was created with, still alive.
        let enabled =
            unsafe { EnabledFeatures::from_create_info(app_info.api_version, &device_info) };
        // SAFETY: the queue created with the device.
        let queue = unsafe { device.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.clone(),
            device: device.clone(),
            physical_device,
            debug_settings: AllocatorDebugSettings::default(),
            buffer_device_address: false,
            allocation_sizes: AllocationSizes::default(),
        })
        .map_err(|e| format!("creating the allocator failed: {e}"))?;
        Ok(Context {
            entry,
            instance,
            debug_utils,
            messenger,
            physical_device,
            device,
            queue_family,
            queue: Arc::new(Mutex::new(queue)),
            allocator: Some(Arc::new(Mutex::new(allocator))),
            enabled,
        })
    }

    fn allocator(&self) -> &Arc<Mutex<Allocator>> {
        self.allocator
            .as_ref()
            .expect("the allocator lives until destroy")
    }

    /// Destroys what the engine created, last the instance. Every user of the device
    /// and the allocator has been dropped ([`Engine::teardown`]).
    fn destroy(mut self) -> Result<(), String> {
        let mut result = Ok(());
        if let Some(allocator) = self.allocator.take() {
            match Arc::try_unwrap(allocator) {
                Ok(allocator) => drop(allocator),
                Err(_) => {
                    result = Err("the allocator is still shared at teardown".to_owned());
                }
            }
        }
        // SAFETY: nothing created from the device or the instance is left.
        unsafe {
            self.device.destroy_device(None);
            self.debug_utils
                .destroy_debug_utils_messenger(self.messenger, None);
            self.instance.destroy_instance(None);
        }
        result
    }
}

/// One image of the engine's own with its memory.
struct OwnImage {
    image: vk::Image,
    view: vk::ImageView,
    info: vk::ImageCreateInfo<'static>,
    allocation: Option<Allocation>,
    /// Where the last recorded frame left it.
    state: ImageState,
}

impl OwnImage {
    fn new(
        context: &Context,
        name: &str,
        format: vk::Format,
        extent: vk::Extent2D,
        usage: vk::ImageUsageFlags,
        aspect: Option<vk::ImageAspectFlags>,
    ) -> Result<OwnImage, String> {
        let device = &context.device;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D {
                width: extent.width,
                height: extent.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info.
        let image = unsafe { device.create_image(&info, None) }.map_err(vk_err("vkCreateImage"))?;
        let mut own = OwnImage {
            image,
            view: vk::ImageView::null(),
            info,
            allocation: None,
            state: ImageState::UNDEFINED,
        };
        // SAFETY: a live image.
        let requirements = unsafe { device.get_image_memory_requirements(image) };
        let allocation = context
            .allocator()
            .lock()
            .map_err(|_| "the allocator's lock is poisoned".to_owned())?
            .allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            });
        let allocation = match allocation {
            Ok(a) => a,
            Err(e) => {
                own.destroy(context);
                return Err(format!("allocating {name} failed: {e}"));
            }
        };
        // SAFETY: fresh memory of the image's requirements.
        let bound =
            unsafe { device.bind_image_memory(image, allocation.memory(), allocation.offset()) };
        own.allocation = Some(allocation);
        if let Err(e) = bound {
            own.destroy(context);
            return Err(format!("vkBindImageMemory failed: {e}"));
        }
        if let Some(aspect) = aspect {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(format)
                .subresource_range(range(aspect));
            // SAFETY: valid create info of a live image.
            match unsafe { device.create_image_view(&view_info, None) } {
                Ok(view) => own.view = view,
                Err(e) => {
                    own.destroy(context);
                    return Err(format!("vkCreateImageView failed: {e}"));
                }
            }
        }
        Ok(own)
    }

    /// Destroys the image; the GPU has finished every frame that used it.
    fn destroy(&mut self, context: &Context) {
        // SAFETY: no pending use (the caller's).
        unsafe {
            if self.view != vk::ImageView::null() {
                context.device.destroy_image_view(self.view, None);
            }
            context.device.destroy_image(self.image, None);
        }
        if let Some(allocation) = self.allocation.take() {
            if let Ok(mut allocator) = context.allocator().lock() {
                let _ = allocator.free(allocation);
            }
        }
        self.view = vk::ImageView::null();
        self.image = vk::Image::null();
    }
}

fn range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

fn barrier(
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    from: ImageState,
    to: ImageState,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(from.stage)
        .src_access_mask(from.access)
        .old_layout(from.layout)
        .dst_stage_mask(to.stage)
        .dst_access_mask(to.access)
        .new_layout(to.layout)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range(aspect))
}

/// The frame's images: Combustion's colour target and depth image, and the copy.
struct Targets {
    extent: vk::Extent2D,
    color: OwnImage,
    depth: OwnImage,
    copy: OwnImage,
    /// The last frame recorded into them.
    last_frame: Option<u64>,
}

impl Targets {
    fn new(context: &Context, extent: vk::Extent2D) -> Result<Targets, String> {
        let mut color = OwnImage::new(
            context,
            "colour target",
            COLOR_FORMAT,
            extent,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            Some(vk::ImageAspectFlags::COLOR),
        )?;
        let depth = OwnImage::new(
            context,
            "depth",
            DEPTH_FORMAT,
            extent,
            vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            Some(vk::ImageAspectFlags::DEPTH),
        );
        let mut depth = match depth {
            Ok(depth) => depth,
            Err(e) => {
                color.destroy(context);
                return Err(e);
            }
        };
        let copy = OwnImage::new(
            context,
            "colour copy",
            COLOR_FORMAT,
            extent,
            vk::ImageUsageFlags::TRANSFER_DST,
            None,
        );
        match copy {
            Ok(copy) => Ok(Targets {
                extent,
                color,
                depth,
                copy,
                last_frame: None,
            }),
            Err(e) => {
                color.destroy(context);
                depth.destroy(context);
                Err(e)
            }
        }
    }

    fn destroy(mut self, context: &Context) {
        self.color.destroy(context);
        self.depth.destroy(context);
        self.copy.destroy(context);
    }
}

/// An object the engine added to the current scene, to remove again.
struct Added {
    object: ObjectId,
    material: MaterialId,
    mesh: MeshId,
}

/// Everything of the engine that uses the device: Combustion's objects, the frame ring
/// and the targets.
struct Engine<'c> {
    context: &'c Context,
    device: Option<Arc<Device>>,
    renderer: Option<Renderer>,
    scene: Option<GpuScene>,
    scenes: Vec<(String, Scene)>,
    command_pool: vk::CommandPool,
    commands: Vec<vk::CommandBuffer>,
    fences: Vec<vk::Fence>,
    /// The frame each slot last submitted, until its fence has been waited for.
    in_flight: [Option<u64>; FRAMES_IN_FLIGHT],
    /// Every frame up to this one has completed.
    completed: Option<u64>,
    targets: Option<Targets>,
    retired: Vec<Targets>,
}

impl<'c> Engine<'c> {
    fn new(context: &'c Context, options: &Options) -> Result<Engine<'c>, String> {
        let mut engine = Engine {
            context,
            device: None,
            renderer: None,
            scene: None,
            scenes: Vec::new(),
            command_pool: vk::CommandPool::null(),
            commands: Vec::new(),
            fences: Vec::new(),
            in_flight: [None; FRAMES_IN_FLIGHT],
            completed: None,
            targets: None,
            retired: Vec::new(),
        };
        if let Err(error) = engine.init(options) {
            let _ = engine.teardown();
            return Err(error);
        }
        Ok(engine)
    }

    fn init(&mut self, options: &Options) -> Result<(), String> {
        let context = self.context;
        for name in BUILTIN_SCENES {
            let scene = SceneSource::Builtin((*name).to_owned())
                .load()
                .map_err(|e| format!("builtin:{name}: {e}"))?;
            self.scenes.push((format!("builtin:{name}"), scene));
        }
        for path in &options.gltf {
            let file = find_gltf(path)?;
            let scene = SceneSource::File(file.clone())
                .load()
                .map_err(|e| e.to_string())?;
            self.scenes.push((file.display().to_string(), scene));
        }

        let device = Device::from_host(HostDevice {
            entry: context.entry.clone(),
            instance: context.instance.clone(),
            physical_device: context.physical_device,
            device: context.device.clone(),
            queue_family: context.queue_family,
            queue_index: 0,
            queue: context.queue.clone(),
            allocator: Some(context.allocator().clone()),
            enabled: context.enabled.clone(),
        })
        .map_err(|e| e.to_string())?;
        self.device = Some(device.clone());
        let mut renderer = Renderer::new(
            device,
            RendererSettings {
                frames_in_flight: FRAMES_IN_FLIGHT,
                ..RendererSettings::default()
            },
        )
        .map_err(|e| e.to_string())?;
        renderer
            .prepare_output(COLOR_FORMAT)
            .map_err(|e| e.to_string())?;
        self.renderer = Some(renderer);

        let raw = &context.device;
        let pool_info = vk::CommandPoolCreateInfo::default()
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)
            .queue_family_index(context.queue_family);
        // SAFETY: valid create info.
        self.command_pool = unsafe { raw.create_command_pool(&pool_info, None) }
            .map_err(vk_err("vkCreateCommandPool"))?;
        let allocate = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(FRAMES_IN_FLIGHT as u32);
        // SAFETY: a live pool.
        self.commands = unsafe { raw.allocate_command_buffers(&allocate) }
            .map_err(vk_err("vkAllocateCommandBuffers"))?;
        for _ in 0..FRAMES_IN_FLIGHT {
            // SAFETY: valid create info.
            let fence = unsafe { raw.create_fence(&vk::FenceCreateInfo::default(), None) }
                .map_err(vk_err("vkCreateFence"))?;
            self.fences.push(fence);
        }
        self.targets = Some(Targets::new(
            context,
            vk::Extent2D {
                width: options.width,
                height: options.height,
            },
        )?);
        Ok(())
    }

    /// Waits for the fence of `slot`'s last frame, if it has one in flight.
    fn wait_slot(&mut self, slot: usize) -> Result<(), String> {
        if let Some(frame) = self.in_flight[slot] {
            let raw = &self.context.device;
            let fence = [self.fences[slot]];
            // SAFETY: a fence of a submitted frame.
            unsafe { raw.wait_for_fences(&fence, true, u64::MAX) }
                .map_err(vk_err("vkWaitForFences"))?;
            // SAFETY: signalled, no pending use.
            unsafe { raw.reset_fences(&fence) }.map_err(vk_err("vkResetFences"))?;
            self.in_flight[slot] = None;
            // A fence signal covers every command submitted before it on the queue.
            self.completed = Some(self.completed.map_or(frame, |c| c.max(frame)));
        }
        Ok(())
    }

    /// Destroys retired targets whose frames have all completed.
    fn destroy_retired(&mut self) {
        let completed = self.completed;
        let (done, keep): (Vec<Targets>, Vec<Targets>) =
            self.retired
                .drain(..)
                .partition(|t| match (t.last_frame, completed) {
                    (None, _) => true,
                    (Some(last), Some(done)) => last <= done,
                    (Some(_), None) => false,
                });
        self.retired = keep;
        for targets in done {
            targets.destroy(self.context);
        }
    }

    fn frames(&mut self, options: &Options, report: &mut Report) -> Result<(), String> {
        let mut added: Option<Added> = None;
        let mut scene_frame = 0u64;
        let mut scene_index = 0usize;
        for frame in 0..options.frames {
            let slot = (frame % FRAMES_IN_FLIGHT as u64) as usize;
            // The only wait: the frame that last used this slot (frame − 3).
            self.wait_slot(slot)?;
            self.destroy_retired();

            let renderer = self.renderer.as_mut().ok_or("no renderer")?;
            // Switch scenes: upload the next one, drop the last (safe with frames in flight).
            if frame % options.switch_every == 0 {
                scene_index = (frame / options.switch_every) as usize % self.scenes.len();
                let (label, cpu) = &self.scenes[scene_index];
                let upload_start = Instant::now();
                let uploaded = renderer
                    .upload(cpu)
                    .map_err(|e| format!("uploading {label}: {e}"))?;
                self.scene = Some(uploaded);
                added = None;
                scene_frame = 0;
                report.uploads += 1;
                if options.verbose {
                    println!(
                        "frame {frame}: {label} uploaded in {:.2} s",
                        upload_start.elapsed().as_secs_f64()
                    );
                }
            }
            let scene = self.scene.as_mut().ok_or("no scene")?;
            // An edit by handle every so often: add an emissive sphere, later remove it.
            if frame % options.edit_every == options.edit_every / 2 {
                let edit_start = Instant::now();
                let what = match added.take() {
                    None => {
                        let cpu = scene.scene();
                        let camera = cpu.camera;
                        let size = (camera.position - camera.target).length().max(1e-3);
                        let at = camera.target + Vec3::new(0.0, 0.15 * size, 0.0);
                        let (ids, _edit) = renderer
                            .try_edit_scene(scene, |e| {
                                let mesh =
                                    e.add_mesh(Mesh::uv_sphere("engine ball", 0.05 * size, 24, 12));
                                let material = e.add_material(Material {
                                    name: "engine glow".into(),
                                    base_color: [0.2, 0.2, 0.2],
                                    emissive_factor: [1.0, 0.6, 0.2],
                                    emissive_strength: 2.0,
                                    ..Material::default()
                                });
                                let object =
                                    e.add_object(mesh, material, Mat4::from_translation(at))?;
                                Ok(Added {
                                    object,
                                    material,
                                    mesh,
                                })
                            })
                            .map_err(|e| format!("frame {frame}: adding an object: {e}"))?;
                        added = Some(ids);
                        "added"
                    }
                    Some(ids) => {
                        renderer
                            .try_edit_scene(scene, |e| {
                                e.remove_object(ids.object)?;
                                e.remove_material(ids.material)?;
                                e.remove_mesh(ids.mesh)?;
                                Ok(())
                            })
                            .map_err(|e| format!("frame {frame}: removing an object: {e}"))?;
                        "removed"
                    }
                };
                report.edits += 1;
                if options.verbose {
                    println!(
                        "frame {frame}: object {what} in {:.2} s",
                        edit_start.elapsed().as_secs_f64()
                    );
                }
            }
            // Resize once, half way: new targets now, the old ones destroyed when the
            // frames that used them have completed.
            if frame == options.frames / 2 {
                let extent = vk::Extent2D {
                    width: options.resized.0,
                    height: options.resized.1,
                };
                let new = Targets::new(self.context, extent)?;
                if let Some(old) = self.targets.replace(new) {
                    self.retired.push(old);
                }
                if options.verbose {
                    println!(
                        "frame {frame}: resized to {}x{}",
                        extent.width, extent.height
                    );
                }
            }

            // Camera and a light move every frame.
            let cpu = scene.scene();
            let t = scene_frame as f32;
            let camera = orbit_camera(&cpu.camera, 0.35 * (t * 0.07).sin());
            let lights = moving_lights(cpu, t * 0.1);
            let exposure = 1.0;

            let cmd = self.commands[slot];
            let raw = &self.context.device;
            let targets = self.targets.as_mut().ok_or("no targets")?;
            // SAFETY: the slot's last submission has completed (waited above).
            unsafe {
                raw.reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                    .map_err(vk_err("vkResetCommandBuffer"))?;
                raw.begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .map_err(vk_err("vkBeginCommandBuffer"))?;
            }
            let color_after = ImageState::COLOR_ATTACHMENT_READ_WRITE;
            let depth_after = ImageState::DEPTH_ATTACHMENT_READ_WRITE;
            let target = FrameTarget {
                color: ColorTarget::from_create_info(
                    targets.color.image,
                    targets.color.view,
                    &targets.color.info,
                    targets.color.state,
                    color_after,
                )
                .map_err(|e| e.to_string())?,
                depth: Some(
                    DepthTarget::from_create_info(
                        targets.depth.image,
                        &targets.depth.info,
                        targets.depth.state,
                        depth_after,
                    )
                    .map_err(|e| e.to_string())?,
                ),
            };
            let inputs = FrameInputs {
                camera,
                exposure,
                lights: &lights,
                overlay: &[],
                environment: None,
                background: combustion::renderer::Background::None,
                tone_mapping: combustion::renderer::ToneMapping::Exponential,
                pose: None,
                environment_seed: 0,
                anti_aliasing: combustion::renderer::AntiAliasing::None,
                auto_exposure: None,
                bloom_intensity: combustion::renderer::DEFAULT_BLOOM_INTENSITY,
            };
            if let Err(e) = renderer.record(cmd, slot, scene, &inputs, &target) {
                // SAFETY: end the (empty) recording so the buffer can be reset later.
                let _ = unsafe { raw.end_command_buffer(cmd) };
                return Err(format!("frame {frame}: record: {e}"));
            }
            targets.color.state = color_after;
            targets.depth.state = depth_after;
            // SAFETY: recording; the engine's own pass.
            unsafe { record_own_pass(raw, cmd, targets) };
            // SAFETY: recording.
            unsafe { raw.end_command_buffer(cmd) }.map_err(vk_err("vkEndCommandBuffer"))?;
            targets.last_frame = Some(frame);

            let buffers = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
            let submit = [vk::SubmitInfo2::default().command_buffer_infos(&buffers)];
            {
                let queue = self
                    .context
                    .queue
                    .lock()
                    .map_err(|_| "the queue's lock is poisoned".to_owned())?;
                // SAFETY: the queue is held; the fence is unsignalled and unused.
                unsafe { raw.queue_submit2(*queue, &submit, self.fences[slot]) }
                    .map_err(vk_err("vkQueueSubmit2"))?;
            }
            self.in_flight[slot] = Some(frame);
            report.frames += 1;
            scene_frame += 1;
            if options.verbose && frame % 100 == 99 {
                println!("frame {}: {}", frame + 1, self.scenes[scene_index].0);
            }
        }
        Ok(())
    }

    /// Waits for the engine's frames, then drops Combustion's objects (scene, renderer,
    /// device) and destroys the engine's own.
    fn teardown(mut self) -> Result<(), String> {
        let mut result = Ok(());
        for slot in 0..self.fences.len() {
            if let Err(e) = self.wait_slot(slot) {
                result = Err(e);
            }
        }
        self.scene = None;
        self.renderer = None;
        if let Some(device) = self.device.take() {
            if Arc::strong_count(&device) != 1 {
                result = Err("Combustion's device is still shared at teardown".to_owned());
            }
        }
        let context = self.context;
        for targets in self.retired.drain(..).chain(self.targets.take()) {
            targets.destroy(context);
        }
        // SAFETY: every frame has completed (waited above).
        unsafe {
            for &fence in &self.fences {
                context.device.destroy_fence(fence, None);
            }
            if self.command_pool != vk::CommandPool::null() {
                context.device.destroy_command_pool(self.command_pool, None);
            }
        }
        result
    }
}

/// The engine's pass after Combustion's: a rendering that loads the colour target and
/// the scene's depth and clears a marker into a corner of the colour, then a copy of the
/// colour target into the engine's own image.
///
/// # Safety
/// `cmd` is recording, after Combustion's frame released the colour target and the depth
/// image in the states `targets` names.
unsafe fn record_own_pass(raw: &ash::Device, cmd: vk::CommandBuffer, targets: &mut Targets) {
    let extent = targets.extent;
    let color_attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(targets.color.view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::LOAD)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(targets.depth.view)
        .image_layout(vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::LOAD)
        .store_op(vk::AttachmentStoreOp::STORE);
    let area = vk::Rect2D {
        offset: vk::Offset2D { x: 0, y: 0 },
        extent,
    };
    let rendering = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color_attachment)
        .depth_attachment(&depth_attachment);
    let marker = vk::ClearRect {
        rect: vk::Rect2D {
            offset: vk::Offset2D { x: 2, y: 2 },
            extent: vk::Extent2D {
                width: 6.min(extent.width),
                height: 6.min(extent.height),
            },
        },
        base_array_layer: 0,
        layer_count: 1,
    };
    let clear = vk::ClearAttachment {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        color_attachment: 0,
        clear_value: vk::ClearValue {
            color: vk::ClearColorValue {
                float32: [1.0, 0.0, 1.0, 1.0],
            },
        },
    };
    // SAFETY: the caller's.
    unsafe {
        raw.cmd_begin_rendering(cmd, &rendering);
        raw.cmd_clear_attachments(cmd, &[clear], &[marker]);
        raw.cmd_end_rendering(cmd);
    }

    let color = &mut targets.color;
    let copy = &mut targets.copy;
    let barriers = [
        barrier(
            color.image,
            vk::ImageAspectFlags::COLOR,
            color.state,
            ImageState::COPY_SOURCE,
        ),
        barrier(
            copy.image,
            vk::ImageAspectFlags::COLOR,
            copy.state,
            ImageState::COPY_DESTINATION,
        ),
    ];
    let layers = vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: 0,
        layer_count: 1,
    };
    let region = vk::ImageCopy {
        src_subresource: layers,
        src_offset: vk::Offset3D::default(),
        dst_subresource: layers,
        dst_offset: vk::Offset3D::default(),
        extent: vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        },
    };
    // SAFETY: the caller's.
    unsafe {
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
        );
        raw.cmd_copy_image(
            cmd,
            color.image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            copy.image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
        );
    }
    color.state = ImageState::COPY_SOURCE;
    copy.state = ImageState::COPY_DESTINATION;
}

/// `camera` turned by `angle` radians about its up axis through its target.
fn orbit_camera(camera: &Camera, angle: f32) -> Camera {
    let axis = camera.up.try_normalize().unwrap_or(Vec3::Y);
    let offset = Quat::from_axis_angle(axis, angle) * (camera.position - camera.target);
    Camera {
        position: camera.target + offset,
        ..*camera
    }
}

/// The scene's lights with the first one turned by `angle` about the vertical through the
/// camera's target; a scene lit by its environment alone gets one orbiting point light.
fn moving_lights(scene: &Scene, angle: f32) -> Vec<Light> {
    let pivot = scene.camera.target;
    let turn = Quat::from_rotation_y(angle);
    let mut lights = scene.lights.clone();
    match lights.first_mut() {
        Some(Light::Point { position, .. }) | Some(Light::Spot { position, .. }) => {
            *position = pivot + turn * (*position - pivot);
        }
        Some(Light::Directional { direction, .. }) => *direction = turn * *direction,
        None => {
            let distance = (scene.camera.position - pivot).length().max(1e-3);
            let offset = Vec3::new(0.5 * distance, 0.5 * distance, 0.0);
            let d2 = offset.length_squared();
            lights.push(Light::Point {
                position: pivot + turn * offset,
                intensity: [d2, d2 * 0.9, d2 * 0.8],
                range: None,
                casts_shadows: true,
                radius: 0.0,
            });
        }
    }
    lights
}
