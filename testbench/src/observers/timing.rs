//! Timing diagram in the style of the patent's FIG. 15A-15C and 16A-16D ([0226]-[0258]).
//!
//! Rows, top to bottom: Sig (only when the key is on somewhere in the window), the timing signal
//! St ([0336]), the second sensor power Vs2 ([0206]), the sign signals Cs and Cc ([0086]-[0087]),
//! the change histories of Cs and Cc ([0237], [0240]), the power supply count CNTr ([0248]) and
//! the drive interval Si as a staircase in ms ([0199]). A detected rotation is marked with the
//! patent's reference signs: 100 where a change of Cs shortens the interval ([0226], FIG. 18 S23),
//! 101 where a change of Cc does ([0227], S28). A sign that changes back before the other one
//! has changed ([0232]-[0236], S21/S26: no shortening) is marked "Cs back" / "Cc back".
//!
//! The recorder is an [`Observer`]: it keeps only the ticks where a drawn signal changes, so a
//! long run costs little memory. Time is the absolute run time in ms.

use crate::plot::svg::{tick_label, ticks, Anchor, Svg};
use crate::sim::{Observer, SimError, TickView};
use pmu50_core::drive_interval_changing_56b::Fig18;
use std::collections::BTreeMap;
use std::fmt::Write as _;

/// The drawn signals during one tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct State {
    pub sig: bool,
    pub st: bool,
    pub vs2: bool,
    pub cs: bool,
    pub cc: bool,
    pub hist_s: bool,
    pub hist_c: bool,
    pub cnt_r: u8,
    /// Drive interval in ticks.
    pub si: u16,
}

/// A detected change, at the edge that makes it visible.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mark {
    pub tick: u64,
    pub label: &'static str,
}

impl Mark {
    /// The patent's reference signs are for the changes that shorten the interval.
    pub fn is_reference_sign(&self) -> bool {
        self.label == "100" || self.label == "101"
    }
}

/// Records the diagram's signals over the run or over a window of ticks [start, end).
pub struct TimingRecorder {
    window: Option<(u64, u64)>,
    clock_ns: u64,
    /// (tick, state from this tick on); the first row is the window start.
    pub rows: Vec<(u64, State)>,
    pub marks: Vec<Mark>,
    /// First and last tick drawn (the end is exclusive).
    pub start: u64,
    pub end: u64,
    /// Replay of skipped key-off periods: the stretch since the last period boundary (first
    /// tick, and per tick its state and label) and the last whole one.
    cur: Option<Drawn>,
    done: Option<Drawn>,
}

