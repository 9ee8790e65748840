//! Malformed and hostile inputs: the reader and the diff refuse each with the
//! file, the line and what is wrong (exit code 2), never a panic, a warning or
//! a silent EQUAL.

use std::path::{Path, PathBuf};

use pmu50_waves::diff::{diff, diff_files, exit_code, DiffError, DiffOptions, Outcome};
use pmu50_waves::fuzzing::{self, Malformed, MALFORMED, VALID_SAMPLE};
use pmu50_waves::reader::{ReadError, ReadLimits, Waveform, DEFAULT_MAX_VAR_WIDTH};
use pmu50_waves::validate::{validate, Problem, ValidateError};

/// A fresh temporary folder named after `tag`, removed with what it holds when dropped.
fn tmp(tag: &str) -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix(&format!("pmu50-waves-malformed-{tag}-"))
        .tempdir()
        .unwrap()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

fn shape(name: &str) -> Malformed {
    *MALFORMED
        .iter()
        .find(|m| m.name == name)
        .unwrap_or_else(|| panic!("no shape {name}"))
}

/// Validator, reader and `diff_files` all refuse `m` with its line and message.
fn refused(m: Malformed) {
    match validate(m.vcd, DEFAULT_MAX_VAR_WIDTH) {
        Err(ValidateError::Malformed(Problem { line, what })) => {
            assert_eq!(line, m.line, "{}: line of `{what}`", m.name);
            assert!(
                what.contains(m.says),
                "{}: `{what}` lacks `{}`",
                m.name,
                m.says
            );
        }
        other => panic!("{}: validator gave {other:?}", m.name),
    }
    let e = Waveform::from_bytes(m.vcd.to_vec()).unwrap_err();
    assert!(
        matches!(e, ReadError::Malformed { line, .. } if line == m.line),
        "{}: {e:?}",
        m.name
    );
    assert!(
        e.to_string()
            .starts_with(&format!("<memory>:{}: malformed VCD: ", m.line)),
        "{e}"
    );

    let t = tmp(m.name);
    let d = t.path();
    let bad = write(d, "bad.vcd", m.vcd);
    let good = write(d, "good.vcd", VALID_SAMPLE);
    for (l, r, side) in [(&bad, &good, "left"), (&good, &bad, "right")] {
        let res = diff_files(l, r, &DiffOptions::default());
        assert_eq!(exit_code(&res), 2, "{}", m.name);
        let e = res.unwrap_err();
        assert_eq!(e.exit_code(), DiffError::EXIT_CODE);
        let msg = e.to_string();
        let want = format!(
            "cannot read {side} waveform: {}:{}: malformed VCD: ",
            bad.display(),
            m.line
        );
        assert!(msg.starts_with(&want), "{msg}");
        assert!(msg.contains(m.says), "{msg}");
        assert!(!msg.contains('\n'), "one line: {msg}");
    }
    // the fuzz body treats a refused file as a normal outcome
    fuzzing::vcd(m.vcd);
}

