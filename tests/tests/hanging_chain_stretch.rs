//! Stretch stiffness is respected: a vertical chain hanging from its root, settled under gravity,
//! stretches each segment by the weight it carries divided by the spring stiffness.
//!
//! Reference (statics of a linear spring chain): segment j carries the weight of every point below
//! it, `T_j = g Σ_{i>j} m_i`, so `Δl_j = T_j / k`. The point masses are deliberately unequal (the
//! stretch must follow the actual weights, not a uniform-density formula). Stretch damping and air
//! drag bring the chain to rest; neither acts at rest. The chain stays on its vertical line, where
//! the springs are exactly linear, so the only error left is f32 rounding: positions within
//! |z| ≤ 0.2 m are held to half an ulp (7.5e-9 m), so a segment length to 1.5e-8 m, 5e-5 of the
//! smallest stretch (2.9e-4 m). The limit, 2e-4 relative, is four times that.

mod common;

use common::integrators::{chain_stretch_and_weight_over_k, hanging_chain};
use common::*;
use hair_core::{MassSpringSolver, SolverSettings};

#[test]
fn settled_hanging_chain_stretches_by_weight_below_over_k() {
    let (mut strands, scalp, mass, params) = hanging_chain();
    let mut solver =
        MassSpringSolver::new(SolverSettings::default(), params, &strands, &scalp, 0).unwrap();
    // 3 s: every longitudinal mode decays at least as fast as exp(−drag·t/2) = e^{−30}.
    run(&mut solver, &mut strands, &scalp, 72, |_, _| {}).unwrap();

    let mut worst = 0.0f64;
    for (j, (measured, expected)) in chain_stretch_and_weight_over_k(&strands, &mass)
        .into_iter()
        .enumerate()
    {
        let rel = (measured - expected).abs() / expected;
        worst = worst.max(rel);
        println!(
            "segment {j}: stretch {measured:.6e} m, weight below / k = {expected:.6e} m \
             (rel. error {rel:.2e})"
        );
    }
    println!("worst relative error {worst:.2e} (limit 2e-4)");
    assert!(worst < 2e-4, "stretch off T/k by {worst:.2e}");
}
