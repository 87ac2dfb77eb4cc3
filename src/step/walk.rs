//! The walk over a particle's stencil, the one place that knows how a stencil lies on the
//! grid: every pass states its Sec. 4.2 sums as terms handed to these walks. The walks know
//! rows, reach, axis folding, packing and lanes, and no physics: a pass's per-node term (a
//! node field to sum, or a closure that adds to a node) is written once, in the pass, so a new
//! per-node quantity is one edit there (a field in the tuple the gather's closure returns, or
//! a line in the scatter's closure).
//!
//! **The nodes.** A particle's stencil has `S` nodes per axis; a body's grid stores its nodes
//! in padded blocks whose rows are `p` = block + S − 1 nodes long, so that node (i, j, k) of a
//! stencil is `i + j p + k p²` nodes after its first ([`Walker::at`] finds that first node, as
//! the grid's allocation recorded it).
//!
//! **Rows.** The weights are products of one-axis weights, w_ip = w_i w_j w_k and
//! ∇w_ip = (w'_i w_j w_k, w_i w'_j w_k, w_i w_j w'_k) (grid units folded into w'), so each
//! walk goes row by row. A gather takes the node fields a pass states for a node (a tuple of
//! [`Field`]s, each asking for Σ_i w_ip f_i, Σ_i f_i ⊗ ∇w_ip or Σ_i w_ip f_i ⊗ d_i), sums
//! them against w_i, w'_i (and the offset d_i) along the first axis, then multiplies the
//! row's sums by the row's factors w_j w_k, w'_j w_k and w_j w'_k ([`NodeField`]). The
//! scatter ([`scatter`]) calls the pass's per-node terms with the node's [`Weights`], which
//! form w_ip, ∇w_ip, F ∇w_ip and A d_i with the row's factors first. A node then costs a few
//! multiply-adds. [`scatter_pair`] walks two node arrays laid out alike at once (the 3D
//! scatter's nodes and mass gradients).
//!
//! **Owners.** A pass over a few particles (the traction, `traction.rs`) walks the same rows on
//! the nodes' owners instead ([`on_owners`]), looking each node's block up, so that it reads
//! and adds to the owners with no halo to fill or reduce.
//!
//! **Axis folding.** 2D runs the same loops with the third axis's weight 1 and derivative 0
//! and one `k` (`third_axis`); LLVM folds them away.
//!
//! **Reach.** The loops stop at the last node with weight along each axis
//! ([`Stencil::reach`]): a GIMP stencil has two along an axis where the particle's domain does
//! not cross a node, three elsewhere (`nodes_along`).
//!
//! **2D packing.** In 2D two vectors fit one `Vec4`, so the 2D walks keep two sums side by
//! side: [`gather_rows_packed_2d`], [`gather_values_packed_2d`] (two fields, chosen by their
//! shape) and [`gradient_packed_2d`] are packing specialisations of the row walk
//! [`gather_rows`], chosen by [`gather`] and [`gradient`], and [`Weights::gradient_times`]
//! forms F ∇w_ip of both columns of F in one `Vec4`; the tests below compare each with the
//! plain per-node sums.
//!
//! **Lanes.** The stress update advances eight particles at once in SIMD lanes;
//! [`update_in_lanes`] puts a chunk of particles into lanes, pads a short one, and takes the
//! results back out.

use crate::grid::{BlockLayout, GHOST, Grid, Node, stencil_span};
use crate::kernel::{Kernel, KernelKind, Stencil, floor_nonneg};
use crate::math::{
    Batch, Dim, LANES, Real, Real4, Real4x2, SymTensor, Vec2, Vec4, VectorOps, sum_from_first,
};
use std::marker::PhantomData;

/// Grid coordinates of a position: x/h plus the ghost nodes before the domain.
#[inline(always)]
pub fn grid_coords<D: Dim>(x: D::Vector, inv_h: Real) -> [Real; 3] {
    let mut g = [0.0; 3];
    for (a, c) in g.iter_mut().enumerate().take(D::DIM) {
        *c = x[a] * inv_h + GHOST as Real;
    }
    g
}

/// Nodes per row of a padded block for a kernel of `S` nodes per axis (a compile-time
/// constant after monomorphisation).
#[inline(always)]
pub const fn row_length<D: Dim, const S: usize>() -> usize {
    Grid::<D>::BLOCK + S - 1
}

/// The number of consecutive nodes a stencil spans.
#[inline(always)]
fn span<D: Dim, const S: usize>() -> usize {
    stencil_span(D::DIM, row_length::<D, S>(), S)
}

/// A particle's place on its body's grid: its stencil, and the storage index of the
/// stencil's first node.
#[derive(Clone, Copy)]
pub struct At<const S: usize> {
    pub st: Stencil<S>,
    pub origin: usize,
}

impl<const S: usize> At<S> {
    /// The stencil's nodes.
    #[inline(always)]
    fn nodes<'a, D: Dim>(&self, nodes: &'a [Node<D::Vector>]) -> &'a [Node<D::Vector>] {
        &nodes[self.origin..][..span::<D, S>()]
    }
}

/// A body's particles walked in order over its grid: each one's stencil and first node.
pub struct Walker<'g, D: Dim, K: Kernel<S>, const S: usize> {
    layout: &'g BlockLayout<D>,
    particle_node: &'g [u32],
    stencils: Stencils<D, K, S>,
}

impl<'g, D: Dim, K: Kernel<S>, const S: usize> Walker<'g, D, K, S> {
    /// For a grid laid out by `layout` whose allocation found the first stencil node
    /// `particle_node[q]` of each particle, of half-width `lp` grid units on cells of 1/`inv_h`.
    #[inline(always)]
    pub fn new(
        layout: &'g BlockLayout<D>,
        particle_node: &'g [u32],
        inv_h: Real,
        lp: Real,
    ) -> Self {
        debug_assert_eq!(
            layout.padded(),
            row_length::<D, S>(),
            "grid laid out for another kernel"
        );
        Walker {
            layout,
            particle_node,
            stencils: Stencils::new(inv_h, lp),
        }
    }

    /// Particle `q`'s place, at `x[q]` (debug builds check that its stencil did not move since
    /// the grid was allocated).
    #[inline(always)]
    pub fn at(&mut self, x: &[D::Vector], q: usize) -> At<S> {
        let st = self.stencils.at(x, q);
        let node = self.particle_node[q];
        debug_assert_eq!(
            node as usize % self.layout.padded_nodes(),
            self.layout.stencil_origin(0, st.base),
            "particle's stencil moved since the grid was allocated"
        );
        At {
            st,
            origin: node as usize,
        }
    }
}

/// The particles' stencils, one particle after another, for a pass that walks them in order.
/// In native 2D builds two particles' GIMP stencils are evaluated at once
/// ([`Kernel::stencil_pair_2d`], a packing specialisation of [`Kernel::stencil`]): the second
/// waits here for the pass to ask for it.
pub struct Stencils<D: Dim, K: Kernel<S>, const S: usize> {
    inv_h: Real,
    lp: Real,
    /// The particle whose stencil `next` is (`usize::MAX`: none).
    cached: usize,
    next: Stencil<S>,
    _kernel: PhantomData<(D, K)>,
}

impl<D: Dim, K: Kernel<S>, const S: usize> Stencils<D, K, S> {
    /// For particles of half-width `lp` grid units on a grid of 1/`inv_h` cells.
    #[inline(always)]
    pub fn new(inv_h: Real, lp: Real) -> Self {
        Stencils {
            inv_h,
            lp,
            cached: usize::MAX,
            next: Stencil::at([0; 3]),
            _kernel: PhantomData,
        }
    }

