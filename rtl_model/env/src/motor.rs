//! Angle profile θ(t) of the motor rotation shaft 21.
//!
//! The patent's rotation number detection ([0084]-[0100]) and the key-off
//! monitoring ([0005], [0226]-[0228]) are driven by the mechanical angle of
//! the motor rotation shaft 21, which may turn while the ignition key is off
//! (e.g. the steering shaft is rotated by external force, [0005]). This module
//! provides that angle as a piecewise-linear function of time:
//!
//! * angle in degrees, multi-turn and unbounded (`f64`),
//! * time in integer nanoseconds (`u64`), starting at `t = 0`,
//! * segments [`Segment::Hold`] (constant angle) and [`Segment::Move`]
//!   (constant speed by `delta_deg` over `duration_ns`); after the last
//!   segment the angle holds at its final value.
//!
//! [`MotorProfile::angle_at`] is exact at segment boundaries (it returns the
//! pre-computed cumulative start angle of the segment, never an interpolated
//! value) and costs `O(log n)` per query (binary search over the segment start
//! times), so querying every 10 us tick for millions of ticks is cheap.

use serde::Deserialize;

/// One piece of the motor angle profile.
///
/// In a scenario file (internally tagged by `kind`):
/// `{ kind = "hold", duration_ns = 1000000 }` or
/// `{ kind = "move", duration_ns = 500000000, delta_deg = 720.0 }`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Segment {
    /// Angle constant for `duration_ns` (may be 0, then it is a no-op).
    Hold { duration_ns: u64 },
    /// Angle changes linearly by `delta_deg` (signed) over `duration_ns`
    /// (must be >= 1; a jump in angle is not physical).
    Move { duration_ns: u64, delta_deg: f64 },
}

impl Segment {
    /// Duration of the segment in ns.
    pub fn duration_ns(&self) -> u64 {
        match *self {
            Segment::Hold { duration_ns } | Segment::Move { duration_ns, .. } => duration_ns,
        }
    }

    /// Signed angle change over the segment in degrees.
    pub fn delta_deg(&self) -> f64 {
        match *self {
            Segment::Hold { .. } => 0.0,
            Segment::Move { delta_deg, .. } => delta_deg,
        }
    }
}

/// Scenario-file form of a motor profile.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorConfig {
    /// Shaft angle at `t = 0`, degrees (multi-turn).
    pub start_deg: f64,
    /// Segments, executed in order from `t = 0`.
    #[serde(default)]
    pub segments: Vec<Segment>,
}

/// Invalid motor profile.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MotorError {
    #[error("motor start_deg = {value} is invalid: must be a finite number of degrees")]
    NonFiniteStart { value: f64 },
    #[error(
        "motor segment {index} (Move): delta_deg = {value} is invalid: must be a finite number of degrees"
    )]
    NonFiniteDelta { index: usize, value: f64 },
    #[error(
        "motor segment {index} (Move): duration_ns = 0 is invalid: a Move needs duration_ns >= 1 \
         (an instantaneous angle jump is not physical; use a Hold for no motion)"
    )]
    ZeroDurationMove { index: usize },
    #[error(
        "motor segment {index}: cumulative end time overflows u64 nanoseconds; \
         the total of all duration_ns must be <= {max}",
        max = u64::MAX
    )]
    DurationOverflow { index: usize },
    #[error(
        "motor segment {index}: cumulative angle {value} deg is not finite; \
         the sum of all delta_deg must stay finite"
    )]
    NonFiniteCumulativeAngle { index: usize, value: f64 },
}

/// Validated piecewise-linear motor angle profile.
#[derive(Debug, Clone, PartialEq)]
pub struct MotorProfile {
    start_deg: f64,
    segments: Vec<Segment>,
    /// Start time of each segment (non-decreasing).
    seg_start_ns: Vec<u64>,
    /// Angle at the start of each segment (cumulative, exact at boundaries).
    seg_start_deg: Vec<f64>,
    end_ns: u64,
    end_deg: f64,
    /// The segment the last [`MotorProfile::angle_at`] found: a bench asks tick after tick,
    /// mostly inside the same segment or the next.
    hint: SegmentHint,
}

