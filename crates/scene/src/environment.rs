//! Light arriving from infinitely far away in every direction: the environment a scene
//! is lit by besides its lights. Radiance L(ω) in W·sr⁻¹·m⁻² per RGB channel, ω the
//! direction the light comes *from* (world space, y up).
//!
//! The radiance functions here are the definition: the renderer's cube-map bake
//! evaluates the same formula in GLSL (`shaders/include/environment.glsl`), and the f64
//! environment oracle (`combustion_renderer::reference`) integrates against these.

use crate::SceneError;

/// The studio environment's sky colour at the zenith (W·sr⁻¹·m⁻²).
pub const STUDIO_SKY: [f64; 3] = [0.60, 0.70, 0.85];
/// The studio environment's ground colour at the nadir.
pub const STUDIO_GROUND: [f64; 3] = [0.25, 0.22, 0.20];
/// The studio's soft boxes: (direction towards the box, peak radiance, exponent p of
/// the max(0, ω·k)^p falloff). A key above front left, a cooler rim behind right.
pub const STUDIO_BOXES: [([f64; 3], [f64; 3], f64); 2] = [
    ([-0.5, 0.8, 0.6], [6.0, 5.6, 5.0], 24.0),
    ([0.7, 0.3, -0.6], [2.0, 2.4, 3.0], 12.0),
];

/// Where an environment's radiance comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Environment {
    /// The same radiance from every direction (a "white furnace" when 1, 1, 1).
    Uniform([f32; 3]),
    /// The built-in studio, an analytic radiance ([`Environment::radiance`]): a sky-to-
    /// ground gradient linear in ω_y plus two soft boxes,
    /// L(ω) = G + (S − G)(1 + ω_y)/2 + Σ_i B_i max(0, ω·k_i)^p_i
    /// with S = [`STUDIO_SKY`], G = [`STUDIO_GROUND`], (k_i, B_i, p_i) = [`STUDIO_BOXES`]
    /// (k_i normalised). Smooth everywhere, so a cube map of it has no aliasing to hide.
    Studio,
}

impl Environment {
    /// L(ω) in f64 for `direction` (need not be unit length; zero gives the gradient's
    /// middle).
    pub fn radiance(&self, direction: [f64; 3]) -> [f64; 3] {
        match self {
            Environment::Uniform(l) => l.map(f64::from),
            Environment::Studio => studio_radiance(direction),
        }
    }

    /// Every radiance finite and ≥ 0.
    pub fn validate(&self) -> Result<(), SceneError> {
        match self {
            Environment::Uniform(l) if !l.iter().all(|&x| x.is_finite() && x >= 0.0) => {
                Err(SceneError::Invalid(format!(
                    "uniform environment radiance {l:?} must be finite and ≥ 0"
                )))
            }
            _ => Ok(()),
        }
    }

    /// A short name for logs and panels.
    pub fn name(&self) -> String {
        match self {
            Environment::Uniform(l) => format!("uniform {},{},{}", l[0], l[1], l[2]),
            Environment::Studio => "studio".into(),
        }
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if len > 0.0 {
        v.map(|c| c / len)
    } else {
        [0.0; 3]
    }
}

/// The studio's radiance ([`Environment::Studio`]).
pub fn studio_radiance(direction: [f64; 3]) -> [f64; 3] {
    let d = unit(direction);
    let up = 0.5 * (1.0 + d[1]);
    let mut l = [0.0; 3];
    for (c, out) in l.iter_mut().enumerate() {
        *out = STUDIO_GROUND[c] + (STUDIO_SKY[c] - STUDIO_GROUND[c]) * up;
    }
    for (towards, peak, exponent) in STUDIO_BOXES {
        let k = unit(towards);
        let cos = d[0] * k[0] + d[1] * k[1] + d[2] * k[2];
        if cos > 0.0 {
            let w = cos.powf(exponent);
            for c in 0..3 {
                l[c] += peak[c] * w;
            }
        }
    }
    l
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn studio_is_the_gradient_away_from_the_boxes_and_peaks_at_them() {
        // Straight down: the ground; no box reaches below the horizon there.
        assert_eq!(studio_radiance([0.0, -1.0, 0.0]), STUDIO_GROUND);
        let k = unit(STUDIO_BOXES[0].0);
        let at_key = studio_radiance(k);
        let up = 0.5 * (1.0 + k[1]);
        let other = {
            let k2 = unit(STUDIO_BOXES[1].0);
            (k[0] * k2[0] + k[1] * k2[1] + k[2] * k2[2]).max(0.0)
        };
        for c in 0..3 {
            let gradient = STUDIO_GROUND[c] + (STUDIO_SKY[c] - STUDIO_GROUND[c]) * up;
            let expected =
                gradient + STUDIO_BOXES[0].1[c] + STUDIO_BOXES[1].1[c] * other.powf(12.0);
            assert!((at_key[c] - expected).abs() < 1e-12);
        }
    }

    #[test]
    fn negative_or_nan_uniform_radiance_is_refused() {
        assert!(Environment::Uniform([1.0, -1.0, 0.0]).validate().is_err());
        assert!(Environment::Uniform([f32::NAN, 1.0, 0.0])
            .validate()
            .is_err());
        assert!(Environment::Uniform([0.0, 2.0, 1.0]).validate().is_ok());
        assert!(Environment::Studio.validate().is_ok());
    }
}
