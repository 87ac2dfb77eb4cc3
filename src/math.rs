//! Scalars, vectors and symmetric stress tensors, and the [`Dim`] trait that carries them
//! for the two dimensions the solver is monomorphised for.
//!
//! 2D is *plane strain*: the in-plane velocity has two components, but the stress keeps its
//! out-of-plane normal component σ_zz (ε_zz = 0), so that the invariants I1 and J2 that the
//! yield criteria use are those of the real 3D stress state. Masses, volumes and energies in
//! 2D are per unit depth (kg/m, m², J/m).

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Div, Index, IndexMut, Mul, MulAssign, Neg, Sub, SubAssign};

#[cfg(not(feature = "f64"))]
mod precision {
    /// The floating-point type of particle and grid state.
    pub type Real = f32;
    pub type Vec2 = glam::Vec2;
    pub type Vec3 = glam::Vec3;
    pub type Vec3A = glam::Vec3A;
    pub type Vec4 = glam::Vec4;
    pub type Mat2 = glam::Mat2;
    pub type Mat3 = glam::Mat3;
    pub type Mat3A = glam::Mat3A;
    pub type Mat4 = glam::Mat4;
    /// Four values side by side in SIMD lanes (four particles' constitutive updates at once).
    pub type Real4 = glam::Vec4;
}
#[cfg(feature = "f64")]
mod precision {
    /// The floating-point type of particle and grid state.
    pub type Real = f64;
    pub type Vec2 = glam::DVec2;
    pub type Vec3 = glam::DVec3;
    pub type Vec3A = glam::DVec3;
    pub type Vec4 = glam::DVec4;
    pub type Mat2 = glam::DMat2;
    pub type Mat3 = glam::DMat3;
    pub type Mat3A = glam::DMat3;
    pub type Mat4 = glam::DMat4;
    pub type Real4 = glam::DVec4;
}
pub use precision::*;

/// The vector operations the generic solver needs (implemented for glam's `Vec2` and `Vec3`).
pub trait VectorOps:
    Copy
    + Default
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Mul<Real, Output = Self>
    + Div<Real, Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign<Real>
    + Index<usize, Output = Real>
    + IndexMut<usize>
{
    const ZERO: Self;
    fn dot(self, other: Self) -> Real;
    fn length(self) -> Real;
    fn is_finite(self) -> bool;
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    fn splat(value: Real) -> Self;
    /// The vector whose i-th component is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> Real) -> Self;
    /// The vector with a mass in the lane after its last component: a grid node keeps its
    /// momentum (then velocity) and mass in one register, so that one SIMD multiply-add
    /// scatters both (one `Vec4` in both dimensions; in 2D its fourth lane is padding).
    type WithMass: Copy
        + Default
        + Debug
        + Send
        + Sync
        + 'static
        + Add<Output = Self::WithMass>
        + AddAssign
        + Mul<Real, Output = Self::WithMass>;
    fn with_mass(self, m: Real) -> Self::WithMass;
    /// The vector part of a vector with mass.
    fn without_mass(p: Self::WithMass) -> Self;
    /// The mass part of a vector with mass.
    fn mass_of(p: Self::WithMass) -> Real;
    fn length_squared(self) -> Real {
        self.dot(self)
    }
}

macro_rules! impl_vector_ops {
    ($t:ty, $n:expr, $wm:ty, $add:expr, $drop:expr) => {
        impl VectorOps for $t {
            const ZERO: Self = <$t>::ZERO;
            type WithMass = $wm;
            #[inline(always)]
            fn with_mass(self, m: Real) -> $wm {
                $add(self, m)
            }
            #[inline(always)]
            fn without_mass(p: $wm) -> Self {
                $drop(p)
            }
            #[inline(always)]
            fn mass_of(p: $wm) -> Real {
                p[$n]
            }
            #[inline(always)]
            fn dot(self, other: Self) -> Real {
                <$t>::dot(self, other)
            }
            #[inline(always)]
            fn length(self) -> Real {
                <$t>::length(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                <$t>::min(self, other)
            }
            #[inline(always)]
            fn max(self, other: Self) -> Self {
                <$t>::max(self, other)
            }
            #[inline(always)]
            fn splat(value: Real) -> Self {
                <$t>::splat(value)
            }
            #[inline(always)]
            fn from_fn(mut f: impl FnMut(usize) -> Real) -> Self {
                let mut v = <$t>::ZERO;
                for i in 0..$n {
                    v[i] = f(i);
                }
                v
            }
        }
    };
}
// In 2D the fourth lane is padding: one SIMD multiply-add per node instead of a 2-lane and a
// 1-lane one.
impl_vector_ops!(
    Vec2,
    2,
    Vec4,
    |v: Vec2, m| Vec4::new(v.x, v.y, m, 0.0),
    |p: Vec4| p.truncate().truncate()
);
impl_vector_ops!(Vec3, 3, Vec4, Vec3::extend, Vec4::truncate);
// The lane after z of a `Vec3A` is padding that glam ignores, so the conversion from `Vec4`
// is free and the mass riding along in it never shows.
#[cfg(not(feature = "f64"))]
impl_vector_ops!(Vec3A, 3, Vec4, Vec3A::extend, Vec3A::from_vec4);

/// A symmetric second-order tensor holding a (plane-strain or 3D) stress or strain rate.
///
/// The trace, the double contraction and the deviator are those of the full 3×3 tensor in
/// both dimensions (the 2D tensor carries its zz component).
pub trait SymTensor:
    Copy
    + Default
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Real, Output = Self>
    + AddAssign
{
    /// The number type of the components: [`Real`], or [`Real4`] for four tensors at once.
    type Scalar: Number;
    /// The material spin W = ½(∇v − ∇vᵀ): one component in 2D, three in 3D.
    type Spin: Copy + Debug + Default;
    const ZERO: Self;
    const IDENTITY: Self;
    fn trace(self) -> Self::Scalar;
    /// A : B = Σ_ij A_ij B_ij.
    fn ddot(self, other: Self) -> Self::Scalar;
    fn is_finite(self) -> bool;
    /// Q A Qᵀ with Q the Cayley transform of the spin increment ½ dt W, i.e. the rotation of
    /// the Hughes–Winget integration of the Jaumann rate: orthogonal, so a pure rotation
    /// rotates the stress without changing its invariants.
    fn rotate(self, spin: Self::Spin, dt: Real) -> Self;
    /// The components as a flat slice (2D: xx, yy, zz, xy; 3D: xx, yy, zz, xy, xz, yz).
    fn components(&self) -> &[Self::Scalar];
    /// The tensor times a number of the component type.
    fn scaled(self, k: Self::Scalar) -> Self;
    /// p I.
    fn iso(p: Self::Scalar) -> Self;

    #[inline(always)]
    fn deviator(self) -> Self {
        self - Self::iso(self.trace() * (1.0 / 3.0))
    }
    /// J2 = ½ s : s of the deviator s.
    #[inline(always)]
    fn j2(self) -> Self::Scalar {
        let s = self.deviator();
        s.ddot(s) * 0.5
    }
}

/// A number the constitutive models compute with: one [`Real`], or [`Real4`], four particles'
/// values side by side, so that one model update advances four particles in SIMD lanes. Only
/// what the models need; comparisons are selects, never branches, so that every lane takes the
/// same path.
pub trait Number:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<Real, Output = Self>
    + Sub<Real, Output = Self>
    + Mul<Real, Output = Self>
    + AddAssign
{
    const ZERO: Self;
    const ONE: Self;
    fn splat(x: Real) -> Self;
    fn sqrt(self) -> Self;
    fn abs(self) -> Self;
    /// The smaller of the two (lane by lane), as a compare and select (see [`min`]).
    fn min(self, other: Self) -> Self;
    fn max(self, other: Self) -> Self;
    /// `if a > b { x } else { y }`, lane by lane.
    fn select_gt(a: Self, b: Self, x: Self, y: Self) -> Self;
    /// 1 where `a > b`, else 0, lane by lane (a factor, not a select).
    fn step_gt(a: Self, b: Self) -> Self;
    fn all_finite(self) -> bool;
    /// eˣ, lane by lane.
    fn exp(self) -> Self;
    /// The sum, the smallest and the largest of the lanes.
    fn sum(self) -> Real;
    fn min_element(self) -> Real;
    fn max_element(self) -> Real;
}

impl Number for Real {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Real::abs(self)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        min(self, other)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        max(self, other)
    }
    #[inline(always)]
    fn select_gt(a: Self, b: Self, x: Self, y: Self) -> Self {
        if a > b { x } else { y }
    }
    #[inline(always)]
    fn step_gt(a: Self, b: Self) -> Self {
        (a > b) as u32 as Real
    }
    #[inline(always)]
    fn all_finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn exp(self) -> Self {
        Real::exp(self)
    }
    #[inline(always)]
    fn sum(self) -> Real {
        self
    }
    #[inline(always)]
    fn min_element(self) -> Real {
        self
    }
    #[inline(always)]
    fn max_element(self) -> Real {
        self
    }
}

