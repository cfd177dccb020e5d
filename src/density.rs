//! How densely a point set is packed: the relative radius ρ.

use crate::vector::unit_ball_volume;

/// The densest packing fraction of equal balls known in `n` dimensions
/// (proven optimal for `n <= 3` and `n = 8`; the best lattice for `4..=7`).
fn packing_density(n: usize) -> Option<f64> {
    use core::f64::consts::PI;
    let pi2 = PI * PI;
    Some(match n {
        1 => 1.0,
        2 => PI / 12f64.sqrt(),
        3 => PI / 18f64.sqrt(),
        4 => pi2 / 16.0,
        5 => pi2 / (15.0 * 2f64.sqrt()),
        6 => pi2 * PI / (48.0 * 3f64.sqrt()),
        7 => pi2 * PI / 105.0,
        8 => pi2 * pi2 / 384.0,
        _ => return None,
    })
}

/// The relative radius ρ = r / r_max of `count` points with minimum
/// distance `radius` in a domain of the given `volume`, after Lagae & Dutré
/// (2008): `r_max` is the largest minimum distance `count` points could have
/// at the densest packing (in 2-D, `r_max = sqrt(2 / (√3 · count / area))`,
/// the hexagonal lattice). ρ near 0.75 is the classic Poisson disk look;
/// 1.0 is a lattice.
///
/// Returns `None` if `N` is 0 or above 8 (no packing density known), or
/// `count` is 0.
///
/// # Example: ρ of a square lattice
/// ```
/// // 100 points 0.1 apart in the unit square.
/// let rho = bridson::relative_radius::<2>(0.1, 100, 1.0).unwrap();
/// assert!((rho - 0.9306).abs() < 1e-4);
/// ```
pub fn relative_radius<const N: usize>(radius: f64, count: usize, volume: f64) -> Option<f64> {
    if count == 0 {
        return None;
    }
    let density = packing_density(N)?;
    #[expect(clippy::cast_precision_loss, reason = "a count, ratio only")]
    let per_point = volume / count as f64;
    // count balls of radius r_max/2 fill `density` of the volume.
    let half =
        (density * per_point / unit_ball_volume(N)).powf(1.0 / f64::from(u32::try_from(N).ok()?));
    Some(radius / (2.0 * half))
}

/// Points per `r^N` that the sampler makes at `k = 30` in the interior of a
/// large periodic box, for `N = 1..=8`: `[annulus, sphere]`. Measured with
/// `cargo run --release --example count_density -- interior` (4 seeds of
/// about 10⁵ points; 6-D up about 10⁴; standard error of the mean below
/// 0.1 % to 3-D). 1-D on-sphere candidates make a lattice of spacing
/// `r·(1 + 1e-7)`.
const INTERIOR: [[f64; 2]; 8] = [
    [0.66683, 0.99999],
    [0.61538, 0.88088],
    [0.57556, 0.72980],
    [0.57002, 0.70256],
    [0.59936, 0.72042],
    [0.66856, 0.78248],
    [0.78334, 0.90134],
    [0.96472, 1.08970],
];

/// The axis lengths, in radii, at which [`AXIS_2D`] and [`AXIS_3D`] are
/// tabulated.
const AXIS_X: [f64; 35] = [
    0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7, 1.8,
    1.9, 2.0, 2.25, 2.5, 2.75, 3.0, 3.5, 4.0, 4.5, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0, 16.0,
];

