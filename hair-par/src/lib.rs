//! Data parallelism for the hairsys crates, behind the `parallel` feature.
//!
//! With `parallel` (the default) this is rayon: [`prelude`], [`join`], [`ThreadPool`] and
//! [`ThreadPoolBuilder`] are rayon's own items. Without it, the same names run the same calls in
//! order on the calling thread: `into_par_iter`, `par_iter`, `par_chunks_mut` and the rest give
//! standard iterators, `map_init`/`for_each_init` create their state once, [`join`] runs its
//! two closures one after the other, a [`ThreadPool`] runs what it installs where it is called,
//! and [`current_num_threads`] is 1. The crates' results do not depend on the thread count
//! (their tests compare one thread with several), so a build without `parallel` computes the
//! same bits as a one-thread pool, except where a parallel reduction sums floats
//! ([`reduce`]: in order here, in rayon's split order there).
//!
//! A host that schedules work in its own job system (a DCC's task graph, a farm's per-core
//! slots) builds without `parallel`: no worker threads start, and the hair runs on whichever
//! thread calls it.

#![warn(missing_docs)]

#[cfg(feature = "parallel")]
pub use rayon::{
    current_num_threads, join, prelude, ThreadPool, ThreadPoolBuildError, ThreadPoolBuilder,
};

/// A worker thread a pool asks its spawn handler to start (rayon's own; only with `parallel`,
/// where pools have threads).
#[cfg(feature = "parallel")]
pub use rayon::ThreadBuilder;

#[cfg(not(feature = "parallel"))]
mod sequential;
#[cfg(not(feature = "parallel"))]
pub use sequential::{
    current_num_threads, join, prelude, ThreadPool, ThreadPoolBuildError, ThreadPoolBuilder,
};

/// Reduces `iter` with `op`, starting each part from `identity()` (rayon's `reduce`; in order
/// without `parallel`). `op` should be associative: with `parallel`, how the items are split
/// among threads decides the order of the combinations.
#[cfg(feature = "parallel")]
pub fn reduce<I, ID, OP>(iter: I, identity: ID, op: OP) -> I::Item
where
    I: prelude::ParallelIterator,
    ID: Fn() -> I::Item + Sync + Send,
    OP: Fn(I::Item, I::Item) -> I::Item + Sync + Send,
{
    iter.reduce(identity, op)
}

/// Reduces `iter` with `op`, starting from `identity()` (rayon's `reduce` without `parallel`:
/// in order).
#[cfg(not(feature = "parallel"))]
pub fn reduce<I, ID, OP>(iter: I, identity: ID, op: OP) -> I::Item
where
    I: Iterator,
    ID: Fn() -> I::Item,
    OP: Fn(I::Item, I::Item) -> I::Item,
{
    iter.fold(identity(), op)
}

#[cfg(test)]
mod tests {
    use super::prelude::*;

    #[test]
    fn the_calls_the_crates_make_give_the_sequential_answers() {
        let v: Vec<u32> = (0..1000).collect();
        let squares: Vec<u64> = v.par_iter().map(|&x| u64::from(x) * u64::from(x)).collect();
        assert_eq!(squares[999], 998_001);
        let mut w = v.clone();
        w.par_chunks_mut(7).enumerate().for_each(|(k, c)| {
            c.iter_mut().for_each(|x| *x += k as u32);
        });
        assert_eq!(w[14], 16);
        let sums: Vec<u32> = (0..10u32)
            .into_par_iter()
            .map_init(|| 5u32, |s, x| *s + x)
            .collect();
        assert_eq!(sums, (5..15).collect::<Vec<_>>());
        let max = super::reduce(v.par_iter().map(|&x| x as f32), || 0.0, f32::max);
        assert_eq!(max, 999.0);
        let (a, b) = super::join(|| 1, || 2);
        assert_eq!((a, b), (1, 2));
        let pool = super::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        assert_eq!(pool.install(|| 3), 3);
        let mut order = vec![3, 1, 2];
        order.par_sort();
        assert_eq!(order, [1, 2, 3]);
        let mut out = Vec::new();
        (0..4u32)
            .into_par_iter()
            .with_min_len(2)
            .collect_into_vec(&mut out);
        assert_eq!(out, [0, 1, 2, 3]);
        let flat: Vec<u32> = (0..3u32)
            .into_par_iter()
            .flat_map_iter(|x| std::iter::repeat_n(x, 2))
            .collect();
        assert_eq!(flat, [0, 0, 1, 1, 2, 2]);
    }
}
