//! Velocity–position mismatch between two frames: do the stored velocities describe the motion
//! the positions show?
//!
//! For each point, `|(x₁ − x₀)/Δt − (v₀ + v₁)/2|` (m/s): the mean velocity the positions imply
//! against the trapezoidal mean of the stored ones. It is exactly 0 for motion of constant
//! acceleration (the trapezoid rule integrates a linear velocity exactly), `Δt²/12 |x⁽³⁾|` for
//! smooth motion, and it reads any velocity the solver stores but the point did not move with
//! (a stale or missing correction) directly: a stored velocity off by `δ` at both frames gives
//! `δ`. Cubic Hermite sampling between the frames (how `hair-cache` samples sub-frames) then
//! leaves the path by up to about `0.1 Δt δ` (the largest value of the Hermite tangent basis
//! `h₁₀ + h₁₁ = s(1 − s)(1 − 2s)` on [0, 1] is 0.096).

use nalgebra::Vector3;

use super::distribution::Distribution;

/// Mismatch of every point between the previous frame (`x0`, `v0`) and this one (`x1`, `v1`),
/// `dt` s apart.
pub(crate) fn mismatch(
    x0: &[Vector3<f32>],
    v0: &[Vector3<f32>],
    x1: &[Vector3<f32>],
    v1: &[Vector3<f32>],
    dt: f32,
) -> Distribution {
    let mut out = Distribution::new();
    let inv_dt = 1.0 / dt;
    for (((a, va), b), vb) in x0.iter().zip(v0).zip(x1).zip(v1) {
        let implied = (b - a) * inv_dt;
        out.add((implied - (va + vb) * 0.5).norm());
    }
    out
}
