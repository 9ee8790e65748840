//! docs/signals.md carries the tables of the signal table (`pmu50_core::signals`) between its
//! BEGIN/END GENERATED markers. This test regenerates them and compares, so the documentation
//! cannot drift from the model; with `PMU50_REGENERATE=1` it rewrites the file instead
//! (temporary file in the same folder, then rename):
//! `PMU50_REGENERATE=1 cargo test -p pmu50-core --test signal_table`.
//!
//! It also checks the table against the model itself: every register of `Regs` is in the table
//! (a register changed through its struct field is seen by exactly one entry), widths match the
//! structural parameters, and the reset values match `pmu50::reset`.

use pmu50_core::pmu50::{self, Structural};
use pmu50_core::signals::{self, check_generated, markdown_tables, Reset, Width};
use pmu50_core::{Params, Pmu50};

#[test]
fn signals_md_tables_are_generated_from_the_signal_table() {
    let markers = ("<!-- BEGIN GENERATED", "<!-- END GENERATED -->");
    check_generated(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."),
        "docs/signals.md",
        markers,
        &markdown_tables(),
        "cargo test -p pmu50-core --test signal_table",
    )
    .unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn reset_values_in_the_table_are_the_model_reset() {
    let p = Params {
        si_max: 700,
        pw: 3,
        cth: 9,
        adaptive: false,
        ..Params::default()
    };
    let r = pmu50::reset(&p);
    let params = p.hdl_parameters();
    for sig in signals::REGISTERS {
        let v = (sig.get)(&r);
        match sig.reset {
            Reset::Value(want) => assert_eq!(v, want, "{}", sig.path()),
            Reset::Param(name) => {
                let want = params
                    .iter()
                    .find(|(n, _)| *n == name)
                    .unwrap_or_else(|| panic!("{}: no parameter {name}", sig.path()))
                    .1;
                assert_eq!(v, want, "{}", sig.path());
            }
            Reset::None => panic!("{} is a register without a reset value", sig.path()),
        }
    }
}

#[test]
fn every_register_bit_is_seen_by_exactly_one_entry_and_fits_its_width() {
    // Flip every bit of every register field through a random walk of the core, and check that
    // each entry's value fits the entry's width in every structural configuration.
    for (sd, cw) in [(1u8, 2u8), (2, 16), (4, 5)] {
        let p = Params {
            sync_depth: sd,
            cnt_width: cw,
            ..Params::default()
        };
        let s = Structural {
            sync_depth: sd,
            cnt_width: cw,
        };
        let mut core = Pmu50::new(p).unwrap();
        let mut x = 0x2545_F491_4F6C_DD1Du64;
        for k in 0..40_000u32 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let i = pmu50_core::Inputs {
                ig: (k / 3000) % 2 == 1,
                vs2_ok: x & 1 == 1,
                cmp_s: x & 2 == 2,
                cmp_c: x & 4 == 4,
                ..Default::default()
            };
            core.step(&i);
            for sig in signals::REGISTERS {
                let v = (sig.get)(core.regs());
                assert!(
                    v < (1u64 << sig.bits(&s)),
                    "{} = {v:#x} wider than {} bits",
                    sig.path(),
                    sig.bits(&s)
                );
            }
            for sig in signals::OUTPUTS {
                let v = (sig.get)(&core.peek());
                assert!(
                    v < (1u64 << sig.bits(&s)),
                    "{} = {v:#x} wider than {} bits",
                    sig.path(),
                    sig.bits(&s)
                );
            }
        }
    }
    // Names and accessors against the struct itself: the Debug text of `Regs` lists every
    // field as `block: Regs { field: value, .. }` in declaration order; the table must list the
    // same (block, field) pairs in the same order and read the same values. Values are distinct
    // where the type allows, and neighbouring flags differ, so an accessor that reads the wrong
    // field fails.
    for flip in [false, true] {
        let f = |b: bool| b ^ flip;
        let r = pmu50::Regs {
            action_switching: pmu50_core::action_switching_56a::Regs { sync: 1 },
            register_file: pmu50_core::register_file::Regs {
                adaptive: f(false),
                pw: 2,
                pi: 3,
                ps: 4,
                si_max: 5,
                si_min: 6,
                t1: 7,
                t2: 8,
                cth: 9,
                smp_on: 10,
                bus_err: f(true),
                rdata: 12,
            },
            timing_generator: pmu50_core::timing_generator_56::Regs { tmr: 13 },
            sensor_power_determination: pmu50_core::sensor_power_determination_57::Regs {
                sr: f(true),
            },
            comparator_latch: pmu50_core::comparator_latch_58ab::Regs {
                cs: f(false),
                cc: f(true),
                vld: f(false),
            },
            updown_counter: pmu50_core::updown_counter_58cd::Regs {
                cnt_s: 18,
                cnt_c: 19,
                quadrant_skip: f(true),
            },
            drive_interval: pmu50_core::drive_interval_changing_56b::Regs {
                si: 21,
                hist_s: f(false),
                hist_c: f(true),
                cnt_r: 24,
            },
            count_diagnosis: pmu50_core::count_diagnosis::Regs { diag: f(false) },
        };
        let dbg = format!("{r:?}")
            .replace('{', " { ")
            .replace('}', " } ")
            .replace(',', " ");
        let mut fields = Vec::new();
        let (mut depth, mut block, mut field) = (0, String::new(), None::<String>);
        for t in dbg.split_whitespace() {
            match t {
                "{" => depth += 1,
                "}" => depth -= 1,
                _ if t.ends_with(':') && depth == 1 => block = t.trim_end_matches(':').to_string(),
                _ if t.ends_with(':') && depth == 2 => {
                    field = Some(t.trim_end_matches(':').to_string())
                }
                _ if depth == 2 => {
                    let v = match t {
                        "true" => 1,
                        "false" => 0,
                        n => n.parse::<u64>().unwrap(),
                    };
                    fields.push((block.clone(), field.take().unwrap(), v));
                }
                _ => {}
            }
        }
        let table: Vec<(String, String, u64)> = signals::REGISTERS
            .iter()
            .map(|s| (s.scope.to_string(), s.name.to_string(), (s.get)(&r)))
            .collect();
        assert_eq!(
            table, fields,
            "the signal table's registers are not the fields of pmu50::Regs"
        );
    }
    assert!(matches!(signals::REGISTERS[0].width, Width::SyncDepth));
}
