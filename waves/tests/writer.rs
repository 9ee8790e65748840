//! Writer: exact output, rejection of invalid use, window option.

mod common;

use common::{sample, sample_builder, text, wave};
use pmu50_waves::reader::Value;
use pmu50_waves::writer::{BitType, Frame, Logic, SigId, VcdBuilder, VcdWriter, WriteError};
use pmu50_waves::{TimeUnit, Timescale};

const HEADER: &str = "$version
    pmu50-waves test
$end
$timescale 1 us $end
$scope module pmu50 $end
$var wire 1 ! clk $end
$var reg 1 \" en $end
$scope module drive_interval $end
$var reg 16 # si [15:0] $end
$var real 64 $ vout $end
$upscope $end
$upscope $end
$enddefinitions $end
";

#[test]
fn exact_output_with_full_dumpvars_and_only_changes() {
    let mut s = sample();
    // assignments at time 0 become the initial values of #0 $dumpvars
    s.w.change_bool(s.en, false).unwrap();
    s.w.set_time(2).unwrap();
    s.w.change_bool(s.clk, true).unwrap();
    s.w.change_vector(s.si, 0xabcd).unwrap();
    s.w.change_real(s.vout, 3.3).unwrap();
    s.w.change_bool(s.en, false).unwrap(); // same value: skipped
    s.w.set_time(3).unwrap();
    s.w.change_bool(s.en, false).unwrap(); // same value: no time stamp at all
    s.w.set_time(4).unwrap();
    s.w.change_bits(s.si, "xxxxzzzz0000111X").unwrap();
    s.w.change_real(s.vout, -0.0).unwrap();
    s.w.change_bit(s.clk, Logic::Z).unwrap();
    s.w.set_time(10).unwrap();
    let out = text(s.w);
    let expected = format!(
        "{HEADER}#0
$dumpvars
0!
0\"
b0000000000000000 #
r0 $
$end
#2
1!
b1010101111001101 #
r3.3 $
#4
z!
bxxxxzzzz0000111x #
r0 $
#10
"
    );
    assert_eq!(out, expected);
}

#[test]
fn no_date_and_byte_identical_across_runs() {
    let run = || {
        let mut s = sample();
        for t in 1..50u64 {
            s.w.set_time(t * 3).unwrap();
            s.w.change_bool(s.clk, t % 2 == 1).unwrap();
            s.w.change_vector(s.si, t * 1000).unwrap();
            s.w.change_real(s.vout, (t as f64).sqrt()).unwrap();
        }
        text(s.w)
    };
    let a = run();
    assert!(!a.contains("$date"));
    assert!(a.contains("$timescale 1 us $end"));
    assert_eq!(a, run());
}

#[test]
fn timescales_are_written_as_given() {
    for (ts, line) in [
        (Timescale::new(10, TimeUnit::Us), "$timescale 10 us $end"),
        (Timescale::new(1, TimeUnit::Ns), "$timescale 1 ns $end"),
        (Timescale::new(100, TimeUnit::Ps), "$timescale 100 ps $end"),
    ] {
        let (b, ..) = sample_builder(ts);
        let out = text(b.start(Vec::new()).unwrap());
        assert!(out.contains(line), "{out}");
    }
    let err = VcdBuilder::new(Timescale::new(2, TimeUnit::Us), "v").unwrap_err();
    assert!(matches!(err, WriteError::InvalidTimescale { factor: 2 }));
    assert!(err.to_string().contains("1, 10 or 100"), "{err}");
}

#[test]
fn rejects_backwards_time() {
    let mut s = sample();
    s.w.set_time(5).unwrap();
    s.w.set_time(5).unwrap(); // equal time is fine (same step)
    let err = s.w.set_time(4).unwrap_err();
    assert!(
        matches!(
            err,
            WriteError::TimeBackwards {
                requested: 4,
                current: 5
            }
        ),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains("set_time(4)") && msg.contains("current time is 5"),
        "{msg}"
    );
    // the writer stays usable at the old time
    assert_eq!(s.w.time(), 5);
    s.w.set_time(6).unwrap();
}

#[test]
fn rejects_double_change_in_one_step() {
    let mut s = sample();
    s.w.set_time(7).unwrap();
    s.w.change_vector(s.si, 1).unwrap();
    let err = s.w.change_vector(s.si, 2).unwrap_err();
    assert!(
        matches!(&err, WriteError::DoubleChange { name, time: 7 } if name == "pmu50.drive_interval.si"),
        "{err:?}"
    );
    // re-entering the same time is still the same step
    s.w.set_time(7).unwrap();
    assert!(matches!(
        s.w.change_vector(s.si, 1),
        Err(WriteError::DoubleChange { .. })
    ));
    // assigning the same value twice is also a double change
    s.w.change_bool(s.clk, false).unwrap();
    assert!(matches!(
        s.w.change_bool(s.clk, false),
        Err(WriteError::DoubleChange { .. })
    ));
    // next step is fine
    s.w.set_time(8).unwrap();
    s.w.change_vector(s.si, 2).unwrap();
    // double change before the first set_time (time 0) is caught too
    let mut s = sample();
    s.w.change_real(s.vout, 1.0).unwrap();
    assert!(matches!(
        s.w.change_real(s.vout, 2.0),
        Err(WriteError::DoubleChange { time: 0, .. })
    ));
}

