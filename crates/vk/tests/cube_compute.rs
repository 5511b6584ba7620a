//! Cube maps, mip chains, image arrays and compute pipelines as the backend describes
//! them, on lavapipe with validation (synchronization included): a compute shader writes
//! every mip level of a cube map through per-level array views, a second one samples the
//! cube through a `samplerCube` at each face's centre and level, and every texel and
//! sample read back says which face and level it came from.

use std::sync::Arc;

use combustion_vk::gpu_allocator::MemoryLocation;
use combustion_vk::{
    vk, Buffer, DescriptorPool, DescriptorSetLayout, Device, DeviceDesc, DeviceSelector, Image,
    ImageDesc, OneShot, Pipeline, PipelineCache, PipelineLayout, Sampler, ShaderCompiler,
    ShaderModule, ShaderSources, ShaderStage,
};

const FILL: &str = r#"#version 460
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba32f) uniform writeonly image2DArray level;
layout(push_constant) uniform Push { uint mip; uint size; } push;
void main() {
    uvec3 id = gl_GlobalInvocationID;
    if (id.x >= push.size || id.y >= push.size) {
        return;
    }
    imageStore(level, ivec3(id), vec4(float(id.z), float(push.mip), float(id.x), float(id.y)));
}
"#;

const SAMPLE: &str = r#"#version 460
layout(local_size_x = 1) in;
layout(set = 0, binding = 0) uniform samplerCube cube;
layout(std430, set = 0, binding = 1) writeonly buffer Results { vec4 results[]; };
const vec3 FACE_CENTRES[6] = vec3[](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0),
                                    vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));
void main() {
    uint i = gl_GlobalInvocationID.x;
    results[i] = textureLod(cube, FACE_CENTRES[i % 6u], float(i / 6u));
}
"#;

const SIZE: u32 = 16;

fn device() -> Arc<Device> {
    Device::new(&DeviceDesc {
        selector: DeviceSelector::NameContains("llvmpipe".into()),
        validation: true,
        synchronization_validation: true,
        ..DeviceDesc::default()
    })
    .expect("lavapipe with validation")
}

fn compute(
    device: &Arc<Device>,
    compiler: &ShaderCompiler,
    name: &str,
    set_layout: &DescriptorSetLayout,
    push: u32,
) -> (PipelineLayout, Pipeline) {
    let ranges = [vk::PushConstantRange {
        stage_flags: vk::ShaderStageFlags::COMPUTE,
        offset: 0,
        size: push,
    }];
    let layout =
        PipelineLayout::new(device, &[set_layout], if push > 0 { &ranges } else { &[] }).unwrap();
    let spirv = compiler.compile(name, ShaderStage::Compute, &[]).unwrap();
    let module = ShaderModule::new(device, &spirv, ShaderStage::Compute).unwrap();
    let cache = PipelineCache::new(device, &[]).unwrap();
    let pipeline = Pipeline::compute(device, &module, &layout, Some(&cache)).unwrap();
    (layout, pipeline)
}