    /// The stencil of particle `q` at `x[q]` (in 2D, with particle q + 1's when q is not
    /// the second of a pair: a pass asks for q + 1 next, whose position it has not moved yet).
    #[inline(always)]
    pub fn at(&mut self, x: &[D::Vector], q: usize) -> Stencil<S> {
        let (inv_h, lp) = (self.inv_h, self.lp);
        // Pairs pay for GIMP's weights natively; the linear kernel's and the B-spline's cost
        // about what keeping the second stencil does, and in WebAssembly V8 ran the pairs
        // slower (docs/performance.md).
        if D::DIM != 2 || K::KIND != KernelKind::Gimp || cfg!(target_arch = "wasm32") {
            return K::stencil(grid_coords::<D>(x[q], inv_h), D::DIM, inv_h, lp);
        }
        if self.cached == q {
            return self.next;
        }
        let b = x[if q + 1 < x.len() { q + 1 } else { q }];
        let [first, second] = K::stencil_pair_2d(
            grid_coords::<D>(x[q], inv_h),
            grid_coords::<D>(b, inv_h),
            inv_h,
            lp,
        );
        (self.next, self.cached) = (second, q + 1);
        first
    }
}

/// The stencil's weight and derivative along the third axis for node `k`: those of the
/// kernel in 3D, and (1, 0) in 2D, where the loops over `k` run once.
#[inline(always)]
fn third_axis<D: Dim, const S: usize>(st: &Stencil<S>, k: usize) -> (Real, Real) {
    if D::DIM == 3 {
        (st.w[k][2], st.dw[k][2])
    } else {
        (1.0, 0.0)
    }
}

/// The stencil nodes with weight along axis `a` (one along the third axis in 2D): the first
/// `reach[a]` of `S` for GIMP (the rest carry none, and the walks skip them), all `S` for the
/// other kernels (a constant, so that their loops unroll) — and for GIMP in the 2D WebAssembly
/// build, where V8 ran the loops of varying length slower than the unrolled ones
/// (docs/performance.md).
#[inline(always)]
fn nodes_along<D: Dim, K: Kernel<S>, const S: usize>(st: &Stencil<S>, a: usize) -> usize {
    if a >= D::DIM {
        return 1;
    }
    let skip = D::DIM == 3 || !cfg!(target_arch = "wasm32");
    if K::KIND == KernelKind::Gimp && skip {
        st.reach[a]
    } else {
        S
    }
}

/// One stencil node's weights, as [`scatter`] hands them to a pass's terms: w_ip = w_i w_j w_k
/// and ∇w_ip = (w'_i w_j w_k, w_i w'_j w_k, w_i w_j w'_k) kept as the node's first-axis factors
/// (w_i, w'_i) and its row's (w_j w_k, w'_j w_k, w_j w'_k), and the node's offset d_i from the
/// particle in cells. Its methods form the products a term asks for, the row's factors first
/// (loop-invariant along the row, so the compiler keeps them out of the node loop).
#[derive(Clone, Copy)]
pub struct Weights<D: Dim> {
    wi: Real,
    dwi: Real,
    di: Real,
    /// w_i and w'_i as vectors.
    wiv: D::Vector,
    dwiv: D::Vector,
    /// (w'_i, w'_i, w_i, w_i), for the 2D packing of [`Weights::gradient_times`].
    packed: Vec4,
    row: Row,
}

/// A stencil row's factors: w_j w_k, w'_j w_k, w_j w'_k, and the row's offsets d_j, d_k.
#[derive(Clone, Copy)]
pub struct Row {
    wjk: Real,
    dwj_wk: Real,
    wj_dwk: Real,
    dj: Real,
    dk: Real,
}

impl Row {
    /// The factors of row (j, k) of the stencil `st` (in 2D, w_k = 1 and w'_k = 0).
    #[inline(always)]
    fn at<D: Dim, const S: usize>(st: &Stencil<S>, j: usize, k: usize) -> Row {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        Row {
            wjk: st.w[j][1] * wk,
            dwj_wk: st.dw[j][1] * wk,
            wj_dwk: st.w[j][1] * dwk,
            dj: st.d[j][1],
            dk: if D::DIM == 3 { st.d[k][2] } else { 0.0 },
        }
    }
}

/// A stencil's first-axis weights w_i and w'_i as vectors, once per stencil.
struct FirstAxis<D: Dim, const S: usize> {
    wv: [D::Vector; S],
    dwv: [D::Vector; S],
    /// (w'_i, w'_i, w_i, w_i) per node, formed once per stencil (2D packing; unused, and so
    /// not formed, in 3D).
    packed: [Vec4; S],
}

impl<D: Dim, const S: usize> FirstAxis<D, S> {
    #[inline(always)]
    fn of(st: &Stencil<S>) -> Self {
        FirstAxis {
            wv: std::array::from_fn(|i| D::Vector::splat(st.w[i][0])),
            dwv: std::array::from_fn(|i| D::Vector::splat(st.dw[i][0])),
            packed: std::array::from_fn(|i| {
                Vec4::new(st.dw[i][0], st.dw[i][0], st.w[i][0], st.w[i][0])
            }),
        }
    }

    /// Node i's [`Weights`] on the row of factors `row`.
    #[inline(always)]
    fn weights(&self, st: &Stencil<S>, i: usize, row: Row) -> Weights<D> {
        Weights {
            wi: st.w[i][0],
            dwi: st.dw[i][0],
            di: st.d[i][0],
            wiv: self.wv[i],
            dwiv: self.dwv[i],
            packed: self.packed[i],
            row,
        }
    }
}

impl<D: Dim> Weights<D> {
    /// w_ip.
    #[inline(always)]
    pub fn value(&self) -> Real {
        self.wi * self.row.wjk
    }

    /// ∇w_ip.
    #[inline(always)]
    pub fn gradient(&self) -> D::Vector {
        let r = &self.row;
        D::vector([self.dwi * r.wjk, self.wi * r.dwj_wk, self.wi * r.wj_dwk])
    }

    /// F ∇w_ip for a symmetric F: (F e_x w_j w_k) w'_i + (F e_y w'_j w_k + F e_z w_j w'_k) w_i;
    /// in 2D, packing specialisation, both columns side by side in one `Vec4`,
    /// ((F_xx, F_xy) w_j, (F_xy, F_yy) w'_j) ∘ (w'_i, w'_i, w_i, w_i), then the halves added
    /// (the same products and sums); the node's (w'_i, w'_i, w_i, w_i) is formed once per
    /// stencil (`FirstAxis`), which keeps it out of the row loops (5 and 14 instructions per
    /// particle-substep fewer on 2D linear and B-spline sand than formed per node).
    #[inline(always)]
    pub fn gradient_times(&self, f: D::Sym) -> D::Vector {
        let r = &self.row;
        let [f0, f1, f2] = D::sym_columns(f);
        if D::DIM == 2 {
            let fj =
                Vec4::new(f0[0], f0[1], f1[0], f1[1]) * Vec4::new(r.wjk, r.wjk, r.dwj_wk, r.dwj_wk);
            let t = fj * self.packed;
            return D::vector([t.x + t.z, t.y + t.w, 0.0]);
        }
        let fx = f0 * r.wjk;
        let mut fyz = f1 * r.dwj_wk;
        if D::DIM == 3 {
            fyz += f2 * r.wj_dwk;
        }
        fx * self.dwiv + fyz * self.wiv
    }

    /// b + A d_i for a matrix A given by its columns `a` (of any vector type):
    /// (b + A e_y d_j + A e_z d_k) + A e_x d_i.
    #[inline(always)]
    pub fn plus_offset<T>(&self, b: T, a: [T; 3]) -> T
    where
        T: Copy + std::ops::Add<Output = T> + std::ops::Mul<Real, Output = T>,
    {
        let r = &self.row;
        let mut row = b + a[1] * r.dj;
        if D::DIM == 3 {
            row = row + a[2] * r.dk;
        }
        row + a[0] * self.di
    }
}

