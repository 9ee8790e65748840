//! Waveform diff behaviour.

mod common;

use common::{sample_builder, vcd, wave};
use pmu50_waves::diff::{
    diff, exit_code, DiffError, DiffOptions, DiffReport, Outcome, Sample, XPolicy,
};
use pmu50_waves::reader::{SignalKind, Waveform};
use pmu50_waves::writer::Logic;
use pmu50_waves::{TimeUnit, Timescale};

/// A model run written with the writer; `flip` flips bit 3 of `si` at that time.
fn run(ts: Timescale, scale: u64, flip: Option<u64>) -> Waveform {
    let (b, clk, en, si, vout) = sample_builder(ts);
    let mut w = b.start(Vec::new()).unwrap();
    w.change_bit(en, Logic::Zero).unwrap();
    for t in 1..100u64 {
        w.set_time(t * scale).unwrap();
        w.change_bool(clk, t % 2 == 1).unwrap();
        let mut v = (t * 37) % 65536;
        if flip == Some(t) {
            v ^= 1 << 3;
        }
        w.change_vector(si, v).unwrap();
        if t % 10 == 0 {
            w.change_real(vout, t as f64 / 8.0).unwrap();
            w.change_bool(en, t % 20 == 0).unwrap();
        }
    }
    Waveform::from_bytes(w.finish().unwrap()).unwrap()
}

/// A VCD with timescale `ts`, one scope `t`, the variables `vars` (as [`vcd`] takes them) and
/// the value changes `body`.
fn t_wave(ts: &str, vars: &[(&str, &str)], body: &str) -> Waveform {
    wave(&vcd(ts, &["t"], vars, body))
}

/// A VCD in 1 ns with the scope path `scopes`, the variables `vars` and the value changes `body`.
fn ns_wave(scopes: &[&str], vars: &[(&str, &str)], body: &str) -> Waveform {
    wave(&vcd("1 ns", scopes, vars, body))
}

/// [`t_wave`] in 1 ns.
fn t_ns(vars: &[(&str, &str)], body: &str) -> Waveform {
    ns_wave(&["t"], vars, body)
}

/// The diff of `l` and `r` with `opts`, checked EQUAL.
fn equal(l: &Waveform, r: &Waveform, opts: &DiffOptions) -> DiffReport {
    let report = diff(l, r, opts).unwrap();
    assert_eq!(report.outcome, Outcome::Equal, "{report}");
    report
}

/// [`equal`], with `n` signals compared.
fn equal_over(l: &Waveform, r: &Waveform, opts: &DiffOptions, n: usize) -> DiffReport {
    let report = equal(l, r, opts);
    assert_eq!(report.signals_compared, n);
    report
}

fn us() -> Timescale {
    Timescale::new(1, TimeUnit::Us)
}

#[test]
fn identical_files_are_equal() {
    let r = equal(
        &run(us(), 1, None),
        &run(us(), 1, None),
        &DiffOptions::default(),
    );
    assert_eq!(r.exit_code(), 0);
    assert_eq!(r.signals_compared, 4);
    assert_eq!(r.mismatch_count, 0);
    assert_eq!(r.first_mismatch_time, None);
    assert!(r.only_in_left.is_empty() && r.only_in_right.is_empty());
    assert_eq!(r.time_unit, Some(us()));
    assert!(r.to_string().starts_with("waveform diff: EQUAL"), "{r}");
}

#[test]
fn one_flipped_bit_is_the_first_mismatch_at_its_time() {
    let r = diff(
        &run(us(), 1, None),
        &run(us(), 1, Some(37)),
        &DiffOptions::default(),
    )
    .unwrap();
    assert_eq!(r.outcome, Outcome::Differ, "{r}");
    assert_eq!(r.exit_code(), 1);
    assert_eq!(r.mismatch_count, 1);
    assert_eq!(r.first_mismatch_time, Some(37));
    let m = &r.mismatches[0];
    assert_eq!(m.time, 37);
    assert_eq!(m.left_name, "pmu50.drive_interval.si[15:0]");
    assert_eq!(m.left, format!("{:016b}", 37 * 37));
    assert_eq!(m.right, format!("{:016b}", (37 * 37) ^ 8));
    let text = r.to_string();
    assert!(
        text.contains("value mismatches: 1 (first at 37 us)"),
        "{text}"
    );
    assert!(
        text.contains("t=37 us  pmu50.drive_interval.si[15:0]"),
        "{text}"
    );
}

