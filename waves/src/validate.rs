//! Streaming VCD validator: checks a file before it is handed to `wellen`.
//!
//! `wellen` is a fast, forgiving VCD parser: on many malformed files it panics
//! (a value wider than its variable, a bad bit character, an undeclared
//! identifier, an unparsable real, an unbalanced `$upscope`, a second
//! `$timescale`, ...), prints a warning and drops data (time going backwards),
//! or silently ignores text (anything after `$enddefinitions $end` on the same
//! line). [`validate`] reads the file once, front to back, and accepts only
//! files that `wellen` reads completely and correctly; for anything else it
//! returns the line and what is wrong ([`Problem`]).
//!
//! Memory is bounded: the input is read through a 64 KiB buffer; the
//! validator keeps one token (at most [`MAX_TOKEN_BYTES`], or the width bound
//! plus one for vector values) and one entry per declared identifier.
//!
//! Accepted grammar (IEEE 1364-2005 §18.2, restricted to what `wellen` reads):
//!
//! * header commands `$date`, `$version`, `$comment` (free text, `$date`,
//!   `$version` at most once), `$timescale` (once; factor a whole number >= 1,
//!   unit `s ms us ns ps fs`), `$scope TYPE NAME`, `$upscope` (balanced),
//!   `$var TYPE SIZE ID NAME [INDEX]`, `$enddefinitions` (all scopes closed);
//!   each ends with a whitespace-separated `$end`; `$attrbegin`/`$attrend` are
//!   refused;
//! * `$var`: a type `wellen` knows, a decimal size from 1 to the width bound
//!   (0 or 1 for `event`), an identifier of printable ASCII, a UTF-8 name
//!   without control characters; an identifier declared twice must have the
//!   same kind and width both times;
//! * body: `#TIME` (decimal, never smaller than the previous time), scalar
//!   changes `0 1 x z h u w l -` (either case) for 1-bit variables and events,
//!   `bBITS ID` for bit vectors (1 to width bits; fewer bits are extended only
//!   from a leading `0 1 x z`), `rREAL ID` for real variables (Rust's `f64`
//!   syntax, `nan` and `inf` included), `sTEXT ID` (UTF-8) for string
//!   variables, `$comment ... $end`, and the markers `$dumpvars $dumpall
//!   $dumpon $dumpoff $end`. Every identifier must be declared.

use std::collections::HashMap;
use std::io::Read;

/// Longest token (outside vector values) the validator accepts.
pub const MAX_TOKEN_BYTES: usize = 1 << 20;

/// Longest header command body (`$var ... $end`) the validator accepts.
const MAX_COMMAND_BYTES: usize = 1 << 16;

/// What is wrong with a VCD, and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Problem {
    /// 1-based line of the offending token or command.
    pub line: u64,
    /// What is wrong and what would be valid.
    pub what: String,
}

/// Why validation stopped.
#[derive(Debug)]
pub enum ValidateError {
    /// Reading failed.
    Io(std::io::Error),
    /// The file is not a VCD `wellen` reads correctly.
    Malformed(Problem),
}

impl From<std::io::Error> for ValidateError {
    fn from(e: std::io::Error) -> Self {
        ValidateError::Io(e)
    }
}

/// What a valid file contains.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Summary {
    /// Number of `$var` declarations.
    pub vars: usize,
    /// Number of `#time` lines.
    pub timestamps: u64,
    /// Last time stamp (0 if none).
    pub end_time: u64,
    /// Number of value changes.
    pub changes: u64,
}

/// Value kind of a declared identifier, as `wellen` encodes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Bits(u32),
    Event,
    Real,
    Text,
}

impl Kind {
    fn describe(self) -> String {
        match self {
            Kind::Bits(w) => format!("{w}-bit vector"),
            Kind::Event => "event".into(),
            Kind::Real => "real".into(),
            Kind::Text => "string".into(),
        }
    }
}

struct Decl {
    kind: Kind,
    /// full dotted path, for messages
    path: String,
    line: u64,
}

