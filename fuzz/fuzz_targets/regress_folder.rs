//! The readers of a regression folder (`regress.json`, `results.jsonl`, merge inputs: two folders
//! and a coverage file, separated by NUL bytes); body: `pmu50_verif::fuzzing::regress_folder`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50_verif::fuzzing::regress_folder(data));
