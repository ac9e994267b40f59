//! User strings on their way into generated code and messages.
//!
//! Generated Rust contains a few strings that come from the user: the shape's
//! name and where it came from (a file path) in comments and doc comments,
//! and the body type name as code. This module decides what is allowed and
//! escapes the rest, so that no user string can end a comment and become
//! code:
//!
//! - shape and coordinate names: [`check_name`], a restricted character set
//!   ([`NAME_CHARS`]) and a bounded length;
//! - anything placed in a comment: [`comment_text`], printable ASCII only,
//!   everything else escaped, `*/` and `/*` broken up;
//! - type names and body names: [`check_type_name`] and [`check_identifier`],
//!   plain ASCII Rust identifiers that are not keywords (in any edition) and,
//!   for types, not primitive type names;
//! - user text quoted in error messages: [`snippet`], escaped and shortened.

use crate::limits::MAX_IDENTIFIER_CHARS;

/// The characters allowed in shape and coordinate names, for messages.
pub const NAME_CHARS: &str = "ASCII letters, digits, `_`, `.` and `-`";

/// Whether `c` may appear in a shape or coordinate name.
pub fn is_name_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '.' | '-')
}

/// Check a shape or coordinate name: 1 to `max_chars` characters from
/// `[A-Za-z0-9_.-]`. On failure returns the byte offset of the offending
/// character (0 for an empty or too long name) and a message.
pub fn check_name(name: &str, what: &str, max_chars: usize) -> Result<(), (usize, String)> {
    if name.is_empty() {
        return Err((0, format!("{what} must not be empty")));
    }
    if let Some((i, c)) = name.char_indices().find(|&(_, c)| !is_name_char(c)) {
        return Err((
            i,
            format!(
                "{what} `{}` contains {}: names may use only {NAME_CHARS}",
                snippet(name, 40),
                describe_char(c)
            ),
        ));
    }
    let n = name.chars().count();
    if n > max_chars {
        return Err((
            0,
            format!(
                "{what} `{}` is {n} characters long: at most {max_chars} are allowed",
                snippet(name, 40)
            ),
        ));
    }
    Ok(())
}

/// A character as it reads in a message: `` `x` `` or its code point.
pub fn describe_char(c: char) -> String {
    if c.is_ascii_graphic() {
        format!("the character `{c}`")
    } else if c == ' ' {
        "a space".into()
    } else {
        format!("the character U+{:04X}", c as u32)
    }
}

use ffr_spec::text::escape_char;
pub use ffr_spec::text::snippet;

/// `s` made safe to place inside any Rust comment (`//`, `///`, `//!`,
/// `/* */`): printable ASCII is kept, everything else (control characters,
/// `\r`, `\n`, Unicode line and paragraph separators, bidirectional and
/// other invisible format characters, any non-ASCII character) is written as
/// an escape (`\n`, `\u{202e}`), and the comment delimiters `*/` and `/*` are
/// broken up (`*\/`, `/\*`). The result is a single line of printable ASCII
/// that cannot end or nest a comment.
pub fn comment_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut prev: Option<char> = None;
    for c in s.chars() {
        if c == ' ' || c.is_ascii_graphic() {
            match (prev, c) {
                (Some('*'), '/') => out.push_str("\\/"),
                (Some('/'), '*') => out.push_str("\\*"),
                _ => out.push(c),
            }
        } else {
            escape_char(c, &mut out);
        }
        prev = Some(c);
    }
    out
}

/// Keywords of every Rust edition (strict, 2018+, reserved and 2024's `gen`):
/// none of them may name a generated type or body, raw or not.
pub const KEYWORDS: &[&str] = &[
    "_", "abstract", "as", "async", "await", "become", "box", "break", "const", "continue",
    "crate", "do", "dyn", "else", "enum", "extern", "false", "final", "fn", "for", "gen", "if",
    "impl", "in", "let", "loop", "macro", "match", "mod", "move", "mut", "override", "priv", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "try", "type",
    "typeof", "unsafe", "unsized", "use", "virtual", "where", "while", "yield",
];

/// Primitive type names: a struct named like one would shadow it in the
/// generated code (whose fields are `f64`).
pub const PRIMITIVE_TYPES: &[&str] = &[
    "bool", "char", "str", "f16", "f32", "f64", "f128", "i8", "i16", "i32", "i64", "i128", "isize",
    "u8", "u16", "u32", "u64", "u128", "usize",
];

