//! Every relative link in the README and docs/ resolves: the file it names exists, and a
//! `#anchor` into a Markdown file names one of its headings (GitHub's slugs).

use std::path::{Path, PathBuf};

fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        if p.is_dir() {
            markdown_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "md") {
            out.push(p);
        }
    }
}

/// GitHub's anchor of a heading: lower case, spaces to dashes, punctuation dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// The targets of the `[text](target)` links of `text`.
fn links(text: &str) -> Vec<String> {
    text.match_indices("](")
        .filter_map(|(at, _)| {
            let rest = &text[at + 2..];
            let end = rest.find(')')?;
            let target = rest[..end].split_whitespace().next()?.to_string();
            Some(target)
        })
        .collect()
}

/// The relative links of `file` that do not resolve.
fn broken(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap();
    let dir = file.parent().unwrap();
    let mut out = Vec::new();
    for target in links(&text) {
        if target.contains("://") || target.starts_with("mailto:") {
            continue;
        }
        let (path, anchor) = match target.split_once('#') {
            Some((p, a)) => (p, Some(a)),
            None => (target.as_str(), None),
        };
        let resolved = if path.is_empty() {
            file.to_path_buf()
        } else {
            dir.join(path)
        };
        if !resolved.exists() {
            out.push(format!("{target}: no such file"));
            continue;
        }
        if let Some(a) = anchor
            && resolved.extension().is_some_and(|e| e == "md")
        {
            let headings = std::fs::read_to_string(&resolved).unwrap();
            let known = headings
                .lines()
                .filter(|l| l.starts_with('#'))
                .any(|l| slug(l.trim_start_matches('#')) == a);
            if !known {
                out.push(format!("{target}: no heading #{a}"));
            }
        }
    }
    out
}

#[test]
fn every_relative_link_in_the_readme_and_docs_resolves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md")];
    markdown_files(&root.join("docs"), &mut files);
    assert!(files.len() > 10, "found {} Markdown files", files.len());
    let mut wrong = Vec::new();
    for f in &files {
        for b in broken(f) {
            wrong.push(format!("{}: {b}", f.strip_prefix(root).unwrap().display()));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn a_link_to_a_missing_file_or_heading_is_found() {
    let dir = std::env::temp_dir().join(format!("proleg-doc-links-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let page = dir.join("page.md");
    std::fs::write(
        &page,
        "# A page\n## Python environments\n[ok](page.md#python-environments) [gone](../NOPE.md) [no](#missing)\n",
    )
    .unwrap();
    let found = broken(&page);
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        found,
        ["../NOPE.md: no such file", "#missing: no heading #missing"]
    );
}
