//! The instruction set the frame's hot kernels run with, chosen once per
//! renderer at run time.
//!
//! The portable build targets baseline x86-64 (SSE2). Where the CPU has
//! AVX2 and FMA (x86-64-v3), the planning of a chunk and the drawing of a
//! band run inside a function compiled for those features
//! ([`pulp::x86::V3`], whose detection and feature-enabled entry point keep
//! this crate free of `unsafe`); the kernels they call are
//! `#[inline(always)]`, so one source is compiled twice and the compiler
//! gives the second copy 256-bit lanes in its auto-vectorised loops, the
//! SSE4.1 integer forms (packed minimum and maximum) and three-operand VEX
//! forms. Code left out of line (an iterator's `fold` the compiler does
//! not inline, glam's own functions) stays portable in both. Rust never
//! fuses a multiply and an add on its own, so both copies compute the
//! same values and the images are the same bit for bit (tested).
//!
//! Cost: one branch per chunk and per band.

/// Which copy of the hot kernels runs.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Isa {
    /// The portable build's own instructions.
    Base,
    /// AVX2 and FMA (x86-64-v3), detected at run time.
    #[cfg(target_arch = "x86_64")]
    V3(pulp::x86::V3),
}

impl Isa {
    /// The best copy this CPU runs; [`Isa::Base`] when `simd` is false.
    pub(crate) fn detect(simd: bool) -> Self {
        #[cfg(target_arch = "x86_64")]
        if let Some(v3) = pulp::x86::V3::try_new().filter(|_| simd) {
            return Isa::V3(v3);
        }
        let _ = simd;
        Isa::Base
    }

    /// Runs `f` with this instruction set: what `f` inlines is compiled
    /// for it.
    #[inline(always)]
    pub(crate) fn run<R>(self, f: impl FnOnce() -> R) -> R {
        match self {
            Isa::Base => f(),
            #[cfg(target_arch = "x86_64")]
            Isa::V3(v3) => pulp::Simd::vectorize(v3, f),
        }
    }

    /// A short name for statistics and logs.
    pub(crate) fn name(self) -> &'static str {
        match self {
            Isa::Base => "base",
            #[cfg(target_arch = "x86_64")]
            Isa::V3(_) => "x86-64-v3",
        }
    }
}
