//! Quoting input in messages: never more than [`QUOTE_CHARS`] characters.

/// The most characters of input that any message quotes (see [`excerpt`]).
pub const QUOTE_CHARS: usize = 80;

/// At most [`QUOTE_CHARS`] characters of `text`, for quoting input in a message: longer text is
/// cut there and the cut says how many bytes were left out; control characters (ESC, newlines)
/// are shown escaped (`\u{1b}`, `\n`). Every message that echoes a header,
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
    let (shown, used) = visible_prefix(text);
    if used == text.len() {
        shown
    } else {
        format!("{shown}… ({} more bytes)", text.len() - used)
    }
}

/// The longest prefix of `text` whose visible form (control characters escaped) is at most
/// [`QUOTE_CHARS`] characters, and the bytes of `text` it takes.
fn visible_prefix(text: &str) -> (String, usize) {
    let mut out = String::new();
    let mut shown = 0;
    for (at, c) in text.char_indices() {
        let width = if c.is_control() {
            c.escape_default().count()
        } else {
            1
        };
        if shown + width > QUOTE_CHARS {
            return (out, at);
        }
        push_visible(&mut out, c);
        shown += width;
    }
    (out, text.len())
}

/// Pushes `c`, or for a control character (ESC, a newline, …) its escape (`\u{1b}`, `\n`),
/// so that quoted input can neither move the cursor, colour a terminal nor split a line.
fn push_visible(out: &mut String, c: char) {
    if c.is_control() {
        out.extend(c.escape_default());
    } else {
        out.push(c);
    }
}

/// A message made safe to print whatever it quotes: control characters escaped, and every run
/// of more than [`QUOTE_CHARS`] characters without a blank (a 4000-character path, a
/// 309-digit number) shortened: a number to its value in scientific notation, anything else
/// by [`excerpt`]. The command-line tool passes every message through this last.
///
/// # Examples
/// ```
/// use bearing_ident::error::bounded;
/// let huge = format!("rate {} Hz", 1e308);
/// assert_eq!(bounded(&huge), "rate 1.000000e308 Hz");
/// let path = "d/".repeat(2000);
/// assert!(bounded(&format!("{path}: no such file")).chars().count() < 120);
/// assert_eq!(bounded("header `a\u{1b}[31m`"), "header `a\\u{1b}[31m`");
/// ```
pub fn bounded(message: &str) -> String {
    let mut out = String::with_capacity(message.len().min(1024));
    let mut run = String::new();
    let flush = |run: &mut String, out: &mut String| {
        if run.chars().count() > QUOTE_CHARS {
            let number = run.trim_end_matches(['.', ',', ';', ':', ')']);
            match number.parse::<f64>() {
                Ok(v)
                    if number
                        .bytes()
                        .all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b)) =>
                {
                    out.push_str(&format!("{v:.6e}"));
                    out.push_str(&run[number.len()..]);
                }
                _ => out.push_str(&excerpt(run)),
            }
        } else {
            out.push_str(run);
        }
        run.clear();
    };
    for c in message.chars() {
        if c == ' ' {
            flush(&mut run, &mut out);
            out.push(c);
        } else {
            push_visible(&mut run, c);
        }
    }
    flush(&mut run, &mut out);
    out
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
    let (shown, used) = visible_prefix(&text);
    if used == text.len() && head.len() == bytes.len() {
        return shown;
    }
    // Input bytes behind the shown characters (exact for UTF-8 input).
    let behind = bytes.len().saturating_sub(used);
    format!("{shown}… ({behind} more bytes)")
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

    /// Control bytes of quoted input are escaped (before: raw ESC from a CSV header and
    /// newlines of file names reached the terminal); long runs are shortened (before: a
    /// 309-digit number and a 4000-character path were echoed whole).
    #[test]
    fn quotes_are_visible_and_runs_bounded() {
        assert_eq!(excerpt("a\u{1b}[2Jb\nc"), "a\\u{1b}[2Jb\\nc");
        // Escapes count as what they show: 80 NUL bytes quote 16 of them (5 characters each).
        let nul = excerpt_bytes(&[0u8; 80]);
        assert!(
            nul.starts_with(&"\\u{0}".repeat(16)) && nul.ends_with("(64 more bytes)"),
            "{nul}"
        );
        assert!(nul.chars().count() < 100, "{nul}");
        let number = format!("{}", -1e308);
        assert_eq!(number.len(), 310);
        assert_eq!(
            bounded(&format!("value {number}, expected a finite step")),
            "value -1.000000e308, expected a finite step"
        );
        let path = format!("/{}/r.csv", "p".repeat(4000));
        let m = bounded(&format!("{path}, line 3: bad\nline"));
        assert!(
            m.starts_with(&path[..80]) && m.ends_with(" line 3: bad\\nline"),
            "{m}"
        );
        assert!(m.chars().count() < 130, "{m}");
        assert_eq!(bounded("short stays as it is"), "short stays as it is");
    }
}
