//! RON's lexical grammar as pure functions over text: whitespace, identifiers (raw ones
//! too), numbers (every base, `_` separators, type suffixes) and strings (escapes, line
//! continuations, raw strings). Each scanner returns what it read and how many bytes it
//! used, or where and why it failed; [`super::parse`] turns that into nodes and positions.
//!
//! The rules follow the `ron` crate 0.12 (`ron::parse`), so that sinew accepts and reads
//! every value RON does, except on purpose: non-finite numbers (`inf`, `NaN`), character
//! and byte literals and ranges have no use in a rig and are refused with a message.

use unicode_ident::{is_xid_continue, is_xid_start};

/// A scanning failure: the byte offset (from where the scan started) it points at, the
/// message and a fix hint.
#[derive(Debug)]
pub struct LexError {
    /// Offset from the start of the scanned token, in bytes.
    pub at: usize,
    /// What is wrong.
    pub message: String,
    /// How to fix it.
    pub hint: &'static str,
}

fn fail<T>(at: usize, message: impl Into<String>, hint: &'static str) -> Result<T, LexError> {
    Err(LexError {
        at,
        message: message.into(),
        hint,
    })
}

/// RON's whitespace: space, tab, line feed, carriage return, U+000B, U+000C, U+0085,
/// U+200E, U+200F, U+2028 and U+2029.
pub fn is_whitespace(c: char) -> bool {
    matches!(
        c,
        ' ' | '\t' | '\n' | '\r' | '\x0B' | '\x0C' | '\u{85}' | '\u{200E}' | '\u{200F}' | '\u{2028}' | '\u{2029}'
    )
}

/// The first character of an identifier (`_` or Unicode XID_Start).
pub fn is_ident_start(c: char) -> bool {
    c == '_' || is_xid_start(c)
}

/// A later character of an identifier (Unicode XID_Continue).
pub fn is_ident_continue(c: char) -> bool {
    is_xid_continue(c)
}

/// A character of a raw identifier after `r#` (XID_Continue, `.`, `+`, `-`).
pub fn is_raw_ident_char(c: char) -> bool {
    matches!(c, '.' | '+' | '-') || is_xid_continue(c)
}

/// Describes the character `c` for a message: itself in backquotes when it is visible,
/// else its code point and name, so an invisible character never appears bare.
pub fn describe_char(c: char) -> String {
    let name = match c {
        '\u{FEFF}' => Some("byte order mark"),
        '\u{200B}' => Some("zero width space"),
        '\u{200C}' => Some("zero width non-joiner"),
        '\u{200D}' => Some("zero width joiner"),
        '\u{00A0}' => Some("no-break space"),
        '\u{00AD}' => Some("soft hyphen"),
        '\u{2060}' => Some("word joiner"),
        _ => None,
    };
    let invisible = c.is_control() || c.is_whitespace() || name.is_some() || ('\u{2000}'..='\u{206F}').contains(&c);
    match (invisible, name) {
        (false, _) => format!("`{c}`"),
        (true, Some(n)) => format!("the invisible character U+{:04X} ({n})", c as u32),
        (true, None) => format!("the invisible character U+{:04X}", c as u32),
    }
}

/// An identifier at the start of `s`: `name` or `r#name`. Returns the name (without
/// `r#`) and the bytes used, or `None` when `s` does not start with one (a raw string
/// `r"..."`/`r#"..."#` is not an identifier).
pub fn ident(s: &str) -> Option<(&str, usize)> {
    if ["r\"", "r#\"", "r##"].iter().any(|p| s.starts_with(p)) {
        return None;
    }
    if let Some(rest) = s.strip_prefix("r#") {
        let len = rest.find(|c| !is_raw_ident_char(c)).unwrap_or(rest.len());
        return (len > 0).then(|| (&rest[..len], len + 2));
    }
    let first = s.chars().next()?;
    if !is_ident_start(first) {
        return None;
    }
    let len = first.len_utf8()
        + s[first.len_utf8()..]
            .find(|c| !is_ident_continue(c))
            .unwrap_or(s.len() - first.len_utf8());
    Some((&s[..len], len))
}

