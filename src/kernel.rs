//! Shape functions: the paper's linear (bilinear/trilinear) kernel of Eq. 16–19 and the
//! quadratic B-spline, which has a continuous gradient and so does not suffer the
//! cell-crossing error of the linear kernel.
//!
//! Coordinates are in grid units: a particle at `xg = x/h + GHOST` lies between nodes
//! `floor(xg)` and `floor(xg) + 1`; node `n` sits at `x = (n − GHOST) h`.

use crate::math::Real;
use serde::{Deserialize, Serialize};
use std::ops::{Add, Mul, Sub};

/// Runs `$body` with the type `$k` and const `$s` set to the kernel `$kind` and its support.
macro_rules! with_kernel {
    ($kind:expr, $k:ident, $s:ident => $body:expr) => {
        match $kind {
            $crate::kernel::KernelKind::Linear => {
                type $k = $crate::kernel::Linear;
                const $s: usize = 2;
                $body
            }
            $crate::kernel::KernelKind::QuadraticBspline => {
                type $k = $crate::kernel::QuadraticBspline;
                const $s: usize = 3;
                $body
            }
            $crate::kernel::KernelKind::Gimp => {
                type $k = $crate::kernel::Gimp;
                const $s: usize = 3;
                $body
            }
        }
    };
}
pub(crate) use with_kernel;

/// ⌊x⌋ for 0 ≤ x ≤ 2^22 (other values, NaN included, are clamped into that range first), as a
/// truncating cast (grid coordinates are never negative: the domain starts
/// [`crate::grid::GHOST`] nodes in). On baseline x86-64 `f32::floor` is a library call, and a
/// plain `as i32` adds saturation checks (docs/performance.md).
#[inline(always)]
pub fn floor_nonneg(x: Real) -> i32 {
    debug_assert!(x >= 0.0 || x.is_nan(), "negative grid coordinate {x}");
    // `max` gives 0 for NaN and −∞, `min` gives 2^22 for +∞.
    let c = crate::math::min(crate::math::max(x, 0.0), 4_194_304.0);
    // SAFETY: `c` is finite and in [0, 2^22], so its truncation is representable in i32
    // (the precondition of `to_int_unchecked`).
    unsafe { c.to_int_unchecked() }
}

/// The arithmetic the shape functions are written in: one axis at a time ([`Real`]), or, in
/// the x86-64 and WebAssembly builds, all four lanes of a stencil at once ([`F4`]). LLVM turns
/// the scalar lane loop of [`Kernel::stencil`] into SIMD only in part natively (with shuffles
/// between most operations) and not at all for wasm32, where V8 then compiles each clamp to
/// two branches and each truncation to a checked round trip.
pub trait ShapeArith: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {
    /// The integer type with as many lanes.
    type Int: Copy;
    fn splat(x: Real) -> Self;
    fn abs(self) -> Self;
    /// `f32::clamp` in each lane (NaN stays NaN).
    fn clamp(self, lo: Real, hi: Real) -> Self;
    /// max(x, 0) in each lane (0 for NaN).
    fn max0(self) -> Self;
    /// [`floor_nonneg`] in each lane, as an integer and as a [`Real`] (the same value).
    fn floor_nonneg(self) -> (Self::Int, Self);
}

impl ShapeArith for Real {
    type Int = i32;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Real::abs(self)
    }
    #[inline(always)]
    fn clamp(self, lo: Real, hi: Real) -> Self {
        Real::clamp(self, lo, hi)
    }
    #[inline(always)]
    fn max0(self) -> Self {
        crate::math::max(self, 0.0)
    }
    #[inline(always)]
    fn floor_nonneg(self) -> (i32, Real) {
        let b = floor_nonneg(self);
        (b, b as Real)
    }
}

#[cfg(all(
    target_arch = "wasm32",
    target_feature = "simd128",
    not(feature = "f64")
))]
pub use simd::F4;
#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
pub use sse::F4;

/// Four f32 lanes in one SSE register, for the stencils of the native x86-64 build (SSE2 is
/// part of the baseline). LLVM vectorises the scalar lane loop of [`Kernel::stencil`] only in
/// part, with a shuffle for every other operation (docs/performance.md).
#[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
mod sse {
    use super::ShapeArith;
    use core::arch::x86_64::*;
    use std::ops::{Add, Mul, Sub};

    /// Runs SSE2 intrinsics.
    macro_rules! sse {
        ($e:expr) => {
            // SAFETY: the intrinsics' only requirement is the CPU feature they are marked
            // with, SSE or SSE2, which every x86-64 CPU has (the target's baseline enables
            // both); none of those called through this macro reads or writes memory.
            unsafe { $e }
        };
    }

