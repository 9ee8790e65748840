//! `report.html`: one static page, no script and no external resource (it works offline):
//! the regression's verdicts, the coverage of every group as a heat map (crosses as matrices),
//! what was never hit, the failures by signature with their repro folders, and the closure
//! curve (coverage against seeds) as an inline SVG.

use crate::curve::pct;
use crate::summary::scenario_closure;
use crate::summary::Summary;
use pmu50_coverage::{layout, model::crosses, model::POINTS};
use std::fmt::Write;

use pmu50_testbench::plot::svg::esc;

/// Heat colour of a hit count (none: red; then from amber to green on a log scale); grey for
/// an unreachable bin, blue-grey for a port-level bin not hit.
fn colour(hits: u64, unreachable: bool, port_only: bool) -> &'static str {
    if unreachable {
        return "#d9d9d9";
    }
    match hits {
        0 if port_only => "#c9d6e3",
        0 => "#f4a6a6",
        1..=2 => "#fbe3a0",
        3..=9 => "#d9ef8b",
        10..=99 => "#a6d96a",
        100..=9999 => "#66bd63",
        _ => "#1a9850",
    }
}

/// A closure curve: label, colour, (seeds, % of the bins scenario stimuli reach).
pub type Line<'a> = (&'a str, &'a str, Vec<(u64, f64)>);

/// An SVG of closure curves, seeds on a log axis.
pub fn curve_svg(curves: &[Line<'_>], title: &str) -> String {
    let (w, h, ml, mr, mt, mb) = (720.0, 360.0, 60.0, 20.0, 36.0, 48.0);
    let maxn = curves
        .iter()
        .flat_map(|c| c.2.last().map(|p| p.0))
        .max()
        .unwrap_or(1)
        .max(10) as f64;
    let lo = curves
        .iter()
        .flat_map(|c| c.2.first().map(|p| p.1))
        .fold(100.0f64, f64::min)
        .min(90.0);
    let y0 = (lo / 10.0).floor() * 10.0;
    let x = |n: f64| ml + (n.max(1.0).ln() / maxn.ln()) * (w - ml - mr);
    let y = |p: f64| mt + (100.0 - p) / (100.0 - y0) * (h - mt - mb);
    let mut s = String::new();
    let _ = write!(s, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\" font-size=\"12\">");
    let _ = write!(s, "<rect width=\"{w}\" height=\"{h}\" fill=\"white\"/><text x=\"{}\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">{}</text>", w / 2.0, esc(title));
    let mut p = 100.0;
    while p >= y0 - 1e-9 {
        let _ = write!(s, "<line x1=\"{ml}\" x2=\"{}\" y1=\"{:.1}\" y2=\"{:.1}\" stroke=\"#eee\"/><text x=\"{}\" y=\"{:.1}\" text-anchor=\"end\">{p:.0} %</text>", w - mr, y(p), y(p), ml - 6.0, y(p) + 4.0);
        p -= if 100.0 - y0 > 40.0 { 20.0 } else { 10.0 };
    }
    let mut n = 1.0;
    while n <= maxn * 1.0001 {
        let _ = write!(s, "<line x1=\"{:.1}\" x2=\"{:.1}\" y1=\"{mt}\" y2=\"{}\" stroke=\"#eee\"/><text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{n}</text>", x(n), x(n), h - mb, x(n), h - mb + 16.0);
        n *= 10.0;
    }
    let _ = write!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">seeds (log scale)</text>",
        (ml + w - mr) / 2.0,
        h - 10.0
    );
    let _ = write!(s, "<text x=\"14\" y=\"{}\" transform=\"rotate(-90 14 {})\" text-anchor=\"middle\">bins hit of those scenarios reach</text>", (mt + h - mb) / 2.0, (mt + h - mb) / 2.0);
    for (k, (label, col, pts)) in curves.iter().enumerate() {
        let mut d = String::new();
        for (i, (n, p)) in pts.iter().enumerate() {
            let _ = write!(
                d,
                "{}{:.1},{:.1}",
                if i == 0 { "M" } else { "L" },
                x(*n as f64),
                y(*p)
            );
        }
        let _ = write!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{col}\" stroke-width=\"2\"/>"
        );
        let ly = h - mb - 16.0 - 18.0 * (curves.len() - 1 - k) as f64;
        let _ = write!(s, "<line x1=\"{}\" x2=\"{}\" y1=\"{ly}\" y2=\"{ly}\" stroke=\"{col}\" stroke-width=\"3\"/><text x=\"{}\" y=\"{}\">{}</text>", w - mr - 230.0, w - mr - 205.0, w - mr - 200.0, ly + 4.0, esc(label));
    }
    s.push_str("</svg>\n");
    s
}

