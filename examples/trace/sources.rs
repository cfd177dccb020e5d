//! Where each render's samples come from: every sampler of
//! `common::samplers` through the crate's [`PixelSampler`] trait (exactly
//! `spp` per pixel); the crate's exact mode streamed over the whole image
//! as a renderer would run it ([`CameraPixels`] over
//! `Tiled::builder(w, h).exact(spp)`, one sampler per [`ExactMethod`]:
//! exactly `spp` per pixel too); and three Poisson schemes whose counts
//! vary from pixel to pixel: `poisson-sweep` (the crate's streaming sweep,
//! natural counts, as [`CameraPixels`] gives them), `poisson-joint` (one
//! 5-D set per pixel over film, time and lens) and `poisson-paper` (the
//! paper as published).
//!
//! A sample is what the tracer consumes: the camera's values and one 2-D
//! light sample, the sampler's next dimension pair after the camera's.

use crate::common::samplers::{self, hash};
use bridson::{
    CameraPixels, CameraSample, Domain, ExactMethod, PixelSampler, PoissonDisk,
    PoissonPixelSampler, Scheme, Tiled,
};
use std::f64::consts::PI;

/// One camera sample and its light sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Sample {
    pub(crate) camera: CameraSample,
    pub(crate) light: [f64; 2],
}

/// The crate's exact mode streamed over the whole image, one sampler per
/// [`ExactMethod`], after those of [`samplers::NAMES`]. Unlike
/// `poisson-exact` there (one `1 × 1` stream per pixel, so that pixels are
/// independent trials for the convergence study), the film points of
/// neighbouring pixels keep their distance from each other, as in a
/// renderer's [`CameraPixels`]; and the method is chosen, so the study can
/// judge the two.
pub(crate) const EXACT_STREAMED: [(&str, ExactMethod); 2] = [
    ("poisson-exact-eliminate", ExactMethod::Eliminate),
    ("poisson-exact-random", ExactMethod::Random),
];

/// The samplers whose counts are natural, not exact, after those of
/// [`EXACT_STREAMED`].
pub(crate) const NATURAL: [&str; 3] = ["poisson-sweep", "poisson-joint", "poisson-paper"];

/// Every name `--sampler` accepts, in the study's order: those of
/// [`samplers::NAMES`] and [`samplers::EXTRA_NAMES`] (`net`, `zsobol`,
/// `pmj02bn`), then the streamed and natural-count schemes.
pub(crate) fn names() -> Vec<&'static str> {
    samplers::NAMES
        .iter()
        .chain(&samplers::EXTRA_NAMES)
        .copied()
        .chain(EXACT_STREAMED.iter().map(|&(name, _)| name))
        .chain(NATURAL)
        .collect()
}

/// The samplers a study runs when `--sampler` is not given: every name
/// but `net`, which is left out until it is measured in full.
pub(crate) fn default_names() -> Vec<&'static str> {
    names().into_iter().filter(|&n| n != "net").collect()
}

/// Whether `name` is drawn through the [`PixelSampler`] trait (one of
/// `common::samplers`).
fn is_trait_sampler(name: &str) -> bool {
    samplers::NAMES.contains(&name) || samplers::EXTRA_NAMES.contains(&name)
}

/// The exact method of an [`EXACT_STREAMED`] sampler.
fn exact_method(name: &str) -> Option<ExactMethod> {
    EXACT_STREAMED
        .iter()
        .find(|&&(n, _)| n == name)
        .map(|&(_, method)| method)
}

/// The dimension of the light sample in a [`PixelSampler`]: after time
/// (dimension 0) and lens (1 and 2).
const LIGHT_DIMENSION: u32 = 3;

/// A sampler's recipe for one render: cheap to make, and shared by the
/// render threads, each of which builds its own [`PixelFiller`]; the
/// streamed schemes also keep one [`FilmStream`].
#[derive(Clone, Debug)]
pub(crate) struct Recipe {
    pub(crate) name: String,
    pub(crate) spp: u32,
    pub(crate) seed: u64,
    pub(crate) size: [u32; 2],
    /// `poisson-joint`: the radius of the 5-D set that averages `spp`
    /// points.
    joint_radius: f64,
}

impl Recipe {
    /// The recipe of sampler `name` at `spp` samples per pixel.
    ///
    /// # Errors
    /// A message if the name is unknown or the sampler refuses `spp`.
    pub(crate) fn new(name: &str, spp: u32, seed: u64, size: [u32; 2]) -> Result<Self, String> {
        if !names().contains(&name) {
            return Err(format!(
                "unknown sampler {name:?}; known: {}",
                names().join(", ")
            ));
        }
        if is_trait_sampler(name) {
            // Fail now, not in a render thread.
            samplers::by_name(name, spp, seed)?;
        } else if !(1..=bridson::MAX_SAMPLES_PER_PIXEL).contains(&spp) {
            return Err(format!(
                "{name}: --spp must be from 1 to {}",
                bridson::MAX_SAMPLES_PER_PIXEL
            ));
        }
        let joint_radius = if name == "poisson-joint" {
            joint_radius(spp)?
        } else {
            0.0
        };
        Ok(Self {
            name: name.to_owned(),
            spp,
            seed,
            size,
            joint_radius,
        })
    }

