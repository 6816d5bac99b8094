//! `hairsys simulate`: run a scene frame by frame and write every frame to an MCAP point cache.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use hair_cache::{CacheHeader, CacheLayout, CacheSummary, CacheWriter, WriterOptions};
use hair_core::{FrameReport, ProjectionReport, Solver, StrandModel};
use serde::Serialize;

use crate::model::ModelSolver;
use crate::resume::resume;
use crate::scene::{SceneError, SceneFile};

/// Why a run stopped.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The scene or the options are unusable (exit code 2).
    #[error("{0}")]
    Input(#[from] SceneError),
    /// An option is out of range (exit code 2).
    #[error("{0}")]
    Usage(String),
    /// The solver refused the setup or blew up (exit code 1).
    #[error("{scene}: {source}")]
    Solver {
        /// The scene being run.
        scene: String,
        /// The solver's error.
        source: hair_core::HairError,
    },
    /// The cache could not be written (exit code 1).
    #[error("{0}")]
    Cache(#[from] hair_cache::CacheError),
}

impl RunError {
    /// Process exit code: 2 for bad input, 1 for a failed run.
    pub fn exit_code(&self) -> i32 {
        match self {
            RunError::Input(_) | RunError::Usage(_) => 2,
            RunError::Solver { .. } | RunError::Cache(_) => 1,
        }
    }
}

/// Options of one run.
pub struct SimulateOptions {
    /// The scene.
    pub scene: SceneFile,
    /// Cache path to write.
    pub cache: PathBuf,
    /// Frame range overriding the scene's `[first, last]`.
    pub frames: Option<(u32, u32)>,
    /// Worker threads (default: all cores).
    pub threads: Option<usize>,
    /// Cache compression, chunking and the optional Foxglove view.
    pub writer: WriterOptions,
    /// Continue the interrupted run left in `CACHE.partial` instead of starting over.
    pub resume: bool,
}

impl SimulateOptions {
    fn scene_error(&self, message: String) -> SceneError {
        SceneError {
            file: self.scene.origin.clone(),
            message,
        }
    }
}

/// What a finished run did.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// Frames simulated (not counting the rest frame).
    pub frames: u32,
    /// Strands simulated.
    pub strands: usize,
    /// Points simulated.
    pub points: usize,
    /// Worker threads.
    pub threads: usize,
    /// Force substeps per step.
    pub substeps: u32,
    /// Substep length, s.
    pub dt: f64,
    /// Stability bound 2/ω, s.
    pub dt_bound: f64,
    /// Strand model that ran: `"mass-spring"`, `"rod"` or `"strips"`.
    pub model: &'static str,
    /// Compiled copy of the mass-spring kernel this CPU ran: `"avx2"` or `"baseline"` (same
    /// bits, see [`hair_core::kernel_instructions`]).
    pub kernel: &'static str,
    /// The rod model's projection figures over the run (absent for mass-spring).
    pub projection: Option<ProjectionReport>,
    /// Model components that ran.
    pub components: Vec<&'static str>,
    /// Mean wall-clock time per simulated frame, ms (solver only).
    pub ms_per_frame: f64,
    /// Mean time per frame spent writing the cache, ms.
    pub cache_ms_per_frame: f64,
    /// Mean time per frame evaluating roots, ms.
    pub roots_ms_per_frame: f64,
    /// Mean time per frame in the strand substeps, ms.
    pub strands_ms_per_frame: f64,
    /// Mean time per frame detecting contacts, ms (0 without colliders).
    pub contacts_ms_per_frame: f64,
    /// Mean time per frame in the hair–hair voxel grid (build, friction, repulsion), ms (0 when
    /// off).
    pub hair_hair_ms_per_frame: f64,
    /// Mean time per frame evaluating force fields, ms (0 without fields).
    pub fields_ms_per_frame: f64,
    /// Mean number of points with a contact per collision step.
    pub contact_points_per_step: f64,
    /// Point-frames that ended inside a collider (closer than radius + thickness) after
    /// outrunning detection's margin, put back on its surface by the frame-end check (see
    /// `hair_core::contacts`). Nonzero means hair moved faster within a step than detection
    /// allowed for: a strain limit (`max_strain`) or more collision steps keeps it within.
    pub escaped_points: u64,
    /// Most collision steps any frame took (more than `[solver] steps` when colliders moved
    /// fast).
    pub max_collision_steps: u32,
    /// Throughput of the solver, point-substeps per second.
    pub point_substeps_per_s: f64,
    /// Largest relative segment stretch seen at any frame end.
    pub max_stretch: f32,
    /// The written cache.
    pub cache: CacheSummary,
    /// With `--resume`: the frame the interrupted run was continued from.
    pub resumed_from: Option<u32>,
    /// With `--resume`: what the interrupted run had lost (frames after its last complete chunk).
    pub recovery_warning: Option<String>,
}

