//! Exact visibility of lights from surface points: what a shadow map approximates.
//!
//! # Leaving the surface
//!
//! A shadow ray that starts exactly on the surface it leaves may hit that surface at
//! t ≈ 0 (or just beyond, through rounding). The ray therefore starts at
//! [`shadow_ray_origin`]: the point moved along the unit `offset_normal` by
//! [`surface_offset`]`(point)` = [`SURFACE_OFFSET`] · max(1 m, ‖point‖∞), that is
//! 1e-4 relative (0.1 mm within a metre of the origin, 10 cm at 1 km). The bound it has
//! to beat is the error of the points the reference is given: a point reconstructed
//! from an f32 depth buffer is off by ≈ 1e-6 of its distance to the camera, and an f32
//! position by 6e-8 of its magnitude; 1e-4 leaves a factor of 100 for a camera up to
//! that many times farther from the point than the point is from the origin (for
//! points computed in f64 on the triangle, the margin is 1e12). What the offset costs is
//! that blockers closer than it to the surface (contact shadows finer than 1e-4
//! relative) are missed, and that a ray whose direction grazes the surface within
//! ≈ offset/distance radians of it escapes the surface's neighbours: both far below
//! what a shadow map resolves.
//!
//! `offset_normal` is the side the light should be seen from: the caller passes the
//! geometric (or shading) normal, flipped towards the light or the viewer. Its length
//! does not matter; a zero or non-finite one means no offset. The ray then has
//! `t_min = 0` (its origin is already off the surface) and, towards a point light, ends
//! short of the light by [`surface_offset`] of the light's position (a light placed on
//! a surface is not blocked by it).
//!
//! # Light sizes
//!
//! The scene's lights are points and directions for now; [`SceneBvh::disc_visibility`]
//! and [`SceneBvh::sun_visibility`] already give the visible fraction of a disc light
//! and of a sun of non-zero angular diameter, for when they get a size.
//!
//! Their estimate is stratified: with n = `samples_per_axis`, the unit square is cut
//! into N = n² cells, one jittered sample in each (a deterministic PCG32 generator
//! seeded from the arguments: the same call gives the same answer), mapped onto the
//! disc by Shirley and Chiu's concentric map, which preserves area. The estimate is
//! unbiased, and only cells crossed by the visible region's boundary contribute
//! variance: with M such cells, Var ≤ M/(4N²) (each cell's sample is a Bernoulli
//! variable of variance p(1 − p) ≤ 1/4), and the error is never more than M/N. The
//! inverse of the concentric map (disc of radius 1 to the square [−1, 1]²) stretches
//! lengths by at most √(1 + k²/2 + √((1 − k²/2)² + k²)) ≈ 1.76, k = 4/π; a curve of
//! length L in the square crosses at most √2·L/h grid lines of spacing h = 2/n, so a
//! boundary of length ℓ disc radii crosses M ≤ 1 + 1.25·ℓ·n cells. Hence, for a
//! smooth boundary, the standard error is σ ≤ √(1 + 1.25·ℓ·n) / (2n²) ≈
//! 0.56·√ℓ · N^(−3/4): with 32 × 32 samples and a boundary across the disc's diameter
//! (ℓ = 2), σ ≤ 0.0044 and the error is at most 0.079.

use combustion_scene::Light;
use glam::DVec3;

use crate::{Ray, SceneBvh};

/// The relative size of the step off the surface that a shadow ray takes
/// ([`surface_offset`]); see the module docs for the choice.
pub const SURFACE_OFFSET: f64 = 1e-4;

/// How far (metres) a shadow ray leaving `point` starts from it:
/// [`SURFACE_OFFSET`] · max(1, ‖point‖∞).
pub fn surface_offset(point: [f64; 3]) -> f64 {
    let magnitude = point.iter().fold(1.0_f64, |m, c| m.max(c.abs()));
    SURFACE_OFFSET * magnitude
}

