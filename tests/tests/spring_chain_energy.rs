//! Energy of an undamped spring chain: semi-implicit Euler keeps it bounded, explicit Euler makes
//! it grow.
//!
//! Scene: three segments of stiffness k from a fixed root, equal point masses m, no gravity, no
//! damping or drag, stretched longitudinally at t = 0 and released. The motion stays on the
//! chain's line, where the springs are exactly linear: `M ẍ = −K x`. Each normal mode (frequency
//! ω_i, from the eigenvalues of `M^{-1/2} K M^{-1/2}`) then evolves on its own, and for a
//! substep h:
//!
//! - **semi-implicit Euler** (`v += h a(x); x += h v`) conserves exactly the modified energy
//!   `H̃ = H − (h/2) vᵀ K x = H + (h/2) v·F(x)` (F: spring forces). Since
//!   `|vᵀ K x| ≤ ω_max · 2H`, H itself stays within `[(1−a)/(1+a), (1+a)/(1−a)] · H(0)` with
//!   `a = h ω_max / 2`, for ever, with no drift. Only f32 rounding can move H̃;
//! - **explicit Euler** (`x += h v; v += h a(x_old)`) multiplies each mode's energy by exactly
//!   `1 + (h ω_i)²` per substep, so `E_n = Σ_i E_i(0) (1 + (h ω_i)²)^n`, which grows for any h.
//!
//! h is 0.05 × the solver's bound `2/ω` (ω = 2√(k/m)), so `a ≈ 0.05` and the excursion bound is
//! about ±10 %; 10,000 substeps. Explicit Euler's energy is compared with the modal prediction
//! while the chain stays straight (the springs are linear only until a segment folds through zero
//! length); it must have gained more than 100× by then. After that it keeps growing until the
//! blow-up detector stops it with `HairError::Unstable`, which is accepted as the end of the run.

mod common;

use common::*;
use hair_core::{
    energy, HairError, Integrator, MassSpringSolver, Scalp, SolverSettings, StrandSet, Substeps,
};
use nalgebra::{DVector, Vector3};

const SEGMENTS: usize = 3;
const SEG_LEN: f32 = 0.1;
const MASS: f64 = 1e-3;
const K: f64 = 100.0;
/// Initial longitudinal displacement of the free points, m (a generic mix of all modes).
const DISPLACEMENT: [f32; SEGMENTS] = [0.0015, -0.001, 0.002];
const SUBSTEPS_PER_FRAME: u32 = 100;
const FRAMES: u32 = 100;
/// Substep as a fraction of the solver's stability bound.
const RATIO: f64 = 0.05;

fn scene(integrator: Integrator) -> (StrandSet, MassSpringSolver, Scalp) {
    let rest = straight(SEGMENTS, SEG_LEN, -Vector3::z());
    let mut mass = vec![MASS as f32; SEGMENTS + 1];
    mass[0] = 0.0;
    let scalp = Scalp::fixed();
    let mut strands = set_on(
        &scalp,
        [strand(
            // Root at z = 0.15 m so the chain straddles the origin: f32 rounding is smallest there.
            anchor_at(Vector3::new(0.0, 0.0, 0.15)),
            rest,
            mass,
            root_only(SEGMENTS + 1),
        )],
    );
    for (i, u) in DISPLACEMENT.iter().enumerate() {
        strands.positions[i + 1].z -= u;
    }

    let params = bare_params(K as f32);
    // The bound depends on masses and stiffness only; pick fps so that h = RATIO × bound.
    let probe =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    let h = RATIO * probe.bound().dt_max;
    let settings = SolverSettings {
        max_strain: None,
        fps: (1.0 / (h * SUBSTEPS_PER_FRAME as f64)) as f32,
        steps: 1,
        substeps: Substeps::Fixed(SUBSTEPS_PER_FRAME),
        damping_iterations: 0,
        integrator,
        kernel: Default::default(),
    };
    let solver = MassSpringSolver::new(settings, params, &strands, &scalp, 0).unwrap();
    (strands, solver, scalp)
}

/// Total mechanical energy, J.
fn total_energy(strands: &StrandSet, solver: &MassSpringSolver) -> f64 {
    energy(strands, solver.params(), solver.roots()).total()
}

/// `v · F(x)` with F the stretch spring forces on the free points, W.
fn power_of_springs(strands: &StrandSet) -> f64 {
    let x = &strands.positions;
    let v = &strands.velocities;
    let l0 = strands.rest_lengths();
    let mut p = 0.0;
    for j in 0..SEGMENTS {
        let d = (x[j + 1] - x[j]).cast::<f64>();
        let len = d.norm();
        let f = d / len * (K * (len - l0[j] as f64));
        // f pulls point j towards j + 1 and point j + 1 towards j.
        p += v[j].cast::<f64>().dot(&f) - v[j + 1].cast::<f64>().dot(&f);
    }
    p
}

/// Frequencies (rad/s) and initial energy (J) of each longitudinal mode of the released chain.
fn modal_energies() -> (Vec<f64>, Vec<f64>) {
    let (omega, vectors) = chain_modes(K, &[MASS; SEGMENTS]);
    // Mass-weighted displacement; velocities are zero at t = 0.
    let u = DVector::from_iterator(
        SEGMENTS,
        DISPLACEMENT.iter().map(|&d| d as f64 * MASS.sqrt()),
    );
    let q = vectors.transpose() * u;
    let e = omega
        .iter()
        .zip(q.iter())
        .map(|(w, q)| 0.5 * w * w * q * q)
        .collect();
    (omega, e)
}