    #[derive(Clone, Copy, Debug)]
    pub struct F4(__m128);

    impl F4 {
        #[inline(always)]
        pub fn new(x: [f32; 4]) -> Self {
            F4(sse!(_mm_setr_ps(x[0], x[1], x[2], x[3])))
        }
        #[inline(always)]
        pub fn store(self, to: &mut [f32; 4]) {
            // SAFETY: `to` is valid for writes of 16 bytes (four f32), and `_mm_storeu_ps` has
            // no alignment requirement.
            unsafe { _mm_storeu_ps(to.as_mut_ptr(), self.0) }
        }
        /// Bit `a` set where lane `a` equals zero (±0; not NaN).
        #[inline(always)]
        pub fn zero_lanes(self) -> u32 {
            sse!(_mm_movemask_ps(_mm_cmpeq_ps(self.0, _mm_setzero_ps()))) as u32
        }
    }
    macro_rules! binop {
        ($tr:ident, $f:ident, $op:ident) => {
            impl $tr for F4 {
                type Output = F4;
                #[inline(always)]
                fn $f(self, o: F4) -> F4 {
                    F4(sse!($op(self.0, o.0)))
                }
            }
        };
    }
    binop!(Add, add, _mm_add_ps);
    binop!(Sub, sub, _mm_sub_ps);
    binop!(Mul, mul, _mm_mul_ps);
    impl ShapeArith for F4 {
        type Int = [i32; 4];
        #[inline(always)]
        fn splat(x: f32) -> Self {
            F4(sse!(_mm_set1_ps(x)))
        }
        #[inline(always)]
        fn abs(self) -> Self {
            // Clears the sign bit, as `f32::abs`.
            F4(sse!(_mm_andnot_ps(_mm_set1_ps(-0.0), self.0)))
        }
        #[inline(always)]
        fn clamp(self, lo: f32, hi: f32) -> Self {
            // maxps(a, b) = a > b ? a : b and minps(a, b) = a < b ? a : b, so with the bound
            // first a NaN lane stays NaN: `if x < lo { lo }`, then `if x > hi { hi }`, as
            // `f32::clamp`.
            let x = sse!(_mm_max_ps(_mm_set1_ps(lo), self.0));
            F4(sse!(_mm_min_ps(_mm_set1_ps(hi), x)))
        }
        #[inline(always)]
        fn max0(self) -> Self {
            // x > 0 ? x : 0, as `math::max(x, 0)` (0 for NaN).
            F4(sse!(_mm_max_ps(self.0, _mm_setzero_ps())))
        }
        #[inline(always)]
        fn floor_nonneg(self) -> ([i32; 4], Self) {
            // As `super::floor_nonneg`: the clamp to [0, 2^22] (0 for NaN), then truncation,
            // which is the floor of a number ≥ 0.
            let c = sse!(_mm_max_ps(self.0, _mm_setzero_ps()));
            let c = sse!(_mm_min_ps(c, _mm_set1_ps(4_194_304.0)));
            let n = sse!(_mm_cvttps_epi32(c));
            let mut out = [0i32; 4];
            // SAFETY: `out` is valid for writes of 16 bytes (four i32), and
            // `_mm_storeu_si128` has no alignment requirement.
            unsafe { _mm_storeu_si128(out.as_mut_ptr().cast::<__m128i>(), n) };
            (out, F4(sse!(_mm_cvtepi32_ps(n))))
        }
    }
}

/// Four f32 lanes in one `v128`, for the stencils of the WebAssembly build.
#[cfg(all(
    target_arch = "wasm32",
    target_feature = "simd128",
    not(feature = "f64")
))]
mod simd {
    use super::ShapeArith;
    use core::arch::wasm32::*;
    use std::ops::{Add, Mul, Sub};

    #[derive(Clone, Copy, Debug)]
    pub struct F4(v128);

