//! Export of a coverage file to the UCIS 1.0 XML interchange format (Accellera Unified Coverage
//! Interoperability Standard, the `UCIS` root of its `ucis.xsd`), so that UCIS tools can read and
//! merge what `pmu50` sampled. python/tests/test_ucis.py validates the export against pyucis'
//! copy of the schema, reads it back with pyucis' XML reader and merges two exports with pyucis'
//! merger, and checks every bin's hits against `coverage.json` and `pmu50 merge`.
//!
//! Mapping:
//! - one history node per run (`logicalName` = run id, `testStatus` true for a `pass` verdict);
//!   a file without runs gets one node named `pmu50-coverage` (the schema needs at least one);
//! - one instance `pmu50` holding one covergroup `pmu50` with one instance `pmu50`;
//! - each coverpoint of the model is a `coverpoint` named `group.point` (`fig17.path`), each of
//!   its bins a `coverpointBin` named as in the model, of type `bins`, or `ignore` for a bin
//!   that can never be hit (with the reason in a `userAttr`; how the coverage proofs decided
//!   the bin, when `pmu50 signoff` knows it, in a `userAttr` `proof`);
//! - each cross is a `cross` named after it (`fig17_x_fig18`) over its two coverpoints, each of
//!   its bins a `crossBin` named `<a,b>` with the bins' indices, of type `default` or `ignore`.
//!
//! The text is deterministic: the same coverage file gives the same bytes (`writtenTime` and the
//! nodes' `date` are fixed, as coverage.json records no time).

use crate::db::CoverageFile;
use crate::model::{crosses, POINTS};
use std::fmt::Write;

/// The fixed time stamp of the export (coverage.json records no time).
const TIME: &str = "1970-01-01T00:00:00";

/// Escape text for an XML attribute or element: `&`, `<`, `>` and `"` always; with `full`, also
/// `'` and the control characters XML 1.0 cannot carry at all (as U+FFFD). The UCIS export
/// escapes fully; the SVG pictures and the HTML report of the CLI escape the four.
pub fn xml_escape(s: &str, full: bool) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' if full => o.push_str("&apos;"),
            c if full && (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r') => {
                o.push('\u{FFFD}')
            }
            c => o.push(c),
        }
    }
    o
}

fn esc(s: &str) -> String {
    xml_escape(s, true)
}

/// One bin element (`coverpointBin` or `crossBin`): its attributes, its count line and, for a bin
/// that cannot be hit, the reason.
fn bin_element(w: &mut dyn Write, tag: &str, attrs: &str, count: &str, b: &crate::db::BinRecord) {
    let _ = writeln!(w, "          <{tag} {attrs}>");
    let _ = writeln!(w, "            {count}");
    for (key, v) in [("unreachable", &b.unreachable), ("proof", &b.proof)] {
        if let Some(v) = v {
            let _ = writeln!(
                w,
                "            <userAttr key=\"{key}\" type=\"str\">{}</userAttr>",
                esc(v)
            );
        }
    }
    let _ = writeln!(w, "          </{tag}>");
}

/// The UCIS XML text of a coverage file (its bins must be this model's, as
/// [`CoverageFile::check`] ensures for every file read or merged).
pub fn to_ucis_xml(f: &CoverageFile) -> String {
    let mut s = String::with_capacity(f.runs.len() * 320 + (1 << 16));
    let _ = write_ucis_xml(f, &mut s);
    s
}

