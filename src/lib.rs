//! # mpm — a material point method playground for solids
//!
//! The solver of Jiang, Yang, Chang and Hu, *MPM based simulation for various solid
//! deformation*: hypoelastic stress with the Jaumann rate, von Mises plasticity for
//! deformable objects, non-associated Drucker–Prager for sand, the eight-step update of their
//! Sec. 4.2 with a PIC/FLIP blend, walls with Coulomb friction and multi-grid contact between
//! bodies. One generic solver ([`Simulation<D>`]) is monomorphised for plane strain ([`D2`])
//! and 3D ([`D3`]); [`AnySimulation`] picks one at run time.
//!
//! ```
//! use mpm::{Simulation, D2, BodyConfig, Material, Shape};
//! let mut sim = Simulation::<D2>::builder(&[1.0, 1.0], 0.05)
//!     .body(BodyConfig::new("block", Shape::cuboid(&[0.3, 0.0], &[0.7, 0.4]), Material::elastic(1e5, 0.3, 1000.0)))
//!     .build()
//!     .unwrap();
//! sim.advance(0.01).unwrap();
//! assert!(sim.diagnostics().kinetic >= 0.0);
//! ```
//!
//! Units are SI throughout; angles are in degrees. In 2D, masses, volumes and energies are
//! per metre of depth.

// `Real` is f32 by default and f64 with the `f64` feature; conversions between `Real` and f64
// (diagnostics, parameters) are needed in the first and are no-ops in the second.
#![cfg_attr(feature = "f64", allow(clippy::unnecessary_cast))]

pub mod boundary;
pub mod config;
pub mod error;
pub mod geometry;
pub mod grid;
#[cfg(not(target_arch = "wasm32"))]
pub mod io;
pub mod kernel;
pub mod lab;
pub mod laws;
pub mod lesson;
pub mod material;
pub mod math;
pub mod measure;
pub mod params;
pub mod playground;
pub mod recipe;
pub mod recovery;
pub mod sim;
pub mod step;
#[cfg(target_arch = "wasm32")]
pub mod wasm;

pub use config::{
    BodyConfig, BoundaryConfig, ContactConfig, DomainConfig, PourConfig, SceneConfig,
};
pub use error::{Error, Result};
pub use geometry::Shape;
pub use kernel::KernelKind;
pub use material::Material;
pub use math::{D2, D3, Dim, Real};
pub use sim::{AnySimulation, BodyStats, Diagnostics, PassTimings, Simulation, SimulationBuilder};
