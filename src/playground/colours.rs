//! The per-particle colour scalar of the views: body, speed, pressure (sand's as recovered on
//! the grid, [`crate::recovery`]), plastic strain, yield state or sleeping, with the range a
//! colour map should span.

use crate::error::{Result, not_one_of};
use crate::material::pq;
use crate::math::{Dim, Real, SymTensor};
use crate::sim::Simulation;

/// What a particle's colour scalar shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourMode {
    /// The body index (a categorical palette).
    Body,
    /// |v| (m/s).
    Speed,
    /// P = −tr σ / 3 (Pa, compression positive).
    Pressure,
    /// Accumulated equivalent plastic strain.
    PlasticStrain,
    /// 0 elastic, 0.5 on the yield surface, 1 flowing (plastic strain grew since the last
    /// colour update).
    Yield,
    /// Awake particles: their body index (as [`ColourMode::Body`]); sleeping ones: −1 − the
    /// body index ([`crate::step::sleep`]).
    Sleeping,
}

impl ColourMode {
    pub const ALL: [(&'static str, ColourMode); 6] = [
        ("body", ColourMode::Body),
        ("speed", ColourMode::Speed),
        ("pressure", ColourMode::Pressure),
        ("plastic_strain", ColourMode::PlasticStrain),
        ("yield", ColourMode::Yield),
        ("sleeping", ColourMode::Sleeping),
    ];

    pub fn parse(name: &str) -> Result<Self> {
        Self::ALL
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, m)| *m)
            .ok_or_else(|| not_one_of("colour", name, Self::ALL.iter().map(|(n, _)| n)))
    }
}

/// The colour scalars of a simulation and the range their map spans.
#[derive(Clone, Debug, Default)]
pub struct Colours {
    pub values: Vec<f32>,
    /// [0, body count) for bodies, [0, 1] for yield states, else [0, the 99th percentile].
    pub range: [f32; 2],
    /// Plastic strain at the previous update, by particle id (for the yield view).
    previous_plastic: Vec<Real>,
}

impl Colours {
    /// Recomputes the scalars of `s` for `mode`.
    pub fn update<D: Dim>(&mut self, s: &Simulation<D>, mode: ColourMode) {
        fill(s, mode, &mut self.values, &mut self.previous_plastic);
        self.range = match mode {
            ColourMode::Body | ColourMode::Sleeping => [0.0, s.bodies().len().max(1) as f32],
            ColourMode::Yield => [0.0, 1.0],
            _ => {
                let hi = percentile(&self.values, 0.99).max(match mode {
                    ColourMode::Speed => 0.05,
                    ColourMode::Pressure => 10.0,
                    _ => 1e-3,
                });
                [0.0, hi]
            }
        };
    }
}

/// The value at fraction `q` of the sorted values (0 for none).
fn percentile(values: &[f32], q: f64) -> f32 {
    let mut v: Vec<f32> = values.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return 0.0;
    }
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    let (_, x, _) = v.select_nth_unstable_by(k, f32::total_cmp);
    *x
}

// `as f32` is a no-op in the default build and a conversion with the `f64` feature.
#[allow(clippy::unnecessary_cast)]
fn fill<D: Dim>(
    s: &Simulation<D>,
    mode: ColourMode,
    out: &mut Vec<f32>,
    previous_plastic: &mut Vec<Real>,
) {
    let p = s.particles();
    out.clear();
    out.resize(p.len(), 0.0);
    match mode {
        ColourMode::Body => {
            for (b, body) in s.bodies().iter().enumerate() {
                out[body.range()].fill(b as f32);
            }
        }
        ColourMode::Sleeping => {
            for (b, body) in s.bodies().iter().enumerate() {
                let (range, active) = (body.range(), body.active());
                out[range.start..active.end].fill(b as f32);
                out[active.end..range.end].fill(-1.0 - b as f32);
            }
        }
        ColourMode::Speed => out.iter_mut().enumerate().for_each(|(i, c)| {
            *c = p.speed(i) as f32;
        }),
        // sand's as recovered on the grid (crate::recovery)
        ColourMode::Pressure => {
            for (c, s) in out.iter_mut().zip(crate::recovery::shown_stress(s)) {
                *c = -s.trace() as f32 / 3.0;
            }
        }
        ColourMode::PlasticStrain => {
            for (c, &e) in out.iter_mut().zip(&p.plastic_strain) {
                *c = e as f32;
            }
        }
        ColourMode::Yield => {
            let max_id = p.id.iter().copied().max().map_or(0, |m| m as usize + 1);
            if previous_plastic.len() < max_id {
                previous_plastic.resize(max_id, Real::NAN);
            }
            for (body, config) in s.bodies().iter().zip(&s.scene().bodies) {
                // sand's cone depends on each particle's plastic strain (the start–stop match)
                let surfaces = config.material.pq_surfaces();
                for i in body.range() {
                    let id = p.id[i] as usize;
                    let ep = p.plastic_strain[i];
                    let surface = surfaces(ep as f64);
                    let before = previous_plastic[id];
                    previous_plastic[id] = ep;
                    let (pressure, q) = pq(p.stress[i]);
                    out[i] = if before.is_finite() && ep > before {
                        1.0
                    } else if surface.reached(pressure, q) {
                        0.5
                    } else {
                        0.0
                    };
                }
            }
        }
    }
}
