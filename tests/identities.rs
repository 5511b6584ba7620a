//! Whole-pipeline checks against hand computations and physical identities, on lavapipe.

use crate::common;

use combustion::renderer::gbuffer::srgb_to_linear;
use combustion::renderer::Readback;
use combustion::scene::{builtin_scene, Light, Material, Scene, SPHERE_GRID_ROUGHNESS};
use glam::Vec3;

/// A large plane seen from above, lit straight down by a directional light.
fn lit_plane(material: Material, outside_ior: f32, irradiance: [f32; 3]) -> Scene {
    let light = Light::Directional {
        direction: Vec3::NEG_Y,
        irradiance,
        casts_shadows: true,
        angular_diameter: 0.0,
    };
    Scene {
        outside_ior,
        ..common::plane_from_above("lit plane", material, vec![light])
    }
}

/// Albedos that are exact 8-bit sRGB codes, so the G-buffer stores them without loss.
fn exact_albedo(codes: [u8; 3]) -> [f32; 3] {
    codes.map(|c| srgb_to_linear(f64::from(c) / 255.0) as f32)
}

/// With the dielectric's IOR equal to the outside medium's there is no interface: Fresnel
/// reflectance is 0, no specular, and all light goes to the diffuse lobe, so a Lambert
/// surface under irradiance E shows L = ρ/π·E in every pixel — in air (1 = 1) and under
/// water (1.33 = 1.33) alike.
#[test]
fn matched_ior_plane_is_exactly_lambert() {
    let codes = [200u8, 128, 60];
    let albedo = exact_albedo(codes);
    let irradiance = [0.9f32, 1.7, 2.5];
    for ior in [1.0f32, 1.33] {
        let material = Material {
            base_color: albedo,
            dielectric_ior: ior,
            roughness: 0.6,
            ..Material::default()
        };
        let frame = common::render(
            &lit_plane(material, ior, irradiance),
            64,
            64,
            common::exact_f32(),
            Readback::IMAGES,
        );
        let mut worst = 0.0f64;
        for pixel in &frame.hdr {
            for c in 0..3 {
                let expected =
                    f64::from(albedo[c]) / std::f64::consts::PI * f64::from(irradiance[c]);
                worst = worst.max((f64::from(pixel[c]) - expected).abs() / expected);
            }
        }
        eprintln!("ior {ior}: worst relative error {worst:e}");
        // f32 shading of a handful of operations: the error budget is a few ulps
        // (ulp = 6e-8); 1e-6 leaves room for the sRGB decode of the albedo on the GPU.
        assert!(worst < 1e-6, "ior {ior}: relative error {worst:e}");
    }
}

/// The outside medium really reaches the shader: a glass-like dielectric (η = 1.33)
/// reflects in air but not under water, where its IOR matches the medium.
#[test]
fn outside_medium_changes_dielectric_reflection() {
    let material = Material {
        base_color: exact_albedo([128, 128, 128]),
        dielectric_ior: 1.33,
        roughness: 0.3,
        ..Material::default()
    };
    let render = |outside: f32| {
        common::render(
            &lit_plane(material.clone(), outside, [1.0; 3]),
            32,
            32,
            common::exact_f32(),
            Readback::IMAGES,
        )
    };
    let (air, water) = (render(1.0), render(1.33));
    let centre = 16 * 32 + 16;
    let lambert = f64::from(material.base_color[0]) / std::f64::consts::PI;
    let water_centre = f64::from(water.hdr[centre][0]);
    let air_centre = f64::from(air.hdr[centre][0]);
    assert!(
        (water_centre - lambert).abs() < 1e-6 * lambert,
        "{water_centre} vs {lambert}"
    );
    // In air the view and light are both along the normal at the centre: a specular
    // highlight (F0 = ((1.33−1)/(1.33+1))² = 0.02) adds to the diffuse.
    assert!(
        air_centre > water_centre * 1.01,
        "air {air_centre}, water {water_centre}"
    );
}

/// On the sphere grid, highlights tighten as roughness falls: along the gold row (pure
/// specular), the peak radiance rises and the area above half the peak shrinks,
/// column by column, as roughness decreases.
#[test]
fn highlights_tighten_as_roughness_falls() {
    let scene = builtin_scene("spheres").unwrap();
    let frame = common::render(&scene, 384, 256, common::exact_f32(), Readback::ALL);
    let gbuffer = frame.gbuffer.as_ref().unwrap();
    let columns = SPHERE_GRID_ROUGHNESS.len();
    let gold_row = 1;
    let mut stats = Vec::new();
    for (column, &roughness) in SPHERE_GRID_ROUGHNESS.iter().enumerate() {
        let material = (gold_row * columns + column) as u16;
        let values: Vec<f64> = gbuffer
            .texels
            .iter()
            .zip(&frame.hdr)
            .filter(|(t, _)| t.depth < 1.0 && t.material_direction[0] == material)
            .map(|(_, hdr)| common::luminance(*hdr))
            .collect();
        assert!(
            values.len() > 100,
            "sphere {column} covers {} pixels",
            values.len()
        );
        let peak = values.iter().cloned().fold(0.0, f64::max);
        let area = values.iter().filter(|&&v| v > 0.5 * peak).count();
        stats.push((roughness, peak, area));
    }
    eprintln!("(roughness, peak, pixels above half peak): {stats:?}");
    for pair in stats.windows(2) {
        let (smoother, rougher) = (pair[0], pair[1]);
        assert!(
            smoother.1 > rougher.1,
            "peak must fall with roughness: {stats:?}"
        );
        assert!(
            smoother.2 < rougher.2,
            "highlight must grow with roughness: {stats:?}"
        );
    }
}

/// The G-buffer stores an anisotropy direction only where the surface is anisotropic
/// (an isotropic lobe is the same about any direction in its plane: code 0, the
/// decoder's reference tangent, and the pass skips the encoding). builtin:grid-7x7's
/// aluminium row (strength 0.7) keeps directions; its six isotropic rows store 0.
#[test]
fn only_anisotropic_pixels_store_a_direction() {
    let scene = builtin_scene("grid-7x7").unwrap();
    let frame = common::render(&scene, 192, 108, common::exact_f32(), Readback::ALL);
    let gbuffer = frame.gbuffer.as_ref().unwrap();
    let (mut isotropic, mut isotropic_coded, mut anisotropic, mut anisotropic_coded) =
        (0usize, 0usize, 0usize, 0usize);
    for texel in gbuffer.texels.iter().filter(|t| t.depth < 1.0) {
        let material = &scene.materials[usize::from(texel.material_direction[0])];
        let coded = texel.material_direction[1] != 0;
        if material.anisotropy_strength == 0.0 {
            isotropic += 1;
            isotropic_coded += usize::from(coded);
        } else {
            anisotropic += 1;
            anisotropic_coded += usize::from(coded);
        }
    }
    eprintln!(
        "isotropic: {isotropic_coded} of {isotropic} coded; anisotropic: {anisotropic_coded} of {anisotropic}"
    );
    assert!(
        isotropic > 1000 && anisotropic > 150,
        "{isotropic}, {anisotropic}"
    );
    assert_eq!(isotropic_coded, 0);
    // A direction whose angle rounds to 0 is stored as 0 too: a few pixels at most.
    assert!(
        anisotropic_coded as f64 > 0.99 * anisotropic as f64,
        "{anisotropic_coded} of {anisotropic}"
    );
}
