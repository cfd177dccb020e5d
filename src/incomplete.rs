//! The result of a run that stopped before its set was complete.

use crate::error::Error;
use core::fmt;

/// The points a run made before it stopped early, and why it stopped: the
/// `Err` of [`PoissonDisk::generate`](crate::PoissonDisk::generate) and
/// its kin. Every guarantee holds for these points (the spacing, the box),
/// but the set is not complete: parts of the domain have none. An
/// `Incomplete` converts into its [`Error`], so `?` in a function returning
/// `Result<_, bridson::Error>` works as before and drops the points.
///
/// # Example: keeping what a run made within its budget
/// ```
/// use bridson::{Domain, Error, PoissonDisk2};
/// let sampler = PoissonDisk2::builder(Domain::from_extent([1.0, 1.0])?, 0.0045)
///     .max_grid_bytes(300_000)
///     .build()?;
/// match sampler.generate_seeded(1) {
///     Ok(points) => println!("all {} points", points.len()),
///     Err(stopped) => {
///         assert!(matches!(stopped.error(), Error::MemoryBudgetExceeded { .. }));
///         let valid = stopped.into_points(); // valid, but not the whole box
///         assert!(!valid.is_empty());
///     }
/// }
/// # Ok::<(), bridson::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Incomplete<const N: usize> {
    points: Vec<[f64; N]>,
    error: Error,
}

impl<const N: usize> Incomplete<N> {
    pub(crate) fn new(points: Vec<[f64; N]>, error: Error) -> Self {
        Self { points, error }
    }

    /// Why the run stopped.
    pub fn error(&self) -> Error {
        self.error
    }

    /// The valid points made before it stopped (none if it stopped before
    /// its first, as a refused run does).
    pub fn points(&self) -> &[[f64; N]] {
        &self.points
    }

    /// The valid points made before it stopped.
    pub fn into_points(self) -> Vec<[f64; N]> {
        self.points
    }
}

impl<const N: usize> fmt::Display for Incomplete<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} ({} valid points kept)",
            self.error,
            self.points.len()
        )
    }
}

impl<const N: usize> std::error::Error for Incomplete<N> {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        Some(&self.error)
    }
}

impl<const N: usize> From<Incomplete<N>> for Error {
    fn from(stopped: Incomplete<N>) -> Self {
        stopped.error
    }
}
