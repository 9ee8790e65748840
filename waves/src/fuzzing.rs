//! Bodies of the waveform fuzz targets (`fuzz/fuzz_targets/vcd_diff.rs`, `fst_read.rs`).
//!
//! They live here, in the library, so that the cargo-fuzz target (nightly,
//! libFuzzer) and the stable replay test (`tests/fuzz_replay.rs`, part of
//! `make test`) run exactly the same code. A body returns normally for every
//! input, valid or not; it panics only when it finds a bug:
//!
//! * `wellen` panicked on a file [`crate::validate`] accepted (a validator gap);
//! * a readable file is not EQUAL to itself (e.g. NaN, duplicate names);
//! * the reader's last time differs from the validator's (a dropped time step);
//! * an FST's error is not one line.
//!
//! For FST, [`crate::fst_check`] refuses what would make wellen allocate without bound, loop or
//! panic on sizes and counts; damaged *contents* of the packed value changes (a bit character
//! `4`, a value one bit short) still make wellen panic, which the reader's guard turns into
//! [`ReadError::FstReaderPanicked`], one line, nothing printed: accepted here. An abort (an
//! allocation of what a damaged size declares) or a hang fails libFuzzer's run and the stable
//! replay by itself.

use crate::diff::{diff, DiffOptions, Outcome, XPolicy};
use crate::reader::{ReadError, ReadLimits, Waveform};
use crate::validate::validate;

/// Limits for fuzzing: small enough that one input stays fast.
pub const FUZZ_LIMITS: ReadLimits = ReadLimits {
    max_file_bytes: 1 << 20,
    max_var_width: 4096,
};

/// Reads `data` as a VCD and diffs it with itself.
///
/// # Panics
/// Only on a bug (see the module documentation), never on malformed input.
pub fn vcd(data: &[u8]) {
    let summary = validate(data, FUZZ_LIMITS.max_var_width);
    let w = match Waveform::from_bytes_with(data.to_vec(), &FUZZ_LIMITS) {
        Ok(w) => w,
        Err(ReadError::ParserPanicked { message, .. }) => {
            panic!("wellen panicked on a VCD the validator accepted: {message}")
        }
        Err(_) => return,
    };
    let summary = summary.expect("the reader accepted a file the validator refused");
    assert_eq!(
        w.end_time(),
        summary.end_time,
        "the reader's last time differs from the file's last #time"
    );
    for i in 0..w.signals().len() {
        let ch = w.changes_at(i);
        assert!(
            ch.windows(2).all(|p| p[0].0 <= p[1].0),
            "changes of {} are not in time order",
            w.signals()[i].gtkwave_name()
        );
    }
    for x_policy in [XPolicy::Strict, XPolicy::EitherXIsWildcard] {
        let opts = DiffOptions {
            x_policy,
            ..DiffOptions::default()
        };
        let r = match diff(&w, &w, &opts) {
            Ok(r) => r,
            Err(e) => panic!("diff of a readable file with itself failed: {e}"),
        };
        assert_eq!(
            r.outcome,
            Outcome::Equal,
            "a file differs from itself:\n{r}"
        );
    }
}

/// Reads `data` as an FST (any bytes: the reader takes a file starting with a NUL byte for an
/// FST) and diffs it with itself.
///
/// # Panics
/// Only on a bug (see the module documentation), never on a damaged file.
pub fn fst(data: &[u8]) {
    let w = match Waveform::from_bytes_with(data.to_vec(), &FUZZ_LIMITS) {
        Ok(w) => w,
        Err(e) => {
            let text = e.to_string();
            assert!(!text.contains('\n'), "an error is one line: {text}");
            return;
        }
    };
    for i in 0..w.signals().len() {
        let ch = w.changes_at(i);
        assert!(
            ch.windows(2).all(|p| p[0].0 <= p[1].0),
            "changes of {} are not in time order",
            w.signals()[i].gtkwave_name()
        );
    }
    let r = match diff(&w, &w, &DiffOptions::default()) {
        Ok(r) => r,
        Err(e) => panic!("diff of a readable FST with itself failed: {e}"),
    };
    assert_eq!(
        r.outcome,
        Outcome::Equal,
        "an FST differs from itself:\n{r}"
    );
}

