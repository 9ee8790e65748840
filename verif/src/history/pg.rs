//! The history on a PostgreSQL server: a small synchronous client of the frontend/backend
//! protocol 3.0 (PostgreSQL's documentation, "Frontend/Backend Protocol"), the simple query
//! flow only, over TCP or a Unix socket. Authentication: trust, cleartext password, or
//! SCRAM-SHA-256 (RFC 7677, the servers' default since PostgreSQL 14).
//!
//! URL: `postgres://USER[:PASSWORD]@HOST[:PORT]/DB`; an empty HOST, or `?host=/dir`, is the Unix
//! socket in that folder (default `/var/run/postgresql`).

use super::db::{HistoryError, Sql};
use sha2::{Digest, Sha256};
use std::io::{Read, Write};

trait Stream: Read + Write {}
impl<T: Read + Write> Stream for T {}

pub struct Pg {
    s: Box<dyn Stream>,
    name: String,
}

/// The URL without its password, for messages.
pub fn redact(url: &str) -> String {
    match (url.find("://"), url.rfind('@')) {
        (Some(a), Some(b)) if b > a => {
            let cred = &url[a + 3..b];
            match cred.find(':') {
                Some(c) => format!("{}{}:***{}", &url[..a + 3], &cred[..c], &url[b..]),
                None => url.to_string(),
            }
        }
        _ => url.to_string(),
    }
}

struct Url {
    user: String,
    password: Option<String>,
    host: String,
    port: u16,
    db: String,
}

fn parse(url: &str) -> Result<Url, String> {
    let rest = url
        .strip_prefix("postgres://")
        .or_else(|| url.strip_prefix("postgresql://"))
        .ok_or("valid is postgres://USER[:PASSWORD]@HOST[:PORT]/DB")?;
    let (rest, query) = match rest.split_once('?') {
        Some((a, q)) => (a, Some(q)),
        None => (rest, None),
    };
    let (cred, hostpart) = match rest.rsplit_once('@') {
        Some((c, h)) => (c, h),
        None => ("", rest),
    };
    let (user, password) = match cred.split_once(':') {
        Some((u, p)) => (u.to_string(), Some(p.to_string())),
        None => (cred.to_string(), None),
    };
    let (hp, db) = hostpart.split_once('/').unwrap_or((hostpart, ""));
    let (mut host, port) = match hp.rsplit_once(':') {
        Some((h, p)) => (
            h.to_string(),
            p.parse::<u16>()
                .map_err(|_| format!("port `{p}`: valid is 1 to 65535"))?,
        ),
        None => (hp.to_string(), 5432),
    };
    for kv in query.unwrap_or("").split('&').filter(|s| !s.is_empty()) {
        if let Some(h) = kv.strip_prefix("host=") {
            host = h.to_string();
        }
    }
    let user = if user.is_empty() {
        std::env::var("USER").unwrap_or_else(|_| "postgres".into())
    } else {
        user
    };
    Ok(Url {
        db: if db.is_empty() {
            user.clone()
        } else {
            db.to_string()
        },
        user,
        password,
        host,
        port,
    })
}

fn msg(kind: u8, body: &[u8]) -> Vec<u8> {
    let mut m = vec![kind];
    m.extend_from_slice(&((body.len() + 4) as u32).to_be_bytes());
    m.extend_from_slice(body);
    m
}

fn hmac(key: &[u8], data: &[u8]) -> [u8; 32] {
    let mut k = [0u8; 64];
    if key.len() > 64 {
        k[..32].copy_from_slice(&Sha256::digest(key));
    } else {
        k[..key.len()].copy_from_slice(key);
    }
    let mut inner = Sha256::new();
    inner.update(k.map(|b| b ^ 0x36));
    inner.update(data);
    let mut outer = Sha256::new();
    outer.update(k.map(|b| b ^ 0x5c));
    outer.update(inner.finalize());
    outer.finalize().into()
}

