//! [`Error`]: everything the library can refuse or report. Each variant says whether the input
//! was bad or the work failed; what a host makes of that (an exit code, an exception class) is
//! the host's decision.

use crate::output::OutputError;
use crate::scene::SceneError;

/// Why a scene, a session or a run could not go on.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene is unusable (bad input). Names the file, the field and the fix.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// An option of a run is out of range (bad input).
    #[error("{0}")]
    Usage(String),
    /// A value a host handed the session is unusable (bad input): names the argument, what
    /// was given and what is expected.
    #[error("{argument}: {message}")]
    Argument {
        /// The argument (e.g. `scalp_vertices`, `collider 3`).
        argument: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The solver refused the setup or blew up (failed work).
    #[error("{scene}: {source}")]
    Solver {
        /// The scene (or session) being run.
        scene: String,
        /// The solver's error.
        source: hair_core::HairError,
    },
    /// An output could not be made (see [`OutputError::is_bad_input`]); boxed, so every
    /// `Result` of the library stays small.
    #[error("{0}")]
    Output(Box<OutputError>),
    /// The cache could not be written or read (failed work).
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
    /// A session whose last step failed was stepped again (failed work): its state is the
    /// failed one. Restore a snapshot or build a new session.
    #[error(
        "the session's step at frame {frame} failed ({cause}); its state is not usable: restore \
         a snapshot or start a new session"
    )]
    Failed {
        /// The frame whose step failed.
        frame: u32,
        /// The failure, as it was reported.
        cause: String,
    },
}

impl From<OutputError> for Error {
    fn from(e: OutputError) -> Self {
        Error::Output(Box::new(e))
    }
}

impl Error {
    /// An [`Error::Argument`] for `argument`.
    pub fn argument(argument: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Argument {
            argument: argument.into(),
            message: message.into(),
        }
    }
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
