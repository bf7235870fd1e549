//! Errors of the description readers: where in which file, and what was expected.

use std::fmt;
use std::path::PathBuf;

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
#[derive(Debug, Clone, Default)]
pub struct LineIndex {
    starts: Vec<usize>,
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
        LineIndex { starts }
    }

    /// The position of byte `offset` of `text` (the text this index was made of), as
    /// [`Position::of_offset`] gives it.
    pub fn position(&self, text: &[u8], offset: usize) -> Position {
        let offset = offset.min(text.len());
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let start = self.starts.get(line - 1).copied().unwrap_or(0).min(offset);
        let column = String::from_utf8_lossy(&text[start..offset])
            .chars()
            .count() as u32
            + 1;
        Position {
            line: line as u32,
            column,
        }
    }
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