#[test]
fn reports_first_n_mismatches_in_time_order_and_counts_all() {
    let left = ns_wave(
        &["top"],
        &[("!", "wire 4 a [3:0]"), ("\"", "wire 4 b [3:0]")],
        "#0\nb0 !\nb0 \"\n#10\nb1 !\nb1 \"\n#20\nb10 !\nb10 \"\n#30\nb11 !\nb11 \"\n",
    );
    let right = ns_wave(
        &["top"],
        &[("!", "wire 4 a [3:0]"), ("\"", "wire 4 b [3:0]")],
        "#0\nb0 !\nb1111 \"\n#10\nb1111 !\n#20\nb1110 !\n#30\nb1101 !\n",
    );
    let opts = DiffOptions {
        max_reported: 3,
        ..DiffOptions::default()
    };
    let r = diff(&left, &right, &opts).unwrap();
    assert_eq!(r.mismatch_count, 7, "{r}");
    let got: Vec<(u64, &str)> = r
        .mismatches
        .iter()
        .map(|m| (m.time, m.left_name.as_str()))
        .collect();
    assert_eq!(
        got,
        [(0, "top.b[3:0]"), (10, "top.a[3:0]"), (10, "top.b[3:0]")]
    );
    let none = diff(
        &left,
        &right,
        &DiffOptions {
            max_reported: 0,
            ..DiffOptions::default()
        },
    )
    .unwrap();
    assert_eq!(none.mismatch_count, 7);
    assert!(none.mismatches.is_empty());
    assert_eq!(none.first_mismatch_time, Some(0));
}

#[test]
fn prefix_mapping_pairs_pmu50_with_tb_dut() {
    let left = ns_wave(
        &["pmu50"],
        &[("!", "wire 1 clk"), ("\"", "reg 8 cnt [7:0]")],
        "#0\n0!\nb0 \"\n#5\n1!\nb101 \"\n",
    );
    let right = wave(
        "$timescale 1 ns $end\n$scope module tb $end\n$var wire 1 % stim $end\n\
         $scope module dut $end\n$var wire 1 ! clk $end\n$var reg 8 \" cnt [7:0] $end\n\
         $upscope $end\n$upscope $end\n$enddefinitions $end\n#0\n0!\nb0 \"\n1%\n#5\n1!\nb101 \"\n",
    );
    // default: no common path, stripping the top scope gives clk vs dut.clk: nothing matches
    let r = diff(&left, &right, &DiffOptions::default()).unwrap();
    assert_eq!(r.outcome, Outcome::Differ);
    assert_eq!(r.signals_compared, 0);
    assert_eq!(r.only_in_left, ["pmu50.clk", "pmu50.cnt[7:0]"]);
    assert_eq!(r.only_in_right.len(), 3);
    // mapped: equal; tb.stim lies outside the mapped prefix and is ignored
    let opts = DiffOptions {
        prefix_map: vec![("pmu50".into(), "tb.dut".into())],
        ..DiffOptions::default()
    };
    let r = equal_over(&left, &right, &opts, 2);
    assert!(
        r.mapping.contains("`pmu50` <-> right `tb.dut`"),
        "{}",
        r.mapping
    );
    // a mapped difference reports both names
    let right2 = wave(&right_text_with_cnt("b110"));
    let r = diff(&left, &right2, &opts).unwrap();
    assert_eq!(r.first_mismatch_time, Some(5));
    assert_eq!(r.mismatches[0].left_name, "pmu50.cnt[7:0]");
    assert_eq!(r.mismatches[0].right_name, "tb.dut.cnt[7:0]");
    // a prefix that matches nothing is bad input
    let bad = DiffOptions {
        prefix_map: vec![("pmu5".into(), "tb.dut".into())],
        ..DiffOptions::default()
    };
    let err = diff(&left, &right, &bad).unwrap_err();
    assert!(
        matches!(&err, DiffError::PrefixNotFound { side: "left", prefix, .. } if prefix == "pmu5")
    );
    assert_eq!(exit_code(&Err(err)), 2);
}

