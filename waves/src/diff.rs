//! Waveform diff of two VCD files (read with `wellen` via [`crate::reader`]).
//!
//! * **Signal matching.** By default signals are matched by full path; if no
//!   path is common to both files, the top scope is stripped on both sides
//!   (`pmu50.x` ↔ `tb.x`). With [`DiffOptions::prefix_map`] (`pmu50` ↔ `tb.dut`)
//!   only signals under the mapped prefixes take part and are matched by the
//!   path below the prefix. A path that a file declares more than once (bit
//!   selects `b [0]`, `b [1]`) is keyed by its GTKWave name (`b[0]`).
//! * **Timescales** are normalised to the coarsest unit both files' ticks are
//!   integer multiples of (`1 us` vs `1000 ns` compare in `1 us`; `1 us` vs
//!   `1 ns` compare in `1 ns`). All reported times are in that unit.
//! * **Widths** are normalised by zero-extending the narrower vector; a real
//!   or string against a vector is reported as a type mismatch.
//! * **Instants.** Every time either side changes ([`Sample::Changes`]), or only
//!   at rising edges of a clock ([`Sample::RisingEdge`]) or every N ticks
//!   ([`Sample::Every`]). At an instant each side's value is its last value at
//!   or before that time (values after all changes at that time stamp). Before
//!   a signal's first value it is treated as all-x and shown as `(none)`.
//! * **x/z** follow [`XPolicy`].
//!
//! [`DiffReport::exit_code`] and [`DiffError::EXIT_CODE`] give CLI exit codes:
//! 0 = equal, 1 = differ, 2 = bad input.

use std::collections::{BTreeMap, BinaryHeap, HashMap};
use std::fmt;
use std::path::Path;

use thiserror::Error;

use crate::reader::{ReadError, ReadLimits, SignalInfo, SignalKind, Value, Waveform};
use crate::time::{TimeUnit, Timescale};

/// When signals are compared.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub enum Sample {
    /// At every time stamp where either side of a signal pair changes.
    #[default]
    Changes,
    /// At rising edges (`0`/`x`/`z` → `1`) of this one-bit clock, given as full
    /// path or GTKWave name; looked up in the left file first, then the right.
    RisingEdge(String),
    /// At 0, N, 2N, … up to the later end time, N in **left-file** ticks.
    Every(u64),
}

/// How `x` bits are compared (`z` is always compared literally).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum XPolicy {
    /// `x` only equals `x`.
    #[default]
    Strict,
    /// An `x` bit (or a missing value) on the left matches anything on the right
    /// (left = golden reference with don't-cares).
    LeftXIsWildcard,
    /// An `x` bit (or a missing value) on either side matches anything.
    EitherXIsWildcard,
}

/// Diff options; `DiffOptions::default()` compares everything strictly.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffOptions {
    /// `(left prefix, right prefix)` pairs, e.g. `("pmu50", "tb.dut")`. Empty:
    /// match by full path, falling back to top-scope-stripped paths.
    pub prefix_map: Vec<(String, String)>,
    /// Comparison instants.
    pub sample: Sample,
    /// x handling.
    pub x_policy: XPolicy,
    /// How many mismatches (earliest first) to keep in the report.
    pub max_reported: usize,
    /// Absolute tolerance for real values (0 = exact).
    pub real_tolerance: f64,
    /// If true, signals present on one side only do not make the result `Differ`.
    pub allow_unmatched: bool,
    /// Size bounds for [`diff_files`] (file bytes, declared widths).
    pub read_limits: ReadLimits,
}

impl Default for DiffOptions {
    fn default() -> Self {
        DiffOptions {
            prefix_map: Vec::new(),
            sample: Sample::Changes,
            x_policy: XPolicy::Strict,
            max_reported: 20,
            real_tolerance: 0.0,
            allow_unmatched: false,
            read_limits: ReadLimits::default(),
        }
    }
}

