//! The one CPU dispatch of the library: which vector unit a vectorised path runs on.
//!
//! Every vectorised or fused-multiply-add path is written once, generic over the constant `FMA`,
//! and compiled by the crate-private macro `dispatched!` for each [`Level`]: AVX-512 with FMA, AVX2 with FMA, and the
//! portable path (SSE2 on x86-64, no fused multiply-adds). Which copy runs is chosen from a
//! [`Simd`], a capability that only run-time detection creates, so a copy compiled for features
//! the CPU lacks can never be called: that is the invariant every `unsafe` call in the dispatch
//! rests on.
//!
//! The two FMA levels give bit-identical results (the same operations, only the register width
//! differs; Rust never fuses or reorders floating-point operations on its own). The portable level
//! differs from them at the rounding level, because a fused multiply-add rounds once where a
//! multiply and an add round twice.

use serde::Serialize;

/// A vector unit the library's vectorised paths are compiled for, widest first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Level {
    /// Neither of the below: SSE2 on x86-64, or any other architecture; no fused multiply-adds.
    Portable,
    /// AVX2 and FMA.
    Avx2,
    /// AVX-512F and FMA.
    Avx512,
}

impl Level {
    /// Whether this level's copies use fused multiply-adds.
    pub fn fma(self) -> bool {
        self != Level::Portable
    }
}

/// The capability to run code compiled for a [`Level`]: created only by [`Simd::detect`] (the
/// widest level this CPU has) and [`Simd::available`] (every level this CPU has), never from a
/// bare `Level`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Simd(Level);

thread_local! {
    /// The widest level this thread may use ([`Simd::capped`]): lowering it is always safe.
    static CAP: std::cell::Cell<Level> = const { std::cell::Cell::new(Level::Avx512) };
}

impl Simd {
    /// The widest level this CPU supports.
    fn cpu() -> Level {
        #[cfg(target_arch = "x86_64")]
        {
            let fma = std::arch::is_x86_feature_detected!("fma");
            if fma && std::arch::is_x86_feature_detected!("avx512f") {
                return Level::Avx512;
            }
            if fma && std::arch::is_x86_feature_detected!("avx2") {
                return Level::Avx2;
            }
        }
        Level::Portable
    }

    /// The widest level this CPU supports (and this thread may use, see [`Simd::capped`]).
    #[inline]
    pub fn detect() -> Simd {
        Simd(Simd::cpu().min(CAP.with(std::cell::Cell::get)))
    }

    /// Every level this CPU supports, narrowest first (for tests that compare the levels).
    pub fn available() -> Vec<Simd> {
        let cpu = Simd::cpu();
        [Level::Portable, Level::Avx2, Level::Avx512]
            .into_iter()
            .filter(|&l| l <= cpu)
            .map(Simd)
            .collect()
    }

    /// This capability lowered to at most `level` (always safe: a CPU with a level has every
    /// narrower one). For code that runs faster on narrower registers than the widest the CPU
    /// has.
    pub fn at_most(self, level: Level) -> Simd {
        Simd(self.0.min(level))
    }

    /// The level this capability names.
    pub fn level(self) -> Level {
        self.0
    }

    /// Runs `f` on this thread with every dispatch of the library at most at this level (so a
    /// test can run the same inputs on each level this CPU has). Work that `f` hands to other
    /// threads is not capped.
    pub fn capped<R>(self, f: impl FnOnce() -> R) -> R {
        let before = CAP.with(|c| c.replace(self.0));
        let out = f();
        CAP.with(|c| c.set(before));
        out
    }
}

/// `dispatched! { fn name[generics](args…) -> ret = body }` defines `name(simd: Simd, args…)`,
/// which runs `body` (a call of an `#[inline(always)]` function, with the constant `FMA` in
/// scope) compiled for the level `simd` names. `[generics]` is optional: the generic parameters
/// of the copies, inferred from the arguments at the call.
macro_rules! dispatched {
    ($(#[$doc:meta])* $vis:vis fn $name:ident $([$($g:tt)*])? ($($arg:ident: $ty:ty),* $(,)?) -> $ret:ty = $body:expr) => {
        $(#[$doc])*
        $vis fn $name $(<$($g)*>)? (simd: $crate::simd::Simd, $($arg: $ty),*) -> $ret {
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx512f,fma")]
            fn avx512 $(<$($g)*>)? ($($arg: $ty),*) -> $ret {
                #[allow(dead_code)] // (not every body multiplies)
                const FMA: bool = true;
                $body
            }
            #[cfg(target_arch = "x86_64")]
            #[target_feature(enable = "avx2,fma")]
            fn avx2 $(<$($g)*>)? ($($arg: $ty),*) -> $ret {
                #[allow(dead_code)] // (not every body multiplies)
                const FMA: bool = true;
                $body
            }
            fn portable $(<$($g)*>)? ($($arg: $ty),*) -> $ret {
                #[allow(dead_code)] // (as above)
                const FMA: bool = false;
                $body
            }
            match simd.level() {
                // SAFETY: a `Simd` is created only by run-time detection, so the CPU has every
                // feature of the level it names.
                #[cfg(target_arch = "x86_64")]
                $crate::simd::Level::Avx512 => unsafe { avx512($($arg),*) },
                // SAFETY: as above.
                #[cfg(target_arch = "x86_64")]
                $crate::simd::Level::Avx2 => unsafe { avx2($($arg),*) },
                _ => portable($($arg),*),
            }
        }
    };
}
pub(crate) use dispatched;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_is_the_widest_available_level_and_a_cap_only_lowers_it() {
        let all = Simd::available();
        assert_eq!(all[0].level(), Level::Portable);
        assert_eq!(*all.last().unwrap(), Simd::detect());
        for s in &all {
            assert_eq!(s.capped(Simd::detect), *s);
        }
        assert_eq!(Simd::detect(), *all.last().unwrap());
    }

    dispatched! {
        fn fused(a: f64, b: f64, c: f64) -> f64 = if FMA { a.mul_add(b, c) } else { a * b + c }
    }

    #[test]
    fn every_level_runs_its_own_copy() {
        // a·b + c with a = b = 1 + 2⁻³⁰, c = −(1 + 2⁻²⁹): the product's 2⁻⁶⁰ survives only fused
        let (a, c) = (1.0 + 2f64.powi(-30), -(1.0 + 2f64.powi(-29)));
        for s in Simd::available() {
            let want = if s.level().fma() { 2f64.powi(-60) } else { 0.0 };
            assert_eq!(fused(s, a, a, c), want, "{:?}", s.level());
        }
    }
}
