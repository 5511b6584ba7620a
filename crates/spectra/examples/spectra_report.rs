//! Prints the markdown tables of `assets/spectra/README.md`.
//!
//! ```text
//! cargo run -p combustion-spectra --example spectra_report             # README tables
//! cargo run -p combustion-spectra --example spectra_report -- a.csv b.csv
//! ```
//!
//! With CSV paths as arguments it prints, for each file, the RGB η, k of method (a) and
//! the normal-incidence reflectance in air of methods (a) and (b), one table row per file
//! (used to compare alternative data sets; nothing here reads them by default).

use combustion_spectra::{
    compare_builtin_metals, rgb_band_averaged_reflectance, rgb_optical_constants,
    AveragingComparison, BuiltinDielectric, RgbBand, Spectrum, SpectrumError,
    COMPARISON_ANGLES_DEG, COMPARISON_OUTSIDE_ETAS,
};
use std::process::ExitCode;

fn triple(v: [f64; 3], decimals: usize) -> String {
    format!("{:.d$}, {:.d$}, {:.d$}", v[0], v[1], v[2], d = decimals)
}

fn signed_triple(v: [f64; 3]) -> String {
    format!("{:+.5}, {:+.5}, {:+.5}", v[0], v[1], v[2])
}

/// Largest |(a) − (b)| among `rows` with the given outside index, and where it occurs.
fn max_difference(rows: &[AveragingComparison], outside_eta: f64) -> String {
    let mut best = (0.0f64, 0usize, 0.0f64);
    for row in rows.iter().filter(|r| r.outside_eta == outside_eta) {
        for (c, d) in row.difference().into_iter().enumerate() {
            if d.abs() > best.0.abs() {
                best = (d, c, row.theta_deg);
            }
        }
    }
    let channel = RgbBand::ALL[best.1].name();
    format!("{:.5} ({}, {}°)", best.0.abs(), channel, best.2)
}

fn builtin_report() -> Result<(), SpectrumError> {
    println!("### Dielectrics");
    println!();
    println!("| dielectric | data | η (R, G, B) | k (R, G, B) | R(0°), ηi = 1 (R, G, B) |");
    println!("|---|---|---|---|---|");
    for dielectric in BuiltinDielectric::ALL {
        let c = rgb_optical_constants(dielectric.spectrum())?;
        let r0 = c.reflectance(1.0, 1.0, 0.5)?;
        println!(
            "| {} | {} | {} | {:.2e}, {:.2e}, {:.2e} | {} |",
            dielectric.name(),
            dielectric.dataset(),
            triple(c.eta, 5),
            c.k[0],
            c.k[1],
            c.k[2],
            triple(r0, 5),
        );
    }
    println!();
    let report = compare_builtin_metals()?;
    println!("### Method (a) − method (b), per metal, angle and channel");
    println!();
    println!(
        "Unpolarised light (w = ½). (a) = Fresnel of the band-averaged η, k; (b) = \
         band-averaged Fresnel reflectance. Values are reflectances in [0, 1]."
    );
    for (metal, rows) in &report {
        println!();
        println!(
            "**{}** ({}, {})",
            metal.name(),
            metal.symbol(),
            metal.dataset()
        );
        println!();
        println!("| ηi | θ | (a) R, G, B | (b) R, G, B | (a) − (b) R, G, B |");
        println!("|---|---|---|---|---|");
        for row in rows {
            println!(
                "| {} | {}° | {} | {} | {} |",
                row.outside_eta,
                row.theta_deg,
                triple(row.averaged_constants, 4),
                triple(row.averaged_reflectance, 4),
                signed_triple(row.difference())
            );
        }
    }
    println!();
    println!("### Summary per metal");
    println!();
    println!(
        "η, k: method (a) band means. R(0°): normal incidence from air (ηi = 1), method (a). \
         max |(a) − (b)|: over θ ∈ {{{}}}° and the three channels (where it occurs in \
         parentheses), unpolarised.",
        COMPARISON_ANGLES_DEG.map(|a| a.to_string()).join(", ")
    );
    println!();
    println!(
        "| metal | data | η (R, G, B) | k (R, G, B) | R(0°), ηi = 1 (R, G, B) | max \\|(a) − (b)\\|, ηi = {} | max \\|(a) − (b)\\|, ηi = {} |",
        COMPARISON_OUTSIDE_ETAS[0], COMPARISON_OUTSIDE_ETAS[1]
    );
    println!("|---|---|---|---|---|---|---|");
    for (metal, rows) in &report {
        let c = rgb_optical_constants(metal.spectrum())?;
        let r0 = c.reflectance(1.0, 1.0, 0.5)?;
        println!(
            "| {} | {} | {} | {} | {} | {} | {} |",
            metal.name(),
            metal.dataset(),
            triple(c.eta, 4),
            triple(c.k, 4),
            triple(r0, 4),
            max_difference(rows, COMPARISON_OUTSIDE_ETAS[0]),
            max_difference(rows, COMPARISON_OUTSIDE_ETAS[1]),
        );
    }
    Ok(())
}

fn file_report(paths: &[String]) -> Result<(), String> {
    println!("| file | η (R, G, B) | k (R, G, B) | R(0°) (a) | R(0°) (b) |");
    println!("|---|---|---|---|---|");
    for path in paths {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
        let s = Spectrum::from_csv(&text).map_err(|e| format!("{path}: {e}"))?;
        let c = rgb_optical_constants(&s).map_err(|e| e.to_string())?;
        let a = c.reflectance(1.0, 1.0, 0.5);
        let b = rgb_band_averaged_reflectance(&s, 1.0, 1.0, 0.5);
        let show = |r: Result<[f64; 3], SpectrumError>| match r {
            Ok(r) => triple(r, 4),
            Err(e) => format!("({e})"),
        };
        println!(
            "| {path} | {} | {} | {} | {} |",
            triple(c.eta, 4),
            triple(c.k, 4),
            show(a),
            show(b)
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = if args.is_empty() {
        builtin_report().map_err(|e| e.to_string())
    } else {
        file_report(&args)
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
