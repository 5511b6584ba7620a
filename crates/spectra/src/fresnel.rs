//! The one place this crate calls the Fresnel equations of `combustion-optics`.

/// Reflectance of the interface outside medium (real index `outside_eta`) → conductor
/// `eta + i k`, at `cos_theta`, polarisation weight `w` (0 = s, 1 = p).
pub(crate) fn conductor_reflectance(
    cos_theta: f64,
    outside_eta: f64,
    eta: f64,
    k: f64,
    w: f64,
) -> f64 {
    // TODO(spectra): call combustion-optics once its conductor Fresnel lands.
    let _ = (cos_theta, outside_eta, eta, k, w);
    f64::NAN
}
