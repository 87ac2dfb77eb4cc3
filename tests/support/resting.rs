//! The resting pressure field of sand, against the lithostatic mean p₀(z) = ρ g z (1 + 2K0)/3
//! (vertical stress ρ g z, horizontal and out-of-plane K0 ρ g z). K0 = 1 − sin φ (Jaky 1944,
//! normally consolidated sand); for the shipped sand (φ = 35°, ν = 0.3) it is 0.426, next to
//! the elastic value ν/(1 − ν) = 0.429 of a layer loaded under gravity with no lateral strain,
//! which is how the simulated layer, released stress-free between walls, is loaded.
//!
//! [`pressure_bands`] sorts particles into depth bands one cell thick below the free surface
//! (the surface over a particle is the top of the particles within a quarter cell of its x,
//! plus half a particle spacing); in each band it takes each particle's ratio r = p / p₀(z) at
//! its own depth (so that the pressure's rise across the band does not count as scatter), the
//! band's mean of r, and the share of particles within ±25 % of that mean.

/// The resting pressure of a set of particles, band by band.
#[derive(Clone, Debug)]
pub struct Bands {
    pub bands: Vec<Band>,
    /// Over every band: the share of particles within ±25 % of their band's mean.
    pub within: f64,
    /// The band mean of p/p₀ farthest from 1.
    pub worst_mean: f64,
    /// Particles counted.
    pub count: usize,
}

#[derive(Clone, Debug)]
pub struct Band {
    /// Depth range (m).
    pub from: f64,
    pub to: f64,
    pub count: usize,
    /// Mean of p/p₀(z).
    pub mean: f64,
    /// Share within ±25 % of the mean.
    pub within: f64,
    /// Least and greatest pressure (Pa).
    pub min: f64,
    pub max: f64,
    /// Share with p < p₀(z)/10.
    pub tenth: f64,
}

/// Lithostatic mean pressure at depth z (Pa).
pub fn lithostatic(rho: f64, g: f64, k0: f64, z: f64) -> f64 {
    rho * g * z * (1.0 + 2.0 * k0) / 3.0
}

/// Jaky's K0 = 1 − sin φ.
pub fn jaky(phi_degrees: f64) -> f64 {
    1.0 - phi_degrees.to_radians().sin()
}

/// The bands of particles at (x, y) with pressures `p` (Pa) among `all` (every particle of the
/// body, for the free surface), counting those with x in `window` and depth in
/// [`min_depth`, ∞), in bands `h` thick; `spacing` is the particle spacing (m).
#[allow(clippy::too_many_arguments)]
pub fn pressure_bands(
    all: &[(f64, f64)],
    p: &[f64],
    window: (f64, f64),
    h: f64,
    spacing: f64,
    min_depth: f64,
    rho: f64,
    g: f64,
    k0: f64,
) -> Bands {
    let depth = |x: f64, y: f64| {
        let top = all
            .iter()
            .filter(|q| (q.0 - x).abs() <= 0.25 * h)
            .map(|q| q.1)
            .fold(f64::MIN, f64::max);
        top + 0.5 * spacing - y
    };
    let mut rows: Vec<(f64, f64, f64)> = all
        .iter()
        .zip(p)
        .filter(|(q, _)| q.0 >= window.0 && q.0 <= window.1)
        .map(|(q, &pq)| (depth(q.0, q.1), pq, 0.0))
        .filter(|r| r.0 >= min_depth)
        .map(|(z, pq, _)| (z, pq, pq / lithostatic(rho, g, k0, z)))
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut bands = Vec::new();
    let mut from = min_depth;
    let deepest = rows.last().map_or(min_depth, |r| r.0);
    while from < deepest {
        let to = from + h;
        let band: Vec<_> = rows.iter().filter(|r| r.0 >= from && r.0 < to).collect();
        if band.len() >= 4 {
            let n = band.len() as f64;
            let mean = band.iter().map(|r| r.2).sum::<f64>() / n;
            bands.push(Band {
                from,
                to,
                count: band.len(),
                mean,
                within: band
                    .iter()
                    .filter(|r| (r.2 / mean - 1.0).abs() <= 0.25)
                    .count() as f64
                    / n,
                min: band.iter().map(|r| r.1).fold(f64::MAX, f64::min),
                max: band.iter().map(|r| r.1).fold(f64::MIN, f64::max),
                tenth: band.iter().filter(|r| r.2 < 0.1).count() as f64 / n,
            });
        }
        from = to;
    }
    let count: usize = bands.iter().map(|b| b.count).sum();
    Bands {
        within: bands.iter().map(|b| b.within * b.count as f64).sum::<f64>() / count.max(1) as f64,
        worst_mean: bands
            .iter()
            .map(|b| b.mean)
            .max_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()))
            .unwrap_or(f64::NAN),
        count,
        bands,
    }
}

impl std::fmt::Display for Bands {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "  {} particles: {:.1} % within ±25 % of their band's mean; worst band mean p/p0 {:.3}",
            self.count,
            100.0 * self.within,
            self.worst_mean
        )?;
        for b in &self.bands {
            writeln!(
                f,
                "  depth {:.3}-{:.3} m: n {:4}  mean p/p0 {:.3}  within {:5.1} %  p {:8.1} … {:8.1} Pa  under p0/10 {:5.1} %",
                b.from,
                b.to,
                b.count,
                b.mean,
                100.0 * b.within,
                b.min,
                b.max,
                100.0 * b.tenth
            )?;
        }
        Ok(())
    }
}

/// Gives a 2D sand layer whose top is at `top` (m) the stress of a layer at rest under
/// gravity between walls: σ_yy = −ρ g (top − y), σ_xx = σ_zz = K σ_yy, no shear.
#[allow(dead_code)]
pub fn geostatic(sim: &mut mpm::Simulation<mpm::D2>, top: f64, rho: f64, g: f64, k: f64) {
    let p = sim.particles_mut();
    for i in 0..p.len() {
        let vertical = -rho * g * (top - p.x[i][1] as f64);
        p.stress[i] = mpm::math::Sym2 {
            xx: (k * vertical) as mpm::Real,
            yy: vertical as mpm::Real,
            zz: (k * vertical) as mpm::Real,
            xy: 0.0,
        };
    }
}
