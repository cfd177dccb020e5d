//! Statistics of a 2-D point set over a pixel raster, where border bias
//! shows: how density varies with the position inside a pixel, how many
//! points each pixel holds, and the density in thin bands along the pixel
//! edges against the pixel interiors.
//!
//! Every function takes a plain list of points in raster coordinates and
//! the raster size, so a batch set over a `W × H` box and a set streamed
//! pixel by pixel are measured the same way.

/// A `width × height` raster. Pixel `(i, j)` is the unit square
/// `[i, i + 1) × [j, j + 1)` in raster coordinates (x to the right, y down).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Raster {
    pub(crate) width: u32,
    pub(crate) height: u32,
}

impl Raster {
    /// The pixel holding `p` and `p`'s position inside it (each coordinate
    /// in `[0, 1)`), or `None` if `p` is outside the raster.
    pub(crate) fn locate(self, p: [f64; 2]) -> Option<([u32; 2], [f64; 2])> {
        let (x, y) = (p[0], p[1]);
        if !(x >= 0.0 && x < f64::from(self.width) && y >= 0.0 && y < f64::from(self.height)) {
            return None;
        }
        let (fx, fy) = (x.floor(), y.floor());
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "whole numbers in 0..width and 0..height, checked above"
        )]
        let pixel = [fx as u32, fy as u32];
        // Exact: x and floor(x) are within a factor of 2 or x < 1.
        Some((pixel, [x - fx, y - fy]))
    }

    /// The number of pixels.
    pub(crate) fn pixels(self) -> usize {
        usize::try_from(u64::from(self.width) * u64::from(self.height))
            .expect("pixel count fits usize")
    }
}

/// Density as a function of position inside a pixel, accumulated over the
/// whole image: every point's position inside its pixel falls into one of
/// `bins × bins` bins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct InPixelDensity {
    bins: usize,
    /// Row-major, row = bin of the y position.
    counts: Vec<u64>,
    inside: u64,
    outside: u64,
}

impl InPixelDensity {
    /// No points yet, `bins × bins` bins per pixel.
    pub(crate) fn new(bins: usize) -> Self {
        let bins = bins.max(1);
        Self {
            bins,
            counts: vec![0; bins * bins],
            inside: 0,
            outside: 0,
        }
    }

    /// Adds the points of one set over `raster`; points outside it are only
    /// counted.
    pub(crate) fn add(&mut self, points: &[[f64; 2]], raster: Raster) {
        for &p in points {
            match raster.locate(p) {
                Some((_, inner)) => {
                    let [bx, by] = inner.map(|t| bin(t, self.bins));
                    self.counts[by * self.bins + bx] += 1;
                    self.inside += 1;
                }
                None => self.outside += 1,
            }
        }
    }

    pub(crate) fn bins(&self) -> usize {
        self.bins
    }

    /// Points that fell inside the raster.
    pub(crate) fn inside(&self) -> u64 {
        self.inside
    }

    /// Points that fell outside the raster (none for a correct sampler).
    pub(crate) fn outside(&self) -> u64 {
        self.outside
    }

    /// The density of each bin relative to the mean (1 = average), row-major
    /// as the bins; all NaN when no point fell inside.
    pub(crate) fn relative(&self) -> Vec<f64> {
        let mean = self.inside as f64 / self.counts.len() as f64;
        self.counts.iter().map(|&c| c as f64 / mean).collect()
    }
}

/// The bin of a position `t` in `[0, 1)` among `bins` equal bins.
fn bin(t: f64, bins: usize) -> usize {
    let b = (t * bins as f64).floor();
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "t is in [0, 1), so b is in 0..bins (clamped for safety)"
    )]
    let b = b.max(0.0) as usize;
    b.min(bins - 1)
}

/// The per-pixel point counts as a histogram: entry `k` is the number of
/// pixels holding exactly `k` points.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct CountHistogram {
    pub(crate) pixels_with: Vec<u64>,
    /// Points outside the raster, not counted in any pixel.
    pub(crate) outside: u64,
}

/// Counts the points of each pixel of `raster` and histograms the counts.
pub(crate) fn pixel_count_histogram(points: &[[f64; 2]], raster: Raster) -> CountHistogram {
    let mut per_pixel = vec![0usize; raster.pixels()];
    let mut outside = 0;
    let width = usize::try_from(raster.width).expect("width fits usize");
    for &p in points {
        match raster.locate(p) {
            Some(([i, j], _)) => {
                let (i, j) = (usize_of(i), usize_of(j));
                per_pixel[j * width + i] += 1;
            }
            None => outside += 1,
        }
    }
    let most = per_pixel.iter().copied().max().unwrap_or(0);
    let mut pixels_with = vec![0u64; most + 1];
    for c in per_pixel {
        pixels_with[c] += 1;
    }
    CountHistogram {
        pixels_with,
        outside,
    }
}

fn usize_of(v: u32) -> usize {
    usize::try_from(v).expect("u32 fits usize")
}

/// Density in the band `band` pixels wide along each of the four pixel
/// edges, divided by the density in the pixel interior (the inner square
/// `[band, 1 − band)²`), summed over all pixels. 1 means no border bias.
/// The bands overlap at the corners; each is a full strip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct EdgeRatios {
    pub(crate) band: f64,
    /// Along the edge at the pixel's low x.
    pub(crate) left: f64,
    /// Along the edge at the pixel's high x.
    pub(crate) right: f64,
    /// Along the edge at the pixel's low y (y grows downwards).
    pub(crate) top: f64,
    /// Along the edge at the pixel's high y.
    pub(crate) bottom: f64,
}

