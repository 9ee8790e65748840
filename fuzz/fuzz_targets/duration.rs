//! Duration parser (`"2.2 ms"` -> ns) and its printed form; body: `pmu50_testbench::fuzzing::duration`.
#![no_main]
libfuzzer_sys::fuzz_target!(|data: &[u8]| pmu50_testbench::fuzzing::duration(data));