/// `pmu50 closure -o FILE.svg DIR...`: the closure curves of regression folders in one SVG, and
/// for each the seed at which every bin scenario stimuli reach was hit.
pub fn closure_cli(
    dirs: &[std::path::PathBuf],
    out: &std::path::Path,
) -> Result<String, crate::error::RegressError> {
    if dirs.is_empty() {
        return Err(crate::error::RegressError::Usage(
            "closure needs at least one regression folder".into(),
        ));
    }
    const COLOURS: [&str; 6] = [
        "#b2182b", "#2166ac", "#1b7837", "#762a83", "#e08214", "#4d4d4d",
    ];
    let mut curves = Vec::new();
    let mut text = String::new();
    for (k, d) in dirs.iter().enumerate() {
        let spec = crate::summary::read_spec(d)?;
        let s = Summary::build(spec.clone(), &[crate::summary::Source::of(d, &spec)])?;
        let c = s.curve.clone();
        let label = format!(
            "{} ({} seeds)",
            if s.spec.directed {
                "directed"
            } else {
                "uniform random"
            },
            s.seeds()
        );
        match c.iter().find(|(_, p)| *p >= 100.0 - 1e-9) {
            Some((n, _)) => text.push_str(&format!(
                "{}: {label}: every bin scenario stimuli reach hit at seed {n}\n",
                d.display()
            )),
            None => text.push_str(&format!(
                "{}: {label}: {:.1} % of the bins scenario stimuli reach after {} seeds\n",
                d.display(),
                c.last().map_or(0.0, |p| p.1),
                s.seeds()
            )),
        }
        curves.push((label, COLOURS[k % COLOURS.len()], c));
    }
    let refs: Vec<Line<'_>> = curves
        .iter()
        .map(|(l, c, v)| (l.as_str(), *c, v.clone()))
        .collect();
    let svg = curve_svg(&refs, "coverage closure: bins hit against seeds");
    let mut b = pmu50_testbench::atomic_file::Batch::new();
    b.add(pmu50_testbench::atomic_file::write_atomic(
        out,
        svg.as_bytes(),
    )?);
    b.commit()?;
    text.push_str(&format!("wrote {}\n", out.display()));
    Ok(text)
}

/// The page.
/// What the report says of the DUT beside its name: the map, what the RTL fixes and the knobs
/// that are therefore not drawn (docs/hdl-guide.md, "Your RTL").
fn dut_notes(spec: &crate::spec::RunSpec) -> String {
    let mut n = String::new();
    if let Some(m) = &spec.map {
        n.push_str(&format!(
            "; registers and internals of the map {} compared beside the ports",
            esc(m)
        ));
    } else if crate::dut::of(&spec.dut).is_ok_and(|b| b.caps.rtl) {
        n.push_str("; the output ports compared after every edge");
    }
    if !spec.pool.is_empty() {
        // build modes: the pool of parameter sets the seeds drew from
        n.push_str(&format!(
            "<br>parameter sets: a pool of {} (at most {}, <code>--param-sets</code>), each built once, the seeds spread over them:<ol style=\"margin:0\">",
            spec.pool.len(),
            spec.param_sets
        ));
        for set in &spec.pool {
            n.push_str(&format!("<li><code>{}</code></li>", esc(&set.text())));
        }
        n.push_str("</ol>");
    }
    if !spec.fixed.is_empty() {
        let off: Vec<String> = crate::gen::knobs_off(&spec.fixed)
            .iter()
            .map(|k| format!("{k:?}"))
            .collect();
        n.push_str(&format!("<br>the RTL fixes {} (its top lacks these parameters; read back through the bus after reset): every seed keeps them", esc(&spec.fixed.text())));
        if !off.is_empty() {
            n.push_str(&format!(
                "<br>knobs not drawn (they need another value of a fixed parameter): {}",
                esc(&off.join(", "))
            ));
        }
    }
    n
}