const VAR_TYPES: &[&str] = &[
    "wire",
    "reg",
    "parameter",
    "integer",
    "string",
    "event",
    "real",
    "real_parameter",
    "supply0",
    "supply1",
    "time",
    "tri",
    "triand",
    "trior",
    "trireg",
    "tri0",
    "tri1",
    "wand",
    "wor",
    "logic",
    "port",
    "sparray",
    "realtime",
    "bit",
    "int",
    "shortint",
    "longint",
    "byte",
    "enum",
    "shortreal",
];

const SCOPE_TYPES: &[&str] = &[
    "module",
    "task",
    "function",
    "begin",
    "fork",
    "generate",
    "struct",
    "union",
    "class",
    "interface",
    "package",
    "program",
    "vhdl_architecture",
    "vhdl_procedure",
    "vhdl_function",
    "vhdl_record",
    "vhdl_process",
    "vhdl_block",
    "vhdl_for_generate",
    "vhdl_if_generate",
    "vhdl_generate",
    "vhdl_package",
    "unknown",
    "clocking",
    "sv_array",
];

const UNITS: &[&str] = &["s", "ms", "us", "ns", "ps", "fs"];

fn is_bit_char(c: u8) -> bool {
    matches!(
        c,
        b'0' | b'1'
            | b'x'
            | b'X'
            | b'z'
            | b'Z'
            | b'h'
            | b'H'
            | b'u'
            | b'U'
            | b'w'
            | b'W'
            | b'l'
            | b'L'
            | b'-'
    )
}

/// `wellen`'s header whitespace.
fn is_header_ws(c: u8) -> bool {
    matches!(c, b' ' | b'\n' | b'\r' | b'\t')
}

/// Shows bytes for a message: lossy UTF-8, control characters escaped, cut at 60 characters.
fn show(bytes: &[u8]) -> String {
    let s = String::from_utf8_lossy(bytes);
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i == 60 {
            out.push_str("...");
            break;
        }
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    out
}

/// Byte source with a 64 KiB buffer and line counting.
struct Src<R> {
    reader: R,
    buf: Box<[u8]>,
    pos: usize,
    len: usize,
    line: u64,
}

impl<R: Read> Src<R> {
    fn new(r: R) -> Self {
        Src {
            reader: r,
            buf: vec![0u8; 1 << 16].into_boxed_slice(),
            pos: 0,
            len: 0,
            line: 1,
        }
    }

    #[inline]
    fn next(&mut self) -> std::io::Result<Option<u8>> {
        if self.pos == self.len {
            loop {
                match self.reader.read(&mut self.buf) {
                    Ok(n) => {
                        self.pos = 0;
                        self.len = n;
                        break;
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e),
                }
            }
            if self.len == 0 {
                return Ok(None);
            }
        }
        let b = self.buf[self.pos];
        self.pos += 1;
        if b == b'\n' {
            self.line += 1;
        }
        Ok(Some(b))
    }
}

fn bad<T>(line: u64, what: impl Into<String>) -> Result<T, ValidateError> {
    Err(ValidateError::Malformed(Problem {
        line,
        what: what.into(),
    }))
}

/// Validate a VCD read from `input`; `max_var_width` bounds every `$var` size.
pub fn validate(input: impl Read, max_var_width: u32) -> Result<Summary, ValidateError> {
    let mut v = Validator {
        src: Src::new(input),
        max_width: max_var_width,
        ids: HashMap::new(),
        scopes: Vec::new(),
        summary: Summary::default(),
    };
    v.header()?;
    v.body()?;
    Ok(v.summary)
}

struct Validator<R> {
    src: Src<R>,
    max_width: u32,
    ids: HashMap<Vec<u8>, Decl>,
    scopes: Vec<String>,
    summary: Summary,
}