    /// The film stream, for the schemes that draw their film positions from
    /// one [`Tiled`] stream over the image, in scan order.
    ///
    /// # Errors
    /// A message if the stream cannot be built.
    pub(crate) fn film_stream(&self) -> Result<Option<FilmStream>, String> {
        let [w, h] = self.size;
        let err = |e: bridson::Error| format!("{}: {e}", self.name);
        let camera = |builder: bridson::TiledBuilder| {
            let tiled = builder.build().map_err(err)?;
            CameraPixels::new(&tiled, self.seed, 0)
                .map(FilmStream::Sweep)
                .map_err(err)
        };
        if let Some(method) = exact_method(&self.name) {
            let builder = Tiled::builder(w, h).exact(self.spp).exact_method(method);
            return camera(builder).map(Some);
        }
        Ok(match self.name.as_str() {
            "poisson-sweep" => Some(camera(Tiled::builder(w, h).per_pixel(f64::from(self.spp)))?),
            "poisson-paper" => {
                let tiled = Tiled::builder(w, h)
                    .radius(paper_radius(self.spp))
                    .scheme(Scheme::Paper)
                    .build()
                    .map_err(err)?;
                Some(FilmStream::Paper(tiled.pixels_seeded(self.seed)))
            }
            _ => None,
        })
    }

    /// A filler for one render thread.
    ///
    /// # Errors
    /// A message if the sampler cannot be built.
    pub(crate) fn filler(&self) -> Result<PixelFiller, String> {
        let sampler = if is_trait_sampler(&self.name) {
            Some(samplers::by_name(&self.name, self.spp, self.seed)?)
        } else {
            None
        };
        Ok(PixelFiller {
            recipe: self.clone(),
            sampler,
            by_count: Vec::new(),
        })
    }
}

/// The paper's radius for `n` samples per pixel, `r = sqrt(8 / (5πn))`:
/// from its estimate that a point of a Bridson set covers `5πr²/8`.
pub(crate) fn paper_radius(n: u32) -> f64 {
    (8.0 / (5.0 * PI * f64::from(n))).sqrt()
}

/// The same rule carried to the 1-D time set: candidates uniform on
/// `r..2r` lie `1.5 r` away on average, so `r = 1 / (1.5 n)`.
fn paper_radius_1d(n: u32) -> f64 {
    1.0 / (1.5 * f64::from(n))
}

/// The radius at which a Bridson set on the periodic unit 5-cube (film,
/// time, lens) has `spp` points on average, found by fixed-point iteration
/// on `count ∝ r⁻⁵` over 16 seeds; a pure function of `spp`.
fn joint_radius(spp: u32) -> Result<f64, String> {
    let domain = Domain::from_extent([1.0; 5])
        .map_err(|e| e.to_string())?
        .with_periodic([true; 5]);
    // The 2-D density of the crate's sweep, carried to 5-D, as a start.
    let mut radius = (0.3 / f64::from(spp)).powf(0.2);
    for _ in 0..5 {
        let disk = PoissonDisk::new(domain, radius).map_err(|e| e.to_string())?;
        let mut total = 0_usize;
        for seed in 0..16 {
            total += disk
                .generate_seeded(hash(&[0x006a_6f69_6e74, u64::from(spp), seed]))
                .map_err(|e| e.to_string())?
                .len();
        }
        #[expect(clippy::cast_precision_loss, reason = "a count of points")]
        let mean = total as f64 / 16.0;
        radius *= (mean / f64::from(spp)).powf(0.2);
    }
    Ok(radius)
}

/// The film stream of `poisson-sweep`, the [`EXACT_STREAMED`] samplers or
/// `poisson-paper`: pixels in scan order.
#[derive(Debug)]
pub(crate) enum FilmStream {
    /// The crate's camera samples in streaming form (film, time, lens), of
    /// the natural sweep or of exact mode.
    Sweep(CameraPixels),
    /// Film points only; the rest is drawn per pixel by the filler.
    Paper(bridson::Pixels<bridson::DefaultRng>),
}

