//! Numbers as text, as every table, report and figure of the crate prints them.

/// `v` with `digits` significant digits: fixed-point for magnitudes from 10⁻³ to below 10⁶,
/// scientific otherwise (the format of every number in the report and the CLI's table).
///
/// # Examples
/// ```
/// use bearing_ident::text::significant;
/// assert_eq!(significant(146_312.345, 7), "146312.3");
/// assert_eq!(significant(0.000_123_4, 3), "1.23e-4");
/// assert_eq!(significant(4.7, 3), "4.70");
/// ```
pub fn significant(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = v.abs().log10().floor() as i32;
    if (-3..6).contains(&exp) {
        let decimals = (digits as i32 - 1 - exp).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.prec$e}", prec = digits.max(1) - 1)
    }
}

/// Widest line of the crate's text tables, in characters: a table with more columns than fit
/// is split (see [`table`]).
pub const TABLE_WIDTH: usize = 120;

/// Where a text table's cells sit in their columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Align {
    /// Flush left (names, text).
    Left,
    /// Flush right (numbers: their last digits line up under the header's end).
    Right,
}

/// `rows` (the header first) as a text table: each column as wide as its widest cell, two
/// spaces between columns, every line after `indent` spaces and without trailing spaces.
///
/// The first `keys` columns name a row; the others come in groups of the sizes `groups` lists
/// (columns past the groups form one more). When the lines would be wider than
/// [`TABLE_WIDTH`], the table is split into blocks, one under the other with a blank line
/// between them, each repeating the key columns and holding as many whole groups as fit (a
/// group wider than the width alone still gets a block of its own). A row shorter than the
/// header leaves its last cells empty.
///
/// # Examples
/// ```
/// use bearing_ident::text::{Align, TABLE_WIDTH, table};
/// let row = |name: &str, v: &str| {
///     let mut r = vec![name.to_owned()];
///     r.extend(std::iter::repeat_n(v.to_owned(), 12));
///     r
/// };
/// let rows = vec![row("speed", "coefficient"), row("1000", "1.5e6")];
/// let text = table(&rows, 1, &[6, 6], Align::Right, 2);
/// let lines: Vec<&str> = text.lines().collect();
/// // 6 columns of 11 characters and the key fit in 120; 12 do not: two blocks of 6.
/// assert_eq!(lines.len(), 5);
/// assert!(lines[3].starts_with("  speed  coefficient"));
/// assert!(lines.iter().all(|l| l.chars().count() <= TABLE_WIDTH));
/// ```
pub fn table(
    rows: &[Vec<String>],
    keys: usize,
    groups: &[usize],
    align: Align,
    indent: usize,
) -> String {
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let keys = keys.min(columns);
    let widths: Vec<usize> = (0..columns)
        .map(|c| {
            rows.iter()
                .map(|r| r.get(c).map_or(0, |s| s.chars().count()))
                .max()
                .unwrap_or(0)
        })
        .collect();
    // The groups as column ranges, the rest of the columns one more group.
    let mut spans = Vec::new();
    let mut from = keys;
    for &size in groups {
        let to = (from + size).min(columns);
        if to > from {
            spans.push(from..to);
        }
        from = to;
    }
    if from < columns {
        spans.push(from..columns);
    }
    let span_width =
        |span: &std::ops::Range<usize>| span.clone().map(|c| widths[c] + 2).sum::<usize>();
    let key_width = indent + (0..keys).map(|c| widths[c] + 2).sum::<usize>();
    // Whole groups per block, as many as fit.
    let mut blocks: Vec<Vec<usize>> = Vec::new();
    let mut width = key_width;
    for span in &spans {
        let w = span_width(span);
        match blocks.last_mut() {
            Some(block) if width + w <= TABLE_WIDTH + 2 => {
                block.extend(span.clone());
                width += w;
            }
            _ => {
                blocks.push(span.clone().collect());
                width = key_width + w;
            }
        }
    }
    if blocks.is_empty() {
        blocks.push(Vec::new());
    }
    let mut out = String::new();
    for (b, block) in blocks.iter().enumerate() {
        if b > 0 {
            out.push('\n');
        }
        for row in rows {
            let mut line = " ".repeat(indent);
            for (k, c) in (0..keys).chain(block.iter().copied()).enumerate() {
                if k > 0 {
                    line.push_str("  ");
                }
                let cell = row.get(c).map_or("", String::as_str);
                let pad = widths[c] - cell.chars().count();
                match align {
                    Align::Left => {
                        line.push_str(cell);
                        line.extend(std::iter::repeat_n(' ', pad));
                    }
                    Align::Right => {
                        line.extend(std::iter::repeat_n(' ', pad));
                        line.push_str(cell);
                    }
                }
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
    }
    out
}

/// `words` (separated by single spaces) folded into lines of at most [`TABLE_WIDTH`]
/// characters, the first after `first`, the others after `indent` spaces; a word longer than
/// a line stands alone on its line.
///
/// # Examples
/// ```
/// use bearing_ident::text::{TABLE_WIDTH, wrap};
/// let text = wrap("residuals:", &vec!["1.5e-15"; 40].join(" "), 2);
/// assert_eq!(text.lines().count(), 3);
/// assert!(text.lines().all(|l| l.chars().count() <= TABLE_WIDTH));
/// assert!(text.lines().nth(1).unwrap().starts_with("  1.5e-15"));
/// ```
pub fn wrap(first: &str, words: &str, indent: usize) -> String {
    let mut out = String::new();
    let mut line = first.to_owned();
    for word in words.split(' ').filter(|w| !w.is_empty()) {
        let blank = line.trim().is_empty();
        if !blank && line.chars().count() + 1 + word.chars().count() > TABLE_WIDTH {
            out.push_str(line.trim_end());
            out.push('\n');
            line = " ".repeat(indent);
        } else if !blank {
            line.push(' ');
        }
        line.push_str(word);
    }
    out.push_str(line.trim_end());
    out.push('\n');
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(cells: &[&str]) -> Vec<String> {
        cells.iter().map(|c| (*c).to_owned()).collect()
    }

    #[test]
    fn columns_align_and_groups_stay_whole() {
        let wide = "w".repeat(50);
        let rows = vec![
            row(&["key", "a", "b", &wide, "c"]),
            row(&["k2", "10", "2", "x"]),
        ];
        // Groups [a, b] and [wide, c] fit in one block; the short row's last cell is empty.
        let text = table(&rows, 1, &[2, 2], Align::Right, 0);
        assert_eq!(text.lines().count(), 2, "{text}");
        let want = format!(" k2  10  2  {}x", " ".repeat(49));
        assert_eq!(text.lines().nth(1).unwrap(), want);
        // With a wider first group the second moves whole into a block of its own: 2 + 3 + 2
        // + 55 + 2 + 55 is 119 characters, and 4 more would pass 120.
        let wide = "w".repeat(55);
        let rows = vec![
            row(&["key", &wide, &wide, "a", "b"]),
            row(&["k2", "1", "2", "3"]),
        ];
        let text = table(&rows, 1, &[2, 2], Align::Left, 2);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        assert_eq!(lines[2], "");
        assert_eq!(lines[3], "  key  a  b");
        assert_eq!(lines[4], "  k2   3");
        assert!(lines.iter().all(|l| l.chars().count() <= TABLE_WIDTH));
    }

    #[test]
    fn wrap_keeps_a_long_word_whole() {
        let long = "z".repeat(130);
        let text = wrap("first", &format!("a {long} b"), 4);
        assert_eq!(text, format!("first a\n    {long}\n    b\n"));
        assert_eq!(wrap("", "", 2), "\n");
    }
}
