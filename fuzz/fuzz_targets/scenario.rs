//! Scenario parser (TOML text -> validated `Scenario`); body: `pmu50::fuzzing::scenario`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50::fuzzing::scenario(data));
