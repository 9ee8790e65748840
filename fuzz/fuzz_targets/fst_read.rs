//! FST checks, reader (wellen) and diff of a file with itself; body: `pmu50_waves::fuzzing::fst`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50_waves::fuzzing::fst(data));
