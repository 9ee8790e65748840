//! Scenario files (TOML): configuration overrides, environment, timeline, expectations.
//!
//! Format (every duration is a string with a unit: `"2.2 ms"`, `"220 us"`, `"1 s"`):
//!
//! ```toml
//! name = "fig15a"                  # optional, default: file stem
//! description = "..."
//! duration = "60 ms"               # run length
//!
//! [core]                           # overrides of the core configuration (docs/spec.md)
//! clock = "10 us"
//! x = "6.6 ms"                     # also: min t1 t2 pw pi ps smp_on cth adaptive sync_depth cnt_width
//!
//! [env]                            # environment models (floats allowed here)
//! vcc1_v = 5.0
//! vcc2_v = 3.3
//! mpu_boot = "1 ms"                # key-on to the MPU's read-out
//! theta_t_deg = 0.0                # torsion angle θt for θi = θm·Rg + θt ([0116])
//! [env.sensor2]                    # gain_s gain_c offset_s_v offset_c_v phase_s_deg phase_c_deg tau_us
//! [env.comparator]                 # vr_err_s vr_err_c (fraction of the amplitude Vs2/2)
//! [env.sensor1]                    # resolution_deg error_deg
//! [env.readout]                    # gear_ratio diag_threshold_deg count_diff_threshold
//! [env.dark_current]               # i_vm_ma i_vs1_ma i_vs2_ma i_vp_ua i_q_ua
//!
//! [motor]
//! start_deg = 45.0
//! segments = [
//!   { kind = "hold", duration = "10 ms" },
//!   { kind = "move", duration = "20 ms", delta_deg = 90.0 },
//! ]
//!
//! [[events]]                       # in time order; exactly one action each
//! at = "0 ms"
//! ig = true                        # or: write = { reg = "T2", value = 110 }  or: vs2_fault = true
//!                                  # or: read = 0xE0 (the MPU reads any 8-bit bus address this
//!                                  # tick instead of its polling; the key must be on)
//!                                  # or: bus_write = { addr = 0x10, data = 0x0100 } (a raw bus
//!                                  # cycle: any address, any 16-bit word; the register file
//!                                  # refuses or takes it; the key must be on)
//!                                  # or: vs2_pg_leak = true (Vs2's power-good reads high while
//!                                  # the rail is off; with the rail on it follows the rail)
//!
//! [expect]                         # checks; `pmu50 run` exits 1 when one fails
//! si_sequence_ms = [6.6, 4.4, 2.2] # successive distinct drive intervals at key-off pulses
//! readout_within_deg = 0.1         # every key-on read-out within this of the true angle
//! diag = false                     # diag at the end of the run
//! quadrant_skip = false            # quadrant_skip at the end of the run
//!
//! [vcd]
//! window = ["10 ms", "60 ms"]      # dump only this time window
//! trace = "all"                    # "ports", "registers", "all", or "none" (summary only; days of
//!                                  # parking, docs/spec.md 5.1); absent: chosen from the run's length
//! ```
//!
//! Every error names the file, the line and the field, and says what is valid.

use pmu50_core::register_file::MAP;
use pmu50_core::{CoreConfig, Dur, Params};
use pmu50_env::{
    ComparatorConfig, ComparatorPair, DarkCurrentConfig, DarkCurrentMeter, MotorProfile, Readout,
    ReadoutConfig, Segment, Sensor1, Sensor1Config, Sensor2, Sensor2Config,
};
use serde::Deserialize;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Which signals a waveform holds (`pmu50 run --trace`, `[vcd] trace`): each level is the one
/// below plus more signals, in the same scopes under the same names.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Level {
    /// The core's ports (inputs and outputs, scope `pmu50`) and the analog `env` reals.
    Ports,
    /// `ports` and every register (`pmu50.<block>`), the free-running timer `tmr` among them.
    Registers,
    /// `registers` and the combinational internals (`pmu50.internals`).
    #[default]
    All,
}

impl Level {
    /// The word of the CLI and the scenario (`ports`, `registers`, `all`).
    pub fn name(self) -> &'static str {
        match self {
            Level::Ports => "ports",
            Level::Registers => "registers",
            Level::All => "all",
        }
    }

    /// Whether the level holds the registers.
    pub fn registers(self) -> bool {
        self >= Level::Registers
    }

    /// Whether the level holds the internals.
    pub fn internals(self) -> bool {
        self == Level::All
    }
}

/// Largest scenario file accepted (1 MiB; the shipped ones are under 4 kB).
pub const MAX_SCENARIO_BYTES: u64 = 1 << 20;