#[test]
fn semi_implicit_euler_keeps_chain_energy_bounded() {
    let (mut strands, mut solver, scalp) = scene(Integrator::SemiImplicitEuler);
    let h = solver.dt();
    let (omega, e_modes) = modal_energies();
    let omega_max = *omega.last().unwrap();
    let a = 0.5 * h * omega_max;
    let e0 = total_energy(&strands, &solver);
    let modified0 = e0 + 0.5 * h * power_of_springs(&strands);
    assert!(
        (e_modes.iter().sum::<f64>() - e0).abs() < 1e-3 * e0,
        "modal split"
    );

    let (mut lo, mut hi, mut modified_drift) = (1.0f64, 1.0f64, 0.0f64);
    run(&mut solver, &mut strands, &scalp, FRAMES, |s, set| {
        let e = total_energy(set, s);
        lo = lo.min(e / e0);
        hi = hi.max(e / e0);
        let modified = e + 0.5 * h * power_of_springs(set);
        modified_drift = modified_drift.max((modified - modified0).abs() / e0);
    })
    .unwrap();
    let substeps = FRAMES * SUBSTEPS_PER_FRAME;
    let (band_lo, band_hi) = ((1.0 - a) / (1.0 + a), (1.0 + a) / (1.0 - a));
    println!(
        "semi-implicit Euler, {substeps} substeps at h = {h:.3e} s ({RATIO} × bound, h ω_max = \
         {:.3}): E/E0 in [{lo:.5}, {hi:.5}], analytic band [{band_lo:.5}, {band_hi:.5}]; \
         modified energy H̃ drift {modified_drift:.2e} × E0 (exactly conserved in exact \
         arithmetic)",
        h * omega_max
    );
    assert_eq!(substeps, 10_000);
    assert!(
        lo >= band_lo && hi <= band_hi,
        "energy left the analytic band"
    );
    // Only f32 rounding moves H̃: each substep rounds positions (|x| ≤ 0.15 m) by up to half an
    // ulp, 7.5e-9 m, against displacements of ~2 mm: ~7.5e-6 of E0 per substep, a random walk of
    // ~7.5e-4 E0 after 10⁴ substeps. No secular drift beyond that is allowed.
    assert!(
        modified_drift < 1e-3,
        "modified energy drifted by {modified_drift:.2e} E0"
    );
}

#[test]
fn explicit_euler_gains_chain_energy_at_the_predicted_rate() {
    let (mut strands, mut solver, scalp) = scene(Integrator::ExplicitEuler);
    let h = solver.dt();
    let (omega, e_modes) = modal_energies();
    let e0 = total_energy(&strands, &solver);
    let predicted = |n: u32| -> f64 {
        omega
            .iter()
            .zip(&e_modes)
            .map(|(w, e)| e * (1.0 + (h * w).powi(2)).powi(n as i32))
            .sum::<f64>()
            / e0
    };

    let mut last_ok = (0u32, 1.0f64);
    let mut worst = 0.0f64;
    let mut folded = None;
    let outcome = run(&mut solver, &mut strands, &scalp, FRAMES, |s, set| {
        let n = s.frame() * SUBSTEPS_PER_FRAME;
        // The springs are linear only while every segment keeps its orientation along the line;
        // once one folds through zero length the modal prediction no longer applies.
        let straight = set.positions.windows(2).all(|w| w[1].z < w[0].z);
        if !straight && folded.is_none() {
            folded = Some(n);
        }
        if folded.is_none() {
            let growth = total_energy(set, s) / e0;
            worst = worst.max((growth / predicted(n) - 1.0).abs());
            last_ok = (n, growth);
        }
    });
    let (n, growth) = last_ok;
    let floor = (1.0 + (h * omega[0]).powi(2)).powi(n as i32);
    println!(
        "explicit Euler at the same h = {h:.3e} s: E/E0 = {growth:.4e} after {n} substeps \
         (modal prediction {:.4e}, worst relative mismatch {worst:.2e}; lowest-mode floor \
         {floor:.3}); a segment first folded after {folded:?} substeps; run ended with {:?}",
        predicted(n),
        outcome.as_ref().err().map(|e| e.to_string())
    );
    // Every frame follows Σ E_i (1 + h²ω_i²)^n; f32 rounding accumulates with the growth.
    assert!(
        worst < 0.01,
        "energy growth off the modal prediction by {worst:.2e}"
    );
    // A clear gain: explicit Euler either ran all substeps and gained energy, or grew until the
    // blow-up detector stopped it (which must then name the strand and the bound).
    assert!(growth > 100.0, "explicit Euler gained only {growth:.3}×");
    match outcome {
        Ok(()) => assert_eq!(n, 10_000),
        Err(HairError::Unstable { strand, bound, .. }) => {
            assert_eq!(strand, 0);
            assert_eq!(bound, solver.bound().dt_max);
        }
        Err(e) => panic!("unexpected error {e}"),
    }
}