/// A scanned number.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Number {
    /// An integer that fits an i64.
    Int(i64),
    /// Any other number (floats, and integers beyond i64 as RON reads them).
    Float(f64),
}

fn is_int_char(c: char) -> bool {
    c.is_ascii_hexdigit() || c == '_'
}

fn is_float_char(c: char) -> bool {
    c.is_ascii_digit() || matches!(c, 'e' | 'E' | '.' | '+' | '-' | '_')
}

/// Whether `s` starts with `word` followed by no identifier character.
fn word_at(s: &str, word: &str) -> bool {
    s.strip_prefix(word)
        .is_some_and(|r| !r.chars().next().is_some_and(is_ident_continue))
}

const NON_FINITE_HINT: &str = "sinew refuses non-finite numbers (inf, NaN): give a finite number";

/// Whether `s` (after an optional sign) spells a non-finite number: `inf`, `NaN`,
/// optionally with an `f32`/`f64` suffix.
pub fn is_non_finite_word(s: &str) -> bool {
    ["inf", "NaN"].iter().any(|w| {
        s.strip_prefix(w)
            .is_some_and(|r| word_at(r, "") || word_at(r, "f32") || word_at(r, "f64"))
    })
}

/// A number at the start of `s` (RON's integer and float grammar): optional sign;
/// integers in decimal, `0x`, `0o` or `0b` with `_` separators and an optional
/// `i8`..`i64`/`u8`..`u64` suffix (range-checked); floats with fraction and/or exponent
/// and an optional `f32`/`f64` suffix (an `f32` is read as f32 and widened). `-0` reads
/// as `-0.0`, as RON reads it into a float. Integers beyond the range of u64 read as
/// floats, as in RON.
pub fn number(s: &str) -> Result<(Number, usize), LexError> {
    let sign_len = usize::from(s.starts_with(['+', '-']));
    let negative = s.starts_with('-');
    let body = &s[sign_len..];
    if is_non_finite_word(body) {
        return fail(0, "numbers must be finite", NON_FINITE_HINT);
    }
    let run = |f: fn(char) -> bool| body.find(|c| !f(c)).unwrap_or(body.len());
    let float_run = run(is_float_char);
    let float_len = body[..float_run].find("..").unwrap_or(float_run);
    if float_len > run(is_int_char) {
        return float(s, sign_len).map(|(x, n)| (Number::Float(x), n));
    }
    match integer(body, negative) {
        Ok((n, len)) => Ok((n, sign_len + len)),
        Err(e) => match float(s, sign_len) {
            // RON reads what the integer grammar refuses as a float when the float
            // grammar gets at least as far (`1e5`, `1f32`, integers beyond u64).
            Ok((x, n)) if n >= sign_len + e.at => Ok((Number::Float(x), n)),
            Err(f) if f.message.contains("finite") => Err(f),
            _ => Err(LexError {
                at: sign_len + e.at,
                ..e
            }),
        },
    }
}

