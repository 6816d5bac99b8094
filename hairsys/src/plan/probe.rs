//! Short probes: a few frames of the scene's own motion on a few patches of its strands.
//!
//! A probe never simulates the whole groom. [`patches`] picks a few compact patches of
//! neighbouring strands spread over the scalp (farthest-point centres, each with its nearest
//! strands), so that inside a patch the strands are as dense as in the full groom: hair–hair
//! friction sees the same neighbours, and the sim-hair count can be studied by interpolation
//! inside a patch at the full groom's spacing ([`crate::plan::levels`]).
//!
//! [`strand_subset`] copies the chosen strands out of the built scene exactly (rest shapes,
//! sag-free rest curvatures and lengths, masses, goals, pins), or rebuilt at another segment
//! count: the groom polyline resampled at equal arc length, masses from the strand's linear
//! density, the springs rescaled to the same material ([`same_material`]), and the sag-free rest
//! state solved again for the new discretisation, as `SceneFile::build` would for `[hair]
//! segments`.

use hair_core::{HairError, HairParams, Integrator, StrandInput, StrandSet, Substeps};
use nalgebra::Vector3;

use crate::build::Simulation;
use crate::plan::levels::farthest_points;
use crate::plan::trace::Trace;
use crate::scene::SceneFile;
use crate::{Error, Session};

/// One way of running the scene: what `plan` varies.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Method {
    /// The integrator.
    #[serde(serialize_with = "serialize_integrator")]
    pub integrator: Integrator,
    /// Force substeps per collision step; `None` = the stability bound (`"auto"`).
    pub substeps: Option<u32>,
    /// The inextensibility projection after each substep.
    pub inextensible: bool,
    /// Segments per strand.
    pub segments: u32,
}

fn serialize_integrator<S: serde::Serializer>(i: &Integrator, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(crate::scene::integrator::integrator_name(*i))
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let name = match (self.integrator, self.inextensible) {
            (Integrator::SemiImplicitEuler, false) => "springs",
            (Integrator::SemiImplicitEuler, true) => "springs+inext",
            (Integrator::ExplicitEuler, _) => "explicit",
            (Integrator::ImplicitEuler, false) => "implicit",
            (Integrator::ImplicitEuler, true) => "implicit+inext",
            (Integrator::Bdf2, false) => "bdf2",
            (Integrator::Bdf2, true) => "bdf2+inext",
            (Integrator::Xpbd, false) => "xpbd",
            (Integrator::Xpbd, true) => "xpbd+inext",
        };
        match self.substeps {
            Some(n) => write!(f, "{name}, {n} substeps, {} segments", self.segments),
            None => write!(f, "{name}, auto substeps, {} segments", self.segments),
        }
    }
}

/// What one probe measured.
#[derive(Debug, Clone)]
pub struct ProbeRun {
    /// Sampled positions per stepped frame.
    pub trace: Trace,
    /// CPU time of the steps summed over the process's threads, s ([`cpu_seconds`]).
    pub seconds: f64,
    /// Substeps per step the solver used (the last frame's).
    pub substeps: u32,
    /// Points × substeps advanced.
    pub point_substeps: u64,
}

/// `patch_count` patches of about `strands / patch_count` neighbouring strands each (by root
/// distance), centred on farthest-point samples of the roots. Returns the strand indices of
/// each patch (disjoint, every patch non-empty).
pub fn patches(set: &StrandSet, strands: usize, patch_count: usize) -> Vec<Vec<usize>> {
    let roots: Vec<Vector3<f32>> = (0..set.len())
        .map(|s| set.positions[set.points(s).start])
        .collect();
    let all: Vec<usize> = (0..set.len()).collect();
    if strands >= set.len() {
        return vec![all];
    }
    let centres = farthest_points(&roots, &all, patch_count.max(1));
    let per_patch = (strands / centres.len()).max(1);
    let mut taken = vec![false; set.len()];
    let mut out = Vec::new();
    for &c in &centres {
        let mut near: Vec<usize> = all.iter().copied().filter(|&s| !taken[s]).collect();
        near.sort_by(|&a, &b| {
            (roots[a] - roots[c])
                .norm_squared()
                .total_cmp(&(roots[b] - roots[c]).norm_squared())
        });
        near.truncate(per_patch);
        for &s in &near {
            taken[s] = true;
        }
        out.push(near);
    }
    out
}

/// The strands `keep` of `set` as a new set: an exact copy (`segments = None`), or each strand
/// rebuilt with `segments` segments (see the module docs; its rest state is left at the first
/// frame's pose to the caller, who must run sag-free again if the scene asks for it).
pub fn strand_subset(
    set: &StrandSet,
    keep: &[usize],
    segments: Option<u32>,
) -> Result<StrandSet, HairError> {
    let mut out = StrandSet::new();
    for &s in keep {
        let p = set.points(s);
        let inv = &set.inverse_masses()[p.clone()];
        let input = match segments {
            None => StrandInput {
                anchor: set.anchors()[s],
                rest: set.rest_local()[p.clone()].to_vec(),
                mass: set.masses()[p.clone()].to_vec(),
                radius: set.radii()[p.clone()].to_vec(),
                goal_weight: set.goal_weights()[p.clone()].to_vec(),
                pinned: inv.iter().map(|&m| m == 0.0).collect(),
            },
            Some(n) => resampled(set, s, n),
        };
        out.push(input)?;
        if segments.is_none() {
            let last = out.len() - 1;
            let (dst_p, dst_s, src_s) = (out.points(last), out.segments(last), set.segments(s));
            out.rest_lengths_mut()[dst_s.clone()]
                .copy_from_slice(&set.rest_lengths()[src_s.clone()]);
            out.bend_rest_mut()[dst_s].copy_from_slice(&set.bend_rest()[src_s]);
            out.positions[dst_p.clone()].copy_from_slice(&set.positions[p.clone()]);
            out.velocities[dst_p].copy_from_slice(&set.velocities[p]);
        }
    }
    Ok(out)
}

