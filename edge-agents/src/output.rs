//! The replay-line writer: `--output FILE.jsonl` or `--output -` (stdout), one JSON object per line in the
//! input form of PROTOCOL.md "Replay files" (`{"descriptor": ...}`, `{"measurements": ...}`, `{"truth": ...}`).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use protocol::ReplayLine;

use crate::error::AgentError;

/// Writes replay lines to a file or stdout.
pub struct ReplayWriter {
    out: Box<dyn Write + Send>,
    /// `stdout` or the file's name, for error messages.
    target: String,
    /// Flush after every line (live runs, so a reader sees each set as it is published); off when writing as
    /// fast as possible, where a buffer is much cheaper.
    flush_each_line: bool,
    lines: u64,
}

impl ReplayWriter {
    /// Opens `path` for writing (truncating it), or stdout when `path` is `-`.
    pub fn create(path: &Path, flush_each_line: bool) -> Result<Self, AgentError> {
        let (out, target): (Box<dyn Write + Send>, String) = if path.as_os_str() == "-" {
            (Box::new(BufWriter::new(std::io::stdout())), "stdout".into())
        } else {
            let target = path.display().to_string();
            let file = File::create(path).map_err(|source| AgentError::Output {
                target: target.clone(),
                source,
            })?;
            (Box::new(BufWriter::new(file)), target)
        };
        Ok(Self {
            out,
            target,
            flush_each_line,
            lines: 0,
        })
    }

    /// Appends one line.
    pub fn write(&mut self, line: &ReplayLine) -> Result<(), AgentError> {
        let result = serde_json::to_writer(&mut self.out, line)
            .map_err(std::io::Error::from)
            .and_then(|()| self.out.write_all(b"\n"))
            .and_then(|()| {
                if self.flush_each_line {
                    self.out.flush()
                } else {
                    Ok(())
                }
            });
        result.map_err(|source| self.error(source))?;
        self.lines += 1;
        Ok(())
    }

    /// Number of lines written so far.
    pub fn lines(&self) -> u64 {
        self.lines
    }

    /// Flushes what is buffered; call once at the end of the run.
    pub fn finish(&mut self) -> Result<(), AgentError> {
        self.out.flush().map_err(|source| self.error(source))
    }

    /// The target's name, for the run summary.
    pub fn target(&self) -> &str {
        &self.target
    }

    /// The error for a failed write or flush of this target.
    fn error(&self, source: std::io::Error) -> AgentError {
        AgentError::Output {
            target: self.target.clone(),
            source,
        }
    }
}
