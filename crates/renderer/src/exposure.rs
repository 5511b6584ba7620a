//! Exposure: the factor the output pass multiplies radiance by before the tone curve,
//! given by hand, by a physical camera ([`PhysicalCamera`]: aperture, shutter time, ISO),
//! or metered from the frame itself ([`AutoExposure`], the `auto exposure` passes).
//!
//! Units. The renderer's radiance is in W·sr⁻¹·m⁻² per linear sRGB channel. glTF's lights
//! are photometric (candela, lux) and are read 1 cd → 1 W/sr (docs/gltf.md), so the
//! luminance of a radiance (R, G, B) is read as Y = 0.2126 R + 0.7152 G + 0.0722 B in
//! cd·m⁻² (one lumen per watt: no luminous efficacy is applied either way).
//!
//! The photometric relations (ISO 2720, ISO 12232):
//! - exposure value at ISO 100: EV100 = log2(N² / t) − log2(S / 100) for f-number N,
//!   shutter time t in seconds and sensitivity S;
//! - the exposure factor by saturation-based sensitivity: the luminance that just
//!   saturates the sensor is L_max = 78 / (S·q) · N² / t = 1.2 · 2^EV100 cd·m⁻² (lens
//!   transmission q = 0.65), and the factor is 1 / L_max ([`exposure_of_ev100`]);
//! - metering by a reflected-light meter: EV100 = log2(L̄ · 100 / K) with the meter's
//!   calibration K = 12.5 cd·s·m⁻², L̄ the scene's average luminance.

use crate::error::RenderError;
use combustion_optics::readable;

/// Bins of the metering histogram of log2 luminance.
pub const HISTOGRAM_BINS: usize = 256;

/// The log2 luminances (cd·m⁻²) the histogram spans: 2⁻¹⁶ to 2²⁴ (1.5e-5 to 1.7e7), in
/// bins of 0.156 EV. Darker pixels count in the first bin, brighter ones (and
/// infinities) in the last; black ones (luminance 0: no surface under a black
/// background, unlit) and NaN are not counted.
pub const METERED_LOG2_LUMINANCE: [f32; 2] = [-16.0, 24.0];

/// The reflected-light meter's calibration constant K (cd·s·m⁻²).
pub const METER_CALIBRATION: f32 = 12.5;

/// The exposure factor of an exposure value at ISO 100: 1 / (1.2 · 2^EV100).
pub fn exposure_of_ev100(ev100: f32) -> f32 {
    1.0 / (1.2 * ev100.exp2())
}

/// The exposure value at ISO 100 of an exposure factor (the inverse of
/// [`exposure_of_ev100`]).
pub fn ev100_of_exposure(exposure: f32) -> f32 {
    -(1.2 * exposure).log2()
}

/// The exposure value at ISO 100 a reflected-light meter gives for an average luminance
/// (cd·m⁻²): log2(L̄ · 100 / K).
pub fn metered_ev100(average_luminance: f32) -> f32 {
    (average_luminance * 100.0 / METER_CALIBRATION).log2()
}

/// A camera's exposure settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhysicalCamera {
    /// The aperture's f-number N (0.5 to 128).
    pub f_number: f32,
    /// The shutter time in seconds (1e-6 to 3600).
    pub shutter_seconds: f32,
    /// The sensitivity, ISO S (1 to 1e6).
    pub iso: f32,
}

impl PhysicalCamera {
    /// The f-numbers taken.
    pub const F_NUMBERS: [f32; 2] = [0.5, 128.0];
    /// The shutter times taken, in seconds.
    pub const SHUTTER_SECONDS: [f32; 2] = [1e-6, 3600.0];
    /// The sensitivities taken.
    pub const ISOS: [f32; 2] = [1.0, 1e6];

    /// Its exposure value at ISO 100: log2(N²/t) − log2(S/100).
    pub fn ev100(&self) -> f32 {
        (self.f_number * self.f_number / self.shutter_seconds).log2() - (self.iso / 100.0).log2()
    }

    /// Its exposure factor ([`exposure_of_ev100`] of [`PhysicalCamera::ev100`]).
    pub fn exposure(&self) -> f32 {
        exposure_of_ev100(self.ev100())
    }

    /// Checks each setting against its range.
    ///
    /// # Errors
    /// [`RenderError::InvalidExposureSettings`] naming the first setting out of range.
    pub fn validate(&self) -> Result<(), RenderError> {
        within("aperture f-number", self.f_number, Self::F_NUMBERS)?;
        within("shutter time", self.shutter_seconds, Self::SHUTTER_SECONDS)?;
        within("ISO", self.iso, Self::ISOS)
    }
}

/// Exposure metered from the frame's own radiance (the `auto exposure` passes): a
/// histogram of the HDR image's log2 luminance ([`METERED_LOG2_LUMINANCE`]), the mean log
/// luminance of the pixels between two percentiles of it, the reflected-light meter's
/// exposure value for that mean ([`metered_ev100`]) less the compensation, reached at
/// once or at a limited speed. The factor replaces [`crate::FrameInputs::exposure`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutoExposure {
    /// Stops added to the metered exposure (positive: brighter), −16 to 16.
    pub compensation: f32,
    /// The share of the counted pixels, darkest first, whose mean is metered: from
    /// `window[0]` to `window[1]` (0 ≤ low < high ≤ 1; by default 0.1 to 0.9, so that
    /// neither the darkest nor the brightest tenth moves it).
    pub window: [f32; 2],
    /// How fast the exposure rises towards a darker scene's, in EV per second (0.01 to
    /// 1000; 1 by default).
    pub rise_per_second: f32,
    /// How fast it falls towards a brighter scene's, in EV per second (0.01 to 1000; 3
    /// by default: eyes and cameras follow light faster than dark).
    pub fall_per_second: f32,
    /// The time since the previous frame of the renderer, in seconds, which the speeds
    /// apply over; `None` (still renders, and any first frame) takes the metered exposure
    /// of this frame at once, so that a headless frame is exposed by its own radiance
    /// alone, the same for the same frame.
    pub elapsed_seconds: Option<f32>,
}