/// Overall result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// No mismatch, no type mismatch, (unless allowed) no unmatched signal.
    Equal,
    /// Anything else.
    Differ,
}

/// One value mismatch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// Time in [`DiffReport::time_unit`] units.
    pub time: u64,
    /// Left signal (GTKWave name).
    pub left_name: String,
    /// Right signal (GTKWave name).
    pub right_name: String,
    /// Left value (`(none)` before the first value).
    pub left: String,
    /// Right value.
    pub right: String,
}

/// A matched pair whose kinds cannot be compared (real vs vector, ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeMismatch {
    /// Left signal (GTKWave name).
    pub left_name: String,
    /// Right signal (GTKWave name).
    pub right_name: String,
    /// Left kind.
    pub left_kind: SignalKind,
    /// Right kind.
    pub right_kind: SignalKind,
}

/// Result of a diff.
#[derive(Debug, Clone, PartialEq)]
pub struct DiffReport {
    /// Equal or Differ.
    pub outcome: Outcome,
    /// Unit of all reported times (`None` if neither file has a `$timescale`).
    pub time_unit: Option<Timescale>,
    /// How signals were matched, in words.
    pub mapping: String,
    /// How instants were chosen, in words.
    pub sampling: String,
    /// Number of signal pairs compared value by value.
    pub signals_compared: usize,
    /// Left signals without partner (GTKWave names).
    pub only_in_left: Vec<String>,
    /// Right signals without partner (GTKWave names).
    pub only_in_right: Vec<String>,
    /// Pairs whose kinds differ.
    pub type_mismatches: Vec<TypeMismatch>,
    /// Total number of (instant, signal) mismatches.
    pub mismatch_count: u64,
    /// Earliest mismatch time.
    pub first_mismatch_time: Option<u64>,
    /// The earliest `max_reported` mismatches, by time then left declaration order.
    pub mismatches: Vec<Mismatch>,
}

impl DiffReport {
    /// Process exit code: 0 for [`Outcome::Equal`], 1 for [`Outcome::Differ`].
    pub fn exit_code(&self) -> u8 {
        match self.outcome {
            Outcome::Equal => 0,
            Outcome::Differ => 1,
        }
    }
}

/// Bad input: the diff could not be carried out.
#[derive(Debug, Error)]
pub enum DiffError {
    /// A file could not be read.
    #[error("cannot read {side} waveform: {source}")]
    Read {
        /// "left" or "right"
        side: &'static str,
        /// the reader error
        source: ReadError,
    },
    /// Only one file declares a timescale.
    #[error("{side} waveform {origin} has no $timescale but the other file has `{other}`: times cannot be normalised; add a $timescale to both files")]
    MissingTimescale {
        /// side without timescale
        side: &'static str,
        /// its origin
        origin: String,
        /// the other file's timescale
        other: Timescale,
    },
    /// The two timescales have no common unit within 64-bit range.
    #[error("timescales `{left}` (left) and `{right}` (right) are too far apart to compare with 64-bit times")]
    IncompatibleTimescales {
        /// left timescale
        left: Timescale,
        /// right timescale
        right: Timescale,
    },
    /// Converting to the common unit overflows 64 bits.
    #[error("{side} time {time} overflows 64 bits when converted to the common unit {unit}")]
    TimeOverflow {
        /// side
        side: &'static str,
        /// time in file units
        time: u64,
        /// the common unit
        unit: String,
    },
    /// `allow_unmatched` with no signal in common: nothing would be compared, and EQUAL would
    /// say nothing about the files.
    #[error("no signal of {left} matches one of {right} ({left_count} and {right_count} signals): nothing would be compared; check the names, or map the scopes with --map LEFT=RIGHT")]
    NothingInCommon {
        /// left origin
        left: String,
        /// right origin
        right: String,
        /// signals declared on the left
        left_count: usize,
        /// signals declared on the right
        right_count: usize,
    },
    /// A prefix of the map matches nothing.
    #[error("{side} prefix `{prefix}` matches no signal in {origin}; prefixes are dotted scope paths such as `pmu50` or `tb.dut`")]
    PrefixNotFound {
        /// side
        side: &'static str,
        /// the prefix
        prefix: String,
        /// file origin
        origin: String,
    },
    /// Sample clock not found.
    #[error("sample clock `{name}` not found in either file; give its full dotted path (e.g. `pmu50.clk`)")]
    ClockNotFound {
        /// the name
        name: String,
    },
    /// Sample clock is not one bit.
    #[error("sample clock `{name}` is a {width}-bit {kind}; a clock must be a one-bit signal")]
    ClockNotOneBit {
        /// the name
        name: String,
        /// its width
        width: u32,
        /// its kind
        kind: SignalKind,
    },
    /// `Sample::Every(0)`.
    #[error("sample period 0 is invalid: Sample::Every needs a period of at least 1 tick")]
    ZeroPeriod,
    /// Too many sample instants.
    #[error("sampling every {period} tick(s) up to {end} gives more than {limit} instants; use a larger period")]
    TooManySamples {
        /// the period (left ticks)
        period: u64,
        /// the end time (common unit)
        end: u64,
        /// the limit
        limit: u64,
    },
    /// Negative or NaN real tolerance.
    #[error("real tolerance {0} is invalid: it must be a finite number >= 0")]
    BadTolerance(f64),
}

