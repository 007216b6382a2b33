//! Rust syntax highlighting for the module editor (thesis fig. 4.9): a small tokenizer
//! (comments, strings, chars, numbers, keywords, types, macros) coloured into an egui
//! `LayoutJob`. It needs no grammar files and colours a module of a few hundred lines
//! in well under a frame.

use bevy_egui::egui::{self, Color32, FontId, TextFormat, text::LayoutJob};

/// What a piece of source is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Token {
    /// A comment.
    Comment,
    /// A string or character literal.
    Str,
    /// A number.
    Number,
    /// A Rust keyword.
    Keyword,
    /// A capitalised name: types, traits, constants.
    Type,
    /// A macro call.
    Macro,
    /// Anything else.
    Plain,
}

const KEYWORDS: &[&str] = &[
    "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn", "for",
    "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub", "ref", "return",
    "self", "Self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use", "where",
    "while", "dyn", "f64", "usize", "u64", "bool", "u32", "i32",
];

/// Splits `text` into (byte range, token) pieces covering it completely.
pub fn tokens(text: &str) -> Vec<(std::ops::Range<usize>, Token)> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    let n = bytes.len();
    while i < n {
        let start = i;
        let c = bytes[i];
        let token = if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < n && bytes[i] != b'\n' {
                i += 1;
            }
            Token::Comment
        } else if c == b'/' && bytes.get(i + 1) == Some(&b'*') {
            i += 2;
            while i < n && !(bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/')) {
                i += 1;
            }
            i = (i + 2).min(n);
            Token::Comment
        } else if c == b'"' {
            i += 1;
            while i < n && bytes[i] != b'"' {
                if bytes[i] == b'\\' {
                    i += 1;
                    i += text
                        .get(i..)
                        .and_then(|t| t.chars().next())
                        .map_or(0, char::len_utf8);
                } else {
                    i += 1;
                }
            }
            i = (i + 1).min(n);
            Token::Str
        } else if c == b'\'' && bytes.get(i + 2) == Some(&b'\'') {
            i += 3;
            Token::Str
        } else if c.is_ascii_digit() {
            while i < n
                && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'.' || bytes[i] == b'_')
            {
                // `1..5` is a range, not a number.
                if bytes[i] == b'.' && bytes.get(i + 1) == Some(&b'.') {
                    break;
                }
                i += 1;
            }
            Token::Number
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < n && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            let word = &text[start..i];
            if bytes.get(i) == Some(&b'!') {
                i += 1;
                Token::Macro
            } else if KEYWORDS.contains(&word) {
                Token::Keyword
            } else if c.is_ascii_uppercase() {
                Token::Type
            } else {
                Token::Plain
            }
        } else {
            // Anything else up to the next interesting character (keeps UTF-8 intact).
            i += text[i..].chars().next().map_or(1, char::len_utf8);
            while i < n
                && !bytes[i].is_ascii_alphanumeric()
                && !matches!(bytes[i], b'_' | b'"' | b'\'' | b'/')
            {
                i += text[i..].chars().next().map_or(1, char::len_utf8);
            }
            Token::Plain
        };
        out.push((start..i, token));
    }
    out
}

fn colour(token: Token, dark: bool) -> Color32 {
    match (token, dark) {
        (Token::Comment, _) => Color32::from_rgb(120, 150, 110),
        (Token::Str, _) => Color32::from_rgb(206, 145, 90),
        (Token::Number, _) => Color32::from_rgb(150, 200, 160),
        (Token::Keyword, true) => Color32::from_rgb(100, 160, 240),
        (Token::Keyword, false) => Color32::from_rgb(20, 70, 200),
        (Token::Type, true) => Color32::from_rgb(80, 200, 190),
        (Token::Type, false) => Color32::from_rgb(20, 130, 120),
        (Token::Macro, _) => Color32::from_rgb(190, 120, 220),
        (Token::Plain, true) => Color32::from_gray(220),
        (Token::Plain, false) => Color32::from_gray(30),
    }
}

/// The coloured layout of `text` in `font`.
pub fn highlight(text: &str, font: FontId, dark: bool, wrap_width: f32) -> LayoutJob {
    let mut job = LayoutJob::default();
    for (range, token) in tokens(text) {
        job.append(
            &text[range],
            0.0,
            TextFormat::simple(font.clone(), colour(token, dark)),
        );
    }
    job.wrap.max_width = wrap_width;
    job
}

/// A code-editor text field with highlighting.
pub fn code_editor(ui: &mut egui::Ui, text: &mut String, rows: usize) -> egui::Response {
    let dark = ui.visuals().dark_mode;
    let mut layouter = |ui: &egui::Ui, buf: &dyn egui::TextBuffer, wrap_width: f32| {
        let font = egui::TextStyle::Monospace.resolve(ui.style());
        ui.ctx()
            .fonts_mut(|f| f.layout_job(highlight(buf.as_str(), font, dark, wrap_width)))
    };
    ui.add(
        egui::TextEdit::multiline(text)
            .code_editor()
            .desired_rows(rows)
            .desired_width(f32::INFINITY)
            .layouter(&mut layouter),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_cover_the_text_and_classify_rust() {
        let src = "// step\nfn compute(&mut self) { let x = 2.5 * p.get(AMPLITUDE, j); println!(\"a{}\", 'c'); for k in 0..5 {} }";
        let toks = tokens(src);
        let joined: String = toks.iter().map(|(r, _)| &src[r.clone()]).collect();
        assert_eq!(joined, src);
        let kind = |word: &str| {
            toks.iter()
                .find(|(r, _)| &src[r.clone()] == word)
                .map(|(_, t)| *t)
        };
        assert_eq!(kind("// step"), Some(Token::Comment));
        assert_eq!(kind("fn"), Some(Token::Keyword));
        assert_eq!(kind("2.5"), Some(Token::Number));
        assert_eq!(kind("AMPLITUDE"), Some(Token::Type));
        assert_eq!(kind("println!"), Some(Token::Macro));
        assert_eq!(kind("\"a{}\""), Some(Token::Str));
        assert_eq!(kind("'c'"), Some(Token::Str));
        assert_eq!(kind("0"), Some(Token::Number));
        assert_eq!(kind("compute"), Some(Token::Plain));
    }

    #[test]
    fn unterminated_pieces_and_unicode_do_not_break_it() {
        for src in [
            "\"open",
            "/* open",
            "x = 'ä'; // ü",
            "ö",
            "1..",
            "\"\\",
            "\"\\ä\"",
        ] {
            let joined: String = tokens(src).iter().map(|(r, _)| &src[r.clone()]).collect();
            assert_eq!(joined, src);
        }
    }
}
