//! The **curly** case: a case that needs twist.
//!
//! One physical hair ([`crate::physical`]) 15 cm long, shaped at rest as a helix of radius 1 cm
//! and pitch 2.5 cm (about 2.2 turns) hanging down from its root, released under gravity with
//! air drag 5/s and followed for 2 s while it settles; the root frame holds the first segment's
//! direction. Its bending length `(EI/μg)^{1/3}` is 4.9 mm against a curl radius of 10 mm, so
//! gravity loosens the curl without pulling it straight: the weight of the hair below the root,
//! `μ g L` = 9.7 µN, at the curl's radius is 1/8 of the moment `EI/R` that holds the curl.
//!
//! A helix bends in a plane that turns along the strand (its torsion), so the shape it keeps is
//! a matter of how a model carries the bend's direction from one segment to the next: the rod
//! carries a material frame by parallel transport with its twist; the mass-spring bending
//! springs hold each segment's rest direction in the previous segment's frame. The truth is the
//! converged rod ([`crate::truth`]), and the measures that say most are the position and tip
//! errors and the **curl kept** (mean curvature against the truth's).
//!
//! The strand at any segment count ([`curly_at`]) samples the same helix at equal steps of its
//! parameter (equal arc lengths): its points lie on the helix, its segments are its chords, its
//! point masses `μ l`. Coarser counts are coarser polygons of the same curve (at 4 segments a
//! segment spans half a turn), which the segments axis measures.

use crate::cases::CaseError;
use std::f64::consts::TAU;

use crate::cases::{one_hair, Case, OneHair, Resegment};
use crate::physical::RADIUS;

/// Length of the hair, m.
pub const LENGTH: f64 = 0.15;
/// Radius of the helix, m.
pub const CURL_RADIUS: f64 = 0.01;
/// Pitch of the helix (drop per turn), m.
pub const PITCH: f64 = 0.025;
/// Segments of the case as charted.
pub const SEGMENTS: usize = 16;

/// Point `i` of `n` equal steps along the helix: root at the origin, axis along −z, the first
/// tangent in the xy plane tilted down by the pitch angle, m.
pub fn helix_point(i: usize, n: usize) -> [f64; 3] {
    let rise = PITCH / TAU;
    // Arc length per radian of the helix's angle.
    let speed = (CURL_RADIUS * CURL_RADIUS + rise * rise).sqrt();
    let theta = LENGTH / speed * i as f64 / n as f64;
    [
        CURL_RADIUS * theta.sin(),
        CURL_RADIUS * (1.0 - theta.cos()),
        -rise * theta,
    ]
}

/// Turns of the helix.
pub fn turns() -> f64 {
    let rise = PITCH / TAU;
    LENGTH / (CURL_RADIUS * CURL_RADIUS + rise * rise).sqrt() / TAU
}

/// The curly hair of [`curly`] at its charted segment count.
pub fn curly() -> Result<Case, CaseError> {
    curly_at(SEGMENTS)
}

