//! A regression folder's files, written from its [`Summary`]: `regress.json`, `results.jsonl`
//! (sorted by seed), `coverage.json`, `coverage.ucis.xml`, the code coverage, `report.html` with
//! the sign-off table at its top, and `missing.txt`.

use crate::error::RegressError;
use crate::summary::Summary;
use pmu50_coverage::CoverageFile;
use std::io::Write;
use std::path::Path;

/// A `fmt::Write` into an `io::Write`, keeping the first I/O error.
struct IoText<W: std::io::Write> {
    out: W,
    err: Option<std::io::Error>,
}

impl<W: std::io::Write> std::fmt::Write for IoText<W> {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        if self.err.is_some() {
            return Err(std::fmt::Error);
        }
        self.out.write_all(s.as_bytes()).map_err(|e| {
            self.err = Some(e);
            std::fmt::Error
        })
    }
}

/// Write regress.json, results.jsonl (sorted by seed), coverage.json, coverage.ucis.xml,
/// report.html (and missing.txt when seeds are missing) into `dir`, each atomically; the
/// folders of `failures/` whose signature no seed has any more are removed.
pub fn write(s: &Summary, dir: &Path, extra: Option<&str>) -> Result<(), RegressError> {
    use pmu50_testbench::atomic_file::{write_atomic, AtomicFile, OutputError};
    let mut batch = pmu50_testbench::atomic_file::Batch::new();
    // the digests of the completed files, sealed into regress.json (renamed last)
    let mut digests = std::collections::BTreeMap::new();
    let results = dir.join("results.jsonl");
    let werr = |path: &Path| {
        let path = path.to_path_buf();
        move |source: std::io::Error| {
            RegressError::Output(OutputError::Write {
                path: path.clone(),
                source,
            })
        }
    };
    {
        let mut w = std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&results)?);
        let mut reader = s.store.reader()?;
        for e in &s.store.entries {
            let line = reader.line(e)?;
            w.write_all(line)
                .and_then(|_| w.write_all(b"\n"))
                .map_err(werr(&results))?;
        }
        let f = w.into_inner().map_err(|e| werr(&results)(e.into_error()))?;
        digests.insert(
            "results.jsonl".to_string(),
            crate::evidence::file_digest(f.temp_path())?,
        );
        batch.add(f);
    }
    // Written a line at a time: the run list of a million seeds is 330 MB of UCIS text.
    type Text = fn(&CoverageFile, &mut dyn std::fmt::Write) -> std::fmt::Result;
    let texts: [(&str, Text); 2] = [
        ("coverage.json", |c, w| c.write_text(w)),
        ("coverage.ucis.xml", |c, w| {
            pmu50_coverage::write_ucis_xml(c, w)
        }),
    ];
    for (name, text) in texts {
        let path = dir.join(name);
        let mut w = IoText {
            out: std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&path)?),
            err: None,
        };
        if text(&s.coverage, &mut w).is_err() || w.err.is_some() {
            return Err(werr(&path)(
                w.err
                    .unwrap_or_else(|| std::io::Error::other("formatting failed")),
            ));
        }
        let f = w
            .out
            .into_inner()
            .map_err(|e| werr(&path)(e.into_error()))?;
        digests.insert(
            name.to_string(),
            crate::evidence::file_digest(f.temp_path())?,
        );
        batch.add(f);
    }
    if let Some(code) = &s.code {
        // the regression's code coverage, whether one run wrote it or a merge of its parts:
        // the same bytes either way
        let prov = s.evidence.as_ref().map(|e| crate::provenance::Provenance {
            made_by: "pmu50 regress --code-coverage".into(),
            ..e.provenance.clone()
        });
        code.write(dir, &mut batch, prov.as_ref())?;
    }
    let spec = crate::evidence::spec_text(&s.spec, s.evidence.as_ref(), &digests)?;
    batch.set_last(write_atomic(&dir.join("regress.json"), spec.as_bytes())?);
    let repros = s.repro_folders(dir)?;
    // The sign-off table at the top, with what the folder holds so far (pmu50 signoff
    // rewrites it once the proofs and the formal kit have run).
    let signoff = crate::signoff::SignOff::evaluate(
        dir,
        s,
        &crate::criterion::Thresholds::default(),
        if s.missing.is_empty() {
            Ok(())
        } else {
            Err("the regression did not complete: pmu50 regress --resume".into())
        },
        None,
    )
    .map(|t| t.html())
    .unwrap_or_else(|e| {
        format!(
            "<h2>Sign-off</h2>\n<p class=\"bad\">{}</p>\n",
            pmu50_testbench::plot::svg::esc(&e.to_string())
        )
    });
    batch.add(write_atomic(
        &dir.join("report.html"),
        crate::report::html(s, extra, &repros, Some(&signoff)).as_bytes(),
    )?);
    let missing = dir.join("missing.txt");
    if s.missing.is_empty() {
        batch.remove_stale(missing);
    } else {
        let mut w = std::io::BufWriter::with_capacity(1 << 16, AtomicFile::stage(&missing)?);
        for s in s.missing.iter().flat_map(|r| r.clone()) {
            writeln!(w, "{s}").map_err(werr(&missing))?;
        }
        batch.add(w.into_inner().map_err(|e| werr(&missing)(e.into_error()))?);
    }
    batch.commit()?;
    Ok(())
}
