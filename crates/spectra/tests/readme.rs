//! assets/spectra/README.md must match what the code computes (regenerate it with
//! `cargo run -p combustion-spectra --example spectra_report` when this fails).

use combustion_spectra::{rgb_optical_constants, BuiltinDielectric, BuiltinMetal};

const README: &str = include_str!("../../../assets/spectra/README.md");

fn triple(v: [f64; 3], decimals: usize) -> String {
    format!("{:.d$}, {:.d$}, {:.d$}", v[0], v[1], v[2], d = decimals)
}

#[test]
fn readme_summary_matches_the_code() {
    let summary = README
        .rsplit_once("### Summary per metal")
        .expect("README has the summary table")
        .1;
    for metal in BuiltinMetal::ALL {
        let c = rgb_optical_constants(metal.spectrum()).unwrap();
        let r0 = c.reflectance(1.0, 1.0, 0.5).unwrap();
        let row = format!(
            "| {} | {} | {} | {} | {} |",
            metal.name(),
            metal.dataset(),
            triple(c.eta, 4),
            triple(c.k, 4),
            triple(r0, 4)
        );
        assert!(summary.contains(&row), "README is stale: missing `{row}`");
    }
    for dielectric in BuiltinDielectric::ALL {
        let c = rgb_optical_constants(dielectric.spectrum()).unwrap();
        let row = format!("| {} | {} |", dielectric.dataset(), triple(c.eta, 5));
        assert!(README.contains(&row), "README is stale: missing `{row}`");
    }
}

#[test]
fn readme_lists_every_embedded_file() {
    for csv in BuiltinMetal::ALL
        .map(|m| m.csv())
        .into_iter()
        .chain(BuiltinDielectric::ALL.map(|d| d.csv()))
    {
        // The database path in the file header appears in the README's file table.
        let path = csv
            .lines()
            .find_map(|l| l.split("file database/data/").nth(1))
            .expect("header names the database file");
        assert!(README.contains(path), "README does not list {path}");
    }
}
