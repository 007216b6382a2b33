//! A small element tree with source positions, read with quick-xml.
//!
//! The typed formats are built from this tree rather than straight from serde so that
//! every semantic error (a NaN mass, an unknown module) can still name the line and
//! column it came from. Element names are matched case-insensitively, as OpenRAVE does.

use quick_xml::events::{BytesStart, Event};
use quick_xml::reader::Reader;

use crate::config::error::{ConfigError, ErrorKind, Pos};

/// Deepest element nesting accepted; deeper input is rejected instead of recursing.
pub const MAX_DEPTH: usize = 128;

/// One attribute with the position of its value.
#[derive(Debug, Clone)]
pub struct Attr {
    /// The attribute's name.
    pub name: String,
    /// Its value, unescaped.
    pub value: String,
    /// Where it was written (line, column).
    pub pos: Pos,
}

/// One element: name, attributes, child elements, and its own text (trimmed).
#[derive(Debug, Clone)]
pub struct Element {
    /// The tag name.
    pub name: String,
    /// Where it was written (line, column).
    pub pos: Pos,
    /// Its attributes.
    pub attrs: Vec<Attr>,
    /// Its child elements.
    pub children: Vec<Element>,
    /// Its text, trimmed.
    pub text: String,
    /// Where its text starts.
    pub text_pos: Pos,
    /// Comments directly inside this element, with positions.
    pub comments: Vec<(String, Pos)>,
}

/// A parsed document: the root element and comments outside it.
#[derive(Debug, Clone)]
pub struct Document {
    /// The root element.
    pub root: Element,
    /// Comments before or after the root element (the thesis keeps the robot pose there).
    pub outer_comments: Vec<(String, Pos)>,
}

impl Element {
    fn new(name: String, pos: Pos) -> Self {
        Element {
            name,
            pos,
            attrs: Vec::new(),
            children: Vec::new(),
            text: String::new(),
            text_pos: pos,
            comments: Vec::new(),
        }
    }

    /// Whether this element has the given name (ASCII case-insensitive).
    pub fn is(&self, name: &str) -> bool {
        self.name.eq_ignore_ascii_case(name)
    }

    /// The attribute of that name (ASCII case-insensitive), if present.
    pub fn attr(&self, name: &str) -> Option<&Attr> {
        self.attrs
            .iter()
            .find(|a| a.name.eq_ignore_ascii_case(name))
    }

    /// Child elements with one of the given names.
    pub fn children_named<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a Element> + 'a {
        self.children.iter().filter(move |c| c.is(name))
    }

    /// The first child of that name, if any.
    pub fn child(&self, name: &str) -> Option<&Element> {
        self.children.iter().find(|c| c.is(name))
    }
}

/// Line-start table to turn byte offsets into 1-based line and column numbers.
struct LineIndex {
    starts: Vec<usize>,
}

impl LineIndex {
    fn new(text: &str) -> Self {
        let mut starts = vec![0];
        starts.extend(text.match_indices('\n').map(|(i, _)| i + 1));
        LineIndex { starts }
    }

    fn pos(&self, text: &str, offset: usize) -> Pos {
        let offset = offset.min(text.len());
        let line = match self.starts.binary_search(&offset) {
            Ok(i) => i,
            Err(i) => i - 1,
        };
        let start = self.starts[line];
        let col = text
            .get(start..offset)
            .map(|s| s.chars().count())
            .unwrap_or(offset - start);
        Pos::new(line as u32 + 1, col as u32 + 1)
    }
}

