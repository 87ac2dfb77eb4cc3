use mpm::*;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let dim: usize = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(2);
    let kernel = match args.get(2).map(|s| s.as_str()) { Some("linear") => KernelKind::Linear, Some("gimp") => KernelKind::Gimp, _ => KernelKind::QuadraticBspline };
    let sand = args.get(3).map(|s| s == "sand").unwrap_or(true);
    let steps: usize = args.get(4).map(|s| s.parse().unwrap()).unwrap_or(20);
    let mat = if sand { Material::drucker_prager(3.5e5, 0.3, 2200.0, 35.0, 0.0, 0.0) } else { Material::elastic(1e5, 0.3, 1000.0) };
    let mut scene = if dim == 3 { SceneConfig::new(3, &[1.0, 0.5, 1.0], 0.0125) } else { SceneConfig::new(2, &[1.0, 0.5], 0.002) };
    scene.kernel = kernel;
    scene.boundary.friction = 0.5;
    let (lo, hi) = if dim == 3 { (vec![0.3, 0.0, 0.3], vec![0.7, 0.2, 0.7]) } else { (vec![0.25, 0.0], vec![0.75, 0.25]) };
    scene.bodies.push(BodyConfig::new("block", Shape::cuboid(&lo, &hi), mat));
    let mut sim = AnySimulation::new(scene).unwrap();
    let t = std::time::Instant::now();
    for _ in 0..steps { sim.step().unwrap(); }
    let s = t.elapsed().as_secs_f64();
    println!("{} particles, {:.2} M particle-steps/s", sim.particle_count(), (sim.particle_count() * steps) as f64 / s / 1e6);
}
