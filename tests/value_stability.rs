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
            [0.15071435574598752, 0.14691513282660434],
            [0.10011101368971312, 0.11760731739405583],
            [0.23876473311491453, 0.1928993533313651],
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
            [-1.3445229234100933, 10.384249215633874],
            [-1.359487283408796, 10.44322724869967],
            [-1.3092189343573208, 10.463403564007287],
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
            [0.9802528201215088, 0.7331648631456569, 0.06662780589946826],
            [0.9668835176698982, 0.8850067301157192, 0.15555365033039173],
            [0.9056991754643737, 0.8927675722602084, 0.029691919158783747],
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
                0.07892272998286987,
                0.7393289377141574,
                0.5444910817444869,
                0.3139753431036834,
                0.3929786479353279,
            ],
            [
                0.31797732922114624,
                0.7846822225862906,
                0.5010429546296857,
                0.055727281457727956,
                0.42645606838831007,
            ],
            [
                0.12482241443742567,
                0.6383902846087872,
                0.6614607063921214,
                0.0688879918713704,
                0.6869546937077611,
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
                0.6870899856894651,
                0.23368443821000123,
                0.16653326839947877,
                0.6769840801764647,
            ],
            [
                0.4308191752556685,
                0.29768736256145184,
                0.2758430843105092,
                0.5859880388363867,
            ],
            [
                0.672951367501182,
                0.6232430043192327,
                0.41493928461874435,
                0.8662065668987555,
            ],
        ],
    );
}
