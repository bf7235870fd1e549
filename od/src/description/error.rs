//! Errors of the description readers: where in which file, and what was expected.

use std::fmt;
use std::path::PathBuf;
use std::sync::OnceLock;

/// A place in a source file: 1-based line and column (columns count characters).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Position {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub column: u32,
}

impl Position {
    /// The line and column of byte offset `offset` in `text` (clamped to the text's end).
    pub fn of_offset(text: &[u8], offset: usize) -> Position {
        let offset = offset.min(text.len());
        let before = &text[..offset];
        let line = before.iter().filter(|&&b| b == b'\n').count() as u32 + 1;
        let line_start = before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |p| p + 1);
        let column = String::from_utf8_lossy(&before[line_start..])
            .chars()
            .count() as u32
            + 1;
        Position { line, column }
    }
}

/// The starts of the lines of a text, so that many offsets turn into positions without scanning the
/// text from its start for each.
///
/// A column at most 128 bytes into its line is counted from the line's start. One further in (in a file
/// written on one line, say) is counted from the nearest of the marks the index makes when the first
/// such column is asked for: the number of characters before every 128th byte of the text (when the
/// text is UTF-8; otherwise the column is counted from the line's start too). A position then costs
/// the same whatever the lengths of the lines, and reading a file takes time in proportion to its
/// size for any layout.
#[derive(Debug, Clone, Default)]
pub struct LineIndex {
    starts: Vec<usize>,
    /// Characters before byte `k · MARK`, for each `k` up to the text's length; empty when the text is
    /// not UTF-8 (then columns are counted from the line's start). Made when a column far into a line
    /// is first asked for.
    marks: OnceLock<Vec<usize>>,
}

/// Bytes between two character counts of a [`LineIndex`], and the furthest into a line a column is
/// counted from the line's start.
const MARK: usize = 128;

/// The characters of UTF-8 `bytes` that start in them: every byte that is not a continuation byte
/// (`10xxxxxx`). For a slice cut inside a character this is what a lossy decoding counts, one
/// replacement character for the part.
fn chars_in(bytes: &[u8]) -> usize {
    bytes.iter().filter(|&&b| b & 0xC0 != 0x80).count()
}

/// The characters before every `MARK`-th byte of `text`; none when `text` is not UTF-8.
fn marks(text: &[u8]) -> Vec<usize> {
    if std::str::from_utf8(text).is_err() {
        return Vec::new();
    }
    let mut before = 0;
    let mut marks = vec![0];
    for chunk in text.chunks_exact(MARK) {
        before += chars_in(chunk);
        marks.push(before);
    }
    marks
}

impl LineIndex {
    /// The line starts of `text` (LF ends a line).
    pub fn new(text: &[u8]) -> LineIndex {
        let mut starts = vec![0];
        starts.extend(
            text.iter()
                .enumerate()
                .filter(|&(_, &b)| b == b'\n')
                .map(|(i, _)| i + 1),
        );
        LineIndex {
            starts,
            marks: OnceLock::new(),
        }
    }

    /// The position of byte `offset` of `text` (the text this index was made of), as
    /// [`Position::of_offset`] gives it.
    pub fn position(&self, text: &[u8], offset: usize) -> Position {
        let offset = offset.min(text.len());
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let start = self.starts.get(line - 1).copied().unwrap_or(0).min(offset);
        let column = self.chars_between(text, start, offset) as u32 + 1;
        Position {
            line: line as u32,
            column,
        }
    }

    /// The characters of `text[start..end]`: counted when they are few or the text is not UTF-8,
    /// else from the marks.
    fn chars_between(&self, text: &[u8], start: usize, end: usize) -> usize {
        if end - start > MARK {
            let marks = self.marks.get_or_init(|| marks(text));
            if let (Some(before_start), Some(before_end)) = (
                chars_before(marks, text, start),
                chars_before(marks, text, end),
            ) {
                return before_end - before_start;
            }
        }
        String::from_utf8_lossy(&text[start..end]).chars().count()
    }
}

/// The characters of `text` before byte `offset`: those before the mark at or below it and those
/// from there. `None` without marks.
fn chars_before(marks: &[usize], text: &[u8], offset: usize) -> Option<usize> {
    let k = offset / MARK;
    let before = marks.get(k)?;
    Some(before + chars_in(text.get(k * MARK..offset)?))
}

impl fmt::Display for Position {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_index_gives_what_a_scan_gives() {
        let text = "ab\nµc\r\n\nxyz".as_bytes();
        let index = LineIndex::new(text);
        for offset in 0..=text.len() + 2 {
            assert_eq!(
                index.position(text, offset),
                Position::of_offset(text, offset),
                "offset {offset}"
            );
        }
        assert_eq!(
            index.position(text, 6),
            Position { line: 2, column: 3 },
            "µ is one character"
        );
        let empty = LineIndex::new(b"");
        assert_eq!(empty.position(b"", 5), Position { line: 1, column: 1 });
    }

    /// A text of lines shorter and longer than the marks, with characters of one to four bytes
    /// that the marks cut.
    fn long_lines() -> String {
        let mut text = String::from("ab\n");
        for n in 0..700 {
            text.push(['a', 'µ', '€', '𝄞'][n % 4]);
            if n % 97 == 96 {
                text.push('\n');
            }
        }
        text.push_str("\n\n");
        text.push_str(&"µ€x".repeat(150));
        text
    }