/// Calls `term(n, w)` for every node n of the stencil at `at` with weight (`nodes` laid out as
/// the grid's nodes, from the first), with its [`Weights`] w: row by row, each row's factors
/// once, over the nodes with weight along each axis (`nodes_along`), and in 2D one `k` with
/// w_k = 1, w'_k = 0 (`third_axis`). A pass states its per-node terms in `term`.
#[inline(always)]
pub fn scatter<D: Dim, K: Kernel<S>, const S: usize, N>(
    nodes: &mut [N],
    at: &At<S>,
    mut term: impl FnMut(&mut N, Weights<D>),
) {
    let p = row_length::<D, S>();
    let st = &at.st;
    let nodes = &mut nodes[at.origin..][..span::<D, S>()];
    let first = FirstAxis::<D, S>::of(st);
    for k in 0..nodes_along::<D, K, S>(st, 2) {
        for j in 0..nodes_along::<D, K, S>(st, 1) {
            let base = j * p + k * p * p;
            let row = Row::at::<D, S>(st, j, k);
            let row_nodes = &mut nodes[base..base + S];
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                term(&mut row_nodes[i], first.weights(st, i, row));
            }
        }
    }
}

/// [`scatter`] over two node arrays laid out alike, `nodes` and `second`: calls
/// `term(n, s, w)` for every node of the stencil with weight, in one walk (the same rows,
/// nodes and [`Weights`] as two scatters, so the same sums bit for bit).
#[inline(always)]
pub fn scatter_pair<D: Dim, K: Kernel<S>, const S: usize, N, M>(
    nodes: &mut [N],
    second: &mut [M],
    at: &At<S>,
    mut term: impl FnMut(&mut N, &mut M, Weights<D>),
) {
    let p = row_length::<D, S>();
    let st = &at.st;
    let nodes = &mut nodes[at.origin..][..span::<D, S>()];
    let second = &mut second[at.origin..][..span::<D, S>()];
    let first = FirstAxis::<D, S>::of(st);
    for k in 0..nodes_along::<D, K, S>(st, 2) {
        for j in 0..nodes_along::<D, K, S>(st, 1) {
            let base = j * p + k * p * p;
            let row = Row::at::<D, S>(st, j, k);
            let (row_nodes, row_second) = (&mut nodes[base..base + S], &mut second[base..base + S]);
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                term(
                    &mut row_nodes[i],
                    &mut row_second[i],
                    first.weights(st, i, row),
                );
            }
        }
    }
}

/// [`scatter`]'s walk over the stencil `st` on the nodes' owners: calls `term(n, w)` for every
/// node with weight that `grid` allocated, n its storage index in the block that owns it (not
/// a padded block's halo copy). For a pass over a few particles that reads and adds to the
/// owners directly, with no halo to fill or reduce; each node costs a look-up of its block.
#[inline(always)]
pub fn on_owners<D: Dim, K: Kernel<S>, const S: usize>(
    grid: &Grid<D>,
    st: &Stencil<S>,
    mut term: impl FnMut(usize, Weights<D>),
) {
    let first = FirstAxis::<D, S>::of(st);
    let b = st.base;
    for k in 0..nodes_along::<D, K, S>(st, 2) {
        let bk = if D::DIM == 3 { b[2] + k as i32 } else { 0 };
        for j in 0..nodes_along::<D, K, S>(st, 1) {
            let row = Row::at::<D, S>(st, j, k);
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                if let Some(n) = grid.node_index([b[0] + i as i32, b[1] + j as i32, bk]) {
                    term(n, first.weights(st, i, row));
                }
            }
        }
    }
}

/// One node field f_i that a pass sums over a particle's stencil, with the sums it asks for:
/// (`VALUE`) Σ_i w_ip f_i, (`GRADIENT`) Σ_i f_i ⊗ ∇w_ip and (`MOMENT`) Σ_i w_ip f_i ⊗ d_i, d_i
/// the node's offset from the particle in cells. A field that asks for none is not summed. A
/// pass states the fields of a node in the closure it hands to [`gather`], a tuple of these.
#[derive(Clone, Copy)]
pub struct Field<D: Dim, const VALUE: bool, const GRADIENT: bool, const MOMENT: bool>(
    pub D::Vector,
);

/// A field's sums over the stencil, as [`gather`] returns them (those not asked for zero).
#[derive(Clone, Copy)]
pub struct FieldSums<D: Dim> {
    /// Σ_i w_ip f_i.
    pub value: D::Vector,
    /// Σ_i f_i ⊗ ∇w_ip.
    pub gradient: D::Grad,
    /// Σ_i w_ip f_i ⊗ d_i.
    pub moment: D::Grad,
}

/// A field's sums along one stencil row (first-axis factors only): Σ_i w_i f_i, Σ_i w'_i f_i
/// and Σ_i w_i d_i f_i.
#[derive(Clone, Copy)]
pub struct FieldRow<D: Dim> {
    n: D::Vector,
    d: D::Vector,
    x: D::Vector,
}

/// A field's sums while the walk goes: the value, and the gradient's and moment's columns.
#[derive(Clone, Copy)]
pub struct FieldAcc<D: Dim> {
    value: D::Vector,
    c: [D::Vector; 3],
    b: [D::Vector; 3],
}

/// A node field with the sums it asks for ([`Field`]).
pub trait NodeField<D: Dim>: Copy {
    const VALUE: bool;
    const GRADIENT: bool;
    const MOMENT: bool;
    fn vector(self) -> D::Vector;

    /// Whether any sum of the field is asked for.
    #[inline(always)]
    fn summed() -> bool {
        Self::VALUE || Self::GRADIENT || Self::MOMENT
    }

    /// Adds the node's terms to the row's sums: the field at first-axis weight `w`,
    /// derivative `dw` (both as vectors) and offset `d`.
    #[inline(always)]
    fn add(self, r: &mut FieldRow<D>, w: D::Vector, dw: D::Vector, d: Real) {
        if !Self::summed() {
            return;
        }
        let v = self.vector();
        let vw = v * w;
        r.n += vw;
        if Self::MOMENT {
            r.x += vw * d;
        }
        if Self::GRADIENT {
            r.d += v * dw;
        }
    }

    /// Adds a row's sums times the row's factors: w_j w_k for the value, (w_j w_k, w'_j w_k,
    /// w_j w'_k) for the gradient's columns, w_j w_k (1, d_j, d_k) for the moment's.
    #[inline(always)]
    fn fold(r: &FieldRow<D>, s: &mut FieldAcc<D>, row: &Row) {
        if !Self::summed() {
            return;
        }
        s.value += r.n * row.wjk;
        if Self::GRADIENT {
            s.c[0] += r.d * row.wjk;
            s.c[1] += r.n * row.dwj_wk;
            if D::DIM == 3 {
                s.c[2] += r.n * row.wj_dwk;
            }
        }
        if Self::MOMENT {
            s.b[0] += r.x * row.wjk;
            s.b[1] += r.n * (row.wjk * row.dj);
            if D::DIM == 3 {
                s.b[2] += r.n * (row.wjk * row.dk);
            }
        }
    }

    /// The plain per-node form of [`NodeField::add`] and [`NodeField::fold`]: every sum with
    /// the node's w_ip, ∇w_ip and d_i as the products they are (the tests' reference).
    #[cfg(test)]
    #[inline(always)]
    fn add_plain(self, s: &mut FieldAcc<D>, w: Real, gw: D::Vector, d: D::Vector) {
        let v = self.vector();
        s.value += v * w;
        for a in 0..D::DIM {
            s.c[a] += v * gw[a];
            s.b[a] += v * (w * d[a]);
        }
    }
}

