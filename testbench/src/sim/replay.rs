//! Replay of skipped key-off periods for observers that dump every tick (docs/spec.md 5.1): the waveform writer records what it dumped during the last whole period, and when the
//! bench skips `n` repeats of that period ([`super::skip`]) it emits `n` copies shifted by the
//! period instead of the bench evaluating them.
//!
//! [`PeriodRecorder`] keeps, for the period since the last boundary, the full value vector of
//! its first tick and, for every later tick, the list of slots whose value changed against the
//! tick before (`(slot, value)`, the value of a `real` as its bit pattern). Memory is bounded:
//! a stretch longer than [`MAX_TICKS`] ticks or with more than [`MAX_CHANGES`] changes is
//! dropped (the bench then steps, as without replay).
//!
//! Why a copy is exact: the bench skips only periods whose start state equals the one a period
//! earlier, with the same inputs ahead; every tick's view (registers, ports, inputs, internals,
//! analog values) is a deterministic function of them, so tick `b + j·len + i` of a skipped
//! stretch shows the values of tick `b - len + i`. The first tick of each copy follows the last
//! tick of the period before, whose values are the recorded period's last values: so the first
//! tick's changes of a copy are the recorded first values against the recorded last values.

/// Longest period recorded, in ticks (the drive interval `si` is at most 0xFFFF ticks).
pub const MAX_TICKS: u64 = 0x1_0000;
/// Most value changes recorded for one period (12 bytes each).
pub const MAX_CHANGES: usize = 1 << 20;

/// One recorded stretch of ticks from a boundary on.
#[derive(Debug, Default)]
struct Stretch {
    /// First tick.
    start: u64,
    /// The tick expected next (`start` + ticks recorded).
    next: u64,
    /// Values of the first tick.
    first: Vec<u64>,
    /// Ticks after the first with at least one change: (offset from `start`, end of its
    /// changes in `slots`/`values`).
    ticks: Vec<(u32, u32)>,
    slots: Vec<u32>,
    values: Vec<u64>,
    /// Contiguous and within the bounds.
    ok: bool,
}

impl Stretch {
    fn drop_data(&mut self) {
        self.ok = false;
        self.first = Vec::new();
        self.ticks = Vec::new();
        self.slots = Vec::new();
        self.values = Vec::new();
    }
}

/// The boundary hooks of an [`crate::sim::Observer`] that keeps its periods in a
/// [`PeriodRecorder`] field `$rec`: `period_boundary` and `moving_boundary` pass the boundary
/// to it (used inside the observer's `impl Observer`).
macro_rules! recorder_boundaries {
    ($rec:ident) => {
        fn period_boundary(&mut self, k: u64) -> Result<(), crate::sim::SimError> {
            self.$rec.boundary(k);
            Ok(())
        }

        fn moving_boundary(&mut self, k: u64) -> Result<(), crate::sim::SimError> {
            self.$rec.moving_boundary(k);
            Ok(())
        }
    };
}
pub(crate) use recorder_boundaries;

/// Records the per-tick values of one observer between period boundaries (see the module
/// documentation).
#[derive(Debug, Default)]
pub struct PeriodRecorder {
    /// Values of the last recorded tick.
    last: Vec<u64>,
    last_tick: Option<u64>,
    /// Recording: since the first boundary the bench announced, except after a
    /// [`PeriodRecorder::moving_boundary`] until the next boundary.
    active: bool,
    cur: Stretch,
    /// The last complete stretch from one boundary to the next.
    done: Option<Stretch>,
}

impl PeriodRecorder {
    pub fn new() -> PeriodRecorder {
        PeriodRecorder::default()
    }

    /// Whether the recorder records the ticks it is given: after a boundary the bench
    /// announced (before that nothing is recorded: a bench that steps every tick never does),
    /// unless it was a [`PeriodRecorder::moving_boundary`].
    pub fn active(&self) -> bool {
        self.active
    }

    /// A period boundary at tick `k` (before tick `k` is evaluated): the stretch since the
    /// previous boundary is complete if it saw every tick up to `k - 1`.
    pub fn boundary(&mut self, k: u64) {
        self.end_stretch(k);
        self.active = true;
        self.cur = Stretch {
            start: k,
            next: k,
            ok: true,
            ..Stretch::default()
        };
    }

