//! The one place this crate calls the Fresnel equations: `combustion-optics`'
//! dielectric–conductor reflectance with an outside medium.

use combustion_optics::fresnel::fresnel_conductor;

/// Reflectance of the interface from an outside medium of real index `outside_eta` into a
/// conductor `eta + i k`, at `cos_theta` (angle of incidence in the outside medium),
/// polarisation weight `w`: (1 − w)·Rs + w·Rp (0 = s / perpendicular, 1 = p / parallel).
pub(crate) fn conductor_reflectance(
    cos_theta: f64,
    outside_eta: f64,
    eta: f64,
    k: f64,
    w: f64,
) -> f64 {
    fresnel_conductor(cos_theta, outside_eta, eta, k).weighted(w)
}
