//! A body's numerical recipe: how the step treats it besides its constitutive law. Six
//! choices, made here and nowhere else ([`Recipe::new`], from the material, the body's own
//! settings and the scene's kernel and cell size), and read by every pass:
//!
//! | choice | granular (sand) | solid (elastic, von Mises) |
//! | --- | --- | --- |
//! | transfer ([`Recipe::apic`]) | APIC with the C¹ kernels, PIC with the linear one | PIC |
//! | default FLIP share α ([`Recipe::flip`]) | 0.05 | 0 |
//! | where the stress update sits ([`StressOrder`]) | first (Sec. 4.2's order) | last with the C¹ kernels, first with the linear one |
//! | volumetric rate ([`VolumetricRate`]) | the material's option | the particle's own |
//! | artificial bulk viscosity ([`Recipe::bulk_length`]) | none | C h |
//! | parted grains close again ([`Recipe::closing`]) | a poured body | never |
//!
//! A body's `flip`, `apic` and `stress_last` settings override the first three and
//! `close_grains` the last; a kinematic body carries no
//! stress and so no bulk viscosity. Which column a material takes is its own statement
//! ([`Material::behaviour`]).
//!
//! **Why.** The paper's PIC/FLIP blend with α = 0.05 for sand and 0 for solids (Sec. 4.2).
//! Sand takes APIC with the C¹ kernels: the PIC part of the paper's blend damps a granular
//! flow so much that plane columns ran out 40–56 % short of Lube et al. (2005), and APIC
//! removes that damping while keeping the α slider's meaning (docs/validation.md). Solids keep
//! PIC: APIC does not damp the ringing of an elastic body released stress-free, which PIC
//! does. The linear kernel keeps PIC for every body: its APIC inertia D_p vanishes when a
//! particle sits on a node, and the multilinear form that avoids it was unstable for stiff
//! bodies. The stress order is explained in [`StressOrder`]; the bulk viscosity in
//! [`BULK_VISCOSITY`]: sand has none (its flows are dissipative already, and a viscosity is
//! what docs/validation.md finds too much of). Parted grains close again in a poured body,
//! whose stream parts tenfold and would otherwise heap at half its density
//! (`src/step/stress.rs`); the validated collapses and slopes keep the paper's volume, which
//! their reports were measured with (docs/decisions.md).

use crate::config::BodyConfig;
use crate::kernel::KernelKind;
use crate::material::{Behaviour, Material, VolumetricRate};
use crate::math::Real;

/// Where the stress update sits in the step ([`crate::step`] explains both orders).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StressOrder {
    /// Sec. 4.2's order: from the grid velocities of step 1, before the forces.
    First,
    /// At the end of the step, from the new grid velocities, in the gather's walk.
    Last,
}

/// The bulk viscosity's coefficient C: q acts over a length C h. At 0.5 the supersonic blows
/// of the stability tests gain no energy, as at 1, and the elastic bunnies' rebound moves by
/// under 1 % (2.9 % at 1; docs/stability.md).
pub const BULK_VISCOSITY: Real = 0.5;

/// How the step treats one body (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recipe {
    /// The FLIP share α ∈ [0, 1] of the new particle velocity.
    pub flip: Real,
    /// Whether particles carry an APIC affine velocity.
    pub apic: bool,
    /// Where the stress update sits in the step.
    pub stress_order: StressOrder,
    /// Which volumetric strain rate the stress update takes.
    pub volumetric_rate: VolumetricRate,
    /// The length C h of the artificial bulk viscosity ([`BULK_VISCOSITY`]); zero for none.
    pub bulk_length: Real,
    /// Whether a granular body's parted grains close again before they carry stress.
    pub closing: bool,
}

