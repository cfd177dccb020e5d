//! Exact mode: exactly `n` points in every pixel, by weighted sample
//! elimination (Yuksel 2015, "Sample Elimination for Generating Poisson Disk
//! Sample Sets") applied pixel by pixel to an oversampled sweep.
//!
//! The sweep runs at the radius that gives about [`OVERSAMPLE`]`·n` points
//! per pixel. When a pixel is emitted, its points are thinned to `n` by
//! removing, one at a time, the point with the largest weight
//! `Σ (1 - d/2rₑ)⁸` over neighbours closer than `2rₑ`, where
//! `rₑ = sqrt(1 / (2√3·n))` is the spacing of `n` points per pixel on a
//! hexagonal lattice. The neighbours are the pixel's own remaining points
//! and the *oversampled* points of the pixels around it, on every side,
//! counted at a share [`NEIGHBOUR_SHARE`]. Every pixel thus sees the same
//! kind of surroundings, whichever side they are on. (Weighing the already thinned points of pixels emitted before
//! against the oversampled points of pixels still to come — the natural
//! streaming choice — left the left and top bands of every pixel 14–19 %
//! denser and the right and bottom ones 32–37 % sparser: the weight is so
//! steep that nearness to the denser side dominates any share.)
//!
//! Elimination only removes points, so the set keeps the minimum distance of
//! the oversampled sweep (ρ ≈ 0.52 for the kept density: close pairs across
//! pixel borders survive, since each pixel is thinned on its own). A pixel that received fewer than `n` points (rare
//! at this oversampling) is topped up with best-candidate darts: of 32
//! uniform darts in the pixel, the one farthest from every point near it.
//! Those may come closer than the sweep's radius; [`Pixels::top_ups`]
//! counts them.
//!
//! [`Pixels::top_ups`]: super::Pixels::top_ups

use super::window::Window;
use crate::random::unit;
use crate::vector::distance_squared;
use rand::Rng;

/// Points per pixel the sweep makes, relative to the `n` kept.
pub(crate) const OVERSAMPLE: f64 = 2.0;

/// Weight of a neighbouring pixel's oversampled point relative to one of
/// the pixel's own. Tuned, not derived: measured with `examples/stream.rs
/// --exact 4 --pixels 160x160`, the edge-band/interior density ratios are
/// 1.08–1.10 at 0.05, 0.99–1.01 at 0.1, 0.94–0.96 at 0.15, 0.85 at 0.3 and
/// 0.77 at 0.5. At 0.1 they are 1.04–1.07 for 8 per pixel and 0.75–0.77 for
/// 1 per pixel: the balance depends on `n`, which a better scheme should
/// not.
const NEIGHBOUR_SHARE: f64 = 0.1;

/// Exponent of the elimination weight (Yuksel's α).
const ALPHA: i32 = 8;

/// Darts per best-candidate top-up.
const DARTS: usize = 32;

/// Elimination settings for `n` points per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Thinning {
    pub(crate) n: usize,
    /// `2rₑ`: the reach of the weight.
    reach: f64,
    /// Pixels searched on each side for neighbours.
    pixels: usize,
}

impl Thinning {
    pub(crate) fn new(n: usize) -> Self {
        #[expect(clippy::cast_precision_loss, reason = "a count per pixel")]
        let r_e = (1.0 / (2.0 * 3f64.sqrt() * n as f64)).sqrt();
        let reach = 2.0 * r_e;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "reach <= 2 / sqrt(2√3) < 2 pixels"
        )]
        let pixels = reach.ceil() as usize;
        Self { n, reach, pixels }
    }

    /// Thins (or tops up) the points of pixel `(x, y)` to exactly `n`, in
    /// generation order, keeping the oversampled ones for the neighbours.
    /// Returns the number of top-up darts placed.
    pub(crate) fn apply<R: Rng + ?Sized>(
        &self,
        window: &mut Window,
        (x, y): (usize, usize),
        (width, height): (usize, usize),
        rng: &mut R,
    ) -> usize {
        // Neighbours outside the pixel, with their weight factor.
        let mut around: Vec<([f64; 2], f64)> = Vec::new();
        let reach = isize::try_from(self.pixels).unwrap_or(1);
        for dy in -reach..=reach {
            for dx in -reach..=reach {
                let (Some(qx), Some(qy)) = (x.checked_add_signed(dx), y.checked_add_signed(dy))
                else {
                    continue;
                };
                if (dx, dy) == (0, 0) || qx >= width || qy >= height || !window.holds_row(qy) {
                    continue;
                }
                let slot = window.slot(qx, qy);
                let made = if (qy, qx) < (y, x) {
                    &slot.oversampled
                } else {
                    &slot.points
                };
                around.extend(made.iter().map(|&p| (p, NEIGHBOUR_SHARE)));
            }
        }
        let Some(slot) = window.slot_mut(x, y) else {
            return 0;
        };
        let mut mine = core::mem::take(&mut slot.points);
        slot.oversampled.clone_from(&mine);
        let reach2 = self.reach * self.reach;
        let weight = |d2: f64| {
            if d2 < reach2 {
                (1.0 - d2.sqrt() / self.reach).powi(ALPHA)
            } else {
                0.0
            }
        };
        while mine.len() > self.n {
            // O(m²) per removal: m is about 2n, a handful of points.
            let mut worst = (f64::NEG_INFINITY, 0);
            for (i, p) in mine.iter().enumerate() {
                let own: f64 = mine
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, q)| weight(distance_squared(p, q)))
                    .sum();
                let outside: f64 = around
                    .iter()
                    .map(|(q, share)| share * weight(distance_squared(p, q)))
                    .sum();
                let w = own + outside;
                if w > worst.0 {
                    worst = (w, i);
                }
            }
            mine.remove(worst.1);
        }
        let mut top_ups = 0;
        #[expect(clippy::cast_precision_loss, reason = "pixel indices < 2^32")]
        let (fx, fy) = (x as f64, y as f64);
        while mine.len() < self.n {
            let mut best = (f64::NEG_INFINITY, [fx, fy]);
            for _ in 0..DARTS {
                let dart = [fx + unit(rng), fy + unit(rng)];
                if dart[0] >= fx + 1.0 || dart[1] >= fy + 1.0 {
                    continue;
                }
                let nearest = mine
                    .iter()
                    .chain(around.iter().map(|(q, _)| q))
                    .map(|q| distance_squared(&dart, q))
                    .fold(f64::INFINITY, f64::min);
                if nearest > best.0 {
                    best = (nearest, dart);
                }
            }
            mine.push(best.1);
            top_ups += 1;
        }
        if let Some(slot) = window.slot_mut(x, y) {
            slot.points = mine;
        }
        top_ups
    }
}