impl<D: Dim, const VALUE: bool, const GRADIENT: bool, const MOMENT: bool> NodeField<D>
    for Field<D, VALUE, GRADIENT, MOMENT>
{
    const VALUE: bool = VALUE;
    const GRADIENT: bool = GRADIENT;
    const MOMENT: bool = MOMENT;
    #[inline(always)]
    fn vector(self) -> D::Vector {
        self.0
    }
}

impl<D: Dim> FieldRow<D> {
    const ZERO: Self = FieldRow {
        n: D::Vector::ZERO,
        d: D::Vector::ZERO,
        x: D::Vector::ZERO,
    };
}

impl<D: Dim> FieldAcc<D> {
    const ZERO: Self = FieldAcc {
        value: D::Vector::ZERO,
        c: [D::Vector::ZERO; 3],
        b: [D::Vector::ZERO; 3],
    };
    #[inline(always)]
    fn finish(self) -> FieldSums<D> {
        FieldSums {
            value: self.value,
            gradient: D::from_columns(self.c),
            moment: D::from_columns(self.b),
        }
    }
}

/// The node fields a pass sums over a stencil: a tuple of [`NodeField`]s, one or more. The
/// walk sums each field's terms ([`NodeField::add`], [`NodeField::fold`]); a new per-node
/// quantity is one more field in the pass's tuple.
pub trait Fields<D: Dim>: Copy {
    /// One [`FieldSums`] per field, in the tuple's order.
    type Sums;
    /// One [`FieldRow`] per field.
    type Rows: Copy;
    /// One [`FieldAcc`] per field.
    type Acc: Copy;
    const ZERO_ROWS: Self::Rows;
    const ZERO_ACC: Self::Acc;
    fn add(self, r: &mut Self::Rows, w: D::Vector, dw: D::Vector, d: Real);
    fn fold(r: &Self::Rows, s: &mut Self::Acc, row: &Row);
    fn finish(s: Self::Acc) -> Self::Sums;
    #[cfg(test)]
    fn add_plain(self, s: &mut Self::Acc, w: Real, gw: D::Vector, d: D::Vector);

    /// The sums of the fields `f` gives the stencil's `nodes` (from its first): the row walk
    /// [`gather_rows`], or a packing specialisation of it.
    #[inline(always)]
    fn walk<K: Kernel<S>, const S: usize>(
        nodes: &[Node<D::Vector>],
        st: &Stencil<S>,
        f: impl Fn(&Node<D::Vector>) -> Self,
    ) -> Self::Sums {
        gather_rows::<D, K, S, Self>(nodes, st, f)
    }
}

macro_rules! fields_tuple {
    ($($F:ident $i:tt),+; $($walk:item)?) => {
        impl<D: Dim, $($F: NodeField<D>),+> Fields<D> for ($($F,)+) {
            type Sums = ($(fields_tuple!(@as $F FieldSums<D>),)+);
            type Rows = ($(fields_tuple!(@as $F FieldRow<D>),)+);
            type Acc = ($(fields_tuple!(@as $F FieldAcc<D>),)+);
            const ZERO_ROWS: Self::Rows = ($(fields_tuple!(@as $F FieldRow::<D>::ZERO),)+);
            const ZERO_ACC: Self::Acc = ($(fields_tuple!(@as $F FieldAcc::<D>::ZERO),)+);
            #[inline(always)]
            fn add(self, r: &mut Self::Rows, w: D::Vector, dw: D::Vector, d: Real) {
                $(self.$i.add(&mut r.$i, w, dw, d);)+
            }
            #[inline(always)]
            fn fold(r: &Self::Rows, s: &mut Self::Acc, row: &Row) {
                $($F::fold(&r.$i, &mut s.$i, row);)+
            }
            #[inline(always)]
            fn finish(s: Self::Acc) -> Self::Sums {
                ($(s.$i.finish(),)+)
            }
            #[cfg(test)]
            #[inline(always)]
            fn add_plain(self, s: &mut Self::Acc, w: Real, gw: D::Vector, d: D::Vector) {
                $(self.$i.add_plain(&mut s.$i, w, gw, d);)+
            }
            $($walk)?
        }
    };
    (@as $F:ident $($t:tt)*) => { $($t)* };
}

fields_tuple!(A 0; );
fields_tuple!(A 0, B 1, C 2; );
fields_tuple!(A 0, B 1, C 2, E 3; );
// Two fields in 2D, the second asking for its value at most and the first for no moment:
// the packing specialisations.
fields_tuple!(A 0, B 1;
    #[inline(always)]
    fn walk<K: Kernel<S>, const S: usize>(
        nodes: &[Node<D::Vector>],
        st: &Stencil<S>,
        f: impl Fn(&Node<D::Vector>) -> Self,
    ) -> Self::Sums {
        if D::DIM == 2 && A::VALUE && !A::MOMENT && !B::GRADIENT && !B::MOMENT {
            if A::GRADIENT {
                gather_rows_packed_2d::<D, K, S, A, B>(nodes, st, f)
            } else {
                gather_values_packed_2d::<D, K, S, A, B>(nodes, st, f)
            }
        } else {
            gather_rows::<D, K, S, Self>(nodes, st, f)
        }
    }
);

/// The sums of the node fields `f` states ([`Fields`]) over the stencil at `at`. With two
/// fields in 2D, the first without its moment and the second with its value alone, this is
/// [`gather_rows_packed_2d`] or, without the gradient either, [`gather_values_packed_2d`];
/// else [`gather_rows`].
#[inline(always)]
pub fn gather<D: Dim, K: Kernel<S>, const S: usize, F: Fields<D>>(
    nodes: &[Node<D::Vector>],
    at: &At<S>,
    f: impl Fn(&Node<D::Vector>) -> F,
) -> F::Sums {
    F::walk::<K, S>(at.nodes::<D>(nodes), &at.st, f)
}

/// The gradient Σ_i f_i ⊗ ∇w_ip of the node field `f` at `at`: in 2D
/// [`gradient_packed_2d`], else [`gather_rows`]'.
#[inline(always)]
pub fn gradient<D: Dim, K: Kernel<S>, const S: usize>(
    nodes: &[Node<D::Vector>],
    at: &At<S>,
    f: impl Fn(&Node<D::Vector>) -> D::Vector,
) -> D::Grad {
    let (nodes, st) = (at.nodes::<D>(nodes), &at.st);
    if D::DIM == 2 {
        gradient_packed_2d::<D, K, S>(nodes, st, f)
    } else {
        let (l,) =
            gather_rows::<D, K, S, _>(nodes, st, |n| (Field::<D, false, true, false>(f(n)),));
        l.gradient
    }
}

