//! The camera: a pinhole, or a thin lens whose aperture is sampled through
//! Shirley and Chiu's concentric mapping (the same for every sampler, so
//! only the samplers differ).

use crate::geometry::{Ray, V3};
use bridson::CameraSample;
use std::f64::consts::FRAC_PI_4;

/// A perspective camera looking from `eye` towards `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Camera {
    eye: V3,
    /// The image plane's axes at unit distance: right, down, forward.
    right: V3,
    down: V3,
    forward: V3,
    /// Half-width and half-height of the image plane at unit distance.
    half: [f64; 2],
    /// The aperture radius (0: a pinhole) and the distance in focus.
    lens_radius: f64,
    focus: f64,
    /// The image size in pixels.
    size: [u32; 2],
}

impl Camera {
    /// A pinhole camera with vertical field of view `fov_degrees` for an
    /// image of `size` pixels.
    pub(crate) fn pinhole(eye: V3, target: V3, fov_degrees: f64, size: [u32; 2]) -> Self {
        let forward = (target - eye).unit();
        // pbrt's convention: looking down +z with y up, +x is to the right
        // (a left-handed frame on the film).
        let right = V3(0.0, 1.0, 0.0).cross(forward).unit();
        let down = right.cross(forward);
        let half_h = (fov_degrees.to_radians() / 2.0).tan();
        let half_w = half_h * f64::from(size[0]) / f64::from(size[1]);
        Self {
            eye,
            right,
            down,
            forward,
            half: [half_w, half_h],
            lens_radius: 0.0,
            focus: 1.0,
            size,
        }
    }

    /// The same camera with a thin lens of radius `lens_radius`, in focus
    /// at distance `focus` along the view direction.
    pub(crate) fn with_lens(self, lens_radius: f64, focus: f64) -> Self {
        Self {
            lens_radius,
            focus,
            ..self
        }
    }

    /// The ray of a camera sample taken in `pixel`: the film offset moves
    /// inside the pixel (a box filter: every offset weighs the same), the
    /// lens sample picks the point on the aperture, and the time rides
    /// along.
    pub(crate) fn ray(&self, pixel: [u32; 2], sample: &CameraSample) -> Ray {
        let x = (f64::from(pixel[0]) + sample.film[0]) / f64::from(self.size[0]);
        let y = (f64::from(pixel[1]) + sample.film[1]) / f64::from(self.size[1]);
        let on_plane = self.forward
            + self.right * ((2.0 * x - 1.0) * self.half[0])
            + self.down * ((2.0 * y - 1.0) * self.half[1]);
        if self.lens_radius == 0.0 {
            return Ray {
                origin: self.eye,
                direction: on_plane.unit(),
                time: sample.time,
            };
        }
        // Every ray through the lens meets the chief ray at the focus
        // plane (distance `focus` along `forward`).
        let focus_point = self.eye + on_plane * self.focus;
        let [dx, dy] = concentric_disk(sample.lens);
        let origin =
            self.eye + self.right * (dx * self.lens_radius) + self.down * (dy * self.lens_radius);
        Ray {
            origin,
            direction: (focus_point - origin).unit(),
            time: sample.time,
        }
    }
}

/// Shirley and Chiu's concentric mapping of `[0, 1)²` onto the unit disk:
/// squares of the centred square `[−1, 1]²` go to rings, area-preserving
/// up to the constant π/4, so well-spread points stay well spread.
pub(crate) fn concentric_disk(u: [f64; 2]) -> [f64; 2] {
    let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    if a == 0.0 && b == 0.0 {
        return [0.0, 0.0];
    }
    let (radius, angle) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    [radius * angle.cos(), radius * angle.sin()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mapping's Jacobian determinant is π everywhere (the unit square's
    /// area 1 goes to the disk's area π): checked by central differences at
    /// points of a grid, away from the diagonals where it is not smooth.
    #[test]
    fn concentric_mapping_preserves_area() {
        let h = 1e-6;
        let mut checked = 0;
        for i in 0..50 {
            for j in 0..50 {
                let u = [(f64::from(i) + 0.37) / 50.0, (f64::from(j) + 0.61) / 50.0];
                let (a, b) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
                if (a.abs() - b.abs()).abs() < 1e-3 {
                    continue;
                }
                let d = |du: [f64; 2]| {
                    let p = concentric_disk([u[0] + du[0], u[1] + du[1]]);
                    let m = concentric_disk([u[0] - du[0], u[1] - du[1]]);
                    [(p[0] - m[0]) / (2.0 * h), (p[1] - m[1]) / (2.0 * h)]
                };
                let (dx, dy) = (d([h, 0.0]), d([0.0, h]));
                let det = dx[0] * dy[1] - dx[1] * dy[0];
                assert!(
                    (det.abs() - std::f64::consts::PI).abs() < 1e-5,
                    "Jacobian {det} at {u:?}"
                );
                checked += 1;
            }
        }
        assert!(checked > 2400, "checked {checked}");
        // And the whole square lands inside the disk, its edge on the rim.
        for &u in &[[0.0, 0.5], [0.5, 0.0], [0.0, 0.0], [0.999, 0.3]] {
            let [x, y] = concentric_disk(u);
            assert!(x * x + y * y <= 1.0 + 1e-12, "{u:?}");
        }
        let [x, y] = concentric_disk([0.0, 0.3]);
        assert!((x * x + y * y - 1.0).abs() < 1e-12, "edge to rim");
    }

    #[test]
    fn the_centre_ray_looks_at_the_target_and_lens_rays_meet_in_focus() {
        let size = [64, 48];
        let camera = Camera::pinhole(V3(0.0, 1.0, -5.0), V3(0.0, 1.0, 0.0), 40.0, size);
        let centre = CameraSample {
            film: [0.0, 0.0],
            time: 0.0,
            lens: [0.5, 0.5],
        };
        let ray = camera.ray([32, 24], &centre);
        assert!(
            (ray.direction - V3(0.0, 0.0, 1.0)).length() < 1e-12,
            "{ray:?}"
        );
        // The top row looks up (rows grow going down); the right column
        // towards +x.
        let top = camera.ray([32, 0], &centre);
        assert!(top.direction.1 > 0.0, "{top:?}");
        let right = camera.ray([63, 24], &centre);
        assert!(right.direction.0 > 0.0, "{right:?}");
        let lens = camera.with_lens(0.5, 5.0);
        for u in [[0.1, 0.2], [0.9, 0.5], [0.5, 0.95]] {
            let r = lens.ray([10, 7], &CameraSample { lens: u, ..centre });
            let p = ray_at_z(&r, 0.0);
            let q = ray_at_z(&camera.ray([10, 7], &centre), 0.0);
            assert!(
                (p - q).length() < 1e-12,
                "in focus at z = 0: {p:?} vs {q:?}"
            );
        }
    }

    fn ray_at_z(ray: &Ray, z: f64) -> V3 {
        ray.at((z - ray.origin.2) / ray.direction.2)
    }
}
