//! Hypoelastic stress with the Jaumann rate (Eq. 2–6):
//! Dσ/Dt = 2G(ε̇ − ⅓tr(ε̇)I) + K tr(ε̇) I + ωσ − σω.
//!
//! The rotation terms are integrated objectively (Hughes–Winget): the stress is first rotated
//! by the Cayley transform of ½ dt ω, then the elastic increment is added. To first order this
//! is Eq. 6; unlike a forward-Euler step of ωσ − σω it never inflates the stress of a body that
//! only rotates.

use super::{Constitutive, StressUpdate};
use crate::error::{Result, check_positive, check_range};
use crate::math::{Number, Real, SymTensor};
use serde::{Deserialize, Serialize};

/// Elastic parameters: Young's modulus E (Pa), Poisson ratio ν ∈ [0, 0.5), density (kg/m³).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ElasticParams {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
}

impl ElasticParams {
    /// Shear modulus G = E / (2(1 + ν)).
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
    }
    /// Bulk modulus K = E / (3(1 − 2ν)).
    pub fn bulk_modulus(&self) -> f64 {
        self.youngs_modulus / (3.0 * (1.0 - 2.0 * self.poisson_ratio))
    }
    /// √((K + 4G/3)/ρ) in m/s.
    pub fn wave_speed(&self) -> f64 {
        self.model().wave_speed(self.density)
    }
    pub fn validate(&self, path: &str) -> Result<()> {
        check_positive(format!("{path}.youngs_modulus"), self.youngs_modulus, "Pa")?;
        check_range(
            format!("{path}.poisson_ratio"),
            self.poisson_ratio,
            0.0,
            0.5,
            true,
            "",
        )?;
        check_positive(format!("{path}.density"), self.density, "kg/m³")
    }
    /// An elastic model never yields.
    pub fn pq_surface(&self) -> super::PqSurface {
        super::PqSurface::NONE
    }
    pub fn model(&self) -> Elastic {
        Elastic::new(self.shear_modulus() as Real, self.bulk_modulus() as Real)
    }
}

/// The hypoelastic model with shear modulus `g` and bulk modulus `k` (Pa).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    pub g: Real,
    pub k: Real,
    inv_4g: Real,
    inv_2k: Real,
}

impl Elastic {
    pub fn new(g: Real, k: Real) -> Self {
        Elastic {
            g,
            k,
            inv_4g: 0.25 / g,
            inv_2k: 0.5 / k,
        }
    }

    /// The dilatational wave speed √((K + 4G/3)/ρ) at density ρ (kg/m³), in m/s: what bounds
    /// the stable time step.
    pub fn wave_speed(&self, density: f64) -> f64 {
        ((self.k + 4.0 * self.g / 3.0) as f64 / density).sqrt()
    }

    /// The stored elastic energy per unit volume of a stress: s:s/(4G) + P²/(2K).
    #[inline(always)]
    pub fn energy_density<S: SymTensor>(&self, stress: S) -> S::Scalar {
        let mean = stress.trace() * (1.0 / 3.0);
        let s = stress - S::iso(mean);
        self.energy_from_invariants(s.ddot(s) * 0.5, mean)
    }

    /// The same energy density from the invariants J2 = ½ s:s and the mean stress tr(σ)/3:
    /// J2/(2G) + mean²/(2K).
    #[inline(always)]
    pub fn energy_from_invariants<T: Number>(&self, j2: T, mean: T) -> T {
        j2 * (2.0 * self.inv_4g) + mean * mean * self.inv_2k
    }

    /// The elastic trial stress: the old stress rotated with the material, plus the
    /// elastic increment 2G dt dev(ε̇) + K dt tr(ε̇) I.
    #[inline(always)]
    pub fn trial<S: SymTensor>(&self, stress: S, rate: S, spin: S::Spin, dt: Real) -> S {
        let tr = rate.trace();
        let dev = rate - S::iso(tr * (1.0 / 3.0));
        stress.rotate(spin, dt) + dev * (2.0 * self.g * dt) + S::iso(tr * (self.k * dt))
    }
}

impl Constitutive for Elastic {
    const PLASTIC: bool = false;
    #[inline(always)]
    fn update<S: SymTensor>(
        &self,
        stress: &mut S,
        rate: S,
        spin: S::Spin,
        _plastic_strain: S::Scalar,
        dt: Real,
    ) -> StressUpdate<S::Scalar> {
        *stress = self.trial(*stress, rate, spin, dt);
        StressUpdate::elastic(self.energy_density(*stress))
    }
    fn elastic(&self) -> &Elastic {
        self
    }
}