/// Where a shadow ray leaving `point` on the side of `offset_normal` starts: `point`
/// moved by [`surface_offset`]`(point)` along the unit `offset_normal` (not moved when
/// the normal is zero or not finite).
pub fn shadow_ray_origin(point: [f64; 3], offset_normal: [f64; 3]) -> [f64; 3] {
    let n = DVec3::from(offset_normal).normalize_or_zero();
    (DVec3::from(point) + n * surface_offset(point)).to_array()
}

impl SceneBvh {
    /// Whether nothing lies on the open segment from `from` to `to` (no triangle hit at
    /// 0 < t < 1 on [`Ray::through`]`(from, to)`). Exact: no offset at either end.
    pub fn segment_visible(&self, from: [f64; 3], to: [f64; 3]) -> bool {
        !self.any_hit(&Ray::through(from, to), 0.0, 1.0)
    }

    /// Whether nothing lies on the ray from `from` along `direction` (any length), to
    /// infinity (no triangle hit at t > 0). Exact: no offset.
    pub fn direction_visible(&self, from: [f64; 3], direction: [f64; 3]) -> bool {
        !self.any_hit(&Ray::new(from, direction), 0.0, f64::INFINITY)
    }

    /// Visibility of `light` from the surface point `point`: 1.0 when nothing blocks
    /// it, 0.0 when something does. Point and spot lights: the segment from
    /// [`shadow_ray_origin`] to the light's position, ending [`surface_offset`] short of
    /// the light (a spot light's cone is its emission, not a blocker: it is not applied
    /// here). Directional lights: the ray from [`shadow_ray_origin`] against the
    /// light's `direction`, to infinity. A light that [`Light`]'s validation refuses (a
    /// zero or non-finite direction or position) gives an unspecified 0.0 or 1.0,
    /// never a panic.
    pub fn light_visibility(&self, point: [f64; 3], offset_normal: [f64; 3], light: &Light) -> f64 {
        let origin = shadow_ray_origin(point, offset_normal);
        let visible = match *light {
            Light::Point { position, .. } | Light::Spot { position, .. } => {
                self.towards_light_visible(origin, position.as_dvec3().to_array())
            }
            Light::Directional { direction, .. } => {
                self.direction_visible(origin, (-direction.as_dvec3()).to_array())
            }
        };
        if visible {
            1.0
        } else {
            0.0
        }
    }

    /// The visible fraction of `light` from `point`, with its size: a point or spot
    /// light of radius r > 0 is the disc of radius r facing the point (the sphere's
    /// silhouette, to O(r²/d²)) sampled by [`SceneBvh::disc_visibility`]; a directional
    /// light of angular diameter θ > 0, the cone of directions sampled by
    /// [`SceneBvh::sun_visibility`]; both with `samples_per_axis`² stratified samples
    /// (their stated error). Lights of size 0: [`SceneBvh::light_visibility`], exact.
    pub fn light_visible_fraction(
        &self,
        point: [f64; 3],
        offset_normal: [f64; 3],
        light: &Light,
        samples_per_axis: u32,
    ) -> f64 {
        match *light {
            Light::Point {
                position, radius, ..
            }
            | Light::Spot {
                position, radius, ..
            } if radius > 0.0 => {
                let center = position.as_dvec3();
                let facing = (DVec3::from(point) - center).normalize_or_zero();
                self.disc_visibility(
                    point,
                    offset_normal,
                    center.to_array(),
                    facing.to_array(),
                    f64::from(radius),
                    samples_per_axis,
                )
            }
            Light::Directional {
                direction,
                angular_diameter,
                ..
            } if angular_diameter > 0.0 => self.sun_visibility(
                point,
                offset_normal,
                (-direction.as_dvec3()).to_array(),
                f64::from(angular_diameter),
                samples_per_axis,
            ),
            _ => self.light_visibility(point, offset_normal, light),
        }
    }

