//! GTKWave save files: exact lines for a sample, validation, names checked
//! against a written VCD, and (when gtkwave + xvfb-run are installed) a round
//! trip through GTKWave itself.

mod common;

use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{sample, text, tools_or_skip, wave};
use pmu50_waves::gtkw::{Analog, Color, Format, GtkwError, GtkwSave, Trace};

fn sample_save(dumpfile: &str) -> GtkwSave {
    let mut s = GtkwSave::new(dumpfile).unwrap();
    s.size(1200, 700).timestart(0).zoom(-3.0).unwrap();
    s.begin_group("pmu50", false).unwrap();
    s.trace(Trace::new("pmu50.clk")).unwrap();
    s.trace(Trace::new("pmu50.en")).unwrap();
    s.begin_group("drive_interval", true).unwrap();
    s.trace(
        Trace::new("pmu50.drive_interval.si[15:0]")
            .format(Format::Hex)
            .color(Color::Green),
    )
    .unwrap();
    s.trace(
        Trace::new("pmu50.drive_interval.si[15:0]")
            .format(Format::Decimal)
            .alias("si decimal"),
    )
    .unwrap();
    s.end_group().unwrap();
    s.trace(
        Trace::new("pmu50.drive_interval.si[15:0]")
            .format(Format::SignedDecimal)
            .analog(Analog::Step, 3),
    )
    .unwrap();
    s.trace(
        Trace::new("pmu50.drive_interval.vout")
            .analog(Analog::Interpolated, 2)
            .color(Color::Red),
    )
    .unwrap();
    s.end_group().unwrap();
    s
}

const EXPECTED: &str = "[*]
[*] pmu50-waves GTKWave save file
[*]
[dumpfile] \"out/run.vcd\"
[timestart] 0
[size] 1200 700
*-3.000000 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1 -1
@800200
-pmu50
@28
pmu50.clk
pmu50.en
@c00200
-drive_interval
@22
[color] 4
pmu50.drive_interval.si[15:0]
@24
+{si decimal} pmu50.drive_interval.si[15:0]
@1401200
-drive_interval
@8420
pmu50.drive_interval.si[15:0]
@20000
-
-
@10028
[color] 1
pmu50.drive_interval.vout
@20000
-
@1000200
-pmu50
";

#[test]
fn sample_has_exact_group_flag_and_analog_lines() {
    let out = sample_save("out/run.vcd").render().unwrap();
    assert_eq!(out, EXPECTED);
    // the individual facts the format relies on
    assert!(out.contains("@800200\n-pmu50\n"));
    assert!(out.contains("@1000200\n-pmu50\n"));
    assert!(out.contains("@420") || out.contains("@8420"));
    assert!(!out.contains("[dumpfile_mtime]") && !out.contains("[pos]"));
}

#[test]
fn flag_words_match_gtkwave_analyzer_h() {
    assert_eq!(Trace::new("a").flags(), 0x28);
    assert_eq!(Trace::new("a").format(Format::Hex).flags(), 0x22);
    assert_eq!(Trace::new("a").format(Format::Decimal).flags(), 0x24);
    assert_eq!(Trace::new("a").format(Format::SignedDecimal).flags(), 0x420);
    assert_eq!(
        Trace::new("a")
            .format(Format::SignedDecimal)
            .analog(Analog::Step, 1)
            .flags(),
        0x8420
    );
    assert_eq!(
        Trace::new("a").analog(Analog::Interpolated, 1).flags(),
        0x10028
    );
}

#[test]
fn flags_line_only_when_flags_change_and_output_is_deterministic() {
    let mut s = GtkwSave::new("x.vcd").unwrap();
    for n in ["t.a", "t.b", "t.c"] {
        s.trace(Trace::new(n).format(Format::Hex)).unwrap();
    }
    s.trace(Trace::new("t.d").analog(Analog::Step, 1)).unwrap();
    let out = s.render().unwrap();
    assert!(out.ends_with("@22\nt.a\nt.b\nt.c\n@8028\nt.d\n"), "{out}");
    assert_eq!(out, s.render().unwrap());
    assert_eq!(
        sample_save("a.vcd").render().unwrap(),
        sample_save("a.vcd").render().unwrap()
    );
}

