//! Light through transmissive surfaces (KHR_materials_transmission, KHR_materials_volume),
//! exactly for the scene's own geometry: the oracle the renderer's screen-space
//! transmission is measured against.
//!
//! - **Thin-walled** (no volume): the surface is a shell of no thickness; light goes
//!   straight through both of its interfaces, with the incoherent sum of the internal
//!   reflections between them: (1 − R)/(1 + R) per polarisation, R the dielectric
//!   reflectance at the view angle from the outside medium into the material. A rough
//!   one spreads what it lets through as its two interfaces, both of its roughness,
//!   refract it: in through a microfacet normal the view sees (GGX visible normals, the
//!   surface's α), η_i/η_t, and out through one the far wall (parallel, no thickness
//!   away) shows the light inside, η_t/η_i, each direction weighted by the masking of
//!   the refracted ray (separable Smith G₁ per interface). The spread is normalised (it
//!   loses no light: the smooth wall's transmittance is kept) and integrated with
//!   [`ROUGH_SAMPLES`] Hammersley–Halton points (shifted per point) at the first surface a pixel's light passes
//!   through (a rough thin wall behind it is followed straight through). Where the
//!   indices match, nothing bends, rough or not.
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
//! - **A thin film** on the surface (KHR_materials_iridescence) filters every crossing
//!   of it: each transmits T + w ((1 − R_film) − T) per polarisation and channel and
//!   reflects the rest (`film_crossing_transmittance`; the film absorbs nothing): a thin
//!   wall passes (1 − R)/(1 + R) with R the film's mixed reflectance, and a volume's
//!   exits and internal reflections use the film as at the entry point.
//! - A volume's interfaces are smooth: a rough one's transmission is followed along its
//!   shading normal, as a smooth one's (its reflection keeps its roughness).
//! - Shading normals: where an interpolated normal faces away from the ray that meets it
//!   (near a silhouette), it is bent towards the ray until their cosine is 10⁻⁴, as the
//!   renderer does.
//! - Secondary rays read textures at their finest level; what they miss is black (no
//!   environment behind).

use combustion_optics::environment::sample_ggx_vndf;
use combustion_optics::fresnel::{fresnel_dielectric, fresnel_dielectric_transmittance};
use combustion_optics::microfacet::lambda_ggx_anisotropic;
use combustion_optics::thin_film::{film_crossing_transmittance, ThinFilm};
use combustion_optics::vec3::Vec3 as OpticsVec3;
use combustion_scene::Material;
use glam::DVec3;

use crate::primary::{next_seen, seen_surface};
use crate::shading::{SceneShading, SurfacePoint};
use crate::visibility::surface_offset;
use crate::Ray;

/// Interfaces light is followed through (entries, exits and internal reflections)
/// beyond the first surface a pixel shows.
pub const TRANSMISSION_DEPTH: u32 = 8;

/// The directions a rough thin-walled surface's transmission is integrated over, per
/// point (see the module docs).
pub const ROUGH_SAMPLES: u32 = 1024;

/// The smallest cosine between a ray and the normal it crosses (see the module docs).
const MIN_COS: f64 = 1e-4;

/// A radiance per polarisation (s, p), RGB each.
pub(crate) type Polarised3 = ([f64; 3], [f64; 3]);

/// One crossing of an interface from index `from` into `to` at the cosine `cos` (on the
/// `from` side): the transmittance and the reflectance per polarisation and channel.
/// Under a thin film (KHR_materials_iridescence) the film's mix
/// (`film_crossing_transmittance`; the film absorbs nothing, R = 1 − T), else the bare
/// interface's Fresnel equations.
pub(crate) fn crossing(
    cos: f64,
    from: f64,
    to: f64,
    film: Option<&ThinFilm<f64>>,
) -> (Polarised3, Polarised3) {
    match film.filter(|f| f.is_present()) {
        None => {
            let t = fresnel_dielectric_transmittance(cos, from, to);
            let r = fresnel_dielectric(cos, from, to);
            (([t.s; 3], [t.p; 3]), ([r.s; 3], [r.p; 3]))
        }
        Some(film) => {
            let t = film_crossing_transmittance(cos, from, to, Some(film));
            ((t.s, t.p), (t.s.map(|x| 1.0 - x), t.p.map(|x| 1.0 - x)))
        }
    }
}

