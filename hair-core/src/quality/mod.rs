//! A quality report of simulated hair: does a frame (or a run) look like hair?
//!
//! Pure functions over data, no I/O: a host hands [`measure`] one frame's strands ([`Frame`]:
//! positions, velocities, rest lengths, strand offsets — from a [`StrandSet`] or a cache),
//! optionally the previous frame ([`Previous`]), the colliders at the frame's pose and a
//! reference shape, and gets a [`QualityReport`]; reports of many frames [`QualityReport::merge`]
//! into one for the run (counts add, maxima take the larger, quantiles come from merged
//! log-spaced histograms, see [`Distribution`]). What it measures, and why:
//!
//! - **Penetration** ([`Penetration`]): the fraction of free points whose
//!   collision sphere lies inside a collider's thickened surface by more than a contact
//!   tolerance, and the deepest penetration (m). The contact response keeps a point's centre at
//!   its radius plus the collider's thickness from the surface (see [`crate::contacts`]), so a
//!   point the solver handled has depth 0; the tolerance ([`QualityOptions::contact_tolerance`],
//!   0.1 mm by default, about one real hair's diameter and the floor of the contact model's
//!   fast-motion tolerance) absorbs the model's small, documented misses (a curved surface's
//!   sagitta within a step, the strain limit's correction after the response).
//! - **Strain** ([`Strain`]): stretch and compression of every segment against its rest length
//!   (p50, p99, max); a strain-limited run holds p99 stretch at or below its `max_strain`.
//! - **Hairpins** ([`Hairpins`]): interior points where the strand turns by more than 90° — a
//!   fold no real hair makes at one point — and the largest turn (degrees).
//! - **Drift** ([`Drift`]): RMS and largest distance of free points and of tips from a
//!   reference shape, e.g. the groom posed on the scalp ([`rest_positions`]) after settling.
//! - **Velocity–position mismatch** (`motion`): per point, `|(x₁ − x₀)/Δt − (v₀ + v₁)/2|`
//!   (m/s) between consecutive frames; 0 for motion of constant acceleration, and it reads a
//!   velocity the points did not move with directly (a stale velocity under the strain limit
//!   read 0.25 m/s on the Sintel scene), which is what spoils Hermite sampling between frames.
//!
//! # Cost
//! Linear in points and bound by reading memory: the per-strand measures take one pass over
//! each strand (`strand_pass`, chunks of strands in parallel); penetration screens each point
//! by its collider's enclosing sphere and, with a [`PenetrationMemory`], by its distance bound
//! from the last frame, and projects the rest exactly (warm-started from the triangle it
//! projected on before), in parallel. Measured against the run it reports on with `hairsys
//! simulate --json` (`quality_ms_per_frame`) in BENCHMARKS.md.

mod distribution;
mod penetration;
mod shape;
mod strand_pass;

use hair_par::prelude::*;
use nalgebra::Vector3;
#[cfg(feature = "serde")]
use serde::Serialize;

use crate::contacts::Colliders;
use crate::error::{HairError, Result};
use crate::mesh::RootFrame;
use crate::strands::{Scalp, StrandSet};

pub use distribution::Distribution;
pub use penetration::{inside_flags, resting_normals, Penetration, PenetrationMemory};
pub use shape::{Drift, Hairpins, Strain};

/// One frame of strands, borrowed: the layout of a [`StrandSet`] (strand-contiguous points).
#[derive(Debug, Clone, Copy)]
pub struct Frame<'a> {
    /// Index of each strand's first point, then the point count (strands + 1 entries).
    pub offsets: &'a [u32],
    /// Positions, m, world.
    pub positions: &'a [Vector3<f32>],
    /// Velocities, m/s.
    pub velocities: &'a [Vector3<f32>],
    /// Rest length of every segment, m (points − strands entries, strand after strand).
    pub rest_lengths: &'a [f32],
    /// Collision radius of every point, m.
    pub radii: &'a [f32],
    /// Inverse mass of every point, 1/kg (0 for kinematic points: roots and pinned points,
    /// which the solver never moves and penetration and drift skip); `None` treats each
    /// strand's first point as its only kinematic point.
    pub inverse_masses: Option<&'a [f32]>,
}

impl<'a> Frame<'a> {
    /// The current state of `strands`.
    pub fn of(strands: &'a StrandSet) -> Self {
        Self {
            offsets: strands.offsets(),
            positions: &strands.positions,
            velocities: &strands.velocities,
            rest_lengths: strands.rest_lengths(),
            radii: strands.radii(),
            inverse_masses: Some(strands.inverse_masses()),
        }
    }

