//! Batch sampler, dimensions 1 to 8, inputs decoded from raw bytes: see
//! `fuzz/common/batch.rs`.
#![no_main]

#[path = "../../tests/common/mod.rs"]
mod common;

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/batch.rs"]
mod batch;

libfuzzer_sys::fuzz_target!(|data: &[u8]| batch::run(data));