/// The index of a segment, a guess only ([`MotorProfile::segment_of`] checks it): part of no
/// comparison and kept by a clone. Atomic (relaxed) so a profile can be shared by threads.
#[derive(Debug, Default)]
struct SegmentHint(std::sync::atomic::AtomicUsize);

impl SegmentHint {
    fn get(&self) -> usize {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
    fn set(&self, i: usize) {
        self.0.store(i, std::sync::atomic::Ordering::Relaxed);
    }
}

impl Clone for SegmentHint {
    fn clone(&self) -> Self {
        SegmentHint(self.get().into())
    }
}

impl PartialEq for SegmentHint {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

impl MotorProfile {
    /// Builds a profile starting at `start_deg` at `t = 0`.
    pub fn new(start_deg: f64, segments: Vec<Segment>) -> Result<Self, MotorError> {
        if !start_deg.is_finite() {
            return Err(MotorError::NonFiniteStart { value: start_deg });
        }
        let mut seg_start_ns = Vec::with_capacity(segments.len());
        let mut seg_start_deg = Vec::with_capacity(segments.len());
        let mut t: u64 = 0;
        let mut a = start_deg;
        for (index, seg) in segments.iter().enumerate() {
            if let Segment::Move {
                duration_ns,
                delta_deg,
            } = *seg
            {
                if !delta_deg.is_finite() {
                    return Err(MotorError::NonFiniteDelta {
                        index,
                        value: delta_deg,
                    });
                }
                if duration_ns == 0 {
                    return Err(MotorError::ZeroDurationMove { index });
                }
            }
            seg_start_ns.push(t);
            seg_start_deg.push(a);
            t = t
                .checked_add(seg.duration_ns())
                .ok_or(MotorError::DurationOverflow { index })?;
            a += seg.delta_deg();
            if !a.is_finite() {
                return Err(MotorError::NonFiniteCumulativeAngle { index, value: a });
            }
        }
        Ok(Self {
            start_deg,
            segments,
            seg_start_ns,
            seg_start_deg,
            end_ns: t,
            end_deg: a,
            hint: SegmentHint::default(),
        })
    }

    /// A shaft that never moves.
    pub fn constant(angle_deg: f64) -> Result<Self, MotorError> {
        Self::new(angle_deg, Vec::new())
    }

    /// The largest shaft speed, in degrees per nanosecond, of the segments that overlap
    /// `[from_ns, to_ns)` (0 when the shaft holds throughout).
    pub fn max_speed_deg_per_ns(&self, from_ns: u64, to_ns: u64) -> f64 {
        let mut worst: f64 = 0.0;
        for (k, seg) in self.segments.iter().enumerate() {
            let start = self.seg_start_ns[k];
            if let Segment::Move {
                duration_ns,
                delta_deg,
            } = *seg
            {
                if start < to_ns && start + duration_ns > from_ns {
                    worst = worst.max(delta_deg.abs() / duration_ns.max(1) as f64);
                }
            }
        }
        worst
    }

    /// Shaft angle (degrees, multi-turn) at time `t_ns`.
    ///
    /// At a segment boundary the returned value is the cumulative start angle
    /// of the segment beginning there (`start_deg + Σ previous delta_deg`),
    /// bit-exact and independent of interpolation rounding. After the last
    /// segment the final angle is held.
    pub fn angle_at(&self, t_ns: u64) -> f64 {
        if t_ns >= self.end_ns {
            return self.end_deg;
        }
        self.angle_in(self.segment_of(t_ns), t_ns)
    }