/// [`gather`] row by row, for the stencil's `nodes` (from its first), in any dimension: along
/// a row each field's Σ_i w_i f_i, Σ_i w'_i f_i and Σ_i w_i d_i f_i ([`NodeField::add`]),
/// then the row's factors ([`NodeField::fold`]).
#[inline(always)]
pub fn gather_rows<D: Dim, K: Kernel<S>, const S: usize, F: Fields<D>>(
    nodes: &[Node<D::Vector>],
    st: &Stencil<S>,
    f: impl Fn(&Node<D::Vector>) -> F,
) -> F::Sums {
    let p = row_length::<D, S>();
    let nodes = &nodes[..span::<D, S>()];
    let mut acc = F::ZERO_ACC;
    // The first axis's weights as vectors, once.
    let w: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.w[i][0]));
    let dw: [D::Vector; S] = std::array::from_fn(|i| D::Vector::splat(st.dw[i][0]));
    for k in 0..nodes_along::<D, K, S>(st, 2) {
        let (wk, dwk) = third_axis::<D, S>(st, k);
        let dk = if D::DIM == 3 { st.d[k][2] } else { 0.0 };
        for j in 0..nodes_along::<D, K, S>(st, 1) {
            let base = j * p + k * p * p;
            let row = &nodes[base..base + S];
            let mut r = F::ZERO_ROWS;
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                f(&row[i]).add(&mut r, w[i], dw[i], st.d[i][0]);
            }
            let factors = Row {
                wjk: st.w[j][1] * wk,
                dwj_wk: st.dw[j][1] * wk,
                wj_dwk: st.w[j][1] * dwk,
                dj: st.d[j][1],
                dk,
            };
            F::fold(&r, &mut acc, &factors);
        }
    }
    F::finish(acc)
}

/// [`gather_rows`] in 2D for two fields, the first (f) without its moment, the second (g)
/// with its value at most, packing specialisation: along a row, (f w_i, g w_i) — or without
/// g, (f w_i, f w'_i) — in one `Vec4`, then the two gradient columns (Σ_i w'_i f_i) w_j and
/// (Σ_i w_i f_i) w'_j side by side in another.
#[inline(always)]
pub fn gather_rows_packed_2d<D: Dim, K: Kernel<S>, const S: usize, A, B>(
    nodes: &[Node<D::Vector>],
    st: &Stencil<S>,
    f: impl Fn(&Node<D::Vector>) -> (A, B),
) -> (FieldSums<D>, FieldSums<D>)
where
    A: NodeField<D>,
    B: NodeField<D>,
{
    debug_assert!(D::DIM == 2 && !A::MOMENT && !B::GRADIENT && !B::MOMENT);
    let second = B::VALUE;
    let p = row_length::<D, S>();
    let nodes = &nodes[..span::<D, S>()];
    let (mut vel, mut grad) = (Vec4::ZERO, Vec4::ZERO);
    for j in 0..nodes_along::<D, K, S>(st, 1) {
        let row = &nodes[j * p..j * p + S];
        // rn: Σ_i w_i f_i, rd: Σ_i w'_i f_i, ro: Σ_i w_i g_i.
        let (rn, rd, ro) = if second {
            let (mut rv, mut rd) = (Vec4::ZERO, Vec2::ZERO);
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                let (n, o) = f(&row[i]);
                let (n, o) = (n.vector(), o.vector());
                rv += Vec4::new(n[0], n[1], o[0], o[1]) * st.w[i][0];
                rd += Vec2::new(n[0], n[1]) * st.dw[i][0];
            }
            (Vec2::new(rv.x, rv.y), rd, Vec2::new(rv.z, rv.w))
        } else {
            let mut r = Vec4::ZERO;
            for i in 0..nodes_along::<D, K, S>(st, 0) {
                let n = f(&row[i]).0.vector();
                r += Vec4::new(n[0], n[1], n[0], n[1])
                    * Vec4::new(st.w[i][0], st.w[i][0], st.dw[i][0], st.dw[i][0]);
            }
            let rn = Vec2::new(r.x, r.y);
            (rn, Vec2::new(r.z, r.w), rn)
        };
        vel += Vec4::new(rn.x, rn.y, ro.x, ro.y) * st.w[j][1];
        grad += Vec4::new(rd.x, rd.y, rn.x, rn.y)
            * Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
    }
    let gradient = D::from_columns([
        D::vector([grad.x, grad.y, 0.0]),
        D::vector([grad.z, grad.w, 0.0]),
        D::Vector::ZERO,
    ]);
    (
        FieldSums {
            value: D::vector([vel.x, vel.y, 0.0]),
            gradient: if A::GRADIENT { gradient } else { D::GRAD_ZERO },
            moment: D::GRAD_ZERO,
        },
        FieldSums {
            value: if second {
                D::vector([vel.z, vel.w, 0.0])
            } else {
                D::Vector::ZERO
            },
            gradient: D::GRAD_ZERO,
            moment: D::GRAD_ZERO,
        },
    )
}

/// [`gather_rows`] in 2D for the values alone of two fields, packing specialisation: f and g
/// side by side in one `Vec4`.
#[inline(always)]
pub fn gather_values_packed_2d<D: Dim, K: Kernel<S>, const S: usize, A, B>(
    nodes: &[Node<D::Vector>],
    st: &Stencil<S>,
    f: impl Fn(&Node<D::Vector>) -> (A, B),
) -> (FieldSums<D>, FieldSums<D>)
where
    A: NodeField<D>,
    B: NodeField<D>,
{
    debug_assert!(D::DIM == 2 && !A::MOMENT && !A::GRADIENT && !B::GRADIENT && !B::MOMENT);
    let p = row_length::<D, S>();
    let nodes = &nodes[..span::<D, S>()];
    let acc = sum_from_first(nodes_along::<D, K, S>(st, 1), |j| {
        let row = &nodes[j * p..j * p + S];
        sum_from_first(nodes_along::<D, K, S>(st, 0), |i| {
            let (n, o) = f(&row[i]);
            let (n, o) = (n.vector(), o.vector());
            Vec4::new(n[0], n[1], o[0], o[1]) * st.w[i][0]
        }) * st.w[j][1]
    });
    let value = |v: D::Vector| FieldSums {
        value: v,
        gradient: D::GRAD_ZERO,
        moment: D::GRAD_ZERO,
    };
    (
        value(D::vector([acc.x, acc.y, 0.0])),
        value(if B::VALUE {
            D::vector([acc.z, acc.w, 0.0])
        } else {
            D::Vector::ZERO
        }),
    )
}

/// The gradient of [`gather_rows`] in 2D, packing specialisation: both columns in one `Vec4`,
/// (L_xx, L_yx, L_xy, L_yy) = Σ_i (f_i, f_i) ∘ (∂_x w_ip ×2, ∂_y w_ip ×2), node by node.
#[inline(always)]
pub fn gradient_packed_2d<D: Dim, K: Kernel<S>, const S: usize>(
    nodes: &[Node<D::Vector>],
    st: &Stencil<S>,
    f: impl Fn(&Node<D::Vector>) -> D::Vector,
) -> D::Grad {
    debug_assert_eq!(D::DIM, 2);
    let p = row_length::<D, S>();
    let nodes = &nodes[..span::<D, S>()];
    let l = sum_from_first(nodes_along::<D, K, S>(st, 1), |j| {
        let row = &nodes[j * p..j * p + S];
        let wj = Vec4::new(st.w[j][1], st.w[j][1], st.dw[j][1], st.dw[j][1]);
        sum_from_first(nodes_along::<D, K, S>(st, 0), |i| {
            let g = Vec4::new(st.dw[i][0], st.dw[i][0], st.w[i][0], st.w[i][0]) * wj;
            let v = f(&row[i]);
            Vec4::new(v[0], v[1], v[0], v[1]) * g
        })
    });
    D::from_columns([
        D::vector([l.x, l.y, 0.0]),
        D::vector([l.z, l.w, 0.0]),
        D::Vector::ZERO,
    ])
}

/// The storage index of the lowest node of the cell holding a particle at `x` (grid spacing
/// 1/`inv_h`), in the block that handles the particle (its place `at`). The cell's nodes all
/// carry weight, so that node is stencil node 0 or 1 along each axis.
#[inline(always)]
pub fn cell_node<D: Dim, const S: usize>(x: D::Vector, inv_h: Real, at: &At<S>) -> usize {
    let xg = grid_coords::<D>(x, inv_h);
    let (mut n, mut stride) = (at.origin, 1);
    for (a, c) in xg.iter().enumerate().take(D::DIM) {
        let k = floor_nonneg(*c) - at.st.base[a];
        debug_assert!((0..S as i32 - 1).contains(&k), "cell outside the stencil");
        n += k as usize * stride;
        stride *= row_length::<D, S>();
    }
    n
}

