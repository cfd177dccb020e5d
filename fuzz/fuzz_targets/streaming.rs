//! Streaming mode (`bridson::Tiled`), inputs decoded from raw bytes: see
//! `fuzz/common/streaming.rs`.
#![no_main]

#[path = "../common/streaming.rs"]
mod streaming;

libfuzzer_sys::fuzz_target!(|data: &[u8]| streaming::run(data));
