//! The rod and strip models in the bench: the rod's error against the catenary falls as the
//! substeps grow, its projection keeps every segment within 10⁻⁴ of its rest length through the
//! fast head turn, its cantilever under a tip moment lies on the elastica, and the strip model
//! reports a cost per represented hair and its edges' error against the rod truth.

use hairsys_bench::cases;
use hairsys_bench::methods::{Method, Rod, Strips};
use hairsys_bench::metrics::rms_difference;
use hairsys_bench::{tip_moment, truth};

#[test]
fn rod_drift_from_the_catenary_falls_as_substeps_grow() {
    // The chain started on its catenary: the rod moves off it only by its time error.
    let case = cases::chain_at_rest().unwrap();
    let truth = truth::truth(&case, 0).unwrap();
    let rod = Rod { iterations: 8 };
    let ladder = [4, 8, 16, 32];
    let errors: Vec<f64> = ladder
        .iter()
        .map(|&s| {
            rms_difference(
                &case,
                &rod.run(&case, Some(s)).unwrap().samples,
                &truth.samples,
            )
        })
        .collect();
    println!("rod on the chain at rest: substeps {ladder:?}, drift (m) {errors:?}");
    for w in errors.windows(2) {
        assert!(w[1] < 0.8 * w[0], "rod drift does not fall: {errors:?}");
    }
    assert!(
        errors[3] < 0.35 * errors[0],
        "8× the substeps should cut the drift well below half: {errors:?}"
    );
}

#[test]
fn rod_max_strain_stays_below_1e_4_in_the_fast_head_turn() {
    let case = cases::head_turn(true).unwrap();
    for iterations in [4, 8] {
        let trace = Rod { iterations }.run(&case, Some(64)).unwrap();
        let p = trace.projection.expect("rod runs report their projection");
        println!(
            "rod, {iterations} iterations, 64 substeps: strain {:.2e}, residual {:.2e}, \
             {:.2} iterations per projection",
            p.max_strain,
            p.residual,
            p.mean_iterations()
        );
        assert!(p.max_strain < 1e-4, "strain {}", p.max_strain);
        assert!(trace.max_stretch < 1e-4, "stretch {}", trace.max_stretch);
        assert!(p.max_iterations <= iterations);
    }
}

#[test]
fn rod_tip_moment_reproduces_the_elastica_at_small_and_large_deflection() {
    for t in tip_moment::ROTATIONS {
        let stable = tip_moment::run(8, 0.5 * tip_moment::bound(), t);
        println!("{stable:?}");
        assert_eq!(stable.status, "at rest");
        let error = stable.error_over_length.unwrap();
        assert!(error < 0.01, "t = {t}: node error {error} of L");
        let (u, v) = tip_moment::analytic_tip(t);
        assert!((stable.tip_u.unwrap() - u).abs() < 0.01 * tip_moment::LENGTH);
        assert!((stable.tip_v.unwrap() - v).abs() < 0.01 * tip_moment::LENGTH);
        // The tip turns by ML/EI: the last segment's direction is the arc's tangent at its
        // middle, s = L − l/2, turned by t (1 − 1/40) on 20 segments.
        let angle = stable.tip_angle.unwrap();
        let expected = t * (1.0 - 1.0 / 40.0);
        assert!(
            (angle - expected).abs() < 2e-3 * t,
            "t = {t}: tip turned by {angle} rad, the elastica {expected}"
        );
    }
    // One projection iteration above the bound cannot hold the lengths: the run says so.
    let failed = tip_moment::run(1, 1.5 * tip_moment::bound(), 1.5);
    assert!(failed.error_over_length.is_none(), "{failed:?}");
    assert!(
        failed.status.contains("projection not converging"),
        "{failed:?}"
    );
}

#[test]
fn strips_report_cost_per_represented_hair_and_edge_error() {
    let case = cases::head_strips(true).unwrap();
    let strips = case.sim.strands.len() as u64 / 2;
    assert_eq!(case.represented_hairs, Some(strips * 100));
    let trace = Strips.run(&case, Some(64)).unwrap();
    let per_hair = trace.cost.us_per_represented_hair.unwrap();
    let expected = 1e3 * trace.cost.ms_per_frame / (strips * 100) as f64;
    assert!(
        (per_hair - expected).abs() <= 1e-9 * expected,
        "{per_hair} against {expected}"
    );
    let truth = truth::truth(&case, 512).unwrap();
    let error = rms_difference(&case, &trace.samples, &truth.samples);
    println!("{strips} strips: {per_hair:.3} µs/frame/hair, edge error {error:.2e} m");
    // The strips' edges keep the default scene's springs (bending 18× the physical wisp's):
    // they are centimetres from the rod truth, but finite and below the strand length.
    assert!(error.is_finite() && error < 0.2, "edge error {error} m");
    assert!(Rod { iterations: 4 }.cannot_run(&case).is_some());
    assert!(Strips.cannot_run(&cases::pendulum().unwrap()).is_some());
}
