//! The sparse background grid of one body: square blocks of nodes, allocated only where the
//! body's particles reach, indexed through a table over the body's bounding box of blocks.
//! Cost and memory follow the occupied blocks (plus a 4-byte table entry per block of the
//! bounding box), never the domain.
//!
//! Blocks are *padded*: each stores its own `B^d` nodes plus a halo of `S − 1` nodes on its
//! upper side along each axis (S: the kernel's nodes per axis). A particle is handled by the
//! block that holds the first node of its stencil, so its whole stencil lies in that block's
//! storage at fixed strides, with no lookup per node. After the particles scatter, halo values
//! are added to the blocks that own those nodes ([`BlockLayout::reduce_halo`]); before the particles
//! gather, the owners' values are copied into the halos ([`BlockLayout::fill_halo`]).

use crate::math::{Dim, Real, VectorOps, max, min};

/// Ghost nodes before the domain's lower corner along each axis: node `n` sits at
/// `x = (n − GHOST) h`, so that every stencil index is non-negative.
pub const GHOST: i32 = 2;

const EMPTY: u32 = u32::MAX;

/// How many consecutive nodes a stencil of `s` nodes per axis spans in a padded block whose
/// rows are `p` nodes long.
#[inline(always)]
pub fn stencil_span(dim: usize, p: usize, s: usize) -> usize {
    let far = if dim == 3 { 1 + p + p * p } else { 1 + p };
    (s - 1) * far + 1
}

/// One grid node of one body.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct Node<V: VectorOps> {
    /// Momentum while scattering, then the velocity v_i^n; with the mass m_i in the lane
    /// after them (see [`Node::vel`], [`Node::mass`]).
    pub vm: V::WithMass,
    /// Internal force while the stresses scatter, then the updated velocity v_i^{n+1}.
    pub new_vel: V,
}

impl<V: VectorOps> Node<V> {
    /// The mass m_i.
    #[inline(always)]
    pub fn mass(&self) -> Real {
        V::mass_of(self.vm)
    }
    /// The momentum while scattering, then the velocity v_i^n.
    #[inline(always)]
    pub fn vel(&self) -> V {
        V::without_mass(self.vm)
    }
}

/// Where the blocks of a sparse grid are: a table over the bounding box of blocks mapping each
/// block to its storage slot.
#[derive(Clone, Debug)]
pub struct GridIndex<D: Dim> {
    /// Block coordinate of the table's first entry.
    origin: [i32; 3],
    /// Table extent in blocks.
    dims: [usize; 3],
    table: Vec<u32>,
    /// Block coordinate of each allocated block, in slot order.
    blocks: Vec<[i32; 3]>,
    _dim: std::marker::PhantomData<D>,
}

impl<D: Dim> Default for GridIndex<D> {
    fn default() -> Self {
        GridIndex {
            origin: [0; 3],
            dims: [0; 3],
            table: Vec::new(),
            blocks: Vec::new(),
            _dim: Default::default(),
        }
    }
}

impl<D: Dim> GridIndex<D> {
    /// Nodes owned by a block along each axis.
    pub const BLOCK: usize = 1 << D::LOG_BLOCK;
    const MASK: i32 = (1 << D::LOG_BLOCK) - 1;

    /// Number of allocated blocks.
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// Bytes held by the index.
    pub fn memory_bytes(&self) -> usize {
        self.table.capacity() * 4 + self.blocks.capacity() * 12
    }

    /// Block-coordinate bounding box (inclusive) of the allocated blocks.
    pub fn block_bounds(&self) -> ([i32; 3], [i32; 3]) {
        let mut hi = self.origin;
        for a in 0..D::DIM {
            hi[a] += self.dims[a] as i32 - 1;
        }
        (self.origin, hi)
    }

    /// Allocated block coordinates, in slot order.
    pub fn blocks(&self) -> &[[i32; 3]] {
        &self.blocks
    }

