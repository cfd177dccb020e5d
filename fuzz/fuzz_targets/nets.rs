//! The Poisson disk net pixel sampler (`bridson::NetPixelSampler`), inputs
//! decoded from raw bytes: see `fuzz/common/nets.rs`.
#![no_main]

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/nets.rs"]
mod nets;

libfuzzer_sys::fuzz_target!(|data: &[u8]| nets::run(data));
