//! Helpers shared by the integration tests.
#![allow(dead_code)]

use mpm::{BodyConfig, D2, D3, Dim, Material, Shape, Simulation};

/// A builder for a scene in dimension `D` whose extents are given for 3D and cut to 2D.
pub fn cut<D: Dim>(v: [f64; 3]) -> Vec<f64> {
    v[..D::DIM].to_vec()
}

/// Runs both dimensions of a test.
pub fn both(f2: impl FnOnce(), f3: impl FnOnce()) {
    f2();
    f3();
}

pub fn elastic(e: f64, nu: f64, rho: f64) -> Material {
    Material::elastic(e, nu, rho)
}

pub fn sand(phi: f64) -> Material {
    Material::drucker_prager(3.5e5, 0.3, 2200.0, phi, 0.0, 0.0)
}

pub fn body(name: &str, lo: [f64; 3], hi: [f64; 3], material: Material, dim: usize) -> BodyConfig {
    BodyConfig::new(name, Shape::cuboid(&lo[..dim], &hi[..dim]), material)
}

/// Zero crossings (linear interpolation) of a sampled signal.
pub fn zero_crossings(t: &[f64], y: &[f64]) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 1..y.len() {
        if (y[i - 1] < 0.0) != (y[i] < 0.0) {
            let f = y[i - 1] / (y[i - 1] - y[i]);
            out.push(t[i - 1] + f * (t[i] - t[i - 1]));
        }
    }
    out
}

pub type Sim2 = Simulation<D2>;
pub type Sim3 = Simulation<D3>;
