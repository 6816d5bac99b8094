//! The nearest parents of every parent's root: a uniform grid over the roots, searched ring by ring
//! until no closer root can remain (exact, ties broken by parent index, so deterministic).
//!
//! Cells are `L / ∛P` wide (`L` the roots' largest extent, `P` their number): a few roots per
//! occupied cell on a scalp, so most searches stop after the first ring of 27 cells.

use std::collections::HashMap;

use hair_par::prelude::*;
use nalgebra::Vector3;

/// For every root, the indices of its `m` nearest roots (itself first, then by distance, ties by
/// index), flat: root `p`'s list is `[p·m, (p+1)·m)`. Needs `1 ≤ m ≤ roots.len()`.
pub(crate) fn nearest(roots: &[Vector3<f32>], m: usize) -> Vec<u32> {
    let n = roots.len();
    let (lo, hi) = roots.iter().fold(
        (
            Vector3::repeat(f32::INFINITY),
            Vector3::repeat(f32::NEG_INFINITY),
        ),
        |(lo, hi), r| (lo.inf(r), hi.sup(r)),
    );
    let extent = (hi - lo).max();
    let h = (extent / (n as f32).cbrt()).max(1e-6);
    let cell = |r: &Vector3<f32>| -> [i32; 3] {
        let c = (r - lo) / h;
        [c.x as i32, c.y as i32, c.z as i32]
    };
    let mut grid: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
    for (i, r) in roots.iter().enumerate() {
        grid.entry(cell(r)).or_default().push(i as u32);
    }
    let reach = cell(&hi).into_iter().max().unwrap_or(0) + 1;
    // By squared distance, ties by index.
    let order = |a: &(f32, u32), b: &(f32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
    let mut out = vec![0u32; n * m];
    out.par_chunks_mut(m).enumerate().for_each_init(
        Vec::new,
        |found: &mut Vec<(f32, u32)>, (p, list)| {
            found.clear();
            let me = roots[p];
            let [cx, cy, cz] = cell(&me);
            for r in 0..=reach {
                for dx in -r..=r {
                    for dy in -r..=r {
                        for dz in -r..=r {
                            if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                                continue;
                            }
                            if let Some(ids) = grid.get(&[cx + dx, cy + dy, cz + dz]) {
                                found.extend(
                                    ids.iter()
                                        .map(|&i| ((roots[i as usize] - me).norm_squared(), i)),
                                );
                            }
                        }
                    }
                }
                if found.len() >= m {
                    // The m nearest so far (in any order), the m-th nearest last.
                    found.select_nth_unstable_by(m - 1, order);
                    found.truncate(m);
                    // Roots in rings beyond r are at least r·h away.
                    let bound = r as f32 * h;
                    if found[m - 1].0 <= bound * bound {
                        break;
                    }
                }
            }
            found.sort_unstable_by(order);
            // Itself first even when another root coincides with it.
            if let Some(k) = found.iter().position(|f| f.1 as usize == p) {
                found[..=k].rotate_right(1);
            }
            for (slot, f) in list.iter_mut().zip(found.iter()) {
                *slot = f.1;
            }
        },
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_search_equals_brute_force() {
        let roots: Vec<_> = (0..500u32)
            .map(|i| {
                let a = i as f32 * 2.399_963;
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 500.0;
                let r = (1.0 - z * z).sqrt();
                Vector3::new(r * a.cos(), r * a.sin(), z) * 0.1
            })
            .collect();
        let m = 7;
        let got = nearest(&roots, m);
        for p in 0..roots.len() {
            let mut all: Vec<(f32, u32)> = roots
                .iter()
                .enumerate()
                .map(|(i, r)| ((r - roots[p]).norm_squared(), i as u32))
                .collect();
            all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let want: Vec<u32> = all[..m].iter().map(|f| f.1).collect();
            assert_eq!(&got[p * m..(p + 1) * m], &want[..], "root {p}");
        }
    }
}
