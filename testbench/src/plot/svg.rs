//! A small, deterministic SVG writer and a line/step chart on top of it.
//!
//! Hand-written rather than a plotting crate: every coordinate is printed with a fixed number of
//! decimals, elements come out in the order they are drawn, and nothing depends on the fonts
//! installed, so reruns are byte-identical and the snapshots in golden/ stay readable.

use std::fmt::Write as _;

/// Font stack used for every text element.
pub const FONT: &str = "DejaVu Sans, Verdana, Arial, sans-serif";

/// Colours of the series, in order (colour-blind friendly, Okabe-Ito).
pub const PALETTE: [&str; 8] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442",
];

/// Escape text for XML (`&`, `<`, `>`, `"`).
pub fn esc(s: &str) -> String {
    pmu50_coverage::ucis::xml_escape(s, false)
}

/// A coordinate with two decimals; `-0.00` is printed as `0.00`.
pub fn n(v: f64) -> String {
    let s = format!("{v:.2}");
    if s == "-0.00" {
        "0.00".into()
    } else {
        s
    }
}

/// An SVG document being drawn.
pub struct Svg {
    pub width: f64,
    pub height: f64,
    body: String,
}

/// Horizontal anchor of a text.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn as_str(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

impl Svg {
    pub fn new(width: f64, height: f64) -> Svg {
        Svg {
            width,
            height,
            body: String::new(),
        }
    }

    /// One `<line>`: the element's own attributes, in its order.
    #[allow(clippy::too_many_arguments)]
    pub fn line(
        &mut self,
        x1: f64,
        y1: f64,
        x2: f64,
        y2: f64,
        stroke: &str,
        width: f64,
        dash: Option<&str>,
    ) {
        let d = dash
            .map(|d| format!(" stroke-dasharray=\"{d}\""))
            .unwrap_or_default();
        let _ = writeln!(self.body, "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{stroke}\" stroke-width=\"{}\"{d}/>", n(x1), n(y1), n(x2), n(y2), n(width));
    }

    pub fn polyline(&mut self, pts: &[(f64, f64)], stroke: &str, width: f64, dash: Option<&str>) {
        if pts.is_empty() {
            return;
        }
        let mut p = String::new();
        for (i, (x, y)) in pts.iter().enumerate() {
            if i > 0 {
                p.push(' ');
            }
            p += &format!("{},{}", n(*x), n(*y));
        }
        let d = dash
            .map(|d| format!(" stroke-dasharray=\"{d}\""))
            .unwrap_or_default();
        let _ = writeln!(self.body, "<polyline points=\"{p}\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{}\" stroke-linejoin=\"miter\"{d}/>", n(width));
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: Option<&str>) {
        let s = stroke
            .map(|s| format!(" stroke=\"{s}\" stroke-width=\"1.00\""))
            .unwrap_or_default();
        let _ = writeln!(
            self.body,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\"{s}/>",
            n(x),
            n(y),
            n(w.max(0.0)),
            n(h.max(0.0))
        );
    }

    pub fn circle(&mut self, x: f64, y: f64, r: f64, fill: &str) {
        let _ = writeln!(
            self.body,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"{fill}\"/>",
            n(x),
            n(y),
            n(r)
        );
    }

    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, fill: &str, s: &str) {
        let _ = writeln!(
            self.body,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{}\" fill=\"{fill}\">{}</text>",
            n(x),
            n(y),
            n(size),
            anchor.as_str(),
            esc(s)
        );
    }

    /// Text rotated by -90 degrees around its anchor point (a y-axis label).
    pub fn text_vertical(&mut self, x: f64, y: f64, size: f64, s: &str) {
        let _ = writeln!(self.body, "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"middle\" fill=\"#000\" transform=\"rotate(-90 {} {})\">{}</text>", n(x), n(y), n(size), n(x), n(y), esc(s));
    }

    pub fn finish(self) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" font-family=\"{FONT}\">\n<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n{}</svg>\n",
            n(self.width),
            n(self.height),
            n(self.width),
            n(self.height),
            n(self.width),
            n(self.height),
            self.body
        )
    }
}

/// Rough width of a text in pixels (DejaVu Sans averages about 0.6 em per character).
pub fn text_width(s: &str, size: f64) -> f64 {
    s.chars().count() as f64 * size * 0.6
}