/// The curly hair (module docs) with `n` segments.
pub fn curly_at(n: usize) -> Result<Case, CaseError> {
    let points: Vec<[f64; 3]> = (0..=n).map(|i| helix_point(i, n)).collect();
    one_hair(
        OneHair {
            name: "curly",
            title: "curly: a 15 cm hair coiled as a helix (radius 1 cm, pitch 2.5 cm, 2.2 turns) \
                    in 16 segments, root held, released under gravity, 2 s; truth: the \
                    converged rod",
            air_drag: 5.0,
            radius: Some(RADIUS),
            extra: String::new(),
        },
        &points,
        Resegment {
            segments: SEGMENTS,
            build: curly_at,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helix_points_are_equal_chords_of_the_stated_helix() {
        let n = 64;
        let p: Vec<[f64; 3]> = (0..=n).map(|i| helix_point(i, n)).collect();
        let chord = |a: [f64; 3], b: [f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        let first = chord(p[0], p[1]);
        for w in p.windows(2) {
            assert!((chord(w[0], w[1]) - first).abs() < 1e-12);
        }
        // Each chord spans the helix angle Δ = L / (n √(R² + c²)) (c the rise per radian):
        // 2R sin(Δ/2) across the axis and cΔ along it; their sum falls short of the helix's
        // length by the chord deficit, about (κ l)²/24 (1.7 × 10⁻³ at 64 segments).
        let c = PITCH / TAU;
        let delta = LENGTH / (n as f64 * (CURL_RADIUS.powi(2) + c * c).sqrt());
        let want = ((2.0 * CURL_RADIUS * (delta / 2.0).sin()).powi(2) + (c * delta).powi(2)).sqrt();
        assert!((first - want).abs() < 1e-12, "{first} against {want}");
        let total: f64 = p.windows(2).map(|w| chord(w[0], w[1])).sum();
        assert!(total < LENGTH && total > 0.998 * LENGTH, "{total}");
        // Every point is at the curl radius from the axis through (0, R).
        for q in &p {
            let r = (q[0].powi(2) + (q[1] - CURL_RADIUS).powi(2)).sqrt();
            assert!((r - CURL_RADIUS).abs() < 1e-12);
        }
        assert!((turns() - 2.22).abs() < 0.01, "{}", turns());
    }
}

#[cfg(test)]
mod implicit_tests {
    use super::*;
    use crate::methods::{MassSpring, Method, Stretch};
    use hair_core::Integrator;

    /// Implicit Euler and BDF2 hold the curly hair (joints turning 46° at rest) at 32 substeps
    /// per frame with its soft springs, and implicit Euler at 16 with the physical ones, within
    /// 0.5 % stretch, with bending's Gauss–Newton Hessian on sharply bent hair (with the
    /// small-angle Hessian about a straight joint these runs stretch 3 % and 23 %); the
    /// explicit kernel's converged run stretches 0.14 %.
    #[test]
    fn implicit_integrators_hold_the_curl_at_large_steps() {
        let case = curly().unwrap();
        for (integrator, stretch, substeps) in [
            (Integrator::ImplicitEuler, Stretch::Soft, 32),
            (Integrator::Bdf2, Stretch::Soft, 32),
            (Integrator::ImplicitEuler, Stretch::Physical, 16),
        ] {
            let m = MassSpring {
                integrator,
                stretch,
                ..MassSpring::DEFAULT
            };
            let trace = m.run(&case, Some(substeps)).unwrap();
            println!(
                "{} at {substeps}: max stretch {:.4}",
                m.name(),
                trace.max_stretch
            );
            assert!(
                trace.max_stretch < 5e-3,
                "{} at {substeps} substeps/frame stretched {:.2} %",
                m.name(),
                100.0 * trace.max_stretch
            );
        }
    }
}

/// A study, not a test: BDF2's flutter on the curly hair at fine steps (`hair_core::integrate`
/// module `implicit`, "Flutter at fine steps"; its history: `docs/design/implicit-integrators.md`).
/// Prints, every fourth frame, the largest stretch and the strand's energy of BDF2 and
/// implicit Euler at the substep counts of `SUBSTEPS` (default 64,128,256,512,1024), run in
/// `STEPS` collision steps per frame (default 1; each step restarts BDF2):
/// `STEPS=16 cargo test --release -p hairsys-cli --lib bdf2_flutter -- --ignored --nocapture`.
#[cfg(test)]
mod flutter_study {
    use super::*;
    use crate::methods::{MassSpring, Stretch};
    use hair_core::{Integrator, MassSpringSolver, SolverSettings, StrandSolver};

    fn env_list(name: &str, default: &str) -> Vec<u32> {
        std::env::var(name)
            .unwrap_or_else(|_| default.into())
            .split(',')
            .map(|s| s.trim().parse().expect("a list of counts"))
            .collect()
    }

    #[test]
    #[ignore = "a study: prints figures, asserts nothing"]
    fn bdf2_flutter() {
        let case = curly().expect("the curly case");
        let sim = &case.sim;
        let steps = env_list("STEPS", "1")[0];
        for substeps in env_list("SUBSTEPS", "64,128,256,512,1024") {
            for integrator in [Integrator::ImplicitEuler, Integrator::Bdf2] {
                let method = MassSpring {
                    integrator,
                    stretch: Stretch::Soft,
                    ..MassSpring::DEFAULT
                };
                let per_step = method
                    .solver(&case, Some(substeps / steps))
                    .expect("a solver");
                let settings = SolverSettings {
                    steps,
                    ..*per_step.settings()
                };
                let rest = sim.scalp_at(sim.first_frame as f32);
                let solver = MassSpringSolver::new(
                    settings,
                    *per_step.params(),
                    &sim.strands,
                    &rest,
                    sim.first_frame,
                )
                .expect("a solver");
                let mut solver = StrandSolver::from(solver);
                let mut strands = sim.strands.clone();
                let mut line = format!("{integrator:?} {substeps}/frame, {steps} steps:");
                for frame in sim.first_frame + 1..=sim.last_frame {
                    let scalp = sim.scalp_at(frame as f32);
                    let report = solver
                        .step_frame(&mut strands, &scalp, None)
                        .expect("a frame");
                    if frame % 4 == 0 {
                        let stretch = 100.0 * report.max_stretch;
                        let energy = solver.energy(&strands);
                        line += &format!(" | {frame}: {stretch:.2} % {energy:.3e} J");
                    }
                }
                println!("{line}");
            }
        }
    }
}