/// The effective length `E(x)`, in radii, of one axis `x` radii long:
/// with every other axis long and periodic, a box holds
/// `INTERIOR · E(x) · Π(other lengths / r)` points. `[[annulus bounded,
/// annulus periodic], [sphere bounded, sphere periodic]]`, at [`AXIS_X`].
/// Measured with `count_density -- axis --dim 2` (4 seeds, about 5·10⁴
/// points each). Past 16 radii, `E(x) = x + (E(16) - 16)`: a bounded axis
/// holds about half a radius more than its length (its two faces), a
/// periodic one exactly its length. Below about 2 radii a bounded axis
/// is erratic: most annulus candidates land outside the slab, so growth
/// dies out early, and the count varies widely between seeds.
const AXIS_2D: [[[f64; 35]; 2]; 2] = [
    [
        [
            0.0000, 0.0000, 0.0000, 0.0001, 0.0001, 0.0001, 0.0002, 0.0004, 0.0005, 0.0010, 0.0017,
            0.0059, 0.0056, 0.0131, 0.0382, 0.0636, 0.1195, 0.2446, 1.1378, 1.5497, 2.5052, 2.7373,
            2.9888, 3.2470, 3.5024, 3.9932, 4.4935, 4.9962, 5.4949, 6.4969, 7.4961, 8.4934,
            10.4925, 12.4962, 16.4896,
        ],
        [
            0.1544, 0.1636, 0.1682, 0.1697, 0.2955, 0.2780, 0.3756, 0.4960, 0.4266, 0.3105, 0.6608,
            0.8817, 0.9511, 1.1017, 1.1983, 1.0930, 1.4500, 1.3266, 1.6511, 1.8086, 2.0337, 2.3575,
            2.5026, 2.6979, 2.9611, 3.5154, 3.9964, 4.4949, 5.0005, 5.9954, 6.9950, 7.9966, 9.9972,
            11.9952, 15.9999,
        ],
    ],
    [
        [
            0.0000, 0.0000, 0.0007, 1.1397, 1.1408, 1.1431, 1.1473, 1.1541, 1.1652, 1.1939, 1.5549,
            1.8964, 2.0049, 2.0558, 2.0895, 2.1248, 2.1689, 2.2213, 2.2956, 2.4250, 2.6088, 2.9409,
            3.1088, 3.3078, 3.6168, 4.1057, 4.6138, 5.1061, 5.6119, 6.6092, 7.6079, 8.6072,
            10.6090, 12.6095, 16.6087,
        ],
        [
            0.0000, 0.0000, 0.0012, 1.1385, 1.1426, 1.1495, 1.1596, 1.1727, 1.1896, 1.2098, 1.2352,
            1.2648, 1.3012, 1.3447, 1.3977, 1.4643, 1.5481, 1.6578, 1.8241, 1.9816, 2.1129, 2.2999,
            2.4417, 2.7264, 3.0586, 3.4639, 4.0308, 4.4813, 5.0133, 6.0054, 7.0017, 8.0022,
            10.0007, 12.0002, 16.0032,
        ],
    ],
];

/// From 4-D to 8-D, the extra length of a bounded axis, in radii: a
/// bounded cube `x` radii wide holds `INTERIOR · (x + c)^N` points. Fitted
/// from bounded annulus cubes 2.5 to 8 radii wide, 3 seeds each:
/// `count_density -- cube --seeds 3` gives 0.345 (8 radii) and 0.357 (5)
/// in 4-D, 0.280 and 0.273 in 5-D, 0.235 and 0.209 in 6-D, 0.174 in 7-D
/// and 0.128 in 8-D (an earlier run with other seeds: 0.354, 0.325, 0.286,
/// 0.261, 0.234, 0.213, 0.179). No thin-axis table: a periodic axis counts
/// its length.
const BOUNDED_HIGH: [f64; 5] = [0.34, 0.27, 0.22, 0.18, 0.12];

