//! Fuzzes the spectral-table parser (`wavelength_nm,n,k` CSV, as `plot spectrum --csv`
//! and `COMBUSTION_materials_optics` spectra read it) and the RGB band means computed
//! from whatever it accepts.

#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(spectrum) = combustion_spectra::Spectrum::from_csv(text) {
        let _ = combustion_spectra::rgb_optical_constants(&spectrum);
    }
});