impl Number for Real4 {
    const ZERO: Self = Real4::ZERO;
    const ONE: Self = Real4::ONE;
    #[inline(always)]
    fn splat(x: Real) -> Self {
        Real4::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real4::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Real4::abs(self)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        Real4::select(self.cmplt(other), self, other)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        Real4::select(self.cmpgt(other), self, other)
    }
    #[inline(always)]
    fn select_gt(a: Self, b: Self, x: Self, y: Self) -> Self {
        Real4::select(a.cmpgt(b), x, y)
    }
    #[inline(always)]
    fn step_gt(a: Self, b: Self) -> Self {
        Real4::select(a.cmpgt(b), Real4::ONE, Real4::ZERO)
    }
    #[inline(always)]
    fn all_finite(self) -> bool {
        self.is_finite()
    }
    #[inline(always)]
    fn exp(self) -> Self {
        Real4::from_array(self.to_array().map(Real::exp))
    }
    #[inline(always)]
    fn sum(self) -> Real {
        self.element_sum()
    }
    #[inline(always)]
    fn min_element(self) -> Real {
        Real4::min_element(self)
    }
    #[inline(always)]
    fn max_element(self) -> Real {
        Real4::max_element(self)
    }
}

/// Eight values side by side: two [`Real4`], whose operations interleave instruction by
/// instruction, so that two groups of four particles' constitutive updates (each a long chain
/// of dependent operations) advance together.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Real4x2(pub Real4, pub Real4);

macro_rules! lanes2_op {
    ($tr:ident, $f:ident) => {
        impl $tr for Real4x2 {
            type Output = Real4x2;
            #[inline(always)]
            fn $f(self, o: Real4x2) -> Real4x2 {
                Real4x2(self.0.$f(o.0), self.1.$f(o.1))
            }
        }
        impl $tr<Real> for Real4x2 {
            type Output = Real4x2;
            #[inline(always)]
            fn $f(self, o: Real) -> Real4x2 {
                Real4x2(self.0.$f(o), self.1.$f(o))
            }
        }
    };
}
lanes2_op!(Add, add);
lanes2_op!(Sub, sub);
lanes2_op!(Mul, mul);
impl Div for Real4x2 {
    type Output = Real4x2;
    #[inline(always)]
    fn div(self, o: Real4x2) -> Real4x2 {
        Real4x2(self.0 / o.0, self.1 / o.1)
    }
}
impl Neg for Real4x2 {
    type Output = Real4x2;
    #[inline(always)]
    fn neg(self) -> Real4x2 {
        Real4x2(-self.0, -self.1)
    }
}
impl AddAssign for Real4x2 {
    #[inline(always)]
    fn add_assign(&mut self, o: Real4x2) {
        self.0 += o.0;
        self.1 += o.1;
    }
}

impl Number for Real4x2 {
    const ZERO: Self = Real4x2(Real4::ZERO, Real4::ZERO);
    const ONE: Self = Real4x2(Real4::ONE, Real4::ONE);
    #[inline(always)]
    fn splat(x: Real) -> Self {
        Real4x2(Real4::splat(x), Real4::splat(x))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Real4x2(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Real4x2(self.0.abs(), self.1.abs())
    }
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        Real4x2(Number::min(self.0, o.0), Number::min(self.1, o.1))
    }
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        Real4x2(Number::max(self.0, o.0), Number::max(self.1, o.1))
    }
    #[inline(always)]
    fn select_gt(a: Self, b: Self, x: Self, y: Self) -> Self {
        Real4x2(
            Real4::select_gt(a.0, b.0, x.0, y.0),
            Real4::select_gt(a.1, b.1, x.1, y.1),
        )
    }
    #[inline(always)]
    fn step_gt(a: Self, b: Self) -> Self {
        Real4x2(Real4::step_gt(a.0, b.0), Real4::step_gt(a.1, b.1))
    }
    #[inline(always)]
    fn all_finite(self) -> bool {
        self.0.is_finite() && self.1.is_finite()
    }
    #[inline(always)]
    fn exp(self) -> Self {
        Real4x2(Number::exp(self.0), Number::exp(self.1))
    }
    #[inline(always)]
    fn sum(self) -> Real {
        self.0.element_sum() + self.1.element_sum()
    }
    #[inline(always)]
    fn min_element(self) -> Real {
        min(self.0.min_element(), self.1.min_element())
    }
    #[inline(always)]
    fn max_element(self) -> Real {
        max(self.0.max_element(), self.1.max_element())
    }
}

