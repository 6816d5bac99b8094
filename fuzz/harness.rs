//! Seeded mutation fuzzing on stable Rust, for the file readers' test suites.
//!
//! Included by `hair-cache/tests/fuzz.rs` and `hair-groom/tests/fuzz.rs`
//! (`#[path = "../../fuzz/harness.rs"] mod harness;`), which install [`Counting`] as their test
//! binary's global allocator. [`run`] derives mutants from real files with a seeded generator
//! (the same seed gives the same mutants on every machine), hands each to a reader, and records a
//! failure when the reader
//!
//! - panics (caught with `catch_unwind`, so one bad mutant does not hide the others),
//! - or, while it reads, allocates more than a budget proportional to the input: a single request
//!   or the peak of live bytes on the reading thread, counted by [`Counting`].
//!
//! A request above [`HUGE`] is refused by returning null, which aborts the binary: before that,
//! the allocator prints the seed file and mutant number to stderr, so the abort is reproducible.
//! Requests between the budget and [`HUGE`] are served and reported as failures after the mutant
//! (a 4 GiB reserve on an 11 KB file is caught this way without being refused).
//!
//! Failing mutants are written to `<target tmp>/fuzz-failures/` to become regression files.
//!
//! Mutations, one to three per mutant: bit flips, byte overwrites with boundary values
//! (0x00, 0x01, 0x7F, 0x80, 0xFE, 0xFF), 32- and 64-bit little-endian length fields inflated to
//! boundary or file-relative values, truncation, deletion, and duplication of a slice (MCAP
//! records and chunks, lines of text); for text, numbers replaced by extreme ones and lines
//! duplicated. This is the approach of AFL's deterministic and havoc stages (Zalewski,
//! "american fuzzy lop" technical whitepaper), without coverage feedback.

#![allow(dead_code)] // each test binary uses a part of it

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

/// Largest allocation served while a mutant is read, bytes (1 GiB); a larger request aborts the
/// test binary after naming the mutant on stderr.
pub const HUGE: usize = 1 << 30;

thread_local! {
    /// Whether the allocations of this thread are being counted.
    static WATCH: Cell<bool> = const { Cell::new(false) };
    /// Bytes allocated and not freed since counting started (saturating at 0).
    static LIVE: Cell<usize> = const { Cell::new(0) };
    /// Largest `LIVE` since counting started.
    static PEAK: Cell<usize> = const { Cell::new(0) };
    /// Largest single request since counting started.
    static LARGEST: Cell<usize> = const { Cell::new(0) };
    /// Seed number and mutant number being read, for the abort message.
    static CURRENT: Cell<(usize, usize)> = const { Cell::new((0, 0)) };
}

/// The system allocator, counting per thread while [`run`] reads a mutant.
pub struct Counting;

fn watching() -> bool {
    WATCH.try_with(Cell::get).unwrap_or(false)
}

fn grow(bytes: usize) {
    let live = LIVE.get().saturating_add(bytes);
    LIVE.set(live);
    PEAK.set(PEAK.get().max(live));
}

fn shrink(bytes: usize) {
    LIVE.set(LIVE.get().saturating_sub(bytes));
}

/// Counts a request of `size` bytes; `false` if it must be refused.
fn admit(size: usize) -> bool {
    LARGEST.set(LARGEST.get().max(size));
    if size <= HUGE {
        return true;
    }
    // No allocation here: format into a stack buffer and write it to stderr directly.
    use std::io::Write;
    let (seed, mutant) = CURRENT.get();
    let mut buf = [0u8; 160];
    let mut cursor = std::io::Cursor::new(&mut buf[..]);
    let _ = writeln!(
        cursor,
        "fuzz: refusing an allocation of {size} bytes while reading seed {seed} mutant {mutant}"
    );
    let n = cursor.position() as usize;
    let _ = std::io::stderr().write_all(&buf[..n]);
    false
}

