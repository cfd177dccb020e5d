//! The serialised form of a [`Tiled`] sampler's settings (feature `serde`).
//!
//! A [`TiledBuilder`] keeps its spacing as one private enum; on the wire it
//! is one of three optional fields, `radius`, `per_pixel` or `exact`, as on
//! the `points` command line. `exact` may come with either of the others
//! (it overrides them, as [`TiledBuilder::exact`] does); `radius` with
//! `per_pixel` is refused, since the builder keeps only the last one given.
//! Exact mode's knobs are `exact_method` (`"eliminate"`, `"random"`),
//! `exact_oversample` and `exact_edge_bias` (`[βx, βy, γ]` or null for the
//! calibrated table), checked by `build()` like the rest. `attempts` absent
//! or null means the default `k` (30, or `EXACT_ATTEMPTS` in exact mode).
//! A [`Tiled`] is (de)serialised as its builder, and deserialising it runs
//! [`TiledBuilder::build`], so a bad file is an [`Error`], never a bad
//! sampler.

use super::exact::DEFAULT_OVERSAMPLE;
use super::{DEFAULT_MAX_WINDOW_BYTES, ExactMethod, Scheme, Spacing, Tiled, TiledBuilder};
use crate::candidates::Candidates;
use crate::error::Error;

/// The fields of a [`TiledBuilder`] as written: `width` and `height` are
/// required, the rest have the builder's defaults, unknown fields are
/// errors.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(rename = "Tiled", deny_unknown_fields)]
pub(super) struct TiledRepr {
    width: u32,
    height: u32,
    #[serde(default)]
    radius: Option<f64>,
    #[serde(default)]
    per_pixel: Option<f64>,
    #[serde(default)]
    exact: Option<u32>,
    #[serde(default)]
    exact_method: ExactMethod,
    #[serde(default = "default_oversample")]
    exact_oversample: f64,
    #[serde(default)]
    exact_edge_bias: Option<[f64; 3]>,
    #[serde(default)]
    attempts: Option<u32>,
    #[serde(default)]
    candidates: Candidates,
    #[serde(default)]
    scheme: Scheme,
    #[serde(default = "default_window")]
    max_window_bytes: u64,
}

fn default_oversample() -> f64 {
    DEFAULT_OVERSAMPLE
}

fn default_window() -> u64 {
    DEFAULT_MAX_WINDOW_BYTES
}

/// Why a serialised builder cannot be read.
const BOTH_SPACINGS: &str =
    "give the spacing as `radius` or `per_pixel`, not both (`exact` may come with either)";

impl TryFrom<TiledRepr> for TiledBuilder {
    type Error = &'static str;
    fn try_from(raw: TiledRepr) -> Result<Self, &'static str> {
        let spacing = match (raw.radius, raw.per_pixel) {
            (Some(_), Some(_)) => return Err(BOTH_SPACINGS),
            (Some(r), None) => Spacing::Radius(r),
            (None, Some(n)) => Spacing::PerPixel(n),
            (None, None) => Spacing::Unset,
        };
        Ok(Self {
            width: raw.width,
            height: raw.height,
            spacing,
            attempts: raw.attempts,
            candidates: raw.candidates,
            scheme: raw.scheme,
            max_window_bytes: raw.max_window_bytes,
            exact: raw.exact,
            exact_method: raw.exact_method,
            exact_oversample: raw.exact_oversample,
            exact_bias: raw.exact_edge_bias,
        })
    }
}

impl From<TiledBuilder> for TiledRepr {
    fn from(b: TiledBuilder) -> Self {
        let (radius, per_pixel) = match b.spacing {
            Spacing::Unset => (None, None),
            Spacing::Radius(r) => (Some(r), None),
            Spacing::PerPixel(n) => (None, Some(n)),
        };
        Self {
            width: b.width,
            height: b.height,
            radius,
            per_pixel,
            exact: b.exact,
            exact_method: b.exact_method,
            exact_oversample: b.exact_oversample,
            exact_edge_bias: b.exact_bias,
            attempts: b.attempts,
            candidates: b.candidates,
            scheme: b.scheme,
            max_window_bytes: b.max_window_bytes,
        }
    }
}

impl TryFrom<TiledBuilder> for Tiled {
    type Error = Error;
    fn try_from(builder: TiledBuilder) -> Result<Self, Error> {
        builder.build()
    }
}

impl From<Tiled> for TiledBuilder {
    fn from(tiled: Tiled) -> Self {
        tiled.settings
    }
}
