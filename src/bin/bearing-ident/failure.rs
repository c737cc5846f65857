//! How the tool fails: a stable kind and a one-line message ([`Failure`]), and writing to
//! stdout, where a reader that went away (`bearing-ident … | head -1`) is a quiet success.

use std::io::Write as _;

/// A failure of the tool: a stable kind and a one-line message.
pub struct Failure {
    pub kind: &'static str,
    pub message: String,
}

impl From<bearing_ident::Error> for Failure {
    fn from(e: bearing_ident::Error) -> Self {
        let mut message = e.to_string();
        // The library speaks of its own types; the tool adds its flags.
        if matches!(e, bearing_ident::Error::MlNeedsRepeats) {
            message.push_str(" (on the command line: `--excitation periodic --period S`)");
        }
        if matches!(e, bearing_ident::Error::BadRecord { .. }) {
            message.push_str(" (on the command line: `--reject-bad-records`)");
        }
        Failure {
            kind: e.kind().as_str(),
            message,
        }
    }
}

/// An `invalid_argument` failure.
pub fn invalid(message: String) -> Failure {
    Failure {
        kind: "invalid_argument",
        message,
    }
}

/// The kind of the failure that a closed stdout is; [`Failure::is_broken_pipe`] tells it.
const BROKEN_PIPE: &str = "broken_pipe";

impl Failure {
    /// Whether stdout was closed by its reader (`… | head -1`): the tool then ends quietly
    /// with status 0.
    pub fn is_broken_pipe(&self) -> bool {
        self.kind == BROKEN_PIPE
    }
}

/// Writes one line to stderr and ignores a stderr that cannot take it (`2>/dev/full`, a closed
/// terminal): what stderr says is a courtesy, never a reason to fail or to lose the JSON on
/// stdout and the exit status.
pub fn print_err(text: std::fmt::Arguments<'_>) {
    let mut err = std::io::stderr().lock();
    let _ = err.write_fmt(text).and_then(|()| err.write_all(b"\n"));
}

/// Writes `text` to stdout (locked) and flushes it. A reader that went away is the quiet
/// [`Failure::is_broken_pipe`]; any other error of stdout is an `io_error`.
pub fn print_out(text: std::fmt::Arguments<'_>) -> Result<(), Failure> {
    let mut out = std::io::stdout().lock();
    out.write_fmt(text)
        .and_then(|()| out.flush())
        .map_err(|e| Failure {
            kind: if e.kind() == std::io::ErrorKind::BrokenPipe {
                BROKEN_PIPE
            } else {
                "io_error"
            },
            message: format!("stdout: {e}"),
        })
}
