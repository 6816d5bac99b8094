//! Per-strand physical parameters (per-region physics): `MassSpringSolver::with_strand_scales`.
//!
//! Twelve identical horizontal cantilevers (a SIMD group of eight and one of four) sag under
//! gravity; strands 2 and 9 — one in each group, so a lane of a group carries a different
//! strand's parameters than its neighbours — get four times the bending stiffness. The
//! reference is the statics of `bending_cantilever.rs`: at these slight deflections (~2 % of
//! the length) the tip sag is `Σ_j l sin φ_j` with joint turns `θ_j = M_j / (k_b l²)`, so it
//! scales as `1/k_b` to first order: the stiff strands sag a quarter as far (to within the
//! neglected `θ²` terms, ~10⁻³ here).
//!
//! What is asserted, for every strand integrator (semi-implicit Euler, implicit Euler, XPBD):
//! - unit scales give the unscaled run bit for bit (what a scene without regions runs);
//! - with a fixed substep, the strands outside the region move bit for bit as in the run
//!   without it, and the region's strands differ and sag less, by the beam's ratio of 1/4
//!   within 2 %;
//! - `substeps = "auto"` and the stability bound take the stiffest strand.

mod common;

use common::*;
use hair_core::{
    HairParams, Integrator, MassSpringSolver, Scalp, SolverSettings, StabilityBound, StrandScales,
    StrandSet, Substeps,
};
use nalgebra::Vector3;

const STRANDS: usize = 12;
const SEGMENTS: usize = 20;
const SEG_LEN: f32 = 0.01;
/// The strands of the stiff region (one per SIMD group).
const REGION: [usize; 2] = [2, 9];

/// Twelve horizontal cantilevers 1 cm apart along y, 20 segments of 1 cm, 0.01 kg/m.
fn cantilevers() -> (StrandSet, Scalp) {
    let scalp = Scalp::fixed();
    let point_mass = 0.01 * SEG_LEN;
    let mut mass = vec![point_mass; SEGMENTS + 1];
    mass[SEGMENTS] *= 0.5;
    let inputs = (0..STRANDS).map(|s| {
        strand(
            anchor_along(Vector3::new(0.0, 0.01 * s as f32, 0.1), Vector3::x()),
            straight(SEGMENTS, SEG_LEN, Vector3::z()),
            mass.clone(),
            root_only(SEGMENTS + 1),
        )
    });
    (set_on(&scalp, inputs), scalp)
}

fn params() -> HairParams {
    let mut p = bare_params(100.0);
    p.bend_stiffness = 5000.0;
    p.gravity = gravity();
    p.air_drag = 20.0;
    p.stretch_damping = 50.0;
    p
}

/// Four times the bending stiffness on the region's strands, the scene's material elsewhere.
fn stiff_region() -> Vec<StrandScales> {
    (0..STRANDS)
        .map(|s| StrandScales {
            bend: if REGION.contains(&s) { 4.0 } else { 1.0 },
            ..StrandScales::ONE
        })
        .collect()
}

/// Positions (as bits) after 2 s with `scales` (None: no scales given).
fn run_with(settings: SolverSettings, scales: Option<Vec<StrandScales>>) -> (Vec<[u32; 3]>, u32) {
    let (mut strands, scalp) = cantilevers();
    let mut solver = MassSpringSolver::new(settings, params(), &strands, &scalp, 0).unwrap();
    if let Some(scales) = scales {
        solver = solver.with_strand_scales(scales, &strands).unwrap();
    }
    run(&mut solver, &mut strands, &scalp, 48, |_, _| {}).unwrap();
    let bits = strands
        .positions
        .iter()
        .map(|p| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()])
        .collect();
    (bits, solver.substeps())
}

fn tip_sag(bits: &[[u32; 3]], s: usize) -> f64 {
    let tip = bits[s * (SEGMENTS + 1) + SEGMENTS];
    0.1 - f32::from_bits(tip[2]) as f64
}

/// The substeps per frame that keep the stiff region stable (its bound, with margin).
fn stable_substeps() -> u32 {
    let (strands, _) = cantilevers();
    StabilityBound::of_scaled(&strands, &params(), &stiff_region()).auto_substeps(1.0 / 24.0)
}

