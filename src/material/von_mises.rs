//! Von Mises plasticity by radial return (Eq. 7–10).
//!
//! The yield function is f = J2 − Y² (Eq. 7). The paper's Eq. 9, s = s_tr √(Y/J2), is not
//! consistent with Eq. 7 (it does not put the stress on f = 0); the radial return that does is
//! s = s_tr · Y/√J2. The user-facing `yield_stress` is the uniaxial yield stress σ_y, so
//! Y = σ_y/√3 (a bar in uniaxial tension yields at σ_xx = σ_y). Perfect plasticity: no hardening.

use super::{Constitutive, Elastic, ElasticParams, StressUpdate};
use crate::error::{Result, check_positive};
use crate::math::{Number, Real, SymTensor};

const SQRT_3: Real = 1.732_050_8;
use serde::{Deserialize, Serialize};

/// Parameters: E (Pa), ν, density (kg/m³) and the uniaxial yield stress σ_y (Pa).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VonMisesParams {
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    pub yield_stress: f64,
}

impl VonMisesParams {
    pub fn elastic(&self) -> ElasticParams {
        ElasticParams {
            youngs_modulus: self.youngs_modulus,
            poisson_ratio: self.poisson_ratio,
            density: self.density,
        }
    }
    pub fn validate(&self, path: &str) -> Result<()> {
        self.elastic().validate(path)?;
        check_positive(format!("{path}.yield_stress"), self.yield_stress, "Pa")
    }
    /// √J2 = Y = σ_y/√3, so q = √3 √J2 = σ_y at every pressure: a cylinder about the
    /// hydrostatic axis.
    pub fn pq_surface(&self) -> super::PqSurface {
        super::PqSurface {
            kind: "von_mises",
            label: "von Mises: q = σ_y",
            slope: 0.0,
            intercept: self.yield_stress,
            apex_p: f64::NEG_INFINITY,
            lower: None,
        }
    }
    pub fn model(&self) -> VonMises {
        VonMises {
            elastic: self.elastic().model(),
            y: (self.yield_stress / 3f64.sqrt()) as Real,
        }
    }
}

/// The von Mises model; `y` is Y = σ_y/√3, the yield value of √J2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VonMises {
    pub elastic: Elastic,
    pub y: Real,
}

impl Constitutive for VonMises {
    const PLASTIC: bool = true;
    #[inline(always)]
    fn update<S: SymTensor>(
        &self,
        stress: &mut S,
        rate: S,
        spin: S::Spin,
        _plastic_strain: S::Scalar,
        dt: Real,
    ) -> StressUpdate<S::Scalar> {
        let trial = self.elastic.trial(*stress, rate, spin, dt); // Eq. 6
        let mean = trial.trace() * (1.0 / 3.0);
        let s_tr = trial - S::iso(mean); // Eq. 8
        let j2 = s_tr.ddot(s_tr) * 0.5;
        let sqrt_j2 = j2.sqrt();
        let y = S::Scalar::splat(self.y);
        // Outside the surface (√J2 > Y) the deviator is scaled by Y/√J2 (Eq. 9 corrected,
        // Eq. 10), inside by 1: written as a correction of the trial stress, so that an elastic
        // step leaves it exactly, and as selects, so that all lanes take the same path.
        let yielding =
            |then: S::Scalar, other: S::Scalar| S::Scalar::select_gt(sqrt_j2, y, then, other);
        let ratio = yielding(y / sqrt_j2, S::Scalar::ONE);
        *stress = trial + s_tr.scaled(ratio - 1.0);
        let g = self.elastic.g;
        StressUpdate {
            plastic_strain: yielding((sqrt_j2 - y) * (1.0 / (SQRT_3 * g)), S::Scalar::ZERO),
            // the plastic work σ:Δε_p = s:(s_tr − s)/(2G) with s = (Y/√J2) s_tr
            dissipation: yielding(y * (sqrt_j2 - y) * (1.0 / g), S::Scalar::ZERO),
            energy: self
                .elastic
                .energy_from_invariants(yielding(y * y, j2), mean),
        }
    }
    fn elastic(&self) -> &Elastic {
        &self.elastic
    }
}

