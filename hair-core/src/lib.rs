//! # hair-core
//!
//! The simulation level of hairsys: strands stored structure-of-arrays ([`StrandSet`]), scalp
//! meshes with stable surface samples ([`TriMesh`], [`MeshSample`], [`RootFrame`]), the
//! mass-spring strand [`Solver`], the discrete-rod strand solver of seed 002 ([`rod`]:
//! [`RodSolver`]), the hair-strip model of seed 000 ([`strips`]: edge strands in pairs
//! bounding ribbons) and hair–object collision ([`contacts`]: [`Colliders`]),
//! voxel hair–hair interaction ([`volume`]) and force fields ([`fields`]), and a quality report
//! of simulated frames ([`quality`]: penetration, strain, hairpins, drift, velocity–position
//! mismatch). Units are SI (m, s, kg), Z up.
//!
//! This crate does no file or terminal I/O and keeps no global state: a host (the `hairsys` CLI
//! or a DCC plugin) sets the scalp for each frame, calls [`Solver::step_frame`] and reads the
//! positions back.
//!
//! ```
//! use hair_core::{Anchor, HairParams, RootFrame, Scalp, Solver, SolverSettings, StrandInput, StrandSet};
//! use nalgebra::Vector3;
//!
//! // One hair of 8 segments growing along +x from the origin, held at its root.
//! let rest = (0..9).map(|i| Vector3::new(0.0, 0.0, 0.02 * i as f32)).collect();
//! let anchor = Anchor::Body(RootFrame::at(Vector3::zeros()));
//! let mut strands = StrandSet::new();
//! strands.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-4, 0.0, 0.0)).unwrap();
//! let scalp = Scalp::fixed();
//! let mut solver = Solver::new(SolverSettings::default(), HairParams::default(), &strands, &scalp, 1).unwrap();
//! let report = solver.step_frame(&mut strands, &scalp).unwrap();
//! assert_eq!(report.frame, 2);
//! ```

pub mod contacts;
pub mod error;
pub mod fields;
pub mod frames;
pub mod mesh;
pub mod model;
pub mod quality;
pub mod rod;
pub mod solver;
pub mod strands;
pub mod strips;
pub mod volume;

pub use contacts::{Collider, ColliderId, ColliderShape, Colliders, ContactSettings, MeshKind};
pub use error::{Blowup, HairError, MeshError, Result};
pub use fields::{Falloff, FalloffShape, FieldKind, ForceField, Strength};
pub use mesh::{MeshSample, RootFrame, TriMesh};
pub use model::{Component, ComponentSet, ModelFigures, StrandSolver, StripFigures};
pub use quality::{QualityInput, QualityOptions, QualityReport};
pub use rod::{ProjectionReport, RodFrameReport, RodParams, RodSolver, StrandModel};
pub use solver::energy::{energy, Energy};
pub use solver::{
    kernel_instructions, make_sag_free, make_sag_free_supported, FrameReport, HairParams,
    Inextensibility, Integrator, KernelChoice, PhaseTimes, SagFreeLimits, SagFreeReport, Solver,
    SolverSettings, StabilityBound, StrandScales, Substeps,
};
pub use strands::{Anchor, Scalp, StrandInput, StrandSet};
pub use volume::{HairHairSettings, VoxelGrid};
