//! What the `diff_images` fuzz target does with one input (shared with the test that
//! replays its corpus, crates/diff/tests/fuzz_corpus.rs): `diff`'s and batch goldens'
//! image readers and the comparison.
//!
//! The first byte's low bits say whether each of two images is an OpenEXR file (else a
//! PNG); the next two bytes (little-endian) the first image's length, the rest the
//! second's. Each is read header first (`ImageFile::from_bytes`: its size checked
//! before a pixel is decoded) and decoded; an image read must hold the pixels its
//! header said, within the budget; two read images are compared (their sizes or kinds
//! may differ: an error then), and each with itself, which must not differ at all.

#![allow(dead_code)] // the replay test and the target use parts of it

use combustion_diff::{compare, DiffImage, ImageFile, Pixels, MAX_PIXELS};

/// Reads one image: `None` where it is refused.
fn read(bytes: &[u8], radiance: bool) -> Option<DiffImage> {
    let file = ImageFile::from_bytes(bytes.to_vec(), radiance).ok()?;
    let (width, height) = (file.width, file.height);
    assert!(width >= 1 && height >= 1);
    assert!(u64::from(width) * u64::from(height) <= MAX_PIXELS);
    let image = file.decode().ok()?;
    assert_eq!(
        (image.width, image.height),
        (width, height),
        "the decoded size is the header's"
    );
    let pixels = match &image.pixels {
        Pixels::Display(p) => {
            assert!(!radiance);
            p.len()
        }
        Pixels::Radiance(p) => {
            assert!(radiance);
            p.len()
        }
    };
    assert_eq!(pixels as u64, u64::from(width) * u64::from(height));
    Some(image)
}

/// Checks a comparison's figures against what they are.
fn check(a: &DiffImage, b: &DiffImage) {
    let Ok(comparison) = compare(a, b) else {
        assert!(
            (a.width, a.height) != (b.width, b.height)
                || matches!(
                    (&a.pixels, &b.pixels),
                    (Pixels::Display(_), Pixels::Radiance(_))
                        | (Pixels::Radiance(_), Pixels::Display(_))
                ),
            "images of one size and kind compare"
        );
        return;
    };
    let pixels = (a.width * a.height) as usize;
    assert_eq!(comparison.channel_diff.len(), pixels);
    assert_eq!(comparison.flip.len(), pixels);
    assert!(comparison.channel_diff.iter().all(|&d| d >= 0.0));
    assert!(comparison.flip.iter().all(|f| (0.0..=1.0).contains(f)));
    let mean = comparison.mean_flip();
    assert!((0.0..=1.0).contains(&mean), "mean FLIP {mean}");
    let share = comparison.share_above(0.0);
    assert!((0.0..=1.0).contains(&share));
    assert_eq!(combustion_diff::heat_map(&comparison).len(), pixels);
}

/// Runs one input.
pub fn read_and_compare(data: &[u8]) {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let Some((length, rest)) = rest.split_first_chunk::<2>() else {
        return;
    };
    let split = usize::from(u16::from_le_bytes(*length)).min(rest.len());
    let (first, second) = rest.split_at(split);
    let a = read(first, flags & 1 != 0);
    let b = read(second, flags & 2 != 0);
    for image in a.iter().chain(&b) {
        let itself = compare(image, image).expect("an image compares with itself");
        assert_eq!(
            itself.max_channel_diff(),
            0.0,
            "an image differs from itself"
        );
        assert_eq!(itself.mean_flip(), 0.0, "an image differs from itself");
    }
    if let (Some(a), Some(b)) = (&a, &b) {
        check(a, b);
    }
}