/// Below this |a|² (a = ½ Δt ω, the rotation of one step) the stress rotation leaves out its
/// second-order terms (of size 4|a|² |σ|, under 1e-4 of the float resolution, 2.4e-12 in
/// f32). They change nothing a float holds, and kept, they multiply the stress by products
/// of two small numbers that underflow into subnormals whenever the spin is small, as it is
/// in bodies at rest, and x86 cores take a slow path for each subnormal result
/// (docs/performance.md). In 3D, |a|² itself still underflows when one spin component is
/// below 1e-19 (a few particles of a resting block; flushing those cost more than it saved).
const SECOND_ORDER: Real = Real::EPSILON * 2.0e-5;

/// A plane-strain symmetric tensor: in-plane xx, yy, xy and the out-of-plane normal zz.
/// `Sym2<Real4>` holds four of them, component by component.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Sym2<T = Real> {
    pub xx: T,
    pub yy: T,
    pub zz: T,
    pub xy: T,
}

/// A 3D symmetric tensor (`Sym3<Real4>`: four of them).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct Sym3<T = Real> {
    pub xx: T,
    pub yy: T,
    pub zz: T,
    pub xy: T,
    pub xz: T,
    pub yz: T,
}

macro_rules! impl_sym_arith {
    ($t:ident { $($f:ident),* }) => {
        impl<T: Number> Add for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn add(self, o: Self) -> Self { $t { $($f: self.$f + o.$f),* } }
        }
        impl<T: Number> Sub for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn sub(self, o: Self) -> Self { $t { $($f: self.$f - o.$f),* } }
        }
        impl<T: Number> Mul<Real> for $t<T> {
            type Output = Self;
            #[inline(always)]
            fn mul(self, k: Real) -> Self { $t { $($f: self.$f * k),* } }
        }
        impl<T: Number> AddAssign for $t<T> {
            #[inline(always)]
            fn add_assign(&mut self, o: Self) { $(self.$f += o.$f;)* }
        }
        impl<T: Number> $t<T> {
            /// One test for all components: x·0 is ±0 exactly when x is finite (NaN
            /// otherwise), so the sum of the x·0 is finite exactly when every x is.
            #[inline(always)]
            fn all_finite(&self) -> bool { (T::ZERO $(+ self.$f * 0.0)*).all_finite() }
            #[inline(always)]
            fn scale_by(self, k: T) -> Self { $t { $($f: self.$f * k),* } }
        }
        impl $t<Real> {
            /// Four tensors as one of [`Real4`], component by component: the plain
            /// reference for [`Batch::pack`].
            #[inline(always)]
            pub fn pack_plain(s: &[Self; LANES]) -> $t<Real4> {
                $t { $($f: Real4::new(s[0].$f, s[1].$f, s[2].$f, s[3].$f)),* }
            }
            /// The four tensors of one of [`Real4`], component by component: the plain
            /// reference for [`Batch::unpack`].
            #[inline(always)]
            pub fn unpack_plain(l: $t<Real4>) -> [Self; LANES] {
                $(let $f = l.$f.to_array();)*
                std::array::from_fn(|i| $t { $($f: $f[i]),* })
            }
        }
        impl $t<Real4> {
            /// Two tensors of [`Real4`] as one of [`Real4x2`].
            #[inline(always)]
            pub fn zip(a: Self, b: Self) -> $t<Real4x2> {
                $t { $($f: Real4x2(a.$f, b.$f)),* }
            }
            /// The two tensors of [`Real4`] of one of [`Real4x2`].
            #[inline(always)]
            pub fn unzip(l: $t<Real4x2>) -> (Self, Self) {
                ($t { $($f: l.$f.0),* }, $t { $($f: l.$f.1),* })
            }
        }
    };
}
impl_sym_arith!(Sym2 { xx, yy, zz, xy });
impl_sym_arith!(Sym3 {
    xx,
    yy,
    zz,
    xy,
    xz,
    yz
});

/// Particles per SIMD group of the constitutive update.
pub const LANES: usize = 4;

/// A tensor of `Real`s that four at a time make a tensor of [`Real4`] (component by
/// component): the stress pass packs four particles' stresses and rates, updates them in one
/// model call, and unpacks the results.
pub trait Batch: SymTensor<Scalar = Real> {
    type Packed: SymTensor<Scalar = Real4>;
    fn pack(s: &[Self; LANES]) -> Self::Packed;
    fn unpack(l: Self::Packed) -> [Self; LANES];
    fn pack_spin(w: &[Self::Spin; LANES]) -> <Self::Packed as SymTensor>::Spin;
    /// Eight tensors side by side: two of [`Self::Packed`].
    type Packed2: SymTensor<Scalar = Real4x2>;
    fn zip(a: Self::Packed, b: Self::Packed) -> Self::Packed2;
    fn unzip(l: Self::Packed2) -> (Self::Packed, Self::Packed);
    fn zip_spin(
        a: <Self::Packed as SymTensor>::Spin,
        b: <Self::Packed as SymTensor>::Spin,
    ) -> <Self::Packed2 as SymTensor>::Spin;
}

// Packing specialisation: four tensors go into lanes as the rows of a 4×4 matrix (one
// vector load per tensor) transposed by shuffles, and come out the same way, instead of one
// scalar load or store per component. `pack_plain` and `unpack_plain` are the reference a
// test compares them with.
impl Batch for Sym2 {
    type Packed = Sym2<Real4>;
    #[inline(always)]
    fn pack(s: &[Self; LANES]) -> Sym2<Real4> {
        let row = |t: &Sym2| Real4::new(t.xx, t.yy, t.zz, t.xy);
        let m = Mat4::from_cols(row(&s[0]), row(&s[1]), row(&s[2]), row(&s[3])).transpose();
        Sym2 {
            xx: m.x_axis,
            yy: m.y_axis,
            zz: m.z_axis,
            xy: m.w_axis,
        }
    }
    #[inline(always)]
    fn unpack(l: Sym2<Real4>) -> [Self; LANES] {
        let m = Mat4::from_cols(l.xx, l.yy, l.zz, l.xy).transpose();
        std::array::from_fn(|i| {
            let c = m.col(i);
            Sym2 {
                xx: c.x,
                yy: c.y,
                zz: c.z,
                xy: c.w,
            }
        })
    }
    #[inline(always)]
    fn pack_spin(w: &[Real; LANES]) -> Real4 {
        Real4::from_array(*w)
    }
    type Packed2 = Sym2<Real4x2>;
    #[inline(always)]
    fn zip(a: Sym2<Real4>, b: Sym2<Real4>) -> Sym2<Real4x2> {
        Sym2::zip(a, b)
    }
    #[inline(always)]
    fn unzip(l: Sym2<Real4x2>) -> (Sym2<Real4>, Sym2<Real4>) {
        Sym2::unzip(l)
    }
    #[inline(always)]
    fn zip_spin(a: Real4, b: Real4) -> Real4x2 {
        Real4x2(a, b)
    }
}

