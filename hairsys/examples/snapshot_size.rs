//! How many bytes a [`hairsys::Snapshot`] holds: the built-in default scene (`scenes/default.toml`,
//! or the scene file given) is stepped a few frames, so contacts and the hair–hair grid are in
//! use, and the heap bytes that taking one snapshot allocates are counted by a global allocator
//! that keeps a running total. Bytes the snapshot shares with the session (shapes behind an
//! `Arc`) are not counted: they are not copied.
//!
//! `cargo run --release -p hairsys --example snapshot_size [-- scene.toml [frames]]`

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicIsize, Ordering};

use hairsys::scene::SceneFile;
use hairsys::Session;

/// The system allocator, counting the bytes it has handed out and not got back.
struct Counting;

/// Bytes allocated and not freed, B.
static LIVE: AtomicIsize = AtomicIsize::new(0);

// SAFETY: every call is forwarded to `System` with the caller's arguments; the counter only
// observes sizes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_add(
                new_size as isize - layout.size() as isize,
                Ordering::Relaxed,
            );
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene = match args.next() {
        Some(path) => SceneFile::load(Path::new(&path))?,
        None => SceneFile::builtin_default(),
    };
    let frames: u32 = match args.next() {
        Some(n) => n.parse()?,
        None => 3,
    };
    let mut session = Session::from_scene(&scene)?;
    for _ in 0..frames {
        session.step()?;
    }
    let before = LIVE.load(Ordering::SeqCst);
    let snapshot = session.snapshot();
    let bytes = LIVE.load(Ordering::SeqCst) - before;
    println!(
        "a snapshot of {} strands, {} points at frame {} holds {bytes} heap bytes ({:.2} MB; \
         positions and velocities alone: {} bytes)",
        session.strand_offsets().len() - 1,
        session.positions().len(),
        snapshot.frame(),
        bytes as f64 / 1e6,
        2 * std::mem::size_of_val(session.positions()),
    );
    Ok(())
}
