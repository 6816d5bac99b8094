//! Hair levels (seed 001, "Hair Levels"): render hairs interpolated from fewer simulated hairs.
//!
//! Of a group of strands that were all simulated, a fraction is kept as *sim hairs* (chosen by
//! farthest-point sampling of the roots, so they cover the group evenly) and every other strand
//! becomes a *render hair*: its own rest shape, placed by its root frame, plus the blended
//! displacement of its `k` nearest sim hairs from their own posed rest shapes,
//!
//! `x_c(j) = F_c(r_c(j)) + Σ w_p (x_p(j) − F_p(r_p(j)))`,
//!
//! sampled at the same fractions of the rest length (`F` a root frame, `r` a rest shape in root
//! coordinates). The render hair keeps its groom and takes its motion from the simulation, the
//! seed's split of rest shape and deformation. Weights are Franke–Little inverse-distance
//! weights over the root distances, `w ∝ ((R − d)/(R d))²` with `R` the distance to the
//! `(k + 1)`-th nearest sim hair (or `2 d_k`), as `hair_render`'s interpolated children use
//! (Franke & Nielson 1980). Comparing the result with the run in which every strand was simulated
//! gives the error of simulating only that fraction.

use nalgebra::Vector3;

use crate::plan::trace::Trace;

/// Sim hairs blended per render hair.
pub const NEIGHBOURS: usize = 4;

/// `count` of the strands `among`, spread by farthest-point sampling of `roots` (the first is
/// `among[0]`); all of them when `count ≥ among.len()`.
pub fn farthest_points(roots: &[Vector3<f32>], among: &[usize], count: usize) -> Vec<usize> {
    if count >= among.len() {
        return among.to_vec();
    }
    let mut chosen = Vec::with_capacity(count);
    let mut nearest = vec![f32::INFINITY; among.len()];
    let mut next = 0;
    while chosen.len() < count {
        let c = among[next];
        chosen.push(c);
        let mut best = (0, -1.0f32);
        for (i, &s) in among.iter().enumerate() {
            let d = (roots[s] - roots[c]).norm_squared();
            nearest[i] = nearest[i].min(d);
            if nearest[i] > best.1 {
                best = (i, nearest[i]);
            }
        }
        next = best.0;
    }
    chosen
}

/// The frames of `trace` with all but `keep` of the strands of each group replaced by render
/// hairs interpolated from the kept ones of the same group (see the module docs). `keep(n)`
/// gives how many of a group of `n` strands stay simulated (at least 1).
pub fn interpolate(
    trace: &Trace,
    frames: &[Vec<Vector3<f32>>],
    groups: &[Vec<usize>],
    keep: impl Fn(usize) -> usize,
) -> Vec<Vec<Vector3<f32>>> {
    let n = trace.points_per_strand;
    let mut out = frames.to_vec();
    for group in groups {
        let kept = farthest_points(&trace.roots, group, keep(group.len()).max(1));
        let mut is_kept = vec![false; trace.strands];
        for &s in &kept {
            is_kept[s] = true;
        }
        for &c in group.iter().filter(|&&s| !is_kept[s]) {
            let shares = weights(&trace.roots, &kept, c);
            for (f, frame) in out.iter_mut().enumerate() {
                for j in 0..n {
                    let mut x = trace.posed_rest(f, c, j);
                    for &(p, w) in &shares {
                        x += (frames[f][p * n + j] - trace.posed_rest(f, p, j)) * w;
                    }
                    frame[c * n + j] = x;
                }
            }
        }
    }
    out
}

/// Render hairs with the rest shapes, roots and root frames of `render` (every frame of it),
/// each interpolated from all the strands of `sims` (a run of other, usually fewer, strands of
/// the same scalp over the same frames; see the module docs). A render hair rooted on a sim hair
/// takes that hair's motion alone.
pub fn render_from(sims: &Trace, render: &Trace) -> Vec<Vec<Vector3<f32>>> {
    assert_eq!(sims.frames.len(), render.frames.len(), "the same frames");
    assert_eq!(
        sims.points_per_strand, render.points_per_strand,
        "the same samples"
    );
    let n = render.points_per_strand;
    let all: Vec<usize> = (0..sims.strands).collect();
    let mut out = vec![Vec::with_capacity(render.strands * n); render.frames.len()];
    for c in 0..render.strands {
        let shares = weights_at(&sims.roots, &all, render.roots[c]);
        for (f, frame) in out.iter_mut().enumerate() {
            for j in 0..n {
                let mut x = render.posed_rest(f, c, j);
                for &(p, w) in &shares {
                    x += (sims.frames[f][p * n + j] - sims.posed_rest(f, p, j)) * w;
                }
                frame.push(x);
            }
        }
    }
    out
}

/// The sim hairs a render hair rooted at `roots[c]` blends and their weights (summing to 1).
fn weights(roots: &[Vector3<f32>], kept: &[usize], c: usize) -> Vec<(usize, f32)> {
    weights_at(roots, kept, roots[c])
}

/// [`weights`] for a render hair rooted at `root`.
fn weights_at(roots: &[Vector3<f32>], kept: &[usize], root: Vector3<f32>) -> Vec<(usize, f32)> {
    let mut by_distance: Vec<(f32, usize)> = kept
        .iter()
        .map(|&p| ((roots[p] - root).norm(), p))
        .collect();
    by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
    if by_distance[0].0 < 1e-6 {
        return vec![(by_distance[0].1, 1.0)];
    }
    let k = NEIGHBOURS.min(by_distance.len());
    let radius = by_distance
        .get(k)
        .map_or(2.0 * by_distance[k - 1].0, |d| d.0)
        .max(by_distance[k - 1].0 * (1.0 + 1e-4));
    let mut shares: Vec<(usize, f32)> = by_distance[..k]
        .iter()
        .map(|&(d, p)| (p, ((radius - d) / (radius * d)).powi(2)))
        .collect();
    let total: f32 = shares.iter().map(|s| s.1).sum();
    for s in &mut shares {
        s.1 /= total;
    }
    shares
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn farthest_points_spread_over_a_line() {
        let roots: Vec<_> = (0..11).map(|i| Vector3::new(i as f32, 0.0, 0.0)).collect();
        let all: Vec<usize> = (0..11).collect();
        let mut chosen = farthest_points(&roots, &all, 3);
        chosen.sort();
        assert_eq!(chosen, vec![0, 5, 10]);
    }

    #[test]
    fn weights_sum_to_one_and_favour_the_nearest() {
        let roots: Vec<_> = (0..6).map(|i| Vector3::new(i as f32, 0.0, 0.0)).collect();
        let w = weights(&roots, &[0, 2, 3, 4, 5], 1);
        let total: f32 = w.iter().map(|s| s.1).sum();
        assert!((total - 1.0).abs() < 1e-6);
        let near: f32 = w.iter().filter(|s| s.0 == 0 || s.0 == 2).map(|s| s.1).sum();
        assert!(
            near > 0.9,
            "the two sim hairs 1 m away carry the blend: {w:?}"
        );
        // The (k+1)-th nearest, at the radius, gets no weight.
        assert!(w.iter().all(|s| s.0 != 5));
    }
}
