//! The build cache of RTL under test (verif/src/cache.rs, `pmu50 cache`): bounded by its cap
//! through many edits of an RTL, one build of a library when two regressions start at once, and
//! what `pmu50 cache` and `pmu50 cache clean` say and do.

use crate::common;
use common::{text, tmp, BIN};
use std::path::Path;
use std::process::Command;

/// A copy of the twin's RTL in `dir`, its file list `dir/pmu50.f`, with `tag` in a comment of
/// its top (an edit: another content hash, another folder of the cache).
fn twin_copy(dir: &Path, tag: &str) {
    let hdl = Path::new(env!("CARGO_MANIFEST_DIR")).join("hdl");
    std::fs::create_dir_all(dir.join("rtl")).unwrap();
    let list = std::fs::read_to_string(hdl.join("pmu50.f")).unwrap();
    for l in list.lines().filter(|l| l.ends_with(".v")) {
        let mut t = std::fs::read_to_string(hdl.join(l)).unwrap();
        if l == "pmu50.v" {
            t.push_str(&format!("// edit {tag}\n"));
        }
        std::fs::write(dir.join(l), t).unwrap();
    }
    std::fs::write(dir.join("pmu50.f"), list).unwrap();
}

fn pmu50_with(cache: &Path, max: Option<&str>, args: &[&str]) -> Command {
    let mut c = Command::new(BIN);
    c.args(args)
        .env("PMU50_CACHE_DIR", cache)
        .current_dir(env!("CARGO_MANIFEST_DIR"));
    match max {
        Some(m) => c.env("PMU50_CACHE_MAX", m),
        None => c.env_remove("PMU50_CACHE_MAX"),
    };
    c
}

fn size(p: &Path) -> u64 {
    let Ok(m) = std::fs::symlink_metadata(p) else {
        return 0;
    };
    if m.is_dir() {
        std::fs::read_dir(p)
            .unwrap()
            .flatten()
            .map(|e| size(&e.path()))
            .sum()
    } else {
        m.len()
    }
}

