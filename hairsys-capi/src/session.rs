//! `HairsysSession`: a [`hairsys::Session`] behind an opaque handle, and every call on it.
//!
//! A handle holds the session in a [`Mutex`] that calls only *try* to lock: a second thread
//! calling while another's call runs gets `HAIRSYS_STATUS_BUSY` instead of a data race. A call
//! that panicked poisons the handle (its message is kept), and every later call but
//! [`hairsys_session_destroy`] returns `HAIRSYS_STATUS_POISONED`.
//!
//! Views ([`HairsysPointsView`], [`HairsysIndexView`]) point into the session's own arrays
//! without a copy: they stay valid until the next call that changes the session (a setter,
//! step, restore, record) or destroys it.

use std::sync::{Arc, Condvar, Mutex, TryLockError};
use std::time::Duration;

use hair_cache::{Compression, Precision, WriterOptions};
use hair_core::ColliderId;
use hairsys::scene::SceneFile;
use hairsys::{Session, Snapshot};

use crate::check;
use crate::error::{guard, panic_message, Failure, HairsysStatus};
use crate::groom::{options, Arrays};
use crate::types::{
    HairsysCacheSummary, HairsysFrameReport, HairsysGroomArrays, HairsysGroomOptions,
    HairsysIndexView, HairsysParams, HairsysPointsView, HairsysSessionInfo, HairsysTransform,
    HAIRSYS_COMPRESSION_LZ4, HAIRSYS_COMPRESSION_NONE, HAIRSYS_COMPRESSION_ZSTD,
    HAIRSYS_MAX_THREADS,
};

/// A simulation session (opaque). Made by `hairsys_session_from_scene` or
/// `hairsys_session_from_groom`, owned by the host, released with `hairsys_session_destroy`.
/// Used from one thread at a time (any thread, one after the other).
pub struct HairsysSession {
    // Dropped first: the session, and with it its own pool, which tells its workers to stop.
    inner: Mutex<Inner>,
    // Dropped second: waits for those workers to exit.
    _workers: Option<Workers>,
}

/// The workers of a session's own pool: how many have not finished yet (counted down by
/// rayon's exit handler) and their join handles (the pool's threads are started by its spawn
/// handler, not detached). Dropping it (after the pool) waits for the count to reach 0, then
/// joins every thread, so no thread of the library outlives the handle that made it — not even
/// the last instructions after the exit handler, whose stack and thread-local storage a leak
/// checker would otherwise see allocated: a host may unload the library once it has destroyed
/// its sessions. The wait gives up after [`WORKER_EXIT_WAIT`], leaving stragglers detached.
struct Workers {
    live: Arc<(Mutex<usize>, Condvar)>,
    threads: Arc<Mutex<Vec<std::thread::JoinHandle<()>>>>,
}

/// The longest a session's destruction waits for its workers to exit.
const WORKER_EXIT_WAIT: Duration = Duration::from_secs(10);

impl Drop for Workers {
    fn drop(&mut self) {
        let (live, exited) = &*self.live;
        let live = live.lock().unwrap_or_else(|p| p.into_inner());
        let Ok((live, _)) = exited.wait_timeout_while(live, WORKER_EXIT_WAIT, |n| *n > 0) else {
            return;
        };
        if *live > 0 {
            return;
        }
        drop(live);
        let mut threads = self.threads.lock().unwrap_or_else(|p| p.into_inner());
        for thread in threads.drain(..) {
            // Past its exit handler: the join only waits for the thread's own teardown.
            let _ = thread.join();
        }
    }
}

struct Inner {
    session: Session,
    /// The message of the panic that poisoned the handle.
    poisoned: Option<String>,
}

/// A copy of a session's state at one frame (opaque), for `hairsys_session_restore`. Owned by
/// the host, released with `hairsys_snapshot_destroy`; independent of its session's lifetime.
pub struct HairsysSnapshot {
    snapshot: Snapshot,
}