    /// The angle at `t_ns` inside segment `i` (the segment active at `t_ns`).
    #[inline]
    fn angle_in(&self, i: usize, t_ns: u64) -> f64 {
        let elapsed = t_ns - self.seg_start_ns[i];
        match self.segments[i] {
            Segment::Hold { .. } => self.seg_start_deg[i],
            Segment::Move {
                duration_ns,
                delta_deg,
            } => {
                if elapsed == 0 {
                    self.seg_start_deg[i]
                } else {
                    self.seg_start_deg[i] + delta_deg * (elapsed as f64 / duration_ns as f64)
                }
            }
        }
    }

    /// The last segment whose start is <= `t_ns` (`t_ns < end_ns`, so there is one). Zero-length
    /// Holds share a start time with their successor; the successor (the one actually active)
    /// is the one. The hint's segment or the next when either is it, else a binary search:
    /// always the index `partition_point(|s| s <= t_ns) - 1`.
    #[inline]
    fn segment_of(&self, t_ns: u64) -> usize {
        let starts = &self.seg_start_ns;
        let h = self.hint.get();
        if h < starts.len() && starts[h] <= t_ns {
            // `h` is the last start <= t_ns when the next one is later (or there is none)
            match starts.get(h + 1) {
                None => return h,
                Some(&n) if n > t_ns => return h,
                Some(_) => {
                    if starts.get(h + 2).is_none_or(|&n| n > t_ns) {
                        self.hint.set(h + 1);
                        return h + 1;
                    }
                }
            }
        }
        let i = starts.partition_point(|&s| s <= t_ns) - 1;
        self.hint.set(i);
        i
    }

    /// "No change before t": the last time up to which the angle stays exactly (bit for bit)
    /// what it is at `t_ns`: `angle_at(u)` equals `angle_at(t_ns)` for every `u` in
    /// `[t_ns, constant_until_ns(t_ns)]`; `u64::MAX` when it never changes again. Inside a Move
    /// this is `t_ns` itself. Exact at segment boundaries (the cumulative start angles).
    pub fn constant_until_ns(&self, t_ns: u64) -> u64 {
        if t_ns >= self.end_ns {
            return u64::MAX;
        }
        let a = self.angle_at(t_ns).to_bits();
        let mut i = self.seg_start_ns.partition_point(|&s| s <= t_ns) - 1;
        if matches!(self.segments[i], Segment::Move { .. }) {
            return t_ns;
        }
        // A Hold: constant through its end, and through every following Hold at the same angle.
        loop {
            i += 1;
            if i == self.segments.len() {
                return if self.end_deg.to_bits() == a {
                    u64::MAX
                } else {
                    self.end_ns - 1
                };
            }
            // Every later segment starts after t_ns (partition_point took the last start <= t_ns).
            if self.seg_start_deg[i].to_bits() != a {
                return self.seg_start_ns[i] - 1;
            }
            if matches!(self.segments[i], Segment::Move { .. }) {
                // The Move starts at the held angle and leaves it right after its start.
                return self.seg_start_ns[i];
            }
        }
    }

    /// Largest absolute speed over all Move segments, deg/s (0 if none).
    pub fn max_speed_deg_per_s(&self) -> f64 {
        self.segments
            .iter()
            .filter_map(|s| match *s {
                Segment::Move {
                    duration_ns,
                    delta_deg,
                } => Some(delta_deg.abs() / (duration_ns as f64 * 1e-9)),
                Segment::Hold { .. } => None,
            })
            .fold(0.0, f64::max)
    }

    /// Angle at `t = 0`.
    pub fn start_deg(&self) -> f64 {
        self.start_deg
    }

    /// Time at which the last segment ends (the angle holds afterwards).
    pub fn end_ns(&self) -> u64 {
        self.end_ns
    }

    /// Angle held after the last segment.
    pub fn end_deg(&self) -> f64 {
        self.end_deg
    }

