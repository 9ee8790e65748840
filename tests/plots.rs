//! Pictures and analyses (testbench/src/plot, testbench/src/analysis): the SVGs parse, reruns are byte-identical, and
//! their numbers are right: the steady-state speed limit of the sweep is within one sweep step of
//! the analytic bound 90 deg / min (docs/analysis.md), the budget's totals are the sums of its
//! parts, and the fixed cycle's Vs2 duty is Wt / x ([0229]-[0231]).

use pmu50_core::Dur;
use pmu50_testbench::analysis::budget::{self, Variant};
use pmu50_testbench::analysis::speed::{self, Bounds, Sweep, SweepSpec};
use pmu50_testbench::output::{run_to_files, FileOptions};
use pmu50_testbench::scenario::Scenario;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scenario(name: &str) -> Scenario {
    Scenario::load(&root().join("scenarios").join(format!("{name}.toml"))).unwrap()
}

fn defaults() -> Scenario {
    Scenario::parse(
        "duration = \"1 ms\"\n",
        "<defaults>",
        "defaults",
        Path::new(""),
    )
    .unwrap()
}

fn tmp(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pmu50-plots-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Parse an SVG and return the text of its <text> elements.
fn parse_svg(text: &str) -> Vec<String> {
    let doc =
        roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("SVG does not parse: {e}"));
    let svg = doc.root_element();
    assert_eq!(svg.tag_name().name(), "svg");
    let w: f64 = svg.attribute("width").unwrap().parse().unwrap();
    let h: f64 = svg.attribute("height").unwrap().parse().unwrap();
    assert!(w > 100.0 && h > 100.0);
    // every coordinate is a finite number inside the picture
    for n in doc.descendants().filter(|n| n.is_element()) {
        for a in ["x", "y", "x1", "y1", "x2", "y2", "cx", "cy"] {
            if let Some(v) = n.attribute(a) {
                let v: f64 = v
                    .parse()
                    .unwrap_or_else(|_| panic!("{a}={v} is not a number"));
                assert!(
                    v.is_finite() && v >= -1.0 && v <= w.max(h) + 1.0,
                    "{a}={v} outside the picture"
                );
            }
        }
    }
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").to_string())
        .collect()
}

fn small_spec(from: f64, to: f64, step: f64) -> SweepSpec {
    SweepSpec {
        from_dps: from,
        to_dps: to,
        step_dps: step,
        accel_from: 1e5,
        accel_ratio: 10.0,
        accel_points: 2,
    }
}

#[test]
fn steady_state_limit_is_within_one_step_of_90_deg_per_min() {
    for (x_us, min_us) in [(6_600, 2_200), (6_600, 1_100)] {
        let mut sc = defaults();
        sc.core.x = Dur::us(x_us);
        sc.core.min = Dur::us(min_us);
        sc.params = sc.core.to_params().unwrap();
        let b = Bounds::of(&sc);
        assert!((b.steady_dps - 90.0 / (min_us as f64 * 1e-6)).abs() < 1e-6);
        let step = 1_000.0;
        let r = speed::sweep(
            &sc,
            small_spec(b.steady_dps - 8_000.0, b.steady_dps + 6_000.0, step),
            &mut |_| {},
        )
        .unwrap();
        // the interval really was at min when the test speed started
        for p in r.points.iter().filter(|p| p.sweep == Sweep::SteadyState) {
            assert!(
                (p.si_at_start_ms - min_us as f64 / 1e3).abs() < 1e-9,
                "{p:?}"
            );
        }
        let found = r
            .limit(Sweep::SteadyState)
            .expect("the lowest speed is tracked");
        assert!(
            (found - b.steady_dps).abs() <= step,
            "min = {min_us} us: found {found} deg/s, bound {} deg/s",
            b.steady_dps
        );
        // and every speed a step above the bound loses the angle
        assert!(r
            .points
            .iter()
            .filter(|p| p.sweep == Sweep::SteadyState && p.value >= b.steady_dps + step)
            .all(|p| !p.tracked()));
    }
}

