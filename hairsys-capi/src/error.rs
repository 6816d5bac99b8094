//! Status codes, the thread-local last error and the guard every entry point runs in.
//!
//! Every function of the C API returns a [`HairsysStatus`]. The call also leaves its status and
//! a message (UTF-8, naming the argument and the fix) in storage local to the calling thread,
//! read with [`hairsys_last_error_code`] and [`hairsys_last_error_message`]: a successful call
//! clears them (code [`HairsysStatus::Ok`], empty message).
//!
//! Nothing unwinds across the boundary: [`guard`] runs the body inside
//! [`std::panic::catch_unwind`] and turns a panic into [`HairsysStatus::Panic`]. A panic inside a
//! session (or cache) call poisons that handle, whose state may be half-updated: every later
//! call on it returns [`HairsysStatus::Poisoned`] with the panic's message, and only
//! destroying it is allowed.

use std::cell::RefCell;
use std::ffi::{c_char, CString};
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// The outcome of a call. `HAIRSYS_STATUS_OK` (0) is success; every other value is an error
/// whose message [`hairsys_last_error_message`] gives on the same thread.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HairsysStatus {
    /// Success.
    Ok = 0,
    /// A pointer argument that must not be NULL was NULL (the message names it).
    NullPointer = 1,
    /// A pointer argument is not aligned for its type (4 bytes for `float` and `uint32_t`
    /// arrays, 8 for handles and structs holding pointers).
    Misaligned = 2,
    /// An array's length does not match what the session expects, or overflows the address
    /// space (the message gives the expected length).
    BadLength = 3,
    /// A float argument is NaN or infinite (the message names the argument and the index).
    NotFinite = 4,
    /// A value is out of range or unusable (the message names the argument and what is
    /// expected): a bad option, a collider id the session does not have, a path that is not
    /// UTF-8, an unknown enum value, a quaternion that is not unit, a thread count over
    /// `HAIRSYS_MAX_THREADS`, hair or child counts over the library's 8 GiB memory budget.
    BadArgument = 5,
    /// The scene file cannot be used (the message names the file, the key and the fix).
    Scene = 6,
    /// The solver refused the setup or blew up (the message names the frame, the strand and
    /// the stability bound). The session is failed: restore a snapshot or destroy it.
    Solver = 7,
    /// The session's last step failed and it was stepped again: restore a snapshot or destroy
    /// it.
    SessionFailed = 8,
    /// A cache could not be written or read.
    Cache = 9,
    /// An output (a USD file) could not be made.
    Output = 10,
    /// A bug in hairsys: a Rust panic, caught before it reached the host. The handle the call
    /// was made on is poisoned.
    Panic = 11,
    /// The handle was poisoned by an earlier panic: destroy it and build a new one.
    Poisoned = 12,
    /// The handle is in use by another thread's call right now: a handle is used from one
    /// thread at a time.
    Busy = 13,
}

/// Why a call failed: a status code and its message. Built by the argument checks and from the
/// library's errors; turned into the thread-local last error by [`guard`].
#[derive(Debug)]
pub enum Failure {
    /// A NULL pointer where one is required.
    Null {
        /// The argument.
        argument: &'static str,
    },
    /// A pointer not aligned to `align` bytes.
    Misaligned {
        /// The argument.
        argument: &'static str,
        /// The alignment its type needs, bytes.
        align: usize,
    },
    /// An array of the wrong length.
    Length {
        /// The argument.
        argument: String,
        /// What was given and what is expected.
        message: String,
    },
    /// A NaN or infinite float.
    NotFinite {
        /// The argument.
        argument: String,
        /// The first bad element (float index).
        index: usize,
    },
    /// A value out of range, an unknown enum value, a path that is not UTF-8.
    Argument {
        /// The argument.
        argument: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// The library refused or failed.
    Library(hairsys::Error),
    /// A caught panic (the payload's message).
    Panic(String),
    /// A handle poisoned by an earlier panic (that panic's message).
    Poisoned(String),
    /// A handle used by two threads at once.
    Busy,
}

impl Failure {
    /// A [`Failure::Argument`].
    pub fn argument(argument: impl Into<String>, message: impl Into<String>) -> Self {
        Failure::Argument {
            argument: argument.into(),
            message: message.into(),
        }
    }