#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error("{file}: cannot read the scenario: {source}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: is {kind}, not a regular file; a scenario is a TOML file")]
    NotAFile { file: String, kind: &'static str },
    #[error("{file}: {size} bytes is larger than a scenario can be ({max} bytes at most)")]
    TooLarge { file: String, size: u64, max: u64 },
    #[error("{file}:{line}:{col}: {msg}")]
    Syntax {
        file: String,
        line: usize,
        col: usize,
        msg: String,
    },
    #[error("{file}:{line}: `{field}`: {msg}")]
    Invalid {
        file: String,
        line: usize,
        field: String,
        msg: String,
    },
    /// A value the core's or an environment model's own validation refused.
    #[error("{file}:{line}: `{field}`: {source}")]
    Model {
        file: String,
        line: usize,
        field: String,
        #[source]
        source: ModelError,
    },
}

/// The typed error of the model that refused a scenario value.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    #[error(transparent)]
    Duration(#[from] pmu50_core::config::DurParseError),
    #[error(transparent)]
    Core(#[from] pmu50_core::ConfigError),
    #[error(transparent)]
    Env(#[from] pmu50_env::EnvError),
    #[error(transparent)]
    Motor(#[from] pmu50_env::MotorError),
}

// ---------------------------------------------------------------- raw (as written) ----

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    name: Option<Spanned<String>>,
    description: Option<String>,
    duration: Spanned<String>,
    #[serde(default)]
    core: RawCore,
    #[serde(default)]
    env: RawEnv,
    motor: Option<Spanned<RawMotor>>,
    #[serde(default)]
    events: Vec<Spanned<RawEvent>>,
    #[serde(default)]
    expect: Option<Spanned<RawExpect>>,
    #[serde(default)]
    vcd: RawVcd,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawCore {
    clock: Option<Spanned<String>>,
    sync_depth: Option<Spanned<i64>>,
    cnt_width: Option<Spanned<i64>>,
    adaptive: Option<Spanned<bool>>,
    pw: Option<Spanned<String>>,
    pi: Option<Spanned<String>>,
    ps: Option<Spanned<String>>,
    x: Option<Spanned<String>>,
    min: Option<Spanned<String>>,
    t1: Option<Spanned<String>>,
    t2: Option<Spanned<String>>,
    cth: Option<Spanned<i64>>,
    smp_on: Option<Spanned<String>>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawEnv {
    vcc1_v: Option<Spanned<f64>>,
    vcc2_v: Option<Spanned<f64>>,
    mpu_boot: Option<Spanned<String>>,
    theta_t_deg: Option<Spanned<f64>>,
    sensor2: Option<Spanned<Sensor2Config>>,
    comparator: Option<Spanned<ComparatorConfig>>,
    sensor1: Option<Spanned<Sensor1Config>>,
    readout: Option<Spanned<ReadoutConfig>>,
    dark_current: Option<Spanned<DarkCurrentConfig>>,
}

/// serde's words for a wrong type, in the scenario's terms (no Rust type or struct names).
fn humanize(msg: &str) -> String {
    if msg.contains("expected struct ") {
        // `core = []`, `env = 3`, ...: serde names the Rust struct.
        let got = msg.split(',').next().unwrap_or(msg).trim();
        let got = got
            .strip_prefix("invalid type: ")
            .or_else(|| got.strip_prefix("invalid length ").map(|_| "an array"))
            .unwrap_or(got);
        return format!("expected a table (a `[section]` of `key = value` lines, or `{{ key = value, ... }}`), got {got}");
    }
    let mut m = msg.to_string();
    for (rust, words) in [
        ("expected u8", "expected a whole number from 0 to 255"),
        ("expected u16", "expected a whole number from 0 to 65535"),
        (
            "expected u32",
            "expected a whole number from 0 to 4294967295",
        ),
        ("expected i64", "expected a whole number"),
        ("expected f64", "expected a number"),
        ("expected a sequence", "expected an array `[...]`"),
        ("expected a boolean", "expected true or false"),
    ] {
        m = m.replace(rust, words);
    }
    m
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMotor {
    #[serde(default)]
    start_deg: f64,
    #[serde(default)]
    segments: Vec<Spanned<RawSegment>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSegment {
    kind: Spanned<String>,
    duration: Spanned<String>,
    delta_deg: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEvent {
    at: Spanned<String>,
    ig: Option<bool>,
    write: Option<Spanned<RawWrite>>,
    read: Option<Spanned<i64>>,
    vs2_fault: Option<bool>,
    bus_write: Option<Spanned<RawBusWrite>>,
    vs2_pg_leak: Option<bool>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBusWrite {
    addr: Spanned<i64>,
    data: Spanned<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWrite {
    reg: Spanned<String>,
    value: Spanned<i64>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawExpect {
    si_sequence_ms: Option<Vec<f64>>,
    readout_within_deg: Option<f64>,
    diag: Option<bool>,
    quadrant_skip: Option<bool>,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawVcd {
    window: Option<Spanned<Vec<Spanned<String>>>>,
    trace: Option<Spanned<String>>,
}

/// The integer fields of `[core]`: name, legal range, and what they count (for messages). The
/// Python binding checks its keyword arguments with the same table and words.
pub const CORE_INTS: [(&str, &str); 3] = [
    ("cth", "a whole number of quiet pulses"),
    ("sync_depth", "a whole number of flip-flops"),
    ("cnt_width", "a whole number of bits"),
];

/// The range of an integer field of `[core]`: the core's legality table
/// ([`pmu50_core::params::LEGAL`]), written once there.
fn core_int_range(field: &str) -> Option<(i64, i64)> {
    pmu50_core::params::LEGAL
        .iter()
        .find(|l| l.field == field)
        .and_then(|l| match l.rule {
            pmu50_core::params::Rule::Range { min, max } => Some((min as i64, max as i64)),
            _ => None,
        })
}

/// The message for the integer field `field` of `[core]` ([`CORE_INTS`]) when `value` (shown as
/// `shown`) is out of its range; `None` when it is in range or the field is not an integer field.
pub fn core_int_out_of_range(field: &str, shown: &str, value: i64) -> Option<String> {
    let &(_, what) = CORE_INTS.iter().find(|f| f.0 == field)?;
    let (lo, hi) = core_int_range(field)?;
    (value < lo || value > hi)
        .then(|| format!("{shown} is out of range; valid is {what} from {lo} to {hi}"))
}

// ---------------------------------------------------------------- checked ----

/// One action of the timeline.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// The ignition key signal changes level.
    Ig(bool),
    /// The MPU writes a register (the key must be on).
    Write { addr: u8, name: String, value: u16 },
    /// Fault injection: the Vs2 rail does not come up (power-good stays low) while true.
    Vs2Fault(bool),
    /// Fault injection: Vs2's power-good reads high while the rail is off (a leaking or stuck
    /// power-good), while true; with the rail on it follows the rail. Sr must stay 0
    /// ([0209], docs/spec.md 2.3).
    Vs2PgLeak(bool),
    /// The MPU reads a bus address (any of the 8-bit `bus_addr`, mapped or not) in this tick
    /// instead of its polling; the key must be on.
    Read { addr: u8 },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Event {
    pub tick: u64,
    pub action: Action,
    /// Line of the event's `at` in the scenario file (for messages).
    pub line: usize,
}

/// Checks a run must pass.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Expect {
    pub si_sequence_ms: Option<Vec<f64>>,
    pub readout_within_deg: Option<f64>,
    pub diag: Option<bool>,
    pub quadrant_skip: Option<bool>,
}

/// Environment of a run.
#[derive(Clone, Debug)]
pub struct EnvSpec {
    pub vcc1_v: f64,
    pub vcc2_v: f64,
    pub mpu_boot_ticks: u64,
    /// Torsion angle θt of the torsion bar ([0112], [0116]), constant during the run.
    pub theta_t_deg: f64,
    pub sensor2: Sensor2Config,
    pub comparator: ComparatorConfig,
    pub sensor1: Sensor1Config,
    pub readout: ReadoutConfig,
    pub dark_current: DarkCurrentConfig,
}

/// A validated scenario.
#[derive(Clone, Debug)]
pub struct Scenario {
    pub name: String,
    pub description: String,
    pub path: PathBuf,
    pub core: CoreConfig,
    pub params: Params,
    pub env: EnvSpec,
    pub motor: MotorProfile,
    pub events: Vec<Event>,
    pub ticks: u64,
    pub expect: Expect,
    /// VCD dump window in ticks, [start, end).
    pub vcd_window: Option<(u64, u64)>,
    /// What `pmu50 run` writes of the run besides its summary (`[vcd] trace`); `None` when the
    /// scenario does not say, and the level is chosen from the run's length
    /// (`pmu50::output::choose_trace`).
    pub trace: Option<Trace>,
}

/// What `pmu50 run` writes of a run besides its summary. `ports`, `registers` and `all` write the
/// waveform with the signals of that level ([`Level`]), its GTKWave save file and, on request,
/// the change log and the timing diagram; `none` only the summary, for days of parking, where a
/// waveform of every tick cannot be written and the bench skips repeated key-off periods instead
/// of stepping them (docs/spec.md 5.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Trace {
    None,
    Wave(Level),
}

/// The words of `--trace` and `[vcd] trace`, in the order of the messages.
pub const TRACE_WORDS: [&str; 4] = ["ports", "registers", "all", "none"];

/// What each word writes (for messages listing the valid words).
pub const TRACE_VALID: &str = "\"ports\" (the core's inputs and outputs and the analog env values), \"registers\" (ports and every register), \"all\" (registers and the internals) and \"none\" (the summary only)";

impl Trace {
    /// Every level, as the VCD of every signal: the default of a short run.
    pub const ALL: Trace = Trace::Wave(Level::All);

    /// The level named `text` (one of [`TRACE_WORDS`]).
    pub fn parse(text: &str) -> Option<Trace> {
        match text {
            "ports" => Some(Trace::Wave(Level::Ports)),
            "registers" => Some(Trace::Wave(Level::Registers)),
            "all" => Some(Trace::ALL),
            "none" => Some(Trace::None),
            _ => None,
        }
    }

    /// Its word.
    pub fn name(self) -> &'static str {
        match self {
            Trace::None => "none",
            Trace::Wave(l) => l.name(),
        }
    }

    /// The signals of the waveform, or `None` when no waveform is written.
    pub fn level(self) -> Option<Level> {
        match self {
            Trace::None => None,
            Trace::Wave(l) => Some(l),
        }
    }
}

impl Scenario {
    pub fn clock_ns(&self) -> u64 {
        self.core.clock.0
    }

    /// Read and validate a scenario file. FIFOs, devices, sockets and folders are refused before
    /// they are opened (opening a FIFO would block), and so are files over [`MAX_SCENARIO_BYTES`].
    pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
        use std::io::Read;
        use std::os::unix::fs::FileTypeExt;
        let file = path.display().to_string();
        let io = |source| ScenarioError::Io {
            file: file.clone(),
            source,
        };
        let meta = std::fs::metadata(path).map_err(io)?;
        let ft = meta.file_type();
        if !ft.is_file() {
            let kind = if ft.is_dir() {
                "a folder"
            } else if ft.is_fifo() {
                "a FIFO (named pipe)"
            } else if ft.is_socket() {
                "a socket"
            } else if ft.is_char_device() || ft.is_block_device() {
                "a device"
            } else {
                "not a regular file"
            };
            return Err(ScenarioError::NotAFile { file, kind });
        }
        if meta.len() > MAX_SCENARIO_BYTES {
            return Err(ScenarioError::TooLarge {
                file,
                size: meta.len(),
                max: MAX_SCENARIO_BYTES,
            });
        }
        let mut src = String::new();
        // Read at most one byte past the limit: the file may have grown since `metadata`.
        let f = std::fs::File::open(path).map_err(io)?;
        f.take(MAX_SCENARIO_BYTES + 1)
            .read_to_string(&mut src)
            .map_err(io)?;
        if src.len() as u64 > MAX_SCENARIO_BYTES {
            return Err(ScenarioError::TooLarge {
                file,
                size: src.len() as u64,
                max: MAX_SCENARIO_BYTES,
            });
        }
        let stem = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        Scenario::parse(&src, &file, &stem, path)
    }

    /// Validate scenario text; `file` is used in messages, `stem` is the default name.
    pub fn parse(
        src: &str,
        file: &str,
        stem: &str,
        path: &Path,
    ) -> Result<Scenario, ScenarioError> {
        let cx = Cx { src, file };
        let raw: Raw = toml::from_str(src).map_err(|e| {
            let (line, col) = e.span().map(|s| cx.line_col(s.start)).unwrap_or((1, 1));
            ScenarioError::Syntax {
                file: file.to_string(),
                line,
                col,
                msg: humanize(e.message().trim()),
            }
        })?;
        cx.build(raw, stem, path)
    }
}

struct Cx<'a> {
    src: &'a str,
    file: &'a str,
}

impl Cx<'_> {
    fn line_col(&self, offset: usize) -> (usize, usize) {
        let before = &self.src[..offset.min(self.src.len())];
        let line = before.matches('\n').count() + 1;
        let col = before.len() - before.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
        (line, col)
    }

    fn err(&self, span: Range<usize>, field: &str, msg: impl Into<String>) -> ScenarioError {
        ScenarioError::Invalid {
            file: self.file.to_string(),
            line: self.line_col(span.start).0,
            field: field.to_string(),
            msg: msg.into(),
        }
    }

    /// Offset of `field = ` inside the table that starts at `from` (up to the next `[` header),
    /// to place an error about one field of a table on its own line.
    fn field_offset(&self, from: usize, field: &str) -> Option<usize> {
        let from = from.min(self.src.len());
        let rest = &self.src[from..];
        let end = rest[1.min(rest.len())..]
            .find("\n[")
            .map_or(rest.len(), |i| i + 1);
        let body = &rest[..end];
        let mut at = 0;
        while let Some(i) = body[at..].find(field) {
            let k = at + i;
            let before = body[..k].chars().next_back();
            let after = body[k + field.len()..].trim_start();
            if before.is_none_or(|c| c.is_whitespace() || c == '{' || c == ',')
                && after.starts_with('=')
            {
                return Some(from + k);
            }
            at = k + field.len();
        }
        None
    }

    /// An integer field of `[core]` ([`CORE_INTS`]), its range said in words.
    fn int(&self, v: &Spanned<i64>, field: &str) -> Result<i64, ScenarioError> {
        let x = *v.get_ref();
        match core_int_out_of_range(field, &x.to_string(), x) {
            Some(msg) => Err(self.err(v.span(), &format!("core.{field}"), msg)),
            None => Ok(x),
        }
    }

    fn model(
        &self,
        span: Range<usize>,
        field: &str,
        source: impl Into<ModelError>,
    ) -> ScenarioError {
        ScenarioError::Model {
            file: self.file.to_string(),
            line: self.line_col(span.start).0,
            field: field.to_string(),
            source: source.into(),
        }
    }

    fn dur(&self, s: &Spanned<String>, field: &str) -> Result<Dur, ScenarioError> {
        Dur::parse(s.get_ref()).map_err(|e| self.model(s.span(), field, e))
    }

    /// A duration that must be a whole, positive number of ticks... or zero when `allow_zero`.
    fn ticks(
        &self,
        s: &Spanned<String>,
        field: &str,
        clock: Dur,
        allow_zero: bool,
    ) -> Result<u64, ScenarioError> {
        let d = self.dur(s, field)?;
        if d.0 % clock.0 != 0 {
            return Err(self.err(s.span(), field, format!("{d} is not a whole number of clock ticks (clock = {clock}); use a multiple of {clock}")));
        }
        if d.0 == 0 && !allow_zero {
            return Err(self.err(s.span(), field, "must be longer than zero"));
        }
        Ok(d.0 / clock.0)
    }

    fn build(&self, raw: Raw, stem: &str, path: &Path) -> Result<Scenario, ScenarioError> {
        // ---- core ----
        let mut core = CoreConfig::default();
        let rc = &raw.core;
        // Span of each core field, to place errors from the core's own validation.
        let mut spans: Vec<(&'static str, Range<usize>)> = Vec::new();
        macro_rules! dur_field {
            ($f:ident, $name:literal) => {
                if let Some(s) = &rc.$f {
                    core.$f = self.dur(s, concat!("core.", $name))?;
                    spans.push(($name, s.span()));
                }
            };
        }
        dur_field!(clock, "clock");
        dur_field!(pw, "pw");
        dur_field!(pi, "pi");
        dur_field!(ps, "ps");
        dur_field!(x, "x");
        dur_field!(min, "min");
        dur_field!(t1, "t1");
        dur_field!(t2, "t2");
        dur_field!(smp_on, "smp_on");
        if let Some(v) = &rc.cth {
            core.cth = self.int(v, "cth")? as u32;
            spans.push(("cth", v.span()));
        }
        if let Some(v) = &rc.adaptive {
            core.adaptive = *v.get_ref();
            spans.push(("adaptive", v.span()));
        }
        if let Some(v) = &rc.sync_depth {
            core.sync_depth = self.int(v, "sync_depth")? as u8;
            spans.push(("sync_depth", v.span()));
        }
        if let Some(v) = &rc.cnt_width {
            core.cnt_width = self.int(v, "cnt_width")? as u8;
            spans.push(("cnt_width", v.span()));
        }
        let params = core.to_params().map_err(|e| {
            // Point at the involved field written last in the file (the one most likely edited).
            let named = spans
                .iter()
                .filter(|(n, _)| e.fields().contains(n))
                .max_by_key(|(_, sp)| sp.start);
            match named {
                Some((n, span)) => self.model(span.clone(), &format!("core.{n}"), e),
                None => ScenarioError::Invalid {
                    file: self.file.to_string(),
                    // A default that no longer fits, e.g. after a change of `clock`: point at
                    // the clock when it is given.
                    line: spans
                        .iter()
                        .find(|(n, _)| *n == "clock")
                        .map_or(1, |(_, sp)| self.line_col(sp.start).0),
                    field: format!("core.{}", e.fields().first().copied().unwrap_or("core")),
                    msg: format!("{e} (with the default values of the fields not given)"),
                },
            }
        })?;
        let clock = core.clock;

        // ---- run length ----
        let ticks = self.ticks(&raw.duration, "duration", clock, false)?;

        // ---- env ----
        let e = raw.env;
        let volts =
            |v: &Option<Spanned<f64>>, f: &str, default: f64| -> Result<f64, ScenarioError> {
                let Some(v) = v else { return Ok(default) };
                let x = *v.get_ref();
                if !(x.is_finite() && x > 0.0 && x <= 40.0) {
                    return Err(self.err(
                        v.span(),
                        f,
                        format!("{x} V is not a supply voltage; valid is 0 < V <= 40"),
                    ));
                }
                Ok(x)
            };
        let vcc1_v = volts(&e.vcc1_v, "env.vcc1_v", 5.0)?;
        let vcc2_v = volts(&e.vcc2_v, "env.vcc2_v", 3.3)?;
        let mpu_boot_ticks = match &e.mpu_boot {
            Some(s) => self.ticks(s, "env.mpu_boot", clock, true)?,
            None => Dur::ms(1).0.div_ceil(clock.0),
        };
        macro_rules! sub {
            ($opt:expr, $name:literal, $check:expr) => {{
                match $opt {
                    Some(s) => {
                        let span = s.span();
                        let v = s.into_inner();
                        #[allow(clippy::redundant_closure_call)]
                        ($check)(v.clone()).map_err(|er: pmu50_env::EnvError| {
                            // Point at the line of the field the model names, when it is written.
                            let msg = er.to_string();
                            let field = msg
                                .split_once("field `")
                                .and_then(|(_, r)| r.split_once('`'))
                                .map(|(f, _)| f.to_string());
                            match field
                                .as_deref()
                                .and_then(|f| self.field_offset(span.start, f))
                            {
                                Some(at) => self.model(
                                    at..at,
                                    &format!("{}.{}", $name, field.unwrap_or_default()),
                                    er,
                                ),
                                None => self.model(span, $name, er),
                            }
                        })?;
                        v
                    }
                    None => Default::default(),
                }
            }};
        }
        let sensor2: Sensor2Config = sub!(e.sensor2, "env.sensor2", |c| Sensor2::new(c)
            .map(|_| ())
            .map_err(Into::into));
        let comparator: ComparatorConfig =
            sub!(e.comparator, "env.comparator", |c| ComparatorPair::new(c)
                .map(|_| ())
                .map_err(Into::into));
        let sensor1: Sensor1Config = sub!(e.sensor1, "env.sensor1", |c| Sensor1::new(c)
            .map(|_| ())
            .map_err(Into::into));
        let readout: ReadoutConfig = sub!(e.readout, "env.readout", |c| Readout::new(c)
            .map(|_| ())
            .map_err(Into::into));
        let dark_current: DarkCurrentConfig = sub!(e.dark_current, "env.dark_current", |c| {
            DarkCurrentMeter::new(c).map(|_| ()).map_err(Into::into)
        });
        let theta_t_deg = match &e.theta_t_deg {
            None => 0.0,
            Some(v) => {
                let x = *v.get_ref();
                if !x.is_finite() || x.abs() > 90.0 {
                    return Err(self.err(
                        v.span(),
                        "env.theta_t_deg",
                        format!("{x} deg is not a torsion angle; valid is -90 to 90 degrees"),
                    ));
                }
                x
            }
        };
        let env = EnvSpec {
            vcc1_v,
            vcc2_v,
            mpu_boot_ticks,
            theta_t_deg,
            sensor2,
            comparator,
            sensor1,
            readout,
            dark_current,
        };

        // ---- motor ----
        let motor = match raw.motor {
            None => MotorProfile::constant(0.0).map_err(|er| ScenarioError::Invalid {
                file: self.file.into(),
                line: 1,
                field: "motor".into(),
                msg: er.to_string(),
            })?,
            Some(m) => {
                let mspan = m.span();
                let m = m.into_inner();
                let mut segs = Vec::new();
                for (k, s) in m.segments.iter().enumerate() {
                    let field = format!("motor.segments[{k}]");
                    let d = self.dur(&s.get_ref().duration, &format!("{field}.duration"))?;
                    let seg = match (s.get_ref().kind.get_ref().as_str(), s.get_ref().delta_deg) {
                        ("hold", None) => Segment::Hold { duration_ns: d.0 },
                        ("hold", Some(_)) => {
                            return Err(self.err(
                                s.span(),
                                &format!("{field}.delta_deg"),
                                "a hold segment has no delta_deg",
                            ))
                        }
                        ("move", Some(delta_deg)) => {
                            if d.0 == 0 {
                                return Err(self.err(
                                    s.get_ref().duration.span(),
                                    &format!("{field}.duration"),
                                    "a move must last longer than zero",
                                ));
                            }
                            Segment::Move {
                                duration_ns: d.0,
                                delta_deg,
                            }
                        }
                        ("move", None) => {
                            return Err(self.err(
                                s.span(),
                                &format!("{field}.delta_deg"),
                                "a move segment needs delta_deg (degrees, signed)",
                            ))
                        }
                        (other, _) => {
                            return Err(self.err(
                                s.get_ref().kind.span(),
                                &format!("{field}.kind"),
                                format!(
                                    "unknown kind `{other}`; valid kinds are \"hold\" and \"move\""
                                ),
                            ))
                        }
                    };
                    segs.push(seg);
                }
                MotorProfile::new(m.start_deg, segs).map_err(|er| self.model(mspan, "motor", er))?
            }
        };

        // ---- events ----
        let mut events = Vec::new();
        let mut last_tick = 0u64;
        let mut ig = false;
        // (tick, line, what) of the last bus access (a write or a read): the bus takes one a tick.
        let mut last_access: Option<(u64, usize, &str)> = None;
        for (k, ev) in raw.events.iter().enumerate() {
            let field = format!("events[{k}]");
            let r = ev.get_ref();
            let tick = self.ticks(&r.at, &format!("{field}.at"), clock, true)?;
            if tick < last_tick {
                return Err(self.err(r.at.span(), &format!("{field}.at"), format!("time goes backwards: {} is before the previous event at {}; list events in time order", Dur(tick * clock.0), Dur(last_tick * clock.0))));
            }
            if tick >= ticks {
                return Err(self.err(
                    r.at.span(),
                    &format!("{field}.at"),
                    format!(
                        "{} is not before the end of the run (duration = {})",
                        Dur(tick * clock.0),
                        Dur(ticks * clock.0)
                    ),
                ));
            }
            last_tick = tick;
            let given = usize::from(r.ig.is_some())
                + usize::from(r.write.is_some())
                + usize::from(r.read.is_some())
                + usize::from(r.vs2_fault.is_some())
                + usize::from(r.bus_write.is_some())
                + usize::from(r.vs2_pg_leak.is_some());
            if given != 1 {
                return Err(self.err(ev.span(), &field, format!("an event has exactly one action (ig, write, read, bus_write, vs2_fault or vs2_pg_leak); this one has {given}")));
            }
            let action = if let Some(v) = r.ig {
                ig = v;
                Action::Ig(v)
            } else if let Some(v) = r.vs2_fault {
                Action::Vs2Fault(v)
            } else if let Some(v) = r.vs2_pg_leak {
                Action::Vs2PgLeak(v)
            } else if let Some(b) = &r.bus_write {
                // a raw cycle of the register bus, as a port-level bench drives it
                let bf = format!("{field}.bus_write");
                let b_span = b.span();
                let b = b.get_ref();
                let a = *b.addr.get_ref();
                let Ok(addr) = u8::try_from(a) else {
                    return Err(self.err(
                        b.addr.span(),
                        &format!("{bf}.addr"),
                        format!("bus address {a} does not fit the 8-bit bus_addr; valid is 0..=255 (0x00..=0xFF)"),
                    ));
                };
                let d = *b.data.get_ref();
                let Ok(value) = u16::try_from(d) else {
                    return Err(self.err(
                        b.data.span(),
                        &format!("{bf}.data"),
                        format!("{d} does not fit the 16-bit bus_wdata; valid is 0..=65535 (0x0000..=0xFFFF)"),
                    ));
                };
                if !ig {
                    return Err(self.err(r.at.span(), &bf, "the key is off at this time: the MPU is not powered and cannot write ([0205]); turn ig on first"));
                }
                let line = self.line_col(b_span.start).0;
                if let Some((t, l, what)) = last_access.filter(|(t, ..)| *t == tick) {
                    return Err(self.err(
                        b_span,
                        &bf,
                        format!("a bus write at {} (the {what} of line {l} is at the same time); the bus takes one access per clock tick; move it at least one tick ({clock}) later", Dur(t * clock.0)),
                    ));
                }
                last_access = Some((tick, line, "write"));
                let name = MAP
                    .iter()
                    .find(|(_, a, ..)| *a == addr)
                    .map_or_else(|| format!("0x{addr:02X}"), |(n, ..)| n.to_string());
                Action::Write { addr, name, value }
            } else if let Some(a) = &r.read {
                let rf = format!("{field}.read");
                let v = *a.get_ref();
                let Ok(addr) = u8::try_from(v) else {
                    return Err(self.err(
                        a.span(),
                        &rf,
                        format!("bus address {v} does not fit the 8-bit bus_addr; valid is 0..=255 (0x00..=0xFF)"),
                    ));
                };
                if !ig {
                    return Err(self.err(r.at.span(), &rf, "the key is off at this time: the MPU is not powered and cannot read ([0205]); turn ig on first"));
                }
                let line = self.line_col(a.span().start).0;
                if let Some((t, l, what)) = last_access.filter(|(t, ..)| *t == tick) {
                    return Err(self.err(
                        a.span(),
                        &rf,
                        format!("a read at {} (the {what} of line {l} is at the same time); the bus takes one access per clock tick; move it at least one tick ({clock}) later", Dur(t * clock.0)),
                    ));
                }
                last_access = Some((tick, line, "read"));
                Action::Read { addr }
            } else {
                let w_span = r.write.as_ref().map_or(r.at.span(), |w| w.span());
                let w = r
                    .write
                    .as_ref()
                    .map(|w| w.get_ref())
                    .ok_or_else(|| self.err(ev.span(), &field, "missing action"))?;
                let name = w.reg.get_ref().to_ascii_uppercase();
                let Some(&(_, addr, width, access)) = MAP.iter().find(|(n, ..)| *n == name) else {
                    let names: Vec<&str> = MAP.iter().map(|(n, ..)| *n).collect();
                    return Err(self.err(
                        w.reg.span(),
                        &format!("{field}.write.reg"),
                        format!(
                            "unknown register `{}`; registers are {}",
                            w.reg.get_ref(),
                            names.join(", ")
                        ),
                    ));
                };
                if !(access.contains("RW") || access.contains("W1C")) {
                    return Err(self.err(
                        w.reg.span(),
                        &format!("{field}.write.reg"),
                        format!("register {name} is read-only ({access})"),
                    ));
                }
                let v = *w.value.get_ref();
                let max = (1i64 << width.min(16)) - 1;
                let max = if name == "STATUS" { 0xFFFF } else { max };
                if !(0..=max).contains(&v) {
                    return Err(self.err(
                        w.value.span(),
                        &format!("{field}.write.value"),
                        format!(
                            "{v} does not fit register {name} ({width} bits); valid is 0..={max}"
                        ),
                    ));
                }
                if !ig {
                    return Err(self.err(r.at.span(), &format!("{field}.write"), "the key is off at this time: the MPU is not powered and cannot write ([0205]); turn ig on first"));
                }
                let line = self.line_col(w_span.start).0;
                if let Some((t, l, what)) = last_access.filter(|(t, ..)| *t == tick) {
                    return Err(self.err(
                        w_span,
                        &format!("{field}.write"),
                        format!("a second {} at {} (the {what} of line {l} is at the same time); the bus takes one access per clock tick, so only the last would happen; move it at least one tick ({clock}) later", if what == "write" { "write" } else { "bus access" }, Dur(t * clock.0)),
                    ));
                }
                last_access = Some((tick, line, "write"));
                Action::Write {
                    addr,
                    name,
                    value: v as u16,
                }
            };
            // Messages point at the action's line (`write = ...`, `read = ...`), else at `at`.
            let line = self
                .line_col(
                    r.write
                        .as_ref()
                        .map(|w| w.span().start)
                        .or_else(|| r.read.as_ref().map(|a| a.span().start))
                        .or_else(|| r.bus_write.as_ref().map(|b| b.span().start))
                        .unwrap_or(r.at.span().start),
                )
                .0;
            events.push(Event { tick, action, line });
        }

        // ---- expect ----
        let expect = match raw.expect {
            None => Expect::default(),
            Some(x) => {
                let span = x.span();
                let x = x.into_inner();
                if let Some(t) = x.readout_within_deg {
                    if !(t.is_finite() && t > 0.0) {
                        let at = self
                            .field_offset(span.start, "readout_within_deg")
                            .unwrap_or(span.start);
                        return Err(self.err(
                            at..at,
                            "expect.readout_within_deg",
                            format!("{t} is not a positive angle in degrees"),
                        ));
                    }
                }
                if let Some(seq) = &x.si_sequence_ms {
                    if seq.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
                        let at = self
                            .field_offset(span.start, "si_sequence_ms")
                            .unwrap_or(span.start);
                        return Err(self.err(
                            at..at,
                            "expect.si_sequence_ms",
                            "intervals are positive numbers of milliseconds",
                        ));
                    }
                }
                Expect {
                    si_sequence_ms: x.si_sequence_ms,
                    readout_within_deg: x.readout_within_deg,
                    diag: x.diag,
                    quadrant_skip: x.quadrant_skip,
                }
            }
        };

        // ---- vcd ----
        let vcd_window = match &raw.vcd.window {
            None => None,
            Some(w) => {
                let list = w.get_ref();
                if list.len() != 2 {
                    return Err(self.err(
                        w.span(),
                        "vcd.window",
                        format!("a window is [start, end], got {} values", list.len()),
                    ));
                }
                let a = self.ticks(&list[0], "vcd.window[0]", clock, true)?;
                let b = self.ticks(&list[1], "vcd.window[1]", clock, true)?;
                if b <= a {
                    return Err(self.err(
                        list[1].span(),
                        "vcd.window[1]",
                        "the window ends before it starts",
                    ));
                }
                if b > ticks {
                    return Err(self.err(list[1].span(), "vcd.window[1]", format!("the window ends at {}, after the end of the run (duration = {}); valid is a window within 0 to {}", Dur(b * clock.0), Dur(ticks * clock.0), Dur(ticks * clock.0))));
                }
                Some((a, b))
            }
        };

        let trace = match &raw.vcd.trace {
            None => None,
            Some(t) => Some(Trace::parse(t.get_ref()).ok_or_else(|| {
                self.err(
                    t.span(),
                    "vcd.trace",
                    format!(
                        "`{}` is not a trace level; valid are {TRACE_VALID}",
                        t.get_ref()
                    ),
                )
            })?),
        };
        if trace == Some(Trace::None) && vcd_window.is_some() {
            let at = raw.vcd.trace.as_ref().map_or(0..0, |t| t.span());
            return Err(self.err(at, "vcd.trace", "a run with trace = \"none\" writes no waveform, so a `window` has nothing to limit; remove one of them"));
        }

        let name = match &raw.name {
            Some(n) => {
                let v = n.get_ref();
                if v.is_empty()
                    || !v
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
                {
                    return Err(self.err(n.span(), "name", format!("`{v}` is not a valid name; use letters, digits, `_` and `-` (it names the output files)")));
                }
                v.clone()
            }
            None => stem.to_string(),
        };

        Ok(Scenario {
            name,
            description: raw.description.unwrap_or_default(),
            path: path.to_path_buf(),
            core,
            params,
            env,
            motor,
            events,
            ticks,
            expect,
            vcd_window,
            trace,
        })
    }
}
