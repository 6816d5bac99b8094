//! # hairsys for Python
//!
//! The `hairsys` Python module (pyo3 + numpy, an abi3 wheel for CPython ≥ 3.11 built by
//! maturin; see `python/pyproject.toml` and the type stub `python/hairsys.pyi`): the library's
//! [`hairsys::Session`] for Python hosts such as Blender, Houdini or Maya.
//!
//! - [`session`]: `hairsys.Session` (`from_scene`, `from_groom`, `step`, zero-copy
//!   `positions`/`velocities`, collider and parameter setters, snapshots, caches, children);
//! - [`cache`]: `hairsys.Cache`, frames of a cache read back;
//! - [`children`]: `hairsys.Children`, render children as numpy arrays;
//! - [`errors`]: the typed exceptions and the panic guard;
//! - [`arrays`], [`groom`]: host arrays checked and converted.
//!
//! ```python
//! import hairsys
//! s = hairsys.Session.from_scene("scenes/default.toml")
//! for _ in range(24):
//!     s.step()
//! print(s.frame, s.positions.shape)
//! ```

use pyo3::prelude::*;

pub mod arrays;
pub mod cache;
pub mod children;
pub mod errors;
pub mod groom;
pub mod session;

/// The `hairsys` module.
#[pymodule]
#[pyo3(name = "hairsys")]
fn hairsys_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<session::PySession>()?;
    m.add_class::<session::PySnapshot>()?;
    m.add_class::<cache::PyCache>()?;
    m.add_class::<children::Children>()?;
    errors::register(m)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
