//! The field sampler, dimensions 1 to 3, inputs decoded from raw bytes:
//! see `fuzz/common/field.rs`.
#![no_main]

#[path = "../common/bytes.rs"]
mod bytes;

#[path = "../common/field.rs"]
mod field;

libfuzzer_sys::fuzz_target!(|data: &[u8]| field::run(data));
