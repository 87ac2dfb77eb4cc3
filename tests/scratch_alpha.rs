#[path = "support/validation.rs"]
mod validation;
use mpm::{BodyConfig, D2, KernelKind, Material, Shape, Simulation};
use validation::*;
#[test]
fn alpha95() {
    let mut sim = Simulation::<D2>::builder(&[1.0, 0.4], 0.02)
        .wall_friction(0.5)
        .body(BodyConfig::new("heap", Shape::polygon(&[[0.3, 0.0], [0.7, 0.0], [0.55, 0.08], [0.45, 0.08]]),
            Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0)).with_flip(0.95))
        .build().unwrap();
    let mut late = 0.0f64;
    let mut com = [0.0; 3];
    for k in 0..100_000 { sim.step().unwrap(); if k == 50_000 { com = sim.bodies()[0].stats().center_of_mass; } if k > 50_000 { late = late.max(sim.diagnostics().max_speed); } }
    let s = sim.bodies()[0].stats();
    eprintln!("heap α=0.95: 100k steps, late max speed {late:.2e}, com drift {:.2e}, KE {:.2e}", ((s.center_of_mass[0]-com[0]).powi(2)+(s.center_of_mass[1]-com[1]).powi(2)).sqrt(), sim.diagnostics().kinetic);
    for (file, a) in [("column_collapse_a0.5_2d.json", 0.5), ("column_collapse_a1_2d.json", 1.0), ("column_collapse_a3_2d.json", 3.0)] {
        let c = column_collapse(file, &Numerics::new(0.01, KernelKind::Gimp).flip(0.95), 4.0);
        eprintln!("α=0.95 a={a}: runout {:.3} (Lube {:.2}) height {:.3} (Lube {:.3}) rest {:.2} {:?}", c.runout, lube_runout(a), c.height, lube_height(a), c.settled_at, c.failure);
    }
}
