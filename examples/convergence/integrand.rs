//! The test integrands of the study: functions on `[0, 1)²` whose integral
//! is known exactly, each drawn at random (centre, size, rotation, and a
//! toroidal shift of the input) so that an average over instances does not
//! reward a sampler for the placement of one fixed edge.
//!
//! A toroidal shift `x ↦ frac(x + s)` maps `[0, 1)²` onto itself and keeps
//! area, so it never changes an integral: the exact value of a shifted
//! instance is that of the unshifted shape, clipped to the unit square. It
//! does move the shape's edges (and the square's own, where the shape
//! crosses them) to random places.

use bridson::rand::RngExt;
use core::f64::consts::{PI, TAU};
use std::str::FromStr;

/// The kinds of integrand, named as on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    /// The indicator of a disk on the torus (radius 0.05 to 0.45).
    Disk,
    /// The indicator of a rotated, scaled copy of the triangle `y < x`,
    /// clipped to the square.
    Triangle,
    /// The step `x < 1/3`, rotated about the square's centre.
    Step,
    /// An isotropic Gaussian on the torus (σ from 0.03 to 0.15).
    Gaussian,
    /// The bilinear `x y`.
    Bilinear,
}

impl Kind {
    /// Every kind, in the order of the study.
    pub(crate) const ALL: [Self; 5] = [
        Self::Disk,
        Self::Triangle,
        Self::Step,
        Self::Gaussian,
        Self::Bilinear,
    ];

    /// The name on the command line and in the output.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Disk => "disk",
            Self::Triangle => "triangle",
            Self::Step => "step",
            Self::Gaussian => "gaussian",
            Self::Bilinear => "bilinear",
        }
    }

    /// A random instance, drawn from `rng`.
    pub(crate) fn draw<R: RngExt + ?Sized>(self, rng: &mut R) -> Instance {
        let shift = [rng.random::<f64>(), rng.random::<f64>()];
        let shape = match self {
            Self::Disk => Shape::Disk {
                centre: [rng.random::<f64>(), rng.random::<f64>()],
                radius: 0.05 + 0.4 * rng.random::<f64>(),
            },
            Self::Triangle => {
                let centre = [rng.random::<f64>(), rng.random::<f64>()];
                let scale = 0.4 + 0.8 * rng.random::<f64>();
                let angle = TAU * rng.random::<f64>();
                // The triangle y < x of the unit square, about its centroid.
                let base = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
                let centroid = [2.0 / 3.0, 1.0 / 3.0];
                let vertices = base.map(|v| {
                    let p = rotate([v[0] - centroid[0], v[1] - centroid[1]], angle);
                    [centre[0] + scale * p[0], centre[1] + scale * p[1]]
                });
                Shape::Polygon(HalfPlanes::of_ccw_polygon(&vertices))
            }
            Self::Step => {
                // x < 1/3 is n·(p − c) < −1/6 with n = (1, 0), c the centre;
                // rotating the step about c rotates n.
                let angle = TAU * rng.random::<f64>();
                let normal = rotate([1.0, 0.0], angle);
                let offset = -1.0 / 6.0 + normal[0] * 0.5 + normal[1] * 0.5;
                Shape::Polygon(HalfPlanes(vec![(normal, offset)]))
            }
            Self::Gaussian => Shape::Gaussian {
                centre: [rng.random::<f64>(), rng.random::<f64>()],
                sigma: 0.03 + 0.12 * rng.random::<f64>(),
            },
            Self::Bilinear => Shape::Bilinear,
        };
        let exact = shape.integral();
        Instance {
            shape,
            shift,
            exact,
        }
    }
}

impl FromStr for Kind {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == text)
            .ok_or_else(|| format!("unknown integrand {text:?}; known: {}", names()))
    }
}

/// The names of every kind, comma-separated (for help and errors).
pub(crate) fn names() -> String {
    Kind::ALL.map(Kind::name).join(",")
}