// Packing specialisation, as for `Sym2`: the six components as two overlapping rows of four
// (xx yy zz xy and zz xy xz yz), each set of rows transposed.
impl Batch for Sym3 {
    type Packed = Sym3<Real4>;
    #[inline(always)]
    fn pack(s: &[Self; LANES]) -> Sym3<Real4> {
        let lo = |t: &Sym3| Real4::new(t.xx, t.yy, t.zz, t.xy);
        let hi = |t: &Sym3| Real4::new(t.zz, t.xy, t.xz, t.yz);
        let a = Mat4::from_cols(lo(&s[0]), lo(&s[1]), lo(&s[2]), lo(&s[3])).transpose();
        let b = Mat4::from_cols(hi(&s[0]), hi(&s[1]), hi(&s[2]), hi(&s[3])).transpose();
        Sym3 {
            xx: a.x_axis,
            yy: a.y_axis,
            zz: a.z_axis,
            xy: a.w_axis,
            xz: b.z_axis,
            yz: b.w_axis,
        }
    }
    #[inline(always)]
    fn unpack(l: Sym3<Real4>) -> [Self; LANES] {
        let a = Mat4::from_cols(l.xx, l.yy, l.zz, l.xy).transpose();
        let b = Mat4::from_cols(l.xz, l.yz, l.xz, l.yz).transpose();
        std::array::from_fn(|i| {
            let (c, d) = (a.col(i), b.col(i));
            Sym3 {
                xx: c.x,
                yy: c.y,
                zz: c.z,
                xy: c.w,
                xz: d.x,
                yz: d.y,
            }
        })
    }
    #[inline(always)]
    fn pack_spin(w: &[[Real; 3]; LANES]) -> [Real4; 3] {
        let row = |v: &[Real; 3]| Real4::new(v[0], v[1], v[2], 0.0);
        let m = Mat4::from_cols(row(&w[0]), row(&w[1]), row(&w[2]), row(&w[3])).transpose();
        [m.x_axis, m.y_axis, m.z_axis]
    }
    type Packed2 = Sym3<Real4x2>;
    #[inline(always)]
    fn zip(a: Sym3<Real4>, b: Sym3<Real4>) -> Sym3<Real4x2> {
        Sym3::zip(a, b)
    }
    #[inline(always)]
    fn unzip(l: Sym3<Real4x2>) -> (Sym3<Real4>, Sym3<Real4>) {
        Sym3::unzip(l)
    }
    #[inline(always)]
    fn zip_spin(a: [Real4; 3], b: [Real4; 3]) -> [Real4x2; 3] {
        std::array::from_fn(|c| Real4x2(a[c], b[c]))
    }
}

impl<T: Number> SymTensor for Sym2<T> {
    type Scalar = T;
    type Spin = T;
    const ZERO: Self = Sym2 {
        xx: T::ZERO,
        yy: T::ZERO,
        zz: T::ZERO,
        xy: T::ZERO,
    };
    const IDENTITY: Self = Sym2 {
        xx: T::ONE,
        yy: T::ONE,
        zz: T::ONE,
        xy: T::ZERO,
    };
    #[inline(always)]
    fn trace(self) -> T {
        self.xx + self.yy + self.zz
    }
    #[inline(always)]
    fn ddot(self, o: Self) -> T {
        self.xx * o.xx + self.yy * o.yy + self.zz * o.zz + self.xy * o.xy * 2.0
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.all_finite()
    }
    #[inline(always)]
    fn rotate(self, w: T, dt: Real) -> Self {
        // Q = [[c, −s], [s, c]]; the increment Q A Qᵀ − A is formed from the small
        // quantities c − 1 and s so that f32 rounding does not bias the norm.
        let a = w * (0.5 * dt);
        // An increment below 1e-18 is set to zero, so that its square and products stay
        // normal numbers (it rotates a stress by less than 1e-18 of its size).
        let a = T::select_gt(a.abs(), T::splat(1e-18), a, T::ZERO);
        let a2 = a * a;
        let inv = T::ONE / (a2 + 1.0);
        let s = a * inv * 2.0;
        // The second-order quantities c − 1 = −2a²/(1 + a²) and s², kept only above
        // `SECOND_ORDER`. A select here, not the 3D rotation's 0/1 factor: with two scalars
        // the select was the faster of the two (docs/performance.md).
        let big = T::splat(SECOND_ORDER);
        let cm = T::select_gt(a2, big, -(a2 * inv * 2.0), T::ZERO);
        let ss = T::select_gt(a2, big, s * s, T::ZERO);
        let c = cm + 1.0;
        let dcc = cm * (cm + 2.0); // c² − 1
        let cs = c * s;
        Sym2 {
            xx: self.xx + (dcc * self.xx - cs * self.xy * 2.0 + ss * self.yy),
            yy: self.yy + (ss * self.xx + cs * self.xy * 2.0 + dcc * self.yy),
            zz: self.zz,
            xy: self.xy + (cs * (self.xx - self.yy) + (dcc - ss) * self.xy),
        }
    }
    fn components(&self) -> &[T] {
        // SAFETY: Sym2 is #[repr(C)] with exactly four fields of type T and no padding (all
        // fields have the same type and alignment), so it has the layout of [T; 4].
        unsafe { std::slice::from_raw_parts(self as *const Self as *const T, 4) }
    }
    #[inline(always)]
    fn scaled(self, k: T) -> Self {
        self.scale_by(k)
    }
    #[inline(always)]
    fn iso(p: T) -> Self {
        Sym2 {
            xx: p,
            yy: p,
            zz: p,
            xy: T::ZERO,
        }
    }
}