/// Checks `integrator` (module docs), the beam's 1/4 sag ratio within 2 % included.
fn check_integrator(integrator: Integrator, name: &str) {
    // Unit scales: the unscaled run, bit for bit (auto substeps resolve the same).
    let auto = SolverSettings {
        integrator,
        ..SolverSettings::default()
    };
    let (plain, n_plain) = run_with(auto, None);
    let (unit, n_unit) = run_with(auto, Some(vec![StrandScales::ONE; STRANDS]));
    assert_eq!(n_plain, n_unit, "{name}: unit scales changed the substeps");
    assert!(plain == unit, "{name}: unit scales changed the bits");

    // A stiff region at a fixed substep changes only its own strands (the explicit kernel at
    // the stiff region's bound; implicit Euler, BDF2 and XPBD have none, and run 24 per frame).
    let substeps = match integrator {
        Integrator::SemiImplicitEuler | Integrator::ExplicitEuler => stable_substeps(),
        Integrator::ImplicitEuler | Integrator::Bdf2 | Integrator::Xpbd => 24,
    };
    let fixed = fixed_settings(24.0, substeps, integrator);
    let (without, _) = run_with(fixed, None);
    let (with, _) = run_with(fixed, Some(stiff_region()));
    for s in 0..STRANDS {
        let points = s * (SEGMENTS + 1)..(s + 1) * (SEGMENTS + 1);
        let same = without[points.clone()] == with[points];
        if REGION.contains(&s) {
            assert!(!same, "{name}: region strand {s} did not change");
        } else {
            assert!(same, "{name}: strand {s} outside the region changed");
        }
    }
    for &s in &REGION {
        let (soft, stiff) = (tip_sag(&without, s), tip_sag(&with, s));
        println!(
            "{name}: strand {s} tip sag {soft:.4e} m at k_b, {stiff:.4e} m at 4 k_b (ratio {:.4})",
            stiff / soft
        );
        assert!(
            stiff > 0.0 && stiff < soft,
            "{name}: the stiff region does not sag less ({stiff} m against {soft} m)"
        );
        let ratio = stiff / soft;
        assert!(
            (ratio - 0.25).abs() < 0.02 * 0.25,
            "{name}: strand {s} sag ratio {ratio:.4} at 4× bending stiffness, beam statics 0.25"
        );
    }
}

#[test]
fn region_stiffness_changes_only_that_region_semi_implicit() {
    check_integrator(Integrator::SemiImplicitEuler, "semi-implicit Euler");
}

#[test]
fn region_stiffness_changes_only_that_region_implicit_euler() {
    check_integrator(Integrator::ImplicitEuler, "implicit Euler");
}

#[test]
fn region_stiffness_changes_only_that_region_bdf2() {
    check_integrator(Integrator::Bdf2, "BDF2");
}

#[test]
fn region_stiffness_changes_only_that_region_xpbd() {
    check_integrator(Integrator::Xpbd, "XPBD");
}

#[test]
fn auto_substeps_follow_the_stiffest_region() {
    let (strands, scalp) = cantilevers();
    let p = params();
    let plain = StabilityBound::of(&strands, &p);
    // Stretch ×10 on one strand only: the bound is that strand's.
    let mut scales = vec![StrandScales::ONE; STRANDS];
    scales[5].stretch = 10.0;
    let scaled = StabilityBound::of_scaled(&strands, &p, &scales);
    let expected = plain.stiffness + 9.0 * p.stretch_stiffness as f64;
    assert!(
        (scaled.stiffness - expected).abs() < 1e-9 * expected,
        "bound stiffness {} N/m, expected {expected} N/m",
        scaled.stiffness
    );
    assert!(scaled.dt_max < plain.dt_max);
    // Softer everywhere: the bound is the softest material's, not the scene's.
    let soft = vec![
        StrandScales {
            stretch: 0.5,
            bend: 0.5,
            ..StrandScales::ONE
        };
        STRANDS
    ];
    let softer = StabilityBound::of_scaled(&strands, &p, &soft);
    assert!((softer.stiffness - 0.5 * plain.stiffness).abs() < 1e-9 * plain.stiffness);

    let settings = SolverSettings {
        substeps: Substeps::Auto,
        ..SolverSettings::default()
    };
    let solver = MassSpringSolver::new(settings, p, &strands, &scalp, 0).unwrap();
    let before = solver.substeps();
    let solver = solver.with_strand_scales(scales, &strands).unwrap();
    assert_eq!(
        solver.substeps(),
        scaled.auto_substeps(settings.step_dt()),
        "auto substeps not resolved from the scaled bound"
    );
    assert!(solver.substeps() > before);
    assert_eq!(solver.bound(), scaled);
}

#[test]
fn bad_strand_scales_are_refused_by_strand_and_factor() {
    let (strands, scalp) = cantilevers();
    let solver =
        || MassSpringSolver::new(SolverSettings::default(), params(), &strands, &scalp, 0).unwrap();
    let e = solver()
        .with_strand_scales(vec![StrandScales::ONE; 3], &strands)
        .unwrap_err()
        .to_string();
    assert!(e.contains("strand_scales") && e.contains("12"), "{e}");
    let mut scales = vec![StrandScales::ONE; STRANDS];
    scales[7].bend = f32::NAN;
    let e = solver()
        .with_strand_scales(scales.clone(), &strands)
        .unwrap_err()
        .to_string();
    assert!(e.contains("strand_scales[7].bend"), "{e}");
    scales[7].bend = 1.0;
    scales[4].stretch = 0.0;
    let e = solver()
        .with_strand_scales(scales, &strands)
        .unwrap_err()
        .to_string();
    assert!(e.contains("strand_scales[4].stretch"), "{e}");
}