#[test]
fn rejects_values_that_do_not_fit_the_width() {
    let mut s = sample();
    let err = s.w.change_vector(s.si, 0x1_0000).unwrap_err();
    assert!(
        matches!(
            err,
            WriteError::ValueTooWide {
                width: 16,
                max: 0xffff,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(err.to_string().contains("0..=65535"), "{err}");
    assert!(matches!(
        s.w.change_vector(s.clk, 2),
        Err(WriteError::ValueTooWide { width: 1, .. })
    ));
    // bit strings of the wrong width
    let err = s.w.change_bits(s.si, "0101").unwrap_err();
    assert!(
        matches!(
            err,
            WriteError::WrongWidth {
                expected: 16,
                got: 4,
                ..
            }
        ),
        "{err:?}"
    );
    assert!(matches!(
        s.w.change_bits(s.si, "00000000000000000"),
        Err(WriteError::WrongWidth {
            expected: 16,
            got: 17,
            ..
        })
    ));
    // a single bit for a vector
    assert!(matches!(
        s.w.change_bit(s.si, Logic::One),
        Err(WriteError::WrongWidth {
            expected: 16,
            got: 1,
            ..
        })
    ));
    // invalid characters
    let err = s.w.change_bits(s.si, "000000000000000q").unwrap_err();
    assert!(
        matches!(
            err,
            WriteError::InvalidBit {
                ch: 'q',
                pos: 15,
                ..
            }
        ),
        "{err:?}"
    );
    // declared initial value too wide
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "v").unwrap();
    b.push_scope("top").unwrap();
    assert!(matches!(
        b.add_vector(BitType::Wire, "n", 3, 0, 16),
        Err(WriteError::ValueTooWide { width: 4, .. })
    ));
    // none of the failed calls counted as an assignment
    s.w.change_vector(s.si, 0xffff).unwrap();
    s.w.change_bool(s.clk, true).unwrap();
}

#[test]
fn rejects_nan_and_infinite_reals_and_normalises_negative_zero() {
    let mut s = sample();
    let err = s.w.change_real(s.vout, f64::NAN).unwrap_err();
    assert!(
        matches!(&err, WriteError::NotFinite { name, .. } if name == "pmu50.drive_interval.vout")
    );
    assert!(err.to_string().contains("NaN"), "{err}");
    assert!(matches!(
        s.w.change_real(s.vout, f64::INFINITY),
        Err(WriteError::NotFinite { .. })
    ));
    assert!(matches!(
        s.w.change_real(s.vout, f64::NEG_INFINITY),
        Err(WriteError::NotFinite { .. })
    ));
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "v").unwrap();
    b.push_scope("top").unwrap();
    assert!(matches!(
        b.add_real("r", f64::NAN),
        Err(WriteError::NotFinite { .. })
    ));
    // -0.0 equals the initial 0.0: no change written
    s.w.set_time(1).unwrap();
    s.w.change_real(s.vout, -0.0).unwrap();
    s.w.set_time(2).unwrap();
    s.w.change_real(s.vout, 1e300).unwrap();
    s.w.set_time(3).unwrap();
    s.w.change_real(s.vout, -2.5e-9).unwrap();
    let out = text(s.w);
    assert!(!out.contains("#1\n"), "{out}");
    assert!(out.contains("#2\nr1e300 $\n#3\nr-2.5e-9 $\n"), "{out}");
    let w = wave(&out);
    let ch = w.changes("pmu50.drive_interval.vout").unwrap();
    assert_eq!(
        ch,
        vec![
            (0, Value::Real(0.0)),
            (2, Value::Real(1e300)),
            (3, Value::Real(-2.5e-9))
        ]
    );
}

#[test]
fn rejects_type_mismatch_and_foreign_ids() {
    let mut s = sample();
    assert!(matches!(
        s.w.change_real(s.clk, 1.0),
        Err(WriteError::TypeMismatch { .. })
    ));
    assert!(matches!(
        s.w.change_vector(s.vout, 1),
        Err(WriteError::TypeMismatch { .. })
    ));
    assert!(matches!(
        s.w.change_bits(s.vout, "1"),
        Err(WriteError::TypeMismatch { .. })
    ));
    assert!(matches!(
        s.w.change_bool(s.vout, true),
        Err(WriteError::TypeMismatch { .. })
    ));
    let other = sample();
    let err = s.w.change_bool(other.clk, true).unwrap_err();
    assert!(matches!(err, WriteError::UnknownId { .. }), "{err:?}");
    assert!(s.w.gtkwave_name(other.si).is_err());
}

#[test]
fn rejects_bad_declarations() {
    let ts = Timescale::new(1, TimeUnit::Us);
    assert!(matches!(
        VcdBuilder::new(ts, "x $end y"),
        Err(WriteError::InvalidVersion { .. })
    ));
    assert!(matches!(
        VcdBuilder::new(ts, ""),
        Err(WriteError::InvalidVersion { .. })
    ));
    let mut b = VcdBuilder::new(ts, "v").unwrap();
    assert!(matches!(
        b.add_bit(BitType::Wire, "a", Logic::Zero),
        Err(WriteError::NoScope { .. })
    ));
    assert!(matches!(b.pop_scope(), Err(WriteError::NoOpenScope)));
    for bad in ["", "1abc", "a b", "a.b", "a[3]", "$x", "ä"] {
        let err = b.push_scope(bad).unwrap_err();
        assert!(
            matches!(err, WriteError::InvalidName { what: "scope", .. }),
            "{bad:?}: {err:?}"
        );
    }
    b.push_scope("top").unwrap();
    b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap();
    let err = b.add_bit(BitType::Reg, "a", Logic::One).unwrap_err();
    assert!(
        matches!(&err, WriteError::Duplicate { path } if path == "top.a"),
        "{err:?}"
    );
    assert!(matches!(
        b.push_scope("a"),
        Err(WriteError::Duplicate { .. })
    ));
    assert!(matches!(
        b.add_vector(BitType::Wire, "v", u32::MAX, 0, 0),
        Err(WriteError::RangeTooLarge { .. })
    ));
    assert!(matches!(
        b.add_vector(BitType::Wire, "v", 70_000, 0, 0),
        Err(WriteError::RangeTooLarge { .. })
    ));
    b.add_vector(BitType::Wire, "v", 65_535, 0, 0).unwrap();
    assert!(matches!(
        b.add_real("bad name", 0.0),
        Err(WriteError::InvalidName {
            what: "variable",
            ..
        })
    ));
    b.push_scope("sub").unwrap();
    let err = b.start(Vec::new()).unwrap_err();
    assert!(
        matches!(&err, WriteError::UnclosedScopes { open: 2, innermost } if innermost == "top.sub"),
        "{err:?}"
    );

    let mut b = VcdBuilder::new(ts, "v").unwrap();
    b.push_scope("top").unwrap();
    b.pop_scope().unwrap();
    assert!(matches!(b.start(Vec::new()), Err(WriteError::NoVariables)));

    let mut b = VcdBuilder::new(ts, "v").unwrap();
    assert!(matches!(
        b.window(5, 5),
        Err(WriteError::InvalidWindow { start: 5, end: 5 })
    ));
    assert!(matches!(
        b.window(6, 5),
        Err(WriteError::InvalidWindow { .. })
    ));
}

#[test]
fn gtkwave_names_and_bit_selects() {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Ns), "v").unwrap();
    b.push_scope("pmu50").unwrap();
    b.push_scope("drive_interval").unwrap();
    let si = b.add_vector(BitType::Wire, "si", 15, 0, 0).unwrap();
    let one = b.add_vector(BitType::Wire, "b", 3, 3, 1).unwrap();
    let le = b.add_vector(BitType::Wire, "le", 0, 7, 0).unwrap();
    let r = b.add_real("r", 0.0).unwrap();
    b.pop_scope().unwrap();
    b.pop_scope().unwrap();
    assert_eq!(b.gtkwave_name(si).unwrap(), "pmu50.drive_interval.si[15:0]");
    assert_eq!(b.gtkwave_name(one).unwrap(), "pmu50.drive_interval.b[3]");
    assert_eq!(b.gtkwave_name(le).unwrap(), "pmu50.drive_interval.le[0:7]");
    assert_eq!(b.gtkwave_name(r).unwrap(), "pmu50.drive_interval.r");
    let mut w = b.start(Vec::new()).unwrap();
    w.change_bit(one, Logic::Zero).unwrap();
    w.change_bits(le, "10000000").unwrap();
    let out = text(w);
    assert!(out.contains("$var wire 1 \" b [3] $end"), "{out}");
    assert!(out.contains("$var wire 8 # le [0:7] $end"), "{out}");
    let names: Vec<String> = wave(&out)
        .signals()
        .iter()
        .map(|s| s.gtkwave_name())
        .collect();
    assert_eq!(
        names,
        [
            "pmu50.drive_interval.si[15:0]",
            "pmu50.drive_interval.b[3]",
            "pmu50.drive_interval.le[0:7]",
            "pmu50.drive_interval.r"
        ]
    );
}