/// Strand `s` of `set` rebuilt with `segments` segments of equal rest length along its groom.
fn resampled(set: &StrandSet, s: usize, segments: u32) -> StrandInput {
    let p = set.points(s);
    let rest = &set.rest_local()[p.clone()];
    let lengths: Vec<f32> = rest.windows(2).map(|w| (w[1] - w[0]).norm()).collect();
    let total: f32 = lengths.iter().sum();
    // Linear density from the stored lumped masses (the root's is not stored: it is pinned).
    let free_mass: f32 = set.masses()[p.clone()].iter().sum();
    let free_length = total - 0.5 * lengths[0];
    let density = free_mass / free_length;
    let n = segments as usize + 1;
    let mut points = Vec::with_capacity(n);
    let (mut seg, mut start) = (0, 0.0f32);
    for j in 0..n {
        let target = total * j as f32 / (n - 1) as f32;
        while seg + 1 < lengths.len() && start + lengths[seg] < target {
            start += lengths[seg];
            seg += 1;
        }
        let t = ((target - start) / lengths[seg]).clamp(0.0, 1.0);
        points.push(rest[seg] + (rest[seg + 1] - rest[seg]) * t);
    }
    let goal = &set.goal_weights()[p.clone()];
    StrandInput::uniform(
        set.anchors()[s],
        points,
        density,
        set.radii()[p.start],
        goal[0],
        goal[goal.len() - 1],
    )
}

/// `params` of strands of `from` segments rescaled for the same strands cut into `to`: the
/// springs are per segment, so the material they stand for is kept by keeping the axial
/// stiffness `EA = k_s l` and the bending stiffness `EI = k_b l³` (a joint resists a turn with
/// `k_b l²` N·m/rad, and `EI` is that times the segment length `l`). Without this, fewer
/// segments would be a stiffer hair, not a coarser one.
pub fn same_material(params: &HairParams, from: u32, to: u32) -> HairParams {
    let r = to as f32 / from as f32;
    HairParams {
        stretch_stiffness: params.stretch_stiffness * r,
        bend_stiffness: params.bend_stiffness * r * r * r,
        ..*params
    }
}

/// Runs `method` on the strands `keep` of the built scene `base` (whose strands are the full
/// set `full`) over its frames, recording `samples` segments per strand.
pub fn run(
    scene: &SceneFile,
    base: &Simulation,
    full: &StrandSet,
    keep: &[usize],
    method: Method,
    samples: usize,
    rebuild: bool,
) -> Result<ProbeRun, Error> {
    let solver_error = |source| Error::Solver {
        scene: scene.origin.clone(),
        source,
    };
    let mut sim = base.clone();
    sim.strands =
        strand_subset(full, keep, rebuild.then_some(method.segments)).map_err(solver_error)?;
    sim.settings.integrator = method.integrator;
    sim.settings.substeps = match method.substeps {
        Some(n) => Substeps::Fixed(n),
        None => Substeps::Auto,
    };
    sim.inextensibility = method
        .inextensible
        .then(hair_core::Inextensibility::default);
    if rebuild {
        let from = (full.points(keep[0]).len() - 1) as u32;
        sim.params = same_material(&sim.params, from, method.segments);
        let scalp = sim.scalp_at(sim.first_frame as f32);
        sim.strands.reset_to_rest(&scalp);
        if scene.scene.solver.sag_free {
            let roots = sim.strands.root_frames(&scalp);
            let supports = sim.resting_supports().map_err(solver_error)?;
            let report = hair_core::make_sag_free_supported(
                &mut sim.strands,
                &sim.params,
                &roots,
                &supports,
                hair_core::SagFreeLimits::default(),
            )
            .map_err(solver_error)?;
            // As `SceneFile::build` refuses such a scene: these strands would sag.
            if !report.unbalanced.is_empty() {
                return Err(Error::Usage(format!(
                    "[solver] sag_free cannot hold {} of {} probed strands at {} segments",
                    report.unbalanced.len(),
                    sim.strands.len(),
                    method.segments
                )));
            }
        }
    }
    let (first, last) = (sim.first_frame, sim.last_frame);
    let mut trace = Trace::new(&sim.strands, samples);
    let mut session = Session::from_simulation(sim, scene, "plan probe".into())?;
    let start = cpu_seconds();
    let (mut substeps, mut point_substeps) = (0, 0);
    for _ in first..last {
        let report = session.step()?;
        substeps = report.substeps;
        point_substeps += report.point_substeps;
        trace.record(session.strands(), session.root_frames());
    }
    Ok(ProbeRun {
        trace,
        seconds: cpu_seconds() - start,
        substeps,
        point_substeps,
    })
}

/// CPU time the process's threads have run, s: on Linux the sum of every thread's
/// `/proc/self/task/*/schedstat` (nanoseconds on a CPU), so that probes on a machine other work
/// loads are timed by the work they do, not by the time they waited; elsewhere the wall clock
/// since the first call.
pub fn cpu_seconds() -> f64 {
    let from_proc = || -> Option<f64> {
        let mut ns = 0u64;
        for task in std::fs::read_dir("/proc/self/task").ok()? {
            let text = std::fs::read_to_string(task.ok()?.path().join("schedstat")).ok()?;
            ns += text.split_whitespace().next()?.parse::<u64>().ok()?;
        }
        Some(ns as f64 * 1e-9)
    };
    static START: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();
    from_proc().unwrap_or_else(|| {
        START
            .get_or_init(std::time::Instant::now)
            .elapsed()
            .as_secs_f64()
    })
}
