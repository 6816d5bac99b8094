//! The methods `hairsys bench` compares, behind one trait so that other models can join: a
//! method has a name, names the model it converges to (its reference), and runs a case at a
//! given number of substeps per frame. A solver with an iteration count of its own (a
//! discrete-rod solver's projection iterations, say) joins as one [`Method`] value per count.

use hair_core::{
    HairError, HairParams, Inextensibility, Integrator, Solver, SolverSettings, Substeps,
};

use super::cases::Case;
use super::metrics::{drive, Trace};

/// A way of advancing a case in time.
pub trait Method: Sync {
    /// Label in charts and tables.
    fn name(&self) -> String;
    /// The method whose very fine run is this one's reference: the same model (same physics),
    /// advanced by the most accurate integrator.
    fn reference(&self) -> Box<dyn Method>;
    /// Runs `case` from its first to its last frame with `substeps` force substeps per frame
    /// (`None`: the method's own automatic choice, if it has one).
    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError>;
    /// Predicted largest stable substep of `case`, s (infinite if the method has no bound).
    fn bound(&self, case: &Case) -> Result<f64, HairError>;
    /// The model components it runs on `case`, as the solver reports them.
    fn components(&self, case: &Case) -> Result<Vec<String>, HairError>;
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
    /// Keep the stretch springs (false: the projection alone holds the lengths).
    pub springs: bool,
}

impl MassSpring {
    /// Semi-implicit Euler with the damping sub-loop: the solver's default.
    pub const DEFAULT: Self = Self {
        integrator: Integrator::SemiImplicitEuler,
        damping: true,
        projection: false,
        springs: true,
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
                springs: false,
                ..d
            }),
        ]
    }

    fn params(&self, case: &Case) -> HairParams {
        HairParams {
            stretch_stiffness: if self.springs {
                case.sim.params.stretch_stiffness
            } else {
                0.0
            },
            ..case.sim.params
        }
    }

    fn settings(&self, case: &Case, substeps: Option<u32>) -> SolverSettings {
        let s = case.sim.settings;
        SolverSettings {
            steps: 1,
            substeps: substeps.map_or(Substeps::Auto, Substeps::Fixed),
            damping_iterations: if self.damping {
                s.damping_iterations.max(1)
            } else {
                0
            },
            integrator: self.integrator,
            ..s
        }
    }

    fn solver(&self, case: &Case, substeps: Option<u32>) -> Result<Solver, HairError> {
        let sim = &case.sim;
        let solver = Solver::new(
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
        };
        if !self.damping {
            name += ", no damping loop";
        }
        if self.projection {
            name += if self.springs {
                " + projection"
            } else {
                " + projection, no stretch springs"
            };
        }
        name
    }

    fn reference(&self) -> Box<dyn Method> {
        Box::new(Self {
            integrator: Integrator::SemiImplicitEuler,
            ..*self
        })
    }

    fn run(&self, case: &Case, substeps: Option<u32>) -> Result<Trace, HairError> {
        drive(case, self.solver(case, substeps)?)
    }

    fn bound(&self, case: &Case) -> Result<f64, HairError> {
        Ok(self.solver(case, Some(1))?.bound().dt_max)
    }

    fn components(&self, case: &Case) -> Result<Vec<String>, HairError> {
        let solver = self.solver(case, Some(1))?;
        let mut c: Vec<String> = solver
            .components(&case.sim.strands)
            .0
            .into_iter()
            .map(String::from)
            .collect();
        if case.sim.has_colliders() {
            c.push("contacts".into());
        }
        Ok(c)
    }
}
