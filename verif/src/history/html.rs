//! The history as one static HTML page (no script, no network): per RTL content hash, the pass
//! rate and functional coverage of each run over time; every failure signature with the first
//! and last day it was seen; a row per test-plan area (the FIG. or paragraph the bins cite) with
//! its coverage run by run; and the runs.

use super::db::{HistoryError, Sql};
use super::query::Run;
use pmu50_testbench::plot::svg::esc;

fn pct(h: u64, t: u64) -> f64 {
    if t == 0 {
        0.0
    } else {
        100.0 * h as f64 / t as f64
    }
}

/// A chart of two series in percent over the runs of one RTL (x: run, in time order).
fn chart(runs: &[&Run]) -> String {
    let (w, h, l, b) = (640.0, 180.0, 40.0, 24.0);
    let n = runs.len().max(2) as f64 - 1.0;
    let x = |i: usize| l + (w - l - 10.0) * i as f64 / n;
    let y = |p: f64| 8.0 + (h - b - 8.0) * (1.0 - p / 100.0);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" font-size=\"11\">\n"
    );
    for p in [0.0, 50.0, 100.0] {
        s += &format!(
            "<line x1=\"{l}\" y1=\"{0:.1}\" x2=\"{1}\" y2=\"{0:.1}\" stroke=\"#ddd\"/><text x=\"4\" y=\"{2:.1}\">{p:.0} %</text>\n",
            y(p),
            w - 10.0,
            y(p) + 4.0
        );
    }
    let series = [
        (
            "#2a7",
            "pass rate",
            runs.iter()
                .map(|r| pct(r.pass, r.seed_count.max(r.pass + r.fail + r.error)))
                .collect::<Vec<_>>(),
        ),
        (
            "#27c",
            "functional coverage",
            runs.iter().map(|r| pct(r.func_hit, r.func_total)).collect(),
        ),
    ];
    for (k, (color, name, v)) in series.iter().enumerate() {
        let pts: Vec<String> = v
            .iter()
            .enumerate()
            .map(|(i, p)| format!("{:.1},{:.1}", x(i), y(*p)))
            .collect();
        s += &format!(
            "<polyline fill=\"none\" stroke=\"{color}\" stroke-width=\"2\" points=\"{}\"/>\n",
            pts.join(" ")
        );
        for (i, p) in v.iter().enumerate() {
            s += &format!(
                "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"3\" fill=\"{color}\"><title>{} {}: {p:.1} %</title></circle>\n",
                x(i),
                y(*p),
                esc(&runs[i].day),
                name
            );
        }
        s += &format!(
            "<rect x=\"{}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"{color}\"/><text x=\"{}\" y=\"{}\">{name}</text>\n",
            l + 10.0 + 170.0 * k as f64,
            h - 12.0,
            l + 24.0 + 170.0 * k as f64,
            h - 3.0
        );
    }
    if let (Some(a), Some(z)) = (runs.first(), runs.last()) {
        s += &format!(
            "<text x=\"{l}\" y=\"{:.1}\" fill=\"#666\">{}</text><text x=\"{:.1}\" y=\"{:.1}\" fill=\"#666\" text-anchor=\"end\">{}</text>\n",
            h - b + 10.0,
            esc(&a.day),
            w - 10.0,
            h - b + 10.0,
            esc(&z.day)
        );
    }
    s + "</svg>\n"
}

/// A small bar per run of an area's coverage.
fn bars(v: &[(String, u64, u64)]) -> String {
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"20\">",
        6 * v.len().max(1)
    );
    for (i, (day, h, t)) in v.iter().enumerate() {
        let p = pct(*h, *t);
        let hh = (18.0 * p / 100.0).max(1.0);
        let color = if h == t {
            "#2a7"
        } else if p >= 90.0 {
            "#da2"
        } else {
            "#c33"
        };
        s += &format!(
            "<rect x=\"{}\" y=\"{:.1}\" width=\"5\" height=\"{hh:.1}\" fill=\"{color}\"><title>{}: {h}/{t}</title></rect>",
            6 * i,
            19.0 - hh,
            esc(day)
        );
    }
    s + "</svg>"
}

