//! The history: every regression, merge and sign-off appends one record (SQLite by default,
//! PostgreSQL through the same code); `pmu50 history` prints the runs and writes the dashboard;
//! the soak row turns from missed to met after seven faked nightlies at 100 % on one RTL; and
//! concurrent writers never lose or tear a record.

use pmu50_verif::history::{self, Location};
use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common;
use common::{expect, pmu50, s, tmp, BIN};

const DAY: i64 = 86_400;
/// 2025-03-01 02:00 UTC: the faked nightlies start here.
const START: i64 = 1_740_794_400;

/// `pmu50 ARGS` with the history's clock set to `at`.
fn at(at: i64, args: &[&str]) -> std::process::Output {
    Command::new(BIN)
        .args(args)
        .env("PMU50_HISTORY_TIME", at.to_string())
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap()
}

fn sealed(p: &Path, text: &str, made_by: &str, seeds: Option<&str>) {
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(p, text).unwrap();
    let twin = Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl/pmu50.f");
    let mut a = vec!["seal", s(p), "--made-by", made_by, "--rtl", s(&twin)];
    if let Some(x) = seeds {
        a.extend(["--seeds", x]);
    }
    expect(&pmu50(&a), 0, &[]);
}

#[test]
fn a_week_of_nightlies_turns_the_soak_row_from_missed_to_met() {
    let t = tmp("soak");
    let db = t.join("history.sqlite");
    let r = t.join("r");
    let o = at(
        START,
        &[
            "regress",
            "--directed",
            "--iterations",
            "2",
            "--dut",
            "verilator",
            "--no-triage",
            "--history",
            s(&db),
            "--out",
            s(&r),
        ],
    );
    expect(&o, 0, &["history: regress record appended"]);
    // the other inputs, and thresholds that leave the soak the only open row
    let mut bins = Vec::new();
    for b in &pmu50_coverage::layout().bins {
        bins.push(match b.unreachable {
            Some(w) => serde_json::json!({"name": b.name, "status": "proven_unreachable", "declared_unreachable": w}),
            None => serde_json::json!({"name": b.name, "status": "witnessed"}),
        });
    }
    sealed(
        &r.join("coverage-proofs.json"),
        &serde_json::json!({"bins": bins}).to_string(),
        "hdl/formal/coverage.py",
        None,
    );
    sealed(
        &r.join("formal.json"),
        r#"{"properties": [{"name": "p", "set": "small", "verdict": "proven"}]}"#,
        "hdl/formal/run.py",
        None,
    );
    sealed(
        &r.join("code/summary.json"),
        r#"{"format": "pmu50-code-coverage-1", "seeds": 2, "seeds_unaccounted": 0, "line": {"hit": 1, "total": 1, "waived": 0, "pct": 100.0}, "toggle": {"hit": 1, "total": 1, "waived": 0, "pct": 100.0}, "expr": {"hit": 1, "total": 1, "waived": 0, "pct": 100.0}, "expr_measured": true, "files": [], "waivers": [], "waivers_file": ""}"#,
        "pmu50 regress --code-coverage",
        Some("1:2"),
    );
    let clean = r#"{"tool": "t", "ran": true, "reason": "", "findings": []}"#;
    sealed(
        &r.join("lint.json"),
        &format!(
            r#"{{"format": "pmu50-lint-1", "checks": [{clean}], "unwaived": [], "waivers": [], "waivers_file": ""}}"#
        ),
        "pmu50 lint",
        None,
    );
    sealed(
        &r.join("xprop.json"),
        &format!(
            r#"{{"format": "pmu50-xprop-1", "seeds": 1, "checks": [{clean}], "unwaived": [], "waivers": [], "waivers_file": ""}}"#
        ),
        "pmu50 xprop",
        None,
    );
    let th = t.join("t.toml");
    std::fs::write(&th, "[thresholds]\nfunctional = 1\n").unwrap();
    let signoff = |when: i64| {
        at(
            when,
            &[
                "signoff",
                s(&r),
                "--thresholds",
                s(&th),
                "--history",
                s(&db),
            ],
        )
    };
    let o = signoff(START + 3600);
    let out = expect(&o, 1, &["soak"]);
    let line = out.lines().find(|l| l.starts_with("soak")).unwrap();
    assert!(
        line.contains(" 1 ") && line.contains(">= 7 days") && line.contains("MISSED"),
        "{line}"
    );
    // six more nightlies of the same RTL (merges of the folder, each a regression's record)
    for d in 1..7 {
        let m = t.join(format!("m{d}"));
        let o = at(
            START + d * DAY,
            &["merge", "--history", s(&db), "--out", s(&m), s(&r)],
        );
        expect(&o, 0, &["history: merge record appended"]);
    }
    let o = signoff(START + 6 * DAY + 3600);
    let out = expect(&o, 0, &["every threshold met"]);
    let line = out.lines().find(|l| l.starts_with("soak")).unwrap();
    assert!(
        line.contains(" 7 ") && line.contains("up to 2025-03-07"),
        "{line}"
    );
    // a missed night breaks the soak
    let m = t.join("m9");
    expect(
        &at(
            START + 8 * DAY,
            &["merge", "--history", s(&db), "--out", s(&m), s(&r)],
        ),
        0,
        &[],
    );
    let o = signoff(START + 8 * DAY + 3600);
    let out = expect(&o, 1, &["soak"]);
    assert!(
        out.lines()
            .find(|l| l.starts_with("soak"))
            .unwrap()
            .contains(" 1 "),
        "{out}"
    );
    // the runs and the dashboard
    let html = t.join("history.html");
    let o = pmu50(&["history", "--history", s(&db), "--html", s(&html)]);
    let out = expect(
        &o,
        0,
        &[
            "2025-03-01 regress",
            "2025-03-07 merge",
            "signoff",
            "runs in",
        ],
    );
    assert_eq!(
        out.lines().filter(|l| l.contains(" merge ")).count(),
        7,
        "{out}"
    );
    let page = std::fs::read_to_string(&html).unwrap();
    for want in [
        "Pass rate and coverage over time",
        "<polyline",
        "FIG. 17",
        "Test-plan areas",
        "soak: 1 consecutive day",
    ] {
        assert!(page.contains(want), "{want}");
    }
}

