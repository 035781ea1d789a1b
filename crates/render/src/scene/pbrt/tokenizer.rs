//! Splitting a pbrt-v4 file into tokens, each with its 1-based line.
//!
//! The format (pbrt-v4's file-format reference): `#` starts a comment that
//! runs to the end of the line (outside strings); strings are enclosed in
//! double quotes and may contain the escapes `\"`, `\\`, `\n`, `\t`, `\r`,
//! `\b` and `\f`; `[` and `]` delimit value lists; everything else is a word
//! (a directive name, a number, or `true`/`false`) separated by white space,
//! quotes, brackets or comments.

use crate::scene::loader::SceneFileError;
use std::path::Path;

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TokenKind {
    /// A directive name, a number or a bare boolean.
    Word,
    /// A quoted string (the text is the string's content, escapes resolved).
    String,
    /// `[`.
    OpenBracket,
    /// `]`.
    CloseBracket,
}

/// One token and where it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    pub text: String,
    /// 1-based line of the token's first character.
    pub line: u32,
}

impl Token {
    /// How the token reads in an error message.
    pub fn describe(&self) -> String {
        match self.kind {
            TokenKind::Word => format!("'{}'", self.text),
            TokenKind::String => format!("the string \"{}\"", self.text),
            TokenKind::OpenBracket => "'['".into(),
            TokenKind::CloseBracket => "']'".into(),
        }
    }
}

fn syntax_error(file: &Path, line: u32, message: String) -> SceneFileError {
    SceneFileError::Syntax {
        file: file.to_path_buf(),
        line,
        message,
    }
}