/// [`to_ucis_xml`] into `w`, a line at a time (a file of a million runs is 330 MB of text).
pub fn write_ucis_xml(f: &CoverageFile, w: &mut dyn Write) -> std::fmt::Result {
    let _ = writeln!(w, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(w, "<UCIS xmlns:ucis=\"http://www.w3.org/2001/XMLSchema-instance\" ucisVersion=\"1.0\" writtenBy=\"pmu50-coverage\" writtenTime=\"{TIME}\">");
    let _ = writeln!(
        w,
        "  <sourceFiles fileName=\"docs/verification.md\" id=\"1\"/>"
    );
    let model = esc(&f.model);
    let node = |w: &mut dyn Write, k: usize, name: &str, pass: bool, comment: &str| {
        let _ = writeln!(
            w,
            "  <historyNodes historyNodeId=\"{k}\" logicalName=\"{}\" kind=\"1\" testStatus=\"{pass}\" date=\"{TIME}\" toolCategory=\"UCIS:simulator\" ucisVersion=\"1.0\" vendorId=\"pmu50\" vendorTool=\"pmu50-coverage\" vendorToolVersion=\"{}\" comment=\"{}\"/>",
            esc(name),
            model,
            esc(comment)
        );
    };
    if f.runs.is_empty() {
        node(
            w,
            0,
            "pmu50-coverage",
            true,
            "no run recorded in the coverage file",
        );
    }
    for (k, r) in f.runs.iter().enumerate() {
        node(
            w,
            k,
            &r.id,
            r.verdict == "pass",
            &format!("verdict {}", r.verdict),
        );
    }
    let _ = writeln!(
        w,
        "  <instanceCoverages name=\"pmu50\" key=\"0\" instanceId=\"0\" moduleName=\"pmu50\">"
    );
    let _ = writeln!(w, "    <id file=\"1\" line=\"1\" inlineCount=\"1\"/>");
    let _ = writeln!(w, "    <covergroupCoverage>");
    let _ = writeln!(w, "      <cgInstance name=\"pmu50\" key=\"0\">");
    let _ = writeln!(w, "        <options weight=\"1\" goal=\"100\" at_least=\"1\" per_instance=\"true\" merge_instances=\"true\"/>");
    let _ = writeln!(w, "        <cgId cgName=\"pmu50\" moduleName=\"pmu50\">");
    let _ = writeln!(
        w,
        "          <cginstSourceId file=\"1\" line=\"1\" inlineCount=\"1\"/>"
    );
    let _ = writeln!(
        w,
        "          <cgSourceId file=\"1\" line=\"1\" inlineCount=\"1\"/>"
    );
    let _ = writeln!(w, "        </cgId>");
    let mut k = 0usize;
    for p in POINTS.iter() {
        let _ = writeln!(
            w,
            "        <coverpoint name=\"{}.{}\" key=\"0\">",
            esc(p.group),
            esc(p.name)
        );
        let _ = writeln!(
            w,
            "          <options weight=\"1\" goal=\"100\" at_least=\"1\"/>"
        );
        for (j, _) in p.bins.iter().enumerate() {
            let b = &f.bins[k];
            let local = b.name.rsplit('.').next().unwrap_or(&b.name);
            let ty = if b.unreachable.is_some() {
                "ignore"
            } else {
                "bins"
            };
            let attrs = format!("name=\"{}\" type=\"{ty}\" key=\"{j}\"", esc(local));
            let count = format!(
                "<range from=\"{j}\" to=\"{j}\"><contents coverageCount=\"{}\"/></range>",
                b.hits
            );
            bin_element(w, "coverpointBin", &attrs, &count, b);
            k += 1;
        }
        let _ = writeln!(w, "        </coverpoint>");
    }
    for c in crosses() {
        let (pa, pb) = (&POINTS[c.rows], &POINTS[c.columns]);
        let _ = writeln!(w, "        <cross name=\"{}\" key=\"0\">", esc(c.name));
        let _ = writeln!(
            w,
            "          <options weight=\"1\" goal=\"100\" at_least=\"1\"/>"
        );
        let _ = writeln!(
            w,
            "          <crossExpr>{}.{}</crossExpr>",
            esc(pa.group),
            esc(pa.name)
        );
        let _ = writeln!(
            w,
            "          <crossExpr>{}.{}</crossExpr>",
            esc(pb.group),
            esc(pb.name)
        );
        for (ia, ba) in pa.bins.iter().enumerate() {
            for (ib, bb) in pb.bins.iter().enumerate() {
                let b = &f.bins[k];
                let ty = if b.unreachable.is_some() {
                    "ignore"
                } else {
                    "default"
                };
                let attrs = format!(
                    "name=\"{}\" key=\"{}\" type=\"{ty}\"",
                    esc(&format!("<{},{}>", ba.name, bb.name)),
                    ia * pb.bins.len() + ib
                );
                let count = format!(
                    "<index>{ia}</index><index>{ib}</index><contents coverageCount=\"{}\"/>",
                    b.hits
                );
                bin_element(w, "crossBin", &attrs, &count, b);
                k += 1;
            }
        }
        let _ = writeln!(w, "        </cross>");
    }
    let _ = writeln!(w, "      </cgInstance>");
    let _ = writeln!(w, "    </covergroupCoverage>");
    let _ = writeln!(w, "  </instanceCoverages>");
    writeln!(w, "</UCIS>")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RunRecord;
    use crate::sample::layout;

    #[test]
    fn every_bin_appears_once_with_its_hits_and_names_are_escaped() {
        let n = layout().bins.len();
        let hits: Vec<u64> = (0..n as u64).map(|k| k * 7 + 1).collect();
        let f = CoverageFile::from_coverage(
            &hits,
            vec![RunRecord {
                id: "a<&\"b'>".into(),
                verdict: "fail".into(),
            }],
        );
        let x = to_ucis_xml(&f);
        assert_eq!(x.matches("coverageCount=").count(), n);
        let counts: Vec<u64> = x
            .split("coverageCount=\"")
            .skip(1)
            .map(|t| t[..t.find('"').unwrap()].parse().unwrap())
            .collect();
        assert_eq!(counts, hits, "bins in the model's order");
        assert!(x.contains(
            "logicalName=\"a&lt;&amp;&quot;b&apos;&gt;\" kind=\"1\" testStatus=\"false\""
        ));
        assert_eq!(x, to_ucis_xml(&f), "deterministic");
        let empty = to_ucis_xml(&CoverageFile::empty());
        assert_eq!(empty.matches("<historyNodes ").count(), 1);
    }
}