impl<T: Number> SymTensor for Sym3<T> {
    type Scalar = T;
    /// (W_xy, W_xz, W_yz).
    type Spin = [T; 3];
    const ZERO: Self = Sym3 {
        xx: T::ZERO,
        yy: T::ZERO,
        zz: T::ZERO,
        xy: T::ZERO,
        xz: T::ZERO,
        yz: T::ZERO,
    };
    const IDENTITY: Self = Sym3 {
        xx: T::ONE,
        yy: T::ONE,
        zz: T::ONE,
        xy: T::ZERO,
        xz: T::ZERO,
        yz: T::ZERO,
    };
    #[inline(always)]
    fn trace(self) -> T {
        self.xx + self.yy + self.zz
    }
    #[inline(always)]
    fn ddot(self, o: Self) -> T {
        self.xx * o.xx
            + self.yy * o.yy
            + self.zz * o.zz
            + (self.xy * o.xy + self.xz * o.xz + self.yz * o.yz) * 2.0
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        self.all_finite()
    }
    #[inline(always)]
    fn rotate(self, w: [T; 3], dt: Real) -> Self {
        // A = ½ dt W is skew with A_xy = p, A_xz = q, A_yz = r; A v = u × v with
        // u = (−r, q, −p), so A² = u uᵀ − |a|² I, and the Cayley transform is
        // Q = (I − A)⁻¹(I + A) = I + B with B = 2 (A + A²) / (1 + |a|²).
        let [p, q, r] = w.map(|c| c * (0.5 * dt));
        let a2 = p * p + q * q + r * r;
        // The second-order terms (A² in B, and B S Bᵀ) are kept only above `SECOND_ORDER`:
        // one factor of each product is multiplied by k (1 or 0, no branch or select, which
        // wasm engines compile as branches that cost more than the multiplications).
        let k = T::step_gt(a2, T::splat(SECOND_ORDER));
        let c = T::ONE / (a2 + 1.0) * 2.0;
        let (ux, uy, uz) = (-r * k, q * k, -p * k);
        let (kxy, kxz, kyz) = (ux * q, ux * -p, uy * -p); // k u_i u_j
        let ka2 = a2 * k;
        let b = [
            [(ux * -r - ka2) * c, (p + kxy) * c, (q + kxz) * c],
            [(kxy - p) * c, (uy * q - ka2) * c, (r + kyz) * c],
            [(kxz - q) * c, (kyz - r) * c, (uz * -p - ka2) * c],
        ];
        // With B small, Q S Qᵀ = S + (B S + S Bᵀ + B S Bᵀ): forming the increment from B
        // keeps f32 rounding from biasing the norm. P = B S; D_ij = P_ij + P_ji + (P Bᵀ)_ij.
        let s = [
            [self.xx, self.xy, self.xz],
            [self.xy, self.yy, self.yz],
            [self.xz, self.yz, self.zz],
        ];
        let pm: [[T; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| b[i][0] * s[0][j] + b[i][1] * s[1][j] + b[i][2] * s[2][j])
        });
        // (P (k B)ᵀ)_ij: k multiplies B before the products, so that they are exact zeros
        // below the threshold instead of underflowing.
        let bk = b.map(|row| row.map(|x| x * k));
        let pb =
            |i: usize, j: usize| pm[i][0] * bk[j][0] + pm[i][1] * bk[j][1] + pm[i][2] * bk[j][2];
        Sym3 {
            xx: self.xx + (pm[0][0] * 2.0 + pb(0, 0)),
            yy: self.yy + (pm[1][1] * 2.0 + pb(1, 1)),
            zz: self.zz + (pm[2][2] * 2.0 + pb(2, 2)),
            xy: self.xy + (pm[0][1] + pm[1][0] + pb(0, 1)),
            xz: self.xz + (pm[0][2] + pm[2][0] + pb(0, 2)),
            yz: self.yz + (pm[1][2] + pm[2][1] + pb(1, 2)),
        }
    }
    fn components(&self) -> &[T] {
        // SAFETY: Sym3 is #[repr(C)] with exactly six fields of type T and no padding (all
        // fields have the same type and alignment), so it has the layout of [T; 6].
        unsafe { std::slice::from_raw_parts(self as *const Self as *const T, 6) }
    }
    #[inline(always)]
    fn scaled(self, k: T) -> Self {
        self.scale_by(k)
    }
    #[inline(always)]
    fn iso(p: T) -> Self {
        Sym3 {
            xx: p,
            yy: p,
            zz: p,
            xy: T::ZERO,
            xz: T::ZERO,
            yz: T::ZERO,
        }
    }
}

/// The dimension of a simulation: its vector, gradient and stress types.
/// Implemented by the marker types [`D2`] and [`D3`]; `Simulation<D>` is written once.
pub trait Dim: Copy + Default + Debug + Send + Sync + 'static {
    const DIM: usize;
    /// Grid blocks are `2^LOG_BLOCK` nodes along each axis.
    const LOG_BLOCK: u32;
    type Vector: VectorOps;
    /// The velocity gradient L_ij = ∂v_i/∂x_j.
    type Grad: Copy
        + Debug
        + Default
        + AddAssign
        + Mul<Real, Output = Self::Grad>
        + Send
        + Sync
        + 'static;
    const GRAD_ZERO: Self::Grad;
    type Sym: Batch;

    /// Entry (row, col) of a gradient.
    fn grad_entry(g: &Self::Grad, row: usize, col: usize) -> Real;
    /// v ⊗ g (the contribution v_i ∇w_ip of one node to the velocity gradient).
    fn outer(v: Self::Vector, g: Self::Vector) -> Self::Grad;
    /// The strain rate ½(L + Lᵀ) (with zz = 0 in plane strain) and the spin ½(L − Lᵀ).
    fn rate_and_spin(l: Self::Grad) -> (Self::Sym, <Self::Sym as SymTensor>::Spin);
    /// Builds a vector from the first `DIM` entries of `xyz`.
    fn vector(xyz: [Real; 3]) -> Self::Vector;

    /// Column `c` of a gradient, ∂v/∂x_c (zero for c ≥ DIM).
    fn column(g: &Self::Grad, c: usize) -> Self::Vector;
    /// The gradient whose columns are the first `DIM` of `c`.
    fn from_columns(c: [Self::Vector; 3]) -> Self::Grad;
    /// The in-plane columns of a symmetric tensor (the first `DIM` used): the vectors A e_c
    /// that the tensor maps the axes to. A plane-strain tensor's zz acts on no in-plane
    /// direction and stays out.
    fn sym_columns(s: Self::Sym) -> [Self::Vector; 3];
}

/// The larger of `a` and `b` as one compare and select (`b` when `a` is NaN, as `f32::max`
/// gives; NaN when `b` is). `f32::max` follows IEEE maxNum, which WebAssembly has no instruction
/// for: there it is a call to `fmaxf` in the middle of the hot loops.
#[inline(always)]
pub fn max(a: Real, b: Real) -> Real {
    if a > b { a } else { b }
}

/// The smaller of `a` and `b` as one compare and select (see [`max`]).
#[inline(always)]
pub fn min(a: Real, b: Real) -> Real {
    if a < b { a } else { b }
}