fn right_text_with_cnt(cnt_at_5: &str) -> String {
    format!(
        "$timescale 1 ns $end\n$scope module tb $end\n$scope module dut $end\n\
         $var wire 1 ! clk $end\n$var reg 8 \" cnt [7:0] $end\n$upscope $end\n$upscope $end\n\
         $enddefinitions $end\n#0\n0!\nb0 \"\n#5\n1!\n{cnt_at_5} \"\n"
    )
}

#[test]
fn default_matching_falls_back_to_stripping_the_top_scope() {
    let left = ns_wave(&["pmu50", "core"], &[("!", "wire 1 a")], "#0\n0!\n#3\n1!\n");
    let right = ns_wave(&["top", "core"], &[("#", "wire 1 a")], "#0\n0#\n#3\n1#\n");
    let r = equal_over(&left, &right, &DiffOptions::default(), 1);
    assert!(r.mapping.contains("top scope stripped"), "{}", r.mapping);
}

#[test]
fn timescales_1us_and_1000ns_compare_equal() {
    let a = run(us(), 1, None);
    let b = run(Timescale::new(100, TimeUnit::Ns), 10, None);
    let r = equal(&a, &b, &DiffOptions::default());
    // 1 us and 100 ns ticks: the common unit is 100 ns
    assert_eq!(r.time_unit, Some(Timescale::new(100, TimeUnit::Ns)));
    // `1000 ns` (not an IEEE factor, but readers accept it) vs `1 us`: compared in 1 us
    let l = t_wave("1 us", &[("!", "wire 1 a")], "#0\n0!\n#2\n1!\n#5\n0!\n");
    let k = t_wave("1000 ns", &[("!", "wire 1 a")], "#0\n0!\n#2\n1!\n#5\n0!\n");
    let r = equal(&l, &k, &DiffOptions::default());
    assert_eq!(r.time_unit, Some(us()));
    // 1 us vs 1 ns ticks with a difference: reported in ns
    let same = t_ns(&[("!", "wire 1 a")], "#0\n0!\n#2000\n1!\n#5000\n0!\n");
    let other = t_ns(&[("!", "wire 1 a")], "#0\n0!\n#2000\n1!\n#5001\n0!\n");
    let r = equal(&l, &same, &DiffOptions::default());
    assert_eq!(r.time_unit, Some(Timescale::new(1, TimeUnit::Ns)));
    let r = diff(&l, &other, &DiffOptions::default()).unwrap();
    assert_eq!(r.first_mismatch_time, Some(5000), "{r}");
    assert_eq!(r.mismatch_count, 1);
    // 10 us vs 100 ns compare in 100 ns
    let l = t_wave("10 us", &[("!", "wire 1 a")], "#0\n0!\n#3\n1!\n");
    let rr = t_wave("100 ns", &[("!", "wire 1 a")], "#0\n0!\n#300\n1!\n");
    let r = equal(&l, &rr, &DiffOptions::default());
    assert_eq!(r.time_unit, Some(Timescale::new(100, TimeUnit::Ns)));
}

#[test]
fn missing_timescale_on_one_side_is_bad_input() {
    let l = t_wave("1 us", &[("!", "wire 1 a")], "#0\n0!\n");
    let r = wave(
        "$scope module t $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end\n#0\n0!\n",
    );
    let err = diff(&l, &r, &DiffOptions::default()).unwrap_err();
    assert!(
        matches!(err, DiffError::MissingTimescale { side: "right", .. }),
        "{err:?}"
    );
    assert!(err.to_string().contains("$timescale"), "{err}");
    // timescales too far apart for 64-bit ticks are bad input, not a panic
    let huge = t_wave("4000000000 s", &[("!", "wire 1 a")], "#0\n0!\n");
    let tiny = t_wave("1 fs", &[("!", "wire 1 a")], "#0\n0!\n");
    let err = diff(&huge, &tiny, &DiffOptions::default()).unwrap_err();
    assert!(
        matches!(err, DiffError::IncompatibleTimescales { .. }),
        "{err:?}"
    );
}

