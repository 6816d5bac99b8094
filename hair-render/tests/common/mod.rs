//! Parents shared by the integration tests.

#![allow(dead_code)]

use hair_render::ChildBuffers;
use nalgebra::Vector3;

/// Point `i` of the children's flat point buffer, m.
pub fn point(c: &ChildBuffers, i: usize) -> Vector3<f32> {
    Vector3::new(c.points[3 * i], c.points[3 * i + 1], c.points[3 * i + 2])
}

/// Index of the first point of every curve, and one past the last.
pub fn starts(c: &ChildBuffers) -> Vec<usize> {
    let mut s = vec![0];
    for &n in &c.vertex_counts {
        s.push(s.last().unwrap() + n as usize);
    }
    s
}

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
