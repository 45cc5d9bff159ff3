//! JSON lines in and out: numbered input lines from a file or stdin, and records
//! ([`crate::records`]) written to stdout (or a file) one per line, each flushed as soon as it is
//! written.

use crate::records::{Header, Record};
use anyhow::{bail, Context, Result};
use serde::Serialize;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
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

/// One non-blank input line with its 1-based number, or why it could not be read.
pub struct InputLine {
    /// Line number, counting from 1 (blank lines count).
    pub number: usize,
    /// The line's text, or a description of why it is not text.
    pub text: Result<String, String>,
}

/// Iterates over the non-blank lines of `input`, numbering every line.
pub fn numbered_lines(
    mut input: Box<dyn BufRead + Send>,
) -> impl Iterator<Item = io::Result<InputLine>> {
    let mut number = 0;
    let mut buffer = Vec::new();
    std::iter::from_fn(move || loop {
        buffer.clear();
        match input.read_until(b'\n', &mut buffer) {
            Ok(0) => return None,
            Ok(_) => {
                number += 1;
                let text = match std::str::from_utf8(&buffer) {
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
