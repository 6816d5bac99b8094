//! `hairsys.Cache`: frames of an MCAP point cache read back (the Blender add-on's playback).

use std::path::PathBuf;

use hair_cache::{CacheReader, Interpolation};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::rows_to_numpy;
use crate::errors::{guard, CacheError};

/// A hairsys MCAP cache opened for reading (`hairsys.Cache(path)`).
///
/// `frame(n)` returns `(positions, velocities)`, each (P, 3) float32 (m, m/s) in the layout of
/// `strand_offsets`; the arrays own the decoded frame (no copy after decoding). Raises
/// CacheError for a file that is not a finished hairsys cache or a frame it does not hold.
#[pyclass(name = "Cache", module = "hairsys")]
pub struct PyCache {
    reader: CacheReader,
}

/// `(positions, velocities)`, each `(P, 3)` float32.
type FrameArrays<'py> = (Bound<'py, PyArray2<f32>>, Bound<'py, PyArray2<f32>>);

fn cache_error(e: hair_cache::CacheError) -> PyErr {
    CacheError::new_err(e.to_string())
}

#[pymethods]
impl PyCache {
    /// Opens the cache at `path`.
    #[new]
    fn open(path: PathBuf) -> PyResult<Self> {
        guard(|| {
            Ok(Self {
                reader: CacheReader::open(&path).map_err(cache_error)?,
            })
        })
    }

    /// Frame numbers stored, in increasing order.
    #[getter]
    fn frames(&self) -> Vec<u32> {
        self.reader.frame_numbers().to_vec()
    }

    /// Frames per second.
    #[getter]
    fn fps(&self) -> f64 {
        self.reader.header().fps
    }

    /// Strand s is points `strand_offsets[s]:strand_offsets[s+1]`.
    #[getter]
    fn strand_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        PyArray1::from_slice(py, &self.reader.layout().offsets)
    }

    /// Number of points per frame.
    #[getter]
    fn point_count(&self) -> usize {
        self.reader.layout().point_count()
    }

    /// The scene text stored in the cache (empty for a session built from arrays).
    #[getter]
    fn scene_toml(&self) -> String {
        self.reader.header().scene_toml.clone()
    }

    /// `(positions, velocities)` of frame `n`, each (P, 3) float32.
    fn frame<'py>(&mut self, py: Python<'py>, n: u32) -> PyResult<FrameArrays<'py>> {
        let f = guard(|| self.reader.read_frame(n).map_err(cache_error))?;
        Ok((
            rows_to_numpy(py, f.positions),
            rows_to_numpy(py, f.velocities),
        ))
    }

    /// `(positions, velocities)` at `time` s, between frames by cubic Hermite interpolation
    /// with the cached velocities (motion-blur samples).
    fn sample<'py>(&mut self, py: Python<'py>, time: f64) -> PyResult<FrameArrays<'py>> {
        let f = guard(|| {
            self.reader
                .sample(time, Interpolation::Hermite)
                .map_err(cache_error)
        })?;
        Ok((
            rows_to_numpy(py, f.positions),
            rows_to_numpy(py, f.velocities),
        ))
    }

    fn __len__(&self) -> usize {
        self.reader.frame_count()
    }

    fn __repr__(&self) -> String {
        format!(
            "<hairsys.Cache {} · {} frames · {} points>",
            self.reader.path().display(),
            self.reader.frame_count(),
            self.reader.layout().point_count()
        )
    }
}
