//! The CPU reference's hot functions, in f64 as the parity test, the error view and the
//! speed-against-error report call them once per pixel (and per light):
//! `cargo bench -p combustion-optics --bench reference`. Timings are reported, never
//! asserted.

use combustion_optics::brdf::{
    brdf_evaluate, brdf_evaluate_view, brdf_view, BrdfInputs, DiffuseModel,
};
use combustion_optics::fresnel::{
    fresnel_conductor, fresnel_dielectric, fresnel_dielectric_transmittance,
};
use combustion_optics::microfacet::{
    d_ggx_anisotropic, visibility_smith_ggx_height_correlated_anisotropic,
};
use combustion_optics::vec3::Vec3;
use criterion::{black_box, criterion_group, criterion_main, Criterion};

/// 64 cosines from grazing to normal incidence.
fn cosines() -> Vec<f64> {
    (0..64).map(|i| (f64::from(i) + 0.5) / 64.0).collect()
}

fn direction(theta: f64, phi: f64) -> Vec3<f64> {
    Vec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

fn material(metalness: f64, model: DiffuseModel, outside_eta: f64) -> BrdfInputs<f64> {
    BrdfInputs {
        base_color: [0.8, 0.5, 0.2],
        metalness,
        alpha_x: 0.3,
        alpha_y: 0.1,
        // gold's RGB optical constants (approximately the spectra crate's)
        conductor_eta: [0.18, 0.42, 1.37],
        conductor_k: [3.42, 2.35, 1.77],
        dielectric_eta: 1.5,
        outside_eta,
        polarisation_weight: 0.5,
        diffuse_model: model,
        oren_nayar_sigma: 0.3,
    }
}

fn fresnel(c: &mut Criterion) {
    let cos = cosines();
    c.bench_function("fresnel_conductor ×64 (gold, air)", |b| {
        b.iter(|| {
            cos.iter()
                .map(|&x| fresnel_conductor(black_box(x), 1.0, 0.42, 2.35).unpolarised())
                .sum::<f64>()
        })
    });
    c.bench_function("fresnel_dielectric ×64 (glass in water)", |b| {
        b.iter(|| {
            cos.iter()
                .map(|&x| fresnel_dielectric(black_box(x), 1.33, 1.5).unpolarised())
                .sum::<f64>()
        })
    });
    c.bench_function(
        "fresnel_dielectric_transmittance ×64 (water seen from glass, TIR)",
        |b| {
            b.iter(|| {
                cos.iter()
                    .map(|&x| {
                        fresnel_dielectric_transmittance(black_box(x), 1.5, 1.33).unpolarised()
                    })
                    .sum::<f64>()
            })
        },
    );
}

fn microfacet(c: &mut Criterion) {
    let dirs: Vec<(Vec3<f64>, Vec3<f64>)> = (0..64)
        .map(|i| {
            let t = f64::from(i) / 64.0;
            (direction(0.1 + 1.3 * t, 0.4), direction(1.2 - 1.0 * t, 2.5))
        })
        .collect();
    c.bench_function("D GGX anisotropic + height-correlated V ×64", |b| {
        b.iter(|| {
            dirs.iter()
                .map(|&(v, l)| {
                    let h = (v + l).normalize();
                    d_ggx_anisotropic(black_box(h), 0.3, 0.1)
                        * visibility_smith_ggx_height_correlated_anisotropic(v, l, 0.3, 0.1)
                })
                .sum::<f64>()
        })
    });
}

fn brdf(c: &mut Criterion) {
    let n = Vec3::new(0.0, 0.0, 1.0);
    let t = Vec3::new(1.0, 0.0, 0.0);
    let bt = Vec3::new(0.0, 1.0, 0.0);
    let v = direction(0.7, 0.3);
    let lights: Vec<Vec3<f64>> = (0..4)
        .map(|i| direction(0.2 + 0.3 * f64::from(i), 1.7 * f64::from(i)))
        .collect();
    for (name, m) in [
        ("conductor", material(1.0, DiffuseModel::Lambert, 1.0)),
        (
            "dielectric, Lambert",
            material(0.0, DiffuseModel::Lambert, 1.0),
        ),
        (
            "dielectric, Oren–Nayar full, in water",
            material(0.0, DiffuseModel::OrenNayarFull, 1.33),
        ),
        (
            "half metal, Oren–Nayar qualitative",
            material(0.5, DiffuseModel::OrenNayarQualitative, 1.0),
        ),
    ] {
        c.bench_function(&format!("brdf_evaluate, 1 light ({name})"), |b| {
            b.iter(|| brdf_evaluate(black_box(&m), n, t, bt, black_box(v), lights[0]))
        });
        c.bench_function(&format!("brdf_view + 4 lights ({name})"), |b| {
            b.iter(|| {
                let view = brdf_view(black_box(&m), n, t, bt, black_box(v));
                lights
                    .iter()
                    .map(|&l| brdf_evaluate_view(&m, &view, l)[0])
                    .sum::<f64>()
            })
        });
    }
}

criterion_group!(benches, fresnel, microfacet, brdf);
criterion_main!(benches);
