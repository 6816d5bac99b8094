//! The calls of rayon's the hairsys crates make, run in order on the calling thread (the
//! crate's `parallel` feature off).

use std::fmt;

/// Runs `a`, then `b`, on the calling thread, and returns both results.
pub fn join<A, B, RA, RB>(a: A, b: B) -> (RA, RB)
where
    A: FnOnce() -> RA,
    B: FnOnce() -> RB,
{
    let ra = a();
    (ra, b())
}

/// Threads work runs on: always 1 here.
pub fn current_num_threads() -> usize {
    1
}

/// A thread pool that runs what it installs on the calling thread.
#[derive(Debug)]
pub struct ThreadPool(());

impl ThreadPool {
    /// Runs `op` on the calling thread and returns its result.
    pub fn install<R>(&self, op: impl FnOnce() -> R) -> R {
        op()
    }

    /// Threads of the pool: always 1 here.
    pub fn current_num_threads(&self) -> usize {
        1
    }
}

/// Builds a [`ThreadPool`]; the thread count asked for is accepted and not used.
#[derive(Debug, Default)]
pub struct ThreadPoolBuilder(());

impl ThreadPoolBuilder {
    /// A builder.
    pub fn new() -> Self {
        Self(())
    }

    /// Accepts the thread count a parallel build would start (work still runs on the calling
    /// thread).
    pub fn num_threads(self, _threads: usize) -> Self {
        self
    }

    /// The pool; never fails here.
    pub fn build(self) -> Result<ThreadPool, ThreadPoolBuildError> {
        Ok(ThreadPool(()))
    }
}

/// Why a pool could not start (never, without worker threads; the type keeps the signature of
/// the parallel build).
#[derive(Debug)]
pub struct ThreadPoolBuildError(());

impl fmt::Display for ThreadPoolBuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("thread pool error")
    }
}

impl std::error::Error for ThreadPoolBuildError {}

/// The traits that give rayon's method names to standard iterators and slices.
pub mod prelude {
    /// `into_par_iter`: the value's own iterator.
    pub trait IntoParallelIterator: IntoIterator + Sized {
        /// The value's iterator, in order.
        fn into_par_iter(self) -> Self::IntoIter {
            self.into_iter()
        }
    }

    impl<T: IntoIterator> IntoParallelIterator for T {}

    /// rayon's iterator adapters that standard iterators lack, in order.
    pub trait ParallelIterator: Iterator + Sized {
        /// `map` with a state made once by `init` and handed to every call of `f`.
        fn map_init<T, R, INIT, F>(self, init: INIT, mut f: F) -> impl Iterator<Item = R>
        where
            INIT: FnOnce() -> T,
            F: FnMut(&mut T, Self::Item) -> R,
        {
            let mut state = init();
            self.map(move |item| f(&mut state, item))
        }

        /// `for_each` with a state made once by `init` and handed to every call of `f`.
        fn for_each_init<T, INIT, F>(self, init: INIT, mut f: F)
        where
            INIT: FnOnce() -> T,
            F: FnMut(&mut T, Self::Item),
        {
            let mut state = init();
            self.for_each(|item| f(&mut state, item));
        }

        /// The iterator itself (how many items a thread takes at least does not apply).
        fn with_min_len(self, _min: usize) -> Self {
            self
        }

        /// `flat_map` over a standard iterator per item.
        fn flat_map_iter<U, F>(self, f: F) -> std::iter::FlatMap<Self, U, F>
        where
            U: IntoIterator,
            F: FnMut(Self::Item) -> U,
        {
            self.flat_map(f)
        }

        /// Collects into `target`, replacing what it held.
        fn collect_into_vec(self, target: &mut Vec<Self::Item>) {
            target.clear();
            target.extend(self);
        }
    }

    impl<I: Iterator> ParallelIterator for I {}

    /// rayon's read-only slice methods: the standard ones, in order.
    pub trait ParallelSlice<T> {
        /// `iter`.
        fn par_iter(&self) -> std::slice::Iter<'_, T>;
        /// `chunks(size)`.
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T>;
        /// `chunks_exact(size)`.
        fn par_chunks_exact(&self, size: usize) -> std::slice::ChunksExact<'_, T>;
    }

    impl<T> ParallelSlice<T> for [T] {
        fn par_iter(&self) -> std::slice::Iter<'_, T> {
            self.iter()
        }
        fn par_chunks(&self, size: usize) -> std::slice::Chunks<'_, T> {
            self.chunks(size)
        }
        fn par_chunks_exact(&self, size: usize) -> std::slice::ChunksExact<'_, T> {
            self.chunks_exact(size)
        }
    }

    /// rayon's mutable slice methods: the standard ones, in order.
    pub trait ParallelSliceMut<T> {
        /// `iter_mut`.
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T>;
        /// `chunks_mut(size)`.
        fn par_chunks_mut(&mut self, size: usize) -> std::slice::ChunksMut<'_, T>;
        /// `chunks_exact_mut(size)`.
        fn par_chunks_exact_mut(&mut self, size: usize) -> std::slice::ChunksExactMut<'_, T>;
        /// `sort` (stable).
        fn par_sort(&mut self)
        where
            T: Ord;
        /// `sort_by` (stable).
        fn par_sort_by<F>(&mut self, compare: F)
        where
            F: FnMut(&T, &T) -> std::cmp::Ordering;
    }

    impl<T> ParallelSliceMut<T> for [T] {
        fn par_iter_mut(&mut self) -> std::slice::IterMut<'_, T> {
            self.iter_mut()
        }
        fn par_chunks_mut(&mut self, size: usize) -> std::slice::ChunksMut<'_, T> {
            self.chunks_mut(size)
        }
        fn par_chunks_exact_mut(&mut self, size: usize) -> std::slice::ChunksExactMut<'_, T> {
            self.chunks_exact_mut(size)
        }
        fn par_sort(&mut self)
        where
            T: Ord,
        {
            self.sort();
        }
        fn par_sort_by<F>(&mut self, compare: F)
        where
            F: FnMut(&T, &T) -> std::cmp::Ordering,
        {
            self.sort_by(compare);
        }
    }
}
