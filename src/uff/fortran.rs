//! Fixed-width Fortran fields: reading `E`/`D` floats and integers, writing `Ew.d`.

/// A Fortran real field's value: blanks around it ignored, `D`/`d` exponents, an exponent
/// without its letter (`1.23456-105`, as Fortran writes three-digit exponents), an empty field
/// is `None`. Text that is not a number is `Err(())`.
pub(super) fn real(field: &[u8]) -> Result<Option<f64>, ()> {
    let field = field.trim_ascii();
    if field.is_empty() {
        return Ok(None);
    }
    if field.len() > 64 {
        return Err(());
    }
    let mut buf = [0u8; 72];
    let mut len = 0;
    let mut has_exp = false;
    for (i, &b) in field.iter().enumerate() {
        let c = match b {
            b'0'..=b'9' | b'.' => b,
            b'e' | b'E' | b'd' | b'D' | b'q' | b'Q' => {
                has_exp = true;
                b'e'
            }
            b'+' | b'-' => {
                // A sign after a digit or point, with no exponent letter yet, starts the exponent.
                if i > 0 && !has_exp && matches!(field[i - 1], b'0'..=b'9' | b'.') {
                    buf[len] = b'e';
                    len += 1;
                    has_exp = true;
                }
                b
            }
            _ => return Err(()),
        };
        buf[len] = c;
        len += 1;
    }
    let text = std::str::from_utf8(&buf[..len]).map_err(|_| ())?;
    text.parse::<f64>().map(Some).map_err(|_| ())
}

/// A Fortran integer field's value; an empty field is 0.
pub(super) fn integer(field: &[u8]) -> Result<i64, ()> {
    let field = field.trim_ascii();
    if field.is_empty() {
        return Ok(0);
    }
    if !field
        .iter()
        .enumerate()
        .all(|(i, b)| b.is_ascii_digit() || (i == 0 && matches!(b, b'+' | b'-')))
    {
        return Err(());
    }
    std::str::from_utf8(field)
        .map_err(|_| ())?
        .parse::<i64>()
        .map_err(|_| ())
}

/// The fields of `line` at the given widths, in order (missing ones at the end are empty).
pub(super) fn columns<'a>(line: &'a [u8], widths: &[usize]) -> Vec<&'a [u8]> {
    let mut at = 0;
    widths
        .iter()
        .map(|&w| {
            let start = at.min(line.len());
            let end = (at + w).min(line.len());
            at += w;
            &line[start..end]
        })
        .collect()
}

/// Appends the real values of one line of record 12 to `out`: the fields at the repeating
/// `widths` first; if one of them is not a number (or a blank field sits between values), the
/// line split at whitespace instead. `Err` holds the offending text.
pub(super) fn values(line: &[u8], widths: &[usize], out: &mut Vec<f64>) -> Result<(), String> {
    let start = out.len();
    let mut at = 0;
    let mut k = 0;
    let mut ok = true;
    let mut ended = false;
    while at < line.len() {
        let w = widths[k % widths.len()];
        let field = &line[at..(at + w).min(line.len())];
        match real(field) {
            Ok(Some(v)) if !ended => out.push(v),
            Ok(None) => ended = true,
            _ => {
                ok = false;
                break;
            }
        }
        at += w;
        k += 1;
    }
    if ok {
        return Ok(());
    }
    out.truncate(start);
    for token in line
        .split(|b| b.is_ascii_whitespace())
        .filter(|t| !t.is_empty())
    {
        match real(token) {
            Ok(Some(v)) => out.push(v),
            _ => return Err(crate::error::excerpt_bytes(token)),
        }
    }
    Ok(())
}

/// `v` as a Fortran `Ew.d` field, right-aligned in `width` characters: `d` digits after the
/// point, an exponent of at least two digits with its sign (`-1.73331E-04`).
pub(super) fn e_field(v: f64, d: usize, width: usize) -> String {
    let text = format!("{v:.d$e}");
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    format!(
        "{:>width$}",
        format!("{mantissa}E{sign}{:02}", exponent.unsigned_abs())
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_fortran_reals() {
        assert_eq!(real(b"  1.73331e-04"), Ok(Some(1.73331e-4)));
        assert_eq!(real(b" -1.5D+02"), Ok(Some(-150.0)));
        assert_eq!(real(b"1.23456-105"), Ok(Some(1.23456e-105)));
        assert_eq!(real(b"0.5+300"), Ok(Some(0.5e300)));
        assert_eq!(real(b"-2.0E-100"), Ok(Some(-2.0e-100)));
        assert_eq!(real(b"   "), Ok(None));
        assert_eq!(real(b"7"), Ok(Some(7.0)));
        assert!(real(b"NaN").is_err());
        assert!(real(b"1.0x").is_err());
        assert!(real(b"--1").is_err());
    }

    #[test]
    fn reads_integers() {
        assert_eq!(integer(b"   -12"), Ok(-12));
        assert_eq!(integer(b"     "), Ok(0));
        assert!(integer(b"1.5").is_err());
        assert!(integer(b"99999999999999999999999").is_err());
    }

    #[test]
    fn splits_touching_fields_and_falls_back_to_whitespace() {
        let mut out = Vec::new();
        values(b"-1.23450E-100-4.56000E+002  7.00000E+00", &[13], &mut out).unwrap();
        assert_eq!(out, [-1.2345e-100, -456.0, 7.0]);
        out.clear();
        values(b"1.5 2.5 -3", &[13], &mut out).unwrap();
        assert_eq!(out, [1.5, 2.5, -3.0]);
        out.clear();
        values(b"  1.00000E+00  2.00000E+00", &[13, 20], &mut out).unwrap();
        assert_eq!(out, [1.0, 2.0]);
        out.clear();
        assert!(values(b"  1.00000E+00 abc", &[13], &mut out).is_err());
    }

    #[test]
    fn writes_e_fields() {
        assert_eq!(e_field(1.73331e-4, 5, 13), "  1.73331E-04");
        assert_eq!(e_field(-1.5e-100, 5, 13), "-1.50000E-100");
        assert_eq!(e_field(0.0, 12, 20), "  0.000000000000E+00");
        assert_eq!(e_field(250.0, 5, 13), "  2.50000E+02");
    }
}
