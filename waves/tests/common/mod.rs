//! Helpers shared by the integration tests.
#![allow(dead_code)]

use pmu50_waves::reader::Waveform;
use pmu50_waves::writer::{BitType, Logic, SigId, VcdBuilder, VcdWriter};
use pmu50_waves::{TimeUnit, Timescale};

/// A small PMU-like header: pmu50.{clk, en, drive_interval.{si[15:0], vout}}.
pub struct Sample {
    pub w: VcdWriter<Vec<u8>>,
    pub clk: SigId,
    pub en: SigId,
    pub si: SigId,
    pub vout: SigId,
}

pub fn sample_builder(ts: Timescale) -> (VcdBuilder, SigId, SigId, SigId, SigId) {
    let mut b = VcdBuilder::new(ts, "pmu50-waves test").unwrap();
    b.push_scope("pmu50").unwrap();
    let clk = b.add_bit(BitType::Wire, "clk", Logic::Zero).unwrap();
    let en = b.add_bit(BitType::Reg, "en", Logic::X).unwrap();
    b.push_scope("drive_interval").unwrap();
    let si = b.add_vector(BitType::Reg, "si", 15, 0, 0).unwrap();
    let vout = b.add_real("vout", 0.0).unwrap();
    b.pop_scope().unwrap();
    b.pop_scope().unwrap();
    (b, clk, en, si, vout)
}

pub fn sample() -> Sample {
    let (b, clk, en, si, vout) = sample_builder(Timescale::new(1, TimeUnit::Us));
    Sample {
        w: b.start(Vec::new()).unwrap(),
        clk,
        en,
        si,
        vout,
    }
}

pub fn text(w: VcdWriter<Vec<u8>>) -> String {
    String::from_utf8(w.finish().unwrap()).unwrap()
}

pub fn wave(text: &str) -> Waveform {
    Waveform::from_bytes(text.as_bytes().to_vec()).unwrap()
}

/// Build a VCD text by hand: header with `ts`, one scope path, vars given as
/// (id, "wire 8 name [7:0]") and a body.
pub fn vcd(ts: &str, scopes: &[&str], vars: &[(&str, &str)], body: &str) -> String {
    let mut s = format!("$timescale {ts} $end\n");
    for sc in scopes {
        s += &format!("$scope module {sc} $end\n");
    }
    for (id, decl) in vars {
        let mut parts = decl.splitn(3, ' ');
        let ty = parts.next().unwrap();
        let w = parts.next().unwrap();
        let rest = parts.next().unwrap();
        s += &format!("$var {ty} {w} {id} {rest} $end\n");
    }
    for _ in scopes {
        s += "$upscope $end\n";
    }
    s += "$enddefinitions $end\n";
    s += body;
    s
}

/// The path of the program `name` on PATH.
pub fn tool(name: &str) -> Option<std::path::PathBuf> {
    std::env::var_os("PATH").and_then(|p| {
        std::env::split_paths(&p)
            .map(|d| d.join(name))
            .find(|f| f.is_file())
    })
}

/// The paths of the programs `names` for the test `test`; when one is missing, `None` after
/// saying so (`missing`: which programs and where they come from), which is allowed only with
/// PMU50_ALLOW_MISSING_TOOLS set (`make test` installs them).
pub fn tools_or_skip(test: &str, names: &[&str], missing: &str) -> Option<Vec<std::path::PathBuf>> {
    let found: Option<Vec<_>> = names.iter().map(|n| tool(n)).collect();
    if found.is_none() {
        assert!(
            std::env::var_os("PMU50_ALLOW_MISSING_TOOLS").is_some(),
            "missing tool for {test}: {missing}; `make test` installs it (set PMU50_ALLOW_MISSING_TOOLS=1 to skip knowingly)"
        );
        println!("SKIPPED {test}: {missing}");
    }
    found
}
