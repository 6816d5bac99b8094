//! The methods `hairsys bench` compares, behind one trait so that other models can join: a
//! method has a name and runs a case at a given number of substeps per frame; every method is
//! measured against the case's one truth ([`crate::truth`]). A solver with an iteration count of
//! its own (a discrete-rod solver's projection iterations, say) joins as one [`Method`] value per
//! count. [`all`] is the one list of methods: a new integrator joins there.
//!
//! The mass-spring methods differ in integrator, damping loop, projection and **stretch**: the
//! case's soft springs ([`Stretch::Soft`], what a scene sets for an affordable step), the
//! physical `EA/l` of the hair ([`Stretch::Physical`], which only an integrator without a
//! stability bound can carry at frame-rate substeps), or none (the projection alone holds the
//! lengths).

use crate::cases::CaseError;
use hair_core::{
    HairError, HairParams, Inextensibility, Integrator, MassSpringSolver, RodParams, RodSolver,
    SolverSettings, StrandModel, Substeps,
};

use crate::cases::Case;
use crate::metrics::{drive, drive_model, Trace};
use crate::stability;
use hair_core::StrandSolver;

/// A way of advancing a case in time.
pub trait Method: Sync {
    /// Label in charts and tables.
    fn name(&self) -> String;
    /// Runs `case` from its first to its last frame with `substeps` force substeps per frame
    /// (`None`: the method's own automatic choice, if it has one).
    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError>;
    /// Predicted largest stable substep of `case`, s (infinite if the method has no bound).
    fn bound(&self, case: &Case) -> Result<f64, HairError>;
    /// The model components it runs on `case`, as the solver reports them.
    fn components(&self, case: &Case) -> Result<Vec<String>, HairError>;
    /// Why it cannot run `case`, if it cannot (the case is then left out for this method and
    /// the report says why).
    fn cannot_run(&self, case: &Case) -> Option<String>;
    /// The stability map's probe for the row of stiffness `k` (N/m), run for `frames` frames:
    /// the probe strand with stretch stiffness `k` (see [`stability::probe_case`]).
    fn probe(&self, k: f64, frames: u32) -> Result<Case, CaseError> {
        stability::probe_case(k, frames)
    }
    /// What the rows of its stability map vary.
    fn stiffness_axis(&self) -> &'static str {
        "stretch stiffness k (N/m)"
    }
}

/// Settings of `case` with `substeps` per frame (`None`: auto), one collision step per frame.
fn fixed_settings(case: &Case, substeps: Option<u32>) -> SolverSettings {
    SolverSettings {
        steps: 1,
        substeps: substeps.map_or(Substeps::Auto, Substeps::Fixed),
        ..case.sim.settings
    }
}

/// Names the model components `solver` runs on `case`, with contacts when the case has
/// colliders.
fn named_components(case: &Case, solver: &StrandSolver) -> Vec<String> {
    let mut c: Vec<String> = solver
        .components(&case.sim.strands)
        .names()
        .into_iter()
        .map(String::from)
        .collect();
    if case.sim.has_colliders() {
        c.push("contacts".into());
    }
    c
}

/// Every method the bench compares, in chart order: the mass-spring configurations, the rod's
/// iteration limits, the strips. A new integrator of the mass-spring solver joins
/// [`MassSpring::all`].
pub fn all() -> Vec<Box<dyn Method>> {
    let mut methods = MassSpring::all();
    methods.extend(Rod::all());
    methods.push(Box::new(Strips));
    methods
}

/// What holds a mass-spring strand's segments at their length.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stretch {
    /// The case's stretch springs (soft: see [`crate::physical::soft_fraction`]).
    Soft,
    /// Springs of the hair's physical stiffness `EA/l` ([`Case::physical_stretch`]).
    Physical,
    /// No springs (with the projection: inextensible).
    None,
}

/// hair-core's mass-spring solver in one configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassSpring {
    /// Time integrator.
    pub integrator: Integrator,
    /// Run the damping sub-loop (the case's iterations) or switch it off (0 iterations).
    pub damping: bool,
    /// Run the inextensibility projection after every substep.
    pub projection: bool,
    /// Stretch springs.
    pub stretch: Stretch,
}

impl MassSpring {
    /// Semi-implicit Euler with the damping sub-loop: the solver's default.
    pub const DEFAULT: Self = Self {
        integrator: Integrator::SemiImplicitEuler,
        damping: true,
        projection: false,
        stretch: Stretch::Soft,
    };

