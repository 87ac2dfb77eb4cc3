//! The sparse background grid of one body: square blocks of nodes, allocated only where the
//! body's particles reach, indexed through a table over the body's bounding box of blocks.
//!
//! Cost and memory follow the occupied blocks (plus a 4-byte table entry per block of the
//! bounding box), never the domain.

use crate::kernel::{KernelKind, floor_nonneg};
use crate::math::{Dim, Real, VectorOps};

/// Ghost nodes before the domain's lower corner along each axis: node `n` sits at
/// `x = (n − GHOST) h`, so that every stencil index is non-negative.
pub const GHOST: i32 = 2;

const EMPTY: u32 = u32::MAX;

/// One grid node of one body.
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub struct Node<V> {
    pub mass: Real,
    /// Momentum while scattering, then the velocity v_i^n.
    pub vel: V,
    /// Internal force while the stresses scatter, then the updated velocity v_i^{n+1}.
    pub new_vel: V,
}

/// The table offsets of a particle's stencil nodes along each axis (see [`Grid::node`]).
#[derive(Clone, Copy, Debug)]
pub struct StencilIndex<const S: usize> {
    table: [[usize; S]; 3],
    local: [[usize; S]; 3],
}

/// The sparse grid of one body: where its blocks are, and its node values.
#[derive(Clone, Debug)]
pub struct Grid<D: Dim> {
    pub index: GridIndex<D>,
    pub nodes: Vec<Node<D::Vector>>,
    /// Σ_p m_p ∇w_ip, filled only for bodies that may touch another body.
    pub mass_grad: Vec<D::Vector>,
}

impl<D: Dim> Default for Grid<D> {
    fn default() -> Self {
        Grid {
            index: GridIndex::default(),
            nodes: Vec::new(),
            mass_grad: Vec::new(),
        }
    }
}