/// Parses `text` into a [`Document`]. `file` is only used in error messages.
pub fn parse(file: &str, text: &str) -> Result<Document, ConfigError> {
    let index = LineIndex::new(text);
    let err = |offset: usize, kind: ErrorKind, msg: String| {
        ConfigError::new(file, index.pos(text, offset), kind, msg)
    };
    let mut reader = Reader::from_str(text);
    reader.config_mut().check_end_names = true;
    reader.config_mut().check_comments = false;

    let mut stack: Vec<Element> = Vec::new();
    let mut root: Option<Element> = None;
    let mut outer_comments = Vec::new();

    loop {
        let before = reader.buffer_position() as usize;
        let event = match reader.read_event() {
            Ok(e) => e,
            Err(e) => {
                let at = reader.error_position() as usize;
                return Err(err(at, ErrorKind::Syntax, format!("malformed XML: {e}")));
            }
        };
        match event {
            Event::Start(start) => {
                may_open(&start, &stack, root.is_some(), before, &err)?;
                let el = open_element(&start, before, text, &index, file)?;
                stack.push(el);
            }
            Event::Empty(start) => {
                may_open(&start, &stack, root.is_some(), before, &err)?;
                let el = open_element(&start, before, text, &index, file)?;
                match stack.last_mut() {
                    Some(parent) => parent.children.push(el),
                    None => root = Some(el),
                }
            }
            Event::End(_) => close_element(&mut stack, &mut root),
            Event::Text(t) => {
                let raw = t.xml10_content();
                push_text(&mut stack, &raw, before, text, &index, file, &err)?;
            }
            Event::CData(t) => {
                let raw = t.to_string();
                push_text(&mut stack, &raw, before, text, &index, file, &err)?;
            }
            Event::GeneralRef(r) => {
                let resolved = resolve_reference(&r)
                    .map_err(|m| err(before, ErrorKind::Syntax, m.to_string()))?;
                push_text(&mut stack, &resolved, before, text, &index, file, &err)?;
            }
            Event::Comment(c) => {
                let body = c.to_string();
                let pos = index.pos(text, before);
                match stack.last_mut() {
                    Some(parent) => parent.comments.push((body, pos)),
                    None => outer_comments.push((body, pos)),
                }
            }
            Event::Decl(_) | Event::PI(_) | Event::DocType(_) => {}
            Event::Eof => break,
        }
    }
    finish(stack, root, outer_comments, file, &err)
}

/// Whether element `start` may open here: not a second root, not nested too deep.
fn may_open(
    start: &BytesStart,
    stack: &[Element],
    has_root: bool,
    before: usize,
    err: &dyn Fn(usize, ErrorKind, String) -> ConfigError,
) -> Result<(), ConfigError> {
    if has_root && stack.is_empty() {
        let name = start.name().as_ref().to_string();
        return Err(err(
            before,
            ErrorKind::Syntax,
            format!("second root element <{name}>: a file holds exactly one root element"),
        ));
    }
    if stack.len() >= MAX_DEPTH {
        return Err(err(
            before,
            ErrorKind::Syntax,
            format!("elements nested deeper than {MAX_DEPTH} levels"),
        ));
    }
    Ok(())
}

/// The document once the text ended: every element closed, one root.
fn finish(
    stack: Vec<Element>,
    root: Option<Element>,
    outer_comments: Vec<(String, Pos)>,
    file: &str,
    err: &dyn Fn(usize, ErrorKind, String) -> ConfigError,
) -> Result<Document, ConfigError> {
    if let Some(open) = stack.last() {
        return Err(ConfigError::new(
            file,
            open.pos,
            ErrorKind::Syntax,
            format!("<{}> is never closed", open.name),
        ));
    }
    match root {
        Some(root) => Ok(Document {
            root,
            outer_comments,
        }),
        None => Err(err(
            0,
            ErrorKind::Syntax,
            "the file holds no XML element".into(),
        )),
    }
}

/// The text of an entity or character reference (`&amp;`, `&#955;`).
fn resolve_reference(r: &quick_xml::events::BytesRef<'_>) -> Result<String, ReferenceError> {
    match r.resolve_char_ref() {
        Ok(Some(c)) => Ok(c.to_string()),
        Ok(None) => {
            let name = r.to_string();
            quick_xml::escape::resolve_predefined_entity(&name)
                .map(str::to_string)
                .ok_or(ReferenceError::UnknownEntity(name))
        }
        Err(e) => Err(ReferenceError::BadCharacter(e)),
    }
}

/// Why a reference has no text.
#[derive(Debug, thiserror::Error)]
enum ReferenceError {
    /// Not one of XML's predefined entities.
    #[error("unknown entity &{0};")]
    UnknownEntity(String),
    /// A `&#...;` that names no character.
    #[error("bad character reference: {0}")]
    BadCharacter(quick_xml::Error),
}

/// Closes the innermost open element: its text trimmed, it joins its parent (or becomes
/// the root). quick-xml checks that end names match, so an element is open here.
fn close_element(stack: &mut Vec<Element>, root: &mut Option<Element>) {
    if let Some(mut el) = stack.pop() {
        let trimmed = el.text.trim();
        if trimmed.len() != el.text.len() {
            el.text = trimmed.to_string();
        }
        match stack.last_mut() {
            Some(parent) => parent.children.push(el),
            None => *root = Some(el),
        }
    }
}

