//! The `nets` fuzz target's logic (`bridson::NetPixelSampler` through the
//! `PixelSampler` trait), shared with `tests/fuzz_corpus.rs`. Plain Rust on
//! std and `bridson` only; the including crate declares `mod bytes;`.
//!
//! Decodes a sample count (mostly 1 to 64, sometimes 0, 256, 257 or up to
//! `u32::MAX`), a seed, an optional image size (sides 0 to 15), then one
//! operation per input byte (at most [`OP_LIMIT`]): `start_pixel_sample`
//! with pixels, indices and dimensions near the limits, `get_1d`, `get_2d`,
//! `get_pixel_2d`, `camera_sample`, a draw from a clone, and a whole pixel.
//! A model follows the sampler: `new` fails exactly for counts outside
//! `1..=NET_MAX_SAMPLES_PER_PIXEL`; `start_pixel_sample` fails exactly as
//! the trait says (index first) and leaves the sampler where it was; the
//! dimension counter moves by 1, 2, 0 and 3; every value is in `[0, 1)`; a
//! clone gives the same bits; a whole pixel's film offsets and 2-D pairs
//! are nets at powers of two and stratified in x and y otherwise, its 1-D
//! values stratified, and no two of its 2-D points closer than
//! `min_distance_2d`.

use crate::bytes::Bytes;
use bridson::{Error, NET_MAX_SAMPLES_PER_PIXEL, NetPixelSampler, PixelSampler};

/// Most operations per input.
const OP_LIMIT: usize = 64;

/// Decodes `data` and checks the sampler against the model.
pub(crate) fn run(data: &[u8]) {
    let mut b = Bytes::new(data);
    let spp = match b.u8() % 8 {
        0 => 0,
        1 => 256,
        2 => 257,
        3 => b.u32(),
        _ => u32::from(b.u8() % 64) + 1,
    };
    let seed = b.u64();
    let resolution = (b.u8() % 2 == 1).then(|| [u32::from(b.u8() % 16), u32::from(b.u8() % 16)]);
    let built = NetPixelSampler::new(spp, seed);
    let Ok(sampler) = built else {
        assert!(
            spp == 0 || spp > NET_MAX_SAMPLES_PER_PIXEL,
            "new({spp}) failed: {built:?}"
        );
        assert_eq!(
            built.err(),
            Some(Error::InvalidSamplesPerPixel {
                spp,
                max: NET_MAX_SAMPLES_PER_PIXEL
            }),
            "new({spp})"
        );
        return;
    };
    assert!(
        (1..=NET_MAX_SAMPLES_PER_PIXEL).contains(&spp),
        "new({spp}) succeeded"
    );
    let mut s = match resolution {
        Some(r) => sampler.with_resolution(r),
        None => sampler,
    };
    let mut model = ([0u32, 0u32], 0u32, 0u32);
    for _ in 0..OP_LIMIT {
        let op = b.u8();
        match op % 8 {
            0 => {
                let pixel = [near(&mut b), near(&mut b)];
                let index = match b.u8() % 4 {
                    0 => spp,
                    1 => spp - 1,
                    2 => u32::MAX,
                    _ => b.u32() % spp,
                };
                let dimension = match b.u8() % 3 {
                    0 => u32::MAX - u32::from(b.u8() % 4),
                    _ => u32::from(b.u8()),
                };
                let got = s.start_pixel_sample(pixel, index, dimension);
                let expected = if index >= spp {
                    Err(Error::SampleIndexOutOfRange { index, spp })
                } else if let Some(r) = resolution
                    && (pixel[0] >= r[0] || pixel[1] >= r[1])
                {
                    Err(Error::PixelOutOfImage {
                        pixel,
                        resolution: r,
                    })
                } else {
                    Ok(())
                };
                assert_eq!(
                    got, expected,
                    "start_pixel_sample({pixel:?}, {index}, {dimension})"
                );
                if got.is_ok() {
                    model = (pixel, index, dimension);
                }
            }
            1 => {
                unit(s.get_1d());
                model.2 = model.2.wrapping_add(1);
            }
            2 => {
                s.get_2d().into_iter().for_each(unit);
                model.2 = model.2.wrapping_add(2);
            }
            3 => {
                s.get_pixel_2d().into_iter().for_each(unit);
            }
            4 => {
                let mut c = s.clone();
                let a = s.camera_sample();
                let film = c.get_pixel_2d();
                let time = c.get_1d();
                let lens = c.get_2d();
                assert_eq!(
                    (a.film, a.time, a.lens),
                    (film, time, lens),
                    "camera_sample"
                );
                model.2 = model.2.wrapping_add(3);
            }
            5 => {
                let mut c = s.clone();
                assert_eq!(c.get_2d(), s.get_2d(), "clone");
                model.2 = model.2.wrapping_add(2);
            }
            6 if spp <= 64 => whole_pixel(&s, model.0),
            _ => {}
        }
        assert_eq!((s.pixel(), s.sample_index(), s.dimension()), model, "state");
    }
}

