//! [`Error`]: everything the library can refuse or report, with the process exit code the
//! `hairsys` command gives it.

use crate::scene::SceneError;

/// Why a scene, a session or a run could not go on.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene is unusable (exit code 2). Names the file, the field and the fix.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// An option of a run is out of range (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// A value a host handed the session is unusable (exit code 2): names the argument, what
    /// was given and what is expected.
    #[error("{argument}: {message}")]
    Argument {
        /// The argument (e.g. `scalp_vertices`, `collider 3`).
        argument: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The solver refused the setup or blew up (exit code 1).
    #[error("{scene}: {source}")]
    Solver {
        /// The scene (or session) being run.
        scene: String,
        /// The solver's error.
        source: hair_core::HairError,
    },
    /// An output file could not be written (exit code 1): names the file and the reason.
    #[error("{0}")]
    Output(String),
    /// The cache could not be written or read (exit code 1).
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
    /// A session whose last step failed was stepped again (exit code 1): its state is the
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

impl Error {
    /// Process exit code: 2 for bad input (scene, options, host arguments), 1 for a run that
    /// failed (solver blow-up, cache I/O, stepping a failed session).
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scene(_) | Error::Usage(_) | Error::Argument { .. } => 2,
            Error::Solver { .. } | Error::Cache(_) | Error::Output(_) | Error::Failed { .. } => 1,
        }
    }

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
