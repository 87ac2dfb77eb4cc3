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

    /// Inserts particles before index `at` (the particles from `at` on move up by their
    /// number): at positions `x` with velocities `v`, each of `volume` and `mass`, with zero
    /// stress, plastic strain, viscous pressure, affine velocity and area, and the ids from
    /// `first_id` on.
    pub fn insert(
        &mut self,
        at: usize,
        x: &[D::Vector],
        v: &[D::Vector],
        volume: Real,
        mass: Real,
        first_id: u32,
    ) {
        let n = x.len();
        assert_eq!(v.len(), n, "one velocity per position");
        fn put<T: Clone>(field: &mut Vec<T>, at: usize, values: impl IntoIterator<Item = T>) {
            field.splice(at..at, values);
        }
        put(&mut self.x, at, x.iter().copied());
        put(&mut self.v, at, v.iter().copied());
        put(&mut self.stress, at, std::iter::repeat_n(D::Sym::ZERO, n));
        put(&mut self.volume, at, std::iter::repeat_n(volume, n));
        put(&mut self.mass, at, std::iter::repeat_n(mass, n));
        put(&mut self.plastic_strain, at, std::iter::repeat_n(0.0, n));
        put(&mut self.viscous_pressure, at, std::iter::repeat_n(0.0, n));
        put(&mut self.id, at, first_id..first_id + n as u32);
        if self.with_affine {
            put(&mut self.affine, at, std::iter::repeat_n(D::GRAD_ZERO, n));
        }
        if self.with_area {
            put(&mut self.area, at, std::iter::repeat_n(D::Vector::ZERO, n));
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{D2, Mat2, Vec2};

    /// Inserted particles land at the index given, with zero stress, strain, affine velocity
    /// and area and the ids asked for; every field of the others moves up with them.
    #[test]
    fn insert_moves_every_field_of_the_particles_after() {
        let mut p = Particles::<D2>::default();
        p.enable_affine();
        p.enable_area();
        for i in 0..3 {
            let x = D2::vector([i as Real, 0.0, 0.0]);
            p.push(x, x, 1.0, 2.0, i);
        }
        for i in 0..3 {
            p.stress[i] = SymTensor::iso(i as Real + 1.0);
            p.plastic_strain[i] = i as Real;
            p.viscous_pressure[i] = i as Real;
            p.affine[i] = Mat2::from_diagonal(Vec2::splat(i as Real));
            p.area[i] = D2::vector([i as Real; 3]);
        }
        let before = p.clone();
        let new = [D2::vector([9.0, 9.0, 0.0]); 2];
        p.insert(1, &new, &new, 0.5, 0.25, 7);
        assert_eq!(p.len(), 5);
        assert_eq!(p.id, [0, 7, 8, 1, 2]);
        for (old, now) in [(0, 0), (1, 3), (2, 4)] {
            assert_eq!(p.x[now], before.x[old]);
            assert_eq!(p.v[now], before.v[old]);
            assert_eq!(p.stress[now], before.stress[old]);
            assert_eq!(p.volume[now], before.volume[old]);
            assert_eq!(p.mass[now], before.mass[old]);
            assert_eq!(p.plastic_strain[now], before.plastic_strain[old]);
            assert_eq!(p.viscous_pressure[now], before.viscous_pressure[old]);
            assert_eq!(p.affine[now], before.affine[old]);
            assert_eq!(p.area[now], before.area[old]);
        }
        for i in 1..3 {
            assert_eq!((p.x[i], p.v[i]), (new[0], new[0]));
            assert_eq!((p.volume[i], p.mass[i]), (0.5, 0.25));
            assert_eq!(p.stress[i], <D2 as Dim>::Sym::ZERO);
            assert_eq!((p.plastic_strain[i], p.viscous_pressure[i]), (0.0, 0.0));
            assert_eq!(p.affine[i], D2::GRAD_ZERO);
            assert_eq!(p.area[i], D2::vector([0.0; 3]));
        }
    }
}