fn near(b: &mut Bytes<'_>) -> u32 {
    match b.u8() % 4 {
        0 => u32::MAX - u32::from(b.u8() % 2),
        1 => u32::from(b.u8() % 16),
        _ => u32::from(b.u8()),
    }
}

fn unit(v: f64) {
    assert!((0.0..1.0).contains(&v), "{v} outside [0, 1)");
}

/// Every sample of `pixel`, on a clone: nets or stratified sets, spaced.
fn whole_pixel(s: &NetPixelSampler, pixel: [u32; 2]) {
    let mut c = s.clone();
    if c.start_pixel_sample(pixel, 0, 0).is_err() {
        // The sampler's first pixel, [0, 0], lies outside a small image.
        return;
    }
    let n = c.samples_per_pixel();
    let mut sets: [Vec<[f64; 2]>; 3] = Default::default();
    let mut times = Vec::new();
    for i in 0..n {
        c.start_pixel_sample(pixel, i, 0).expect("a valid pixel");
        let cs = c.camera_sample();
        sets[0].push(cs.film);
        sets[1].push(cs.lens);
        sets[2].push(c.get_2d());
        times.push(cs.time);
    }
    let n = n as usize;
    assert!(stratified(times.iter().copied(), n), "time");
    let floor = c.min_distance_2d();
    for set in &sets {
        assert!(stratified(set.iter().map(|p| p[0]), n), "x");
        assert!(stratified(set.iter().map(|p| p[1]), n), "y");
        if n.is_power_of_two() {
            let m = n.trailing_zeros();
            for k in 0..=m {
                let (cols, rows) = (1usize << k, n >> k);
                let mut seen = vec![false; n];
                for &[x, y] in set {
                    #[allow(
                        clippy::cast_possible_truncation,
                        clippy::cast_sign_loss,
                        clippy::cast_precision_loss,
                        reason = "cells of a small grid"
                    )]
                    let cell = (x * cols as f64) as usize * rows + (y * rows as f64) as usize;
                    assert!(!std::mem::replace(&mut seen[cell], true), "not a net");
                }
            }
        }
        if let Some(r) = floor {
            for (j, p) in set.iter().enumerate() {
                for q in &set[..j] {
                    let d = |a: f64, b: f64| {
                        let d = (a - b).abs();
                        d.min(1.0 - d)
                    };
                    let (dx, dy) = (d(p[0], q[0]), d(p[1], q[1]));
                    assert!(
                        dx * dx + dy * dy >= r * r * (1.0 - 1e-12),
                        "closer than {r}"
                    );
                }
            }
        }
    }
}

fn stratified(values: impl Iterator<Item = f64>, n: usize) -> bool {
    let mut seen = vec![false; n];
    values.into_iter().all(|v| {
        #[allow(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            clippy::cast_precision_loss,
            reason = "strata of a small count"
        )]
        let j = (v * n as f64) as usize;
        j < n && !std::mem::replace(&mut seen[j], true)
    })
}