/// `repros`: the signatures whose folder `failures/<signature>/` holds a repro (linked), each
/// with the SVG picture of its divergence when there is one (inlined).
pub fn html(
    s: &Summary,
    extra: Option<&str>,
    repros: &std::collections::BTreeMap<String, Option<String>>,
    signoff: Option<&str>,
) -> String {
    let l = layout();
    let c = &s.coverage;
    let (hit, reachable) = c.closure();
    let (shit, sreach) = scenario_closure(c);
    let mut h = String::new();
    let spec = &s.spec;
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>pmu50 regress: seeds {}..{}</title>\n<style>\
body{{font-family:sans-serif;margin:1.5em;color:#222}}table{{border-collapse:collapse;margin:.4em 0 1em}}td,th{{border:1px solid #bbb;padding:2px 6px;font-size:13px}}\
th{{background:#f2f2f2}}.bin{{display:inline-block;min-width:7em;margin:1px;padding:2px 4px;border:1px solid #999;font-size:12px}}\
.mx td{{text-align:right;min-width:2.5em}}.ok{{color:#1a7f37}}.bad{{color:#b3261e}}code{{background:#f6f6f6;padding:0 3px}}\
</style></head><body>\n<h1>pmu50 regress</h1>\n",
        spec.start_seed,
        spec.start_seed + spec.iterations.saturating_sub(1)
    );
    if let Some(t) = signoff {
        h.push_str(t);
    }
    let pass = s.pass;
    let _ = writeln!(
        h,
        "<table><tr><th>seeds</th><td>{} of {} (from {}){}</td></tr><tr><th>generator</th><td>{}</td></tr><tr><th>DUT</th><td>{}{}</td></tr>\
<tr><th>verdicts</th><td><span class=\"ok\">{pass} pass</span>, <span class=\"bad\">{} fail, {} error</span></td></tr>\
<tr><th>coverage</th><td>{hit} of {reachable} reachable bins ({:.1} %); {shit} of the {sreach} that scenario stimuli reach ({:.1} %); {} bins declared unreachable</td></tr></table>",
        s.seeds(),
        spec.iterations,
        spec.start_seed,
        match s.missing.first() {
            None => String::new(),
            Some(m) => format!(", <b class=\"bad\">{} missing</b> (first {})", s.missing_count(), m.start),
        },
        if spec.directed { "directed (biased towards empty bins)" } else { "uniform random" },
        format!("{:?}", spec.dut).to_lowercase(),
        spec.rtl.as_deref().map(|r| format!(", RTL {}", esc(r))).unwrap_or_default() + &dut_notes(spec),
        s.fail,
        s.error,
        pct(hit, reachable),
        pct(shit, sreach),
        l.bins.iter().filter(|b| b.unreachable.is_some()).count(),
    );

    // Failures.
    let _ = writeln!(h, "<h2>Failures by signature</h2>");
    if s.groups.is_empty() {
        h.push_str("<p class=\"ok\">No failure.</p>\n");
    } else {
        h.push_str("<table><tr><th>signature</th><th>seeds</th><th>smallest</th><th>first failure</th><th>repro</th></tr>\n");
        for (sig, g) in &s.groups {
            let f = &g.failure;
            let what = format!(
                "tick {}: {} expected {} got {} — {}",
                f.tick,
                esc(&f.signal),
                esc(&f.expected),
                esc(&f.got),
                esc(&f.detail)
            );
            let repro = if repros.contains_key(sig) {
                format!("<a href=\"failures/{0}/failure.txt\">failure</a> <a href=\"failures/{0}/repro.toml\">repro.toml</a> <a href=\"failures/{0}/repro.gtkw\">repro.gtkw</a> <a href=\"failures/{0}/divergence.svg\">divergence.svg</a><br>waves: <code>gtkwave failures/{0}/repro.vcd failures/{0}/repro.gtkw</code>", esc(sig))
            } else {
                "no repro folder (not shrunk: an error, or a run with <code>--no-triage</code>)"
                    .to_string()
            };
            let _ = writeln!(h, "<tr><td><code>{}</code></td><td>{}</td><td>{}</td><td>{what}</td><td>{repro}</td></tr>", esc(sig), g.count, g.smallest);
            // the picture of the shrunk repro around the first divergence, inline
            if let Some(Some(svg)) = repros.get(sig) {
                let _ = writeln!(h, "<tr><td colspan=\"5\" class=\"picture\">{svg}</td></tr>");
            }
        }
        h.push_str("</table>\n");
    }

    // Code coverage of the RTL (verif/src/code_cov/).
    if let Some(code) = &s.code {
        h.push_str(&crate::code_cov::render_html(code));
    }

    // Closure curve.
    let curve = s.curve.clone();
    if !curve.is_empty() {
        h.push_str("<h2>Closure</h2>\n");
        h.push_str(&curve_svg(
            &[(
                if spec.directed {
                    "directed"
                } else {
                    "uniform random"
                },
                "#2166ac",
                curve,
            )],
            "coverage against seeds",
        ));
    }
    if let Some(x) = extra {
        h.push_str(x);
    }

    // Never hit.
    let never: Vec<&pmu50_coverage::BinInfo> = l
        .bins
        .iter()
        .zip(&c.bins)
        .filter(|(b, r)| r.hits == 0 && b.unreachable.is_none())
        .map(|(b, _)| b)
        .collect();
    let _ = writeln!(h, "<h2>Never hit ({})</h2>", never.len());
    if never.is_empty() {
        h.push_str("<p class=\"ok\">Every reachable bin was hit.</p>\n");
    } else {
        h.push_str("<table><tr><th>bin</th><th>cites</th><th>meaning</th></tr>\n");
        for b in &never {
            let _ = writeln!(
                h,
                "<tr><td><code>{}</code>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&b.name),
                if b.port_only {
                    " (port-level stimuli)"
                } else {
                    ""
                },
                esc(b.cite),
                esc(&b.meaning)
            );
        }
        h.push_str("</table>\n");
    }

    // Heat map: points.
    h.push_str("<h2>Coverage by group</h2>\n<p>Colours: red never hit, amber 1-2 hits, then greener with more; grey declared unreachable (the reason is the tooltip); blue-grey reached only by port-level stimuli (cocotb, DPI).</p>\n");
    let mut group = "";
    for (pi, p) in POINTS.iter().enumerate() {
        if p.group != group {
            group = p.group;
            let _ = writeln!(h, "<h3>{}</h3>", esc(group));
        }
        let off = l.point_offset[pi];
        let _ = write!(
            h,
            "<p><b>{}.{}</b> — {} <i>({})</i><br>",
            esc(p.group),
            esc(p.name),
            esc(p.meaning),
            esc(p.cite)
        );
        for (k, b) in p.bins.iter().enumerate() {
            let info = &l.bins[off + k];
            let hits = c.bins[off + k].hits;
            let tip = info
                .unreachable
                .map(|r| format!("unreachable: {r}"))
                .unwrap_or_else(|| info.meaning.clone());
            let _ = write!(
                h,
                "<span class=\"bin\" style=\"background:{}\" title=\"{}\">{} <b>{hits}</b></span>",
                colour(hits, info.unreachable.is_some(), info.port_only),
                esc(&tip),
                esc(b.name)
            );
        }
        h.push_str("</p>\n");
    }
    // Crosses as matrices.
    h.push_str("<h3>crosses</h3>\n");
    for (ci, x) in crosses().enumerate() {
        let (pa, pb) = (&POINTS[x.rows], &POINTS[x.columns]);
        let off = l.cross_offset[ci];
        let _ = write!(h, "<p><b>cross.{}</b> — {} <i>({})</i></p><table class=\"mx\"><tr><th>{}.{} \\ {}.{}</th>", esc(x.name), esc(x.meaning), esc(x.cite), pa.group, pa.name, pb.group, pb.name);
        for b in pb.bins {
            let _ = write!(h, "<th>{}</th>", esc(b.name));
        }
        h.push_str("</tr>\n");
        for (i, a) in pa.bins.iter().enumerate() {
            let _ = write!(h, "<tr><th>{}</th>", esc(a.name));
            for j in 0..pb.bins.len() {
                let k = off + i * pb.bins.len() + j;
                let info = &l.bins[k];
                let hits = c.bins[k].hits;
                let tip = info
                    .unreachable
                    .map(|r| format!("unreachable: {r}"))
                    .unwrap_or_else(|| info.name.clone());
                let shown = if info.unreachable.is_some() {
                    "—".to_string()
                } else {
                    hits.to_string()
                };
                let _ = write!(
                    h,
                    "<td style=\"background:{}\" title=\"{}\">{shown}</td>",
                    colour(hits, info.unreachable.is_some(), info.port_only),
                    esc(&tip)
                );
            }
            h.push_str("</tr>\n");
        }
        h.push_str("</table>\n");
    }
    let _ = writeln!(
        h,
        "<p>Coverage model <code>{}</code>; {} bins. Generated by pmu50 {}.</p>\n</body></html>",
        esc(&c.model),
        l.bins.len(),
        env!("CARGO_PKG_VERSION")
    );
    h
}
