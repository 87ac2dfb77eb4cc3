//! Thin-layer friction for the Drucker–Prager cone, after Pouliquen's h_stop (Pouliquen 1999,
//! *Scaling laws in granular flows down rough inclined planes*, Phys. Fluids 11, 542;
//! Pouliquen & Forterre 2002, J. Fluid Mech. 453, 133): a layer of thickness h on a rough
//! bed comes to rest on slopes below θ_stop(h),
//!
//! tan θ_stop(h) = tan θ_1 + (tan θ_2 − tan θ_1) / (1 + h/(A d)),
//!
//! so the thinner the layer, the more friction it mobilises, up to tan θ_2 for a layer of no
//! thickness, down to tan θ_1 for a deep one. The constants are the published ones for glass
//! beads that [`super::mu_i`] uses (Jop, Forterre & Pouliquen 2005, J. Fluid Mech. 541, 167;
//! 2006): tan θ_2 − tan θ_1 = tan 32.76° − tan 20.9° = 0.262 and A = L/d = 1.65; d is the
//! material's grain diameter. The material's own friction angle φ plays θ_1's part: a particle
//! in a column of material h thick has the cone of φ(h), tan φ(h) = tan φ + 0.262/(1 + h/(A d)),
//! in whatever friction match the body takes (so a deep deposit has exactly its
//! rate-independent cone). h is the material in the particle's grid column (the body's mass
//! there over ρ and the column's cross-section, gravity along −y), formed by the stress pass
//! each step ([`column_thickness`]). In a scene:
//! `"drucker_prager": {..., "thin_layer": {"grain_diameter": 0.002}}`.

use super::drucker_prager::{DruckerPrager, DruckerPragerParams};
use super::mu_i::jop_friction_rise;
use crate::error::{Error, Result};
use crate::math::{Dim, Real};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// A = L/d of the h_stop law for glass beads (Jop, Forterre & Pouliquen 2005).
pub const POULIQUEN_A: f64 = 1.65;

/// Scene-file parameters: the grain diameter d (m).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ThinLayerParams {
    pub grain_diameter: f64,
}

impl ThinLayerParams {
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
}

/// The law with the material it widens (whose own `thin_layer` is off).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinLayer {
    /// The material at depth: its cone is the one of `base.friction_angle`.
    pub base: DruckerPragerParams,
    /// tan θ_2 − tan θ_1.
    pub rise: f64,
    /// A d (m).
    pub length: f64,
}

impl ThinLayer {
    pub fn new(params: &DruckerPragerParams, thin: ThinLayerParams) -> Self {
        ThinLayer {
            base: DruckerPragerParams {
                thin_layer: None,
                ..*params
            },
            rise: jop_friction_rise(),
            length: POULIQUEN_A * thin.grain_diameter,
        }
    }
    /// tan φ(h) = tan φ + (tan θ_2 − tan θ_1)/(1 + h/(A d)) for a layer `thickness` thick (m).
    pub fn friction(&self, thickness: f64) -> f64 {
        self.base.friction_angle.to_radians().tan() + self.rise / (1.0 + thickness / self.length)
    }
    /// The cone of a particle in a layer `thickness` thick.
    pub fn model(&self, thickness: f64) -> DruckerPrager {
        DruckerPragerParams {
            friction_angle: self.friction(thickness).atan().to_degrees(),
            ..self.base
        }
        .model()
    }
}

/// The thickness of material in each particle's grid column (cells of side `h`; columns along
/// y): the mass of the particles in the column over `density` and the column's cross-section
/// h^(dim − 1).
pub fn column_thickness<D: Dim>(x: &[D::Vector], mass: &[Real], density: f64, h: f64) -> Vec<Real> {
    let column = |p: &D::Vector| {
        let k = |a: usize| (p[a] as f64 / h).floor() as i64;
        (k(0), if D::DIM == 3 { k(2) } else { 0 })
    };
    let mut sums: HashMap<(i64, i64), f64> = HashMap::new();
    for (p, &m) in x.iter().zip(mass) {
        *sums.entry(column(p)).or_default() += m as f64;
    }
    let area = h.powi(D::DIM as i32 - 1);
    x.iter()
        .map(|p| (sums[&column(p)] / (density * area)) as Real)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::FrictionMatch;
    use crate::math::{D2, Vec2};

    fn sand(phi: f64) -> DruckerPragerParams {
        let crate::material::Material::DruckerPrager(p) =
            crate::material::Material::drucker_prager(3.5e5, 0.3, 2200.0, phi, 0.0, 0.0)
        else {
            unreachable!()
        };
        p
    }

    /// The law's limits: tan θ_2 − tan θ_1 more friction for a layer of no thickness, half of it
    /// at h = A d, and the material's own cone for a deep deposit.
    #[test]
    fn a_thin_layer_has_more_friction_and_a_deep_one_the_materials() {
        let p = sand(30.0);
        let law = ThinLayer::new(
            &p,
            ThinLayerParams {
                grain_diameter: 2e-3,
            },
        );
        let t = 30f64.to_radians().tan();
        assert!((law.friction(0.0) - t - 0.2615).abs() < 1e-3);
        assert!((law.friction(law.length) - t - 0.5 * law.rise).abs() < 1e-12);
        assert!((law.friction(1e3) - t).abs() < 1e-5);
        // deep: the material's own cone (start–stop, as the body)
        let deep = law.model(1e6);
        assert!((deep.alpha_phi - p.model().alpha_phi).abs() < 1e-6);
        assert_eq!(p.friction_match, FrictionMatch::StartStop);
        // one grain thick: a wider cone
        assert!(law.model(2e-3).alpha_phi > 1.05 * p.model().alpha_phi);
    }

    /// A layer of particles of known mass: each particle's column holds the layer's thickness.
    #[test]
    fn column_thickness_of_a_uniform_layer() {
        let (h, rho) = (0.01, 2000.0);
        // four particles per cell, a layer 3 cells wide and 2.5 cells thick
        let s = 0.5 * h;
        let mut x = Vec::new();
        for i in 0..6 {
            for j in 0..5 {
                x.push(Vec2::new(
                    (i as f64 + 0.5) as Real * s as Real,
                    (j as f64 + 0.5) as Real * s as Real,
                ));
            }
        }
        let mass = vec![(rho * s * s) as Real; x.len()];
        let th = column_thickness::<D2>(&x, &mass, rho, h);
        for t in th {
            assert!((t as f64 - 2.5 * h).abs() < 1e-6, "{t}");
        }
    }

    #[test]
    fn validation() {
        let bad = ThinLayerParams {
            grain_diameter: -1.0,
        };
        assert_eq!(
            bad.validate("m.thin_layer").unwrap_err().to_string(),
            "m.thin_layer.grain_diameter = -1: must be in (0, 0.1] (m)"
        );
    }
}
