//! Vectors, rays and the analytic primitives, each with its exact ray
//! intersection: sphere, plane, parallelogram (quad), disk, capsule,
//! ellipsoid and axis-aligned box.

use std::ops::{Add, Mul, Neg, Sub};

/// A point or direction in 3-D.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct V3(pub(crate) f64, pub(crate) f64, pub(crate) f64);

impl V3 {
    pub(crate) fn dot(self, o: Self) -> f64 {
        self.0 * o.0 + self.1 * o.1 + self.2 * o.2
    }
    pub(crate) fn cross(self, o: Self) -> Self {
        Self(
            self.1 * o.2 - self.2 * o.1,
            self.2 * o.0 - self.0 * o.2,
            self.0 * o.1 - self.1 * o.0,
        )
    }
    pub(crate) fn length(self) -> f64 {
        self.dot(self).sqrt()
    }
    pub(crate) fn unit(self) -> Self {
        self * (1.0 / self.length())
    }
    /// Component-wise quotient.
    pub(crate) fn over(self, o: Self) -> Self {
        Self(self.0 / o.0, self.1 / o.1, self.2 / o.2)
    }
}

impl Add for V3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self(self.0 + o.0, self.1 + o.1, self.2 + o.2)
    }
}
impl Sub for V3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self(self.0 - o.0, self.1 - o.1, self.2 - o.2)
    }
}
impl Mul<f64> for V3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self(self.0 * s, self.1 * s, self.2 * s)
    }
}
impl Neg for V3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self(-self.0, -self.1, -self.2)
    }
}

/// A ray `origin + t · direction`, at a time in the shutter interval.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Ray {
    pub(crate) origin: V3,
    /// Unit length.
    pub(crate) direction: V3,
    /// In `[0, 1)`: where in the shutter interval the ray is traced.
    pub(crate) time: f64,
}

impl Ray {
    pub(crate) fn at(&self, t: f64) -> V3 {
        self.origin + self.direction * t
    }
}

/// Rays closer than this to their origin are ignored (self-intersection).
pub(crate) const T_MIN: f64 = 1e-7;

/// A hit: the ray parameter and the unit normal facing the ray's side the
/// shape was defined with (outward for solids).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Hit {
    pub(crate) t: f64,
    pub(crate) normal: V3,
}

/// An analytic shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Shape {
    /// Centre, radius; the centre moves by `velocity · time` over the
    /// shutter (zero for a still sphere).
    Sphere {
        centre: V3,
        radius: f64,
        velocity: V3,
    },
    /// The infinite plane through `point` with unit `normal`.
    Plane { point: V3, normal: V3 },
    /// The parallelogram `corner + a·u + b·v`, `a, b` in `[0, 1]`.
    Quad { corner: V3, u: V3, v: V3 },
    /// A flat disk.
    Disk { centre: V3, normal: V3, radius: f64 },
    /// All points within `radius` of the segment `a..b`.
    Capsule { a: V3, b: V3, radius: f64 },
    /// An axis-aligned ellipsoid with the given semi-axes.
    Ellipsoid { centre: V3, radii: V3 },
    /// An axis-aligned box.
    Cuboid { min: V3, max: V3 },
}

