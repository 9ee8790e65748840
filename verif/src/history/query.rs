//! The history read back: the runs, the signatures with the first and last day each was seen,
//! each test-plan area's coverage run by run, and the soak of an RTL.

use super::db::{HistoryError, Sql};

/// `YYYY-MM-DD` of a time (UTC).
pub fn day_of(unix: i64) -> String {
    // civil from days (Howard Hinnant's algorithm)
    let z = unix.div_euclid(86_400) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    format!("{:04}-{m:02}-{d:02}", if m <= 2 { y + 1 } else { y })
}

/// A run as listed (the run table's columns).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Run {
    pub id: String,
    pub at_unix: i64,
    pub day: String,
    pub host: String,
    pub kind: String,
    pub folder: String,
    pub rtl_hash: String,
    pub seed_count: u64,
    pub pass: u64,
    pub fail: u64,
    pub error: u64,
    pub missing: u64,
    pub func_hit: u64,
    pub func_total: u64,
    pub line: Option<(u64, u64)>,
    pub toggle: Option<(u64, u64)>,
    pub signoff_met: Option<bool>,
}

impl Run {
    /// Every seed of the run passed, none missing.
    pub fn all_pass(&self) -> bool {
        self.seed_count > 0 && self.fail == 0 && self.error == 0 && self.missing == 0
    }
}

fn num(v: &Option<String>) -> u64 {
    v.as_deref().and_then(|s| s.parse().ok()).unwrap_or(0)
}

/// Every run, oldest first (by time, then id).
pub fn runs(db: &mut dyn Sql) -> Result<Vec<Run>, HistoryError> {
    let rows = db.query(
        "SELECT id, at_unix, day, host, kind, folder, rtl_hash, seed_count, pass, fail, error, \
         missing, func_hit, func_total, line_hit, line_total, toggle_hit, toggle_total, signoff_met \
         FROM pmu50_runs ORDER BY at_unix, id",
    )?;
    Ok(rows
        .into_iter()
        .map(|r| {
            let s = |i: usize| r.get(i).cloned().flatten().unwrap_or_default();
            let pair =
                |i: usize| match (r.get(i).cloned().flatten(), r.get(i + 1).cloned().flatten()) {
                    (Some(a), Some(b)) => Some((a.parse().unwrap_or(0), b.parse().unwrap_or(0))),
                    _ => None,
                };
            Run {
                id: s(0),
                at_unix: s(1).parse().unwrap_or(0),
                day: s(2),
                host: s(3),
                kind: s(4),
                folder: s(5),
                rtl_hash: s(6),
                seed_count: num(&r[7]),
                pass: num(&r[8]),
                fail: num(&r[9]),
                error: num(&r[10]),
                missing: num(&r[11]),
                func_hit: num(&r[12]),
                func_total: num(&r[13]),
                line: pair(14),
                toggle: pair(16),
                signoff_met: r[18].as_deref().map(|v| v == "1"),
            }
        })
        .collect())
}

/// Each signature: (signature, first run's day, last run's day, runs it was seen in).
pub fn signatures(db: &mut dyn Sql) -> Result<Vec<(String, String, String, u64)>, HistoryError> {
    let rows = db.query(
        "SELECT s.signature, MIN(r.day), MAX(r.day), COUNT(*) FROM pmu50_signatures s \
         JOIN pmu50_runs r ON r.id = s.run_id GROUP BY s.signature ORDER BY MIN(r.at_unix), s.signature",
    )?;
    Ok(rows
        .into_iter()
        .map(|r| {
            let s = |i: usize| r.get(i).cloned().flatten().unwrap_or_default();
            (s(0), s(1), s(2), s(3).parse().unwrap_or(0))
        })
        .collect())
}

/// One test-plan area's coverage over time: (area, [(day, hit, total)]).
pub type AreaSeries = (String, Vec<(String, u64, u64)>);

/// Per area, the coverage of each regression run in time order.
pub fn areas(db: &mut dyn Sql) -> Result<Vec<AreaSeries>, HistoryError> {
    let rows = db.query(
        "SELECT a.area, r.day, a.hit, a.total FROM pmu50_areas a JOIN pmu50_runs r ON r.id = a.run_id \
         WHERE r.kind <> 'signoff' ORDER BY a.area, r.at_unix, r.id",
    )?;
    let mut out: Vec<AreaSeries> = Vec::new();
    for r in rows {
        let s = |i: usize| r.get(i).cloned().flatten().unwrap_or_default();
        let area = s(0);
        if out.last().map(|(a, _)| a != &area).unwrap_or(true) {
            out.push((area.clone(), Vec::new()));
        }
        if let Some(last) = out.last_mut() {
            last.1
                .push((s(1), s(2).parse().unwrap_or(0), s(3).parse().unwrap_or(0)));
        }
    }
    Ok(out)
}

/// The soak of an RTL: the consecutive days, ending at the latest day with a regression of
/// `rtl_hash`, on each of which every regression of that RTL passed every seed (a day without
/// a run, or with a run below 100 %, ends the streak). Returns (days, last day).
pub fn soak(runs: &[Run], rtl_hash: &str) -> (u64, Option<String>) {
    let mut days: std::collections::BTreeMap<i64, bool> = Default::default();
    for r in runs
        .iter()
        .filter(|r| r.rtl_hash == rtl_hash && r.kind != "signoff")
    {
        let d = r.at_unix.div_euclid(86_400);
        let ok = days.entry(d).or_insert(true);
        *ok &= r.all_pass();
    }
    let Some((&last, _)) = days.iter().next_back() else {
        return (0, None);
    };
    let mut n = 0;
    let mut d = last;
    while days.get(&d) == Some(&true) {
        n += 1;
        d -= 1;
    }
    (n, Some(day_of(last * 86_400)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn days_are_utc_calendar_days() {
        assert_eq!(day_of(0), "1970-01-01");
        assert_eq!(day_of(951_782_400), "2000-02-29");
        assert_eq!(day_of(1_767_225_599), "2025-12-31");
        assert_eq!(day_of(-1), "1969-12-31");
    }
    fn run(day: i64, pass: u64, seeds: u64, hash: &str) -> Run {
        Run {
            id: format!("{day}{hash}"),
            at_unix: day * 86_400 + 7200,
            day: day_of(day * 86_400),
            host: "h".into(),
            kind: "regress".into(),
            folder: "f".into(),
            rtl_hash: hash.into(),
            seed_count: seeds,
            pass,
            fail: seeds - pass,
            error: 0,
            missing: 0,
            func_hit: 1,
            func_total: 1,
            line: None,
            toggle: None,
            signoff_met: None,
        }
    }

    #[test]
    fn the_soak_counts_consecutive_green_days_of_one_rtl() {
        let mut v: Vec<Run> = (0..5).map(|d| run(100 + d, 10, 10, "a")).collect();
        assert_eq!(soak(&v, "a").0, 5);
        // another RTL's runs do not count
        v.push(run(105, 10, 10, "b"));
        assert_eq!(soak(&v, "a").0, 5);
        // a failing run on the last day breaks the streak
        v.push(run(104, 9, 10, "a"));
        assert_eq!(soak(&v, "a").0, 0);
        // a day without a run breaks it too
        let v: Vec<Run> = [100, 101, 103, 104]
            .iter()
            .map(|d| run(*d, 3, 3, "a"))
            .collect();
        assert_eq!(soak(&v, "a").0, 2);
    }
}
