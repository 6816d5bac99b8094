//! Helpers shared by the integration tests: a small strand set and deterministic frames.
#![allow(dead_code)] // each test binary uses a part of these helpers

use std::collections::BTreeMap;

use hair_cache::{CacheHeader, CacheLayout};
use hair_core::{Anchor, RootFrame, StrandInput, StrandSet};
use nalgebra::Vector3;

/// Three strands of 4, 5 and 6 points.
pub fn strands() -> StrandSet {
    let mut set = StrandSet::new();
    for (s, n) in [4usize, 5, 6].into_iter().enumerate() {
        let rest = (0..n)
            .map(|i| Vector3::new(0.01 * s as f32, 0.0, -0.02 * i as f32))
            .collect();
        let anchor = Anchor::Body(RootFrame::at(Vector3::zeros()));
        set.push(StrandInput::uniform(
            anchor,
            rest,
            1e-3,
            1e-4 * (s + 1) as f32,
            0.5,
            0.0,
        ))
        .unwrap();
    }
    set
}

pub fn layout() -> CacheLayout {
    CacheLayout::of(&strands())
}

pub fn header() -> CacheHeader {
    CacheHeader {
        fps: 24.0,
        first_frame: 1,
        scene_toml: "[simulation]\nfps = 24\nsubsteps = \"auto\"\n".into(),
        scene_hash: "9f86d081884c7d659a2feaa0c55ad015a3bf4f1b2b0b822cd15d6c15b0f00a08".into(),
        extra: BTreeMap::from([
            ("components".to_string(), "stretch,bend,gravity".to_string()),
            ("substeps".to_string(), "12".to_string()),
        ]),
    }
}

/// Positions and velocities of frame `frame`: irregular values whose bits must survive,
/// including -0.0, a subnormal and the largest finite f32.
pub fn frame_data(frame: u32, points: usize) -> (Vec<Vector3<f32>>, Vec<Vector3<f32>>) {
    let x = (0..points)
        .map(|i| {
            let t = frame as f32 * 0.37 + i as f32 * 1.13;
            Vector3::new(t.sin() * 0.1, t.cos() * 1e-3, -0.02 * i as f32 + 1e-7 * t)
        })
        .collect::<Vec<_>>();
    let mut v = (0..points)
        .map(|i| {
            Vector3::new(
                i as f32 * 0.5,
                -(frame as f32) / 3.0,
                1.0 / (i as f32 + 1.0),
            )
        })
        .collect::<Vec<_>>();
    v[0] = Vector3::new(-0.0, f32::MIN_POSITIVE / 8.0, f32::MAX);
    (x, v)
}

/// Bit patterns of vectors, for exact comparison (-0.0 ≠ 0.0).
pub fn bits(v: &[Vector3<f32>]) -> Vec<[u32; 3]> {
    v.iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect()
}