// SAFETY: every call is forwarded to `System` unchanged, or refused with null as `GlobalAlloc`
// allows; the counters are plain thread-local integers without destructors.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if watching() {
            if !admit(layout.size()) {
                return std::ptr::null_mut();
            }
            grow(layout.size());
        }
        System.alloc(layout)
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if watching() {
            if !admit(layout.size()) {
                return std::ptr::null_mut();
            }
            grow(layout.size());
        }
        System.alloc_zeroed(layout)
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if watching() {
            shrink(layout.size());
        }
        System.dealloc(ptr, layout)
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if watching() {
            if !admit(new_size) {
                return std::ptr::null_mut();
            }
            grow(new_size);
            shrink(layout.size());
        }
        System.realloc(ptr, layout, new_size)
    }
}

/// Runs `f` with this thread's allocations counted; returns its result, the peak of live bytes
/// and the largest single request, bytes.
pub fn measure<T>(f: impl FnOnce() -> T) -> (T, usize, usize) {
    for counter in [&LIVE, &PEAK, &LARGEST] {
        counter.set(0);
    }
    WATCH.set(true);
    let out = f();
    WATCH.set(false);
    (out, PEAK.get(), LARGEST.get())
}

/// A deterministic generator (SplitMix64, Steele, Lea & Flood 2014).
pub struct Rng(u64);

impl Rng {
    /// A generator for `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
}

/// Boundary byte values.
const BYTES: [u8; 6] = [0x00, 0x01, 0x7f, 0x80, 0xfe, 0xff];

/// Applies one random mutation to `data`; `text` adds the text mutations.
pub fn mutate(rng: &mut Rng, data: &mut Vec<u8>, text: bool) {
    if data.is_empty() {
        data.push(BYTES[rng.below(BYTES.len())]);
        return;
    }
    let len = data.len();
    let at = rng.below(len);
    match rng.below(if text { 9 } else { 7 }) {
        // Bit flips.
        0 => {
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
        }
        // A boundary byte.
        1 => data[at] = BYTES[rng.below(BYTES.len())],
        // A length field inflated: u32 or u64, little-endian, at any offset.
        2 | 3 => {
            let n = len as u64;
            let values = [
                u64::from(u32::MAX),
                0x7fff_ffff,
                0x8000_0000,
                0x1_0000,
                n + 1,
                2 * n,
                n.saturating_mul(1000),
                1 << 40,
                u64::MAX,
                u64::MAX / 2,
            ];
            let v = values[rng.below(values.len())];
            let width = if rng.below(2) == 0 { 4 } else { 8 };
            let bytes = v.to_le_bytes();
            let n = width.min(len - at);
            data[at..at + n].copy_from_slice(&bytes[..n]);
        }
        // Truncation.
        4 => data.truncate(at),
        // Deletion of a slice.
        5 => {
            let n = 1 + rng.below((len - at).min(64));
            data.drain(at..at + n);
        }
        // Duplication of a slice (a record, a chunk, a few lines).
        6 => {
            let n = 1 + rng.below((len - at).min(4096));
            let slice = data[at..at + n].to_vec();
            let to = rng.below(len + 1);
            data.splice(to..to, slice);
        }
        // Text: a number replaced by an extreme one.
        7 => {
            let Some(start) = (at..len).find(|&i| data[i].is_ascii_digit()) else {
                return;
            };
            let end = (start..len)
                .find(|&i| !data[i].is_ascii_digit())
                .unwrap_or(len);
            let values: [&[u8]; 8] = [
                b"4294967295",
                b"99999999999999999999",
                b"-1",
                b"0",
                b"nan",
                b"1e39",
                b"-2147483648",
                b"18446744073709551616",
            ];
            data.splice(start..end, values[rng.below(values.len())].iter().copied());
        }
        // Text: a line repeated.
        _ => {
            let start = data[..at]
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |i| i + 1);
            let end = (at..len).find(|&i| data[i] == b'\n').map_or(len, |i| i + 1);
            let line = data[start..end].to_vec();
            for _ in 0..1 + rng.below(8) {
                data.splice(end..end, line.iter().copied());
            }
        }
    }
}