#[test]
fn compute_writes_and_samples_every_face_and_level_of_a_cube_map() {
    let device = device();
    let log = device.validation_log();
    let compiler = ShaderCompiler::new(ShaderSources::new([
        ("fill.comp", FILL),
        ("sample.comp", SAMPLE),
    ]))
    .unwrap();
    let cube = Image::new(
        &device,
        &ImageDesc::cube(
            "cube",
            vk::Format::R32G32B32A32_SFLOAT,
            SIZE,
            vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC,
        )
        .full_mips(),
    )
    .unwrap();
    let levels = cube.mip_levels();
    assert_eq!(levels, 5);
    assert_eq!(cube.layers(), 6);
    let level_views: Vec<_> = (0..levels)
        .map(|m| {
            cube.view_of(m..m + 1, 0..6, vk::ImageViewType::TYPE_2D_ARRAY)
                .unwrap()
        })
        .collect();
    let storage = DescriptorSetLayout::new(
        &device,
        &[(
            0,
            vk::DescriptorType::STORAGE_IMAGE,
            1,
            vk::ShaderStageFlags::COMPUTE,
        )],
    )
    .unwrap();
    let sampling = DescriptorSetLayout::new(
        &device,
        &[
            (
                0,
                vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                1,
                vk::ShaderStageFlags::COMPUTE,
            ),
            (
                1,
                vk::DescriptorType::STORAGE_BUFFER,
                1,
                vk::ShaderStageFlags::COMPUTE,
            ),
        ],
    )
    .unwrap();
    let (fill_layout, fill) = compute(&device, &compiler, "fill.comp", &storage, 8);
    let (sample_layout, sample) = compute(&device, &compiler, "sample.comp", &sampling, 0);
    let pool = DescriptorPool::new(
        &device,
        levels + 1,
        &[
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_IMAGE,
                descriptor_count: levels,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 1,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: 1,
            },
        ],
    )
    .unwrap();
    let sampler = Sampler::new(
        &device,
        &vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .max_lod(vk::LOD_CLAMP_NONE),
    )
    .unwrap();
    let samples = (6 * levels) as usize;
    let results = Buffer::new(
        &device,
        "cube samples",
        (samples * 16) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuToCpu,
    )
    .unwrap();
    let readbacks: Vec<Buffer> = (0..levels)
        .flat_map(|m| (0..6).map(move |face| (m, face)))
        .map(|(m, _)| {
            let side = u64::from((SIZE >> m).max(1));
            Buffer::new(
                &device,
                "cube level readback",
                side * side * 16,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )
            .unwrap()
        })
        .collect();

    let fill_sets: Vec<_> = level_views
        .iter()
        .map(|view| {
            let set = pool.allocate(&storage).unwrap();
            let info = [vk::DescriptorImageInfo {
                sampler: vk::Sampler::null(),
                image_view: view.raw(),
                image_layout: vk::ImageLayout::GENERAL,
            }];
            let write = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::STORAGE_IMAGE)
                .image_info(&info);
            unsafe { device.raw().update_descriptor_sets(&[write], &[]) };
            set
        })
        .collect();
    let sample_set = pool.allocate(&sampling).unwrap();
    let image_info = [vk::DescriptorImageInfo {
        sampler: sampler.raw(),
        image_view: cube.view(),
        image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    }];
    let buffer_info = [vk::DescriptorBufferInfo {
        buffer: results.raw(),
        offset: 0,
        range: vk::WHOLE_SIZE,
    }];
    unsafe {
        device.raw().update_descriptor_sets(
            &[
                vk::WriteDescriptorSet::default()
                    .dst_set(sample_set)
                    .dst_binding(0)
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .image_info(&image_info),
                vk::WriteDescriptorSet::default()
                    .dst_set(sample_set)
                    .dst_binding(1)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(&buffer_info),
            ],
            &[],
        )
    };

    use vk::{AccessFlags2 as A, ImageLayout as L, PipelineStageFlags2 as S};
    let mut commands = OneShot::new(&device).unwrap();
    let cmd = commands.begin().unwrap();
    let raw = device.raw();
    let barrier = |barrier: vk::ImageMemoryBarrier2<'static>| unsafe {
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().image_memory_barriers(&[barrier]),
        )
    };
    barrier(cube.barrier(
        (S::NONE, A::NONE, L::UNDEFINED),
        (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, L::GENERAL),
    ));
    unsafe {
        raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, fill.raw());
    }
    for (m, set) in fill_sets.iter().enumerate() {
        let side = (SIZE >> m).max(1);
        let push = [m as u32, side];
        unsafe {
            raw.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                fill_layout.raw(),
                0,
                &[*set],
                &[],
            );
            raw.cmd_push_constants(
                cmd,
                fill_layout.raw(),
                vk::ShaderStageFlags::COMPUTE,
                0,
                bytemuck_u32(&push),
            );
            raw.cmd_dispatch(cmd, side.div_ceil(8), side.div_ceil(8), 6);
        }
    }
    barrier(cube.barrier(
        (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, L::GENERAL),
        (
            S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        ),
    ));
    unsafe {
        raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, sample.raw());
        raw.cmd_bind_descriptor_sets(
            cmd,
            vk::PipelineBindPoint::COMPUTE,
            sample_layout.raw(),
            0,
            &[sample_set],
            &[],
        );
        raw.cmd_dispatch(cmd, samples as u32, 1, 1);
    }
    barrier(cube.barrier(
        (
            S::COMPUTE_SHADER,
            A::SHADER_SAMPLED_READ,
            L::SHADER_READ_ONLY_OPTIMAL,
        ),
        (S::COPY, A::TRANSFER_READ, L::TRANSFER_SRC_OPTIMAL),
    ));
    for (i, buffer) in readbacks.iter().enumerate() {
        let (m, face) = (i as u32 / 6, i as u32 % 6);
        cube.record_level_copy_to_buffer(cmd, buffer, m, face);
    }
    let to_host = [vk::MemoryBarrier2::default()
        .src_stage_mask(S::COPY | S::COMPUTE_SHADER)
        .src_access_mask(A::TRANSFER_WRITE | A::SHADER_STORAGE_WRITE)
        .dst_stage_mask(S::HOST)
        .dst_access_mask(A::HOST_READ)];
    unsafe {
        raw.cmd_pipeline_barrier2(
            cmd,
            &vk::DependencyInfo::default().memory_barriers(&to_host),
        )
    };
    commands.submit_and_wait().unwrap();

    for (i, buffer) in readbacks.iter().enumerate() {
        let (m, face) = (i as u32 / 6, i as u32 % 6);
        let side = (SIZE >> m).max(1);
        let texels = floats(buffer.mapped().unwrap());
        for y in 0..side {
            for x in 0..side {
                let t = &texels[((y * side + x) * 4) as usize..][..4];
                assert_eq!(
                    t,
                    [face as f32, m as f32, x as f32, y as f32],
                    "level {m}, face {face}, texel ({x}, {y})"
                );
            }
        }
    }
    let sampled = floats(results.mapped().unwrap());
    for i in 0..samples {
        let (m, face) = (i / 6, i % 6);
        let s = &sampled[i * 4..][..4];
        assert_eq!(
            (s[0], s[1]),
            (face as f32, m as f32),
            "sample of face {face} at level {m}: {s:?}"
        );
    }
    drop((level_views, fill_sets));
    drop((
        fill,
        sample,
        fill_layout,
        sample_layout,
        pool,
        storage,
        sampling,
    ));
    drop((cube, sampler, results, readbacks, commands));
    drop(device);
    let messages = log.messages();
    assert!(messages.is_empty(), "validation:\n{}", messages.join("\n"));
}

