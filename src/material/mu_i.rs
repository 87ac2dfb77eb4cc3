//! Rate-dependent friction for the Drucker–Prager cone: the μ(I) law of Jop, Forterre &
//! Pouliquen (2006, *A constitutive law for dense granular flows*, Nature 441, 727–730),
//!
//! μ(I) = μ_s + (μ_2 − μ_s) / (I_0/I + 1),   I = γ̇ d / √(p/ρ_s),
//!
//! with γ̇ = √(2 ε̇′ : ε̇′) the shear rate (their |γ̇| = √(½ γ̇_ij γ̇_ij), γ̇_ij = 2 ε̇_ij: γ̇ in
//! simple shear), p the pressure, d the grain diameter and ρ_s the grain density (the
//! material's density). μ_s = tan φ comes from the user's friction angle; the rise
//! μ_2 − μ_s = tan 32.76° − tan 20.9° = 0.262 and I_0 = 0.279 are Jop et al.'s published
//! constants for glass beads (d = 0.53 mm). The cone takes the friction through the body's
//! friction match ([`FrictionMatch`]): Eq. 13, α_φ(I) = μ(I)/√(9 + 12 μ(I)²), by default, or
//! α_φ(I) = μ(I)/3 with the steady-flow match, so a material at rest (I = 0) has exactly its
//! rate-independent cone and a flowing one a wider cone: the friction of the flow rises with
//! its inertial number. In a scene: `"drucker_prager": {..., "mu_i": {"grain_diameter": 5e-4}}`.

use super::FrictionMatch;
use crate::error::{Error, Result};
use crate::math::{Number, Real, SymTensor};
use serde::{Deserialize, Serialize};

/// Jop et al. (2006): μ_s = tan 20.9°, μ_2 = tan 32.76°, I_0 = 0.279 (glass beads).
pub const JOP_STATIC_ANGLE: f64 = 20.9;
pub const JOP_LIMIT_ANGLE: f64 = 32.76;
pub const JOP_I0: f64 = 0.279;

/// The published rise of the friction coefficient, μ_2 − μ_s.
pub fn jop_friction_rise() -> f64 {
    JOP_LIMIT_ANGLE.to_radians().tan() - JOP_STATIC_ANGLE.to_radians().tan()
}

/// Scene-file parameters: the grain diameter d (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MuIParams {
    pub grain_diameter: f64,
}

impl MuIParams {
    pub fn validate(&self, path: &str) -> Result<()> {
        let d = self.grain_diameter;
        if d.is_finite() && d > 0.0 && d <= 0.1 {
            Ok(())
        } else {
            Err(Error::invalid(
                format!("{path}.grain_diameter"),
                d,
                "must be in (0, 0.1] (m)".to_string(),
            ))
        }
    }
    /// The law for a material of friction angle φ (degrees) and density ρ_s (kg/m³) whose cone
    /// follows the friction by `friction_match`.
    pub fn model(&self, friction_angle: f64, density: f64, friction_match: FrictionMatch) -> MuI {
        MuI {
            friction_match,
            mu_s: friction_angle.to_radians().tan() as Real,
            rise: jop_friction_rise() as Real,
            i0: JOP_I0 as Real,
            d_sqrt_rho: (self.grain_diameter * density.sqrt()) as Real,
        }
    }
}

/// The μ(I) law with its constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MuI {
    /// How the cone's α_φ follows from μ(I).
    pub friction_match: FrictionMatch,
    /// μ_s = tan φ.
    pub mu_s: Real,
    /// μ_2 − μ_s.
    pub rise: Real,
    pub i0: Real,
    /// d √ρ_s, so that I = γ̇ d √ρ_s / √p.
    pub d_sqrt_rho: Real,
}