    /// Allocates the blocks touched by the stencils of particles whose first stencil nodes are
    /// `bases`, all within `[lo, hi]`; `support` is the number of stencil nodes per axis.
    /// Slots are assigned in table order, so blocks are laid out in space-filling order. `out`
    /// receives, for each particle, `locate(slot, base)` with `base` its first stencil node and
    /// `slot` the block holding that node.
    pub fn rebuild(
        &mut self,
        bases: &[[i32; 3]],
        (mut lo, mut hi): ([i32; 3], [i32; 3]),
        support: usize,
        out: &mut Vec<u32>,
        locate: impl Fn(u32, &[i32; 3]) -> u32,
    ) {
        let slots = out;
        self.blocks.clear();
        self.table.clear();
        self.dims = [0; 3];
        slots.clear();
        if bases.is_empty() {
            return;
        }
        let reach = support as i32 - 1;
        debug_assert!(
            reach < Self::BLOCK as i32,
            "a stencil spans at most two blocks"
        );
        for h in hi.iter_mut().take(D::DIM) {
            *h += reach;
        }
        let mut dims = [1usize; 3];
        for a in 0..D::DIM {
            lo[a] >>= D::LOG_BLOCK;
            hi[a] >>= D::LOG_BLOCK;
            dims[a] = (hi[a] - lo[a] + 1) as usize;
        }
        self.origin = lo;
        self.dims = dims;
        self.table.resize(dims[0] * dims[1] * dims[2], EMPTY);
        let stride = [1, dims[0], dims[0] * dims[1]];

        // Mark every block a stencil reaches (0 = marked, not yet numbered): the block of the
        // first node `t`, and its upper neighbours along the axes where the stencil spills
        // over. Consecutive particles mostly share both, so a repeat is skipped.
        let mut last = u64::MAX;
        let table = &mut self.table;
        slots.extend(bases.iter().map(|b| {
            let (mut t, mut spill) = (0usize, 0u64);
            for a in 0..D::DIM {
                t += ((b[a] >> D::LOG_BLOCK) - lo[a]) as usize * stride[a];
                spill |= ((((b[a] & Self::MASK) + reach) >> D::LOG_BLOCK) as u64) << a;
            }
            let key = (t as u64) << 3 | spill;
            if key != last {
                last = key;
                for corner in 0..1u64 << D::DIM {
                    if corner & !spill == 0 {
                        let mut n = t;
                        for (a, s) in stride.iter().enumerate().take(D::DIM) {
                            n += (corner >> a & 1) as usize * s;
                        }
                        table[n] = 0;
                    }
                }
            }
            t as u32
        }));
        // Number the marked blocks in table order.
        for (t, entry) in self.table.iter_mut().enumerate() {
            if *entry == 0 {
                *entry = self.blocks.len() as u32;
                let (x, y, z) = (
                    t % dims[0],
                    (t / dims[0]) % dims[1],
                    t / (dims[0] * dims[1]),
                );
                self.blocks.push([
                    self.origin[0] + x as i32,
                    self.origin[1] + y as i32,
                    self.origin[2] + z as i32,
                ]);
            }
        }
        for (s, base) in slots.iter_mut().zip(bases) {
            *s = locate(self.table[*s as usize], base);
        }
    }

    /// The slot of the block containing grid node `node`, if allocated.
    #[inline]
    pub fn slot_of(&self, node: [i32; 3]) -> Option<usize> {
        let mut block = [0; 3];
        for a in 0..D::DIM {
            block[a] = node[a] >> D::LOG_BLOCK;
        }
        self.slot_of_block(block)
    }

    /// The slot of the block with block coordinate `block`, if allocated.
    #[inline]
    pub fn slot_of_block(&self, block: [i32; 3]) -> Option<usize> {
        let mut t = 0usize;
        let mut stride = 1usize;
        for a in 0..D::DIM {
            let b = block[a] - self.origin[a];
            if b < 0 || b as usize >= self.dims[a] {
                return None;
            }
            t += b as usize * stride;
            stride *= self.dims[a];
        }
        match self.table.get(t) {
            Some(&s) if s != EMPTY => Some(s as usize),
            _ => None,
        }
    }