impl DiffError {
    /// Exit code for bad input.
    pub const EXIT_CODE: u8 = 2;

    /// Process exit code for this error: always [`DiffError::EXIT_CODE`] (2,
    /// bad input), whatever was wrong.
    pub fn exit_code(&self) -> u8 {
        Self::EXIT_CODE
    }
}

/// Exit code of a diff result: 0 equal, 1 differ, 2 bad input.
pub fn exit_code(result: &Result<DiffReport, DiffError>) -> u8 {
    match result {
        Ok(r) => r.exit_code(),
        Err(e) => e.exit_code(),
    }
}

/// Diff two VCD files. Each must be a regular file of at most
/// `opts.read_limits.max_file_bytes` bytes (2 GiB by default) whose `$var`
/// sizes are at most `opts.read_limits.max_var_width` bits (65 536); a FIFO,
/// directory or device, a larger file, or a malformed VCD is a
/// [`DiffError::Read`] (exit code 2), never a result.
pub fn diff_files(
    left: impl AsRef<Path>,
    right: impl AsRef<Path>,
    opts: &DiffOptions,
) -> Result<DiffReport, DiffError> {
    let l = Waveform::open_with(left, &opts.read_limits).map_err(|source| DiffError::Read {
        side: "left",
        source,
    })?;
    let r = Waveform::open_with(right, &opts.read_limits).map_err(|source| DiffError::Read {
        side: "right",
        source,
    })?;
    diff(&l, &r, opts)
}

const MAX_SAMPLES: u64 = 100_000_000;

/// Comparison instants shared by all signal pairs.
enum Instants {
    /// every change of either side of the pair
    Changes,
    /// explicit list (clock edges)
    List(Vec<u64>),
    /// 0, step, 2·step, … (`count` instants)
    Every { step: u64, count: u64 },
}

/// Internal value: `None` = no value yet (all-x).
#[derive(Debug, Clone, PartialEq)]
enum V {
    Bits(Vec<u8>),
    Real(f64),
    Text(String),
}

impl V {
    fn show(v: Option<&V>) -> String {
        match v {
            None => "(none)".to_string(),
            Some(V::Bits(b)) => String::from_utf8_lossy(b).into_owned(),
            Some(V::Real(r)) => format!("{r}"),
            Some(V::Text(s)) => format!("{s:?}"),
        }
    }
}

/// Changes of one signal in common time units, one value per time stamp.
struct Track {
    times: Vec<u64>,
    vals: Vec<V>,
}