fn integer(body: &str, negative: bool) -> Result<(Number, usize), LexError> {
    let (base, prefix) = match body.get(..2) {
        Some("0b") => (2u32, 2usize),
        Some("0o") => (8, 2),
        Some("0x") => (16, 2),
        _ => (10, 0),
    };
    let digits = &body[prefix..];
    let len = digits.find(|c| !is_int_char(c)).unwrap_or(digits.len());
    if len == 0 {
        return fail(prefix, "expected digits", "write numbers like 1, -0.5, 0x1F or 2.5e-3");
    }
    if digits.starts_with('_') {
        return fail(
            prefix,
            "a number cannot start with `_`",
            "write separators between digits: 1_000",
        );
    }
    // Accumulate the magnitude in u128 (enough for every suffix); refuse digits of the
    // wrong base where they are.
    let mut mag: u128 = 0;
    for (i, c) in digits[..len].char_indices() {
        if c == '_' {
            continue;
        }
        let d = c.to_digit(16).unwrap_or(99);
        if d >= base {
            return fail(
                prefix + i,
                format!("`{c}` is not a digit in base {base}"),
                "write numbers like 1, -0.5, 0x1F or 2.5e-3",
            );
        }
        mag = mag * u128::from(base) + u128::from(d);
        if mag > u128::from(u64::MAX) + 1 {
            return fail(prefix + len, "integer out of range", "integers must fit 64 bits");
        }
    }
    let rest = &digits[len..];
    let suffixes: [(&str, i128, i128); 8] = [
        ("i8", i8::MIN.into(), i8::MAX.into()),
        ("i16", i16::MIN.into(), i16::MAX.into()),
        ("i32", i32::MIN.into(), i32::MAX.into()),
        ("i64", i64::MIN.into(), i64::MAX.into()),
        ("u8", 0, u8::MAX.into()),
        ("u16", 0, u16::MAX.into()),
        ("u32", 0, u32::MAX.into()),
        ("u64", 0, u64::MAX.into()),
    ];
    let value = if negative { -(mag as i128) } else { mag as i128 };
    let used = prefix + len;
    let suffix = match rest.as_bytes().first() {
        Some(b'i' | b'u') => suffixes.iter().find(|(sfx, ..)| word_at(rest, sfx)),
        _ => None,
    };
    if let Some(&(suffix, lo, hi)) = suffix {
        if value < lo || value > hi || (negative && mag != 0 && lo == 0) {
            // Past the suffix, as RON's cursor: no float reading gets that far.
            return fail(
                used + suffix.len(),
                format!("integer out of range for `{suffix}`"),
                "give a value the suffix's type can hold",
            );
        }
        return Ok((to_number(value, negative), used + suffix.len()));
    }
    if value < i128::from(i64::MIN) || value > i128::from(u64::MAX) {
        return fail(used, "integer out of range", "integers must fit 64 bits");
    }
    Ok((to_number(value, negative), used))
}

fn to_number(value: i128, negative: bool) -> Number {
    match i64::try_from(value) {
        Ok(0) if negative => Number::Float(-0.0),
        Ok(i) => Number::Int(i),
        Err(_) => Number::Float(value as f64),
    }
}

/// A float at `s[sign_len..]` (the sign included in the value): RON's float characters,
/// `_` separators (not first, not after `.`), then Rust's `f64` grammar, then an optional
/// `f32`/`f64` suffix.
fn float(s: &str, sign_len: usize) -> Result<(f64, usize), LexError> {
    let body = &s[sign_len..];
    let run = body.find(|c| !is_float_char(c)).unwrap_or(body.len());
    let len = body[..run].find("..").unwrap_or(run);
    if len == 0 {
        return fail(sign_len, "expected a number", "write numbers like 1, -0.5 or 2.5e-3");
    }
    let mut text = String::with_capacity(len + 1);
    text.push_str(&s[..sign_len]);
    let mut allow_underscore = false;
    for (i, c) in body[..len].char_indices() {
        match c {
            '_' if allow_underscore => continue,
            '_' => return fail(sign_len + i, "misplaced `_` in a number", "put `_` only between digits"),
            '0'..='9' | 'e' | 'E' => allow_underscore = true,
            '.' => allow_underscore = false,
            _ => {}
        }
        text.push(c);
    }
    let rest = &body[len..];
    let bad = || LexError {
        at: 0,
        message: format!("`{}` is not a number", &s[..sign_len + len]),
        hint: "write numbers like 1, -0.5 or 2.5e-3",
    };
    let (value, used) = if word_at(rest, "f32") {
        let v = text.parse::<f32>().map_err(|_| bad())?;
        (f64::from(v), len + 3)
    } else if word_at(rest, "f64") {
        (text.parse::<f64>().map_err(|_| bad())?, len + 3)
    } else {
        (text.parse::<f64>().map_err(|_| bad())?, len)
    };
    if !value.is_finite() {
        return fail(
            0,
            format!("`{}` is not a finite number", &s[..sign_len + used]),
            "give a number within the range of f64",
        );
    }
    Ok((value, sign_len + used))
}

