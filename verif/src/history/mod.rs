//! The history of regressions, merges and sign-offs (docs/verification.md, "History"): one
//! record per run in a database, SQLite by default (a file), PostgreSQL when a team shares one
//! (`postgres://user[:password]@host[:port]/db`). Both take the same SQL text, built here once
//! ([`schema`], [`insert`], the queries); only the transport differs ([`Sql`]: `sqlite`, `pg`).
//!
//! A record is written in one transaction: its run row and its signatures, sign-off rows and
//! coverage areas, all or nothing, so concurrent writers (the shards of one regression, two
//! regressions) never lose or tear one. Where the database is: `--history`, else
//! `PMU50_HISTORY`, else `history.sqlite` beside the run's folder; `PMU50_HISTORY=off` turns
//! recording off.

mod db;
mod html;
mod pg;
pub mod query;
mod sqlite;

pub use db::{HistoryError, Sql};
pub use html::dashboard;
pub use query::{day_of, runs, soak, Run};

use crate::summary::Summary;
use std::path::{Path, PathBuf};

/// Where the history is: a SQLite file or a PostgreSQL URL.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Location {
    Sqlite(PathBuf),
    Postgres(String),
}

impl Location {
    pub fn parse(s: &str) -> Location {
        if s.starts_with("postgres://") || s.starts_with("postgresql://") {
            Location::Postgres(s.to_string())
        } else {
            Location::Sqlite(PathBuf::from(s))
        }
    }

    /// `--history`, else `PMU50_HISTORY`, else `history.sqlite` beside `folder` (`None`: off).
    pub fn choose(given: Option<&str>, folder: &Path) -> Option<Location> {
        let env = std::env::var("PMU50_HISTORY")
            .ok()
            .filter(|v| !v.is_empty());
        match given.map(str::to_string).or(env) {
            Some(v) if v == "off" => None,
            Some(v) => Some(Location::parse(&v)),
            None => {
                let parent = folder
                    .parent()
                    .filter(|p| !p.as_os_str().is_empty())
                    .unwrap_or(Path::new("."));
                Some(Location::Sqlite(parent.join("history.sqlite")))
            }
        }
    }

    pub fn text(&self) -> String {
        match self {
            Location::Sqlite(p) => p.display().to_string(),
            Location::Postgres(u) => pg::redact(u),
        }
    }

    /// The database, its tables created when missing.
    pub fn open(&self) -> Result<Box<dyn Sql>, HistoryError> {
        let mut db: Box<dyn Sql> = match self {
            Location::Sqlite(p) => Box::new(sqlite::Sqlite::open(p)?),
            Location::Postgres(u) => Box::new(pg::Pg::connect(u)?),
        };
        let mut st: Vec<String> = db.schema_lock().into_iter().collect();
        st.extend(schema());
        db.transaction(&st)?;
        Ok(db)
    }
}

/// The tables (the same text on SQLite and PostgreSQL).
pub fn schema() -> Vec<String> {
    [
        "CREATE TABLE IF NOT EXISTS pmu50_runs (id TEXT PRIMARY KEY, at_unix BIGINT NOT NULL, \
         day TEXT NOT NULL, host TEXT NOT NULL, kind TEXT NOT NULL, folder TEXT NOT NULL, \
         rtl_hash TEXT NOT NULL, rtl_list TEXT NOT NULL, model_id TEXT NOT NULL, tool TEXT NOT NULL, \
         dut TEXT NOT NULL, seed_start BIGINT NOT NULL, seed_count BIGINT NOT NULL, \
         pass BIGINT NOT NULL, fail BIGINT NOT NULL, error BIGINT NOT NULL, missing BIGINT NOT NULL, \
         func_hit BIGINT NOT NULL, func_total BIGINT NOT NULL, line_hit BIGINT, line_total BIGINT, \
         toggle_hit BIGINT, toggle_total BIGINT, signoff_met INTEGER)",
        "CREATE TABLE IF NOT EXISTS pmu50_signatures (run_id TEXT NOT NULL, signature TEXT NOT NULL, \
         seeds BIGINT NOT NULL, smallest BIGINT NOT NULL)",
        "CREATE TABLE IF NOT EXISTS pmu50_rows (run_id TEXT NOT NULL, name TEXT NOT NULL, \
         figure TEXT NOT NULL, met INTEGER NOT NULL, detail TEXT NOT NULL)",
        "CREATE TABLE IF NOT EXISTS pmu50_areas (run_id TEXT NOT NULL, area TEXT NOT NULL, \
         hit BIGINT NOT NULL, total BIGINT NOT NULL)",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect()
}

/// A sign-off row as the history keeps it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RowRecord {
    pub name: String,
    pub figure: String,
    pub met: bool,
    pub detail: String,
}