/// A day of edits: the twin edited 20 times, each edit's library built (`pmu50 rtl-info`
/// prepares the RTL as a regression does), under a cap that holds the Verilator runtime (built
/// once, shared by every RTL) and about six builds of the twin. After every edit the cache is
/// within the cap, and `pmu50 cache` lists the RTL just built.
#[test]
fn an_rtl_edited_20_times_under_a_small_cap_stays_under_the_cap() {
    let t = tmp("edits");
    let cache = t.join("cache");
    let mut cap = None;
    // a day of edits in `make test-long`; 8 in `make test` (the cap holds about six builds, so
    // the first edits are evicted either way)
    let edits = if std::env::var_os("PMU50_TEST_LONG").is_some() {
        20
    } else {
        8
    };
    for i in 0..edits {
        let rtl = t.join(format!("rtl{i}"));
        twin_copy(&rtl, &i.to_string());
        let list = rtl.join("pmu50.f");
        let max = cap.map(|c: u64| c.to_string());
        let o = pmu50_with(
            &cache,
            max.as_deref(),
            &["rtl-info", "--rtl", list.to_str().unwrap()],
        )
        .output()
        .unwrap();
        assert!(o.status.success(), "edit {i}: {}", text(&o));
        let s = size(&cache);
        match cap {
            // the first edit: the runtime and one RTL, plus room for about five more
            None => cap = Some(s + (3 << 19)),
            Some(c) => assert!(
                s <= c,
                "edit {i}: the cache holds {s} bytes, over its cap of {c}"
            ),
        }
        let o = pmu50_with(&cache, max.as_deref(), &["cache"])
            .output()
            .unwrap();
        let shown = text(&o);
        assert!(
            shown.contains(list.to_str().unwrap()),
            "edit {i}: `pmu50 cache` does not list the RTL just built:\n{shown}"
        );
    }
    // the oldest edits were evicted, the newest kept
    let o = pmu50_with(&cache, None, &["cache"]).output().unwrap();
    let shown = text(&o);
    assert!(
        shown.contains(&format!("rtl{}/pmu50.f", edits - 1)),
        "{shown}"
    );
    assert!(!shown.contains("rtl0/pmu50.f"), "{shown}");
    // clean empties it (nothing runs now)
    let o = pmu50_with(&cache, None, &["cache", "clean"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let o = pmu50_with(&cache, None, &["cache"]).output().unwrap();
    assert!(text(&o).contains(" 0 build(s)"), "{}", text(&o));
    // and all it owns: no folder but the empty ones of the builds (the compiler cache and the
    // unpacked HDL kits are gone too)
    let left: Vec<String> = std::fs::read_dir(&cache)
        .unwrap()
        .flatten()
        .filter(|e| e.path().is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| {
            !matches!(n.as_str(), "verilator" | "icarus")
                || std::fs::read_dir(cache.join(n)).unwrap().next().is_some()
        })
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

fn have_ccache() -> bool {
    Command::new("ccache")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// With ccache installed (`make deps` installs it) the builds compile through it, its objects in
/// the cache folder: after a second edit of the RTL in place that leaves the generated C++ as it
/// was (a comment), the build finds every object there.
#[test]
fn a_second_edit_in_place_finds_its_objects_in_the_compiler_cache() {
    if !have_ccache() {
        // without it the builds run g++ alone: a_build_killed_half_way_is_made_again_and_its_
        // leftover_removed builds so
        return;
    }
    let t = tmp("objcache");
    let cache = t.join("cache");
    let rtl = t.join("rtl");
    let list = rtl.join("pmu50.f");
    for edit in ["first", "second"] {
        twin_copy(&rtl, edit);
        let o = pmu50_with(&cache, None, &["rtl-info", "--rtl", list.to_str().unwrap()])
            .env_remove("OBJCACHE")
            .env_remove("CCACHE_DIR")
            .output()
            .unwrap();
        assert!(o.status.success(), "{edit}: {}", text(&o));
    }
    let stats = Command::new("ccache")
        .arg("--print-stats")
        .env("CCACHE_DIR", cache.join("ccache"))
        .output()
        .unwrap();
    let stats = String::from_utf8_lossy(&stats.stdout).into_owned();
    let count = |keys: &[&str]| -> u64 {
        stats
            .lines()
            .filter_map(|l| l.split_once('\t'))
            .filter(|(k, _)| keys.contains(k))
            .filter_map(|(_, v)| v.trim().parse::<u64>().ok())
            .sum()
    };
    // the second build's unit: a hit; the first's and the runtime's: misses
    assert_eq!(
        count(&["direct_cache_hit", "preprocessed_cache_hit"]),
        1,
        "{stats}"
    );
    assert!(count(&["cache_miss"]) >= 2, "{stats}");
    let logs: Vec<String> = std::fs::read_dir(cache.join("verilator"))
        .unwrap()
        .flatten()
        .filter_map(|e| std::fs::read_to_string(e.path().join("builds.log")).ok())
        .collect();
    assert_eq!(logs.len(), 2, "{logs:?}");
    assert!(logs.iter().all(|l| l.contains("(ccache)")), "{logs:?}");
}

/// `pmu50 cache clean` removes the HDL kits unpacked by pmu50 binaries (`hdl-<key>/`) and the
/// compiler cache, but not a kit a running process holds.
#[test]
fn clean_removes_the_kits_and_the_compiler_cache_no_process_uses() {
    let t = tmp("kits");
    let cache = t.join("cache");
    for d in ["hdl-0000000000000001", "hdl-0000000000000002", "ccache/a"] {
        std::fs::create_dir_all(cache.join(d)).unwrap();
        std::fs::write(cache.join(d).join("f"), "x").unwrap();
    }
    // a process using the second kit: its lease
    let held = std::fs::File::create(cache.join("hdl-0000000000000002.lock")).unwrap();
    held.lock_shared().unwrap();
    let o = pmu50_with(&cache, None, &["cache", "clean"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!cache.join("hdl-0000000000000001").exists());
    assert!(!cache.join("ccache").exists());
    assert!(
        cache.join("hdl-0000000000000002/f").is_file(),
        "in use: kept"
    );
    assert!(text(&o).contains("1 in use"), "{}", text(&o));
    drop(held);
    let o = pmu50_with(&cache, None, &["cache", "clean"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(!cache.join("hdl-0000000000000002").exists());
}

/// Two regressions of the same RTL started at once build each library once: the second waits
/// for the first's build (its lock) and takes it. Both pass, and every build of the RTL's
/// folder is recorded once in its builds.log.
#[test]
fn two_regressions_at_once_build_each_library_once() {
    let t = tmp("twice");
    let cache = t.join("cache");
    let rtl = t.join("rtl");
    twin_copy(&rtl, "twice");
    let list = rtl.join("pmu50.f");
    let run = |out: &str| {
        pmu50_with(
            &cache,
            None,
            &[
                "regress",
                "--dut",
                "verilator",
                "--rtl",
                list.to_str().unwrap(),
                "--iterations",
                "4",
                "--param-sets",
                "6",
                "--jobs",
                "1",
                "--no-triage",
                "--out",
                t.join(out).to_str().unwrap(),
            ],
        )
        .spawn()
        .unwrap()
    };
    let (a, b) = (run("a"), run("b"));
    for c in [a, b] {
        let o = c.wait_with_output().unwrap();
        assert!(o.status.success(), "{}", text(&o));
    }
    let folders: Vec<_> = std::fs::read_dir(cache.join("verilator"))
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("rtl.txt").is_file())
        .collect();
    assert_eq!(folders.len(), 1, "{folders:?}");
    let log = std::fs::read_to_string(folders[0].join("builds.log")).unwrap();
    let mut keys: Vec<&str> = log.lines().filter_map(|l| l.split(' ').next()).collect();
    let n = keys.len();
    keys.sort();
    keys.dedup();
    assert_eq!(keys.len(), n, "a library built twice:\n{log}");
    assert!(n >= 2, "{log}");
    // no build left half-made
    for e in std::fs::read_dir(&folders[0]).unwrap().flatten() {
        assert!(
            !e.file_name().to_string_lossy().starts_with(".build-"),
            "{}",
            e.path().display()
        );
    }
}

/// A cap that is not a size is refused with what is valid (exit 2), by `pmu50 cache` and before
/// any build of a run.
#[test]
fn a_cap_that_is_not_a_size_is_refused() {
    let t = tmp("badcap");
    let cache = t.join("cache");
    for args in [vec!["cache"], vec!["rtl-info", "--rtl", "hdl/pmu50.f"]] {
        let o = pmu50_with(&cache, Some("lots"), &args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(
            text(&o).contains("PMU50_CACHE_MAX=lots: not a size"),
            "{}",
            text(&o)
        );
    }
    assert!(!cache.join("verilator").exists(), "nothing built");
}

/// A build killed half-way (SIGKILL while its library compiles) leaves nothing a later run
/// takes for complete: the next run builds the library and passes, and a trim removes the
/// killed build's temporary folder.
#[test]
fn a_build_killed_half_way_is_made_again_and_its_leftover_removed() {
    let t = tmp("killed");
    let cache = t.join("cache");
    let rtl = t.join("rtl");
    twin_copy(&rtl, "killed");
    let list = rtl.join("pmu50.f");
    // without a compiler cache: OBJCACHE empty, as on a machine without ccache
    let info = || {
        let mut c = pmu50_with(&cache, None, &["rtl-info", "--rtl", list.to_str().unwrap()]);
        c.env("OBJCACHE", "");
        c
    };
    let leftovers = || -> Vec<std::path::PathBuf> {
        let Ok(d) = std::fs::read_dir(cache.join("verilator")) else {
            return Vec::new();
        };
        d.flatten()
            .filter(|e| e.path().is_dir())
            .flat_map(|e| std::fs::read_dir(e.path()).unwrap().flatten())
            .map(|e| e.path())
            .filter(|p| {
                p.file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with(".build-"))
            })
            .collect()
    };
    let mut child = info().spawn().unwrap();
    let t0 = std::time::Instant::now();
    while leftovers().is_empty() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its build started"
        );
        assert!(t0.elapsed().as_secs() < 600, "no build started");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let killed = leftovers();
    assert_eq!(killed.len(), 1, "{killed:?}");
    // the key's place holds no library
    let name = killed[0]
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    let key = name["build-".len() + 1..].rsplit_once('-').unwrap().0;
    assert!(!killed[0]
        .with_file_name(key)
        .join("libpmu50_dut.so")
        .exists());
    // a later run builds it and passes
    let o = info().output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert!(killed[0]
        .with_file_name(key)
        .join("libpmu50_dut.so")
        .is_file());
    // built without the compiler cache: none made, and the build's record says so
    assert!(!cache.join("ccache").exists());
    let log = std::fs::read_to_string(killed[0].with_file_name("builds.log")).unwrap();
    assert!(log.contains(" g++ ") && !log.contains("(ccache)"), "{log}");
    // and a trim removes the leftover, under the cap or not
    let o = pmu50_with(&cache, None, &["cache", "clean", "--to-cap"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(leftovers(), Vec::<std::path::PathBuf>::new());
}
