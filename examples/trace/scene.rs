//! What is rendered: objects (a shape and a procedural texture), one quad
//! area light, the shading model of each scene, and the four scenes
//! themselves (`figure`, `dof`, `checker`, `motion`).
//!
//! Radiance is one number (grey): the samplers' differences show as well in
//! grey as in colour, and the error maths stays simple.

use crate::camera::Camera;
use crate::geometry::{Hit, Ray, Shape, V3};
use std::f64::consts::PI;

/// A procedural reflectance in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Texture {
    Constant(f64),
    /// Squares of side `size` on the two world axes `axes` (0 = x, 1 = y,
    /// 2 = z), alternating `dark` and `light`.
    Checker {
        size: f64,
        axes: [usize; 2],
        dark: f64,
        light: f64,
    },
    /// Bands of width `period / 2` across world axis `axis`.
    Stripes {
        period: f64,
        axis: usize,
        dark: f64,
        light: f64,
    },
}

impl Texture {
    pub(crate) fn at(&self, p: V3) -> f64 {
        let coord = |axis: usize| [p.0, p.1, p.2][axis.min(2)];
        match *self {
            Self::Constant(value) => value,
            Self::Checker {
                size,
                axes,
                dark,
                light,
            } => {
                let cell = (coord(axes[0]) / size).floor() + (coord(axes[1]) / size).floor();
                if cell.rem_euclid(2.0) < 0.5 {
                    light
                } else {
                    dark
                }
            }
            Self::Stripes {
                period,
                axis,
                dark,
                light,
            } => {
                if (coord(axis) / period).rem_euclid(1.0) < 0.5 {
                    light
                } else {
                    dark
                }
            }
        }
    }
}

/// A shape with a Lambertian reflectance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Object {
    pub(crate) shape: Shape,
    pub(crate) texture: Texture,
}

/// A one-sided parallelogram emitter `corner + a·u + b·v`, emitting
/// `radiance` on the side of `u × v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct QuadLight {
    pub(crate) corner: V3,
    pub(crate) u: V3,
    pub(crate) v: V3,
    pub(crate) radiance: f64,
}

impl QuadLight {
    fn normal(&self) -> V3 {
        self.u.cross(self.v).unit()
    }

    fn area(&self) -> f64 {
        self.u.cross(self.v).length()
    }

    /// One sample of the irradiance at `p` (unit normal `n`) from the light,
    /// ignoring occlusion: the point `u` of the light, chosen uniformly by
    /// area, gives `L · A · cos θ_p · cos θ_light / d²`, whose mean over `u`
    /// is the irradiance. Returns it with the direction and distance to the
    /// light point, for the shadow ray.
    pub(crate) fn irradiance_sample(&self, p: V3, n: V3, u: [f64; 2]) -> (f64, V3, f64) {
        let y = self.corner + self.u * u[0] + self.v * u[1];
        let w = y - p;
        let d2 = w.dot(w);
        let d = d2.sqrt();
        let dir = w * (1.0 / d);
        let cos_p = n.dot(dir);
        let cos_l = -self.normal().dot(dir);
        if cos_p <= 0.0 || cos_l <= 0.0 {
            return (0.0, dir, d);
        }
        (self.radiance * self.area() * cos_p * cos_l / d2, dir, d)
    }
}

/// How a scene turns a hit into radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Shading {
    /// Reflectance / π times the direct light of the quad light (one
    /// shadow ray per camera sample), plus a constant ambient term.
    AreaLight { ambient: f64 },
    /// Reflectance times a fixed lighting from direction `towards` (no
    /// sampling, no shadows): only the camera's dimensions make noise.
    Headlight { towards: V3, ambient: f64 },
    /// Reflectance itself (a texture seen as it is).
    Unlit,
}