    /// The grid coordinate of the first node of allocated block `slot`.
    #[inline]
    pub fn block_origin(&self, slot: usize) -> [i32; 3] {
        let b = self.blocks[slot];
        let mut n = [0; 3];
        for a in 0..D::DIM {
            n[a] = b[a] << D::LOG_BLOCK;
        }
        n
    }
}

/// The halo nodes of a padded block that belong to one neighbour: the neighbour's offset in
/// blocks and the (halo, owner) padded-local index pairs.
#[derive(Clone, Debug)]
struct HaloLinks {
    offset: [i32; 3],
    pairs: Vec<(u32, u32)>,
}

/// How a grid's padded blocks are laid out for a kernel of a given support.
#[derive(Clone, Debug)]
pub struct BlockLayout<D: Dim> {
    /// Halo width (S − 1).
    halo: usize,
    links: Vec<HaloLinks>,
    _dim: std::marker::PhantomData<D>,
}

impl<D: Dim> BlockLayout<D> {
    /// Nodes owned by a block along each axis.
    pub const BLOCK: usize = GridIndex::<D>::BLOCK;

    /// The layout for stencils of `support` nodes per axis.
    pub fn new(support: usize) -> Self {
        let mut l = BlockLayout {
            halo: support - 1,
            links: Vec::new(),
            _dim: Default::default(),
        };
        l.links = l.halo_links();
        l
    }

    /// Nodes per axis of a padded block.
    #[inline(always)]
    pub fn padded(&self) -> usize {
        Self::BLOCK + self.halo
    }

    /// Nodes stored per block.
    #[inline(always)]
    pub fn padded_nodes(&self) -> usize {
        self.padded().pow(D::DIM as u32)
    }

    /// Storage strides of the three axes.
    #[inline(always)]
    pub fn strides(&self) -> [usize; 3] {
        let p = self.padded();
        [1, p, p * p]
    }

    /// The padded-local index of local coordinates.
    #[inline(always)]
    fn local_index(&self, l: [usize; 3]) -> usize {
        let st = self.strides();
        (0..D::DIM).map(|a| l[a] * st[a]).sum()
    }

    /// Storage index of the first stencil node `base` of a particle handled by block `slot`;
    /// stencil node (i, j, k) is at that plus `i + j·strides[1] + k·strides[2]`.
    #[inline(always)]
    pub fn stencil_origin(&self, slot: u32, base: [i32; 3]) -> usize {
        let st = self.strides();
        let mut local = 0;
        for a in 0..D::DIM {
            local += (base[a] & GridIndex::<D>::MASK) as usize * st[a];
        }
        slot as usize * self.padded_nodes() + local
    }

    /// Visits every node block `slot` owns: `f(grid coordinate, storage index)`.
    pub fn for_each_owned(
        &self,
        index: &GridIndex<D>,
        slot: usize,
        mut f: impl FnMut([i32; 3], usize),
    ) {
        let origin = index.block_origin(slot);
        let base = slot * self.padded_nodes();
        let b = Self::BLOCK;
        let nz = if D::DIM == 3 { b } else { 1 };
        for z in 0..nz {
            for y in 0..b {
                for x in 0..b {
                    let l = [x, y, z];
                    let mut c = origin;
                    for a in 0..D::DIM {
                        c[a] += l[a] as i32;
                    }
                    f(c, base + self.local_index(l));
                }
            }
        }
    }

    /// The (halo, owner) index pairs of a padded block, grouped by the owner's direction.
    fn halo_links(&self) -> Vec<HaloLinks> {
        let (b, p) = (Self::BLOCK, self.padded());
        let mut out: Vec<HaloLinks> = Vec::new();
        let nz = if D::DIM == 3 { p } else { 1 };
        for z in 0..nz {
            for y in 0..p {
                for x in 0..p {
                    let l = [x, y, z];
                    let mut offset = [0i32; 3];
                    let mut owner = l;
                    for a in 0..D::DIM {
                        if l[a] >= b {
                            offset[a] = 1;
                            owner[a] -= b;
                        }
                    }
                    if offset == [0; 3] {
                        continue;
                    }
                    let pair = (self.local_index(l) as u32, self.local_index(owner) as u32);
                    match out.iter_mut().find(|h| h.offset == offset) {
                        Some(h) => h.pairs.push(pair),
                        None => out.push(HaloLinks {
                            offset,
                            pairs: vec![pair],
                        }),
                    }
                }
            }
        }
        out
    }

