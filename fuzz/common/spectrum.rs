//! What the `spectrum_csv` fuzz target does with one input, shared with the test that
//! replays the committed corpus (crates/spectra/tests/fuzz_corpus.rs).

/// The spectral-table parser (`wavelength_nm,n,k` CSV, as `plot spectrum --csv` and
/// `COMBUSTION_materials_optics` spectra read it) and the RGB band means of whatever it
/// accepts.
pub fn parse_and_reduce(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(spectrum) = combustion_spectra::Spectrum::from_csv(text) {
        let _ = combustion_spectra::rgb_optical_constants(&spectrum);
    }
}
