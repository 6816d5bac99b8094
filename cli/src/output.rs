//! Everything the command prints on stdout goes through here, so a reader that goes away
//! (`hairsys simulate --json | head -1`) or a full disk (`> /dev/full`) ends the command with a
//! message and exit code 1 instead of the panic `println!` gives.
//!
//! The first write error is kept and every later write is skipped: a run whose stdout closed
//! goes on to finish its cache (a batch run is not worth losing for a closed pipe), and
//! [`finish`] then reports the error on stderr and turns the exit code into 1.

use std::io::Write;
use std::sync::Mutex;

/// The first error writing stdout, if any.
static FAILED: Mutex<Option<std::io::Error>> = Mutex::new(None);

/// Writes `text` to stdout unless an earlier write failed; a failure is kept for [`finish`].
pub fn write(text: &str) {
    let mut failed = FAILED.lock().unwrap_or_else(|e| e.into_inner());
    if failed.is_some() {
        return;
    }
    let mut out = std::io::stdout().lock();
    if let Err(e) = out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        *failed = Some(e);
    }
}

/// Writes `text` and a newline to stdout (see [`write()`]).
pub fn line(text: &str) {
    write(&format!("{text}\n"));
}

/// Writes `text` to stdout ending with exactly the newline it may lack (for multi-line
/// summaries whose `Display` leaves the last line open, see [`write()`]).
pub fn block(text: &str) {
    if text.ends_with('\n') {
        write(text);
    } else {
        line(text);
    }
}

/// The exit code after `code`: unchanged if stdout took everything, else 1 (with the error on
/// stderr) when the command had succeeded.
pub fn finish(code: u8) -> u8 {
    write("");
    let failed = FAILED.lock().unwrap_or_else(|e| e.into_inner()).take();
    match failed {
        None => code,
        Some(e) => {
            eprintln!(
                "error: cannot write to stdout ({e}); the output is incomplete{}",
                if code == 0 {
                    ""
                } else {
                    " (and the command failed, see above)"
                }
            );
            if code == 0 {
                1
            } else {
                code
            }
        }
    }
}