/// The smaller root of `a t² + 2 b t + c` above [`T_MIN`], if any.
fn nearest_root(a: f64, half_b: f64, c: f64, t_max: f64) -> Option<f64> {
    let disc = half_b * half_b - a * c;
    if disc < 0.0 || a == 0.0 {
        return None;
    }
    let s = disc.sqrt();
    // The numerically stable pair of roots.
    let q = -(half_b + half_b.signum() * s);
    let (r0, r1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    let (lo, hi) = if r0 < r1 { (r0, r1) } else { (r1, r0) };
    [lo, hi].into_iter().find(|&t| t > T_MIN && t < t_max)
}

fn sphere(origin: V3, direction: V3, centre: V3, radius: f64, t_max: f64) -> Option<Hit> {
    let oc = origin - centre;
    let t = nearest_root(
        direction.dot(direction),
        oc.dot(direction),
        oc.dot(oc) - radius * radius,
        t_max,
    )?;
    let normal = (origin + direction * t - centre) * (1.0 / radius);
    Some(Hit { t, normal })
}

/// Where the ray meets the plane through `point` with normal `normal`.
fn plane_t(ray: &Ray, point: V3, normal: V3, t_max: f64) -> Option<f64> {
    let denom = normal.dot(ray.direction);
    if denom == 0.0 {
        return None;
    }
    let t = (point - ray.origin).dot(normal) / denom;
    (t > T_MIN && t < t_max).then_some(t)
}

impl Shape {
    /// The nearest hit with `T_MIN < t < t_max`.
    pub(crate) fn intersect(&self, ray: &Ray, t_max: f64) -> Option<Hit> {
        match *self {
            Self::Sphere {
                centre,
                radius,
                velocity,
            } => sphere(
                ray.origin,
                ray.direction,
                centre + velocity * ray.time,
                radius,
                t_max,
            ),
            Self::Plane { point, normal } => {
                plane_t(ray, point, normal, t_max).map(|t| Hit { t, normal })
            }
            Self::Quad { corner, u, v } => {
                let normal = u.cross(v).unit();
                let t = plane_t(ray, corner, normal, t_max)?;
                let d = ray.at(t) - corner;
                // Coordinates in the (u, v) basis, through the dual basis.
                let n = u.cross(v);
                let nn = n.dot(n);
                let a = d.cross(v).dot(n) / nn;
                let b = u.cross(d).dot(n) / nn;
                ((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)).then_some(Hit { t, normal })
            }
            Self::Disk {
                centre,
                normal,
                radius,
            } => {
                let t = plane_t(ray, centre, normal, t_max)?;
                let d = ray.at(t) - centre;
                (d.dot(d) <= radius * radius).then_some(Hit { t, normal })
            }
            Self::Capsule { a, b, radius } => capsule(ray, a, b, radius, t_max),
            Self::Ellipsoid { centre, radii } => {
                // A unit sphere after scaling space by 1/radii; the normal
                // goes back through the inverse transpose (1/radii again).
                let origin = (ray.origin - centre).over(radii);
                let direction = ray.direction.over(radii);
                let hit = sphere(origin, direction, V3::default(), 1.0, t_max)?;
                Some(Hit {
                    t: hit.t,
                    normal: hit.normal.over(radii).unit(),
                })
            }
            Self::Cuboid { min, max } => cuboid(ray, min, max, t_max),
        }
    }
}

/// The capsule: the cylinder's side between the end caps, or one of the two
/// end spheres, whichever is nearest.
fn capsule(ray: &Ray, a: V3, b: V3, radius: f64, t_max: f64) -> Option<Hit> {
    let axis = b - a;
    let length = axis.length();
    let w = axis * (1.0 / length);
    let oc = ray.origin - a;
    // Components perpendicular to the axis.
    let d_perp = ray.direction - w * ray.direction.dot(w);
    let o_perp = oc - w * oc.dot(w);
    let mut best: Option<Hit> = None;
    if let Some(t) = nearest_root(
        d_perp.dot(d_perp),
        o_perp.dot(d_perp),
        o_perp.dot(o_perp) - radius * radius,
        t_max,
    ) {
        let s = (ray.at(t) - a).dot(w);
        if (0.0..=length).contains(&s) {
            let normal = (ray.at(t) - (a + w * s)) * (1.0 / radius);
            best = Some(Hit { t, normal });
        }
    }
    for end in [a, b] {
        let limit = best.map_or(t_max, |h| h.t);
        if let Some(hit) = sphere(ray.origin, ray.direction, end, radius, limit) {
            best = Some(hit);
        }
    }
    best
}

/// Slab test for an axis-aligned box; the normal is the face's.
fn cuboid(ray: &Ray, min: V3, max: V3, t_max: f64) -> Option<Hit> {
    let o = [ray.origin.0, ray.origin.1, ray.origin.2];
    let d = [ray.direction.0, ray.direction.1, ray.direction.2];
    let lo = [min.0, min.1, min.2];
    let hi = [max.0, max.1, max.2];
    let (mut t_near, mut t_far) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut near_axis, mut far_axis) = (0, 0);
    for k in 0..3 {
        let inv = 1.0 / d[k];
        let (t0, t1) = ((lo[k] - o[k]) * inv, (hi[k] - o[k]) * inv);
        let (t0, t1) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
        if t0 > t_near {
            (t_near, near_axis) = (t0, k);
        }
        if t1 < t_far {
            (t_far, far_axis) = (t1, k);
        }
    }
    if t_near > t_far {
        return None;
    }
    let (t, axis) = if t_near > T_MIN {
        (t_near, near_axis)
    } else {
        (t_far, far_axis)
    };
    if !(t > T_MIN && t < t_max) {
        return None;
    }
    let p = ray.at(t);
    let centre = (min + max) * 0.5;
    let mut n = [0.0; 3];
    let p = [p.0, p.1, p.2];
    let c = [centre.0, centre.1, centre.2];
    n[axis] = if p[axis] > c[axis] { 1.0 } else { -1.0 };
    Some(Hit {
        t,
        normal: V3(n[0], n[1], n[2]),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(origin: V3, direction: V3) -> Ray {
        Ray {
            origin,
            direction: direction.unit(),
            time: 0.0,
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    fn close_v(a: V3, b: V3) -> bool {
        (a - b).length() < 1e-12
    }

    #[test]
    fn sphere_hits_at_distance_minus_radius_and_moves_with_time() {
        let s = Shape::Sphere {
            centre: V3(0.0, 0.0, 5.0),
            radius: 2.0,
            velocity: V3(1.0, 0.0, 0.0),
        };
        let r = ray(V3(0.0, 0.0, 0.0), V3(0.0, 0.0, 1.0));
        let hit = s.intersect(&r, f64::INFINITY).expect("hits");
        assert!(close(hit.t, 3.0), "t = {}", hit.t);
        assert!(close_v(hit.normal, V3(0.0, 0.0, -1.0)), "{:?}", hit.normal);
        // At time 0.5 the centre is at x = 0.5: t = 5 − sqrt(4 − 0.25).
        let moved = Ray { time: 0.5, ..r };
        let hit = s.intersect(&moved, f64::INFINITY).expect("hits");
        assert!(close(hit.t, 5.0 - 3.75_f64.sqrt()), "t = {}", hit.t);
        // From inside: the far side.
        let inside = ray(V3(-1.0, 0.0, 5.0), V3(0.0, 1.0, 0.0));
        let hit = s.intersect(&inside, f64::INFINITY).expect("hits");
        assert!(close(hit.t, 3.0_f64.sqrt()), "t = {}", hit.t);
        // A miss, and a hit past t_max.
        assert!(
            s.intersect(&ray(V3(0.0, 3.0, 0.0), V3(0.0, 0.0, 1.0)), 9.0)
                .is_none(),
            "miss"
        );
        assert!(s.intersect(&r, 2.9).is_none(), "beyond t_max");
    }

    #[test]
    fn plane_quad_and_disk_match_closed_forms() {
        let up = V3(0.0, 1.0, 0.0);
        let plane = Shape::Plane {
            point: V3(0.0, -1.0, 0.0),
            normal: up,
        };
        // A ray down at 45 degrees from height 0 reaches y = −1 at t = √2.
        let r = ray(V3(0.0, 0.0, 0.0), V3(0.0, -1.0, 1.0));
        let hit = plane.intersect(&r, f64::INFINITY).expect("hits");
        assert!(close(hit.t, 2.0_f64.sqrt()), "t = {}", hit.t);
        assert!(
            plane
                .intersect(&ray(V3(0.0, 0.0, 0.0), V3(0.0, 1.0, 1.0)), 1e9)
                .is_none(),
            "up"
        );
        let quad = Shape::Quad {
            corner: V3(-1.0, -1.0, 3.0),
            u: V3(2.0, 0.0, 0.0),
            v: V3(0.0, 1.0, 0.0),
        };
        let hit = quad.intersect(&ray(V3(0.5, -0.5, 0.0), V3(0.0, 0.0, 1.0)), 1e9);
        assert!(close(hit.expect("inside").t, 3.0), "quad");
        // Just outside the v edge (y = 0) misses.
        assert!(
            quad.intersect(&ray(V3(0.5, 0.01, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
                .is_none(),
            "outside"
        );
        let disk = Shape::Disk {
            centre: V3(0.0, 0.0, 2.0),
            normal: V3(0.0, 0.0, -1.0),
            radius: 1.0,
        };
        let hit = disk
            .intersect(&ray(V3(0.0, 0.0, 0.0), V3(0.6, 0.0, 2.0)), 1e9)
            .expect("hits");
        assert!(close(hit.t, (0.36_f64 + 4.0).sqrt()), "t = {}", hit.t);
        assert!(
            disk.intersect(&ray(V3(0.0, 0.0, 0.0), V3(1.01, 0.0, 2.0)), 1e9)
                .is_none(),
            "rim"
        );
    }

    #[test]
    fn capsule_ellipsoid_and_box_match_closed_forms() {
        let capsule = Shape::Capsule {
            a: V3(-1.0, 0.0, 4.0),
            b: V3(1.0, 0.0, 4.0),
            radius: 0.5,
        };
        // Side: straight at the body.
        let hit = capsule
            .intersect(&ray(V3(0.3, 0.0, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
            .expect("side");
        assert!(close(hit.t, 3.5), "t = {}", hit.t);
        assert!(close_v(hit.normal, V3(0.0, 0.0, -1.0)), "{:?}", hit.normal);
        // Along the axis: the end sphere's pole at x = −1.5.
        let hit = capsule
            .intersect(&ray(V3(-5.0, 0.0, 4.0), V3(1.0, 0.0, 0.0)), 1e9)
            .expect("end");
        assert!(close(hit.t, 3.5), "t = {}", hit.t);
        // The end cap off-axis: sphere at (1, 0, 4), ray at x = 1.3.
        let hit = capsule
            .intersect(&ray(V3(1.3, 0.0, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
            .expect("cap");
        assert!(close(hit.t, 4.0 - 0.16_f64.sqrt()), "t = {}", hit.t);
        let ellipsoid = Shape::Ellipsoid {
            centre: V3(0.0, 0.0, 10.0),
            radii: V3(1.0, 2.0, 3.0),
        };
        let hit = ellipsoid
            .intersect(&ray(V3(0.0, 0.0, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
            .expect("z");
        assert!(close(hit.t, 7.0), "t = {}", hit.t);
        let hit = ellipsoid
            .intersect(&ray(V3(0.0, -9.0, 10.0), V3(0.0, 1.0, 0.0)), 1e9)
            .expect("y");
        assert!(close(hit.t, 7.0), "t = {}", hit.t);
        // The normal at (x, y, z) on the surface is ∝ (x/a², y/b², z/c²).
        let r = ray(V3(0.5, 0.0, 0.0), V3(0.0, 0.0, 1.0));
        let hit = ellipsoid.intersect(&r, 1e9).expect("off-centre");
        let z = 3.0 * (1.0 - 0.25_f64).sqrt();
        assert!(close(hit.t, 10.0 - z), "t = {}", hit.t);
        let expected = V3(0.5, 0.0, -z / 9.0).unit();
        assert!(
            close_v(hit.normal, expected),
            "{:?} vs {expected:?}",
            hit.normal
        );
        let cuboid = Shape::Cuboid {
            min: V3(-1.0, -1.0, 2.0),
            max: V3(1.0, 1.0, 3.0),
        };
        let hit = cuboid
            .intersect(&ray(V3(0.0, 0.0, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
            .expect("front");
        assert!(close(hit.t, 2.0), "t = {}", hit.t);
        assert!(close_v(hit.normal, V3(0.0, 0.0, -1.0)), "{:?}", hit.normal);
        let hit = cuboid
            .intersect(&ray(V3(0.0, 0.0, 2.5), V3(1.0, 0.0, 0.0)), 1e9)
            .expect("inside");
        assert!(close(hit.t, 1.0), "t = {}", hit.t);
        assert!(close_v(hit.normal, V3(1.0, 0.0, 0.0)), "{:?}", hit.normal);
        assert!(
            cuboid
                .intersect(&ray(V3(0.0, 1.5, 0.0), V3(0.0, 0.0, 1.0)), 1e9)
                .is_none(),
            "miss"
        );
    }
}
