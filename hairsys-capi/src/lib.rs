//! # hairsys for C and C++
//!
//! A C ABI over [`hairsys::Session`] for hosts written in C or C++ (a Houdini SOP, a Maya
//! node, a pipeline tool): `libhairsys_capi.so` / `libhairsys_capi.a`, the header
//! `include/hairsys.h` generated from this crate by cbindgen (a test fails when it is out of
//! date), and the header-only C++ wrapper `include/hairsys.hpp` (RAII handles, `std::span`
//! views, exceptions). The guide is `docs/c-api.md`.
//!
//! The API mirrors the Rust session: create a session from a scene file or from the host's
//! arrays ([`session`], [`groom`]), set the scalp and the colliders for the next frame, step,
//! read positions and velocities without a copy, snapshot and restore, record a cache, make
//! render children ([`children`]), read a cache back and write it as USD ([`cache`]).
//!
//! # Conventions
//! - **Units and layouts.** SI units (m, s, kg); point arrays are `float` xyz interleaved and
//!   counted in points; transforms are a translation and a unit quaternion `(x, y, z, w)`
//!   ([`HairsysTransform`]), body to world.
//! - **Errors.** Every call returns a [`HairsysStatus`]; the message of the last call on the
//!   calling thread is [`hairsys_last_error_message`] ([`error`]). NULL and misaligned
//!   pointers, lengths that do not match, NaN and infinities, unknown enum values and paths
//!   that are not UTF-8 are refused with a status, never read. No panic crosses the boundary: a
//!   handle in which one happened is poisoned.
//! - **Ownership.** Every handle a create call writes (`HairsysSession`, `HairsysSnapshot`,
//!   `HairsysChildren`, `HairsysCache`) is owned by the host and released by its `_destroy`
//!   (NULL is ignored). Arrays the host passes are read during the call and not kept. Views
//!   the library writes point into a handle's memory and are valid until the next call that
//!   changes that handle, or its destruction.
//! - **Threads.** A handle is used from one thread at a time (a concurrent call gets
//!   `HAIRSYS_STATUS_BUSY`); different handles are independent. A session steps on its own
//!   pool of `threads` workers, or on the library's shared pool (`threads` = 0); results do
//!   not depend on the thread count.
//! - **ABI version.** [`hairsys_abi_version`] returns `major << 16 | minor` of the library
//!   loaded. A host built against the header's [`HAIRSYS_ABI_VERSION_MAJOR`] and
//!   [`HAIRSYS_ABI_VERSION_MINOR`] runs with a library of the same major and a minor at least
//!   as large. A minor version only adds functions and constants; anything that changes an
//!   existing function's signature or meaning, or any struct's layout, raises the major.

pub mod cache;
pub mod check;
pub mod children;
pub mod error;
pub mod groom;
pub mod session;
pub mod types;

pub use cache::*;
pub use children::*;
pub use error::{hairsys_last_error_code, hairsys_last_error_message, HairsysStatus};
pub use groom::hairsys_groom_options_default;
pub use session::*;
pub use types::*;

/// The ABI's major version: raised by any change that breaks a host built against an earlier
/// header (a signature, a meaning, a struct layout).
pub const HAIRSYS_ABI_VERSION_MAJOR: u32 = 1;
/// The ABI's minor version: raised when functions or constants are added.
pub const HAIRSYS_ABI_VERSION_MINOR: u32 = 0;
/// `HAIRSYS_ABI_VERSION_MAJOR << 16 | HAIRSYS_ABI_VERSION_MINOR`: what the header was made for.
pub const HAIRSYS_ABI_VERSION: u32 = (HAIRSYS_ABI_VERSION_MAJOR << 16) | HAIRSYS_ABI_VERSION_MINOR;

/// The ABI version of the library loaded, `major << 16 | minor`. A host built against this
/// header runs with it when `version >> 16 == HAIRSYS_ABI_VERSION_MAJOR` and
/// `(version & 0xffff) >= HAIRSYS_ABI_VERSION_MINOR`.
#[no_mangle]
pub extern "C" fn hairsys_abi_version() -> u32 {
    HAIRSYS_ABI_VERSION
}