/// The radical inverse of `i` in `base`: the Halton sequence's coordinate, in [0, 1).
fn radical_inverse(base: u32, mut i: u32) -> f64 {
    let (mut inverse, mut scale) = (0.0, 1.0 / f64::from(base));
    while i > 0 {
        inverse += f64::from(i % base) * scale;
        i /= base;
        scale /= f64::from(base);
    }
    inverse
}

/// [`refract`] in the optics crate's vectors: `d` (unit) through a microfacet of unit
/// normal `m` on the side `d` comes from, relative index `eta`; `None` past the
/// critical angle.
pub(crate) fn refract_local(
    d: OpticsVec3<f64>,
    m: OpticsVec3<f64>,
    eta: f64,
) -> Option<OpticsVec3<f64>> {
    let m = if m.dot(d) > 0.0 { m * -1.0 } else { m };
    let to = |w: OpticsVec3<f64>| DVec3::new(w.x, w.y, w.z);
    refract(to(d), to(m), eta).map(|r| OpticsVec3::new(r.x, r.y, r.z))
}

/// `n` bent towards `towards` (unit) until their cosine is at least [`MIN_COS`].
pub(crate) fn facing(n: DVec3, towards: DVec3) -> DVec3 {
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
pub(crate) fn refract(d: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
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
        // A thin film on the surface filters every crossing of it (the film as at this
        // point: an exit of the object's own surface sees the same film).
        let film = surface.layers.film.as_ref();
        let (t, r) = crossing(cos_v, eta_i, eta_t, film);
        let (s, p): Polarised3 = match material.volume {
            None => {
                // Both sides of the shell, each crossed once (the film's crossing from
                // inside transmits as much as from outside: reciprocity).
                let behind = self.through_thin_wall(surface, n, position, depth);
                (
                    std::array::from_fn(|c| behind[c] * (1.0 - r.0[c]) / (1.0 + r.0[c])),
                    std::array::from_fn(|c| behind[c] * (1.0 - r.1[c]) / (1.0 + r.1[c])),
                )
            }
            Some(volume) => {
                let Some(inside) = refract(-v, n, eta_i / eta_t) else {
                    return [0.0; 3];
                };
                let sigma = volume.absorption();
                let (s, p) = self.inside(position, inside, (eta_t, eta_i), sigma, film, depth);
                (
                    std::array::from_fn(|c| s[c] * t.0[c]),
                    std::array::from_fn(|c| p[c] * t.1[c]),
                )
            }
        };
        std::array::from_fn(|c| (1.0 - w) * s[c] + w * p[c])
    }

    /// What a thin-walled `surface` (shading normal `n`, facing its viewer) lets through
    /// towards its viewer before its transmittance: straight through where it is smooth,
    /// else the mean over the directions its two rough interfaces refract the light
    /// into (see the module docs).
    fn through_thin_wall(
        &self,
        surface: &SurfacePoint,
        n: DVec3,
        position: DVec3,
        depth: u32,
    ) -> [f64; 3] {
        let v = surface.v;
        // Only the first surface a pixel's light passes through is integrated over; a
        // rough thin wall further along is followed straight through (as the renderer's
        // screen-space lookup sees the opaque scene only).
        let first = depth + 1 == TRANSMISSION_DEPTH;
        if surface.roughness.is_nan() || surface.roughness <= 0.0 || !first {
            return self.radiance_along(position, -v, depth);
        }
        let (ax, ay) = (surface.brdf.alpha_x, surface.brdf.alpha_y);
        let (eta_i, eta_t) = (surface.brdf.outside_eta, surface.brdf.dielectric_eta);
        // The shading frame about the (possibly bent) normal: z towards the viewer.
        let t = (surface.t - n * n.dot(surface.t)).normalize_or(n.any_orthonormal_vector());
        let b = n.cross(t);
        let v_local = OpticsVec3::new(v.dot(t), v.dot(b), v.dot(n));
        // G₁ of a direction below the surface, as seen from below.
        let g1_below = |d: OpticsVec3<f64>| {
            1.0 / (1.0 + lambda_ggx_anisotropic(OpticsVec3::new(d.x, d.y, -d.z), ax, ay))
        };
        // The point set shifted per point (Cranley–Patterson), so that neighbouring
        // pixels' integration errors do not line up into streaks.
        let mut random = combustion_optics::environment::SplitMix64::new(
            position
                .to_array()
                .iter()
                .fold(0x5EED, |h, c| h ^ c.to_bits().rotate_left(17)),
        );
        let shift: [f64; 4] = std::array::from_fn(|_| random.next_f64());
        let (mut sum, mut weights) = ([0.0; 3], 0.0);
        for i in 0..ROUGH_SAMPLES {
            let u1 = ((f64::from(i) + 0.5) / f64::from(ROUGH_SAMPLES) + shift[0]).fract();
            let u2 = (f64::from(i.reverse_bits()) * (1.0 / 4_294_967_296.0) + shift[1]).fract();
            // In through a microfacet the view sees...
            let m_in = sample_ggx_vndf(v_local, ax, ay, u1, u2);
            let Some(inside) = refract_local(-v_local, m_in, eta_i / eta_t) else {
                continue;
            };
            // ...and out through one of the far wall's (parallel, as rough) that the
            // light inside meets (seen from inside, the glass's side is above it too).
            let u3 = (radical_inverse(3, i) + shift[2]).fract();
            let u4 = (radical_inverse(5, i) + shift[3]).fract();
            let m_out = sample_ggx_vndf(-inside, ax, ay, u3, u4);
            let Some(out) = refract_local(inside, m_out, eta_t / eta_i) else {
                continue;
            };
            if !(inside.z < 0.0 && out.z < 0.0) {
                continue;
            }
            let weight = g1_below(inside) * g1_below(out);
            let through = (t * out.x + b * out.y + n * out.z).normalize();
            let radiance = self.radiance_along(position, through, depth);
            for c in 0..3 {
                sum[c] += weight * radiance[c];
            }
            weights += weight;
        }
        if weights > 0.0 {
            sum.map(|s| s / weights)
        } else {
            self.radiance_along(position, -v, depth)
        }
    }

    /// The radiance per polarisation carried back to `origin` by light travelling inside
    /// a medium of index `indices.0` (outside it: `indices.1`) along `direction`, of
    /// absorption `sigma`, from the interface it meets next (under `film`, the film of
    /// the object it travels in).
    fn inside(
        &self,
        origin: DVec3,
        direction: DVec3,
        (eta_inside, eta_outside): (f64, f64),
        sigma: [f64; 3],
        film: Option<&ThinFilm<f64>>,
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
        let (t, r) = crossing(cos_e, eta_inside, eta_outside, film);
        let out = refract(direction, -outward, eta_inside / eta_outside)
            .map_or([0.0; 3], |d| self.radiance_along(point, d, depth - 1));
        let reflected = direction - 2.0 * direction.dot(outward) * outward;
        let (back_s, back_p) = self.inside(
            point,
            reflected.normalize(),
            (eta_inside, eta_outside),
            sigma,
            film,
            depth - 1,
        );
        (
            std::array::from_fn(|c| absorbed[c] * (t.0[c] * out[c] + r.0[c] * back_s[c])),
            std::array::from_fn(|c| absorbed[c] * (t.1[c] * out[c] + r.1[c] * back_p[c])),
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