impl super::Kind for VonMisesParams {
    const NAME: &'static str = "von_mises";
    const LABEL: &'static str = "Plastic";
    const HINT: &'static str = "clay/metal: von Mises";
    const FIELDS: &'static [&'static str] =
        &["yield_stress", "youngs_modulus", "poisson_ratio", "density"];
    type Model = VonMises;
    fn preset() -> Self {
        VonMisesParams {
            youngs_modulus: 1.0e5,
            poisson_ratio: 0.3,
            density: 1000.0,
            yield_stress: 5.0e3,
        }
    }
    fn elastic_params(&self) -> ElasticParams {
        self.elastic()
    }
    fn check(&self, path: &str) -> Result<()> {
        self.validate(path)
    }
    fn runtime(&self) -> VonMises {
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
        match name {
            "yield_stress" => Some(&mut self.yield_stress),
            _ => super::elastic_field(
                name,
                [
                    &mut self.youngs_modulus,
                    &mut self.poisson_ratio,
                    &mut self.density,
                ],
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::test_util::{drive, rate_spin};
    use crate::math::Sym3;

    fn metal() -> VonMises {
        VonMisesParams {
            youngs_modulus: 2.0e7,
            poisson_ratio: 0.3,
            density: 1000.0,
            yield_stress: 1.0e5,
        }
        .model()
    }

    /// Uniaxial stress: the axial strain rate is prescribed, the lateral rate is solved each
    /// step (secant iterations) so that the lateral stresses stay zero.
    fn uniaxial_stress(
        m: &VonMises,
        axial_rate: Real,
        dt: Real,
        steps: usize,
    ) -> Vec<(Real, Real, Sym3, Real)> {
        let mut s = Sym3::ZERO;
        let mut ep = 0.0;
        let mut out = Vec::new();
        let mut lateral = -0.3 * axial_rate;
        for i in 0..steps {
            let try_rate = |lat: Real| {
                let (r, w) = rate_spin([[axial_rate, 0.0, 0.0], [0.0, lat, 0.0], [0.0, 0.0, lat]]);
                let mut t = s;
                let u = m.update(&mut t, r, w, 0.0, dt);
                (t, u)
            };
            let (mut a, mut b) = (lateral, lateral * 1.01 + 1e-6);
            let (mut fa, mut fb) = (try_rate(a).0.yy, try_rate(b).0.yy);
            for _ in 0..30 {
                if (fb - fa).abs() < 1e-12 {
                    break;
                }
                let c = b - fb * (b - a) / (fb - fa);
                (a, fa) = (b, fb);
                b = c;
                fb = try_rate(b).0.yy;
            }
            lateral = b;
            let (t, u) = try_rate(b);
            s = t;
            ep += u.plastic_strain;
            out.push((axial_rate * dt * (i + 1) as Real, s.xx, s, ep));
        }
        out
    }

    #[test]
    fn uniaxial_tension_is_elastic_with_slope_e_then_flat_at_the_yield_stress() {
        let m = metal();
        let e = 2.0e7;
        let sy = 1.0e5;
        let path = uniaxial_stress(&m, 1.0, 1e-5, 1000); // to 1 % strain; yield at 0.5 %
        for &(eps, sxx, s, ep) in &path {
            assert!(
                s.yy.abs() < 1e-2 * sy && s.zz.abs() < 1e-2 * sy,
                "lateral stress {s:?}"
            );
            if eps < 0.99 * sy / e {
                assert!(
                    (sxx - e * eps).abs() < 2e-3 * sy,
                    "elastic branch at {eps}: {sxx}"
                );
                assert_eq!(ep, 0.0);
            } else if eps > 1.02 * sy / e {
                assert!(
                    (sxx - sy).abs() < 2e-3 * sy,
                    "plastic branch at {eps}: {sxx}"
                );
                // on the yield surface: √(3 J2) = σ_y
                assert!(((3.0 * s.j2()).sqrt() - sy).abs() < 1e-3 * sy);
                // plastic strain ≈ total strain − σ_y/E
                assert!(
                    (ep - (eps - sy / e)).abs() < 0.05 * (eps - sy / e) + 2e-5,
                    "{ep} at {eps}"
                );
            }
        }
    }

    #[test]
    fn pure_shear_yields_at_y_and_stays_on_the_surface() {
        let m = metal();
        let a = 1.0;
        let mut first_plastic = None;
        let (s, ep, diss) = drive(
            &m,
            Sym3::ZERO,
            [[0.0, a, 0.0], [a, 0.0, 0.0], [0.0; 3]],
            1e-5,
            600,
            |i, s| {
                let j2 = s.j2();
                assert!(j2 <= m.y * m.y * 1.0001);
                if first_plastic.is_none() && j2 > 0.9999 * m.y * m.y {
                    first_plastic = Some(i);
                }
            },
        );
        // elastic until 2G γ̇/2·t = Y: t = Y/(2 G a)
        let t_yield = m.y / (2.0 * m.elastic.g * a);
        let i_yield = (t_yield / 1e-5) as usize;
        assert!((first_plastic.unwrap() as i64 - i_yield as i64).abs() <= 1);
        assert!((s.xy - m.y).abs() < 1e-3 * m.y);
        assert!(ep > 0.0);
        // dissipation ≈ Y × plastic shear strain γ_p, with ε̄p = γ_p/√3.
        let gamma_p = ep * 3.0f32.sqrt() as Real;
        assert!(
            (diss - m.y * gamma_p).abs() < 0.02 * m.y * gamma_p,
            "{diss} vs {}",
            m.y * gamma_p
        );
    }

    #[test]
    fn pressure_is_untouched_by_the_return() {
        let m = metal();
        let r = 2.0;
        let (s, _, _) = drive(
            &m,
            Sym3::ZERO,
            [[r, 0.0, 0.0], [0.0, r, 0.0], [0.0, 0.0, -r * 0.5]],
            1e-5,
            400,
            |_, _| {},
        );
        let k = m.elastic.k;
        let tr_eps = (r + r - 0.5 * r) * 1e-5 * 400.0;
        assert!((s.trace() / 3.0 - k * tr_eps).abs() < 1e-3 * k * tr_eps);
        assert!((s.j2().sqrt() - m.y).abs() < 1e-3 * m.y);
    }

    #[test]
    fn validation() {
        let p = VonMisesParams {
            youngs_modulus: 1e6,
            poisson_ratio: 0.3,
            density: 1.0,
            yield_stress: 0.0,
        };
        assert_eq!(
            p.validate("b.von_mises").unwrap_err().to_string(),
            "b.von_mises.yield_stress = 0: must be a finite number > 0 (Pa)"
        );
    }
}
