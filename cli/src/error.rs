//! [`CliError`]: why a command failed, and the one place exit codes are decided.
//!
//! | code | meaning |
//! |---|---|
//! | 0 | done |
//! | 1 | the work failed: a solver blow-up, cache or output I/O, a closed or full stdout |
//! | 2 | bad input: the scene, a file, an option, an environment variable |
//!
//! The library's errors ([`hairsys::Error`], [`hairsys::output::OutputError`]) say what went
//! wrong; which exit code that is, is the command's decision, made in [`CliError::exit_code`].

use hairsys::output::OutputError;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Bad input the command itself found: a flag, a file name, an environment variable. The
    /// message names it and the fix.
    #[error("{0}")]
    Input(String),
    /// Work the command itself could not do (writing a file it was asked for). The message
    /// names the file and the reason.
    #[error("{0}")]
    Failed(String),
    /// What the library refused or could not do.
    #[error("{0}")]
    Library(#[from] hairsys::Error),
    /// A scene file the library could not use.
    #[error("{0}")]
    Scene(#[from] hairsys::scene::SceneError),
    /// An output (children, shot export, preview, cards, quality report) the library could
    /// not make.
    #[error("{0}")]
    Output(Box<OutputError>),
    /// A shot file the library could not use.
    #[error("{0}")]
    Shot(#[from] hairsys::shot::ShotError),
    /// A farm job that could not be written, or a task of one that could not run.
    #[error("{0}")]
    Farm(Box<hairsys::farm::FarmError>),
}

impl From<hairsys::farm::FarmError> for CliError {
    fn from(e: hairsys::farm::FarmError) -> Self {
        CliError::Farm(Box::new(e))
    }
}

impl From<OutputError> for CliError {
    fn from(e: OutputError) -> Self {
        CliError::Output(Box::new(e))
    }
}

impl CliError {
    /// Bad input, with its message.
    pub fn input(message: impl Into<String>) -> Self {
        CliError::Input(message.into())
    }

    /// Failed work, with its message.
    pub fn failed(message: impl Into<String>) -> Self {
        CliError::Failed(message.into())
    }

    /// The process exit code: 2 for bad input, 1 for work that failed (see the module docs).
    pub fn exit_code(&self) -> u8 {
        use hairsys::Error as E;
        match self {
            CliError::Input(_) | CliError::Scene(_) | CliError::Shot(_) => 2,
            CliError::Farm(e) => {
                if e.is_bad_input() {
                    2
                } else {
                    1
                }
            }
            CliError::Failed(_) => 1,
            CliError::Library(e) => match e {
                E::Scene(_) | E::Usage(_) | E::Argument { .. } => 2,
                E::Solver { .. } | E::Cache(_) | E::Output(_) | E::Failed { .. } => 1,
            },
            CliError::Output(e) => {
                if e.is_bad_input() {
                    2
                } else {
                    1
                }
            }
        }
    }
}
