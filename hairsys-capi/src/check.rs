//! The checks every pointer, array, string and float from the host goes through before it is
//! read: NULL, alignment, length (in elements, overflow-checked before anything is read or
//! allocated), finiteness, UTF-8.
//!
//! The one thing no check can see is whether an array really holds as many elements as the
//! host says: that is the host's promise, written on every function that takes one.

use std::ffi::{c_char, CStr};
use std::path::PathBuf;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion};

use crate::error::Failure;
use crate::types::HairsysTransform;

/// Refuses a NULL or misaligned `ptr` to a `T`.
pub fn pointer<T>(ptr: *const T, argument: &'static str) -> Result<(), Failure> {
    if ptr.is_null() {
        return Err(Failure::Null { argument });
    }
    if !ptr.is_aligned() {
        return Err(Failure::Misaligned {
            argument,
            align: std::mem::align_of::<T>(),
        });
    }
    Ok(())
}

/// Drops a handle made by `Box::into_raw`: NULL and misaligned pointers are ignored, and a
/// panic in a destructor stays on this side of the boundary.
///
/// # Safety
/// `handle` is NULL or a live handle made by `Box::into_raw`, not used again.
pub unsafe fn destroy<T>(handle: *mut T) {
    if handle.is_null() || !handle.is_aligned() {
        return;
    }
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // SAFETY: the caller's promise: a live handle made by `Box::into_raw`.
        drop(unsafe { Box::from_raw(handle) });
    }));
}

/// `&*ptr`, checked for NULL and alignment.
///
/// # Safety
/// A non-NULL `ptr` points to a valid `T` for the returned lifetime.
pub unsafe fn reference<'a, T>(ptr: *const T, argument: &'static str) -> Result<&'a T, Failure> {
    pointer(ptr, argument)?;
    // SAFETY: non-NULL and aligned (checked); valid by the caller's promise.
    Ok(unsafe { &*ptr })
}

/// `&mut *ptr` for an out-parameter, checked for NULL and alignment.
///
/// # Safety
/// A non-NULL `ptr` points to writable memory for a `T` (it may be uninitialised: it is only
/// written).
pub unsafe fn out<'a, T>(
    ptr: *mut T,
    argument: &'static str,
) -> Result<&'a mut std::mem::MaybeUninit<T>, Failure> {
    pointer(ptr.cast_const(), argument)?;
    // SAFETY: non-NULL and aligned (checked); writable by the caller's promise.
    Ok(unsafe { &mut *(ptr as *mut std::mem::MaybeUninit<T>) })
}

/// The array of `count` elements of `N` `T`s each at `ptr`: NULL is allowed only when `count`
/// is 0; the byte size is checked against the address space before the slice is made.
///
/// # Safety
/// A non-NULL `ptr` points to at least `count * N` valid `T`s for the returned lifetime.
pub unsafe fn array<'a, T, const N: usize>(
    ptr: *const T,
    count: usize,
    argument: &'static str,
) -> Result<&'a [[T; N]], Failure> {
    if count == 0 {
        return Ok(&[]);
    }
    pointer(ptr, argument)?;
    let fits = count
        .checked_mul(N * std::mem::size_of::<T>())
        .is_some_and(|bytes| bytes <= isize::MAX as usize);
    if !fits {
        return Err(Failure::Length {
            argument: argument.into(),
            message: format!(
                "{count} elements of {N} values do not fit in memory: pass the number of \
                 elements, not of bytes"
            ),
        });
    }
    // SAFETY: non-NULL, aligned, size within isize::MAX (checked); `[T; N]` has `T`'s
    // alignment; valid by the caller's promise.
    Ok(unsafe { std::slice::from_raw_parts(ptr as *const [T; N], count) })
}

/// [`array()`] of writable elements, for the host's output buffers.
///
/// # Safety
/// A non-NULL `ptr` points to at least `count * N` writable `T`s for the returned lifetime,
/// not aliased by anything else the call reads.
pub unsafe fn array_mut<'a, T, const N: usize>(
    ptr: *mut T,
    count: usize,
    argument: &'static str,
) -> Result<&'a mut [[T; N]], Failure> {
    // SAFETY: the same promise as `array`'s, for writing.
    let shared = unsafe { array::<T, N>(ptr.cast_const(), count, argument)? };
    // SAFETY: `shared` came from `ptr`, which the caller gives for writing.
    Ok(unsafe { std::slice::from_raw_parts_mut(shared.as_ptr() as *mut [T; N], shared.len()) })
}

/// Refuses NaN and infinities in `values`, naming the first bad float.
pub fn finite<const N: usize>(values: &[[f32; N]], argument: &str) -> Result<(), Failure> {
    match values.iter().flatten().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(index) => Err(Failure::NotFinite {
            argument: argument.into(),
            index,
        }),
    }
}

/// Refuses a NaN or infinite scalar.
pub fn finite_scalar(value: f32, argument: &str) -> Result<(), Failure> {
    finite(&[[value]], argument)
}

/// A `0`/`1` flag.
pub fn flag(value: u32, argument: &str) -> Result<bool, Failure> {
    match value {
        0 => Ok(false),
        1 => Ok(true),
        other => Err(Failure::argument(
            argument,
            format!("= {other}: give 0 (off) or 1 (on)"),
        )),
    }
}

/// A NUL-terminated UTF-8 string.
///
/// # Safety
/// A non-NULL `ptr` points to a NUL-terminated string.
pub unsafe fn string<'a>(ptr: *const c_char, argument: &'static str) -> Result<&'a str, Failure> {
    if ptr.is_null() {
        return Err(Failure::Null { argument });
    }
    // SAFETY: non-NULL; NUL-terminated by the caller's promise.
    let text = unsafe { CStr::from_ptr(ptr) };
    text.to_str()
        .map_err(|e| Failure::argument(argument, format!("is not UTF-8 ({e}): pass a UTF-8 path")))
}

/// A file path, as [`string`].
///
/// # Safety
/// As [`string`].
pub unsafe fn path(ptr: *const c_char, argument: &'static str) -> Result<PathBuf, Failure> {
    // SAFETY: forwarded.
    Ok(PathBuf::from(unsafe { string(ptr, argument)? }))
}

/// Largest departure of a rotation quaternion's length from 1 that is taken as unit (a
/// `HairsysTransform` beyond it is refused).
pub const HAIRSYS_QUATERNION_TOLERANCE: f32 = 1e-4;

/// The rigid transform `t`: finite, with a unit quaternion (taken as given, not renormalised,
/// so the same floats give the same bits as a Rust host's `UnitQuaternion::new_unchecked`).
pub fn transform(t: &HairsysTransform, argument: &str) -> Result<Isometry3<f32>, Failure> {
    finite(&[t.translation], argument)?;
    finite(&[t.rotation], argument).map_err(|e| match e {
        Failure::NotFinite { argument, index } => Failure::NotFinite {
            argument,
            index: index + 3,
        },
        other => other,
    })?;
    let [x, y, z, w] = t.rotation;
    let q = Quaternion::new(w, x, y, z);
    if (q.norm() - 1.0).abs() > HAIRSYS_QUATERNION_TOLERANCE {
        return Err(Failure::argument(
            argument,
            format!(
                "rotation (x, y, z, w) = ({x}, {y}, {z}, {w}) has length {}: give a unit \
                 quaternion (normalise it; the identity is (0, 0, 0, 1))",
                q.norm()
            ),
        ));
    }
    let [tx, ty, tz] = t.translation;
    Ok(Isometry3::from_parts(
        Translation3::new(tx, ty, tz),
        UnitQuaternion::new_unchecked(q),
    ))
}
