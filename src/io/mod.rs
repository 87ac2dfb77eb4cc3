//! Output of a running simulation, kept out of the solver: a dimension-independent snapshot
//! of the particles, binary PLY frames, a software splat renderer writing PNG images, and the
//! JSON run summary. Used by the `mpm` command-line tool (native only).

pub mod ply;
pub mod render;
pub mod snapshot;
pub mod summary;

pub use render::{Camera, ColorBy, Image, RenderOptions, render};
pub use snapshot::Snapshot;
pub use summary::Summary;