/// eˣ, cheaply for the small arguments a time step gives (|x| ≤ 1/32: the Taylor series to x⁴,
/// relative error below x⁵/120 ≈ 2·10⁻¹⁰, under f32 rounding), and by `exp` otherwise. `exp` is
/// a library call natively and a software routine in WebAssembly. The f64 build (for
/// validation) always calls `exp`: the series is not exact to f64 rounding.
/// Number by lane for [`Real4`] (the series when every lane is small).
#[inline(always)]
pub fn exp_small<T: Number>(x: T) -> T {
    if !cfg!(feature = "f64") && x.abs().max_element() <= 1.0 / 32.0 {
        x * (x * (x * (x * (1.0 / 24.0) + 1.0 / 6.0) + 0.5) + 1.0) + 1.0
    } else {
        x.exp()
    }
}

/// Σ_{k < n} f(k) for n ≥ 1, started from the first term: a sum started from zero costs an
/// addition of +0.0 that the compiler must keep (−0 + 0 = +0).
#[inline(always)]
pub fn sum_from_first<T: Add<Output = T>>(n: usize, f: impl Fn(usize) -> T) -> T {
    (1..n).fold(f(0), |s, k| s + f(k))
}

/// Plane strain.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D2;
/// Three dimensions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct D3;

impl Dim for D2 {
    const DIM: usize = 2;
    const LOG_BLOCK: u32 = 3;
    type Vector = Vec2;
    type Grad = Mat2;
    type Sym = Sym2;
    const GRAD_ZERO: Mat2 = Mat2::ZERO;

    fn grad_entry(g: &Mat2, row: usize, col: usize) -> Real {
        g.col(col)[row]
    }
    #[inline(always)]
    fn outer(v: Vec2, g: Vec2) -> Mat2 {
        Mat2::from_cols(v * g.x, v * g.y)
    }
    #[inline(always)]
    fn rate_and_spin(l: Mat2) -> (Sym2, Real) {
        // l.y_axis.x = L_xy = ∂v_x/∂y, l.x_axis.y = L_yx = ∂v_y/∂x.
        let (lxy, lyx) = (l.y_axis.x, l.x_axis.y);
        let rate = Sym2 {
            xx: l.x_axis.x,
            yy: l.y_axis.y,
            zz: 0.0,
            xy: 0.5 * (lxy + lyx),
        };
        (rate, 0.5 * (lyx - lxy))
    }
    #[inline(always)]
    fn vector(xyz: [Real; 3]) -> Vec2 {
        Vec2::new(xyz[0], xyz[1])
    }
    #[inline(always)]
    fn column(g: &Mat2, c: usize) -> Vec2 {
        if c < 2 { g.col(c) } else { Vec2::ZERO }
    }
    #[inline(always)]
    fn from_columns(c: [Vec2; 3]) -> Mat2 {
        Mat2::from_cols(c[0], c[1])
    }
    #[inline(always)]
    fn sym_columns(s: Sym2) -> [Vec2; 3] {
        [Vec2::new(s.xx, s.xy), Vec2::new(s.xy, s.yy), Vec2::ZERO]
    }
}

impl Dim for D3 {
    const DIM: usize = 3;
    const LOG_BLOCK: u32 = 2;
    type Vector = Vec3A;
    type Grad = Mat3A;
    type Sym = Sym3;
    const GRAD_ZERO: Mat3A = Mat3A::ZERO;

