//! Physically based light transport: geometry, spectra, camera, film, materials,
//! lights and integrators, all driven by the primary-sample-space samplers of the
//! `qmc` crate.

pub mod camera;
pub mod film;
pub mod geometry;
pub mod image;
pub mod integrators;
pub mod light;
pub mod material;
pub mod math;
pub mod medium;
pub mod memory;
pub mod renderer;
pub mod replication;
pub mod sampler;
pub mod sampling;
pub mod scene;
pub mod spectrum;
pub mod statistics;
#[cfg(test)]
mod test_support;
pub mod texture;