impl MuI {
    /// I = γ̇ d / √(p/ρ_s) (infinite at p = 0 with shear).
    pub fn inertial_number(&self, shear_rate: Real, pressure: Real) -> Real {
        shear_rate * self.d_sqrt_rho / pressure.max(0.0).sqrt()
    }
    /// μ(I) = μ_s + (μ_2 − μ_s) I/(I + I_0).
    pub fn friction(&self, i: Real) -> Real {
        if i.is_infinite() {
            return self.mu_s + self.rise;
        }
        self.mu_s + self.rise * i / (i + self.i0)
    }
    /// The cone's α_φ of μ(I) (μ/√(9 + 12 μ²) by Eq. 13, μ/3 by the steady-flow match) for
    /// the strain rate `rate` and the first invariant `i1` of the stress (tension positive),
    /// lane by lane. I/(I + I_0) is formed as x/(x + y) with x = γ̇ d √ρ_s and y = I_0 √p, finite for every pressure: μ_2 where
    /// the pressure is zero and the material shears, μ_s where it does not shear.
    #[inline(always)]
    pub fn alpha_phi<S: SymTensor>(&self, rate: S, i1: S::Scalar) -> S::Scalar {
        let dev = rate - S::iso(rate.trace() * (1.0 / 3.0));
        let x = (dev.ddot(dev) * 2.0).sqrt() * self.d_sqrt_rho;
        let y = (i1 * (-1.0 / 3.0)).max(S::Scalar::ZERO).sqrt() * self.i0;
        let share = x / (x + y).max(S::Scalar::splat(Real::MIN_POSITIVE));
        let mu = share * self.rise + self.mu_s;
        // the branch is on the model, the same in every lane
        self.friction_match.alpha(mu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Sym3;

    fn law(phi: f64, d: f64) -> MuI {
        MuIParams { grain_diameter: d }.model(phi, 2500.0, FrictionMatch::PlaneStrain)
    }

    fn eq13(mu: f64) -> f64 {
        mu / (9.0 + 12.0 * mu * mu).sqrt()
    }

    /// Simple shear v_x = γ̇ y: ε̇_xy = γ̇/2.
    fn shear(gamma: Real) -> Sym3 {
        Sym3 {
            xy: 0.5 * gamma,
            ..Sym3::ZERO
        }
    }

    #[test]
    fn published_constants() {
        assert!((jop_friction_rise() - 0.2615).abs() < 1e-3);
        let m = law(20.9, 0.53e-3);
        assert!((m.mu_s as f64 - 0.382).abs() < 1e-3);
        assert!((m.friction(0.0) - m.mu_s).abs() < 1e-7);
        // μ(I_0) is halfway between μ_s and μ_2; μ(∞) = μ_2
        let half = m.friction(m.i0) as f64;
        assert!((half - 0.5 * (0.3819 + 0.6434)).abs() < 1e-3, "{half}");
        let top = m.friction(Real::INFINITY) as f64;
        assert!((top - 32.76f64.to_radians().tan()).abs() < 1e-4, "{top}");
    }

    #[test]
    fn inertial_number_of_a_simple_shear() {
        // γ̇ = 10 /s, d = 1 mm, ρ_s = 2500, p = 250 Pa: I = 0.01 · √(2500/250) = 0.0316
        let m = law(30.0, 1e-3);
        let i = m.inertial_number(10.0, 250.0) as f64;
        assert!((i - 0.01 * 10f64.sqrt()).abs() < 1e-5, "{i}");
        // the cone's α_φ from the tensor form equals Eq. 13 of μ(I)
        let p = 250.0;
        let a = m.alpha_phi(shear(10.0), -3.0 * p) as f64;
        let mu = m.friction(i as Real) as f64;
        assert!((a - eq13(mu)).abs() < 1e-6, "{a} vs {}", eq13(mu));
        // a volumetric rate is no shear: γ̇ = 0
        let iso = Sym3::iso(0.7);
        assert!((m.alpha_phi(iso, -3.0 * p) as f64 - eq13(m.mu_s as f64)).abs() < 1e-7);
    }

    #[test]
    fn rest_is_the_rate_independent_cone_and_zero_pressure_the_limit() {
        let m = law(32.0, 5e-4);
        let static_alpha = eq13(32f64.to_radians().tan());
        // no shear, at any pressure (zero included): the paper's cone
        for p in [0.0, 1.0, 1e4] {
            let a = m.alpha_phi(Sym3::ZERO, -3.0 * p) as f64;
            assert!((a - static_alpha).abs() < 1e-7, "p = {p}: {a}");
        }
        // shear without pressure: μ_2 = μ_s + rise; tension counts as zero pressure
        let limit = eq13(32f64.to_radians().tan() + jop_friction_rise());
        for i1 in [0.0, 50.0] {
            let a = m.alpha_phi(shear(1.0), i1) as f64;
            assert!((a - limit).abs() < 1e-6, "{a} vs {limit}");
        }
        // monotone in the shear rate, between the two
        let mut last = static_alpha;
        for g in [1e-2, 1e-1, 1.0, 10.0, 100.0] {
            let a = m.alpha_phi(shear(g), -3.0 * 100.0) as f64;
            assert!(a > last && a < limit, "γ̇ = {g}: {a}");
            last = a;
        }
    }

    #[test]
    fn validation() {
        let bad = MuIParams {
            grain_diameter: 0.0,
        };
        assert_eq!(
            bad.validate("m.mu_i").unwrap_err().to_string(),
            "m.mu_i.grain_diameter = 0: must be in (0, 0.1] (m)"
        );
        assert!(
            MuIParams {
                grain_diameter: 5e-4
            }
            .validate("m")
            .is_ok()
        );
    }
}
