//! How long work reports itself: a bar with ETA on a terminal, nothing with `--quiet`, JSON lines
//! on stdout with `--json`.

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

/// Where progress goes.
pub enum Progress {
    /// An indicatif bar on stderr.
    Bar(ProgressBar),
    /// One JSON object per event on stdout.
    Json,
    /// Nothing.
    Quiet,
}

impl Progress {
    /// Chooses the mode from the flags and whether stderr is a terminal.
    pub fn new(total: u64, quiet: bool, json: bool, what: &str) -> Self {
        if json {
            Progress::Json
        } else if quiet || !std::io::stderr().is_terminal() {
            Progress::Quiet
        } else {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template(
                    "{msg}{prefix} [{bar:30}] {pos}/{len} {rate} ETA {eta}",
                )
                .expect("the template is valid")
                .with_key(
                    "rate",
                    |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = write!(w, "{:.1}/s", state.per_sec());
                    },
                )
                .progress_chars("=> "),
            );
            bar.set_message(what.to_string());
            Progress::Bar(bar)
        }
    }

    /// Reports one unit of work done, with a JSON payload for `--json`.
    pub fn tick<T: Serialize>(&self, event: &T) {
        match self {
            Progress::Bar(bar) => bar.inc(1),
            Progress::Json => {
                crate::output::line(&serde_json::to_string(event).expect("events serialise"))
            }
            Progress::Quiet => {}
        }
    }

    /// Reports `frame` written, the `written`-th frame of the run counting its first (so the
    /// bar agrees with the summary and `cache info`, also when a resumed run starts part way),
    /// with a JSON payload for `--json`.
    pub fn frame_written<T: Serialize>(&self, frame: u32, written: u64, event: &T) {
        match self {
            Progress::Bar(bar) => {
                bar.set_position(written);
                bar.set_prefix(format!(" frame {frame}"));
            }
            _ => self.tick(event),
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        if let Progress::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}