#[test]
fn wide_vectors_beyond_64_bits() {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Ns), "v").unwrap();
    b.push_scope("top").unwrap();
    let v = b.add_vector(BitType::Reg, "wide", 79, 0, u64::MAX).unwrap();
    b.pop_scope().unwrap();
    let mut w = b.start(Vec::new()).unwrap();
    w.set_time(1).unwrap();
    let bits = format!("1{}", "0".repeat(79));
    w.change_bits(v, &bits).unwrap();
    w.set_time(2).unwrap();
    w.change_vector(v, 5).unwrap();
    let out = text(w);
    let ch = wave(&out).changes("top.wide").unwrap();
    assert_eq!(
        ch[0],
        (
            0,
            Value::Bits(format!("{}{}", "0".repeat(16), "1".repeat(64)))
        )
    );
    assert_eq!(ch[1], (1, Value::Bits(bits)));
    assert_eq!(ch[2], (2, Value::Bits(format!("{}101", "0".repeat(77)))));
}

fn windowed(start: u64, end: u64) -> String {
    let (mut b, clk, _en, si, vout) = sample_builder(Timescale::new(1, TimeUnit::Us));
    b.window(start, end).unwrap();
    let mut w = b.start(Vec::new()).unwrap();
    for t in 0..=20u64 {
        w.set_time(t).unwrap();
        w.change_bool(clk, t % 2 == 1).unwrap();
        if t % 4 == 0 {
            w.change_vector(si, t).unwrap();
        }
        if t == 3 {
            w.change_real(vout, 1.25).unwrap();
        }
    }
    text(w)
}

#[test]
fn window_starts_with_dumpvars_at_start_and_keeps_absolute_times() {
    // start = 6 falls on a step: dump at #6 with the values of step 6
    let out = windowed(6, 10);
    let body = out.split("$enddefinitions $end\n").nth(1).unwrap();
    assert_eq!(
        body,
        "#6\n$dumpvars\n0!\nx\"\nb0000000000000100 #\nr1.25 $\n$end\n#7\n1!\n#8\n0!\nb0000000000001000 #\n#9\n1!\n"
    );
    // no change before start or at/after end was dumped
    let w = wave(&out);
    for s in w.signals() {
        for (t, _) in w.changes(&s.path).unwrap() {
            assert!((6..10).contains(&t), "{} at {t}", s.path);
        }
    }
}

#[test]
fn window_start_between_steps_dumps_values_current_at_start() {
    let (mut b, clk, _en, si, _vout) = sample_builder(Timescale::new(1, TimeUnit::Us));
    b.window(15, u64::MAX).unwrap();
    let mut w = b.start(Vec::new()).unwrap();
    w.set_time(10).unwrap();
    w.change_vector(si, 10).unwrap();
    w.set_time(20).unwrap();
    w.change_vector(si, 20).unwrap();
    w.change_bool(clk, true).unwrap();
    w.set_time(30).unwrap();
    let out = text(w);
    let body = out.split("$enddefinitions $end\n").nth(1).unwrap();
    assert_eq!(
        body,
        "#15\n$dumpvars\n0!\nx\"\nb0000000000001010 #\nr0 $\n$end\n#20\n1!\nb0000000000010100 #\n#30\n"
    );
}

#[test]
fn window_that_is_never_reached_writes_only_the_header() {
    let out = windowed(100, 200);
    assert!(out.ends_with("$enddefinitions $end\n"), "{out}");
}

#[test]
fn window_reads_back_like_the_full_dump_restricted_to_the_window() {
    let full = wave(&windowed(0, u64::MAX));
    let part = wave(&windowed(5, 13));
    for s in full.signals() {
        let all = full.changes(&s.path).unwrap();
        // value at 5 = last change at or before 5
        let at_start = all.iter().rev().find(|(t, _)| *t <= 5).unwrap().1.clone();
        let mut expected = vec![(5, at_start)];
        expected.extend(all.iter().filter(|(t, _)| *t > 5 && *t < 13).cloned());
        assert_eq!(part.changes(&s.path).unwrap(), expected, "{}", s.path);
    }
}

#[test]
fn error_messages_say_what_where_and_what_is_valid() {
    let mut s = sample();
    s.w.set_time(3).unwrap();
    let msg = s.w.change_bits(s.si, "12").unwrap_err().to_string();
    assert!(
        msg.contains("pmu50.drive_interval.si") && msg.contains("valid bits are 0, 1, x, z"),
        "{msg}"
    );
    let msg = s.w.change_vector(s.si, 70000).unwrap_err().to_string();
    assert!(
        msg.contains("70000") && msg.contains("16 bit") && msg.contains("0..=65535"),
        "{msg}"
    );
}

// ---- frames: declared once, dumped every step, identical output to single changes ----

fn frame_builder() -> (VcdBuilder, Vec<SigId>) {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "pmu50-waves test").unwrap();
    b.push_scope("pmu50").unwrap();
    let mut ids = vec![b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap()];
    ids.push(b.add_vector(BitType::Reg, "tmr", 15, 0, 0).unwrap());
    ids.push(b.add_vector(BitType::Reg, "w", 4, 0, 3).unwrap());
    ids.push(b.add_vector(BitType::Wire, "wide", 63, 0, 0).unwrap());
    ids.push(b.add_bit(BitType::Reg, "z", Logic::X).unwrap());
    b.pop_scope().unwrap();
    (b, ids)
}

/// A writer started from a builder and its ids (as [`frame_builder`] gives them), with a frame
/// of the first `n` variables.
fn framed((b, ids): (VcdBuilder, Vec<SigId>), n: usize) -> (VcdWriter<Vec<u8>>, Frame, Vec<SigId>) {
    let mut w = b.start(Vec::new()).unwrap();
    let f = w.frame(&ids[..n]).unwrap();
    (w, f, ids)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, failure_persistence: None, ..Default::default() })]

    /// A frame dump writes exactly what `set_time` plus one `change_vector` per variable writes.
    #[test]
    fn frame_dumps_equal_single_changes(steps in proptest::collection::vec((0u64..3, proptest::array::uniform4(0u64..4), proptest::prelude::any::<bool>()), 0..60)) {
        let (b1, ids) = frame_builder();
        let (b2, ids2) = frame_builder();
        let mut w1 = b1.start(Vec::new()).unwrap();
        let mut w2 = b2.start(Vec::new()).unwrap();
        let mut f = w2.frame(&ids2[..4]).unwrap();
        let mut t = 0;
        let mut first = true;
        for (dt, v, z) in steps {
            t += dt;
            let vals = [v[0] & 1, v[1] * 1000, v[2] * 7, v[3] << 60];
            if dt == 0 && !first {
                // Same time again: every frame variable is already assigned in this step.
                let again = w2.dump_frame(&mut f, t, &vals);
                proptest::prop_assert!(matches!(again, Err(WriteError::DoubleChange { .. })), "{:?}", again);
                continue;
            }
            first = false;
            w1.set_time(t).unwrap();
            for (id, x) in ids.iter().zip(vals) {
                w1.change_vector(*id, x).unwrap();
            }
            w2.dump_frame(&mut f, t, &vals).unwrap();
            // A variable outside the frame, changed singly in the same step.
            if z {
                w1.change_bool(ids[4], t % 2 == 0).unwrap();
                w2.change_bool(ids2[4], t % 2 == 0).unwrap();
            }
        }
        proptest::prop_assert_eq!(text(w1), text(w2));
    }
}

