//! Bad input is a clear error naming the file, the line and the field, never a panic.

use pmu50_testbench::scenario::{Scenario, ScenarioError};
use proptest::prelude::*;
use std::path::Path;

fn err(text: &str) -> String {
    match Scenario::parse(text, "bad.toml", "bad", Path::new("bad.toml")) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// (scenario text, substrings the message must contain)
const CASES: &[(&str, &[&str])] = &[
    // zero and negative durations
    ("duration = \"0 ms\"", &["bad.toml:1:", "`duration`", "longer than zero"]),
    ("duration = \"10 ms\"\n[core]\nt1 = \"0 ms\"", &["bad.toml:3:", "core.t1", "longer than zero"]),
    ("duration = \"10 ms\"\n[core]\nt2 = \"-1.1 ms\"", &["bad.toml:3:", "core.t2", "negative"]),
    // wrong units
    ("duration = \"10 ms\"\n[core]\nx = \"6.6\"", &["bad.toml:3:", "core.x", "no unit"]),
    ("duration = \"10 ms\"\n[core]\nx = \"6.6 min\"", &["bad.toml:3:", "core.x", "valid units are s, ms, us, ns"]),
    // not whole ticks
    ("duration = \"10 ms\"\n[core]\nt2 = \"1.105 ms\"", &["bad.toml:3:", "core.t2", "not a whole number of clock ticks"]),
    ("duration = \"10.005 ms\"", &["bad.toml:1:", "duration", "whole number of clock ticks"]),
    // Wt longer than the interval
    ("duration = \"10 ms\"\n[core]\npi = \"3 ms\"", &["bad.toml:3:", "core.pi", "Wt"]),
    // no settling tick: sample before the registered sr rises
    ("duration = \"10 ms\"\n[core]\npw = \"0 us\"\npi = \"0 us\"\nps = \"10 us\"", &["bad.toml:4:", "core.pi", "pw + pi"]),
    // minimum above x
    ("duration = \"10 ms\"\n[core]\n\nmin = \"7 ms\"", &["bad.toml:4:", "core.min", "maximum interval x"]),
    // out-of-range integers
    ("duration = \"10 ms\"\n[core]\ncth = 0", &["bad.toml:3:", "core.cth", "valid is a whole number of quiet pulses from 1 to 255"]),
    ("duration = \"10 ms\"\n[core]\nsync_depth = 9", &["bad.toml:3:", "core.sync_depth", "valid is a whole number of flip-flops from 1 to 4"]),
    ("duration = \"10 ms\"\n[core]\ncnt_width = 256", &["bad.toml:3:", "`core.cnt_width`: 256 is out of range; valid is a whole number of bits from 2 to 16"]),
    ("duration = \"10 ms\"\n[core]\ncnt_width = -1", &["bad.toml:3:", "valid is a whole number of bits from 2 to 16"]),
    ("duration = \"10 ms\"\ncore = []", &["bad.toml:2:", "expected a table (a `[section]` of `key = value` lines, or `{ key = value, ... }`), got an array"]),
    ("duration = \"10 ms\"\nenv = 3", &["bad.toml:2:", "expected a table", "got integer `3`"]),
    ("duration = \"10 ms\"\nevents = 3", &["bad.toml:2:", "expected an array `[...]`"]),
    ("duration = \"10 ms\"\n[env]\nvcc1_v = \"5\"", &["bad.toml:3:", "expected a number"]),
    ("duration = \"10 ms\"\n[expect]\ndiag = 1", &["bad.toml:3:", "expected true or false"]),
    // unknown fields, anywhere
    ("duration = \"10 ms\"\nspeed = 3", &["bad.toml:2:", "unknown field `speed`", "duration"]),
    ("duration = \"10 ms\"\n[core]\nt3 = \"1 ms\"", &["bad.toml:3:", "unknown field `t3`", "t2"]),
    ("duration = \"10 ms\"\n[env.sensor2]\ngain = 1.0", &["bad.toml:3:", "unknown field `gain`"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"1 ms\"\nig = true\nfoo = 1", &["bad.toml:5:", "unknown field `foo`"]),
    // times that go backwards, events outside the run
    ("duration = \"10 ms\"\n[[events]]\nat = \"5 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nig = false", &["bad.toml:6:", "events[1].at", "backwards"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"10 ms\"\nig = true", &["bad.toml:3:", "events[0].at", "not before the end"]),
    // events with zero or two actions
    ("duration = \"10 ms\"\n[[events]]\nat = \"1 ms\"", &["bad.toml:", "events[0]", "exactly one action"]),
    // register writes: unknown, read-only, too wide, key off
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"1 ms\"\nwrite = { reg = \"FOO\", value = 1 }", &["bad.toml:7:", "events[1].write.reg", "unknown register `FOO`", "SI_MAX"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"1 ms\"\nwrite = { reg = \"CNT_S\", value = 1 }", &["bad.toml:7:", "read-only"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"1 ms\"\nwrite = { reg = \"CTH\", value = 300 }", &["bad.toml:7:", "write.value", "0..=255"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"1 ms\"\nwrite = { reg = \"T2\", value = 100 }", &["bad.toml:3:", "events[0].write", "key is off"]),
    // motor
    ("duration = \"10 ms\"\n[motor]\nsegments = [ { kind = \"spin\", duration = \"1 ms\" } ]", &["bad.toml:3:", "motor.segments[0].kind", "\"hold\" and \"move\""]),
    ("duration = \"10 ms\"\n[motor]\nsegments = [ { kind = \"move\", duration = \"1 ms\" } ]", &["bad.toml:3:", "delta_deg"]),
    ("duration = \"10 ms\"\n[motor]\nsegments = [ { kind = \"move\", duration = \"0 ms\", delta_deg = 5.0 } ]", &["bad.toml:3:", "longer than zero"]),
    // environment values
    ("duration = \"10 ms\"\n[env.comparator]\nvr_err_s = 1.5", &["bad.toml:3:", "env.comparator.vr_err_s", "between -1.0 and 1.0"]),
    // env errors name the line of the field, not line 1
    ("duration = \"10 ms\"\n\n[env.sensor2]\ngain_s = 1.0\ntau_us = -5.0\n[motor]\nstart_deg = 1.0", &["bad.toml:5:", "env.sensor2.tau_us"]),
    ("duration = \"10 ms\"\nenv.comparator = { vr_err_c = 0.0, vr_err_s = 2.0 }", &["bad.toml:2:", "env.comparator.vr_err_s"]),
    ("duration = \"10 ms\"\n[env]\n\nvcc1_v = 50.0", &["bad.toml:4:", "env.vcc1_v", "0 < V <= 40"]),
    ("duration = \"10 ms\"\n[env]\nvcc1_v = 5.0\ntheta_t_deg = 91.0", &["bad.toml:4:", "env.theta_t_deg", "-90 to 90 degrees"]),
    // two writes at the same time: only the last would happen
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nwrite = { reg = \"T2\", value = 100 }\n[[events]]\nat = \"2 ms\"\nwrite = { reg = \"T1\", value = 100 }", &["bad.toml:10:", "events[2].write", "a second write at 2 ms (the write of line 7 is at the same time)"]),
    // a read: an 8-bit address, the key on, one bus access a tick
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nread = 256", &["bad.toml:7:", "events[1].read", "bus address 256 does not fit the 8-bit bus_addr; valid is 0..=255"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nread = -1", &["bad.toml:7:", "events[1].read", "valid is 0..=255"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"2 ms\"\nread = 224", &["bad.toml:3:", "events[0].read", "the key is off at this time"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nwrite = { reg = \"T2\", value = 100 }\n[[events]]\nat = \"2 ms\"\nread = 224", &["bad.toml:10:", "events[2].read", "a read at 2 ms (the write of line 7 is at the same time)"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n[[events]]\nat = \"2 ms\"\nread = 224\n[[events]]\nat = \"2 ms\"\nwrite = { reg = \"T1\", value = 100 }", &["bad.toml:10:", "events[2].write", "a second bus access at 2 ms (the read of line 7 is at the same time)"]),
    ("duration = \"10 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\nread = 224", &["bad.toml:2:", "events[0]", "exactly one action (ig, write, read, bus_write, vs2_fault or vs2_pg_leak); this one has 2"]),
    // expectations and defaults that no longer fit name their line
    ("duration = \"10 ms\"\n[expect]\ndiag = false\nreadout_within_deg = -1.0", &["bad.toml:4:", "expect.readout_within_deg", "positive angle"]),
    ("duration = \"10 ms\"\n[expect]\n\nsi_sequence_ms = [6.6, 0.0]", &["bad.toml:4:", "expect.si_sequence_ms"]),
    ("duration = \"10 ms\"\n[core]\nadaptive = true\nclock = \"1 ms\"", &["bad.toml:4:", "with the default values of the fields not given"]),
    // a dump window beyond the run
    ("duration = \"10 ms\"\n[vcd]\nwindow = [\"2 ms\", \"12 ms\"]", &["bad.toml:3:", "vcd.window[1]", "after the end of the run (duration = 10 ms)"]),
    ("duration = \"10 ms\"\n[env]\nvcc2_v = -3.3", &["env.vcc2_v", "0 < V <= 40"]),
    // syntax and types
    ("duration = 10", &["bad.toml:1:", "string"]),
    ("duration = \"10 ms\"\n[core\n", &["bad.toml:2:"]),
    ("name = \"a b\"\nduration = \"1 ms\"", &["bad.toml:1:", "`name`", "letters, digits"]),
    ("[vcd]\nwindow = [\"2 ms\"]\n", &["missing field `duration`"]),
    ("duration = \"10 ms\"\n[vcd]\nwindow = [\"5 ms\", \"2 ms\"]", &["bad.toml:3:", "vcd.window[1]", "ends before it starts"]),
];

#[test]
fn each_bad_input_names_file_line_and_field() {
    for (text, want) in CASES {
        let msg = err(text);
        for w in *want {
            assert!(
                msg.contains(w),
                "message for\n{text}\n---\n{msg}\n--- lacks `{w}`"
            );
        }
        // No Rust type or internal struct names (RawCore, u8, f64, Spanned, ...).
        for internal in [
            "Raw",
            "struct",
            "Spanned",
            "u8",
            "u16",
            "u32",
            "i64",
            "f64",
            "a sequence",
        ] {
            assert!(
                !msg.contains(internal),
                "message for\n{text}\n---\n{msg}\n--- names `{internal}`"
            );
        }
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let e = Scenario::load(Path::new("no/such/scenario.toml")).unwrap_err();
    assert!(matches!(e, ScenarioError::Io { .. }));
    assert!(
        std::error::Error::source(&e).is_some(),
        "the io::Error is the source"
    );
    assert!(e.to_string().contains("no/such/scenario.toml"), "{e}");
}

const VALID: &str = r#"name = "ok"
duration = "20 ms"
[core]
clock = "10 us"
x = "6.6 ms"
t2 = "1.1 ms"
cth = 4
[env.comparator]
vr_err_s = -0.1
[motor]
start_deg = 10.0
segments = [ { kind = "move", duration = "5 ms", delta_deg = 30.0 } ]
[[events]]
at = "0 ms"
ig = true
[[events]]
at = "5 ms"
write = { reg = "T2", value = 220 }
[expect]
diag = false
"#;

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// Any corruption of a valid file is either accepted or an error, never a panic; an
    /// accepted scenario also runs without panicking.
    #[test]
    fn no_panic_on_corrupted_files(pos in 0usize..VALID.len(), del in 0usize..6, ins in "[ -~\n]{0,6}") {
        let mut s = VALID.to_string();
        let p = (0..=pos).rev().find(|&i| s.is_char_boundary(i)).unwrap_or(0);
        let end = (p + del).min(s.len());
        let end = (end..=s.len()).find(|&i| s.is_char_boundary(i)).unwrap_or(s.len());
        s.replace_range(p..end, &ins);
        if let Ok(sc) = Scenario::parse(&s, "fuzz.toml", "fuzz", Path::new("fuzz.toml")) {
            if sc.ticks < 20_000 {
                let _ = pmu50_testbench::sim::run(&sc, pmu50_testbench::sim::SimOptions::default(), &mut []);
            }
        }
    }
}

#[test]
fn model_errors_keep_their_typed_source() {
    use pmu50_testbench::scenario::ModelError;
    use std::error::Error;
    type IsKind = fn(&ModelError) -> bool;
    let cases: [(&str, IsKind); 4] = [
        ("duration = \"10 ms\"\n[core]\nt2 = \"-1.1 ms\"", |m| {
            matches!(m, ModelError::Duration(_))
        }),
        ("duration = \"10 ms\"\n[core]\npi = \"3 ms\"", |m| {
            matches!(m, ModelError::Core(_))
        }),
        (
            "duration = \"10 ms\"\n[env.comparator]\nvr_err_s = 1.5",
            |m| matches!(m, ModelError::Env(_)),
        ),
        ("duration = \"10 ms\"\n[motor]\nstart_deg = nan", |m| {
            matches!(m, ModelError::Motor(_))
        }),
    ];
    for (text, kind) in cases {
        let e = Scenario::parse(text, "bad.toml", "bad", Path::new("bad.toml")).unwrap_err();
        match &e {
            ScenarioError::Model { source, .. } => assert!(kind(source), "{text}: {source:?}"),
            other => panic!("{text}: expected a model error, got {other:?}"),
        }
        assert!(e.source().is_some(), "{text}");
    }
}