/// Runs `f` on the session behind `handle`, as every call on a session does: checks the handle,
/// refuses a busy or poisoned one, poisons it if `f` panics, and leaves the outcome as the
/// thread's last error. A Rust crate that adds its own entry points over the same handles
/// builds them on this.
///
/// # Safety
/// A non-NULL `handle` was returned by a create call and is not destroyed.
pub unsafe fn with_session(
    handle: *const HairsysSession,
    f: impl FnOnce(&mut Session) -> Result<(), Failure>,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let handle = unsafe { check::reference(handle, "session")? };
        let mut inner = match handle.inner.try_lock() {
            Ok(guard) => guard,
            Err(TryLockError::WouldBlock) => return Err(Failure::Busy),
            // A panic is caught inside the lock, so the mutex is never poisoned; if it were,
            // its state would be as unknown as a poisoned handle's.
            Err(TryLockError::Poisoned(p)) => {
                let mut g = p.into_inner();
                g.poisoned.get_or_insert_with(|| "a poisoned lock".into());
                g
            }
        };
        if let Some(why) = &inner.poisoned {
            return Err(Failure::Poisoned(why.clone()));
        }
        let session = &mut inner.session;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(session))) {
            Ok(result) => result,
            Err(payload) => {
                let what = panic_message(&*payload);
                inner.poisoned = Some(what.clone());
                Err(Failure::Panic(what))
            }
        }
    })
}

/// A session's own pool and the count of its workers still running.
type OwnPool = (Arc<hair_par::ThreadPool>, Workers);

/// The session's own pool of `threads` workers (`None` for 0: the shared pool), made before
/// the session so a bad count costs nothing.
fn pool(threads: u32) -> Result<Option<OwnPool>, Failure> {
    if threads > HAIRSYS_MAX_THREADS {
        return Err(Failure::argument(
            "threads",
            format!(
                "= {threads}: give at most HAIRSYS_MAX_THREADS ({HAIRSYS_MAX_THREADS}), or 0 for \
                 the shared pool"
            ),
        ));
    }
    if threads == 0 {
        return Ok(None);
    }
    let live = Arc::new((Mutex::new(threads as usize), Condvar::new()));
    let exit = Arc::clone(&live);
    let handles = Arc::new(Mutex::new(Vec::with_capacity(threads as usize)));
    let spawned = Arc::clone(&handles);
    let pool = hair_par::ThreadPoolBuilder::new()
        .num_threads(threads as usize)
        .spawn_handler(move |worker: hair_par::ThreadBuilder| {
            let mut b = std::thread::Builder::new();
            if let Some(name) = worker.name() {
                b = b.name(name.to_owned());
            }
            if let Some(size) = worker.stack_size() {
                b = b.stack_size(size);
            }
            let handle = b.spawn(|| worker.run())?;
            spawned
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .push(handle);
            Ok(())
        })
        .exit_handler(move |_| {
            let (live, exited) = &*exit;
            *live.lock().unwrap_or_else(|p| p.into_inner()) -= 1;
            exited.notify_all();
        })
        .build()
        .map_err(|e| {
            Failure::argument("threads", format!("cannot start {threads} threads: {e}"))
        })?;
    Ok(Some((
        Arc::new(pool),
        Workers {
            live,
            threads: handles,
        },
    )))
}

/// Wraps `session` in a handle stepping on `pool` and writes it to `out`.
fn create(
    out: &mut std::mem::MaybeUninit<*mut HairsysSession>,
    mut session: Session,
    pool: Option<OwnPool>,
) {
    let workers = pool.map(|(pool, workers)| {
        session.set_thread_pool(pool);
        workers
    });
    out.write(Box::into_raw(Box::new(HairsysSession {
        inner: Mutex::new(Inner {
            session,
            poisoned: None,
        }),
        _workers: workers,
    })));
}