#[test]
fn jump_from_rest_limit_is_within_one_step_of_90_deg_per_x() {
    let sc = defaults();
    let b = Bounds::of(&sc);
    let step = 500.0;
    let r = speed::sweep(
        &sc,
        small_spec(b.rest_dps - 3_000.0, b.rest_dps + 2_000.0, step),
        &mut |_| {},
    )
    .unwrap();
    let found = r.limit(Sweep::FromRest).unwrap();
    assert!(
        (found - b.rest_dps).abs() <= step,
        "found {found}, bound {}",
        b.rest_dps
    );
}

#[test]
fn budget_totals_are_the_sum_of_the_parts_and_fixed_duty_is_wt_over_x() {
    for name in ["park_still", "park_bumps", "park_ferry"] {
        let sc = scenario(name);
        let b = budget::budget(&sc).unwrap();
        assert_eq!(b.rows.len(), 4);
        for r in &b.rows {
            let sum_ua: f64 = r.rail_ua.iter().sum();
            let sum_uc: f64 = r.rail_uc.iter().sum();
            assert!(
                (r.total_ua - sum_ua).abs() <= 1e-9 * sum_ua,
                "{name} {:?}",
                r.variant
            );
            assert!((r.total_uc - sum_uc).abs() <= 1e-9 * sum_uc);
            // average current x key-off time = charge
            assert!(
                (r.total_ua * r.key_off_ns as f64 * 1e-9 - r.total_uc).abs() <= 1e-9 * r.total_uc
            );
            // the cumulative curve ends at the total, never decreases
            let last = r.curve.last().unwrap().1;
            assert!((last - r.total_uc / 3.6e6).abs() <= 1e-12 + 1e-9 * last);
            assert!(r.curve.windows(2).all(|w| w[1].1 >= w[0].1 - 1e-15));
        }
        // the curve's key-off time from the timeline is the meter's
        let a = b
            .rows
            .iter()
            .find(|r| r.variant == Variant::Adaptive)
            .unwrap();
        assert_eq!(
            budget::key_off_ns_from_timeline(&sc),
            a.key_off_ns,
            "{name}"
        );
        // the meter's own total (DarkCurrentMeter::report) agrees with the sum of the rails
        let run = pmu50_testbench::analysis::run(&sc).unwrap();
        assert!((run.dark.avg_current_ua.unwrap() - a.total_ua).abs() <= 1e-9 * a.total_ua);
        // fixed cycle: every output is Wt long, and the duty is Wt / x up to one output
        let f = b.rows.iter().find(|r| r.variant == Variant::Fixed).unwrap();
        let clk = sc.clock_ns();
        let wt_ns =
            (u64::from(sc.params.pw) + u64::from(sc.params.pi) + u64::from(sc.params.ps)) * clk;
        let x_ns = u64::from(sc.params.si_max) * clk;
        // (plus at most part of one output at a key transition: the rail follows Sig's edges)
        let extra = f
            .vs2_on_ns
            .checked_sub(f.outputs as u64 * wt_ns)
            .unwrap_or_else(|| panic!("{name}: {} ns for {} outputs", f.vs2_on_ns, f.outputs));
        assert!(
            extra < wt_ns,
            "{name}: {extra} ns more than {} outputs of Wt",
            f.outputs
        );
        let want = wt_ns as f64 / x_ns as f64;
        assert!(
            (f.vs2_duty() - want).abs() <= wt_ns as f64 / f.key_off_ns as f64,
            "{name}: duty {} vs Wt/x {want}",
            f.vs2_duty()
        );
        // sensor always on: duty 1; fixed at min: 10 % as in [0231]
        let on = b
            .rows
            .iter()
            .find(|r| r.variant == Variant::AlwaysOn)
            .unwrap();
        assert_eq!(on.vs2_on_ns, on.key_off_ns);
        let m = b
            .rows
            .iter()
            .find(|r| r.variant == Variant::FixedMin)
            .unwrap();
        assert!((m.vs2_duty() - 0.1).abs() <= wt_ns as f64 / m.key_off_ns as f64);
        // the CSV's total lines are the sums of its rail lines
        let csv = budget::csv(&b);
        for v in [
            "adaptive",
            "fixed_cycle_x",
            "sensor_always_on",
            "fixed_cycle_min",
        ] {
            let rows: Vec<Vec<&str>> = csv
                .lines()
                .filter(|l| l.starts_with(&format!("{v},")))
                .map(|l| l.split(',').collect())
                .collect();
            assert_eq!(rows.len(), 6);
            let parts: f64 = rows[..5].iter().map(|r| r[4].parse::<f64>().unwrap()).sum();
            let total: f64 = rows[5][4].parse().unwrap();
            assert!(
                (parts - total).abs() <= 1e-5,
                "{name} {v}: {parts} vs {total}"
            );
        }
    }
}

