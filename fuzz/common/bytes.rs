//! The byte reader the fuzz targets decode their inputs with, shared by
//! `batch.rs`, `streaming.rs` and `camera.rs` (and so by
//! `tests/fuzz_corpus.rs`), with two helpers the last two share. The
//! including crate declares it as `mod bytes;`.

/// Reads numbers from the fuzz input, little-endian; zeros past the end.
pub(crate) struct Bytes<'a> {
    data: &'a [u8],
}

impl<'a> Bytes<'a> {
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Self { data }
    }

    fn array<const K: usize>(&mut self) -> [u8; K] {
        let mut out = [0u8; K];
        let n = K.min(self.data.len());
        let (head, rest) = self.data.split_at(n);
        out[..n].copy_from_slice(head);
        self.data = rest;
        out
    }

    pub(crate) fn u8(&mut self) -> u8 {
        self.array::<1>()[0]
    }

    pub(crate) fn u16(&mut self) -> u16 {
        u16::from_le_bytes(self.array())
    }

    pub(crate) fn u32(&mut self) -> u32 {
        u32::from_le_bytes(self.array())
    }

    pub(crate) fn u64(&mut self) -> u64 {
        u64::from_le_bytes(self.array())
    }

    #[allow(dead_code, reason = "not every target uses it")]
    pub(crate) fn f64_bits(&mut self) -> f64 {
        f64::from_bits(self.u64())
    }
}

/// `lo · (hi / lo)^t`, `t` uniform in `[0, 1]` from the next two bytes:
/// log-uniform.
#[allow(dead_code, reason = "not every target uses it")]
pub(crate) fn log_uniform(b: &mut Bytes<'_>, lo: f64, hi: f64) -> f64 {
    let t = f64::from(b.u16()) / 65535.0;
    lo * (hi / lo).powf(t)
}

/// `x` moved by `steps` ulps (finite `x` only).
#[allow(dead_code, reason = "not every target uses it")]
pub(crate) fn ulps(x: f64, steps: i8) -> f64 {
    let mut y = x;
    for _ in 0..steps.unsigned_abs() {
        y = if steps > 0 {
            y.next_up()
        } else {
            y.next_down()
        };
    }
    y
}