/// A string literal at the start of `s` (which starts with `"`): escapes `\\ \" \' \n \r
/// \t \0`, `\xHH` (a run of them forming one UTF-8 character), `\u{H..}` (1 to 6 hex
/// digits) and `\` before a line break (the break and the next line's leading spaces are
/// skipped). Returns the content, whether the source text between the quotes is the
/// content itself, and the bytes used.
pub fn string(s: &str) -> Result<(String, bool, usize), LexError> {
    let mut out = String::new();
    let mut exact = true;
    let mut i = 1;
    let bytes = s.as_bytes();
    loop {
        let Some(rel) = s[i..].find(['"', '\\', '\n']) else {
            return fail(0, "unterminated string", "close the string with `\"`");
        };
        out.push_str(&s[i..i + rel]);
        i += rel;
        match bytes[i] {
            b'"' => return Ok((out, exact, i + 1)),
            b'\n' => {
                exact = false;
                out.push('\n');
                i += 1;
            }
            _ => {
                exact = false;
                let (c, used) = escape(&s[i..]).map_err(|e| LexError { at: i + e.at, ..e })?;
                if let Some(c) = c {
                    out.push(c);
                }
                i += used;
            }
        }
    }
}

const ESCAPE_HINT: &str = "escapes are \\n \\r \\t \\0 \\\\ \\\" \\' \\x41 \\u{41}, and \\ before a line break";

/// One escape at the start of `s` (which starts with `\`): the character (none for a line
/// continuation) and the bytes used.
fn escape(s: &str) -> Result<(Option<char>, usize), LexError> {
    let simple = |c| Ok((Some(c), 2));
    match s.as_bytes().get(1) {
        Some(b'n') => simple('\n'),
        Some(b'\r') if s[2..].starts_with('\n') => Ok((None, continuation(s, 3))),
        Some(b'r') => simple('\r'),
        Some(b't') => simple('\t'),
        Some(b'0') => simple('\0'),
        Some(b'\\') => simple('\\'),
        Some(b'"') => simple('"'),
        Some(b'\'') => simple('\''),
        Some(b'\n') => Ok((None, continuation(s, 2))),
        Some(b'x') => {
            let mut buf = Vec::new();
            let mut i = 0;
            while buf.len() < 4 {
                if !s[i..].starts_with("\\x") {
                    return fail(i, "a `\\x` escape above 7F must continue a UTF-8 sequence", ESCAPE_HINT);
                }
                let Some(b) = s.get(i + 2..i + 4).and_then(|h| u8::from_str_radix(h, 16).ok()) else {
                    return fail(i, "malformed `\\x` escape: it takes two hex digits", ESCAPE_HINT);
                };
                buf.push(b);
                i += 4;
                if let Ok(t) = std::str::from_utf8(&buf) {
                    return Ok((t.chars().next(), i));
                }
            }
            fail(0, "the `\\x` escapes do not form a UTF-8 character", ESCAPE_HINT)
        }
        Some(b'u') => {
            if s.as_bytes().get(2) != Some(&b'{') {
                return fail(0, "malformed `\\u` escape", ESCAPE_HINT);
            }
            let hex_len = s[3..].find(|c: char| !c.is_ascii_hexdigit()).unwrap_or(s.len() - 3);
            if hex_len == 0 || hex_len > 6 || s.as_bytes().get(3 + hex_len) != Some(&b'}') {
                return fail(0, "malformed `\\u{..}` escape: it takes 1 to 6 hex digits", ESCAPE_HINT);
            }
            match u32::from_str_radix(&s[3..3 + hex_len], 16)
                .ok()
                .and_then(char::from_u32)
            {
                Some(c) => Ok((Some(c), 4 + hex_len)),
                None => fail(0, "invalid unicode escape (not a character)", ESCAPE_HINT),
            }
        }
        _ => fail(0, "unknown escape in string", ESCAPE_HINT),
    }
}