fn push_text(
    stack: &mut [Element],
    raw: &str,
    offset: usize,
    text: &str,
    index: &LineIndex,
    _file: &str,
    err: &dyn Fn(usize, ErrorKind, String) -> ConfigError,
) -> Result<(), ConfigError> {
    match stack.last_mut() {
        Some(el) => {
            if el.text.trim().is_empty() {
                let lead = raw.len() - raw.trim_start().len();
                if !raw.trim().is_empty() {
                    el.text_pos = index.pos(text, offset + lead);
                }
            }
            el.text.push_str(raw);
            Ok(())
        }
        None if raw.trim().is_empty() => Ok(()),
        None => Err(err(
            offset,
            ErrorKind::Syntax,
            "text outside the root element".into(),
        )),
    }
}

fn open_element(
    start: &BytesStart,
    offset: usize,
    text: &str,
    index: &LineIndex,
    file: &str,
) -> Result<Element, ConfigError> {
    let name = start.name().as_ref().to_string();
    let pos = index.pos(text, offset);
    let mut el = Element::new(name, pos);
    let raw_tag = text.get(offset..).unwrap_or("");
    for attr in start.attributes() {
        let attr = attr.map_err(|e| {
            ConfigError::new(
                file,
                pos,
                ErrorKind::Syntax,
                format!("malformed XML: bad attribute in <{}>: {e}", el.name),
            )
        })?;
        let key = attr.key.as_ref().to_string();
        let value = attr
            .normalized_value(quick_xml::XmlVersion::Implicit1_0)
            .map_err(|e| {
                ConfigError::new(
                    file,
                    pos,
                    ErrorKind::Syntax,
                    format!(
                        "malformed XML: bad value of attribute {key} in <{}>: {e}",
                        el.name
                    ),
                )
            })?
            .into_owned();
        let value_pos = attr_value_offset(raw_tag, &key)
            .map(|o| index.pos(text, offset + o))
            .unwrap_or(pos);
        el.attrs.push(Attr {
            name: key,
            value,
            pos: value_pos,
        });
    }
    Ok(el)
}

/// Byte offset of the first character of attribute `key`'s value inside a raw start tag.
fn attr_value_offset(raw_tag: &str, key: &str) -> Option<usize> {
    let end = raw_tag.find('>').unwrap_or(raw_tag.len());
    let tag = &raw_tag[..end];
    let mut from = 0;
    while let Some(found) = tag[from..].find(key) {
        let at = from + found;
        let before_ok = at > 0 && tag.as_bytes()[at - 1].is_ascii_whitespace();
        let rest = &tag[at + key.len()..];
        let after = rest.trim_start();
        if before_ok && after.starts_with('=') {
            let after_eq = after[1..].trim_start();
            let quote_at = tag.len() - after_eq.len();
            return Some(quote_at + 1);
        }
        from = at + key.len();
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_of_elements_text_and_attribute_values() {
        let doc = parse(
            "f.xml",
            "<a>\n  <b x=\"1\"  yy = '22'>\n    hello\n  </b>\n</a>",
        )
        .unwrap();
        let b = &doc.root.children[0];
        assert_eq!((b.pos.line, b.pos.col), (2, 3));
        assert_eq!((b.attrs[0].pos.line, b.attrs[0].pos.col), (2, 9));
        assert_eq!((b.attrs[1].pos.line, b.attrs[1].pos.col), (2, 19));
        assert_eq!(b.attrs[1].value, "22");
        assert_eq!(b.text, "hello");
        assert_eq!((b.text_pos.line, b.text_pos.col), (3, 5));
    }

    #[test]
    fn entities_cdata_and_comments() {
        let doc = parse("f.xml", "<!-- before --><a n=\"x &amp; y\">1 &lt; 2<![CDATA[ <ok> ]]>&#65;<!-- in --></a><!--Pose: ,1 0 0 0,0 0 0,-->").unwrap();
        assert_eq!(doc.root.attrs[0].value, "x & y");
        assert_eq!(doc.root.text, "1 < 2 <ok> A");
        assert_eq!(doc.root.comments[0].0, " in ");
        assert_eq!(doc.outer_comments.len(), 2);
        assert_eq!(doc.outer_comments[1].0, "Pose: ,1 0 0 0,0 0 0,");
    }

    #[test]
    fn syntax_errors_are_located() {
        let e = parse("f.xml", "<a>\n  <b></c>\n</a>").unwrap_err();
        assert_eq!(e.kind, ErrorKind::Syntax);
        assert_eq!(e.pos.line, 2, "{e}");
        let e = parse("f.xml", "<a>\n<b>").unwrap_err();
        assert!(e.to_string().contains("never closed"), "{e}");
        let e = parse("f.xml", "<a/><b/>").unwrap_err();
        assert!(e.to_string().contains("second root element <b>"), "{e}");
        let e = parse("f.xml", "<a>&nbsp;</a>").unwrap_err();
        assert!(e.to_string().contains("unknown entity &nbsp;"), "{e}");
    }
}
