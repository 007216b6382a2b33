//! The experiment store's tables, described once: both stores make them from this
//! description in their own SQL dialect ([`create_tables`]), so a column added here is in
//! both. The steps that bring an older store up to date stay with each store.

/// Whose SQL.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dialect {
    /// SQLite (`rusqlite`).
    Sqlite,
    /// PostgreSQL.
    Postgres,
}

/// What a column holds; each dialect spells it its own way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Type {
    /// A run's id, made by the database.
    Key,
    /// A reference to a run.
    Run,
    /// A small whole number.
    Int,
    /// A whole number that may pass 2^31 (seeds, evaluation numbers).
    Big,
    /// A floating-point number.
    Real,
    /// Text.
    Text,
    /// When a run started (UTC text, the database's clock).
    Started,
    /// Until when a worker's claim holds.
    Lease,
    /// An evaluation's state: pending, running or done.
    State,
}

impl Type {
    fn sql(self, d: Dialect) -> &'static str {
        use Dialect::{Postgres as P, Sqlite as S};
        match (self, d) {
            (Type::Key, S) => "INTEGER PRIMARY KEY",
            (Type::Key, P) => "BIGSERIAL PRIMARY KEY",
            (Type::Run, S) => "INTEGER NOT NULL REFERENCES runs(id)",
            (Type::Run, P) => "BIGINT NOT NULL REFERENCES runs(id)",
            (Type::Int, _) => "INTEGER",
            (Type::Big, S) => "INTEGER",
            (Type::Big, P) => "BIGINT",
            (Type::Real, S) => "REAL",
            (Type::Real, P) => "DOUBLE PRECISION",
            (Type::Text, _) => "TEXT",
            (Type::Started, S) => "TEXT NOT NULL DEFAULT (datetime('now'))",
            (Type::Started, P) => {
                "TEXT NOT NULL DEFAULT to_char(now() AT TIME ZONE 'UTC', 'YYYY-MM-DD HH24:MI:SS')"
            }
            (Type::Lease, S) => "REAL",
            (Type::Lease, P) => "TIMESTAMPTZ",
            (Type::State, S) => "TEXT NOT NULL DEFAULT 'done'",
            (Type::State, P) => {
                "TEXT NOT NULL DEFAULT 'done' CHECK (state IN ('pending', 'running', 'done'))"
            }
        }
    }
}

/// A column: its name, type and what else it says (`NOT NULL`, a default).
struct Column(&'static str, Type, &'static str);

/// A table: its name, columns and primary key (when not a [`Type::Key`] column).
struct Table(&'static str, &'static [Column], Option<&'static str>);

const NOT_NULL: &str = "NOT NULL";

/// Every table of a store.
const TABLES: &[Table] = &[
    Table(
        "proleg_meta",
        &[Column("schema_version", Type::Int, NOT_NULL)],
        None,
    ),
    Table(
        "runs",
        &[
            Column("id", Type::Key, ""),
            Column("config", Type::Text, NOT_NULL),
            Column("algorithm", Type::Text, NOT_NULL),
            Column("seed", Type::Big, NOT_NULL),
            Column("fitness", Type::Text, NOT_NULL),
            Column("duration", Type::Real, NOT_NULL),
            Column("genes", Type::Text, NOT_NULL),
            Column("started", Type::Started, ""),
            Column("finished", Type::Int, "NOT NULL DEFAULT 0"),
            Column("program", Type::Text, "NOT NULL DEFAULT ''"),
        ],
        None,
    ),
    Table(
        "run_files",
        &[
            Column("run", Type::Run, ""),
            Column("path", Type::Text, NOT_NULL),
            Column("content", Type::Text, NOT_NULL),
        ],
        Some("run, path"),
    ),
    Table(
        "run_episodes",
        &[
            Column("run", Type::Run, ""),
            Column("episode", Type::Int, NOT_NULL),
            Column("seed", Type::Big, NOT_NULL),
            Column("draws", Type::Text, NOT_NULL),
        ],
        Some("run, episode"),
    ),
    Table(
        "evaluations",
        &[
            Column("run", Type::Run, ""),
            Column("number", Type::Big, NOT_NULL),
            Column("round", Type::Big, NOT_NULL),
            Column("genome", Type::Text, NOT_NULL),
            Column("vals", Type::Text, NOT_NULL),
            Column("score", Type::Real, ""),
            Column("engine_scores", Type::Text, "NOT NULL DEFAULT ''"),
            Column("rejected", Type::Text, ""),
            Column("measures", Type::Text, "NOT NULL DEFAULT ''"),
            Column("seed", Type::Big, NOT_NULL),
            Column("wall", Type::Real, "NOT NULL DEFAULT 0"),
            Column("state", Type::State, ""),
            Column("worker", Type::Text, ""),
            Column("attempt", Type::Int, "NOT NULL DEFAULT 0"),
            Column("lease_until", Type::Lease, ""),
        ],
        Some("run, number"),
    ),
];

/// The statements that make every table in dialect `d` (SQLite's only where a table is
/// missing, so an older store gains the tables it lacks); PostgreSQL also indexes the
/// queue's open evaluations.
pub fn create_tables(d: Dialect) -> String {
    let create = match d {
        Dialect::Sqlite => "CREATE TABLE IF NOT EXISTS",
        Dialect::Postgres => "CREATE TABLE",
    };
    let mut sql = String::new();
    for Table(name, columns, key) in TABLES {
        let mut parts: Vec<String> = columns
            .iter()
            .map(|Column(c, ty, rest)| format!("{c} {} {rest}", ty.sql(d)).trim_end().to_string())
            .collect();
        if let Some(k) = key {
            parts.push(format!("PRIMARY KEY ({k})"));
        }
        sql.push_str(&format!(
            "{create} {name} (\n    {});\n",
            parts.join(",\n    ")
        ));
    }
    if d == Dialect::Postgres {
        sql.push_str(
            "CREATE INDEX evaluations_open ON evaluations (run, number) WHERE state <> 'done';\n",
        );
    }
    sql
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sqlite_makes_every_table_and_they_hold_a_run_and_an_evaluation() {
        let conn = rusqlite::Connection::open_in_memory().unwrap();
        conn.execute_batch(&create_tables(Dialect::Sqlite)).unwrap();
        // Made again over an existing store: nothing happens (older stores gain what they lack).
        conn.execute_batch(&create_tables(Dialect::Sqlite)).unwrap();
        conn.execute_batch(
            "INSERT INTO runs (config, algorithm, seed, fitness, duration, genes)
                 VALUES ('a.simulation.xml', 'CMA-ES', 1, 'distance', 2.0, 'g');
             INSERT INTO evaluations (run, number, round, genome, vals, score, seed)
                 VALUES (1, 0, 0, '4', '40', 0.5, 1);",
        )
        .unwrap();
        let (state, wall, started): (String, f64, String) = conn
            .query_row(
                "SELECT e.state, e.wall, r.started FROM evaluations e JOIN runs r ON r.id = e.run",
                [],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )
            .unwrap();
        assert_eq!((state.as_str(), wall), ("done", 0.0));
        assert!(started.len() >= 19, "started {started:?}");
        for Table(name, columns, _) in TABLES {
            let n: i64 = conn
                .query_row(
                    &format!("SELECT COUNT(*) FROM pragma_table_info('{name}')"),
                    [],
                    |r| r.get(0),
                )
                .unwrap();
            assert_eq!(n as usize, columns.len(), "{name}");
        }
    }
}