    impl F4 {
        #[inline(always)]
        pub fn new(x: [f32; 4]) -> Self {
            F4(f32x4(x[0], x[1], x[2], x[3]))
        }
        #[inline(always)]
        pub fn store(self, to: &mut [f32; 4]) {
            // SAFETY: `to` is valid for writes of 16 bytes (four f32), and `v128_store` has no
            // alignment requirement.
            unsafe { v128_store(to.as_mut_ptr().cast::<v128>(), self.0) }
        }
        /// Bit `a` set where lane `a` equals zero (±0; not NaN).
        #[inline(always)]
        pub fn zero_lanes(self) -> u32 {
            i32x4_bitmask(f32x4_eq(self.0, f32x4_splat(0.0))) as u32
        }
    }
    macro_rules! binop {
        ($tr:ident, $f:ident, $op:ident) => {
            impl $tr for F4 {
                type Output = F4;
                #[inline(always)]
                fn $f(self, o: F4) -> F4 {
                    F4($op(self.0, o.0))
                }
            }
        };
    }
    binop!(Add, add, f32x4_add);
    binop!(Sub, sub, f32x4_sub);
    binop!(Mul, mul, f32x4_mul);
    impl ShapeArith for F4 {
        type Int = [i32; 4];
        #[inline(always)]
        fn splat(x: f32) -> Self {
            F4(f32x4_splat(x))
        }
        #[inline(always)]
        fn abs(self) -> Self {
            F4(f32x4_abs(self.0))
        }
        #[inline(always)]
        fn clamp(self, lo: f32, hi: f32) -> Self {
            // pmax(a, b) = a < b ? b : a and pmin(a, b) = b < a ? b : a: `if x < lo { lo }`,
            // then `if x > hi { hi }`, as `f32::clamp`.
            let x = f32x4_pmax(self.0, f32x4_splat(lo));
            F4(f32x4_pmin(x, f32x4_splat(hi)))
        }
        #[inline(always)]
        fn max0(self) -> Self {
            // pmax(0, x) = 0 < x ? x : 0, as `math::max(x, 0)`.
            F4(f32x4_pmax(f32x4_splat(0.0), self.0))
        }
        #[inline(always)]
        fn floor_nonneg(self) -> ([i32; 4], Self) {
            // As `super::floor_nonneg`: pmax(0, x) = 0 < x ? x : 0 (0 for NaN), then
            // pmin(2^22, c) = c < 2^22 ? c : 2^22.
            let c = f32x4_pmax(f32x4_splat(0.0), self.0);
            let c = f32x4_pmin(f32x4_splat(4_194_304.0), c);
            let fl = f32x4_floor(c);
            // An integer 0 ≤ n ≤ 2^22 plus 2^23 is exact, with n in the low mantissa bits.
            let n = i32x4_sub(
                f32x4_add(fl, f32x4_splat(8_388_608.0)),
                i32x4_splat(0x4b00_0000),
            );
            (
                [
                    i32x4_extract_lane::<0>(n),
                    i32x4_extract_lane::<1>(n),
                    i32x4_extract_lane::<2>(n),
                    i32x4_extract_lane::<3>(n),
                ],
                F4(fl),
            )
        }
    }
}

/// The kernel weights of one particle along each axis: `w[k][a]` and `dw[k][a]` (the
/// derivative, already divided by the cell size) for the k-th node of the stencil along axis a,
/// whose first node has grid index `base[a]`; `d[k][a]` is that node's offset from the particle
/// along the axis, in cells (x_i − x_p = d h). Node-major with four lanes, so that a kernel
/// computes all axes of one node at once in SIMD registers (lane 3, and lane 2 in 2D, unused).
/// Only the first `reach[a]` nodes along axis `a` carry weight: the rest have weight and
/// derivative exactly zero, and the stencil walks skip them.
#[derive(Clone, Copy, Debug)]
pub struct Stencil<const S: usize> {
    pub base: [i32; 3],
    pub w: [[Real; 4]; S],
    pub dw: [[Real; 4]; S],
    pub d: [[Real; 4]; S],
    pub reach: [usize; 3],
}

impl<const S: usize> Stencil<S> {
    /// A stencil with first node `base` and all weights zero, for a kernel to fill in.
    #[inline(always)]
    pub fn at(base: [i32; 3]) -> Self {
        Stencil {
            base,
            w: [[0.0; 4]; S],
            dw: [[0.0; 4]; S],
            d: [[0.0; 4]; S],
            reach: [S; 3],
        }
    }
}

/// The shape function of a simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum KernelKind {
    /// The paper's multilinear shape function (2 nodes per axis).
    Linear,
    /// The quadratic B-spline (3 nodes per axis), C¹: no cell-crossing error.
    QuadraticBspline,
    /// uGIMP (Bardenhagen & Kober 2004): the linear kernel averaged over each particle's
    /// domain of half-width h/(2 × particles per cell); C¹, up to 3 nodes per axis.
    #[default]
    Gimp,
}

impl KernelKind {
    /// Nodes per axis of the stencil.
    pub fn support(self) -> usize {
        match self {
            KernelKind::Linear => 2,
            KernelKind::QuadraticBspline | KernelKind::Gimp => 3,
        }
    }
}