/// Creates a session from the scene file at `path` (NUL-terminated UTF-8; NULL: the built-in
/// default scene), at rest at the scene's first frame, and writes its handle to `*out` (on
/// failure `*out` is left alone). `threads`: workers of the session's own pool (at most
/// `HAIRSYS_MAX_THREADS`; 0: the library's shared pool). Whatever the host does not set for a
/// frame follows the scene's keyframes.
///
/// # Safety
/// `path` is NULL or NUL-terminated; `out` points to writable memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_from_scene(
    path: *const std::ffi::c_char,
    threads: u32,
    out: *mut *mut HairsysSession,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let out = unsafe { check::out(out, "out")? };
        let pool = pool(threads)?;
        let scene = if path.is_null() {
            SceneFile::builtin_default()
        } else {
            // SAFETY: the caller's promise.
            SceneFile::load(&unsafe { check::path(path, "path")? }).map_err(hairsys::Error::from)?
        };
        create(out, Session::from_scene(&scene)?, pool);
        Ok(())
    })
}

/// Creates a session of the host's groom `arrays` (see `HairsysGroomArrays`: world space at
/// the first frame, m) simulated as `options` say (`hairsys_groom_options_default` first), at
/// rest at `options->first_frame`, and writes its handle to `*out`. The arrays are copied; the
/// host keeps them. Roots farther than `max_snap_distance` from the scalp are refused by curve
/// index.
///
/// # Safety
/// `arrays` and `options` point to valid structs whose array pointers hold as many elements
/// as their counts say; `out` points to writable memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_from_groom(
    arrays: *const HairsysGroomArrays,
    options: *const HairsysGroomOptions,
    out: *mut *mut HairsysSession,
) -> HairsysStatus {
    guard(|| {
        // SAFETY (each block): the caller's promise.
        let out = unsafe { check::out(out, "out")? };
        let arrays = unsafe { Arrays::read(check::reference(arrays, "arrays")?)? };
        let (opts, threads) = unsafe { self::options(check::reference(options, "options")?)? };
        crate::groom::check_budget(&opts, &arrays)?;
        let pool = pool(threads)?;
        create(out, Session::from_groom(&arrays.groom(), &opts)?, pool);
        Ok(())
    })
}

/// Destroys a session and everything it owns (its views become invalid; a cache being
/// recorded is left as its `.partial` file). NULL is ignored. Snapshots and children taken
/// from it stay valid.
///
/// # Safety
/// `session` is NULL or a live handle, not used by another thread and not used again.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_destroy(session: *mut HairsysSession) {
    // SAFETY: the caller's promise.
    unsafe { crate::check::destroy(session) }
}

/// Writes the session's frame, fps and sizes to `*out`.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_info(
    session: *const HairsysSession,
    out: *mut HairsysSessionInfo,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = check::out(out, "out")?;
            out.write(HairsysSessionInfo {
                frame: s.frame(),
                fps: s.fps(),
                strand_count: s.strands().len(),
                point_count: s.strands().point_count(),
                collider_count: s.colliders().len(),
                scalp_vertex_count: s.rest_scalp().map_or(0, |m| m.positions().len()),
            });
            Ok(())
        })
    }
}

/// Sets the scalp's rigid transform (body to world) for the frame stepped next; roots and the
/// scalp collider follow it.
///
/// # Safety
/// `session` is a live handle; `transform` points to a valid struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_set_scalp_transform(
    session: *const HairsysSession,
    transform: *const HairsysTransform,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let t = check::transform(check::reference(transform, "transform")?, "transform")?;
            Ok(s.set_scalp_transform(t)?)
        })
    }
}