/// A scene: the camera, the objects, the light and the shading.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Scene {
    pub(crate) name: &'static str,
    pub(crate) camera: Camera,
    pub(crate) objects: Vec<Object>,
    pub(crate) light: Option<QuadLight>,
    pub(crate) shading: Shading,
    /// The radiance of rays that hit nothing.
    pub(crate) background: f64,
    /// Does the scene read the time (a moving object)?
    pub(crate) uses_time: bool,
}

/// The scene names `--scene` accepts.
pub(crate) const SCENES: [&str; 4] = ["figure", "dof", "checker", "motion"];

impl Scene {
    /// The nearest hit of `ray` closer than `t_max`, with its object.
    fn nearest(&self, ray: &Ray, t_max: f64) -> Option<(Hit, &Object)> {
        let mut best: Option<(Hit, &Object)> = None;
        for object in &self.objects {
            let limit = best.map_or(t_max, |(h, _)| h.t);
            if let Some(hit) = object.shape.intersect(ray, limit) {
                best = Some((hit, object));
            }
        }
        best
    }

    /// Is anything between `p` and the point `distance` away along `dir`?
    fn occluded(&self, p: V3, dir: V3, distance: f64, time: f64) -> bool {
        let ray = Ray {
            origin: p,
            direction: dir,
            time,
        };
        let limit = distance * (1.0 - 1e-9);
        self.objects
            .iter()
            .any(|o| o.shape.intersect(&ray, limit).is_some())
    }

    /// The radiance arriving along `ray`; `light_sample` picks the point on
    /// the light for the direct-lighting estimate (the sampler's next pair
    /// of dimensions after the camera's).
    pub(crate) fn radiance(&self, ray: &Ray, light_sample: [f64; 2]) -> f64 {
        let light_hit = self.light.and_then(|light| {
            let quad = Shape::Quad {
                corner: light.corner,
                u: light.u,
                v: light.v,
            };
            let hit = quad.intersect(ray, f64::INFINITY)?;
            (ray.direction.dot(light.normal()) < 0.0).then_some((hit.t, light.radiance))
        });
        let limit = light_hit.map_or(f64::INFINITY, |(t, _)| t);
        let Some((hit, object)) = self.nearest(ray, limit) else {
            return light_hit.map_or(self.background, |(_, radiance)| radiance);
        };
        let p = ray.at(hit.t);
        // Shade the side the ray sees.
        let n = if hit.normal.dot(ray.direction) > 0.0 {
            -hit.normal
        } else {
            hit.normal
        };
        let albedo = object.texture.at(p);
        match self.shading {
            Shading::Unlit => albedo,
            Shading::Headlight { towards, ambient } => {
                albedo * (ambient + (1.0 - ambient) * n.dot(towards).max(0.0))
            }
            Shading::AreaLight { ambient } => {
                let direct = self.light.map_or(0.0, |light| {
                    let (e, dir, d) = light.irradiance_sample(p, n, light_sample);
                    if e > 0.0 && !self.occluded(p + n * 1e-6, dir, d, ray.time) {
                        e
                    } else {
                        0.0
                    }
                });
                albedo * (ambient + direct / PI)
            }
        }
    }

    /// A hash of everything that decides the scene's image (its full
    /// description and the image size): a cached reference is valid only
    /// for the same key.
    pub(crate) fn key(&self) -> u64 {
        let text = format!("{self:?}");
        let words: Vec<u64> = text
            .as_bytes()
            .chunks(8)
            .map(|c| c.iter().fold(0_u64, |w, &b| w << 8 | u64::from(b)))
            .collect();
        crate::common::samplers::hash(&words)
    }

    /// The scene called `name` (one of [`SCENES`]) for an image of `size`.
    pub(crate) fn by_name(name: &str, size: [u32; 2]) -> Option<Self> {
        match name {
            "figure" => Some(figure(size)),
            "dof" => Some(dof(size)),
            "checker" => Some(checker(size)),
            "motion" => Some(motion(size)),
            _ => None,
        }
    }
}

fn solid(shape: Shape, albedo: f64) -> Object {
    Object {
        shape,
        texture: Texture::Constant(albedo),
    }
}

