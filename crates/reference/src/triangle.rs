//! The watertight ray–triangle test (Woop, Benthin, Wald 2013) in f64; see the crate
//! docs for why this one.

use crate::Ray;

/// A ray with the test's per-ray constants: the axis `kz` along which the direction is
/// largest, the other two (`kx`, `ky`, swapped for a negative `kz` component so the
/// winding is kept), and the shear taking the direction to +z.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShearedRay {
    pub origin: [f64; 3],
    /// 1/direction per axis, a zero component's infinity replaced by ±f64::MAX so a
    /// box test never computes 0 · ∞.
    pub inverse_direction: [f64; 3],
    kx: usize,
    ky: usize,
    kz: usize,
    shear_x: f64,
    shear_y: f64,
    shear_z: f64,
}

impl ShearedRay {
    pub fn new(ray: &Ray) -> ShearedRay {
        let d = ray.direction;
        let abs = d.map(f64::abs);
        let kz = if abs[0] >= abs[1] && abs[0] >= abs[2] {
            0
        } else if abs[1] >= abs[2] {
            1
        } else {
            2
        };
        let (mut kx, mut ky) = ((kz + 1) % 3, (kz + 2) % 3);
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let inverse_direction = d.map(|c| {
            let inverse = 1.0 / c;
            if inverse.is_infinite() {
                f64::MAX.copysign(inverse)
            } else {
                inverse
            }
        });
        ShearedRay {
            origin: ray.origin,
            inverse_direction,
            kx,
            ky,
            kz,
            shear_x: d[kx] / d[kz],
            shear_y: d[ky] / d[kz],
            shear_z: 1.0 / d[kz],
        }
    }

    /// The hit with `t_min < t < t_max` as (t, [b1, b2]), or `None`. Double-sided.
    #[inline]
    pub fn intersect(
        &self,
        vertices: &[[f64; 3]; 3],
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, [f64; 2])> {
        // The axes as constants: each component a register, not an index into an array
        // on the stack (the same operations on the same values, so the same answer).
        match (self.kx, self.ky, self.kz) {
            (1, 2, 0) => self.intersect_along::<1, 2, 0>(vertices, t_min, t_max),
            (2, 1, 0) => self.intersect_along::<2, 1, 0>(vertices, t_min, t_max),
            (2, 0, 1) => self.intersect_along::<2, 0, 1>(vertices, t_min, t_max),
            (0, 2, 1) => self.intersect_along::<0, 2, 1>(vertices, t_min, t_max),
            (0, 1, 2) => self.intersect_along::<0, 1, 2>(vertices, t_min, t_max),
            (1, 0, 2) => self.intersect_along::<1, 0, 2>(vertices, t_min, t_max),
            _ => unreachable!("ShearedRay::new makes only the six orders above"),
        }
    }

    /// [`Self::intersect`] with the ray's axes `KX`, `KY`, `KZ` (`kx`, `ky`, `kz`).
    #[inline(always)]
    fn intersect_along<const KX: usize, const KY: usize, const KZ: usize>(
        &self,
        vertices: &[[f64; 3]; 3],
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, [f64; 2])> {
        let o = self.origin;
        let relative = |p: &[f64; 3]| [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
        let a = relative(&vertices[0]);
        let b = relative(&vertices[1]);
        let c = relative(&vertices[2]);
        // Each vertex sheared on its own: the same values in every triangle sharing it.
        let ax = a[KX] - self.shear_x * a[KZ];
        let ay = a[KY] - self.shear_y * a[KZ];
        let bx = b[KX] - self.shear_x * b[KZ];
        let by = b[KY] - self.shear_y * b[KZ];
        let cx = c[KX] - self.shear_x * c[KZ];
        let cy = c[KY] - self.shear_y * c[KZ];
        // Edge functions (u weighs vertex 0, v vertex 1, w vertex 2).
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let determinant = u + v + w;
        if determinant == 0.0 {
            return None;
        }
        let az = self.shear_z * a[KZ];
        let bz = self.shear_z * b[KZ];
        let cz = self.shear_z * c[KZ];
        let t = (u * az + v * bz + w * cz) / determinant;
        // Written so that NaN (a degenerate ray) is a miss.
        if !(t > t_min && t < t_max) {
            return None;
        }
        Some((t, [v / determinant, w / determinant]))
    }
}

/// The watertight, double-sided ray–triangle test on its own (what [`crate::SceneBvh`]
/// uses for every triangle): the hit with `t_min < t < t_max` as (t, [b1, b2]) — the
/// point is (1 − b1 − b2)·p0 + b1·p1 + b2·p2 — or `None`. For brute-force checks; a
/// loop over many triangles prepares the ray once ([`TriangleTest`]).
pub fn intersect_triangle(
    ray: &Ray,
    vertices: &[[f64; 3]; 3],
    t_min: f64,
    t_max: f64,
) -> Option<(f64, [f64; 2])> {
    TriangleTest::new(ray).intersect(vertices, t_min, t_max)
}

/// [`intersect_triangle`] with the ray's own constants (its axis order and shear)
/// computed once, for a test against many triangles: the same answer, bit for bit.
#[derive(Clone, Copy, Debug)]
pub struct TriangleTest(ShearedRay);

impl TriangleTest {
    /// `ray` prepared for the test.
    pub fn new(ray: &Ray) -> Self {
        Self(ShearedRay::new(ray))
    }