#[test]
fn adaptive_costs_more_than_fixed_x_only_when_the_shaft_moves() {
    let still = budget::budget(&scenario("park_still")).unwrap();
    let ferry = budget::budget(&scenario("park_ferry")).unwrap();
    let get = |b: &budget::Budget, v| b.rows.iter().find(|r| r.variant == v).unwrap().vs2_on_ns;
    assert_eq!(get(&still, Variant::Adaptive), get(&still, Variant::Fixed));
    assert!(get(&ferry, Variant::Adaptive) > get(&ferry, Variant::Fixed));
    assert!(get(&ferry, Variant::Adaptive) < get(&ferry, Variant::FixedMin));
}

/// Run the three writers twice into two folders; every file is byte-identical and every SVG parses.
#[test]
fn svgs_parse_and_reruns_are_byte_identical() {
    let dirs = [tmp("rerun-a"), tmp("rerun-b")];
    for d in &dirs {
        run_to_files(
            &scenario("fig15b"),
            d,
            FileOptions {
                svg: true,
                ..FileOptions::default()
            },
            &mut [],
        )
        .unwrap();
        speed::run_cli(
            &defaults(),
            d,
            Some(4_000.0),
            Some(4_000.0),
            Some(48_000.0),
            false,
            None,
            None,
        )
        .unwrap();
        budget::run_cli(&scenario("park_bumps"), d).unwrap();
    }
    let files = [
        "fig15b.svg",
        "fig15b_timing.csv",
        "speed_limit.svg",
        "speed_limit.csv",
        "budget.svg",
        "budget.csv",
        "budget_cumulative.csv",
    ];
    for f in files {
        let a = std::fs::read(dirs[0].join(f)).unwrap();
        let b = std::fs::read(dirs[1].join(f)).unwrap();
        assert!(a == b, "{f} differs between two runs");
        if f.ends_with(".svg") {
            let texts = parse_svg(std::str::from_utf8(&a).unwrap());
            assert!(texts.len() > 10, "{f}: {texts:?}");
        }
    }
    let t = parse_svg(&std::fs::read_to_string(dirs[0].join("fig15b.svg")).unwrap());
    for label in [
        "St",
        "Vs2",
        "Cs",
        "Cc",
        "CNTr",
        "Si (ms)",
        "time (ms)",
        "100",
    ] {
        assert!(
            t.iter().any(|s| s == label),
            "fig15b.svg has no label {label}"
        );
    }
    let t = parse_svg(&std::fs::read_to_string(dirs[0].join("budget.svg")).unwrap());
    assert!(t.iter().any(|s| s.starts_with("fixed cycle T = x")));
    // nothing left behind by the atomic writes
    for d in &dirs {
        assert!(std::fs::read_dir(d).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .contains(".tmp")));
        std::fs::remove_dir_all(d).ok();
    }
}

