//! Value stability: the first points for fixed seeds are pinned, so any
//! change to the stream a seed produces is caught and must be flagged as
//! **value-breaking** in CHANGELOG.md. The values were produced by the
//! implementation at the time of writing (shortest round-trip formatting)
//! and are compared bit for bit.
//!
//! If a change is intended, regenerate them and say so in the changelog.

use bridson::{Candidates, Domain, GridLayout, PoissonDisk};

fn check<const N: usize>(sampler: &PoissonDisk<N>, seed: u64, expected: &[[f64; N]]) {
    let got: Vec<[f64; N]> = sampler.iter_seeded(seed).take(expected.len()).collect();
    assert_eq!(got.len(), expected.len(), "seed {seed}: stream too short");
    for (i, (g, e)) in got.iter().zip(expected).enumerate() {
        let same = g.iter().zip(e).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "seed {seed}, point {i}: got {g:?}, pinned {e:?}");
    }
}

#[test]
fn two_d_annulus() {
    let sampler: PoissonDisk<2> =
        PoissonDisk::new(Domain::from_extent([1.0, 1.0]).unwrap(), 0.05).unwrap();
    check(
        &sampler,
        7,
        &[
            [0.05536043647833311, 0.17211585444811772],
            [0.15071435696149701, 0.1469151349955851],
            [0.1001110178616654, 0.11760731212678063],
            [0.13273937217073842, 0.07305376090571292],
        ],
    );
}

#[test]
fn two_d_sphere() {
    let sampler: PoissonDisk<2> =
        PoissonDisk::builder(Domain::from_extent([1.0, 1.0]).unwrap(), 0.05)
            .candidates(Candidates::Sphere)
            .build()
            .unwrap();
    check(
        &sampler,
        7,
        &[
            [0.05536043647833311, 0.17211585444811772],
            [0.02613604501116184, 0.21268598438842667],
            [0.005732595070232868, 0.16602669546082943],
            [0.07448203975826821, 0.12591666843792051],
        ],
    );
}

#[test]
fn two_d_periodic_shifted() {
    let sampler: PoissonDisk<2> = PoissonDisk::new(
        Domain::new([-3.0, 10.0], [-1.0, 10.5])
            .unwrap()
            .with_periodic([true, true]),
        0.05,
    )
    .unwrap();
    check(
        &sampler,
        11,
        &[
            [-1.2804341556431407, 10.403233575136666],
            [-1.3445229230452238, 10.384249216943351],
            [-1.4235760434872804, 10.424242889288767],
            [-1.2815815024218504, 10.462185691196314],
        ],
    );
}

#[test]
fn three_d_annulus() {
    let sampler: PoissonDisk<3> =
        PoissonDisk::new(Domain::from_extent([1.0; 3]).unwrap(), 0.1).unwrap();
    check(
        &sampler,
        1,
        &[
            [0.8116121588818848, 0.7471047161582187, 0.10015090353378375],
            [0.9802528272252196, 0.7331648630268325, 0.06662781086638492],
            [0.948798087011149, 0.8423685551624653, 0.10457637606266941],
            [0.935428785239562, 0.9942104167751008, 0.1935022258271038],
        ],
    );
}

#[test]
fn one_d_annulus() {
    let sampler: PoissonDisk<1> =
        PoissonDisk::new(Domain::from_extent([10.0]).unwrap(), 0.5).unwrap();
    check(
        &sampler,
        3,
        &[
            [0.5145141894999983],
            [1.2041589102930508],
            [1.7278613663293132],
            [2.6867185791753467],
        ],
    );
}

#[test]
fn five_d_annulus_sparse() {
    let sampler: PoissonDisk<5> = PoissonDisk::builder(Domain::from_extent([1.0; 5]).unwrap(), 0.3)
        .layout(GridLayout::Sparse)
        .build()
        .unwrap();
    check(
        &sampler,
        5,
        &[
            [
                0.29202287154046747,
                0.6114394140810253,
                0.09796325663560501,
                0.058611202242922045,
                0.5270564268595844,
            ],
            [
                0.06585699323339317,
                0.8717910959765793,
                0.03640959902191035,
                0.19429962532887982,
                0.29394567609989697,
            ],
            [
                0.4581863623462424,
                0.27293595498507045,
                0.17888202915423979,
                0.11063662693197654,
                0.7599143962504836,
            ],
            [
                0.39422179585097283,
                0.9845972804733099,
                0.28772193870031704,
                0.4590953079081588,
                0.2280381101485576,
            ],
        ],
    );
}

#[test]
fn four_d_sphere() {
    let sampler: PoissonDisk<4> = PoissonDisk::builder(Domain::from_extent([1.0; 4]).unwrap(), 0.3)
        .candidates(Candidates::Sphere)
        .build()
        .unwrap();
    check(
        &sampler,
        9,
        &[
            [
                0.5990316791291411,
                0.4297364011687632,
                0.19864982391454744,
                0.8838122874587226,
            ],
            [
                0.3329863404121178,
                0.31042867515682726,
                0.12937805505512354,
                0.8974865077250703,
            ],
            [
                0.7961116609832299,
                0.4261194920225981,
                0.4224258945021696,
                0.9165336406242763,
            ],
            [
                0.09552964772300551,
                0.1351907606413777,
                0.1175220069860488,
                0.8448990136070844,
            ],
        ],
    );
}
