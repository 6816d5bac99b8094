//! Grooming operators (seed 001, "Hair Edit Operators") as library functions on guides. They
//! edit rest shapes only, in root-frame coordinates (local +z = the surface normal at the root,
//! m), and each says what it keeps:
//!
//! | operator | changes | keeps |
//! |---|---|---|
//! | [`comb`] | segment directions, turned towards a direction | root, point count, every segment length |
//! | [`smooth`] | segment directions, averaged with their neighbours | root, first segment, point count, every segment length |
//! | [`puff`] | segment directions, raised towards the normal, most at the root | root, point count, every segment length |
//! | [`cut`] | drops the part beyond a length; the last kept segment is shortened | root, the kept points and their segment lengths |
//! | [`set_length`] | every segment length, by one factor | root, point count, every segment direction |
//! | [`add_guide`] | adds a guide, its shape interpolated from its neighbours | every other guide |
//! | [`delete_guides`] | removes guides | the order of the others |
//!
//! Parameters out of range are refused by name; no operator panics on a guide's data.

use hair_core::mesh::any_perpendicular;
use hair_core::{MeshSample, TriMesh};
use nalgebra::{Rotation3, Unit, Vector3};

use crate::error::{parameter, GroomError};
use crate::groom::{check_curve, polyline_length};
use crate::interpolate::{interpolate, Distance, InterpolateOptions};
use crate::snap::Guide;

/// Checks that `amount` (named `name` as in the scene file) lies in [0, 1].
fn unit_interval(name: &str, amount: f32) -> Result<(), GroomError> {
    if (0.0..=1.0).contains(&amount) {
        Ok(())
    } else {
        Err(parameter(name, amount, "must lie in [0, 1]"))
    }
}

/// The guide's segments as (unit direction, length, m); a zero-length segment takes the previous
/// direction (local +z for the first).
fn segments(rest: &[Vector3<f32>]) -> Vec<(Vector3<f32>, f32)> {
    let mut previous = Vector3::z();
    rest.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let len = d.norm();
            if len > 0.0 && len.is_finite() {
                previous = d / len;
            }
            (previous, len)
        })
        .collect()
}

/// Rebuilds the points from `root` and the segments.
fn rebuild(root: Vector3<f32>, segments: &[(Vector3<f32>, f32)]) -> Vec<Vector3<f32>> {
    let mut points = Vec::with_capacity(segments.len() + 1);
    points.push(root);
    let mut p = root;
    for (d, len) in segments {
        p += d * *len;
        points.push(p);
    }
    points
}

/// `d` (unit) turned towards `target` (unit) by the fraction `t` of the angle between them.
fn turn_towards(d: &Vector3<f32>, target: &Vector3<f32>, t: f32) -> Vector3<f32> {
    let angle = d.dot(target).clamp(-1.0, 1.0).acos();
    let axis = d.cross(target);
    let axis = if axis.norm() > 1e-7 {
        Unit::new_normalize(axis)
    } else if d.dot(target) > 0.0 {
        return *d;
    } else {
        Unit::new_unchecked(any_perpendicular(d))
    };
    (Rotation3::from_axis_angle(&axis, angle * t) * d).normalize()
}

/// The unit vector of `direction`, refused by name if it is zero or not finite.
fn unit_direction(direction: &Vector3<f32>) -> Result<Vector3<f32>, GroomError> {
    let n = direction.norm();
    if n.is_finite() && n > 0.0 {
        Ok(direction / n)
    } else {
        Err(parameter(
            "direction",
            format!("({}, {}, {})", direction.x, direction.y, direction.z),
            "must be a finite, non-zero vector (root-frame coordinates: +z is the surface normal)",
        ))
    }
}

/// Combs `guide`: turns every segment towards `direction` (root-frame coordinates, any non-zero
/// length) by the fraction `strength` in [0, 1] of its angle to it (1 lays every segment along
/// it). Keeps the root, the point count and every segment length.
pub fn comb(guide: &mut Guide, direction: &Vector3<f32>, strength: f32) -> Result<(), GroomError> {
    unit_interval("strength", strength)?;
    let target = unit_direction(direction)?;
    check_curve(0, &guide.rest)?;
    let segs: Vec<_> = segments(&guide.rest)
        .into_iter()
        .map(|(d, l)| (turn_towards(&d, &target, strength), l))
        .collect();
    guide.rest = rebuild(guide.rest[0], &segs);
    Ok(())
}

