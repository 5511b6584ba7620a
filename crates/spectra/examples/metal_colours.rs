//! The built-in metals' colours by the band method and colorimetrically (docs/metal-colours.md), and the time the colorimetric fit of all nine takes:
//! `cargo run -p combustion-spectra --example metal_colours`.

fn main() {
    let t = std::time::Instant::now();
    for metal in combustion_spectra::BuiltinMetal::ALL {
        combustion_spectra::colorimetric_optical_constants(metal.spectrum()).unwrap();
    }
    eprintln!("fit of 9 metals: {:.1} ms", t.elapsed().as_secs_f64() * 1e3);
    print!("{}", combustion_spectra::metal_colour_table().unwrap());
}
