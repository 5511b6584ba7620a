//! A scene's textures on the GPU: one image (with mipmaps) per distinct scene image, one
//! sampler per distinct sampler state, and one descriptor set per material binding its
//! eight texture slots (set 1 of the G-buffer pass; empty slots get a 1×1 white image).
//! Per-material sets rather than one indexed array: lavapipe (Mesa 22.3) lacks
//! `shaderSampledImageArrayDynamicIndexing`.

use std::collections::HashMap;
use std::sync::Arc;

use combustion_scene::{
    ColorSpace, Filter, Image as SceneImage, Sampler as SceneSampler, Scene, WrapMode,
};
use combustion_vk::{
    full_mip_chain, vk, Buffer, DescriptorPool, DescriptorSetLayout, Device, Image, ImageDesc,
    OneShot, Sampler, VkError,
};

use crate::bindings;
use crate::error::RenderError;

/// Textures of one scene.
pub struct SceneTextures {
    /// Per material: its texture set.
    pub(crate) material_sets: Vec<vk::DescriptorSet>,
    /// Per material, per `TextureSlot::ALL` slot: the texture's index or -1 (the shader
    /// samples a slot only when its index is ≥ 0).
    pub(crate) material_indices: Vec<[i32; combustion_scene::TEXTURE_SLOTS]>,
    /// Owns the sets.
    _pool: DescriptorPool,
    _samplers: Vec<Sampler>,
    /// Each scene image (kept, so that its identity stays its own) with its upload,
    /// shared with the textures of an edited scene that still uses it.
    images: Vec<(Arc<SceneImage>, Arc<Image>)>,
    /// The 1×1 white image of empty slots.
    white: Arc<Image>,
}

fn sampler_info(s: &SceneSampler) -> vk::SamplerCreateInfo<'static> {
    let filter = |f: Filter| match f {
        Filter::Nearest => vk::Filter::NEAREST,
        Filter::Linear => vk::Filter::LINEAR,
    };
    let wrap = |w: WrapMode| match w {
        WrapMode::Repeat => vk::SamplerAddressMode::REPEAT,
        WrapMode::MirroredRepeat => vk::SamplerAddressMode::MIRRORED_REPEAT,
        WrapMode::ClampToEdge => vk::SamplerAddressMode::CLAMP_TO_EDGE,
    };
    vk::SamplerCreateInfo::default()
        .mag_filter(filter(s.mag_filter))
        .min_filter(filter(s.min_filter))
        .mipmap_mode(match s.mipmap_filter {
            Some(Filter::Linear) => vk::SamplerMipmapMode::LINEAR,
            _ => vk::SamplerMipmapMode::NEAREST,
        })
        .address_mode_u(wrap(s.wrap_u))
        .address_mode_v(wrap(s.wrap_v))
        .address_mode_w(vk::SamplerAddressMode::REPEAT)
        .min_lod(0.0)
        // No mipmap filter: sample level 0 only (glTF NEAREST/LINEAR min filters).
        .max_lod(if s.mipmap_filter.is_some() {
            vk::LOD_CLAMP_NONE
        } else {
            0.0
        })
}

fn upload_image(
    device: &Arc<Device>,
    commands: &mut OneShot,
    name: &str,
    width: u32,
    height: u32,
    pixels: &[u8],
    color_space: ColorSpace,
) -> Result<Image, RenderError> {
    let format = match color_space {
        ColorSpace::Srgb => vk::Format::R8G8B8A8_SRGB,
        ColorSpace::Linear => vk::Format::R8G8B8A8_UNORM,
    };
    // Mipmaps by linear blits where the format allows it.
    // SAFETY: plain query.
    let properties = unsafe {
        device
            .instance()
            .get_physical_device_format_properties(device.physical_device(), format)
    };
    let needed = vk::FormatFeatureFlags::BLIT_SRC
        | vk::FormatFeatureFlags::BLIT_DST
        | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
    let mip_levels = if properties.optimal_tiling_features.contains(needed) {
        full_mip_chain(width, height)
    } else {
        1
    };
    let image = Image::new(
        device,
        &ImageDesc::new(
            name,
            format,
            width,
            height,
            vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::TRANSFER_SRC,
        )
        .mips(mip_levels),
    )?;
    let staging = Buffer::with_data(device, name, pixels, vk::BufferUsageFlags::TRANSFER_SRC)?;
    let cmd = commands.begin()?;
    image.record_upload_with_mips(cmd, &staging);
    commands.submit_and_wait()?;
    Ok(image)
}

