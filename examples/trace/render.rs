//! The render loop: the image in bands of rows; for each band, first its
//! samples (the streamed film in scan order on this thread, then the rest
//! per pixel on every thread), then its radiance on every thread. Each
//! pixel's value depends only on its own samples, so the image is the same
//! for any thread count.

use crate::scene::Scene;
use crate::sources::{PixelFiller, Recipe, Sample};
use std::sync::Mutex;
use std::time::Instant;

/// Rows per band: enough work per thread hand-out, little memory.
const BAND_ROWS: u32 = 8;

/// A grey image, row-major from the top-left corner.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Image {
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) values: Vec<f64>,
}

/// A finished render and what it cost.
#[derive(Clone, Debug)]
pub(crate) struct Rendered {
    pub(crate) image: Image,
    /// The fewest and most samples any pixel got.
    pub(crate) samples_per_pixel: [usize; 2],
    /// Wall-clock seconds spent making samples, and in the whole render.
    pub(crate) sample_seconds: f64,
    pub(crate) render_seconds: f64,
}

/// Renders `scene` with the samples of `recipe` on `threads` threads;
/// `progress` hears the fraction of rows done after each band.
///
/// # Errors
/// A message if the sampler cannot be built.
pub(crate) fn render(
    scene: &Scene,
    recipe: &Recipe,
    threads: usize,
    progress: &mut dyn FnMut(f64),
) -> Result<Rendered, String> {
    let start = Instant::now();
    let [width, height] = recipe.size;
    let w = width as usize;
    let mut stream = recipe.film_stream()?;
    let mut fillers = (0..threads.max(1))
        .map(|_| recipe.filler())
        .collect::<Result<Vec<PixelFiller>, String>>()?;
    let mut sample_seconds = start.elapsed().as_secs_f64();
    let mut samples: Vec<Vec<Sample>> = vec![Vec::new(); w * BAND_ROWS as usize];
    let mut values = vec![0.0; w * height as usize];
    let mut counts = [usize::MAX, 0];
    for y0 in (0..height).step_by(BAND_ROWS as usize) {
        let rows = BAND_ROWS.min(height - y0);
        let band = &mut samples[..w * rows as usize];
        let sampling = Instant::now();
        if let Some(stream) = &mut stream {
            for slot in band.iter_mut() {
                stream.next_into(slot);
            }
        }
        let items = (y0..).zip(band.chunks_mut(w)).collect();
        for_each_row(items, &mut fillers, |filler, (y, row)| {
            for (x, slot) in (0..).zip(row.iter_mut()) {
                filler.fill([x, y], slot);
            }
        });
        sample_seconds += sampling.elapsed().as_secs_f64();
        let out = &mut values[y0 as usize * w..(y0 + rows) as usize * w];
        let items = (y0..).zip(band.chunks(w).zip(out.chunks_mut(w))).collect();
        let mut no_state = vec![(); threads.max(1)];
        for_each_row(items, &mut no_state, |(), (y, (row, out))| {
            for ((x, pixel), value) in (0..).zip(row).zip(out.iter_mut()) {
                *value = pixel_value(scene, [x, y], pixel);
            }
        });
        for pixel in band.iter() {
            counts = [counts[0].min(pixel.len()), counts[1].max(pixel.len())];
        }
        progress(f64::from(y0 + rows) / f64::from(height));
    }
    Ok(Rendered {
        image: Image {
            width,
            height,
            values,
        },
        samples_per_pixel: counts,
        sample_seconds,
        render_seconds: start.elapsed().as_secs_f64(),
    })
}

/// The box filter: the mean radiance of the pixel's samples (black for a
/// pixel without any).
fn pixel_value(scene: &Scene, pixel: [u32; 2], samples: &[Sample]) -> f64 {
    if samples.is_empty() {
        return 0.0;
    }
    let sum: f64 = samples
        .iter()
        .map(|s| scene.radiance(&scene.camera.ray(pixel, &s.camera), s.light))
        .sum();
    #[expect(clippy::cast_precision_loss, reason = "a sample count")]
    let n = samples.len() as f64;
    sum / n
}

/// Runs `work` on every item, handing items out one at a time to one
/// thread per worker state (each thread owns one state for the whole run).
fn for_each_row<W: Send, I: Send>(
    items: Vec<I>,
    workers: &mut [W],
    work: impl Fn(&mut W, I) + Sync,
) {
    if let [only] = workers {
        items.into_iter().for_each(|item| work(only, item));
        return;
    }
    let queue = Mutex::new(items.into_iter());
    let next = || queue.lock().ok().and_then(|mut q| q.next());
    std::thread::scope(|scope| {
        for worker in workers.iter_mut() {
            let (next, work) = (&next, &work);
            scope.spawn(move || {
                while let Some(item) = next() {
                    work(worker, item);
                }
            });
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SCENES;

    /// The same seed gives bit-identical images at 1 and 2 threads, for
    /// samplers of every kind: a trait sampler, the streamed sweep, the
    /// streamed exact mode, the paper's scheme and the joint sets.
    #[test]
    fn images_do_not_depend_on_the_thread_count() {
        for scene_name in SCENES {
            let scene = Scene::by_name(scene_name, [9, 7]).expect("known scene");
            for name in [
                "poisson-pixel",
                "poisson-sweep",
                "poisson-exact-random",
                "poisson-paper",
                "poisson-joint",
            ] {
                let recipe = Recipe::new(name, 2, 9, [9, 7]).expect("builds");
                let one = render(&scene, &recipe, 1, &mut |_| {}).expect("renders");
                let two = render(&scene, &recipe, 2, &mut |_| {}).expect("renders");
                let bits = |r: &Rendered| {
                    r.image
                        .values
                        .iter()
                        .map(|v| v.to_bits())
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&one), bits(&two), "{scene_name}, {name}");
                assert_eq!(
                    one.samples_per_pixel, two.samples_per_pixel,
                    "{scene_name}, {name}"
                );
                assert!(
                    one.image.values.iter().all(|v| v.is_finite() && *v >= 0.0),
                    "{scene_name}, {name}"
                );
            }
        }
    }
}