    /// The status code of this failure.
    pub fn status(&self) -> HairsysStatus {
        match self {
            Failure::Null { .. } => HairsysStatus::NullPointer,
            Failure::Misaligned { .. } => HairsysStatus::Misaligned,
            Failure::Length { .. } => HairsysStatus::BadLength,
            Failure::NotFinite { .. } => HairsysStatus::NotFinite,
            Failure::Argument { .. } => HairsysStatus::BadArgument,
            Failure::Library(e) => match e {
                hairsys::Error::Scene(_) => HairsysStatus::Scene,
                hairsys::Error::Usage(_) | hairsys::Error::Argument { .. } => {
                    HairsysStatus::BadArgument
                }
                hairsys::Error::Solver { .. } => HairsysStatus::Solver,
                hairsys::Error::Failed { .. } => HairsysStatus::SessionFailed,
                hairsys::Error::Cache(_) => HairsysStatus::Cache,
                hairsys::Error::Output(_) => HairsysStatus::Output,
            },
            Failure::Panic(_) => HairsysStatus::Panic,
            Failure::Poisoned(_) => HairsysStatus::Poisoned,
            Failure::Busy => HairsysStatus::Busy,
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Null { argument } => {
                write!(f, "{argument}: is NULL; pass a valid pointer")
            }
            Failure::Misaligned { argument, align } => write!(
                f,
                "{argument}: is not aligned to {align} bytes; pass a pointer to an array of its \
                 type (not into the middle of a byte buffer)"
            ),
            Failure::Length { argument, message } | Failure::Argument { argument, message } => {
                write!(f, "{argument}: {message}")
            }
            Failure::NotFinite { argument, index } => write!(
                f,
                "{argument}: float {index} is NaN or infinite; give finite values"
            ),
            Failure::Library(e) => write!(f, "{e}"),
            Failure::Panic(what) => write!(
                f,
                "hairsys bug (a Rust panic, caught before it reached the host): {what}; the \
                 session or cache the call was made on is poisoned: destroy it; please report \
                 this"
            ),
            Failure::Poisoned(what) => write!(
                f,
                "this handle is poisoned by an earlier internal error ({what}): destroy it and \
                 build a new one"
            ),
            Failure::Busy => write!(
                f,
                "this handle is in use by another thread's call: use a handle from one thread \
                 at a time"
            ),
        }
    }
}

impl From<hairsys::Error> for Failure {
    fn from(e: hairsys::Error) -> Self {
        Failure::Library(e)
    }
}

impl From<hair_cache::CacheError> for Failure {
    fn from(e: hair_cache::CacheError) -> Self {
        Failure::Library(hairsys::Error::Cache(e))
    }
}

/// The last call's status and message on this thread.
struct LastError {
    status: HairsysStatus,
    message: CString,
}

thread_local! {
    static LAST: RefCell<LastError> = RefCell::new(LastError {
        status: HairsysStatus::Ok,
        message: CString::default(),
    });
}

/// Records `result` as this thread's last error and returns its status. On a thread whose
/// thread-local storage is being torn down (a call from a thread-exit destructor) the status
/// is returned without a message.
fn record(result: Result<(), Failure>) -> HairsysStatus {
    let status = match &result {
        Ok(()) => HairsysStatus::Ok,
        Err(failure) => failure.status(),
    };
    LAST.try_with(|last| {
        let mut last = last.borrow_mut();
        match result {
            Ok(()) if last.status == HairsysStatus::Ok => {}
            Ok(()) => {
                last.status = HairsysStatus::Ok;
                last.message = CString::default();
            }
            Err(failure) => {
                // A message never holds NUL: the few that could (a path) lose it.
                let text = failure.to_string().replace('\0', "");
                last.status = status;
                last.message = CString::new(text).unwrap_or_default();
            }
        }
        status
    })
    .unwrap_or(status)
}

/// The message of a caught panic's payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Runs the body of an entry point: a panic becomes [`HairsysStatus::Panic`], and the result
/// becomes this thread's last error.
pub fn guard(body: impl FnOnce() -> Result<(), Failure>) -> HairsysStatus {
    let result = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(r) => r,
        Err(payload) => Err(Failure::Panic(panic_message(&*payload))),
    };
    record(result)
}

/// The status of the last hairsys call made on the calling thread (`HAIRSYS_STATUS_OK` after a
/// success).
#[no_mangle]
pub extern "C" fn hairsys_last_error_code() -> HairsysStatus {
    LAST.try_with(|last| last.borrow().status)
        .unwrap_or(HairsysStatus::Ok)
}

/// The message of the last hairsys call made on the calling thread: NUL-terminated UTF-8,
/// empty after a success, never NULL. Owned by the library; valid until the next hairsys call
/// on the same thread (copy it to keep it).
#[no_mangle]
pub extern "C" fn hairsys_last_error_message() -> *const c_char {
    LAST.try_with(|last| last.borrow().message.as_ptr())
        .unwrap_or(c"".as_ptr())
}
