//! The CIF tokenizer: a line's tags, values, `loop_` and `data_` words, quotes, text fields
//! and comments (CIF 1.1 syntax; Hall, Allen & Brown, Acta Cryst. A47 (1991) 655–685).

use crate::error::quote;

/// A CIF token.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Token<'t> {
    /// `_category.item`.
    Tag(&'t [u8]),
    /// A value: bare, quoted (quotes removed) or a text field.
    Value(&'t [u8]),
    /// `loop_`.
    Loop,
    /// `data_name`.
    Data,
}

/// Splits one line (not part of a text field) into tokens.
pub(super) fn tokens<'t>(line: &'t [u8], mut each: impl FnMut(Token<'t>) -> Result<(), String>) -> Result<(), String> {
    let mut i = 0;
    while i < line.len() {
        let Some(start) = line.get(i..).and_then(|rest| rest.iter().position(|b| !b.is_ascii_whitespace())) else {
            break;
        };
        i += start;
        let first = line.get(i).copied().unwrap_or(b' ');
        if first == b'#' {
            break;
        }
        if first == b'\'' || first == b'"' {
            // A quote ends a quoted value only when whitespace or the line's end follows it.
            let rest = line.get(i + 1..).unwrap_or_default();
            let close = rest
                .iter()
                .enumerate()
                .position(|(k, &b)| b == first && rest.get(k + 1).is_none_or(u8::is_ascii_whitespace))
                .ok_or_else(|| format!("unterminated quoted value {}", quote(line.get(i..).unwrap_or_default())))?;
            each(Token::Value(rest.get(..close).unwrap_or_default()))?;
            i += close + 2;
            continue;
        }
        let rest = line.get(i..).unwrap_or_default();
        let len = rest.iter().position(u8::is_ascii_whitespace).unwrap_or(rest.len());
        let word = rest.get(..len).unwrap_or_default();
        i += len;
        let lower = |prefix: &[u8]| {
            word.len() >= prefix.len() && word.get(..prefix.len()).is_some_and(|w| w.eq_ignore_ascii_case(prefix))
        };
        let token = if first == b'_' {
            Token::Tag(word)
        } else if word.eq_ignore_ascii_case(b"loop_") {
            Token::Loop
        } else if lower(b"data_") {
            Token::Data
        } else if lower(b"save_") || lower(b"global_") || lower(b"stop_") {
            return Err(format!("{} (save frames and global blocks are not read)", quote(word)));
        } else {
            Token::Value(word)
        };
        each(token)?;
    }
    Ok(())
}

/// `?` (unknown) and `.` (inapplicable) both mean no value.
pub(super) fn is_null(value: &[u8]) -> bool {
    matches!(value, b"?" | b".")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all_tokens(line: &str) -> Result<Vec<String>, String> {
        let mut out = Vec::new();
        tokens(line.as_bytes(), |t| {
            out.push(match t {
                Token::Tag(t) => format!("tag {}", String::from_utf8_lossy(t)),
                Token::Value(v) => format!("value {}", String::from_utf8_lossy(v)),
                Token::Loop => "loop".to_owned(),
                Token::Data => "data".to_owned(),
            });
            Ok(())
        })?;
        Ok(out)
    }

    #[test]
    fn the_tokenizer_knows_quotes_comments_and_reserved_words() {
        assert_eq!(
            all_tokens("loop_ _a.b 'it''s' \"x y\" O5' # comment").unwrap(),
            ["loop", "tag _a.b", "value it''s", "value x y", "value O5'"],
            "a quote inside a value does not end it unless whitespace follows"
        );
        assert_eq!(all_tokens("data_1TII").unwrap(), ["data"], "data block");
        assert!(all_tokens("'open").unwrap_err().contains("unterminated"), "unterminated quote");
        assert!(all_tokens("save_frame").unwrap_err().contains("save frames"), "save frames refused");
    }
}
