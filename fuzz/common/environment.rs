//! What the `environment_image` fuzz target does with one input, shared with the test that
//! replays the committed corpus (crates/scene/tests/fuzz_corpus.rs).

use combustion_scene::{EnvironmentFormat, EnvironmentImage};

/// The environment image readers (`--environment FILE`): the input's first byte picks the
/// format (even: Radiance `.hdr`, odd: OpenEXR), the rest is the file. An accepted image
/// holds width × height texels, each within the radiance bound, and its environment
/// lookups stay finite.
pub fn decode(data: &[u8]) {
    let Some((&selector, file)) = data.split_first() else {
        return;
    };
    let format = if selector % 2 == 0 {
        EnvironmentFormat::RadianceHdr
    } else {
        EnvironmentFormat::OpenExr
    };
    if let Ok(image) = EnvironmentImage::from_bytes(file, format, "fuzz input") {
        assert!(image.width >= 1 && image.height >= 1);
        assert_eq!(
            image.texels.len(),
            image.width as usize * image.height as usize
        );
        assert!(image
            .texels
            .iter()
            .flatten()
            .all(|c| c.is_finite() && (0.0..=combustion_scene::MAX_RADIANCE).contains(c)));
    }
}
