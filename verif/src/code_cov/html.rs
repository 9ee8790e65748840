//! The code coverage section of `report.html`: figures per file, the sources with their hits
//! and misses.

use super::figures::*;
use super::points::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// Source lines shown in full per file; a longer file (a netlist) shows the lines around its
/// misses only.
pub(super) const FULL_SOURCE_LINES: usize = 1500;
/// Misses listed per file.
pub(super) const MISSES_SHOWN: usize = 200;

/// The "Code coverage" section of report.html: the figures per file, the waivers, and per file
/// (folded) the source with the hit count of each line, the never-hit lines marked, and the
/// bits that did not toggle.
pub fn render_html(r: &CodeReport) -> String {
    use pmu50_testbench::plot::svg::esc;
    use std::fmt::Write;
    let s = &r.summary;
    let mut h = format!("<style>{CSS}</style>\n");
    let _ = write!(
        h,
        "<h2 id=\"code\">Code coverage of the RTL</h2>\n<p>Verilator line coverage (blocks and branches: hit at least once){} and toggle coverage (each bit: rose and fell within one seed's run) over {} seed(s), after {} waiver(s) ({}). Files: <code>code/coverage.dat</code>, <code>code/lcov.info</code>, <code>code/summary.json</code>.</p>\n",
        if s.expr_measured {
            ", expression coverage (each term of an expression's truth table: seen at least once)"
        } else {
            ""
        },
        s.seeds,
        s.waivers.len(),
        esc(if s.waivers_file.is_empty() { "none" } else { &s.waivers_file })
    );
    if s.seeds_unaccounted > 0 {
        let _ = writeln!(h, "<p class=\"cc-bad\">{} seed(s) with a result have no code coverage counted: the folder was interrupted; run <code>pmu50 regress --resume</code> on it.</p>", s.seeds_unaccounted);
    }
    let cell = |c: &Count| {
        let cls = if c.hit == c.total { "cc-ok" } else { "cc-bad" };
        format!(
            "<td class=\"{cls}\">{}/{}</td><td class=\"{cls}\">{:.2} %</td><td>{}</td>",
            c.hit, c.total, c.pct, c.waived
        )
    };
    // the expression columns when the builds measured expression coverage
    let expr = |c: &Count| {
        if s.expr_measured {
            cell(c)
        } else {
            String::new()
        }
    };
    let _ = writeln!(
        h,
        "<table><tr><th>file</th><th>line</th><th>%</th><th>waived</th><th>toggle</th><th>%</th><th>waived</th>{}</tr>",
        if s.expr_measured {
            "<th>expression</th><th>%</th><th>waived</th>"
        } else {
            ""
        }
    );
    for f in &s.files {
        let _ = writeln!(
            h,
            "<tr><td><a href=\"#code-{}\">{}</a></td>{}{}{}</tr>",
            esc(&anchor(&f.file)),
            esc(&f.file),
            cell(&f.line),
            cell(&f.toggle),
            expr(&f.expr)
        );
    }
    let _ = writeln!(
        h,
        "<tr><th>all</th>{}{}{}</tr></table>",
        cell(&s.line),
        cell(&s.toggle),
        expr(&s.expr)
    );
    if !s.waivers.is_empty() {
        h.push_str("<h3>Waivers</h3>\n<table><tr><th>file</th><th>what</th><th>points</th><th>reason</th></tr>\n");
        for w in &s.waivers {
            let note = if w.covered > 0 {
                format!(
                    " <span class=\"cc-bad\">({} covered all the same: check the reason)</span>",
                    w.covered
                )
            } else if w.points == 0 {
                " <span class=\"cc-bad\">(matches nothing)</span>".to_string()
            } else {
                String::new()
            };
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}{note}</td><td>{}</td></tr>",
                esc(&w.file),
                esc(&w.what),
                w.points,
                esc(&w.reason)
            );
        }
        h.push_str("</table>\n");
    }
    for (file, pts) in &r.points {
        let fig = s.files.iter().find(|f| &f.file == file);
        let missed_l = fig.map_or(0, |f| f.line.total - f.line.hit);
        let missed_t = fig.map_or(0, |f| f.toggle.total - f.toggle.hit);
        let _ = writeln!(
            h,
            "<details id=\"code-{}\"{}><summary><code>{}</code>: {} line point(s) and {} bit(s) not covered</summary>",
            esc(&anchor(file)),
            if missed_l + missed_t > 0 { " open" } else { "" },
            esc(file),
            missed_l,
            missed_t
        );
        // the bits that did not toggle
        // by signal (and its declaration's line), the bits as ranges: `cnt[15:12] (line 40)`
        let mut by_signal: BTreeMap<(u32, String), Vec<Option<u32>>> = BTreeMap::new();
        for (p, _, _) in pts
            .iter()
            .filter(|(p, n, by)| p.kind == Kind::Toggle && by.is_none() && !p.covered(*n))
        {
            let (sig, bit) = p.signal();
            by_signal
                .entry((p.line, demangle(sig)))
                .or_default()
                .push(bit);
        }
        let bits: usize = by_signal.values().map(Vec::len).sum();
        let mut untoggled: Vec<String> = Vec::new();
        for ((at, sig), mut v) in by_signal {
            v.sort_unstable_by(|a, b| b.cmp(a));
            let mut i = 0;
            while i < v.len() {
                let mut j = i;
                while let (Some(Some(a)), Some(Some(b))) = (v.get(j), v.get(j + 1)) {
                    if *a != b + 1 {
                        break;
                    }
                    j += 1;
                }
                untoggled.push(match (v[i], v[j]) {
                    (Some(hi), Some(lo)) if hi != lo => format!("{sig}[{hi}:{lo}] (line {at})"),
                    (Some(b), _) => format!("{sig}[{b}] (line {at})"),
                    (None, _) => format!("{sig} (line {at})"),
                });
                i = j + 1;
            }
        }
        if !untoggled.is_empty() {
            let _ = write!(h, "<p>Bits not toggled ({bits}): ");
            let shown: Vec<String> = untoggled
                .iter()
                .take(MISSES_SHOWN)
                .map(|u| format!("<code>{}</code>", esc(u)))
                .collect();
            h.push_str(&shown.join(", "));
            if untoggled.len() > MISSES_SHOWN {
                let _ = write!(h, " and {} more", untoggled.len() - MISSES_SHOWN);
            }
            h.push_str("</p>\n");
        }
        // the expression terms never seen
        let terms: Vec<String> = pts
            .iter()
            .filter(|(p, n, by)| p.kind == Kind::Expr && by.is_none() && !p.covered(*n))
            .map(|(p, _, _)| format!("<code>{}: {}</code>", p.line, esc(&p.comment)))
            .collect();
        if !terms.is_empty() {
            let _ = write!(h, "<p>Expression terms not seen ({}): ", terms.len());
            h.push_str(
                &terms
                    .iter()
                    .take(MISSES_SHOWN)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", "),
            );
            if terms.len() > MISSES_SHOWN {
                let _ = write!(h, " and {} more", terms.len() - MISSES_SHOWN);
            }
            h.push_str("</p>\n");
        }
        h.push_str(&source_html(r, file, pts));
        h.push_str("</details>\n");
    }
    h
}