/// The dashboard of the history in `db`.
pub fn dashboard(db: &mut dyn Sql, title: &str) -> Result<String, HistoryError> {
    let runs = super::query::runs(db)?;
    let sigs = super::query::signatures(db)?;
    let areas = super::query::areas(db)?;
    let mut h = format!(
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>pmu50 history</title><style>\
body{{font-family:sans-serif;margin:2em;max-width:1100px}} table{{border-collapse:collapse;margin:1em 0}} \
td,th{{border:1px solid #ccc;padding:2px 8px;font-size:13px;text-align:left}} .ok{{color:#173}} .bad{{color:#b22}} \
code{{font-size:12px}}</style></head><body>\n<h1>pmu50 history</h1>\n<p>{} runs in {}</p>\n",
        runs.len(),
        esc(title)
    );
    let mut hashes: Vec<&str> = Vec::new();
    for r in &runs {
        if !hashes.contains(&r.rtl_hash.as_str()) {
            hashes.push(&r.rtl_hash);
        }
    }
    h += "<h2>Pass rate and coverage over time, per RTL</h2>\n";
    for hash in &hashes {
        let rs: Vec<&Run> = runs
            .iter()
            .filter(|r| r.rtl_hash == *hash && r.kind != "signoff")
            .collect();
        if rs.is_empty() {
            continue;
        }
        let (soak, last) = super::query::soak(&runs, hash);
        h += &format!(
            "<h3>RTL <code>{}</code></h3>\n<p>{} regressions; soak: {soak} consecutive day(s) at 100 % up to {}</p>\n{}",
            esc(hash),
            rs.len(),
            esc(last.as_deref().unwrap_or("-")),
            chart(&rs)
        );
    }
    h += "<h2>Failure signatures</h2>\n";
    if sigs.is_empty() {
        h += "<p>none</p>\n";
    } else {
        h += "<table><tr><th>signature</th><th>first seen</th><th>last seen</th><th>runs</th></tr>\n";
        for (s, first, last, n) in &sigs {
            h += &format!(
                "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{n}</td></tr>\n",
                esc(s),
                esc(first),
                esc(last)
            );
        }
        h += "</table>\n";
    }
    h += "<h2>Test-plan areas</h2>\n<p>Functional coverage of each area (the FIG. or paragraph its bins cite), run by run, oldest left.</p>\n<table><tr><th>area</th><th>latest</th><th>runs</th></tr>\n";
    for (a, v) in &areas {
        let (hit, total) = v.last().map(|x| (x.1, x.2)).unwrap_or((0, 0));
        h += &format!(
            "<tr><td>{}</td><td class=\"{}\">{hit}/{total}</td><td>{}</td></tr>\n",
            esc(a),
            if hit == total { "ok" } else { "bad" },
            bars(v)
        );
    }
    h += "</table>\n<h2>Runs</h2>\n<table><tr><th>day</th><th>kind</th><th>host</th><th>RTL</th><th>seeds</th><th>pass</th><th>fail</th><th>error</th><th>coverage</th><th>line</th><th>toggle</th><th>sign-off</th><th>folder</th></tr>\n";
    for r in runs.iter().rev() {
        let pair = |p: Option<(u64, u64)>| {
            p.map(|(a, b)| format!("{a}/{b}"))
                .unwrap_or_else(|| "-".into())
        };
        h += &format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td><code>{}</code></td><td>{}</td><td>{}</td><td class=\"{}\">{}</td><td>{}</td><td>{}/{}</td><td>{}</td><td>{}</td><td>{}</td><td><code>{}</code></td></tr>\n",
            esc(&r.day),
            esc(&r.kind),
            esc(&r.host),
            esc(&r.rtl_hash.chars().take(19).collect::<String>()),
            r.seed_count,
            r.pass,
            if r.fail + r.error > 0 { "bad" } else { "ok" },
            r.fail,
            r.error,
            r.func_hit,
            r.func_total,
            pair(r.line),
            pair(r.toggle),
            match r.signoff_met {
                Some(true) => "met",
                Some(false) => "missed",
                None => "-",
            },
            esc(&r.folder)
        );
    }
    Ok(h + "</table>\n</body></html>\n")
}
