//! Hosts of a test's own (`scripts/hosts`): network namespaces on a bridge, each with its
//! own address and share of the cores, removed when the test ends (and by the script's
//! watchdog if the test process dies). Needs root, as CI has; without it the test fails
//! with the script's message.

use std::path::PathBuf;
use std::process::{Command, Stdio};

use super::pg::Pg;

/// A set of hosts.
pub struct Hosts {
    /// The set's name.
    pub name: String,
    /// The /24's first three bytes (host I is `.I+1`, this machine `.254`).
    pub net: String,
    /// The PostgreSQL server's folder, when one runs on a host.
    pg_dir: Option<(usize, PathBuf)>,
}

fn script() -> PathBuf {
    super::root().join("scripts/hosts")
}

impl Hosts {
    /// Makes hosts 0..n of set `name`, each limited to `share` cores.
    pub fn up(name: &str, n: usize, share: f64) -> Hosts {
        let out = Command::new(script())
            .args(["up", name, &n.to_string(), &share.to_string()])
            .arg(std::process::id().to_string())
            .stderr(Stdio::piped())
            .output()
            .expect("scripts/hosts runs");
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        assert!(
            out.status.success(),
            "cannot make hosts: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let net = text
            .lines()
            .find_map(|l| l.strip_prefix("export PROLEG_HOSTS_NET="))
            .unwrap_or_else(|| panic!("no network in: {text}"))
            .to_string();
        Hosts {
            name: name.into(),
            net,
            pg_dir: None,
        }
    }

    /// Host `i`'s address.
    pub fn addr(&self, i: usize) -> String {
        format!("{}.{}", self.net, i + 1)
    }

    /// `program ARGS` on host `i`.
    pub fn command(&self, i: usize, program: &str, args: &[&str]) -> Command {
        let mut c = Command::new(script());
        c.args(["exec", &self.name, &i.to_string(), program])
            .args(args)
            .current_dir(super::root());
        c
    }

    /// `proleg ARGS` on host `i` with `pg`'s admin password in `PGPASSWORD`.
    pub fn proleg(&self, i: usize, pg: &Pg, args: &[&str]) -> Command {
        let mut c = self.command(i, env!("CARGO_BIN_EXE_proleg"), args);
        c.env("PGPASSWORD", &pg.password).env_remove("PGPASSFILE");
        c
    }

    /// Starts the test PostgreSQL server on host `i`.
    pub fn postgres(&mut self, i: usize) -> Pg {
        // Under /tmp: the server runs as the `postgres` user, who must reach the folder.
        let dir = std::env::temp_dir().join(format!("proleg-hosts-{}-pg", self.name));
        let _ = std::fs::remove_dir_all(&dir);
        let out = self
            .command(
                i,
                "scripts/pg-test-server",
                &["start", dir.to_str().unwrap()],
            )
            .env("PROLEG_PG_LISTEN", self.addr(i))
            .output()
            .expect("pg-test-server runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        self.pg_dir = Some((i, dir));
        let text = String::from_utf8_lossy(&out.stdout).into_owned();
        let var = |key: &str| {
            text.lines()
                .find_map(|l| l.strip_prefix(&format!("export {key}=")))
                .unwrap_or_else(|| panic!("no {key}"))
                .to_string()
        };
        Pg {
            url: var("PROLEG_TEST_PG_URL"),
            password: var("PROLEG_TEST_PG_PASSWORD"),
        }
    }

    /// Restarts the server at once (every connection cut), on its host.
    pub fn restart_postgres(&self) {
        let (i, dir) = self.pg_dir.as_ref().expect("a server");
        let ok = self
            .command(
                *i,
                "scripts/pg-test-server",
                &["restart", dir.to_str().unwrap()],
            )
            .status()
            .expect("pg-test-server runs")
            .success();
        assert!(ok, "the server restarts");
    }

    fn run(&self, args: &[&str]) {
        let ok = Command::new(script())
            .args(args)
            .status()
            .expect("scripts/hosts runs")
            .success();
        assert!(ok, "scripts/hosts {args:?}");
    }

    /// Cuts (`false`) or connects host `i`'s link.
    pub fn link(&self, i: usize, up: bool) {
        self.run(&[
            "link",
            &self.name,
            &i.to_string(),
            if up { "up" } else { "down" },
        ]);
    }

    /// Drops `percent` % of host `i`'s packets each way at random.
    pub fn loss(&self, i: usize, percent: f64) {
        self.run(&["loss", &self.name, &i.to_string(), &percent.to_string()]);
    }
}

impl Drop for Hosts {
    fn drop(&mut self) {
        let _ = Command::new(script()).args(["down", &self.name]).status();
        if let Some((_, dir)) = &self.pg_dir {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}
