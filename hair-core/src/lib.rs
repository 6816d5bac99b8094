//! # hair-core
//!
//! The simulation level of hairsys: strands stored structure-of-arrays ([`StrandSet`]), scalp
//! meshes with stable surface samples ([`TriMesh`], [`MeshSample`], [`RootFrame`]), the strand
//! models side by side in [`model`] — the mass-spring [`MassSpringSolver`], the discrete-rod
//! [`RodSolver`] of seed 002 and the hair strips of seed 000 ([`StripSolver`]: edge strands in
//! pairs bounding ribbons), with [`StrandSolver`] the one door over them — built from the
//! numerics in [`integrate`], hair–object collision ([`contacts`]: [`Colliders`]),
//! voxel hair–hair interaction ([`volume`]) and force fields ([`fields`]), and a quality report
//! of simulated frames ([`quality`]: penetration, strain, hairpins, drift, velocity–position
//! mismatch). Units are SI (m, s, kg), Z up.
//!
//! This crate does no file or terminal I/O and keeps no global state: a host (the `hairsys` CLI
//! or a DCC plugin) sets the scalp for each frame, calls [`MassSpringSolver::step_frame`] (or
//! [`StrandSolver::step_frame`]) and reads the positions back.
//!
//! ```
//! use hair_core::{
//!     Anchor, HairParams, MassSpringSolver, RootFrame, Scalp, SolverSettings, StrandInput,
//!     StrandSet,
//! };
//! use nalgebra::Vector3;
//!
//! // One hair of 8 segments growing along +x from the origin, held at its root.
//! let rest = (0..9).map(|i| Vector3::new(0.0, 0.0, 0.02 * i as f32)).collect();
//! let anchor = Anchor::Body(RootFrame::at(Vector3::zeros()));
//! let mut strands = StrandSet::new();
//! strands.push(StrandInput::uniform(anchor, rest, 1e-3, 1e-4, 0.0, 0.0)).unwrap();
//! let scalp = Scalp::fixed();
//! let mut solver =
//!     MassSpringSolver::new(SolverSettings::default(), HairParams::default(), &strands, &scalp, 1)
//!         .unwrap();
//! let report = solver.step_frame(&mut strands, &scalp).unwrap();
//! assert_eq!(report.frame, 2);
//! ```

pub mod contacts;
pub mod error;
pub mod fields;
pub mod frames;
pub mod integrate;
pub mod mesh;
pub mod model;
pub mod quality;
pub mod strands;
pub mod volume;

pub use contacts::{Collider, ColliderId, ColliderShape, Colliders, ContactSettings, MeshKind};
pub use error::{Blowup, HairError, MeshError, Result};
pub use fields::{Falloff, FalloffShape, FieldKind, ForceField, Strength};
pub use integrate::energy::{energy, Energy};
pub use integrate::{
    kernel_instructions, make_sag_free, make_sag_free_supported, HairParams, Inextensibility,
    Integrator, KernelChoice, SagFreeLimits, SagFreeReport, SolverSettings, StabilityBound,
    StrandScales, Substeps,
};
pub use mesh::{MeshSample, RootFrame, TriMesh};
pub use model::rod::{ProjectionReport, RodFrameReport, RodParams, RodSolverState};
pub use model::{
    Component, ComponentSet, FrameReport, MassSpringSolver, MassSpringSolverState, ModelFigures,
    PhaseTimes, RodSolver, StrandModel, StrandSolver, StrandSolverState, StripFigures, StripSolver,
};
pub use quality::{QualityInput, QualityOptions, QualityReport};
pub use strands::{Anchor, Scalp, StrandInput, StrandSet};
pub use volume::{HairHairSettings, VoxelGrid};
