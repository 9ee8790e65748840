//! The fuzz targets on stable Rust: replays every seed (fuzz/seeds/<target>/) and every saved
//! crash reproducer (fuzz/regressions/<target>/) through the target bodies, then runs a bounded,
//! seeded random pass that mutates those inputs (bit flips, byte edits, deletions, insertions,
//! splices and format tokens), a few thousand inputs per target. The bodies are the same library
//! functions the cargo-fuzz targets call (`pmu50_testbench::fuzzing`, `pmu50_waves::fuzzing`), so a crash
//! found by `make fuzz` and fixed stays fixed under `make test`. `FUZZ_REPLAY_SEED=N` picks
//! another random pass; a failing input is written to target/fuzz-replay-failures/.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use pmu50_waves::fuzzing::{MALFORMED, VALID_SAMPLE};

type Body = fn(&[u8]);

/// (target name, body, random-pass iterations)
const TARGETS: [(&str, Body, u32); 6] = [
    ("scenario", pmu50_testbench::fuzzing::scenario, 20_000),
    ("duration", pmu50_testbench::fuzzing::duration, 200_000),
    ("vcd_diff", pmu50_waves::fuzzing::vcd, 20_000),
    ("fst_read", pmu50_waves::fuzzing::fst, 10_000),
    (
        "regress_folder",
        pmu50_verif::fuzzing::regress_folder,
        3_000,
    ),
    // each input is a folder written to disk and signed off: a few hundred
    ("signoff_folder", pmu50_verif::fuzzing::signoff_folder, 300),
];

const VCD_TOKENS: &[&str] = &[
    "$end",
    " $end\n",
    "$var wire 8 ! a [7:0] $end\n",
    "$var real 64 \" r $end\n",
    "$scope module m $end\n",
    "$upscope $end\n",
    "$enddefinitions $end\n",
    "$timescale 1 ns $end\n",
    "$comment c $end",
    "$dumpvars",
    "#",
    "#0\n",
    "#18446744073709551615\n",
    "b",
    "r",
    "s",
    "\n",
    " ",
    "!",
    "\"",
    "[",
    "]",
    ":",
    "nan",
    "inf",
    "-",
    "x",
    "z",
    "X",
    "Z",
    "h",
    "u",
    "w",
    "l",
    "4294967295",
    "65536",
    "0",
    "1",
    "1e308",
    "event",
    "string",
];
const TOML_TOKENS: &[&str] = &[
    "=",
    "\"",
    "'",
    "[",
    "]",
    "{",
    "}",
    ",",
    "\n",
    "ms",
    "us",
    "µs",
    "ns",
    " s",
    ".",
    "-",
    "+",
    "[[events]]\n",
    "at = \"1 ms\"\n",
    "duration",
    "[core]\n",
    "[env]\n",
    "[motor]\n",
    "[expect]\n",
    "[vcd]\n",
    "window",
    "18446744073709551615",
    "0",
    "1.5",
    "true",
    "write = { reg = \"T2\", value = 110 }",
    "ig = true",
    "cnt_width = 256",
    "sync_depth = 0",
    "clock = \"0 ns\"",
    "nan",
    "inf",
    "\u{10ffff}",
    "é",
];
/// FST sizes and block types (big-endian u64s, varints, block type bytes).
const FST_TOKENS: &[&str] = &[
    "\0",
    "\u{1}",
    "\u{3}",
    "\u{4}",
    "\u{6}",
    "\u{7}",
    "\u{8}",
    "\u{7f}",
    "\0\0\0\0\0\0\0\0",
    "\0\0\0\0\0\0\u{1}\u{49}",
    "\u{7f}\u{7f}\u{7f}\u{7f}\u{7f}\u{7f}\u{7f}\u{7f}",
    "\0\0\0\0\u{7f}\u{7f}\u{7f}\u{7f}",
];
/// regress.json, results.jsonl and coverage.json keys and values, and the part separator.
const FOLDER_TOKENS: &[&str] = &[
    "\0",
    "\n",
    "{",
    "}",
    "[",
    "]",
    ":",
    ",",
    "\"",
    "\"shard\":{\"index\":0,\"count\":0}",
    "\"seed\":",
    "\"verdict\":\"fail\"",
    "\"digest\":\"sha256:",
    "\"status\":\"proven_unreachable\"",
    "\"verdict\":\"proven\"",
    "\"total\":0",
    "\"ran\":false",
    "\"failure\":null",
    "\"cov\":\"0:1\"",
    "\"runs\":[]",
    "\"hits\":777",
    "\"start_seed\":",
    "\"iterations\":",
    "\"directed\":true",
    "18446744073709551615",
    "1000000000000",
    "0",
    "-1",
    "1e3",
    "null",
    "true",
    "\"fa{",
];
const DUR_TOKENS: &[&str] = &[
    "s",
    "ms",
    "us",
    "µs",
    "ns",
    ".",
    "-",
    "+",
    " ",
    "0",
    "9",
    "18446744073709551615",
    "000000000",
];

/// xorshift64*: small, seeded, reproducible.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn files_in(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<(String, Vec<u8>)> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| p.is_file())
        .map(|p| (p.display().to_string(), std::fs::read(&p).unwrap()))
        .collect();
    v.sort();
    v
}