/// Splits a header command body like `wellen` does (on space, tab and newline).
fn header_tokens(body: &[u8]) -> Vec<(usize, &[u8])> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &c) in body.iter().enumerate() {
        let ws = matches!(c, b' ' | b'\t' | b'\n');
        match (ws, start) {
            (false, None) => start = Some(i),
            (true, Some(s)) => {
                out.push((s, &body[s..i]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &body[s..]));
    }
    out
}

fn printable_ascii(t: &[u8]) -> bool {
    !t.is_empty() && t.iter().all(|c| (0x21..=0x7e).contains(c))
}

/// A name `wellen` can take apart: UTF-8, no control characters, not starting
/// with `[`, brackets balanced, and no number in brackets longer than 9 digits.
fn check_name(line: u64, what: &str, raw: &[u8]) -> Result<String, ValidateError> {
    let Ok(s) = std::str::from_utf8(raw) else {
        return bad(line, format!("{what} `{}` is not valid UTF-8", show(raw)));
    };
    if s.chars().any(|c| c.is_control()) {
        return bad(
            line,
            format!("{what} `{}` contains a control character", show(raw)),
        );
    }
    if s.starts_with('[') {
        return bad(
            line,
            format!("{what} `{s}` starts with `[`; a name comes before its index"),
        );
    }
    let mut depth = 0u32;
    let mut digits = 0usize;
    for c in s.chars() {
        match c {
            '[' => {
                if depth > 0 {
                    return bad(line, format!("{what} `{s}` has nested `[`"));
                }
                depth = 1;
                digits = 0;
            }
            ']' => {
                if depth == 0 {
                    return bad(line, format!("{what} `{s}` has `]` without `[`"));
                }
                depth = 0;
            }
            '0'..='9' if depth > 0 => {
                digits += 1;
                if digits > 9 {
                    return bad(
                        line,
                        format!("{what} `{s}` has an index longer than 9 digits"),
                    );
                }
            }
            _ => digits = 0,
        }
    }
    if depth > 0 {
        return bad(line, format!("{what} `{s}` has `[` without `]`"));
    }
    Ok(s.to_string())
}

/// A header command: keyword (without `$`), line, body (empty for free-text commands).
type Command = (Vec<u8>, u64, Vec<u8>);

impl<R: Read> Validator<R> {
    /// Reads one header command the way `wellen` does. Returns `None` at end of
    /// file before a command; the keyword, its line, and the body (kept only
    /// for commands other than `$comment`, `$date`, `$version`).
    fn command(&mut self) -> Result<Option<Command>, ValidateError> {
        let first = loop {
            match self.src.next()? {
                None => return Ok(None),
                Some(c) if is_header_ws(c) => continue,
                Some(c) => break c,
            }
        };
        let line = self.src.line;
        if first != b'$' {
            return bad(
                line,
                format!(
                    "expected a header command such as `$scope`, `$var` or `$enddefinitions`, found `{}`",
                    show(&[first])
                ),
            );
        }
        let mut kw = Vec::new();
        loop {
            match self.src.next()? {
                None => return bad(line, format!("file ends inside command `${}`", show(&kw))),
                Some(c) if is_header_ws(c) => break,
                Some(c) => {
                    if kw.len() >= 64 {
                        return bad(
                            line,
                            format!("command `${}` is not a VCD command", show(&kw)),
                        );
                    }
                    kw.push(c);
                }
            }
        }
        let keep = !matches!(kw.as_slice(), b"comment" | b"date" | b"version");
        let mut body = Vec::new();
        let mut skipping = true;
        let mut end_index = 0u8;
        let mut kept = 0usize;
        let mut prev_ws = true; // the byte before the current one was whitespace (or none)
        let mut glued = false; // the `$` of the current `$end` candidate follows a non-space
        loop {
            let Some(c) = self.src.next()? else {
                return bad(
                    line,
                    format!("file ends before the `$end` of `${}`", show(&kw)),
                );
            };
            if skipping {
                if is_header_ws(c) {
                    continue;
                }
                skipping = false;
            }
            kept += 1;
            if keep {
                if kept > MAX_COMMAND_BYTES {
                    return bad(
                        line,
                        format!(
                            "`${}` is longer than {MAX_COMMAND_BYTES} bytes (no `$end`?)",
                            show(&kw)
                        ),
                    );
                }
                body.push(c);
            }
            end_index = match (end_index, c) {
                (0, b'$') => {
                    glued = !prev_ws;
                    1
                }
                (1, b'e') => 2,
                (2, b'n') => 3,
                (3, b'd') => break,
                _ => 0,
            };
            prev_ws = is_header_ws(c);
        }
        if keep {
            // `wellen` ends a command at the first `$end`, even inside a token.
            if glued {
                return bad(
                    line,
                    format!(
                        "`$end` of `${}` must be separated from the text before it by a space",
                        show(&kw)
                    ),
                );
            }
            body.truncate(body.len() - 4);
            while body.last().is_some_and(|c| is_header_ws(*c)) {
                body.pop();
            }
        }
        Ok(Some((kw, line, body)))
    }

    fn header(&mut self) -> Result<(), ValidateError> {
        let mut timescale_line: Option<u64> = None;
        let mut date_line: Option<u64> = None;
        let mut version_line: Option<u64> = None;
        loop {
            let Some((kw, line, body)) = self.command()? else {
                let line = self.src.line;
                return bad(
                    line,
                    "file ends before `$enddefinitions $end`: the header is incomplete",
                );
            };
            match kw.as_slice() {
                b"comment" => {}
                b"date" => {
                    if let Some(l) = date_line {
                        return bad(
                            line,
                            format!(
                                "second `$date` (the first is on line {l}); a VCD has at most one"
                            ),
                        );
                    }
                    date_line = Some(line);
                }
                b"version" => {
                    if let Some(l) = version_line {
                        return bad(line, format!("second `$version` (the first is on line {l}); a VCD has at most one"));
                    }
                    version_line = Some(line);
                }
                b"timescale" => {
                    if let Some(l) = timescale_line {
                        return bad(line, format!("second `$timescale` (the first is on line {l}); a VCD has exactly one"));
                    }
                    timescale_line = Some(line);
                    self.timescale(line, &body)?;
                }
                b"scope" => self.scope(line, &body)?,
                b"upscope" => {
                    if !header_tokens(&body).is_empty() {
                        return bad(
                            line,
                            format!("`$upscope {}`: $upscope takes no arguments", show(&body)),
                        );
                    }
                    if self.scopes.pop().is_none() {
                        return bad(line, "`$upscope` without an open `$scope`");
                    }
                }
                b"var" => self.var(line, &body)?,
                b"enddefinitions" => {
                    if !header_tokens(&body).is_empty() {
                        return bad(line, "`$enddefinitions` takes no arguments");
                    }
                    if !self.scopes.is_empty() {
                        return bad(
                            line,
                            format!(
                                "`$enddefinitions` with {} scope(s) still open (`{}`): each `$scope` needs an `$upscope`",
                                self.scopes.len(),
                                self.scopes.join(".")
                            ),
                        );
                    }
                    return self.after_enddefinitions();
                }
                b"attrbegin" | b"attrend" => {
                    return bad(
                        line,
                        format!(
                            "`${}` (a GTKWave attribute extension) is not supported",
                            show(&kw)
                        ),
                    );
                }
                other => {
                    return bad(
                        line,
                        format!(
                            "unknown header command `${}`; valid are $date $version $comment $timescale $scope $upscope $var $enddefinitions",
                            show(other)
                        ),
                    );
                }
            }
        }
    }

    /// `wellen` skips the rest of the `$enddefinitions $end` line: it must be blank.
    fn after_enddefinitions(&mut self) -> Result<(), ValidateError> {
        let line = self.src.line;
        loop {
            match self.src.next()? {
                None | Some(b'\n') => return Ok(()),
                Some(c) if c.is_ascii_whitespace() => {}
                Some(c) => {
                    return bad(
                        line,
                        format!(
                            "`{}` after `$enddefinitions $end` on the same line would be ignored; start the body on a new line",
                            show(&[c])
                        ),
                    )
                }
            }
        }
    }

    fn timescale(&mut self, line: u64, body: &[u8]) -> Result<(), ValidateError> {
        let toks = header_tokens(body);
        let (factor, unit): (&[u8], &[u8]) = match toks.as_slice() {
            [(_, t)] => {
                let p = t
                    .iter()
                    .position(|c| !c.is_ascii_digit())
                    .unwrap_or(t.len());
                (&t[..p], &t[p..])
            }
            [(_, f), (_, u)] => (f, u),
            _ => {
                return bad(
                    line,
                    format!(
                        "`$timescale {}`: expected a factor and a unit, e.g. `1 ns`",
                        show(body)
                    ),
                );
            }
        };
        let ok_factor = factor.iter().all(|c| c.is_ascii_digit())
            && std::str::from_utf8(factor)
                .ok()
                .and_then(|f| f.parse::<u32>().ok())
                .is_some_and(|f| f >= 1);
        let ok_unit = std::str::from_utf8(unit).is_ok_and(|u| UNITS.contains(&u));
        if !ok_factor || !ok_unit {
            return bad(
                line,
                format!(
                    "`$timescale {}`: expected a whole factor from 1 to 4294967295 and a unit s, ms, us, ns, ps or fs, e.g. `1 ns`",
                    show(body)
                ),
            );
        }
        Ok(())
    }

    fn scope(&mut self, line: u64, body: &[u8]) -> Result<(), ValidateError> {
        let toks = header_tokens(body);
        let [(_, tpe), (_, name)] = toks.as_slice() else {
            return bad(
                line,
                format!(
                    "`$scope {}`: expected a scope type and a name, e.g. `$scope module top $end`",
                    show(body)
                ),
            );
        };
        let tpe_ok = std::str::from_utf8(tpe).is_ok_and(|t| SCOPE_TYPES.contains(&t));
        if !tpe_ok {
            return bad(
                line,
                format!("unknown scope type `{}`; valid are e.g. module, task, function, begin, fork, generate", show(tpe)),
            );
        }
        let name = check_name(line, "scope name", name)?;
        self.scopes.push(name);
        Ok(())
    }

    fn var(&mut self, line: u64, body: &[u8]) -> Result<(), ValidateError> {
        let toks = header_tokens(body);
        if toks.len() < 4 {
            return bad(
                line,
                format!("`$var {}`: expected type, size, identifier and name, e.g. `$var wire 8 ! cnt [7:0] $end`", show(body)),
            );
        }
        let (_, tpe) = toks[0];
        let (_, size) = toks[1];
        let (_, id) = toks[2];
        let name_start = toks[3].0;
        let (last_start, last) = toks[toks.len() - 1];
        let raw_name = &body[name_start..last_start + last.len()];
        let tpe_s = std::str::from_utf8(tpe)
            .ok()
            .filter(|t| VAR_TYPES.contains(t));
        let Some(tpe_s) = tpe_s else {
            return bad(
                line,
                format!("unknown variable type `{}`; valid are e.g. wire, reg, integer, real, event, string, parameter", show(tpe)),
            );
        };
        if size.is_empty() || size.len() > 10 || !size.iter().all(|c| c.is_ascii_digit()) {
            return bad(
                line,
                format!("variable size `{}` is not a whole number", show(size)),
            );
        }
        let width: u64 = std::str::from_utf8(size)
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(u64::MAX);
        if width > u64::from(self.max_width) {
            return bad(
                line,
                format!(
                    "variable `{}` is declared with {width} bits; the limit is {} bits",
                    show(raw_name),
                    self.max_width
                ),
            );
        }
        let width = width as u32;
        let kind = match tpe_s {
            "string" => Kind::Text,
            "real" | "realtime" | "shortreal" | "real_parameter" => Kind::Real,
            "event" => {
                if width > 1 {
                    return bad(
                        line,
                        format!(
                            "event `{}` has size {width}; an event has size 1 (or 0)",
                            show(raw_name)
                        ),
                    );
                }
                Kind::Event
            }
            _ => {
                if width == 0 {
                    return bad(
                        line,
                        format!(
                            "variable `{}` has size 0; a {tpe_s} has at least 1 bit",
                            show(raw_name)
                        ),
                    );
                }
                Kind::Bits(width)
            }
        };
        if !printable_ascii(id) {
            return bad(
                line,
                format!(
                    "identifier `{}` of `{}` must be printable ASCII characters (`!` to `~`)",
                    show(id),
                    show(raw_name)
                ),
            );
        }
        let name = check_name(line, "variable name", raw_name)?;
        let mut path = self.scopes.join(".");
        if !path.is_empty() {
            path.push('.');
        }
        path.push_str(&name);
        if let Some(prev) = self.ids.get(id) {
            if prev.kind != kind {
                return bad(
                    line,
                    format!(
                        "identifier `{}` of `{path}` ({}) was declared on line {} for `{}` as a {}; one identifier is one signal",
                        show(id),
                        kind.describe(),
                        prev.line,
                        prev.path,
                        prev.kind.describe()
                    ),
                );
            }
        } else {
            self.ids.insert(id.to_vec(), Decl { kind, path, line });
        }
        self.summary.vars += 1;
        Ok(())
    }

    /// Next body token (split on ASCII whitespace as `wellen` does), its line,
    /// or `None` at end of file. `cap` bounds its length.
    fn token(&mut self, tok: &mut Vec<u8>, cap: usize) -> Result<Option<u64>, ValidateError> {
        tok.clear();
        let c = loop {
            match self.src.next()? {
                None => return Ok(None),
                Some(c) if c.is_ascii_whitespace() => continue,
                Some(c) => break c,
            }
        };
        let line = self.src.line;
        tok.push(c);
        loop {
            match self.src.next()? {
                None => return Ok(Some(line)),
                Some(c) if c.is_ascii_whitespace() => return Ok(Some(line)),
                Some(c) => {
                    if tok.len() >= cap {
                        return bad(
                            line,
                            format!("token `{}` is longer than {cap} bytes", show(tok)),
                        );
                    }
                    tok.push(c);
                }
            }
        }
    }

    fn body(&mut self) -> Result<(), ValidateError> {
        let cap = MAX_TOKEN_BYTES.max(self.max_width as usize + 1);
        let mut tok = Vec::new();
        let mut id = Vec::new();
        let mut last_time: Option<(u64, u64)> = None; // (time, line)
        while let Some(line) = self.token(&mut tok, cap)? {
            match tok[0] {
                b'#' => {
                    let digits = &tok[1..];
                    let t = if !digits.is_empty()
                        && digits.len() <= 20
                        && digits.iter().all(|c| c.is_ascii_digit())
                    {
                        std::str::from_utf8(digits)
                            .ok()
                            .and_then(|s| s.parse::<u64>().ok())
                    } else {
                        None
                    };
                    let Some(t) = t else {
                        return bad(line, format!("time `{}` is not `#` followed by a whole number of at most 64 bits", show(&tok)));
                    };
                    if let Some((prev, pl)) = last_time {
                        if t < prev {
                            return bad(
                                line,
                                format!("time goes backwards: #{t} after #{prev} (line {pl}); times must not decrease"),
                            );
                        }
                    }
                    last_time = Some((t, line));
                    self.summary.timestamps += 1;
                    self.summary.end_time = t;
                }
                c if is_bit_char(c) => {
                    let decl = self.decl(line, &tok[1..], &tok)?;
                    match decl.kind {
                        Kind::Bits(1) | Kind::Event => {}
                        k => {
                            return bad(
                                line,
                                format!(
                                    "scalar value `{}` for `{}`, a {}; use `b<bits> {}`{}",
                                    show(&tok[..1]),
                                    decl.path,
                                    k.describe(),
                                    show(&tok[1..]),
                                    " (scalar values are for 1-bit variables)"
                                ),
                            );
                        }
                    }
                    self.summary.changes += 1;
                }
                b'b' | b'B' | b'r' | b'R' | b's' | b'S' => {
                    let Some(_) = self.token(&mut id, MAX_TOKEN_BYTES)? else {
                        return bad(
                            line,
                            format!("value `{}` has no identifier after it", show(&tok)),
                        );
                    };
                    self.value(line, &tok, &id)?;
                    self.summary.changes += 1;
                }
                b'$' => match tok.as_slice() {
                    b"$comment" => loop {
                        match self.token(&mut id, MAX_TOKEN_BYTES)? {
                            None => return bad(line, "`$comment` without `$end`"),
                            Some(_) if id.as_slice() == b"$end" => break,
                            Some(_) => {}
                        }
                    },
                    b"$dumpvars" | b"$dumpall" | b"$dumpon" | b"$dumpoff" | b"$end" => {}
                    other => {
                        return bad(
                            line,
                            format!(
                                "unknown command `{}` in the value section; valid are $dumpvars $dumpall $dumpon $dumpoff $end $comment",
                                show(other)
                            ),
                        );
                    }
                },
                _ => {
                    return bad(
                        line,
                        format!(
                            "unexpected `{}`: expected `#time`, a scalar change like `1!`, or `b`/`r`/`s` followed by a value and an identifier",
                            show(&tok)
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    fn decl(&self, line: u64, id: &[u8], tok: &[u8]) -> Result<&Decl, ValidateError> {
        if id.is_empty() {
            return bad(line, format!("value `{}` has no identifier", show(tok)));
        }
        match self.ids.get(id) {
            Some(d) => Ok(d),
            None => bad(
                line,
                format!(
                    "identifier `{}` in `{}` is not declared by any `$var`",
                    show(id),
                    show(tok)
                ),
            ),
        }
    }

    fn value(&self, line: u64, tok: &[u8], id: &[u8]) -> Result<(), ValidateError> {
        let decl = self.decl(line, id, tok)?;
        let v = &tok[1..];
        match (tok[0].to_ascii_lowercase(), decl.kind) {
            (b'b', Kind::Bits(w)) => {
                if let Some(c) = v.iter().find(|c| !is_bit_char(**c)) {
                    return bad(
                        line,
                        format!("bad bit character `{}` in `{}` for `{}`; bits are 0 1 x z (and h u w l -)", show(&[*c]), show(tok), decl.path),
                    );
                }
                let n = v.len();
                if n == 0 {
                    return bad(
                        line,
                        format!(
                            "vector value `{}` for `{}` has no bits",
                            show(tok),
                            decl.path
                        ),
                    );
                }
                if n > w as usize {
                    return bad(
                        line,
                        format!(
                            "value `{}` has {n} bits but `{}` is declared with {w}",
                            show(tok),
                            decl.path
                        ),
                    );
                }
                if n < w as usize
                    && w > 1
                    && !matches!(v[0], b'0' | b'1' | b'x' | b'X' | b'z' | b'Z')
                {
                    return bad(
                        line,
                        format!(
                            "value `{}` has {n} of {w} bits for `{}` and starts with `{}`; a shorter value must start with 0, 1, x or z",
                            show(tok),
                            decl.path,
                            show(&v[..1])
                        ),
                    );
                }
                Ok(())
            }
            (b'r', Kind::Real) => {
                let ok = std::str::from_utf8(v)
                    .ok()
                    .is_some_and(|s| s.parse::<f64>().is_ok());
                if !ok {
                    return bad(
                        line,
                        format!("real value `{}` for `{}` is not a number (e.g. r1.5, r-2e-3, rnan, rinf)", show(tok), decl.path),
                    );
                }
                Ok(())
            }
            (b's', Kind::Text) => {
                if std::str::from_utf8(v).is_err() {
                    return bad(
                        line,
                        format!("string value for `{}` is not valid UTF-8", decl.path),
                    );
                }
                Ok(())
            }
            (c, k) => {
                let given = match c {
                    b'b' => "vector",
                    b'r' => "real",
                    _ => "string",
                };
                bad(
                    line,
                    format!(
                        "{given} value `{}` for `{}`, which is declared as a {}",
                        show(tok),
                        decl.path,
                        k.describe()
                    ),
                )
            }
        }
    }
}
