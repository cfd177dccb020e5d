//! The example baselines (`examples/common/samplers/`) keep the
//! `PixelSampler` contract (pure values, range, exact counts, errors) and
//! each its defining property: strata for `stratified`, (0,m,2)-nets for
//! `low-discrepancy` and `sobol-owen`, spacing for `best-candidate`.

#[path = "../examples/common/samplers/mod.rs"]
mod samplers;

use bridson::PixelSampler;
use samplers::{
    BestCandidateSampler, IndependentSampler, LowDiscrepancySampler, PoissonExactSampler,
    SobolOwenSampler, StratifiedSampler, by_name, hash, permute, to_unit,
};
use std::collections::HashSet;

/// Sample counts for the contract tests: powers of two, primes, others.
const SPPS: [u32; 7] = [1, 2, 3, 7, 16, 61, 100];

/// Pixels for the contract tests, far apart and near the origin.
const PIXELS: [[u32; 2]; 4] = [[0, 0], [3, 5], [17, 2], [100_000, 4_000_000]];

/// The values a renderer draws for one sample: the camera sample (film,
/// time, lens), then 1-D, 2-D, 1-D for an integrator: dimensions 0..=6.
fn draw(s: &mut impl PixelSampler) -> [f64; 10] {
    let c = s.camera_sample();
    let a = s.get_1d();
    let [b, e] = s.get_2d();
    let f = s.get_1d();
    [
        c.film[0], c.film[1], c.time, c.lens[0], c.lens[1], a, b, e, f, 0.0,
    ]
}

/// Every pixel's values for every sample, in order.
fn table_of(s: &mut impl PixelSampler) -> Vec<Vec<[f64; 10]>> {
    PIXELS
        .iter()
        .map(|&p| {
            (0..s.samples_per_pixel())
                .map(|i| {
                    s.start_pixel_sample(p, i, 0).expect("index < spp");
                    draw(s)
                })
                .collect()
        })
        .collect()
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// The contract, for one sampler: consistent values in shuffled order,
/// from a clone, on another thread, and when resuming at a dimension;
/// range; errors past the count.
fn check_contract<S: PixelSampler + Clone + Send + Sync + 'static>(name: &str, mut s: S) {
    let spp = s.samples_per_pixel();
    let reference = table_of(&mut s);

    // Range.
    for (p, pixel) in reference.iter().enumerate() {
        assert_eq!(
            pixel.len(),
            spp as usize,
            "{name} spp {spp}: one row per index"
        );
        for (i, row) in pixel.iter().enumerate() {
            assert!(
                row.iter().all(|v| (0.0..1.0).contains(v)),
                "{name} spp {spp} pixel {p} index {i}: {row:?} outside [0, 1)"
            );
        }
    }

    // Shuffled order from a clone.
    let mut clone = s.clone();
    let total = u32::try_from(PIXELS.len()).expect("4 pixels") * spp;
    for k in 0..total {
        let j = permute(k, total, 99);
        let (p, i) = ((j / spp) as usize, j % spp);
        clone
            .start_pixel_sample(PIXELS[p], i, 0)
            .expect("index < spp");
        assert_eq!(
            bits(&draw(&mut clone)),
            bits(&reference[p][i as usize]),
            "{name} spp {spp}: pixel {:?} index {i} differs when revisited",
            PIXELS[p]
        );
        // Resuming at dimension 3 gives the integrator's first 1-D value.
        clone
            .start_pixel_sample(PIXELS[p], i, 3)
            .expect("index < spp");
        assert_eq!(
            clone.get_1d().to_bits(),
            reference[p][i as usize][5].to_bits(),
            "{name} spp {spp}: resuming at dimension 3"
        );
    }

    // On another thread, in reverse order.
    let mut moved = s.clone();
    let from_thread = std::thread::spawn(move || {
        let mut rows = table_of(&mut moved);
        rows.reverse();
        rows
    })
    .join()
    .expect("the thread does not panic");
    let mut expected = reference.clone();
    expected.reverse();
    assert!(
        from_thread == expected,
        "{name} spp {spp}: another thread differs"
    );

    // Errors past the count; a failed start leaves the sampler in place.
    s.start_pixel_sample(PIXELS[1], spp - 1, 0)
        .expect("the last index");
    assert!(
        s.start_pixel_sample(PIXELS[2], spp, 0).is_err(),
        "{name} spp {spp}: index spp accepted"
    );
    assert!(
        s.start_pixel_sample(PIXELS[2], u32::MAX, 0).is_err(),
        "{name} spp {spp}: index u32::MAX accepted"
    );
    assert_eq!(
        bits(&draw(&mut s)),
        bits(&reference[1][spp as usize - 1]),
        "{name} spp {spp}: a failed start moved the sampler"
    );
}

