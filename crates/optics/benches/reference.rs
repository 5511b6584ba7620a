//! The CPU reference's hot functions, in f64 as the parity test, the error view and the
//! speed-against-error report call them once per pixel (and per light):
//! `cargo bench -p combustion-optics --bench reference [FILTER]`. Timings are reported,
//! never asserted: per function, the median time per call and its quartiles over 51
//! samples, each a batch of calls calibrated to last at least 5 ms. Run without `--bench`
//! (`cargo test --benches`), each function is called once, as a check that it runs.

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
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Samples per function; their median is the figure reported.
const SAMPLES: usize = 51;
/// A sample's batch of calls is doubled until it lasts at least this long.
const SAMPLE_DURATION: Duration = Duration::from_millis(5);

/// Runs the benchmarks whose names contain the filter (all without one) and prints one
/// line each; with `timed` false, calls each function once instead.
struct Bench {
    filter: Option<String>,
    timed: bool,
}

impl Bench {
    /// `cargo bench` passes `--bench` and the user's filter; `cargo test` neither.
    fn from_args() -> Self {
        let mut bench = Bench {
            filter: None,
            timed: false,
        };
        for arg in std::env::args().skip(1) {
            if arg == "--bench" {
                bench.timed = true;
            } else if !arg.starts_with('-') {
                bench.filter = Some(arg);
            }
        }
        bench
    }

    fn bench_function<R>(&mut self, name: &str, mut f: impl FnMut() -> R) {
        if self
            .filter
            .as_ref()
            .is_some_and(|filter| !name.contains(filter.as_str()))
        {
            return;
        }
        if !self.timed {
            black_box(f());
            println!("{name}: ran");
            return;
        }
        let mut batch: u32 = 1;
        while time_batch(&mut f, batch) < SAMPLE_DURATION {
            batch *= 2;
        }
        let mut nanoseconds_per_call: Vec<f64> = (0..SAMPLES)
            .map(|_| time_batch(&mut f, batch).as_secs_f64() * 1e9 / f64::from(batch))
            .collect();
        nanoseconds_per_call.sort_by(f64::total_cmp);
        let quantile = |q: f64| nanoseconds_per_call[((SAMPLES - 1) as f64 * q).round() as usize];
        println!(
            "{name:<66} median {:>8.1} ns per call (quartiles {:.1} … {:.1}; {SAMPLES} samples of {batch} calls)",
            quantile(0.5),
            quantile(0.25),
            quantile(0.75)
        );
    }
}

fn time_batch<R>(f: &mut impl FnMut() -> R, batch: u32) -> Duration {
    let start = Instant::now();
    for _ in 0..batch {
        black_box(f());
    }
    start.elapsed()
}

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

fn fresnel(c: &mut Bench) {
    let cos = cosines();
    c.bench_function("fresnel_conductor ×64 (gold, air)", || {
        cos.iter()
            .map(|&x| fresnel_conductor(black_box(x), 1.0, 0.42, 2.35).unpolarised())
            .sum::<f64>()
    });
    c.bench_function("fresnel_dielectric ×64 (glass in water)", || {
        cos.iter()
            .map(|&x| fresnel_dielectric(black_box(x), 1.33, 1.5).unpolarised())
            .sum::<f64>()
    });
    c.bench_function(
        "fresnel_dielectric_transmittance ×64 (water seen from glass, TIR)",
        || {
            cos.iter()
                .map(|&x| fresnel_dielectric_transmittance(black_box(x), 1.5, 1.33).unpolarised())
                .sum::<f64>()
        },
    );
}

fn microfacet(c: &mut Bench) {
    let dirs: Vec<(Vec3<f64>, Vec3<f64>)> = (0..64)
        .map(|i| {
            let t = f64::from(i) / 64.0;
            (direction(0.1 + 1.3 * t, 0.4), direction(1.2 - 1.0 * t, 2.5))
        })
        .collect();
    c.bench_function("D GGX anisotropic + height-correlated V ×64", || {
        dirs.iter()
            .map(|&(v, l)| {
                let h = (v + l).normalize();
                d_ggx_anisotropic(black_box(h), 0.3, 0.1)
                    * visibility_smith_ggx_height_correlated_anisotropic(v, l, 0.3, 0.1)
            })
            .sum::<f64>()
    });
}

fn brdf(c: &mut Bench) {
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
        c.bench_function(&format!("brdf_evaluate, 1 light ({name})"), || {
            brdf_evaluate(black_box(&m), n, t, bt, black_box(v), lights[0])
        });
        c.bench_function(&format!("brdf_view + 4 lights ({name})"), || {
            let view = brdf_view(black_box(&m), n, t, bt, black_box(v));
            lights
                .iter()
                .map(|&l| brdf_evaluate_view(&m, &view, l)[0])
                .sum::<f64>()
        });
    }
}

fn main() {
    let mut bench = Bench::from_args();
    fresnel(&mut bench);
    microfacet(&mut bench);
    brdf(&mut bench);
}
