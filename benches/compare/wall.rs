//! The wall-time table, after the CPU-time table: whole processes (`pmu50 run --trace all` four
//! ways, Verilator's harness of every variable on one and two threads) side by side in
//! interleaved rounds, the fastest wall time of each, and the ratio lines under the table.

use crate::harness::{rounds, timed, timed_within, Proc};
use crate::stim::{scenario_of, Stim};
use std::path::Path;
use std::process::Command;

/// The rows of the wall-time table (the bench's documentation, in main.rs, says what they run).
const WALL_ROWS: [&str; 6] = [
    "pmu50 run --trace all, writer thread",
    "pmu50 run --trace all, one thread (PMU50_WRITER_THREAD=0)",
    "Verilator -O3 --trace, every variable",
    "Verilator -O3 --trace --threads 2, every variable",
    "pmu50 run --trace all, writer thread, into /dev/shm",
    "pmu50 run --trace all, writer thread, no flush (PMU50_SYNC=0)",
];

/// The harness directory of each Verilator row of [`WALL_ROWS`] (benches/verilator_threads.sh).
const WALL_VERILATOR: [&str; 2] = ["vlw1", "vlw2"];

/// The wall-time table of the stimuli and its ratio lines.
pub fn wall_table(stims: &[Stim], dir: &Path) -> Result<String, String> {
    let bin = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/release/pmu50");
    let mut out = format!(
        "\nwall time, whole processes side by side, fastest of {} interleaved rounds; CPU: that round's user + system time, every thread; loop: Verilator's replay loop alone by the wall clock (file opened to file closed); ratio = Verilator's best traced whole process / this row's wall time; machine: {} CPUs, load average {} at the start\n\n",
        rounds(),
        std::thread::available_parallelism().map_or(0, |n| n.get()),
        std::fs::read_to_string("/proc/loadavg").unwrap_or_default().split_whitespace().take(3).collect::<Vec<_>>().join(" ")
    );
    let w0 = WALL_ROWS.iter().map(|l| l.len()).max().unwrap_or(0);
    out += &format!("| {:w0$} |", "harness");
    for st in stims {
        out += &format!(" {} wall | CPU | loop | ratio |", st.name);
    }
    out += "\n";
    out += &format!("|{}|", "-".repeat(w0 + 2));
    for _ in stims {
        out += "---:|---:|---:|---:|";
    }
    out += "\n";
    let mut cells: Vec<Vec<Option<Proc>>> = vec![Vec::new(); WALL_ROWS.len()];
    let mut lines = Vec::new();
    // the replay loop's wall time a Verilator harness printed
    let loop_s = |p: &Proc| {
        p.stdout
            .split_whitespace()
            .find_map(|w| w.strip_prefix("cpu_s="))
            .and_then(|v| v.parse::<f64>().ok())
    };
    for st in stims {
        let sc = scenario_of(st, dir);
        let vec = st.vec.display().to_string();
        let outd = dir.join("pmu50_wall");
        let vcd = dir.join(format!("verilator_wall_{}.vcd", st.name));
        let run_as = |thread: &str, sync: &str| -> Result<Option<Proc>, String> {
            timed(
                Command::new(&bin)
                    .arg("run")
                    .arg(&sc)
                    .arg("--out-dir")
                    .arg(&outd)
                    .args(["--trace", "all"])
                    .env("PMU50_WRITER_THREAD", thread)
                    .env("PMU50_SYNC", sync),
            )
            .map(Some)
        };
        let run = |thread: &str| run_as(thread, "1");
        // a harness that ran out of time once (more than 20 times the single-threaded one's
        // wall time, at least 2 s) is not run again
        let mut gave_up = [false; 2];
        let mut vl = |j: usize, limit: f64| -> Result<Option<Proc>, String> {
            let b = dir.join(format!("{}_{}/bench", WALL_VERILATOR[j], st.name));
            if !b.exists() || gave_up[j] {
                return Ok(None);
            }
            let p = timed_within(
                Command::new(&b).arg(&vec).arg("1").arg("--trace").arg(&vcd),
                limit,
            )?;
            gave_up[j] = p.is_none();
            Ok(p)
        };
        // the same run into memory (tmpfs): without the disk's share of syncing and renaming
        let shm = Path::new("/dev/shm")
            .is_dir()
            .then(|| Path::new("/dev/shm").join(format!("pmu50_wall_{}", std::process::id())));
        let run_shm = || -> Result<Option<Proc>, String> {
            let Some(d) = shm.as_ref() else {
                return Ok(None);
            };
            timed(
                Command::new(&bin)
                    .arg("run")
                    .arg(&sc)
                    .arg("--out-dir")
                    .arg(d)
                    .args(["--trace", "all"])
                    .env("PMU50_WRITER_THREAD", "1")
                    .env("PMU50_SYNC", "1"),
            )
            .map(Some)
        };
        let mut best: Vec<Option<Proc>> = vec![None; WALL_ROWS.len()];
        for _ in 0..rounds() {
            let one = vl(0, 60.0)?;
            let limit = one.as_ref().map_or(60.0, |p| (20.0 * p.wall).max(2.0));
            let round = [
                run("1")?,
                run("0")?,
                one,
                vl(1, limit)?,
                run_shm()?,
                run_as("1", "0")?,
            ];
            for (b, p) in best.iter_mut().zip(round) {
                if let Some(p) = p {
                    if b.as_ref().is_none_or(|b| p.wall < b.wall) {
                        *b = Some(p);
                    }
                }
            }
        }
        let _ = std::fs::remove_file(&vcd);
        if let Some(d) = shm.as_ref() {
            let _ = std::fs::remove_dir_all(d);
        }
        for (j, g) in gave_up.iter().enumerate() {
            if *g {
                lines.push(format!("{}: {} stopped: it ran 20 times as long as the single-threaded build (at least 2 s), its threads spinning for each other on the busy machine", st.name, WALL_ROWS[2 + j]));
            }
        }
        // Verilator's best traced run
        let (vrow, vbest) = best[2..4]
            .iter()
            .enumerate()
            .filter_map(|(j, p)| p.as_ref().map(|p| (j + 2, p.clone())))
            .min_by(|a, b| a.1.wall.total_cmp(&b.1.wall))
            .ok_or_else(|| format!("{}: no Verilator harness of the wall-time table (DIR/vlw1_{}/bench: benches/verilator_threads.sh)", st.name, st.name))?;
        let best_loop = best[2..4]
            .iter()
            .flatten()
            .filter_map(loop_s)
            .fold(f64::INFINITY, f64::min);
        if let (Some(r), Some(one)) = (&best[0], &best[1]) {
            lines.push(format!(
                "{}: pmu50 run --trace all {:.1} ms wall ({:.1} ms CPU), {:.2}x Verilator's best traced run ({}: {:.1} ms wall, {:.1} ms CPU), {:.2}x Verilator's fastest replay loop alone ({:.1} ms wall); one thread {:.1} ms wall ({:.1} ms CPU), {:.2}x and {:.2}x",
                st.name,
                r.wall * 1e3,
                r.cpu * 1e3,
                vbest.wall / r.wall,
                WALL_ROWS[vrow],
                vbest.wall * 1e3,
                vbest.cpu * 1e3,
                best_loop / r.wall,
                best_loop * 1e3,
                one.wall * 1e3,
                one.cpu * 1e3,
                vbest.wall / one.wall,
                best_loop / one.wall
            ));
        }
        if let Some(n) = &best[5] {
            lines.push(format!(
                "{}: without the flush to the disk before the renames (PMU50_SYNC=0, writer thread) {:.1} ms wall ({:.1} ms CPU), {:.2}x Verilator's best traced run",
                st.name,
                n.wall * 1e3,
                n.cpu * 1e3,
                vbest.wall / n.wall
            ));
        }
        for (row, b) in cells.iter_mut().zip(best) {
            row.push(b);
        }
    }
    for (r, label) in WALL_ROWS.iter().enumerate() {
        out += &format!("| {label:w0$} |");
        for j in 0..stims.len() {
            match &cells[r][j] {
                Some(p) => {
                    let vref = cells[2..4]
                        .iter()
                        .filter_map(|row| row[j].as_ref().map(|p| p.wall))
                        .fold(f64::INFINITY, f64::min);
                    let lp = if (2..4).contains(&r) {
                        loop_s(p).map_or("-".into(), |l| format!("{:.1} ms", l * 1e3))
                    } else {
                        "-".to_string()
                    };
                    out += &format!(
                        " {:.1} ms | {:.1} ms | {lp} | {:.2}x |",
                        p.wall * 1e3,
                        p.cpu * 1e3,
                        vref / p.wall
                    );
                }
                None => out += " - | - | - | - |",
            }
        }
        out += "\n";
    }
    out += "\n";
    for l in lines {
        out += &l;
        out += "\n";
    }
    Ok(out)
}
