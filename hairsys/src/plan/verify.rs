//! Checking a plan the long way: the whole groom, not patches, and the written scene itself.
//!
//! [`rerun`] simulates every strand of the original scene with the plan's reference method and
//! the chosen scene as written (its own sim-hair count, segments, integrator and substeps), then
//! measures the chosen run against the reference: directly when both have the same strands,
//! otherwise through render hairs at the original strands' roots interpolated from the chosen
//! run's sim hairs ([`crate::plan::levels::render_from`]). It costs a full-groom reference run,
//! so it is for tests and studies, not for the plan itself.

use hair_core::{Integrator, Substeps};

use crate::accuracy::ShotErrors;
use crate::plan::levels::render_from;
use crate::plan::probe::{self, Method, ProbeRun};
use crate::plan::trace::errors;
use crate::scene::SceneFile;
use crate::Error;

/// A whole-groom run of `scene` over `frames` with `method` (`None`: the scene's own), sampled
/// at `samples` segments per strand.
pub fn run_all(
    scene: &SceneFile,
    method: Option<Method>,
    frames: (u32, u32),
    samples: usize,
) -> Result<ProbeRun, Error> {
    let mut base = scene.build()?;
    base.set_frames(frames.0, frames.1);
    let full = std::mem::take(&mut base.strands);
    let keep: Vec<usize> = (0..full.len()).collect();
    let method = method.unwrap_or(Method {
        integrator: base.settings.integrator,
        substeps: match base.settings.substeps {
            Substeps::Auto => None,
            Substeps::Fixed(n) => Some(n),
        },
        inextensible: base.inextensibility.is_some(),
        segments: (full.points(0).len() - 1) as u32,
    });
    probe::run(scene, &base, &full, &keep, method, samples, false)
}

/// The error of `chosen` (a scene written by the plan) against `original` run with `reference`
/// over `frames`, every strand simulated (see the module docs).
pub fn rerun(
    original: &SceneFile,
    chosen: &SceneFile,
    reference: Method,
    frames: (u32, u32),
    samples: usize,
) -> Result<ShotErrors, Error> {
    let reference = run_all(original, Some(reference), frames, samples)?;
    let run = run_all(chosen, None, frames, samples)?;
    let same_strands = run.trace.strands == reference.trace.strands
        && run
            .trace
            .roots
            .iter()
            .zip(&reference.trace.roots)
            .all(|(a, b)| (a - b).norm() < 1e-6);
    let frames = if same_strands {
        run.trace.frames
    } else {
        render_from(&run.trace, &reference.trace)
    };
    Ok(errors(&frames, &reference.trace))
}

/// The reference method of a plan for a scene whose `"auto"` substeps are `bound` per step at
/// `segments` segments: the inextensible springs at twice the bound.
pub fn reference_method(bound: u32, segments: u32) -> Method {
    Method {
        integrator: Integrator::SemiImplicitEuler,
        substeps: Some(2 * bound),
        inextensible: true,
        segments,
    }
}
