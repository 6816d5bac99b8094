//! Quasistatic twist (seed 002, "Twist formulation" and "Hair twisting"; Kmoch, Bonanni and
//! Magnenat-Thalmann 2009).
//!
//! Twist is not part of the dynamics: it propagates instantly, so before every substep the twist
//! angles are recomputed from the centreline, root to tip. A hair with an elliptical
//! cross-section only bends over its major axis: ideally each segment's major axis `m1` lies
//! along the bending axis (the curvature binormal) of both its nodes, so that nothing bends over
//! the minor axis. The two nodes generally disagree, so the twist minimises the minor-axis
//! bending of the segment instead, which is directly computable: with `(p, q)` the components of
//! a node's binormal in the segment's reference frame `(u, v)` and `η = atan2(q, p)`,
//!
//! ```text
//! Σ_nodes (κb·m2)² / l̄ = Σ |κb|² sin²(η − θ) / l̄   is least at   2θ = arg Σ (p + i q)² / l̄
//! ```
//!
//! (both nodes bent: the weighted mean axis; one bent: its `η`; neither bent: the previous
//! segment's twist plus the rest twist, i.e. no twisting). The major axis is an axis, not a
//! direction: `θ`, `θ + π` and `θ − π` all align it, and they differ in elastic energy once the
//! rest shape is curved (its curl has a sense) and in twist from the previous segment. Of these
//! candidates the one with the least elastic energy (twist against the previous segment plus the
//! segment's share of bending at both its nodes) is taken, and the sweep moves on to the next
//! segment.
//!
//! A round section (`rod.axis_ratio = 1`) has no major axis: its twist stays at the rest twist.
//!
//! Limit: the twist energy only chooses between candidates; it does not resist a turn of the
//! major axis along the strand, as the seed's model intends (hair twists freely to bend over
//! its major axis).

use super::forces::{side_energy, NodeRest};
use super::frames::{material, EdgeFrames, V3};
use super::stiffness::Stiffness;

/// Bending below this angle (rad) at both nodes of a segment counts as straight: its binormals
/// give no reliable axis (single-precision positions carry about 1e-5 rad of noise).
const STRAIGHT: f64 = 1e-4;

/// Rest data the twist needs per segment and node.
#[derive(Debug, Clone, Copy)]
pub struct TwistRest<'a> {
    /// Rest curvature per bending node (`0..segments`).
    pub bend: &'a [NodeRest],
    /// Rest twist `θ̄_j − θ̄_{j−1}` per segment, rad (`θ̄_{−1} = 0`: the ghost).
    pub twist: &'a [f64],
    /// Share of the rest length per bending node `l̄_i`, m.
    pub voronoi: &'a [f64],
}

/// The twist of every segment: its angle and the material axes it gives.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Twist {
    /// Twist angle per segment, rad, against its reference frame.
    pub theta: Vec<f64>,
    /// Material axes `(m1, m2)` per segment (major, minor).
    pub axes: Vec<(V3, V3)>,
}

/// Computes the twist of every segment for the frames of the current centreline, root to tip,
/// into `out`.
pub fn quasistatic(frames: &EdgeFrames, rest: &TwistRest, stiffness: &Stiffness, out: &mut Twist) {
    let n = frames.t.len();
    out.theta.clear();
    out.axes.clear();
    let pi = std::f64::consts::PI;
    // A round section has no major axis to align: its bending energy does not depend on the
    // twist but through the rest curvature, which is fixed in the material frame. Aligning an
    // axis with the current bending plane would turn a curved rest shape's curvature towards
    // whatever plane the strand happens to bend in, and at a node that straightens or reverses
    // that plane is set by round-off: the rest shape would jump by a step-dependent amount. A
    // round strand therefore keeps its rest twist (no twisting).
    let round = stiffness.major == stiffness.minor;
    let mut prev = 0.0;
    for j in 0..n {
        let reference = prev + rest.twist[j];
        let (u, v) = (&frames.u[j], &frames.v[j]);
        if round {
            out.theta.push(reference);
            out.axes.push(material(u, v, reference));
            prev = reference;
            continue;
        }
        // Nodes of segment j: j (side b) and j + 1 (side a), if it bends.
        let nodes = [(j, true), (j + 1, false)];
        let (mut re, mut im, mut weight) = (0.0, 0.0, 0.0);
        for &(i, _) in nodes.iter().filter(|(i, _)| *i < n) {
            let kb = frames.kb[i];
            let (p, q) = (kb.dot(u), kb.dot(v));
            let w = 1.0 / rest.voronoi[i];
            re += w * (p * p - q * q);
            im += w * 2.0 * p * q;
            weight += w;
        }
        let straight = STRAIGHT * STRAIGHT * weight;
        let ideal = if re * re + im * im > straight * straight {
            let a = 0.5 * im.atan2(re);
            // The axis is defined mod π: take its representative nearest the reference.
            a + pi * ((reference - a) / pi).round()
        } else {
            reference
        };
        // θ and θ ± π share the axis: the latter two flip both material axes.
        let (m1, m2) = material(u, v, ideal);
        let bend = |m1: &V3, m2: &V3| {
            let mut e = 0.0;
            for &(i, own_is_b) in nodes.iter().filter(|(i, _)| *i < n) {
                let r = if own_is_b {
                    rest.bend[i].b
                } else {
                    rest.bend[i].a
                };
                e += side_energy(&frames.kb[i], m1, m2, r, rest.voronoi[i], stiffness);
                if i == 0 {
                    // Node 0 is measured in segment 0's frame on both sides.
                    let a = rest.bend[0].a;
                    e += side_energy(&frames.kb[0], m1, m2, a, rest.voronoi[0], stiffness);
                }
            }
            e
        };
        let twist = |th: f64| stiffness.twist * (th - reference).powi(2) / (2.0 * rest.voronoi[j]);
        let (same, flipped) = (bend(&m1, &m2), bend(&-m1, &-m2));
        let mut best = (ideal, same + twist(ideal), (m1, m2));
        for candidate in [ideal + pi, ideal - pi] {
            let e = flipped + twist(candidate);
            if e < best.1 {
                best = (candidate, e, (-m1, -m2));
            }
        }
        out.theta.push(best.0);
        out.axes.push(best.2);
        prev = best.0;
    }
}