    /// The methods `hairsys bench` compares.
    pub fn all() -> Vec<Box<dyn Method>> {
        let d = Self::DEFAULT;
        vec![
            Box::new(Self {
                integrator: Integrator::ExplicitEuler,
                ..d
            }),
            Box::new(d),
            Box::new(Self {
                damping: false,
                ..d
            }),
            Box::new(Self {
                projection: true,
                ..d
            }),
            Box::new(Self {
                projection: true,
                stretch: Stretch::None,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::ImplicitEuler,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::ImplicitEuler,
                stretch: Stretch::Physical,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::Bdf2,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::Bdf2,
                stretch: Stretch::Physical,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::Xpbd,
                ..d
            }),
            Box::new(Self {
                integrator: Integrator::Xpbd,
                stretch: Stretch::Physical,
                ..d
            }),
        ]
    }

    fn params(&self, case: &Case) -> HairParams {
        HairParams {
            stretch_stiffness: match self.stretch {
                Stretch::Soft => case.sim.params.stretch_stiffness,
                Stretch::Physical => case.physical_stretch,
                Stretch::None => 0.0,
            },
            ..case.sim.params
        }
    }

    fn settings(&self, case: &Case, substeps: Option<u32>) -> SolverSettings {
        let s = case.sim.settings;
        SolverSettings {
            damping_iterations: if self.damping {
                s.damping_iterations.max(1)
            } else {
                0
            },
            integrator: self.integrator,
            ..fixed_settings(case, substeps)
        }
    }

    /// The solver of this configuration for `case` at `substeps` per frame (`None`: auto), one
    /// collision step per frame, at the case's first frame.
    pub fn solver(
        &self,
        case: &Case,
        substeps: Option<u32>,
    ) -> Result<MassSpringSolver, HairError> {
        let sim = &case.sim;
        let solver = MassSpringSolver::new(
            self.settings(case, substeps),
            self.params(case),
            &sim.strands,
            &sim.scalp_at(sim.first_frame as f32),
            sim.first_frame,
        )?;
        if self.projection {
            solver.with_inextensibility(Inextensibility::default())
        } else {
            Ok(solver)
        }
    }
}

impl Method for MassSpring {
    fn name(&self) -> String {
        let mut name = match self.integrator {
            Integrator::ExplicitEuler => "explicit Euler".to_string(),
            Integrator::SemiImplicitEuler => "semi-implicit Euler".to_string(),
            Integrator::ImplicitEuler => "implicit Euler".to_string(),
            Integrator::Bdf2 => "BDF2".to_string(),
            Integrator::Xpbd => "XPBD".to_string(),
        };
        if !self.damping {
            name += ", no damping loop";
        }
        name += match (self.projection, self.stretch) {
            (false, Stretch::Soft) => "",
            (false, Stretch::Physical) => ", physical springs",
            (false, Stretch::None) => ", no stretch springs",
            (true, Stretch::Soft) => " + projection",
            (true, Stretch::Physical) => " + projection, physical springs",
            (true, Stretch::None) => " + projection, no stretch springs",
        };
        name
    }

    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError> {
        drive(case, self.solver(case, substeps)?)
    }

    fn bound(&self, case: &Case) -> Result<f64, HairError> {
        Ok(self.solver(case, Some(1))?.bound().dt_max)
    }

    fn components(&self, case: &Case) -> Result<Vec<String>, HairError> {
        let solver = StrandSolver::from(self.solver(case, Some(1))?);
        Ok(named_components(case, &solver))
    }

    fn cannot_run(&self, case: &Case) -> Option<String> {
        // On the strip case only the default runs beside the strips: the same edge strands as
        // plain hair, for the cost per represented hair.
        (case.sim.model == StrandModel::Strips && *self != Self::DEFAULT).then(|| {
            "the strip case compares the strip model with the default mass-spring method only"
                .into()
        })
    }
}

/// Seed 002's discrete rod ([`RodSolver`]) with a given projection iteration limit; the case's
/// `[rod]` material (the physical hair's, [`crate::physical::Hair::rod`]) and its gravity and
/// air drag. Stretching is a constraint, so the mass-spring stretch, bending and damping
/// parameters of the case do not apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rod {
    /// `rod.projection_iterations`: the projection's iteration limit per substep.
    pub iterations: u32,
}

impl Rod {
    /// Iteration limit of the rod truth (the scene default: converges to its tolerance).
    pub const REFERENCE_ITERATIONS: u32 = 20;