/// Sets the deformed scalp for the frame stepped next: `vertices` (`vertex_count` points, xyz
/// interleaved, m, in the scalp's body space, the rest mesh's order and count:
/// `scalp_vertex_count` of `hairsys_session_info`) placed by `body` (body to world; NULL: the
/// identity, for vertices already in world space). Roots follow their mesh samples exactly.
///
/// # Safety
/// `session` is a live handle; `vertices` holds `3 * vertex_count` floats; `body` is NULL or
/// points to a valid struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_set_scalp_vertices(
    session: *const HairsysSession,
    vertices: *const f32,
    vertex_count: usize,
    body: *const HairsysTransform,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let v = check::array::<f32, 3>(vertices, vertex_count, "vertices")?;
            if v.is_empty() && vertices.is_null() {
                return Err(Failure::Null {
                    argument: "vertices",
                });
            }
            check::finite(v, "vertices")?;
            let body = if body.is_null() {
                nalgebra::Isometry3::identity()
            } else {
                check::transform(check::reference(body, "body")?, "body")?
            };
            let expected = s.rest_scalp().map_or(0, |m| m.positions().len());
            if v.len() != expected && expected > 0 {
                return Err(Failure::Length {
                    argument: "vertex_count".into(),
                    message: format!(
                        "is {}, the scalp mesh has {expected} vertices: give every vertex of the \
                         rest mesh, in its order (the topology cannot change)",
                        v.len()
                    ),
                });
            }
            Ok(s.set_scalp_vertices(v, body)?)
        })
    }
}

/// Poses collider `id` (body to world) at the end of the frame stepped next; it moves there
/// from its current pose during the frame. The scalp collider follows the scalp and is refused.
///
/// # Safety
/// `session` is a live handle; `pose` points to a valid struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_set_collider_pose(
    session: *const HairsysSession,
    id: u32,
    pose: *const HairsysTransform,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let pose = check::transform(check::reference(pose, "pose")?, "pose")?;
            Ok(s.set_collider_pose(ColliderId(id), pose)?)
        })
    }
}

/// Deforms mesh collider `id`: `vertices` (`vertex_count` points, xyz interleaved, m, body
/// space, the order and count of the mesh it was made with) are its shape at the end of the
/// frame stepped next; each vertex moves in a straight line within the frame.
///
/// # Safety
/// `session` is a live handle; `vertices` holds `3 * vertex_count` floats.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_set_collider_vertices(
    session: *const HairsysSession,
    id: u32,
    vertices: *const f32,
    vertex_count: usize,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let v = check::array::<f32, 3>(vertices, vertex_count, "vertices")?;
            if v.is_empty() && vertices.is_null() {
                return Err(Failure::Null {
                    argument: "vertices",
                });
            }
            check::finite(v, "vertices")?;
            let mesh = s
                .cache_rig()
                .colliders
                .get(id as usize)
                .and_then(|c| match &c.shape {
                    hair_core::ColliderShape::Mesh(m) => Some(m.positions().len()),
                    _ => None,
                });
            if let Some(expected) = mesh.filter(|&n| n != v.len()) {
                return Err(Failure::Length {
                    argument: "vertex_count".into(),
                    message: format!(
                        "is {}, collider {id}'s mesh has {expected} vertices: give every vertex, \
                         in the order it was made with",
                        v.len()
                    ),
                });
            }
            Ok(s.set_collider_vertices(ColliderId(id), v)?)
        })
    }
}

/// Reads the material a host may change between frames into `*out`. Refused
/// (`HAIRSYS_STATUS_BAD_ARGUMENT`) for the rod model, whose parameters are fixed.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_params(
    session: *const HairsysSession,
    out: *mut HairsysParams,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = check::out(out, "out")?;
            let p = params_of(s)?;
            out.write(HairsysParams {
                gravity: p.gravity,
                stretch_stiffness: p.stretch_stiffness,
                bend_stiffness: p.bend_stiffness,
                goal_stiffness: p.goal_stiffness,
                stretch_damping: p.stretch_damping,
                air_drag: p.air_drag,
            });
            Ok(())
        })
    }
}

