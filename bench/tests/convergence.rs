//! The bench's cases converge in time as they should: semi-implicit Euler's position error
//! against its own very fine run is first order in the substep (halving dt roughly halves the
//! error), and the inextensibility projection keeps every segment within 0.1 % of its rest
//! length through the fast head turn. (The hanging chain is compared only once settled, where
//! no time error is left to measure, and `bench_truth` checks it against its catenary; on the
//! 5 cm hair cantilever the method's time error at its stable substeps, 256 and more, is below
//! the f32 round-off of a 48-frame run: its error against its own run at 16× the substeps stays
//! at 2 × 10⁻⁵ m from 512 to 4096 substeps.)

use hairsys_bench::cases::{self, Case};
use hairsys_bench::methods::{MassSpring, Method, Stretch};
use hairsys_bench::metrics::rms_difference;

/// Least-squares slope of log(error) against log(dt).
fn fitted_order(dts: &[f64], errors: &[f64]) -> f64 {
    let x: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx).powi(2)).sum();
    sxy / sxx
}

/// Errors of the default method at `ladder` substeps per frame against a run at `reference`.
fn errors(case: &Case, ladder: &[u32], reference: u32) -> Vec<f64> {
    let m = MassSpring::DEFAULT;
    let fine = m.run(case, Some(reference)).unwrap();
    ladder
        .iter()
        .map(|&s| rms_difference(case, &m.run(case, Some(s)).unwrap().samples, &fine.samples))
        .collect()
}

fn check_first_order(case: Case, ladder: &[u32]) {
    let reference = ladder.last().unwrap() * 16;
    let e = errors(&case, ladder, reference);
    let dts: Vec<f64> = ladder.iter().map(|&s| 1.0 / s as f64).collect();
    let order = fitted_order(&dts, &e);
    let shown: Vec<String> = e.iter().map(|x| format!("{x:.2e}")).collect();
    println!(
        "{}: substeps {ladder:?}, errors (m) {shown:?}, order {order:.2}",
        case.name
    );
    for w in e.windows(2) {
        assert!(w[1] < w[0], "{}: error does not fall: {e:?}", case.name);
    }
    assert!(
        (0.7..=1.4).contains(&order),
        "{}: fitted order {order:.2} outside 0.7–1.4 (errors {e:?})",
        case.name
    );
}

#[test]
fn pendulum_error_is_first_order_in_dt() {
    check_first_order(cases::pendulum().unwrap(), &[16, 32, 64, 128]);
}

#[test]
fn head_turn_error_is_first_order_in_dt() {
    check_first_order(cases::head_turn(true).unwrap(), &[128, 256, 512]);
}

#[test]
fn projection_keeps_stretch_below_a_tenth_of_a_percent_in_the_fast_head_turn() {
    let case = cases::head_turn(true).unwrap();
    let springs_only = MassSpring::DEFAULT.run(&case, None).unwrap();
    for stretch in [Stretch::Soft, Stretch::None] {
        let m = MassSpring {
            projection: true,
            stretch,
            ..MassSpring::DEFAULT
        };
        let trace = m.run(&case, None).unwrap();
        println!(
            "{}: max stretch {:.4} % (springs alone {:.3} %)",
            m.name(),
            100.0 * trace.max_stretch,
            100.0 * springs_only.max_stretch
        );
        assert!(
            trace.max_stretch < 1e-3,
            "{}: {}",
            m.name(),
            trace.max_stretch
        );
    }
}