#[test]
fn every_sampler_keeps_the_contract() {
    for spp in SPPS {
        let seed = u64::from(spp) * 31 + 5;
        check_contract(
            "independent",
            IndependentSampler::new(spp, seed).expect("valid"),
        );
        check_contract(
            "stratified",
            StratifiedSampler::new(spp, seed).expect("valid"),
        );
        check_contract(
            "best-candidate",
            BestCandidateSampler::new(spp, seed).expect("valid"),
        );
        check_contract(
            "low-discrepancy",
            LowDiscrepancySampler::new(spp, seed).expect("valid"),
        );
        check_contract(
            "sobol-owen",
            SobolOwenSampler::new(spp, seed).expect("valid"),
        );
        // A stream per pixel: slow in a debug build, so the small counts.
        if spp <= 7 {
            check_contract(
                "poisson-exact",
                PoissonExactSampler::new(spp, seed).expect("valid"),
            );
        }
    }
}

#[test]
fn by_name_knows_every_name_and_refuses_bad_counts() {
    for name in samplers::NAMES {
        let s = by_name(name, 8, 1).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.samples_per_pixel(), 8, "{name}");
        assert!(by_name(name, 0, 1).is_err(), "{name}: spp 0 accepted");
    }
    assert!(
        by_name("best-candidate", 4097, 1).is_err(),
        "best-candidate: spp 4097 accepted"
    );
    assert!(
        by_name("sobol-owen", (1 << 16) + 1, 1).is_err(),
        "sobol-owen: spp 2^16+1"
    );
    assert!(
        by_name("no-such", 4, 1).is_err(),
        "an unknown name accepted"
    );
}

#[test]
fn seeds_change_the_values() {
    for name in samplers::NAMES {
        let mut a = by_name(name, 4, 1).expect("valid");
        let mut b = by_name(name, 4, 2).expect("valid");
        a.start_pixel_sample([1, 1], 0, 0).expect("valid");
        b.start_pixel_sample([1, 1], 0, 0).expect("valid");
        assert_ne!(a.camera_sample(), b.camera_sample(), "{name}: seed ignored");
    }
}

/// The stratum of `v` among `n` equal strata of `[0, 1)`.
fn stratum(v: f64, n: u32) -> u32 {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "v in [0, 1), checked by the contract test"
    )]
    let k = (v * f64::from(n)).floor() as u32;
    k
}

/// The sets of one pixel: film, time, lens, a further 1-D value and a
/// further 2-D pair, one entry per sample index.
#[derive(Debug, Default)]
struct Sets {
    film: Vec<[f64; 2]>,
    time: Vec<f64>,
    lens: Vec<[f64; 2]>,
    one: Vec<f64>,
    two: Vec<[f64; 2]>,
}

/// The [`Sets`] of `pixel`.
fn sets(s: &mut impl PixelSampler, pixel: [u32; 2]) -> Sets {
    let mut out = Sets::default();
    for i in 0..s.samples_per_pixel() {
        s.start_pixel_sample(pixel, i, 0).expect("index < spp");
        let c = s.camera_sample();
        out.film.push(c.film);
        out.time.push(c.time);
        out.lens.push(c.lens);
        out.one.push(s.get_1d());
        out.two.push(s.get_2d());
    }
    out
}

fn one_per_stratum(values: &[f64], n: u32) -> bool {
    let strata: HashSet<u32> = values.iter().map(|&v| stratum(v, n)).collect();
    strata.len() == n as usize && values.len() == n as usize
}

fn one_per_cell(points: &[[f64; 2]], [nx, ny]: [u32; 2]) -> bool {
    let cells: HashSet<(u32, u32)> = points
        .iter()
        .map(|&[x, y]| (stratum(x, nx), stratum(y, ny)))
        .collect();
    cells.len() == (nx * ny) as usize && points.len() == (nx * ny) as usize
}

#[test]
fn stratified_puts_one_sample_in_each_stratum_and_cell() {
    for spp in [1, 2, 3, 5, 7, 12, 13, 16, 31, 36, 64, 97, 100, 257] {
        let mut s = StratifiedSampler::new(spp, 11).expect("valid");
        let [nx, ny] = s.grid();
        assert_eq!(nx * ny, spp, "spp {spp}: grid {nx}×{ny}");
        assert!(
            nx <= ny && (nx..=ny).all(|d| d == nx || d * d > spp || spp % d != 0),
            "spp {spp}: nx {nx} is not the largest divisor <= √spp"
        );
        for pixel in PIXELS {
            let Sets {
                film,
                time,
                lens,
                one,
                two,
            } = sets(&mut s, pixel);
            for (what, values) in [("time", &time), ("1-D", &one)] {
                assert!(
                    one_per_stratum(values, spp),
                    "spp {spp} pixel {pixel:?}: {what} strata"
                );
            }
            for (what, points) in [("film", &film), ("lens", &lens), ("2-D", &two)] {
                assert!(
                    one_per_cell(points, [nx, ny]),
                    "spp {spp} pixel {pixel:?}: {what} cells"
                );
            }
        }
    }
}