    /// A boundary at tick `k` whose period is never replayed (the shaft moves in it,
    /// [`crate::sim::Observer::moving_boundary`]): the stretch since the previous boundary is
    /// complete as at [`PeriodRecorder::boundary`], and nothing is recorded until the next
    /// boundary (the ticks given meanwhile are ignored: the stretch that starts at the next
    /// boundary needs no tick before it, and a replay needs the tick just before it recorded).
    pub fn moving_boundary(&mut self, k: u64) {
        self.end_stretch(k);
        self.active = false;
    }

    fn end_stretch(&mut self, k: u64) {
        let cur = std::mem::take(&mut self.cur);
        self.done = (cur.ok && cur.next == k && cur.next > cur.start).then_some(cur);
    }

    /// The values dumped at tick `k` (same length every tick).
    pub fn record(&mut self, k: u64, values: &[u64]) {
        if self.active {
            self.add(k, values);
            self.last.clear();
            self.last.extend_from_slice(values);
        }
    }

    /// [`PeriodRecorder::record`] taking the values over: `values` is left with the recorder's
    /// spare buffer (of any content), for the caller to fill for the next tick.
    pub fn record_taking(&mut self, k: u64, values: &mut Vec<u64>) {
        if self.active {
            self.add(k, values);
            std::mem::swap(&mut self.last, values);
        }
    }

    /// The changes of tick `k` against the last recorded values, into the current stretch.
    fn add(&mut self, k: u64, values: &[u64]) {
        let c = &mut self.cur;
        if c.ok {
            if c.next != k || k - c.start >= MAX_TICKS {
                c.drop_data();
            } else if k == c.start {
                c.first.extend_from_slice(values);
            } else if self.last.len() != values.len() {
                c.drop_data();
            } else {
                let before = c.slots.len();
                for (i, (v, l)) in values.iter().zip(&self.last).enumerate() {
                    if v != l {
                        c.slots.push(i as u32);
                        c.values.push(*v);
                    }
                }
                if c.slots.len() > MAX_CHANGES {
                    c.drop_data();
                } else if c.slots.len() > before {
                    c.ticks.push(((k - c.start) as u32, c.slots.len() as u32));
                }
            }
            c.next = k + 1;
        }
        self.last_tick = Some(k);
    }

    /// Whether the stretch `[k - len, k)` is recorded whole, so that it can be replayed at `k`.
    pub fn can_replay(&self, k: u64, len: u64) -> bool {
        self.last_tick == Some(k.wrapping_sub(1))
            && self
                .done
                .as_ref()
                .is_some_and(|d| d.ok && d.next == k && d.next - d.start == len)
    }

