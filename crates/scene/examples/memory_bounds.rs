//! Peak memory of the importer and the spectrum parser on worst-case small inputs, per
//! input class, against the data actually present (docs/gltf.md, "Memory bounds").
//!
//! `cargo run --release -p combustion-scene --example memory_bounds` (Linux: reads
//! /proc/self/status and resets the peak through /proc/self/clear_refs between cases).
//! Each case builds its file in a temporary folder, then measures the rise of the
//! process's peak resident memory (VmHWM) over its resident memory just before the
//! import (VmRSS), and prints it with the file's size and the ratio.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use combustion_scene::gltf::{import, save_gltf, ImportOptions};

#[path = "../tests/support.rs"]
mod support;
use combustion_scene::{
    Camera, ColorSpace, EnvironmentImage, Image, Material, Mesh, Object, Sampler, Scene, Texture,
    TextureRef, UvTransform, Vertex,
};
use glam::{Mat4, Vec3};
use support::{peak_rise, placements, textured_triangle};

fn report(class: &str, present: &str, present_bytes: u64, rise: u64) {
    println!(
        "{class:<12} {present:<38} {:>10.2} MiB present, peak +{:>8.2} MiB, {:>6.2}×",
        present_bytes as f64 / (1 << 20) as f64,
        rise as f64 / (1 << 20) as f64,
        rise as f64 / present_bytes as f64
    );
}

