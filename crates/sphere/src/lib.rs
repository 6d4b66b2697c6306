//! The perfect sphere of the original work, built directly as patches.
//!
//! [`build_sphere`] places patch centres almost evenly on a sphere (a
//! Fibonacci lattice relaxed by a few rounds of mutual repulsion), gives each
//! patch a frame whose z axis is the outward normal, and stores in each node
//! the height of the sphere above the patch plane, quantized with step
//! `|az|`. No colour channel.
//!
//! ```
//! let sphere = spatch_sphere::build_sphere(&spatch_sphere::SphereOptions::default())?;
//! assert_eq!(sphere.scene.patches().len(), 1362);
//! assert!(sphere.coverage_margin >= 0.0); // no gaps
//! # Ok::<(), spatch_sphere::SphereError>(())
//! ```
#![forbid(unsafe_code)]

mod centres;
mod orient;
mod sphere;

pub use centres::distribute_on_sphere;
pub use sphere::{build_sphere, Sphere, SphereError, SphereOptions};
