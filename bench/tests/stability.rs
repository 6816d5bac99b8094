//! The bench's stability map against the predicted bound `dt < 2/ω`: semi-implicit Euler's
//! observed boundary lies within ×1.5 of the prediction (with and without the damping
//! sub-loop), and explicit Euler fails at substeps inside it.

use hair_core::Integrator;
use hairsys_bench::methods::{MassSpring, Method};
use hairsys_bench::stability::{map, Grid};

fn grid() -> Grid {
    Grid {
        stiffness: vec![10.0, 1000.0],
        substeps: (0..=11).map(|e| 1 << e).collect(),
        frames: 12,
    }
}

#[test]
fn semi_implicit_euler_boundary_is_within_one_and_a_half_of_the_prediction() {
    let grid = grid();
    for damping in [true, false] {
        let m = MassSpring {
            damping,
            ..MassSpring::DEFAULT
        };
        let result = map(&m, &grid, || {}).unwrap();
        for (row, &k) in grid.stiffness.iter().enumerate() {
            let predicted = result.predicted_dt[row];
            let observed = result.observed_dt[row].expect("some substep is stable");
            let ratio = observed / predicted;
            println!("{}: k {k} N/m, observed / predicted {ratio:.3}", m.name());
            assert!(
                (1.0 / 1.5..=1.5).contains(&ratio),
                "{}: k = {k} N/m, observed boundary {observed:.3e} s vs predicted {predicted:.3e} s",
                m.name()
            );
        }
    }
}

#[test]
fn explicit_euler_diverges_inside_the_predicted_bound() {
    let grid = grid();
    let m = MassSpring {
        integrator: Integrator::ExplicitEuler,
        ..MassSpring::DEFAULT
    };
    let result = map(&m, &grid, || {}).unwrap();
    assert_eq!(
        result.fails_inside_bound(&grid),
        grid.stiffness,
        "explicit Euler should fail inside the bound at every stiffness: {:?}",
        result.stable
    );
    // Semi-implicit Euler does not, on the same grid.
    let semi = map(&MassSpring::DEFAULT, &grid, || {}).unwrap();
    assert!(semi.fails_inside_bound(&grid).is_empty());
}
