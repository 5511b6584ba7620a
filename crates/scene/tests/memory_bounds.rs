//! The memory bounds docs/gltf.md states ("Memory bounds"), held by measurement: each
//! case runs in a process of its own — the test runs its own binary again for that one
//! case — where the rise of the process's peak resident memory (VmHWM, reset through
//! /proc/self/clear_refs) over what it held just before is the case's alone, whatever
//! else the test runner does. Linux only, as the project's tests are.

use std::path::PathBuf;
use std::process::Command;

use combustion_scene::gltf::{import, ImportOptions};

use super::support::{peak_rise, placements, temp_dir as temp_dir_in, textured_triangle};

/// The environment variable naming the case a child process measures.
const CHILD: &str = "COMBUSTION_MEMORY_BOUND_CASE";

/// The rise of this process's peak resident memory while `work` runs, over its resident
/// memory just before, measured in a process of its own: in the test's own process
/// (`test`, its full name) `prepare` is not run and the rise comes back from a child
/// running this test alone; in that child, `prepare` builds the case's input and returns
/// the work measured, and the rise is printed for the parent (`None` there).
fn peak_rise_alone(test: &str, prepare: impl FnOnce() -> Box<dyn FnOnce()>) -> Option<u64> {
    if std::env::var(CHILD).as_deref() == Ok(test) {
        let work = prepare();
        let ((), rise) = peak_rise(work);
        // On a line of its own: the test runner's "test NAME ..." has no line break.
        println!("\npeak rise: {rise}");
        return None;
    }
    let output = Command::new(std::env::current_exe().unwrap())
        .args([test, "--exact", "--nocapture", "--test-threads", "1"])
        .env(CHILD, test)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{test} in its own process: {stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let rise = stdout
        .lines()
        .find_map(|l| l.strip_prefix("peak rise: "))
        .and_then(|n| n.parse::<u64>().ok());
    Some(rise.unwrap_or_else(|| panic!("{test}: no measurement in {stdout}")))
}

fn temp_dir(name: &str) -> PathBuf {
    temp_dir_in("memory-bounds", name)
}

/// Imports `path`, which must succeed, as measured work.
fn importing(path: PathBuf, options: ImportOptions) -> Box<dyn FnOnce()> {
    Box::new(move || {
        if let Err(e) = import(&path, &options) {
            panic!("{e}");
        }
    })
}

/// 1,448 nodes each placing a mesh of 1,448 primitives: 2,096,704 placements (near the
/// 2²¹ limit) from 66 KB of JSON, each at most 320 bytes while imported — the walk's
/// list (80 bytes a placement) beside the objects built from it (192). 911 MiB, 456
/// bytes each, while each placement held its own mesh key and instance transform.
#[test]
fn two_million_placements_take_at_most_320_bytes_each() {
    let side = 1448u64;
    let test = "memory_bounds::two_million_placements_take_at_most_320_bytes_each";
    let Some(rise) = peak_rise_alone(test, || {
        let dir = temp_dir("placements");
        let path = dir.join("placements.gltf");
        std::fs::write(&path, placements(side as usize)).unwrap();
        importing(path, ImportOptions::default())
    }) else {
        return;
    };
    let placements = side * side;
    assert!(
        rise <= 320 * placements,
        "{rise} bytes: {} a placement",
        rise / placements
    );
}

/// 200,000 nodes, each named and translated (9.8 MB of JSON), at most 750 bytes a node
/// while imported: the parsed tree, the node's motion node and the hierarchy walk.
#[test]
fn two_hundred_thousand_nodes_take_at_most_750_bytes_each() {
    let nodes = 200_000u64;
    let test = "memory_bounds::two_hundred_thousand_nodes_take_at_most_750_bytes_each";
    let Some(rise) = peak_rise_alone(test, || {
        let dir = temp_dir("nodes");
        let path = dir.join("nodes.gltf");
        let roots: Vec<String> = (0..nodes).map(|i| i.to_string()).collect();
        let listed: Vec<String> = (0..nodes)
            .map(|i| format!(r#"{{"name":"n{i}","translation":[{i},0,0]}}"#))
            .collect();
        let json = format!(
            r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[{}]}}],"nodes":[{}]}}"#,
            roots.join(","),
            listed.join(",")
        );
        std::fs::write(&path, json).unwrap();
        importing(path, ImportOptions::default())
    }) else {
        return;
    };
    assert!(rise <= 750 * nodes, "{rise} bytes: {} a node", rise / nodes);
}

/// A progressive 4:4:4 JPEG of 2048×2048 pixels decodes within what the budget charges
/// for it before decoding (18 bytes a pixel: its planes, every DCT coefficient, the rows
/// queued to the decoder's threads and the RGB output) and its file's bytes: the charge
/// is a bound on the decode, not a guess. Beside the pixels' 12 bytes the process also
/// spends a few megabytes of its own on the decoder's threads, which an image of 1024²
/// left too little room for under a loaded machine (19.1 MB against 18.9 charged); at
/// 2048² the charge is 72 MiB.
#[test]
fn a_progressive_jpeg_decodes_within_its_charge() {
    let test = "memory_bounds::a_progressive_jpeg_decodes_within_its_charge";
    let image = include_bytes!("data/flat-2048-progressive-444.jpg");
    let Some(rise) = peak_rise_alone(test, || {
        let dir = temp_dir("progressive");
        std::fs::write(dir.join("texture.jpg"), image).unwrap();
        let path = dir.join("textured.gltf");
        std::fs::write(&path, textured_triangle("texture.jpg")).unwrap();
        importing(path, ImportOptions::default())
    }) else {
        return;
    };
    let charge = 18 * 2048 * 2048;
    let file = image.len() as u64;
    assert!(
        rise <= charge + file,
        "{rise} bytes against a charge of {charge} and a file of {file}"
    );
}

/// A spectral table of `rows` rows of wavelength, n, k (about 28 bytes a row).
fn spectral_table(rows: u64) -> String {
    let mut csv = String::from("wavelength_nm,n,k\n");
    for i in 0..rows {
        let wavelength = 400.0 + 400.0 * i as f64 / rows as f64;
        csv += &format!("{wavelength:.6},{:.6},3.000000\n", 0.2 + 1e-6 * i as f64);
    }
    csv
}

/// A spectral table of 200,000 rows parses within the text once more and 64 bytes a row
/// (a sample and its line, 32 bytes, in vectors grown by doubling). 9.3× the text while
/// every record's fields were collected before the first was read.
#[test]
fn a_long_spectral_table_parses_within_its_bound() {
    let rows = 200_000u64;
    let test = "memory_bounds::a_long_spectral_table_parses_within_its_bound";
    let Some(rise) = peak_rise_alone(test, || {
        let csv = spectral_table(rows);
        Box::new(move || {
            combustion_spectra::Spectrum::from_csv(&csv).unwrap();
        })
    }) else {
        return;
    };
    let text = spectral_table(rows).len() as u64;
    assert!(
        rise <= text + 64 * rows,
        "{rise} bytes for {text} bytes of text"
    );
}