fn camera() -> Camera {
    Camera {
        position: Vec3::new(0.0, 0.0, 3.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        vertical_fov: 0.8,
        near: 0.1,
        far: 100.0,
    }
}

fn scene(meshes: Vec<Mesh>, material: Material) -> Scene {
    Scene {
        name: "memory".into(),
        objects: (0..meshes.len())
            .map(|mesh| Object {
                mesh,
                material: 0,
                transform: Mat4::IDENTITY,
                casts_shadows: true,
                node: None,
            })
            .collect(),
        meshes,
        materials: vec![material],
        lights: Vec::new(),
        camera: camera(),
        outside_ior: 1.0,
        environment: None,
        motion: Default::default(),
    }
}

fn file_size(path: &Path) -> u64 {
    std::fs::metadata(path).map(|m| m.len()).unwrap_or(0)
}

fn main() {
    let dir: PathBuf = support::temp_dir("memory", "bounds");
    let options = ImportOptions::default();

    // Spectra: a measured n, k table of 200,000 rows (first: a small case measured after
    // large ones reuses their freed memory and reads too little).
    let rows = 200_000;
    let mut csv = String::from("wavelength_nm,n,k\n");
    for i in 0..rows {
        let wavelength = 400.0 + 400.0 * f64::from(i) / f64::from(rows);
        csv += &format!(
            "{wavelength:.6},{:.6},{:.6}\n",
            0.2 + 1e-6 * f64::from(i),
            3.0
        );
    }
    let (result, rise) = peak_rise(|| combustion_spectra::Spectrum::from_csv(&csv).map(|_| ()));
    println!("spectra: {result:?}");
    report(
        "spectra",
        "200,000 rows of wavelength, n, k",
        csv.len() as u64,
        rise,
    );

    // glTF JSON: 200,000 nodes of one scene, no geometry (the JSON is all there is);
    // then the same count of empty nodes (`{}`): the JSON's worst case, a parsed node
    // and its motion node for three bytes of JSON.
    let nodes = 200_000;
    // Written straight into one string, kept until the import is measured: no freed
    // temporaries for the import to reuse (they would hide its rise).
    let write_nodes = |name: &str, node: &dyn Fn(&mut String, usize)| -> (PathBuf, String) {
        use std::fmt::Write;
        let path = dir.join(name);
        let mut json = String::from(r#"{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":["#);
        for i in 0..nodes {
            let _ = write!(json, "{}{i}", if i == 0 { "" } else { "," });
        }
        json += r#"]}],"nodes":["#;
        for i in 0..nodes {
            if i > 0 {
                json.push(',');
            }
            node(&mut json, i);
        }
        json += "]}";
        std::fs::write(&path, &json).expect("write");
        (path, json)
    };
    let (json_path, _json) = write_nodes("nodes.gltf", &|json, i| {
        use std::fmt::Write;
        let _ = write!(json, r#"{{"name":"n{i}","translation":[{i},0,0]}}"#);
    });
    let (result, rise) = peak_rise(|| import(&json_path, &options).map(|_| ()));
    println!("glTF JSON: {result:?}");
    report("glTF JSON", "200,000 nodes", file_size(&json_path), rise);

    let (empty_path, _json) = write_nodes("empty-nodes.gltf", &|json, _| json.push_str("{}"));
    let (result, rise) = peak_rise(|| import(&empty_path, &options).map(|_| ()));
    println!("glTF JSON, empty nodes: {result:?}");
    report(
        "glTF JSON",
        "200,000 empty nodes",
        file_size(&empty_path),
        rise,
    );

    // Buffers: one mesh of 1,000,000 vertices (position, normal, tangent, uv) and
    // 3,000,000 indices; the .bin is the data present.
    let mesh_path = dir.join("mesh.gltf");
    let count = 1_000_000u32;
    let vertices: Vec<Vertex> = (0..count)
        .map(|i| {
            let x = (i % 1000) as f32 * 1e-3;
            let y = (i / 1000) as f32 * 1e-3;
            Vertex {
                position: [x, y, 0.0],
                normal: [0.0, 0.0, 1.0],
                tangent: [1.0, 0.0, 0.0, 1.0],
                uv: [x, y],
                uv1: [x, y],
                ..Vertex::default()
            }
        })
        .collect();
    let indices: Vec<u32> = (0..count - 2)
        .flat_map(|i| [i, i + 1, i + 2])
        .filter(|&i| i < count)
        .collect();
    let mesh = Mesh {
        name: "strip".into(),
        vertices,
        indices,
        ..Default::default()
    };
    save_gltf(&scene(vec![mesh], Material::default()), &mesh_path).expect("save");
    let (result, rise) = peak_rise(|| import(&mesh_path, &options).map(|_| ()));
    println!("buffers: {result:?}");
    report(
        "buffers",
        "1,000,000 vertices, 3,000,000 indices",
        file_size(&dir.join("mesh.bin")),
        rise,
    );

    // Images: a 4096×4096 texture of one colour (its PNG is tiny; the decoded RGBA8
    // pixels are the data present).
    let image_path = dir.join("image.gltf");
    let side = 4096u32;
    let pixels = [200u8, 120, 40, 255].repeat((side * side) as usize);
    let texture = TextureRef {
        texture: Texture {
            image: Arc::new(Image {
                name: "flat".into(),
                width: side,
                height: side,
                color_space: ColorSpace::Srgb,
                pixels,
            }),
            sampler: Sampler::default(),
        },
        tex_coord: 0,
        transform: UvTransform::IDENTITY,
    };
    let material = Material {
        base_color_texture: Some(texture),
        ..Material::default()
    };
    save_gltf(
        &scene(vec![Mesh::plane("plane", 1.0)], material),
        &image_path,
    )
    .expect("save");
    let png = file_size(&dir.join("image_0.png"));
    let (result, rise) = peak_rise(|| import(&image_path, &options).map(|_| ()));
    println!("images: {result:?} (PNG of {png} bytes)");
    report(
        "images",
        "4096×4096 RGBA8, decoded",
        u64::from(side * side) * 4,
        rise,
    );

    // Encoded images the decoders work beside: an 8192×8192 image of one colour as JPEG
    // (baseline and progressive, 4:2:0 and 4:4:4, by libjpeg-turbo's cjpeg) and WebP
    // (lossy and lossless, by cwebp), each a triangle's texture; skipped where the
    // encoders are not installed (libjpeg-turbo-progs, webp).
    let side = 8192u32;
    let ppm_path = dir.join("flat.ppm");
    let mut ppm = format!("P6\n{side} {side}\n255\n").into_bytes();
    ppm.extend([200u8, 120, 40].repeat((side * side) as usize));
    std::fs::write(&ppm_path, &ppm).expect("write");
    drop(ppm);
    let encoders: [(&str, &str, &[&str]); 6] = [
        (
            "JPEG progressive 4:4:4",
            "cjpeg",
            &["-progressive", "-sample", "1x1"],
        ),
        (
            "JPEG progressive 4:2:0",
            "cjpeg",
            &["-progressive", "-sample", "2x2"],
        ),
        ("JPEG baseline 4:4:4", "cjpeg", &["-sample", "1x1"]),
        ("JPEG baseline 4:2:0", "cjpeg", &["-sample", "2x2"]),
        ("WebP lossy", "cwebp", &["-quiet"]),
        ("WebP lossless", "cwebp", &["-quiet", "-lossless"]),
    ];
    for (label, encoder, arguments) in encoders {
        let encoded = dir.join("texture.image");
        let mut command = std::process::Command::new(encoder);
        command.args(arguments);
        if encoder == "cjpeg" {
            command.arg("-outfile").arg(&encoded).arg(&ppm_path);
        } else {
            command.arg(&ppm_path).arg("-o").arg(&encoded);
        }
        match command.status() {
            Ok(status) if status.success() => {}
            _ => {
                println!("{label}: skipped ({encoder} did not run)");
                continue;
            }
        }
        let path = dir.join("textured.gltf");
        std::fs::write(&path, textured_triangle("texture.image")).expect("write");
        // A budget of 4 GiB: the decoders' worst cases charged (4.5× for a progressive
        // RGB JPEG) let even the largest image in, to measure what it takes.
        let roomy = ImportOptions {
            max_decoded_pixels: 1 << 30,
            ..ImportOptions::default()
        };
        let (result, rise) = peak_rise(|| import(&path, &roomy).map(|_| ()));
        println!("{label}: {result:?} ({} bytes)", file_size(&encoded));
        report(
            label,
            "8192×8192 RGBA8, decoded",
            u64::from(side * side) * 4,
            rise,
        );
    }

    // Accessors without a buffer view: zeros no byte of the file holds, capped at 2²²
    // elements per file. Two small files: 2²¹ − 2 zero positions and as many zero normals
    // (no indices), and 2²² − 1 zero indices under three positions; in each, two sparse
    // values make the first triangle not degenerate. The data present is what the
    // accessors declare.
    let count = (1u64 << 22) - 1;
    let bytes = |words: &[u32], floats: &[f32]| -> Vec<u8> {
        let mut out: Vec<u8> = words.iter().flat_map(|w| w.to_le_bytes()).collect();
        out.extend(floats.iter().flat_map(|f| f.to_le_bytes()));
        out
    };
    let sparse = r#""sparse":{"count":2,"indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":1}}"#;
    let cases = [
        (
            "2 × (2²¹ − 2) positions, normals, no view",
            24,
            // Sparse indices 1, 2; values (1, 0, 0), (0, 1, 0).
            bytes(&[1, 2], &[1.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
            r#"[{"buffer":0,"byteLength":8},{"buffer":0,"byteOffset":8,"byteLength":24}]"#,
            r#"{"POSITION":0,"NORMAL":1}"#,
            format!(
                r#"[{{"componentType":5126,"count":{half},"type":"VEC3","min":[0,0,0],"max":[1,1,0],{sparse}}},
{{"componentType":5126,"count":{half},"type":"VEC3"}}]"#,
                half = (1u64 << 21) - 2
            ),
        ),
        (
            "2²² − 1 indices, no buffer view",
            4,
            // Sparse indices 1, 2; values 1, 2; then three positions.
            bytes(
                &[1, 2, 1, 2],
                &[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            ),
            r#"[{"buffer":0,"byteLength":8},{"buffer":0,"byteOffset":8,"byteLength":8},{"buffer":0,"byteOffset":16,"byteLength":36}]"#,
            r#"{"POSITION":1},"indices":0"#,
            format!(
                r#"[{{"componentType":5125,"count":{count},"type":"SCALAR",{sparse}}},
{{"bufferView":2,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}}]"#
            ),
        ),
    ];
    for (label, element_bytes, bin, views, attributes, accessors) in cases {
        let path = dir.join("unbacked.gltf");
        std::fs::write(dir.join("unbacked.bin"), &bin).expect("write");
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{attributes}}}]}}],"accessors":{accessors},"bufferViews":{views},
"buffers":[{{"byteLength":{},"uri":"unbacked.bin"}}]}}"#,
            bin.len()
        );
        std::fs::write(&path, &json).expect("write");
        let (result, rise) = peak_rise(|| import(&path, &options).map(|_| ()));
        println!(
            "unbacked accessors: {result:?} ({} bytes of JSON and .bin)",
            json.len() + bin.len()
        );
        let elements = if element_bytes == 24 {
            (1 << 21) - 2
        } else {
            count
        };
        report("unbacked", label, elements * element_bytes, rise);
    }

    // Meshes: 100,000 vertices with normals (2.4 MB of .bin), placed by 1,000 primitives
    // whose index accessors alias one triangle: each primitive is a mesh of all 100,000
    // vertices, until the file's mesh budget (256 MiB + 256 × the bytes read) refuses.
    let path = dir.join("aliased.gltf");
    let vertices = 100_000u32;
    let mut bin: Vec<u8> = (0..vertices)
        .flat_map(|i| [(i % 1000) as f32 * 1e-3, (i / 1000) as f32 * 1e-2, 0.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    bin.extend(
        (0..vertices)
            .flat_map(|_| [0.0f32, 0.0, 1.0])
            .flat_map(f32::to_le_bytes),
    );
    bin.extend([0u32, 1, 1000].iter().flat_map(|i| i.to_le_bytes()));
    std::fs::write(dir.join("aliased.bin"), &bin).expect("write");
    let n = vertices as usize * 12;
    let aliases = 1000;
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{}]}}],"accessors":[
{{"bufferView":0,"componentType":5126,"count":{vertices},"type":"VEC3","min":[0,0,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5126,"count":{vertices},"type":"VEC3"}},{}],
"bufferViews":[{{"buffer":0,"byteLength":{n}}},{{"buffer":0,"byteOffset":{n},"byteLength":{n}}},
{{"buffer":0,"byteOffset":{},"byteLength":12}}],
"buffers":[{{"byteLength":{},"uri":"aliased.bin"}}]}}"#,
        (0..aliases)
            .map(|i| format!(
                r#"{{"attributes":{{"POSITION":0,"NORMAL":1}},"indices":{}}}"#,
                i + 2
            ))
            .collect::<Vec<_>>()
            .join(","),
        (0..aliases)
            .map(|_| r#"{"bufferView":2,"componentType":5125,"count":3,"type":"SCALAR"}"#)
            .collect::<Vec<_>>()
            .join(","),
        2 * n,
        bin.len()
    );
    std::fs::write(&path, &json).expect("write");
    let (result, rise) = peak_rise(|| import(&path, &options).map(|_| ()));
    println!("meshes: {result:?}");
    report(
        "meshes",
        "1,000 aliases of 100,000 vertices",
        (json.len() + bin.len()) as u64,
        rise,
    );

    // Placements: 1,448 nodes each placing a mesh of 1,448 primitives (2,096,704, near
    // the 2²¹ limit) from 66 KB of JSON: the limit is the bound.
    let path = dir.join("placements.gltf");
    let side = 1448;
    let json = placements(side);
    std::fs::write(&path, &json).expect("write");
    let (result, rise) = peak_rise(|| import(&path, &options).map(|_| ()));
    println!("placements: {result:?}");
    report(
        "placements",
        "2,096,704 placements",
        json.len() as u64,
        rise,
    );

    // Environment images: an 8192 × 4096 .hdr of one colour (run-length encoded: a few
    // MB) and the same as OpenEXR; the data present is the decoded texels (12 bytes each).
    let (width, height) = (8192u32, 4096u32);
    let hdr_path = dir.join("sky.hdr");
    {
        let texels = vec![image::Rgb([0.5f32, 0.75, 1.0]); (width * height) as usize];
        let file = std::fs::File::create(&hdr_path).expect("create");
        image::codecs::hdr::HdrEncoder::new(std::io::BufWriter::new(file))
            .encode(&texels, width as usize, height as usize)
            .expect("encode .hdr");
    }
    let decoded = u64::from(width * height) * 12;
    let (result, rise) = peak_rise(|| EnvironmentImage::load(&hdr_path).map(|_| ()));
    println!(
        "environment .hdr ({} bytes): {result:?}",
        file_size(&hdr_path)
    );
    report("env .hdr", "8192×4096 texels, RLE .hdr", decoded, rise);

    let _ = std::fs::remove_dir_all(&dir);
}
