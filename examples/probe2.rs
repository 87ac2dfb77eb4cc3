use mpm::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kernel = match args.get(1).map(|s| s.as_str()) {
        Some("linear") => KernelKind::Linear,
        _ => KernelKind::QuadraticBspline,
    };
    let nu: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.0);
    let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], 0.02)
        .kernel(kernel)
        .body(BodyConfig::new(
            "block",
            Shape::cuboid(&[0.3, 0.0], &[0.7, 0.4]),
            Material::elastic(1e5, nu, 1000.0),
        ))
        .build()
        .unwrap();
    let mut last = sim.diagnostics().total_energy();
    for i in 0..2000 {
        sim.step().unwrap();
        let d = sim.diagnostics().clone();
        let e = d.total_energy();
        if e - last > 0.05 {
            // find particle with largest |stress|
            let p = sim.particles();
            let (mut best, mut bi) = (0.0f32, 0);
            for k in 0..p.len() {
                let s = p.stress[k];
                let n = s.xx.abs() + s.yy.abs() + s.xy.abs();
                if n > best {
                    best = n;
                    bi = k;
                }
            }
            println!(
                "step {i} t={:.4} dE={:.3} E={:.3} el={:.3} ke={:.3} maxstress particle {bi} at ({:.4},{:.4}) v=({:.3},{:.3}) s={:?}",
                d.time,
                e - last,
                e,
                d.elastic,
                d.kinetic,
                p.x[bi].x,
                p.x[bi].y,
                p.v[bi].x,
                p.v[bi].y,
                p.stress[bi]
            );
        }
        last = e;
    }
}