/// What [`run`] saw.
#[derive(Debug, Default)]
pub struct Report {
    /// Mutants read.
    pub mutants: usize,
    /// Mutants the reader accepted.
    pub accepted: usize,
    /// Mutants the reader refused with an error.
    pub refused: usize,
    /// Each failure: seed, mutant number and what happened.
    pub failures: Vec<String>,
    /// Time taken, s.
    pub seconds: f64,
}

/// Reads `mutants` mutants of each of `seeds` (name, bytes) with `read`, which returns whether
/// the reader accepted the input (`Ok`) or refused it with an error that names the file
/// (`Err` with the message; an empty message is a failure). `seed` picks the mutants; `text`
/// adds text mutations; `budget` gives the most bytes a mutant of `n` bytes may allocate.
pub fn run(
    name: &str,
    seeds: &[(String, Vec<u8>)],
    mutants: usize,
    seed: u64,
    text: bool,
    budget: impl Fn(usize) -> usize,
    mut read: impl FnMut(&[u8]) -> Result<(), String>,
) -> Report {
    let mut report = Report::default();
    let mut rng = Rng::new(seed);
    let start = std::time::Instant::now();
    for (s, (seed_name, bytes)) in seeds.iter().enumerate() {
        for m in 0..mutants {
            let mut data = bytes.clone();
            for _ in 0..1 + rng.below(3) {
                mutate(&mut rng, &mut data, text);
            }
            let limit = budget(data.len());
            CURRENT.set((s, m));
            for counter in [&LIVE, &PEAK, &LARGEST] {
                counter.set(0);
            }
            WATCH.set(true);
            let outcome = catch_unwind(AssertUnwindSafe(|| read(&data)));
            WATCH.set(false);
            let (peak, largest) = (PEAK.get(), LARGEST.get());
            report.mutants += 1;
            let accepted = matches!(outcome, Ok(Ok(())));
            let failure = match &outcome {
                Ok(Ok(())) => None,
                Ok(Err(message)) if !message.is_empty() => None,
                Ok(Err(_)) => Some("refused without a message".to_string()),
                Err(panic) => Some(format!(
                    "panicked: {}",
                    panic
                        .downcast_ref::<String>()
                        .map(String::as_str)
                        .or_else(|| panic.downcast_ref::<&str>().copied())
                        .unwrap_or("(no message)")
                )),
            }
            .or_else(|| {
                (peak.max(largest) > limit).then(|| {
                    format!(
                        "allocated {largest} bytes at once, {peak} at peak, for {} input bytes \
                         (budget {limit})",
                        data.len()
                    )
                })
            });
            match failure {
                Some(f) => {
                    let file = save_failure(name, s, m, &data);
                    report.failures.push(format!(
                        "{seed_name} mutant {m}: {f} (input saved as {})",
                        file.display()
                    ));
                }
                None if accepted => report.accepted += 1,
                None => report.refused += 1,
            }
        }
    }
    report.seconds = start.elapsed().as_secs_f64();
    report
}

/// Writes a failing mutant to `<target tmp>/fuzz-failures/<name>-<seed>-<mutant>.bin`.
fn save_failure(name: &str, seed: usize, mutant: usize, data: &[u8]) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
    let path = dir.join(format!("{name}-{seed}-{mutant}.bin"));
    let _ = std::fs::create_dir_all(&dir).and_then(|_| std::fs::write(&path, data));
    path
}

/// Panics with every failure of `report` if there is one; else prints its counts.
pub fn assert_clean(name: &str, report: &Report) {
    println!(
        "{name}: {} mutants in {:.1} s, {} read, {} refused with an error",
        report.mutants, report.seconds, report.accepted, report.refused
    );
    assert!(
        report.failures.is_empty(),
        "{name}: {} of {} mutants failed:\n{}",
        report.failures.len(),
        report.mutants,
        report.failures.join("\n")
    );
}
