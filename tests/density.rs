//! How densely the classic 2-D sampler packs: the relative radius
//! ρ = r / r_max (Lagae & Dutré 2008) must match Bridson's pattern.
//!
//! Run with `--nocapture` to see the measured values.

use bridson::{Candidates, Domain, PoissonDisk2};

/// About 10 000 points in the unit square (roughly 0.65 / r² for ρ ≈ 0.73).
const RADIUS: f64 = 0.008;
const SEEDS: [u64; 3] = [1, 2, 0xDEAD_BEEF];

/// ρ computed here from its definition, independently of the crate:
/// `r_max = sqrt(2 / (√3 · n / A))`, the spacing of the hexagonal lattice
/// with `n` points in area `A`.
fn rho(radius: f64, count: usize, area: f64) -> f64 {
    #[expect(clippy::cast_precision_loss, reason = "a count below 2^53")]
    let density = count as f64 / area;
    let r_max = (2.0 / (3f64.sqrt() * density)).sqrt();
    radius / r_max
}

fn sample(periodic: bool, candidates: Candidates, seed: u64) -> usize {
    let domain = Domain::from_extent([1.0, 1.0])
        .expect("unit square")
        .with_periodic([periodic; 2]);
    let sampler = PoissonDisk2::builder(domain, RADIUS)
        .attempts(30)
        .candidates(candidates)
        .build()
        .expect("valid sampler");
    sampler.iter_seeded(seed).count()
}

fn classic_rho(periodic: bool) {
    for seed in SEEDS {
        let n = sample(periodic, Candidates::Annulus, seed);
        let rho = rho(RADIUS, n, 1.0);
        eprintln!("Annulus k=30 periodic={periodic} seed={seed:#x}: n = {n}, rho = {rho:.4}");
        assert!(
            (5_000..=20_000).contains(&n),
            "periodic={periodic} seed={seed:#x}: {n} points, expected 5k-20k"
        );
        assert!(
            (0.70..=0.76).contains(&rho),
            "periodic={periodic} seed={seed:#x}: rho = {rho} (n = {n}, r = {RADIUS}), expected 0.70..=0.76"
        );
    }
}

#[test]
fn classic_relative_radius_bounded_square() {
    classic_rho(false);
}

#[test]
fn classic_relative_radius_periodic_square() {
    classic_rho(true);
}

#[test]
fn crate_relative_radius_matches_the_formula() {
    for (r, n, area) in [
        (RADIUS, 10_000, 1.0),
        (0.01, 7_000, 1.0),
        (0.1, 100, 1.0),
        (2.5, 123, 4_000.0),
        (1e-3, 1, 1e-6),
    ] {
        let ours = rho(r, n, area);
        let theirs = bridson::relative_radius::<2>(r, n, area).expect("N = 2, n > 0");
        assert!(
            ((theirs - ours) / ours).abs() < 1e-12,
            "relative_radius::<2>({r}, {n}, {area}) = {theirs}, formula gives {ours}"
        );
    }
    assert_eq!(
        bridson::relative_radius::<2>(0.1, 0, 1.0),
        None,
        "no points, no rho"
    );
}

#[test]
fn sphere_candidates_pack_denser_than_the_annulus() {
    for periodic in [false, true] {
        for seed in SEEDS {
            let annulus = rho(RADIUS, sample(periodic, Candidates::Annulus, seed), 1.0);
            let sphere = rho(RADIUS, sample(periodic, Candidates::Sphere, seed), 1.0);
            eprintln!(
                "periodic={periodic} seed={seed:#x}: rho Annulus = {annulus:.4}, Sphere = {sphere:.4}"
            );
            assert!(
                sphere < 1.0,
                "periodic={periodic} seed={seed:#x}: Sphere rho {sphere} beats the hexagonal lattice"
            );
            assert!(
                sphere > annulus,
                "periodic={periodic} seed={seed:#x}: Sphere rho {sphere} <= Annulus rho {annulus}"
            );
        }
    }
}