/// As [`AXIS_2D`], for one axis of a 3-D box (`count_density -- axis
/// --dim 3`, 3 seeds).
const AXIS_3D: [[[f64; 35]; 2]; 2] = [
    [
        [
            0.0000, 0.0000, 0.0020, 0.8176, 0.9033, 0.9570, 1.0082, 1.0625, 1.1295, 1.2175, 1.3356,
            1.4721, 1.6086, 1.7338, 1.8443, 1.9503, 2.0470, 2.1407, 2.2342, 2.3294, 2.4245, 2.6714,
            2.9249, 3.1815, 3.4303, 3.9291, 4.4268, 4.9259, 5.4294, 6.4310, 7.4344, 8.4339,
            10.4374, 12.4387, 16.4397,
        ],
        [
            1.0719, 1.0704, 1.0753, 1.0794, 1.0860, 1.0943, 1.1064, 1.1210, 1.1370, 1.1616, 1.1905,
            1.2240, 1.2619, 1.3047, 1.3619, 1.4320, 1.5181, 1.6215, 1.7457, 1.8858, 2.0306, 2.2883,
            2.4955, 2.7335, 2.9950, 3.5067, 4.0024, 4.5041, 5.0066, 6.0060, 7.0109, 8.0027,
            10.0100, 12.0113, 16.0176,
        ],
    ],
    [
        [
            0.0000, 0.0001, 0.0793, 1.0034, 1.0624, 1.1035, 1.1434, 1.1900, 1.2529, 1.3383, 1.4574,
            1.5841, 1.7087, 1.8198, 1.9269, 2.0278, 2.1258, 2.2215, 2.3173, 2.4149, 2.5138, 2.7635,
            3.0126, 3.2637, 3.5105, 4.0122, 4.5117, 5.0118, 5.5124, 6.5120, 7.5117, 8.5076,
            10.5111, 12.5052, 16.5048,
        ],
        [
            0.0001, 0.0002, 0.0119, 0.9946, 1.0476, 1.0766, 1.1000, 1.1216, 1.1446, 1.1705, 1.1998,
            1.2328, 1.2717, 1.3191, 1.3738, 1.4399, 1.5213, 1.6256, 1.7559, 1.8973, 2.0400, 2.2698,
            2.4912, 2.7379, 2.9988, 3.4971, 3.9986, 4.4967, 4.9953, 5.9957, 6.9947, 7.9945, 9.9921,
            11.9936, 15.9900,
        ],
    ],
];

/// The attempts `k` at which [`ATTEMPTS_2D`] and [`ATTEMPTS_3D`] are
/// tabulated: count mode's range of `k` in 2-D and 3-D. Below 3, growth dies out at
/// random (in 2-D with `k = 1` after a handful of points), so no radius
/// gives a count.
pub(crate) const ATTEMPTS_K: [f64; 15] = [
    3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 30.0, 45.0, 60.0, 100.0, 150.0, 200.0, 300.0, 500.0, 1000.0,
];

/// How the density changes with `k` in 2-D, `[annulus, sphere]`, at each
/// [`ATTEMPTS_K`]: `[m, Δ]`, `m` the interior density over that at
/// `k = 30`, `Δ` the change (in radii) of a bounded axis's extra length
/// `E(x) - x`. Measured with `count_density -- attempts --points 50000
/// --seeds 2`: `m` in a periodic cube of 5·10⁴ points, the same seeds at
/// each `k`; `Δ` from bounded cubes 50 radii wide, 8 seeds (its noise,
/// about ±0.1 radii, moves a count of 1000 points by about 0.4 %).
const ATTEMPTS_2D: [[[f64; 2]; 15]; 2] = [
    [
        [0.80354, -0.5632],
        [0.86949, -0.1558],
        [0.90218, -0.1294],
        [0.93265, -0.0255],
        [0.96103, -0.1626],
        [0.97776, -0.0109],
        [1.00000, 0.0000],
        [1.01941, 0.0331],
        [1.03168, 0.0545],
        [1.05254, -0.0296],
        [1.06710, 0.0508],
        [1.07473, 0.1763],
        [1.08812, 0.1100],
        [1.09875, 0.2180],
        [1.11330, 0.0630],
    ],
    [
        [0.82571, -0.2047],
        [0.86112, -0.1729],
        [0.87794, 0.0035],
        [0.91145, -0.0405],
        [0.94985, -0.0930],
        [0.97292, -0.0452],
        [1.00000, 0.0000],
        [1.02028, 0.0258],
        [1.03074, 0.0319],
        [1.04451, 0.0489],
        [1.05114, -0.0253],
        [1.05539, 0.0405],
        [1.05782, 0.0513],
        [1.06183, 0.0588],
        [1.06430, 0.0514],
    ],
];

