//! How far a simulated groom is from a reference one, in measures a TD cares about:
//! no I/O, no solver, only positions of the same strands laid out the same way (strand `s`
//! owns points `offsets[s] .. offsets[s + 1]`, as in [`hair_core::StrandSet::offsets`]).
//!
//! - [`position_rms`]: RMS of `|x − x_ref|` over free points, m (the overall shape);
//! - [`tip_rms`]: RMS distance of the tips, m (the silhouette: where the ends of the hair are);
//! - [`length_error`]: largest `|L / L_rest − 1|` of any strand's total length (hair is nearly
//!   inextensible: a model that stretches shows it here);
//! - [`mean_curvature`] and [`curl_kept`]: the mean turning per unit length, `κ = φ / l̄` at each
//!   interior point (`φ` the angle between its two segments, `l̄` their mean length), and its
//!   ratio to the reference's (1 = the curl kept; below 1 the hair straightened);
//! - shape drift at rest is [`position_rms`] of a groom that should not move against its start;
//! - over a shot, [`shot_errors`]: the worst frame's position RMS, the RMS over every frame, and
//!   the worst frame's tip RMS.
//!
//! These are the one measure of accuracy: `hairsys plan` compares its candidates with them, the
//! bench (`hairsys-bench`) its methods against their truths, and the accuracy studies their
//! integrators against a converged reference. Penetration needs the collider's geometry and
//! stays with the caller (the bench's `Solid`).

use nalgebra::Vector3;

fn ranges(offsets: &[u32]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    offsets.windows(2).map(|w| w[0] as usize..w[1] as usize)
}