#[test]
fn grid_figure_parses_and_lists_every_configuration() {
    let rows = speed::grid(&defaults(), &[6_600], &[2_200, 1_100], &[4], &mut |_| {}).unwrap();
    assert_eq!(rows.len(), 2);
    for r in &rows {
        let s = r.steady.unwrap();
        assert!((s - r.bounds.steady_dps).abs() <= r.step_dps, "{r:?}");
    }
    let t = parse_svg(&speed::grid_svg(&rows));
    assert!(t.iter().any(|s| s == "6.6 / 2.2 / 4") && t.iter().any(|s| s == "6.6 / 1.1 / 4"));
    assert_eq!(speed::grid_csv(&rows).lines().count(), 3);
}

/// The README's pictures (docs/img) are the diagrams the model draws today.
#[test]
fn readme_pictures_are_current() {
    let d = tmp("readme");
    for name in ["fig15a", "fig15b", "fig16"] {
        let w = run_to_files(
            &scenario(name),
            &d,
            FileOptions {
                svg: true,
                ..FileOptions::default()
            },
            &mut [],
        )
        .unwrap()
        .1
        .svg
        .unwrap();
        let now = std::fs::read(&w.svg).unwrap();
        let shipped = std::fs::read(root().join("docs/img").join(format!("{name}.svg"))).unwrap();
        assert!(
            now == shipped,
            "docs/img/{name}.svg is stale: copy {} there",
            w.svg.display()
        );
    }
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn bad_input_exits_2_with_a_message() {
    let bin = env!("CARGO_BIN_EXE_pmu50");
    let d = tmp("bad");
    let out = std::process::Command::new(bin)
        .args(["speed-limit", "--no-grid", "--step=0", "--out-dir"])
        .arg(&d)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("step"));
    // a budget needs key-off time
    let toml = d.join("key_on.toml");
    std::fs::write(
        &toml,
        "duration = \"20 ms\"\n[[events]]\nat = \"0 ms\"\nig = true\n",
    )
    .unwrap();
    let out = std::process::Command::new(bin)
        .arg("budget")
        .arg(&toml)
        .arg("--out-dir")
        .arg(&d)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("never off for a whole interval"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(!d.join("budget.svg").exists());
    std::fs::remove_dir_all(&d).ok();
}

/// `--window` / `[vcd] window`: the diagram and its CSV cover exactly the window, time in ms.
#[test]
fn timing_diagram_covers_the_window_only() {
    let sc = scenario("fig16");
    let d = tmp("window");
    let w = run_to_files(
        &sc,
        &d,
        FileOptions {
            log: false,
            window: Some((3_000, 6_000)),
            svg: true,
            ..FileOptions::default()
        },
        &mut [],
    )
    .unwrap()
    .1
    .svg
    .unwrap();
    let csv = std::fs::read_to_string(&w.csv).unwrap();
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(times.first(), Some(&30.0));
    assert_eq!(times.last(), Some(&60.0));
    assert!(times.windows(2).all(|t| t[0] < t[1]));
    // inside this window the interval is shortened to 2.2 ms and climbs back to 5.5 ms (FIG. 16;
    // 6.6 ms comes at 64 ms, after the window)
    let si: Vec<&str> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').nth(9))
        .filter(|s| !s.is_empty())
        .collect();
    let mut steps: Vec<&str> = si.clone();
    steps.dedup();
    assert_eq!(steps, ["4.400", "2.200", "3.300", "4.400", "5.500"]);
    let t = parse_svg(&std::fs::read_to_string(&w.svg).unwrap());
    assert!(
        t.iter().any(|s| s == "30")
            && t.iter().any(|s| s == "60")
            && !t.iter().any(|s| s == "25" || s == "65"),
        "{t:?}"
    );
    std::fs::remove_dir_all(&d).ok();
}
