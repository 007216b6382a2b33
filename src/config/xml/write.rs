//! An indenting XML writer for the configuration formats.
//!
//! Numbers are written with Rust's shortest round-trip representation, so a model
//! written and read back is equal to the original.

use std::fmt::Write as _;

use quick_xml::escape::escape;

/// Builds an XML document as a string.
#[derive(Debug, Default)]
pub struct XmlWriter {
    out: String,
    open: Vec<String>,
}

impl XmlWriter {
    /// An empty document.
    pub fn new() -> Self {
        XmlWriter {
            out: String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"),
            open: Vec::new(),
        }
    }

    fn indent(&mut self) {
        for _ in 0..self.open.len() {
            self.out.push_str("  ");
        }
    }

    fn tag(&mut self, name: &str, attrs: &[(&str, String)]) {
        self.indent();
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs {
            let _ = write!(self.out, " {k}=\"{}\"", escape(v.as_str()));
        }
    }

    /// Opens `<name attrs...>`; close it with [`XmlWriter::close`].
    pub fn open(&mut self, name: &str, attrs: &[(&str, String)]) {
        self.tag(name, attrs);
        self.out.push_str(">\n");
        self.open.push(name.to_string());
    }

    /// Closes the innermost open element.
    pub fn close(&mut self) {
        if let Some(name) = self.open.pop() {
            self.indent();
            let _ = writeln!(self.out, "</{name}>");
        }
    }

    /// Writes `<name attrs.../>`.
    pub fn empty(&mut self, name: &str, attrs: &[(&str, String)]) {
        self.tag(name, attrs);
        self.out.push_str("/>\n");
    }

    /// Writes `<name attrs...>text</name>`.
    pub fn leaf_attrs(&mut self, name: &str, attrs: &[(&str, String)], text: &str) {
        self.tag(name, attrs);
        let _ = writeln!(self.out, ">{}</{name}>", escape(text));
    }

    /// Writes `<name>text</name>`.
    pub fn leaf(&mut self, name: &str, text: &str) {
        self.leaf_attrs(name, &[], text);
    }

    /// Writes `<name>v</name>` for a number.
    pub fn num(&mut self, name: &str, v: f64) {
        self.leaf(name, &num(v));
    }

    /// Writes `<name>a b c</name>` for a list of numbers.
    pub fn nums(&mut self, name: &str, v: &[f64]) {
        self.leaf(name, &nums(v));
    }

    /// Writes `<name>1</name>` or `<name>0</name>`.
    pub fn flag(&mut self, name: &str, v: bool) {
        self.leaf(name, if v { "1" } else { "0" });
    }

    /// Writes a comment on its own line.
    pub fn comment(&mut self, text: &str) {
        self.indent();
        let safe = text.replace("--", "- -");
        let _ = writeln!(self.out, "<!--{safe}-->");
    }

    /// The finished document.
    pub fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.out
    }
}

/// A number in shortest round-trip form.
pub fn num(v: f64) -> String {
    format!("{v}")
}

/// Numbers separated by single spaces.
pub fn nums(v: &[f64]) -> String {
    v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(" ")
}