/// "Nice" tick positions covering [lo, hi]: steps of 1, 2 or 5 times a power of ten.
pub fn ticks(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        return vec![lo];
    }
    let raw = (hi - lo) / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil();
    let last = (hi / step + 1e-9).floor();
    let mut out = Vec::new();
    let mut k = first;
    while k <= last && out.len() < 1000 {
        let v = k * step;
        out.push(if v.abs() < step * 1e-9 { 0.0 } else { v });
        k += 1.0;
    }
    out
}

/// A tick label: as few decimals as the step needs.
pub fn tick_label(v: f64, ticks: &[f64]) -> String {
    let step = if ticks.len() > 1 {
        (ticks[1] - ticks[0]).abs()
    } else {
        1.0
    };
    let dec = if step >= 1.0 {
        0
    } else {
        (-step.log10()).ceil() as usize
    };
    let s = format!("{v:.dec$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    Line,
    /// Horizontal then vertical (a value held until the next point).
    Step,
    Dashed,
    /// Markers only.
    Points,
    /// Line with markers.
    LinePoints,
    /// A short dashed horizontal bar at each point (x +- 0.3), for category charts.
    Level,
}

#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub color: String,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

/// A line chart with linear axes.
#[derive(Clone, Debug)]
pub struct Chart {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub series: Vec<Series>,
    /// Vertical marker lines: (x, label, colour).
    pub vlines: Vec<(f64, String, String)>,
    /// Category labels under the x axis instead of numbers: (x, label).
    pub x_categories: Vec<(f64, String)>,
}

impl Chart {
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Chart {
        Chart {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_range: (0.0, 1.0),
            y_range: (0.0, 1.0),
            series: Vec::new(),
            vlines: Vec::new(),
            x_categories: Vec::new(),
        }
    }

    /// Ranges from the data, y from zero, with 5 % head room.
    pub fn auto_range(&mut self) {
        let pts = self.series.iter().flat_map(|s| s.points.iter());
        let (mut x0, mut x1, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
        for (x, y) in pts {
            x0 = x0.min(*x);
            x1 = x1.max(*x);
            y1 = y1.max(*y);
        }
        for (x, ..) in &self.vlines {
            x0 = x0.min(*x);
            x1 = x1.max(*x);
        }
        if !x0.is_finite() || x1 <= x0 {
            x0 = 0.0;
            x1 = 1.0;
        }
        if y1 <= 0.0 {
            y1 = 1.0;
        }
        self.x_range = (x0, x1);
        self.y_range = (0.0, y1 * 1.05);
    }

    /// Draw into the box (x, y, w, h) of `svg` (the box includes title, labels and legend).
    pub fn draw(&self, svg: &mut Svg, bx: f64, by: f64, bw: f64, bh: f64) {
        let left = bx + 78.0;
        let top = by + 34.0;
        // three legend entries per line, two when a name is long
        let per_line = if self
            .series
            .iter()
            .any(|s| text_width(&s.name, 11.0) > (bw - 94.0) / 3.0 - 34.0)
        {
            2
        } else {
            3
        };
        let legend_h = 18.0 * self.series.len().div_ceil(per_line) as f64;
        let right = bx + bw - 16.0;
        let bottom = by + bh - 46.0 - legend_h;
        let (w, h) = (right - left, bottom - top);
        svg.text(
            bx + bw / 2.0,
            by + 20.0,
            15.0,
            Anchor::Middle,
            "#000",
            &self.title,
        );
        let (x0, x1) = self.x_range;
        let (y0, y1) = self.y_range;
        let sx = |x: f64| left + (x - x0) / (x1 - x0) * w;
        let sy = |y: f64| bottom - (y - y0) / (y1 - y0) * h;
        // grid and ticks
        let yt = ticks(y0, y1, 6);
        for v in &yt {
            svg.line(left, sy(*v), right, sy(*v), "#e0e0e0", 1.0, None);
            svg.text(
                left - 6.0,
                sy(*v) + 4.0,
                11.0,
                Anchor::End,
                "#000",
                &tick_label(*v, &yt),
            );
        }
        if self.x_categories.is_empty() {
            let xt = ticks(x0, x1, 8);
            for v in &xt {
                svg.line(sx(*v), top, sx(*v), bottom, "#eeeeee", 1.0, None);
                svg.line(sx(*v), bottom, sx(*v), bottom + 4.0, "#000", 1.0, None);
                svg.text(
                    sx(*v),
                    bottom + 17.0,
                    11.0,
                    Anchor::Middle,
                    "#000",
                    &tick_label(*v, &xt),
                );
            }
        } else {
            for (v, l) in &self.x_categories {
                svg.line(sx(*v), bottom, sx(*v), bottom + 4.0, "#000", 1.0, None);
                svg.text(sx(*v), bottom + 17.0, 10.0, Anchor::Middle, "#000", l);
            }
        }
        svg.line(left, bottom, right, bottom, "#000", 1.0, None);
        svg.line(left, top, left, bottom, "#000", 1.0, None);
        svg.text(
            left + w / 2.0,
            bottom + 34.0,
            12.0,
            Anchor::Middle,
            "#000",
            &self.x_label,
        );
        svg.text_vertical(bx + 16.0, top + h / 2.0, 12.0, &self.y_label);
        for (x, _, color) in &self.vlines {
            if *x >= x0 && *x <= x1 {
                svg.line(sx(*x), top, sx(*x), bottom, color, 1.5, Some("6 4"));
            }
        }
        for s in &self.series {
            let clip = |(x, y): (f64, f64)| (sx(x.clamp(x0, x1)), sy(y.clamp(y0, y1)));
            let mut pts: Vec<(f64, f64)> = Vec::new();
            match s.style {
                Style::Step => {
                    for (i, p) in s.points.iter().enumerate() {
                        if i > 0 {
                            pts.push(clip((p.0, s.points[i - 1].1)));
                        }
                        pts.push(clip(*p));
                    }
                }
                _ => pts = s.points.iter().map(|p| clip(*p)).collect(),
            }
            match s.style {
                Style::Line | Style::Step => svg.polyline(&pts, &s.color, 2.0, None),
                Style::Dashed => svg.polyline(&pts, &s.color, 2.0, Some("8 5")),
                Style::Points => pts
                    .iter()
                    .for_each(|(x, y)| svg.circle(*x, *y, 3.0, &s.color)),
                Style::LinePoints => {
                    svg.polyline(&pts, &s.color, 1.5, None);
                    pts.iter()
                        .for_each(|(x, y)| svg.circle(*x, *y, 2.5, &s.color));
                }
                Style::Level => {
                    for p in &s.points {
                        let y = sy(p.1.clamp(y0, y1));
                        svg.line(
                            sx((p.0 - 0.3).max(x0)),
                            y,
                            sx((p.0 + 0.3).min(x1)),
                            y,
                            &s.color,
                            2.0,
                            Some("6 3"),
                        );
                    }
                }
            }
        }
        // marker labels over the data, at mid-height, one below the other so they never touch
        for (i, (x, label, color)) in self.vlines.iter().enumerate() {
            if *x < x0 || *x > x1 {
                continue;
            }
            let anchor = if sx(*x) > left + w * 0.7 {
                Anchor::End
            } else {
                Anchor::Start
            };
            let dx = if anchor == Anchor::End { -4.0 } else { 4.0 };
            let y = top + h * 0.4 + 16.0 * i as f64;
            let tw = text_width(label, 11.0);
            let bx0 = if anchor == Anchor::End {
                sx(*x) + dx - tw
            } else {
                sx(*x) + dx
            };
            svg.rect(bx0 - 2.0, y - 10.0, tw + 4.0, 13.0, "#ffffff", None);
            svg.text(sx(*x) + dx, y, 11.0, anchor, color, label);
        }
        // legend under the x label
        let col_w = w / per_line as f64;
        for (i, s) in self.series.iter().enumerate() {
            let lx = left + (i % per_line) as f64 * col_w;
            let ly = bottom + 52.0 + (i / per_line) as f64 * 18.0;
            match s.style {
                Style::Points => svg.circle(lx + 11.0, ly - 4.0, 3.0, &s.color),
                Style::Dashed | Style::Level => svg.line(
                    lx,
                    ly - 4.0,
                    lx + 22.0,
                    ly - 4.0,
                    &s.color,
                    2.0,
                    Some("6 3"),
                ),
                _ => svg.line(lx, ly - 4.0, lx + 22.0, ly - 4.0, &s.color, 2.0, None),
            }
            svg.text(lx + 28.0, ly, 11.0, Anchor::Start, "#000", &s.name);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round() {
        assert_eq!(ticks(0.0, 10.0, 5), vec![0.0, 2.0, 4.0, 6.0, 8.0, 10.0]);
        assert_eq!(ticks(0.0, 48.0, 8), vec![0.0, 10.0, 20.0, 30.0, 40.0]);
        let t = ticks(0.0, 0.7, 7);
        assert_eq!(tick_label(t[1], &t), "0.1");
    }

    #[test]
    fn text_is_escaped_and_numbers_fixed() {
        assert_eq!(esc("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
        assert_eq!(n(-0.0001), "0.00");
        assert_eq!(n(1.005), "1.00");
    }
}
