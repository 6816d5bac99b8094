//! Physical parameters of a hair system and the solver's time-stepping settings.

use nalgebra::Vector3;
#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

use crate::error::{check_non_negative, check_positive, HairError, Result};

/// Material and environment of a hair system (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct HairParams {
    /// Gravitational acceleration, m/s² (Z up: (0, 0, −9.81)).
    pub gravity: [f32; 3],
    /// Stretch spring stiffness between neighbouring points, N/m.
    pub stretch_stiffness: f32,
    /// Bending stiffness `k_b`, N/m: a strand's bending rigidity is `EI = k_b l̄³` (N·m²) with `l̄`
    /// its mean rest segment length, so a uniformly segmented strand resists a small turn `θ` at
    /// a point with the moment `k_b l² θ` (see [`super::curvature`]).
    pub bend_stiffness: f32,
    /// Goal spring stiffness towards the animated rest position, N/m (scaled by goal weight).
    pub goal_stiffness: f32,
    /// Viscous damping of relative velocity along each segment, 1/s: an isolated segment's
    /// stretching speed decays as exp(−rate·t). Applied in the damping sub-loop.
    pub stretch_damping: f32,
    /// Air drag, 1/s: every free point's velocity decays as exp(−rate·t) in still air.
    pub air_drag: f32,
}

impl Default for HairParams {
    fn default() -> Self {
        Self {
            gravity: [0.0, 0.0, -9.81],
            stretch_stiffness: 200.0,
            bend_stiffness: 0.5,
            goal_stiffness: 0.0,
            stretch_damping: 50.0,
            air_drag: 1.0,
        }
    }
}

impl HairParams {
    /// Checks every parameter is finite and ≥ 0 (gravity finite).
    pub fn validate(&self) -> Result<()> {
        if !self.gravity.iter().all(|g| g.is_finite()) {
            return Err(HairError::Parameter {
                name: "gravity".into(),
                value: format!("{:?}", self.gravity),
                fix: "give three finite numbers in m/s², e.g. [0, 0, -9.81]".into(),
            });
        }
        check_non_negative("stretch_stiffness", self.stretch_stiffness)?;
        check_non_negative("bend_stiffness", self.bend_stiffness)?;
        check_non_negative("goal_stiffness", self.goal_stiffness)?;
        check_non_negative("stretch_damping", self.stretch_damping)?;
        check_non_negative("air_drag", self.air_drag)
    }

    /// Gravity as a vector, m/s².
    pub fn gravity(&self) -> Vector3<f32> {
        Vector3::from(self.gravity)
    }
}

/// One strand's multipliers of the [`HairParams`] springs and damping (per-region physics): the
/// strand runs with `stretch_stiffness × stretch`, `bend_stiffness × bend`,
/// `goal_stiffness × goal`, `stretch_damping × damping` and `air_drag × drag`. All 1 (the
/// default) is the scene's material exactly: `x × 1.0 = x` in floating point, so a solver given
/// only unit scales advances every strand bit for bit as one given none.
///
/// Multipliers rather than values, so that a host animating [`HairParams`] per frame moves every
/// region with it. Gravity is not scaled (it is an acceleration, the same for every hair); mass
/// and radius are per point in the [`crate::StrandSet`] already.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields, default))]
pub struct StrandScales {
    /// Factor of the stretch stiffness (> 0: a strand without stretch springs falls apart).
    pub stretch: f32,
    /// Factor of the bending stiffness (≥ 0).
    pub bend: f32,
    /// Factor of the goal stiffness (≥ 0).
    pub goal: f32,
    /// Factor of the stretch damping rate (≥ 0).
    pub damping: f32,
    /// Factor of the air drag rate (≥ 0).
    pub drag: f32,
}

impl Default for StrandScales {
    fn default() -> Self {
        Self::ONE
    }
}

impl StrandScales {
    /// Every factor 1: the scene's material.
    pub const ONE: Self = Self {
        stretch: 1.0,
        bend: 1.0,
        goal: 1.0,
        damping: 1.0,
        drag: 1.0,
    };

    /// Checks every factor is finite and ≥ 0, the stretch factor > 0; errors name
    /// `strand_scales[strand].factor`.
    pub fn validate(&self, strand: usize) -> Result<()> {
        let fields = [
            ("stretch", self.stretch),
            ("bend", self.bend),
            ("goal", self.goal),
            ("damping", self.damping),
            ("drag", self.drag),
        ];
        for (name, value) in fields {
            let bad = !value.is_finite() || value < 0.0 || (name == "stretch" && value == 0.0);
            if bad {
                return Err(HairError::Parameter {
                    name: format!("strand_scales[{strand}].{name}"),
                    value: value.to_string(),
                    fix: if name == "stretch" {
                        "give a finite factor > 0 of [physics] stretch_stiffness (1 = the scene's)"
                            .into()
                    } else {
                        "give a finite factor ≥ 0 of the scene's value (1 = the scene's)".into()
                    },
                });
            }
        }
        Ok(())
    }

    /// The parameters one strand runs with: `params` with its springs and damping scaled.
    pub fn apply(&self, params: &HairParams) -> HairParams {
        HairParams {
            gravity: params.gravity,
            stretch_stiffness: params.stretch_stiffness * self.stretch,
            bend_stiffness: params.bend_stiffness * self.bend,
            goal_stiffness: params.goal_stiffness * self.goal,
            stretch_damping: params.stretch_damping * self.damping,
            air_drag: params.air_drag * self.drag,
        }
    }
}

