//! JSON lines in and out: numbered input lines from a file or stdin, and records
//! ([`crate::files::records`]) written to stdout (or a file) one per line, each flushed as soon as
//! it is written.

use crate::files::records::{Header, Record};
use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};

/// Opens `path` for reading line by line; `None` or `-` is standard input.
pub fn open_input(path: Option<&Path>) -> Result<Box<dyn BufRead + Send>> {
    match path {
        None => Ok(Box::new(BufReader::new(io::stdin()))),
        Some(p) if p == Path::new("-") => Ok(Box::new(BufReader::new(io::stdin()))),
        Some(p) if p.is_dir() => bail!("cannot read input file {}: it is a directory", p.display()),
        Some(p) => {
            let file =
                File::open(p).with_context(|| format!("cannot open input file {}", p.display()))?;
            Ok(Box::new(BufReader::new(file)))
        }
    }
}

/// Longest input line read, bytes: a longer one is refused with its number, and read past
/// without being held (a road of the validator's 500 points takes about 20 KB).
pub const MAX_LINE_BYTES: usize = 16 << 20;

/// One non-blank input line with its 1-based number, or why it could not be read.
pub struct InputLine {
    /// Line number, counting from 1 (blank lines count).
    pub number: usize,
    /// The line's text, or a description of why it is not text.
    pub text: Result<String, String>,
}

/// Iterates over the non-blank lines of `input`, numbering every line. A line longer than
/// [`MAX_LINE_BYTES`] is given as an error and ends the input (memory and time are bounded
/// whatever its length: `/dev/zero` has no line end); a UTF-8 byte order mark before the first
/// line is dropped.
pub fn numbered_lines(
    mut input: Box<dyn BufRead + Send>,
) -> impl Iterator<Item = io::Result<InputLine>> {
    let mut number = 0;
    let mut buffer = Vec::new();
    let mut ended = false;
    std::iter::from_fn(move || loop {
        if ended {
            return None;
        }
        buffer.clear();
        let read = (&mut input)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut buffer);
        match read {
            Ok(0) => return None,
            Ok(_) => {
                number += 1;
                if buffer.len() > MAX_LINE_BYTES && buffer.last() != Some(&b'\n') {
                    ended = true;
                    let text = Err(format!(
                        "the line is longer than {} MiB; the input is not read further",
                        MAX_LINE_BYTES >> 20
                    ));
                    return Some(Ok(InputLine { number, text }));
                }
                let bytes = match buffer.strip_prefix(b"\xef\xbb\xbf") {
                    Some(rest) if number == 1 => rest,
                    _ => &buffer[..],
                };
                let text = match std::str::from_utf8(bytes) {
                    Ok(text) if text.trim().is_empty() => continue,
                    Ok(text) => Ok(text.trim_end().to_owned()),
                    Err(e) => Err(format!("not UTF-8 text: {e}")),
                };
                return Some(Ok(InputLine { number, text }));
            }
            Err(e) => return Some(Err(e)),
        }
    })
}

/// Most physical lines one JSON value may span before it is answered as an error.
const MAX_LINES_PER_VALUE: usize = 10_000;
/// Most bytes one JSON value may span across lines.
const MAX_BYTES_PER_VALUE: usize = 16 << 20;

/// The JSON values of `input` with the number of the line each begins on: one per non-blank line,
/// except that a value spread over several lines (a pretty-printed competition test) is joined
/// into one, within [`MAX_LINES_PER_VALUE`] lines and [`MAX_BYTES_PER_VALUE`] bytes.
pub fn json_values(input: Box<dyn BufRead + Send>) -> impl Iterator<Item = io::Result<InputLine>> {
    let mut lines = numbered_lines(input);
    std::iter::from_fn(move || {
        let first = lines.next()?;
        Some(first.and_then(|first| join_continued(first, &mut lines)))
    })
}

/// `first` and, when it is the opening bracket of a JSON value spread over lines, the lines that
/// complete it (within [`MAX_LINES_PER_VALUE`] and [`MAX_BYTES_PER_VALUE`]).
fn join_continued(
    first: InputLine,
    rest: &mut impl Iterator<Item = std::io::Result<InputLine>>,
) -> std::io::Result<InputLine> {
    let Ok(text) = &first.text else {
        return Ok(first);
    };
    // Only a line that is nothing but an opening bracket starts a value spread over lines (as a
    // pretty-printer writes it): a truncated one-line record must not swallow the lines after it.
    if !matches!(text.trim(), "{" | "[") || !opens_unfinished_value(text) {
        return Ok(first);
    }
    let mut joined = text.clone();
    for _ in 1..MAX_LINES_PER_VALUE {
        let Some(next) = rest.next() else { break };
        match next?.text {
            Ok(more) => {
                joined.push('\n');
                joined.push_str(&more);
            }
            Err(error) => {
                return Ok(InputLine {
                    number: first.number,
                    text: Err(error),
                })
            }
        }
        if joined.len() > MAX_BYTES_PER_VALUE || !opens_unfinished_value(&joined) {
            break;
        }
    }
    Ok(InputLine {
        number: first.number,
        text: Ok(joined),
    })
}