/// A shape function with `S` nodes per axis.
pub trait Kernel<const S: usize>: Copy + Send + Sync + 'static {
    const KIND: KernelKind;
    /// The first stencil node along one axis for a particle at grid coordinate `xg` of
    /// half-width `lp` grid units (used by GIMP only), as an integer and as a [`Real`].
    fn first<L: ShapeArith>(xg: L, lp: Real) -> (L::Int, L);

    /// Weight and derivative (per grid unit) of the k-th stencil node for a particle at
    /// fractional offset `f` from the first node.
    fn node<L: ShapeArith>(f: L, k: usize, lp: Real) -> (L, L);

    /// Base node index, weights and weight derivatives (per grid unit) along one axis.
    #[inline(always)]
    fn axis(xg: Real, lp: Real) -> (i32, [Real; S], [Real; S]) {
        let (base, first) = Self::first(xg, lp);
        let f = xg - first;
        let (mut w, mut dw) = ([0.0; S], [0.0; S]);
        for k in 0..S {
            (w[k], dw[k]) = Self::node(f, k, lp);
        }
        (base, w, dw)
    }

    /// The first stencil node of a particle at grid coordinates `xg`.
    #[inline(always)]
    fn base(xg: [Real; 3], dim: usize, lp: Real) -> [i32; 3] {
        let mut b = [0; 3];
        for a in 0..dim {
            b[a] = Self::first(xg[a], lp).0;
        }
        b
    }

    /// The full stencil of a particle at grid coordinates `xg` (the first `dim` entries used),
    /// with derivatives scaled by `inv_h` to physical units. All axes go through the same
    /// arithmetic in four lanes (the compiler keeps them in one SIMD register); the unused lanes
    /// repeat the last axis.
    #[inline(always)]
    fn stencil(xg: [Real; 3], dim: usize, inv_h: Real, lp: Real) -> Stencil<S> {
        let last = xg[dim - 1];
        let x = [xg[0], xg[1], if dim == 3 { xg[2] } else { last }, last];
        stencil_of_lanes::<S, Self>(x, inv_h, lp)
    }

    /// The stencils of two 2D particles at grid coordinates `a` and `b` — packing
    /// specialisation of [`Kernel::stencil`]: a 2D stencil uses two of the four lanes, so
    /// both particles' axes go through the lanes at once, (a_x, a_y, b_x, b_y). Each comes
    /// out laid out as [`Kernel::stencil`] lays it out, bit for bit (a test checks it).
    ///
    /// The lanes are computed by the scalar loop: in four SIMD lanes the pairs cost the 2D
    /// sand block's stress pass more than they save elsewhere (docs/performance.md).
    #[inline(always)]
    fn stencil_pair_2d(a: [Real; 3], b: [Real; 3], inv_h: Real, lp: Real) -> [Stencil<S>; 2] {
        let (base, st) = stencil_lanes_scalar::<S, Self>([a[0], a[1], b[0], b[1]], inv_h, lp);
        [
            Stencil::from_lanes(Self::KIND, &st, [base[0], base[1], base[1]], [0, 1, 1, 1]),
            Stencil::from_lanes(Self::KIND, &st, [base[2], base[3], base[3]], [2, 3, 3, 3]),
        ]
    }
}

/// Weights, derivatives and offsets in four lanes, as [`stencil_lanes`] computes them.
#[derive(Clone, Copy)]
struct LaneStencil<const S: usize> {
    w: [[Real; 4]; S],
    dw: [[Real; 4]; S],
    d: [[Real; 4]; S],
}

impl<const S: usize> Stencil<S> {
    /// The stencil whose axis `a` is lane `lanes[a]` of `st`, for kernel `kind`.
    #[inline(always)]
    fn from_lanes(
        kind: KernelKind,
        st: &LaneStencil<S>,
        base: [i32; 3],
        lanes: [usize; 4],
    ) -> Self {
        let pick = |r: &[Real; 4]| lanes.map(|l| r[l]);
        let w = st.w.map(|r| pick(&r));
        // GIMP's last node along an axis has weight and derivative exactly zero where the
        // particle's domain does not reach past the middle node (half the positions at two
        // particles per cell): w = 0 there because hi = lo = −1 in `Gimp::shape`.
        let reach = [0, 1, 2].map(|a| {
            if kind == KernelKind::Gimp && w[S - 1][a] == 0.0 {
                S - 1
            } else {
                S
            }
        });
        Stencil {
            base,
            w,
            dw: st.dw.map(|r| pick(&r)),
            d: st.d.map(|r| pick(&r)),
            reach,
        }
    }
}

