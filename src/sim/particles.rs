//! Particle state, structure of arrays. The particles of one body are contiguous.

use crate::math::{Dim, Real, SymTensor, VectorOps};
use std::ops::Range;

/// The state of every particle of a simulation.
#[derive(Clone, Default)]
pub struct Particles<D: Dim> {
    /// Position x_p (m). In 3D the vectors are SIMD `Vec3A`: four floats per particle in
    /// memory, the fourth unused (a renderer reads them with a stride of 16 bytes).
    pub x: Vec<D::Vector>,
    /// Velocity v_p (m/s).
    pub v: Vec<D::Vector>,
    /// Cauchy stress σ_p (Pa, tension positive).
    pub stress: Vec<D::Sym>,
    /// Volume V_p (m³; m² per unit depth in 2D).
    pub volume: Vec<Real>,
    /// Mass m_p (kg; kg/m in 2D).
    pub mass: Vec<Real>,
    /// Accumulated equivalent plastic strain.
    pub plastic_strain: Vec<Real>,
    /// The artificial bulk viscosity q_p ≥ 0 (Pa) of a solid's latest stress update, a pressure
    /// its next force adds to the stress (see [`crate::step::stress`]); zero for sand.
    pub viscous_pressure: Vec<Real>,
    /// A stable identifier (particles are reordered for locality).
    pub id: Vec<u32>,
    /// The affine velocity C_p of APIC (Jiang et al. 2015); empty unless a body uses APIC.
    pub affine: Vec<D::Grad>,
    /// Whether `affine` is kept (one entry per particle).
    with_affine: bool,
    /// The area vector n da of a surface particle under a traction (m², m per unit depth in
    /// 2D; zero inside the body; [`crate::step::traction`]); empty unless a body has a
    /// traction.
    pub area: Vec<D::Vector>,
    with_area: bool,
}

/// Debug lists the traction's area vectors only where a body has a traction, so the state of
/// a scene without one prints (and hashes, in the throughput bench's digest) as it did before
/// tractions existed.
impl<D: Dim> std::fmt::Debug for Particles<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut s = f.debug_struct("Particles");
        s.field("x", &self.x)
            .field("v", &self.v)
            .field("stress", &self.stress)
            .field("volume", &self.volume)
            .field("mass", &self.mass)
            .field("plastic_strain", &self.plastic_strain)
            .field("viscous_pressure", &self.viscous_pressure)
            .field("id", &self.id)
            .field("affine", &self.affine)
            .field("with_affine", &self.with_affine);
        if self.with_area {
            s.field("area", &self.area)
                .field("with_area", &self.with_area);
        }
        s.finish()
    }
}

impl<D: Dim> Particles<D> {
    pub fn len(&self) -> usize {
        self.x.len()
    }
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Appends a particle at rest with zero stress.
    pub fn push(&mut self, x: D::Vector, v: D::Vector, volume: Real, mass: Real, id: u32) {
        self.x.push(x);
        self.v.push(v);
        self.stress.push(D::Sym::ZERO);
        self.volume.push(volume);
        self.mass.push(mass);
        self.plastic_strain.push(0.0);
        self.viscous_pressure.push(0.0);
        self.id.push(id);
        if self.with_affine {
            self.affine.push(D::GRAD_ZERO);
        }
        if self.with_area {
            self.area.push(D::Vector::ZERO);
        }
    }

    /// Keeps area vectors (zero to begin with) for every particle, for bodies under a
    /// traction.
    pub fn enable_area(&mut self) {
        if !self.with_area {
            self.with_area = true;
            self.area.resize(self.len(), D::Vector::ZERO);
        }
    }

    /// Keeps affine velocities (zero to begin with) for every particle, for APIC bodies.
    pub fn enable_affine(&mut self) {
        if !self.with_affine {
            self.with_affine = true;
            self.affine.resize(self.len(), D::GRAD_ZERO);
        }
    }

    /// Removes the particles of `range`.
    pub fn remove(&mut self, range: Range<usize>) {
        self.x.drain(range.clone());
        self.v.drain(range.clone());
        self.stress.drain(range.clone());
        self.volume.drain(range.clone());
        self.mass.drain(range.clone());
        self.plastic_strain.drain(range.clone());
        self.viscous_pressure.drain(range.clone());
        self.id.drain(range.clone());
        if self.with_affine {
            self.affine.drain(range.clone());
        }
        if self.with_area {
            self.area.drain(range);
        }
    }

    /// Removes every particle.
    pub fn clear(&mut self) {
        self.x.clear();
        self.v.clear();
        self.stress.clear();
        self.volume.clear();
        self.mass.clear();
        self.plastic_strain.clear();
        self.viscous_pressure.clear();
        self.id.clear();
        self.affine.clear();
        self.area.clear();
    }

    /// Reorders the particles of `range` so that the particle now at `range.start + i` is the
    /// one that was at `range.start + order[i]`.
    pub fn permute(&mut self, range: Range<usize>, order: &[u32]) {
        fn apply<T: Copy>(v: &mut [T], order: &[u32]) {
            let old: Vec<T> = v.to_vec();
            for (dst, &src) in v.iter_mut().zip(order) {
                *dst = old[src as usize];
            }
        }
        let r = range;
        apply(&mut self.x[r.clone()], order);
        apply(&mut self.v[r.clone()], order);
        apply(&mut self.stress[r.clone()], order);
        apply(&mut self.volume[r.clone()], order);
        apply(&mut self.mass[r.clone()], order);
        apply(&mut self.plastic_strain[r.clone()], order);
        apply(&mut self.viscous_pressure[r.clone()], order);
        apply(&mut self.id[r.clone()], order);
        if self.with_affine {
            apply(&mut self.affine[r.clone()], order);
        }
        if self.with_area {
            apply(&mut self.area[r], order);
        }
    }

    /// Bytes of particle state per particle.
    pub fn bytes_per_particle() -> usize {
        2 * std::mem::size_of::<D::Vector>()
            + std::mem::size_of::<D::Sym>()
            + 4 * std::mem::size_of::<Real>()
            + 4
    }

    /// Pressure P = −tr(σ)/3 of particle `p` (Pa).
    pub fn pressure(&self, p: usize) -> Real {
        -self.stress[p].trace() / 3.0
    }

    /// Speed |v_p| (m/s).
    pub fn speed(&self, p: usize) -> Real {
        self.v[p].length()
    }
}