/// Whether `text` is the start of a JSON value that more lines could complete.
fn opens_unfinished_value(text: &str) -> bool {
    matches!(
        serde_json::from_str::<serde_json::Value>(text),
        Err(error) if error.is_eof()
    )
}

/// Writes records as JSON lines, flushing after each.
pub struct JsonLinesWriter {
    out: Box<dyn Write + Send>,
}

impl JsonLinesWriter {
    /// Writes to `path`, or to stdout when `None`.
    pub fn create(path: Option<&PathBuf>) -> Result<Self> {
        let out: Box<dyn Write + Send> = match path {
            None => Box::new(io::stdout()),
            Some(p) => {
                Box::new(File::create(p).with_context(|| format!("cannot create {}", p.display()))?)
            }
        };
        Ok(Self { out })
    }

    /// Writes one record and flushes it.
    pub fn write(&mut self, record: &Record) -> Result<()> {
        self.write_any(record)
    }

    /// Writes a run's header record and flushes it.
    pub fn write_header<C: Serialize>(&mut self, header: Header<C>) -> Result<()> {
        self.write_any(&Record::Header(header))
    }

    fn write_any<T: Serialize>(&mut self, record: &T) -> Result<()> {
        let encoded = serde_json::to_vec(record).context("cannot encode a record as JSON")?;
        self.write_encoded(encoded)
    }

    /// Writes one record already encoded as JSON (no newline) and flushes it.
    pub fn write_encoded(&mut self, mut encoded: Vec<u8>) -> Result<()> {
        encoded.push(b'\n');
        self.out
            .write_all(&encoded)
            .context("cannot write output")?;
        self.out.flush().context("cannot flush output")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str) -> Vec<(usize, String)> {
        let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(text.to_owned()));
        json_values(input)
            .map(|line| {
                let line = line.unwrap();
                (line.number, line.text.unwrap())
            })
            .collect()
    }

    #[test]
    fn a_value_spread_over_lines_is_one_input() {
        let text = "{\n  \"road_points\": [\n    [1, 2],\n    [3, 4]\n  ]\n}\n[[5, 6], [7, 8]]\n";
        let read = lines(text);
        assert_eq!(read.len(), 2, "{read:?}");
        assert_eq!(read[0].0, 1);
        assert!(serde_json::from_str::<serde_json::Value>(&read[0].1).is_ok());
        assert_eq!(read[1], (7, "[[5, 6], [7, 8]]".to_owned()));
        // A line that is not JSON at all is not joined with the next.
        assert_eq!(lines("nope\n[[1, 2]]\n").len(), 2);
        // An unfinished value at the end of the input is given as it is.
        assert_eq!(lines("{\n\"road_points\": [\n").len(), 1);
        // A truncated one-line record does not take the next line with it.
        assert_eq!(
            lines("{\"road_points\": [[1, 2]\n[[5, 6], [7, 8]]\n").len(),
            2
        );
    }

    #[test]
    fn a_line_longer_than_the_bound_is_refused_by_number_and_ends_the_input() {
        let mut text = b"[[1, 2]]\n".to_vec();
        text.extend_from_slice(&vec![b'0'; MAX_LINE_BYTES + 10]);
        text.extend_from_slice(b"\n[[3, 4]]\n");
        let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(text));
        let read: Vec<(usize, Result<String, String>)> = numbered_lines(input)
            .map(|line| line.map(|l| (l.number, l.text)).unwrap())
            .collect();
        assert_eq!(read.len(), 2);
        assert_eq!(read[0], (1, Ok("[[1, 2]]".to_owned())));
        assert_eq!(read[1].0, 2);
        assert!(read[1]
            .1
            .as_ref()
            .unwrap_err()
            .contains("longer than 16 MiB"));
        // A line that never ends is refused after the bound, not read for ever.
        let zeros: Box<dyn BufRead + Send> = Box::new(BufReader::new(std::io::repeat(0)));
        let read: Vec<InputLine> = numbered_lines(zeros).map(|l| l.unwrap()).collect();
        assert_eq!(read.len(), 1);
        assert!(read[0].text.is_err());
        // A line of exactly the bound is read.
        let mut exact = vec![b' '; MAX_LINE_BYTES - 1];
        exact[0] = b'1';
        let input: Box<dyn BufRead + Send> = Box::new(std::io::Cursor::new(exact));
        assert!(numbered_lines(input).next().unwrap().unwrap().text.is_ok());
    }

    #[test]
    fn a_byte_order_mark_before_the_first_line_is_dropped() {
        assert_eq!(lines("\u{feff}[[1, 2]]\n"), [(1, "[[1, 2]]".to_owned())]);
    }
}
