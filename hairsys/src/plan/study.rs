//! How many sim hairs a scene needs (seed 001, "Hair Levels").
//!
//! Every strand of the scene is simulated once (the render hairs' truth). Then, for each count
//! `N`, only `N` of the strands — spread over the scalp by farthest-point sampling of the roots —
//! are simulated with the same settings, and every strand of the groom is rebuilt as a render
//! hair interpolated from them ([`crate::plan::levels::render_from`]). The error of the render
//! hairs against the full run, against the measured cost of the `N`-hair run, gives the curve;
//! its knee ([`knee`]) is where more sim hairs stop paying.

use crate::accuracy::ShotErrors;
use crate::plan::levels::{farthest_points, render_from};
use crate::plan::probe;
use crate::plan::trace::errors;
use crate::plan::verify::run_all;
use crate::scene::SceneFile;
use crate::Error;

/// One sim-hair count of the study.
#[derive(Debug, Clone, serde::Serialize)]
pub struct LevelRow {
    /// Simulated hairs.
    pub sim_hairs: usize,
    /// CPU time of the run's steps per frame (every thread's summed), ms.
    pub ms_per_frame: f64,
    /// Error of every strand as a render hair against the full run.
    pub errors: ShotErrors,
}

/// Runs the study on `scene` over `frames` for the counts `counts` (capped at the scene's
/// strand count; the full run is the last row).
pub fn sim_hair_levels(
    scene: &SceneFile,
    frames: (u32, u32),
    counts: &[usize],
    samples: usize,
) -> Result<Vec<LevelRow>, Error> {
    let steps = (frames.1 - frames.0) as f64;
    let full_run = run_all(scene, None, frames, samples)?;
    let mut base = scene.build()?;
    base.set_frames(frames.0, frames.1);
    let full = std::mem::take(&mut base.strands);
    let all: Vec<usize> = (0..full.len()).collect();
    let method = probe::Method {
        integrator: base.settings.integrator,
        substeps: match base.settings.substeps {
            hair_core::Substeps::Auto => None,
            hair_core::Substeps::Fixed(n) => Some(n),
        },
        inextensible: base.inextensibility.is_some(),
        segments: (full.points(0).len() - 1) as u32,
    };
    let mut rows = Vec::new();
    for &n in counts.iter().filter(|&&n| n > 0 && n < full.len()) {
        let mut keep = farthest_points(&full_run.trace.roots, &all, n);
        keep.sort_unstable();
        let run = probe::run(scene, &base, &full, &keep, method, samples, false)?;
        let frames = render_from(&run.trace, &full_run.trace);
        rows.push(LevelRow {
            sim_hairs: n,
            ms_per_frame: run.seconds * 1e3 / steps,
            errors: errors(&frames, &full_run.trace),
        });
    }
    rows.push(LevelRow {
        sim_hairs: full.len(),
        ms_per_frame: full_run.seconds * 1e3 / steps,
        errors: ShotErrors::default(),
    });
    Ok(rows)
}

/// The knee of an error-against-cost curve: the row farthest below the straight line from the
/// cheapest to the dearest row, both axes scaled to [0, 1] (the "Kneedle" rule, Satopää et al.
/// 2011). `None` for fewer than three rows.
pub fn knee(rows: &[LevelRow]) -> Option<usize> {
    if rows.len() < 3 {
        return None;
    }
    let cost = |r: &LevelRow| r.ms_per_frame;
    let err = |r: &LevelRow| r.errors.rms_max as f64;
    let (c0, c1) = (cost(&rows[0]), cost(&rows[rows.len() - 1]));
    let (e0, e1) = (err(&rows[0]), err(&rows[rows.len() - 1]));
    let span = |a: f64, b: f64| if (b - a).abs() > 0.0 { b - a } else { 1.0 };
    (1..rows.len() - 1).max_by(|&a, &b| {
        let gap = |i: usize| {
            let x = (cost(&rows[i]) - c0) / span(c0, c1);
            let y = (err(&rows[i]) - e0) / span(e0, e1);
            // `y` is the fraction of the error removed, `x` the fraction of the cost spent:
            // the knee has removed the most error beyond what the cost alone would buy.
            y - x
        };
        gap(a).total_cmp(&gap(b))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(ms: f64, err: f32) -> LevelRow {
        LevelRow {
            sim_hairs: 0,
            ms_per_frame: ms,
            errors: ShotErrors {
                rms_max: err,
                ..ShotErrors::default()
            },
        }
    }

    #[test]
    fn the_knee_is_where_the_error_stops_falling() {
        // Error halves per doubling of cost down to row 2, then barely moves.
        let rows = [
            row(1.0, 8.0),
            row(2.0, 4.0),
            row(4.0, 1.0),
            row(8.0, 0.8),
            row(16.0, 0.0),
        ];
        assert_eq!(knee(&rows), Some(2));
        assert_eq!(knee(&rows[..2]), None);
    }
}