/// [`ATTEMPTS_2D`] in 3-D (bounded cubes 14 radii wide).
const ATTEMPTS_3D: [[[f64; 2]; 15]; 2] = [
    [
        [0.71690, -0.5866],
        [0.80205, -0.2958],
        [0.84997, -0.2101],
        [0.89275, -0.1269],
        [0.93793, -0.0929],
        [0.96562, -0.0232],
        [1.00000, 0.0000],
        [1.03150, 0.0468],
        [1.05108, 0.0629],
        [1.08574, 0.0782],
        [1.10679, 0.1067],
        [1.12267, 0.1079],
        [1.14350, 0.1277],
        [1.16243, 0.1432],
        [1.18906, 0.1807],
    ],
    [
        [0.74897, -0.4909],
        [0.84749, -0.2660],
        [0.88957, -0.1551],
        [0.92352, -0.0910],
        [0.95745, -0.0558],
        [0.97654, -0.0264],
        [1.00000, 0.0000],
        [1.01880, 0.0318],
        [1.03186, 0.0423],
        [1.05222, 0.0466],
        [1.06338, 0.0708],
        [1.07293, 0.0712],
        [1.08310, 0.0956],
        [1.09518, 0.0958],
        [1.10747, 0.1038],
    ],
];

/// `[m, Δ]` of [`ATTEMPTS_2D`] / [`ATTEMPTS_3D`] at `k`, linear between
/// the tabulated `k` (clamped to the table's ends); `[1, 0]` outside 2-D
/// and 3-D, where count mode is calibrated at `k = 30` only.
pub(crate) fn attempts_factors<const N: usize>(sphere: bool, k: u32) -> [f64; 2] {
    let tables = match N {
        2 => &ATTEMPTS_2D,
        3 => &ATTEMPTS_3D,
        _ => return [1.0, 0.0],
    };
    let table = if sphere { &tables[1] } else { &tables[0] };
    let k = f64::from(k);
    let mut previous = (ATTEMPTS_K[0], table[0]);
    if k <= previous.0 {
        return previous.1;
    }
    for (&at, &row) in ATTEMPTS_K.iter().zip(table).skip(1) {
        if k <= at {
            let (k0, [m0, d0]) = previous;
            let t = (k - k0) / (at - k0);
            return [m0 + (row[0] - m0) * t, d0 + (row[1] - d0) * t];
        }
        previous = (at, row);
    }
    previous.1
}

/// The effective length of an axis `x` radii long, from its table: linear
/// between the tabulated lengths, `E(x_0)` below the first, and
/// `x + (E(16) - 16)` past the last.
fn effective_length(table: &[f64; 35], x: f64) -> f64 {
    let mut previous = (AXIS_X[0], table[0]);
    if x <= previous.0 {
        return previous.1;
    }
    for (&at, &e) in AXIS_X.iter().zip(table).skip(1) {
        if x <= at {
            let (x0, e0) = previous;
            return e0 + (e - e0) * (x - x0) / (at - x0);
        }
        previous = (at, e);
    }
    x + (previous.1 - previous.0)
}

/// The expected number of points a sampler makes in a box with these
/// axis lengths and periodic axes, at radius `radius`, `k` attempts: the
/// interior density times the product of the axes' effective lengths, in
/// 2-D and 3-D both moved by [`attempts_factors`] (a bounded axis's extra
/// length by `Δ`, in full from 4 radii long, in proportion below).
/// 1-D: a bounded segment holds about one point more than a periodic one
/// (both ends can hold a point); 4-D up: [`BOUNDED_HIGH`].
pub(crate) fn expected_count<const N: usize>(
    extent: &[f64; N],
    periodic: &[bool; N],
    sphere: bool,
    attempts: u32,
    radius: f64,
) -> f64 {
    let Some(&[annulus, on_sphere]) = INTERIOR.get(N.wrapping_sub(1)) else {
        return f64::NAN;
    };
    let [m, delta] = attempts_factors::<N>(sphere, attempts);
    let interior = if sphere { on_sphere } else { annulus } * m;
    let [annulus_tables, sphere_tables] = if N == 2 { &AXIS_2D } else { &AXIS_3D };
    let high = BOUNDED_HIGH.get(N.wrapping_sub(4)).copied().unwrap_or(0.0);
    let [bounded, periodic_table] = if sphere {
        sphere_tables
    } else {
        annulus_tables
    };
    let mut count = interior;
    for (&length, &periodic) in extent.iter().zip(periodic) {
        let x = length / radius;
        count *= match (N, periodic) {
            (1, true) => x,
            (1, false) => x + 1.0 / interior,
            (2 | 3, true) => effective_length(periodic_table, x),
            (2 | 3, false) => effective_length(bounded, x) + delta * (x / 4.0).min(1.0),
            (_, true) => x,
            (_, false) => x + high,
        };
    }
    count
}

