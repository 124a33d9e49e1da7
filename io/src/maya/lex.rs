//! The tokenizer of the Maya ASCII reader: words, quoted strings and punctuation, each a
//! byte span of the source, so reading a 1 MB scene allocates one token vector and nothing
//! per token. Positions become `line:col` only when a message needs them ([`LineIndex`]).
//!
//! MEL as Maya writes it: tokens are separated by white space; `"..."` strings use the C
//! escapes `\"`, `\\`, `\n`, `\t`, `\r`; `//` starts a comment to the end of the line and
//! `/* ... */` a block comment; `;` ends a statement; `{`, `}`, `,` appear in
//! `attributeAlias` values, `(`, `)` around long strings that Maya splits into pieces joined
//! by `+`. Everything else up to the next separator is a word (command and flag names,
//! numbers, `yes`/`no`, node names without quotes such as `:time1`).

use std::borrow::Cow;

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokKind {
    /// A bare word: a command, a flag (`-n`), a number, `yes`, a name.
    Word,
    /// A double-quoted string (the span includes the quotes).
    Str,
    /// `;`
    Semi,
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `,`
    Comma,
    /// `(`
    LParen,
    /// `)`
    RParen,
}

/// One token: its kind and its byte span in the source.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tok {
    /// Kind.
    pub kind: TokKind,
    /// Byte offset of the first character.
    pub start: u32,
    /// Byte offset one past the last character.
    pub end: u32,
}

impl Tok {
    /// The token's text as written (strings with their quotes and escapes).
    pub fn raw<'a>(&self, src: &'a str) -> &'a str {
        src.get(self.start as usize..self.end as usize).unwrap_or("")
    }

    /// The token's value: a word as written, a string without quotes and with escapes
    /// decoded (borrowed when it has none).
    pub fn text<'a>(&self, src: &'a str) -> Cow<'a, str> {
        let raw = self.raw(src);
        if self.kind != TokKind::Str {
            return Cow::Borrowed(raw);
        }
        let inner = raw.get(1..raw.len().saturating_sub(1)).unwrap_or("");
        if !inner.contains('\\') {
            return Cow::Borrowed(inner);
        }
        let mut out = String::with_capacity(inner.len());
        let mut chars = inner.chars();
        while let Some(c) = chars.next() {
            if c != '\\' {
                out.push(c);
                continue;
            }
            match chars.next() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some('r') => out.push('\r'),
                Some(other) => out.push(other),
                None => out.push('\\'),
            }
        }
        Cow::Owned(out)
    }
}

/// A tokenizing error: an unterminated string or comment, at a byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LexError {
    /// Byte offset where the problem starts.
    pub offset: u32,
    /// What is wrong.
    pub message: String,
}

fn is_separator(b: u8) -> bool {
    matches!(
        b,
        b' ' | b'\t' | b'\n' | b'\r' | b';' | b'"' | b'{' | b'}' | b',' | b'(' | b')'
    )
}

/// Splits `src` into tokens. Fails on an unterminated string or block comment (a truncated
/// file), or on a source of 4 GiB or more.
pub fn lex(src: &str) -> Result<Vec<Tok>, LexError> {
    let bytes = src.as_bytes();
    if u32::try_from(bytes.len()).is_err() {
        return Err(LexError {
            offset: 0,
            message: "file is 4 GiB or larger; split the scene".into(),
        });
    }
    let mut toks = Vec::with_capacity(bytes.len() / 6);
    let mut i = 0usize;
    let n = bytes.len();
    while i < n {
        let b = bytes[i];
        match b {
            b' ' | b'\t' | b'\n' | b'\r' => i += 1,
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                while i < n && bytes[i] != b'\n' {
                    i += 1;
                }
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                let start = i;
                i += 2;
                loop {
                    if i + 1 >= n {
                        return Err(LexError {
                            offset: start as u32,
                            message: "block comment `/*` is never closed (the file may be truncated)".into(),
                        });
                    }
                    if bytes[i] == b'*' && bytes[i + 1] == b'/' {
                        i += 2;
                        break;
                    }
                    i += 1;
                }
            }
            b'"' => {
                let start = i;
                i += 1;
                loop {
                    match bytes.get(i) {
                        None => {
                            return Err(LexError {
                                offset: start as u32,
                                message: "string is never closed with `\"` (the file may be truncated)".into(),
                            })
                        }
                        Some(b'\\') => i += 2,
                        Some(b'"') => {
                            i += 1;
                            break;
                        }
                        Some(_) => i += 1,
                    }
                }
                let end = i.min(n);
                toks.push(Tok {
                    kind: TokKind::Str,
                    start: start as u32,
                    end: end as u32,
                });
            }
            b';' | b'{' | b'}' | b',' | b'(' | b')' => {
                let kind = match b {
                    b';' => TokKind::Semi,
                    b'{' => TokKind::LBrace,
                    b'}' => TokKind::RBrace,
                    b',' => TokKind::Comma,
                    b'(' => TokKind::LParen,
                    _ => TokKind::RParen,
                };
                toks.push(Tok {
                    kind,
                    start: i as u32,
                    end: i as u32 + 1,
                });
                i += 1;
            }
            _ => {
                let start = i;
                while i < n && !is_separator(bytes[i]) {
                    i += 1;
                }
                toks.push(Tok {
                    kind: TokKind::Word,
                    start: start as u32,
                    end: i as u32,
                });
            }
        }
    }
    Ok(toks)
}