impl Default for AutoExposure {
    fn default() -> Self {
        Self {
            compensation: 0.0,
            window: [0.1, 0.9],
            rise_per_second: 1.0,
            fall_per_second: 3.0,
            elapsed_seconds: None,
        }
    }
}

impl AutoExposure {
    /// The compensations taken, in EV.
    pub const COMPENSATION: [f32; 2] = [-16.0, 16.0];
    /// The adaptation speeds taken, in EV per second.
    pub const SPEEDS: [f32; 2] = [0.01, 1000.0];

    /// Checks each setting against its range.
    ///
    /// # Errors
    /// [`RenderError::InvalidExposureSettings`] naming the first setting out of range.
    pub fn validate(&self) -> Result<(), RenderError> {
        within(
            "exposure compensation",
            self.compensation,
            Self::COMPENSATION,
        )?;
        let [low, high] = self.window;
        within("metering window's low end", low, [0.0, 1.0])?;
        within("metering window's high end", high, [0.0, 1.0])?;
        if low >= high {
            return Err(RenderError::InvalidExposureSettings(format!(
                "the metering window's low end {} must be below its high end {}",
                readable(low),
                readable(high)
            )));
        }
        within("exposure rise speed", self.rise_per_second, Self::SPEEDS)?;
        within("exposure fall speed", self.fall_per_second, Self::SPEEDS)?;
        if let Some(elapsed) = self.elapsed_seconds {
            within("time since the previous frame", elapsed, [0.0, 3600.0])?;
        }
        Ok(())
    }
}

/// `value` within `range` (inclusive), else the error naming `what`.
fn within(what: &str, value: f32, [low, high]: [f32; 2]) -> Result<(), RenderError> {
    if value.is_finite() && (low..=high).contains(&value) {
        return Ok(());
    }
    Err(RenderError::InvalidExposureSettings(format!(
        "{what} {} must be between {} and {}",
        readable(value),
        readable(low),
        readable(high)
    )))
}

/// What the auto exposure of a completed frame metered and used
/// ([`crate::Renderer::last_metered_exposure`]).
#[derive(Clone, Debug, PartialEq)]
pub struct MeteredExposure {
    /// The factor the frame's output was exposed by.
    pub exposure: f32,
    /// Its exposure value at ISO 100 ([`ev100_of_exposure`]).
    pub ev100: f32,
    /// The exposure value the frame's radiance metered (the frame's own, before any
    /// adaptation limited the step to it), the compensation applied.
    pub target_ev100: f32,
    /// The pixels counted (those of luminance above 0; NaN never).
    pub counted: u32,
    /// The histogram: pixels per bin of log2 luminance ([`HISTOGRAM_BINS`] bins over
    /// [`METERED_LOG2_LUMINANCE`]).
    pub histogram: Vec<u32>,
}

impl MeteredExposure {
    /// The bytes the GPU writes (the adaptation pass's state): exposure, EV100, target
    /// EV100, counted pixels, then the histogram.
    pub(crate) const BYTES: u64 = 16 + 4 * HISTOGRAM_BINS as u64;

    /// Reads the GPU's state (`BYTES` bytes).
    pub(crate) fn from_bytes(bytes: &[u8]) -> Self {
        let words: Vec<u32> = bytes
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")))
            .collect();
        Self {
            exposure: f32::from_bits(words[0]),
            ev100: f32::from_bits(words[1]),
            target_ev100: f32::from_bits(words[2]),
            counted: words[3],
            histogram: words[4..4 + HISTOGRAM_BINS].to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sunny-16 rule: f/16 at 1/100 s and ISO 100 is EV100 log2(25,600) = 14.64;
    /// doubling the ISO is one stop less; the factor and EV100 invert each other.
    #[test]
    fn photometric_relations() {
        let sunny = PhysicalCamera {
            f_number: 16.0,
            shutter_seconds: 0.01,
            iso: 100.0,
        };
        assert!((sunny.ev100() - 25_600f32.log2()).abs() < 1e-5);
        let faster_film = PhysicalCamera {
            iso: 200.0,
            ..sunny
        };
        assert!((sunny.ev100() - faster_film.ev100() - 1.0).abs() < 1e-5);
        assert!((ev100_of_exposure(sunny.exposure()) - sunny.ev100()).abs() < 1e-4);
        // A meter reading L̄ = K/100 · 2^EV: EV100 0 at 0.125 cd/m².
        assert!(metered_ev100(0.125).abs() < 1e-6);
        // Exposure 1 is EV100 −log2(1.2).
        assert!((ev100_of_exposure(1.0) + 1.2f32.log2()).abs() < 1e-6);
    }

    #[test]
    fn settings_out_of_range_are_refused_by_name() {
        let camera = PhysicalCamera {
            f_number: 0.1,
            shutter_seconds: 0.01,
            iso: 100.0,
        };
        let message = camera.validate().unwrap_err().to_string();
        assert!(message.contains("aperture f-number 0.1"), "{message}");
        let auto = AutoExposure {
            window: [0.9, 0.1],
            ..AutoExposure::default()
        };
        let message = auto.validate().unwrap_err().to_string();
        assert!(message.contains("low end 0.9"), "{message}");
        let auto = AutoExposure {
            rise_per_second: f32::NAN,
            ..AutoExposure::default()
        };
        assert!(auto.validate().is_err());
        assert!(AutoExposure::default().validate().is_ok());
    }
}
