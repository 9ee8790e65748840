//! The history in an SQLite file (rusqlite, SQLite compiled in): a writer waits for another's
//! transaction (`BEGIN IMMEDIATE`, a busy timeout) instead of failing.

use super::db::{HistoryError, Sql};
use std::path::Path;
use std::time::Duration;

pub struct Sqlite {
    conn: rusqlite::Connection,
    name: String,
}

impl Sqlite {
    pub fn open(path: &Path) -> Result<Sqlite, HistoryError> {
        let name = path.display().to_string();
        let err = |e: rusqlite::Error| HistoryError::Db {
            db: name.clone(),
            reason: e.to_string(),
        };
        if let Some(p) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(p).map_err(|e| HistoryError::Db {
                db: name.clone(),
                reason: e.to_string(),
            })?;
        }
        let conn = rusqlite::Connection::open(path).map_err(err)?;
        conn.busy_timeout(Duration::from_secs(120)).map_err(err)?;
        Ok(Sqlite { conn, name })
    }

    fn err(&self, e: rusqlite::Error) -> HistoryError {
        HistoryError::Db {
            db: self.name.clone(),
            reason: e.to_string(),
        }
    }
}

impl Sql for Sqlite {
    fn transaction(&mut self, statements: &[String]) -> Result<(), HistoryError> {
        let tx = self
            .conn
            .transaction_with_behavior(rusqlite::TransactionBehavior::Immediate)
            .map_err(|e| HistoryError::Db {
                db: self.name.clone(),
                reason: e.to_string(),
            })?;
        for s in statements {
            tx.execute_batch(s).map_err(|e| HistoryError::Db {
                db: self.name.clone(),
                reason: format!("{e} (in `{}`)", s.chars().take(120).collect::<String>()),
            })?;
        }
        tx.commit().map_err(|e| self.err(e))
    }

    fn query(&mut self, sql: &str) -> Result<Vec<Vec<Option<String>>>, HistoryError> {
        let mut st = self.conn.prepare(sql).map_err(|e| HistoryError::Db {
            db: self.name.clone(),
            reason: e.to_string(),
        })?;
        let n = st.column_count();
        let rows = st
            .query_map([], |row| {
                (0..n)
                    .map(|i| {
                        use rusqlite::types::ValueRef;
                        Ok(match row.get_ref(i)? {
                            ValueRef::Null => None,
                            ValueRef::Integer(x) => Some(x.to_string()),
                            ValueRef::Real(x) => Some(x.to_string()),
                            ValueRef::Text(t) | ValueRef::Blob(t) => {
                                Some(String::from_utf8_lossy(t).into_owned())
                            }
                        })
                    })
                    .collect::<Result<Vec<_>, rusqlite::Error>>()
            })
            .map_err(|e| HistoryError::Db {
                db: self.name.clone(),
                reason: e.to_string(),
            })?;
        rows.collect::<Result<Vec<_>, _>>()
            .map_err(|e| HistoryError::Db {
                db: self.name.clone(),
                reason: e.to_string(),
            })
    }
}