#[test]
fn widths_8_and_16_are_zero_extended_and_real_vs_vector_is_a_type_mismatch() {
    let l = t_ns(
        &[("!", "wire 8 v [7:0]"), ("\"", "real 64 r")],
        "#0\nb10100101 !\nr1.5 \"\n#4\nb11111111 !\n",
    );
    let r = t_ns(
        &[("!", "wire 16 v [15:0]"), ("\"", "real 64 r")],
        "#0\nb0000000010100101 !\nr1.5 \"\n#4\nb0000000011111111 !\n",
    );
    equal_over(&l, &r, &DiffOptions::default(), 2);
    // a set upper bit on the wide side is a difference
    let r2 = t_ns(
        &[("!", "wire 16 v [15:0]"), ("\"", "real 64 r")],
        "#0\nb0000000010100101 !\nr1.5 \"\n#4\nb0000000111111111 !\n",
    );
    let res = diff(&l, &r2, &DiffOptions::default()).unwrap();
    assert_eq!(res.first_mismatch_time, Some(4));
    // real on one side, vector on the other
    let r3 = t_ns(
        &[("!", "wire 8 v [7:0]"), ("\"", "wire 64 r [63:0]")],
        "#0\nb10100101 !\nb1 \"\n#4\nb11111111 !\n",
    );
    let res = diff(&l, &r3, &DiffOptions::default()).unwrap();
    assert_eq!(res.outcome, Outcome::Differ);
    assert_eq!(res.signals_compared, 1);
    assert_eq!(res.type_mismatches.len(), 1);
    assert_eq!(res.type_mismatches[0].left_kind, SignalKind::Real);
    assert_eq!(res.type_mismatches[0].right_kind, SignalKind::Bits);
    assert!(
        res.to_string()
            .contains("type mismatch: t.r (real) <-> t.r[63:0] (bit vector)"),
        "{res}"
    );
}

#[test]
fn real_tolerance() {
    let l = t_ns(&[("!", "real 64 r")], "#0\nr1.5 !\n#2\nr2.0 !\n");
    let r = t_ns(&[("!", "real 64 r")], "#0\nr1.5 !\n#2\nr2.0000001 !\n");
    assert_eq!(
        diff(&l, &r, &DiffOptions::default()).unwrap().outcome,
        Outcome::Differ
    );
    let opts = DiffOptions {
        real_tolerance: 1e-6,
        ..DiffOptions::default()
    };
    assert_eq!(diff(&l, &r, &opts).unwrap().outcome, Outcome::Equal);
    let bad = DiffOptions {
        real_tolerance: f64::NAN,
        ..DiffOptions::default()
    };
    assert!(matches!(
        diff(&l, &r, &bad),
        Err(DiffError::BadTolerance(_))
    ));
}

