//! Chunked queries (placeholder).

/// A box cut into chunks.
#[derive(Clone, Debug)]
pub struct Chunks;
