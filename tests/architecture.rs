//! The house's layering, kept by a test (docs/architecture.md): in every crate of the workspace
//! and in every Python package of the project, the files import each other without a circle.
//!
//! The crates are the workspace's packages (their src/ trees) and their bench targets of several
//! files (benches/NAME/, whose main.rs is the crate's root).
//!
//! A Rust file's arrows are the module paths it names (`use crate::a::b`, `super::x`, a child
//! module's `m::f()`, the paths inside `use` trees with braces), each resolved to the file of the
//! longest module prefix; `mod x;` declarations are not arrows, `pub use` re-exports are (a facade
//! imports what it shows). A Python file's arrows are its `import`/`from ... import` of the
//! project's own modules. An arrow that closes a circle is an arrow back up: the test names every
//! circle, file by file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Strip comments, strings and char literals from Rust source, keeping line structure.
fn strip_rust(src: &str) -> String {
    let b: Vec<char> = src.chars().collect();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == '/' && b.get(i + 1) == Some(&'/') {
            while i < b.len() && b[i] != '\n' {
                i += 1;
            }
        } else if c == '/' && b.get(i + 1) == Some(&'*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == '/' && b.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == '*' && b.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    if b[i] == '\n' {
                        out.push('\n');
                    }
                    i += 1;
                }
            }
        } else if c == 'r'
            && (b.get(i + 1) == Some(&'"') || b.get(i + 1) == Some(&'#'))
            && (i == 0 || !(b[i - 1].is_alphanumeric() || b[i - 1] == '_'))
        {
            // raw string r"..." or r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                if j >= b.len() {
                    break;
                }
                if b[j] == '"' && (0..hashes).all(|k| b.get(j + 1 + k) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                if b[j] == '\n' {
                    out.push('\n');
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c == '"' {
            i += 1;
            while i < b.len() && b[i] != '"' {
                if b[i] == '\\' {
                    i += 1;
                }
                if i < b.len() && b[i] == '\n' {
                    out.push('\n');
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c == '\'' {
            // a char literal ('x', '\n', '\u{..}') or a lifetime ('a)
            if b.get(i + 1) == Some(&'\\') {
                let mut j = i + 2;
                while j < b.len() && b[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
                out.push_str("' '");
            } else if b.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push_str("' '");
            } else {
                out.push(c);
                i += 1;
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

/// A Rust crate's module tree: module path -> file.
struct RustCrate {
    name: String,
    modules: BTreeMap<Vec<String>, PathBuf>,
    /// `#[macro_export]` macros live at the crate's root path but in the file that defines them.
    macros: BTreeMap<String, PathBuf>,
}

fn module_path(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut segs: Vec<String> = rel
        .iter()
        .map(|s| s.to_string_lossy().into_owned())
        .collect();
    let last = segs.pop().unwrap();
    let stem = last.trim_end_matches(".rs");
    if !matches!(stem, "mod" | "lib" | "main") {
        segs.push(stem.to_string());
    }
    segs
}

fn rs_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            // src/bin/*.rs are crates of their own
            if p.file_name().is_some_and(|n| n == "bin") && p.parent() == Some(dir) {
                continue;
            }
            rs_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

fn ident_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

/// Every `a::b::c` path of the stripped source, with the `use` trees' braces expanded, each with
/// the inline modules (`mod tests { ... }`) it is written in.
fn paths(code: &str) -> Vec<(Vec<String>, Vec<String>)> {
    let toks = tokenize(code);
    let mut out = Vec::new();
    // inline modules open at this point, with the brace depth each opened at
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    let mut i = 0;
    let here =
        |inline: &Vec<(String, usize)>| inline.iter().map(|(m, _)| m.clone()).collect::<Vec<_>>();
    while i < toks.len() {
        match toks[i].as_str() {
            "{" => depth += 1,
            "}" => {
                depth = depth.saturating_sub(1);
                if inline.last().is_some_and(|(_, d)| *d == depth) {
                    inline.pop();
                }
            }
            "mod" if toks.get(i + 2).map(String::as_str) == Some("{") => {
                inline.push((toks[i + 1].clone(), depth));
                depth += 1;
                i += 3;
                continue;
            }
            _ => {}
        }
        if toks[i] == "use" {
            // parse a use tree up to `;`
            let mut j = i + 1;
            let mut prefix = Vec::new();
            let mut found = Vec::new();
            parse_use_tree(&toks, &mut j, &mut prefix, &mut found);
            let h = here(&inline);
            out.extend(found.into_iter().map(|p| (h.clone(), p)));
            i = j;
            continue;
        }
        if ident_start(toks[i].chars().next().unwrap_or(' '))
            && toks.get(i + 1).map(String::as_str) == Some("::")
            && (i == 0 || toks[i - 1] != "::")
        {
            let mut p = vec![toks[i].clone()];
            let mut j = i + 1;
            while toks.get(j).map(String::as_str) == Some("::")
                && toks
                    .get(j + 1)
                    .is_some_and(|t| ident_start(t.chars().next().unwrap_or(' ')))
            {
                p.push(toks[j + 1].clone());
                j += 2;
            }
            out.push((here(&inline), p));
            i = j;
            continue;
        }
        i += 1;
    }
    out
}

fn tokenize(code: &str) -> Vec<String> {
    let c: Vec<char> = code.chars().collect();
    let mut t = Vec::new();
    let mut i = 0;
    while i < c.len() {
        if ident_start(c[i]) {
            let s = i;
            while i < c.len() && (c[i].is_alphanumeric() || c[i] == '_') {
                i += 1;
            }
            t.push(c[s..i].iter().collect());
        } else if c[i] == ':' && c.get(i + 1) == Some(&':') {
            t.push("::".into());
            i += 2;
        } else if c[i].is_whitespace() {
            i += 1;
        } else {
            t.push(c[i].to_string());
            i += 1;
        }
    }
    t
}

fn parse_use_tree(
    t: &[String],
    j: &mut usize,
    prefix: &mut Vec<String>,
    out: &mut Vec<Vec<String>>,
) {
    let base = prefix.len();
    loop {
        match t.get(*j).map(String::as_str) {
            None | Some(";") => {
                if prefix.len() > base || base > 0 {
                    out.push(prefix.clone());
                }
                break;
            }
            Some("{") => {
                *j += 1;
                loop {
                    let mut sub = prefix.clone();
                    parse_use_tree(t, j, &mut sub, out);
                    match t.get(*j).map(String::as_str) {
                        Some(",") => {
                            *j += 1;
                            if t.get(*j).map(String::as_str) == Some("}") {
                                *j += 1;
                                break;
                            }
                        }
                        Some("}") => {
                            *j += 1;
                            break;
                        }
                        _ => break,
                    }
                }
                prefix.truncate(base);
                return;
            }
            Some("::") => *j += 1,
            Some("as") => *j += 2,
            Some("*") => {
                *j += 1;
            }
            Some(",") | Some("}") => {
                out.push(prefix.clone());
                prefix.truncate(base);
                return;
            }
            Some(s) => {
                prefix.push(s.to_string());
                *j += 1;
            }
        }
    }
    // consume the `;`
    if t.get(*j).map(String::as_str) == Some(";") {
        *j += 1;
    }
    prefix.truncate(base);
}

fn load_crate(dir: &Path) -> Option<RustCrate> {
    let toml = std::fs::read_to_string(dir.join("Cargo.toml")).ok()?;
    let name = toml
        .lines()
        .skip_while(|l| l.trim() != "[package]")
        .find_map(|l| l.trim().strip_prefix("name = "))?
        .trim_matches('"')
        .to_string();
    let src = dir.join("src");
    // a package with a library: src/main.rs is a crate of its own, that names the library by its
    // name; it is checked as one file (its `mod` children would be listed here)
    let skip = src.join("lib.rs").is_file().then(|| src.join("main.rs"));
    Some(load_tree(name, &src, skip.as_deref()))
}

/// The bench targets of a package made of several files: each `benches/NAME/main.rs` is the root
/// of a crate of its own, whose modules are the files of its folder.
fn load_benches(dir: &Path) -> Vec<RustCrate> {
    let Ok(rd) = std::fs::read_dir(dir.join("benches")) else {
        return Vec::new();
    };
    let mut roots: Vec<PathBuf> = rd
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.join("main.rs").is_file())
        .collect();
    roots.sort();
    roots
        .into_iter()
        .map(|r| {
            let rel = r.strip_prefix(root()).unwrap_or(&r).display().to_string();
            load_tree(format!("bench {rel}"), &r, None)
        })
        .collect()
}

/// The module tree of the crate whose root file (lib.rs or main.rs) is in `src`, `skip` left out.
fn load_tree(name: String, src: &Path, skip: Option<&Path>) -> RustCrate {
    let mut files = Vec::new();
    rs_files(src, &mut files);
    let mut modules = BTreeMap::new();
    let mut macros = BTreeMap::new();
    for f in files {
        if skip == Some(f.as_path()) {
            continue;
        }
        let code = strip_rust(&std::fs::read_to_string(&f).unwrap());
        let toks = tokenize(&code);
        for w in toks.windows(3) {
            if w[0] == "macro_rules" && w[1] == "!" {
                macros.insert(w[2].clone(), f.clone());
            }
        }
        modules.insert(module_path(src, &f), f);
    }
    RustCrate {
        name,
        modules,
        macros,
    }
}

/// The file a path from module `here` names, if it is of this crate.
fn resolve(c: &RustCrate, here: &[String], p: &[String]) -> Option<PathBuf> {
    let mut abs: Vec<String> = match p.first().map(String::as_str) {
        Some("crate") if p.len() == 2 && c.macros.contains_key(&p[1]) => {
            return c.macros.get(&p[1]).cloned();
        }
        Some("crate") => p[1..].to_vec(),
        Some("self") => here.iter().cloned().chain(p[1..].iter().cloned()).collect(),
        Some("super") => {
            let mut base = here.to_vec();
            let mut k = 0;
            while p.get(k).map(String::as_str) == Some("super") {
                base.pop();
                k += 1;
            }
            base.into_iter().chain(p[k..].iter().cloned()).collect()
        }
        Some(first) => {
            let mut child = here.to_vec();
            child.push(first.to_string());
            if c.modules.contains_key(&child) {
                here.iter().cloned().chain(p.iter().cloned()).collect()
            } else {
                return None;
            }
        }
        None => return None,
    };
    while !abs.is_empty() {
        if let Some(f) = c.modules.get(&abs) {
            return Some(f.clone());
        }
        abs.pop();
    }
    c.modules.get(&abs).cloned()
}

type Graph = BTreeMap<PathBuf, BTreeSet<PathBuf>>;

fn rust_graph(c: &RustCrate) -> Graph {
    let mut g = Graph::new();
    for (m, f) in &c.modules {
        let code = strip_rust(&std::fs::read_to_string(f).unwrap());
        let mut to = BTreeSet::new();
        for (inline, p) in paths(&code) {
            // a path written in an inline module is relative to it; its `super` of the file
            let here: Vec<String> = m.iter().chain(inline.iter()).cloned().collect();
            if let Some(t) = resolve(c, &here, &p) {
                if &t != f {
                    to.insert(t);
                }
            }
        }
        g.insert(f.clone(), to);
    }
    g
}

/// Python packages of the project: each folder of `.py` files is one namespace; `import x` and
/// `from x import y` of a module in the same folder, or `from .x`/`from pkg.x` of the package,
/// are arrows.
fn python_graph(dir: &Path, pkg_root: &Path, g: &mut Graph) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<_> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if p.file_name()
                .is_some_and(|n| n != "__pycache__" && n != "venv" && n != "build")
            {
                python_graph(&p, pkg_root, g);
            }
            continue;
        }
        if p.extension().is_none_or(|e| e != "py") {
            continue;
        }
        let src = std::fs::read_to_string(&p).unwrap();
        let mut to = BTreeSet::new();
        for line in src.lines() {
            let l = line.trim_start();
            let mods: Vec<String> = if let Some(rest) = l.strip_prefix("from ") {
                let Some((m, names)) = rest.split_once(" import ") else {
                    continue;
                };
                let m = m.trim();
                let mut v = vec![m.to_string()];
                for n in names.trim_matches(|c| c == '(' || c == ')').split(',') {
                    let n = n.split_whitespace().next().unwrap_or("");
                    if !n.is_empty() {
                        v.push(format!("{m}.{n}").replace("..", "."));
                    }
                }
                v
            } else if let Some(rest) = l.strip_prefix("import ") {
                rest.split(',')
                    .map(|s| s.split_whitespace().next().unwrap_or("").to_string())
                    .collect()
            } else {
                continue;
            };
            for m in mods {
                if let Some(t) = py_resolve(&p, pkg_root, &m) {
                    if t != p {
                        to.insert(t);
                    }
                }
            }
        }
        g.insert(p, to);
    }
}

fn py_resolve(file: &Path, pkg_root: &Path, m: &str) -> Option<PathBuf> {
    let dir = file.parent().unwrap();
    let dots = m.chars().take_while(|&c| c == '.').count();
    let rest = &m[dots..];
    let mut bases: Vec<PathBuf> = Vec::new();
    if dots > 0 {
        let mut b = dir.to_path_buf();
        for _ in 1..dots {
            b.pop();
        }
        bases.push(b);
    } else {
        bases.push(dir.to_path_buf());
        let mut b = dir.to_path_buf();
        while b.starts_with(pkg_root) && b != pkg_root {
            b.pop();
            bases.push(b.clone());
        }
    }
    for b in bases {
        let mut p = b.clone();
        for s in rest.split('.').filter(|s| !s.is_empty()) {
            p.push(s);
        }
        let f = p.with_extension("py");
        if f.is_file() {
            return Some(f);
        }
        let init = p.join("__init__.py");
        if !rest.is_empty() && init.is_file() {
            return Some(init);
        }
    }
    None
}

/// Every circle of the graph (Tarjan's strongly connected components of more than one file).
fn circles(g: &Graph) -> Vec<Vec<PathBuf>> {
    struct St<'a> {
        g: &'a Graph,
        idx: BTreeMap<&'a PathBuf, usize>,
        low: BTreeMap<&'a PathBuf, usize>,
        on: BTreeSet<&'a PathBuf>,
        stack: Vec<&'a PathBuf>,
        n: usize,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut St<'a>, v: &'a PathBuf) {
        s.idx.insert(v, s.n);
        s.low.insert(v, s.n);
        s.n += 1;
        s.stack.push(v);
        s.on.insert(v);
        if let Some(ws) = s.g.get(v) {
            for w in ws {
                let Some((w, _)) = s.g.get_key_value(w) else {
                    continue;
                };
                if !s.idx.contains_key(w) {
                    visit(s, w);
                    let l = s.low[w].min(s.low[v]);
                    s.low.insert(v, l);
                } else if s.on.contains(w) {
                    let l = s.idx[w].min(s.low[v]);
                    s.low.insert(v, l);
                }
            }
        }
        if s.low[v] == s.idx[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = St {
        g,
        idx: BTreeMap::new(),
        low: BTreeMap::new(),
        on: BTreeSet::new(),
        stack: Vec::new(),
        n: 0,
        out: Vec::new(),
    };
    for v in g.keys() {
        if !s.idx.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

fn workspace_members() -> Vec<PathBuf> {
    let toml = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let start = toml.find("members = [").expect("workspace members");
    let end = start + toml[start..].find(']').unwrap();
    toml[start + 11..end]
        .split(',')
        .map(|s| s.trim().trim_matches('"'))
        .filter(|s| !s.is_empty())
        .map(|s| root().join(s))
        .collect()
}

fn report(g: &Graph) -> Vec<String> {
    let r = &root();
    circles(g)
        .into_iter()
        .map(|c| {
            let names: Vec<String> = c
                .iter()
                .map(|p| p.strip_prefix(r).unwrap_or(p).display().to_string())
                .collect();
            let arrows: Vec<String> = c
                .iter()
                .flat_map(|a| {
                    g[a].iter().filter(|b| c.contains(b)).map(move |b| {
                        format!(
                            "{} -> {}",
                            a.strip_prefix(r).unwrap_or(a).display(),
                            b.strip_prefix(r).unwrap_or(b).display()
                        )
                    })
                })
                .collect();
            format!(
                "circle of {} files: {}\n    {}",
                c.len(),
                names.join(", "),
                arrows.join("\n    ")
            )
        })
        .collect()
}

#[test]
fn rust_files_import_without_circles() {
    let mut problems = Vec::new();
    let (mut crates, mut benches) = (0, 0);
    for m in workspace_members()
        .iter()
        .chain([root().join("fuzz")].iter())
    {
        let mut trees: Vec<RustCrate> = load_crate(m).into_iter().collect();
        crates += trees.len();
        let bench_trees = load_benches(m);
        benches += bench_trees.len();
        trees.extend(bench_trees);
        for c in trees {
            for p in report(&rust_graph(&c)) {
                problems.push(format!("{}: {p}", c.name));
            }
        }
    }
    assert!(crates >= 5, "found only {crates} crates");
    assert!(
        benches >= 1,
        "found no bench target of several files (benches/NAME/main.rs)"
    );
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn python_files_import_without_circles() {
    let r = root();
    let mut g = Graph::new();
    for d in ["hdl", "python", "cluster", "benches"] {
        python_graph(&r.join(d), &r.join(d), &mut g);
    }
    assert!(g.len() >= 10, "found only {} Python files", g.len());
    let problems = report(&g);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_checker_sees_a_circle() {
    let (a, b, c) = (PathBuf::from("a"), PathBuf::from("b"), PathBuf::from("c"));
    let mut g = Graph::new();
    g.insert(a.clone(), [b.clone()].into());
    g.insert(b.clone(), [c.clone()].into());
    g.insert(c.clone(), [a.clone()].into());
    assert_eq!(circles(&g), vec![vec![a.clone(), b.clone(), c.clone()]]);
    g.insert(c.clone(), BTreeSet::new());
    assert!(circles(&g).is_empty());
    let code = strip_rust(
        "use crate::{a::{b, c as d}, e};\nfn f() { super::g::h(); m::x(); } // crate::z\n",
    );
    let ps: Vec<Vec<String>> = paths(&code).into_iter().map(|(_, p)| p).collect();
    assert!(
        ps.contains(&vec!["crate".into(), "a".into(), "b".into()]),
        "{ps:?}"
    );
    assert!(
        ps.contains(&vec!["crate".into(), "a".into(), "c".into()]),
        "{ps:?}"
    );
    assert!(ps.contains(&vec!["crate".into(), "e".into()]), "{ps:?}");
    assert!(
        ps.contains(&vec!["super".into(), "g".into(), "h".into()]),
        "{ps:?}"
    );
    assert!(
        !ps.iter().any(|p| p.last().is_some_and(|s| s == "z")),
        "{ps:?}"
    );
}

/// The workspace crates a `Cargo.toml` names under `[dependencies]`.
fn workspace_deps(toml: &str, crates: &[String]) -> Vec<String> {
    let mut deps = Vec::new();
    let mut on = false;
    for l in toml.lines() {
        let t = l.trim();
        if t.starts_with('[') {
            on = t == "[dependencies]";
            continue;
        }
        if on {
            if let Some(name) = t.split(['=', '.', ' ']).next() {
                if crates.iter().any(|c| c == name) {
                    deps.push(name.to_string());
                }
            }
        }
    }
    deps.sort();
    deps
}

#[test]
fn docs_architecture_table_is_the_crates_dependencies() {
    let r = root();
    let doc = std::fs::read_to_string(r.join("docs/architecture.md")).unwrap();
    let svg = std::fs::read_to_string(r.join("docs/img/architecture.svg")).unwrap();
    // | `crate` | `folder/` ... | `dep`, `dep` |
    let rows: Vec<(String, String, Vec<String>)> = doc
        .lines()
        .filter(|l| l.starts_with("| `"))
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            let tick = |s: &str| -> Vec<String> {
                s.split('`')
                    .enumerate()
                    .filter(|(i, _)| i % 2 == 1)
                    .map(|(_, x)| x.to_string())
                    .collect()
            };
            let mut deps = tick(cells[3]);
            deps.sort();
            (tick(cells[1])[0].clone(), tick(cells[2])[0].clone(), deps)
        })
        .collect();
    let names: Vec<String> = rows.iter().map(|r| r.0.clone()).collect();
    let mut dirs: Vec<PathBuf> = workspace_members();
    dirs.push(r.join("fuzz"));
    assert_eq!(
        rows.len(),
        dirs.len(),
        "one row per crate of the workspace and fuzz/"
    );
    for dir in dirs {
        let toml = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        let c = load_crate(&dir).unwrap();
        let row = rows
            .iter()
            .find(|x| x.0 == c.name)
            .unwrap_or_else(|| panic!("docs/architecture.md has no row for {}", c.name));
        let folder = dir.strip_prefix(&r).unwrap().display().to_string();
        let folder = if folder.is_empty() {
            "src".into()
        } else {
            folder
        };
        assert_eq!(
            row.1.trim_end_matches('/'),
            folder,
            "the folder of {} in docs/architecture.md",
            c.name
        );
        assert_eq!(
            row.2,
            workspace_deps(&toml, &names),
            "docs/architecture.md: what {} may import is what its Cargo.toml names",
            c.name
        );
        assert!(
            svg.contains(&format!(">{}<", c.name)),
            "docs/img/architecture.svg does not draw {}",
            c.name
        );
    }
}

/// With `autotests = false`, a file of tests/ that is neither a module of tests/integration.rs
/// nor a `[[test]]` of Cargo.toml is never compiled, and its tests never run: each is exactly
/// one of them.
#[test]
fn every_test_file_is_compiled_once() {
    let dir = root().join("tests");
    let integration = std::fs::read_to_string(dir.join("integration.rs")).unwrap();
    let modules: BTreeSet<String> = integration
        .lines()
        .filter_map(|l| l.trim().strip_prefix("mod ")?.strip_suffix(';'))
        .map(|m| format!("{m}.rs"))
        .collect();
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let targets: BTreeSet<String> = manifest
        .lines()
        .filter_map(|l| l.trim().strip_prefix("path = \"tests/")?.strip_suffix('"'))
        .map(str::to_string)
        .collect();
    let mut problems = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if !name.ends_with(".rs") || name == "integration.rs" {
            continue;
        }
        match (modules.contains(&name), targets.contains(&name)) {
            (true, true) => problems.push(format!(
                "tests/{name} is both a module of tests/integration.rs and a [[test]] of Cargo.toml: its tests run twice"
            )),
            (false, false) => problems.push(format!(
                "tests/{name} is compiled by nothing: add `mod {};` to tests/integration.rs (or a [[test]] to Cargo.toml)",
                name.trim_end_matches(".rs")
            )),
            _ => {}
        }
    }
    for m in modules.iter().chain(&targets) {
        let folder = dir.join(m.trim_end_matches(".rs")).join("mod.rs");
        if !dir.join(m).is_file() && !folder.is_file() {
            problems.push(format!("tests/{m} is declared but does not exist"));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