    #[test]
    fn columns_far_into_long_lines_are_those_of_a_scan() {
        let text = long_lines();
        let index = LineIndex::new(text.as_bytes());
        for offset in 0..=text.len() + 2 {
            assert_eq!(
                index.position(text.as_bytes(), offset),
                Position::of_offset(text.as_bytes(), offset),
                "offset {offset}"
            );
        }
        let line = "x".repeat(10) + &"€µ".repeat(500) + "<a>";
        let text = format!("first\n{line}");
        let at = text.find('<').unwrap();
        assert_eq!(at, 2516);
        assert_eq!(
            LineIndex::new(text.as_bytes()).position(text.as_bytes(), at),
            Position {
                line: 2,
                column: 1011
            }
        );
    }

    #[test]
    fn a_text_that_is_not_utf8_has_its_columns_counted_as_a_lossy_decoding_counts() {
        let mut text = long_lines().into_bytes();
        text.extend([0x80, 0xBF, b'a', 0xE2, 0x82, b'b', 0xFF]);
        text.extend("µ".repeat(200).as_bytes());
        let index = LineIndex::new(&text);
        for offset in 0..=text.len() {
            assert_eq!(
                index.position(&text, offset),
                Position::of_offset(&text, offset),
                "offset {offset}"
            );
        }
        assert_eq!(index.marks.get().map(Vec::len), Some(0), "no marks");
    }

    #[test]
    fn the_marks_count_the_characters_before_them() {
        let text = "µ".repeat(300);
        let marks = marks(text.as_bytes());
        assert_eq!(marks, [0, 64, 128, 192, 256]);
        assert_eq!(chars_before(&marks, text.as_bytes(), 0), Some(0));
        assert_eq!(chars_before(&marks, text.as_bytes(), 301), Some(151));
        assert_eq!(chars_before(&marks, text.as_bytes(), 600), Some(300));
        assert_eq!(chars_before(&[], text.as_bytes(), 1), None);
        assert_eq!(chars_in("a€𝄞".as_bytes()), 3);
    }

    #[test]
    fn the_marks_are_made_for_the_first_column_beyond_the_mark_distance() {
        let text = format!("ab\n{}", "x".repeat(300));
        let index = LineIndex::new(text.as_bytes());
        let at = index.position(text.as_bytes(), 3 + MARK);
        assert_eq!(at.column as usize, MARK + 1);
        assert!(index.marks.get().is_none(), "counted from the line's start");
        let at = index.position(text.as_bytes(), 4 + MARK);
        assert_eq!(at.column as usize, MARK + 2);
        assert_eq!(index.marks.get().map(Vec::len), Some(3));
    }
}

/// A description file could not be read: the file, the place in it, and what was wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{source_name}:{position}: {message}")]
pub struct ParseError {
    /// The file name (or another name of the source).
    pub source_name: String,
    /// Where.
    pub position: Position,
    /// What was wrong, or what was expected there.
    pub message: String,
}

impl ParseError {
    /// An error at `position` of `source_name`.
    pub fn new(source_name: &str, position: Position, message: impl Into<String>) -> ParseError {
        ParseError {
            source_name: source_name.to_string(),
            position,
            message: message.into(),
        }
    }

    /// An error at byte `offset` of `text`.
    pub fn at_offset(
        source_name: &str,
        text: &[u8],
        offset: usize,
        message: impl Into<String>,
    ) -> ParseError {
        ParseError::new(source_name, Position::of_offset(text, offset), message)
    }
}

/// Loading a description failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LoadError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The file's contents are not a valid description.
    #[error(transparent)]
    Parse(#[from] ParseError),
    /// The path is not a regular file (a folder, a FIFO, a device).
    #[error("{0}: not a regular file")]
    NotAFile(PathBuf),
    /// The file is larger than its kind of file may be.
    #[error("{path}: {size} bytes, more than the {limit} such a file may have (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)")]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size, or what was read of it.
        size: u64,
        /// The limit.
        limit: u64,
    },
    /// `CANOPEN_MAX_FILE_BYTES` is set to something that is not a number of bytes.
    #[error("CANOPEN_MAX_FILE_BYTES={0:?} is not a number of bytes")]
    BadLimit(String),
    /// The format could not be told from the name or the contents.
    #[error("{0}: not an ESI, XDD, EDS or DCF file (expected EtherCATInfo or ISO15745ProfileContainer XML, or an INI file with [FileInfo]/[DeviceInfo])")]
    UnknownFormat(PathBuf),
}

impl From<LoadError> for std::io::Error {
    /// The reading failure as an I/O error for a caller that names the file itself: the system's
    /// error as it was, a refusal by kind and size without the path.
    fn from(e: LoadError) -> std::io::Error {
        use std::io::{Error, ErrorKind};
        match e {
            LoadError::Io { source, .. } => source,
            LoadError::NotAFile(_) => Error::new(ErrorKind::InvalidInput, "not a regular file"),
            LoadError::TooLarge { size, limit, .. } => Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "{size} bytes, more than the {limit} such a file may have \
                     (CANOPEN_MAX_FILE_BYTES=BYTES raises the limit)"
                ),
            ),
            other => Error::new(ErrorKind::InvalidData, other),
        }
    }
}