/// A stretch of ticks from a period boundary: its first tick, and per tick the drawn state and
/// the label of its edge.
type Drawn = (u64, Vec<(State, Option<&'static str>)>);

impl TimingRecorder {
    pub fn new(clock_ns: u64, window: Option<(u64, u64)>) -> TimingRecorder {
        TimingRecorder {
            window,
            clock_ns,
            rows: Vec::new(),
            marks: Vec::new(),
            start: window.map_or(0, |w| w.0),
            end: 0,
            cur: None,
            done: None,
        }
    }

    fn inside(&self, tick: u64) -> bool {
        self.window.is_none_or(|(a, b)| tick >= a && tick < b)
    }

    /// The stretches of equal `value` as (left x, right x, value), the last one ending at
    /// `right`: where a bus is drawn with its value, or a staircase step labelled.
    fn segments<T: PartialEq>(
        &self,
        value: impl Fn(&State) -> T,
        sx: impl Fn(f64) -> f64,
        right: f64,
    ) -> Vec<(f64, f64, T)> {
        let mut segs: Vec<(f64, f64, T)> = Vec::new();
        for (t, st) in &self.rows {
            let x = sx(self.ms(*t));
            let v = value(st);
            match segs.last_mut() {
                Some(l) if l.2 == v => {}
                Some(l) => {
                    l.1 = x;
                    segs.push((x, right, v));
                }
                None => segs.push((x, right, v)),
            }
        }
        segs
    }

    fn ms(&self, tick: u64) -> f64 {
        tick as f64 * self.clock_ns as f64 / 1e6
    }

    /// The rows and marks as CSV: one line per tick at which a signal changes.
    pub fn csv(&self) -> String {
        let mut by_tick: BTreeMap<u64, (State, Vec<&str>)> = BTreeMap::new();
        let mut cur = self.rows.first().map(|r| r.1).unwrap_or_default();
        let mut i = 0;
        let mut ticks_all: Vec<u64> = self
            .rows
            .iter()
            .map(|r| r.0)
            .chain(self.marks.iter().map(|m| m.tick))
            .collect();
        ticks_all.sort_unstable();
        ticks_all.dedup();
        for t in ticks_all {
            while i < self.rows.len() && self.rows[i].0 <= t {
                cur = self.rows[i].1;
                i += 1;
            }
            by_tick.insert(t, (cur, Vec::new()));
        }
        for m in &self.marks {
            if let Some(e) = by_tick.get_mut(&m.tick) {
                e.1.push(m.label);
            }
        }
        let mut s = String::from("time_ms,sig,st,vs2,cs,cc,hist_s,hist_c,cnt_r,si_ms,ref_sign\n");
        for (t, (st, marks)) in by_tick {
            let _ = writeln!(
                s,
                "{:.3},{},{},{},{},{},{},{},{},{:.3},{}",
                self.ms(t),
                u8::from(st.sig),
                u8::from(st.st),
                u8::from(st.vs2),
                u8::from(st.cs),
                u8::from(st.cc),
                u8::from(st.hist_s),
                u8::from(st.hist_c),
                st.cnt_r,
                self.ms(u64::from(st.si)),
                marks.join(" ")
            );
        }
        let _ = writeln!(s, "{:.3},,,,,,,,,,end", self.ms(self.end));
        s
    }

    /// The diagram as SVG.
    pub fn svg(&self, title: &str) -> String {
        let (t0, t1) = (self.ms(self.start), self.ms(self.end.max(self.start + 1)));
        let show_sig = self.rows.iter().any(|r| r.1.sig);
        let width = 1100.0;
        let label_w = 150.0;
        let right = width - 40.0;
        let plot_w = right - label_w;
        let sx = |t: f64| label_w + (t - t0) / (t1 - t0) * plot_w;
        let row_h = 34.0;
        let marks_top = 44.0;
        let rows_top = marks_top + 36.0;
        type Get = fn(&State) -> bool;
        let mut digital: Vec<(&str, Get)> = Vec::new();
        if show_sig {
            digital.push(("Sig (key on)", |s| s.sig));
        }
        digital.push(("St", |s| s.st));
        digital.push(("Vs2", |s| s.vs2));
        digital.push(("Cs", |s| s.cs));
        digital.push(("Cc", |s| s.cc));
        digital.push(("history of Cs", |s| s.hist_s));
        digital.push(("history of Cc", |s| s.hist_c));
        let bus_top = rows_top + row_h * digital.len() as f64;
        let si_top = bus_top + row_h + 14.0;
        let si_h = 150.0;
        let axis_y = si_top + si_h;
        let height = axis_y + 62.0;
        let mut svg = Svg::new(width, height);
        svg.text(width / 2.0, 24.0, 15.0, Anchor::Middle, "#000", title);

        // time grid
        let tt = ticks(t0, t1, 12);
        for v in &tt {
            svg.line(sx(*v), rows_top - 4.0, sx(*v), axis_y, "#ececec", 1.0, None);
        }

        // reference signs: dashed line through the rows, label at the top (two staggered levels
        // when labels would touch)
        let mut last_x = f64::NEG_INFINITY;
        let mut level = 0;
        for m in &self.marks {
            let x = sx(self.ms(m.tick));
            let color = if m.is_reference_sign() {
                "#C00000"
            } else {
                "#707070"
            };
            svg.line(x, marks_top + 4.0, x, axis_y, color, 1.0, Some("4 3"));
            let w = crate::plot::svg::text_width(m.label, 12.0) + 8.0;
            level = if x - last_x < w { 1 - level } else { 0 };
            last_x = x;
            let y = marks_top + 12.0 + 16.0 * level as f64;
            svg.rect(x - w / 2.0, y - 11.0, w, 15.0, "#ffffff", Some(color));
            svg.text(x, y, 12.0, Anchor::Middle, color, m.label);
        }

        // digital rows
        for (k, (name, get)) in digital.iter().enumerate() {
            let top = rows_top + row_h * k as f64;
            let hi = top + 7.0;
            let lo = top + row_h - 7.0;
            svg.text(label_w - 10.0, lo - 2.0, 12.0, Anchor::End, "#000", name);
            svg.line(label_w, lo, right, lo, "#d0d0d0", 0.5, None);
            let mut pts = Vec::new();
            let mut prev: Option<bool> = None;
            for (t, st) in &self.rows {
                let v = get(st);
                let x = sx(self.ms(*t));
                match prev {
                    None => pts.push((x, if v { hi } else { lo })),
                    Some(p) if p != v => {
                        pts.push((x, if p { hi } else { lo }));
                        pts.push((x, if v { hi } else { lo }));
                    }
                    _ => {}
                }
                prev = Some(v);
            }
            if let Some(p) = prev {
                pts.push((right, if p { hi } else { lo }));
            }
            svg.polyline(&pts, "#000", 1.4, None);
        }

        // CNTr as a bus with its value in each segment
        {
            let top = bus_top + 6.0;
            let bot = bus_top + row_h - 6.0;
            let mid = (top + bot) / 2.0;
            svg.text(label_w - 10.0, bot - 4.0, 12.0, Anchor::End, "#000", "CNTr");
            let segs = self.segments(|st| st.cnt_r, sx, right);
            for (a, b, v) in segs {
                let e = 2.5f64.min((b - a) / 2.0);
                svg.polyline(
                    &[
                        (a, mid),
                        (a + e, top),
                        (b - e, top),
                        (b, mid),
                        (b - e, bot),
                        (a + e, bot),
                        (a, mid),
                    ],
                    "#000",
                    1.2,
                    None,
                );
                let s = v.to_string();
                if b - a > crate::plot::svg::text_width(&s, 11.0) + 6.0 {
                    svg.text((a + b) / 2.0, mid + 4.0, 11.0, Anchor::Middle, "#000", &s);
                }
            }
        }

        // Si staircase in ms
        {
            let max_ms = self
                .rows
                .iter()
                .map(|r| self.ms(u64::from(r.1.si)))
                .fold(0.0, f64::max);
            let y1 = if max_ms > 0.0 {
                (max_ms * 1.15).max(1.0)
            } else {
                1.0
            };
            let sy = |v: f64| axis_y - v / y1 * si_h;
            svg.text(
                label_w - 26.0,
                si_top + si_h / 2.0 - 8.0,
                12.0,
                Anchor::End,
                "#000",
                "drive interval",
            );
            svg.text(
                label_w - 26.0,
                si_top + si_h / 2.0 + 8.0,
                12.0,
                Anchor::End,
                "#000",
                "Si (ms)",
            );
            let yt = ticks(0.0, y1, 5);
            for v in &yt {
                svg.line(label_w, sy(*v), right, sy(*v), "#e4e4e4", 1.0, None);
                svg.text(
                    label_w - 4.0,
                    sy(*v) + 4.0,
                    10.0,
                    Anchor::End,
                    "#404040",
                    &tick_label(*v, &yt),
                );
            }
            svg.line(label_w, si_top, label_w, axis_y, "#000", 1.0, None);
            let mut pts = Vec::new();
            let mut prev: Option<f64> = None;
            for (t, st) in &self.rows {
                let v = self.ms(u64::from(st.si));
                let x = sx(self.ms(*t));
                match prev {
                    None => pts.push((x, sy(v))),
                    Some(p) if (p - v).abs() > 1e-12 => {
                        pts.push((x, sy(p)));
                        pts.push((x, sy(v)));
                    }
                    _ => {}
                }
                prev = Some(v);
            }
            if let Some(p) = prev {
                pts.push((right, sy(p)));
            }
            svg.polyline(&pts, "#0072B2", 2.0, None);
            // value labels: one per step, where the step is wide enough to hold it
            let segs = self.segments(|st| st.si, sx, right);
            for (a, b, v) in segs {
                let ms = self.ms(u64::from(v));
                let s = format!("{ms:.1}");
                if b - a >= crate::plot::svg::text_width(&s, 11.0) + 6.0 {
                    svg.text(a + 3.0, sy(ms) - 5.0, 11.0, Anchor::Start, "#0072B2", &s);
                }
            }
        }

        // time axis
        svg.line(label_w, axis_y, right, axis_y, "#000", 1.0, None);
        for v in &tt {
            svg.line(sx(*v), axis_y, sx(*v), axis_y + 5.0, "#000", 1.0, None);
            svg.text(
                sx(*v),
                axis_y + 19.0,
                11.0,
                Anchor::Middle,
                "#000",
                &tick_label(*v, &tt),
            );
        }
        svg.text(
            label_w + plot_w / 2.0,
            axis_y + 42.0,
            12.0,
            Anchor::Middle,
            "#000",
            "time (ms)",
        );
        svg.text(
            label_w,
            axis_y + 42.0,
            10.0,
            Anchor::Start,
            "#C00000",
            "100 / 101: rotation detected through a change of Cs / Cc (FIG. 18 S23 / S28)",
        );
        svg.finish()
    }
}

impl TimingRecorder {
    /// One tick of the diagram: its state from this tick on and the label of its edge.
    fn draw(&mut self, tick: u64, st: State, label: Option<&'static str>) {
        if !self.inside(tick) {
            return;
        }
        if self.rows.last().is_none_or(|r| r.1 != st) {
            self.rows.push((tick, st));
        }
        self.end = tick + 1;
        if let Some(label) = label {
            if self.inside(tick + 1) {
                self.marks.push(Mark {
                    tick: tick + 1,
                    label,
                });
            }
        }
    }
}

impl Observer for TimingRecorder {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        let st = State {
            sig: v.ports.sig,
            st: v.ports.st,
            vs2: v.env.vs2_v > 0.0,
            cs: v.ports.cs,
            cc: v.ports.cc,
            hist_s: v.ports.hist_s,
            hist_c: v.ports.hist_c,
            cnt_r: v.ports.cnt_r,
            si: v.ports.si,
        };
        // The edge at the end of this tick: a detected change shows from tick + 1 on.
        let label = match v.internals.fig18 {
            Fig18::S23DetectedCs => Some("100"),
            Fig18::S28DetectedCc => Some("101"),
            Fig18::S21CsRepeat => Some("Cs back"),
            Fig18::S26CcRepeat => Some("Cc back"),
            _ => None,
        };
        self.draw(v.tick, st, label);
        if let Some((start, per)) = self.cur.as_mut() {
            if *start + per.len() as u64 == v.tick
                && (per.len() as u64) < crate::sim::replay::MAX_TICKS
            {
                per.push((st, label));
            } else {
                self.cur = None;
            }
        }
        Ok(())
    }

    /// The diagram replays skipped periods: it keeps each tick's state and label of the last
    /// whole period, and draws the copies as stepping would (only the ticks where the state
    /// changes, a label falls or the window starts do anything).
    fn replays_periods(&self) -> bool {
        true
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.done = self
            .cur
            .take()
            .filter(|(a, per)| !per.is_empty() && a + per.len() as u64 == k);
        self.cur = Some((k, Vec::new()));
        Ok(())
    }

    fn moving_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.period_boundary(k)?;
        // the period starting here is never replayed: nothing to keep of it
        self.cur = None;
        Ok(())
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.done
            .as_ref()
            .is_some_and(|(a, per)| a + len == k && per.len() as u64 == len)
    }

    fn replay(&mut self, k: u64, periods: u64, len: u64) -> Result<(), SimError> {
        self.cur = None;
        let Some((_, per)) = self.done.take() else {
            return Ok(());
        };
        let n = per.len();
        // Offsets where a tick does something once the tick before it was drawn: the state
        // changes (the first tick against the last one, the tick before it in the copy before)
        // or a label falls.
        let busy: Vec<usize> = (0..n)
            .filter(|&i| per[i].1.is_some() || per[i].0 != per[(i + n - 1) % n].0)
            .collect();
        let stop = k + periods * len;
        let (lo, hi) = match self.window {
            Some((a, z)) => (
                if a > k { (a - k) / len } else { 0 },
                if z > k {
                    (z - k).div_ceil(len).min(periods)
                } else {
                    0
                },
            ),
            None => (0, periods),
        };
        // The first tick drawn, when the window starts inside the skipped stretch.
        let first = self.window.map(|w| w.0).filter(|&a| a >= k && a < stop);
        for j in lo..hi {
            let base = k + j * len;
            let mut done_first = false;
            for &i in &busy {
                let t = base + i as u64;
                if let Some(a) = first.filter(|&a| !done_first && a < t && a >= base) {
                    let (st, label) = per[(a - base) as usize];
                    self.draw(a, st, label);
                    done_first = true;
                }
                done_first |= first == Some(t);
                let (st, label) = per[i];
                self.draw(t, st, label);
            }
            if let Some(a) = first.filter(|&a| !done_first && a >= base && a < base + len) {
                let (st, label) = per[(a - base) as usize];
                self.draw(a, st, label);
            }
        }
        // Every tick drawn sets the end: the last tick of the stretch inside the window.
        let last = self.window.map_or(stop, |(_, z)| z.min(stop));
        if last > k && self.inside(last - 1) {
            self.end = last;
        }
        Ok(())
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if self.rows.is_empty() {
            // nothing inside the window (e.g. it starts after the run): draw the final state
            self.start = v.tick;
            self.end = v.tick + 1;
            self.rows.push((v.tick, State::default()));
        }
        Ok(())
    }
}