macro_rules! shapes {
    ($($name:ident),* $(,)?) => {
        $(#[test] fn $name() { refused(shape(stringify!($name))); })*
        const TESTED: &[&str] = &[$(stringify!($name)),*];
    };
}

shapes!(
    width_4294967295,
    value_wider_than_var,
    bad_bit_character,
    bad_scalar_character,
    undeclared_identifier,
    undeclared_vector_identifier,
    bad_real,
    real_for_vector,
    vector_for_real,
    string_for_vector,
    scalar_for_vector,
    short_value_not_extendable,
    empty_vector,
    vector_without_identifier,
    vector_for_event,
    unbalanced_upscope,
    scope_not_closed,
    empty_scope,
    unknown_scope_type,
    duplicate_timescale,
    duplicate_date,
    duplicate_version,
    bad_timescale_unit,
    non_utf8_var_name,
    non_utf8_scope_name,
    name_starts_with_bracket,
    index_too_long,
    var_size_not_a_number,
    var_size_zero,
    unknown_var_type,
    var_too_few_tokens,
    identifier_reused_with_other_width,
    end_glued_to_name,
    time_goes_backwards,
    bad_time,
    negative_time,
    unknown_body_command,
    text_after_enddefinitions,
    no_enddefinitions,
    command_without_end,
    not_a_vcd,
    attribute_extension,
    non_utf8_string_value,
);

#[test]
fn every_shape_has_its_own_test() {
    let listed: Vec<&str> = MALFORMED.iter().map(|m| m.name).collect();
    assert_eq!(listed, TESTED);
}

#[test]
fn valid_sample_with_every_kind_is_accepted_and_equal_to_itself() {
    let w = Waveform::from_bytes(VALID_SAMPLE.to_vec()).unwrap();
    assert_eq!(w.signals().len(), 6);
    assert_eq!(w.end_time(), 7);
    let r = diff(&w, &w, &DiffOptions::default()).unwrap();
    assert_eq!(r.outcome, Outcome::Equal, "{r}");
    fuzzing::vcd(VALID_SAMPLE);
}

#[test]
fn icarus_verilog_output_is_accepted() {
    // waves/tests/data/icarus.vcd: `iverilog icarus.v && vvp a.out` (Icarus Verilog 12):
    // $date/$version, `$var reg 8 $ cnt [7:0]` (identifier `$`), integer, time, real (size 1),
    // event, $dumpvars ... $end, and a real that becomes NaN (0.0/0.0) at 100 ns.
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/icarus.vcd");
    let w = Waveform::open(&p).unwrap();
    assert_eq!(w.signals().len(), 9);
    let r = w.changes("tb.r").unwrap();
    assert!(
        matches!(r.last(), Some((_, pmu50_waves::Value::Real(v))) if v.is_nan()),
        "{r:?}"
    );
    let rep = diff_files(&p, &p, &DiffOptions::default()).unwrap();
    assert_eq!(rep.outcome, Outcome::Equal, "{rep}");
}

const NAN_VCD: &str = "$timescale 1 ns $end\n$scope module t $end\n$var real 64 ! v $end\n$upscope $end\n$enddefinitions $end\n#0\nr1.5 !\n#10\nrnan !\n#20\nr2 !\n";

#[test]
fn nan_equals_nan_for_a_diff() {
    let t = tmp("nan");
    let d = t.path();
    let a = write(d, "a.vcd", NAN_VCD.as_bytes());
    let b = write(d, "b.vcd", NAN_VCD.replace("rnan", "rNaN").as_bytes());
    let c = write(d, "c.vcd", NAN_VCD.replace("rnan", "r1").as_bytes());
    for (l, r) in [(&a, &a), (&a, &b)] {
        let rep = diff_files(l, r, &DiffOptions::default()).unwrap();
        assert_eq!(rep.outcome, Outcome::Equal, "{rep}");
        assert_eq!(rep.exit_code(), 0);
    }
    let rep = diff_files(&a, &c, &DiffOptions::default()).unwrap();
    assert_eq!(rep.outcome, Outcome::Differ, "{rep}");
    assert_eq!(rep.mismatch_count, 1);
    assert_eq!(
        (
            rep.mismatches[0].left.as_str(),
            rep.mismatches[0].right.as_str()
        ),
        ("NaN", "1")
    );
    // with a tolerance, NaN still equals only NaN
    let tol = DiffOptions {
        real_tolerance: 1e9,
        ..DiffOptions::default()
    };
    assert_eq!(diff_files(&a, &c, &tol).unwrap().outcome, Outcome::Differ);
}

#[test]
fn time_going_backwards_is_bad_input_not_an_equal() {
    // wellen would print a WARN, drop the change at #5 and call the two files EQUAL
    let t = tmp("backwards");
    let d = t.path();
    let body = "$timescale 1 ns $end\n$scope module t $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end\n#0\n0!\n#10\n1!\n";
    let back = write(d, "back.vcd", format!("{body}#5\n0!\n").as_bytes());
    let plain = write(d, "plain.vcd", body.as_bytes());
    let res = diff_files(&back, &plain, &DiffOptions::default());
    assert_eq!(exit_code(&res), 2);
    let msg = res.unwrap_err().to_string();
    assert!(
        msg.contains(&format!(
            "{}:10: malformed VCD: time goes backwards: #5 after #10 (line 8)",
            back.display()
        )),
        "{msg}"
    );
}

#[test]
fn declared_width_bound_is_checked_before_reading_and_configurable() {
    let at = |w: u32| {
        format!("$timescale 1 ns $end\n$scope module t $end\n$var wire {w} ! a $end\n$upscope $end\n$enddefinitions $end\n#0\nb1 !\n")
    };
    assert!(Waveform::from_bytes(at(DEFAULT_MAX_VAR_WIDTH).into_bytes()).is_ok());
    let e = Waveform::from_bytes(at(DEFAULT_MAX_VAR_WIDTH + 1).into_bytes()).unwrap_err();
    assert!(
        e.to_string()
            .contains("declared with 65537 bits; the limit is 65536 bits"),
        "{e}"
    );
    let small = ReadLimits {
        max_var_width: 16,
        ..ReadLimits::default()
    };
    assert!(Waveform::from_bytes_with(at(16).into_bytes(), &small).is_ok());
    let e = Waveform::from_bytes_with(at(17).into_bytes(), &small).unwrap_err();
    assert!(matches!(e, ReadError::Malformed { line: 3, .. }), "{e:?}");
    // through diff_files, with the limit in the options
    let t = tmp("width");
    let d = t.path();
    let f = write(d, "w.vcd", at(17).as_bytes());
    let opts = DiffOptions {
        read_limits: small,
        ..DiffOptions::default()
    };
    assert_eq!(exit_code(&diff_files(&f, &f, &opts)), 2);
    assert_eq!(exit_code(&diff_files(&f, &f, &DiffOptions::default())), 0);
}

#[test]
fn non_regular_files_are_refused_without_opening_them() {
    let t = tmp("special");
    let d = t.path();
    let good = write(d, "good.vcd", VALID_SAMPLE);
    let fifo = d.join("fifo.vcd");
    let st = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(st.success());
    // a FIFO without a writer would block an open(); it must be refused before that
    for (p, kind) in [
        (fifo.as_path(), "FIFO"),
        (d, "directory"),
        (Path::new("/dev/null"), "character device"),
    ] {
        let e = Waveform::open(p).unwrap_err();
        assert!(
            matches!(e, ReadError::NotRegular { kind: k, .. } if k == kind),
            "{e:?}"
        );
        let res = diff_files(p, &good, &DiffOptions::default());
        assert_eq!(exit_code(&res), 2);
        let msg = res.unwrap_err().to_string();
        assert!(
            msg.contains(&format!("{} is a {kind}, not a regular file", p.display())),
            "{msg}"
        );
        assert_eq!(exit_code(&diff_files(&good, p, &DiffOptions::default())), 2);
    }
    // a symlink to a regular file is read through
    let link = d.join("link.vcd");
    std::os::unix::fs::symlink(&good, &link).unwrap();
    assert_eq!(
        exit_code(&diff_files(&link, &good, &DiffOptions::default())),
        0
    );
}

#[test]
fn files_over_the_size_limit_are_refused() {
    let t = tmp("size");
    let d = t.path();
    let f = write(d, "f.vcd", VALID_SAMPLE);
    let n = VALID_SAMPLE.len() as u64;
    let exact = DiffOptions {
        read_limits: ReadLimits {
            max_file_bytes: n,
            ..ReadLimits::default()
        },
        ..DiffOptions::default()
    };
    assert_eq!(exit_code(&diff_files(&f, &f, &exact)), 0);
    let under = DiffOptions {
        read_limits: ReadLimits {
            max_file_bytes: n - 1,
            ..ReadLimits::default()
        },
        ..DiffOptions::default()
    };
    let res = diff_files(&f, &f, &under);
    assert_eq!(exit_code(&res), 2);
    let msg = res.unwrap_err().to_string();
    assert!(
        msg.contains(&format!(
            "{} is {n} bytes, more than the limit of {} bytes",
            f.display(),
            n - 1
        )),
        "{msg}"
    );
    let e = Waveform::from_bytes_with(VALID_SAMPLE.to_vec(), &under.read_limits).unwrap_err();
    assert!(matches!(e, ReadError::TooLarge { .. }), "{e:?}");
    assert_eq!(
        ReadLimits::default().max_file_bytes,
        2 << 30,
        "the documented default is 2 GiB"
    );
}

#[test]
fn a_huge_token_is_refused_with_bounded_memory() {
    let mut v = b"$timescale 1 ns $end\n$scope module t $end\n$var string 1 ! s $end\n$upscope $end\n$enddefinitions $end\n#0\ns".to_vec();
    v.extend(std::iter::repeat_n(b'a', 3 << 20));
    v.extend_from_slice(b" !\n");
    let e = Waveform::from_bytes(v).unwrap_err();
    assert!(
        e.to_string()
            .contains("<memory>:7: malformed VCD: token `saaaa"),
        "{e}"
    );
    assert!(
        e.to_string().contains("is longer than 1048576 bytes"),
        "{e}"
    );
}