impl FilmStream {
    /// The next pixel's samples into `out`: complete for the sweep, film
    /// only (time and lens zero) for the paper's scheme.
    pub(crate) fn next_into(&mut self, out: &mut Vec<Sample>) -> Option<[u32; 2]> {
        out.clear();
        match self {
            Self::Sweep(stream) => {
                let pixel = stream.next()?;
                out.extend(pixel.samples.iter().map(|&camera| Sample {
                    camera,
                    light: [0.0; 2],
                }));
                Some([pixel.x, pixel.y])
            }
            Self::Paper(stream) => {
                let mut points = Vec::new();
                let (x, y) = stream.next_into(&mut points)?;
                out.extend(points.iter().map(|p| Sample {
                    camera: CameraSample {
                        film: [p[0] - f64::from(x), p[1] - f64::from(y)],
                        time: 0.0,
                        lens: [0.0; 2],
                    },
                    light: [0.0; 2],
                }));
                Some([x, y])
            }
        }
    }
}

/// Makes (or completes) a pixel's samples, on one render thread.
pub(crate) struct PixelFiller {
    recipe: Recipe,
    /// The trait sampler, for the exact-count samplers.
    sampler: Option<Box<dyn PixelSampler>>,
    /// `poisson-sweep`, `poisson-joint` and the [`EXACT_STREAMED`]
    /// samplers: a Poisson pixel sampler per sample count met (index =
    /// count), for the light dimensions.
    by_count: Vec<Option<PoissonPixelSampler>>,
}

impl std::fmt::Debug for PixelFiller {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PixelFiller")
            .field("recipe", &self.recipe)
            .finish_non_exhaustive()
    }
}

impl PixelFiller {
    /// The samples of `pixel` into `out`. For the streamed schemes, `out`
    /// already holds the stream's film (and, for the sweep, time and lens)
    /// and is completed here.
    pub(crate) fn fill(&mut self, pixel: [u32; 2], out: &mut Vec<Sample>) {
        let seed = self.recipe.seed;
        let spp = self.recipe.spp;
        if let Some(sampler) = &mut self.sampler {
            // The renderer's loop of pbrt: start the sample, take the
            // camera's values, then the integrator's next pair.
            out.clear();
            for index in 0..spp {
                if sampler.start_pixel_sample(pixel, index, 0).is_err() {
                    break;
                }
                let camera = sampler.camera_sample();
                let light = sampler.get_2d();
                out.push(Sample { camera, light });
            }
            return;
        }
        let pixel_seed = hash(&[
            seed,
            0x0070_6978_656c,
            u64::from(pixel[0]),
            u64::from(pixel[1]),
        ]);
        match self.recipe.name.as_str() {
            // The streamed film, time and lens are in `out` already.
            name if name == "poisson-sweep" || exact_method(name).is_some() => {
                self.add_light(pixel, out);
            }
            "poisson-joint" => {
                out.clear();
                let points = PoissonDisk::new(
                    Domain::from_extent([1.0; 5])
                        .expect("a unit box")
                        .with_periodic([true; 5]),
                    self.recipe.joint_radius,
                )
                .and_then(|disk| {
                    disk.generate_seeded(pixel_seed)
                        .map_err(bridson::Error::from)
                })
                .unwrap_or_default();
                out.extend(points.iter().map(|p| Sample {
                    camera: CameraSample {
                        film: [p[0], p[1]],
                        time: p[2],
                        lens: [p[3], p[4]],
                    },
                    light: [0.0; 2],
                }));
                self.add_light(pixel, out);
            }
            "poisson-paper" => paper_rest(spp, pixel_seed, out),
            _ => out.clear(),
        }
    }

    /// Light samples for `out`'s samples from a Poisson pixel sampler of
    /// exactly that many samples, at the dimension pair after the camera's.
    fn add_light(&mut self, pixel: [u32; 2], out: &mut [Sample]) {
        let Ok(count) = u32::try_from(out.len()) else {
            return;
        };
        if count == 0 {
            return;
        }
        let index = out.len();
        if self.by_count.len() <= index {
            self.by_count.resize(index + 1, None);
        }
        let seed = hash(&[self.recipe.seed, 0x006c_6967_6874]);
        let slot = &mut self.by_count[index];
        if slot.is_none() {
            *slot = PoissonPixelSampler::new(count, seed).ok();
        }
        let Some(sampler) = slot else { return };
        for (i, sample) in (0..count).zip(out.iter_mut()) {
            if sampler
                .start_pixel_sample(pixel, i, LIGHT_DIMENSION)
                .is_ok()
            {
                sample.light = sampler.get_2d();
            }
        }
    }
}