/// `v` turned by `angle` radians anticlockwise.
fn rotate(v: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

/// A convex region as the intersection of half-planes `n·p < d`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HalfPlanes(Vec<([f64; 2], f64)>);

impl HalfPlanes {
    /// The inside of an anticlockwise convex polygon.
    fn of_ccw_polygon(vertices: &[[f64; 2]]) -> Self {
        let planes = (0..vertices.len())
            .map(|i| {
                let a = vertices[i];
                let b = vertices[(i + 1) % vertices.len()];
                // The outward normal of edge a → b of an anticlockwise
                // polygon is (dy, −dx).
                let normal = [b[1] - a[1], a[0] - b[0]];
                (normal, normal[0] * a[0] + normal[1] * a[1])
            })
            .collect();
        Self(planes)
    }

    fn contains(&self, p: [f64; 2]) -> bool {
        self.0.iter().all(|&(n, d)| n[0] * p[0] + n[1] * p[1] < d)
    }

    /// The area of the region inside the unit square: the square clipped
    /// by each half-plane in turn (Sutherland–Hodgman), then the shoelace
    /// formula.
    fn area_in_unit_square(&self) -> f64 {
        let mut polygon = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        for &(n, d) in &self.0 {
            polygon = clip(&polygon, n, d);
        }
        shoelace(&polygon)
    }
}

/// The part of a convex polygon where `n·p <= d`.
fn clip(polygon: &[[f64; 2]], n: [f64; 2], d: f64) -> Vec<[f64; 2]> {
    let side = |p: [f64; 2]| n[0] * p[0] + n[1] * p[1] - d;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for i in 0..polygon.len() {
        let a = polygon[i];
        let b = polygon[(i + 1) % polygon.len()];
        let (sa, sb) = (side(a), side(b));
        if sa <= 0.0 {
            out.push(a);
        }
        if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
            let t = sa / (sa - sb);
            out.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }
    out
}

/// The area of a simple polygon, either orientation.
fn shoelace(polygon: &[[f64; 2]]) -> f64 {
    let twice: f64 = (0..polygon.len())
        .map(|i| {
            let a = polygon[i];
            let b = polygon[(i + 1) % polygon.len()];
            a[0] * b[1] - b[0] * a[1]
        })
        .sum();
    twice.abs() / 2.0
}

/// The difference `a − b` on the unit torus, each coordinate in
/// `[−1/2, 1/2]`.
fn torus_delta(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [0, 1].map(|i| {
        let d = a[i] - b[i];
        d - d.round()
    })
}

/// What an instance integrates, before the toroidal shift.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Shape {
    /// Inside the disk on the torus (`radius < 1/2`, so it never overlaps
    /// itself).
    Disk { centre: [f64; 2], radius: f64 },
    /// Inside a convex region (a clipped triangle, a half-plane).
    Polygon(HalfPlanes),
    /// `exp(−|x − c|²/2σ²)` with `x − c` the shortest difference on the
    /// torus: the Gaussian restricted to the unit square centred on `c`.
    Gaussian { centre: [f64; 2], sigma: f64 },
    /// `x y`.
    Bilinear,
}

impl Shape {
    fn value(&self, p: [f64; 2]) -> f64 {
        match self {
            Self::Disk { centre, radius } => {
                let [dx, dy] = torus_delta(p, *centre);
                f64::from(u8::from(dx * dx + dy * dy < radius * radius))
            }
            Self::Polygon(region) => f64::from(u8::from(region.contains(p))),
            Self::Gaussian { centre, sigma } => {
                let [dx, dy] = torus_delta(p, *centre);
                (-(dx * dx + dy * dy) / (2.0 * sigma * sigma)).exp()
            }
            Self::Bilinear => p[0] * p[1],
        }
    }

    /// The exact integral over the unit square (to rounding; the
    /// Gaussian's to about 1e-13, see [`gaussian_1d`]).
    fn integral(&self) -> f64 {
        match self {
            Self::Disk { radius, .. } => PI * radius * radius,
            Self::Polygon(region) => region.area_in_unit_square(),
            Self::Gaussian { sigma, .. } => gaussian_1d(*sigma).powi(2),
            Self::Bilinear => 0.25,
        }
    }
}

