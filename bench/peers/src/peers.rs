//! The samplers compared, each called the way its docs show, with `k = 30`
//! wherever the crate takes a `k`, and one adapter per crate from its point
//! type to `[f64; N]` (used only when the output is checked).

use crate::check::check;
use crate::textbook;
use std::time::Instant;

/// One sampler in the comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Peer {
    Bridson,
    Textbook,
    FasterPoisson,
    FastPoisson,
    PoissonDiskus,
    Poisson,
    Bluenoise,
    Bluenoisers,
    Poisson2d,
}

/// Every peer, in the table's order.
pub(crate) const ALL: [Peer; 9] = [
    Peer::Bridson,
    Peer::Textbook,
    Peer::FasterPoisson,
    Peer::FastPoisson,
    Peer::PoissonDiskus,
    Peer::Poisson,
    Peer::Bluenoise,
    Peer::Bluenoisers,
    Peer::Poisson2d,
];

/// `k`, the candidates tried around each active point.
pub(crate) const K: u32 = 30;

impl Peer {
    /// The name on the command line and in the table.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Self::Bridson => "bridson",
            Self::Textbook => "textbook",
            Self::FasterPoisson => "faster_poisson",
            Self::FastPoisson => "fast_poisson",
            Self::PoissonDiskus => "poisson-diskus",
            Self::Poisson => "poisson",
            Self::Bluenoise => "bluenoise",
            Self::Bluenoisers => "bluenoisers",
            Self::Poisson2d => "poisson2d",
        }
    }

    /// What the table says about the crate's setup.
    pub(crate) fn how(self) -> &'static str {
        match self {
            Self::Bridson => "`PoissonDisk::builder(..).attempts(30)`, `generate_seeded`",
            Self::Textbook => "`benches/textbook`: the yardstick's algorithm, in safe Rust",
            Self::FasterPoisson => {
                "1.3: `Poisson2D` (parental), `Poisson3D`, `PoissonND`, `.attempts(30)`"
            }
            Self::FastPoisson => "1.0: `Poisson::<N>::with_dimensions`, `with_samples(30)`",
            Self::PoissonDiskus => "1.0: `bridson_rng(.., 30, use_pbc, SmallRng)`",
            Self::Poisson => {
                "0.10: `Builder::with_radius(r/2, ..)`, `algorithm::Bridson` (k = 30 fixed)"
            }
            Self::Bluenoise => "0.2: `BlueNoise` / `WrappingBlueNoise`, `with_samples(30)`, f32",
            Self::Bluenoisers => "1.1: `blue_noise(dims, r, 30)`, thread_rng (no seed)",
            Self::Poisson2d => {
                "0.1: `Builder::with_radius(r/2, ..)`, `algorithm::Bridson` (k = 30 fixed), f32"
            }
        }
    }

    pub(crate) fn from_name(name: &str) -> Option<Self> {
        ALL.into_iter().find(|p| p.name() == name)
    }

    /// `Err(reason)` when the crate cannot run this kind of case.
    pub(crate) fn supports(self, dim: usize, periodic: bool) -> Result<(), &'static str> {
        let two_d = matches!(self, Self::Bluenoise | Self::Poisson2d);
        let torus = matches!(
            self,
            Self::Bridson | Self::PoissonDiskus | Self::Poisson | Self::Bluenoise | Self::Poisson2d
        );
        if two_d && dim != 2 {
            Err("2-D only")
        } else if periodic && !torus {
            Err("no periodic box")
        } else {
            Ok(())
        }
    }
}

/// What a child run reports.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Outcome {
    pub(crate) count: usize,
    /// Seconds in the sampler's calls, from the child's own clock.
    pub(crate) sampling_seconds: f64,
    /// The smallest distance found by the check, when it ran.
    pub(crate) min_distance: Option<f64>,
    /// The radius the check used: the crate's own, after its conversions
    /// (twice `poisson`'s disk radius; `f32` radii widened).
    pub(crate) checked_radius: f64,
}