fn pbkdf2(password: &[u8], salt: &[u8], iterations: u32) -> [u8; 32] {
    let mut s = salt.to_vec();
    s.extend_from_slice(&1u32.to_be_bytes());
    let mut u = hmac(password, &s);
    let mut out = u;
    for _ in 1..iterations {
        u = hmac(password, &u);
        for (o, x) in out.iter_mut().zip(u) {
            *o ^= x;
        }
    }
    out
}

const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

fn b64(data: &[u8]) -> String {
    let mut s = String::new();
    for c in data.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for i in 0..4 {
            if i <= c.len() {
                s.push(B64[(n >> (18 - 6 * i) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn unb64(s: &str) -> Option<Vec<u8>> {
    let mut out = Vec::new();
    let mut acc = 0u32;
    let mut bits = 0;
    for c in s.bytes().filter(|c| *c != b'=') {
        let v = B64.iter().position(|x| *x == c)? as u32;
        acc = (acc << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Some(out)
}

impl Pg {
    pub fn connect(url: &str) -> Result<Pg, HistoryError> {
        let name = redact(url);
        let e = |reason: String| HistoryError::Db {
            db: name.clone(),
            reason,
        };
        let u = parse(url).map_err(&e)?;
        let s: Box<dyn Stream> = if u.host.is_empty() || u.host.starts_with('/') {
            let dir = if u.host.is_empty() {
                "/var/run/postgresql"
            } else {
                &u.host
            };
            let p = format!("{dir}/.s.PGSQL.{}", u.port);
            Box::new(
                std::os::unix::net::UnixStream::connect(&p)
                    .map_err(|x| e(format!("cannot connect to {p}: {x}")))?,
            )
        } else {
            Box::new(
                std::net::TcpStream::connect((u.host.as_str(), u.port))
                    .map_err(|x| e(format!("cannot connect to {}:{}: {x}", u.host, u.port)))?,
            )
        };
        let mut pg = Pg { s, name };
        let mut body = 196_608u32.to_be_bytes().to_vec();
        for (k, v) in [("user", &u.user), ("database", &u.db)] {
            body.extend_from_slice(k.as_bytes());
            body.push(0);
            body.extend_from_slice(v.as_bytes());
            body.push(0);
        }
        body.push(0);
        let mut m = ((body.len() + 4) as u32).to_be_bytes().to_vec();
        m.extend_from_slice(&body);
        pg.send(&m)?;
        pg.authenticate(&u)?;
        // parameter status, key data, up to ReadyForQuery
        loop {
            let (k, b) = pg.read()?;
            match k {
                b'Z' => break,
                b'E' => return Err(pg.error(&b)),
                _ => {}
            }
        }
        Ok(pg)
    }

    fn err(&self, reason: impl Into<String>) -> HistoryError {
        HistoryError::Db {
            db: self.name.clone(),
            reason: reason.into(),
        }
    }

    fn send(&mut self, b: &[u8]) -> Result<(), HistoryError> {
        self.s
            .write_all(b)
            .and_then(|_| self.s.flush())
            .map_err(|e| self.err(format!("write: {e}")))
    }

    fn read(&mut self) -> Result<(u8, Vec<u8>), HistoryError> {
        let mut h = [0u8; 5];
        self.s
            .read_exact(&mut h)
            .map_err(|e| self.err(format!("read: {e}")))?;
        let n = u32::from_be_bytes([h[1], h[2], h[3], h[4]]) as usize;
        if !(4..=1 << 30).contains(&n) {
            return Err(self.err(format!("a message of {n} bytes: not PostgreSQL's protocol")));
        }
        let mut b = vec![0u8; n - 4];
        self.s
            .read_exact(&mut b)
            .map_err(|e| self.err(format!("read: {e}")))?;
        Ok((h[0], b))
    }

    /// An ErrorResponse as text: its severity, code and message.
    fn error(&self, b: &[u8]) -> HistoryError {
        let mut parts = Vec::new();
        for f in b.split(|c| *c == 0).filter(|f| !f.is_empty()) {
            if matches!(f[0], b'S' | b'C' | b'M') {
                parts.push(String::from_utf8_lossy(&f[1..]).into_owned());
            }
        }
        self.err(parts.join(" "))
    }

    fn authenticate(&mut self, u: &Url) -> Result<(), HistoryError> {
        loop {
            let (k, b) = self.read()?;
            if k == b'E' {
                return Err(self.error(&b));
            }
            if k != b'R' || b.len() < 4 {
                return Err(self.err(format!("unexpected message `{}` at login", k as char)));
            }
            let code = u32::from_be_bytes([b[0], b[1], b[2], b[3]]);
            match code {
                0 => return Ok(()),
                3 => {
                    let Some(p) = &u.password else {
                        return Err(self.err("the server asks for a password: give it in the URL"));
                    };
                    let mut body = p.as_bytes().to_vec();
                    body.push(0);
                    self.send(&msg(b'p', &body))?;
                }
                10 => {
                    let mechs = String::from_utf8_lossy(&b[4..]).into_owned();
                    if !mechs.split('\0').any(|m| m == "SCRAM-SHA-256") {
                        return Err(self.err(format!("SASL mechanisms {mechs:?}: only SCRAM-SHA-256 is spoken")));
                    }
                    let Some(p) = u.password.clone() else {
                        return Err(self.err("the server asks for a password: give it in the URL"));
                    };
                    return self.scram(&p);
                }
                other => {
                    return Err(self.err(format!(
                        "authentication method {other}: valid are trust, password and scram-sha-256 (pg_hba.conf)"
                    )))
                }
            }
        }
    }

    fn scram(&mut self, password: &str) -> Result<(), HistoryError> {
        let seed = format!(
            "{:?}/{}/{:?}",
            std::time::SystemTime::now(),
            std::process::id(),
            std::thread::current().id()
        );
        let nonce = b64(&Sha256::digest(seed.as_bytes())[..18]);
        let bare = format!("n=,r={nonce}");
        let first = format!("n,,{bare}");
        let mut body = b"SCRAM-SHA-256\0".to_vec();
        body.extend_from_slice(&(first.len() as u32).to_be_bytes());
        body.extend_from_slice(first.as_bytes());
        self.send(&msg(b'p', &body))?;
        let (k, b) = self.read()?;
        if k == b'E' {
            return Err(self.error(&b));
        }
        if k != b'R' || b.len() < 4 || b[..4] != 11u32.to_be_bytes() {
            return Err(self.err("SCRAM: no server-first message"));
        }
        let server_first = String::from_utf8_lossy(&b[4..]).into_owned();
        let field = |k: &str| {
            server_first
                .split(',')
                .find_map(|p| p.strip_prefix(k))
                .map(str::to_string)
        };
        let (Some(r), Some(salt), Some(i)) = (field("r="), field("s="), field("i=")) else {
            return Err(self.err(format!("SCRAM: server-first `{server_first}`")));
        };
        if !r.starts_with(&nonce) {
            return Err(self.err("SCRAM: the server's nonce does not extend ours"));
        }
        let salt = unb64(&salt).ok_or_else(|| self.err("SCRAM: salt is not base64"))?;
        let iterations: u32 = i.parse().map_err(|_| self.err("SCRAM: iteration count"))?;
        let salted = pbkdf2(password.as_bytes(), &salt, iterations);
        let client_key = hmac(&salted, b"Client Key");
        let stored: [u8; 32] = Sha256::digest(client_key).into();
        let without_proof = format!("c=biws,r={r}");
        let auth = format!("{bare},{server_first},{without_proof}");
        let sig = hmac(&stored, auth.as_bytes());
        let proof: Vec<u8> = client_key.iter().zip(sig).map(|(a, b)| a ^ b).collect();
        let fin = format!("{without_proof},p={}", b64(&proof));
        self.send(&msg(b'p', fin.as_bytes()))?;
        let (k, b) = self.read()?;
        if k == b'E' {
            return Err(self.error(&b));
        }
        if k != b'R' || b.len() < 4 || b[..4] != 12u32.to_be_bytes() {
            return Err(self.err("SCRAM: no server-final message"));
        }
        let server_key = hmac(&salted, b"Server Key");
        let want = b64(&hmac(&server_key, auth.as_bytes()));
        let got = String::from_utf8_lossy(&b[4..]).into_owned();
        if got.strip_prefix("v=") != Some(want.as_str()) {
            return Err(self.err("SCRAM: the server's signature is wrong"));
        }
        let (k, b) = self.read()?;
        if k == b'E' {
            return Err(self.error(&b));
        }
        if k != b'R' || b.len() < 4 || b[..4] != 0u32.to_be_bytes() {
            return Err(self.err("SCRAM: not accepted"));
        }
        Ok(())
    }

    /// One simple query (several statements run as one transaction): its data rows, or the
    /// server's error.
    fn simple(&mut self, sql: &str) -> Result<Vec<Vec<Option<String>>>, HistoryError> {
        let mut body = sql.replace('\0', "").into_bytes();
        body.push(0);
        self.send(&msg(b'Q', &body))?;
        let mut rows = Vec::new();
        let mut failed = None;
        loop {
            let (k, b) = self.read()?;
            match k {
                b'D' => {
                    let n = u16::from_be_bytes([b[0], b[1]]) as usize;
                    let mut at = 2;
                    let mut row = Vec::with_capacity(n);
                    for _ in 0..n {
                        let len = i32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]]);
                        at += 4;
                        if len < 0 {
                            row.push(None);
                        } else {
                            let l = len as usize;
                            row.push(Some(String::from_utf8_lossy(&b[at..at + l]).into_owned()));
                            at += l;
                        }
                    }
                    rows.push(row);
                }
                b'E' => failed = Some(self.error(&b)),
                b'Z' => break,
                _ => {}
            }
        }
        match failed {
            Some(e) => Err(e),
            None => Ok(rows),
        }
    }
}

impl Sql for Pg {
    fn transaction(&mut self, statements: &[String]) -> Result<(), HistoryError> {
        // a simple query of several statements is one implicit transaction; said explicitly
        let text = format!("BEGIN;\n{};\nCOMMIT;", statements.join(";\n"));
        self.simple(&text).map(|_| ())
    }

    fn query(&mut self, sql: &str) -> Result<Vec<Vec<Option<String>>>, HistoryError> {
        self.simple(sql)
    }

    fn schema_lock(&self) -> Option<String> {
        // an application lock of this transaction, keyed by "PMU5" in ASCII
        Some("SELECT pg_advisory_xact_lock(1347245365)".into())
    }
}

impl Drop for Pg {
    fn drop(&mut self) {
        let _ = self.s.write_all(&msg(b'X', &[]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_and_hmac_of_known_vectors() {
        assert_eq!(b64(b"foobar"), "Zm9vYmFy");
        assert_eq!(b64(b"fo"), "Zm8=");
        assert_eq!(unb64("Zm9vYmE=").unwrap(), b"fooba");
        // RFC 4231 test case 2
        let h = hmac(b"Jefe", b"what do ya want for nothing?");
        let hex: String = h.iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(
            hex,
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843"
        );
    }

    #[test]
    fn a_url_names_user_host_port_and_database() {
        let u = parse("postgres://ci:s3cret@db.example:6543/pmu").unwrap();
        assert_eq!(
            (
                u.user.as_str(),
                u.password.as_deref(),
                u.host.as_str(),
                u.port,
                u.db.as_str()
            ),
            ("ci", Some("s3cret"), "db.example", 6543, "pmu")
        );
        let u = parse("postgresql://ci@/pmu?host=/tmp/pg").unwrap();
        assert_eq!((u.host.as_str(), u.port), ("/tmp/pg", 5432));
        assert!(parse("postgres://x@h:99999/d").is_err());
        assert_eq!(redact("postgres://ci:s3cret@h/d"), "postgres://ci:***@h/d");
    }
}