    /// Number of strands.
    pub fn strands(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Point range of strand `s`.
    fn points(&self, s: usize) -> std::ops::Range<usize> {
        self.offsets[s] as usize..self.offsets[s + 1] as usize
    }

    /// Does the solver move point `i`?
    fn is_free(&self, i: usize) -> bool {
        match self.inverse_masses {
            Some(w) => w[i] > 0.0,
            None => !self.offsets.contains(&(i as u32)),
        }
    }

    /// Checks that every array fits the offsets, and that offsets rise with ≥ 2 points a
    /// strand, so no measure indexes out of range.
    fn validate(&self) -> Result<()> {
        let n = self.positions.len();
        let bad = |name: &str, value: String, fix: &str| {
            Err(HairError::Parameter {
                name: format!("quality.frame.{name}"),
                value,
                fix: fix.into(),
            })
        };
        if self.offsets.first() != Some(&0) || *self.offsets.last().unwrap_or(&1) as usize != n {
            return bad(
                "offsets",
                format!("{} offsets for {n} points", self.offsets.len()),
                "offsets start at 0 and end at the number of points",
            );
        }
        if self.offsets.windows(2).any(|w| w[1] < w[0] + 2) {
            return bad(
                "offsets",
                "a strand with fewer than 2 points".into(),
                "every strand has at least one segment; offsets rise by 2 or more",
            );
        }
        let segments = n - self.strands();
        for (name, len, want) in [
            ("velocities", self.velocities.len(), n),
            ("radii", self.radii.len(), n),
            ("rest_lengths", self.rest_lengths.len(), segments),
            (
                "inverse_masses",
                self.inverse_masses.map_or(n, |w| w.len()),
                n,
            ),
        ] {
            if len != want {
                return bad(
                    name,
                    format!("{len} entries"),
                    &format!(
                        "give one entry per {} ({want})",
                        if name == "rest_lengths" {
                            "segment"
                        } else {
                            "point"
                        }
                    ),
                );
            }
        }
        if let Some(j) = self
            .rest_lengths
            .iter()
            .position(|&l| l.is_nan() || l <= 0.0)
        {
            return bad(
                "rest_lengths",
                format!("segment {j}: {}", self.rest_lengths[j]),
                "rest lengths are > 0 m",
            );
        }
        Ok(())
    }
}

/// The previous frame of the same strands, for the velocity–position mismatch.
#[derive(Debug, Clone, Copy)]
pub struct Previous<'a> {
    /// Positions, m (the same layout as the frame).
    pub positions: &'a [Vector3<f32>],
    /// Velocities, m/s.
    pub velocities: &'a [Vector3<f32>],
    /// Time from the previous frame to this one, s (> 0).
    pub dt: f32,
}

/// What to measure one frame against.
#[derive(Debug, Clone, Copy)]
pub struct QualityInput<'a> {
    /// The frame.
    pub frame: Frame<'a>,
    /// The previous frame, for the velocity–position mismatch.
    pub previous: Option<Previous<'a>>,
    /// Colliders at this frame's pose ([`Colliders::pose`]), for penetration.
    pub colliders: Option<&'a Colliders>,
    /// The reference shape, for drift.
    pub reference: Option<Reference<'a>>,
}

/// A reference shape to measure drift from.
#[derive(Debug, Clone, Copy)]
pub enum Reference<'a> {
    /// Positions, m (the frame's layout), e.g. [`rest_positions`].
    Positions(&'a [Vector3<f32>]),
    /// The rest shape posed on root frames, computed point by point (nothing stored): point `i`
    /// of strand `s` at `roots[s].to_world(&rest_local[i])` — the groom on the scalp when
    /// `roots` are the frame's root frames ([`StrandSet::root_frames`]) and `rest_local` the
    /// strands' [`StrandSet::rest_local`].
    Posed {
        /// One root frame per strand.
        roots: &'a [RootFrame],
        /// Rest positions in their root's frame, m (the frame's layout).
        rest_local: &'a [Vector3<f32>],
    },
}

/// Settings of the report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QualityOptions {
    /// Depth (m) up to which a point's sphere may lie inside a collider's thickened surface and
    /// still count as touching, not inside. Default 1e-4 m (0.1 mm).
    pub contact_tolerance: f32,
}

impl Default for QualityOptions {
    fn default() -> Self {
        Self {
            contact_tolerance: 1e-4,
        }
    }
}

/// The quality of one frame or, merged, of a run. Absent parts (`None`, `null` in JSON) were
/// not measured: no colliders, no previous frame, no reference.
#[derive(Debug, Clone, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize))]
pub struct QualityReport {
    /// Frames measured.
    pub frames: u32,
    /// Points measured, summed over frames.
    pub points: u64,
    /// Segment stretch and compression (dimensionless).
    pub strain: Strain,
    /// Points turning by more than 90°.
    pub hairpins: Hairpins,
    /// Points inside colliders.
    pub penetration: Option<Penetration>,
    /// Distance from the reference shape, m.
    pub drift: Option<Drift>,
    /// Velocity–position mismatch between consecutive frames, m/s.
    pub velocity_mismatch: Option<Distribution>,
}

