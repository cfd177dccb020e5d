//! A progress bar on stderr for long runs, with an estimate of the time
//! left from the rate so far.

use std::io::Write;
use std::time::{Duration, Instant};

/// Progress over a known amount of work, redrawn on one stderr line at
/// most twice a second.
#[derive(Debug)]
pub(crate) struct Progress {
    name: &'static str,
    total: f64,
    done: f64,
    start: Instant,
    last_draw: Option<Instant>,
    drawn: bool,
}

impl Progress {
    /// Progress of the example `name` over `total` units of work.
    pub(crate) fn new(name: &'static str, total: f64) -> Self {
        Self {
            name,
            total: total.max(f64::MIN_POSITIVE),
            done: 0.0,
            start: Instant::now(),
            last_draw: None,
            drawn: false,
        }
    }

    /// Sets the units done so far to `done` and redraws, with `label`
    /// saying what is under way, if half a second has passed.
    pub(crate) fn set(&mut self, done: f64, label: &str) {
        self.done = done.clamp(0.0, self.total);
        let now = Instant::now();
        if self
            .last_draw
            .is_some_and(|t| now.duration_since(t) < Duration::from_millis(500))
        {
            return;
        }
        self.last_draw = Some(now);
        let fraction = self.done / self.total;
        let elapsed = now.duration_since(self.start).as_secs_f64();
        // Too little done for a rate: no estimate yet.
        let left =
            (fraction > 0.002 && elapsed > 1.0).then(|| elapsed * (1.0 - fraction) / fraction);
        self.draw(fraction, left, label);
    }

    fn draw(&mut self, fraction: f64, left: Option<f64>, label: &str) {
        const WIDTH: f64 = 30.0;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a fraction in [0, 1] times 30"
        )]
        let filled = (fraction * WIDTH).round() as usize;
        let bar = format!("{}{}", "#".repeat(filled), ".".repeat(30 - filled.min(30)));
        let eta = left.map_or_else(|| "--".to_owned(), clock);
        let mut err = std::io::stderr().lock();
        let _ = write!(
            err,
            "\r{}: [{bar}] {:3.0}% {eta} left  {label:<48.48}",
            self.name,
            100.0 * fraction
        );
        let _ = err.flush();
        self.drawn = true;
    }

    /// Ends the bar's line, printing the time taken.
    pub(crate) fn finish(&mut self) {
        if self.drawn {
            let elapsed = self.start.elapsed().as_secs_f64();
            let mut err = std::io::stderr().lock();
            let _ = writeln!(err, "\r{}: done in {}{:70}", self.name, clock(elapsed), "");
        }
    }
}

/// Seconds as `1h02m`, `3m05s` or `42s`.
pub(crate) fn clock(seconds: f64) -> String {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a non-negative duration in seconds, far below 2^64"
    )]
    let s = seconds.max(0.0).round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, s / 60 % 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_reads_like_a_clock() {
        assert_eq!(clock(42.4), "42s", "seconds");
        assert_eq!(clock(185.0), "3m05s", "minutes");
        assert_eq!(clock(3725.0), "1h02m", "hours");
        assert_eq!(clock(-3.0), "0s", "never negative");
    }
}
