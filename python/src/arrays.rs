//! Host arrays in: numpy arrays (or anything `numpy.asarray` takes) checked for shape and dtype
//! and read as the flat Rust slices the library takes; and arrays out, handed to numpy without
//! copying.
//!
//! Float inputs accept float32 and float64 (converted to f32); index inputs accept any integer
//! dtype (range-checked). A float32 C-contiguous `(N, 3)` array is read in place, without a
//! copy (the per-frame scalp vertices of a DCC are such arrays).

use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use numpy::ndarray::Array2;
use numpy::{
    PyArray1, PyArray2, PyArrayDescrMethods, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::argument;

/// `obj` as a numpy array (no copy when it already is one).
fn as_array<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    let np = obj.py().import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj,))
        .map_err(|e| argument(name, format!("is not an array ({e})")))?;
    arr.cast_into::<PyUntypedArray>()
        .map_err(|_| argument(name, "is not an array"))
}

/// The dtype kind (`'f'`, `'i'`, `'u'`…) and item size of `arr`.
fn kind(arr: &Bound<'_, PyUntypedArray>) -> (char, usize) {
    let d = arr.dtype();
    (d.kind() as char, d.itemsize())
}

/// Checks that `arr` has `shape` (`None` = any length on that axis), naming `expected`.
fn check_shape(
    arr: &Bound<'_, PyUntypedArray>,
    name: &str,
    columns: Option<usize>,
    expected: &str,
) -> PyResult<()> {
    let shape = arr.shape();
    let ok = match columns {
        Some(c) => shape.len() == 2 && shape[1] == c,
        None => shape.len() == 1,
    };
    if ok {
        Ok(())
    } else {
        Err(argument(
            name,
            format!("has shape {shape:?}, expected {expected}"),
        ))
    }
}

/// Rows of `N` floats (float32 or float64) as `[f32; N]`, passed to `f`; float32 C-contiguous
/// arrays are read in place.
pub fn with_float_rows<const N: usize, R>(
    obj: &Bound<'_, PyAny>,
    name: &str,
    expected: &str,
    f: impl FnOnce(&[[f32; N]]) -> PyResult<R>,
) -> PyResult<R>
where
    [f32; N]: bytemuck::Pod,
{
    let arr = as_array(obj, name)?;
    check_shape(&arr, name, Some(N), expected)?;
    match kind(&arr) {
        ('f', 4) => {
            let typed = arr.cast::<PyArray2<f32>>()?.readonly();
            match typed.as_slice() {
                Ok(flat) => f(as_rows(flat)),
                Err(_) => {
                    let copy: Vec<f32> = typed.as_array().iter().copied().collect();
                    f(as_rows(&copy))
                }
            }
        }
        ('f', 8) => {
            let typed = arr.cast::<PyArray2<f64>>()?.readonly();
            let copy: Vec<f32> = typed.as_array().iter().map(|&x| x as f32).collect();
            f(as_rows(&copy))
        }
        (k, size) => Err(argument(
            name,
            format!(
                "has dtype kind '{k}' of {size} bytes, expected float32 or float64 of {expected}"
            ),
        )),
    }
}

/// A flat slice of `N`-float rows as rows (its length is a multiple of `N` by its shape).
fn as_rows<const N: usize>(flat: &[f32]) -> &[[f32; N]]
where
    [f32; N]: bytemuck::Pod,
{
    bytemuck::cast_slice(flat)
}

/// Rows of `N` floats as an owned vector.
pub fn float_rows<const N: usize>(
    obj: &Bound<'_, PyAny>,
    name: &str,
    expected: &str,
) -> PyResult<Vec<[f32; N]>>
where
    [f32; N]: bytemuck::Pod,
{
    with_float_rows(obj, name, expected, |rows| Ok(rows.to_vec()))
}

/// A 1-D boolean array (numpy dtype `bool`) as bools.
pub fn bools(obj: &Bound<'_, PyAny>, name: &str, expected: &str) -> PyResult<Vec<bool>> {
    let arr = as_array(obj, name)?;
    check_shape(&arr, name, None, expected)?;
    match kind(&arr) {
        ('b', 1) => Ok(arr.cast::<PyArray1<bool>>()?.readonly().as_array().to_vec()),
        (k, size) => Err(argument(
            name,
            format!("has dtype kind '{k}' of {size} bytes, expected bool of {expected}"),
        )),
    }
}

