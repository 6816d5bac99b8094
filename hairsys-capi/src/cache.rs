//! `HairsysCache`: a finished cache read back frame by frame, and a cache written out as USD.

use std::sync::{Mutex, TryLockError};

use hair_cache::CacheReader;
use hairsys::output::shot_export::{export_shot, ShotOptions};

use crate::check;
use crate::error::{guard, panic_message, Failure, HairsysStatus};
use crate::types::{HairsysCacheInfo, HairsysIndexView};

/// A cache opened for reading (opaque). Made by `hairsys_cache_open`, owned by the host,
/// released with `hairsys_cache_destroy`; used from one thread at a time.
pub struct HairsysCache {
    inner: Mutex<Reader>,
}

struct Reader {
    reader: CacheReader,
    poisoned: Option<String>,
}

/// Runs `f` on the reader behind `handle` (busy, poisoned and panics as a session's calls).
///
/// # Safety
/// A non-NULL `handle` is live.
unsafe fn with_reader(
    handle: *const HairsysCache,
    f: impl FnOnce(&mut CacheReader) -> Result<(), Failure>,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let handle = unsafe { check::reference(handle, "cache")? };
        let mut inner = match handle.inner.try_lock() {
            Ok(g) => g,
            Err(TryLockError::WouldBlock) => return Err(Failure::Busy),
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
        };
        if let Some(why) = &inner.poisoned {
            return Err(Failure::Poisoned(why.clone()));
        }
        let reader = &mut inner.reader;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(reader))) {
            Ok(r) => r,
            Err(payload) => {
                let what = panic_message(&*payload);
                inner.poisoned = Some(what.clone());
                Err(Failure::Panic(what))
            }
        }
    })
}

/// Opens the finished cache at `path` (NUL-terminated UTF-8) and writes its handle to `*out`.
///
/// # Safety
/// `path` is NUL-terminated; `out` points to writable memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn hairsys_cache_open(
    path: *const std::ffi::c_char,
    out: *mut *mut HairsysCache,
) -> HairsysStatus {
    guard(|| {
        // SAFETY (both): the caller's promise.
        let out = unsafe { check::out(out, "out")? };
        let reader = CacheReader::open(unsafe { check::path(path, "path")? })?;
        out.write(Box::into_raw(Box::new(HairsysCache {
            inner: Mutex::new(Reader {
                reader,
                poisoned: None,
            }),
        })));
        Ok(())
    })
}

/// Writes what the cache holds to `*out`.
///
/// # Safety
/// `cache` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_cache_info(
    cache: *const HairsysCache,
    out: *mut HairsysCacheInfo,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_reader(cache, |r| {
            let frames = r.frame_numbers();
            let layout = r.layout();
            check::out(out, "out")?.write(HairsysCacheInfo {
                fps: r.header().fps,
                frame_count: frames.len(),
                first_frame: frames.first().copied().unwrap_or(0),
                last_frame: frames.last().copied().unwrap_or(0),
                strand_count: layout.offsets.len().saturating_sub(1),
                point_count: layout.point_count(),
            });
            Ok(())
        })
    }
}

/// Writes a view of the cache's strand offsets (strands + 1 values) to `*out`, valid until the
/// cache is destroyed.
///
/// # Safety
/// `cache` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_cache_strand_offsets(
    cache: *const HairsysCache,
    out: *mut HairsysIndexView,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_reader(cache, |r| {
            let o = &r.layout().offsets;
            check::out(out, "out")?.write(HairsysIndexView {
                data: o.as_ptr(),
                count: o.len(),
            });
            Ok(())
        })
    }
}

/// Copies frame `frame`'s positions (m) into `positions` and, unless `velocities` is NULL, its
/// velocities (m/s) into `velocities`: each `point_count` points, xyz interleaved, in the
/// cache's strand layout; `point_count` must be the cache's (`hairsys_cache_info`).
///
/// # Safety
/// `cache` is a live handle; `positions` (and `velocities` unless NULL) hold
/// `3 * point_count` writable floats.
#[no_mangle]
pub unsafe extern "C" fn hairsys_cache_read_frame(
    cache: *const HairsysCache,
    frame: u32,
    positions: *mut f32,
    velocities: *mut f32,
    point_count: usize,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_reader(cache, |r| {
            let expected = r.layout().point_count();
            if point_count != expected {
                return Err(Failure::Length {
                    argument: "point_count".into(),
                    message: format!(
                        "is {point_count}, the cache has {expected} points per frame: pass \
                         buffers of {expected} points (hairsys_cache_info)"
                    ),
                });
            }
            if positions.is_null() {
                return Err(Failure::Null {
                    argument: "positions",
                });
            }
            let p = check::array_mut::<f32, 3>(positions, point_count, "positions")?;
            let v = if velocities.is_null() {
                None
            } else {
                Some(check::array_mut::<f32, 3>(
                    velocities,
                    point_count,
                    "velocities",
                )?)
            };
            let f = r.read_frame(frame)?;
            for (dst, src) in p.iter_mut().zip(&f.positions) {
                *dst = (*src).into();
            }
            if let Some(v) = v {
                for (dst, src) in v.iter_mut().zip(&f.velocities) {
                    *dst = (*src).into();
                }
            }
            Ok(())
        })
    }
}

/// Destroys a cache reader. NULL is ignored.
///
/// # Safety
/// `cache` is NULL or a live handle, not used again.
#[no_mangle]
pub unsafe extern "C" fn hairsys_cache_destroy(cache: *mut HairsysCache) {
    // SAFETY: the caller's promise.
    unsafe { crate::check::destroy(cache) }
}

/// Writes every frame of the finished cache at `cache_path` as one animated USD file at
/// `usd_path` (`.usda` text or `.usdc` binary, by its extension): the strands as
/// `BasisCurves` at `/hair` (m, time codes = frames) and the scalp, as `hairsys cache export`
/// does. Both paths NUL-terminated UTF-8.
///
/// # Safety
/// Both paths are NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn hairsys_export_usd(
    cache_path: *const std::ffi::c_char,
    usd_path: *const std::ffi::c_char,
) -> HairsysStatus {
    guard(|| {
        // SAFETY (both): the caller's promise.
        let cache = unsafe { check::path(cache_path, "cache_path")? };
        let usd = unsafe { check::path(usd_path, "usd_path")? };
        export_shot(&cache, &usd, &ShotOptions::default()).map_err(hairsys::Error::from)?;
        Ok(())
    })
}