/// One malformed-VCD shape: `wellen` panics on (or silently misreads) each of
/// them; the validator refuses each with its line and a message.
#[derive(Debug, Clone, Copy)]
pub struct Malformed {
    /// Short name (used for test names and seed-corpus files).
    pub name: &'static str,
    /// The file.
    pub vcd: &'static [u8],
    /// Line the validator reports.
    pub line: u64,
    /// A fragment of the message.
    pub says: &'static str,
}

macro_rules! hdr {
    ($vars:literal) => {
        concat!(
            "$timescale 1 us $end\n$scope module top $end\n",
            $vars,
            "$upscope $end\n$enddefinitions $end\n"
        )
    };
}

/// The malformed shapes the reader must refuse as bad input (waves/tests/malformed.rs; and
/// the ones found while writing the validator). Line numbers count from 1; the header of `hdr!` with one `$var`
/// takes lines 1-5, so the body starts on line 6.
pub const MALFORMED: &[Malformed] = &[
    Malformed {
        name: "width_4294967295",
        vcd: concat!(hdr!("$var wire 4294967295 ! a $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "declared with 4294967295 bits; the limit is 65536 bits",
    },
    Malformed {
        name: "value_wider_than_var",
        vcd: concat!(hdr!("$var wire 4 ! a [3:0] $end\n"), "#0\nb10101 !\n").as_bytes(),
        line: 7,
        says: "value `b10101` has 5 bits but `top.a [3:0]` is declared with 4",
    },
    Malformed {
        name: "bad_bit_character",
        vcd: concat!(hdr!("$var wire 4 ! a $end\n"), "#0\nb1021 !\n").as_bytes(),
        line: 7,
        says: "bad bit character `2` in `b1021`",
    },
    Malformed {
        name: "bad_scalar_character",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#0\n2!\n").as_bytes(),
        line: 7,
        says: "unexpected `2!`",
    },
    Malformed {
        name: "undeclared_identifier",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#0\n1#\n").as_bytes(),
        line: 7,
        says: "identifier `#` in `1#` is not declared",
    },
    Malformed {
        name: "undeclared_vector_identifier",
        vcd: concat!(hdr!("$var wire 4 ! a $end\n"), "#0\nb1 %\n").as_bytes(),
        line: 7,
        says: "identifier `%` in `b1` is not declared",
    },
    Malformed {
        name: "bad_real",
        vcd: concat!(hdr!("$var real 64 ! v $end\n"), "#0\nr1.2.3 !\n").as_bytes(),
        line: 7,
        says: "real value `r1.2.3` for `top.v` is not a number",
    },
    Malformed {
        name: "real_for_vector",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nr1.5 !\n").as_bytes(),
        line: 7,
        says: "real value `r1.5` for `top.a`, which is declared as a 8-bit vector",
    },
    Malformed {
        name: "vector_for_real",
        vcd: concat!(hdr!("$var real 64 ! v $end\n"), "#0\nb101 !\n").as_bytes(),
        line: 7,
        says: "vector value `b101` for `top.v`, which is declared as a real",
    },
    Malformed {
        name: "string_for_vector",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nshello !\n").as_bytes(),
        line: 7,
        says: "string value `shello` for `top.a`",
    },
    Malformed {
        name: "scalar_for_vector",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nh!\n").as_bytes(),
        line: 7,
        says: "scalar value `h` for `top.a`, a 8-bit vector",
    },
    Malformed {
        name: "short_value_not_extendable",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nbh1 !\n").as_bytes(),
        line: 7,
        says: "a shorter value must start with 0, 1, x or z",
    },
    Malformed {
        name: "empty_vector",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nb !\n").as_bytes(),
        line: 7,
        says: "has no bits",
    },
    Malformed {
        name: "vector_without_identifier",
        vcd: concat!(hdr!("$var wire 8 ! a $end\n"), "#0\nb1").as_bytes(),
        line: 7,
        says: "value `b1` has no identifier after it",
    },
    Malformed {
        name: "vector_for_event",
        vcd: concat!(hdr!("$var event 1 ! e $end\n"), "#0\nb1 !\n").as_bytes(),
        line: 7,
        says: "declared as a event",
    },
    Malformed {
        name: "unbalanced_upscope",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! a $end\n$upscope $end\n$upscope $end\n$enddefinitions $end\n#0\n1!\n",
        line: 5,
        says: "`$upscope` without an open `$scope`",
    },
    Malformed {
        name: "scope_not_closed",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! a $end\n$enddefinitions $end\n#0\n1!\n",
        line: 4,
        says: "1 scope(s) still open (`top`)",
    },
    Malformed {
        name: "empty_scope",
        vcd: b"$timescale 1 us $end\n$scope $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end\n",
        line: 2,
        says: "expected a scope type and a name",
    },
    Malformed {
        name: "unknown_scope_type",
        vcd: b"$timescale 1 us $end\n$scope modul top $end\n$upscope $end\n$enddefinitions $end\n",
        line: 2,
        says: "unknown scope type `modul`",
    },
    Malformed {
        name: "duplicate_timescale",
        vcd: concat!("$timescale 1 ns $end\n", hdr!("$var wire 1 ! a $end\n"), "#0\n1!\n").as_bytes(),
        line: 2,
        says: "second `$timescale` (the first is on line 1)",
    },
    Malformed {
        name: "duplicate_date",
        vcd: concat!("$date today $end\n$date tomorrow $end\n", hdr!("$var wire 1 ! a $end\n")).as_bytes(),
        line: 2,
        says: "second `$date`",
    },
    Malformed {
        name: "duplicate_version",
        vcd: concat!("$version a $end\n$version b $end\n", hdr!("$var wire 1 ! a $end\n")).as_bytes(),
        line: 2,
        says: "second `$version`",
    },
    Malformed {
        name: "bad_timescale_unit",
        vcd: b"$timescale 1 xs $end\n$enddefinitions $end\n",
        line: 1,
        says: "unit s, ms, us, ns, ps or fs",
    },
    Malformed {
        name: "non_utf8_var_name",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! a\xff\xfe $end\n$upscope $end\n$enddefinitions $end\n#0\n1!\n",
        line: 3,
        says: "is not valid UTF-8",
    },
    Malformed {
        name: "non_utf8_scope_name",
        vcd: b"$timescale 1 us $end\n$scope module t\xc3 $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end\n",
        line: 2,
        says: "scope name `t\u{fffd}` is not valid UTF-8",
    },
    Malformed {
        name: "name_starts_with_bracket",
        vcd: concat!(hdr!("$var wire 1 ! [0] $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "starts with `[`",
    },
    Malformed {
        name: "index_too_long",
        vcd: concat!(hdr!("$var wire 1 ! a [99999999999999999999] $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "index longer than 9 digits",
    },
    Malformed {
        name: "var_size_not_a_number",
        vcd: concat!(hdr!("$var wire x ! a $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "variable size `x` is not a whole number",
    },
    Malformed {
        name: "var_size_zero",
        vcd: concat!(hdr!("$var wire 0 ! a $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "has size 0",
    },
    Malformed {
        name: "unknown_var_type",
        vcd: concat!(hdr!("$var wir 1 ! a $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "unknown variable type `wir`",
    },
    Malformed {
        name: "var_too_few_tokens",
        vcd: concat!(hdr!("$var wire 1 ! $end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "expected type, size, identifier and name",
    },
    Malformed {
        name: "identifier_reused_with_other_width",
        vcd: concat!(hdr!("$var wire 4 ! a $end\n$var wire 8 ! b $end\n"), "#0\nb1 !\n").as_bytes(),
        line: 4,
        says: "identifier `!` of `top.b` (8-bit vector) was declared on line 3 for `top.a` as a 4-bit vector",
    },
    Malformed {
        name: "end_glued_to_name",
        vcd: concat!(hdr!("$var wire 1 ! a$end\n"), "#0\n1!\n").as_bytes(),
        line: 3,
        says: "must be separated from the text before it",
    },
    Malformed {
        name: "time_goes_backwards",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#0\n0!\n#10\n1!\n#5\n0!\n").as_bytes(),
        line: 10,
        says: "time goes backwards: #5 after #10 (line 8)",
    },
    Malformed {
        name: "bad_time",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#0\n0!\n#1e3\n1!\n").as_bytes(),
        line: 8,
        says: "time `#1e3` is not `#` followed by a whole number",
    },
    Malformed {
        name: "negative_time",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#-5\n0!\n").as_bytes(),
        line: 6,
        says: "time `#-5`",
    },
    Malformed {
        name: "unknown_body_command",
        vcd: concat!(hdr!("$var wire 1 ! a $end\n"), "#0\n$dumpvarz\n1!\n").as_bytes(),
        line: 7,
        says: "unknown command `$dumpvarz`",
    },
    Malformed {
        name: "text_after_enddefinitions",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! a $end\n$upscope $end\n$enddefinitions $end #0 1!\n#5\n0!\n",
        line: 5,
        says: "after `$enddefinitions $end` on the same line would be ignored",
    },
    Malformed {
        name: "no_enddefinitions",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var wire 1 ! a $end\n$upscope $end\n",
        line: 5,
        says: "file ends before `$enddefinitions $end`",
    },
    Malformed {
        name: "command_without_end",
        vcd: b"$timescale 1 us $end\n$scope module top\n",
        line: 2,
        says: "file ends before the `$end` of `$scope`",
    },
    Malformed {
        name: "not_a_vcd",
        vcd: b"\x89PNG\r\n\x1a\n",
        line: 1,
        says: "expected a header command",
    },
    Malformed {
        name: "attribute_extension",
        vcd: b"$attrbegin misc 07 e 2 a b 0 1 1 $end\n$enddefinitions $end\n",
        line: 1,
        says: "`$attrbegin` (a GTKWave attribute extension) is not supported",
    },
    Malformed {
        name: "non_utf8_string_value",
        vcd: b"$timescale 1 us $end\n$scope module top $end\n$var string 1 ! s $end\n$upscope $end\n$enddefinitions $end\n#0\nsab\xff !\n",
        line: 7,
        says: "string value for `top.s` is not valid UTF-8",
    },
];

/// A small valid VCD with every value kind, a real `nan`, scalars, vectors
/// shorter than their width, comments and `$dumpvars`.
pub const VALID_SAMPLE: &[u8] = b"$date today $end\n$version fuzz seed $end\n$timescale 10 ns $end\n\
$scope module top $end\n$var wire 1 ! clk $end\n$var reg 8 \" cnt [7:0] $end\n\
$scope module sub $end\n$var real 64 # v $end\n$var event 1 $ ev $end\n$var string 1 % msg $end\n\
$var integer 32 & i [31:0] $end\n$upscope $end\n$upscope $end\n$enddefinitions $end\n\
$comment seed $end\n#0\n$dumpvars\n0!\nb0 \"\nr0.5 #\nsidle %\nbx &\n$end\n#1\n1!\nb101 \"\nrnan #\n1$\n\
#2\n0!\nbz \"\nr-1e-3 #\nsbusy %\nb11111111111111111111111111111111 &\n#2\n#7\nX!\n";