impl<D: Dim> Grid<D> {
    /// Allocates the blocks touched by the stencils of particles whose base nodes are given
    /// by `base_of(p)` for `p in 0..count` (see [`GridIndex::rebuild`]) and zeroes every node.
    pub fn rebuild(&mut self, count: usize, support: usize, base_of: impl Fn(usize) -> [i32; 3]) {
        self.index.rebuild(count, support, base_of);
        self.nodes.clear();
        self.nodes.resize(
            self.index.block_count() * GridIndex::<D>::block_nodes(),
            Node::default(),
        );
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
    /// Nodes along each axis of a block.
    pub const BLOCK: usize = 1 << D::LOG_BLOCK;
    const MASK: i32 = (1 << D::LOG_BLOCK) - 1;

    /// Nodes in one block.
    pub fn block_nodes() -> usize {
        Self::BLOCK.pow(D::DIM as u32)
    }

    /// Number of allocated blocks.
    pub fn block_count(&self) -> usize {
        self.blocks.len()
    }

    /// The table extent (blocks of the bounding box).
    pub fn table_len(&self) -> usize {
        self.table.len()
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

    /// Allocates the blocks touched by the stencils of particles whose base nodes are given
    /// by `base_of(p)` for `p in 0..count`; `support` is the number of stencil nodes per axis.
    /// Slots are assigned in table order, so blocks are laid out in space-filling order.
    pub fn rebuild(&mut self, count: usize, support: usize, base_of: impl Fn(usize) -> [i32; 3]) {
        self.blocks.clear();
        if count == 0 {
            self.table.clear();
            self.dims = [0; 3];
            return;
        }
        let reach = support as i32 - 1;
        let (mut lo, mut hi) = ([i32::MAX; 3], [i32::MIN; 3]);
        for p in 0..count {
            let b = base_of(p);
            for a in 0..D::DIM {
                lo[a] = lo[a].min(b[a]);
                hi[a] = hi[a].max(b[a] + reach);
            }
        }
        let mut dims = [1usize; 3];
        for a in 0..D::DIM {
            lo[a] >>= D::LOG_BLOCK;
            hi[a] >>= D::LOG_BLOCK;
            dims[a] = (hi[a] - lo[a] + 1) as usize;
        }
        self.origin = lo;
        self.dims = dims;
        let len = dims[0] * dims[1] * dims[2];
        self.table.clear();
        self.table.resize(len, EMPTY);

        // Mark every block a stencil reaches (0 = marked, not yet numbered).
        let mut last = (usize::MAX, usize::MAX);
        for p in 0..count {
            let b = base_of(p);
            let (t0, t1) = (self.table_index(b), self.table_index(add(b, reach)));
            if (t0, t1) == last {
                continue;
            }
            last = (t0, t1);
            let mut blo = [0i32; 3];
            let mut bhi = [0i32; 3];
            for a in 0..D::DIM {
                blo[a] = (b[a] >> D::LOG_BLOCK) - self.origin[a];
                bhi[a] = ((b[a] + reach) >> D::LOG_BLOCK) - self.origin[a];
            }
            for z in blo[2]..=bhi[2] {
                for y in blo[1]..=bhi[1] {
                    for x in blo[0]..=bhi[0] {
                        let t = x as usize + dims[0] * (y as usize + dims[1] * z as usize);
                        self.table[t] = 0;
                    }
                }
            }
        }
        // Number the marked blocks in table order.
        for z in 0..dims[2] {
            for y in 0..dims[1] {
                for x in 0..dims[0] {
                    let t = x + dims[0] * (y + dims[1] * z);
                    if self.table[t] == 0 {
                        self.table[t] = self.blocks.len() as u32;
                        self.blocks.push([
                            self.origin[0] + x as i32,
                            self.origin[1] + y as i32,
                            self.origin[2] + z as i32,
                        ]);
                    }
                }
            }
        }
    }

    #[inline(always)]
    fn table_index(&self, node: [i32; 3]) -> usize {
        let mut t = 0usize;
        let mut stride = 1usize;
        for a in 0..D::DIM {
            t += ((node[a] >> D::LOG_BLOCK) - self.origin[a]) as usize * stride;
            stride *= self.dims[a];
        }
        t
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

    /// The storage index of grid node `node`, if its block is allocated.
    #[inline]
    pub fn node_index(&self, node: [i32; 3]) -> Option<usize> {
        let slot = self.slot_of(node)?;
        let mut local = 0usize;
        for a in 0..D::DIM {
            local += ((node[a] & Self::MASK) as usize) << (D::LOG_BLOCK as usize * a);
        }
        Some(slot * Self::block_nodes() + local)
    }

    /// Precomputes the per-axis table and local offsets of a stencil with base node `base`.
    #[inline(always)]
    pub fn stencil_index<const S: usize>(&self, base: [i32; 3]) -> StencilIndex<S> {
        let mut si = StencilIndex {
            table: [[0; S]; 3],
            local: [[0; S]; 3],
        };
        let mut stride = 1usize;
        for a in 0..D::DIM {
            for k in 0..S {
                let n = base[a] + k as i32;
                si.table[a][k] = ((n >> D::LOG_BLOCK) - self.origin[a]) as usize * stride;
                si.local[a][k] = ((n & Self::MASK) as usize) << (D::LOG_BLOCK as usize * a);
            }
            stride *= self.dims[a];
        }
        si
    }

    /// Storage index of the stencil node at offsets `ijk` (from [`Dim::for_each_node`]).
    #[inline(always)]
    pub fn node<const S: usize>(&self, si: &StencilIndex<S>, ijk: [usize; 3]) -> usize {
        let t = si.table[0][ijk[0]] + si.table[1][ijk[1]] + si.table[2][ijk[2]];
        let local = si.local[0][ijk[0]] + si.local[1][ijk[1]] + si.local[2][ijk[2]];
        self.table[t] as usize * Self::block_nodes() + local
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

    /// The grid coordinate of the node stored at `index`.
    #[inline]
    pub fn node_coord(&self, index: usize) -> [i32; 3] {
        let bn = Self::block_nodes();
        let mut n = self.block_origin(index / bn);
        let local = index % bn;
        for (a, c) in n.iter_mut().enumerate().take(D::DIM) {
            *c += ((local >> (D::LOG_BLOCK as usize * a)) & Self::MASK as usize) as i32;
        }
        n
    }

    /// Allocated block coordinates, in slot order.
    pub fn blocks(&self) -> &[[i32; 3]] {
        &self.blocks
    }
}

#[inline(always)]
fn add(b: [i32; 3], r: i32) -> [i32; 3] {
    [b[0] + r, b[1] + r, b[2] + r]
}

/// The base node of a particle at position `x` and of half-width `lp` grid units for a kernel.
#[inline(always)]
pub fn base_node<D: Dim>(x: D::Vector, inv_h: Real, kernel: KernelKind, lp: Real) -> [i32; 3] {
    let off = GHOST as Real - kernel.base_offset(lp);
    let mut b = [0; 3];
    for (a, bb) in b.iter_mut().enumerate().take(D::DIM) {
        *bb = floor_nonneg(x[a] * inv_h + off);
    }
    b
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
        // cluster 1 spans nodes 10..=13 in x → blocks 2,3; y,z 10..=12 → block 2,3 in y,z
        // (12 >> 2 = 3): 2*2*2 = 8 blocks; cluster 2: x 200..=202 (block 50), y 300..302 (75),
        // z 10..12 (2..3) → 2 blocks.
        assert_eq!(g.index.block_count(), 10);
        assert_eq!(g.nodes.len(), 10 * 64);
        for b in bases {
            for d in 0..3 {
                let n = [b[0] + d, b[1] + d, b[2] + d];
                assert!(g.index.node_index(n).is_some());
            }
        }
        assert!(g.index.node_index([100, 100, 10]).is_none());
    }

    #[test]
    fn node_index_round_trips() {
        let bases = [[3, 4, 0], [17, 9, 0]];
        let mut g = GridIndex::<D2>::default();
        g.rebuild(2, 2, |p| bases[p]);
        for b in bases {
            let si = g.stencil_index::<2>(b);
            for j in 0..2 {
                for i in 0..2 {
                    let idx = g.node(&si, [i, j, 0]);
                    assert_eq!(g.node_coord(idx), [b[0] + i as i32, b[1] + j as i32, 0]);
                    assert_eq!(g.node_index(g.node_coord(idx)), Some(idx));
                }
            }
        }
    }
}