impl super::Kind for ElasticParams {
    const NAME: &'static str = "elastic";
    const LABEL: &'static str = "Elastic";
    const HINT: &'static str = "jelly: bounces back";
    const FIELDS: &'static [&'static str] = &["youngs_modulus", "poisson_ratio", "density"];
    type Model = Elastic;
    fn preset() -> Self {
        ElasticParams {
            youngs_modulus: 1.0e5,
            poisson_ratio: 0.3,
            density: 1000.0,
        }
    }
    fn elastic_params(&self) -> ElasticParams {
        *self
    }
    fn check(&self, path: &str) -> Result<()> {
        self.validate(path)
    }
    fn runtime(&self) -> Elastic {
        self.model()
    }
    fn surface(&self) -> impl Fn(f64) -> super::PqSurface + 'static {
        let s = self.pq_surface();
        move |_| s
    }
    fn behaviour(&self) -> super::Behaviour {
        super::Behaviour::Solid
    }
    fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
        super::elastic_field(
            name,
            [
                &mut self.youngs_modulus,
                &mut self.poisson_ratio,
                &mut self.density,
            ],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_util::drive;
    use crate::math::Sym3;

    fn steel_like() -> Elastic {
        ElasticParams {
            youngs_modulus: 1.0e6,
            poisson_ratio: 0.3,
            density: 1000.0,
        }
        .model()
    }

    #[test]
    fn uniaxial_strain_gives_the_constrained_modulus() {
        let m = steel_like();
        let (rate, dt, n) = (0.5, 1e-3, 200);
        let (s, ep, _) = drive(
            &m,
            Sym3::ZERO,
            [[rate, 0.0, 0.0], [0.0; 3], [0.0; 3]],
            dt,
            n,
            |_, _| {},
        );
        let eps = rate * dt * n as Real;
        let (g, k) = (m.g, m.k);
        assert!(
            ((s.xx - (k + 4.0 * g / 3.0) * eps) / s.xx).abs() < 1e-4,
            "{s:?}"
        );
        assert!(((s.yy - (k - 2.0 * g / 3.0) * eps) / s.yy).abs() < 1e-4);
        assert!((s.yy - s.zz).abs() < 1e-3 * s.yy.abs());
        assert_eq!(ep, 0.0);
    }

    #[test]
    fn pure_shear_gives_twice_g() {
        let m = steel_like();
        let a = 0.2; // L_xy = L_yx = a: strain rate ε̇_xy = a, no spin
        let (s, _, _) = drive(
            &m,
            Sym3::ZERO,
            [[0.0, a, 0.0], [a, 0.0, 0.0], [0.0; 3]],
            1e-3,
            100,
            |_, _| {},
        );
        let expect = 2.0 * m.g * a * 0.1;
        assert!(
            ((s.xy - expect) / expect).abs() < 1e-4,
            "{} vs {expect}",
            s.xy
        );
        assert!(s.xx.abs() < 1e-3 * expect && s.yy.abs() < 1e-3 * expect);
    }

    #[test]
    fn pure_rotation_rotates_the_stress_without_growth() {
        let m = steel_like();
        let s0 = Sym3 {
            xx: 3.0e4,
            yy: -1.0e4,
            zz: 5.0e3,
            xy: 2.0e3,
            xz: 0.0,
            yz: 0.0,
        };
        let w: Real = 2.0; // rad/s about z: v = (−w y, w x, 0)
        let dt: Real = 1e-3;
        let steps = 20_000; // 40 rad, more than six turns
        let (s, _, _) = drive(
            &m,
            s0,
            [[0.0, -w, 0.0], [w, 0.0, 0.0], [0.0; 3]],
            dt,
            steps,
            |_, s| {
                // invariants are preserved at every step
                // (a forward-Euler step of ωσ − σω would grow J2 by 8 % over this run)
                assert!(
                    (s.trace() - s0.trace()).abs() < 1e-4 * 3.0e4,
                    "trace drifted to {}",
                    s.trace()
                );
                assert!(
                    (s.j2() - s0.j2()).abs() / s0.j2() < 1e-4,
                    "J2 ratio {}",
                    s.j2() / s0.j2()
                );
            },
        );
        // The exact rotation by the angle ω t.
        let th = (w * dt * steps as Real) as f64;
        let (c, sn) = (th.cos(), th.sin());
        let (xx, yy, xy) = (s0.xx as f64, s0.yy as f64, s0.xy as f64);
        let exx = c * c * xx - 2.0 * c * sn * xy + sn * sn * yy;
        let exy = c * sn * (xx - yy) + (c * c - sn * sn) * xy;
        let scale = 3.0e4;
        // The Cayley angle differs from ωΔt by O((ωΔt)³) per step.
        assert!(
            (s.xx as f64 - exx).abs() < 2e-3 * scale,
            "{} vs {exx}",
            s.xx
        );
        assert!(
            (s.xy as f64 - exy).abs() < 2e-3 * scale,
            "{} vs {exy}",
            s.xy
        );
        assert!((s.zz - s0.zz).abs() < 1.0);
    }

    #[test]
    fn simple_shear_follows_the_jaumann_closed_form() {
        // v_x = γ̇ y: the hypoelastic Jaumann response is σ_xy = G sin γ,
        // σ_xx = −σ_yy = G (1 − cos γ) (Dienes 1979).
        let m = steel_like();
        let gd: Real = 1.0;
        let dt: Real = 1e-4;
        let steps = 30_000; // γ = 3 rad
        let (s, _, _) = drive(
            &m,
            Sym3::ZERO,
            [[0.0, gd, 0.0], [0.0; 3], [0.0; 3]],
            dt,
            steps,
            |_, _| {},
        );
        let gam = (gd * dt * steps as Real) as f64;
        let g = m.g as f64;
        assert!(
            (s.xy as f64 - g * gam.sin()).abs() < 2e-3 * g,
            "{} vs {}",
            s.xy,
            g * gam.sin()
        );
        assert!((s.xx as f64 - g * (1.0 - gam.cos())).abs() < 2e-3 * g);
        assert!((s.yy as f64 + g * (1.0 - gam.cos())).abs() < 2e-3 * g);
    }

    #[test]
    fn validation_names_the_field() {
        let p = ElasticParams {
            youngs_modulus: 1e6,
            poisson_ratio: 0.5,
            density: 1000.0,
        };
        let e = p
            .validate("bodies[0].material.elastic")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "bodies[0].material.elastic.poisson_ratio = 0.5: must be in [0, 0.5)"
        );
        let p = ElasticParams {
            youngs_modulus: -1.0,
            poisson_ratio: 0.2,
            density: 1000.0,
        };
        assert!(
            p.validate("m")
                .unwrap_err()
                .to_string()
                .starts_with("m.youngs_modulus = -1")
        );
    }
}
