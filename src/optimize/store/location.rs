//! Where an experiment store lives, from what `--store` says: a file path (the embedded
//! SQLite store) or a `postgres://` / `postgresql://` URL (a store shared by many hosts).
//!
//! A URL's password is taken from the URL, else `PGPASSWORD`, else the password file
//! (`PGPASSFILE`, default `~/.pgpass`, libpq's format), and is never shown: the location
//! prints as `postgres://user@host:port/db`, and every error names that form.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;
use std::time::Duration;

use postgres::config::{Host, SslMode};

use crate::optimize::error::BadChoice;

/// Seconds to wait for a server that does not answer, unless the URL sets `connect_timeout`.
const CONNECT_TIMEOUT_S: u64 = 10;

/// Seconds a sent request may go unacknowledged before the connection counts as lost (a
/// cut link), unless the URL sets `tcp_user_timeout`; then the worker or driver connects
/// again instead of waiting on a dead socket for the kernel's ~15 minutes.
const TCP_USER_TIMEOUT_S: u64 = 20;

/// Keepalive probes of an idle connection (idle seconds, seconds between probes, probes),
/// unless the URL sets `keepalives_idle`: a link cut while nothing is sent is found in
/// ~25 s.
const KEEPALIVES: (u64, u64, u32) = (10, 5, 3);

/// An experiment store's location.
#[derive(Debug, Clone)]
pub enum StoreLocation {
    /// An embedded SQLite database file.
    Sqlite(PathBuf),
    /// A PostgreSQL database.
    Postgres(Box<PgTarget>),
}

/// A PostgreSQL server, database and role; the password is inside `config` and never shown.
#[derive(Clone)]
pub struct PgTarget {
    /// The connection settings (with the password, when one was found).
    pub config: postgres::Config,
}

impl fmt::Debug for PgTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PgTarget({self})")
    }
}

impl StoreLocation {
    /// Reads what `--store` says. A text with `://` is a URL and must be a PostgreSQL one.
    pub fn parse(text: &str) -> Result<StoreLocation, BadChoice> {
        let Some((scheme, _)) = text.split_once("://") else {
            return Ok(StoreLocation::Sqlite(PathBuf::from(text)));
        };
        if scheme != "postgres" && scheme != "postgresql" {
            return Err(BadChoice::Store(format!(
                "unknown URL scheme \"{scheme}://\": give a file path (SQLite) or a postgres:// URL"
            )));
        }
        let mut config = postgres::Config::from_str(text).map_err(|e| {
            BadChoice::Store(format!("not a valid PostgreSQL URL ({e}); expected postgres://USER@HOST[:PORT]/DATABASE[?sslmode=require]"))
        })?;
        if config.get_dbname().is_none() {
            return Err(BadChoice::Store(
                "the PostgreSQL URL names no database (postgres://USER@HOST/DATABASE)".into(),
            ));
        }
        if config.get_user().is_none() {
            config.user(std::env::var("USER").as_deref().unwrap_or("postgres"));
        }
        if config.get_connect_timeout().is_none() {
            config.connect_timeout(Duration::from_secs(CONNECT_TIMEOUT_S));
        }
        if config.get_tcp_user_timeout().is_none() {
            config.tcp_user_timeout(Duration::from_secs(TCP_USER_TIMEOUT_S));
        }
        if !text.contains("keepalives_idle") {
            let (idle, interval, retries) = KEEPALIVES;
            config
                .keepalives(true)
                .keepalives_idle(Duration::from_secs(idle))
                .keepalives_interval(Duration::from_secs(interval))
                .keepalives_retries(retries);
        }
        config.application_name("proleg");
        let mut target = PgTarget { config };
        target.find_password();
        Ok(StoreLocation::Postgres(Box::new(target)))
    }

    /// A SQLite store at `path`.
    pub fn sqlite(path: impl AsRef<Path>) -> StoreLocation {
        StoreLocation::Sqlite(path.as_ref().to_path_buf())
    }
}

impl fmt::Display for StoreLocation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StoreLocation::Sqlite(p) => write!(f, "{}", p.display()),
            StoreLocation::Postgres(t) => write!(f, "{t}"),
        }
    }
}

impl fmt::Display for PgTarget {
    /// `postgres://user@host:port/db[?sslmode=...]`, never the password.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let c = &self.config;
        let host = self.host();
        let port = c.get_ports().first().copied().unwrap_or(5432);
        write!(
            f,
            "postgres://{}@{}:{port}/{}",
            c.get_user().unwrap_or(""),
            host,
            c.get_dbname().unwrap_or("")
        )?;
        match c.get_ssl_mode() {
            SslMode::Require => write!(f, "?sslmode=require"),
            SslMode::Disable => write!(f, "?sslmode=disable"),
            _ => Ok(()),
        }
    }
}