/// A 1-D float array (float32 or float64) as f32.
pub fn floats(obj: &Bound<'_, PyAny>, name: &str, expected: &str) -> PyResult<Vec<f32>> {
    let arr = as_array(obj, name)?;
    check_shape(&arr, name, None, expected)?;
    match kind(&arr) {
        ('f', 4) => Ok(arr.cast::<PyArray1<f32>>()?.readonly().as_array().to_vec()),
        ('f', 8) => Ok(arr
            .cast::<PyArray1<f64>>()?
            .readonly()
            .as_array()
            .iter()
            .map(|&x| x as f32)
            .collect()),
        (k, size) => Err(argument(
            name,
            format!("has dtype kind '{k}' of {size} bytes, expected float32 or float64 {expected}"),
        )),
    }
}

/// Integers (any integer dtype, 1-D or `(M, columns)`) as u32, each checked to be in range.
pub fn indices(
    obj: &Bound<'_, PyAny>,
    name: &str,
    columns: Option<usize>,
    expected: &str,
) -> PyResult<Vec<u32>> {
    let arr = as_array(obj, name)?;
    check_shape(&arr, name, columns, expected)?;
    let (k, size) = kind(&arr);
    if !matches!(k, 'i' | 'u') {
        return Err(argument(
            name,
            format!("has dtype kind '{k}' of {size} bytes, expected integers of {expected}"),
        ));
    }
    let wide = arr.call_method1("astype", ("int64",))?;
    let values: Vec<i64> = match columns {
        Some(_) => wide
            .cast::<PyArray2<i64>>()?
            .readonly()
            .as_array()
            .iter()
            .copied()
            .collect(),
        None => wide.cast::<PyArray1<i64>>()?.readonly().as_array().to_vec(),
    };
    values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            u32::try_from(v).map_err(|_| {
                argument(
                    name,
                    format!("entry {i} is {v}, expected an index from 0 to {}", u32::MAX),
                )
            })
        })
        .collect()
}

/// Largest deviation of a rigid matrix's rotation part from orthonormality accepted.
const RIGID_TOLERANCE: f32 = 1e-4;

/// A 4×4 matrix (row-major as numpy prints it: `M @ [x, y, z, 1]`) as a rigid transform;
/// refuses a scaled, sheared, projective or non-finite matrix, naming `name`.
pub fn isometry(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Isometry3<f32>> {
    let rows: Vec<[f32; 4]> = float_rows::<4>(obj, name, "(4, 4)")?;
    if rows.len() != 4 {
        return Err(argument(
            name,
            format!("has {} rows, expected a (4, 4) matrix", rows.len()),
        ));
    }
    if rows.iter().flatten().any(|x| !x.is_finite()) {
        return Err(argument(
            name,
            "is not finite: give a finite (4, 4) rigid matrix",
        ));
    }
    let m = Matrix3::from_fn(|r, c| rows[r][c]);
    let t = Vector3::new(rows[0][3], rows[1][3], rows[2][3]);
    let orthonormal = (m.transpose() * m - Matrix3::identity()).abs().max();
    let bottom = [rows[3][0], rows[3][1], rows[3][2], rows[3][3] - 1.0];
    if orthonormal > RIGID_TOLERANCE
        || m.determinant() <= 0.0
        || bottom.iter().any(|x| x.abs() > RIGID_TOLERANCE)
    {
        return Err(argument(
            name,
            "is not rigid (it scales, shears, mirrors or projects): hair follows rigid motion \
             only; pass the world-space vertices as scalp_vertices with an identity matrix \
             instead (or remove the scale from the object)",
        ));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m));
    Ok(Isometry3::from_parts(Translation3::from(t), rotation))
}

/// `rows` (`[f32; 3]` per point) handed to numpy as an `(N, 3)` float32 array that owns the
/// vector (no copy).
pub fn rows_to_numpy<'py>(
    py: Python<'py>,
    rows: Vec<nalgebra::Vector3<f32>>,
) -> Bound<'py, PyArray2<f32>> {
    let n = rows.len();
    let flat = flatten(rows);
    let array = Array2::from_shape_vec((n, 3), flat).expect("3 floats per row");
    PyArray2::from_owned_array(py, array)
}

/// The floats of `rows`, taking over the allocation.
fn flatten(rows: Vec<nalgebra::Vector3<f32>>) -> Vec<f32> {
    let mut rows = std::mem::ManuallyDrop::new(rows);
    let (ptr, len, cap) = (rows.as_mut_ptr(), rows.len(), rows.capacity());
    // SAFETY: `Vector3<f32>` is `repr(C)` over `[[f32; 3]; 1]` (size 12, align 4, no padding),
    // so `cap` vectors are `3 cap` f32 with the same size and alignment: the allocation's
    // layout is the one `Vec<f32>` of capacity `3 cap` frees, and `3 len` floats are initialised.
    unsafe { Vec::from_raw_parts(ptr.cast::<f32>(), 3 * len, 3 * cap) }
}
