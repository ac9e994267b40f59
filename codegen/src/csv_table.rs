//! CSV tables with a header (section tables, FE node files): one reader
//! configuration and one way to say where a CSV error is.

/// A reader of `text`: a header row, `#` comments, every row as long as
/// the header.
pub(crate) fn reader(text: &str) -> csv::Reader<&[u8]> {
    csv::ReaderBuilder::new()
        .has_headers(true)
        .comment(Some(b'#'))
        .flexible(false)
        .from_reader(text.as_bytes())
}

/// The line of a CSV error (1 when the reader gives none) and what is
/// wrong, a short row said in words.
pub(crate) fn error_at(e: &csv::Error) -> (u64, String) {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos,
            expected_len,
            len,
        } => (
            pos.as_ref().map_or(1, |p| p.line()),
            format!("a row has {len} fields, the header {expected_len}"),
        ),
        _ => (e.position().map_or(1, |p| p.line()), e.to_string()),
    }
}