    /// The rod of the truth ([`crate::truth`]).
    pub const REFERENCE: Self = Self {
        iterations: Self::REFERENCE_ITERATIONS,
    };

    /// The rod methods `hairsys bench` compares: 1, 2, 4 and 8 projection iterations.
    pub fn all() -> Vec<Box<dyn Method>> {
        [1, 2, 4, 8]
            .into_iter()
            .map(|iterations| Box::new(Self { iterations }) as Box<dyn Method>)
            .collect()
    }

    fn solver(&self, case: &Case, substeps: Option<u32>) -> Result<RodSolver, HairError> {
        let sim = &case.sim;
        RodSolver::new(
            fixed_settings(case, substeps),
            sim.params,
            RodParams {
                projection_iterations: self.iterations,
                ..sim.rod
            },
            &sim.strands,
            &sim.scalp_at(sim.first_frame as f32),
            sim.first_frame,
        )
    }

    fn model(&self, case: &Case, substeps: Option<u32>) -> Result<StrandSolver, HairError> {
        Ok(self.solver(case, substeps)?.into())
    }
}

impl Method for Rod {
    fn name(&self) -> String {
        format!(
            "rod, {} projection iteration{}",
            self.iterations,
            if self.iterations == 1 { "" } else { "s" }
        )
    }

    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError> {
        drive_model(case, self.model(case, substeps)?)
    }

    fn bound(&self, case: &Case) -> Result<f64, HairError> {
        Ok(self.solver(case, Some(1))?.dt_max())
    }

    fn components(&self, case: &Case) -> Result<Vec<String>, HairError> {
        Ok(named_components(case, &self.model(case, Some(1))?))
    }

    /// The probe strand with the rod's stiffest bending `E I₂` chosen so that its zig-zag mode
    /// has the frequency of a stretch spring `k` on the same points: `32 E I₂ / (m l³) = 4 k/m`,
    /// `E I₂ = k l³/8` (the section's shape as in `[rod]`, Young's modulus scaled). Stretching
    /// is a constraint for the rod, so bending is what bounds its substep.
    fn probe(&self, k: f64, frames: u32) -> Result<Case, CaseError> {
        let mut case = stability::probe_case(k, frames)?;
        let rod = &mut case.sim.rod;
        let wanted = k * stability::PROBE_SEGMENT.powi(3) / 8.0;
        let minor = hair_core::model::rod::Stiffness::of(rod).minor;
        rod.youngs_modulus = (rod.youngs_modulus as f64 * wanted / minor) as f32;
        Ok(case)
    }

    fn stiffness_axis(&self) -> &'static str {
        "bending with the frequency of k: E I₂ = k l³/8 (k in N/m)"
    }

    fn cannot_run(&self, case: &Case) -> Option<String> {
        if case.sim.model == StrandModel::Strips {
            return Some("the strip case is the strip model's".into());
        }
        let goals = case.sim.strands.goal_weights().iter().any(|&w| w > 0.0)
            && case.sim.params.goal_stiffness > 0.0;
        goals.then(|| {
            "the case's strands hold their shape by goal springs, which the rod model does not \
             have (its shape comes from the rest curvature and the [rod] material)"
                .into()
        })
    }
}

/// Seed 000's hair strips ([`hair_core::model::strips::StripSolver`]): the case's edge strands as
/// mass-spring chains with Provot's strain limit, the root angle limiter and the two-stage head
/// collision. Its error is that of the ribbon's edges against the rod truth on the same edge
/// strands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Strips;

impl Method for Strips {
    fn name(&self) -> String {
        "strips".into()
    }

    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError> {
        let mut sim = case.sim.clone();
        sim.settings = fixed_settings(case, substeps);
        drive_model(case, sim.strand_solver()?)
    }

    fn bound(&self, case: &Case) -> Result<f64, HairError> {
        MassSpring::DEFAULT.bound(case)
    }

    fn components(&self, case: &Case) -> Result<Vec<String>, HairError> {
        let mut c = MassSpring::DEFAULT.components(case)?;
        c.extend(
            [
                "Provot strain limit",
                "root angle limiter",
                "two-stage head collision",
            ]
            .map(String::from),
        );
        Ok(c)
    }

    fn cannot_run(&self, case: &Case) -> Option<String> {
        (case.sim.model != StrandModel::Strips).then(|| {
            "the strip model runs on its own strips, grown on the head (case head-strips)".into()
        })
    }
}
