//! The batch run (`hairsys simulate`): a scene run frame by frame through a [`Session`], every
//! frame written to an MCAP point cache, optionally continuing an interrupted run
//! ([`crate::resume`]). Hosts that drive frames themselves use the [`Session`] directly; this
//! is the same loop with the scene's keyframes, so a host that sets the scene's scalp and
//! collider poses each frame gets the same bits.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use hair_cache::{CacheLayout, CacheSummary, CacheWriter, WriterOptions};
use hair_core::{Component, FrameReport, KernelChoice, ModelFigures, ProjectionReport};
use serde::Serialize;

use crate::error::Error;
use crate::output::quality::{FrameToMeasure, QualityTracker, RunQuality};
use crate::resume::{resume, Resumed};
use crate::scene::SceneFile;
use crate::session::{FrameView, Session};

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
    /// Which compiled copy of the mass-spring kernel runs (same bits either way).
    pub kernel: KernelChoice,
    /// Measure every frame's quality (penetration, strain, hairpins, drift from the groom,
    /// velocity–position mismatch) into [`RunSummary::quality`]; costs a few % of the run.
    pub quality: bool,
}

/// What a finished run did.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// Scene name.
    pub scene: String,
    /// Frames written to the cache, the first (rest) frame included: the count `cache info`,
    /// the progress bar and the text summary give (with `--resume`, the frames taken over from
    /// the interrupted run count too).
    pub frames: u32,
    /// Frames this run stepped the solver through: `frames - 1` for a fresh run (the first frame
    /// is the rest state, written without a step), fewer when it resumed.
    pub stepped: u32,
    /// First frame of the run (the rest state).
    pub first_frame: u32,
    /// Last frame of the run.
    pub last_frame: u32,
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
    /// Time integrator of the mass-spring model, as the scene spells it (`None` for the rod and
    /// the strips, which have their own schemes).
    pub integrator: Option<&'static str>,
    /// Why `[solver] integrator = "auto"` chose `integrator`, in words (`None` when the scene
    /// named it).
    pub integrator_reason: Option<String>,
    /// Where the scene named an implicit integrator at a substep it was measured not to hold on
    /// hair this sharply bent: what to expect and what to take instead (see
    /// [`crate::scene::integrator::sharp_joint_warning`]).
    pub integrator_warning: Option<String>,
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
    /// Point-frames whose point had a contact but ended the frame deeper inside a collider than
    /// the contact model's own error (25 µm), put back on its surface by the frame-end check
    /// (see `hair_core::contacts`). Each moves by at most its depth; their count says how often
    /// the substep's contact model missed the exact surface.
    pub deep_contact_points: u64,
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
    /// The run's quality report (with [`SimulateOptions::quality`]; frames taken over by a
    /// resumed run are not in it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quality: Option<RunQuality>,
    /// Mean time per frame the quality report added to the run, ms (0 without it): it is
    /// measured while each frame is written to the cache, so only what outlasts the write
    /// counts.
    pub quality_ms_per_frame: f64,
}