/// One run: when, where, on what, and what it found.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Record {
    pub id: String,
    pub at_unix: i64,
    pub host: String,
    /// `regress`, `merge` or `signoff`.
    pub kind: String,
    pub folder: String,
    pub rtl_hash: String,
    pub rtl_list: String,
    pub model_id: String,
    pub tool: String,
    pub dut: String,
    pub seed_start: u64,
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
    /// Failure signatures: (signature, seeds, smallest seed).
    pub signatures: Vec<(String, u64, u64)>,
    pub rows: Vec<RowRecord>,
    /// Functional coverage per test-plan area (a FIG. or paragraph the bins cite): (area, hit,
    /// reachable).
    pub areas: Vec<(String, u64, u64)>,
}

/// The time of a record: now, or `PMU50_HISTORY_TIME` (seconds since 1970, UTC) when set, to
/// import past runs with their own dates.
pub fn now_unix() -> i64 {
    if let Some(t) = std::env::var("PMU50_HISTORY_TIME")
        .ok()
        .and_then(|v| v.trim().parse::<i64>().ok())
    {
        return t;
    }
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0)
}

/// The test-plan area of a bin: the first `FIG. n` its citation names, else its first
/// paragraph `[nnnn]`, else its group (the name before the first dot).
pub fn area_of(name: &str, cite: &str) -> String {
    if let Some(i) = cite.find("FIG. ") {
        let rest = &cite[i + 5..];
        let n: String = rest
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric())
            .collect();
        if !n.is_empty() {
            return format!("FIG. {n}");
        }
    }
    if let Some(i) = cite.find('[') {
        if let Some(j) = cite[i..].find(']') {
            return cite[i..i + j + 1].to_string();
        }
    }
    name.split('.').next().unwrap_or(name).to_string()
}

/// A record of a regression folder's summary (`kind`: regress, merge, signoff).
pub fn record_of(s: &Summary, kind: &str, folder: &Path) -> Record {
    let at = now_unix();
    let (rtl_hash, rtl_list, model_id, tool) = match &s.evidence {
        Some(e) => (
            e.provenance
                .rtl
                .as_ref()
                .map(|r| r.hash.clone())
                .unwrap_or_else(|| "-".into()),
            e.provenance
                .rtl
                .as_ref()
                .map(|r| r.list.clone())
                .unwrap_or_else(|| "-".into()),
            e.provenance.model_id.clone(),
            e.provenance.tool.clone(),
        ),
        None => (
            "-".into(),
            "-".into(),
            s.spec.model.clone(),
            s.spec.tool.clone(),
        ),
    };
    let (func_hit, func_total) = s.coverage.closure();
    let mut areas: std::collections::BTreeMap<String, (u64, u64)> = Default::default();
    for b in &s.coverage.bins {
        if b.unreachable.is_some() {
            continue;
        }
        let a = areas.entry(area_of(&b.name, &b.cite)).or_default();
        a.0 += u64::from(b.hits > 0);
        a.1 += 1;
    }
    let host = crate::spec::Place::here(None).host;
    let id = crate::digest::sha256_hex(
        format!(
            "{host}/{}/{at}/{:?}/{}",
            std::process::id(),
            std::time::SystemTime::now(),
            folder.display()
        )
        .as_bytes(),
    )[..24]
        .to_string();
    Record {
        id,
        at_unix: at,
        host,
        kind: kind.into(),
        folder: folder.display().to_string(),
        rtl_hash,
        rtl_list,
        model_id,
        tool,
        dut: s.spec.dut.name().to_string(),
        seed_start: s.spec.start_seed,
        seed_count: s.spec.iterations,
        pass: s.pass,
        fail: s.fail,
        error: s.error,
        missing: s.missing_count(),
        func_hit: func_hit as u64,
        func_total: func_total as u64,
        line: s
            .code
            .as_ref()
            .map(|c| (c.summary.line.hit, c.summary.line.total)),
        toggle: s
            .code
            .as_ref()
            .map(|c| (c.summary.toggle.hit, c.summary.toggle.total)),
        signoff_met: None,
        signatures: s
            .groups
            .iter()
            .map(|(k, g)| (k.clone(), g.count, g.smallest))
            .collect(),
        rows: Vec::new(),
        areas: areas.into_iter().map(|(k, (h, t))| (k, h, t)).collect(),
    }
}