/// Sets the material from the next step on (checked then; a much stiffer value than the
/// substeps were chosen for can make that step unstable, which it reports).
///
/// # Safety
/// `session` is a live handle; `params` points to a valid struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_set_params(
    session: *const HairsysSession,
    params: *const HairsysParams,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let n = check::reference(params, "params")?;
            check::finite(
                &[[
                    n.gravity[0],
                    n.gravity[1],
                    n.gravity[2],
                    n.stretch_stiffness,
                    n.bend_stiffness,
                    n.goal_stiffness,
                    n.stretch_damping,
                    n.air_drag,
                ]],
                "params",
            )?;
            let p = params_of(s)?;
            p.gravity = n.gravity;
            p.stretch_stiffness = n.stretch_stiffness;
            p.bend_stiffness = n.bend_stiffness;
            p.goal_stiffness = n.goal_stiffness;
            p.stretch_damping = n.stretch_damping;
            p.air_drag = n.air_drag;
            Ok(())
        })
    }
}

fn params_of(s: &mut Session) -> Result<&mut hair_core::HairParams, Failure> {
    s.params_mut().ok_or_else(|| {
        Failure::argument(
            "params",
            "this session's model (the rod) fixes its parameters when it is built",
        )
    })
}

/// Advances one frame (1/fps s) with what the host set (and a scene's keyframes for the rest),
/// writing it to the cache being recorded; `*report` (NULL: not wanted) says what the step did.
/// A failed step (`HAIRSYS_STATUS_SOLVER`) leaves the session failed until a snapshot is
/// restored.
///
/// # Safety
/// `session` is a live handle; `report` is NULL or points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_step(
    session: *const HairsysSession,
    report: *mut HairsysFrameReport,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = if report.is_null() {
                None
            } else {
                Some(check::out(report, "report")?)
            };
            let r = s.step()?;
            if let Some(out) = out {
                out.write(HairsysFrameReport {
                    frame: r.frame,
                    substeps: r.substeps,
                    steps: r.steps,
                    point_substeps: r.point_substeps,
                    contact_points: r.contact_points,
                    escaped_points: r.escaped_points,
                    max_stretch: r.max_stretch,
                });
            }
            Ok(())
        })
    }
}

/// A view of `points`.
fn points_view(points: &[[f32; 3]]) -> HairsysPointsView {
    HairsysPointsView {
        xyz: points.as_ptr() as *const f32,
        count: points.len(),
    }
}

/// Writes a view of every point's position (m, strand after strand; see
/// `hairsys_session_strand_offsets`) to `*out`, without a copy.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_positions(
    session: *const HairsysSession,
    out: *mut HairsysPointsView,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            check::out(out, "out")?.write(points_view(s.positions()));
            Ok(())
        })
    }
}

/// Writes a view of every point's velocity (m/s, in the order of the positions) to `*out`.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_velocities(
    session: *const HairsysSession,
    out: *mut HairsysPointsView,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            check::out(out, "out")?.write(points_view(s.velocities()));
            Ok(())
        })
    }
}

/// Writes a view of the strand offsets to `*out`: strands + 1 values; strand `s`'s points are
/// `offsets[s]` to `offsets[s + 1] - 1`. Fixed for the session's life.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_strand_offsets(
    session: *const HairsysSession,
    out: *mut HairsysIndexView,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let o = s.strand_offsets();
            check::out(out, "out")?.write(HairsysIndexView {
                data: o.as_ptr(),
                count: o.len(),
            });
            Ok(())
        })
    }
}

/// Copies the session's state at the current frame into a new snapshot written to `*out`.
///
/// # Safety
/// `session` is a live handle; `out` points to writable memory for a pointer.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_snapshot(
    session: *const HairsysSession,
    out: *mut *mut HairsysSnapshot,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = check::out(out, "out")?;
            out.write(Box::into_raw(Box::new(HairsysSnapshot {
                snapshot: s.snapshot(),
            })));
            Ok(())
        })
    }
}

