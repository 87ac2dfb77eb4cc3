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
    /// 0 elastic, 0.5 on the yield surface, 1 flowing: plastic strain growing faster than
    /// [`FLOWING_RATE`] since the last colour update.
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

/// The equivalent plastic strain rate (1/s) above which the yield view calls a particle
/// flowing: 10 % a second. A heap at rest keeps a few hundred particles on its cone whose
/// plastic strain creeps up by round-off and by the grid's small oscillations (the notched
/// block of the stress-path lesson at *Live*, 2–4 s: about 250 of 2 500, at a median of
/// 4·10⁻⁷ /s and at most 0.2 /s), while a flowing one strains at 0.2–10 /s.
pub const FLOWING_RATE: f64 = 0.1;

/// The colour scalars of a simulation and the range their map spans.
#[derive(Clone, Debug, Default)]
pub struct Colours {
    pub values: Vec<f32>,
    /// [0, body count) for bodies, [0, 1] for yield states, else [0, the 99th percentile].
    pub range: [f32; 2],
    /// Plastic strain at the previous update, by particle id, and that update's simulated
    /// time (for the yield view).
    previous_plastic: Vec<Real>,
    previous_time: f64,
}

impl Colours {
    /// Recomputes the scalars of `s` for `mode`.
    pub fn update<D: Dim>(&mut self, s: &Simulation<D>, mode: ColourMode) {
        let since = s.time() - self.previous_time;
        self.previous_time = s.time();
        fill(s, mode, &mut self.values, &mut self.previous_plastic, since);
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
    since: f64,
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
                    // flowing: growing at FLOWING_RATE or faster since the last update (any
                    // growth within an update that took no time)
                    let flowing = before.is_finite()
                        && ep > before
                        && (since <= 0.0 || (ep - before) as f64 > FLOWING_RATE * since);
                    out[i] = if flowing {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::playground::{Playground, Quality};
    use crate::sim::AnySimulation;

    /// Each particle's plastic strain, by particle id.
    fn by_id(pg: &Playground) -> Vec<f64> {
        fn of<D: Dim>(s: &Simulation<D>) -> Vec<f64> {
            let p = s.particles();
            let mut v = vec![0.0; p.id.len()];
            for (i, &id) in p.id.iter().enumerate() {
                v[id as usize] = p.plastic_strain[i] as f64;
            }
            v
        }
        match pg.simulation() {
            AnySimulation::D2(s) => of(s),
            AnySimulation::D3(s) => of(s),
        }
    }

    /// The yield view of the stress-path lesson's notched block at *Live*, updated every
    /// frame of 1/60 s as the page does: while the block collapses most of its particles show
    /// as flowing; once the heap rests (2.5–3.5 s), on no frame more than 1 % of them, where
    /// counting any growth of plastic strain as flowing marks several per cent, frame after
    /// frame (a band at the heap's base).
    #[test]
    fn a_resting_heap_shows_no_flowing_band() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/scenes/notched_sand_block_2d.json"
        ))
        .unwrap();
        let scene = crate::SceneConfig::from_json(&text).unwrap();
        let mut pg = Playground::with_quality(scene, Quality::find("live").unwrap()).unwrap();
        let n = pg.particle_count() as f64;
        let (mut collapsing, mut resting, mut grew) = (0.0f64, 0.0f64, 0.0f64);
        let mut before: Vec<f64> = vec![];
        while pg.time() < 3.5 {
            pg.frame(1.0 / 60.0, 1e12, || 0.0).unwrap();
            pg.update_colours(ColourMode::Yield);
            let flowing = pg.colours().iter().filter(|&&c| c == 1.0).count() as f64 / n;
            // any growth at all, by particle id
            let now = by_id(&pg);
            let growing = now.iter().zip(&before).filter(|(a, b)| a > b).count() as f64 / n;
            before = now;
            if (0.2..0.4).contains(&pg.time()) {
                collapsing = collapsing.max(flowing);
            }
            if pg.time() > 2.5 {
                resting = resting.max(flowing);
                grew = grew.max(growing);
            }
        }
        let figures = format!(
            "flowing: {:.1} % at most while collapsing, {:.2} % at most at rest; plastic strain \
             growing at rest: {:.1} % at most",
            100.0 * collapsing,
            100.0 * resting,
            100.0 * grew
        );
        eprintln!("{figures}");
        assert!(
            collapsing > 0.5 && resting <= 0.01 && grew > 0.03,
            "{figures}"
        );
    }
}