/// `∫ exp(−t²/2σ²) dt` over `[−1/2, 1/2]`: composite Simpson with 2¹⁵
/// intervals. For σ >= 0.03 its error is below `h⁴ max|f⁗| / 180 ≈ 3e-14`.
/// (Rust's standard library has no `erf`; with it this is
/// `σ √(2π) erf(1/(2√2 σ))`.)
pub(crate) fn gaussian_1d(sigma: f64) -> f64 {
    const INTERVALS: u32 = 1 << 15;
    let h = 1.0 / f64::from(INTERVALS);
    let f = |t: f64| (-(t * t) / (2.0 * sigma * sigma)).exp();
    let inner: f64 = (1..INTERVALS)
        .map(|i| {
            let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
            weight * f(-0.5 + f64::from(i) * h)
        })
        .sum();
    h / 3.0 * (f(-0.5) + inner + f(0.5))
}

/// One random integrand: a shape seen through a toroidal shift, and its
/// exact integral.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Instance {
    shape: Shape,
    shift: [f64; 2],
    /// The integral over `[0, 1)²`.
    pub(crate) exact: f64,
}

impl Instance {
    /// The integrand at `p` in `[0, 1)²`: the shape at `frac(p + shift)`.
    pub(crate) fn value(&self, p: [f64; 2]) -> f64 {
        let q = [0, 1].map(|i| {
            let s = p[i] + self.shift[i];
            if s >= 1.0 { s - 1.0 } else { s }
        });
        self.shape.value(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_gives_known_areas() {
        let step = HalfPlanes(vec![([1.0, 0.0], 1.0 / 3.0)]);
        assert!(
            (step.area_in_unit_square() - 1.0 / 3.0).abs() < 1e-15,
            "x < 1/3"
        );
        let diagonal = HalfPlanes(vec![([-1.0, 1.0], 0.0)]);
        assert!(
            (diagonal.area_in_unit_square() - 0.5).abs() < 1e-15,
            "y < x"
        );
        // A triangle inside the square keeps its whole area.
        let inside = HalfPlanes::of_ccw_polygon(&[[0.1, 0.1], [0.5, 0.1], [0.5, 0.4]]);
        assert!(
            (inside.area_in_unit_square() - 0.06).abs() < 1e-15,
            "inside"
        );
        assert!(inside.contains([0.4, 0.15]), "a point inside");
        assert!(!inside.contains([0.2, 0.3]), "a point outside");
        // Wholly outside.
        let outside = HalfPlanes::of_ccw_polygon(&[[2.0, 2.0], [3.0, 2.0], [3.0, 3.0]]);
        assert!(outside.area_in_unit_square().abs() < 1e-15, "outside");
    }

    #[test]
    fn the_gaussian_integral_matches_the_untruncated_one_when_narrow() {
        // At σ = 0.03 the square cuts the Gaussian at 16.7 σ: the tails
        // lost are far below 1e-40, so the integral is σ √(2π).
        let sigma = 0.03;
        let expected = sigma * (TAU).sqrt();
        let got = gaussian_1d(sigma);
        assert!((got - expected).abs() < 1e-14, "{got} vs {expected}");
    }

    /// Each kind's exact integral against a plain Monte Carlo estimate of
    /// many independent points, within 5 standard errors (fixed seeds, so
    /// the test cannot flake), for several instances.
    #[test]
    fn exact_integrals_agree_with_brute_force_monte_carlo() {
        const POINTS: u32 = 200_000;
        for kind in Kind::ALL {
            for trial in 0..6_u64 {
                let seed = 1000 * trial + kind as u64;
                let mut rng = bridson::seeded_rng(seed);
                let instance = kind.draw(&mut rng);
                let (mut sum, mut sum_squares) = (0.0, 0.0);
                for _ in 0..POINTS {
                    let v = instance.value([rng.random::<f64>(), rng.random::<f64>()]);
                    sum += v;
                    sum_squares += v * v;
                }
                let n = f64::from(POINTS);
                let mean = sum / n;
                let variance = (sum_squares / n - mean * mean).max(0.0);
                let error = (variance / n).sqrt();
                let diff = (mean - instance.exact).abs();
                assert!(
                    diff <= 5.0 * error + 1e-12,
                    "{} seed {seed}: estimate {mean}, exact {}, standard error {error}",
                    kind.name(),
                    instance.exact
                );
            }
        }
    }

    #[test]
    fn names_parse_back() {
        for kind in Kind::ALL {
            assert_eq!(kind.name().parse::<Kind>(), Ok(kind), "{}", kind.name());
        }
        assert!("square".parse::<Kind>().is_err(), "unknown name");
    }
}
