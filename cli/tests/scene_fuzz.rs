//! Mutation fuzzing of the scene reader: mutants of the shipped scenes —
//! bytes flipped, deleted or repeated, lines dropped or doubled, numbers replaced by extreme
//! values — are parsed and built (as `scene check` does) under a small budget, and must give a
//! scene or an error, never a panic. Seeded, so a failure reproduces; the suite runs a few
//! hundred mutants (900, about a second), `cargo test -p hairsys-cli --test scene_fuzz --
//! --ignored` 3,000.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use hairsys::budget::Budget;
use hairsys::scene::SceneFile;

/// A small deterministic generator (xorshift64*), so mutants are the same on every machine.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Values that have broken readers elsewhere: huge, tiny, negative, non-finite, overflowing.
const EXTREMES: &[&str] = &[
    "0",
    "-1",
    "1e30",
    "-1e30",
    "1e-30",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "18446744073709551615",
    "99999999999",
    "0.0",
    "[]",
    "\"\"",
    "[1e30, 1e30, 1e30]",
];

/// One mutant of `text`.
fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut bytes = text.as_bytes().to_vec();
    match rng.below(6) {
        0 => {
            let i = rng.below(bytes.len());
            bytes[i] ^= 1 << rng.below(8);
        }
        1 => {
            let i = rng.below(bytes.len());
            let n = 1 + rng.below(16);
            bytes.drain(i..(i + n).min(bytes.len()));
        }
        2 => {
            let i = rng.below(bytes.len());
            let chunk: Vec<u8> = bytes[i..(i + 1 + rng.below(32)).min(bytes.len())].to_vec();
            bytes.splice(i..i, chunk);
        }
        3 | 4 => {
            // Replace a number by an extreme value.
            let s = String::from_utf8_lossy(&bytes).into_owned();
            let numbers: Vec<(usize, usize)> = s
                .char_indices()
                .filter(|(i, c)| {
                    c.is_ascii_digit() && (*i == 0 || !s.as_bytes()[i - 1].is_ascii_alphanumeric())
                })
                .map(|(i, _)| {
                    let end = s[i..]
                        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == 'e' || c == '-'))
                        .map_or(s.len(), |e| i + e);
                    (i, end)
                })
                .collect();
            if let Some(&(a, b)) = numbers.get(rng.below(numbers.len())) {
                let v = EXTREMES[rng.below(EXTREMES.len())];
                return format!("{}{v}{}", &s[..a], &s[b..]);
            }
        }
        _ => {
            let s = String::from_utf8_lossy(&bytes).into_owned();
            let mut lines: Vec<&str> = s.lines().collect();
            let i = rng.below(lines.len());
            if rng.below(2) == 0 {
                lines.remove(i);
            } else {
                let l = lines[i];
                lines.insert(i, l);
            }
            return lines.join("\n");
        }
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Parses and builds `mutants` mutants of every seed scene under a 64 MiB, 10¹⁰ point-substep
/// budget; panics name the seed scene, the mutant number and its text.
fn fuzz(mutants: usize, seed: u64) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let seeds: Vec<(String, String)> = [
        "scenes/collision_demo.toml",
        "scenes/wind_demo.toml",
        "scenes/rod_head.toml",
        "scenes/strips_head.toml",
        "scenes/validation/pendulum.toml",
        "scenes/validation/catenary.toml",
    ]
    .iter()
    .map(|p| {
        let text = std::fs::read_to_string(root.join(p)).unwrap();
        // Small hair counts keep each build quick; the mutants change them again.
        (
            p.to_string(),
            text.replace("count = 2000", "count = 40")
                .replace("count = 500", "count = 40"),
        )
    })
    .collect();
    let budget = Budget {
        memory_bytes: 64 << 20,
        point_substeps: 1e10,
    };
    let mut rng = Rng(seed);
    for (name, text) in &seeds {
        let base_dir = root.join(name).parent().unwrap().to_path_buf();
        for m in 0..mutants {
            let mutant = mutate(text, &mut rng);
            let outcome = catch_unwind(AssertUnwindSafe(|| {
                if let Ok(mut scene) = SceneFile::parse(&mutant, name, base_dir.clone()) {
                    scene.budget = budget;
                    let _ = scene.build();
                }
            }));
            assert!(
                outcome.is_ok(),
                "{name} mutant {m} (seed {seed}) panicked:\n{mutant}"
            );
        }
    }
}

#[test]
fn scene_mutants_give_a_scene_or_an_error_never_a_panic() {
    fuzz(150, 0x5eed_0001);
}

#[test]
#[ignore = "a few thousand mutants, minutes: cargo test -p hairsys-cli --test scene_fuzz -- --ignored"]
fn many_scene_mutants_give_a_scene_or_an_error_never_a_panic() {
    fuzz(500, 0x5eed_0002);
}