/// One run's settings.
pub(crate) struct Job {
    pub(crate) peer: Peer,
    pub(crate) dim: usize,
    pub(crate) periodic: bool,
    pub(crate) radius: f64,
    pub(crate) seed: u64,
    pub(crate) check: bool,
}

/// Runs the job in this process.
///
/// # Errors
/// The crate refused the job, or (with `check`) its output is wrong.
pub(crate) fn run(job: &Job) -> Result<Outcome, String> {
    job.peer.supports(job.dim, job.periodic)?;
    let outcome = match job.dim {
        2 => run_n::<2>(job),
        3 => run_n::<3>(job),
        4 => run_n::<4>(job),
        5 => run_n::<5>(job),
        6 => run_n::<6>(job),
        7 => run_n::<7>(job),
        8 => run_n::<8>(job),
        d => Err(format!("no case in {d}-D")),
    };
    outcome.map_err(|e| {
        if e.starts_with("wrong: ") {
            e
        } else {
            format!("refused: {e}")
        }
    })
}

/// Ends a run: counts, or converts and checks.
fn done<const N: usize, P>(
    job: &Job,
    start: Instant,
    points: &[P],
    radius: f64,
    coord: impl Fn(&P, usize) -> f64,
) -> Result<Outcome, String> {
    let sampling_seconds = start.elapsed().as_secs_f64();
    let mut outcome = Outcome {
        count: points.len(),
        sampling_seconds,
        min_distance: None,
        checked_radius: radius,
    };
    if job.check {
        let converted: Vec<[f64; N]> = points
            .iter()
            .map(|p| core::array::from_fn(|a| coord(p, a)))
            .collect();
        let passed =
            check(&converted, [1.0; N], job.periodic, radius).map_err(|e| format!("wrong: {e}"))?;
        outcome.min_distance = Some(passed.min_distance);
    }
    Ok(outcome)
}