fn still_sphere(centre: V3, radius: f64) -> Shape {
    Shape::Sphere {
        centre,
        radius,
        velocity: V3::default(),
    }
}

fn capsule(a: V3, b: V3, radius: f64) -> Shape {
    Shape::Capsule { a, b, radius }
}

const UP: V3 = V3(0.0, 1.0, 0.0);

/// The floor of `dof` and `motion`: the plane y = 0 in squares of 0.5.
fn checkered_floor() -> Object {
    Object {
        shape: Shape::Plane {
            point: V3::default(),
            normal: UP,
        },
        texture: Texture::Checker {
            size: 0.5,
            axes: [0, 2],
            dark: 0.15,
            light: 0.8,
        },
    }
}

/// The stand-in for the paper's Buddha (Fig. 2): a seated figure of 15
/// analytic primitives on a plinth and a floor, lit from above by one quad
/// light. Curved silhouettes (head, torso, arms), self-occlusion (arms over
/// the torso, hands in the lap), contact shadows (figure on plinth, plinth
/// on floor) and soft penumbrae (the light is 1.8 × 1.4).
pub(crate) fn figure(size: [u32; 2]) -> Scene {
    let body = 0.75;
    let mut objects = vec![
        solid(
            Shape::Plane {
                point: V3::default(),
                normal: UP,
            },
            0.6,
        ),
        solid(
            Shape::Cuboid {
                min: V3(-1.1, 0.0, -0.8),
                max: V3(1.1, 0.35, 0.8),
            },
            0.5,
        ),
        // Crossed legs and the knees at their ends.
        solid(
            capsule(V3(-0.8, 0.52, -0.25), V3(0.45, 0.5, -0.5), 0.18),
            body,
        ),
        solid(
            capsule(V3(0.8, 0.52, -0.25), V3(-0.45, 0.5, -0.5), 0.18),
            body,
        ),
        solid(
            Shape::Ellipsoid {
                centre: V3(0.0, 1.1, 0.0),
                radii: V3(0.55, 0.62, 0.38),
            },
            body,
        ),
        solid(capsule(V3(0.0, 1.6, 0.0), V3(0.0, 1.78, 0.0), 0.13), body),
        solid(still_sphere(V3(0.0, 1.98, 0.0), 0.3), body),
        solid(still_sphere(V3(0.0, 2.3, 0.02), 0.13), body),
        // The hands, in the lap.
        solid(
            Shape::Ellipsoid {
                centre: V3(0.0, 0.72, -0.45),
                radii: V3(0.22, 0.08, 0.14),
            },
            body,
        ),
        // A halo behind the head, tilted up to catch the light.
        solid(
            Shape::Disk {
                centre: V3(0.0, 1.95, 0.5),
                normal: V3(0.0, 0.35, -1.0).unit(),
                radius: 0.75,
            },
            0.85,
        ),
    ];
    for side in [-1.0, 1.0] {
        let shoulder = V3(side * 0.52, 1.45, 0.0);
        let elbow = V3(side * 0.66, 0.95, -0.12);
        let wrist = V3(side * 0.16, 0.74, -0.42);
        objects.push(solid(capsule(shoulder, elbow, 0.12), body));
        objects.push(solid(capsule(elbow, wrist, 0.1), body));
        objects.push(solid(
            Shape::Ellipsoid {
                centre: V3(side * 0.3, 1.95, 0.04),
                radii: V3(0.06, 0.15, 0.07),
            },
            body,
        ));
    }
    Scene {
        name: "figure",
        camera: Camera::pinhole(V3(0.4, 1.9, -5.0), V3(0.0, 1.05, 0.0), 34.0, size),
        objects,
        light: Some(QuadLight {
            corner: V3(-0.9, 4.0, -1.2),
            u: V3(1.8, 0.0, 0.0),
            v: V3(0.0, 0.0, 1.4),
            radiance: 16.0,
        }),
        shading: Shading::AreaLight { ambient: 0.03 },
        background: 0.02,
        uses_time: false,
    }
}

