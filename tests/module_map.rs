//! One module map: each folder's `//!` header (`lib.rs` for `src/`, `mod.rs` for the
//! others) is the one description of its files, so every `pub mod` a folder declares must
//! be named there (in backticks, as a link or a path). A module added without a line in
//! its folder's header fails here, naming both.

use std::path::{Path, PathBuf};

/// The `pub mod`s `text` declares that its `//!` header does not name.
fn missing_from_header(text: &str) -> Vec<String> {
    let header: String = text
        .lines()
        .take_while(|l| l.starts_with("//!"))
        .map(|l| format!("{}\n", &l[3..]))
        .collect();
    let named = |m: &str| {
        header.match_indices('`').any(|(at, _)| {
            let rest = &header[at + 1..];
            let word: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || "_:./".contains(*c))
                .collect();
            let last = word
                .trim_end_matches(['/', '.'])
                .trim_end_matches(".rs")
                .rsplit("::")
                .find(|s| !s.is_empty() && s.chars().all(|c| c.is_alphanumeric() || c == '_'))
                .unwrap_or("");
            // `name`, `name.rs`, `name/`, `crate::a::name`, and `a::name::Item` too.
            last == m || word.split("::").any(|s| s == m)
        })
    };
    text.lines()
        .filter_map(|l| {
            let l = l.trim();
            let name = l.strip_prefix("pub mod ")?.strip_suffix(';')?;
            (!named(name)).then(|| name.to_string())
        })
        .collect()
}

fn folder_headers(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        if p.is_dir() {
            folder_headers(&p, out);
        } else if p
            .file_name()
            .is_some_and(|n| n == "mod.rs" || n == "lib.rs")
        {
            out.push(p);
        }
    }
}

#[test]
fn every_pub_mod_is_named_in_its_folders_header() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    folder_headers(&src, &mut files);
    files.sort();
    assert!(
        files.len() > 30,
        "found only {} folder headers",
        files.len()
    );
    let mut wrong = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for m in missing_from_header(&text) {
            wrong.push(format!(
                "{}: `pub mod {m};` is not named in the //! header",
                f.strip_prefix(&src).unwrap().display()
            ));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn a_module_missing_from_its_header_is_found() {
    let text = "//! The folder:\n//! - [`a`]: one\n//! - `b.rs`: two\n\npub mod a;\npub mod b;\npub mod c;\n";
    assert_eq!(missing_from_header(text), ["c"]);
    let linked = "//! See [`crate::x::c`].\npub mod c;\n";
    assert!(missing_from_header(linked).is_empty());
}

/// Lines of `text` that point at a tracker number ("issue 32", "issues 20").
fn tracker_numbers(text: &str) -> Vec<String> {
    text.lines()
        .filter(|l| {
            let lower = l.to_lowercase();
            lower.match_indices("issue").any(|(at, _)| {
                let rest = lower[at + 5..].trim_start_matches('s').trim_start();
                let rest = rest.strip_prefix('#').unwrap_or(rest);
                rest.starts_with(|c: char| c.is_ascii_digit())
            })
        })
        .map(|l| l.trim().to_string())
        .collect()
}

fn files_under(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        let name = p
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        if p.is_dir() {
            if !["target", "__pycache__", ".venv"].contains(&name.as_str()) {
                files_under(&p, out);
            }
        } else if ["rs", "py", "xml", "toml", "js", "html"]
            .iter()
            .any(|e| name.ends_with(&format!(".{e}")))
        {
            out.push(p);
        }
    }
}

#[test]
fn no_tracker_number_in_the_code() {
    // Code, tests, the Python package and the shipped configurations (whose descriptions
    // `proleg check` prints) say why in words, not by a tracker number.
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in [
        "src", "python", "tests", "configs", "benches", "examples", "assets",
    ] {
        files_under(&root.join(dir), &mut files);
    }
    let mut found = Vec::new();
    // This file's own examples are the one exception.
    for f in files.iter().filter(|f| !f.ends_with("tests/module_map.rs")) {
        let Ok(text) = std::fs::read_to_string(f) else {
            continue;
        };
        for line in tracker_numbers(&text) {
            found.push(format!(
                "{}: {line}",
                f.strip_prefix(root).unwrap().display()
            ));
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}

#[test]
fn a_tracker_number_is_found() {
    assert_eq!(
        tracker_numbers("a\n// (issue 32 part 1)\nb"),
        ["// (issue 32 part 1)"]
    );
    assert_eq!(tracker_numbers("Issues #20 and 21"), ["Issues #20 and 21"]);
    assert!(tracker_numbers("an issue with the 3 files").is_empty());
}