/// Runs a scene to completion, calling `on_frame` after each frame.
pub fn simulate(
    opts: &SimulateOptions,
    mut on_frame: impl FnMut(&FrameReport),
) -> Result<RunSummary, Error> {
    let mut sim = opts.scene.build()?;
    if let Some((first, last)) = opts.frames {
        if last < first {
            return Err(Error::Usage(format!(
                "--frames {first}-{last}: the last frame must not come before the first (one \
                 frame N writes the rest frame alone)"
            )));
        }
        sim.check_deforming_frames(first, last)
            .map_err(|e| Error::Usage(format!("--frames {first}-{last}: {e}")))?;
        sim.set_frames(first, last);
    }
    sim.settings.kernel = opts.kernel;
    let scene_hash = opts.scene.hash()?;
    let (first_frame, last_frame) = (sim.first_frame, sim.last_frame);
    let resumed = match opts.resume {
        true => Some(resume(&opts.cache, &scene_hash, &mut sim)?),
        false => None,
    };
    let threads = opts.threads.unwrap_or_else(hair_par::current_num_threads);
    if threads == 0 {
        return Err(Error::Usage("--threads 0: use at least 1 thread".into()));
    }
    let pool = hair_par::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| {
            Error::Usage(format!(
                "--threads {threads}: cannot start the thread pool ({e})"
            ))
        })?;
    let steps = sim.settings.steps;
    let mass_spring = sim.model == hair_core::StrandModel::MassSpring;
    let integrator = sim.integrator.clone();
    let mut session = Session::from_simulation(sim, &opts.scene, scene_hash)?;
    if let Some((first, last)) = opts.frames {
        // The scene's build checked the work of the scene's own range; --frames replaces it.
        let start = resumed.as_ref().map_or(first_frame, Resumed::last_frame);
        let (points, substeps) = (session.strands().point_count(), session.solver().substeps());
        let frames = last_frame - start;
        let work = crate::budget::RunWork {
            points,
            substeps: f64::from(substeps),
            integrator: integrator.integrator,
            steps,
            frames: f64::from(frames),
        };
        opts.scene
            .budget
            .check_run(&format!("--frames {first}-{last}: "), &work)
            .map_err(|e| Error::Usage(e.to_string()))?;
    }
    session.set_thread_pool(std::sync::Arc::new(pool));
    let mut components = session.solver().components(session.strands());
    if !session.colliders().is_empty() {
        components.insert(Component::Contacts);
    }
    let mut header = session.cache_header();
    header.first_frame = first_frame;
    let mut writer = CacheWriter::create(
        &opts.cache,
        &header,
        &CacheLayout::of(session.strands()),
        WriterOptions {
            // A resumed run keeps the precision its frames were written with.
            precision: resumed
                .as_ref()
                .map_or(opts.writer.precision, |r| r.precision),
            ..opts.writer
        },
    )?;
    // A resumed run first writes the frames it takes over; the last of them is the state it
    // continues from, written by the session like a first frame.
    if let Some(resumed) = &resumed {
        let taken = &resumed.frames[..resumed.frames.len() - 1];
        match &resumed.rig {
            Some((rig, states)) => {
                writer.attach_rig(rig)?;
                for (f, state) in taken.iter().zip(states) {
                    writer.write_frame_with_rig(f.frame, &f.positions, &f.velocities, state)?;
                }
            }
            None => {
                for f in taken {
                    writer.write_frame(f.frame, &f.positions, &f.velocities)?;
                }
            }
        }
    }
    session.record_into(writer)?;

    let mut totals = Totals::default();
    let mut quality = opts
        .quality
        .then(|| QualityTracker::new(f64::from(session.fps())));
    let mut quality_time = Duration::ZERO;
    // The part of it inside the steps' wall-clock time (the first frame is measured before).
    let mut quality_in_steps = Duration::ZERO;
    let measure = |tracker: &mut QualityTracker, view: &FrameView| {
        tracker
            .add(
                view.strands,
                &FrameToMeasure {
                    frame: view.frame,
                    positions: &view.strands.positions,
                    velocities: &view.strands.velocities,
                    colliders: view.colliders,
                    roots: view.roots,
                },
            )
            .map_err(Error::from)
    };
    if let Some(tracker) = &mut quality {
        let t0 = Instant::now();
        let view = FrameView {
            frame: session.frame(),
            strands: session.strands(),
            colliders: session.colliders(),
            roots: session.root_frames(),
        };
        measure(tracker, &view)?;
        quality_time += t0.elapsed();
    }
    while session.frame() < last_frame {
        let t0 = Instant::now();
        let report = match &mut quality {
            // Measured while the frame is written to the cache.
            Some(tracker) => {
                let (report, measured, added) = session.step_with(|s| measure(tracker, s))?;
                measured?;
                quality_time += added;
                quality_in_steps += added;
                report
            }
            None => session.step()?,
        };
        totals.add(&report, t0.elapsed());
        on_frame(&report);
    }
    let cache_time = session.cache_write_time();
    let cache = session.finish_recording()?;
    let stepped = last_frame - resumed.as_ref().map_or(first_frame, Resumed::last_frame);
    let per_frame = |d: Duration| d.as_secs_f64() * 1e3 / stepped.max(1) as f64;
    let solve = totals.wall.saturating_sub(cache_time + quality_in_steps);
    let solver = session.solver();
    Ok(RunSummary {
        scene: opts.scene.scene.scene.name.clone(),
        frames: last_frame - first_frame + 1,
        stepped,
        first_frame,
        last_frame,
        strands: session.strands().len(),
        points: session.strands().point_count(),
        threads,
        substeps: solver.substeps(),
        dt: solver.dt(),
        dt_bound: solver.dt_bound(),
        model: solver.model().name(),
        integrator: mass_spring
            .then(|| crate::scene::integrator::integrator_name(integrator.integrator)),
        integrator_reason: (mass_spring && integrator.auto).then(|| integrator.reason()),
        integrator_warning: integrator.warning.clone(),
        kernel: hair_core::kernel_instructions(opts.kernel),
        projection: totals.projection,
        components: components.names(),
        ms_per_frame: per_frame(solve),
        cache_ms_per_frame: per_frame(cache_time),
        roots_ms_per_frame: per_frame(totals.roots),
        strands_ms_per_frame: per_frame(totals.strands),
        contacts_ms_per_frame: per_frame(totals.contacts),
        hair_hair_ms_per_frame: per_frame(totals.volume),
        fields_ms_per_frame: per_frame(totals.fields),
        contact_points_per_step: totals.contact_points as f64
            / totals.collision_steps.max(1) as f64,
        escaped_points: totals.escaped_points,
        deep_contact_points: totals.deep_contact_points,
        max_collision_steps: totals.max_steps,
        point_substeps_per_s: totals.point_substeps as f64 / solve.as_secs_f64().max(1e-12),
        max_stretch: totals.max_stretch,
        cache,
        resumed_from: resumed.as_ref().map(Resumed::last_frame),
        recovery_warning: resumed.and_then(|r| r.warning.map(|w| w.to_string())),
        quality: quality.map(QualityTracker::finish),
        quality_ms_per_frame: per_frame(quality_time),
    })
}

