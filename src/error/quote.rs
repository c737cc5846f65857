//! Quoting input in messages: never more than [`QUOTE_CHARS`] characters.

/// The most characters of input that any message quotes (see [`excerpt`]).
pub const QUOTE_CHARS: usize = 80;

/// At most [`QUOTE_CHARS`] characters of `text`, for quoting input in a message: longer text is
/// cut there and the cut says how many bytes were left out. Every message that echoes a header,
/// a field, a value or an argument goes through this, so a file with no newline or a pasted
/// megabyte never floods a terminal or a JSON log.
///
/// # Examples
/// ```
/// use bearing_ident::error::excerpt;
/// assert_eq!(excerpt("t,fx,x"), "t,fx,x");
/// let long = "a".repeat(1000);
/// assert_eq!(excerpt(&long), format!("{}… (920 more bytes)", "a".repeat(80)));
/// ```
pub fn excerpt(text: &str) -> String {
    match text.char_indices().nth(QUOTE_CHARS) {
        None => text.to_owned(),
        Some((cut, _)) => format!("{}… ({} more bytes)", &text[..cut], text.len() - cut),
    }
}

/// [`excerpt`] of bytes that may not be UTF-8 (invalid sequences shown as `�`); only the first
/// few hundred bytes are ever looked at.
///
/// # Examples
/// ```
/// use bearing_ident::error::excerpt_bytes;
/// assert_eq!(excerpt_bytes(b"1.5e3"), "1.5e3");
/// assert!(excerpt_bytes(&[0u8; 1 << 20]).len() < 120);
/// ```
pub fn excerpt_bytes(bytes: &[u8]) -> String {
    // 4 bytes per character at most: this prefix holds the quoted characters.
    let head = &bytes[..bytes.len().min(4 * QUOTE_CHARS + 4)];
    let text = String::from_utf8_lossy(head);
    match text.char_indices().nth(QUOTE_CHARS) {
        None if head.len() == bytes.len() => text.into_owned(),
        None => format!("{text}… ({} more bytes)", bytes.len() - head.len()),
        Some((cut, _)) => {
            let shown = &text[..cut];
            // Input bytes behind the shown characters (exact for UTF-8 input).
            let behind = bytes.len().saturating_sub(shown.len());
            format!("{shown}… ({behind} more bytes)")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn excerpts_are_bounded() {
        assert_eq!(excerpt(""), "");
        let eighty = "é".repeat(80);
        assert_eq!(excerpt(&eighty), eighty);
        let long = "é".repeat(81);
        assert_eq!(excerpt(&long), format!("{eighty}… (2 more bytes)"));
        assert_eq!(excerpt_bytes(b"abc"), "abc");
        let s = excerpt_bytes(&[b'x'; 10_000]);
        assert!(
            s.starts_with(&"x".repeat(80)) && s.ends_with("(9920 more bytes)"),
            "{s}"
        );
        assert!(excerpt_bytes(&[0xff; 10_000]).chars().count() < 110);
    }
}