#[test]
fn rejects_invalid_input() {
    assert!(matches!(
        GtkwSave::new(""),
        Err(GtkwError::InvalidText { .. })
    ));
    assert!(matches!(
        GtkwSave::new("a\nb.vcd"),
        Err(GtkwError::InvalidText { .. })
    ));
    assert!(matches!(
        GtkwSave::new("a\"b.vcd"),
        Err(GtkwError::InvalidText { .. })
    ));
    let mut s = GtkwSave::new("x.vcd").unwrap();
    assert!(matches!(s.end_group(), Err(GtkwError::NoOpenGroup)));
    assert!(matches!(s.zoom(f64::NAN), Err(GtkwError::BadZoom(_))));
    for bad in ["", "a b", "-x", "@28", "a\nb"] {
        assert!(
            matches!(s.trace(Trace::new(bad)), Err(GtkwError::InvalidText { .. })),
            "{bad:?}"
        );
    }
    assert!(matches!(
        s.begin_group("a\nb", false),
        Err(GtkwError::InvalidText { .. })
    ));
    for bad in ["", "a}b", "a\nb"] {
        assert!(
            matches!(
                s.trace(Trace::new("t.a").alias(bad)),
                Err(GtkwError::InvalidText {
                    what: "trace alias",
                    ..
                })
            ),
            "{bad:?}"
        );
    }
    assert!(matches!(
        s.trace(Trace::new("t.a").analog(Analog::Step, 0)),
        Err(GtkwError::ZeroHeight { .. })
    ));
    s.begin_group("g", false).unwrap();
    let err = s.render().unwrap_err();
    assert!(matches!(&err, GtkwError::UnclosedGroup(g) if g == "g"));
    assert!(err.to_string().contains("end_group"), "{err}");
}

#[test]
fn fit_sets_timestart_and_gtkwave_zoom() {
    // Pane 1400 - 600 = 800 px; GTKWave shows 2^-zoom / 200 units per pixel: 4096 units in
    // 800 px is 2^10 / 200 per pixel, zoom -10.
    let mut s = GtkwSave::new("x.vcd").unwrap();
    s.size(1400, 800).fit(100, 100 + 4096);
    let out = s.render().unwrap();
    assert!(out.contains("[timestart] 100\n"), "{out}");
    assert!(out.contains("*-10.000000 -1"), "{out}");
    // Any span: rounded down (more zoomed out), so the whole span is visible.
    s.fit(0, 48_000);
    let z: f64 = s
        .render()
        .unwrap()
        .lines()
        .find_map(|l| l.strip_prefix('*'))
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let units_per_px = 2f64.powf(-z) / 200.0;
    assert!(
        units_per_px * 800.0 >= 48_000.0 && units_per_px * 800.0 < 48_000.0 * 1.0001,
        "{z}"
    );
}

#[test]
fn named_markers_go_on_the_zoom_line_with_their_names() {
    let mut s = GtkwSave::new("x.vcd").unwrap();
    s.marker(26_620, "rotation cs, si 4.4 ms").unwrap();
    s.marker(39_820, "rotation cc").unwrap();
    s.note("two markers").unwrap();
    let out = s.render().unwrap();
    let star = out.lines().find(|l| l.starts_with('*')).unwrap();
    let f: Vec<&str> = star.split(' ').collect();
    assert_eq!(
        f.len(),
        2 + 26,
        "zoom, primary marker, 26 named markers: {star}"
    );
    assert_eq!(&f[1..4], ["-1", "26620", "39820"]);
    assert!(
        out.contains("\n[markername] Arotation cs, si 4.4 ms\n[markername] Brotation cc\n"),
        "{out}"
    );
    assert!(
        out.starts_with("[*]\n[*] pmu50-waves GTKWave save file\n[*] two markers\n[*]\n"),
        "{out}"
    );
    // GTKWave reads leading capitals as the marker's letters; 26 is all it has.
    assert!(matches!(
        s.marker(1, "Key on"),
        Err(GtkwError::InvalidText { .. })
    ));
    assert!(matches!(
        s.marker(1, "a\nb"),
        Err(GtkwError::InvalidText { .. })
    ));
    for t in 2..26 {
        s.marker(t, "m").unwrap();
    }
    assert!(matches!(
        s.marker(99, "one too many"),
        Err(GtkwError::TooManyMarkers { max: 26, .. })
    ));
}