/// Depth of field (Figs. 3, 4): a thin lens with a large aperture, in
/// focus on the middle sphere; one sphere in front, one behind, before a
/// fine high-contrast checkered backdrop and a checkered floor.
pub(crate) fn dof(size: [u32; 2]) -> Scene {
    let stripes = |axis| Texture::Stripes {
        period: 0.25,
        axis,
        dark: 0.1,
        light: 0.9,
    };
    let objects = vec![
        checkered_floor(),
        Object {
            shape: Shape::Quad {
                corner: V3(-6.0, 0.0, 5.0),
                u: V3(12.0, 0.0, 0.0),
                v: V3(0.0, 6.0, 0.0),
            },
            texture: Texture::Checker {
                size: 0.3,
                axes: [0, 1],
                dark: 0.02,
                light: 0.98,
            },
        },
        Object {
            shape: still_sphere(V3(-1.1, 0.55, -2.6), 0.55),
            texture: stripes(1),
        },
        Object {
            shape: still_sphere(V3(0.2, 0.7, 0.0), 0.7),
            texture: stripes(0),
        },
        Object {
            shape: still_sphere(V3(1.8, 0.9, 2.8), 0.9),
            texture: stripes(1),
        },
    ];
    Scene {
        name: "dof",
        camera: Camera::pinhole(V3(0.0, 1.2, -6.0), V3(0.2, 0.9, 0.0), 40.0, size)
            .with_lens(0.3, 6.0),
        objects,
        light: None,
        shading: Shading::Headlight {
            towards: V3(-0.4, 0.8, -0.6).unit(),
            ambient: 0.25,
        },
        background: 0.5,
        uses_time: false,
    }
}

/// The classic (Figs. 5, 6): an infinite checkerboard of unit squares
/// receding to the horizon, pinhole camera, unlit; a grey sky.
pub(crate) fn checker(size: [u32; 2]) -> Scene {
    Scene {
        name: "checker",
        camera: Camera::pinhole(V3(0.0, 1.0, 0.0), V3(0.0, 0.45, 4.0), 50.0, size),
        objects: vec![Object {
            shape: Shape::Plane {
                point: V3::default(),
                normal: UP,
            },
            texture: Texture::Checker {
                size: 1.0,
                axes: [0, 2],
                dark: 0.0,
                light: 1.0,
            },
        }],
        light: None,
        shading: Shading::Unlit,
        background: 0.5,
        uses_time: false,
    }
}