/// The paper's lens, time and light sets for one pixel, each a Bridson set
/// of its own at the paper's radius (2-D sets on the unit square, the time
/// on the unit interval), none periodic; the pixel keeps as many samples as
/// its smallest set has, pairing the sets' points in generation order and
/// dropping the rest, as the paper does.
fn paper_rest(spp: u32, seed: u64, out: &mut Vec<Sample>) {
    let r2 = paper_radius(spp);
    let set2 = |salt: u64| {
        Domain::from_extent([1.0, 1.0])
            .and_then(|d| PoissonDisk::new(d, r2))
            .and_then(|disk| {
                disk.generate_seeded(hash(&[seed, salt]))
                    .map_err(bridson::Error::from)
            })
            .unwrap_or_default()
    };
    let lens = set2(1);
    let light = set2(2);
    let time = Domain::from_extent([1.0])
        .and_then(|d| PoissonDisk::new(d, paper_radius_1d(spp)))
        .and_then(|disk| {
            disk.generate_seeded(hash(&[seed, 3]))
                .map_err(bridson::Error::from)
        })
        .unwrap_or_default();
    let count = out.len().min(lens.len()).min(light.len()).min(time.len());
    out.truncate(count);
    for (i, sample) in out.iter_mut().enumerate() {
        sample.camera.lens = lens[i];
        sample.camera.time = time[i][0];
        sample.light = light[i];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_joint_radius_gives_about_spp_points() {
        for spp in [3, 8] {
            let recipe = Recipe::new("poisson-joint", spp, 1, [4, 4]).expect("builds");
            let mut filler = recipe.filler().expect("builds");
            let mut total = 0;
            let mut out = Vec::new();
            for x in 0..16 {
                filler.fill([x, 0], &mut out);
                total += out.len();
                assert!(
                    out.iter().all(|s| (0.0..1.0).contains(&s.light[0])),
                    "light in [0, 1)"
                );
            }
            #[expect(clippy::cast_precision_loss, reason = "a count")]
            let mean = total as f64 / 16.0;
            assert!(
                (mean / f64::from(spp) - 1.0).abs() < 0.25,
                "spp {spp}: mean {mean}"
            );
        }
    }

    #[test]
    fn every_name_makes_samples_in_the_unit_square() {
        for name in names() {
            let recipe = Recipe::new(name, 3, 3, [5, 3]).expect("builds");
            let mut stream = recipe.film_stream().expect("builds");
            let mut filler = recipe.filler().expect("builds");
            let mut out = Vec::new();
            for y in 0..3 {
                for x in 0..5 {
                    if let Some(stream) = &mut stream {
                        assert_eq!(
                            stream.next_into(&mut out),
                            Some([x, y]),
                            "{name}: scan order"
                        );
                    }
                    filler.fill([x, y], &mut out);
                    assert!(!out.is_empty(), "{name}: samples in {x},{y}");
                    for s in &out {
                        let c = &s.camera;
                        let values = [
                            c.film[0], c.film[1], c.time, c.lens[0], c.lens[1], s.light[0],
                            s.light[1],
                        ];
                        assert!(
                            values.iter().all(|v| (0.0..1.0).contains(v)),
                            "{name}: {s:?}"
                        );
                    }
                    if !NATURAL.contains(&name) {
                        assert_eq!(out.len(), 3, "{name}: exact count");
                    }
                }
            }
        }
        assert!(Recipe::new("nope", 4, 1, [2, 2]).is_err(), "unknown name");
    }

    /// The streamed exact samplers draw one set over the whole image, as a
    /// renderer's `CameraPixels` does, not a set per pixel: film points of
    /// neighbouring pixels keep the stream's radius from each other (sets
    /// drawn pixel by pixel would not, at this density), each pixel has
    /// exactly `spp`, and the method is passed on (the two films differ).
    #[test]
    fn exact_streams_are_one_set_across_pixel_borders() {
        let ([w, h], spp) = ([6, 5], 4);
        let mut films = Vec::new();
        for (name, method) in EXACT_STREAMED {
            let recipe = Recipe::new(name, spp, 11, [w, h]).expect("builds");
            let mut stream = recipe.film_stream().expect("builds").expect("streamed");
            let mut out = Vec::new();
            let mut film = Vec::new();
            while let Some([x, y]) = stream.next_into(&mut out) {
                assert_eq!(out.len(), spp as usize, "{name}: exact count");
                let c = |i: u32, f: f64| f64::from(i) + f;
                film.extend(
                    out.iter()
                        .map(|s| [c(x, s.camera.film[0]), c(y, s.camera.film[1])]),
                );
            }
            assert_eq!(film.len(), (w * h * spp) as usize, "{name}: every pixel");
            let radius = Tiled::builder(w, h)
                .exact(spp)
                .exact_method(method)
                .build()
                .expect("builds")
                .radius();
            for (i, a) in film.iter().enumerate() {
                for b in &film[..i] {
                    let d = (a[0] - b[0]).hypot(a[1] - b[1]);
                    assert!(
                        d >= radius,
                        "{name}: {a:?} and {b:?} are {d} < {radius} apart"
                    );
                }
            }
            films.push(film);
        }
        assert_ne!(films[0], films[1], "the methods differ");
    }
}