impl Recipe {
    /// The recipe of `body` in a scene with `kernel` and cells of `cell_size` (m).
    pub fn new(body: &BodyConfig, kernel: KernelKind, cell_size: f64) -> Recipe {
        let granular = matches!(body.material.behaviour(), Behaviour::Granular(_));
        let c1 = kernel != KernelKind::Linear;
        Recipe {
            flip: body
                .flip
                .unwrap_or_else(|| Recipe::default_flip(&body.material)) as Real,
            apic: body.apic.unwrap_or(c1 && granular),
            stress_order: if c1 && body.stress_last.unwrap_or(!granular) {
                StressOrder::Last
            } else {
                StressOrder::First
            },
            volumetric_rate: body.material.volumetric_rate(),
            bulk_length: if granular || body.kinematic {
                0.0
            } else {
                BULK_VISCOSITY * cell_size as Real
            },
            closing: granular && body.close_grains.unwrap_or(body.pour.is_some()),
        }
    }

    /// The FLIP share of a body of `material` that sets none: the paper's α, 0.05 for sand,
    /// 0 for solids.
    pub fn default_flip(material: &Material) -> f64 {
        match material.behaviour() {
            Behaviour::Granular(_) => 0.05,
            Behaviour::Solid => 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Shape;

    fn body(material: Material) -> BodyConfig {
        BodyConfig::new("b", Shape::cuboid(&[0.0, 0.0], &[1.0, 1.0]), material)
    }

    /// The table of the module documentation, and the body's own settings over it.
    #[test]
    fn each_material_gets_its_recipe_and_a_body_may_override_the_transfer() {
        let sand = body(Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0));
        let solid = body(Material::von_mises(1e5, 0.3, 1000.0, 1e3));
        let h = 0.02;
        let r = Recipe::new(&sand, KernelKind::Gimp, h);
        assert_eq!(
            (r.flip, r.apic, r.stress_order, r.bulk_length),
            (0.05, true, StressOrder::First, 0.0)
        );
        let r = Recipe::new(&sand, KernelKind::Linear, h);
        assert!(!r.apic && r.stress_order == StressOrder::First);
        let r = Recipe::new(&solid, KernelKind::QuadraticBspline, h);
        assert_eq!(
            (r.flip, r.apic, r.stress_order, r.bulk_length),
            (0.0, false, StressOrder::Last, BULK_VISCOSITY * h as Real)
        );
        let r = Recipe::new(&solid, KernelKind::Linear, h);
        assert_eq!(r.stress_order, StressOrder::First);
        let r = Recipe::new(&solid.clone().kinematic(), KernelKind::Gimp, h);
        assert_eq!(r.bulk_length, 0.0);
        let r = Recipe::new(
            &sand.clone().without_apic().with_flip(0.5),
            KernelKind::Gimp,
            h,
        );
        assert!(!r.apic && r.flip == 0.5);
        let r = Recipe::new(&sand.clone().with_stress_last(true), KernelKind::Gimp, h);
        assert_eq!(r.stress_order, StressOrder::Last);
        let r = Recipe::new(&solid.clone().with_stress_last(false), KernelKind::Gimp, h);
        assert_eq!(r.stress_order, StressOrder::First);
        assert!(Recipe::new(&solid.clone().with_apic(), KernelKind::Gimp, h).apic);
        assert!(!Recipe::new(&sand, KernelKind::Gimp, h).closing);
        let spout = crate::config::PourConfig {
            spout: vec![0.5, 0.9],
            radius: 0.05,
            rate: 0.01,
            duration: 1.0,
        };
        let poured = BodyConfig::poured("p", spout, sand.material.clone());
        assert!(Recipe::new(&poured, KernelKind::Gimp, h).closing);
        let closed = sand.clone().with_close_grains(true);
        assert!(Recipe::new(&closed, KernelKind::Gimp, h).closing);
        let open = poured.with_close_grains(false);
        assert!(!Recipe::new(&open, KernelKind::Gimp, h).closing);
        assert!(!Recipe::new(&solid, KernelKind::Gimp, h).closing);
    }
}
