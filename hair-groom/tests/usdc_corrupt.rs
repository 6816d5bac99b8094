//! A corrupted (not just truncated) `.usdc` must give the vendored `openusd` crate reader a
//! clean error: no panic, and no allocation sized from a count in the file beyond what the
//! file's bytes can hold (the `hairsys fix` bounds listed in `vendor/openusd/VENDORED.md`).
//!
//! A real layer (animated curves with time samples, a mesh, stage metadata) is written with
//! hairsys's writer, then corrupted two ways: every 8-byte-aligned word overwritten with huge
//! counts (the values a reader sizes buffers from), and seeded random bursts of flipped bytes. Each
//! mutant is opened and every field of every spec is read. A counting global allocator records
//! the largest single allocation; it must stay under [`LIMIT_FACTOR`] × the file's size (LZ4's
//! largest expansion is 255×) plus a small floor.

use std::alloc::{GlobalAlloc, Layout, System};
use std::io::Cursor;
use std::sync::atomic::{AtomicUsize, Ordering};

use hair_groom::formats::obj::UpAxis;
use hair_groom::formats::usd_write::{Samples, UsdCurvesPrim, UsdLayer, UsdMeshPrim, UsdStageInfo};
use openusd::sdf::AbstractData;
use openusd::usdc::CrateData;

/// The global allocator, recording the largest single request while armed.
struct Counting;

static ARMED: AtomicUsize = AtomicUsize::new(0);
static LARGEST: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if ARMED.load(Ordering::Relaxed) != 0 {
            LARGEST.fetch_max(layout.size(), Ordering::Relaxed);
        }
        // Refuse (null: the caller's allocation error) what would really be a huge allocation,
        // so a regression fails the assertion below instead of exhausting the machine.
        if layout.size() > 1 << 32 {
            return std::ptr::null_mut();
        }
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if ARMED.load(Ordering::Relaxed) != 0 {
            LARGEST.fetch_max(new_size, Ordering::Relaxed);
        }
        if new_size > 1 << 32 {
            return std::ptr::null_mut();
        }
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Largest single allocation allowed, as a multiple of the file's size (plus 1 MiB).
const LIMIT_FACTOR: usize = 300;

/// A small but complete layer: animated curves (points, velocities, extent per time code),
/// widths, root UVs, colours, int and float primvars, and a mesh.
fn layer_bytes() -> Vec<u8> {
    let mut layer = UsdLayer::new(&UsdStageInfo {
        up_axis: UpAxis::Z,
        meters_per_unit: 1.0,
        time_codes_per_second: Some(24.0),
        time_range: Some((1.0, 3.0)),
    });
    let frame = |t: f32| -> Vec<f32> { (0..18).map(|i| i as f32 * 0.01 + t).collect() };
    let times = |f: &dyn Fn(f32) -> Vec<f32>| {
        Samples::Times((1..=3).map(|t| (f64::from(t), f(t as f32))).collect())
    };
    layer.add_curves(UsdCurvesPrim {
        name: "hair",
        vertex_counts: vec![3, 3],
        points: times(&frame),
        widths: Some(Samples::Default(vec![0.001; 6])),
        velocities: Some(times(&|t| vec![t; 18])),
        root_uv: Some(vec![0.1, 0.2, 0.3, 0.4]),
        colors: Some(vec![1.0, 0.5, 0.0, 0.2, 0.3, 0.4]),
        extent: true,
        uniform_floats: vec![("random", vec![0.25, 0.75])],
        uniform_ints: vec![("id", vec![0, 1])],
    });
    layer.add_mesh(UsdMeshPrim {
        name: "scalp",
        face_vertex_counts: vec![3, 3],
        face_vertex_indices: vec![0, 1, 2, 0, 2, 3],
        points: Samples::Default(vec![0., 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.]),
        uv: Some(vec![0., 0., 1., 0., 1., 1., 0., 1.]),
        colors: None,
    });
    layer.set_default_prim("hair");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("l.usdc");
    layer.write(&path).unwrap();
    std::fs::read(path).unwrap()
}

/// Opens `bytes` and reads every field of every spec; the number of values read.
fn read_everything(bytes: &[u8]) -> Result<usize, String> {
    let data = CrateData::open(Cursor::new(bytes), true).map_err(|e| format!("{e:#}"))?;
    let mut n = 0;
    for path in data.spec_paths() {
        for field in data.list_fields(&path).unwrap_or_default() {
            if data.try_field(&path, &field).is_ok() {
                n += 1;
            }
        }
    }
    Ok(n)
}

/// Reads `bytes` under the allocation counter; panics are caught and returned as `Err`.
fn probe(bytes: &[u8]) -> (Result<(), String>, usize) {
    LARGEST.store(0, Ordering::Relaxed);
    ARMED.store(1, Ordering::Relaxed);
    let r = std::panic::catch_unwind(|| read_everything(bytes));
    ARMED.store(0, Ordering::Relaxed);
    let largest = LARGEST.load(Ordering::Relaxed);
    match r {
        Ok(_) => (Ok(()), largest),
        Err(p) => {
            let why = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            (Err(why), largest)
        }
    }
}

/// xorshift64*: the mutations are the same on every run.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

#[test]
fn corrupted_usdc_counts_give_errors_not_panics_or_huge_allocations() {
    let good = layer_bytes();
    assert!(
        read_everything(&good).unwrap() > 20,
        "the intact file reads"
    );
    let limit = LIMIT_FACTOR * good.len() + (1 << 20);
    let mut mutants: Vec<(String, Vec<u8>)> = Vec::new();
    for at in (0..good.len().saturating_sub(8)).step_by(8) {
        for (name, word) in [
            ("u64::MAX", u64::MAX),
            ("2^40", 1u64 << 40),
            ("2^31", 1u64 << 31),
            ("2^20", 1u64 << 20),
        ] {
            let mut m = good.clone();
            m[at..at + 8].copy_from_slice(&word.to_le_bytes());
            mutants.push((format!("{name} at byte {at}"), m));
        }
    }
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    for k in 0..400 {
        let mut m = good.clone();
        let start = (rng.next() as usize) % good.len();
        let len = 1 + (rng.next() as usize) % 8;
        for b in m.iter_mut().skip(start).take(len) {
            *b = rng.next() as u8;
        }
        mutants.push((format!("random burst {k} at byte {start}"), m));
    }
    let quiet = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut panics = Vec::new();
    let mut big = Vec::new();
    for (name, m) in &mutants {
        let (r, largest) = probe(m);
        if let Err(why) = r {
            panics.push(format!("{name}: {why}"));
        }
        if largest > limit {
            big.push(format!("{name}: {largest} bytes"));
        }
    }
    std::panic::set_hook(quiet);
    assert!(
        big.is_empty(),
        "{} of {} mutants allocated more than {limit} bytes at once, e.g. {:?}",
        big.len(),
        mutants.len(),
        &big[..big.len().min(5)]
    );
    assert!(
        panics.is_empty(),
        "{} of {} mutants panicked, e.g. {:?}",
        panics.len(),
        mutants.len(),
        &panics[..panics.len().min(8)]
    );
}