/// Runs a scene to completion, calling `on_frame` after each frame.
pub fn simulate(
    opts: &SimulateOptions,
    mut on_frame: impl FnMut(&FrameReport),
) -> Result<RunSummary, RunError> {
    let mut sim = opts.scene.build()?;
    if let Some((first, last)) = opts.frames {
        if last <= first {
            return Err(RunError::Usage(format!(
                "--frames {first}-{last}: the last frame must come after the first"
            )));
        }
        sim.set_frames(first, last);
    }
    let scene_hash = opts.scene.hash()?;
    let first_frame = sim.first_frame;
    let resumed = match opts.resume {
        true => Some(resume(&opts.cache, &scene_hash, &mut sim)?),
        false => None,
    };
    let threads = opts.threads.unwrap_or_else(rayon::current_num_threads);
    if threads == 0 {
        return Err(RunError::Usage("--threads 0: use at least 1 thread".into()));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| {
            RunError::Usage(format!(
                "--threads {threads}: cannot start the thread pool ({e})"
            ))
        })?;
    let scene_name = opts.scene.origin.clone();
    let solver_err = |source| RunError::Solver {
        scene: scene_name.clone(),
        source,
    };
    let mut solver = match sim.model {
        StrandModel::MassSpring => ModelSolver::MassSpring(Box::new(
            Solver::new(
                sim.settings,
                sim.params,
                &sim.strands,
                &sim.scalp_at(sim.first_frame as f32),
                sim.first_frame,
            )
            .and_then(|s| sim.with_interactions(s))
            .and_then(|s| sim.with_inextensibility(s))
            .map_err(solver_err)?,
        )),
        StrandModel::Rod => ModelSolver::rod(&sim).map_err(solver_err)?,
        StrandModel::Strips => ModelSolver::strips(&sim).map_err(solver_err)?,
    };
    let mut components = solver.components(&sim.strands).0;
    // Colliders at the first frame, posed again for every frame (the scalp collider follows the
    // scalp by itself).
    let mut colliders = sim
        .colliders_at(sim.first_frame as f32)
        .map_err(|e| RunError::Input(opts.scene_error(sim.collider_message(&e))))?;
    if !colliders.is_empty() {
        components.push("contacts");
    }

    let mut extra = BTreeMap::new();
    extra.insert("components".to_string(), components.join(","));
    extra.insert("substeps".to_string(), solver.substeps().to_string());
    extra.insert("model".to_string(), solver.model().name().to_string());
    extra.insert(
        "integrator".to_string(),
        format!("{:?}", sim.settings.integrator),
    );
    let header = CacheHeader {
        fps: sim.settings.fps as f64,
        first_frame,
        scene_toml: opts.scene.text.clone(),
        scene_hash,
        extra,
    };
    let mut writer = CacheWriter::create(
        &opts.cache,
        &header,
        &CacheLayout::of(&sim.strands),
        WriterOptions {
            // A resumed run keeps the precision its frames were written with.
            precision: resumed
                .as_ref()
                .map_or(opts.writer.precision, |r| r.precision),
            ..opts.writer
        },
    )?;
    // A resumed run first writes the frames it takes over; the last of them is the state it
    // continues from, written below like a first frame.
    if let Some(resumed) = &resumed {
        for f in &resumed.frames[..resumed.frames.len() - 1] {
            writer.write_frame(f.frame, &f.positions, &f.velocities)?;
        }
    }
    writer.write_frame(
        sim.first_frame,
        &sim.strands.positions,
        &sim.strands.velocities,
    )?;

    let (mut solve_time, mut cache_time) = (Duration::ZERO, Duration::ZERO);
    let (mut roots_time, mut strands_time) = (Duration::ZERO, Duration::ZERO);
    let mut contacts_time = Duration::ZERO;
    let (mut volume_time, mut fields_time) = (Duration::ZERO, Duration::ZERO);
    let (mut contact_points, mut collision_steps, mut max_steps) = (0u64, 0u64, 0u32);
    let mut escaped_points = 0u64;
    let mut point_substeps = 0u64;
    let mut max_stretch = 0.0f32;
    for frame in sim.first_frame + 1..=sim.last_frame {
        let scalp = sim.scalp_at(frame as f32);
        sim.pose_colliders(&mut colliders, frame as f32)
            .map_err(|e| RunError::Input(opts.scene_error(sim.collider_message(&e))))?;
        let t0 = Instant::now();
        let report = pool
            .install(|| solver.step_frame_with_colliders(&mut sim.strands, &scalp, &mut colliders))
            .map_err(solver_err)?;
        solve_time += t0.elapsed();
        roots_time += report.times.roots;
        strands_time += report.times.strands;
        contacts_time += report.times.contacts;
        volume_time += report.times.volume;
        fields_time += report.times.fields;
        contact_points += report.contact_points;
        escaped_points += report.escaped_points;
        collision_steps += report.steps as u64;
        max_steps = max_steps.max(report.steps);
        point_substeps += report.point_substeps;
        max_stretch = max_stretch.max(report.max_stretch);
        let t1 = Instant::now();
        writer.write_frame(frame, &sim.strands.positions, &sim.strands.velocities)?;
        cache_time += t1.elapsed();
        on_frame(&report);
    }
    let cache = writer.finish()?;
    let frames = sim.last_frame - sim.first_frame;
    let per_frame = |d: Duration| d.as_secs_f64() * 1e3 / frames as f64;
    Ok(RunSummary {
        scene: opts.scene.scene.scene.name.clone(),
        frames,
        strands: sim.strands.len(),
        points: sim.strands.point_count(),
        threads,
        substeps: solver.substeps(),
        dt: solver.dt(),
        dt_bound: solver.dt_bound(),
        model: solver.model().name(),
        kernel: hair_core::kernel_instructions(),
        projection: solver.projection(),
        components,
        ms_per_frame: per_frame(solve_time),
        cache_ms_per_frame: per_frame(cache_time),
        roots_ms_per_frame: per_frame(roots_time),
        strands_ms_per_frame: per_frame(strands_time),
        contacts_ms_per_frame: per_frame(contacts_time),
        hair_hair_ms_per_frame: per_frame(volume_time),
        fields_ms_per_frame: per_frame(fields_time),
        contact_points_per_step: contact_points as f64 / collision_steps.max(1) as f64,
        escaped_points,
        max_collision_steps: max_steps,
        point_substeps_per_s: point_substeps as f64 / solve_time.as_secs_f64().max(1e-12),
        max_stretch,
        cache,
        resumed_from: resumed.as_ref().map(|r| r.last_frame()),
        recovery_warning: resumed.and_then(|r| r.warning.map(|w| w.to_string())),
    })
}

