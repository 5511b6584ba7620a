//! Frames of successive sample seeds averaged, per pixel and channel, with each pixel's
//! standard error from the frames' spread: what `render --accumulate-until`, the report's
//! path-traced images and the path tracer's tests converge with.

/// Welford's running mean and sum of squared deviations of frames' HDR radiance.
#[derive(Clone, Debug, Default)]
pub struct FrameMean {
    mean: Vec<[f64; 3]>,
    deviations: Vec<[f64; 3]>,
    frames: u32,
}

impl FrameMean {
    /// No frame yet, for frames of `pixels` pixels.
    pub fn new(pixels: usize) -> Self {
        Self {
            mean: vec![[0.0; 3]; pixels],
            deviations: vec![[0.0; 3]; pixels],
            frames: 0,
        }
    }

    /// Adds a frame's HDR radiance (RGBA per pixel, its pixels in the same order).
    pub fn add(&mut self, hdr: &[[f32; 4]]) {
        self.frames += 1;
        let k = f64::from(self.frames);
        for ((mean, m2), p) in self.mean.iter_mut().zip(&mut self.deviations).zip(hdr) {
            for c in 0..3 {
                let x = f64::from(p[c]);
                let delta = x - mean[c];
                mean[c] += delta / k;
                m2[c] += delta * (x - mean[c]);
            }
        }
    }

    /// How many frames it averages.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Each pixel's mean radiance.
    pub fn mean(&self) -> &[[f64; 3]] {
        &self.mean
    }

    /// Each pixel's standard error of the mean, √(s² / k) per channel (k frames; 0
    /// before two frames).
    pub fn standard_errors(&self) -> Vec<[f64; 3]> {
        let k = f64::from(self.frames);
        self.deviations
            .iter()
            .map(|m2| {
                m2.map(|s| {
                    if self.frames < 2 {
                        0.0
                    } else {
                        (s / (k * (k - 1.0))).sqrt()
                    }
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean and standard error of 1, 2, 3, 4 (and of 2, 4, 6, 8): 2.5 and
    /// √(1.6667 / 4).
    #[test]
    fn the_mean_and_its_standard_error_by_hand() {
        let mut frames = FrameMean::new(2);
        for x in [1.0f32, 2.0, 3.0, 4.0] {
            frames.add(&[[x, x, x, 1.0], [2.0 * x, 0.0, 0.0, 1.0]]);
        }
        assert_eq!(frames.frames(), 4);
        assert_eq!(frames.mean()[0], [2.5; 3]);
        assert_eq!(frames.mean()[1], [5.0, 0.0, 0.0]);
        let e = frames.standard_errors();
        assert!(
            (e[0][0] - (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-12,
            "{e:?}"
        );
        assert!(
            (e[1][0] - 2.0 * (5.0f64 / 3.0 / 4.0).sqrt()).abs() < 1e-12,
            "{e:?}"
        );
        assert_eq!(e[1][1], 0.0);
    }
}
