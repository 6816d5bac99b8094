//! The curly and drape cases and the segments axis: the two rod truths are converged
//! in time and space (the Truths table's `converged`, at the quick bench's sizes), the drape
//! truth lies on its sphere without going into it, the curly case's curl kept is measured and
//! the rod keeps its curl, and on the segments axis the rod's error against the truth falls as
//! its segments double.

use hairsys::accuracy;
use hairsys_bench::cases::{self, Case};
use hairsys_bench::methods::{MassSpring, Method, Rod};
use hairsys_bench::segments;
use hairsys_bench::{bench_case, drape, ladder, Outcome, REFERENCE_FACTOR};

/// The quick bench's finest substep count, as `hairsys bench --quick` charts it.
fn quick_finest() -> u32 {
    *ladder(true).last().unwrap()
}

/// The rod methods and the default, at the quick bench's two finest substep counts: the truth
/// is computed as the bench computes it (at `REFERENCE_FACTOR` × the finest), and the runs set
/// the smallest error charted that `converged` is judged against.
fn truth_of(case: &Case) -> hairsys_bench::truth::Convergence {
    let mut methods = Rod::all();
    methods.push(Box::new(MassSpring::DEFAULT));
    let finest = quick_finest();
    let quiet = hairsys_bench::Silent;
    let (runs, truth) = bench_case(case, &methods, &[finest / 2, finest], &quiet).unwrap();
    let c = truth.convergence;
    println!("{}: {c:?}", case.name);
    assert!(c.substeps >= finest * REFERENCE_FACTOR);
    assert_eq!(c.space_factor, 2);
    for run in &runs {
        assert!(
            run.stable().is_some(),
            "{} on {} at {} substeps failed",
            run.method,
            case.name,
            run.substeps
        );
    }
    c
}

#[test]
fn curly_truth_is_converged_in_time() {
    let case = cases::curly().unwrap();
    let c = truth_of(&case);
    // Halving the step moves the 15 cm hair by tens of micrometres, far below any error charted.
    assert!(c.time_change < 2e-4, "{}", c.time_change);
    assert!(c.time_change < 0.1 * c.smallest_error, "{c:?}");
}

/// The rod's twist is elastic (`hair_core::model::rod::twist`): `G J` resists a coil trading its
/// pitch for torsion, so the curly truth has one answer, which finer segments approach. (With the
/// seed's geometric twist, which exerted no torque, 32 → 64 segments moved it 2.6 cm RMS.)
#[test]
fn curly_truth_is_converged_in_space() {
    let case = cases::curly().unwrap();
    let c = truth_of(&case);
    assert!(
        c.converged,
        "changes {} (time) and {} (space) m against the smallest error {} m",
        c.time_change, c.space_change, c.smallest_error
    );
}

#[test]
fn drape_truth_is_converged_and_lies_on_the_sphere_without_entering_it() {
    let case = cases::drape().unwrap();
    let c = truth_of(&case);
    assert!(
        c.converged,
        "changes {} (time) and {} (space) m against the smallest error {} m",
        c.time_change, c.space_change, c.smallest_error
    );
    // The rod's contacts keep node centres a hair radius (40 µm) off the surface: a centre
    // inside would be a failed contact. A micrometre is allowed for the projection's tolerance.
    assert!(
        c.penetration < 1e-6,
        "the truth went {} m into the sphere",
        c.penetration
    );
}

#[test]
fn drape_rests_on_the_sphere() {
    // At the end of the rod's run the hair wraps the sphere from near its root towards the
    // equator, nodes resting a hair radius off the surface, and hangs straight down from its
    // side below.
    let case = cases::drape().unwrap();
    let run = Rod::REFERENCE.run(&case, Some(256)).unwrap();
    let last = run.samples.last().unwrap();
    let r = drape::SPHERE_RADIUS as f32;
    let hair = hairsys_bench::physical::RADIUS as f32;
    let resting = last
        .iter()
        .filter(|p| p.z > 0.0 && (p.norm() - r - hair).abs() < 1e-5)
        .count();
    println!("final shape: {last:?}");
    assert!(
        resting >= 3,
        "{resting} nodes rest on the upper half-sphere"
    );
    let hanging: Vec<_> = last.iter().filter(|p| p.z < -0.05).collect();
    assert!(hanging.len() >= 6, "{} nodes hang below", hanging.len());
    for p in hanging {
        assert!(
            p.x > r && p.x < r + 0.01,
            "the hair hangs by the sphere's side: {p:?}"
        );
    }
}

#[test]
fn curly_curl_kept_is_measured_and_the_rod_keeps_the_curl() {
    let case = cases::curly().unwrap();
    let truth = hairsys_bench::truth::truth(&case, 512).unwrap();
    let rod = Rod { iterations: 8 };
    let run = rod.run(&case, Some(256)).unwrap();
    let e = hairsys_bench::metrics::errors(&case, &run, &truth);
    let kept = e
        .curl_kept
        .expect("the curly truth is curved: curl kept is computed");
    println!("rod, 8 iterations, 256 substeps: {e:?}");
    // The rod's bending holds the curvature of the coil (its pitch is what it gives away, see
    // `curly_truth_is_converged_in_space`): within 10 % of the truth's, and of the rest helix's.
    assert!(
        (kept - 1.0).abs() < 0.1,
        "the rod keeps {kept} of the truth's curl"
    );
    let offsets = case.sim.strands.offsets();
    let rest = accuracy::mean_curvature(&case.sim.strands.positions, offsets);
    let end = accuracy::mean_curvature(run.samples.last().unwrap(), offsets);
    assert!(
        (end / rest - 1.0).abs() < 0.1,
        "the rod keeps {} of its rest curl",
        end / rest
    );
    let spring = MassSpring::DEFAULT.run(&case, None).unwrap();
    let es = hairsys_bench::metrics::errors(&case, &spring, &truth);
    println!("default mass-spring at auto: {es:?}");
    assert!(es.curl_kept.is_some());
}

#[test]
fn rod_error_falls_as_its_segments_double() {
    // The spatial convergence of a model against the truth: the rod at its automatic substeps
    // at 4, 8 and 16 segments per strand (the truths are at 20 and 32).
    for case in [
        cases::cantilever().unwrap(),
        cases::curly().unwrap(),
        cases::drape().unwrap(),
    ] {
        let truth = hairsys_bench::truth::truth(&case, 512).unwrap();
        let methods: Vec<Box<dyn Method>> = vec![Box::new(Rod { iterations: 8 })];
        let quiet = hairsys_bench::Silent;
        let runs = segments::bench(&case, &truth, &methods, true, &quiet).unwrap();
        let errors: Vec<(usize, f64)> = runs
            .iter()
            .filter(|r| r.segments <= 16)
            .map(|r| match &r.outcome {
                Outcome::Stable { errors, .. } => (r.segments, errors.position_rms),
                Outcome::Unstable { message } => panic!("{} segments: {message}", r.segments),
            })
            .collect();
        println!("{}: rod error by segments {errors:?}", case.name);
        assert_eq!(errors.iter().map(|e| e.0).collect::<Vec<_>>(), [4, 8, 16]);
        for w in errors.windows(2) {
            assert!(
                w[1].1 < 0.7 * w[0].1,
                "{}: doubling the segments should cut the error: {errors:?}",
                case.name
            );
        }
    }
}
