//! A host loop as a DCC plugin runs it: the built-in default scene's groom on a head that the
//! host deforms every frame (a bend of the upper head, as an armature would give), stepped
//! through a `Session` on a pool of the host's size, with a snapshot to scrub back.
//!
//! `cargo run --release -p hairsys --example deforming_scalp`

use std::sync::Arc;

use hairsys::scene::SceneFile;
use hairsys::Session;
use nalgebra::{Isometry3, Vector3};

fn main() -> Result<(), hairsys::Error> {
    let scene = SceneFile::builtin_default();
    let mut session = Session::from_scene(&scene)?;
    let pool = hair_par::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool of two threads starts");
    session.set_thread_pool(Arc::new(pool));
    let rest: Vec<Vector3<f32>> = session
        .rest_scalp()
        .expect("the default scene has a head")
        .positions()
        .to_vec();
    let mut scrub_point = None;
    for frame in 2..=24u32 {
        // The host's deformation: the head above its base bends forward and back.
        let bend = 0.4 * (frame as f32 * 0.5).sin();
        let deformed: Vec<[f32; 3]> = rest
            .iter()
            .map(|v| {
                let h = v.z.max(0.0);
                [v.x, v.y + bend * h * h / 0.22, v.z]
            })
            .collect();
        session.set_scalp_vertices(&deformed, Isometry3::identity())?;
        let report = session.step()?;
        if frame == 12 {
            scrub_point = Some(session.snapshot());
        }
        let tip = session.positions()[session.strand_offsets()[1] as usize - 1];
        println!(
            "frame {:2}: strand 0 tip at ({:+.3}, {:+.3}, {:+.3}) m, max stretch {:.2} %, {:.1} ms",
            report.frame,
            tip[0],
            tip[1],
            tip[2],
            100.0 * report.max_stretch,
            report.times.strands.as_secs_f64() * 1e3
        );
    }
    if let Some(snap) = scrub_point {
        session.restore(&snap)?;
        println!("scrubbed back to frame {}", session.frame());
    }
    Ok(())
}