/// Edge-band to interior density ratios of `points` over `raster` (NaN
/// where the interior is empty). `band` must be in `(0, 0.5)`.
pub(crate) fn edge_ratios(points: &[[f64; 2]], raster: Raster, band: f64) -> EdgeRatios {
    assert!(band > 0.0 && band < 0.5, "band {band} must be in (0, 0.5)");
    let [mut left, mut right, mut top, mut bottom, mut interior] = [0u64; 5];
    for &p in points {
        let Some((_, [u, v])) = raster.locate(p) else {
            continue;
        };
        left += u64::from(u < band);
        right += u64::from(u >= 1.0 - band);
        top += u64::from(v < band);
        bottom += u64::from(v >= 1.0 - band);
        let inner = band..1.0 - band;
        interior += u64::from(inner.contains(&u) && inner.contains(&v));
    }
    // Densities per unit area of pixel; the pixel count cancels.
    let interior_density = interior as f64 / ((1.0 - 2.0 * band) * (1.0 - 2.0 * band));
    let ratio = |count: u64| (count as f64 / band) / interior_density;
    EdgeRatios {
        band,
        left: ratio(left),
        right: ratio(right),
        top: ratio(top),
        bottom: ratio(bottom),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bridson::rand::RngExt;

    fn uniform(n: usize, raster: Raster, seed: u64) -> Vec<[f64; 2]> {
        let mut rng = bridson::seeded_rng(seed);
        (0..n)
            .map(|_| {
                [
                    rng.random::<f64>() * f64::from(raster.width),
                    rng.random::<f64>() * f64::from(raster.height),
                ]
            })
            .collect()
    }

    #[test]
    fn locate_finds_the_pixel_and_the_offset() {
        let r = Raster {
            width: 3,
            height: 2,
        };
        assert_eq!(r.locate([0.0, 0.0]), Some(([0, 0], [0.0, 0.0])), "corner");
        assert_eq!(r.locate([2.5, 1.25]), Some(([2, 1], [0.5, 0.25])), "inside");
        assert_eq!(r.locate([3.0, 0.5]), None, "right edge is outside");
        assert_eq!(r.locate([-1e-300, 0.5]), None, "left of the raster");
        assert_eq!(r.locate([f64::NAN, 0.5]), None, "NaN");
        let below_one = 1.0 - f64::EPSILON / 2.0;
        let (_, inner) = r.locate([below_one, 0.0]).expect("inside");
        assert!(inner[0] < 1.0, "offset stays below 1");
    }

    #[test]
    fn uniform_points_have_no_border_bias() {
        let raster = Raster {
            width: 40,
            height: 30,
        };
        let points = uniform(200_000, raster, 1);
        let e = edge_ratios(&points, raster, 0.1);
        for (name, v) in [
            ("left", e.left),
            ("right", e.right),
            ("top", e.top),
            ("bottom", e.bottom),
        ] {
            // 20 000 points a band: 1σ ≈ 0.008.
            assert!((v - 1.0).abs() < 0.04, "{name} = {v}");
        }
        let mut d = InPixelDensity::new(8);
        d.add(&points, raster);
        assert_eq!(d.inside(), 200_000, "all inside");
        for (k, v) in d.relative().iter().enumerate() {
            // 3 125 points a bin: 1σ ≈ 0.018.
            assert!((v - 1.0).abs() < 0.09, "bin {k}: {v}");
        }
    }

    #[test]
    fn edge_points_raise_the_edge_ratio() {
        let raster = Raster {
            width: 1,
            height: 1,
        };
        // One point in the interior, one in the left band (and in no other).
        let e = edge_ratios(&[[0.5, 0.5], [0.05, 0.5]], raster, 0.1);
        // Band density 1/0.1 = 10; interior density 1/0.64.
        assert!((e.left - 6.4).abs() < 1e-12, "left {}", e.left);
        assert_eq!((e.right, e.top, e.bottom), (0.0, 0.0, 0.0), "others");
        let empty = edge_ratios(&[], raster, 0.1);
        assert!(empty.left.is_nan(), "no interior points: undefined");
    }

    #[test]
    fn histogram_counts_every_pixel_and_point() {
        let raster = Raster {
            width: 3,
            height: 2,
        };
        let points = [[0.5, 0.5], [0.6, 0.1], [2.9, 1.9], [7.0, 0.0]];
        let h = pixel_count_histogram(&points, raster);
        assert_eq!(h.pixels_with, vec![4, 1, 1], "4 empty, 1 single, 1 pair");
        assert_eq!(h.outside, 1, "one outside");
        let big = Raster {
            width: 17,
            height: 9,
        };
        let points = uniform(5000, big, 2);
        let h = pixel_count_histogram(&points, big);
        assert_eq!(
            h.pixels_with.iter().sum::<u64>(),
            17 * 9,
            "every pixel once"
        );
        let total: u64 = (0..).zip(&h.pixels_with).map(|(k, &c)| k * c).sum();
        assert_eq!(total, 5000, "every point once");
    }

    #[test]
    fn density_bins_positions_inside_the_pixel() {
        let raster = Raster {
            width: 2,
            height: 2,
        };
        let mut d = InPixelDensity::new(2);
        // Both points in the top-left quarter of their pixels.
        d.add(&[[0.1, 0.2], [1.4, 1.3], [5.0, 5.0]], raster);
        assert_eq!(d.bins(), 2, "bins");
        assert_eq!((d.inside(), d.outside()), (2, 1), "counts");
        assert_eq!(d.relative(), vec![4.0, 0.0, 0.0, 0.0], "relative density");
    }
}
