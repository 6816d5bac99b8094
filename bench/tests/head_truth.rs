//! The head case's rod truth converges in time and in space by the bench's own criterion: both
//! changes (substep halved; segments halved again) below the smallest error charted against it,
//! which on the head is the rod's own at the finest substep of the ladder.
//!
//! It did not (`head_truth_plateaued_when_the_round_rod_twist_followed_its_bending`): the rod's
//! quasistatic twist turned a round section's material frame onto whatever plane the strand
//! bent in, so the styled groom's rest curvature turned with it, and halving the substep moved
//! the truth by the same 2.4 mm from 256 to 4096 substeps per frame (quick size). A round
//! section now keeps its rest twist, and the truth runs on twice the groom's segments.
//!
//! The full-size check (64 strands, 24 frames; about 3 minutes):
//! `cargo test --release -p hairsys-cli --test bench_head_truth -- --ignored --nocapture`.

use hairsys_bench::cases;
use hairsys_bench::methods::{Method, Rod};
use hairsys_bench::metrics::rms_difference;
use hairsys_bench::{ladder, truth, REFERENCE_FACTOR};

fn check(quick: bool) {
    let case = cases::head_turn(quick).unwrap();
    let finest = *ladder(quick).last().unwrap();
    let truth = truth::truth(&case, finest * REFERENCE_FACTOR).unwrap();
    let c = &truth.convergence;
    let best = Rod { iterations: 8 }.run(&case, Some(finest)).unwrap();
    let smallest = rms_difference(&case, &best.samples, &truth.samples);
    println!(
        "head truth ({} strands): {} substeps, {}× segments; change with the substep halved \
         {:.2e} m, with the segments halved again {:.2e} m; rod at {finest} substeps {:.2e} m",
        case.sim.strands.len(),
        c.substeps,
        c.space_factor,
        c.time_change,
        c.space_change,
        smallest
    );
    assert_eq!(
        c.space_factor, 2,
        "the truth resolves the wisp on twice the segments"
    );
    assert!(
        c.time_change < 0.1 * smallest,
        "halving the truth's substep moved it {} m against {smallest} m",
        c.time_change
    );
    assert!(
        c.space_change < 0.6 * smallest,
        "halving its segments again moved it {} m against {smallest} m",
        c.space_change
    );
}

#[test]
fn head_truth_plateaued_when_the_round_rod_twist_followed_its_bending() {
    // Time convergence of the rod on the styled groom: at first order, not a plateau.
    let case = cases::head_turn(true).unwrap();
    let runs: Vec<_> = [256, 512, 1024]
        .iter()
        .map(|&n| Rod::REFERENCE.run(&case, Some(n)).unwrap().samples)
        .collect();
    let d1 = rms_difference(&case, &runs[0], &runs[1]);
    let d2 = rms_difference(&case, &runs[1], &runs[2]);
    println!("halving the substep: {d1:.2e} m, then {d2:.2e} m");
    assert!((1.6..2.6).contains(&(d1 / d2)), "{d1} then {d2}");
    assert!(d1 < 5e-4, "{d1}");
}

#[test]
fn head_truth_is_converged_in_time_and_space_at_quick_size() {
    check(true);
}

#[test]
#[ignore = "about 3 minutes in release; see the module docs"]
fn head_truth_is_converged_in_time_and_space_at_full_size() {
    check(false);
}
