//! What the C boundary costs per frame: the default scene stepped through `hairsys::Session`
//! and through the C API's functions (`hairsys_session_step`, `hairsys_session_positions`),
//! alternated in one run, and the cost of one call across the boundary on its own.
//!
//! ```sh
//! cargo run --release -p hairsys-capi --example capi_overhead [ROUNDS]
//! ```
//!
//! Each round restores both sessions to the first frame and steps each `FRAMES` frames, reading
//! the positions after every step; the order of the two alternates (ABBA), and the table gives
//! the median and the fastest round of each. The C path here calls the exported functions from
//! Rust (the same code a C host reaches through the shared library, without the dynamic call's
//! few nanoseconds).

use std::ptr;
use std::time::{Duration, Instant};

use hairsys::scene::SceneFile;
use hairsys::Session;
use hairsys_capi::*;

/// Frames stepped per round.
const FRAMES: u32 = 12;

fn check(status: HairsysStatus) {
    assert_eq!(status, HairsysStatus::Ok, "{status:?}");
}

/// The Rust session: restore, then `FRAMES` steps reading the positions.
fn rust_round(s: &mut Session, start: &hairsys::Snapshot) -> Duration {
    s.restore(start).unwrap();
    let t = Instant::now();
    let mut sum = 0.0f32;
    for _ in 0..FRAMES {
        s.step().unwrap();
        sum += s.positions()[0][2];
    }
    std::hint::black_box(sum);
    t.elapsed()
}

/// The same through the C API.
///
/// # Safety
/// `s` and `start` are live handles.
unsafe fn c_round(s: *mut HairsysSession, start: *const HairsysSnapshot) -> Duration {
    // SAFETY: the caller's promise; locals for the out-parameters.
    unsafe {
        check(hairsys_session_restore(s, start));
        let t = Instant::now();
        let mut sum = 0.0f32;
        let mut view = HairsysPointsView {
            xyz: ptr::null(),
            count: 0,
        };
        for _ in 0..FRAMES {
            check(hairsys_session_step(s, ptr::null_mut()));
            check(hairsys_session_positions(s, &mut view));
            sum += *view.xyz.add(2);
        }
        std::hint::black_box(sum);
        t.elapsed()
    }
}

fn median(v: &mut [Duration]) -> Duration {
    v.sort();
    v[v.len() / 2]
}

fn ms_per_frame(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3 / f64::from(FRAMES)
}

fn main() {
    let rounds: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("ROUNDS is a whole number"))
        .unwrap_or(10);
    let scene = SceneFile::builtin_default();
    let mut rust = Session::from_scene(&scene).unwrap();
    let rust_start = rust.snapshot();
    let mut c = ptr::null_mut();
    let mut c_start = ptr::null_mut();
    // SAFETY: locals for the out-parameters.
    unsafe {
        check(hairsys_session_from_scene(ptr::null(), 0, &mut c));
        check(hairsys_session_snapshot(c, &mut c_start));
    }
    // One round of each to warm caches and the pool.
    rust_round(&mut rust, &rust_start);
    // SAFETY: live handles.
    unsafe { c_round(c, c_start) };
    let (mut r, mut k) = (Vec::new(), Vec::new());
    for i in 0..rounds {
        if i % 2 == 0 {
            r.push(rust_round(&mut rust, &rust_start));
            // SAFETY: live handles.
            k.push(unsafe { c_round(c, c_start) });
        } else {
            // SAFETY: live handles.
            k.push(unsafe { c_round(c, c_start) });
            r.push(rust_round(&mut rust, &rust_start));
        }
    }
    let (r_min, k_min) = (*r.iter().min().unwrap(), *k.iter().min().unwrap());
    let (r_med, k_med) = (median(&mut r), median(&mut k));

    // One call across the boundary: a positions view, a million times.
    let calls = 1_000_000u32;
    let mut view = HairsysPointsView {
        xyz: ptr::null(),
        count: 0,
    };
    let t = Instant::now();
    for _ in 0..calls {
        // SAFETY: a live handle and a local.
        check(unsafe { hairsys_session_positions(c, &mut view) });
        std::hint::black_box(view.count);
    }
    let call_ns = t.elapsed().as_secs_f64() * 1e9 / f64::from(calls);
    // SAFETY: live handles, not used again.
    unsafe {
        hairsys_snapshot_destroy(c_start);
        hairsys_session_destroy(c);
    }

    let points = rust.strands().point_count();
    println!(
        "default scene: {} strands, {points} points; {rounds} rounds of {FRAMES} frames, \
         alternated",
        rust.strands().len()
    );
    println!("| path | median ms/frame | fastest ms/frame |");
    println!("|---|---:|---:|");
    println!(
        "| Rust `Session` | {:.3} | {:.3} |",
        ms_per_frame(r_med),
        ms_per_frame(r_min)
    );
    println!(
        "| C API | {:.3} | {:.3} |",
        ms_per_frame(k_med),
        ms_per_frame(k_min)
    );
    println!(
        "C against Rust: {:+.2} % (medians), {:+.2} % (fastest rounds)",
        100.0 * (k_med.as_secs_f64() / r_med.as_secs_f64() - 1.0),
        100.0 * (k_min.as_secs_f64() / r_min.as_secs_f64() - 1.0)
    );
    println!(
        "one call across the boundary (hairsys_session_positions): {call_ns:.1} ns; a frame makes \
         2: {:.5} % of the fastest Rust frame",
        100.0 * 2.0 * call_ns * 1e-6 / ms_per_frame(r_min)
    );
}