    /// The segment from a shadow ray's origin to a light point, ending
    /// [`surface_offset`]`(light)` short of it.
    fn towards_light_visible(&self, origin: [f64; 3], light: [f64; 3]) -> bool {
        let ray = Ray::through(origin, light);
        let length = DVec3::from(ray.direction).length();
        if length == 0.0 || length.is_nan() {
            return true;
        }
        let end = 1.0 - surface_offset(light) / length;
        !self.any_hit(&ray, 0.0, end)
    }

    /// The visible fraction (0 to 1) of a disc light (centre `center`, facing along
    /// `disc_normal`, either sign, radius `radius` metres) from the surface point
    /// `point`: the share of the disc's *area* seen from [`shadow_ray_origin`] (no
    /// cosine or distance weighting), estimated from `samples_per_axis`² stratified
    /// samples (at least 1) as the module docs state, with their error bound. Every
    /// segment ends [`surface_offset`] short of its sample point. Exactly 1.0 when
    /// nothing blocks any sample, exactly 0.0 when everything does.
    #[allow(clippy::too_many_arguments)]
    pub fn disc_visibility(
        &self,
        point: [f64; 3],
        offset_normal: [f64; 3],
        center: [f64; 3],
        disc_normal: [f64; 3],
        radius: f64,
        samples_per_axis: u32,
    ) -> f64 {
        let origin = shadow_ray_origin(point, offset_normal);
        let (tangent, bitangent) = orthonormal_basis(DVec3::from(disc_normal));
        let center = DVec3::from(center);
        let seed = seed_from(&[point, offset_normal, center.to_array(), disc_normal]);
        stratified_fraction(samples_per_axis, seed, |x, y| {
            let sample = center + radius * (x * tangent + y * bitangent);
            self.towards_light_visible(origin, sample.to_array())
        })
    }

    /// The visible fraction (0 to 1) of a sun of angular diameter `angular_diameter`
    /// (radians, clamped to [0, π)) in the direction `towards_sun` (from the surface
    /// towards the sun, any length): rays from [`shadow_ray_origin`] to infinity along
    /// directions `axis + tan(θ/2)·(x, y)`, (x, y) stratified over the unit disc as
    /// for [`SceneBvh::disc_visibility`] (the same error bound). This is uniform over
    /// the cone's disc, not over its solid angle; the two weightings differ by a
    /// relative O(θ²) (2e-5 for the real sun's 0.53°), and a sun of uniform radiance
    /// seen through the projected disc is what the disc sampling gives.
    pub fn sun_visibility(
        &self,
        point: [f64; 3],
        offset_normal: [f64; 3],
        towards_sun: [f64; 3],
        angular_diameter: f64,
        samples_per_axis: u32,
    ) -> f64 {
        let origin = shadow_ray_origin(point, offset_normal);
        let axis = DVec3::from(towards_sun).normalize_or_zero();
        let half_angle = angular_diameter.clamp(0.0, std::f64::consts::PI * (1.0 - 1e-9)) / 2.0;
        let spread = if half_angle.is_nan() {
            0.0
        } else {
            half_angle.tan()
        };
        let (tangent, bitangent) = orthonormal_basis(axis);
        let seed = seed_from(&[point, offset_normal, towards_sun, [angular_diameter; 3]]);
        stratified_fraction(samples_per_axis, seed, |x, y| {
            let direction = axis + spread * (x * tangent + y * bitangent);
            self.direction_visible(origin, direction.to_array())
        })
    }
}

/// The fraction of `n`² stratified, jittered samples of the unit disc (concentric map)
/// for which `visible(x, y)` holds.
fn stratified_fraction(n: u32, seed: u64, mut visible: impl FnMut(f64, f64) -> bool) -> f64 {
    let n = n.max(1);
    let mut random = Pcg32::new(seed);
    let mut seen = 0u64;
    for i in 0..n {
        for j in 0..n {
            let u = (f64::from(i) + random.next_f64()) / f64::from(n);
            let v = (f64::from(j) + random.next_f64()) / f64::from(n);
            let (x, y) = concentric_disc(u, v);
            seen += u64::from(visible(x, y));
        }
    }
    let total = u64::from(n) * u64::from(n);
    if seen == total {
        1.0
    } else {
        seen as f64 / total as f64
    }
}

