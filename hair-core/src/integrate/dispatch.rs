//! One macro for the AVX2 copy of a group kernel, shared by every integrator.
//!
//! Each integrator's group step is generic over the lane type and `#[inline(always)]`, so a
//! caller compiled with other CPU features gets its own machine code. The solver runs the
//! [`super::lanes::F8`] copy compiled for AVX2 where the CPU has it (eight lanes per 256-bit
//! instruction) and the baseline copy otherwise; both give the same bits (the kernel tests check
//! it). [`avx2_copy!`] writes the dispatching function: a runtime check of the CPU, then a call
//! through a `#[target_feature(enable = "avx2")]` wrapper, or the same kernel compiled for the
//! target's baseline on CPUs without AVX2.

/// `avx2_copy!(pub(crate) fn name => generic_kernel)` defines `name`, a
/// [`super::kernel::GroupKernel`] on [`super::lanes::F8`] that runs `generic_kernel::<F8>`
/// compiled for AVX2 where the CPU has it, and compiled for the baseline elsewhere (the same
/// bits either way; see the module docs).
macro_rules! avx2_copy {
    ($(#[$doc:meta])* $vis:vis fn $name:ident => $generic:ident) => {
        $(#[$doc])*
        $vis fn $name(
            views: &mut [$crate::integrate::kernel::StrandView],
            starts: &[$crate::mesh::RootFrame],
            ends: &[$crate::mesh::RootFrame],
            c: &$crate::integrate::kernel::StepConstants,
            g: &mut $crate::integrate::kernel::Scratch<$crate::integrate::lanes::F8>,
        ) {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2")]
                fn compiled_for_avx2(
                    views: &mut [$crate::integrate::kernel::StrandView],
                    starts: &[$crate::mesh::RootFrame],
                    ends: &[$crate::mesh::RootFrame],
                    c: &$crate::integrate::kernel::StepConstants,
                    g: &mut $crate::integrate::kernel::Scratch<$crate::integrate::lanes::F8>,
                ) {
                    $generic::<$crate::integrate::lanes::F8>(views, starts, ends, c, g);
                }
                if std::arch::is_x86_feature_detected!("avx2") {
                    // SAFETY: the CPU has AVX2, checked just above.
                    unsafe { compiled_for_avx2(views, starts, ends, c, g) };
                    return;
                }
            }
            $generic::<$crate::integrate::lanes::F8>(views, starts, ends, c, g);
        }
    };
}

pub(crate) use avx2_copy;
