//! Streaming mode (`bridson::Tiled`), inputs decoded from raw bytes: see
//! `fuzz/common/streaming.rs`.
#![no_main]

#[path = "../../tests/common/mod.rs"]
mod common;

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/streaming.rs"]
mod streaming;

libfuzzer_sys::fuzz_target!(|data: &[u8]| streaming::run(data));
