//! Smooth seeded value noise: hashed lattice values in [−1, 1] blended with the quintic fade
//! `6t⁵ − 15t⁴ + 10t³` (continuous first and second derivatives), so forces built on it vary
//! smoothly in space. The same seed gives the same field on every machine and thread count.

use nalgebra::Vector3;

/// SplitMix64 finaliser: a well-mixed 64-bit hash.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// 64-bit hash of lattice node `(i, j, k)` for `seed`: one SplitMix64 round of the coordinates
/// spread by large odd constants.
fn lattice(i: i64, j: i64, k: i64, seed: u64) -> u64 {
    mix(seed
        ^ (i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (j as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f)
        ^ (k as u64).wrapping_mul(0x1656_67b1_9e37_79f9))
}

/// Channel `c` (0–2) of a lattice hash as a value in [−1, 1]: 21 bits each.
fn channel(h: u64, c: u32) -> f32 {
    let bits = (h >> (1 + 21 * c)) & ((1 << 21) - 1);
    bits as f32 * (2.0 / ((1u64 << 21) - 1) as f32) - 1.0
}

/// Floor without a libm call (the lattice coordinates stay far below 2⁶³).
fn floor(x: f32) -> f32 {
    let t = x as i64 as f32;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Value noise at `p` (lattice units) for `seed`: the three channels (each in [−1, 1]) of one
/// lattice, blended with the quintic fade.
pub fn noise3(p: &Vector3<f32>, seed: u64) -> Vector3<f32> {
    let base = p.map(floor);
    let f = p - base;
    let (i, j, k) = (base.x as i64, base.y as i64, base.z as i64);
    let w = f.map(fade);
    let mut acc = Vector3::zeros();
    for corner in 0..8 {
        let (dx, dy, dz) = (corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        let wx = if dx == 1 { w.x } else { 1.0 - w.x };
        let wy = if dy == 1 { w.y } else { 1.0 - w.y };
        let wz = if dz == 1 { w.z } else { 1.0 - w.z };
        let h = lattice(i + dx, j + dy, k + dz, seed);
        acc += Vector3::new(channel(h, 0), channel(h, 1), channel(h, 2)) * (wx * wy * wz);
    }
    acc
}

/// Scalar value noise at `p` (lattice units) for `seed`, in [−1, 1] (the first channel of
/// [`noise3`] with its own lattice).
pub fn noise(p: &Vector3<f32>, seed: u64) -> f32 {
    let base = p.map(floor);
    let f = p - base;
    let (i, j, k) = (base.x as i64, base.y as i64, base.z as i64);
    let w = f.map(fade);
    let mut acc = 0.0;
    for corner in 0..8 {
        let (dx, dy, dz) = (corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        let wx = if dx == 1 { w.x } else { 1.0 - w.x };
        let wy = if dy == 1 { w.y } else { 1.0 - w.y };
        let wz = if dz == 1 { w.z } else { 1.0 - w.z };
        acc += channel(lattice(i + dx, j + dy, k + dz, seed), 0) * (wx * wy * wz);
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn noise_is_bounded_and_continuous() {
        let mut prev = noise(&Vector3::new(0.0, 0.3, 0.7), 5);
        for s in 1..2000 {
            let p = Vector3::new(s as f32 * 1e-3, 0.3, 0.7);
            let n = noise(&p, 5);
            assert!((-1.0..=1.0).contains(&n));
            assert!((n - prev).abs() < 0.01, "jump at {p:?}");
            prev = n;
        }
    }
}
