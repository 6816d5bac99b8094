//! Time integration of strands: the numerics the strand models in [`crate::model`] advance
//! strands with, one step at a time. It is named for what it does, not for a solver: the
//! solvers, which keep state from frame to frame, are [`crate::MassSpringSolver`],
//! [`crate::RodSolver`] and [`crate::StripSolver`]; nothing here keeps state between steps.
//!
//! - **What a step is given:** the material and the time stepping ([`HairParams`],
//!   [`SolverSettings`], [`Integrator`], [`Substeps`], per-strand [`StrandScales`]), the
//!   stability bound of the explicit integrators and `substeps = "auto"` ([`StabilityBound`],
//!   [`substeps_within`]).
//! - **The mass-spring kernel**, compiled for baseline SIMD and for AVX2 with the same bits
//!   (`kernel`, `lanes`, `f32_lanes`, `dispatch`; [`kernel_instructions`]), with its
//!   integrators: semi-implicit and explicit Euler (`kernel`), implicit Euler and BDF2
//!   (`implicit`, with the banded and block-banded solves of `band`, `block_band`, `blocks`) and
//!   XPBD (`xpbd`); the forces and projections inside a substep: curvature bending
//!   ([`curvature`]), the damping sub-loop (`damping`), the strain limit (`strain_limit`) and the
//!   inextensibility projection ([`inextensible`]).
//! - **What sets a run up and checks it:** sag-free rest shapes ([`sag_free`]) and the
//!   mechanical energy of a strand set ([`energy`]).

mod band;
mod block_band;
mod blocks;
pub mod curvature;
mod damping;
mod dispatch;
pub mod energy;
mod f32_lanes;
pub(crate) mod implicit;
pub mod inextensible;
pub(crate) mod kernel;
pub(crate) mod lanes;
pub mod params;
pub mod sag_free;
pub mod stability;
pub(crate) mod strain_limit;
pub(crate) mod xpbd;

pub use inextensible::Inextensibility;
pub use params::{HairParams, Integrator, KernelChoice, SolverSettings, StrandScales, Substeps};
pub use sag_free::{make_sag_free, make_sag_free_supported, SagFreeLimits, SagFreeReport};
pub use stability::StabilityBound;

/// The compiled copy of the mass-spring kernel (used by the mass-spring and strip models) that
/// `choice` runs on this CPU: `"avx2"` — x86-64 with AVX2, eight lanes per 256-bit instruction —
/// or `"baseline"` — the target's default SIMD, two 128-bit halves (SSE2 on x86-64, NEON on
/// aarch64), on any CPU when [`KernelChoice::Baseline`] asks for it. Both give the same bits; the
/// AVX2 copy runs the substeps of the shipped scenes 1.3–1.6× faster (`BENCHMARKS.md`).
pub fn kernel_instructions(choice: KernelChoice) -> &'static str {
    if kernel::wide_registers(choice) {
        "avx2"
    } else {
        "baseline"
    }
}

/// Force substeps per collision step for `settings`: the fixed count, or `auto` from the
/// stability bound (explicit-type integrators) or the accuracy limit (implicit Euler, XPBD).
pub(crate) fn resolve_substeps(settings: &SolverSettings, bound: &StabilityBound) -> u32 {
    match settings.substeps {
        Substeps::Fixed(n) => n,
        Substeps::Auto => match settings.integrator {
            Integrator::ImplicitEuler => substeps_within(settings.step_dt(), implicit::AUTO_DT),
            Integrator::Bdf2 => substeps_within(settings.step_dt(), implicit::AUTO_DT_BDF2),
            Integrator::Xpbd => substeps_within(settings.step_dt(), xpbd::AUTO_DT),
            Integrator::SemiImplicitEuler | Integrator::ExplicitEuler => {
                bound.auto_substeps(settings.step_dt())
            }
        },
    }
}

/// The fewest substeps per step of length `step_dt` (s) keeping the substep at most `longest`
/// (s), at least 1: `"auto"` for the integrators whose substep follows an accuracy limit.
pub fn substeps_within(step_dt: f64, longest: f64) -> u32 {
    (step_dt / longest * (1.0 - 1e-9))
        .ceil()
        .clamp(1.0, u32::MAX as f64) as u32
}
