//! Exact mode's step 3 by [`ExactMethod::Random`]: each pixel's excess
//! points dropped at random, weighed by the edge correction.

use super::Exact;
#[cfg(doc)]
use super::ExactMethod;
use crate::random::{below, unit};
use rand::Rng;

impl Exact {
    /// Step 3, [`ExactMethod::Random`]: each pixel of row `y` drops its
    /// excess points uniformly at random.
    pub(super) fn drop_at_random<R: Rng + ?Sized>(&mut self, width: usize, rng: &mut R) {
        // The correction changes only between rows (`Exact::store`).
        let corrects = self.corrects();
        for x in 0..width {
            let (Some(&a), Some(&z)) = (self.start.get(x), self.start.get(x + 1)) else {
                continue;
            };
            // Darts only go to short pixels, which end at n: an excess
            // pixel's live points are all among its gathered ones.
            if corrects && self.count.get(x).is_some_and(|&c| c > self.n) {
                let mut factors = core::mem::take(&mut self.factor);
                factors.clear();
                factors.extend((a..z).map(|i| self.edge_factor(i)));
                self.factor = factors;
            }
            while let Some(&c) = self.count.get(x)
                && c > self.n
            {
                if !corrects {
                    let mut k = below(rng, c);
                    for i in a..z {
                        if self.alive.get(i) == Some(&true) {
                            if k == 0 {
                                self.kill(i);
                                break;
                            }
                            k -= 1;
                        }
                    }
                } else {
                    let live = |i: usize| self.alive.get(i) == Some(&true);
                    let factor = |i: usize| self.factor.get(i - a).copied().unwrap_or(1.0);
                    let total: f64 = (a..z).filter(|&i| live(i)).map(factor).sum();
                    let mut t = unit(rng) * total;
                    let mut last = None;
                    for i in a..z {
                        if live(i) {
                            last = Some(i);
                            t -= factor(i);
                            if t < 0.0 {
                                break;
                            }
                        }
                    }
                    if let Some(i) = last {
                        self.kill(i);
                    }
                }
            }
        }
    }
}