#[test]
fn frames_keep_every_check() {
    let (mut w, mut f, ids) = framed(frame_builder(), 3);
    let mut g = w.frame(&ids[2..4]).unwrap();
    w.set_time(1).unwrap();
    // value wider than the variable: 5-bit `w` takes at most 31 (the values before it are taken)
    let e = w.dump_frame(&mut f, 1, &[1, 2, 32]).unwrap_err();
    assert!(
        matches!(
            e,
            WriteError::ValueTooWide {
                value: 32,
                max: 31,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("pmu50.w"), "{e}");
    w.set_time(2).unwrap();
    // wrong number of values
    assert!(matches!(
        w.dump_frame(&mut f, 2, &[1, 2]),
        Err(WriteError::FrameLength {
            expected: 3,
            got: 2
        })
    ));
    // a single change, then the frame, in one step
    w.change_vector(ids[1], 5).unwrap();
    assert!(matches!(
        w.dump_frame(&mut f, 2, &[0, 5, 1]),
        Err(WriteError::DoubleChange { .. })
    ));
    // the frame, then a single change of one of its variables, in one step
    w.dump_frame(&mut f, 3, &[0, 5, 1]).unwrap();
    assert!(matches!(
        w.change_vector(ids[0], 1),
        Err(WriteError::DoubleChange { .. })
    ));
    // two frames sharing `w` in one step
    let e = w.dump_frame(&mut g, 3, &[1, 0]).unwrap_err();
    assert!(
        matches!(&e, WriteError::DoubleChange { name, .. } if name == "pmu50.w"),
        "{e}"
    );
    // time backwards
    assert!(matches!(
        w.dump_frame(&mut f, 2, &[0, 5, 1]),
        Err(WriteError::TimeBackwards { .. })
    ));
    // later steps are fine again, and a variable outside both frames changes with them
    w.dump_frame(&mut g, 4, &[2, 9]).unwrap();
    w.dump_frame(&mut f, 5, &[1, 6, 2]).unwrap();
    w.change_bit(ids[4], Logic::One).unwrap();
    let got = text(w);

    // The same accepted assignments through single changes.
    let (b, ids) = frame_builder();
    let mut r = b.start(Vec::new()).unwrap();
    for (t, ch) in [
        (1, vec![(0, 1), (1, 2)]),
        (2, vec![(1, 5)]),
        (3, vec![(0, 0), (1, 5), (2, 1)]),
        (4, vec![(2, 2), (3, 9)]),
        (5, vec![(0, 1), (1, 6), (2, 2)]),
    ] {
        r.set_time(t).unwrap();
        for (k, v) in ch {
            r.change_vector(ids[k], v).unwrap();
        }
    }
    r.change_bit(ids[4], Logic::One).unwrap();
    let want = text(r);
    assert_eq!(got, want);
    assert!(got.contains("#4\nb00010 #\n"), "{got}");
}

#[test]
fn frames_refuse_reals_wide_vectors_foreign_writers_and_duplicates() {
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "t").unwrap();
    b.push_scope("m").unwrap();
    let r = b.add_real("r", 0.0).unwrap();
    let big = b.add_vector(BitType::Wire, "big", 64, 0, 0).unwrap();
    let a = b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap();
    b.pop_scope().unwrap();
    let mut w = b.start(Vec::new()).unwrap();
    assert!(matches!(
        w.frame(&[r]),
        Err(WriteError::TypeMismatch { .. })
    ));
    assert!(matches!(
        w.frame(&[big]),
        Err(WriteError::TypeMismatch { .. })
    ));
    assert!(matches!(
        w.frame(&[a, a]),
        Err(WriteError::Duplicate { .. })
    ));
    let (b2, ids2) = frame_builder();
    let mut other = b2.start(Vec::new()).unwrap();
    assert!(matches!(
        w.frame(&ids2[..1]),
        Err(WriteError::UnknownId { .. })
    ));
    let mut f2 = other.frame(&ids2[..1]).unwrap();
    assert!(matches!(
        w.dump_frame(&mut f2, 1, &[1]),
        Err(WriteError::UnknownFrame)
    ));
    for _ in 0..pmu50_waves::writer::MAX_FRAMES {
        w.frame(&[a]).unwrap();
    }
    assert!(matches!(w.frame(&[a]), Err(WriteError::TooManyFrames)));
}

// ---- frame steps: a frame's values given one by one, only where they may have changed ----

// ---- frame runs: the writer lent to one frame, direct steps ----

/// What happens after a step of a frame run (the run is ended for everything but `Nothing`).
#[derive(Debug, Clone, Copy)]
enum AfterStep {
    Nothing,
    /// the variable outside the frame changes in the same time step
    OutsideSameTime,
    /// one tick later a frame variable takes `x` bits (or, for the 64-bit one, a value)
    FrameVarLater,
    /// one tick later, nothing
    TimeOnly,
    /// one tick later the 64-bit frame variable takes a value by a single change
    FrameIntLater(u64),
}

fn after_step() -> impl proptest::strategy::Strategy<Value = AfterStep> {
    use proptest::prelude::*;
    prop_oneof![12 => Just(AfterStep::Nothing), 1 => Just(AfterStep::OutsideSameTime), 1 => Just(AfterStep::FrameVarLater), 1 => Just(AfterStep::TimeOnly), 2 => (0u64..5).prop_map(|v| AfterStep::FrameIntLater(v << 60))]
}

/// A frame variable's value in [`frame_builder`]'s frame, from a small drawn number.
fn frame_value(var: usize, v: u64) -> u64 {
    [v & 1, v * 1000, v * 7, v << 60][var]
}

/// The two writers of a run property: `w1` written by the runs under test, `w2` by
/// `dump_frame` (and single changes) with the same values; the frame's values by position,
/// the time, the outside variable's value and the time of the frame's last step.
struct RunPair {
    w1: VcdWriter<Vec<u8>>,
    f1: Frame,
    ids1: Vec<SigId>,
    w2: VcdWriter<Vec<u8>>,
    f2: Frame,
    ids2: Vec<SigId>,
    /// the variable at each frame position
    order: [usize; 4],
    /// the frame position of each variable
    at: [usize; 4],
    /// the frame's values by position
    cur: [u64; 4],
    t: u64,
    zv: bool,
    /// the time of the frame's last step
    frame_at: Option<u64>,
}

impl RunPair {
    /// Two writers of [`frame_builder`] (both with `window`), each with a frame in declaration
    /// order (`sorted`) or out of it.
    fn new(sorted: bool, window: Option<(u64, u64)>) -> RunPair {
        let order: [usize; 4] = if sorted { [0, 1, 2, 3] } else { [3, 1, 0, 2] };
        let start = || {
            let (mut b, ids) = frame_builder();
            if let Some((s, len)) = window {
                b.window(s, s + len + 1).unwrap();
            }
            let mut w = b.start(Vec::new()).unwrap();
            let f = w.frame(&order.map(|k| ids[k])).unwrap();
            (w, f, ids)
        };
        let (w1, f1, ids1) = start();
        let (w2, f2, ids2) = start();
        RunPair {
            w1,
            f1,
            ids1,
            w2,
            f2,
            ids2,
            order,
            at: std::array::from_fn(|var| order.iter().position(|&v| v == var).unwrap()),
            cur: order.map(|var| [0, 0, 3, 0][var]),
            t: 0,
            zv: false,
            frame_at: None,
        }
    }

    /// What happens between two runs, on both writers.
    fn after(&mut self, after: AfterStep) -> Result<(), proptest::test_runner::TestCaseError> {
        match after {
            AfterStep::Nothing => {}
            AfterStep::OutsideSameTime => {
                self.zv = !self.zv;
                self.w1.change_bool(self.ids1[4], self.zv).unwrap();
                self.w2.change_bool(self.ids2[4], self.zv).unwrap();
                // and a frame variable at that time is a double assignment
                let e = self.w1.change_vector(self.ids1[0], 1).err();
                proptest::prop_assert!(
                    matches!(e, Some(WriteError::DoubleChange { .. })),
                    "{:?}",
                    e
                );
            }
            AfterStep::FrameIntLater(v) => {
                // the frame's copy is stale at the next run's first step
                self.t += 1;
                self.w1.set_time(self.t).unwrap();
                self.w2.set_time(self.t).unwrap();
                self.w1.change_vector(self.ids1[3], v).unwrap();
                self.w2.change_vector(self.ids2[3], v).unwrap();
                self.cur[self.at[3]] = v;
                // a frame variable is assigned at `t`: the frame's step there is refused
                self.frame_at = Some(self.t);
            }
            AfterStep::TimeOnly => {
                self.t += 1;
                self.w1.set_time(self.t).unwrap();
                self.w2.set_time(self.t).unwrap();
            }
            AfterStep::FrameVarLater => {
                // `w` (5 bits) becomes x0x0x (its frame position then holds no integer), and
                // the 64-bit variable 5
                self.t += 1;
                for (w, ids) in [(&mut self.w1, &self.ids1), (&mut self.w2, &self.ids2)] {
                    w.set_time(self.t).unwrap();
                    w.change_bits(ids[2], "x0x0x").unwrap();
                    w.change_vector(ids[3], 5).unwrap();
                }
                self.cur[self.at[3]] = 5;
                // the next step sets every position, `w` back to 3 (a run's step is a
                // checked one while `w` holds x; dump_frame compares with x0x0x too)
                self.cur[self.at[2]] = 3;
                self.t += 1;
                let mut run = self.w1.frame_run(&mut self.f1).unwrap();
                let mut s = run.step(self.t).unwrap();
                for (k, v) in self.cur.iter().enumerate() {
                    s.set(k, *v).unwrap();
                }
                drop(run);
                self.w2.dump_frame(&mut self.f2, self.t, &self.cur).unwrap();
                self.frame_at = Some(self.t);
            }
        }
        Ok(())
    }
}

/// Gives a step's drawn values through `set_fn` (a frame run's or a text run's step) and keeps
/// them in `cur`; with `too_wide`, a too-wide value of `w` is refused first, and after the
/// values, a position again (or one before the last) is refused where any was given.
fn give_step(
    set: &[Option<u64>; 4],
    too_wide: bool,
    order: &[usize; 4],
    cur: &mut [u64; 4],
    set_fn: &mut dyn FnMut(usize, u64) -> Result<(), WriteError>,
) -> Result<(), proptest::test_runner::TestCaseError> {
    for (k, v) in set.iter().enumerate() {
        let Some(v) = v else { continue };
        if too_wide && order[k] == 2 {
            // 5-bit `w`: refused, nothing assigned, the position may be given again
            let e = set_fn(k, 32 + v).unwrap_err();
            proptest::prop_assert!(
                matches!(e, WriteError::ValueTooWide { max: 31, .. }),
                "{}",
                e
            );
        }
        let v = frame_value(order[k], *v);
        set_fn(k, v).unwrap();
        cur[k] = v;
    }
    if too_wide {
        // a position again, or one before the last, in the same step
        let e = set_fn(0, cur[0]).err();
        let given = set.iter().any(|v| v.is_some());
        proptest::prop_assert_eq!(
            given,
            matches!(e, Some(WriteError::FrameOrder { .. })),
            "{:?}",
            e
        );
    }
    Ok(())
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, failure_persistence: None, ..Default::default() })]

    /// Runs of frame steps (direct ones inside the window, checked ones elsewhere: at the
    /// writer's time, before the first dump, after the window, after `x` values, for a frame
    /// out of declaration order) write exactly what `dump_frame` writes with the same values,
    /// with single changes between runs, repeated times refused on both sides, and refused
    /// too-wide values.
    #[test]
    fn frame_runs_equal_dump_frame(
        sorted in proptest::prelude::any::<bool>(),
        window in proptest::option::of((0u64..30, 0u64..80)),
        steps in proptest::collection::vec((0u64..3, proptest::array::uniform4(proptest::option::of(0u64..5)), proptest::prelude::any::<bool>(), after_step()), 0..80),
    ) {
        let mut p = RunPair::new(sorted, window);
        let mut idx = 0;
        while idx < steps.len() {
            let mut after = AfterStep::Nothing;
            {
                let mut run = p.w1.frame_run(&mut p.f1).unwrap();
                let mut steps_in_run = 0;
                while idx < steps.len() {
                    let (dt, set, too_wide, a) = steps[idx];
                    idx += 1;
                    p.t += dt;
                    if p.frame_at == Some(p.t) {
                        // the frame's variables are assigned at `t` already
                        let e = run.step(p.t).err();
                        proptest::prop_assert!(matches!(e, Some(WriteError::DoubleChange { .. })), "{:?}", e);
                        let e = p.w2.dump_frame(&mut p.f2, p.t, &p.cur).err();
                        proptest::prop_assert!(matches!(e, Some(WriteError::DoubleChange { .. })), "{:?}", e);
                        continue;
                    }
                    p.frame_at = Some(p.t);
                    let mut s = run.step(p.t).unwrap();
                    if steps_in_run > 0 {
                        proptest::prop_assert!(s.is_current());
                    }
                    steps_in_run += 1;
                    give_step(&set, too_wide, &p.order, &mut p.cur, &mut |k, v| s.set(k, v))?;
                    p.w2.dump_frame(&mut p.f2, p.t, &p.cur).unwrap();
                    if !matches!(a, AfterStep::Nothing) {
                        after = a;
                        break;
                    }
                }
            }
            p.after(after)?;
        }
        proptest::prop_assert_eq!(text(p.w1), text(p.w2));
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, failure_persistence: None, ..Default::default() })]

    /// Text runs (the steps written at once where they can be, through `TextRun::frame_run`
    /// elsewhere: at the writer's time, before the first dump, outside the window, after `x`
    /// values, after single changes, for a frame out of declaration order) write exactly what
    /// `dump_frame` writes with the same values, with single changes between runs, repeated
    /// times refused on both sides, and refused too-wide values and positions out of order.
    /// With `change`, a text step's changed values go through `TextStep::change` (the unchecked
    /// way, for callers that know what changed) where no error is being provoked.
    #[test]
    fn text_runs_equal_dump_frame(
        sorted in proptest::prelude::any::<bool>(),
        change in proptest::prelude::any::<bool>(),
        window in proptest::option::of((0u64..30, 0u64..80)),
        steps in proptest::collection::vec((0u64..3, proptest::array::uniform4(proptest::option::of(0u64..5)), proptest::prelude::any::<bool>(), after_step()), 0..80),
    ) {
        let mut p = RunPair::new(sorted, window);
        let mut idx = 0;
        // steps written at once
        let mut texts = 0;
        while idx < steps.len() {
            let mut after = AfterStep::Nothing;
            {
                let mut run = p.w1.text_run(&mut p.f1).unwrap();
                while idx < steps.len() {
                    let (dt, set, too_wide, a) = steps[idx];
                    idx += 1;
                    p.t += dt;
                    let t = p.t;
                    if p.frame_at == Some(t) {
                        // the frame's variables are assigned at `t` already
                        let e = match run.step(t) {
                            Err(e) => Some(e),
                            Ok(Some(_)) => None,
                            Ok(None) => run.frame_run().unwrap().step(t).err(),
                        };
                        proptest::prop_assert!(matches!(e, Some(WriteError::DoubleChange { .. })), "{:?}", e);
                        let e = p.w2.dump_frame(&mut p.f2, t, &p.cur).err();
                        proptest::prop_assert!(matches!(e, Some(WriteError::DoubleChange { .. })), "{:?}", e);
                        continue;
                    }
                    p.frame_at = Some(t);
                    // the frame's values before the step (a position is given once in it)
                    let before = p.cur;
                    match run.step(t).unwrap() {
                        Some(mut s) if change && !too_wide => {
                            texts += 1;
                            give_step(&set, too_wide, &p.order, &mut p.cur, &mut |k, v| {
                                if v != before[k] {
                                    s.change(k, v);
                                }
                                Ok(())
                            })?;
                        }
                        Some(mut s) => {
                            texts += 1;
                            give_step(&set, too_wide, &p.order, &mut p.cur, &mut |k, v| s.line(k, v))?;
                        }
                        None => {
                            let mut fr = run.frame_run().unwrap();
                            let mut s = fr.step(t).unwrap();
                            give_step(&set, too_wide, &p.order, &mut p.cur, &mut |k, v| s.set(k, v))?;
                        }
                    }
                    p.w2.dump_frame(&mut p.f2, t, &p.cur).unwrap();
                    if !matches!(a, AfterStep::Nothing) {
                        after = a;
                        break;
                    }
                }
            }
            p.after(after)?;
        }
        proptest::prop_assert_eq!(text(p.w1), text(p.w2));
        if sorted && window.is_none() && steps.len() > 40 {
            proptest::prop_assert!(texts > 0, "no step was written at once");
        }
    }
}