#[test]
fn x_handling_strict_and_wildcard() {
    let with_x = t_ns(
        &[("!", "wire 4 v [3:0]")],
        "#0\nb0000 !\n#5\nb01x1 !\n#9\nb0000 !\n",
    );
    let plain = t_ns(
        &[("!", "wire 4 v [3:0]")],
        "#0\nb0000 !\n#5\nb0111 !\n#9\nb0000 !\n",
    );
    let other = t_ns(
        &[("!", "wire 4 v [3:0]")],
        "#0\nb0000 !\n#5\nb1101 !\n#9\nb0000 !\n",
    );
    let with_z = t_ns(
        &[("!", "wire 4 v [3:0]")],
        "#0\nb0000 !\n#5\nb01z1 !\n#9\nb0000 !\n",
    );
    let strict = DiffOptions::default();
    let left_x = DiffOptions {
        x_policy: XPolicy::LeftXIsWildcard,
        ..DiffOptions::default()
    };
    let either = DiffOptions {
        x_policy: XPolicy::EitherXIsWildcard,
        ..DiffOptions::default()
    };
    // strict: x only equals x
    let r = diff(&with_x, &plain, &strict).unwrap();
    assert_eq!(r.first_mismatch_time, Some(5));
    assert_eq!(
        (
            r.mismatches[0].left.as_str(),
            r.mismatches[0].right.as_str()
        ),
        ("01x1", "0111")
    );
    // (left, right, options, outcome)
    let cases = [
        (&with_x, &with_x, &strict, Outcome::Equal),
        // left x is a don't-care ...
        (&with_x, &plain, &left_x, Outcome::Equal),
        // right x is not a don't-care under LeftXIsWildcard, but is under EitherXIsWildcard
        (&plain, &with_x, &left_x, Outcome::Differ),
        (&plain, &with_x, &either, Outcome::Equal),
        // z is never a wildcard
        (&with_z, &plain, &either, Outcome::Differ),
        (&with_z, &with_z, &strict, Outcome::Equal),
    ];
    for (k, (l, r, opts, want)) in cases.into_iter().enumerate() {
        assert_eq!(diff(l, r, opts).unwrap().outcome, want, "case {k}");
    }
    // a left x is a don't-care for that bit only
    assert_eq!(
        diff(&with_x, &other, &left_x).unwrap().first_mismatch_time,
        Some(5)
    );
    // a missing value (signal starts later) counts as x
    let late = t_ns(&[("!", "wire 4 v [3:0]")], "#0\n#5\nb0111 !\n#9\nb0000 !\n");
    let r = diff(&late, &plain, &strict).unwrap();
    assert_eq!(r.first_mismatch_time, Some(0), "{r}");
    assert_eq!(r.mismatches[0].left, "(none)");
    assert_eq!(
        diff(&late, &plain, &left_x).unwrap().outcome,
        Outcome::Equal
    );
}

fn clocked(glitch: bool, at_edge: bool) -> Waveform {
    // clk rises at 10, 30, 50; q changes at the edges; an optional glitch on q
    // between edges (t=15..17) or exactly at the edge instant 30 (value after
    // all changes at 30 differs).
    let mut body = String::from("#0\n0!\nb00 \"\n#10\n1!\nb01 \"\n");
    if glitch {
        body += "#15\nb11 \"\n#17\nb01 \"\n";
    }
    body += "#20\n0!\n";
    body += if at_edge {
        "#30\n1!\nb11 \"\n"
    } else {
        "#30\n1!\nb10 \"\n"
    };
    body += "#40\n0!\n#50\n1!\nb00 \"\n#60\n0!\n";
    ns_wave(
        &["top"],
        &[("!", "wire 1 clk"), ("\"", "reg 2 q [1:0]")],
        &body,
    )
}

#[test]
fn clock_sampling_ignores_glitches_between_edges() {
    let clean = clocked(false, false);
    let glitchy = clocked(true, false);
    let all = diff(&clean, &glitchy, &DiffOptions::default()).unwrap();
    assert_eq!(all.outcome, Outcome::Differ, "{all}");
    assert_eq!(all.first_mismatch_time, Some(15));
    let opts = DiffOptions {
        sample: Sample::RisingEdge("top.clk".into()),
        ..DiffOptions::default()
    };
    let r = equal(&clean, &glitchy, &opts);
    assert!(r.sampling.contains("3 rising edges"), "{}", r.sampling);
    // a difference at an edge is still found
    let wrong = clocked(false, true);
    let r = diff(&clean, &wrong, &opts).unwrap();
    assert_eq!(r.first_mismatch_time, Some(30), "{r}");
    assert_eq!(r.mismatch_count, 1);
    // sampling every 10 ticks also skips the glitch (15, 17 are not multiples of 10)
    let every = DiffOptions {
        sample: Sample::Every(10),
        ..DiffOptions::default()
    };
    assert_eq!(
        diff(&clean, &glitchy, &every).unwrap().outcome,
        Outcome::Equal
    );
    assert_eq!(
        diff(&clean, &wrong, &every).unwrap().first_mismatch_time,
        Some(30)
    );
    // the GTKWave name of the clock works too
    let by_name = DiffOptions {
        sample: Sample::RisingEdge("top.clk".into()),
        ..DiffOptions::default()
    };
    assert!(diff(&clean, &glitchy, &by_name).is_ok());
}

