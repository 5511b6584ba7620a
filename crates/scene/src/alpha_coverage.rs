//! Coverage-preserving alpha for cut-outs (glTF alphaMode MASK) on coarse mip levels:
//! averaging a thin cut-out's alpha in the mip chain pushes it below the cutoff, and it
//! vanishes in the distance. I. Castaño ("Computing Alpha Mipmaps", 2010) scales each
//! level's alpha so that the share of its texels at or above the cutoff is level 0's;
//! [`alpha_mip_scales`] computes those scales, which a renderer multiplies into the alpha
//! it samples from each level. An alpha ramp averages to itself, so its scales are 1
//! and its cuts stay where the cutoff says; a fence of bars keeps its share of texels.

use crate::Image;

/// Mip levels [`alpha_mip_scales`] covers at most (a 32768² image's chain has 16).
pub const ALPHA_MIP_LEVELS: usize = 16;

/// The alpha scale of each mip level of `image` (level 0 first, 1.0) that keeps the share
/// of texels whose alpha × `alpha_factor` × the scale reaches `cutoff` at level 0's
/// share (the threshold halfway between the texels kept and the next smaller value;
/// where a level's texels cannot be split, ties are kept: at least one texel of a
/// level passes when any of level 0 does, so the cut-out does not vanish). The levels are
/// those a linear blit makes (each ⌊w/2⌋ × ⌊h/2⌋, at least 1: every texel the bilinear
/// filter of the level above at its own centre, clamped at the edges, rounded to 8
/// bits), at most [`ALPHA_MIP_LEVELS`] of them; a level whose alpha is zero everywhere
/// gets 1.
pub fn alpha_mip_scales(image: &Image, alpha_factor: f32, cutoff: f32) -> Vec<f32> {
    let (mut width, mut height) = (image.width as usize, image.height as usize);
    let mut level: Vec<f32> = image
        .pixels
        .chunks_exact(4)
        .map(|p| f32::from(p[3]) / 255.0)
        .collect();
    if level.len() != width * height || level.is_empty() {
        return vec![1.0];
    }
    let passes = |alpha: &[f32], scale: f32| {
        alpha
            .iter()
            .filter(|&&a| a * alpha_factor * scale >= cutoff)
            .count()
    };
    let share = passes(&level, 1.0) as f64 / level.len() as f64;
    let mut scales = vec![1.0f32];
    while (width > 1 || height > 1) && scales.len() < ALPHA_MIP_LEVELS {
        let (w, h) = ((width / 2).max(1), (height / 2).max(1));
        level = reduce(&level, (width, height), (w, h));
        (width, height) = (w, h);
        scales.push(keeping_scale(&level, alpha_factor, cutoff, share));
    }
    scales
}

/// The scale that lets `round(share · n)` texels of `alpha` (at least one when `share`
/// is above 0) reach `cutoff`: the threshold it puts on the level's alpha (cutoff ÷ scale
/// ÷ factor) lies halfway between the smallest alpha kept and the next smaller value
/// (0 if there is none), so a cut between two texels moves as little as it can, and the
/// texels tied with the smallest one kept pass too, with the same margin (a threshold at
/// a texel's own value would let the filter's blend with any lower neighbour drop below
/// it everywhere but at the texel's centre).
fn keeping_scale(alpha: &[f32], alpha_factor: f32, cutoff: f32, share: f64) -> f32 {
    let wanted = (share * alpha.len() as f64).round() as usize;
    let wanted = if share > 0.0 { wanted.max(1) } else { 0 };
    if wanted == 0 || alpha_factor <= 0.0 {
        return 1.0;
    }
    let mut sorted = alpha.to_vec();
    sorted.sort_unstable_by(|a, b| b.total_cmp(a));
    let wanted = wanted.min(sorted.len());
    // The smallest alpha that must pass; a zero one cannot, so the last positive.
    let Some(last) = sorted[..wanted].iter().rposition(|&a| a > 0.0) else {
        return 1.0;
    };
    let kept = sorted[last];
    let next = sorted[last..]
        .iter()
        .copied()
        .find(|&a| a < kept)
        .unwrap_or(0.0);
    cutoff / (0.5 * (kept + next) * alpha_factor)
}

