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
            [0.1954649383448293, 0.092406592674248],
            [0.23876474695815114, 0.19289935734842242],
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
            [0.07738031654460224, 0.1272257065104338],
            [0.06943917618222174, 0.23768277079752348],
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
            [-1.3594872760851973, 10.443227247482081],
            [-1.309218933108672, 10.463403558450915],
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
            [0.9668835254536325, 0.885006724639468, 0.1555536606308193],
            [0.7025151785600602, 0.664908964555423, 0.12377642963246832],
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
            [2.4002327941748445],
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
                0.6203876741580472,
                0.7242455985777558,
                0.3492755963140117,
                0.323406884822201,
                0.46114886090824503,
            ],
            [
                0.08744126645622705,
                0.649754792769301,
                0.5338088200100647,
                0.2988102637260668,
                0.1437006917750997,
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
                0.8805139268694185,
                0.44111527349594626,
                0.10350046106797452,
                0.8440017081922153,
            ],
            [
                0.546762354790078,
                0.5992004915339196,
                0.00395554070411272,
                0.7401321082584451,
            ],
        ],
    );
}
