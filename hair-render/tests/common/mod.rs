//! Parents shared by the integration tests.

#![allow(dead_code)]

use nalgebra::Vector3;

/// A straight parent along +z from `root`, `n` points over `length` meters.
pub fn straight(root: Vector3<f32>, n: usize, length: f32) -> Vec<Vector3<f32>> {
    (0..n)
        .map(|i| root + Vector3::new(0.0, 0.0, length * i as f32 / (n - 1) as f32))
        .collect()
}

/// A parent bending over in the x–z plane (quarter circle of radius `r`), `n` points.
pub fn bent(root: Vector3<f32>, n: usize, r: f32) -> Vec<Vector3<f32>> {
    (0..n)
        .map(|i| {
            let a = std::f32::consts::FRAC_PI_2 * i as f32 / (n - 1) as f32;
            root + Vector3::new(r - r * a.cos(), 0.0, r * a.sin())
        })
        .collect()
}

/// Flat positions and offsets of `strands`.
pub fn flatten(strands: &[Vec<Vector3<f32>>]) -> (Vec<Vector3<f32>>, Vec<u32>) {
    let mut offsets = vec![0u32];
    let mut positions = Vec::new();
    for s in strands {
        positions.extend_from_slice(s);
        offsets.push(positions.len() as u32);
    }
    (positions, offsets)
}
