//! Typed reading of element text and attributes, with positioned errors.
//!
//! A [`Reader`] knows which file it reads, so every helper can report
//! `file:line:col: what was expected`.

use std::path::{Path, PathBuf};

use crate::config::error::{ConfigError, ConfigResult, ErrorKind, Pos};
use crate::config::xml::dom::{Attr, Document, Element};

/// Reads values out of the elements of one file.
#[derive(Debug, Clone)]
pub struct Reader {
    /// The file, named in errors.
    pub file: PathBuf,
}

impl Reader {
    /// A reader for `file`.
    pub fn new(file: impl AsRef<Path>) -> Self {
        Reader {
            file: file.as_ref().to_path_buf(),
        }
    }

    /// An error at `pos` of this file.
    pub fn err(&self, pos: Pos, kind: ErrorKind, msg: impl Into<String>) -> ConfigError {
        ConfigError::new(&self.file, pos, kind, msg)
    }

    /// Fails unless every child of `el` has one of the `allowed` names.
    pub fn only_children(&self, el: &Element, allowed: &[&str]) -> ConfigResult<()> {
        for c in &el.children {
            if !allowed.iter().any(|a| c.is(a)) {
                return Err(self.err(
                    c.pos,
                    ErrorKind::UnknownElement,
                    format!(
                        "unknown element <{}> in <{}>; expected one of: {}",
                        c.name,
                        el.name,
                        list(allowed)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Fails unless every attribute of `el` has one of the `allowed` names.
    pub fn only_attrs(&self, el: &Element, allowed: &[&str]) -> ConfigResult<()> {
        for a in &el.attrs {
            if !allowed.iter().any(|n| a.name.eq_ignore_ascii_case(n)) {
                let expected = if allowed.is_empty() {
                    "none".to_string()
                } else {
                    list(allowed)
                };
                return Err(self.err(
                    a.pos,
                    ErrorKind::UnknownElement,
                    format!(
                        "unknown attribute {}= on <{}>; expected: {expected}",
                        a.name, el.name
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Fails if `el` has more than one child of that name.
    pub fn at_most_one<'a>(
        &self,
        el: &'a Element,
        name: &'a str,
    ) -> ConfigResult<Option<&'a Element>> {
        let mut found = el.children_named(name);
        let first = found.next();
        if let Some(second) = found.next() {
            return Err(self.err(
                second.pos,
                ErrorKind::InvalidValue,
                format!("<{}> given twice in <{}>", second.name, el.name),
            ));
        }
        Ok(first)
    }

    /// The one required child of that name.
    pub fn required<'a>(&self, el: &'a Element, name: &'a str) -> ConfigResult<&'a Element> {
        self.at_most_one(el, name)?.ok_or_else(|| {
            self.err(
                el.pos,
                ErrorKind::Missing,
                format!("<{}> needs a <{name}> element", el.name),
            )
        })
    }

    /// A required attribute.
    pub fn required_attr<'a>(&self, el: &'a Element, name: &str) -> ConfigResult<&'a Attr> {
        el.attr(name).ok_or_else(|| {
            self.err(
                el.pos,
                ErrorKind::Missing,
                format!("<{}> needs the attribute {name}=\"...\"", el.name),
            )
        })
    }

    /// The element's text, which must not be empty.
    pub fn text<'a>(&self, el: &'a Element) -> ConfigResult<&'a str> {
        if el.text.is_empty() {
            return Err(self.err(
                el.pos,
                ErrorKind::Missing,
                format!("<{}> is empty; it needs a value", el.name),
            ));
        }
        Ok(&el.text)
    }

    /// One finite number from text at `pos`, naming `what` on failure.
    pub fn number(&self, s: &str, pos: Pos, what: &str) -> ConfigResult<f64> {
        let v: f64 = s.trim().parse().map_err(|_| {
            self.err(
                pos,
                ErrorKind::InvalidValue,
                format!("{what}: expected a number, found \"{}\"", s.trim()),
            )
        })?;
        if !v.is_finite() {
            return Err(self.err(
                pos,
                ErrorKind::InvalidValue,
                format!("{what}: expected a finite number, found \"{}\"", s.trim()),
            ));
        }
        Ok(v)
    }

    /// A number from an element's text.
    pub fn f64(&self, el: &Element) -> ConfigResult<f64> {
        let t = self.text(el)?;
        self.number(t, el.text_pos, &format!("<{}>", el.name))
    }

    /// A number > 0 from an element's text.
    pub fn positive(&self, el: &Element) -> ConfigResult<f64> {
        let v = self.f64(el)?;
        if v <= 0.0 {
            return Err(self.err(
                el.text_pos,
                ErrorKind::OutOfRange,
                format!("<{}> is {v}; it must be > 0", el.name),
            ));
        }
        Ok(v)
    }

    /// The number > 0 of an optional child.
    pub fn opt_positive(&self, el: &Element, name: &str) -> ConfigResult<Option<f64>> {
        self.at_most_one(el, name)?
            .map(|c| self.positive(c))
            .transpose()
    }

    /// A number from an element's text, checked against an inclusive range.
    pub fn f64_in(&self, el: &Element, min: f64, max: f64) -> ConfigResult<f64> {
        let v = self.f64(el)?;
        self.check_range(v, min, max, el.text_pos, &format!("<{}>", el.name))?;
        Ok(v)
    }

    /// Fails unless `min <= v <= max`.
    pub fn check_range(
        &self,
        v: f64,
        min: f64,
        max: f64,
        pos: Pos,
        what: &str,
    ) -> ConfigResult<()> {
        if v < min || v > max {
            let range = match (min.is_finite(), max.is_finite()) {
                (true, true) => format!("between {min} and {max}"),
                (true, false) => format!("at least {min}"),
                (false, true) => format!("at most {max}"),
                (false, false) => "any number".into(),
            };
            return Err(self.err(
                pos,
                ErrorKind::OutOfRange,
                format!("{what} is {v}; it must be {range}"),
            ));
        }
        Ok(())
    }

    /// A whitespace-separated list of finite numbers from text at `pos`.
    pub fn numbers(&self, s: &str, pos: Pos, what: &str) -> ConfigResult<Vec<f64>> {
        s.split_whitespace()
            .map(|w| self.number(w, pos, what))
            .collect()
    }

    /// Exactly `N` numbers from an element's text.
    pub fn array<const N: usize>(&self, el: &Element) -> ConfigResult<[f64; N]> {
        let what = format!("<{}>", el.name);
        let v = self.numbers(self.text(el)?, el.text_pos, &what)?;
        v.try_into().map_err(|v: Vec<f64>| {
            self.err(
                el.text_pos,
                ErrorKind::InvalidValue,
                format!("{what}: expected {N} numbers, found {}", v.len()),
            )
        })
    }

    /// A non-negative integer from an element's text.
    pub fn u32(&self, el: &Element) -> ConfigResult<u32> {
        let t = self.text(el)?;
        self.u32_str(t, el.text_pos, &format!("<{}>", el.name))
    }

    /// A non-negative integer from a string.
    pub fn u32_str(&self, s: &str, pos: Pos, what: &str) -> ConfigResult<u32> {
        s.trim().parse().map_err(|_| {
            self.err(
                pos,
                ErrorKind::InvalidValue,
                format!(
                    "{what}: expected a whole number >= 0, found \"{}\"",
                    s.trim()
                ),
            )
        })
    }

    /// A 0/1 flag (also `true`/`false`) from an element's text.
    pub fn flag(&self, el: &Element) -> ConfigResult<bool> {
        let t = self.text(el)?;
        self.flag_str(t, el.text_pos, &format!("<{}>", el.name))
    }

    /// A 0/1 flag (also `true`/`false`) from a string.
    pub fn flag_str(&self, s: &str, pos: Pos, what: &str) -> ConfigResult<bool> {
        match s.trim().to_ascii_lowercase().as_str() {
            "1" | "true" | "yes" => Ok(true),
            "0" | "false" | "no" => Ok(false),
            other => Err(self.err(
                pos,
                ErrorKind::InvalidValue,
                format!("{what}: expected 1 or 0, found \"{other}\""),
            )),
        }
    }

    /// An optional child's number, or `default`.
    pub fn opt_f64(&self, el: &Element, name: &str) -> ConfigResult<Option<f64>> {
        self.at_most_one(el, name)?.map(|c| self.f64(c)).transpose()
    }
}

/// Parses a file's text and checks that its root element is `root` (e.g. `"Robot"`);
/// `what` names the kind of file in the error.
pub fn read_document(
    file: &str,
    text: &str,
    root: &str,
    what: &str,
) -> ConfigResult<(Document, Reader)> {
    let doc = crate::config::xml::dom::parse(file, text)?;
    let r = Reader::new(file);
    if !doc.root.is(root) {
        return Err(r.err(
            doc.root.pos,
            ErrorKind::UnknownElement,
            format!("{what} starts with <{root}>, not <{}>", doc.root.name),
        ));
    }
    Ok((doc, r))
}

/// `a, b, c` for messages.
pub fn list(items: &[&str]) -> String {
    items.join(", ")
}

/// Whether two names are the same for lookup purposes: case, spaces, `_` and `-` ignored.
pub fn same_name(a: &str, b: &str) -> bool {
    let norm = |s: &str| {
        s.chars()
            .filter(|c| !matches!(c, ' ' | '_' | '-'))
            .flat_map(char::to_lowercase)
            .collect::<String>()
    };
    norm(a) == norm(b)
}
