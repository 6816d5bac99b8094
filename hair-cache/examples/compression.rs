//! Measures each chunk compression on frames of about 8 MB (349 536 points: 10 923 strands of 32
//! points on a head-sized sphere, swinging under gravity in the hair-core solver): bytes on disk
//! per point-frame, write time per frame (payload encoding, compression, I/O) and read time per
//! frame.
//!
//! `cargo run --release -p hair-cache --example compression`

use std::time::Instant;

use hair_cache::{CacheHeader, CacheLayout, CacheReader, CacheWriter, Compression, WriterOptions};
use hair_core::{
    Anchor, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings, StrandInput, StrandSet,
};
use nalgebra::Vector3;

const STRANDS: usize = 10_923;
const POINTS_PER_STRAND: usize = 32;
const FRAMES: u32 = 6;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut strands = StrandSet::new();
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    for s in 0..STRANDS {
        // Roots on the upper half of a 10 cm sphere (Fibonacci spiral), hair growing outwards.
        let z = 1.0 - s as f32 / STRANDS as f32;
        let r = (1.0 - z * z).sqrt();
        let dir = Vector3::new(
            r * (golden * s as f32).cos(),
            r * (golden * s as f32).sin(),
            z,
        );
        let rest = (0..POINTS_PER_STRAND)
            .map(|i| dir * (0.008 * i as f32))
            .collect();
        let anchor = Anchor::Body(RootFrame::at(dir * 0.1));
        strands.push(StrandInput::uniform(anchor, rest, 1e-3, 5e-4, 0.2, 0.0))?;
    }
    let scalp = Scalp::fixed();
    strands.reset_to_rest(&scalp);
    let mut solver = MassSpringSolver::new(
        SolverSettings::default(),
        HairParams::default(),
        &strands,
        &scalp,
        0,
    )?;
    let mut frames = Vec::new();
    let t = Instant::now();
    for _ in 0..FRAMES {
        let report = solver.step_frame(&mut strands, &scalp)?;
        frames.push((
            report.frame,
            strands.positions.clone(),
            strands.velocities.clone(),
        ));
    }
    let points = strands.point_count();
    println!(
        "{points} points, {} bytes per frame payload; solver {:.2} s per frame",
        hair_cache::layout::frame_payload_len(points),
        t.elapsed().as_secs_f64() / f64::from(FRAMES)
    );

    let dir = std::env::temp_dir().join(format!("hair-cache-compression-{}", std::process::id()));
    std::fs::create_dir_all(&dir)?;
    let layout = CacheLayout::of(&strands);
    let header = CacheHeader {
        fps: 24.0,
        first_frame: 0,
        scene_hash: "00".into(),
        ..Default::default()
    };
    // Hair at rest: the rest pose, zero velocities.
    strands.reset_to_rest(&scalp);
    let still: Vec<_> = (1..=FRAMES)
        .map(|f| (f, strands.positions.clone(), strands.velocities.clone()))
        .collect();
    for (name, frames) in [("swinging", &frames), ("still", &still)] {
        println!("{name}: compression  bytes/point-frame  ratio  write ms/frame  read ms/frame");
        for compression in [Compression::None, Compression::Lz4, Compression::Zstd] {
            let path = dir.join(format!("{compression}.mcap"));
            let options = WriterOptions {
                compression,
                ..Default::default()
            };
            // The file without frames: header, metadata, layout attachment, summary.
            let base = CacheWriter::create(&path, &header, &layout, options)?
                .finish()?
                .bytes;
            let t = Instant::now();
            let mut writer = CacheWriter::create(&path, &header, &layout, options)?;
            for (frame, x, v) in frames {
                writer.write_frame(*frame, x, v)?;
            }
            let summary = writer.finish()?;
            let write_ms = t.elapsed().as_secs_f64() * 1e3 / f64::from(FRAMES);
            let t = Instant::now();
            let mut reader = CacheReader::open(&path)?;
            for (frame, _, _) in frames {
                reader.read_frame(*frame)?;
            }
            let read_ms = t.elapsed().as_secs_f64() * 1e3 / f64::from(FRAMES);
            let per = (summary.bytes - base) as f64 / (points as f64 * f64::from(FRAMES));
            println!(
                "{:>width$}  {compression:<11}  {per:>17.2}  {:>5.3}  {write_ms:>14.1}  {read_ms:>13.1}",
                "",
                per / 24.0,
                width = name.len()
            );
        }
    }
    std::fs::remove_dir_all(&dir)?;
    Ok(())
}