/// Whether `points` (`2^m` of them) hold exactly one point in every
/// elementary interval of area `2^-m`, for every shape `2^-a × 2^-(m-a)`.
fn is_02_net(points: &[[f64; 2]], m: u32) -> bool {
    (0..=m).all(|a| one_per_cell(points, [1 << a, 1 << (m - a)]))
}

fn check_nets(name: &str, s: &mut impl PixelSampler) {
    let spp = s.samples_per_pixel();
    let m = spp.trailing_zeros();
    for pixel in PIXELS {
        let Sets {
            film,
            time,
            lens,
            one,
            two,
        } = sets(s, pixel);
        for (what, points) in [("film", &film), ("lens", &lens), ("2-D", &two)] {
            assert!(
                is_02_net(points, m),
                "{name} spp {spp} pixel {pixel:?}: {what} not a (0,{m},2)-net"
            );
        }
        for (what, values) in [("time", &time), ("1-D", &one)] {
            assert!(
                one_per_stratum(values, spp),
                "{name} spp {spp} pixel {pixel:?}: {what} strata"
            );
        }
    }
}

#[test]
fn low_discrepancy_and_sobol_owen_give_02_nets() {
    for spp in [16, 64, 256] {
        check_nets(
            "low-discrepancy",
            &mut LowDiscrepancySampler::new(spp, 3).expect("valid"),
        );
        check_nets(
            "sobol-owen",
            &mut SobolOwenSampler::new(spp, 3).expect("valid"),
        );
    }
}

#[test]
fn the_net_check_can_fail() {
    // Independent points are almost never a net; stratified's jittered
    // grid is a net in one shape only.
    let mut s = IndependentSampler::new(64, 3).expect("valid");
    assert!(
        !is_02_net(&sets(&mut s, [0, 0]).film, 6),
        "independent points passed as a net"
    );
    let mut s = StratifiedSampler::new(64, 3).expect("valid");
    assert!(
        !is_02_net(&sets(&mut s, [0, 0]).film, 6),
        "a jittered grid passed as a net"
    );
}

fn wrapped(a: f64, b: f64) -> f64 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

/// The smallest toroidal distance between two of `points` (all pairs).
fn min_distance(points: &[[f64; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let (dx, dy) = (wrapped(a[0], b[0]), wrapped(a[1], b[1]));
            best = best.min(dx * dx + dy * dy);
        }
    }
    best.sqrt()
}

#[test]
fn best_candidate_table_is_far_better_spread_than_random() {
    let s = BestCandidateSampler::new(16, 0).expect("valid");
    let table = s.table();
    let n = table.image.len();
    assert_eq!(n, 4096, "the table size");
    let best = min_distance(&table.image);
    let lens = min_distance(&table.lens);
    // The best of several random sets, to be fair to random.
    let random = (0..4_u64)
        .map(|seed| {
            let points: Vec<[f64; 2]> = (0..n as u64)
                .map(|i| [to_unit(hash(&[seed, i, 0])), to_unit(hash(&[seed, i, 1]))])
                .collect();
            min_distance(&points)
        })
        .fold(0.0, f64::max);
    println!("min distance: image {best:.3e}, lens {lens:.3e}, random {random:.3e}");
    assert!(
        best >= 3.0 * random,
        "best-candidate {best:e} vs random {random:e}"
    );
    assert!(
        lens >= 3.0 * random,
        "best-candidate lens {lens:e} vs random {random:e}"
    );
    // Time: stratified, so one value in each of the 4096 strata.
    assert!(
        one_per_stratum(&table.time, 4096),
        "table times are not stratified"
    );
}

