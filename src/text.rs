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