/// The frame reports of a run, added up.
#[derive(Debug, Default)]
struct Totals {
    /// Wall-clock time of the steps, cache writes included.
    wall: Duration,
    roots: Duration,
    strands: Duration,
    contacts: Duration,
    volume: Duration,
    fields: Duration,
    contact_points: u64,
    collision_steps: u64,
    max_steps: u32,
    escaped_points: u64,
    deep_contact_points: u64,
    point_substeps: u64,
    max_stretch: f32,
    projection: Option<ProjectionReport>,
}

impl Totals {
    fn add(&mut self, r: &FrameReport, wall: Duration) {
        self.wall += wall;
        self.roots += r.times.roots;
        self.strands += r.times.strands;
        self.contacts += r.times.contacts;
        self.volume += r.times.volume;
        self.fields += r.times.fields;
        self.contact_points += r.contact_points;
        self.escaped_points += r.escaped_points;
        self.deep_contact_points += r.deep_contact_points;
        self.collision_steps += r.steps as u64;
        self.max_steps = self.max_steps.max(r.steps);
        self.point_substeps += r.point_substeps;
        self.max_stretch = self.max_stretch.max(r.max_stretch);
        if let ModelFigures::Rod(p) = &r.figures {
            self.projection
                .get_or_insert_with(Default::default)
                .merge(p);
        }
    }
}

impl std::fmt::Display for RunSummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "{} frames written ({}–{}, {} stepped) of {} strands ({} points) on {} threads ({} kernel)",
            self.frames,
            self.first_frame,
            self.last_frame,
            self.stepped,
            self.strands,
            self.points,
            self.threads,
            self.kernel
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
        if let Some(integrator) = self.integrator {
            match &self.integrator_reason {
                Some(why) => writeln!(f, "  integrator: {integrator} (\"auto\": {why})")?,
                None => writeln!(f, "  integrator: {integrator}")?,
            }
        }
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
            if self.deep_contact_points > 0 {
                writeln!(
                    f,
                    "  contacts: {} point-frames in contact ended deeper than 25 µm inside a \
                     collider; put back on its surface at the frame's end",
                    self.deep_contact_points
                )?;
            }
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
        if let Some(q) = &self.quality {
            let r = &q.run;
            let inside = match &r.penetration {
                Some(p) => format!(
                    "{:.3} % of points inside colliders (deepest {:.2} mm), ",
                    p.inside_fraction * 100.0,
                    p.deepest * 1e3
                ),
                None => String::new(),
            };
            writeln!(
                f,
                "  quality: {inside}p99 stretch {:.2} %, {} hairpin point-frames (largest turn {:.0}°); \
                 {:.2} ms/frame (details: --json, or hairsys preview --report)",
                r.strain.stretch.p99() * 100.0,
                r.hairpins.count,
                r.hairpins.max_turn_deg,
                self.quality_ms_per_frame
            )?;
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