impl PgTarget {
    /// The first host as text (a socket folder for Unix sockets).
    fn host(&self) -> String {
        match self.config.get_hosts().first() {
            Some(Host::Tcp(h)) => h.clone(),
            Some(Host::Unix(p)) => p.display().to_string(),
            None => "localhost".into(),
        }
    }

    /// Fills in the password from `PGPASSWORD` or the password file when the URL has none.
    fn find_password(&mut self) {
        if self.config.get_password().is_some() {
            return;
        }
        if let Ok(p) = std::env::var("PGPASSWORD")
            && !p.is_empty()
        {
            self.config.password(p);
            return;
        }
        let file = std::env::var_os("PGPASSFILE")
            .map(PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| Path::new(&h).join(".pgpass")));
        let Some(text) = file.and_then(|f| std::fs::read_to_string(f).ok()) else {
            return;
        };
        // libpq names a Unix-socket connection "localhost" in the password file.
        let host = match self.config.get_hosts().first() {
            Some(Host::Unix(_)) | None => "localhost".to_string(),
            Some(Host::Tcp(h)) => h.clone(),
        };
        let port = self
            .config
            .get_ports()
            .first()
            .copied()
            .unwrap_or(5432)
            .to_string();
        let want = [
            host.as_str(),
            port.as_str(),
            self.config.get_dbname().unwrap_or(""),
            self.config.get_user().unwrap_or(""),
        ];
        if let Some(p) = pgpass_lookup(&text, want) {
            self.config.password(p);
        }
    }
}

/// The password of the first line of a libpq password file whose host, port, database and
/// user match `want` (`*` matches anything; `\:` and `\\` are escapes).
pub fn pgpass_lookup(text: &str, want: [&str; 4]) -> Option<String> {
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .find_map(|line| {
            let fields = split_pgpass_line(line);
            if fields.len() != 5 {
                return None;
            }
            let matches = fields[..4]
                .iter()
                .zip(want)
                .all(|(f, w)| f == "*" || f == w);
            matches.then(|| fields[4].clone())
        })
}

/// The colon-separated fields of a password-file line, escapes undone.
fn split_pgpass_line(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\\' => {
                if let (Some(next), Some(last)) = (chars.next(), fields.last_mut()) {
                    last.push(next);
                }
            }
            ':' if fields.len() < 5 => fields.push(String::new()),
            c => {
                if let Some(last) = fields.last_mut() {
                    last.push(c);
                }
            }
        }
    }
    fields
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_is_sqlite_and_a_postgres_url_a_shared_store() {
        assert!(matches!(
            StoreLocation::parse("runs/a.sqlite"),
            Ok(StoreLocation::Sqlite(_))
        ));
        let Ok(StoreLocation::Postgres(t)) =
            StoreLocation::parse("postgres://lab:s3cret@db.example:5433/proleg?sslmode=require")
        else {
            panic!("a postgres URL");
        };
        assert_eq!(t.config.get_password(), Some(&b"s3cret"[..]));
        let shown = t.to_string();
        assert_eq!(
            shown,
            "postgres://lab@db.example:5433/proleg?sslmode=require"
        );
        assert!(!format!("{t:?}").contains("s3cret"));
    }

    #[test]
    fn typos_in_urls_are_named() {
        let why = |url| match StoreLocation::parse(url) {
            Err(BadChoice::Store(why)) => why,
            other => panic!("{url}: not a bad store: {other:?}"),
        };
        let scheme = why("postgress://lab@db/proleg");
        assert!(
            scheme.contains("unknown URL scheme \"postgress://\""),
            "{scheme}"
        );
        let port = why("postgres://lab@db:54x2/proleg");
        assert!(port.contains("not a valid PostgreSQL URL"), "{port}");
        let db = why("postgres://lab@db:5432");
        assert!(db.contains("names no database"), "{db}");
    }

    #[test]
    fn the_password_file_matches_wildcards_and_escapes() {
        let text = "# comment\nother:5432:proleg:lab:no\n*:5433:proleg:lab:pa\\:ss\n";
        assert_eq!(
            pgpass_lookup(text, ["db", "5433", "proleg", "lab"]).as_deref(),
            Some("pa:ss")
        );
        assert_eq!(pgpass_lookup(text, ["db", "5434", "proleg", "lab"]), None);
    }
}