/// Twist energy (J) of `theta` against the rest twist: `Σ G J (θ_j − θ_{j−1} − θ̄'_j)² / (2 l̄_j)`.
pub fn energy(theta: &[f64], rest: &TwistRest, stiffness: &Stiffness) -> f64 {
    let mut prev = 0.0;
    let mut e = 0.0;
    for (j, &th) in theta.iter().enumerate() {
        e += stiffness.twist * (th - prev - rest.twist[j]).powi(2) / (2.0 * rest.voronoi[j]);
        prev = th;
    }
    e
}

/// Largest bending over the minor axis relative to the bending over the major axis, over the
/// interior nodes `1..segments`: `max |κb·m2| / max |κb|` on both sides of each node (0 for a
/// straight strand). Near 0 when every segment bends over its major axis.
pub fn minor_axis_bending(frames: &EdgeFrames, twist: &Twist) -> f64 {
    let n = frames.t.len();
    let (mut minor, mut total) = (0.0f64, 0.0f64);
    for i in 1..n {
        let kb: V3 = frames.kb[i];
        for j in [i - 1, i] {
            minor = minor.max(kb.dot(&twist.axes[j].1).abs());
        }
        total = total.max(kb.norm());
    }
    if total > 0.0 {
        minor / total
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::frames::Ghost;
    use super::*;

    #[test]
    fn round_section_keeps_its_rest_twist_however_it_bends() {
        // A round strand curled in the x–y plane at rest (rest curvature about z), bent now in
        // the x–z plane: aligning an axis with the new bending plane would turn the rest curl
        // with it. Its twist must stay at the accumulated rest twist.
        let x: Vec<V3> = (0..8)
            .map(|i| {
                let a = 0.2 * i as f64;
                V3::new(a.sin(), 0.0, 1.0 - a.cos())
            })
            .collect();
        let ghost = Ghost {
            t: V3::x(),
            u: V3::y(),
            length: 0.2,
        };
        let mut frames = EdgeFrames::default();
        frames.update(&x, &ghost);
        let bend = vec![
            NodeRest {
                a: [0.0, 0.2],
                b: [0.0, 0.2],
            };
            7
        ];
        let twist = vec![0.01; 7];
        let voronoi = vec![0.1; 7];
        let rest = TwistRest {
            bend: &bend,
            twist: &twist,
            voronoi: &voronoi,
        };
        let s = Stiffness {
            major: 2.0,
            minor: 2.0,
            twist: 1.0,
        };
        let mut out = Twist::default();
        quasistatic(&frames, &rest, &s, &mut out);
        for (j, th) in out.theta.iter().enumerate() {
            assert!(
                (th - 0.01 * (j + 1) as f64).abs() < 1e-15,
                "segment {j}: {th}"
            );
        }
    }

    #[test]
    fn a_planar_bend_turns_the_major_axis_onto_the_bending_axis() {
        // Straight along x, then bending in the x–y plane (binormal along z); the ghost's u is z,
        // so twist 0 would already align m1 with z; start from u = y instead.
        let x: Vec<V3> = (0..8)
            .map(|i| {
                let a = 0.2 * i as f64;
                V3::new(a.sin(), 1.0 - a.cos(), 0.0)
            })
            .collect();
        let ghost = Ghost {
            t: V3::x(),
            u: V3::y(),
            length: 0.2,
        };
        let mut frames = EdgeFrames::default();
        frames.update(&x, &ghost);
        let bend = vec![NodeRest::default(); 7];
        let twist = vec![0.0; 7];
        let voronoi = vec![0.1; 7];
        let rest = TwistRest {
            bend: &bend,
            twist: &twist,
            voronoi: &voronoi,
        };
        let s = Stiffness {
            major: 1.0,
            minor: 4.0,
            twist: 1.0,
        };
        let mut twist = Twist::default();
        quasistatic(&frames, &rest, &s, &mut twist);
        assert!(minor_axis_bending(&frames, &twist) < 1e-12);
        // u = y → m1 = ±z needs a quarter turn, the nearest one.
        assert!((twist.theta[3].abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
    }
}