/// Check that `s` is a plain ASCII Rust identifier (`[A-Za-z_][A-Za-z0-9_]*`,
/// at most [`MAX_IDENTIFIER_CHARS`] characters), not `_`, not raw (`r#…`) and
/// not a keyword of any edition. `what` names it in the message
/// (e.g. ``--type-name `fn` ``).
pub fn check_identifier(s: &str, what: &str) -> Result<(), String> {
    let shown = snippet(s, 40);
    let mut chars = s.chars();
    let first_ok = matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_');
    if s.starts_with("r#") {
        return Err(format!(
            "{what} `{shown}` is a raw identifier: write it without `r#`, and not as a keyword"
        ));
    }
    if !first_ok || !s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
        let why = match s
            .chars()
            .find(|c| !(c.is_ascii_alphanumeric() || *c == '_'))
        {
            _ if s.is_empty() => "it is empty".to_string(),
            Some(c) => format!("it contains {}", describe_char(c)),
            None => "it starts with a digit".to_string(),
        };
        return Err(format!(
            "{what} `{shown}` is not a Rust identifier ({why}): expected ASCII letters, digits and `_`, not starting with a digit"
        ));
    }
    if s.len() > MAX_IDENTIFIER_CHARS {
        return Err(format!(
            "{what} `{shown}` is {} characters long: at most {MAX_IDENTIFIER_CHARS} are allowed",
            s.len()
        ));
    }
    if KEYWORDS.contains(&s) {
        return Err(format!(
            "{what} `{s}` is a Rust keyword and cannot name a type or body"
        ));
    }
    Ok(())
}

/// Check a name for a generated type: [`check_identifier`], and not a
/// primitive type name (`f64`, `u8`, …).
pub fn check_type_name(s: &str, what: &str) -> Result<(), String> {
    check_identifier(s, what)?;
    if PRIMITIVE_TYPES.contains(&s) {
        return Err(format!(
            "{what} `{s}` is a primitive type name; a struct of that name would shadow it (expected e.g. `Arm`)"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comment_text_cannot_leave_a_comment() {
        let evil = "a\nfn main(){}\r\u{2028}*/ /* \u{202e}x\u{0}ü\\";
        let c = comment_text(evil);
        assert_eq!(
            c,
            "a\\nfn main(){}\\r\\u{2028}*\\/ /\\* \\u{202e}x\\u{0}\\u{fc}\\"
        );
        assert!(c.chars().all(|c| c == ' ' || c.is_ascii_graphic()));
        assert!(!c.contains("*/") && !c.contains("/*"));
        assert_eq!(comment_text("shapes/bar.toml"), "shapes/bar.toml");
    }

    #[test]
    fn names() {
        assert!(check_name("beam3", "shape name", 64).is_ok());
        assert!(check_name("my-bar_2.v1", "shape name", 64).is_ok());
        let (at, m) = check_name("ab\ncd", "shape name", 64).unwrap_err();
        assert_eq!(at, 2);
        assert!(m.contains("U+000A"), "{m}");
        assert!(m.contains("`ab\\ncd`"), "{m}");
        assert!(check_name("", "shape name", 64).is_err());
        assert!(check_name(&"a".repeat(65), "shape name", 64).is_err());
        assert!(check_name("a b", "shape name", 64)
            .unwrap_err()
            .1
            .contains("a space"));
    }

    #[test]
    fn identifiers() {
        for ok in ["Arm", "Body", "two_link_arm", "_Arm", "A1", "union", "raw"] {
            check_type_name(ok, "--type-name").unwrap();
        }
        for bad in [
            "", "fn", "Self", "self", "_", "r#Arm", "9lives", "my-arm", "Ärm", "async", "gen",
            "try", "f64", "u8", "a b",
        ] {
            let e = check_type_name(bad, "--type-name").unwrap_err();
            assert!(e.starts_with("--type-name `"), "{e}");
        }
        assert!(check_identifier(&"a".repeat(65), "x").is_err());
        assert!(check_identifier("f64", "body name").is_ok());
    }

    #[test]
    fn snippets_are_escaped_and_short() {
        assert_eq!(snippet("ab\u{1b}[31mc", 100), "ab\\u{1b}[31mc");
        assert_eq!(snippet("abcdef", 3), "abc…");
        assert_eq!(snippet("jürgen", 10), "jürgen");
        assert_eq!(snippet("a\u{ffff}\u{85}b", 10), "a\\u{ffff}\\u{85}b");
    }
}