pub(super) fn anchor(file: &str) -> String {
    file.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect()
}

/// The source of `file` with, per line, the largest count of its line and branch points, the
/// lines of a point never hit marked (`miss`), the waived ones greyed.
pub(super) fn source_html(
    r: &CodeReport,
    file: &str,
    pts: &[(Point, u64, Option<usize>)],
) -> String {
    use pmu50_testbench::plot::svg::esc;
    // per line: (largest count, a point missed, all waived)
    let mut at: BTreeMap<u32, (u64, bool, bool)> = BTreeMap::new();
    for (p, n, by) in pts.iter().filter(|(p, _, _)| p.is_line()) {
        for &(a, b) in &p.lines {
            for l in a..=b.min(a.saturating_add(100_000)) {
                let e = at.entry(l).or_insert((0, false, true));
                e.0 = e.0.max(*n);
                if by.is_none() {
                    e.2 = false;
                }
            }
        }
        if by.is_none() && !p.covered(*n) {
            at.entry(p.line).or_insert((0, false, false)).1 = true;
        }
    }
    let text = r
        .base
        .as_ref()
        .map(|b| b.join(file))
        .or_else(|| Some(PathBuf::from(file)))
        .and_then(|p| std::fs::read_to_string(p).ok());
    let Some(text) = text else {
        return "<p>(the source is not available here)</p>\n".into();
    };
    let lines: Vec<&str> = text.lines().collect();
    let show: Box<dyn Fn(usize) -> bool> = if lines.len() <= FULL_SOURCE_LINES {
        Box::new(|_| true)
    } else {
        let misses: BTreeSet<usize> = at
            .iter()
            .filter(|(_, v)| v.1)
            .map(|(l, _)| *l as usize)
            .take(MISSES_SHOWN)
            .collect();
        Box::new(move |l| misses.range(l.saturating_sub(2)..=l + 2).next().is_some())
    };
    let mut h = String::from("<pre class=\"src\">");
    let mut gap = false;
    for (i, l) in lines.iter().enumerate() {
        let n = i as u32 + 1;
        if !show(i + 1) {
            if !gap {
                h.push_str("<span class=\"gap\">      ...</span>\n");
                gap = true;
            }
            continue;
        }
        gap = false;
        let (count, cls) = match at.get(&n) {
            Some(&(_, true, _)) => (" miss".to_string(), "miss"),
            Some(&(_, _, true)) => ("waived".to_string(), "waived"),
            Some(&(c, false, false)) => (format!("{c:>6}"), "hit"),
            None => (String::new(), "none"),
        };
        let _ = std::fmt::Write::write_fmt(
            &mut h,
            format_args!(
                "<span class=\"{cls}\">{n:>5} {count:>6}  {}</span>\n",
                esc(l)
            ),
        );
    }
    h.push_str("</pre>\n");
    h
}

/// The style of the section (added to report.html's).
pub const CSS: &str = "pre.src{font-size:12px;line-height:1.25;overflow-x:auto;background:#fafafa;padding:4px}pre.src span{display:inline-block;width:100%}pre.src .miss{background:#f4a6a6}pre.src .hit{background:#e5f5e0}pre.src .waived{background:#e0e0e0;color:#555}pre.src .gap{color:#888}.cc-ok{background:#e5f5e0}.cc-bad{background:#fbe3a0}";