#[expect(clippy::cast_possible_truncation, reason = "f32 crates take f32 radii")]
fn run_n<const N: usize>(job: &Job) -> Result<Outcome, String> {
    let (r, seed, periodic) = (job.radius, job.seed, job.periodic);
    let start = Instant::now();
    match job.peer {
        Peer::Bridson => {
            let domain = bridson::Domain::<N>::from_extent([1.0; N])
                .map_err(|e| e.to_string())?
                .with_periodic([periodic; N]);
            let points = bridson::PoissonDisk::builder(domain, r)
                .attempts(K)
                .build()
                .map_err(|e| e.to_string())?
                .generate_seeded(seed)
                .map_err(|e| e.to_string())?;
            done::<N, _>(job, start, &points, r, |p, a| p[a])
        }
        Peer::Textbook => {
            let mut rng = bridson::seeded_rng(seed);
            let points = textbook::textbook([1.0; N], r, K, &mut rng)
                .ok_or("its grid would exceed 2^28 cells")?;
            done::<N, _>(job, start, &points, r, |p, a| p[a])
        }
        Peer::FasterPoisson => {
            let seed = Some(seed);
            let attempts = K as usize;
            match N {
                2 => {
                    let points = faster_poisson::Poisson2D::new()
                        .dims([1.0; 2])
                        .radius(r)
                        .attempts(attempts)
                        .seed(seed)
                        .run();
                    done::<N, _>(job, start, &points, r, |p, a| p[a])
                }
                3 => {
                    let points = faster_poisson::Poisson3D::new()
                        .dims([1.0; 3])
                        .radius(r)
                        .attempts(attempts)
                        .seed(seed)
                        .run();
                    done::<N, _>(job, start, &points, r, |p, a| p[a])
                }
                _ => {
                    let points = faster_poisson::PoissonND::<N>::new()
                        .dims([1.0; N])
                        .radius(r)
                        .attempts(attempts)
                        .seed(seed)
                        .run();
                    done::<N, _>(job, start, &points, r, |p, a| p[a])
                }
            }
        }
        Peer::FastPoisson => {
            let points = fast_poisson::Poisson::<N>::new()
                .with_dimensions([1.0; N], r)
                .with_samples(K)
                .with_seed(seed)
                .generate();
            done::<N, _>(job, start, &points, r, |p, a| p[a])
        }
        Peer::PoissonDiskus => {
            use rand08::SeedableRng;
            let mut rng = rand08::rngs::SmallRng::seed_from_u64(seed);
            let points = poisson_diskus::bridson_rng(&[1.0; N], r, K as usize, periodic, &mut rng)
                .map_err(|e| format!("{e:?}"))?;
            done::<N, _>(job, start, &points, r, |p, a| p[a])
        }
        Peer::Poisson => poisson_crate::<N>(job, start),
        Peer::Bluenoise => {
            use rand09::SeedableRng;
            use rand09::rngs::SmallRng;
            let r32 = r as f32;
            let points: Vec<_> = if periodic {
                let mut noise = bluenoise::WrappingBlueNoise::from_rng(
                    1.0,
                    1.0,
                    r32,
                    SmallRng::seed_from_u64(seed),
                );
                noise.with_samples(K);
                noise.collect()
            } else {
                let mut noise =
                    bluenoise::BlueNoise::from_rng(1.0, 1.0, r32, SmallRng::seed_from_u64(seed));
                noise.with_samples(K);
                noise.collect()
            };
            done::<N, _>(job, start, &points, f64::from(r32), |p, a| {
                f64::from(if a == 0 { p.x } else { p.y })
            })
        }
        Peer::Bluenoisers => {
            let points = bluenoisers::blue_noise(vec![1.0; N], r, K as usize);
            if let Some(p) = points.iter().find(|p| p.len() != N) {
                return Err(format!("a point has {} coordinates", p.len()));
            }
            done::<N, _>(job, start, &points, r, |p, a| p[a])
        }
        Peer::Poisson2d => {
            use rand07::SeedableRng;
            let half = (r / 2.0) as f32;
            let kind = if periodic {
                poisson2d::Type::Periodic
            } else {
                poisson2d::Type::Normal
            };
            let points = poisson2d::Builder::with_radius(half, kind)
                .build(
                    rand07::rngs::SmallRng::seed_from_u64(seed),
                    poisson2d::algorithm::Bridson,
                )
                .generate();
            done::<N, _>(job, start, &points, 2.0 * f64::from(half), |p, a| {
                f64::from(if a == 0 { p.x } else { p.y })
            })
        }
    }
}

/// The `poisson` crate: nalgebra vectors of each dimension, `r/2` as its
/// disk radius.
fn poisson_crate<const N: usize>(job: &Job, start: Instant) -> Result<Outcome, String> {
    use poisson::{Builder, Type, algorithm::Bridson};
    use rand06::SeedableRng;
    use rand06::rngs::SmallRng;
    let half = job.radius / 2.0;
    if half > core::f64::consts::FRAC_1_SQRT_2 {
        return Err("its radius must be at most sqrt(2)/2".into());
    }
    let kind = if job.periodic {
        Type::Perioditic
    } else {
        Type::Normal
    };
    let rng = SmallRng::seed_from_u64(job.seed);
    macro_rules! with_vector {
        ($v:ty) => {{
            let points = Builder::<f64, $v>::with_radius(half, kind)
                .build(rng, Bridson)
                .generate();
            done::<N, _>(job, start, &points, 2.0 * half, |p, a| p[a])
        }};
    }
    match N {
        2 => with_vector!(nalgebra::Vector2<f64>),
        3 => with_vector!(nalgebra::Vector3<f64>),
        4 => with_vector!(nalgebra::Vector4<f64>),
        5 => with_vector!(nalgebra::Vector5<f64>),
        6 => with_vector!(nalgebra::Vector6<f64>),
        7 => with_vector!(nalgebra::VectorN<f64, nalgebra::U7>),
        8 => with_vector!(nalgebra::VectorN<f64, nalgebra::U8>),
        _ => Err(format!("no nalgebra vector for {N}-D here")),
    }
}