impl Track {
    /// Cursor-based lookup of the value at `t` (instants must be increasing).
    fn value_at(&self, t: u64, cursor: &mut usize) -> Option<&V> {
        while *cursor < self.times.len() && self.times[*cursor] <= t {
            *cursor += 1;
        }
        if *cursor == 0 {
            None
        } else {
            Some(&self.vals[*cursor - 1])
        }
    }
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Returns the common unit and the multipliers of left and right ticks, or
/// `None` if the two timescales are too far apart for 64-bit arithmetic.
fn common_unit(l: Timescale, r: Timescale) -> Option<(Timescale, u64, u64)> {
    let (el, er) = (l.unit.exponent(), r.unit.exponent());
    let base = el.min(er);
    let ml = u128::from(l.factor.max(1)) * 10u128.pow((el - base) as u32);
    let mr = u128::from(r.factor.max(1)) * 10u128.pow((er - base) as u32);
    let (ml, mr) = (u64::try_from(ml).ok()?, u64::try_from(mr).ok()?);
    let g = gcd(ml, mr);
    let (mut f, mut k) = (g, base);
    while f % 10 == 0 && k < 0 {
        f /= 10;
        k += 1;
    }
    let u = k.div_euclid(3) * 3;
    let f = f.checked_mul(10u64.pow((k - u) as u32))?;
    let unit = TimeUnit::from_exponent(u)?;
    let factor = u32::try_from(f).ok()?;
    Some((Timescale::new(factor, unit), ml / g, mr / g))
}

fn fmt_time(t: u64, unit: Option<Timescale>) -> String {
    match unit {
        None => format!("{t}"),
        Some(u) if u.factor == 1 => format!("{t} {}", u.unit),
        Some(u) => format!("{t} (x {u})"),
    }
}

/// Keys of a file's signals: path, or GTKWave name where a path repeats.
fn keys(w: &Waveform) -> Vec<String> {
    let mut count: HashMap<&str, usize> = HashMap::new();
    for s in w.signals() {
        *count.entry(s.path.as_str()).or_default() += 1;
    }
    w.signals()
        .iter()
        .map(|s| {
            if count[s.path.as_str()] > 1 {
                s.gtkwave_name()
            } else {
                s.path.clone()
            }
        })
        .collect()
}

fn under<'a>(key: &'a str, prefix: &str) -> Option<&'a str> {
    if prefix.is_empty() {
        return Some(key);
    }
    if key == prefix {
        return Some("");
    }
    key.strip_prefix(prefix)
        .and_then(|rest| rest.strip_prefix('.'))
}

fn join(prefix: &str, rest: &str) -> String {
    match (prefix.is_empty(), rest.is_empty()) {
        (true, _) => rest.to_string(),
        (false, true) => prefix.to_string(),
        (false, false) => format!("{prefix}.{rest}"),
    }
}

fn strip_top(key: &str) -> Option<&str> {
    key.split_once('.').map(|(_, rest)| rest)
}

struct Matching {
    pairs: Vec<(usize, usize)>,
    only_left: Vec<usize>,
    only_right: Vec<usize>,
    description: String,
}

/// Pair signals by equal key; `lk`/`rk` map key → index (BTreeMap for determinism).
fn pair_up(lk: &BTreeMap<String, usize>, rk: &BTreeMap<String, usize>) -> Matching {
    let mut pairs: Vec<(usize, usize)> = lk
        .iter()
        .filter_map(|(k, &li)| rk.get(k).map(|&ri| (li, ri)))
        .collect();
    pairs.sort_unstable();
    let mut only_left: Vec<usize> = lk
        .iter()
        .filter(|(k, _)| !rk.contains_key(*k))
        .map(|(_, &i)| i)
        .collect();
    let mut only_right: Vec<usize> = rk
        .iter()
        .filter(|(k, _)| !lk.contains_key(*k))
        .map(|(_, &i)| i)
        .collect();
    only_left.sort_unstable();
    only_right.sort_unstable();
    Matching {
        pairs,
        only_left,
        only_right,
        description: String::new(),
    }
}

