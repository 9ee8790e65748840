//! Key events of a run, for GTKWave's named markers in the `.gtkw` save file.
//!
//! | marker name | placed at | meaning |
//! |---|---|---|
//! | `key on`, `key off` | the tick the ignition input `ig` changes | key edges ([0205]) |
//! | `rotation cs` | the key-off sampling edge where FIG. 18 S23 detects a rotation through Cs ([0232]) | |
//! | `rotation cc` | the edge where FIG. 18 S28 detects a rotation through Cc | |
//! | `si 4.4 ms` | the edge where the drive interval `si` takes a new value (FIG. 17, [0226]-[0258]) | new value |
//!
//! Events at the same instant share one marker, their names joined by `, `
//! (`rotation cs, si 4.4 ms`). GTKWave 3.3 has 26 named markers (A-Z): when a run has more
//! events, the key edges are kept and the rest are the earliest; the save file says how many
//! were left out.

use crate::sim::{Observer, SimError, TickView};
use pmu50_core::drive_interval_changing_56b::Fig18;

/// GTKWave's number of named markers (A-Z).
pub const MAX_MARKERS: usize = 26;

#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Marker {
    /// Tick (time = tick · clock).
    pub tick: u64,
    pub name: String,
    /// A key edge (kept first when there are more than [`MAX_MARKERS`]).
    pub key: bool,
}

/// Observer collecting the key events of a run.
pub struct MarkerObserver {
    clock_ns: u64,
    prev_ig: bool,
    prev_si: Option<u16>,
    events: Vec<Marker>,
    /// Marker events pushed so far (a push may join an existing marker).
    pushes: u64,
    /// Replay of skipped periods: the stretch since the last period boundary (first tick, tick
    /// expected next, pushes before it), and the last whole stretch without an event.
    cur: Option<(u64, u64, u64)>,
    quiet: Option<(u64, u64)>,
}

impl MarkerObserver {
    pub fn new(clock_ns: u64) -> MarkerObserver {
        MarkerObserver {
            clock_ns,
            prev_ig: false,
            prev_si: None,
            events: Vec::new(),
            pushes: 0,
            cur: None,
            quiet: None,
        }
    }

    fn push(&mut self, tick: u64, name: String, key: bool) {
        self.pushes += 1;
        match self.events.iter_mut().find(|m| m.tick == tick) {
            Some(m) => {
                m.name = format!("{}, {name}", m.name);
                m.key |= key;
            }
            None => self.events.push(Marker { tick, name, key }),
        }
    }

    /// Markers within `[start, end]` ticks, at most [`MAX_MARKERS`], in time order, and the number
    /// left out.
    pub fn markers(&self, window: Option<(u64, u64)>) -> (Vec<Marker>, usize) {
        let mut inside: Vec<Marker> = self
            .events
            .iter()
            .filter(|m| window.is_none_or(|(a, z)| m.tick >= a && m.tick <= z))
            .cloned()
            .collect();
        inside.sort_by_key(|m| m.tick);
        let total = inside.len();
        if total <= MAX_MARKERS {
            return (inside, 0);
        }
        let keys = inside.iter().filter(|m| m.key).count().min(MAX_MARKERS);
        let mut room = MAX_MARKERS - keys;
        let mut kept_keys = 0;
        let kept: Vec<Marker> = inside
            .into_iter()
            .filter(|m| {
                if m.key && kept_keys < keys {
                    kept_keys += 1;
                    true
                } else if !m.key && room > 0 {
                    room -= 1;
                    true
                } else {
                    false
                }
            })
            .collect();
        let left = total - kept.len();
        (kept, left)
    }
}

impl Observer for MarkerObserver {
    fn tick(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        self.cur = self
            .cur
            .filter(|c| c.1 == v.tick)
            .map(|(a, n, p)| (a, n + 1, p));
        if v.inputs.ig != self.prev_ig {
            self.prev_ig = v.inputs.ig;
            self.push(
                v.tick,
                if v.inputs.ig {
                    "key on".into()
                } else {
                    "key off".into()
                },
                true,
            );
        }
        if self.prev_si.is_some_and(|p| p != v.ports.si) {
            let ms = f64::from(v.ports.si) * self.clock_ns as f64 / 1e6;
            self.push(v.tick, format!("si {ms:.1} ms"), false);
        }
        self.prev_si = Some(v.ports.si);
        // The sample is taken at the edge that ends this tick.
        match v.internals.fig18 {
            Fig18::S23DetectedCs => self.push(v.tick + 1, "rotation cs".into(), false),
            Fig18::S28DetectedCc => self.push(v.tick + 1, "rotation cc".into(), false),
            _ => {}
        }
        Ok(())
    }

    fn finish(&mut self, v: &TickView<'_>) -> Result<(), SimError> {
        if self.prev_si.is_some_and(|p| p != v.ports.si) {
            let ms = f64::from(v.ports.si) * self.clock_ns as f64 / 1e6;
            self.push(v.tick, format!("si {ms:.1} ms"), false);
        }
        // Rotations detected at the last edge belong at tick `ticks`, already pushed.
        Ok(())
    }

    /// A skipped period is replayed when the last one pushed no event: then its copies push
    /// none either (the key level and `si` stay those of the tick before the period, and no
    /// rotation is detected), and nothing is left to do.
    fn replays_periods(&self) -> bool {
        true
    }

    fn period_boundary(&mut self, k: u64) -> Result<(), SimError> {
        self.quiet = self
            .cur
            .filter(|&(a, n, p)| n == k && n > a && p == self.pushes)
            .map(|(a, _, _)| (a, k));
        self.cur = Some((k, k, self.pushes));
        Ok(())
    }

    fn can_replay(&self, k: u64, len: u64) -> bool {
        self.quiet.is_some_and(|(a, z)| z == k && z - a == len)
    }

    fn replay(&mut self, _k: u64, _periods: u64, _len: u64) -> Result<(), SimError> {
        self.cur = None;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn over_26_events_keep_key_edges_then_the_earliest() {
        let mut m = MarkerObserver::new(10_000);
        for t in 0..40 {
            m.push(t * 10, format!("e{t}"), t % 10 == 9);
        }
        m.push(30, "same".into(), false);
        let (kept, left) = m.markers(None);
        assert_eq!(kept.len(), MAX_MARKERS);
        assert_eq!(left, 40 - MAX_MARKERS);
        assert!(kept.iter().any(|k| k.name == "e39"), "key edges are kept");
        assert_eq!(
            kept.iter().find(|k| k.tick == 30).map(|k| k.name.as_str()),
            Some("e3, same")
        );
        assert!(kept.windows(2).all(|w| w[0].tick < w[1].tick));
        let (w, _) = m.markers(Some((100, 200)));
        assert_eq!(w.first().map(|k| k.tick), Some(100));
        assert_eq!(w.last().map(|k| k.tick), Some(200));
    }
}