/// Byte offsets of line starts, to turn a byte offset into `line:col` (both from 1; the
/// column counts characters, as editors do).
#[derive(Clone, Debug)]
pub struct LineIndex {
    starts: Vec<u32>,
}

impl LineIndex {
    /// Indexes `src`.
    pub fn new(src: &str) -> Self {
        let mut starts = Vec::with_capacity(src.len() / 40 + 1);
        starts.push(0);
        // `match_indices` with a char finds the newlines with memchr (word at a time).
        starts.extend(src.match_indices('\n').map(|(i, _)| i as u32 + 1));
        LineIndex { starts }
    }

    /// `(line, column)` of byte `offset` in `src` (the text this index was built from).
    pub fn line_col(&self, src: &str, offset: u32) -> (u32, u32) {
        let line = match self.starts.binary_search(&offset) {
            Ok(l) => l,
            Err(l) => l.saturating_sub(1),
        };
        let start = self.starts.get(line).copied().unwrap_or(0) as usize;
        let end = (offset as usize).min(src.len());
        let col = src
            .get(start..end)
            .map_or(end.saturating_sub(start), |s| s.chars().count());
        (line as u32 + 1, col as u32 + 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<(TokKind, String)> {
        lex(src)
            .unwrap()
            .iter()
            .map(|t| (t.kind, t.text(src).into_owned()))
            .collect()
    }

    #[test]
    fn words_strings_and_punctuation() {
        use TokKind::*;
        let src = "setAttr \".t\" -type \"double3\" 1 -2.5e-3 3 ;// comment\n{\"a\",\"b\\\"c\"}";
        assert_eq!(
            kinds(src),
            vec![
                (Word, "setAttr".into()),
                (Str, ".t".into()),
                (Word, "-type".into()),
                (Str, "double3".into()),
                (Word, "1".into()),
                (Word, "-2.5e-3".into()),
                (Word, "3".into()),
                (Semi, ";".into()),
                (LBrace, "{".into()),
                (Str, "a".into()),
                (Comma, ",".into()),
                (Str, "b\"c".into()),
                (RBrace, "}".into()),
            ]
        );
    }

    #[test]
    fn comments_are_skipped_and_unterminated_things_fail() {
        assert_eq!(
            kinds("a /* x ; y */ b"),
            vec![(TokKind::Word, "a".into()), (TokKind::Word, "b".into())]
        );
        assert_eq!(lex("a \"open").unwrap_err().offset, 2);
        assert_eq!(lex("a /* open").unwrap_err().offset, 2);
        assert_eq!(lex("\"ends in escape\\").unwrap_err().offset, 0);
    }

    #[test]
    fn line_and_column() {
        let src = "ab\ncdé f\n";
        let idx = LineIndex::new(src);
        assert_eq!(idx.line_col(src, 0), (1, 1));
        assert_eq!(idx.line_col(src, 3), (2, 1));
        // 'f' is at byte 8 (é takes two bytes) but at column 5.
        assert_eq!(idx.line_col(src, 8), (2, 5));
        assert_eq!(idx.line_col(src, 100), (3, 1));
    }
}
