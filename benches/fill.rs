//! How fast meshes are filled with particles: the Stanford bunny (3998 triangles) sampled on
//! lattices of 10⁴ to 10⁶ points, by the region-by-region lattice classification that
//! `Shape::sample` uses, by one fast-winding-number query per point, and (on a subsample) by
//! the exact generalised winding number summed over every triangle. Prints figures; asserts
//! only that the three agree.
//!
//!     cargo bench --bench fill
//!
//! One machine-readable line per case:
//! `bench fill method=<m> lattice_points=<n> inside=<k> seconds=<s> us_per_point=<x>`.

use mpm::Shape;
use mpm::geometry::TriMesh;
use std::time::Instant;

fn main() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.obj");
    let text = std::fs::read_to_string(path).expect("scenes/bunny.obj");
    let t0 = Instant::now();
    let mesh = TriMesh::from_obj("bunny.obj", &text).expect("a valid mesh");
    println!(
        "parse + tree: {} triangles in {:.1} ms",
        mesh.triangles.len(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    let shape = Shape::mesh_from(mesh.clone(), 1.0, &[0.6, 0.0, 0.5]);
    for n in [22, 46, 100] {
        // lattice spacing so that the bunny's bounding box holds about n³ points
        let dx = 1.05 / n as f64;
        let lattice_points = shape.lattice_candidates(3, dx, 1);

        let t = Instant::now();
        let (pts, vol) = shape.sample(3, dx, 1);
        let s = t.elapsed().as_secs_f64();
        line("lattice", lattice_points, pts.len(), s);
        println!(
            "    volume {:.4} (the mesh's: 0.2045)",
            pts.len() as f64 * vol
        );

        let t = Instant::now();
        let per_point = shape.inside_test(3);
        let b = shape.bounds(3);
        let mut inside = 0;
        let lo: Vec<i64> = (0..3)
            .map(|a| (b.min[a] / dx - 0.5).ceil() as i64)
            .collect();
        let hi: Vec<i64> = (0..3)
            .map(|a| (b.max[a] / dx - 0.5).floor() as i64)
            .collect();
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    let p = [i, j, k].map(|x| (x as f64 + 0.5) * dx);
                    if per_point.contains(p) {
                        inside += 1;
                    }
                }
            }
        }
        let s = t.elapsed().as_secs_f64();
        line("per_point", lattice_points, inside, s);
        assert_eq!(inside, pts.len(), "per-point and lattice fills disagree");

        // the exact sum over every triangle, on every 97th lattice point
        let t = Instant::now();
        let (mut tested, mut agree) = (0usize, 0usize);
        let mut count = 0usize;
        for k in lo[2]..=hi[2] {
            for j in lo[1]..=hi[1] {
                for i in lo[0]..=hi[0] {
                    count += 1;
                    if !count.is_multiple_of(97) {
                        continue;
                    }
                    let p = [i, j, k].map(|x| (x as f64 + 0.5) * dx);
                    let local = [p[0] - 0.6, p[1], p[2] - 0.5];
                    let exact = mesh.tree.winding_number_exact(local).abs() > 0.5;
                    tested += 1;
                    if exact == per_point.contains(p) {
                        agree += 1;
                    }
                }
            }
        }
        let s = t.elapsed().as_secs_f64();
        println!(
            "bench fill method=exact lattice_points={tested} inside=- seconds={s:.4} us_per_point={:.2}",
            s * 1e6 / tested as f64
        );
        println!("    exact and fast agree on {agree} of {tested} points");
        assert_eq!(agree, tested);
    }
}

fn line(method: &str, n: f64, inside: usize, s: f64) {
    println!(
        "bench fill method={method} lattice_points={n} inside={inside} seconds={s:.4} us_per_point={:.3}",
        s * 1e6 / n
    );
}