    /// Calls `f(slot, neighbour slot, links)` for every allocated neighbour owning halo nodes.
    fn for_each_link(&self, index: &GridIndex<D>, mut f: impl FnMut(usize, usize, &[(u32, u32)])) {
        for slot in 0..index.block_count() {
            let b = index.blocks[slot];
            for links in &self.links {
                let mut nb = b;
                for a in 0..D::DIM {
                    nb[a] += links.offset[a];
                }
                if let Some(owner) = index.slot_of_block(nb) {
                    f(slot, owner, &links.pairs);
                }
            }
        }
    }

    /// Adds the halo values of `data` (laid out like the nodes) into the nodes that own them.
    /// Halo nodes whose owner is not allocated hold nothing (no stencil reached them).
    pub fn reduce_halo<T: Copy>(
        &self,
        index: &GridIndex<D>,
        data: &mut [T],
        add: impl Fn(&mut T, &T),
    ) {
        let pn = self.padded_nodes();
        self.for_each_link(index, |slot, owner, pairs| {
            for &(h, o) in pairs {
                let v = data[slot * pn + h as usize];
                add(&mut data[owner * pn + o as usize], &v);
            }
        });
    }

    /// Copies the owners' values into the halos of `data` with `copy(halo, owner)`.
    pub fn fill_halo<T: Copy>(
        &self,
        index: &GridIndex<D>,
        data: &mut [T],
        copy: impl Fn(&mut T, &T),
    ) {
        let pn = self.padded_nodes();
        self.for_each_link(index, |slot, owner, pairs| {
            for &(h, o) in pairs {
                let v = data[owner * pn + o as usize];
                copy(&mut data[slot * pn + h as usize], &v);
            }
        });
    }
}

/// The sparse grid of one body: where its blocks are, and its node values.
#[derive(Clone, Debug)]
pub struct Grid<D: Dim> {
    pub index: GridIndex<D>,
    pub layout: BlockLayout<D>,
    /// Node storage: `slot * padded_nodes() + padded local index`.
    pub nodes: Vec<Node<D::Vector>>,
    /// Σ_p m_p ∇w_ip, filled only for bodies that may touch another body.
    pub mass_grad: Vec<D::Vector>,
    /// For each particle of the body: the storage index (in `nodes`) of its first stencil
    /// node, in the block that holds that node. The passes read a particle's stencil from
    /// there, and the block is this divided by [`BlockLayout::padded_nodes`].
    pub particle_node: Vec<u32>,
    /// Σ_p V_p tr ε̇_p and Σ_p V_p over the particles of each cell, at the cell's lowest node
    /// (laid out like `nodes`): filled by the stress pass only for sand whose volumetric rate
    /// is averaged over cells, empty otherwise.
    pub cell_dilatation: Vec<[Real; 2]>,
    /// Scratch: each particle's first stencil node.
    bases: Vec<[i32; 3]>,
}

impl<D: Dim> Default for Grid<D> {
    fn default() -> Self {
        Grid {
            index: GridIndex::default(),
            layout: BlockLayout::new(2),
            nodes: Vec::new(),
            mass_grad: Vec::new(),
            particle_node: Vec::new(),
            cell_dilatation: Vec::new(),
            bases: Vec::new(),
        }
    }
}

impl<D: Dim> Grid<D> {
    /// Nodes owned by a block along each axis.
    pub const BLOCK: usize = GridIndex::<D>::BLOCK;