/// Whether this build evaluates stencils in four SIMD lanes ([`F4`]): natively on x86-64
/// (SSE2), and in WebAssembly with simd128.
macro_rules! simd_stencils {
    ($($item:item)*) => {$(
        #[cfg(all(
            any(target_arch = "x86_64", all(target_arch = "wasm32", target_feature = "simd128")),
            not(feature = "f64")
        ))]
        $item
    )*};
}
/// The opposite of [`simd_stencils`].
macro_rules! scalar_stencils {
    ($($item:item)*) => {$(
        #[cfg(not(all(
            any(target_arch = "x86_64", all(target_arch = "wasm32", target_feature = "simd128")),
            not(feature = "f64")
        )))]
        $item
    )*};
}

// [`Kernel::stencil`] of the lanes `x`: in the build's SIMD lanes where it has them, else
// one lane at a time.
simd_stencils! {
    use self::stencil_simd as stencil_of_lanes;
}
scalar_stencils! {
    use self::stencil_scalar as stencil_of_lanes;
}

/// [`Kernel::stencil`] of the lanes `x` by the scalar lane loop: the reference for
/// [`stencil_simd`], and the version of builds without SIMD lanes.
#[cfg_attr(not(test), allow(dead_code))] // only the tests call it where the build has lanes
#[inline(always)]
fn stencil_scalar<const S: usize, K: Kernel<S>>(x: [Real; 4], inv_h: Real, lp: Real) -> Stencil<S> {
    let (base, st) = stencil_lanes_scalar::<S, K>(x, inv_h, lp);
    Stencil::from_lanes(K::KIND, &st, [base[0], base[1], base[2]], [0, 1, 2, 3])
}

/// The weights, derivatives and offsets of a stencil's four lanes, one lane at a time (for
/// [`stencil_scalar`] and [`Kernel::stencil_pair_2d`]).
#[inline(always)]
fn stencil_lanes_scalar<const S: usize, K: Kernel<S>>(
    x: [Real; 4],
    inv_h: Real,
    lp: Real,
) -> ([i32; 4], LaneStencil<S>) {
    let mut base = [0i32; 4];
    let mut f = [0.0; 4];
    for a in 0..4 {
        let first;
        (base[a], first) = K::first(x[a], lp);
        f[a] = x[a] - first;
    }
    let mut st = LaneStencil {
        w: [[0.0; 4]; S],
        dw: [[0.0; 4]; S],
        d: [[0.0; 4]; S],
    };
    for k in 0..S {
        for a in 0..4 {
            let (w, dw) = K::node(f[a], k, lp);
            st.w[k][a] = w;
            st.dw[k][a] = dw * inv_h;
            st.d[k][a] = k as Real - f[a];
        }
    }
    (base, st)
}

simd_stencils! {
    /// [`stencil_scalar`] in four SIMD lanes ([`F4`]) — SIMD specialisation: the same
    /// arithmetic lane by lane, bit for bit (tests compare the two, natively and in wasm),
    /// each row stored straight into the stencil and GIMP's reach read from one compare of
    /// the last row. Natively LLVM vectorises the scalar loop only in part, with shuffles
    /// between most operations; for wasm32 not at all, and V8 compiles each clamp to two
    /// branches (docs/performance.md).
    #[inline(always)]
    fn stencil_simd<const S: usize, K: Kernel<S>>(x: [Real; 4], inv_h: Real, lp: Real) -> Stencil<S> {
        let x = F4::new(x);
        let (base, first) = K::first(x, lp);
        let f = x - first;
        let mut st = Stencil::at([base[0], base[1], base[2]]);
        for k in 0..S {
            let (w, dw) = K::node(f, k, lp);
            w.store(&mut st.w[k]);
            (dw * F4::splat(inv_h)).store(&mut st.dw[k]);
            (F4::splat(k as Real) - f).store(&mut st.d[k]);
            if K::KIND == KernelKind::Gimp && k == S - 1 {
                // as `Stencil::from_lanes` finds it: one bit per lane whose weight is zero
                let zero = w.zero_lanes();
                st.reach = [0, 1, 2].map(|a| S - ((zero >> a) & 1) as usize);
            }
        }
        st
    }
}

/// The paper's linear shape function (Eq. 16–17): N = ½(1 + N_x N_Ix) per axis.
#[derive(Clone, Copy, Debug)]
pub struct Linear;

/// The least offset of a particle from its first node under the linear kernel, in cells.
pub const LINEAR_NUDGE: Real = 1e-6;

