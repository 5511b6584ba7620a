//! Light through transmissive surfaces (KHR_materials_transmission, KHR_materials_volume),
//! exactly for the scene's own geometry: the oracle the renderer's screen-space
//! transmission is measured against.
//!
//! - **Thin-walled** (no volume): the surface is a shell of no thickness; light goes
//!   straight through both of its interfaces, with the incoherent sum of the internal
//!   reflections between them: (1 − R)/(1 + R) per polarisation, R the dielectric
//!   reflectance at the view angle from the outside medium into the material.
//! - **Volume**: the view ray is refracted into the object (Snell, η_i/η_t; none past the
//!   critical angle), followed through the scene's triangles to where it leaves (the
//!   first surface it meets inside, whichever object's), absorbed on the way
//!   (Beer–Lambert, e^(−σ s) over its path length s), split there by the Fresnel
//!   equations into the part that refracts out and the part reflected back inside (total
//!   internal reflection past the critical angle), and each part followed on: outside, to
//!   whatever the ray meets next, shaded as seen from there; inside, to the next
//!   interface, for up to [`TRANSMISSION_DEPTH`] interfaces in all (what remains beyond
//!   them is dropped). Each polarisation is carried separately and weighted at the end
//!   (the planes of incidence of successive interfaces are taken to coincide).
//! - Interfaces are smooth: a rough surface's transmission is followed along its shading
//!   normal, as a smooth one's (its reflection keeps its roughness).
//! - Shading normals: where an interpolated normal faces away from the ray that meets it
//!   (near a silhouette), it is bent towards the ray until their cosine is 10⁻⁴, as the
//!   renderer does.
//! - Secondary rays read textures at their finest level; what they miss is black (no
//!   environment behind).

use combustion_optics::fresnel::{fresnel_dielectric, fresnel_dielectric_transmittance};
use combustion_scene::Material;
use glam::DVec3;

use crate::primary::{next_seen, seen_surface};
use crate::shading::{SceneShading, SurfacePoint};
use crate::visibility::surface_offset;
use crate::Ray;

/// Interfaces light is followed through (entries, exits and internal reflections)
/// beyond the first surface a pixel shows.
pub const TRANSMISSION_DEPTH: u32 = 8;

/// The smallest cosine between a ray and the normal it crosses (see the module docs).
const MIN_COS: f64 = 1e-4;

/// A radiance per polarisation (s, p), RGB each.
type Polarised3 = ([f64; 3], [f64; 3]);

/// `n` bent towards `towards` (unit) until their cosine is at least [`MIN_COS`].
fn facing(n: DVec3, towards: DVec3) -> DVec3 {
    let c = n.dot(towards);
    if c > MIN_COS {
        n
    } else {
        (n + (MIN_COS - c) * towards).normalize()
    }
}

/// The direction a ray along `d` (unit) takes through an interface of unit normal `n`
/// (facing against `d`) with relative index `eta` = η_from/η_to; `None` past the critical
/// angle.
fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let cos_i = -n.dot(d);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((d * eta + n * (eta * cos_i - cos_t)).normalize())
}