    /// Allocates the blocks touched by the stencils of particles whose first stencil nodes are
    /// `base_of(p)` for `p in 0..count`, `support` nodes per axis, zeroes every node and
    /// records each particle's block.
    pub fn rebuild(&mut self, count: usize, support: usize, base_of: impl Fn(usize) -> [i32; 3]) {
        if support - 1 != self.layout.halo {
            self.layout = BlockLayout::new(support);
        }
        // The bases and their bounds in one sweep. In native 3D builds the bounds are kept in
        // floating point (exact: node indices are below 2^22), which LLVM keeps in SIMD
        // registers where SSE2's integer form costs compares and selects per axis; in 2D it
        // vectorises the integer form over four particles, which is cheaper still, and wasm
        // has integer SIMD min and max (docs/performance.md).
        let in_reals = D::DIM == 3 && !cfg!(target_arch = "wasm32");
        let (mut lo, mut hi) = ([0; 3], [0; 3]);
        let (mut lo_r, mut hi_r) = ([0.0; 3], [0.0; 3]);
        for a in 0..D::DIM {
            (lo[a], hi[a]) = (i32::MAX, i32::MIN);
            (lo_r[a], hi_r[a]) = (Real::INFINITY, Real::NEG_INFINITY);
        }
        self.bases.clear();
        self.bases.extend((0..count).map(|p| {
            let b = base_of(p);
            for a in 0..D::DIM {
                if in_reals {
                    lo_r[a] = min(lo_r[a], b[a] as Real);
                    hi_r[a] = max(hi_r[a], b[a] as Real);
                } else {
                    lo[a] = lo[a].min(b[a]);
                    hi[a] = hi[a].max(b[a]);
                }
            }
            b
        }));
        if in_reals {
            for a in 0..D::DIM {
                (lo[a], hi[a]) = (lo_r[a] as i32, hi_r[a] as i32);
            }
        }
        let (layout, bases) = (&self.layout, &self.bases);
        self.index.rebuild(
            bases,
            (lo, hi),
            support,
            &mut self.particle_node,
            |slot, base| layout.stencil_origin(slot, *base) as u32,
        );
        let node_count = self.index.block_count() * self.layout.padded_nodes();
        // Node indices are kept in 32 bits: 2³² nodes would take 128 GiB.
        assert!(
            node_count <= u32::MAX as usize,
            "grid of {node_count} nodes: more than 2^32"
        );
        self.nodes.clear();
        self.nodes.resize(node_count, Node::default());
        self.mass_grad.clear();
    }

    /// Allocates (zeroed) mass gradients for every node.
    pub fn enable_mass_gradient(&mut self) {
        self.mass_grad.clear();
        self.mass_grad.resize(self.nodes.len(), D::Vector::ZERO);
    }

    /// Bytes held by this grid.
    pub fn memory_bytes(&self) -> usize {
        self.index.memory_bytes()
            + self.nodes.capacity() * std::mem::size_of::<Node<D::Vector>>()
            + self.mass_grad.capacity() * std::mem::size_of::<D::Vector>()
            + self.particle_node.capacity() * 4
            + self.cell_dilatation.capacity() * std::mem::size_of::<[Real; 2]>()
    }

    /// Adds halo node values into their owners with `add(owner, halo)`.
    pub fn reduce_nodes(&mut self, add: impl Fn(&mut Node<D::Vector>, &Node<D::Vector>)) {
        self.layout.reduce_halo(&self.index, &mut self.nodes, add);
    }

    /// Copies owner node values into the halos with `copy(halo, owner)`.
    pub fn fill_nodes(&mut self, copy: impl Fn(&mut Node<D::Vector>, &Node<D::Vector>)) {
        self.layout.fill_halo(&self.index, &mut self.nodes, copy);
    }

    /// Adds halo mass gradients into their owners.
    pub fn reduce_mass_gradient(&mut self) {
        self.layout
            .reduce_halo(&self.index, &mut self.mass_grad, |o, h| *o += *h);
    }

