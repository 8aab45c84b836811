//! Escaping of the values that errors and warnings echo (ids, names, keys, paths, strings of
//! a scene file): a control character there would break the message (a newline in an id
//! split `unknown id` over two lines, issue 44), reach the terminal as a command (ESC) or
//! reorder the text around it (bidirectional overrides). Each such character is written as
//! Rust writes it in a string literal (`\t`, `\n`, `\r`, `\0`, `\u{1b}`); everything else,
//! backslashes included, is kept as it is, so a message without them is unchanged.
//!
//! [`crate::error::Error`]'s messages and [`crate::warning::warn`] pass through [`escape`]:
//! every value they echo is escaped, wherever it was formatted.

use std::borrow::Cow;

/// Whether `c` is written escaped: a C0 or C1 control character or DEL (a newline and a tab
/// included), a line or paragraph separator, or a bidirectional formatting character.
pub fn needs_escape(c: char) -> bool {
    c.is_control()
        || matches!(c, '\u{2028}' | '\u{2029}' | '\u{200e}' | '\u{200f}')
        || ('\u{202a}'..='\u{202e}').contains(&c)
        || ('\u{2066}'..='\u{2069}').contains(&c)
}

/// `text` with every character of [`needs_escape`] escaped (`\t`, `\n`, `\u{1b}`, ...);
/// borrowed when there is none.
pub fn escape(text: &str) -> Cow<'_, str> {
    if !text.chars().any(needs_escape) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if needs_escape(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn controls_are_escaped_and_the_rest_kept() {
        assert_eq!(escape("\t\n1"), "\\t\\n1");
        assert_eq!(escape("a\rb\0c\u{1b}[2J"), "a\\rb\\u{0}c\\u{1b}[2J");
        assert_eq!(escape("\u{7f}\u{85}\u{9b}"), "\\u{7f}\\u{85}\\u{9b}");
        assert_eq!(escape("x\u{2028}y\u{202e}z"), "x\\u{2028}y\\u{202e}z");
        // Backslashes, quotes, non-ASCII letters and paths stay as written.
        let plain = "C:\\scenes\\ünïcode `a` \"b\" 1.0";
        assert!(matches!(escape(plain), Cow::Borrowed(p) if p == plain));
    }
}
