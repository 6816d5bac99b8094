//! The optional Foxglove view: a `foxglove.SceneUpdate` message per frame, with one line strip per
//! displayed strand, so a cache can be scrubbed in Foxglove's 3D panel.
//!
//! Channel [`SCENE_TOPIC`], message encoding `json`, schema `foxglove.SceneUpdate` with encoding
//! `jsonschema` and the official schema text ([`SCENE_UPDATE_SCHEMA`], MIT, © Foxglove
//! Technologies). Strands are decimated evenly to at most [`FoxgloveOptions::max_strands`] so the
//! view stays light (a 20,000-strand groom would otherwise add ~15 MB of JSON per frame). Every
//! field of the schema is written (Foxglove fills nothing in for JSON messages). Positions are in
//! the cache's frame `world` (meters, Z up).

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::layout::CacheLayout;

/// Topic of the Foxglove view channel.
pub const SCENE_TOPIC: &str = "/hairsys/scene";
/// Schema name of the view's messages.
pub const SCENE_UPDATE_SCHEMA_NAME: &str = "foxglove.SceneUpdate";
/// The official JSON schema of `foxglove.SceneUpdate`.
pub const SCENE_UPDATE_SCHEMA: &str = include_str!("../schemas/foxglove/SceneUpdate.json");

/// What the view shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct FoxgloveOptions {
    /// Largest number of strands drawn per frame (evenly spaced through the set).
    pub max_strands: usize,
}

impl Default for FoxgloveOptions {
    fn default() -> Self {
        Self { max_strands: 500 }
    }
}

impl FoxgloveOptions {
    /// Indices of the strands drawn, evenly spaced, in increasing order.
    pub fn strands(&self, strand_count: usize) -> Vec<usize> {
        let shown = self.max_strands.min(strand_count);
        (0..shown)
            .map(|i| i * strand_count / shown.max(1))
            .collect()
    }
}

#[derive(Serialize)]
struct Time {
    sec: u64,
    nsec: u32,
}

#[derive(Serialize)]
struct Xyz {
    x: f64,
    y: f64,
    z: f64,
}

#[derive(Serialize)]
struct Quaternion {
    x: f64,
    y: f64,
    z: f64,
    w: f64,
}

#[derive(Serialize)]
struct Pose {
    position: Xyz,
    orientation: Quaternion,
}

#[derive(Serialize)]
struct Color {
    r: f64,
    g: f64,
    b: f64,
    a: f64,
}

#[derive(Serialize)]
struct Line {
    #[serde(rename = "type")]
    kind: u8,
    pose: Pose,
    thickness: f64,
    scale_invariant: bool,
    points: Vec<Xyz>,
    color: Color,
    colors: [Color; 0],
    indices: [u32; 0],
}

#[derive(Serialize)]
struct Entity {
    timestamp: Time,
    frame_id: &'static str,
    id: &'static str,
    lifetime: Time,
    frame_locked: bool,
    metadata: [(); 0],
    arrows: [(); 0],
    cubes: [(); 0],
    spheres: [(); 0],
    cylinders: [(); 0],
    lines: Vec<Line>,
    triangles: [(); 0],
    texts: [(); 0],
    models: [(); 0],
}

#[derive(Serialize)]
struct SceneUpdate {
    deletions: [(); 0],
    entities: [Entity; 1],
}

/// The JSON `foxglove.SceneUpdate` of one frame at `time_ns` (ns): entity `hair` in frame
/// `world`, one line strip (2 px, hair brown) per shown strand of `positions` (m).
pub fn scene_update(
    layout: &CacheLayout,
    positions: &[Vector3<f32>],
    time_ns: u64,
    options: &FoxgloveOptions,
) -> Vec<u8> {
    let identity = || Pose {
        position: Xyz {
            x: 0.0,
            y: 0.0,
            z: 0.0,
        },
        orientation: Quaternion {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        },
    };
    let lines = options
        .strands(layout.strand_count())
        .into_iter()
        .map(|s| {
            let range = layout.offsets[s] as usize..layout.offsets[s + 1] as usize;
            Line {
                kind: 0, // LINE_STRIP
                pose: identity(),
                thickness: 2.0,
                scale_invariant: true,
                points: positions[range]
                    .iter()
                    .map(|p| Xyz {
                        x: p.x as f64,
                        y: p.y as f64,
                        z: p.z as f64,
                    })
                    .collect(),
                color: Color {
                    r: 0.45,
                    g: 0.3,
                    b: 0.15,
                    a: 1.0,
                },
                colors: [],
                indices: [],
            }
        })
        .collect();
    let timestamp = Time {
        sec: time_ns / 1_000_000_000,
        nsec: (time_ns % 1_000_000_000) as u32,
    };
    let update = SceneUpdate {
        deletions: [],
        entities: [Entity {
            timestamp,
            frame_id: "world",
            id: "hair",
            lifetime: Time { sec: 0, nsec: 0 },
            frame_locked: false,
            metadata: [],
            arrows: [],
            cubes: [],
            spheres: [],
            cylinders: [],
            lines,
            triangles: [],
            texts: [],
            models: [],
        }],
    };
    serde_json::to_vec(&update).expect("scene updates serialise")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimation_is_even_and_bounded() {
        let o = FoxgloveOptions { max_strands: 4 };
        assert_eq!(o.strands(10), vec![0, 2, 5, 7]);
        assert_eq!(o.strands(3), vec![0, 1, 2]);
        assert!(o.strands(0).is_empty());
    }

    #[test]
    fn schema_is_the_official_scene_update() {
        let schema: serde_json::Value = serde_json::from_str(SCENE_UPDATE_SCHEMA).unwrap();
        assert_eq!(schema["title"], SCENE_UPDATE_SCHEMA_NAME);
    }
}
