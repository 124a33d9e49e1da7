//! Command output and how a command ends: every command writes its results through an
//! [`Output`] and fails with a [`CliError`], and [`super::run`] maps that to the exit code.
//!
//! The rules (the same for every command, present and future):
//! - Results go to standard output through the `Output` the command is given (never
//!   `print!`/`println!`, which panic when the reader has gone away). Write as you go
//!   (`out.text(..)` per record) rather than building one big string: output then streams,
//!   in constant memory, and a reader that stops early (`sinew eval … | head`) stops the
//!   work early too.
//! - A closed pipe on standard output is a normal, quiet end: the write fails with
//!   [`CliError::OutputClosed`], the command returns it with `?`, and the process exits 0
//!   without a message, as Unix tools do.
//! - Any other write error (`> /dev/full`) becomes [`CliError::Failed`] with the OS message:
//!   `error: cannot write to standard output: …` and exit code 1. The final flush is done by
//!   `run`, so an error at flush time is reported the same way.
//! - Problems with the input are `CliError::Failed(message)` (a `String` converts with `?`);
//!   `run` prints `error: message` (or the message as is when it is already
//!   `file:line:col: error: …` diagnostics) on standard error and exits 1.
//! - Files a command writes (`-o`) are checked with [`super::paths::check_outputs`] first.

use std::io::{self, Write};

/// Why a command stopped before finishing normally.
#[derive(Debug)]
pub enum CliError {
    /// A failure to report on standard error (exit code 1).
    Failed(String),
    /// Standard output was closed by its reader (a broken pipe): a quiet, successful end.
    OutputClosed,
}

impl CliError {
    /// The error a failed write to standard output means (see the module docs).
    pub fn from_write(e: &io::Error) -> CliError {
        if e.kind() == io::ErrorKind::BrokenPipe {
            CliError::OutputClosed
        } else {
            CliError::Failed(format!("cannot write to standard output: {e}"))
        }
    }

    /// The message to print, if any (`None` for a closed output).
    pub fn message(&self) -> Option<&str> {
        match self {
            CliError::Failed(m) => Some(m),
            CliError::OutputClosed => None,
        }
    }
}

impl From<String> for CliError {
    fn from(message: String) -> Self {
        CliError::Failed(message)
    }
}

impl From<&str> for CliError {
    fn from(message: &str) -> Self {
        CliError::Failed(message.to_string())
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::Failed(m) => f.write_str(m),
            CliError::OutputClosed => f.write_str("standard output was closed"),
        }
    }
}

/// Where a command writes its results (standard output in the binary, a buffer in tests).
pub struct Output<'w> {
    w: &'w mut dyn Write,
    /// Flush after every [`Output::text`] (for a terminal, or `check --watch`).
    eager: bool,
}

impl<'w> Output<'w> {
    /// Output to `w`, buffered as `w` is.
    pub fn new(w: &'w mut dyn Write) -> Self {
        Output { w, eager: false }
    }

    /// Flushes after every [`Output::text`] when `eager` (results appear as they are made).
    pub fn eager(mut self, eager: bool) -> Self {
        self.eager = eager;
        self
    }

    /// The same output for a nested call (with its own `eager` setting).
    pub fn reborrow(&mut self) -> Output<'_> {
        Output {
            w: &mut *self.w,
            eager: self.eager,
        }
    }

    /// Writes `text` followed by a newline unless it already ends with one; writes nothing
    /// for empty text.
    pub fn text(&mut self, text: &str) -> Result<(), CliError> {
        if text.is_empty() {
            return Ok(());
        }
        self.bytes(text.as_bytes())?;
        if !text.ends_with('\n') {
            self.bytes(b"\n")?;
        }
        if self.eager {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes raw bytes.
    pub fn bytes(&mut self, bytes: &[u8]) -> Result<(), CliError> {
        self.w.write_all(bytes).map_err(|e| CliError::from_write(&e))
    }

    /// The underlying writer, for serializers that write directly (map their errors
    /// with [`CliError::from_write`]).
    pub fn writer(&mut self) -> &mut dyn Write {
        self.w
    }

    /// Flushes buffered output.
    pub fn flush(&mut self) -> Result<(), CliError> {
        self.w.flush().map_err(|e| CliError::from_write(&e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer failing with a chosen error kind after `ok` bytes.
    struct Failing {
        ok: usize,
        kind: io::ErrorKind,
    }

    impl Write for Failing {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            if self.ok == 0 {
                return Err(io::Error::from(self.kind));
            }
            let n = buf.len().min(self.ok);
            self.ok -= n;
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn text_adds_one_newline_and_skips_empty_text() {
        let mut buf = Vec::new();
        let mut out = Output::new(&mut buf);
        out.text("a").unwrap();
        out.text("b\n").unwrap();
        out.text("").unwrap();
        assert_eq!(buf, b"a\nb\n");
    }

    #[test]
    fn broken_pipe_is_a_quiet_end_and_other_errors_fail() {
        let mut w = Failing {
            ok: 3,
            kind: io::ErrorKind::BrokenPipe,
        };
        let e = Output::new(&mut w).text("hello").unwrap_err();
        assert!(matches!(e, CliError::OutputClosed) && e.message().is_none());
        let mut w = Failing {
            ok: 0,
            kind: io::ErrorKind::StorageFull,
        };
        let e = Output::new(&mut w).text("hello").unwrap_err();
        let m = e.message().unwrap();
        assert!(m.starts_with("cannot write to standard output: "), "{m}");
    }
}