/// Particles per chunk of the gather between two stress updates (a multiple of `LANES`).
pub const CHUNK: usize = 2 * LANES;

/// The strain rates and spins of one chunk of particles.
pub struct Rates<D: Dim> {
    pub rate: [D::Sym; CHUNK],
    pub spin: [<D::Sym as SymTensor>::Spin; CHUNK],
}

impl<D: Dim> Rates<D> {
    pub fn zero() -> Self {
        Rates {
            rate: [D::Sym::ZERO; CHUNK],
            spin: [Default::default(); CHUNK],
        }
    }
    /// Sets particle `i`'s rate and spin from its velocity gradient.
    #[inline(always)]
    pub fn set(&mut self, i: usize, grad: D::Grad) {
        (self.rate[i], self.spin[i]) = D::rate_and_spin(grad);
    }
}

/// The particle state of a chunk of at most [`CHUNK`] particles that a stress update reads
/// and writes: the plastic strains when the update makes them, and the bulk viscosity's
/// pressures when it computes them.
pub struct Chunk<'a, D: Dim> {
    pub stress: &'a mut [D::Sym],
    pub volume: &'a mut [Real],
    pub mass: &'a [Real],
    pub plastic_strain: Option<&'a mut [Real]>,
    pub viscous_pressure: Option<&'a mut [Real]>,
}

/// One chunk's stress-update state in SIMD lanes: eight particles as two groups of four, side
/// by side ([`Real4x2`]), for [`update_in_lanes`]' `update`.
pub struct InLanes<'a, D: Dim> {
    pub stress: &'a mut <D::Sym as Batch>::Packed2,
    pub rate: <D::Sym as Batch>::Packed2,
    pub spin: <<D::Sym as Batch>::Packed2 as SymTensor>::Spin,
    /// The accumulated plastic strains (zero when the chunk has none).
    pub history: Real4x2,
    pub volume: &'a mut Real4x2,
    /// The masses, when asked for.
    pub mass: Option<Real4x2>,
    /// Where `update` leaves the bulk viscosity's pressures (zero to start with).
    pub viscous_pressure: &'a mut Real4x2,
}

/// The stress update [`update_in_lanes`] runs on a chunk: it returns the plastic strain
/// increments and what the report gains. A trait with an always-inlined method rather than a
/// closure: passed as a closure, the update was compiled as a function of its own (2D sand
/// with the linear kernel: +6 % instructions in the stress pass, +2.6 % in the step).
pub trait LaneUpdate<D: Dim> {
    type Report;
    fn update(self, lanes: InLanes<'_, D>) -> (Real4x2, Self::Report);
}

/// Runs the stress update `update` on the particles of `ps`, whose rates and spins are the
/// first entries of `rates`, in SIMD lanes, eight at a time: the two groups' dependency
/// chains interleave. `update` returns the plastic strain increments (added to the chunk's)
/// and what the report gains, which this returns; `with_mass` puts the masses in lanes too.
///
/// A full chunk is updated where it is stored; a short one is copied and padded with zero
/// stress, rate and plastic strain and a real particle's volume and mass, whose update adds
/// nothing. (Copying every chunk cost four `memcpy` calls per chunk, and the SIMD registers
/// they clobber.)
#[inline(always)]
pub fn update_in_lanes<D: Dim, U: LaneUpdate<D>>(
    rates: &mut Rates<D>,
    ps: Chunk<'_, D>,
    with_mass: bool,
    update: U,
) -> U::Report {
    let len = ps.stress.len();
    let lanes = |m: &[Real]| {
        Real4x2(
            Real4::from_slice(&m[..LANES]),
            Real4::from_slice(&m[LANES..]),
        )
    };
    let mass = with_mass.then(|| {
        if len == CHUNK {
            lanes(ps.mass)
        } else {
            let mut mass = [ps.mass[0]; CHUNK];
            mass[..len].copy_from_slice(ps.mass);
            lanes(&mass)
        }
    });
    // Set only for a short chunk (zeroing them for every chunk cost 4 instructions a particle).
    let (mut pad_stress, mut pad_volume);
    let (stress, volume, short): (&mut [D::Sym; CHUNK], &mut [Real; CHUNK], _) = if len == CHUNK {
        let stress = ps.stress.try_into().expect("a full chunk");
        let volume = ps.volume.try_into().expect("a full chunk");
        (stress, volume, None)
    } else {
        (pad_stress, pad_volume) = ([D::Sym::ZERO; CHUNK], [ps.volume[0]; CHUNK]);
        pad_stress[..len].copy_from_slice(ps.stress);
        pad_volume[..len].copy_from_slice(ps.volume);
        rates.rate[len..].fill(D::Sym::ZERO);
        rates.spin[len..].fill(Default::default());
        (
            &mut pad_stress,
            &mut pad_volume,
            Some((ps.stress, ps.volume)),
        )
    };
    let plastic_strain = ps.plastic_strain;
    let history = match plastic_strain.as_deref() {
        None => Real4x2(Real4::ZERO, Real4::ZERO),
        Some(e) if len == CHUNK => lanes(e),
        Some(e) => {
            let mut padded = [0.0; CHUNK];
            padded[..len].copy_from_slice(e);
            lanes(&padded)
        }
    };
    let mut increments = [0.0; CHUNK];
    // Four tensors into lanes at a time ([`Batch`]), then the two groups side by side.
    let pack = |g: usize| {
        let group = |a: &[D::Sym]| -> [D::Sym; LANES] { a[g..g + LANES].try_into().unwrap() };
        let spins: [_; LANES] = rates.spin[g..g + LANES].try_into().unwrap();
        (
            D::Sym::pack(&group(&stress[..])),
            D::Sym::pack(&group(&rates.rate)),
            D::Sym::pack_spin(&spins),
            Real4::from_slice(&volume[g..g + LANES]),
        )
    };
    let ((s0, r0, w0, v0), (s1, r1, w1, v1)) = (pack(0), pack(LANES));
    let mut s = D::Sym::zip(s0, s1);
    let mut v = Real4x2(v0, v1);
    let mut q = Real4x2(Real4::ZERO, Real4::ZERO);
    let (ep, u) = update.update(InLanes {
        stress: &mut s,
        rate: D::Sym::zip(r0, r1),
        spin: D::Sym::zip_spin(w0, w1),
        history,
        volume: &mut v,
        mass,
        viscous_pressure: &mut q,
    });
    if let Some(pressure) = ps.viscous_pressure {
        match <&mut [Real; CHUNK]>::try_from(&mut *pressure) {
            Ok(out) => {
                q.0.write_to_slice(&mut out[..LANES]);
                q.1.write_to_slice(&mut out[LANES..]);
            }
            Err(_) => {
                let mut all = [0.0; CHUNK];
                q.0.write_to_slice(&mut all[..LANES]);
                q.1.write_to_slice(&mut all[LANES..]);
                pressure.copy_from_slice(&all[..len]);
            }
        }
    }
    let (s0, s1) = D::Sym::unzip(s);
    stress[..LANES].copy_from_slice(&D::Sym::unpack(s0));
    stress[LANES..].copy_from_slice(&D::Sym::unpack(s1));
    v.0.write_to_slice(&mut volume[..LANES]);
    v.1.write_to_slice(&mut volume[LANES..]);
    ep.0.write_to_slice(&mut increments[..LANES]);
    ep.1.write_to_slice(&mut increments[LANES..]);
    if let Some(e) = plastic_strain {
        // A full chunk adds its plastic strains in lanes (one by one they cost 7 instructions
        // a particle); a short one adds them one by one.
        match <&mut [Real; CHUNK]>::try_from(&mut *e) {
            Ok(e) => {
                (history.0 + ep.0).write_to_slice(&mut e[..LANES]);
                (history.1 + ep.1).write_to_slice(&mut e[LANES..]);
            }
            Err(_) => {
                for (e, de) in e.iter_mut().zip(increments) {
                    *e += de;
                }
            }
        }
    }
    if let Some((to_stress, to_volume)) = short {
        to_stress.copy_from_slice(&stress[..len]);
        to_volume.copy_from_slice(&volume[..len]);
    }
    u
}

/// Plain per-node forms: each node's weight and gradient as the products they are, for the
/// tests that compare the row walks and their specialisations with them.
#[cfg(test)]
pub(crate) mod plain {
    use super::*;

