//! The private PostgreSQL server of the shared-store tests: `scripts/test` starts it with
//! `scripts/pg-test-server` and exports its admin URL (no password) and password; each test
//! works in a database of its own. Passwords reach `proleg` only through `PGPASSWORD`.

use std::process::{Child, Command, Output, Stdio};

/// The test server.
pub struct Pg {
    /// Admin URL, without a password.
    pub url: String,
    /// The admin role's password.
    pub password: String,
}

/// The server `scripts/test` started; without it the test fails and says how to start one.
pub fn server() -> Pg {
    match (
        std::env::var("PROLEG_TEST_PG_URL"),
        std::env::var("PROLEG_TEST_PG_PASSWORD"),
    ) {
        (Ok(url), Ok(password)) => Pg { url, password },
        _ => panic!(
            "no test PostgreSQL server: run scripts/test (it starts one), or \
             `eval \"$(scripts/pg-test-server start /tmp/pgtest)\"` before cargo test"
        ),
    }
}

impl Pg {
    /// A connection as admin to database `db`.
    pub fn connect(&self, db: &str) -> postgres::Client {
        let mut config: postgres::Config = self.url_of(db).parse().expect("test URL");
        config.password(&self.password);
        config
            .connect(postgres::NoTls)
            .expect("the test server answers")
    }

    /// The library's view of database `db` as a store (created when empty), with the
    /// password in the URL (kept in this process; never printed).
    pub fn open_store(&self, db: &str) -> proleg::optimize::store::PgStore {
        use proleg::optimize::store::{PgStore, StoreLocation};
        let url = self
            .url_of(db)
            .replace("proleg_admin@", &format!("proleg_admin:{}@", self.password));
        let Ok(StoreLocation::Postgres(target)) = StoreLocation::parse(&url) else {
            panic!("a postgres URL");
        };
        match PgStore::open(&target, true) {
            Ok(s) => s,
            Err(e) => panic!("{e}"),
        }
    }

    /// The URL (no password) of database `db` on the server.
    pub fn url_of(&self, db: &str) -> String {
        let base = self
            .url
            .rsplit_once('/')
            .map(|(b, _)| b)
            .unwrap_or(&self.url);
        format!("{base}/{db}")
    }

    /// A new, empty database for one test (dropped first if an earlier run left it);
    /// returns its URL.
    pub fn database(&self, name: &str) -> String {
        let mut admin = self.connect("postgres");
        admin
            .batch_execute(&format!("DROP DATABASE IF EXISTS {name} WITH (FORCE)"))
            .expect("drop");
        admin
            .batch_execute(&format!("CREATE DATABASE {name}"))
            .expect("create");
        self.url_of(name)
    }

    /// `proleg ARGS` in the repository root with the admin password in `PGPASSWORD`.
    pub fn proleg(&self, args: &[&str]) -> Command {
        self.proleg_as(&self.password, args)
    }

    /// `proleg ARGS` with `password` in `PGPASSWORD`.
    pub fn proleg_as(&self, password: &str, args: &[&str]) -> Command {
        let mut c = Command::new(env!("CARGO_BIN_EXE_proleg"));
        c.args(args)
            .current_dir(super::root())
            .env("PGPASSWORD", password)
            .env_remove("PGPASSFILE");
        c
    }
}

impl Pg {
    /// Waits (up to a minute) until `query` on `db` returns true; fails if `child` ends first.
    pub fn wait_until(&self, db: &str, query: &str, child: &mut Child) {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
        let mut c = self.connect(db);
        loop {
            let holds = c
                .query_one(query, &[])
                .ok()
                .and_then(|r| r.try_get::<_, bool>(0).ok())
                .unwrap_or(false);
            if holds {
                return;
            }
            if let Ok(Some(status)) = child.try_wait() {
                panic!("the process ended ({status}) before: {query}");
            }
            assert!(
                std::time::Instant::now() < deadline,
                "timed out waiting for: {query}"
            );
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
    }
}

/// Runs a command to its end: its output.
pub fn output(mut c: Command) -> Output {
    c.output().expect("proleg runs")
}

/// Starts a command with its output captured.
pub fn spawn(mut c: Command) -> Child {
    c.stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("proleg starts")
}

/// Text of an output stream.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}