impl Kernel<2> for Linear {
    const KIND: KernelKind = KernelKind::Linear;
    #[inline(always)]
    fn first<L: ShapeArith>(xg: L, _lp: Real) -> (L::Int, L) {
        xg.floor_nonneg()
    }
    /// A particle on a node line (f = 0 exactly, as happens when x/h rounds to a whole number
    /// in f32) is moved a millionth of a cell past it: else the second node gets weight 0 but
    /// gradient 1/h, so a force on no mass (dropped: momentum lost) and a velocity of 0 in the
    /// particle's velocity gradient (a translating body strained from nothing). Beyond 16
    /// cells the nudge is under one f32 step of x/h: the stencil is that of the next position
    /// a particle can have, one the kernel meets as often (docs/stability.md).
    #[inline(always)]
    fn node<L: ShapeArith>(f: L, k: usize, _lp: Real) -> (L, L) {
        let f = f.clamp(LINEAR_NUDGE, 1.0);
        if k == 0 {
            (L::splat(1.0) - f, L::splat(-1.0))
        } else {
            (f, L::splat(1.0))
        }
    }
}

/// The quadratic B-spline.
#[derive(Clone, Copy, Debug)]
pub struct QuadraticBspline;

impl Kernel<3> for QuadraticBspline {
    const KIND: KernelKind = KernelKind::QuadraticBspline;
    #[inline(always)]
    fn first<L: ShapeArith>(xg: L, _lp: Real) -> (L::Int, L) {
        (xg - L::splat(0.5)).floor_nonneg()
    }
    #[inline(always)]
    fn node<L: ShapeArith>(f: L, k: usize, _lp: Real) -> (L, L) {
        let s = L::splat;
        match k {
            0 => (s(0.5) * (s(1.5) - f) * (s(1.5) - f), f - s(1.5)),
            1 => (
                s(0.75) - (f - s(1.0)) * (f - s(1.0)),
                s(-2.0) * (f - s(1.0)),
            ),
            _ => (s(0.5) * (f - s(0.5)) * (f - s(0.5)), f - s(0.5)),
        }
    }
}

/// uGIMP: the linear hat averaged over a particle domain of half-width `lp` (grid units,
/// at most ½).
#[derive(Clone, Copy, Debug)]
pub struct Gimp;

impl Gimp {
    /// Weight and derivative for a node at signed distance `xi` (grid units): the average of
    /// the hat N(s) = max(0, 1 − |s|) over [xi − lp, xi + lp], written with the hat's
    /// antiderivative H(s) = ½ + c − ½ c|c| (c = s clamped to [−1, 1]) so that it has no branch:
    /// w = (H(hi) − H(lo)) / 2lp and dw = (N(hi) − N(lo)) / 2lp with hi, lo = xi ± lp clamped.
    ///
    /// H(hi) − H(lo) is formed as (hi − lo)(1 − ½(|hi| + |lo|)) + max(0, −hi lo), which equals
    /// it whether or not [lo, hi] straddles 0, so that it never subtracts two numbers near 1:
    /// where the particle's domain barely reaches the node (hi = 1, lo = 1 − δ) it gives
    /// w = δ²/4lp to full precision, consistent with dw = −δ/2lp. (The plain difference left
    /// w at zero there while dw was not, and a node of next to no mass took a finite force.)
    #[inline(always)]
    fn shape<L: ShapeArith>(xi: L, lp: Real, inv_2lp: Real) -> (L, L) {
        let hi = (xi + L::splat(lp)).clamp(-1.0, 1.0);
        let lo = (xi - L::splat(lp)).clamp(-1.0, 1.0);
        let (ahi, alo) = (hi.abs(), lo.abs());
        let straddle = (L::splat(0.0) - hi * lo).max0();
        let w = ((hi - lo) * (L::splat(1.0) - L::splat(0.5) * (ahi + alo)) + straddle)
            * L::splat(inv_2lp);
        let dw = (alo - ahi) * L::splat(inv_2lp);
        (w, dw)
    }
}

