//! The SIMD specialisation of the stress update ([`super::update_one`] is the reference; a test
//! in [`super`] checks that they agree bit for bit).

use super::{Group, StressState, update_group};
use crate::material::Constitutive;
use crate::math::{Dim, Real, Real4x2, SymTensor, max};
use crate::step::report::StressReport;
use crate::step::walk::{self, Chunk, Rates};

/// Steps 2–3 for the particles of `ps` (at most [`walk::CHUNK`], the first of them particle
/// `first`), whose rates and spins are the first entries of `rates`: `update_group` for
/// eight particles at once in SIMD lanes ([`walk::update_in_lanes`]), a specialisation of
/// [`super::update_one`].
#[inline(always)]
pub fn update_chunk<D: Dim, M: Constitutive>(
    model: &M,
    rates: &mut Rates<D>,
    ps: StressState<'_, D>,
    first: usize,
    dt: Real,
    report: &mut StressReport,
) {
    let StressState {
        stress,
        volume,
        mass,
        plastic_strain,
        viscous_pressure,
        bulk_length: length,
        closing,
    } = ps;
    let packed = model.packed_specific_volume();
    // The masses: for a granular model's packed volume m_p/ρ, and the bulk viscosity's
    // m_p (C h)².
    let with_mass = length > 0.0 || packed.is_some();
    let lanes = Chunk {
        stress: &mut *stress,
        volume: &mut *volume,
        mass,
        plastic_strain: M::PLASTIC.then_some(plastic_strain),
        viscous_pressure: (length > 0.0).then_some(viscous_pressure),
    };
    let update = Update {
        model,
        packed,
        closing,
        length,
        dt,
    };
    let u = walk::update_in_lanes(rates, lanes, with_mass, update);
    if u.finite {
        report.elastic += u.elastic;
        report.dissipated += u.dissipated;
        report.max_volume = max(report.max_volume, u.max_volume);
        report.viscous += u.viscous;
        report.max_compression = max(report.max_compression, u.max_compression);
    } else {
        // Only a chunk that was not all finite is looked at particle by particle.
        for (i, (s, &v)) in stress.iter().zip(volume.iter()).enumerate() {
            if !(s.is_finite() && v.is_finite() && v > 0.0) {
                report.bad(first + i, s.is_finite(), v);
            }
        }
    }
}

/// `update_group` on one chunk in lanes, with the chunk's packed volumes and bulk viscosity.
struct Update<'m, M> {
    model: &'m M,
    packed: Option<Real>,
    closing: bool,
    length: Real,
    dt: Real,
}

impl<D: Dim, M: Constitutive> walk::LaneUpdate<D> for Update<'_, M> {
    type Report = Group;
    #[inline(always)]
    fn update(self, l: walk::InLanes<'_, D>) -> (Real4x2, Group) {
        let Update {
            model,
            packed,
            closing,
            length,
            dt,
        } = self;
        let packed = packed.zip(l.mass).map(|(s, m)| m * s);
        let bulk = l
            .mass
            .filter(|_| length > 0.0)
            .map(|m| m * (length * length));
        let q = bulk.map(|b| (b, l.viscous_pressure));
        update_group(
            model, l.stress, l.rate, l.spin, l.history, l.volume, packed, closing, q, dt,
        )
    }
}
