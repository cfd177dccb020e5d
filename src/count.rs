//! Point counts as callers hold them: `u64`, `usize`, `u32`, or an integer
//! literal, and for a cap also `None` / `Some(u64)`.
//!
//! Sealed traits rather than `impl Into<Option<u64>>`: `usize` (what
//! `Vec::len` gives) has no `From` into `u64`. An untyped literal such as
//! `1000` is an `i32` to the compiler once more than one integer type is
//! accepted, so `i32` is accepted too, and a negative one is refused by
//! `build()` ([`Error::InvalidPointCount`](crate::Error::InvalidPointCount)),
//! as the crate's setters never fail. Only one `Option` type is accepted, so
//! that a bare `None` or `Some(1000)` needs no annotation.

mod sealed {
    /// The conversion behind [`PointCap`](super::PointCap); outside the
    /// crate it cannot be named, so no other type can implement it.
    pub trait Sealed {
        /// `Ok(Some(n))` for a count, `Ok(None)` for "no cap", `Err(())` for
        /// a negative number.
        fn to_cap(self) -> Result<Option<u64>, ()>;
    }
}

/// A number of points: a `u64`, `usize`, `u32` or an integer literal (an
/// `i32`, refused by `build()` if negative). Taken by
/// [`Builder::about_points`](crate::Builder::about_points).
pub trait PointCount: sealed::Sealed {}

/// A point cap: a `u64`, `usize`, `u32` or an integer literal (an `i32`,
/// refused by `build()` if negative) for "stop after that many", or an
/// `Option<u64>`, where `None` means no cap. Taken by
/// [`Builder::max_points`](crate::Builder::max_points).
///
/// # Example: the forms a cap can take
/// ```
/// use bridson::{Domain, PoissonDisk2};
/// let builder = PoissonDisk2::builder(Domain::from_extent([1.0, 1.0])?, 0.01);
/// let wanted: usize = 250;
/// for capped in [
///     builder.max_points(wanted),
///     builder.max_points(250),
///     builder.max_points(250_u64),
///     builder.max_points(Some(250)),
/// ] {
///     assert_eq!(capped.build()?.generate_seeded(1)?.len(), 250);
/// }
/// assert_eq!(builder.max_points(None).build()?.max_points(), None);
/// # Ok::<(), bridson::Error>(())
/// ```
pub trait PointCap: sealed::Sealed {}

/// Converts a count or cap: `Err(())` if negative.
pub(crate) fn to_cap(cap: impl PointCap) -> Result<Option<u64>, ()> {
    sealed::Sealed::to_cap(cap)
}

/// Converts a count: `Err(())` if negative.
pub(crate) fn to_count(count: impl PointCount) -> Result<u64, ()> {
    sealed::Sealed::to_cap(count).and_then(|c| c.ok_or(()))
}

macro_rules! integer_counts {
    ($($t:ty),*) => {$(
        impl sealed::Sealed for $t {
            fn to_cap(self) -> Result<Option<u64>, ()> {
                u64::try_from(self).map(Some).map_err(|_| ())
            }
        }
        impl PointCount for $t {}
        impl PointCap for $t {}
    )*};
}

integer_counts!(u64, usize, u32, i32);

impl sealed::Sealed for Option<u64> {
    fn to_cap(self) -> Result<Option<u64>, ()> {
        Ok(self)
    }
}

impl PointCap for Option<u64> {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_form_converts() {
        let n: usize = 7;
        assert_eq!(to_cap(n), Ok(Some(7)), "usize");
        assert_eq!(to_cap(7_u32), Ok(Some(7)), "u32");
        assert_eq!(to_cap(u64::MAX), Ok(Some(u64::MAX)), "u64");
        assert_eq!(to_cap(7), Ok(Some(7)), "literal");
        assert_eq!(to_cap(-1), Err(()), "negative literal");
        assert_eq!(to_cap(None), Ok(None), "no cap");
        assert_eq!(to_cap(Some(0)), Ok(Some(0)), "zero cap");
        assert_eq!(to_count(n), Ok(7), "count");
        assert_eq!(to_count(i32::MIN), Err(()), "negative count");
    }
}