#[test]
fn impossible_image_descriptions_are_refused_with_their_reason() {
    let device = device();
    let log = device.validation_log();
    let usage = vk::ImageUsageFlags::SAMPLED;
    let cases = [
        (
            ImageDesc::new("not square", vk::Format::R8G8B8A8_UNORM, 8, 4, usage).array(6),
            "must be square",
        ),
        (
            ImageDesc::new("too many mips", vk::Format::R8G8B8A8_UNORM, 8, 8, usage).mips(5),
            "1 to 4",
        ),
        (
            ImageDesc::new("no layers", vk::Format::R8G8B8A8_UNORM, 8, 8, usage).array(0),
            "no layers",
        ),
    ];
    for (i, (desc, reason)) in cases.into_iter().enumerate() {
        let desc = if i == 0 {
            ImageDesc { cube: true, ..desc }
        } else {
            desc
        };
        match Image::new(&device, &desc) {
            Ok(_) => panic!("{} was accepted", desc.name),
            Err(e) => assert!(e.to_string().contains(reason), "{}: {e}", desc.name),
        }
    }
    let image = Image::new(
        &device,
        &ImageDesc::new("plain", vk::Format::R8G8B8A8_UNORM, 8, 8, usage).full_mips(),
    )
    .unwrap();
    assert!(image
        .view_of(0..5, 0..1, vk::ImageViewType::TYPE_2D)
        .is_err());
    assert!(image
        .view_of(1..3, 0..1, vk::ImageViewType::TYPE_2D)
        .is_ok());
    drop(image);
    drop(device);
    assert!(log.is_empty(), "{:?}", log.messages());
}

fn bytemuck_u32(values: &[u32]) -> &[u8] {
    // SAFETY: u32 has no padding and any byte pattern is a valid u8.
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast(), std::mem::size_of_val(values)) }
}

fn floats(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}