    fn grad_entry(g: &Mat3A, row: usize, col: usize) -> Real {
        g.col(col)[row]
    }
    #[inline(always)]
    fn outer(v: Vec3A, g: Vec3A) -> Mat3A {
        Mat3A::from_cols(v * g.x, v * g.y, v * g.z)
    }
    #[inline(always)]
    fn rate_and_spin(l: Mat3A) -> (Sym3, [Real; 3]) {
        // Column j of `l` holds ∂v/∂x_j, so L_ij = l.col(j)[i].
        let (c0, c1, c2) = (l.x_axis, l.y_axis, l.z_axis);
        let rate = Sym3 {
            xx: c0.x,
            yy: c1.y,
            zz: c2.z,
            xy: 0.5 * (c1.x + c0.y),
            xz: 0.5 * (c2.x + c0.z),
            yz: 0.5 * (c2.y + c1.z),
        };
        let spin = [
            0.5 * (c1.x - c0.y),
            0.5 * (c2.x - c0.z),
            0.5 * (c2.y - c1.z),
        ];
        (rate, spin)
    }
    #[inline(always)]
    fn vector(xyz: [Real; 3]) -> Vec3A {
        Vec3A::new(xyz[0], xyz[1], xyz[2])
    }
    #[inline(always)]
    fn column(g: &Mat3A, c: usize) -> Vec3A {
        g.col(c)
    }
    #[inline(always)]
    fn from_columns(c: [Vec3A; 3]) -> Mat3A {
        Mat3A::from_cols(c[0], c[1], c[2])
    }
    #[inline(always)]
    fn sym_columns(s: Sym3) -> [Vec3A; 3] {
        [
            Vec3A::new(s.xx, s.xy, s.xz),
            Vec3A::new(s.xy, s.yy, s.yz),
            Vec3A::new(s.xz, s.yz, s.zz),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The transposing pack and unpack (a packing specialisation) give bit for bit what the
    /// component-by-component reference gives, NaN payloads and signed zeros included.
    #[test]
    fn packing_by_transposes_matches_the_plain_reference() {
        let v = |i: usize| -> Real {
            let specials = [
                0.0,
                -0.0,
                Real::NAN,
                Real::INFINITY,
                Real::MIN_POSITIVE / 4.0,
            ];
            if i % 7 == 3 {
                specials[i / 7 % specials.len()]
            } else {
                (i as Real * 0.37 - 3.1).sin() * (10.0 as Real).powi((i % 9) as i32 - 4)
            }
        };
        let bits = |x: Real| x.to_bits();
        let same = |a: Real4, b: Real4| a.to_array().map(bits) == b.to_array().map(bits);
        for round in 0..20 {
            let k = round * 24;
            let s2: [Sym2; LANES] = std::array::from_fn(|i| Sym2 {
                xx: v(k + 4 * i),
                yy: v(k + 4 * i + 1),
                zz: v(k + 4 * i + 2),
                xy: v(k + 4 * i + 3),
            });
            let (a, b) = (<Sym2 as Batch>::pack(&s2), Sym2::pack_plain(&s2));
            assert!(same(a.xx, b.xx) && same(a.yy, b.yy) && same(a.zz, b.zz) && same(a.xy, b.xy));
            let (u, w) = (<Sym2 as Batch>::unpack(a), Sym2::unpack_plain(a));
            for (x, y) in u.iter().zip(&w) {
                assert_eq!(
                    x.components().iter().map(|c| bits(*c)).collect::<Vec<_>>(),
                    y.components().iter().map(|c| bits(*c)).collect::<Vec<_>>()
                );
            }
            let s3: [Sym3; LANES] = std::array::from_fn(|i| Sym3 {
                xx: v(k + 6 * i),
                yy: v(k + 6 * i + 1),
                zz: v(k + 6 * i + 2),
                xy: v(k + 6 * i + 3),
                xz: v(k + 6 * i + 4),
                yz: v(k + 6 * i + 5),
            });
            let (a, b) = (<Sym3 as Batch>::pack(&s3), Sym3::pack_plain(&s3));
            for (x, y) in a.components().iter().zip(b.components()) {
                assert!(same(*x, *y));
            }
            let (u, w) = (<Sym3 as Batch>::unpack(a), Sym3::unpack_plain(a));
            for (x, y) in u.iter().zip(&w) {
                assert_eq!(
                    x.components().iter().map(|c| bits(*c)).collect::<Vec<_>>(),
                    y.components().iter().map(|c| bits(*c)).collect::<Vec<_>>()
                );
            }
            let spins: [[Real; 3]; LANES] =
                std::array::from_fn(|i| [v(k + 3 * i), v(k + 3 * i + 1), v(k + 3 * i + 2)]);
            let packed = <Sym3 as Batch>::pack_spin(&spins);
            for c in 0..3 {
                let plain = Real4::new(spins[0][c], spins[1][c], spins[2][c], spins[3][c]);
                assert!(same(packed[c], plain));
            }
        }
    }

    fn sym3(m: Mat3) -> Sym3 {
        Sym3 {
            xx: m.x_axis.x,
            yy: m.y_axis.y,
            zz: m.z_axis.z,
            xy: m.y_axis.x,
            xz: m.z_axis.x,
            yz: m.z_axis.y,
        }
    }

    #[test]
    fn rotation_3d_matches_an_exact_rotation_and_keeps_invariants() {
        let s = Sym3 {
            xx: 3.0,
            yy: -1.0,
            zz: 0.5,
            xy: 0.7,
            xz: -0.2,
            yz: 0.4,
        };
        // spin about z with rate w: W_xy = -w (v = w × x gives ∂v_x/∂y = -w).
        let w = 0.8;
        let dt = 0.01;
        let r = s.rotate([-w, 0.0, 0.0], dt);
        // Cayley angle for an increment a = w dt / 2.
        let a = 0.5 * w * dt;
        let theta = 2.0 * (a as f64).atan();
        let q = Mat3::from_rotation_z(theta as Real);
        let m = Mat3::from_cols(
            Vec3::new(s.xx, s.xy, s.xz),
            Vec3::new(s.xy, s.yy, s.yz),
            Vec3::new(s.xz, s.yz, s.zz),
        );
        let expect = sym3(q * m * q.transpose());
        for (a, b) in r.components().iter().zip(expect.components()) {
            assert!((a - b).abs() < 1e-5, "{r:?} vs {expect:?}");
        }
        assert!((r.trace() - s.trace()).abs() < 1e-5);
        assert!((r.j2() - s.j2()).abs() < 1e-4);
    }

    /// The exact Cayley rotation Q S Qᵀ in f64, Q = (I − A)⁻¹(I + A), A = ½ dt W.
    fn exact_rotation(s: Sym3, a: [f64; 3]) -> [f64; 6] {
        use glam::{DMat3, DVec3};
        let skew = DMat3::from_cols(
            DVec3::new(0.0, -a[0], -a[1]),
            DVec3::new(a[0], 0.0, -a[2]),
            DVec3::new(a[1], a[2], 0.0),
        );
        let q = (DMat3::IDENTITY - skew).inverse() * (DMat3::IDENTITY + skew);
        let c = |x: Real| x as f64;
        let m = DMat3::from_cols(
            DVec3::new(c(s.xx), c(s.xy), c(s.xz)),
            DVec3::new(c(s.xy), c(s.yy), c(s.yz)),
            DVec3::new(c(s.xz), c(s.yz), c(s.zz)),
        );
        let r = q * m * q.transpose();
        [
            r.x_axis.x, r.y_axis.y, r.z_axis.z, r.y_axis.x, r.z_axis.x, r.z_axis.y,
        ]
    }

    /// Leaving out the second-order terms of small rotations (`SECOND_ORDER`) costs no
    /// accuracy: from spins far below the threshold to far above it, in 2D and 3D, with
    /// stress components of very different sizes, the rotated stress is the exact rotation
    /// to within a few roundings of the largest component.
    #[test]
    fn rotations_of_every_size_match_the_exact_rotation() {
        let s = Sym3 {
            xx: -148.0,
            yy: -365.1,
            zz: -160.2,
            xy: -7.49,
            xz: -8.1e-8,
            yz: 3.3e-7,
        };
        let dt = 1e-4;
        for e in -40..=-2 {
            let a = (10.0 as Real).powi(e / 2) * if e % 2 == 0 { 1.0 } else { 3.0 };
            // a dominant axis and two much smaller ones, as in a body at rest
            let spin = Vec3::new(a, -1e-7 * a, 3e-3 * a) * (2.0 / dt);
            let r = s.rotate(spin.into(), dt);
            let exact = exact_rotation(s, [a as f64, -1e-7 * a as f64, 3e-3 * a as f64]);
            for (k, (got, want)) in r.components().iter().zip(exact).enumerate() {
                assert!(
                    (*got as f64 - want).abs() <= 4.0 * Real::EPSILON as f64 * 365.1,
                    "3D, a = {a:e}, component {k}: {got} vs {want}"
                );
            }
            let s2 = Sym2 {
                xx: s.xx,
                yy: s.yy,
                zz: s.zz,
                xy: s.xy,
            };
            // 2D spin w = W_yx about z: A_xy = −a.
            let r2 = s2.rotate(a * (2.0 / dt), dt);
            let exact = exact_rotation(s, [-a as f64, 0.0, 0.0]);
            for (got, want) in [(r2.xx, exact[0]), (r2.yy, exact[1]), (r2.xy, exact[3])] {
                assert!(
                    (got as f64 - want).abs() <= 4.0 * Real::EPSILON as f64 * 365.1,
                    "2D, a = {a:e}: {r2:?} vs {exact:?}"
                );
            }
        }
    }

    /// The rotation of a body at rest (a tiny spin, small stresses) runs without producing a
    /// subnormal number: x86 takes a slow path for each one (docs/performance.md). The MXCSR
    /// underflow flag is cleared before and read after a call. The rotation is the stress
    /// update's own, eight particles in lanes (`Real4x2`), every lane holding the same state:
    /// a lane's every product is then one the formula forms. (The scalar form is compiled
    /// into packed instructions whose unused lanes hold products the formula never forms, and
    /// those differ from one build profile to another.) In 3D a spin component below 1e-19
    /// still underflows in |a|²: see `SECOND_ORDER`.
    #[cfg(all(target_arch = "x86_64", not(feature = "f64")))]
    #[test]
    fn rotations_at_rest_do_not_underflow() {
        use std::hint::black_box;
        fn mxcsr() -> u32 {
            let mut v = 0u32;
            // SAFETY: `stmxcsr` stores the 32-bit SSE control/status register to the given
            // address, which is a valid, aligned, writable u32 on this stack frame.
            unsafe { std::arch::asm!("stmxcsr [{}]", in(reg) &mut v, options(nostack)) };
            v
        }
        fn clear_flags() {
            let v = mxcsr() & !0x3f;
            // SAFETY: `ldmxcsr` loads the register from a valid u32; only the six sticky
            // exception-status bits are cleared, the control bits (rounding, masks) are
            // written back unchanged.
            unsafe { std::arch::asm!("ldmxcsr [{}]", in(reg) &v, options(nostack)) };
        }
        type L = Real4x2;
        #[inline(never)]
        fn rotate2(s: Sym2<L>, w: L, dt: Real) -> Sym2<L> {
            s.rotate(w, dt)
        }
        #[inline(never)]
        fn rotate3(s: Sym3<L>, w: [L; 3], dt: Real) -> Sym3<L> {
            s.rotate(w, dt)
        }
        let lanes2 = |s: Sym2| Sym2 {
            xx: L::splat(s.xx),
            yy: L::splat(s.yy),
            zz: L::splat(s.zz),
            xy: L::splat(s.xy),
        };
        let lanes3 = |s: Sym3| Sym3 {
            xx: L::splat(s.xx),
            yy: L::splat(s.yy),
            zz: L::splat(s.zz),
            xy: L::splat(s.xy),
            xz: L::splat(s.xz),
            yz: L::splat(s.yz),
        };
        const UNDERFLOW: u32 = 0x10;
        // the state of a sand particle near the free surface, found by probing a settling run
        let s3 = Sym3 {
            xx: -2.08e-6,
            yy: -4.59e-6,
            zz: -2.08e-6,
            xy: 6.5e-7,
            xz: -3.4e-10,
            yz: -1.0e-9,
        };
        // the state of a sand particle near the free surface, found by probing a settling run
        let s2 = Sym2 {
            xx: -3.29e-7,
            yy: -7.68e-7,
            zz: -3.29e-7,
            xy: 0.0,
        };
        for w in [9.4e-13, 3e-9, 1.5e-8] {
            clear_flags();
            black_box(rotate2(
                black_box(lanes2(s2)),
                black_box(L::splat(w)),
                black_box(7e-5),
            ));
            assert_eq!(mxcsr() & UNDERFLOW, 0, "2D rotation by w = {w} underflowed");
            clear_flags();
            let spin = [w, 0.3 * w, -0.5 * w];
            black_box(rotate3(
                black_box(lanes3(s3)),
                black_box(spin.map(L::splat)),
                black_box(4e-4),
            ));
            assert_eq!(
                mxcsr() & UNDERFLOW,
                0,
                "3D rotation by {spin:?} underflowed"
            );
        }
    }

    #[test]
    fn rotation_2d_matches_3d_about_z() {
        let s2 = Sym2 {
            xx: 2.0,
            yy: -1.0,
            zz: 0.3,
            xy: 0.5,
        };
        let s3 = Sym3 {
            xx: 2.0,
            yy: -1.0,
            zz: 0.3,
            xy: 0.5,
            xz: 0.0,
            yz: 0.0,
        };
        let w = 1.3; // W_yx
        let r2 = s2.rotate(w, 0.05);
        let r3 = s3.rotate([-w, 0.0, 0.0], 0.05);
        assert!((r2.xx - r3.xx).abs() < 1e-6);
        assert!((r2.yy - r3.yy).abs() < 1e-6);
        assert!((r2.xy - r3.xy).abs() < 1e-6);
        assert!((r2.zz - r3.zz).abs() < 1e-6);
    }

    #[test]
    fn exp_small_matches_exp_on_both_sides_of_the_switch() {
        for i in -400..=400 {
            let x = i as f64 * 1e-4; // -0.04 ..= 0.04, across ±1/32
            let (fast, exact) = (exp_small(x as Real) as f64, x.exp());
            assert!(
                ((fast - exact) / exact).abs() < 2.0 * Real::EPSILON as f64,
                "{x}: {fast}"
            );
        }
        assert!(exp_small(Real::NAN).is_nan());
        assert!(exp_small(-800.0) == 0.0 && exp_small(-1.0) == (-1.0 as Real).exp());
    }

    #[test]
    fn exp_small_in_lanes_is_exp_small_in_each_lane() {
        // all lanes small: the series, bit for bit as one lane at a time
        let small = [-0.03, -1e-7, 0.0, 0.031];
        let l = exp_small(Real4::from_array(small)).to_array();
        for (x, e) in small.iter().zip(l) {
            assert_eq!(e.to_bits(), exp_small(*x).to_bits(), "{x}");
        }
        // one lane large: every lane still within two roundings of eˣ, a NaN stays NaN
        let mixed = [-0.02, 0.5, -3.0, Real::NAN];
        let l = exp_small(Real4::from_array(mixed)).to_array();
        for (x, e) in mixed.iter().zip(l).take(3) {
            let exact = (*x as f64).exp();
            assert!(
                ((e as f64 - exact) / exact).abs() < 2.0 * Real::EPSILON as f64,
                "{x}: {e}"
            );
        }
        assert!(l[3].is_nan());
    }

    #[test]
    fn rate_and_spin_split_the_gradient() {
        // v = (a y, 0): simple shear.
        let l = D2::outer(Vec2::new(1.0, 0.0), Vec2::new(0.0, 2.0));
        let (d, w) = D2::rate_and_spin(l);
        assert_eq!(
            d,
            Sym2 {
                xx: 0.0,
                yy: 0.0,
                zz: 0.0,
                xy: 1.0
            }
        );
        assert_eq!(w, -1.0);
        let l3 = D3::outer(Vec3A::new(1.0, 0.0, 0.0), Vec3A::new(0.0, 2.0, 0.0));
        let (d3, w3) = D3::rate_and_spin(l3);
        assert_eq!(d3.xy, 1.0);
        assert_eq!(w3, [1.0, 0.0, 0.0]);
    }
}