/// How many force substeps each collision step takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum Substeps {
    /// Exactly this many substeps per step.
    Fixed(u32),
    /// Derived from the stability bound of the stiffest spring on the lightest point; with
    /// [`Integrator::ImplicitEuler`] and [`Integrator::Xpbd`], which have no such bound, from an
    /// accuracy limit on the substep (measured on the default scene).
    Auto,
}

/// Time integration scheme of the force substeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Integrator {
    /// `v += dt·a(x, v); x += dt·v` — symplectic, the default of [`SolverSettings`] (scene
    /// files choose between it and [`Integrator::ImplicitEuler`] by cost unless they name one).
    SemiImplicitEuler,
    /// `x += dt·v; v += dt·a(x, v)` with the old velocity — the baseline that fails first.
    ExplicitEuler,
    /// Linearised backward Euler along each strand, one banded direct solve per strand per
    /// substep: stable at any substep, so the substep follows accuracy (see
    /// `hair_core::integrate` module `implicit`). It adds artificial damping of `≈ exp(−π ω h)` per
    /// period to a swing of angular frequency `ω`.
    ImplicitEuler,
    /// The second-order backward differentiation formula (BDF2), linearised like
    /// [`Integrator::ImplicitEuler`] and solved by the same banded solve: stable far past the
    /// explicit bound (the bench's stability map: from 4 substeps per frame on a stiff whipping
    /// chain, 6 at 10⁴ N/m, where implicit Euler holds from 2), with far less artificial damping
    /// (`≈ (ωh)⁴/4` of the amplitude per substep instead of `(ωh)²/2`), so fewer substeps reach
    /// the same accuracy. BDF2 needs the state one substep back, so each step starts afresh: with
    /// an implicit midpoint substep, or with a backward Euler third when the step has one
    /// substep; a step depends on nothing before it and resume is unchanged. Not for sharply
    /// pre-bent hair at fine steps: on a curl (rest joints turning ~46°) it flutters at 128–512
    /// substeps per frame, as what its bending matrix leaves out feeds energy faster than its
    /// damping removes it (module `implicit`, "Flutter at fine steps"). Scene key `"bdf2"`.
    Bdf2,
    /// Extended position-based dynamics with small steps (Macklin et al. 2016, 2019): stretch,
    /// bending and goal springs as compliant constraints (compliance = 1/stiffness), the stretch
    /// and bending constraints of each strand solved together by one banded direct solve (Deul
    /// et al. 2018); no stability bound, so the substep follows accuracy (see
    /// `hair_core::integrate` module `xpbd`).
    /// Scene key `"xpbd"`.
    Xpbd,
}

/// Which compiled copy of the mass-spring kernel runs (see [`crate::kernel_instructions`]). Both
/// copies give the same bits; the choice only changes speed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum KernelChoice {
    /// The fastest copy this CPU runs (AVX2 where it has it).
    #[default]
    Auto,
    /// The portable baseline copy on any CPU (to compare speeds, or to check on one machine
    /// that both copies give the same bits).
    Baseline,
}

/// Time stepping of the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct SolverSettings {
    /// Frames per second of the animation.
    pub fps: f32,
    /// Collision steps per frame (roots, contacts and grids are evaluated once per step).
    pub steps: u32,
    /// Force substeps per step.
    pub substeps: Substeps,
    /// Iterations of the damping sub-loop per substep (0 switches damping off).
    pub damping_iterations: u32,
    /// Integration scheme.
    pub integrator: Integrator,
    /// Strain limit after each substep: segments longer than `(1 + max_strain) × rest length`
    /// are shortened to it (root to tip, velocities corrected). `Some(0.0)` makes strands
    /// inextensible; `None` switches it off.
    pub max_strain: Option<f32>,
    /// Which compiled copy of the kernel runs (same bits either way).
    #[cfg_attr(feature = "serde", serde(default))]
    pub kernel: KernelChoice,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            fps: 24.0,
            steps: 1,
            substeps: Substeps::Auto,
            damping_iterations: 10,
            integrator: Integrator::SemiImplicitEuler,
            max_strain: None,
            kernel: KernelChoice::Auto,
        }
    }
}

impl SolverSettings {
    /// Force substeps per collision step these settings take on strands whose stability bound
    /// is `bound`: the fixed count, or what `"auto"` resolves to for the integrator (the
    /// stability bound's count for the explicit-type integrators, the accuracy limit's for
    /// implicit Euler and XPBD). The [`crate::MassSpringSolver`] built from them takes the same
    /// count.
    pub fn resolved_substeps(&self, bound: &super::StabilityBound) -> u32 {
        super::resolve_substeps(self, bound)
    }

    /// Checks fps > 0, steps ≥ 1 and fixed substeps ≥ 1.
    pub fn validate(&self) -> Result<()> {
        check_positive("fps", self.fps)?;
        if self.steps == 0 {
            return Err(HairError::Parameter {
                name: "steps".into(),
                value: "0".into(),
                fix: "use at least 1 collision step per frame".into(),
            });
        }
        if self.substeps == Substeps::Fixed(0) {
            return Err(HairError::Parameter {
                name: "substeps".into(),
                value: "0".into(),
                fix: "use at least 1, or \"auto\"".into(),
            });
        }
        if let Some(limit) = self.max_strain {
            check_non_negative("max_strain", limit)?;
        }
        Ok(())
    }

    /// Length of one collision step, s.
    pub fn step_dt(&self) -> f64 {
        1.0 / (self.fps as f64 * self.steps as f64)
    }
}