fn unique_map<'a>(
    it: impl Iterator<Item = (Option<String>, usize)> + 'a,
) -> Option<BTreeMap<String, usize>> {
    let mut m = BTreeMap::new();
    for (k, i) in it {
        let k = k?;
        if m.insert(k, i).is_some() {
            return None;
        }
    }
    Some(m)
}

fn match_signals(
    left: &Waveform,
    right: &Waveform,
    lkeys: &[String],
    rkeys: &[String],
    map: &[(String, String)],
) -> Result<Matching, DiffError> {
    if !map.is_empty() {
        for (lp, rp) in map {
            if !lkeys.iter().any(|k| under(k, lp).is_some()) {
                return Err(DiffError::PrefixNotFound {
                    side: "left",
                    prefix: lp.clone(),
                    origin: left.origin().to_string(),
                });
            }
            if !rkeys.iter().any(|k| under(k, rp).is_some()) {
                return Err(DiffError::PrefixNotFound {
                    side: "right",
                    prefix: rp.clone(),
                    origin: right.origin().to_string(),
                });
            }
        }
        let mut lk = BTreeMap::new();
        for (i, k) in lkeys.iter().enumerate() {
            if let Some((rest, rp)) = map
                .iter()
                .find_map(|(lp, rp)| under(k, lp).map(|r| (r, rp)))
            {
                lk.entry(join(rp, rest)).or_insert(i);
            }
        }
        let mut rk = BTreeMap::new();
        for (i, k) in rkeys.iter().enumerate() {
            if map.iter().any(|(_, rp)| under(k, rp).is_some()) {
                rk.entry(k.clone()).or_insert(i);
            }
        }
        let mut m = pair_up(&lk, &rk);
        m.description = map
            .iter()
            .map(|(l, r)| format!("left `{l}` <-> right `{r}`"))
            .collect::<Vec<_>>()
            .join(", ");
        return Ok(m);
    }
    let lk: BTreeMap<String, usize> = lkeys
        .iter()
        .enumerate()
        .map(|(i, k)| (k.clone(), i))
        .collect();
    let rk: BTreeMap<String, usize> = rkeys
        .iter()
        .enumerate()
        .map(|(i, k)| (k.clone(), i))
        .collect();
    let mut m = pair_up(&lk, &rk);
    m.description = "by full path".to_string();
    if m.pairs.is_empty() && !lk.is_empty() && !rk.is_empty() {
        let ls = unique_map(
            lkeys
                .iter()
                .enumerate()
                .map(|(i, k)| (strip_top(k).map(String::from), i)),
        );
        let rs = unique_map(
            rkeys
                .iter()
                .enumerate()
                .map(|(i, k)| (strip_top(k).map(String::from), i)),
        );
        if let (Some(ls), Some(rs)) = (ls, rs) {
            let s = pair_up(&ls, &rs);
            if !s.pairs.is_empty() {
                m = s;
                m.description = "by path with the top scope stripped on both sides".to_string();
            }
        }
    }
    Ok(m)
}

fn track(
    w: &Waveform,
    i: usize,
    mult: u64,
    side: &'static str,
    unit: &str,
) -> Result<Track, DiffError> {
    let mut times: Vec<u64> = Vec::new();
    let mut vals: Vec<V> = Vec::new();
    for (t, v) in w.changes_at(i) {
        let t = t.checked_mul(mult).ok_or_else(|| DiffError::TimeOverflow {
            side,
            time: t,
            unit: unit.to_string(),
        })?;
        let v = match v {
            Value::Bits(b) => V::Bits(b.into_bytes()),
            Value::Real(r) => V::Real(r),
            Value::Text(s) => V::Text(s),
        };
        if times.last() == Some(&t) {
            if let Some(last) = vals.last_mut() {
                *last = v;
            }
        } else {
            times.push(t);
            vals.push(v);
        }
    }
    Ok(Track { times, vals })
}