/// The radius at which a sampler of this box is expected to make `count`
/// points ([`expected_count`]), found by halving the radius until the box
/// is expected to hold `count` points, then bisecting. Only `+ - × ÷` are
/// used, so the radius, and hence the points, are the same on every
/// platform. Returns NaN if `N` is 0 or above 8.
pub(crate) fn radius_for_count<const N: usize>(
    extent: &[f64; N],
    periodic: &[bool; N],
    sphere: bool,
    attempts: u32,
    count: u64,
) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "a target, rounded is fine")]
    let target = count as f64;
    let at = |r: f64| expected_count(extent, periodic, sphere, attempts, r);
    // Start above every axis, where any box holds a handful of points.
    let mut high = extent.iter().fold(1e-300_f64, |m, &e| m.max(e)) * 64.0;
    if at(high).is_nan() {
        return f64::NAN;
    }
    let mut low = high;
    for _ in 0..2100 {
        if at(low) >= target || low == 0.0 {
            break;
        }
        high = low;
        low /= 2.0;
    }
    // `at(low) >= target > at(high)` (unless the box holds `count` points at
    // any radius): bisect to the last bit.
    for _ in 0..64 {
        let mid = low + (high - low) / 2.0;
        if mid <= low || mid >= high {
            break;
        }
        if at(mid) >= target {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_two_dimensional_formula() {
        let (r, n, a) = (0.01_f64, 7000usize, 1.0_f64);
        #[expect(clippy::cast_precision_loss, reason = "test")]
        let expected = r / (2.0 / (3f64.sqrt() * n as f64 / a)).sqrt();
        let got = relative_radius::<2>(r, n, a).unwrap();
        assert!((got - expected).abs() < 1e-12, "{got} vs {expected}");
    }

    #[test]
    fn effective_lengths_interpolate_and_extend() {
        let table = &AXIS_2D[0][0];
        assert_eq!(effective_length(table, 0.0), table[0], "below the table");
        assert_eq!(effective_length(table, 2.0), table[20], "on a tabulated x");
        let mid = effective_length(table, 2.125);
        assert!((mid - (table[20] + table[21]) / 2.0).abs() < 1e-12, "{mid}");
        let far = effective_length(table, 116.0);
        assert!((far - (100.0 + table[34])).abs() < 1e-9, "{far}");
    }

    #[test]
    fn the_radius_found_gives_the_count_asked_for() {
        for (extent, periodic, sphere) in [
            ([1.0, 1.0, 1.0], [false; 3], false),
            ([5.0, 0.5, 1.0], [true, false, true], true),
        ] {
            for count in [1000_u64, 12_345, 1 << 30] {
                let r = radius_for_count(&extent, &periodic, sphere, 30, count);
                #[expect(clippy::cast_precision_loss, reason = "test")]
                let target = count as f64;
                let at = expected_count(&extent, &periodic, sphere, 30, r);
                assert!((at / target - 1.0).abs() < 1e-9, "{count}: {at} at r = {r}");
                let beyond = expected_count(&extent, &periodic, sphere, 30, r * (1.0 + 1e-6));
                assert!(beyond < target, "{count}: the largest such radius");
            }
        }
        let none = radius_for_count(&[1.0; 9], &[false; 9], false, 30, 10);
        assert!(none.is_nan(), "no table past 8-D");
    }

    #[test]
    fn a_lattice_at_the_packing_density_is_one() {
        // Simple cubic lattice in 1-D: spacing r, density 1.
        let got = relative_radius::<1>(0.1, 10, 1.0).unwrap();
        assert!((got - 1.0).abs() < 1e-12, "{got}");
        assert_eq!(relative_radius::<9>(0.1, 10, 1.0), None, "no known density");
        assert_eq!(relative_radius::<2>(0.1, 0, 1.0), None, "no points");
    }
}