fn corpus(target: &str) -> Vec<(String, Vec<u8>)> {
    let mut v = files_in(&root().join("fuzz/seeds").join(target));
    v.extend(files_in(&root().join("fuzz/regressions").join(target)));
    v
}

/// Runs `body` on `data`; on a panic saves the input and fails with its path.
fn run_one(target: &str, what: &str, body: Body, data: &[u8]) {
    if catch_unwind(AssertUnwindSafe(|| body(data))).is_ok() {
        return;
    }
    let dir = root().join("target/fuzz-replay-failures");
    std::fs::create_dir_all(&dir).unwrap();
    let h = data.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x100_0000_01b3)
    });
    let path = dir.join(format!("{target}-{h:016x}"));
    std::fs::write(&path, data).unwrap();
    panic!("fuzz target `{target}` fails on {what}; input saved as {} (replay: cargo +nightly fuzz run {target} {})", path.display(), path.display());
}

fn mutate(rng: &mut Rng, base: &[u8], other: &[u8], tokens: &[&str]) -> Vec<u8> {
    let mut d = base.to_vec();
    for _ in 0..1 + rng.below(4) {
        let at = rng.below(d.len() + 1);
        match rng.below(7) {
            0 if !d.is_empty() => {
                let i = rng.below(d.len());
                d[i] ^= 1 << rng.below(8);
            }
            1 if !d.is_empty() => {
                let i = rng.below(d.len());
                d[i] = [0u8, b' ', b'\n', b'$', b'#', 0x7f, 0xff, b'9'][rng.below(8)];
            }
            2 if !d.is_empty() => {
                let i = rng.below(d.len());
                let n = (1 + rng.below(16)).min(d.len() - i);
                d.drain(i..i + n);
            }
            3 => {
                let n = 1 + rng.below(8);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next() as u8).collect();
                d.splice(at..at, bytes);
            }
            4 if !d.is_empty() => {
                let i = rng.below(d.len());
                let n = (1 + rng.below(64)).min(d.len() - i);
                let chunk = d[i..i + n].to_vec();
                d.splice(at..at, chunk);
            }
            5 if !other.is_empty() => {
                let cut = rng.below(other.len());
                d.truncate(at);
                d.extend_from_slice(&other[cut..]);
            }
            _ => {
                let t = tokens[rng.below(tokens.len())].as_bytes();
                d.splice(at..at, t.iter().copied());
            }
        }
    }
    d
}

#[test]
fn every_target_has_seeds() {
    for (t, _, _) in TARGETS {
        assert!(
            corpus(t).len() >= 3,
            "fuzz/seeds/{t} has fewer than 3 seeds"
        );
    }
}

#[test]
fn vcd_seeds_hold_every_malformed_shape_and_the_valid_sample() {
    // PMU50_UPDATE_SEEDS=1 rewrites them from pmu50_waves::fuzzing
    let dir = root().join("fuzz/seeds/vcd_diff");
    let update = std::env::var_os("PMU50_UPDATE_SEEDS").is_some();
    let mut want: Vec<(String, &[u8])> = MALFORMED
        .iter()
        .map(|m| (format!("malformed-{}.vcd", m.name), m.vcd))
        .collect();
    want.push(("valid-sample.vcd".into(), VALID_SAMPLE));
    for (name, bytes) in want {
        let p = dir.join(&name);
        if update {
            std::fs::write(&p, bytes).unwrap();
        }
        assert_eq!(
            std::fs::read(&p).ok().as_deref(),
            Some(bytes),
            "{} differs from pmu50_waves::fuzzing (PMU50_UPDATE_SEEDS=1 rewrites it)",
            p.display()
        );
    }
}

#[test]
fn seeds_and_regressions_replay_cleanly() {
    for (t, body, _) in TARGETS {
        for (name, data) in corpus(t) {
            run_one(t, &name, body, &data);
        }
    }
    for m in MALFORMED {
        run_one("vcd_diff", m.name, pmu50_waves::fuzzing::vcd, m.vcd);
    }
}

#[test]
fn bounded_random_pass_finds_no_crash() {
    let seed: u64 = std::env::var("FUZZ_REPLAY_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x5eed_0050);
    for (i, (t, body, iters)) in TARGETS.into_iter().enumerate() {
        let inputs = corpus(t);
        let tokens = match t {
            "vcd_diff" => VCD_TOKENS,
            "fst_read" => FST_TOKENS,
            "scenario" => TOML_TOKENS,
            "regress_folder" | "signoff_folder" => FOLDER_TOKENS,
            _ => DUR_TOKENS,
        };
        let mut rng = Rng(seed ^ (0x9e37_79b9_7f4a_7c15u64.wrapping_mul(i as u64 + 1)) | 1);
        for n in 0..iters {
            let a = &inputs[rng.below(inputs.len())].1;
            let b = &inputs[rng.below(inputs.len())].1;
            let data = mutate(&mut rng, a, b, tokens);
            run_one(t, &format!("random input {n} of seed {seed}"), body, &data);
        }
    }
}