/// After `\` and a line break of `at` bytes: skips the following spaces, tabs and line
/// breaks (RON's string continuation).
fn continuation(s: &str, at: usize) -> usize {
    at + s[at..]
        .find(|c| !matches!(c, ' ' | '\t' | '\n' | '\r'))
        .unwrap_or(s.len() - at)
}

/// A raw string at the start of `s` (`r"..."`, `r#"..."#`, ...): the content and the
/// bytes used.
pub fn raw_string(s: &str) -> Result<(String, usize), LexError> {
    let hashes = s[1..].find(|c| c != '#').unwrap_or(s.len() - 1);
    if !s[1 + hashes..].starts_with('"') {
        return fail(0, "malformed raw string", "write raw strings as r\"..\" or r#\"..\"#");
    }
    let start = 2 + hashes;
    let end = format!("\"{}", "#".repeat(hashes));
    match s[start..].find(&end) {
        Some(k) => Ok((s[start..start + k].to_string(), start + k + end.len())),
        None => fail(
            0,
            "unterminated raw string",
            "close it with `\"` and as many `#` as it opened with",
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn num(s: &str) -> Number {
        number(s).unwrap_or_else(|e| panic!("{s}: {e:?}")).0
    }

    #[test]
    fn numbers_in_every_form() {
        assert_eq!(num("0x18"), Number::Int(24));
        assert_eq!(num("0o30"), Number::Int(24));
        assert_eq!(num("0b11"), Number::Int(3));
        assert_eq!(num("-0x18"), Number::Int(-24));
        assert_eq!(num("24i64"), Number::Int(24));
        assert_eq!(num("1_000"), Number::Int(1000));
        assert_eq!(num("24.0f64"), Number::Float(24.0));
        assert_eq!(num("0.1f32"), Number::Float(f64::from(0.1f32)));
        assert_eq!(num("1e5"), Number::Float(1e5));
        assert_eq!(num("1f32"), Number::Float(1.0));
        assert_eq!(num("2.5e-3"), Number::Float(2.5e-3));
        assert_eq!(num(".5"), Number::Float(0.5));
        assert_eq!(num("1."), Number::Float(1.0));
        assert!(matches!(num("-0"), Number::Float(x) if x == 0.0 && x.is_sign_negative()));
        assert_eq!(num("18446744073709551615"), Number::Float(18446744073709551615.0));
        assert!(number("300u8").is_err());
        assert!(number("-1u8").is_err());
        assert!(number("0b12").is_err());
        assert!(number("0x_1").is_err());
        assert!(number("1._5").is_err());
        assert!(number("NaN").is_err());
        assert!(number("-inf").is_err());
        assert!(number("1e999").is_err());
    }

    #[test]
    fn strings_with_every_escape() {
        let s = |t: &str| string(t).unwrap_or_else(|e| panic!("{t}: {e:?}")).0;
        assert_eq!(s(r#""\x61b""#), "ab");
        assert_eq!(s(r#""\xC3\xA9""#), "é");
        assert_eq!(s("\"a\\\n    b\""), "ab");
        assert_eq!(s(r#""\u{1F600}\t""#), "😀\t");
        assert!(string(r#""\q""#).is_err());
        assert!(string(r#""\xC3""#).is_err());
        assert_eq!(raw_string(r###"r#"a"b"#"###).unwrap().0, "a\"b");
    }

    #[test]
    fn identifiers_raw_and_unicode() {
        assert_eq!(ident("r#joint(").unwrap(), ("joint", 7));
        assert_eq!(ident("héllo x").unwrap(), ("héllo", 6));
        assert!(ident("r\"x\"").is_none());
        assert!(describe_char('\u{200B}').contains("U+200B"));
        assert_eq!(describe_char('x'), "`x`");
    }
}
