//! FST output: the same calls give an FST that wellen reads back exactly like the VCD (every
//! signal's path, range, width, kind and every value change), with frames, single changes, x/z
//! bits, reals, windows and timescales of 10 and 100 units; and the checks hold for FST too.
//! A windowed FST starts at the window start (header and first block), so `pmu50 diff` of the
//! windowed VCD against the windowed FST of the same calls is EQUAL, and different windows or
//! values are still told apart.

use pmu50_waves::diff::{diff, DiffOptions, Outcome};
use pmu50_waves::fst::start_fst;
use pmu50_waves::reader::Waveform;
use pmu50_waves::writer::{BitType, Logic, SigId, VcdBuilder, WriteError};
use pmu50_waves::{TimeUnit, Timescale};
use std::path::PathBuf;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50_waves_fst_{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

struct Ids {
    a: SigId,
    tmr: SigId,
    sel: SigId,
    wide: SigId,
    r: SigId,
}

fn builder(ts: Timescale, window: Option<(u64, u64)>) -> (VcdBuilder, Ids) {
    let mut b = VcdBuilder::new(ts, "pmu50-waves fst test").unwrap();
    if let Some((s, e)) = window {
        b.window(s, e).unwrap();
    }
    b.push_scope("pmu50").unwrap();
    let a = b.add_bit(BitType::Wire, "a", Logic::X).unwrap();
    b.push_scope("timing_generator").unwrap();
    let tmr = b.add_vector(BitType::Reg, "tmr", 15, 0, 0).unwrap();
    let sel = b.add_vector(BitType::Wire, "sel", 3, 3, 0).unwrap();
    b.pop_scope().unwrap();
    let wide = b.add_vector(BitType::Wire, "wide", 69, 0, 0).unwrap();
    b.pop_scope().unwrap();
    b.push_scope("env").unwrap();
    let r = b.add_real("theta_deg", 0.0).unwrap();
    b.pop_scope().unwrap();
    (
        b,
        Ids {
            a,
            tmr,
            sel,
            wide,
            r,
        },
    )
}

/// The same sequence of calls on any checked writer.
macro_rules! drive {
    ($w:expr, $ids:expr) => {{
        let w = &mut $w;
        let ids = &$ids;
        let mut f = w.frame(&[ids.tmr, ids.sel]).unwrap();
        for k in 0..300u64 {
            let t = k * 3;
            w.dump_frame(&mut f, t, &[k % 37, (k / 50) & 1]).unwrap();
            if k % 7 == 0 {
                w.change_bool(ids.a, k % 14 == 0).unwrap();
            }
            if k == 98 {
                w.change_bit(ids.a, Logic::Z).unwrap_err(); // already assigned at this time
            }
            if k == 99 {
                w.change_bit(ids.a, Logic::Z).unwrap();
            }
            if k % 40 == 1 {
                w.change_bits(ids.wide, &format!("1x{}", "01".repeat(34)))
                    .unwrap();
            }
            if k % 40 == 21 {
                w.change_vector(ids.wide, k << 40).unwrap();
            }
            w.change_real(ids.r, (k as f64 * 0.37).sin() * 180.0)
                .unwrap();
        }
        w.set_time(1000).unwrap();
    }};
}

fn same_content(vcd: &Waveform, fst: &Waveform) {
    assert_eq!(
        vcd.timescale()
            .map(|t| t.unit.exponent() + (t.factor as f64).log10() as i32),
        fst.timescale()
            .map(|t| t.unit.exponent() + (t.factor as f64).log10() as i32)
    );
    assert_eq!(vcd.signals().len(), fst.signals().len());
    let mut n = 0;
    for (i, s) in vcd.signals().iter().enumerate() {
        let j = fst
            .find(&s.gtkwave_name())
            .unwrap_or_else(|| panic!("{} not in the FST", s.gtkwave_name()));
        let t = &fst.signals()[j];
        assert_eq!(
            (&s.path, s.index, s.width, &s.kind),
            (&t.path, t.index, t.width, &t.kind),
            "{}",
            s.path
        );
        let scale = |w: &Waveform| w.timescale().map_or(1, |t| u64::from(t.factor));
        let a: Vec<_> = vcd
            .changes_at(i)
            .into_iter()
            .map(|(t, v)| (t * scale(vcd), v))
            .collect();
        let b: Vec<_> = fst
            .changes_at(j)
            .into_iter()
            .map(|(t, v)| (t * scale(fst), v))
            .collect();
        assert_eq!(a, b, "{}", s.path);
        n += a.len();
    }
    assert!(n > 400, "only {n} changes compared");
}

#[test]
fn fst_reads_back_like_the_vcd() {
    for (ts, window) in [
        (Timescale::new(1, TimeUnit::Us), None),
        (Timescale::new(10, TimeUnit::Ns), None),
        (Timescale::new(100, TimeUnit::Ns), Some((50, 700))),
    ] {
        let (b, ids) = builder(ts, window);
        let mut v = b.start(Vec::new()).unwrap();
        drive!(v, ids);
        let vcd = Waveform::from_bytes(v.finish().unwrap()).unwrap();
        let (b, ids) = builder(ts, window);
        let path = tmp(&format!("t{}_{}.fst", ts.factor, window.is_some()));
        let mut f = start_fst(b, &path).unwrap();
        drive!(f, ids);
        f.finish().unwrap();
        let fst = Waveform::open(&path).unwrap();
        same_content(&vcd, &fst);
        let d = diff(&vcd, &fst, &DiffOptions::default()).unwrap();
        assert_eq!(d.outcome, Outcome::Equal, "{window:?}: {d}");
        std::fs::remove_file(&path).unwrap();
    }
}

#[test]
fn fst_keeps_the_checks() {
    let (b, ids) = builder(Timescale::new(1, TimeUnit::Us), None);
    let path = tmp("checks.fst");
    let mut w = start_fst(b, &path).unwrap();
    w.set_time(5).unwrap();
    assert!(matches!(
        w.set_time(4),
        Err(WriteError::TimeBackwards { .. })
    ));
    w.change_vector(ids.tmr, 3).unwrap();
    assert!(matches!(
        w.change_vector(ids.tmr, 4),
        Err(WriteError::DoubleChange { .. })
    ));
    assert!(matches!(
        w.change_vector(ids.sel, 2),
        Err(WriteError::ValueTooWide { .. })
    ));
    assert!(matches!(
        w.change_real(ids.r, f64::NAN),
        Err(WriteError::NotFinite { .. })
    ));
    assert!(matches!(
        w.change_real(ids.a, 1.0),
        Err(WriteError::TypeMismatch { .. })
    ));
    w.finish().unwrap();
    std::fs::remove_file(&path).unwrap();
    // Declarations are checked before the file is created.
    let mut b = VcdBuilder::new(Timescale::new(1, TimeUnit::Us), "t").unwrap();
    b.push_scope("m").unwrap();
    let p2 = tmp("unclosed.fst");
    assert!(matches!(
        start_fst(b, &p2),
        Err(WriteError::UnclosedScopes { .. })
    ));
    assert!(!p2.exists());
}

fn vcd_of(ts: Timescale, window: Option<(u64, u64)>) -> Waveform {
    let (b, ids) = builder(ts, window);
    let mut v = b.start(Vec::new()).unwrap();
    drive!(v, ids);
    Waveform::from_bytes(v.finish().unwrap()).unwrap()
}

/// Writes the FST of `drive!` (plus, if `extra`, a change of `tmr` at its last time, 1000) and returns its bytes and its reading.
fn fst_of(
    name: &str,
    ts: Timescale,
    window: Option<(u64, u64)>,
    extra: bool,
) -> (Vec<u8>, Waveform) {
    let (b, ids) = builder(ts, window);
    let path = tmp(name);
    let mut f = start_fst(b, &path).unwrap();
    drive!(f, ids);
    if extra {
        f.change_vector(ids.tmr, 40).unwrap(); // drive! writes tmr values 0..37 only
    }
    f.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let w = Waveform::open(&path).unwrap();
    std::fs::remove_file(&path).unwrap();
    (bytes, w)
}

fn be64(b: &[u8], at: usize) -> u64 {
    u64::from_be_bytes(b[at..at + 8].try_into().unwrap())
}

/// Regression (`pmu50 run --window A..B` in VCD and in FST said DIFFER): fst-writer wrote the
/// window start into the header's time-zero field and left the start times 0, so wellen gave the
/// window-start frame at time 0 while the VCD starts at the window start.
#[test]
fn windowed_fst_starts_at_the_window_and_diffs_equal_to_the_vcd() {
    let ts = Timescale::new(1, TimeUnit::Us);
    let window = Some((50, 700));
    let vcd = vcd_of(ts, window);
    let (bytes, fst) = fst_of("window.fst", ts, window, false);
    // FST header block: type 0, length 329, start time, end time, ..., time zero last.
    assert_eq!((bytes[0], be64(&bytes, 1)), (0, 329));
    assert_eq!(be64(&bytes, 9), 50, "header start time");
    assert_eq!(be64(&bytes, 17), vcd.end_time(), "header end time");
    assert!(vcd.end_time() > 600);
    assert_eq!(
        be64(&bytes, 1 + 329 - 8),
        0,
        "time zero (an offset viewers add to every time)"
    );
    // every signal's first value is at the window start, as in the VCD
    for (i, s) in fst.signals().iter().enumerate() {
        assert_eq!(
            fst.changes_at(i).first().map(|c| c.0),
            Some(50),
            "{}",
            s.path
        );
    }
    for (l, r) in [(&vcd, &fst), (&fst, &vcd)] {
        let d = diff(l, r, &DiffOptions::default()).unwrap();
        assert_eq!(d.outcome, Outcome::Equal, "{d}");
        assert_eq!(d.signals_compared, 5);
    }
    // genuinely different files still differ: another window, the whole run, one more change
    let (_, later) = fst_of("later.fst", ts, Some((51, 700)), false);
    let d = diff(&vcd, &later, &DiffOptions::default()).unwrap();
    assert_eq!(
        (d.outcome, d.first_mismatch_time),
        (Outcome::Differ, Some(50)),
        "{d}"
    );
    let (_, whole) = fst_of("whole.fst", ts, None, false);
    let d = diff(&vcd, &whole, &DiffOptions::default()).unwrap();
    assert_eq!(
        (d.outcome, d.first_mismatch_time),
        (Outcome::Differ, Some(0)),
        "{d}"
    );
    // without a window the file starts at 0 and equals its VCD, and one more change differs
    let unwindowed = vcd_of(ts, None);
    let d = diff(&unwindowed, &whole, &DiffOptions::default()).unwrap();
    assert_eq!(d.outcome, Outcome::Equal, "{d}");
    let (_, extra) = fst_of("extra.fst", ts, None, true);
    let d = diff(&unwindowed, &extra, &DiffOptions::default()).unwrap();
    assert_eq!(
        (d.outcome, d.mismatch_count, d.first_mismatch_time),
        (Outcome::Differ, 1, Some(1000)),
        "{d}"
    );
}
