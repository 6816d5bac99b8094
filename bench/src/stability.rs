//! The stability map: which (stretch stiffness, substep) pairs each method survives, against the
//! predicted bound `dt < 2/ω`, `ω² = 4 (k_stretch + 4 k_bend) / m_min` ([`hair_core::StabilityBound`]).
//!
//! The probe is a strand of 16 segments of 1 cm with 10 mg at every free point (the tip too, so
//! the lightest point is a typical one), without bending, released horizontally under gravity
//! with the default damping and drag.
//! A run is *unstable* if the solver stops it ([`HairError::Unstable`]: non-finite values or
//! runaway energy) or a segment ends a frame stretched to more than twice its rest length
//! ([`crate::metrics::BLOWN_UP_STRETCH`]).
//!
//! For each stiffness and method the *observed boundary* is the longest substep from which every
//! shorter one on the grid is stable, refined by bisection on the substep count between the last
//! unstable and the first stable grid column. With equal masses the chain's highest mode is
//! `2 √(k/m) cos(π/(2N+1))`, so semi-implicit Euler should hold to just above the prediction.
//! (On strands whose tip carries half a point mass, as generated hair does, the prediction takes
//! the tip's mass and is conservative by about √2.)

use crate::cases::CaseError;
use hair_core::HairError;
use serde::Serialize;

use crate::cases::Case;
use crate::methods::Method;
use crate::metrics::blown_up;
use hairsys::scene::SceneFile;

/// Segment length of the probe strand, m.
pub const PROBE_SEGMENT: f64 = 0.01;

/// Frames per second of the probes (the substep is `1 / (24 · substeps)` s).
pub const FPS: f64 = 24.0;

/// A grid of probe runs.
#[derive(Debug, Clone)]
pub struct Grid {
    /// Stretch stiffnesses (rows), N/m.
    pub stiffness: Vec<f64>,
    /// Substeps per frame (columns), increasing.
    pub substeps: Vec<u32>,
    /// Frames each probe runs.
    pub frames: u32,
}

impl Grid {
    /// The full grid (9 stiffnesses from 1 to 10⁴ N/m, substeps 1 to 4096 on a √2 ladder, 1 s
    /// probes) or the quick one (4 stiffnesses, powers of two to 2048, 0.5 s).
    pub fn new(quick: bool) -> Self {
        if quick {
            Self {
                stiffness: vec![1.0, 10.0, 100.0, 1000.0],
                substeps: (0..=11).map(|e| 1 << e).collect(),
                frames: 12,
            }
        } else {
            let mut substeps: Vec<u32> = (0..=24)
                .map(|e| 2f64.powf(e as f64 / 2.0).round() as u32)
                .collect();
            substeps.dedup();
            Self {
                stiffness: (0..=8).map(|e| 10f64.powf(e as f64 / 2.0)).collect(),
                substeps,
                frames: 24,
            }
        }
    }
}

/// One method's map.
#[derive(Debug, Clone, Serialize)]
pub struct MethodMap {
    /// The method.
    pub method: String,
    /// What the rows vary ([`Method::stiffness_axis`]).
    pub axis: String,
    /// `stable[row][column]` on the [`Grid`].
    pub stable: Vec<Vec<bool>>,
    /// Predicted largest stable substep per row, s.
    pub predicted_dt: Vec<f64>,
    /// Observed boundary per row: the longest substep from which all shorter ones are stable, s
    /// (`None`: no column is stable; infinite: every column is).
    pub observed_dt: Vec<Option<f64>>,
}

impl MethodMap {
    /// Rows with a finite predicted bound where some run with a substep shorter than the
    /// prediction failed.
    pub fn fails_inside_bound(&self, grid: &Grid) -> Vec<f64> {
        grid.stiffness
            .iter()
            .enumerate()
            .filter(|&(r, _)| self.predicted_dt[r].is_finite())
            .filter(|&(r, _)| {
                grid.substeps.iter().enumerate().any(|(c, &s)| {
                    !self.stable[r][c] && 1.0 / (FPS * s as f64) < self.predicted_dt[r]
                })
            })
            .map(|(_, &k)| k)
            .collect()
    }
}

/// The probe strand with stretch stiffness `k` (N/m), run for `frames` frames.
pub fn probe_case(k: f64, frames: u32) -> Result<Case, CaseError> {
    let points: Vec<String> = (0..=16)
        .map(|i| format!("[{:.3}, 0.0, 0.0]", PROBE_SEGMENT * i as f64))
        .collect();
    let text = format!(
        r#"
[scene]
name = "stability probe"
fps = {FPS}
frames = [0, {frames}]
[physics]
stretch_stiffness = {k}
bend_stiffness = 0.0
stretch_damping = 50.0
air_drag = 1.0
[[strands]]
masses = [0.0{}]
points = [{}]
"#,
        ", 1e-5".repeat(16),
        points.join(", ")
    );
    let sim = SceneFile::parse(&text, "<stability probe>", std::path::PathBuf::new())?.build()?;
    Ok(Case {
        name: "probe",
        title: "stability probe",
        samples: Vec::new(),
        energy_scale: 1.0,
        head: None,
        represented_hairs: None,
        truth: crate::truth::TruthKind::Rod,
        truth_subdivision: 1,
        mass_per_length: 0.0,
        // The row's stiffness is the probe's physical one too: the rows vary it.
        physical_stretch: k as f32,
        resegment: None,
        ball: None,
        sim,
    })
}

/// Runs `method` on `case` at `substeps`: `Ok(true)` if it stays stable.
pub fn is_stable(method: &dyn Method, case: &Case, substeps: u32) -> Result<bool, HairError> {
    match method.run(case, Some(substeps)) {
        Ok(trace) => Ok(blown_up(&trace).is_none()),
        Err(HairError::Unstable { .. }) => Ok(false),
        Err(e) => Err(e),
    }
}

/// Maps `method` over `grid`, calling `tick` after each row.
pub fn map(
    method: &dyn Method,
    grid: &Grid,
    mut tick: impl FnMut(),
) -> Result<MethodMap, crate::BenchError> {
    let mut out = MethodMap {
        method: method.name(),
        axis: method.stiffness_axis().into(),
        stable: Vec::new(),
        predicted_dt: Vec::new(),
        observed_dt: Vec::new(),
    };
    for &k in &grid.stiffness {
        let case = method.probe(k, grid.frames)?;
        let row = grid
            .substeps
            .iter()
            .map(|&s| is_stable(method, &case, s))
            .collect::<Result<Vec<bool>, HairError>>()?;
        // The first column from which every later one is stable.
        let first = row.iter().rposition(|&ok| !ok).map_or(0, |c| c + 1);
        let observed = if first == row.len() {
            None
        } else if first == 0 {
            Some(f64::INFINITY)
        } else {
            // Bisect on the substep count between the unstable and the stable column.
            let (mut lo, mut hi) = (grid.substeps[first - 1], grid.substeps[first]);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if is_stable(method, &case, mid)? {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            Some(1.0 / (FPS * hi as f64))
        };
        out.predicted_dt.push(method.bound(&case)?);
        out.observed_dt.push(observed);
        out.stable.push(row);
        tick();
    }
    Ok(out)
}