/// Writers at once on one database: every record arrives whole.
fn hammer(loc: &Location, writers: usize, each: usize) {
    let handles: Vec<_> = (0..writers)
        .map(|w| {
            let loc = loc.clone();
            std::thread::spawn(move || {
                for k in 0..each {
                    let mut r = record(&format!("w{w}-{k}"));
                    r.signatures = (0..5).map(|i| (format!("sig-{w}-{k}-{i}"), 1, i)).collect();
                    history::append(&loc, &r).unwrap();
                }
            })
        })
        .collect();
    for h in handles {
        h.join().unwrap();
    }
    let mut db = loc.open().unwrap();
    let runs = history::runs(db.as_mut()).unwrap();
    assert_eq!(runs.len(), writers * each);
    let n = db.query("SELECT COUNT(*) FROM pmu50_signatures").unwrap();
    assert_eq!(
        n[0][0].as_deref(),
        Some((writers * each * 5).to_string().as_str())
    );
    // no signature without its run
    let orphans = db
        .query("SELECT COUNT(*) FROM pmu50_signatures s LEFT JOIN pmu50_runs r ON r.id = s.run_id WHERE r.id IS NULL")
        .unwrap();
    assert_eq!(orphans[0][0].as_deref(), Some("0"));
}

fn record(id: &str) -> history::Record {
    history::Record {
        id: id.into(),
        at_unix: START,
        host: "h".into(),
        kind: "regress".into(),
        folder: "it's/a folder".into(),
        rtl_hash: "sha256:ab".into(),
        rtl_list: "x.f".into(),
        model_id: "m".into(),
        tool: "pmu50".into(),
        dut: "verilator".into(),
        seed_start: 1,
        seed_count: 4,
        pass: 4,
        fail: 0,
        error: 0,
        missing: 0,
        func_hit: 3,
        func_total: 4,
        line: Some((1, 2)),
        toggle: None,
        signoff_met: None,
        signatures: Vec::new(),
        rows: Vec::new(),
        areas: vec![("FIG. 17".into(), 1, 2)],
    }
}

#[test]
fn concurrent_writers_on_sqlite_lose_and_tear_nothing() {
    let t = tmp("sqlite");
    hammer(&Location::Sqlite(t.join("h.sqlite")), 8, 25);
    // two regressions at once, into one history
    let db = t.join("two.sqlite");
    let kids: Vec<_> = (0..2)
        .map(|k| {
            Command::new(BIN)
                .args([
                    "regress",
                    "--iterations",
                    "4",
                    "--jobs",
                    "1",
                    "--no-triage",
                    "--history",
                    s(&db),
                    "--out",
                ])
                .arg(t.join(format!("r{k}")))
                .current_dir(env!("CARGO_MANIFEST_DIR"))
                .spawn()
                .unwrap()
        })
        .collect();
    for mut k in kids {
        assert!(k.wait().unwrap().success());
    }
    let mut h = Location::Sqlite(db).open().unwrap();
    assert_eq!(history::runs(h.as_mut()).unwrap().len(), 2);
}