/// One 2:1 reduction of an alpha level as a linear blit makes it (see
/// [`alpha_mip_scales`]).
fn reduce(above: &[f32], (width, height): (usize, usize), (w, h): (usize, usize)) -> Vec<f32> {
    let (sx, sy) = (width as f32 / w as f32, height as f32 / h as f32);
    let at = |x: isize, y: isize| {
        let x = x.clamp(0, width as isize - 1) as usize;
        let y = y.clamp(0, height as isize - 1) as usize;
        above[y * width + x]
    };
    let mut out = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            // The bilinear filter at the texel's centre, in the level above's texels.
            let (u, v) = ((x as f32 + 0.5) * sx - 0.5, (y as f32 + 0.5) * sy - 0.5);
            let (x0, y0) = (u.floor(), v.floor());
            let (fx, fy) = (u - x0, v - y0);
            let (x0, y0) = (x0 as isize, y0 as isize);
            let value = (1.0 - fy) * ((1.0 - fx) * at(x0, y0) + fx * at(x0 + 1, y0))
                + fy * ((1.0 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
            out.push((value * 255.0).round() / 255.0);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ColorSpace;

    fn image(side: u32, alpha: impl Fn(u32, u32) -> u8) -> Image {
        Image {
            name: "alpha".into(),
            width: side,
            height: side,
            color_space: ColorSpace::Srgb,
            pixels: (0..side)
                .flat_map(|y| (0..side).map(move |x| (x, y)))
                .flat_map(|(x, y)| [0, 0, 0, alpha(x, y)])
                .collect(),
        }
    }

    /// A ramp averages to itself: every level's scale down to 2×2 is 1 within the 8-bit
    /// steps, so its cuts stay put.
    #[test]
    fn a_ramp_keeps_a_scale_of_one() {
        let ramp = image(64, |_, y| {
            ((f64::from(y) + 0.5) / 64.0 * 255.0).round() as u8
        });
        let scales = alpha_mip_scales(&ramp, 1.0, 0.5);
        assert_eq!(scales.len(), 7);
        for (level, s) in scales[..6].iter().enumerate() {
            assert!((s - 1.0).abs() < 0.02, "level {level}: {s}");
        }
        // The 1×1 level (the mean, 0.5) cannot be cut; it is kept, halfway above 0.
        assert!((scales[6] * 0.5 - 1.0).abs() < 0.02, "{scales:?}");
    }

    /// Bars of 3 texels in 8: level 3 averages to 0.375 everywhere (code 96), below the
    /// cutoff of 0.5; its scale lifts it to twice the cutoff, the threshold halfway to 0
    /// (every texel passes: a uniform level cannot keep 3/8 of its texels, and vanishing
    /// is the worse choice).
    #[test]
    fn a_fence_is_kept_on_every_level() {
        let fence = image(64, |x, _| if x % 8 < 3 { 255 } else { 0 });
        let scales = alpha_mip_scales(&fence, 1.0, 0.5);
        let level_3 = 96.0 / 255.0;
        assert!((scales[3] * level_3 - 1.0).abs() < 1e-5, "{scales:?}");
        for (level, &s) in scales.iter().enumerate() {
            assert!(s.is_finite() && s > 0.0, "level {level}: {s}");
        }
        // The factor is part of the product: half the factor, twice the scale.
        let halved = alpha_mip_scales(&fence, 0.5, 0.5);
        assert!((halved[3] - scales[3] * 2.0).abs() < 1e-4, "{halved:?}");
    }

    /// Nothing to keep: no texel reaches the cutoff at level 0, or the image is
    /// transparent everywhere; every scale is 1.
    #[test]
    fn nothing_to_keep_leaves_the_alpha_alone() {
        for (img, cutoff) in [(image(16, |_, _| 100), 0.5), (image(16, |_, _| 0), 0.5)] {
            assert!(alpha_mip_scales(&img, 1.0, cutoff)
                .iter()
                .all(|&s| s == 1.0));
        }
    }
}