    /// Replay `periods` copies of the recorded stretch `[k - len, k)` at ticks `k ..
    /// k + periods·len`: `emit(tick, changes)` for every tick with at least one change, in
    /// time order, with the (slot, value) pairs of that tick. Copies that lie wholly outside
    /// `window` (ticks `[a, z)`) are left out: they would only assign values that the copy before
    /// and after assign too, and write nothing. Call only after [`PeriodRecorder::can_replay`].
    pub fn replay<E>(
        &mut self,
        k: u64,
        periods: u64,
        len: u64,
        window: Option<(u64, u64)>,
        mut emit: impl FnMut(u64, &[(u32, u64)]) -> Result<(), E>,
    ) -> Result<(), E> {
        let Some(d) = self.done.as_ref().filter(|_| self.can_replay(k, len)) else {
            return Ok(());
        };
        // First tick of a copy: its values against the last tick of the copy before.
        let first: Vec<(u32, u64)> = d
            .first
            .iter()
            .zip(&self.last)
            .enumerate()
            .filter(|(_, (f, l))| f != l)
            .map(|(i, (f, _))| (i as u32, *f))
            .collect();
        // Copies j = 0 .. periods; copy j covers ticks [k + j·len, k + (j+1)·len).
        let (lo, hi) = match window {
            Some((a, z)) => {
                let lo = if a > k { (a - k) / len } else { 0 };
                let hi = if z > k {
                    (z - k).div_ceil(len).min(periods)
                } else {
                    0
                };
                (lo, hi)
            }
            None => (0, periods),
        };
        let mut buf: Vec<(u32, u64)> = Vec::new();
        for j in lo..hi {
            let base = k + j * len;
            if !first.is_empty() {
                emit(base, &first)?;
            }
            let mut from = 0usize;
            for &(off, end) in &d.ticks {
                let end = end as usize;
                buf.clear();
                buf.extend(
                    d.slots[from..end]
                        .iter()
                        .copied()
                        .zip(d.values[from..end].iter().copied()),
                );
                emit(base + u64::from(off), &buf)?;
                from = end;
            }
        }
        // The values after the replay are those of its last tick, the recorded last values:
        // `last` stays; the next stretch starts at the next boundary.
        self.last_tick = Some(k + periods * len - 1);
        self.cur.drop_data();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Replaying a recorded period gives the ticks that stepping would have given.
    #[test]
    fn replay_continues_a_periodic_sequence() {
        // Values of tick k: a period of 5 ticks after a transient of 7.
        let val = |k: u64| -> Vec<u64> {
            if k < 7 {
                vec![k, 100 + k, 9]
            } else {
                let i = (k - 7) % 5;
                vec![i, if i == 0 { 1 } else { 2 }, 9]
            }
        };
        // Ticks 0..17 recorded with boundaries at 7, 12 and 17: two whole periods seen.
        let recorded = || {
            let mut r = PeriodRecorder::new();
            for k in 0..17 {
                if k == 7 || k == 12 {
                    r.boundary(k);
                }
                r.record(k, &val(k));
            }
            r.boundary(17);
            r
        };
        let mut r = recorded();
        assert!(r.can_replay(17, 5));
        assert!(!r.can_replay(17, 4) && !r.can_replay(16, 5));
        let mut got: Vec<(u64, Vec<(u32, u64)>)> = Vec::new();
        r.replay::<()>(17, 3, 5, None, |t, c| {
            got.push((t, c.to_vec()));
            Ok(())
        })
        .unwrap();
        // Reference: the changes of stepping ticks 17..32.
        let mut want = Vec::new();
        for k in 17..32u64 {
            let (p, v) = (val(k - 1), val(k));
            let c: Vec<(u32, u64)> = p
                .iter()
                .zip(&v)
                .enumerate()
                .filter(|(_, (a, b))| a != b)
                .map(|(i, (_, b))| (i as u32, *b))
                .collect();
            if !c.is_empty() {
                want.push((k, c));
            }
        }
        assert_eq!(got, want);
        // A windowed replay leaves out the copies outside the window only.
        let mut r2 = recorded();
        let mut ticks = Vec::new();
        r2.replay::<()>(17, 3, 5, Some((23, 26)), |t, _| {
            ticks.push(t);
            Ok(())
        })
        .unwrap();
        assert!(
            ticks.iter().all(|&t| (22..27).contains(&t))
                && ticks.contains(&23)
                && ticks.contains(&25),
            "{ticks:?}"
        );
    }

    /// After a moving boundary nothing is recorded; the period that ended there still replays,
    /// the one that started there does not, and recording resumes at the next boundary.
    #[test]
    fn a_moving_boundary_ends_the_stretch_and_records_nothing_until_the_next() {
        let val = |k: u64| vec![k % 3, 7];
        let mut r = PeriodRecorder::new();
        r.boundary(0);
        for k in 0..3 {
            r.record(k, &val(k));
        }
        r.moving_boundary(3);
        assert!(r.can_replay(3, 3));
        assert!(!r.active());
        for k in 3..6 {
            r.record(k, &val(k));
        }
        assert!(r.cur.first.is_empty() && r.cur.slots.is_empty());
        r.boundary(6);
        assert!(!r.can_replay(6, 3), "the moving period was not recorded");
        for k in 6..9 {
            r.record(k, &val(k));
        }
        r.boundary(9);
        assert!(r.can_replay(9, 3));
        let mut got = Vec::new();
        r.replay::<()>(9, 1, 3, None, |t, c| {
            got.push((t, c.to_vec()));
            Ok(())
        })
        .unwrap();
        assert_eq!(
            got,
            vec![(9, vec![(0, 0)]), (10, vec![(0, 1)]), (11, vec![(0, 2)])]
        );
    }

    #[test]
    fn a_gap_or_an_overlong_stretch_is_not_replayable() {
        let mut r = PeriodRecorder::new();
        r.boundary(0);
        r.record(0, &[1]);
        r.record(2, &[2]); // tick 1 missing
        r.boundary(3);
        assert!(!r.can_replay(3, 3));
        let mut r = PeriodRecorder::new();
        r.boundary(0);
        for k in 0..=MAX_TICKS {
            r.record(k, &[k]);
        }
        r.boundary(MAX_TICKS + 1);
        assert!(!r.can_replay(MAX_TICKS + 1, MAX_TICKS + 1));
        assert!(r.cur.ok);
    }
}