/// A PostgreSQL server of this test: initdb into a folder, started on a free port with a
/// password (SCRAM) user; stopped when dropped. `None` (with the reason printed) when the
/// server cannot be had.
struct Server {
    bin: PathBuf,
    data: PathBuf,
    url: String,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = Command::new("su")
            .args(["postgres", "-c"])
            .arg(format!(
                "{}/pg_ctl -D {} -m immediate stop",
                self.bin.display(),
                self.data.display()
            ))
            .output();
    }
}

fn pg_bin() -> Option<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir("/usr/lib/postgresql")
        .ok()?
        .flatten()
        .map(|e| e.path().join("bin"))
        .filter(|p| p.join("initdb").is_file())
        .collect();
    v.sort();
    v.pop()
}

fn server(dir: &Path) -> Result<Server, String> {
    let root = unsafe { libc::geteuid() } == 0;
    // installing the server is part of `make test-long` (PMU50_TEST_LONG); `make test` uses one
    // that is installed already and says SKIPPED otherwise
    let long = std::env::var_os("PMU50_TEST_LONG").is_some();
    if pg_bin().is_none() && root && long {
        let _ = Command::new("apt-get").args(["update", "-qq"]).output();
        let _ = Command::new("apt-get")
            .args(["install", "-y", "-qq", "postgresql"])
            .env("DEBIAN_FRONTEND", "noninteractive")
            .output();
    }
    let bin = pg_bin()
        .ok_or("PostgreSQL is not installed (Debian package postgresql) and cannot be installed")?;
    if !root {
        return Err("the test starts PostgreSQL as its user postgres, which needs root".into());
    }
    let data = dir.join("pgdata");
    std::fs::create_dir_all(&data).map_err(|e| e.to_string())?;
    let sock = dir.join("sock");
    std::fs::create_dir_all(&sock).map_err(|e| e.to_string())?;
    let chown = Command::new("chown")
        .args(["-R", "postgres:postgres"])
        .arg(dir)
        .status()
        .map_err(|e| e.to_string())?;
    if !chown.success() {
        return Err("chown to the user postgres failed".into());
    }
    // the folders above must let the user postgres through
    let _ = Command::new("chmod")
        .args(["o+x"])
        .arg(dir.parent().unwrap())
        .status();
    let port = std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map_err(|e| e.to_string())?
        .port();
    let su = |cmd: String| -> Result<(), String> {
        let o = Command::new("su")
            .args(["postgres", "-c", &cmd])
            .output()
            .map_err(|e| e.to_string())?;
        if o.status.success() {
            Ok(())
        } else {
            Err(format!("{cmd}: {}", String::from_utf8_lossy(&o.stderr)))
        }
    };
    su(format!(
        "{}/initdb -D {} --auth-local=trust --auth-host=scram-sha-256 -U postgres",
        bin.display(),
        data.display()
    ))?;
    let srv = Server {
        bin: bin.clone(),
        data: data.clone(),
        url: format!("postgres://pmu:s3cret@127.0.0.1:{port}/pmu"),
    };
    su(format!(
        "{}/pg_ctl -D {} -w -l {}/log -o '-p {port} -k {} -c listen_addresses=127.0.0.1' start",
        bin.display(),
        data.display(),
        dir.display(),
        sock.display()
    ))?;
    su(format!("{}/psql -h {} -p {port} -U postgres -c \"CREATE USER pmu PASSWORD 's3cret'\" -c 'CREATE DATABASE pmu OWNER pmu'", bin.display(), sock.display()))?;
    Ok(srv)
}

#[test]
fn the_same_history_on_a_real_postgresql_server() {
    let t = tmp("pg");
    let srv = match server(&t) {
        Ok(s) => s,
        Err(why) => {
            eprintln!("SKIPPED: no PostgreSQL server for this test: {why}");
            return;
        }
    };
    let loc = Location::parse(&srv.url);
    hammer(&loc, 4, 10);
    // the CLI through the same code: a regression recorded, the runs listed, the dashboard
    let o = pmu50(&[
        "regress",
        "--iterations",
        "2",
        "--no-triage",
        "--history",
        &srv.url,
        "--out",
        s(&t.join("r")),
    ]);
    let out = expect(
        &o,
        0,
        &["history: regress record appended to postgres://pmu:***@127.0.0.1"],
    );
    assert!(!out.contains("s3cret"), "{out}");
    let html = t.join("h.html");
    let o = pmu50(&["history", "--history", &srv.url, "--html", s(&html)]);
    expect(&o, 0, &["41 runs in"]);
    assert!(std::fs::read_to_string(&html)
        .unwrap()
        .contains("Test-plan areas"));
    // a wrong password is an error naming the server's refusal, not a silent nothing
    let bad = srv.url.replace("s3cret", "wrong");
    let e = Location::parse(&bad).open().err().unwrap().to_string();
    assert!(e.contains("password authentication failed"), "{e}");
}