impl Kernel<3> for Gimp {
    const KIND: KernelKind = KernelKind::Gimp;
    #[inline(always)]
    fn first<L: ShapeArith>(xg: L, lp: Real) -> (L::Int, L) {
        (xg - L::splat(lp)).floor_nonneg()
    }
    #[inline(always)]
    fn node<L: ShapeArith>(f: L, k: usize, lp: Real) -> (L, L) {
        Self::shape(f - L::splat(k as Real), lp, 0.5 / lp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_partition<const S: usize, K: Kernel<S>>(lp: Real) {
        for i in 0..200 {
            let xg = 3.0 + i as Real * 0.0137;
            let (base, w, dw) = K::axis(xg, lp);
            let sum: Real = w.iter().sum();
            let dsum: Real = dw.iter().sum();
            // Partition of unity and linear completeness: Σ w = 1, Σ w x_i = x, Σ dw = 0, Σ dw x_i = 1.
            let first: Real = (0..S).map(|k| w[k] * (base + k as i32) as Real).sum();
            let dfirst: Real = (0..S).map(|k| dw[k] * (base + k as i32) as Real).sum();
            assert!((sum - 1.0).abs() < 1e-5, "{:?} sum {sum}", K::KIND);
            assert!(dsum.abs() < 1e-5);
            assert!((first - xg).abs() < 1e-4, "{:?} at {xg}: {first}", K::KIND);
            assert!((dfirst - 1.0).abs() < 1e-4);
            assert!(w.iter().all(|&v| v >= 0.0));
        }
    }

    fn check_stencil<const S: usize, K: Kernel<S>>(lp: Real) {
        let inv_h = 50.0;
        for i in 0..300 {
            let xg = [
                3.0 + i as Real * 0.0137,
                4.1 + i as Real * 0.0071,
                2.5 + i as Real * 0.011,
            ];
            for dim in [2, 3] {
                let st = K::stencil(xg, dim, inv_h, lp);
                for a in 0..dim {
                    let (base, w, dw) = K::axis(xg[a], lp);
                    assert_eq!(st.base[a], base);
                    for k in 0..S {
                        assert!((st.w[k][a] - w[k]).abs() < 1e-6, "{:?} w {a} {k}", K::KIND);
                        assert!((st.dw[k][a] - dw[k] * inv_h).abs() < 1e-4 * inv_h);
                        let d = (base + k as i32) as Real - xg[a];
                        assert!((st.d[k][a] - d).abs() < 1e-5);
                    }
                }
            }
        }
    }

    #[test]
    fn stencils_give_every_axis_what_the_one_axis_kernel_gives() {
        check_stencil::<2, Linear>(0.0);
        check_stencil::<3, QuadraticBspline>(0.0);
        check_stencil::<3, Gimp>(0.25);
    }

    /// Two 2D stencils evaluated in one set of lanes are the two single ones, bit for bit.
    fn check_pairs<const S: usize, K: Kernel<S>>(lp: Real) {
        let inv_h = 50.0;
        for i in 0..300 {
            let a = [3.0 + i as Real * 0.0137, 4.1 + i as Real * 0.0071, 0.0];
            let b = [2.5 + i as Real * 0.011, 7.3 - i as Real * 0.0093, 0.0];
            let [sa, sb] = K::stencil_pair_2d(a, b, inv_h, lp);
            for (pair, single) in [
                (sa, K::stencil(a, 2, inv_h, lp)),
                (sb, K::stencil(b, 2, inv_h, lp)),
            ] {
                assert_eq!(pair.base[..2], single.base[..2]);
                let bits =
                    |s: &Stencil<S>| [s.w, s.dw, s.d].map(|r| r.map(|l| l.map(Real::to_bits)));
                assert_eq!(bits(&pair), bits(&single), "{:?} at {a:?}, {b:?}", K::KIND);
            }
        }
    }

    simd_stencils! {
        /// The SIMD stencils give what the scalar lane loop gives, bit for bit, for every
        /// kernel, at node positions, ties and the values the floor clamps (huge, infinite,
        /// NaN).
        #[test]
        fn simd_stencils_equal_the_scalar_lanes_bit_for_bit() {
            fn bits<const S: usize>(st: &Stencil<S>) -> ([i32; 3], [usize; 3], Vec<u32>) {
                let all = [st.w, st.dw, st.d];
                let v = all
                    .iter()
                    .flatten()
                    .flatten()
                    .map(|v| v.to_bits())
                    .collect();
                (st.base, st.reach, v)
            }
            fn check<const S: usize, K: Kernel<S>>(lp: Real) {
                let mut xs: Vec<Real> = (0..2000).map(|i| 2.0 + i as Real * 0.003_71).collect();
                xs.extend([
                    0.5,
                    0.75,
                    1.0,
                    3.0,
                    3.5,
                    1e30,
                    4_194_304.0,
                    Real::INFINITY,
                    Real::NAN,
                ]);
                for (i, &x) in xs.iter().enumerate() {
                    let pick = |m: usize, c: usize| xs[(i * m + c) % xs.len()];
                    let lanes = [x, pick(7, 3), pick(13, 5), pick(3, 11)];
                    let scalar = stencil_scalar::<S, K>(lanes, 25.0, lp);
                    let simd = stencil_simd::<S, K>(lanes, 25.0, lp);
                    assert_eq!(bits(&scalar), bits(&simd), "{:?} at {lanes:?}", K::KIND);
                }
            }
            check::<2, Linear>(0.0);
            check::<3, QuadraticBspline>(0.0);
            for lp in [0.125, 0.25, 0.5] {
                check::<3, Gimp>(lp);
            }
        }
    }

    #[test]
    fn stencils_in_pairs_are_the_single_ones() {
        check_pairs::<2, Linear>(0.0);
        check_pairs::<3, QuadraticBspline>(0.0);
        check_pairs::<3, Gimp>(0.25);
    }

    #[test]
    fn floor_nonneg_truncates_and_clamps_what_is_out_of_range() {
        for (x, n) in [
            (0.0, 0),
            (0.999, 0),
            (1.0, 1),
            (7.5, 7),
            (4_194_304.0, 4_194_304),
        ] {
            assert_eq!(floor_nonneg(x), n, "{x}");
        }
        for (x, n) in [
            (1e30, 4_194_304),
            (Real::INFINITY, 4_194_304),
            (Real::NAN, 0),
        ] {
            assert_eq!(floor_nonneg(x), n, "{x}");
        }
    }

    #[test]
    fn kernels_reproduce_constants_and_linear_fields() {
        check_partition::<2, Linear>(0.0);
        check_partition::<3, QuadraticBspline>(0.0);
        for lp in [0.125, 0.25, 0.5] {
            check_partition::<3, Gimp>(lp);
        }
    }

    #[test]
    fn linear_kernel_matches_the_papers_natural_coordinates() {
        // Eq. 16-17 in 1D: N_I(x) = ½(1 + N_x N_I) with N_x = 2(x - x_c)/h, N_I = ±1.
        let xg: Real = 5.3;
        let (base, w, _) = Linear::axis(xg, 0.0);
        let nx = 2.0 * (xg - (base as Real + 0.5));
        assert!((w[0] - 0.5 * (1.0 - nx)).abs() < 1e-6);
        assert!((w[1] - 0.5 * (1.0 + nx)).abs() < 1e-6);
    }

    #[test]
    fn gimp_matches_the_linear_field_average_and_has_continuous_gradients() {
        let lp = 0.25;
        // A particle whose domain lies inside one cell interpolates like the linear kernel.
        let (b, w, _) = Gimp::axis(5.5, lp);
        let (bl, wl, _) = Linear::axis(5.5, 0.0);
        for k in 0..3 {
            let n = b + k as i32;
            let lin = if n == bl {
                wl[0]
            } else if n == bl + 1 {
                wl[1]
            } else {
                0.0
            };
            assert!((w[k] - lin).abs() < 1e-6);
        }
        let eps = 1e-4;
        for x0 in [5.0 - lp, 5.0, 5.0 + lp, 5.75] {
            let (b0, _, d0) = Gimp::axis(x0 - eps, lp);
            let (b1, _, d1) = Gimp::axis(x0 + eps, lp);
            for k in 0..3 {
                if let Some(k1) = (0..3).find(|&k1| b1 + k1 as i32 == b0 + k as i32) {
                    assert!((d0[k] - d1[k1]).abs() < 1e-2, "jump at {x0}");
                }
            }
        }
    }

    /// Where a particle's domain barely reaches a node, GIMP's weight is δ²/4lp and its
    /// derivative δ/2lp (δ: how far the domain reaches past the hat's edge), so that
    /// w = lp dw² holds to rounding however small δ is: a node never receives a force
    /// without the mass that goes with it.
    #[test]
    fn gimp_weight_and_gradient_vanish_together_at_the_edge() {
        let lp: Real = 0.25;
        for e in 1..=20 {
            let delta = (2.0 as Real).powi(-e);
            // node 4 just reached from the right, node 6 from the left
            for (xg, node) in [(4.0 + (1.0 + lp - delta), 4), (6.0 - (1.0 + lp - delta), 6)] {
                let (base, w, dw) = Gimp::axis(xg, lp);
                let k = (node - base) as usize;
                let exact = lp * dw[k] * dw[k];
                assert!(exact > 0.0, "δ = {delta:e}: node {node} out of reach");
                assert!(
                    (w[k] - exact).abs() <= 1e-3 * exact,
                    "δ = {delta:e}, node {node}: w = {:e}, lp dw² = {exact:e}",
                    w[k]
                );
            }
        }
    }

    #[test]
    fn bspline_gradient_is_continuous_across_cells() {
        let eps = 1e-3;
        for n in 3..6 {
            for off in [0.0, 0.5] {
                let x0 = n as Real + off;
                let (b0, _, d0) = QuadraticBspline::axis(x0 - eps, 0.0);
                let (b1, _, d1) = QuadraticBspline::axis(x0 + eps, 0.0);
                // compare the derivative of the weight of the same node on both sides
                for k in 0..3 {
                    let node = b0 + k as i32;
                    if let Some(k1) = (0..3).find(|&k1| b1 + k1 as i32 == node) {
                        assert!((d0[k] - d1[k1]).abs() < 1e-2, "jump at {x0}");
                    }
                }
            }
        }
    }
}