    /// The segments as given.
    pub fn segments(&self) -> &[Segment] {
        &self.segments
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn profile() -> MotorProfile {
        MotorProfile::new(
            10.0,
            vec![
                Segment::Hold { duration_ns: 1_000 },
                Segment::Move {
                    duration_ns: 3_000,
                    delta_deg: 0.3,
                },
                Segment::Hold { duration_ns: 0 },
                Segment::Move {
                    duration_ns: 7_000,
                    delta_deg: -1234.7,
                },
            ],
        )
        .unwrap()
    }

    #[test]
    fn exact_at_boundaries() {
        let p = profile();
        assert_eq!(p.angle_at(0), 10.0);
        assert_eq!(p.angle_at(1_000), 10.0);
        // Boundary after the first Move: exactly start + 0.3 (the same
        // floating-point sum the cumulative table uses), not an interpolation.
        assert_eq!(p.angle_at(4_000), 10.0 + 0.3);
        assert_eq!(p.angle_at(11_000), 10.0 + 0.3 - 1234.7);
        assert_eq!(p.end_deg(), 10.0 + 0.3 - 1234.7);
        assert_eq!(p.end_ns(), 11_000);
        // Holds after the end.
        assert_eq!(p.angle_at(11_001), p.end_deg());
        assert_eq!(p.angle_at(u64::MAX), p.end_deg());
    }

    #[test]
    fn linear_inside_move() {
        let p = profile();
        assert!((p.angle_at(2_500) - 10.15).abs() < 1e-12);
        assert!((p.angle_at(4_000 + 3_500) - (10.3 - 617.35)).abs() < 1e-9);
        assert_eq!(p.angle_at(999), 10.0);
    }

    #[test]
    fn boundaries_exact_over_many_segments() {
        // 10000 alternating moves of 0.1 deg: boundary values must equal the
        // running sum exactly, even though 0.1 is not representable.
        let segs: Vec<Segment> = (0..10_000)
            .map(|i| Segment::Move {
                duration_ns: 10_000 + i as u64,
                delta_deg: if i % 3 == 0 { -0.1 } else { 0.1 },
            })
            .collect();
        let p = MotorProfile::new(-5.0, segs.clone()).unwrap();
        let mut t = 0u64;
        let mut a = -5.0;
        for s in &segs {
            assert_eq!(p.angle_at(t), a);
            t += s.duration_ns();
            a += s.delta_deg();
        }
        assert_eq!(p.angle_at(t), a);
    }

    /// The angle by a binary search, as before the segment hint.
    fn searched(p: &MotorProfile, t_ns: u64) -> f64 {
        if t_ns >= p.end_ns {
            return p.end_deg;
        }
        p.angle_in(p.seg_start_ns.partition_point(|&s| s <= t_ns) - 1, t_ns)
    }

    proptest::proptest! {
        /// Whatever the hint holds (times forwards, backwards, at and around the boundaries,
        /// zero-length segments), `angle_at` is the binary search's angle, bit for bit.
        #[test]
        fn the_segment_hint_never_changes_an_angle(
            segs in proptest::collection::vec((0u64..4, 0u64..50, -400.0f64..400.0), 0..12),
            times in proptest::collection::vec(0u64..400, 1..200),
        ) {
            let segments: Vec<Segment> = segs
                .iter()
                .map(|&(kind, d, delta)| match kind {
                    0 => Segment::Hold { duration_ns: d },
                    _ => Segment::Move { duration_ns: d + 1, delta_deg: delta },
                })
                .collect();
            let p = MotorProfile::new(3.25, segments).unwrap();
            // a sweep forwards tick by tick, then the random times, then a clone's
            for t in (0..p.end_ns + 3).chain(times.iter().copied()) {
                proptest::prop_assert_eq!(p.angle_at(t).to_bits(), searched(&p, t).to_bits(), "t = {}", t);
            }
            let q = p.clone();
            proptest::prop_assert_eq!(&q, &p);
            for &t in times.iter().rev() {
                proptest::prop_assert_eq!(q.angle_at(t).to_bits(), searched(&p, t).to_bits(), "t = {}", t);
            }
        }
    }

    #[test]
    fn constant_until_agrees_with_angle_at() {
        let p = MotorProfile::new(
            5.0,
            vec![
                Segment::Hold { duration_ns: 100 },
                Segment::Hold { duration_ns: 0 },
                Segment::Hold { duration_ns: 50 },
                Segment::Move {
                    duration_ns: 30,
                    delta_deg: 2.5,
                },
                Segment::Hold { duration_ns: 40 },
                Segment::Move {
                    duration_ns: 20,
                    delta_deg: -2.5,
                },
            ],
        )
        .unwrap();
        assert_eq!(p.constant_until_ns(0), 150);
        assert_eq!(p.constant_until_ns(149), 150);
        assert_eq!(p.constant_until_ns(150), 150);
        assert_eq!(p.constant_until_ns(160), 160);
        assert_eq!(p.constant_until_ns(180), 220);
        assert_eq!(p.constant_until_ns(240), u64::MAX);
        // Brute force: the angle is constant up to the bound and changes right after it.
        for t in 0..260u64 {
            let u = p.constant_until_ns(t);
            let a = p.angle_at(t).to_bits();
            for v in t..=u.min(300) {
                assert_eq!(p.angle_at(v).to_bits(), a, "t={t} v={v} until={u}");
            }
            if u < 300 {
                assert_ne!(
                    p.angle_at(u + 1).to_bits(),
                    a,
                    "t={t} until={u} is not the last"
                );
            }
        }
        assert_eq!(
            MotorProfile::constant(1.0).unwrap().constant_until_ns(0),
            u64::MAX
        );
    }

    #[test]
    fn max_speed() {
        let p = profile();
        // 1234.7 deg in 7 us.
        let expect = 1234.7 / 7e-6;
        assert!((p.max_speed_deg_per_s() - expect).abs() / expect < 1e-12);
        assert_eq!(
            MotorProfile::constant(3.0).unwrap().max_speed_deg_per_s(),
            0.0
        );
    }

    #[test]
    fn rejects_bad_input() {
        assert!(matches!(
            MotorProfile::new(f64::NAN, vec![]),
            Err(MotorError::NonFiniteStart { .. })
        ));
        assert!(matches!(
            MotorProfile::new(f64::INFINITY, vec![]),
            Err(MotorError::NonFiniteStart { .. })
        ));
        assert_eq!(
            MotorProfile::new(
                0.0,
                vec![
                    Segment::Hold { duration_ns: 5 },
                    Segment::Move {
                        duration_ns: 0,
                        delta_deg: 1.0
                    }
                ]
            ),
            Err(MotorError::ZeroDurationMove { index: 1 })
        );
        assert!(matches!(
            MotorProfile::new(
                0.0,
                vec![Segment::Move {
                    duration_ns: 1,
                    delta_deg: f64::NAN
                }]
            ),
            Err(MotorError::NonFiniteDelta { index: 0, .. })
        ));
        assert_eq!(
            MotorProfile::new(
                0.0,
                vec![
                    Segment::Hold {
                        duration_ns: u64::MAX
                    },
                    Segment::Hold { duration_ns: 1 }
                ]
            ),
            Err(MotorError::DurationOverflow { index: 1 })
        );
        assert!(matches!(
            MotorProfile::new(
                0.0,
                vec![
                    Segment::Move {
                        duration_ns: 1,
                        delta_deg: f64::MAX
                    },
                    Segment::Move {
                        duration_ns: 1,
                        delta_deg: f64::MAX
                    }
                ]
            ),
            Err(MotorError::NonFiniteCumulativeAngle { index: 1, .. })
        ));
    }

    #[test]
    fn error_message_names_field_and_valid_range() {
        let e = MotorError::ZeroDurationMove { index: 3 }.to_string();
        assert!(e.contains("segment 3") && e.contains("duration_ns") && e.contains(">= 1"));
    }
}
