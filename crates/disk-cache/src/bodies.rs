//! What each kind of entry's body must be, checked when it is read: an entry that
//! passes the cache's own checks (magic, key, checksum) may still have been forged or
//! written by something else, and a body that is not what its kind holds is a miss,
//! never a wrong result or an error that blames the input.

/// SPIR-V's magic number, the first word of every module.
pub const SPIRV_MAGIC: u32 = 0x0723_0203;

/// The words of a SPIR-V body: a whole number of little-endian words, at least one, the
/// first SPIR-V's magic number; else `None`.
pub fn spirv_words(body: &[u8]) -> Option<Vec<u32>> {
    if body.len() < 4 || body.len() % 4 != 0 {
        return None;
    }
    let words: Vec<u32> = body
        .chunks_exact(4)
        .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
        .collect();
    (words.first() == Some(&SPIRV_MAGIC)).then_some(words)
}

/// Whether `body` is baked radiance: exactly `bytes` long, RGBA texels of little-endian
/// f32s, each colour channel between 0 and `max_radiance` and each alpha finite (a
/// forged entry of NaN texels would otherwise light every frame with them).
pub fn is_radiance(body: &[u8], bytes: u64, max_radiance: f32) -> bool {
    body.len() as u64 == bytes
        && body.len() % 16 == 0
        && body.chunks_exact(16).all(|texel| {
            let value =
                |i: usize| f32::from_le_bytes([texel[i], texel[i + 1], texel[i + 2], texel[i + 3]]);
            (0..3).all(|c| (0.0..=max_radiance).contains(&value(4 * c))) && value(12).is_finite()
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spirv_bodies_are_whole_words_from_the_magic() {
        let module: Vec<u8> = [SPIRV_MAGIC, 0x0001_0000, 7]
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect();
        assert_eq!(
            spirv_words(&module),
            Some(vec![SPIRV_MAGIC, 0x0001_0000, 7])
        );
        assert_eq!(spirv_words(&module[..11]), None, "a part of a word");
        assert_eq!(spirv_words(&[]), None);
        assert_eq!(spirv_words(&module[4..]), None, "no magic");
    }

    #[test]
    fn radiance_bodies_are_finite_texels_of_their_size() {
        let texels =
            |values: [f32; 8]| -> Vec<u8> { values.iter().flat_map(|v| v.to_le_bytes()).collect() };
        let good = texels([0.0, 1.0, 2.0, 1.0, 3.0, 0.5, 0.0, 1.0]);
        assert!(is_radiance(&good, 32, 1e6));
        assert!(!is_radiance(&good, 48, 1e6), "another size");
        assert!(!is_radiance(&good[..31], 31, 1e6), "a part of a texel");
        for bad in [f32::NAN, f32::INFINITY, -1.0, 2e6] {
            let forged = texels([0.0, bad, 2.0, 1.0, 3.0, 0.5, 0.0, 1.0]);
            assert!(!is_radiance(&forged, 32, 1e6), "{bad}");
        }
        let nan_alpha = texels([0.0, 1.0, 2.0, f32::NAN, 3.0, 0.5, 0.0, 1.0]);
        assert!(!is_radiance(&nan_alpha, 32, 1e6));
    }
}