/// Smooths `guide`: `iterations` passes, each moving every segment direction after the first
/// the fraction `factor` in [0, 1] towards the mean of its neighbours' (the last segment's towards
/// its one neighbour). Keeps the root, the first segment, the point count and every segment
/// length (so the total length).
pub fn smooth(guide: &mut Guide, factor: f32, iterations: u32) -> Result<(), GroomError> {
    unit_interval("factor", factor)?;
    check_curve(0, &guide.rest)?;
    let mut segs = segments(&guide.rest);
    for _ in 0..iterations {
        let previous = segs.clone();
        for i in 1..segs.len() {
            let next = previous.get(i + 1).map_or(previous[i - 1].0, |s| s.0);
            let mean = previous[i - 1].0 + next;
            if mean.norm() > 1e-7 {
                segs[i].0 = turn_towards(&previous[i].0, &mean.normalize(), factor);
            }
        }
    }
    guide.rest = rebuild(guide.rest[0], &segs);
    Ok(())
}

/// Puffs `guide` up: turns each segment towards the surface normal (local +z) by the fraction
/// `amount · (1 − s)` of its angle to it, `s` the segment's start along the strand (0 at the root,
/// 1 at the tip), so hair lifts off the scalp at the root and falls freely at the tip. `amount`
/// in [0, 1]. Keeps the root, the point count and every segment length.
pub fn puff(guide: &mut Guide, amount: f32) -> Result<(), GroomError> {
    unit_interval("amount", amount)?;
    check_curve(0, &guide.rest)?;
    let segs = segments(&guide.rest);
    let n = segs.len() as f32;
    let segs: Vec<_> = segs
        .into_iter()
        .enumerate()
        .map(|(i, (d, l))| {
            (
                turn_towards(&d, &Vector3::z(), amount * (1.0 - i as f32 / n)),
                l,
            )
        })
        .collect();
    guide.rest = rebuild(guide.rest[0], &segs);
    Ok(())
}

/// Cuts `guide` to at most `length` m (finite, > 0) along the strand: points beyond it are
/// dropped and the segment it falls in ends at it. A shorter guide is left as it is. Keeps the
/// root, every kept point and the lengths of the kept segments before the cut.
pub fn cut(guide: &mut Guide, length: f32) -> Result<(), GroomError> {
    if !(length.is_finite() && length > 0.0) {
        return Err(parameter("length", length, "must be a finite length > 0 m"));
    }
    check_curve(0, &guide.rest)?;
    let mut walked = 0.0f32;
    for i in 1..guide.rest.len() {
        let seg = (guide.rest[i] - guide.rest[i - 1]).norm();
        if walked + seg > length {
            let t = (length - walked) / seg;
            let end = guide.rest[i - 1].lerp(&guide.rest[i], t);
            guide.rest.truncate(i);
            // A cut at a point keeps the point rather than a zero-length segment.
            if t > 1e-6 || i == 1 {
                guide.rest.push(end);
            }
            return Ok(());
        }
        walked += seg;
    }
    Ok(())
}

/// Sets `guide`'s length along the strand to `length` m (finite, > 0) by scaling every segment by
/// the same factor. Keeps the root, the point count and every segment direction (the shape, up
/// to scale). Refuses a guide of length 0.
pub fn set_length(guide: &mut Guide, length: f32) -> Result<(), GroomError> {
    if !(length.is_finite() && length > 0.0) {
        return Err(parameter("length", length, "must be a finite length > 0 m"));
    }
    check_curve(0, &guide.rest)?;
    let current = polyline_length(&guide.rest) as f32;
    if current <= 0.0 {
        return Err(GroomError::Curve {
            curve: 0,
            message: "has length 0; it has no shape to scale".into(),
        });
    }
    let root = guide.rest[0];
    let factor = length / current;
    for p in &mut guide.rest {
        *p = root + (*p - root) * factor;
    }
    Ok(())
}