/// The checks of one step at `t` of a frame of [`frame_builder`]'s first three variables, its
/// values given through `give` (a text step's `line`, a run step's `set`): position 1 takes
/// 4 + t; a position past the frame, one before the last given, the last given again and a
/// too-wide value of `w` are refused, each with its error; position 2 then takes t.
fn step_checks(t: u64, give: &mut dyn FnMut(usize, u64) -> Result<(), WriteError>) {
    give(1, 4 + t).unwrap();
    let e = give(3, 1).unwrap_err();
    assert!(
        matches!(
            e,
            WriteError::FramePosition {
                position: 3,
                len: 3
            }
        ),
        "{e}"
    );
    let e = give(0, 1).unwrap_err();
    assert!(
        matches!(
            e,
            WriteError::FrameOrder {
                position: 0,
                previous: 1
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("increasing order"), "{e}");
    let e = give(1, 9).unwrap_err();
    assert!(
        matches!(
            e,
            WriteError::FrameOrder {
                position: 1,
                previous: 1
            }
        ),
        "{e}"
    );
    let e = give(2, 32).unwrap_err();
    assert!(
        matches!(
            e,
            WriteError::ValueTooWide {
                value: 32,
                max: 31,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("pmu50.w"), "{e}");
    give(2, t).unwrap();
}

/// The checks after a run of `w` (a frame of the first three of [`frame_builder`]'s variables):
/// the last step is the writer's pending one, so a frame variable again is a double assignment
/// and another variable joins the step. Returns another writer (kept for as long as its frame is
/// used) and a frame of it, which `w` must refuse.
fn after_a_run(w: &mut VcdWriter<Vec<u8>>, ids: &[SigId]) -> (VcdWriter<Vec<u8>>, Frame) {
    assert!(matches!(
        w.change_vector(ids[1], 1),
        Err(WriteError::DoubleChange { .. })
    ));
    w.change_vector(ids[3], 1).unwrap();
    let (other, f2, _) = framed(frame_builder(), 1);
    (other, f2)
}

/// A text run's steps are written at once and its last one is taken back when the run ends
/// (it becomes the writer's pending step); the checks of a frame step stay (position, order,
/// width, time, a step at a time the frame was assigned), and a frame of another writer is
/// refused.
#[test]
fn text_runs_keep_every_check() {
    let (mut w, mut f, ids) = framed(frame_builder(), 3);
    {
        let mut run = w.text_run(&mut f).unwrap();
        // t = 0: before the first dump, through a frame run
        assert!(run.step(0).unwrap().is_none());
        run.frame_run().unwrap().step(0).unwrap().set(1, 4).unwrap();
        // t = 1: the writer's first step is written (the first dump), then this one at once
        run.step(1)
            .unwrap()
            .expect("a step written at once")
            .line(1, 5)
            .unwrap();
        for t in 2..5 {
            let mut s = run.step(t).unwrap().expect("a step written at once");
            step_checks(t, &mut |k, v| s.line(k, v));
        }
        // a step without a change takes its stamp back
        let mut s = run.step(5).unwrap().unwrap();
        s.line(1, 8).unwrap();
        assert!(matches!(run.step(5), Err(WriteError::DoubleChange { .. })));
        assert!(matches!(
            run.step(4),
            Err(WriteError::TimeBackwards {
                requested: 4,
                current: 5
            })
        ));
        let mut s = run.step(6).unwrap().unwrap();
        s.line(0, 1).unwrap();
    }
    let (_other, mut f2) = after_a_run(&mut w, &ids);
    assert!(matches!(w.text_run(&mut f2), Err(WriteError::UnknownFrame)));
    let got = text(w);
    assert!(
        got.contains("#1\nb0000000000000101 \"\n#2\nb0000000000000110 \"\nb00010 #\n#3\n"),
        "{got}"
    );
    assert!(got.contains("#4\nb0000000000001000 \"\nb00100 #\n#6\n1!\nb0000000000000000000000000000000000000000000000000000000000000001 $\n"), "{got}");
    assert!(!got.contains("#5"), "{got}");
}

/// `TextStep::change` writes what `line` writes for a changed value; its caller's guarantees
/// (increasing positions, a changed value, a value that fits) are asserted in debug builds, the
/// frame's end in every build.
#[test]
fn text_step_change_writes_a_changed_value() {
    let got = after_a_text_run(|run| {
        let mut s = run.step(1).unwrap().expect("a step written at once");
        s.change(1, 5);
        s.change(2, 7);
    });
    assert!(
        got.contains("#1\nb0000000000000101 \"\nb00111 #\n"),
        "{got}"
    );
}

/// The VCD after a text run of a 3-variable frame (a 16-bit and a 5-bit variable at positions 1
/// and 2) whose first step, at t = 0, went through a frame run (values 0, 4, 3); `body` takes
/// the run's later steps.
fn after_a_text_run(body: impl FnOnce(&mut pmu50_waves::writer::TextRun<'_, Vec<u8>>)) -> String {
    let (mut w, mut f, _ids) = framed(frame_builder(), 3);
    assert_eq!(
        (f.max(1), f.max(2), f.max(3)),
        (Some(0xFFFF), Some(31), None)
    );
    {
        let mut run = w.text_run(&mut f).unwrap();
        assert!(run.step(0).unwrap().is_none());
        run.frame_run().unwrap().step(0).unwrap().set(1, 4).unwrap();
        body(&mut run);
    }
    text(w)
}

/// A text step's lines are the writer's as soon as they are written: a step that is leaked
/// (`mem::forget`, safe code) loses nothing (the step keeps its end of text in a register, and
/// each line stores it in the writer as well).
#[test]
// `TextStep` has no `Drop` (the point of the test: a caller's `forget` must not lose its lines)
#[allow(clippy::forget_non_drop)]
fn a_leaked_text_step_keeps_its_lines() {
    let got = after_a_text_run(|run| {
        let mut s = run.step(1).unwrap().expect("a step written at once");
        s.line(1, 5).unwrap();
        s.change(2, 7);
        std::mem::forget(s);
        let mut s = run.step(2).unwrap().expect("a step written at once");
        s.line(1, 6).unwrap();
    });
    assert!(
        got.contains("#1\nb0000000000000101 \"\nb00111 #\n#2\nb0000000000000110 \"\n"),
        "{got}"
    );
}

/// One of `TextStep::change`'s broken guarantees, in a text step at t = 1 of a 3-variable frame
/// whose values are 0, 4, 3.
#[cfg(debug_assertions)]
fn broken_change(k: usize, v: u64, first: Option<(usize, u64)>) {
    after_a_text_run(|run| {
        let mut s = run.step(1).unwrap().expect("a step written at once");
        if let Some((k, v)) = first {
            s.change(k, v);
        }
        s.change(k, v);
    });
}

#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "did not change")]
fn text_step_change_of_an_unchanged_value_is_asserted() {
    broken_change(1, 4, None);
}

#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "too wide for position 2")]
fn text_step_change_of_a_too_wide_value_is_asserted() {
    broken_change(2, 32, None);
}

#[cfg(debug_assertions)]
#[test]
#[should_panic(expected = "position 0 after 2")]
fn text_step_change_out_of_order_is_asserted() {
    broken_change(0, 1, Some((1, 9)));
}

#[test]
#[should_panic(expected = "index out of bounds")]
fn text_step_change_past_the_frame_panics() {
    let (mut w, mut f, _ids) = framed(frame_builder(), 3);
    let mut run = w.text_run(&mut f).unwrap();
    assert!(run.step(0).unwrap().is_none());
    run.frame_run().unwrap().step(0).unwrap().set(1, 4).unwrap();
    run.step(1)
        .unwrap()
        .expect("a step written at once")
        .change(3, 1);
}

/// A run's direct steps are written when the next step begins and the last one when the run
/// ends; the checks of a frame step stay (position, order, width, time, a step at a time the
/// frame was assigned), and a frame of another writer is refused.
#[test]
fn frame_runs_keep_every_check() {
    let (mut w, mut f, ids) = framed(frame_builder(), 3);
    {
        let mut run = w.frame_run(&mut f).unwrap();
        // t = 0 is the writer's time: a checked step (the first dump)
        run.step(0).unwrap().set(1, 4).unwrap();
        for t in 1..4 {
            let mut s = run.step(t).unwrap();
            assert!(s.is_current());
            step_checks(t, &mut |k, v| s.set(k, v));
        }
        assert!(matches!(run.step(3), Err(WriteError::DoubleChange { .. })));
        assert!(matches!(
            run.step(2),
            Err(WriteError::TimeBackwards {
                requested: 2,
                current: 3
            })
        ));
    }
    let (_other, mut f2) = after_a_run(&mut w, &ids);
    assert!(matches!(
        w.frame_run(&mut f2),
        Err(WriteError::UnknownFrame)
    ));
    let got = text(w);
    assert!(
        got.contains("#1\nb0000000000000101 \"\nb00001 #\n#2\n"),
        "{got}"
    );
    assert!(got.ends_with("#3\nb0000000000000111 \"\nb00011 #\nb0000000000000000000000000000000000000000000000000000000000000001 $\n"), "{got}");
}

/// Time stamps (two digits per division into a reused line): across digit boundaries, large
/// jumps and the largest times they are the decimal of the time (`u64::MAX` itself is outside
/// every window, which ends before it).
#[test]
fn time_stamps_across_digit_boundaries() {
    let times = [
        0u64,
        1,
        9,
        10,
        11,
        19,
        99,
        100,
        101,
        999,
        1000,
        1009,
        99_999,
        100_000,
        123_456_789,
        123_456_790,
        999_999_999_999,
        1_000_000_000_000,
        u64::MAX / 2,
        u64::MAX - 10,
        u64::MAX - 2,
        u64::MAX - 1,
    ];
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Ns), "t").unwrap();
    b.push_scope("m").unwrap();
    let a = b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap();
    b.pop_scope().unwrap();
    let mut w = b.start(Vec::new()).unwrap();
    for (k, &t) in times.iter().enumerate() {
        w.set_time(t).unwrap();
        w.change_bool(a, k % 2 == 1).unwrap();
    }
    let vcd = text(w);
    let stamps: Vec<u64> = vcd
        .lines()
        .filter_map(|l| l.strip_prefix('#'))
        .map(|d| d.parse().unwrap())
        .collect();
    assert_eq!(stamps, times, "{vcd}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, failure_persistence: None, ..Default::default() })]

    /// Time stamps of any increasing times (runs of equal steps, odd steps, jumps past 10^16)
    /// are the decimal of the time.
    #[test]
    fn time_stamps_are_the_decimal_of_the_time(start in 0u64..20_000_000_000_000_000, steps in proptest::collection::vec((1u64..4, 0u64..3), 1..80)) {
        let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Ns), "t").unwrap();
        b.push_scope("m").unwrap();
        let a = b.add_bit(BitType::Wire, "a", Logic::Zero).unwrap();
        b.pop_scope().unwrap();
        let mut w = b.start(Vec::new()).unwrap();
        let mut times = Vec::new();
        let mut t = start;
        for (k, (n, kind)) in steps.into_iter().enumerate() {
            // a step of 10, a step of 9_999, or a jump of 10^15
            let d = [10, 9_999, 1_000_000_000_000_000][kind as usize] * n;
            t = t.saturating_add(d).min(u64::MAX - 1);
            if times.last() == Some(&t) {
                break;
            }
            w.set_time(t).unwrap();
            w.change_bool(a, k % 2 == 0).unwrap();
            times.push(t);
        }
        let vcd = text(w);
        let stamps: Vec<u64> = vcd.lines().filter_map(|l| l.strip_prefix('#')).map(|d| d.parse().unwrap()).collect();
        proptest::prop_assert_eq!(&stamps[1..], &times[..]);
    }
}

/// A single change that keeps a frame variable's value is still an assignment: the frame cannot
/// be dumped in the same step (neither whole nor by a frame run's step), and an empty frame is
/// refused.
#[test]
fn a_single_change_to_the_same_value_blocks_the_frame_in_its_step() {
    let (mut w, mut f, ids) = framed(frame_builder(), 3);
    w.dump_frame(&mut f, 1, &[1, 2, 3]).unwrap();
    w.set_time(2).unwrap();
    w.change_vector(ids[1], 2).unwrap();
    assert!(matches!(
        w.dump_frame(&mut f, 2, &[1, 2, 3]),
        Err(WriteError::DoubleChange { .. })
    ));
    assert!(matches!(
        w.frame_run(&mut f).unwrap().step(2).err(),
        Some(WriteError::DoubleChange { .. })
    ));
    w.dump_frame(&mut f, 3, &[1, 2, 3]).unwrap();
    assert!(matches!(w.frame(&[]), Err(WriteError::EmptyFrame)));
}

/// [`frame_builder`]'s variables and two reals after them.
fn frame_builder_with_reals() -> (VcdBuilder, Vec<SigId>) {
    let (mut b, mut ids) = frame_builder();
    b.push_scope("env").unwrap();
    ids.push(b.add_real("theta", 0.0).unwrap());
    ids.push(b.add_real("vs2", 1.5).unwrap());
    b.pop_scope().unwrap();
    (b, ids)
}

/// The body of the two proptests below. Reals given in runs (`real`, after each step's frame
/// values) write exactly what `dump_frame` and `change_real` write at each step, with runs ended
/// at random (and a single change between them), inside or outside a window. `$open` opens a run
/// on the writer `$w` and frame `$f`; `$set` writes the step's frame values `$vals` at `$t`.
macro_rules! runs_with_reals_equal_change_real {
    ($window:expr, $steps:expr, |$w:ident, $f:ident| $open:expr, |$run:ident, $t:ident, $vals:ident| $set:block) => {{
        let (window, steps): (Option<(u64, u64)>, Vec<(u64, [u64; 4], [Option<usize>; 2], u8)>) = ($window, $steps);
        let reals = [0.0, -0.0, 37.001, 1.25e-7, 3e20];
        let start = |b: VcdBuilder, ids: &[SigId]| {
            let mut b = b;
            if let Some((s, len)) = window {
                b.window(s, s + len + 1).unwrap();
            }
            let mut w = b.start(Vec::new()).unwrap();
            let f = w.frame(&ids[..4]).unwrap();
            (w, f)
        };
        let (b1, ids1) = frame_builder_with_reals();
        let (b2, ids2) = frame_builder_with_reals();
        let (mut w1, mut f1) = start(b1, &ids1);
        let (mut w2, mut f2) = start(b2, &ids2);
        let (mut t, mut idx, mut zv) = (0u64, 0, false);
        while idx < steps.len() {
            {
                let mut $run = {
                    let ($w, $f) = (&mut w1, &mut f1);
                    $open
                };
                while idx < steps.len() {
                    let (dt, set, given, end) = steps[idx];
                    idx += 1;
                    t += dt;
                    let $vals: [u64; 4] = std::array::from_fn(|k| frame_value(k, set[k]));
                    let $t = t;
                    $set
                    w2.dump_frame(&mut f2, t, &$vals).unwrap();
                    for (j, g) in given.iter().enumerate() {
                        if let Some(g) = g {
                            $run.real(ids1[5 + j], reals[*g]).unwrap();
                            w2.change_real(ids2[5 + j], reals[*g]).unwrap();
                        }
                    }
                    if given.iter().all(Option::is_some) {
                        // each real once a step, in declaration order
                        let (e5, e6) = ($run.real(ids1[5], 1.0).err(), $run.real(ids1[6], 1.0).err());
                        proptest::prop_assert!(matches!(e5, Some(WriteError::FrameOrder { .. }) | Some(WriteError::DoubleChange { .. })), "{:?}", e5);
                        proptest::prop_assert!(matches!(e6, Some(WriteError::DoubleChange { .. })), "{:?}", e6);
                    }
                    if end == 0 {
                        break;
                    }
                }
            }
            // between runs: a change of the frame's `z` (outside the frame) at the same time
            zv = !zv;
            w1.change_bool(ids1[4], zv).unwrap();
            w2.change_bool(ids2[4], zv).unwrap();
        }
        proptest::prop_assert_eq!(text(w1), text(w2));
    }};
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 300, failure_persistence: None, ..Default::default() })]

    /// Reals given in text runs (`TextRun::real`, after each step's frame values) write exactly
    /// what `dump_frame` and `change_real` write at each step, with runs ended at random (and
    /// a single change between them), inside or outside a window.
    #[test]
    fn text_run_reals_equal_change_real(
        window in proptest::option::of((0u64..30, 0u64..80)),
        steps in proptest::collection::vec((1u64..3, proptest::array::uniform4(0u64..4), proptest::array::uniform2(proptest::option::of(0usize..5)), 0u8..8), 0..80),
    ) {
        runs_with_reals_equal_change_real!(window, steps, |w, f| w.text_run(f).unwrap(), |run, t, vals| {
            match run.step(t).unwrap() {
                Some(mut s) => {
                    for (k, v) in vals.iter().enumerate() {
                        s.line(k, *v).unwrap();
                    }
                }
                None => {
                    let mut fr = run.frame_run().unwrap();
                    let mut s = fr.step(t).unwrap();
                    for (k, v) in vals.iter().enumerate() {
                        s.set(k, *v).unwrap();
                    }
                }
            }
        });
    }

    /// Reals given in frame runs (`FrameRun::real`, after each step's frame values) write
    /// exactly what `dump_frame` and `change_real` write at each step, with runs ended at
    /// random (and a single change between them), inside or outside a window.
    #[test]
    fn frame_run_reals_equal_change_real(
        window in proptest::option::of((0u64..30, 0u64..80)),
        steps in proptest::collection::vec((1u64..3, proptest::array::uniform4(0u64..4), proptest::array::uniform2(proptest::option::of(0usize..5)), 0u8..8), 0..80),
    ) {
        runs_with_reals_equal_change_real!(window, steps, |w, f| w.frame_run(f).unwrap(), |run, t, vals| {
            let mut s = run.step(t).unwrap();
            for (k, v) in vals.iter().enumerate() {
                s.set(k, *v).unwrap();
            }
        });
    }
}