impl QualityReport {
    /// Adds another frame's (or run's) report to this one.
    pub fn merge(&mut self, other: &QualityReport) {
        self.frames += other.frames;
        self.points += other.points;
        self.strain.merge(&other.strain);
        self.hairpins.merge(&other.hairpins);
        merge_option(
            &mut self.penetration,
            &other.penetration,
            Penetration::merge,
        );
        merge_option(&mut self.drift, &other.drift, Drift::merge);
        merge_option(
            &mut self.velocity_mismatch,
            &other.velocity_mismatch,
            Distribution::merge,
        );
    }
}

fn merge_option<T: Clone>(a: &mut Option<T>, b: &Option<T>, merge: impl Fn(&mut T, &T)) {
    match (a.as_mut(), b) {
        (Some(x), Some(y)) => merge(x, y),
        (None, Some(y)) => *a = Some(y.clone()),
        _ => {}
    }
}

/// Measures one frame. Errors name the array that does not fit the frame's layout, or a
/// non-positive `dt` or tolerance.
pub fn measure(input: &QualityInput, options: &QualityOptions) -> Result<QualityReport> {
    measure_inner(input, options, None)
}

/// [`measure`] for one frame of a run, with `memory` carried from the run's previous frame: the
/// same report, but points that cannot have reached a collider since they were last measured
/// are not projected again (see [`PenetrationMemory`]). Give every frame of a run, in order,
/// the same memory.
pub fn measure_remembered(
    input: &QualityInput,
    options: &QualityOptions,
    memory: &mut PenetrationMemory,
) -> Result<QualityReport> {
    measure_inner(input, options, Some(memory))
}

fn measure_inner(
    input: &QualityInput,
    options: &QualityOptions,
    memory: Option<&mut PenetrationMemory>,
) -> Result<QualityReport> {
    let frame = &input.frame;
    frame.validate()?;
    let n = frame.positions.len();
    let tolerance = options.contact_tolerance;
    if !(tolerance.is_finite() && tolerance >= 0.0) {
        return Err(HairError::Parameter {
            name: "quality.contact_tolerance".into(),
            value: tolerance.to_string(),
            fix: "use a finite depth ≥ 0 m, e.g. 1e-4".into(),
        });
    }
    if let Some(p) = &input.previous {
        if !(p.dt.is_finite() && p.dt > 0.0) {
            return Err(HairError::Parameter {
                name: "quality.previous.dt".into(),
                value: p.dt.to_string(),
                fix: "give the time between the two frames in seconds, > 0".into(),
            });
        }
        check_len("previous.positions", p.positions.len(), n)?;
        check_len("previous.velocities", p.velocities.len(), n)?;
    }
    match input.reference {
        Some(Reference::Positions(r)) => check_len("reference", r.len(), n)?,
        Some(Reference::Posed { roots, rest_local }) => {
            check_len("reference.rest_local", rest_local.len(), n)?;
            if roots.len() != frame.strands() {
                return Err(HairError::Parameter {
                    name: "quality.reference.roots".into(),
                    value: format!("{} entries", roots.len()),
                    fix: format!("give one root frame per strand ({})", frame.strands()),
                });
            }
        }
        None => {}
    }
    // Penetration (parallel over points) runs beside the per-strand measures (parallel over
    // chunks of strands).
    let (strands, penetration) = hair_par::join(
        || strand_pass::measure(frame, input.previous.as_ref(), input.reference.as_ref()),
        || {
            input.colliders.map(|c| {
                penetration::measure(
                    c,
                    frame.positions,
                    frame.radii,
                    &|i| frame.is_free(i),
                    tolerance,
                    memory,
                )
            })
        },
    );
    let strand_pass::StrandMeasures {
        strain,
        hairpins,
        drift,
        velocity_mismatch,
    } = strands;
    Ok(QualityReport {
        frames: 1,
        points: n as u64,
        strain,
        hairpins,
        penetration,
        drift,
        velocity_mismatch,
    })
}

fn check_len(name: &str, len: usize, points: usize) -> Result<()> {
    if len == points {
        Ok(())
    } else {
        Err(HairError::Parameter {
            name: format!("quality.{name}"),
            value: format!("{len} entries"),
            fix: format!("give one entry per point of the frame ({points})"),
        })
    }
}

/// The rest shape of `strands` posed on `scalp` (m, world): the reference for drift.
pub fn rest_positions(strands: &StrandSet, scalp: &Scalp) -> Vec<Vector3<f32>> {
    let rest = strands.rest_local();
    (0..strands.len())
        .into_par_iter()
        .with_min_len(256)
        .flat_map_iter(|s| {
            let root = scalp.root_frame(&strands.anchors()[s]);
            strands.points(s).map(move |i| root.to_world(&rest[i]))
        })
        .collect()
}