#[test]
fn trace_names_are_checked_against_the_vcd() {
    let mut smp = sample();
    smp.w.set_time(1).unwrap();
    let names = [
        smp.w.gtkwave_name(smp.clk).unwrap(),
        smp.w.gtkwave_name(smp.si).unwrap(),
        smp.w.gtkwave_name(smp.vout).unwrap(),
    ];
    assert_eq!(names[1], "pmu50.drive_interval.si[15:0]");
    let w = wave(&text(smp.w));
    sample_save("run.vcd").check_names(&w).unwrap();
    let mut s = GtkwSave::new("run.vcd").unwrap();
    s.trace(Trace::new("pmu50.drive_interval.si")).unwrap(); // missing range
    s.trace(Trace::new("pmu50.nope")).unwrap();
    let err = s.check_names(&w).unwrap_err();
    match &err {
        GtkwError::UnknownSignals {
            missing, example, ..
        } => {
            assert_eq!(missing, &["pmu50.drive_interval.si", "pmu50.nope"]);
            assert_eq!(example, "pmu50.drive_interval.si[15:0]");
        }
        other => panic!("unexpected {other:?}"),
    }
}

/// GTKWave loads the VCD and our save file, then writes its own save file;
/// the trace section it writes must equal ours line for line and it must not
/// print warnings.
#[test]
fn gtkwave_reads_and_rewrites_the_save_file_identically() {
    let missing = "`gtkwave` and/or `xvfb-run` not on PATH (apt-get install gtkwave xvfb xauth)";
    let Some(tools) = tools_or_skip(
        "gtkwave_reads_and_rewrites_the_save_file_identically",
        &["gtkwave", "xvfb-run"],
        missing,
    ) else {
        return;
    };
    let (gtkwave, xvfb) = (&tools[0], &tools[1]);
    let dir = std::env::temp_dir().join(format!("pmu50-waves-gtkw-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut smp = sample();
    for t in 1..20u64 {
        smp.w.set_time(t).unwrap();
        smp.w.change_bool(smp.clk, t % 2 == 1).unwrap();
        smp.w.change_vector(smp.si, (t * 3000) & 0xffff).unwrap();
        smp.w.change_real(smp.vout, (t as f64 * 0.3).sin()).unwrap();
    }
    smp.w.change_bool(smp.en, true).unwrap();
    let vcd_path = dir.join("run.vcd");
    std::fs::write(&vcd_path, text(smp.w)).unwrap();
    let mut save = sample_save(vcd_path.to_str().unwrap());
    save.marker(5, "key on").unwrap();
    save.marker(11, "rotation cs, si 4.4 ms").unwrap();
    let ours = save.render().unwrap();
    let gtkw_path = dir.join("view.gtkw");
    save.write(&gtkw_path).unwrap();
    let tcl = dir.join("write.tcl");
    std::fs::write(
        &tcl,
        "gtkwave::/File/Write_Save_File\ngtkwave::/File/Quit\n",
    )
    .unwrap();
    let mut child = Command::new(xvfb)
        .arg("-a")
        .arg(gtkwave)
        .arg(&gtkw_path)
        .arg("-S")
        .arg(&tcl)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // never hang the test suite on a stuck X server / GTKWave
    let deadline = Instant::now() + Duration::from_secs(120);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("gtkwave did not finish within 120 s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let out = child.wait_with_output().unwrap();
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "gtkwave failed: {log}");
    assert!(log.contains("Wrote save file OK"), "{log}");
    for line in log.lines() {
        let l = line.to_ascii_lowercase();
        assert!(
            !l.contains("warning") && !l.contains("error"),
            "gtkwave complained: {line}\n{log}"
        );
    }
    let theirs = std::fs::read_to_string(&gtkw_path).unwrap();
    let traces = |s: &str| -> Vec<String> {
        s.lines()
            .skip_while(|l| !l.starts_with('@'))
            .filter(|l| !l.starts_with("[pattern_trace]"))
            .map(String::from)
            .collect()
    };
    assert_eq!(traces(&theirs), traces(&ours), "GTKWave rewrote:\n{theirs}");
    assert!(
        theirs.contains(&format!("[dumpfile] \"{}\"", vcd_path.display())),
        "{theirs}"
    );
    assert!(theirs.contains("[size] 1200 700"), "{theirs}");
    // GTKWave kept the zoom, the named markers and their names.
    let markers = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| l.starts_with('*') || l.starts_with("[markername]"))
            .map(String::from)
            .collect()
    };
    assert_eq!(
        markers(&theirs),
        markers(&ours),
        "GTKWave rewrote:\n{theirs}"
    );
    assert!(ours.contains("*-3.000000 -1 5 11 -1"), "{ours}");
    let _ = std::fs::remove_dir_all(&dir);
}