impl SceneTextures {
    /// The textures of `scene`: images that `previous` (the textures of the scene
    /// before an edit) already uploaded — the same scene image, by identity — are
    /// shared, the others uploaded. Also returns how many images were uploaded.
    pub fn new(
        device: &Arc<Device>,
        scene: &Scene,
        set_layout: &DescriptorSetLayout,
        previous: Option<&SceneTextures>,
    ) -> Result<(Self, usize), RenderError> {
        let table = scene.texture_table();
        let max = device.max_image_dimension_2d();
        let mut commands = OneShot::new(device)?;
        let mut uploaded = 0;
        let mut images: Vec<(Arc<SceneImage>, Arc<Image>)> = Vec::with_capacity(table.images.len());
        for image in &table.images {
            let earlier = previous.and_then(|p| {
                p.images
                    .iter()
                    .find(|(source, _)| Arc::ptr_eq(source, image))
                    .map(|(_, gpu)| gpu.clone())
            });
            if let Some(gpu) = earlier {
                images.push((image.clone(), gpu));
                continue;
            }
            if image.width > max || image.height > max {
                return Err(RenderError::TooLarge(format!(
                    "image `{}` is {}×{}, larger than this device's limit of {max} per side",
                    image.name, image.width, image.height
                )));
            }
            let gpu = upload_image(
                device,
                &mut commands,
                &image.name,
                image.width,
                image.height,
                &image.pixels,
                image.color_space,
            )?;
            uploaded += 1;
            images.push((image.clone(), Arc::new(gpu)));
        }
        let white = match previous {
            Some(p) => p.white.clone(),
            None => Arc::new(upload_image(
                device,
                &mut commands,
                "white 1x1",
                1,
                1,
                &[255; 4],
                ColorSpace::Linear,
            )?),
        };
        let mut samplers = Vec::new();
        let mut sampler_index = HashMap::new();
        let mut sampler_for = |s: &SceneSampler| -> Result<usize, VkError> {
            if let Some(&i) = sampler_index.get(s) {
                return Ok(i);
            }
            samplers.push(Sampler::new(device, &sampler_info(s))?);
            sampler_index.insert(*s, samplers.len() - 1);
            Ok(samplers.len() - 1)
        };
        let default_sampler = sampler_for(&SceneSampler::default())?;
        let texture_samplers = table
            .textures
            .iter()
            .map(|t| sampler_for(&t.sampler))
            .collect::<Result<Vec<_>, _>>()?;
        let material_count = scene.materials.len().max(1) as u32;
        let decl = &bindings::MATERIAL_TEXTURES;
        let pool = DescriptorPool::new(
            device,
            material_count,
            &decl.pool_sizes(material_count, device.ray_queries()),
        )?;
        let mut material_sets = Vec::with_capacity(scene.materials.len());
        for slots in &table.material_textures {
            let set = pool.allocate(set_layout)?;
            let mut writer = decl.writer(set);
            for (binding, slot) in decl.bindings.iter().zip(slots) {
                let (image, sampler) = match slot {
                    Some(t) => (&images[table.textures[*t].image].1, texture_samplers[*t]),
                    None => (&white, default_sampler),
                };
                writer = writer.image(
                    binding.name,
                    image.view(),
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    samplers[sampler].raw(),
                );
            }
            // The set is new and not in use.
            writer.apply(device);
            material_sets.push(set);
        }
        let material_indices = table
            .material_textures
            .iter()
            .map(|slots| slots.map(|s| s.map_or(-1, |i| i as i32)))
            .collect();
        Ok((
            Self {
                material_sets,
                material_indices,
                _pool: pool,
                _samplers: samplers,
                images,
                white,
            },
            uploaded,
        ))
    }
}
