use mpm::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let kernel = match args.get(1).map(|s| s.as_str()) {
        Some("linear") => KernelKind::Linear,
        Some("gimp") => KernelKind::Gimp,
        _ => KernelKind::QuadraticBspline,
    };
    let nu: f64 = args.get(2).map(|s| s.parse().unwrap()).unwrap_or(0.0);
    let h: f64 = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(0.02);
    let t_end: f64 = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(4.0);
    let e = 1e5;
    let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], h)
        .kernel(kernel)
        .body(BodyConfig::new(
            "block",
            Shape::cuboid(&[0.3, 0.0], &[0.7, 0.4]),
            Material::elastic(e, nu, 1000.0),
        ))
        .build()
        .unwrap();
    let y0 = sim.bodies()[0].stats().center_of_mass[1];
    let com_drop = 1000.0 * 9.81 * 0.4f64.powi(2) * (1.0 - nu * nu) / (3.0 * e);
    println!("analytic com drop {com_drop:.5}");
    let n = 8;
    for _ in 0..n {
        sim.advance(t_end / n as f64).unwrap();
        let d = sim.diagnostics();
        let s = sim.bodies()[0].stats();
        println!(
            "t={:.2} steps={} com_drop={:.5} ({:+.1}%) ke={:.2e} vmax={:.2e} E={:.3} el={:.3} diss_b={:.3} miny={:.5}",
            sim.time(),
            sim.steps(),
            y0 - s.center_of_mass[1],
            100.0 * ((y0 - s.center_of_mass[1]) / com_drop - 1.0),
            d.kinetic,
            d.max_speed,
            d.total_energy(),
            d.elastic,
            d.dissipated_boundary,
            s.bbox_min[1]
        );
    }
    // stress profile at the centre column
    let p = sim.particles();
    let mut rows: Vec<(f32, f32)> = (0..p.len())
        .filter(|&i| (p.x[i].x - 0.5).abs() < 0.05)
        .map(|i| (p.x[i].y, p.stress[i].yy))
        .collect();
    rows.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    let top = rows.iter().map(|r| r.0).fold(0.0f32, f32::max) + (h as f32) / 4.0;
    for r in rows.iter().step_by(rows.len() / 10) {
        println!(
            "y={:.4} syy={:.1} expect={:.1}",
            r.0,
            r.1,
            -1000.0 * 9.81 * (top - r.0)
        );
    }
}
