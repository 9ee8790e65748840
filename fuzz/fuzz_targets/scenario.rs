//! Scenario parser (TOML text -> validated `Scenario`); body: `pmu50_testbench::fuzzing::scenario`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50_testbench::fuzzing::scenario(data));
