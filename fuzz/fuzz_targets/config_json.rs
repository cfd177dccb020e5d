//! Sampler configurations deserialised from arbitrary JSON (the `serde`
//! feature): see `fuzz/common/config_json.rs`.
#![no_main]

#[path = "../../tests/common/mod.rs"]
mod common;

#[path = "../common/bytes.rs"]
#[allow(dead_code, reason = "only batch.rs's decoding uses it")]
mod bytes;

#[path = "../common/batch.rs"]
#[allow(dead_code, reason = "only batch::check_generate is used here")]
mod batch;

#[path = "../common/config_json.rs"]
mod config_json;

libfuzzer_sys::fuzz_target!(|data: &[u8]| config_json::run(data));
