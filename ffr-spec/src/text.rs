//! User text in messages: escaped so that it cannot move a terminal's
//! cursor or reorder text, and cut to a length.

/// One character escaped as `\n`, `\r`, `\t` or `\u{…}`.
pub fn escape_char(c: char, out: &mut String) {
    match c {
        '\n' => out.push_str("\\n"),
        '\r' => out.push_str("\\r"),
        '\t' => out.push_str("\\t"),
        c => out.push_str(&format!("\\u{{{:x}}}", c as u32)),
    }
}

/// User text quoted in an error message or shown on a terminal or in a
/// plot: control, format and other non-printing characters (and the
/// non-characters U+FFFE, U+FFFF, which XML does not allow) escaped as in
/// ffr-codegen's `comment_text` (so a message cannot move the cursor, change colours or
/// reorder text on a terminal, and an SVG stays well-formed XML once its
/// writer has escaped `<`, `&` and quotes), and cut to at most `max_chars`
/// characters with `…`.
pub fn snippet(s: &str, max_chars: usize) -> String {
    let mut out = String::new();
    for (n, c) in s.chars().enumerate() {
        if n == max_chars {
            out.push('…');
            break;
        }
        if c.is_control() || is_invisible(c) || matches!(c, '\u{fffe}' | '\u{ffff}') {
            escape_char(c, &mut out);
        } else {
            out.push(c);
        }
    }
    out
}

/// Format characters that change how text displays without showing:
/// bidirectional controls, zero-width characters, line and paragraph
/// separators, the byte-order mark, soft hyphen, tags.
fn is_invisible(c: char) -> bool {
    matches!(c as u32,
        0x00AD | 0x061C | 0x180E | 0x200B..=0x200F | 0x2028..=0x202E | 0x2060..=0x206F
        | 0xFEFF | 0xFFF9..=0xFFFB | 0xE0000..=0xE007F)
}

/// The most characters of a user string (a name, a key, a marker) quoted in
/// a message; longer ones are cut with `…`.
pub const MAX_QUOTED_CHARS: usize = 64;

/// A user string as quoted in a message: escaped and at most
/// [`MAX_QUOTED_CHARS`] characters ([`snippet`]).
pub fn quoted(s: &str) -> String {
    snippet(s, MAX_QUOTED_CHARS)
}

/// The longest number, in characters, that [`Num`] writes in decimal form.
pub const MAX_DECIMAL_CHARS: usize = 16;

/// A number as messages show it: Rust's shortest decimal form (`1.5`,
/// `0.001`, `2700`) for magnitudes from 1e-4 to below 1e9 (and 0) when that
/// is at most [`MAX_DECIMAL_CHARS`] characters, otherwise its shortest
/// exponent form (`2e9`; `1e308`, not 309 digits; `1e-310`, not 312).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        let s = self.0.to_string();
        if (a == 0.0 || (1e-4..1e9).contains(&a)) && s.chars().count() <= MAX_DECIMAL_CHARS {
            f.write_str(&s)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod num_tests {
    use super::Num;

    #[test]
    fn numbers_are_short_and_read_back() {
        for (x, shown) in [
            (1.0, "1"),
            (1.5, "1.5"),
            (2700.0, "2700"),
            (1e308, "1e308"),
            (-1e308, "-1e308"),
            (1e-310, "1e-310"),
            (2e9, "2e9"),
            (123456789.5, "123456789.5"),
            (1e-5, "1e-5"),
            (0.0, "0"),
            (0.1 + 0.2, "3.0000000000000004e-1"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
        ] {
            let s = Num(x).to_string();
            assert_eq!(s, shown);
            if x.is_finite() {
                assert_eq!(s.parse::<f64>().unwrap(), x, "{s} reads back");
            }
        }
    }
}

/// The most characters of a path shown in a message; a longer one keeps
/// its first [`PATH_HEAD_CHARS`] and its end (the file's name), with `…`
/// between.
pub const MAX_PATH_CHARS: usize = 160;

/// Characters kept from the start of a path cut by [`path_text`].
pub const PATH_HEAD_CHARS: usize = 48;

/// A path as messages show it: escaped as [`snippet`] does, and at most
/// [`MAX_PATH_CHARS`] characters, cut in the middle so that the file's
/// name stays.
pub fn path_text(path: &str) -> String {
    let n = path.chars().count();
    if n <= MAX_PATH_CHARS {
        return snippet(path, usize::MAX);
    }
    let head: String = path.chars().take(PATH_HEAD_CHARS).collect();
    let tail: String = path
        .chars()
        .skip(n - (MAX_PATH_CHARS - PATH_HEAD_CHARS - 1))
        .collect();
    format!(
        "{}…{}",
        snippet(&head, usize::MAX),
        snippet(&tail, usize::MAX)
    )
}

#[cfg(test)]
mod path_tests {
    use super::*;

    #[test]
    fn long_paths_are_cut_in_the_middle_and_keep_the_file_name() {
        assert_eq!(path_text("scenes/a.toml"), "scenes/a.toml");
        assert_eq!(path_text("a\nb"), "a\\nb");
        let long = format!("/tmp/{}/{}/scene.toml", "d".repeat(3000), "e".repeat(3000));
        let shown = path_text(&long);
        assert_eq!(shown.chars().count(), MAX_PATH_CHARS);
        assert!(shown.starts_with("/tmp/ddd") && shown.ends_with("eee/scene.toml"));
        assert!(shown.contains('…'));
    }
}