/// Shirley and Chiu's concentric map from the unit square onto the unit disc: area
/// preserving, and squares' concentric rings go to the disc's.
pub(crate) fn concentric_disc(u: f64, v: f64) -> (f64, f64) {
    use std::f64::consts::FRAC_PI_4;
    let a = 2.0 * u - 1.0;
    let b = 2.0 * v - 1.0;
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

/// Two unit vectors perpendicular to `n` and to each other (Duff et al. 2017); for a
/// zero or non-finite `n`, the x and z axes.
fn orthonormal_basis(n: DVec3) -> (DVec3, DVec3) {
    let n = n.normalize_or_zero();
    if n == DVec3::ZERO {
        return (DVec3::X, DVec3::Z);
    }
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// A seed from the bits of the given coordinates (SplitMix64 steps), so each call is
/// reproducible and different points get different jitter.
fn seed_from(values: &[[f64; 3]]) -> u64 {
    let mut h = 0x853c_49e6_748f_ea9b_u64;
    for value in values.iter().flatten() {
        h = splitmix64(h ^ value.to_bits());
    }
    h
}

fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// O'Neill's PCG32 (XSH-RR): a tiny, deterministic generator, enough for jitter.
struct Pcg32 {
    state: u64,
}

impl Pcg32 {
    const MULTIPLIER: u64 = 6_364_136_223_846_793_005;
    const INCREMENT: u64 = 1_442_695_040_888_963_407;

    fn new(seed: u64) -> Pcg32 {
        let mut pcg = Pcg32 { state: 0 };
        pcg.next_u32();
        pcg.state = pcg.state.wrapping_add(seed);
        pcg.next_u32();
        pcg
    }

    fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(Self::MULTIPLIER)
            .wrapping_add(Self::INCREMENT);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        xorshifted.rotate_right((old >> 59) as u32)
    }

    /// Uniform in [0, 1), 53 random bits.
    fn next_f64(&mut self) -> f64 {
        let bits = (u64::from(self.next_u32()) << 21) ^ u64::from(self.next_u32());
        (bits & ((1 << 53) - 1)) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_concentric_map_fills_the_disc_evenly() {
        // Equal-area: each of the four quadrants of the square's cells lands in the
        // disc, and the mean of r² over a fine grid is 1/2 (uniform on the disc).
        let n = 200;
        let mut sum_r2 = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) =
                    concentric_disc((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                let r2 = x * x + y * y;
                assert!(r2 <= 1.0 + 1e-12);
                sum_r2 += r2;
            }
        }
        let mean = sum_r2 / (n * n) as f64;
        assert!((mean - 0.5).abs() < 1e-4, "{mean}");
    }

    #[test]
    fn the_basis_is_orthonormal() {
        for n in [
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
            [0.3, -2.0, 0.1],
            [1.0, 0.0, 0.0],
        ] {
            let n = DVec3::from(n).normalize();
            let (t, b) = orthonormal_basis(n);
            assert!((t.length() - 1.0).abs() < 1e-14 && (b.length() - 1.0).abs() < 1e-14);
            assert!(t.dot(b).abs() < 1e-14 && t.dot(n).abs() < 1e-14 && b.dot(n).abs() < 1e-14);
        }
    }

    #[test]
    fn the_generator_is_uniform_enough_and_reproducible() {
        let mut a = Pcg32::new(7);
        let mut b = Pcg32::new(7);
        let mut sum = 0.0;
        for _ in 0..10_000 {
            let x = a.next_f64();
            assert_eq!(x, b.next_f64());
            assert!((0.0..1.0).contains(&x));
            sum += x;
        }
        assert!((sum / 10_000.0 - 0.5).abs() < 0.01);
    }
}