/// Adds a guide rooted at `root` whose shape is interpolated from the `k` nearest existing
/// guides ([`interpolate`] with surface distances and the point count of the guides' longest
/// list), and returns its
/// index (the last). Keeps every other guide. Errors if there is no guide to interpolate from or
/// `root` does not lie on `mesh`.
pub fn add_guide(
    mesh: &TriMesh,
    guides: &mut Vec<Guide>,
    root: MeshSample,
    k: usize,
) -> Result<usize, GroomError> {
    let points = guides
        .iter()
        .map(|g| g.rest.len())
        .max()
        .ok_or(GroomError::NoEnabledGuides)?;
    let enabled = vec![true; guides.len()];
    let opts = InterpolateOptions {
        k,
        points,
        distance: Distance::Surface,
    };
    let hair = interpolate(mesh, guides, &enabled, &[root], &opts)?.remove(0);
    guides.push(Guide {
        root,
        rest: hair.rest,
    });
    Ok(guides.len() - 1)
}

/// Deletes the guides at `indices` (any order, repeats allowed), keeping the others in their
/// order. Returns, for every old index, its new index or `None` if deleted, to carry masks and
/// selections over. Refuses an index out of range, deleting nothing.
pub fn delete_guides(
    guides: &mut Vec<Guide>,
    indices: &[usize],
) -> Result<Vec<Option<usize>>, GroomError> {
    let mut delete = vec![false; guides.len()];
    for &i in indices {
        *delete.get_mut(i).ok_or_else(|| {
            parameter(
                "guide",
                i,
                &format!("is out of range: there are {} guides", guides.len()),
            )
        })? = true;
    }
    let mut next = 0;
    let map = delete
        .iter()
        .map(|&d| {
            (!d).then(|| {
                next += 1;
                next - 1
            })
        })
        .collect();
    let mut k = 0;
    guides.retain(|_| {
        k += 1;
        !delete[k - 1]
    });
    Ok(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::uv_sphere;

    /// A wavy guide of 10 uneven segments.
    fn guide() -> Guide {
        let rest = (0..11)
            .map(|i| {
                let s = i as f32;
                Vector3::new(
                    0.004 * (s * 0.9).sin(),
                    0.002 * s,
                    0.01 * s + 0.0005 * s * s,
                )
            })
            .collect();
        Guide {
            root: MeshSample {
                triangle: 0,
                weights: [1.0, 0.0, 0.0],
            },
            rest,
        }
    }

    fn lengths(g: &Guide) -> Vec<f32> {
        segments(&g.rest).iter().map(|s| s.1).collect()
    }

    fn assert_lengths_kept(before: &Guide, after: &Guide) {
        assert_eq!(before.rest.len(), after.rest.len());
        assert_eq!(before.rest[0], after.rest[0]);
        for (a, b) in lengths(before).iter().zip(lengths(after)) {
            assert!((a - b).abs() < 1e-6 * a.max(1e-3), "segment {a} became {b}");
        }
    }

    #[test]
    fn comb_lays_segments_along_the_direction_keeping_lengths() {
        let g0 = guide();
        let mut g = g0.clone();
        comb(&mut g, &Vector3::new(1.0, 0.0, 0.2), 0.5).unwrap();
        assert_lengths_kept(&g0, &g);
        let dir = Vector3::new(1.0, 0.0, 0.2).normalize();
        let mut full = g0.clone();
        comb(&mut full, &dir, 1.0).unwrap();
        assert!(segments(&full.rest)
            .iter()
            .all(|(d, _)| (d - dir).norm() < 1e-5));
        assert!(comb(&mut g, &Vector3::zeros(), 0.5)
            .unwrap_err()
            .to_string()
            .contains("`direction`"));
        assert!(comb(&mut g, &dir, 1.5)
            .unwrap_err()
            .to_string()
            .contains("`strength`"));
        // Antiparallel segments turn too, without NaN.
        let mut back = g0.clone();
        comb(&mut back, &-Vector3::z(), 1.0).unwrap();
        assert!(back.rest.iter().all(|p| p.iter().all(|c| c.is_finite())));
    }

    #[test]
    fn smooth_straightens_keeping_lengths_and_first_segment() {
        let g0 = guide();
        let mut g = g0.clone();
        smooth(&mut g, 0.5, 20).unwrap();
        assert_lengths_kept(&g0, &g);
        assert!((g.rest[1] - g0.rest[1]).norm() < 1e-7);
        // Less turning between consecutive segments than before.
        let turning = |g: &Guide| {
            segments(&g.rest)
                .windows(2)
                .map(|w| w[0].0.angle(&w[1].0))
                .sum::<f32>()
        };
        assert!(
            turning(&g) < 0.5 * turning(&g0),
            "{} vs {}",
            turning(&g),
            turning(&g0)
        );
    }

    #[test]
    fn puff_raises_the_root_end_keeping_lengths() {
        let mut flat = Guide {
            root: guide().root,
            rest: (0..6)
                .map(|i| Vector3::new(0.01 * i as f32, 0.0, 0.0))
                .collect(),
        };
        let g0 = flat.clone();
        puff(&mut flat, 0.5).unwrap();
        assert_lengths_kept(&g0, &flat);
        let segs = segments(&flat.rest);
        assert!(segs[0].0.z > segs[4].0.z && segs[4].0.z > 0.0, "{segs:?}");
        assert!(puff(&mut flat, -0.1).is_err());
    }

    #[test]
    fn cut_and_set_length() {
        let g0 = guide();
        let total = polyline_length(&g0.rest) as f32;
        let mut g = g0.clone();
        cut(&mut g, 0.5 * total).unwrap();
        assert!((polyline_length(&g.rest) as f32 - 0.5 * total).abs() < 1e-6);
        assert_eq!(&g.rest[..g.rest.len() - 1], &g0.rest[..g.rest.len() - 1]);
        let mut longer = g0.clone();
        cut(&mut longer, 2.0 * total).unwrap();
        assert_eq!(longer, g0);
        // A cut within the first segment keeps two points.
        let mut tiny = g0.clone();
        cut(&mut tiny, 1e-4).unwrap();
        assert_eq!(tiny.rest.len(), 2);

        let mut g = g0.clone();
        set_length(&mut g, 0.3).unwrap();
        assert!((polyline_length(&g.rest) - 0.3).abs() < 1e-6);
        for ((d0, _), (d1, _)) in segments(&g0.rest).iter().zip(segments(&g.rest)) {
            assert!((d0 - d1).norm() < 1e-5);
        }
        assert!(set_length(&mut g, 0.0)
            .unwrap_err()
            .to_string()
            .contains("`length`"));
        assert!(cut(&mut g, f32::NAN)
            .unwrap_err()
            .to_string()
            .contains("`length`"));
    }

    #[test]
    fn add_and_delete_guides() {
        let mesh = uv_sphere(0.1, 16, 8).unwrap();
        let mut guides = vec![
            Guide {
                root: MeshSample {
                    triangle: 20,
                    weights: [0.2, 0.3, 0.5],
                },
                rest: guide().rest,
            },
            Guide {
                root: MeshSample {
                    triangle: 40,
                    weights: [0.6, 0.2, 0.2],
                },
                rest: guide().rest,
            },
        ];
        let at = add_guide(
            &mesh,
            &mut guides,
            MeshSample {
                triangle: 30,
                weights: [0.3, 0.3, 0.4],
            },
            2,
        )
        .unwrap();
        assert_eq!((at, guides.len()), (2, 3));
        assert_eq!(guides[2].rest.len(), 11);
        let kept = guides[2].clone();
        let map = delete_guides(&mut guides, &[0, 1, 0]).unwrap();
        assert_eq!(map, vec![None, None, Some(0)]);
        assert_eq!(guides, vec![kept]);
        assert!(delete_guides(&mut guides, &[3])
            .unwrap_err()
            .to_string()
            .contains("out of range"));
        assert_eq!(guides.len(), 1);
        let mut none = Vec::new();
        assert!(matches!(
            add_guide(&mesh, &mut none, guide().root, 2),
            Err(GroomError::NoEnabledGuides)
        ));
    }
}