/// Motion blur: a striped sphere crossing the frame during the shutter, a
/// still one beside it, over a checkered floor.
pub(crate) fn motion(size: [u32; 2]) -> Scene {
    let objects = vec![
        checkered_floor(),
        Object {
            shape: Shape::Sphere {
                centre: V3(-1.4, 0.9, 0.0),
                radius: 0.5,
                velocity: V3(2.2, 0.4, 0.0),
            },
            texture: Texture::Stripes {
                period: 0.2,
                axis: 1,
                dark: 0.05,
                light: 0.95,
            },
        },
        Object {
            shape: still_sphere(V3(0.9, 0.45, 1.2), 0.45),
            texture: Texture::Stripes {
                period: 0.2,
                axis: 0,
                dark: 0.1,
                light: 0.9,
            },
        },
    ];
    Scene {
        name: "motion",
        camera: Camera::pinhole(V3(0.0, 1.6, -5.0), V3(0.0, 0.6, 0.0), 38.0, size),
        objects,
        light: None,
        shading: Shading::Headlight {
            towards: V3(-0.3, 0.9, -0.5).unit(),
            ambient: 0.25,
        },
        background: 0.5,
        uses_time: true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The irradiance of a uniform polygonal emitter, in closed form
    /// (Lambert's formula): `E = L/2 · |Σ Θ_i (n · Γ_i)|`, with `Θ_i` the
    /// angle edge `i` subtends at `p` and `Γ_i` the unit normal of the plane
    /// through `p` and that edge.
    fn polygon_irradiance(p: V3, n: V3, vertices: &[V3], radiance: f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..vertices.len() {
            let a = (vertices[i] - p).unit();
            let b = (vertices[(i + 1) % vertices.len()] - p).unit();
            let angle = a.dot(b).clamp(-1.0, 1.0).acos();
            sum += angle * n.dot(a.cross(b).unit());
        }
        radiance / 2.0 * sum.abs()
    }

    /// The light estimator's mean over its 2-D sample equals the closed-form
    /// irradiance (midpoint rule on a 1024² grid: the estimator is smooth,
    /// so the rule's error is far below the tolerance), at points under the
    /// light, beside it, and on tilted surfaces (the light wholly above
    /// each surface's horizon, where the closed form holds).
    #[test]
    fn light_estimator_is_unbiased() {
        let light = figure([8, 8]).light.expect("figure has a light");
        let vertices = [
            light.corner,
            light.corner + light.u,
            light.corner + light.u + light.v,
            light.corner + light.v,
        ];
        let cases = [
            (V3(0.0, 0.0, 0.0), UP),
            (V3(2.0, 0.5, 1.0), UP),
            (V3(0.3, 1.0, -2.0), V3(0.0, 1.0, -1.0).unit()),
            (V3(-3.0, 0.0, 4.0), V3(0.2, 1.0, -0.3).unit()),
        ];
        for (p, n) in cases {
            let m = 1024;
            let mut sum = 0.0;
            for i in 0..m {
                for j in 0..m {
                    let u = [
                        (f64::from(i) + 0.5) / f64::from(m),
                        (f64::from(j) + 0.5) / f64::from(m),
                    ];
                    sum += light.irradiance_sample(p, n, u).0;
                }
            }
            let mean = sum / f64::from(m * m);
            let exact = polygon_irradiance(p, n, &vertices, light.radiance);
            assert!(
                (mean - exact).abs() < 1e-5 * exact,
                "at {p:?}, n {n:?}: estimator mean {mean}, closed form {exact}"
            );
        }
    }

    #[test]
    fn textures_alternate() {
        let checker = Texture::Checker {
            size: 1.0,
            axes: [0, 2],
            dark: 0.0,
            light: 1.0,
        };
        assert_eq!(checker.at(V3(0.5, 0.0, 0.5)), 1.0, "origin square");
        assert_eq!(checker.at(V3(1.5, 0.0, 0.5)), 0.0, "next along x");
        assert_eq!(checker.at(V3(-0.5, 7.0, 0.5)), 0.0, "negative x, any y");
        assert_eq!(checker.at(V3(-0.5, 0.0, -0.5)), 1.0, "diagonal");
        let stripes = Texture::Stripes {
            period: 1.0,
            axis: 1,
            dark: 0.0,
            light: 1.0,
        };
        assert_eq!(stripes.at(V3(0.0, 0.25, 0.0)), 1.0, "first half");
        assert_eq!(stripes.at(V3(0.0, 0.75, 0.0)), 0.0, "second half");
    }

    #[test]
    fn every_scene_builds_and_its_key_tracks_the_size() {
        for name in SCENES {
            let a = Scene::by_name(name, [16, 16]).expect("known");
            let b = Scene::by_name(name, [16, 12]).expect("known");
            assert_ne!(a.key(), b.key(), "{name}: size in the key");
            assert_eq!(
                a.key(),
                Scene::by_name(name, [16, 16]).expect("known").key(),
                "{name}"
            );
        }
        assert!(Scene::by_name("buddha", [4, 4]).is_none(), "unknown");
        let figure = figure([4, 4]);
        assert!(
            (10..=20).contains(&(figure.objects.len() - 1)),
            "10-20 primitives besides the floor"
        );
    }
}