    /// The storage index of grid node `node` in the block that owns it, if allocated.
    pub fn node_index(&self, node: [i32; 3]) -> Option<usize> {
        let slot = self.index.slot_of(node)?;
        let mut l = [0usize; 3];
        for a in 0..D::DIM {
            l[a] = (node[a] & GridIndex::<D>::MASK) as usize;
        }
        Some(slot * self.layout.padded_nodes() + self.layout.local_index(l))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{D2, D3};

    #[test]
    fn blocks_follow_particles_not_the_domain() {
        // two clusters far apart: only their blocks are allocated
        let bases = [[10, 10, 10], [11, 10, 10], [200, 300, 10]];
        let mut g = Grid::<D3>::default();
        g.rebuild(bases.len(), 3, |p| bases[p]);
        // cluster 1 spans nodes 10..=13 in x → blocks 2,3; y,z 10..=12 → blocks 2,3:
        // 8 blocks; cluster 2: x 200..=202 (block 50), y 300..302 (75), z 10..12 (2..3): 2.
        assert_eq!(g.index.block_count(), 10);
        assert_eq!(g.nodes.len(), 10 * 6 * 6 * 6);
        for b in bases {
            for d in 0..3 {
                assert!(g.node_index([b[0] + d, b[1] + d, b[2] + d]).is_some());
            }
        }
        assert!(g.node_index([100, 100, 10]).is_none());
        assert_eq!(g.particle_node.len(), 3);
    }

    /// Scattering through padded blocks and reducing the halos gives the same node sums as
    /// adding into the owners directly, and filling the halos gives every stencil node the
    /// owner's value.
    fn halo_round_trip<D: Dim>(support: usize) {
        let bases: Vec<[i32; 3]> = (0..200)
            .map(|p| {
                let mut b = [0; 3];
                for a in 0..D::DIM {
                    b[a] = 3 + ((p * (7 + 5 * a) + a * 13) % 23) as i32;
                }
                b
            })
            .collect();
        let mut g = Grid::<D>::default();
        g.rebuild(bases.len(), support, |p| bases[p]);
        for (p, b) in bases.iter().enumerate() {
            assert_eq!(
                Some(g.particle_node[p] as usize),
                g.node_index(*b),
                "particle {p}: its first stencil node, in the block that owns it"
            );
        }
        let st = g.layout.strides();
        let stencil = |origin: usize| {
            let nz = if D::DIM == 3 { support } else { 1 };
            let mut v = Vec::new();
            for k in 0..nz {
                for j in 0..support {
                    for i in 0..support {
                        v.push(((i, j, k), origin + i * st[0] + j * st[1] + k * st[2]));
                    }
                }
            }
            v
        };
        let mut direct = std::collections::HashMap::new();
        let mut data = vec![0.0f64; g.nodes.len()];
        for (p, b) in bases.iter().enumerate() {
            let origin = g.particle_node[p] as usize;
            for ((i, j, k), n) in stencil(origin) {
                let w = (p + 1) as f64;
                data[n] += w;
                let key = [
                    b[0] + i as i32,
                    b[1] + j as i32,
                    if D::DIM == 3 { b[2] + k as i32 } else { 0 },
                ];
                *direct.entry(key).or_insert(0.0) += w;
            }
        }
        g.layout.reduce_halo(&g.index, &mut data, |o, h| *o += *h);
        for (node, sum) in &direct {
            let n = g.node_index(*node).unwrap();
            assert!(
                (data[n] - sum).abs() < 1e-9,
                "node {node:?}: {} vs {sum}",
                data[n]
            );
        }
        g.layout.fill_halo(&g.index, &mut data, |h, o| *h = *o);
        for (p, b) in bases.iter().enumerate() {
            let origin = g.particle_node[p] as usize;
            for ((i, j, k), n) in stencil(origin) {
                let key = [
                    b[0] + i as i32,
                    b[1] + j as i32,
                    if D::DIM == 3 { b[2] + k as i32 } else { 0 },
                ];
                assert_eq!(data[n], direct[&key]);
            }
        }
    }

    #[test]
    fn halos_reduce_into_and_fill_from_their_owners() {
        for s in [2, 3] {
            halo_round_trip::<D2>(s);
            halo_round_trip::<D3>(s);
        }
    }
}
