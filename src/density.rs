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
    fn a_lattice_at_the_packing_density_is_one() {
        // Simple cubic lattice in 1-D: spacing r, density 1.
        let got = relative_radius::<1>(0.1, 10, 1.0).unwrap();
        assert!((got - 1.0).abs() < 1e-12, "{got}");
        assert_eq!(relative_radius::<9>(0.1, 10, 1.0), None, "no known density");
        assert_eq!(relative_radius::<2>(0.1, 0, 1.0), None, "no points");
    }
}