fn bits_equal(a: &[u8], b: &[u8], policy: XPolicy) -> bool {
    let n = a.len().max(b.len());
    for i in 0..n {
        let ca = if i < a.len() {
            a[a.len() - 1 - i]
        } else {
            b'0'
        };
        let cb = if i < b.len() {
            b[b.len() - 1 - i]
        } else {
            b'0'
        };
        let ok = ca == cb
            || match policy {
                XPolicy::Strict => false,
                XPolicy::LeftXIsWildcard => ca == b'x',
                XPolicy::EitherXIsWildcard => ca == b'x' || cb == b'x',
            };
        if !ok {
            return false;
        }
    }
    true
}

fn values_equal(l: Option<&V>, r: Option<&V>, policy: XPolicy, tol: f64) -> bool {
    match (l, r) {
        (None, None) => true,
        (None, Some(v)) => match policy {
            XPolicy::LeftXIsWildcard | XPolicy::EitherXIsWildcard => true,
            XPolicy::Strict => matches!(v, V::Bits(b) if b.iter().all(|c| *c == b'x')),
        },
        (Some(v), None) => match policy {
            XPolicy::EitherXIsWildcard => true,
            _ => matches!(v, V::Bits(b) if b.iter().all(|c| *c == b'x')),
        },
        (Some(V::Bits(a)), Some(V::Bits(b))) => bits_equal(a, b, policy),
        // NaN equals NaN: a diff asks whether both files hold the same value.
        (Some(V::Real(a)), Some(V::Real(b))) => {
            a == b || (a.is_nan() && b.is_nan()) || (a - b).abs() <= tol
        }
        (Some(V::Text(a)), Some(V::Text(b))) => a == b,
        _ => false,
    }
}