/// RMS distance between `a` and `b` over the points with `inverse_mass > 0`, m (0 if none).
pub fn position_rms(a: &[Vector3<f32>], b: &[Vector3<f32>], inverse_mass: &[f32]) -> f64 {
    let (mut sum, mut count) = (0.0f64, 0usize);
    for ((pa, pb), &w) in a.iter().zip(b).zip(inverse_mass) {
        if w > 0.0 {
            sum += (pa - pb).cast::<f64>().norm_squared();
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

/// RMS distance between the last points (tips) of each strand of `a` and `b`, m.
pub fn tip_rms(a: &[Vector3<f32>], b: &[Vector3<f32>], offsets: &[u32]) -> f64 {
    let (mut sum, mut count) = (0.0f64, 0usize);
    for r in ranges(offsets) {
        if let (Some(pa), Some(pb)) = (a.get(r.end.wrapping_sub(1)), b.get(r.end.wrapping_sub(1))) {
            sum += (pa - pb).cast::<f64>().norm_squared();
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

/// Largest `|L / L_rest − 1|` over strands, where `L` is the strand's polyline length in
/// `positions` and `L_rest` the sum of its `rest_lengths` (one per segment, strand-contiguous:
/// strand `s` owns `offsets[s] − s .. offsets[s + 1] − s − 1`).
pub fn length_error(positions: &[Vector3<f32>], offsets: &[u32], rest_lengths: &[f32]) -> f64 {
    let mut worst = 0.0f64;
    for (s, r) in ranges(offsets).enumerate() {
        let segs = r.start - s..r.end.saturating_sub(s + 1);
        let rest: f64 = rest_lengths
            .get(segs)
            .map_or(0.0, |l| l.iter().map(|&x| x as f64).sum());
        let now: f64 = positions[r]
            .windows(2)
            .map(|w| (w[1] - w[0]).cast::<f64>().norm())
            .sum();
        if rest > 0.0 {
            worst = worst.max((now / rest - 1.0).abs());
        }
    }
    worst
}

/// Mean discrete curvature over every interior point of every strand, 1/m: `φ / l̄`, `φ` the
/// angle between the point's two segments and `l̄` their mean length (0 for straight hair).
pub fn mean_curvature(positions: &[Vector3<f32>], offsets: &[u32]) -> f64 {
    let (mut sum, mut count) = (0.0f64, 0usize);
    for r in ranges(offsets) {
        for w in positions[r].windows(3) {
            let (a, b) = ((w[1] - w[0]).cast::<f64>(), (w[2] - w[1]).cast::<f64>());
            let (la, lb) = (a.norm(), b.norm());
            if la > 0.0 && lb > 0.0 {
                let phi = a.cross(&b).norm().atan2(a.dot(&b));
                sum += phi / (0.5 * (la + lb));
                count += 1;
            }
        }
    }
    sum / count.max(1) as f64
}

/// The curl kept: [`mean_curvature`] of `run` over that of `reference` (1 = the same; `None`
/// when the reference is straight, where the ratio says nothing).
pub fn curl_kept(run: &[Vector3<f32>], reference: &[Vector3<f32>], offsets: &[u32]) -> Option<f64> {
    let k_ref = mean_curvature(reference, offsets);
    (k_ref > 1e-9).then(|| mean_curvature(run, offsets) / k_ref)
}

/// A run's error against a reference over a shot (the same strands and frames), m.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
pub struct ShotErrors {
    /// Largest per-frame [`position_rms`], m: what a tolerance bounds.
    pub rms_max: f32,
    /// RMS distance over every frame and every free point, m.
    pub rms: f32,
    /// Largest per-frame [`tip_rms`], m.
    pub tip_max: f32,
}

/// [`ShotErrors`] of `run` against `reference`, frame by frame (the frames' points laid out as
/// `offsets` says, free where `inverse_mass > 0`).
pub fn shot_errors(
    run: &[Vec<Vector3<f32>>],
    reference: &[Vec<Vector3<f32>>],
    offsets: &[u32],
    inverse_mass: &[f32],
) -> ShotErrors {
    let mut out = ShotErrors::default();
    let mut sum_sq = 0.0f64;
    for (a, b) in run.iter().zip(reference) {
        let rms = position_rms(a, b, inverse_mass);
        sum_sq += rms * rms;
        out.rms_max = out.rms_max.max(rms as f32);
        out.tip_max = out.tip_max.max(tip_rms(a, b, offsets) as f32);
    }
    // Every frame has the same free points, so the RMS over all is the RMS of the frames'.
    out.rms = (sum_sq / run.len().max(1) as f64).sqrt() as f32;
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32) -> Vector3<f32> {
        Vector3::new(x, y, z)
    }

    /// A strand of `n` segments on a circle of radius `r` (m), in the xy plane.
    fn arc(n: usize, r: f32, turn: f32) -> Vec<Vector3<f32>> {
        (0..=n)
            .map(|i| {
                let a = turn * i as f32 / n as f32;
                v(r * a.sin(), r * (1.0 - a.cos()), 0.0)
            })
            .collect()
    }

    #[test]
    fn mean_curvature_of_a_sampled_circle_is_one_over_its_radius() {
        let p = arc(64, 0.02, 3.0);
        let k = mean_curvature(&p, &[0, 65]);
        assert!((k * 0.02 - 1.0).abs() < 1e-3, "{k}");
        let straight: Vec<_> = (0..5).map(|i| v(0.0, 0.0, i as f32)).collect();
        assert_eq!(mean_curvature(&straight, &[0, 5]), 0.0);
        assert_eq!(curl_kept(&straight, &straight, &[0, 5]), None);
    }

    #[test]
    fn straightened_curl_keeps_less_than_one() {
        let curly = arc(32, 0.01, 4.0);
        let looser = arc(32, 0.02, 2.0);
        let kept = curl_kept(&looser, &curly, &[0, 33]).unwrap();
        assert!((kept - 0.5).abs() < 1e-3, "{kept}");
    }

    #[test]
    fn length_error_of_a_uniformly_stretched_strand_is_its_strain() {
        let rest = [0.1f32; 4];
        let p: Vec<_> = (0..5).map(|i| v(0.101 * i as f32, 0.0, 0.0)).collect();
        let e = length_error(&p, &[0, 5], &rest);
        assert!((e - 0.01).abs() < 1e-6, "{e}");
        // Two strands: the second one compressed by 2 % is the worst.
        let mut two = p.clone();
        two.extend((0..3).map(|i| v(0.098 * i as f32, 1.0, 0.0)));
        let e = length_error(&two, &[0, 5, 8], &[0.1; 6]);
        assert!((e - 0.02).abs() < 1e-6, "{e}");
    }

    #[test]
    fn rms_measures_skip_pinned_points_and_use_tips() {
        let a = vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0)];
        let b = vec![v(5.0, 0.0, 0.0), v(1.0, 3.0, 0.0), v(2.0, 4.0, 0.0)];
        let rms = position_rms(&a, &b, &[0.0, 1.0, 1.0]);
        assert!((rms - 12.5f64.sqrt()).abs() < 1e-12);
        assert!((tip_rms(&a, &b, &[0, 3]) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn shot_errors_take_the_worst_frame_and_the_rms_of_all() {
        let rest = vec![v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0)];
        let off = |d: f32| vec![v(0.0, 0.0, 0.0), v(1.0, d, 0.0)];
        let e = shot_errors(
            &[off(3.0), off(4.0)],
            &[rest.clone(), rest],
            &[0, 2],
            &[0.0, 1.0],
        );
        assert_eq!((e.rms_max, e.tip_max), (4.0, 4.0));
        assert!((e.rms - 12.5f32.sqrt()).abs() < 1e-6, "{}", e.rms);
    }
}
