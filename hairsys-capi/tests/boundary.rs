//! The boundary's rules, through the exported functions: a panic becomes a status and poisons
//! its handle, a handle used while busy refuses, the last error is per thread, a failed step
//! is reported and cleared by a restore, the ABI version is the header's.

use std::ffi::CStr;
use std::ptr;

use hairsys_capi::session::with_session;
use hairsys_capi::*;

/// A 2 × 2 grid scalp (0.1 m) and two 4-point curves.
struct Groom {
    vertices: [f32; 12],
    triangles: [u32; 6],
    points: Vec<f32>,
    counts: [u32; 2],
}

impl Groom {
    fn new() -> Self {
        let mut points = Vec::new();
        for c in 0..2 {
            for k in 0..4 {
                points.extend([0.03 + 0.04 * c as f32, 0.05, 0.0005 + 0.02 * k as f32]);
            }
        }
        Self {
            vertices: [0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.1, 0.1, 0.0, 0.0, 0.1, 0.0],
            triangles: [0, 1, 2, 0, 2, 3],
            points,
            counts: [4, 4],
        }
    }

    fn arrays(&self) -> HairsysGroomArrays {
        HairsysGroomArrays {
            scalp_vertices: self.vertices.as_ptr(),
            scalp_vertex_count: 4,
            scalp_triangles: self.triangles.as_ptr(),
            scalp_triangle_count: 2,
            scalp_uvs: ptr::null(),
            curve_points: self.points.as_ptr(),
            curve_point_count: 8,
            curve_counts: self.counts.as_ptr(),
            curve_count: 2,
            goal_weights: ptr::null(),
            pinned: ptr::null(),
            strand_scales: ptr::null(),
        }
    }

    /// A session of the groom with `options` changed by `change`.
    fn session(&self, change: impl FnOnce(&mut HairsysGroomOptions)) -> *mut HairsysSession {
        let mut o = std::mem::MaybeUninit::uninit();
        // SAFETY: a pointer to a live local.
        let status = unsafe { hairsys_groom_options_default(o.as_mut_ptr()) };
        assert_eq!(status, HairsysStatus::Ok, "{}", message());
        // SAFETY: filled by the call above.
        let mut o = unsafe { o.assume_init() };
        change(&mut o);
        let mut s = ptr::null_mut();
        // SAFETY: valid pointers to live locals.
        let status = unsafe { hairsys_session_from_groom(&self.arrays(), &o, &mut s) };
        assert_eq!(status, HairsysStatus::Ok, "{}", message());
        s
    }
}

/// This thread's last error message.
fn message() -> String {
    // SAFETY: the library returns a NUL-terminated string, never NULL.
    unsafe { CStr::from_ptr(hairsys_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

#[test]
fn a_panic_becomes_a_status_and_poisons_the_session() {
    let groom = Groom::new();
    let s = groom.session(|_| {});
    // SAFETY: a live handle.
    let status = unsafe { with_session(s, |_| panic!("a deliberate bug")) };
    assert_eq!(status, HairsysStatus::Panic);
    assert!(message().contains("a deliberate bug"), "{}", message());
    // SAFETY: a live handle.
    let again = unsafe { hairsys_session_step(s, ptr::null_mut()) };
    assert_eq!(again, HairsysStatus::Poisoned);
    assert!(message().contains("a deliberate bug"), "{}", message());
    let mut info = HairsysSessionInfo::default();
    // SAFETY: a live handle and a local.
    let read = unsafe { hairsys_session_info(s, &mut info) };
    assert_eq!(read, HairsysStatus::Poisoned);
    // SAFETY: a live handle, not used again.
    unsafe { hairsys_session_destroy(s) };
}

#[test]
fn a_session_in_use_refuses_a_second_call() {
    let groom = Groom::new();
    let s = groom.session(|_| {});
    let mut inner = HairsysStatus::Ok;
    // SAFETY: a live handle; the inner call is made while the outer holds it.
    let outer = unsafe {
        with_session(s, |_| {
            let mut info = HairsysSessionInfo::default();
            inner = hairsys_session_info(s, &mut info);
            Ok(())
        })
    };
    assert_eq!(inner, HairsysStatus::Busy);
    assert_eq!(outer, HairsysStatus::Ok);
    // SAFETY: a live handle, not used again.
    unsafe { hairsys_session_destroy(s) };
}

#[test]
fn the_last_error_belongs_to_the_thread_that_made_it() {
    // SAFETY: NULL is refused, never read.
    let status = unsafe { hairsys_session_step(ptr::null(), ptr::null_mut()) };
    assert_eq!(status, HairsysStatus::NullPointer);
    assert_eq!(hairsys_last_error_code(), HairsysStatus::NullPointer);
    let other = std::thread::spawn(|| (hairsys_last_error_code(), message()))
        .join()
        .unwrap();
    assert_eq!(other, (HairsysStatus::Ok, String::new()));
    assert!(message().starts_with("session: is NULL"), "{}", message());
}

#[test]
fn a_failed_step_is_reported_until_a_snapshot_is_restored() {
    let groom = Groom::new();
    let s = groom.session(|o| {
        o.integrator = c"explicit-euler".as_ptr();
        o.substeps = 1;
    });
    let mut snap = ptr::null_mut();
    // SAFETY: live handles and locals throughout.
    unsafe {
        assert_eq!(hairsys_session_snapshot(s, &mut snap), HairsysStatus::Ok);
        let mut p = HairsysParams {
            gravity: [0.0; 3],
            stretch_stiffness: 0.0,
            bend_stiffness: 0.0,
            goal_stiffness: 0.0,
            stretch_damping: 0.0,
            air_drag: 0.0,
        };
        assert_eq!(hairsys_session_params(s, &mut p), HairsysStatus::Ok);
        p.stretch_stiffness *= 1e6;
        p.bend_stiffness *= 1e6;
        assert_eq!(hairsys_session_set_params(s, &p), HairsysStatus::Ok);
        let mut failed = HairsysStatus::Ok;
        for _ in 0..5 {
            failed = hairsys_session_step(s, ptr::null_mut());
            if failed != HairsysStatus::Ok {
                break;
            }
        }
        assert_eq!(failed, HairsysStatus::Solver, "{}", message());
        assert_eq!(
            hairsys_session_step(s, ptr::null_mut()),
            HairsysStatus::SessionFailed
        );
        assert_eq!(hairsys_session_restore(s, snap), HairsysStatus::Ok);
        let mut info = HairsysSessionInfo::default();
        assert_eq!(hairsys_session_info(s, &mut info), HairsysStatus::Ok);
        assert_eq!(info.frame, 1);
        hairsys_snapshot_destroy(snap);
        hairsys_session_destroy(s);
    }
}

#[test]
fn the_abi_version_is_the_headers() {
    let v = hairsys_abi_version();
    assert_eq!(v >> 16, HAIRSYS_ABI_VERSION_MAJOR);
    assert_eq!(v & 0xffff, HAIRSYS_ABI_VERSION_MINOR);
    let header =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/include/hairsys.h")).unwrap();
    assert!(header.contains(&format!(
        "#define HAIRSYS_ABI_VERSION_MAJOR {HAIRSYS_ABI_VERSION_MAJOR}"
    )));
}
