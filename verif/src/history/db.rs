//! The history's database as the rest of the module sees it: SQL text in, rows of text out.

/// Why the history cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum HistoryError {
    #[error("history {db}: {reason}")]
    Db { db: String, reason: String },
}

/// A database that runs SQL text: statements in one transaction, queries returning text.
pub trait Sql {
    /// Run `statements` in one transaction: all or none.
    fn transaction(&mut self, statements: &[String]) -> Result<(), HistoryError>;
    /// The rows of a query, every value as text (`None`: SQL NULL).
    fn query(&mut self, sql: &str) -> Result<Vec<Vec<Option<String>>>, HistoryError>;
    /// A statement that serialises the creation of the tables between writers, run first in
    /// its transaction, where the database needs one (PostgreSQL: two `CREATE TABLE IF NOT
    /// EXISTS` at once can collide; SQLite's write transactions are serial already).
    fn schema_lock(&self) -> Option<String> {
        None
    }
}