#[test]
fn best_candidate_gives_each_pixel_exactly_spp_table_samples() {
    for spp in [1, 2, 3, 5, 16, 64, 100, 1000, 4096] {
        let mut s = BestCandidateSampler::new(spp, 9).expect("valid");
        let tiling = s.tiling();
        let [w, h] = tiling.size;
        let n = (w * h * spp) as usize;
        assert!(
            n <= 4096 && n > 4096 - 4096 / 4,
            "spp {spp}: tile {w}×{h} uses {n} samples"
        );
        // Every table sample of the prefix is used exactly once.
        let used: HashSet<u16> = tiling.entries.iter().map(|e| e.0).collect();
        assert_eq!(used.len(), n, "spp {spp}: table samples used");
        assert!(
            used.iter().all(|&k| usize::from(k) < n),
            "spp {spp}: past the prefix"
        );
        println!(
            "spp {spp}: tile {w}×{h}, {} of {n} samples moved",
            tiling.moved
        );
        assert!(
            tiling.moved * 4 <= n,
            "spp {spp}: {} of {n} samples moved",
            tiling.moved
        );
        // Through the trait: a pixel in the second tile row and column gets
        // spp distinct film offsets, which are those of its tile pixel.
        for pixel in [[w + 1, h + 1], [1, 1], [5 * w + w - 1, 3 * h]] {
            let local = [pixel[0] % w, pixel[1] % h];
            let film = sets(&mut s, pixel).film;
            let film_local = sets(&mut s, local).film;
            assert_eq!(film, film_local, "spp {spp}: tiles repeat the film pattern");
            let distinct: HashSet<[u64; 2]> = film.iter().map(|p| p.map(f64::to_bits)).collect();
            assert_eq!(
                distinct.len(),
                spp as usize,
                "spp {spp} pixel {pixel:?}: film offsets"
            );
        }
    }
}

#[test]
fn independent_values_are_uniform() {
    let mut s = IndependentSampler::new(64, 5).expect("valid");
    let mut sums = [0.0; 5];
    let mut count = 0.0_f64;
    for y in 0..8 {
        for x in 0..8 {
            for i in 0..64 {
                s.start_pixel_sample([x, y], i, 0).expect("valid");
                let c = s.camera_sample();
                for (sum, v) in sums
                    .iter_mut()
                    .zip([c.film[0], c.film[1], c.time, c.lens[0], c.lens[1]])
                {
                    *sum += v;
                }
                count += 1.0;
            }
        }
    }
    // Standard error of a mean of uniforms: √(1/12 / count).
    let se = (1.0 / 12.0 / count).sqrt();
    for (d, sum) in sums.iter().enumerate() {
        let mean = sum / count;
        assert!(
            (mean - 0.5).abs() < 5.0 * se,
            "dimension {d}: mean {mean} (se {se})"
        );
    }
}

/// The `K` nearest image neighbours of every point (all pairs, toroidal).
fn nearest_neighbours<const K: usize>(points: &[[f64; 2]]) -> Vec<[usize; K]> {
    points
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let mut best = [(f64::INFINITY, 0); K];
            for (j, b) in points.iter().enumerate() {
                let d = wrapped(a[0], b[0]).powi(2) + wrapped(a[1], b[1]).powi(2);
                if j != i && d < best[K - 1].0 {
                    best[K - 1] = (d, j);
                    best.sort_by(|x, y| x.0.total_cmp(&y.0));
                }
            }
            best.map(|(_, j)| j)
        })
        .collect()
}

#[test]
fn best_candidate_spreads_time_and_lens_over_image_neighbours() {
    // For each table sample, the smallest time (lens) gap to its 6 nearest
    // image neighbours, averaged: the redistribution must beat the same
    // values dealt out by a random permutation by a clear margin.
    let s = BestCandidateSampler::new(1, 0).expect("valid");
    let table = s.table();
    let n = u32::try_from(table.image.len()).expect("4096");
    let neighbours = nearest_neighbours::<6>(&table.image);
    let mean_min_gap = |time: &dyn Fn(usize) -> f64, lens: &dyn Fn(usize) -> [f64; 2]| {
        let (mut t, mut l) = (0.0, 0.0);
        for (i, near) in neighbours.iter().enumerate() {
            t += near
                .iter()
                .map(|&j| wrapped(time(i), time(j)))
                .fold(1.0, f64::min);
            l += near
                .iter()
                .map(|&j| {
                    let (p, q) = (lens(i), lens(j));
                    (wrapped(p[0], q[0]).powi(2) + wrapped(p[1], q[1]).powi(2)).sqrt()
                })
                .fold(1.0, f64::min);
        }
        (t / f64::from(n), l / f64::from(n))
    };
    let shuffled = |i: usize| permute(u32::try_from(i).expect("4096"), n, 5) as usize;
    let (time, lens) = mean_min_gap(&|i| table.time[i], &|i| table.lens[i]);
    let (time_random, lens_random) =
        mean_min_gap(&|i| table.time[shuffled(i)], &|i| table.lens[shuffled(i)]);
    println!(
        "mean smallest gap to 6 image neighbours: time {time:.4} (random {time_random:.4}), \
         lens {lens:.4} (random {lens_random:.4})"
    );
    assert!(
        time >= 1.5 * time_random,
        "time {time} vs random {time_random}"
    );
    assert!(
        lens >= 1.5 * lens_random,
        "lens {lens} vs random {lens_random}"
    );
}