/// Splits `bytes`, the contents of `file`, into tokens. Fails on text that is
/// not UTF-8, an unterminated string or an unknown escape.
pub fn tokenize(bytes: &[u8], file: &Path) -> Result<Vec<Token>, SceneFileError> {
    let source = std::str::from_utf8(bytes).map_err(|error| {
        let line = 1 + bytes[..error.valid_up_to()]
            .iter()
            .filter(|&&b| b == b'\n')
            .count() as u32;
        syntax_error(file, line, "the file is not UTF-8 text".into())
    })?;
    let mut tokens = Vec::new();
    let mut line = 1u32;
    let mut characters = source.chars().peekable();
    while let Some(&character) = characters.peek() {
        match character {
            '\n' => {
                line += 1;
                characters.next();
            }
            c if c.is_whitespace() => {
                characters.next();
            }
            '#' => {
                while let Some(&c) = characters.peek() {
                    if c == '\n' {
                        break;
                    }
                    characters.next();
                }
            }
            '[' | ']' => {
                characters.next();
                tokens.push(Token {
                    kind: if character == '[' {
                        TokenKind::OpenBracket
                    } else {
                        TokenKind::CloseBracket
                    },
                    text: character.to_string(),
                    line,
                });
            }
            '"' => {
                characters.next();
                let start_line = line;
                let mut text = String::new();
                loop {
                    match characters.next() {
                        None => {
                            return Err(syntax_error(
                                file,
                                start_line,
                                "unterminated string (expected a closing '\"')".into(),
                            ));
                        }
                        Some('"') => break,
                        Some('\n') => {
                            return Err(syntax_error(
                                file,
                                start_line,
                                "a string runs past the end of its line (expected a closing '\"')"
                                    .into(),
                            ));
                        }
                        Some('\\') => {
                            let escaped = match characters.next() {
                                Some('"') => '"',
                                Some('\\') => '\\',
                                Some('n') => '\n',
                                Some('t') => '\t',
                                Some('r') => '\r',
                                Some('b') => '\u{8}',
                                Some('f') => '\u{c}',
                                Some('\'') => '\'',
                                other => {
                                    return Err(syntax_error(
                                        file,
                                        line,
                                        format!(
                                            "unknown escape '\\{}' in a string",
                                            other.map(String::from).unwrap_or_default()
                                        ),
                                    ));
                                }
                            };
                            text.push(escaped);
                        }
                        Some(c) => text.push(c),
                    }
                }
                tokens.push(Token {
                    kind: TokenKind::String,
                    text,
                    line: start_line,
                });
            }
            _ => {
                let mut text = String::new();
                while let Some(&c) = characters.peek() {
                    if c.is_whitespace() || matches!(c, '"' | '[' | ']' | '#') {
                        break;
                    }
                    text.push(c);
                    characters.next();
                }
                tokens.push(Token {
                    kind: TokenKind::Word,
                    text,
                    line,
                });
            }
        }
    }
    Ok(tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds_and_texts(source: &str) -> Vec<(TokenKind, String, u32)> {
        tokenize(source.as_bytes(), Path::new("test.pbrt"))
            .unwrap()
            .into_iter()
            .map(|t| (t.kind, t.text, t.line))
            .collect()
    }

    #[test]
    fn words_strings_brackets_and_lines() {
        let tokens =
            kinds_and_texts("Shape \"sphere\"\n  \"float radius\" [ 2.5 ]\n\"bool x\" true");
        use TokenKind::*;
        assert_eq!(
            tokens,
            vec![
                (Word, "Shape".into(), 1),
                (String, "sphere".into(), 1),
                (String, "float radius".into(), 2),
                (OpenBracket, "[".into(), 2),
                (Word, "2.5".into(), 2),
                (CloseBracket, "]".into(), 2),
                (String, "bool x".into(), 3),
                (Word, "true".into(), 3),
            ]
        );
    }

    #[test]
    fn comments_run_to_the_end_of_the_line() {
        let tokens = kinds_and_texts("# a comment \"not a string\" [\nWorldBegin # more\n#\n1");
        assert_eq!(
            tokens,
            vec![
                (TokenKind::Word, "WorldBegin".into(), 2),
                (TokenKind::Word, "1".into(), 4),
            ]
        );
    }

    #[test]
    fn a_hash_inside_a_string_is_text() {
        let tokens = kinds_and_texts("\"a # b\"");
        assert_eq!(tokens, vec![(TokenKind::String, "a # b".into(), 1)]);
    }

    #[test]
    fn brackets_and_numbers_need_no_spaces() {
        let tokens = kinds_and_texts("[1 -2.5e-3 .5][\"a\"\"b\"]");
        let texts: Vec<&str> = tokens.iter().map(|t| t.1.as_str()).collect();
        assert_eq!(texts, ["[", "1", "-2.5e-3", ".5", "]", "[", "a", "b", "]"]);
    }

    #[test]
    fn escapes_are_resolved() {
        let tokens = kinds_and_texts(r#""a\"b\\c\nd""#);
        assert_eq!(tokens[0].1, "a\"b\\c\nd");
    }

    #[test]
    fn crlf_line_ends_count_once() {
        let tokens = kinds_and_texts("A\r\nB\r\n\r\nC");
        let lines: Vec<u32> = tokens.iter().map(|t| t.2).collect();
        assert_eq!(lines, [1, 2, 4]);
    }

    #[test]
    fn unterminated_strings_name_their_line() {
        let error = tokenize(b"Shape\n\"sphere", Path::new("scene.pbrt")).unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with("scene.pbrt:2:"), "{message}");
        assert!(message.contains("unterminated string"), "{message}");
        let error = tokenize(b"\"abc\ndef\"", Path::new("scene.pbrt")).unwrap_err();
        assert!(error.to_string().starts_with("scene.pbrt:1:"));
    }

    #[test]
    fn bad_escapes_and_bad_utf8_are_errors() {
        let error = tokenize(br#""a\qb""#, Path::new("s.pbrt")).unwrap_err();
        assert!(error.to_string().contains("unknown escape"), "{error}");
        let error = tokenize(b"A\nB\n\xff", Path::new("s.pbrt")).unwrap_err();
        assert!(error.to_string().starts_with("s.pbrt:3:"), "{error}");
    }
}
