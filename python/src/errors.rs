//! Python exceptions of the module, the mapping of [`hairsys::Error`] onto them, and the guard
//! that keeps a Rust panic from crossing into the host.
//!
//! | exception | base | raised for |
//! |---|---|---|
//! | `SceneError` | `ValueError` | a scene file that cannot be used ([`hairsys::Error::Scene`]) |
//! | `ArgumentError` | `ValueError` | an argument of the wrong shape, dtype, size or value |
//! | `SolverError` | `RuntimeError` | the solver refused the setup or blew up |
//! | `SessionFailedError` | `SolverError` | stepping a session whose last step failed |
//! | `CacheError` | `OSError` | a cache that cannot be written or read |
//! | `InternalError` | `RuntimeError` | a bug: a Rust panic, caught at the boundary |
//!
//! Every message is the Rust error's, which names the argument (or file and key) and the fix.
//!
//! # Panics
//! pyo3 turns a panic into `pyo3_runtime.PanicException`, a `BaseException` that hosts (Blender's
//! operators, `except Exception:`) do not catch, so the module catches panics itself
//! ([`guard`]) and raises `InternalError`; a session in which a panic happened is marked broken
//! and refuses further calls, since its state may be half-updated. Nothing in the library panics
//! on host input by design (bad input is an error), so this is a last line of defence.

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    hairsys,
    SceneError,
    PyValueError,
    "A scene file cannot be used; the message names the file, the key and the fix."
);
create_exception!(
    hairsys,
    ArgumentError,
    PyValueError,
    "An argument has the wrong shape, dtype, size or value; the message names the argument and \
     what is expected."
);
create_exception!(
    hairsys,
    SolverError,
    PyRuntimeError,
    "The solver refused the setup or blew up (names the frame, strand and stability bound)."
);
create_exception!(
    hairsys,
    SessionFailedError,
    SolverError,
    "The session's last step failed: restore a snapshot or build a new session."
);
create_exception!(
    hairsys,
    CacheError,
    PyOSError,
    "A cache cannot be written or read."
);
create_exception!(
    hairsys,
    InternalError,
    PyRuntimeError,
    "A bug in hairsys (a Rust panic caught at the module boundary); please report it."
);

/// The Python exception of a library error.
pub fn to_py(e: hairsys::Error) -> PyErr {
    let message = e.to_string();
    match e {
        hairsys::Error::Scene(_) => SceneError::new_err(message),
        hairsys::Error::Usage(_) | hairsys::Error::Argument { .. } => {
            ArgumentError::new_err(message)
        }
        hairsys::Error::Solver { .. } => SolverError::new_err(message),
        hairsys::Error::Failed { .. } => SessionFailedError::new_err(message),
        hairsys::Error::Cache(_) | hairsys::Error::Output(_) => CacheError::new_err(message),
    }
}

/// An `ArgumentError` for `argument`.
pub fn argument(argument: &str, message: impl std::fmt::Display) -> PyErr {
    ArgumentError::new_err(format!("{argument}: {message}"))
}

/// Runs `f`, turning a panic into `InternalError` (see the module docs).
pub fn guard<R>(f: impl FnOnce() -> PyResult<R>) -> PyResult<R> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(InternalError::new_err(panic_message(&*payload))),
    }
}

/// The message of a caught panic.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into());
    format!(
        "hairsys bug (a Rust panic, caught before it reached the host): {what}; please report it"
    )
}

/// Adds the exception types to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("ArgumentError", py.get_type::<ArgumentError>())?;
    m.add("SolverError", py.get_type::<SolverError>())?;
    m.add("SessionFailedError", py.get_type::<SessionFailedError>())?;
    m.add("CacheError", py.get_type::<CacheError>())?;
    m.add("InternalError", py.get_type::<InternalError>())?;
    Ok(())
}
