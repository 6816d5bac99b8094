//! `hairsys.Children`: render children as numpy arrays that own the library's buffers (moved,
//! not copied).

use hair_render::ChildBuffers;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// Render children of a frame (`Session.children(...)`): flat buffers a host's curves or an
/// exporter consume directly.
///
/// `vertex_counts` (C,) uint32: points per child curve; `points` (N, 3) float32, m;
/// `widths` (N,) float32, m; `parent` (C,) uint32: the strand each child follows; `root_uv`
/// (C, 2) float32 or None: the scalp UV at each root.
#[pyclass(name = "Children", module = "hairsys", frozen)]
pub struct Children {
    vertex_counts: Py<PyArray1<u32>>,
    points: Py<PyArray2<f32>>,
    widths: Py<PyArray1<f32>>,
    parent: Py<PyArray1<u32>>,
    root_uv: Option<Py<PyArray2<f32>>>,
}

impl Children {
    /// Wraps `buffers`, moving each into a numpy array.
    pub fn new(buffers: ChildBuffers) -> impl FnOnce(Python<'_>) -> PyResult<Self> {
        move |py| {
            let n = buffers.points.len() / 3;
            let points = Array2::from_shape_vec((n, 3), buffers.points)
                .map_err(|e| crate::errors::InternalError::new_err(e.to_string()))?;
            let root_uv = match buffers.root_uv {
                Some(uv) => {
                    let c = uv.len() / 2;
                    let a = Array2::from_shape_vec((c, 2), uv)
                        .map_err(|e| crate::errors::InternalError::new_err(e.to_string()))?;
                    Some(PyArray2::from_owned_array(py, a).unbind())
                }
                None => None,
            };
            Ok(Self {
                vertex_counts: buffers.vertex_counts.into_pyarray(py).unbind(),
                points: PyArray2::from_owned_array(py, points).unbind(),
                widths: buffers.widths.into_pyarray(py).unbind(),
                parent: buffers.parent.into_pyarray(py).unbind(),
                root_uv,
            })
        }
    }
}

#[pymethods]
impl Children {
    /// Points per child curve, (C,) uint32.
    #[getter]
    fn vertex_counts(&self, py: Python<'_>) -> Py<PyArray1<u32>> {
        self.vertex_counts.clone_ref(py)
    }

    /// Every child's points, root first, curve after curve, (N, 3) float32, m.
    #[getter]
    fn points(&self, py: Python<'_>) -> Py<PyArray2<f32>> {
        self.points.clone_ref(py)
    }

    /// Width at every point, (N,) float32, m.
    #[getter]
    fn widths(&self, py: Python<'_>) -> Py<PyArray1<f32>> {
        self.widths.clone_ref(py)
    }

    /// The strand each child follows, (C,) uint32.
    #[getter]
    fn parent(&self, py: Python<'_>) -> Py<PyArray1<u32>> {
        self.parent.clone_ref(py)
    }

    /// Scalp UV at each child's root, (C, 2) float32, or None when the scalp has no UVs.
    #[getter]
    fn root_uv(&self, py: Python<'_>) -> Option<Py<PyArray2<f32>>> {
        self.root_uv.as_ref().map(|a| a.clone_ref(py))
    }

    /// Number of child curves.
    fn __len__(&self, py: Python<'_>) -> usize {
        self.vertex_counts.bind(py).len()
    }
}