    /// Calls `f(index, w_ip, ∇w_ip, d)` for every node of the stencil (index from its first
    /// node; d the node's offset from the particle in cells).
    pub fn for_each_node<D: Dim, const S: usize>(
        st: &Stencil<S>,
        mut f: impl FnMut(usize, Real, D::Vector, D::Vector),
    ) {
        let p = row_length::<D, S>();
        for k in 0..if D::DIM == 3 { S } else { 1 } {
            let (wk, dwk) = third_axis::<D, S>(st, k);
            let dk = if D::DIM == 3 { st.d[k][2] } else { 0.0 };
            for j in 0..S {
                for i in 0..S {
                    let w = st.w[i][0] * st.w[j][1] * wk;
                    let grad = D::vector([
                        st.dw[i][0] * st.w[j][1] * wk,
                        st.w[i][0] * st.dw[j][1] * wk,
                        st.w[i][0] * st.w[j][1] * dwk,
                    ]);
                    let d = D::vector([st.d[i][0], st.d[j][1], dk]);
                    f(i + j * p + k * p * p, w, grad, d);
                }
            }
        }
    }

    /// The plain [`super::gather`]: every sum of every field, node by node.
    pub fn gather<D: Dim, const S: usize, F: Fields<D>>(
        nodes: &[Node<D::Vector>],
        st: &Stencil<S>,
        f: impl Fn(&Node<D::Vector>) -> F,
    ) -> F::Sums {
        let mut acc = F::ZERO_ACC;
        for_each_node::<D, S>(st, |n, w, gw, d| f(&nodes[n]).add_plain(&mut acc, w, gw, d));
        F::finish(acc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::{Gimp, Linear, QuadraticBspline};
    use crate::math::{D2, D3};
    use crate::step::test_util::{noise, random_stencils};

    /// Whether two vectors agree up to rounding, relative to `scale`.
    fn near<V: VectorOps>(a: V, b: V, scale: Real) -> bool {
        (a - b).length() <= 1e-5 * (1.0 + scale)
    }

    /// Whether two nodes' momenta and masses agree up to rounding.
    fn same_mass<V: VectorOps>(x: &Node<V>, y: &Node<V>) -> bool {
        near(x.vel(), y.vel(), y.vel().length())
            && (x.mass() - y.mass()).abs() <= 1e-5 * (1.0 + y.mass().abs())
    }

    /// A made-up particle's mass m, momentum mv, (`affine`) A and (`force`) F.
    #[allow(clippy::type_complexity)]
    fn share<D: Dim>(
        seed: &mut u64,
        affine: bool,
        force: bool,
    ) -> (Real, D::Vector, Option<D::Grad>, Option<D::Sym>) {
        let mut v = || D::vector([0; 3].map(|_| noise(seed)));
        let (mv, a0, a1, a2) = (v(), v(), v(), v());
        let f = D::rate_and_spin(D::from_columns([a2, a1, a0])).0;
        (
            2.5,
            mv,
            affine.then(|| D::from_columns([a0, a1, a2])),
            force.then_some(f),
        )
    }

    /// Terms stated with the walk's [`Weights`] add to the nodes what the same terms as plain
    /// per-node products add, up to rounding: m_i += w_ip m, (mv)_i += w_ip (mv + A d_i),
    /// f_i += F ∇w_ip, ∇m_i += m ∇w_ip; [`scatter_pair`] adds exactly what two scatters add.
    fn scatter_matches_plain<D: Dim, K: Kernel<S>, const S: usize>() {
        let (nodes, stencils) = random_stencils::<D, K, S>(40, row_length::<D, S>());
        let mut seed = 3;
        for (affine, force) in [(false, false), (false, true), (true, false), (true, true)] {
            let (mut rows, mut plain) = (nodes.clone(), nodes.clone());
            let mut g_rows = vec![D::Vector::ZERO; nodes.len()];
            let mut g_plain = g_rows.clone();
            let (mut pair, mut g_pair) = (nodes.clone(), g_rows.clone());
            for st in &stencils {
                let (m, mv, a, f) = share::<D>(&mut seed, affine, force);
                let at = At { st: *st, origin: 0 };
                let columns = a.map(|a| {
                    [0, 1, 2].map(|c| {
                        if c < D::DIM {
                            D::column(&a, c)
                        } else {
                            D::Vector::ZERO
                        }
                    })
                });
                scatter::<D, K, S, _>(&mut rows, &at, |n, w| {
                    let p = columns.map_or(mv, |c| w.plus_offset(mv, c));
                    n.vm += p.with_mass(m) * w.value();
                    if let Some(f) = f {
                        n.new_vel += w.gradient_times(f);
                    }
                });
                scatter::<D, K, S, _>(&mut g_rows, &at, |g, w| *g += w.gradient() * m);
                // The same terms in one walk over both fields: the same sums, bit for bit.
                scatter_pair::<D, K, S, _, _>(&mut pair, &mut g_pair, &at, |n, g, w| {
                    let p = columns.map_or(mv, |c| w.plus_offset(mv, c));
                    n.vm += p.with_mass(m) * w.value();
                    if let Some(f) = f {
                        n.new_vel += w.gradient_times(f);
                    }
                    *g += w.gradient() * m;
                });
                plain::for_each_node::<D, S>(st, |n, w, gw, d| {
                    let mut p = mv;
                    if let Some(a) = a {
                        for x in 0..D::DIM {
                            p += D::column(&a, x) * d[x];
                        }
                    }
                    plain[n].vm += p.with_mass(m) * w;
                    g_plain[n] += gw * m;
                    if let Some(f) = f {
                        let c = D::sym_columns(f);
                        for x in 0..D::DIM {
                            plain[n].new_vel += c[x] * gw[x];
                        }
                    }
                });
            }
            for (n, (x, y)) in rows.iter().zip(&pair).enumerate() {
                let bits = |n: &Node<D::Vector>| format!("{:?} {:?}", n.vm, n.new_vel);
                assert!(bits(x) == bits(y), "pair walk, node {n}");
                assert!(g_rows[n] == g_pair[n], "pair walk, ∇m {n}");
            }
            for (n, (x, y)) in rows.iter().zip(&plain).enumerate() {
                assert!(same_mass(x, y), "momentum at node {n}");
                assert!(near(x.new_vel, y.new_vel, y.new_vel.length()), "force {n}");
                assert!(near(g_rows[n], g_plain[n], g_plain[n].length()), "∇m {n}");
            }
        }
    }

    #[test]
    fn the_scatter_walks_add_the_plain_per_node_shares() {
        scatter_matches_plain::<D2, Linear, 2>();
        scatter_matches_plain::<D2, QuadraticBspline, 3>();
        scatter_matches_plain::<D2, Gimp, 3>();
        scatter_matches_plain::<D3, Linear, 2>();
        scatter_matches_plain::<D3, Gimp, 3>();
    }

    /// The walk on the owners hands each allocated node of a stencil the weight and gradient
    /// the plain per-node products give it, at the node's owner: Σ w_ip and Σ ∇w_ip summed at
    /// each owner agree up to rounding, and the walk reaches every node with weight.
    fn owners_match_plain<D: Dim, K: Kernel<S>, const S: usize>() {
        let (_, stencils) = random_stencils::<D, K, S>(30, row_length::<D, S>());
        let mut grid = Grid::<D>::default();
        grid.rebuild(stencils.len(), S, |q| stencils[q].base);
        let p = row_length::<D, S>();
        let zero = (0.0, D::Vector::ZERO);
        let (mut walked, mut plain) = (vec![zero; grid.nodes.len()], vec![zero; grid.nodes.len()]);
        for st in &stencils {
            on_owners::<D, K, S>(&grid, st, |n, w| {
                walked[n].0 += w.value();
                walked[n].1 += w.gradient();
            });
            plain::for_each_node::<D, S>(st, |local, w, g, _| {
                let (i, j, k) = (local % p, local / p % p, local / (p * p));
                let b = st.base;
                let node = [b[0] + i as i32, b[1] + j as i32, b[2] + k as i32];
                let n = grid
                    .node_index(node)
                    .expect("the stencil's blocks are allocated");
                plain[n].0 += w;
                plain[n].1 += g;
            });
        }
        for (n, (a, b)) in walked.iter().zip(&plain).enumerate() {
            assert!(
                (a.0 - b.0).abs() <= 1e-5 * (1.0 + b.0.abs()),
                "w at node {n}"
            );
            assert!(near(a.1, b.1, b.1.length()), "∇w at node {n}");
        }
        assert!(
            plain.iter().any(|x| x.0 > 0.0),
            "the stencils reach allocated nodes"
        );
    }

    #[test]
    fn the_walk_on_owners_hands_each_owner_its_plain_weights() {
        owners_match_plain::<D2, Linear, 2>();
        owners_match_plain::<D2, QuadraticBspline, 3>();
        owners_match_plain::<D2, Gimp, 3>();
        owners_match_plain::<D3, Linear, 2>();
        owners_match_plain::<D3, Gimp, 3>();
    }

    /// Whether two gradients agree up to rounding, column by column.
    fn near_grad<D: Dim>(a: D::Grad, b: D::Grad) -> bool {
        (0..D::DIM).all(|c| {
            let (x, y) = (D::column(&a, c), D::column(&b, c));
            near(x, y, y.length())
        })
    }

    /// Whether two gradients are the same, bit for bit.
    fn same_grad<D: Dim>(a: D::Grad, b: D::Grad) -> bool {
        (0..D::DIM).all(|c| D::column(&a, c) == D::column(&b, c))
    }

    /// Whether a field's sums agree with the plain ones up to rounding, those asked for
    /// (`value`, `gradient`, `moment`) and the others zero.
    fn near_sums<D: Dim>(s: &FieldSums<D>, plain: &FieldSums<D>, asked: [bool; 3]) -> bool {
        let zero = |g: &D::Grad| same_grad::<D>(*g, D::GRAD_ZERO);
        (if asked[0] {
            near(s.value, plain.value, plain.value.length())
        } else {
            s.value == D::Vector::ZERO
        }) && (if asked[1] {
            near_grad::<D>(s.gradient, plain.gradient)
        } else {
            zero(&s.gradient)
        }) && (if asked[2] {
            near_grad::<D>(s.moment, plain.moment)
        } else {
            zero(&s.moment)
        })
    }

    /// The walks, as a pass calls them ([`gather`]: the row walk, and in 2D its packing
    /// specialisations) and as [`gather_rows`], sum each field's asked-for terms as the plain
    /// per-node sums do, up to rounding, with any number of fields: the gather pass's two
    /// (v_i^{n+1} with its gradient and moment as asked, v_i^n's value or nothing) and a third.
    fn gather_matches_plain<D: Dim, K: Kernel<S>, const S: usize>() {
        type V<D> = <D as Dim>::Vector;
        let (nodes, stencils) = random_stencils::<D, K, S>(50, row_length::<D, S>());
        for st in &stencils {
            let at = At { st: *st, origin: 0 };
            let (new, old) = plain::gather::<D, S, _>(&nodes, st, |n| {
                (
                    Field::<D, true, true, true>(n.new_vel),
                    Field::<D, true, true, true>(n.vel()),
                )
            });
            // Every combination the gather pass asks for: (gradient, moment, old velocity).
            macro_rules! pass {
                ($g:literal, $m:literal, $o:literal) => {{
                    let f = |n: &Node<V<D>>| {
                        (
                            Field::<D, true, $g, $m>(n.new_vel),
                            Field::<D, $o, false, false>(n.vel()),
                        )
                    };
                    let (a, b) = gather::<D, K, S, _>(&nodes, &at, f);
                    assert!(
                        near_sums(&a, &new, [true, $g, $m]),
                        "v^(n+1) {:?}",
                        ($g, $m, $o)
                    );
                    assert!(
                        near_sums(&b, &old, [$o, false, false]),
                        "v^n {:?}",
                        ($g, $m, $o)
                    );
                    // The row walk itself: each sum the same, bit for bit, with or without
                    // the others.
                    let (r, _) = gather_rows::<D, K, S, _>(&nodes, st, f);
                    let (all,) = gather_rows::<D, K, S, _>(&nodes, st, |n: &Node<V<D>>| {
                        (Field::<D, true, true, true>(n.new_vel),)
                    });
                    assert!(r.value == all.value);
                    assert!(!$g || same_grad::<D>(r.gradient, all.gradient));
                    assert!(!$m || same_grad::<D>(r.moment, all.moment));
                }};
            }
            pass!(false, false, false);
            pass!(false, false, true);
            pass!(true, false, false);
            pass!(true, false, true);
            pass!(false, true, false);
            pass!(false, true, true);
            pass!(true, true, false);
            pass!(true, true, true);
            // The gradient walk (in 2D its packing specialisation).
            let l = gradient::<D, K, S>(&nodes, &at, |n| n.vel());
            assert!(near_grad::<D>(l, old.gradient));
            // A third field needs no change to the walks.
            let (plain3, _, _) = plain::gather::<D, S, _>(&nodes, st, |n| {
                (
                    Field::<D, true, true, true>(n.new_vel - n.vel()),
                    Field::<D, false, false, false>(n.vel()),
                    Field::<D, false, false, false>(n.vel()),
                )
            });
            let (a, b, c) = gather::<D, K, S, _>(&nodes, &at, |n| {
                (
                    Field::<D, true, true, false>(n.new_vel),
                    Field::<D, true, false, false>(n.vel()),
                    Field::<D, true, true, true>(n.new_vel - n.vel()),
                )
            });
            assert!(near_sums(&a, &new, [true, true, false]));
            assert!(near_sums(&b, &old, [true, false, false]));
            assert!(near_sums(&c, &plain3, [true, true, true]));
        }
    }

    #[test]
    fn the_gather_walks_sum_the_plain_per_node_terms() {
        gather_matches_plain::<D2, Linear, 2>();
        gather_matches_plain::<D2, QuadraticBspline, 3>();
        gather_matches_plain::<D2, Gimp, 3>();
        gather_matches_plain::<D3, Linear, 2>();
        gather_matches_plain::<D3, QuadraticBspline, 3>();
        gather_matches_plain::<D3, Gimp, 3>();
    }
}
