//! Pieces of a line: fixed columns and numbers, checked.

use std::ops::Range;

/// Columns `range` (0-based, end exclusive) of `line`, cut to what the line holds: a short
/// line gives a short or empty field, never a panic.
#[inline]
pub(crate) fn columns(line: &[u8], range: Range<usize>) -> &[u8] {
    let end = range.end.min(line.len());
    line.get(range.start.min(end)..end).unwrap_or_default()
}

/// The number in `field` (surrounding spaces ignored), or why it is not one.
#[inline]
pub(crate) fn parse_f32(field: &[u8]) -> Result<f32, &'static str> {
    let text = std::str::from_utf8(field).map_err(|_| "not text")?.trim_ascii();
    if text.is_empty() {
        return Err("empty");
    }
    let value: f32 = text.parse().map_err(|_| "not a number")?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err("not finite")
    }
}

/// Like [`parse_f32`], in double precision (for values scaled or composed before use).
#[inline]
pub(crate) fn parse_f64(field: &[u8]) -> Result<f64, &'static str> {
    let text = std::str::from_utf8(field).map_err(|_| "not text")?.trim_ascii();
    if text.is_empty() {
        return Err("empty");
    }
    let value: f64 = text.parse().map_err(|_| "not a number")?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err("not finite")
    }
}

/// The value in an optional `field` of `what` (record, field): `None` when blank, and `None`
/// with a warning on `line` when `parse` cannot read it (a bad B-factor does not lose the
/// atom).
pub(crate) fn optional<T>(
    atoms: &mut crate::molecule::Builder<'_>,
    (record, name): (&'static str, &'static str),
    field: &[u8],
    line: u64,
    parse: impl FnOnce(&str) -> Option<T>,
) -> Option<T> {
    let text = std::str::from_utf8(field).ok().map(str::trim_ascii);
    match text {
        Some("") => None,
        Some(text) => parse(text).or_else(|| {
            atoms.warn(line, || format!("{record} {name} {:?} is not a number: none kept", crate::error::quote(field)));
            None
        }),
        None => {
            atoms.warn(line, || format!("{record} {name} {:?} is not text: none kept", crate::error::quote(field)));
            None
        }
    }
}

/// `text` as a finite `f32`, for [`optional`].
pub(crate) fn finite(text: &str) -> Option<f32> {
    text.parse::<f32>().ok().filter(|v| v.is_finite())
}

/// The whole non-negative number in `field` (surrounding spaces ignored), or why it is not one.
pub(crate) fn parse_count(field: &[u8]) -> Result<u64, &'static str> {
    let text = std::str::from_utf8(field).map_err(|_| "not text")?.trim_ascii();
    if text.is_empty() {
        return Err("empty");
    }
    text.parse().map_err(|_| "not a whole number")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_never_reach_past_the_line() {
        assert_eq!(columns(b"ATOM      1", 6..11), b"    1", "inside");
        assert_eq!(columns(b"ATOM  ", 4..11), b"  ", "cut at the end");
        assert_eq!(columns(b"ATOM", 30..38), b"", "beyond the end");
    }

    #[test]
    fn numbers_are_checked() {
        assert_eq!(parse_f32(b"  -9.336"), Ok(-9.336), "spaces around");
        assert_eq!(parse_f32(b"12.3a4"), Err("not a number"), "letters");
        assert_eq!(parse_f32(b"        "), Err("empty"), "blank");
        assert_eq!(parse_f32(b"inf"), Err("not finite"), "infinity is refused");
        assert_eq!(parse_f32(b"NaN"), Err("not finite"), "NaN is refused");
        assert_eq!(parse_f32(b"1e39"), Err("not finite"), "beyond f32 is refused");
        assert_eq!(parse_f32(&[b'1', 0xff]), Err("not text"), "bytes that are not UTF-8");
        assert_eq!(parse_count(b" 5684 "), Ok(5684), "a count");
        assert_eq!(parse_count(b"-1"), Err("not a whole number"), "negative");
        assert_eq!(parse_f64(b"0.808320"), Ok(0.808_32), "double");
    }
}