    /// As [`intersect_triangle`] with this test's ray.
    #[inline]
    pub fn intersect(
        &self,
        vertices: &[[f64; 3]; 3],
        t_min: f64,
        t_max: f64,
    ) -> Option<(f64, [f64; 2])> {
        self.0.intersect(vertices, t_min, t_max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hits_report_t_and_barycentrics_of_the_point() {
        let triangle = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        for direction in [[0.0, 0.0, -1.0], [0.0, 0.0, 2.0], [0.3, 0.2, 0.5]] {
            let target = [0.5, 0.25, 0.0];
            let origin = [
                target[0] - 3.0 * direction[0],
                target[1] - 3.0 * direction[1],
                target[2] - 3.0 * direction[2],
            ];
            let ray = Ray::new(origin, direction);
            let (t, [b1, b2]) = intersect_triangle(&ray, &triangle, 0.0, f64::INFINITY).unwrap();
            assert!((t - 3.0).abs() < 1e-14, "{t}");
            assert!((b1 - 0.25).abs() < 1e-14 && (b2 - 0.125).abs() < 1e-14);
            // The open interval excludes its ends.
            assert!(intersect_triangle(&ray, &triangle, 0.0, t).is_none());
            assert!(intersect_triangle(&ray, &triangle, t, f64::INFINITY).is_none());
        }
        let miss = Ray::new([1.5, 1.5, 1.0], [0.0, 0.0, -1.0]);
        assert!(intersect_triangle(&miss, &triangle, 0.0, f64::INFINITY).is_none());
        let degenerate = Ray::new([0.5, 0.25, 1.0], [0.0, 0.0, 0.0]);
        assert!(intersect_triangle(&degenerate, &triangle, 0.0, f64::INFINITY).is_none());
        let nan = Ray::new([f64::NAN, 0.25, 1.0], [0.0, 0.0, -1.0]);
        assert!(intersect_triangle(&nan, &triangle, 0.0, f64::INFINITY).is_none());
    }

    /// Each of the six axis orders (the largest direction component along +x, −x, +y,
    /// −y, +z, −z) finds the point, t and barycentrics of a triangle across that axis.
    #[test]
    fn every_axis_order_hits_the_point_it_aims_at() {
        let mut orders = Vec::new();
        for axis in 0..3 {
            // A triangle in the plane across `axis` at 0: p0 at the origin, p1 two units
            // along the next axis, p2 two along the one after.
            let (next, after) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut triangle = [[0.0; 3]; 3];
            triangle[1][next] = 2.0;
            triangle[2][after] = 2.0;
            for sign in [1.0, -1.0] {
                // Aimed at b1 = 0.25, b2 = 0.125 from 3 units away, slightly oblique.
                let mut target = [0.0; 3];
                target[next] = 0.5;
                target[after] = 0.25;
                let mut direction = [0.0; 3];
                direction[axis] = sign;
                direction[next] = 0.1;
                direction[after] = -0.2;
                let origin: [f64; 3] = std::array::from_fn(|i| target[i] - 3.0 * direction[i]);
                let ray = Ray::new(origin, direction);
                let sheared = ShearedRay::new(&ray);
                assert_eq!(sheared.kz, axis);
                orders.push((sheared.kx, sheared.ky, sheared.kz));
                let (t, [b1, b2]) =
                    intersect_triangle(&ray, &triangle, 0.0, f64::INFINITY).unwrap();
                assert!((t - 3.0).abs() < 1e-14, "axis {axis} sign {sign}: t {t}");
                assert!(
                    (b1 - 0.25).abs() < 1e-14 && (b2 - 0.125).abs() < 1e-14,
                    "axis {axis} sign {sign}: {b1} {b2}"
                );
            }
        }
        orders.sort();
        orders.dedup();
        assert_eq!(orders.len(), 6, "{orders:?}");
    }
}
