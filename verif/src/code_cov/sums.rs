//! Counts summed by point key: a part of a folder, or its total; LCOV output.

use super::points::*;
use crate::error::RegressError;
use std::collections::BTreeMap;
use std::path::Path;

/// Counts by point key, sorted: a part, or the total of a folder.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Total {
    pub counts: BTreeMap<String, u64>,
}

impl Total {
    /// Add a seed's counts (and its build's points, at zero where not hit).
    pub fn add_seed(&mut self, s: &SeedCode) {
        for &p in s.points.iter() {
            self.counts.entry(key_of(p).to_string()).or_insert(0);
        }
        for &(p, n) in &s.counts {
            let c = self.counts.entry(key_of(p).to_string()).or_insert(0);
            *c = c.saturating_add(n);
        }
    }

    pub fn add(&mut self, o: &Total) {
        for (k, n) in &o.counts {
            let c = self.counts.entry(k.clone()).or_insert(0);
            *c = c.saturating_add(*n);
        }
    }

    /// As a Verilator coverage.dat, with `note` lines (`# ...`) after the header.
    pub fn dat(&self, note: &str) -> String {
        let mut s = String::with_capacity(self.counts.len() * 160);
        s.push_str(DAT_HEADER);
        s.push('\n');
        for l in note.lines() {
            s.push_str("# ");
            s.push_str(l);
            s.push('\n');
        }
        for (k, n) in &self.counts {
            s.push_str("C '");
            s.push_str(k);
            s.push_str("' ");
            s.push_str(&n.to_string());
            s.push('\n');
        }
        s
    }

    /// Read a coverage.dat (a part): its counts and its `# ` note lines.
    pub fn read(path: &Path) -> Result<(Total, Vec<String>), RegressError> {
        let f = crate::folder::open_regular(path, false)?.ok_or_else(|| RegressError::File {
            path: path.to_path_buf(),
            reason: "No such file".into(),
        })?;
        let mut text = String::new();
        std::io::Read::read_to_string(&mut std::io::Read::take(f, 1 << 30), &mut text).map_err(
            |e| RegressError::File {
                path: path.to_path_buf(),
                reason: e.to_string(),
            },
        )?;
        let mut t = Total::default();
        let mut notes = Vec::new();
        for (n, l) in text.lines().enumerate() {
            if l == DAT_HEADER || l.is_empty() {
                continue;
            }
            if let Some(note) = l.strip_prefix("# ") {
                notes.push(note.to_string());
                continue;
            }
            let (k, c) = dat_line(l).ok_or_else(|| RegressError::Line {
                path: path.to_path_buf(),
                line: n as u64 + 1,
                reason: "not a line of a Verilator coverage file (C '<key>' <count>)".into(),
            })?;
            let e = t.counts.entry(k.to_string()).or_insert(0);
            *e = e.saturating_add(c);
        }
        Ok((t, notes))
    }

    /// LCOV tracefile data: per file, `DA:<line>,<count>` for each source line of a block or
    /// branch (the largest count of the points holding the line), `BRDA:<line>,0,<n>,<count>`
    /// for each branch, `BRDA:<line>,1,<n>,<count>` for each toggle bit (block 1: toggles,
    /// `<count>` the bit's rise-and-fall pairs) and `BRDA:<line>,2,<n>,<count>` for each
    /// expression term (block 2), with the LF/LH/BRF/BRH totals. Waivers are not
    /// applied.
    pub fn lcov(&self) -> String {
        struct F {
            da: BTreeMap<u32, u64>,
            br: Vec<(u32, u8, u64)>,
        }
        let mut files: BTreeMap<String, F> = BTreeMap::new();
        for (k, &n) in &self.counts {
            let p = Point::parse(k);
            if p.kind == Kind::Other || p.file.is_empty() {
                continue;
            }
            let f = files.entry(p.file.clone()).or_insert(F {
                da: BTreeMap::new(),
                br: Vec::new(),
            });
            match p.kind {
                Kind::Line | Kind::Branch => {
                    for &(a, b) in &p.lines {
                        for l in a..=b.min(a.saturating_add(100_000)) {
                            let e = f.da.entry(l).or_insert(0);
                            *e = (*e).max(n);
                        }
                    }
                    if p.kind == Kind::Branch {
                        f.br.push((p.line, 0, n));
                    }
                }
                Kind::Toggle => f.br.push((p.line, 1, n)),
                Kind::Expr => f.br.push((p.line, 2, n)),
                Kind::Other => {}
            }
        }
        let mut s = String::from("TN:pmu50\n");
        for (name, mut f) in files {
            s.push_str(&format!("SF:{name}\n"));
            f.br.sort_by_key(|b| (b.0, b.1));
            let mut seq: BTreeMap<(u32, u8), u32> = BTreeMap::new();
            for (l, block, n) in &f.br {
                let i = seq.entry((*l, *block)).or_insert(0);
                s.push_str(&format!("BRDA:{l},{block},{i},{n}\n"));
                *i += 1;
            }
            s.push_str(&format!(
                "BRF:{}\nBRH:{}\n",
                f.br.len(),
                f.br.iter().filter(|b| b.2 > 0).count()
            ));
            for (l, n) in &f.da {
                s.push_str(&format!("DA:{l},{n}\n"));
            }
            s.push_str(&format!(
                "LF:{}\nLH:{}\nend_of_record\n",
                f.da.len(),
                f.da.values().filter(|n| **n > 0).count()
            ));
        }
        s
    }
}

/// Seeds as ranges: `1-32,40`.
pub fn seeds_text(seeds: &[u64]) -> String {
    let mut v: Vec<u64> = seeds.to_vec();
    v.sort_unstable();
    v.dedup();
    let mut out: Vec<String> = Vec::new();
    let mut i = 0;
    while i < v.len() {
        let mut j = i;
        while j + 1 < v.len() && v[j + 1] == v[j] + 1 {
            j += 1;
        }
        out.push(if i == j {
            v[i].to_string()
        } else {
            format!("{}-{}", v[i], v[j])
        });
        i = j + 1;
    }
    out.join(",")
}

pub(super) fn parse_seeds(text: &str) -> Option<Vec<u64>> {
    let mut v = Vec::new();
    for r in text.split(',').filter(|r| !r.is_empty()) {
        match r.split_once('-') {
            Some((a, b)) => {
                let (a, b): (u64, u64) = (a.parse().ok()?, b.parse().ok()?);
                if b < a || b - a > crate::folder::MAX_SEEDS {
                    return None;
                }
                v.extend(a..=b);
            }
            None => v.push(r.parse().ok()?),
        }
    }
    Some(v)
}