/// Puts the session back in the state of `snapshot` (taken from this session) and clears a
/// failed step: stepping on gives the same bits as stepping on from where it was taken.
/// Refused while a cache is being recorded.
///
/// # Safety
/// `session` and `snapshot` are live handles.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_restore(
    session: *const HairsysSession,
    snapshot: *const HairsysSnapshot,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let snap = check::reference(snapshot, "snapshot")?;
            Ok(s.restore(&snap.snapshot)?)
        })
    }
}

/// The frame a snapshot holds, written to `*out`.
///
/// # Safety
/// `snapshot` is a live handle; `out` points to writable memory for a `uint32_t`.
#[no_mangle]
pub unsafe extern "C" fn hairsys_snapshot_frame(
    snapshot: *const HairsysSnapshot,
    out: *mut u32,
) -> HairsysStatus {
    guard(|| {
        // SAFETY: the caller's promise.
        let snap = unsafe { check::reference(snapshot, "snapshot")? };
        // SAFETY: the caller's promise.
        unsafe { check::out(out, "out")? }.write(snap.snapshot.frame());
        Ok(())
    })
}

/// Destroys a snapshot. NULL is ignored.
///
/// # Safety
/// `snapshot` is NULL or a live handle, not used again.
#[no_mangle]
pub unsafe extern "C" fn hairsys_snapshot_destroy(snapshot: *mut HairsysSnapshot) {
    // SAFETY: the caller's promise.
    unsafe { crate::check::destroy(snapshot) }
}

/// Starts recording an MCAP cache at `path` (NUL-terminated UTF-8; written as `path.partial`
/// until `hairsys_session_finish_recording` renames it): the current frame now, then every
/// step. `compression`: `HAIRSYS_COMPRESSION_NONE`, `_LZ4` or `_ZSTD`; `quantize`: 1 for 16-bit
/// positions and velocities, 0 for f32.
///
/// # Safety
/// `session` is a live handle; `path` is NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_record(
    session: *const HairsysSession,
    path: *const std::ffi::c_char,
    compression: u32,
    quantize: u32,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let path = check::path(path, "path")?;
            let compression = match compression {
                HAIRSYS_COMPRESSION_NONE => Compression::None,
                HAIRSYS_COMPRESSION_LZ4 => Compression::Lz4,
                HAIRSYS_COMPRESSION_ZSTD => Compression::Zstd,
                other => {
                    return Err(Failure::argument(
                        "compression",
                        format!(
                            "= {other}: give HAIRSYS_COMPRESSION_NONE (0), _LZ4 (1) or _ZSTD (2)"
                        ),
                    ))
                }
            };
            let precision = if check::flag(quantize, "quantize")? {
                Precision::Quantized16
            } else {
                Precision::F32
            };
            let options = WriterOptions {
                compression,
                precision,
                ..WriterOptions::default()
            };
            Ok(s.record(&path, options)?)
        })
    }
}

/// Finishes the cache being recorded (index, summary, renamed to its final name); `*out` (NULL:
/// not wanted) says what it holds.
///
/// # Safety
/// `session` is a live handle; `out` is NULL or points to writable memory for the struct.
#[no_mangle]
pub unsafe extern "C" fn hairsys_session_finish_recording(
    session: *const HairsysSession,
    out: *mut HairsysCacheSummary,
) -> HairsysStatus {
    // SAFETY: the caller's promise.
    unsafe {
        with_session(session, |s| {
            let out = if out.is_null() {
                None
            } else {
                Some(check::out(out, "out")?)
            };
            let summary = s.finish_recording()?;
            if let Some(out) = out {
                out.write(HairsysCacheSummary {
                    frames: summary.frames,
                    first_frame: summary.first_frame.unwrap_or(0),
                    last_frame: summary.last_frame.unwrap_or(0),
                    fps: summary.fps,
                    strands: summary.strands,
                    points: summary.points,
                    bytes: summary.bytes,
                });
            }
            Ok(())
        })
    }
}
