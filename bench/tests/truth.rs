//! The bench's truths are right: the analytic ones are the limits the inextensible methods
//! converge to (the rigid pendulum, the catenary), the soft springs miss them by their stretch,
//! and the rod truth of the cantilever is converged in time and in space.

use hairsys_bench::analytic;
use hairsys_bench::cases;
use hairsys_bench::methods::{MassSpring, Method, Stretch};
use hairsys_bench::metrics::rms_difference;
use hairsys_bench::truth;

const INEXTENSIBLE: MassSpring = MassSpring {
    projection: true,
    stretch: Stretch::None,
    ..MassSpring::DEFAULT
};

#[test]
fn inextensible_pendulum_converges_to_the_rigid_pendulum_at_first_order() {
    let case = cases::pendulum().unwrap();
    let truth = truth::truth(&case, 0).unwrap();
    let errors: Vec<f64> = [64, 128, 256]
        .iter()
        .map(|&s| {
            let run = INEXTENSIBLE.run(&case, Some(s)).unwrap();
            rms_difference(&case, &run.samples, &truth.samples)
        })
        .collect();
    println!("projection, no springs, against the rigid pendulum: {errors:?} m");
    for w in errors.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (1.6..2.5).contains(&ratio),
            "halving dt: ratio {ratio} ({errors:?})"
        );
    }
    // The soft spring stretches under the swing: its error stalls at millimetres, however
    // fine the step.
    let soft: Vec<f64> = [64, 256]
        .iter()
        .map(|&s| {
            let run = MassSpring::DEFAULT.run(&case, Some(s)).unwrap();
            rms_difference(&case, &run.samples, &truth.samples)
        })
        .collect();
    println!("soft springs: {soft:?} m");
    assert!(soft[1] > 0.8 * soft[0], "soft error should stall: {soft:?}");
    assert!(soft[1] > 3.0 * errors[2], "{soft:?} against {errors:?}");
}

#[test]
fn released_chain_settles_on_its_catenary_and_soft_springs_sag_below_it() {
    let case = cases::hanging_chain().unwrap();
    let truth = truth::truth(&case, 0).unwrap();
    // The discrete catenary's sag is the continuous one's to within its 20 links.
    let lowest = truth.samples[0]
        .iter()
        .map(|p| -p.z as f64)
        .fold(0.0, f64::max);
    let sag = analytic::catenary_sag(1.0, 0.8);
    assert!((lowest - sag).abs() < 2e-3 * sag, "{lowest} against {sag}");
    let inextensible = INEXTENSIBLE.run(&case, Some(16)).unwrap();
    let e = rms_difference(&case, &inextensible.samples, &truth.samples);
    assert!(e < 1e-4, "inextensible chain {e} m from the catenary");
    let soft = MassSpring::DEFAULT.run(&case, Some(64)).unwrap();
    let e_soft = rms_difference(&case, &soft.samples, &truth.samples);
    let z_soft = soft.samples[0]
        .iter()
        .map(|p| -p.z as f64)
        .fold(0.0, f64::max);
    println!("inextensible {e:.2e} m, soft springs {e_soft:.2e} m (sag {z_soft} against {lowest})");
    assert!(e_soft > 1e-3, "soft springs {e_soft} m from the catenary");
    assert!(
        z_soft > lowest + 1e-3,
        "soft springs must sag more: {z_soft} against {lowest}"
    );
}

#[test]
fn rod_truth_of_the_cantilever_is_converged_in_time_and_space() {
    let case = cases::cantilever().unwrap();
    let truth = truth::truth(&case, 2048).unwrap();
    let c = &truth.convergence;
    println!("{c:?}");
    assert!(c.substeps >= 2048 && c.space_factor == 2);
    // 5 cm hair: a µm in time, a few hundredths of a percent of its length in space.
    assert!(
        c.time_change < 1e-6,
        "halving the substep moved it {} m",
        c.time_change
    );
    assert!(
        c.space_change < 1e-4,
        "halving the segments moved it {} m",
        c.space_change
    );
    // Both far below what the mass-spring model at its stable substeps misses it by.
    let run = MassSpring::DEFAULT.run(&case, Some(512)).unwrap();
    let e = rms_difference(&case, &run.samples, &truth.samples);
    assert!(e > 10.0 * c.space_change, "{e} against {}", c.space_change);
}