/// A text literal of SQL (quotes doubled, NUL removed): the same on SQLite and PostgreSQL
/// (standard_conforming_strings, its default since 9.1).
fn lit(s: &str) -> String {
    format!("'{}'", s.replace('\0', "").replace('\'', "''"))
}

fn opt(v: Option<u64>) -> String {
    v.map(|x| x.to_string()).unwrap_or_else(|| "NULL".into())
}

/// The statements that add a record (one transaction).
pub fn insert(r: &Record) -> Vec<String> {
    let mut v = Vec::new();
    let id = lit(&r.id);
    for (sig, n, smallest) in &r.signatures {
        v.push(format!(
            "INSERT INTO pmu50_signatures (run_id, signature, seeds, smallest) VALUES ({id}, {}, {n}, {smallest})",
            lit(sig)
        ));
    }
    for row in &r.rows {
        v.push(format!(
            "INSERT INTO pmu50_rows (run_id, name, figure, met, detail) VALUES ({id}, {}, {}, {}, {})",
            lit(&row.name),
            lit(&row.figure),
            i32::from(row.met),
            lit(&row.detail)
        ));
    }
    for (a, h, t) in &r.areas {
        v.push(format!(
            "INSERT INTO pmu50_areas (run_id, area, hit, total) VALUES ({id}, {}, {h}, {t})",
            lit(a)
        ));
    }
    v.push(format!(
        "INSERT INTO pmu50_runs (id, at_unix, day, host, kind, folder, rtl_hash, rtl_list, model_id, \
         tool, dut, seed_start, seed_count, pass, fail, error, missing, func_hit, func_total, \
         line_hit, line_total, toggle_hit, toggle_total, signoff_met) VALUES ({id}, {}, {}, {}, {}, \
         {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {})",
        r.at_unix,
        lit(&day_of(r.at_unix)),
        lit(&r.host),
        lit(&r.kind),
        lit(&r.folder),
        lit(&r.rtl_hash),
        lit(&r.rtl_list),
        lit(&r.model_id),
        lit(&r.tool),
        lit(&r.dut),
        r.seed_start as i64,
        r.seed_count,
        r.pass,
        r.fail,
        r.error,
        r.missing,
        r.func_hit,
        r.func_total,
        opt(r.line.map(|x| x.0)),
        opt(r.line.map(|x| x.1)),
        opt(r.toggle.map(|x| x.0)),
        opt(r.toggle.map(|x| x.1)),
        r.signoff_met
            .map(|m| i32::from(m).to_string())
            .unwrap_or_else(|| "NULL".into()),
    ));
    v
}

/// Append `r` to the history at `loc`.
pub fn append(loc: &Location, r: &Record) -> Result<(), HistoryError> {
    let mut db = loc.open()?;
    db.transaction(&insert(r))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_follow_the_figures_cited() {
        assert_eq!(area_of("fig17.path.s6", "FIG. 17, S6 [0112]"), "FIG. 17");
        assert_eq!(area_of("cnt.wrap", "[0097] rule"), "[0097]");
        assert_eq!(area_of("bus.write_reg.unmapped", ""), "bus");
    }

    #[test]
    fn a_literal_cannot_end_its_quotes() {
        assert_eq!(lit("it's"), "'it''s'");
        assert_eq!(lit("a\0b"), "'ab'");
    }
}