/// Diff two loaded waveforms.
pub fn diff(
    left: &Waveform,
    right: &Waveform,
    opts: &DiffOptions,
) -> Result<DiffReport, DiffError> {
    if !opts.real_tolerance.is_finite() || opts.real_tolerance < 0.0 {
        return Err(DiffError::BadTolerance(opts.real_tolerance));
    }
    let (unit, ml, mr) = match (left.timescale(), right.timescale()) {
        (Some(l), Some(r)) => {
            let (u, ml, mr) =
                common_unit(l, r).ok_or(DiffError::IncompatibleTimescales { left: l, right: r })?;
            (Some(u), ml, mr)
        }
        (None, None) => (None, 1, 1),
        (None, Some(other)) => {
            return Err(DiffError::MissingTimescale {
                side: "left",
                origin: left.origin().into(),
                other,
            })
        }
        (Some(other), None) => {
            return Err(DiffError::MissingTimescale {
                side: "right",
                origin: right.origin().into(),
                other,
            })
        }
    };
    let unit_s = unit
        .map(|u| u.to_string())
        .unwrap_or_else(|| "file ticks".to_string());
    let lkeys = keys(left);
    let rkeys = keys(right);
    let m = match_signals(left, right, &lkeys, &rkeys, &opts.prefix_map)?;

    let end = {
        // a side's end time in the common unit
        let end_of = |w: &Waveform, m: u64, side: &'static str| {
            w.end_time().checked_mul(m).ok_or(DiffError::TimeOverflow {
                side,
                time: w.end_time(),
                unit: unit_s.clone(),
            })
        };
        end_of(left, ml, "left")?.max(end_of(right, mr, "right")?)
    };

    // Sample instants shared by all pairs.
    let (instants, sampling): (Instants, String) = match &opts.sample {
        Sample::Changes => (
            Instants::Changes,
            "at every change of either side".to_string(),
        ),
        Sample::Every(n) => {
            if *n == 0 {
                return Err(DiffError::ZeroPeriod);
            }
            let step = n.checked_mul(ml).ok_or(DiffError::TimeOverflow {
                side: "left",
                time: *n,
                unit: unit_s.clone(),
            })?;
            let count = end / step + 1;
            if count > MAX_SAMPLES {
                return Err(DiffError::TooManySamples {
                    period: *n,
                    end,
                    limit: MAX_SAMPLES,
                });
            }
            (
                Instants::Every { step, count },
                format!("every {} ({} instants)", fmt_time(step, unit), count),
            )
        }
        Sample::RisingEdge(name) => {
            let (w, i, mult, side) = match left.find(name) {
                Some(i) => (left, i, ml, "left"),
                None => match right.find(name) {
                    Some(i) => (right, i, mr, "right"),
                    None => return Err(DiffError::ClockNotFound { name: name.clone() }),
                },
            };
            let info: &SignalInfo = &w.signals()[i];
            if info.kind != SignalKind::Bits || info.width != 1 {
                return Err(DiffError::ClockNotOneBit {
                    name: name.clone(),
                    width: info.width,
                    kind: info.kind,
                });
            }
            let tr = track(w, i, mult, side, &unit_s)?;
            let mut edges = Vec::new();
            let mut prev: Option<&V> = None;
            for (t, v) in tr.times.iter().zip(tr.vals.iter()) {
                let is_one = matches!(v, V::Bits(b) if b.as_slice() == b"1");
                let was_one = matches!(prev, Some(V::Bits(b)) if b.as_slice() == b"1");
                if is_one && prev.is_some() && !was_one {
                    edges.push(*t);
                }
                prev = Some(v);
            }
            let s = format!(
                "at {} rising edges of {side} `{}`",
                edges.len(),
                info.gtkwave_name()
            );
            (Instants::List(edges), s)
        }
    };

    let mut type_mismatches = Vec::new();
    let mut compared = 0usize;
    let mut count = 0u64;
    let mut first: Option<u64> = None;
    // max-heap of the earliest `max_reported` mismatches
    let mut heap: BinaryHeap<(u64, usize, String, String)> = BinaryHeap::new();

    for (pi, &(li, ri)) in m.pairs.iter().enumerate() {
        let (ls, rs) = (&left.signals()[li], &right.signals()[ri]);
        if ls.kind != rs.kind {
            type_mismatches.push(TypeMismatch {
                left_name: ls.gtkwave_name(),
                right_name: rs.gtkwave_name(),
                left_kind: ls.kind,
                right_kind: rs.kind,
            });
            continue;
        }
        compared += 1;
        let tl = track(left, li, ml, "left", &unit_s)?;
        let tr = track(right, ri, mr, "right", &unit_s)?;
        let mut record = |t: u64, l: Option<&V>, r: Option<&V>| {
            if values_equal(l, r, opts.x_policy, opts.real_tolerance) {
                return;
            }
            count += 1;
            first = Some(first.map_or(t, |f| f.min(t)));
            if opts.max_reported == 0 {
                return;
            }
            let key = (t, pi);
            let worse = heap.len() >= opts.max_reported
                && heap.peek().is_some_and(|top| (top.0, top.1) < key);
            if !worse {
                heap.push((t, pi, V::show(l), V::show(r)));
                if heap.len() > opts.max_reported {
                    heap.pop();
                }
            }
        };
        let (mut cl, mut cr) = (0usize, 0usize);
        match &instants {
            Instants::List(ts) => {
                for &t in ts {
                    let l = tl.value_at(t, &mut cl);
                    let r = tr.value_at(t, &mut cr);
                    record(t, l, r);
                }
            }
            Instants::Every { step, count } => {
                for k in 0..*count {
                    let t = k * step;
                    let l = tl.value_at(t, &mut cl);
                    let r = tr.value_at(t, &mut cr);
                    record(t, l, r);
                }
            }
            Instants::Changes => {
                let (mut i, mut j) = (0usize, 0usize);
                while i < tl.times.len() || j < tr.times.len() {
                    let t = match (tl.times.get(i), tr.times.get(j)) {
                        (Some(&a), Some(&b)) => a.min(b),
                        (Some(&a), None) => a,
                        (None, Some(&b)) => b,
                        (None, None) => break,
                    };
                    while i < tl.times.len() && tl.times[i] <= t {
                        i += 1;
                    }
                    while j < tr.times.len() && tr.times[j] <= t {
                        j += 1;
                    }
                    let l = tl.value_at(t, &mut cl);
                    let r = tr.value_at(t, &mut cr);
                    record(t, l, r);
                }
            }
        }
    }

    let mut kept = heap.into_sorted_vec();
    kept.truncate(opts.max_reported);
    let mismatches = kept
        .into_iter()
        .map(|(time, pi, l, r)| {
            let (li, ri) = m.pairs[pi];
            Mismatch {
                time,
                left_name: left.signals()[li].gtkwave_name(),
                right_name: right.signals()[ri].gtkwave_name(),
                left: l,
                right: r,
            }
        })
        .collect();
    let only_in_left: Vec<String> = m
        .only_left
        .iter()
        .map(|&i| left.signals()[i].gtkwave_name())
        .collect();
    let only_in_right: Vec<String> = m
        .only_right
        .iter()
        .map(|&i| right.signals()[i].gtkwave_name())
        .collect();
    let unmatched = !only_in_left.is_empty() || !only_in_right.is_empty();
    if opts.allow_unmatched && unmatched && compared == 0 && type_mismatches.is_empty() {
        return Err(DiffError::NothingInCommon {
            left: left.origin().to_string(),
            right: right.origin().to_string(),
            left_count: left.signals().len(),
            right_count: right.signals().len(),
        });
    }
    let outcome =
        if count > 0 || !type_mismatches.is_empty() || (unmatched && !opts.allow_unmatched) {
            Outcome::Differ
        } else {
            Outcome::Equal
        };
    Ok(DiffReport {
        outcome,
        time_unit: unit,
        mapping: m.description,
        sampling,
        signals_compared: compared,
        only_in_left,
        only_in_right,
        type_mismatches,
        mismatch_count: count,
        first_mismatch_time: first,
        mismatches,
    })
}

