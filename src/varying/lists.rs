//! The fallback index of a varying radius: a linked list per coarse cell
//! (side `r_max`), a head per cell and a next per point; a candidate is
//! checked against every point of the 3^N cells around it, its own cell
//! first. Slow where `r_max / r_min` is large (a cell then holds many
//! points), but its memory does not depend on `r_min`: it serves the
//! fields that [`Levels`](super::levels::Levels) cannot afford.

use super::coarse::Coarse;
use super::{Stored, too_close};

/// An empty list.
const NONE: u32 = u32::MAX;

#[derive(Debug)]
pub(super) struct Lists<const N: usize> {
    coarse: Coarse<N>,
    /// The first point of each cell, or `NONE`.
    heads: Vec<u32>,
    /// The next point in the same cell, or `NONE`.
    next: Vec<u32>,
}

impl<const N: usize> Lists<N> {
    pub(super) fn new(coarse: Coarse<N>) -> Self {
        Self {
            heads: vec![NONE; coarse.count()],
            coarse,
            next: Vec::new(),
        }
    }

    /// A stored point closer to `c` than `max(rc, its radius)`, if any.
    pub(super) fn blocked(
        &self,
        points: &[Stored<N>],
        periods: &[f64; N],
        c: &[f64; N],
        rc: f64,
    ) -> Option<usize> {
        let cell = self.coarse.cell_of(c);
        self.coarse.find_around(&cell, |at| {
            let mut k = self.heads.get(at).copied().unwrap_or(NONE);
            while k != NONE {
                let i = k as usize;
                if too_close(points, periods, c, rc, i) {
                    return Some(i);
                }
                k = self.next.get(i).copied().unwrap_or(NONE);
            }
            None
        })
    }

    /// Files point `index`, at `p`; `false` if it cannot be.
    pub(super) fn insert(&mut self, index: u32, p: &[f64; N]) -> bool {
        let cell = self.coarse.linear(&self.coarse.cell_of(p));
        let Some(head) = self.heads.get_mut(cell) else {
            return false;
        };
        self.next.push(*head);
        *head = index;
        true
    }
}
