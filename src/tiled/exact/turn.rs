//! `cos` and `sin` of a fraction of a turn from `+ - ×` only, for exact
//! mode's edge correction and its feedback: the same bits on every
//! platform (the crate uses no libm function where a result can change
//! points).

/// `(cos 2πf, sin 2πf)` for `f` in `[0, 1)`: the half angle `a = π·(f - ½)` in
/// `[-π/2, π/2)` by Taylor series to `a¹³` and `a¹⁴` (error under 10⁻⁷),
/// then doubled, and turned by half a turn.
pub(super) fn turn(f: f64) -> (f64, f64) {
    let a = core::f64::consts::PI * (f - 0.5);
    let a2 = a * a;
    // Horner's form: sin a = a·(1 - a²/(2·3)·(1 - a²/(4·5)·(…))), to a¹³;
    // cos a = 1 - a²/(1·2)·(1 - a²/(3·4)·(…)), to a¹⁴.
    let mut s = 1.0;
    for k in SIN_STEPS.iter().rev() {
        s = 1.0 - a2 * k * s;
    }
    let mut c = 1.0;
    for k in COS_STEPS.iter().rev() {
        c = 1.0 - a2 * k * c;
    }
    let s = a * s;
    // 2πf = 2a + π: cos(2a + π) = 2 sin²a - 1, sin(2a + π) = -2 sin a cos a.
    (2.0 * s * s - 1.0, -2.0 * s * c)
}

/// `1 / (2k·(2k + 1))` for `k` = 1 to 6: the sine series' steps.
const SIN_STEPS: [f64; 6] = [
    1.0 / 6.0,
    1.0 / 20.0,
    1.0 / 42.0,
    1.0 / 72.0,
    1.0 / 110.0,
    1.0 / 156.0,
];

/// `1 / ((2k - 1)·2k)` for `k` = 1 to 7: the cosine series' steps.
const COS_STEPS: [f64; 7] = [
    1.0 / 2.0,
    1.0 / 12.0,
    1.0 / 30.0,
    1.0 / 56.0,
    1.0 / 90.0,
    1.0 / 132.0,
    1.0 / 182.0,
];

#[cfg(test)]
mod tests {
    use super::turn;

    /// The series matches the platform's `sin_cos` to 10⁻⁷ over the pixel.
    #[test]
    fn turn_is_cos_and_sin_of_the_turn() {
        for i in 0..=10_000 {
            let f = f64::from(i) / 10_001.0;
            let (c, s) = turn(f);
            let (s0, c0) = (core::f64::consts::TAU * f).sin_cos();
            assert!(
                (c - c0).abs() < 1e-7 && (s - s0).abs() < 1e-7,
                "{f}: {c} {s}"
            );
        }
    }
}