impl fmt::Display for DiffReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = match self.outcome {
            Outcome::Equal => "EQUAL",
            Outcome::Differ => "DIFFER",
        };
        writeln!(f, "waveform diff: {verdict}")?;
        let unit = self
            .time_unit
            .map(|u| u.to_string())
            .unwrap_or_else(|| "file ticks".into());
        writeln!(
            f,
            "  time unit: {unit}; matching: {}; compared {}",
            self.mapping, self.sampling
        )?;
        writeln!(
            f,
            "  signals compared: {}; only in left: {}; only in right: {}; type mismatches: {}",
            self.signals_compared,
            self.only_in_left.len(),
            self.only_in_right.len(),
            self.type_mismatches.len()
        )?;
        match self.first_mismatch_time {
            Some(t) => writeln!(
                f,
                "  value mismatches: {} (first at {})",
                self.mismatch_count,
                fmt_time(t, self.time_unit)
            )?,
            None => writeln!(f, "  value mismatches: 0")?,
        }
        if !self.mismatches.is_empty() {
            writeln!(f, "  first {} mismatch(es):", self.mismatches.len())?;
            for m in &self.mismatches {
                let names = if m.left_name == m.right_name {
                    m.left_name.clone()
                } else {
                    format!("{} <-> {}", m.left_name, m.right_name)
                };
                writeln!(
                    f,
                    "    t={}  {}: left={} right={}",
                    fmt_time(m.time, self.time_unit),
                    names,
                    m.left,
                    m.right
                )?;
            }
        }
        for t in &self.type_mismatches {
            writeln!(
                f,
                "  type mismatch: {} ({}) <-> {} ({})",
                t.left_name, t.left_kind, t.right_name, t.right_kind
            )?;
        }
        for n in &self.only_in_left {
            writeln!(f, "  only in left: {n}")?;
        }
        for n in &self.only_in_right {
            writeln!(f, "  only in right: {n}")?;
        }
        Ok(())
    }
}