/// A run's `real` refuses a bit and a NaN and writes 2.5 into the real `ids[5]`.
fn real_keeps_the_checks(
    mut real: impl FnMut(SigId, f64) -> Result<(), WriteError>,
    ids: &[SigId],
) {
    assert!(
        matches!(real(ids[0], 1.0), Err(WriteError::TypeMismatch { .. })),
        "a bit is not a real"
    );
    assert!(matches!(
        real(ids[5], f64::NAN),
        Err(WriteError::NotFinite { .. })
    ));
    real(ids[5], 2.5).unwrap();
}

/// After [`real_keeps_the_checks`] in a run whose step at 2 set position 1 to 5: the real was
/// assigned in that step, once.
fn real_was_written_at_2(mut w: VcdWriter<Vec<u8>>, ids: &[SigId]) {
    assert!(matches!(
        w.change_real(ids[5], 3.0),
        Err(WriteError::DoubleChange { .. })
    ));
    let vcd = text(w);
    assert!(vcd.contains("#2\nb0000000000000101 \"\nr2.5 &\n"), "{vcd}");
}

#[test]
fn frame_run_reals_keep_the_checks() {
    let (b, ids) = frame_builder_with_reals();
    let mut w = b.start(Vec::new()).unwrap();
    let mut f = w.frame(&ids[..4]).unwrap();
    let mut run = w.frame_run(&mut f).unwrap();
    run.step(1).unwrap();
    // the first step of a run goes through the writer; the next one is direct
    let mut s = run.step(2).unwrap();
    s.set(1, 5).unwrap();
    real_keeps_the_checks(|id, v| run.real(id, v), &ids);
    drop(run);
    real_was_written_at_2(w, &ids);
}

#[test]
fn text_run_reals_keep_the_checks() {
    let (mut w, mut f, ids) = framed(frame_builder_with_reals(), 4);
    let mut run = w.text_run(&mut f).unwrap();
    run.frame_run().unwrap().step(1).unwrap();
    // the first step of a run goes through the writer; the next one is a text step
    let mut s = run.step(2).unwrap().expect("a text step");
    s.line(1, 5).unwrap();
    real_keeps_the_checks(|id, v| run.real(id, v), &ids);
    drop(run);
    real_was_written_at_2(w, &ids);
}