impl std::fmt::Display for RunSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "simulated {} frames of {} strands ({} points) on {} threads ({} kernel)",
            self.frames, self.strands, self.points, self.threads, self.kernel
        )?;
        writeln!(
            f,
            "  solver: {:.2} ms/frame ({:.1} M point-substeps/s; roots {:.2} ms, strands {:.2} ms), cache {:.2} ms/frame",
            self.ms_per_frame,
            self.point_substeps_per_s / 1e6,
            self.roots_ms_per_frame,
            self.strands_ms_per_frame,
            self.cache_ms_per_frame
        )?;
        writeln!(
            f,
            "  substeps: {} per step, dt = {:.3e} s (stability bound 2/ω = {:.3e} s)",
            self.substeps, self.dt, self.dt_bound
        )?;
        if self.components.contains(&"contacts") {
            writeln!(
                f,
                "  contacts: detection {:.2} ms/frame, {:.0} points in contact per step, up to {} collision steps per frame",
                self.contacts_ms_per_frame, self.contact_points_per_step, self.max_collision_steps
            )?;
            if self.escaped_points > 0 {
                writeln!(
                    f,
                    "  contacts: {} point-frames outran detection and ended inside a collider; \
                     put back on its surface (a strain limit, max_strain, or more steps avoids it)",
                    self.escaped_points
                )?;
            }
        }
        if self.hair_hair_ms_per_frame > 0.0 || self.fields_ms_per_frame > 0.0 {
            writeln!(
                f,
                "  hair-hair grid {:.2} ms/frame, force fields {:.2} ms/frame",
                self.hair_hair_ms_per_frame, self.fields_ms_per_frame
            )?;
        }
        if let Some(frame) = self.resumed_from {
            writeln!(f, "  resumed from frame {frame}")?;
        }
        writeln!(f, "  model: {}", self.model)?;
        if let Some(p) = &self.projection {
            writeln!(
                f,
                "  projection: {:.2} iterations per projection on average, at most {}; residual up \
                 to {:.1e} (tolerance {:.0e}); max strain {:.1e}",
                p.mean_iterations(),
                p.max_iterations,
                p.residual,
                p.tolerance,
                p.max_strain
            )?;
            if let Some(w) = p.warning() {
                writeln!(f, "  warning: {w}")?;
            }
        }
        writeln!(f, "  max stretch: {:.3} %", self.max_stretch * 100.0)?;
        writeln!(f, "  components: {}", self.components.join(", "))?;
        write!(f, "{}", self.cache)
    }
}