impl SceneShading<'_> {
    /// The radiance that passes through `surface` (of transmissive `material`) towards
    /// its viewer, before the weight (1 − metalness) · transmission · base colour,
    /// following light through `depth` more interfaces.
    pub(crate) fn transmitted(
        &self,
        surface: &SurfacePoint,
        material: &Material,
        depth: u32,
    ) -> [f64; 3] {
        let v = surface.v;
        let n = facing(surface.n, v);
        let cos_v = n.dot(v).clamp(0.0, 1.0);
        let (eta_i, eta_t) = (surface.brdf.outside_eta, surface.brdf.dielectric_eta);
        let w = surface.brdf.polarisation_weight;
        let position = DVec3::from(surface.hit.position);
        let (s, p) = match material.volume {
            None => {
                let r = fresnel_dielectric(cos_v, eta_i, eta_t);
                let behind = self.radiance_along(position, -v, depth);
                (
                    behind.map(|l| l * (1.0 - r.s) / (1.0 + r.s)),
                    behind.map(|l| l * (1.0 - r.p) / (1.0 + r.p)),
                )
            }
            Some(volume) => {
                let Some(inside) = refract(-v, n, eta_i / eta_t) else {
                    return [0.0; 3];
                };
                let t = fresnel_dielectric_transmittance(cos_v, eta_i, eta_t);
                let sigma = volume.absorption();
                let (s, p) = self.inside(position, inside, (eta_t, eta_i), sigma, depth);
                (s.map(|l| l * t.s), p.map(|l| l * t.p))
            }
        };
        std::array::from_fn(|c| (1.0 - w) * s[c] + w * p[c])
    }

    /// The radiance per polarisation carried back to `origin` by light travelling inside
    /// a medium of index `indices.0` (outside it: `indices.1`) along `direction`, of
    /// absorption `sigma`, from the interface it meets next.
    fn inside(
        &self,
        origin: DVec3,
        direction: DVec3,
        (eta_inside, eta_outside): (f64, f64),
        sigma: [f64; 3],
        depth: u32,
    ) -> Polarised3 {
        if depth == 0 {
            return ([0.0; 3], [0.0; 3]);
        }
        let ray = Ray::new(origin.to_array(), direction.to_array());
        let offset = surface_offset(origin.to_array());
        let Some(hit) = self.bvh.closest_hit(&ray, offset, f64::INFINITY) else {
            return ([0.0; 3], [0.0; 3]);
        };
        let Some(exit) = seen_surface(self.scene, &ray, &hit) else {
            return ([0.0; 3], [0.0; 3]);
        };
        let point = DVec3::from(exit.position);
        let absorbed = sigma.map(|s| (-s * hit.t).exp());
        // The exit's outward normal, facing the way the light leaves.
        let mut outward = DVec3::from(exit.normal);
        if outward.dot(DVec3::from(exit.geometric_normal)) < 0.0 {
            outward = -outward;
        }
        if DVec3::from(exit.geometric_normal).dot(direction) < 0.0 {
            outward = -outward; // met from outside its mesh's orientation
        }
        let outward = facing(outward, direction);
        let cos_e = outward.dot(direction).clamp(0.0, 1.0);
        let r = fresnel_dielectric(cos_e, eta_inside, eta_outside);
        let t = fresnel_dielectric_transmittance(cos_e, eta_inside, eta_outside);
        let out = refract(direction, -outward, eta_inside / eta_outside)
            .map_or([0.0; 3], |d| self.radiance_along(point, d, depth - 1));
        let reflected = direction - 2.0 * direction.dot(outward) * outward;
        let (back_s, back_p) = self.inside(
            point,
            reflected.normalize(),
            (eta_inside, eta_outside),
            sigma,
            depth - 1,
        );
        (
            std::array::from_fn(|c| absorbed[c] * (t.s * out[c] + r.s * back_s[c])),
            std::array::from_fn(|c| absorbed[c] * (t.p * out[c] + r.p * back_p[c])),
        )
    }

    /// The radiance arriving at `origin` against unit `direction`: what the ray from
    /// `origin` along `direction` meets (back faces of single-sided materials passed, as
    /// the rasteriser culls them), shaded as seen from `origin`, following light through
    /// `depth` more interfaces; 0 where it meets nothing.
    pub(crate) fn radiance_along(&self, origin: DVec3, direction: DVec3, depth: u32) -> [f64; 3] {
        let ray = Ray::new(origin.to_array(), direction.to_array());
        let mut t_min = surface_offset(origin.to_array());
        let Some((hit, material)) =
            next_seen(self.scene, self.bvh, &ray, &mut t_min, f64::INFINITY)
        else {
            return [0.0; 3];
        };
        let Some(surface) = seen_surface(self.scene, &ray, &hit)
            .and_then(|seen| self.surface_seen_from(seen, origin))
        else {
            return [0.0; 3];
        };
        let radiance = self.radiance_followed(&surface, depth);
        if !material.is_blended() {
            return radiance;
        }
        // A blended surface: over what the ray meets beyond it.
        let alpha = surface.alpha.clamp(0.0, 1.0);
        let point = DVec3::from(surface.hit.position);
        let beyond = self.radiance_along(point, direction, depth);
        std::array::from_fn(|c| alpha * radiance[c] + (1.0 - alpha) * beyond[c])
    }
}