#[test]
fn bad_sampling_options_are_bad_input() {
    let a = clocked(false, false);
    let o = |s: Sample| DiffOptions {
        sample: s,
        ..DiffOptions::default()
    };
    assert!(matches!(
        diff(&a, &a, &o(Sample::RisingEdge("top.nope".into()))),
        Err(DiffError::ClockNotFound { .. })
    ));
    let err = diff(&a, &a, &o(Sample::RisingEdge("top.q[1:0]".into()))).unwrap_err();
    assert!(
        matches!(err, DiffError::ClockNotOneBit { width: 2, .. }),
        "{err:?}"
    );
    assert!(matches!(
        diff(&a, &a, &o(Sample::Every(0))),
        Err(DiffError::ZeroPeriod)
    ));
}

#[test]
fn signals_on_one_side_only() {
    let l = t_ns(
        &[("!", "wire 1 a"), ("\"", "wire 1 extra")],
        "#0\n0!\n0\"\n",
    );
    let r = t_ns(&[("!", "wire 1 a")], "#0\n0!\n");
    let res = diff(&l, &r, &DiffOptions::default()).unwrap();
    assert_eq!(res.outcome, Outcome::Differ);
    assert_eq!(res.only_in_left, ["t.extra"]);
    assert!(res.to_string().contains("only in left: t.extra"), "{res}");
    let allow = DiffOptions {
        allow_unmatched: true,
        ..DiffOptions::default()
    };
    assert_eq!(diff(&l, &r, &allow).unwrap().outcome, Outcome::Equal);
}

#[test]
fn bit_selects_merge_into_one_vector_and_repeated_paths_use_gtkwave_names() {
    // wellen merges `b [0]` + `b [1]` into `b[1:0]`, whatever the declaration order
    let l = t_ns(
        &[("!", "wire 1 b [0]"), ("\"", "wire 1 b [1]")],
        "#0\n0!\n1\"\n",
    );
    let r = t_ns(
        &[("\"", "wire 1 b [1]"), ("!", "wire 1 b [0]")],
        "#0\n0!\n1\"\n",
    );
    equal_over(&l, &r, &DiffOptions::default(), 1);
    // a path declared twice (scalar `a` and vector `a [3:0]`) is keyed by GTKWave name
    let decls = [("!", "wire 1 a"), ("\"", "wire 4 a [3:0]")];
    let l = t_ns(&decls, "#0\n0!\nb0101 \"\n");
    let r = t_ns(&decls, "#0\n0!\nb0111 \"\n");
    let res = diff(&l, &r, &DiffOptions::default()).unwrap();
    assert_eq!(res.signals_compared, 2, "{res}");
    assert_eq!(res.mismatch_count, 1, "{res}");
    assert_eq!(res.mismatches[0].left_name, "t.a[3:0]");
}

#[test]
fn unreadable_files_are_bad_input() {
    let dir = std::env::temp_dir().join(format!("pmu50-waves-diff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("good.vcd");
    std::fs::write(&good, vcd("1 ns", &["t"], &[("!", "wire 1 a")], "#0\n0!\n")).unwrap();
    let garbage = dir.join("garbage.vcd");
    std::fs::write(&garbage, "this is not a waveform\n").unwrap();
    let missing = dir.join("missing.vcd");
    for (l, r, side) in [(&good, &missing, "right"), (&garbage, &good, "left")] {
        let res = pmu50_waves::diff::diff_files(l, r, &DiffOptions::default());
        assert_eq!(exit_code(&res), DiffError::EXIT_CODE);
        let err = res.unwrap_err();
        assert!(
            matches!(&err, DiffError::Read { side: s, .. } if *s == side),
            "{err:?}"
        );
        assert!(err.to_string().contains(side), "{err}");
    }
    let ok = pmu50_waves::diff::diff_files(&good, &good, &DiffOptions::default());
    assert_eq!(exit_code(&ok), 0);
    let _ = std::fs::remove_dir_all(&dir);
}
