//! A sign-off folder (regress.json, results.jsonl, coverage.json, code/summary.json, the proofs,
//! formal, lint and X reports, separated by NUL bytes): no panic, and no row met from an input not
//! as its maker wrote it; body: `pmu50_verif::fuzzing::signoff_folder`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50_verif::fuzzing::signoff_folder(data));
